//! Observed orders of convergence from run records: least-squares slope of log(error) against
//! log(h) (log(dt) for a 0D case) per case × sweep × space × scheme × quantity, with the RMS
//! residual of the fit and the value expected from the literature where known. A series whose
//! sizes do not refine (span less than [`MIN_SPAN`]) is not fitted.

use super::jobs::{RunRecord, Status};
use super::metrics::{Metrics, METRIC_COLUMNS};
use super::reference::{common_reference, Series};
use super::run::Summary;
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

/// An order expected from theory: a range `[low, high]` and how it is written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Expected {
    /// Lower end.
    pub low: f64,
    /// Upper end.
    pub high: f64,
    /// As written in `orders.csv` (`1`, `1/3-1/2`).
    pub text: &'static str,
}

/// Expected order from the literature / theory, where known (`shared/reference/methods.md`:
/// about 1 for u in L∞(L²) and u(0, t), about ⅓ to ½ for the H¹ error, the energy and the
/// contact stress in L²(0, T), for second-order schemes with dt ∝ h on the bar).
pub fn expected(case: &str, quantity: &str) -> Option<Expected> {
    let (low, high, text) = match (case, quantity) {
        ("bar1d", "err_u_linf_l2" | "err_u_contact") => (1.0, 1.0, "1"),
        ("bar1d", "err_u_l2_h1" | "err_energy" | "err_sigma_l2") => (1.0 / 3.0, 0.5, "1/3-1/2"),
        // The same velocity jumps on characteristics (shared/reference/bar_flight_and_two_bars.md).
        ("two_bars" | "two_bars_unequal", "err_u_linf_l2" | "err_u_contact") => (1.0, 1.0, "1"),
        ("two_bars" | "two_bars_unequal", "err_u_l2_h1" | "err_sigma_l2") => {
            (1.0 / 3.0, 0.5, "1/3-1/2")
        }
        _ => return None,
    };
    Some(Expected { low, high, text })
}

/// The `literature` column: the expected order as written, or empty.
pub fn literature(case: &str, quantity: &str) -> &'static str {
    expected(case, quantity).map_or("", |e| e.text)
}

/// An RMS residual of the fit (in ln) above this: the errors do not lie on a line, the slope
/// is not an order.
pub const IRREGULAR: f64 = 0.25;
/// A finest-level error above this fraction of the coarsest: the error does not decrease.
pub const FLAT: f64 = 0.9;
/// An order below this (the fit otherwise sound): the quantity does not converge.
pub const STALLS: f64 = 0.2;
/// An order at or above this fraction of the expected lower end meets the expectation.
pub const MEETS: f64 = 0.7;

/// What an observed order says, in the words of the report and of `orders.csv`'s `verdict`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Converges at (or near: [`MEETS`]) the expected order, or at order ≥ [`STALLS`] where
    /// none is known.
    Meets,
    /// Converges, more slowly than expected.
    Below,
    /// A sound fit of order below [`STALLS`]: does not converge.
    Stalls,
    /// The error grows: the finest-level error exceeds the coarsest / [`FLAT`] (or the slope
    /// is negative).
    Grows,
    /// The finest-level error is within [`FLAT`] of the coarsest (either way): the error does
    /// not decrease.
    Flat,
    /// The fit's residual exceeds [`IRREGULAR`]: the errors do not lie on a line.
    Irregular,
    /// Fewer than two usable levels, or levels whose sizes do not refine (within [`MIN_SPAN`]).
    TooFewLevels,
}

