//! The small-sliding limit of the node-to-segment interface of two bodies
//! ([`Bodies::pairings`]). Each slave vertex s is paired with a master face F once, in the
//! reference configuration, and its row (the normal `n_m`, the shape functions `N_k(ξ_s)` at the
//! projection) is kept for the whole run. That is right while s stays over F: the gap
//! `g₀ − B_N U` is then the distance to F, and the force acts on F at the point facing s. A
//! vertex that slides off F is measured against F's extension and pushes the master at a point
//! outside F; past the master's edge it is held up in the air (a block sliding off the block
//! below it kept its force and its height).
//!
//! [`SmallSliding::check`] projects each slave vertex in contact (λ_r > 0), displaced, along
//! `n_m` on its face, displaced. The projection may fall outside the face by [`MAX_EXCESS`] (in
//! the face's reference coordinates, the allowance of the pairing itself) beyond where it fell
//! at t = 0 (0 inside the face; up to [`MAX_EXCESS`] for a vertex paired in the dead zone above a
//! convex master's kink); further, the vertex must lie over a face beside its own (one sharing a
//! vertex with it, within [`MAX_EXCESS`]), and less than a whole face beyond its own: on a face
//! beside its own the row's face is extended by less than one face, whose error is second order
//! in the slip (none on a flat master). Else the vertex has slid off its face, or off the
//! master, and the run stops, naming the vertex, the step and how far it slid. Rows out of
//! contact are not checked: a vertex off its face matters once it touches.

use super::bodies::{project, Bodies, MAX_EXCESS};
use crate::error::Result;

/// The rows of an interface, as the check needs them ([`SmallSliding::new`]).
#[derive(Debug, Clone)]
pub struct SmallSliding {
    rows: Vec<Row>,
    /// The slave's and the master's numbers (1-based, as messages name the bodies).
    bodies: (usize, usize),
}

/// A point of a body: its reference position and its global dofs (None where fixed).
#[derive(Debug, Clone)]
struct Point {
    x: [f64; 3],
    dofs: Vec<Option<usize>>,
}

impl Point {
    /// Its position displaced by `u`.
    fn at(&self, u: &[f64]) -> [f64; 3] {
        std::array::from_fn(|k| self.x[k] + self.displacement(u)[k])
    }

    /// Its displacement in `u` (none in an empty `u`: the reference configuration).
    fn displacement(&self, u: &[f64]) -> [f64; 3] {
        std::array::from_fn(|k| {
            self.dofs
                .get(k)
                .copied()
                .flatten()
                .and_then(|j| u.get(j))
                .map_or(0.0, |&v| v)
        })
    }
}

/// One row: the slave vertex (and its name), the master face's vertices with their shape
/// functions at the reference projection, the row's normal, how far outside the face the
/// projection may fall (`MAX_EXCESS` beyond where it fell at t = 0), and the master faces beside
/// it (their vertices and normals).
#[derive(Debug, Clone)]
struct Row {
    name: String,
    slave: Point,
    face: Vec<(Point, f64)>,
    normal: [f64; 3],
    limit: f64,
    beside: Vec<(Vec<Point>, [f64; 3])>,
}

impl SmallSliding {
    /// The check of the rows of [`Bodies::interface`]`(slave, master)`, in their order.
    pub fn new(bodies: &Bodies, slave: usize, master: usize) -> Result<Self> {
        let d = bodies.dim();
        let point = |b: usize, i: usize| {
            let part = &bodies.parts[b];
            Point {
                x: part.mesh.nodes[i],
                dofs: (0..d)
                    .map(|c| part.dofs.get(i, c).map(|j| bodies.offset(b) + j))
                    .collect(),
            }
        };
        let (s, m) = (&bodies.parts[slave], &bodies.parts[master]);
        // The master's Γ_C faces through each of its nodes.
        let mut through = vec![Vec::new(); m.mesh.nodes.len()];
        for (f, face) in m.contact_faces.iter().enumerate() {
            for &k in &face.vertices {
                through[k].push(f);
            }
        }
        let beside = |vertices: &[usize]| {
            let mut faces: Vec<usize> = vertices
                .iter()
                .flat_map(|&k| &through[k])
                .copied()
                .collect();
            faces.sort_unstable();
            faces.dedup();
            let mut own = vertices.to_vec();
            own.sort_unstable();
            faces
                .into_iter()
                .map(|f| &m.contact_faces[f])
                .filter(|f| {
                    let mut v = f.vertices.clone();
                    v.sort_unstable();
                    v != own
                })
                .map(|f| {
                    (
                        f.vertices.iter().map(|&k| point(master, k)).collect(),
                        f.normal,
                    )
                })
                .collect()
        };
        let rows = bodies
            .pairings(slave, master)?
            .into_iter()
            .map(|p| {
                let i = s.contact_vertices[p.slave].0;
                let vertices: Vec<usize> = p.master.iter().map(|&(k, _)| k).collect();
                let mut row = Row {
                    name: s.mesh.node_name(i),
                    slave: point(slave, i),
                    face: p
                        .master
                        .iter()
                        .map(|&(k, n)| (point(master, k), n))
                        .collect(),
                    normal: p.normal,
                    limit: MAX_EXCESS,
                    beside: beside(&vertices),
                };
                row.limit += row.excess(&[])?.unwrap_or(0.0);
                Ok(row)
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            rows,
            bodies: (slave + 1, master + 1),
        })
    }

