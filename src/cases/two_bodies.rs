//! `two_discs` / `two_spheres` / `two_blocks2d` / `two_blocks3d`: two free elastic bodies meeting
//! along the line of impact e_d (issue 24 §2; `notes/papers/two_body_contact.md`), the
//! curved-body impact of [`super::body`] with the rigid plane replaced by a second body.
//!
//! Body 1 (the slave) is the body of a `hertz2d`/`hertz3d` case file: generated touching
//! `x_d = 0` from above (or lifted by `geometry.lift`), moving at `geometry.velocity < 0`. Body 2
//! (the master) is the same body, or the one `[master]` describes (its own material, geometry,
//! mesh, contact; a `box` is centred under body 1), generated the same way and turned upside
//! down by a rotation of π (2D: `(x, y) ↦ (−x, −y)`; 3D: `(x, y, z) ↦ (x, −y, −z)`, which keeps
//! the cells' orientation); it moves towards body 1 at `|velocity|` of its own table (default:
//! body 1's, the equal and opposite velocities ±v/2 of a pair in its centre-of-mass frame).
//!
//! **Gmsh input** (`[mesh] file`, or `--mesh` on `two_discs.toml` / `two_spheres.toml`): one
//! MSH 4.1 file holds both bodies where they are, the line of impact the x_d axis: physical
//! groups `body1` (the slave's cells, above), `body2` (the master's, below), `contact1` and
//! `contact2` (the faces of each body's potential contact zone Γ_C); the meshes need not match
//! across the interface. Geometry and material stay the case file's (the radius is Hertz's);
//! each body alone against the plane is its mesh moved onto `x_d = 0` (body 2 turned). Example
//! meshes with their `.geo`: `cases/meshes/two_discs.*`, `cases/meshes/two_spheres.*`.
//!
//! The slave's Γ_C vertices are paired node-to-segment on the master's Γ_C faces
//! ([`crate::fem::bodies`]); no external force, so the momentum `(M̃ 1_d)ᵀ V` is an invariant.
//!
//! **Friction and weight** (issue 25 §1): `[contact] friction = μ` of body 1 (or `--friction`)
//! is Coulomb's law on the interface rows ([`Bodies::friction`]); each body may carry its own
//! weight (`geometry.gravity`, along −e_d) and slide along e_1 (`geometry.tangential_velocity`,
//! in the global frame for both bodies; body 2's are 0 unless `[master.geometry]` gives them).
//! `[master] plane = true` sets body 2 on a frictionless rigid plane (its faces facing −e_d,
//! appended as frictionless points of the law). `cases/slide_on_block2d.toml` (and `3d`) slides
//! a block on another resting on the plane: the rigid-body answer is
//! [`crate::exact::slide::SlideOnBlock`].
//!
//! **Hertz reference** (Johnson 1985, §4.2): two curved bodies in contact are Hertz's body of
//! relative curvature `1/R* = 1/R₁ + 1/R₂` (a box: 0), modulus `1/E* = Σ (1 − ν_i²)/E_i` and
//! reduced mass `m* = m₁ m₂ / (m₁ + m₂)` at the relative speed `v = |v₁| + |v₂|`; for two equal
//! bodies `R* = R/2`, `E* = E₁*/2`, `m* = m/2`. In 2D the check is the pressure profile at peak
//! force (half-width `b = √(4 P R* / (π E*))`), as for `hertz2d`. Each body alone against the
//! plane is a `hertz2d`/`hertz3d` (or `block2d`/`block3d`) case ([`Case::bodies`]): the
//! finite-body reference of the pair adds their compliances ([`crate::study::finite_body`]).

use super::body::{Body, BodySpec, ContactSpec, Geometry, Material, MeshSpec};
use super::sweep::{HistorySpec, SweepSpec};
use super::{Case, Impact, Overrides, RunSpec, Size};
use crate::error::{Error, Result};
use crate::exact::hertz::Hertz;
use crate::fem::bodies::Bodies;
use crate::fem::discretisation::{Discretisation, Initial};
use crate::fem::mass_model::MassModel;
use crate::mesh::Mesh;
use crate::problem::Problem;
use crate::space::Space;
use serde::Deserialize;

