//! The harness: every combination declared in the `[[sweep]]` tables of case files, run in
//! parallel (rayon) with a progress bar (indicatif), one [`RunRecord`] per run, and observed orders.
//!
//! A run that fails (solver failure, unstable time step, unsupported combination) or diverges
//! (NaN, or energy above [`BLOWUP_FACTOR`] × E(0)) is recorded with its status and reason; it never
//! aborts the sweep. Records come back in enumeration order, so outputs are deterministic.

use crate::cases::{self, sweep::Refinement, sweep::SchemeChoice, Case};
use crate::error::{Error, Result};
use crate::metrics::Metrics;
use crate::run::{self, RunResult, Summary};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A run whose energy exceeds this multiple of E(0) is recorded as diverged.
pub const BLOWUP_FACTOR: f64 = 100.0;

/// One combination to run.
#[derive(Debug, Clone)]
pub struct Job {
    /// Case file (for messages) and its text.
    pub path: Arc<PathBuf>,
    text: Arc<String>,
    /// Sweep name.
    pub sweep: String,
    /// Space.
    pub space: String,
    /// Scheme and parameters.
    pub choice: SchemeChoice,
    /// Level index (0 = coarsest).
    pub level: usize,
    /// Refinement of this level.
    pub refinement: Refinement,
    overrides: cases::Overrides,
}

/// Outcome of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Finished, energy bounded.
    Ok,
    /// NaN or energy blow-up.
    Diverged,
    /// Error before or during the run (unstable dt, solver failure, …).
    Failed,
    /// The combination is not defined (e.g. an explicit scheme with the singular dynamic mass).
    Unsupported,
}

impl Status {
    /// The status called `name` (as written by [`Status::as_str`]).
    pub fn parse(name: &str) -> Option<Self> {
        [
            Status::Ok,
            Status::Diverged,
            Status::Failed,
            Status::Unsupported,
        ]
        .into_iter()
        .find(|s| s.as_str() == name)
    }

    /// Name written to CSV.
    pub fn as_str(&self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Diverged => "diverged",
            Status::Failed => "failed",
            Status::Unsupported => "unsupported",
        }
    }
}

/// One row of `records.csv`.
#[derive(Debug, Clone)]
pub struct RunRecord {
    /// Sweep name.
    pub sweep: String,
    /// Level index.
    pub level: usize,
    /// Outcome.
    pub status: Status,
    /// Why the run is not `ok` (empty otherwise).
    pub reason: String,
    /// Identification, cost and metrics (metrics NaN/None when the run did not finish).
    pub summary: Summary,
    /// Probe series `(t, u_contact, σ_N)` of a finished run without exact solution, kept for
    /// [`reference_errors`] (empty otherwise, and after it).
    pub probe: Vec<(f64, f64, f64)>,
}

impl RunRecord {
    /// The run series a record belongs to: case × sweep × space × scheme × parameters (its
    /// levels differ only in h and dt).
    pub fn series_key(&self) -> (String, String, String, String, String) {
        let s = &self.summary;
        (
            s.case.clone(),
            self.sweep.clone(),
            s.space.clone(),
            s.scheme.clone(),
            s.parameters.clone(),
        )
    }
}

/// Distinct items in first-appearance order (so that outputs follow the enumeration order).
pub fn unique<T: PartialEq>(items: impl IntoIterator<Item = T>) -> Vec<T> {
    let mut v = Vec::new();
    for x in items {
        if !v.contains(&x) {
            v.push(x);
        }
    }
    v
}

/// Items grouped by `key`, groups and members in first-appearance order.
pub fn group_by<K: PartialEq, T>(
    items: impl IntoIterator<Item = T>,
    key: impl Fn(&T) -> K,
) -> Vec<(K, Vec<T>)> {
    let mut groups: Vec<(K, Vec<T>)> = Vec::new();
    for x in items {
        let k = key(&x);
        match groups.iter_mut().find(|(g, _)| *g == k) {
            Some((_, v)) => v.push(x),
            None => groups.push((k, vec![x])),
        }
    }
    groups
}

