//! One run: case × space × scheme × (h, dt) → time series at the contact probe and summary metrics.

use crate::cases::Case;
use crate::error::Result;
use crate::metrics::{self, Metrics};
use crate::problem::Problem;
use crate::time::Integrator;
use std::time::Instant;

/// One sample of the probe time series (one per step, and t = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Time.
    pub t: f64,
    /// Displacement of the contact dof.
    pub u_contact: f64,
    /// Velocity of the contact point (inertial velocity dof of the probe).
    pub v_contact: f64,
    /// Normal contact stress σ_N = −λ/area (≤ 0).
    pub sigma_contact: f64,
    /// Total energy.
    pub energy: f64,
    /// Gap g = g₀ − B_N U at the probe.
    pub gap: f64,
    /// Exact `(u, σ_N, E)` at the contact point, when the case has an exact solution.
    pub exact: Option<(f64, f64, f64)>,
}

/// Identification and cost of a run; [`Metrics`] hold the numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Case kind.
    pub case: String,
    /// Space name.
    pub space: String,
    /// Scheme name.
    pub scheme: String,
    /// Scheme parameters, `key=value;…`.
    pub parameters: String,
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
    /// Metrics of DESIGN.md §6.
    pub metrics: Metrics,
}

/// Result of [`run`].
#[derive(Debug, Clone)]
pub struct RunResult {
    /// Probe time series.
    pub rows: Vec<Row>,
    /// Summary.
    pub summary: Summary,
}

/// Runs the case with its `[run]` settings.
pub fn run(case: &dyn Case) -> Result<RunResult> {
    let spec = case.run();
    let space = crate::space::by_name(&spec.space)?;
    let scheme = crate::time::by_name(&spec.scheme, spec.scheme_params())?;
    let problem = case.problem(space.as_ref())?;
    let solver =
        crate::contact::by_name(&spec.contact_solver, problem.contact.len(), spec.penalty)?;
    let field = case.field_error();
    let exact = case.exact();
    let start = Instant::now();
    let mut integrator = scheme.prepare(&problem, spec.dt, solver)?;
    let steps = spec.steps();
    let mut rows = Vec::with_capacity(steps + 1);
    let mut field_errors = Vec::with_capacity(steps + 1);
    let mut iterations = 0;
    let sample = |it: &dyn Integrator, rows: &mut Vec<Row>, errs: &mut Vec<(f64, f64)>| {
        let s = it.state();
        rows.push(probe_row(&problem, &s, exact));
        if let Some(f) = &field {
            errs.push(f.errors(s.u, s.t));
        }
    };
    sample(integrator.as_ref(), &mut rows, &mut field_errors);
    for _ in 0..steps {
        iterations += integrator.step()?.contact_iterations;
        sample(integrator.as_ref(), &mut rows, &mut field_errors);
    }
    let wall_time = start.elapsed().as_secs_f64();
    let metrics = metrics::compute(
        &rows,
        &field_errors,
        spec.dt,
        case.stress_is_function(),
        exact.and_then(|e| e.first_impact()),
    );
    Ok(RunResult {
        rows,
        summary: Summary {
            case: case.kind().to_string(),
            space: space.name().to_string(),
            scheme: scheme.name().to_string(),
            parameters: scheme.parameters(),
            h: case.h(),
            dt: spec.dt,
            dofs: problem.n(),
            steps,
            contact_iterations: iterations,
            wall_time,
            metrics,
        },
    })
}

fn probe_row(
    problem: &Problem,
    s: &crate::time::State<'_>,
    exact: Option<&dyn crate::exact::ExactContact>,
) -> Row {
    let p = problem.probe;
    Row {
        t: s.t,
        u_contact: s.u[p.u_dof],
        v_contact: s.v[p.w_dof],
        sigma_contact: problem.contact_stress(s.lambda, p.contact),
        energy: problem.energy(s.energy_u, s.v),
        gap: problem.contact.gap_at(s.u, p.contact),
        exact: exact.map(|e| {
            let c = e.contact(s.t);
            (c.u, c.sigma, e.energy(s.t))
        }),
    }
}
