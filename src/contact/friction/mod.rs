//! Coulomb friction with Signorini contact at the nodal points: the per-step problem and its
//! exact solvers ([`alart_curnier`], [`projected_gauss_seidel`], [`de_saxce`]).
//!
//! Local variables of contact point i (`notes/papers/friction.md` §0, after Siconos'
//! `friction_contact.rst` lines 44–46): the relative "velocity" `u = (u_N, u_T)` (u_N > 0
//! separates: the gap, or its rate; u_T the slip, or its rate, as the scheme measures it) and the
//! reaction `r = (r_N, r_T)`, r_N ≥ 0 the pressure. After the predictor of a step,
//! `u = q + W r` with W the Delassus operator of the stacked rows `[B_N; −B_T]`
//! ([`crate::time::step::direct`]), and the law is
//!
//! `0 ≤ u_N ⊥ r_N ≥ 0`,  `‖r_T‖ ≤ μ r_N`,  `u_T ≠ 0 ⇒ r_T = −μ r_N u_T/‖u_T‖`.
//!
//! In 2D `r_T` lies in an interval (a box-constrained complementarity problem), in 3D in a disc
//! (a second-order cone complementarity problem). No regularisation: the solvers return the
//! exact law to their tolerance [`TOLERANCE`] on the Alart–Curnier residual, or an error.
//!
//! Row layout (the solvers' `q`, `λ`): the n_c normal rows first, then the tangential rows,
//! point-major (`n_c + i (d − 1) + k`). A point whose normal `q_i` is `+∞` is excluded (r = 0).

pub mod alart_curnier;
pub mod de_saxce;
pub mod projected_gauss_seidel;

use super::{SolveInfo, Solver};
use crate::error::{Error, Result, SolverError};
use nalgebra::{DMatrix, DVector};

/// Names of the friction solvers (also accepted, without friction, for Signorini's LCP).
pub const SOLVERS: &[&str] = &["alart_curnier", "projected_gauss_seidel", "de_saxce"];

/// The solver of a friction run when `--contact-solver` is not given.
pub const DEFAULT_SOLVER: &str = "alart_curnier";

/// Relative tolerance on the Alart–Curnier residual `‖F(r)‖ ≤ TOLERANCE · scale`, with scale the
/// largest of `‖r‖` and `‖ρ q‖` (a force), the tangential rows measured against the friction
/// radii they are computed from where those are larger ([`Local::converged`]).
pub const TOLERANCE: f64 = 1e-11;

/// The law at the contact points: coefficient μ, n_c points, d − 1 tangents per point
/// (0: Signorini's law alone).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coulomb {
    /// μ ≥ 0.
    pub mu: f64,
    /// Contact points n_c.
    pub points: usize,
    /// Tangents per point (d − 1, or 0 without friction).
    pub tangents: usize,
    /// The last points that are frictionless (μ = 0 there: `r_T = 0`), e.g. a frictionless
    /// support beside a frictional interface ([`crate::problem::Friction::frictionless`]).
    pub frictionless: usize,
}

impl Coulomb {
    /// Whether it is Signorini's law alone (no tangent or μ = 0).
    pub fn is_signorini(&self) -> bool {
        self.tangents == 0 || self.mu == 0.0
    }

    /// The coefficient at point i: μ, or 0 on the last [`Coulomb::frictionless`] points.
    pub fn mu_at(&self, i: usize) -> f64 {
        if i + self.frictionless < self.points {
            self.mu
        } else {
            0.0
        }
    }

    /// Rows per point, 1 + tangents.
    pub fn dim(&self) -> usize {
        1 + self.tangents
    }

    /// The global row of local component `c` (0 normal, 1.. tangential) of point `i`.
    pub fn row(&self, i: usize, c: usize) -> usize {
        if c == 0 {
            i
        } else {
            self.points + i * self.tangents + c - 1
        }
    }
}

