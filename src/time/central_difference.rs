//! Explicit central difference with the contact law at t_{n+1} (Carpenter, Taylor, Katona 1991,
//! forward-increment Lagrange multipliers):
//!
//! `M (U_{n+1} − 2Uₙ + U_{n−1})/Δt² + K Uₙ = F − B_Nᵀ λ_{n+1}` on the dofs with mass (R),
//! `K_SS U_{n+1,S} + K_SR U_{n+1,R} = F_S − (B_Nᵀ λ_{n+1})_S` on the massless dofs S (their rows of M
//! are zero, e.g. the contact dofs under mass redistribution): quasi-static, solved with the
//! contact law once the massive dofs are known. The step matrix `A = M + Δt² K_SS` is block
//! diagonal and factored once (for a lumped mass it is diagonal).
//!
//! Stable for `Δt ≤ 2/ω_max`, `ω²_max = λ_max(K_RR, M_RR)` (an upper bound of the condensed
//! problem's, so the limit is safe), estimated before the run by a power iteration with the
//! Rayleigh quotient ([`cfl`]); a Δt above [`CFL_SAFETY`] times that limit is an "unstable time
//! step" error. Needs a sparse mass (every space but singular_dynamic) and contact dofs that are
//! all massive or all massless. Reports the half-step velocity and the midpoint energy like
//! [`super::paoli_schatzman`].

use super::scheme::{Integrator, Scheme, State, StepInfo};
use super::step::cfl::{self, zero_where, CFL_SAFETY};
use super::step::{time_step, Stepper, ThreeLevel};
use super::step::{ContactStep, LinearSolver};
use crate::contact::Enforcement;
use crate::error::{Error, Result};
use crate::linalg::{self, SpMat, TripletBuilder};
use crate::param::Entry;
use crate::problem::Problem;

/// Registry entry: `central_difference` (no parameter).
pub const ENTRY: Entry<dyn Scheme> = Entry {
    name: "central_difference",
    params: &[],
    build: |_| Ok(Box::new(CentralDifference)),
};

/// Explicit central difference (no parameter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CentralDifference;

impl Scheme for CentralDifference {
    fn name(&self) -> &'static str {
        "central_difference"
    }

    fn enforcement(&self) -> Enforcement {
        Enforcement::Explicit
    }

    fn prepare<'p>(
        &self,
        problem: &'p Problem,
        dt: f64,
        contact: super::scheme::Solvers,
    ) -> Result<Box<dyn Integrator + 'p>> {
        let dt = time_step(problem, dt)?;
        if contact.linear == LinearSolver::Cg {
            return Err(Error::Unsupported(
                "central_difference factors only its small quasi-static block; linear solver cg \
                 does not apply (use auto or direct)"
                    .into(),
            ));
        }
        let contact = super::scheme::Solvers {
            linear: LinearSolver::Direct,
            ..contact
        };
        let Some(m) = problem.inertia.sparse() else {
            return Err(Error::Unsupported(
                "central_difference needs a sparse mass matrix, which this space does not \
                 assemble"
                    .into(),
            ));
        };
        let massless = problem.inertia.massless();
        check_contact_dofs(problem, &massless)?;
        let k_ss = restrict(&problem.k, &massless)?;
        let mut system =
            ContactStep::with_stiffness(problem, &k_ss, (1.0, dt * dt), dt * dt, contact)?;
        let dt_max = CFL_SAFETY * critical_time_step(problem, m, &mut system, &massless)?;
        cfl::check_time_step(self.name(), dt, dt_max, "this mesh and mass")?;
        let levels = ThreeLevel::start(problem, dt)?;
        let s = Stepper::new(problem, dt, system)?;
        let n = problem.n();
        Ok(Box::new(CentralDifferenceIntegrator {
            quasi_static: massless.iter().any(|&b| b),
            massless,
            levels,
            u_new: vec![0.0; n],
            w_new: vec![0.0; n],
            scratch: vec![0.0; n],
            s,
        }))
    }
}

