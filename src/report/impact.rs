//! The report's figures of a curved-body impact (cases with a Hertz reference), from one run of
//! the case's defaults (`--quick`: its first sweep's coarsest level):
//! - `<case>_force.png` (also for two bodies, the only figure there): the total contact force
//!   against time, with Hertz's quasi-static
//!   `F(t)` dashed (sphere; the disc has no closed form) and, for the sphere, the quasi-static
//!   impact of the discrete body's own static law ([`crate::study::finite_body`]); the caption
//!   gives the run's errors against both, and `<case>_finite_body.csv` the static solves;
//! - `<case>_pressure.png`: the pressure `λ_r / |Γ_C|_r` of every Γ_C vertex at peak force
//!   against its distance from the contact centre, with Hertz's profile `p₀ √(1 − r²/a²)` for
//!   the computed force dashed;
//! - `<case>_von_mises.png` (2D): the body near the contact, deformed (true scale) and coloured
//!   by the von Mises stress at peak force: Hertz's subsurface maximum below the contact;
//! - `<case>_pressure_map.png` (3D): the Γ_C faces within two contact radii, seen from the
//!   plane, coloured by the mean pressure of their vertices at peak force.

use super::doc::Figure;
use super::style;
use crate::cases::{Case, CaseFile, Impact, Overrides};
use crate::error::{Error, Result};
use crate::fem::discretisation::Discretisation;
use crate::output::csv::write_rows;
use crate::output::field_plot::{cell_map, scatter_plot, Cell, Labels};
use crate::output::fmt_float;
use crate::output::plot::{time_plot, Dash, Marker, Series, Style};
use crate::study::finite_body::{finite_body, FiniteBody};
use crate::study::jobs::Job;
use crate::study::metrics::ImpactMeasures;
use crate::study::run::{run, Peak, RunResult};
use std::path::Path;
use std::sync::Arc;

/// Samples of Hertz's quasi-static force history drawn.
const HERTZ_SAMPLES: usize = 400;
/// Half-width of the von Mises picture, in contact half-widths.
const ZOOM: f64 = 4.0;

/// The run of the impact figures: the case's defaults, or (`quick`) its first sweep's first
/// level.
pub fn impact_overrides(file: &CaseFile, quick: bool) -> Result<Overrides> {
    let mut o = Overrides::default();
    if quick {
        let case = file.defaults()?;
        if let Some(sweep) = case.sweeps().first() {
            let level = sweep.refinements(true)?[0];
            (o.elements, o.dt, o.t_end) = (level.elements, Some(level.dt), sweep.t_end);
        }
    }
    Ok(o)
}

/// The overrides of the impact figures' run ([`impact_overrides`]) and its case.
fn impact_case(file: &CaseFile, quick: bool) -> Result<(Overrides, Arc<dyn Case>)> {
    let o = impact_overrides(file, quick)?;
    let case = if quick {
        file.build(&o)?.into()
    } else {
        file.defaults()?
    };
    Ok((o, case))
}

/// The key of the job of `jobs` that runs the impact figures' run of `file`, if any (hertz3d's
/// defaults are its sweep's finest level of the mass redistribution): the figures are then
/// drawn from that run, made once.
pub fn sweep_run(file: &CaseFile, quick: bool, jobs: &[Job]) -> Result<Option<String>> {
    let (o, case) = impact_case(file, quick)?;
    if case.impact().is_none() {
        return Ok(None);
    }
    for j in jobs {
        if j.runs(file, &o, case.as_ref())? {
            return Ok(Some(j.key.clone()));
        }
    }
    Ok(None)
}

