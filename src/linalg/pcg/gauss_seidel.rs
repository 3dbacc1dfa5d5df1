//! Symmetric block Gauss–Seidel preconditioned CG by Eisenstat's trick (S. C. Eisenstat,
//! "Efficient implementation of a class of preconditioned conjugate gradient methods", SIAM J.
//! Sci. Stat. Comput. 2, 1981), for 3 × 3 node blocks stored as their upper triangle.
//!
//! On the free dofs, order the factored block S first and the nodes after it, and split
//! `A = L + D + Lᵀ` (D: A_SS and the nodal diagonal blocks on the dofs outside S; L: the strictly
//! lower blocks). With `P = D̃ + L`, D̃⁻¹ the factored block's solve and the nodal Jacobi inverses
//! (restricted to the free dofs), the preconditioner is `M = P D⁻¹ Pᵀ` (symmetric Gauss–Seidel
//! for D̃ = D). CG runs on `Â = P⁻¹ A P⁻ᵀ` with the preconditioner D (a product), where
//! `A = P + Pᵀ + (D − 2 D̃)` gives
//!
//! `Â p = t + P⁻¹ (p − 2 s + D t)`,  `t = P⁻ᵀ p`,  `s = D̃ t`:
//!
//! one backward and one forward sweep, each one pass over the stored blocks, in place of the
//! product. Each node needs its predecessors; the nodes are renumbered into two halves that do
//! not couple and their separator, numbered last ([`BlockSym::halves`]): the halves sweep side
//! by side on two threads, the separator after them (forward) or before them (backward). The
//! halves grow from the nodes of S and of its couplings, which the first half holds: S's
//! solves run on its thread, before its sweep (forward) or after it (backward), beside the
//! second half's, which holds more blocks to match. This is symmetric Gauss–Seidel in that
//! order on any number of threads. The iterate in the original variables moves by `α t`. The
//! residual `r = P r̂` is not formed: CG stops on `r̂ᵀ D r̂ = rᵀ M⁻¹ r` scaled by its ratio to
//! `‖r‖²` at the start, and the caller checks the exact residual afterwards, as for the
//! single-precision product. From the run's own guesses (hertz3d, residual 1e-6 to 5e-5
//! of ‖b‖ down to 1e-10) it takes 0.35 to 0.39 times nodal Jacobi's iterations at n = 16 and 24.

use super::{packed_mul, FactoredBlock, Pcg, PASS_CHUNK};
use crate::linalg::block::LANES;
use crate::linalg::{dot, BlockSym, SpMat};
use std::ops::Range;

/// The sweeps' data beside the factored block of a [`Pcg`]. The nodes are renumbered into
/// [`Halves`](crate::linalg::block::Halves), whose sweeps run on two threads; the iterations run
/// in that order.
#[derive(Debug)]
pub(super) struct GaussSeidel {
    /// The node at each position.
    order: Vec<usize>,
    /// The nodes of the two halves (the separator follows).
    sizes: [usize; 2],
    /// `Π A Πᵀ` by its upper blocks.
    blocks: BlockSym<f32>,
    /// The nodal Jacobi inverses, in that order.
    inv: Vec<f32>,
    /// `D_J` of every node on its dofs outside the factored block (zero rows and columns on
    /// those), its upper triangle in single precision.
    diag: Vec<f32>,
    /// The factored block's dofs (in its order), renumbered.
    dofs: Vec<usize>,
    /// For each dof of the factored block (in its order), its column of A outside the block
    /// `(i, A_ij)`: the couplings L between S and the nodes.
    coupling: Vec<Vec<(usize, f64)>>,
    /// The iterate and the free dofs, renumbered.
    x: Vec<f64>,
    free: Vec<bool>,
    /// `s = D̃ t` (accumulated by the backward sweep, [`LANES`] entries per node).
    s: Vec<f64>,
    /// `t = P⁻ᵀ p`.
    t: Vec<f64>,
    /// `p − 2 s + D t`, then `P⁻¹` of it.
    u: Vec<f64>,
    /// A product on the factored block (its own order).
    ys: Vec<f64>,
}

