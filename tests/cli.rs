//! The binary end to end: outputs of `run`, and clear errors (exit code ≠ 0, no panic) on bad input.

use std::path::Path;
use std::process::{Command, Output, Stdio};

fn dyncontact(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dyncontact"))
        .args(args)
        .output()
        .expect("binary runs")
}

/// Writes `cases/bar1d.toml` with `from` replaced by `to` into `dir` and returns its path.
fn edited_case(dir: &Path, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string("cases/bar1d.toml").unwrap();
    assert!(
        text.contains(from),
        "test setup: `{from}` not in the case file"
    );
    let path = dir.join("case.toml");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_str().unwrap().to_string()
}

fn assert_clear_error(out: &Output, needle: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected failure, got success");
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert!(
        stderr.contains(needle),
        "error should mention `{needle}`: {stderr}"
    );
}

#[test]
fn bad_case_files_give_errors_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases = [
        ("density = 1.0", "density = -1.0", "material.density"),
        ("dt = 0.0125", "dt = 0.0", "run.dt"),
        ("dt = 0.0125", "dt = -0.1", "run.dt"),
        ("young = 1.0", "young = nan", "material.young"),
        (
            "space = \"mass_redistribution\"",
            "space = \"magic\"",
            "unknown space `magic`",
        ),
        ("lift = 0.5", "lift = \"half\"", "malformed case file"),
        ("elements = 40", "elemnts = 40", "malformed case file"),
        ("beta = 0.5", "beta = 0.9", "beta"),
        ("beta = 0.5", "betta = 0.5", "`run.betta`: 0.5 (unknown key"),
        ("beta = 0.5", "beta = \"half\"", "`beta`: expected a number"),
    ];
    for (from, to, needle) in cases {
        let out = dyncontact(&[
            "run",
            &edited_case(d, from, to),
            "--out",
            d.join("o").to_str().unwrap(),
        ]);
        assert_clear_error(&out, needle);
    }
}

#[test]
fn bad_command_line_values_give_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("o");
    let o = out_dir.to_str().unwrap();
    assert_clear_error(
        &dyncontact(&["run", "cases/bar1d.toml", "--dt", "-1", "--out", o]),
        "run.dt",
    );
    assert_clear_error(
        &dyncontact(&["run", "cases/bar1d.toml", "--space", "nope", "--out", o]),
        "unknown space",
    );
    assert_clear_error(
        &dyncontact(&["run", "cases/bar1d.toml", "--scheme", "rk4", "--out", o]),
        "unknown scheme",
    );
    assert_clear_error(
        &dyncontact(&["run", "cases/missing.toml", "--out", o]),
        "missing.toml",
    );
    assert_clear_error(
        &dyncontact(&["run", "cases/block2d.toml", "--cells", "hex", "--out", o]),
        "mesh.cells",
    );
    assert_clear_error(
        &dyncontact(&["run", "cases/bar1d.toml", "--cells", "tet", "--out", o]),
        "--cells",
    );
    assert_clear_error(
        &dyncontact(&[
            "run",
            "cases/bar1d.toml",
            "--space",
            "singular_dynamic",
            "--degree",
            "1",
            "--out",
            o,
        ]),
        "degree 2",
    );
    let scheme_cases: [(&[&str], &str); 7] = [
        (&["--scheme", "hht", "--alpha", "0.5"], "alpha"),
        (
            &["--scheme", "paoli_schatzman", "--restitution", "1.5"],
            "restitution",
        ),
        (&["--scheme", "moreau_jean", "--theta", "0.2"], "theta"),
        (&["--contact-solver", "simplex"], "unknown contact solver"),
        (&["--contact", "mortar"], "unknown contact formulation"),
        (&["--contact", "penalty", "--penalty", "0"], "run.penalty"),
        (
            &["--scheme", "central_difference", "--dt", "0.1"],
            "unstable time step",
        ),
    ];
    for (args, needle) in scheme_cases {
        let mut a = vec!["run", "cases/bar1d.toml", "--out", o];
        a.extend_from_slice(args);
        assert_clear_error(&dyncontact(&a), needle);
    }
    assert_clear_error(
        &dyncontact(&["sweep", "cases/bar1d.toml", "--shard", "3/2", "--out", o]),
        "--shard",
    );
    // Field output needs a mesh, and a positive stride.
    assert_clear_error(
        &dyncontact(&["run", "cases/bar1d.toml", "--vtu", o, "--out", o]),
        "needs a 2D/3D body case",
    );
    let file = dir.path().join("a_file");
    std::fs::write(&file, "").unwrap();
    assert_clear_error(
        &dyncontact(&[
            "run",
            "cases/hertz2d.toml",
            "--vtu",
            file.to_str().unwrap(),
            "--out",
            o,
        ]),
        "not a directory",
    );
    assert_clear_error(
        &dyncontact(&[
            "run",
            "cases/hertz2d.toml",
            "--vtu",
            o,
            "--vtu-every",
            "0",
            "--out",
            o,
        ]),
        "--vtu-every",
    );
}

