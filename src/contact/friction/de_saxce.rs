//! De Saxcé's modified velocity and the fixed point on its convex relaxation (Acary, Cadoux,
//! Lemaréchal & Malick), each inner problem a conic QP for Clarabel's second-order cones.
//! Sources (`notes/papers/friction.md` §2, siconos/siconos 6070f0f): `friction_contact.rst`
//! lines 27–40 (with `û = u + μ‖u_T‖ e_N`, `C*_μ ∋ û ⊥ r ∈ C_μ` is Signorini + Coulomb),
//! `fc3d_ACLMFixedPoint.c` lines 124–153 (the fixed point) and `fc3d_SOCLCP.c` lines 93–120
//! (the un-iterated relaxation is not Coulomb). Repeat, with `s_i = μ‖u_{T,i}‖` from the
//! previous iterate:
//!
//! `min ½ rᵀ W r + (q + s e_N)ᵀ r  s.t.  (μ r_N, r_T) ∈ SOC` per point,
//!
//! whose KKT conditions are `C*_μ ∋ W r + q + s e_N ⊥ r ∈ C_μ`: in Clarabel's form `A = −D`,
//! `D = diag(μ, 1, …)`, `b = 0`, cone `SecondOrderConeT(d)` with the cone variable t first
//! (`clarabel-0.11.1/src/solver/core/cones/socone.rs` line 105), in units of order one per
//! point ([`Units`]; unscaled, every case failed at its first contact step). A round that
//! Clarabel does not solve to 1e-12 is solved again at 1e-11, then 1e-10 ([`IP_TOLERANCES`]).
//! At a fixed point s = μ‖u_T‖ and û is De Saxcé's: the law holds exactly. The outer loop stops
//! when the Alart–Curnier residual ([`super::alart_curnier`]) is below [`TOLERANCE`] · scale
//! (looser than the other solvers' 1e-11). Once [`STAGNANT`] rounds have not improved it by
//! 1 %, or after [`MAX_FIXED_POINT`] rounds, its best iterate is accepted below [`FLOOR`] ·
//! scale, the square root of the interior point's tolerance, its accuracy on a degenerate pair
//! (a point with no gap and no force, or at the cone's apex; one step of oblique3d and one of
//! slide3d level off at 1.0e-7 and 1.2e-7), and it fails otherwise: the fixed point is not
//! guaranteed to converge (the problem is not convex). Without friction every round is the
//! LCP's QP: it is solved once, as `clarabel` solves it ([`DeSaxce::signorini`]).
//!
//! **Its reach in μ.** At a slipping point the rounds converge linearly, and ever more slowly
//! as μ grows: the shift's error shrinks by `κ = μ(μW_TT − σW_TN)/(W_NN − 2μσW_NT + μ²W_TT)`
//! per round (σ the slip's direction, the point's Delassus block), μ²/(1 + μ²) or more where
//! `W_TT ≥ W_NN` and `W_NT = 0` (slide2d's nodes but its corners), 0.9 at μ = 3, 0.99 at 10,
//! and κ > 1 past μ_c = W_NN/|W_NT| (the slip branch turns over, [`super::alart_curnier`]).
//! Its [`MAX_FIXED_POINT`] rounds cannot bring a residual of order one to [`TOLERANCE`] above
//! [`largest_mu`] = 2.39: a larger μ is refused up front (`--friction`, [`super::by_name`]).
//! Below it the corner coupling can still defeat it (slide2d at h = ⅛ fails from μ = 1.5, slide3d
//! at h = ¼ from 1.2; at h = ½ it converges to 2.39): it fails then, naming μ. Every failure
//! names the solver and μ (`contact.friction`), Clarabel's too (`DeSaxce::named`).

use super::{Coulomb, Local};
use crate::contact::clarabel_qp::{upper, ClarabelQp, Units};
use crate::contact::{SolveInfo, Solver};
use crate::error::SolverError;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector};

/// Relative tolerance on the Alart–Curnier residual at a fixed point.
pub const TOLERANCE: f64 = 1e-7;

