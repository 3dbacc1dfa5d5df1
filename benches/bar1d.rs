//! Time stepping cost on bar1d: factor once, then per step one predictor solve and a 1×1 LCP.
//! `full_run/<space>`: 10³ elements, 10³ Newmark(½,½) steps (prepare included, no output).
//! `schemes/<scheme>`: the same run (mass redistribution, 10³ elements, 10³ steps) per scheme.
//! `speed_target/mass_redistribution_1e4x1e4`: the target, 10⁴ P1 elements × 10⁴ steps.

use criterion::{criterion_group, criterion_main, Criterion};
use dyncontact::cases::bar1d::Bar1d;
use dyncontact::cases::{Case, RunSpec};
use dyncontact::exact::bar_impact::BarImpact;
use std::hint::black_box;

fn bar(elements: usize, degree: usize) -> Bar1d {
    let exact = BarImpact {
        length: 1.0,
        young: 1.0,
        density: 1.0,
        lift: 0.5,
    };
    let run = RunSpec::new("standard", "newmark", 0.5 / elements as f64, 1.0)
        .with("beta", 0.5)
        .with("gamma", 0.5);
    Bar1d::new(exact, elements, degree, true, run).expect("valid bar")
}

/// Prepare and take `steps` steps of Newmark(½, ½); returns the final contact displacement.
fn simulate(case: &Bar1d, space: &str, steps: usize) -> f64 {
    simulate_with(case, space, "newmark", steps)
}

/// Prepare and take `steps` steps of `scheme` (Newmark β = γ = ½, other parameters default).
fn simulate_with(case: &Bar1d, space: &str, scheme: &str, steps: usize) -> f64 {
    let problem = case
        .problem(dyncontact::space::by_name(space).unwrap().as_ref())
        .unwrap();
    let scheme = dyncontact::time::by_name(scheme, case.run().params()).unwrap();
    let solver = dyncontact::contact::by_name("active_set", 1).unwrap();
    let mut it = scheme
        .prepare(&problem, case.run().dt, solver.into())
        .unwrap();
    for _ in 0..steps {
        it.step().unwrap();
    }
    it.state().u[0]
}

fn full_run(c: &mut Criterion) {
    let mut g = c.benchmark_group("full_run");
    g.sample_size(10);
    for space in &dyncontact::space::names() {
        let degree = if *space == "singular_dynamic" { 2 } else { 1 };
        let case = bar(1000, degree);
        g.bench_function(*space, |b| {
            b.iter(|| black_box(simulate(&case, space, 1000)))
        });
    }
    g.finish();
}

fn schemes(c: &mut Criterion) {
    let mut g = c.benchmark_group("schemes");
    g.sample_size(10);
    // dt = h/4 keeps central difference below its CFL limit h/√3.
    let mut case = bar(1000, 1);
    case = Bar1d::new(
        case.exact,
        1000,
        1,
        true,
        RunSpec {
            dt: 0.25 / 1000.0,
            ..case.run().clone()
        },
    )
    .expect("valid bar");
    for scheme in dyncontact::param::names(dyncontact::time::SCHEMES) {
        g.bench_function(scheme, |b| {
            b.iter(|| black_box(simulate_with(&case, "mass_redistribution", scheme, 1000)))
        });
    }
    g.finish();
}

fn speed_target(c: &mut Criterion) {
    let mut g = c.benchmark_group("speed_target");
    g.sample_size(10);
    let case = bar(10_000, 1);
    g.bench_function("mass_redistribution_1e4x1e4", |b| {
        b.iter(|| black_box(simulate(&case, "mass_redistribution", 10_000)))
    });
    g.finish();
}

criterion_group!(benches, full_run, schemes, speed_target);
criterion_main!(benches);
