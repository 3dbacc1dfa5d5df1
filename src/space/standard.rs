//! Consistent mass `M_ij = ∫ρ φ_i·φ_j`. Ill-posed with contact: every contact node carries inertia.

use super::{MassModel, Space};
use crate::error::Result;
use crate::problem::Inertia;

/// The standard (consistent-mass) FEM semi-discretisation.
#[derive(Debug, Clone, Copy)]
pub struct Standard;

impl Space for Standard {
    fn name(&self) -> &'static str {
        "standard"
    }

    fn inertia(&self, model: &MassModel) -> Result<Inertia> {
        Ok(Inertia::Sparse {
            m: model.assemble(|el, _| el.mass.clone())?,
        })
    }
}