/// Enumerates the jobs of every `[[sweep]]` of the case file at `path` (`--quick`: the first
/// levels only). Errors on an invalid case file or sweep table, before anything runs.
pub fn jobs(path: &Path, quick: bool) -> Result<Vec<Job>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let case = cases::parse(&text, path, &cases::Overrides::default())?;
    if case.sweeps().is_empty() {
        return Err(Error::invalid(
            "sweep",
            path.display().to_string(),
            "the case file has no [[sweep]] table",
        ));
    }
    let (path, text) = (Arc::new(path.to_path_buf()), Arc::new(text));
    let mut out = Vec::new();
    for s in case.sweeps() {
        let levels = s.refinements(quick)?;
        for space in &s.spaces {
            crate::space::by_name(space)?;
            for choice in &s.schemes {
                for (level, &refinement) in levels.iter().enumerate() {
                    let overrides = s.overrides(space, choice, refinement);
                    let mut spec = case.run().clone();
                    overrides.apply(&mut spec);
                    spec.validate()?;
                    out.push(Job {
                        path: path.clone(),
                        text: text.clone(),
                        sweep: s.name.clone(),
                        space: space.clone(),
                        choice: choice.clone(),
                        level,
                        refinement,
                        overrides,
                    });
                }
            }
        }
    }
    Ok(out)
}

/// The jobs of shard `i` of `n` (1-based): every n-th job starting at i − 1.
pub fn shard(jobs: Vec<Job>, (i, n): (usize, usize)) -> Result<Vec<Job>> {
    if n == 0 || i == 0 || i > n {
        return Err(Error::invalid(
            "--shard",
            format!("{i}/{n}"),
            "must be i/n with 1 ≤ i ≤ n",
        ));
    }
    Ok(jobs
        .into_iter()
        .enumerate()
        .filter(|(k, _)| k % n == i - 1)
        .map(|(_, j)| j)
        .collect())
}

