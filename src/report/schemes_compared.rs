//! "Schemes compared" (issue 23 §3): the table that answers *which space + scheme gives a stable
//! energy, no penetration and a usable contact stress, at what cost?*, first in the findings.
//!
//! A case × sweep is compared when it runs at least [`MIN_SCHEMES`] distinct time schemes (the
//! sweeps that put the time-scheme cures beside the space cures: bar1d's and bar_flight's
//! `orders`, block2d's `schemes`) of a case without friction (with friction the energy drift is
//! mostly the work friction dissipates, and the frictionless baseline of such a case slides under
//! gravity, never "after the last impact": the "Friction" section reads those runs). One row per
//! scheme × space, read at the finest level that finished: the energy drift `max_n |E_n − E_0| / E_0` over the run, the energy change
//! `E_N / E_0 − 1` at the end (after the last impact: every compared run ends out of contact),
//! the largest penetration `max(0, −g)` at the probe, the total variation of σ_N over the run
//! relative to the exact one (1: as smooth as the exact stress), the observed orders of u, σ_N and
//! the energy error over the levels, the wall time per step and per dof·step, and the status of
//! the levels. One figure per case: energy drift against max penetration, one panel per space,
//! one mark per scheme, so that the trade-off is seen at a glance.

use super::doc::{Block, Cell, Doc, Figure, Rich, Tone};
use super::verdict::cell_text;
use crate::error::Result;
use crate::output::plot::{loglog_panels, Dash, Series, Style};
use crate::study::jobs::{RunRecord, Status};
use crate::study::orders::Order;
use crate::util::unique;
use std::path::Path;

/// A sweep with at least this many distinct schemes is compared.
pub const MIN_SCHEMES: usize = 3;

/// The section's id; its figures carry it as their `case`.
pub const SECTION: &str = "schemes compared";

/// Values at or below this are drawn at it on the figure's log axes (no penetration at all,
/// energy conserved to round-off).
pub const FLOOR: f64 = 1e-14;

/// The orders shown, each the first of its group a sweep has: displacement, contact stress,
/// energy.
const ORDERS: [&[&str]; 3] = [
    &["err_u_contact", "err_u_contact_ref", "err_u_linf_l2"],
    &["err_sigma_l2", "err_sigma_l2_ref"],
    &["err_energy"],
];

/// The compared case × sweep pairs, in record order.
pub fn compared(records: &[RunRecord]) -> Vec<(String, String)> {
    let friction_cases = unique(
        records
            .iter()
            .filter(|r| r.summary.metrics.friction_balance.is_some())
            .map(|r| r.summary.case.clone()),
    );
    unique(
        records
            .iter()
            .map(|r| (r.summary.case.clone(), r.sweep.clone())),
    )
    .into_iter()
    .filter(|(case, sweep)| {
        let runs = || {
            records
                .iter()
                .filter(|r| &r.summary.case == case && &r.sweep == sweep)
        };
        unique(runs().map(|r| r.summary.scheme.clone())).len() >= MIN_SCHEMES
            && !friction_cases.contains(case)
    })
    .collect()
}

/// One row of the table: a scheme × space series of a compared sweep.
#[derive(Debug, Clone)]
pub struct Row<'a> {
    /// Scheme with parameters as every output writes it.
    pub method: String,
    /// Scheme name (its style).
    pub scheme: String,
    /// Space.
    pub space: String,
    /// The finest level that finished.
    pub finest: Option<&'a RunRecord>,
    /// Levels that did not finish, and the first one's status.
    pub failed: (usize, usize, Option<Status>),
}

impl Row<'_> {
    /// `(max penetration, energy drift)` of the finest level, floored at [`FLOOR`].
    pub fn tradeoff(&self) -> Option<(f64, f64)> {
        let m = &self.finest?.summary.metrics;
        let floor = |x: f64| if x.is_finite() { x.max(FLOOR) } else { x };
        Some((floor(m.max_penetration), floor(m.energy_drift)))
    }
}