/// `sweep --quick` writes one record per run and an orders table covering every space × scheme
/// of the case's `[[sweep]]` table; shards partition the runs.
#[test]
fn sweep_writes_records_and_orders_for_every_combination() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().to_str().unwrap();
    let out = dyncontact(&["sweep", "cases/spring_mass.toml", "--quick", "--out", o]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let records = std::fs::read_to_string(dir.path().join("records.csv")).unwrap();
    let orders = std::fs::read_to_string(dir.path().join("orders.csv")).unwrap();
    // 7 schemes × 3 quick levels.
    assert_eq!(records.lines().count(), 1 + 7 * 3);
    let swept = dyncontact::cases::load(Path::new("cases/spring_mass.toml"), &Default::default())
        .unwrap()
        .sweeps()[0]
        .schemes
        .iter()
        .map(|s| s.scheme.clone())
        .collect::<Vec<_>>();
    for scheme in swept {
        assert!(
            orders
                .lines()
                .any(|l| l.contains(&format!(",{scheme},")) && l.contains("impact_time_err")),
            "no order for {scheme}"
        );
    }
    let mut sharded = 0;
    for i in 1..=2 {
        let shard = format!("{i}/2");
        let out = dyncontact(&[
            "sweep",
            "cases/spring_mass.toml",
            "--quick",
            "--shard",
            &shard,
            "--out",
            o,
        ]);
        assert!(out.status.success());
        let name = format!("records-{i}-of-2.csv");
        sharded += std::fs::read_to_string(dir.path().join(name))
            .unwrap()
            .lines()
            .count()
            - 1;
    }
    assert_eq!(sharded, 7 * 3);
}

#[test]
fn run_writes_the_documented_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("run");
    let args = [
        "run",
        "cases/bar1d.toml",
        "--elements",
        "10",
        "--dt",
        "0.05",
        "--t-end",
        "3",
        "--out",
    ];
    let mut a = args.to_vec();
    a.push(o.to_str().unwrap());
    let out = dyncontact(&a);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let ts = std::fs::read_to_string(o.join("timeseries.csv")).unwrap();
    assert_eq!(
        ts.lines().next().unwrap(),
        "t,u_contact,v_contact,sigma_contact,energy,gap,force_contact,u_contact_exact,sigma_contact_exact,energy_exact"
    );
    assert_eq!(ts.lines().count(), 1 + 61);
    let summary = std::fs::read_to_string(o.join("summary.csv")).unwrap();
    for col in [
        "energy_drift",
        "max_penetration",
        "err_u_linf_l2",
        "err_u_l2_h1",
        "err_sigma_l2",
        "err_energy",
        "sigma_total_variation",
        "err_contact_duration",
        "err_peak_force",
        "err_max_approach",
        "restitution_eff",
    ] {
        assert!(
            summary.lines().next().unwrap().split(',').any(|c| c == col),
            "missing column {col}"
        );
    }
    for png in ["energy.png", "contact.png"] {
        let bytes = std::fs::read(o.join(png)).unwrap();
        assert!(
            bytes.starts_with(b"\x89PNG") && bytes.len() > 10_000,
            "{png} looks empty"
        );
    }
    // Deterministic: a second run gives a byte-identical time series.
    let out2 = dyncontact(&a);
    assert!(out2.status.success());
    assert_eq!(
        std::fs::read_to_string(o.join("timeseries.csv")).unwrap(),
        ts
    );
}

