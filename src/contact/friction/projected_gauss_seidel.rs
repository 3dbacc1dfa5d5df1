//! Projected Gauss–Seidel on the contact points, the baseline of the Moreau–Jean codes (Jean's
//! NSGS; Siconos `fc3d_nsgs.c`; `notes/papers/friction.md` §1–2). One sweep visits each point i
//! with the others fixed and gives it the exact solution of its own law
//! `u_i = b_i + W_ii r_i`, `b_i = q_i + Σ_{j≠i} W_ij r_j` (`solve_point`: open, stick or slip,
//! as Siconos' NSGS does with an exact local solver), so that its fixed points are exactly the
//! solutions of Signorini + Coulomb. It stops when the Alart–Curnier residual
//! ([`super::alart_curnier`]) is below [`super::TOLERANCE`] · scale, and fails after
//! [`MAX_SWEEPS`] sweeps: linear convergence, slow when W couples the points strongly.
//!
//! The sweep used to update `r_N ← max(0, r_N − ρ_N u_N)` and then
//! `r_T ← proj_{disc(μ r_N)}(r_T − ρ_T u_T)` (the projection local solver): on a slipping point
//! that is an iteration of gain `μ|W_NT|/W_NN` on r_N, which diverges past μ_c = W_NN/|W_NT|
//! (3.2 at slide2d's corner nodes at h = ⅛: it failed from μ = 3). **Limit**: Gauss–Seidel
//! itself converges only where the sweep contracts near the solution, and a slipping point's
//! reaction −μ r_N n̂ follows the other points' normal pushes, a gain that grows with μ: on
//! slide2d at h = ⅛ (step 1) the sweep's spectral radius at the (unique) solution is 0.81 at
//! μ = 25, 1.15 at 30 and 6.6 at 100, so it fails from μ ≈ 30 there (at h = ½ and ¼ it converges
//! to μ = 10¹⁵, slide3d at h = ¼ to 10⁸); alart_curnier solves those.

use super::{Coulomb, Local, TOLERANCE};
use crate::contact::{SolveInfo, Solver};
use crate::error::SolverError;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Sweeps allowed per step.
pub const MAX_SWEEPS: usize = 20_000;

/// Projected Gauss–Seidel for `law`.
#[derive(Debug, Clone)]
pub struct ProjectedGaussSeidel {
    law: Coulomb,
}

impl ProjectedGaussSeidel {
    /// For `law`.
    pub fn new(law: Coulomb) -> Self {
        Self { law }
    }
}

/// The exact solution of point p's own problem with the other points fixed
/// ([`solve_point`] on its block `W_pp` and `b = q_p + Σ_{j≠p} W_pj r_j`).
fn local(loc: &Local, r: &DVector<f64>, p: usize) -> [f64; 3] {
    let (s, dim) = (p * loc.dim, loc.dim);
    let mut a = [[0.0; 3]; 3];
    let mut b = [0.0; 3];
    for c in 0..dim {
        b[c] = loc.q[s + c] + loc.w.row(s + c).dot(&r.transpose());
        for e in 0..dim {
            a[c][e] = loc.w[(s + c, s + e)];
            b[c] -= a[c][e] * r[s + e];
        }
    }
    solve_point(loc.mu[p], &a, &b[..dim], &r.as_slice()[s..s + dim])
}

/// One sweep over the points: each gets the exact solution of its own problem.
fn sweep(loc: &Local, r: &mut DVector<f64>) {
    let dim = loc.dim;
    for p in 0..loc.points.len() {
        let x = local(loc, r, p);
        for c in 0..dim {
            r[p * dim + c] = x[c];
        }
    }
}