impl GaussSeidel {
    /// The sweeps of `a`, stored by 3 × 3 upper `blocks` (None for other blocks), with the
    /// factored block on the dofs `factored` (in the block's order `dofs`; its factor has
    /// `entries`) and the nodal Jacobi inverses `inv` elsewhere. The first half holds the nodes
    /// of the block's dofs and of its couplings, whose solves run beside the second half's sweep
    /// ([`extra`]).
    pub(super) fn new(
        a: &SpMat,
        blocks: &BlockSym<f32>,
        (factored, dofs, entries): (&[bool], &[usize], usize),
        inv: &[f32],
    ) -> Option<Self> {
        if !blocks.is_upper() {
            return None;
        }
        let n = a.nrows();
        let a = a.as_ref();
        let mut coupling: Vec<Vec<(usize, f64)>> = dofs
            .iter()
            .map(|&j| {
                let rows = a.row_idx_of_col_raw(j).iter().copied();
                let entries = rows.zip(a.val_of_col(j).iter().copied());
                entries.filter(|&(i, _)| !factored[i]).collect()
            })
            .collect();
        let mut near = vec![false; n / 3];
        let coupled = coupling.iter().flatten().map(|&(i, _)| i);
        for i in dofs.iter().copied().chain(coupled) {
            near[i / 3] = true;
        }
        let near: Vec<usize> = (0..n / 3).filter(|&j| near[j]).collect();
        let couplings = coupling.iter().map(Vec::len).sum::<usize>();
        let halves = blocks.halves(&near, extra(entries, couplings));
        let mut position = vec![0; n / 3];
        for (p, &j) in halves.order.iter().enumerate() {
            position[j] = p;
        }
        let renumbered = |i: usize| 3 * position[i / 3] + i % 3;
        let mut diag = Vec::with_capacity(n / 3 * 6);
        for &jb in &halves.order {
            let d = blocks.diagonal_block(jb)?;
            let kept = |r: usize| !factored[3 * jb + r];
            for (r, row) in d.iter().enumerate() {
                for (c, &v) in row.iter().enumerate().skip(r) {
                    diag.push(if kept(r) && kept(c) { v } else { 0.0 });
                }
            }
        }
        for (i, _) in coupling.iter_mut().flatten() {
            *i = renumbered(*i);
        }
        let dofs: Vec<usize> = dofs.iter().map(|&i| renumbered(i)).collect();
        let first = 3 * halves.sizes[0];
        let inside = |i: &usize| *i < first;
        assert!(dofs.iter().all(inside) && coupling.iter().flatten().all(|(i, _)| inside(i)));
        Some(Self {
            blocks: blocks.permuted(&halves.order),
            inv: (halves.order.iter())
                .flat_map(|&j| inv[6 * j..6 * j + 6].iter().copied())
                .collect(),
            order: halves.order,
            sizes: halves.sizes,
            diag,
            ys: vec![0.0; dofs.len()],
            dofs,
            coupling,
            x: vec![0.0; n],
            free: vec![false; n],
            s: vec![0.0; n / 3 * LANES],
            t: vec![0.0; n],
            u: vec![0.0; n],
        })
    }
}

/// The work of the factored block's part of a sweep in stored blocks of a half, for the
/// balance of the halves: its factor's `entries` and a quarter of its `couplings` to the
/// nodes. Measured at hertz3d n = 44 (0.70M entries, 0.51M couplings; the first 30 steps), the
/// backward sweep's first half (its nodes, then the block) against the second: with the
/// entries and all the couplings (1.21M) 7.2 + 3.7 ms against 12.4 ms; with the entries alone
/// 7.9 + 3.4 against 10.4; with this rule (0.83M) 7.1 + 3.5 against 10.9.
fn extra(entries: usize, couplings: usize) -> usize {
    entries + couplings / 4
}

