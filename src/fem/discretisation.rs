//! The discretisation of an elastic body against the rigid plane `x_d = 0` (d the last
//! coordinate, obstacle below): a [`Mesh`], its Lagrange family (degree 1 or 2, isoparametric) and
//! the dof map `(node i, component c) ↦ i·d + c`. It assembles everything a case needs from any
//! mesh, structured or not:
//! - the stiffness `K` of isotropic linear elasticity (plane strain in 2D);
//! - the [`MassModel`] every space builds its inertia from (element masses, the contact normal
//!   dofs, and for degree 2 the degree-1 velocity space H_h of the singular dynamic method);
//! - the contact operator at the vertices of Γ_C: `g = g₀ − B_N U` with `g₀_i = x_{i,d} + lift`
//!   (signed distance to the plane) and `B_N U = −u_{i,d}` (the displacement along the **plane's**
//!   outward normal −e_d, whatever the body's normal there);
//! - the quadrature points of Γ_C for Nitsche's boundary integrals ([`super::boundary`]);
//! - the probe: the Γ_C vertex nearest the plane at t = 0 (ties: nearest the centre of Γ_C's
//!   bounding box).

use crate::element::reference::Tabulation;
use crate::element::segment::Segment;
use crate::error::{Error, Result};
use crate::fem::assembly::assemble_square;
use crate::fem::assembly::{segment_mass, segment_mixed_mass, segment_stiffness};
use crate::fem::boundary::contact_points;
pub use crate::fem::dofs::DofMap;
use crate::fem::elasticity::{
    element_mass, element_stiffness, mixed_matrices, stress, von_mises, Lame,
};
use crate::fem::mass_model::{ElementMass, ElementMixed, MassModel, VelocitySpace};
use crate::linalg::{SpMat, TripletBuilder};
use crate::mesh::{ContactRule, Face, Mesh, FACING};
use crate::problem::{Contact, ContactFace, Friction, Inertia, Probe, Problem};
use nalgebra::DMatrix;
use rayon::prelude::*;

/// Initial penetration refused at t = 0, relative to the mesh size h.
pub const PENETRATION_TOLERANCE: f64 = 1e-6;

/// A body's mesh with its material and its contact boundary.
#[derive(Debug, Clone)]
pub struct Discretisation {
    /// The mesh.
    pub mesh: Mesh,
    /// Lamé constants.
    pub lame: Lame,
    /// Density ρ.
    pub density: f64,
    /// The faces of Γ_C.
    pub contact_faces: Vec<Face>,
    /// The vertices of Γ_C (increasing node index) with their tributary length or area.
    pub contact_vertices: Vec<(usize, f64)>,
    /// The dofs of the free nodes.
    pub dofs: DofMap,
}

/// The initial state and load of a body, in the dof layout of its discretisation.
#[derive(Debug, Clone)]
pub struct Initial {
    /// U₀.
    pub displacement: Vec<f64>,
    /// V₀.
    pub velocity: Vec<f64>,
    /// The body force: gravity `g ≥ 0` along `−e_d` (None: no load at all).
    pub gravity: Option<f64>,
    /// The gap between Γ_C and the plane at t = 0 (≥ 0).
    pub lift: f64,
}

/// Why a node off Γ_C at height `x` (along `e_d`) is refused by
/// [`Discretisation::check_tagged_contact`] against Γ_C's lowest vertex at `lowest`: it lies
/// below it (the body would sink through the plane there), at its level, or above it by less
/// than the tolerance `PENETRATION_TOLERANCE · h` within which a node is taken to be at Γ_C's
/// level (as for an initial penetration): the top of a plate thinner than the tolerance, which
/// the check cannot tell from its bottom.
fn lower_than(x: f64, lowest: f64, h: f64, d: usize) -> String {
    let level = format!(
        "Γ_C's lowest vertex (x_{d} = {})",
        crate::error::short(lowest)
    );
    if x < lowest {
        format!(
            "lies below {level} by {:.3e}: the body would meet the plane there, outside Γ_C, and \
             sink through it (tag the lower part of the boundary as the contact group)",
            lowest - x
        )
    } else if x == lowest {
        format!(
            "lies at the level of {level}: it would meet the plane outside Γ_C (tag the faces \
             through it as contact too)"
        )
    } else {
        format!(
            "lies {:.3e} above {level}, less than the tolerance {:.3e} ({PENETRATION_TOLERANCE:e} \
             h, h = {}) within which a node is taken to be at Γ_C's level: the body is too thin \
             there to tell this node from Γ_C, and it would meet the plane outside Γ_C (make the \
             body thicker than the tolerance, or tag the faces through the node as contact too)",
            x - lowest,
            PENETRATION_TOLERANCE * h,
            crate::error::short(h)
        )
    }
}

