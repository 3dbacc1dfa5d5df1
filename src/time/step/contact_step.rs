//! The constant step operator of an implicit scheme with its contact coupling, solved directly
//! ([`super::direct`]: factored once, Delassus operator on the contact rows) or by CG with an
//! active set ([`super::iterative`]), as `--linear-solver` chooses.

use super::compliant::{symmetric_law, CompliantStep};
use super::direct::DirectStep;
use super::iterative::{own_dofs, IterativeStep};
use crate::contact::{SolveInfo, Solver};
use crate::error::{Error, Result};
use crate::linalg::{self, SpMat};
use crate::problem::Problem;
use crate::time::Solvers;

/// How the step matrix is solved (`--linear-solver`, `[run] linear_solver`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinearSolver {
    /// [`LinearSolver::Cg`] where it applies and pays, [`LinearSolver::Direct`] otherwise; the rule
    /// is [`cg_pays`].
    #[default]
    Auto,
    /// Sparse Cholesky (LU for the singular dynamic saddle system), factored once, with the
    /// Delassus operator on the contact dofs.
    Direct,
    /// Jacobi-preconditioned CG with a primal–dual active set ([`super::iterative`]).
    Cg,
}

/// Linear solver names accepted by [`LinearSolver::by_name`].
pub const LINEAR_SOLVERS: &[&str] = &[DEFAULT_LINEAR_SOLVER, "direct", "cg"];

/// Default linear solver (`--linear-solver`).
pub const DEFAULT_LINEAR_SOLVER: &str = "auto";

impl LinearSolver {
    /// The linear solver called `name`.
    pub fn by_name(name: &str) -> Result<Self> {
        match name {
            "auto" => Ok(Self::Auto),
            "direct" => Ok(Self::Direct),
            "cg" => Ok(Self::Cg),
            _ => Err(Error::UnknownName {
                kind: "linear solver",
                name: name.to_string(),
                known: LINEAR_SOLVERS.join(", "),
            }),
        }
    }
}

/// Dofs from which [`LinearSolver::Auto`] considers CG.
pub const AUTO_CG_DOFS: usize = 50_000;

/// The stiffness's weight in a 2D step matrix above which [`LinearSolver::Auto`] keeps the
/// direct factor: the median over the dofs with mass of `k K_ii / (m M_ii)` ([`stiffness_weight`]).
/// CG's iterations grow with it (as the Courant number cΔt/h squared) while a 2D factor stays
/// cheap. Measured on this machine (wall, whole runs, direct against cg): hertz2d n = 96 and 128
/// (weights 25 and 44) 7.7 against 31.6 s and 17.2 against 40.4 s; block2d Q1 224², weight 0.13
/// (Δt = 1e-3), 0.81 (2.5e-3) and 8.3 (8e-3): 37.5 against 14.1 s, 53.6 against 27.0 s, 21.6
/// against 22.8 s. A 3D factor fills in too much for the direct step to win at any weight
/// measured (hertz3d, weight 8.8: 88 against 15 s).
pub const AUTO_DIRECT_WEIGHT_2D: f64 = 8.0;

/// The rule of [`LinearSolver::Auto`]: CG when the mass is a sparse matrix, every contact row
/// has a dof of its own (nodal contact along axes, node-to-segment pairs of two bodies:
/// [`super::iterative::own_dofs`]), the problem has n ≥ [`AUTO_CG_DOFS`] dofs and K is not a
/// narrow band (2D and 3D meshes, where the Cholesky factor fills in and each direct step also
/// pays the Delassus correction over every active contact column), and, in 2D, the step matrix
/// `m M + k K` (`coefs`) is not stiffness-dominated ([`AUTO_DIRECT_WEIGHT_2D`]); the direct
/// factor otherwise, 1D included. Measured (README, Speed): block2d Q1 224² 19 against 42 ms
/// per step, block3d Q1 32³ 41 ms against 0.56 s (and 65 s of prepare).
pub fn cg_pays(problem: &Problem, k: &SpMat, coefs: (f64, f64)) -> bool {
    own_dofs(problem).is_ok() && cg_pays_on_mesh(problem, k, coefs)
}

