//! Paoli–Schatzman scheme with restitution e ∈ [0, 1] (Paoli & Schatzman 2002, SIAM J. Numer.
//! Anal. 40; for FEM: Dumont & Paoli 2006): a three-level midpoint scheme
//!
//! `M (U_{n+1} − 2Uₙ + U_{n−1})/Δt² + K (U_{n+1} + 2Uₙ + U_{n−1})/4 = F − B_Nᵀ λ`,
//!
//! with the Signorini conditions on `Z = (U_{n+1} + e U_{n−1})/(1 + e)`:
//! `g₀ − B_N Z ≥ 0, λ ≥ 0, λ·(g₀ − B_N Z) = 0`. Substituting `U_{n+1} = (1 + e) Z − e U_{n−1}`, each
//! step solves for Z with `A = M + Δt²/4 K` and contact coefficient `Δt²/(1 + e)`:
//!
//! `A Z = [M (2Uₙ + (e − 1) U_{n−1}) − Δt²/4 K (2Uₙ + (1 − e) U_{n−1}) + Δt² F]/(1 + e) − Δt²/(1 + e) B_Nᵀ λ`.
//!
//! Without contact it conserves `E_{n+½} = ½‖(U_{n+1} − Uₙ)/Δt‖²_M + ½ Ūᵀ K Ū − Fᵀ Ū`,
//! `Ū = (U_{n+1} + Uₙ)/2`, which is the energy reported (see [`super::State::energy_u`]).
//! Started from `U₋₁ = U₀ − Δt V₀ + ½ Δt² A₀`. M products use the inertial variables, so every
//! space, including the singular dynamic method, is supported.

use super::scheme::{Integrator, Scheme, State, StepInfo};
use super::step::ContactStep;
use super::step::{time_step, Stepper, ThreeLevel};
use crate::contact::Enforcement;
use crate::error::{in_range, Result};
use crate::linalg;
use crate::param::{Entry, Param};
use crate::problem::Problem;

/// Newton's restitution coefficient e (also Moreau–Jean's).
pub const RESTITUTION: Param = Param {
    name: "restitution",
    label: "e",
    default: 0.0,
    help: "Restitution coefficient e ∈ [0, 1] (paoli_schatzman, moreau_jean; spring_mass: the case's e)",
};

/// Registry entry: `paoli_schatzman` with e.
pub const ENTRY: Entry<dyn Scheme> = Entry {
    name: "paoli_schatzman",
    params: &[&RESTITUTION],
    build: |p| Ok(Box::new(PaoliSchatzman::new(p.get(&RESTITUTION))?)),
};

/// Restitution coefficient e ∈ [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaoliSchatzman {
    /// e (1: elastic impacts, 0: inelastic).
    pub restitution: f64,
}

impl PaoliSchatzman {
    /// Validated restitution.
    pub fn new(restitution: f64) -> Result<Self> {
        in_range("restitution", restitution, 0.0, 1.0)?;
        Ok(Self { restitution })
    }
}

impl Scheme for PaoliSchatzman {
    fn name(&self) -> &'static str {
        "paoli_schatzman"
    }

    fn enforcement(&self) -> Enforcement {
        Enforcement::Impact
    }

    fn prepare<'p>(
        &self,
        problem: &'p Problem,
        dt: f64,
        contact: super::scheme::Solvers,
    ) -> Result<Box<dyn Integrator + 'p>> {
        let dt = time_step(problem, dt)?;
        let e = self.restitution;
        let system =
            ContactStep::new(problem, (1.0, 0.25 * dt * dt), dt * dt / (1.0 + e), contact)?;
        let levels = ThreeLevel::start(problem, dt)?;
        let s = Stepper::new(problem, dt, system)?;
        Ok(Box::new(PaoliSchatzmanIntegrator {
            e,
            levels,
            z: vec![0.0; s.u.len()],
            wz: vec![0.0; s.w.len()],
            s,
        }))
    }
}

struct PaoliSchatzmanIntegrator<'p> {
    s: Stepper<'p>,
    e: f64,
    levels: ThreeLevel,
    /// Z (and scratch), displacement dofs.
    z: Vec<f64>,
    /// Inertial Z (and scratch).
    wz: Vec<f64>,
}

impl Integrator for PaoliSchatzmanIntegrator<'_> {
    fn step(&mut self) -> Result<StepInfo> {
        let (dt, e) = (self.s.dt, self.e);
        let (up, wp) = (&self.levels.u_prev, &self.levels.w_prev);
        linalg::combine(&mut self.z, (2.0, &self.s.u), (1.0 - e, up));
        linalg::combine(&mut self.wz, (2.0, &self.s.w), (e - 1.0, wp));
        self.s.rhs_from_load(dt * dt);
        linalg::mul_add(&mut self.s.rhs, &self.s.problem.k, &self.z, -0.25 * dt * dt);
        self.s
            .problem
            .inertia
            .apply_add(&mut self.s.rhs, &self.wz, 1.0);
        self.s.rhs.iter_mut().for_each(|r| *r /= 1.0 + e);
        let info = self.s.solve_position_into(&mut self.z, &mut self.wz)?;
        linalg::scale_add(&mut self.z, 1.0 + e, -e, &self.levels.u_prev);
        linalg::scale_add(&mut self.wz, 1.0 + e, -e, &self.levels.w_prev);
        self.levels.rotate(&mut self.s, &mut self.z, &mut self.wz);
        self.s.finish(info)
    }

    fn state(&self) -> State<'_> {
        self.s.state(&self.levels.midpoint)
    }
}
