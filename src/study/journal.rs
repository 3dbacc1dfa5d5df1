//! The journal of a study: one line per finished run, appended and flushed as the run finishes,
//! so that a study killed mid-way loses no finished run and `--resume` skips them.
//!
//! `journal.csv` has the columns of `records.csv` (with the timing columns) and, after the run's
//! `key` ([`Job::key`]), the `case_hash` of the case file's content: a run is taken from the
//! journal only when both match. The probe series `(t, u, σ_N)` of a run without exact solution,
//! which the reference errors need, is written beside it as `probes/<key>.csv` before the
//! journal line. A torn last line (a kill during the write) is dropped on resume. When the
//! study is over, [`rewrite`] writes the journal again in run order with the final records (the
//! reference errors included), so that it and `summary.csv` hold the same metrics, then the
//! recorded runs a narrower `--resume` (`--case`, `--quick`) left out.
//!
//! The outputs are always computed from what the journal holds, read back, so an interrupted
//! and resumed study writes the same bytes as an uninterrupted one.

use super::jobs::{run_job, run_job_keeping, runs_bar, Job, RunRecord};
use super::records::{read_rows, record_fields, record_header};
use super::run::RunResult;
use super::schedule::{self, Estimate};
use crate::error::{Error, Result};
use crate::input::{Input, TABLE};
use crate::output::{csv::write_rows, fmt_float};
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The journal read back (`--resume`, and the records of a study).
const JOURNAL: Input = TABLE.named("journal");
/// A probe series read back.
const PROBE: Input = TABLE.named("probe series");

/// The column of the case file's content hash.
const CASE_HASH: &str = "case_hash";

/// The journal's header: `key`, `case_hash`, then the other columns of a records file.
pub fn header() -> Vec<&'static str> {
    let mut h = record_header(true);
    h.insert(1, CASE_HASH);
    h
}

/// One journal line's fields.
fn fields(record: &RunRecord, case_hash: &str) -> Vec<String> {
    let mut f = record_fields(record, true);
    f.insert(1, case_hash.to_string());
    f
}

/// An open journal.
pub struct Journal {
    path: PathBuf,
    file: Mutex<std::fs::File>,
}

impl Journal {
    /// Opens `dir/name`: emptied unless `resume`; with `resume`, returns the complete lines
    /// already there with their case hash (rewriting the file without a torn last line).
    pub fn open(dir: &Path, name: &str, resume: bool) -> Result<(Self, Vec<(RunRecord, String)>)> {
        let path = dir.join(name);
        std::fs::create_dir_all(dir.join(PROBES)).map_err(|e| Error::io(dir, e))?;
        let done = if resume && path.exists() {
            let text = JOURNAL.read(&path)?;
            let complete = &text[..text.iter().rposition(|&b| b == b'\n').map_or(0, |k| k + 1)];
            if complete.len() != text.len() {
                crate::output::atomic::write_bytes(&path, complete)?;
            }
            read_journal(complete, &path)?
        } else {
            Vec::new()
        };
        if done.is_empty() {
            write_rows(&path, &header(), std::iter::empty::<Vec<String>>())?;
        }
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(|e| Error::io(&path, e))?;
        Ok((
            Self {
                path,
                file: Mutex::new(file),
            },
            done,
        ))
    }

    /// Appends one record (its probe series first), as one write, and flushes.
    pub fn append(&self, case_hash: &str, record: &RunRecord) -> Result<()> {
        if !record.probe.is_empty() {
            write_rows(
                &probe_path(&self.path, &record.key),
                PROBE_COLUMNS,
                record
                    .probe
                    .iter()
                    .map(|&(t, u, s)| [t, u, s].map(|x| fmt_float(Some(x)))),
            )?;
        }
        let mut line = csv::Writer::from_writer(Vec::new());
        let err = |e: String| Error::Csv {
            path: self.path.clone(),
            message: e,
        };
        line.write_record(fields(record, case_hash))
            .map_err(|e| err(e.to_string()))?;
        let bytes = line.into_inner().map_err(|e| err(e.to_string()))?;
        let mut file = self
            .file
            .lock()
            .map_err(|_| err("journal lock poisoned".into()))?;
        file.write_all(&bytes)
            .and_then(|_| file.flush())
            .map_err(|e| Error::io(&self.path, e))
    }
}

/// The records of journal text, each with its case hash. Refuses a run recorded twice (one key,
/// one case file content): which row would count?
fn read_journal(text: &[u8], path: &Path) -> Result<Vec<(RunRecord, String)>> {
    let rows = read_rows(text, path, JOURNAL, &[CASE_HASH])?;
    let mut rows_of: HashMap<(&str, &str), usize> = HashMap::new();
    for (k, (r, extra)) in rows.iter().enumerate() {
        let hash = extra.first().map_or("", String::as_str);
        if let Some(first) = rows_of.insert((r.key.as_str(), hash), k) {
            return Err(JOURNAL.error(
                path,
                format!(
                    "row {}, column `key`: `{}` is the key of row {} too, of the same case file \
                     content (one run, one row: remove one)",
                    k + 2,
                    r.key,
                    first + 2
                ),
            ));
        }
    }
    Ok(rows
        .into_iter()
        .map(|(r, mut x)| (r, x.remove(0)))
        .collect())
}