/// The residual accepted when the rounds stop improving: √1e-12, the interior point's accuracy
/// on a degenerate pair.
pub const FLOOR: f64 = 1e-6;

/// Fixed-point rounds allowed per step.
pub const MAX_FIXED_POINT: usize = 100;

/// The largest μ the fixed point can take: `κ^MAX_FIXED_POINT ≤ TOLERANCE` for
/// `κ = μ²/(1 + μ²)`, 2.39. At a slipping point the rounds are an affine map of the shift with
/// slope `κ = μ(μW_TT − σW_TN)/(W_NN − 2μσW_NT + μ²W_TT)` (σ the slip's direction; the point's
/// Delassus block), so the residual shrinks by κ per round; with `W_NT = 0` and `W_TT ≥ W_NN`
/// (slide2d's nodes but its corners: `W_TT/W_NN` = 1.00 to 1.04) κ ≥ μ²/(1 + μ²), and above
/// this μ the rounds allowed cannot bring a residual of order one to the tolerance (measured:
/// 7.5e-5 after 100 rounds at μ = 3 on slide2d, h = ½, against κ¹⁰⁰ = 2.7e-5), whatever the
/// interior point's accuracy. It is refused up front ([`super::by_name`]).
pub fn largest_mu() -> f64 {
    let kappa = TOLERANCE.powf(1.0 / MAX_FIXED_POINT as f64);
    (kappa / (1.0 - kappa)).sqrt()
}

/// Rounds in a row without a 1 % decrease of the best residual after which the fixed point
/// stops: it has reached the interior point's accuracy.
pub const STAGNANT: usize = 5;

/// The interior point's tolerances (gap and feasibility, in the round's units of order one),
/// tightest first: a round that ends otherwise than solved at one is solved again at the next.
pub const IP_TOLERANCES: [f64; 3] = [1e-12, 1e-11, 1e-10];

/// The fixed point with Clarabel's interior point for each round.
#[derive(Debug, Clone)]
pub struct DeSaxce {
    law: Coulomb,
    settings: Vec<DefaultSettings<f64>>,
    /// The LCP's solver, without friction.
    lcp: ClarabelQp,
}

impl DeSaxce {
    /// For `law`, interior point to [`IP_TOLERANCES`] without console output.
    pub fn new(law: Coulomb) -> Self {
        let settings = IP_TOLERANCES
            .iter()
            .map(|&tol| {
                DefaultSettingsBuilder::default()
                    .verbose(false)
                    .max_iter(200)
                    .tol_gap_abs(tol)
                    .tol_gap_rel(tol)
                    .tol_feas(tol)
                    .tol_ktratio(tol * 100.0)
                    .build()
                    .expect("constant Clarabel settings are valid")
            })
            .collect();
        Self {
            law,
            settings,
            lcp: ClarabelQp::new(),
        }
    }

    /// One convex round: the reaction for the shifts `s` (per point), and the interior point's
    /// iterations.
    fn round(&self, loc: &Local, s: &[f64]) -> Result<(DVector<f64>, usize), SolverError> {
        let (k, dim) = (loc.q.len(), loc.dim);
        let mut q: Vec<f64> = loc.q.iter().copied().collect();
        for (pt, si) in s.iter().enumerate() {
            q[pt * dim] += si;
        }
        let Some(units) = Units::new(&loc.w, &q, dim)? else {
            return Ok((DVector::zeros(k), 0));
        };
        let (p, q) = (upper(&units.matrix(&loc.w)), units.load(&q));
        // A = −D (diagonal), b = 0: the slack is D r.
        let diag: Vec<f64> = (0..k)
            .map(|a| {
                if a % dim == 0 && dim > 1 {
                    -loc.mu[a / dim]
                } else {
                    -1.0
                }
            })
            .collect();
        let a = CscMatrix::new(k, k, (0..=k).collect(), (0..k).collect(), diag);
        let b = vec![0.0; k];
        let cones: Vec<SupportedConeT<f64>> = if dim == 1 {
            vec![SupportedConeT::NonnegativeConeT(k)]
        } else {
            (0..loc.points.len())
                .map(|_| SupportedConeT::SecondOrderConeT(dim))
                .collect()
        };
        let (mut iterations, mut statuses) = (0, Vec::new());
        for settings in &self.settings {
            let mut solver =
                DefaultSolver::new(&p, &q, &a, &b, &cones, settings.clone()).map_err(|e| {
                    SolverError::Clarabel {
                        status: format!("setup failed: {e}"),
                    }
                })?;
            solver.solve();
            iterations += solver.info.iterations as usize;
            let status = solver.solution.status;
            // Almost solved at a tighter rung is kept: the outer loop's residual judges it.
            if matches!(status, SolverStatus::Solved | SolverStatus::AlmostSolved) {
                let r = DVector::from_vec(units.unscale(&solver.solution.x));
                return Ok((r, iterations));
            }
            statuses.push(format!("{status:?}"));
        }
        Err(SolverError::Clarabel {
            status: statuses.join(", then "),
        })
    }

