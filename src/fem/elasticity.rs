//! Isotropic linear elasticity on the reference elements of [`crate::element::reference`]: element stiffness
//! `K_(a,c),(b,d) = ∫ λ ∂_c φ_a ∂_d φ_b + μ ∂_d φ_a ∂_c φ_b + μ δ_cd ∇φ_a·∇φ_b` (plane strain in 2D:
//! the 3D Lamé constants), scalar element mass `∫ ρ φ_a φ_b`, mixed mass `∫ ρ ψ_i φ_b` with the
//! degree-1 basis ψ, and the stress `σ = λ tr ε I + 2 μ ε`. Local dof `(a, c)` has index
//! `a · dim + c`. The geometry is isoparametric: a cell is given by the coordinates `x` of its
//! local nodes, `x(ξ) = Σ_a x_a φ_a(ξ)` (curved P2/Q2 cells included); [`crate::mesh::Mesh::check`]
//! has refused cells whose Jacobian vanishes or changes sign.

use crate::element::geometry::{jacobian_from, physical, physical_gradients};
use crate::element::reference::{RefElement, Tabulation};
use nalgebra::{DMatrix, Matrix3};

/// Lamé constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lame {
    /// λ.
    pub lambda: f64,
    /// μ (shear modulus).
    pub mu: f64,
}

impl Lame {
    /// Young's modulus `E = μ (3λ + 2μ) / (λ + μ)`.
    pub fn young(&self) -> f64 {
        self.mu * (3.0 * self.lambda + 2.0 * self.mu) / (self.lambda + self.mu)
    }

    /// From Young's modulus and Poisson's ratio: `λ = Eν/((1+ν)(1−2ν))`, `μ = E/(2(1+ν))`.
    pub fn from_young_poisson(young: f64, poisson: f64) -> Self {
        Self {
            lambda: young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
            mu: young / (2.0 * (1.0 + poisson)),
        }
    }
}

/// Element stiffness (`dim · n` square) of the cell with node coordinates `x`, from its
/// element's basis at the quadrature points (`tab`, computed once for all the cells).
pub fn element_stiffness(tab: &Tabulation, x: &[[f64; 3]], lame: Lame) -> DMatrix<f64> {
    match tab.element.dim {
        1 => stiffness::<1>(tab, x, lame),
        2 => stiffness::<2>(tab, x, lame),
        _ => stiffness::<3>(tab, x, lame),
    }
}

/// [`element_stiffness`] in dimension `D`, its entries `(a, c), (b, e)` summed over the points
/// by rows `(a, c, e)` of every b: per entry, the same operations in the same order as one
/// entry at a time.
fn stiffness<const D: usize>(tab: &Tabulation, x: &[[f64; 3]], lame: Lame) -> DMatrix<f64> {
    let el = &tab.element;
    let n = el.n_nodes();
    let mut g = vec![[0.0; 3]; n];
    // ∂_l φ_b at l n + b, and ∇φ_a·∇φ_b of one a at b.
    let (mut gt, mut dot) = (vec![0.0; D * n], vec![0.0; n]);
    // K_(a,c),(b,e) at ((a D + c) D + e) n + b.
    let mut k = vec![0.0; n * D * D * n];
    for point in &tab.points {
        let wd = point.weight * physical_gradients(el, x, &point.gradients, &mut g);
        for (b, gb) in g.iter().enumerate() {
            for l in 0..D {
                gt[l * n + b] = gb[l];
            }
        }
        for (a, ga) in g.iter().enumerate() {
            for (b, d) in dot.iter_mut().enumerate() {
                *d = (0..D).map(|l| ga[l] * gt[l * n + b]).sum();
            }
            for c in 0..D {
                let lc = lame.lambda * ga[c];
                for e in 0..D {
                    let me = lame.mu * ga[e];
                    let row = &mut k[((a * D + c) * D + e) * n..][..n];
                    let (ge, gc) = (&gt[e * n..][..n], &gt[c * n..][..n]);
                    if c == e {
                        for (b, kb) in row.iter_mut().enumerate() {
                            let mut s = lc * ge[b] + me * gc[b];
                            s += lame.mu * dot[b];
                            *kb += wd * s;
                        }
                    } else {
                        for (b, kb) in row.iter_mut().enumerate() {
                            *kb += wd * (lc * ge[b] + me * gc[b]);
                        }
                    }
                }
            }
        }
    }
    DMatrix::from_fn(n * D, n * D, |i, j| {
        let (a, c, b, e) = (i / D, i % D, j / D, j % D);
        k[((a * D + c) * D + e) * n + b]
    })
}

/// Scalar element mass `∫ρ φ_a φ_b` (`n` square; the same on every component).
pub fn element_mass(tab: &Tabulation, x: &[[f64; 3]], rho: f64) -> DMatrix<f64> {
    let el = &tab.element;
    let n = el.n_nodes();
    let mut m = DMatrix::zeros(n, n);
    for p in &tab.points {
        let (w, v) = (p.weight, &p.values);
        let det = jacobian_from(el, x, &p.gradients).determinant().abs();
        for a in 0..n {
            for b in 0..n {
                m[(a, b)] += w * det * rho * v[a] * v[b];
            }
        }
    }
    m
}