/// `to = Π from` by nodes of three entries: `to_p = from_{order(p)}`.
fn gather<T: Copy>(order: &[usize], from: &[T], to: &mut [T]) {
    for (to, &j) in to.chunks_exact_mut(3).zip(order) {
        to.copy_from_slice(&from[3 * j..3 * j + 3]);
    }
}

/// `to = Πᵀ from`: `to_{order(p)} = from_p`.
fn scatter<T: Copy>(order: &[usize], from: &[T], to: &mut [T]) {
    for (from, &j) in from.chunks_exact(3).zip(order) {
        to[3 * j..3 * j + 3].copy_from_slice(from);
    }
}

/// The free dofs of node J.
fn node_free(free: &[bool], jb: usize) -> [bool; 3] {
    [free[3 * jb], free[3 * jb + 1], free[3 * jb + 2]]
}

impl FactoredBlock {
    /// `y_S = Π A_SS Π x_S` in the block's order (S: the block's `dofs` in x's numbering).
    fn mul_free(&self, dofs: &[usize], x: &[f64], free: &[bool], y: &mut [f64]) {
        let a = self.a_ss.as_ref();
        for (j, yj) in y.iter_mut().enumerate() {
            *yj = 0.0;
            if !free[dofs[j]] {
                continue;
            }
            let rows = a.row_idx_of_col_raw(j).iter();
            for (&i, &v) in rows.zip(a.val_of_col(j)) {
                if free[dofs[i]] {
                    *yj += v * x[dofs[i]];
                }
            }
        }
    }

    /// `x_S ← Π D̃_S⁻¹ Π w` with `w_k = rhs(k)` in the block's order (its factor).
    fn solve_into(
        &mut self,
        dofs: &[usize],
        x: &mut [f64],
        free: &[bool],
        rhs: impl Fn(usize) -> f64,
    ) {
        for (k, w) in self.work.iter_mut().enumerate() {
            *w = rhs(k) as f32;
        }
        self.factor.solve_in_place(&mut self.work);
        for (&w, &i) in self.work.iter().zip(dofs) {
            x[i] = if free[i] { f64::from(w) } else { 0.0 };
        }
    }

    /// The block's part of the forward sweep on `x` (the block's dofs and their couplings
    /// inside): `x_S ← D̃_S⁻¹ x_S`, taken out of x and returned (x_S = 0), and `x_N −= L_NS x_S`.
    fn forward(&mut self, (dofs, coupling): Part<'_>, x: &mut [f64], free: &[bool]) -> Vec<f64> {
        let rhs: Vec<f64> = dofs.iter().map(|&i| x[i]).collect();
        self.solve_into(dofs, x, free, |k| rhs[k]);
        let xs: Vec<f64> = dofs.iter().map(|&i| std::mem::take(&mut x[i])).collect();
        for (col, &v) in coupling.iter().zip(&xs) {
            for &(i, a) in col {
                x[i] -= a * v;
            }
        }
        xs
    }

    /// The block's part of the backward sweep, after the nodes' t: `s_S = p_S − L_NSᵀ t_N`,
    /// `t_S = D̃_S⁻¹ s_S` and `u_S = p_S − 2 s_S + A_SS t_S` (`ys`: room for `A_SS t_S`).
    fn backward(
        &mut self,
        (dofs, coupling): Part<'_>,
        p: &[f64],
        free: &[bool],
        (t, u, ys): (&mut [f64], &mut [f64], &mut [f64]),
    ) {
        let s: Vec<f64> = (dofs.iter().zip(coupling))
            .map(|(&j, col)| p[j] - col.iter().map(|&(i, a)| a * t[i]).sum::<f64>())
            .collect();
        self.solve_into(dofs, t, free, |k| s[k]);
        self.mul_free(dofs, t, free, ys);
        for ((&j, &dt), s) in dofs.iter().zip(&*ys).zip(s) {
            u[j] = if free[j] { p[j] - 2.0 * s + dt } else { 0.0 };
        }
    }
}

