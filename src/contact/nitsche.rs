//! Nitsche's method for contact (Chouly, Hild, Renard, "A Nitsche finite element method for
//! dynamic contact", ESAIM: M2AN 49, 2015), with their notation: find u_h with
//!
//! `(ρ ü_h, v_h) + a(u_h, v_h) − θ ∫_{Γ_C} γ σ_n(u_h) σ_n(v_h)
//!   + ∫_{Γ_C} (1/γ) [u_{h,n} − g − γ σ_n(u_h)]₊ (v_{h,n} − θ γ σ_n(v_h)) = L(v_h)`,
//!
//! `γ = h / (γ₀ E)` (`--nitsche-gamma γ₀`, h the diameter of the cell at the point, E Young's
//! modulus), θ ∈ {1, 0, −1} (`--nitsche-theta`: symmetric, skew-less, skew-symmetric), n the
//! rigid plane's outward normal. No multiplier: the contact pressure `−σ_n ≈ (1/γ)[·]₊` is a
//! function of the displacement. The boundary integrals are taken by quadrature on the faces
//! of Γ_C ([`crate::fem::boundary`]; in 1D at the end point, exactly), with `[·]₊` evaluated at
//! each quadrature point x_i (weight w_i, rows `u_n = B_N U` and `σ_n = S U` there).
//!
//! Each quadrature point becomes a contact row: stiffness `K − θ Σ_i w_i γ_i S_iᵀ S_i` (constant,
//! in the factored step matrix), gap rows `B_N − γ S`, force `Qᵀ λ` with `Q = B_N − θ γ S` and
//! `λ_i = (w_i/γ_i) [−g_i]₊`, the force of point i (pressure `λ_i / w_i`; for the vertex outputs
//! it is spread to its face's vertices by their hat functions, and the probe is the point
//! nearest the probe vertex, whose `gap` column is the physical gap `g₀ − u_n`). Each implicit
//! step is then a semismooth equation in λ, solved by a generalised (semismooth) Newton method
//! on `min(λ, g + (γ/w) λ) = 0` ([`NitscheLaw`]), exact once its active set repeats; its
//! iterations are `contact_iterations`. The energy reported is
//! the paper's `E_h = ½ (ρ u̇, u̇) + ½ a(u, u) − ½ ‖γ^{½} σ_n(u)‖² + ½ ‖γ^{−½} [u_n − g − γ σ_n(u)]₊‖²`
//! − L(u), conserved by the semi-discrete problem for θ = 1.
//!
//! Coulomb friction (`friction = μ`): GetFEM's Nitsche contact brick
//! (`add_Nitsche_contact_with_rigid_obstacle_brick`, `doc/sphinx/source/userdoc/model_Nitsche.rst`,
//! "Generic Nitsche's method for contact with friction condition", after Chouly, Hild & Renard
//! and Chouly, "An adaptation of Nitsche's method to the Tresca friction problem", JMAA 411,
//! 2014): with G = σ(u)n the whole traction, the boundary terms become
//!
//! `− θ ∫ γ G·G(v) − ∫ P_{n,μ}(G − (A u − g n − α w_T)/γ) · (v − θ γ G(v))`,
//!
//! `P_{n,μ}(x) = −(x·n)₋ n + P_{B(0, μ (x·n)₋)}(x − (x·n) n)` (the normal part on ℝ₋, the
//! tangential part on the disc of radius μ times the pressure), A = α I + (1 − α) n nᵀ and
//! α (u_T − w_T) the scheme's slip: here α = 1, w_T = u_T(tₙ), so the tangential argument is
//! `σ_T(U_{n+1}) − Δs/γ` with the slip increment Δs = u_T(U_{n+1}) − u_T(Uₙ), the position-level
//! schemes' "Coulomb on the discrete slip" (DESIGN.md §8). Per quadrature point this adds the
//! tangential rows (tangents t_k = e_k, point-major as the nodal `B_T`): law rows `u_T − γ σ_T`,
//! force rows `Q_T = u_T − θ γ σ_T`, stiffness `− θ Σ_i w_i γ_i S_{T,i}ᵀ S_{T,i}` and the energy's
//! `½ (θ − 1) w γ |σ_T|²`, so that E_h's `−½ ‖γ^{½} σ_n‖²` becomes `−½ ‖γ^{½} σ(u)n‖²`. With
//! `c = γ/w` and the step's `u = q + D r` on the stacked law rows (u_N the law gap, u_T the law
//! slip `Δs − γσ_T`), the law of point i is `c r = P_{n,μ}(−u)`, r = (λ_N, r_T) its forces
//! (r_T the shear force on the body, `w σ_T`), and this is exactly Coulomb–Signorini's law on
//! `ũ = u + c r = q + (D + diag(c)) r`: the projection's residual is the Alart–Curnier function
//! with ρ = 1/c, solved by its semismooth Newton method ([`AlartCurnier::nitsche`]; in 2D the
//! residual is piecewise linear, so the step is exact once the open/stick/slip sets repeat; in
//! 3D the slip direction converges quadratically to the solvers' tolerance). The friction work
//! is that of the force applied, `−r_T · Q_T (U_{n+1} − Uₙ)` ([`crate::time::step::friction`]).
//! Every θ ∈ [−1, 1] runs (D is not symmetric for θ ≠ 1; the LU does not need it). Refused:
//! the cg step, in 2D and 3D (its Newton method solves an SPD system on the active set, and the
//! Jacobian of a slipping point is not symmetric: Coulomb's law is not associated), a pair of
//! bodies and the 1D end point (no tangent). Cost: on slide3d (64 quadrature points, 192 law
//! rows) 1199 Newton iterations and 0.94 s CPU over 500 steps, against 715 and 0.07 s for the
//! nodal friction (25 vertices) and 0.07 s for the frictionless Nitsche run. μ = 0 is the frictionless method above (GetFEM's form at μ = 0 would
//! keep `−θ ∫ γ σ_T(u) σ_T(v)`, consistent but not the same discrete problem).
//!
//! Schemes: Newmark, HHT and backward Euler (contact law at t_{n+1}); Paoli–Schatzman and
//! Moreau–Jean impose an impact law on the gap, which Nitsche's form has no place for, and the
//! explicit central difference would need a stability restriction depending on γ₀: they are
//! refused. Cases: bar1d and every meshed 2D/3D body (not the spring–mass, which has no stress).