/// `(C, B)` of the singular dynamic method on one cell: `C_ij = ∫ρ ψ_i ψ_j`, `B_ij = ∫ρ ψ_i φ_j`
/// with ψ the degree-1 basis of the same shape.
pub fn mixed_matrices(tab: &Tabulation, x: &[[f64; 3]], rho: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let el = &tab.element;
    let n = el.n_nodes();
    let nl = tab.points.first().map_or(0, |p| p.linear.len());
    let mut c = DMatrix::zeros(nl, nl);
    let mut b = DMatrix::zeros(nl, n);
    for p in &tab.points {
        let (phi, psi) = (&p.values, &p.linear);
        let wd = p.weight * jacobian_from(el, x, &p.gradients).determinant().abs() * rho;
        for i in 0..nl {
            for j in 0..nl {
                c[(i, j)] += wd * psi[i] * psi[j];
            }
            for j in 0..n {
                b[(i, j)] += wd * psi[i] * phi[j];
            }
        }
    }
    (c, b)
}

/// Stress tensor at reference point ξ of a cell from its local displacements `u[a·dim + c]`
/// (in 2D the plane-strain tensor, with σ_zz = λ tr ε).
pub fn stress(
    el: &RefElement,
    x: &[[f64; 3]],
    lame: Lame,
    u: &[f64],
    xi: [f64; 3],
) -> Matrix3<f64> {
    let d = el.dim;
    let (_, g, _) = physical(el, x, xi);
    let mut grad = Matrix3::zeros();
    for (a, ga) in g.iter().enumerate() {
        for c in 0..d {
            for l in 0..d {
                grad[(c, l)] += u[a * d + c] * ga[l];
            }
        }
    }
    let eps = (grad + grad.transpose()) * 0.5;
    let mut sigma = eps * (2.0 * lame.mu);
    let tr = eps.trace();
    for c in 0..d {
        sigma[(c, c)] += lame.lambda * tr;
    }
    if d == 2 {
        // Plane strain: ε_zz = 0, σ_zz = λ tr ε.
        sigma[(2, 2)] = lame.lambda * tr;
    }
    sigma
}

/// Von Mises equivalent stress `√(3/2 s:s)`, `s = σ − (tr σ / 3) I` the deviator.
pub fn von_mises(sigma: &Matrix3<f64>) -> f64 {
    let s = sigma - Matrix3::identity() * (sigma.trace() / 3.0);
    (1.5 * s.component_mul(&s).sum()).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The element stiffness as it was written before the tabulated basis, one entry at a time
    /// (`K_(a,c),(b,e) += |J| w (λ ∂_c φ_a ∂_e φ_b + μ ∂_e φ_a ∂_c φ_b + μ δ_ce ∇φ_a·∇φ_b)`).
    fn entry_by_entry(el: &RefElement, x: &[[f64; 3]], lame: Lame) -> DMatrix<f64> {
        let (n, d) = (el.n_nodes(), el.dim);
        let mut k = DMatrix::zeros(n * d, n * d);
        for (xi, w) in el.quadrature() {
            let (_, g, det) = physical(el, x, xi);
            for (a, ga) in g.iter().enumerate() {
                for (b, gb) in g.iter().enumerate() {
                    let dot: f64 = (0..d).map(|l| ga[l] * gb[l]).sum();
                    for c in 0..d {
                        for e in 0..d {
                            let mut s = lame.lambda * ga[c] * gb[e] + lame.mu * ga[e] * gb[c];
                            if c == e {
                                s += lame.mu * dot;
                            }
                            k[(a * d + c, b * d + e)] += w * det * s;
                        }
                    }
                }
            }
        }
        k
    }

    /// The stiffness by rows over the tabulated basis is the entry-by-entry stiffness bit for
    /// bit, on a distorted cell of every family.
    #[test]
    fn the_stiffness_by_rows_is_the_entry_by_entry_one_to_the_bit() {
        let lame = Lame::from_young_poisson(2.1, 0.3);
        for el in RefElement::every() {
            let x: Vec<[f64; 3]> = (0..el.n_nodes())
                .map(|a| {
                    let p = el.node(a);
                    let wobble = |k: usize| 0.07 * ((a * 3 + k) as f64).sin();
                    std::array::from_fn(|k| if k < el.dim { p[k] + wobble(k) } else { 0.0 })
                })
                .collect();
            let (ours, theirs) = (
                element_stiffness(&el.tabulate(), &x, lame),
                entry_by_entry(&el, &x, lame),
            );
            let bits = |m: &DMatrix<f64>| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&ours), bits(&theirs), "{el:?}");
        }
    }
}
