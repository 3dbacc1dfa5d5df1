//! The report's figures: convergence plots per case × sweep × quantity, and energy and contact
//! stress against time per case file.

use super::doc::Figure;
use super::quantity::{named, Named};
use super::style;
use crate::cases::sweep::HistorySpec;
use crate::cases::{Case, CaseFile};
use crate::error::Result;
use crate::output::plot::{loglog_plot, time_panels, time_plot, LogLog, Series, Style};
use crate::study::jobs::blowup;
use crate::study::jobs::{RunRecord, Status};
use crate::study::orders::{self, reference_slope, Order};
use crate::study::run::{method_label, run, RunResult, Summary};
use crate::study::trajectory::Row;
use crate::util::{group_by, unique};
use rayon::prelude::*;
use std::path::Path;

/// The quantities drawn against h (or dt): displacement, energy, contact stress, first impact
/// time and the errors against Hertz.
const PLOTTED: [&str; 8] = [
    "err_u_linf_l2",
    "err_energy",
    "err_sigma_l2",
    "impact_time_err",
    "err_contact_duration",
    "err_peak_force",
    "err_contact_radius",
    "err_peak_pressure",
];

/// The space whose schemes are compared: mass redistribution when swept, else the first space.
fn reference_space(spaces: &[String]) -> &str {
    spaces
        .iter()
        .find(|s| *s == crate::space::REFERENCE)
        .unwrap_or(&spaces[0])
}

/// What the curves of a figure of one space differ by: the scheme, or (one scheme) its
/// contact formulation or parameters.
fn variants_are(summaries: &[&Summary]) -> &'static str {
    let schemes = unique(summaries.iter().map(|s| s.scheme.as_str()));
    let contact = |s: &Summary| {
        s.parameters
            .split(';')
            .filter(|p| p.starts_with("contact=") || p.starts_with("nitsche_"))
            .collect::<Vec<_>>()
            .join(";")
    };
    if schemes.len() > 1 {
        "scheme"
    } else if unique(summaries.iter().map(|s| contact(s))).len() > 1 {
        "contact formulation"
    } else {
        "parameter set"
    }
}

/// The contact formulation of a run (the `contact=` of its parameters; `nodal` by default).
fn contact_of(s: &Summary) -> &str {
    s.parameters
        .split(';')
        .find_map(|p| p.strip_prefix("contact="))
        .unwrap_or(crate::contact::DEFAULT_FORMULATION)
}

/// Each method of `summaries` (in order) with its style: by scheme, or by contact formulation
/// when that is what differs (`what`, from [`variants_are`]); the k-th parameter set of one
/// scheme or formulation gets its k-th variant.
fn method_styles(summaries: &[&Summary], what: &str) -> Vec<(String, Style)> {
    let methods = unique(
        summaries
            .iter()
            .map(|s| (s.method(), s.scheme.clone(), contact_of(s).to_string())),
    );
    methods
        .iter()
        .enumerate()
        .map(|(k, (m, scheme, contact))| {
            let style = if what == "contact formulation" {
                let variant = methods[..k].iter().filter(|x| x.2 == *contact).count();
                style::formulation(contact, variant)
            } else {
                let variant = methods[..k].iter().filter(|x| x.1 == *scheme).count();
                style::scheme(scheme, variant)
            };
            (m.clone(), style)
        })
        .collect()
}

/// The largest relative difference between the curves at their common abscissae, when every
/// curve has the abscissae of the first (None otherwise).
fn spread(series: &[Series]) -> Option<f64> {
    let first = series.first()?;
    let mut worst = 0.0f64;
    for s in &series[1..] {
        if s.points.len() != first.points.len() {
            return None;
        }
        for (a, b) in first.points.iter().zip(&s.points) {
            if a.0 != b.0 {
                return None;
            }
            worst = worst.max((a.1 - b.1).abs() / a.1.abs().max(b.1.abs()));
        }
    }
    Some(worst)
}

