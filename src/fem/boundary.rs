//! Quadrature on the faces of Γ_C, for the boundary integrals of Nitsche's method
//! ([`crate::contact::nitsche`]).
//!
//! A face F of cell T is the image of the degree-1 interpolation ξ(s) of its local vertices' reference
//! coordinates ξ_k (a segment, a triangle, or a bilinear quadrilateral) under the cell's
//! isoparametric map, so a curved P2/Q2 face is integrated as the cell sees it:
//! `∫_F f = Σ_q ŵ_q |J ∂ξ/∂s| f(x(s_q))` in 2D and `Σ_q ŵ_q |J ∂ξ/∂s × J ∂ξ/∂t| f` in 3D
//! (J the cell's Jacobian). Gauss–Legendre rules with `degree + 1` points per direction (its
//! collapsed version on triangles): exact for the face mass of the displacement's trace on
//! straight faces. At each point, with the plane's outward normal `n = −e_d`:
//! - `u_N = u·n = −Σ_a φ_a u_{a,d}`, the gap `g₀ = x_d + lift`;
//! - `σ_N = n·σ(u)n = σ_dd = λ div u + 2μ ∂_d u_d`, from the gradients of T's basis;
//! - along the tangents `t_k = e_k` (k < d − 1, as the nodal `B_T`): `u_T = u_k` and
//!   `σ_T = t_k·σ(u)n = −σ_kd = −μ (∂_d u_k + ∂_k u_d)` (Nitsche's friction);
//! - `h/E` with h the diameter of T (largest distance between its vertices).

use super::dofs::DofMap;
use super::elasticity::Lame;
use crate::element::geometry::{jacobian, physical};
use crate::element::quadrature::gauss_legendre_01;
use crate::element::segment::Segment;
use crate::mesh::{Face, Mesh};
use crate::problem::BoundaryPoint;
use nalgebra::Vector3;
use std::collections::HashMap;

/// Basis values below this are the zeros of the nodes off the face (dropped from the rows).
const ZERO: f64 = 1e-13;

/// A point of the reference face: its degree-1 hat functions (one per face vertex), the
/// derivatives of ξ(s) with respect to the face parameters, and the rule's weight.
struct FacePoint {
    hats: Vec<f64>,
    tangents: Vec<[f64; 3]>,
    weight: f64,
}