/// The factored block's dofs (renumbered) and, for each, its couplings to the nodes `(i, A_ij)`.
type Part<'a> = (&'a [usize], &'a [Vec<(usize, f64)>]);

impl GaussSeidel {
    /// The forward sweep over the nodes with their Jacobi inverses, `x ← (D̃ + L)⁻¹ x` (the
    /// factored block's entries of x at 0): the halves side by side, `block` on the first
    /// half's entries of x before its sweep, then the separator. Returns the sum of
    /// `visit(J, y_J)` over the nodes (the halves', then the separator's).
    fn forward_nodes(
        &self,
        x: &mut [f64],
        free: &[bool],
        visit: impl Fn(usize, [f64; 3]) -> f64 + Sync,
        block: impl FnOnce(&mut [f64]) + Send,
    ) -> f64 {
        let [a, b] = self.sizes;
        let sweep = |held: (usize, &mut [f64]), nodes: Range<usize>| {
            let mut sum = 0.0;
            self.blocks.forward_sweep(
                held,
                nodes,
                #[inline(always)]
                |jb, rhs| {
                    let y = packed_mul::<3>(&self.inv[6 * jb..], rhs, node_free(free, jb));
                    sum += visit(jb, y);
                    y
                },
            );
            sum
        };
        let (first, second) = x.split_at_mut(3 * a);
        let (sa, sb) = rayon::join(
            || {
                block(first);
                sweep((0, first), 0..a)
            },
            || sweep((a, &mut second[..3 * b]), a..a + b),
        );
        let nodes = x.len() / 3;
        (sa + sb) + sweep((0, x), a + b..nodes)
    }

    /// `t = P⁻ᵀ p` and `u = p − 2 s + D t` (s = D̃ t): the backward sweep over the nodes (s = p
    /// on entry), the separator, then the halves side by side, and the factored `block` after
    /// the first half's.
    fn backward(&mut self, p: &[f64], free: &[bool], block: Option<&mut FactoredBlock>) {
        let [a, b] = self.sizes;
        let Self {
            blocks,
            inv,
            diag,
            dofs,
            coupling,
            s,
            t,
            u,
            ys,
            ..
        } = self;
        let (blocks, inv, diag) = (&*blocks, &*inv, &*diag);
        let sweep = |(first, s, t, u): (usize, &mut [f64], &mut [f64], &mut [f64]),
                     nodes: Range<usize>| {
            blocks.backward_sweep(
                (first, s, t),
                nodes,
                #[inline(always)]
                |jb, s| {
                    let fr = node_free(free, jb);
                    let t = packed_mul::<3>(&inv[6 * jb..], s, fr);
                    let dt = packed_mul::<3>(&diag[6 * jb..], t, fr);
                    for c in 0..3 {
                        let i = 3 * jb + c;
                        u[i - 3 * first] = if fr[c] {
                            p[i] - 2.0 * s[c] + dt[c]
                        } else {
                            0.0
                        };
                    }
                    t
                },
            );
        };
        let nodes = t.len() / 3;
        sweep((0, s, t, u), a + b..nodes);
        let (s, sb) = s.split_at_mut(LANES * a);
        let (t, tb) = t.split_at_mut(3 * a);
        let (u, ub) = u.split_at_mut(3 * a);
        rayon::join(
            || {
                sweep((0, &mut *s, &mut *t, &mut *u), 0..a);
                if let Some(bl) = block {
                    bl.backward((dofs, coupling), p, free, (t, u, ys));
                }
            },
            || sweep((a, sb, tb, ub), a..a + b),
        );
    }
}

