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

/// Units of order one for an interior point, whose tolerances are absolute: `x = f S x̃` with
/// `S = diag(s)`, `s_i = 1/√(largest D_jj over the rows j of row i's point)` (one factor per
/// point, normal and tangents alike, so that the cones are kept) and `f = ‖S q‖∞`, turns
/// `½ xᵀ D x + qᵀ x` into `f² (½ x̃ᵀ (S D S) x̃ + (S q / f)ᵀ x̃)`, whose diagonal is at most 1
/// (1 on each point's largest); the multiplier of the cone constraint (the gap, for the LCP)
/// is `g = f S⁻¹ z̃`. Unscaled, a step's forces of 1e-4
/// (block2d) met Clarabel's tolerances 1e-8 of the way to the solution; with one factor for
/// every point, points of compliances 1e-6 apart failed.
#[derive(Debug, Clone)]
pub(crate) struct Units {
    /// `s_i` per row.
    s: Vec<f64>,
    /// `‖S q‖∞`.
    f: f64,
}

impl Units {
    /// The units of `D` and `q` for points of `dim` rows each (the first the normal one);
    /// `None` when q = 0, which x = 0 solves. A normal diagonal entry that is not positive is
    /// refused (D is not positive definite).
    pub fn new(d: &DMatrix<f64>, q: &[f64], dim: usize) -> Result<Option<Self>, SolverError> {
        let mut s = Vec::with_capacity(q.len());
        for p in 0..q.len() / dim {
            let pivot = d[(p * dim, p * dim)];
            if !(pivot > 0.0 && pivot.is_finite()) {
                return Err(SolverError::NotPositiveDefinite { pivot });
            }
            let largest = (p * dim..(p + 1) * dim).fold(pivot, |m, i| m.max(d[(i, i)]));
            s.extend(std::iter::repeat_n(1.0 / largest.sqrt(), dim));
        }
        let f = q
            .iter()
            .zip(&s)
            .fold(0.0, |m: f64, (v, s)| m.max((v * s).abs()));
        Ok((f > 0.0).then_some(Self { s, f }))
    }

    /// `S D S`.
    pub fn matrix(&self, d: &DMatrix<f64>) -> DMatrix<f64> {
        DMatrix::from_fn(d.nrows(), d.ncols(), |i, j| {
            self.s[i] * d[(i, j)] * self.s[j]
        })
    }

    /// `S q / f`.
    pub fn load(&self, q: &[f64]) -> Vec<f64> {
        q.iter().zip(&self.s).map(|(v, s)| v * s / self.f).collect()
    }

    /// `x = f S x̃`.
    pub fn unscale(&self, x: &[f64]) -> Vec<f64> {
        x.iter().zip(&self.s).map(|(v, s)| v * s * self.f).collect()
    }

    /// The cone's multiplier `g = f S⁻¹ z̃` (the gap, for the LCP).
    pub fn gap(&self, z: &[f64]) -> Vec<f64> {
        z.iter().zip(&self.s).map(|(v, s)| v * self.f / s).collect()
    }
}

/// The upper triangle of `d` as a Clarabel CSC matrix.
pub(crate) fn upper(d: &DMatrix<f64>) -> CscMatrix<f64> {
    let k = d.nrows();
    let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
    for j in 0..k {
        for i in 0..=j {
            rowval.push(i);
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
        let dk = DMatrix::from_fn(k, k, |a, b| d[(index[a], index[b])]);
        let Some(units) = Units::new(&dk, &qs, 1)? else {
            return Ok(SolveInfo::default());
        };
        let (p, qs) = (upper(&units.matrix(&dk)), units.load(&qs));
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
        let (x, gap) = (
            units.unscale(&solver.solution.x),
            units.gap(&solver.solution.z),
        );
        let guess: Vec<bool> = index
            .iter()
            .zip(&x)
            .zip(&gap)
            .map(|((&i, &x), &g)| x * d[(i, i)] > g)
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
