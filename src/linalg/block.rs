//! Symmetric sparse matrices stored by dense node blocks, for products at less memory traffic.

mod sweeps;

pub use sweeps::Halves;

use super::products::CHUNK;
use super::sparse::{csc, SpMat};
use super::vectors::masked_dot;

/// A symmetric sparse matrix stored by dense b × b blocks (b = 3 or 2: the node blocks of a
/// vector field numbered node by node), for products at less memory traffic than compressed
/// columns (one 4-byte index per b² values). The values are `f64`, or `f32` for the fast products
/// of CG ([`BlockSym::rounded`], with the rounding errors kept apart for exact products,
/// [`BlockSym::mul_exact`]).
///
/// 2 × 2 blocks are all stored and gathered, `(A x)_J = Σ_I A_IJᵀ x_I` (by symmetry), block
/// columns in parallel chunks. 3 × 3 blocks (3D, where the traffic dominates) are stored in the
/// upper triangle only: `(A x)_J = Σ_{I ≤ J} A_IJᵀ x_I + Σ_{K > J} A_JK x_K` is formed block column by block column: each
/// stored block A_IJ (I ≤ J) adds `A_IJᵀ x_I` to `y_J` and, off the diagonal, `A_IJ x_J` to
/// `y_I`. The block columns are cut into [`PARTS`] ranges of equal work, each accumulated in its
/// own full-length buffer (so the scattered additions never race; [`LANES`] entries per node)
/// and the buffers summed in a fixed order: the result does not depend on the number of threads.
#[derive(Debug)]
pub struct BlockSym<T = f64> {
    b: usize,
    /// Only the blocks I ≤ J are stored.
    upper: bool,
    ptr: Vec<usize>,
    idx: Vec<u32>,
    /// Block (I, J) (I ≤ J for 3 × 3 blocks, stored column-major; 2 × 2 row-major).
    val: Vec<T>,
    /// For `f32` values, `A − val` rounded to `f32` (the exact value to 2⁻⁴⁸ relative).
    rest: Vec<f32>,
    /// First block column of each part (and the end).
    cuts: Vec<usize>,
    /// One accumulation buffer per part.
    parts: std::sync::Mutex<Vec<Vec<f64>>>,
}

/// Block-column ranges of a [`BlockSym`] product: one per core of the 2-core machines the suite
/// is timed on (each range costs a zeroed buffer of length n and its pass in the sum; 2 instead
/// of 4 saved about 8 % of a CG iteration on hertz3d).
const PARTS: usize = 2;

/// A stored value of a [`BlockSym`].
pub trait BlockValue: Copy + Send + Sync + std::fmt::Debug {
    /// The value in double precision.
    fn get(self) -> f64;

    /// The values as single-precision numbers, if they are (the vector kernel's input).
    fn singles(values: &[Self]) -> Option<&[f32]> {
        let _ = values;
        None
    }

    /// The values as double-precision numbers, if they are (the vector kernel's input).
    fn doubles(values: &[Self]) -> Option<&[f64]> {
        let _ = values;
        None
    }
}

impl BlockValue for f64 {
    #[inline(always)]
    fn get(self) -> f64 {
        self
    }

    fn doubles(values: &[Self]) -> Option<&[f64]> {
        Some(values)
    }
}

impl BlockValue for f32 {
    #[inline(always)]
    fn get(self) -> f64 {
        f64::from(self)
    }

    fn singles(values: &[Self]) -> Option<&[f32]> {
        Some(values)
    }
}

/// Which values a product uses: the stored ones, or (single precision) the stored ones plus
/// their rounding errors.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Values {
    Stored,
    Exact,
}

/// Entries per node in the partial products of 3 × 3 blocks: the node's three and a pad, so that
/// a node's entries are one 4-lane vector, loaded and stored whole.
pub const LANES: usize = 4;

/// How far ahead (in values: 512 single-precision values, 2 KiB, 57 blocks; 4 KiB of
/// double-precision values, not tuned) the vector kernel asks for the values it will read.
/// Without it the product of the 10⁶-dof sphere's step matrix streamed its 175 MB of values at
/// 12 GB/s on two cores; 256, 512 and 1 024 gave 9.4, 8.9 and 9.1 ms against 12.6 ms (best of
/// 7 × 5 products, 1 040 163 dofs).
const PREFETCH: usize = 512;

