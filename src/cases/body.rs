//! An elastic body dropped on the rigid plane `x_d = 0` (obstacle below, d the last coordinate):
//! - `block2d` / `block3d`: a box, the seed paper's 2D experiment (plane strain) and its 3D version
//!   (`shared/reference/block_drop.md`); no exact solution, the convergence reference is a run on
//!   a finer mesh and time step (see the report);
//! - `hertz3d` / `hertz2d`: a sphere / a disc (plane strain) touching the plane at t = 0, checked
//!   against Hertz theory ([`crate::exact::hertz`], `shared/reference/hertz_impact.md`);
//! - `disc2d`: GetFEM's demo disc falling under gravity;
//! - `roll2d`: GetFEM's disc on a plane of slope α (gravity tilted), released at rest with
//!   friction: it rolls when μ ≥ tan α / 3 ([`crate::exact::roll`]);
//! - `slide2d` / `slide3d`: a box resting on the plane under gravity, launched along the first
//!   axis (`tangential_velocity`), with Coulomb friction (`[contact] friction = μ`): its centre
//!   of mass against the rigid-body slide on the flat plane ([`crate::exact::slide`]; a `slope`
//!   is refused);
//! - `oblique3d`: hertz3d's sphere thrown at the plane at an incidence θ with friction: its
//!   tangential restitution and rebound spin against the rigid-body limits and Chung & Ooi's
//!   curve ([`crate::exact::oblique`]); `[oblique]` lists the report's incidences.
//!
//! The case holds only physics: material, geometry (or a Gmsh file), initial state, the obstacle;
//! [`Discretisation`] turns it into matrices. Isotropic linear elasticity, no Dirichlet condition.
//! Contact with the plane at the vertices of Γ_C: `B_N U = −u_d` and `g = x_d + lift + u_d ≥ 0`
//! at each vertex; frictionless unless `[contact] friction = μ > 0` (or `--friction μ`), which
//! adds the tangential rows of [`Discretisation::friction`]. Initial state: undeformed, uniform vertical
//! velocity; optional gravity.

use super::sweep::{Refinement, SweepSpec};
use super::{Case, Overrides, RunSpec, Size};
use crate::element::reference::{RefElement, Shape};
use crate::error::{positive, Error, Result};
use crate::exact::hertz::Hertz;
use crate::exact::slide::Slide;
use crate::fem::discretisation::{Discretisation, Initial};
use crate::fem::elasticity::Lame;
use crate::mesh::curved::RoundBody;
use crate::mesh::structured::box_mesh;
use crate::mesh::{ContactRule, Mesh, FACING};
use crate::problem::Problem;
use crate::space::Space;
use serde::Deserialize;
use std::path::PathBuf;
use std::sync::OnceLock;

/// `[material]`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
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
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// `box` (default), `disc` (2D) or `sphere` (3D); ignored when `[mesh] file` is given.
    #[serde(default = "default_shape")]
    pub shape: String,
    /// Box size (2 or 3 entries; `box` only), the body in `[0, size_k]`.
    #[serde(default)]
    pub size: Vec<f64>,
    /// Radius R (`disc`, `sphere`; with a file, the radius Hertz theory uses), the body centred
    /// at `(0, …, R)` so that it touches the plane at the origin.
    #[serde(default)]
    pub radius: Option<f64>,
    /// Initial vertical velocity (negative: towards the plane).
    pub velocity: f64,
    /// Initial velocity along the first axis, tangential to the plane (the slide cases).
    #[serde(default)]
    pub tangential_velocity: f64,
    /// Initial gap between Γ_C and the plane (≥ 0).
    #[serde(default)]
    pub lift: f64,
    /// Gravity acceleration g ≥ 0 (body force −ρ g e_d, or tilted by `slope`).
    #[serde(default)]
    pub gravity: f64,
    /// Slope α of the plane in radians, |α| < π/2 (the roll case): gravity is
    /// `g (sin α e_1 − cos α e_d)` in the plane's frame (default 0). Refused by the slides, whose
    /// rigid reference is the flat slide, and by Hertz impacts and pairs (no gravity, or none
    /// tilted); the blocks and disc2d take it (no reference).
    #[serde(default)]
    pub slope: f64,
}

