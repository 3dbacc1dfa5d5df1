//! Sparse linear algebra on top of faer, one concept per file:
//! - [`sparse`]: the compressed-column matrix, its construction from triplets, `a X + b Y`, its
//!   arrays cut by ranges of columns (to fill them in parallel);
//! - [`products`]: `A x` and `Aᵀ x`;
//! - [`quadratic`]: `xᵀ A x` (energies);
//! - [`vectors`]: inner products and vector updates;
//! - [`factor`]: the direct factor (sparse Cholesky / LU), analysed and factored once;
//! - [`ordering`]: the fill-reducing orderings of the factorisations (AMD, nested dissection);
//! - [`single`]: a Cholesky factor in single precision (preconditioners);
//! - [`block`]: symmetric matrices stored by node blocks;
//! - [`pcg`]: preconditioned conjugate gradients.

pub mod block;
pub mod factor;
pub mod ordering;
pub mod pcg;
pub mod products;
pub mod quadratic;
pub mod single;
pub mod sparse;
pub mod vectors;

pub use block::{node_size, BlockSym, BlockValue};
pub use factor::Factor;
pub use pcg::{principal_submatrix, Pcg, Tie};
pub use products::{mul, mul_add, mul_t_add, sym_mul, PARALLEL_NNZ};
pub use quadratic::{quad, QuadraticForm};
pub use single::SingleFactor;
pub use sparse::{
    diagonal, is_narrow_band, lin_comb, rows, to_dense, triplets, SpMat, TripletBuilder,
};
pub use vectors::{axpy, combine, dot, dot_unordered, masked_dot, row_dot, scale_add, PASS_CHUNK};

/// Test matrices shared by the unit tests of this module.
#[cfg(test)]
pub(crate) mod testing {
    use super::{SpMat, TripletBuilder};

    /// The 1D Laplacian `tridiag(−1, 2, −1)` of order n.
    pub fn laplacian(n: usize) -> SpMat {
        let mut t = TripletBuilder::new(n, n);
        for i in 0..n {
            t.add(i, i, 2.0);
            if i + 1 < n {
                t.add(i, i + 1, -1.0);
                t.add(i + 1, i, -1.0);
            }
        }
        t.build().unwrap()
    }

    /// `max_i |a_i − b_i|`.
    pub fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
    }

    /// A symmetric matrix of `nodes` × `nodes` dense b × b blocks on a ring of node couplings.
    pub fn block_matrix(nodes: usize, b: usize) -> SpMat {
        let n = nodes * b;
        let mut t = TripletBuilder::new(n, n);
        let value = |i: usize, j: usize| ((i * 7 + j * 13) % 11) as f64 / 11.0 - 0.3;
        for p in 0..nodes {
            for q in [p, (p + 1) % nodes, (p + 3) % nodes] {
                for r in 0..b {
                    for c in 0..b {
                        let (i, j) = (p * b + r, q * b + c);
                        let v = value(i.min(j), i.max(j)) + if i == j { 4.0 } else { 0.0 };
                        t.add(i, j, v);
                        if p != q {
                            t.add(j, i, v);
                        }
                    }
                }
            }
        }
        t.build().unwrap()
    }
}
