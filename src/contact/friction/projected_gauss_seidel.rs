//! Projected Gauss–Seidel on the contact points, the baseline of the Moreau–Jean codes (Jean's
//! NSGS; Siconos `fc3d_nsgs.c` with the projection local solver; `notes/papers/friction.md`
//! §1–2). One sweep visits each point i with the others fixed:
//!
//! `r_N ← max(0, r_N − ρ_N u_N)`, then, with u_T updated for the new r_N,
//! `r_T ← proj_{disc(μ r_N)}(r_T − ρ_T u_T)`,
//!
//! `ρ_N = 1/W_NN`, `ρ_T = 1/λ_max(W_TT)` (the local blocks of point i). Its fixed points are
//! exactly the solutions of Signorini + Coulomb (the projection form of the law, Siconos'
//! "Christensen & Pang" radius μ r_N). It stops when the Alart–Curnier residual
//! ([`super::alart_curnier`]) is below [`super::TOLERANCE`] · scale, and fails after
//! [`MAX_SWEEPS`] sweeps: linear convergence, slow when W couples the points strongly.

use super::{project_disc, Coulomb, Local, TOLERANCE};
use crate::contact::{SolveInfo, Solver};
use crate::error::SolverError;
use nalgebra::{DMatrix, DVector};

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

/// `1/λ_max` of the tangential block of point p (a 1×1 or 2×2 symmetric block).
fn tangential_rho(loc: &Local, p: usize) -> f64 {
    let (s, dim) = (p * loc.dim, loc.dim);
    let a = loc.w[(s + 1, s + 1)];
    if dim == 2 {
        return 1.0 / a;
    }
    let (b, c) = (loc.w[(s + 1, s + 2)], loc.w[(s + 2, s + 2)]);
    1.0 / (0.5 * (a + c) + (0.25 * (a - c).powi(2) + b * b).sqrt())
}

/// `(q + W r)` at row a.
fn row_velocity(loc: &Local, r: &DVector<f64>, a: usize) -> f64 {
    loc.q[a] + loc.w.row(a).dot(&r.transpose())
}

/// One sweep over the points.
fn sweep(loc: &Local, rho_t: &[f64], r: &mut DVector<f64>) {
    let dim = loc.dim;
    for (p, &rho_n) in loc.rho.iter().enumerate() {
        let s = p * dim;
        let un = row_velocity(loc, r, s);
        let rn = (r[s] - rho_n * un).max(0.0);
        r[s] = rn;
        if dim == 1 {
            continue;
        }
        let mut rt = [0.0; 2];
        for (c, x) in rt.iter_mut().enumerate().take(dim - 1) {
            let ut = row_velocity(loc, r, s + 1 + c);
            *x = r[s + 1 + c] - rho_t[p] * ut;
        }
        project_disc(&mut rt[..dim - 1], loc.mu[p] * rn);
        for c in 1..dim {
            r[s + c] = rt[c - 1];
        }
    }
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
        let rho_t: Vec<f64> = if loc.dim > 1 {
            (0..loc.points.len())
                .map(|p| tangential_rho(&loc, p))
                .collect()
        } else {
            Vec::new()
        };
        for it in 0..MAX_SWEEPS {
            if loc.converged(&r, TOLERANCE).1 {
                return Ok(loc.finish(&self.law, &r, lambda, it));
            }
            sweep(&loc, &rho_t, &mut r);
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