/// `[mesh]`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// `quad` or `triangle` (2D), `hex` or `tet` (3D) for generated meshes.
    #[serde(default)]
    pub cells: String,
    /// Polynomial degree (1 or 2) for generated meshes.
    #[serde(default = "default_degree")]
    pub degree: usize,
    /// Box: cells along the first direction (the others in proportion to the size). Disc and
    /// sphere: cells along each edge of the O-grid's inner square/cube.
    #[serde(default)]
    pub elements: usize,
    /// Disc and sphere: grading ratio ≥ 1 towards the pole (largest over smallest spacing).
    #[serde(default = "default_grading")]
    pub grading: f64,
    /// A Gmsh mesh (MSH 4.1, ASCII or binary), relative to the case file's directory.
    #[serde(default)]
    pub file: Option<PathBuf>,
}

/// `[contact]`: which boundary faces form Γ_C.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Gmsh physical group of the contact faces (default `contact`).
    #[serde(default)]
    pub group: Option<String>,
    /// Generated meshes: faces whose outward normal has `n_d < −facing` (default 0.01).
    #[serde(default)]
    pub facing: Option<f64>,
    /// Coulomb friction coefficient μ ≥ 0 at the plane (default 0: frictionless).
    #[serde(default)]
    pub friction: Option<f64>,
}

/// `[oblique]`: the report's oblique-impact study, one run per incidence (`oblique3d`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObliqueSpec {
    /// Incidences θ in degrees from the normal (the full report), each in [0, 90).
    pub angles: Vec<f64>,
    /// The incidences of `report --quick`.
    pub quick_angles: Vec<f64>,
    /// Mesh and time step of the full report.
    pub level: Refinement,
    /// Mesh and time step of `report --quick`.
    pub quick_level: Refinement,
}

impl ObliqueSpec {
    /// The incidences (degrees) and the level of the report (`quick` or not).
    pub fn study(&self, quick: bool) -> (&[f64], Refinement) {
        if quick {
            (&self.quick_angles, self.quick_level)
        } else {
            (&self.angles, self.level)
        }
    }

    fn validate(&self) -> Result<()> {
        for &a in self.angles.iter().chain(&self.quick_angles) {
            if !(0.0..90.0).contains(&a) {
                return Err(Error::invalid("oblique.angles", a, "degrees in [0, 90)"));
            }
        }
        positive("oblique.level.dt", self.level.dt)?;
        positive("oblique.quick_level.dt", self.quick_level.dt)?;
        Ok(())
    }
}

/// `g` with its initial velocity turned to the incidence θ (degrees from the normal, towards
/// +e_1), its speed `V = |(velocity, tangential_velocity)|` kept.
fn incline(g: &mut Geometry, theta: f64) -> Result<()> {
    let speed = g.velocity.hypot(g.tangential_velocity);
    if !(0.0..90.0).contains(&theta) {
        return Err(Error::invalid("--incidence", theta, "degrees in [0, 90)"));
    }
    if speed == 0.0 {
        return Err(Error::invalid(
            "--incidence",
            theta,
            "turns the initial velocity, and this body starts at rest (geometry.velocity and \
             geometry.tangential_velocity are 0)",
        ));
    }
    let (s, c) = theta.to_radians().sin_cos();
    g.velocity = -speed * c;
    g.tangential_velocity = speed * s;
    Ok(())
}

fn default_shape() -> String {
    "box".into()
}
fn default_degree() -> usize {
    1
}
pub(super) fn default_grading() -> f64 {
    1.0
}

/// Case kinds of this module with their dimension.
pub const KINDS: &[(&str, usize)] = &[
    ("block2d", 2),
    ("block3d", 3),
    ("hertz2d", 2),
    ("hertz3d", 3),
    ("disc2d", 2),
    ("slide2d", 2),
    ("slide3d", 3),
    ("roll2d", 2),
    ("oblique3d", 3),
];

/// The whole case file of an elastic body.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// One of [`KINDS`].
    pub case: String,
    /// Units statement.
    pub units: String,
    /// Material.
    pub material: Material,
    /// Geometry and initial state.
    pub geometry: Geometry,
    /// Mesh.
    pub mesh: MeshSpec,
    /// Γ_C selection.
    #[serde(default)]
    pub contact: ContactSpec,
    /// Run defaults.
    pub run: RunSpec,
    /// Sweeps.
    #[serde(default)]
    pub sweep: Vec<SweepSpec>,
    /// Time histories for the report.
    #[serde(default)]
    pub history: Vec<super::sweep::HistorySpec>,
    /// The report's oblique-impact study (`oblique3d`).
    #[serde(default)]
    pub oblique: Option<ObliqueSpec>,
}

