//! The report's figures: convergence plots per case × sweep × quantity, and energy and contact
//! stress against time per case file.

use super::Figure;
use crate::cases::sweep::HistorySpec;
use crate::cases::{Case, CaseFile};
use crate::error::{Error, Result};
use crate::output::plot::{loglog_plot, time_panels, time_plot, LogLog, Series, PALETTE};
use crate::study::jobs::{RunRecord, Status};
use crate::study::orders::{self, reference_slope};
use crate::study::run::{run, RunResult, Summary};
use crate::study::trajectory::Row;
use crate::util::{group_by, unique};
use rayon::prelude::*;
use std::path::Path;

/// Plotted error quantities and their axis labels.
const PLOTTED: [(&str, &str); 8] = [
    ("err_u_linf_l2", "max_t ||u_h - u||_L2"),
    ("err_energy", "max_t |E_h - E| / E"),
    (
        "err_sigma_l2",
        "||sigma_h - sigma||_L2(0,T) at the contact point",
    ),
    ("impact_time_err", "first impact time error"),
    ("err_contact_duration", "|t_c - Hertz| / Hertz"),
    ("err_peak_force", "|F_max - Hertz| / Hertz"),
    (
        "err_contact_radius",
        "|a - Hertz(F)| / Hertz(F) at peak force",
    ),
    (
        "err_peak_pressure",
        "|p0 - Hertz(F)| / Hertz(F) at peak force",
    ),
];

/// The space whose schemes are compared: mass redistribution when swept, else the first space.
fn reference_space(spaces: &[String]) -> &str {
    spaces
        .iter()
        .find(|s| *s == crate::space::REFERENCE)
        .unwrap_or(&spaces[0])
}

fn scheme_label(s: &Summary) -> String {
    if s.parameters.is_empty() {
        s.scheme.clone()
    } else {
        format!("{} ({})", s.scheme, s.parameters.replace(';', ", "))
    }
}

/// Convergence plots of every case × sweep.
pub fn convergence_figures(out: &Path, records: &[RunRecord]) -> Result<Vec<Figure>> {
    let mut figures = Vec::new();
    let groups = group_by(records, |r| (r.summary.case.clone(), r.sweep.clone()));
    for ((case, sweep), rs) in groups {
        let spaces = unique(rs.iter().map(|r| r.summary.space.clone()));
        let schemes = unique(rs.iter().map(|r| scheme_label(&r.summary)));
        let x_label = if rs[0].summary.h.is_finite() {
            "h"
        } else {
            "dt"
        };
        let reference = reference_space(&spaces).to_string();
        for (quantity, y_label) in PLOTTED {
            // The bar's first impact is a wave arrival, not a convergence measure.
            if quantity == "impact_time_err" && x_label == "h" {
                continue;
            }
            let get = orders::quantities()
                .find(|q| q.0 == quantity)
                .map(|q| q.1)
                .expect("plotted quantities are fitted quantities");
            let series_of = |keep: &dyn Fn(&Summary) -> bool, label: String, k: usize| {
                let pts: Vec<(f64, f64)> = rs
                    .iter()
                    .filter(|r| r.status == Status::Ok && keep(&r.summary))
                    .filter_map(|r| {
                        let s = &r.summary;
                        let x = if s.h.is_finite() { s.h } else { s.dt };
                        get(&s.metrics)
                            .filter(|e| *e > 0.0 && e.is_finite())
                            .map(|e| (x, e))
                    })
                    .collect();
                (pts.len() >= 2).then(|| Series::solid(label, pts, PALETTE[k % PALETTE.len()]))
            };
            let mut plot = |name: String, title: String, series: Vec<Series>, caption: String| {
                if series.is_empty() {
                    return Ok(());
                }
                let axes = LogLog {
                    title: &title,
                    x_label,
                    y_label,
                    slope: reference_slope(quantity),
                };
                loglog_plot(&out.join(&name), axes, &series)?;
                figures.push(Figure {
                    file: name,
                    caption,
                });
                Ok::<(), Error>(())
            };
            if spaces.len() > 1 {
                let first = schemes[0].clone();
                let series = spaces
                    .iter()
                    .enumerate()
                    .filter_map(|(k, sp)| {
                        series_of(
                            &|s| s.space == *sp && scheme_label(s) == first,
                            sp.clone(),
                            k,
                        )
                    })
                    .collect();
                plot(
                    format!("{case}_{sweep}_{quantity}_spaces.png"),
                    format!("{case}: {quantity} vs {x_label}, {first}"),
                    series,
                    format!("{case}: {y_label} against {x_label} for every space with {first}."),
                )?;
            }
            if schemes.len() > 1 {
                let series = schemes
                    .iter()
                    .enumerate()
                    .filter_map(|(k, sc)| {
                        series_of(
                            &|s| s.space == reference && scheme_label(s) == *sc,
                            sc.clone(),
                            k,
                        )
                    })
                    .collect();
                plot(
                    format!("{case}_{sweep}_{quantity}_schemes.png"),
                    format!("{case}: {quantity} vs {x_label}, {reference}"),
                    series,
                    format!(
                        "{case}: {y_label} against {x_label} for every scheme with {reference}."
                    ),
                )?;
            }
        }
    }
    Ok(figures)
}