impl Verdict {
    /// The `verdict` column.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Meets => "meets",
            Verdict::Below => "below",
            Verdict::Stalls => "stalls",
            Verdict::Grows => "grows",
            Verdict::Flat => "flat",
            Verdict::Irregular => "irregular",
            Verdict::TooFewLevels => "too_few_levels",
        }
    }

    /// True when the slope is an order worth printing (meets, below, stalls).
    pub fn is_order(self) -> bool {
        matches!(self, Verdict::Meets | Verdict::Below | Verdict::Stalls)
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
    /// residual of the fit; None with fewer than two usable levels or sizes that span less
    /// than [`MIN_SPAN`].
    pub fit: Option<(f64, f64)>,
    /// Levels used (status ok, error finite and > 0).
    pub points: usize,
    /// The error at the coarsest and at the finest usable level.
    pub ends: Option<(f64, f64)>,
    /// h (dt for a 0D case) of the finest usable level.
    pub finest: Option<f64>,
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
            let usable: Vec<(&Summary, f64)> = runs
                .iter()
                .filter(|r| r.status == Status::Ok)
                .filter_map(|r| {
                    let e = get(&r.summary.metrics).filter(|e| e.is_finite() && *e > 0.0)?;
                    Some((&r.summary, e))
                })
                .collect();
            if runs.iter().all(|r| get(&r.summary.metrics).is_none()) {
                continue;
            }
            let pts: Vec<(f64, f64)> = usable.iter().map(|(s, e)| (size(s), *e)).collect();
            let (x, y): (Vec<f64>, Vec<f64>) = pts.iter().copied().unzip();
            // Levels come coarsest first.
            let finest = pts.iter().copied().min_by(|a, b| a.0.total_cmp(&b.0));
            let coarsest = pts.iter().copied().max_by(|a, b| a.0.total_cmp(&b.0));
            out.push(Order {
                case: case.clone(),
                sweep: sweep.clone(),
                space: space.clone(),
                scheme: scheme.clone(),
                parameters: parameters.clone(),
                quantity,
                fit: refines(&usable).then(|| fit_order(&x, &y)),
                points: pts.len(),
                ends: coarsest.zip(finest).map(|(c, f)| (c.1, f.1)),
                finest: finest.map(|f| f.0),
                reference: reference_of(quantity),
            });
        }
    }
    out
}

/// Levels whose sizes span less than this ratio are not a refinement: no order is fitted
/// (repeated or near-repeated levels gave a NaN or an order of 10⁹).
pub const MIN_SPAN: f64 = 1.1;

/// The size a level is fitted against: h, or dt for the 0D spring (whose h is NaN), as the
/// figures draw them.
fn size(s: &Summary) -> f64 {
    if s.h.is_finite() {
        s.h
    } else {
        s.dt
    }
}

/// True when the levels are a refinement to fit: at least two, all with a finite h or all
/// without (the 0D spring: dt), their sizes finite, positive and spanning [`MIN_SPAN`].
fn refines(levels: &[(&Summary, f64)]) -> bool {
    let with_h = levels.iter().filter(|(s, _)| s.h.is_finite()).count();
    if levels.len() < 2 || (with_h != 0 && with_h != levels.len()) {
        return false;
    }
    let sizes: Vec<f64> = levels.iter().map(|(s, _)| size(s)).collect();
    if sizes.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
        return false;
    }
    let lo = sizes.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = sizes.iter().copied().fold(0.0, f64::max);
    hi >= MIN_SPAN * lo
}

impl Order {
    /// What the fit says ([`Verdict`]), against the expected order of its case and quantity.
    pub fn verdict(&self) -> Verdict {
        let (Some((order, residual)), Some((first, last))) = (self.fit, self.ends) else {
            return Verdict::TooFewLevels;
        };
        if residual > IRREGULAR {
            Verdict::Irregular
        } else if last > first / FLAT || (order < 0.0 && last <= FLAT * first) {
            Verdict::Grows
        } else if last > FLAT * first {
            Verdict::Flat
        } else if order < STALLS {
            Verdict::Stalls
        } else {
            match expected(&self.case, self.quantity) {
                Some(e) if order < MEETS * e.low => Verdict::Below,
                _ => Verdict::Meets,
            }
        }
    }
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
    "finest_error",
    "verdict",
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
                crate::output::fmt_float(o.ends.map(|e| e.1)),
                o.verdict().as_str().to_string(),
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