/// The rule of [`LinearSolver::Auto`] for a compliant law (Nitsche's): as [`cg_pays`], with a
/// symmetric law (θ = 1) in place of nodal contact (measured in [`super::compliant`]: 2.7 times
/// less CPU than the direct step on the default hertz3d sphere).
fn compliant_cg_pays(problem: &Problem, k: &SpMat, coefs: (f64, f64)) -> bool {
    symmetric_law(problem).is_ok() && cg_pays_on_mesh(problem, k, coefs)
}

/// What both rules ask of the problem whatever its law: a sparse mass, n ≥ [`AUTO_CG_DOFS`], a
/// stiffness that is not a narrow band, and a 2D step matrix that the stiffness does not
/// dominate.
fn cg_pays_on_mesh(problem: &Problem, k: &SpMat, coefs: (f64, f64)) -> bool {
    problem.inertia.sparse().is_some()
        && problem.n() >= AUTO_CG_DOFS
        && !linalg::is_narrow_band(k)
        && !stiff_2d(problem, k, coefs)
}

/// True for a 2D mesh (nodes of 2 dofs) whose step matrix weighs the stiffness above
/// [`AUTO_DIRECT_WEIGHT_2D`].
fn stiff_2d(problem: &Problem, k: &SpMat, coefs: (f64, f64)) -> bool {
    linalg::node_size(k) == 2
        && problem
            .inertia
            .sparse()
            .and_then(|m| stiffness_weight(m, k, coefs))
            .is_some_and(|w| w > AUTO_DIRECT_WEIGHT_2D)
}

/// The median over the dofs with mass of `k K_ii / (m M_ii)`, `coefs = (m, k)`: how much the
/// stiffness weighs in the step matrix `m M + k K` (None without a dof with mass).
pub fn stiffness_weight(m: &SpMat, k: &SpMat, (m_coef, k_coef): (f64, f64)) -> Option<f64> {
    let (dm, dk) = (linalg::diagonal(m), linalg::diagonal(k));
    let mut w: Vec<f64> = dm
        .iter()
        .zip(&dk)
        .filter(|(m, _)| **m > 0.0)
        .map(|(m, k)| (k_coef * k / (m_coef * m)).abs())
        .collect();
    let mid = w.len() / 2;
    (!w.is_empty()).then(|| *w.select_nth_unstable_by(mid, f64::total_cmp).1)
}

/// Refuses a step matrix `m M + k K` in which the stiffness is below the round-off of the mass
/// (`k max K_ii < ε m max M_ii`): the time step is then so small that K no longer enters the
/// step (with a massless dof the matrix is singular), which would otherwise surface as a
/// factorisation failure or a silently wrong solve.
fn check_stiffness_resolved(
    problem: &Problem,
    k: &SpMat,
    (m_coef, k_coef): (f64, f64),
) -> Result<()> {
    let max_diag = |a: &SpMat| {
        linalg::diagonal(a)
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()))
    };
    let mass = max_diag(problem.inertia.kinetic());
    let k_max = max_diag(k);
    let (stiff, mass) = (k_coef.abs() * k_max, m_coef.abs() * mass);
    if stiff > 0.0 && stiff >= f64::EPSILON * mass || k_max == 0.0 {
        return Ok(());
    }
    Err(Error::StepMatrix {
        k: k_coef,
        stiff,
        mass,
    })
}

/// The constant step operator with its contact coupling, solved directly or by CG.
#[allow(clippy::large_enum_variant)]
pub enum ContactStep {
    /// Factored once, Delassus operator on the contact dofs.
    Direct(DirectStep),
    /// CG with an active set.
    Iterative(IterativeStep),
    /// CG with a compliant law's semismooth Newton (Nitsche).
    Compliant(CompliantStep),
}

impl ContactStep {
    /// The step operator `m_coef M + k_coef K` with the solvers' choice (see [`DirectStep::new`]).
    pub fn new(problem: &Problem, coefs: (f64, f64), c: f64, solvers: Solvers) -> Result<Self> {
        Self::with_stiffness(problem, &problem.k, coefs, c, solvers)
    }

