//! `dyncontact report`: the bar1d convergence study for every space × Newmark variant, the
//! spring–mass restitution table, and the figures, written to one directory with an `index.md`.
//!
//! bar1d: h = 1/20 … 1/320 with dt = h/2, T = 12 (P1; singular_dynamic P2/P1). Observed orders are
//! least-squares slopes of log(error) against log(h), with the RMS residual of the fit.

use crate::cases::bar1d::Bar1d;
use crate::cases::{self, Case, Overrides, RunSpec};
use crate::error::{Error, Result};
use crate::output::csv::{summary_record, SUMMARY_COLUMNS};
use crate::output::plot::{loglog_plot, time_plot, Series, PALETTE};
use crate::run::{run, RunResult, Summary};
use crate::space::SPACES;
use std::fmt::Write as _;
use std::path::Path;

/// Refinement levels of the bar convergence study (elements).
pub const LEVELS: [usize; 5] = [20, 40, 80, 160, 320];
/// Newmark (β, γ) variants of the study.
pub const NEWMARK: [(f64, f64); 2] = [(0.5, 0.5), (0.25, 0.5)];

/// The quantities whose orders are reported, with their accessor.
type Quantity = (&'static str, fn(&Summary) -> Option<f64>);
const QUANTITIES: [Quantity; 5] = [
    ("err_u_linf_l2", |s| s.metrics.err_u_linf_l2),
    ("err_u_contact", |s| s.metrics.err_u_contact),
    ("err_u_l2_h1", |s| s.metrics.err_u_l2_h1),
    ("err_energy", |s| s.metrics.err_energy),
    ("err_sigma_l2", |s| s.metrics.err_sigma_l2),
];

/// Least-squares slope of log(y) against log(x) and the RMS residual of the fit.
pub fn fit_order(x: &[f64], y: &[f64]) -> (f64, f64) {
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let n = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx).powi(2)).sum();
    let slope = sxy / sxx;
    let res = lx
        .iter()
        .zip(&ly)
        .map(|(a, b)| (b - my - slope * (a - mx)).powi(2))
        .sum::<f64>();
    (slope, (res / n).sqrt())
}

fn bar_run(base: &Bar1d, space: &str, (beta, gamma): (f64, f64), n: usize) -> Result<RunResult> {
    let degree = if space == "singular_dynamic" { 2 } else { 1 };
    let spec = RunSpec {
        beta,
        gamma,
        ..RunSpec::new(
            space,
            "newmark",
            base.exact.length / (2.0 * n as f64),
            12.0 * base.exact.length / base.exact.wave_speed(),
        )
    };
    run(&Bar1d::new(base.exact, n, degree, true, spec)? as &dyn Case)
}

fn write_csv(path: &Path, header: &[&str], rows: &[Vec<String>]) -> Result<()> {
    let mut text = header.join(",");
    text.push('\n');
    for r in rows {
        text.push_str(&r.join(","));
        text.push('\n');
    }
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}

