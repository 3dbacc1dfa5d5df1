//! Preconditioned conjugate gradients with a Jacobi preconditioner, optionally with a principal
//! block solved by its Cholesky factor, for the SPD step matrices of the time schemes.
//!
//! An iteration is one product (on the rayon pool, which also forms `pᵀAp`), one fused pass
//! `x += αp, r −= αq, z = D⁻¹r` over chunks of [`PASS_CHUNK`] on the rayon pool, during which
//! the factored block is solved on the other thread, and `p = z + βp`. Every sum is formed per
//! chunk and the chunk sums added in order: the iterates do not depend on the number of threads.

use super::PASS_CHUNK;
use super::{check_finite, diagonal, dot, factor_err, masked_dot, scale_add, sym_mul, triplets};
use super::{BlockSym, SingleFactor, SpMat, TripletBuilder};
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

    /// `y = Π A x` (Π: zero where not free), returning `xᵀ y`.
    fn mul_masked_dot(&self, y: &mut [f64], x: &[f64], free: &[bool]) -> f64 {
        match self {
            Self::Block(b) => b.mul_masked_dot(y, x, free),
            Self::Csc(a) => {
                sym_mul(y, a, x);
                masked_dot(y, x, free, |_, yi| yi)
            }
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
    /// The block of the preconditioner solved by its factor, if any.
    block: Option<FactoredBlock>,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

/// A principal block `A_SS` of the preconditioner, factored (sparse Cholesky) and solved in
/// single precision ([`SingleFactor`]): half the memory traffic of the double-precision solve,
/// and the same CG iterations (hertz3d n = 20, 60 steps: 3 359 against 3 357), since the
/// residual, the product and the stopping test stay in double precision.
#[derive(Debug)]
struct FactoredBlock {
    dofs: Vec<usize>,
    factor: SingleFactor,
    work: Vec<f32>,
}

impl FactoredBlock {
    /// `z_S = A_SS⁻¹ r_S` on the free dofs of S (0 on the fixed ones); returns `Σ_S r_i z_i`.
    fn apply(&mut self, r: &[f64], z: &mut [f64], free: &[bool]) -> f64 {
        self.load(|i| r[i]);
        self.factor.solve_in_place(&mut self.work);
        self.store(r, z, free)
    }

    /// `w = (r_i)_{i ∈ S}`.
    fn load(&mut self, r: impl Fn(usize) -> f64) {
        for (w, &i) in self.work.iter_mut().zip(&self.dofs) {
            *w = r(i) as f32;
        }
    }

    /// `z_S = w` on the free dofs of S (0 on the fixed ones); returns `Σ_S r_i z_i`.
    fn store(&self, r: &[f64], z: &mut [f64], free: &[bool]) -> f64 {
        let mut rz = 0.0;
        for (&w, &i) in self.work.iter().zip(&self.dofs) {
            z[i] = if free[i] { f64::from(w) } else { 0.0 };
            rz += r[i] * z[i];
        }
        rz
    }
}

/// One pass of CG over chunks of [`PASS_CHUNK`] on the rayon pool: `x += α p`, `r −= α q`,
/// `z = D⁻¹ r` (Jacobi; 0 on the factored block, where `D⁻¹` is 0); returns `(r·z, r·r)`.
fn update(
    (x, r, z): (&mut [f64], &mut [f64], &mut [f64]),
    (p, q, inv_diag): (&[f64], &[f64], &[f64]),
    alpha: f64,
) -> (f64, f64) {
    use rayon::prelude::*;
    let mine = x
        .par_chunks_mut(PASS_CHUNK)
        .zip(r.par_chunks_mut(PASS_CHUNK));
    let theirs = p.par_chunks(PASS_CHUNK).zip(q.par_chunks(PASS_CHUNK));
    let passes = mine
        .zip(z.par_chunks_mut(PASS_CHUNK))
        .zip(theirs.zip(inv_diag.par_chunks(PASS_CHUNK)))
        .map(|(((x, r), z), ((p, q), d))| {
            let (mut rz, mut rr) = ([0.0; 4], [0.0; 4]);
            for (k, (((xi, ri), zi), ((pi, qi), di))) in x
                .iter_mut()
                .zip(r.iter_mut())
                .zip(z.iter_mut())
                .zip(p.iter().zip(q).zip(d))
                .enumerate()
            {
                *xi += alpha * pi;
                *ri -= alpha * qi;
                *zi = di * *ri;
                rz[k % 4] += *ri * *zi;
                rr[k % 4] += *ri * *ri;
            }
            let sum = |a: [f64; 4]| (a[0] + a[1]) + (a[2] + a[3]);
            (sum(rz), sum(rr))
        });
    let mut sums = Vec::new();
    passes.collect_into_vec(&mut sums);
    sums.iter()
        .fold((0.0, 0.0), |(a, b), (rz, rr)| (a + rz, b + rr))
}

/// `p = z + β p` over chunks on the rayon pool.
fn next_direction(p: &mut [f64], z: &[f64], beta: f64) {
    use rayon::prelude::*;
    p.par_chunks_mut(PASS_CHUNK)
        .zip(z.par_chunks(PASS_CHUNK))
        .for_each(|(p, z)| scale_add(p, beta, 1.0, z));
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

    /// As [`Pcg::new`] with the principal block `A_SS` on `dofs` solved by its sparse Cholesky
    /// factor (rounded to single precision) in the preconditioner, Jacobi elsewhere:
    /// `P = blockdiag(A_SS, diag(A))`. Meant for the
    /// dofs where the stiffness dominates the step matrix (massless dofs of mass redistribution,
    /// small cells), which Jacobi resolves badly.
    pub fn with_block(a: &SpMat, name: &str, dofs: Vec<usize>) -> Result<Self> {
        let mut pcg = Self::new(a, name)?;
        if dofs.is_empty() {
            return Ok(pcg);
        }
        let factor = SingleFactor::cholesky(
            &principal_submatrix(a, &dofs)?,
            &format!("{name} (stiffness-dominated block)"),
        )?;
        for &i in &dofs {
            pcg.inv_diag[i] = 0.0;
        }
        pcg.block = Some(FactoredBlock {
            work: vec![0.0; dofs.len()],
            dofs,
            factor,
        });
        Ok(pcg)
    }

    /// Size of the factored block (0 for plain Jacobi).
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
            let alpha = rz / op.mul_masked_dot(q, p, free);
            if let Some(bl) = block.as_mut() {
                bl.load(|i| r[i] - alpha * q[i]);
            }
            let (xs, rs, zs) = (&mut x[..], &mut r[..], &mut z[..]);
            let (ps, qs, ds) = (&p[..], &q[..], &inv_diag[..]);
            let mut pass = move || update((xs, rs, zs), (ps, qs, ds), alpha);
            // The block's residual r_S − α q_S is solved on one thread while the pass runs.
            let ((rz_jacobi, rr), rz_block) = match block.as_mut() {
                None => (pass(), 0.0),
                Some(bl) => {
                    let (w, factor) = (&mut bl.work, &mut bl.factor);
                    let (sums, ()) = rayon::join(pass, || factor.solve_in_place(w));
                    (sums, bl.store(r, z, free))
                }
            };
            let rz_new = rz_jacobi + rz_block;
            res2 = rr;
            next_direction(p, z, rz_new / rz);
            rz = rz_new;
            it += 1;
        }
        Ok(it)
    }
}
