//! The block drop at production size (issue "2D and 3D block drop", speed target: 10⁵ dofs × 10³
//! steps under 60 s on 2 cores). Mass redistribution + Newmark(½, ½), dt = 1e-3:
//! - `block2d_1e5/prepare`: Q1 224 × 224 (101 250 dofs, 225 contact points): assembly, one sparse
//!   Cholesky, the Delassus operator (blocked solves) and the initial state;
//! - `block2d_1e5/step`: one time step during persistent contact (triangular solves, the contact
//!   LCP with a cached factor, the correction by the stored `A⁻¹ B_Nᵀ`);
//! - `block3d_15k/{prepare,step}`: Q1 16³ (14 739 dofs, 289 contact points).
//!
//! A full run costs `prepare + 1000 × step`.

use criterion::{criterion_group, criterion_main, Criterion};
use dyncontact::cases::{self, Case, Overrides};
use std::hint::black_box;
use std::path::Path;

fn case(file: &str, elements: usize) -> Box<dyn Case> {
    let o = Overrides {
        elements: Some(elements),
        dt: Some(1e-3),
        ..Default::default()
    };
    cases::load(Path::new(file), &o).expect("valid case")
}

fn prepare_and_step(c: &mut Criterion, group: &str, file: &str, elements: usize) {
    let case = case(file, elements);
    let space = dyncontact::space::by_name("mass_redistribution").unwrap();
    let scheme = dyncontact::time::by_name("newmark", case.run().params()).unwrap();
    let solver = |n_c| dyncontact::contact::by_name("active_set", n_c).unwrap();
    let mut g = c.benchmark_group(group);
    g.sample_size(10);
    g.bench_function("prepare", |b| {
        b.iter(|| {
            let problem = case.problem(space.as_ref()).unwrap();
            let it = scheme
                .prepare(&problem, 1e-3, solver(problem.contact.len()).into())
                .unwrap();
            black_box(it.state().u.len())
        })
    });
    let problem = case.problem(space.as_ref()).unwrap();
    let mut it = scheme
        .prepare(&problem, 1e-3, solver(problem.contact.len()).into())
        .unwrap();
    for _ in 0..10 {
        it.step().unwrap();
    }
    g.bench_function("step", |b| b.iter(|| black_box(it.step().unwrap())));
    g.finish();
}

fn block2d(c: &mut Criterion) {
    prepare_and_step(c, "block2d_1e5", "cases/block2d.toml", 224);
}

fn block3d(c: &mut Criterion) {
    prepare_and_step(c, "block3d_15k", "cases/block3d.toml", 16);
}

criterion_group!(benches, block2d, block3d);
criterion_main!(benches);
