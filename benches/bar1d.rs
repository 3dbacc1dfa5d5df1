//! Time stepping cost on bar1d: factor once, then per step one predictor solve and a 1×1 LCP.
//! `full_run/<space>`: 10³ elements, 10³ Newmark(½,½) steps (prepare included, no output).
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
    let run = RunSpec {
        space: "standard".into(),
        scheme: "newmark".into(),
        beta: 0.5,
        gamma: 0.5,
        dt: 0.5 / elements as f64,
        t_end: 1.0,
        contact_solver: "active_set".into(),
    };
    Bar1d::new(exact, elements, degree, true, run).expect("valid bar")
}

/// Prepare and take `steps` steps; returns the final contact displacement.
fn simulate(case: &Bar1d, space: &str, steps: usize) -> f64 {
    let problem = case
        .problem(dyncontact::space::by_name(space).unwrap().as_ref())
        .unwrap();
    let scheme = dyncontact::time::by_name(
        "newmark",
        dyncontact::time::SchemeParams {
            beta: 0.5,
            gamma: 0.5,
        },
    )
    .unwrap();
    let solver = dyncontact::contact::by_name("active_set", 1).unwrap();
    let mut it = scheme.prepare(&problem, case.run().dt, solver).unwrap();
    for _ in 0..steps {
        it.step().unwrap();
    }
    it.state().u[0]
}

fn full_run(c: &mut Criterion) {
    let mut g = c.benchmark_group("full_run");
    g.sample_size(10);
    for space in dyncontact::space::SPACES {
        let degree = if *space == "singular_dynamic" { 2 } else { 1 };
        let case = bar(1000, degree);
        g.bench_function(*space, |b| {
            b.iter(|| black_box(simulate(&case, space, 1000)))
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

criterion_group!(benches, full_run, speed_target);
criterion_main!(benches);
