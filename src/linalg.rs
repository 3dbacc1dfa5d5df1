//! Sparse linear algebra on top of faer: assembly from triplets, products, and a factorisation that
//! is analysed and factored once, then solves in place without allocating (faer's `MemStack`).

use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};

mod pcg;
pub use pcg::{principal_submatrix, Pcg};

/// Sparse matrix in compressed-column form (faer).
pub type SpMat = SparseColMat<usize, f64>;

/// Accumulates `(row, col, value)` entries; duplicates are summed on [`TripletBuilder::build`].
#[derive(Debug, Clone, Default)]
pub struct TripletBuilder {
    nrows: usize,
    ncols: usize,
    entries: Vec<Triplet<usize, usize, f64>>,
}

impl TripletBuilder {
    /// An empty `nrows × ncols` matrix.
    pub fn new(nrows: usize, ncols: usize) -> Self {
        Self {
            nrows,
            ncols,
            entries: Vec::new(),
        }
    }

    /// Adds `value` at `(row, col)` (summed with previous entries there).
    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        debug_assert!(row < self.nrows && col < self.ncols);
        self.entries.push(Triplet::new(row, col, value));
    }

    /// Adds `scale · m` with its top-left corner at `(row0, col0)`.
    pub fn add_scaled(&mut self, row0: usize, col0: usize, scale: f64, m: &SpMat) {
        for (i, j, v) in triplets(m) {
            self.add(row0 + i, col0 + j, scale * v);
        }
    }

    /// The assembled matrix: entries bucketed by column (counting sort), then each column
    /// sorted by row (stable: duplicates are summed in insertion order) and merged.
    pub fn build(&self) -> Result<SpMat> {
        let (n, m) = (self.nrows, self.ncols);
        if let Some(t) = self.entries.iter().find(|t| t.row >= n || t.col >= m) {
            return Err(Error::Factorisation {
                matrix: format!("{n}x{m} assembly"),
                reason: format!("entry ({}, {}) out of bounds", t.row, t.col),
            });
        }
        let mut start = vec![0usize; m + 1];
        for t in &self.entries {
            start[t.col + 1] += 1;
        }
        for j in 0..m {
            start[j + 1] += start[j];
        }
        let mut next = start.clone();
        let mut bucket = vec![(0usize, 0.0f64); self.entries.len()];
        for t in &self.entries {
            bucket[next[t.col]] = (t.row, t.val);
            next[t.col] += 1;
        }
        let mut col_ptr = Vec::with_capacity(m + 1);
        let mut row_idx = Vec::with_capacity(bucket.len());
        let mut val = Vec::with_capacity(bucket.len());
        col_ptr.push(0);
        for j in 0..m {
            let col = &mut bucket[start[j]..start[j + 1]];
            col.sort_by_key(|e| e.0);
            for &(i, v) in col.iter() {
                if row_idx.len() > col_ptr[j] && row_idx.last() == Some(&i) {
                    if let Some(last) = val.last_mut() {
                        *last += v;
                    }
                } else {
                    row_idx.push(i);
                    val.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let symbolic =
            faer::sparse::SymbolicSparseColMat::new_checked(n, m, col_ptr, None, row_idx);
        Ok(SpMat::new(symbolic, val))
    }
}

/// The rows of a sparse matrix as `(column, value)` lists (short rows, e.g. contact rows).
pub fn rows(m: &SpMat) -> Vec<Vec<(usize, f64)>> {
    let mut rows = vec![Vec::new(); m.nrows()];
    for (i, j, v) in triplets(m) {
        rows[i].push((j, v));
    }
    rows
}

/// Stored entries `(row, col, value)` of a sparse matrix.
pub fn triplets(m: &SpMat) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
    let m = m.as_ref();
    (0..m.ncols()).flat_map(move |j| {
        m.row_idx_of_col_raw(j)
            .iter()
            .zip(m.val_of_col(j))
            .map(move |(&i, &v)| (i, j, v))
    })
}

/// Compressed-column arrays `(col_ptr, row_idx, values)` of `a`, whose columns are contiguous
/// (faer matrices built from triplets are).
fn csc(a: &SpMat) -> (&[usize], &[usize], &[f64]) {
    let a = a.as_ref();
    debug_assert!(a.symbolic().col_nnz().is_none());
    (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val())
}

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
fn col_dot((cp, ri, v): (&[usize], &[usize], &[f64]), x: &[f64], j: usize) -> f64 {
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
const CHUNK: usize = 2048;

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

/// The diagonal of a square sparse matrix (duplicates summed).
pub fn diagonal(a: &SpMat) -> Vec<f64> {
    let mut d = vec![0.0; a.nrows()];
    for (i, _, v) in triplets(a).filter(|(i, j, _)| i == j) {
        d[i] += v;
    }
    d
}

/// Euclidean inner product summed in four interleaved partial sums (not bit-identical to
/// [`dot`]; a sequential sum is bound by the latency of one addition per term).
pub fn dot_unordered(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail = dot(xc.remainder(), yc.remainder());
    for (a, b) in xc.zip(yc) {
        for k in 0..4 {
            acc[k] += a[k] * b[k];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Euclidean inner product.
pub fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// Entries per chunk of the vector passes of CG: each chunk forms its own sums and the chunk
/// sums are added in order, so that the result does not depend on the number of threads. A
/// multiple of 2 and 3, so that a chunk holds whole nodes of a 2D or 3D vector field.
pub const PASS_CHUNK: usize = 4098;

/// Chunk sums added in order.
fn sum_in_order(chunks: impl rayon::iter::IndexedParallelIterator<Item = f64>) -> f64 {
    let mut sums = Vec::new();
    chunks.collect_into_vec(&mut sums);
    sums.iter().sum()
}

/// `y_i ← g(i, y_i)` where `free_i`, 0 elsewhere, for every i, returning `Σ_i x_i y_i` (chunks of
/// [`PASS_CHUNK`] on the rayon pool).
pub fn masked_dot(
    y: &mut [f64],
    x: &[f64],
    free: &[bool],
    g: impl Fn(usize, f64) -> f64 + Sync,
) -> f64 {
    use rayon::prelude::*;
    let chunks = y.par_chunks_mut(PASS_CHUNK).zip(x.par_chunks(PASS_CHUNK));
    sum_in_order(
        chunks
            .zip(free.par_chunks(PASS_CHUNK))
            .enumerate()
            .map(|(c, ((y, x), free))| {
                for (k, (yi, &f)) in y.iter_mut().zip(free).enumerate() {
                    *yi = if f { g(c * PASS_CHUNK + k, *yi) } else { 0.0 };
                }
                dot_unordered(x, y)
            }),
    )
}

/// `out = a x + b y`.
pub fn combine(out: &mut [f64], (a, x): (f64, &[f64]), (b, y): (f64, &[f64])) {
    for ((o, xi), yi) in out.iter_mut().zip(x).zip(y) {
        *o = a * xi + b * yi;
    }
}

/// `y = a y + b x`.
pub fn scale_add(y: &mut [f64], a: f64, b: f64, x: &[f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi = a * *yi + b * xi;
    }
}

/// `y += alpha x`.
pub fn axpy(y: &mut [f64], alpha: f64, x: &[f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += alpha * xi;
    }
}

/// `A = a · X + b · Y` for two sparse matrices of the same shape (union of the patterns), by a
/// merge of their sorted columns (no triplet sort).
pub fn lin_comb(a: f64, x: &SpMat, b: f64, y: &SpMat) -> Result<SpMat> {
    let (n, m) = (x.nrows(), x.ncols());
    if (y.nrows(), y.ncols()) != (n, m) {
        return Err(Error::Factorisation {
            matrix: format!("{n}x{m} + {}x{}", y.nrows(), y.ncols()),
            reason: "shapes differ".into(),
        });
    }
    let ((xp, xi, xv), (yp, yi, yv)) = (csc(x), csc(y));
    let mut col_ptr = Vec::with_capacity(m + 1);
    let mut row_idx = Vec::with_capacity(xv.len().max(yv.len()));
    let mut val = Vec::with_capacity(row_idx.capacity());
    col_ptr.push(0);
    for j in 0..m {
        let (mut p, mut q) = (xp[j], yp[j]);
        while p < xp[j + 1] || q < yp[j + 1] {
            let rx = if p < xp[j + 1] { xi[p] } else { usize::MAX };
            let ry = if q < yp[j + 1] { yi[q] } else { usize::MAX };
            let r = rx.min(ry);
            let mut v = 0.0;
            if rx == r {
                v += a * xv[p];
                p += 1;
            }
            if ry == r {
                v += b * yv[q];
                q += 1;
            }
            row_idx.push(r);
            val.push(v);
        }
        col_ptr.push(row_idx.len());
    }
    let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(n, m, col_ptr, None, row_idx);
    Ok(SpMat::new(symbolic, val))
}

/// Which factorisation a [`Factor`] holds.
enum Kind {
    /// `A = L Lᵀ` (A SPD), fill-reducing ordering from faer's AMD.
    Llt {
        symbolic: SymbolicCholesky<usize>,
        values: Vec<f64>,
    },
    /// `P A Q = L U` with partial pivoting (A square, possibly indefinite).
    Lu {
        symbolic: SymbolicLu<usize>,
        numeric: NumericLu<usize, f64>,
    },
}

/// Index arrays of a simplicial Cholesky factor computed by faer (`L` in CSC form, diagonal
/// first in each column, and the fill-reducing permutation `P A Pᵀ = L Lᵀ`).
struct Simplicial {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    perm_fwd: Vec<usize>,
    /// `1 / L_jj`: the sweeps are a serial dependency chain, and a multiplication has a quarter
    /// of a division's latency.
    inv_diag: Vec<f64>,
    /// For a bidiagonal L (1D P1 in its natural order): `(l_{j−1,j}... )` scaled couplings
    /// `f_j = l_{j,j−1}/l_jj` and `b_j = l_{j+1,j}/l_jj`, so that each sweep step is one FMA on
    /// the critical path: `w_j = w_j/l_jj − f_j w_{j−1}`.
    band: Option<(Vec<f64>, Vec<f64>)>,
    perm_is_identity: bool,
    work: Vec<f64>,
}

/// A sparse factorisation computed once; [`Factor::solve_in_place`] then performs the triangular
/// solves with a preallocated workspace (no allocation per call).
pub struct Factor {
    kind: Kind,
    n: usize,
    buffer: MemBuffer,
    /// When faer chose a simplicial factor, its arrays: the solves then run as two plain
    /// column sweeps over faer's `L` (faer's generic multi-column solve costs ≈ 18 ns per dof on a
    /// tridiagonal factor, the sweeps ≈ 3 ns).
    simplicial: Option<Simplicial>,
}

impl std::fmt::Debug for Factor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = match self.kind {
            Kind::Llt { .. } => "LLt",
            Kind::Lu { .. } => "LU",
        };
        let path = if self.simplicial.is_some() {
            ", simplicial sweeps"
        } else {
            ""
        };
        write!(f, "Factor({kind}, n = {}{path})", self.n)
    }
}

fn factor_err(name: &str, e: impl std::fmt::Debug) -> Error {
    Error::Factorisation {
        matrix: name.to_string(),
        reason: format!("{e:?}"),
    }
}

/// From this order on, faer factors and solves on the rayon pool (both cores); below it the
/// threads would cost more than they save.
const PARALLEL_FACTOR_DOFS: usize = 50_000;

/// faer's parallelism for a matrix of order `n`.
fn par_for(n: usize) -> Par {
    if n >= PARALLEL_FACTOR_DOFS {
        Par::rayon(0)
    } else {
        Par::Seq
    }
}

impl Factor {
    /// Sparse Cholesky of a symmetric positive definite matrix (both triangles stored; the lower
    /// one is read). `name` is used in the error when `A` is not numerically SPD.
    pub fn cholesky(a: &SpMat, name: &str) -> Result<Self> {
        check_finite(a, name)?;
        let n = a.nrows();
        let par = par_for(n);
        // A narrow band (1D meshes) factors without fill in its own order; AMD otherwise.
        let identity: Vec<usize> = (0..n).collect();
        let ordering = if bandwidth(a) <= NARROW_BAND {
            SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(&identity, &identity, n))
        } else {
            SymmetricOrdering::Amd
        };
        let symbolic =
            factorize_symbolic_cholesky(a.symbolic(), Side::Lower, ordering, Default::default())
                .map_err(|e| factor_err(name, e))?;
        let mut values = vec![0.0; symbolic.len_val()];
        let req = symbolic
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let mut buffer = MemBuffer::try_new(req).map_err(|e| factor_err(name, e))?;
        symbolic
            .factorize_numeric_llt(
                &mut values,
                a.as_ref(),
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut buffer),
                Default::default(),
            )
            .map_err(|e| Error::Factorisation {
                matrix: name.to_string(),
                reason: format!("not symmetric positive definite ({e:?})"),
            })?;
        let simplicial = match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(l) => {
                let mut path = Simplicial {
                    inv_diag: (0..n).map(|j| 1.0 / values[l.col_ptr()[j]]).collect(),
                    col_ptr: l.col_ptr().to_vec(),
                    row_idx: l.row_idx().to_vec(),
                    perm_fwd: symbolic
                        .perm()
                        .map_or_else(|| (0..n).collect(), |p| p.arrays().0.to_vec()),
                    band: None,
                    perm_is_identity: false,
                    work: vec![0.0; n],
                };
                path.perm_is_identity = path.perm_fwd.iter().enumerate().all(|(i, &p)| i == p);
                path.band = path.band_couplings(&values);
                Some(path)
            }
            SymbolicCholeskyRaw::Supernodal(_) => None,
        };
        Ok(Self {
            kind: Kind::Llt { symbolic, values },
            n,
            buffer,
            simplicial,
        })
    }

    /// Sparse LU with partial pivoting of a square matrix.
    pub fn lu(a: &SpMat, name: &str) -> Result<Self> {
        check_finite(a, name)?;
        let n = a.nrows();
        let par = par_for(n);
        let symbolic = factorize_symbolic_lu(a.symbolic(), Default::default())
            .map_err(|e| factor_err(name, e))?;
        let mut numeric = NumericLu::new();
        let req = symbolic
            .factorize_numeric_lu_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let mut buffer = MemBuffer::try_new(req).map_err(|e| factor_err(name, e))?;
        symbolic
            .factorize_numeric_lu(
                &mut numeric,
                a.as_ref(),
                par,
                MemStack::new(&mut buffer),
                Default::default(),
            )
            .map_err(|e| factor_err(name, e))?;
        Ok(Self {
            kind: Kind::Lu { symbolic, numeric },
            n,
            buffer,
            simplicial: None,
        })
    }

    /// Order of the factored matrix.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Solves `A X = B` in place for `ncols` right-hand sides stored column-major in `x`
    /// (blocked triangular solves; allocates its workspace: for setup, not for time steps).
    pub fn solve_columns(&mut self, x: &mut [f64], ncols: usize) {
        assert_eq!(
            x.len(),
            self.n * ncols,
            "right-hand sides of the wrong length"
        );
        let rhs = MatMut::from_column_major_slice_mut(x, self.n, ncols);
        // Setup-time blocked solves use every core (the per-step solves stay sequential).
        let par = Par::rayon(0);
        let req = match &self.kind {
            Kind::Llt { symbolic, .. } => symbolic.solve_in_place_scratch::<f64>(ncols, par),
            Kind::Lu { symbolic, .. } => symbolic.solve_in_place_scratch::<f64>(ncols, par),
        };
        let mut buffer = MemBuffer::new(req);
        let stack = MemStack::new(&mut buffer);
        match &self.kind {
            Kind::Llt { symbolic, values } => {
                LltRef::new(symbolic, values).solve_in_place_with_conj(Conj::No, rhs, par, stack)
            }
            Kind::Lu { symbolic, numeric } => LuRef::new_unchecked(symbolic, numeric)
                .solve_in_place_with_conj(Conj::No, rhs, par, stack),
        }
    }

    /// Solves `A x = b` in place (`x` holds `b` on entry).
    pub fn solve_in_place(&mut self, x: &mut [f64]) {
        assert_eq!(x.len(), self.n, "right-hand side of the wrong length");
        if let (Some(s), Kind::Llt { values, .. }) = (&mut self.simplicial, &self.kind) {
            s.solve(values, x);
            return;
        }
        let rhs = MatMut::from_column_major_slice_mut(x, self.n, 1);
        let stack = MemStack::new(&mut self.buffer);
        match &self.kind {
            Kind::Llt { symbolic, values } => LltRef::new(symbolic, values)
                .solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack),
            Kind::Lu { symbolic, numeric } => LuRef::new_unchecked(symbolic, numeric)
                .solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack),
        }
    }
}

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
        write!(f, "SingleFactor(LLt, n = {})", self.n)
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

