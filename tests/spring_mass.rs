//! Spring–mass impact: effective restitution of each space × scheme against the exact e = 1 bounce.

use dyncontact::cases::{self, Overrides};
use dyncontact::study::run::run;
use std::path::Path;

fn spring(
    space: &str,
    beta: f64,
    gamma: f64,
    dt: f64,
) -> dyncontact::Result<dyncontact::study::run::RunResult> {
    let o = Overrides {
        space: Some(space.into()),
        dt: Some(dt),
        ..Default::default()
    }
    .with("beta", beta)
    .with("gamma", gamma);
    let case = cases::load(Path::new("cases/spring_mass.toml"), &o)?;
    run(case.as_ref())
}

/// Newmark(½, ½) with the contact at the new time level restores the elastic bounce: e_eff → 1,
/// impact time and trajectory errors → 0 with dt (measured: e_eff = 1.0000, max|u_h − u| 6.0e-2,
/// 6.0e-3 for dt = 1e-2, 1e-3: order 1). Standard and lumped mass coincide for one dof.
#[test]
fn newmark_half_half_reproduces_the_elastic_bounce() {
    for space in ["standard", "lumped"] {
        let coarse = spring(space, 0.5, 0.5, 1e-2).unwrap().summary.metrics;
        let fine = spring(space, 0.5, 0.5, 1e-3).unwrap().summary.metrics;
        println!(
            "{space}: e_eff {:?} {:?}",
            coarse.restitution_eff, fine.restitution_eff
        );
        assert!((fine.restitution_eff.unwrap() - 1.0).abs() < 1e-3);
        let (ec, ef) = (coarse.err_u_linf_l2.unwrap(), fine.err_u_linf_l2.unwrap());
        assert!((ec / ef).log10() > 0.8, "trajectory error {ec:e} -> {ef:e}");
        assert!(fine.impact_time_err.unwrap() < coarse.impact_time_err.unwrap());
        assert!((fine.energy_ratio - 1.0).abs() < 1e-3);
    }
}

/// Newmark(¼, ½) gains energy at the impact: e_eff > 1 (measured 2.68 at dt = 1e-2, 1.37 at 1e-3).
#[test]
fn newmark_trapezoidal_rebounds_with_restitution_above_one() {
    for dt in [1e-2, 1e-3] {
        let m = spring("standard", 0.25, 0.5, dt).unwrap().summary.metrics;
        let e = m.restitution_eff.unwrap();
        println!("dt={dt}: e_eff = {e}");
        assert!(e > 1.2, "dt={dt}: e_eff = {e}");
    }
}

/// Spaces that remove the inertia of the contact dof leave nothing to move on one dof.
#[test]
fn inertia_free_spaces_are_rejected_on_the_single_dof() {
    for space in [
        "mass_redistribution",
        "mass_elimination",
        "singular_dynamic",
    ] {
        let err = spring(space, 0.5, 0.5, 1e-2).unwrap_err().to_string();
        assert!(err.contains("single dof"), "{space}: {err}");
    }
}
