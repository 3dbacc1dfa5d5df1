//! `block2d` / `block3d`: an elastic block dropped on a rigid plane (`shared/reference/
//! block_drop.md`), the seed paper's 2D experiment (plane strain) and its 3D version.
//!
//! Ω = (0, L_x) × (0, L_y) [× (0, L_z)], isotropic linear elasticity, no Dirichlet condition.
//! Contact with the rigid plane at the vertices of the bottom face Γ_C (normal dofs only,
//! frictionless): outward normal `−e_d`, so `B_N U = −u_d` and `g = lift + u_d ≥ 0` at each vertex.
//! Initial state: undeformed, uniform vertical velocity; optional gravity. No exact solution: the
//! convergence reference is a run on a finer mesh and time step (see the report).

use super::sweep::SweepSpec;
use super::{Case, FieldError, Overrides, RunSpec};
use crate::error::{positive, Error, Result};
use crate::exact::ExactContact;
use crate::fem::assembly::assemble;
use crate::fem::elasticity::{element_mass, element_stiffness, mixed_matrices, Lame};
use crate::fem::reference::{RefElement, Shape};
use crate::linalg::TripletBuilder;
use crate::mesh::structured::StructuredMesh;
use crate::problem::{Contact, Inertia, Probe, Problem};
use crate::space::{ElementMass, ElementMixed, MassModel, Space};
use rayon::prelude::*;
use serde::Deserialize;

/// `[material]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν ∈ (−1, ½).
    pub poisson: f64,
    /// Density ρ.
    pub density: f64,
}

/// `[geometry]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// Box size (2 or 3 entries).
    pub size: Vec<f64>,
    /// Initial vertical velocity (negative: towards the plane).
    pub velocity: f64,
    /// Initial gap between Γ_C and the plane (≥ 0).
    #[serde(default)]
    pub lift: f64,
    /// Gravity acceleration g ≥ 0 (body force −ρ g e_d).
    #[serde(default)]
    pub gravity: f64,
}

/// `[mesh]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// `quad` or `triangle` (2D), `hex` or `tet` (3D).
    pub cells: String,
    /// Polynomial degree (1 or 2).
    pub degree: usize,
    /// Cells along the first direction (the others in proportion to the size).
    pub elements: usize,
}

/// The whole `block2d` / `block3d` case file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlockSpec {
    /// `block2d` or `block3d`.
    pub case: String,
    /// Units statement.
    pub units: String,
    /// Material.
    pub material: Material,
    /// Geometry and initial state.
    pub geometry: Geometry,
    /// Mesh.
    pub mesh: MeshSpec,
    /// Run defaults.
    pub run: RunSpec,
    /// Sweeps.
    #[serde(default)]
    pub sweep: Vec<SweepSpec>,
    /// Time histories for the report.
    #[serde(default)]
    pub history: Vec<super::sweep::HistorySpec>,
}

/// A validated block case.
#[derive(Debug, Clone)]
pub struct Block {
    kind: &'static str,
    /// The mesh.
    pub mesh: StructuredMesh,
    /// Lamé constants.
    pub lame: Lame,
    /// Density.
    pub density: f64,
    /// Geometry and initial state.
    pub geometry: Geometry,
    run: RunSpec,
    sweeps: Vec<SweepSpec>,
    /// Time histories for the report.
    pub history: Vec<super::sweep::HistorySpec>,
}

/// Estimated bytes of the assembly: the triplets of one global matrix (24 B per entry of every
/// element matrix), then K, M and the step matrix compressed (16 B per stored entry, a node
/// coupling to the (2p + 1)^d nodes around it).
fn assembly_bytes(element: &RefElement, cells: [usize; 3]) -> f64 {
    let (d, p) = (element.dim, element.degree);
    let cells = &cells[..d];
    let per_cell = if element.shape == Shape::Simplex {
        [1, 1, 2, 6][d]
    } else {
        1
    };
    let elements = cells.iter().map(|&c| c as f64).product::<f64>() * per_cell as f64;
    let nodes: f64 = cells.iter().map(|&c| (p * c + 1) as f64).product();
    let local = (element.n_nodes() * d) as f64;
    let coupled = ((2 * p + 1) as f64).powi(d as i32) * (d * d) as f64;
    elements * local * local * 24.0 + 3.0 * nodes * coupled * 16.0
}

