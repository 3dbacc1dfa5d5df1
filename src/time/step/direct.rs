//! The contact-coupled linear solve shared by the implicit schemes.
//!
//! Each step solves `A X = r − c B_Nᵀ λ` (Nitsche: `Qᵀ λ`, see [`crate::contact::nitsche`]) with a constant `A = m M + k K` (factored once) and λ
//! from the LCP `γ = o − B_N X = q + D λ ≥ 0, λ ≥ 0, λ·γ = 0`, where `X* = A⁻¹ r` (predictor),
//! `q = o − B_N X*`, `Z = A⁻¹ B_Nᵀ` and `D = c B_N Z` (Delassus operator, n_c × n_c). The offset
//! `o` is the initial gap g₀ for a position-level law (then γ is the gap at the new level) and a
//! velocity term for Moreau–Jean; `o_i = +∞` excludes point i from the step.
//! Only the columns of D (and Z) of the points that come into contact are formed, the first time
//! they enter a step's working set ([`DirectStep::solve_with`]): on a 3D body most points of Γ_C
//! never touch. With Coulomb friction ([`crate::problem::Friction`]) the rows are stacked,
//! `[B_N; −B_T]` both as law and force rows (the force `−c B_N^T λ_N + c B_T^T r_T`; Nitsche's
//! force rows `[Q; −Q_T]`), so that the law sees `u_N = o_N − B_N X` and `u_T = o_T + B_T X`
//! (the slip, with the scheme's offset `o_T`); a point enters and leaves the working set with all its rows. `Z`'s columns are kept while their entries stay within [`STORE_Z_LIMIT`] (for a
//! sparse mass its inertial part is `Z` itself and is not stored twice); otherwise the corrected
//! state is obtained by a second solve.

use crate::contact::{SolveInfo, Solver};
use crate::error::{Error, Result};
use crate::linalg::{self, row_dot};
use crate::problem::{Problem, StepOperator};
use nalgebra::DMatrix;

/// Right-hand sides per blocked solve when forming `Z = A⁻¹ B_Nᵀ`.
const BLOCK: usize = 64;

/// Above this many entries `Z = A⁻¹ B_Nᵀ` is not stored; a second solve is done instead.
pub const STORE_Z_LIMIT: usize = 30_000_000;

/// Constant step operator, factored once, with its contact coupling formed column by column
/// for the points that enter a step's working set (see [`DirectStep::solve_with`]).
pub struct DirectStep {
    op: Box<dyn StepOperator>,
    /// The formulation's law (taken out while it solves).
    solver: Option<Box<dyn Solver>>,
    /// Columns of `Z = A⁻¹ Qᵀ` formed so far (displacement part, inertial part: empty for a
    /// sparse mass, whose inertial variables are the displacements), while their entries stay
    /// within [`STORE_Z_LIMIT`].
    z: Vec<Option<(Vec<f64>, Vec<f64>)>>,
    stored: usize,
    /// `D = c B_N Z`: the columns in `formed` only (zero elsewhere).
    d: DMatrix<f64>,
    formed: Vec<bool>,
    /// `D` is symmetric (`Q = B_N`): each pair of formed columns is averaged with its transpose.
    symmetric: bool,
    c: f64,
    q: Vec<f64>,
    rhs: Vec<f64>,
    /// Rows of `B_N` and of `Q` as `(dof, value)` lists (n_c short rows: `B_N U` without a pass
    /// over n).
    b_rows: Vec<Vec<(usize, f64)>>,
    f_rows: Vec<Vec<(usize, f64)>>,
    /// Sizes of U and of the inertial variables.
    n: usize,
    nw: usize,
    /// Contact points (the first `points` rows are the normal ones) and tangents per point.
    points: usize,
    tangents: usize,
}

