//! Semismooth Newton on the Alart–Curnier function (Alart & Curnier 1991), as Siconos writes it:
//! `computeAlartCurnierSTD`, `numerics/src/FrictionContact/fc3d_AlartCurnier_functions.c`
//! lines 506–646 (siconos/siconos 6070f0f; `notes/papers/friction.md` §1). Per point, with
//! `ρ > 0`:
//!
//! `RV_N = r_N − ρ u_N`,  `RV_T = r_T − ρ u_T`,  `R = μ max(0, RV_N)`,
//! `F_N = r_N − max(0, RV_N)`,  `F_T = r_T − proj_{disc(R)}(RV_T)`,
//!
//! and `F(r) = 0` with `u = q + W r` is exactly Signorini + Coulomb. Newton solves
//! `(A W + B) Δr = −F` with the generalized Jacobians `A = ∂F/∂u`, `B = ∂F/∂r` (stick:
//! `A_TT = ρ I`; slip: `A_TN = μρ n̂`, `A_TT = ρ R Γ`, `B_TN = −μ n̂`, `B_TT = I − R Γ`,
//! `n̂ = RV_T/‖RV_T‖`, `Γ = (I − n̂n̂ᵀ)/‖RV_T‖`; open: `B = I`), a dense LU on the points in the
//! step, with a backtracking line search on ‖F‖. ρ = 1/W_NN per point (Siconos' scaled ρ: an
//! unscaled ρ stalls when W is far from 1). Stops at `‖F‖ ≤` [`super::TOLERANCE`] · scale.
//!
//! **Past μ_c = W_NN/|W_NT|.** On a slipping point the Jacobian's block is
//! `[[ρW_NN, ρW_NT], [μσ(ρW_NN − 1), 1 + μσρW_NT]]` (2D, σ = −n̂), of determinant
//! `ρ(W_NN − μσW_NT)` whatever ρ: along the slip the normal reaction presses the point in
//! (`∂u_N/∂r_N = W_NN − μσW_NT`), and beyond `μ_c = W_NN/|W_NT|` the slip branch of that point
//! turns over. ‖F‖ then has stationary points that are no solution, where the line search finds
//! no decrease: a block's corner node couples by `W_NT/W_NN = 0.31` on slide2d at h = ⅛
//! (μ_c = 3.2), and from μ = 4 Newton cycled between them for its 100 iterations (taking the full
//! step where the line search failed). The law still has a solution for every μ (W SPD, Acary,
//! Cadoux, Lemaréchal & Malick 2011), and at μ = 0 it is the LCP's, unique. So when Newton fails
//! at μ (the iterations above, unchanged where they converge), the solution is followed from
//! μ = 0: Newton from the last solution at μ_{k+1} = μ_k + Δ, Δ doubled after a stage that
//! converges and quartered after one that stalls (the first min(μ, 1)/64, at most
//! [`CONTINUATION_ITERATIONS`] in all). Where the path folds back (a stage of 10⁻⁶ μ stalls:
//! met between two bodies at large μ, not on a rigid plane), Newton at μ from the fold's solution
//! is the last try; then it fails, naming the μ reached.

use super::{Coulomb, Local, TOLERANCE};
use crate::contact::{SolveInfo, Solver};
use crate::error::SolverError;
use nalgebra::{DMatrix, DVector};

/// Newton iterations allowed per step.
pub const MAX_ITERATIONS: usize = 100;

/// Halvings of the line search before Newton is said to stall.
const LINE_SEARCH: usize = 30;

/// Newton iterations allowed to the continuation in μ, all its stages together.
pub const CONTINUATION_ITERATIONS: usize = 2000;

/// The continuation's first stage, a fraction of min(μ, 1) (doubled after each stage that
/// converges, quartered after one that does not): μ is a slope, the cone's opening reaches 45°
/// at 1, and the law's character changes below some μ of order one (`docs/methods.md`).
const FIRST_STEP: f64 = 1.0 / 64.0;

/// The shortest stage of the continuation, relative to the μ it reaches.
const SMALLEST_STEP: f64 = 1e-6;

/// The Alart–Curnier function of one point and its generalized Jacobians (`dim` ≤ 3 rows).
#[derive(Debug, Clone, Copy, Default)]
pub struct PointResidual {
    /// F.
    pub f: [f64; 3],
    /// ∂F/∂u.
    pub a: [[f64; 3]; 3],
    /// ∂F/∂r.
    pub b: [[f64; 3]; 3],
}

