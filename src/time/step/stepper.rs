//! State and workspace shared by every scheme: the factored step system, the displacement, the
//! inertial variables and the contact pressures, and the bookkeeping of one step.

use super::contact_step::ContactStep;
use super::friction::FrictionStep;
use crate::contact::SolveInfo;
use crate::error::{positive, Error, Result};
use crate::linalg;
use crate::problem::Problem;
use crate::time::scheme::{check_finite, State, StepInfo};

/// The common part of every integrator.
pub struct Stepper<'p> {
    pub problem: &'p Problem,
    pub system: ContactStep,
    pub dt: f64,
    pub step: usize,
    /// Displacement U.
    pub u: Vec<f64>,
    /// Inertial displacement w (U, or `C⁻¹ B U` for the mixed mass).
    pub w: Vec<f64>,
    /// Inertial velocity.
    pub v: Vec<f64>,
    /// Contact pressures (nodal forces).
    pub lambda: Vec<f64>,
    /// Right-hand side workspace (displacement dofs).
    pub rhs: Vec<f64>,
    /// Coulomb friction, when the problem has it.
    pub friction: Option<FrictionStep>,
}

impl<'p> Stepper<'p> {
    /// Starts from `(U₀, V₀)` after validating the problem and `dt`.
    pub fn new(problem: &'p Problem, dt: f64, system: ContactStep) -> Result<Self> {
        let w = problem.inertia.project(&problem.u0)?;
        let v = problem.inertia.project(&problem.v0)?;
        if w.iter().chain(&v).any(|x| !x.is_finite()) {
            return Err(Error::invalid(
                "initial state",
                "NaN",
                "initial data must be finite",
            ));
        }
        Ok(Self {
            problem,
            system,
            dt,
            step: 0,
            u: problem.u0.clone(),
            w,
            v,
            lambda: vec![0.0; problem.contact.len()],
            rhs: vec![0.0; problem.n()],
            friction: FrictionStep::new(problem),
        })
    }

    /// `(step, time)` of the level being computed (for error messages).
    pub fn next(&self) -> (usize, f64) {
        (self.step + 1, (self.step + 1) as f64 * self.dt)
    }

    /// `rhs = scale · F` (start of every right-hand side).
    pub fn rhs_from_load(&mut self, scale: f64) {
        let f = &self.problem.f;
        self.rhs.iter_mut().zip(f).for_each(|(r, f)| *r = scale * f);
    }

    /// Solves `A (U, w) = rhs − c B_Nᵀ λ` with the Signorini law on the new gap `g₀ − B_N U`;
    /// with friction, `+ c B_Tᵀ r_T` and Coulomb's law on the slip increment
    /// `Δs = B_T (U_{n+1} − Uₙ)` ([`FrictionStep::position`]), whose work it adds up.
    pub fn solve_position(&mut self) -> Result<SolveInfo> {
        if let Some(f) = self.friction.as_mut() {
            f.position(&self.problem.contact.g0, &self.u);
        }
        let (mut u, mut w) = (std::mem::take(&mut self.u), std::mem::take(&mut self.w));
        let info = self.solve_position_into(&mut u, &mut w);
        (self.u, self.w) = (u, w);
        let info = info?;
        if let Some(f) = self.friction.as_mut() {
            f.dissipate(&self.u);
        }
        Ok(info)
    }

    /// As [`Stepper::solve_position`], writing `(X, w_X)` to `u`, `w` (the schemes whose unknown
    /// is not the new displacement itself; with friction, the offsets must have been set).
    pub fn solve_position_into(&mut self, u: &mut [f64], w: &mut [f64]) -> Result<SolveInfo> {
        let at = self.next();
        let Some(f) = self.friction.as_mut() else {
            return self.system.solve(
                self.problem,
                (&self.rhs, &self.problem.contact.g0),
                (u, w),
                &mut self.lambda,
                at,
            );
        };
        let info = self.system.solve(
            self.problem,
            (&self.rhs, &f.offset),
            (u, w),
            &mut f.reaction,
            at,
        )?;
        self.lambda.copy_from_slice(f.normal());
        Ok(info)
    }

    /// Ends a step: advances the counter and checks that the state is finite.
    pub fn finish(&mut self, info: SolveInfo) -> Result<StepInfo> {
        self.step += 1;
        let t = self.step as f64 * self.dt;
        check_finite(&self.u, self.step, t, "displacement")?;
        check_finite(&self.v, self.step, t, "velocity")?;
        check_finite(&self.lambda, self.step, t, "contact pressure")?;
        Ok(StepInfo {
            contact_iterations: info.iterations,
            active: info.active,
        })
    }

    /// The state, with the scheme's energy displacement.
    pub fn state<'a>(&'a self, energy_u: &'a [f64]) -> State<'a> {
        State {
            t: self.step as f64 * self.dt,
            step: self.step,
            u: &self.u,
            v: &self.v,
            energy_u,
            lambda: &self.lambda,
            extra_energy: 0.0,
            friction_work: self.friction.as_ref().map_or(0.0, |f| f.work),
        }
    }
}

/// Validated time step.
pub fn time_step(problem: &Problem, dt: f64) -> Result<f64> {
    problem.validate()?;
    positive("dt", dt)
}

/// The Galerkin acceleration at t = 0 from `M A₀ = F − K U₀` (no contact force).
pub fn initial_acceleration(problem: &Problem) -> Result<Vec<f64>> {
    let mut r = problem.f.clone();
    linalg::mul_add(&mut r, &problem.k, &problem.u0, -1.0);
    problem.inertia.acceleration(&r)
}

/// Levels n − 1, the midpoint displacement and the half-step velocity of the three-level schemes
/// (Paoli–Schatzman, central difference), started from the Taylor value
/// `U₋₁ = U₀ − Δt V₀ + ½ Δt² A₀`.
pub struct ThreeLevel {
    /// `U_{n−1}`.
    pub u_prev: Vec<f64>,
    /// Inertial `w_{n−1}`.
    pub w_prev: Vec<f64>,
    /// `(U_n + U_{n−1})/2` after a step (U₀ at the start).
    pub midpoint: Vec<f64>,
}

impl ThreeLevel {
    /// The fictitious level −1.
    pub fn start(problem: &Problem, dt: f64) -> Result<Self> {
        let a = initial_acceleration(problem)?;
        let u_prev: Vec<f64> = (0..problem.n())
            .map(|i| problem.u0[i] - dt * problem.v0[i] + 0.5 * dt * dt * a[i])
            .collect();
        Ok(Self {
            w_prev: problem.inertia.project(&u_prev)?,
            u_prev,
            midpoint: problem.u0.clone(),
        })
    }

    /// Moves to the next level: `(u_new, w_new)` becomes the current level (the old current level
    /// becomes n − 1 and the buffers receive the old n − 1, free for reuse); updates the
    /// half-step velocity `v = (w_{n+1} − w_n)/Δt` and the midpoint.
    pub fn rotate(&mut self, s: &mut Stepper, u_new: &mut Vec<f64>, w_new: &mut Vec<f64>) {
        std::mem::swap(&mut self.u_prev, &mut s.u);
        std::mem::swap(&mut s.u, u_new);
        std::mem::swap(&mut self.w_prev, &mut s.w);
        std::mem::swap(&mut s.w, w_new);
        for ((v, w), wp) in s.v.iter_mut().zip(&s.w).zip(&self.w_prev) {
            *v = (w - wp) / s.dt;
        }
        for ((m, u), up) in self.midpoint.iter_mut().zip(&s.u).zip(&self.u_prev) {
            *m = 0.5 * (u + up);
        }
    }
}
