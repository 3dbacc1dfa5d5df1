//! Meshes: every case's body is one unstructured [`Mesh`] of a single element family — the
//! uniform interval of the 1D bar ([`interval`]), structured boxes ([`structured`]), the curved
//! bodies of the Hertz cases ([`curved`]) and Gmsh files ([`gmsh`]).

pub mod curved;
pub mod gmsh;
pub mod interval;
pub mod structured;

use crate::element::reference::RefElement;
use crate::error::{Error, Result};
use std::collections::HashMap;

/// An unstructured mesh of one element family (any vertex numbering; cells with every local
/// orientation are accepted, inverted or degenerate cells are refused by [`Mesh::check`]).
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Where the mesh comes from (a file name or a generator), for messages.
    pub origin: String,
    /// Reference element of every cell.
    pub element: RefElement,
    /// Node coordinates (unused components 0).
    pub nodes: Vec<[f64; 3]>,
    /// Local-to-global node map of every cell (the reference element's node order).
    pub connectivity: Vec<Vec<usize>>,
    /// Characteristic mesh size at the contact (the `h` of convergence studies).
    pub h: f64,
    /// Boundary faces tagged as Γ_C by the mesh source (a Gmsh physical group), as sorted vertex
    /// lists; `None`: Γ_C is chosen by [`ContactRule::Facing`].
    pub contact_faces: Option<Vec<Vec<usize>>>,
}

/// A boundary face: its vertices, measure and unit outward normal.
#[derive(Debug, Clone, PartialEq)]
pub struct Face {
    /// Global vertices (cyclic order for quadrilaterals).
    pub vertices: Vec<usize>,
    /// Length (2D) or area (3D) of the straight face through the vertices.
    pub measure: f64,
    /// Unit outward normal.
    pub normal: [f64; 3],
    /// The cell it bounds.
    pub cell: usize,
    /// The cell's local node indices of `vertices`.
    pub local: Vec<usize>,
}

/// Which boundary faces form Γ_C.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactRule {
    /// Faces whose outward normal n has `n · e_d < −threshold` (they face the plane below;
    /// GetFEM's rule with threshold 0.01).
    Facing(f64),
    /// The faces tagged by the mesh source ([`Mesh::contact_faces`]).
    Tagged,
}

/// Default threshold of [`ContactRule::Facing`].
pub const FACING: f64 = 0.01;

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|k| a[k] - b[k])
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    a.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn centroid(x: impl Iterator<Item = [f64; 3]>) -> [f64; 3] {
    let (mut c, mut n) = ([0.0; 3], 0.0);
    for p in x {
        for k in 0..3 {
            c[k] += p[k];
        }
        n += 1.0;
    }
    c.map(|v| v / n)
}

impl Mesh {
    /// Spatial dimension.
    #[inline]
    pub fn dim(&self) -> usize {
        self.element.dim
    }

    /// Coordinates of the nodes of cell `c`.
    pub fn cell_nodes(&self, c: usize) -> Vec<[f64; 3]> {
        self.connectivity[c]
            .iter()
            .map(|&i| self.nodes[i])
            .collect()
    }

    /// `true` for every node that is a vertex of some cell.
    pub fn vertex_flags(&self) -> Vec<bool> {
        let mut flag = vec![false; self.nodes.len()];
        let local = self.element.vertices();
        for cell in &self.connectivity {
            for &a in &local {
                flag[cell[a]] = true;
            }
        }
        flag
    }

