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

use super::iterative::{nodal_points, IterativeStep};
use crate::contact::{SolveInfo, Solver};
use crate::error::{Error, Result};
use crate::linalg;
use crate::linalg::SpMat;
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

/// How the step matrix is solved (`--linear-solver`, `[run] linear_solver`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinearSolver {
    /// [`LinearSolver::Cg`] where it applies and pays, [`LinearSolver::Direct`] otherwise; the rule
    /// is [`cg_pays`].
    #[default]
    Auto,
    /// Sparse Cholesky (LU for the singular dynamic saddle system), factored once, with the
    /// Delassus operator on the contact dofs.
    Direct,
    /// Jacobi-preconditioned CG with a primal–dual active set ([`super::iterative`]).
    Cg,
}

/// Linear solver names accepted by [`LinearSolver::by_name`].
pub const LINEAR_SOLVERS: &[&str] = &["auto", "direct", "cg"];

impl LinearSolver {
    /// The linear solver called `name`.
    pub fn by_name(name: &str) -> Result<Self> {
        match name {
            "auto" => Ok(Self::Auto),
            "direct" => Ok(Self::Direct),
            "cg" => Ok(Self::Cg),
            _ => Err(Error::UnknownName {
                kind: "linear solver",
                name: name.to_string(),
                known: LINEAR_SOLVERS.join(", "),
            }),
        }
    }
}

/// Dofs from which [`LinearSolver::Auto`] considers CG.
pub const AUTO_CG_DOFS: usize = 50_000;
/// The rule of [`LinearSolver::Auto`]: CG when the mass is a sparse matrix, the contact is nodal
/// along axes, the problem has n ≥ [`AUTO_CG_DOFS`] dofs and K is not a narrow band (2D and 3D
/// meshes, where the Cholesky factor fills in and each direct step also pays the Delassus
/// correction over every active contact column); the direct factor otherwise, 1D included.
/// Measured (README, Speed): block2d Q1 224² 19 against 42 ms per step, block3d Q1 32³ 41 ms
/// against 0.56 s (and 65 s of prepare).
pub fn cg_pays(problem: &Problem, k: &SpMat) -> bool {
    problem.inertia.sparse().is_some()
        && problem.n() >= AUTO_CG_DOFS
        && !linalg::is_narrow_band(k)
        && nodal_points(problem).is_ok()
}

/// Refuses a step matrix `m M + k K` in which the stiffness is below the round-off of the mass
/// (`k max K_ii < ε m max M_ii`): the time step is then so small that K no longer enters the
/// step (with a massless dof the matrix is singular), which would otherwise surface as a
/// factorisation failure or a silently wrong solve.
fn check_stiffness_resolved(
    problem: &Problem,
    k: &SpMat,
    (m_coef, k_coef): (f64, f64),
) -> Result<()> {
    let max_diag = |a: &SpMat| {
        linalg::diagonal(a)
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()))
    };
    let mass = max_diag(problem.inertia.kinetic());
    let k_max = max_diag(k);
    let (stiff, mass) = (k_coef.abs() * k_max, m_coef.abs() * mass);
    if stiff > 0.0 && stiff >= f64::EPSILON * mass || k_max == 0.0 {
        return Ok(());
    }
    Err(Error::invalid(
        "dt",
        format!("a step matrix with stiffness factor {k_coef:.3e}"),
        &format!(
            "too small: the stiffness term of the step matrix ({stiff:.3e}) is below the \
             round-off of its mass term ({mass:.3e}); increase dt"
        ),
    ))
}

/// The constant step operator with its contact coupling, solved directly or by CG.
#[allow(clippy::large_enum_variant)]
pub enum ContactStep {
    /// Factored once, Delassus operator on the contact dofs.
    Direct(DirectStep),
    /// CG with an active set.
    Iterative(IterativeStep),
}

impl ContactStep {
    /// The step operator `m_coef M + k_coef K` with the solvers' choice (see [`DirectStep::new`]).
    pub fn new(
        problem: &Problem,
        coefs: (f64, f64),
        c: f64,
        solvers: super::Solvers,
    ) -> Result<Self> {
        Self::with_stiffness(problem, &problem.k, coefs, c, solvers)
    }

    /// As [`ContactStep::new`] with the stiffness `k` in place of the problem's.
    pub fn with_stiffness(
        problem: &Problem,
        k: &SpMat,
        coefs: (f64, f64),
        c: f64,
        solvers: super::Solvers,
    ) -> Result<Self> {
        check_stiffness_resolved(problem, k, coefs)?;
        let signorini = solvers.contact.signorini();
        let cg = match solvers.linear {
            LinearSolver::Direct => false,
            LinearSolver::Cg if !signorini => {
                return Err(Error::Unsupported(format!(
                    "linear solver cg enforces Signorini's law by its own active set, not the {} \
                     law (use direct)",
                    solvers.contact.name()
                )))
            }
            LinearSolver::Cg => true,
            LinearSolver::Auto => signorini && cg_pays(problem, k),
        };
        Ok(if cg {
            Self::Iterative(IterativeStep::new(problem, k, coefs, c)?)
        } else {
            Self::Direct(DirectStep::with_stiffness(
                problem,
                k,
                coefs,
                c,
                solvers.contact,
            )?)
        })
    }

    /// Solves `A X = r` without contact.
    pub fn solve_free(&mut self, r: &[f64], u: &mut [f64], w: &mut [f64]) -> Result<()> {
        match self {
            Self::Direct(s) => {
                s.solve_free(r, u, w);
                Ok(())
            }
            Self::Iterative(s) => s.solve_free(r, u, w),
        }
    }

    /// Solves the step with the complementarity law (see [`DirectStep::solve`]).
    pub fn solve(
        &mut self,
        problem: &Problem,
        rhs: (&[f64], &[f64]),
        x: (&mut [f64], &mut [f64]),
        lambda: &mut [f64],
        at: (usize, f64),
    ) -> Result<SolveInfo> {
        match self {
            Self::Direct(s) => s.solve(problem, rhs, x, lambda, at),
            Self::Iterative(s) => s.solve(rhs, x, lambda, at),
        }
    }
}

/// Constant step operator, factored once, with its contact coupling.
pub struct DirectStep {
    op: Box<dyn StepOperator>,
    solver: Box<dyn Solver>,
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
            solver,
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
        let info = self
            .solver
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
