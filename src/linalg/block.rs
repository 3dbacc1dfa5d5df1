//! Symmetric sparse matrices stored by dense node blocks, for products at less memory traffic.

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
/// own full-length buffer (so the scattered additions never race) and the buffers summed in a
/// fixed order: the result does not depend on the number of threads.
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
}

impl BlockValue for f64 {
    #[inline(always)]
    fn get(self) -> f64 {
        self
    }
}

impl BlockValue for f32 {
    #[inline(always)]
    fn get(self) -> f64 {
        f64::from(self)
    }
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

impl BlockSym {
    /// The block form of `a`, when its pattern is made of aligned b × b blocks for b = 3 or 2.
    pub fn new(a: &SpMat) -> Option<Self> {
        [3, 2].into_iter().find_map(|b| Self::with_block(a, b))
    }

    fn with_block(a: &SpMat, b: usize) -> Option<Self> {
        let upper = b == 3;
        let (cp, ri, v) = csc(a);
        let n = a.ncols();
        if !n.is_multiple_of(b) || a.nrows() != n || u32::try_from(n / b).is_err() {
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
                // 2 × 2 blocks row-major, 3 × 3 column-major ([`BlockSym::upper_part_any`]).
                for e in 0..b * b {
                    let (r, c) = if upper {
                        (e % b, e / b)
                    } else {
                        (e / b, e % b)
                    };
                    val.push(v[cp[b * jb + c] + b * k + r]);
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
            rest: Vec::new(),
            cuts,
            parts: std::sync::Mutex::new(Vec::new()),
        })
    }

    /// The same matrix with its values rounded to single precision (half the memory traffic of
    /// a product, for the fast products of CG) and the rounding errors kept apart in single
    /// precision, for [`BlockSym::mul_exact`]: the same memory as the double-precision values.
    pub fn rounded(self) -> BlockSym<f32> {
        let val: Vec<f32> = self.val.iter().map(|&v| v as f32).collect();
        let rest = self
            .val
            .iter()
            .zip(&val)
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
        let value = |k: usize| f64::from(self.val[k]) + f64::from(self.rest[k]);
        self.apply(y, x, value, (|yi: &mut f64, v: f64| *yi = v, true));
    }
}

impl<T: BlockValue> BlockSym<T> {
    /// Size b of the blocks.
    pub fn block_size(&self) -> usize {
        self.b
    }

    /// The stored value k.
    #[inline(always)]
    fn value(&self, k: usize) -> f64 {
        self.val[k].get()
    }

    /// `y = A x`, the parts in parallel.
    pub fn mul(&self, y: &mut [f64], x: &[f64]) {
        self.apply(y, x, |k| self.value(k), (|yi, v| *yi = v, true));
    }

    /// `y += alpha · A x`.
    pub fn mul_add(&self, y: &mut [f64], x: &[f64], alpha: f64) {
        self.apply(y, x, |k| self.value(k), (|yi, v| *yi += alpha * v, true));
    }

    /// `y = A x` on the calling thread (beside the time loop, on the sampling thread).
    pub fn apply_serial(&self, y: &mut [f64], x: &[f64]) {
        self.apply(y, x, |k| self.value(k), (|yi, v| *yi = v, false));
    }

    /// `f(y_i, (A x)_i)` for every i, with the stored value k read as `value(k)`.
    fn apply(
        &self,
        y: &mut [f64],
        x: &[f64],
        value: impl Fn(usize) -> f64 + Sync,
        (f, parallel): (impl Fn(&mut f64, f64) + Sync, bool),
    ) {
        use rayon::prelude::*;
        if !self.upper {
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
        let parts = self.upper_parts(x, &value, parallel);
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
        let parts = self.upper_parts(x, &|k| self.value(k), true);
        masked_dot(y, x, free, |i, _| Self::sum_parts(&parts, i))
    }

    /// The [`PARTS`] partial products by 3 × 3 upper blocks (each in its own buffer).
    fn upper_parts(
        &self,
        x: &[f64],
        value: &(impl Fn(usize) -> f64 + Sync),
        parallel: bool,
    ) -> std::sync::MutexGuard<'_, Vec<Vec<f64>>> {
        use rayon::prelude::*;
        let mut parts = self.parts.lock().unwrap_or_else(|e| e.into_inner());
        parts.resize_with(PARTS, Vec::new);
        let part = |(p, z): (usize, &mut Vec<f64>)| {
            z.clear();
            z.resize(x.len(), 0.0);
            self.upper_part(p, x, z, value);
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

    /// Part `p` of the product by 3 × 3 upper blocks, accumulated in `z`: compiled for AVX2 where
    /// the processor has it (the same operations in the same order, so the same result).
    fn upper_part(&self, p: usize, x: &[f64], z: &mut [f64], value: &impl Fn(usize) -> f64) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor supports AVX2, checked on the line above.
            return unsafe { self.upper_part_avx2(p, x, z, value) };
        }
        self.upper_part_any(p, x, z, value);
    }

    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn upper_part_avx2(
        &self,
        p: usize,
        x: &[f64],
        z: &mut [f64],
        value: &impl Fn(usize) -> f64,
    ) {
        self.upper_part_any(p, x, z, value);
    }

    /// [`BlockSym::upper_part`] for any instruction set. Each stored block A_IJ (column-major)
    /// is read as three columns `a_c` padded to 4 lanes with a zero; `A_IJᵀ x_I` accumulates
    /// `a_c ⊙ x_I` lane by lane in three 4-lane sums, added across lanes once per block column
    /// J, and `A_IJ x_J = Σ_c a_c x_Jc` is added to `z_I` (three lanes: a wider store would
    /// overlap the next node's and stall the loads that follow it).
    #[inline(always)]
    fn upper_part_any(&self, p: usize, x: &[f64], z: &mut [f64], value: &impl Fn(usize) -> f64) {
        const B: usize = 3;
        let (xs, zs) = (x.as_chunks::<B>().0, z.as_chunks_mut::<B>().0);
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
                    for (r, zr) in zs[ib].iter_mut().enumerate() {
                        *zr += (cols[0][r] * xj[0] + cols[1][r] * xj[1]) + cols[2][r] * xj[2];
                    }
                }
            }
            for (zc, a) in zs[jb].iter_mut().zip(&acc) {
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
}