/// The Gmsh physical groups of the bodies' cells: body 1 (the slave), body 2 (the master).
pub const BODY_GROUPS: [&str; 2] = ["body1", "body2"];
/// The Gmsh physical groups of the bodies' potential contact zones Γ_C (faces).
pub const CONTACT_GROUPS: [&str; 2] = ["contact1", "contact2"];

/// Case kinds of this module with their dimension.
pub const KINDS: &[(&str, usize)] = &[
    ("two_discs", 2),
    ("two_spheres", 3),
    ("two_blocks2d", 2),
    ("two_blocks3d", 3),
];

/// Body 2's cells `e2 n / e1` (rounded, at least 1) when `--elements n` replaces body 1's
/// `e1`: slide_on_block3d's 4 and 6 stay 4 and 6 under `--elements 4`, and become 8 and 12
/// under `--elements 8`.
fn proportional(n: usize, e1: usize, e2: usize) -> usize {
    if e1 == 0 || e2 == 0 {
        return n; // a count left to its default: no proportion to keep
    }
    ((n as f64 * e2 as f64 / e1 as f64).round() as usize).max(1)
}

/// The estimated [`Size`] of a pair, for the scheduler: twice body 1's generated mesh (body 2
/// is its image unless `[master]` gives another, which this estimate ignores), or the Gmsh
/// file's length (both bodies).
pub fn size(spec: &TwoBodiesSpec, o: &Overrides) -> Size {
    let dim = KINDS.iter().find(|k| k.0 == spec.case).map_or(3, |k| k.1);
    super::body::mesh_size((&spec.geometry, &spec.mesh), dim, o, 2.0)
}

/// `[master]`: body 2 where it differs from body 1 (each table in full, as body 1's).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MasterSpec {
    /// Its material (default: body 1's).
    #[serde(default)]
    pub material: Option<Material>,
    /// Its shape and velocity towards body 1 (negative; default: body 1's).
    #[serde(default)]
    pub geometry: Option<Geometry>,
    /// Its mesh (default: body 1's).
    #[serde(default)]
    pub mesh: Option<MeshSpec>,
    /// Its Γ_C (default: body 1's rule).
    #[serde(default)]
    pub contact: Option<ContactSpec>,
    /// Whether it rests on a frictionless rigid plane under it (its faces facing −e_d, nodal
    /// rows beside the interface's; default false: it flies free).
    #[serde(default)]
    pub plane: bool,
}

/// The whole case file of two bodies.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TwoBodiesSpec {
    /// One of [`KINDS`].
    pub case: String,
    /// Units statement.
    pub units: String,
    /// Body 1's material (and body 2's unless `[master]` gives one).
    pub material: Material,
    /// Body 1's shape, velocity towards body 2 (< 0) and gap (`lift`).
    pub geometry: Geometry,
    /// Body 1's mesh.
    pub mesh: MeshSpec,
    /// Body 1's Γ_C.
    #[serde(default)]
    pub contact: ContactSpec,
    /// Body 2 where it differs.
    #[serde(default)]
    pub master: MasterSpec,
    /// Run defaults.
    pub run: RunSpec,
    /// Sweeps.
    #[serde(default)]
    pub sweep: Vec<SweepSpec>,
    /// Time histories for the report.
    #[serde(default)]
    pub history: Vec<HistorySpec>,
}

/// A validated two-body case.
#[derive(Debug, Clone)]
pub struct TwoBodies {
    kind: &'static str,
    /// Each body alone against the rigid plane (its own frame, its own Hertz reference).
    pub parts: [Body; 2],
    /// Body 2 is body 1 (the same material, geometry, mesh and Γ_C: its image turned over), so
    /// that alone against the plane it is body 1's case.
    twins: bool,
    /// Body 1 (slave, above) and body 2 (master, below, turned) in the global frame.
    pub bodies: Bodies,
    /// The pair's impact against Hertz (curved body 1), built once.
    impact: Option<Impact>,
    /// Body 2 rests on a frictionless rigid plane.
    plane: bool,
    run: RunSpec,
    sweeps: Vec<SweepSpec>,
    history: Vec<HistorySpec>,
}