/// `F`, `∂F/∂u`, `∂F/∂r` at one point (`r`, `u`: normal first, then its tangents).
pub fn point(mu: f64, rho: f64, r: &[f64], u: &[f64]) -> PointResidual {
    let dim = r.len();
    let mut out = PointResidual::default();
    let rv_n = r[0] - rho * u[0];
    if rv_n > 0.0 {
        out.f[0] = rho * u[0];
        out.a[0][0] = rho;
    } else {
        out.f[0] = r[0];
        out.b[0][0] = 1.0;
    }
    if dim == 1 {
        return out;
    }
    let radius = mu * rv_n.max(0.0);
    let mut rv_t = [0.0; 2];
    for ((x, rc), uc) in rv_t.iter_mut().zip(&r[1..]).zip(&u[1..]) {
        *x = rc - rho * uc;
    }
    let norm = rv_t.iter().map(|x| x * x).sum::<f64>().sqrt();
    if radius > 0.0 && norm <= radius {
        // Stick: F_T = ρ u_T.
        for (c, uc) in u.iter().enumerate().skip(1) {
            out.f[c] = rho * uc;
            out.a[c][c] = rho;
        }
    } else if radius == 0.0 {
        // Open (or no friction force available): F_T = r_T.
        for (c, rc) in r.iter().enumerate().skip(1) {
            out.f[c] = *rc;
            out.b[c][c] = 1.0;
        }
    } else {
        // Slip: F_T = r_T − R n̂.
        let n: Vec<f64> = rv_t[..dim - 1].iter().map(|x| x / norm).collect();
        for c in 1..dim {
            out.f[c] = r[c] - radius * n[c - 1];
            out.a[c][0] = mu * rho * n[c - 1];
            out.b[c][0] = -mu * n[c - 1];
            for e in 1..dim {
                let delta = if c == e { 1.0 } else { 0.0 };
                let gamma = (delta - n[c - 1] * n[e - 1]) / norm;
                out.a[c][e] = rho * radius * gamma;
                out.b[c][e] = delta - radius * gamma;
            }
        }
    }
    out
}

/// `F(r)` on the local problem and, when asked, `J = A W + B`.
pub(crate) fn residual(
    loc: &Local,
    r: &DVector<f64>,
    jacobian: bool,
) -> (DVector<f64>, Option<DMatrix<f64>>) {
    let u = loc.velocity(r);
    let (k, dim) = (r.len(), loc.dim);
    let mut f = DVector::zeros(k);
    let mut jac = jacobian.then(|| DMatrix::zeros(k, k));
    for p in 0..loc.points.len() {
        let s = p * dim;
        let res = point(
            loc.mu[p],
            loc.rho[p],
            &r.as_slice()[s..s + dim],
            &u.as_slice()[s..s + dim],
        );
        for c in 0..dim {
            f[s + c] = res.f[c];
        }
        if let Some(j) = jac.as_mut() {
            for c in 0..dim {
                for e in 0..dim {
                    j[(s + c, s + e)] += res.b[c][e];
                    if res.a[c][e] != 0.0 {
                        for col in 0..k {
                            j[(s + c, col)] += res.a[c][e] * loc.w[(s + e, col)];
                        }
                    }
                }
            }
        }
    }
    (f, jac)
}

/// The semismooth Newton solver of the Coulomb–Signorini problem.
#[derive(Debug, Clone)]
pub struct AlartCurnier {
    law: Coulomb,
    /// Nitsche's `c_i = γ_i/w_i` per point (None: Signorini–Coulomb).
    compliance: Option<Vec<f64>>,
}

impl AlartCurnier {
    /// For `law`.
    pub fn new(law: Coulomb) -> Self {
        Self {
            law,
            compliance: None,
        }
    }

    /// Nitsche's law with friction ([`crate::contact::nitsche`]): `c r = P_{n,μ}(−u)` per point,
    /// `c = γ/w`, which is Coulomb–Signorini's law on `ũ = u + c r = q + (D + diag(c)) r`; with
    /// `ρ = 1/c` the Alart–Curnier function is that projection's residual itself.
    pub fn nitsche(law: Coulomb, compliance: Vec<f64>) -> Self {
        Self {
            law,
            compliance: Some(compliance),
        }
    }
}