/// Convergence plots of every case × sweep: one figure per quantity with every space (the
/// sweep's first scheme), one with every scheme (the reference space); captions say what the
/// errors are measured against (from `orders`).
pub fn convergence_figures(
    out: &Path,
    records: &[RunRecord],
    orders: &[Order],
) -> Result<Vec<Figure>> {
    let mut figures = Vec::new();
    let groups = group_by(records, |r| (r.summary.case.clone(), r.sweep.clone()));
    for ((case, sweep), rs) in groups {
        let spaces = unique(rs.iter().map(|r| r.summary.space.clone()));
        let methods = unique(rs.iter().map(|r| r.summary.method()));
        let x_label = if rs[0].summary.h.is_finite() {
            "h"
        } else {
            "dt"
        };
        let reference = reference_space(&spaces).to_string();
        for quantity in PLOTTED {
            // The bar's first impact is a wave arrival, not a convergence measure.
            if quantity == "impact_time_err" && x_label == "h" {
                continue;
            }
            let Some(name) = named(quantity) else {
                continue;
            };
            let get = orders::quantities()
                .find(|q| q.0 == quantity)
                .map(|q| q.1)
                .expect("plotted quantities are fitted quantities");
            let against = orders
                .iter()
                .find(|o| o.case == case && o.sweep == sweep && o.quantity == quantity)
                .map_or_else(String::new, |o| o.reference.clone());
            let series_of = |keep: &dyn Fn(&Summary) -> bool, label: String, style: Style| {
                // A level that diverged is drawn at +∞: marked at the top edge.
                let pts: Vec<(f64, f64)> = rs
                    .iter()
                    .filter(|r| keep(&r.summary))
                    .filter_map(|r| {
                        let s = &r.summary;
                        let x = if s.h.is_finite() { s.h } else { s.dt };
                        match r.status {
                            Status::Ok => get(&s.metrics)
                                .filter(|e| *e > 0.0 && e.is_finite())
                                .map(|e| (x, e)),
                            Status::Diverged => Some((x, f64::INFINITY)),
                            _ => None,
                        }
                    })
                    .collect();
                let finite = pts.iter().filter(|p| p.1.is_finite()).count();
                (finite >= 2).then(|| Series::new(label, pts, style))
            };
            let plot = ConvergencePlot {
                out,
                case: &case,
                sweep: &sweep,
                x_label,
                name,
                against: &against,
            };
            if spaces.len() > 1 {
                let first = methods[0].clone();
                let series: Vec<Series> = spaces
                    .iter()
                    .filter_map(|sp| {
                        let keep = |s: &Summary| s.space == *sp && s.method() == first;
                        series_of(&keep, sp.clone(), style::space(sp))
                    })
                    .collect();
                figures.extend(plot.draw(
                    "spaces",
                    "space",
                    &format!("all with {first}"),
                    series,
                )?);
            }
            if methods.len() > 1 {
                let of_reference: Vec<&Summary> = rs
                    .iter()
                    .map(|r| &r.summary)
                    .filter(|s| s.space == reference)
                    .collect();
                let what = variants_are(&of_reference);
                let series: Vec<Series> = method_styles(&of_reference, what)
                    .into_iter()
                    .filter_map(|(m, style)| {
                        let keep = |s: &Summary| s.space == reference && s.method() == m;
                        series_of(&keep, m.clone(), style)
                    })
                    .collect();
                figures.extend(plot.draw(
                    "schemes",
                    what,
                    &format!("all with {reference}"),
                    series,
                )?);
            }
        }
    }
    Ok(figures)
}

/// One convergence figure's setting.
struct ConvergencePlot<'a> {
    out: &'a Path,
    case: &'a str,
    sweep: &'a str,
    x_label: &'a str,
    name: Named,
    /// What the errors are measured against (`orders.csv`'s `reference`).
    against: &'a str,
}

