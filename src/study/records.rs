//! `records.csv` / `summary.csv` of a sweep: one row per run, written and read back (for
//! `dyncontact merge` and the journal), and `timings.csv` with the only non-deterministic
//! columns.

use super::jobs::{RunRecord, Status};
use super::metrics::{Metrics, METRIC_COLUMNS};
use super::run::{fmt_mib, summary_columns, summary_record, Summary, TIMING_COLUMNS};
use crate::error::Result;
use crate::input::{Input, TABLE};
use crate::output::csv::write_rows;
use std::collections::HashMap;
use std::path::Path;

/// Columns of `records.csv` before the summary columns.
pub const RECORD_COLUMNS: &[&str] = &["key", "sweep", "level", "status", "reason"];

/// The header of a records file: [`RECORD_COLUMNS`] then `summary.csv`'s columns, without the
/// machine-dependent [`TIMING_COLUMNS`] unless `with_timing`.
pub fn record_header(with_timing: bool) -> Vec<&'static str> {
    let mut header = RECORD_COLUMNS.to_vec();
    header.extend(
        summary_columns()
            .into_iter()
            .filter(|c| with_timing || !TIMING_COLUMNS.contains(c)),
    );
    header
}

/// The fields of one record under [`record_header`]`(with_timing)`.
pub fn record_fields(r: &RunRecord, with_timing: bool) -> Vec<String> {
    let mut v = vec![
        r.key.clone(),
        r.sweep.clone(),
        r.level.to_string(),
        r.status.as_str().to_string(),
        r.reason.clone(),
    ];
    v.extend(
        summary_record(&r.summary)
            .into_iter()
            .zip(summary_columns())
            .filter(|(_, c)| with_timing || !TIMING_COLUMNS.contains(c))
            .map(|(x, _)| x),
    );
    v
}

/// Writes the records under [`record_header`] (without the timing columns unless
/// `with_timing`, so that two report runs give byte-identical files).
pub fn write_records(path: &Path, records: &[RunRecord], with_timing: bool) -> Result<()> {
    write_rows(
        path,
        &record_header(with_timing),
        records.iter().map(|r| record_fields(r, with_timing)),
    )
}

/// Columns of `timings.csv`.
pub const TIMINGS_COLUMNS: &[&str] = &[
    "key",
    "case",
    "sweep",
    "space",
    "scheme",
    "parameters",
    "level",
    "dofs",
    "steps",
    "wall_time_s",
    "time_per_step_s",
    "time_per_dof_step_s",
    "max_rss_mb",
];

/// Writes `timings.csv`: wall time of the time loop (prepare included), per step and per
/// dof·step, and the process's peak resident memory when the run ended (MiB; runs in parallel
/// share it).
pub fn write_timings(path: &Path, records: &[RunRecord]) -> Result<()> {
    write_rows(
        path,
        TIMINGS_COLUMNS,
        records.iter().filter(|r| r.summary.steps > 0).map(|r| {
            let s = &r.summary;
            let per_step = s.wall_time / s.steps as f64;
            vec![
                r.key.clone(),
                s.case.clone(),
                r.sweep.clone(),
                s.space.clone(),
                s.scheme.clone(),
                s.parameters.clone(),
                r.level.to_string(),
                s.dofs.to_string(),
                s.steps.to_string(),
                format!("{:.6e}", s.wall_time),
                format!("{per_step:.6e}"),
                format!("{:.6e}", per_step / s.dofs.max(1) as f64),
                fmt_mib(s.max_rss),
            ]
        }),
    )
}

/// A records file read back (`dyncontact merge`).
pub const RECORDS_FILE: Input = TABLE.named("records file");

/// What the record files of a merge read so far hold, for the checks across files.
#[derive(Default)]
pub struct Seen {
    /// Each key's place (file, row).
    keys: HashMap<String, String>,
    /// Each case's case-file stem (the first part of its keys) with the place it came from.
    stems: HashMap<String, (String, String)>,
}