/// The rows of `case` × `sweep`, by scheme then space in record order.
pub fn rows<'a>(records: &'a [RunRecord], (case, sweep): (&str, &str)) -> Vec<Row<'a>> {
    let series: Vec<&RunRecord> = records
        .iter()
        .filter(|r| r.summary.case == case && r.sweep == sweep)
        .collect();
    let methods = unique(series.iter().map(|r| r.summary.method()));
    let spaces = unique(series.iter().map(|r| r.summary.space.clone()));
    let mut out = Vec::new();
    for method in &methods {
        for space in &spaces {
            let levels: Vec<&&RunRecord> = series
                .iter()
                .filter(|r| &r.summary.method() == method && &r.summary.space == space)
                .collect();
            let Some(first) = levels.first() else {
                continue;
            };
            let failed: Vec<&&&RunRecord> =
                levels.iter().filter(|r| r.status != Status::Ok).collect();
            out.push(Row {
                method: method.clone(),
                scheme: first.summary.scheme.clone(),
                space: space.clone(),
                finest: levels
                    .iter()
                    .filter(|r| r.status == Status::Ok)
                    .max_by_key(|r| r.level)
                    .map(|r| **r),
                failed: (failed.len(), levels.len(), failed.first().map(|r| r.status)),
            });
        }
    }
    out
}

/// A number in three significant digits, or a dash's absence (empty) when unknown.
fn sci(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2e}")
    } else {
        String::new()
    }
}

/// The order cell of the first quantity of `group` the series has.
fn order_cell(
    orders: &[Order],
    (case, sweep): (&str, &str),
    row: &Row<'_>,
    group: &[&str],
) -> Cell {
    let found = group.iter().find_map(|q| {
        orders.iter().find(|o| {
            o.case == case
                && o.sweep == sweep
                && o.space == row.space
                && o.quantity == *q
                && crate::study::run::method_label(&o.scheme, &o.parameters) == row.method
        })
    });
    match found {
        Some(o) => {
            let (text, tone) = cell_text(o);
            Cell {
                lines: vec![(Rich::default().text(text), tone)],
                tone: Tone::Plain,
            }
        }
        None => Cell::default(),
    }
}

/// The table of one compared case × sweep.
fn table(d: &mut Doc, records: &[RunRecord], orders: &[Order], at: (&str, &str)) {
    let header = [
        "scheme",
        "space",
        "energy drift",
        "E(T)/E₀ − 1",
        "max penetration",
        "σₙ total variation",
        "order u",
        "order σₙ",
        "order E",
        "ms / step",
        "µs / dof·step",
        "status",
    ]
    .map(|h| Rich::default().text(h))
    .to_vec();
    let body = rows(records, at)
        .iter()
        .map(|row| {
            let mut cells: Vec<Cell> = vec![row.method.clone().into(), row.space.clone().into()];
            let s = row.finest.map(|r| &r.summary);
            let metric = |f: &dyn Fn(&crate::study::run::Summary) -> f64| -> Cell {
                sci(s.map_or(f64::NAN, f)).into()
            };
            cells.push(metric(&|s| s.metrics.energy_drift));
            cells.push(metric(&|s| s.metrics.energy_ratio - 1.0));
            cells.push(metric(&|s| s.metrics.max_penetration));
            cells.push(metric(&|s| s.metrics.sigma_total_variation));
            for group in ORDERS {
                cells.push(order_cell(orders, at, row, group));
            }
            cells.push(metric(&|s| 1e3 * s.wall_time / s.steps as f64));
            cells.push(metric(&|s| 1e6 * s.wall_time / (s.steps * s.dofs) as f64));
            let (bad, all, first) = row.failed;
            cells.push(match first {
                None => Cell::plain("ok"),
                Some(status) => Cell {
                    lines: vec![(
                        Rich::default().text(format!("{bad} of {all} {}", status.as_str())),
                        Tone::Bad,
                    )],
                    tone: Tone::Plain,
                },
            });
            cells
        })
        .collect();
    d.push(Block::Table(header, body));
}