impl ConvergencePlot<'_> {
    /// Draws `series` (one per `per`: space, scheme, …) as `<case>_<sweep>_<quantity>_<suffix>`;
    /// nothing when there are none.
    fn draw(
        &self,
        suffix: &str,
        per: &str,
        common: &str,
        series: Vec<Series>,
    ) -> Result<Option<Figure>> {
        if series.is_empty() {
            return Ok(None);
        }
        let (case, sweep, x, n) = (self.case, self.sweep, self.x_label, self.name);
        let file = format!("{case}_{sweep}_{}_{suffix}.png", n.key);
        let slope = reference_slope(n.key);
        let title = format!("{case}: {} against {x}, {common}", n.symbol);
        loglog_plot(
            &self.out.join(&file),
            LogLog {
                title: &title,
                x_label: if x == "h" {
                    "mesh size h"
                } else {
                    "time step dt"
                },
                y_label: n.axis,
                slope,
            },
            &series,
        )?;
        let labels: Vec<&str> = series.iter().map(|s| s.label.as_str()).collect();
        let coincide = match spread(&series) {
            Some(d) if series.len() > 1 && d < 1e-3 => format!(
                " The {} curves coincide to the eye (largest relative difference {d:.1e}): the \
                 {per} does not change this error here.",
                series.len()
            ),
            _ => String::new(),
        };
        let against = if self.against.is_empty() {
            String::new()
        } else {
            format!(", errors against {}", self.against)
        };
        Ok(Some(Figure {
            file,
            case: case.to_string(),
            alt: format!(
                "Log-log plot of {} against {x}, one curve with markers per {per} ({}), and a \
                 dashed slope-{slope} triangle.",
                n.axis,
                labels.join(", ")
            ),
            caption: format!(
                "{case}, sweep `{sweep}`: {} (`{}`{against}) against {x}, one curve per {per}, \
                 {common}; a level is drawn when its run finished with a positive error, one \
                 that diverged is marked ▲ at the top edge. The triangle has slope \
                 {slope}.{coincide}",
                n.axis, n.key
            ),
        }))
    }
}

/// Energy and contact stress against time for a case file without Hertz reference: its
/// `[[history]]` tables (one panel per space, one curve per dt, the first only with `quick`:
/// the seed paper's figures side by side), or by default the first sweep at its third level
/// (first with `quick`) with every space for the first scheme, or every scheme when the sweep has
/// one space. Failed runs are left out and named in the caption.
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
    let per_space = sweep.spaces.len() > 1;
    let combos: Vec<(String, usize)> = if per_space {
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
            match file.build(&o) {
                Ok(c) => {
                    let label = if per_space {
                        space.clone()
                    } else {
                        c.run().parameters().map_or_else(
                            |_| c.run().scheme.clone(),
                            |p| method_label(&c.run().scheme, &p),
                        )
                    };
                    (label, run(c.as_ref()))
                }
                Err(e) => (sweep.schemes[*k].label(), Err(e)),
            }
        })
        .collect();
    let at = levels[level]
        .elements
        .map_or(String::new(), |n| format!("{n} elements, "));
    let setting = format!("{at}dt = {}", levels[level].dt);
    let (runs, left_out) = split_failed(curves);
    let common = match (per_space, runs.first()) {
        (true, Some((_, r))) => format!(", all with {}", r.summary.method()),
        (false, Some((_, r))) => format!(", all with {}", r.summary.space),
        _ => String::new(),
    };
    let per = if per_space { "space" } else { "scheme" };
    let mut figures = Vec::new();
    for q in VS_TIME {
        let mut series = time_curves(&runs, q.get, |k| {
            let s = &runs[k].1.summary;
            if per_space {
                style::space(&s.space)
            } else {
                let variant = runs[..k]
                    .iter()
                    .filter(|r| r.1.summary.scheme == s.scheme)
                    .count();
                style::scheme(&s.scheme, variant)
            }
        });
        roughest_first(&mut series);
        let exact: Vec<(f64, f64)> = runs.first().map_or_else(Vec::new, |(_, r)| {
            r.rows
                .iter()
                .filter_map(|x| x.exact.map(|e| (x.t, (q.exact)(e))))
                .collect()
        });
        let has_exact = !exact.is_empty();
        if has_exact {
            series.push(Series::reference("exact", exact));
        }
        if series.is_empty() {
            continue;
        }
        let name = format!("{kind}_{}.png", q.file);
        time_plot(
            &out.join(&name),
            &format!("{kind}: {}, {setting}", q.title),
            q.axis,
            &series,
        )?;
        let labels: Vec<&str> = series.iter().map(|s| s.label.as_str()).collect();
        figures.push(Figure {
            file: name,
            case: kind.to_string(),
            alt: format!(
                "Line plot of {} against time t, one curve per {per} ({}).",
                q.axis,
                labels.join(", ")
            ),
            caption: format!(
                "{kind}: {} against time ({setting}), one curve per {per}{common}{}.{left_out}",
                q.what,
                if has_exact {
                    "; the exact solution dashed"
                } else {
                    ""
                }
            ),
        });
    }
    Ok(figures)
}

