//! What every time scheme is: a [`Scheme`] holds the parameters and declares how it enforces the
//! contact law; [`Scheme::prepare`] assembles and factors once and returns an [`Integrator`]
//! whose [`Integrator::step`] advances one time step. Schemes are written with the toolkit of
//! [`super::step`].

use super::step::LinearSolver;
use crate::contact::{self, Enforcement};
use crate::error::{Error, Result};
use crate::problem::Problem;

/// Per-step report.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepInfo {
    /// Contact-solver iterations in this step.
    pub contact_iterations: usize,
    /// Active contact points after this step.
    pub active: usize,
}

/// Read-only view of the discrete state at time `t`.
#[derive(Debug, Clone, Copy)]
pub struct State<'a> {
    /// Current time.
    pub t: f64,
    /// Steps taken.
    pub step: usize,
    /// Displacement U.
    pub u: &'a [f64],
    /// Inertial velocity (U̇ for a sparse mass, the H_h velocity for the singular dynamic method;
    /// the half-step velocity `(U_{n+1} − U_n)/Δt` for the three-level schemes).
    pub v: &'a [f64],
    /// Displacement at which the scheme's discrete energy is evaluated with `v`: U itself, or the
    /// midpoint `(U_{n+1} + U_n)/2` for the three-level schemes (the energy they conserve).
    pub energy_u: &'a [f64],
    /// Contact pressures λ (nodal forces, ≥ 0) at the current time level.
    pub lambda: &'a [f64],
    /// Energy stored by the scheme's own contact law (a penalty energy `½ κ [−g]₊²`), added to
    /// the problem's energy (evaluated at `energy_u`, `v`) in the reported energy; 0 otherwise.
    pub extra_energy: f64,
    /// Work of the friction forces so far, `W_f ≥ 0` (0 without friction).
    pub friction_work: f64,
}

/// A prepared scheme on one problem.
pub trait Integrator {
    /// Advances one step.
    fn step(&mut self) -> Result<StepInfo>;
    /// The current state.
    fn state(&self) -> State<'_>;
}

/// A time discretisation (parameters only).
pub trait Scheme: std::fmt::Debug + Send + Sync {
    /// Name used on the CLI and in outputs.
    fn name(&self) -> &'static str;
    /// How the step imposes the contact law (formulations refuse by it).
    fn enforcement(&self) -> Enforcement;
    /// With Coulomb friction: the slip its law is posed on (None: friction is refused).
    fn friction(&self) -> Option<&'static str> {
        None
    }
    /// The contact law the scheme applies by its own rule, never through an LCP solver (then
    /// `--contact-solver` would be ignored and is refused); None: it calls the solver.
    fn own_law(&self) -> Option<&'static str> {
        None
    }
    /// False for a scheme that solves no linear system (a lumped mass stepped explicitly):
    /// `--linear-solver` would be ignored and is refused.
    fn solves_linear_system(&self) -> bool {
        true
    }
    /// Assembles and factors once; the returned integrator starts from `(U₀, V₀)`.
    fn prepare<'p>(
        &self,
        problem: &'p Problem,
        dt: f64,
        solvers: Solvers,
    ) -> Result<Box<dyn Integrator + 'p>>;
}

/// The solvers of an implicit step: the LCP solver on the contact dofs (direct step) and the
/// linear solver of the step matrix.
pub struct Solvers {
    /// LCP solver of the direct step.
    pub contact: Box<dyn contact::Solver>,
    /// Direct factor or CG.
    pub linear: LinearSolver,
}

impl From<Box<dyn contact::Solver>> for Solvers {
    /// The contact solver with [`LinearSolver::Auto`].
    fn from(contact: Box<dyn contact::Solver>) -> Self {
        Self {
            contact,
            linear: LinearSolver::Auto,
        }
    }
}

/// Error if any value of `x` is not finite.
pub(crate) fn check_finite(x: &[f64], step: usize, time: f64, what: &str) -> Result<()> {
    // `v · 0` is 0 for finite v and NaN otherwise: a branch-free test, with 8 independent
    // accumulators so that it vectorises.
    let mut acc = [0.0f64; 8];
    let chunks = x.chunks_exact(8);
    let rest: f64 = chunks.remainder().iter().map(|v| v * 0.0).sum();
    for c in chunks {
        for (a, v) in acc.iter_mut().zip(c) {
            *a += v * 0.0;
        }
    }
    if acc.iter().sum::<f64>() + rest == 0.0 {
        Ok(())
    } else {
        Err(Error::Diverged {
            step,
            time,
            reason: format!("{what} is not finite"),
        })
    }
}

/// Refuses Coulomb friction on `problem` unless both the scheme and the formulation take it.
pub fn check_friction(
    problem: &Problem,
    scheme: &dyn Scheme,
    formulation: &dyn contact::Formulation,
) -> Result<()> {
    if problem.contact.friction.is_none() {
        return Ok(());
    }
    if let Err(why) = formulation.friction() {
        return Err(Error::Unsupported(format!(
            "Coulomb friction is implemented on the nodal, weak and nitsche contact rows, not with \
             contact = \"{}\": {why}",
            formulation.name()
        )));
    }
    if scheme.friction().is_none() {
        return Err(Error::Unsupported(format!(
            "Coulomb friction is implemented in the implicit position-level schemes (newmark, hht, \
             backward_euler) and moreau_jean, not in {}",
            scheme.name()
        )));
    }
    Ok(())
}
