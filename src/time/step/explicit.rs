//! The explicit central-difference step with a diagonal (lumped) mass and a contact force at
//! t_n, for the explicit schemes with a contact law of their own (forward-increment multiplier,
//! velocity correction, penalty):
//!
//! `u_{n+1} = 2u_n − u_{n−1} + Δt² M⁻¹ (F − K u_n − B_Nᵀ λ_n)`,
//!
//! in two stages: the predictor `u* = 2u_n − u_{n−1} + Δt² a_n` with the free acceleration
//! `a_n = M⁻¹ (F − K u_n)` and its gaps `g* = g₀ − B_N u*` ([`Explicit::predict`]), then the
//! correction `u_{n+1} = u* − Δt² M⁻¹ B_Nᵀ λ_n` ([`Explicit::correct`]), which moves the gaps to
//! `g_{n+1} = g* + Δt² W λ_n`, `W = B_N M⁻¹ B_Nᵀ` (diagonal, [`Explicit::delassus`], when the
//! rows share no dof: [`shared_dof`]). The scheme chooses λ_n between the two stages, from g*
//! or from `g_n`. No factorisation: per step one product by K, O(n) work and O(nnz B_N) for the
//! contact. Started like [`super::ThreeLevel`] from `u₋₁ = u₀ − Δt v₀ + ½ Δt² a₀` (no contact
//! force at t = 0); the state reports the half-step velocity `v_{n+½} = (u_{n+1} − u_n)/Δt` and
//! the midpoint energy, as central difference does.
//!
//! Multiplying the step by `M (u_{n+1} − u_{n−1})/2` gives the exact identity (F constant)
//!
//! `H_{n+½} − H_{n−½} = ½ λ_n · (g_{n+1} − g_{n−1})`,
//! `H_{n+½} = ½ v_{n+½}ᵀ M v_{n+½} + ½ u_nᵀ K u_{n+1} − ½ Fᵀ (u_n + u_{n+1})`
//!
//! (`H = ½ vᵀ(M − Δt²/4 K)v + ½ u_{n+½}ᵀ K u_{n+½} − Fᵀu_{n+½} ≥ 0` below the CFL limit): each
//! scheme's law turns it into its energy statement.

use super::cfl::{self, CFL_SAFETY};
use super::contact_step::LinearSolver;
use super::stepper::time_step;
use crate::error::{Error, Result};
use crate::linalg;
use crate::problem::Problem;
use crate::time::scheme::{check_finite, State, StepInfo};
use nalgebra::DMatrix;

/// What an explicit scheme checks before it starts: `dt` valid, no cg linear solver (there is no
/// linear system), a lumped mass ([`lumped_inverse`]: `otherwise` says what to use instead) and
/// `dt` within the stability limit of `(K + κ B_NᵀB_N, M)` ([`critical_time_step`]; κ = 0: the
/// contact-free limit).
pub fn start<'p>(
    problem: &'p Problem,
    dt: f64,
    linear: LinearSolver,
    (scheme, otherwise): (&str, &str),
    kappa: f64,
) -> Result<Explicit<'p>> {
    let dt = time_step(problem, dt)?;
    if linear == LinearSolver::Cg {
        return Err(Error::Unsupported(format!(
            "{scheme} solves no linear system (lumped mass); linear solver cg does not apply (use \
             auto or direct)"
        )));
    }
    let inv_mass = lumped_inverse(problem, scheme, otherwise)?;
    let dt_max = CFL_SAFETY * critical_time_step(problem, &inv_mass, kappa)?;
    let of = if kappa > 0.0 {
        format!("this mesh, mass and penalty stiffness κ = {kappa:.6e}")
    } else {
        "this mesh and mass".to_string()
    };
    cfl::check_time_step(scheme, dt, dt_max, &of)?;
    Explicit::new(problem, dt, inv_mass)
}

