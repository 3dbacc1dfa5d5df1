//! HHT-α (Hilber, Hughes, Taylor 1977) with the contact law at t_{n+1}:
//!
//! `M a_{n+1} + (1 + α) K U_{n+1} − α K Uₙ = F − B_Nᵀ λ_{n+1}`, α ∈ [−⅓, 0],
//!
//! with the Newmark updates for `β = (1 − α)²/4`, `γ = ½ − α`. Second order, unconditionally
//! stable, dissipating the high frequencies more as |α| grows; α = 0 is Newmark(¼, ½). The contact
//! pressure is not weighted by α (impenetrability is imposed at t_{n+1}). Implemented by the
//! shared Newmark integrator in inertial variables ([`super::newmark`]).
//! Coulomb friction as Newmark's: the friction force at t_{n+1} (unweighted, as the pressure) on
//! the slip increment `Δs = B_T (U_{n+1} − Uₙ)`.

use super::newmark::{Newmark, NewmarkIntegrator};
use super::scheme::{Integrator, Scheme};
use crate::contact::Enforcement;
use crate::error::{in_range, Result};
use crate::param::{Entry, Param};
use crate::problem::Problem;

/// HHT α.
pub const ALPHA: Param = Param {
    name: "alpha",
    label: "alpha",
    default: -0.05,
    help: "HHT α ∈ [−1/3, 0]",
};

/// Registry entry: `hht` with α.
pub const ENTRY: Entry<dyn Scheme> = Entry {
    name: "hht",
    params: &[&ALPHA],
    build: |p| Ok(Box::new(Hht::new(p.get(&ALPHA))?)),
};

/// HHT parameter α ∈ [−⅓, 0].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hht {
    /// α (−0.05: mild damping, −⅓: maximal).
    pub alpha: f64,
}

impl Hht {
    /// Validated α.
    pub fn new(alpha: f64) -> Result<Self> {
        in_range("alpha", alpha, -1.0 / 3.0, 0.0)?;
        Ok(Self { alpha })
    }

    /// The Newmark parameters `β = (1 − α)²/4`, `γ = ½ − α`.
    pub fn newmark(&self) -> Newmark {
        Newmark {
            beta: 0.25 * (1.0 - self.alpha).powi(2),
            gamma: 0.5 - self.alpha,
        }
    }
}

impl Scheme for Hht {
    fn name(&self) -> &'static str {
        "hht"
    }

    fn enforcement(&self) -> Enforcement {
        Enforcement::Position
    }

    fn friction(&self) -> Option<&'static str> {
        Some(super::step::friction::POSITION_SLIP)
    }

    fn prepare<'p>(
        &self,
        problem: &'p Problem,
        dt: f64,
        contact: super::scheme::Solvers,
    ) -> Result<Box<dyn Integrator + 'p>> {
        Ok(Box::new(NewmarkIntegrator::new(
            problem,
            dt,
            contact,
            self.newmark(),
            self.alpha,
        )?))
    }
}
