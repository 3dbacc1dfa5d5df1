//! One run: case × space × scheme × (h, dt) → time series at the contact probe and summary metrics,
//! written as `timeseries.csv`, `summary.csv`, `energy.png` and `contact.png`.

use super::metrics::{self, Metrics, METRIC_COLUMNS};
use super::trajectory::{self, Row};
use crate::cases::{Case, Impact};
use crate::error::{Error, Result};
use crate::output::plot::{time_plot, Series, Style, PALETTE};
use crate::output::vtu::{Fields, VtuSeries};
use crate::output::{csv::write_rows, fmt_float};
use crate::problem::{EnergyForm, Problem};
use crate::time::{Integrator, State};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::Path;
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Identification and cost of a run; [`Metrics`] hold the numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Case kind.
    pub case: String,
    /// Space name.
    pub space: String,
    /// Scheme name.
    pub scheme: String,
    /// Scheme parameters, `key=value;…`, with the formulation's and the solvers' other than
    /// the defaults ([`crate::cases::RunSpec::parameters`]).
    pub parameters: String,
    /// Contact formulation as labelled (`nodal`, `weak_p1`, `nitsche`, `penalty`).
    pub contact: String,
    /// Polynomial degree of the displacement (None for 0D).
    pub degree: Option<usize>,
    /// Cell shape (`segment`, `triangle`, `quad`, `tet`, `hex`; empty for 0D).
    pub cells: String,
    /// Mesh size (NaN for 0D).
    pub h: f64,
    /// Time step.
    pub dt: f64,
    /// Displacement dofs.
    pub dofs: usize,
    /// Steps taken.
    pub steps: usize,
    /// Total contact-solver iterations.
    pub contact_iterations: usize,
    /// Wall time of the time loop in seconds (not deterministic; kept apart in reports).
    pub wall_time: f64,
    /// Peak resident memory of the process when the run ended, bytes (`VmHWM`; with runs in
    /// parallel, an upper bound of this run's; NaN where unknown).
    pub max_rss: f64,
    /// Metrics of DESIGN.md §6.
    pub metrics: Metrics,
}

/// A scheme with its parameters as every output writes it: `newmark (beta=0.5;gamma=0.5)`, the
/// `parameters` column of the records in parentheses (the scheme alone when it has none).
pub fn method_label(scheme: &str, parameters: &str) -> String {
    if parameters.is_empty() {
        scheme.to_string()
    } else {
        format!("{scheme} ({parameters})")
    }
}

impl Summary {
    /// [`method_label`] of this run.
    pub fn method(&self) -> String {
        method_label(&self.scheme, &self.parameters)
    }
}

/// The state at the sample of largest total contact force (impact cases).
#[derive(Debug, Clone, Default)]
pub struct Peak {
    /// Time.
    pub t: f64,
    /// Displacement.
    pub u: Vec<f64>,
    /// Nodal contact forces.
    pub lambda: Vec<f64>,
}

impl Peak {
    fn fill(&mut self, s: &State<'_>) {
        self.t = s.t;
        self.u.clear();
        self.u.extend_from_slice(s.u);
        self.lambda.clear();
        self.lambda.extend_from_slice(s.lambda);
    }
}

/// Result of [`run`].
#[derive(Debug, Clone)]
pub struct RunResult {
    /// Probe time series.
    pub rows: Vec<Row>,
    /// The state at peak contact force (impact cases, else None).
    pub peak: Option<Peak>,
    /// Summary.
    pub summary: Summary,
    /// The work of the loads across the bodies' extent, `‖F‖₁ D` (D the diagonal of the box
    /// around the meshes; 0 without loads or mesh): the energy scale of a run whose E(0)
    /// vanishes by the choice of the potential's origin ([`super::jobs::blowup`]).
    pub load_scale: f64,
}

/// Runs the case with its `[run]` settings (no progress bar).
pub fn run(case: &dyn Case) -> Result<RunResult> {
    run_with_progress(case, false)
}

