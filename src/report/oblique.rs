//! The "Friction" section's oblique impact (issue 25 §2–3): one run of an `oblique3d` case per
//! incidence of its `[oblique]` table (`--quick`: the quick incidences and level), each giving
//! the tangential restitution e_t, the rebound spin ω'R/V, the normal restitution e_n and the
//! impulses; a table and two figures beside the rigid-body limits and Chung & Ooi's curve as
//! digitised by the Kratos developers ([`crate::exact::oblique`]) and Maw, Barber & Fawcett's
//! theory computed by the method of dimensionality reduction ([`crate::exact::mbf`]), and the
//! conclusions computed from them: the gross-slip agreement with `e_t = 1 − μ(1 + e_n)/tan θ`,
//! and where the stick regime lies against the band [3/7, 1], MBF and the digitised points.

use super::doc::{Block, Cell, Figure, Rich};
use super::friction::{par_runs, SECTION};
use crate::cases::{sweep::Refinement, CaseFile, Overrides};
use crate::error::Result;
use crate::exact::mbf::{Mbf, Rebound, Resolution, REPORT_RESOLUTION};
use crate::exact::oblique::{
    chung_ooi_spin, maw_incidence, nearest, Oblique, CHUNG_OOI_ET, STICK_BAND,
};
use crate::output::plot::{xy_plot, Dash, Marker, Series, Style, PALETTE};
use crate::study::run::run;
use crate::study::schedule::Estimate;
use std::path::Path;

/// `|J_t| / (μ J_n)` at least this: the contact slid throughout (Coulomb's equality, to the
/// contact solver's tolerance and the impulse of the steps where a point sticks).
pub const GROSS_SLIP: f64 = 0.999;

/// The figures' MBF curve, one impact a degree: a quarter of the table's steps and springs
/// (second order in both: within 1e-6 of it).
const CURVE: Resolution = Resolution {
    steps: REPORT_RESOLUTION.steps / 4,
    springs: REPORT_RESOLUTION.springs / 4,
};

/// MBF at θ (degrees) for the case's ν and μ: scale-free (e_n = 1, quasi-static), so at unit
/// radius, moduli, density and speed.
fn mbf(reference: &Mbf, theta: f64, res: Resolution) -> Result<Rebound> {
    reference.impact(1.0, theta.to_radians(), res)
}

/// One incidence's run.
#[derive(Debug, Clone, Copy)]
struct Point {
    /// θ, degrees.
    theta: f64,
    e_n: f64,
    e_t: f64,
    /// `ω' R / V`.
    spin: f64,
    /// `|J_t| / (μ J_n)`.
    slip: f64,
    balance: f64,
    least_work: f64,
    /// MBF's rebound at this θ.
    mbf: Rebound,
}

impl Point {
    /// The rigid body with this run's μ, θ and measured e_n.
    fn rigid(&self, mu: f64) -> Oblique {
        Oblique {
            mu,
            incidence: self.theta.to_radians(),
            restitution: self.e_n,
        }
    }

    /// The contact point's `w'/w = (v_t' − ω'R)/v_t = e_t − (ω'R/V)/sin θ`.
    fn contact_point(&self) -> f64 {
        self.e_t - self.spin / self.theta.to_radians().sin()
    }
}

/// The run at incidence θ (degrees) with `o`'s mesh and time step.
fn point(file: &CaseFile, o: &Overrides, theta: f64, reference: &Mbf) -> Result<Option<Point>> {
    let (mu, mbf) = (reference.mu, mbf(reference, theta, REPORT_RESOLUTION)?);
    let case = file.build(&Overrides {
        incidence: Some(theta),
        ..o.clone()
    })?;
    let radius = case.spin().map_or(1.0, |s| s.radius);
    let r = run(case.as_ref())?;
    let m = &r.summary.metrics;
    let speed = r.rows.first().and_then(|x| {
        let (vt, vn) = (x.friction?.0, x.spin?.0);
        Some(vt.hypot(vn))
    });
    Ok((|| {
        Some(Point {
            theta,
            e_n: m.restitution_eff?,
            e_t: m.tangential_restitution?,
            spin: m.rebound_spin? * radius / speed?,
            slip: m.tangential_impulse?.abs() / (mu * m.normal_impulse?),
            balance: m.friction_balance?,
            least_work: m.friction_work_min_step?,
            mbf,
        })
    })())
}

fn f4(x: f64) -> Cell {
    format!("{x:.4}").into()
}

