//! The report's "Friction" section (issue 25 §3): per case with Coulomb friction, a table of every
//! space × scheme of its friction sweeps against the rigid-body slide ([`crate::exact::slide`]):
//! the centre of mass's velocity error, its stopping time and distance, the energy balance
//! `E + W_f = E(0)` and the least friction work of a step, and the cost per step against the same
//! run without friction (a sweep with `friction = 0`); the conclusions computed from it; and the
//! centre of mass's velocity against time beside `v₀ − μ g t`.

use super::doc::{Block, Cell, Doc, Figure, Rich, Tone};
use super::style;
use crate::cases::CaseFile;
use crate::error::Result;
use crate::exact::slide::Slide;
use crate::output::plot::{time_panels, Series};
use crate::study::jobs::{RunRecord, Status};
use crate::study::metrics::STOPPED;
use crate::study::run::{run, Summary};
use crate::util::{group_by, unique};
use rayon::prelude::*;
use std::path::Path;

/// `f` over `items` in parallel (the studies' runs): the first error, else the values `f`
/// gives (None: a run without the quantities, left out).
pub(super) fn par_runs<T: Sync, U: Send>(
    items: &[T],
    f: impl Fn(&T) -> Result<Option<U>> + Sync + Send,
) -> Result<Vec<U>> {
    Ok(items
        .par_iter()
        .map(f)
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .flatten()
        .collect())
}

/// The section's anchor and the `case` of its figures.
pub const SECTION: &str = "friction";

/// A step whose friction work falls by more than this (the solvers' tolerance) gives energy
/// back.
const DISSIPATION_TOL: f64 = 1e-12;

/// The rigid slide of each case kind that has one (`(kind, slide)`, from its case file).
pub type Slides = [(String, Slide)];

/// A run with friction (its friction metrics are set).
fn with_friction(r: &RunRecord) -> bool {
    r.summary.metrics.friction_balance.is_some()
}

/// The case × sweep pairs with friction: a sweep with a run that has friction metrics, with
/// every run of it (those refused included), at the coarsest level.
fn friction_sweeps(records: &[RunRecord]) -> Vec<(String, String)> {
    unique(
        records
            .iter()
            .filter(|r| with_friction(r))
            .map(|r| (r.summary.case.clone(), r.sweep.clone())),
    )
}

/// The same run without friction: same case, space, scheme and parameters, level 0, in a sweep
/// without friction, finished.
fn frictionless<'a>(records: &'a [RunRecord], s: &Summary) -> Option<&'a RunRecord> {
    records.iter().find(|r| {
        let t = &r.summary;
        r.status == Status::Ok
            && r.level == 0
            && !with_friction(r)
            && (&t.case, &t.space, &t.scheme, &t.parameters)
                == (&s.case, &s.space, &s.scheme, &s.parameters)
    })
}

/// `x` to three digits, empty when unknown.
fn sci(x: Option<f64>) -> Cell {
    x.filter(|x| x.is_finite())
        .map_or_else(Cell::default, |x| format!("{x:.2e}").into())
}

/// The deceleration of a run in units of μ g, `t*/t̂`.
fn deceleration(s: &Summary, slide: Option<&Slide>) -> Option<f64> {
    Some(slide?.stopping_time() / s.metrics.stop_time?)
}

/// Wall time per step, ms.
fn ms_per_step(s: &Summary) -> f64 {
    1e3 * s.wall_time / s.steps as f64
}

/// The runs of one friction sweep at the coarsest level, in record order.
fn runs<'a>(records: &'a [RunRecord], (case, sweep): (&str, &str)) -> Vec<&'a RunRecord> {
    records
        .iter()
        .filter(|r| r.summary.case == case && r.sweep == sweep && r.level == 0)
        .collect()
}