/// Energy and contact stress against time for a case file: its `[[history]]` tables (one panel
/// per space, one curve per dt, the first only with `quick`: the seed paper's figures side by
/// side), or by default the first sweep at its third level (first with `quick`) with every space
/// for the first scheme, or every scheme when the sweep has one space. Failed runs are left out and named in the caption.
/// (Curved-body impacts get their own figures, [`super::impact`].)
pub fn time_histories(
    file: &CaseFile,
    case: &dyn Case,
    out: &Path,
    quick: bool,
) -> Result<Vec<Figure>> {
    let kind = case.kind();
    if !case.histories().is_empty() {
        let mut figures = Vec::new();
        for h in case.histories() {
            figures.extend(history_panels(file, out, kind, h, quick)?);
        }
        return Ok(figures);
    }
    let sweep = &case.sweeps()[0];
    let levels = sweep.refinements(quick)?;
    let level = if quick { 0 } else { 2.min(levels.len() - 1) };
    let combos: Vec<(String, usize)> = if sweep.spaces.len() > 1 {
        sweep.spaces.iter().map(|s| (s.clone(), 0)).collect()
    } else {
        (0..sweep.schemes.len())
            .map(|k| (sweep.spaces[0].clone(), k))
            .collect()
    };
    let curves: Vec<Curve> = combos
        .par_iter()
        .map(|(space, k)| {
            let o = sweep.overrides(space, &sweep.schemes[*k], levels[level]);
            let label = if sweep.spaces.len() > 1 {
                space.clone()
            } else {
                sweep.schemes[*k].label()
            };
            (label, file.build(&o).and_then(|c| run(c.as_ref())))
        })
        .collect();
    let at = levels[level]
        .elements
        .map_or(String::new(), |n| format!("{n} elements, "));
    let setting = format!("{at}dt = {}", levels[level].dt);
    let (runs, left_out) = split_failed(curves);
    let mut figures = Vec::new();
    for (what, file, get) in QUANTITIES_VS_TIME {
        let mut series = solid_curves(&runs, get.0);
        if let Some((_, r)) = runs.first() {
            let pts: Vec<(f64, f64)> = r
                .rows
                .iter()
                .filter_map(|x| x.exact.map(|e| (x.t, (get.1)(e))))
                .collect();
            if !pts.is_empty() {
                series.push(Series::dashed("exact", pts, plotters::style::BLACK));
            }
        }
        if series.is_empty() {
            continue;
        }
        let name = format!("{kind}_{file}.png");
        time_plot(
            &out.join(&name),
            &format!("{kind}: {what}, {setting}"),
            what,
            &series,
        )?;
        figures.push(Figure {
            file: name,
            caption: format!(
                "{kind}: {what} at the contact point against time ({setting}), exact dashed.{left_out}"
            ),
        });
    }
    Ok(figures)
}

