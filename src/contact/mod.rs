//! Contact formulations ([`Formulation`]: [`nodal`], [`weak`], [`nitsche`], [`penalty`]) and the solvers of the per-step
//! linear complementarity problem on the contact dofs ([`Solver`]).
//!
//! After the predictor solve of an implicit step, the gaps at the new time level are affine in the
//! contact pressures: `g = q + D λ`, with `D = c · B_N A⁻¹ B_Nᵀ` (the Delassus operator, the Schur
//! complement of the step matrix A on the contact dofs, SPD). A [`Solver`] returns λ with
//! `λ ≥ 0, g ≥ 0, λ · g = 0`. A point with `q_i = +∞` is excluded from this step (λ_i = 0): the
//! Moreau–Jean scheme uses it for points outside its index set.

pub mod active_set;
pub mod clarabel_qp;
pub mod friction;
pub mod nitsche;
pub mod nodal;
pub mod penalty;
pub mod weak;

use crate::error::{Error, Result, SolverError};
use crate::param::{Entry, Options};
use crate::problem::Problem;
use nalgebra::DMatrix;

/// Outcome of one LCP solve.
#[derive(Debug, Clone, Copy, Default)]
pub struct SolveInfo {
    /// Pivots / iterations used.
    pub iterations: usize,
    /// Number of contact points with λ > 0.
    pub active: usize,
}

/// A solver of `LCP(D, q)`: find λ ≥ 0 with `g = q + D λ ≥ 0`, `λ · g = 0`.
pub trait Solver: Send {
    /// Name used on the CLI and in reports.
    fn name(&self) -> &'static str;
    /// Whether the law solved is Signorini's LCP itself, so that a step may enforce it by its
    /// own means (the cg step's active set); false for a modified law (penalty, Nitsche's).
    fn signorini(&self) -> bool {
        true
    }
    /// The compliances ε_i of a law `λ_i = [−g_i]₊ / ε_i` (Nitsche's), which a step may enforce
    /// by its own means (the cg step's semismooth Newton); None for the other laws.
    fn compliance(&self) -> Option<&[f64]> {
        None
    }
    /// Solves the LCP; `lambda` holds a warm start on entry and the solution on exit.
    fn solve(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> std::result::Result<SolveInfo, SolverError>;
}

/// LCP solver names accepted by [`by_name`] (the friction solvers solve Signorini's LCP as
/// their frictionless case).
pub const SOLVERS: &[&str] = &[
    "active_set",
    "clarabel",
    "alart_curnier",
    "projected_gauss_seidel",
    "de_saxce",
];

/// The LCP solver called `name`, with a workspace for `n_c` contact points.
pub fn by_name(name: &str, n_c: usize) -> Result<Box<dyn Solver>> {
    let signorini = friction::Coulomb {
        mu: 0.0,
        points: n_c,
        tangents: 0,
        frictionless: 0,
    };
    match name {
        "active_set" => Ok(Box::new(active_set::ActiveSet::new(n_c))),
        "clarabel" => Ok(Box::new(clarabel_qp::ClarabelQp::new())),
        "alart_curnier" | "projected_gauss_seidel" | "de_saxce" => {
            friction::by_name(name, signorini)
        }
        _ => Err(Error::UnknownName {
            kind: "contact solver",
            name: name.to_string(),
            known: SOLVERS.join(", "),
        }),
    }
}

/// The solver called `name` of the law on `contact`'s rows: Signorini's LCP, or with
/// [`crate::problem::Friction`] Coulomb's law on the normal and tangential rows.
pub fn law(contact: &crate::problem::Contact, name: &str) -> Result<Box<dyn Solver>> {
    let points = contact.len();
    match &contact.friction {
        None => by_name(name, points),
        Some(f) => friction::by_name(
            name,
            friction::Coulomb {
                mu: f.mu,
                points,
                tangents: f.tangents,
                frictionless: f.frictionless,
            },
        ),
    }
}

/// How a time scheme imposes the contact law in its step: what a formulation may need to know
/// to refuse a scheme (declared by each scheme, `time::Scheme::enforcement`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Enforcement {
    /// An implicit step with Signorini's law on the gap at the new time level (Newmark, HHT,
    /// backward Euler).
    Position,
    /// An implicit step with an impact law: on a combination of positions or on velocities
    /// (Paoli–Schatzman, Moreau–Jean).
    Impact,
    /// An explicit step: the law on the next position through an explicit multiplier (central
    /// difference).
    Explicit,
    /// A penalty force on the penetration: the gap is not kept non-negative (it closes by an
    /// amount that shrinks with the penalty stiffness).
    Penalty,
}