/// The parameter-space rule of a face with `k` vertices (2: segment, 3: triangle, 4:
/// quadrilateral in cyclic order), `m` Gauss points per direction, the face's reference vertices
/// `x`.
fn face_rule(x: &[[f64; 3]], m: usize) -> Vec<FacePoint> {
    let rule = gauss_legendre_01(m);
    let d = |a: usize, b: usize| -> [f64; 3] { std::array::from_fn(|c| x[a][c] - x[b][c]) };
    let lerp = |p: [f64; 3], q: [f64; 3], t: f64| -> [f64; 3] {
        std::array::from_fn(|c| (1.0 - t) * p[c] + t * q[c])
    };
    let mut out = Vec::new();
    match x.len() {
        2 => {
            for &(s, w) in &rule {
                out.push(FacePoint {
                    hats: vec![1.0 - s, s],
                    tangents: vec![d(1, 0)],
                    weight: w,
                });
            }
        }
        3 => {
            // (u, v) ∈ [0, 1]² ↦ (u, v (1 − u)), Jacobian 1 − u.
            for &(u, wu) in &rule {
                for &(v, wv) in &rule {
                    let (a, b) = (u, v * (1.0 - u));
                    out.push(FacePoint {
                        hats: vec![1.0 - a - b, a, b],
                        tangents: vec![d(1, 0), d(2, 0)],
                        weight: wu * wv * (1.0 - u),
                    });
                }
            }
        }
        _ => {
            for &(t, wt) in &rule {
                for &(s, ws) in &rule {
                    out.push(FacePoint {
                        hats: vec![(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t],
                        tangents: vec![lerp(d(1, 0), d(2, 3), t), lerp(d(3, 0), d(2, 1), s)],
                        weight: ws * wt,
                    });
                }
            }
        }
    }
    out
}

/// The diameter of cell `c` (largest distance between two of its vertices).
fn diameter(mesh: &Mesh, c: usize) -> f64 {
    let x: Vec<[f64; 3]> = mesh
        .element
        .vertices()
        .iter()
        .map(|&a| mesh.nodes[mesh.connectivity[c][a]])
        .collect();
    let mut h: f64 = 0.0;
    for (i, p) in x.iter().enumerate() {
        for q in &x[i + 1..] {
            h = h.max((0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt());
        }
    }
    h
}

/// The quadrature points of the faces of Γ_C (in face order) for a body lifted by `lift` above
/// the plane `x_d = 0`; `row` maps a Γ_C vertex to its contact row, `dofs` a node's components
/// to their dofs.
pub fn contact_points(
    mesh: &Mesh,
    faces: &[Face],
    lame: Lame,
    lift: f64,
    (row, dofs): (&HashMap<usize, usize>, &DofMap),
) -> Vec<BoundaryPoint> {
    if mesh.dim() == 1 {
        return faces
            .iter()
            .map(|f| end_point(mesh, f, lame, lift, (row, dofs)))
            .collect();
    }
    let (el, d) = (mesh.element, mesh.dim());
    let young = lame.young();
    let mut points = Vec::new();
    for f in faces {
        let cell = &mesh.connectivity[f.cell];
        let x = mesh.cell_nodes(f.cell);
        let corners: Vec<[f64; 3]> = f.local.iter().map(|&a| el.node(a)).collect();
        let h_over_e = diameter(mesh, f.cell) / young;
        for p in face_rule(&corners, el.degree + 1) {
            let xi: [f64; 3] =
                std::array::from_fn(|c| p.hats.iter().zip(&corners).map(|(h, v)| h * v[c]).sum());
            let jac = jacobian(&el, &x, xi);
            let t: Vec<Vector3<f64>> = p
                .tangents
                .iter()
                .map(|t| jac * Vector3::new(t[0], t[1], t[2]))
                .collect();
            let measure = if t.len() == 1 {
                t[0].norm()
            } else {
                t[0].cross(&t[1]).norm()
            };
            let (phi, grad, _) = physical(&el, &x, xi);
            let last = d - 1;
            let mut u_n = Vec::new();
            let mut sigma_n = Vec::new();
            let mut u_t = vec![Vec::new(); last];
            let mut sigma_t = vec![Vec::new(); last];
            let mut height = 0.0;
            for (a, &node) in cell.iter().enumerate() {
                height += phi[a] * x[a][last];
                if phi[a].abs() > ZERO {
                    if let Some(dof) = dofs.get(node, last) {
                        u_n.push((dof, -phi[a]));
                    }
                }
                for c in 0..d {
                    let mut s = lame.lambda * grad[a][c];
                    if c == last {
                        s += 2.0 * lame.mu * grad[a][last];
                    }
                    if let (true, Some(dof)) = (s != 0.0, dofs.get(node, c)) {
                        sigma_n.push((dof, s));
                    }
                }
                for k in 0..last {
                    if let (true, Some(dof)) = (phi[a].abs() > ZERO, dofs.get(node, k)) {
                        u_t[k].push((dof, phi[a]));
                    }
                    for (c, g) in [(k, grad[a][last]), (last, grad[a][k])] {
                        if let (true, Some(dof)) = (g != 0.0, dofs.get(node, c)) {
                            sigma_t[k].push((dof, -lame.mu * g));
                        }
                    }
                }
            }
            points.push(BoundaryPoint {
                weight: p.weight * measure,
                g0: height + lift,
                u_n,
                sigma_n,
                u_t,
                sigma_t,
                h_over_e,
                vertices: f.vertices.iter().map(|v| row[v]).zip(p.hats).collect(),
            });
        }
    }
    points
}

/// The boundary "integral" at the end point `f` of a 1D body (unit cross-section): the point
/// value, weight 1, with `σ_N = n·σ n = (λ + 2μ) u'` from the segment's basis (the bar's
/// `E u'`, ν = 0) and `h/E` on the uniform length.
fn end_point(
    mesh: &Mesh,
    f: &Face,
    lame: Lame,
    lift: f64,
    (row, dofs): (&HashMap<usize, usize>, &DofMap),
) -> BoundaryPoint {
    let (el, h) = (mesh.element, mesh.h);
    let seg = Segment { degree: el.degree };
    let modulus = lame.lambda + 2.0 * lame.mu;
    let a = f.local[0];
    let xi = el.node(a)[0];
    let cell = &mesh.connectivity[f.cell];
    let node = cell[a];
    BoundaryPoint {
        weight: 1.0,
        g0: mesh.nodes[node][0] + lift,
        u_n: dofs
            .get(node, 0)
            .map(|dof| (dof, -1.0))
            .into_iter()
            .collect(),
        sigma_n: cell
            .iter()
            .enumerate()
            .filter_map(|(k, &i)| {
                dofs.get(i, 0)
                    .map(|dof| (dof, modulus * seg.derivative(k, xi) / h))
            })
            .collect(),
        u_t: Vec::new(),
        sigma_t: Vec::new(),
        h_over_e: h / modulus,
        vertices: vec![(row[&node], 1.0)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::reference::{RefElement, Shape};
    use crate::mesh::{structured::box_mesh, ContactRule, FACING};

    fn points(mesh: &Mesh, lame: Lame, lift: f64) -> Vec<BoundaryPoint> {
        let faces = mesh.contact_faces(ContactRule::Facing(FACING)).unwrap();
        let row = mesh
            .tributary(&faces)
            .iter()
            .enumerate()
            .map(|(r, v)| (v.0, r))
            .collect();
        let dofs = DofMap::free(mesh.nodes.len(), mesh.dim());
        contact_points(mesh, &faces, lame, lift, (&row, &dofs))
    }

    /// On the bottom of the unit box, for every element family: the weights sum to |Γ_C| = 1 and
    /// integrate x² exactly (1/3), the shares sum to 1, g₀ is the lift, u_N of a vertical
    /// translation u = c e_d is −c, and σ_N of a linear field u_k = Σ_l G_kl x_l is the exact
    /// `λ tr G + 2μ G_dd`.
    #[test]
    fn box_bottom_quadrature_is_exact_for_every_element() {
        let lame = Lame::from_young_poisson(2.0, 0.3);
        let grad = [[0.1, -0.2, 0.3], [0.05, 0.4, -0.1], [0.2, 0.15, -0.3]];
        for el in RefElement::every() {
            let mesh = box_mesh(el, [3, 2, 2], [1.0, 1.0, 1.0]).unwrap();
            let d = el.dim;
            let pts = points(&mesh, lame, 0.25);
            let total: f64 = pts.iter().map(|p| p.weight).sum();
            assert!((total - 1.0).abs() < 1e-13, "{el:?}: |Γ_C| = {total}");
            let n = mesh.nodes.len() * d;
            let mut shift = vec![0.0; n];
            let mut linear = vec![0.0; n];
            for (i, x) in mesh.nodes.iter().enumerate() {
                shift[i * d + d - 1] = 0.7;
                for k in 0..d {
                    linear[i * d + k] = (0..d).map(|l| grad[k][l] * x[l]).sum();
                }
            }
            let dot =
                |row: &[(usize, f64)], u: &[f64]| row.iter().map(|&(j, v)| v * u[j]).sum::<f64>();
            let tr: f64 = (0..d).map(|k| grad[k][k]).sum();
            let exact = lame.lambda * tr + 2.0 * lame.mu * grad[d - 1][d - 1];
            let faces = mesh.contact_faces(ContactRule::Facing(FACING)).unwrap();
            let vertices = mesh.tributary(&faces);
            let mut second = 0.0;
            for p in &pts {
                assert!((p.g0 - 0.25).abs() < 1e-14, "{el:?}: g₀ {}", p.g0);
                let shares: f64 = p.vertices.iter().map(|e| e.1).sum();
                assert!((shares - 1.0).abs() < 1e-14, "{el:?}");
                assert!((dot(&p.u_n, &shift) + 0.7).abs() < 1e-13, "{el:?}");
                assert!((dot(&p.sigma_n, &linear) - exact).abs() < 1e-12, "{el:?}");
                assert_eq!(p.u_t.len(), d - 1, "{el:?}");
                for (k, (u_t, sigma_t)) in p.u_t.iter().zip(&p.sigma_t).enumerate() {
                    let slide: Vec<f64> = (0..n).map(|j| f64::from(j % d == k)).collect();
                    let shear = -lame.mu * (grad[k][d - 1] + grad[d - 1][k]);
                    assert!(dot(u_t, &shift).abs() < 1e-14, "{el:?}");
                    assert!((dot(u_t, &slide) - 1.0).abs() < 1e-13, "{el:?}");
                    assert!((dot(sigma_t, &linear) - shear).abs() < 1e-12, "{el:?}");
                }
                let x: f64 = p
                    .vertices
                    .iter()
                    .map(|&(r, s)| s * mesh.nodes[vertices[r].0][0])
                    .sum();
                second += p.weight * x * x;
            }
            assert!((second - 1.0 / 3.0).abs() < 1e-13, "{el:?}: ∫x² = {second}");
        }
    }

    /// On the disc (curved Γ_C, isoparametric cells): degree 1 integrates the straight faces
    /// (weights sum to the chords), degree 2 the curved ones: the weights sum to the arc `R Δφ`
    /// between Γ_C's end vertices (φ from the pole) a hundred times closer than the chords
    /// (O(h⁴) against O(h²); measured 5.2e-5 against 2.2e-2 at n = 4).
    #[test]
    fn curved_faces_are_integrated_as_the_cells_see_them() {
        let lame = Lame::from_young_poisson(1.0, 0.3);
        for degree in [1, 2] {
            let el = RefElement {
                shape: Shape::Tensor,
                dim: 2,
                degree,
            };
            let mesh = crate::mesh::curved::round_body(el, 4, 1.0, 1.0).unwrap();
            let faces = mesh.contact_faces(ContactRule::Facing(FACING)).unwrap();
            let chords: f64 = faces.iter().map(|f| f.measure).sum();
            let angles: Vec<f64> = mesh
                .tributary(&faces)
                .iter()
                .map(|v| mesh.nodes[v.0][0].atan2(1.0 - mesh.nodes[v.0][1]))
                .collect();
            let span = angles.iter().fold(f64::NEG_INFINITY, |m, &a| m.max(a))
                - angles.iter().fold(f64::INFINITY, |m, &a| m.min(a));
            let total: f64 = points(&mesh, lame, 0.0).iter().map(|p| p.weight).sum();
            println!("degree {degree}: Σw = {total:.8}, chords {chords:.8}, arc {span:.8}");
            if degree == 1 {
                assert!((total - chords).abs() < 1e-13);
            } else {
                assert!((total - span).abs() < 0.01 * (chords - span).abs());
            }
        }
    }
}