    /// As [`ContactStep::new`] with the stiffness `k` in place of the problem's.
    pub fn with_stiffness(
        problem: &Problem,
        k: &SpMat,
        coefs: (f64, f64),
        c: f64,
        solvers: Solvers,
    ) -> Result<Self> {
        check_stiffness_resolved(problem, k, coefs)?;
        let signorini = solvers.contact.signorini();
        let compliance = solvers.contact.compliance();
        // The cg step solves Signorini's law by its own active set: another solver of the LCP
        // (clarabel, de_saxce, …) would be ignored, so auto takes the direct step for it.
        let own = solvers.contact.name() == crate::contact::DEFAULT_SOLVER;
        let cg = match solvers.linear {
            LinearSolver::Direct => false,
            LinearSolver::Cg if !signorini && compliance.is_none() => {
                return Err(Error::Unsupported(format!(
                    "linear solver cg enforces Signorini's law by its own active set, not the {} \
                     law (use direct)",
                    solvers.contact.name()
                )))
            }
            LinearSolver::Cg if compliance.is_none() && !own => {
                return Err(Error::Unsupported(format!(
                    "linear solver cg enforces Signorini's law by its own active set: contact \
                     solver {} would be ignored (use direct, or active_set)",
                    solvers.contact.name()
                )))
            }
            LinearSolver::Cg => true,
            LinearSolver::Auto if compliance.is_some() => compliant_cg_pays(problem, k, coefs),
            LinearSolver::Auto => signorini && own && cg_pays(problem, k, coefs),
        };
        Ok(if let (true, Some(eps)) = (cg, compliance) {
            Self::Compliant(CompliantStep::new(problem, k, coefs, c, eps)?)
        } else if cg {
            Self::Iterative(IterativeStep::new(problem, k, coefs, c)?)
        } else {
            Self::Direct(DirectStep::with_stiffness(
                problem,
                k,
                coefs,
                c,
                solvers.contact,
            )?)
        })
    }

    /// The direct step as built, its factor kept, with the law `solver` ([`DirectStep::restart`]);
    /// the cg steps have no factor to keep and are refused.
    pub fn restart(&mut self, solver: Box<dyn Solver>) -> Result<()> {
        match self {
            Self::Direct(s) => {
                s.restart(solver);
                Ok(())
            }
            Self::Iterative(_) | Self::Compliant(_) => Err(Error::Unsupported(
                "a cg step is built anew, not restarted".into(),
            )),
        }
    }

    /// Solves `A X = r` without contact.
    pub fn solve_free(&mut self, r: &[f64], u: &mut [f64], w: &mut [f64]) -> Result<()> {
        match self {
            Self::Direct(s) => {
                s.solve_free(r, u, w);
                Ok(())
            }
            Self::Iterative(s) => s.solve_free(r, u, w),
            Self::Compliant(s) => s.solve_free(r, u, w),
        }
    }

    /// Solves the step with the complementarity law (see [`DirectStep::solve`]).
    pub fn solve(
        &mut self,
        problem: &Problem,
        rhs: (&[f64], &[f64]),
        x: (&mut [f64], &mut [f64]),
        lambda: &mut [f64],
        at: (usize, f64),
    ) -> Result<SolveInfo> {
        match self {
            Self::Direct(s) => s.solve(problem, rhs, x, lambda, at),
            Self::Iterative(s) => s.solve(rhs, x, lambda, at),
            Self::Compliant(s) => s.solve(rhs, x, lambda, at),
        }
    }

    /// Solves the step with the law `law` (a scheme's own, e.g. a penalty force written as a
    /// discrete derivative) in place of the formulation's. The direct step only: the cg step
    /// enforces Signorini's law by its own active set (a scheme with its own law builds its
    /// step with [`LinearSolver::Direct`]).
    pub fn solve_with(
        &mut self,
        law: &mut dyn Solver,
        problem: &Problem,
        rhs: (&[f64], &[f64]),
        x: (&mut [f64], &mut [f64]),
        lambda: &mut [f64],
        at: (usize, f64),
    ) -> Result<SolveInfo> {
        match self {
            Self::Direct(s) => s.solve_with(law, problem, rhs, x, lambda, at),
            Self::Iterative(_) | Self::Compliant(_) => Err(Error::Unsupported(format!(
                "linear solver cg enforces Signorini's law by its own active set, not the {} law \
                 (use direct)",
                law.name()
            ))),
        }
    }
}