/// The friction solver called `name` for `law`.
pub fn by_name(name: &str, law: Coulomb) -> Result<Box<dyn Solver>> {
    match name {
        "alart_curnier" => Ok(Box::new(alart_curnier::AlartCurnier::new(law))),
        "de_saxce" if law.frictionless > 0 && !law.is_signorini() => Err(Error::Unsupported(
            "de_saxce with frictionless points beside frictional ones: its cone (μ r_N, r_T) \
             loses r_N ≥ 0 where μ = 0; use alart_curnier or projected_gauss_seidel"
                .into(),
        )),
        "de_saxce" if law.mu > de_saxce::largest_mu() => Err(Error::invalid(
            "contact.friction",
            law.mu,
            &format!(
                "de_saxce takes --friction μ ≤ {:.2}: its fixed point contracts by \
                 μ²W_TT/(W_NN + μ²W_TT) ≥ μ²/(1 + μ²) per round at a slipping point, and its {} \
                 rounds reach its tolerance {:e} only below that; use alart_curnier",
                de_saxce::largest_mu(),
                de_saxce::MAX_FIXED_POINT,
                de_saxce::TOLERANCE
            ),
        )),
        "de_saxce" => Ok(Box::new(de_saxce::DeSaxce::new(law))),
        "projected_gauss_seidel" => Ok(Box::new(
            projected_gauss_seidel::ProjectedGaussSeidel::new(law),
        )),
        "active_set" | "clarabel" => Err(Error::invalid(
            "run.contact_solver",
            name,
            &format!(
                "solves the frictionless LCP; with friction use one of {}",
                SOLVERS.join(", ")
            ),
        )),
        _ => Err(Error::UnknownName {
            kind: "friction solver",
            name: name.to_string(),
            known: SOLVERS.join(", "),
        }),
    }
}

/// The problem restricted to the points in the step (finite normal q), blocks of `dim` rows per
/// point: `u = q + W r`, with `ρ` = 1/W_NN per point.
pub(crate) struct Local {
    pub points: Vec<usize>,
    pub dim: usize,
    /// μ per point in the step.
    pub mu: Vec<f64>,
    pub w: DMatrix<f64>,
    pub q: DVector<f64>,
    pub rho: Vec<f64>,
}

impl Local {
    /// Gathers the points of `q` not excluded, with the warm start `lambda`. With `compliance`
    /// (c_i per point) the operator is `W = D + diag(c)` on every row of point i and `ρ_i = 1/c_i`
    /// (Nitsche's law, [`crate::contact::nitsche`]).
    pub fn gather(
        law: &Coulomb,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &[f64],
        compliance: Option<&[f64]>,
    ) -> std::result::Result<(Self, DVector<f64>), SolverError> {
        let dim = law.dim();
        let points: Vec<usize> = (0..law.points).filter(|&i| q[i].is_finite()).collect();
        let k = points.len() * dim;
        let rows: Vec<usize> = points
            .iter()
            .flat_map(|&i| (0..dim).map(move |c| law.row(i, c)))
            .collect();
        let mut w = DMatrix::from_fn(k, k, |a, b| d[(rows[a], rows[b])]);
        if let Some(c) = compliance {
            for a in 0..k {
                w[(a, a)] += c[points[a / dim]];
            }
        }
        let mut rho = Vec::with_capacity(points.len());
        for (p, &i) in points.iter().enumerate() {
            let wnn = w[(p * dim, p * dim)];
            if wnn.is_nan() || wnn <= 0.0 {
                return Err(SolverError::NotPositiveDefinite { pivot: wnn });
            }
            rho.push(1.0 / compliance.map_or(wnn, |c| c[i]));
        }
        let local = Self {
            dim,
            mu: points.iter().map(|&i| law.mu_at(i)).collect(),
            q: DVector::from_fn(k, |a, _| q[rows[a]]),
            w,
            rho,
            points,
        };
        let r = DVector::from_fn(k, |a, _| lambda[rows[a]]);
        Ok((local, r))
    }

    /// Writes the local reaction `r` to the rows of `lambda` (0 on the excluded points).
    pub fn scatter(&self, law: &Coulomb, r: &DVector<f64>, lambda: &mut [f64]) {
        lambda.fill(0.0);
        for (p, &i) in self.points.iter().enumerate() {
            for c in 0..self.dim {
                lambda[law.row(i, c)] = r[p * self.dim + c];
            }
        }
    }