/// `(l₀ + l₁) + (l₂ + l₃)` of a 4-lane vector.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn lane_sum(a: std::arch::x86_64::__m256d) -> f64 {
    let mut l = [0.0; 4];
    // SAFETY: l holds four doubles.
    unsafe { std::arch::x86_64::_mm256_storeu_pd(l.as_mut_ptr(), a) };
    (l[0] + l[1]) + (l[2] + l[3])
}

impl<T: BlockValue> Clone for BlockSym<T> {
    fn clone(&self) -> Self {
        Self {
            b: self.b,
            upper: self.upper,
            ptr: self.ptr.clone(),
            idx: self.idx.clone(),
            val: self.val.clone(),
            rest: self.rest.clone(),
            cuts: self.cuts.clone(),
            parts: std::sync::Mutex::new(Vec::new()),
        }
    }
}

/// First block column of each of the [`PARTS`] of equal work (and the end), from the block
/// columns' starts `ptr`.
fn cuts(ptr: &[usize]) -> Vec<usize> {
    super::sparse::balanced_cuts(ptr, PARTS)
}

/// Dofs per node of the square `a` numbered node by node (a vector field in 2D or 3D): the b ∈
/// {3, 2} for which its pattern is made of aligned b × b blocks (every column of a node has the
/// rows of the node's first, in whole nodes), 1 when neither is.
pub fn node_size(a: &SpMat) -> usize {
    use rayon::prelude::*;
    let (cp, ri, _) = csc(a);
    let n = a.ncols();
    let aligned = |b: usize| {
        let nodes = |jb: usize| {
            let rows = &ri[cp[b * jb]..cp[b * jb + 1]];
            let same = (1..b).all(|c| ri[cp[b * jb + c]..cp[b * jb + c + 1]] == *rows);
            let whole = |block: &[usize]| {
                block[0].is_multiple_of(b)
                    && block.iter().enumerate().all(|(r, &i)| i == block[0] + r)
            };
            same && rows.len() % b == 0 && rows.chunks_exact(b).all(whole)
        };
        n.is_multiple_of(b) && u32::try_from(n / b).is_ok() && (0..n / b).into_par_iter().all(nodes)
    };
    if a.nrows() != n {
        return 1;
    }
    [3, 2].into_iter().find(|&b| aligned(b)).unwrap_or(1)
}

/// Block columns copied by one task of [`BlockSym::new`].
const BLOCK_CHUNK: usize = 2048;

impl BlockSym {
    /// The block form of `a`, when its pattern is made of aligned b × b blocks for b = 3 or 2.
    pub fn new(a: &SpMat) -> Option<Self> {
        let b = node_size(a);
        (b > 1).then(|| Self::with_block(a, b))
    }

    /// The blocks of `a`, whose pattern is made of aligned b × b blocks ([`node_size`]): their
    /// rows counted, then the values copied in parallel by chunks of block columns.
    fn with_block(a: &SpMat, b: usize) -> Self {
        use rayon::prelude::*;
        let upper = b == 3;
        let (cp, ri, v) = csc(a);
        let n = a.ncols();
        // The first row of each stored block of block column jb.
        let firsts = |jb: usize| {
            let rows = ri[cp[b * jb]..cp[b * jb + 1]].chunks_exact(b);
            rows.map(|block| block[0])
                .enumerate()
                .filter(move |(_, r)| !upper || r / b <= jb)
        };
        let mut ptr = vec![0];
        for jb in 0..n / b {
            ptr.push(ptr[jb] + firsts(jb).count());
        }
        // The vector kernel reads a block's last column as four values: one zero after them.
        let (mut idx, mut val) = (vec![0; ptr[n / b]], vec![0.0; b * b * ptr[n / b] + 1]);
        let chunks = super::sparse::column_cuts(n / b, BLOCK_CHUNK);
        let idxs = super::sparse::split_columns(&chunks, |jb| ptr[jb], &mut idx);
        let vals = super::sparse::split_columns(&chunks, |jb| b * b * ptr[jb], &mut val);
        (chunks.par_windows(2).zip(idxs).zip(vals)).for_each(|((w, idx), val)| {
            let mut at = 0;
            for jb in w[0]..w[1] {
                for (k, row) in firsts(jb) {
                    idx[at] = (row / b) as u32;
                    // 2 × 2 blocks row-major, 3 × 3 column-major ([`BlockSym::upper_part_any`]).
                    for e in 0..b * b {
                        let (r, c) = if upper {
                            (e % b, e / b)
                        } else {
                            (e / b, e % b)
                        };
                        val[b * b * at + e] = v[cp[b * jb + c] + b * k + r];
                    }
                    at += 1;
                }
            }
        });
        let cuts = cuts(&ptr);
        Self {
            b,
            upper,
            ptr,
            idx,
            val,
            rest: Vec::new(),
            cuts,
            parts: std::sync::Mutex::new(Vec::new()),
        }
    }

