//! Penalty contact (inexact, for comparison): the pressure of a stiff spring on the penetration,
//! `λ = κ (−g)₊`, with compliance `ε = 1/κ`.
//!
//! With `g = q + Dλ` the law is `LCP(D + ε I, q)`, solved exactly by [`ActiveSet`]; the result
//! penetrates by `g_i = −ε λ_i`. The compliance is relative to the step: `ε = r · max_i D_ii`
//! (r = `run.penalty`, default 10⁻³), i.e. a penalty stiffness 1/r times that of the stiffest
//! contact point in the step operator. The error is O(r), not zero: the exact solvers are the
//! reference.

use super::active_set::ActiveSet;
use super::{SolveInfo, Solver};
use crate::error::{positive, Result};
use nalgebra::DMatrix;

/// Penalty solver with relative compliance `r`.
#[derive(Debug, Clone)]
pub struct Penalty {
    ratio: f64,
    regularised: DMatrix<f64>,
    exact: ActiveSet,
}

impl Penalty {
    /// Workspace for `n_c` points and relative compliance `ratio` (> 0).
    pub fn new(n_c: usize, ratio: f64) -> Result<Self> {
        Ok(Self {
            ratio: positive("run.penalty", ratio)?,
            regularised: DMatrix::zeros(n_c, n_c),
            exact: ActiveSet::new(n_c),
        })
    }
}

impl Solver for Penalty {
    fn name(&self) -> &'static str {
        "penalty"
    }

    fn solve(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> std::result::Result<SolveInfo, String> {
        let n = q.len();
        let eps = self.ratio * (0..n).fold(0.0f64, |m, i| m.max(d[(i, i)]));
        self.regularised.copy_from(d);
        for i in 0..n {
            self.regularised[(i, i)] += eps;
        }
        self.exact.solve(&self.regularised, q, lambda)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn penalty_penetrates_by_epsilon_lambda() {
        let d = DMatrix::from_element(1, 1, 2.0);
        let mut l = [0.0];
        Penalty::new(1, 0.01)
            .unwrap()
            .solve(&d, &[-1.0], &mut l)
            .unwrap();
        // λ = 1/(2 + 0.02), g = −1 + 2λ = −0.02 λ.
        assert!((l[0] - 1.0 / 2.02).abs() < 1e-15);
        assert!(Penalty::new(1, 0.0).is_err());
    }
}
