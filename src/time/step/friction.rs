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

use crate::linalg;
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
    /// Rows of `B_T`.
    rows: Vec<Vec<(usize, f64)>>,
    points: usize,
    /// Friction work `W_f` so far.
    pub work: f64,
}

impl FrictionStep {
    /// The friction of `problem`, if it has any.
    pub fn new(problem: &Problem) -> Option<Self> {
        let f = problem.contact.friction.as_ref()?;
        let points = problem.contact.len();
        let rows = linalg::rows(&f.b_t);
        let m = points + rows.len();
        Some(Self {
            offset: vec![0.0; m],
            reaction: vec![0.0; m],
            rows,
            points,
            work: 0.0,
        })
    }

    /// Position-level offsets: `o_N = g₀`, `o_T = −B_T Uₙ`.
    pub fn position(&mut self, g0: &[f64], u_n: &[f64]) {
        self.offset[..self.points].copy_from_slice(g0);
        for (o, row) in self.offset[self.points..].iter_mut().zip(&self.rows) {
            *o = -row.iter().map(|&(j, v)| v * u_n[j]).sum::<f64>();
        }
    }

    /// Velocity-level offsets: `o_N = normal`, `o_T = 0`.
    pub fn velocity(&mut self, normal: &[f64]) {
        self.offset[..self.points].copy_from_slice(normal);
        self.offset[self.points..].fill(0.0);
    }

    /// Adds the work of the step, `−r_T · (o_T + B_T X)`, X the step's solution.
    pub fn dissipate(&mut self, x: &[f64]) {
        let (offset, reaction) = (&self.offset[self.points..], &self.reaction[self.points..]);
        for ((row, o), r) in self.rows.iter().zip(offset).zip(reaction) {
            let slip = o + row.iter().map(|&(j, v)| v * x[j]).sum::<f64>();
            self.work -= r * slip;
        }
    }

    /// The normal reactions λ_N.
    pub fn normal(&self) -> &[f64] {
        &self.reaction[..self.points]
    }
}
