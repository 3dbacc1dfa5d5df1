//! `dyncontact report`: runs every `[[sweep]]` of the case files (the [`crate::harness`]) and
//! writes, into one directory:
//! - `summary.csv` (one row per run, deterministic), `timings.csv` (wall times), `orders.csv`;
//! - convergence PNGs per case × sweep × quantity (one series per space for the sweep's first
//!   scheme, one series per scheme for the reference space), each with a slope triangle;
//! - energy and contact stress against time for every case;
//! - `index.md` and `index.html` listing every figure and table with one sentence each.
//!
//! `dyncontact merge` rebuilds the same files (without the time histories, which need the time
//! series) from record files written by `dyncontact sweep --shard i/n`.

use crate::cases;
use crate::cases::sweep::HistorySpec;
use crate::error::{Error, Result};
use crate::harness::{self, group_by, unique, RunRecord, Status};
use crate::orders::{self, reference_slope, Order};
use crate::output::plot::{loglog_plot, time_panels, time_plot, LogLog, Series, PALETTE};
use crate::output::records::{write_records, write_timings};
use crate::run::{run, Row, RunResult, Summary};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// A figure of the report: file name (in the output directory) and what it shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// File name.
    pub file: String,
    /// One sentence on what it shows.
    pub caption: String,
}

/// Report settings.
#[derive(Debug, Clone, Copy, Default)]
pub struct Options {
    /// Only the first `quick_levels` levels of every sweep.
    pub quick: bool,
    /// Progress bar on the terminal.
    pub progress: bool,
}

/// Case files with `[[sweep]]` tables in `dir`, sorted by name.
pub fn case_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let mut out = Vec::new();
    for f in files {
        if !cases::load(&f, &cases::Overrides::default())?
            .sweeps()
            .is_empty()
        {
            out.push(f);
        }
    }
    Ok(out)
}

/// Runs every sweep of the case files in `cases_dir` and writes the report into `out`.
pub fn report(cases_dir: &Path, out: &Path, opts: Options) -> Result<Vec<RunRecord>> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let files = case_files(cases_dir)?;
    let mut jobs = Vec::new();
    for f in &files {
        jobs.extend(harness::jobs(f, opts.quick)?);
    }
    let mut records = harness::run_jobs(&jobs, opts.progress);
    harness::reference_errors(&mut records);
    let mut figures = Vec::new();
    for f in &files {
        figures.extend(time_histories(f, out, opts.quick)?);
    }
    write(out, &records, figures, opts.quick)?;
    Ok(records)
}

/// Joins record files (from `sweep --shard`) into a report in `out` (no time histories).
pub fn merge(files: &[PathBuf], out: &Path) -> Result<Vec<RunRecord>> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let mut records = Vec::new();
    for f in files {
        records.extend(crate::output::records::read_records(f)?);
    }
    write(out, &records, Vec::new(), false)?;
    Ok(records)
}

fn write(out: &Path, records: &[RunRecord], mut figures: Vec<Figure>, quick: bool) -> Result<()> {
    write_records(&out.join("summary.csv"), records, false)?;
    write_timings(&out.join("timings.csv"), records)?;
    let orders = orders::orders(records);
    orders::write_orders(&out.join("orders.csv"), &orders)?;
    figures.splice(0..0, convergence_figures(out, records)?);
    crate::output::index::write_index(out, records, &orders, &figures, quick)
}

/// Plotted error quantities and their axis labels.
const PLOTTED: [(&str, &str); 4] = [
    ("err_u_linf_l2", "max_t ||u_h - u||_L2"),
    ("err_energy", "max_t |E_h - E| / E"),
    (
        "err_sigma_l2",
        "||sigma_h - sigma||_L2(0,T) at the contact point",
    ),
    ("impact_time_err", "first impact time error"),
];

/// The space whose schemes are compared: mass redistribution when swept, else the first space.
fn reference_space(spaces: &[String]) -> &str {
    spaces
        .iter()
        .find(|s| *s == "mass_redistribution")
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
fn convergence_figures(out: &Path, records: &[RunRecord]) -> Result<Vec<Figure>> {
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
            let get = orders::QUANTITIES
                .iter()
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
/// per space, one curve per dt: the seed paper's figures side by side), or by default the first
/// sweep at its third level (first with `quick`) with every space for the first scheme, or every
/// scheme when the sweep has one space. Failed runs are left out and named in the caption.
fn time_histories(path: &Path, out: &Path, quick: bool) -> Result<Vec<Figure>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let case = cases::parse(&text, path, &cases::Overrides::default())?;
    let kind = case.kind();
    if !case.histories().is_empty() {
        let mut figures = Vec::new();
        for h in case.histories() {
            figures.extend(history_panels(&text, path, out, kind, h)?);
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
            (
                label,
                cases::parse(&text, path, &o).and_then(|c| run(c.as_ref())),
            )
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

/// One `[[history]]`: a panel per space, a curve per time step, for energy and contact stress.
fn history_panels(
    text: &str,
    path: &Path,
    out: &Path,
    kind: &str,
    h: &HistorySpec,
) -> Result<Vec<Figure>> {
    let combos: Vec<(&String, f64)> = h
        .spaces
        .iter()
        .flat_map(|s| h.dts.iter().map(move |&dt| (s, dt)))
        .collect();
    let curves: Vec<(String, Curve)> = combos
        .par_iter()
        .map(|&(space, dt)| {
            let r = cases::parse(text, path, &h.overrides(space, dt)).and_then(|c| run(c.as_ref()));
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
                h.dts
                    .iter()
                    .map(|d| d.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
    }
    Ok(figures)
}

/// Orders of one case × sweep as a table: rows space × scheme, columns the fitted quantities.
pub fn order_table(orders: &[Order], case: &str, sweep: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let rows_of: Vec<&Order> = orders
        .iter()
        .filter(|o| o.case == case && o.sweep == sweep)
        .collect();
    let quantities = unique(rows_of.iter().map(|o| o.quantity));
    let keys = unique(
        rows_of
            .iter()
            .map(|o| (o.space.clone(), o.scheme.clone(), o.parameters.clone())),
    );
    let mut header = vec!["space".to_string(), "scheme".to_string()];
    header.extend(quantities.iter().map(|q| q.to_string()));
    let rows = keys
        .iter()
        .map(|(space, scheme, params)| {
            let mut row = vec![
                space.clone(),
                if params.is_empty() {
                    scheme.clone()
                } else {
                    format!("{scheme} ({params})")
                },
            ];
            row.extend(quantities.iter().map(|q| {
                rows_of
                    .iter()
                    .find(|o| {
                        o.space == *space
                            && o.scheme == *scheme
                            && o.parameters == *params
                            && o.quantity == *q
                    })
                    .and_then(|o| o.fit)
                    .map_or("–".to_string(), |f| format!("{:.2}", f.0))
            }));
            row
        })
        .collect();
    (header, rows)
}