/// `2/ω_max`, `ω²_max` the largest eigenvalue of `(K + κ B_NᵀB_N, M)` with the lumped mass
/// `M⁻¹ = diag(inv_mass)` ([`cfl::critical_time_step`]); with κ = 0 the contact-free limit, with
/// κ > 0 the limit with every contact point penetrating (the stiffest state of the penalty).
pub fn critical_time_step(problem: &Problem, inv_mass: &[f64], kappa: f64) -> Result<f64> {
    let b = &problem.contact.b_n;
    let mut bx = vec![0.0; b.nrows()];
    cfl::critical_time_step(
        &vec![false; inv_mass.len()],
        |x, kx| {
            kx.fill(0.0);
            linalg::mul_add(kx, &problem.k, x, 1.0);
            if kappa > 0.0 {
                bx.fill(0.0);
                linalg::mul_add(&mut bx, b, x, 1.0);
                linalg::mul_t_add(kx, b, &bx, kappa);
            }
        },
        |x| (0..x.len()).map(|i| x[i] * x[i] / inv_mass[i]).sum(),
        |r, x| {
            for ((x, r), m) in x.iter_mut().zip(r).zip(inv_mass) {
                *x = r * m;
            }
            Ok(())
        },
    )
}

/// `1/m_i` of a diagonal mass with a positive diagonal (the lumped mass), or the reason why
/// `scheme` cannot run on this mass, ending with `otherwise` (what to use instead).
pub fn lumped_inverse(problem: &Problem, scheme: &str, otherwise: &str) -> Result<Vec<f64>> {
    let refuse = |why: String| Err(Error::Unsupported(format!("{scheme} {why}; {otherwise}")));
    let Some(m) = problem.inertia.sparse() else {
        return refuse(
            "needs a diagonal (lumped) mass, not the singular dynamic method's (dense and \
             singular)"
                .into(),
        );
    };
    let mut diagonal = vec![0.0; m.nrows()];
    for (i, j, v) in linalg::triplets(m) {
        if i == j {
            diagonal[i] += v;
        } else if v != 0.0 {
            return refuse(format!(
                "needs a diagonal (lumped) mass: this one couples dofs {i} and {j}"
            ));
        }
    }
    if let Some(i) = diagonal.iter().position(|&d| d <= 0.0) {
        return refuse(format!(
            "divides by the mass of every dof: dof {i} is massless (mass redistribution or \
             mass elimination)"
        ));
    }
    Ok(diagonal.iter().map(|d| 1.0 / d).collect())
}

/// Two contact rows sharing a dof, `(i, j, dof)`: then `W = B_N M⁻¹ B_Nᵀ` is not diagonal
/// (weak multipliers on faces); None for nodal rows.
pub fn shared_dof(rows: &[Vec<(usize, f64)>], n: usize) -> Option<(usize, usize, usize)> {
    let mut owner = vec![usize::MAX; n];
    for (i, row) in rows.iter().enumerate() {
        for &(j, _) in row {
            if owner[j] != usize::MAX && owner[j] != i {
                return Some((owner[j], i, j));
            }
            owner[j] = i;
        }
    }
    None
}

/// The explicit step's state and workspace.
pub struct Explicit<'p> {
    pub problem: &'p Problem,
    pub dt: f64,
    pub step: usize,
    /// `1/m_i`.
    inv_mass: Vec<f64>,
    /// Rows of B_N as `(dof, value)` lists.
    pub rows: Vec<Vec<(usize, f64)>>,
    /// `u_n`.
    pub u: Vec<f64>,
    /// `u_{n−1}`.
    pub u_prev: Vec<f64>,
    /// The predictor u*, corrected into `u_{n+1}` (workspace between the stages).
    next: Vec<f64>,
    /// The free acceleration `a_n = M⁻¹ (F − K u_n)`.
    pub acc: Vec<f64>,
    /// `v_{n−½} = (u_n − u_{n−1})/Δt` (v₀ at the start).
    pub v: Vec<f64>,
    /// `(u_n + u_{n−1})/2` (u₀ at the start).
    pub midpoint: Vec<f64>,
    /// The contact force λ_n of the step (set by the scheme between the stages).
    pub lambda: Vec<f64>,
    /// `g_n = g₀ − B_N u_n`.
    pub gap: Vec<f64>,
    /// `g* = g₀ − B_N u*` (after [`Explicit::predict`]).
    pub gap_star: Vec<f64>,
}

