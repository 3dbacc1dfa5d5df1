//! Oblique impact of an elastic sphere with Coulomb friction (issue 25 §2, `cases/oblique3d.toml`:
//! R = 1, E = ρ = 1, ν = 0.23, μ = 0.092, speed V = 0.01, mass redistribution + Newmark ½,½)
//! against the limits that hold exactly ([`dyncontact::exact::oblique`]): gross slip at large
//! incidence, `|J_t| < μ J_n` and the compliance band at small incidence, the energy balance.
//! Run with `-- --nocapture` to see the measured numbers quoted in the doc comments.

use dyncontact::cases::{self, Overrides};
use dyncontact::exact::oblique::{Oblique, STICK_BAND};
use dyncontact::study::metrics::Metrics;
use dyncontact::study::run::run;
use std::path::Path;

const MU: f64 = 0.092;

/// The metrics of the run at incidence θ (degrees) on the mesh with n cells per edge.
fn oblique(theta: f64, n: usize, dt: f64) -> Metrics {
    oblique_with(theta, n, dt, "nodal")
}

/// As [`oblique`] with the contact `formulation`.
fn oblique_with(theta: f64, n: usize, dt: f64, formulation: &str) -> Metrics {
    let mut o = Overrides {
        incidence: Some(theta),
        elements: Some(n),
        dt: Some(dt),
        ..Default::default()
    };
    o.options.contact = Some(formulation.into());
    let case = cases::load(Path::new("cases/oblique3d.toml"), &o).unwrap();
    let m = run(case.as_ref()).unwrap().summary.metrics;
    println!(
        "θ = {theta}, n = {n}: e_n {:?}, e_t {:?}, ω' {:?}, J_n {:?}, J_t {:?}, balance {:?}, \
         least ΔW_f {:?}",
        m.restitution_eff,
        m.tangential_restitution,
        m.rebound_spin,
        m.normal_impulse,
        m.tangential_impulse,
        m.friction_balance,
        m.friction_work_min_step
    );
    m
}

/// `|J_t| / (μ J_n)`.
fn slip(m: &Metrics) -> f64 {
    m.tangential_impulse.unwrap().abs() / (MU * m.normal_impulse.unwrap())
}

/// The energy balance `E + W_f = E(0)` and the sign of the friction work. Newmark ½,½ with the
/// mass redistribution conserves the frictionless energy; with friction on the slip increment
/// the balance holds to the step's quadrature of the friction work: measured
/// `max |E + W_f − E(0)|/E(0)` 1.9e-3 (θ = 60°, n = 4) and 4.6e-4 (θ = 10°, n = 8); asserted
/// < 5e-3. No step gives energy back (measured least ΔW_f = 0).
fn balanced(m: &Metrics) {
    let (balance, least) = (
        m.friction_balance.unwrap(),
        m.friction_work_min_step.unwrap(),
    );
    assert!(balance < 5e-3, "E + W_f off E(0) by {balance:e}");
    assert!(least >= -1e-12, "a step gave energy back: {least:e}");
}

/// At θ = 60° (tan θ = 1.73 > 7/2 μ (1 + e) = 0.64) every point of the contact slides forwards
/// throughout: `r_T = −μ r_N` at each, so `|J_t| = μ J_n` up to the steps where an edge point
/// sticks (measured `|J_t|/(μJ_n)` = 0.99933 at n = 4; asserted within 2e-3). Then
/// `e_t = 1 − (m_n/m_t) |J_t|/(μJ_n) · μ(1 + e_n)/tan θ` exactly (J = m Δv; the mass
/// redistribution removes the normal inertia of Γ_C, so m_n < m_t): measured e_n = 0.99630,
/// e_t = 0.89404 against `1 − μ(1 + e_n)/tan θ` = 0.89396 (asserted within 1e-3). The rebound
/// spin follows the rigid sliding `ω'R/V = 5/2 μ(1 + e_n) cos θ` = 0.2296 to the mesh's moment
/// of inertia: measured 0.2374 (+3.4 %; the straight-sided O-grid loses its mass at the surface,
/// where r² is largest), asserted within 5 %.
#[test]
fn at_large_incidence_the_sphere_slides_throughout() {
    let m = oblique(60.0, 4, 0.2);
    let ratio = slip(&m);
    let e_n = m.restitution_eff.unwrap();
    let rigid = Oblique {
        mu: MU,
        incidence: 60f64.to_radians(),
        restitution: e_n,
    };
    assert!(rigid.slides());
    let e_t = m.tangential_restitution.unwrap();
    let spin = m.rebound_spin.unwrap() / 0.01;
    println!(
        "|J_t|/(μJ_n) {ratio:.5}, e_t {e_t:.5} against {:.5}, ω'R/V {spin:.4} against {:.4}",
        rigid.sliding_restitution(),
        rigid.spin()
    );
    assert!((ratio - 1.0).abs() < 2e-3, "|J_t|/(μJ_n) = {ratio}");
    assert!(
        (e_t - rigid.sliding_restitution()).abs() < 1e-3,
        "e_t = {e_t}, sliding {}",
        rigid.sliding_restitution()
    );
    assert!((spin / rigid.spin() - 1.0).abs() < 0.05, "ω'R/V = {spin}");
    assert!(e_n > 0.99 && e_n <= 1.0, "e_n = {e_n}");
    balanced(&m);
}

