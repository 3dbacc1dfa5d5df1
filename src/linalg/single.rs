//! A Cholesky factor rounded to single precision, for preconditioners.

use super::factor::{factor_err, numeric_llt, par_for, Factor, Kind};
use super::sparse::SpMat;
use crate::error::Result;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::sparse::SparseColMatRef;
use faer::{Conj, MatMut, Par};

/// A Cholesky factor `L` rounded to single precision, `L̃ = fl₃₂(L)`: its solves apply
/// `(L̃ L̃ᵀ)⁻¹` (up to single-precision round-off) with half the memory traffic of `L`, for a
/// preconditioner, where `L̃ L̃ᵀ` need only be close to the matrix.
pub struct SingleFactor {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f32>,
    n: usize,
    buffer: MemBuffer,
}

impl std::fmt::Debug for SingleFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "SingleFactor(LLt, n = {}, {} entries)",
            self.n,
            self.values.len()
        )
    }
}

impl SingleFactor {
    /// [`Factor::cholesky`] of `a`, rounded to single precision.
    pub fn cholesky(a: &SpMat, name: &str) -> Result<Self> {
        let factor = Factor::cholesky(a, name)?;
        let Kind::Llt { symbolic, values } = factor.kind else {
            return Err(factor_err(name, "not a Cholesky factor"));
        };
        let buffer = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f32>(1, Par::Seq))
            .map_err(|e| factor_err(name, e))?;
        Ok(Self {
            values: values.iter().map(|&v| v as f32).collect(),
            symbolic,
            n: factor.n,
            buffer,
        })
    }

    /// Factors `a` again on the pattern analysed by [`SingleFactor::cholesky`] (no new
    /// ordering or symbolic analysis: `a` must have the analysed matrix's pattern).
    pub fn refactor(&mut self, a: SparseColMatRef<'_, usize, f64>, name: &str) -> Result<()> {
        let values = numeric_llt(&self.symbolic, a, par_for(self.n), name)?;
        self.values = values.iter().map(|&v| v as f32).collect();
        Ok(())
    }

    /// The entries of the factor.
    pub fn entries(&self) -> usize {
        self.values.len()
    }

    /// `x ← (L̃ L̃ᵀ)⁻¹ x` in single precision.
    pub fn solve_in_place(&mut self, x: &mut [f32]) {
        assert_eq!(x.len(), self.n, "right-hand side of the wrong length");
        let rhs = MatMut::from_column_major_slice_mut(x, self.n, 1);
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.buffer),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::mul;
    use crate::linalg::testing::{laplacian, max_diff};

    /// The single-precision factor solves to the accuracy its rounding allows: relative error
    /// below a few κ(A) ε₃₂ (the 1D Laplacian of order n: κ ≈ 4 (n + 1)² / π²).
    #[test]
    fn single_factor_solves_to_single_precision() {
        let n = 50;
        let a = laplacian(n);
        let x: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64 * 0.37).sin()).collect();
        let mut y: Vec<f32> = mul(&a, &x).iter().map(|&v| v as f32).collect();
        SingleFactor::cholesky(&a, "A")
            .unwrap()
            .solve_in_place(&mut y);
        let y: Vec<f64> = y.iter().map(|&v| f64::from(v)).collect();
        let kappa = 4.0 * ((n + 1) as f64 / std::f64::consts::PI).powi(2);
        let bound = 4.0 * kappa * f64::from(f32::EPSILON) * 2.0;
        let err = max_diff(&y, &x);
        assert!(err < bound, "error {err:.3e} above {bound:.3e}");
    }
}