/// Field output of a run (`run --vtu DIR --vtu-every K`): the `.vtu` files of every K-th sample
/// (the initial state included) and their `.pvd` collection, see [`crate::output::vtu`].
#[derive(Debug, Clone)]
pub struct FieldOutput {
    /// Output directory.
    pub dir: std::path::PathBuf,
    /// Write every `every`-th sample (≥ 1).
    pub every: usize,
}

/// Runs the case; with `progress`, a bar with steps/s and ETA appears on stderr once the time
/// loop has taken [`PROGRESS_AFTER`].
///
/// The time loop only steps and copies the state: the probe row (energy included) and the field
/// errors of each sample are computed on a second thread from recycled copies, so a run costs
/// what its solver costs on two cores.
///
/// The first non-finite quantity stops the run with [`Error::Diverged`] naming the step, the
/// time and the quantity: U, V and λ are checked by the time loop after every step, the sampled
/// quantities (energy, gap, probe values, approach, field errors) by the sampling thread, which
/// sees the samples in order, so the earlier of the two failures is the one reported.
pub fn run_with_progress(case: &dyn Case, progress: bool) -> Result<RunResult> {
    run_with_output(case, progress, None)
}

/// As [`run_with_progress`], with field output when `fields` is given (body cases only: an
/// error names the case otherwise).
pub fn run_with_output(
    case: &dyn Case,
    progress: bool,
    fields: Option<&FieldOutput>,
) -> Result<RunResult> {
    let timer = super::profile::Timer::start();
    let result = simulate(case, progress, fields);
    if let Some(t) = timer {
        let spec = case.run();
        let (dofs, status) = result
            .as_ref()
            .map_or((0, "error"), |r| (r.summary.dofs, "ok"));
        // A 0D case has no h (NaN): left out rather than written as NaN.
        let h = Some(case.h())
            .filter(|h| !h.is_nan())
            .map_or(String::new(), |h| format!(" h={h:.4e}"));
        t.stop(
            "run",
            &format!(
                "{} {} {} {}{h} dt={:.4e} steps={} dofs={dofs} {status}",
                case.kind(),
                spec.space,
                spec.scheme,
                spec.parameters().unwrap_or_default(),
                spec.dt,
                spec.steps()
            ),
        );
    }
    result
}

