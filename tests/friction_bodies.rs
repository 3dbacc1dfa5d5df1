//! Coulomb friction between two bodies (issue 25 §1) on `cases/slide_on_block2d.toml`: a block
//! (1 × ½, m₁ = ½) launched at v₀ = 0.1 on a block (2 × ½, m₂ = 1) that rests on a frictionless
//! rigid plane, both under g = 1, μ = 0.25 between them, node-to-segment rows on non-matching
//! meshes. The rigid bodies ([`dyncontact::exact::slide::SlideOnBlock`]): the top decelerates at
//! μ g = 0.25, the bottom accelerates at μ g m₁/m₂ = 0.125, they stick at t* = 0.2667 and move on
//! at 1/30; tangential momentum m₁ v₀ conserved; W_f = ½ m* v₀² = 1/600 by t*. Run with
//! `-- --nocapture` to see the measured numbers quoted in the doc comments.

use dyncontact::cases::{self, Overrides};
use dyncontact::exact::slide::{Slide, SlideOnBlock};
use std::path::Path;

const EXACT: SlideOnBlock = SlideOnBlock {
    top: Slide {
        speed: 0.1,
        gravity: 1.0,
        mu: 0.25,
    },
    masses: [0.5, 1.0],
};

/// `cases/slide_on_block3d.toml`: the same in 3D, m₂ = 2.
const EXACT_3D: SlideOnBlock = SlideOnBlock {
    masses: [0.5, 2.0],
    ..EXACT
};

const CASE_2D: &str = "cases/slide_on_block2d.toml";

/// One step's state: `t`, the blocks' centre-of-mass velocities along e_1 `(M̃1_b)ᵀV / 1_bᵀM̃1_b`
/// with the space's own mass, the total tangential momentum `Σ_b (M̃1_b)ᵀV`, E and W_f.
#[derive(Debug, Clone, Copy)]
struct Sample {
    t: f64,
    v: [f64; 2],
    momentum: f64,
    energy: f64,
    work: f64,
}

/// Every step of the 2D case with `space`, `scheme` and the overrides `set`.
fn samples(
    space: &str,
    scheme: &str,
    set: impl Fn(&mut Overrides),
) -> dyncontact::Result<Vec<Sample>> {
    samples_of(CASE_2D, space, scheme, set)
}

/// Every step of the case `file` with `space`, `scheme` and the overrides `set`.
fn samples_of(
    file: &str,
    space: &str,
    scheme: &str,
    set: impl Fn(&mut Overrides),
) -> dyncontact::Result<Vec<Sample>> {
    let mut o = Overrides {
        space: Some(space.into()),
        scheme: Some(scheme.into()),
        degree: (space == "singular_dynamic").then_some(2),
        ..Default::default()
    };
    set(&mut o);
    let case = cases::load(Path::new(file), &o)?;
    let spec = case.run();
    let space = dyncontact::space::by_name(&spec.space)?;
    let mut problem = case.problem(space.as_ref())?;
    let n = problem.n();
    let formulation = dyncontact::contact::formulation(&spec.options)?;
    dyncontact::time::check_friction(&problem, scheme_of(spec)?.as_ref(), formulation.as_ref())?;
    // The top block's translation is the friction's; the bottom's, the rest of e_1 (every dof
    // free: component 0 at the dofs j with j mod d = 0).
    let friction = problem
        .contact
        .friction
        .as_ref()
        .expect("slide_on_block has friction");
    let (d, top) = (friction.tangents + 1, friction.translation.clone());
    let bottom: Vec<f64> = (0..n).map(|j| f64::from(j % d == 0) - top[j]).collect();
    let weights: Vec<(Vec<f64>, f64)> = [top, bottom]
        .into_iter()
        .map(|one| {
            let mut m1 = vec![0.0; n];
            let inertial = problem.inertia.project(&one).unwrap();
            problem.inertia.apply_add(&mut m1, &inertial, 1.0);
            let mass = m1.iter().zip(&one).map(|(a, b)| a * b).sum();
            (one, mass)
        })
        .collect();
    let solver = formulation.setup(&mut problem, spec.options.contact_solver_with(true))?;
    let mut it = scheme_of(spec)?.prepare(&problem, spec.dt, solver.into())?;
    let mut energy = problem.energy_form();
    let mut mv = vec![0.0; n];
    let mut out = Vec::new();
    for step in 0..=spec.steps() {
        let s = it.state();
        mv.fill(0.0);
        problem.inertia.apply_add(&mut mv, s.v, 1.0);
        let p = |one: &[f64]| one.iter().zip(&mv).map(|(a, b)| a * b).sum::<f64>();
        out.push(Sample {
            t: s.t,
            v: std::array::from_fn(|b| p(&weights[b].0) / weights[b].1),
            momentum: p(&weights[0].0) + p(&weights[1].0),
            energy: energy.energy(s.energy_u, s.v) + s.extra_energy,
            work: s.friction_work,
        });
        if step < spec.steps() {
            it.step()?;
        }
    }
    Ok(out)
}

