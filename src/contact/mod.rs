//! Contact solvers for the per-step linear complementarity problem on the contact dofs.
//!
//! After the predictor solve of an implicit step, the gaps at the new time level are affine in the
//! contact pressures: `g = q + D λ`, with `D = c · B_N A⁻¹ B_Nᵀ` (the Delassus operator, the Schur
//! complement of the step matrix A on the contact dofs, SPD). A [`Solver`] returns λ with
//! `λ ≥ 0, g ≥ 0, λ · g = 0`.

pub mod active_set;

use nalgebra::DMatrix;

/// Outcome of one LCP solve.
#[derive(Debug, Clone, Copy, Default)]
pub struct SolveInfo {
    /// Pivots / iterations used.
    pub iterations: usize,
    /// Number of contact points with λ > 0.
    pub active: usize,
}

/// A solver of `LCP(D, q)`: find λ ≥ 0 with `g = q + D λ ≥ 0`, `λ · g = 0`.
pub trait Solver: Send {
    /// Name used on the CLI and in reports.
    fn name(&self) -> &'static str;
    /// Solves the LCP; `lambda` holds a warm start on entry and the solution on exit.
    /// Returns a reason string when the solver fails.
    fn solve(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> std::result::Result<SolveInfo, String>;
}

/// Contact solver names accepted by [`by_name`].
pub const SOLVERS: &[&str] = &["active_set"];

/// The solver called `name` for `n_c` contact points.
pub fn by_name(name: &str, n_c: usize) -> crate::Result<Box<dyn Solver>> {
    match name {
        "active_set" => Ok(Box::new(active_set::ActiveSet::new(n_c))),
        _ => Err(crate::Error::UnknownName {
            kind: "contact solver",
            name: name.to_string(),
            known: SOLVERS.join(", "),
        }),
    }
}
