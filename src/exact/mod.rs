//! Exact solutions the discrete runs are compared with.

pub mod bar_impact;
pub mod hertz;
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