impl Pcg {
    /// `x ← P⁻¹ x`: the factored block first, its couplings moved to the right-hand side of the
    /// nodes, beside the second half's sweep, then the forward sweep over the nodes (with the
    /// block's entries of x at 0, so that the sweep does not count them twice). Returns the sum
    /// of `visit(J, y_J)` over the nodes.
    fn forward(
        &mut self,
        x: &mut [f64],
        free: &[bool],
        visit: impl Fn(usize, [f64; 3]) -> f64 + Sync,
    ) -> f64 {
        let gs = self.gauss_seidel.as_ref().expect("sweeps");
        let mut xs = Vec::new();
        let block = self.block.as_mut();
        let sum = gs.forward_nodes(x, free, visit, |x| {
            if let Some(bl) = block {
                xs = bl.forward((&gs.dofs, &gs.coupling), x, free);
            }
        });
        for (&i, v) in gs.dofs.iter().zip(xs) {
            x[i] = v;
        }
        sum
    }

    /// `t = P⁻ᵀ p` and `u = p − 2 s + D t` ([`GaussSeidel::backward`]).
    fn backward(&mut self, p: &[f64], free: &[bool]) {
        let gs = self.gauss_seidel.as_mut().expect("sweeps");
        gs.backward(p, free, self.block.as_mut());
    }

    /// `x += α t`, `r −= α (t + u)` and `z = D r` (the nodal blocks, and A_SS on the factored
    /// block) in one pass over chunks on the rayon pool (α = 0: z alone); returns `r·z`.
    fn update(&mut self, x: &mut [f64], free: &[bool], alpha: f64) -> f64 {
        use rayon::prelude::*;
        let gs = self.gauss_seidel.as_mut().expect("sweeps");
        let (r, z, diag) = (&mut self.r, &mut self.z, &gs.diag);
        let mine = x
            .par_chunks_mut(PASS_CHUNK)
            .zip(r.par_chunks_mut(PASS_CHUNK));
        let theirs = gs.t.par_chunks(PASS_CHUNK).zip(gs.u.par_chunks(PASS_CHUNK));
        let chunks = mine.zip(z.par_chunks_mut(PASS_CHUNK)).zip(theirs);
        let mut rz: Vec<f64> = Vec::new();
        chunks
            .zip(free.par_chunks(PASS_CHUNK))
            .enumerate()
            .map(|(c, ((((x, r), z), (t, u)), free))| {
                if alpha != 0.0 {
                    for (((x, r), t), u) in x.iter_mut().zip(r.iter_mut()).zip(t).zip(u) {
                        *x += alpha * t;
                        *r -= alpha * (t + u);
                    }
                }
                super::packed_apply::<3>(&diag[c * PASS_CHUNK / 3 * 6..], r, z, free)
            })
            .collect_into_vec(&mut rz);
        let mut rz = rz.iter().sum::<f64>();
        let (r, z) = (&self.r, &mut self.z);
        if let Some(bl) = self.block.as_ref() {
            bl.mul_free(&gs.dofs, r, free, &mut gs.ys);
            for (&i, &v) in gs.dofs.iter().zip(&gs.ys) {
                z[i] = v;
                rz += r[i] * v;
            }
        }
        rz
    }

    /// `p = z + β p`, and `s = p` for the next backward sweep, over chunks on the rayon pool.
    fn next_direction(&mut self, beta: f64) {
        use rayon::prelude::*;
        let gs = self.gauss_seidel.as_mut().expect("sweeps");
        let chunks = self
            .p
            .par_chunks_mut(PASS_CHUNK)
            .zip(self.z.par_chunks(PASS_CHUNK));
        chunks
            .zip(gs.s.par_chunks_mut(PASS_CHUNK / 3 * LANES))
            .for_each(|((p, z), s)| {
                for ((p, z), s) in p
                    .chunks_exact_mut(3)
                    .zip(z.chunks_exact(3))
                    .zip(s.chunks_exact_mut(LANES))
                {
                    for c in 0..3 {
                        p[c] = z[c] + beta * p[c];
                        s[c] = p[c];
                    }
                }
            });
    }