fn table(d: &mut Doc, records: &[RunRecord], runs: &[&RunRecord], slide: Option<&Slide>) {
    let (t_star, d_star) = slide.map_or((String::new(), String::new()), |s| {
        (
            format!(" (t* = {})", s.stopping_time()),
            format!(" (v₀²/2μg = {})", s.stopping_distance()),
        )
    });
    let header = [
        "space".to_string(),
        "scheme".into(),
        "max |v − (v₀ − μgt)⁺|".into(),
        format!("stop t̂{t_star}"),
        "deceleration / μg".into(),
        format!("distance{d_star}"),
        "max |E + W_f − E₀| / E₀".into(),
        "min ΔW_f".into(),
        "contact iterations / step (μ = 0)".into(),
        "ms / step (μ = 0)".into(),
        "status".into(),
    ]
    .map(|h| Rich::default().text(h))
    .to_vec();
    let body = runs
        .iter()
        .map(|r| {
            let s = &r.summary;
            let m = &s.metrics;
            let ok = r.status == Status::Ok;
            let base = frictionless(records, s).map(|b| &b.summary);
            let pair = |f: fn(&Summary) -> f64| -> Cell {
                match (ok, base) {
                    (true, Some(b)) => format!("{:.3} ({:.3})", f(s), f(b)).into(),
                    (true, None) => format!("{:.3}", f(s)).into(),
                    _ => Cell::default(),
                }
            };
            let status = if ok {
                Cell::plain("ok")
            } else {
                Cell {
                    lines: vec![(
                        Rich::default().text(r.status.as_str()),
                        if r.status == Status::Unsupported {
                            Tone::Missing
                        } else {
                            Tone::Bad
                        },
                    )],
                    tone: Tone::Plain,
                }
            };
            vec![
                s.space.clone().into(),
                s.method().into(),
                sci(m.slide_velocity_err),
                m.stop_time.map_or_else(
                    || {
                        if ok {
                            format!("> T (v > v₀/{})", 1.0 / STOPPED).into()
                        } else {
                            Cell::default()
                        }
                    },
                    |t| format!("{t:.2}").into(),
                ),
                deceleration(s, slide).map_or_else(Cell::default, |a| format!("{a:.3}").into()),
                m.stop_distance
                    .map_or_else(Cell::default, |x| format!("{x:.4}").into()),
                sci(m.friction_balance),
                sci(m.friction_work_min_step),
                pair(|s| s.contact_iterations as f64 / s.steps as f64),
                pair(ms_per_step),
                status,
            ]
        })
        .collect();
    d.push(Block::Table(header, body));
}

/// The extreme of `key` over `runs` (by `pick`), with its run's method and space.
fn extreme(
    runs: &[&RunRecord],
    key: fn(&Summary) -> Option<f64>,
    pick: fn(f64, f64) -> bool,
) -> Option<(f64, String)> {
    runs.iter()
        .filter_map(|r| key(&r.summary).map(|x| (x, &r.summary)))
        .reduce(|a, b| if pick(b.0, a.0) { b } else { a })
        .map(|(x, s)| (x, format!("{}, {}", s.method(), s.space)))
}