/// The case file's stem that starts `r`'s key, which a sweep writes as
/// `<stem>-<sweep>-<space>-<scheme>[-<parameters>]-L<level>` from the row's sweep, space,
/// scheme and level (the parameters as the sweep named them, which the `parameters` column may
/// spell otherwise); None when the key is not of the row's run.
fn key_stem(r: &RunRecord) -> Option<&str> {
    let s = &r.summary;
    let body = r.key.strip_suffix(&format!("-L{}", r.level))?;
    let run = format!("-{}-{}-{}", r.sweep, s.space, s.scheme);
    let stem = body
        .strip_suffix(&run)
        .or_else(|| body.find(&format!("{run}-")).map(|k| &body[..k]))?;
    (!stem.is_empty()).then_some(stem)
}

/// Reads records written by [`write_records`] (with or without the timing columns) for a
/// merge. Refuses a key `seen` already holds (one run, one row: from this file or an earlier
/// one), a key that is not of its row's run (sweep, space, scheme, parameters, level), and keys
/// of two case files of one case (their runs would be fitted as one series), naming both
/// places; adds the file's records to `seen`.
pub fn read_records(path: &Path, seen: &mut Seen) -> Result<Vec<RunRecord>> {
    let text = RECORDS_FILE.read(path)?;
    let records: Vec<RunRecord> = read_rows(&text, path, RECORDS_FILE, &[])?
        .into_iter()
        .map(|r| r.0)
        .collect();
    for (line, r) in records.iter().enumerate() {
        let here = format!("{}, row {}", path.display(), line + 2);
        let err = |m: String| {
            RECORDS_FILE.error(
                path,
                format!("row {}, column `key`: `{}` {m}", line + 2, r.key),
            )
        };
        if let Some(first) = seen.keys.insert(r.key.clone(), here.clone()) {
            return Err(err(format!("is the key of {first} too (one run, one row)")));
        }
        let s = &r.summary;
        let stem = key_stem(r).ok_or_else(|| {
            err(format!(
                "is not the key of its row's run, `<case file>-{}-{}-{}[-<parameters>]-L{}` \
                 (edited by hand?)",
                r.sweep, s.space, s.scheme, r.level
            ))
        })?;
        // A run whose case failed to build may have no case (written so before 2026-11-29).
        if s.case.is_empty() {
            continue;
        }
        let (first, place) = seen
            .stems
            .entry(s.case.clone())
            .or_insert_with(|| (stem.to_string(), here));
        if first != stem {
            return Err(err(format!(
                "is a run of case file `{stem}`, {place} one of case file `{first}`, both of case \
                 `{}`: their runs would be fitted as one series (merge each case file's records \
                 apart)",
                s.case
            )));
        }
    }
    Ok(records)
}

/// Metric columns that are maxima of absolute values, norms or times (`reports/COLUMNS.md`),
/// never negative: every `err_*` column and these.
const MAGNITUDES: &[&str] = &[
    "energy_drift",
    "energy_drift_free",
    "max_penetration",
    "sigma_total_variation",
    "impact_time_err",
    "slide_velocity_err",
    "friction_balance",
    "momentum_drift",
    "stop_time",
];

/// Whether the metric column `name` is never negative ([`MAGNITUDES`]).
fn is_magnitude(name: &str) -> bool {
    name.starts_with("err_") || MAGNITUDES.contains(&name)
}