impl Simplicial {
    /// `x ← A⁻¹ x` with `P A Pᵀ = L Lᵀ`: `w = P x`, `L Lᵀ w' = w`, `x = Pᵀ w'`.
    fn solve(&mut self, values: &[f64], x: &mut [f64]) {
        if self.perm_is_identity {
            self.sweeps(values, x);
            return;
        }
        let mut w = std::mem::take(&mut self.work);
        for (wi, &f) in w.iter_mut().zip(&self.perm_fwd) {
            *wi = x[f];
        }
        self.sweeps(values, &mut w);
        for (wi, &f) in w.iter().zip(&self.perm_fwd) {
            x[f] = *wi;
        }
        self.work = w;
    }

    /// The scaled couplings of a bidiagonal L (every column holds the diagonal and at most the
    /// next row: a tridiagonal matrix in a banded order, e.g. 1D P1), or None.
    fn band_couplings(&self, values: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
        let (cp, ri, n) = (&self.col_ptr, &self.row_idx, self.inv_diag.len());
        let sub = |j: usize| match cp[j + 1] - cp[j] {
            1 => Some(0.0),
            2 if ri[cp[j] + 1] == j + 1 => Some(values[cp[j] + 1]),
            _ => None,
        };
        let subs: Vec<f64> = (0..n).map(sub).collect::<Option<_>>()?;
        let fwd = (0..n)
            .map(|j| {
                if j == 0 {
                    0.0
                } else {
                    subs[j - 1] * self.inv_diag[j]
                }
            })
            .collect();
        let bwd = (0..n).map(|j| subs[j] * self.inv_diag[j]).collect();
        Some((fwd, bwd))
    }

