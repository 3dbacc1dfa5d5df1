//! Several elastic bodies as one semi-discrete problem (DESIGN.md §1, §8;
//! `notes/papers/two_body_contact.md`): the dofs of body b follow those of the bodies before it,
//! `U = (U₁, U₂, …)`, the element data and the stiffness are block diagonal,
//! `M̃ = diag(M̃₁, M̃₂)`, `K = diag(K₁, K₂)`, and the contact rows pair the two bodies' Γ_C
//! node-to-segment (small deformations: pairing, projection and normals in the reference
//! configuration). Slave vertex s, master face F with vertices k, shape functions `N_k(ξ_s)` at
//! the orthogonal projection ξ_s of X_s on F (on a warped quadrilateral of a 3D hexahedral mesh:
//! the point of the bilinear face whose offset to X_s is along F's averaged normal), unit outward
//! master normal `n_m` (towards the slave; the face's averaged normal):
//!
//! `g = g₀ − B_N U ≥ 0`, `g₀ = (X_s − X_m(ξ_s))·n_m`, row of `B_N`: `−n_mᵀ` on s, `+N_k n_mᵀ` on k,
//!
//! with the conventions of [`crate::problem`]: the force `−B_Nᵀλ` is `+λ n_m` on the slave and
//! `−λ N_k n_m` on the master. In 1D the faces are the end points: node to node, `N = 1`.
//!
//! **Momentum.** `Σ_k N_k = 1`, so the contact forces of a row are equal and opposite:
//! `1_dᵀ B_Nᵀ = 0` for every unit translation `1_d`; with `K 1_d = 0` (free bodies) and any
//! symmetric `M̃`, `d/dt (M̃ 1_d)ᵀ V = 0`: the momentum `(M̃1_d)ᵀV` of the space's own mass is an
//! exact invariant ([`Bodies::translation`]).
//!
//! **What the mass cures need of a coupled row.** Mass redistribution wants every constraint
//! direction massless, `b_cᵀ M̃ b_c = 0` (`N_iᵀ M̃ N_j = 0`). A row touches both bodies and `M̃` is
//! block diagonal and PSD, so `b_cᵀ M̃ b_c = b_{c,1}ᵀ M̃₁ b_{c,1} + b_{c,2}ᵀ M̃₂ b_{c,2}` is a sum of two
//! non-negative terms: it vanishes only when **both** do, i.e. the slave's normal dof and every
//! master dof of the row are massless. Hence the merged [`MassModel`] lists the Γ_C normal dofs of
//! both bodies as contact dofs, and every space redistributes (or eliminates) within each body,
//! never coupling them. Massless on the slave side alone is enough for well-posedness but leaves
//! the row with mass (the note measures 10× the energy error and chatter while the bars graze).
//! The singular dynamic method keeps mass on the contact dofs; its inf-sup condition is checked
//! by rank on the coupled rows, `rank [B; b_cᵀ] = rank B + 1`
//! ([`crate::space::singular_dynamic::inf_sup_holds_rows`]).
//!
//! The contact dofs are the last components (as for the plane, the bodies meet along e_d: the
//! axis of the bars in 1D). A slave vertex whose projection falls on no master face gets no row.
//!
//! **Friction** ([`Bodies::friction`]): beside each row, the d − 1 rows of `B_T` along the
//! tangents t_k of `n_m`, `+t_kᵀ` on s and `−N_k t_kᵀ` on k: `B_T ΔU` is the slave's slip
//! relative to the master's point, and the force `+B_Tᵀ r_T` is again equal and opposite
//! (`Σ_k N_k = 1`), so the momentum stays an invariant with friction. Small sliding: the
//! pairing, normals and tangents stay those of the reference configuration.

use crate::error::{Error, Result};
use crate::fem::discretisation::{Discretisation, Initial, PENETRATION_TOLERANCE};
use crate::fem::mass_model::{ElementMass, ElementMixed, MassModel, VelocitySpace};
use crate::linalg::{SpMat, TripletBuilder};
use crate::problem::{Contact, ContactFace, Friction, Inertia, NoQuadrature, Probe, Problem};

/// Distance, in master mesh sizes h, within which two faces' projected points are one point
/// (an edge or vertex where their normals are averaged).
const PROJECTION_TOLERANCE: f64 = 1e-9;
/// How far (in reference coordinates of the face) a projection may fall outside every master
/// face and still be paired, clamped onto the nearest: above a convex master's kink the
/// projections along the two faces' normals miss both by about `g₀ / R` (R the radius of
/// curvature); a slave vertex further beyond the master's Γ_C gets no row.
pub(super) const MAX_EXCESS: f64 = 0.25;
/// Newton iterations of a projection on a warped quadrilateral (converged to 1e-14 in a few).
const NEWTON_ITERATIONS: usize = 30;

/// The bodies of a multi-body case and their dof offsets.
#[derive(Debug, Clone)]
pub struct Bodies {
    /// The bodies' discretisations (same dimension).
    pub parts: Vec<Discretisation>,
    offsets: Vec<usize>,
}

/// One node-to-segment row: the slave vertex's dof rows and the master face's.
#[derive(Debug, Clone, PartialEq)]
pub struct Pairing {
    /// Index of the slave vertex in the slave's Γ_C vertices.
    pub slave: usize,
    /// Row `(dof, value)` of `B_N` (global dofs).
    pub row: Vec<(usize, f64)>,
    /// The rows of `B_T` along the tangents `t_k` of the master face ([`tangents`]): `+t_kᵀ` on
    /// s, `−N_k t_kᵀ` on k, so that `B_T U` is the slave's tangential displacement relative to
    /// the master's point (the slip) and the force `+B_Tᵀ r_T` is equal and opposite.
    pub tangential: Vec<Vec<(usize, f64)>>,
    /// g₀.
    pub g0: f64,
    /// The master face's vertices (node indices of the master) and their shape functions N_k
    /// at the projection.
    pub master: Vec<(usize, f64)>,
    /// The unit normal `n_m` of the row (the mean of the faces' meeting at the projection).
    pub normal: [f64; 3],
}

/// One body's part of a run's state, for field output ([`Bodies::split`]).
#[derive(Debug, Clone)]
pub struct BodyFields {
    /// Its block of U.
    pub u: Vec<f64>,
    /// Its block of V (in V_h, or in H_h for the singular dynamic method).
    pub v: Vec<f64>,
    /// The contact force on each of its Γ_C vertices ([`Discretisation::contact_vertices`]).
    pub lambda: Vec<f64>,
}