/// `probes/<key>.csv` beside the journal at `journal`.
fn probe_path(journal: &Path, key: &str) -> PathBuf {
    let dir = journal.parent().unwrap_or(Path::new("."));
    dir.join(PROBES).join(format!("{key}.csv"))
}

/// The probe series written for `r` beside the journal, if any, as the run wrote it: a row per
/// sample (`steps + 1`), `t` the sample's time `n·dt`, every value finite; anything else (a file
/// edited by hand) is refused naming the file, row and column.
fn read_probe(journal: &Path, r: &RunRecord) -> Result<Vec<(f64, f64, f64)>> {
    let path = probe_path(journal, &r.key);
    if !path.exists() {
        return Ok(Vec::new());
    }
    let err = |m: String| PROBE.error(&path, m);
    let text = PROBE.read(&path)?;
    let rows: Vec<(f64, f64, f64)> = csv::Reader::from_reader(text.as_slice())
        .deserialize::<(f64, f64, f64)>()
        .map(|row| row.map_err(|e| err(e.to_string())))
        .collect::<Result<_>>()?;
    let (steps, dt) = (r.summary.steps, r.summary.dt);
    if rows.len() != steps + 1 {
        return Err(err(format!(
            "{} rows, not the {} samples of run {} ({steps} steps; edited by hand? remove it \
             and its journal row to run it again)",
            rows.len(),
            steps + 1,
            r.key
        )));
    }
    // The writer's 13 significant digits, over the whole run.
    let tolerance = 1e-9 * dt * steps.max(1) as f64;
    for (n, row) in rows.iter().enumerate() {
        let values = [row.0, row.1, row.2];
        for (v, column) in values.iter().zip(PROBE_COLUMNS) {
            if !v.is_finite() {
                return Err(err(format!(
                    "row {}, column `{column}`: {v} (a run's samples are finite)",
                    n + 2
                )));
            }
        }
        let t = n as f64 * dt;
        if (row.0 - t).abs() > tolerance {
            return Err(err(format!(
                "row {}, column `t`: {} (sample {n} of run {} is at n·dt = {t:e})",
                n + 2,
                row.0,
                r.key
            )));
        }
    }
    Ok(rows)
}

/// The files a study writes into `dir` beside its records, for
/// [`crate::input::refuse_overwrite`]: the journal `name`, its lock and the probe series of
/// `jobs`.
pub fn outputs(dir: &Path, name: &str, jobs: &[Job]) -> Vec<crate::input::Named> {
    let journal = dir.join(name);
    let lock = dir.join(format!("{name}.lock"));
    [journal.clone(), lock]
        .into_iter()
        .chain(jobs.iter().map(|j| probe_path(&journal, &j.key)))
        .map(|p| ("--out", p))
        .collect()
}

/// Folder of the probe series, beside the journal.
const PROBES: &str = "probes";

/// Columns of a probe file.
pub const PROBE_COLUMNS: &[&str] = &["t", "u_contact", "sigma_contact"];

/// Runs the jobs that `dir/journal` does not hold yet (every job without `resume`), in parallel,
/// appending each record as it finishes; returns every job's record in job order, as read back
/// from the journal, with its probe series. Two jobs with the same key are refused.
pub fn run_study(
    jobs: &[Job],
    dir: &Path,
    journal: &str,
    resume: bool,
    progress: bool,
) -> Result<Vec<RunRecord>> {
    let none: &[Extra<'_, ()>] = &[];
    Ok(run_study_with(jobs, (dir, journal), (resume, progress), none)?.0)
}

/// A task of a study besides its runs (the report's figures), scheduled with them.
pub struct Extra<'a, R> {
    /// Its estimated cost.
    pub estimate: Estimate,
    /// The key of a job whose run the task draws from: the task runs and records it, and
    /// passes it to `work` (None when the journal holds it already), instead of the study
    /// running it apart.
    pub job: Option<String>,
    /// The task, given that run.
    pub work: Box<dyn Fn(Option<RunResult>) -> R + Sync + 'a>,
}