/// Contact dofs must be all massive or all massless (otherwise λ couples the two stages).
fn check_contact_dofs(problem: &Problem, massless: &[bool]) -> Result<()> {
    let contact_massless = linalg::triplets(&problem.contact.b_n).all(|(_, j, _)| massless[j]);
    if massless.contains(&true) && !contact_massless {
        return Err(Error::Unsupported(
            "central_difference: the mass has massless dofs but some contact dofs carry mass"
                .into(),
        ));
    }
    Ok(())
}

/// `K_SS` embedded in an n × n matrix (zero outside the massless block).
fn restrict(k: &SpMat, massless: &[bool]) -> Result<SpMat> {
    let mut t = TripletBuilder::new(k.nrows(), k.ncols());
    for (i, j, v) in linalg::triplets(k) {
        if massless[i] && massless[j] {
            t.add(i, j, v);
        }
    }
    t.build()
}

/// `2/ω_max` with `ω²_max` the largest eigenvalue of `(K_RR, M_RR)` (the R block of A⁻¹ is
/// `M_RR⁻¹`).
fn critical_time_step(
    problem: &Problem,
    m: &SpMat,
    system: &mut ContactStep,
    massless: &[bool],
) -> Result<f64> {
    let mut w = vec![0.0; problem.n()];
    cfl::critical_time_step(
        massless,
        |x, kx| {
            kx.fill(0.0);
            linalg::mul_add(kx, &problem.k, x, 1.0);
        },
        |x| linalg::quad(m, x, x),
        |r, x| system.solve_free(r, x, &mut w),
    )
}

struct CentralDifferenceIntegrator<'p> {
    s: Stepper<'p>,
    massless: Vec<bool>,
    quasi_static: bool,
    levels: ThreeLevel,
    u_new: Vec<f64>,
    w_new: Vec<f64>,
    scratch: Vec<f64>,
}

impl CentralDifferenceIntegrator<'_> {
    /// `r_R = M (2Uₙ − U_{n−1}) + Δt² (F − K Uₙ)`, `r_S = 0`.
    fn explicit_rhs(&mut self) {
        let dt = self.s.dt;
        for ((y, u), up) in self
            .scratch
            .iter_mut()
            .zip(&self.s.u)
            .zip(&self.levels.u_prev)
        {
            *y = 2.0 * u - up;
        }
        self.s.rhs_from_load(dt * dt);
        linalg::mul_add(&mut self.s.rhs, &self.s.problem.k, &self.s.u, -dt * dt);
        self.s
            .problem
            .inertia
            .apply_add(&mut self.s.rhs, &self.scratch, 1.0);
        zero_where(&mut self.s.rhs, &self.massless);
    }

    /// `r_S = Δt² (F_S − K_SR U_{n+1,R})` from the massive part of the free solve.
    fn quasi_static_rhs(&mut self) -> Result<()> {
        let dt = self.s.dt;
        self.s
            .system
            .solve_free(&self.s.rhs, &mut self.u_new, &mut self.w_new)?;
        zero_where(&mut self.u_new, &self.massless);
        self.scratch.fill(0.0);
        linalg::mul_add(&mut self.scratch, &self.s.problem.k, &self.u_new, 1.0);
        for i in 0..self.s.rhs.len() {
            if self.massless[i] {
                self.s.rhs[i] = dt * dt * (self.s.problem.f[i] - self.scratch[i]);
            }
        }
        Ok(())
    }
}

impl Integrator for CentralDifferenceIntegrator<'_> {
    fn step(&mut self) -> Result<StepInfo> {
        self.explicit_rhs();
        if self.quasi_static {
            self.quasi_static_rhs()?;
        }
        let info = self
            .s
            .solve_position_into(&mut self.u_new, &mut self.w_new)?;
        self.levels
            .rotate(&mut self.s, &mut self.u_new, &mut self.w_new);
        self.s.finish(info)
    }

    fn state(&self) -> State<'_> {
        self.s.state(&self.levels.midpoint)
    }
}
