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
use crate::fem::discretisation::Discretisation;
use crate::fem::elasticity::Lame;
use crate::fem::reference::{RefElement, Shape};
use crate::mesh::structured::box_mesh;
use crate::mesh::{ContactRule, FACING};
use crate::problem::Problem;
use crate::space::Space;
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
    /// Mesh, material and Γ_C.
    pub fem: Discretisation,
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
            fem: Discretisation::new(
                box_mesh(element, cells, size)?,
                Lame::from_young_poisson(m.young, m.poisson),
                m.density,
                ContactRule::Facing(FACING),
            )?,
            geometry: spec.geometry,
            run,
            sweeps: spec.sweep,
            history: spec.history,
        })
    }
}

impl Case for Block {
    fn kind(&self) -> &'static str {
        self.kind
    }

    fn h(&self) -> f64 {
        self.fem.mesh.h
    }

    fn problem(&self, space: &dyn Space) -> Result<Problem> {
        let fem = &self.fem;
        let (d, n) = (fem.dim(), fem.n_dofs());
        let model = fem.mass_model();
        let inertia = space.inertia(&model)?;
        let contact = fem.contact(self.geometry.lift)?;
        let probe = fem.probe(&contact, &inertia)?;
        let mut v0 = vec![0.0; n];
        for v in v0.iter_mut().skip(d - 1).step_by(d) {
            *v = self.geometry.velocity;
        }
        Ok(Problem {
            k: fem.stiffness()?,
            f: fem.gravity_load(&model, self.geometry.gravity),
            inertia,
            contact,
            u0: vec![0.0; n],
            v0,
            probe,
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