fn scheme_of(
    spec: &dyncontact::cases::RunSpec,
) -> dyncontact::Result<Box<dyn dyncontact::time::Scheme>> {
    dyncontact::time::by_name(&spec.scheme, spec.params())
}

/// What a run measures against the rigid bodies.
#[derive(Debug)]
struct Measured {
    /// `max |v_b − v_b,rigid|` over the slip (t ≤ t* − 0.02) and after it (t ≥ t* + 0.05).
    slip: [f64; 2],
    stuck: [f64; 2],
    /// `max |P − P₀| / P₀` of the tangential momentum.
    momentum: f64,
    /// The first sample with `v₁ − v₂ ≤ 0.01 v₀`.
    stick: f64,
    /// `W_f` at the end, the least increment of a step, `max |E + W_f − E₀| / E₀`.
    work: f64,
    least_increment: f64,
    balance: f64,
    /// The largest increase of `E + W_f` in a step, over E₀.
    rise: f64,
}

fn measure(s: &[Sample]) -> Measured {
    measure_against(&EXACT, s)
}

fn measure_against(exact: &SlideOnBlock, s: &[Sample]) -> Measured {
    let t_star = exact.stick_time();
    let worst = |range: &dyn Fn(f64) -> bool, b: usize| {
        s.iter()
            .filter(|x| range(x.t))
            .map(|x| (x.v[b] - exact.velocities(x.t)[b]).abs())
            .fold(0.0, f64::max)
    };
    let sliding = |t: f64| t <= t_star - 0.02;
    let stuck = |t: f64| t >= t_star + 0.05;
    let p0 = s[0].momentum;
    Measured {
        slip: [worst(&sliding, 0), worst(&sliding, 1)],
        stuck: [worst(&stuck, 0), worst(&stuck, 1)],
        momentum: s
            .iter()
            .map(|x| (x.momentum - p0).abs() / p0)
            .fold(0.0, f64::max),
        stick: s
            .iter()
            .find(|x| x.v[0] - x.v[1] <= 0.01 * exact.top.speed)
            .map_or(f64::NAN, |x| x.t),
        work: s.last().map_or(f64::NAN, |x| x.work),
        least_increment: s
            .windows(2)
            .map(|w| w[1].work - w[0].work)
            .fold(f64::INFINITY, f64::min),
        balance: s
            .iter()
            .map(|x| (x.energy + x.work - s[0].energy).abs() / s[0].energy)
            .fold(0.0, f64::max),
        rise: s
            .windows(2)
            .map(|w| (w[1].energy + w[1].work - w[0].energy - w[0].work) / s[0].energy)
            .fold(f64::NEG_INFINITY, f64::max),
    }
}

