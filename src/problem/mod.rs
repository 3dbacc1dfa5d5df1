//! The semi-discrete contact problem every scheme consumes (DESIGN.md §1):
//!
//! `M Ü + K U = F − B_Nᵀ λ`,  `g = g₀ − B_N U ≥ 0`,  `λ ≥ 0`,  `λ · g = 0`.
//!
//! Sign convention: `B_N U` is the normal displacement along the body's *outward* normal at the
//! contact points (it closes the gap), `λ` is the contact pressure (nodal force, compression
//! positive) and the obstacle pushes the body with `−B_Nᵀ λ`, which opens the gap. (DESIGN.md §1
//! writes `+B_Nᵀ λ`; with `g = g₀ − B_N U` and `λ ≥ 0` only `−B_Nᵀ λ` does no work on a closing gap.)
//! The normal contact stress reported is `σ_N = −λ / (tributary area)` (≤ 0).

pub mod contact;
pub mod energy;
pub mod inertia;

pub use contact::{
    BoundaryPoint, Contact, ContactEnergy, ContactFace, Friction, NoQuadrature, VertexMap,
};
pub use energy::EnergyForm;
pub use inertia::{Inertia, StepOperator};

use crate::error::{Error, Result};
use crate::linalg::{self, SpMat};

/// Where the time series are sampled: contact point `contact`, its displacement dof `u_dof`
/// (normal direction) and its inertial (velocity) dof `w_dof`.
#[derive(Debug, Clone, Copy)]
pub struct Probe {
    /// Index of the contact point.
    pub contact: usize,
    /// Displacement dof of the probe.
    pub u_dof: usize,
    /// Velocity dof of the probe in the inertial variables.
    pub w_dof: usize,
}

/// `M Ü + K U = F − B_Nᵀ λ` with complementarity, and its initial data.
#[derive(Debug)]
pub struct Problem {
    /// Mass operator.
    pub inertia: Box<dyn Inertia>,
    /// Stiffness K (SPD once Dirichlet dofs are removed, or PSD with M + K SPD).
    pub k: SpMat,
    /// Constant external load F.
    pub f: Vec<f64>,
    /// Contact points.
    pub contact: Contact,
    /// Initial displacement U₀.
    pub u0: Vec<f64>,
    /// Initial velocity V₀ (displacement dofs).
    pub v0: Vec<f64>,
    /// Time-series probe.
    pub probe: Probe,
    /// Constant added to the energy so that it is the physical one (e.g. ½ k u_e² for a spring
    /// whose rest position is not at u = 0).
    pub energy_shift: f64,
}

impl Problem {
    /// Number of displacement dofs n.
    pub fn n(&self) -> usize {
        self.k.nrows()
    }

    /// The total energy, as stored quadratic forms for evaluation at every step.
    pub fn energy_form(&self) -> EnergyForm {
        EnergyForm {
            kinetic: linalg::QuadraticForm::new(self.inertia.kinetic()),
            stiffness: linalg::QuadraticForm::new(&self.k),
            load: self.f.iter().any(|&x| x != 0.0).then(|| self.f.clone()),
            shift: self.energy_shift,
            contact: self.contact.energy.clone(),
            work: Vec::new(),
        }
    }

    /// Normal contact stress `σ_N = −λ / area` at contact point `i`.
    pub fn contact_stress(&self, lambda: &[f64], i: usize) -> f64 {
        // `+ 0.0` turns −0 into +0 so that a free contact prints as 0.
        -lambda[i] / self.contact.area[i] + 0.0
    }

    /// Checks shapes and finiteness; a space or case that builds an inconsistent problem is a bug,
    /// but a NaN from user data must surface as an error, not as a silent NaN trajectory.
    pub fn validate(&self) -> Result<()> {
        let n = self.n();
        let shape = |what: &str, len: usize, want: usize| {
            if len == want {
                Ok(())
            } else {
                Err(Error::Internal(format!(
                    "{what} has length {len}, expected {want}"
                )))
            }
        };
        shape("F", self.f.len(), n)?;
        shape("U0", self.u0.len(), n)?;
        shape("V0", self.v0.len(), n)?;
        shape("B_N columns", self.contact.b_n.ncols(), n)?;
        shape("B_N rows", self.contact.b_n.nrows(), self.contact.len())?;
        shape("contact areas", self.contact.area.len(), self.contact.len())?;
        for (name, v) in [
            ("F", &self.f),
            ("U0", &self.u0),
            ("V0", &self.v0),
            ("g0", &self.contact.g0),
        ] {
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                return Err(Error::invalid(name, x, "must be finite"));
            }
        }
        // Parameters each finite but whose products overflow (a modulus and a density near
        // 1e308) leave infinite entries, which the factorisation would report without a field.
        for (name, a, fields) in [
            ("K", &self.k, "material.young (or system.stiffness)"),
            (
                "M",
                self.inertia.kinetic(),
                "material.density (or system.mass)",
            ),
        ] {
            if let Some(x) = a.val().iter().find(|x| !x.is_finite()) {
                return Err(Error::invalid(
                    name,
                    x,
                    &format!("must be finite: {fields} overflows in its entries"),
                ));
            }
        }
        Ok(())
    }
}
