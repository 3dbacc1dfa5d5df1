//! Exact solutions the discrete runs are compared with.

pub mod bar_flight;
pub mod bar_impact;
pub mod hertz;
pub mod mbf;
pub mod oblique;
pub mod roll;
pub mod slide;
pub mod spring_mass;
pub mod two_bars;

/// Exact values at the contact point at time t.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactValues {
    /// Normal-direction displacement of the contact point (the gap for these cases).
    pub u: f64,
    /// Its velocity.
    pub v: f64,
    /// Normal contact stress σ_N (≤ 0).
    pub sigma: f64,
}

/// An exact solution sampled at the contact point, with its (conserved) energy.
pub trait ExactContact: Send + Sync {
    /// Values at the contact point at time t.
    fn contact(&self, t: f64) -> ContactValues;
    /// Exact total energy at time t.
    fn energy(&self, t: f64) -> f64;
    /// Time of the first impact, if any.
    fn first_impact(&self) -> Option<f64>;
}

/// The lines of a 1D field that is linear between consecutive `ends` (increasing, from 0): for
/// each piece `(right end, value at 0 of the line, slope σ/E)`, from `field(x) = (u, σ)` at its
/// midpoint.
pub fn lines_between(
    ends: impl IntoIterator<Item = f64>,
    young: f64,
    field: impl Fn(f64) -> (f64, f64),
) -> Vec<(f64, f64, f64)> {
    let mut left = 0.0;
    ends.into_iter()
        .map(|right| {
            let mid = 0.5 * (left + right);
            let (u, sigma) = field(mid);
            let slope = sigma / young;
            left = right;
            (right, u - slope * mid, slope)
        })
        .collect()
}

/// An exact 1D bar solution (bar (0, L), modulus E) that is piecewise linear in x at every t,
/// with at most two kinks (its wave fronts): the bar cases' field errors are exact per piece
/// ([`crate::cases::bar::BarFieldError`]).
pub trait PiecewiseLinearBar: ExactContact {
    /// L.
    fn length(&self) -> f64;
    /// E.
    fn young(&self) -> f64;
    /// ρ.
    fn density(&self) -> f64;
    /// `(u, σ = E u_x, u_t)` at (x, t).
    fn field(&self, x: f64, t: f64) -> (f64, f64, f64);
    /// The kinks of `u(·, t)` in increasing order; a kink may repeat, or lie at 0 or L, when
    /// there are fewer than two inside the bar.
    fn kinks(&self, t: f64) -> [f64; 2];
}