    /// CG on `Â` from `x` and its residual in `self.r` (as [`Pcg::iterate`], whose contract it
    /// keeps, with the residual estimated from `r̂ᵀ D r̂`), in the sweeps' order of the nodes.
    pub(super) fn iterate_gauss_seidel(
        &mut self,
        x: &mut [f64],
        free: &[bool],
        limits: (f64, usize),
        (check2, stop): (f64, &mut impl FnMut(&[f64]) -> bool),
    ) -> (usize, bool) {
        let gs = self.gauss_seidel.as_mut().expect("sweeps");
        let order = std::mem::take(&mut gs.order);
        let (mut xp, mut fp) = (std::mem::take(&mut gs.x), std::mem::take(&mut gs.free));
        gather(&order, x, &mut xp);
        gather(&order, free, &mut fp);
        gather(&order, &self.r, &mut self.q);
        std::mem::swap(&mut self.r, &mut self.q);
        let done = self.cg_gauss_seidel(
            &mut xp,
            &fp,
            limits,
            (check2, &mut |xp: &[f64]| {
                scatter(&order, xp, x);
                stop(x)
            }),
        );
        scatter(&order, &xp, x);
        scatter(&order, &self.r, &mut self.q);
        std::mem::swap(&mut self.r, &mut self.q);
        let gs = self.gauss_seidel.as_mut().expect("sweeps");
        (gs.order, gs.x, gs.free) = (order, xp, fp);
        done
    }