/// The exact solution of one point's law `u = b + A r` (A its SPD block, `dim = b.len()` rows,
/// normal first): open (`r = 0`) when `b_N ≥ 0`, else stick (`r = −A⁻¹b` inside the cone), else
/// slip: `r = r_N (1, −μ t)` with `u_N = 0`, `r_N = −b_N/(A_NN − μ A_NT·t) > 0` and
/// `u_T = λ t`, λ ≥ 0; in 3D the direction t is a root of the angle equation `t⊥·u_T = 0`
/// (a trigonometric polynomial of degree 2 once multiplied by `A_NN − μ A_NT·t`: at most four
/// roots, [`directions`]); of several slips the nearest to `current` (the point's reaction so
/// far). One of the three exists for any μ ≥ 0 (the one-point case of Acary, Cadoux, Lemaréchal
/// & Malick's existence theorem, A SPD); a slip whose normal compliance `A_NN − μ A_NT·t` is not
/// positive (the friction force presses the point into the plane at least as much as the normal
/// force lifts it: μ ≥ A_NN/|A_NT|) has no r_N > 0 and is not a candidate. At round-off from the
/// cone's edge the candidate with the smallest local Alart–Curnier residual is taken.
fn solve_point(mu: f64, a: &[[f64; 3]; 3], b: &[f64], current: &[f64]) -> [f64; 3] {
    let dim = b.len();
    let mut r = [0.0; 3];
    if b[0] >= 0.0 {
        return r;
    }
    if dim == 1 || mu == 0.0 {
        r[0] = -b[0] / a[0][0];
        return r;
    }
    let stick = solve_spd(a, b, dim);
    let rt = (stick[1] * stick[1] + stick[2] * stick[2]).sqrt();
    if stick[0] > 0.0 && rt <= mu * stick[0] {
        return stick;
    }
    // Slip along t: its r and u_T·t (≥ 0 when the slip goes along t), or None where the
    // normal compliance along t is not positive.
    let slip = |t: [f64; 2]| -> Option<([f64; 3], f64)> {
        let c = a[0][0] - mu * (a[0][1] * t[0] + a[0][2] * t[1]);
        if c <= 0.0 {
            return None;
        }
        let rn = -b[0] / c;
        let x = [rn, -mu * rn * t[0], -mu * rn * t[1]];
        let along = (1..dim)
            .map(|k| (b[k] + (0..dim).map(|e| a[k][e] * x[e]).sum::<f64>()) * t[k - 1])
            .sum::<f64>();
        Some((x, along))
    };
    let mut candidates: Vec<([f64; 3], f64)> = Vec::new();
    if dim == 2 {
        candidates.extend([[1.0, 0.0], [-1.0, 0.0]].into_iter().filter_map(slip));
    } else {
        // t⊥·u_T (c > 0 factored out) as a function of the angle.
        let across = |theta: f64| -> f64 {
            let (t, n) = ([theta.cos(), theta.sin()], [-theta.sin(), theta.cos()]);
            let c = a[0][0] - mu * (a[0][1] * t[0] + a[0][2] * t[1]);
            let wt = |k: usize| a[k][0] - mu * (a[k][1] * t[0] + a[k][2] * t[1]);
            (1..3)
                .map(|k| (c * b[k] - b[0] * wt(k)) * n[k - 1])
                .sum::<f64>()
        };
        for theta in directions(&across) {
            candidates.extend(slip([theta.cos(), theta.sin()]));
        }
    }
    // Several slips (a local problem past uniqueness): the nearest to the current reaction.
    let distance = |x: &[f64; 3]| (0..dim).map(|c| (x[c] - current[c]).powi(2)).sum::<f64>();
    if let Some((x, _)) = candidates
        .iter()
        .filter(|(x, along)| x[0] > 0.0 && *along >= 0.0)
        .min_by(|p, q| distance(&p.0).total_cmp(&distance(&q.0)))
    {
        return *x;
    }
    // Round-off at the cone's edge: the candidate closest to the law.
    let mut cone = stick;
    cone[0] = cone[0].max(0.0);
    let radius = mu * cone[0];
    super::project_disc(&mut cone[1..dim], radius);
    candidates
        .into_iter()
        .map(|(x, _)| x)
        .chain([cone])
        .map(|x| (point_residual(mu, a, b, &x), x))
        .min_by(|p, q| p.0.total_cmp(&q.0))
        .map_or(cone, |(_, x)| x)
}