/// Records from CSV text, each with the values of the `extra` columns (empty where the file has
/// none); `path` and `kind` name the file in messages.
pub fn read_rows(
    text: &[u8],
    path: &Path,
    kind: Input,
    extra: &[&str],
) -> Result<Vec<(RunRecord, Vec<String>)>> {
    let mut reader = csv::Reader::from_reader(text);
    let err = |m: String| kind.error(path, m);
    let header = reader.headers().map_err(|e| err(e.to_string()))?.clone();
    let col = |name: &str| header.iter().position(|h| h == name);
    for needed in record_header(false) {
        if col(needed).is_none() {
            return Err(err(format!("missing column `{needed}`")));
        }
    }
    let mut out = Vec::new();
    for (line, row) in reader.records().enumerate() {
        let row = row.map_err(|e| err(e.to_string()))?;
        let at = |what: &str| format!("row {}, column `{what}`", line + 2);
        let text = |name: &str| col(name).and_then(|i| row.get(i)).unwrap_or("").to_string();
        let float = |name: &str| -> Result<Option<f64>> {
            let t = text(name);
            if t.is_empty() {
                return Ok(None);
            }
            match t.parse::<f64>() {
                // Records write an absent value as an empty field, and every value finite (a
                // run that goes non-finite stops as `diverged`).
                Ok(v) if !v.is_finite() => Err(err(format!(
                    "{}: `{t}` (values are finite; an absent value is an empty field)",
                    at(name)
                ))),
                Ok(v) => Ok(Some(v)),
                Err(e) => Err(err(format!("{}: {e}", at(name)))),
            }
        };
        // A size of the run (finite, by `float`): positive (dt, h) or not negative (time,
        // memory).
        let size = |name: &str, zero: bool| -> Result<Option<f64>> {
            let v = float(name)?;
            match v {
                Some(x) if x < 0.0 || (x == 0.0 && !zero) => Err(err(format!(
                    "{}: {x} (must be {})",
                    at(name),
                    if zero { "≥ 0" } else { "> 0" }
                ))),
                _ => Ok(v),
            }
        };
        let count = |name: &str| -> Result<usize> {
            text(name)
                .parse()
                .map_err(|e| err(format!("{}: {e}", at(name))))
        };
        let nan = |x: Option<f64>| x.unwrap_or(f64::NAN);
        let status = Status::parse(&text("status")).ok_or_else(|| {
            let known: Vec<&str> = Status::ALL.iter().map(|s| s.as_str()).collect();
            err(format!(
                "{}: `{}` (one of {})",
                at("status"),
                text("status"),
                known.join(", ")
            ))
        })?;
        // The case and the sweep name the report's files: plain names, no `/` nor `..` (an
        // empty case: a run whose case failed to build, written so before 2026-11-29).
        let name = |column: &str| -> Result<String> {
            let value = text(column);
            if !(column == "case" && value.is_empty()) {
                crate::util::check_name(column, &value)
                    .map_err(|e| err(format!("{}: {e}", at(column))))?;
            }
            Ok(value)
        };
        let (case, sweep) = (name("case")?, name("sweep")?);
        let mut metrics = Metrics::default();
        for c in METRIC_COLUMNS {
            let v = float(c.name)?;
            if let Some(x) = v.filter(|&x| x < 0.0 && is_magnitude(c.name)) {
                return Err(err(format!(
                    "{}: {x} (a maximum of absolute values, a norm or a time: ≥ 0; \
                     see COLUMNS.md)",
                    at(c.name)
                )));
            }
            (c.set)(&mut metrics, v);
        }
        let key = text("key");
        if key.is_empty() {
            return Err(err(format!("{}: empty (every run has a key)", at("key"))));
        }
        let steps = count("steps")?;
        // A run that did not finish records 0 steps; one that did took at least one.
        if steps == 0 && status == Status::Ok {
            return Err(err(format!(
                "{}: 0 with status `ok` (a finished run took at least one step)",
                at("steps")
            )));
        }
        let degree = match text("degree").as_str() {
            "" => None,
            _ => Some(count("degree")?),
        };
        let record = RunRecord {
            key,
            sweep,
            level: count("level")?,
            status,
            reason: text("reason"),
            summary: Summary {
                case,
                space: text("space"),
                scheme: text("scheme"),
                parameters: text("parameters"),
                contact: text("contact"),
                degree,
                cells: text("cells"),
                h: nan(size("h", false)?),
                dt: size("dt", false)?.ok_or_else(|| err(format!("{}: empty", at("dt"))))?,
                dofs: count("dofs")?,
                steps,
                contact_iterations: count("contact_iterations")?,
                wall_time: size("wall_time_s", true)?.unwrap_or(0.0),
                max_rss: size("max_rss_mb", true)?.map_or(f64::NAN, |m| m * 1048576.0),
                metrics,
            },
            probe: Vec::new(),
        };
        out.push((record, extra.iter().map(|c| text(c)).collect()));
    }
    Ok(out)
}
