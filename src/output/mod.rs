//! Generic outputs: CSV files (fixed float formatting) and PNG plots; they know nothing of
//! runs or reports.

pub mod csv;
pub mod field_plot;
pub mod plot;
pub mod vtu;

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