fn table(points: &[Point], (mu, poisson): (f64, f64)) -> Block {
    let spin_ref = chung_ooi_spin();
    let header = [
        "θ (°)",
        "ψ₁ = χ tan θ/μ",
        "e_n",
        "e_t",
        "e_t rigid",
        "e_t Chung & Ooi (digitised)",
        "e_t MBF (MDR)",
        "ω'R/V",
        "ω'R/V rigid",
        "ω'R/V Chung & Ooi (digitised)",
        "ω'R/V MBF (MDR)",
        "w'/w",
        "w'/w MBF (MDR)",
        "|J_t|/(μJ_n)",
        "max |E + W_f − E₀|/E₀",
        "min ΔW_f",
    ]
    .map(Rich::from)
    .to_vec();
    let reference = |curve: &[(f64, f64)], theta: f64| {
        nearest(curve, theta).map_or_else(Cell::default, |p| {
            format!("{:.4} ({:.1}°)", p.1, p.0).into()
        })
    };
    let rows = points
        .iter()
        .map(|p| {
            let rigid = p.rigid(mu);
            vec![
                format!("{:.0}", p.theta).into(),
                format!("{:.2}", maw_incidence(poisson, mu, p.theta.to_radians())).into(),
                f4(p.e_n),
                f4(p.e_t),
                format!(
                    "{:.4} ({})",
                    rigid.tangential_restitution(),
                    if rigid.slides() { "slides" } else { "sticks" }
                )
                .into(),
                reference(&CHUNG_OOI_ET, p.theta),
                f4(p.mbf.tangential_restitution),
                f4(p.spin),
                f4(rigid.spin()),
                reference(&spin_ref, p.theta),
                f4(p.mbf.spin),
                f4(p.contact_point()),
                f4(p.mbf.contact_point),
                f4(p.slip),
                format!("{:.2e}", p.balance).into(),
                format!("{:.2e}", p.least_work).into(),
            ]
        })
        .collect();
    Block::Table(header, rows)
}

/// The conclusions computed from the points.
fn conclusions(points: &[Point], mu: f64) -> Vec<Rich> {
    let mut out = Vec::new();
    let (slid, stuck): (Vec<&Point>, Vec<&Point>) =
        points.iter().partition(|p| p.slip >= GROSS_SLIP);
    if let Some(worst) = slid.iter().copied().max_by(|a, b| {
        let d = |p: &Point| (p.e_t - p.rigid(mu).sliding_restitution()).abs();
        d(a).total_cmp(&d(b))
    }) {
        let exact = worst.rigid(mu).sliding_restitution();
        let ratio = slid
            .iter()
            .map(|p| (p.slip - 1.0).abs())
            .fold(0.0, f64::max);
        out.push(Rich::parse(&format!(
            "Gross slip (`|J_t| ≥ {GROSS_SLIP} μJ_n`) at θ = {}°: `|J_t|/(μJ_n)` within {ratio:.1e} of 1, and \
             e_t agrees with `1 − μ(1 + e_n)/tan θ` (e_n measured) to {:.2e} ({:.3} %, worst at θ = {:.0}°: \
             {:.4} against {exact:.4}).",
            slid.iter().map(|p| format!("{:.0}", p.theta)).collect::<Vec<_>>().join(", "),
            (worst.e_t - exact).abs(),
            100.0 * (worst.e_t - exact).abs() / exact,
            worst.theta,
            worst.e_t
        )));
    }
    if !stuck.is_empty() {
        let inside = stuck
            .iter()
            .filter(|p| (STICK_BAND.0..=STICK_BAND.1).contains(&p.e_t))
            .count();
        let against: Vec<f64> = stuck
            .iter()
            .filter_map(|p| nearest(&CHUNG_OOI_ET, p.theta).map(|c| p.e_t - c.1))
            .collect();
        let worst = against
            .iter()
            .copied()
            .max_by(|a, b| a.abs().total_cmp(&b.abs()));
        out.push(Rich::parse(&format!(
            "Not sliding throughout (`|J_t| < {GROSS_SLIP} μJ_n`) at θ = {}°: e_t from {:.4} to \
             {:.4}, {inside} of {} inside the band [3/7, 1] that tangential compliance allows \
             while the contact sticks (the rigid stick: 5/7 = 0.7143){}. This is where the \
             elastic sphere's tangential compliance acts: the rigid limits do not hold, and the \
             digitised curve is a plausibility band only.",
            stuck
                .iter()
                .map(|p| format!("{:.0}", p.theta))
                .collect::<Vec<_>>()
                .join(", "),
            stuck.iter().map(|p| p.e_t).fold(f64::INFINITY, f64::min),
            stuck
                .iter()
                .map(|p| p.e_t)
                .fold(f64::NEG_INFINITY, f64::max),
            stuck.len(),
            worst.map_or(String::new(), |w| format!(
                "; the largest deviation from Chung & Ooi's digitised points is {w:+.3}"
            ))
        )));
        out.push(against_mbf(&stuck));
    }
    let balance = points.iter().map(|p| p.balance).fold(0.0, f64::max);
    let least = points
        .iter()
        .map(|p| p.least_work)
        .fold(f64::INFINITY, f64::min);
    out.push(Rich::parse(&format!(
        "Energy balance over the {} runs: `max |E + W_f − E(0)|/E(0)` ≤ {balance:.2e}; least friction \
         work of a step {least:.2e}.",
        points.len()
    )));
    out
}