/// `(x, y) ↦ (−x, −y)` (2D) or `(x, y, z) ↦ (x, −y, −z)` (3D): the rotation by π that turns a
/// body resting on `x_d = 0` from above into one below it.
fn turn(x: [f64; 3], dim: usize) -> [f64; 3] {
    if dim == 2 {
        [-x[0], -x[1], x[2]]
    } else {
        [x[0], -x[1], -x[2]]
    }
}

/// Body `fem` moved rigidly: each node (and Γ_C normal) through `map`, then the nodes shifted
/// by `shift`.
fn moved(
    mut fem: Discretisation,
    map: impl Fn([f64; 3]) -> [f64; 3],
    shift: [f64; 3],
) -> Discretisation {
    for x in &mut fem.mesh.nodes {
        let y = map(*x);
        *x = std::array::from_fn(|k| y[k] + shift[k]);
    }
    for f in &mut fem.contact_faces {
        f.normal = map(f.normal);
    }
    fem
}

/// The two bodies of the Gmsh file of the case (`mesh.file` or `--mesh`), if any: the cells of
/// the physical groups `body1` (the slave) and `body2` (the master) with Γ_C the groups
/// `contact1` and `contact2`, and the shifts that put each on `x_d = 0` in its own frame (body
/// 1: `x − b₁ e_d`, b₁ its lowest x_d; body 2, turned: `turn(x − t₂ e_d)`, t₂ its highest).
#[allow(clippy::type_complexity)]
fn gmsh_bodies(
    spec: &TwoBodiesSpec,
    o: &Overrides,
    dim: usize,
) -> Result<Option<([Mesh; 2], [[f64; 3]; 2])>> {
    let m = &spec.master;
    if m.mesh.as_ref().is_some_and(|m| m.file.is_some()) {
        return Err(Error::invalid(
            "master.mesh.file",
            "a Gmsh file",
            "both bodies come from the one file of `mesh.file` (or --mesh), physical groups \
             body1, body2, contact1, contact2",
        ));
    }
    let Some(file) = o.mesh.as_ref().or(spec.mesh.file.as_ref()) else {
        return Ok(None);
    };
    // The file gives body 2's mesh: a [master.mesh] would be ignored ([master.geometry] is not:
    // its velocity, gravity and radius are body 2's).
    if m.mesh.is_some() {
        return Err(Error::invalid(
            "master.mesh",
            "a mesh of body 2",
            &format!(
                "the Gmsh file {} gives both bodies' meshes (groups body1, body2): this table \
                 would be ignored",
                file.display()
            ),
        ));
    }
    let groups = [Some(&spec.contact), m.contact.as_ref()]
        .into_iter()
        .flatten()
        .find_map(|c| c.group.as_ref());
    if let Some(group) = groups {
        return Err(Error::invalid(
            "contact.group",
            group,
            "a two-body Gmsh file names its groups body1, body2, contact1 (the slave's Γ_C), \
             contact2 (the master's)",
        ));
    }
    let meshes = crate::mesh::gmsh::read_bodies(
        file,
        dim,
        &[
            (BODY_GROUPS[0], CONTACT_GROUPS[0]),
            (BODY_GROUPS[1], CONTACT_GROUPS[1]),
        ],
    )?;
    let extents = [0, 1].map(|b| meshes[b].extent(dim - 1));
    check_placement(file, dim, extents)?;
    let shape2 = m
        .geometry
        .as_ref()
        .map_or(&spec.geometry.shape, |g| &g.shape);
    if spec.geometry.shape != "box" && shape2 != "box" {
        check_alignment(file, dim, &meshes)?;
    }
    let along = |z: f64| std::array::from_fn(|k| if k == dim - 1 { z } else { 0.0 });
    let shifts = [along(extents[0].0), along(extents[1].1)];
    let [m1, m2]: [Mesh; 2] = meshes
        .try_into()
        .map_err(|_| Error::Internal("two bodies read".into()))?;
    Ok(Some(([m1, m2], shifts)))
}

