//! The element data every space builds its inertia from ([`crate::space`]): element masses,
//! the contact normal dofs and, for degree-2 displacements, the velocity space H_h of the
//! singular dynamic method. Produced by a discretisation ([`super::discretisation`]).

use crate::error::{Error, Result};
use crate::fem::assembly::assemble_square;
use crate::linalg::SpMat;
use nalgebra::DMatrix;

/// Element data for the mass: a scalar consistent mass `∫ρ φ_a φ_b` repeated on each displacement
/// component (the vector mass is block diagonal).
#[derive(Debug, Clone)]
pub struct ElementMass {
    /// Coordinates of the local nodes (unused components 0).
    pub x: Vec<[f64; 3]>,
    /// Scalar consistent element mass `M^K_ab = ∫_K ρ φ_a φ_b`.
    pub mass: DMatrix<f64>,
    /// For each displacement component, the global dof of each local node (None: eliminated).
    pub dofs: Vec<Vec<Option<usize>>>,
}

/// Element data of the velocity space H_h (singular dynamic method).
#[derive(Debug, Clone)]
pub struct ElementMixed {
    /// `C^K_ij = ∫_K ρ ψ_i ψ_j` (H_h basis).
    pub c: DMatrix<f64>,
    /// `B^K_ij = ∫_K ρ ψ_i φ_j` (rows H_h, columns V_h local nodes).
    pub b: DMatrix<f64>,
    /// For each component, the global H_h dof of each local H_h node.
    pub vdofs: Vec<Vec<usize>>,
}

/// The velocity space H_h (degree 1 on the same mesh) of the singular dynamic method.
#[derive(Debug, Clone)]
pub struct VelocitySpace {
    /// Element data, one per element of the [`MassModel`], same order.
    pub elements: Vec<ElementMixed>,
    /// dim H_h.
    pub dim: usize,
    /// The H_h dof at the node of each displacement dof, when that node is a vertex.
    pub dof_of: Vec<Option<usize>>,
}

/// Everything a space needs: element masses, which dofs are contact normal dofs, and (when the
/// displacement is of degree ≥ 2) the velocity space of the singular dynamic method.
#[derive(Debug, Clone)]
pub struct MassModel {
    /// Number of free displacement dofs.
    pub n_dofs: usize,
    /// Spatial dimension (number of coordinates used for moments).
    pub dim: usize,
    /// Element data, one per element.
    pub elements: Vec<ElementMass>,
    /// Global dofs of the contact normal displacements (massless under mass redistribution),
    /// sorted increasingly.
    pub contact_dofs: Vec<usize>,
    /// The velocity space H_h of the singular dynamic method, when the displacement's degree
    /// allows one.
    pub velocity: Option<VelocitySpace>,
}

impl MassModel {
    /// Assembles `Σ_K Σ_c local(K, c)` over the elements and displacement components `c`
    /// (streamed: [`assemble_square`], element matrices in parallel, added in element order).
    pub fn assemble(
        &self,
        local: impl Fn(&ElementMass, usize) -> DMatrix<f64> + Sync,
    ) -> Result<SpMat> {
        let comps = self.elements.first().map_or(1, |el| el.dofs.len());
        assemble_square(
            self.n_dofs,
            self.elements.len() * comps,
            |k| self.elements[k / comps].dofs[k % comps].clone(),
            |k| local(&self.elements[k / comps], k % comps),
        )
    }

    /// True when element `el` has a contact dof on component `comp` at local node `a`.
    pub fn is_contact(&self, el: &ElementMass, comp: usize, a: usize) -> bool {
        el.dofs[comp][a].is_some_and(|d| self.contact_dofs.binary_search(&d).is_ok())
    }

    /// True when the element touches the contact boundary.
    pub fn touches_contact(&self, el: &ElementMass) -> bool {
        (0..el.dofs.len()).any(|c| (0..el.x.len()).any(|a| self.is_contact(el, c, a)))
    }

    /// Refuses the mass `m` that space `space` assembled when it leaves a floating body
    /// (elements connected through their dofs, none of them fixed) without inertia along a
    /// displacement component c: the rigid translation t along c has `tᵀ m t` ≤ 1e-12 of the
    /// consistent mass's, and `m M + k K` is singular on it (slide_on_block3d's lower block of
    /// one layer of cells, its every node on Γ_C, failed in the factorisation with a
    /// non-positive pivot under mass redistribution and modified quadrature).
    pub fn check_inertia(&self, space: &str, m: &SpMat) -> Result<()> {
        let comps = self.elements.first().map_or(1, |el| el.dofs.len());
        let mut parent: Vec<usize> = (0..self.n_dofs).collect();
        let mut comp = vec![0; self.n_dofs];
        for el in &self.elements {
            let mut dofs = el
                .dofs
                .iter()
                .enumerate()
                .flat_map(|(c, d)| d.iter().flatten().map(move |&i| (c, i)));
            let Some((c0, first)) = dofs.next() else {
                continue;
            };
            comp[first] = c0;
            for (c, i) in dofs {
                comp[i] = c;
                let (a, b) = (root(&mut parent, i), root(&mut parent, first));
                parent[a] = b;
            }
        }
        // Per body (root): elements, some fixed dof, the translations' consistent mass and m's.
        let mut body = std::collections::BTreeMap::<usize, (usize, bool, f64, [f64; 3])>::new();
        for el in &self.elements {
            let Some(&first) = el.dofs.iter().flatten().flatten().next() else {
                continue;
            };
            let b = body.entry(root(&mut parent, first)).or_default();
            b.0 += 1;
            b.1 |= el.dofs.iter().flatten().any(Option::is_none);
            b.2 += el.mass.sum();
        }
        for (i, _, v) in crate::linalg::triplets(m) {
            if let Some(b) = body.get_mut(&root(&mut parent, i)) {
                b.3[comp[i]] += v;
            }
        }
        let massless = body
            .values()
            .filter(|b| !b.1)
            .find_map(|&(elements, _, full, kept)| {
                (0..comps)
                    .find(|&c| kept[c] <= 1e-12 * full)
                    .map(|c| (elements, c, full))
            });
        match massless {
            Some((elements, c, full)) => Err(Error::Unsupported(format!(
                "space `{space}` leaves a free body without inertia along e_{}: the \
                 rigid translation of its {elements} elements has no mass (its consistent mass: \
                 {full:.3e}), so the step matrix m M + k K is singular on it; use more elements \
                 across the body (mesh.elements, master.mesh.elements), or the standard mass",
                c + 1
            ))),
            None => Ok(()),
        }
    }
}

/// The root of `i` in the union–find forest `parent` (paths halved on the way).
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}