/// A contact formulation: how the Signorini condition enters the semi-discrete problem and
/// which law the per-step problem on the contact rows obeys. One file each, registered in
/// [`FORMULATIONS`].
pub trait Formulation: Send + Sync + std::fmt::Debug {
    /// Name on the command line, in case files and in records.
    fn name(&self) -> &'static str;
    /// The name with its variant, as in the records' `contact=` (default: the name).
    fn label(&self) -> String {
        self.name().to_string()
    }
    /// Turns the nodal contact rows a case builds (one per vertex of Γ_C) into this
    /// formulation's (rows, force rows, stored energy, probe) and returns the per-step law on
    /// them, given the name of the LCP solver chosen by `--contact-solver` ([`by_name`]).
    fn setup(&self, problem: &mut Problem, solver: &str) -> Result<Box<dyn Solver>>;
    /// Refuses a time scheme (`scheme`, enforcing the law as `enforcement`) this formulation does
    /// not run with.
    fn check_scheme(&self, _scheme: &str, _enforcement: Enforcement) -> Result<()> {
        Ok(())
    }
    /// Whether `--contact-solver` chooses the solver of its per-step law (false: the
    /// formulation solves its own law).
    fn takes_solver(&self) -> bool {
        true
    }
    /// Whether it takes Coulomb friction ([`crate::problem::Friction`]): Ok, or why not.
    fn friction(&self) -> std::result::Result<(), &'static str> {
        Err("not implemented for this formulation")
    }
    /// A failure of the run's setup explained in the formulation's terms (default: as is).
    fn explain(&self, error: Error) -> Error {
        error
    }
}

/// The contact formulations, one registry line each (their parameters are declared in their
/// files).
pub const FORMULATIONS: &[Entry<dyn Formulation, Options>] =
    &[nodal::ENTRY, weak::ENTRY, nitsche::ENTRY, penalty::ENTRY];

/// Default formulation.
pub const DEFAULT_FORMULATION: &str = "nodal";

/// Default LCP solver (`--contact-solver`): the one the cg step and carpenter's closed form
/// are exact for.
pub const DEFAULT_SOLVER: &str = "active_set";

/// The registry entry of the formulation called `name`.
pub fn formulation_entry(name: &str) -> Result<&'static Entry<dyn Formulation, Options>> {
    crate::param::find(FORMULATIONS, "contact formulation", name)
}

/// The formulation chosen by `options` (`contact`, default [`DEFAULT_FORMULATION`]), with its
/// parameters read from them and validated.
pub fn formulation(options: &Options) -> Result<Box<dyn Formulation>> {
    (formulation_entry(options.contact())?.build)(options)
}

/// Checks `λ ≥ 0`, `g = q + Dλ ≥ −tol` and `|λ_i g_i| ≤ tol` on the points with finite `q_i`
/// (excluded points must have λ_i = 0); the error names the first violated condition.
pub fn check_solution(
    d: &DMatrix<f64>,
    q: &[f64],
    lambda: &[f64],
    tol: f64,
) -> std::result::Result<(), String> {
    for i in 0..q.len() {
        if !q[i].is_finite() {
            if lambda[i] != 0.0 {
                return Err(format!("excluded point {i} has λ = {}", lambda[i]));
            }
            continue;
        }
        let g = q[i] + (0..q.len()).map(|j| d[(i, j)] * lambda[j]).sum::<f64>();
        if lambda[i] < 0.0 || g < -tol || (lambda[i] * g).abs() > tol {
            return Err(format!("point {i}: λ = {:e}, g = {g:e}", lambda[i]));
        }
    }
    Ok(())
}