impl Solver for AlartCurnier {
    fn name(&self) -> &'static str {
        match self.compliance {
            None => "alart_curnier",
            Some(_) => "nitsche_alart_curnier",
        }
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
        let (mut loc, start) = Local::gather(&self.law, d, q, lambda, self.compliance.as_deref())?;
        let (mut r, mut iterations) = (start.clone(), 0);
        if newton(&loc, &mut r, &mut iterations, MAX_ITERATIONS, true) == Outcome::Converged {
            return Ok(loc.finish(&self.law, &r, lambda, iterations));
        }
        // Newton stalled (or ran out): follow the solution from μ = 0 instead.
        let plain = iterations;
        let target = loc.mu.clone();
        let top = target.iter().copied().fold(0.0, f64::max);
        let (mut mu, mut step) = (0.0, FIRST_STEP * top.min(1.0));
        r.copy_from(&start);
        loc.mu.fill(0.0);
        let mut reached = newton(&loc, &mut r, &mut iterations, plain + MAX_ITERATIONS, false);
        while reached == Outcome::Converged && mu < top {
            let next = (mu + step).min(top);
            for (m, m0) in loc.mu.iter_mut().zip(&target) {
                *m = m0 * (next / top);
            }
            let mut trial = r.clone();
            let limit = (iterations + MAX_ITERATIONS).min(plain + CONTINUATION_ITERATIONS);
            reached = newton(&loc, &mut trial, &mut iterations, limit, false);
            if reached == Outcome::Converged {
                (mu, r, step) = (next, trial, 2.0 * step);
            } else if step > SMALLEST_STEP * next && iterations < plain + CONTINUATION_ITERATIONS {
                // Too far along the path for Newton from the last solution: a shorter stage.
                (reached, step) = (Outcome::Converged, 0.25 * step);
            } else {
                // The path folds back here: Newton at μ itself from its last solution.
                loc.mu.copy_from_slice(&target);
                let limit = iterations + MAX_ITERATIONS;
                reached = newton(&loc, &mut r, &mut iterations, limit, true);
                break;
            }
        }
        if reached == Outcome::Converged {
            return Ok(loc.finish(&self.law, &r, lambda, iterations));
        }
        let norm = loc.converged(&r, TOLERANCE).0;
        Err(loc.not_converged(
            ("alart_curnier", &self.law),
            &r,
            (norm, TOLERANCE),
            format!(
                "{iterations} Newton iterations ({plain} at μ, then a continuation from μ = 0 \
                 that stopped at μ = {mu:.6e})"
            ),
        ))
    }
}

/// How a run of [`newton`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    /// Within the tolerance.
    Converged,
    /// The line search found no decrease of ‖F‖: a stationary point of ‖F‖ that is no solution.
    Stalled,
    /// `limit` iterations reached.
    Exhausted,
}