/// Refuses a file whose body 1 (the slave, moving along −e_d) does not lie above body 2 (the
/// master, moving along +e_d): the middle of its extent `(lo, hi)` along x_d must be above body
/// 2's, or the bodies would fly apart, each turned the wrong way for its own Hertz reference.
fn check_placement(file: &std::path::Path, dim: usize, extent: [(f64, f64); 2]) -> Result<()> {
    let middle = extent.map(|(lo, hi)| 0.5 * (lo + hi));
    if middle[0] > middle[1] {
        return Ok(());
    }
    Err(Error::Mesh {
        origin: file.display().to_string(),
        message: format!(
            "`{}` (body 1, the slave, moving along −e_{dim}) must lie above `{}` (body 2, the \
             master, moving along +e_{dim}), as in cases/meshes/two_discs.geo: the middle of its \
             extent along x_{dim} is {:e}, body 2's {:e} (swap the groups `{}`/`{}` and \
             `{}`/`{}`)",
            BODY_GROUPS[0],
            BODY_GROUPS[1],
            middle[0],
            middle[1],
            BODY_GROUPS[0],
            BODY_GROUPS[1],
            CONTACT_GROUPS[0],
            CONTACT_GROUPS[1]
        ),
    })
}

/// Largest offset across e_d between the centres of the two bodies' extents, relative to the
/// narrower body's width, that [`check_alignment`] lets pass: the impact's obliquity, about
/// the offset over R₁ + R₂, stays below 1°, and the extent of a polygonal disc of boundary
/// spacing h is off centre by at most h²/(16R), 1e-2 of its width up to h ≈ 0.56 R.
const ALIGNMENT_TOLERANCE: f64 = 1e-2;

/// Refuses a file of two round bodies offset across e_d: the pair meets along e_d, head on, as
/// its Hertz reference assumes (body 2 shifted by half a radius ran and compared its 1.9 % and
/// 7.7 % radius and pressure errors with the head-on reference). Compares the centres of each
/// body's extent along every x_k, k < d. (A round body on a box meets it head on wherever it
/// lands on the box's face: not checked.)
fn check_alignment(file: &std::path::Path, dim: usize, meshes: &[Mesh]) -> Result<()> {
    for k in 0..dim - 1 {
        let [(lo1, hi1), (lo2, hi2)] = [0, 1].map(|b| meshes[b].extent(k));
        let offset = 0.5 * ((lo1 + hi1) - (lo2 + hi2));
        let width = (hi1 - lo1).min(hi2 - lo2);
        if offset.abs() > ALIGNMENT_TOLERANCE * width {
            return Err(Error::Mesh {
                origin: file.display().to_string(),
                message: format!(
                    "`{}` and `{}` must meet head on along e_{dim}, as the pair's Hertz \
                     reference assumes: the centres of their extents along x_{} differ by {} \
                     (more than {ALIGNMENT_TOLERANCE:e} of the narrower body's width, {}); \
                     align them",
                    BODY_GROUPS[0],
                    BODY_GROUPS[1],
                    k + 1,
                    format_args!("{offset:.3e}"),
                    format_args!("{width:.3e}")
                ),
            });
        }
    }
    Ok(())
}

/// A mesh moved rigidly: each node `x ↦ map(x − shift)`.
fn placed(mut mesh: Mesh, map: impl Fn([f64; 3]) -> [f64; 3], shift: [f64; 3]) -> Mesh {
    for x in &mut mesh.nodes {
        *x = map(std::array::from_fn(|k| x[k] - shift[k]));
    }
    mesh
}

/// The shift that centres a box's tangential extent on the line of impact (0 for round bodies,
/// generated centred).
fn centring(fem: &Discretisation, shape: &str) -> [f64; 3] {
    let d = fem.dim();
    let mut shift = [0.0; 3];
    if shape == "box" {
        for (k, s) in shift.iter_mut().enumerate().take(d - 1) {
            let (lo, hi) = fem
                .mesh
                .nodes
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x[k]), hi.max(x[k]))
                });
            *s = -0.5 * (lo + hi);
        }
    }
    shift
}