/// At θ = 10° (ψ₁ = χ tan θ/μ = 1.67, below the rigid sliding threshold θ* = 32.8°) the contact
/// does not slide throughout: measured `|J_t|/(μJ_n)` = 0.53 at n = 8. Then e_t lies in the band
/// [3/7, 1] of tangential compliance: the contact point's tangential velocity changes 7/2 times as
/// much as the centre's, and while it sticks the compliance returns at most the energy it stored,
/// so its final velocity w' ∈ [−w, w] and `e_t = 1 − (1 − w'/w)·2/7 ∈ [3/7, 1]`; and below the
/// rigid stick 5/7 (Maw, Barber & Fawcett: compliance reverses the contact point). Measured
/// e_t = 0.4507 at n = 8, Δt = 0.1 (0.4519 at Δt = 0.05; 0.3978 at n = 4, outside the band: the
/// coarse sphere feeds energy of its vibrations back into the tangential motion); Chung & Ooi's
/// digitised finite element curve gives 0.687 at 10.2° — a plausibility band only.
#[test]
fn at_small_incidence_the_contact_sticks_and_e_t_lies_in_the_compliance_band() {
    let m = oblique(10.0, 8, 0.1);
    let ratio = slip(&m);
    let e_t = m.tangential_restitution.unwrap();
    println!("|J_t|/(μJ_n) {ratio:.4}, e_t {e_t:.4}");
    assert!(ratio < 0.9, "|J_t|/(μJ_n) = {ratio}: it slid throughout");
    assert!(
        (STICK_BAND.0..=STICK_BAND.1).contains(&e_t),
        "e_t = {e_t} outside [3/7, 1]"
    );
    assert!(e_t < 5.0 / 7.0, "e_t = {e_t} above the rigid stick");
    balanced(&m);
}

/// The report's Moreau–Jean runs (the case's `oblique` sweep: θ = ½, n = 4, Δt = 0.2) slide
/// throughout at 60° like the position-level schemes: `|J_t| = μ J_n` (measured 0.9995 standard,
/// 0.9993 mass redistribution; asserted within 2e-2), the sphere rebounds (e_n 1.0006 and
/// 0.9953) and e_t follows the rigid slide `1 − μ(1 + e_n)/tan θ` (measured within 1.2e-4;
/// asserted within 1e-3). They take e = 0 at the nodes: with e = 1 (the sweep's choice before)
/// the standard mass gives `|J_t|/(μJ_n)` = 0.40 (asserted < 0.5: the flipping nodal velocities
/// of [`dyncontact::time::moreau_jean`]) and the sphere passes through the plane with the mass
/// redistribution (e_n = −0.986).
#[test]
fn moreau_jean_slides_throughout_at_large_incidence() {
    let path = Path::new("cases/oblique3d.toml");
    let case = cases::load(path, &Overrides::default()).unwrap();
    let sweep = case.sweeps().iter().find(|s| s.name == "oblique").unwrap();
    let choice = sweep
        .schemes
        .iter()
        .find(|c| c.scheme == "moreau_jean")
        .unwrap();
    let level = sweep.refinements(false).unwrap()[0];
    let metrics = |space: &str, restitution: Option<f64>| {
        let mut o = Overrides {
            incidence: Some(60.0),
            ..sweep.overrides(space, choice, level)
        };
        if let Some(e) = restitution {
            o.options.params.set("restitution", e);
        }
        let m = run(cases::load(path, &o).unwrap().as_ref())
            .unwrap()
            .summary
            .metrics;
        println!(
            "{space}, e = {restitution:?}: |J_t|/(μJ_n) {:.4}, e_n {:?}, e_t {:?}",
            slip(&m),
            m.restitution_eff,
            m.tangential_restitution
        );
        m
    };
    for space in &sweep.spaces {
        let m = metrics(space, None);
        let e_n = m.restitution_eff.unwrap();
        let rigid = Oblique {
            mu: MU,
            incidence: 60f64.to_radians(),
            restitution: e_n,
        };
        let e_t = m.tangential_restitution.unwrap();
        assert!(
            (slip(&m) - 1.0).abs() < 2e-2,
            "{space}: |J_t|/(μJ_n) = {}",
            slip(&m)
        );
        assert!(e_n > 0.99 && e_n < 1.01, "{space}: e_n = {e_n}");
        assert!(
            (e_t - rigid.sliding_restitution()).abs() < 1e-3,
            "{space}: e_t = {e_t}, sliding {}",
            rigid.sliding_restitution()
        );
    }
    let bouncing = metrics("standard", Some(1.0));
    assert!(
        slip(&bouncing) < 0.5,
        "e = 1: |J_t|/(μJ_n) = {}",
        slip(&bouncing)
    );
}

