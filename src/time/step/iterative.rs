//! The contact-coupled step solved without a factorisation: preconditioned conjugate gradients
//! on the constant step matrix `A = m M + k K` (SPD; mass-dominated on the blocks at Δt = 10⁻³,
//! `k λ_max(M⁻¹K)` ≈ 10⁻², where CG converges in a few iterations from a good guess, but not on
//! the graded sphere at its Δt: `k K_ii / M_ii` has median 8.8 at n = 16 and 20 at n = 24),
//! and the Signorini law by a primal–dual active set on the contact points (Hintermüller, Ito,
//! Kunisch, SIAM J. Optim. 13, 2003).
//!
//! Applies when every row of `B_N` is `b e_dᵀ` (nodal contact along a coordinate axis, distinct
//! dofs d): on the active set 𝒜 the constraint `o_i − b_i U_{d_i} = 0` fixes U_{d_i}, and CG
//! solves `A U = r` on the other dofs; then
//! - `λ_i = (r − A U)_{d_i} / (c b_i)` on 𝒜 (the row of `A U = r − c B_Nᵀ λ`), 0 elsewhere;
//! - `g_i = o_i − b_i U_{d_i}` off 𝒜;
//!
//! and likewise when row i is `b_i e_{d_i}ᵀ + Σ_j b_ij e_jᵀ` with a dof d_i of its own (in no
//! other row, and no row's own dof among the j: the slave's normal dof of a node-to-segment pair
//! of two bodies, [`own_dofs`]): on 𝒜 the row ties `U_{d_i} = (o_i − Σ_j b_ij U_j) / b_i`, CG
//! solves `Tᵀ A T Y = Tᵀ (r − A U₀)` on the untied dofs ([`Pcg::set_ties`]; the preconditioner
//! stays A's, its factored block holding both bodies' caps), λ_i is read off row
//! d_i as above and `g_i = o_i − b_i U_{d_i} − Σ_j b_ij U_j` off 𝒜.
//! - 𝒜 ← {i ∈ 𝒜 : λ_i ≥ −τ_λ} ∪ {i ∉ 𝒜 : g_i < −τ_g}, until 𝒜 no longer changes.
//!
//! U starts from the cubic extrapolation `4U_n − 6U_{n−1} + 4U_{n−2} − U_{n−3}` of the previous
//! solutions (error O(Δt⁴) on smooth motion; 9 CG iterations per step on block3d 32³ at
//! Δt = 10⁻³, against 14 from the quadratic one), and 𝒜 from the previous step's updated once
//! with that guess: a point the extrapolated motion pushes through the obstacle enters, a point
//! whose extrapolated λ is negative leaves, before the first CG solve (hertz3d: 1.27 solves per
//! step instead of 1.8, 27 % fewer CG iterations).
//! CG stops at `‖r‖₂ ≤` [`CG_TOLERANCE`] `‖b‖₂`, or, once `‖r‖₂ ≤` [`ACTIVE_SET_CHECK`] `‖b‖₂`,
//! at the first iterate under which 𝒜 would change: that solve is about to be redone on the new
//! set, and 𝒜 is accepted only after a solve to full tolerance that leaves it unchanged
//! (hertz3d n = 20, 60 steps: 2 689 CG iterations instead of 3 036, the same 76 solves).
//! Preconditioner: Jacobi by nodes, with the block of the massless dofs and their neighbours
//! solved by its Cholesky factor in single precision ([`massless_neighbourhood`]).
//!
//! Cost against the mesh (hertz3d, 300 steps, n = 12, 16, 24; 2026-11-24, before the product
//! in vectors and the smaller factored block of 2026-11-28): the CPU time per dof and CG
//! iteration is flat (56.5, 55.4, 54.2 ns), and so are the solves per step (1.05, 1.12, 1.17),
//! but the CG iterations per step grow as n (24.9, 31.9, 49.5, about 2 n): Δt is fixed while
//! h ∝ 1/n, so `k λ_max(M⁻¹K)`, and with it Jacobi's condition number, grows as n². A coarse
//! space of smoothed aggregates (two-level additive, `Pᵀ A P` factored) took the growth of the
//! iterations per solve from n = 16 to 24 from 1.48 to 1.21, but its coarse solve cost more
//! than it saved (CPU 198 s against 138 s at n = 24): it pays only with a recursive (multigrid)
//! coarse level.

use crate::contact::SolveInfo;
use crate::error::{Error, Result, SolverError};
use crate::linalg::{self, row_dot, Pcg, SpMat};
use crate::problem::Problem;

