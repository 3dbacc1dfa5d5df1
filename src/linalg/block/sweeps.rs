//! Block Gauss–Seidel sweeps of single-precision 3 × 3 upper blocks.

use super::{lane_sum, BlockSym, LANES, PREFETCH};

/// Block Gauss–Seidel sweeps by the stored 3 × 3 upper blocks `A_IJ` (I ≤ J), with the
/// diagonal blocks left to a `solve(J, rhs)` of the caller (an approximate inverse, masked
/// dofs): one pass over the values each, on the calling thread (each node needs its
/// predecessors), by 4-lane vectors where the processor has AVX2 (as the product).
impl BlockSym<f32> {
    /// Forward sweep `(D̃ + L) y = x` in place (L the strictly lower blocks): for J = 0, 1, …,
    /// `y_J = solve(J, x_J − Σ_{I<J} A_IJᵀ y_I)`, a block column's dot.
    pub fn forward_sweep(&self, x: &mut [f64], mut solve: impl FnMut(usize, [f64; 3]) -> [f64; 3]) {
        assert!(self.upper && x.len() == 3 * (self.ptr.len() - 1));
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor supports AVX2, checked on the line above.
            return unsafe { self.forward_sweep_avx2(x, &mut solve) };
        }
        self.forward_sweep_any(x, &mut solve);
    }

    /// [`BlockSym::forward_sweep`] for any instruction set.
    fn forward_sweep_any(
        &self,
        x: &mut [f64],
        solve: &mut impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        let xs = x.as_chunks_mut::<3>().0;
        for jb in 0..xs.len() {
            // acc[c][r] = Σ_I A_IJ[r][c] x_I[r]: nine independent sums.
            let mut acc = [[0.0; 3]; 3];
            for k in self.ptr[jb]..self.ptr[jb + 1] {
                let ib = self.idx[k] as usize;
                if ib == jb {
                    continue;
                }
                let (xi, v) = (xs[ib], &self.val[9 * k..9 * k + 9]);
                for (c, a) in acc.iter_mut().enumerate() {
                    for r in 0..3 {
                        a[r] += f64::from(v[3 * c + r]) * xi[r];
                    }
                }
            }
            let xj = xs[jb];
            xs[jb] = solve(
                jb,
                std::array::from_fn(|c| xj[c] - ((acc[c][0] + acc[c][1]) + acc[c][2])),
            );
        }
    }

    /// [`BlockSym::forward_sweep`] in AVX2 vectors (a block's column one 4-value load, as in
    /// [`BlockSym::upper_part_avx2`]).
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn forward_sweep_avx2(
        &self,
        x: &mut [f64],
        solve: &mut impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        use std::arch::x86_64::*;
        let nodes = x.len() / 3;
        let val = &self.val;
        // A block's last column reads one value past it (the pad of `rounded`).
        assert!(val.len() > 9 * self.idx.len());
        debug_assert!(self.idx.iter().all(|&i| (i as usize) < nodes));
        let zero = _mm256_setzero_pd();
        for jb in 0..nodes {
            let mut acc = [zero; 3];
            for k in self.ptr[jb]..self.ptr[jb + 1] {
                let ib = self.idx[k] as usize;
                if ib == jb {
                    continue;
                }
                let o = 9 * k;
                _mm_prefetch::<_MM_HINT_T0>(val.as_ptr().wrapping_add(o + PREFETCH).cast());
                let xi = if ib + 1 < nodes {
                    // SAFETY: 3 ib + 3 < x.len() when I is not the last node.
                    _mm256_blend_pd::<0b1000>(
                        unsafe { _mm256_loadu_pd(x.as_ptr().add(3 * ib)) },
                        zero,
                    )
                } else {
                    _mm256_set_pd(0.0, x[3 * ib + 2], x[3 * ib + 1], x[3 * ib])
                };
                for (c, a) in acc.iter_mut().enumerate() {
                    // SAFETY: o + 3 c + 3 < val.len() (the assertion above).
                    let col = unsafe { _mm256_cvtps_pd(_mm_loadu_ps(val.as_ptr().add(o + 3 * c))) };
                    *a = _mm256_add_pd(*a, _mm256_mul_pd(col, xi));
                }
            }
            let sums = [lane_sum(acc[0]), lane_sum(acc[1]), lane_sum(acc[2])];
            let rhs = [
                x[3 * jb] - sums[0],
                x[3 * jb + 1] - sums[1],
                x[3 * jb + 2] - sums[2],
            ];
            x[3 * jb..3 * jb + 3].copy_from_slice(&solve(jb, rhs));
        }
    }

    /// Backward sweep `(D̃ + Lᵀ) y = x`: for J = n − 1, …, 0, `y_J = solve(J, s_J)` with
    /// `s_J = x_J − Σ_{K>J} A_JK y_K`, accumulated in `s` (x on entry, [`LANES`] entries per
    /// node; the pad is scratch) by scattering each block column `A_IJ y_J` into its rows I < J;
    /// `y` (3 entries per node) is written.
    pub fn backward_sweep(
        &self,
        s: &mut [f64],
        y: &mut [f64],
        mut solve: impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        let nodes = self.ptr.len() - 1;
        assert!(self.upper && s.len() == LANES * nodes && y.len() == 3 * nodes);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor supports AVX2, checked on the line above.
            return unsafe { self.backward_sweep_avx2(s, y, &mut solve) };
        }
        self.backward_sweep_any(s, y, &mut solve);
    }

    /// [`BlockSym::backward_sweep`] for any instruction set.
    fn backward_sweep_any(
        &self,
        s: &mut [f64],
        y: &mut [f64],
        solve: &mut impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        let nodes = self.ptr.len() - 1;
        let (ss, ys) = (s.as_chunks_mut::<LANES>().0, y.as_chunks_mut::<3>().0);
        for jb in (0..nodes).rev() {
            let yj = solve(jb, [ss[jb][0], ss[jb][1], ss[jb][2]]);
            ys[jb] = yj;
            for k in self.ptr[jb]..self.ptr[jb + 1] {
                let ib = self.idx[k] as usize;
                if ib == jb {
                    continue;
                }
                let v = &self.val[9 * k..9 * k + 9];
                for (r, sr) in ss[ib][..3].iter_mut().enumerate() {
                    *sr -= (f64::from(v[r]) * yj[0] + f64::from(v[3 + r]) * yj[1])
                        + f64::from(v[6 + r]) * yj[2];
                }
            }
        }
    }

    /// [`BlockSym::backward_sweep`] in AVX2 vectors: `A_IJ y_J` as three columns times
    /// broadcast entries, its fourth lane (the next column's first value) into `s_I`'s pad.
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn backward_sweep_avx2(
        &self,
        s: &mut [f64],
        y: &mut [f64],
        solve: &mut impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        use std::arch::x86_64::*;
        let nodes = y.len() / 3;
        let val = &self.val;
        assert!(val.len() > 9 * self.idx.len() && s.len() == LANES * nodes);
        debug_assert!(self.idx.iter().all(|&i| (i as usize) < nodes));
        let sp = s.as_mut_ptr();
        for jb in (0..nodes).rev() {
            let sj = [s[LANES * jb], s[LANES * jb + 1], s[LANES * jb + 2]];
            let yj = solve(jb, sj);
            y[3 * jb..3 * jb + 3].copy_from_slice(&yj);
            let b = yj.map(|v| _mm256_set1_pd(v));
            for k in (self.ptr[jb]..self.ptr[jb + 1]).rev() {
                let ib = self.idx[k] as usize;
                if ib == jb {
                    continue;
                }
                let o = 9 * k;
                // The values go down (the blocks of a column too: in increasing order, the
                // sawtooth took 2.3 times as long at n = 44): ask for those PREFETCH behind.
                _mm_prefetch::<_MM_HINT_T0>(
                    val.as_ptr().wrapping_add(o).wrapping_sub(PREFETCH).cast(),
                );
                // SAFETY: o + 9 < val.len() (the assertion above).
                let col = |c: usize| unsafe {
                    _mm256_cvtps_pd(_mm_loadu_ps(val.as_ptr().add(o + 3 * c)))
                };
                let c01 = _mm256_add_pd(_mm256_mul_pd(col(0), b[0]), _mm256_mul_pd(col(1), b[1]));
                let t = _mm256_add_pd(c01, _mm256_mul_pd(col(2), b[2]));
                // SAFETY: LANES ib + 4 <= s.len().
                unsafe {
                    let si = sp.add(LANES * ib);
                    _mm256_storeu_pd(si, _mm256_sub_pd(_mm256_loadu_pd(si), t));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::{block_matrix, max_diff};

    /// The sweeps solve `(D + L) y = x` and `(D + Lᵀ) y = x` (L, Lᵀ: the strictly lower and
    /// upper blocks of the stored values, D the diagonal blocks, solved exactly here), by vectors
    /// and for any instruction set, to round-off.
    #[test]
    fn the_sweeps_solve_the_block_triangular_systems() {
        let a = BlockSym::new(&block_matrix(29, 3))
            .expect("blocks")
            .rounded();
        let n = 3 * (a.ptr.len() - 1);
        let mut dense = nalgebra::DMatrix::<f64>::zeros(n, n);
        for jb in 0..n / 3 {
            for k in a.ptr[jb]..a.ptr[jb + 1] {
                let ib = a.idx[k] as usize;
                for (e, v) in a.val[9 * k..9 * k + 9].iter().enumerate() {
                    dense[(3 * ib + e % 3, 3 * jb + e / 3)] = f64::from(*v);
                    dense[(3 * jb + e / 3, 3 * ib + e % 3)] = f64::from(*v);
                }
            }
        }
        let block = |j: usize| dense.view((3 * j, 3 * j), (3, 3)).into_owned();
        let solve = |j: usize, r: [f64; 3]| {
            let y = block(j)
                .lu()
                .solve(&nalgebra::Vector3::from(r))
                .expect("regular");
            [y[0], y[1], y[2]]
        };
        let lower = |i: usize, j: usize| i / 3 >= j / 3;
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let check = |y: &[f64], keep: &dyn Fn(usize, usize) -> bool| {
            let m = nalgebra::DMatrix::from_fn(
                n,
                n,
                |i, j| if keep(i, j) { dense[(i, j)] } else { 0.0 },
            );
            let r = m * nalgebra::DVector::from_column_slice(y);
            max_diff(r.as_slice(), &x)
        };
        let (mut y, mut z) = (x.clone(), x.clone());
        a.forward_sweep(&mut y, solve);
        a.forward_sweep_any(&mut z, &mut { solve });
        assert!(check(&y, &lower) < 1e-12 && check(&z, &lower) < 1e-12);
        let padded =
            |v: &[f64]| -> Vec<f64> { v.chunks(3).flat_map(|c| [c[0], c[1], c[2], 0.0]).collect() };
        let upper = |i: usize, j: usize| i / 3 <= j / 3;
        let (mut s, mut t) = (padded(&x), padded(&x));
        a.backward_sweep(&mut s, &mut y, solve);
        a.backward_sweep_any(&mut t, &mut z, &mut { solve });
        assert!(check(&y, &upper) < 1e-12 && check(&z, &upper) < 1e-12);
    }
}