/// The impact figures of `file`, or none when the case has no Hertz reference; `given` is their
/// run when it was made already ([`sweep_run`]).
pub fn impact_figures(
    file: &CaseFile,
    out: &Path,
    quick: bool,
    given: Option<RunResult>,
) -> Result<Vec<Figure>> {
    let (_, case) = impact_case(file, quick)?;
    let Some(impact) = case.impact() else {
        return Ok(Vec::new());
    };
    let kind = case.kind();
    let r = match given {
        Some(r) => r,
        None => run(case.as_ref())?,
    };
    let peak = r
        .peak
        .as_ref()
        .filter(|p| p.lambda.iter().any(|&l| l > 0.0));
    let Some(peak) = peak else {
        return Ok(Vec::new());
    };
    let s = &r.summary;
    let setting = format!(
        "{} + {}, h = {:.3e}, dt = {}",
        s.space,
        s.method(),
        s.h,
        s.dt
    );
    let finite = if impact.hertz.dim == 3 {
        let f = finite_body(case.as_ref())?;
        write_finite_body(&out.join(format!("{kind}_finite_body.csv")), &f)?;
        Some(f)
    } else {
        None
    };
    let shot = Shot {
        out,
        kind,
        in_series: !case.bodies().is_empty(),
        peak,
        impact: &impact,
        finite: finite.as_ref(),
        space: &s.space,
        setting,
    };
    let mut figures = vec![shot.force(&r.rows)?];
    // The pictures of the body need its mesh (one body: the rows are its Γ_C vertices).
    if let Some(fem) = case.discretisation() {
        figures.push(shot.pressure(fem)?);
        figures.push(if fem.dim() == 2 {
            shot.von_mises(fem)?
        } else {
            shot.pressure_map(fem)?
        });
    }
    Ok(figures)
}

/// What the figures of one impact run are drawn from.
struct Shot<'a> {
    out: &'a Path,
    kind: &'a str,
    /// Two bodies: the finite-body law is both bodies' in series.
    in_series: bool,
    peak: &'a Peak,
    impact: &'a Impact,
    /// The discrete body's own quasi-static impact (sphere).
    finite: Option<&'a FiniteBody>,
    /// The space, for titles.
    space: &'a str,
    /// Space, scheme, h and dt, for captions.
    setting: String,
}