    /// Column sweeps `L w = w`, then `Lᵀ w = w` (bidiagonal L: [`Simplicial::band_sweeps`]).
    fn sweeps(&self, values: &[f64], w: &mut [f64]) {
        if let Some(band) = &self.band {
            return self.band_sweeps(band, w);
        }
        let (cp, ri, inv) = (&self.col_ptr, &self.row_idx, &self.inv_diag);
        for j in 0..w.len() {
            let wj = w[j] * inv[j];
            w[j] = wj;
            for p in cp[j] + 1..cp[j + 1] {
                w[ri[p]] -= values[p] * wj;
            }
        }
        for j in (0..w.len()).rev() {
            let mut s = w[j];
            for p in cp[j] + 1..cp[j + 1] {
                s -= values[p] * w[ri[p]];
            }
            w[j] = s * inv[j];
        }
    }

    /// The same sweeps for a bidiagonal L, carrying the previous unknown in a register: one
    /// FMA per unknown on the critical path.
    fn band_sweeps(&self, (fwd, bwd): &(Vec<f64>, Vec<f64>), w: &mut [f64]) {
        let inv = &self.inv_diag;
        let mut prev = 0.0;
        for ((wj, ij), fj) in w.iter_mut().zip(inv).zip(fwd) {
            prev = (*wj * ij) - fj * prev;
            *wj = prev;
        }
        let mut next = 0.0;
        for ((wj, ij), bj) in w.iter_mut().zip(inv).zip(bwd).rev() {
            next = (*wj * ij) - bj * next;
            *wj = next;
        }
    }
}