/// The run of [`run_with_output`].
fn simulate(case: &dyn Case, progress: bool, fields: Option<&FieldOutput>) -> Result<RunResult> {
    let spec = case.run();
    // The bodies written and, for several, each row's force on their Γ_C vertices.
    let bodies = case.multi_body();
    let shares = match (fields, bodies) {
        (Some(_), Some(b)) => b.vertex_shares()?,
        _ => Vec::new(),
    };
    // Two bodies: their interface's small-sliding limit, checked at every sample.
    let mut sliding = bodies
        .map(|b| crate::fem::sliding::SmallSliding::new(b, 0, 1))
        .transpose()?;
    let mut parts = match bodies {
        Some(b) => b.parts.iter().collect(),
        None => case.discretisation().into_iter().collect::<Vec<_>>(),
    };
    let extent = diagonal(&parts);
    parts.retain(|p| p.dim() >= 2);
    let mut vtu = match fields {
        None => None,
        Some(_) if parts.is_empty() => {
            return Err(Error::Unsupported(format!(
                "field output (--vtu) needs a 2D/3D body case, not {}",
                case.kind()
            )))
        }
        Some(f) => Some(VtuSeries::of_bodies(parts, &f.dir, case.kind(), f.every)?),
    };
    let steps = spec.steps();
    // The time series and field errors kept per step (rows, copies in flight aside).
    let per_step = (std::mem::size_of::<Row>() + 16) as f64;
    crate::util::check_memory("run.t_end", spec.t_end, (steps + 1) as f64 * per_step)?;
    let space = crate::space::by_name(&spec.space)?;
    let scheme = crate::time::by_name(&spec.scheme, spec.params())?;
    let formulation = crate::contact::formulation(&spec.options)?;
    let mut problem = case.problem(space.as_ref())?;
    formulation.check_scheme(scheme.name(), scheme.enforcement())?;
    crate::time::check_friction(&problem, scheme.as_ref(), formulation.as_ref())?;
    let friction = problem.contact.friction.is_some();
    let solver = formulation.setup(&mut problem, spec.options.contact_solver_with(friction))?;
    let field = case.field_error();
    let exact = case.exact();
    let impact = case.impact();
    let start = Instant::now();
    let solvers = crate::time::Solvers {
        contact: solver,
        linear: crate::time::LinearSolver::by_name(spec.options.linear_solver())?,
    };
    let parameters = crate::time::entry(&spec.scheme)?.describe(spec.params());
    let mut integrator = scheme
        .prepare(&problem, spec.dt, solvers)
        .map_err(|e| formulation.explain(e).at_time_step(spec.dt, &parameters))?;
    let mut bar = Progress::new(progress, steps);
    let (rows, field_errors, mut peak, iterations, masses) =
        std::thread::scope(|scope| -> Result<_> {
            let (tx, rx) = mpsc::sync_channel::<Snapshot>(SAMPLE_QUEUE);
            let (recycle, recycled) = mpsc::channel();
            let (problem, field) = (&problem, &field);
            let master: Option<Vec<(usize, usize, f64)>> =
                bodies.map(|b| b.master_probe()).transpose()?.map(|w| {
                    w.into_iter()
                        .map(|(j, n)| (j, problem.inertia.velocity_dof(j), n))
                        .collect()
                });
            let mut probe = Probe {
                b_row: problem.contact.gap_row(problem.probe.contact),
                energy: problem.energy_form(),
                impact: impact.as_ref(),
                translation: case.momentum().map(|t| (t, vec![0.0; problem.n()])),
                mean: MeanVelocity::new(problem, master.as_deref()),
                master,
                slide: friction.then(|| slide_direction(problem)),
                spin: case.spin().map(|spin| SpinProbe::new(problem, spin)),
            };
            let masses = probe
                .slide
                .as_ref()
                .zip(probe.spin.as_ref())
                .map(|(t, s)| (t.1, s.normal.1));
            let sampler = scope.spawn(move || -> Result<_> {
                let mut rows: Vec<Row> = Vec::with_capacity(steps + 1);
                let mut errors = Vec::with_capacity(if field.is_some() { steps + 1 } else { 0 });
                // The state at the sample of largest total force (impact cases).
                let (mut peak, mut f_peak) = (Peak::default(), 0.0);
                for (index, snap) in rx.into_iter().enumerate() {
                    let s = snap.state();
                    // Checked before any output of the sample: no field file of a NaN.
                    let row = probe_row(problem, &mut probe, &s, exact);
                    if let Some((what, value)) = row.non_finite() {
                        return Err(diverged(index, s.t, what, value));
                    }
                    if let Some(c) = sliding.as_mut() {
                        if let Some(reason) = c.check(s.u, s.lambda)? {
                            let (step, time) = (index, s.t);
                            return Err(Error::SmallSliding { step, time, reason });
                        }
                    }
                    if let Some(out) = vtu.as_mut() {
                        match bodies {
                            Some(b) => {
                                let split = b.split(&shares, s.u, s.v, s.lambda);
                                let each: Vec<Fields> = split
                                    .iter()
                                    .map(|f| Fields {
                                        t: s.t,
                                        u: &f.u,
                                        v: &f.v,
                                        lambda: &f.lambda,
                                    })
                                    .collect();
                                out.sample_bodies(index, &each)?;
                            }
                            None => out.sample(
                                index,
                                &Fields {
                                    t: s.t,
                                    u: s.u,
                                    v: s.v,
                                    lambda: &problem.contact.vertex_forces(s.lambda).0,
                                },
                            )?,
                        }
                    }
                    if probe.impact.is_some() && row.force_contact > f_peak {
                        f_peak = row.force_contact;
                        peak.fill(&s);
                    }
                    rows.push(row);
                    if let Some(f) = field {
                        let e = f.errors(s.u, s.t);
                        // The H¹ error is NaN where it is not computed.
                        let h1 = if e.1.is_nan() { 0.0 } else { e.1 };
                        if let Some((what, value)) =
                            [("L² field error", e.0), ("H¹ field error", h1)]
                                .into_iter()
                                .find(|(_, v)| !v.is_finite())
                        {
                            return Err(diverged(index, s.t, what, value));
                        }
                        errors.push(e);
                    }
                    // The time loop may have finished: a snapshot nobody reuses is dropped.
                    let _ = recycle.send(snap);
                }
                Ok((rows, errors, peak))
            });
            // A failed send means the sampler stopped on an error, which its join reports.
            let send = |it: &dyn Integrator| {
                let mut snap: Snapshot = recycled.try_recv().unwrap_or_default();
                snap.fill(&it.state());
                tx.send(snap).is_ok()
            };
            let mut iterations = 0;
            let mut stepped = Ok(());
            if send(integrator.as_ref()) {
                for n in 0..steps {
                    match integrator.step() {
                        Ok(info) => iterations += info.contact_iterations,
                        Err(e) => {
                            stepped = Err(e);
                            break;
                        }
                    }
                    if !send(integrator.as_ref()) {
                        break;
                    }
                    bar.update(n + 1);
                }
            }
            drop(tx);
            // The sampler's error is at an earlier step than the loop's, or the same.
            let sampled = sampler
                .join()
                .map_err(|_| Error::Internal("the sampling thread panicked".into()))?;
            let (rows, errors, peak) = sampled.and_then(|r| stepped.map(|()| r))?;
            if rows.len() != steps + 1 {
                return Err(Error::Internal("the sampling thread stopped".into()));
            }
            Ok((rows, errors, peak, iterations, masses))
        })?;
    bar.finish();
    let wall_time = start.elapsed().as_secs_f64();
    let mut metrics = metrics::compute(
        &rows,
        &field_errors,
        spec.dt,
        case.stress_is_function(),
        exact.and_then(|e| e.first_impact()),
    );
    // The impact metrics and figures read forces per vertex of Γ_C.
    let (vertex_lambda, vertex_area) = problem.contact.vertex_forces(&peak.lambda);
    let vertex_lambda = vertex_lambda.into_owned();
    if let Some(i) = &impact {
        metrics::hertz(&mut metrics, &rows, (&vertex_lambda, vertex_area), i);
    }
    metrics::friction(&mut metrics, &rows, case.slide().as_ref());
    // The impulses are the momentum the contact changed: a load (gravity) would add its own.
    if let Some(masses) = masses.filter(|_| problem.f.iter().all(|&f| f == 0.0)) {
        metrics::oblique(&mut metrics, &rows, masses);
    }
    metrics.drop_non_finite();
    peak.lambda = vertex_lambda;
    Ok(RunResult {
        load_scale: problem.f.iter().map(|f| f.abs()).sum::<f64>() * extent,
        rows,
        peak: impact.is_some().then_some(peak),
        summary: Summary {
            case: case.kind().to_string(),
            space: space.name().to_string(),
            scheme: scheme.name().to_string(),
            parameters: spec.parameters()?,
            contact: formulation.label(),
            degree: case.element().map(|e| e.1),
            cells: case.element().map_or(String::new(), |e| e.0.to_string()),
            h: case.h(),
            dt: spec.dt,
            dofs: problem.n(),
            steps,
            contact_iterations: iterations,
            wall_time,
            max_rss: crate::util::peak_memory().unwrap_or(f64::NAN),
            metrics,
        },
    })
}