use super::friction::{alart_curnier::AlartCurnier, Coulomb};
use super::{Enforcement, Formulation, SolveInfo, Solver};
use crate::error::{in_range, positive, Error, Result, SolverError};
use crate::linalg::TripletBuilder;
use crate::param::{Entry, Options, Param};
use crate::problem::{BoundaryPoint, ContactEnergy, NoQuadrature, Problem, VertexMap};
use faer::linalg::solvers::Solve;
use nalgebra::DMatrix;

/// Nitsche's parameter γ₀ (γ = h / (γ₀ E)).
pub const GAMMA0: Param = Param {
    name: "nitsche_gamma",
    label: "gamma0",
    default: 100.0,
    help: "Nitsche parameter γ₀ > 0 of the nitsche contact (γ = h/(γ₀ E))",
};
/// Nitsche's variant θ.
pub const THETA: Param = Param {
    name: "nitsche_theta",
    label: "theta_N",
    default: 1.0,
    help: "Nitsche variant θ ∈ [−1, 1] (1 symmetric, 0 skew-less, −1 skew-symmetric)",
};

/// Registry entry: `nitsche` with γ₀, θ.
pub const ENTRY: Entry<dyn Formulation, Options> = Entry {
    name: "nitsche",
    params: &[&GAMMA0, &THETA],
    build: |o| {
        Ok(Box::new(Nitsche::new(
            o.params.get(&GAMMA0),
            o.params.get(&THETA),
        )?))
    },
};

/// Newton iterations allowed per step.
pub const MAX_ITERATIONS: usize = 100;

/// Nitsche contact with γ₀ and θ.
#[derive(Debug, Clone, Copy)]
pub struct Nitsche {
    /// γ₀ > 0.
    pub gamma0: f64,
    /// θ ∈ [−1, 1].
    pub theta: f64,
}

impl Nitsche {
    /// Validated parameters.
    pub fn new(gamma0: f64, theta: f64) -> Result<Self> {
        Ok(Self {
            gamma0: positive("run.nitsche_gamma", gamma0)?,
            theta: in_range("run.nitsche_theta", theta, -1.0, 1.0)?,
        })
    }
}

/// `b − c s` of two sparse rows.
fn combine(b: &[(usize, f64)], s: &[(usize, f64)], c: f64) -> Vec<(usize, f64)> {
    b.iter()
        .copied()
        .chain(s.iter().map(|&(j, v)| (j, -c * v)))
        .collect()
}