/// Where the sphere does not slide throughout: its e_t and contact point against MBF's, and the
/// digitised points against MBF's.
fn against_mbf(stuck: &[&Point]) -> Rich {
    let rows: Vec<String> = stuck
        .iter()
        .map(|p| {
            format!(
                "{:.0}°: {:.3} against {:.3}{}",
                p.theta,
                p.e_t,
                p.mbf.tangential_restitution,
                nearest(&CHUNG_OOI_ET, p.theta)
                    .map_or(String::new(), |c| format!(" (digitised {:.3})", c.1))
            )
        })
        .collect();
    let span = |f: &dyn Fn(&Point) -> f64| {
        let v: Vec<f64> = stuck.iter().map(|p| f(p)).collect();
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        (lo, v.iter().copied().fold(f64::NEG_INFINITY, f64::max))
    };
    let fe = span(&|p| p.e_t - p.mbf.tangential_restitution);
    let digitised: Vec<f64> = stuck
        .iter()
        .filter_map(|p| nearest(&CHUNG_OOI_ET, p.theta).map(|c| c.1 - p.mbf.tangential_restitution))
        .collect();
    let worst = digitised
        .iter()
        .copied()
        .max_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap_or(0.0);
    let (w, w_mbf) = (span(&|p| p.contact_point()), span(&|p| p.mbf.contact_point));
    Rich::parse(&format!(
        "Against Maw, Barber & Fawcett's theory (the method of dimensionality reduction, the same ν \
         and μ, e_n = 1, no Poisson coupling, quasi-static): e_t {}. The finite elements differ from \
         it by {:+.3} to {:+.3}, the digitised points by up to {worst:+.3}; the contact point's \
         `w'/w = (v_t' − ω'R)/v_t` is {:.2} to {:.2} here and {:.2} to {:.2} in MBF. The finite \
         element sphere is not quasi-static at this speed (its e_t rises towards MBF's as the \
         impact slows) and has the Poisson coupling MBF leaves out (two equal spheres, without \
         it, are nearer MBF at small θ): `tests/oblique.rs`.",
        rows.join(", "),
        fe.0,
        fe.1,
        w.0,
        w.1,
        w_mbf.0,
        w_mbf.1
    ))
}

/// e_t(θ) and ω'R/V(θ) beside the rigid limits (e = the runs' mean e_n) and the digitised
/// points.
fn figures(points: &[Point], reference: &Mbf, out: &Path, setting: &str) -> Result<Vec<Figure>> {
    let mu = reference.mu;
    let e = points.iter().map(|p| p.e_n).sum::<f64>() / points.len() as f64;
    let curve = (1..90)
        .map(|t| Ok((t as f64, mbf(reference, t as f64, CURVE)?)))
        .collect::<Result<Vec<_>>>()?;
    let theory = |f: fn(&Rebound) -> f64| -> Series {
        Series::new(
            "Maw, Barber & Fawcett (MDR)",
            curve.iter().map(|(t, r)| (*t, f(r))).collect(),
            Style {
                dash: Dash::Long,
                ..Style::line(PALETTE[2])
            },
        )
    };
    let rigid = |f: fn(&Oblique) -> f64| -> Vec<(f64, f64)> {
        (1..90)
            .map(|t| {
                let o = Oblique {
                    mu,
                    incidence: (t as f64).to_radians(),
                    restitution: e,
                };
                (t as f64, f(&o))
            })
            .collect()
    };
    let marks = |color, marker| Style {
        color,
        marker,
        dash: Dash::None,
        hollow: true,
    };
    let fe = |f: fn(&Point) -> f64| -> Series {
        Series::new(
            "finite elements",
            points.iter().map(|p| (p.theta, f(p))).collect(),
            Style {
                marker: Marker::Circle,
                ..Style::line(PALETTE[0])
            },
        )
    };
    let plots = [
        (
            "oblique3d_tangential_restitution.png",
            "tangential restitution e_t = v_t'/v_t",
            fe(|p| p.e_t),
            rigid(Oblique::tangential_restitution),
            CHUNG_OOI_ET.to_vec(),
            theory(|r| r.tangential_restitution),
        ),
        (
            "oblique3d_rebound_spin.png",
            "rebound spin ω'R/V",
            fe(|p| p.spin),
            rigid(Oblique::spin),
            chung_ooi_spin(),
            theory(|r| r.spin),
        ),
    ];
    let mut figs = Vec::new();
    for (file, label, fe, rigid, digitised, theory) in plots {
        let series = [
            fe,
            theory,
            Series::reference(format!("rigid body (e = {e:.3})"), rigid),
            Series::new(
                "Chung & Ooi, digitised by Kratos",
                digitised,
                marks(PALETTE[1], Marker::Square),
            ),
        ];
        xy_plot(
            &out.join(file),
            &format!("oblique3d: {label}"),
            ("incidence θ (degrees from the normal)", label),
            &series,
        )?;
        figs.push(Figure {
            file: file.into(),
            case: SECTION.into(),
            alt: format!(
                "A line plot of the {label} against the incidence angle: the finite element runs, \
                 Maw, Barber & Fawcett's theory, the rigid-body limit and Chung & Ooi's digitised \
                 points."
            ),
            caption: format!(
                "oblique3d ({setting}, μ = {mu}): the {label} against the incidence θ, one run per \
                 angle; long dashes Maw, Barber & Fawcett's theory (Hertz + Cattaneo–Mindlin with \
                 microslip, computed by the method of dimensionality reduction, e_n = 1); dashed the \
                 rigid body (sliding throughout above `tan θ = 7/2 μ(1 + e)`, rigid stick below); \
                 squares Chung & Ooi's finite element curve (aluminium oxide, \
                 ν = 0.23, μ = 0.092) as digitised by the Kratos developers from the paper's figure."
            ),
        });
    }
    Ok(figs)
}