/// Hertz's body of the pair: `1/R* = Σ 1/R_i` (a box: 0), `1/E* = Σ 1/E_i*`, `m* = m₁m₂/(m₁ +
/// m₂)` (the bodies' continuum masses), relative speed `v = |v₁| + |v₂|`; None unless body 1 is
/// curved.
fn pair_hertz(parts: &[Body; 2], dim: usize, materials: [&Material; 2]) -> Option<Hertz> {
    parts[0].hertz?;
    let curvature: f64 = parts
        .iter()
        .filter_map(|p| p.hertz)
        .map(|h| 1.0 / h.radius)
        .sum();
    let compliance: f64 = materials
        .iter()
        .map(|m| (1.0 - m.poisson * m.poisson) / m.young)
        .sum();
    let mass = |p: &Body, m: &Material| match p.hertz {
        Some(h) => h.mass,
        None => m.density * p.geometry.size.iter().product::<f64>(),
    };
    let (m1, m2) = (mass(&parts[0], materials[0]), mass(&parts[1], materials[1]));
    Some(Hertz {
        dim,
        radius: 1.0 / curvature,
        e_star: 1.0 / compliance,
        mass: m1 * m2 / (m1 + m2),
        speed: -parts[0].geometry.velocity - parts[1].geometry.velocity,
        compliance: 0.0,
    })
}

impl TwoBodies {
    /// Validates the spec, applies the overrides (to both bodies) and builds both meshes.
    pub fn from_spec(spec: TwoBodiesSpec, o: &Overrides) -> Result<Self> {
        let Some(&(kind, dim)) = KINDS.iter().find(|k| k.0 == spec.case) else {
            return Err(Error::UnknownName {
                kind: "case",
                name: spec.case.clone(),
                known: KINDS.iter().map(|k| k.0).collect::<Vec<_>>().join(", "),
            });
        };
        let meshes = gmsh_bodies(&spec, o, dim)?;
        if let Some(mu) = spec.master.contact.as_ref().and_then(|c| c.friction) {
            return Err(Error::invalid(
                "master.contact.friction",
                mu,
                "the interface's μ is body 1's [contact] friction",
            ));
        }
        let slopes = [
            ("geometry.slope", Some(&spec.geometry)),
            ("master.geometry.slope", spec.master.geometry.as_ref()),
        ];
        if let Some((field, slope)) = slopes
            .into_iter()
            .filter_map(|(f, g)| Some((f, g?.slope)))
            .find(|s| s.1 != 0.0)
        {
            return Err(Error::invalid(
                field,
                slope,
                "two bodies meet along e_d, without a slope (0)",
            ));
        }
        if let Some(lift) = spec
            .master
            .geometry
            .as_ref()
            .map(|g| g.lift)
            .filter(|l| *l != 0.0)
        {
            return Err(Error::invalid(
                "master.geometry.lift",
                lift,
                "the gap between the bodies is body 1's geometry.lift (body 2's would be unused)",
            ));
        }
        let m = &spec.master;
        let material2 = m.material.clone().unwrap_or_else(|| spec.material.clone());
        let geometry2 = m.geometry.clone().unwrap_or_else(|| Geometry {
            lift: 0.0,
            tangential_velocity: 0.0,
            gravity: 0.0,
            ..spec.geometry.clone()
        });
        let part = |material: Material, geometry: Geometry, mesh, contact, read, o: &Overrides| {
            let round = geometry.shape != "box";
            let case = match (round, dim) {
                (true, 2) => "hertz2d",
                (true, _) => "hertz3d",
                (false, 2) => "block2d",
                (false, _) => "block3d",
            };
            let body = BodySpec {
                case: case.into(),
                units: spec.units.clone(),
                material,
                geometry,
                mesh,
                contact,
                run: spec.run.clone(),
                sweep: Vec::new(),
                history: Vec::new(),
                oblique: None,
            };
            Body::with_mesh(body, o, read)
        };
        // Each body in its own frame, resting on x_d = 0 from above (a file's bodies placed so).
        let [read1, read2] = match &meshes {
            Some(([m1, m2], [s1, s2])) => [
                Some(placed(m1.clone(), |x| x, *s1)),
                Some(placed(m2.clone(), |x| turn(x, dim), *s2)),
            ],
            None => [None, None],
        };
        // Body 1's [mesh] when body 2 has none; its grading only where body 2 is round too
        // (a box master under a graded disc would be refused for a field the file never set).
        let mesh2 = m.mesh.clone().unwrap_or_else(|| MeshSpec {
            grading: match geometry2.shape.as_str() {
                "box" => super::body::default_grading(),
                _ => spec.mesh.grading,
            },
            ..spec.mesh.clone()
        });
        let contact2 = m.contact.clone().unwrap_or_else(|| spec.contact.clone());
        // Two bodies read from a Gmsh file are two meshes, never twins.
        let twins = meshes.is_none()
            && (&material2, &geometry2, &mesh2, &contact2)
                == (&spec.material, &spec.geometry, &spec.mesh, &spec.contact);
        // `--elements N` refines body 2's own [master.mesh] in the file's proportion.
        let o2 = match (&m.mesh, o.elements) {
            (Some(mesh), Some(n)) => Overrides {
                elements: Some(proportional(n, spec.mesh.elements, mesh.elements)),
                ..o.clone()
            },
            _ => o.clone(),
        };
        let parts = [
            part(
                spec.material.clone(),
                spec.geometry.clone(),
                spec.mesh.clone(),
                spec.contact.clone(),
                read1,
                o,
            )?,
            // Body 1's tables passed: what fails here is [master]'s, named so.
            part(material2.clone(), geometry2, mesh2, contact2, read2, &o2).map_err(|e| {
                e.with_field(|f| {
                    let table = ["material.", "geometry.", "mesh.", "contact."];
                    if table.iter().any(|t| f.starts_with(t)) {
                        format!("master.{f}")
                    } else {
                        f.to_string()
                    }
                })
            })?,
        ];
        for (p, field) in parts
            .iter()
            .zip(["geometry.velocity", "master.geometry.velocity"])
        {
            if p.geometry.velocity > 0.0 {
                return Err(Error::invalid(
                    field,
                    p.geometry.velocity,
                    "must be ≤ 0 (towards the other body, or at rest)",
                ));
            }
        }
        // Back to the global frame: body 1 (the slave) `x + s₁`, body 2 turned, `turn(x) + s₂`
        // (a file's: `s₁ = b₁ e_d`, `s₂ = t₂ e_d`, undoing [`gmsh_bodies`]' placement).
        let [mut s1, s2] = match &meshes {
            Some((_, shifts)) => *shifts,
            None => [
                centring(&parts[0].fem, &parts[0].geometry.shape),
                turn(centring(&parts[1].fem, &parts[1].geometry.shape), dim),
            ],
        };
        s1[dim - 1] += spec.geometry.lift;
        let slave = moved(parts[0].fem.clone(), |x| x, s1);
        let master = moved(parts[1].fem.clone(), |x| turn(x, dim), s2);
        let bodies = Bodies::new(vec![slave, master])?;
        let hertz = pair_hertz(&parts, dim, [&spec.material, &material2]);
        let impact = hertz.map(|h| pair_impact(&parts, &bodies, h)).transpose()?;
        let mut run = spec.run;
        o.apply(&mut run);
        run.validate()?;
        if let Some(i) = &impact {
            super::check_touch(spec.geometry.lift, i.gap, i.hertz.speed, run.t_end)?;
        }
        Ok(Self {
            kind,
            parts,
            twins,
            bodies,
            impact,
            plane: spec.master.plane,
            run,
            sweeps: spec.sweep,
            history: spec.history,
        })
    }
}