    /// The same matrix with its values rounded to single precision (half the memory traffic of
    /// a product, for the fast products of CG) and the rounding errors kept apart in single
    /// precision, for [`BlockSym::mul_exact`]: the same memory as the double-precision values.
    ///
    /// Both keep the zero that follows the values ([`BlockSym::new`]).
    pub fn rounded(self) -> BlockSym<f32> {
        use rayon::prelude::*;
        let val: Vec<f32> = self.val.par_iter().map(|&v| v as f32).collect();
        let rest: Vec<f32> = (self.val.par_iter().zip(&val))
            .map(|(&v, &h)| (v - f64::from(h)) as f32)
            .collect();
        BlockSym {
            b: self.b,
            upper: self.upper,
            ptr: self.ptr,
            idx: self.idx,
            val,
            rest,
            cuts: self.cuts,
            parts: std::sync::Mutex::new(Vec::new()),
        }
    }
}

impl BlockSym<f32> {
    /// `y = A x` with the values restored from their single-precision parts (`val + rest`, the
    /// matrix to 2⁻⁴⁸ relative), on the rayon pool.
    pub fn mul_exact(&self, y: &mut [f64], x: &[f64]) {
        self.apply(y, x, Values::Exact, (|yi: &mut f64, v: f64| *yi = v, true));
    }
}

impl BlockSym<f32> {
    /// The diagonal block of node J (its stored values), row-major.
    pub fn diagonal_block(&self, jb: usize) -> Option<[[f32; 3]; 3]> {
        let k = (self.ptr[jb]..self.ptr[jb + 1]).find(|&k| self.idx[k] as usize == jb)?;
        Some(std::array::from_fn(|r| {
            std::array::from_fn(|c| self.val[9 * k + 3 * c + r])
        }))
    }

    /// The number of stored values.
    pub fn stored_values(&self) -> usize {
        self.val.len()
    }

    /// Whether the blocks are the upper triangle of 3 × 3 blocks (what the sweeps need).
    pub fn is_upper(&self) -> bool {
        self.upper
    }
}

impl<T: BlockValue> BlockSym<T> {
    /// Size b of the blocks.
    pub fn block_size(&self) -> usize {
        self.b
    }

    /// The value k: stored, or with its rounding error.
    #[inline(always)]
    fn value(&self, k: usize, values: Values) -> f64 {
        match values {
            Values::Exact if !self.rest.is_empty() => self.val[k].get() + f64::from(self.rest[k]),
            _ => self.val[k].get(),
        }
    }

    /// `y = A x`, the parts in parallel.
    pub fn mul(&self, y: &mut [f64], x: &[f64]) {
        self.apply(y, x, Values::Stored, (|yi, v| *yi = v, true));
    }

    /// `y += alpha · A x`.
    pub fn mul_add(&self, y: &mut [f64], x: &[f64], alpha: f64) {
        self.apply(y, x, Values::Stored, (|yi, v| *yi += alpha * v, true));
    }

    /// `y = A x` on the calling thread (beside the time loop, on the sampling thread).
    pub fn apply_serial(&self, y: &mut [f64], x: &[f64]) {
        self.apply(y, x, Values::Stored, (|yi, v| *yi = v, false));
    }

