//! The small-sliding limit of the node-to-segment interface of two bodies
//! ([`Bodies::pairings`]). Each slave vertex s is paired with a master face F once, in the
//! reference configuration, and its row (the normal `n_m`, the shape functions `N_k(ξ_s)` at the
//! projection) is kept for the whole run: its gap is measured against the plane of F through
//! the master's point that faced s at t = 0, and its force acts there. Linearised as the
//! elasticity is, that holds while s stays over the master's Γ_C (on a flat master exactly,
//! across any number of faces; on a curved one to second order in the slip). A vertex that
//! slides past the master's Γ_C is still held by that plane: a block sliding off the block
//! below it kept its force and its height, in the air.
//!
//! [`SmallSliding::check`] projects each slave vertex in contact (λ_r > 0), displaced, along
//! `n_m` on its face, displaced. The projection may fall outside the face by [`MAX_EXCESS`] (in
//! the face's reference coordinates, the allowance of the pairing itself) beyond where it fell
//! at t = 0; further, the vertex must lie over some face of the master's Γ_C (within
//! [`MAX_EXCESS`] along that face's normal, both displaced), searched from the last one found
//! outwards through faces sharing a vertex. A vertex over no face stops the run, naming the
//! vertex, the step and how far it slid. Rows out of contact are not checked: a vertex off the
//! master matters once it touches.

use super::bodies::{project, Bodies, MAX_EXCESS};
use crate::error::{short, Result};
use std::collections::VecDeque;

/// The rows of an interface and the master's Γ_C faces, as the check needs them
/// ([`SmallSliding::new`]).
#[derive(Debug, Clone)]
pub struct SmallSliding {
    rows: Vec<Row>,
    faces: Vec<Face>,
    /// The slave's and the master's numbers (1-based, as messages name the bodies).
    bodies: (usize, usize),
    /// Space dimension (for messages).
    dim: usize,
}

/// A point of a body: its reference position and its global dofs (None where fixed).
#[derive(Debug, Clone)]
struct Point {
    x: [f64; 3],
    dofs: Vec<Option<usize>>,
}

impl Point {
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

    /// Its position displaced by `u`.
    fn at(&self, u: &[f64]) -> [f64; 3] {
        let d = self.displacement(u);
        std::array::from_fn(|k| self.x[k] + d[k])
    }
}

/// A face of the master's Γ_C: its vertices, its unit normal, the faces sharing a vertex with
/// it.
#[derive(Debug, Clone)]
struct Face {
    points: Vec<Point>,
    normal: [f64; 3],
    beside: Vec<usize>,
}

impl Face {
    /// How far outside the face, displaced by `u` (reference coordinates of the face), `p`
    /// projects along `normal`; None when no point of the face faces it.
    fn excess(&self, u: &[f64], normal: [f64; 3], p: [f64; 3]) -> Result<Option<f64>> {
        let x: Vec<[f64; 3]> = self.points.iter().map(|q| q.at(u)).collect();
        Ok(project(&x, normal, p)?.map(|(e, _)| e))
    }
}

/// One row: the slave vertex (and its name), its face (an index of the master's faces) with
/// the shape functions at the reference projection, the row's normal, how far outside its face
/// the projection may fall (`MAX_EXCESS` beyond where it fell at t = 0), and the face it was
/// last found over.
#[derive(Debug, Clone)]
struct Row {
    name: String,
    slave: Point,
    face: usize,
    shape: Vec<f64>,
    normal: [f64; 3],
    limit: f64,
    last: usize,
}

