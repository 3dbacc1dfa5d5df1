//! Mass elimination (GetFEM's dynamic contact demo): no mass is integrated on the elements that
//! touch Γ_C, `M_ij = Σ_{K ∩ Γ_C = ∅} ∫_K ρ φ_i φ_j`. The contact dofs are massless, but the mass of
//! those elements is lost (1D: total mass ρ(L − h) per contact end). Every component loses it,
//! the tangential ones too: with Coulomb friction a body sliding under gravity (whose load keeps
//! the consistent mass m) carries the friction force μ m g with the inertia `1ᵀM̃1 < m` and
//! decelerates at `μ g m / 1ᵀM̃1` (slide2d, 4 cells across: ⁴⁄₃ μ g, measured in
//! `tests/friction.rs`).

use super::sparse_mass::SparseMass;
use super::{MassModel, Space};
use crate::error::Result;
use crate::param::Entry;
use crate::problem::Inertia;
use nalgebra::DMatrix;

/// Mass elimination on the elements touching Γ_C.
#[derive(Debug, Clone, Copy)]
pub struct MassElimination;

/// Registry entry: `mass_elimination` (no parameter).
pub const ENTRY: Entry<dyn Space> = Entry {
    name: "mass_elimination",
    params: &[],
    build: |_| Ok(Box::new(MassElimination)),
};

impl Space for MassElimination {
    fn name(&self) -> &'static str {
        "mass_elimination"
    }

    fn inertia(&self, model: &MassModel) -> Result<Box<dyn Inertia>> {
        let m = model.assemble(|el, _| {
            if model.touches_contact(el) {
                DMatrix::zeros(el.mass.nrows(), el.mass.ncols())
            } else {
                el.mass.clone()
            }
        })?;
        model.check_inertia(self.name(), &m)?;
        Ok(SparseMass::boxed(m))
    }
}
