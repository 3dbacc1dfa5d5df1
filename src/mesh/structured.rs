//! Structured meshes of a rectangle (2D: quadrilaterals, or triangles by splitting each
//! quadrilateral along its (0,0)–(1,1) diagonal) and of a box (3D: hexahedra, or the six Kuhn
//! tetrahedra of each hexahedron around its (0,0,0)–(1,1,1) diagonal), of degree 1 or 2.
//!
//! Nodes form the grid of `degree · n_k + 1` equispaced points per direction (every P2/Q2 node is
//! a grid point, including the quadrilateral centre used by the split triangles' diagonal
//! midpoint). Node `(i, j, k)` has index `i + N_x (j + N_y k)`. The contact boundary Γ_C is the
//! bottom face (last coordinate 0).

use crate::error::{Error, Result};
use crate::fem::reference::{RefElement, Shape};
use nalgebra::Matrix3;

/// A structured mesh of `[0, size_0] × … ` with `cells[k]` cells per direction.
#[derive(Debug, Clone)]
pub struct StructuredMesh {
    /// Reference element of every cell.
    pub element: RefElement,
    /// Cells per direction.
    pub cells: [usize; 3],
    /// Box size.
    pub size: [f64; 3],
    /// Node coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// Local-to-global node map of every cell (the reference element's node order).
    pub connectivity: Vec<Vec<usize>>,
}

impl StructuredMesh {
    /// The mesh of the box `size` (first `element.dim` entries used) with `cells` per direction.
    pub fn new(element: RefElement, cells: [usize; 3], size: [f64; 3]) -> Result<Self> {
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
                                let mut local: Vec<usize> =
                                    simplex.iter().map(|&v| at(v)).collect();
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
        Ok(Self {
            element,
            cells,
            size,
            nodes,
            connectivity,
        })
    }

    /// Spatial dimension.
    #[inline]
    pub fn dim(&self) -> usize {
        self.element.dim
    }

    /// Affine map of cell `c`: origin and Jacobian (columns: images of the reference axes; the
    /// unused block of a 2D mesh is the identity).
    pub fn jacobian(&self, c: usize) -> ([f64; 3], Matrix3<f64>) {
        let local = &self.connectivity[c];
        let x0 = self.nodes[local[0]];
        let mut j = Matrix3::identity();
        let p = self.element.degree;
        for k in 0..self.dim() {
            let a = match self.element.shape {
                Shape::Simplex => k + 1,
                Shape::Tensor => p * (p + 1).pow(k as u32),
            };
            let xa = self.nodes[local[a]];
            for r in 0..3 {
                j[(r, k)] = xa[r] - x0[r];
            }
        }
        (x0, j)
    }

    /// True when node `i` lies on Γ_C (last coordinate 0).
    pub fn on_contact_face(&self, i: usize) -> bool {
        self.nodes[i][self.dim() - 1] == 0.0
    }

    /// True when node `i` is a vertex of the mesh (grid indices multiples of the degree).
    pub fn is_vertex(&self, i: usize) -> bool {
        let p = self.element.degree;
        let mut rest = i;
        (0..self.dim()).all(|k| {
            let n = p * self.cells[k] + 1;
            let idx = rest % n;
            rest /= n;
            idx % p == 0
        })
    }

    /// The vertices of Γ_C with their tributary length (2D) or area (3D).
    pub fn contact_vertices(&self) -> Vec<(usize, f64)> {
        let d = self.dim();
        (0..self.nodes.len())
            .filter(|&i| self.on_contact_face(i) && self.is_vertex(i))
            .map(|i| {
                let area = (0..d - 1)
                    .map(|k| {
                        let h = self.size[k] / self.cells[k] as f64;
                        let x = self.nodes[i][k];
                        let boundary = x == 0.0 || (x - self.size[k]).abs() < 1e-12 * self.size[k];
                        if boundary {
                            0.5 * h
                        } else {
                            h
                        }
                    })
                    .product();
                (i, area)
            })
            .collect()
    }

    /// The cell volume `|det J|` times the reference measure.
    pub fn volume(&self) -> f64 {
        (0..self.dim()).map(|k| self.size[k]).product()
    }
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
        for (shape, dim) in [
            (Shape::Simplex, 2),
            (Shape::Simplex, 3),
            (Shape::Tensor, 2),
            (Shape::Tensor, 3),
        ] {
            for degree in [1, 2] {
                let e = RefElement { shape, dim, degree };
                let m = StructuredMesh::new(e, [3, 2, 2], [1.5, 1.0, 1.0]).unwrap();
                let vol: f64 = (0..m.connectivity.len())
                    .map(|c| {
                        let meas = match (shape, dim) {
                            (Shape::Tensor, _) => 1.0,
                            (_, 2) => 0.5,
                            _ => 1.0 / 6.0,
                        };
                        m.jacobian(c).1.determinant() * meas
                    })
                    .sum();
                assert!((vol - m.volume()).abs() < 1e-12, "{e:?}: {vol}");
                let cv = m.contact_vertices();
                let want = if dim == 2 { 4 } else { 4 * 3 };
                assert_eq!(cv.len(), want, "{e:?}");
                let area: f64 = cv.iter().map(|v| v.1).sum();
                // Γ_C has length 1.5 (2D) or area 1.5 × 1 (3D).
                assert!((area - 1.5).abs() < 1e-12);
                for c in 0..m.connectivity.len() {
                    assert!(m.jacobian(c).1.determinant() > 0.0);
                }
            }
        }
    }
}
