//! The step with a compliant contact law solved without a factorisation: Nitsche's law
//! `λ_i = [R_i U − o_i]₊ / ε_i` at the quadrature points of Γ_C ([`crate::contact::nitsche`], θ = 1,
//! where the force rows are the gap rows R and ε_i = γ_i / w_i), by a semismooth Newton method
//! whose linear solves are preconditioned CG on the constant step matrix plus the active points'
//! terms: on the active set 𝒜 the step `A U = r − c Rᵀ λ` is
//!
//! `(A + c Σ_{i∈𝒜} ε_i⁻¹ R_iᵀ R_i) U = r + c Σ_{i∈𝒜} ε_i⁻¹ o_i R_iᵀ`
//!
//! (SPD), then 𝒜 ← {i : R_i U − o_i > τ} ∪ {i ∈ 𝒜 : R_i U − o_i ≥ −τ}, until 𝒜 no longer changes;
//! the same solution as the direct step's Newton method on the Delassus operator, to CG's
//! tolerance. The preconditioner is the cg step's (Jacobi by nodes, the massless dofs and their
//! neighbours factored), with the rows' dofs on their leading component in the factored block
//! ([`leading_component`]), factored again with the active terms when 𝒜 changes (the terms' entries
//! outside the block, about 1/γ₀ of those inside, are left to the product: with every dof of the
//! rows in the block the default sphere took 19.5–21.1 s wall against 13.9–14.2 s, 652 solves
//! against 649, the outputs within 3.5e-4 relative); U starts from the cubic extrapolation and 𝒜
//! from the previous step's, updated once from that guess. A solve stops early, from a residual of
//! [`ACTIVE_SET_CHECK`] ‖b‖ down, at the first iterate under which 𝒜 would change (the nodal cg
//! step's rule; measured from 1e-7 ‖b‖): hertz3d 54.5 → 42.5 s CPU, 38.0 → 32.4 s wall (2026-11-25,
//! quiet machine; nodal 24 s CPU, 14.5 s wall), the probe's displacement and force within 3.2e-7 of
//! their largest values. The block is analysed once for every point's terms
//! ([`Pcg::reserve_rank_one`]), so that a change of 𝒜 refactors values only: 46.0 → 35.4 s CPU,
//! 36.2 → 25.8 s wall, the same outputs to the last digit.
//!
//! Measured on the default hertz3d sphere (mass redistribution, 51 651 dofs × 300 steps, load
//! average about 6, `/usr/bin/time`): 61 s CPU, 75 s wall, 0.46 GB, against 168 s CPU, 365 s
//! wall, 1.49 GB with the direct factor, and 30 s CPU, 42 s wall for the nodal contact (cg);
//! the probe's displacement and total force agree with the direct step's to 2e-7 relative.

use super::iterative::{
    massless_neighbourhood, not_converged, unsettled, History, ACTIVE_SET_CHECK,
    ACTIVE_SET_TOLERANCE, CG_MAX_ITERATIONS, CG_TOLERANCE, MAX_ACTIVE_SET_UPDATES,
};
use crate::contact::SolveInfo;
use crate::error::{Error, Result};
use crate::linalg::{self, Pcg, SpMat};
use crate::problem::Problem;

/// Name of the step matrix in messages.
const NAME: &str = "step matrix m·M + k·K with the active Nitsche terms";

/// The CG step of a compliant law with its active set and solution history.
pub struct CompliantStep {
    pcg: Pcg,
    /// The gap rows R_i (also the force rows).
    rows: Vec<Vec<(usize, f64)>>,
    /// `c / ε_i` of every point.
    stiffness: Vec<f64>,
    c: f64,
    active: Vec<bool>,
    all: Vec<bool>,
    rhs: Vec<f64>,
    history: History,
}

impl CompliantStep {
    /// Assembles `m M + k K`; `c` is the factor of `Rᵀ λ` in the step equation and `compliance`
    /// the law's ε_i. Errors (naming why) when the mass is not a sparse matrix or the force rows
    /// are not the gap rows (θ ≠ 1: the system is not symmetric).
    pub fn new(
        problem: &Problem,
        k: &SpMat,
        (m_coef, k_coef): (f64, f64),
        c: f64,
        compliance: &[f64],
    ) -> Result<Self> {
        symmetric_law(problem)?;
        let Some(m) = problem.inertia.sparse() else {
            return Err(Error::Unsupported(
                "linear solver cg: the singular dynamic saddle system is not SPD (use direct)"
                    .into(),
            ));
        };
        let a = linalg::lin_comb(m_coef, m, k_coef, k)?;
        let n = a.nrows();
        let rows = linalg::rows(&problem.contact.b_n);
        let b = linalg::node_size(k);
        let leading = rows.iter().flat_map(|row| leading_component(row, b));
        let block = massless_neighbourhood(m, k, b, leading);
        let mut pcg = Pcg::with_block(&a, NAME, block)?;
        pcg.reserve_rank_one(&rows, NAME)?;
        Ok(Self {
            pcg,
            stiffness: compliance.iter().map(|e| c / e).collect(),
            c,
            active: vec![false; rows.len()],
            rows,
            all: vec![true; n],
            rhs: vec![0.0; n],
            history: History::new(n),
        })
    }

    /// Solves `A U = r` without contact.
    pub fn solve_free(&mut self, r: &[f64], u: &mut [f64], w: &mut [f64]) -> Result<()> {
        let none = vec![false; self.rows.len()];
        self.set_active(none)?;
        self.history.extrapolate(u);
        self.cg(r, u, (0, f64::NAN), None)?;
        self.history.remember(u);
        w.copy_from_slice(u);
        Ok(())
    }

