//! The contact-coupled linear solve shared by the implicit schemes.
//!
//! Each step solves `A X = r − c B_Nᵀ λ` (Nitsche: `Qᵀ λ`, see [`crate::contact::nitsche`]) with a constant `A = m M + k K` (factored once) and λ
//! from the LCP `γ = o − B_N X = q + D λ ≥ 0, λ ≥ 0, λ·γ = 0`, where `X* = A⁻¹ r` (predictor),
//! `q = o − B_N X*`, `Z = A⁻¹ B_Nᵀ` and `D = c B_N Z` (Delassus operator, n_c × n_c). The offset
//! `o` is the initial gap g₀ for a position-level law (then γ is the gap at the new level) and a
//! velocity term for Moreau–Jean; `o_i = +∞` excludes point i from the step.
//! `Z` is kept when it is small (entries ≤ [`STORE_Z_LIMIT`]; for a sparse mass its inertial
//! part is `Z` itself and is not stored twice); otherwise the corrected state is obtained by a
//! second solve.

use crate::contact::{SolveInfo, Solver};
use crate::error::{Error, Result};
use crate::linalg;
use crate::problem::{Problem, StepOperator};
use nalgebra::DMatrix;

/// Right-hand sides per blocked solve when forming `Z = A⁻¹ B_Nᵀ`.
const BLOCK: usize = 64;

/// Above this many entries `Z = A⁻¹ B_Nᵀ` is not stored; a second solve is done instead.
pub const STORE_Z_LIMIT: usize = 30_000_000;

/// Columns of `Z = A⁻¹ B_Nᵀ`: displacement part and, for the mixed mass, inertial part (empty
/// for a sparse mass, whose inertial variables are the displacements), one vector per point.
struct Coupling {
    zu: Vec<Vec<f64>>,
    zw: Vec<Vec<f64>>,
}

/// `Σ v u_j` over a sparse row of `(j, v)`.
fn row_dot(row: &[(usize, f64)], u: &[f64]) -> f64 {
    row.iter().map(|&(j, v)| v * u[j]).sum()
}

/// Constant step operator, factored once, with its contact coupling.
pub struct DirectStep {
    op: Box<dyn StepOperator>,
    /// The formulation's law (taken out while it solves).
    solver: Option<Box<dyn Solver>>,
    /// `A⁻¹ B_Nᵀ`, when small enough to store.
    z: Option<Coupling>,
    d: DMatrix<f64>,
    c: f64,
    q: Vec<f64>,
    rhs: Vec<f64>,
    /// Rows of `B_N` as `(dof, value)` lists (n_c short rows: `B_N U` without a pass over n).
    b_rows: Vec<Vec<(usize, f64)>>,
}

impl DirectStep {
    /// Factors `m_coef M + k_coef K` and forms the Delassus matrix `D = c B_N A⁻¹ B_Nᵀ`
    /// (`c` is the factor of `B_Nᵀ λ` in the step equation).
    pub fn new(
        problem: &Problem,
        (m_coef, k_coef): (f64, f64),
        c: f64,
        solver: Box<dyn Solver>,
    ) -> Result<Self> {
        Self::with_stiffness(problem, &problem.k, (m_coef, k_coef), c, solver)
    }