    /// Checks node indices, finite coordinates and the Jacobian of every cell: `det J` must keep
    /// one sign over the cell's quadrature points and vertices (any orientation is accepted) and
    /// `|det J|` must exceed 1e-10 of the cell's largest value times the mesh's scale (no
    /// degenerate cell).
    pub fn check(&self) -> Result<()> {
        let err = |m: String| Error::Mesh {
            origin: self.origin.clone(),
            message: m,
        };
        if let Some((i, _)) = self
            .nodes
            .iter()
            .enumerate()
            .find(|(_, x)| x.iter().any(|v| !v.is_finite()))
        {
            return Err(err(format!("node {i} has a non-finite coordinate")));
        }
        if self.connectivity.is_empty() {
            return Err(err("no cell".into()));
        }
        let n = self.element.n_nodes();
        let mut points = self.element.quadrature();
        points.extend(
            self.element
                .vertices()
                .iter()
                .map(|&a| (self.element.node(a), 0.0)),
        );
        for (c, cell) in self.connectivity.iter().enumerate() {
            if cell.len() != n || cell.iter().any(|&i| i >= self.nodes.len()) {
                return Err(err(format!(
                    "cell {c}: {} nodes or an index out of range (expected {n} nodes below {})",
                    cell.len(),
                    self.nodes.len()
                )));
            }
            let x = self.cell_nodes(c);
            let dets: Vec<f64> = points
                .iter()
                .map(|(xi, _)| {
                    crate::element::geometry::jacobian(&self.element, &x, *xi).determinant()
                })
                .collect();
            let big = dets.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
            let (lo, hi) = dets
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &d| {
                    (l.min(d), h.max(d))
                });
            if big.is_nan() || big <= 0.0 || (lo < 1e-10 * big && hi > -1e-10 * big) {
                return Err(err(format!(
                    "cell {c} (nodes {cell:?}) is inverted or degenerate: det J ranges over [{lo:.3e}, {hi:.3e}]"
                )));
            }
        }
        Ok(())
    }

    /// Every boundary face (a face of exactly one cell), in order of first appearance.
    pub fn boundary_faces(&self) -> Vec<Face> {
        let faces = self.element.faces();
        let verts = self.element.vertices();
        let mut count: HashMap<Vec<usize>, (usize, usize, usize)> = HashMap::new();
        let mut order = Vec::new();
        for (c, cell) in self.connectivity.iter().enumerate() {
            for (f, local) in faces.iter().enumerate() {
                let mut key: Vec<usize> = local.iter().map(|&a| cell[a]).collect();
                key.sort_unstable();
                let e = count.entry(key.clone()).or_insert_with(|| {
                    order.push(key);
                    (0, c, f)
                });
                e.0 += 1;
            }
        }
        order
            .into_iter()
            .filter_map(|key| {
                let (n, c, f) = count[&key];
                (n == 1).then(|| {
                    let cell = &self.connectivity[c];
                    let vertices: Vec<usize> = faces[f].iter().map(|&a| cell[a]).collect();
                    let inside = centroid(verts.iter().map(|&a| self.nodes[cell[a]]));
                    self.face(vertices, inside, (c, faces[f].clone()))
                })
            })
            .collect()
    }

    /// The face through `vertices` of `(cell, local vertices)`, its normal oriented away from the
    /// point `inside`.
    fn face(
        &self,
        vertices: Vec<usize>,
        inside: [f64; 3],
        (cell, local): (usize, Vec<usize>),
    ) -> Face {
        let x: Vec<[f64; 3]> = vertices.iter().map(|&i| self.nodes[i]).collect();
        let (measure, mut normal) = match (self.dim(), x.len()) {
            // An end point of a 1D body of unit cross-section.
            (1, _) => (1.0, [1.0, 0.0, 0.0]),
            (2, _) => {
                let e = sub(x[1], x[0]);
                (norm(e), [e[1], -e[0], 0.0])
            }
            (_, 3) => {
                let n = cross(sub(x[1], x[0]), sub(x[2], x[0]));
                (0.5 * norm(n), n)
            }
            _ => {
                let n = cross(sub(x[2], x[0]), sub(x[3], x[1]));
                (0.5 * norm(n), n)
            }
        };
        let len = norm(normal);
        let out = sub(centroid(x.iter().copied()), inside);
        let sign = if (0..3).map(|k| normal[k] * out[k]).sum::<f64>() < 0.0 {
            -1.0
        } else {
            1.0
        };
        for v in &mut normal {
            *v *= sign / len;
        }
        Face {
            vertices,
            measure,
            normal,
            cell,
            local,
        }
    }

    /// The faces of Γ_C under `rule`.
    pub fn contact_faces(&self, rule: ContactRule) -> Result<Vec<Face>> {
        let d = self.dim();
        let boundary = self.boundary_faces();
        let faces: Vec<Face> = match (rule, &self.contact_faces) {
            (ContactRule::Facing(t), _) => boundary
                .into_iter()
                .filter(|f| f.normal[d - 1] < -t)
                .collect(),
            (ContactRule::Tagged, Some(tagged)) => {
                let mut want: Vec<Vec<usize>> = tagged.clone();
                for w in &mut want {
                    w.sort_unstable();
                }
                want.sort_unstable();
                boundary
                    .into_iter()
                    .filter(|f| {
                        let mut k = f.vertices.clone();
                        k.sort_unstable();
                        want.binary_search(&k).is_ok()
                    })
                    .collect()
            }
            (ContactRule::Tagged, None) => {
                return Err(Error::Mesh {
                    origin: self.origin.clone(),
                    message: "no contact group in the mesh".into(),
                })
            }
        };
        if faces.is_empty() {
            return Err(Error::Mesh {
                origin: self.origin.clone(),
                message:
                    "Γ_C is empty: no boundary face is in the contact group or faces the plane"
                        .into(),
            });
        }
        Ok(faces)
    }

    /// The vertices of `faces` in increasing order, each with its tributary length (2D) or area
    /// (3D): `Σ |F| / #vertices(F)` over the faces F around it.
    pub fn tributary(&self, faces: &[Face]) -> Vec<(usize, f64)> {
        let mut area: HashMap<usize, f64> = HashMap::new();
        for f in faces {
            for &v in &f.vertices {
                *area.entry(v).or_insert(0.0) += f.measure / f.vertices.len() as f64;
            }
        }
        let mut out: Vec<(usize, f64)> = area.into_iter().collect();
        out.sort_unstable_by_key(|v| v.0);
        out
    }

    /// Volume (2D: area) by quadrature of `|det J|`.
    pub fn volume(&self) -> f64 {
        let q = self.element.quadrature();
        (0..self.connectivity.len())
            .map(|c| {
                let x = self.cell_nodes(c);
                q.iter()
                    .map(|(xi, w)| {
                        w * crate::element::geometry::jacobian(&self.element, &x, *xi)
                            .determinant()
                            .abs()
                    })
                    .sum::<f64>()
            })
            .sum()
    }
}