/// The conclusions of one friction sweep, computed from its runs.
fn conclusions(runs: &[&RunRecord], slide: Option<&Slide>) -> Vec<Rich> {
    let ok: Vec<&RunRecord> = runs
        .iter()
        .copied()
        .filter(|r| r.status == Status::Ok && with_friction(r))
        .collect();
    let mut out = Vec::new();
    let balance = |s: &Summary| s.metrics.friction_balance;
    if let (Some(lo), Some(hi)) = (
        extreme(&ok, balance, |a, b| a < b),
        extreme(&ok, balance, |a, b| a > b),
    ) {
        let exact = if lo.0 == 0.0 { "" } else { "No scheme makes " };
        out.push(Rich::parse(&format!(
            "{exact}`E + W_f = E(0)` exact{}: `max |E + W_f − E(0)| / E(0)` ranges from \
             {:.2e} ({}) to {:.2e} ({}).",
            if lo.0 == 0.0 {
                " in one run at least"
            } else {
                ""
            },
            lo.0,
            lo.1,
            hi.0,
            hi.1
        )));
    }
    let step = |s: &Summary| s.metrics.friction_work_min_step;
    if let Some(least) = extreme(&ok, step, |a, b| a < b) {
        let negative = ok
            .iter()
            .filter(|r| step(&r.summary).is_some_and(|w| w < -DISSIPATION_TOL))
            .count();
        out.push(Rich::parse(&if negative == 0 {
            format!(
                "Friction never gives energy back: `ΔW_f ≥ −{DISSIPATION_TOL:.0e}` at every step \
                 of the {} runs (least {:.2e}, {}).",
                ok.len(),
                least.0,
                least.1
            )
        } else {
            format!(
                "`ΔW_f < −{DISSIPATION_TOL:.0e}` in {negative} of {} runs (least {:.2e}, {}): \
                 friction gives energy back there.",
                ok.len(),
                least.0,
                least.1
            )
        }));
    }
    let mut near_four_thirds = false;
    let per_space: Vec<String> = unique(ok.iter().map(|r| r.summary.space.clone()))
        .into_iter()
        .filter_map(|space| {
            let a: Vec<f64> = ok
                .iter()
                .filter(|r| r.summary.space == space)
                .filter_map(|r| deceleration(&r.summary, slide))
                .collect();
            let lo = a.iter().copied().reduce(f64::min)?;
            let hi = a.iter().copied().reduce(f64::max)?;
            near_four_thirds |= space == "mass_elimination" && (lo - 4.0 / 3.0).abs() < 0.05;
            Some(format!("{space} {lo:.3}–{hi:.3}"))
        })
        .collect();
    if !per_space.is_empty() {
        let why = if near_four_thirds {
            " Mass elimination decelerates at about 4/3 μg: it drops the mass of the contact \
             elements in every component but keeps their weight (one row of elements in four \
             here, `1ᵀM̃1 = ¾ m`)."
        } else {
            ""
        };
        out.push(Rich::parse(&format!(
            "Deceleration `t*/t̂` in units of μg (the rigid block: 1): {}.{why}",
            per_space.join(", ")
        )));
    }
    let sliding: Vec<String> = ok
        .iter()
        .filter(|r| r.summary.metrics.stop_time.is_none())
        .map(|r| format!("{}, {}", r.summary.method(), r.summary.space))
        .collect();
    if !sliding.is_empty() {
        out.push(Rich::parse(&format!(
            "The centre of mass never drops below v₀/{} (vibrating about the stop, or still \
             sliding) in: {}.",
            1.0 / STOPPED,
            sliding.join("; ")
        )));
    }
    out
}

/// The section: per friction sweep of a slide case its table and conclusions, the oblique
/// impact's and the rolling disc's studies ([`super::oblique`], [`super::roll`]), then the
/// figures.
pub fn section(
    d: &mut Doc,
    records: &[RunRecord],
    (slides, studies): (&Slides, &[Block]),
    figures: &[Figure],
) {
    let pairs: Vec<(String, String)> = friction_sweeps(records)
        .into_iter()
        .filter(|p| slides.iter().any(|s| s.0 == p.0))
        .collect();
    if pairs.is_empty() && studies.is_empty() {
        return;
    }
    d.heading_id(2, SECTION, "Friction");
    d.para(
        "Coulomb friction at the rigid plane, against the rigid-body slide: launched at v₀, the \
         centre of mass decelerates at μg and stops at `t* = v₀/(μg)` after `v₀²/(2μg)`. One \
         row per space × scheme (the schemes without friction are refused: `unsupported`): \
         the largest error of the centre of mass's tangential velocity against \
         `max(v₀ − μgt, 0)`; the first time t̂ it drops below v₀/100 and the deceleration \
         `t*/t̂` it implies; the distance it travels over the run; the energy balance with the \
         friction work W_f; the least work a step dissipates (negative: energy given back); \
         contact-solver iterations and wall time per step (machine-dependent: timings.csv), \
         in brackets the same run without friction (μ = 0).",
    );
    for (case, sweep) in &pairs {
        let slide = slides.iter().find(|s| s.0 == *case).map(|s| &s.1);
        let runs = runs(records, (case, sweep));
        d.para(format!("**{case}**, sweep `{sweep}`."));
        table(d, records, &runs, slide);
        d.push(Block::List(conclusions(&runs, slide)));
    }
    for block in studies {
        d.push(block.clone());
    }
    for f in figures.iter().filter(|f| f.case == SECTION) {
        d.figure(f.clone());
    }
}

