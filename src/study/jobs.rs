//! Jobs: every combination declared in the `[[sweep]]` tables of case files, run in parallel
//! (longest first within a memory budget, [`super::schedule`]) with a progress bar (indicatif),
//! one [`RunRecord`] per run.
//!
//! A run that fails (solver failure, unstable time step, unsupported combination) or diverges
//! (NaN, or energy above [`BLOWUP_FACTOR`] × E(0)) is recorded with its status and reason; it never
//! aborts the sweep. Records come back in enumeration order, so outputs are deterministic.

use super::metrics::{self, Metrics};
use super::run::{self, RunResult, Summary};
use super::schedule::{self, Estimate};
use crate::cases::{self, sweep::Refinement, sweep::SchemeChoice, Case, CaseFile, Size};
use crate::error::{Error, Result};
use indicatif::{ProgressBar, ProgressStyle};
use std::sync::Arc;

/// A run whose energy moves from E(0) by more than this multiple of its scale is recorded as
/// diverged.
pub const BLOWUP_FACTOR: f64 = 100.0;

/// Why a finished run counts as diverged: its energy moved from E(0) by more than
/// [`BLOWUP_FACTOR`] × its scale, `max(|E(0)|, W)` with W the loads' work across the bodies
/// ([`RunResult::load_scale`]; by more than [`BLOWUP_FACTOR`] when both are 0;
/// [`metrics::first_blowup`]), as `(step, time, reason)` at the first step it did. W keeps a
/// run whose E(0) vanishes by the potential's origin from being called diverged by round-off:
/// roll2d at a slope of π/2 (gravity along the plane, E(0) = m g R cos α = 1.9e-16) sliding
/// as it should was "|E − E(0)| = 3.3e10 |E(0)|" at step 1.
pub fn blowup(result: &RunResult) -> Option<(usize, f64, String)> {
    let rows = &result.rows;
    let e0 = rows.first()?.energy.abs();
    let w = result.load_scale;
    let scale = e0.max(w);
    metrics::first_blowup(rows, BLOWUP_FACTOR, w).map(|(step, t, drift)| {
        let reason = if scale == 0.0 {
            format!(
                "the energy moved from E(0) = 0 by more than {BLOWUP_FACTOR} (|E| = {drift:.3e})"
            )
        } else if w > e0 {
            format!(
                "the energy moved from E(0) by more than {BLOWUP_FACTOR} W, W = {w:.3e} the \
                 loads' work across the bodies (above |E(0)| = {e0:.3e}; |E − E(0)| = \
                 {drift:.3e} W)"
            )
        } else {
            format!(
                "the energy moved from E(0) by more than {BLOWUP_FACTOR} |E(0)| (|E − E(0)| = \
                 {drift:.3e} |E(0)|)"
            )
        };
        (step, t, reason)
    })
}

/// One combination to run.
#[derive(Debug, Clone)]
pub struct Job {
    /// The case file, parsed once per command.
    pub file: Arc<CaseFile>,
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
    /// The run's name in the records and the name of its probe file (`probes/<key>.csv`):
    /// `<case file>-<sweep>-<space>-<scheme>[-<parameters>]-L<level>`, e.g.
    /// `bar1d-orders-standard-newmark-beta=0.5;gamma=0.5-L0` (`--quick` keeps the same keys;
    /// a solver other than its default is a parameter: `…-backward_euler-linear_solver=cg-L0`).
    pub key: String,
    overrides: cases::Overrides,
    /// The run's estimated size and its steps, for [`Job::estimate`].
    size: Size,
    steps: usize,
}

impl Job {
    /// The run's estimated cost ([`estimate`]).
    pub fn estimate(&self) -> Estimate {
        estimate(self.size, self.steps, &self.space)
    }

    /// Whether this job runs what `case`, built from `file` with `o`, runs: the same case file,
    /// the same run table after the overrides, the same mesh (size, cell, h) and the same
    /// case-level overrides (mesh file, friction, incidence).
    pub fn runs(&self, file: &CaseFile, o: &cases::Overrides, case: &dyn Case) -> Result<bool> {
        if self.file.path != file.path
            || self.file.hash != file.hash
            || (
                &self.overrides.mesh,
                self.overrides.friction,
                self.overrides.incidence,
            ) != (&o.mesh, o.friction, o.incidence)
            || self.size != file.size(o)
        {
            return Ok(false);
        }
        let mine = self.file.build(&self.overrides)?;
        Ok(mine.run() == case.run() && mine.h() == case.h() && mine.element() == case.element())
    }