/// `--incidence` turns the speed, keeps it, and is refused where it means nothing.
#[test]
fn incidence_turns_the_velocity_and_is_refused_elsewhere() {
    let load = |path: &str, theta: f64| {
        cases::load(
            Path::new(path),
            &Overrides {
                incidence: Some(theta),
                ..Default::default()
            },
        )
    };
    for (path, theta) in [
        ("cases/oblique3d.toml", 90.0),
        ("cases/oblique3d.toml", -1.0),
        ("cases/bar1d.toml", 30.0),
        ("cases/roll2d.toml", 30.0),
    ] {
        let Err(e) = load(path, theta) else {
            panic!("{path}: --incidence {theta} accepted");
        };
        assert!(e.to_string().contains("--incidence"), "{path}: {e}");
    }
    let case = load("cases/oblique3d.toml", 30.0).unwrap();
    let space = dyncontact::space::by_name("standard").unwrap();
    let p = case.problem(space.as_ref()).unwrap();
    let v =
        p.v0.iter()
            .fold((0.0f64, 0.0f64), |a, &x| (a.0.max(x), a.1.min(x)));
    println!("velocities {v:?}");
    assert!((v.0 - 0.005).abs() < 1e-12 && (v.1 + 0.01 * 30f64.to_radians().cos()).abs() < 1e-12);
}

/// Nitsche's friction (the disc projection at the quadrature points of the sphere's Γ_C) on the
/// oblique impact, against the nodal contact on the same mesh: at 60° (n = 4, Δt = 0.2) the
/// sphere slides throughout (`|J_t|/(μJ_n)` measured 0.99953, nodal 0.99933; asserted within
/// 2e-3 of 1) with e_t 0.89393 against the nodal run's 0.89403 (asserted within 1e-3), the energy
/// balance 2.0e-3 (nodal 1.9e-3) and no step giving energy back. At 10° (n = 8, Δt = 0.1: about
/// 230 s CPU with Nitsche, not run here) the contact sticks as the nodal one: `|J_t|/(μJ_n)`
/// 0.508 (nodal 0.528), e_t 0.4712 (nodal 0.4507), both in the compliance band and below 5/7.
#[test]
fn nitsche_friction_slides_as_the_nodal_contact_at_large_incidence() {
    let (a, b) = (
        oblique_with(60.0, 4, 0.2, "nitsche"),
        oblique_with(60.0, 4, 0.2, "nodal"),
    );
    let (ra, rb) = (slip(&a), slip(&b));
    let (ea, eb) = (
        a.tangential_restitution.unwrap(),
        b.tangential_restitution.unwrap(),
    );
    println!("|J_t|/(μJ_n) {ra:.5} (nodal {rb:.5}), e_t {ea:.5} (nodal {eb:.5})");
    assert!((ra - 1.0).abs() < 2e-3, "|J_t|/(μJ_n) = {ra}");
    assert!((ea - eb).abs() < 1e-3, "e_t {ea}, nodal {eb}");
    balanced(&a);
}