impl TwoBodies {
    /// The nodal rows of body 2 on the rigid plane under it (`x_d` at its lowest node): its faces
    /// facing −e_d in the global frame, with tangential rows when `friction` (frictionless
    /// there: [`crate::problem::Friction::frictionless`]); and their normal dofs (body 2's).
    fn support(&self, friction: bool) -> Result<(crate::problem::Contact, Vec<usize>)> {
        let master = &self.bodies.parts[1];
        let d = master.dim();
        let mut mesh = master.mesh.clone();
        mesh.contact_faces = None;
        let lowest = mesh
            .nodes
            .iter()
            .map(|x| x[d - 1])
            .fold(f64::INFINITY, f64::min);
        let fem = Discretisation::new(
            mesh,
            master.lame,
            master.density,
            crate::mesh::ContactRule::Facing(crate::mesh::FACING),
        )?;
        let mut contact = fem.contact(-lowest)?;
        if friction {
            contact.friction = Some(fem.friction(0.0)?);
        }
        Ok((contact, fem.mass_model().contact_dofs))
    }
}

/// The pair's impact: the relative approach of the centres of mass `δ = −Σ w U − g₀` (body
/// 1's weights, body 2's negated: it approaches along +e_d; g₀ the gap between body 1's lowest
/// point and body 2's highest, closed at the relative speed before the first touch), the
/// reduced discrete mass, and the initial positions of the slave vertices with a contact row
/// (the rows' order).
fn pair_impact(parts: &[Body; 2], bodies: &Bodies, hertz: Hertz) -> Result<Impact> {
    let (c1, m1) = parts[0].centre();
    let (c2, m2) = parts[1].centre();
    let o = bodies.offset(1);
    let mut centre = c1;
    centre.extend(c2.into_iter().map(|(j, w)| (j + o, -w)));
    let slave = &bodies.parts[0];
    let positions = bodies
        .pairings(0, 1)?
        .iter()
        .map(|p| slave.mesh.nodes[slave.contact_vertices[p.slave].0])
        .collect();
    let d = bodies.dim();
    let gap = bodies.parts[0].mesh.extent(d - 1).0 - bodies.parts[1].mesh.extent(d - 1).1;
    Ok(Impact {
        hertz,
        centre,
        mass: m1 * m2 / (m1 + m2),
        positions,
        gap,
    })
}

