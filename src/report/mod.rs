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

pub mod columns;
pub mod doc;
pub mod figures;
pub mod findings;
pub mod friction;
pub mod impact;
pub mod index;
pub mod oblique;
pub mod quantity;
pub mod roll;
pub mod schemes_compared;
pub mod style;
pub mod two_bodies;
pub mod verdict;

use crate::cases::{self, Case, CaseFile, Overrides, Size};
use crate::error::{Error, Result};
use crate::input::Named;
use crate::study::jobs::{self, RunRecord};
use crate::study::journal::{self, run_study_with, Extra};
use crate::study::manifest;
use crate::study::orders;
use crate::study::peers::{self, Agreement};
use crate::study::profile;
use crate::study::records::{read_records, write_records, write_timings, Seen, RECORDS_FILE};
use crate::study::reference;
use crate::study::run::RunResult;
use crate::study::schedule::Estimate;
use doc::Figure;
use figures::{convergence_figures, time_histories};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Report settings.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// Only the first `quick_levels` levels of every sweep.
    pub quick: bool,
    /// Progress bar on the terminal.
    pub progress: bool,
    /// Skip the runs already in `journal.csv` of the output directory.
    pub resume: bool,
    /// Only these cases (a case file's name without `.toml`, or its `case` kind); all when empty.
    pub cases: Vec<String>,
}

/// A case of the report: its kind, a one-line title and its case file (relative to the report
/// directory, where the report copies it).
#[derive(Debug, Clone, PartialEq)]
pub struct CaseEntry {
    /// Case kind (`summary.csv`'s `case`).
    pub kind: String,
    /// What the case is (the case file's first comment line).
    pub title: String,
    /// The case file, relative to the report directory (None in a merged report).
    pub file: Option<String>,
}

/// A case file's figures and blocks of the report's sections.
type Part = (Vec<Figure>, Vec<doc::Block>);

/// A section study of a case file: its figures and blocks.
type Study = fn(&CaseFile, &Path, bool) -> Result<Part>;

/// The friction figures of a case file, as a [`Study`].
fn friction_study(file: &CaseFile, out: &Path, quick: bool) -> Result<Part> {
    Ok((friction::figures(file, out, quick)?, Vec::new()))
}

/// Case files with `[[sweep]]` or `[[history]]` tables in `dir`, sorted by name, each read and
/// parsed once.
pub fn case_files(dir: &Path) -> Result<Vec<Arc<CaseFile>>> {
    let mut out = Vec::new();
    for f in cases::case_paths(dir)? {
        let file = CaseFile::read(&f)?;
        let case = file.defaults().map_err(|e| e.in_case_file(&f))?;
        if !case.sweeps().is_empty() || !case.histories().is_empty() {
            out.push(Arc::new(file));
        }
    }
    Ok(out)
}

/// The case files named in `names` (file stem or case kind; every file when `names` is empty),
/// or an error naming a name that matches none.
fn select(files: Vec<Arc<CaseFile>>, names: &[String], dir: &Path) -> Result<Vec<Arc<CaseFile>>> {
    if names.is_empty() {
        return Ok(files);
    }
    let kind = |f: &CaseFile| f.defaults().map(|c| c.kind());
    for n in names {
        if !files
            .iter()
            .any(|f| f.stem() == *n || kind(f).is_ok_and(|k| k == n))
        {
            let known: Vec<String> = files.iter().map(|f| f.stem()).collect();
            return Err(Error::invalid(
                "--case",
                n,
                &format!(
                    "no case file with [[sweep]] or [[history]] tables of that name in {}; \
                     known: {}",
                    dir.display(),
                    known.join(", ")
                ),
            ));
        }
    }
    Ok(files
        .into_iter()
        .filter(|f| {
            names
                .iter()
                .any(|n| f.stem() == *n || kind(f).is_ok_and(|k| k == n))
        })
        .collect())
}

/// Copies the case files into `out/cases/` (the index links them there) and returns their
/// entries.
fn copy_cases(files: &[Arc<CaseFile>], out: &Path) -> Result<Vec<CaseEntry>> {
    let dir = out.join("cases");
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    files
        .iter()
        .map(|f| {
            let name = format!("{}.toml", f.stem());
            let to = dir.join(&name);
            crate::output::atomic::write_with(&to, |tmp| {
                std::fs::copy(&f.path, tmp)
                    .map(drop)
                    .map_err(|e| Error::io(&to, e))
            })?;
            Ok(CaseEntry {
                kind: f.defaults()?.kind().to_string(),
                title: f.title.clone(),
                file: Some(format!("cases/{name}")),
            })
        })
        .collect()
}

