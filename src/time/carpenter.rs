//! Explicit central difference with the forward-increment Lagrange multiplier of Carpenter,
//! Taylor & Katona, "Lagrange constraints for transient finite element surface contact", IJNME 32
//! (1991) 103–128. The paper could not be read here: the scheme is transcribed from three codes
//! that implement it (FrontISTR's `forward_increment_Lagrange`, which cites the paper, Kratos'
//! `ForwardIncrementLagrangeMultiplierScheme` and a MATLAB two-bar code; `notes/papers/
//! carpenter.md`), and no equation number of the paper is quoted. With a diagonal mass M:
//!
//! - predictor `u* = 2u_n − u_{n−1} + Δt² M⁻¹ (F − K u_n)`;
//! - the contact force at t_n fixed by the gap one step ahead (the "forward increment"):
//!   `0 ≤ λ_n ⊥ g_{n+1} = g(u*) + Δt² W λ_n ≥ 0`, `W = B_N M⁻¹ B_Nᵀ` (g = g₀ − B_N u, the
//!   sign of [`crate::problem`]);
//! - `u_{n+1} = u* − Δt² M⁻¹ B_Nᵀ λ_n`,
//!
//! so that `M (u_{n+1} − 2u_n + u_{n−1})/Δt² + K u_n = F − B_Nᵀ λ_n` with `g_{n+1} ≥ 0`: no
//! penetration at any step. Written with [`super::step::explicit`]: no factorisation, one product
//! by K per step; for nodal rows (one row per point, no dof shared) W is diagonal and the LCP is
//! solved in closed form, `λ_i = max(0, −g*_i / (Δt² W_ii))` (FrontISTR's Jacobi loop is exact
//! then, and so is the default active set); rows sharing dofs (weak multipliers on faces), a
//! formulation's modified law (penalty) or another `--contact-solver` asked for take the LCP
//! solver on the dense `Δt² W`. Stable below the contact-free CFL limit `2/ω_max(M⁻¹K)` (the
//! correction is a projection of the increment, not a stiffness), refused above
//! [`super::step::cfl::CFL_SAFETY`] times it.
//!
//! **Relation to [`super::central_difference`]**: on a nonsingular mass that scheme *is* this
//! method — its `λ_{n+1}` is this λ_n, the same force in the same equation, named by the level it
//! makes admissible — computed with M factored (a sparse Cholesky, also for a lumped M) and the
//! correction through stored columns `M⁻¹ B_Nᵀ` (O(n) per active point); it also solves massless
//! dofs quasi-statically. Measured on lumped bar1d (N = 40, Δt = h/2, T = 6, 480 steps): the two
//! trajectories agree to 2.5e-13 in u and 1.3e-11 in λ (round-off; tested). Hence this file
//! refuses what central difference covers: a non-diagonal M (standard: central difference
//! factors it once) and a singular one (mass redistribution, mass elimination: central
//! difference solves the massless block quasi-statically; the singular dynamic mass: neither
//! applies).
//!
//! **Energy.** The step's identity ([`super::step::explicit`]) with `λ_n · g_{n+1} = 0`:
//!
//! `H_{n+½} − H_{n−½} = ½ λ_n · (g_{n+1} − g_{n−1}) = −½ λ_n · g_{n−1} ≤ 0`:
//!
//! each impact dissipates (the contact node's approach velocity is killed: a perfectly plastic
//! impact of the node, lumped mass h/2 on the bar), persistent contact (`g_{n−1} = 0`) does not.
//! Measured on bar1d (lumped, N = 40, Δt = h/2, T = 6): g ≥ −8.7e-19 at every level, identity
//! to 4.7e-16, 1.9 % of H₀ dissipated in 37 impact steps, reported midpoint energy
//! E(T)/E₀ = 0.9805 (the note's 0.99266 for N = 40 uses the backward-difference velocity, a
//! different energy; not compared).
//!
//! Choices: started like central difference (a₀ without a contact force: the note's remark about
//! λ₀ in a₀ matters only for a contact active at t = 0); λ reported at t_{n+1}, as central
//! difference does; the exact LCP in place of FrontISTR's Jacobi loop (which neither projects
//! λ ≥ 0 nor caps its iterations).

use super::scheme::{Integrator, Scheme, Solvers, State, StepInfo};
use super::step::explicit::{self, shared_dof, Explicit};
use crate::contact::{self, Enforcement};
use crate::error::{Error, Result};
use crate::param::Entry;
use crate::problem::Problem;
use nalgebra::DMatrix;

/// Registry entry: `carpenter` (no parameter).
pub const ENTRY: Entry<dyn Scheme> = Entry {
    name: "carpenter",
    params: &[],
    build: |_| Ok(Box::new(Carpenter)),
};

/// Central difference with the forward-increment Lagrange multiplier (no parameter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Carpenter;

/// What the refusals of a mass point at.
const OTHERWISE: &str = "central_difference is this method with M factored once, and solves \
                         massless dofs quasi-statically";

impl Scheme for Carpenter {
    fn name(&self) -> &'static str {
        "carpenter"
    }

    fn enforcement(&self) -> Enforcement {
        Enforcement::Explicit
    }

    fn solves_linear_system(&self) -> bool {
        false
    }

    fn prepare<'p>(
        &self,
        problem: &'p Problem,
        dt: f64,
        solvers: Solvers,
    ) -> Result<Box<dyn Integrator + 'p>> {
        let x = explicit::start(problem, dt, solvers.linear, (self.name(), OTHERWISE), 0.0)?;
        let h2 = x.dt * x.dt;
        let closed_form = solvers.contact.signorini()
            && solvers.contact.name() == crate::contact::DEFAULT_SOLVER
            && shared_dof(&x.rows, problem.n()).is_none();
        let law = if closed_form {
            Law::ClosedForm(x.delassus().iter().map(|w| 1.0 / (h2 * w)).collect())
        } else {
            Law::Solver(solvers.contact, x.delassus_matrix(h2))
        };
        if let Law::ClosedForm(inv) = &law {
            if let Some(i) = inv.iter().position(|v| !v.is_finite()) {
                return Err(Error::Unsupported(format!(
                    "carpenter: contact point {i} acts on no dof (an empty row of B_N)"
                )));
            }
        }
        Ok(Box::new(CarpenterIntegrator { x, law }))
    }
}

