//! Generic outputs: CSV files (fixed float formatting), PNG plots and VTK fields; they know
//! nothing of runs or reports. Every file is written through [`atomic`]: complete or not at all.

pub mod atomic;
pub mod csv;
pub mod field_plot;
pub mod plot;
pub mod vtu;

/// A float as written to CSV: `{:.12e}`, −0 as 0 (`approach` at t = 0); `None` and NaN (a
/// value that does not exist, e.g. h of a 0D case or a metric of a run that did not finish) as
/// an empty field, the one missing-value convention of every CSV.
pub fn fmt_float(x: Option<f64>) -> String {
    match x {
        Some(v) if !v.is_nan() => format!("{:.12e}", v + 0.0),
        _ => String::new(),
    }
}

/// `x` rounded to 6 significant digits, printed in scientific notation (snapshots).
pub fn sig6(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.5e}")
    } else {
        format!("{x}")
    }
}
