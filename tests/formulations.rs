//! Contact formulations (`--contact`): the claims each one makes, checked on the bar (exact
//! solution) and on the disc (Hertz).

mod common;

use common::{bar, run_spec};
use dyncontact::cases::{self, Overrides};
use dyncontact::study::run::{run, RunResult};
use std::path::Path;

/// The bar (80 elements of degree `degree`, mass redistribution, Newmark ½, ½, T = 3) with the
/// contact options `contact` and `multiplier`.
fn bar_with(degree: usize, contact: &str, multiplier: Option<&str>) -> RunResult {
    let mut spec = run_spec("mass_redistribution", 0.5, 0.5, 0.5 / 80.0, 3.0);
    spec.options.contact = Some(contact.into());
    spec.options.contact_multiplier = multiplier.map(Into::into);
    run(&bar(80, degree, spec)).unwrap()
}

/// Largest difference of the probe displacement and contact stress between two runs.
fn max_difference(a: &RunResult, b: &RunResult) -> f64 {
    a.rows
        .iter()
        .zip(&b.rows)
        .map(|(x, y)| {
            (x.u_contact - y.u_contact)
                .abs()
                .max((x.sigma_contact - y.sigma_contact).abs())
        })
        .fold(0.0, f64::max)
}

/// In 1D Γ_C is the end point: the weak constraint `∫_{Γ_C} μ (g − u·n)` is the point value, so
/// the weak multipliers (P1 and P0) and the nodal one coincide, to round-off, for P1 and P2.
#[test]
fn weak_and_nodal_multipliers_coincide_in_1d() {
    for degree in [1, 2] {
        let nodal = bar_with(degree, "nodal", None);
        for multiplier in ["p1", "p0"] {
            let weak = bar_with(degree, "weak", Some(multiplier));
            let diff = max_difference(&nodal, &weak);
            println!("P{degree}, weak {multiplier}: max difference {diff:e}");
            assert!(diff <= 1e-13, "P{degree} {multiplier}: {diff:e}");
            assert!(weak
                .summary
                .parameters
                .ends_with(&format!("contact=weak_{multiplier}")));
        }
    }
}

fn disc(contact: &str, multiplier: Option<&str>) -> RunResult {
    let mut o = Overrides {
        elements: Some(24),
        dt: Some(0.04),
        ..Default::default()
    };
    o.options.contact = Some(contact.into());
    o.options.contact_multiplier = multiplier.map(Into::into);
    let case = cases::load(Path::new("cases/hertz2d.toml"), &o).unwrap();
    run(case.as_ref()).unwrap()
}

/// The disc against Hertz's line contact at peak force (n = 24, dt = 0.04, mass redistribution):
/// the weak multipliers, P1 at the vertices and P0 per face, give the contact half-width and the
/// peak pressure within 2 % (measured when written: P1 0.57 % and 0.24 %, P0 0.17 % and 0.23 %;
/// nodal 0.25 % and 0.13 %), and conserve the energy as the nodal contact does (drift < 1e-3).
#[test]
fn weak_contact_on_the_disc_agrees_with_hertz() {
    for multiplier in ["p1", "p0"] {
        let m = disc("weak", Some(multiplier)).summary.metrics;
        let (a, p0) = (m.err_contact_radius.unwrap(), m.err_peak_pressure.unwrap());
        println!(
            "weak {multiplier}: half-width {a:.3e}, p0 {p0:.3e}, drift {:.3e}",
            m.energy_drift
        );
        assert!(a < 0.02 && p0 < 0.02, "{multiplier}: {a} {p0}");
        assert!(
            m.energy_drift < 1e-3,
            "{multiplier}: drift {}",
            m.energy_drift
        );
    }
}

/// P0 multipliers on a triangulated Γ_C (more faces than vertices) are refused, and a
/// multiplier space without `contact = "weak"` too.
#[test]
fn unstable_or_meaningless_multiplier_choices_are_refused() {
    let mut o = Overrides {
        mesh: Some("cases/meshes/sphere.msh".into()),
        t_end: Some(0.5),
        ..Default::default()
    };
    o.options.contact = Some("weak".into());
    o.options.contact_multiplier = Some("p0".into());
    let case = cases::load(Path::new("cases/hertz3d.toml"), &o).unwrap();
    let e = run(case.as_ref()).err().unwrap().to_string();
    assert!(e.contains("P0 multipliers") && e.contains("faces"), "{e}");
    o.options.contact = None;
    let e = cases::load(Path::new("cases/hertz3d.toml"), &o)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("contact_multiplier"), "{e}");
}
