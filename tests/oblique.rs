//! Oblique impact of an elastic sphere with Coulomb friction (issue 25 §2, `cases/oblique3d.toml`:
//! R = 1, E = ρ = 1, ν = 0.23, μ = 0.092, speed V = 0.01, mass redistribution + Newmark ½,½)
//! against the limits that hold exactly ([`dyncontact::exact::oblique`]): gross slip at large
//! incidence, `|J_t| < μ J_n` and the compliance band at small incidence, the energy balance.
//! Run with `-- --nocapture` to see the measured numbers quoted in the doc comments.

use dyncontact::cases::{self, Overrides};
use dyncontact::exact::hertz::DURATION_FACTOR;
use dyncontact::exact::mbf::{linear_oscillator, Mbf, Rebound, Resolution, REPORT_RESOLUTION};
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
    oblique_in(Path::new("cases/oblique3d.toml"), theta, n, dt, formulation)
}

/// [`oblique_with`] of the case file `path`.
fn oblique_in(path: &Path, theta: f64, n: usize, dt: f64, formulation: &str) -> Metrics {
    let mut o = Overrides {
        incidence: Some(theta),
        elements: Some(n),
        dt: Some(dt),
        ..Default::default()
    };
    o.options.contact = Some(formulation.into());
    let case = cases::load(path, &o).unwrap();
    let m = run(case.as_ref()).unwrap().summary.metrics;
    println!(
        "{}: θ = {theta}, n = {n}: e_n {:?}, e_t {:?}, ω' {:?}, J_n {:?}, J_t {:?}, balance {:?}, \
         least ΔW_f {:?}",
        path.display(),
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
/// throughout at 60° like the position-level schemes: `|J_t| = μ J_n` (measured 0.9995 standard;
/// 0.9993 with the mass redistribution, which θ = ½ now refuses: its contact dofs have no
/// inertia; asserted within 2e-2), the sphere rebounds (e_n 1.0006; 0.9953) and e_t follows the rigid slide `1 − μ(1 + e_n)/tan θ` (measured within 1.2e-4;
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
        if space == "mass_redistribution" {
            let mut o = sweep.overrides(space, choice, level);
            o.incidence = Some(60.0);
            let e = run(cases::load(path, &o).unwrap().as_ref()).unwrap_err();
            assert!(
                e.to_string().contains("needs inertia at the contact dofs"),
                "{e}"
            );
            continue;
        }
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

/// Chung & Ooi's aluminium oxide in the case's units (R = E = ρ = 1, V = 0.01), computed by the
/// method of dimensionality reduction ([`dyncontact::exact::mbf`]).
fn alumina() -> Mbf {
    Mbf::sphere(1.0, 1.0, 1.0, 0.23, MU).unwrap()
}

const SPEED: f64 = 0.01;

fn mbf(s: &Mbf, degrees: f64, res: Resolution) -> Rebound {
    let r = s.impact(SPEED, degrees.to_radians(), res).unwrap();
    println!(
        "MBF θ = {degrees}°, κ = {:.4}, ψ₁ = {:.3}: e_n {:.8}, e_t {:.7}, w'/w {:.7}, \
         |J_t|/(μJ_n) {:.6}",
        s.kappa(),
        s.psi(degrees.to_radians()),
        r.normal_restitution,
        r.tangential_restitution,
        r.contact_point,
        r.tangential_impulse.abs() / (s.mu * r.normal_impulse)
    );
    r
}

/// The MDR reference is converged: doubling its steps and springs changes e_t by at most 4.7e-8
/// and w'/w by 1.7e-7 at 5°, 10°, 20° (measured; asserted < 1e-4). Its normal impact is
/// Hertz's: e_n = 1 within 5e-9 (velocity Verlet on `m δ̈ = −F_n`; asserted 1e-6), the contact
/// time within one step (asserted 2/steps) of `t_c = 2.9433 δ_max/v_n`, and
/// `J_n = m (1 + e_n) v_n` to round-off.
#[test]
fn mbf_reference_is_hertz_normally_and_converged() {
    let s = alumina();
    let fine = Resolution {
        steps: 2 * REPORT_RESOLUTION.steps,
        springs: 2 * REPORT_RESOLUTION.springs,
    };
    for degrees in [5.0, 10.0, 20.0] {
        let (a, b) = (mbf(&s, degrees, REPORT_RESOLUTION), mbf(&s, degrees, fine));
        let d = (a.tangential_restitution - b.tangential_restitution).abs();
        let dw = (a.contact_point - b.contact_point).abs();
        println!("θ = {degrees}°: |Δe_t| {d:.1e}, |Δw'/w| {dw:.1e}");
        assert!(d < 1e-4 && dw < 1e-4, "θ = {degrees}°: not converged");
        let vn = SPEED * degrees.to_radians().cos();
        let hertz = s.hertz(vn);
        let tc = DURATION_FACTOR * hertz.max_approach().unwrap() / vn;
        assert!(
            (a.normal_restitution - 1.0).abs() < 1e-6,
            "e_n {}",
            a.normal_restitution
        );
        assert!(
            (a.duration / tc - 1.0).abs() < 2.0 / REPORT_RESOLUTION.steps as f64,
            "t_c {} against {tc}",
            a.duration
        );
        let momentum = s.mass * (1.0 + a.normal_restitution) * vn;
        assert!((a.normal_impulse / momentum - 1.0).abs() < 1e-12);
    }
}

/// Gross slip: every spring slides at its bound throughout, so `|J_t| = μ J_n` (the springs'
/// midpoint sum against Hertz's closed form: measured within 8.9e-11 at 30°, 40°, 60°) and
/// `e_t = 1 − μ(1 + e_n)/tan θ` (within 2e-11); asserted 1e-8. MBF's compliant contact slides
/// throughout from a smaller incidence than the rigid body's threshold 32.8°: at 30° (ψ₁ = 5.5)
/// already, where the rigid body sticks.
#[test]
fn mbf_reference_slides_throughout_at_large_incidence() {
    let s = alumina();
    for degrees in [30.0, 40.0, 60.0] {
        let r = mbf(&s, degrees, REPORT_RESOLUTION);
        let ratio = r.tangential_impulse.abs() / (s.mu * r.normal_impulse);
        println!("θ = {degrees}°: |J_t|/(μJ_n) − 1 = {:.1e}", ratio - 1.0);
        let rigid = Oblique {
            mu: MU,
            incidence: degrees.to_radians(),
            restitution: r.normal_restitution,
        };
        if degrees < 32.0 {
            assert!(!rigid.slides() && ratio > 0.9999, "θ = {degrees}°: {ratio}");
            continue;
        }
        assert!(
            (ratio - 1.0).abs() < 1e-5,
            "θ = {degrees}°: |J_t|/(μJ_n) {ratio}"
        );
        let off = r.tangential_restitution - rigid.sliding_restitution();
        println!("θ = {degrees}°: e_t − (1 − μ(1 + e_n)/tan θ) = {off:.1e}");
        assert!(
            off.abs() < 1e-8,
            "θ = {degrees}°: e_t {}",
            r.tangential_restitution
        );
    }
}

/// `G* → ∞` with μ = 1 (θ = 20°, far below the sliding threshold): the contact point stops
/// early and the springs, held within `|u| ≤ μ (E*/G*)(δ − x²/R)`, store at most
/// `E_s = ½ (μE*)²/G* ∫ (δ_max − x²/R)² dx = 8/15 (μE*)² δ_max² a_max / G*`, all they can give
/// back, so `|w'| ≤ √(2 E_s/m_c)` with `m_c = m/(1 + mR²/I)` and
/// `|e_t − 5/7| = 2/7 |w'|/v_t`: the rigid stick. Measured e_t − 5/7 = −1.5e-2, +1.4e-3,
/// −5e-6 at G*/E* = 100, 1000, 10000 against bounds 0.15, 0.047, 0.015.
#[test]
fn mbf_reference_sticks_rigidly_as_the_tangential_stiffness_grows() {
    let theta = 20f64.to_radians();
    let vt = SPEED * theta.sin();
    for (ratio, steps) in [(100.0, 16_000), (1000.0, 64_000), (10_000.0, 200_000)] {
        let base = alumina();
        let s = Mbf {
            mu: 1.0,
            g_star: ratio * base.e_star,
            ..base
        };
        let r = mbf(
            &s,
            20.0,
            Resolution {
                steps,
                springs: 1000,
            },
        );
        let vn = SPEED * theta.cos();
        let hertz = s.hertz(vn);
        let dmax = hertz.max_approach().unwrap();
        let stored =
            8.0 / 15.0 * (s.mu * s.e_star).powi(2) * dmax.powi(2) * (s.radius * dmax).sqrt()
                / s.g_star;
        let bound = 2.0 / 7.0 * (2.0 * stored * s.contact_factor() / s.mass).sqrt() / vt;
        let off = r.tangential_restitution - 5.0 / 7.0;
        println!("G*/E* = {ratio}: e_t − 5/7 = {off:.2e}, bound {bound:.3}");
        assert!(off.abs() <= bound, "G*/E* = {ratio}: e_t − 5/7 = {off}");
    }
}

/// Small incidence: the contact sticks and the problem is linear in w, so w'/w depends only on
/// `κ = (1 + mR²/I) G*/E*`. Measured (μ = 10⁶, i.e. ψ₁ → 0): w'/w = 0.296200 at κ = 3.045
/// (ν = 0.23) at 1° and 10°, and the same for ν = 0.1 with I/(mR²) chosen for the same κ (asserted
/// within 1e-6); with μ = 0.092 it tends to that as θ → 0 (0.1°: 0.2927; asserted within 5e-3).
/// The linear-oscillator estimate cos(π√κ) = 0.696 is far from it; at κ = 1 it is exact:
/// the tangential problem is the normal one scaled by w/v_n, so w' = −w whenever ψ₁ ≤ 1, with
/// μ = 0.092 at 10° (ψ₁ = 0.55; measured w'/w + 1 = 3e-10, asserted 1e-6) and no slip.
#[test]
fn mbf_reference_at_small_incidence_depends_only_on_kappa() {
    let base = alumina();
    let stuck = Mbf { mu: 1e6, ..base };
    let f = mbf(&stuck, 1.0, REPORT_RESOLUTION).contact_point;
    assert!((mbf(&stuck, 10.0, REPORT_RESOLUTION).contact_point - f).abs() < 1e-6);
    let other = Mbf::sphere(1.0, 1.0, 1.0, 0.1, 1e6).unwrap();
    let chi = other.g_star / other.e_star;
    let same = Mbf {
        inertia: 1.0 / (base.kappa() / chi - 1.0),
        ..other
    };
    assert!((same.kappa() - base.kappa()).abs() < 1e-12);
    assert!((mbf(&same, 5.0, REPORT_RESOLUTION).contact_point - f).abs() < 1e-6);
    let small = mbf(&base, 0.1, REPORT_RESOLUTION).contact_point;
    assert!((small - f).abs() < 5e-3, "0.1°: {small} against {f}");
    println!(
        "κ = {:.4}: w'/w {f:.6}, cos(π√κ) {:.6}",
        base.kappa(),
        linear_oscillator(base.kappa())
    );
    let unit = Mbf {
        g_star: base.e_star / base.contact_factor(),
        ..base
    };
    assert!((unit.kappa() - 1.0).abs() < 1e-12);
    let r = mbf(&unit, 10.0, REPORT_RESOLUTION);
    assert!(unit.psi(10f64.to_radians()) < 1.0);
    assert!(
        (r.contact_point - linear_oscillator(1.0)).abs() < 1e-6,
        "κ = 1: {}",
        r.contact_point
    );
}

/// The case file `src` with the lines of `changes` (key, replacement lines) rewritten, as `name`
/// in `dir`.
fn rewritten(dir: &Path, src: &str, name: &str, changes: &[(&str, String)]) -> std::path::PathBuf {
    let text = std::fs::read_to_string(src).unwrap();
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            let key = l.split(" =").next().unwrap_or("");
            changes
                .iter()
                .find(|c| c.0 == key)
                .map_or_else(|| l.to_string(), |c| c.1.clone())
        })
        .collect();
    let path = dir.join(name);
    std::fs::write(&path, lines.join("\n")).unwrap();
    path
}

