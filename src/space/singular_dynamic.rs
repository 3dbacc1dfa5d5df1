//! Singular dynamic method (Renard 2010, J. Comput. Appl. Math. 234:906–923).
//!
//! Displacement in V_h (P2), velocity in H_h (P1) on the same mesh:
//! `C_ij = ∫ρ ψ_i ψ_j`, `B_ij = ∫ρ ψ_i φ_j`, `M = Bᵀ C⁻¹ B` (dense, rank dim H_h: never formed; the
//! schemes carry `w = C⁻¹ B U` as unknowns). The contact dofs keep some mass (`M₀₀ ≠ 0`); the
//! problem is well posed when the inf-sup condition holds: some `u ∈ ker M` has a non-zero contact
//! trace, i.e. `rank [B; e_cᵀ] = rank B + 1` for each contact dof c ([`inf_sup_holds`]).

use super::{MassModel, Space};
use crate::error::{Error, Result};
use crate::fem::assembly::assemble;
use crate::linalg::SpMat;
use crate::problem::Inertia;
use nalgebra::DMatrix;

/// The singular dynamic method with the velocity space of the [`MassModel`].
#[derive(Debug, Clone, Copy)]
pub struct SingularDynamic;

impl Space for SingularDynamic {
    fn name(&self) -> &'static str {
        "singular_dynamic"
    }

    fn inertia(&self, model: &MassModel) -> Result<Inertia> {
        let (b, c) = mixed_matrices(model)?;
        Ok(Inertia::Mixed {
            b,
            c,
            consistent: model.assemble(|el, _| el.mass.clone())?,
        })
    }
}

/// Assembles `(B, C)` from the velocity-space element data.
pub fn mixed_matrices(model: &MassModel) -> Result<(SpMat, SpMat)> {
    let Some((elements, nh)) = &model.velocity else {
        return Err(Error::Unsupported(
            "singular_dynamic needs a displacement of degree 2 (P2 displacement / P1 velocity); \
             use --degree 2"
                .into(),
        ));
    };
    let pairs = model.elements.iter().zip(elements);
    let b = assemble(
        *nh,
        model.n_dofs,
        pairs.clone().flat_map(|(el, mx)| {
            el.dofs
                .iter()
                .zip(&mx.vdofs)
                .map(move |(d, v)| (v.iter().map(|&i| Some(i)).collect(), d.clone(), &mx.b))
        }),
    )?;
    let c = assemble(
        *nh,
        *nh,
        pairs.flat_map(|(_, mx)| {
            mx.vdofs.iter().map(move |v| {
                let v: Vec<Option<usize>> = v.iter().map(|&i| Some(i)).collect();
                (v.clone(), v, &mx.c)
            })
        }),
    )?;
    Ok((b, c))
}

/// Numerical rank of a dense matrix (relative tolerance 1e-10 on the singular values).
pub fn rank(m: &DMatrix<f64>) -> usize {
    let sv = m.clone().svd(false, false).singular_values;
    let tol = 1e-10 * sv.max().max(f64::MIN_POSITIVE);
    sv.iter().filter(|&&s| s > tol).count()
}

/// The inf-sup rank condition `rank [B; e_cᵀ] = rank B + 1` for every contact dof c (dense SVD:
/// a diagnostic for small meshes only).
pub fn inf_sup_holds(b: &DMatrix<f64>, contact_dofs: &[usize]) -> bool {
    let rb = rank(b);
    contact_dofs.iter().all(|&c| {
        let mut ext = b.clone().insert_row(b.nrows(), 0.0);
        ext[(b.nrows(), c)] = 1.0;
        rank(&ext) == rb + 1
    })
}