/// The runs of the study at `level` (each with its incidence besides).
fn level_overrides(level: Refinement) -> Overrides {
    Overrides {
        elements: level.elements,
        dt: Some(level.dt),
        ..Default::default()
    }
}

/// The estimated cost of [`study`], for the scheduler: one run per angle, two at a time.
pub fn estimate(file: &CaseFile, quick: bool) -> Result<Estimate> {
    let case = file.defaults()?;
    let Some(study) = case.oblique() else {
        return Ok(Estimate::default());
    };
    let (angles, level) = study.spec.study(quick);
    let o = level_overrides(level);
    let mut spec = case.run().clone();
    o.apply(&mut spec);
    let one = crate::study::jobs::estimate(file.size(&o), spec.steps(), &spec.space);
    Ok(Estimate {
        seconds: angles.len() as f64 * one.seconds,
        bytes: 2.0 * one.bytes,
    })
}

/// The oblique-impact study of `file`'s `[oblique]` table (none without one): its figures and
/// the section's table and conclusions.
pub fn study(file: &CaseFile, out: &Path, quick: bool) -> Result<(Vec<Figure>, Vec<Block>)> {
    let case = file.defaults()?;
    let Some(study) = case.oblique() else {
        return Ok((Vec::new(), Vec::new()));
    };
    let (angles, level) = study.spec.study(quick);
    let o = level_overrides(level);
    let mu = study.mu;
    let reference = Mbf::sphere(1.0, 1.0, 1.0, study.poisson, mu)?;
    let points = par_runs(angles, |&theta| point(file, &o, theta, &reference))?;
    if points.is_empty() {
        return Ok((Vec::new(), Vec::new()));
    }
    let run = case.run();
    let setting = format!(
        "{} + {}, {} elements, dt = {}",
        run.space,
        run.scheme,
        level.elements.map_or(String::new(), |n| n.to_string()),
        level.dt
    );
    let blocks = vec![
        Block::Para(Rich::parse(&format!(
            "**{}**, oblique impact ({setting}, ν = {}, μ = {mu}): one run per incidence θ; e_t and e_n \
             of the centre of mass, the rebound spin `ω'R/V` (angular momentum about the centre of \
             mass over the mesh's moment of inertia), the impulses from the momentum the contact \
             changed; the contact point's `w'/w = (v_t' − ω'R)/v_t`; beside them the rigid body \
             with the measured e_n, Chung & Ooi's finite element curve (aluminium oxide) as \
             digitised by the Kratos developers from the paper's figure (the paper is not readable \
             here; the nearest digitised angle in brackets) and Maw, Barber & Fawcett's theory \
             computed by the method of dimensionality reduction (MBF (MDR): Hertz + \
             Cattaneo–Mindlin with microslip and its history, e_n = 1, scale-free).",
            case.kind(),
            study.poisson
        ))),
        table(&points, (mu, study.poisson)),
        Block::List(conclusions(&points, mu)),
    ];
    Ok((figures(&points, &reference, out, &setting)?, blocks))
}