/// A labelled run (or its failure).
type Curve = (String, Result<RunResult>);

/// A quantity plotted against time.
struct VsTime {
    /// What it is, in captions.
    what: &'static str,
    /// In titles.
    title: &'static str,
    /// y-axis label.
    axis: &'static str,
    /// File suffix.
    file: &'static str,
    /// The computed value of a row.
    get: fn(&Row) -> f64,
    /// The exact value from `(u, σ, E)`.
    exact: fn((f64, f64, f64)) -> f64,
}

/// Quantities plotted against time: the body's energy and the contact stress at the probe.
const VS_TIME: [VsTime; 2] = [
    VsTime {
        what: "the total energy of the body (kinetic + elastic + potential of the loads)",
        title: "total energy",
        axis: "total energy E",
        file: "energy",
        get: |r| r.energy,
        exact: |e| e.2,
    },
    VsTime {
        what: "the contact stress σ_{n} at the contact probe (compression < 0)",
        title: "contact stress at the probe",
        axis: "contact stress σₙ at the probe",
        file: "contact_stress",
        get: |r| r.sigma_contact,
        exact: |e| e.1,
    },
];

/// One curve of `get` against time per labelled run, styled by `style(k)`; a run whose energy
/// moved from E(0) by more than 100 max(|E(0)|, W) ([`blowup`]) is marked diverged (drawn clipped,
/// said in its label).
fn time_curves(
    runs: &[(String, RunResult)],
    get: fn(&Row) -> f64,
    style: impl Fn(usize) -> Style,
) -> Vec<Series> {
    runs.iter()
        .enumerate()
        .map(|(k, (label, r))| {
            let pts = r.rows.iter().map(|x| (x.t, get(x))).collect();
            let mut s = Series::new(label.clone(), pts, style(k));
            if blowup(r).is_some() {
                s.diverged = true;
                s.label.push_str(" (diverged: drawn clipped)");
            }
            s
        })
        .collect()
}

/// Orders the curves by decreasing total variation `Σ |y_{k+1} − y_k|` (a stable sort), so that
/// a smooth curve is drawn over the chattering ones instead of under them (bar1d's mass
/// redistribution stress was hidden under the singular dynamic method's); the legend follows.
fn roughest_first(series: &mut [Series]) {
    let variation =
        |s: &Series| -> f64 { s.points.windows(2).map(|w| (w[1].1 - w[0].1).abs()).sum() };
    series.sort_by(|a, b| variation(b).total_cmp(&variation(a)));
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
    let scheme = panels_runs
        .iter()
        .find_map(|(_, runs)| runs.first())
        .map_or_else(|| h.scheme.label(), |(_, r)| r.summary.method());
    let dts: Vec<String> = dts.iter().map(|d| d.to_string()).collect();
    let mut figures = Vec::new();
    for q in VS_TIME {
        let panels: Vec<(String, Vec<Series>)> = panels_runs
            .iter()
            .filter(|(_, runs)| !runs.is_empty())
            .map(|(space, runs)| {
                let n = runs.len();
                let series = time_curves(runs, q.get, |k| style::sequence(k, n));
                (format!("{kind}: {space}"), series)
            })
            .collect();
        if panels.is_empty() {
            continue;
        }
        let name = format!("{kind}{suffix}_{}.png", q.file);
        time_panels(&out.join(&name), q.axis, &panels)?;
        let spaces: Vec<&str> = panels.iter().map(|p| &p.0[kind.len() + 2..]).collect();
        figures.push(Figure {
            file: name,
            case: kind.to_string(),
            alt: format!(
                "{} line plots side by side, one per space ({}), of {} against time t, one \
                 curve per time step ({}).",
                panels.len(),
                spaces.join(", "),
                q.axis,
                dts.join(", ")
            ),
            caption: format!(
                "{kind}: {} against time, {scheme}, one panel per space ({}), one curve per dt \
                 ({}); the probe is the centre of the contact face.{notes}",
                q.what,
                spaces.join(", "),
                dts.join(", ")
            ),
        });
    }
    if figures.is_empty() {
        // Every run failed: nothing to draw, and a table that vanished without a word.
        return Err(crate::Error::invalid(
            h.field(""),
            h.spaces.join(", "),
            &format!("every run of the table failed:{notes}"),
        )
        .in_case_file(&file.path));
    }
    Ok(figures)
}
