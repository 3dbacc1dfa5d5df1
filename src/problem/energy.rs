//! The total energy of a state, evaluated at every sample of a run.

use super::ContactEnergy;
use crate::linalg;

/// The total energy `E = ½ vᵀ M v + ½ Uᵀ K U − Fᵀ U (+ shift)`, with `v` the inertial velocity
/// (`C` in place of `M` for the mixed mass, v ∈ H_h), `M` (or `C`) and `K` stored as
/// [`linalg::QuadraticForm`]s.
#[derive(Debug)]
pub struct EnergyForm {
    pub(super) kinetic: linalg::QuadraticForm,
    pub(super) stiffness: linalg::QuadraticForm,
    /// F, when not zero.
    pub(super) load: Option<Vec<f64>>,
    /// [`Problem::energy_shift`].
    pub(super) shift: f64,
    /// The energy stored in the contact rows ([`Contact::energy`]).
    pub(super) contact: Vec<ContactEnergy>,
    pub(super) work: Vec<f64>,
}

impl EnergyForm {
    /// `E = ½ vᵀ M v + ½ Uᵀ K U − Fᵀ U (+ shift)` (+ the energy of the contact rows).
    pub fn energy(&mut self, u: &[f64], v: &[f64]) -> f64 {
        0.5 * self.kinetic.eval(v, &mut self.work)
            + 0.5 * self.stiffness.eval(u, &mut self.work)
            + self.contact.iter().map(|b| b.eval(u)).sum::<f64>()
            - self
                .load
                .as_ref()
                .map_or(0.0, |f| linalg::dot_unordered(f, u))
            + self.shift
    }
}