    /// `u = q + W r`.
    pub fn velocity(&self, r: &DVector<f64>) -> DVector<f64> {
        &self.q + &self.w * r
    }

    /// The scale of the residual: the largest of `‖r‖` and `‖ρ q‖` (a force), or the smallest
    /// positive number.
    pub fn scale(&self, r: &DVector<f64>) -> f64 {
        let rq = (0..self.q.len())
            .map(|a| (self.rho[a / self.dim] * self.q[a]).powi(2))
            .sum::<f64>()
            .sqrt();
        r.norm().max(rq).max(f64::MIN_POSITIVE)
    }

    /// The magnitude of the friction radii `μ max(0, r_N − ρ u_N)` that the tangential rows of
    /// F are computed from: `‖μ_i (|r_N| + ρ_i (|q_N| + Σ_j |W_Nj r_j|))‖` over the points. Its
    /// round-off, ε times it, bounds how small those rows can be computed: it grows with μ.
    pub fn radii(&self, r: &DVector<f64>) -> f64 {
        let dim = self.dim;
        let radii: Vec<f64> = (0..self.points.len())
            .map(|p| {
                let s = p * dim;
                let pushed = self.q[s].abs()
                    + (0..r.len())
                        .map(|b| (self.w[(s, b)] * r[b]).abs())
                        .sum::<f64>();
                self.mu[p] * (r[s].abs() + self.rho[p] * pushed)
            })
            .collect();
        // The norm without squaring a radius of 1e300 (μ up to f64::MAX is taken).
        let top = radii.iter().fold(0.0, |m: f64, x| m.max(*x));
        if top == 0.0 || !top.is_finite() {
            return top;
        }
        top * radii.iter().map(|x| (x / top).powi(2)).sum::<f64>().sqrt()
    }

    /// The Alart–Curnier residual and whether it is within `tolerance` · scale: `‖F‖`, its
    /// tangential rows measured against the larger of the scale and the radii they are computed
    /// from ([`Local::radii`]; the same as ‖F‖ up to μ of order one, and reachable in floating
    /// point for any μ: at μ = 1e8 the radii's round-off exceeds 1e-11 · scale).
    pub fn converged(&self, r: &DVector<f64>, tolerance: f64) -> (f64, bool) {
        let f = alart_curnier::residual(self, r, false).0;
        let scale = self.scale(r);
        let tangential = scale / self.radii(r).max(scale);
        let norm = f
            .iter()
            .enumerate()
            .map(|(a, x)| {
                if a % self.dim == 0 {
                    x * x
                } else {
                    (tangential * x).powi(2)
                }
            })
            .sum::<f64>()
            .sqrt();
        (norm, norm <= tolerance * scale)
    }

    /// Writes the solution `r` to `lambda` and reports `iterations` and the points with r_N > 0.
    pub fn finish(
        &self,
        law: &Coulomb,
        r: &DVector<f64>,
        lambda: &mut [f64],
        iterations: usize,
    ) -> SolveInfo {
        self.scatter(law, r, lambda);
        let active = (0..self.points.len())
            .filter(|&p| r[p * self.dim] > 0.0)
            .count();
        SolveInfo { iterations, active }
    }

    /// The failure of `method` after `rounds` (e.g. "100 Newton iterations") at residual `norm`,
    /// with the law's μ (`contact.friction`, which a run may have set too large to converge).
    pub fn not_converged(
        &self,
        (method, law): (&'static str, &Coulomb),
        r: &DVector<f64>,
        (norm, tolerance): (f64, f64),
        rounds: String,
    ) -> SolverError {
        SolverError::NotConverged {
            method,
            detail: format!(
                "Alart–Curnier residual {norm:.3e} (tolerance {:.3e}) after {rounds} on {} \
                 points, with μ = {:?} (contact.friction)",
                tolerance * self.scale(r),
                self.points.len(),
                law.mu
            ),
        }
    }
}

/// The projection of `x` (the `n` tangential components) onto the disc of radius `radius ≥ 0`.
pub(crate) fn project_disc(x: &mut [f64], radius: f64) {
    let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
    if norm > radius {
        let s = if norm > 0.0 { radius / norm } else { 0.0 };
        x.iter_mut().for_each(|v| *v *= s);
    }
}

#[cfg(test)]
pub(crate) mod testing {
    //! A 2D two-point problem with a known answer, shared by the solvers' tests.
    use super::Coulomb;
    use nalgebra::DMatrix;