/// The bound on the velocity errors while they slip: both blocks start undeformed and fall
/// freely until the plane's reaction has crossed the bottom block and the interface's the top
/// (H₁ + H₂ = 1 at c_p = √((λ + 2G)/ρ) = 116), so the friction force lags μ m₁ g by at most that
/// long: `|v₁ − v₁,rigid| ≤ μ g (H₁ + H₂)/c_p = 2.15e-3`, and the bottom's m₁/m₂ of it.
fn lag() -> f64 {
    let c_p = (1e4 * 0.7 / (1.3 * 0.4_f64)).sqrt();
    EXACT.top.deceleration() * 1.0 / c_p
}

/// Backward Euler, standard mass (the case's defaults) against the rigid bodies. Measured: while
/// they slip |v₁ − v₁,rigid| ≤ 1.22e-3 and |v₂ − v₂,rigid| ≤ 6.1e-4 (bound 2.15e-3 and 1.08e-3);
/// they stick at t = 0.264 (first v₁ − v₂ ≤ 0.01 v₀; t* = 0.2667) and move on at 1/30 to 3.6e-4
/// (their elastic vibration; asserted 0.01 v₀); the tangential momentum is kept to 1.0e-11
/// (relative; the solver's tolerance); W_f never decreases (least increment 0) and ends at
/// 1.6513e-3 (−0.9 % of ½ m* v₀² = 1/600: what backward Euler dissipates of the tangential
/// vibration); `E + W_f` never rises in a step (largest change −4.9e-9 E₀) and loses 1.26 % of E₀
/// by t = 0.5 (the scheme's dissipation of the vibration the weight sets off).
#[test]
fn a_block_slides_on_a_block_against_the_rigid_bodies() {
    let s = samples("standard", "backward_euler", |_| {}).unwrap();
    let m = measure(&s);
    println!("{m:?}");
    assert!(m.slip[0] < lag() && m.slip[1] < lag() * 0.5, "{m:?}");
    assert!(m.stuck[0] < 1e-3 && m.stuck[1] < 1e-3, "{m:?}");
    assert!((m.stick - EXACT.stick_time()).abs() < 0.01, "{m:?}");
    assert!(m.momentum < 1e-9, "{m:?}");
    assert!(m.least_increment >= -1e-15, "{m:?}");
    assert!(
        (m.work - EXACT.work(1.0)).abs() < 0.02 * EXACT.work(1.0),
        "{m:?}"
    );
    assert!(m.rise <= 1e-12 && m.balance < 0.02, "{m:?}");
}

/// In 3D (`cases/slide_on_block3d.toml`, two tangents per point, m₂ = 2: t* = 0.32, common
/// velocity 0.02, W_f = 0.002), backward Euler on the standard mass. Measured: while they slip
/// the top is off by 1.18e-3 and the bottom by 3.0e-4 (bound 2.15e-3 and m₁/m₂ of it), after
/// t* by 2.5e-4 and 6e-5; they stick at t = 0.318; the momentum is kept to 2.9e-12; W_f never
/// decreases and ends at 1.985e-3 (−0.8 %); `E + W_f` never rises in a step.
#[test]
fn the_3d_block_slides_on_its_block_as_the_2d_one() {
    let s = samples_of(
        "cases/slide_on_block3d.toml",
        "standard",
        "backward_euler",
        |_| {},
    )
    .unwrap();
    let m = measure_against(&EXACT_3D, &s);
    println!("3D: {m:?}");
    assert!(m.slip[0] < lag() && m.slip[1] < lag() * 0.25, "{m:?}");
    assert!(m.stuck[0] < 1e-3 && m.stuck[1] < 1e-3, "{m:?}");
    assert!((m.stick - EXACT_3D.stick_time()).abs() < 0.01, "{m:?}");
    assert!(m.momentum < 1e-9, "{m:?}");
    assert!(m.least_increment >= -1e-15, "{m:?}");
    assert!(
        (m.work - EXACT_3D.work(1.0)).abs() < 0.02 * EXACT_3D.work(1.0),
        "{m:?}"
    );
    assert!(m.rise <= 1e-12, "{m:?}");
}