impl Block {
    /// Validates the spec, applies the overrides and builds the mesh.
    pub fn from_spec(spec: BlockSpec, o: &Overrides) -> Result<Self> {
        let (kind, dim) = match spec.case.as_str() {
            "block2d" => ("block2d", 2),
            _ => ("block3d", 3),
        };
        let m = &spec.material;
        positive("material.young", m.young)?;
        positive("material.density", m.density)?;
        if !(m.poisson.is_finite() && m.poisson > -1.0 && m.poisson < 0.5) {
            return Err(Error::invalid(
                "material.poisson",
                m.poisson,
                "must be in (−1, ½)",
            ));
        }
        let g = &spec.geometry;
        if g.size.len() != dim {
            return Err(Error::invalid(
                "geometry.size",
                &g.size,
                &format!("needs {dim} entries for {kind}"),
            ));
        }
        for s in &g.size {
            positive("geometry.size", *s)?;
        }
        crate::error::finite("geometry.velocity", g.velocity)?;
        crate::error::non_negative("geometry.lift", g.lift)?;
        crate::error::non_negative("geometry.gravity", g.gravity)?;
        let shape = match (spec.mesh.cells.as_str(), dim) {
            ("quad", 2) | ("hex", 3) => Shape::Tensor,
            ("triangle", 2) | ("tet", 3) => Shape::Simplex,
            (c, _) => {
                return Err(Error::invalid(
                    "mesh.cells",
                    c,
                    if dim == 2 {
                        "quad or triangle"
                    } else {
                        "hex or tet"
                    },
                ))
            }
        };
        let degree = o.degree.unwrap_or(spec.mesh.degree);
        if !(1..=2).contains(&degree) {
            return Err(Error::invalid("mesh.degree", degree, "must be 1 or 2"));
        }
        let n = o.elements.unwrap_or(spec.mesh.elements);
        if n == 0 {
            return Err(Error::invalid("mesh.elements", n, "must be ≥ 1"));
        }
        let mut cells = [1; 3];
        let mut size = [0.0; 3];
        for k in 0..dim {
            size[k] = g.size[k];
            cells[k] = ((n as f64 * g.size[k] / g.size[0]).round() as usize).max(1);
        }
        let mut run = spec.run;
        o.apply(&mut run);
        run.validate()?;
        let element = RefElement { shape, dim, degree };
        crate::util::check_memory("mesh.elements", n, assembly_bytes(&element, cells))?;
        Ok(Self {
            kind,
            mesh: StructuredMesh::new(element, cells, size)?,
            lame: Lame::from_young_poisson(m.young, m.poisson),
            density: m.density,
            geometry: spec.geometry,
            run,
            sweeps: spec.sweep,
            history: spec.history,
        })
    }

    fn dim(&self) -> usize {
        self.mesh.dim()
    }

    /// Global dofs of cell `c` per component (`node · dim + comp`).
    fn cell_dofs(&self, c: usize) -> Vec<Vec<Option<usize>>> {
        let d = self.dim();
        (0..d)
            .map(|comp| {
                self.mesh.connectivity[c]
                    .iter()
                    .map(|&i| Some(i * d + comp))
                    .collect()
            })
            .collect()
    }

    /// Global index of every vertex in the velocity space H_h (degree-1 nodes), or None.
    fn vertex_index(&self) -> (Vec<Option<usize>>, usize) {
        let mut count = 0;
        let index = (0..self.mesh.nodes.len())
            .map(|i| {
                self.mesh.is_vertex(i).then(|| {
                    count += 1;
                    count - 1
                })
            })
            .collect();
        (index, count)
    }

    /// Element data for the spaces (and the velocity space H_h for degree 2).
    pub fn mass_model(&self) -> MassModel {
        let (d, mesh) = (self.dim(), &self.mesh);
        let el = mesh.element;
        let (vertex, nv) = self.vertex_index();
        let (lin, map) = el.linear();
        let mut elements = Vec::with_capacity(mesh.connectivity.len());
        let mut mixed = Vec::new();
        for c in 0..mesh.connectivity.len() {
            let (_, jac) = mesh.jacobian(c);
            let mass = element_mass(&el, &jac, self.density);
            elements.push(ElementMass {
                x: mesh.connectivity[c]
                    .iter()
                    .map(|&i| mesh.nodes[i])
                    .collect(),
                mass,
                dofs: self.cell_dofs(c),
            });
            if el.degree == 2 {
                let (cm, bm) = mixed_matrices(&el, &jac, self.density);
                let verts: Vec<usize> = (0..lin.n_nodes())
                    .map(|b| vertex[mesh.connectivity[c][map[b]]].expect("a vertex"))
                    .collect();
                mixed.push(ElementMixed {
                    c: cm,
                    b: bm,
                    vdofs: (0..d)
                        .map(|comp| verts.iter().map(|v| v * d + comp).collect())
                        .collect(),
                });
            }
        }
        let mut contact_dofs: Vec<usize> = self
            .mesh
            .contact_vertices()
            .iter()
            .map(|(i, _)| i * d + d - 1)
            .collect();
        contact_dofs.sort_unstable();
        MassModel {
            n_dofs: mesh.nodes.len() * d,
            dim: d,
            elements,
            contact_dofs,
            velocity: (el.degree == 2).then_some((mixed, nv * d)),
        }
    }
}

