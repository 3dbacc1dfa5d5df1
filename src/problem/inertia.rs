//! What a time scheme needs of the mass, whatever space discretisation produced it
//! (DESIGN.md §3): each space is one file in [`crate::space`] implementing [`Inertia`].
//!
//! A scheme works on *inertial variables* `w`: the displacements themselves for a sparse mass
//! (`w = U`, `M` a sparse matrix), or `w = C⁻¹ B U`, the L²(ρ) projection of U on the velocity
//! space H_h, for the singular dynamic method (`M = Bᵀ C⁻¹ B`, never formed). The inertial force
//! of an inertial vector y is `Lᵀ y` (`L = M` or `B`), the kinetic energy `½ vᵀ M v` or `½ vᵀ C v`
//! of the inertial velocity v.

use crate::error::Result;
use crate::linalg::SpMat;

/// The mass operator of a space.
pub trait Inertia: std::fmt::Debug + Send + Sync {
    /// Number of inertial variables (n for a sparse mass, dim H_h for the mixed one).
    fn dim(&self) -> usize;

    /// Inertial variables of a displacement field: `w = U` or `w = C⁻¹ B U`.
    fn project(&self, u: &[f64]) -> Result<Vec<f64>>;

    /// `out += alpha · Lᵀ y` with `L = M` (sparse) or `L = B` (mixed): the inertial force of the
    /// inertial vector `y`, as a force on the displacement dofs.
    fn apply_add(&self, out: &mut [f64], y: &[f64], alpha: f64);

    /// `M x` on displacement dofs (mixed: `Bᵀ C⁻¹ B x`, applied, never formed).
    fn mass_times(&self, x: &[f64]) -> Result<Vec<f64>> {
        let mut out = vec![0.0; x.len()];
        self.apply_add(&mut out, &self.project(x)?, 1.0);
        Ok(out)
    }

    /// Factors the constant step matrix `m_coef · M + k_coef · K` once (with the inertial
    /// variables as extra unknowns when they are not the displacements).
    fn step_operator(&self, k: &SpMat, m_coef: f64, k_coef: f64) -> Result<Box<dyn StepOperator>>;

    /// Galerkin acceleration `A` on the displacement dofs from `M A = r` (r = F − K U₀ at zero
    /// contact force); 0 on massless dofs (their equation is quasi-static).
    fn acceleration(&self, r: &[f64]) -> Result<Vec<f64>>;

    /// The matrix of the kinetic energy `½ vᵀ (·) v` of an inertial velocity: M, or C.
    fn kinetic(&self) -> &SpMat;

    /// The sparse mass M when the inertial variables are the displacements (None for the
    /// mixed mass, whose M is dense and never formed).
    fn sparse(&self) -> Option<&SpMat>;

    /// The inertial dof that carries the velocity of displacement dof `u_dof` (itself for a
    /// sparse mass; the H_h dof at the same vertex for the mixed mass).
    fn velocity_dof(&self, u_dof: usize) -> usize;

    /// The displacement dofs whose row of M is zero (e.g. the Γ_C normal dofs of mass
    /// redistribution), one flag per displacement dof; none for the mixed mass, whose M has
    /// no zero row.
    fn massless(&self) -> Vec<bool>;
}

/// The factored step matrix of [`Inertia::step_operator`]; solves for `(U, w)`.
pub trait StepOperator: std::fmt::Debug + Send {
    /// True when the inertial variables are unknowns of their own (the mixed mass).
    fn is_mixed(&self) -> bool;

    /// Solves the step system with displacement right-hand side `rhs_u` (inertial rows 0),
    /// writing the displacements to `u` and the inertial variables to `w`. Allocates nothing.
    fn solve(&mut self, rhs_u: &[f64], u: &mut [f64], w: &mut [f64]);

    /// Solves for `ncols` displacement right-hand sides at once: `rhs` holds them column-major
    /// (length `n · ncols`) and receives the displacements; `w` (length `dim w · ncols`) receives
    /// the inertial variables (setup only: allocates).
    fn solve_columns(&mut self, rhs: &mut [f64], w: &mut [f64], ncols: usize);
}