/// Runs the jobs in parallel; `progress` shows a bar on the terminal. Records are in job order.
pub fn run_jobs(jobs: &[Job], progress: bool) -> Vec<RunRecord> {
    let bar = if progress {
        ProgressBar::new(jobs.len() as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let records = jobs
        .par_iter()
        .map(|j| {
            let r = run_job(j);
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    records
}

/// Runs one job and classifies its outcome.
pub fn run_job(job: &Job) -> RunRecord {
    let failed = |e: Error, case: Option<&dyn Case>| {
        let status = match e {
            Error::Diverged { .. } => Status::Diverged,
            Error::Unsupported(_) => Status::Unsupported,
            _ => Status::Failed,
        };
        (status, e.to_string(), failed_summary(job, case))
    };
    let mut probe = Vec::new();
    let (status, reason, summary) = match cases::parse(&job.text, &job.path, &job.overrides) {
        Err(e) => failed(e, None),
        Ok(case) => match run::run(case.as_ref()) {
            Err(e) => failed(e, Some(case.as_ref())),
            Ok(RunResult { summary, .. }) if summary.metrics.energy_drift > BLOWUP_FACTOR => (
                Status::Diverged,
                format!("energy exceeded {BLOWUP_FACTOR} × E(0)"),
                summary,
            ),
            Ok(RunResult { summary, rows }) => {
                if case.exact().is_none() {
                    probe = rows
                        .iter()
                        .map(|r| (r.t, r.u_contact, r.sigma_contact))
                        .collect();
                }
                (Status::Ok, String::new(), summary)
            }
        },
    };
    RunRecord {
        sweep: job.sweep.clone(),
        level: job.level,
        status,
        reason,
        summary,
        probe,
    }
}

/// Identification of a run that produced no metrics.
fn failed_summary(job: &Job, case: Option<&dyn Case>) -> Summary {
    let spec = case.map(|c| c.run().clone());
    let parameters = spec
        .as_ref()
        .and_then(|s| crate::time::by_name(&s.scheme, s.scheme_params()).ok())
        .map_or_else(String::new, |s| s.parameters());
    Summary {
        case: case.map_or("", |c| c.kind()).to_string(),
        space: job.space.clone(),
        scheme: job.choice.scheme.clone(),
        parameters,
        h: case.map_or(f64::NAN, |c| c.h()),
        dt: job.refinement.dt,
        dofs: 0,
        steps: 0,
        contact_iterations: 0,
        wall_time: 0.0,
        metrics: Metrics::unavailable(),
    }
}

/// Linear interpolation of `(t, value)` samples (sorted by t) at `t`.
fn interpolate(series: &[(f64, f64)], t: f64) -> f64 {
    let k = series.partition_point(|p| p.0 < t);
    if k == 0 {
        return series[0].1;
    }
    if k == series.len() {
        return series[k - 1].1;
    }
    let ((t0, v0), (t1, v1)) = (series[k - 1], series[k]);
    v0 + (v1 - v0) * (t - t0) / (t1 - t0)
}

/// For cases without an exact solution: `err_u_contact = max_n |u_h(t_n) − u_ref(t_n)|` and
/// `err_sigma_l2 = (Σ_n Δt (σ_h − σ_ref)²)^{1/2}` at the probe, against the finest finished level
/// of the same case × sweep × space × scheme (interpolated linearly in time; the probe must sit at
/// the same point on every level: the block sweeps use even cell counts so that the centre of Γ_C
/// is a vertex). The reference run itself gets no error. Frees the probe series.
pub fn reference_errors(records: &mut [RunRecord]) {
    for (_, indices) in group_by(0..records.len(), |&i| records[i].series_key()) {
        let members: Vec<usize> = indices
            .into_iter()
            .filter(|&i| !records[i].probe.is_empty())
            .collect();
        let Some(&finest) = members.iter().max_by_key(|&&i| records[i].level) else {
            continue;
        };
        let u_ref: Vec<(f64, f64)> = records[finest].probe.iter().map(|p| (p.0, p.1)).collect();
        let s_ref: Vec<(f64, f64)> = records[finest].probe.iter().map(|p| (p.0, p.2)).collect();
        for &i in members.iter().filter(|&&i| i != finest) {
            let r = &mut records[i];
            let dt = r.summary.dt;
            let du = r
                .probe
                .iter()
                .map(|p| (p.1 - interpolate(&u_ref, p.0)).abs());
            let ds = r
                .probe
                .iter()
                .skip(1)
                .map(|p| dt * (p.2 - interpolate(&s_ref, p.0)).powi(2));
            r.summary.metrics.err_u_contact = Some(du.fold(0.0, f64::max));
            r.summary.metrics.err_sigma_l2 = Some(ds.sum::<f64>().sqrt());
        }
    }
    for r in records.iter_mut() {
        r.probe = Vec::new();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(level: usize, dt: f64, offset: f64) -> RunRecord {
        let summary = Summary {
            case: "block2d".into(),
            space: "standard".into(),
            scheme: "newmark".into(),
            parameters: String::new(),
            h: 0.1 / (level + 1) as f64,
            dt,
            dofs: 1,
            steps: (1.0 / dt) as usize,
            contact_iterations: 0,
            wall_time: 0.0,
            metrics: Metrics::default(),
        };
        let n = (1.0 / dt).round() as usize;
        let probe = (0..=n)
            .map(|k| {
                let t = k as f64 * dt;
                (t, t.sin() + offset, t.cos())
            })
            .collect();
        RunRecord {
            sweep: "s".into(),
            level,
            status: Status::Ok,
            reason: String::new(),
            summary,
            probe,
        }
    }

    #[test]
    fn reference_errors_compare_against_the_finest_level() {
        let mut r = vec![record(0, 0.1, 0.25), record(1, 0.01, 0.0)];
        reference_errors(&mut r);
        let (eu, es) = (
            r[0].summary.metrics.err_u_contact,
            r[0].summary.metrics.err_sigma_l2,
        );
        // u differs by 0.25 plus the interpolation error of sin at dt = 0.01 (< 1.3e-5).
        assert!((eu.unwrap() - 0.25).abs() < 2e-5, "{eu:?}");
        assert!(es.unwrap() < 1e-4, "{es:?}");
        assert!(r[1].summary.metrics.err_u_contact.is_none());
        assert!(r.iter().all(|x| x.probe.is_empty()));
    }
}