/// The error of a sample whose quantity `what` is `value`, not finite. At step 0 no step has
/// run: the initial state itself overflows, and the message says where to look.
fn diverged(step: usize, time: f64, what: &str, value: f64) -> Error {
    let before = if step == 0 {
        " in the initial state, before any step: an initial condition (the velocity, the lift) \
         or a material parameter of the case overflows"
    } else {
        ""
    };
    Error::Diverged {
        step,
        time,
        reason: format!("{what} is {value}{before}"),
    }
}

/// The diagonal of the box around the nodes of `parts` (0 without a node).
fn diagonal(parts: &[&crate::fem::discretisation::Discretisation]) -> f64 {
    if parts.iter().all(|p| p.mesh.nodes.is_empty()) {
        return 0.0;
    }
    let side = |k: usize| {
        let (lo, hi) = parts
            .iter()
            .map(|p| p.mesh.extent(k))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| {
                (lo.min(a), hi.max(b))
            });
        hi - lo
    };
    (0..3).map(|k| side(k).powi(2)).sum::<f64>().sqrt()
}

/// Snapshots in flight between the time loop and the sampling thread.
const SAMPLE_QUEUE: usize = 8;

/// The time loop's state copied for the sampling thread (buffers recycled between steps).
#[derive(Debug, Default)]
struct Snapshot {
    t: f64,
    u: Vec<f64>,
    v: Vec<f64>,
    /// The energy displacement when it is not U itself (three-level schemes).
    energy_u: Option<Vec<f64>>,
    lambda: Vec<f64>,
    extra_energy: f64,
    friction_work: f64,
}