/// Relative residual at which CG stops. 1e-8 was measured to let the energy drift of block3d
/// 32³ (mass redistribution, Newmark ½, ½, Δt = 10⁻³, T = 1) grow from 7.3e-6 to 7.0e-4: the
/// step errors accumulate; at 1e-10 the trajectories agree with the direct solve to 1e-6.
pub const CG_TOLERANCE: f64 = 1e-10;
/// CG iterations allowed per solve.
pub(super) const CG_MAX_ITERATIONS: usize = 5000;
/// Active-set updates allowed per step.
pub(super) const MAX_ACTIVE_SET_UPDATES: usize = 50;
/// Relative residual from which CG stops early at an iterate that changes the active set
/// (hertz3d n = 20, 60 steps: 2 602, 2 631, 2 689 and 2 783 CG iterations from 1e-5, 1e-6,
/// 1e-7 and 1e-8, in 113, 77, 76 and 76 solves; n = 44, the first 100 steps: 9 030, 9 084,
/// 9 222 and 10 112 iterations from 1e-5, 3e-6, 1e-6 and 1e-7, in 352, 200, 177 and 165
/// solves, 184, 159, 158 s wall for the first three: at 1e-5 many early verdicts are spurious,
/// and each costs a solve's two exact products; n = 16, 300 steps: 9 650 against 9 703).
pub(super) const ACTIVE_SET_CHECK: f64 = 1e-6;
/// Relative thresholds τ of the active-set update (above CG's accuracy, so that round-off
/// does not flip a grazing point).
pub(super) const ACTIVE_SET_TOLERANCE: f64 = 1e-8;
/// Name of the step matrix in messages.
const NAME: &str = "step matrix m·M + k·K";

/// A sparse row `(j, v_j)`.
type SparseRow = Vec<(usize, f64)>;
/// Each contact row's own dof and coefficient `(d_i, b_i)`, and the rest of the row.
pub type OwnDofs = (Vec<(usize, f64)>, Vec<SparseRow>);

/// The CG step with its active set and solution history.
pub struct IterativeStep {
    /// Row `d_i` of A at every contact point (A itself lives in the preconditioned CG only).
    rows: Vec<Vec<(usize, f64)>>,
    pcg: Pcg,
    c: f64,
    /// `(d_i, b_i)` of every contact point: its own dof and coefficient in row i of B_N.
    points: Vec<(usize, f64)>,
    /// The rest of row i of B_N, `(j, b_ij)` (empty for nodal contact).
    others: Vec<Vec<(usize, f64)>>,
    /// The active set whose ties CG's matrix has (pair rows only).
    tied: Vec<bool>,
    free: Vec<bool>,
    active: Vec<bool>,
    history: History,
}

/// The last four solutions, newest first, and how many are set: the initial guess of CG.
pub(super) struct History {
    solutions: [Vec<f64>; 4],
    filled: usize,
}

impl History {
    pub(super) fn new(n: usize) -> Self {
        Self {
            solutions: [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            filled: 0,
        }
    }

    /// The initial guess: `u` itself, then the constant, linear, quadratic and cubic
    /// extrapolation of the previous solutions.
    pub(super) fn extrapolate(&self, u: &mut [f64]) {
        let [h0, h1, h2, h3] = &self.solutions;
        match self.filled {
            0 => {}
            1 => u.copy_from_slice(h0),
            2 => linalg::combine(u, (2.0, h0), (-1.0, h1)),
            3 => {
                for (((x, a), b), c) in u.iter_mut().zip(h0).zip(h1).zip(h2) {
                    *x = 3.0 * (a - b) + c;
                }
            }
            _ => {
                for ((((x, a), b), c), d) in u.iter_mut().zip(h0).zip(h1).zip(h2).zip(h3) {
                    *x = 4.0 * (a + c) - 6.0 * b - d;
                }
            }
        }
    }

    pub(super) fn remember(&mut self, u: &[f64]) {
        self.solutions.rotate_right(1);
        self.solutions[0].copy_from_slice(u);
        self.filled = (self.filled + 1).min(4);
    }
}

impl IterativeStep {
    /// Assembles `m M + k K`; `c` is the factor of `B_Nᵀ λ` in the step equation. Errors (naming
    /// why) when the mass is not a sparse matrix or `B_N` is not nodal along axes.
    pub fn new(problem: &Problem, k: &SpMat, (m_coef, k_coef): (f64, f64), c: f64) -> Result<Self> {
        let Some(m) = problem.inertia.sparse() else {
            return Err(Error::Unsupported(
                "linear solver cg: the singular dynamic saddle system is not SPD (use direct)"
                    .into(),
            ));
        };
        let (points, others) = own_dofs(problem)?;
        let a = linalg::lin_comb(m_coef, m, k_coef, k)?;
        let n = a.nrows();
        let b = linalg::node_size(k);
        // Pair rows: each row's dofs on the component of its own dof in the factored block
        // (two_spheres, 300 steps: 24.7 → 19.4 s wall against every dof of the rows, the
        // outputs within 2e-6 relative; 70 s CPU against 78 s for every dof of the rows
        // against the massless dofs alone, measured before).
        let pairs = others.iter().any(|o| !o.is_empty());
        let partners = points.iter().zip(&others).filter(|_| pairs);
        let partners = partners.flat_map(|(&(d, _), row)| {
            let mine = row.iter().filter(move |e| e.0 % b == d % b);
            std::iter::once(d).chain(mine.map(|e| e.0))
        });
        let block = massless_neighbourhood(m, k, b, partners);
        Ok(Self {
            pcg: Pcg::with_block(&a, NAME, block)?,
            rows: points.iter().map(|&(d, _)| column(&a, d)).collect(),
            c,
            active: vec![false; points.len()],
            tied: vec![false; points.len()],
            points,
            others,
            free: vec![true; n],
            history: History::new(n),
        })
    }

