//! Moreau–Jean time-stepping (Moreau 1988, Jean 1999; Acary & Brogliato 2008, §10.1): a θ-method
//! on the velocities with a velocity-level Signorini law and Newton's restitution e:
//!
//! - `M (V_{n+1} − Vₙ) = Δt (F − K U_{n+θ}) − B_Nᵀ P_{n+1}`, `U_{n+θ} = (1 − θ) Uₙ + θ U_{n+1}`,
//!   `U_{n+1} = Uₙ + Δt ((1 − θ) Vₙ + θ V_{n+1})`, i.e.
//!   `(M + θ² Δt² K) V_{n+1} = M Vₙ + Δt (F − K Uₙ) − θ (1 − θ) Δt² K Vₙ − B_Nᵀ P_{n+1}`;
//! - index set `𝒜 = {i : g_i(Uₙ + ½ Δt Vₙ) ≤ 0}` (points predicted closed at mid-step);
//! - on 𝒜: `0 ≤ P_i ⊥ (ġ_{n+1} + e ġₙ)_i ≥ 0` with `ġ = −B_N V`; off 𝒜: `P_i = 0`.
//!
//! P is an impulse; the reported pressure is `λ = P/Δt`. First order with impacts; θ = ½ and e = 1
//! conserve the energy `½ V·MV + ½ UᵀKU − FᵀU` exactly (the impulse does no work when
//! `ġ_{n+1} = −ġₙ`). Penetration is O(Δt), not zero: the law holds on velocities. With the
//! singular dynamic method the inertial variable is the H_h velocity `C⁻¹ B V`.
//!
//! On a finite element body take e = 0: the body's elasticity makes its rebound. A nodal e = 1
//! models no elastic body: with θ = ½ a point with `P_i > 0` has `ġ_{n+1} = −ġₙ`, so its gap
//! freezes (`Δg = ½ Δt (ġₙ + ġ_{n+1}) = 0`) while its velocity flips sign every step. On
//! `cases/oblique3d.toml` (n = 8, Δt = 0.1, 45°, standard mass) the closed points' normal
//! velocities reach 1.07 (150 V), their slip velocities 0.02 (3 × the sliding 0.007): at
//! mid-impact 35–48 of the 88 closed points slip backwards and 13–26 stick, so each obeys
//! Coulomb (`Σ|p_T| = 0.085 p_N`) but the resultant is 0.01 p_N, and `|J_t| = 0.15 μ J_n`
//! against 0.998 with e = 0 (`tests/oblique.rs`).
//!
//! Coulomb friction (its natural home; Siconos `event_capturing.rst` lines 519–549,
//! `notes/papers/friction.md` §3): `+ B_Tᵀ P_T` beside the normal impulse, the law on the
//! index set between the impulse and the end-of-step slip velocity `u_T = B_T V_{n+1}` (no
//! tangential restitution). The friction work reported is `Σ −P_T · u_{T,n+1} ≥ 0`; the scheme's
//! energy identity holds the θ-weighted `P · V_θ` instead, so `E + W_f` is not conserved
//! exactly (exactly only when `P_T · (V_{T,n+1} − V_{T,n}) = 0`, e.g. steady sliding with θ = 1).

use super::paoli_schatzman::RESTITUTION;
use super::scheme::{Integrator, Scheme, State, StepInfo};
use super::step::ContactStep;
use super::step::{time_step, Stepper};
use crate::contact::Enforcement;
use crate::error::{in_range, Error, Result};
use crate::linalg;
use crate::param::{Entry, Param};
use crate::problem::Problem;

/// Moreau–Jean θ.
pub const THETA: Param = Param {
    name: "theta",
    label: "theta",
    default: 0.5,
    help: "Moreau–Jean θ ∈ [1/2, 1]",
};

/// Registry entry: `moreau_jean` with θ and e.
pub const ENTRY: Entry<dyn Scheme> = Entry {
    name: "moreau_jean",
    params: &[&THETA, &RESTITUTION],
    build: |p| {
        Ok(Box::new(MoreauJean::new(
            p.get(&THETA),
            p.get(&RESTITUTION),
        )?))
    },
};

/// θ ∈ [½, 1] and restitution e ∈ [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoreauJean {
    /// θ (½: midpoint, 1: implicit Euler on velocities).
    pub theta: f64,
    /// Newton restitution coefficient e.
    pub restitution: f64,
}

impl MoreauJean {
    /// Validated parameters.
    pub fn new(theta: f64, restitution: f64) -> Result<Self> {
        in_range("theta", theta, 0.5, 1.0)?;
        in_range("restitution", restitution, 0.0, 1.0)?;
        Ok(Self { theta, restitution })
    }
}

/// The smallest θ on a space without inertia at the contact dofs: the odd–even factor
/// `(1 − θ)/θ` is then 0.82. Measured on bar1d (mass redistribution, 40 elements, Δt = h/2):
/// penetration 0.497 at θ = ½, 0.49 at 0.501, 6.2e-2 at 0.51, 1.2e-2 at 0.52 and 2.8e-3 at
/// 0.55, the standard mass's O(Δt) (2.9e-3 at ½).
pub const THETA_WITHOUT_INERTIA: f64 = 0.55;