impl Bodies {
    /// The bodies, numbered in order; refuses bodies of different dimensions.
    pub fn new(parts: Vec<Discretisation>) -> Result<Self> {
        let Some(d) = parts.first().map(Discretisation::dim) else {
            return Err(Error::Internal("no body".into()));
        };
        if let Some(p) = parts.iter().find(|p| p.dim() != d) {
            return Err(Error::Mesh {
                origin: p.mesh.origin.clone(),
                message: format!(
                    "a body of dimension {} among bodies of dimension {d}",
                    p.dim()
                ),
            });
        }
        let offsets = parts
            .iter()
            .scan(0, |n, p| {
                let o = *n;
                *n += p.n_dofs();
                Some(o)
            })
            .collect();
        Ok(Self { parts, offsets })
    }

    /// Number of displacement dofs of all bodies.
    pub fn n_dofs(&self) -> usize {
        self.parts.iter().map(Discretisation::n_dofs).sum()
    }

    /// Spatial dimension d.
    pub fn dim(&self) -> usize {
        self.parts[0].dim()
    }

    /// The larger of the bodies' mesh sizes at the contact.
    pub fn h(&self) -> f64 {
        self.parts.iter().map(|p| p.mesh.h).fold(0.0, f64::max)
    }

    /// The cell shape and degree of the slave's mesh (the records' key columns).
    pub fn element(&self) -> (&'static str, usize) {
        let e = self.parts[0].mesh.element;
        (e.cells(), e.degree)
    }

    /// The first global dof of body b.
    pub fn offset(&self, b: usize) -> usize {
        self.offsets[b]
    }

    /// Body b's vector `local` copied into its block of the global vector `out`.
    fn place(&self, b: usize, local: &[f64], out: &mut [f64]) {
        let o = self.offsets[b];
        out[o..o + local.len()].copy_from_slice(local);
    }

    /// The unit translation `1_d` along the last coordinate (the impact line): the momentum
    /// along it is `(M̃ 1_d)ᵀ V`.
    pub fn translation(&self) -> Vec<f64> {
        let d = self.dim();
        let mut t = vec![0.0; self.n_dofs()];
        for (b, p) in self.parts.iter().enumerate() {
            let local = p.interpolate(|_| std::array::from_fn(|k| f64::from(k == d - 1)));
            self.place(b, &local, &mut t);
        }
        t
    }

    /// `K = diag(K₁, K₂, …)`.
    pub fn stiffness(&self) -> Result<SpMat> {
        let n = self.n_dofs();
        let mut t = TripletBuilder::new(n, n);
        for (p, &o) in self.parts.iter().zip(&self.offsets) {
            t.add_scaled(o, o, 1.0, &p.stiffness()?);
        }
        t.build()
    }

    /// The merged element data: every body's elements with shifted dofs, the Γ_C normal dofs of
    /// every body as contact dofs, and the velocity space H_h when every body has one.
    pub fn mass_model(&self) -> MassModel {
        let models: Vec<MassModel> = self.parts.iter().map(|p| p.mass_model()).collect();
        let shift = |dofs: &[Vec<Option<usize>>], o: usize| -> Vec<Vec<Option<usize>>> {
            dofs.iter()
                .map(|c| c.iter().map(|d| d.map(|d| d + o)).collect())
                .collect()
        };
        let mut elements = Vec::new();
        let mut contact_dofs = Vec::new();
        for (m, &o) in models.iter().zip(&self.offsets) {
            elements.extend(m.elements.iter().map(|e| ElementMass {
                x: e.x.clone(),
                mass: e.mass.clone(),
                dofs: shift(&e.dofs, o),
            }));
            contact_dofs.extend(m.contact_dofs.iter().map(|d| d + o));
        }
        contact_dofs.sort_unstable();
        let velocity = models
            .iter()
            .map(|m| m.velocity.as_ref())
            .collect::<Option<Vec<_>>>()
            .map(|spaces| merge_velocity(&spaces));
        MassModel {
            n_dofs: self.n_dofs(),
            dim: self.dim(),
            elements,
            contact_dofs,
            velocity,
        }
    }