/// Why a case without boundary quadrature is refused: Nitsche's terms are integrals of σ_N
/// over Γ_C of one body against the rigid plane.
fn refusal(why: NoQuadrature) -> Error {
    let only = "nitsche runs on one body against the rigid plane (bar1d, bar_flight and the \
                meshed bodies); use contact = \"nodal\"";
    match why {
        NoQuadrature::TwoBodies => Error::Unsupported(format!(
            "nitsche contact between two bodies is not implemented (its integrals over their \
             interface, docs/methods.md): {only}"
        )),
        NoQuadrature::PointMass => Error::Unsupported(format!(
            "nitsche contact integrates σ_N over Γ_C, and a point mass has none: {only}"
        )),
        NoQuadrature::Taken => {
            Error::Internal("the boundary quadrature of Γ_C was taken before nitsche's".into())
        }
    }
}

impl Formulation for Nitsche {
    fn name(&self) -> &'static str {
        "nitsche"
    }

    /// GetFEM's Nitsche friction (see the module documentation).
    fn friction(&self) -> std::result::Result<(), &'static str> {
        Ok(())
    }

    fn check_scheme(&self, scheme: &str, enforcement: Enforcement) -> Result<()> {
        if enforcement == Enforcement::Position {
            return Ok(());
        }
        Err(Error::Unsupported(format!(
            "nitsche contact runs with the implicit schemes whose law is Signorini's on the new \
             position only, not {scheme} (an impact law or an explicit step has no place for \
             Nitsche's boundary term)"
        )))
    }

    fn takes_solver(&self) -> bool {
        false
    }

    /// A failed factorisation: its term `−θ ∫ γ σ_n(u) σ_n(v)` (θ > 0) makes the stiffness
    /// indefinite when γ₀ is too small.
    fn explain(&self, error: Error) -> Error {
        match error {
            Error::Factorisation { matrix, reason } if self.theta > 0.0 => Error::Factorisation {
                matrix,
                reason: format!(
                    "{reason}; with nitsche contact and θ > 0 the term −θ ∫ γ σ_n(u) σ_n(v) makes \
                     the stiffness indefinite when γ₀ is too small: increase run.nitsche_gamma"
                ),
            },
            // θ ≤ 0: the term is positive semi-definite (zero at θ = 0), not the cause.
            Error::Factorisation { matrix, reason } => Error::Factorisation {
                matrix,
                reason: format!(
                    "{reason}; with nitsche contact and θ = {} ≤ 0 the term −θ ∫ γ σ_n(u) \
                     σ_n(v) adds no indefinite part (run.nitsche_gamma = {:e} is not the cause \
                     unless it makes γ = h/(γ₀ E) swamp the stiffness)",
                    self.theta, self.gamma0
                ),
            },
            e => e,
        }
    }

    /// Replaces the vertex rows by one row per quadrature point of Γ_C (see the module
    /// documentation); the probe becomes the point nearest the probe vertex. The per-step law is
    /// [`NitscheLaw`] (the LCP solver chosen is not used).
    fn setup(&self, problem: &mut Problem, _solver: &str) -> Result<Box<dyn Solver>> {
        let points = problem.contact.take_quadrature().map_err(refusal)?;
        let n = problem.k.ncols();
        let mut gap = TripletBuilder::new(points.len(), n);
        let mut force = TripletBuilder::new(points.len(), n);
        let mut k = TripletBuilder::new(n, n);
        k.add_scaled(0, 0, 1.0, &problem.k);
        let mut tangential = self.tangential(problem, &points)?;
        let (mut compliance, mut energy) = (Vec::new(), Vec::new());
        // The largest entry of the stiffness and of the Nitsche term `w γ S_iᵀ S_i` (θ aside).
        let stiff = problem.k.val().iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let mut term = 0.0_f64;
        for (i, p) in points.iter().enumerate() {
            let (w, gamma) = (p.weight, p.h_over_e / self.gamma0);
            if !gamma.is_normal() || !(1.0 / gamma).is_finite() {
                return Err(Error::invalid(
                    "run.nitsche_gamma",
                    self.gamma0,
                    &format!(
                        "gives γ = h/(γ₀ E) = {gamma:e} at contact point {i}: γ and 1/γ must \
                         be finite and non-zero"
                    ),
                ));
            }
            let r = combine(&p.u_n, &p.sigma_n, gamma);
            for &(j, v) in &r {
                gap.add(i, j, v);
            }
            for (j, v) in combine(&p.u_n, &p.sigma_n, self.theta * gamma) {
                force.add(i, j, v);
            }
            let mut s = vec![p.sigma_n.clone()];
            if let Some(t) = tangential.as_mut() {
                t.add(i, p, gamma);
                s.extend(p.sigma_t.iter().cloned());
            }
            for row in &s {
                let top = row.iter().fold(0.0_f64, |m, v| m.max(v.1.abs()));
                term = term.max(w * gamma * top * top);
                for &(a, sa) in row {
                    for &(b, sb) in row {
                        k.add(a, b, -self.theta * w * gamma * sa * sb);
                    }
                }
            }
            compliance.push(gamma / w);
            energy.push(ContactEnergy {
                s,
                r,
                g0: p.g0,
                a: 0.5 * (self.theta - 1.0) * w * gamma,
                b: 0.5 * w / gamma,
            });
        }
        problem.probe.contact = nearest_point(&points, problem.probe.contact)?;
        problem.k = k.build()?;
        if let Some(v) = problem.k.val().iter().find(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "run.nitsche_gamma",
                self.gamma0,
                &format!(
                    "its term −θ ∫ γ σ_n(u) σ_n(v), γ = h/(γ₀ E), puts {v} in the stiffness: γ₀ is \
                     too small for this mesh and material"
                ),
            ));
        }
        check_scale(self.gamma0, term, stiff)?;
        let contact = &mut problem.contact;
        contact.b_n = gap.build()?;
        contact.g0 = points.iter().map(|p| p.g0).collect();
        contact.vertices = Some(VertexMap {
            shares: points.iter().map(|p| p.vertices.clone()).collect(),
            area: std::mem::take(&mut contact.area),
        });
        contact.area = points.iter().map(|p| p.weight).collect();
        contact.force = Some(force.build()?);
        contact.energy = energy;
        contact.normal = Some(points.into_iter().map(|p| p.u_n).collect());
        match (tangential, contact.friction.as_mut()) {
            (Some(t), Some(f)) => {
                (f.b_t, f.force, f.slip) = (
                    t.law.build()?,
                    Some(t.force.build()?),
                    Some(t.slip.build()?),
                );
                let law = Coulomb {
                    mu: f.mu,
                    points: contact.g0.len(),
                    tangents: f.tangents,
                    frictionless: 0,
                };
                Ok(Box::new(AlartCurnier::nitsche(law, compliance)))
            }
            _ => Ok(Box::new(NitscheLaw { compliance })),
        }
    }
}