/// A validated body case.
#[derive(Debug, Clone)]
pub struct Body {
    kind: &'static str,
    /// Mesh, material and Γ_C.
    pub fem: Discretisation,
    /// The Hertz reference (`hertz2d`, `hertz3d`).
    pub hertz: Option<Hertz>,
    /// Geometry and initial state.
    pub geometry: Geometry,
    /// Coulomb friction coefficient μ at the plane (0: frictionless).
    pub friction: f64,
    /// The rigid-body slide of the centre of mass (`slide2d`, `slide3d`).
    pub slide: Option<Slide>,
    run: RunSpec,
    sweeps: Vec<SweepSpec>,
    /// Time histories for the report.
    pub history: Vec<super::sweep::HistorySpec>,
    /// The report's oblique-impact study.
    pub oblique: Option<ObliqueStudy>,
    /// [`Body::centre`], computed on first use (a mass assembly; the report's estimates and
    /// figures ask a case for it several times).
    centre: OnceLock<(Vec<(usize, f64)>, f64)>,
}

/// The oblique-impact study of an `oblique3d` case: `[oblique]` with the material's ν and μ.
#[derive(Debug, Clone)]
pub struct ObliqueStudy {
    /// `[oblique]`.
    pub spec: ObliqueSpec,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
}

/// Estimated bytes of the assembly: the triplets of one global matrix (24 B per entry of every
/// element matrix), then K, M and the step matrix compressed (16 B per stored entry, a node
/// coupling to the (2p + 1)^d nodes around it).
fn assembly_bytes(element: &RefElement, cells: f64, nodes: f64) -> f64 {
    let (d, p) = (element.dim, element.degree);
    let local = (element.n_nodes() * d) as f64;
    let coupled = ((2 * p + 1) as f64).powi(d as i32) * (d * d) as f64;
    cells * local * local * 24.0 + 3.0 * nodes * coupled * 16.0
}

/// The largest ratio of a generated box cell's edges (geometry.size against mesh.elements).
pub const MAX_ASPECT: f64 = 1e6;

/// Cells of a box along each direction: `n` along the first, the others in proportion to the
/// size (at least 1).
fn box_cells(g: &Geometry, dim: usize, n: usize) -> [usize; 3] {
    let mut cells = [1; 3];
    for (c, s) in cells.iter_mut().zip(&g.size).take(dim) {
        *c = ((n as f64 * s / g.size[0]).round() as usize).max(1);
    }
    cells
}

/// Nodes of the generated mesh with `n` cells per edge and degree `degree`: a box's
/// `Π (p c_k + 1)`, a disc's or sphere's O-grid `(1 + d) (p n + 1)^d` (an upper bound).
pub(super) fn generated_nodes(g: &Geometry, dim: usize, n: usize, degree: usize) -> f64 {
    if g.shape == "box" {
        let cells = box_cells(g, dim, n);
        cells[..dim]
            .iter()
            .map(|&c| degree as f64 * c as f64 + 1.0)
            .product()
    } else {
        (degree as f64 * n as f64 + 1.0).powi(dim as i32) * (1.0 + dim as f64)
    }
}

/// The size of a run of `spec` with the overrides `o`, before anything is built (for the
/// scheduling of a study): a generated mesh's node count, a Gmsh file's about one node per
/// [`GMSH_BYTES_PER_NODE`] of its length.
pub fn size(spec: &BodySpec, o: &Overrides) -> Size {
    let dim = KINDS.iter().find(|k| k.0 == spec.case).map_or(3, |k| k.1);
    mesh_size((&spec.geometry, &spec.mesh), dim, o, 1.0)
}

/// The [`Size`] of `bodies` generated copies of a body's mesh in dimension `dim`, or of the Gmsh
/// file given (by `--mesh` or `[mesh] file`), whose nodes are estimated from its length
/// ([`GMSH_BYTES_PER_NODE`]) whatever it holds.
pub fn mesh_size(
    (geometry, mesh): (&Geometry, &MeshSpec),
    dim: usize,
    o: &Overrides,
    bodies: f64,
) -> Size {
    let file = o.mesh.as_ref().or(mesh.file.as_ref());
    let nodes = match file {
        Some(file) => std::fs::metadata(file).map_or(0.0, |m| m.len() as f64) / GMSH_BYTES_PER_NODE,
        None => {
            bodies
                * generated_nodes(
                    geometry,
                    dim,
                    o.elements.unwrap_or(mesh.elements),
                    o.degree.unwrap_or(mesh.degree),
                )
        }
    };
    Size {
        dim,
        dofs: nodes * dim as f64,
        exact: (file.is_none() && geometry.shape == "box" && bodies == 1.0)
            .then_some(nodes as usize * dim),
    }
}

