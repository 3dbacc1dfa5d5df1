//! The "Friction" section's disc on the slope (issue 25 §2–3): one run per `[[sweep]]` of a
//! `roll2d` case (its coarsest level, first space × scheme; each sweep its own μ), the centre's
//! velocity and the contact point's slip velocity `v − Rω` against time beside the rigid disc
//! ([`crate::exact::roll`]: `⅔ g sin α` rolling when μ ≥ tan α / 3, `g (sin α − μ cos α)`
//! sliding, the slip growing at `g (sin α − 3μ cos α)`), and a table row per run with the
//! accelerations fitted after the release's bounce.

use super::doc::{Block, Figure, Rich};
use super::friction::{par_runs, SECTION};
use super::style;
use crate::cases::CaseFile;
use crate::error::Result;
use crate::exact::roll::Roll;
use crate::output::plot::{time_plot, Dash, Series, Style};
use crate::study::run::run;
use std::path::Path;

/// The fit leaves out `t < FIT_FROM · T` (the bounce of the release on the plane).
const FIT_FROM: f64 = 0.375;

/// Least-squares slope of `points`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (sxx, sxy) = points
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 * p.0, a.1 + p.0 * p.1));
    (n * sxy - sx * sy) / (n * sxx - sx * sx)
}

/// One run: its rigid disc, the centre's velocity and the slip velocity against time.
struct Curve {
    exact: Roll,
    velocity: Vec<(f64, f64)>,
    slip: Vec<(f64, f64)>,
}

impl Curve {
    /// The fitted (acceleration, slip acceleration, small-displacement disc's acceleration of
    /// radius `radius` on the same samples) over `t ≥ FIT_FROM · T`.
    fn fitted(&self, radius: f64) -> (f64, f64, f64) {
        let from = FIT_FROM * self.velocity.last().map_or(0.0, |p| p.0);
        let late = |c: &[(f64, f64)]| -> Vec<(f64, f64)> {
            c.iter().copied().filter(|p| p.0 >= from).collect()
        };
        let small: Vec<(f64, f64)> = late(&self.velocity)
            .iter()
            .map(|p| (p.0, self.exact.small_displacement(radius, p.0).1))
            .collect();
        (
            slope(&late(&self.velocity)),
            slope(&late(&self.slip)),
            slope(&small),
        )
    }
}

