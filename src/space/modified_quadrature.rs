//! Modified mass by quadrature, after Hager, Hüeber & Wohlmuth (IJNME 73, 2008) and Hager &
//! Wohlmuth (SINUM 47, 2009): the construction of `notes/papers/modified_quadrature.md` (the
//! papers could not be read here; their rule of points and weights is not checked, the idea is).
//!
//! On every element K touching Γ_C the mass is integrated by a *nodal* quadrature whose points
//! are the nodes of K not on Γ_C: `M̃^K = diag(w_a)`, `w_a = 0` at every node with a contact dof
//! (all its components are then massless, tangential ones too), `w_a ≥ 0` elsewhere; the other
//! elements keep their consistent mass. The weights integrate exactly, as far as nonnegative
//! weights on the remaining nodes allow, the moment groups in order
//! - the element mass `Σ w_a = ∫_K ρ` (always kept),
//! - the first moments `Σ w_a x_{a,k} = ∫_K ρ x_k`,
//! - the second moments `Σ w_a x_{a,k} x_{a,l} = ∫_K ρ x_k x_l`,
//!
//! each level the nonnegative solution closest (Euclidean) to the HRZ-lumped masses of the
//! remaining nodes, found by projecting onto the constraints and dropping the nodes that come
//! out negative until none does. Kept moments sum over elements, so the global `M̃` keeps them.
//! Kept: 1D P1 the mass only (the first element's centre of mass moves from h/2 to h: global
//! `xᵀM̃1 = ∫ρx + ρh²/2`); 1D P2 mass and first moment (the weight sits on the mid node, none on
//! the far node, which keeps the mass of its other element; second moment `∫ρx² − ρh³/12`); Q1
//! with an edge on Γ_C the mass (and the tangential first moment). Only the Γ_C nodes are
//! massless as long as every other node of a touching element belongs to an untouched one.

use super::lumped::hrz;
use super::mass_redistribution::{moment_groups, relative_coords, Kept};
use super::sparse_mass::SparseMass;
use super::{MassModel, Space};
use crate::error::Result;
use crate::param::Entry;
use crate::problem::Inertia;
use nalgebra::{DMatrix, DVector};

/// Modified quadrature on the elements touching Γ_C.
#[derive(Debug, Clone, Copy)]
pub struct ModifiedQuadrature;

/// Registry entry: `modified_quadrature` (no parameter).
pub const ENTRY: Entry<dyn Space> = Entry {
    name: "modified_quadrature",
    params: &[],
    build: |_| Ok(Box::new(ModifiedQuadrature)),
};

impl Space for ModifiedQuadrature {
    fn name(&self) -> &'static str {
        "modified_quadrature"
    }

    fn inertia(&self, model: &MassModel) -> Result<Box<dyn Inertia>> {
        let m = model.assemble(|el, _| {
            let contact: Vec<bool> = (0..el.x.len())
                .map(|a| (0..el.dofs.len()).any(|c| model.is_contact(el, c, a)))
                .collect();
            if contact.iter().any(|&b| b) {
                DMatrix::from_diagonal(&nodal_weights(&el.mass, &el.x, model.dim, &contact).0)
            } else {
                el.mass.clone()
            }
        })?;
        model.check_inertia(self.name(), &m)?;
        Ok(SparseMass::boxed(m))
    }
}

/// The nodal weights `w ≥ 0` of an element with consistent mass `m` and nodes `x`, zero where
/// `contact[a]`, and the moments they keep (see the module doc).
pub fn nodal_weights(
    m: &DMatrix<f64>,
    x: &[[f64; 3]],
    dim: usize,
    contact: &[bool],
) -> (DVector<f64>, Kept) {
    let n = m.nrows();
    let xs = relative_coords(x);
    let lumped = hrz(m).diagonal();
    let mut best = (DVector::zeros(n), Kept::Nothing);
    let (mut rows, mut targets) = (Vec::new(), Vec::new());
    let levels = [Kept::Total, Kept::FirstMoments, Kept::SecondMoments];
    for (group, kept) in moment_groups(dim).into_iter().zip(levels) {
        for f in &group {
            rows.push((0..n).map(|a| f(&xs[a], &xs[a])).collect::<Vec<_>>());
            targets.push(
                (0..n)
                    .flat_map(|a| (0..n).map(move |b| (a, b)))
                    .map(|(a, b)| m[(a, b)] * f(&xs[a], &xs[b]))
                    .sum::<f64>(),
            );
        }
        match nonnegative_projection(&rows, &targets, &lumped, contact) {
            Some(w) => best = (w, kept),
            // More constraints cannot be met either.
            None => break,
        }
    }
    best
}