/// Bytes of a Gmsh file per node, roughly (its node and cell lines), for [`size`].
pub(super) const GMSH_BYTES_PER_NODE: f64 = 100.0;

/// Cells per structured cell (simplices split each box cell).
fn per_cell(element: &RefElement) -> f64 {
    match (element.shape, element.dim) {
        (Shape::Tensor, _) => 1.0,
        (_, 2) => 2.0,
        _ => 6.0,
    }
}

pub(super) fn check_material(m: &Material) -> Result<()> {
    positive("material.young", m.young)?;
    positive("material.density", m.density)?;
    if !(m.poisson.is_finite() && m.poisson > -1.0 && m.poisson < 0.5) {
        return Err(Error::invalid(
            "material.poisson",
            m.poisson,
            "must be in (−1, ½)",
        ));
    }
    Ok(())
}

/// The reference element of a generated mesh (`[mesh] cells`, degree).
fn generated_element(cells: &str, dim: usize, degree: usize) -> Result<RefElement> {
    let shape = match (cells, dim) {
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
    if !(1..=2).contains(&degree) {
        return Err(Error::invalid("mesh.degree", degree, "must be 1 or 2"));
    }
    Ok(RefElement { shape, dim, degree })
}

/// Refuses the overrides of a generated mesh (`--elements`, `--cells`, `--degree`) for a mesh
/// read from `file`, which fixes the cells, their shape and degree.
pub(super) fn refuse_generated(o: &Overrides, file: &str) -> Result<()> {
    let generated = [
        ("--elements", o.elements.map(|n| n.to_string())),
        ("--cells", o.cells.clone()),
        ("--degree", o.degree.map(|n| n.to_string())),
    ];
    match generated.into_iter().find_map(|(f, v)| Some((f, v?))) {
        Some((flag, value)) => Err(Error::invalid(
            flag,
            value,
            &format!("applies to a generated mesh, not to the mesh file {file}"),
        )),
        None => Ok(()),
    }
}

/// Refuses the fields of a case file that only a generated mesh uses, beside its own `[mesh]
/// file` (which fixes the cells, their shape, degree and Γ_C): `mesh.cells`, `mesh.degree`,
/// `mesh.elements`, `mesh.grading`, `contact.facing`, `geometry.size`; and `geometry.shape` and
/// `geometry.radius` unless the case reads them from the file's body too (the Hertz reference's
/// radius of `hertz2d`/`hertz3d`, the shape `oblique3d` checks, the rolling spin of a round body
/// with friction). `kind` is the case, `friction` its μ.
fn refuse_beside_file(spec: &BodySpec, kind: &str, friction: f64) -> Result<()> {
    let Some(file) = &spec.mesh.file else {
        return Ok(());
    };
    let (g, m) = (&spec.geometry, &spec.mesh);
    let hertz = kind.starts_with("hertz");
    let shape_read = hertz || kind == "oblique3d" || friction > 0.0;
    let radius_read = hertz || (friction > 0.0 && g.shape != "box");
    let set = [
        ("mesh.cells", (!m.cells.is_empty()).then(|| m.cells.clone())),
        (
            "mesh.degree",
            (m.degree != default_degree()).then(|| m.degree.to_string()),
        ),
        (
            "mesh.elements",
            (m.elements != 0).then(|| m.elements.to_string()),
        ),
        (
            "mesh.grading",
            (m.grading != default_grading()).then(|| m.grading.to_string()),
        ),
        ("contact.facing", spec.contact.facing.map(|t| t.to_string())),
        (
            "geometry.size",
            (!g.size.is_empty()).then(|| format!("{:?}", g.size)),
        ),
        (
            "geometry.shape",
            (!shape_read && g.shape != default_shape()).then(|| g.shape.clone()),
        ),
        (
            "geometry.radius",
            g.radius.filter(|_| !radius_read).map(|r| r.to_string()),
        ),
    ];
    match set.into_iter().find_map(|(f, v)| Some((f, v?))) {
        Some((field, value)) => Err(Error::invalid(
            field,
            value,
            &format!(
                "applies to a generated mesh, and this case's mesh is the file {} (mesh.file): \
                 remove the field, or mesh.file",
                file.display()
            ),
        )),
        None => Ok(()),
    }
}

/// Relative tolerance of [`hertz_body`]: a mesh of flat faces inscribed in the circle or sphere
/// misses its extent and measure by O(h²) (0.5 % at 16 faces a half-circle).
const HERTZ_BODY_TOLERANCE: f64 = 0.05;

/// Refuses a mesh file that is not the disc or ball of `radius` the Hertz reference is of: its
/// extent along every axis `2R` and its area `πR²` (volume `4πR³/3`), within
/// [`HERTZ_BODY_TOLERANCE`]. A disc of radius 2 was compared with the radius-1 reference.
fn hertz_body(mesh: &Mesh, radius: f64, dim: usize) -> Result<()> {
    let span = |k: usize| {
        let (lo, hi) = mesh
            .nodes
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x[k]), b.max(x[k]))
            });
        hi - lo
    };
    let spans: Vec<f64> = (0..dim).map(span).collect();
    let ball = if dim == 2 {
        std::f64::consts::PI * radius * radius
    } else {
        4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
    };
    let measure = mesh.volume();
    let off = |x: f64, want: f64| (x - want).abs() > HERTZ_BODY_TOLERANCE * want;
    if spans.iter().any(|&w| off(w, 2.0 * radius)) || off(measure, ball) {
        return Err(Error::Mesh {
            origin: mesh.origin.clone(),
            message: format!(
                "spans {spans:.4?} with {} {measure:.4}: not the {} of geometry.radius = {} \
                 that the Hertz reference is of (spans {:.4}, {} {ball:.4}, within {} %); set \
                 geometry.radius to the mesh's",
                if dim == 2 { "area" } else { "volume" },
                if dim == 2 { "disc" } else { "sphere" },
                crate::error::short(radius),
                2.0 * radius,
                if dim == 2 { "area" } else { "volume" },
                100.0 * HERTZ_BODY_TOLERANCE
            ),
        });
    }
    Ok(())
}