/// The roll study of `file` (none for a case without a rigid disc): figures and table.
pub fn study(file: &CaseFile, out: &Path, quick: bool) -> Result<(Vec<Figure>, Vec<Block>)> {
    let case = file.defaults()?;
    let (Some(roll), Some(radius)) = (case.roll(), case.spin().map(|s| s.radius)) else {
        return Ok((Vec::new(), Vec::new()));
    };
    let runs = case
        .sweeps()
        .iter()
        .map(|sweep| {
            let level = sweep.refinements(quick)?[0];
            let o = sweep.overrides(&sweep.spaces[0], &sweep.schemes[0], level);
            let mu = sweep.friction.unwrap_or(roll.mu);
            Ok((o, Roll { mu, ..roll }))
        })
        .collect::<Result<Vec<_>>>()?;
    let curves = par_runs(&runs, |(o, exact)| -> Result<Option<Curve>> {
        let r = run(file.build(o)?.as_ref())?;
        let pts: Option<Vec<(f64, f64, f64)>> = r
            .rows
            .iter()
            .map(|x| Some((x.t, x.friction?.0, x.spin?.1)))
            .collect();
        Ok(pts.map(|pts| Curve {
            exact: *exact,
            velocity: pts.iter().map(|p| (p.0, p.1)).collect(),
            slip: pts.iter().map(|p| (p.0, p.1 - radius * p.2)).collect(),
        }))
    })?;
    if curves.is_empty() {
        return Ok((Vec::new(), Vec::new()));
    }
    let threshold = roll.slope.tan() / 3.0;
    let header = [
        "μ",
        "regime (tan α/3 = ",
        "acceleration (fit)",
        "rigid disc",
        "the other law",
        "small-displacement disc (rolling)",
        "slip acceleration (fit)",
        "rigid disc",
        "slip v − Rω at T",
    ]
    .map(|h| {
        Rich::from(if h.ends_with("= ") {
            format!("{h}{threshold:.4})")
        } else {
            h.to_string()
        })
    })
    .to_vec();
    let rows = curves
        .iter()
        .map(|c| {
            let (a, s, small) = c.fitted(radius);
            let e = c.exact;
            let other = if e.rolls() {
                e.gravity * (e.slope.sin() - e.mu * e.slope.cos())
            } else {
                2.0 / 3.0 * e.gravity * e.slope.sin()
            };
            [
                format!("{}", e.mu),
                (if e.rolls() { "rolls" } else { "slides" }).into(),
                format!("{a:.4}"),
                format!("{:.4}", e.acceleration()),
                format!("{other:.4}"),
                format!("{small:.4}"),
                format!("{s:.4}"),
                format!("{:.4}", e.slip_acceleration()),
                format!("{:.2e}", c.slip.last().map_or(f64::NAN, |p| p.1)),
            ]
            .map(Into::into)
            .to_vec()
        })
        .collect();
    let kind = case.kind();
    let blocks = vec![
        Block::Para(Rich::parse(&format!(
            "**{kind}**, the disc on a slope α = {} released at rest: one run per sweep (its own \
             μ), the accelerations fitted (least squares) to the centre's velocity and to the \
             contact point's slip velocity `v − Rω` over `t ≥ {FIT_FROM} T` (after the release's \
             bounce), against the rigid disc: `⅔ g sin α` with no slip when μ ≥ tan α/3, \
             `g (sin α − μ cos α)` with the slip growing at `g (sin α − 3μ cos α)` otherwise. The \
             finite element disc is linearly elastic: rolling, it converges under refinement to \
             the small-displacement disc (`exact::roll`; the linearised rotation stretches it, \
             so it rises by `R θ²/2` as it turns, `a = ⅔ g (sin α − θ cos α)`), fitted on the \
             same samples; a coarse mesh pivoting about its pole node follows the rigid disc \
             while `θ < h/2R`.",
            roll.slope
        ))),
        Block::Table(header, rows),
    ];
    let mut velocity = Vec::new();
    let mut slip = Vec::new();
    for (k, c) in curves.iter().enumerate() {
        let e = c.exact;
        let label = format!(
            "μ = {} ({})",
            e.mu,
            if e.rolls() { "rolls" } else { "slides" }
        );
        let colour = style::sequence(k, curves.len());
        let line = |pts: &[(f64, f64)], rate: f64| -> Vec<(f64, f64)> {
            pts.iter().map(|p| (p.0, rate * p.0)).collect()
        };
        velocity.push(Series::new(label.clone(), c.velocity.clone(), colour));
        let dashed = Style {
            dash: Dash::Dashed,
            ..colour
        };
        velocity.push(Series::new(
            format!("rigid, μ = {}: {:.4} t", e.mu, e.acceleration()),
            line(&c.velocity, e.acceleration()),
            dashed,
        ));
        slip.push(Series::new(label, c.slip.clone(), colour));
        slip.push(Series::new(
            format!("rigid, μ = {}: {:.4} t", e.mu, e.slip_acceleration()),
            line(&c.slip, e.slip_acceleration()),
            dashed,
        ));
    }
    let mut figures = Vec::new();
    for (name, what, series) in [
        ("velocity", "centre's velocity down the slope v", velocity),
        ("slip", "contact point's slip velocity v − Rω", slip),
    ] {
        let file = format!("friction_{kind}_{name}.png");
        time_plot(&out.join(&file), &format!("{kind}: {what}"), what, &series)?;
        figures.push(Figure {
            file,
            case: SECTION.into(),
            alt: format!(
                "A line plot of the disc's {what} against time t, one curve per friction \
                 coefficient, each with the rigid disc's straight line dashed."
            ),
            caption: format!(
                "{kind}: the {what} against time for μ on both sides of tan α/3 = {threshold:.4} \
                 (α = {}); dashed the rigid disc (rolling `⅔ g sin α t` and no slip, or sliding \
                 `g (sin α − μ cos α) t` with slip `g (sin α − 3μ cos α) t`).",
                roll.slope
            ),
        });
    }
    Ok((figures, blocks))
}