    /// [`Pcg::iterate_gauss_seidel`] on the renumbered `x`, `free` and `self.r`.
    fn cg_gauss_seidel(
        &mut self,
        x: &mut [f64],
        free: &[bool],
        (target2, limit): (f64, usize),
        (check2, stop): (f64, &mut impl FnMut(&[f64]) -> bool),
    ) -> (usize, bool) {
        let res2 = dot(&self.r, &self.r);
        let mut r = std::mem::take(&mut self.r);
        self.forward(&mut r, free, |_, _| 0.0);
        self.r = r;
        let mut rz = self.update(x, free, 0.0);
        // ‖r‖² ≈ scale · rᵀ M⁻¹ r (exactly at the start).
        let scale = res2 / rz;
        self.next_direction(0.0);
        let mut it = 0;
        while scale * rz > target2 {
            if scale * rz <= check2 && stop(x) {
                return (it, true);
            }
            if it == limit {
                break;
            }
            let p = std::mem::take(&mut self.p);
            self.backward(&p, free);
            let gs = self.gauss_seidel.as_mut().expect("sweeps");
            let (mut u, t) = (std::mem::take(&mut gs.u), std::mem::take(&mut gs.t));
            let mut pv = self.forward(
                &mut u,
                free,
                #[inline(always)]
                |jb, y| {
                    let i = 3 * jb;
                    (p[i] * (t[i] + y[0]) + p[i + 1] * (t[i + 1] + y[1]))
                        + p[i + 2] * (t[i + 2] + y[2])
                },
            );
            let gs = self.gauss_seidel.as_mut().expect("sweeps");
            pv += gs.dofs.iter().map(|&i| p[i] * u[i]).sum::<f64>();
            (gs.u, gs.t, self.p) = (u, t, p);
            let rz_new = self.update(x, free, rz / pv);
            self.next_direction(rz_new / rz);
            rz = rz_new;
            it += 1;
        }
        (it, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::pcg::NodalJacobi;
    use crate::linalg::testing::block_matrix;
    use crate::linalg::{triplets, TripletBuilder};

    /// The halves side by side and then the separator (or the separator first, backward) give
    /// the bits of one sweep over every node in the new order, on the rayon pool.
    #[test]
    fn the_sweeps_by_halves_are_one_sweep_in_their_order() {
        let a = block_matrix(300, 3);
        let n = a.nrows();
        let blocks = BlockSym::new(&a).expect("blocks").rounded();
        let none = vec![false; n];
        let jacobi = NodalJacobi::new(&a, 3, &none, "A").unwrap();
        let mut gs = GaussSeidel::new(&a, &blocks, (&none, &[], 0), &jacobi.inv).unwrap();
        let [first, second] = gs.sizes;
        assert!(first > 100 && second > 100, "{:?}", gs.sizes);
        let mut free = vec![true; n];
        free[7] = false;
        let solve = |jb: usize, rhs: [f64; 3]| {
            packed_mul::<3>(&gs.inv[6 * jb..], rhs, node_free(&free, jb))
        };
        let x: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
        let (mut by_halves, mut whole) = (x.clone(), x.clone());
        gs.forward_nodes(&mut by_halves, &free, |_, _| 0.0, |_| {});
        gs.blocks.forward_sweep((0, &mut whole), 0..n / 3, solve);
        assert!(by_halves
            .iter()
            .zip(&whole)
            .all(|(p, q)| p.to_bits() == q.to_bits()));
        let padded: Vec<f64> = x.chunks(3).flat_map(|c| [c[0], c[1], c[2], 0.0]).collect();
        let (mut s, mut t) = (padded.clone(), vec![0.0; n]);
        gs.blocks
            .backward_sweep((0, &mut s, &mut t), 0..n / 3, solve);
        gs.s = padded;
        gs.backward(&x, &free, None);
        assert!(gs.t.iter().zip(&t).all(|(p, q)| p.to_bits() == q.to_bits()));
    }

    /// The factored block's solves inside the first half's thread are the operator they were
    /// on one thread: the block, then the nodes' sweep (forward), and the nodes' sweep, then the
    /// block (backward), to the bit, with the block in one of two bodies, in both, and on a
    /// dof of every node (the first half then holds them all).
    #[test]
    fn the_block_beside_the_second_half_is_the_block_before_or_after_the_nodes() {
        let nodes = 300;
        let n = 3 * nodes;
        let mut t = TripletBuilder::new(2 * n, 2 * n);
        for (i, j, v) in triplets(&block_matrix(nodes, 3)) {
            let d = if i == j { 12.0 } else { 0.0 };
            t.add(i, j, v + d);
            t.add(i + n, j + n, v + d);
        }
        let a = t.build().unwrap();
        let cap = |first: usize, c: usize| (0..60).map(move |k| first + 3 * k + c);
        let blocks: [Vec<usize>; 3] = [
            cap(0, 2).collect(),
            cap(0, 2).chain(cap(n, 1)).collect(),
            (0..2 * n).filter(|i| i % 3 == 2).collect(),
        ];
        let free: Vec<bool> = (0..2 * n).map(|i| i % 17 != 5).collect();
        let x: Vec<f64> = (0..2 * n).map(|i| (0.37 * i as f64).sin()).collect();
        let same = |p: &[f64], q: &[f64]| p.iter().zip(q).all(|(p, q)| p.to_bits() == q.to_bits());
        for dofs in blocks {
            let mut pcg = Pcg::build(&a, "A", dofs, |_| true).unwrap();
            let mut beside = x.clone();
            let sum = pcg.forward(&mut beside, &free, |_, y| y[0]);
            let (gs, bl) = (
                pcg.gauss_seidel.as_mut().unwrap(),
                pcg.block.as_mut().unwrap(),
            );
            let mut before = x.clone();
            let xs = bl.forward((&gs.dofs, &gs.coupling), &mut before, &free);
            let sum_before = gs.forward_nodes(&mut before, &free, |_, y| y[0], |_| {});
            for (&i, v) in gs.dofs.iter().zip(xs) {
                before[i] = v;
            }
            assert!(same(&beside, &before) && sum.to_bits() == sum_before.to_bits());
            let padded: Vec<f64> = x.chunks(3).flat_map(|c| [c[0], c[1], c[2], 0.0]).collect();
            gs.s.clone_from(&padded);
            gs.backward(&x, &free, Some(bl));
            let (t, u) = (gs.t.clone(), gs.u.clone());
            gs.s = padded;
            gs.backward(&x, &free, None);
            bl.backward(
                (&gs.dofs, &gs.coupling),
                &x,
                &free,
                (&mut gs.t, &mut gs.u, &mut gs.ys),
            );
            assert!(same(&t, &gs.t) && same(&u, &gs.u));
        }
    }
}
