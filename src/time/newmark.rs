//! Newmark(β, γ) with the contact law at t_{n+1} (Lagrange multipliers, exact LCP per step).
//!
//! Written on the inertial variables (w, v, a) so that it works with a singular mass, as in
//! GetFEM's MU/MV/MA form (`shared/reference/methods.md`):
//!
//! - predictor `w̃ = wₙ + Δt vₙ + Δt² (½ − β) aₙ`;
//! - `(M + (1 + α) β Δt² K) U_{n+1} = M w̃ + β Δt² (F + α K Uₙ − B_Nᵀ λ_{n+1})` with the Signorini
//!   conditions on `g_{n+1} = g₀ − B_N U_{n+1}` (singular dynamic method: `Bᵀ w_{n+1} + … = …`,
//!   `C w_{n+1} = B U_{n+1}`); α = 0 here, α ≠ 0 is [`super::hht`];
//! - `a_{n+1} = (w_{n+1} − w̃)/(β Δt²)`, `v_{n+1} = vₙ + Δt ((1 − γ) aₙ + γ a_{n+1})`.
//!
//! Newmark (1959); with contact: Khenous, Laborde, Renard (2008), Eur. J. Mech. A/Solids 27.
//!
//! Coulomb friction: `+ β Δt² B_Tᵀ r_T` beside the pressure, the law at t_{n+1} on the slip
//! increment `Δs = B_T (U_{n+1} − Uₙ)` ([`super::step::friction`]).

use super::scheme::{Integrator, Scheme, State, StepInfo};
use super::step::ContactStep;
use super::step::{initial_acceleration, time_step, Stepper};
use crate::contact::Enforcement;
use crate::error::{in_range, positive, Result};
use crate::linalg;
use crate::param::{Entry, Param};
use crate::problem::Problem;

/// Newmark β; default ½, the value of every case file's sweeps (¼, the trapezoidal rule,
/// diverges on spring_mass with contact at dt = 2.5e-3).
pub const BETA: Param = Param {
    name: "beta",
    label: "beta",
    default: 0.5,
    help: "Newmark β ∈ (0, 1/2], 1/4 the trapezoidal rule",
};
/// Newmark γ.
pub const GAMMA: Param = Param {
    name: "gamma",
    label: "gamma",
    default: 0.5,
    help: "Newmark γ ∈ [1/2, 1]",
};

/// Registry entry: `newmark` with β, γ.
pub const ENTRY: Entry<dyn Scheme> = Entry {
    name: "newmark",
    params: &[&BETA, &GAMMA],
    build: |p| Ok(Box::new(Newmark::new(p.get(&BETA), p.get(&GAMMA))?)),
};

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
        Ok(Box::new(NewmarkIntegrator::new(
            problem, dt, contact, *self, 0.0,
        )?))
    }
}

/// Newmark / HHT-α integrator (α = 0: Newmark).
pub(crate) struct NewmarkIntegrator<'p> {
    s: Stepper<'p>,
    p: Newmark,
    alpha: f64,
    a: Vec<f64>,
    w_pred: Vec<f64>,
}

impl<'p> NewmarkIntegrator<'p> {
    /// Factors `M + (1 + α) β Δt² K` and starts from a consistent initial acceleration.
    pub fn new(
        problem: &'p Problem,
        dt: f64,
        contact: super::scheme::Solvers,
        p: Newmark,
        alpha: f64,
    ) -> Result<Self> {
        let dt = time_step(problem, dt)?;
        let c = p.beta * dt * dt;
        let system = ContactStep::new(problem, (1.0, (1.0 + alpha) * c), c, contact)?;
        let a = problem.inertia.project(&initial_acceleration(problem)?)?;
        let s = Stepper::new(problem, dt, system)?;
        super::scheme::check_finite(&a, 0, 0.0, "initial acceleration")?;
        Ok(Self {
            w_pred: vec![0.0; a.len()],
            s,
            p,
            alpha,
            a,
        })
    }
}

impl Integrator for NewmarkIntegrator<'_> {
    fn step(&mut self) -> Result<StepInfo> {
        let (dt, beta, gamma) = (self.s.dt, self.p.beta, self.p.gamma);
        let c = beta * dt * dt;
        let k = dt * dt * (0.5 - beta);
        for (((wp, &w), &v), &a) in self
            .w_pred
            .iter_mut()
            .zip(&self.s.w)
            .zip(&self.s.v)
            .zip(&self.a)
        {
            *wp = w + dt * v + k * a;
        }
        self.s.rhs_from_load(c);
        if self.alpha != 0.0 {
            linalg::mul_add(
                &mut self.s.rhs,
                &self.s.problem.k,
                &self.s.u,
                c * self.alpha,
            );
        }
        self.s
            .problem
            .inertia
            .apply_add(&mut self.s.rhs, &self.w_pred, 1.0);
        let info = self.s.solve_position()?;
        let inv_c = 1.0 / c;
        let (ga, gb) = (dt * (1.0 - gamma), dt * gamma);
        let pairs = self.s.w.iter().zip(&self.w_pred);
        for ((v, a), (&w, &wp)) in self.s.v.iter_mut().zip(self.a.iter_mut()).zip(pairs) {
            let a_new = (w - wp) * inv_c;
            *v += ga * *a + gb * a_new;
            *a = a_new;
        }
        self.s.finish(info)
    }

    fn state(&self) -> State<'_> {
        self.s.state(&self.s.u)
    }
}