    /// The node-to-segment rows of the slave body's Γ_C vertices on the master body's Γ_C faces:
    /// the face containing the projection (else the one it misses by least, within
    /// [`MAX_EXCESS`], the projection clamped onto it, when the vertex lies in the dead zone
    /// above a convex master's kink: [`in_wedge`]), nearest in |g₀| among ties; the normal is the
    /// mean of the normals of the faces meeting at the projected point (one inside a face, two
    /// on an edge, all around a vertex).
    pub fn pairings(&self, slave: usize, master: usize) -> Result<Vec<Pairing>> {
        let (s, m) = (&self.parts[slave], &self.parts[master]);
        let d = self.dim();
        let dot = |a: [f64; 3], b: [f64; 3]| (0..d).map(|k| a[k] * b[k]).sum::<f64>();
        let mut out = Vec::new();
        let reach: Vec<Reach> = m
            .contact_faces
            .iter()
            .map(|f| Reach::new(f, &m.mesh.nodes))
            .collect();
        for (r, &(i, _)) in s.contact_vertices.iter().enumerate() {
            let xs = s.mesh.nodes[i];
            // (excess, |g₀| along the face's normal, point, shape functions, face)
            let mut candidates = Vec::new();
            for (face, reach) in m.contact_faces.iter().zip(&reach) {
                if !reach.may_project(face.normal, xs) {
                    continue;
                }
                let x = &reach.x;
                let Some((excess, shape)) = project(x, face.normal, xs)? else {
                    continue;
                };
                if excess <= MAX_EXCESS {
                    let xm: [f64; 3] =
                        std::array::from_fn(|k| shape.iter().zip(x).map(|(n, p)| n * p[k]).sum());
                    let g0 = dot(std::array::from_fn(|k| xs[k] - xm[k]), face.normal);
                    candidates.push((excess, g0.abs(), xm, shape, face));
                }
            }
            let Some(best) = candidates
                .iter()
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)))
            else {
                continue;
            };
            let (xm, shape, face) = (best.2, &best.3, best.4);
            let tol = PROJECTION_TOLERANCE * m.mesh.h;
            // The faces through the projected point: xm projected on each is itself.
            let mut meeting: Vec<[f64; 3]> = Vec::new();
            for c in &candidates {
                let x: Vec<[f64; 3]> = c.4.vertices.iter().map(|&k| m.mesh.nodes[k]).collect();
                if let Some((_, sh)) = project(&x, c.4.normal, xm)? {
                    let on = (0..3)
                        .map(|k| {
                            (xm[k] - sh.iter().zip(&x).map(|(n, p)| n * p[k]).sum::<f64>()).powi(2)
                        })
                        .sum::<f64>()
                        .sqrt();
                    if on <= tol {
                        meeting.push(c.4.normal);
                    }
                }
            }
            let mut normal = [0.0; 3];
            for n in &meeting {
                for (a, x) in normal.iter_mut().zip(n) {
                    *a += x;
                }
            }
            let len = dot(normal, normal).sqrt();
            let normal: [f64; 3] = std::array::from_fn(|k| normal[k] / len);
            let offset: [f64; 3] = std::array::from_fn(|k| xs[k] - xm[k]);
            if best.0 > 0.0 && !in_wedge(offset, normal, &meeting, tol) {
                continue;
            }
            let g0 = dot(std::array::from_fn(|k| xs[k] - xm[k]), normal);
            // `−aᵀ` on the slave vertex, `N_k aᵀ` on the master face's vertices.
            let along = |a: [f64; 3]| {
                let mut row: Vec<(usize, f64)> =
                    (0..d).map(|c| (self.global(slave, i, c), -a[c])).collect();
                for (&k, n) in face.vertices.iter().zip(shape) {
                    row.extend((0..d).map(|c| (self.global(master, k, c), n * a[c])));
                }
                row.retain(|e| e.1 != 0.0);
                row
            };
            let tangential = tangents(normal, d)
                .into_iter()
                .map(|t| along(t.map(|x| -x)))
                .collect();
            let master = face.vertices.iter().copied().zip(shape.iter().copied());
            out.push(Pairing {
                slave: r,
                row: along(normal),
                tangential,
                g0,
                master: master.collect(),
                normal,
            });
        }
        if out.is_empty() {
            return Err(Error::Mesh {
                origin: s.mesh.origin.clone(),
                message: "no vertex of the slave's Γ_C projects on the master's Γ_C".into(),
            });
        }
        self.refuse_penetration((slave, master), &out)?;
        Ok(out)
    }

    /// Refuses an initial penetration of a slave vertex into the master deeper than
    /// [`PENETRATION_TOLERANCE`] · h (overlapping bodies, or bodies given in the wrong order).
    fn refuse_penetration(&self, (slave, master): (usize, usize), pairs: &[Pairing]) -> Result<()> {
        let s = &self.parts[slave];
        let tol = PENETRATION_TOLERANCE * s.mesh.h.min(self.parts[master].mesh.h);
        let Some(p) = pairs.iter().find(|p| p.g0 < -tol) else {
            return Ok(());
        };
        let i = s.contact_vertices[p.slave].0;
        Err(Error::Mesh {
            origin: s.mesh.origin.clone(),
            message: format!(
                "body {} {} at {:?} penetrates body {}'s contact face by {:.3e} at t = 0 \
                 (overlapping bodies, or body 1 given below body 2)",
                slave + 1,
                s.mesh.node_name(i),
                s.mesh.nodes[i],
                master + 1,
                -p.g0
            ),
        })
    }

    /// The force of each contact row of [`Bodies::interface`]`(0, 1)` carried to each body's Γ_C
    /// vertices, as `(row, vertex, weight)` per body: λ_r on the row's slave vertex (weight 1),
    /// `N_k λ_r` on the vertices k of its master face (the reaction, equal and opposite, spread
    /// by the master's shape functions at the projection; `Σ_k N_k = 1`).
    pub fn vertex_shares(&self) -> Result<Vec<Vec<(usize, usize, f64)>>> {
        let m = &self.parts[1];
        let mut of_node = vec![None; m.mesh.nodes.len()];
        for (r, &(i, _)) in m.contact_vertices.iter().enumerate() {
            of_node[i] = Some(r);
        }
        let pairs = self.pairings(0, 1)?;
        let of_node = &of_node;
        let slave = pairs.iter().enumerate().map(|(r, p)| (r, p.slave, 1.0));
        let master = pairs.iter().enumerate().flat_map(|(r, p)| {
            p.master
                .iter()
                .filter_map(move |&(k, n)| Some((r, of_node[k]?, n)))
        });
        Ok(vec![slave.collect(), master.collect()])
    }

    /// The master's contact point facing the probe ([`Bodies::problem`]): the global dofs along
    /// e_d of the vertices k of the master face the probe's slave vertex projects on, with N_k
    /// (the point's displacement along the line of impact is `Σ N_k U_k`; in 1D the master
    /// bar's end).
    pub fn master_probe(&self) -> Result<Vec<(usize, f64)>> {
        let pairs = self.pairings(0, 1)?;
        let d = self.dim();
        Ok(pairs[first_row(&pairs)]
            .master
            .iter()
            .map(|&(k, n)| (self.global(1, k, d - 1), n))
            .collect())
    }

    /// Each body's part of a run's state (U, V, the rows' contact forces λ), with the rows'
    /// `shares` of [`Bodies::vertex_shares`]. V is in V_h (the length of U) or in the singular
    /// dynamic method's H_h, each body's vertices in turn.
    pub fn split(
        &self,
        shares: &[Vec<(usize, usize, f64)>],
        u: &[f64],
        v: &[f64],
        lambda: &[f64],
    ) -> Vec<BodyFields> {
        let d = self.dim();
        let mut w0 = 0;
        self.parts
            .iter()
            .zip(&self.offsets)
            .zip(shares)
            .map(|((p, &o), share)| {
                let n = p.n_dofs();
                let nw = if v.len() == self.n_dofs() {
                    n
                } else {
                    p.vertex_count() * d
                };
                let mut forces = vec![0.0; p.contact_vertices.len()];
                for &(r, i, w) in share {
                    forces[i] += w * lambda[r];
                }
                let fields = BodyFields {
                    u: u[o..o + n].to_vec(),
                    v: v[w0..(w0 + nw).min(v.len())].to_vec(),
                    lambda: forces,
                };
                w0 += nw;
                fields
            })
            .collect()
    }

    /// The global dof of node i, component c of body b (its Γ_C vertices are free).
    fn global(&self, b: usize, i: usize, c: usize) -> usize {
        self.dof(b, i, c).unwrap_or(usize::MAX)
    }

    /// The global dof of component `c` of node `i` of body `b`, None where it is fixed.
    pub fn dof(&self, b: usize, i: usize, c: usize) -> Option<usize> {
        self.parts[b].dofs.get(i, c).map(|j| self.offsets[b] + j)
    }

    /// The contact rows of the interface (slave's Γ_C vertices on the master's faces), with the
    /// slave vertices' tributary areas (`σ_N = −λ/area`) and the slave's Γ_C faces on those rows.
    pub fn interface(&self, slave: usize, master: usize) -> Result<Contact> {
        self.contact_of(slave, &self.pairings(slave, master)?)
    }

    /// The contact rows of the pairings `pairs` of the body `slave`'s Γ_C vertices.
    fn contact_of(&self, slave: usize, pairs: &[Pairing]) -> Result<Contact> {
        let s = &self.parts[slave];
        let mut b_n = TripletBuilder::new(pairs.len(), self.n_dofs());
        for (r, p) in pairs.iter().enumerate() {
            for &(j, v) in &p.row {
                b_n.add(r, j, v);
            }
        }
        let row_of = |vertex: usize| {
            pairs
                .iter()
                .position(|p| s.contact_vertices[p.slave].0 == vertex)
        };
        let faces = s
            .contact_faces
            .iter()
            .filter_map(|f| {
                let rows = f
                    .vertices
                    .iter()
                    .map(|&v| row_of(v))
                    .collect::<Option<Vec<_>>>()?;
                (rows.len() == 1).then(|| ContactFace::point(rows[0]))
            })
            .collect();
        Ok(Contact {
            b_n: b_n.build()?,
            g0: pairs.iter().map(|p| p.g0).collect(),
            area: pairs
                .iter()
                .map(|p| s.contact_vertices[p.slave].1)
                .collect(),
            faces,
            vertices: None,
            quadrature: Err(NoQuadrature::TwoBodies),
            force: None,
            normal: None,
            energy: Vec::new(),
            friction: None,
        })
    }

    /// Coulomb friction with coefficient `mu` on the interface rows of [`Bodies::interface`]:
    /// `B_T` from each pairing's tangential rows (point-major, as for the plane), and the
    /// slave's translation along `e_1` (its centre of mass's velocity is `com_velocity_t`).
    pub fn friction(&self, slave: usize, master: usize, mu: f64) -> Result<Friction> {
        let pairs = self.pairings(slave, master)?;
        let tangents = self.dim() - 1;
        let mut b_t = TripletBuilder::new(pairs.len() * tangents, self.n_dofs());
        for (r, p) in pairs.iter().enumerate() {
            for (k, row) in p.tangential.iter().enumerate() {
                for &(j, v) in row {
                    b_t.add(r * tangents + k, j, v);
                }
            }
        }
        let s = &self.parts[slave];
        let mut translation = vec![0.0; self.n_dofs()];
        self.place(slave, &s.interpolate(|_| [1.0, 0.0, 0.0]), &mut translation);
        Ok(Friction::new(mu, b_t.build()?, tangents, translation))
    }

    /// The semi-discrete problem of the bodies (body 0 the slave, body 1 the master) with the
    /// inertia a space builds from the merged element data, from each body's `initial` state:
    /// a body with `gravity` g carries its weight `−ρ g e_d` (each body its own, so that one may
    /// press on the other, which flies free but for their contact); the gravitational energy
    /// `−Fᵀ U` is measured from the reference configuration. The probe is the slave's normal dof
    /// at the contact row of smallest initial gap (its vertex: the row's own, as a slave vertex
    /// may have no row).
    pub fn problem(
        &self,
        inertia: impl FnOnce(&MassModel) -> Result<Box<dyn Inertia>>,
        initial: &[Initial],
    ) -> Result<Problem> {
        if self.parts.len() != 2 || initial.len() != 2 {
            return Err(Error::Unsupported(
                "a multi-body problem has exactly two bodies (slave, master)".into(),
            ));
        }
        let inertia = inertia(&self.mass_model())?;
        let pairs = self.pairings(0, 1)?;
        let contact = self.contact_of(0, &pairs)?;
        let n = self.n_dofs();
        let (mut u0, mut v0, mut f) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for (b, init) in initial.iter().enumerate() {
            self.place(b, &init.displacement, &mut u0);
            self.place(b, &init.velocity, &mut v0);
            if let Some(g) = init.gravity {
                let p = &self.parts[b];
                self.place(b, &p.gravity_load(&p.mass_model(), g), &mut f);
            }
        }
        let first = first_row(&pairs);
        let s = &self.parts[0];
        let vertex = s.contact_vertices[pairs[first].slave].0;
        let u_dof = self.global(0, vertex, self.dim() - 1);
        Ok(Problem {
            probe: Probe {
                contact: first,
                u_dof,
                w_dof: inertia.velocity_dof(u_dof),
            },
            inertia,
            k: self.stiffness()?,
            f,
            contact,
            u0,
            v0,
            energy_shift: 0.0,
        })
    }
}