impl Shot<'_> {
    fn force(&self, rows: &[crate::study::trajectory::Row]) -> Result<Figure> {
        let (out, kind, impact, setting) = (self.out, self.kind, self.impact, &self.setting);
        let computed: Vec<(f64, f64)> = rows.iter().map(|r| (r.t, r.force_contact)).collect();
        let mut series = vec![Series::new(
            format!("computed ({})", self.space),
            computed,
            Style::line(style::space(self.space).color),
        )];
        // Hertz's histories start at the first touch, t₀ = g₀/v.
        let from_touch = |h: Vec<(f64, f64)>| -> Vec<(f64, f64)> {
            let t0 = impact.touch_time();
            h.into_iter().map(|(t, f)| (t0 + t, f)).collect()
        };
        let hertz = impact.hertz.force_history(HERTZ_SAMPLES).map(from_touch);
        if let Some(h) = &hertz {
            series.push(Series::reference("Hertz (quasi-static)", h.clone()));
        }
        if let Some(history) = self
            .finite
            .and_then(|f| f.hertz.force_history(HERTZ_SAMPLES))
            .map(from_touch)
        {
            series.push(Series::new(
                if self.in_series {
                    "quasi-static, the bodies' own static laws in series"
                } else {
                    "quasi-static, the body's own static law"
                },
                history,
                Style {
                    dash: Dash::Long,
                    ..Style::line(plotters::style::RGBColor(110, 110, 110))
                },
            ));
        }
        let name = format!("{kind}_force.png");
        time_plot(
            &out.join(&name),
            &format!("{kind}: total contact force ({})", self.space),
            "total contact force Σλ",
            &series,
        )?;
        let decomposition = match (self.finite, ImpactMeasures::of(rows)) {
            (Some(f), Some(m)) => {
                let pct = |e: [Option<f64>; 3]| {
                    e.map(|x| x.map_or_else(|| "-".into(), |x| format!("{:+.2} %", 100.0 * x)))
                        .join(", ")
                };
                let (mass, law) = if self.in_series {
                    (
                        "meshes' reduced mass m₁m₂/(m₁ + m₂)",
                        "two bodies' own static laws in series (each measured alone against \
                         the plane, the approaches added), δ(F) = (F/k*)^(2/3) − c F/(E* R*)",
                    )
                } else {
                    (
                        "mesh's mass",
                        "body's own static law δ(F) = (F/k)^(2/3) − c F/(E* R)",
                    )
                };
                format!(
                    ". Errors of (t_c, F_max, δ_max): against Hertz {}; against Hertz for the \
                     {mass} ({:.4}) {}; against the quasi-static impact of the {law}, \
                     c = {:.4} (static solves in \
                     [{kind}_finite_body.csv]({kind}_finite_body.csv)), {}: what Hertz's \
                     half-space misses is the finite body, the rest is the dynamics",
                    pct(m.errors(&impact.hertz)),
                    f.half_space.mass,
                    pct(m.errors(&f.half_space)),
                    f.coefficient,
                    pct(m.errors(&f.hertz)),
                )
            }
            _ => String::new(),
        };
        let labels: Vec<&str> = series.iter().map(|s| s.label.as_str()).collect();
        Ok(Figure {
            file: name,
            case: kind.to_string(),
            alt: format!(
                "Line plot of the total contact force against time t: {}.",
                labels.join("; ")
            ),
            caption: format!(
                "{kind}: total contact force Σλ against time ({setting}){}{decomposition}.",
                if hertz.is_some() {
                    ", Hertz's quasi-static force history dashed"
                } else {
                    " (a disc has no closed-form force history)"
                }
            ),
        })
    }

    fn pressure(&self, fem: &Discretisation) -> Result<Figure> {
        let (out, kind, peak, impact) = (self.out, self.kind, self.peak, self.impact);
        let setting = &self.setting;
        let (r, force) = impact.distances(&peak.lambda);
        let (a, p0) = (
            impact.hertz.contact_radius(force),
            impact.hertz.peak_pressure(force),
        );
        let points: Vec<(f64, f64)> = fem
            .contact_vertices
            .iter()
            .zip(&peak.lambda)
            .zip(r)
            .map(|((&(_, area), l), r)| (r, l / area))
            .filter(|p| p.1 > 0.0 || p.0 <= 2.0 * a)
            .collect();
        let profile: Vec<(f64, f64)> = (0..=200)
            .map(|k| {
                let r = a * k as f64 / 200.0;
                (r, p0 * (1.0 - (r / a).powi(2)).max(0.0).sqrt())
            })
            .collect();
        let name = format!("{kind}_pressure.png");
        let n_points = points.len();
        let marks = Style {
            marker: Marker::Circle,
            dash: Dash::None,
            ..style::space(self.space)
        };
        scatter_plot(
            &out.join(&name),
            Labels {
                title: &format!("{kind}: contact pressure at peak force (t = {:.3})", peak.t),
                x: "distance r from the centre of pressure",
                y: "",
                value: "contact pressure p = λ / area",
            },
            &[
                Series::new(
                    format!("computed, each contact vertex ({})", self.space),
                    points,
                    marks,
                ),
                Series::reference(
                    format!("Hertz for F = {force:.4e}: a = {a:.4}, p₀ = {p0:.4}"),
                    profile,
                ),
            ],
        )?;
        Ok(Figure {
            file: name,
            case: kind.to_string(),
            alt: format!(
                "Scatter plot of the contact pressure of {} contact vertices against their \
                 distance from the contact centre, with Hertz's half-ellipse profile dashed \
                 (a = {a:.4}, p0 = {p0:.4}).",
                n_points
            ),
            caption: format!(
                "{kind}: pressure λ/area of every Γ_{{C}} vertex at peak force (t = {:.3}) against \
                 its distance from the centre of pressure ({setting}); Hertz's profile \
                 p₀ √(1 − r²/a²) for the computed force F = {force:.4e} dashed (a = {a:.4}, \
                 p₀ = {p0:.4}).",
                peak.t
            ),
        })
    }

    fn von_mises(&self, fem: &Discretisation) -> Result<Figure> {
        let (out, kind, peak, impact) = (self.out, self.kind, self.peak, self.impact);
        let setting = &self.setting;
        let (c, force) = impact.centre_of_pressure(&peak.lambda);
        let window = ZOOM * impact.hertz.contact_radius(force);
        let stress = fem.von_mises(&peak.u);
        let corners = fem.mesh.element.cyclic_vertices();
        let d = fem.dim();
        let cells: Vec<Cell> = fem
            .mesh
            .connectivity
            .iter()
            .zip(&stress)
            .filter_map(|(cell, &v)| {
                let poly: Vec<(f64, f64)> = corners
                    .iter()
                    .map(|&a| {
                        let i = cell[a];
                        let x = fem.mesh.nodes[i];
                        (x[0] + peak.u[i * d], x[1] + peak.u[i * d + 1])
                    })
                    .collect();
                let inside = poly
                    .iter()
                    .all(|p| (p.0 - c[0]).abs() <= window && p.1 <= window);
                inside.then_some((poly, v))
            })
            .collect();
        let name = format!("{kind}_von_mises.png");
        if cells.is_empty() {
            return Err(Error::Plot {
                path: out.join(&name),
                message: format!("no cell within {window:.3e} of the contact"),
            });
        }
        cell_map(
            &out.join(&name),
            Labels {
                title: &format!("{kind}: von Mises stress at peak force (t = {:.3})", peak.t),
                x: "x (deformed)",
                y: "height y above the plane (deformed)",
                value: "von Mises stress",
            },
            &cells,
            &[],
        )?;
        Ok(Figure {
            file: name,
            case: kind.to_string(),
            alt: format!(
                "Map of the deformed disc near the contact, x horizontal and height y vertical \
                 on equal scales, {} cells coloured by the von Mises stress on a viridis scale.",
                cells.len()
            ),
            caption: format!(
                "{kind}: the body within {ZOOM} contact half-widths of the contact at peak force \
                 (t = {:.3}), deformed at true scale, x horizontal and the height y above the \
                 plane vertical on equal scales, each cell coloured by the von Mises stress at \
                 its centroid ({setting}); Hertz's line contact puts the largest shear stress, \
                 0.30 p₀, at a depth 0.78 b.",
                peak.t
            ),
        })
    }

    fn pressure_map(&self, fem: &Discretisation) -> Result<Figure> {
        let (peak, impact, kind) = (self.peak, self.impact, self.kind);
        let (c, force) = impact.centre_of_pressure(&peak.lambda);
        let window = 2.0 * impact.hertz.contact_radius(force);
        let pressure = fem.contact_pressure(&peak.lambda);
        let cells: Vec<Cell> = fem
            .contact_faces
            .iter()
            .filter_map(|f| {
                let poly: Vec<(f64, f64)> = f
                    .vertices
                    .iter()
                    .map(|&i| (fem.mesh.nodes[i][0], fem.mesh.nodes[i][1]))
                    .collect();
                let inside = poly
                    .iter()
                    .all(|p| (p.0 - c[0]).abs() <= window && (p.1 - c[1]).abs() <= window);
                let mean =
                    f.vertices.iter().map(|&i| pressure[i]).sum::<f64>() / f.vertices.len() as f64;
                inside.then_some((poly, mean))
            })
            .collect();
        let name = format!("{kind}_pressure_map.png");
        let a = impact.hertz.contact_radius(force);
        let circle: Vec<(f64, f64)> = (0..=120)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 120.0;
                (c[0] + a * t.cos(), c[1] + a * t.sin())
            })
            .collect();
        cell_map(
            &self.out.join(&name),
            Labels {
                title: &format!(
                    "{kind}: contact pressure on the contact boundary at peak force (t = {:.3})",
                    peak.t
                ),
                x: "x",
                y: "y",
                value: "contact pressure",
            },
            &cells,
            &[Series::reference(format!("Hertz, a = {a:.4}"), circle)],
        )?;
        Ok(Figure {
            file: name,
            case: kind.to_string(),
            alt: format!(
                "Map of {} contact faces seen from the plane, x and y on equal scales, coloured \
                 by the contact pressure on a viridis scale, with Hertz's contact circle of \
                 radius {a:.4} drawn dashed.",
                cells.len()
            ),
            caption: format!(
                "{kind}: the Γ_{{C}} faces within two Hertz contact radii of the centre of \
                 pressure, seen from the plane (undeformed x, y on equal scales), coloured by the \
                 mean pressure of their vertices at peak force (t = {:.3}; {}); the dashed \
                 circle is Hertz's contact, radius a = {a:.4} for the computed force.",
                peak.t, self.setting
            ),
        })
    }
}

/// `<case>_finite_body.csv`: the static solves of the finite-body law, one row each: force F,
/// approach δ of the centre of mass, Hertz's approach `(F/k)^{2/3}`, coefficient
/// `c = (δ_Hertz − δ) E* R / F` (the caption gives the least-squares c).
fn write_finite_body(path: &Path, f: &FiniteBody) -> Result<()> {
    let rows = f.points.iter().map(|p| {
        [p.force, p.approach, p.hertz, p.coefficient(&f.hertz)].map(|x| fmt_float(Some(x)))
    });
    write_rows(path, FINITE_BODY_COLUMNS, rows)
}

/// Columns of `<case>_finite_body.csv`.
pub const FINITE_BODY_COLUMNS: &[&str] = &["force", "approach", "approach_hertz", "coefficient"];
