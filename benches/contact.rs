//! Cost of one contact solve (the per-step LCP) per solver and number of contact points n_c, on a
//! random SPD Delassus matrix `GᵀG/n + 0.1 I` with a random gap vector (half the points active
//! on average). `contact_solve/<solver>/<n_c>`: time per step spent in the contact solver.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use dyncontact::contact::by_name;
use nalgebra::DMatrix;
use std::hint::black_box;

/// Deterministic pseudo-random numbers in (−1, 1) (no extra dependency).
fn noise(n: usize, seed: u64) -> Vec<f64> {
    let mut x = seed;
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

fn lcp(n: usize) -> (DMatrix<f64>, Vec<f64>) {
    let g = DMatrix::from_column_slice(n, n, &noise(n * n, 1));
    let d = g.transpose() * &g / n as f64 + DMatrix::identity(n, n) * 0.1;
    (d, noise(n, 2))
}

fn contact_solve(c: &mut Criterion) {
    let mut g = c.benchmark_group("contact_solve");
    g.sample_size(20);
    for n in [10, 50, 200] {
        let (d, q) = lcp(n);
        for name in ["active_set", "clarabel"] {
            let mut solver = by_name(name, n).unwrap();
            let mut lambda = vec![0.0; n];
            g.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| {
                    // Cold start: the first step of an impact (warm starts are cheaper).
                    lambda.fill(0.0);
                    black_box(solver.solve(&d, &q, &mut lambda).unwrap())
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, contact_solve);
criterion_main!(benches);
