//! The seed paper's argument about the time-scheme cures (issue 23 §3), as tests that can fail,
//! on bar1d (unit bar, lift ½, N = 40 P1 elements, P2 for the singular dynamic method, Δt = h/2,
//! T = 6: two periods, two impacts). Run with `-- --nocapture` for the measured table.
//!
//! The seed: the cures that adapt the time scheme "either dissipate too much, or conserve
//! energy but then show local violations of the contact constraint, which can be large, or large
//! oscillations of the contact stress (or both)"; the space cures (mass redistribution, singular
//! dynamic method) let plain Newmark reach a stable energy and a smooth stress with no
//! penetration.

mod common;

use common::bar;
use dyncontact::cases::{Case, RunSpec};
use dyncontact::study::run::{run, RunResult};
use dyncontact::Error;

/// Elements of the bar.
const N: usize = 40;
/// Final time: two periods 3L/c.
const T: f64 = 6.0;

/// Runs bar1d with `scheme` on `space` (P2 for singular_dynamic), Δt = h/2; None when the
/// combination is refused by design (`Unsupported`).
fn bar_run(space: &str, scheme: &str, n: usize, set: impl Fn(&mut RunSpec)) -> Option<RunResult> {
    let degree = if space == "singular_dynamic" { 2 } else { 1 };
    let mut spec = RunSpec::new(space, scheme, 0.5 / n as f64, T);
    set(&mut spec);
    match run(&bar(n, degree, spec) as &dyn Case) {
        Ok(r) => Some(r),
        Err(Error::Unsupported(why)) => {
            println!("{scheme} on {space}: refused ({why})");
            None
        }
        Err(e) => panic!("{scheme} on {space}: {e}"),
    }
}

/// Newmark's β and γ.
fn newmark(beta: f64) -> impl Fn(&mut RunSpec) {
    move |s: &mut RunSpec| {
        s.options.params.set("beta", beta).set("gamma", 0.5);
    }
}

/// The largest one-step rise of the energy, relative to E₀.
fn worst_rise(r: &RunResult) -> f64 {
    let e0 = r.rows[0].energy;
    r.rows
        .windows(2)
        .map(|w| (w[1].energy - w[0].energy) / e0)
        .fold(f64::MIN, f64::max)
}

/// Laursen–Chawla conserves the energy to round-off in every step, but penetrates, by O(Δt).
#[test]
fn laursen_chawla_conserves_energy_to_round_off_but_penetrates_by_order_dt() {
    let mut pen = Vec::new();
    for n in [N, 4 * N] {
        let r = bar_run("standard", "laursen_chawla", n, |_| ()).expect("runs");
        let e0 = r.rows[0].energy;
        let step = r
            .rows
            .windows(2)
            .map(|w| (w[1].energy - w[0].energy).abs() / e0)
            .fold(0.0, f64::max);
        let p = r.summary.metrics.max_penetration;
        println!("laursen_chawla N = {n}: largest |E_(n+1) − E_n| / E₀ = {step:.1e}, max penetration {p:.3e}");
        assert!(step < 1e-11, "energy changed by {step:e} E₀ in a step");
        assert!(p > 1e-4, "no penetration at N = {n}: {p:e}");
        pen.push(p);
    }
    let order = (pen[0] / pen[1]).log2() / 2.0;
    println!("penetration order {order:.2}");
    assert!((0.7..1.3).contains(&order), "penetration order {order}");
}

/// Hauret–Le Tallec and Deuflhard–Krause–Ertel never increase the energy (Hauret–Le Tallec's
/// includes the penalty energy), on every space they run on.
#[test]
fn hauret_le_tallec_and_deuflhard_krause_ertel_never_increase_the_energy() {
    for scheme in ["hauret_le_tallec", "contact_stabilised_newmark"] {
        for space in &dyncontact::space::names() {
            let Some(r) = bar_run(space, scheme, N, |_| ()) else {
                continue;
            };
            let rise = worst_rise(&r);
            println!("{scheme} on {space}: largest one-step rise {rise:.1e} E₀");
            assert!(
                rise < 1e-11,
                "{scheme} on {space}: energy rose by {rise:e} E₀"
            );
        }
    }
}

/// Hauret–Le Tallec's penalty law runs through block3d's impact with the massless contact dofs
/// of mass redistribution and mass elimination (25 points), its E + Φ never rising beyond
/// round-off. Its convergence test was relative to each point's own force, so that a point of
/// nearly no force asked for nearly no error: steps 2065 and 2043 failed after Newton, the
/// Gauss–Seidel sweeps (converged by their own measure, relative to the largest force) and
/// Newton again. The test is now relative to the largest force, the sweeps' measure.
#[test]
fn hauret_le_tallec_runs_through_the_block_with_massless_contact_dofs() {
    for space in ["mass_redistribution", "mass_elimination"] {
        let o = dyncontact::cases::Overrides {
            space: Some(space.into()),
            scheme: Some("hauret_le_tallec".into()),
            ..Default::default()
        };
        let case = dyncontact::cases::load(std::path::Path::new("cases/block3d.toml"), &o).unwrap();
        let r = run(case.as_ref()).expect("runs to the end");
        let rise = worst_rise(&r);
        println!("hauret_le_tallec on block3d, {space}: largest one-step rise {rise:.1e} E₀");
        assert!(rise < 1e-11, "{space}: energy rose by {rise:e} E₀");
    }
}