/// How λ_n solves `0 ≤ λ ⊥ g* + Δt² W λ ≥ 0`.
enum Law {
    /// W diagonal and Signorini's law: `λ_i = max(0, −g*_i · inv_i)`, `inv_i = 1/(Δt² W_ii)`.
    ClosedForm(Vec<f64>),
    /// The formulation's law on the dense `Δt² W`.
    Solver(Box<dyn contact::Solver>, DMatrix<f64>),
}

struct CarpenterIntegrator<'p> {
    x: Explicit<'p>,
    law: Law,
}

impl Integrator for CarpenterIntegrator<'_> {
    fn step(&mut self) -> Result<StepInfo> {
        let x = &mut self.x;
        x.predict();
        let iterations = match &mut self.law {
            Law::ClosedForm(inv) => {
                for ((l, g), inv) in x.lambda.iter_mut().zip(&x.gap_star).zip(&*inv) {
                    *l = f64::max(0.0, -g * inv);
                }
                0
            }
            Law::Solver(solver, d) => {
                let (step, time) = x.next();
                solver
                    .solve(d, &x.gap_star, &mut x.lambda)
                    .map_err(|reason| Error::ContactSolver { step, time, reason })?
                    .iterations
            }
        };
        x.correct(iterations)
    }

    fn state(&self) -> State<'_> {
        self.x.state()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::central_difference::CentralDifference;
    use crate::time::step::explicit::testing::{bar, lumped_run, prepare, shadow_energy};

    /// `(u_n, λ_n)` of one level.
    type Level = (Vec<f64>, Vec<f64>);

    /// Every point admissible (g ≥ −1e-15 at every level), and the step's energy identity
    /// `H_{n+½} − H_{n−½} = −½ λ_n · g_{n−1} ≤ 0` to round-off in every step (lumped bar1d,
    /// N = 40, Δt = h/2, T = 6).
    #[test]
    fn never_penetrates_and_dissipates_only_at_impacts() {
        let (n, dt) = (40, 0.5 / 40.0);
        let run = lumped_run(&Carpenter, n);
        let (levels, gaps, min_gap) = (&run.levels, &run.gaps, run.min_gap);
        let h = |k: usize| shadow_energy(&run.problem, dt, &levels[k].0, &levels[k + 1].0);
        let h0 = h(0);
        let (mut worst, mut dissipated, mut impacts) = (0.0f64, 0.0, 0);
        for k in 1..levels.len() - 1 {
            // λ_k, the force of the step k → k + 1, is reported with level k + 1.
            let lambda = &levels[k + 1].1;
            let work: f64 = lambda.iter().zip(&gaps[k - 1]).map(|(l, g)| l * g).sum();
            let change = h(k) - h(k - 1);
            worst = worst.max((change + 0.5 * work).abs());
            dissipated += 0.5 * work;
            impacts += usize::from(work > 0.0);
        }
        println!(
            "carpenter lumped N = {n}: min g = {min_gap:e}, max |ΔH + ½λ·g_(n−1)| = {worst:e}, \
             dissipated {:.4e} H₀ in {impacts} steps, reported E(T)/E₀ = {:.5}",
            dissipated / h0,
            run.energy
        );
        assert!(min_gap >= -1e-15, "penetration {min_gap:e}");
        assert!(worst < 1e-13 * h0, "energy identity off by {worst:e}");
        assert!(impacts > 0 && dissipated > 0.0);
    }

    /// On a lumped mass this is central difference: the same displacements and forces (to
    /// round-off) over the run (bar1d, N = 40, Δt = h/2, T = 6).
    #[test]
    fn is_central_difference_on_a_lumped_mass() {
        let n = 40;
        let ours = lumped_run(&Carpenter, n).levels;
        let theirs = lumped_run(&CentralDifference, n).levels;
        let apart = |f: fn(&Level) -> &Vec<f64>| {
            ours.iter()
                .zip(&theirs)
                .flat_map(|(a, b)| f(a).iter().zip(f(b)).map(|(x, y)| (x - y).abs()))
                .fold(0.0f64, f64::max)
        };
        let (du, dl) = (apart(|l| &l.0), apart(|l| &l.1));
        let pressed = theirs.iter().filter(|(_, l)| l[0] > 0.0).count();
        println!("carpenter vs central_difference, lumped N = {n}: max |Δu| = {du:e}, max |Δλ| = {dl:e} ({pressed} levels pressed)");
        assert!(pressed > 0);
        assert!(du < 1e-11 && dl < 1e-9, "apart: u {du:e}, λ {dl:e}");
    }

    /// A non-diagonal mass and a massless dof are refused, naming central difference.
    #[test]
    fn refuses_a_mass_it_cannot_invert_diagonally() {
        for space in ["standard", "mass_redistribution"] {
            let problem = bar(space, 20);
            let result = prepare(&Carpenter, &problem, 0.02).map(|_| ());
            match result {
                Err(Error::Unsupported(why)) => {
                    println!("{space}: {why}");
                    assert!(why.contains("central_difference"), "{why}");
                }
                Err(e) => panic!("{space}: {e}"),
                Ok(_) => panic!("{space}: ran"),
            }
        }
    }
}