impl Snapshot {
    fn fill(&mut self, s: &State<'_>) {
        let copy = |dst: &mut Vec<f64>, src: &[f64]| {
            dst.clear();
            dst.extend_from_slice(src);
        };
        self.t = s.t;
        self.extra_energy = s.extra_energy;
        self.friction_work = s.friction_work;
        copy(&mut self.u, s.u);
        copy(&mut self.v, s.v);
        copy(&mut self.lambda, s.lambda);
        if std::ptr::eq(s.energy_u, s.u) {
            self.energy_u = None;
        } else {
            copy(self.energy_u.get_or_insert_with(Vec::new), s.energy_u);
        }
    }

    fn state(&self) -> State<'_> {
        State {
            t: self.t,
            step: 0,
            u: &self.u,
            v: &self.v,
            energy_u: self.energy_u.as_deref().unwrap_or(&self.u),
            lambda: &self.lambda,
            extra_energy: self.extra_energy,
            friction_work: self.friction_work,
        }
    }
}

/// A run is this long before its progress bar appears.
pub const PROGRESS_AFTER: Duration = Duration::from_secs(2);

/// Progress of the time loop: a bar (steps/s, ETA) created once the loop has run for
/// [`PROGRESS_AFTER`], only when asked for.
struct Progress {
    enabled: bool,
    start: Instant,
    steps: usize,
    bar: Option<ProgressBar>,
}

impl Progress {
    fn new(enabled: bool, steps: usize) -> Self {
        Self {
            enabled,
            start: Instant::now(),
            steps,
            bar: None,
        }
    }

    fn update(&mut self, step: usize) {
        if !self.enabled || !step.is_multiple_of(32) {
            return;
        }
        if self.bar.is_none() && self.start.elapsed() >= PROGRESS_AFTER {
            let bar = ProgressBar::new(self.steps as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:40} {pos}/{len} steps, {per_sec}, {elapsed} elapsed, ETA {eta}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            self.bar = Some(bar);
        }
        if let Some(b) = &self.bar {
            b.set_position(step as u64);
        }
    }

    fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

/// What the sampling thread evaluates at every sample besides the probe dofs.
struct Probe<'a> {
    /// The row of the probe's physical gap ([`crate::problem::Contact::gap_row`]).
    b_row: Vec<(usize, f64)>,
    energy: EnergyForm,
    /// The impact of the curved-body cases, for Hertz's approach ([`Impact::approach`]).
    impact: Option<&'a Impact>,
    /// The unit translation `1_d` of a multi-body case and a buffer for `M̃V`.
    translation: Option<(Vec<f64>, Vec<f64>)>,
    /// A multi-body case's master point facing the probe: `(u dof, inertial velocity dof, N_k)`.
    master: Option<Vec<(usize, usize, f64)>>,
    /// With friction: the unit translation along the first tangent with its buffer, and the
    /// mass `1ᵀM̃1` (the centre of mass's velocity is `(M̃1)ᵀV / 1ᵀM̃1`).
    slide: Option<Slide>,
    /// A disc or sphere with friction: its normal velocity and angular velocity.
    spin: Option<SpinProbe>,
    /// The velocity of a massless probe point.
    mean: MeanVelocity,
}

/// The velocity of a probe point whose dofs carry no mass (mass redistribution's Γ_C normal
/// dofs): no dynamics fixes their velocity variable, which a scheme's update (Newmark's
/// `v_{n+1} = vₙ + Δt ((1 − γ) aₙ + γ a_{n+1})` with the Newmark a of the displacements) carries
/// with an odd–even oscillation (the bar's end read +½ while it moved at −½). Such a point's
/// velocity is the mean over the last step, `(u_n − u_{n−1}) / (t_n − t_{n−1})`; the first
/// sample keeps the initial velocity.
#[derive(Debug)]
struct MeanVelocity {
    /// Whether the probe's dof, and any of the master point's dofs, are massless.
    probe: bool,
    master: bool,
    /// The last sample's `(t, u_contact, u_contact_master)`.
    last: Option<(f64, f64, f64)>,
}

impl MeanVelocity {
    fn new(problem: &Problem, master: Option<&[(usize, usize, f64)]>) -> Self {
        let massless = problem.inertia.massless();
        MeanVelocity {
            probe: massless[problem.probe.u_dof],
            master: master.is_some_and(|w| w.iter().any(|&(j, _, _)| massless[j])),
            last: None,
        }
    }

    /// Replaces a massless point's velocity in `row` by its mean over the last step.
    fn apply(&mut self, row: &mut Row) {
        let master_u = row.master.map_or(0.0, |m| m.0);
        if let Some((t, u, m)) = self.last {
            let dt = row.t - t;
            if self.probe {
                row.v_contact = (row.u_contact - u) / dt;
            }
            if let Some(point) = row.master.as_mut().filter(|_| self.master) {
                point.1 = (point.0 - m) / dt;
            }
        }
        self.last = Some((row.t, row.u_contact, master_u));
    }
}

/// The normal translation and the rotation of [`crate::cases::Spin`], each with its buffer and
/// its mass (`1_dᵀM̃1_d`, the moment of inertia `φᵀM̃φ`), φ made M̃-orthogonal to the
/// translations along e_1 and e_d so that `(M̃φ)ᵀV` is the angular momentum about the centre
/// of mass.
struct SpinProbe {
    normal: Slide,
    rotation: Slide,
}

impl SpinProbe {
    fn new(problem: &Problem, spin: crate::cases::Spin) -> Self {
        // `(a, M̃ project(b))`, the space's mass as an inner product of U-layout fields.
        let inner = |a: &[f64], b: &[f64]| {
            let inertial = problem.inertia.project(b).unwrap_or_else(|_| b.to_vec());
            momentum(
                problem,
                &mut (a.to_vec(), vec![0.0; problem.n()]),
                &inertial,
            )
        };
        let tangent = problem
            .contact
            .friction
            .as_ref()
            .map_or_else(|| vec![0.0; problem.n()], |f| f.translation.clone());
        let mut phi = spin.rotation;
        for t in [&tangent, &spin.normal] {
            let (c, m) = (inner(t, &phi), inner(t, t));
            if m > 0.0 {
                crate::linalg::axpy(&mut phi, -c / m, t);
            }
        }
        let buffer = || vec![0.0; problem.n()];
        let (m_n, inertia) = (inner(&spin.normal, &spin.normal), inner(&phi, &phi));
        Self {
            normal: ((spin.normal, buffer()), m_n),
            rotation: ((phi, buffer()), inertia),
        }
    }