    /// Solves `A U = r` without contact.
    pub fn solve_free(&mut self, r: &[f64], u: &mut [f64], w: &mut [f64]) -> Result<()> {
        self.free.fill(true);
        self.active.fill(false);
        self.tie_active();
        self.history.extrapolate(u);
        self.cg(r, u, (0, f64::NAN), None)?;
        self.history.remember(u);
        w.copy_from_slice(u);
        Ok(())
    }

    /// Solves `A U = r − c B_Nᵀ λ` with the complementarity law on `o − B_N U` (`offset` = o;
    /// `o_i = +∞` excludes point i) at `(step, time)` (for messages).
    pub fn solve(
        &mut self,
        (r, offset): (&[f64], &[f64]),
        (u, w): (&mut [f64], &mut [f64]),
        lambda: &mut [f64],
        at: (usize, f64),
    ) -> Result<SolveInfo> {
        self.history.extrapolate(u);
        let tau = thresholds(u, r, self.c);
        // The active set predicted by the extrapolated solution: one update before the first
        // solve, so that the points entering or leaving contact on smooth motion do not cost a
        // second solve.
        self.fix_active(offset, u);
        self.update_active((r, offset), tau, u, lambda);
        for update in 1..=MAX_ACTIVE_SET_UPDATES {
            self.fix_active(offset, u);
            self.cg(r, u, at, Some((offset, tau)))?;
            if !self.update_active((r, offset), tau, u, lambda) {
                self.history.remember(u);
                w.copy_from_slice(u);
                return Ok(SolveInfo {
                    iterations: update,
                    active: self.active.iter().filter(|&&x| x).count(),
                });
            }
        }
        Err(unsettled("the active set of the cg step", at))
    }

    /// Fixes `U_{d_i} = (o_i − Σ_j b_ij U_j) / b_i` on the active points (the gap closed) and
    /// frees the other dofs.
    fn fix_active(&mut self, offset: &[f64], u: &mut [f64]) {
        for (i, &(d, b)) in self.points.iter().enumerate() {
            self.free[d] = !self.active[i];
            if self.active[i] {
                u[d] = (offset[i] - row_dot(&self.others[i], u)) / b;
            }
        }
    }

    /// Gives CG's matrix the ties of the active pair rows, `U_{d_i} = −Σ_j (b_ij / b_i) U_j`
    /// (nothing to do for nodal contact).
    fn tie_active(&mut self) {
        if self.tied == self.active || self.others.iter().all(|o| o.is_empty()) {
            return;
        }
        let ties = (0..self.points.len())
            .filter(|&i| self.active[i])
            .map(|i| {
                let (d, b) = self.points[i];
                (
                    d,
                    self.others[i].iter().map(|&(j, v)| (j, -v / b)).collect(),
                )
            })
            .collect();
        self.pcg.set_ties(ties);
        self.tied.clone_from(&self.active);
    }

    /// One update of the active set from `u` with the thresholds `tau`, writing `λ` on the
    /// active points (0 elsewhere); true when the set changed.
    fn update_active(
        &mut self,
        (r, offset): (&[f64], &[f64]),
        tau: (f64, f64),
        u: &[f64],
        lambda: &mut [f64],
    ) -> bool {
        let law = Signorini::new((&self.rows, &self.others), self.c, (r, offset), tau);
        let mut changed = false;
        for (i, &point) in self.points.iter().enumerate() {
            let (l, flips) = law.verdict(i, point, self.active[i], u);
            lambda[i] = l.max(0.0);
            if flips {
                self.active[i] = !self.active[i];
                changed = true;
            }
        }
        changed
    }

