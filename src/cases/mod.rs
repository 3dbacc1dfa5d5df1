//! Case files (`cases/*.toml`): parsing, validation and the [`Case`] trait that turns a case into a
//! [`Problem`] for a given space.
//!
//! A case file names its kind in `case = "…"`, states its units in `units = "…"`, and has a `[run]`
//! table with the default space, scheme and time step; the rest depends on the kind
//! (see `cases/bar1d.toml`, `cases/spring_mass.toml`).

pub mod bar;
pub mod bar1d;
pub mod bar_flight;
pub mod body;
pub mod spring_mass;
pub mod sweep;
pub mod two_bars;
pub mod two_bodies;

use crate::error::{positive, short, Error, Result};
use crate::exact::ExactContact;
pub use crate::param::Options;
use crate::param::{Param, Params};
use crate::problem::Problem;
use crate::space::Space;
use serde::de::DeserializeOwned;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Error evaluator of a full displacement field against the exact one.
pub trait FieldError: Sync {
    /// `(‖u_h − u‖_{L²(Ω)}, |u_h − u|_{H¹(Ω)})` at time t.
    fn errors(&self, u: &[f64], t: f64) -> (f64, f64);
}

/// A canonical case, ready to build problems.
pub trait Case: Send + Sync {
    /// Kind of the case (`bar1d`, `bar_flight`, `spring_mass`, …).
    fn kind(&self) -> &'static str;
    /// Mesh size h (NaN for a 0D case).
    fn h(&self) -> f64;
    /// The semi-discrete problem with the given space.
    fn problem(&self, space: &dyn Space) -> Result<Problem>;
    /// Exact solution at the contact point, if known (none by default).
    fn exact(&self) -> Option<&dyn ExactContact> {
        None
    }
    /// Exact-field error evaluator (for a problem built by this case), if known (none by
    /// default).
    fn field_error(&self) -> Option<Box<dyn FieldError + '_>> {
        None
    }
    /// True when the exact contact stress is a function of time (not a sum of impulses), so that
    /// its L²(0, T) error is meaningful (by default; the point mass's is a sum of impulses).
    fn stress_is_function(&self) -> bool {
        true
    }
    /// The run settings (defaults from the file, possibly overridden).
    fn run(&self) -> &RunSpec;
    /// The `[[sweep]]` tables of the case file.
    fn sweeps(&self) -> &[sweep::SweepSpec];
    /// The `[[history]]` tables of the case file (time series the report plots).
    fn histories(&self) -> &[sweep::HistorySpec] {
        &[]
    }
    /// The mesh discretisation of a 2D/3D body case (field output), if any.
    fn discretisation(&self) -> Option<&crate::fem::discretisation::Discretisation> {
        None
    }
    /// The cell shape (`segment`, `triangle`, `quad`, `tet`, `hex`) and polynomial degree of
    /// the mesh; None for a 0D case.
    fn element(&self) -> Option<(&'static str, usize)> {
        None
    }
    /// What an impact against Hertz theory measures (curved-body cases), if anything.
    fn impact(&self) -> Option<Impact> {
        None
    }
    /// The unit translation `1_d` along the line of impact of a multi-body case with no
    /// external force (dof layout of U), whose momentum `(M̃ 1_d)ᵀ V` is then an invariant.
    fn momentum(&self) -> Option<Vec<f64>> {
        None
    }
    /// The rigid-body slide its centre of mass follows (the slide cases), if any.
    fn slide(&self) -> Option<crate::exact::slide::Slide> {
        None
    }
    /// The bodies of a multi-body case in the global frame (field output writes them all).
    fn multi_body(&self) -> Option<&crate::fem::bodies::Bodies> {
        None
    }
    /// The rigid motions of a disc or sphere with friction whose velocities a run records
    /// (`com_velocity_n`, `angular_velocity`), if any.
    fn spin(&self) -> Option<Spin> {
        None
    }
    /// The incidences of the report's oblique-impact study (`[oblique]` of a case file), if any.
    fn oblique(&self) -> Option<&body::ObliqueStudy> {
        None
    }
    /// The rigid disc on the slope it is compared with (`roll2d`), if any.
    fn roll(&self) -> Option<crate::exact::roll::Roll> {
        None
    }
    /// Each body of a multi-body case alone against the rigid plane, in its own frame (empty
    /// for a single body): the finite-body reference of a pair adds theirs. Bodies that are the
    /// same body (a pair of twins) are the same case, listed twice.
    fn bodies(&self) -> Vec<&dyn Case> {
        Vec::new()
    }
}

/// The rigid motions of a disc or sphere rolling or bouncing on the plane with friction: the
/// run records the centre of mass's normal velocity `(M̃1_d)ᵀV / 1_dᵀM̃1_d` and the angular
/// velocity `ω = (M̃φ)ᵀV / φᵀM̃φ`, with φ made M̃-orthogonal to the translations (the angular
/// momentum about the centre of mass over the moment of inertia, both of the space's own mass).
#[derive(Debug, Clone)]
pub struct Spin {
    /// The unit translation along the plane's normal e_d (dof layout of U).
    pub normal: Vec<f64>,
    /// The infinitesimal rotation about the centre `c = (0, …, R)` that rolls the body along
    /// +e_1: `φ(x) = (x_d − R) e_1 − x_1 e_d` (a body rolling forwards at ω has `V = ω φ` about
    /// its centre; its contact point moves at `v_t − ω R`).
    pub rotation: Vec<f64>,
    /// Radius R.
    pub radius: f64,
}