    fn order(quantity: &'static str, errors: &[f64]) -> Order {
        let h: Vec<f64> = (0..errors.len()).map(|k| 0.5f64.powi(k as i32)).collect();
        Order {
            case: "bar1d".into(),
            sweep: "orders".into(),
            space: "standard".into(),
            scheme: "newmark".into(),
            parameters: String::new(),
            quantity,
            fit: (errors.len() >= 2).then(|| fit_order(&h, errors)),
            points: errors.len(),
            ends: errors.first().zip(errors.last()).map(|(a, b)| (*a, *b)),
            finest: h.last().copied(),
            reference: "exact".into(),
        }
    }

    fn level(h: f64, dt: f64) -> Summary {
        Summary {
            case: "bar1d".into(),
            space: "standard".into(),
            scheme: "newmark".into(),
            parameters: String::new(),
            contact: "nodal".into(),
            degree: Some(1),
            cells: "segment".into(),
            h,
            dt,
            dofs: 1,
            steps: 1,
            contact_iterations: 0,
            wall_time: 0.0,
            max_rss: f64::NAN,
            metrics: Metrics::unavailable(),
        }
    }

    /// Only a refinement is fitted: repeated or near-repeated sizes (a NaN, or an order of 10⁹,
    /// before), a level without h among levels with one, a single level are not.
    #[test]
    fn only_levels_that_refine_are_fitted() {
        let fits = |sizes: &[(f64, f64)]| {
            let levels: Vec<Summary> = sizes.iter().map(|&(h, dt)| level(h, dt)).collect();
            let usable: Vec<(&Summary, f64)> = levels.iter().map(|s| (s, 1.0)).collect();
            refines(&usable)
        };
        assert!(fits(&[(0.1, 0.01), (0.05, 0.005)]));
        assert!(
            fits(&[(f64::NAN, 0.01), (f64::NAN, 0.005)]),
            "the spring: dt"
        );
        assert!(!fits(&[(0.1, 0.01)]));
        assert!(
            !fits(&[(0.1, 0.01), (0.1, 0.005)]),
            "h repeated: not against dt"
        );
        assert!(!fits(&[(0.1, 0.01), (0.1 * (1.0 + 1e-9), 0.01)]));
        assert!(!fits(&[(0.1, 0.01), (f64::NAN, 0.005), (0.025, 0.0025)]));
        assert!(!fits(&[(f64::NAN, 0.01), (f64::NAN, 0.01)]));
        assert!(!fits(&[(0.1, 0.01), (-0.05, 0.005)]));
    }

    /// The verdicts of the examples: hertz2d standard's peak pressure error growing
    /// from 5e-5 to 1.6e-2, Moreau–Jean's flat 0.6, the standard σ_N's order 0.1.
    #[test]
    fn fits_that_are_not_orders_are_flagged() {
        assert_eq!(
            order("err_sigma_l2", &[5e-5, 1e-3, 1.6e-2]).verdict(),
            Verdict::Grows
        );
        assert_eq!(
            order("err_u_contact", &[0.6, 0.61, 0.6, 0.6]).verdict(),
            Verdict::Flat
        );
        assert_eq!(
            order("err_u_contact", &[0.6, 0.6, 0.6, 0.59]).verdict(),
            Verdict::Flat
        );
        let e: Vec<f64> = (0..5).map(|k| 0.8 * 0.5f64.powf(0.11 * k as f64)).collect();
        assert_eq!(order("err_sigma_l2", &e).verdict(), Verdict::Stalls);
        let e: Vec<f64> = (0..5).map(|k| 0.3 * 0.5f64.powf(0.33 * k as f64)).collect();
        assert_eq!(order("err_sigma_l2", &e).verdict(), Verdict::Meets);
        let e: Vec<f64> = (0..5).map(|k| 0.1 * 0.5f64.powf(0.5 * k as f64)).collect();
        assert_eq!(order("err_u_contact", &e).verdict(), Verdict::Below);
        assert_eq!(
            order("err_u_contact", &[1e-1, 1e-3, 5e-2, 1e-4]).verdict(),
            Verdict::Irregular
        );
        assert_eq!(
            order("err_u_contact", &[1e-1]).verdict(),
            Verdict::TooFewLevels
        );
    }
}
