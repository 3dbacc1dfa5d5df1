//! One run: case × space × scheme × (h, dt) → time series at the contact probe and summary metrics,
//! written as `timeseries.csv`, `summary.csv`, `energy.png` and `contact.png`.

use super::metrics::{self, Metrics};
use super::trajectory::{self, Row};
use crate::cases::Case;
use crate::error::{Error, Result};
use crate::output::plot::{time_plot, Series, PALETTE};
use crate::output::{csv::write_rows, fmt_float};
use crate::problem::Problem;
use crate::time::Integrator;
use std::path::Path;
use std::time::Instant;

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

/// Columns of `summary.csv`.
pub const SUMMARY_COLUMNS: &[&str] = &[
    "case",
    "space",
    "scheme",
    "parameters",
    "h",
    "dt",
    "dofs",
    "steps",
    "contact_iterations",
    "wall_time_s",
    "energy_drift",
    "energy_ratio",
    "max_penetration",
    "err_u_linf_l2",
    "err_u_l2_h1",
    "err_sigma_l2",
    "err_energy",
    "err_u_contact",
    "sigma_total_variation",
    "restitution_eff",
    "impact_time_err",
];

/// The fields of one summary row, in [`SUMMARY_COLUMNS`] order.
pub fn summary_record(s: &Summary) -> Vec<String> {
    let m = &s.metrics;
    let mut v = vec![
        s.case.clone(),
        s.space.clone(),
        s.scheme.clone(),
        s.parameters.clone(),
        fmt_float(Some(s.h)),
        fmt_float(Some(s.dt)),
        s.dofs.to_string(),
        s.steps.to_string(),
        s.contact_iterations.to_string(),
        format!("{:.6e}", s.wall_time),
    ];
    v.extend(
        [
            Some(m.energy_drift),
            Some(m.energy_ratio),
            Some(m.max_penetration),
            m.err_u_linf_l2,
            m.err_u_l2_h1,
            m.err_sigma_l2,
            m.err_energy,
            m.err_u_contact,
            Some(m.sigma_total_variation),
            m.restitution_eff,
            m.impact_time_err,
        ]
        .into_iter()
        .map(fmt_float),
    );
    v
}

/// Writes `summary.csv` with one row per run.
pub fn write_summary(path: &Path, runs: &[Summary]) -> Result<()> {
    write_rows(path, SUMMARY_COLUMNS, runs.iter().map(summary_record))
}

/// Writes `timeseries.csv`, `summary.csv`, `energy.png` and `contact.png` of a run into `dir`.
pub fn write_run(dir: &Path, result: &RunResult) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    trajectory::write_timeseries(&dir.join("timeseries.csv"), &result.rows)?;
    write_summary(
        &dir.join("summary.csv"),
        std::slice::from_ref(&result.summary),
    )?;
    let s = &result.summary;
    let label = format!("{} + {} ({})", s.space, s.scheme, s.parameters);
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
            v.push(Series::dashed("exact", ex, PALETTE[1]));
        }
        v
    };
    time_plot(
        &dir.join("energy.png"),
        &format!(
            "{}: total energy, h = {:.3e}, dt = {:.3e}",
            s.case, s.h, s.dt
        ),
        "energy",
        &with_exact(
            Series::solid(label.clone(), curve(&|r| r.energy), PALETTE[0]),
            exact(&|e| e.2),
        ),
    )?;
    time_plot(
        &dir.join("contact.png"),
        &format!("{}: contact stress at the contact point", s.case),
        "sigma_N (compression < 0)",
        &with_exact(
            Series::solid(label, curve(&|r| r.sigma_contact), PALETTE[0]),
            exact(&|e| e.1),
        ),
    )
}