impl<'p> Explicit<'p> {
    /// Starts from `(U₀, V₀)` with the inverse lumped mass `inv_mass` ([`lumped_inverse`]); the
    /// contact force acts through the rows of `B_N` (not Nitsche's force rows).
    pub fn new(problem: &'p Problem, dt: f64, inv_mass: Vec<f64>) -> Result<Self> {
        if problem.contact.force.is_some() {
            return Err(Error::Unsupported(
                "an explicit step applies the contact force through B_N, not through separate \
                 force rows (Nitsche)"
                    .into(),
            ));
        }
        let n = problem.n();
        let nc = problem.contact.len();
        let mut s = Self {
            problem,
            dt,
            step: 0,
            inv_mass,
            rows: linalg::rows(&problem.contact.b_n),
            u: problem.u0.clone(),
            u_prev: vec![0.0; n],
            next: vec![0.0; n],
            acc: vec![0.0; n],
            v: problem.v0.clone(),
            midpoint: problem.u0.clone(),
            lambda: vec![0.0; nc],
            gap: vec![0.0; nc],
            gap_star: vec![0.0; nc],
        };
        s.free_acceleration();
        for i in 0..n {
            s.u_prev[i] = s.u[i] - dt * s.v[i] + 0.5 * dt * dt * s.acc[i];
        }
        gaps(&s.rows, &problem.contact.g0, &s.u, &mut s.gap);
        Ok(s)
    }

    /// `(step, time)` of the level being computed (for error messages).
    pub fn next(&self) -> (usize, f64) {
        (self.step + 1, (self.step + 1) as f64 * self.dt)
    }

    /// `W_ii = Σ_k (B_N)_ik² / m_k`: the diagonal of `W = B_N M⁻¹ B_Nᵀ`.
    pub fn delassus(&self) -> Vec<f64> {
        let w = |row: &[(usize, f64)]| row.iter().map(|&(j, b)| b * b * self.inv_mass[j]).sum();
        self.rows.iter().map(|r| w(r)).collect()
    }

    /// `c W = c B_N M⁻¹ B_Nᵀ` as a dense n_c × n_c matrix (for a law on coupled rows).
    pub fn delassus_matrix(&self, c: f64) -> DMatrix<f64> {
        let nc = self.rows.len();
        let mut scaled = vec![0.0; self.u.len()];
        let mut d = DMatrix::zeros(nc, nc);
        for (i, row) in self.rows.iter().enumerate() {
            for &(k, b) in row {
                scaled[k] = c * b * self.inv_mass[k];
            }
            for (j, other) in self.rows.iter().enumerate() {
                d[(j, i)] = other.iter().map(|&(k, b)| b * scaled[k]).sum();
            }
            for &(k, _) in row {
                scaled[k] = 0.0;
            }
        }
        d
    }

    /// The predictor `u* = 2u_n − u_{n−1} + Δt² a_n` and its gaps g*.
    pub fn predict(&mut self) {
        let h2 = self.dt * self.dt;
        for i in 0..self.u.len() {
            self.next[i] = 2.0 * self.u[i] - self.u_prev[i] + h2 * self.acc[i];
        }
        let g0 = &self.problem.contact.g0;
        gaps(&self.rows, g0, &self.next, &mut self.gap_star);
    }

    /// The correction `u_{n+1} = u* − Δt² M⁻¹ B_Nᵀ λ_n`, then the levels move on (velocity,
    /// midpoint, gaps, free acceleration); `iterations` of the contact solve are reported.
    pub fn correct(&mut self, iterations: usize) -> Result<StepInfo> {
        let h2 = self.dt * self.dt;
        for (row, &l) in self.rows.iter().zip(&self.lambda) {
            if l != 0.0 {
                for &(j, b) in row {
                    self.next[j] -= h2 * l * b * self.inv_mass[j];
                }
            }
        }
        std::mem::swap(&mut self.u_prev, &mut self.u);
        std::mem::swap(&mut self.u, &mut self.next);
        for i in 0..self.u.len() {
            self.v[i] = (self.u[i] - self.u_prev[i]) / self.dt;
            self.midpoint[i] = 0.5 * (self.u[i] + self.u_prev[i]);
        }
        let g0 = &self.problem.contact.g0;
        gaps(&self.rows, g0, &self.u, &mut self.gap);
        self.free_acceleration();
        self.step += 1;
        let t = self.step as f64 * self.dt;
        check_finite(&self.u, self.step, t, "displacement")?;
        check_finite(&self.lambda, self.step, t, "contact force")?;
        Ok(StepInfo {
            contact_iterations: iterations,
            active: self.lambda.iter().filter(|&&l| l > 0.0).count(),
        })
    }