/// Runs every sweep of the case files in `cases_dir` (those of `opts.cases` only, when given) and
/// writes the report into `out`.
pub fn report(cases_dir: &Path, out: &Path, opts: &Options) -> Result<Vec<RunRecord>> {
    let files = select(case_files(cases_dir)?, &opts.cases, cases_dir)?;
    if files.is_empty() {
        return Err(Error::invalid(
            "--cases",
            cases_dir.display().to_string(),
            "holds no case file with [[sweep]] or [[history]] tables: nothing to report",
        ));
    }
    jobs::distinct_cases(&files)?;
    let mut all = Vec::new();
    for f in &files {
        all.extend(jobs::jobs(f, opts.quick)?);
    }
    let inputs: Vec<Named> = files
        .iter()
        .flat_map(|f| f.inputs(&Overrides::default()))
        .collect();
    let mut outputs = journal::outputs(out, "journal.csv", &all);
    outputs.extend(REPORT_FILES.iter().map(|f| ("--out", out.join(f))));
    crate::input::refuse_overwrite(&inputs, &outputs)?;
    crate::util::output_dir(out, "--out")?;
    let _lock = crate::study::lock::Lock::acquire(out, "journal.csv")?;
    // The figures' and the studies' own runs are scheduled with the sweeps' (they need no
    // record), each case file's in the order of the report: friction, oblique, roll, figures.
    let mut extras: Vec<Extra<'_, Result<Part>>> = Vec::new();
    for f in &files {
        let case = f.defaults()?;
        let studies: [(&str, Study, Estimate); 3] = [
            ("friction", friction_study, Estimate::default()),
            ("oblique", oblique::study, oblique::estimate(f, opts.quick)?),
            ("roll", roll::study, Estimate::default()),
        ];
        for (name, study, estimate) in studies {
            if name == "friction" && case.slide().is_none() {
                continue;
            }
            extras.push(Extra {
                estimate,
                job: None,
                work: Box::new(move |_| {
                    profile::section(&format!("{name} {}", f.stem()), || {
                        study(f, out, opts.quick)
                    })
                }),
            });
        }
        extras.push(Extra {
            estimate: figures_estimate(f, opts.quick)?,
            job: impact::sweep_run(f, opts.quick, &all)?,
            work: Box::new(move |run| {
                profile::section(&format!("figures {}", f.stem()), || {
                    Ok((case_figures(f, out, opts.quick, run)?, Vec::new()))
                })
            }),
        });
    }
    let (mut records, parts) = profile::section("sweeps and figures", || {
        run_study_with(
            &all,
            (out, "journal.csv"),
            (opts.resume, opts.progress),
            &extras,
        )
    })?;
    profile::section("reference errors", || {
        reference::reference_errors(&mut records)
    });
    journal::rewrite(out, "journal.csv", &all, &records)?;
    let mut figures = Vec::new();
    let mut studies = Vec::new();
    for part in parts {
        let (f, blocks) = part?;
        figures.extend(f);
        studies.extend(blocks);
    }
    let mut slides = Vec::new();
    for f in &files {
        let case = f.defaults()?;
        if let Some(s) = case.slide() {
            slides.push((case.kind().to_string(), s));
        }
    }
    let peers_dir = cases_dir
        .parent()
        .unwrap_or(Path::new(""))
        .join("golden/peers");
    let stems: Vec<String> = files.iter().map(|f| f.stem()).collect();
    let agreements = profile::section("peers", || {
        peers::compare_all(&peers_dir, cases_dir, &stems)
    })?;
    if !agreements.is_empty() {
        peers::write_cross_code(&out.join("cross_code.csv"), &agreements)?;
    }
    let cases = copy_cases(&files, out)?;
    profile::section("write", || {
        write(
            out,
            &records,
            figures,
            (&agreements, (&slides, &studies)),
            (&cases, opts.quick),
        )
    })?;
    Ok(records)
}

/// The time-history figures of a case file, or its impact figures for a curved body (from
/// `run` when the sweep's run is the impact run, [`impact::sweep_run`]).
fn case_figures(
    file: &CaseFile,
    out: &Path,
    quick: bool,
    run: Option<RunResult>,
) -> Result<Vec<Figure>> {
    let case = file.defaults()?;
    if case.impact().is_some() {
        impact::impact_figures(file, out, quick, run)
    } else {
        time_histories(file, case.as_ref(), out, quick)
    }
}