impl MoreauJean {
    /// Refuses θ below [`THETA_WITHOUT_INERTIA`] on a mass without inertia at the contact dofs
    /// (mass redistribution, mass elimination, modified quadrature: zero rows; the singular
    /// dynamic method: a kernel). There `M (V_{n+1} − Vₙ)` does not see the velocity, which the
    /// θ-method's `V_{n+1} = (U_{n+θ} − Uₙ)/(θ²Δt) − (1 − θ)/θ · Vₙ` carries with the odd–even
    /// factor `−(1 − θ)/θ`, undamped at θ = ½ and barely damped near it: on bar1d the law
    /// `ġ_{n+1} ≥ 0` is met by the oscillation and the end passes through the obstacle by the
    /// whole lift with no impulse; slide2d's energy grows past twice.
    fn check_inertia(&self, problem: &Problem) -> Result<()> {
        if self.theta >= THETA_WITHOUT_INERTIA {
            return Ok(());
        }
        let without = problem.inertia.sparse().is_none() || {
            let massless = problem.inertia.massless();
            linalg::triplets(&problem.contact.b_n).any(|(_, j, _)| massless[j])
        };
        if !without {
            return Ok(());
        }
        Err(Error::Unsupported(format!(
            "moreau_jean with θ = {} needs inertia at the contact dofs, and this space has none \
             there: θ near ½ leaves their velocity's odd–even mode (factor (1 − θ)/θ per step) \
             too little damped and the velocity law does not hold the position (bar1d: the end \
             passes through the obstacle by the whole lift at θ = ½, 6.2e-2 at 0.51); take \
             θ ≥ {THETA_WITHOUT_INERTIA} (bar1d: penetration 2.8e-3)",
            crate::error::short(self.theta)
        )))
    }
}

impl Scheme for MoreauJean {
    fn name(&self) -> &'static str {
        "moreau_jean"
    }

    fn enforcement(&self) -> Enforcement {
        Enforcement::Impact
    }

    fn friction(&self) -> Option<&'static str> {
        Some(super::step::friction::VELOCITY_SLIP)
    }

    fn prepare<'p>(
        &self,
        problem: &'p Problem,
        dt: f64,
        contact: super::scheme::Solvers,
    ) -> Result<Box<dyn Integrator + 'p>> {
        self.check_inertia(problem)?;
        let dt = time_step(problem, dt)?;
        let th = self.theta * dt;
        let system = ContactStep::new(problem, (1.0, th * th), 1.0, contact)?;
        let s = Stepper::new(problem, dt, system)?;
        let nc = problem.contact.len();
        Ok(Box::new(MoreauJeanIntegrator {
            p: *self,
            vel: problem.v0.clone(),
            scratch: vec![0.0; problem.n()],
            offset: vec![0.0; nc],
            normal_velocity: vec![0.0; nc],
            impulse: vec![0.0; nc],
            s,
        }))
    }
}

struct MoreauJeanIntegrator<'p> {
    s: Stepper<'p>,
    p: MoreauJean,
    /// Displacement velocity V (the Stepper's `v` is the inertial velocity).
    vel: Vec<f64>,
    scratch: Vec<f64>,
    offset: Vec<f64>,
    normal_velocity: Vec<f64>,
    impulse: Vec<f64>,
}

impl MoreauJeanIntegrator<'_> {
    /// Offsets of the velocity law: `−e (B_N Vₙ)_i` on the index set, `+∞` elsewhere.
    fn index_set(&mut self) {
        let (dt, contact) = (self.s.dt, &self.s.problem.contact);
        for ((x, u), v) in self.scratch.iter_mut().zip(&self.s.u).zip(&self.vel) {
            *x = u + 0.5 * dt * v;
        }
        contact.gap(&self.scratch, &mut self.offset);
        self.normal_velocity.fill(0.0);
        linalg::mul_add(&mut self.normal_velocity, &contact.b_n, &self.vel, 1.0);
        for (o, bv) in self.offset.iter_mut().zip(&self.normal_velocity) {
            *o = if *o <= 0.0 {
                -self.p.restitution * bv
            } else {
                f64::INFINITY
            };
        }
    }
}

impl Integrator for MoreauJeanIntegrator<'_> {
    fn step(&mut self) -> Result<StepInfo> {
        let (dt, th) = (self.s.dt, self.p.theta);
        self.index_set();
        let k = &self.s.problem.k;
        self.s.rhs_from_load(dt);
        linalg::mul_add(&mut self.s.rhs, k, &self.s.u, -dt);
        linalg::mul_add(&mut self.s.rhs, k, &self.vel, -th * (1.0 - th) * dt * dt);
        self.s
            .problem
            .inertia
            .apply_add(&mut self.s.rhs, &self.s.v, 1.0);
        linalg::axpy(&mut self.s.u, (1.0 - th) * dt, &self.vel);
        let at = self.s.next();
        let (offset, impulse) = match self.s.friction.as_mut() {
            None => (&self.offset, &mut self.impulse),
            Some(f) => {
                f.velocity(&self.offset);
                (&f.offset, &mut f.reaction)
            }
        };
        let info = self.s.system.solve(
            self.s.problem,
            (&self.s.rhs, offset),
            (&mut self.vel, &mut self.s.v),
            impulse,
            at,
        )?;
        if let Some(f) = self.s.friction.as_mut() {
            f.dissipate(&self.vel);
            self.impulse.copy_from_slice(f.normal());
        }
        linalg::axpy(&mut self.s.u, th * dt, &self.vel);
        for (l, p) in self.s.lambda.iter_mut().zip(&self.impulse) {
            *l = p / dt;
        }
        self.s.finish(info)
    }

    fn state(&self) -> State<'_> {
        self.s.state(&self.s.u)
    }
}