/// The zeros of `h`, a trigonometric polynomial of degree ≤ 2 in the angle: its coefficients
/// from five equal steps (exact at that degree), then the real roots x of the quartic
/// `(1 + x²)² h(2 atan x)` (eigenvalues of its companion matrix; θ = π where the quartic loses
/// its degree), each polished by Newton's method on h.
fn directions(h: &impl Fn(f64) -> f64) -> Vec<f64> {
    use std::f64::consts::{PI, TAU};
    let samples: Vec<(f64, f64)> = (0..5)
        .map(|j| {
            let theta = TAU * j as f64 / 5.0;
            (theta, h(theta))
        })
        .collect();
    let coefficient =
        |k: f64, f: fn(f64) -> f64| samples.iter().map(|&(t, v)| v * f(k * t)).sum::<f64>() * 0.4;
    let a0 = samples.iter().map(|s| s.1).sum::<f64>() / 5.0;
    let (a1, b1) = (coefficient(1.0, f64::cos), coefficient(1.0, f64::sin));
    let (a2, b2) = (coefficient(2.0, f64::cos), coefficient(2.0, f64::sin));
    let dh = |t: f64| {
        -a1 * t.sin() + b1 * t.cos() - 2.0 * a2 * (2.0 * t).sin() + 2.0 * b2 * (2.0 * t).cos()
    };
    // x⁰ … x⁴.
    let quartic = [
        a0 + a1 + a2,
        2.0 * b1 + 4.0 * b2,
        2.0 * a0 - 6.0 * a2,
        2.0 * b1 - 4.0 * b2,
        a0 - a1 + a2,
    ];
    let size = quartic.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if size == 0.0 {
        return Vec::new();
    }
    let mut roots = Vec::new();
    let mut degree = 4;
    while quartic[degree].abs() <= 1e-14 * size {
        // The quartic's leading coefficient is h(π).
        if degree == 4 {
            roots.push(PI);
        }
        degree -= 1;
    }
    if degree > 0 {
        let mut companion = DMatrix::zeros(degree, degree);
        for i in 0..degree {
            companion[(0, i)] = -quartic[degree - 1 - i] / quartic[degree];
            if i + 1 < degree {
                companion[(i + 1, i)] = 1.0;
            }
        }
        for z in companion.complex_eigenvalues().iter() {
            if z.im.abs() <= 1e-7 * (1.0 + z.re.abs()) {
                roots.push(2.0 * z.re.atan());
            }
        }
    }
    for theta in roots.iter_mut() {
        for _ in 0..3 {
            let slope = dh(*theta);
            if slope != 0.0 {
                *theta -= h(*theta) / slope;
            }
        }
    }
    roots
}

/// `−A⁻¹ b` for the SPD block A (`dim` ≤ 3 rows) by nalgebra's Cholesky, the unused rows
/// as the identity (0 there); NaN on the first `dim` where A is not positive definite (no
/// stick candidate then).
fn solve_spd(a: &[[f64; 3]; 3], b: &[f64], dim: usize) -> [f64; 3] {
    let m = Matrix3::from_fn(|i, j| match (i < dim && j < dim, i == j) {
        (true, _) => a[i][j],
        (false, true) => 1.0,
        (false, false) => 0.0,
    });
    let rhs = Vector3::from_fn(|i, _| if i < dim { -b[i] } else { 0.0 });
    match m.cholesky() {
        Some(l) => l.solve(&rhs).into(),
        None => std::array::from_fn(|i| if i < dim { f64::NAN } else { 0.0 }),
    }
}

/// The norm of the Alart–Curnier function of one point at `x`, `ρ = 1/A_NN`.
fn point_residual(mu: f64, a: &[[f64; 3]; 3], b: &[f64], x: &[f64; 3]) -> f64 {
    let dim = b.len();
    let u: Vec<f64> = (0..dim)
        .map(|c| b[c] + (0..dim).map(|e| a[c][e] * x[e]).sum::<f64>())
        .collect();
    let f = super::alart_curnier::point(mu, 1.0 / a[0][0], &x[..dim], &u).f;
    f.iter().map(|v| v * v).sum::<f64>().sqrt()
}

