//! Preconditioned conjugate gradients with a Jacobi preconditioner, optionally with a principal
//! block solved exactly, for the SPD step matrices of the time schemes.

use super::{check_finite, diagonal, dot, dot_unordered, factor_err, scale_add, sym_mul, triplets};
use super::{BlockSym, Factor, SpMat, TripletBuilder};
use crate::error::Result;

/// The product of a symmetric matrix: by blocks where it has them, by compressed columns otherwise.
#[derive(Debug, Clone)]
enum SymOperator {
    Block(BlockSym),
    Csc(SpMat),
}

impl SymOperator {
    fn mul(&self, y: &mut [f64], x: &[f64]) {
        match self {
            Self::Block(b) => b.mul(y, x),
            Self::Csc(a) => sym_mul(y, a, x),
        }
    }
}

/// Preconditioned conjugate gradients for an SPD matrix, with workspaces kept between solves
/// (Hestenes–Stiefel 1952). The preconditioner is `P = diag(A)` (Jacobi), or
/// `P = blockdiag(A_SS, diag(A))` with a principal block factored ([`Pcg::with_block`]); with
/// fixed entries it acts on the free ones only (`Π P⁻¹ Π`, still SPD on that subspace).
#[derive(Debug)]
pub struct Pcg {
    op: SymOperator,
    inv_diag: Vec<f64>,
    /// The block of the preconditioner solved exactly, if any.
    block: Option<ExactBlock>,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

/// A principal block `A_SS` of the preconditioner, factored (sparse Cholesky).
#[derive(Debug)]
struct ExactBlock {
    dofs: Vec<usize>,
    factor: Factor,
    work: Vec<f64>,
}

impl ExactBlock {
    /// `z_S = A_SS⁻¹ r_S` on the free dofs of S (0 on the fixed ones); returns `Σ_S r_i z_i`.
    fn apply(&mut self, r: &[f64], z: &mut [f64], free: &[bool]) -> f64 {
        for (w, &i) in self.work.iter_mut().zip(&self.dofs) {
            *w = r[i];
        }
        self.factor.solve_in_place(&mut self.work);
        let mut rz = 0.0;
        for (&w, &i) in self.work.iter().zip(&self.dofs) {
            z[i] = if free[i] { w } else { 0.0 };
            rz += r[i] * z[i];
        }
        rz
    }
}

/// The principal submatrix `A_SS` (rows and columns `dofs`, in that order).
pub fn principal_submatrix(a: &SpMat, dofs: &[usize]) -> Result<SpMat> {
    let mut index = vec![usize::MAX; a.nrows()];
    for (k, &i) in dofs.iter().enumerate() {
        index[i] = k;
    }
    let mut b = TripletBuilder::new(dofs.len(), dofs.len());
    for (i, j, v) in triplets(a) {
        if index[i] != usize::MAX && index[j] != usize::MAX {
            b.add(index[i], index[j], v);
        }
    }
    b.build()
}

impl Pcg {
    /// Workspaces and `diag(A)⁻¹`; errors when a diagonal entry is negative (A not SPD). A dof
    /// with a zero diagonal must be kept fixed (`free` false) in [`Pcg::solve`].
    pub fn new(a: &SpMat, name: &str) -> Result<Self> {
        check_finite(a, name)?;
        let n = a.nrows();
        let diag = diagonal(a);
        if let Some(i) = diag.iter().position(|&d| d < 0.0) {
            return Err(factor_err(
                name,
                format!("not positive definite: diagonal entry {i} is {}", diag[i]),
            ));
        }
        Ok(Self {
            op: BlockSym::new(a).map_or_else(|| SymOperator::Csc(a.clone()), SymOperator::Block),
            inv_diag: diag
                .iter()
                .map(|&d| if d > 0.0 { 1.0 / d } else { 0.0 })
                .collect(),
            block: None,
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            q: vec![0.0; n],
        })
    }

    /// As [`Pcg::new`] with the principal block `A_SS` on `dofs` solved exactly (sparse Cholesky)
    /// in the preconditioner, Jacobi elsewhere: `P = blockdiag(A_SS, diag(A))`. Meant for the
    /// dofs where the stiffness dominates the step matrix (massless dofs of mass redistribution,
    /// small cells), which Jacobi resolves badly.
    pub fn with_block(a: &SpMat, name: &str, dofs: Vec<usize>) -> Result<Self> {
        let mut pcg = Self::new(a, name)?;
        if dofs.is_empty() {
            return Ok(pcg);
        }
        let factor = Factor::cholesky(
            &principal_submatrix(a, &dofs)?,
            &format!("{name} (stiffness-dominated block)"),
        )?;
        for &i in &dofs {
            pcg.inv_diag[i] = 0.0;
        }
        pcg.block = Some(ExactBlock {
            work: vec![0.0; dofs.len()],
            dofs,
            factor,
        });
        Ok(pcg)
    }

    /// Size of the exactly solved block (0 for plain Jacobi).
    pub fn block_len(&self) -> usize {
        self.block.as_ref().map_or(0, |b| b.dofs.len())
    }

    /// Solves `A x = b` for the entries where `free` is true, the others of `x` fixed at their
    /// values on entry; `x` is also the initial guess. Stops when `‖r‖₂ ≤ tol ‖b‖₂` over the free
    /// entries; returns the iterations, or `Err(‖r‖/‖b‖)` after `max_iter`.
    pub fn solve(
        &mut self,
        b: &[f64],
        x: &mut [f64],
        free: &[bool],
        (tol, max_iter): (f64, usize),
    ) -> std::result::Result<usize, f64> {
        let Self {
            op,
            inv_diag,
            block,
            r,
            z,
            p,
            q,
        } = self;
        let masked = |i: usize, v: f64| if free[i] { v } else { 0.0 };
        op.mul(q, x);
        let mut b2 = 0.0;
        for i in 0..x.len() {
            r[i] = masked(i, b[i] - q[i]);
            z[i] = inv_diag[i] * r[i];
            b2 += masked(i, b[i]).powi(2);
        }
        let target2 = tol * tol * b2;
        // Jacobi leaves z = 0 on the block (inv_diag 0 there), which adds its own part.
        let mut rz = dot(r, z) + block.as_mut().map_or(0.0, |bl| bl.apply(r, z, free));
        p.copy_from_slice(z);
        let mut res2 = dot(r, r);
        let mut it = 0;
        while res2 > target2 {
            if it == max_iter {
                return Err((res2 / b2).sqrt());
            }
            op.mul(q, p);
            for (i, qi) in q.iter_mut().enumerate() {
                *qi = masked(i, *qi);
            }
            let alpha = rz / dot_unordered(p, q);
            // One pass: x += αp, r −= αq, z = P⁻¹r, and the sums r·z, r·r (four lanes each).
            let (mut rz4, mut rr4) = ([0.0; 4], [0.0; 4]);
            for (k, (((xi, ri), zi), (pi, qi))) in x
                .iter_mut()
                .zip(r.iter_mut())
                .zip(z.iter_mut())
                .zip(p.iter().zip(q.iter()))
                .enumerate()
            {
                *xi += alpha * pi;
                *ri -= alpha * qi;
                *zi = inv_diag[k] * *ri;
                rz4[k % 4] += *ri * *zi;
                rr4[k % 4] += *ri * *ri;
            }
            let rz_new =
                rz4.iter().sum::<f64>() + block.as_mut().map_or(0.0, |bl| bl.apply(r, z, free));
            res2 = rr4.iter().sum();
            scale_add(p, rz_new / rz, 1.0, z);
            rz = rz_new;
            it += 1;
        }
        Ok(it)
    }
}
