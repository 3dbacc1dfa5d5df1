//! Backward (implicit) Euler on the first-order form, contact at t_{n+1}:
//!
//! `v_{n+1} = vₙ + Δt a_{n+1}`, `U_{n+1} = Uₙ + Δt v_{n+1}`, i.e. in inertial variables
//! `(M + Δt² K) U_{n+1} = M (wₙ + Δt vₙ) + Δt² (F − B_Nᵀ λ_{n+1})`, `v_{n+1} = (w_{n+1} − wₙ)/Δt`.
//!
//! First order and dissipative: multiplying by `U_{n+1} − Uₙ` gives
//! `E_{n+1} − Eₙ = −½‖v_{n+1} − vₙ‖²_M − ½‖U_{n+1} − Uₙ‖²_K − λ_{n+1}·gₙ ≤ 0`
//! (the contact force only works on a gap that closes). Hairer & Wanner, Solving ODEs II.
//!
//! Coulomb friction: `+ Δt² B_Tᵀ r_T`, the law at t_{n+1} on the slip increment
//! `Δs = B_T (U_{n+1} − Uₙ)`; the same product gives `E_{n+1} + W_{f,n+1} ≤ Eₙ + W_{f,n}` with
//! `W_{f,n+1} − W_{f,n} = −r_T · Δs ≥ 0`: the friction work never exceeds the energy lost.

use super::scheme::{Integrator, Scheme, State, StepInfo};
use super::step::ContactStep;
use super::step::{time_step, Stepper};
use crate::contact::Enforcement;
use crate::error::Result;
use crate::param::Entry;
use crate::problem::Problem;

/// Registry entry: `backward_euler` (no parameter).
pub const ENTRY: Entry<dyn Scheme> = Entry {
    name: "backward_euler",
    params: &[],
    build: |_| Ok(Box::new(BackwardEuler)),
};

/// Backward Euler (no parameter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BackwardEuler;

impl Scheme for BackwardEuler {
    fn name(&self) -> &'static str {
        "backward_euler"
    }

    fn enforcement(&self) -> Enforcement {
        Enforcement::Position
    }

    fn friction(&self) -> Option<&'static str> {
        Some(super::step::friction::POSITION_SLIP)
    }

    fn prepare<'p>(
        &self,
        problem: &'p Problem,
        dt: f64,
        contact: super::scheme::Solvers,
    ) -> Result<Box<dyn Integrator + 'p>> {
        let system = Self::system(problem, dt, contact)?;
        Ok(Box::new(Self::with_system(problem, dt, system)?))
    }
}

impl BackwardEuler {
    /// The step system `M + Δt² K` of `problem` with its contact coupling (factored, for a
    /// direct solver).
    pub fn system(
        problem: &Problem,
        dt: f64,
        contact: super::scheme::Solvers,
    ) -> Result<ContactStep> {
        let dt = time_step(problem, dt)?;
        ContactStep::new(problem, (1.0, dt * dt), dt * dt, contact)
    }

    /// The integrator from the problem's initial state with the step system of
    /// [`BackwardEuler::system`] for this Δt, built for a problem with the same matrices and
    /// contact (its load and initial state may differ: several static solves share a factor).
    pub fn with_system(
        problem: &Problem,
        dt: f64,
        system: ContactStep,
    ) -> Result<BackwardEulerIntegrator<'_>> {
        let s = Stepper::new(problem, time_step(problem, dt)?, system)?;
        Ok(BackwardEulerIntegrator {
            y: vec![0.0; s.w.len()],
            s,
        })
    }
}

/// Backward Euler's integrator ([`BackwardEuler::with_system`]).
pub struct BackwardEulerIntegrator<'p> {
    s: Stepper<'p>,
    /// `wₙ + Δt vₙ`.
    y: Vec<f64>,
}

impl BackwardEulerIntegrator<'_> {
    /// Its step system, for another integrator ([`BackwardEuler::with_system`]).
    pub fn into_system(self) -> ContactStep {
        self.s.system
    }
}

impl Integrator for BackwardEulerIntegrator<'_> {
    fn step(&mut self) -> Result<StepInfo> {
        let dt = self.s.dt;
        for ((y, w), v) in self.y.iter_mut().zip(&self.s.w).zip(&self.s.v) {
            *y = w + dt * v;
        }
        self.s.rhs_from_load(dt * dt);
        self.s
            .problem
            .inertia
            .apply_add(&mut self.s.rhs, &self.y, 1.0);
        let info = self.s.solve_position()?;
        // v_{n+1} = (w_{n+1} − wₙ)/Δt = vₙ + (w_{n+1} − y)/Δt.
        for ((v, w), y) in self.s.v.iter_mut().zip(&self.s.w).zip(&self.y) {
            *v += (w - y) / dt;
        }
        self.s.finish(info)
    }

    fn state(&self) -> State<'_> {
        self.s.state(&self.s.u)
    }
}