/// Every space × scheme that takes friction at the plane runs here; every other scheme is
/// refused as at the plane. On every run the tangential momentum is kept to 1e-9 (measured
/// ≤ 6.1e-11) and the friction work never decreases (measured least increment −4.3e-19). The
/// spaces that keep the tangential inertia with the position-level schemes follow the rigid
/// slide within the lag bound (measured ≤ 1.74e-3 on the top block); mass elimination drops the
/// interface and plane elements' mass in every component and slides off by 1.6e-2 (top) and
/// 3.6e-2 (bottom), as at the plane (`tests/friction.rs`); the singular dynamic method (P2)
/// 2.3e-3; Moreau–Jean (θ = ½) on the standard and lumped mass 2.2e-3 and 1.9e-3. It was
/// unstable on the spaces without inertia at the contact dofs (`E + W_f` off by 7.8, 1.1e3 and
/// 25 × E₀ on mass redistribution, mass elimination and the singular dynamic method), as under
/// gravity at the plane: θ = ½ is refused there ([`dyncontact::time::moreau_jean`]).
#[test]
fn every_space_and_friction_scheme_slides_on_the_block() {
    for scheme in ["backward_euler", "newmark", "hht", "moreau_jean"] {
        for space in [
            "standard",
            "lumped",
            "mass_redistribution",
            "mass_elimination",
            "singular_dynamic",
        ] {
            let ran = samples(space, scheme, |_| {});
            if scheme == "moreau_jean" && !["standard", "lumped"].contains(&space) {
                let e = ran.unwrap_err();
                assert!(
                    matches!(e, dyncontact::Error::Unsupported(_)),
                    "{space}: {e}"
                );
                continue;
            }
            let m = measure(&ran.unwrap());
            println!("{scheme} {space}: {m:?}");
            assert!(m.momentum < 1e-9, "{scheme} {space}: {m:?}");
            assert!(m.least_increment >= -1e-15, "{scheme} {space}: {m:?}");
            let keeps = ["standard", "lumped", "mass_redistribution"].contains(&space);
            if keeps && scheme != "moreau_jean" {
                assert!(m.slip[0] < lag(), "{scheme} {space}: {m:?}");
            }
        }
    }
    for scheme in [
        "central_difference",
        "paoli_schatzman",
        "carpenter",
        "laursen_chawla",
    ] {
        let e = samples("lumped", scheme, |_| {}).unwrap_err();
        assert!(
            matches!(e, dyncontact::Error::Unsupported(_)) && e.to_string().contains(scheme),
            "{e}"
        );
    }
}

/// The solvers and formulations that cannot take the frictionless plane's points beside the
/// frictional interface say so: De Saxcé's cone loses `r_N ≥ 0` where μ = 0; weak multipliers
/// would mix the two sets of rows.
#[test]
fn mixed_frictional_and_frictionless_points_are_refused_where_unsupported() {
    let e = samples("standard", "backward_euler", |o| {
        o.options.contact_solver = Some("de_saxce".into())
    })
    .unwrap_err();
    assert!(e.to_string().contains("de_saxce"), "{e}");
    let e = samples("standard", "backward_euler", |o| {
        o.options.contact = Some("weak".into())
    })
    .unwrap_err();
    assert!(e.to_string().contains("frictionless"), "{e}");
}

/// Mass redistribution makes every contact direction massless, the plane's rows under the
/// bottom block as the interface's (the merged mass model lists the plane's normal dofs too).
#[test]
fn mass_redistribution_frees_the_plane_rows_too() {
    let o = Overrides::default();
    let case = cases::load(Path::new(CASE_2D), &o).unwrap();
    let space = dyncontact::space::by_name("mass_redistribution").unwrap();
    let problem = case.problem(space.as_ref()).unwrap();
    let massless = problem.inertia.massless();
    let plane = problem.contact.friction.as_ref().unwrap().frictionless;
    assert_eq!(plane, 13, "12 faces under the bottom block");
    for i in 0..problem.contact.len() {
        let row = problem.contact.row(i);
        let mut b = vec![0.0; problem.n()];
        for &(j, v) in &row {
            b[j] = v;
        }
        let mb = problem.inertia.mass_times(&b).unwrap();
        assert!(mb.iter().all(|x| x.abs() < 1e-14), "row {i}: {row:?}");
        assert!(row.iter().any(|&(j, _)| massless[j]), "row {i}");
    }
}