/// The estimated cost of [`case_figures`]: its runs (the impact run and the finite-body law,
/// the `[[history]]` tables, or the first sweep's level 2, as the figures take them), of which
/// two at a time are in memory; the impact run and the law one after the other (the run's
/// matrices are gone when the law is measured).
fn figures_estimate(file: &CaseFile, quick: bool) -> Result<Estimate> {
    let case = file.defaults()?;
    let mut runs: Vec<Overrides> = Vec::new();
    let mut extra = Estimate::default();
    if case.impact().is_some() {
        runs.push(impact::impact_overrides(file, quick)?);
        if case.impact().is_some_and(|i| i.hertz.dim == 3) {
            extra = finite_body_estimate(case.as_ref(), file.size(&runs[0]));
        }
    } else if !case.histories().is_empty() {
        crate::cases::sweep::validate_histories(case.histories())
            .map_err(|e| e.in_case_file(&file.path))?;
        for h in case.histories() {
            let dts = if quick {
                &h.dts[..h.dts.len().min(1)]
            } else {
                &h.dts[..]
            };
            for space in &h.spaces {
                runs.extend(dts.iter().map(|&dt| h.overrides(space, dt)));
            }
        }
    } else {
        let sweep = &case.sweeps()[0];
        let levels = sweep.refinements(quick)?;
        let level = levels[if quick { 0 } else { 2.min(levels.len() - 1) }];
        for space in &sweep.spaces {
            runs.extend(
                sweep
                    .schemes
                    .iter()
                    .map(|c| sweep.overrides(space, c, level)),
            );
        }
    }
    let mut each: Vec<Estimate> = runs
        .iter()
        .map(|o| {
            let mut spec = case.run().clone();
            o.apply(&mut spec);
            jobs::estimate(file.size(o), spec.steps(), &spec.space)
        })
        .collect();
    each.push(extra);
    each.sort_by(|a, b| b.bytes.total_cmp(&a.bytes));
    let together = if case.impact().is_some() { 1 } else { 2 };
    Ok(Estimate {
        seconds: each.iter().map(|e| e.seconds).sum(),
        bytes: each.iter().take(together).map(|e| e.bytes).sum(),
    })
}

/// The estimated cost of the finite-body laws of a case of `size`: one law per distinct body
/// (twins are measured once, [`crate::study::finite_body::in_series`]), one after another, each
/// on its body's share of the dofs (a single body is the whole case).
fn finite_body_estimate(case: &dyn Case, size: Size) -> Estimate {
    let bodies = case.bodies();
    let listed = bodies.len().max(1) as f64;
    let distinct = bodies
        .iter()
        .enumerate()
        .filter(|&(i, &b)| !bodies[..i].iter().any(|&q| std::ptr::addr_eq(b, q)))
        .count()
        .max(1) as f64;
    let one = crate::study::finite_body::estimate(Size {
        dofs: size.dofs / listed,
        ..size
    });
    Estimate {
        seconds: one.seconds * distinct,
        bytes: one.bytes,
    }
}

/// Joins record files (from `sweep --shard`) into a report in `out` (no time histories), each
/// study's complete and in its enumeration order ([`manifest::in_study_order`]).
pub fn merge(files: &[PathBuf], out: &Path) -> Result<Vec<RunRecord>> {
    distinct_files(files)?;
    complete_shards(files)?;
    let (mut read, mut seen) = (Vec::new(), Seen::default());
    for f in files {
        read.push((f.clone(), read_records(f, &mut seen)?));
    }
    if read.iter().all(|(_, r)| r.is_empty()) {
        return Err(Error::invalid(
            "records",
            files.len(),
            "the files hold no run: nothing to report",
        ));
    }
    // The inputs are named records*.csv and manifest*.txt (in_study_order refuses others),
    // none of the report's own names: no output can overwrite them.
    let records = manifest::in_study_order(read)?;
    // After the inputs, which are cheap to read: a bad input leaves no empty directory.
    crate::util::output_dir(out, "--out")?;
    let cases: Vec<CaseEntry> = crate::util::unique(records.iter().map(|r| r.summary.case.clone()))
        .into_iter()
        .map(|kind| CaseEntry {
            kind,
            title: String::new(),
            file: None,
        })
        .collect();
    write(
        out,
        &records,
        Vec::new(),
        (&[], (&[], &[])),
        (&cases, false),
    )?;
    Ok(records)
}