/// The file of the figure of `case` × `sweep`.
fn figure_file(case: &str, sweep: &str) -> String {
    format!("schemes_compared_{case}_{sweep}.png")
}

/// The trade-off figure of each compared case × sweep, written into `out`.
pub fn figures(out: &Path, records: &[RunRecord]) -> Result<Vec<Figure>> {
    let mut figures = Vec::new();
    for (case, sweep) in compared(records) {
        let rows = rows(records, (&case, &sweep));
        let spaces = unique(rows.iter().map(|r| r.space.clone()));
        let methods = unique(rows.iter().map(|r| (r.method.clone(), r.scheme.clone())));
        let panels: Vec<(String, Vec<Series>)> = spaces
            .iter()
            .map(|space| {
                let series = methods
                    .iter()
                    .enumerate()
                    .map(|(i, (method, scheme))| {
                        // The variant's place among the parameter sets of its scheme.
                        let k = methods[..i].iter().filter(|(_, s)| s == scheme).count();
                        let points = rows
                            .iter()
                            .filter(|r| &r.space == space && &r.method == method)
                            .filter_map(Row::tradeoff)
                            .collect();
                        Series::new(
                            method.clone(),
                            points,
                            Style {
                                dash: Dash::None,
                                ..super::style::scheme(scheme, k)
                            },
                        )
                    })
                    .collect();
                (space.clone(), series)
            })
            .collect();
        let file = figure_file(&case, &sweep);
        loglog_panels(
            &out.join(&file),
            (
                "max penetration at the probe",
                "energy drift max |Eₙ − E₀| / E₀",
            ),
            &panels,
        )?;
        figures.push(Figure {
            file,
            case: SECTION.into(),
            alt: format!(
                "{case}, sweep {sweep}: energy drift against max penetration, log-log, one \
                 panel per space, one mark per scheme at the finest level"
            ),
            caption: format!(
                "{case} (sweep `{sweep}`, finest level of each scheme × space): energy drift \
                 `max |Eₙ − E₀| / E₀` against the largest penetration `max(0, −g)` at the \
                 probe, one panel per space, one mark per scheme; the best corner is bottom \
                 left. Values at or below {FLOOR:.0e} (no penetration, energy conserved to \
                 round-off) are drawn at {FLOOR:.0e}; a scheme missing from a panel did not \
                 finish, was refused, or has its mark under another's at the same values \
                 (several at {FLOOR:.0e}): the table *Schemes compared* holds every value."
            ),
        });
    }
    Ok(figures)
}

/// The section: an explanation, then per compared case × sweep its table and figure.
pub fn section(d: &mut Doc, (records, orders): (&[RunRecord], &[Order]), figures: &[Figure]) {
    let pairs = compared(records);
    if pairs.is_empty() {
        return;
    }
    d.heading_id(3, SECTION, "Schemes compared");
    d.para(
        "Which space and time scheme give a stable energy, no penetration and a usable contact \
         stress, at what cost? One row per scheme × space at the finest level that finished: \
         the energy drift `max |Eₙ − E₀| / E₀` over the run; `E(T)/E₀ − 1`, the energy kept \
         at the end, after the last impact (negative: dissipated); the largest penetration \
         `max(0, −g)` at the probe; the total variation of σₙ over the run relative to the \
         exact one (1: as smooth as the exact stress; without an exact stress, relative to one \
         clean pulse `2 max|σₙ|`); the observed orders of u, σₙ and the energy error over the \
         levels (marks as in the matrices below); the wall time per step and per dof·step \
         (machine-dependent: timings.csv); the levels that did not finish.",
    );
    for (case, sweep) in &pairs {
        d.para(format!("**{case}**, sweep `{sweep}`."));
        table(d, records, orders, (case, sweep));
        if let Some(f) = figures.iter().find(|f| f.file == figure_file(case, sweep)) {
            d.figure(f.clone());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_three_significant_digits_and_unknowns_are_empty() {
        assert_eq!(sci(1.23456e-7), "1.23e-7");
        assert_eq!(sci(f64::NAN), "");
        assert_eq!(sci(f64::INFINITY), "");
    }
}