/// `cases/oblique3d.toml` at speed V (towards the plane; `--incidence` turns it) with its cap
/// `facing`, written into `dir`.
fn at_speed(dir: &Path, speed: f64, facing: f64) -> std::path::PathBuf {
    rewritten(
        dir,
        "cases/oblique3d.toml",
        &format!("oblique3d_{speed}.toml"),
        &[
            ("velocity", format!("velocity = {}", -speed)),
            ("tangential_velocity", "tangential_velocity = 0.0".into()),
            ("facing", format!("facing = {facing}")),
        ],
    )
}

/// Why the finite elements stick below MBF (issue 25 §2): MBF is quasi-static, the finite element
/// sphere is not. At 10° with the contact radius over the pole spacing about 6 (V = 0.03, n = 8,
/// a larger cap; V = 0.01, n = 12) e_t is 0.388 and 0.471 against MBF's 0.640: the gap
/// shrinks by 1.49 as V/c falls by 3, close to `(V/c)^{2/5}` = (transit time/contact time)²,
/// the size of the sphere's own vibration against the contact's. Asserted: e_t rises towards
/// MBF and the gap shrinks by more than 1.2. About 31 s CPU: run with `--ignored`. Measured with
/// `dyncontact run` at a/h ≈ 4 (a larger cap at V = 0.03): V = 0.03, 0.01, 0.003, 0.001 with
/// n = 5, 8, 12, 20 give e_t = 0.362, 0.451, 0.507, 0.540 (the last 130 s CPU, 2.6 GB), gaps
/// to MBF 0.278, 0.189, 0.133, 0.100: as `V^0.3`. Chung & Ooi's V/c is 25 times ours.
#[test]
#[ignore]
fn the_stick_regime_approaches_mbf_as_the_impact_slows() {
    let dir = tempfile::tempdir().unwrap();
    let fast = oblique_in(&at_speed(dir.path(), 0.03, 0.89), 10.0, 8, 0.1, "nodal");
    let slow = oblique_in(&at_speed(dir.path(), 0.01, 0.95), 10.0, 12, 0.1, "nodal");
    let theory = mbf(&alumina(), 10.0, REPORT_RESOLUTION).tangential_restitution;
    let (a, b) = (
        fast.tangential_restitution.unwrap(),
        slow.tangential_restitution.unwrap(),
    );
    println!("e_t {a:.4} (V = 0.03), {b:.4} (V = 0.01), MBF {theory:.4}");
    assert!(a < b && b < theory, "e_t {a}, {b} against MBF {theory}");
    assert!((theory - a) / (theory - b) > 1.2);
}