    /// `(v_n, ω)` of the inertial velocity v.
    fn velocities(&mut self, problem: &Problem, v: &[f64]) -> (f64, f64) {
        let of = |(t, mass): &mut Slide| momentum(problem, t, v) / *mass;
        (of(&mut self.normal), of(&mut self.rotation))
    }
}

/// The unit translation along the first tangent of the plane, a buffer for `M̃V`, the mass
/// `1ᵀM̃1`.
type Slide = ((Vec<f64>, Vec<f64>), f64);

/// The translation along the first tangent ([`crate::problem::Friction::translation`]), its
/// buffer and the mass it carries, `1ᵀM̃1`.
fn slide_direction(problem: &Problem) -> Slide {
    let one = problem
        .contact
        .friction
        .as_ref()
        .map_or_else(|| vec![0.0; problem.n()], |f| f.translation.clone());
    let inertial = problem
        .inertia
        .project(&one)
        .unwrap_or_else(|_| one.clone());
    let mut t = (one, vec![0.0; problem.n()]);
    let mass = momentum(problem, &mut t, &inertial);
    (t, mass)
}

/// The momentum `(M̃1_d)ᵀV = 1_dᵀ(Lᵀv)`: the inertial force of the inertial velocity v
/// (`M̃V` for a sparse mass, `BᵀC⁻¹BV` for the mixed one) along the translation `1_d`.
fn momentum(problem: &Problem, (one, mv): &mut (Vec<f64>, Vec<f64>), v: &[f64]) -> f64 {
    mv.fill(0.0);
    problem.inertia.apply_add(mv, v, 1.0);
    one.iter().zip(mv.iter()).map(|(a, b)| a * b).sum()
}

/// The probe's row of the time series.
fn probe_row(
    problem: &Problem,
    probe: &mut Probe<'_>,
    s: &State<'_>,
    exact: Option<&dyn crate::exact::ExactContact>,
) -> Row {
    let p = problem.probe;
    let mut row = Row {
        t: s.t,
        u_contact: s.u[p.u_dof],
        v_contact: s.v[p.w_dof],
        sigma_contact: problem.contact_stress(s.lambda, p.contact),
        energy: probe.energy.energy(s.energy_u, s.v) + s.extra_energy,
        gap: problem.contact.g0[p.contact] - crate::linalg::row_dot(&probe.b_row, s.u),
        force_contact: s.lambda.iter().sum(),
        approach: probe.impact.map(|i| i.approach(s.u)),
        momentum: probe
            .translation
            .as_mut()
            .map(|t| momentum(problem, t, s.v)),
        master: probe.master.as_ref().map(|w| {
            w.iter().fold((0.0, 0.0), |(u, v), &(j, k, n)| {
                (u + n * s.u[j], v + n * s.v[k])
            })
        }),
        friction: probe
            .slide
            .as_mut()
            .map(|(t, mass)| (momentum(problem, t, s.v) / *mass, s.friction_work)),
        spin: probe.spin.as_mut().map(|p| p.velocities(problem, s.v)),
        exact: exact.map(|e| {
            let c = e.contact(s.t);
            (c.u, c.sigma, e.energy(s.t))
        }),
    };
    probe.mean.apply(&mut row);
    row
}

/// Columns of `summary.csv` before the metrics; the last two are machine-dependent
/// ([`TIMING_COLUMNS`]).
pub const RUN_COLUMNS: &[&str] = &[
    "case",
    "space",
    "scheme",
    "parameters",
    "contact",
    "degree",
    "cells",
    "h",
    "dt",
    "dofs",
    "steps",
    "contact_iterations",
    "wall_time_s",
    "max_rss_mb",
];

/// The machine-dependent columns of a summary, left out where outputs must be byte-identical.
pub const TIMING_COLUMNS: [&str; 2] = ["wall_time_s", "max_rss_mb"];