/// Refuses a records file given twice, by one path or by two that reach the same file (`./x`
/// and `x`, a symbolic link; compared as canonical paths): its runs would come twice, which the
/// shard count or the repeated keys reported only indirectly. A path that cannot be resolved (a
/// missing file) is compared as given; reading it names its fault.
fn distinct_files(files: &[PathBuf]) -> Result<()> {
    let same: Vec<PathBuf> = files
        .iter()
        .map(|f| std::fs::canonicalize(f).unwrap_or_else(|_| f.clone()))
        .collect();
    for (j, file) in same.iter().enumerate() {
        if let Some(i) = same[..j].iter().position(|f| f == file) {
            let how = match files[i] == files[j] {
                true => String::new(),
                false => format!(
                    " (as {} and {}: one file)",
                    files[i].display(),
                    files[j].display()
                ),
            };
            return Err(RECORDS_FILE.error(
                &files[i],
                format!("given twice{how}: give each records file once"),
            ));
        }
    }
    Ok(())
}

/// Refuses an incomplete set of shards: among the files named `records-<i>-of-<n>.csv` (as
/// `sweep --shard i/n` writes them, into one directory or one each), every i of 1..=n of one n
/// must come equally often: once for one sweep, k times for k sweeps sharded alike (their keys
/// differ; the same shard twice is a repeated key). A shard given more often than another is
/// named with its paths (one file given twice is [`distinct_files`]'s). A name of that form (i
/// and n digits) that `sweep` does not write (i = 0, i > n, a leading zero, beyond `usize`) is
/// refused, naming the file. Files of other names are the user's own.
fn complete_shards(files: &[PathBuf]) -> Result<()> {
    let shard = |f: &PathBuf| -> Result<Option<(usize, usize)>> {
        let parts = f.file_name().and_then(|n| n.to_str()).and_then(|name| {
            let digits = |x: &str| !x.is_empty() && x.bytes().all(|b| b.is_ascii_digit());
            let rest = name.strip_prefix("records-")?.strip_suffix(".csv")?;
            rest.split_once("-of-")
                .filter(|(i, n)| digits(i) && digits(n))
        });
        let Some((i, n)) = parts else {
            return Ok(None);
        };
        match (i.parse::<usize>(), n.parse::<usize>()) {
            (Ok(k), Ok(m)) if (1..=m).contains(&k) && k.to_string() == i && m.to_string() == n => {
                Ok(Some((m, k)))
            }
            _ => Err(RECORDS_FILE.error(
                f,
                format!(
                    "named as shard i = {i} of n = {n}, which `sweep --shard i/n` does not \
                     write (1 ≤ i ≤ n, without leading zeros; rename a file that is no shard)"
                ),
            )),
        }
    };
    let mut shards = Vec::new();
    for f in files {
        shards.extend(shard(f)?.map(|(n, k)| (n, k, f)));
    }
    shards.sort_unstable();
    for group in shards.chunk_by(|a, b| a.0 == b.0) {
        let n = group[0].0;
        let count = |k: usize| group.iter().filter(|s| s.1 == k).count();
        let most = group.iter().map(|s| count(s.1)).max().unwrap_or(0);
        // Lazily: n may be far above the files given (records-1-of-99999999999.csv).
        let mut missing = (1..=n).filter(|&k| count(k) < most).peekable();
        if missing.peek().is_some() {
            let mut names: Vec<String> = missing
                .by_ref()
                .take(5)
                .map(|k| format!("records-{k}-of-{n}.csv"))
                .collect();
            if missing.next().is_some() {
                names.push("…".into());
            }
            let names = names.join(", ");
            let why = match most {
                1 => format!(
                    " (given: {:?}; missing: {names})",
                    group.iter().map(|s| s.1).collect::<Vec<_>>()
                ),
                // A shard from two directories: a copy, or k sweeps' shards with one short.
                _ => {
                    let k = (1..=n).find(|&k| count(k) == most).unwrap_or(1);
                    let paths: Vec<String> = (group.iter().filter(|s| s.1 == k))
                        .map(|s| s.2.display().to_string())
                        .collect();
                    format!(
                        ": records-{k}-of-{n}.csv is given {most} times ({}), but {names} fewer \
                         (each shard comes once per sweep sharded alike: drop a copy, or give \
                         every shard of each sweep)",
                        paths.join(", ")
                    )
                }
            };
            return Err(Error::invalid(
                "records",
                format!("records-*-of-{n}.csv"),
                &format!("not the {n} shards of a sweep, each as often{why}"),
            ));
        }
    }
    Ok(())
}

/// The files of fixed names a report (or a merge) writes into its directory besides the
/// journal and the figures ([`write`], [`report`]).
const REPORT_FILES: [&str; 7] = [
    "summary.csv",
    "COLUMNS.md",
    "timings.csv",
    "orders.csv",
    "index.md",
    "index.html",
    "cross_code.csv",
];