/// The data of an impact compared with Hertz theory ([`crate::exact::hertz`]).
#[derive(Debug, Clone)]
pub struct Impact {
    /// The Hertz reference.
    pub hertz: crate::exact::hertz::Hertz,
    /// `(dof, w)`: the centre of mass's displacement towards the plane is `δ = −Σ w U_dof`
    /// (`w = ∫ρ φ_i / m` on the normal components).
    pub centre: Vec<(usize, f64)>,
    /// The discrete body's mass `m = Σ ∫ρ φ_i` (the sphere's less what straight-sided cells
    /// lose).
    pub mass: f64,
    /// Initial coordinates of each contact point (for the pressure profile).
    pub positions: Vec<[f64; 3]>,
    /// The initial gap `g₀ = min g₀_i` along e_d (`geometry.lift` plus the lowest node's height
    /// above the plane; two bodies: the smallest gap of the pairings), closed in free flight at
    /// the speed `hertz.speed` before the first touch: Hertz's approach and time start there.
    pub gap: f64,
}

impl Impact {
    /// Hertz's approach `δ = −Σ w U_dof − g₀`: the centre of mass's displacement towards the
    /// plane since the first touch (0 there, `−g₀` at t = 0).
    pub fn approach(&self, u: &[f64]) -> f64 {
        -self.centre.iter().map(|&(j, w)| w * u[j]).sum::<f64>() - self.gap
    }

    /// The time of the first touch, `t₀ = g₀ / v` (free flight, no gravity in a Hertz impact).
    pub fn touch_time(&self) -> f64 {
        self.gap / self.hertz.speed
    }

    /// The centre of pressure `Σ λ_i x_i / Σ λ_i` (tangential coordinates, unused ones 0) of
    /// the nodal contact forces λ, and the total force `Σ λ_i`.
    pub fn centre_of_pressure(&self, lambda: &[f64]) -> ([f64; 2], f64) {
        let force: f64 = lambda.iter().sum();
        let mut c = [0.0; 2];
        for (l, x) in lambda.iter().zip(&self.positions) {
            for (ck, xk) in c.iter_mut().zip(&x[..self.hertz.dim - 1]) {
                *ck += l * xk / force;
            }
        }
        (c, force)
    }