/// Peak memory in MiB as written: one decimal, empty where unknown.
pub fn fmt_mib(bytes: f64) -> String {
    if bytes.is_finite() {
        format!("{:.1}", bytes / 1048576.0)
    } else {
        String::new()
    }
}

/// Columns of `summary.csv`: [`RUN_COLUMNS`], then the metrics' [`METRIC_COLUMNS`].
pub fn summary_columns() -> Vec<&'static str> {
    RUN_COLUMNS
        .iter()
        .copied()
        .chain(METRIC_COLUMNS.iter().map(|c| c.name))
        .collect()
}

/// The fields of one summary row, in [`summary_columns`] order.
pub fn summary_record(s: &Summary) -> Vec<String> {
    let mut v = vec![
        s.case.clone(),
        s.space.clone(),
        s.scheme.clone(),
        s.parameters.clone(),
        s.contact.clone(),
        s.degree.map_or(String::new(), |d| d.to_string()),
        s.cells.clone(),
        fmt_float(Some(s.h)),
        fmt_float(Some(s.dt)),
        s.dofs.to_string(),
        s.steps.to_string(),
        s.contact_iterations.to_string(),
        format!("{:.6e}", s.wall_time),
        fmt_mib(s.max_rss),
    ];
    v.extend(
        METRIC_COLUMNS
            .iter()
            .map(|c| fmt_float((c.get)(&s.metrics))),
    );
    v
}

/// Writes `summary.csv` with one row per run.
pub fn write_summary(path: &Path, runs: &[Summary]) -> Result<()> {
    write_rows(path, &summary_columns(), runs.iter().map(summary_record))
}

/// `h = …, dt = …` of a run (`dt = …` alone for a 0D case, which has no h).
fn size(s: &Summary) -> String {
    if s.h.is_finite() {
        format!("h = {:.3e}, dt = {:.3e}", s.h, s.dt)
    } else {
        format!("dt = {:.3e}", s.dt)
    }
}

/// The files [`write_run`] writes into its directory.
pub const RUN_FILES: [&str; 6] = [
    "timeseries.csv",
    "summary.csv",
    "energy.png",
    "energy.svg",
    "contact.png",
    "contact.svg",
];

/// Writes `timeseries.csv`, `summary.csv`, `energy.png` and `contact.png` (each with its SVG) of
/// a run into `dir`.
pub fn write_run(dir: &Path, result: &RunResult) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    trajectory::write_timeseries(&dir.join("timeseries.csv"), &result.rows)?;
    write_summary(
        &dir.join("summary.csv"),
        std::slice::from_ref(&result.summary),
    )?;
    let s = &result.summary;
    let label = format!("{} + {}", s.space, s.method());
    let curve = |f: &dyn Fn(&Row) -> f64| result.rows.iter().map(|r| (r.t, f(r))).collect();
    let exact = |f: &dyn Fn((f64, f64, f64)) -> f64| -> Vec<(f64, f64)> {
        result
            .rows
            .iter()
            .filter_map(|r| r.exact.map(|e| (r.t, f(e))))
            .collect()
    };
    let with_exact = |main: Series, ex: Vec<(f64, f64)>| {
        let mut v = vec![main];
        if !ex.is_empty() {
            v.push(Series::reference("exact", ex));
        }
        v
    };
    time_plot(
        &dir.join("energy.png"),
        &format!("{}: total energy, {}", s.case, size(s)),
        "total energy E",
        &with_exact(
            Series::new(label.clone(), curve(&|r| r.energy), Style::line(PALETTE[0])),
            exact(&|e| e.2),
        ),
    )?;
    time_plot(
        &dir.join("contact.png"),
        &format!("{}: contact stress at the probe, {}", s.case, size(s)),
        "contact stress σₙ at the probe (compression < 0)",
        &with_exact(
            Series::new(label, curve(&|r| r.sigma_contact), Style::line(PALETTE[0])),
            exact(&|e| e.1),
        ),
    )
}