    /// CG on the free dofs; with `(offset, tau)`, it stops early (from a residual of
    /// [`ACTIVE_SET_CHECK`] `‖b‖₂` down) at an iterate under which the active set would change,
    /// since the next update re-solves anyway (the same verdict as [`Self::update_active`]'s).
    fn cg(
        &mut self,
        r: &[f64],
        u: &mut [f64],
        (step, time): (usize, f64),
        stop: Option<(&[f64], (f64, f64))>,
    ) -> Result<()> {
        self.tie_active();
        let Self {
            pcg,
            rows,
            c,
            points,
            others,
            active,
            free,
            ..
        } = self;
        let law = stop.map(|(offset, tau)| Signorini::new((rows, others), *c, (r, offset), tau));
        let changes = |u: &[f64]| {
            law.as_ref().is_some_and(|law| {
                let mut points = points.iter().zip(active.iter()).enumerate();
                points.any(|(i, (&point, &act))| law.verdict(i, point, act, u).1)
            })
        };
        let check = if stop.is_some() {
            ACTIVE_SET_CHECK
        } else {
            0.0
        };
        pcg.solve_until(
            r,
            u,
            free,
            (CG_TOLERANCE, CG_MAX_ITERATIONS),
            (check, changes),
        )
        .map_err(|res| not_converged(res, (step, time)))?;
        Ok(())
    }
}

/// CG stopped at the relative residual `res` after [`CG_MAX_ITERATIONS`] at `(step, time)`.
pub(super) fn not_converged(res: f64, (step, time): (usize, f64)) -> Error {
    Error::ContactSolver {
        step,
        time,
        reason: SolverError::NotConverged {
            method: "cg",
            detail: format!("relative residual {res:.3e} after {CG_MAX_ITERATIONS} iterations"),
        },
    }
}

/// The active set `method` kept changing for [`MAX_ACTIVE_SET_UPDATES`] updates at
/// `(step, time)`.
pub(super) fn unsettled(method: &'static str, (step, time): (usize, f64)) -> Error {
    Error::ContactSolver {
        step,
        time,
        reason: SolverError::NotConverged {
            method,
            detail: format!("no settled set in {MAX_ACTIVE_SET_UPDATES} updates"),
        },
    }
}

/// The Signorini law at the contact points for a step's right-hand side `r` and offsets `o`,
/// with the thresholds of the active-set update.
struct Signorini<'a> {
    /// Row `d_i` of A at every point.
    rows: &'a [Vec<(usize, f64)>],
    /// The rest of row i of B_N.
    others: &'a [Vec<(usize, f64)>],
    c: f64,
    r: &'a [f64],
    offset: &'a [f64],
    tau_g: f64,
    tau_l: f64,
}

impl<'a> Signorini<'a> {
    fn new(
        (rows, others): (&'a [SparseRow], &'a [SparseRow]),
        c: f64,
        (r, offset): (&'a [f64], &'a [f64]),
        (tau_g, tau_l): (f64, f64),
    ) -> Self {
        Self {
            rows,
            others,
            c,
            r,
            offset,
            tau_g,
            tau_l,
        }
    }

    /// Point i = `(d_i, b_i)` under `u`: its multiplier `λ_i = (r − A u)_{d_i} / (c b_i)` when
    /// active (0 otherwise: no other row has d_i), and whether it leaves 𝒜 (`λ_i < −τ_λ`) or
    /// enters it (`g_i = o_i − b_i u_{d_i} − Σ_j b_ij u_j < −τ_g`).
    fn verdict(&self, i: usize, (d, b): (usize, f64), active: bool, u: &[f64]) -> (f64, bool) {
        if active {
            let l = (self.r[d] - row_dot(&self.rows[i], u)) / (self.c * b);
            (l, l < -self.tau_l)
        } else {
            let gap = self.offset[i] - b * u[d] - row_dot(&self.others[i], u);
            (0.0, gap < -self.tau_g)
        }
    }
}

/// The thresholds `(τ_g, τ_λ)` of the active-set update, relative to the scales of the guess `u`
/// and of `r / c` (fixed for a step: the check inside CG and the update give the same verdicts).
fn thresholds(u: &[f64], r: &[f64], c: f64) -> (f64, f64) {
    let scale = |x: &[f64]| x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    (
        ACTIVE_SET_TOLERANCE * scale(u).max(f64::MIN_POSITIVE),
        ACTIVE_SET_TOLERANCE * scale(r).max(f64::MIN_POSITIVE) / c.abs(),
    )
}