    /// The state: half-step velocity and midpoint energy.
    pub fn state(&self) -> State<'_> {
        State {
            t: self.step as f64 * self.dt,
            step: self.step,
            u: &self.u,
            v: &self.v,
            energy_u: &self.midpoint,
            lambda: &self.lambda,
            extra_energy: 0.0,
            friction_work: 0.0,
        }
    }

    /// `a_n = M⁻¹ (F − K u_n)`.
    fn free_acceleration(&mut self) {
        self.acc.copy_from_slice(&self.problem.f);
        linalg::mul_add(&mut self.acc, &self.problem.k, &self.u, -1.0);
        for (a, m) in self.acc.iter_mut().zip(&self.inv_mass) {
            *a *= m;
        }
    }
}

/// `g = g₀ − B_N u` on the rows.
fn gaps(rows: &[Vec<(usize, f64)>], g0: &[f64], u: &[f64], out: &mut [f64]) {
    for ((g, row), g0) in out.iter_mut().zip(rows).zip(g0) {
        *g = g0 - row.iter().map(|&(j, b)| b * u[j]).sum::<f64>();
    }
}

#[cfg(test)]
pub(crate) mod testing {
    //! What the explicit schemes' tests share: the unit bar of bar1d and the energy `H` of the
    //! step's identity.
    use crate::cases::bar1d::Bar1d;
    use crate::cases::{Case, RunSpec};
    use crate::exact::bar_impact::BarImpact;
    use crate::linalg;
    use crate::problem::Problem;
    use crate::time::{Integrator, Scheme, Solvers};

    /// The unit bar of bar1d (lift ½, P1, `n` elements) on `space`.
    pub fn bar(space: &str, n: usize) -> Problem {
        let exact = BarImpact {
            length: 1.0,
            young: 1.0,
            density: 1.0,
            lift: 0.5,
        };
        let spec = RunSpec::new(space, "central_difference", 0.5 / n as f64, 1.0);
        let case = Bar1d::new(exact, n, 1, true, spec).unwrap();
        case.problem(crate::space::by_name(space).unwrap().as_ref())
            .unwrap()
    }

    /// `scheme` on `problem` (nodal rows, exact LCP solver).
    pub fn prepare<'p>(
        scheme: &dyn Scheme,
        problem: &'p Problem,
        dt: f64,
    ) -> crate::Result<Box<dyn Integrator + 'p>> {
        let solver = crate::contact::by_name("active_set", problem.contact.len()).unwrap();
        scheme.prepare(problem, dt, Solvers::from(solver))
    }

    /// A run of a scheme on lumped bar1d ([`lumped_run`]).
    pub struct Run {
        pub problem: Problem,
        /// `(u_n, λ_n)` of every level.
        pub levels: Vec<(Vec<f64>, Vec<f64>)>,
        /// `g_n` of every level.
        pub gaps: Vec<Vec<f64>>,
        /// The smallest gap of the run.
        pub min_gap: f64,
        /// The energy the scheme reports at the end, over the exact 1/8.
        pub energy: f64,
    }

    /// `scheme` on lumped bar1d (`n` elements, Δt = h/2, T = 6).
    pub fn lumped_run(scheme: &dyn Scheme, n: usize) -> Run {
        let (problem, dt) = (bar("lumped", n), 0.5 / n as f64);
        let (levels, energy) = {
            let mut it = prepare(scheme, &problem, dt).unwrap();
            let levels = levels(it.as_mut(), 12 * n);
            let s = it.state();
            (
                levels,
                problem.energy_form().energy(s.energy_u, s.v) / 0.125,
            )
        };
        let gaps: Vec<Vec<f64>> = levels.iter().map(|(u, _)| gap(&problem, u)).collect();
        let min_gap = gaps.iter().flatten().copied().fold(f64::INFINITY, f64::min);
        Run {
            problem,
            levels,
            gaps,
            min_gap,
            energy,
        }
    }

    /// The displacement and contact force `(u_n, λ_n)` of every level of `steps` steps (λ_0 = 0).
    pub fn levels(it: &mut dyn Integrator, steps: usize) -> Vec<(Vec<f64>, Vec<f64>)> {
        let mut out = vec![(it.state().u.to_vec(), it.state().lambda.to_vec())];
        for _ in 0..steps {
            it.step().unwrap();
            out.push((it.state().u.to_vec(), it.state().lambda.to_vec()));
        }
        out
    }

    /// `H_{n+½} = ½ vᵀ M v + ½ u_nᵀ K u_{n+1} − ½ Fᵀ (u_n + u_{n+1})`, `v = (u_{n+1} − u_n)/Δt`.
    pub fn shadow_energy(problem: &Problem, dt: f64, u: &[f64], u_next: &[f64]) -> f64 {
        let v: Vec<f64> = u_next.iter().zip(u).map(|(a, b)| (a - b) / dt).collect();
        let m = problem.inertia.sparse().unwrap();
        let mut ku = vec![0.0; u.len()];
        linalg::mul_add(&mut ku, &problem.k, u_next, 1.0);
        let load: f64 = (0..u.len())
            .map(|i| problem.f[i] * (u[i] + u_next[i]))
            .sum();
        0.5 * linalg::quad(m, &v, &v) + 0.5 * linalg::dot(u, &ku) - 0.5 * load
    }

    /// `g = g₀ − B_N u`.
    pub fn gap(problem: &Problem, u: &[f64]) -> Vec<f64> {
        let mut g = vec![0.0; problem.contact.len()];
        problem.contact.gap(u, &mut g);
        g
    }
}

