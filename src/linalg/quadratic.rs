//! Quadratic forms `xᵀ A x` of sparse matrices, evaluated at every sample of a run (energies).

use super::block::BlockSym;
use super::products::{col_dot, PARALLEL_NNZ};
use super::sparse::{bandwidth, csc, triplets, SpMat, NARROW_BAND};
use super::vectors::dot_unordered;

/// `xᵀ A y` for a sparse `A` (no allocation), as `Σ_j y_j (Aᵀ x)_j`, on the calling thread
/// (it runs beside the time loop, on the sampling thread).
pub fn quad(a: &SpMat, x: &[f64], y: &[f64]) -> f64 {
    let arrays = csc(a);
    (0..a.ncols()).map(|j| y[j] * col_dot(arrays, x, j)).sum()
}

/// The quadratic form `q(x) = xᵀ A x` of a square sparse matrix, for evaluation at every step.
///
/// Rows are summed first, `q(x) = Σ_i x_i (A x)_i`, so that the cancellation inside `(A x)_i`
/// (a stiffness row applied to a smooth field) happens before the large products are added. A
/// narrow-band matrix (1D meshes) is stored by diagonals, `(A x)_i = Σ_d A_{i,i+d} x_{i+d}`, and
/// evaluated diagonal by diagonal in vectorised passes; a large block-structured one by
/// [`BlockSym`]; any other matrix uses [`quad`].
#[derive(Debug, Clone)]
pub enum QuadraticForm {
    /// Diagonals `(d, A_{i,i+d} for every i)` with `|d| ≤` [`NARROW_BAND`].
    Band(Vec<(isize, Vec<f64>)>),
    /// Node blocks (large vector problems: half the memory traffic), `q = x · (A x)`.
    Block(BlockSym),
    /// The compressed-column matrix itself.
    General(SpMat),
}

impl QuadraticForm {
    /// The form of the square matrix `a`.
    pub fn new(a: &SpMat) -> Self {
        let n = a.nrows();
        if bandwidth(a) > NARROW_BAND {
            return match BlockSym::new(a) {
                Some(b) if a.val().len() >= PARALLEL_NNZ => Self::Block(b),
                _ => Self::General(a.clone()),
            };
        }
        let b = NARROW_BAND as isize;
        let mut diagonals: Vec<(isize, Vec<f64>)> = (-b..=b).map(|d| (d, vec![0.0; n])).collect();
        for (i, j, v) in triplets(a) {
            let d = j as isize - i as isize;
            diagonals[(d + b) as usize].1[i] += v;
        }
        diagonals.retain(|(_, v)| v.iter().any(|&x| x != 0.0));
        Self::Band(diagonals)
    }

    /// `xᵀ A x`; `ax` is a workspace (it receives `A x` for a band matrix).
    pub fn eval(&self, x: &[f64], ax: &mut Vec<f64>) -> f64 {
        let diagonals = match self {
            Self::General(a) => return quad(a, x, x),
            Self::Block(b) => {
                ax.resize(x.len(), 0.0);
                b.apply_serial(ax, x);
                return dot_unordered(x, ax);
            }
            Self::Band(d) => d,
        };
        let n = x.len();
        ax.clear();
        ax.resize(n, 0.0);
        for (d, a) in diagonals {
            let (lo, hi) = ((-d).max(0) as usize, n - (*d).max(0) as usize);
            let shifted = &x[(lo as isize + d) as usize..(hi as isize + d) as usize];
            for ((y, a), xs) in ax[lo..hi].iter_mut().zip(&a[lo..hi]).zip(shifted) {
                *y += a * xs;
            }
        }
        dot_unordered(x, ax)
    }
}