impl SmallSliding {
    /// The check of the rows of [`Bodies::interface`]`(slave, master)`, in their order.
    pub fn new(bodies: &Bodies, slave: usize, master: usize) -> Result<Self> {
        let d = bodies.dim();
        let point = |b: usize, i: usize| Point {
            x: bodies.parts[b].mesh.nodes[i],
            dofs: (0..d).map(|c| bodies.dof(b, i, c)).collect(),
        };
        let (s, m) = (&bodies.parts[slave], &bodies.parts[master]);
        // The master's Γ_C faces through each of its nodes.
        let mut through = vec![Vec::new(); m.mesh.nodes.len()];
        for (f, face) in m.contact_faces.iter().enumerate() {
            for &k in &face.vertices {
                through[k].push(f);
            }
        }
        let faces: Vec<Face> = m
            .contact_faces
            .iter()
            .enumerate()
            .map(|(f, face)| {
                let mut beside: Vec<usize> = face
                    .vertices
                    .iter()
                    .flat_map(|&k| &through[k])
                    .copied()
                    .collect();
                beside.sort_unstable();
                beside.dedup();
                beside.retain(|&g| g != f);
                Face {
                    points: face.vertices.iter().map(|&k| point(master, k)).collect(),
                    normal: face.normal,
                    beside,
                }
            })
            .collect();
        // A row's face: the one whose vertices are its master vertices.
        let sorted = |mut v: Vec<usize>| {
            v.sort_unstable();
            v
        };
        let face_of = |vertices: Vec<usize>| {
            let key = sorted(vertices);
            m.contact_faces
                .iter()
                .position(|f| sorted(f.vertices.clone()) == key)
        };
        let mut rows = Vec::new();
        for p in bodies.pairings(slave, master)? {
            let i = s.contact_vertices[p.slave].0;
            let Some(face) = face_of(p.master.iter().map(|&(k, _)| k).collect()) else {
                continue;
            };
            let slave = point(slave, i);
            let excess = faces[face].excess(&[], p.normal, slave.x)?;
            rows.push(Row {
                name: s.mesh.node_name(i),
                slave,
                face,
                shape: p.master.iter().map(|&(_, n)| n).collect(),
                normal: p.normal,
                limit: MAX_EXCESS + excess.unwrap_or(0.0),
                last: face,
            });
        }
        Ok(Self {
            rows,
            faces,
            bodies: (slave + 1, master + 1),
            dim: d,
        })
    }

    /// Why the state `u` with the contact forces `lambda` (of the interface's rows first) is
    /// past small sliding, if it is: the first row in contact whose slave vertex lies over no
    /// face of the master's Γ_C (the module's rule). Remembers the face each vertex was found
    /// over, where the next search starts.
    pub fn check(&mut self, u: &[f64], lambda: &[f64]) -> Result<Option<String>> {
        for (row, _) in self.rows.iter_mut().zip(lambda).filter(|(_, &l)| l > 0.0) {
            let p = row.slave.at(u);
            let own = self.faces[row.face].excess(u, row.normal, p)?;
            if own.is_some_and(|e| e <= row.limit) {
                continue;
            }
            if let Some(f) = over(&self.faces, row.last, u, p)? {
                row.last = f;
                continue;
            }
            let (slave, master) = self.bodies;
            let at: Vec<String> = row.slave.x[..self.dim].iter().map(|&x| short(x)).collect();
            return Ok(Some(format!(
                "body {slave}'s Γ_C {} (at [{}]) has slid {:.3e} relative to body {master} and lies \
                 over no face of body {master}'s Γ_C (its projection falls outside each by more \
                 than {MAX_EXCESS} of the face): the interface pairs each vertex with a face \
                 once, in the reference configuration (small sliding), and would hold it on \
                 the plane of a face it has left; the run stops there",
                row.name,
                at.join(", "),
                row.slip(&self.faces, u)
            )));
        }
        Ok(None)
    }
}

/// The first face of `faces` over which `p` lies in the state `u` (projected along the face's
/// normal within [`MAX_EXCESS`]), searched breadth-first from `start` through the faces beside
/// each, then among the faces that search did not reach (another part of Γ_C).
fn over(faces: &[Face], start: usize, u: &[f64], p: [f64; 3]) -> Result<Option<usize>> {
    let mut seen = vec![false; faces.len()];
    let mut queue = VecDeque::from([start]);
    seen[start] = true;
    let mut next_unseen = 0;
    loop {
        let f = match queue.pop_front() {
            Some(f) => f,
            None => match (next_unseen..faces.len()).find(|&g| !seen[g]) {
                Some(g) => {
                    next_unseen = g + 1;
                    seen[g] = true;
                    g
                }
                None => return Ok(None),
            },
        };
        let face = &faces[f];
        if face
            .excess(u, face.normal, p)?
            .is_some_and(|e| e <= MAX_EXCESS)
        {
            return Ok(Some(f));
        }
        for &g in &face.beside {
            if !seen[g] {
                seen[g] = true;
                queue.push_back(g);
            }
        }
    }
}

impl Row {
    /// The length of the tangential part (orthogonal to the row's normal) of the slave
    /// vertex's displacement relative to the master's point that faced it at t = 0
    /// (`u_s − Σ_k N_k u_k`).
    fn slip(&self, faces: &[Face], u: &[f64]) -> f64 {
        let us = self.slave.displacement(u);
        let mut rel = us;
        for (p, n) in faces[self.face].points.iter().zip(&self.shape) {
            let du = p.displacement(u);
            for k in 0..3 {
                rel[k] -= n * du[k];
            }
        }
        let along = (0..3).map(|k| rel[k] * self.normal[k]).sum::<f64>();
        (0..3)
            .map(|k| (rel[k] - along * self.normal[k]).powi(2))
            .sum::<f64>()
            .sqrt()
    }
}