    /// Coulomb's law at two points with one tangent each (2D), all frictional.
    fn two_point_law(mu: f64) -> Coulomb {
        Coulomb {
            mu,
            points: 2,
            tangents: 1,
            frictionless: 0,
        }
    }

    /// Two points, one tangent each: rows `[N0, N1, T0, T1]`, W SPD with coupling.
    pub fn two_points(mu: f64) -> (Coulomb, DMatrix<f64>) {
        let law = two_point_law(mu);
        #[rustfmt::skip]
        let w = DMatrix::from_row_slice(4, 4, &[
            2.0, 0.5, 0.3, 0.1,
            0.5, 2.0, 0.1, 0.3,
            0.3, 0.1, 1.0, 0.2,
            0.1, 0.3, 0.2, 1.0,
        ]);
        (law, w)
    }

    /// Two points, point 1 coupled as a block's corner node is, strongly: `W_NT/W_NN = 0.61`
    /// there (0.31 at slide2d's corners at h = ⅛), so that its slip branch turns over past
    /// μ_c = 1.65; rows `[N0, N1, T0, T1]`. With q: up to μ = 4 the unique solution is point 0
    /// sticking and point 1 open (found by enumerating the 4² open/stick/slip± states; from
    /// about 4.6 two more appear, point 1 sticking or slipping), and Newton from r = 0 cycled at
    /// μ = 4 for its 100 iterations.
    pub fn corner(mu: f64) -> (Coulomb, DMatrix<f64>, [f64; 4]) {
        let law = two_point_law(mu);
        #[rustfmt::skip]
        let w = DMatrix::from_row_slice(4, 4, &[
            0.86, 1.792, 0.018, 1.235,
            1.792, 8.155, -1.725, 4.94,
            0.018, -1.725, 2.328, -1.292,
            1.235, 4.94, -1.292, 3.987,
        ]);
        (law, w, [-1.778, -2.211, -0.369, -0.268])
    }

    /// The largest violation of the law at the solution `r` of `u = q + W r` (rows as the
    /// solvers'): negative gap or pressure, complementarity, cone, and slip against the force.
    pub fn violation(law: &Coulomb, w: &DMatrix<f64>, q: &[f64], r: &[f64]) -> f64 {
        let u: Vec<f64> = (0..q.len())
            .map(|a| q[a] + (0..q.len()).map(|b| w[(a, b)] * r[b]).sum::<f64>())
            .collect();
        let mut worst: f64 = 0.0;
        for i in 0..law.points {
            let (un, rn) = (u[i], r[i]);
            worst = worst.max(-un).max(-rn).max((un * rn).abs());
            let ut: Vec<f64> = (1..law.dim()).map(|c| u[law.row(i, c)]).collect();
            let rt: Vec<f64> = (1..law.dim()).map(|c| r[law.row(i, c)]).collect();
            let nt = ut.iter().map(|x| x * x).sum::<f64>().sqrt();
            let nr = rt.iter().map(|x| x * x).sum::<f64>().sqrt();
            worst = worst.max(nr - law.mu_at(i) * rn);
            // A slip is either negligible (stick, counted as is) or opposed by μ r_N.
            let direction = rt
                .iter()
                .zip(&ut)
                .map(|(a, b)| (a + law.mu_at(i) * rn * b / nt).abs())
                .fold(0.0, f64::max);
            if nt > 0.0 {
                worst = worst.max(nt.min(direction));
            }
        }
        worst
    }
}