/// True when `a` has bandwidth at most [`NARROW_BAND`] (1D meshes).
pub fn is_narrow_band(a: &SpMat) -> bool {
    bandwidth(a) <= NARROW_BAND
}

/// Largest bandwidth kept in the natural order by [`Factor::cholesky`].
const NARROW_BAND: usize = 4;

/// `max |i − j|` over the stored entries.
fn bandwidth(a: &SpMat) -> usize {
    triplets(a)
        .map(|(i, j, _)| i.abs_diff(j))
        .max()
        .unwrap_or(0)
}

fn check_finite(a: &SpMat, name: &str) -> Result<()> {
    if a.nrows() != a.ncols() {
        return Err(factor_err(
            name,
            format!("not square: {}x{}", a.nrows(), a.ncols()),
        ));
    }
    if triplets(a).any(|(_, _, v)| !v.is_finite()) {
        return Err(factor_err(name, "matrix has non-finite entries"));
    }
    Ok(())
}

/// Dense copy (tests and small diagnostics only).
pub fn to_dense(a: &SpMat) -> nalgebra::DMatrix<f64> {
    let mut d = nalgebra::DMatrix::zeros(a.nrows(), a.ncols());
    for (i, j, v) in triplets(a) {
        d[(i, j)] += v;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    fn laplacian(n: usize) -> SpMat {
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

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
    }

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

    #[test]
    fn cholesky_and_lu_solve_the_same_system() {
        let a = laplacian(50);
        let x: Vec<f64> = (0..50).map(|i| (i as f64 * 0.37).sin()).collect();
        let b = mul(&a, &x);
        for mut f in [
            Factor::cholesky(&a, "A").unwrap(),
            Factor::lu(&a, "A").unwrap(),
        ] {
            let mut y = b.clone();
            f.solve_in_place(&mut y);
            let err = max_diff(&y, &x);
            assert!(err < 1e-11, "solve error {err}");
        }
    }

    /// A 2D Laplacian on a 12 × 12 grid with scrambled numbering (so that faer's ordering is a
    /// real permutation) plus a small shift: the simplicial sweeps match the exact solution.
    #[test]
    fn simplicial_sweeps_solve_a_permuted_system() {
        let m = 12;
        let n = m * m;
        let id = |i: usize, j: usize| (7 * (i * m + j) + 3) % n; // 7 is invertible mod 144
        let mut t = TripletBuilder::new(n, n);
        for i in 0..m {
            for j in 0..m {
                t.add(id(i, j), id(i, j), 4.1);
                for (a, b) in [(i + 1, j), (i, j + 1)] {
                    if a < m && b < m {
                        t.add(id(i, j), id(a, b), -1.0);
                        t.add(id(a, b), id(i, j), -1.0);
                    }
                }
            }
        }
        let a = t.build().unwrap();
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.61).cos()).collect();
        let mut y = mul(&a, &x);
        let mut f = Factor::cholesky(&a, "A").unwrap();
        assert!(
            f.simplicial.is_some(),
            "expected faer to choose a simplicial factor"
        );
        f.solve_in_place(&mut y);
        let err = max_diff(&y, &x);
        assert!(err < 1e-12, "solve error {err}");
    }

    #[test]
    fn cholesky_rejects_an_indefinite_matrix() {
        let mut t = TripletBuilder::new(2, 2);
        t.add(0, 0, 1.0);
        t.add(1, 1, -1.0);
        let err = Factor::cholesky(&t.build().unwrap(), "K").unwrap_err();
        assert!(
            err.to_string().contains("not symmetric positive definite"),
            "{err}"
        );
    }

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

    /// A symmetric matrix of `nodes` × `nodes` dense b × b blocks on a ring of node couplings.
    fn block_matrix(nodes: usize, b: usize) -> SpMat {
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
        let solve = |threads: usize, block: bool| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut pcg = if block {
                    Pcg::with_block(&a, "A", (0..600).collect()).unwrap()
                } else {
                    Pcg::new(&a, "A").unwrap()
                };
                let mut x = vec![0.0; n];
                let it = pcg.solve(&b, &mut x, &free, (1e-12, 500)).unwrap();
                (it, x)
            })
        };
        for block in [false, true] {
            let ((it1, x1), (it2, x2)) = (solve(1, block), solve(2, block));
            assert_eq!(it1, it2);
            assert!(x1.iter().zip(&x2).all(|(p, q)| p.to_bits() == q.to_bits()));
            let ax = mul(&a, &x1);
            let res = (0..n).filter(|&i| free[i]).map(|i| (ax[i] - b[i]).abs());
            assert!(
                res.fold(0.0, f64::max) < 1e-10,
                "block {block}: {it1} iterations"
            );
        }
    }

    #[test]
    fn block_products_match_the_compressed_columns() {
        for b in [2, 3] {
            let a = block_matrix(29, b);
            let blocks = BlockSym::new(&a).expect("block pattern");
            let x: Vec<f64> = (0..a.nrows()).map(|i| (i as f64 * 0.37).sin()).collect();
            let (mut y, mut z, mut w) =
                (vec![0.0; x.len()], vec![0.0; x.len()], vec![1.0; x.len()]);
            sym_mul(&mut y, &a, &x);
            blocks.mul(&mut z, &x);
            assert!(max_diff(&y, &z) < 1e-12, "b = {b}");
            blocks.apply_serial(&mut z, &x);
            assert!(max_diff(&y, &z) < 1e-12, "b = {b}");
            blocks.mul_add(&mut w, &x, 2.0);
            let expect: Vec<f64> = y.iter().map(|v| 1.0 + 2.0 * v).collect();
            assert!(max_diff(&w, &expect) < 1e-12, "b = {b}");
            let q = quad(&a, &x, &x);
            for form in [QuadraticForm::new(&a), QuadraticForm::Block(blocks.clone())] {
                assert!((form.eval(&x, &mut Vec::new()) - q).abs() < 1e-12 * q.abs());
            }
        }
        assert!(BlockSym::new(&laplacian(9)).is_none(), "scalar pattern");
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

/// A symmetric sparse matrix stored by dense b × b blocks (b = 3 or 2: the node blocks of a
/// vector field numbered node by node), for products at less memory traffic than compressed
/// columns (one 4-byte index per b² values).
///
/// 2 × 2 blocks are all stored and gathered, `(A x)_J = Σ_I A_IJᵀ x_I` (by symmetry), block
/// columns in parallel chunks. 3 × 3 blocks (3D, where the traffic dominates) are stored in the
/// upper triangle only: `(A x)_J = Σ_{I ≤ J} A_IJᵀ x_I + Σ_{K > J} A_JK x_K` is formed block column by block column: each
/// stored block A_IJ (I ≤ J) adds `A_IJᵀ x_I` to `y_J` and, off the diagonal, `A_IJ x_J` to
/// `y_I`. The block columns are cut into [`PARTS`] ranges of equal work, each accumulated in its
/// own full-length buffer (so the scattered additions never race) and the buffers summed in a
/// fixed order: the result does not depend on the number of threads.
#[derive(Debug)]
pub struct BlockSym {
    b: usize,
    /// Only the blocks I ≤ J are stored.
    upper: bool,
    ptr: Vec<usize>,
    idx: Vec<u32>,
    /// Block (I, J), I ≤ J, row-major.
    val: Vec<f64>,
    /// First block column of each part (and the end).
    cuts: Vec<usize>,
    /// One accumulation buffer per part.
    parts: std::sync::Mutex<Vec<Vec<f64>>>,
}

/// Block-column ranges of a [`BlockSym`] product: one per core of the 2-core machines the suite
/// is timed on (each range costs a zeroed buffer of length n and its pass in the sum; 2 instead
/// of 4 saved about 8 % of a CG iteration on hertz3d).
const PARTS: usize = 2;

impl Clone for BlockSym {
    fn clone(&self) -> Self {
        Self {
            b: self.b,
            upper: self.upper,
            ptr: self.ptr.clone(),
            idx: self.idx.clone(),
            val: self.val.clone(),
            cuts: self.cuts.clone(),
            parts: std::sync::Mutex::new(Vec::new()),
        }
    }
}

impl BlockSym {
    /// The block form of `a`, when its pattern is made of aligned b × b blocks for b = 3 or 2.
    pub fn new(a: &SpMat) -> Option<Self> {
        [3, 2].into_iter().find_map(|b| Self::with_block(a, b))
    }

    fn with_block(a: &SpMat, b: usize) -> Option<Self> {
        let upper = b == 3;
        let (cp, ri, v) = csc(a);
        let n = a.ncols();
        if n % b != 0 || a.nrows() != n || u32::try_from(n / b).is_err() {
            return None;
        }
        let mut ptr = vec![0];
        let (mut idx, mut val) = (Vec::new(), Vec::new());
        for jb in 0..n / b {
            let rows = &ri[cp[b * jb]..cp[b * jb + 1]];
            if rows.len() % b != 0 {
                return None;
            }
            for c in 1..b {
                if ri[cp[b * jb + c]..cp[b * jb + c + 1]] != *rows {
                    return None;
                }
            }
            for (k, block) in rows.chunks_exact(b).enumerate() {
                if block[0] % b != 0 || block.iter().enumerate().any(|(r, &i)| i != block[0] + r) {
                    return None;
                }
                if upper && block[0] / b > jb {
                    continue;
                }
                idx.push((block[0] / b) as u32);
                for r in 0..b {
                    for c in 0..b {
                        val.push(v[cp[b * jb + c] + b * k + r]);
                    }
                }
            }
            ptr.push(idx.len());
        }
        let blocks = idx.len();
        let cuts = (0..=PARTS)
            .map(|p| ptr.partition_point(|&q| q < blocks * p / PARTS).min(n / b))
            .collect();
        Some(Self {
            b,
            upper,
            ptr,
            idx,
            val,
            cuts,
            parts: std::sync::Mutex::new(Vec::new()),
        })
    }

    /// Size b of the blocks.
    pub fn block_size(&self) -> usize {
        self.b
    }

    /// `y = A x`, the parts in parallel.
    pub fn mul(&self, y: &mut [f64], x: &[f64]) {
        self.apply(y, x, |yi, v| *yi = v, true);
    }

    /// `y += alpha · A x`.
    pub fn mul_add(&self, y: &mut [f64], x: &[f64], alpha: f64) {
        self.apply(y, x, |yi, v| *yi += alpha * v, true);
    }

    /// `y = A x` on the calling thread (beside the time loop, on the sampling thread).
    pub fn apply_serial(&self, y: &mut [f64], x: &[f64]) {
        self.apply(y, x, |yi, v| *yi = v, false);
    }

    fn apply(&self, y: &mut [f64], x: &[f64], f: impl Fn(&mut f64, f64) + Sync, parallel: bool) {
        use rayon::prelude::*;
        if !self.upper {
            let chunk = |(ch, chunk): (usize, &mut [f64])| {
                for (k, out) in chunk.chunks_exact_mut(2).enumerate() {
                    let jb = ch * CHUNK + k;
                    let mut acc = [0.0; 2];
                    for q in self.ptr[jb]..self.ptr[jb + 1] {
                        let i = self.idx[q] as usize * 2;
                        let blk = &self.val[q * 4..q * 4 + 4];
                        acc[0] += blk[0] * x[i] + blk[2] * x[i + 1];
                        acc[1] += blk[1] * x[i] + blk[3] * x[i + 1];
                    }
                    f(&mut out[0], acc[0]);
                    f(&mut out[1], acc[1]);
                }
            };
            if parallel {
                y.par_chunks_mut(CHUNK * 2).enumerate().for_each(chunk);
            } else {
                y.chunks_mut(CHUNK * 2).enumerate().for_each(chunk);
            }
            return;
        }
        let parts = self.upper_parts(x, parallel);
        for (i, yi) in y.iter_mut().enumerate() {
            f(yi, Self::sum_parts(&parts, i));
        }
    }

    /// `y_i = free_i (A x)_i` (0 where not free), returning `Σ_i x_i y_i`: the masked product
    /// of CG and its curvature `xᵀ Π A x` in one pass over `y`, on the rayon pool.
    pub fn mul_masked_dot(&self, y: &mut [f64], x: &[f64], free: &[bool]) -> f64 {
        if !self.upper {
            self.mul(y, x);
            return masked_dot(y, x, free, |_, yi| yi);
        }
        let parts = self.upper_parts(x, true);
        masked_dot(y, x, free, |i, _| Self::sum_parts(&parts, i))
    }

    /// The [`PARTS`] partial products by 3 × 3 upper blocks (each in its own buffer).
    fn upper_parts(&self, x: &[f64], parallel: bool) -> std::sync::MutexGuard<'_, Vec<Vec<f64>>> {
        use rayon::prelude::*;
        let mut parts = self.parts.lock().unwrap_or_else(|e| e.into_inner());
        parts.resize_with(PARTS, Vec::new);
        let part = |(p, z): (usize, &mut Vec<f64>)| {
            z.clear();
            z.resize(x.len(), 0.0);
            self.upper_part(p, x, z);
        };
        if parallel {
            parts.par_iter_mut().enumerate().for_each(part);
        } else {
            parts.iter_mut().enumerate().for_each(part);
        }
        parts
    }

    /// `(A x)_i` from the partial products, added in a fixed order.
    #[inline(always)]
    fn sum_parts(parts: &[Vec<f64>], i: usize) -> f64 {
        parts[0][i] + parts[1][i]
    }

    /// Part `p` of the product by 3 × 3 upper blocks, accumulated in `z`.
    fn upper_part(&self, p: usize, x: &[f64], z: &mut [f64]) {
        const B: usize = 3;
        for jb in self.cuts[p]..self.cuts[p + 1] {
            let j = jb * B;
            let xj: [f64; B] = std::array::from_fn(|c| x[j + c]);
            let mut acc = [0.0; B];
            for k in self.ptr[jb]..self.ptr[jb + 1] {
                let i = self.idx[k] as usize * B;
                let blk = &self.val[k * B * B..(k + 1) * B * B];
                let xi = &x[i..i + B];
                for (c, a) in acc.iter_mut().enumerate() {
                    *a += (0..B).map(|r| blk[r * B + c] * xi[r]).sum::<f64>();
                }
                if i != j {
                    for r in 0..B {
                        z[i + r] += (0..B).map(|c| blk[r * B + c] * xj[c]).sum::<f64>();
                    }
                }
            }
            for c in 0..B {
                z[j + c] += acc[c];
            }
        }
    }
}