    /// Without friction (the shifts 0) De Saxcé's relaxation is the LCP's convex QP on the
    /// normal rows, solved once as [`ClarabelQp`] does, with its polish on the active set: the
    /// interior point alone leaves points with no gap and no force at the square root of its
    /// tolerance. The tangential rows (μ = 0) get no force.
    fn signorini(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> Result<SolveInfo, SolverError> {
        let n = self.law.points;
        lambda[n..].fill(0.0);
        let normal = d.view((0, 0), (n, n)).into_owned();
        self.lcp.solve(&normal, &q[..n], &mut lambda[..n])
    }
}

/// `s_i = μ ‖u_{T,i}‖` at `r`.
fn shifts(loc: &Local, r: &DVector<f64>) -> Vec<f64> {
    let (u, dim) = (loc.velocity(r), loc.dim);
    (0..loc.points.len())
        .map(|p| {
            let t = (1..dim).map(|c| u[p * dim + c].powi(2)).sum::<f64>();
            loc.mu[p] * t.sqrt()
        })
        .collect()
}

impl Solver for DeSaxce {
    fn name(&self) -> &'static str {
        "de_saxce"
    }

    fn signorini(&self) -> bool {
        self.law.is_signorini()
    }

    fn solve(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> Result<SolveInfo, SolverError> {
        if self.law.is_signorini() {
            let lcp = self.signorini(d, q, lambda);
            return lcp.map_err(|e| self.named(e, None));
        }
        let (loc, r) =
            Local::gather(&self.law, d, q, lambda, None).map_err(|e| self.named(e, None))?;
        if loc.points.is_empty() {
            lambda.fill(0.0);
            return Ok(SolveInfo::default());
        }
        let (r, iterations) = self.fixed_point(&loc, r)?;
        Ok(loc.finish(&self.law, &r, lambda, iterations))
    }
}

impl DeSaxce {
    /// `e` as this solver's failure, naming the solver and μ (`contact.friction`) where it does
    /// not already (Clarabel's statuses, a Delassus block that is not positive definite).
    fn named(&self, e: SolverError, round: Option<usize>) -> SolverError {
        match e {
            SolverError::NotConverged {
                method: "de_saxce", ..
            } => e,
            other => SolverError::NotConverged {
                method: "de_saxce",
                detail: format!(
                    "{other}{} on {} points, with μ = {:?} (contact.friction)",
                    round.map_or(String::new(), |k| format!(" in fixed-point round {k}")),
                    self.law.points,
                    self.law.mu
                ),
            },
        }
    }