    /// The first column of `r`, a record read back under this job's key, that is not of the
    /// run this job specifies, as `(column, recorded, specified)`: `dt`, and for a finished run
    /// `steps` and, where the size is known before the run ([`Size::exact`]), `dofs`.
    pub fn contradiction(&self, r: &RunRecord) -> Option<(&'static str, String, String)> {
        let (s, dt) = (&r.summary, self.refinement.dt);
        // The records' 13 significant digits.
        if (s.dt - dt).abs() > 1e-9 * dt {
            return Some(("dt", format!("{:e}", s.dt), format!("{dt:e}")));
        }
        if r.status != Status::Ok {
            return None;
        }
        if s.steps != self.steps {
            return Some(("steps", s.steps.to_string(), self.steps.to_string()));
        }
        match self.size.exact {
            Some(dofs) if dofs != s.dofs => Some(("dofs", s.dofs.to_string(), dofs.to_string())),
            _ => None,
        }
    }
}

/// Refuses two jobs of one key (one run's record would stand for the other's), naming both
/// case files and sweeps and the cause: a `-` in a case file's or a sweep's name (case file
/// `a` with sweep `x-s` and case file `a-x` with sweep `s` both give `a-x-s-…`), or one run
/// listed twice in a sweep.
pub fn distinct_keys(jobs: &[Job]) -> Result<()> {
    let mut first: std::collections::HashMap<&str, &Job> = Default::default();
    for j in jobs {
        let Some(a) = first.get(j.key.as_str()) else {
            first.insert(&j.key, j);
            continue;
        };
        let why = if (&a.file.path, &a.sweep) != (&j.file.path, &j.sweep) {
            "a `-` in a case file's or a sweep's name lets the keys `<case file>-<sweep>-…` of \
             two runs meet: rename the case file or the sweep"
        } else {
            "one run listed twice (the same scheme, parameters and solvers twice in `schemes`, \
             a linear solver counting as unset with a scheme that solves no linear system; or \
             two [[sweep]] tables of one name)"
        };
        let run = |j: &Job| format!("{} sweep `{}`", j.file.path.display(), j.sweep);
        return Err(Error::invalid(
            "sweep",
            &j.key,
            &format!("the key of runs of {} and of {}: {why}", run(a), run(j)),
        ));
    }
    Ok(())
}

/// The cost model of a run, by space dimension (0 to 3; the spring–mass is 0): microseconds per
/// dof·step, KB per dof and MB per run, for a sparse mass and for the singular dynamic method
/// (an LU-factored saddle system, with the stored Delassus columns). Measured on this 2-core
/// machine at 661ce8a (the full report; hertz3d: 1.5 µs and 4.4 KB per dof with cg, 10 µs and
/// 2.4 GB for the singular dynamic Q2 sphere of 51 651 dofs, 0.4 GB at 6 819).
const MICROSECONDS: [[f64; 2]; 4] = [[7.0, 7.0], [0.3, 0.5], [0.3, 1.3], [3.0, 10.0]];
const KB_PER_DOF: [[f64; 2]; 4] = [[0.0, 0.0], [1.0, 2.0], [4.0, 6.0], [6.0, 42.0]];
const MB_PER_RUN: [[f64; 2]; 4] = [[1.0, 1.0], [5.0, 10.0], [20.0, 50.0], [100.0, 250.0]];

/// The estimated cost of a run of `steps` steps of `size` with `space`, for the scheduler: only
/// its order among the others and its memory matter.
pub fn estimate(size: Size, steps: usize, space: &str) -> Estimate {
    let d = size.dim.min(3);
    let m = usize::from(space == crate::space::singular_dynamic::ENTRY.name);
    Estimate {
        seconds: size.dofs * steps as f64 * MICROSECONDS[d][m] * 1e-6,
        bytes: MB_PER_RUN[d][m] * 1e6 + size.dofs * KB_PER_DOF[d][m] * 1e3,
    }
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
    /// An internal fault (a bug): the run says nothing about the method.
    Internal,
}

impl Status {
    /// Every status, in the order of the report's counts.
    pub const ALL: [Status; 5] = [
        Status::Ok,
        Status::Diverged,
        Status::Failed,
        Status::Unsupported,
        Status::Internal,
    ];