/// Fields the generated shape would not use, refused by name: a box's radius or grading, a
/// disc's or sphere's size.
fn unused_by_shape(g: &Geometry, m: &MeshSpec) -> Result<()> {
    let boxes_only = "sizes a box; a disc or sphere is sized by geometry.radius";
    match (g.shape.as_str(), g.radius) {
        ("box", Some(r)) => Err(Error::invalid(
            "geometry.radius",
            r,
            "a box (geometry.shape, default \"box\") has no radius: geometry.size gives it",
        )),
        ("box", None) if m.grading != default_grading() => Err(Error::invalid(
            "mesh.grading",
            m.grading,
            "grades a disc's or sphere's O-grid towards its pole; a box's cells are uniform",
        )),
        ("disc" | "sphere", _) if !g.size.is_empty() => {
            Err(Error::invalid("geometry.size", &g.size, boxes_only))
        }
        _ => Ok(()),
    }
}

/// The mesh a body's geometry, mesh and contact tables describe (a file when given, else the
/// generated shape), the rule that selects Γ_C on it and, for a generated disc or sphere, its
/// parameters (which explain a failed check of the mesh, [`RoundBody::explain`]).
pub(super) fn build_mesh(
    (g, spec_mesh, contact): (&Geometry, &MeshSpec, &ContactSpec),
    o: &Overrides,
    kind: &str,
    dim: usize,
) -> Result<(Mesh, ContactRule, Option<RoundBody>)> {
    let facing = match contact.facing {
        Some(t) => crate::error::in_range("contact.facing", t, 0.0, 1.0)?,
        None => FACING,
    };
    if let Some(file) = o.mesh.as_ref().or(spec_mesh.file.as_ref()) {
        refuse_generated(o, &file.display().to_string())?;
        let group = contact.group.as_deref().unwrap_or("contact");
        let mesh = crate::mesh::gmsh::read(file, dim, group)?;
        return Ok((mesh, ContactRule::Tagged, None));
    }
    if let Some(group) = &contact.group {
        return Err(Error::invalid(
            "contact.group",
            group,
            "names a physical group of a Gmsh mesh (--mesh or mesh.file); a generated mesh \
             takes Γ_C by contact.facing",
        ));
    }
    let degree = o.degree.unwrap_or(spec_mesh.degree);
    let cells = o.cells.as_deref().unwrap_or(&spec_mesh.cells);
    let element = generated_element(cells, dim, degree)?;
    let n = o.elements.unwrap_or(spec_mesh.elements);
    if n == 0 {
        return Err(Error::invalid("mesh.elements", n, "must be ≥ 1"));
    }
    unused_by_shape(g, spec_mesh)?;
    let mut round = None;
    let mesh = match g.shape.as_str() {
        "box" => {
            if g.size.len() != dim {
                return Err(Error::invalid(
                    "geometry.size",
                    &g.size,
                    &format!(
                        "a box (geometry.shape, default \"box\") needs {dim} entries for {kind}"
                    ),
                ));
            }
            for s in &g.size {
                crate::error::length("geometry.size", *s)?;
            }
            let cells = box_cells(g, dim, n);
            let h: Vec<f64> = (0..dim).map(|k| g.size[k] / cells[k] as f64).collect();
            let aspect = h.iter().fold(0.0_f64, |a, &x| a.max(x))
                / h.iter().fold(f64::INFINITY, |a, &x| a.min(x));
            if aspect > MAX_ASPECT {
                return Err(Error::invalid(
                    "geometry.size",
                    &g.size,
                    &format!(
                        "its cells would be {aspect:.1e} times longer one way than another (at \
                         most {MAX_ASPECT:e}): the stiffness would be singular to round-off"
                    ),
                ));
            }
            let mut size = [0.0; 3];
            size[..dim].copy_from_slice(&g.size[..dim]);
            let count = cells[..dim].iter().map(|&c| c as f64).product::<f64>();
            let bytes = assembly_bytes(
                &element,
                count * per_cell(&element),
                generated_nodes(g, dim, n, degree),
            );
            crate::util::check_memory("mesh.elements", n, bytes)?;
            box_mesh(element, cells, size)?
        }
        "disc" | "sphere" => {
            let want = if dim == 2 { "disc" } else { "sphere" };
            if g.shape != want {
                return Err(Error::invalid(
                    "geometry.shape",
                    &g.shape,
                    &format!("{kind} needs `{want}`"),
                ));
            }
            let radius = g.radius.ok_or_else(|| {
                Error::invalid(
                    "geometry.radius",
                    "missing",
                    "a disc or sphere needs a radius",
                )
            })?;
            crate::error::length("geometry.radius", radius)?;
            let cells = (n as f64).powi(dim as i32) * (1.0 + dim as f64) * per_cell(&element);
            let nodes = generated_nodes(g, dim, n, degree);
            crate::util::check_memory("mesh.elements", n, assembly_bytes(&element, cells, nodes))?;
            let body = RoundBody {
                element,
                n,
                grading: spec_mesh.grading,
            };
            round = Some(body);
            body.mesh(radius)?
        }
        other => {
            return Err(Error::invalid(
                "geometry.shape",
                other,
                "box, disc (2D) or sphere (3D)",
            ))
        }
    };
    Ok((mesh, ContactRule::Facing(facing), round))
}

