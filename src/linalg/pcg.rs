//! Preconditioned conjugate gradients with a nodal (block) Jacobi preconditioner, optionally with
//! a principal block solved by its Cholesky factor, for the SPD step matrices of the time schemes;
//! from `GAUSS_SEIDEL_FROM` values of 3 × 3 blocks, symmetric block Gauss–Seidel by
//! Eisenstat's trick instead (`pcg/gauss_seidel.rs`).
//!
//! An iteration is one product (on the rayon pool, which also forms `pᵀAp`), one fused pass
//! `x += αp, r −= αq, z = D⁻¹r` over chunks of [`PASS_CHUNK`] on the rayon pool, during which
//! the factored block is solved on the other thread, and `p = z + βp`. Every sum is formed per
//! chunk and the chunk sums added in order: the iterates do not depend on the number of threads.
//!
//! Mixed precision: a block matrix is stored with its values rounded to single precision and the
//! rounding errors kept apart ([`BlockSym::rounded`], the memory of the double-precision values).
//! The iterations use the single-precision values (a product at 0.6–0.8 of the time once the
//! matrix no longer fits in cache: hertz3d n = 32, 402 819 dofs, 13.0 against 16.2 ms); the
//! residual `b − A x` is formed with the exact matrix at the start and checked at the end, and the
//! iterations go on from there if it is above the tolerance.

use super::factor::{check_finite, factor_err};
use super::PASS_CHUNK;
use super::{diagonal, dot, masked_dot, scale_add, sym_mul, triplets};
use super::{BlockSym, SingleFactor, SpMat, TripletBuilder};
use crate::error::{Error, Result};

mod gauss_seidel;
use gauss_seidel::GaussSeidel;

/// The product of a symmetric matrix: by blocks where it has them, by compressed columns otherwise.
#[derive(Debug, Clone)]
enum SymOperator {
    /// Single-precision values for the fast products, their rounding errors for the exact ones.
    Block(BlockSym<f32>),
    Csc(SpMat),
}

impl SymOperator {
    /// Dofs per node: the block size of a [`BlockSym`], 1 otherwise.
    fn node_size(&self) -> usize {
        match self {
            Self::Block(b) => b.block_size(),
            Self::Csc(_) => 1,
        }
    }

    /// `y = A x` with the exact matrix.
    fn mul(&self, y: &mut [f64], x: &[f64]) {
        match self {
            Self::Block(b) => b.mul_exact(y, x),
            Self::Csc(a) => sym_mul(y, a, x),
        }
    }

