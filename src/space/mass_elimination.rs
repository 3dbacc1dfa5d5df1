//! Mass elimination (GetFEM's dynamic contact demo): no mass is integrated on the elements that
//! touch Γ_C, `M_ij = Σ_{K ∩ Γ_C = ∅} ∫_K ρ φ_i φ_j`. The contact dofs are massless, but the mass of
//! those elements is lost (1D: total mass ρ(L − h) per contact end). Every component loses it,
//! the tangential ones too: with Coulomb friction a body sliding under gravity (whose load keeps
//! the consistent mass m) carries the friction force μ m g with the inertia `1ᵀM̃1 < m` and
//! decelerates at `μ g m / 1ᵀM̃1` (slide2d, 4 cells across: ⁴⁄₃ μ g, measured in
//! `tests/friction.rs`).

use super::sparse_mass::SparseMass;
use super::{MassModel, Space};
use crate::error::{Error, Result};
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
        check_mass_left(model)?;
        Ok(SparseMass::boxed(model.assemble(|el, _| {
            if model.touches_contact(el) {
                DMatrix::zeros(el.mass.nrows(), el.mass.ncols())
            } else {
                el.mass.clone()
            }
        })?))
    }
}

/// Refuses a floating body (elements connected through their dofs, none of them fixed) whose
/// every element touches Γ_C: this space leaves it no mass, and `m M + k K` is singular on its
/// rigid motions (slide_on_block3d's lower block, two layers of cells between the plane and the
/// upper block, failed in the factorisation with a non-positive pivot).
fn check_mass_left(model: &MassModel) -> Result<()> {
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut parent: Vec<usize> = (0..model.n_dofs).collect();
    let dofs = |el: &crate::fem::mass_model::ElementMass| {
        el.dofs
            .iter()
            .flatten()
            .flatten()
            .copied()
            .collect::<Vec<usize>>()
    };
    for el in &model.elements {
        let d = dofs(el);
        for w in d.windows(2) {
            let (a, b) = (root(&mut parent, w[0]), root(&mut parent, w[1]));
            parent[a] = b;
        }
    }
    // Per body (root): (elements, some fixed dof, some element off Γ_C).
    let mut body = vec![(0usize, false, false); model.n_dofs];
    for el in &model.elements {
        let Some(&first) = dofs(el).first() else {
            continue;
        };
        let b = &mut body[root(&mut parent, first)];
        b.0 += 1;
        b.1 |= el.dofs.iter().flatten().any(Option::is_none);
        b.2 |= !model.touches_contact(el);
    }
    match body.iter().find(|b| b.0 > 0 && !b.1 && !b.2) {
        Some(&(elements, ..)) => Err(Error::Unsupported(format!(
            "space `mass_elimination` leaves a free body without mass: each of its {elements} \
             elements touches Γ_C, so the step matrix is singular on its rigid motions; use more \
             elements across it (mesh.elements, master.mesh.elements) or mass_redistribution"
        ))),
        None => Ok(()),
    }
}