#[cfg(test)]
mod tests {
    use super::testing::{gap, lumped_run, shadow_energy};
    use super::*;
    use crate::time::central_difference::CentralDifference;

    /// Driven with central difference's contact forces, the step reproduces central difference
    /// on a lumped mass (the same equation, computed without a factorisation: measured max
    /// |Δu| = 1.9e-13 over the run, round-off), and its energy
    /// identity `H_{n+½} − H_{n−½} = ½ λ_n · (g_{n+1} − g_{n−1})` holds to round-off in every
    /// step (measured 6.9e-16, H₀ = 0.1246; lumped bar1d, N = 40, Δt = h/2, T = 6).
    #[test]
    fn is_central_difference_with_its_energy_identity() {
        let (n, dt, steps) = (40, 0.5 / 40.0, 480);
        let run = lumped_run(&CentralDifference, n);
        let (problem, reference) = (&run.problem, &run.levels);
        let touching = run.gaps.iter().filter(|g| g[0] <= 0.0).count();
        let inv_mass = lumped_inverse(problem, "test", "").unwrap();
        let mut x = Explicit::new(problem, dt, inv_mass).unwrap();
        let mut u = vec![x.u.clone()];
        for k in 0..steps {
            x.predict();
            x.lambda.copy_from_slice(&reference[k + 1].1);
            x.correct(0).unwrap();
            u.push(x.u.clone());
        }
        let scale = u.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let apart = u
            .iter()
            .zip(reference)
            .flat_map(|(a, (b, _))| a.iter().zip(b).map(|(a, b)| (a - b).abs()))
            .fold(0.0f64, f64::max);
        let gaps: Vec<Vec<f64>> = u.iter().map(|u| gap(problem, u)).collect();
        let h = |k: usize| shadow_energy(problem, dt, &u[k], &u[k + 1]);
        let mut identity = 0.0f64;
        for k in 1..steps {
            let lambda = &reference[k + 1].1;
            let work: f64 = (0..lambda.len())
                .map(|i| lambda[i] * (gaps[k + 1][i] - gaps[k - 1][i]))
                .sum();
            identity = identity.max((h(k) - h(k - 1) - 0.5 * work).abs());
        }
        let forced = reference.iter().filter(|(_, l)| l[0] > 0.0).count();
        println!(
            "explicit step vs central_difference, lumped N = {n}: max |Δu| = {apart:e} (max |u| = \
             {scale:.3}), {forced} levels with λ > 0, {touching} touching, identity off by \
             {identity:e} (H₀ = {:.6}); central difference: min g = {:e}, E(T)/E₀ = {:.5}",
            h(0),
            run.min_gap,
            run.energy
        );
        assert!(forced > 0 && touching > 0, "no contact on the run");
        assert!(
            run.min_gap >= -1e-15,
            "central difference penetrates: {}",
            run.min_gap
        );
        // Round-off only (measured 1.9e-13: central difference solves with the factored M).
        assert!(
            apart < 1e-11 * scale,
            "the step departs from central difference: {apart:e}"
        );
        assert!(
            identity < 1e-13 * h(0),
            "energy identity off by {identity:e}"
        );
    }
}
