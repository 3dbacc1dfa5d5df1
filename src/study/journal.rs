//! The journal of a study: one line per finished run, appended and flushed as the run finishes,
//! so that a study killed mid-way loses no finished run and `--resume` skips them.
//!
//! `journal.csv` has the columns of `records.csv` (with the wall time) after a `key`: the case
//! file's content hash, the sweep, space, scheme with its parameters, and the level
//! ([`Job::key`]). The probe series `(t, u, σ_N)` of a run without exact solution, which the
//! reference errors need, is written beside it as `probes/<hash of the key>.csv` before the
//! journal line. A torn last line (a kill during the write) is dropped on resume.
//!
//! The outputs are always computed from what the journal holds, read back, so an interrupted
//! and resumed study writes the same bytes as an uninterrupted one.

use super::jobs::{run_job, runs_bar, Job, RunRecord};
use super::records::{read_keyed, record_fields, record_header};
use crate::error::{Error, Result};
use crate::output::{csv::write_rows, fmt_float};
use crate::util::content_hash;
use rayon::prelude::*;
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// An open journal.
pub struct Journal {
    path: PathBuf,
    file: Mutex<std::fs::File>,
}

impl Journal {
    /// Opens `dir/name`: emptied unless `resume`; with `resume`, returns the complete lines
    /// already there (rewriting the file without a torn last line).
    pub fn open(dir: &Path, name: &str, resume: bool) -> Result<(Self, Vec<(String, RunRecord)>)> {
        let path = dir.join(name);
        std::fs::create_dir_all(dir.join(PROBES)).map_err(|e| Error::io(dir, e))?;
        let done = if resume && path.exists() {
            let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
            let complete = &text[..text.rfind('\n').map_or(0, |k| k + 1)];
            if complete.len() != text.len() {
                std::fs::write(&path, complete).map_err(|e| Error::io(&path, e))?;
            }
            read_keyed(csv::Reader::from_reader(complete.as_bytes()), &path)?
        } else {
            Vec::new()
        };
        if done.is_empty() {
            let mut header = vec!["key"];
            header.extend(record_header(true));
            write_rows(&path, &header, std::iter::empty::<Vec<String>>())?;
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
    pub fn append(&self, key: &str, record: &RunRecord) -> Result<()> {
        if !record.probe.is_empty() {
            write_rows(
                &self.probe_path(key),
                &["t", "u_contact", "sigma_contact"],
                record
                    .probe
                    .iter()
                    .map(|&(t, u, s)| [t, u, s].map(|x| fmt_float(Some(x)))),
            )?;
        }
        let mut fields = vec![key.to_string()];
        fields.extend(record_fields(record, true));
        let mut line = csv::Writer::from_writer(Vec::new());
        let err = |e: String| Error::Csv {
            path: self.path.clone(),
            message: e,
        };
        line.write_record(&fields).map_err(|e| err(e.to_string()))?;
        let bytes = line.into_inner().map_err(|e| err(e.to_string()))?;
        let mut file = self
            .file
            .lock()
            .map_err(|_| err("journal lock poisoned".into()))?;
        file.write_all(&bytes)
            .and_then(|_| file.flush())
            .map_err(|e| Error::io(&self.path, e))
    }

    fn probe_path(&self, key: &str) -> PathBuf {
        let dir = self.path.parent().unwrap_or(Path::new("."));
        dir.join(PROBES)
            .join(format!("{}.csv", content_hash(key.as_bytes())))
    }

    /// The probe series written for `key`, if any.
    fn read_probe(&self, key: &str) -> Result<Vec<(f64, f64, f64)>> {
        let path = self.probe_path(key);
        if !path.exists() {
            return Ok(Vec::new());
        }
        let err = |m: String| Error::Csv {
            path: path.clone(),
            message: m,
        };
        let mut reader = csv::Reader::from_path(&path).map_err(|e| err(e.to_string()))?;
        reader
            .deserialize::<(f64, f64, f64)>()
            .map(|row| row.map_err(|e| err(e.to_string())))
            .collect()
    }
}

/// Folder of the probe series, beside the journal.
const PROBES: &str = "probes";

/// Runs the jobs that `dir/journal` does not hold yet (every job without `resume`), in parallel,
/// appending each record as it finishes; returns every job's record in job order, as read back
/// from the journal, with its probe series.
pub fn run_study(
    jobs: &[Job],
    dir: &Path,
    journal: &str,
    resume: bool,
    progress: bool,
) -> Result<Vec<RunRecord>> {
    let (journal, done) = Journal::open(dir, journal, resume)?;
    let done_keys: std::collections::HashSet<&str> = done.iter().map(|d| d.0.as_str()).collect();
    let todo: Vec<&Job> = jobs
        .iter()
        .filter(|j| !done_keys.contains(j.key().as_str()))
        .collect();
    if resume && !done.is_empty() && progress {
        eprintln!(
            "resuming: {} of {} runs already recorded",
            jobs.len() - todo.len(),
            jobs.len()
        );
    }
    let bar = runs_bar(todo.len(), progress);
    todo.par_iter().try_for_each(|j| {
        let r = run_job(j);
        bar.inc(1);
        journal.append(&j.key(), &r)
    })?;
    bar.finish_and_clear();
    let text = std::fs::read_to_string(&journal.path).map_err(|e| Error::io(&journal.path, e))?;
    let all: HashMap<String, RunRecord> =
        read_keyed(csv::Reader::from_reader(text.as_bytes()), &journal.path)?
            .into_iter()
            .collect();
    jobs.iter()
        .map(|j| {
            let key = j.key();
            let mut r = all.get(&key).cloned().ok_or_else(|| Error::Csv {
                path: journal.path.clone(),
                message: format!("no record for run {key}"),
            })?;
            r.probe = journal.read_probe(&key)?;
            Ok(r)
        })
        .collect()
}