/// A labelled run (or its failure).
type Curve = (String, Result<RunResult>);
/// Accessors of a time-series row and of the exact `(u, σ, E)`.
type RowAccess = (fn(&Row) -> f64, fn((f64, f64, f64)) -> f64);

/// Quantities plotted against time: description, file suffix, accessors.
const QUANTITIES_VS_TIME: [(&str, &str, RowAccess); 2] = [
    ("total energy", "energy", (|r| r.energy, |e| e.2)),
    (
        "contact stress",
        "contact_stress",
        (|r| r.sigma_contact, |e| e.1),
    ),
];

/// One solid curve of `get` against time per labelled run, in palette order.
fn solid_curves(runs: &[(String, RunResult)], get: fn(&Row) -> f64) -> Vec<Series> {
    runs.iter()
        .enumerate()
        .map(|(k, (label, r))| {
            let pts = r.rows.iter().map(|x| (x.t, get(x))).collect();
            Series::solid(label.clone(), pts, PALETTE[k % PALETTE.len()])
        })
        .collect()
}

/// The successful runs, and a caption sentence naming the failed ones.
fn split_failed(curves: Vec<Curve>) -> (Vec<(String, RunResult)>, String) {
    let mut runs = Vec::new();
    let mut failed = Vec::new();
    for (label, r) in curves {
        match r {
            Ok(r) => runs.push((label, r)),
            Err(e) => failed.push(format!("{label} ({e})")),
        }
    }
    let note = if failed.is_empty() {
        String::new()
    } else {
        format!(" Not shown: {}.", failed.join("; "))
    };
    (runs, note)
}

/// One `[[history]]`: a panel per space, a curve per time step (the first only with `quick`),
/// for energy and contact stress.
fn history_panels(
    file: &CaseFile,
    out: &Path,
    kind: &str,
    h: &HistorySpec,
    quick: bool,
) -> Result<Vec<Figure>> {
    let dts = if quick {
        &h.dts[..h.dts.len().min(1)]
    } else {
        &h.dts[..]
    };
    let combos: Vec<(&String, f64)> = h
        .spaces
        .iter()
        .flat_map(|s| dts.iter().map(move |&dt| (s, dt)))
        .collect();
    let curves: Vec<(String, Curve)> = combos
        .par_iter()
        .map(|&(space, dt)| {
            let r = file
                .build(&h.overrides(space, dt))
                .and_then(|c| run(c.as_ref()));
            (space.clone(), (format!("dt = {dt}"), r))
        })
        .collect();
    let mut notes = String::new();
    let panels_runs: Vec<(String, Vec<(String, RunResult)>)> = group_by(curves, |c| c.0.clone())
        .into_iter()
        .map(|(space, curves)| {
            let (runs, note) = split_failed(curves.into_iter().map(|c| c.1).collect());
            notes.push_str(&note);
            (space, runs)
        })
        .collect();
    let suffix = if h.name.is_empty() {
        String::new()
    } else {
        format!("_{}", h.name)
    };
    let scheme = h.scheme.label();
    let mut figures = Vec::new();
    for (what, file, get) in QUANTITIES_VS_TIME {
        let panels: Vec<(String, Vec<Series>)> = panels_runs
            .iter()
            .filter(|(_, runs)| !runs.is_empty())
            .map(|(space, runs)| (format!("{kind}: {space}"), solid_curves(runs, get.0)))
            .collect();
        if panels.is_empty() {
            continue;
        }
        let name = format!("{kind}{suffix}_{file}.png");
        time_panels(&out.join(&name), what, &panels)?;
        figures.push(Figure {
            file: name,
            caption: format!(
                "{kind}: {what} at the centre of the contact face against time, {scheme}, one \
                 panel per space ({}), one curve per dt ({}).{notes}",
                h.spaces.join(", "),
                dts.iter()
                    .map(|d| d.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
    }
    Ok(figures)
}
