//! The isoparametric map of a cell, `x(ξ) = Σ_a x_a φ_a(ξ)` from the coordinates `x` of its local
//! nodes (curved P2/Q2 cells included): its Jacobian, and the physical gradients of the basis.

use super::reference::RefElement;
use nalgebra::Matrix3;

/// Jacobian `J = Σ_a x_a ⊗ ∇̂φ_a(ξ)` of the isoparametric map at ξ (columns: images of the
/// reference axes; the unused block of a 2D cell is the identity).
pub fn jacobian(el: &RefElement, x: &[[f64; 3]], xi: [f64; 3]) -> Matrix3<f64> {
    jacobian_from(el, x, &el.eval(xi).1)
}

pub fn jacobian_from(el: &RefElement, x: &[[f64; 3]], g: &[[f64; 3]]) -> Matrix3<f64> {
    let mut j = Matrix3::identity();
    for k in 0..el.dim {
        for r in 0..el.dim {
            j[(r, k)] = x.iter().zip(g).map(|(xa, ga)| xa[r] * ga[k]).sum();
        }
    }
    j
}

/// Values and physical gradients `J⁻ᵀ ∇̂φ` at a point, and `|det J|`.
pub fn physical(el: &RefElement, x: &[[f64; 3]], xi: [f64; 3]) -> (Vec<f64>, Vec<[f64; 3]>, f64) {
    let (v, g) = el.eval(xi);
    let mut out = vec![[0.0; 3]; g.len()];
    let det = physical_gradients(el, x, &g, &mut out);
    (v, out, det)
}

/// The physical gradients `J⁻ᵀ ∇̂φ_a` into `out` from the reference gradients `g` at a point
/// (e.g. [`super::reference::Tabulation`]'s), and `|det J|`.
pub fn physical_gradients(
    el: &RefElement,
    x: &[[f64; 3]],
    g: &[[f64; 3]],
    out: &mut [[f64; 3]],
) -> f64 {
    let jac = jacobian_from(el, x, g);
    // Checked cells have det J ≠ 0 (Mesh::check); zero gradients rather than a panic otherwise.
    let inv_t = jac.try_inverse().unwrap_or_else(Matrix3::zeros).transpose();
    for (o, gr) in out.iter_mut().zip(g) {
        let p = inv_t * nalgebra::Vector3::new(gr[0], gr[1], gr[2]);
        *o = [p[0], p[1], p[2]];
    }
    jac.determinant().abs()
}