/// One task of [`run_study_with`].
enum Task<'t, 'a, R> {
    Run(&'t Job),
    Extra(&'t Extra<'a, R>),
}

/// As [`run_study`], with the `extras` scheduled among the runs ([`schedule::run`]: longest first
/// within the memory budget); returns their results too, in order.
pub fn run_study_with<R: Send>(
    jobs: &[Job],
    (dir, journal): (&Path, &str),
    (resume, progress): (bool, bool),
    extras: &[Extra<'_, R>],
) -> Result<(Vec<RunRecord>, Vec<R>)> {
    super::jobs::distinct_keys(jobs)?;
    let (journal, done) = Journal::open(dir, journal, resume)?;
    let done_keys: std::collections::HashSet<(&str, &str)> = done
        .iter()
        .map(|(r, hash)| (r.key.as_str(), hash.as_str()))
        .collect();
    let todo: Vec<&Job> = jobs
        .iter()
        .filter(|j| !done_keys.contains(&(j.key.as_str(), j.file.hash.as_str())))
        .collect();
    // The runs the extras make, by key.
    let shared: HashMap<&str, &Job> = todo
        .iter()
        .filter(|j| {
            extras
                .iter()
                .any(|e| e.job.as_deref() == Some(j.key.as_str()))
        })
        .map(|j| (j.key.as_str(), *j))
        .collect();
    if resume && !done.is_empty() && progress {
        eprintln!(
            "resuming: {} of {} runs already recorded",
            jobs.len() - todo.len(),
            jobs.len()
        );
    }
    let bar = runs_bar(todo.len(), progress);
    let tasks: Vec<Task<'_, '_, R>> = todo
        .iter()
        .filter(|j| !shared.contains_key(j.key.as_str()))
        .map(|j| Task::Run(j))
        .chain(extras.iter().map(Task::Extra))
        .collect();
    let estimate = |t: &Task<'_, '_, R>| match t {
        Task::Run(j) => j.estimate(),
        Task::Extra(e) => e.estimate,
    };
    let done = schedule::run(&tasks, estimate, schedule::workers(), |t| match t {
        Task::Run(j) => {
            let r = run_job(j);
            bar.inc(1);
            (Some(journal.append(&j.file.hash, &r)), None)
        }
        Task::Extra(e) => match e.job.as_deref().and_then(|k| shared.get(k)) {
            Some(j) => {
                let (r, result) = run_job_keeping(j);
                bar.inc(1);
                let appended = journal.append(&j.file.hash, &r);
                (Some(appended), Some((e.work)(result)))
            }
            None => (None, Some((e.work)(None))),
        },
    });
    bar.finish_and_clear();
    let mut results = Vec::with_capacity(extras.len());
    for (appended, r) in done {
        appended.transpose()?;
        results.extend(r);
    }
    let text = JOURNAL.read(&journal.path)?;
    let all: HashMap<(String, String), RunRecord> = read_journal(&text, &journal.path)?
        .into_iter()
        .map(|(r, hash)| ((r.key.clone(), hash), r))
        .collect();
    let records = jobs
        .iter()
        .map(|j| {
            let mut r = all
                .get(&(j.key.clone(), j.file.hash.clone()))
                .cloned()
                .ok_or_else(|| {
                    JOURNAL.error(&journal.path, format!("no record for run {}", j.key))
                })?;
            // A row edited by hand would lend its key to another run.
            let (s, o) = (&r.summary, (&j.sweep, &j.space, &j.choice.scheme, j.level));
            if (&r.sweep, &s.space, &s.scheme, r.level) != o {
                return Err(JOURNAL.error(
                    &journal.path,
                    format!(
                        "the row of run {} is of sweep `{}`, {} × {}, level {}: not that run \
                         (edited by hand? remove the row, or run without --resume)",
                        j.key, r.sweep, s.space, s.scheme, r.level
                    ),
                ));
            }
            if let Some((column, recorded, specified)) = j.contradiction(&r) {
                return Err(JOURNAL.error(
                    &journal.path,
                    format!(
                        "the row of run {}, column `{column}`: {recorded}, where the run is \
                         specified with {specified} (edited by hand? remove the row, or run \
                         without --resume)",
                        j.key
                    ),
                ));
            }
            r.probe = read_probe(&journal.path, &r)?;
            Ok(r)
        })
        .collect::<Result<_>>()?;
    Ok((records, results))
}

/// Writes `dir/journal` again with `records` (the final ones, one per job, in job order), so
/// that it holds what `summary.csv` holds, then the rows of the runs a narrower selection left
/// out (another `--case`, `--quick` or not), by key, for a later `--resume`: the last row of
/// each key that is not a job, unless its case is one of this selection's with another hash
/// (a row of the case file before an edit, which no run would take again). [`write_rows`]
/// writes it beside and renames it, so that a kill leaves the old journal or the new one.
pub fn rewrite(dir: &Path, journal: &str, jobs: &[Job], records: &[RunRecord]) -> Result<()> {
    let path = dir.join(journal);
    let mine: std::collections::HashSet<&str> = jobs.iter().map(|j| j.key.as_str()).collect();
    let hashes: HashMap<&str, &str> = records
        .iter()
        .zip(jobs)
        .map(|(r, j)| (r.summary.case.as_str(), j.file.hash.as_str()))
        .collect();
    let old = match path.exists() {
        true => read_journal(&JOURNAL.read(&path)?, &path)?,
        false => Vec::new(),
    };
    let mut others: std::collections::BTreeMap<&str, Vec<String>> = Default::default();
    for (r, hash) in &old {
        let current = hashes.get(r.summary.case.as_str());
        if !mine.contains(r.key.as_str()) && current.is_none_or(|h| h == hash) {
            others.insert(r.key.as_str(), fields(r, hash));
        }
    }
    write_rows(
        &path,
        &header(),
        jobs.iter()
            .zip(records)
            .map(|(j, r)| fields(r, &j.file.hash))
            .chain(others.into_values()),
    )
}
