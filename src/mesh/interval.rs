//! Uniform mesh of the interval (0, L).

use crate::error::{positive, Error, Result};

/// `n_elements` equal segments of (0, `length`); vertex i at x_i = i L / N.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntervalMesh {
    /// Length L of the interval.
    pub length: f64,
    /// Number of elements N.
    pub n_elements: usize,
}

impl IntervalMesh {
    /// A validated mesh (L > 0, N ≥ 1).
    pub fn new(length: f64, n_elements: usize) -> Result<Self> {
        positive("geometry.length", length)?;
        if n_elements == 0 {
            return Err(Error::invalid("elements", n_elements, "must be >= 1"));
        }
        Ok(Self { length, n_elements })
    }

    /// Element size h = L / N.
    pub fn h(&self) -> f64 {
        self.length / self.n_elements as f64
    }

    /// Left end of element `e`.
    pub fn x_left(&self, e: usize) -> f64 {
        e as f64 * self.h()
    }

    /// The element containing `x` (the last one for x = L) and the reference coordinate ξ ∈ [0, 1].
    pub fn locate(&self, x: f64) -> (usize, f64) {
        let s = (x / self.h()).clamp(0.0, self.n_elements as f64);
        let e = (s.floor() as usize).min(self.n_elements - 1);
        (e, s - e as f64)
    }
}
