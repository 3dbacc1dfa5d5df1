//! Block Gauss–Seidel sweeps of single-precision 3 × 3 upper blocks.

use super::{cuts, lane_sum, BlockSym, LANES, PREFETCH};
use std::ops::Range;

/// Block Gauss–Seidel sweeps by the stored 3 × 3 upper blocks `A_IJ` (I ≤ J), with the
/// diagonal blocks left to a `solve(J, rhs)` of the caller (an approximate inverse, masked
/// dofs): one pass over the values of a range of nodes each, on the calling thread (each node
/// needs its predecessors: ranges that do not couple may sweep side by side, [`Halves`]), by
/// 4-lane vectors where the processor has AVX2 (as the product).
impl BlockSym<f32> {
    /// Forward sweep `(D̃ + L) y = x` in place on the `nodes` (L the strictly lower blocks):
    /// for J in `nodes` in increasing order, `y_J = solve(J, x_J − Σ_{I<J} A_IJᵀ y_I)`, a block
    /// column's dot. `x` holds the nodes from `first` on, and their columns must not reach
    /// below it (a node range that couples to no earlier node outside it).
    pub fn forward_sweep(
        &self,
        (first, x): (usize, &mut [f64]),
        nodes: Range<usize>,
        mut solve: impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        assert!(self.upper && nodes.start >= first);
        assert!(3 * nodes.end.saturating_sub(first) <= x.len());
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor supports AVX2, checked on the line above.
            return unsafe { self.forward_sweep_avx2((first, x), nodes, &mut solve) };
        }
        self.forward_sweep_any((first, x), nodes, &mut solve);
    }

    /// [`BlockSym::forward_sweep`] for any instruction set.
    fn forward_sweep_any(
        &self,
        (first, x): (usize, &mut [f64]),
        nodes: Range<usize>,
        solve: &mut impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        let xs = x.as_chunks_mut::<3>().0;
        for jb in nodes {
            // acc[c][r] = Σ_I A_IJ[r][c] x_I[r]: nine independent sums.
            let mut acc = [[0.0; 3]; 3];
            for k in self.ptr[jb]..self.ptr[jb + 1] {
                let ib = self.idx[k] as usize;
                if ib == jb {
                    continue;
                }
                let (xi, v) = (xs[ib - first], &self.val[9 * k..9 * k + 9]);
                for (c, a) in acc.iter_mut().enumerate() {
                    for r in 0..3 {
                        a[r] += f64::from(v[3 * c + r]) * xi[r];
                    }
                }
            }
            let xj = xs[jb - first];
            xs[jb - first] = solve(
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
        (first, x): (usize, &mut [f64]),
        nodes: Range<usize>,
        solve: &mut impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        use std::arch::x86_64::*;
        let held = x.len() / 3;
        let val = &self.val;
        // A block's last column reads one value past it (the pad of `permuted`).
        assert!(val.len() > 9 * self.idx.len());
        let zero = _mm256_setzero_pd();
        for jb in nodes {
            let mut acc = [zero; 3];
            for k in self.ptr[jb]..self.ptr[jb + 1] {
                let ib = self.idx[k] as usize;
                if ib == jb {
                    continue;
                }
                let o = 9 * k;
                _mm_prefetch::<_MM_HINT_T0>(val.as_ptr().wrapping_add(o + PREFETCH).cast());
                let i = ib
                    .checked_sub(first)
                    .expect("a column reaching below the first node");
                let xi = if i + 1 < held {
                    // SAFETY: 3 i + 3 < x.len() when I is not the last node held.
                    _mm256_blend_pd::<0b1000>(
                        unsafe { _mm256_loadu_pd(x.as_ptr().add(3 * i)) },
                        zero,
                    )
                } else {
                    _mm256_set_pd(0.0, x[3 * i + 2], x[3 * i + 1], x[3 * i])
                };
                for (c, a) in acc.iter_mut().enumerate() {
                    // SAFETY: o + 3 c + 3 < val.len() (the assertion above).
                    let col = unsafe { _mm256_cvtps_pd(_mm_loadu_ps(val.as_ptr().add(o + 3 * c))) };
                    *a = _mm256_add_pd(*a, _mm256_mul_pd(col, xi));
                }
            }
            let sums = [lane_sum(acc[0]), lane_sum(acc[1]), lane_sum(acc[2])];
            let j = 3 * (jb - first);
            let rhs = [x[j] - sums[0], x[j + 1] - sums[1], x[j + 2] - sums[2]];
            x[j..j + 3].copy_from_slice(&solve(jb, rhs));
        }
    }

    /// Backward sweep `(D̃ + Lᵀ) y = x` on the `nodes`: for J in `nodes` in decreasing order,
    /// `y_J = solve(J, s_J)` with `s_J = x_J − Σ_{K>J} A_JK y_K`, accumulated in `s` (x on
    /// entry, [`LANES`] entries per node; the pad is scratch) by scattering each block column
    /// `A_IJ y_J` into its rows I < J; `y` (3 entries per node) is written. `s` and `y` hold the
    /// nodes from `first` on, and the columns must not reach below it.
    pub fn backward_sweep(
        &self,
        (first, s, y): (usize, &mut [f64], &mut [f64]),
        nodes: Range<usize>,
        mut solve: impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        let held = nodes.end.saturating_sub(first);
        assert!(self.upper && nodes.start >= first);
        assert!(s.len() >= LANES * held && y.len() >= 3 * held);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor supports AVX2, checked on the line above.
            return unsafe { self.backward_sweep_avx2((first, s, y), nodes, &mut solve) };
        }
        self.backward_sweep_any((first, s, y), nodes, &mut solve);
    }

    /// [`BlockSym::backward_sweep`] for any instruction set.
    fn backward_sweep_any(
        &self,
        (first, s, y): (usize, &mut [f64], &mut [f64]),
        nodes: Range<usize>,
        solve: &mut impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        let (ss, ys) = (s.as_chunks_mut::<LANES>().0, y.as_chunks_mut::<3>().0);
        for jb in nodes.rev() {
            let sj = ss[jb - first];
            let yj = solve(jb, [sj[0], sj[1], sj[2]]);
            ys[jb - first] = yj;
            for k in self.ptr[jb]..self.ptr[jb + 1] {
                let ib = self.idx[k] as usize;
                if ib == jb {
                    continue;
                }
                let v = &self.val[9 * k..9 * k + 9];
                for (r, sr) in ss[ib - first][..3].iter_mut().enumerate() {
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
        (first, s, y): (usize, &mut [f64], &mut [f64]),
        nodes: Range<usize>,
        solve: &mut impl FnMut(usize, [f64; 3]) -> [f64; 3],
    ) {
        use std::arch::x86_64::*;
        let held = s.len() / LANES;
        let val = &self.val;
        assert!(val.len() > 9 * self.idx.len());
        let sp = s.as_mut_ptr();
        for jb in nodes.rev() {
            let j = jb - first;
            let sj = [s[LANES * j], s[LANES * j + 1], s[LANES * j + 2]];
            let yj = solve(jb, sj);
            y[3 * j..3 * j + 3].copy_from_slice(&yj);
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
                let i = ib
                    .checked_sub(first)
                    .expect("a column reaching below the first node");
                assert!(i < held);
                // SAFETY: LANES i + 4 <= s.len() (the assertion above).
                unsafe {
                    let si = sp.add(LANES * i);
                    _mm256_storeu_pd(si, _mm256_sub_pd(_mm256_loadu_pd(si), t));
                }
            }
        }
    }
}

/// A node order for Gauss–Seidel sweeps on two threads: two halves that do not couple, then
/// the nodes that separate them. The sweeps of the halves run side by side and the separator's
/// after them (forward) or before them (backward): symmetric Gauss–Seidel in this order,
/// whatever the number of threads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Halves {
    /// The node at each position of the order.
    pub order: Vec<usize>,
    /// The nodes of the first and of the second half (the separator follows).
    pub sizes: [usize; 2],
}

/// The blocks above the diagonal by rows: `(row_ptr, (column, block))`.
type Rows = (Vec<usize>, Vec<(usize, usize)>);

impl BlockSym<f32> {
    /// The halves by breadth-first levels: the levels below a middle one, the levels above it,
    /// and the middle level as their separator (a level only couples to its neighbours), each
    /// part in the stored order. The levels start from the `near` nodes, which the first half
    /// then holds, the middle one where the first half's blocks and `extra` (the work of a solve
    /// beside its sweep, in stored blocks) make about the second half's; without `near`, from a
    /// peripheral node (the last one reached from the first node of the piece with the most
    /// blocks), the middle one where the two halves hold about as many blocks. The other
    /// pieces, out of reach, go to the second half. At hertz3d n = 44, the separator is 3 % of
    /// the nodes from a peripheral node, 3.2 % from the factored block's nodes (the nodes from
    /// the stored order's midpoint on that couple below it were 5 %, spread over the second
    /// half, and cost 10 % more iterations).
    pub fn halves(&self, near: &[usize], extra: usize) -> Halves {
        let nodes = self.ptr.len() - 1;
        let rows = self.rows();
        if nodes == 0 {
            return Halves {
                order: Vec::new(),
                sizes: [0, 0],
            };
        }
        let mut level = vec![usize::MAX; nodes];
        let last = if near.is_empty() {
            self.levels_from_a_peripheral_node(&rows, &mut level)
        } else {
            self.search(&rows, near, &mut level, |_| {})
        };
        let depth = level[last] + 1;
        // Nodes out of reach (another body) couple to none of these: the second half takes them.
        let mut work = vec![0; depth + 1];
        for j in 0..nodes {
            work[level[j].min(depth)] += self.ptr[j + 1] - self.ptr[j];
        }
        let below: Vec<usize> = work
            .iter()
            .scan(0, |sum, &w| Some(std::mem::replace(sum, *sum + w)))
            .collect();
        let total: usize = work.iter().sum();
        // The near nodes, at level 0, stay in the first half.
        let lowest = usize::from(!near.is_empty());
        let middle = (lowest..depth.max(lowest + 1))
            .min_by_key(|&l| (below[l] + extra).abs_diff(total - below[l] - work[l]))
            .expect("a level");
        let part = |j: usize| match level[j] {
            l if l < middle => 0,
            l if l == middle => 2,
            _ => 1,
        };
        let of = |q: u8| (0..nodes).filter(move |&j| part(j) == q);
        Halves {
            sizes: [of(0).count(), of(1).count()],
            order: of(0).chain(of(1)).chain(of(2)).collect(),
        }
    }

    /// The levels from a peripheral node: the last one reached from the first node of the piece
    /// (body) with the most blocks, the first such piece; returns the last node reached.
    fn levels_from_a_peripheral_node(&self, rows: &Rows, level: &mut [usize]) -> usize {
        let mut heaviest = (0, 0);
        for j in 0..level.len() {
            if level[j] == usize::MAX {
                let mut blocks = 0;
                self.search(rows, &[j], level, |i| {
                    blocks += self.ptr[i + 1] - self.ptr[i]
                });
                if blocks > heaviest.0 {
                    heaviest = (blocks, j);
                }
            }
        }
        level.fill(usize::MAX);
        let far = self.search(rows, &[heaviest.1], level, |_| {});
        level.fill(usize::MAX);
        self.search(rows, &[far], level, |_| {})
    }

    /// Breadth-first search from the nodes `start` (level 0; not empty) over the nodes not yet
    /// reached (`level` at `usize::MAX`), writing their levels and passing each to `visit`;
    /// returns the last one reached (the farthest).
    fn search(
        &self,
        rows: &Rows,
        start: &[usize],
        level: &mut [usize],
        mut visit: impl FnMut(usize),
    ) -> usize {
        let mut queue = std::collections::VecDeque::new();
        for &j in start {
            if level[j] == usize::MAX {
                level[j] = 0;
                queue.push_back(j);
            }
        }
        let mut last = start[0];
        while let Some(j) = queue.pop_front() {
            visit(j);
            last = j;
            for (i, _, _) in self.neighbours(rows, j) {
                if level[i] == usize::MAX {
                    level[i] = level[j] + 1;
                    queue.push_back(i);
                }
            }
        }
        last
    }

    /// The blocks above the diagonal by rows.
    fn rows(&self) -> Rows {
        let nodes = self.ptr.len() - 1;
        let blocks =
            || (0..nodes).flat_map(|j| (self.ptr[j]..self.ptr[j + 1]).map(move |k| (j, k)));
        let above = || blocks().filter(|&(j, k)| self.idx[k] as usize != j);
        let mut row_ptr = vec![0; nodes + 1];
        for (_, k) in above() {
            row_ptr[self.idx[k] as usize + 1] += 1;
        }
        for i in 0..nodes {
            row_ptr[i + 1] += row_ptr[i];
        }
        let mut rows = vec![(0, 0); row_ptr[nodes]];
        let mut next = row_ptr.clone();
        for (j, k) in above() {
            let i = self.idx[k] as usize;
            rows[next[i]] = (j, k);
            next[i] += 1;
        }
        (row_ptr, rows)
    }

    /// The blocks coupling node J to each node I (itself included): `(I, block, mirrored)`, the
    /// block stored as `A_IJ` in column J, or as `A_JI` in column I (mirrored).
    fn neighbours<'a>(
        &'a self,
        (row_ptr, rows): &'a Rows,
        j: usize,
    ) -> impl Iterator<Item = (usize, usize, bool)> + 'a {
        let stored = (self.ptr[j]..self.ptr[j + 1]).map(|k| (self.idx[k] as usize, k, false));
        stored.chain(
            rows[row_ptr[j]..row_ptr[j + 1]]
                .iter()
                .map(|&(i, k)| (i, k, true)),
        )
    }

    /// `Π A Πᵀ` for the node order `order` (the node at each position), by its upper blocks,
    /// without the rounding errors (for the sweeps): a stored block `A_IJ` goes to column
    /// `max(π_I, π_J)`, transposed when `π_I > π_J`.
    pub fn permuted(&self, order: &[usize]) -> Self {
        assert!(self.upper && order.len() == self.ptr.len() - 1);
        let nodes = order.len();
        let mut position = vec![0; nodes];
        for (p, &j) in order.iter().enumerate() {
            position[j] = p;
        }
        let rows = self.rows();
        let (mut ptr, mut idx, mut val) = (vec![0], Vec::new(), Vec::new());
        let mut column: Vec<(usize, usize, bool)> = Vec::new();
        for &j in order {
            let pj = position[j];
            column.clear();
            for (i, k, transposed) in self.neighbours(&rows, j) {
                if position[i] <= pj {
                    column.push((position[i], k, transposed));
                }
            }
            column.sort_unstable_by_key(|e| e.0);
            for &(pi, k, transposed) in &column {
                idx.push(pi as u32);
                let v = &self.val[9 * k..9 * k + 9];
                val.extend((0..9).map(|e| {
                    if transposed {
                        v[3 * (e % 3) + e / 3]
                    } else {
                        v[e]
                    }
                }));
            }
            ptr.push(idx.len());
        }
        val.push(0.0);
        Self {
            b: 3,
            upper: true,
            cuts: cuts(&ptr),
            ptr,
            idx,
            val,
            rest: Vec::new(),
            parts: std::sync::Mutex::new(Vec::new()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::{block_matrix, max_diff};
    use crate::linalg::{triplets, TripletBuilder};

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
        let all = 0..n / 3;
        a.forward_sweep((0, &mut y), all.clone(), solve);
        a.forward_sweep_any((0, &mut z), all.clone(), &mut { solve });
        assert!(check(&y, &lower) < 1e-12 && check(&z, &lower) < 1e-12);
        let padded =
            |v: &[f64]| -> Vec<f64> { v.chunks(3).flat_map(|c| [c[0], c[1], c[2], 0.0]).collect() };
        let upper = |i: usize, j: usize| i / 3 <= j / 3;
        let (mut s, mut t) = (padded(&x), padded(&x));
        a.backward_sweep((0, &mut s, &mut y), all.clone(), solve);
        a.backward_sweep_any((0, &mut t, &mut z), all, &mut { solve });
        assert!(check(&y, &upper) < 1e-12 && check(&z, &upper) < 1e-12);
    }

    /// The halves hold `order[..first]` and `order[first..first + second]`: every node once, and
    /// no block couples them.
    fn assert_halves_do_not_couple(a: &BlockSym<f32>, halves: &Halves) -> BlockSym<f32> {
        let nodes = a.ptr.len() - 1;
        let mut sorted = halves.order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..nodes).collect::<Vec<_>>());
        let [first, second] = halves.sizes;
        let p = a.permuted(&halves.order);
        for j in 0..nodes {
            for k in p.ptr[j]..p.ptr[j + 1] {
                let i = p.idx[k] as usize;
                assert!(i <= j);
                if j < first + second {
                    assert_eq!(i < first, j < first, "block ({i}, {j}) couples the halves");
                }
            }
        }
        p
    }

    /// From `near` nodes (a factored block's), on a ring of 80 nodes: the first half holds them,
    /// the separator is one level (the nodes 6 and 8 steps away on each side: at most 12 nodes
    /// of at most 3 stored blocks), and the first half's blocks and the `extra` make the
    /// second's to within a level's blocks; with every node near, the first half holds them
    /// all, and with an `extra` beyond all the blocks, the near nodes alone.
    #[test]
    fn the_halves_from_near_nodes_hold_them_in_the_first() {
        let a = BlockSym::new(&block_matrix(80, 3))
            .expect("blocks")
            .rounded();
        let blocks =
            |nodes: &[usize]| -> usize { nodes.iter().map(|&j| a.ptr[j + 1] - a.ptr[j]).sum() };
        for extra in [0, 60] {
            let halves = a.halves(&[10, 11], extra);
            assert_halves_do_not_couple(&a, &halves);
            let [first, second] = halves.sizes;
            let (near, far) = (&halves.order[..first], &halves.order[first..first + second]);
            assert!(near.contains(&10) && near.contains(&11), "{halves:?}");
            assert!(80 - first - second <= 12, "{halves:?}");
            let diff = (blocks(near) + extra).abs_diff(blocks(far));
            assert!(
                diff <= 36,
                "{extra}: {} + {extra} against {}",
                blocks(near),
                blocks(far)
            );
        }
        let all: Vec<usize> = (0..80).collect();
        for (near, extra) in [(&all[..], 0), (&all[..], 1 << 40), (&[5, 6][..], 1 << 40)] {
            let halves = a.halves(near, extra);
            assert_halves_do_not_couple(&a, &halves);
            let [first, second] = halves.sizes;
            assert_eq!(first, near.len(), "{near:?}, {extra}: {halves:?}");
            assert!(second + first >= 68, "{halves:?}");
        }
    }

    /// On a ring of node couplings (to the third neighbour) and on two rings (two bodies, the
    /// smaller first), the halves do not couple and hold about as many nodes (the larger ring is
    /// split, the smaller one, out of reach, goes to the second half), the separator is a level
    /// of a few nodes, and the permuted matrix is `Π A Πᵀ`: its product is the permuted product.
    #[test]
    fn the_halves_do_not_couple_and_the_permuted_matrix_is_the_same() {
        let mut t = TripletBuilder::new(240, 240);
        for (i, j, v) in triplets(&block_matrix(20, 3)) {
            t.add(i, j, v);
        }
        for (i, j, v) in triplets(&block_matrix(60, 3)) {
            t.add(i + 60, j + 60, v);
        }
        for a in [block_matrix(80, 3), t.build().unwrap()] {
            let a = BlockSym::new(&a).expect("blocks").rounded();
            let halves = a.halves(&[], 0);
            let p = assert_halves_do_not_couple(&a, &halves);
            let [first, second] = halves.sizes;
            assert!(
                first >= 30 && second >= 30 && first + second >= 74,
                "{halves:?}"
            );
            let x: Vec<f64> = (0..240).map(|i| (i as f64 * 0.37).sin()).collect();
            let (mut y, mut yp) = (vec![0.0; 240], vec![0.0; 240]);
            a.mul(&mut y, &x);
            let permute = |v: &[f64]| -> Vec<f64> {
                (halves.order.iter())
                    .flat_map(|&j| v[3 * j..3 * j + 3].to_vec())
                    .collect()
            };
            p.mul(&mut yp, &permute(&x));
            assert!(max_diff(&permute(&y), &yp) < 1e-12);
        }
    }
}