impl DirectStep {
    /// Factors `m_coef M + k_coef K`; the Delassus matrix `D = c B_N A⁻¹ Qᵀ` (`c` is the factor
    /// of `Qᵀ λ` in the step equation) is formed column by column as points come into contact.
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
        let op = problem.inertia.step_operator(k, m_coef, k_coef)?;
        let (n, nw, points) = (problem.n(), problem.inertia.dim(), problem.contact.len());
        let mut b_rows = linalg::rows(&problem.contact.b_n);
        let mut f_rows = linalg::rows(problem.contact.force_rows());
        let mut tangents = 0;
        if let Some(f) = &problem.contact.friction {
            let minus = |rows: &crate::linalg::SpMat| {
                linalg::rows(rows)
                    .into_iter()
                    .map(|row| row.into_iter().map(|(j, v)| (j, -v)).collect::<Vec<_>>())
            };
            b_rows.extend(minus(&f.b_t));
            f_rows.extend(minus(f.force_rows()));
            tangents = f.tangents;
        }
        let nc = b_rows.len();
        Ok(Self {
            op,
            solver: Some(solver),
            z: vec![None; nc],
            stored: 0,
            d: DMatrix::zeros(nc, nc),
            formed: vec![false; nc],
            symmetric: problem.contact.force.is_none(),
            c,
            q: vec![0.0; nc],
            rhs: vec![0.0; n],
            b_rows,
            f_rows,
            n,
            nw,
            points,
            tangents,
        })
    }

    /// Forms the columns `cols` of Z and D not formed yet, by blocks of right-hand sides
    /// (blocked triangular solves), and averages each new pair of formed columns with its
    /// transpose when D is symmetric.
    fn form(&mut self, cols: &[usize]) {
        let (n, nw) = (self.n, self.nw);
        let new: Vec<usize> = cols.iter().copied().filter(|&j| !self.formed[j]).collect();
        let mixed = self.op.is_mixed();
        for block in new.chunks(BLOCK) {
            let k = block.len();
            let mut u = vec![0.0; n * k];
            let mut w = vec![0.0; nw * k];
            for (b, &j) in block.iter().enumerate() {
                for &(i, v) in &self.f_rows[j] {
                    u[b * n + i] += v;
                }
            }
            self.op.solve_columns(&mut u, &mut w, k);
            for (b, &j) in block.iter().enumerate() {
                let (uc, wc) = (&u[b * n..(b + 1) * n], &w[b * nw..(b + 1) * nw]);
                for (i, row) in self.b_rows.iter().enumerate() {
                    self.d[(i, j)] = self.c * row_dot(row, uc);
                }
                let len = if mixed { n + nw } else { n };
                if self.stored + len <= STORE_Z_LIMIT {
                    self.stored += len;
                    let zw = if mixed { wc.to_vec() } else { Vec::new() };
                    self.z[j] = Some((uc.to_vec(), zw));
                }
            }
        }
        for &j in &new {
            self.formed[j] = true;
        }
        if self.symmetric {
            for &j in &new {
                for i in 0..self.formed.len() {
                    // A pair of new columns is visited twice: the mean is idempotent.
                    if self.formed[i] {
                        let mean = 0.5 * (self.d[(i, j)] + self.d[(j, i)]);
                        self.d[(i, j)] = mean;
                        self.d[(j, i)] = mean;
                    }
                }
            }
        }
    }

    /// Forgets the contact columns formed and takes the law `solver`: the step as
    /// [`DirectStep::new`] built it, its factor kept (a problem with another load or initial
    /// state and the same matrices and contact).
    pub fn restart(&mut self, solver: Box<dyn Solver>) {
        self.z.fill(None);
        self.stored = 0;
        self.d.fill(0.0);
        self.formed.fill(false);
        self.solver = Some(solver);
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
        // The working set: the points predicted in contact or warm-started, grown by the points
        // that the solution on it penetrates until there are none (the law sees q_i = +∞, i.e.
        // excludes, outside the set; D is formed on the set's columns only). A tangential row
        // follows its point.
        let (nc, points, tangents) = (self.q.len(), self.points, self.tangents);
        let point = |row: usize| match row.checked_sub(points) {
            None => row,
            Some(t) => t / tangents,
        };
        let mut set: Vec<bool> = (0..points)
            .map(|i| self.q[i].is_finite() && (self.q[i] < 0.0 || lambda[i] != 0.0))
            .collect();
        let mut info = SolveInfo::default();
        loop {
            let cols: Vec<usize> = (0..nc).filter(|&i| set[point(i)]).collect();
            self.form(&cols);
            let q_set: Vec<f64> = (0..nc)
                .map(|i| match (set[point(i)], i < points) {
                    (true, _) => self.q[i],
                    (false, true) => f64::INFINITY,
                    (false, false) => 0.0,
                })
                .collect();
            for (i, l) in lambda.iter_mut().enumerate() {
                if !set[point(i)] {
                    *l = 0.0;
                }
            }
            let round = law
                .solve(&self.d, &q_set, lambda)
                .map_err(|reason| Error::ContactSolver { step, time, reason })?;
            info = SolveInfo {
                iterations: info.iterations + round.iterations,
                active: round.active,
            };
            let mut gap = self.q.clone();
            for (j, &l) in lambda.iter().enumerate().filter(|e| *e.1 != 0.0) {
                linalg::axpy(&mut gap, l, self.d.column(j).as_slice());
            }
            let mut grown = false;
            for i in 0..points {
                if !set[i] && self.q[i].is_finite() && gap[i] < 0.0 {
                    set[i] = true;
                    grown = true;
                }
            }
            if !grown {
                break;
            }
        }
        if lambda.iter().all(|&l| l == 0.0) {
            return Ok(info);
        }
        let stored = lambda
            .iter()
            .zip(&self.z)
            .all(|(&l, z)| l == 0.0 || z.is_some());
        if stored {
            for (&l, z) in lambda.iter().zip(&self.z) {
                if let (true, Some((zu, zw))) = (l != 0.0, z) {
                    linalg::axpy(u, -self.c * l, zu);
                    if !zw.is_empty() {
                        linalg::axpy(w, -self.c * l, zw);
                    }
                }
            }
            if !self.op.is_mixed() {
                w.copy_from_slice(u);
            }
        } else {
            self.rhs.copy_from_slice(r);
            let (normal, tangential) = lambda.split_at(self.points);
            linalg::mul_t_add(&mut self.rhs, problem.contact.force_rows(), normal, -self.c);
            if let Some(f) = &problem.contact.friction {
                linalg::mul_t_add(&mut self.rhs, f.force_rows(), tangential, self.c);
            }
            self.op.solve(&self.rhs, u, w);
        }
        Ok(info)
    }
}
