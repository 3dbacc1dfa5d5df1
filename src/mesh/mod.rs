//! Meshes: every case's body is one unstructured [`Mesh`] of a single element family — the
//! uniform interval of the 1D bar ([`interval`]), structured boxes ([`structured`]), the curved
//! bodies of the Hertz cases ([`curved`]) and Gmsh files ([`gmsh`]).

pub mod curved;
pub mod gmsh;
pub mod interval;
pub mod structured;

use crate::element::geometry::jacobian_from;
use crate::element::reference::RefElement;
use crate::error::{Error, Result};
use rayon::prelude::*;
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
    /// The file's own numbers of the nodes and cells (Gmsh tags), for messages; `None` for a
    /// generated mesh, whose messages count from 0.
    pub tags: Option<Tags>,
}

/// The numbers a mesh file gives its nodes and cells, by index.
#[derive(Debug, Clone, PartialEq)]
pub struct Tags {
    /// Node tag of each node.
    pub nodes: Vec<u64>,
    /// Element tag of each cell.
    pub cells: Vec<u64>,
    /// Element tag of each tagged contact face, in the order of [`Mesh::contact_faces`].
    pub faces: Vec<u64>,
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

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| a[k] * b[k]).sum()
}

/// The right-hand normal of a face given as a vertex list `x` (not normalised): `e_x` at an end
/// point of a 1D body, `(t_y, −t_x)` of the edge `t = x₁ − x₀` in 2D, `(x₁ − x₀) × (x₂ − x₀)` of
/// a triangle, and the cross product of the diagonals `(x₂ − x₀) × (x₃ − x₁)` of a quadrilateral
/// in cyclic order; its length is the edge's length, or twice the face's area.
fn list_normal(dim: usize, x: &[[f64; 3]]) -> [f64; 3] {
    match (dim, x.len()) {
        (1, _) => [1.0, 0.0, 0.0],
        (2, _) => {
            let e = sub(x[1], x[0]);
            [e[1], -e[0], 0.0]
        }
        (_, 3) => cross(sub(x[1], x[0]), sub(x[2], x[0])),
        _ => cross(sub(x[2], x[0]), sub(x[3], x[1])),
    }
}