impl Body {
    /// Validates the spec, applies the overrides and builds the mesh.
    /// A Hertz impact must touch the plane before `t_end` ([`super::check_touch`]; a part of
    /// a pair, built by [`Body::with_mesh`], is checked as the pair).
    pub fn from_spec(spec: BodySpec, o: &Overrides) -> Result<Self> {
        let body = Self::with_mesh(spec, o, None)?;
        if let Some(h) = &body.hertz {
            super::check_touch(body.geometry.lift, body.gap(), h.speed, body.run.t_end)?;
        }
        Ok(body)
    }

    /// As [`Body::from_spec`], on `mesh` (read by the caller, Γ_C tagged) when given.
    pub fn with_mesh(spec: BodySpec, o: &Overrides, mesh: Option<Mesh>) -> Result<Self> {
        let Some(&(kind, dim)) = KINDS.iter().find(|k| k.0 == spec.case) else {
            return Err(Error::UnknownName {
                kind: "case",
                name: spec.case.clone(),
                known: KINDS.iter().map(|k| k.0).collect::<Vec<_>>().join(", "),
            });
        };
        let m = &spec.material;
        check_material(m)?;
        let mut spec = spec;
        if let Some(theta) = o.incidence {
            if kind.starts_with("slide") {
                return Err(Error::invalid(
                    "--incidence",
                    theta,
                    "a slide starts on the plane, moving along it: it has no incidence",
                ));
            }
            incline(&mut spec.geometry, theta)?;
        }
        if let Some(oblique) = &spec.oblique {
            if kind != "oblique3d" {
                return Err(Error::invalid(
                    "oblique",
                    kind,
                    "the oblique-impact study is for oblique3d",
                ));
            }
            oblique.validate()?;
        }
        let (m, g) = (&spec.material, &spec.geometry);
        crate::error::finite("geometry.velocity", g.velocity)?;
        crate::error::finite("geometry.tangential_velocity", g.tangential_velocity)?;
        let friction = match o.friction.or(spec.contact.friction) {
            Some(mu) => crate::error::non_negative("contact.friction", mu)?,
            None => 0.0,
        };
        crate::error::non_negative("geometry.lift", g.lift)?;
        crate::error::non_negative("geometry.gravity", g.gravity)?;
        crate::error::in_range(
            "geometry.slope",
            g.slope,
            -0.5 * std::f64::consts::PI,
            0.5 * std::f64::consts::PI,
        )?;
        if g.slope != 0.0 && g.gravity == 0.0 {
            return Err(Error::invalid(
                "geometry.slope",
                g.slope,
                "tilts gravity, and geometry.gravity = 0: it would be ignored",
            ));
        }
        if kind.starts_with("hertz") && g.shape == "box" {
            return Err(Error::invalid(
                "geometry.shape",
                &g.shape,
                "Hertz theory is of a curved body: a disc (2D) or a sphere (3D), of \
                 geometry.radius",
            ));
        }
        refuse_beside_file(&spec, kind, friction)?;
        let (mesh, rule, round) = match mesh {
            Some(mesh) => {
                refuse_generated(o, &mesh.origin)?;
                (mesh, ContactRule::Tagged, None)
            }
            None => build_mesh((g, &spec.mesh, &spec.contact), o, kind, dim)?,
        };
        let hertz = if kind.starts_with("hertz") {
            let radius = g.radius.ok_or_else(|| {
                Error::invalid(
                    "geometry.radius",
                    "missing",
                    "Hertz theory needs the radius",
                )
            })?;
            positive("geometry.radius", radius)?;
            if matches!(rule, ContactRule::Tagged) {
                hertz_body(&mesh, radius, dim)?;
            }
            if g.velocity >= 0.0 {
                return Err(Error::invalid(
                    "geometry.velocity",
                    g.velocity,
                    "a Hertz impact needs a velocity towards the plane (< 0)",
                ));
            }
            if g.gravity != 0.0 {
                return Err(Error::invalid(
                    "geometry.gravity",
                    g.gravity,
                    "a Hertz impact has no gravity (= 0): the body flies at its velocity",
                ));
            }
            Some(Hertz::new(
                dim,
                radius,
                m.density,
                m.young,
                m.poisson,
                -g.velocity,
            ))
        } else {
            None
        };
        if hertz.is_some() && !spec.history.is_empty() {
            return Err(Error::invalid(
                "history",
                spec.history.len(),
                "a Hertz impact's report draws its impact figures: [[history]] tables would be \
                 ignored",
            ));
        }
        if kind == "oblique3d" && (g.shape != "sphere" || g.velocity >= 0.0 || g.gravity != 0.0) {
            return Err(Error::invalid(
                "geometry.velocity",
                g.velocity,
                "an oblique impact is a sphere thrown at the plane (velocity < 0), without gravity",
            ));
        }
        let slide = if kind.starts_with("slide") {
            let normal = [("geometry.velocity", g.velocity), ("geometry.lift", g.lift)];
            if let Some((field, value)) = normal.into_iter().find(|f| f.1 != 0.0) {
                return Err(Error::invalid(
                    field,
                    value,
                    "a slide starts on the plane at rest along its normal (velocity = 0, lift = 0)",
                ));
            }
            if g.slope != 0.0 {
                return Err(Error::invalid(
                    "geometry.slope",
                    g.slope,
                    "the rigid slide this case is measured against (slide_velocity_err, \
                     stop_time, stop_distance) is on a flat plane, decelerating at μ g: on a \
                     slope it would be wrong (roll2d is the case on a slope)",
                ));
            }
            Some(Slide::new(g.tangential_velocity, g.gravity, friction)?)
        } else {
            None
        };
        let mut run = spec.run;
        o.apply(&mut run);
        run.validate()?;
        // The mesh checked first: a degenerate or overflowing mesh is named as such, not
        // blamed on the density through its h.
        let fem = Discretisation::new(
            mesh,
            Lame::from_young_poisson(m.young, m.poisson),
            m.density,
            rule,
        )
        .map_err(|e| match round {
            Some(body) => body.explain(e),
            None => e,
        })?;
        if rule == ContactRule::Tagged {
            fem.check_tagged_contact()?;
        }
        super::check_time_scale(
            ("material.density", m.density),
            ("material.young", m.young),
            fem.mesh.h,
            run.dt,
        )?;
        Ok(Self {
            kind,
            fem,
            hertz,
            geometry: spec.geometry,
            friction,
            slide,
            run,
            sweeps: spec.sweep,
            history: spec.history,
            oblique: spec.oblique.map(|spec| ObliqueStudy {
                spec,
                mu: friction,
                poisson: m.poisson,
            }),
            centre: OnceLock::new(),
        })
    }
}