impl Solver for ProjectedGaussSeidel {
    fn name(&self) -> &'static str {
        "projected_gauss_seidel"
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
        let (loc, mut r) = Local::gather(&self.law, d, q, lambda, None)?;
        for it in 0..MAX_SWEEPS {
            if loc.converged(&r, TOLERANCE).1 {
                return Ok(loc.finish(&self.law, &r, lambda, it));
            }
            sweep(&loc, &mut r);
        }
        match loc.converged(&r, TOLERANCE) {
            (_, true) => Ok(loc.finish(&self.law, &r, lambda, MAX_SWEEPS)),
            (norm, false) => Err(loc.not_converged(
                ("projected_gauss_seidel", &self.law),
                &r,
                (norm, TOLERANCE),
                format!("{MAX_SWEEPS} sweeps"),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::alart_curnier::AlartCurnier;
    use super::super::testing::{two_points, violation};
    use super::*;

    #[test]
    fn agrees_with_alart_curnier_on_coupled_points() {
        for mu in [0.0, 0.1, 0.5, 2.0] {
            let (law, w) = two_points(mu);
            for q in [
                [-1.0, -0.5, 0.8, -0.1],
                [-1.0, 0.5, 0.1, 3.0],
                [0.2, 0.3, 1.0, 1.0],
            ] {
                let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
                AlartCurnier::new(law).solve(&w, &q, &mut a).unwrap();
                ProjectedGaussSeidel::new(law)
                    .solve(&w, &q, &mut b)
                    .unwrap();
                assert!(
                    violation(&law, &w, &q, &b) < 1e-10,
                    "μ {mu}, q {q:?}: {b:?}"
                );
                let diff = a
                    .iter()
                    .zip(&b)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max);
                assert!(diff < 1e-9, "μ {mu}, q {q:?}: {a:?} against {b:?}");
            }
        }
    }

    /// The corner-like point past its μ_c: the old split update (`r_N`, then `r_T` projected)
    /// had gain μ W_NT/W_NN > 1 there; the exact local solve reaches the stick solution.
    #[test]
    fn a_corner_past_its_critical_mu_is_solved() {
        for mu in [1.0, 2.0, 3.0, 4.0, 10.0, 100.0] {
            let (law, w, q) = super::super::testing::corner(mu);
            let mut r = [0.0; 4];
            ProjectedGaussSeidel::new(law)
                .solve(&w, &q, &mut r)
                .unwrap();
            assert!(violation(&law, &w, &q, &r) < 1e-10, "μ {mu}: {r:?}");
            if mu <= 4.0 {
                assert_eq!((r[1], r[3]), (0.0, 0.0), "μ {mu}: point 1 open");
            }
        }
    }

    /// A point's exact local solution on random SPD blocks (2D and 3D) and offsets, for μ from
    /// 0.1 to 10⁴: the law holds to round-off (open, stick, slip on the cone's boundary, against
    /// the slip), whichever case it is.
    #[test]
    fn the_local_solution_satisfies_the_law() {
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut cases = [0usize; 3];
        for tangents in [1, 2] {
            let dim = 1 + tangents;
            for mu in [0.1, 1.0, 3.0, 10.0, 1e4] {
                for _ in 0..200 {
                    let g: Vec<f64> = (0..dim * dim).map(|_| next()).collect();
                    let mut w = DMatrix::from_fn(dim, dim, |i, j| {
                        (0..dim)
                            .map(|k| g[i * dim + k] * g[j * dim + k])
                            .sum::<f64>()
                    });
                    for i in 0..dim {
                        w[(i, i)] += 0.1;
                    }
                    let b: Vec<f64> = (0..dim).map(|_| next()).collect();
                    let mut a = [[0.0; 3]; 3];
                    for i in 0..dim {
                        for j in 0..dim {
                            a[i][j] = w[(i, j)];
                        }
                    }
                    let x = solve_point(mu, &a, &b, &[0.0; 3][..dim]);
                    let law = Coulomb {
                        mu,
                        points: 1,
                        tangents,
                        frictionless: 0,
                    };
                    let v = violation(&law, &w, &b, &x[..dim]);
                    let size = x.iter().chain(&b).fold(1.0f64, |m, y| m.max(y.abs()));
                    assert!(
                        v < 1e-9 * size,
                        "μ {mu}, W {w}, b {b:?}: {x:?}, violation {v:e}"
                    );
                    let rt = x[1..].iter().map(|y| y * y).sum::<f64>().sqrt();
                    cases[if x[0] == 0.0 {
                        0
                    } else if rt < mu * x[0] * (1.0 - 1e-9) {
                        1
                    } else {
                        2
                    }] += 1;
                }
            }
        }
        assert!(
            cases.iter().all(|&c| c > 100),
            "open, stick, slip: {cases:?}"
        );
    }

    #[test]
    fn excluded_point_gets_no_reaction() {
        let (law, w) = two_points(0.3);
        let q = [f64::INFINITY, -1.0, 5.0, 0.5];
        let mut r = [1.0; 4];
        ProjectedGaussSeidel::new(law)
            .solve(&w, &q, &mut r)
            .unwrap();
        assert_eq!((r[0], r[2]), (0.0, 0.0));
        assert!(r[1] > 0.0);
    }
}
