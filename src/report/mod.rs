//! `dyncontact report`: runs every `[[sweep]]` of the case files (the [`crate::study`] layer) and
//! writes, into one directory:
//! - `summary.csv` (one row per run, deterministic), `timings.csv` (wall times), `orders.csv`;
//! - convergence PNGs per case × sweep × quantity (one series per space for the sweep's first
//!   scheme, one series per scheme for the reference space), each with a slope triangle;
//! - energy and contact stress against time for every case;
//! - `index.md` and `index.html` listing every figure and table with one sentence each.
//!
//! Runs are streamed to `journal.csv` (and their probe series to `probes/`) as they finish;
//! `report --resume` skips those already there and gives the same files as an uninterrupted
//! report.
//!
//! `dyncontact merge` rebuilds the same files (without the time histories, which need the time
//! series) from record files written by `dyncontact sweep --shard i/n`.

pub mod figures;
pub mod impact;
pub mod index;

use crate::cases::{self, CaseFile};
use crate::error::{Error, Result};
use crate::study::jobs::{self, RunRecord};
use crate::study::journal::run_study;
use crate::study::orders;
use crate::study::peers::{self, Agreement};
use crate::study::records::{read_records, write_records, write_timings};
use crate::study::reference;
use figures::{convergence_figures, time_histories};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A figure of the report: file name (in the output directory) and what it shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// File name.
    pub file: String,
    /// One sentence on what it shows.
    pub caption: String,
}

/// Report settings.
#[derive(Debug, Clone, Copy, Default)]
pub struct Options {
    /// Only the first `quick_levels` levels of every sweep.
    pub quick: bool,
    /// Progress bar on the terminal.
    pub progress: bool,
    /// Skip the runs already in `journal.csv` of the output directory.
    pub resume: bool,
}

/// Case files with `[[sweep]]` tables in `dir`, sorted by name, each read and parsed once.
pub fn case_files(dir: &Path) -> Result<Vec<Arc<CaseFile>>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let mut out = Vec::new();
    for f in files {
        let file = CaseFile::read(&f)?;
        if !file
            .build(&cases::Overrides::default())?
            .sweeps()
            .is_empty()
        {
            out.push(Arc::new(file));
        }
    }
    Ok(out)
}

/// Runs every sweep of the case files in `cases_dir` and writes the report into `out`.
pub fn report(cases_dir: &Path, out: &Path, opts: Options) -> Result<Vec<RunRecord>> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let files = case_files(cases_dir)?;
    let mut all = Vec::new();
    for f in &files {
        all.extend(jobs::jobs(f, opts.quick)?);
    }
    let mut records = run_study(&all, out, "journal.csv", opts.resume, opts.progress)?;
    reference::reference_errors(&mut records);
    let mut figures = Vec::new();
    for f in &files {
        let case = f.build(&Default::default())?;
        figures.extend(if case.impact().is_some() {
            impact::impact_figures(f, out, opts.quick)?
        } else {
            time_histories(f, case.as_ref(), out, opts.quick)?
        });
    }
    let peers_dir = cases_dir
        .parent()
        .unwrap_or(Path::new(""))
        .join("golden/peers");
    let agreements = peers::compare_all(&peers_dir, cases_dir)?;
    peers::write_cross_code(&out.join("cross_code.csv"), &agreements)?;
    write(out, &records, figures, &agreements, opts.quick)?;
    Ok(records)
}

/// Joins record files (from `sweep --shard`) into a report in `out` (no time histories).
pub fn merge(files: &[PathBuf], out: &Path) -> Result<Vec<RunRecord>> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let mut records = Vec::new();
    for f in files {
        records.extend(read_records(f)?);
    }
    write(out, &records, Vec::new(), &[], false)?;
    Ok(records)
}

fn write(
    out: &Path,
    records: &[RunRecord],
    mut figures: Vec<Figure>,
    peers: &[Agreement],
    quick: bool,
) -> Result<()> {
    write_records(&out.join("summary.csv"), records, false)?;
    write_timings(&out.join("timings.csv"), records)?;
    let orders = orders::orders(records);
    orders::write_orders(&out.join("orders.csv"), &orders)?;
    figures.splice(0..0, convergence_figures(out, records)?);
    index::write_index(out, records, &orders, &figures, peers, quick)
}