    /// The status of a run that ended with `e`: a blow-up is `diverged`, a combination refused
    /// by design `unsupported`, a bug `internal`, anything else `failed`.
    pub fn of(e: &Error) -> Self {
        match e {
            Error::Diverged { .. } => Status::Diverged,
            Error::Unsupported(_) => Status::Unsupported,
            Error::Internal(_) => Status::Internal,
            _ => Status::Failed,
        }
    }

    /// The status called `name` (as written by [`Status::as_str`]).
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.as_str() == name)
    }

    /// Name written to CSV.
    pub fn as_str(&self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Diverged => "diverged",
            Status::Failed => "failed",
            Status::Unsupported => "unsupported",
            Status::Internal => "internal",
        }
    }
}

/// One row of `records.csv`.
#[derive(Debug, Clone)]
pub struct RunRecord {
    /// The run's key ([`Job::key`]).
    pub key: String,
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

/// Enumerates the jobs of every `[[sweep]]` of a case file (`--quick`: the first levels only).
/// Refuses two case files of one case (`kind()`) in one study: records, orders and figures are
/// keyed by the case, so their runs would mix in one fit (two spring_mass files of different
/// stiffness were fitted as one series of six levels).
pub fn distinct_cases(files: &[Arc<CaseFile>]) -> Result<()> {
    let mut seen: Vec<(&'static str, &Arc<CaseFile>)> = Vec::new();
    for f in files {
        let kind = f.defaults().map_err(|e| e.in_case_file(&f.path))?.kind();
        if let Some((_, first)) = seen.iter().find(|(k, _)| *k == kind) {
            return Err(Error::invalid(
                "case",
                kind,
                &format!(
                    "given by {} and {}: a study keys its records, orders and figures by the \
                     case, so their runs would mix (run them into separate --out directories)",
                    first.path.display(),
                    f.path.display()
                ),
            ));
        }
        seen.push((kind, f));
    }
    Ok(())
}

/// Errors on an invalid case file or sweep table, before anything runs, naming the file (and
/// the sweep and job). None for a case file without `[[sweep]]` tables.
pub fn jobs(file: &Arc<CaseFile>, quick: bool) -> Result<Vec<Job>> {
    sweep_jobs(file, quick).map_err(|e| e.in_case_file(&file.path))
}

fn sweep_jobs(file: &Arc<CaseFile>, quick: bool) -> Result<Vec<Job>> {
    let case = file.defaults()?;
    let mut out = Vec::new();
    for s in case.sweeps() {
        let in_sweep = |e: Error| e.context(format!("sweep `{}`", s.name));
        let levels = s.refinements(quick).map_err(in_sweep)?;
        for space in &s.spaces {
            crate::space::by_name(space).map_err(in_sweep)?;
            for choice in &s.schemes {
                // The scheme's parameters, named as the sweep's (once per choice).
                let mut spec = case.run().clone();
                s.overrides(space, choice, levels[0]).apply(&mut spec);
                crate::time::by_name(&spec.scheme, spec.params())
                    .map_err(|e| in_sweep(e.in_table(&s.field("schemes"))))?;
                for (level, &refinement) in levels.iter().enumerate() {
                    let overrides = s.overrides(space, choice, refinement);
                    // The sweep's fields, not the flags a run would name.
                    let as_field = |f: &str| s.field(f.trim_start_matches("--"));
                    file.check_overrides(&overrides)
                        .map_err(|e| in_sweep(e.with_field(as_field)))?;
                    let mut spec = case.run().clone();
                    overrides.apply(&mut spec);
                    let in_job = |e: Error| {
                        e.context(format!(
                            "sweep `{}`, {space} × {}, level {level}",
                            s.name,
                            choice.label()
                        ))
                    };
                    file.complete(&mut spec).map_err(in_job)?;
                    spec.validate().map_err(in_job)?;
                    let parameters = spec.parameters().map_err(in_job)?;
                    let size = file.size(&overrides);
                    let key = [
                        file.stem().as_str(),
                        &s.name,
                        space,
                        &choice.scheme,
                        &parameters,
                        &format!("L{level}"),
                    ]
                    .iter()
                    .filter(|p| !p.is_empty())
                    .copied()
                    .collect::<Vec<&str>>()
                    .join("-");
                    out.push(Job {
                        file: file.clone(),
                        sweep: s.name.clone(),
                        space: space.clone(),
                        choice: choice.clone(),
                        level,
                        refinement,
                        key,
                        overrides,
                        size,
                        steps: spec.steps(),
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
        .filter(|(k, _)| in_shard(*k, (i, n)))
        .map(|(_, j)| j)
        .collect())
}

/// Whether the run at `index` of the enumeration belongs to shard `i` of `n` (1 ≤ i ≤ n):
/// every n-th run, starting at i − 1.
pub fn in_shard(index: usize, (i, n): (usize, usize)) -> bool {
    index % n == i - 1
}

/// A progress bar over `runs` runs (hidden unless `progress`).
pub fn runs_bar(runs: usize, progress: bool) -> ProgressBar {
    let bar = if progress {
        ProgressBar::new(runs as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs, {elapsed} elapsed, ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// Runs the jobs in parallel ([`schedule::run`]); `progress` shows a bar on the terminal.
/// Records are in job order.
pub fn run_jobs(jobs: &[Job], progress: bool) -> Vec<RunRecord> {
    let bar = runs_bar(jobs.len(), progress);
    let records = schedule::run(jobs, Job::estimate, schedule::workers(), |j| {
        let r = run_job(j);
        bar.inc(1);
        r
    });
    bar.finish_and_clear();
    records
}

/// Runs one job and classifies its outcome.
pub fn run_job(job: &Job) -> RunRecord {
    run_job_keeping(job).0
}

/// As [`run_job`], also returning the run itself when it finished (for a figure drawn from it).
pub fn run_job_keeping(job: &Job) -> (RunRecord, Option<RunResult>) {
    let failed = |e: Error, case: Option<&dyn Case>| {
        let e = job.overrides.named(e);
        (Status::of(&e), e.to_string(), failed_summary(job, case))
    };
    let mut probe = Vec::new();
    let mut result = None;
    let (status, reason, summary) = match job.file.build(&job.overrides) {
        Err(e) => failed(e, None),
        Ok(case) => match run::run(case.as_ref()) {
            Err(e) => failed(e, Some(case.as_ref())),
            Ok(r) => {
                let summary = r.summary.clone();
                let outcome = if let Some((step, t, reason)) = blowup(&r) {
                    let reason = format!("{reason} at step {step} (t = {t:.6e})");
                    (Status::Diverged, reason, summary)
                } else {
                    if case.exact().is_none() {
                        probe = r
                            .rows
                            .iter()
                            .map(|r| (r.t, r.u_contact, r.sigma_contact))
                            .collect();
                    }
                    (Status::Ok, String::new(), summary)
                };
                result = Some(r);
                outcome
            }
        },
    };
    let record = RunRecord {
        key: job.key.clone(),
        sweep: job.sweep.clone(),
        level: job.level,
        status,
        reason,
        summary,
        probe,
    };
    (record, result)
}

/// Identification of a run that produced no metrics.
fn failed_summary(job: &Job, case: Option<&dyn Case>) -> Summary {
    let spec = case.map(|c| c.run().clone());
    let parameters = spec
        .as_ref()
        .and_then(|s| s.parameters().ok())
        .unwrap_or_default();
    let element = case.and_then(|c| c.element());
    Summary {
        // The case file's kind even when this run's case failed to build (a mesh beyond the
        // memory): the case column names the report's files.
        case: match case {
            Some(c) => c.kind(),
            None => job.file.defaults().map_or("", |c| c.kind()),
        }
        .to_string(),
        space: job.space.clone(),
        scheme: job.choice.scheme.clone(),
        parameters,
        contact: spec
            .as_ref()
            .and_then(|s| crate::contact::formulation(&s.options).ok())
            .map_or(String::new(), |f| f.label()),
        degree: element.map(|e| e.1),
        cells: element.map_or(String::new(), |e| e.0.to_string()),
        h: case.map_or(f64::NAN, |c| c.h()),
        dt: job.refinement.dt,
        dofs: 0,
        steps: 0,
        contact_iterations: 0,
        wall_time: 0.0,
        max_rss: f64::NAN,
        metrics: Metrics::unavailable(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bug is recorded as `internal`, never as an unsupported combination, and every status
    /// reads back from its name.
    #[test]
    fn internal_faults_are_their_own_status() {
        let internal = Error::Internal("a worker stopped".into());
        assert_eq!(Status::of(&internal), Status::Internal);
        assert_eq!(
            Status::of(&Error::Unsupported("by design".into())),
            Status::Unsupported
        );
        assert_eq!(
            Status::of(&Error::invalid("dt", -1.0, "> 0")),
            Status::Failed
        );
        for s in Status::ALL {
            assert_eq!(Status::parse(s.as_str()), Some(s));
        }
    }
}
