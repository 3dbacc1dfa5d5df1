//! Penalty contact (a formulation, `--contact penalty`; inexact, for comparison): nodal rows, and
//! the pressure of a stiff spring on the penetration, `λ = κ (−g)₊`, with compliance `ε = 1/κ`.
//!
//! With `g = q + Dλ` the law is `LCP(D + ε I, q)`, solved exactly by the chosen LCP solver
//! (`--contact-solver`); the result
//! penetrates by `g_i = −ε λ_i`. The compliance is relative to the step: `ε = r · max_i D_ii`
//! (r = `run.penalty`, default 10⁻³), i.e. a penalty stiffness 1/r times that of the stiffest
//! contact point in the step operator. The error is O(r), not zero: the exact solvers are the
//! reference.

use super::{Formulation, SolveInfo, Solver};
use crate::error::{Result, SolverError};
use crate::param::{Entry, Options, Param};
use crate::problem::Problem;
use nalgebra::DMatrix;

/// Relative compliance r of the penalty.
pub const PENALTY: Param = Param {
    name: "penalty",
    label: "penalty",
    default: 1e-3,
    help: "Relative compliance r of the penalty contact (ε = r · max D_ii)",
};

/// Registry entry: `penalty` with r.
pub const ENTRY: Entry<dyn Formulation, Options> = Entry {
    name: "penalty",
    params: &[&PENALTY],
    build: |o| Ok(Box::new(PenaltyContact::new(o.params.get(&PENALTY))?)),
};

/// The penalty formulation: nodal rows, penalised law.
#[derive(Debug, Clone, Copy)]
pub struct PenaltyContact {
    ratio: f64,
}

impl PenaltyContact {
    /// Relative compliance `ratio` (> 0): the penalty stiffness `1/ε` is `1/ratio` times the
    /// step's stiffest contact point's `1/max D_ii`, refused below [`crate::error::MIN_PENALTY`].
    pub fn new(ratio: f64) -> Result<Self> {
        let scale =
            "the stiffness 1/max D_ii of the step's stiffest contact point (ε = r max D_ii)";
        Ok(Self {
            ratio: crate::error::penalty("run.penalty", ratio, 1.0 / ratio, scale)?,
        })
    }
}

impl Formulation for PenaltyContact {
    fn name(&self) -> &'static str {
        "penalty"
    }

    /// Refused: with a penalised normal law, friction would want a tangential penalty too, a
    /// regularisation that changes Coulomb's law.
    fn friction(&self) -> std::result::Result<(), &'static str> {
        Err(
            "a penalised normal law has no exact Coulomb counterpart here (a tangential penalty \
             would regularise the law); use contact = \"nodal\" or \"weak\"",
        )
    }

    fn setup(&self, problem: &mut Problem, solver: &str) -> Result<Box<dyn Solver>> {
        let exact = super::by_name(solver, problem.contact.len())?;
        Ok(Box::new(Penalty::new(self.ratio, exact)))
    }
}

/// The penalised law `LCP(D + εI, q)`, solved by an exact LCP solver.
pub struct Penalty {
    ratio: f64,
    regularised: DMatrix<f64>,
    exact: Box<dyn Solver>,
}

impl Penalty {
    /// Relative compliance `ratio`, the regularised LCP solved by `exact`.
    pub fn new(ratio: f64, exact: Box<dyn Solver>) -> Self {
        Self {
            ratio,
            regularised: DMatrix::zeros(0, 0),
            exact,
        }
    }
}

impl Solver for Penalty {
    fn name(&self) -> &'static str {
        "penalty"
    }

    fn signorini(&self) -> bool {
        false
    }

    fn solve(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> std::result::Result<SolveInfo, SolverError> {
        let eps = self.ratio * (0..q.len()).fold(0.0f64, |m, i| m.max(d[(i, i)]));
        let regularised = shifted(&mut self.regularised, d, |_| eps);
        self.exact.solve(regularised, q, lambda)
    }
}

/// `D + diag(shift_i)` written into the workspace `out` (allocated on the first call only: the
/// per-step laws reuse it).
fn shifted<'w>(
    out: &'w mut DMatrix<f64>,
    d: &DMatrix<f64>,
    shift: impl Fn(usize) -> f64,
) -> &'w DMatrix<f64> {
    if out.shape() != d.shape() {
        *out = d.clone();
    } else {
        out.copy_from(d);
    }
    for i in 0..d.nrows() {
        out[(i, i)] += shift(i);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn penalty_penetrates_by_epsilon_lambda() {
        let d = DMatrix::from_element(1, 1, 2.0);
        let mut l = [0.0];
        Penalty::new(0.01, Box::new(super::super::active_set::ActiveSet::new(1)))
            .solve(&d, &[-1.0], &mut l)
            .unwrap();
        // λ = 1/(2 + 0.02), g = −1 + 2λ = −0.02 λ.
        assert!((l[0] - 1.0 / 2.02).abs() < 1e-15);
        assert!(PenaltyContact::new(0.0).is_err());
    }
}
