//! Shared helpers for the integration tests.
#![allow(dead_code)]

use dyncontact::cases::bar1d::Bar1d;
use dyncontact::cases::{Case, RunSpec};
use dyncontact::exact::bar_impact::BarImpact;
use dyncontact::study::run::{run, RunResult};

/// The unit bar of `shared/reference/bar_impact.md`.
pub const UNIT_BAR: BarImpact = BarImpact {
    length: 1.0,
    young: 1.0,
    density: 1.0,
    lift: 0.5,
};

/// Run settings for bar1d.
pub fn run_spec(space: &str, beta: f64, gamma: f64, dt: f64, t_end: f64) -> RunSpec {
    RunSpec::new(space, "newmark", dt, t_end)
        .with("beta", beta)
        .with("gamma", gamma)
}

/// The clamped unit bar with `n` elements of degree `degree`.
pub fn bar(n: usize, degree: usize, spec: RunSpec) -> Bar1d {
    Bar1d::new(UNIT_BAR, n, degree, true, spec).expect("valid bar")
}

/// Runs bar1d and returns the result.
pub fn run_bar(
    space: &str,
    n: usize,
    degree: usize,
    beta: f64,
    gamma: f64,
    dt: f64,
    t_end: f64,
) -> RunResult {
    let case = bar(n, degree, run_spec(space, beta, gamma, dt, t_end));
    run(&case as &dyn Case).expect("run succeeds")
}

/// Least-squares slope of log(err) against log(h).
pub fn observed_order(h: &[f64], err: &[f64]) -> f64 {
    dyncontact::study::orders::fit_order(h, err).0
}