impl Case for TwoBodies {
    fn kind(&self) -> &'static str {
        self.kind
    }

    /// The larger of the two bodies' mesh sizes at the contact.
    fn h(&self) -> f64 {
        self.bodies.h()
    }

    fn element(&self) -> Option<(&'static str, usize)> {
        Some(self.bodies.element())
    }

    /// Both bodies undeformed, body 1 at `v₁ e_d + v_{t,1} e_1`, body 2 at `|v₂| e_d + v_{t,2} e_1`
    /// (global frame), each under its own gravity; Coulomb friction on the interface with body
    /// 1's μ.
    fn problem(&self, space: &dyn Space) -> Result<Problem> {
        let d = self.bodies.dim();
        let initial: Vec<Initial> = self
            .bodies
            .parts
            .iter()
            .zip(&self.parts)
            .zip([1.0, -1.0])
            .map(|((p, body), sign)| {
                let g = &body.geometry;
                let v = sign * g.velocity;
                Initial {
                    displacement: vec![0.0; p.n_dofs()],
                    velocity: p.interpolate(|_| {
                        std::array::from_fn(|k| match k {
                            k if k == d - 1 => v,
                            0 => g.tangential_velocity,
                            _ => 0.0,
                        })
                    }),
                    gravity: (g.gravity != 0.0).then_some(g.gravity),
                    lift: 0.0,
                }
            })
            .collect();
        let mu = self.parts[0].friction;
        let offset = self.bodies.offset(1);
        let support = self.plane.then(|| self.support(mu > 0.0)).transpose()?;
        // The plane's normal dofs are contact dofs too (massless under mass redistribution).
        let inertia = |m: &MassModel| match &support {
            None => space.inertia(m),
            Some((_, dofs)) => {
                let mut m = m.clone();
                m.contact_dofs.extend(dofs.iter().map(|d| d + offset));
                m.contact_dofs.sort_unstable();
                m.contact_dofs.dedup();
                space.inertia(&m)
            }
        };
        let mut problem = self.bodies.problem(inertia, &initial)?;
        if mu > 0.0 {
            problem.contact.friction = Some(self.bodies.friction(0, 1, mu)?);
        }
        if let Some((contact, _)) = &support {
            problem.contact.append(contact, offset)?;
        }
        Ok(problem)
    }

    fn run(&self) -> &RunSpec {
        &self.run
    }

    fn sweeps(&self) -> &[SweepSpec] {
        &self.sweeps
    }

    fn histories(&self) -> &[HistorySpec] {
        &self.history
    }

    fn impact(&self) -> Option<Impact> {
        self.impact.clone()
    }

    /// The translation along e_d, when no body carries a weight (else its momentum is not an
    /// invariant).
    fn momentum(&self) -> Option<Vec<f64>> {
        self.parts
            .iter()
            .all(|p| p.geometry.gravity == 0.0)
            .then(|| self.bodies.translation())
    }

    fn multi_body(&self) -> Option<&Bodies> {
        Some(&self.bodies)
    }

    /// Body 2 of twins is body 1's case itself ([`crate::study::finite_body::in_series`] then
    /// measures the law once).
    fn bodies(&self) -> Vec<&dyn Case> {
        let second = if self.twins { 0 } else { 1 };
        vec![&self.parts[0], &self.parts[second]]
    }
}