    /// The fixed point from `r`: its solution and the interior point's iterations.
    fn fixed_point(
        &self,
        loc: &Local,
        mut r: DVector<f64>,
    ) -> Result<(DVector<f64>, usize), SolverError> {
        let (mut iterations, mut best, mut stagnant, mut done) =
            (0, (f64::INFINITY, r.clone()), 0, 0);
        while done < MAX_FIXED_POINT && stagnant < STAGNANT {
            let (next, its) = self
                .round(loc, &shifts(loc, &r))
                .map_err(|e| self.named(e, Some(done + 1)))?;
            (iterations, done, r) = (iterations + its, done + 1, next);
            let (norm, converged) = loc.converged(&r, TOLERANCE);
            if converged {
                return Ok((r, iterations));
            }
            stagnant = if norm < 0.99 * best.0 {
                0
            } else {
                stagnant + 1
            };
            if norm < best.0 {
                best = (norm, r.clone());
            }
        }
        // The rounds stopped improving, or ran out: the best within the interior point's floor.
        let (norm, r) = best;
        if loc.converged(&r, FLOOR).1 {
            return Ok((r, iterations));
        }
        let why = if stagnant == STAGNANT {
            format!(" (the last {STAGNANT} without progress)")
        } else {
            String::new()
        };
        Err(loc.not_converged(
            ("de_saxce", &self.law),
            &r,
            (norm, FLOOR),
            format!("{done} fixed-point rounds{why}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::super::alart_curnier::AlartCurnier;
    use super::super::testing::{two_points, violation};
    use super::*;

    #[test]
    fn agrees_with_alart_curnier_on_coupled_points() {
        for mu in [0.1, 0.5, 2.0] {
            let (law, w) = two_points(mu);
            for q in [
                [-1.0, -0.5, 0.8, -0.1],
                [-1.0, 0.5, 0.1, 3.0],
                [0.2, 0.3, 1.0, 1.0],
            ] {
                let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
                AlartCurnier::new(law).solve(&w, &q, &mut a).unwrap();
                DeSaxce::new(law).solve(&w, &q, &mut b).unwrap();
                let v = violation(&law, &w, &q, &b);
                assert!(
                    v < 1e-7,
                    "μ {mu}, q {q:?}: {b:?} against {a:?}, violation {v:e}"
                );
                let diff = a
                    .iter()
                    .zip(&b)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max);
                assert!(diff < 1e-7, "μ {mu}, q {q:?}: {a:?} against {b:?}");
            }
        }
    }

    /// Above the μ its rounds can reach it is refused up front, naming `--friction`; at it, it
    /// is taken.
    #[test]
    fn a_mu_beyond_its_reach_is_refused() {
        let law = |mu| two_points(mu).0;
        assert!((largest_mu() - 2.39).abs() < 0.01, "{}", largest_mu());
        for mu in [3.0, 100.0, 1e15] {
            let e = super::super::by_name("de_saxce", law(mu)).err().unwrap();
            let text = e.to_string();
            assert!(
                text.contains("contact.friction") && text.contains("--friction"),
                "{text}"
            );
        }
        assert!(super::super::by_name("de_saxce", law(largest_mu())).is_ok());
    }

    /// Every failure names the solver and μ, an interior point's status too.
    #[test]
    fn its_failures_name_it_and_mu() {
        let (law, _) = two_points(1.5);
        let e = DeSaxce::new(law).named(
            SolverError::Clarabel {
                status: "InsufficientProgress".into(),
            },
            Some(3),
        );
        let text = e.to_string();
        for part in [
            "de_saxce",
            "InsufficientProgress",
            "round 3",
            "μ = 1.5 (contact.friction)",
        ] {
            assert!(text.contains(part), "{part}: {text}");
        }
    }

    #[test]
    fn three_d_point_on_the_cone() {
        let law = Coulomb {
            mu: 0.4,
            points: 1,
            tangents: 2,
            frictionless: 0,
        };
        #[rustfmt::skip]
        let w = DMatrix::from_row_slice(3, 3, &[
            1.0, 0.1, 0.0,
            0.1, 1.5, 0.2,
            0.0, 0.2, 0.8,
        ]);
        let q = [-1.0, 1.0, -2.0];
        let (mut a, mut b) = ([0.0; 3], [0.0; 3]);
        AlartCurnier::new(law).solve(&w, &q, &mut a).unwrap();
        DeSaxce::new(law).solve(&w, &q, &mut b).unwrap();
        let diff = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(diff < 1e-7, "{a:?} against {b:?}");
    }
}
