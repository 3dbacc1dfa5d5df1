//! Sparse matrix–vector products: scatter `A x`, gather `Aᵀ x` (parallel above
//! [`PARALLEL_NNZ`] stored entries, in fixed chunks: the result does not depend on the number of
//! threads).

use super::sparse::{csc, SpMat};

/// `y += alpha · A x`.
pub fn mul_add(y: &mut [f64], a: &SpMat, x: &[f64], alpha: f64) {
    debug_assert_eq!(a.ncols(), x.len());
    debug_assert_eq!(a.nrows(), y.len());
    let (cp, ri, v) = csc(a);
    for (j, &xj) in x.iter().enumerate() {
        if xj == 0.0 {
            continue;
        }
        let s = alpha * xj;
        let col = cp[j]..cp[j + 1];
        for (&i, &vij) in ri[col.clone()].iter().zip(&v[col]) {
            y[i] += vij * s;
        }
    }
}

/// `(Aᵀ x)_j = Σ_i A_ij x_i`, the dot of column j with x.
#[inline(always)]
pub(super) fn col_dot((cp, ri, v): (&[usize], &[usize], &[f64]), x: &[f64], j: usize) -> f64 {
    let col = cp[j]..cp[j + 1];
    ri[col.clone()]
        .iter()
        .zip(&v[col])
        .map(|(&i, &vij)| vij * x[i])
        .sum()
}

/// Above this many stored entries the column dots of [`gather`] run over the rayon pool, in chunks of [`CHUNK`] columns (fixed: the result does not depend on the thread count).
pub const PARALLEL_NNZ: usize = 200_000;
/// Columns per parallel chunk.
pub(super) const CHUNK: usize = 2048;

/// `f(y_j, (Aᵀ x)_j)` for every column j.
fn gather(y: &mut [f64], a: &SpMat, x: &[f64], f: impl Fn(&mut f64, f64) + Sync) {
    use rayon::prelude::*;
    let arrays = csc(a);
    if arrays.2.len() < PARALLEL_NNZ {
        for (j, yj) in y.iter_mut().enumerate() {
            f(yj, col_dot(arrays, x, j));
        }
    } else {
        y.par_chunks_mut(CHUNK).enumerate().for_each(|(c, chunk)| {
            for (k, yj) in chunk.iter_mut().enumerate() {
                f(yj, col_dot(arrays, x, c * CHUNK + k));
            }
        });
    }
}

/// `y += alpha · Aᵀ x`.
pub fn mul_t_add(y: &mut [f64], a: &SpMat, x: &[f64], alpha: f64) {
    debug_assert_eq!(a.nrows(), x.len());
    debug_assert_eq!(a.ncols(), y.len());
    gather(y, a, x, |yj, d| *yj += alpha * d);
}

/// `y = A x` for a symmetric `A` (the gather form `Aᵀ x`).
pub fn sym_mul(y: &mut [f64], a: &SpMat, x: &[f64]) {
    gather(y, a, x, |yj, d| *yj = d);
}

/// `A x` as a new vector.
pub fn mul(a: &SpMat, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; a.nrows()];
    mul_add(&mut y, a, x, 1.0);
    y
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{to_dense, TripletBuilder};

    #[test]
    fn duplicates_are_summed_and_transpose_product_matches() {
        let mut t = TripletBuilder::new(2, 3);
        t.add(0, 1, 1.0);
        t.add(0, 1, 2.0);
        t.add(1, 2, 4.0);
        let a = t.build().unwrap();
        assert_eq!(to_dense(&a)[(0, 1)], 3.0);
        let mut y = vec![0.0; 3];
        mul_t_add(&mut y, &a, &[1.0, 1.0], 1.0);
        assert_eq!(y, vec![0.0, 3.0, 4.0]);
    }
}