/// The probe's row: the pairing of smallest g₀ (the first to close), the first of ties.
fn first_row(pairs: &[Pairing]) -> usize {
    (0..pairs.len())
        .min_by(|&a, &b| pairs[a].g0.total_cmp(&pairs[b].g0))
        .unwrap_or(0)
}

/// The velocity spaces of the bodies side by side (H_h dofs shifted like the V_h dofs).
fn merge_velocity(spaces: &[&VelocitySpace]) -> VelocitySpace {
    let mut elements = Vec::new();
    let mut dof_of = Vec::new();
    let mut dim = 0;
    for v in spaces {
        elements.extend(v.elements.iter().map(|e| {
            ElementMixed {
                c: e.c.clone(),
                b: e.b.clone(),
                vdofs: e
                    .vdofs
                    .iter()
                    .map(|c| c.iter().map(|i| i + dim).collect())
                    .collect(),
            }
        }));
        dof_of.extend(v.dof_of.iter().map(|d| d.map(|d| d + dim)));
        dim += v.dim;
    }
    VelocitySpace {
        elements,
        dim,
        dof_of,
    }
}

/// The d − 1 unit tangents of the unit normal n, orthonormal and right-handed with it: in 2D
/// `t = (n_y, −n_x)`; in 3D `t₁` the axis least aligned with n (the first among ties) made
/// orthogonal to n, `t₂ = n × t₁`. A horizontal interface (`n = e_d`) gets the axes `e_1` (and
/// `e_2`), the tangents of the rigid plane ([`Discretisation::friction`]).
fn tangents(n: [f64; 3], d: usize) -> Vec<[f64; 3]> {
    match d {
        1 => Vec::new(),
        2 => vec![[n[1], -n[0], 0.0]],
        _ => {
            let k = (0..3)
                .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
                .unwrap_or(0);
            let mut t = [0.0; 3];
            t[k] = 1.0;
            let tn = n[k];
            t = std::array::from_fn(|c| t[c] - tn * n[c]);
            let len = t.iter().map(|x| x * x).sum::<f64>().sqrt();
            let t1 = t.map(|x| x / len);
            let t2 = [
                n[1] * t1[2] - n[2] * t1[1],
                n[2] * t1[0] - n[0] * t1[2],
                n[0] * t1[1] - n[1] * t1[0],
            ];
            vec![t1, t2]
        }
    }
}