impl Discretisation {
    /// Checks the mesh (no inverted or degenerate cell; a 1D mesh uniform, every cell of length
    /// `h`) and selects Γ_C by `rule`; every node free.
    pub fn new(mesh: Mesh, lame: Lame, density: f64, rule: ContactRule) -> Result<Self> {
        mesh.check()?;
        if mesh.dim() == 1 {
            check_uniform(&mesh)?;
        }
        let contact_faces = mesh.contact_faces(rule)?;
        let contact_vertices = mesh.tributary(&contact_faces);
        let dofs = DofMap::free(mesh.nodes.len(), mesh.dim());
        Ok(Self {
            mesh,
            lame,
            density,
            contact_faces,
            contact_vertices,
            dofs,
        })
    }

    /// Γ_C tagged by a mesh file for a body against the plane `x_d = 0` below it (its own frame):
    /// refuses a group whose every face points away from the plane, `n_d > FACING` (side faces
    /// and a sphere's equator, `n_d ≈ 0`, face it; so does a whole boundary), and a vertex of the
    /// cells off Γ_C as low as Γ_C's lowest vertex, within `PENETRATION_TOLERANCE · h`, or lower
    /// (the body would meet the plane outside Γ_C and sink through it; a body thinner than that
    /// tolerance is refused so: its top cannot be told from its bottom at the plane's level).
    pub fn check_tagged_contact(&self) -> Result<()> {
        let (d, mesh) = (self.dim(), &self.mesh);
        let refuse = |message: String| {
            Err(Error::Mesh {
                origin: mesh.origin.clone(),
                message,
            })
        };
        // A whole boundary tagged (a disc that rolls past a quarter turn) faces every way: only
        // a group whose every face faces away from the plane can never meet it.
        let meets = self.contact_faces.iter().any(|f| f.normal[d - 1] <= FACING);
        if let (false, Some(f)) = (meets, self.contact_faces.first()) {
            return refuse(format!(
                "every contact face faces away from the plane below the body: every outward \
                 normal has n_{d} > {FACING}, e.g. face {}'s ({}) has n_{d} = {:.3} (Γ_C holds \
                 the faces that can meet the plane x_{d} = 0 under the body: tag the lower part \
                 of the boundary, or all of it)",
                mesh.face_name(f),
                f.normal[..d]
                    .iter()
                    .map(|x| format!("{x:.3}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                f.normal[d - 1]
            ));
        }
        let height = |i: usize| mesh.nodes[i][d - 1];
        let lowest = self
            .contact_vertices
            .iter()
            .map(|v| height(v.0))
            .fold(f64::INFINITY, f64::min);
        // A vertex outside Γ_C as low as its lowest meets the plane with it (the bottom corner
        // of a square whose left side alone is Γ_C) and sinks through.
        // The vertices of Γ_C come in increasing node index.
        let off_contact = |i: usize| {
            self.contact_vertices
                .binary_search_by_key(&i, |v| v.0)
                .is_err()
        };
        let below = mesh
            .vertex_flags()
            .iter()
            .enumerate()
            .filter(|&(i, &v)| {
                v && off_contact(i) && height(i) < lowest + PENETRATION_TOLERANCE * mesh.h
            })
            .map(|(i, _)| i)
            .min_by(|&a, &b| height(a).total_cmp(&height(b)));
        match below {
            Some(i) => refuse(format!(
                "{} at {:?}, not on Γ_C, {}",
                mesh.node_name(i),
                &mesh.nodes[i][..d],
                lower_than(height(i), lowest, mesh.h, d)
            )),
            None => Ok(()),
        }
    }

    /// `self` with the nodes where `fixed(x)` holds clamped (u = 0, their dofs eliminated);
    /// refuses to clamp a vertex of Γ_C.
    pub fn clamped(mut self, fixed: impl Fn([f64; 3]) -> bool) -> Result<Self> {
        let flags: Vec<bool> = self.mesh.nodes.iter().map(|&x| fixed(x)).collect();
        if let Some(&(i, _)) = self.contact_vertices.iter().find(|v| flags[v.0]) {
            return Err(Error::Mesh {
                origin: self.mesh.origin.clone(),
                message: format!("the clamped {} is a vertex of Γ_C", self.mesh.node_name(i)),
            });
        }
        self.dofs = DofMap::new(self.dim(), &flags);
        Ok(self)
    }

    /// Spatial dimension d.
    pub fn dim(&self) -> usize {
        self.mesh.dim()
    }

    /// Number of displacement dofs.
    pub fn n_dofs(&self) -> usize {
        self.dofs.len()
    }

    /// Global dof of node i, component c, which is free (a Γ_C vertex or a body without clamp).
    fn dof(&self, i: usize, c: usize) -> usize {
        self.dofs.get(i, c).unwrap_or(usize::MAX)
    }

    /// Global dofs of cell `c` per component.
    fn cell_dofs(&self, c: usize) -> Vec<Vec<Option<usize>>> {
        (0..self.dim())
            .map(|comp| {
                self.mesh.connectivity[c]
                    .iter()
                    .map(|&i| self.dofs.get(i, comp))
                    .collect()
            })
            .collect()
    }

    /// `v_i = f(x_i)` at every free dof (node i, component c ↦ `f(x_i)[c]`).
    pub fn interpolate(&self, f: impl Fn([f64; 3]) -> [f64; 3]) -> Vec<f64> {
        let mut v = vec![0.0; self.n_dofs()];
        for (i, &x) in self.mesh.nodes.iter().enumerate() {
            let value = f(x);
            for (c, value) in value.iter().enumerate().take(self.dim()) {
                if let Some(dof) = self.dofs.get(i, c) {
                    v[dof] = *value;
                }
            }
        }
        v
    }

    /// The segment element of a 1D mesh and its (uniform) length.
    fn segment(&self) -> (Segment, f64) {
        (
            Segment {
                degree: self.mesh.element.degree,
            },
            self.mesh.h,
        )
    }

    /// The modulus of 1D elasticity `σ = (λ + 2μ) u'` (E for a bar, whose ν is 0).
    fn modulus_1d(&self) -> f64 {
        self.lame.lambda + 2.0 * self.lame.mu
    }

    /// The element stiffness of cell `c` (1D: the segment's closed form on the uniform length;
    /// `tab`: the element's basis at its quadrature points).
    fn cell_stiffness(&self, tab: &Tabulation, c: usize) -> DMatrix<f64> {
        if self.dim() == 1 {
            let (seg, h) = self.segment();
            return segment_stiffness(seg, h, self.modulus_1d());
        }
        element_stiffness(tab, &self.mesh.cell_nodes(c), self.lame)
    }

    /// The scalar element mass of the cell with nodes `x`.
    fn cell_mass(&self, tab: &Tabulation, x: &[[f64; 3]]) -> DMatrix<f64> {
        if self.dim() == 1 {
            let (seg, h) = self.segment();
            return segment_mass(seg, h, self.density);
        }
        element_mass(tab, x, self.density)
    }

    /// `(C, B)` of the cell with nodes `x` for the degree-1 velocity space.
    fn cell_mixed(&self, tab: &Tabulation, x: &[[f64; 3]]) -> (DMatrix<f64>, DMatrix<f64>) {
        if self.dim() == 1 {
            let (seg, h) = self.segment();
            let p1 = Segment { degree: 1 };
            return (
                segment_mass(p1, h, self.density),
                segment_mixed_mass(p1, seg, h, self.density),
            );
        }
        mixed_matrices(tab, x, self.density)
    }

    /// The semi-discrete problem of this body with the inertia a space builds from its element
    /// data (`inertia`, e.g. `|m| space.inertia(m)`), from `initial`. Gravitational energy is
    /// measured from the plane: `−Fᵀ(x_d + lift) = m g (z_cm + lift)`.
    pub fn problem(
        &self,
        inertia: impl FnOnce(&MassModel) -> Result<Box<dyn Inertia>>,
        initial: &Initial,
    ) -> Result<Problem> {
        let d = self.dim();
        let model = self.mass_model();
        let inertia = inertia(&model)?;
        let contact = self.contact(initial.lift)?;
        let probe = self.probe(&contact, inertia.as_ref())?;
        let (f, energy_shift) = match initial.gravity {
            None => (vec![0.0; self.n_dofs()], 0.0),
            Some(g) => {
                let f = self.gravity_load(&model, g);
                let shift = -(0..self.mesh.nodes.len())
                    .filter_map(|i| self.dofs.get(i, d - 1).map(|dof| (i, dof)))
                    .map(|(i, dof)| f[dof] * (self.mesh.nodes[i][d - 1] + initial.lift))
                    .sum::<f64>();
                (f, shift)
            }
        };
        Ok(Problem {
            k: self.stiffness()?,
            f,
            inertia,
            contact,
            u0: initial.displacement.clone(),
            v0: initial.velocity.clone(),
            probe,
            energy_shift,
        })
    }

    /// Number of vertices (the nodes of the velocity space H_h of degree 1).
    pub fn vertex_count(&self) -> usize {
        self.vertex_index().1
    }

    /// Index of every vertex in the velocity space H_h (degree-1 nodes, by node order), or None.
    fn vertex_index(&self) -> (Vec<Option<usize>>, usize) {
        let mut count = 0;
        let index = self
            .mesh
            .vertex_flags()
            .into_iter()
            .map(|v| {
                v.then(|| {
                    count += 1;
                    count - 1
                })
            })
            .collect();
        (index, count)
    }

    /// The stiffness `K` (element matrices in parallel, added in cell order, streamed:
    /// [`assemble_square`]).
    pub fn stiffness(&self) -> Result<SpMat> {
        let (d, mesh) = (self.dim(), &self.mesh);
        let tab = mesh.element.tabulate();
        assemble_square(
            self.n_dofs(),
            mesh.connectivity.len(),
            |c| {
                mesh.connectivity[c]
                    .iter()
                    .flat_map(|&i| (0..d).map(move |comp| self.dofs.get(i, comp)))
                    .collect()
            },
            |c| self.cell_stiffness(&tab, c),
        )
    }

    /// Cell c's data for [`Discretisation::mass_model`]: its element mass, and for degree 2 its
    /// mixed matrices on the velocity space's vertices (`vertex`: the H_h index of each node;
    /// `map`: the element's local vertices, [`crate::element::reference::RefElement::linear`]).
    fn cell_model(
        &self,
        tab: &Tabulation,
        (vertex, map): (&[Option<usize>], &[usize]),
        c: usize,
    ) -> (ElementMass, Option<ElementMixed>) {
        let (d, el, cell) = (self.dim(), self.mesh.element, &self.mesh.connectivity[c]);
        let x = self.mesh.cell_nodes(c);
        let mixed = (el.degree == 2).then(|| {
            let (cm, bm) = self.cell_mixed(tab, &x);
            // Every local vertex is a mesh vertex by construction of `vertex_flags`.
            let verts: Vec<usize> = map.iter().filter_map(|&a| vertex[cell[a]]).collect();
            ElementMixed {
                c: cm,
                b: bm,
                vdofs: (0..d)
                    .map(|comp| verts.iter().map(|v| v * d + comp).collect())
                    .collect(),
            }
        });
        let mass = ElementMass {
            mass: self.cell_mass(tab, &x),
            x,
            dofs: self.cell_dofs(c),
        };
        (mass, mixed)
    }

    /// Element data for the spaces (and the velocity space H_h for degree 2).
    pub fn mass_model(&self) -> MassModel {
        let (d, mesh) = (self.dim(), &self.mesh);
        let el = mesh.element;
        let (vertex, nv) = self.vertex_index();
        let (tab, (_, map)) = (el.tabulate(), el.linear());
        let (elements, mixed): (Vec<ElementMass>, Vec<Option<ElementMixed>>) =
            (0..mesh.connectivity.len())
                .into_par_iter()
                .map(|c| self.cell_model(&tab, (&vertex, &map), c))
                .unzip();
        let mixed: Vec<ElementMixed> = mixed.into_iter().flatten().collect();
        let mut contact_dofs: Vec<usize> = self
            .contact_vertices
            .iter()
            .map(|&(i, _)| self.dof(i, d - 1))
            .collect();
        contact_dofs.sort_unstable();
        MassModel {
            n_dofs: self.n_dofs(),
            dim: d,
            elements,
            contact_dofs,
            velocity: (el.degree == 2).then(|| VelocitySpace {
                elements: mixed,
                dim: nv * d,
                dof_of: self.velocity_dofs(&vertex),
            }),
        }
    }

    /// The H_h dof at the node of each displacement dof (`vertex`: the H_h index of each
    /// vertex node).
    fn velocity_dofs(&self, vertex: &[Option<usize>]) -> Vec<Option<usize>> {
        let d = self.dim();
        let mut of = vec![None; self.n_dofs()];
        for (i, v) in vertex.iter().enumerate() {
            for c in 0..d {
                if let Some(dof) = self.dofs.get(i, c) {
                    of[dof] = v.map(|v| v * d + c);
                }
            }
        }
        of
    }

    /// The mass `∫ρ φ_i` of every node (row sums of the consistent element masses).
    pub fn nodal_masses(&self, model: &MassModel) -> Vec<f64> {
        let mut w = vec![0.0; self.mesh.nodes.len()];
        for (e, cell) in model.elements.iter().zip(&self.mesh.connectivity) {
            for (a, &i) in cell.iter().enumerate() {
                w[i] += e.mass.row(a).sum();
            }
        }
        w
    }

    /// The consistent body force `F_i = −g ∫ρ φ_i` on the last component (gravity g ≥ 0).
    pub fn gravity_load(&self, model: &MassModel, gravity: f64) -> Vec<f64> {
        self.body_force(model, self.dim() - 1, -gravity)
    }

    /// The consistent body force `F_i = a ∫ρ φ_i` of the acceleration `a` along component `k`.
    pub fn body_force(&self, model: &MassModel, k: usize, a: f64) -> Vec<f64> {
        let mut f = vec![0.0; self.n_dofs()];
        for (i, m) in self.nodal_masses(model).into_iter().enumerate() {
            if let Some(dof) = self.dofs.get(i, k) {
                f[dof] = a * m;
            }
        }
        f
    }

    /// The contact operator with the body lifted by `lift` above the plane: refuses an initial
    /// penetration deeper than [`PENETRATION_TOLERANCE`] · h of any node of the body, naming it
    /// (the vertices of Γ_C, and the others: a body partly below the plane with Γ_C elsewhere,
    /// the midside node of a curved face of Γ_C; the plane is rigid).
    pub fn contact(&self, lift: f64) -> Result<Contact> {
        let (d, x) = (self.dim(), &self.mesh.nodes);
        let n = self.n_dofs();
        if let Some((i, g)) = x
            .iter()
            .map(|p| p[d - 1] + lift)
            .enumerate()
            .find(|&(_, g)| g < -PENETRATION_TOLERANCE * self.mesh.h)
        {
            return Err(Error::Mesh {
                origin: self.mesh.origin.clone(),
                message: format!(
                    "{} at {:?} is below the plane x_{d} = 0 by {:.3e} at t = 0 (lift {}): it \
                     penetrates the rigid obstacle, above which every node of the body must start",
                    self.mesh.node_name(i),
                    x[i],
                    -g,
                    crate::error::short(lift)
                ),
            });
        }
        let mut b_n = TripletBuilder::new(self.contact_vertices.len(), n);
        let mut g0 = Vec::with_capacity(self.contact_vertices.len());
        for (r, &(i, _)) in self.contact_vertices.iter().enumerate() {
            b_n.add(r, self.dof(i, d - 1), -1.0);
            g0.push(x[i][d - 1] + lift);
        }
        let row: std::collections::HashMap<usize, usize> = self
            .contact_vertices
            .iter()
            .enumerate()
            .map(|(r, v)| (v.0, r))
            .collect();
        let faces = self
            .contact_faces
            .iter()
            .map(|f| ContactFace {
                rows: f.vertices.iter().map(|v| row[v]).collect(),
                mass: face_mass(&f.vertices.iter().map(|&v| x[v]).collect::<Vec<_>>()),
            })
            .collect();
        Ok(Contact {
            b_n: b_n.build()?,
            g0,
            area: self.contact_vertices.iter().map(|v| v.1).collect(),
            faces,
            vertices: None,
            quadrature: Ok(contact_points(
                &self.mesh,
                &self.contact_faces,
                self.lame,
                lift,
                (&row, &self.dofs),
            )),
            force: None,
            normal: None,
            energy: Vec::new(),
            friction: None,
        })
    }

    /// Coulomb friction with coefficient `mu` at the vertices of Γ_C on the plane `x_d = 0`:
    /// the tangents are the first d − 1 axes, `B_T` row `r (d − 1) + k` picks component k of
    /// vertex r (in [`Discretisation::contact_vertices`] order).
    pub fn friction(&self, mu: f64) -> Result<Friction> {
        let tangents = self.dim() - 1;
        let mut b_t = TripletBuilder::new(self.contact_vertices.len() * tangents, self.n_dofs());
        for (r, &(i, _)) in self.contact_vertices.iter().enumerate() {
            for k in 0..tangents {
                b_t.add(r * tangents + k, self.dof(i, k), 1.0);
            }
        }
        let mut translation = vec![0.0; self.n_dofs()];
        for i in 0..self.mesh.nodes.len() {
            if let Some(dof) = self.dofs.get(i, 0) {
                translation[dof] = 1.0;
            }
        }
        Ok(Friction::new(mu, b_t.build()?, tangents, translation))
    }

    /// Von Mises stress `√(3/2 s:s)` of the displacement `u` at the centroid of every cell
    /// (plane strain in 2D).
    pub fn von_mises(&self, u: &[f64]) -> Vec<f64> {
        let (d, mesh) = (self.dim(), &self.mesh);
        let (el, centre) = (mesh.element, mesh.element.centre());
        (0..mesh.connectivity.len())
            .into_par_iter()
            .map(|c| {
                let local: Vec<f64> = mesh.connectivity[c]
                    .iter()
                    .flat_map(|&i| (0..d).map(move |k| u[i * d + k]))
                    .collect();
                von_mises(&stress(&el, &mesh.cell_nodes(c), self.lame, &local, centre))
            })
            .collect()
    }

    /// The velocity at every node (dof layout of U): `v` itself when it lives in V_h; the H_h
    /// velocity of the singular dynamic method (degree 1, at the vertices) interpolated at the
    /// other nodes. Errors on any other length.
    pub fn nodal_velocity(&self, v: &[f64]) -> Result<Vec<f64>> {
        let (d, n) = (self.dim(), self.n_dofs());
        if v.len() == n {
            return Ok(v.to_vec());
        }
        let (vertex, nv) = self.vertex_index();
        if v.len() != nv * d {
            return Err(Error::Internal(format!(
                "a velocity of {} entries is neither in V_h ({n}) nor in H_h ({})",
                v.len(),
                nv * d
            )));
        }
        let el = self.mesh.element;
        let (lin, map) = el.linear();
        let mut out = vec![0.0; n];
        // H_h is continuous: every cell containing node i gives the same value.
        for cell in &self.mesh.connectivity {
            for (a, &i) in cell.iter().enumerate() {
                let psi = lin.eval(el.node(a)).0;
                for k in 0..d {
                    out[i * d + k] = map
                        .iter()
                        .zip(&psi)
                        .filter_map(|(&la, p)| vertex[cell[la]].map(|vi| p * v[vi * d + k]))
                        .sum();
                }
            }
        }
        Ok(out)
    }

    /// The contact pressure `λ_r / |Γ_C|_r` at every node (0 off Γ_C) from the nodal contact
    /// forces λ (one per Γ_C vertex, in [`Discretisation::contact_vertices`] order).
    pub fn contact_pressure(&self, lambda: &[f64]) -> Vec<f64> {
        let mut p = vec![0.0; self.mesh.nodes.len()];
        for (&(i, area), l) in self.contact_vertices.iter().zip(lambda) {
            p[i] = l / area;
        }
        p
    }

    /// The probe: the Γ_C vertex nearest the plane at t = 0, ties (within 1e-9 h) broken by the
    /// distance to the centre of Γ_C's bounding box, then by the lowest index.
    pub fn probe(&self, contact: &Contact, inertia: &dyn Inertia) -> Result<Probe> {
        let (d, x) = (self.dim(), &self.mesh.nodes);
        let verts = &self.contact_vertices;
        let centre: Vec<f64> = (0..d - 1)
            .map(|k| {
                let (lo, hi) = verts
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |m, v| {
                        (m.0.min(x[v.0][k]), m.1.max(x[v.0][k]))
                    });
                0.5 * (lo + hi)
            })
            .collect();
        let dist = |r: usize| -> f64 {
            (0..d - 1)
                .map(|k| (x[verts[r].0][k] - centre[k]).powi(2))
                .sum()
        };
        let lowest = contact.g0.iter().copied().fold(f64::INFINITY, f64::min);
        let tie = 1e-9 * self.mesh.h;
        let probe = (0..verts.len())
            .filter(|&r| contact.g0[r] <= lowest + tie)
            .min_by(|&a, &b| dist(a).total_cmp(&dist(b)))
            .ok_or_else(|| Error::Mesh {
                origin: self.mesh.origin.clone(),
                message: "Γ_C has no vertex".into(),
            })?;
        let node = verts[probe].0;
        let u_dof = self.dof(node, d - 1);
        Ok(Probe {
            contact: probe,
            u_dof,
            w_dof: inertia.velocity_dof(u_dof),
        })
    }
}

/// Refuses a 1D mesh whose cells are not all of length `h` (relative 1e-12): the segment's
/// element matrices are formed once on that length.
fn check_uniform(mesh: &Mesh) -> Result<()> {
    let el = mesh.element;
    let (first, last) = (0, el.degree);
    for (c, cell) in mesh.connectivity.iter().enumerate() {
        let (a, b) = (mesh.nodes[cell[first]][0], mesh.nodes[cell[last]][0]);
        // The rounding of the coordinates themselves (eps |x| each) on top of 1e-12 h: a
        // uniform mesh of 10⁴ elements differs from h by ~1e4 eps h at its far end.
        let tolerance = 1e-12 * mesh.h + 4.0 * f64::EPSILON * a.abs().max(b.abs());
        let len = b - a;
        if (len.abs() - mesh.h).abs() > tolerance {
            return Err(Error::Mesh {
                origin: mesh.origin.clone(),
                message: format!(
                    "cell {c} has length {:.6e}: a 1D mesh must be uniform (h = {:.6e})",
                    len.abs(),
                    mesh.h
                ),
            });
        }
    }
    Ok(())
}

/// `∫_F ψ_a ψ_b` of the degree-1 hat functions of a straight face with vertices `x` (cyclic
/// order): a segment `|F|/6 [2 1; 1 2]`, a triangle `|F|/12 (1 + δ_ab)`, a quadrilateral by 2 × 2
/// Gauss points on its bilinear map (exact: the integrand is of degree 3 in each variable).
fn face_mass(x: &[[f64; 3]]) -> Vec<f64> {
    let k = x.len();
    if k == 1 {
        // An end point of a 1D body: the point value.
        return vec![1.0];
    }
    let sub =
        |a: [f64; 3], b: [f64; 3]| nalgebra::Vector3::new(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    match k {
        2 | 3 => {
            let measure = if k == 2 {
                sub(x[1], x[0]).norm()
            } else {
                0.5 * sub(x[1], x[0]).cross(&sub(x[2], x[0])).norm()
            };
            let scale = measure / ((k + 1) * k) as f64;
            (0..k * k)
                .map(|ab| scale * if ab / k == ab % k { 2.0 } else { 1.0 })
                .collect()
        }
        _ => {
            let g = 0.5 / 3f64.sqrt();
            let mut m = vec![0.0; 16];
            for (s, t) in [
                (0.5 - g, 0.5 - g),
                (0.5 + g, 0.5 - g),
                (0.5 + g, 0.5 + g),
                (0.5 - g, 0.5 + g),
            ] {
                let psi = [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
                let ds = sub(x[1], x[0]) * (1.0 - t) + sub(x[2], x[3]) * t;
                let dt = sub(x[3], x[0]) * (1.0 - s) + sub(x[2], x[1]) * s;
                let w = 0.25 * ds.cross(&dt).norm();
                for a in 0..4 {
                    for b in 0..4 {
                        m[a * 4 + b] += w * psi[a] * psi[b];
                    }
                }
            }
            m
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::reference::{RefElement, Shape};
    use crate::mesh::structured::box_mesh;
    use crate::mesh::FACING;

    /// A node off Γ_C is said to lie below Γ_C, at its level, or above it within the tolerance
    /// (a node exactly at the level was "0.000e0 above … too thin").
    #[test]
    fn a_node_off_contact_is_placed_where_it_is() {
        assert!(lower_than(-1e-3, 0.0, 1.0, 2).starts_with("lies below"));
        assert!(lower_than(0.0, 0.0, 1.0, 2).starts_with("lies at the level of"));
        let above = lower_than(1e-7, 0.0, 1.0, 2);
        assert!(above.starts_with("lies 1.000e-7 above") && above.contains("too thin"));
    }

    /// A uniform interval of 10⁵ elements passes the uniformity check (its coordinates round
    /// by up to ~1e5 eps h at the far end); a moved node does not.
    #[test]
    fn long_uniform_intervals_pass_and_a_moved_node_fails() {
        let mut mesh = crate::mesh::interval::interval(1.0, 100_000, 1).unwrap();
        assert!(check_uniform(&mesh).is_ok());
        mesh.nodes[50_000][0] += 1e-9 * mesh.h;
        assert!(check_uniform(&mesh).is_err());
    }

    /// A body already through the plane at t = 0 is refused, naming the node; a reflected mesh
    /// (every cell negatively oriented) is accepted and gives the same stiffness.
    #[test]
    fn initial_penetration_is_refused_and_orientation_does_not_matter() {
        let e = RefElement {
            shape: Shape::Tensor,
            dim: 2,
            degree: 1,
        };
        let lame = Lame::from_young_poisson(1.0, 0.3);
        let mut mesh = box_mesh(e, [2, 2, 1], [1.0, 1.0, 1.0]).unwrap();
        mesh.nodes[0][1] = -0.1;
        let fem = Discretisation::new(mesh, lame, 1.0, ContactRule::Facing(FACING)).unwrap();
        let err = fem.contact(0.0).unwrap_err().to_string();
        assert!(
            err.contains("node 0") && err.contains("penetrates"),
            "{err}"
        );
        assert!(fem.contact(0.2).is_ok());
        // A node off the vertices of Γ_C below the plane: the midside node of a Q9 cell's
        // bottom edge bulging 0.1 through it (the vertices on the plane were all checked).
        let q9 = RefElement { degree: 2, ..e };
        let mut mesh = box_mesh(q9, [1, 1, 1], [1.0, 1.0, 1.0]).unwrap();
        let mid = (0..mesh.nodes.len())
            .find(|&i| mesh.nodes[i] == [0.5, 0.0, 0.0])
            .unwrap();
        mesh.nodes[mid][1] = -0.1;
        let fem = Discretisation::new(mesh, lame, 1.0, ContactRule::Facing(FACING)).unwrap();
        let err = fem.contact(0.0).unwrap_err().to_string();
        assert!(
            err.contains(&format!("node {mid} ")) && err.contains("below the plane"),
            "{err}"
        );
        assert!(fem.contact(0.1).is_ok());
        let mesh = box_mesh(e, [2, 2, 1], [1.0, 1.0, 1.0]).unwrap();
        let mut mirrored = mesh.clone();
        for x in &mut mirrored.nodes {
            x[0] = 1.0 - x[0];
        }
        let k = |m| {
            Discretisation::new(m, lame, 1.0, ContactRule::Facing(FACING))
                .unwrap()
                .stiffness()
                .unwrap()
        };
        let (a, b) = (k(mesh), k(mirrored));
        let diag = |m: &SpMat| crate::linalg::diagonal(m);
        assert!(diag(&a)
            .iter()
            .zip(diag(&b))
            .all(|(x, y)| (x - y).abs() < 1e-14));
    }

    /// The 1D bar through the same discretisation: a clamped P2 interval has the assembled
    /// closed-form stiffness of the segment (row sums of K vanish on the free interior, the
    /// clamped node's dofs are gone), Γ_C is the end x = 0 with σ_N = E u' there, and the mesh
    /// must be uniform; clamping Γ_C is refused.
    #[test]
    fn the_bar_is_a_clamped_interval_of_segments() {
        let young = 3.0;
        let lame = Lame {
            lambda: 0.0,
            mu: 0.5 * young,
        };
        let rule = ContactRule::Facing(FACING);
        let mesh = crate::mesh::interval::interval(2.0, 4, 2).unwrap();
        let fem = Discretisation::new(mesh.clone(), lame, 1.0, rule)
            .unwrap()
            .clamped(|x| x[0] == 2.0)
            .unwrap();
        assert_eq!(fem.n_dofs(), 8);
        assert_eq!(fem.contact_vertices, vec![(0, 1.0)]);
        let k = crate::linalg::to_dense(&fem.stiffness().unwrap());
        // K·1 = 0 away from the clamped end (rigid translation).
        for i in 0..6 {
            assert!(k.row(i).sum().abs() < 1e-12, "row {i}");
        }
        let c = fem.contact(0.0).unwrap();
        let sigma = &c.quadrature.unwrap()[0].sigma_n;
        // u = x on the first element (h = 0.5): σ = E.
        let s: f64 = sigma.iter().map(|&(j, v)| v * 0.25 * j as f64).sum();
        assert!((s - young).abs() < 1e-12, "σ_N = {s}");
        let err = Discretisation::new(mesh.clone(), lame, 1.0, rule)
            .unwrap()
            .clamped(|x| x[0] == 0.0)
            .unwrap_err();
        assert!(err.to_string().contains("Γ_C"), "{err}");
        let mut skewed = mesh;
        skewed.nodes[2][0] += 0.1;
        skewed.nodes[1][0] += 0.05;
        let err = Discretisation::new(skewed, lame, 1.0, rule).unwrap_err();
        assert!(err.to_string().contains("uniform"), "{err}");
    }
}