/// The rest of the gap at small incidence is Poisson coupling, which MBF leaves out (Dundurs'
/// β = 0) and an elastic sphere on a rigid plane has (β = 0.35 at ν = 0.23). Two equal spheres
/// (`cases/two_spheres.toml` with ν = 0.23, μ = 0.092, n = 8) have β = 0 and, in their centre of
/// mass frame, each is the sphere on the plane at V = 0.01, θ = 10° (body 1 at `−v_n` and `2 v_t`,
/// body 2 at `+v_n`; the same κ, time and length scales): e_t = 0.533 against the plane's 0.451
/// and MBF's 0.640 (n = 12: 0.553 and 0.471). Measured with `dyncontact run` at 5° and 20°:
/// 0.575 against 0.447, and 0.537 against 0.548: coupling matters where the tangential energy
/// is small (a frictional normal impact dissipates 0.7 % of E(0) by radial microslip; the
/// tangential energy is 0.8 % of it at 5°, 3 % at 10°, 12 % at 20°). Asserted at 10°: the pair
/// above the plane by more than 0.05 and below MBF. About 10 s CPU: run with `--ignored`.
#[test]
#[ignore]
fn without_poisson_coupling_the_stick_regime_is_nearer_mbf() {
    let dir = tempfile::tempdir().unwrap();
    let theta = 10f64.to_radians();
    let (vn, vt) = (SPEED * theta.cos(), SPEED * theta.sin());
    let pair = rewritten(
        dir.path(),
        "cases/two_spheres.toml",
        "pair.toml",
        &[
            ("poisson", "poisson = 0.23".into()),
            (
                "velocity",
                format!("velocity = {}\ntangential_velocity = {}", -vn, 2.0 * vt),
            ),
            ("facing", format!("facing = 0.95\nfriction = {MU}")),
        ],
    );
    let o = Overrides {
        elements: Some(8),
        dt: Some(0.1),
        t_end: Some(30.0),
        ..Default::default()
    };
    let rows = run(cases::load(&pair, &o).unwrap().as_ref()).unwrap().rows;
    let (first, last) = (
        rows[0].friction.unwrap().0,
        rows[rows.len() - 1].friction.unwrap().0,
    );
    assert_eq!(rows[rows.len() - 1].force_contact, 0.0, "still in contact");
    // Body 1's tangential velocity in the centre of mass frame (equal masses): v − v₀/2.
    let e_t = (last - 0.5 * first) / (0.5 * first);
    let plane = oblique(10.0, 8, 0.1).tangential_restitution.unwrap();
    let theory = mbf(&alumina(), 10.0, REPORT_RESOLUTION).tangential_restitution;
    println!("e_t: pair {e_t:.4}, plane {plane:.4}, MBF {theory:.4}");
    assert!(
        e_t > plane + 0.05 && e_t < theory,
        "pair {e_t}, plane {plane}, MBF {theory}"
    );
}