    /// As [`DirectStep::new`] with the stiffness `k` in place of the problem's (central
    /// difference puts only the block of its massless dofs in the step matrix).
    pub fn with_stiffness(
        problem: &Problem,
        k: &crate::linalg::SpMat,
        (m_coef, k_coef): (f64, f64),
        c: f64,
        solver: Box<dyn Solver>,
    ) -> Result<Self> {
        let mut op = problem.inertia.step_operator(k, m_coef, k_coef)?;
        let (n, nw, nc) = (problem.n(), problem.inertia.dim(), problem.contact.len());
        let mut d = DMatrix::zeros(nc, nc);
        let mut zu = Vec::with_capacity(nc);
        let mut zw = Vec::with_capacity(nc);
        let mixed = op.is_mixed();
        let stored_len = if mixed { n + nw } else { n };
        let store = stored_len * nc <= STORE_Z_LIMIT;
        let b_rows = linalg::rows(&problem.contact.b_n);
        // The force rows: B_N, or other rows Q (then D = c B_N A⁻¹ Qᵀ is not symmetric).
        let f_rows = linalg::rows(problem.contact.force_rows());
        // Columns of Z = A⁻¹ Qᵀ by blocks of right-hand sides (blocked triangular solves).
        for start in (0..nc).step_by(BLOCK) {
            let cols = BLOCK.min(nc - start);
            let mut u = vec![0.0; n * cols];
            let mut w = vec![0.0; nw * cols];
            for (k, row) in f_rows[start..start + cols].iter().enumerate() {
                for &(j, v) in row {
                    u[k * n + j] += v;
                }
            }
            op.solve_columns(&mut u, &mut w, cols);
            for k in 0..cols {
                let (uc, wc) = (&u[k * n..(k + 1) * n], &w[k * nw..(k + 1) * nw]);
                for (i, row) in b_rows.iter().enumerate() {
                    d[(i, start + k)] = c * row_dot(row, uc);
                }
                if store {
                    zu.push(uc.to_vec());
                    if mixed {
                        zw.push(wc.to_vec());
                    }
                }
            }
        }
        let d = if problem.contact.force.is_some() {
            d
        } else {
            (&d + d.transpose()) * 0.5
        };
        Ok(Self {
            op,
            solver: Some(solver),
            z: store.then_some(Coupling { zu, zw }),
            d,
            c,
            q: vec![0.0; nc],
            rhs: vec![0.0; n],
            b_rows,
        })
    }

    /// Solves `A X = r` without contact (X: displacement-like unknowns `u`, inertial `w`).
    pub fn solve_free(&mut self, r: &[f64], u: &mut [f64], w: &mut [f64]) {
        self.op.solve(r, u, w);
    }

    /// Solves `A (X, w) = r − c B_Nᵀ λ` with the complementarity law on `o − B_N X` (`offset` = o)
    /// at step `step`, time `time` (for error messages); `lambda` is a warm start on entry.
    pub fn solve(
        &mut self,
        problem: &Problem,
        rhs: (&[f64], &[f64]),
        x: (&mut [f64], &mut [f64]),
        lambda: &mut [f64],
        at: (usize, f64),
    ) -> Result<SolveInfo> {
        let mut own = self
            .solver
            .take()
            .ok_or_else(|| Error::Internal("the step's contact law is in use".into()))?;
        let out = self.solve_with(own.as_mut(), problem, rhs, x, lambda, at);
        self.solver = Some(own);
        out
    }

    /// As [`DirectStep::solve`] with the law `law` (a scheme's own) in place of the
    /// formulation's: λ solves `law` on `g = q + D λ`.
    pub fn solve_with(
        &mut self,
        law: &mut dyn Solver,
        problem: &Problem,
        (r, offset): (&[f64], &[f64]),
        (u, w): (&mut [f64], &mut [f64]),
        lambda: &mut [f64],
        (step, time): (usize, f64),
    ) -> Result<SolveInfo> {
        self.op.solve(r, u, w);
        self.q.copy_from_slice(offset);
        for (q, row) in self.q.iter_mut().zip(&self.b_rows) {
            *q -= row_dot(row, u);
        }
        let info = law
            .solve(&self.d, &self.q, lambda)
            .map_err(|reason| Error::ContactSolver { step, time, reason })?;
        if lambda.iter().all(|&l| l == 0.0) {
            return Ok(info);
        }
        match &self.z {
            Some(Coupling { zu, zw }) => {
                for (j, &l) in lambda.iter().enumerate() {
                    if l != 0.0 {
                        linalg::axpy(u, -self.c * l, &zu[j]);
                        if let Some(zwj) = zw.get(j) {
                            linalg::axpy(w, -self.c * l, zwj);
                        }
                    }
                }
                if zw.is_empty() {
                    w.copy_from_slice(u);
                }
            }
            None => {
                self.rhs.copy_from_slice(r);
                linalg::mul_t_add(&mut self.rhs, problem.contact.force_rows(), lambda, -self.c);
                self.op.solve(&self.rhs, u, w);
            }
        }
        Ok(info)
    }
}