/// The dofs the preconditioner factors: the massless dofs (mass redistribution's Γ_C
/// normal dofs, `M_ii = 0`) and the dofs of the same displacement component that K couples to
/// them (on the cells touching them, where mass redistribution changed that component's mass,
/// far from diagonally dominant; the other components keep their consistent mass). Jacobi
/// alone needs about 400 CG iterations per solve on `hertz3d`, 20 to 40 with this block (1 474
/// of 51 651 dofs); the standard mass has no massless dof and keeps plain Jacobi. Every
/// component of those nodes (4 422 dofs) took 1.3 % fewer iterations (9 576 against 9 703 over
/// 300 steps) for a factor of 10 times the entries (612 360 against 58 747), whose solve on
/// one core bounded the CG pass beside it: at n = 44 (1 040 163 dofs, 30 630 against 10 210 in
/// the block, 6.19M against 0.70M entries) 6.0 against 1.2 ms per iteration, 16.1 against 13.1
/// ms for the whole iteration. `b`: dofs per node ([`linalg::node_size`]); the dofs `with`
/// (the contact rows' that the caller factors too) are added, the result in increasing order.
pub(super) fn massless_neighbourhood(
    m: &SpMat,
    k: &SpMat,
    b: usize,
    with: impl IntoIterator<Item = usize>,
) -> Vec<usize> {
    let mass = linalg::diagonal(m);
    let mut block = vec![false; mass.len()];
    for (i, j, _) in linalg::triplets(k) {
        if mass[j] == 0.0 && i % b == j % b {
            block[i] = true;
        }
    }
    for i in with {
        block[i] = true;
    }
    (0..mass.len()).filter(|&i| block[i]).collect()
}

/// Row d of the symmetric `a` (its column d) as `(j, A_dj)`.
fn column(a: &SpMat, d: usize) -> Vec<(usize, f64)> {
    let a = a.as_ref();
    let rows = a.row_idx_of_col_raw(d).iter().copied();
    rows.zip(a.val_of_col(d).iter().copied()).collect()
}

/// Each row i of `B_N` split into its own dof and coefficient `(d_i, b_i)` (the entry of largest
/// |b| among the dofs no other row has; the only entry of a nodal row) and the rest `(j, b_ij)`,
/// none of which is a row's own dof (so that an active row solves for `U_{d_i}` alone: the
/// slave's normal dof of a node-to-segment pair); or why `B_N` has no such split.
pub fn own_dofs(problem: &Problem) -> Result<OwnDofs> {
    if problem.contact.force.is_some() {
        return Err(Error::Unsupported(
            "linear solver cg needs nodal contact, whose force rows are its gap rows (use direct)"
                .into(),
        ));
    }
    let b_n = &problem.contact.b_n;
    let unsupported = |why: String| {
        Error::Unsupported(format!(
            "linear solver cg needs contact rows with a dof of their own: {why} (use direct)"
        ))
    };
    let rows = linalg::rows(b_n);
    let mut uses = vec![0_usize; b_n.ncols()];
    for &(j, _) in rows.iter().flatten() {
        uses[j] += 1;
    }
    let mut own = vec![false; b_n.ncols()];
    let mut points = Vec::with_capacity(rows.len());
    for (i, row) in rows.iter().enumerate() {
        let mine = row.iter().filter(|e| uses[e.0] == 1);
        let best = mine.fold(None, |best: Option<(usize, f64)>, &(j, v)| match best {
            Some((_, w)) if w.abs() >= v.abs() => best,
            _ => Some((j, v)),
        });
        let Some((d, b)) = best else {
            return Err(unsupported(if row.is_empty() {
                format!("row {i} of B_N is empty")
            } else {
                format!("every dof of row {i} of B_N is in another row")
            }));
        };
        own[d] = true;
        points.push((d, b));
    }
    let others: Vec<Vec<(usize, f64)>> = rows
        .into_iter()
        .zip(&points)
        .map(|(row, &(d, _))| row.into_iter().filter(|e| e.0 != d).collect())
        .collect();
    for (i, row) in others.iter().enumerate() {
        if let Some(&(j, _)) = row.iter().find(|e| own[e.0]) {
            return Err(unsupported(format!(
                "dof {j} of row {i} of B_N is another row's own dof"
            )));
        }
    }
    Ok((points, others))
}