/// Refuses a γ₀ whose Nitsche term (largest entry `term`, of `w γ σ σ`, γ = h/(γ₀ E)) is not
/// finite or outweighs the stiffness (largest entry `stiff`) beyond round-off (1/ε): the step
/// matrix would be the term alone to round-off, singular, whatever θ.
fn check_scale(gamma0: f64, term: f64, stiff: f64) -> Result<()> {
    let ratio = term / stiff;
    if stiff > 0.0 && (ratio.is_nan() || ratio > 1.0 / f64::EPSILON) {
        return Err(Error::invalid(
            "run.nitsche_gamma",
            gamma0,
            &format!(
                "makes the term θ ∫ γ σ_n(u) σ_n(v), γ = h/(γ₀ E), {ratio:e} times the stiffness \
                 (at most 1/ε = {:e}): the step matrix would be singular to round-off; increase \
                 γ₀",
                1.0 / f64::EPSILON
            ),
        ));
    }
    Ok(())
}

impl Nitsche {
    /// The tangential rows of a run with friction (None without): refused on frictionless
    /// points (a pair) and where Γ_C has no tangent (a 1D end point).
    fn tangential(
        &self,
        problem: &Problem,
        points: &[BoundaryPoint],
    ) -> Result<Option<Tangential>> {
        let Some(f) = &problem.contact.friction else {
            return Ok(None);
        };
        if f.frictionless > 0 || points.iter().any(|p| p.u_t.len() != f.tangents) {
            return Err(Error::Unsupported(
                "nitsche contact with friction needs the tangents of one Γ_C on the rigid plane \
                 (a meshed 2D/3D body; not a pair of bodies or a 1D end point)"
                    .into(),
            ));
        }
        let (rows, n) = (points.len() * f.tangents, problem.k.ncols());
        Ok(Some(Tangential {
            law: TripletBuilder::new(rows, n),
            force: TripletBuilder::new(rows, n),
            slip: TripletBuilder::new(rows, n),
            theta: self.theta,
        }))
    }
}