    /// `y = Π Ã x` (Π: zero where not free) with the fast matrix Ã (A rounded to single
    /// precision for a block matrix), returning `xᵀ y`.
    fn mul_masked_dot_fast(&self, y: &mut [f64], x: &[f64], free: &[bool]) -> f64 {
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
/// (Hestenes–Stiefel 1952). The preconditioner is `P = D`, the nodal diagonal blocks of A
/// (Jacobi by nodes), or `P = blockdiag(A_SS, D)` with a principal block factored
/// ([`Pcg::with_block`]); with fixed entries it acts on the free ones only (`Π P⁻¹ Π`, still SPD
/// on that subspace).
#[derive(Debug)]
pub struct Pcg {
    op: SymOperator,
    jacobi: NodalJacobi,
    /// The block of the preconditioner solved by its factor, if any.
    block: Option<FactoredBlock>,
    /// Symmetric Gauss–Seidel by Eisenstat's trick, where the matrix has 3 × 3 upper blocks.
    gauss_seidel: Option<GaussSeidel>,
    /// The terms `κ_i r_i r_iᵀ` added to A, as `(i, κ_i)` over the reserved rows r_i
    /// ([`Pcg::set_reserved_rank_one`]; κ_i ≠ 0).
    rank_one: Vec<(usize, f64)>,
    /// The rows of [`Pcg::reserve_rank_one`].
    reserved_rows: Vec<Vec<(usize, f64)>>,
    /// Tied dofs `x_p = Σ_j t_j x_j` ([`Pcg::set_ties`]).
    ties: Vec<Tie>,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

/// A dof `p` tied to others, `x_p = Σ_j t_j x_j + const` (an active constraint row solved for
/// its own dof): `(p, [(j, t_j)])`.
pub type Tie = (usize, Vec<(usize, f64)>);

/// `x_p = Σ_j t_j x_j` on every tied dof (the expansion `x = T y`).
fn expand(ties: &[Tie], x: &mut [f64]) {
    for (p, row) in ties {
        x[*p] = row.iter().map(|&(j, t)| t * x[j]).sum();
    }
}

/// `y ← Tᵀ y` restricted to the free dofs: each tied dof's entry goes to its partners, weighted
/// by `t_j` (the free ones), and the tied entry becomes 0.
fn fold(ties: &[Tie], y: &mut [f64], free: &[bool]) {
    for (p, row) in ties {
        let v = std::mem::take(&mut y[*p]);
        for &(j, t) in row.iter().filter(|e| free[e.0]) {
            y[j] += t * v;
        }
    }
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
    /// `A_SS` itself, refactored with the rank-one terms when they change; after
    /// [`Pcg::reserve_rank_one`], on the pattern of every reserved term (explicit zeros).
    a_ss: SpMat,
    /// For each reserved row, its pairs inside the block: `(position in a_ss's values, v_i v_j)`
    /// (empty before [`Pcg::reserve_rank_one`]).
    positions: Vec<Vec<(usize, f64)>>,
    /// The block's fixed dofs (its order) whose rows and columns the factor has replaced by the
    /// identity's ([`FactoredBlock::restrict`]); empty when it is `A_SS`'s own.
    fixed: Vec<bool>,
}

impl FactoredBlock {
    /// Factors `a_ss`'s pattern with the entries `values` again.
    fn refactor(&mut self, values: &[f64], name: &str) -> Result<()> {
        let a = faer::sparse::SparseColMatRef::new(self.a_ss.symbolic(), values);
        self.factor.refactor(a, &block_name(name))?;
        self.fixed.clear();
        Ok(())
    }

    /// Factors `A_SS` restricted to the dofs `free` (None: all), the rows and columns of the
    /// others replaced by the identity's, unless it already is; on failure the previous factor
    /// stays (a preconditioner still, if a poorer one), and false is returned.
    fn restrict(&mut self, free: Option<&[bool]>) -> bool {
        let fixed: Vec<bool> =
            free.map_or_else(Vec::new, |f| self.dofs.iter().map(|&i| !f[i]).collect());
        let fixed = if fixed.contains(&true) {
            fixed
        } else {
            Vec::new()
        };
        if fixed == self.fixed {
            return true;
        }
        let a = self.a_ss.as_ref();
        let mut values = a.val().to_vec();
        if !fixed.is_empty() {
            for j in 0..a.ncols() {
                for (k, &i) in (a.col_ptr()[j]..).zip(a.row_idx_of_col_raw(j)) {
                    if fixed[i] || fixed[j] {
                        values[k] = f64::from(u8::from(i == j));
                    }
                }
            }
        }
        if self.refactor(&values, "").is_err() {
            return false;
        }
        self.fixed = fixed;
        true
    }

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

/// Jacobi by nodes (consecutive groups of `b` dofs, b = 1, 2 or 3): `z_k = D_k⁻¹ r_k` with `D_k`
/// the diagonal block of node k, restricted to its dofs outside the factored block (and with a
/// positive diagonal). For 3D elasticity, 3 × 3 nodal blocks take 10 % fewer CG iterations than
/// the scalar diagonal (hertz3d n = 20, 60 steps: 3 036 against 3 359). The inverses are stored
/// as their upper triangles in single precision (exactly symmetric; a third of the memory
/// traffic of the full blocks in double precision, which the CG pass of the 10⁶-dof sphere read
/// at 25 MB per iteration).
#[derive(Debug)]
struct NodalJacobi {
    b: usize,
    /// `D_k⁻¹` of every node, its upper triangle row by row (b (b + 1) / 2 entries), with zero
    /// rows and columns on the excluded dofs.
    inv: Vec<f32>,
}

/// Position of entry (r, c), r ≤ c, in the upper triangle of a B × B block stored row by row.
const fn packed<const B: usize>(r: usize, c: usize) -> usize {
    r * B - r * (r + 1) / 2 + c
}

impl NodalJacobi {
    /// The nodal blocks of `a` inverted on the dofs not `excluded`; errors (naming the node)
    /// when one is not positive definite, or its inverse is beyond single precision's range.
    fn new(a: &SpMat, b: usize, excluded: &[bool], name: &str) -> Result<Self> {
        let mut blocks = vec![0.0; a.nrows() * b];
        for (i, j, v) in triplets(a).filter(|(i, j, _)| i / b == j / b) {
            blocks[(i / b) * b * b + (i % b) * b + j % b] += v;
        }
        let mut inv = Vec::with_capacity(a.nrows() / b * b * (b + 1) / 2);
        for (k, block) in blocks.chunks_exact(b * b).enumerate() {
            let kept = |r: usize| !excluded[k * b + r] && block[r * b + r] > 0.0;
            let kept: [bool; 3] = std::array::from_fn(|r| r < b && kept(r));
            let m = nalgebra::Matrix3::from_fn(|r, c| match (kept[r], kept[c]) {
                (true, true) => block[r * b + c],
                _ => f64::from(u8::from(r == c)),
            });
            let d = m.cholesky().map(|l| l.inverse()).ok_or_else(|| {
                factor_err(
                    name,
                    format!("not positive definite: the diagonal block of node {k}"),
                )
            })?;
            if d.iter().any(|v| (*v as f32).is_infinite()) {
                return Err(factor_err(
                    name,
                    format!(
                        "the inverse of the diagonal block of node {k} is beyond single \
                         precision's range (|entry| > {:.1e}): rescale the units",
                        f32::MAX
                    ),
                ));
            }
            for r in 0..b {
                for c in r..b {
                    inv.push(if kept[r] && kept[c] {
                        d[(r, c)] as f32
                    } else {
                        0.0
                    });
                }
            }
        }
        Ok(Self { b, inv })
    }

    /// `z = Π D⁻¹ r` on the nodes of `r` (a whole number of nodes from node `first`), returning
    /// `r·z`.
    fn apply(&self, first: usize, r: &[f64], z: &mut [f64], free: &[bool]) -> f64 {
        match self.b {
            3 => self.apply_nodes::<3>(first, r, z, free),
            2 => self.apply_nodes::<2>(first, r, z, free),
            _ => self.apply_nodes::<1>(first, r, z, free),
        }
    }

    /// [`NodalJacobi::apply`] for nodes of `B` dofs.
    fn apply_nodes<const B: usize>(
        &self,
        first: usize,
        r: &[f64],
        z: &mut [f64],
        free: &[bool],
    ) -> f64 {
        packed_apply::<B>(&self.inv[first * B * (B + 1) / 2..], r, z, free)
    }
}

/// `z_k = Π_k S_k r_k` for the nodes of `r` (B dofs each), `S_k` the symmetric blocks stored as
/// upper triangles in `blocks` from the first node of `r` on; returns `r·z`.
fn packed_apply<const B: usize>(blocks: &[f32], r: &[f64], z: &mut [f64], free: &[bool]) -> f64 {
    let size = B * (B + 1) / 2;
    let nodes = z.chunks_exact_mut(B).zip(r.chunks_exact(B));
    let mut rz = [0.0; 4];
    let per_node = blocks.chunks_exact(size).zip(free.chunks_exact(B));
    for (k, ((z, r), (block, free))) in nodes.zip(per_node).enumerate() {
        let r: [f64; B] = std::array::from_fn(|a| r[a]);
        let free: [bool; B] = std::array::from_fn(|a| free[a]);
        let v = packed_mul::<B>(block, r, free);
        z.copy_from_slice(&v);
        for (ra, za) in r.iter().zip(&v) {
            rz[k % 4] += ra * za;
        }
    }
    (rz[0] + rz[1]) + (rz[2] + rz[3])
}

/// `Π S r` for one node's symmetric block S stored as its upper triangle at the start of
/// `block` (Π: zero where not `free`).
#[inline(always)]
fn packed_mul<const B: usize>(block: &[f32], r: [f64; B], free: [bool; B]) -> [f64; B] {
    let block = &block[..B * (B + 1) / 2];
    let mut out = [0.0; B];
    for (a, out) in out.iter_mut().enumerate() {
        // From −0.0, as a float sum: the bits of an iterator's `sum`, without its call.
        let mut v = -0.0;
        for (c, rc) in r.iter().enumerate() {
            v += f64::from(block[packed::<B>(a.min(c), a.max(c))]) * rc;
        }
        *out = if free[a] { v } else { 0.0 };
    }
    out
}

/// One pass of CG over chunks of [`PASS_CHUNK`] (whole nodes) on the rayon pool: `x += α p`,
/// `r −= α q`, `z = Π D⁻¹ r` (nodal Jacobi; 0 on the factored block); returns `(r·z, r·r)`.
fn update(
    (x, r, z): (&mut [f64], &mut [f64], &mut [f64]),
    (p, q): (&[f64], &[f64]),
    (jacobi, free): (&NodalJacobi, &[bool]),
    alpha: f64,
) -> (f64, f64) {
    use rayon::prelude::*;
    let mine = x
        .par_chunks_mut(PASS_CHUNK)
        .zip(r.par_chunks_mut(PASS_CHUNK));
    let theirs = p.par_chunks(PASS_CHUNK).zip(q.par_chunks(PASS_CHUNK));
    let passes = mine
        .zip(z.par_chunks_mut(PASS_CHUNK))
        .zip(theirs.zip(free.par_chunks(PASS_CHUNK)))
        .enumerate()
        .map(|(c, (((x, r), z), ((p, q), free)))| {
            let mut rr = [0.0; 4];
            for (k, ((xi, ri), (pi, qi))) in x
                .iter_mut()
                .zip(r.iter_mut())
                .zip(p.iter().zip(q))
                .enumerate()
            {
                *xi += alpha * pi;
                *ri -= alpha * qi;
                rr[k % 4] += *ri * *ri;
            }
            let rz = jacobi.apply(c * PASS_CHUNK / jacobi.b, r, z, free);
            (rz, (rr[0] + rr[1]) + (rr[2] + rr[3]))
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

/// Single-precision values of a 3 × 3 block matrix with a factored block from which CG uses
/// symmetric Gauss–Seidel ([`gauss_seidel`]) instead of nodal Jacobi: where its two sweeps, each
/// streaming the values on two threads (the halves), cost less than the product for the
/// iterations they save. Measured on hertz3d (2 cores, 32 MB of L3 cache), 300 steps: n = 32,
/// 17M values, 89.2–90.7 s against 102.4–109.2 s; n = 44, 44M values, 4 min 51 s against 6 min
/// 20–38 s; below, the values stay in the cache, where the product is cheap: n = 24, 7.1M values,
/// 32.3–34.4 s against 30.0–30.9 s; n = 16, 2.1M values, 7.9–8.1 s against 6.6–8.7 s (6.6–6.8
/// in the quiet runs). Only with a factored block: without one (the standard mass) it gained
/// nothing at n = 16 (6.84 s against 6.81 s) and lost at n = 44 before the halves (the first 30
/// steps, 65.2 s against 55.1 s).
const GAUSS_SEIDEL_FROM: usize = 12 << 20;

/// The name of the factored block of the matrix `name` in messages.
fn block_name(name: &str) -> String {
    format!("{name} (stiffness-dominated block)")
}

/// `y += Π Σ_i κ_i r_i (r_iᵀ x)` over the terms `(i, κ_i)` of the `rows` (Π: zero where not
/// `free`, when given), returning its part of `xᵀ y`, `Σ_i κ_i (r_iᵀ x) (r_iᵀ Π x)`.
fn add_rank_one(
    terms: &[(usize, f64)],
    rows: &[Vec<(usize, f64)>],
    y: &mut [f64],
    x: &[f64],
    free: Option<&[bool]>,
) -> f64 {
    let kept = |j: usize| free.is_none_or(|f| f[j]);
    let mut xy = 0.0;
    for &(i, kappa) in terms {
        let row = &rows[i];
        let s = super::row_dot(row, x);
        let mut s_kept = 0.0;
        for &(j, v) in row.iter().filter(|e| kept(e.0)) {
            y[j] += kappa * s * v;
            s_kept += v * x[j];
        }
        xy += kappa * s * s_kept;
    }
    xy
}

/// The position of each dof in `dofs` (`usize::MAX` outside), for vectors of length n.
fn block_index(dofs: &[usize], n: usize) -> Vec<usize> {
    let mut index = vec![usize::MAX; n];
    for (k, &i) in dofs.iter().enumerate() {
        index[i] = k;
    }
    index
}

/// `f(index[i], index[j], v_i v_j)` for every pair of entries of the sparse `row` inside the
/// block (`index` not `usize::MAX`).
fn for_pairs_inside(row: &[(usize, f64)], index: &[usize], mut f: impl FnMut(usize, usize, f64)) {
    let inside = row.iter().filter(|e| index[e.0] != usize::MAX);
    for &(i, vi) in inside.clone() {
        for &(j, vj) in inside.clone() {
            f(index[i], index[j], vi * vj);
        }
    }
}

/// The principal submatrix `A_SS` (rows and columns `dofs`, in that order).
pub fn principal_submatrix(a: &SpMat, dofs: &[usize]) -> Result<SpMat> {
    let index = block_index(dofs, a.nrows());
    let mut b = TripletBuilder::new(dofs.len(), dofs.len());
    // The columns of the block in increasing order, as the whole matrix's entries would come.
    let mut columns = dofs.to_vec();
    columns.sort_unstable();
    columns.dedup();
    let a = a.as_ref();
    for j in columns {
        let rows = a.row_idx_of_col_raw(j).iter();
        for (&i, &v) in rows.zip(a.val_of_col(j)) {
            if index[i] != usize::MAX {
                b.add(index[i], index[j], v);
            }
        }
    }
    b.build()
}

impl Pcg {
    /// Workspaces and the nodal Jacobi preconditioner; errors when a diagonal entry is
    /// negative or a nodal block not positive definite (A not SPD). A dof with a zero diagonal
    /// must be kept fixed (`free` false) in [`Pcg::solve`].
    pub fn new(a: &SpMat, name: &str) -> Result<Self> {
        Self::with_block(a, name, Vec::new())
    }

    /// As [`Pcg::new`] with the principal block `A_SS` on `dofs` solved by its sparse Cholesky
    /// factor (rounded to single precision) in the preconditioner, nodal Jacobi elsewhere:
    /// `P = blockdiag(A_SS, D)`. Meant for the dofs where the stiffness dominates the step
    /// matrix (massless dofs of mass redistribution, small cells), which Jacobi resolves badly.
    pub fn with_block(a: &SpMat, name: &str, dofs: Vec<usize>) -> Result<Self> {
        let factored = !dofs.is_empty();
        Self::build(a, name, dofs, |b| {
            factored && b.stored_values() >= GAUSS_SEIDEL_FROM
        })
    }

    /// As [`Pcg::with_block`], with symmetric Gauss–Seidel's sweeps where `sweeps` holds for
    /// the matrix's 3 × 3 upper blocks.
    fn build(
        a: &SpMat,
        name: &str,
        dofs: Vec<usize>,
        sweeps: impl Fn(&BlockSym<f32>) -> bool,
    ) -> Result<Self> {
        check_finite(a, name)?;
        let n = a.nrows();
        let diag = diagonal(a);
        if let Some(i) = diag.iter().position(|&d| d < 0.0) {
            return Err(factor_err(
                name,
                format!("not positive definite: diagonal entry {i} is {}", diag[i]),
            ));
        }
        let op = BlockSym::new(a).map_or_else(
            || SymOperator::Csc(a.clone()),
            |b| SymOperator::Block(b.rounded()),
        );
        let mut factored = vec![false; n];
        for &i in &dofs {
            factored[i] = true;
        }
        let jacobi = NodalJacobi::new(a, op.node_size(), &factored, name)?;
        let block = if dofs.is_empty() {
            None
        } else {
            let a_ss = principal_submatrix(a, &dofs)?;
            let factor = SingleFactor::cholesky(&a_ss, &block_name(name))?;
            Some(FactoredBlock {
                work: vec![0.0; dofs.len()],
                dofs,
                factor,
                a_ss,
                positions: Vec::new(),
                fixed: Vec::new(),
            })
        };
        let gauss_seidel = match &op {
            SymOperator::Block(blocks) if sweeps(blocks) => {
                let (dofs, entries) = block
                    .as_ref()
                    .map_or((&[][..], 0), |bl| (&bl.dofs[..], bl.factor.entries()));
                GaussSeidel::new(a, blocks, (&factored, dofs, entries), &jacobi.inv)
            }
            _ => None,
        };
        Ok(Self {
            op,
            jacobi,
            block,
            gauss_seidel,
            rank_one: Vec::new(),
            reserved_rows: Vec::new(),
            ties: Vec::new(),
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            q: vec![0.0; n],
        })
    }

    /// Size of the factored block (0 for plain Jacobi).
    pub fn block_len(&self) -> usize {
        self.block.as_ref().map_or(0, |b| b.dofs.len())
    }

    /// Analyses the factored block once for every term [`Pcg::set_reserved_rank_one`] may add on
    /// these rows: the block's pattern becomes `A_SS` with every pair of a row's dofs inside the
    /// block (explicit zeros), so that a change of the terms refactors its values only (hertz3d
    /// with Nitsche: the ordering, the symbolic analysis and the triplet sort at each change of
    /// the active set took 12 % of the CPU).
    pub fn reserve_rank_one(&mut self, rows: &[Vec<(usize, f64)>], name: &str) -> Result<()> {
        let n = self.r.len();
        if let Some(bl) = self.block.as_mut() {
            let index = block_index(&bl.dofs, n);
            let mut t = TripletBuilder::new(bl.dofs.len(), bl.dofs.len());
            t.add_scaled(0, 0, 1.0, &bl.a_ss);
            for row in rows {
                for_pairs_inside(row, &index, |i, j, _| t.add(i, j, 0.0));
            }
            bl.a_ss = t.build()?;
            bl.factor = SingleFactor::cholesky(&bl.a_ss, &block_name(name))?;
            let a = bl.a_ss.as_ref();
            bl.positions = rows
                .iter()
                .map(|row| {
                    let mut pos = Vec::new();
                    for_pairs_inside(row, &index, |i, j, v| {
                        if let Ok(k) = a.row_idx_of_col_raw(j).binary_search(&i) {
                            pos.push((a.col_ptr()[j] + k, v));
                        }
                    });
                    pos
                })
                .collect();
        }
        self.reserved_rows = rows.to_vec();
        Ok(())
    }

    /// Solves with `A + Σ_i κ_i r_i r_iᵀ` from now on (`r_i` the rows reserved by
    /// [`Pcg::reserve_rank_one`], `κ_i ≥ 0`, 0: no term; the active points of a compliant contact
    /// law), until the next call. The factored block is factored again with the terms' entries
    /// inside it, located once by the reservation (hertz3d with Nitsche: locating them at every
    /// change of the active set took 5 % of the CPU); those outside it are left to the product.
    pub fn set_reserved_rank_one(&mut self, kappa: &[f64], name: &str) -> Result<()> {
        if kappa.len() != self.reserved_rows.len() {
            return Err(Error::Internal(format!(
                "{name}: {} rank-one coefficients for {} reserved rows",
                kappa.len(),
                self.reserved_rows.len()
            )));
        }
        if let Some(bl) = self.block.as_mut() {
            let mut values = bl.a_ss.val().to_vec();
            for (pairs, &k) in bl.positions.iter().zip(kappa).filter(|e| *e.1 != 0.0) {
                for &(p, v) in pairs {
                    values[p] += k * v;
                }
            }
            bl.refactor(&values, name)?;
        }
        let terms = kappa.iter().copied().enumerate();
        self.rank_one = terms.filter(|e| e.1 != 0.0).collect();
        Ok(())
    }

    /// Solves with the dofs `p` of `ties` tied to others, `x_p = Σ_j t_j x_j + const` (active
    /// constraint rows, each solved for a dof of its own; `x` satisfies them on entry to
    /// [`Pcg::solve`]), until the next call: CG runs on `TᵀAT` (T the expansion `x = T y` of the
    /// untied dofs; the tied ones must be kept fixed, `free` false). The preconditioner stays
    /// that of A, restricted to the untied dofs (SPD there, so CG converges to the same
    /// tolerance): refactoring the block as `T_SSᵀ A_SS T_SS` at every change of the ties cost
    /// more than the iterations it saved (two_spheres, 103 302 dofs, 300 steps: 84 s CPU
    /// against 70 s). Not with rank-one terms ([`Pcg::set_reserved_rank_one`]).
    pub fn set_ties(&mut self, ties: Vec<Tie>) {
        self.ties = ties;
    }

    /// Solves `A x = b` for the entries where `free` is true, the others of `x` fixed at their
    /// values on entry; `x` is also the initial guess. Stops when `‖r‖₂ ≤ tol ‖b‖₂` over the free
    /// entries; returns the iterations, or `Err(‖r‖/‖b‖)` after `max_iter`.
    pub fn solve(
        &mut self,
        b: &[f64],
        x: &mut [f64],
        free: &[bool],
        limits: (f64, usize),
    ) -> std::result::Result<usize, f64> {
        self.solve_until(b, x, free, limits, (0.0, |_: &[f64]| false))
    }

    /// As [`Pcg::solve`], and also stops (returning the iterations so far) at the first iterate
    /// with `‖r‖₂ ≤ check ‖b‖₂` for which `stop(x)` holds: for an outer loop that will change
    /// the system on seeing such an iterate.
    ///
    /// The iterations use the fast product (single-precision values for a block matrix); their
    /// recursive residual is then checked against `b − A x` with the exact matrix, and the
    /// iterations go on from there until the exact residual meets the tolerance. From a good
    /// guess one pass suffices: the rounding of A (2⁻²⁴ relative) only enters through the
    /// correction `x − x₀`, whose residual is small.
    pub fn solve_until(
        &mut self,
        b: &[f64],
        x: &mut [f64],
        free: &[bool],
        (tol, max_iter): (f64, usize),
        (check, mut stop): (f64, impl FnMut(&[f64]) -> bool),
    ) -> std::result::Result<usize, f64> {
        let b2: f64 = (0..x.len()).filter(|&i| free[i]).map(|i| b[i] * b[i]).sum();
        let (target2, check2) = (tol * tol * b2, check * check * b2);
        // The products keep the tied dofs' entries for `fold`.
        let mut wide = Vec::new();
        if !self.ties.is_empty() {
            wide = free.to_vec();
            for (p, _) in &self.ties {
                wide[*p] = true;
            }
        }
        let masks = (free, if wide.is_empty() { free } else { &wide[..] });
        let mut it = 0;
        loop {
            let res2 = self.residual(b, x, masks);
            if res2 <= target2 {
                return Ok(it);
            }
            let limits = (target2, max_iter - it);
            let (done, stopped) = if self.sweeps(free) {
                self.iterate_gauss_seidel(x, free, limits, (check2, &mut stop))
            } else {
                self.iterate(x, masks, limits, (check2, &mut stop))
            };
            it += done;
            if stopped {
                return Ok(it);
            }
            if done == 0 {
                return Err((res2 / b2).sqrt());
            }
        }
    }

    /// Whether the iterations on `free` use symmetric Gauss–Seidel (3 × 3 upper blocks, no ties
    /// and no rank-one terms), with the factored block restricted to the free dofs; otherwise
    /// the block is `A_SS` itself, as nodal Jacobi's iterations expect.
    fn sweeps(&mut self, free: &[bool]) -> bool {
        let wanted =
            self.gauss_seidel.is_some() && self.ties.is_empty() && self.reserved_rows.is_empty();
        let Some(bl) = self.block.as_mut() else {
            return wanted;
        };
        if wanted && bl.restrict(Some(free)) {
            return true;
        }
        bl.restrict(None);
        false
    }

    /// `r = Π Tᵀ (b − A x)` with the exact matrix (`wide`: the free and the tied dofs); returns
    /// `r·r`.
    fn residual(&mut self, b: &[f64], x: &[f64], (free, wide): (&[bool], &[bool])) -> f64 {
        let (r, q) = (&mut self.r, &mut self.q);
        self.op.mul(q, x);
        add_rank_one(&self.rank_one, &self.reserved_rows, q, x, None);
        for i in 0..x.len() {
            r[i] = if wide[i] { b[i] - q[i] } else { 0.0 };
        }
        fold(&self.ties, r, free);
        dot(r, r)
    }

    /// PCG iterations with the fast product from `x` and its residual `r` (in `self.r`), until
    /// the recursive residual is below `target2` (squared), `limit` iterations are done, or
    /// `stop(x)` holds at an iterate with a squared residual below `check2`. Returns the
    /// iterations and whether `stop` ended them.
    fn iterate(
        &mut self,
        x: &mut [f64],
        (free, wide): (&[bool], &[bool]),
        (target2, limit): (f64, usize),
        (check2, stop): (f64, &mut impl FnMut(&[f64]) -> bool),
    ) -> (usize, bool) {
        let Self {
            op,
            jacobi,
            block,
            rank_one,
            reserved_rows,
            ties,
            r,
            z,
            p,
            q,
            ..
        } = self;
        // Jacobi leaves z = 0 on the block, which adds its own part.
        let mut rz =
            jacobi.apply(0, r, z, free) + block.as_mut().map_or(0.0, |bl| bl.apply(r, z, free));
        p.copy_from_slice(z);
        let mut res2 = dot(r, r);
        let mut it = 0;
        while res2 > target2 {
            if res2 <= check2 && stop(x) {
                return (it, true);
            }
            if it == limit {
                break;
            }
            expand(ties, p);
            let curvature = op.mul_masked_dot_fast(q, p, wide)
                + add_rank_one(rank_one, reserved_rows, q, p, Some(free));
            fold(ties, q, free);
            let alpha = rz / curvature;
            if let Some(bl) = block.as_mut() {
                bl.load(|i| r[i] - alpha * q[i]);
            }
            let (xs, rs, zs) = (&mut x[..], &mut r[..], &mut z[..]);
            let (ps, qs, jac) = (&p[..], &q[..], &*jacobi);
            let mut pass = move || update((xs, rs, zs), (ps, qs), (jac, free), alpha);
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
        (it, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::{block_matrix, laplacian, max_diff};
    use crate::linalg::{lin_comb, mul, to_dense};

    /// Two 3D nodes: A = [[D₀, C], [Cᵀ, D₁]], all blocks full (stored as 3 × 3 blocks).
    fn two_nodes(d0: [[f64; 3]; 3]) -> SpMat {
        let d1 = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
        let mut t = TripletBuilder::new(6, 6);
        for r in 0..3 {
            for c in 0..3 {
                t.add(r, c, d0[r][c]);
                t.add(3 + r, 3 + c, d1[r][c]);
                t.add(r, 3 + c, -0.1);
                t.add(3 + c, r, -0.1);
            }
        }
        t.build().unwrap()
    }

    /// Rank-one terms on reserved rows refactor the block on its analysed pattern: the solve of
    /// `(A + Σ κ_i r_i r_iᵀ) x = b` agrees with the dense solve to CG's tolerance, with a block
    /// holding every dof of the rows and with one leaving a dof of a term to the product; a
    /// coefficient per reserved row is required.
    #[test]
    fn reserved_rank_one_terms_refactor_the_block() {
        let n = 30;
        let a = laplacian(n);
        let rows: Vec<Vec<(usize, f64)>> = (0..4)
            .map(|k| vec![(3 * k + 1, 1.0), (3 * k + 2, -0.5), (3 * k + 4, 0.25)])
            .collect();
        let block: Vec<usize> = (0..16).collect();
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).cos()).collect();
        let terms = vec![(rows[1].clone(), 50.0), (rows[3].clone(), 7.0)];
        let mut dense = to_dense(&a);
        for (row, kappa) in &terms {
            for &(i, vi) in row {
                for &(j, vj) in row {
                    dense[(i, j)] += kappa * vi * vj;
                }
            }
        }
        let exact = dense
            .lu()
            .solve(&nalgebra::DVector::from_column_slice(&b))
            .unwrap();
        // Dof 13 of the second term outside the block of 0..12.
        for block in [block.clone(), (0..12).collect()] {
            let last = block.len();
            let mut pcg = Pcg::with_block(&a, "A", block).unwrap();
            pcg.reserve_rank_one(&rows, "A").unwrap();
            pcg.set_reserved_rank_one(&[0.0, 50.0, 0.0, 7.0], "A")
                .unwrap();
            let mut x = vec![0.0; n];
            pcg.solve(&b, &mut x, &vec![true; n], (1e-12, 200)).unwrap();
            let err = max_diff(&x, exact.as_slice());
            assert!(err < 1e-9, "block 0..{last}: error {err:.3e}");
        }
        let mut pcg = Pcg::with_block(&a, "A", block).unwrap();
        pcg.reserve_rank_one(&rows[..1], "A").unwrap();
        assert!(pcg.set_reserved_rank_one(&[1.0, 2.0], "A").is_err());
    }

    /// `z_k = D_k⁻¹ r_k` on the kept dofs of each node (`D_k z_k = r_k` there, to the single
    /// precision of the stored inverse), 0 on the excluded and the fixed ones.
    #[test]
    fn nodal_jacobi_inverts_the_diagonal_blocks_on_the_kept_dofs() {
        let a = two_nodes([[5.0, 1.0, -1.0], [1.0, 4.0, 0.3], [-1.0, 0.3, 3.0]]);
        let excluded = [false, false, false, false, true, false];
        let jacobi = NodalJacobi::new(&a, 3, &excluded, "A").unwrap();
        let r = [1.0, -2.0, 0.5, 0.7, 0.0, -0.3];
        let mut free = [true; 6];
        free[2] = false;
        let mut z = [f64::NAN; 6];
        let rz = jacobi.apply(0, &r, &mut z, &free);
        assert_eq!((z[2], z[4]), (0.0, 0.0));
        // Node 1 without its excluded dof 4: the 2 × 2 block on dofs 3 and 5.
        let kept = [3, 5];
        for &i in &kept {
            let block_row: f64 = kept.iter().map(|&j| a.get(i, j).unwrap() * z[j]).sum();
            assert!(
                (block_row - r[i]).abs() < 1e-6,
                "dof {i}: {block_row} against {}",
                r[i]
            );
        }
        let expected: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
        assert!((rz - expected).abs() < 1e-14);
    }

    /// A nodal block that is not positive definite (though its diagonal is) is refused,
    /// naming the node.
    #[test]
    fn an_indefinite_nodal_block_is_refused() {
        let a = two_nodes([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let err = Pcg::new(&a, "A").unwrap_err().to_string();
        assert!(err.contains("node 0"), "{err}");
    }

    /// A nodal block whose inverse the single-precision Jacobi cannot hold (entries of 1e-40)
    /// is refused, naming the node, instead of an infinite preconditioner.
    #[test]
    fn a_nodal_inverse_beyond_single_precision_is_refused() {
        let a = two_nodes([[1e-40, 0.0, 0.0], [0.0, 1e-40, 0.0], [0.0, 0.0, 1e-40]]);
        let err = NodalJacobi::new(&a, 3, &[false; 6], "A")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("node 0") && err.contains("single precision"),
            "{err}"
        );
    }

    /// The CG iterates are formed in fixed chunks and parts: one thread or two give the same
    /// bits, with and without a factored block (9 000 dofs: three chunks of the vector passes).
    #[test]
    fn pcg_does_not_depend_on_the_number_of_threads() {
        let n = 9000;
        let mut t = TripletBuilder::new(n, n);
        for (i, j, v) in triplets(&block_matrix(n / 3, 3)) {
            t.add(i, j, v + if i == j { 12.0 } else { 0.0 });
        }
        let a = t.build().unwrap();
        let b: Vec<f64> = (0..n).map(|i| (0.1 * i as f64).sin()).collect();
        let mut free = vec![true; n];
        free[7] = false;
        // (factored block, symmetric Gauss–Seidel)
        let solve = |threads: usize, (block, sweeps): (bool, bool)| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let dofs = if block {
                    (0..600).collect()
                } else {
                    Vec::new()
                };
                let mut pcg = Pcg::build(&a, "A", dofs, |_| sweeps).unwrap();
                let mut x = vec![0.0; n];
                let it = pcg.solve(&b, &mut x, &free, (1e-12, 500)).unwrap();
                (it, x)
            })
        };
        for variant in [(false, false), (true, false), (false, true), (true, true)] {
            let ((it1, x1), (it2, x2)) = (solve(1, variant), solve(2, variant));
            assert_eq!(it1, it2);
            assert!(x1.iter().zip(&x2).all(|(p, q)| p.to_bits() == q.to_bits()));
            let ax = mul(&a, &x1);
            let res = (0..n).filter(|&i| free[i]).map(|i| (ax[i] - b[i]).abs());
            assert!(
                res.fold(0.0, f64::max) < 1e-10,
                "{variant:?}: {it1} iterations"
            );
        }
    }

    #[test]
    fn lin_comb_merges_patterns_and_pcg_solves_with_fixed_entries() {
        let (a, k) = (laplacian(40), block_matrix(20, 2));
        let sum = lin_comb(2.0, &a, 0.5, &k).unwrap();
        let (da, dk, ds) = (to_dense(&a), to_dense(&k), to_dense(&sum));
        assert!((ds - (da * 2.0 + dk * 0.5)).abs().max() < 1e-15);
        let mut pcg = Pcg::new(&sum, "A").unwrap();
        let x_true: Vec<f64> = (0..40).map(|i| (i as f64).cos()).collect();
        let b = mul(&sum, &x_true);
        let mut free = vec![true; 40];
        let mut x = vec![0.0; 40];
        (free[3], x[3]) = (false, x_true[3]);
        let it = pcg.solve(&b, &mut x, &free, (1e-12, 200)).unwrap();
        assert!(max_diff(&x, &x_true) < 1e-9, "{it} iterations");
        assert!(pcg
            .solve(&b, &mut vec![0.0; 40], &free, (1e-12, 1))
            .is_err());
    }

    /// A tied dof `x₀ = ½ x₃ − ⅕ x₇ + 0.1` (fixed for CG, its row folded onto its partners, the
    /// block factored without the tie): the solution keeps the tie and solves `Tᵀ (b − A x) = 0`
    /// on the untied dofs, the constrained system.
    #[test]
    fn pcg_with_a_tie_solves_the_constrained_system() {
        let n = 60;
        let mut t = TripletBuilder::new(n, n);
        for (i, j, v) in triplets(&laplacian(n)) {
            let s = if i < n / 2 && j < n / 2 { 1e4 } else { 1.0 };
            t.add(i, j, s * v + if i == j { 1e-2 } else { 0.0 });
        }
        let a = t.build().unwrap();
        let b: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).sin()).collect();
        let mut pcg = Pcg::with_block(&a, "A", (0..n / 2 + 1).collect()).unwrap();
        let tie = vec![(3, 0.5), (7, -0.2)];
        pcg.set_ties(vec![(0, tie.clone())]);
        let mut free = vec![true; n];
        free[0] = false;
        let mut x = vec![0.0; n];
        x[0] = 0.1;
        let it = pcg.solve(&b, &mut x, &free, (1e-12, 500)).unwrap();
        assert!((x[0] - 0.5 * x[3] + 0.2 * x[7] - 0.1).abs() < 1e-14);
        let ax = mul(&a, &x);
        let res: Vec<f64> = (0..n).map(|i| b[i] - ax[i]).collect();
        let mut folded = res.clone();
        for &(j, t) in &tie {
            folded[j] += t * res[0];
        }
        let worst = (1..n).map(|i| folded[i].abs()).fold(0.0, f64::max);
        assert!(worst < 1e-9, "{it} iterations: residual {worst:e}");
    }

    /// Symmetric Gauss–Seidel by Eisenstat's trick solves with fixed dofs inside and outside
    /// the factored block (which it factors again on the free dofs) to the tolerance, in fewer
    /// iterations than nodal Jacobi with the same block, and again after the fixed dofs change.
    #[test]
    fn gauss_seidel_solves_with_fixed_dofs_in_fewer_iterations() {
        let nodes = 400;
        let n = 3 * nodes;
        let mut t = TripletBuilder::new(n, n);
        for (i, j, v) in triplets(&block_matrix(nodes, 3)) {
            t.add(i, j, v + if i == j { 9.0 } else { 0.0 });
        }
        let a = t.build().unwrap();
        let x_true: Vec<f64> = (0..n).map(|i| (0.05 * i as f64).cos()).collect();
        let b = mul(&a, &x_true);
        // The block: the z component of the first 100 nodes (as the massless normal dofs).
        let dofs: Vec<usize> = (0..100).map(|k| 3 * k + 2).collect();
        let solve = |pcg: &mut Pcg, fixed: &[usize]| {
            let mut free = vec![true; n];
            let mut x = vec![0.0; n];
            for &i in fixed {
                free[i] = false;
                x[i] = x_true[i];
            }
            let it = pcg.solve(&b, &mut x, &free, (1e-12, 500)).unwrap();
            assert!(max_diff(&x, &x_true) < 1e-9, "{it} iterations");
            it
        };
        let mut jacobi = Pcg::build(&a, "A", dofs.clone(), |_| false).unwrap();
        let mut sweeps = Pcg::build(&a, "A", dofs, |_| true).unwrap();
        for fixed in [vec![2, 5, 50, 601], vec![], vec![8, 11, 14, 700, 701]] {
            let (j, s) = (solve(&mut jacobi, &fixed), solve(&mut sweeps, &fixed));
            assert!(
                s < j,
                "fixed {fixed:?}: {s} iterations against Jacobi's {j}"
            );
        }
    }

    /// With a block solved by its (single-precision) factor, PCG still converges to the solution (a fixed entry inside
    /// the block included), and the block of a stiff region cuts the iterations: a Laplacian
    /// whose first half is scaled by 10⁴ needs fewer iterations with that half factored.
    #[test]
    fn pcg_with_a_factored_block_converges_faster() {
        let n = 60;
        let lap = laplacian(n);
        let mut t = TripletBuilder::new(n, n);
        for (i, j, v) in triplets(&lap) {
            let s = if i < n / 2 && j < n / 2 { 1e4 } else { 1.0 };
            t.add(i, j, s * v + if i == j { 1e-2 } else { 0.0 });
        }
        let a = t.build().unwrap();
        let x_true: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).sin()).collect();
        let b = mul(&a, &x_true);
        let mut free = vec![true; n];
        let solve = |pcg: &mut Pcg, free: &[bool]| {
            let mut x = vec![0.0; n];
            x[5] = x_true[5];
            let it = pcg.solve(&b, &mut x, free, (1e-12, 2000)).unwrap();
            assert!(max_diff(&x, &x_true) < 1e-6, "{it} iterations");
            it
        };
        let jacobi = solve(&mut Pcg::new(&a, "A").unwrap(), &free);
        let mut blocked = Pcg::with_block(&a, "A", (0..n / 2 + 1).collect()).unwrap();
        assert_eq!(blocked.block_len(), n / 2 + 1);
        let with_block = solve(&mut blocked, &free);
        assert!(with_block < jacobi, "{with_block} ≥ {jacobi}");
        free[5] = false;
        solve(&mut blocked, &free);
    }
}