/// Runs the study from the case files in `cases_dir` and writes everything into `out`.
pub fn report(cases_dir: &Path, out: &Path, progress: &mut dyn FnMut(&str)) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let bar_path = cases_dir.join("bar1d.toml");
    let bar_text = std::fs::read_to_string(&bar_path).map_err(|e| Error::io(&bar_path, e))?;
    let base = Bar1d::from_spec(
        cases::spec_from_str(&bar_text, &bar_path)?,
        &Overrides::default(),
    )?;
    let mut summaries = Vec::new();
    let mut orders = Vec::new();
    let mut conv_series = Vec::new();
    let mut samples: Vec<(String, RunResult)> = Vec::new();
    for (k, space) in SPACES.iter().enumerate() {
        for nm in NEWMARK {
            let mut runs = Vec::new();
            for n in LEVELS {
                progress(&format!(
                    "bar1d {space} newmark({}, {}) N = {n}",
                    nm.0, nm.1
                ));
                let r = bar_run(&base, space, nm, n)?;
                if n == 80 && nm == (0.5, 0.5) {
                    samples.push((space.to_string(), r.clone()));
                }
                runs.push(r.summary);
            }
            let h: Vec<f64> = runs.iter().map(|s| s.h).collect();
            for (name, get) in QUANTITIES {
                let e: Vec<f64> = runs.iter().filter_map(get).collect();
                if e.len() == h.len() && e.iter().all(|v| *v > 0.0) {
                    let (p, res) = fit_order(&h, &e);
                    let s = &runs[0];
                    orders.push(vec![
                        s.case.clone(),
                        s.space.clone(),
                        s.scheme.clone(),
                        s.parameters.clone(),
                        name.to_string(),
                        format!("{p:.4}"),
                        format!("{res:.4}"),
                    ]);
                }
            }
            if nm == (0.5, 0.5) {
                let pts = runs
                    .iter()
                    .filter_map(|s| s.metrics.err_u_linf_l2.map(|e| (s.h, e)))
                    .collect();
                conv_series.push(Series::solid(*space, pts, PALETTE[k % PALETTE.len()]));
            }
            summaries.extend(runs);
        }
    }
    for space in ["standard", "lumped"] {
        for nm in NEWMARK {
            progress(&format!("spring_mass {space} newmark({}, {})", nm.0, nm.1));
            let o = Overrides {
                space: Some(space.into()),
                beta: Some(nm.0),
                gamma: Some(nm.1),
                ..Default::default()
            };
            let case = cases::load(&cases_dir.join("spring_mass.toml"), &o)?;
            summaries.push(run(case.as_ref())?.summary);
        }
    }
    let rows: Vec<Vec<String>> = summaries.iter().map(summary_record).collect();
    write_csv(&out.join("summary.csv"), SUMMARY_COLUMNS, &rows)?;
    write_csv(
        &out.join("orders.csv"),
        &[
            "case",
            "space",
            "scheme",
            "parameters",
            "quantity",
            "order",
            "fit_residual",
        ],
        &orders,
    )?;
    loglog_plot(
        &out.join("bar1d_convergence.png"),
        "bar1d: max_t ||u_h - u||_L2, Newmark(1/2, 1/2), dt = h/2",
        "error in u, L-inf(L2)",
        &conv_series,
    )?;
    let curve = |r: &RunResult, f: fn(&crate::run::Row) -> f64| {
        r.rows.iter().map(|x| (x.t, f(x))).collect()
    };
    let pick = |names: &[&str]| -> Vec<&(String, RunResult)> {
        samples
            .iter()
            .filter(|(s, _)| names.contains(&s.as_str()))
            .collect()
    };
    let shown = pick(&["standard", "mass_redistribution", "singular_dynamic"]);
    let mut stress: Vec<Series> = shown
        .iter()
        .enumerate()
        .map(|(i, (s, r))| Series::solid(s.clone(), curve(r, |x| x.sigma_contact), PALETTE[i]))
        .collect();
    let mut energy: Vec<Series> = shown
        .iter()
        .enumerate()
        .map(|(i, (s, r))| Series::solid(s.clone(), curve(r, |x| x.energy), PALETTE[i]))
        .collect();
    if let Some((_, r)) = shown.first() {
        let ex = |f: fn((f64, f64, f64)) -> f64| {
            r.rows
                .iter()
                .filter_map(|x| x.exact.map(|e| (x.t, f(e))))
                .collect()
        };
        stress.push(Series::dashed("exact", ex(|e| e.1), BLACK_RGB));
        energy.push(Series::dashed("exact", ex(|e| e.2), BLACK_RGB));
    }
    time_plot(
        &out.join("bar1d_contact_stress.png"),
        "bar1d: contact stress at x = 0, N = 80, dt = h/2, Newmark(1/2, 1/2)",
        "sigma_N",
        &stress,
    )?;
    time_plot(
        &out.join("bar1d_energy.png"),
        "bar1d: total energy, N = 80, dt = h/2, Newmark(1/2, 1/2)",
        "energy",
        &energy,
    )?;
    write_index(out, &orders)
}

const BLACK_RGB: plotters::style::RGBColor = plotters::style::RGBColor(0, 0, 0);

fn write_index(out: &Path, orders: &[Vec<String>]) -> Result<()> {
    let mut md = String::from("# dyncontact report\n\n");
    md.push_str("Generated by `cargo run --release -- report`. bar1d: unit bar of `shared/reference/bar_impact.md`, ");
    md.push_str("h = 1/20 … 1/320, dt = h/2, T = 12 (P1; singular_dynamic P2/P1).\n\n");
    md.push_str("- `summary.csv`: one row per run (metrics of DESIGN.md §6; `wall_time_s` is the only non-deterministic column).\n");
    md.push_str("- `orders.csv`: observed orders (least-squares slope of log error vs log h) and fit residuals.\n");
    md.push_str(
        "- `bar1d_convergence.png`: displacement error vs h for every space, Newmark(½, ½).\n",
    );
    md.push_str("- `bar1d_contact_stress.png`: contact stress at x = 0 (standard oscillates, mass redistribution is close to the exact square wave).\n");
    md.push_str("- `bar1d_energy.png`: total energy vs time against the exact 1/8.\n\n");
    md.push_str("## Observed orders (Newmark ½, ½)\n\n| space | u L∞(L²) | u(0,t) | u L²(H¹) | energy | σ_N L²(0,T) |\n|---|---|---|---|---|---|\n");
    for space in SPACES {
        let get = |q: &str| {
            orders
                .iter()
                .find(|r| r[1] == *space && r[3] == "beta=0.5;gamma=0.5" && r[4] == q)
                .map_or("–".to_string(), |r| r[5].clone())
        };
        let _ = writeln!(
            md,
            "| {space} | {} | {} | {} | {} | {} |",
            get("err_u_linf_l2"),
            get("err_u_contact"),
            get("err_u_l2_h1"),
            get("err_energy"),
            get("err_sigma_l2")
        );
    }
    std::fs::write(out.join("index.md"), md).map_err(|e| Error::io(out.join("index.md"), e))
}