fn write(
    out: &Path,
    records: &[RunRecord],
    mut figures: Vec<Figure>,
    (peers, (slides, studies)): (&[Agreement], (&friction::Slides, &[doc::Block])),
    (cases, quick): (&[CaseEntry], bool),
) -> Result<()> {
    write_records(&out.join("summary.csv"), records, false)?;
    crate::output::atomic::write_bytes(&out.join("COLUMNS.md"), columns::columns_md())?;
    write_timings(&out.join("timings.csv"), records)?;
    let orders = orders::orders(records);
    orders::write_orders(&out.join("orders.csv"), &orders)?;
    figures.splice(0..0, convergence_figures(out, records, &orders)?);
    figures.extend(schemes_compared::figures(out, records)?);
    index::write_index(
        out,
        &index::Contents {
            records,
            orders: &orders,
            figures: &figures,
            peers,
            slides,
            studies,
            cases,
            quick,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shards of one sweep in one directory or one each, and two sweeps sharded alike, merge;
    /// a missing or repeated shard does not (nor one of 10^11 shards, listed lazily); a name of
    /// the shard form that no sweep writes is refused; other names are the user's own set.
    #[test]
    fn every_shard_of_a_sweep_comes_equally_often() {
        let set = |names: &[&str]| -> Vec<PathBuf> { names.iter().map(PathBuf::from).collect() };
        for ok in [
            &["s/records-1-of-2.csv", "s/records-2-of-2.csv"][..],
            &["a/records-1-of-2.csv", "b/records-2-of-2.csv"],
            &[
                "a/records-1-of-2.csv",
                "a/records-2-of-2.csv",
                "b/records-2-of-2.csv",
                "b/records-1-of-2.csv",
            ],
            &["records-1-of-1.csv", "mine.csv"],
            &["mine.csv", "yours.csv"],
        ] {
            assert!(complete_shards(&set(ok)).is_ok(), "{ok:?}");
        }
        for (bad, missing) in [
            (&["records-1-of-2.csv"][..], "records-2-of-2.csv"),
            (&["records-1-of-2.csv", "mine.csv"], "records-2-of-2.csv"),
            (
                &[
                    "a/records-1-of-2.csv",
                    "b/records-1-of-2.csv",
                    "records-2-of-2.csv",
                ],
                "records-2-of-2.csv",
            ),
            (
                &["records-1-of-99999999999.csv"],
                "records-2-of-99999999999.csv",
            ),
        ] {
            let e = complete_shards(&set(bad)).unwrap_err().to_string();
            assert!(
                e.contains("shards of a sweep, each as often") && e.contains(missing),
                "{bad:?}: {e}"
            );
        }
        for name in [
            "records-3-of-2.csv",
            "records-0-of-2.csv",
            "records-1-of-0.csv",
            "records-01-of-2.csv",
            "records-1-of-18446744073709551616.csv",
        ] {
            let e = complete_shards(&set(&["mine.csv", name]))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(name) && e.contains("does not write"),
                "{name}: {e}"
            );
        }
        // A shard from two directories is named with both paths.
        let e = complete_shards(&set(&[
            "a/records-1-of-3.csv",
            "b/records-1-of-3.csv",
            "a/records-2-of-3.csv",
            "a/records-3-of-3.csv",
        ]))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains(
                "records-1-of-3.csv is given 2 times (a/records-1-of-3.csv, b/records-1-of-3.csv), \
                 but records-2-of-3.csv, records-3-of-3.csv fewer"
            ),
            "{e}"
        );
    }

    /// One records file given twice said the other shards were given "fewer than 2 times, as
    /// another shard is": it is named as given twice, by one path or by two reaching it
    /// (`sub/../x` and `x`); distinct files pass, and so does a path that does not resolve
    /// (read later).
    #[test]
    fn a_records_file_given_twice_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let [one, two] = ["records-1-of-2.csv", "records-2-of-2.csv"].map(|f| dir.path().join(f));
        for f in [&one, &two] {
            std::fs::write(f, "").unwrap();
        }
        let e = distinct_files(&[one.clone(), one.clone(), two.clone()])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("{}: given twice: give each", one.display())),
            "{e}"
        );
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let other = dir.path().join("sub/../records-1-of-2.csv");
        let e = distinct_files(&[other.clone(), two.clone(), one.clone()])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!(
                "as {} and {}: one file",
                other.display(),
                one.display()
            )),
            "{e}"
        );
        let missing = dir.path().join("records-3-of-3.csv");
        assert!(distinct_files(&[one, two, missing]).is_ok());
    }
}
