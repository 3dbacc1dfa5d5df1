//! Consistent mass `M_ij = ∫ρ φ_i·φ_j`. Ill-posed with contact: every contact node carries inertia.

use super::sparse_mass::SparseMass;
use super::{MassModel, Space};
use crate::error::Result;
use crate::param::Entry;
use crate::problem::Inertia;

/// The standard (consistent-mass) FEM semi-discretisation.
#[derive(Debug, Clone, Copy)]
pub struct Standard;

/// Registry entry: `standard` (no parameter).
pub const ENTRY: Entry<dyn Space> = Entry {
    name: "standard",
    params: &[],
    build: |_| Ok(Box::new(Standard)),
};

impl Space for Standard {
    fn name(&self) -> &'static str {
        "standard"
    }

    fn inertia(&self, model: &MassModel) -> Result<Box<dyn Inertia>> {
        Ok(SparseMass::boxed(model.assemble(|el, _| el.mass.clone())?))
    }
}