/// The orientation of a face's vertex list against its canonical one (±1): an edge `(a, b)` is
/// positive when `a < b`; a triangle or a quadrilateral in cyclic order when, started at its
/// smallest vertex, the next vertex is smaller than the previous one. Two lists of the same face
/// have the same sign iff they give the same right-hand normal.
fn list_orientation(v: &[usize]) -> f64 {
    let n = v.len();
    let k = (0..n).min_by_key(|&i| v[i]).unwrap_or(0);
    let positive = if n == 2 {
        k == 0
    } else {
        v[(k + 1) % n] < v[(k + n - 1) % n]
    };
    if positive {
        1.0
    } else {
        -1.0
    }
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

    /// The number of node `i` in messages: its tag in the mesh file, or its index.
    fn node_tag(&self, i: usize) -> u64 {
        self.tags
            .as_ref()
            .and_then(|t| t.nodes.get(i))
            .map_or(i as u64, |&n| n)
    }

    /// The extent `(lowest, highest)` of the nodes along x_{k+1} (`(∞, −∞)` without a node).
    pub fn extent(&self, k: usize) -> (f64, f64) {
        self.nodes
            .iter()
            .map(|x| x[k])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), z| {
                (lo.min(z), hi.max(z))
            })
    }

    /// `node 9` for the node of index `i`, by its tag in the mesh file when there is one.
    pub fn node_name(&self, i: usize) -> String {
        format!("node {}", self.node_tag(i))
    }

    /// The nodes `list` as the mesh file numbers them.
    fn node_list(&self, list: &[usize]) -> Vec<u64> {
        list.iter().map(|&i| self.node_tag(i)).collect()
    }

    /// `element 7 (nodes [3, 4])` for a tagged contact face of a mesh file (its own element
    /// tag), else `the face of nodes [3, 4] of <cell>`.
    pub fn face_name(&self, face: &Face) -> String {
        let key = |v: &[usize]| {
            let mut k = v.to_vec();
            k.sort_unstable();
            k
        };
        let nodes = self.node_list(&face.vertices);
        let tag = self
            .tags
            .as_ref()
            .zip(self.contact_faces.as_ref())
            .and_then(|(t, f)| {
                let k = key(&face.vertices);
                f.iter()
                    .position(|g| key(g) == k)
                    .and_then(|i| t.faces.get(i))
            });
        match tag {
            Some(tag) => format!("element {tag} (nodes {nodes:?})"),
            None => format!(
                "the face of nodes {nodes:?} of {}",
                self.cell_name(face.cell)
            ),
        }
    }

    /// `element 3` (a mesh file's tag) or `cell 0` (a generated mesh's index) for cell `c`.
    pub fn cell_name(&self, c: usize) -> String {
        match &self.tags {
            Some(t) => format!("element {}", t.cells.get(c).map_or(c as u64, |&n| n)),
            None => format!("cell {c}"),
        }
    }

    /// Checks node indices, finite coordinates and the Jacobian of every cell: `det J` must keep
    /// one sign over the cell's quadrature points and vertices (any orientation is accepted) and
    /// `|det J|` must exceed 1e-10 of the cell's largest value times the mesh's scale (no
    /// degenerate cell); then that no cell folds over its neighbours ([`Mesh::check_neighbours`]).
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
            return Err(err(format!(
                "{} has a non-finite coordinate",
                self.node_name(i)
            )));
        }
        if self.connectivity.is_empty() {
            return Err(err("no cell".into()));
        }
        let n = self.element.n_nodes();
        let ranges = self.det_ranges();
        let mut orientation = Vec::with_capacity(self.connectivity.len());
        for (c, range) in ranges.into_iter().enumerate() {
            let cell = &self.connectivity[c];
            let Some((lo, hi, big)) = range else {
                return Err(err(format!(
                    "{}: {} nodes or an index out of range (expected {n} nodes below {})",
                    self.cell_name(c),
                    cell.len(),
                    self.nodes.len()
                )));
            };
            if !big.is_finite() || !big.is_normal() && big > 0.0 {
                return Err(err(format!(
                    "{} (nodes {:?}): det J = {big:.3e} is out of floating-point range \
                     (coordinates too large or too small)",
                    self.cell_name(c),
                    self.node_list(cell)
                )));
            }
            if big.is_nan() || big <= 0.0 || (lo < 1e-10 * big && hi > -1e-10 * big) {
                return Err(err(format!(
                    "{} (nodes {:?}) is inverted or degenerate: det J ranges over [{lo:.3e}, \
                     {hi:.3e}]",
                    self.cell_name(c),
                    self.node_list(cell)
                )));
            }
            orientation.push(hi.signum());
        }
        self.check_neighbours(&orientation)?;
        self.check_coincident()
    }

    /// `(lowest, highest, largest |det J|)` of every cell over its quadrature points and
    /// vertices, in parallel (the basis tabulated once); None for a cell without the element's
    /// number of nodes or with a node index out of range.
    fn det_ranges(&self) -> Vec<Option<(f64, f64, f64)>> {
        let el = &self.element;
        let mut points = el.quadrature();
        points.extend(el.vertices().iter().map(|&a| (el.node(a), 0.0)));
        let tab = el.tabulate_at(points);
        let n = el.n_nodes();
        (self.connectivity.par_iter().enumerate())
            .map(|(c, cell)| {
                if cell.len() != n || cell.iter().any(|&i| i >= self.nodes.len()) {
                    return None;
                }
                let x = self.cell_nodes(c);
                let dets =
                    (tab.points.iter()).map(|p| jacobian_from(el, &x, &p.gradients).determinant());
                Some(dets.fold(
                    (f64::INFINITY, f64::NEG_INFINITY, 0.0_f64),
                    |(l, h, m), d| (l.min(d), h.max(d), m.max(d.abs())),
                ))
            })
            .collect()
    }

    /// Refuses two nodes of the cells closer than 1e-9 of the smallest distance between two
    /// vertices of a cell (an unmerged seam: the body would fall apart along it), by a grid
    /// hash of twice that spacing, O(nodes).
    fn check_coincident(&self) -> Result<()> {
        let verts = self.element.vertices();
        let mut smallest = f64::INFINITY;
        let mut used = vec![false; self.nodes.len()];
        for cell in &self.connectivity {
            for (k, &a) in verts.iter().enumerate() {
                for &b in &verts[k + 1..] {
                    smallest = smallest.min(norm(sub(self.nodes[cell[a]], self.nodes[cell[b]])));
                }
            }
            for &i in cell {
                used[i] = true;
            }
        }
        let tol = 1e-9 * smallest;
        if !(tol.is_normal() && tol.is_finite()) {
            return Ok(());
        }
        // Cells of side 2 tol: a node within tol of x lies in x's cell or, along each axis, in
        // the neighbour on the side of the nearer face (8 cells).
        let scaled = |x: [f64; 3]| x.map(|v| v / (2.0 * tol));
        let key = |x: [f64; 3]| scaled(x).map(|v| v.floor() as i64);
        let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for i in (0..self.nodes.len()).filter(|&i| used[i]) {
            grid.entry(key(self.nodes[i])).or_default().push(i);
        }
        for i in (0..self.nodes.len()).filter(|&i| used[i]) {
            let k = key(self.nodes[i]);
            let side = scaled(self.nodes[i]).map(|v| if v - v.floor() < 0.5 { -1 } else { 1 });
            for d in 0..8_i64 {
                let o: [i64; 3] = std::array::from_fn(|c| (d >> c & 1) * side[c]);
                let near: [i64; 3] = std::array::from_fn(|c| k[c].saturating_add(o[c]));
                for &j in grid.get(&near).into_iter().flatten() {
                    if j > i && norm(sub(self.nodes[i], self.nodes[j])) <= tol {
                        return Err(Error::Mesh {
                            origin: self.origin.clone(),
                            message: format!(
                                "{} and {} coincide at {:?} (closer than {tol:.3e}): \
                                 duplicate nodes, an unmerged seam that would split the \
                                 body (merge them, e.g. Gmsh's Coherence)",
                                self.node_name(i),
                                self.node_name(j),
                                self.nodes[i]
                            ),
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// Checks that no cell folds over its neighbours: every face bounds at most two cells, and
    /// two cells sharing a face lie on opposite sides of it.
    ///
    /// With `σ_K = sign det J_K` (`orientation`, one sign per cell by [`Mesh::check`]), the
    /// outward normal of cell K on its face f is `σ_K s_f N(list)`: N the right-hand normal of the
    /// face's vertex list in the cell's order, `s_f = ±1` whether N points out of the reference
    /// cell. Written against the face's canonical orientation, the outward normals of the two
    /// cells must have opposite signs. The test is combinatorial: exact on curved (P2/Q2) faces,
    /// one sort of the cells' faces, O(cells log cells) (hertz3d's n = 24 sphere, 55 296
    /// cells: 33–62 ms, against 0.8–1.3 s for the Jacobians above on a loaded machine, before
    /// they were computed from a tabulated basis on both cores).
    ///
    /// It is also the divergence theorem's check: `Σ_K |K| = (1/d) Σ_K ∮_{∂K} x·n_K`, and the
    /// contributions of an interior face cancel exactly when its two cells induce opposite
    /// normals, so the measured volume equals the volume enclosed by the boundary faces iff
    /// this test passes. Neither sees a mesh that overlaps itself without folding (two sheets
    /// stacked, a strip wound twice): that needs a geometric search.
    fn check_neighbours(&self, orientation: &[f64]) -> Result<()> {
        let faces = self.element.faces();
        let sides: Vec<f64> = faces
            .iter()
            .map(|f| {
                let x: Vec<[f64; 3]> = f.iter().map(|&a| self.element.node(a)).collect();
                let out = sub(centroid(x.iter().copied()), self.element.centre());
                dot(list_normal(self.dim(), &x), out).signum()
            })
            .collect();
        // (sorted vertices of the face (padded), cell, the cell's outward sign), sorted so that
        // the entries of one face are adjacent.
        let mut entries: Vec<([usize; 4], usize, f64)> =
            Vec::with_capacity(self.connectivity.len() * faces.len());
        for (c, cell) in self.connectivity.iter().enumerate() {
            for (local, side) in faces.iter().zip(&sides) {
                let mut list = face_list(cell, local);
                let out = orientation[c] * side * list_orientation(&list[..local.len()]);
                list.sort_unstable();
                entries.push((list, c, out));
            }
        }
        entries.sort_unstable_by_key(|e| (e.0, e.1));
        for face in entries.chunk_by(|a, b| a.0 == b.0) {
            let nodes: Vec<usize> = face[0]
                .0
                .iter()
                .copied()
                .filter(|&v| v != usize::MAX)
                .collect();
            let err = |m: String| Error::Mesh {
                origin: self.origin.clone(),
                message: m,
            };
            match face {
                [_] => {}
                [a, b] if a.2 != b.2 => {}
                [a, b] => {
                    return Err(err(format!(
                        "{} and {} lie on the same side of their common face (nodes {:?}): \
                         the mesh folds over itself there (a cell inverted against its \
                         neighbour, or overlapping it)",
                        self.cell_name(a.1),
                        self.cell_name(b.1),
                        self.node_list(&nodes)
                    )))
                }
                _ => {
                    let cells: Vec<String> = face.iter().map(|e| self.cell_name(e.1)).collect();
                    return Err(err(format!(
                        "the face with nodes {:?} bounds {}: cells overlap (a face bounds at \
                         most two)",
                        self.node_list(&nodes),
                        cells.join(", ")
                    )));
                }
            }
        }
        Ok(())
    }

    /// Every boundary face (a face of exactly one cell), in order of first appearance (cell,
    /// then local face): found as the keys that appear once among the cells' faces sorted by
    /// their vertices.
    pub fn boundary_faces(&self) -> Vec<Face> {
        let faces = self.element.faces();
        let verts = self.element.vertices();
        // (sorted vertices of the face (padded), cell, local face).
        let nf = faces.len();
        let mut entries: Vec<([usize; 4], usize, usize)> = (0..self.connectivity.len() * nf)
            .into_par_iter()
            .map(|k| {
                let (c, f) = (k / nf, k % nf);
                let mut key = face_list(&self.connectivity[c], &faces[f]);
                key.sort_unstable();
                (key, c, f)
            })
            .collect();
        entries.par_sort_unstable();
        let mut once: Vec<(usize, usize)> = (entries.chunk_by(|a, b| a.0 == b.0))
            .filter_map(|face| match face {
                [(_, c, f)] => Some((*c, *f)),
                _ => None,
            })
            .collect();
        once.sort_unstable();
        once.into_iter()
            .map(|(c, f)| {
                let cell = &self.connectivity[c];
                let vertices: Vec<usize> = faces[f].iter().map(|&a| cell[a]).collect();
                let inside = centroid(verts.iter().map(|&a| self.nodes[cell[a]]));
                self.face(vertices, inside, (c, faces[f].clone()))
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
        let mut normal = list_normal(self.dim(), &x);
        let len = norm(normal);
        let measure = match self.dim() {
            // An end point of a 1D body of unit cross-section.
            1 => 1.0,
            2 => len,
            _ => 0.5 * len,
        };
        let out = sub(centroid(x.iter().copied()), inside);
        let sign = if dot(normal, out) < 0.0 { -1.0 } else { 1.0 };
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
                message: match rule {
                    ContactRule::Facing(t) => format!(
                        "Γ_C is empty: no boundary face faces the plane (outward normal n_d < \
                         −{t}, contact.facing)"
                    ),
                    ContactRule::Tagged => {
                        "Γ_C is empty: no boundary face is in the contact group (contact.group)"
                            .into()
                    }
                },
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

    /// Volume (2D: area) by quadrature of `|det J|` (the basis tabulated once).
    pub fn volume(&self) -> f64 {
        let tab = self.element.tabulate();
        (0..self.connectivity.len())
            .map(|c| {
                let x = self.cell_nodes(c);
                (tab.points.iter())
                    .map(|p| {
                        p.weight
                            * jacobian_from(&self.element, &x, &p.gradients)
                                .determinant()
                                .abs()
                    })
                    .sum::<f64>()
            })
            .sum()
    }
}

/// The global vertices of the local face `local` of `cell`, in the face's order, padded with
/// `usize::MAX` to four.
fn face_list(cell: &[usize], local: &[usize]) -> [usize; 4] {
    let mut list = [usize::MAX; 4];
    for (v, &a) in list.iter_mut().zip(local) {
        *v = cell[a];
    }
    list
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::reference::Shape;

    /// The unit square split into four triangles around its centre node 4, Γ_C tagged nowhere.
    fn fan(centre: [f64; 3]) -> Mesh {
        Mesh {
            origin: "fan".into(),
            element: RefElement {
                shape: Shape::Simplex,
                dim: 2,
                degree: 1,
            },
            nodes: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                centre,
            ],
            connectivity: vec![vec![0, 1, 4], vec![1, 2, 4], vec![2, 3, 4], vec![3, 0, 4]],
            h: 1.0,
            contact_faces: None,
            tags: None,
        }
    }

    #[test]
    fn a_fan_whose_centre_leaves_the_square_is_refused_though_every_cell_is_valid() {
        let m = fan([0.5, 0.5, 0.0]);
        m.check().unwrap();
        assert!((m.volume() - 1.0).abs() < 1e-15);
        // Moved out through the right side: cell 1 flips and every cell alone is still valid;
        // the cells cover 1.5 times the square.
        let m = fan([1.5, 0.25, 0.0]);
        assert!((m.volume() - 1.5).abs() < 1e-12, "{}", m.volume());
        let e = m.check().unwrap_err().to_string();
        assert!(e.contains("fan") && e.contains("same side"), "{e}");
        assert!(
            e.contains("cell 0 and cell 1") || e.contains("cell 1 and cell 2"),
            "{e}"
        );
    }

    #[test]
    fn every_family_folded_over_a_face_is_refused_and_any_local_numbering_is_accepted() {
        for e in RefElement::every() {
            let mut m = structured::box_mesh(e, [2, 1, 1], [2.0, 1.0, 1.0]).unwrap();
            // Number every other cell through a reflection R of the reference cell (ξ₀ → 1 − ξ₀,
            // or ξ₀ ↔ ξ₁ for a simplex), which reverses its orientation: the same valid mesh.
            let reflect = |x: [f64; 3]| match e.shape {
                Shape::Tensor => [1.0 - x[0], x[1], x[2]],
                Shape::Simplex => [x[1], x[0], x[2]],
            };
            let perm: Vec<usize> = (0..e.n_nodes())
                .map(|a| {
                    let r = reflect(e.node(a));
                    (0..e.n_nodes()).find(|&b| e.node(b) == r).unwrap()
                })
                .collect();
            for cell in m.connectivity.iter_mut().step_by(2) {
                *cell = perm.iter().map(|&p| cell[p]).collect();
            }
            m.check()
                .unwrap_or_else(|err| panic!("{e:?} renumbered: {err}"));
            let mut m = structured::box_mesh(e, [2, 1, 1], [2.0, 1.0, 1.0]).unwrap();
            m.check().unwrap();
            // Fold the right half back over the left: x → 2 − x for x > 1.
            for x in &mut m.nodes {
                if x[0] > 1.0 {
                    x[0] = 2.0 - x[0];
                }
            }
            let err = m.check().unwrap_err().to_string();
            assert!(
                err.contains("same side of their common face"),
                "{e:?}: {err}"
            );
        }
    }

    #[test]
    fn a_face_of_three_cells_is_refused() {
        // A fifth triangle on the interior edge 1–4 (a flap through cell 1).
        let mut m = fan([0.5, 0.5, 0.0]);
        m.nodes.push([0.9, 0.3, 0.0]);
        m.connectivity.push(vec![1, 5, 4]);
        let e = m.check().unwrap_err().to_string();
        assert!(
            e.contains("[1, 4] bounds cell 0, cell 1, cell 4") && e.contains("at most two"),
            "{e}"
        );
    }

    #[test]
    fn coordinates_out_of_floating_point_range_are_refused_naming_the_cell() {
        for (scale, needle) in [
            (1e200, "out of floating-point range"),
            (1e-300, "degenerate"),
        ] {
            let mut m = fan([0.5, 0.5, 0.0]);
            for x in &mut m.nodes {
                *x = x.map(|v| v * scale);
            }
            let e = m.check().unwrap_err().to_string();
            assert!(
                e.contains("fan") && e.contains("cell 0") && e.contains(needle),
                "{e}"
            );
        }
    }

    #[test]
    fn coincident_nodes_of_the_cells_are_refused_naming_both() {
        // Cell 3 uses a copy (node 5) of corner 3: the fan is cut along the edge 3–4.
        let mut m = fan([0.5, 0.5, 0.0]);
        m.nodes.push([0.0, 1.0, 0.0]);
        m.connectivity[3] = vec![5, 0, 4];
        let e = m.check().unwrap_err().to_string();
        assert!(e.contains("node 3 and node 5 coincide"), "{e}");
    }

    /// The grid of the coincident-node search, cells of side 2 tol, looks in the 8 cells a
    /// node within tol can lie in: pairs 0.9 tol apart along an axis or a diagonal are found
    /// wherever they fall in the grid (shifts of the mesh, negative coordinates), and pairs
    /// 1.1 tol apart are not coincident (the fan is then cut along 3–4, which is valid).
    #[test]
    fn coincident_nodes_are_found_wherever_they_fall_in_the_grid() {
        // The fan's smallest vertex distance is its centre's √2/2.
        let tol = 1e-9 * 0.5_f64.sqrt();
        for shift in [-1.3, -0.7137, 0.0, 0.25, 3.1, 1e3 + 0.123] {
            for dir in [
                [1.0, 0.0],
                [-1.0, 0.0],
                [0.0, 1.0],
                [0.6, -0.8],
                [-0.6, -0.8],
            ] {
                for (factor, coincide) in [(0.9, true), (1.1, false)] {
                    let mut m = fan([0.5, 0.5, 0.0]);
                    let at = [dir[0] * factor * tol, dir[1] * factor * tol];
                    m.nodes.push([at[0], 1.0 + at[1], 0.0]);
                    m.connectivity[3] = vec![5, 0, 4];
                    for x in &mut m.nodes {
                        *x = [x[0] + shift, x[1] - shift, 0.0];
                    }
                    let found = m.check().is_err_and(|e| e.to_string().contains("coincide"));
                    assert_eq!(found, coincide, "shift {shift}, {dir:?} × {factor} tol");
                }
            }
        }
    }

    /// A cell with a node index out of range is named only when no earlier cell is invalid:
    /// the checks report the first bad cell whatever its fault.
    #[test]
    fn the_first_bad_cell_is_named_whatever_its_fault() {
        let mut m = fan([0.5, 0.5, 0.0]);
        m.connectivity[1] = vec![1, 1, 4];
        m.connectivity[3] = vec![3, 0, 9];
        let e = m.check().unwrap_err().to_string();
        assert!(e.contains("cell 1") && e.contains("degenerate"), "{e}");
        m.connectivity[1] = vec![1, 2, 4];
        let e = m.check().unwrap_err().to_string();
        assert!(e.contains("cell 3") && e.contains("out of range"), "{e}");
    }
}