/// The centre of mass's tangential velocity against time for every space × scheme of the
/// friction sweeps of a slide case (coarsest level; colour by space, dash by scheme), beside
/// the rigid slide; none for a case without one.
pub fn figures(file: &CaseFile, out: &Path, quick: bool) -> Result<Vec<Figure>> {
    let case = file.defaults()?;
    let Some(exact) = case.slide() else {
        return Ok(Vec::new());
    };
    let kind = case.kind();
    let mut figures = Vec::new();
    for sweep in case.sweeps().iter().filter(|s| s.friction != Some(0.0)) {
        let level = sweep.refinements(quick)?[0];
        let combos: Vec<(&String, usize)> = sweep
            .spaces
            .iter()
            .flat_map(|s| (0..sweep.schemes.len()).map(move |k| (s, k)))
            .collect();
        let curves: Vec<(String, Series)> = combos
            .par_iter()
            .filter_map(|&(space, k)| {
                let c = file
                    .build(&sweep.overrides(space, &sweep.schemes[k], level))
                    .ok()?;
                let r = run(c.as_ref()).ok()?;
                let points: Vec<(f64, f64)> = r
                    .rows
                    .iter()
                    .filter_map(|x| x.friction.map(|f| (x.t, f.0)))
                    .collect();
                // Styled by scheme: the panels (one per space) share the first one's legend.
                let scheme = &sweep.schemes[k].scheme;
                let variant = sweep.schemes[..k]
                    .iter()
                    .filter(|c| &c.scheme == scheme)
                    .count();
                let style = style::scheme(scheme, variant);
                (!points.is_empty()).then(|| {
                    (
                        space.clone(),
                        Series::new(r.summary.method(), points, style),
                    )
                })
            })
            .collect();
        let Some(first) = curves.first() else {
            continue;
        };
        let rigid: Vec<(f64, f64)> = first
            .1
            .points
            .iter()
            .map(|p| (p.0, exact.velocity(p.0)))
            .collect();
        let panels: Vec<(String, Vec<Series>)> = group_by(curves, |c| c.0.clone())
            .into_iter()
            .map(|(space, curves)| {
                let mut series: Vec<Series> = curves.into_iter().map(|c| c.1).collect();
                series.push(Series::reference("rigid slide (v₀ − μgt)⁺", rigid.clone()));
                (format!("{kind}: {space}"), series)
            })
            .collect();
        let name = format!("friction_{kind}_{}_com_velocity.png", sweep.name);
        let setting = level
            .elements
            .map_or(String::new(), |e| format!("{e} elements, "));
        time_panels(&out.join(&name), "centre of mass velocity v_t", &panels)?;
        figures.push(Figure {
            file: name,
            case: SECTION.into(),
            alt: format!(
                "{} line plots side by side, one per space of {kind}'s sweep {}, of the centre \
                 of mass's tangential velocity against time t, one curve per scheme and the \
                 rigid slide.",
                panels.len(),
                sweep.name
            ),
            caption: format!(
                "{kind} (sweep `{}`, {setting}dt = {}): the centre of mass's velocity along the \
                 plane against time, one panel per space, one colour and mark per scheme as in \
                 every figure (the refused schemes have no curve); the rigid slide `max(v₀ − μgt, 0)` dashed (μ = {}, \
                 t* = {}).",
                sweep.name,
                level.dt,
                exact.mu,
                exact.stopping_time()
            ),
        });
    }
    Ok(figures)
}
