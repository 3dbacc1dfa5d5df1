//! Observed orders of convergence from run records: least-squares slope of log(error) against
//! log(h) (log(dt) for a 0D case) per case × sweep × space × scheme × quantity, with the RMS
//! residual of the fit and the value expected from the literature where known.

use super::jobs::{RunRecord, Status};
use super::metrics::{Metrics, METRIC_COLUMNS};
use super::reference::{common_reference, Series};
use crate::error::Result;
use crate::util::group_by;
use std::path::Path;

/// Least-squares slope of log(y) against log(x) and the RMS residual of the fit.
pub fn fit_order(x: &[f64], y: &[f64]) -> (f64, f64) {
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let n = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx).powi(2)).sum();
    let slope = sxy / sxx;
    let res = lx
        .iter()
        .zip(&ly)
        .map(|(a, b)| (b - my - slope * (a - mx)).powi(2))
        .sum::<f64>();
    (slope, (res / n).sqrt())
}

/// Quantities whose observed orders are fitted, with their accessor.
pub type Quantity = (&'static str, fn(&Metrics) -> Option<f64>);

/// The errors against Hertz theory (curved-body cases): they reach a plateau, Hertz's own model
/// error, rather than zero as h, dt → 0; their fitted slope says how flat it is.
pub const HERTZ_QUANTITIES: [&str; 4] = [
    "err_contact_duration",
    "err_peak_force",
    "err_contact_radius",
    "err_peak_pressure",
];

/// The fitted quantities (metric columns): displacement, energy, contact stress and impact time
/// errors, and the errors against Hertz theory.
pub const FITTED: [&str; 12] = [
    "err_u_linf_l2",
    "err_u_contact",
    "err_u_l2_h1",
    "err_energy",
    "err_sigma_l2",
    "impact_time_err",
    "err_u_contact_ref",
    "err_sigma_l2_ref",
    "err_contact_duration",
    "err_peak_force",
    "err_contact_radius",
    "err_peak_pressure",
];

/// The fitted quantities with their accessors, in [`FITTED`] order.
pub fn quantities() -> impl Iterator<Item = Quantity> {
    FITTED.into_iter().filter_map(|name| {
        METRIC_COLUMNS
            .iter()
            .find(|c| c.name == name)
            .map(|c| (c.name, c.get))
    })
}

/// Slope of the reference triangle drawn on convergence plots of `quantity`.
pub fn reference_slope(quantity: &str) -> f64 {
    match quantity {
        "err_u_linf_l2" | "err_u_contact" => 1.0,
        "impact_time_err" => 2.0,
        _ => 0.5,
    }
}

/// Expected order from the literature / theory, where known (`shared/reference/methods.md`).
pub fn literature(case: &str, quantity: &str) -> &'static str {
    match (case, quantity) {
        ("bar1d", "err_u_linf_l2" | "err_u_contact") => "1",
        ("bar1d", "err_u_l2_h1" | "err_energy" | "err_sigma_l2") => "1/3-1/2",
        _ => "",
    }
}

/// One row of `orders.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct Order {
    /// Case kind.
    pub case: String,
    /// Sweep name.
    pub sweep: String,
    /// Space.
    pub space: String,
    /// Scheme.
    pub scheme: String,
    /// Scheme parameters.
    pub parameters: String,
    /// Quantity name.
    pub quantity: &'static str,
    /// Least-squares slope of log(error) against log(h) (log(dt) for 0D cases) and the RMS
    /// residual of the fit; None with fewer than two usable levels.
    pub fit: Option<(f64, f64)>,
    /// Levels used (status ok, error finite and > 0).
    pub points: usize,
    /// What the errors are measured against: `exact`, `own finest level`, or the common
    /// reference `<space> <scheme> (<parameters>) finest level`.
    pub reference: String,
}

/// Observed orders per case × sweep × space × scheme × quantity, in record order.
pub fn orders(records: &[RunRecord]) -> Vec<Order> {
    let mut out = Vec::new();
    let common: Vec<((String, String), Option<Series>)> =
        group_by(records, |r| (r.summary.case.clone(), r.sweep.clone()))
            .into_iter()
            .map(|(k, rs)| (k, common_reference(rs.into_iter())))
            .collect();
    for ((case, sweep, space, scheme, parameters), runs) in group_by(records, |r| r.series_key()) {
        // The probe errors of a case with an exact field solution are against it.
        let exact = runs.iter().any(|r| r.summary.metrics.err_energy.is_some());
        let reference_of = |quantity: &str| -> String {
            if exact {
                return "exact".into();
            }
            if HERTZ_QUANTITIES.contains(&quantity) {
                return "Hertz theory".into();
            }
            if !quantity.ends_with("_ref") {
                return "own finest level".into();
            }
            common
                .iter()
                .find(|(k, _)| *k == (case.clone(), sweep.clone()))
                .and_then(|(_, c)| c.as_ref())
                .map_or_else(String::new, |(sp, sc, pa)| {
                    format!("{sp} {} finest level", super::run::method_label(sc, pa))
                })
        };
        for (quantity, get) in quantities() {
            let pts: Vec<(f64, f64)> = runs
                .iter()
                .filter(|r| r.status == Status::Ok)
                .filter_map(|r| {
                    let s = &r.summary;
                    let x = if s.h.is_finite() { s.h } else { s.dt };
                    get(&s.metrics)
                        .filter(|e| e.is_finite() && *e > 0.0)
                        .map(|e| (x, e))
                })
                .collect();
            if runs.iter().all(|r| get(&r.summary.metrics).is_none()) {
                continue;
            }
            let (x, y): (Vec<f64>, Vec<f64>) = pts.iter().copied().unzip();
            out.push(Order {
                case: case.clone(),
                sweep: sweep.clone(),
                space: space.clone(),
                scheme: scheme.clone(),
                parameters: parameters.clone(),
                quantity,
                fit: (pts.len() >= 2).then(|| fit_order(&x, &y)),
                points: pts.len(),
                reference: reference_of(quantity),
            });
        }
    }
    out
}

/// Columns of `orders.csv`.
pub const ORDER_COLUMNS: &[&str] = &[
    "case",
    "sweep",
    "space",
    "scheme",
    "parameters",
    "quantity",
    "order",
    "fit_residual",
    "points",
    "literature",
    "reference",
];

/// Writes `orders.csv` (orders and residuals with 4 decimals).
pub fn write_orders(path: &Path, orders: &[Order]) -> Result<()> {
    crate::output::csv::write_rows(
        path,
        ORDER_COLUMNS,
        orders.iter().map(|o| {
            vec![
                o.case.clone(),
                o.sweep.clone(),
                o.space.clone(),
                o.scheme.clone(),
                o.parameters.clone(),
                o.quantity.to_string(),
                o.fit.map_or_else(String::new, |f| format!("{:.4}", f.0)),
                o.fit.map_or_else(String::new, |f| format!("{:.4}", f.1)),
                o.points.to_string(),
                literature(&o.case, o.quantity).to_string(),
                o.reference.clone(),
            ]
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every fitted quantity is a metric column (a misspelt name would drop it silently).
    #[test]
    fn every_fitted_quantity_is_a_metric_column() {
        assert_eq!(quantities().count(), FITTED.len());
    }
}