    /// Why the state `u` with the contact forces `lambda` (of the interface's rows first) is
    /// past small sliding, if it is: the first row in contact whose slave vertex is off its
    /// face and not over a face beside it (the module's rule).
    pub fn check(&self, u: &[f64], lambda: &[f64]) -> Result<Option<String>> {
        for (row, _) in self.rows.iter().zip(lambda).filter(|(_, &l)| l > 0.0) {
            let excess = row.excess(u)?;
            if excess.is_some_and(|e| e <= row.limit) {
                continue;
            }
            let next = excess.is_some_and(|e| e <= row.limit - MAX_EXCESS + 1.0);
            if next && row.over_a_face_beside(u)? {
                continue;
            }
            let outside = excess.map_or("no point of it faces the vertex".to_string(), |e| {
                let over = if next {
                    "and over no face beside it"
                } else {
                    "beyond the faces beside it"
                };
                format!("its projection falls {e:.3} of the face outside it, {over}")
            });
            let (slave, master) = self.bodies;
            return Ok(Some(format!(
                "body {slave}'s Γ_C {} (at {:?}) has slid {:.4e} along body {master}'s contact \
                 face it was paired with at t = 0 and is off that face ({outside}): the interface pairs each vertex with a face once, in the \
                 reference configuration (small sliding), so its gap and its force would now be \
                 those of the face's extension; the run stops rather than hold the vertex on a \
                 face it has left",
                row.name,
                row.slave.x,
                row.slip(u)
            )));
        }
        Ok(None)
    }
}

impl Row {
    /// True when the slave vertex, in the state `u`, projects on a master face beside its own
    /// within [`MAX_EXCESS`].
    fn over_a_face_beside(&self, u: &[f64]) -> Result<bool> {
        let p = self.slave.at(u);
        for (face, normal) in &self.beside {
            let x: Vec<[f64; 3]> = face.iter().map(|q| q.at(u)).collect();
            if project(&x, *normal, p)?.is_some_and(|(e, _)| e <= MAX_EXCESS) {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// How far outside its face (reference coordinates of the face) the slave vertex projects
    /// in the state `u` (`&[]`: the reference configuration); None when no point of the face
    /// faces it.
    fn excess(&self, u: &[f64]) -> Result<Option<f64>> {
        let face: Vec<[f64; 3]> = self.face.iter().map(|(p, _)| p.at(u)).collect();
        Ok(project(&face, self.normal, self.slave.at(u))?.map(|(e, _)| e))
    }

    /// The length of the slave vertex's displacement relative to the master's point facing it
    /// at t = 0 (`u_s − Σ_k N_k u_k`), across the normal.
    fn slip(&self, u: &[f64]) -> f64 {
        let us = self.slave.displacement(u);
        let rel: [f64; 3] = std::array::from_fn(|k| {
            us[k]
                - self
                    .face
                    .iter()
                    .map(|(p, n)| n * p.displacement(u)[k])
                    .sum::<f64>()
        });
        let along = (0..3).map(|k| rel[k] * self.normal[k]).sum::<f64>();
        (0..3)
            .map(|k| (rel[k] - along * self.normal[k]).powi(2))
            .sum::<f64>()
            .sqrt()
    }
}
