//! `timeseries.csv` and `summary.csv` of a run.
//!
//! `timeseries.csv`: `t, u_contact, v_contact, sigma_contact, energy, gap` and, when the case has
//! an exact solution, `u_contact_exact, sigma_contact_exact, energy_exact`. `sigma_contact` is the
//! normal contact stress σ_N = −λ/area (compression negative). Units are those of the case file
//! (time, length, length/time, force/area, energy, length).

use super::fmt_float;
use crate::error::{Error, Result};
use crate::run::{Row, Summary};
use std::path::Path;

/// Columns of `timeseries.csv` (then the `_exact` columns when present).
pub const TIMESERIES_COLUMNS: &[&str] = &[
    "t",
    "u_contact",
    "v_contact",
    "sigma_contact",
    "energy",
    "gap",
];
/// Exact-solution columns of `timeseries.csv`.
pub const EXACT_COLUMNS: &[&str] = &["u_contact_exact", "sigma_contact_exact", "energy_exact"];
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

fn writer(path: &Path) -> Result<csv::Writer<std::fs::File>> {
    csv::Writer::from_path(path).map_err(|e| Error::Csv {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Writes a CSV file with `header` and string rows.
pub fn write_rows<I, R>(path: &Path, header: &[&str], rows: I) -> Result<()>
where
    I: IntoIterator<Item = R>,
    R: IntoIterator<Item = String>,
{
    let err = |e: csv::Error| Error::Csv {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let mut w = writer(path)?;
    w.write_record(header).map_err(err)?;
    for r in rows {
        w.write_record(r).map_err(err)?;
    }
    w.flush().map_err(|e| Error::io(path, e))
}

/// Writes `timeseries.csv`.
pub fn write_timeseries(path: &Path, rows: &[Row]) -> Result<()> {
    let exact = rows.first().is_some_and(|r| r.exact.is_some());
    let mut header = TIMESERIES_COLUMNS.to_vec();
    if exact {
        header.extend_from_slice(EXACT_COLUMNS);
    }
    write_rows(
        path,
        &header,
        rows.iter().map(|r| {
            let mut v = vec![
                r.t,
                r.u_contact,
                r.v_contact,
                r.sigma_contact,
                r.energy,
                r.gap,
            ];
            if let Some((u, s, e)) = r.exact {
                v.extend([u, s, e]);
            }
            v.into_iter().map(|x| fmt_float(Some(x)))
        }),
    )
}

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