/// The impulses and restitutions of an oblique impact are the momentum the contact changed, so
/// they hold no load's: disc2d (GetFEM's disc, gravity 0.1) thrown at v = (0.5, −1) with μ = 0.3
/// and released by T gave `normal_impulse` 2 494 at T = 24 and 1 740 at T = 30 (gravity's
/// impulse m g T taken for the contact's) and a centre-of-mass restitution 0.985 and 0.385.
/// Under a load they are now absent, whatever T, and `restitution_eff` is the probe's.
#[test]
fn a_body_under_gravity_has_no_oblique_impulses() {
    let text = std::fs::read_to_string("cases/disc2d.toml").unwrap();
    let thrown = text
        .replacen(
            "velocity = 0.0\n",
            "velocity = -1.0\ntangential_velocity = 0.5\n",
            1,
        )
        .replacen("[mesh]", "[contact]\nfriction = 0.3\n\n[mesh]", 1);
    let at = |t_end: f64| {
        let o = Overrides {
            t_end: Some(t_end),
            ..Default::default()
        };
        let case = cases::parse(&thrown, Path::new("cases/x.toml"), &o).unwrap();
        run(case.as_ref()).unwrap().summary.metrics
    };
    let (early, late) = (at(24.0), at(30.0));
    for m in [&early, &late] {
        let oblique = [
            m.tangential_restitution,
            m.rebound_spin,
            m.normal_impulse,
            m.tangential_impulse,
        ];
        assert!(oblique.iter().all(Option::is_none), "{oblique:?}");
    }
    assert_eq!(early.restitution_eff, late.restitution_eff);
}