impl Case for Block {
    fn kind(&self) -> &'static str {
        self.kind
    }

    fn h(&self) -> f64 {
        self.mesh.size[0] / self.mesh.cells[0] as f64
    }

    fn problem(&self, space: &dyn Space) -> Result<Problem> {
        let (d, mesh) = (self.dim(), &self.mesh);
        let n = mesh.nodes.len() * d;
        let el = mesh.element;
        let stiffness: Vec<(Vec<Option<usize>>, nalgebra::DMatrix<f64>)> =
            (0..mesh.connectivity.len())
                .into_par_iter()
                .map(|c| {
                    let (_, jac) = mesh.jacobian(c);
                    let k = element_stiffness(&el, &jac, self.lame);
                    let dofs = mesh.connectivity[c]
                        .iter()
                        .flat_map(|&i| (0..d).map(move |comp| Some(i * d + comp)))
                        .collect();
                    (dofs, k)
                })
                .collect();
        let k = assemble(
            n,
            n,
            stiffness
                .iter()
                .map(|(dofs, k)| (dofs.clone(), dofs.clone(), k)),
        )?;
        let model = self.mass_model();
        let inertia = space.inertia(&model)?;
        // Gravity: F = −g ∫ρ φ_i on the vertical component (consistent load).
        let mut f = vec![0.0; n];
        for e in &model.elements {
            for (a, dof) in e.dofs[d - 1].iter().enumerate() {
                if let Some(i) = dof {
                    f[*i] -= self.geometry.gravity * e.mass.row(a).sum();
                }
            }
        }
        let vertices = mesh.contact_vertices();
        let mut b_n = TripletBuilder::new(vertices.len(), n);
        for (r, (i, _)) in vertices.iter().enumerate() {
            b_n.add(r, i * d + d - 1, -1.0);
        }
        let mut v0 = vec![0.0; n];
        for i in 0..mesh.nodes.len() {
            v0[i * d + d - 1] = self.geometry.velocity;
        }
        // Probe: the contact vertex closest to the centre of Γ_C.
        let centre: Vec<f64> = (0..d - 1).map(|k| 0.5 * mesh.size[k]).collect();
        let dist = |i: usize| -> f64 {
            (0..d - 1)
                .map(|k| (mesh.nodes[i][k] - centre[k]).powi(2))
                .sum()
        };
        let probe = (0..vertices.len())
            .min_by(|&a, &b| dist(vertices[a].0).total_cmp(&dist(vertices[b].0)))
            .ok_or_else(|| Error::Unsupported("block: no contact vertex".into()))?;
        let u_dof = vertices[probe].0 * d + d - 1;
        let w_dof = match &inertia {
            Inertia::Sparse { .. } => u_dof,
            Inertia::Mixed { .. } => {
                let (vertex, _) = self.vertex_index();
                vertex[vertices[probe].0].expect("a vertex") * d + d - 1
            }
        };
        Ok(Problem {
            inertia,
            k,
            f,
            contact: Contact {
                b_n: b_n.build()?,
                g0: vec![self.geometry.lift; vertices.len()],
                area: vertices.iter().map(|v| v.1).collect(),
            },
            u0: vec![0.0; n],
            v0,
            probe: Probe {
                contact: probe,
                u_dof,
                w_dof,
            },
            energy_shift: 0.0,
        })
    }

    fn exact(&self) -> Option<&dyn ExactContact> {
        None
    }

    fn field_error(&self) -> Option<Box<dyn FieldError + '_>> {
        None
    }

    fn stress_is_function(&self) -> bool {
        true
    }

    fn run(&self) -> &RunSpec {
        &self.run
    }

    fn sweeps(&self) -> &[SweepSpec] {
        &self.sweeps
    }

    fn histories(&self) -> &[super::sweep::HistorySpec] {
        &self.history
    }
}
