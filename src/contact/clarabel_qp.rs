//! The contact LCP as a convex QP solved by Clarabel's interior point method:
//!
//! `min ½ λᵀ D λ + qᵀ λ  s.t.  λ ≥ 0`,
//!
//! whose KKT conditions are the LCP (the multiplier of `λ ≥ 0` is the gap `g = q + Dλ`). Written as
//! Clarabel's `Ax + s = b, s ∈ ℝ₊` with `A = −I`, `b = 0`, on the points with finite `q_i`,
//! in units of order one ([`Units`]: Clarabel's tolerances are absolute).
//! The interior-point iterate is polished as in OSQP: the active set it identifies
//! (`λ_i D_ii > g_i`) is solved exactly, `D_𝒜𝒜 λ_𝒜 = −q_𝒜`, and kept when it satisfies the LCP;
//! otherwise the raw iterate is returned (or an error if Clarabel did not converge).
//! Clarabel builds its own workspace at every solve: it is the general-purpose choice for large
//! n_c, not the fast path (see `benches/contact.rs`).

use super::{SolveInfo, Solver};
use crate::error::SolverError;
use clarabel::algebra::{CscMatrix, MatrixMathMut};
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::DMatrix;

/// Interior-point tolerance (gap and feasibility, absolute and relative).
pub const TOLERANCE: f64 = 1e-10;

/// Clarabel QP solver with tight tolerances.
#[derive(Debug, Clone)]
pub struct ClarabelQp {
    settings: DefaultSettings<f64>,
}

impl Default for ClarabelQp {
    fn default() -> Self {
        Self::new()
    }
}

impl ClarabelQp {
    /// Solver with [`TOLERANCE`] and no console output.
    pub fn new() -> Self {
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_iter(200)
            .tol_gap_abs(TOLERANCE)
            .tol_gap_rel(TOLERANCE)
            .tol_feas(TOLERANCE)
            .tol_ktratio(1e-10)
            .build()
            .expect("constant Clarabel settings are valid");
        Self { settings }
    }
}

/// Units of order one for an interior point, whose tolerances are absolute: with `w` the largest
/// diagonal entry of D and `f = ‖q‖∞`, `x = (f/w) x̃` turns `½ xᵀ D x + qᵀ x` into
/// `(f²/w) (½ x̃ᵀ (D/w) x̃ + (q/f)ᵀ x̃)`; the cones are invariant under scaling. Unscaled, a
/// step's forces of 1e-4 (block2d) met the tolerances 1e-8 of the way to the solution.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Units {
    /// The largest diagonal entry of D.
    pub w: f64,
    /// ‖q‖∞.
    pub f: f64,
}

impl Units {
    /// The units of D (its diagonal `diag`) and `q`; `None` when q = 0, which x = 0 solves.
    pub fn new(diag: impl Iterator<Item = f64>, q: &[f64]) -> Option<Self> {
        let w = diag.fold(0.0, f64::max);
        let f = q.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
        (f > 0.0 && w > 0.0).then_some(Self { w, f })
    }

    /// x from the scaled x̃.
    pub fn unscale(&self, x: &[f64]) -> Vec<f64> {
        x.iter().map(|v| v * self.f / self.w).collect()
    }
}

