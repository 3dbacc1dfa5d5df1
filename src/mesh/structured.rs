//! Structured meshes of a rectangle (2D: quadrilaterals, or triangles by splitting each
//! quadrilateral along its (0,0)–(1,1) diagonal) and of a box (3D: hexahedra, or the six Kuhn
//! tetrahedra of each hexahedron around its (0,0,0)–(1,1,1) diagonal), of degree 1 or 2.
//!
//! Nodes form the grid of `degree · n_k + 1` equispaced points per direction (every P2/Q2 node is
//! a grid point, including the quadrilateral centre used by the split triangles' diagonal
//! midpoint). Node `(i, j, k)` has index `i + N_x (j + N_y k)`. The contact boundary Γ_C is the
//! bottom face (last coordinate 0): the boundary faces facing the plane below.

use super::Mesh;
use crate::element::reference::{RefElement, Shape};
use crate::error::{Error, Result};

/// The mesh of the box `size` (first `element.dim` entries used) with `cells` per direction;
/// `h = size_0 / cells_0`.
pub fn box_mesh(element: RefElement, cells: [usize; 3], size: [f64; 3]) -> Result<Mesh> {
    let dim = element.dim;
    if let Some(c) = cells[..dim].iter().find(|&&c| c == 0) {
        return Err(Error::invalid("mesh.elements", c, "must be ≥ 1"));
    }
    let p = element.degree;
    let n = |k: usize| if k < dim { p * cells[k] + 1 } else { 1 };
    let (nx, ny, nz) = (n(0), n(1), n(2));
    let mut nodes = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let c = |idx: usize, kk: usize| {
                    if kk < dim {
                        size[kk] * idx as f64 / (p * cells[kk]) as f64
                    } else {
                        0.0
                    }
                };
                nodes.push([c(i, 0), c(j, 1), c(k, 2)]);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| i + nx * (j + ny * k);
    let mut connectivity = Vec::new();
    let cz = if dim == 3 { cells[2] } else { 1 };
    for c2 in 0..cz {
        for c1 in 0..cells[1] {
            for c0 in 0..cells[0] {
                let origin = [p * c0, p * c1, if dim == 3 { p * c2 } else { 0 }];
                match element.shape {
                    Shape::Tensor => {
                        let local = (0..element.n_nodes())
                            .map(|a| {
                                let x = element.node(a);
                                let off = |kk: usize| (x[kk] * p as f64).round() as usize;
                                id(origin[0] + off(0), origin[1] + off(1), origin[2] + off(2))
                            })
                            .collect();
                        connectivity.push(local);
                    }
                    Shape::Simplex => {
                        for simplex in simplices(dim) {
                            // Vertex corners in doubled cell units, so midpoints are integers.
                            let at = |c: [usize; 3]| {
                                id(
                                    origin[0] + c[0] * p / 2,
                                    origin[1] + c[1] * p / 2,
                                    origin[2] + c[2] * p / 2,
                                )
                            };
                            let mut local: Vec<usize> = simplex.iter().map(|&v| at(v)).collect();
                            if p == 2 {
                                for &(s, t) in element.edges() {
                                    let m = std::array::from_fn(|k| {
                                        (simplex[s][k] + simplex[t][k]) / 2
                                    });
                                    local.push(at(m));
                                }
                            }
                            connectivity.push(local);
                        }
                    }
                }
            }
        }
    }
    Ok(Mesh {
        origin: format!(
            "structured box of {:?} cells (mesh.elements)",
            &cells[..dim]
        ),
        element,
        nodes,
        connectivity,
        h: size[0] / cells[0] as f64,
        contact_faces: None,
        tags: None,
    })
}

/// Positively oriented simplices of the unit cell (corners in doubled units: 0 or 2): two
/// triangles around the (0,0)–(1,1) diagonal, or the six Kuhn tetrahedra around (0,0,0)–(1,1,1).
fn simplices(dim: usize) -> Vec<Vec<[usize; 3]>> {
    if dim == 2 {
        return vec![
            vec![[0, 0, 0], [2, 0, 0], [2, 2, 0]],
            vec![[0, 0, 0], [2, 2, 0], [0, 2, 0]],
        ];
    }
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    perms
        .iter()
        .map(|order| {
            let mut corner = [0; 3];
            let mut verts = vec![corner];
            for &k in order {
                corner[k] = 2;
                verts.push(corner);
            }
            // Odd permutations give negatively oriented tetrahedra: swap two vertices.
            let e = |v: usize| -> [f64; 3] {
                std::array::from_fn(|k| verts[v][k] as f64 - verts[0][k] as f64)
            };
            let (a, b, c) = (e(1), e(2), e(3));
            let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]);
            if det < 0.0 {
                verts.swap(2, 3);
            }
            verts
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_cover_the_box_and_gamma_c_has_the_right_vertices() {
        for e in RefElement::every() {
            let dim = e.dim;
            let m = box_mesh(e, [3, 2, 2], [1.5, 1.0, 1.0]).unwrap();
            m.check().unwrap();
            // Area 1.5 × 1 (2D), volume 1.5 × 1 × 1 (3D).
            assert!((m.volume() - 1.5).abs() < 1e-12, "{e:?}: {}", m.volume());
            let faces = m
                .contact_faces(super::super::ContactRule::Facing(0.01))
                .unwrap();
            let cv = m.tributary(&faces);
            let want = if dim == 2 { 4 } else { 4 * 3 };
            assert_eq!(cv.len(), want, "{e:?}");
            assert!(cv.iter().all(|&(i, _)| m.nodes[i][dim - 1] == 0.0));
            let area: f64 = cv.iter().map(|v| v.1).sum();
            // Γ_C has length 1.5 (2D) or area 1.5 × 1 (3D).
            assert!((area - 1.5).abs() < 1e-12);
            // The whole boundary: perimeter 5 (2D) or area 2(1.5 + 1.5 + 1) = 8 (3D).
            let total: f64 = m.boundary_faces().iter().map(|f| f.measure).sum();
            assert!((total - if dim == 2 { 5.0 } else { 8.0 }).abs() < 1e-12);
        }
    }
}
