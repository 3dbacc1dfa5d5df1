//! Space discretisations of the inertia (DESIGN.md §3), one file each: every space turns the
//! same element data ([`MassModel`]) into an [`Inertia`] (the trait the time schemes consume);
//! the stiffness is the same for all of them. A sparse mass ([`sparse_mass`]) serves standard,
//! lumped, mass redistribution, mass elimination and modified quadrature; the singular dynamic
//! method carries its own saddle system ([`singular_dynamic`]).

pub mod lumped;
pub mod mass_elimination;
pub mod mass_redistribution;
pub mod modified_quadrature;
pub mod singular_dynamic;
pub mod sparse_mass;
pub mod standard;

use crate::error::Result;
pub use crate::fem::mass_model::{ElementMass, ElementMixed, MassModel, VelocitySpace};
use crate::param::{Entry, Params};
use crate::problem::Inertia;

/// A space discretisation of the inertia: one file each, registered in [`SPACES`].
pub trait Space: std::fmt::Debug + Send + Sync {
    /// Name used on the CLI and in outputs.
    fn name(&self) -> &'static str;
    /// Builds the mass operator.
    fn inertia(&self, model: &MassModel) -> Result<Box<dyn Inertia>>;
}

/// The spaces, one registry line each.
pub const SPACES: &[Entry<dyn Space>] = &[
    standard::ENTRY,
    lumped::ENTRY,
    mass_redistribution::ENTRY,
    mass_elimination::ENTRY,
    singular_dynamic::ENTRY,
    modified_quadrature::ENTRY,
];

/// The space whose runs are the common reference of a sweep's convergence (when swept): mass
/// redistribution, well posed and energy conserving (Khenous, Laborde, Renard 2008).
pub const REFERENCE: &str = mass_redistribution::ENTRY.name;

/// The names of the spaces, in registry order.
pub fn names() -> Vec<&'static str> {
    crate::param::names(SPACES)
}

/// The space called `name`.
pub fn by_name(name: &str) -> Result<Box<dyn Space>> {
    (crate::param::find(SPACES, "space", name)?.build)(&Params::default())
}