/// `--friction 0` makes the interface frictionless: no tangential rows, no friction columns.
#[test]
fn without_friction_the_top_block_keeps_v0() {
    let o = Overrides {
        friction: Some(0.0),
        ..Default::default()
    };
    let case = cases::load(Path::new(CASE_2D), &o).unwrap();
    let r = dyncontact::study::run::run(case.as_ref()).unwrap();
    assert!(r.rows.iter().all(|x| x.friction.is_none()));
    let space = dyncontact::space::by_name("standard").unwrap();
    assert!(case
        .problem(space.as_ref())
        .unwrap()
        .contact
        .friction
        .is_none());
}

/// A space that leaves a floating body without inertia along a direction is refused naming
/// the space and what to change: the step matrix is singular on that rigid translation, and
/// failed in the factorisation with a non-positive pivot. Mass elimination takes the mass of
/// every element touching Γ_C: the 3D lower block (two layers of cells, one on the plane, one
/// under the upper block) keeps none. Mass redistribution (normal inertia) and modified
/// quadrature (all of it) take it from the contact nodes: a lower block of one layer of cells
/// (`--elements 2`: 2 × 2 × 1 on 3 × 3 × 1) has nothing else.
#[test]
fn a_body_left_without_inertia_is_refused() {
    for (space, elements) in [
        ("mass_elimination", None),
        ("mass_redistribution", Some(2)),
        ("modified_quadrature", Some(2)),
    ] {
        let o = dyncontact::cases::Overrides {
            space: Some(space.into()),
            elements,
            ..Default::default()
        };
        let path = std::path::Path::new("cases/slide_on_block3d.toml");
        let e = match dyncontact::cases::load(path, &o) {
            Err(e) => e,
            Ok(case) => match dyncontact::study::run::run(case.as_ref()) {
                Err(e) => e,
                Ok(_) => panic!("{space}: a body without inertia ran"),
            },
        };
        let e = e.to_string();
        assert!(
            e.contains(space) && e.contains("without inertia") && e.contains("mesh.elements"),
            "{e}"
        );
    }
}

/// `--elements N` refines a pair whose body 2 has its own `[master.mesh]` in the file's
/// proportion: slide_on_block3d's 4 and 6 cells stay as they are under `--elements 4` (it used
/// to set body 2's to 4 too: one layer of cells), and double under `--elements 8`; a count left
/// to its default is N.
#[test]
fn elements_refine_both_bodies_in_proportion() {
    let path = std::path::Path::new("cases/slide_on_block3d.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let dofs = |text: &str, elements: Option<usize>| {
        let o = dyncontact::cases::Overrides {
            elements,
            ..Default::default()
        };
        let case = dyncontact::cases::parse(text, path, &o).unwrap();
        let space = dyncontact::space::by_name("standard").unwrap();
        case.problem(space.as_ref()).unwrap().n()
    };
    assert!(text.contains("elements = 4 ") && text.contains("elements = 6 "));
    let doubled = text
        .replace("elements = 4 ", "elements = 8 ")
        .replace("elements = 6 ", "elements = 12 ");
    assert_eq!(dofs(&text, Some(4)), dofs(&text, None));
    assert_eq!(dofs(&text, Some(8)), dofs(&doubled, None));
    assert_ne!(dofs(&text, Some(8)), dofs(&text, None));
    // Body 2 without a count of its own takes N itself (it was given 1 cell).
    let unset = text.replace("elements = 6 ", "# elements = 6 ");
    let equal = text.replace("elements = 6 ", "elements = 4 ");
    assert_eq!(dofs(&unset, Some(8)), dofs(&equal, Some(8)));
}