    /// The distance of each contact point from the centre of pressure of λ (in the plane), and
    /// the total force `Σ λ_i`.
    pub fn distances(&self, lambda: &[f64]) -> (Vec<f64>, f64) {
        let (c, force) = self.centre_of_pressure(lambda);
        let tangential = self.hertz.dim - 1;
        let r = self
            .positions
            .iter()
            .map(|x| {
                (0..tangential)
                    .map(|k| (x[k] - c[k]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .collect();
        (r, force)
    }
}

/// The `[run]` table: default discretisation choices.
#[derive(Debug, Clone, Deserialize, PartialEq)]
pub struct RunSpec {
    /// Space discretisation name.
    pub space: String,
    /// Time scheme name.
    pub scheme: String,
    /// Time step.
    pub dt: f64,
    /// Final time.
    pub t_end: f64,
    /// Contact formulation, solvers and the methods' parameters.
    #[serde(flatten)]
    pub options: Options,
}

impl RunSpec {
    /// Default settings for `space` and `scheme` (parameters at their defaults).
    pub fn new(space: &str, scheme: &str, dt: f64, t_end: f64) -> Self {
        Self {
            space: space.into(),
            scheme: scheme.into(),
            dt,
            t_end,
            options: Options::default(),
        }
    }

    /// `self` with parameter `name` set (builder form).
    pub fn with(mut self, name: &str, value: f64) -> Self {
        self.options.params.set(name, value);
        self
    }

    /// Checks dt, t_end (a whole number of steps, see [`STEPS_TOLERANCE`]), the names and the
    /// parameters.
    pub fn validate(&self) -> Result<()> {
        positive("run.dt", self.dt)?;
        positive("run.t_end", self.t_end)?;
        if self.dt > self.t_end {
            return Err(Error::invalid(
                "run.dt",
                self.dt,
                "must not exceed run.t_end",
            ));
        }
        let ratio = self.t_end / self.dt;
        // Beyond 2^53, t_end/dt is no longer a count of steps (and a count the loop can take).
        if ratio > 2f64.powi(53) {
            return Err(Error::invalid(
                "run.t_end",
                self.t_end,
                &format!(
                    "is {ratio:e} steps of run.dt = {:?}: a run takes at most 2^53 steps",
                    self.dt
                ),
            ));
        }
        if (ratio - ratio.round()).abs() > STEPS_TOLERANCE * ratio {
            // N·dt to 10 significant digits (3 × 0.4 prints as 1.2; 1e-318 not in 330 digits).
            let at = |n: f64| {
                let x = n * self.dt;
                crate::error::short(format!("{x:.9e}").parse::<f64>().unwrap_or(x))
            };
            return Err(Error::invalid(
                "run.t_end",
                self.t_end,
                &format!(
                    "must be a whole number of steps of run.dt = {:?}: t_end/dt = {ratio}, so the \
                     run would end at {} or {}, not at t_end",
                    self.dt,
                    at(ratio.floor()),
                    at(ratio.ceil())
                ),
            ));
        }
        self.options.params.validate("run")?;
        self.check_applicable()?;
        crate::space::by_name(&self.space)?;
        let own = self.own_law()?;
        if let (Some(m), false) = (
            &self.options.contact_multiplier,
            self.options.contact() == "weak",
        ) {
            return Err(Error::invalid(
                "run.contact_multiplier",
                m,
                "applies to contact = \"weak\" only",
            ));
        }
        let default = crate::contact::DEFAULT_SOLVER;
        if let (Some(why), true) = (own, self.options.contact_solver() != default) {
            return Err(Error::invalid(
                "run.contact_solver",
                self.options.contact_solver(),
                &format!("{why}, not through an LCP solver (leave the default, {default})"),
            ));
        }
        crate::contact::by_name(self.options.contact_solver(), 0)?;
        crate::time::LinearSolver::by_name(self.options.linear_solver())?;
        Ok(())
    }

    /// Why the contact solver has no effect on this run, if so: a formulation that solves its
    /// own law per step (Nitsche's semismooth Newton) or a scheme that applies its own (a
    /// penalty, a velocity correction) would silently ignore an LCP solver.
    fn own_law(&self) -> Result<Option<String>> {
        let scheme =
            crate::time::by_name(&self.scheme, self.params()).map_err(|e| e.in_table("run"))?;
        let formulation = crate::contact::formulation(&self.options)?;
        Ok(match (formulation.takes_solver(), scheme.own_law()) {
            (false, _) => Some(format!(
                "contact = \"{}\" solves its own law per step",
                formulation.name()
            )),
            (true, Some(law)) => Some(format!("scheme {} applies {law}", scheme.name())),
            (true, None) => None,
        })
    }

    /// Refuses a solver given on the command line (`given`: the flags' options) that this run
    /// would not use, whatever its value, the default included: `--contact-solver` where the
    /// formulation or the scheme solves its own law, `--linear-solver` with a scheme that
    /// solves no linear system.
    pub fn refuse_unused_flags(&self, given: &Options) -> Result<()> {
        if let (Some(solver), Some(why)) = (&given.contact_solver, self.own_law()?) {
            return Err(Error::invalid(
                "--contact-solver",
                solver,
                &format!("{why}, not through an LCP solver: the option would have no effect"),
            ));
        }
        let scheme = crate::time::by_name(&self.scheme, self.params())?;
        if let (Some(solver), false) = (&given.linear_solver, scheme.solves_linear_system()) {
            return Err(Error::invalid(
                "--linear-solver",
                solver,
                &format!(
                    "scheme {} solves no linear system (lumped mass, explicit steps): the option \
                     would have no effect",
                    scheme.name()
                ),
            ));
        }
        Ok(())
    }

    /// Refuses a parameter that neither the scheme nor the contact formulation declares
    /// (`--beta` with backward_euler, `--alpha` with newmark, `nitsche_gamma` with nodal
    /// contact): the run would ignore it.
    fn check_applicable(&self) -> Result<()> {
        let own = applicable(&self.scheme, &self.options)?;
        for p in crate::methods::all_params() {
            if let (Some(v), false) = (self.params().value(p), own.contains(&p.name)) {
                return Err(Error::invalid(
                    format!("run.{}", p.name),
                    v,
                    &format!(
                        "does not apply to scheme `{}` with contact `{}`, whose parameters are: {}",
                        self.scheme,
                        self.options.contact(),
                        if own.is_empty() {
                            "none".to_string()
                        } else {
                            own.join(", ")
                        }
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The methods' parameter values of this run.
    pub fn params(&self) -> &Params {
        &self.options.params
    }

    /// The `parameters` column of the records: the scheme's `name=value;…`, then, for a contact
    /// formulation other than the default, `contact=<name>` and its parameters, then the solvers
    /// set to other than their defaults ([`RunSpec::solver_parameters`]).
    pub fn parameters(&self) -> Result<String> {
        let mut parts = vec![crate::time::entry(&self.scheme)?.describe(self.params())];
        let contact = self.options.contact();
        if contact != crate::contact::DEFAULT_FORMULATION {
            let entry = crate::contact::formulation_entry(contact)?;
            let label = crate::contact::formulation(&self.options)?.label();
            parts.push(format!("contact={label}"));
            parts.push(entry.describe(self.params()));
        }
        parts.extend(self.solver_parameters()?);
        parts.retain(|p| !p.is_empty());
        Ok(parts.join(";"))
    }

    /// `contact_solver=<name>` for a contact solver other than `active_set` and
    /// `linear_solver=<name>` for a linear solver other than `auto` with a scheme that solves
    /// a linear system (the others ignore it), so that two runs differing by a solver differ in
    /// their key and records. A friction run without a solver set takes `alart_curnier`, written
    /// as nothing.
    fn solver_parameters(&self) -> Result<Vec<String>> {
        let mut out = Vec::new();
        let contact = self.options.contact_solver();
        if contact != crate::contact::DEFAULT_SOLVER {
            out.push(format!("contact_solver={contact}"));
        }
        let linear = self.options.linear_solver();
        if linear != crate::time::DEFAULT_LINEAR_SOLVER
            && crate::time::by_name(&self.scheme, self.params())?.solves_linear_system()
        {
            out.push(format!("linear_solver={linear}"));
        }
        Ok(out)
    }

    /// Number of steps `t_end / dt`, a whole number by [`RunSpec::validate`] (≥ 1).
    pub fn steps(&self) -> usize {
        ((self.t_end / self.dt).round() as usize).max(1)
    }
}

/// The parameters that apply to `scheme` with the contact formulation of `options`: those
/// their registry entries declare ([`crate::time::entry`], [`crate::contact::formulation_entry`]).
pub fn applicable(scheme: &str, options: &Options) -> Result<Vec<&'static str>> {
    let scheme = crate::time::entry(scheme)?.params.iter();
    let contact = crate::contact::formulation_entry(options.contact())?
        .params
        .iter();
    Ok(scheme.chain(contact).map(|p: &&Param| p.name).collect())
}

/// Relative tolerance on `t_end / dt` being a whole number N: the run takes N steps of dt and
/// ends at N·dt = t_end to that tolerance. A shortened last step would need another step matrix
/// (implicit schemes factor `m M + k K` once for one dt) and its own starting values for the
/// three-level schemes, so a t_end off the grid is refused instead.
pub const STEPS_TOLERANCE: f64 = 1e-9;

/// Largest accepted ratio `Δt / τ` of the time step to the time scale of the inertia against the
/// stiffness, `τ = h √(ρ/E)` (a wave crossing an element; `√(m/k)` for one mass on a spring).
pub const TIME_SCALE_RATIO: f64 = 1e6;

/// Refuses a density (or mass) so small against the stiffness (or a stiffness so large) that the
/// time step exceeds [`TIME_SCALE_RATIO`] times `τ = h √(ρ/E)`: the mass term of the step matrix
/// `m M + k K` is then about `(τ/Δt)² ≤ 1e-12` of the stiffness term, a few digits above its
/// round-off, so the inertia hardly enters the step (a free body's step matrix is singular to
/// round-off and its factorisation fails). `density` and `stiffness` are `(field, value)`,
/// refused first if not finite, > 0 and ≥ 0 respectively (τ would be NaN, and the message blame
/// the density for a negative stiffness). A non-finite `h` (a mesh node at NaN) is left to the
/// mesh's check, which names the node.
pub fn check_time_scale(
    density: (&str, f64),
    stiffness: (&str, f64),
    h: f64,
    dt: f64,
) -> Result<()> {
    positive(density.0, density.1)?;
    crate::error::non_negative(stiffness.0, stiffness.1)?;
    let tau = h * (density.1 / stiffness.1).sqrt();
    if !h.is_finite() || tau * TIME_SCALE_RATIO >= dt {
        return Ok(());
    }
    Err(Error::invalid(
        density.0,
        density.1,
        &format!(
            "too small against {} = {:e} on elements of size h = {h:.3e} (geometry and mesh): \
             the time scale of the inertia against the stiffness, τ = {tau:.3e} (h √(ρ/E), or \
             √(m/k)), is below run.dt / {TIME_SCALE_RATIO:e} = {:.3e}, so the mass would fall \
             to the round-off of the stiffness in the step matrix",
            stiffness.0,
            stiffness.1,
            dt / TIME_SCALE_RATIO
        ),
    ))
}

/// Refuses a Hertz impact that ends before its first touch, `t_end ≤ t₀ = g₀ / v` up to a
/// relative 1e-9 (the gap g₀ closed at the speed v, [`Impact::touch_time`]): the run would have
/// no contact and no Hertz errors. Named `geometry.lift` (`lift`), the gap's knob.
pub fn check_touch(lift: f64, gap: f64, speed: f64, t_end: f64) -> Result<()> {
    let t0 = gap / speed;
    // Relative to t_end: a touch at t_end up to rounding (0.3 / 0.1 = 2.9999999999999996 < 3)
    // would leave no contact either.
    if t0 < t_end * (1.0 - 1e-9) {
        return Ok(());
    }
    Err(Error::invalid(
        "geometry.lift",
        lift,
        &format!(
            "the body starts {} from the plane or the other body (the lift plus the mesh's \
             own placement) at the speed {}: it first touches at t = gap/speed = {}, \
             not before run.t_end = {}, so the run would have no contact and no Hertz \
             errors",
            short(gap),
            short(speed),
            short(t0),
            short(t_end)
        ),
    ))
}

/// Overrides of a case file from the command line.
#[derive(Debug, Clone, Default)]
pub struct Overrides {
    /// `--space`.
    pub space: Option<String>,
    /// `--scheme`.
    pub scheme: Option<String>,
    /// `--contact`, `--contact-solver`, `--linear-solver` and the parameters (`--beta`, …).
    pub options: Options,
    /// `--degree`.
    pub degree: Option<usize>,
    /// `--elements`.
    pub elements: Option<usize>,
    /// `--cells`: the cell shape of a generated 2D/3D mesh.
    pub cells: Option<String>,
    /// `--mesh`: a Gmsh file replacing the case's mesh.
    pub mesh: Option<PathBuf>,
    /// `--dt`.
    pub dt: Option<f64>,
    /// `--t-end`.
    pub t_end: Option<f64>,
    /// `--friction`: the Coulomb coefficient μ of a 2D/3D body case or pair (its `[contact]
    /// friction`).
    pub friction: Option<f64>,
    /// `--incidence`: the angle θ (degrees, from the normal) of a body case's initial velocity,
    /// its speed kept: `velocity = −V cos θ`, `tangential_velocity = V sin θ`.
    pub incidence: Option<f64>,
    /// Where the values came from, for the errors that name them: the command line (None) or a
    /// table of the case file (`[[sweep]]`, `[[history]]`).
    pub origin: Option<Origin>,
}

/// A table of a case file that set a run's overrides: its fields as errors name them
/// ([`Overrides::named`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Origin {
    /// `sweep.orders`, `history.energy`.
    pub table: String,
    /// The table's fields that gave `dt` and `elements`: `dt` and `elements`, or `refinements`
    /// for both; a history's `dts`.
    pub levels: [&'static str; 2],
    /// The table's field that gave the scheme, its options and parameters: a sweep's `schemes`,
    /// a history's `scheme`.
    pub choice: &'static str,
}

impl Origin {
    /// The table's field that gave the override `key` ([`Overrides::key_of`]).
    fn field_of<'a>(&self, key: &'a str) -> &'a str {
        match key {
            "dt" => self.levels[0],
            "elements" => self.levels[1],
            "t_end" | "friction" | "degree" | "cells" => key,
            _ => self.choice,
        }
    }
}

impl Overrides {
    /// Applies the run-level overrides to `run`. When they change the scheme or the contact
    /// formulation, the parameters `run` had for the methods replaced, and that the new ones do
    /// not declare, are dropped (a case file's `beta` under `--scheme backward_euler`); a
    /// parameter the overrides set for a method they do not use is kept, and refused by
    /// [`RunSpec::validate`].
    pub fn apply(&self, run: &mut RunSpec) {
        let before = (run.scheme.clone(), run.options.contact().to_string());
        if let Some(s) = &self.space {
            run.space = s.clone();
        }
        if let Some(s) = &self.scheme {
            run.scheme = s.clone();
        }
        let mut options = run.options.clone();
        options.overlay(&self.options);
        if (run.scheme.as_str(), options.contact()) != (before.0.as_str(), before.1.as_str()) {
            if let Ok(own) = applicable(&run.scheme, &options) {
                let mut kept = Params::default();
                for p in crate::methods::all_params() {
                    let value = self.options.params.value(p).or_else(|| {
                        own.contains(&p.name)
                            .then(|| run.options.params.value(p))
                            .flatten()
                    });
                    if let Some(v) = value {
                        kept.set(p.name, v);
                    }
                }
                options.params = kept;
            }
        }
        run.options = options;
        run.dt = self.dt.unwrap_or(run.dt);
        run.t_end = self.t_end.unwrap_or(run.t_end);
    }

    /// `e` with the field it names followed by where the overrides set its value, when they did:
    /// `run.dt (--dt)` from the command line, `run.dt (sweep.orders.dt)` from a sweep, whose
    /// values are not the case file's `[run] dt`; a scheme's parameter from a sweep names its
    /// scheme entry (`run.alpha (sweep.orders.schemes)`).
    pub fn named(&self, e: Error) -> Error {
        e.with_field(|field| match self.key_of(field) {
            None => field.to_string(),
            Some(key) => match &self.origin {
                None => format!("{field} (--{})", key.replace('_', "-")),
                Some(o) => format!("{field} ({}.{})", o.table, o.field_of(key)),
            },
        })
    }

    /// The key of `field` (as errors name it: `run.dt`, `mesh.cells`, `run.beta`) when these
    /// overrides set its value: `dt`, `cells`, `beta`.
    fn key_of<'a>(&self, field: &'a str) -> Option<&'a str> {
        let o = &self.options;
        let set = match field {
            "run.dt" => self.dt.is_some(),
            "run.t_end" => self.t_end.is_some(),
            "mesh.elements" => self.elements.is_some(),
            "mesh.degree" => self.degree.is_some(),
            "mesh.cells" => self.cells.is_some(),
            "contact.friction" => self.friction.is_some(),
            "run.contact" => o.contact.is_some(),
            "run.contact_multiplier" => o.contact_multiplier.is_some(),
            "run.contact_solver" => o.contact_solver.is_some(),
            "run.linear_solver" => o.linear_solver.is_some(),
            f => f.strip_prefix("run.").is_some_and(|p| o.params.is_set(p)),
        };
        set.then(|| field.split_once('.').map_or(field, |(_, key)| key))
    }

    /// `self` with parameter `name` set (tests and benches: `Overrides::default().with("beta", 0.5)`).
    pub fn with(mut self, name: &str, value: f64) -> Self {
        self.options.params.set(name, value);
        self
    }
}

/// The size of a run estimated from its case file and overrides before anything is built, for
/// the scheduling of a study ([`CaseFile::size`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Size {
    /// Space dimension (0 for the spring–mass).
    pub dim: usize,
    /// Displacement dofs, about.
    pub dofs: f64,
    /// The run's number of dofs where it is known before the run (a bar, the spring, one
    /// generated box), for a resumed study's check; None where `dofs` is an estimate (a curved
    /// mesh's bound, a Gmsh file's length, a pair of bodies).
    pub exact: Option<usize>,
}

/// Case kinds known to [`load`].
pub const CASES: &[&str] = &[
    "bar1d",
    "bar_flight",
    "spring_mass",
    "block2d",
    "block3d",
    "hertz2d",
    "hertz3d",
    "disc2d",
    "slide2d",
    "slide3d",
    "roll2d",
    "oblique3d",
    "two_bars",
    "two_discs",
    "two_spheres",
    "two_blocks2d",
    "two_blocks3d",
];

#[derive(Deserialize)]
struct Header {
    case: String,
}

/// The parsed spec of a case file, one variant per kind.
#[derive(Debug, Clone)]
enum Spec {
    Bar1d(bar1d::Bar1dSpec),
    BarFlight(bar_flight::BarFlightSpec),
    Body(Box<body::BodySpec>),
    SpringMass(spring_mass::SpringMassSpec),
    TwoBars(two_bars::TwoBarsSpec),
    TwoBodies(Box<two_bodies::TwoBodiesSpec>),
}

/// A case file read and parsed once per command: its path, the hash of its text (the content
/// key of the study records) and its spec. [`CaseFile::build`] validates it with overrides, once per run.
#[derive(Debug, Clone)]
pub struct CaseFile {
    /// Where it was read (for messages).
    pub path: PathBuf,
    /// [`crate::util::content_hash`] of its text and of its `[mesh] file`'s bytes (the study
    /// records' key).
    pub hash: String,
    /// What the case is: the file's first comment line, up to a parenthesis or a full stop.
    pub title: String,
    spec: Spec,
    /// The case without overrides, once built ([`CaseFile::defaults`]).
    defaults: Defaults,
}

/// The case of a file without overrides, built on first use and shared.
#[derive(Clone, Default)]
struct Defaults(std::sync::OnceLock<std::sync::Arc<dyn Case>>);

impl std::fmt::Debug for Defaults {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let built = if self.0.get().is_some() {
            "built"
        } else {
            "not built"
        };
        write!(f, "Defaults({built})")
    }
}

impl CaseFile {
    /// Reads and parses the case file at `path`.
    pub fn read(path: &Path) -> Result<Self> {
        let text = crate::input::CASE_FILE.read_to_string(path)?;
        Self::parse(text, path)
    }

    /// Parses case-file text (`path` is only used in messages).
    pub fn parse(text: String, path: &Path) -> Result<Self> {
        let table: toml::Table = spec_from_str(&text, path)?;
        let header: Header = table
            .try_into()
            .map_err(|e: toml::de::Error| Error::CaseSyntax {
                path: path.to_path_buf(),
                message: format!("missing or invalid `case` field: {e}"),
            })?;
        let spec = match header.case.as_str() {
            "bar1d" => Spec::Bar1d(spec_from_str(&text, path)?),
            "bar_flight" => Spec::BarFlight(spec_from_str(&text, path)?),
            "block2d" | "block3d" | "hertz2d" | "hertz3d" | "disc2d" | "slide2d" | "slide3d"
            | "roll2d" | "oblique3d" => {
                let mut spec: body::BodySpec = spec_from_str(&text, path)?;
                beside(&mut spec.mesh.file, path);
                Spec::Body(Box::new(spec))
            }
            "spring_mass" => Spec::SpringMass(spec_from_str(&text, path)?),
            "two_bars" => Spec::TwoBars(spec_from_str(&text, path)?),
            "two_discs" | "two_spheres" | "two_blocks2d" | "two_blocks3d" => {
                let mut spec: two_bodies::TwoBodiesSpec = spec_from_str(&text, path)?;
                beside(&mut spec.mesh.file, path);
                Spec::TwoBodies(Box::new(spec))
            }
            other => {
                return Err(Error::UnknownName {
                    kind: "case",
                    name: other.to_string(),
                    known: CASES.join(", "),
                })
            }
        };
        let mut file = Self {
            path: path.to_path_buf(),
            hash: String::new(),
            title: title(&text),
            spec,
            defaults: Defaults::default(),
        };
        // The mesh file's bytes too: a journal row of the old mesh is not this file's run.
        let mut bytes = text.into_bytes();
        if let Some(mesh) = file.mesh_file() {
            bytes.extend(crate::input::MESH_FILE.read(mesh)?);
        }
        file.hash = crate::util::content_hash(&bytes);
        Ok(file)
    }

    /// The file's name without extension (`bar1d` for `cases/bar1d.toml`).
    pub fn stem(&self) -> String {
        self.path
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().to_string())
    }

    /// The estimated [`Size`] of a run with `overrides` (nothing is built or validated).
    pub fn size(&self, o: &Overrides) -> Size {
        // The bar's dofs, and how many of its nodes are fixed (None: not known here).
        let bar = |mesh: &bar::MeshSpec, bars: f64, fixed: Option<usize>| {
            let (elements, degree) = (
                o.elements.unwrap_or(mesh.elements),
                o.degree.unwrap_or(mesh.degree),
            );
            Size {
                dim: 1,
                dofs: bars * (elements as f64 * degree as f64 + 1.0),
                exact: fixed.map(|f| elements * degree + 1 - f),
            }
        };
        match &self.spec {
            // bar1d's far end is fixed; two_bars's second bar may have other elements.
            Spec::Bar1d(s) => bar(&s.mesh, 1.0, Some(1)),
            Spec::BarFlight(s) => bar(&s.mesh, 1.0, Some(0)),
            Spec::TwoBars(s) => bar(&s.mesh, 2.0, None),
            Spec::Body(s) => body::size(s, o),
            Spec::TwoBodies(s) => two_bodies::size(s, o),
            Spec::SpringMass(_) => Size {
                dim: 0,
                dofs: 1.0,
                exact: Some(1),
            },
        }
    }

    /// [`CaseFile::build`] without overrides, built once and shared: a report asks a case file
    /// for its sweeps, studies and figures many times, and some cases take long to build (the
    /// two-sphere pair, n = 16: 1.7 s).
    pub fn defaults(&self) -> Result<std::sync::Arc<dyn Case>> {
        if let Some(case) = self.defaults.0.get() {
            return Ok(case.clone());
        }
        let case: std::sync::Arc<dyn Case> = self.build(&Overrides::default())?.into();
        Ok(self.defaults.0.get_or_init(|| case).clone())
    }

    /// The validated case with `overrides` applied (a mesh override given to a case without
    /// that kind of mesh is refused: it would be ignored).
    pub fn build(&self, overrides: &Overrides) -> Result<Box<dyn Case>> {
        self.build_named(overrides).map_err(|e| overrides.named(e))
    }

    fn build_named(&self, overrides: &Overrides) -> Result<Box<dyn Case>> {
        self.check_overrides(overrides)?;
        Ok(match &self.spec {
            Spec::Bar1d(s) => Box::new(bar1d::Bar1d::from_spec(s.clone(), overrides)?),
            Spec::BarFlight(s) => {
                Box::new(bar_flight::BarFlightCase::from_spec(s.clone(), overrides)?)
            }
            Spec::Body(s) => Box::new(body::Body::from_spec((**s).clone(), overrides)?),
            Spec::SpringMass(s) => Box::new(spring_mass::SpringMassCase::from_spec(
                s.clone(),
                overrides,
            )?),
            Spec::TwoBars(s) => Box::new(two_bars::TwoBars::from_spec(s.clone(), overrides)?),
            Spec::TwoBodies(s) => {
                Box::new(two_bodies::TwoBodies::from_spec(*s.clone(), overrides)?)
            }
        })
    }

    /// Completes a run specification as the case will when it builds, with what it takes from
    /// its own tables (the spring's physical restitution), so that a study keys the run by the
    /// parameters it uses.
    pub fn complete(&self, run: &mut RunSpec) -> Result<()> {
        match &self.spec {
            Spec::SpringMass(s) => spring_mass::physical_restitution(run, s.system.restitution),
            _ => Ok(()),
        }
    }

    /// The case file's own mesh file (`[mesh] file`, relative to the case file), if any.
    pub fn mesh_file(&self) -> Option<&PathBuf> {
        match &self.spec {
            Spec::Body(s) => s.mesh.file.as_ref(),
            Spec::TwoBodies(s) => s.mesh.file.as_ref(),
            _ => None,
        }
    }

    /// The files a command reads for this case file with `o`: the case file and its mesh
    /// (`--mesh`, else `[mesh] file`), for [`crate::input::refuse_overwrite`].
    pub fn inputs(&self, o: &Overrides) -> Vec<crate::input::Named> {
        let mesh = o.mesh.as_ref().or(self.mesh_file()).cloned();
        std::iter::once(("case file", self.path.clone()))
            .chain(mesh.map(|m| ("mesh file", m)))
            .collect()
    }

    /// Refuses the overrides the case would ignore (a mesh override given to a case without
    /// that kind of mesh), naming the flag.
    pub fn check_overrides(&self, o: &Overrides) -> Result<()> {
        let (refused, why): (&[&str], &str) = match self.spec {
            Spec::Body(_) => (&[], ""),
            Spec::TwoBodies(_) => (
                &["--incidence"],
                "applies to one body: two bodies meet head-on along e_d",
            ),
            Spec::Bar1d(_) | Spec::BarFlight(_) | Spec::TwoBars(_) => (
                &["--mesh", "--cells", "--friction", "--incidence"],
                "applies to the 2D/3D body cases only",
            ),
            Spec::SpringMass(_) => (
                &[
                    "--mesh",
                    "--cells",
                    "--elements",
                    "--degree",
                    "--friction",
                    "--incidence",
                ],
                "applies to meshed cases only: spring_mass has one dof",
            ),
        };
        let given = [
            ("--mesh", o.mesh.as_ref().map(|m| m.display().to_string())),
            ("--cells", o.cells.clone()),
            ("--elements", o.elements.map(|n| n.to_string())),
            ("--degree", o.degree.map(|n| n.to_string())),
            ("--friction", o.friction.map(|m| m.to_string())),
            ("--incidence", o.incidence.map(|m| m.to_string())),
        ];
        if let Some((flag, value)) = given
            .into_iter()
            .filter(|(f, _)| refused.contains(f))
            .find_map(|(f, v)| Some((f, v?)))
        {
            return Err(Error::invalid(flag, value, why));
        }
        // A mesh file (the case's own or --mesh) fixes the cells: a sweep's `elements` or
        // `degree` is refused here, before any run, named as the sweep's field.
        if let Some(file) = o.mesh.as_ref().or(self.mesh_file()) {
            body::refuse_generated(o, &file.display().to_string())?;
        }
        Ok(())
    }
}

/// A mesh file named in the case file at `path` is relative to the case file's directory.
fn beside(file: &mut Option<PathBuf>, path: &Path) {
    if let (Some(f), Some(dir)) = (file.as_ref(), path.parent()) {
        *file = Some(dir.join(f));
    }
}

/// The case files (`*.toml`) of `dir`, sorted; an error saying where they are expected when
/// `dir` cannot be read.
pub fn case_paths(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).map_err(|source| Error::NoCaseDirectory {
        dir: std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf()),
        source,
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    Ok(files)
}

/// The first comment line of a case file, up to ` (`, `: ` or a full stop.
fn title(text: &str) -> String {
    let first = text
        .lines()
        .find_map(|l| l.trim().strip_prefix('#'))
        .unwrap_or("")
        .trim();
    let end = [" (", ": ", ". "]
        .iter()
        .filter_map(|m| first.find(m))
        .min()
        .unwrap_or(first.len());
    first[..end].trim_end_matches('.').to_string()
}

/// Reads, parses and validates a case file, applying `overrides` (errors name the file).
pub fn load(path: &Path, overrides: &Overrides) -> Result<Box<dyn Case>> {
    CaseFile::read(path)
        .and_then(|f| f.build(overrides))
        .map_err(|e| e.in_case_file(path))
}

/// Deserialises case-file text into the spec of one case kind (`path` is only used in messages).
pub fn spec_from_str<T: DeserializeOwned>(text: &str, path: &Path) -> Result<T> {
    toml::from_str(text).map_err(|e: toml::de::Error| Error::CaseSyntax {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Parses case-file text and validates it with `overrides` (`path` is only used in messages).
pub fn parse(text: &str, path: &Path, overrides: &Overrides) -> Result<Box<dyn Case>> {
    CaseFile::parse(text.to_string(), path)?.build(overrides)
}

#[cfg(test)]
mod tests {
    use super::RunSpec;

    /// A solver set to other than its default enters the `parameters` column (and so the run's
    /// key); the defaults, set or not, leave it as it was, and a linear solver is left out for
    /// a scheme that solves no linear system.
    #[test]
    fn solvers_other_than_the_defaults_are_parameters() {
        let with = |scheme: &str, contact: Option<&str>, linear: Option<&str>| {
            let mut spec = RunSpec::new("standard", scheme, 0.1, 1.0);
            spec.options.contact_solver = contact.map(Into::into);
            spec.options.linear_solver = linear.map(Into::into);
            spec.parameters().unwrap()
        };
        let newmark = "beta=0.5;gamma=0.5";
        assert_eq!(with("newmark", None, None), newmark);
        assert_eq!(with("newmark", Some("active_set"), Some("auto")), newmark);
        assert_eq!(
            with("newmark", Some("projected_gauss_seidel"), Some("cg")),
            format!("{newmark};contact_solver=projected_gauss_seidel;linear_solver=cg")
        );
        assert_eq!(
            with("backward_euler", Some("alart_curnier"), None),
            "contact_solver=alart_curnier"
        );
        assert_eq!(
            with("backward_euler", None, Some("direct")),
            "linear_solver=direct"
        );
        assert_eq!(with("taylor_flanagan", None, Some("cg")), "");
        let mut weak = RunSpec::new("standard", "backward_euler", 0.1, 1.0);
        weak.options.contact = Some("weak".into());
        weak.options.contact_multiplier = Some("p0".into());
        weak.options.contact_solver = Some("clarabel".into());
        assert_eq!(
            weak.parameters().unwrap(),
            "contact=weak_p0;contact_solver=clarabel"
        );
    }
}