/// Carpenter's forward-increment multiplier keeps `g ≥ 0` at every step. Another LCP solver
/// asked for is the one used (it was ignored for the closed form of the nodal rows), and solves
/// the same law: the same gaps and forces to its tolerance.
#[test]
fn carpenter_keeps_the_gap_closed_from_below_at_every_step() {
    let r = bar_run("lumped", "carpenter", N, |_| ()).expect("runs on the lumped mass");
    let min = r.rows.iter().map(|x| x.gap).fold(f64::INFINITY, f64::min);
    println!("carpenter: smallest gap {min:.1e}");
    assert!(min >= -1e-12, "carpenter penetrates: {min:e}");
    let clarabel = bar_run("lumped", "carpenter", N, |s| {
        s.options.contact_solver = Some("clarabel".into());
    })
    .expect("runs with clarabel");
    let diff = r
        .rows
        .iter()
        .zip(&clarabel.rows)
        .map(|(a, b)| {
            (a.gap - b.gap)
                .abs()
                .max((a.sigma_contact - b.sigma_contact).abs())
        })
        .fold(0.0, f64::max);
    println!("carpenter, closed form against clarabel: {diff:.1e}");
    assert!(diff > 0.0, "the same bytes: was clarabel used?");
    assert!(diff < 1e-6, "closed form and clarabel differ by {diff:e}");
}

/// What a run says for the comparison: energy drift, σ_N total variation, max penetration.
fn measures(r: &RunResult) -> (f64, f64, f64) {
    let m = &r.summary.metrics;
    (m.energy_drift, m.sigma_total_variation, m.max_penetration)
}

/// With mass redistribution and the singular dynamic method, plain Newmark ½, ½ does not
/// penetrate. Against the time-scheme cures run on the standard (implicit cures) or lumped
/// (explicit cures) mass, measured (N = 40, `-- --nocapture`):
///
/// | scheme on space | energy drift | σ_N total variation | max penetration |
/// |---|---|---|---|
/// | laursen_chawla, standard | 2.5e-13 | 49.5 | 6.3e-3 |
/// | hauret_le_tallec, standard | 1.35e-2 | 6.48 | 2.7e-4 |
/// | contact_stabilised_newmark, standard | 1.36e-2 | 3.39 | 0 |
/// | kane, standard | 1.33e-2 | 27.0 | 0 |
/// | carpenter, lumped | 2.07e-2 | 2.99 | 0 |
/// | taylor_flanagan, lumped | 2.57e-2 | 3.45 | 0 |
/// | explicit_penalty, lumped | 3.1e-3 | 15.4 | 1.0e-2 |
/// | newmark ½, ½, mass_redistribution | 3.08e-2 | 1.70 | 0 |
/// | newmark ½, ½, singular_dynamic (P2) | 5.0e-3 | 13.2 | 0 |
/// | newmark ¼, ½, mass_redistribution | 2.76e-2 | 2.23 | 0 |
/// | newmark ¼, ½, singular_dynamic (P2) | 6.3e-3 | 39.3 | 0 |
///
/// The seed's claim holds for mass redistribution's contact stress (the smoothest of all) and
/// its non-penetration; it does **not** hold for the energy (Newmark ½, ½ is dissipative: its
/// drift is the largest), nor, at this resolution, for the singular dynamic method's P2 stress
/// (4.4 times the best cure's total variation). Both are pinned here as measured, so that a
/// change of either shows.
#[test]
fn space_cures_with_plain_newmark_against_the_time_scheme_cures() {
    let cures = [
        ("standard", "laursen_chawla"),
        ("standard", "hauret_le_tallec"),
        ("standard", "contact_stabilised_newmark"),
        ("standard", "kane"),
        ("lumped", "carpenter"),
        ("lumped", "taylor_flanagan"),
        ("lumped", "explicit_penalty"),
    ];
    let (mut best_tv, mut best_drift) = (f64::INFINITY, f64::INFINITY);
    println!("scheme on space: energy drift, σ_N total variation, max penetration");
    for (space, scheme) in cures {
        let r = bar_run(space, scheme, N, |_| ()).expect("the cure runs on its mass");
        let (drift, tv, pen) = measures(&r);
        println!("{scheme} on {space}: {drift:.2e}, {tv:.2}, {pen:.2e}");
        best_tv = best_tv.min(tv);
        best_drift = best_drift.min(drift);
    }
    let mut measured = Vec::new();
    for space in ["mass_redistribution", "singular_dynamic"] {
        for beta in [0.5, 0.25] {
            let r = bar_run(space, "newmark", N, newmark(beta)).expect("runs");
            let (drift, tv, pen) = measures(&r);
            println!("newmark β = {beta}, γ = ½ on {space}: {drift:.2e}, {tv:.2}, {pen:.2e}");
            assert!(pen < 1e-12, "{space}, β = {beta}: penetration {pen:e}");
            if beta == 0.5 {
                measured.push((drift, tv));
            }
        }
    }
    let [(mr_drift, mr_tv), (sd_drift, sd_tv)] = measured[..] else {
        unreachable!()
    };
    assert!(
        mr_tv <= best_tv,
        "mass redistribution: σ_N total variation {mr_tv} above the best cure's {best_tv}"
    );
    // Pinned contradictions (see the doc comment): the drift of Newmark ½, ½ above the best
    // cure's on both spaces, the singular dynamic P2 stress rougher than the best cure's.
    assert!(
        mr_drift > best_drift && sd_drift > best_drift,
        "the energy claim now holds: {mr_drift:e}, {sd_drift:e} against {best_drift:e}"
    );
    assert!(
        sd_tv > 2.0 * best_tv,
        "the singular dynamic stress claim now holds: {sd_tv} against {best_tv}"
    );
}