/// Nitsche's tangential rows, point-major as `B_T`: law `u_T − γ σ_T`, force
/// `Q_T = u_T − θ γ σ_T`, slip `u_T`.
struct Tangential {
    law: TripletBuilder,
    force: TripletBuilder,
    slip: TripletBuilder,
    theta: f64,
}

impl Tangential {
    /// The rows of point `i`.
    fn add(&mut self, i: usize, p: &BoundaryPoint, gamma: f64) {
        let d = p.u_t.len();
        for (k, (u, s)) in p.u_t.iter().zip(&p.sigma_t).enumerate() {
            let row = i * d + k;
            for (j, v) in combine(u, s, gamma) {
                self.law.add(row, j, v);
            }
            for (j, v) in combine(u, s, self.theta * gamma) {
                self.force.add(row, j, v);
            }
            for &(j, v) in u {
                self.slip.add(row, j, v);
            }
        }
    }
}

/// The quadrature point with the largest share of `vertex` (ties: the lowest g₀, then the
/// lowest index).
fn nearest_point(points: &[BoundaryPoint], vertex: usize) -> Result<usize> {
    let share = |p: &BoundaryPoint| {
        p.vertices
            .iter()
            .find(|e| e.0 == vertex)
            .map_or(0.0, |e| e.1)
    };
    (0..points.len())
        .filter(|&q| share(&points[q]) > 0.0)
        .min_by(|&a, &b| {
            share(&points[b])
                .total_cmp(&share(&points[a]))
                .then(points[a].g0.total_cmp(&points[b].g0))
        })
        .ok_or_else(|| Error::Internal("the probe vertex is on no face of Γ_C".into()))
}

/// The per-step law `λ = (w/γ)[−g]₊` with `g = q + D λ` (D not symmetric for θ ≠ 1): the
/// semismooth Newton method on `min(λ, q + (D + diag(c)) λ) = 0`, `c = γ/w`, i.e. the primal–dual
/// active set with a dense LU of the active block (faer). Per iteration it costs `n_c` times the number
/// of nonzero λ (columns of D) plus the LU; D itself is neither copied nor shifted. On the cg
/// path the step solves the same law by its own Newton method ([`Solver::compliance`],
/// `time::step::compliant`).
#[derive(Debug, Clone)]
pub struct NitscheLaw {
    compliance: Vec<f64>,
}

impl Solver for NitscheLaw {
    fn name(&self) -> &'static str {
        "nitsche_newton"
    }

    fn signorini(&self) -> bool {
        false
    }

    fn compliance(&self) -> Option<&[f64]> {
        Some(&self.compliance)
    }

    fn solve(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> std::result::Result<SolveInfo, SolverError> {
        let n = q.len();
        let c = &self.compliance;
        let mut active: Vec<usize> = Vec::new();
        for it in 1..=MAX_ITERATIONS {
            // y = q + D λ + c λ, D λ over the columns of the nonzero λ_j (contiguous in D).
            let mut y: Vec<f64> = (0..n).map(|i| q[i] + c[i] * lambda[i]).collect();
            for (j, &l) in lambda.iter().enumerate().filter(|e| *e.1 != 0.0) {
                for (yi, dij) in y.iter_mut().zip(d.column(j).iter()) {
                    *yi += dij * l;
                }
            }
            let next: Vec<usize> = (0..n)
                .filter(|&i| q[i].is_finite() && y[i] < lambda[i])
                .collect();
            if it > 1 && next == active {
                return Ok(SolveInfo {
                    iterations: it - 1,
                    active: active.len(),
                });
            }
            active = next;
            lambda.fill(0.0);
            if active.is_empty() {
                continue;
            }
            let k = active.len();
            // A dense LU of the active block (faer's blocked LU: the block reaches hundreds of
            // points on a 3D contact patch).
            let block = faer::Mat::from_fn(k, k, |a, b| {
                let (i, j) = (active[a], active[b]);
                d[(i, j)] + if i == j { c[i] } else { 0.0 }
            });
            let mut x = faer::Mat::from_fn(k, 1, |a, _| -q[active[a]]);
            block.partial_piv_lu().solve_in_place(&mut x);
            if !(0..k).all(|a| x[(a, 0)].is_finite()) {
                return Err(SolverError::Singular {
                    method: "Nitsche Newton",
                });
            }
            let x = x.col(0);
            for (a, &i) in active.iter().enumerate() {
                lambda[i] = x[a];
            }
        }
        Err(SolverError::NotConverged {
            method: "Nitsche Newton",
            detail: format!("no settled active set in {MAX_ITERATIONS} iterations"),
        })
    }
}
