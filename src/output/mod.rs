//! Outputs: CSV files (fixed float formatting) and PNG plots.

pub mod csv;
pub mod index;
pub mod plot;
pub mod records;

/// A float as written to CSV: `{:.12e}`; `None` as an empty field.
pub fn fmt_float(x: Option<f64>) -> String {
    x.map_or_else(String::new, |v| format!("{v:.12e}"))
}

/// `x` rounded to 6 significant digits, printed in scientific notation (snapshots).
pub fn sig6(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.5e}")
    } else {
        format!("{x}")
    }
}

use crate::error::{Error, Result};
use crate::run::RunResult;
use plot::{time_plot, Series, PALETTE};
use std::path::Path;

/// Writes `timeseries.csv`, `summary.csv`, `energy.png` and `contact.png` of a run into `dir`.
pub fn write_run(dir: &Path, result: &RunResult) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    csv::write_timeseries(&dir.join("timeseries.csv"), &result.rows)?;
    csv::write_summary(
        &dir.join("summary.csv"),
        std::slice::from_ref(&result.summary),
    )?;
    let s = &result.summary;
    let label = format!("{} + {} ({})", s.space, s.scheme, s.parameters);
    let curve =
        |f: &dyn Fn(&crate::run::Row) -> f64| result.rows.iter().map(|r| (r.t, f(r))).collect();
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