impl Body {
    /// The initial gap to the plane, `g₀ = min_i x_{i,d} + lift` (0 for a generated body
    /// released touching it; a Gmsh body may be placed above it).
    pub fn gap(&self) -> f64 {
        let d = self.fem.dim();
        let lowest = self
            .fem
            .mesh
            .nodes
            .iter()
            .map(|x| x[d - 1])
            .fold(f64::INFINITY, f64::min);
        lowest + self.geometry.lift
    }

    /// The centre of mass's weights `(dof, w = ∫ρ φ_i / m)` on the components along e_d (its
    /// displacement towards the plane is `−Σ w U_dof`) and the discrete mass `m = Σ ∫ρ φ_i`.
    pub fn centre(&self) -> (Vec<(usize, f64)>, f64) {
        let compute = || {
            let fem = &self.fem;
            let d = fem.dim();
            let w = fem.nodal_masses(&fem.mass_model());
            let m: f64 = w.iter().sum();
            let centre = w
                .iter()
                .enumerate()
                .filter(|(_, &x)| x != 0.0)
                .map(|(i, x)| (i * d + d - 1, x / m))
                .collect();
            (centre, m)
        };
        self.centre.get_or_init(compute).clone()
    }
}

impl Case for Body {
    fn kind(&self) -> &'static str {
        self.kind
    }

    fn h(&self) -> f64 {
        self.fem.mesh.h
    }

    fn element(&self) -> Option<(&'static str, usize)> {
        let e = self.fem.mesh.element;
        Some((e.cells(), e.degree))
    }

    fn problem(&self, space: &dyn Space) -> Result<Problem> {
        let (fem, g) = (&self.fem, &self.geometry);
        let d = fem.dim();
        let initial = Initial {
            displacement: vec![0.0; fem.n_dofs()],
            velocity: fem.interpolate(|_| {
                std::array::from_fn(|k| match k {
                    k if k == d - 1 => g.velocity,
                    0 => g.tangential_velocity,
                    _ => 0.0,
                })
            }),
            gravity: Some(g.gravity * g.slope.cos()),
            lift: g.lift,
        };
        let mut problem = fem.problem(|m| space.inertia(m), &initial)?;
        if g.slope != 0.0 {
            // The component of gravity along the slope, on the first component.
            let along = fem.body_force(&fem.mass_model(), 0, g.gravity * g.slope.sin());
            crate::linalg::axpy(&mut problem.f, 1.0, &along);
        }
        if self.friction > 0.0 {
            problem.contact.friction = Some(fem.friction(self.friction)?);
        }
        Ok(problem)
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

    fn discretisation(&self) -> Option<&Discretisation> {
        Some(&self.fem)
    }

    fn slide(&self) -> Option<Slide> {
        self.slide
    }

    fn spin(&self) -> Option<super::Spin> {
        let (fem, g) = (&self.fem, &self.geometry);
        if self.friction == 0.0 || g.shape == "box" {
            return None;
        }
        let radius = g.radius?;
        let d = fem.dim();
        let unit = |k: usize| std::array::from_fn(|c| if c == k { 1.0 } else { 0.0 });
        Some(super::Spin {
            normal: fem.interpolate(|_| unit(d - 1)),
            rotation: fem.interpolate(|x| {
                std::array::from_fn(|c| match c {
                    0 => x[d - 1] - radius,
                    c if c == d - 1 => -x[0],
                    _ => 0.0,
                })
            }),
            radius,
        })
    }

    fn oblique(&self) -> Option<&ObliqueStudy> {
        self.oblique.as_ref()
    }

    fn roll(&self) -> Option<crate::exact::roll::Roll> {
        let g = &self.geometry;
        (self.kind == "roll2d").then_some(crate::exact::roll::Roll {
            gravity: g.gravity,
            slope: g.slope,
            mu: self.friction,
        })
    }

    fn impact(&self) -> Option<super::Impact> {
        let hertz = self.hertz?;
        let fem = &self.fem;
        let (centre, mass) = self.centre();
        Some(super::Impact {
            hertz,
            centre,
            mass,
            positions: fem
                .contact_vertices
                .iter()
                .map(|&(i, _)| fem.mesh.nodes[i])
                .collect(),
            gap: self.gap(),
        })
    }
}