/// `w ≥ 0` with `G w = c`, `w_a = 0` where `fixed[a]`, closest to `w0`: the projection onto the
/// constraints restricted to the free nodes, dropping the negative ones until none is left.
/// None when no such w is found (the constraints are inconsistent on the nodes left).
fn nonnegative_projection(
    g: &[Vec<f64>],
    c: &[f64],
    w0: &DVector<f64>,
    fixed: &[bool],
) -> Option<DVector<f64>> {
    let mut free: Vec<usize> = (0..w0.len()).filter(|&a| !fixed[a]).collect();
    let scale = c
        .iter()
        .fold(0.0f64, |s, v| s.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    while !free.is_empty() {
        let gf = DMatrix::from_fn(g.len(), free.len(), |i, j| g[i][free[j]]);
        let w0f = DVector::from_iterator(free.len(), free.iter().map(|&a| w0[a]));
        let r = DVector::from_column_slice(c) - &gf * &w0f;
        // Minimum-norm correction: dependent constraints are allowed when consistent.
        let dw = gf.clone().pseudo_inverse(1e-12).ok()? * &r;
        let wf = w0f + dw;
        if (&gf * &wf - DVector::from_column_slice(c)).amax() > 1e-10 * scale {
            return None;
        }
        let min = wf.min();
        if min >= -1e-12 * scale {
            let mut w = DVector::zeros(w0.len());
            for (&a, v) in free.iter().zip(wf.iter()) {
                w[a] = v.max(0.0);
            }
            return Some(w);
        }
        let negative: Vec<usize> = free
            .iter()
            .zip(wf.iter())
            .filter(|(_, &v)| v < -1e-12 * scale)
            .map(|(&a, _)| a)
            .collect();
        free.retain(|a| !negative.contains(a));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::segment::Segment;
    use crate::fem::assembly::segment_mass;

    fn segment(degree: usize, h: f64) -> (DMatrix<f64>, Vec<[f64; 3]>) {
        let x = (0..=degree)
            .map(|k| [2.0 + h * k as f64 / degree as f64, 0.0, 0.0])
            .collect();
        (segment_mass(Segment { degree }, h, 3.0), x)
    }

    /// `(Σ w, Σ w x, Σ w x²)` and the exact `ρ ∫_K (1, x, x²)` on the segment (2, 2 + h), ρ = 3.
    fn moments(w: &DVector<f64>, x: &[[f64; 3]], h: f64) -> ([f64; 3], [f64; 3]) {
        let got =
            std::array::from_fn(|k| w.iter().zip(x).map(|(w, p)| w * p[0].powi(k as i32)).sum());
        let exact = std::array::from_fn(|k| {
            3.0 * ((2.0 + h).powi(k as i32 + 1) - 2f64.powi(k as i32 + 1)) / (k as f64 + 1.0)
        });
        (got, exact)
    }

    #[test]
    fn p1_segment_keeps_the_mass_only_on_the_far_node() {
        let h = 0.25;
        let (m, x) = segment(1, h);
        let (w, kept) = nodal_weights(&m, &x, 1, &[true, false]);
        assert_eq!(kept, Kept::Total);
        assert_eq!(w[0], 0.0);
        let (got, exact) = moments(&w, &x, h);
        assert!((got[0] - exact[0]).abs() < 1e-14);
        // The centre of mass moves from the midpoint to the far node: + ρ h²/2.
        assert!((got[1] - exact[1] - 3.0 * h * h / 2.0).abs() < 1e-13);
    }

    #[test]
    fn p2_segment_keeps_mass_and_first_moment_on_the_mid_node() {
        let h = 0.25;
        let (m, x) = segment(2, h);
        for contact in [[true, false, false], [false, false, true]] {
            let (w, kept) = nodal_weights(&m, &x, 1, &contact);
            assert_eq!(kept, Kept::FirstMoments);
            let (got, exact) = moments(&w, &x, h);
            assert!((got[0] - exact[0]).abs() < 1e-14 && (got[1] - exact[1]).abs() < 1e-13);
            // Simpson-like midpoint: the second moment misses ρ h³/12.
            assert!((exact[2] - got[2] - 3.0 * h.powi(3) / 12.0).abs() < 1e-13);
            assert!((w[1] - 3.0 * h).abs() < 1e-14, "{w}");
            assert!(w
                .iter()
                .zip(contact)
                .all(|(&w, c)| w >= 0.0 && (!c || w == 0.0)));
        }
    }

    /// Q1 on the unit square with the edge y = 0 on Γ_C (nodes (0,0), (1,0), (1,1), (0,1)):
    /// ½ on each far node, total and tangential first moment kept, normal moment 1 instead of ½.
    #[test]
    fn q1_with_an_edge_on_gamma_c_keeps_the_mass() {
        let q = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]) / 6.0;
        // Consistent Q1 mass = Kronecker product of the 1D masses (node order mapped).
        let idx = [(0, 0), (1, 0), (1, 1), (0, 1)];
        let m = DMatrix::from_fn(4, 4, |a, b| {
            q[(idx[a].0, idx[b].0)] * q[(idx[a].1, idx[b].1)]
        });
        let x = idx.map(|(i, j)| [i as f64, j as f64, 0.0]);
        let (w, kept) = nodal_weights(&m, &x, 2, &[true, true, false, false]);
        assert_eq!(kept, Kept::Total);
        assert!(
            (w[2] - 0.5).abs() < 1e-14 && (w[3] - 0.5).abs() < 1e-14,
            "{w}"
        );
    }
}
