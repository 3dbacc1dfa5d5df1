//! Coulomb friction in an implicit step ([`crate::problem::Friction`]): the offsets of the law on
//! the stacked rows `[B_N; −B_T]` ([`super::direct`]), the reactions `(λ_N, r_T)` and the
//! friction work.
//!
//! The law sees `u_N = o_N − B_N X` and `u_T = o_T + B_T X`, X the step's unknown:
//! - position level (Newmark, HHT, backward Euler; X = U_{n+1}): `o_N = g₀`, `o_T = −B_T Uₙ`,
//!   so that `u_T = Δs = B_T (U_{n+1} − Uₙ)`, the slip increment of the step ("Coulomb on the
//!   discrete slip", DESIGN.md §8);
//! - velocity level (Moreau–Jean; X = V_{n+1}): `o_N` the scheme's impact offsets, `o_T = 0`, so
//!   that `u_T = B_T V_{n+1}`, the end-of-step slip velocity, and r is an impulse.
//!
//! Friction work: `W_f += −r_T · u_T` per step (`r_T · Δs` for a force, `p_T · v_T` for an
//! impulse, an energy either way), ≥ 0 by Coulomb's law (`r_T = −μ λ_N u_T/‖u_T‖` when
//! `u_T ≠ 0`) up to the solver's tolerance.
//!
//! Nitsche's friction ([`crate::contact::nitsche`]) has law rows `B_T − γ S_T` and force rows
//! `Q_T = B_T − θ γ S_T` beside its slip rows `B_T`: the offset is `o_T = −B_T Uₙ` (so the law
//! sees `Δs − γ σ_T(U_{n+1})`) and the work is that of the force it applies,
//! `W_f += −r_T · Q_T (U_{n+1} − Uₙ) = −r_T · (Δs − θ γ Δσ_T)`, which closes `E + W_f` as the
//! nodal work does; its sign is measured, not guaranteed (`tests/friction.rs`).

use crate::linalg::{self, row_dot as dot};
use crate::problem::Problem;

/// What the position-level schemes pose Coulomb's law on ([`crate::time::Scheme::friction`]).
pub const POSITION_SLIP: &str = "the slip increment Δs = B_T (U_{n+1} − Uₙ)";
/// What the velocity-level schemes pose Coulomb's law on.
pub const VELOCITY_SLIP: &str = "the end-of-step slip velocity B_T V_{n+1}";

/// Offsets, reactions and work of the friction law of a step.
#[derive(Debug, Clone)]
pub struct FrictionStep {
    /// Stacked offsets `(o_N, o_T)`.
    pub offset: Vec<f64>,
    /// Stacked reactions `(λ_N, r_T)` (warm start of the next step).
    pub reaction: Vec<f64>,
    /// Rows of the slip `B_T` and of the tangential force `Q_T` (both `B_T` but for Nitsche).
    slip: Vec<Vec<(usize, f64)>>,
    force: Vec<Vec<(usize, f64)>>,
    /// `−Q_T Uₙ` at position level, 0 at velocity level: the work is `−r_T · (moved + Q_T X)`.
    moved: Vec<f64>,
    points: usize,
    /// Friction work `W_f` so far.
    pub work: f64,
}

impl FrictionStep {
    /// The friction of `problem`, if it has any.
    pub fn new(problem: &Problem) -> Option<Self> {
        let f = problem.contact.friction.as_ref()?;
        let points = problem.contact.len();
        let (slip, force) = (linalg::rows(f.slip_rows()), linalg::rows(f.force_rows()));
        let m = points + slip.len();
        Some(Self {
            offset: vec![0.0; m],
            reaction: vec![0.0; m],
            moved: vec![0.0; slip.len()],
            slip,
            force,
            points,
            work: 0.0,
        })
    }

    /// Position-level offsets: `o_N = g₀`, `o_T = −B_T Uₙ` (and `−Q_T Uₙ` for the work).
    pub fn position(&mut self, g0: &[f64], u_n: &[f64]) {
        self.offset[..self.points].copy_from_slice(g0);
        for (o, row) in self.offset[self.points..].iter_mut().zip(&self.slip) {
            *o = -dot(row, u_n);
        }
        for (o, row) in self.moved.iter_mut().zip(&self.force) {
            *o = -dot(row, u_n);
        }
    }

    /// Velocity-level offsets: `o_N = normal`, `o_T = 0`.
    pub fn velocity(&mut self, normal: &[f64]) {
        self.offset[..self.points].copy_from_slice(normal);
        self.offset[self.points..].fill(0.0);
        self.moved.fill(0.0);
    }

    /// Adds the work of the step, `−r_T · (moved + Q_T X)`, X the step's solution (`Q_T = B_T`
    /// but for Nitsche: `−r_T · (o_T + B_T X)`).
    pub fn dissipate(&mut self, x: &[f64]) {
        let reaction = &self.reaction[self.points..];
        for ((row, o), r) in self.force.iter().zip(&self.moved).zip(reaction) {
            let slip = o + dot(row, x);
            self.work -= r * slip;
        }
    }

    /// The normal reactions λ_N.
    pub fn normal(&self) -> &[f64] {
        &self.reaction[..self.points]
    }
}
