//! The trapezoidal step (Newmark ¼, ½ on the smooth forces) with the contact force applied
//! once over the step, shared by the schemes that differ only in their predictor and their law
//! on the contact rows (Laursen–Chawla, Kane et al., Deuflhard–Krause–Ertel, Hauret–Le Tallec):
//!
//! - `M (v_{n+1} − v_n)/Δt = F − K u_{n+½} − B_Nᵀ λ`,  `(u_{n+1} − u_n)/Δt = (v_n + v_{n+1})/2`;
//! - eliminating v_{n+1}: `(M + Δt²/4 K) u_{n+1} = Lᵀ y − Δt²/4 K u_n + Δt²/2 F − Δt²/2 B_Nᵀ λ`
//!   with the inertial predictor `y = w_n + Δt v_n` (Lᵀ y = M y for a sparse mass), then
//!   `v_{n+1} = v_n + (2/Δt)(w_{n+1} − y)`.
//!
//! A scheme may replace y by a projection of it before the solve (the contact-stabilised
//! Newmark of Deuflhard, Krause & Ertel); the velocity update uses the y of the solve.

use super::contact_step::ContactStep;
use super::stepper::Stepper;
use crate::error::Result;
use crate::linalg;
use crate::problem::Problem;
use crate::time::Solvers;

/// The predictor y of the trapezoidal step (inertial variables).
pub struct Trapezoidal {
    /// `y = w_n + Δt v_n`, or what the scheme replaced it with.
    pub y: Vec<f64>,
}

impl Trapezoidal {
    /// The step operator `A = M + Δt²/4 K` with the force factor `c = Δt²/2`.
    pub fn system(problem: &Problem, dt: f64, solvers: Solvers) -> Result<ContactStep> {
        ContactStep::new(problem, (1.0, 0.25 * dt * dt), 0.5 * dt * dt, solvers)
    }

    /// A predictor of the stepper's inertial dimension.
    pub fn new(s: &Stepper) -> Self {
        Self {
            y: vec![0.0; s.w.len()],
        }
    }

    /// `y = w_n + Δt v_n`.
    pub fn predict(&mut self, s: &Stepper) {
        for ((y, w), v) in self.y.iter_mut().zip(&s.w).zip(&s.v) {
            *y = w + s.dt * v;
        }
    }

    /// `rhs = Lᵀ y − Δt²/4 K u_n + Δt²/2 F`.
    pub fn rhs(&self, s: &mut Stepper) {
        let dt = s.dt;
        s.rhs_from_load(0.5 * dt * dt);
        linalg::mul_add(&mut s.rhs, &s.problem.k, &s.u, -0.25 * dt * dt);
        s.problem.inertia.apply_add(&mut s.rhs, &self.y, 1.0);
    }

    /// `v_{n+1} = v_n + (2/Δt)(w_{n+1} − y)`, after the solve.
    pub fn velocity(&self, s: &mut Stepper) {
        let k = 2.0 / s.dt;
        for ((v, w), y) in s.v.iter_mut().zip(&s.w).zip(&self.y) {
            *v += k * (w - y);
        }
    }
}