    /// `f(y_i, (A x)_i)` for every i, with the `values`.
    fn apply(
        &self,
        y: &mut [f64],
        x: &[f64],
        values: Values,
        (f, parallel): (impl Fn(&mut f64, f64) + Sync, bool),
    ) {
        use rayon::prelude::*;
        if !self.upper {
            let value = |k: usize| self.value(k, values);
            let chunk = |(ch, chunk): (usize, &mut [f64])| {
                for (k, out) in chunk.chunks_exact_mut(2).enumerate() {
                    let jb = ch * CHUNK + k;
                    let mut acc = [0.0; 2];
                    for q in self.ptr[jb]..self.ptr[jb + 1] {
                        let i = self.idx[q] as usize * 2;
                        let blk: [f64; 4] = std::array::from_fn(|e| value(q * 4 + e));
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
        let parts = self.upper_parts(x, values, parallel);
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
        let parts = self.upper_parts(x, Values::Stored, true);
        masked_dot(y, x, free, |i, _| Self::sum_parts(&parts, i))
    }

    /// The [`PARTS`] partial products by 3 × 3 upper blocks (each in its own buffer, [`LANES`]
    /// entries per node).
    fn upper_parts(
        &self,
        x: &[f64],
        values: Values,
        parallel: bool,
    ) -> std::sync::MutexGuard<'_, Vec<Vec<f64>>> {
        use rayon::prelude::*;
        let mut parts = self.parts.lock().unwrap_or_else(|e| e.into_inner());
        parts.resize_with(PARTS, Vec::new);
        let part = |(p, z): (usize, &mut Vec<f64>)| {
            z.clear();
            z.resize(x.len() / 3 * LANES, 0.0);
            self.upper_part(p, x, z, values);
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
        let k = i / 3 * LANES + i % 3;
        parts[0][k] + parts[1][k]
    }

    /// Part `p` of the product by 3 × 3 upper blocks, accumulated in `z`: by 4-lane vectors
    /// where the processor has AVX2 (single- or double-precision values), by
    /// [`BlockSym::upper_part_any`] otherwise (the same operations in the same order, so the
    /// same result).
    fn upper_part(&self, p: usize, x: &[f64], z: &mut [f64], values: Values) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            if let Some(val) = T::singles(&self.val) {
                let rest = (values == Values::Exact).then_some(&self.rest[..]);
                // SAFETY: the processor supports AVX2, checked on the line above.
                return unsafe { self.upper_part_avx2(p, x, z, (val, rest)) };
            }
            if let Some(val) = T::doubles(&self.val) {
                // SAFETY: as above.
                return unsafe { self.upper_part_avx2_doubles(p, x, z, val) };
            }
        }
        self.upper_part_any(p, x, z, |k| self.value(k, values));
    }

    /// [`BlockSym::upper_part_any`] for single-precision values (`val`, with the rounding errors
    /// `rest` added for an exact product) in AVX2 vectors of four doubles
    /// ([`BlockSym::upper_part_vectors`]): a block's column is one 4-value load converted to
    /// double.
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn upper_part_avx2(
        &self,
        p: usize,
        x: &[f64],
        z: &mut [f64],
        (val, rest): (&[f32], Option<&[f32]>),
    ) {
        use std::arch::x86_64::*;
        // A block's last column reads one value past it (the zero after the values: `with_block`
        // leaves it, `rounded` keeps it, `permuted` adds its own).
        assert!(val.len() > 9 * self.idx.len() && rest.is_none_or(|r| r.len() == val.len()));
        let column = |o: usize| {
            // SAFETY: o + 3 < val.len() (the assertion above).
            let v = unsafe { _mm256_cvtps_pd(_mm_loadu_ps(val.as_ptr().add(o))) };
            match rest {
                None => v,
                // SAFETY: rest has val's length.
                Some(r) => unsafe {
                    _mm256_add_pd(v, _mm256_cvtps_pd(_mm_loadu_ps(r.as_ptr().add(o))))
                },
            }
        };
        let prefetch = |o: usize| {
            _mm_prefetch::<_MM_HINT_T0>(val.as_ptr().wrapping_add(o + PREFETCH).cast());
            if let Some(r) = rest {
                _mm_prefetch::<_MM_HINT_T0>(r.as_ptr().wrapping_add(o + PREFETCH).cast());
            }
        };
        // SAFETY: the processor supports AVX2 (this function's contract).
        unsafe { self.upper_part_vectors(p, x, z, (column, prefetch)) }
    }

    /// [`BlockSym::upper_part_any`] for double-precision values in AVX2 vectors
    /// ([`BlockSym::upper_part_vectors`]): a block's column is one 4-value load (the energies'
    /// forms, on the sampling thread: hertz3d n = 44, M's and K's 2 × 44M values, 140 ms a
    /// sample by `upper_part_any`).
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn upper_part_avx2_doubles(&self, p: usize, x: &[f64], z: &mut [f64], val: &[f64]) {
        use std::arch::x86_64::*;
        // A block's last column reads one value past it (the pad of `with_block`).
        assert!(val.len() > 9 * self.idx.len());
        // SAFETY: o + 3 < val.len() (the assertion above).
        let column = |o: usize| unsafe { _mm256_loadu_pd(val.as_ptr().add(o)) };
        let prefetch = |o: usize| {
            _mm_prefetch::<_MM_HINT_T0>(val.as_ptr().wrapping_add(o + PREFETCH).cast());
        };
        // SAFETY: the processor supports AVX2 (this function's contract).
        unsafe { self.upper_part_vectors(p, x, z, (column, prefetch)) }
    }

    /// The body of the vector kernels: `column(o)` is the block column at value o in four lanes,
    /// whose fourth lane (the next column's first value) meets the zero of `x_I`'s fourth lane
    /// in `A_IJᵀ x_I` and lands in `z_I`'s pad in `A_IJ x_J`; `z_I` is one load and one store;
    /// `prefetch(o)` asks for the values [`PREFETCH`] ahead. The same operations in the same
    /// order as [`BlockSym::upper_part_any`] (no fused multiply–add; the fourth lanes of the
    /// sums stay +0 for finite values): the same result.
    ///
    /// # Safety
    /// The processor must support AVX2, and `column(o)` read inside the values for every block
    /// o = 9 k + 3 c.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn upper_part_vectors(
        &self,
        p: usize,
        x: &[f64],
        z: &mut [f64],
        (column, prefetch): (impl Fn(usize) -> std::arch::x86_64::__m256d, impl Fn(usize)),
    ) {
        use std::arch::x86_64::*;
        const B: usize = 3;
        let nodes = x.len() / B;
        // The bounds every unchecked access below relies on: `x_I` four entries unless I is the
        // last node, `z_I` four (I < nodes: the block rows of a matrix of order 3 nodes,
        // `with_block`).
        assert!(z.len() == nodes * LANES && self.ptr.len() == nodes + 1);
        debug_assert!(self.idx.iter().all(|&i| (i as usize) < nodes));
        let (xp, zp, zero) = (x.as_ptr(), z.as_mut_ptr(), _mm256_setzero_pd());
        for jb in self.cuts[p]..self.cuts[p + 1] {
            let xj = [0, 1, 2].map(|c| _mm256_broadcast_sd(&x[B * jb + c]));
            let mut acc = [zero; B];
            for k in self.ptr[jb]..self.ptr[jb + 1] {
                let (ib, o) = (self.idx[k] as usize, k * B * B);
                prefetch(o);
                let cols = [column(o), column(o + B), column(o + 2 * B)];
                let xi = if ib + 1 < nodes {
                    // SAFETY: B ib + 3 < x.len() when I is not the last node.
                    let x4 = unsafe { _mm256_loadu_pd(xp.add(B * ib)) };
                    _mm256_blend_pd::<0b1000>(x4, zero)
                } else {
                    _mm256_set_pd(0.0, x[B * ib + 2], x[B * ib + 1], x[B * ib])
                };
                for (a, col) in acc.iter_mut().zip(&cols) {
                    *a = _mm256_add_pd(*a, _mm256_mul_pd(*col, xi));
                }
                if ib != jb {
                    let c01 =
                        _mm256_add_pd(_mm256_mul_pd(cols[0], xj[0]), _mm256_mul_pd(cols[1], xj[1]));
                    let t = _mm256_add_pd(c01, _mm256_mul_pd(cols[2], xj[2]));
                    // SAFETY: LANES ib + 4 <= z.len().
                    unsafe {
                        let zi = zp.add(LANES * ib);
                        _mm256_storeu_pd(zi, _mm256_add_pd(_mm256_loadu_pd(zi), t));
                    }
                }
            }
            for (c, a) in acc.iter().enumerate() {
                let mut l = [0.0; 4];
                // SAFETY: l holds four doubles.
                unsafe { _mm256_storeu_pd(l.as_mut_ptr(), *a) };
                z[LANES * jb + c] += (l[0] + l[1]) + (l[2] + l[3]);
            }
        }
    }

    /// [`BlockSym::upper_part`] for any instruction set. Each stored block A_IJ (column-major)
    /// is read as three columns `a_c` padded to 4 lanes with a zero; `A_IJᵀ x_I` accumulates
    /// `a_c ⊙ x_I` lane by lane in three 4-lane sums, added across lanes once per block column
    /// J, and `A_IJ x_J = Σ_c a_c x_Jc` is added to `z_I` (three lanes: a wider store would
    /// overlap the next node's and stall the loads that follow it).
    #[inline(always)]
    fn upper_part_any(&self, p: usize, x: &[f64], z: &mut [f64], value: impl Fn(usize) -> f64) {
        const B: usize = 3;
        let (xs, zs) = (x.as_chunks::<B>().0, z.as_chunks_mut::<LANES>().0);
        for jb in self.cuts[p]..self.cuts[p + 1] {
            let xj = xs[jb];
            let mut acc = [[0.0; 4]; B];
            for k in self.ptr[jb]..self.ptr[jb + 1] {
                let ib = self.idx[k] as usize;
                let col = |c: usize| {
                    let o = k * B * B + c * B;
                    [value(o), value(o + 1), value(o + 2), 0.0]
                };
                let cols = [col(0), col(1), col(2)];
                let xi = xs[ib];
                let xi = [xi[0], xi[1], xi[2], 0.0];
                for (a, col) in acc.iter_mut().zip(&cols) {
                    for l in 0..4 {
                        a[l] += col[l] * xi[l];
                    }
                }
                if ib != jb {
                    for (r, zr) in zs[ib][..B].iter_mut().enumerate() {
                        *zr += (cols[0][r] * xj[0] + cols[1][r] * xj[1]) + cols[2][r] * xj[2];
                    }
                }
            }
            for (zc, a) in zs[jb][..B].iter_mut().zip(&acc) {
                *zc += (a[0] + a[1]) + (a[2] + a[3]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::{block_matrix, laplacian, max_diff};
    use crate::linalg::{quad, sym_mul, QuadraticForm};

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
            // Rounded to single precision: the fast product to about 2⁻²⁴, the exact one (with
            // the rounding errors kept apart) to round-off.
            let rounded = blocks.clone().rounded();
            rounded.mul(&mut z, &x);
            let fast = max_diff(&y, &z);
            assert!(fast > 1e-12 && fast < 1e-6, "b = {b}: {fast:.3e}");
            rounded.mul_exact(&mut z, &x);
            assert!(max_diff(&y, &z) < 1e-12, "b = {b}");
            let q = quad(&a, &x, &x);
            for form in [QuadraticForm::new(&a), QuadraticForm::Block(blocks.clone())] {
                assert!((form.eval(&x, &mut Vec::new()) - q).abs() < 1e-12 * q.abs());
            }
        }
        assert!(BlockSym::new(&laplacian(9)).is_none(), "scalar pattern");
    }

    /// The vector kernels of 3 × 3 blocks give the bits of the kernel for any instruction set:
    /// single precision with the stored values and with their rounding errors added, and double
    /// precision (29 nodes: the last one's x is read without its neighbour's). On a processor
    /// without AVX2 there is nothing to compare.
    #[test]
    fn the_vector_kernels_give_the_same_bits() {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let a = BlockSym::new(&block_matrix(29, 3)).expect("block pattern");
            let x: Vec<f64> = (0..a.ptr.len() * 3 - 3)
                .map(|i| (i as f64 * 0.37).sin())
                .collect();
            // SAFETY: the processor supports AVX2 (checked above).
            let doubles = |p: usize, z: &mut [f64]| unsafe {
                a.upper_part_avx2_doubles(p, &x, z, &a.val);
            };
            same_bits(&a, &x, Values::Stored, doubles);
            let a = a.rounded();
            for values in [Values::Stored, Values::Exact] {
                let rest = (values == Values::Exact).then_some(&a.rest[..]);
                // SAFETY: as above.
                let singles = |p: usize, z: &mut [f64]| unsafe {
                    a.upper_part_avx2(p, &x, z, (&a.val, rest))
                };
                same_bits(&a, &x, values, singles);
            }
        }
    }

    /// `kernel(p, z)` and `upper_part_any` give the same bits on every part.
    fn same_bits<T: BlockValue>(
        a: &BlockSym<T>,
        x: &[f64],
        values: Values,
        kernel: impl Fn(usize, &mut [f64]),
    ) {
        for p in 0..PARTS {
            let mut z = vec![vec![0.0; x.len() / 3 * LANES]; 2];
            kernel(p, &mut z[0]);
            a.upper_part_any(p, x, &mut z[1], |k| a.value(k, values));
            for i in 0..x.len() {
                let k = i / 3 * LANES + i % 3;
                assert_eq!(z[0][k].to_bits(), z[1][k].to_bits(), "part {p}, entry {i}");
            }
        }
    }
}
