//! The speed targets, each timed end to end as `dyncontact run` does it (case file read, problem
//! assembled, prepared, stepped, metrics, `timeseries.csv`, `summary.csv` and both PNGs written),
//! with the measured time and its ratio to the target:
//!
//!     cargo bench --bench targets            # all six (about 4 minutes)
//!     cargo bench --bench targets -- bar1d   # the ones whose name contains `bar1d`
//!
//! Each target runs once (the heavy ones take close to a minute; criterion's ten samples would
//! take ten); the bar runs three times and reports the best, as its wall time is short.

use dyncontact::cases::{self, Overrides};
use dyncontact::study::run;
use std::path::Path;
use std::time::Instant;

/// A speed target: name, case file, overrides, limit in seconds.
struct Target {
    name: &'static str,
    file: &'static str,
    overrides: Overrides,
    limit: f64,
    repeat: usize,
}

fn targets() -> Vec<Target> {
    let o = |space: &str, elements: usize, dt: f64, t_end: f64| {
        Overrides {
            space: Some(space.into()),
            scheme: Some("newmark".into()),
            elements: Some(elements),
            dt: Some(dt),
            t_end: Some(t_end),
            ..Default::default()
        }
        .with("beta", 0.5)
        .with("gamma", 0.5)
    };
    vec![
        Target {
            name: "bar1d MR Newmark, 1e4 P1 x 1e4 steps",
            file: "cases/bar1d.toml",
            overrides: o("mass_redistribution", 10_000, 1e-4, 1.0),
            limit: 1.5,
            repeat: 3,
        },
        Target {
            name: "block2d Q1 224^2 MR Newmark, dt 1e-3, 1e3 steps",
            file: "cases/block2d.toml",
            overrides: o("mass_redistribution", 224, 1e-3, 1.0),
            limit: 45.0,
            repeat: 1,
        },
        Target {
            name: "block3d Q1 32^3 MR Newmark, dt 1e-3, 1e3 steps",
            file: "cases/block3d.toml",
            overrides: o("mass_redistribution", 32, 1e-3, 1.0),
            limit: 60.0,
            repeat: 1,
        },
        // The curved bodies at their defaults (issue 9: each under a minute).
        Target {
            name: "hertz2d disc Q1 n 48 (14k dofs), defaults",
            file: "cases/hertz2d.toml",
            overrides: Overrides::default(),
            limit: 60.0,
            repeat: 1,
        },
        Target {
            name: "hertz3d sphere Q1 n 16 (52k dofs), defaults",
            file: "cases/hertz3d.toml",
            overrides: Overrides::default(),
            limit: 60.0,
            repeat: 1,
        },
        // Issue 9's size for the graded sphere: n = 20 with the default grading is 99 843 dofs.
        Target {
            name: "hertz3d sphere Q1 n 20 (100k dofs), defaults",
            file: "cases/hertz3d.toml",
            overrides: Overrides {
                elements: Some(20),
                ..Default::default()
            },
            limit: 60.0,
            repeat: 1,
        },
    ]
}

/// Seconds of one end-to-end run.
fn end_to_end(t: &Target, out: &Path) -> f64 {
    let start = Instant::now();
    let case = cases::load(Path::new(t.file), &t.overrides).expect("valid case");
    let result = run::run(case.as_ref()).expect("run");
    run::write_run(out, &result).expect("outputs");
    start.elapsed().as_secs_f64()
}

fn main() {
    let filter: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let out = std::env::temp_dir().join("dyncontact-targets");
    println!(
        "{:<50} {:>10} {:>8} {:>7}",
        "target", "measured", "limit", "ratio"
    );
    for t in targets()
        .into_iter()
        .filter(|t| filter.is_empty() || filter.iter().any(|f| t.name.contains(f.as_str())))
    {
        let best = (0..t.repeat)
            .map(|_| end_to_end(&t, &out))
            .fold(f64::INFINITY, f64::min);
        let verdict = if best <= t.limit { "met" } else { "NOT MET" };
        println!(
            "{:<50} {:>9.2}s {:>7.1}s {:>7.2} {verdict}",
            t.name,
            best,
            t.limit,
            best / t.limit
        );
    }
}