/// Body case files: out-of-range material, wrong geometry or cell type name the field.
#[test]
fn bad_block_case_files_give_errors_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string("cases/block2d.toml").unwrap();
    let cases = [
        ("poisson = 0.3", "poisson = 0.5", "material.poisson"),
        ("size = [1.0, 1.0]", "size = [1.0]", "geometry.size"),
        ("cells = \"quad\"", "cells = \"hex\"", "mesh.cells"),
        ("elements = 10", "elements = 0", "mesh.elements"),
        ("density = 1.0", "density = -1.0", "material.density"),
    ];
    for (from, to, needle) in cases {
        assert!(text.contains(from), "test setup: `{from}`");
        let path = dir.path().join("block.toml");
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
        let out = dyncontact(&[
            "run",
            path.to_str().unwrap(),
            "--out",
            dir.path().join("o").to_str().unwrap(),
        ]);
        assert_clear_error(&out, needle);
    }
}

/// A closed stdout (`dyncontact list | head -1`) ends the program quietly: exit 0, no panic.
#[test]
fn a_closed_stdout_pipe_ends_the_program_quietly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dyncontact"))
        .arg("list")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("binary runs");
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("binary ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert!(out.status.success(), "{:?}: {stderr}", out.status);
}

/// Outside the repository `list` still lists the methods, and says where the case files are
/// expected and how to point at them; `report` refuses with the same words.
#[test]
fn list_outside_the_repository_says_where_the_case_files_are() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_dyncontact"))
        .arg("list")
        .current_dir(dir.path())
        .output()
        .expect("binary runs");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stderr}");
    assert!(stdout.contains("spaces: standard") && stdout.contains("newmark (beta="));
    for needle in [
        "no case files at",
        "cases/",
        "dyncontact list DIR",
        "--cases DIR",
    ] {
        assert!(stderr.contains(needle), "`{needle}` not in: {stderr}");
    }
    let out = Command::new(env!("CARGO_BIN_EXE_dyncontact"))
        .args(["report", "--quick", "--out", "r"])
        .current_dir(dir.path())
        .output()
        .expect("binary runs");
    assert_clear_error(&out, "--cases DIR");
}

/// `report --case NAME` runs the named cases only; an unknown name is refused with the known.
#[test]
fn report_runs_the_cases_named_only() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("r");
    let out = dyncontact(&[
        "report",
        "--quick",
        "--case",
        "spring_mass",
        "--out",
        o.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = std::fs::read_to_string(o.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 1 + 7 * 3, "spring_mass only");
    assert!(summary
        .lines()
        .skip(1)
        .all(|l| l.starts_with("spring_mass-")));
    assert!(o.join("cases/spring_mass.toml").exists());
    assert!(
        !o.join("cross_code.csv").exists(),
        "no GetFEM comparison of the bar and block"
    );
    let out = dyncontact(&[
        "report",
        "--quick",
        "--case",
        "bar2d",
        "--out",
        o.to_str().unwrap(),
    ]);
    assert_clear_error(&out, "--case");
    assert_clear_error(&out, "known: bar1d, bar_flight, block2d");
}

/// The headline of `run`: the drift outside the impact steps when one impact step's dip would
/// dominate (Paoli–Schatzman on the spring: 0.96 over every step, 2.5e-5 outside), the other
/// beside it.
#[test]
fn run_prints_the_drift_that_says_whether_the_energy_holds() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("ps");
    let out = dyncontact(&[
        "run",
        "cases/spring_mass.toml",
        "--scheme",
        "paoli_schatzman",
        "--out",
        o.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(
        stdout.contains("energy drift 2.500e-5 outside impact steps (9.637e-1 over every step)"),
        "{stdout}"
    );
}
