//! The report's "Two bodies" section (issue 24 §3): the invariants of every two-body run (the
//! cases with a `momentum` column: `two_bars`, `two_bars_unequal`, `two_discs`,
//! `two_spheres`), one row per case × space × scheme, and links to the figures of those cases
//! (the two-bar convergence plots, the pairs' force against Hertz and the finite-body laws),
//! which their own sections show.

use super::doc::{Block, Cell, Doc, Figure, Rich};
use crate::study::jobs::{RunRecord, Status};
use crate::study::run::method_label;
use crate::util::group_by;

/// Appends the section when some run has a momentum (nothing otherwise).
pub fn section(d: &mut Doc, records: &[RunRecord], figures: &[Figure]) {
    let runs: Vec<&RunRecord> = records
        .iter()
        .filter(|r| r.status == Status::Ok && r.summary.metrics.momentum_drift.is_some())
        .collect();
    if runs.is_empty() {
        return;
    }
    let cases: Vec<String> = crate::util::unique(runs.iter().map(|r| r.summary.case.clone()));
    d.heading(2, "Two bodies");
    d.para(
        "Free bodies meeting head-on, node-to-segment contact rows of the slave's Γ_{C} \
         vertices on the master's faces. Without external force the total momentum \
         P = (M̃1_{d})ᵀV along the line of impact is an invariant of every space × scheme (the \
         contact forces of a row are equal and opposite): its largest change over a run \
         (`momentum_drift`) measures the solves' round-off. The energy drift is the one to read \
         first, as in [Findings](#findings); the penetration is the probe's. One row per case × \
         space × scheme: the largest momentum drift over the levels that finished, the energy \
         drift and penetration of the finest.",
    );
    let figures: Vec<Rich> = figures
        .iter()
        .filter(|f| cases.contains(&f.case))
        .map(|f| Rich::parse(&format!("[{}]({}): {}", f.file, f.file, f.caption)))
        .collect();
    if !figures.is_empty() {
        d.para("Figures (in the sections of their cases):");
        d.push(Block::List(figures));
    }
    let rows = group_by(runs, |r| {
        let s = &r.summary;
        (
            s.case.clone(),
            s.space.clone(),
            s.scheme.clone(),
            s.parameters.clone(),
        )
    })
    .into_iter()
    .map(|((case, space, scheme, parameters), rs)| {
        let momentum = rs
            .iter()
            .filter_map(|r| r.summary.metrics.momentum_drift)
            .fold(0.0, f64::max);
        let finest = rs
            .iter()
            .min_by(|a, b| a.summary.h.total_cmp(&b.summary.h))
            .map(|r| &r.summary);
        let (drift, penetration) = finest.map_or((String::new(), String::new()), |s| {
            (
                s.metrics.drift().to_string(),
                format!("{:.2e}", s.metrics.max_penetration),
            )
        });
        vec![
            Cell::from(case.as_str()),
            space.as_str().into(),
            Rich::default()
                .text(method_label(&scheme, &parameters))
                .into(),
            rs.len().to_string().into(),
            format!("{momentum:.2e}").into(),
            drift.into(),
            penetration.into(),
        ]
    })
    .collect();
    let header = [
        "case",
        "space",
        "scheme",
        "levels",
        "max |P − P₀|",
        "energy drift (finest)",
        "penetration (finest)",
    ];
    d.push(Block::Table(header.map(Rich::from).to_vec(), rows));
}
