//! Time schemes. A [`Scheme`] holds the parameters; [`Scheme::prepare`] assembles and factors the
//! constant step matrix once and returns an [`Integrator`] whose [`Integrator::step`] advances one
//! time step with the contact law enforced at the new time level.

pub mod implicit;
pub mod newmark;

use crate::contact;
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
    /// Inertial velocity (U̇ for a sparse mass, the H_h velocity for the singular dynamic method).
    pub v: &'a [f64],
    /// Contact pressures λ (nodal forces, ≥ 0) at the current time level.
    pub lambda: &'a [f64],
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
    /// Parameters as `key=value` pairs separated by `;` (for summaries).
    fn parameters(&self) -> String;
    /// Assembles and factors once; the returned integrator starts from `(U₀, V₀)`.
    fn prepare<'p>(
        &self,
        problem: &'p Problem,
        dt: f64,
        contact: Box<dyn contact::Solver>,
    ) -> Result<Box<dyn Integrator + 'p>>;
}

/// Scheme names accepted on the CLI (`newmark` so far).
pub const SCHEMES: &[&str] = &["newmark"];

/// Scheme parameters as given by a case file or the CLI; unused ones are ignored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SchemeParams {
    /// Newmark β.
    pub beta: f64,
    /// Newmark γ.
    pub gamma: f64,
}

impl Default for SchemeParams {
    fn default() -> Self {
        Self {
            beta: 0.25,
            gamma: 0.5,
        }
    }
}

/// The scheme called `name` with validated parameters.
pub fn by_name(name: &str, p: SchemeParams) -> Result<Box<dyn Scheme>> {
    match name {
        "newmark" => Ok(Box::new(newmark::Newmark::new(p.beta, p.gamma)?)),
        _ => Err(Error::UnknownName {
            kind: "scheme",
            name: name.to_string(),
            known: SCHEMES.join(", "),
        }),
    }
}

/// Error if any value of `x` is not finite.
pub(crate) fn check_finite(x: &[f64], step: usize, time: f64, what: &str) -> Result<()> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::Diverged {
            step,
            time,
            reason: format!("{what} is not finite"),
        })
    }
}