/// Newton's iterations on `loc` from `r` until converged, stalled, or `iterations` reaches
/// `limit` (`iterations` counts them). With `full`, a step the line search cannot shorten into
/// a decrease is taken whole (the iterate leaves the stationary point, ‖F‖ may grow) instead of
/// stopping there.
fn newton(
    loc: &Local,
    r: &mut DVector<f64>,
    iterations: &mut usize,
    limit: usize,
    full: bool,
) -> Outcome {
    loop {
        if loc.converged(r, TOLERANCE).1 {
            return Outcome::Converged;
        }
        if *iterations >= limit {
            return Outcome::Exhausted;
        }
        let (f, jac) = residual(loc, r, true);
        let norm = f.norm();
        // A singular Jacobian (a slip branch at the edge of existence) gives no direction.
        let Some(dr) = jac.and_then(|j| j.lu().solve(&(-f))) else {
            return Outcome::Stalled;
        };
        *iterations += 1;
        let mut t = 1.0;
        for _ in 0..LINE_SEARCH {
            let trial = residual(loc, &(&*r + t * &dr), false).0.norm();
            if trial <= (1.0 - 1e-4 * t) * norm {
                *r += t * &dr;
                break;
            }
            t *= 0.5;
        }
        if t < 0.5f64.powi(LINE_SEARCH as i32 - 1) {
            if !full {
                return Outcome::Stalled;
            }
            *r += &dr;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{two_points, violation};
    use super::*;

    #[test]
    fn one_point_slides_with_the_coulomb_force() {
        // W = I: pushed into the plane (q_N = −1) and along t (q_T = 2): r_N = 1, slip
        // u_T = 2 + r_T with r_T = −μ r_N = −0.3.
        let law = Coulomb {
            mu: 0.3,
            points: 1,
            tangents: 1,
            frictionless: 0,
        };
        let w = DMatrix::identity(2, 2);
        let mut r = [0.0; 2];
        AlartCurnier::new(law)
            .solve(&w, &[-1.0, 2.0], &mut r)
            .unwrap();
        assert!(
            (r[0] - 1.0).abs() < 1e-12 && (r[1] + 0.3).abs() < 1e-12,
            "{r:?}"
        );
    }

    #[test]
    fn one_point_sticks_inside_the_cone() {
        let law = Coulomb {
            mu: 0.5,
            points: 1,
            tangents: 1,
            frictionless: 0,
        };
        let w = DMatrix::identity(2, 2);
        let mut r = [0.0; 2];
        AlartCurnier::new(law)
            .solve(&w, &[-1.0, 0.2], &mut r)
            .unwrap();
        assert!(
            (r[0] - 1.0).abs() < 1e-12 && (r[1] + 0.2).abs() < 1e-12,
            "{r:?}"
        );
    }

    #[test]
    fn coupled_points_satisfy_the_law() {
        for mu in [0.0, 0.1, 0.5, 2.0] {
            let (law, w) = two_points(mu);
            for q in [
                [-1.0, -0.5, 0.8, -0.1],
                [-1.0, 0.5, 0.1, 3.0],
                [0.2, 0.3, 1.0, 1.0],
            ] {
                let mut r = [0.0; 4];
                AlartCurnier::new(law).solve(&w, &q, &mut r).unwrap();
                assert!(
                    violation(&law, &w, &q, &r) < 1e-10,
                    "μ {mu}, q {q:?}: {r:?}"
                );
            }
        }
    }

    /// Past μ_c of a corner-like point the Newton iterations stall (its slip branch turns over);
    /// the continuation from μ = 0 reaches the solution: up to μ = 4 the unique one, point 0
    /// sticking, `r_0 = −W_00⁻¹ q_0`, point 1 open; beyond, one of three.
    #[test]
    fn a_corner_past_its_critical_mu_is_solved_along_mu() {
        for mu in [1.0, 2.0, 3.0, 4.0, 10.0, 100.0, 1e8] {
            let (law, w, q) = super::super::testing::corner(mu);
            let mut r = [0.0; 4];
            let info = AlartCurnier::new(law).solve(&w, &q, &mut r).unwrap();
            let det = w[(0, 0)] * w[(2, 2)] - w[(0, 2)] * w[(2, 0)];
            let stick = [
                -(w[(2, 2)] * q[0] - w[(0, 2)] * q[2]) / det,
                -(w[(0, 0)] * q[2] - w[(2, 0)] * q[0]) / det,
            ];
            let err = (r[0] - stick[0])
                .abs()
                .max((r[2] - stick[1]).abs())
                .max(r[1].abs())
                .max(r[3].abs());
            if mu <= 4.0 {
                assert!(err < 1e-10, "μ {mu}: {r:?}, {} iterations", info.iterations);
            }
            if mu == 4.0 {
                // Newton alone cycled: the continuation took over.
                assert!(info.iterations > MAX_ITERATIONS, "{}", info.iterations);
            }
            assert!(violation(&law, &w, &q, &r) < 1e-10, "μ {mu}: {r:?}");
        }
    }

    #[test]
    fn three_d_point_slides_against_its_slip() {
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
        let mut r = [0.0; 3];
        AlartCurnier::new(law).solve(&w, &q, &mut r).unwrap();
        assert!(violation(&law, &w, &q, &r) < 1e-10, "{r:?}");
        let rt = (r[1] * r[1] + r[2] * r[2]).sqrt();
        assert!(
            (rt - 0.4 * r[0]).abs() < 1e-10,
            "on the cone's boundary: {r:?}"
        );
    }

    /// Nitsche's law (`AlartCurnier::nitsche`) on the two coupled points, W not symmetric (as
    /// for θ ≠ 1): at the solution, with `u = q + W r`, each point obeys GetFEM's
    /// `c r_N = [−u_N]₊` and `c r_T = P_{[−μ R, μ R]}(−u_T)`, R = [−u_N]₊, to round-off, in
    /// the open, stick and slip cases.
    #[test]
    fn nitsche_law_is_the_coulomb_projection_of_the_nitsche_vector() {
        let (law, mut w) = two_points(0.4);
        w[(0, 2)] = -0.2;
        let c = [0.7, 1.3];
        for q in [
            [-1.0, -0.5, 0.8, -0.1],
            [-1.0, 0.5, 0.1, 3.0],
            [-2.0, -0.1, 0.05, -0.02],
        ] {
            let mut r = [0.0; 4];
            let info = AlartCurnier::nitsche(law, c.to_vec())
                .solve(&w, &q, &mut r)
                .unwrap();
            let u: Vec<f64> = (0..4)
                .map(|a| q[a] + (0..4).map(|b| w[(a, b)] * r[b]).sum::<f64>())
                .collect();
            for i in 0..2 {
                let normal = (-u[i]).max(0.0);
                let radius = 0.4 * normal;
                let tangential = (-u[2 + i]).clamp(-radius, radius);
                assert!((c[i] * r[i] - normal).abs() < 1e-12, "q {q:?}: {r:?}");
                assert!(
                    (c[i] * r[2 + i] - tangential).abs() < 1e-12,
                    "q {q:?}: {r:?}"
                );
            }
            assert!(info.iterations <= 10, "{} iterations", info.iterations);
        }
    }
}