/// Whether a slave vertex whose projection misses every face lies in the dead zone above the
/// kink where the faces of normals `meeting` meet (an edge or vertex shared by at least two of
/// them): its offset from the kink makes an angle with their mean normal `n` no larger than the
/// largest angle α between `n` and theirs, `|offset − (offset·n) n| ≤ |offset·n| tan α`. Beyond
/// the master's Γ_C (a boundary edge, one face) it does not: no row, rather than a row whose
/// gap along the mean normal underestimates the distance.
fn in_wedge(offset: [f64; 3], n: [f64; 3], meeting: &[[f64; 3]], tol: f64) -> bool {
    let dot = |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| a[k] * b[k]).sum::<f64>();
    if meeting.len() < 2 {
        return false;
    }
    let cos = meeting
        .iter()
        .map(|&m| dot(m, n).clamp(-1.0, 1.0))
        .fold(1.0, f64::min);
    let gn = dot(offset, n);
    let tangential: [f64; 3] = std::array::from_fn(|k| offset[k] - gn * n[k]);
    let tan = (1.0 - cos * cos).sqrt() / cos;
    dot(tangential, tangential).sqrt() <= gn.abs() * tan + tol
}

/// Where a master face's projections can come from: [`project`] puts a point `p` at
/// `x(s, t) = Σ N_k x_k` with `p − x(s, t)` along the face's normal n, and [`Bodies::pairings`]
/// keeps it when (s, t) lies within [`MAX_EXCESS`] = e of the face, where `Σ |N_k| ≤ (1 + 2e)²`
/// (a quadrilateral's corner (−e, −e) is the worst; a triangle's `1 + 4e` and a segment's
/// `1 + 2e` are below), so `|x(s, t) − c| ≤ (1 + 2e)² max_k |x_k − c|` about the vertices' mean
/// c. Hence p's distance to c across n is at most that plus the projection's tolerance: a point
/// further away cannot pair with the face ([`Reach::may_project`]), and the test skips the
/// projection of a slave vertex on every far face (the pairs are the same).
struct Reach {
    /// The face's vertices.
    x: Vec<[f64; 3]>,
    /// Their mean c.
    centre: [f64; 3],
    /// The bound on the distance across the normal, with a relative margin for round-off.
    radius: f64,
}

impl Reach {
    fn new(face: &crate::mesh::Face, nodes: &[[f64; 3]]) -> Self {
        let x: Vec<[f64; 3]> = face.vertices.iter().map(|&k| nodes[k]).collect();
        let len = x.len().max(1) as f64;
        let centre: [f64; 3] = std::array::from_fn(|k| x.iter().map(|y| y[k]).sum::<f64>() / len);
        let far = |a: [f64; 3]| {
            x.iter()
                .map(|y| (0..3).map(|k| (y[k] - a[k]).powi(2)).sum::<f64>().sqrt())
                .fold(0.0, f64::max)
        };
        // [`project`]'s tolerance on the offset across the normal: 1e-9 of the face's size. A
        // point (1D) takes every vertex, and [`project`] refuses larger faces: no bound.
        let radius = match x.len() {
            2..=4 => {
                ((1.0 + 2.0 * MAX_EXCESS).powi(2) * far(centre) + 1e-9 * far(x[0])) * (1.0 + 1e-6)
            }
            _ => f64::INFINITY,
        };
        Self { x, centre, radius }
    }

    /// Whether `p` can project on the face within [`MAX_EXCESS`] along its normal `n`.
    fn may_project(&self, n: [f64; 3], p: [f64; 3]) -> bool {
        let v: [f64; 3] = std::array::from_fn(|k| p[k] - self.centre[k]);
        let vn = (0..3).map(|k| v[k] * n[k]).sum::<f64>();
        let across = (0..3).map(|k| (v[k] - vn * n[k]).powi(2)).sum::<f64>();
        across.sqrt() <= self.radius
    }
}