    /// Solves `A U = r − c Rᵀ λ` with Nitsche's law on `o − R U` (`offset` = o; `o_i = +∞`
    /// excludes point i) at `(step, time)` (for messages).
    pub fn solve(
        &mut self,
        (r, offset): (&[f64], &[f64]),
        (u, w): (&mut [f64], &mut [f64]),
        lambda: &mut [f64],
        at: (usize, f64),
    ) -> Result<SolveInfo> {
        self.history.extrapolate(u);
        let tau = ACTIVE_SET_TOLERANCE * u.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
        let mut next = self.next_active(offset, u, tau);
        for update in 1..=MAX_ACTIVE_SET_UPDATES {
            self.set_active(next)?;
            self.rhs.copy_from_slice(r);
            for (i, row) in self.rows.iter().enumerate().filter(|e| self.active[e.0]) {
                for &(j, v) in row {
                    self.rhs[j] += self.stiffness[i] * offset[i] * v;
                }
            }
            let rhs = std::mem::take(&mut self.rhs);
            let solved = self.cg(&rhs, u, at, Some((offset, tau)));
            self.rhs = rhs;
            solved?;
            next = self.next_active(offset, u, tau);
            if next == self.active {
                for (i, l) in lambda.iter_mut().enumerate() {
                    *l = if self.active[i] {
                        (self.stiffness[i] / self.c * penetration((&self.rows[i], offset[i]), u))
                            .max(0.0)
                    } else {
                        0.0
                    };
                }
                self.history.remember(u);
                w.copy_from_slice(u);
                return Ok(SolveInfo {
                    iterations: update,
                    active: self.active.iter().filter(|&&a| a).count(),
                });
            }
        }
        Err(unsettled("the active set of the cg step (Nitsche)", at))
    }

    /// The active set under `u`: a point enters when it penetrates by more than τ, leaves when
    /// its gap opens by more than τ (excluded points never enter).
    fn next_active(&self, offset: &[f64], u: &[f64], tau: f64) -> Vec<bool> {
        (0..self.rows.len())
            .map(|i| stays_active(self.active[i], (&self.rows[i], offset[i]), u, tau))
            .collect()
    }

    /// Makes `active` the active set, with its terms in CG's matrix.
    fn set_active(&mut self, active: Vec<bool>) -> Result<()> {
        if active == self.active {
            return Ok(());
        }
        let kappa: Vec<f64> = (self.stiffness.iter().zip(&active))
            .map(|(&k, &on)| if on { k } else { 0.0 })
            .collect();
        self.active = active;
        self.pcg.set_reserved_rank_one(&kappa, NAME)
    }

    /// CG on the step matrix with the active terms; with `(offset, τ)`, it stops early (from a
    /// residual of [`ACTIVE_SET_CHECK`] `‖b‖₂` down) at an iterate under which the active set
    /// would change, since the next update re-solves anyway (as the nodal cg step does).
    fn cg(
        &mut self,
        r: &[f64],
        u: &mut [f64],
        at: (usize, f64),
        stop: Option<(&[f64], f64)>,
    ) -> Result<()> {
        let Self {
            pcg, rows, active, ..
        } = self;
        let changes = |u: &[f64]| {
            stop.is_some_and(|(offset, tau)| {
                (0..rows.len())
                    .any(|i| stays_active(active[i], (&rows[i], offset[i]), u, tau) != active[i])
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
            &self.all,
            (CG_TOLERANCE, CG_MAX_ITERATIONS),
            (check, changes),
        )
        .map_err(|res| not_converged(res, at))?;
        Ok(())
    }
}

/// `R_i u − o_i` of a point with gap row `R_i` and offset `o_i` (> 0: it penetrates).
fn penetration((row, offset): (&[(usize, f64)], f64), u: &[f64]) -> f64 {
    linalg::row_dot(row, u) - offset
}

/// Whether a point with gap row `R_i` and offset `o_i` is active under `u`: it enters when it
/// penetrates (`R_i u − o_i`) by more than τ, leaves when its gap opens by more than τ; an
/// excluded point (`o_i = +∞`) never enters.
fn stays_active(active: bool, point: (&[(usize, f64)], f64), u: &[f64], tau: f64) -> bool {
    let p = penetration(point, u);
    point.1.is_finite() && if active { p >= -tau } else { p > tau }
}

/// Refuses a law whose force rows differ from its gap rows (Nitsche with θ ≠ 1): its step
/// matrix is not symmetric.
pub fn symmetric_law(problem: &Problem) -> Result<()> {
    let c = &problem.contact;
    let same = c
        .force
        .as_ref()
        .is_none_or(|f| linalg::triplets(f).eq(linalg::triplets(&c.b_n)));
    if same {
        Ok(())
    } else {
        Err(Error::Unsupported(
            "linear solver cg needs a symmetric contact law (nitsche_theta = 1: the force rows \
             are the gap rows; use direct)"
                .into(),
        ))
    }
}

/// The dofs of the sparse `row` on the displacement component (of `b` per node) of its largest
/// entry: for a Nitsche row `u_N − γ σ_N(u)` on a plane normal to an axis, the normal
/// component, which carries `u_N`'s shape-function values; γ σ_N's entries on the other
/// components are about 1/γ₀ of them (γ = h/(γ₀ E)).
fn leading_component(row: &[(usize, f64)], b: usize) -> impl Iterator<Item = usize> + '_ {
    let top = row.iter().max_by(|p, q| p.1.abs().total_cmp(&q.1.abs()));
    let component = top.map(|e| e.0 % b);
    row.iter()
        .filter(move |e| Some(e.0 % b) == component)
        .map(|e| e.0)
}