/// Upper triangle of `D` restricted to `index`, as a Clarabel CSC matrix.
fn upper_block(d: &DMatrix<f64>, index: &[usize]) -> CscMatrix<f64> {
    let k = index.len();
    let mut colptr = Vec::with_capacity(k + 1);
    let mut rowval = Vec::with_capacity(k * (k + 1) / 2);
    let mut nzval = Vec::with_capacity(k * (k + 1) / 2);
    colptr.push(0);
    for (b, &j) in index.iter().enumerate() {
        for (a, &i) in index.iter().enumerate().take(b + 1) {
            rowval.push(a);
            nzval.push(d[(i, j)]);
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(k, k, colptr, rowval, nzval)
}

/// Exact solve on the guessed active set; `Some` only if the result satisfies the LCP.
fn polish(d: &DMatrix<f64>, q: &[f64], index: &[usize], guess: &[bool]) -> Option<Vec<f64>> {
    let act: Vec<usize> = index
        .iter()
        .zip(guess)
        .filter_map(|(&i, &a)| a.then_some(i))
        .collect();
    let k = act.len();
    let daa = DMatrix::from_fn(k, k, |a, b| d[(act[a], act[b])]);
    let rhs = nalgebra::DVector::from_fn(k, |a, _| -q[act[a]]);
    let sol = if k == 0 {
        rhs
    } else {
        daa.cholesky()?.solve(&rhs)
    };
    let mut full = vec![0.0; q.len()];
    for (a, &i) in act.iter().enumerate() {
        full[i] = sol[a];
    }
    let scale = index.iter().map(|&i| q[i].abs()).fold(0.0, f64::max);
    let ok = index.iter().all(|&i| {
        let g = q[i] + (0..q.len()).map(|j| d[(i, j)] * full[j]).sum::<f64>();
        full[i] >= 0.0 && g >= -1e-12 * scale.max(f64::MIN_POSITIVE)
    });
    ok.then(|| index.iter().map(|&i| full[i]).collect())
}

impl Solver for ClarabelQp {
    fn name(&self) -> &'static str {
        "clarabel"
    }

    fn solve(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> std::result::Result<SolveInfo, SolverError> {
        lambda.fill(0.0);
        let index: Vec<usize> = (0..q.len()).filter(|&i| q[i].is_finite()).collect();
        if index.is_empty() {
            return Ok(SolveInfo::default());
        }
        let k = index.len();
        let qs: Vec<f64> = index.iter().map(|&i| q[i]).collect();
        let Some(units) = Units::new(index.iter().map(|&i| d[(i, i)]), &qs) else {
            return Ok(SolveInfo::default());
        };
        let qs: Vec<f64> = qs.iter().map(|v| v / units.f).collect();
        let mut p = upper_block(d, &index);
        p.nzval.iter_mut().for_each(|v| *v /= units.w);
        let mut a = CscMatrix::identity(k);
        a.negate();
        let b = vec![0.0; k];
        let cones = [SupportedConeT::NonnegativeConeT(k)];
        let mut solver = DefaultSolver::new(&p, &qs, &a, &b, &cones, self.settings.clone())
            .map_err(|e| SolverError::Clarabel {
                status: format!("setup failed: {e}"),
            })?;
        solver.solve();
        let status = solver.solution.status;
        if !matches!(
            status,
            SolverStatus::Solved | SolverStatus::AlmostSolved | SolverStatus::InsufficientProgress
        ) {
            return Err(SolverError::Clarabel {
                status: format!("{status:?}"),
            });
        }
        // The dual variable of `λ ≥ 0` is the gap; a point is active when its pressure dominates.
        let x = units.unscale(&solver.solution.x);
        let guess: Vec<bool> = index
            .iter()
            .zip(&x)
            .zip(&solver.solution.z)
            .map(|((&i, &x), &g)| x * d[(i, i)] > g * units.f)
            .collect();
        let polished = polish(d, q, &index, &guess);
        let active = guess.iter().filter(|a| **a).count();
        match polished {
            Some(l) => {
                for (&i, v) in index.iter().zip(l) {
                    lambda[i] = v;
                }
            }
            None if status == SolverStatus::Solved => {
                for (&i, &x) in index.iter().zip(&x) {
                    lambda[i] = x.max(0.0);
                }
            }
            None => {
                return Err(SolverError::Clarabel {
                    status: format!("{status:?}, polishing failed"),
                })
            }
        }
        Ok(SolveInfo {
            iterations: solver.info.iterations as usize,
            active,
        })
    }
}