/// The projection of `p` along the face's unit normal `n` on the face with vertices `x`: how far
/// outside the face it falls (in reference coordinates, 0 inside) and the shape functions at
/// the nearest point of the face (a point: `[1]`; a segment: `[1 − t, t]`; a triangle:
/// `[1 − s − t, s, t]`; a quadrilateral in cyclic order: the bilinear
/// `[(1 − s)(1 − t), s(1 − t), s t, (1 − s) t]`); None when Newton fails. On a straight face this is the orthogonal projection;
/// on a warped quadrilateral, the point whose offset to `p` is parallel to the face's averaged
/// normal (Newton on the two tangential equations), so that the row's torque vanishes.
pub(super) fn project(x: &[[f64; 3]], n: [f64; 3], p: [f64; 3]) -> Result<Option<(f64, Vec<f64>)>> {
    let shape = |s: f64, t: f64| -> Vec<f64> {
        match x.len() {
            2 => vec![1.0 - s, s],
            3 => vec![1.0 - s - t, s, t],
            _ => vec![(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t],
        }
    };
    // ∂N/∂s and ∂N/∂t.
    let slopes = |s: f64, t: f64| -> [Vec<f64>; 2] {
        match x.len() {
            2 => [vec![-1.0, 1.0], vec![0.0, 0.0]],
            3 => [vec![-1.0, 1.0, 0.0], vec![-1.0, 0.0, 1.0]],
            _ => [
                vec![-(1.0 - t), 1.0 - t, t, -t],
                vec![-(1.0 - s), -s, s, 1.0 - s],
            ],
        }
    };
    let combine = |w: &[f64]| -> [f64; 3] {
        std::array::from_fn(|k| w.iter().zip(x).map(|(w, y)| w * y[k]).sum())
    };
    let dot = |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| a[k] * b[k]).sum::<f64>();
    match x.len() {
        1 => return Ok(Some((0.0, vec![1.0]))),
        2..=4 => {}
        k => {
            return Err(Error::Unsupported(format!(
                "node-to-segment pairing on faces of {k} vertices"
            )))
        }
    }
    let (mut s, mut t) = if x.len() == 2 {
        (0.5, 0.0)
    } else {
        (1.0 / 3.0, 1.0 / 3.0)
    };
    for _ in 0..NEWTON_ITERATIONS {
        let xm = combine(&shape(s, t));
        let r: [f64; 3] = std::array::from_fn(|k| xm[k] - p[k]);
        let [ds, dt] = slopes(s, t).map(|w| combine(&w));
        // The tangential part of the residual: r − (r·n) n, and the tangents' likewise.
        let tangential = |v: [f64; 3]| -> [f64; 3] {
            let vn = dot(v, n);
            std::array::from_fn(|k| v[k] - vn * n[k])
        };
        let (r, a, b) = (tangential(r), tangential(ds), tangential(dt));
        let step = if x.len() == 2 {
            [dot(r, a) / dot(a, a), 0.0]
        } else {
            // Least squares on the tangent plane: [a b]ᵀ[a b] (δs, δt) = [a b]ᵀ r.
            let (aa, ab, bb) = (dot(a, a), dot(a, b), dot(b, b));
            let det = aa * bb - ab * ab;
            let (ra, rb) = (dot(r, a), dot(r, b));
            [(bb * ra - ab * rb) / det, (aa * rb - ab * ra) / det]
        };
        s -= step[0];
        t -= step[1];
        if step[0].abs().max(step[1].abs()) < 1e-14 {
            break;
        }
    }
    // Converged: the offset to p is along n (to round-off of the face's size). Far from the
    // face, the bilinear map of a warped quadrilateral may fold and Newton wander: no projection.
    let size = x
        .iter()
        .map(|y| {
            dot(
                std::array::from_fn(|k| y[k] - x[0][k]),
                std::array::from_fn(|k| y[k] - x[0][k]),
            )
        })
        .fold(0.0, f64::max)
        .sqrt();
    let r: [f64; 3] = {
        let xm = combine(&shape(s, t));
        std::array::from_fn(|k| xm[k] - p[k])
    };
    let rn = dot(r, n);
    let tangential: [f64; 3] = std::array::from_fn(|k| r[k] - rn * n[k]);
    if !(s.is_finite() && t.is_finite()) || dot(tangential, tangential).sqrt() > 1e-9 * size {
        return Ok(None);
    }
    let excess = match x.len() {
        2 => (-s).max(s - 1.0),
        3 => (-s).max(-t).max(s + t - 1.0),
        _ => (-s).max(s - 1.0).max(-t).max(t - 1.0),
    }
    .max(0.0);
    let (s, t) = match x.len() {
        2 => (s.clamp(0.0, 1.0), 0.0),
        3 => {
            let (s, t) = (s.max(0.0), t.max(0.0));
            let over = (s + t - 1.0).max(0.0);
            (s - 0.5 * over, t - 0.5 * over)
        }
        _ => (s.clamp(0.0, 1.0), t.clamp(0.0, 1.0)),
    };
    Ok(Some((excess, shape(s, t))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::elasticity::Lame;
    use crate::linalg::{to_dense, triplets};
    use crate::mesh::interval::interval;
    use crate::mesh::ContactRule;
    use crate::space::{singular_dynamic, SPACES};

    /// A free bar on (x0, x0 + L) whose Γ_C is its end at x = 0.
    fn bar(x0: f64, length: f64, elements: usize, degree: usize) -> Discretisation {
        let mut mesh = interval(length, elements, degree).unwrap();
        for x in &mut mesh.nodes {
            x[0] += x0;
        }
        let end = if x0 < 0.0 { mesh.nodes.len() - 1 } else { 0 };
        mesh.contact_faces = Some(vec![vec![end]]);
        let lame = Lame {
            lambda: 0.0,
            mu: 0.5,
        };
        Discretisation::new(mesh, lame, 1.0, ContactRule::Tagged).unwrap()
    }

    fn bars(degree: usize) -> Bodies {
        Bodies::new(vec![bar(-1.0, 1.0, 4, degree), bar(0.0, 2.0, 8, degree)]).unwrap()
    }

    /// Two bars meeting at x = 0: one node-to-node row, `g = u₂(0) − u₁(0)` (+1 on bar 1's end,
    /// −1 on bar 2's first dof: forces equal and opposite, `B_N 1 = 0`), g₀ = 0; K block
    /// diagonal with two rigid translations; the merged mass has the total mass 3 and both end
    /// dofs as contact dofs.
    #[test]
    fn two_bars_give_one_node_to_node_row() {
        let b = bars(1);
        assert_eq!(b.n_dofs(), 5 + 9);
        let c = b.interface(0, 1).unwrap();
        let row: Vec<_> = triplets(&c.b_n).map(|(_, j, v)| (j, v)).collect();
        assert_eq!(row, vec![(4, 1.0), (5, -1.0)]);
        assert_eq!(c.g0, vec![0.0]);
        let k = b.stiffness().unwrap();
        let one = b.translation();
        assert!(crate::linalg::mul(&k, &one).iter().all(|x| x.abs() < 1e-12));
        let mut rigid1 = vec![0.0; 14];
        rigid1[..5].fill(1.0);
        assert!(crate::linalg::mul(&k, &rigid1)
            .iter()
            .all(|x| x.abs() < 1e-12));
        let model = b.mass_model();
        assert_eq!(model.contact_dofs, vec![4, 5]);
        for space in SPACES {
            let s = (space.build)(&Default::default()).unwrap();
            let Ok(inertia) = s.inertia(&model) else {
                continue;
            };
            let m = inertia.mass_times(&one).unwrap();
            let total: f64 = m.iter().sum();
            // Mass elimination loses the mass of the elements at the interface (h₁ + h₂).
            let want = if space.name == "mass_elimination" {
                3.0 - 0.25 - 0.25
            } else {
                3.0
            };
            assert!((total - want).abs() < 1e-12, "{}: {total}", space.name);
        }
    }

    /// Mass redistribution on the merged model makes the coupled row's direction massless
    /// (`b_cᵀ M̃ b_c = 0`, both end dofs massless) with each bar's mass kept; the singular dynamic
    /// method's inf-sup condition holds on the coupled row (P2/P1).
    #[test]
    fn the_cures_act_on_both_sides_of_the_coupled_row() {
        let b = bars(1);
        let model = b.mass_model();
        let inertia = crate::space::by_name("mass_redistribution")
            .unwrap()
            .inertia(&model)
            .unwrap();
        let massless = inertia.massless();
        assert!(massless[4] && massless[5]);
        assert_eq!(massless.iter().filter(|&&m| m).count(), 2);
        let row = b.pairings(0, 1).unwrap()[0].row.clone();
        let mut bc = vec![0.0; b.n_dofs()];
        for (j, v) in &row {
            bc[*j] = *v;
        }
        let mb = inertia.mass_times(&bc).unwrap();
        assert!(mb.iter().all(|x| x.abs() < 1e-15));
        let mut ones1 = vec![0.0; b.n_dofs()];
        ones1[..5].fill(1.0);
        let p1: f64 = inertia.mass_times(&ones1).unwrap().iter().sum();
        assert!((p1 - 1.0).abs() < 1e-12, "bar 1 mass {p1}");

        let b2 = bars(2);
        let model = b2.mass_model();
        let (bm, _) = singular_dynamic::mixed_matrices(&model).unwrap();
        let rows: Vec<Vec<(usize, f64)>> = b2
            .pairings(0, 1)
            .unwrap()
            .into_iter()
            .map(|p| p.row)
            .collect();
        assert!(singular_dynamic::inf_sup_holds_rows(&to_dense(&bm), &rows));
        assert_eq!(model.velocity.as_ref().unwrap().dim, 5 + 9);
    }

    /// Two stacked Q1 blocks in 2D with non-matching meshes: the upper (slave, 3 cells across,
    /// lifted by 0.1) on the lower's top faces (master, 2 cells across). Every slave vertex gets
    /// a row `−n_m` on itself and `N_k n_m` on its master face (N = (1/3, 2/3) at x = 1/3 on the
    /// face (0, ½)), g₀ = 0.1; the rows annihilate both translations (`B_N 1_x = B_N 1_y = 0`:
    /// equal and opposite forces); mass redistribution on the merged model makes every row's
    /// direction massless, `M̃ b_c = 0`, and keeps the total mass.
    #[test]
    fn stacked_blocks_pair_node_to_segment_on_non_matching_meshes() {
        use crate::element::reference::{RefElement, Shape};
        use crate::mesh::structured::box_mesh;
        let q1 = RefElement {
            shape: Shape::Tensor,
            dim: 2,
            degree: 1,
        };
        let lame = Lame::from_young_poisson(1.0, 0.3);
        let mut lower = box_mesh(q1, [2, 2, 1], [1.0, 1.0, 1.0]).unwrap();
        let top: Vec<Vec<usize>> = lower
            .boundary_faces()
            .into_iter()
            .filter(|f| f.normal[1] > 0.5)
            .map(|f| f.vertices)
            .collect();
        lower.contact_faces = Some(top);
        let mut upper = box_mesh(q1, [3, 3, 1], [1.0, 1.0, 1.0]).unwrap();
        for x in &mut upper.nodes {
            x[1] += 1.1;
        }
        let master = Discretisation::new(lower, lame, 1.0, ContactRule::Tagged).unwrap();
        let slave = Discretisation::new(upper, lame, 1.0, ContactRule::Facing(0.01)).unwrap();
        let b = Bodies::new(vec![slave, master]).unwrap();
        let pairs = b.pairings(0, 1).unwrap();
        assert_eq!(pairs.len(), 4);
        let n = b.n_dofs();
        for p in &pairs {
            assert!((p.g0 - 0.1).abs() < 1e-12, "{p:?}");
            for c in 0..2 {
                let sum: f64 = p.row.iter().filter(|e| e.0 % 2 == c).map(|e| e.1).sum();
                assert!(sum.abs() < 1e-12, "component {c}: {p:?}");
            }
        }
        let third = pairs
            .iter()
            .find(|p| {
                let s = &b.parts[0];
                (s.mesh.nodes[s.contact_vertices[p.slave].0][0] - 1.0 / 3.0).abs() < 1e-12
            })
            .unwrap();
        let mut shares: Vec<f64> = third.row.iter().skip(1).map(|e| e.1).collect();
        shares.sort_by(f64::total_cmp);
        assert!((shares[0] - 1.0 / 3.0).abs() < 1e-12 && (shares[1] - 2.0 / 3.0).abs() < 1e-12);
        assert_eq!(third.row[0].1, -1.0);
        let inertia = crate::space::by_name("mass_redistribution")
            .unwrap()
            .inertia(&b.mass_model())
            .unwrap();
        for p in &pairs {
            let mut bc = vec![0.0; n];
            for &(j, v) in &p.row {
                bc[j] = v;
            }
            let mb = inertia.mass_times(&bc).unwrap();
            assert!(mb.iter().all(|x| x.abs() < 1e-14), "{p:?}");
        }
        let one = b.translation();
        let total: f64 = inertia.mass_times(&one).unwrap().iter().sum();
        assert!((total - 2.0).abs() < 1e-12, "total mass {total}");
        // The tangential rows: `+e_x` on the slave vertex, `−N_k e_x` on the master's (the
        // master normal is e_y): x components only, summing to 0 (equal and opposite forces).
        for p in &pairs {
            assert_eq!(p.tangential.len(), 1);
            let t = &p.tangential[0];
            assert_eq!(t[0].1, 1.0);
            assert!(t.iter().all(|e| e.0 % 2 == 0), "x components only: {t:?}");
            let sum: f64 = t.iter().map(|e| e.1).sum();
            assert!(sum.abs() < 1e-12, "{t:?}");
        }
        let f = b.friction(0, 1, 0.3).unwrap();
        assert_eq!((f.b_t.nrows(), f.tangents, f.frictionless), (4, 1, 0));
    }

    /// The tangents of a unit normal are unit, orthogonal to it and to each other, and
    /// right-handed (`t₁ × t₂ = n` in 3D); the normal e_d gets the axes.
    #[test]
    fn tangents_complete_the_normal_to_a_frame() {
        assert_eq!(tangents([0.0, 1.0, 0.0], 2), vec![[1.0, 0.0, 0.0]]);
        assert_eq!(
            tangents([0.0, 0.0, 1.0], 3),
            vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        );
        let l = (1.0_f64 + 4.0 + 9.0).sqrt();
        let n = [1.0 / l, -2.0 / l, 3.0 / l];
        let t = tangents(n, 3);
        let dot = |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| a[k] * b[k]).sum::<f64>();
        for a in &t {
            assert!((dot(*a, *a) - 1.0).abs() < 1e-15 && dot(*a, n).abs() < 1e-15);
        }
        assert!(dot(t[0], t[1]).abs() < 1e-15);
        let cross = [
            t[0][1] * t[1][2] - t[0][2] * t[1][1],
            t[0][2] * t[1][0] - t[0][0] * t[1][2],
            t[0][0] * t[1][1] - t[0][1] * t[1][0],
        ];
        assert!((0..3).all(|k| (cross[k] - n[k]).abs() < 1e-15), "{cross:?}");
    }

    /// Node-to-segment projection: a vertex above the middle of a master segment gets shape
    /// functions (½, ½); one beyond its end misses it by the excess (¼ face), the shape
    /// functions of the end; on a triangle the barycentric coordinates; on a warped
    /// quadrilateral (one vertex lifted) the bilinear shape functions at the point whose offset
    /// to the vertex is along the face normal: they sum to 1 and reproduce the point,
    /// `Σ N_k x_k = p − g₀ n`.
    #[test]
    fn node_to_segment_projects_on_the_master_face() {
        let up = [0.0, 1.0, 0.0];
        let face = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let near = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-14);
        let (excess, n) = project(&face, up, [1.0, 0.3, 0.0]).unwrap().unwrap();
        assert!(excess == 0.0 && near(&n, &[0.5, 0.5]), "{n:?}");
        let (excess, n) = project(&face, up, [2.5, 0.3, 0.0]).unwrap().unwrap();
        assert!(
            (excess - 0.25).abs() < 1e-14 && near(&n, &[0.0, 1.0]),
            "{excess} {n:?}"
        );
        let z = [0.0, 0.0, 1.0];
        let tri = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let (excess, n) = project(&tri, z, [0.2, 0.1, 0.5]).unwrap().unwrap();
        assert!(excess == 0.0 && near(&n, &[0.7, 0.2, 0.1]), "{n:?}");
        let (excess, _) = project(&tri, z, [0.8, 0.8, 0.5]).unwrap().unwrap();
        assert!((excess - 0.6).abs() < 1e-14, "{excess}");
        let quad = [[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.2], [0.0, 1.0, 0.0]];
        let p = [0.7, 0.4, 0.9];
        let (excess, n) = project(&quad, z, p).unwrap().unwrap();
        assert!(excess == 0.0 && (n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        let xm: Vec<f64> = (0..3)
            .map(|k| n.iter().zip(&quad).map(|(w, x)| w * x[k]).sum())
            .collect();
        assert!(near(&xm[..2], &p[..2]), "{xm:?}");
        assert!((xm[2] - 0.2 * 0.7 * 0.4).abs() < 1e-14, "{xm:?}");
        assert!(project(&quad, z, [1.2, 0.5, 0.0]).unwrap().unwrap().0 > 0.19);
        assert!(project(&[[0.0; 3]; 5], z, p).is_err());
    }

    /// [`Reach`] keeps every point that projects on a face within [`MAX_EXCESS`] (a segment, a
    /// triangle, a warped quadrilateral; points on a grid around each, above and below) and
    /// rejects the points far across the normal.
    #[test]
    fn reach_keeps_every_point_that_projects_on_the_face() {
        let faces: [(Vec<[f64; 3]>, [f64; 3]); 3] = [
            (vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]], [0.0, 1.0, 0.0]),
            (
                vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                [0.0, 0.0, 1.0],
            ),
            (
                vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.2], [0.0, 1.0, 0.0]],
                [0.0, 0.0, 1.0],
            ),
        ];
        for (x, normal) in faces {
            let nodes = x.clone();
            let face = crate::mesh::Face {
                vertices: (0..x.len()).collect(),
                measure: 1.0,
                normal,
                cell: 0,
                local: vec![],
            };
            let reach = Reach::new(&face, &nodes);
            let (mut paired, mut skipped) = (0, 0);
            for i in -60..=60 {
                for j in -60..=60 {
                    for h in [-1.0, 0.05, 2.0] {
                        let (a, b) = (i as f64 / 20.0, j as f64 / 20.0);
                        let p = if x.len() == 2 { [a, h, b] } else { [a, b, h] };
                        let near = project(&x, normal, p)
                            .unwrap()
                            .is_some_and(|(excess, _)| excess <= MAX_EXCESS);
                        let kept = reach.may_project(normal, p);
                        assert!(kept || !near, "{p:?} projects on {x:?} but is skipped");
                        paired += usize::from(near);
                        skipped += usize::from(!kept);
                    }
                }
            }
            assert!(paired > 0 && skipped > paired, "{paired} {skipped}");
        }
    }

    /// A convex master (two segments meeting at a kink of 0.2 rad below the slave vertex at
    /// height 0.5): the projections along both faces' normals miss them (the dead zone), the
    /// vertex is paired with the kink itself and the mean normal, the bisector `e_y`; its row
    /// still annihilates both translations. A vertex beyond the master's end (a single face
    /// there, no kink) gets no row.
    #[test]
    fn a_vertex_above_a_convex_kink_gets_the_mean_normal() {
        use crate::mesh::{Face, Mesh};
        let q1 = crate::element::reference::RefElement {
            shape: crate::element::reference::Shape::Tensor,
            dim: 2,
            degree: 1,
        };
        let a = 0.1_f64;
        let (c, s) = (a.cos(), a.sin());
        let mesh = |nodes: Vec<[f64; 3]>| Mesh {
            origin: "test".into(),
            element: q1,
            nodes,
            connectivity: vec![vec![0, 1, 2, 3]],
            h: 1.0,
            contact_faces: None,
            tags: None,
        };
        // The master's top: (−c, −s) – (0, 0) – (c, −s), outward normals (±s, c).
        let mut master = bar(0.0, 1.0, 1, 1);
        master.mesh = mesh(vec![
            [-c, -s, 0.0],
            [0.0, 0.0, 0.0],
            [c, -s, 0.0],
            [0.0, -2.0, 0.0],
        ]);
        let face = |v: Vec<usize>, normal: [f64; 3]| Face {
            vertices: v,
            measure: 1.0,
            normal,
            cell: 0,
            local: vec![],
        };
        master.contact_faces = vec![
            face(vec![0, 1], [-s, c, 0.0]),
            face(vec![1, 2], [s, c, 0.0]),
        ];
        master.dofs = crate::fem::dofs::DofMap::free(4, 2);
        let mut slave = master.clone();
        slave.mesh = mesh(vec![
            [0.0, 0.5, 0.0],
            [1.0, 0.5, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ]);
        slave.mesh.nodes[1] = [1.2, 0.3, 0.0];
        slave.contact_vertices = vec![(0, 1.0), (1, 1.0)];
        let b = Bodies::new(vec![slave, master]).unwrap();
        let pairs = b.pairings(0, 1).unwrap();
        // Vertex 1 misses the master's end by 0.16 face: beyond Γ_C, no row.
        assert_eq!(pairs.len(), 1);
        let p = &pairs[0];
        assert!((p.g0 - 0.5).abs() < 1e-14, "{p:?}");
        assert_eq!(p.row[0], (1, -1.0));
        for comp in 0..2 {
            let sum: f64 = p.row.iter().filter(|e| e.0 % 2 == comp).map(|e| e.1).sum();
            assert!(sum.abs() < 1e-14, "{p:?}");
        }
    }
}
