//! Newmark(β, γ) with the contact law at t_{n+1} (Lagrange multipliers, exact LCP per step).
//!
//! Written on the inertial variables (w, v, a) so that it works with a singular mass, as in
//! GetFEM's MU/MV/MA form (`shared/reference/methods.md`):
//!
//! - predictor `w̃ = wₙ + Δt vₙ + Δt² (½ − β) aₙ`;
//! - `(M + β Δt² K) U_{n+1} = M w̃ + β Δt² (F − B_Nᵀ λ_{n+1})` with the Signorini conditions on
//!   `g_{n+1} = g₀ − B_N U_{n+1}` (singular dynamic method: `Bᵀ w_{n+1} + β Δt² K U_{n+1} = …`,
//!   `C w_{n+1} = B U_{n+1}`);
//! - `a_{n+1} = (w_{n+1} − w̃)/(β Δt²)`, `v_{n+1} = vₙ + Δt ((1 − γ) aₙ + γ a_{n+1})`.
//!
//! Newmark (1959); with contact: Khenous, Laborde, Renard (2008), Eur. J. Mech. A/Solids 27.

use super::implicit::ContactStep;
use super::{check_finite, Integrator, Scheme, State, StepInfo};
use crate::contact;
use crate::error::{in_range, positive, Error, Result};
use crate::linalg;
use crate::problem::Problem;

/// Newmark parameters: `β ∈ (0, ½]`, `γ ∈ [½, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Newmark {
    /// β (¼: trapezoidal rule, ½: the seed paper's choice).
    pub beta: f64,
    /// γ (½: no numerical damping).
    pub gamma: f64,
}

impl Newmark {
    /// Validated parameters.
    pub fn new(beta: f64, gamma: f64) -> Result<Self> {
        in_range("beta", positive("beta", beta)?, 0.0, 0.5)?;
        in_range("gamma", gamma, 0.5, 1.0)?;
        Ok(Self { beta, gamma })
    }
}

impl Scheme for Newmark {
    fn name(&self) -> &'static str {
        "newmark"
    }

    fn parameters(&self) -> String {
        format!("beta={};gamma={}", self.beta, self.gamma)
    }

    fn prepare<'p>(
        &self,
        problem: &'p Problem,
        dt: f64,
        contact: Box<dyn contact::Solver>,
    ) -> Result<Box<dyn Integrator + 'p>> {
        positive("dt", dt)?;
        problem.validate()?;
        let c = self.beta * dt * dt;
        let system = ContactStep::new(problem, 1.0, c, c, contact)?;
        let w = problem.inertia.project(&problem.u0)?;
        let v = problem.inertia.project(&problem.v0)?;
        let mut r = problem.f.clone();
        linalg::mul_add(&mut r, &problem.k, &problem.u0, -1.0);
        let a = problem.inertia.initial_acceleration(&r)?;
        let nw = w.len();
        if [&w, &v, &a]
            .iter()
            .any(|x| x.iter().any(|y| !y.is_finite()))
        {
            return Err(Error::invalid(
                "initial state",
                "NaN",
                "initial data must be finite",
            ));
        }
        Ok(Box::new(NewmarkIntegrator {
            p: *self,
            problem,
            system,
            dt,
            t: 0.0,
            step: 0,
            u: problem.u0.clone(),
            w,
            v,
            a,
            lambda: vec![0.0; problem.contact.len()],
            w_pred: vec![0.0; nw],
            rhs: vec![0.0; problem.n()],
        }))
    }
}

struct NewmarkIntegrator<'p> {
    p: Newmark,
    problem: &'p Problem,
    system: ContactStep,
    dt: f64,
    t: f64,
    step: usize,
    u: Vec<f64>,
    w: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    lambda: Vec<f64>,
    w_pred: Vec<f64>,
    rhs: Vec<f64>,
}

impl Integrator for NewmarkIntegrator<'_> {
    fn step(&mut self) -> Result<StepInfo> {
        let (dt, beta, gamma) = (self.dt, self.p.beta, self.p.gamma);
        let c = beta * dt * dt;
        for i in 0..self.w.len() {
            self.w_pred[i] = self.w[i] + dt * self.v[i] + dt * dt * (0.5 - beta) * self.a[i];
        }
        self.rhs
            .iter_mut()
            .zip(&self.problem.f)
            .for_each(|(r, f)| *r = c * f);
        self.problem
            .inertia
            .apply_add(&mut self.rhs, &self.w_pred, 1.0);
        let t_new = (self.step + 1) as f64 * dt;
        let info = self.system.solve(
            self.problem,
            &self.rhs,
            &mut self.u,
            &mut self.w,
            &mut self.lambda,
            (self.step + 1, t_new),
        )?;
        for i in 0..self.w.len() {
            let a_new = (self.w[i] - self.w_pred[i]) / c;
            self.v[i] += dt * ((1.0 - gamma) * self.a[i] + gamma * a_new);
            self.a[i] = a_new;
        }
        self.step += 1;
        self.t = t_new;
        check_finite(&self.u, self.step, self.t, "displacement")?;
        check_finite(&self.v, self.step, self.t, "velocity")?;
        Ok(StepInfo {
            contact_iterations: info.iterations,
            active: info.active,
        })
    }

    fn state(&self) -> State<'_> {
        State {
            t: self.t,
            step: self.step,
            u: &self.u,
            v: &self.v,
            lambda: &self.lambda,
        }
    }
}
