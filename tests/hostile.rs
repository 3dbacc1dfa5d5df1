//! Hostile inputs (issue 27): special files, non-finite states, tangled meshes, time grids that
//! miss t_end, interrupted output. Each test runs the binary and asserts a clear error (exit ≠ 0,
//! no panic, the field or file named) within a time limit, or the documented outcome.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs the binary with `args`; kills it and fails if it takes longer than `limit` (a read
/// that never ends, a FIFO that blocks).
fn dyncontact_within(args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dyncontact"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("binary runs");
    let start = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "`dyncontact {}` still running after {limit:?}",
                args.join(" ")
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("binary ends")
}

fn dyncontact(args: &[&str]) -> Output {
    dyncontact_within(args, Duration::from_secs(120))
}

/// `dyncontact run` with `args`, then `tail` (the output directory and the like).
fn run(args: &[&str], tail: &[&str]) -> Output {
    dyncontact(&[&["run"], args, tail].concat())
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn assert_clear_error(out: &Output, needles: &[&str]) {
    let e = stderr(out);
    assert!(!out.status.success(), "expected failure, got success: {e}");
    assert!(!e.contains("panicked"), "panic: {e}");
    for n in needles {
        assert!(e.contains(n), "error should mention `{n}`: {e}");
    }
}

#[test]
fn devices_fifos_and_directories_are_refused_as_inputs_without_reading_them() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let fifo = dir.path().join("case.toml");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let fifo = fifo.to_str().unwrap();
    let limit = Duration::from_secs(20);
    for (args, needles) in [
        (
            vec!["run", "/dev/zero"],
            [
                "case file /dev/zero",
                "not a regular file (a character device)",
            ],
        ),
        (
            vec!["run", "/dev/urandom"],
            ["case file /dev/urandom", "not a regular file"],
        ),
        (
            vec!["run", fifo],
            ["case file", "not a regular file (a FIFO)"],
        ),
        (
            vec!["run", "cases/block2d.toml", "--mesh", "/dev/zero"],
            ["mesh file /dev/zero", "not a regular file"],
        ),
        (
            vec!["run", "cases/block2d.toml", "--mesh", fifo],
            ["mesh file", "a FIFO"],
        ),
        (vec!["sweep", "cases"], ["case file cases", "a directory"]),
        (vec!["merge", fifo], ["records file", "a FIFO"]),
    ] {
        let mut a = args.clone();
        a.extend(["--out", o]);
        assert_clear_error(&dyncontact_within(&a, limit), &needles);
    }
}

#[test]
fn an_oversized_case_file_is_refused_with_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = std::fs::read_to_string("cases/bar1d.toml").unwrap();
    text.push_str(&format!("# {}\n", "x".repeat(2 << 20)));
    let path = dir.path().join("big.toml");
    std::fs::write(&path, text).unwrap();
    let o = dir.path().join("o");
    let out = dyncontact(&["run", path.to_str().unwrap(), "--out", o.to_str().unwrap()]);
    assert_clear_error(&out, &["case file", "limit of 1 MiB"]);
}

#[test]
fn records_that_cannot_be_read_back_are_called_input_files() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("records.csv");
    std::fs::write(&path, "sweep,level\norders,x\n").unwrap();
    let out = dyncontact(&[
        "merge",
        path.to_str().unwrap(),
        "--out",
        dir.path().join("o").to_str().unwrap(),
    ]);
    assert_clear_error(&out, &["records file", "missing column"]);
    assert!(!stderr(&out).contains("csv output"), "{}", stderr(&out));
}

/// `cases/<file>` with each `(from, to)` replaced, written into `dir/<file>`.
fn edited(dir: &Path, file: &str, edits: &[(&str, &str)]) -> String {
    let mut text = std::fs::read_to_string(format!("cases/{file}")).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "test setup: `{from}` not in {file}");
        text = text.replacen(from, to, 1);
    }
    let path = dir.join(file);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// The step named by "diverged at step N".
fn diverged_step(e: &str) -> usize {
    let rest = e
        .split("diverged at step ")
        .nth(1)
        .expect("a diverged error");
    rest.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn the_first_non_finite_quantity_stops_the_run_naming_step_time_and_quantity() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    // An infinite initial energy (½ ρ v² overflows): diverged at step 0, nothing plotted.
    let block = edited(
        dir.path(),
        "block2d.toml",
        &[("velocity = -0.1", "velocity = -1e200")],
    );
    let out = dyncontact(&["run", &block, "--t-end", "0.01", "--out", o]);
    assert_clear_error(&out, &["diverged at step 0 (t = 0", "energy is inf"]);
    // The energy overflows at a later step while U and V stay finite: the sampling thread's
    // check names it; no CSV full of inf, no plot.
    let bar = edited(
        dir.path(),
        "bar1d.toml",
        &[("lift = 0.5", "lift = 1.3e154")],
    );
    let out = dyncontact(&["run", &bar, "--space", "standard", "--out", o]);
    assert_clear_error(
        &out,
        &["solution diverged at step", "(t = ", "energy is inf"],
    );
    assert!(diverged_step(&stderr(&out)) > 0, "{}", stderr(&out));
    for f in ["timeseries.csv", "summary.csv", "energy.png", "contact.png"] {
        assert!(!dir.path().join("o").join(f).exists(), "{f} written");
    }
}

#[test]
fn an_energy_blown_up_past_the_study_limit_fails_the_run_naming_its_step() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    // A penalty 10¹² times its default: finite, but the energy grows to 10¹⁵ E(0). The files are
    // written (the curves are the evidence), and `run` fails as a study records it: diverged.
    let out = run(
        &["cases/bar1d.toml", "--scheme", "hauret_le_tallec"],
        &["--penalty-gamma", "1e14", "--out", o.to_str().unwrap()],
    );
    assert_clear_error(
        &out,
        &[
            "diverged at step",
            "the energy moved from E(0) by more than 100 |E(0)|",
        ],
    );
    assert!(diverged_step(&stderr(&out)) > 0, "{}", stderr(&out));
    for f in ["timeseries.csv", "summary.csv", "energy.png"] {
        assert!(o.join(f).exists(), "{f} not written");
    }
    // The trapezoidal rule's growth on the bar (2.8 %) is a result, not a divergence.
    let out = run(
        &["cases/bar1d.toml", "--beta", "0.25"],
        &["--out", o.to_str().unwrap()],
    );
    assert!(out.status.success(), "{}", stderr(&out));
}

#[test]
fn a_sweep_records_a_non_finite_run_as_diverged_and_the_report_shows_it() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = "[[sweep]]\nname = \"hostile\"\nspaces = [\"standard\"]\n\
                 schemes = [{ scheme = \"newmark\", beta = 0.5, gamma = 0.5 }]\n\
                 elements = 40\ndt = 0.0125\nlevels = 1\n";
    let text = std::fs::read_to_string("cases/bar1d.toml").unwrap();
    let head = &text[..text.find("[[sweep]]").unwrap()];
    let path = dir.path().join("bar.toml");
    std::fs::write(
        &path,
        format!("{}{sweep}", head.replace("lift = 0.5", "lift = 1.3e154")),
    )
    .unwrap();
    let o = dir.path().join("o");
    let out = dyncontact(&[
        "sweep",
        path.to_str().unwrap(),
        "--out",
        o.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let records = std::fs::read_to_string(o.join("records.csv")).unwrap();
    let row = records.lines().nth(1).unwrap();
    assert!(
        row.contains(",diverged,") && row.contains("energy is inf"),
        "{row}"
    );
    let merged = dir.path().join("m");
    let out = dyncontact(&[
        "merge",
        o.join("records.csv").to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let index = std::fs::read_to_string(merged.join("index.md")).unwrap();
    assert!(index.contains("diverged"), "{index}");
}

/// A Gmsh MSH 4.1 file of the unit square split into four 3-node triangles around a centre node
/// at `centre`, the bottom edge in the physical group `contact`.
fn fan_msh(centre: [f64; 2]) -> String {
    let [cx, cy] = centre;
    format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
         $PhysicalNames\n2\n1 1 \"contact\"\n2 2 \"body\"\n$EndPhysicalNames\n\
         $Entities\n0 1 1 0\n1 0 0 0 1 0 0 1 1 0\n1 0 0 0 1 1 0 1 2 0\n$EndEntities\n\
         $Nodes\n1 5 1 5\n2 1 0 5\n1\n2\n3\n4\n5\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n{cx} {cy} 0\n$EndNodes\n\
         $Elements\n2 5 1 5\n1 1 1 1\n1 1 2\n2 1 2 4\n2 1 2 5\n3 2 3 5\n4 3 4 5\n5 4 1 5\n\
         $EndElements\n"
    )
}

#[test]
fn a_tangled_gmsh_mesh_is_refused_naming_the_cells() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let mesh = dir.path().join("fan.msh");
    let args = |m: &Path| {
        let m = m.to_str().unwrap().to_string();
        [
            "run",
            "cases/block2d.toml",
            "--mesh",
            &m,
            "--t-end",
            "0.01",
            "--out",
            o,
        ]
        .map(String::from)
    };
    let run = |a: [String; 8]| dyncontact(&a.iter().map(String::as_str).collect::<Vec<_>>());
    std::fs::write(&mesh, fan_msh([0.5, 0.5])).unwrap();
    let out = run(args(&mesh));
    assert!(out.status.success(), "{}", stderr(&out));
    // The centre node moved out through the right side: every triangle alone is valid, but
    // one is flipped over its neighbours and the cells cover 1.5 times the square.
    std::fs::write(&mesh, fan_msh([1.5, 0.25])).unwrap();
    let out = run(args(&mesh));
    assert_clear_error(
        &out,
        &["fan.msh", "element 2 and element 3", "face (nodes [2, 5])"],
    );
    // Messages number nodes and cells as the file does (they counted from 0); a face of Γ_C
    // through one node twice is named (it was blamed on `material.density`, with h = 0).
    let degenerate = fan_msh([0.5, 0.5]).replace("1 1 1 1\n1 1 2\n", "1 1 1 1\n1 1 1\n");
    std::fs::write(&mesh, degenerate).unwrap();
    assert_clear_error(
        &run(args(&mesh)),
        &["fan.msh", "element 1 of group `contact` has node 1 twice"],
    );
    // A file cut short: the section left open is named (it was "Unknown error occurred"), and
    // the parser's place in the file in one line, without its dump of up to 700 bytes in hex.
    let text = fan_msh([0.5, 0.5]);
    std::fs::write(&mesh, text.replace("$EndElements\n", "")).unwrap();
    assert_clear_error(
        &run(args(&mesh)),
        &["fan.msh", "section $Elements has no $EndElements line"],
    );
    std::fs::write(&mesh, &text[..text.find("$EndNodes").unwrap() - 8]).unwrap();
    let out = run(args(&mesh));
    assert_clear_error(
        &out,
        &["fan.msh", "not a readable MSH 4.1 file: in node section"],
    );
    assert!(!stderr(&out).contains("Hex dump"), "{}", stderr(&out));
}

/// A Gmsh `contact` group the plane below cannot meet was accepted and the body sank through
/// the plane ("max penetration 0", the bottom 0.4 below it at t = 4): the top edge of the unit
/// square (outward normal +e_y), or a side edge above a lower corner of the body. A group with
/// faces that face away beside others (the whole boundary) runs.
#[test]
fn a_gmsh_contact_group_the_plane_cannot_meet_is_refused_naming_the_face_or_node() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let mesh = dir.path().join("sq.msh");
    let args = [
        "cases/block2d.toml",
        "--mesh",
        mesh.to_str().unwrap(),
        "--dt",
        "0.01",
        "--t-end",
        "0.01",
    ];
    let with = |edge: &str| fan_msh([0.5, 0.5]).replace("1 1 1 1\n1 1 2\n", edge);
    std::fs::write(&mesh, with("1 1 1 1\n1 3 4\n")).unwrap();
    let out = run(&args, &["--out", o.to_str().unwrap()]);
    assert_clear_error(&out, &["sq.msh", "element 1 (nodes [3, 4])", "faces away"]);
    // A side edge (n_y = 0) down to the lowest corner is not: the other bottom corner meets the
    // plane outside Γ_C (the bottom edge sank through, the left corner held). The whole
    // boundary (a body that may roll: its top faces face away) runs.
    std::fs::write(&mesh, with("1 1 1 1\n1 4 1\n")).unwrap();
    let out = run(&args, &["--out", o.to_str().unwrap()]);
    assert_clear_error(&out, &["sq.msh", "node 2", "outside Γ_C"]);
    let whole = fan_msh([0.5, 0.5]).replace(
        "$Elements\n2 5 1 5\n1 1 1 1\n1 1 2\n",
        "$Elements\n2 8 1 8\n1 1 1 4\n1 1 2\n6 2 3\n7 3 4\n8 4 1\n",
    );
    std::fs::write(&mesh, whole).unwrap();
    let out = run(&args, &["--out", o.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    // The right edge raised by 0.5 above the left corner: node 1 would meet the plane first.
    let raised = with("1 1 1 1\n1 2 3\n").replace(
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 0\n",
        "0 0 0\n1 0.5 0\n1 1.5 0\n0 1.5 0\n0.5 1 0\n",
    );
    std::fs::write(&mesh, raised).unwrap();
    let out = run(&args, &["--out", o.to_str().unwrap()]);
    assert_clear_error(
        &out,
        &[
            "sq.msh",
            "node 1",
            "lies below Γ_C's lowest vertex (x_2 = 0.5) by 5.000e-1",
        ],
    );
    // A plate 1e-7 thick (h = 0.5 along Γ_C): its top corner is 1e-7 above Γ_C, within the
    // tolerance 1e-6 h; it said "lies as low as Γ_C's lowest vertex or lower (by -1.000e-7".
    let thin = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
         $PhysicalNames\n2\n1 1 \"contact\"\n2 2 \"body\"\n$EndPhysicalNames\n\
         $Entities\n0 1 1 0\n1 0 0 0 1 0 0 1 1 0\n1 0 0 0 1 1e-7 0 1 2 0\n$EndEntities\n\
         $Nodes\n1 6 1 6\n2 1 0 6\n1\n2\n3\n4\n5\n6\n\
         0 0 0\n0.5 0 0\n1 0 0\n1 1e-7 0\n0.5 1e-7 0\n0 1e-7 0\n$EndNodes\n\
         $Elements\n2 4 1 4\n1 1 1 2\n1 1 2\n2 2 3\n2 1 3 2\n3 1 2 5 6\n4 2 3 4 5\n\
         $EndElements\n";
    std::fs::write(&mesh, thin).unwrap();
    let out = run(&args, &["--out", o.to_str().unwrap()]);
    assert_clear_error(
        &out,
        &[
            "sq.msh",
            "node 6 at [0.0, 1e-7]",
            "lies 1.000e-7 above Γ_C's lowest vertex (x_2 = 0), less than the tolerance 5.000e-7",
            "too thin",
        ],
    );
    assert!(!stderr(&out).contains("by -"), "{}", stderr(&out));
}

/// `two_bars` ran `lengths = [1.0, 1.0, 7.0]` as [1.0, 1.0], the third entry unread (and
/// `[1.0]` was a TOML type error): both are refused as `geometry.size` is, "needs 2 entries".
#[test]
fn two_bars_lengths_of_other_than_two_entries_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    for lengths in ["[1.0, 1.0, 7.0]", "[1.0]"] {
        let to = format!("lengths = {lengths}");
        let case = edited(
            dir.path(),
            "two_bars.toml",
            &[("lengths = [1.0, 1.0]", &to)],
        );
        let out = run(&[&case], &["--out", o.to_str().unwrap()]);
        assert_clear_error(
            &out,
            &["two_bars.toml", "geometry.lengths", "needs 2 entries"],
        );
    }
}

/// A penalty so soft that the contact vanished ran with exit 0, the block falling through the
/// plane by its whole travel (max penetration 5.0e-2): `--penalty 1e300` (a relative
/// compliance), `--penalty-gamma 1e-300` and `--penalty-stiffness 1e-300` (relative
/// stiffnesses). Each is refused below 1e-12 of its stiffness scale, named; a soft penalty of a
/// compliance study (r = 1e6) runs.
#[test]
fn a_penalty_too_soft_to_hold_the_body_is_refused_naming_the_parameter_and_its_scale() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let block = [
        "cases/block2d.toml",
        "--elements",
        "2",
        "--dt",
        "0.01",
        "--t-end",
        "0.5",
    ];
    let refused = [
        (
            &["--contact", "penalty", "--penalty", "1e300"][..],
            "run.penalty",
            "max D_ii",
        ),
        (
            &["--scheme", "hauret_le_tallec", "--penalty-gamma", "1e-300"],
            "run.penalty_gamma",
            "(B_N K B_Nᵀ)_ii",
        ),
        (
            &[
                "--scheme",
                "explicit_penalty",
                "--space",
                "lumped",
                "--penalty-stiffness",
                "1e-300",
            ],
            "run.penalty_stiffness",
            "max_i K_ii",
        ),
    ];
    for (flags, field, scale) in refused {
        let out = run(&[&block[..], flags].concat(), &["--out", o]);
        assert_clear_error(&out, &["block2d.toml", field, scale, "below 1e-12"]);
    }
    let out = run(
        &block,
        &["--contact", "penalty", "--penalty", "1e6", "--out", o],
    );
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Messages of extreme inputs: run.t_end off the grid of dt = 1e-320 printed both end times in
/// about 330 digits; a step matrix without stiffness quoted a sentence as run.dt's "value"
/// (`"k = 1.000e-304 in the step matrix m M + k K"`); a contact solver failure and a divergence
/// lacked the case file that every other error of `run` names first.
#[test]
fn extreme_values_are_named_short_and_run_time_errors_name_the_case_file() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let spring = |flags: &[&str]| {
        run(
            &[&["cases/spring_mass.toml"], flags].concat(),
            &["--out", o],
        )
    };
    let out = spring(&["--dt", "1e-320", "--t-end", "1e-318"]);
    assert_clear_error(
        &out,
        &["run.t_end", "would end at 9.9999e-319 or 1.00999e-318"],
    );
    assert!(stderr(&out).len() < 400, "{}", stderr(&out));
    let out = spring(&["--beta", "1e-300"]);
    assert_clear_error(&out, &["`run.dt`: 0.01 (", "beta=1e-300", "k = 1.000e-304"]);
    let out = spring(&["--dt", "1e-300", "--t-end", "1e-299"]);
    assert_clear_error(
        &out,
        &["`run.dt (--dt)`: 1e-300 (", "k = 0 (it underflows)"],
    );
    // μ = 1e300 is solved now (the base sticks and the block tips off the plane); Gauss–Seidel
    // at μ = 100 on this mesh is repelled by the solution (docs/methods.md, "Large μ").
    let out = run(
        &[
            "cases/slide2d.toml",
            "--friction",
            "1e300",
            "--t-end",
            "0.5",
        ],
        &["--out", o],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let out = run(
        &[
            "cases/slide2d.toml",
            "--friction",
            "100",
            "--contact-solver",
            "projected_gauss_seidel",
            "--t-end",
            "0.5",
        ],
        &["--out", o],
    );
    assert_clear_error(
        &out,
        &["error: cases/slide2d.toml: contact solver failed at step 1"],
    );
    let fast = edited(
        dir.path(),
        "two_bars.toml",
        &[("velocity = ", "velocity = 1e200 #")],
    );
    let out = run(&[&fast], &["--out", o]);
    assert_clear_error(
        &out,
        &[&format!("error: {fast}: solution diverged at step 0")],
    );
}

#[test]
fn a_final_time_off_the_time_grid_is_refused_naming_both_values() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let out = dyncontact(&[
        "run",
        "cases/spring_mass.toml",
        "--dt",
        "0.4",
        "--t-end",
        "1",
        "--out",
        o,
    ]);
    assert_clear_error(
        &out,
        &[
            "run.t_end (--t-end)`: 1.0",
            "run.dt = 0.4",
            "t_end/dt = 2.5",
            "0.8 or 1.2",
        ],
    );
    // On the grid, the last sample is t_end itself.
    let out = dyncontact(&[
        "run",
        "cases/spring_mass.toml",
        "--dt",
        "0.25",
        "--t-end",
        "1",
        "--out",
        o,
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let series = std::fs::read_to_string(dir.path().join("o/timeseries.csv")).unwrap();
    let last = series.lines().last().unwrap();
    assert!(last.starts_with("1.000000000000e0,"), "{last}");
}

/// A run killed while writing its outputs (the file-size limit `ulimit -f` sends SIGXFSZ in
/// the middle of timeseries.csv) leaves the previous run's files complete under their names.
#[cfg(unix)]
#[test]
fn a_run_killed_while_writing_leaves_the_previous_outputs_whole() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let os = o.to_str().unwrap();
    let first = dyncontact(&["run", "cases/spring_mass.toml", "--t-end", "1", "--out", os]);
    assert!(first.status.success(), "{}", stderr(&first));
    let read = |f: &str| std::fs::read(o.join(f)).unwrap();
    let before: Vec<Vec<u8>> = ["timeseries.csv", "summary.csv", "energy.png", "energy.svg"]
        .map(read)
        .into();
    // 10⁵ steps: a timeseries.csv of about 10 MB, killed at 32–64 KiB.
    let killed = Command::new("sh")
        .args(["-c", "ulimit -f 64 && exec \"$0\" \"$@\""])
        .arg(env!("CARGO_BIN_EXE_dyncontact"))
        .args(["run", "cases/spring_mass.toml", "--dt", "1e-4", "--out", os])
        .output()
        .unwrap();
    assert!(!killed.status.success(), "the limit did not stop the run");
    let after: Vec<Vec<u8>> = ["timeseries.csv", "summary.csv", "energy.png", "energy.svg"]
        .map(read)
        .into();
    assert!(before == after, "an output was changed by the killed run");
}

#[test]
fn report_and_sweep_errors_name_the_case_file_and_the_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let cases = dir.path().join("cases");
    std::fs::create_dir(&cases).unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let bad = edited(&cases, "bar1d.toml", &[("density = 1.0", "density = -1.0")]);
    let out = dyncontact(&["report", "--cases", cases.to_str().unwrap(), "--out", o]);
    assert_clear_error(
        &out,
        &[&format!("{bad}: invalid value for `material.density`")],
    );
    let out = dyncontact(&["sweep", &bad, "--out", o]);
    assert_clear_error(
        &out,
        &[&format!("{bad}: invalid value for `material.density`")],
    );
    // A level of a sweep that misses t_end: the file, the sweep, the job and the field.
    let bad = edited(&cases, "bar1d.toml", &[("dt = 0.025", "dt = 0.07")]);
    let out = dyncontact(&["sweep", &bad, "--quick", "--out", o]);
    assert_clear_error(
        &out,
        &[
            &format!("{bad}: sweep `orders`, standard × newmark"),
            "level 0",
            "run.t_end",
        ],
    );
}

/// A `[[sweep]]` table that would ignore what it says or name files outside the report is
/// refused before any run, naming the field: `refinements` beside `levels` (which ran one
/// level), a degree for a space it does not run, a space listed twice (blamed on "two case files
/// of one name?"), a name with a `/` (every run went first, then a plotting error).
#[test]
fn sweep_tables_that_would_ignore_a_field_or_misname_a_file_are_refused_first() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    for (from, to, needles) in [
        (
            "levels = 5",
            "levels = 5\nrefinements = [{ dt = 0.01 }]",
            &["sweep.orders.dt`", "not with `refinements`"][..],
        ),
        (
            "quick_levels = 3",
            "quick_levels = 3\ndegree = { no_such_space = 2 }",
            &[
                "sweep.orders.degree.no_such_space`: 2",
                "not a space of this table",
            ],
        ),
        (
            "spaces = [\"standard\"]",
            "spaces = [\"standard\", \"standard\"]",
            &["sweep.orders.spaces`: \"standard\"", "listed twice"],
        ),
        (
            "quick_levels = 3",
            "quick_levels = 3\nfriction = -1.0",
            &["sweep.orders.friction`: -1.0"],
        ),
        (
            "name = \"orders\"",
            "name = \"a/b\"",
            &["sweep.name`: \"a/b\"", "part of file names"],
        ),
        // The same level twice: orders.csv had NaN orders (found 2026-11-29, fifth round).
        (
            "dt = 0.01\nratio = 2\nlevels = 5",
            "refinements = [{ dt = 0.01 }, { dt = 0.005 }, { dt = 0.01 }]",
            &["sweep.orders.refinements`", "a level listed twice"],
        ),
    ] {
        let bad = edited(dir.path(), "spring_mass.toml", &[(from, to)]);
        let start = Instant::now();
        let out = dyncontact(&["sweep", &bad, "--quick", "--out", o]);
        assert_clear_error(&out, needles);
        assert!(!stderr(&out).contains("running"), "{}", stderr(&out));
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "{from}: ran first"
        );
    }
    // A sweep's elements or degree out of range: every run was recorded `failed` naming
    // `mesh.elements` or `mesh.degree` (not the table's field), and the sweep exited 0.
    for (from, to, needle) in [
        (
            "elements = 20\ndt = 0.025",
            "elements = 0\ndt = 0.025",
            "`sweep.orders.elements`: 0 (must be ≥ 1)",
        ),
        (
            "singular_dynamic = 2, modified",
            "singular_dynamic = 7, modified",
            "`sweep.orders.degree`: { singular_dynamic = 7 } (a degree must be 1 or 2)",
        ),
    ] {
        let bad = edited(dir.path(), "bar1d.toml", &[(from, to)]);
        let out = dyncontact(&["sweep", &bad, "--quick", "--out", o]);
        assert_clear_error(&out, &["bar1d.toml", needle]);
        assert!(!stderr(&out).contains("running"), "{}", stderr(&out));
    }
}

/// A run's failure in a sweep names the field as the sweep set it: `run.dt (sweep.orders.dt)`
/// (it said `run.dt`: 0.025 where the case file's `[run] dt` is 0.0125), as the command line's
/// `run.dt (--dt)`.
#[test]
fn a_sweep_run_s_failure_names_the_sweep_s_field() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let out = dyncontact(&["sweep", "cases/bar1d.toml", "--quick", "--out", o]);
    assert!(out.status.success(), "{}", stderr(&out));
    let records = std::fs::read_to_string(dir.path().join("o/records.csv")).unwrap();
    let reasons: Vec<&str> = records
        .lines()
        .filter(|l| l.contains(",failed,") && l.contains("modified_quadrature-central"))
        .collect();
    assert!(!reasons.is_empty(), "{records}");
    for r in reasons {
        assert!(
            r.contains("`run.dt (sweep.orders.dt)`: 0.0") && r.contains("(unstable time step"),
            "{r}"
        );
    }
    let out = dyncontact(&["run", "cases/bar1d.toml", "--dt", "-1", "--out", o]);
    assert_clear_error(&out, &["`run.dt (--dt)`: -1.0"]);
}

/// `merge` reads back only what a sweep writes: every shard once (one of two shards was "11 runs
/// merged"), one row per run (the same file twice was "22 runs merged"), plain case and sweep
/// names (`../ESCAPED` wrote figures beside `--out`), finite values (records write an absent one
/// as an empty field), a positive dt, a known status.
#[test]
fn merge_refuses_records_that_no_sweep_writes() {
    let dir = tempfile::tempdir().unwrap();
    let shard = dir.path().join("s");
    let s = shard.to_str().unwrap();
    let out = dyncontact(&[
        "sweep",
        "cases/spring_mass.toml",
        "--quick",
        "--shard",
        "1/2",
        "--out",
        s,
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let records = shard.join("records-1-of-2.csv");
    let text = std::fs::read_to_string(&records).unwrap();
    let o = dir.path().join("o");
    let merge = |files: &[&Path]| {
        let mut args = vec!["merge".to_string()];
        args.extend(files.iter().map(|f| f.to_str().unwrap().to_string()));
        args.extend(["--out".to_string(), o.to_str().unwrap().to_string()]);
        dyncontact(&args.iter().map(String::as_str).collect::<Vec<_>>())
    };
    // Shard 1 of 2 alone, or twice, is not a sweep's set; a copy under another name is the
    // user's own set, whose keys must be distinct.
    assert_clear_error(
        &merge(&[&records]),
        &["not the 2 shards of a sweep", "missing: records-2-of-2.csv"],
    );
    // The same file twice, by one path or two (it said shard 2 was "given fewer than 2 times,
    // as another shard is").
    let other = shard.join("..").join("s").join("records-1-of-2.csv");
    for (twice, how) in [
        (
            [&records, &records],
            "given twice: give each records file once",
        ),
        ([&records, &other], "given twice (as "),
    ] {
        let out = merge(&twice.map(PathBuf::as_path));
        assert_clear_error(&out, &["records-1-of-2.csv", how]);
        assert!(!stderr(&out).contains("fewer"), "{}", stderr(&out));
    }
    let [mine, again] = ["mine.csv", "again.csv"].map(|f| dir.path().join(f));
    std::fs::copy(&records, &mine).unwrap();
    std::fs::copy(&records, &again).unwrap();
    assert_clear_error(
        &merge(&[&mine, &again]),
        &["column `key`", "one run, one row"],
    );
    let header_only = dir.path().join("empty.csv");
    std::fs::write(
        &header_only,
        text.lines().next().unwrap().to_string() + "\n",
    )
    .unwrap();
    assert_clear_error(&merge(&[&header_only]), &["no run"]);
    // Column `column` of the first row set to `value`.
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let with = |column: &str, value: &str| {
        let k = header.iter().position(|h| *h == column).unwrap();
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        let mut row: Vec<String> = lines[1].split(',').map(String::from).collect();
        row[k] = value.to_string();
        lines[1] = row.join(",");
        let path = dir.path().join(format!("{column}.csv"));
        std::fs::write(&path, lines.join("\n") + "\n").unwrap();
        path
    };
    for (column, value, needles) in [
        (
            "case",
            "../ESCAPED",
            &["row 2, column `case`", "part of file names"][..],
        ),
        (
            "sweep",
            "a/b",
            &["row 2, column `sweep`", "part of file names"],
        ),
        ("dt", "NaN", &["row 2, column `dt`: `NaN`", "empty field"]),
        ("dt", "-1", &["row 2, column `dt`: -1", "> 0"]),
        (
            "wall_time_s",
            "inf",
            &["row 2, column `wall_time_s`: `inf`", "finite"],
        ),
        (
            "energy_drift",
            "-inf",
            &["row 2, column `energy_drift`: `-inf`", "finite"],
        ),
        (
            "status",
            "great",
            &["row 2, column `status`: `great`", "ok, diverged"],
        ),
        // Impossible values, which then became points = 0 or a missing timings row.
        (
            "energy_drift",
            "-5",
            &["row 2, column `energy_drift`: -5", "≥ 0"],
        ),
        (
            "max_penetration",
            "-1",
            &["row 2, column `max_penetration`: -1", "≥ 0"],
        ),
        ("key", "", &["row 2, column `key`: empty"]),
        ("steps", "0", &["row 2, column `steps`: 0", "status `ok`"]),
        // The key's `-L0` against the level column, and a key of no run.
        (
            "level",
            "1",
            &["row 2, column `key`", "not the key of its row's run"],
        ),
        (
            "key",
            "other-key",
            &["row 2, column `key`: `other-key`", "not the key"],
        ),
    ] {
        assert_clear_error(&merge(&[&with(column, value)]), needles);
    }
    assert!(!dir.path().join("ESCAPED_orders_energy.png").exists());
    // A records file under a name of its own has no manifest to tell its study.
    assert_clear_error(&merge(&[&mine]), &["mine.csv", "no manifest beside it"]);
    // A name of the shard form that no sweep writes is no way around the completeness check.
    for name in [
        "records-1-of-18446744073709551616.csv",
        "records-0-of-1.csv",
        "records-01-of-1.csv",
    ] {
        let renamed = dir.path().join(name);
        std::fs::copy(&records, &renamed).unwrap();
        assert_clear_error(&merge(&[&renamed]), &[name, "does not write"]);
    }
}

/// Found by a fifth round of hostile inputs (2026-11-29): `merge` fitted the records of two
/// case files of one case (stiffness 1 and 4) as one series; `sweep --resume` copied a negative
/// energy drift from the journal; `report --resume` took edited probe series (inf, NaN, a cut
/// file, a `t` of 9.9e9) into the reference errors.
#[test]
fn merge_and_resume_refuse_what_no_run_writes() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = |case: &str, out: &str, resume: bool| {
        let o = dir.path().join(out);
        let mut args = vec!["sweep", case, "--quick", "--out", o.to_str().unwrap()];
        args.extend(resume.then_some("--resume"));
        dyncontact(&args)
    };
    let stiff = edited(
        dir.path(),
        "spring_mass.toml",
        &[("stiffness = 1.0", "stiffness = 4.0")],
    );
    for (case, out) in [("cases/spring_mass.toml", "a"), (stiff.as_str(), "b")] {
        let done = sweep(case, out, false);
        assert!(done.status.success(), "{}", stderr(&done));
    }
    let [a, b] = ["a", "b"].map(|d| dir.path().join(d).join("records.csv"));
    std::fs::rename(&b, dir.path().join("b/sm4.csv")).unwrap();
    // The stem `sm4` in b's keys, as a case file `sm4.toml` would write them.
    let text = std::fs::read_to_string(dir.path().join("b/sm4.csv")).unwrap();
    std::fs::write(&b, text.replace("\nspring_mass-", "\nsm4-")).unwrap();
    let o = dir.path().join("o");
    let out = dyncontact(&[
        "merge",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--out",
        o.to_str().unwrap(),
    ]);
    assert_clear_error(
        &out,
        &[
            "row 2, column `key`",
            "case file `sm4`",
            "case file `spring_mass`",
        ],
    );
    // A journal row with a negative drift.
    let journal = dir.path().join("a/journal.csv");
    let text = std::fs::read_to_string(&journal).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == "energy_drift").unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut row: Vec<String> = lines[1].split(',').map(String::from).collect();
    row[k] = "-7".into();
    lines[1] = row.join(",");
    std::fs::write(&journal, lines.join("\n") + "\n").unwrap();
    let out = sweep("cases/spring_mass.toml", "a", true);
    assert_clear_error(&out, &["journal", "row 2, column `energy_drift`: -7"]);
    // Probe series (block2d has no exact solution): 10 steps, 11 samples.
    let text = std::fs::read_to_string("cases/block2d.toml").unwrap();
    let keep = text.split("\n[[").next().unwrap().to_string();
    let case = dir.path().join("block2d.toml");
    let table = "\n[[sweep]]\nname = \"p\"\nspaces = [\"standard\"]\n\
                 schemes = [{ scheme = \"newmark\", beta = 0.5, gamma = 0.5 }]\n\
                 elements = 2\ndt = 0.05\nt_end = 0.5\nratio = 2\nlevels = 2\n";
    std::fs::write(&case, keep + table).unwrap();
    let case = case.to_str().unwrap();
    let done = sweep(case, "p", false);
    assert!(done.status.success(), "{}", stderr(&done));
    let probe = dir
        .path()
        .join("p/probes/block2d-p-standard-newmark-beta=0.5;gamma=0.5-L0.csv");
    let good = std::fs::read_to_string(&probe).unwrap();
    let second = good.lines().nth(2).unwrap().to_string();
    let (t, rest) = second.split_once(',').unwrap();
    let (u, _) = rest.split_once(',').unwrap();
    let cut: String = good.lines().take(2).map(|l| format!("{l}\n")).collect();
    for (edited, needles) in [
        (
            good.replacen(&second, &format!("{t},{u},inf"), 1),
            &["row 3, column `sigma_contact`: inf"][..],
        ),
        (
            good.replacen(&second, &format!("{t},NaN,{u}"), 1),
            &["row 3, column `u_contact`: NaN"],
        ),
        (
            good.replacen(&second, &format!("9.9e9,{rest}"), 1),
            &["row 3, column `t`: 9900000000", "n·dt"],
        ),
        (cut, &["1 rows, not the 11 samples", "10 steps"]),
    ] {
        std::fs::write(&probe, edited).unwrap();
        let out = sweep(case, "p", true);
        assert_clear_error(&out, &[&["probe series", "-L0.csv"][..], needles].concat());
    }
    std::fs::write(&probe, good).unwrap();
    let out = sweep(case, "p", true);
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Found by a third round of hostile inputs (2026-11-29, later): a field the run would ignore
/// or that breaks the run is named itself, not a field it would have blamed.
#[test]
fn fields_that_break_or_do_nothing_are_named_themselves() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let run = |case: &str, extra: &[&str]| run(&[case], &[extra, &["--out", o]].concat());
    // Each edited file in a directory of its own (the same name would be overwritten).
    let own = |k: &str| {
        let d = dir.path().join(k);
        std::fs::create_dir_all(&d).unwrap();
        d
    };
    let block = |k: &str, from: &str, to: &str| edited(&own(k), "block2d.toml", &[(from, to)]);
    for (case, extra, needles) in [
        // Nitsche's γ = h/(γ₀ E): its products overflowed into K (blamed on material.young), or
        // 1/γ did at step 0 ("energy is NaN").
        (
            "cases/bar1d.toml".to_string(),
            &["--contact", "nitsche", "--nitsche-gamma", "1e-308"][..],
            &["`run.nitsche_gamma (--nitsche-gamma)`: 1e-308", "too small"][..],
        ),
        (
            "cases/bar1d.toml".to_string(),
            &["--contact", "nitsche", "--nitsche-gamma", "1e308"],
            &["`run.nitsche_gamma (--nitsche-gamma)`: 1e308", "γ and 1/γ"],
        ),
        // A slope tilts gravity: without gravity it changed nothing.
        (
            block("slope", "gravity = 0.0", "gravity = 0.0\nslope = 0.3"),
            &[],
            &["`geometry.slope`: 0.3", "geometry.gravity = 0"],
        ),
        // Cells of aspect ratio 1e39: a failed factorisation, "NonPositivePivot { index: 3 }".
        (
            block("flat", "size = [1.0, 1.0]", "size = [1.0, 1e-40]"),
            &[],
            &["`geometry.size`: [1.0, 1e-40]", "at most 1e6"],
        ),
        // Gravity in a Hertz impact was blamed on the valid velocity.
        (
            edited(
                dir.path(),
                "hertz2d.toml",
                &[("gravity = 0.0", "gravity = 1.0")],
            ),
            &[],
            &["`geometry.gravity`: 1.0", "no gravity"],
        ),
        // A Gmsh file replaced the [master] box without a word.
        (
            "cases/slide_on_block2d.toml".to_string(),
            &["--mesh", "cases/meshes/two_discs.msh", "--t-end", "0.1"],
            &["`master.mesh`", "this table would be ignored"],
        ),
        // The incidence turns a velocity that roll2d does not have (30° is in range).
        (
            "cases/roll2d.toml".to_string(),
            &["--incidence", "30"],
            &["`--incidence`: 30.0", "starts at rest"],
        ),
        // A bar 2 of 1e-16 panicked building the exact solution (1e-6: minutes).
        (
            edited(
                &own("short"),
                "two_bars.toml",
                &[("[1.0, 1.0]", "[1.0, 1e-16]")],
            ),
            &[],
            &["`geometry.lengths[1]`: 1e-16", "crossings"],
        ),
        // Hertz errors were computed for a box.
        (
            edited(
                &own("box"),
                "hertz2d.toml",
                &[("shape = \"disc\"", "shape = \"box\"\nsize = [1.0, 1.0]")],
            ),
            &[],
            &["`geometry.shape`: \"box\"", "curved body"],
        ),
        // Body 2's tables were named as body 1's.
        (
            edited(
                &own("master"),
                "slide_on_block2d.toml",
                &[("elements = 12", "elements = 0")],
            ),
            &[],
            &["`master.mesh.elements`: 0"],
        ),
        // Fields of the other shape, and body 2's lift, changed nothing (found 2026-11-29).
        (
            block(
                "radius",
                "size = [1.0, 1.0]",
                "size = [1.0, 1.0]\nradius = 1.0",
            ),
            &[],
            &["`geometry.radius`: 1.0", "has no radius"],
        ),
        (
            block(
                "grading",
                "cells = \"quad\"",
                "cells = \"quad\"\ngrading = 4.0",
            ),
            &[],
            &["`mesh.grading`: 4.0", "uniform"],
        ),
        (
            edited(
                &own("size"),
                "hertz2d.toml",
                &[("gravity = 0.0", "gravity = 0.0\nsize = [1.0, 1.0]")],
            ),
            &[],
            &["`geometry.size`: [1.0, 1.0]", "sized by geometry.radius"],
        ),
        (
            edited(
                &own("lift"),
                "slide_on_block2d.toml",
                &[(
                    "shape = \"box\"\nsize = [2.0, 0.5]",
                    "shape = \"box\"\nlift = 0.1\nsize = [2.0, 0.5]",
                )],
            ),
            &[],
            &["`master.geometry.lift`: 0.1", "body 1's geometry.lift"],
        ),
        // A slide has no incidence (it blamed geometry.velocity, which the file sets to 0).
        (
            "cases/slide2d.toml".to_string(),
            &["--incidence", "45"],
            &["`--incidence`: 45.0", "no incidence"],
        ),
        // A friction coefficient too large for the Newton solver: its failure names μ.
        (
            "cases/slide_on_block2d.toml".to_string(),
            &["--friction", "1e6"],
            &[
                "contact solver failed at step",
                "μ = 1000000.0 (contact.friction)",
            ],
        ),
        // An initial state that overflows: step 0 says so.
        (
            block("fast", "velocity = -0.1", "velocity = -1e200"),
            &[],
            &[
                "diverged at step 0",
                "in the initial state",
                "initial condition",
            ],
        ),
    ] {
        assert_clear_error(&run(&case, extra), needles);
    }
    // A diverged run wrote the non-finite sample's ParaView file (von_mises inf) first.
    let heavy = block("heavy", "gravity = 0.0", "gravity = 1e300");
    let fields = dir.path().join("fields");
    let vtu = [
        "--t-end",
        "0.01",
        "--elements",
        "2",
        "--vtu",
        fields.to_str().unwrap(),
    ];
    assert_clear_error(&run(&heavy, &vtu), &["diverged at step 1"]);
    let written: Vec<String> = std::fs::read_dir(&fields)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".vtu"))
        .collect();
    assert_eq!(written, ["block2d_000000.vtu"]);
    // A box under a graded disc takes body 1's [mesh] without its grading (it was refused as
    // master.mesh.grading, a field the file does not set).
    let master = "[master]\n[master.geometry]\nshape = \"box\"\nsize = [2.0, 0.5]\n\
                  velocity = 0.0\n\n[[sweep]]";
    let boxed = edited(&own("boxed"), "two_discs.toml", &[("[[sweep]]", master)]);
    let out = run(&boxed, &["--t-end", "0.1"]);
    assert!(out.status.success(), "{}", stderr(&out));
}

/// A FIFO where a study writes its profile or its lock file blocked forever (opening it for
/// writing waits for a reader) or failed with "Invalid argument": refused as not a regular file.
#[cfg(unix)]
#[test]
fn a_fifo_as_profile_or_lock_file_is_refused_without_opening_it() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("profile.csv");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        return; // no mkfifo here
    }
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let args = [
        "report",
        "--quick",
        "--case",
        "spring_mass",
        "--out",
        o,
        "--profile",
    ];
    let out = dyncontact_within(
        &[&args[..], &[fifo.to_str().unwrap()]].concat(),
        Duration::from_secs(30),
    );
    assert_clear_error(&out, &["`--profile`", "not a regular file (a FIFO)"]);
    std::fs::create_dir_all(dir.path().join("o")).unwrap();
    let lock = dir.path().join("o/journal.csv.lock");
    assert!(Command::new("mkfifo")
        .arg(&lock)
        .status()
        .unwrap()
        .success());
    let out = dyncontact_within(
        &["sweep", "cases/spring_mass.toml", "--quick", "--out", o],
        Duration::from_secs(30),
    );
    assert_clear_error(&out, &["journal.csv.lock", "not a regular file (a FIFO)"]);
}

/// What a study would mix or drop without a word: two case files of one case (two spring_mass
/// files of different stiffness were fitted as one series), a journal row edited to another
/// scheme (`--resume` added a kane series to a sweep without kane), a `[[history]]` whose runs
/// all fail (its figures vanished, exit 0) or whose time steps are not positive.
#[test]
fn a_study_refuses_what_it_would_mix_or_drop() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let stiff = edited(
        dir.path(),
        "spring_mass.toml",
        &[("stiffness = 1.0", "stiffness = 2.0")],
    );
    let out = dyncontact(&[
        "sweep",
        "cases/spring_mass.toml",
        &stiff,
        "--quick",
        "--out",
        o,
    ]);
    assert_clear_error(&out, &["`case`: \"spring_mass\"", "would mix"]);
    // A journal row edited by hand.
    let out = dyncontact(&["sweep", "cases/spring_mass.toml", "--quick", "--out", o]);
    assert!(out.status.success(), "{}", stderr(&out));
    let journal = dir.path().join("o/journal.csv");
    let text = std::fs::read_to_string(&journal).unwrap();
    let edited_row = text.replacen(",newmark,", ",kane,", 1);
    assert_ne!(text, edited_row);
    std::fs::write(&journal, edited_row).unwrap();
    let out = dyncontact(&[
        "sweep",
        "cases/spring_mass.toml",
        "--quick",
        "--resume",
        "--out",
        o,
    ]);
    assert_clear_error(&out, &["journal", "standard × kane", "not that run"]);
    // Histories: every run refused (an alpha with newmark), or no positive time step.
    let history = "\n[[history]]\nname = \"bad\"\nspaces = [\"standard\"]\ndts = [DT]\n\
                   scheme = { scheme = \"newmark\", alpha = -0.1 }\n";
    for (dt, needles) in [
        (
            "0.001",
            &[
                "block2d.toml",
                "history.bad",
                "every run of the table failed",
            ][..],
        ),
        ("-0.001", &["block2d.toml", "history.bad.dts", "-0.001"]),
    ] {
        let cases = dir.path().join(format!("cases{dt}"));
        std::fs::create_dir_all(&cases).unwrap();
        let text = std::fs::read_to_string("cases/block2d.toml").unwrap();
        let keep = text.split("\n[[").next().unwrap().to_string();
        std::fs::write(
            cases.join("block2d.toml"),
            keep + &history.replace("DT", dt),
        )
        .unwrap();
        let out = dyncontact(&[
            "report",
            "--quick",
            "--cases",
            cases.to_str().unwrap(),
            "--out",
            o,
        ]);
        assert_clear_error(&out, needles);
    }
}

/// What the checks on read-back and on two-body files must still accept (a review of them): a
/// run whose case fails to build (a level beyond the memory) is a failed row the journal reads
/// back, with its case named (it was written with an empty case, which the name check then
/// refused after every run); `[master.geometry]` beside a two-body Gmsh file gives body 2's
/// velocity; `--profile /dev/null` writes into a device.
#[test]
fn what_a_study_writes_or_a_case_gives_is_read_back_and_run() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let text = std::fs::read_to_string("cases/block2d.toml").unwrap();
    let keep = text.split("\n[[").next().unwrap().to_string();
    let big = dir.path().join("big.toml");
    std::fs::write(
        &big,
        keep + "\n[[sweep]]\nname = \"big\"\nspaces = [\"standard\"]\n\
                schemes = [{ scheme = \"newmark\", beta = 0.5, gamma = 0.5 }]\n\
                refinements = [{ elements = 4, dt = 0.01 }, { elements = 400000, dt = 0.005 }]\n\
                t_end = 0.1\n",
    )
    .unwrap();
    let big = big.to_str().unwrap();
    for resume in [&[][..], &["--resume"]] {
        let out = dyncontact(&[&["sweep", big, "--out", o][..], resume].concat());
        assert!(out.status.success(), "{resume:?}: {}", stderr(&out));
        let said = String::from_utf8_lossy(&out.stdout);
        assert!(said.contains("2 runs, 1 not ok"), "{said}");
    }
    let records = std::fs::read_to_string(dir.path().join("o/records.csv")).unwrap();
    let failed = records.lines().find(|l| l.contains(",failed,")).unwrap();
    assert!(failed.contains(",block2d,standard,newmark,"), "{failed}");
    // Body 2's velocity from [master.geometry] with the discs of the Gmsh file.
    let discs = std::fs::read_to_string("cases/two_discs.toml").unwrap()
        + "\n[master.geometry]\nshape = \"disc\"\nradius = 1.0\nvelocity = -0.02\n";
    let case = dir.path().join("discs.toml");
    std::fs::write(&case, discs).unwrap();
    let mesh = [
        "--mesh",
        "cases/meshes/two_discs.msh",
        "--t-end",
        "0.1",
        "--out",
        o,
    ];
    let out = run(&[case.to_str().unwrap()], &mesh);
    assert!(out.status.success(), "{}", stderr(&out));
    let quick = [
        "report",
        "--quick",
        "--case",
        "spring_mass",
        "--out",
        o,
        "--profile",
    ];
    let out = dyncontact(&[&quick[..], &["/dev/null"]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
}

#[test]
fn a_bar_at_rest_reports_an_absolute_energy_drift_not_nan() {
    let dir = tempfile::tempdir().unwrap();
    let bar = edited(dir.path(), "bar1d.toml", &[("lift = 0.5", "lift = 0.0")]);
    let o = dir.path().join("o");
    let out = dyncontact(&["run", &bar, "--out", o.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let summary = std::fs::read_to_string(o.join("summary.csv")).unwrap();
    let (header, row) = summary.split_once('\n').unwrap();
    let drift = header.split(',').position(|c| c == "energy_drift").unwrap();
    assert_eq!(row.split(',').nth(drift), Some("0.000000000000e0"), "{row}");
    assert!(!row.contains("NaN"), "{row}");
}

#[test]
fn a_space_that_would_leave_the_bar_without_mass_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    for space in ["mass_redistribution", "mass_elimination"] {
        let out = dyncontact(&[
            "run",
            "cases/bar1d.toml",
            "--elements",
            "1",
            "--space",
            space,
            "--out",
            o.to_str().unwrap(),
        ]);
        assert_clear_error(
            &out,
            &[
                "cases/bar1d.toml: ",
                "mesh.elements (--elements)`: 1",
                space,
                "without mass",
            ],
        );
    }
}

#[test]
fn a_mass_lost_against_the_stiffness_is_refused_naming_the_density() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    // block2d was a failed factorisation ("not symmetric positive definite"), bar1d a run with
    // an energy drift of 1e270, spring_mass an exact trajectory of 10⁵ impacts.
    for (file, from, to, field) in [
        (
            "block2d.toml",
            "density = 1.0",
            "density = 1e-300",
            "material.density`: 1e-300",
        ),
        (
            "bar1d.toml",
            "density = 1.0",
            "density = 1e-300",
            "material.density`: 1e-300",
        ),
        (
            "bar1d.toml",
            "young = 1.0",
            "young = 1e300",
            "against material.young = 1e300",
        ),
        (
            "bar_flight.toml",
            "density = 1.0",
            "density = 1e-300",
            "material.density`: 1e-300",
        ),
        (
            "two_bars.toml",
            "density = 1.0",
            "density = 1e-300",
            "material.density`: 1e-300",
        ),
        (
            "spring_mass.toml",
            "mass = 1.0",
            "mass = 1e-300",
            "system.mass`: 1e-300",
        ),
    ] {
        let case = edited(dir.path(), file, &[(from, to)]);
        let out = dyncontact(&["run", &case, "--t-end", "0.1", "--out", o]);
        assert_clear_error(&out, &[field, "round-off of the stiffness"]);
    }
}

#[test]
fn a_final_time_too_far_is_blamed_on_t_end() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    // 8e16 steps: beyond a count of steps; 8e14 steps: beyond the memory of the time series.
    for (t_end, dt, why) in [
        ("1e15", "0.0125", "at most 2^53 steps"),
        ("1e300", "1e-300", "is inf steps of run.dt = 1e-300"),
        ("1e13", "0.0125", "GiB"),
    ] {
        if why == "GiB" && !Path::new("/proc/meminfo").exists() {
            continue; // no estimate of the memory available: the run would start
        }
        let out = dyncontact(&[
            "run",
            "cases/bar1d.toml",
            "--t-end",
            t_end,
            "--dt",
            dt,
            "--out",
            o,
        ]);
        assert_clear_error(&out, &["invalid value for `run.t_end (--t-end)`", why]);
    }
}

/// The memory estimate is held against the process's own limit too (`ulimit -v`, as a batch
/// scheduler sets it), not only the machine's free memory: a spring of 1.6·10⁷ steps (about
/// 3 GiB of time series) under a 2 GB address-space limit was an allocation failure, an abort
/// with status 134 (found by a hostile-input round, with 1.3·10⁸ steps under 8 GB).
#[test]
fn a_run_beyond_the_process_memory_limit_is_refused_before_it_allocates() {
    if !Path::new("/proc/self/limits").exists() {
        return; // no limits to read: the estimate is held against the free memory only
    }
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let script = format!(
        "ulimit -v 2000000 && exec {} run cases/spring_mass.toml --dt 6.103515625e-7 --out {}",
        env!("CARGO_BIN_EXE_dyncontact"),
        o.display()
    );
    let out = Command::new("sh")
        .args(["-c", &script])
        .output()
        .expect("sh runs");
    assert_clear_error(&out, &["`run.t_end`", "GiB", "ulimit -v"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    // Under 500 MB of address space, hertz3d at n = 12 (estimated 0.2 GiB resident, 0.68 GB of
    // address space at its peak) aborted in an allocation (status 134): the threads' arenas
    // are allowed for. The default bar (0.36 GB at its peak) still runs: they are not counted
    // twice once the pool has started.
    let limited = |args: &str| {
        let script = format!(
            "ulimit -v 500000 && exec {} run {args} --out {}",
            env!("CARGO_BIN_EXE_dyncontact"),
            o.display()
        );
        Command::new("sh")
            .args(["-c", &script])
            .output()
            .expect("sh runs")
    };
    let out = limited("cases/hertz3d.toml --elements 12 --dt 0.1 --t-end 0.2");
    assert_clear_error(&out, &["`mesh.elements (--elements)`: 12", "ulimit -v"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let out = limited("cases/bar1d.toml --t-end 0.5");
    assert!(out.status.success(), "{}", stderr(&out));
}

#[test]
fn options_the_run_would_ignore_are_refused_naming_the_flag_or_field() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let run = |args: &[&str]| run(args, &["--t-end", "0.5", "--out", o]);
    for (args, needles) in [
        (
            &["cases/spring_mass.toml", "--elements", "7"][..],
            &["`--elements`", "spring_mass has one dof"][..],
        ),
        (
            &[
                "cases/spring_mass.toml",
                "--scheme",
                "backward_euler",
                "--beta",
                "0.3",
            ],
            &[
                "run.beta (--beta)",
                "scheme `backward_euler`",
                "parameters are: none",
            ],
        ),
        (
            &["cases/bar1d.toml", "--alpha", "-0.1"],
            &["run.alpha (--alpha)", "scheme `newmark`", "beta, gamma"],
        ),
        (
            &["cases/bar1d.toml", "--nitsche-gamma", "10"],
            &["run.nitsche_gamma (--nitsche-gamma)", "contact `nodal`"],
        ),
        (
            &[
                "cases/hertz2d.toml",
                "--mesh",
                "cases/meshes/disc.msh",
                "--elements",
                "8",
            ],
            &["`--elements`", "not to the mesh file cases/meshes/disc.msh"],
        ),
    ] {
        assert_clear_error(&run(args), needles);
    }
    // Schemes that apply their own contact law would ignore an LCP solver (the outputs were
    // byte-identical with every solver).
    for scheme in ["explicit_penalty", "hauret_le_tallec", "taylor_flanagan"] {
        let args = [
            "cases/bar1d.toml",
            "--scheme",
            scheme,
            "--contact-solver",
            "clarabel",
        ];
        let needles = [
            "`run.contact_solver (--contact-solver)`: \"clarabel\"",
            scheme,
            "not through an LCP",
        ];
        assert_clear_error(&run(&args), &needles);
    }
    // The same parameter written in the case file is named as the file's field, not as a flag.
    let text = std::fs::read_to_string("cases/spring_mass.toml").unwrap();
    let file = dir.path().join("euler.toml");
    std::fs::write(
        &file,
        text.replacen("scheme = \"newmark\"", "scheme = \"backward_euler\"", 1),
    )
    .unwrap();
    let out = run(&[file.to_str().unwrap()]);
    assert_clear_error(&out, &["`run.beta`", "scheme `backward_euler`"]);
    assert!(!stderr(&out).contains("--beta"), "{}", stderr(&out));
    // The case file's β and γ are Newmark's: another scheme drops them rather than refuse.
    let out = run(&["cases/bar1d.toml", "--scheme", "backward_euler"]);
    assert!(out.status.success(), "{}", stderr(&out));
    // A physical group names Γ_C in a Gmsh file only.
    let text = std::fs::read_to_string("cases/block2d.toml").unwrap();
    let case = dir.path().join("group.toml");
    std::fs::write(&case, format!("{text}\n[contact]\ngroup = \"bottom\"\n")).unwrap();
    let out = run(&[case.to_str().unwrap()]);
    assert_clear_error(&out, &["contact.group`: \"bottom\"", "Gmsh mesh"]);
}

/// Two studies into one directory: the second is refused naming the first's process; once the
/// first is killed, its lock file is taken over.
#[test]
fn a_second_study_into_the_same_directory_is_refused_naming_the_first() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().to_str().unwrap();
    let (mut first, pid) = holding_the_lock(&["report", "--quick", "--out", o], dir.path());
    let lock = dir.path().join("journal.csv.lock");
    let second = dyncontact(&["sweep", "cases/spring_mass.toml", "--quick", "--out", o]);
    first.kill().unwrap();
    first.wait().unwrap();
    assert_clear_error(&second, &["journal.csv.lock", &format!("(process {pid})")]);
    assert!(lock.exists(), "a killed study cannot remove its lock file");
    let third = dyncontact(&["sweep", "cases/spring_mass.toml", "--quick", "--out", o]);
    assert!(third.status.success(), "{}", stderr(&third));
    assert!(!lock.exists(), "a study that ends removes its lock file");
}

/// Found by a second round of hostile inputs (2026-11-29): a parameter the time-scale check
/// cannot measure is named itself, not the density it would have blamed (a mesh node at NaN, a
/// negative stiffness or mass, an element count beyond the memory), and material parameters
/// whose products overflow name the matrix and the fields instead of failing in the
/// factorisation.
#[test]
fn what_the_time_scale_cannot_measure_is_named_before_it() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let mesh = dir.path().join("fan.msh");
    std::fs::write(&mesh, fan_msh([f64::NAN, 0.5])).unwrap();
    let mesh = mesh.to_str().unwrap();
    let run = |case: &str, extra: &[&str]| run(&[case], &[extra, &["--out", o]].concat());
    let block = ["--mesh", mesh, "--t-end", "0.01"];
    assert_clear_error(
        &run("cases/block2d.toml", &block),
        &["fan.msh", "node 5 has a non-finite coordinate"],
    );
    let spring = |edits: &[(&str, &str)]| edited(dir.path(), "spring_mass.toml", edits);
    let stiffness = spring(&[("stiffness = 1.0", "stiffness = -1.0")]);
    assert_clear_error(
        &run(&stiffness, &[]),
        &["`system.stiffness`: -1.0", "must be finite and >= 0"],
    );
    let mass = spring(&[("mass = 1.0", "mass = -1.0")]);
    assert_clear_error(
        &run(&mass, &[]),
        &["`system.mass`: -1.0", "must be finite and > 0"],
    );
    // No stiffness is a free mass bouncing on the obstacle: still a run.
    let free = spring(&[("stiffness = 1.0", "stiffness = 0.0")]);
    let out = run(&free, &["--t-end", "0.5"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let short = ["--dt", "0.05", "--t-end", "1"];
    let huge = ["--elements", "99999999999", "--dt", "0.05", "--t-end", "1"];
    assert_clear_error(
        &run("cases/bar1d.toml", &huge),
        &["`mesh.elements (--elements)`: 99999999999", "GiB"],
    );
    let overflow = edited(
        dir.path(),
        "bar1d.toml",
        &[
            ("young = 1.0", "young = 1e308"),
            ("density = 1.0", "density = 1e308"),
        ],
    );
    let mut args = vec!["--elements", "10"];
    args.extend_from_slice(&short);
    assert_clear_error(
        &run(&overflow, &args),
        &["`K`: inf", "material.young", "overflow"],
    );
}

/// An output path that is a file, `--vtu-every` without `--vtu`, a sweep that would run nothing
/// (no space, no scheme, no quick level) or a flag its case ignores (`elements` on the spring),
/// and a report from a directory without case files: refused before any work, naming the flag
/// or the field.
#[test]
fn outputs_and_sweeps_that_would_come_to_nothing_are_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, "").unwrap();
    let file = file.to_str().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let bar = [
        "cases/bar1d.toml",
        "--elements",
        "10",
        "--dt",
        "0.05",
        "--t-end",
        "1",
    ];
    assert_clear_error(
        &run(&bar, &["--out", file]),
        &["`--out`", "not a directory"],
    );
    assert_clear_error(
        &dyncontact(&["sweep", "cases/spring_mass.toml", "--quick", "--out", file]),
        &["`--out`", "not a directory"],
    );
    let out = run(&bar, &["--vtu-every", "5", "--out", o]);
    assert_clear_error(&out, &["--vtu <DIR>"]);
    let spring = |edits: &[(&str, &str)]| edited(dir.path(), "spring_mass.toml", edits);
    for (edit, needles) in [
        (
            ("spaces = [\"standard\"]", "spaces = []"),
            &["`sweep.orders.spaces`", "at least one space"][..],
        ),
        (
            (
                "scheme = \"newmark\", beta = 0.5",
                "scheme = \"newmark\", beta = 0.0",
            ),
            &["`sweep.orders.schemes.beta`: 0.0"],
        ),
        (
            ("quick_levels = 3", "quick_levels = 0"),
            &["`sweep.orders.quick_levels`: 0"],
        ),
        (
            (
                "spaces = [\"standard\"]",
                "spaces = [\"standard\"]\nelements = 10",
            ),
            &[
                "sweep `orders`",
                "`sweep.orders.elements`",
                "spring_mass has one dof",
            ],
        ),
    ] {
        let case = spring(&[edit]);
        let out = dyncontact(&["sweep", &case, "--quick", "--out", o]);
        assert_clear_error(&out, needles);
    }
    // A sweep without schemes, the case's own sweep replaced.
    let text = std::fs::read_to_string("cases/spring_mass.toml").unwrap();
    let head = text.split("[[sweep]]").next().unwrap();
    let case = dir.path().join("no-schemes.toml");
    let sweep = "[[sweep]]\nname = \"orders\"\nspaces = [\"standard\"]\nschemes = []\ndt = 0.01\nlevels = 1\n";
    std::fs::write(&case, format!("{head}{sweep}")).unwrap();
    let out = dyncontact(&["sweep", case.to_str().unwrap(), "--out", o]);
    assert_clear_error(&out, &["`sweep.orders.schemes`", "at least one scheme"]);
    let empty = dir.path().join("no-cases");
    std::fs::create_dir(&empty).unwrap();
    let out = dyncontact(&["report", "--cases", empty.to_str().unwrap(), "--out", o]);
    assert_clear_error(
        &out,
        &[
            "`--cases`",
            "no case file with [[sweep]] or [[history]] tables",
        ],
    );
}

/// A field is named as the case file has it, with the flag that set it (`--beta 0` was `beta`, `--elements 0` on the bar
/// `elements`), a grading beyond the generator's range by `mesh.grading` (1e300 was blamed on
/// the density), two bars beyond the memory by `mesh.degree` or `mesh.elements`, and a mass
/// beyond the round-off of the stiffness by `run.dt` with the mass.
#[test]
fn fields_are_named_as_in_the_case_file() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let run = |args: &[&str]| run(args, &["--out", o]);
    for (flag, needle) in [
        ("--beta", "`run.beta (--beta)`: 0.0"),
        ("--elements", "`mesh.elements (--elements)`: 0"),
    ] {
        let out = run(&[
            "cases/bar1d.toml",
            "--dt",
            "0.05",
            "--t-end",
            "1",
            flag,
            "0",
        ]);
        assert_clear_error(&out, &[needle]);
    }
    let graded = edited(
        dir.path(),
        "hertz2d.toml",
        &[("grading = 16.0", "grading = 1e300")],
    );
    assert_clear_error(&run(&[&graded]), &["`mesh.grading`: 1e300", "[1, 1e10]"]);
    // Bar 2's element count in floating point: a huge degree or length ratio cannot wrap it
    // (lengths 1 and 1e30 wrapped to 39 elements and panicked indexing the exact solution).
    let degree = run(&["cases/two_bars.toml", "--degree", "1000000000000"]);
    assert_clear_error(&degree, &["`mesh.degree (--degree)`: 1000000000000"]);
    let long = edited(
        dir.path(),
        "two_bars.toml",
        &[("lengths = [1.0, 1.0]", "lengths = [1.0, 1e30]")],
    );
    assert_clear_error(&run(&[&long]), &["`mesh.elements`: 40", "GiB"]);
    let heavy = edited(
        dir.path(),
        "spring_mass.toml",
        &[("mass = 1.0", "mass = 1e300")],
    );
    assert_clear_error(&run(&[&heavy]), &["`run.dt`", "check the mass"]);
}

/// `RAYON_NUM_THREADS=100000` never started a run (10⁴ took 35 s for a one-step spring), and
/// rayon reads a typo as "one per core" without a word: both are refused naming the variable,
/// before any work. So is rayon's deprecated `RAYON_RS_NUM_CPUS`, which it reads when the first
/// is unset (20 000 kept a spring_mass run busy for over a minute).
#[test]
fn worker_threads_beyond_the_machine_are_refused_naming_the_variable() {
    for name in ["RAYON_NUM_THREADS", "RAYON_RS_NUM_CPUS"] {
        for value in ["100000", "two"] {
            let out = Command::new(env!("CARGO_BIN_EXE_dyncontact"))
                .args(["list", "cases"])
                .env_remove("RAYON_NUM_THREADS")
                .env(name, value)
                .output()
                .expect("binary runs");
            assert_clear_error(&out, &[name, value]);
        }
    }
}

/// Found by a fifth round of hostile inputs (2026-11-29): levels that do not refine gave an
/// order of 2.6e9 marked `meets`; two unnamed `[[history]]` tables drew one figure over the
/// other; a resumed report with a narrower selection dropped the other runs from its journal.
#[test]
fn studies_fit_only_refinements_keep_their_figures_and_their_records() {
    let dir = tempfile::tempdir().unwrap();
    let near = edited(
        dir.path(),
        "spring_mass.toml",
        &[
            ("t_end = 10.0", "t_end = 1.0"),
            (
                "dt = 0.01\nratio = 2\nlevels = 5",
                "refinements = [{ dt = 0.01 }, { dt = 0.01000000001 }]",
            ),
        ],
    );
    let o = dir.path().join("near");
    let out = dyncontact(&["sweep", &near, "--out", o.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let orders = std::fs::read_to_string(o.join("orders.csv")).unwrap();
    let verdicts: Vec<&str> = orders
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap())
        .collect();
    assert!(
        !verdicts.is_empty() && verdicts.iter().all(|v| *v == "too_few_levels"),
        "{orders}"
    );
    assert!(!orders.contains("NaN"), "{orders}");
    // The key names the restitution the run uses, the spring's own (it said the default, 0).
    let records = std::fs::read_to_string(o.join("records.csv")).unwrap();
    let keyed = "spring_mass-orders-standard-paoli_schatzman-restitution=1-L0,";
    assert!(records.contains(keyed), "{records}");
    // Two unnamed histories, refused before any run.
    let cases = dir.path().join("cases");
    std::fs::create_dir_all(&cases).unwrap();
    edited(&cases, "block2d.toml", &[("name = \"weak\"\n", "")]);
    let start = Instant::now();
    let out = dyncontact(&[
        "report",
        "--cases",
        cases.to_str().unwrap(),
        "--quick",
        "--out",
        o.to_str().unwrap(),
    ]);
    assert_clear_error(
        &out,
        &[
            "block2d.toml",
            "`history.name`",
            "would write the same figures",
        ],
    );
    assert!(start.elapsed() < Duration::from_secs(10), "ran first");
    // A quick resume over a full report keeps the runs it does not take.
    std::fs::remove_file(cases.join("block2d.toml")).unwrap();
    edited(
        &cases,
        "spring_mass.toml",
        &[("t_end = 10.0", "t_end = 1.0")],
    );
    let r = dir.path().join("R");
    let report = |extra: &[&str]| {
        let args = [
            &[
                "report",
                "--cases",
                cases.to_str().unwrap(),
                "--out",
                r.to_str().unwrap(),
            ],
            extra,
        ]
        .concat();
        let out = dyncontact(&args);
        assert!(out.status.success(), "{}", stderr(&out));
        let rows = std::fs::read_to_string(r.join("journal.csv"))
            .unwrap()
            .lines()
            .count()
            - 1;
        (rows, stderr(&out))
    };
    assert_eq!(report(&[]).0, 35);
    let (rows, said) = report(&["--resume", "--quick"]);
    assert_eq!(rows, 35, "{said}");
    let (rows, said) = report(&["--resume"]);
    assert!(
        rows == 35 && said.contains("35 of 35 runs already recorded"),
        "{said}"
    );
    // The case file edited to four levels: its fifth level's rows are of the file before the
    // edit, which no run takes again, and go.
    edited(
        &cases,
        "spring_mass.toml",
        &[
            ("t_end = 10.0", "t_end = 1.0"),
            ("levels = 5", "levels = 4"),
        ],
    );
    assert_eq!(report(&["--resume"]).0, 28);
}

/// `--profile` named as a file the report writes in `--out` was overwritten by it (the profile
/// lost, exit 0), or removed (its lock file): a profile inside `--out` is refused.
#[test]
fn a_profile_is_never_a_file_the_report_writes() {
    let dir = tempfile::tempdir().unwrap();
    let cases = dir.path().join("cases");
    std::fs::create_dir_all(&cases).unwrap();
    edited(
        &cases,
        "spring_mass.toml",
        &[("t_end = 10.0", "t_end = 1.0")],
    );
    let r = dir.path().join("R");
    let report = |profile: &str| {
        let r = r.to_str().unwrap();
        let args = [
            "report",
            "--cases",
            cases.to_str().unwrap(),
            "--quick",
            "--out",
            r,
        ];
        dyncontact(&[&args[..], &["--profile", &format!("{r}/{profile}")]].concat())
    };
    let out = report("../profile.csv");
    assert!(out.status.success(), "{}", stderr(&out));
    let profile = std::fs::read_to_string(dir.path().join("profile.csv")).unwrap();
    assert!(
        profile.starts_with("kind,task,") && profile.lines().count() > 21,
        "{profile}"
    );
    for taken in [
        "journal.csv",
        "journal.csv.lock",
        "probes",
        "mine.csv",
        "./probes/../p.csv",
    ] {
        assert_clear_error(&report(taken), &["--profile", taken, "inside --out"]);
    }
}

/// Starts the binary with `args` (one worker thread) and waits until it holds the lock of
/// `dir` (`journal.csv.lock` holding its process id); returns it and its id.
fn holding_the_lock(args: &[&str], dir: &Path) -> (std::process::Child, String) {
    let mut first = Command::new(env!("CARGO_BIN_EXE_dyncontact"))
        .args(args)
        .env("RAYON_NUM_THREADS", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let lock = dir.join("journal.csv.lock");
    let pid = first.id().to_string();
    let start = Instant::now();
    while std::fs::read_to_string(&lock).ok().as_deref() != Some(pid.as_str()) {
        assert!(first.try_wait().unwrap().is_none(), "the first ended first");
        assert!(start.elapsed() < Duration::from_secs(60), "no lock file");
        std::thread::sleep(Duration::from_millis(20));
    }
    (first, pid)
}

/// Found by a sixth round of hostile inputs: two `run`s into one `--out` at once mixed their
/// files (one's summary, the other's figures). A run holds the lock a study takes on its
/// directory: a second run is refused naming the directory, the lock file and the holder.
#[test]
fn a_second_run_into_the_same_directory_is_refused_naming_the_lock() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().to_str().unwrap();
    let long = [
        "run",
        "cases/block2d.toml",
        "--elements",
        "8",
        "--dt",
        "1e-4",
    ];
    let (mut first, pid) = holding_the_lock(
        &[&long[..], &["--t-end", "1000", "--out", o]].concat(),
        dir.path(),
    );
    let lock = dir.path().join("journal.csv.lock");
    let short = ["cases/block2d.toml", "--elements", "2", "--t-end", "0.1"];
    let second = run(&short, &["--out", o]);
    first.kill().unwrap();
    first.wait().unwrap();
    assert_clear_error(
        &second,
        &["journal.csv.lock", o, &format!("(process {pid})")],
    );
    assert!(
        !dir.path().join("summary.csv").exists(),
        "the second run wrote"
    );
    let third = run(&short, &["--out", o]);
    assert!(third.status.success(), "{}", stderr(&third));
    assert!(!lock.exists(), "a run that ends removes its lock file");
}

/// Found by a sixth round of hostile inputs: beside a case file's own `[mesh] file`, the fields
/// only a generated mesh uses were silently ignored (a degree 2 ran degree 1). Each is refused
/// naming the field, the mesh file and the case file; the fields the case still reads from a
/// file's body (a Hertz case's shape and radius) are kept.
#[test]
fn generator_fields_beside_a_mesh_file_are_refused_naming_field_and_files() {
    let dir = tempfile::tempdir().unwrap();
    let msh = std::fs::canonicalize("cases/meshes/disc.msh").unwrap();
    let base = |case: &str, geometry: &str, extra: &str| {
        format!(
            "case = \"{case}\"\nunits = \"x\"\n[material]\nyoung = 1.0\npoisson = 0.3\n\
             density = 1.0\n[geometry]\nvelocity = -0.01\n{geometry}\n[mesh]\nfile = {:?}\n\
             {extra}\n[run]\nspace = \"mass_redistribution\"\nscheme = \"newmark\"\n\
             dt = 0.02\nt_end = 0.1\n",
            msh.display()
        )
    };
    let o = dir.path().join("o");
    for (geometry, extra, field) in [
        ("", "cells = \"triangle\"", "mesh.cells"),
        ("", "degree = 2", "mesh.degree"),
        ("", "elements = 12", "mesh.elements"),
        ("", "grading = 4.0", "mesh.grading"),
        ("", "[contact]\nfacing = 0.5", "contact.facing"),
        ("size = [5.0, 5.0]", "", "geometry.size"),
        ("shape = \"disc\"", "", "geometry.shape"),
        ("radius = 3.0", "", "geometry.radius"),
    ] {
        let path = dir.path().join("beside.toml");
        std::fs::write(&path, base("block2d", geometry, extra)).unwrap();
        let out = run(&[path.to_str().unwrap()], &["--out", o.to_str().unwrap()]);
        assert_clear_error(
            &out,
            &[
                &format!("`{field}`"),
                "beside.toml",
                "disc.msh",
                "mesh.file",
            ],
        );
    }
    // A Hertz case reads its shape and radius with a file: the reference's radius.
    let path = dir.path().join("hertz.toml");
    std::fs::write(&path, base("hertz2d", "shape = \"disc\"\nradius = 1.0", "")).unwrap();
    let out = run(&[path.to_str().unwrap()], &["--out", o.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Found by a sixth round of hostile inputs: a sweep refining by `elements` a case whose mesh
/// is a file ran every level and failed each on a flag nobody gave (`--elements`). It is
/// refused before any run, naming the sweep's field, the mesh file and the case file.
#[test]
fn a_sweep_refining_the_elements_of_a_mesh_file_case_is_refused_up_front() {
    let dir = tempfile::tempdir().unwrap();
    let msh = std::fs::canonicalize("cases/meshes/disc.msh").unwrap();
    let text = format!(
        "case = \"hertz2d\"\nunits = \"x\"\n[material]\nyoung = 1.0\npoisson = 0.3\n\
         density = 1.0\n[geometry]\nshape = \"disc\"\nradius = 1.0\nvelocity = -0.01\n\
         [mesh]\nfile = {:?}\n[run]\nspace = \"mass_redistribution\"\nscheme = \"newmark\"\n\
         dt = 0.02\nt_end = 0.1\n[[sweep]]\nname = \"hertz\"\nspaces = [\"standard\"]\n\
         schemes = [{{ scheme = \"newmark\", beta = 0.5, gamma = 0.5 }}]\nelements = 12\n\
         dt = 0.02\nt_end = 0.08\nratio = 2\nlevels = 3\nquick_levels = 1\n",
        msh.display()
    );
    let path = dir.path().join("h2sweep.toml");
    std::fs::write(&path, text).unwrap();
    let o = dir.path().join("o");
    let out = dyncontact(&[
        "sweep",
        path.to_str().unwrap(),
        "--quick",
        "--out",
        o.to_str().unwrap(),
    ]);
    assert_clear_error(
        &out,
        &["`sweep.hertz.elements`", "h2sweep.toml", "disc.msh"],
    );
    assert!(!o.join("records.csv").exists(), "the sweep ran");
}

/// A temporary directory and its `o`, an output directory inside it.
fn temp_out() -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o").to_str().unwrap().to_string();
    (dir, o)
}

/// Found by a sixth round of hostile inputs: a solver option with no effect on the run was
/// refused at a non-default value and silently accepted at its default. Given on the command
/// line, it is refused whatever its value, naming the flag.
#[test]
fn a_solver_flag_without_effect_is_refused_at_its_default_value_too() {
    let (_dir, o) = temp_out();
    let o = o.as_str();
    for (args, flag) in [
        (
            &["--space", "lumped", "--scheme", "taylor_flanagan"][..],
            ["--contact-solver", "active_set"],
        ),
        (
            &["--contact", "nitsche"][..],
            ["--contact-solver", "active_set"],
        ),
        (
            &["--space", "lumped", "--scheme", "explicit_penalty"][..],
            ["--linear-solver", "direct"],
        ),
        (
            &["--space", "lumped", "--scheme", "explicit_penalty"][..],
            ["--linear-solver", "auto"],
        ),
    ] {
        let out = run(
            &[&["cases/bar1d.toml"], args, &flag, &["--t-end", "1"]].concat(),
            &["--out", o],
        );
        assert_clear_error(&out, &[&format!("`{}`", flag[0]), flag[1], "no effect"]);
    }
    // Where the option is used, its default is accepted.
    let out = run(
        &[
            "cases/bar1d.toml",
            "--contact-solver",
            "active_set",
            "--t-end",
            "1",
        ],
        &["--out", o],
    );
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Found by a sixth round of hostile inputs: `--nitsche-theta -1 --nitsche-gamma 1e-300` blamed
/// "θ > 0" for a failed factorisation on block2d and gave only "energy is NaN" on bar1d. A γ₀
/// whose term γ σ_n σ_n outweighs the stiffness beyond round-off is refused before stepping,
/// whatever θ, naming the flag.
#[test]
fn a_nitsche_gamma_that_swamps_the_stiffness_is_refused_whatever_theta() {
    let (_dir, o) = temp_out();
    let o = o.as_str();
    for case in [
        &["cases/block2d.toml", "--elements", "2"][..],
        &["cases/bar1d.toml"],
    ] {
        for theta in ["-1", "0", "1"] {
            let nitsche = ["--contact", "nitsche", "--nitsche-theta", theta];
            let tail = ["--nitsche-gamma", "1e-300", "--t-end", "0.5", "--out", o];
            let out = run(&[case, &nitsche[..]].concat(), &tail);
            assert_clear_error(
                &out,
                &["--nitsche-gamma", "1e-300", "singular to round-off"],
            );
            assert!(!stderr(&out).contains("θ > 0"), "{}", stderr(&out));
        }
    }
}

/// Two bodies overlapping at t = 0 ran (energy drift 57 on overlapping discs; body 1 below body
/// 2 diverged at step 1 only): a slave vertex inside the master is refused, named. Body 2 the
/// unit square, body 1 the same square lifted by 0.9 (two 3-node triangles each), on
/// slide_on_block2d (two_discs would refuse squares as no Hertz disc first).
#[test]
fn two_bodies_overlapping_at_the_start_are_refused_naming_the_vertex() {
    let msh = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
         $PhysicalNames\n4\n1 3 \"contact1\"\n1 4 \"contact2\"\n2 1 \"body1\"\n2 2 \"body2\"\n\
         $EndPhysicalNames\n$Entities\n0 2 2 0\n1 0 0.9 0 1 0.9 0 1 3 0\n2 0 1 0 1 1 0 1 4 0\n\
         1 0 0.9 0 1 1.9 0 1 1 0\n2 0 0 0 1 1 0 1 2 0\n$EndEntities\n\
         $Nodes\n1 8 1 8\n2 1 0 8\n1\n2\n3\n4\n5\n6\n7\n8\n\
         0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0.9 0\n1 0.9 0\n1 1.9 0\n0 1.9 0\n$EndNodes\n\
         $Elements\n4 6 1 6\n1 1 1 1\n1 5 6\n1 2 1 1\n2 3 4\n\
         2 1 2 2\n3 5 6 7\n4 5 7 8\n2 2 2 2\n5 1 2 3\n6 1 3 4\n$EndElements\n";
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("overlap.msh");
    std::fs::write(&mesh, msh).unwrap();
    // Body 2's [master.mesh] would be refused beside a file of both bodies.
    let text = std::fs::read_to_string("cases/slide_on_block2d.toml").unwrap();
    let (head, table) = text.split_at(text.find("[master.mesh]").unwrap());
    let case = dir.path().join("blocks.toml");
    std::fs::write(
        &case,
        format!("{head}{}", &table[table.find("\n[").unwrap()..]),
    )
    .unwrap();
    let o = dir.path().join("o");
    let tail = [
        "--mesh",
        mesh.to_str().unwrap(),
        "--out",
        o.to_str().unwrap(),
    ];
    let out = run(&[case.to_str().unwrap()], &tail);
    assert_clear_error(
        &out,
        &["overlap.msh", "body 1 node", "penetrates body 2", "t = 0"],
    );
}

/// A mesh too small for floating point (coordinates ×1e-300) is named as degenerate, with the
/// file and the cell; it was blamed on `material.density` (h = 0), the file unnamed.
#[test]
fn a_mesh_out_of_floating_point_range_is_refused_naming_the_file_and_cell() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("tiny.msh");
    let tiny = fan_msh([5e-301, 5e-301]).replace(
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n",
        "0 0 0\n1e-300 0 0\n1e-300 1e-300 0\n0 1e-300 0\n",
    );
    std::fs::write(&mesh, tiny).unwrap();
    let o = dir.path().join("o");
    let out = run(
        &[
            "cases/block2d.toml",
            "--mesh",
            mesh.to_str().unwrap(),
            "--t-end",
            "0.01",
        ],
        &["--out", o.to_str().unwrap()],
    );
    assert_clear_error(
        &out,
        &["tiny.msh", "element 2 (nodes [1, 2, 5])", "degenerate"],
    );
    assert!(!stderr(&out).contains("density"), "{}", stderr(&out));
}

/// Found by a seventh round of hostile inputs (2026-11-29): `report --profile` replaced the
/// case file it was given with the profile's header, and `run o/q/summary.csv --out o/q` its
/// own case file with the run's summary. An input is never an output: refused before any run,
/// naming both paths; a profile replaces only a profile.
#[test]
fn an_input_is_never_overwritten_by_an_output() {
    let dir = tempfile::tempdir().unwrap();
    let pc = dir.path().join("pc");
    std::fs::create_dir_all(&pc).unwrap();
    let case = edited(&pc, "spring_mass.toml", &[("t_end = 10.0", "t_end = 1.0")]);
    let text = std::fs::read_to_string(&case).unwrap();
    let o = dir.path().join("o");
    let report = |profile: &str| {
        let args = ["report", "--quick", "--cases", pc.to_str().unwrap()];
        let out = ["--out", o.to_str().unwrap(), "--profile", profile];
        dyncontact(&[&args[..], &out].concat())
    };
    assert_clear_error(&report(&case), &["--profile", &case, "not a profile"]);
    assert_eq!(std::fs::read_to_string(&case).unwrap(), text);
    // A profile of an earlier report is replaced.
    let profile = dir.path().join("profile.csv");
    let header = "kind,task,start_s,end_s,wall_s,cpu_s,thread_cpu_s,rss_mb\n";
    std::fs::write(&profile, header).unwrap();
    let out = report(profile.to_str().unwrap());
    assert!(out.status.success(), "{}", stderr(&out));
    // A case file that is one of the files `run` or `sweep` writes into --out.
    let q = dir.path().join("q");
    std::fs::create_dir_all(&q).unwrap();
    for (command, name) in [("run", "summary.csv"), ("sweep", "orders.csv")] {
        let input = q.join(name);
        std::fs::write(&input, &text).unwrap();
        let input = input.to_str().unwrap();
        let out = dyncontact(&[command, input, "--out", q.to_str().unwrap()]);
        assert_clear_error(
            &out,
            &["--out", input, "is the case file", "destroy its input"],
        );
        assert_eq!(std::fs::read_to_string(input).unwrap(), text);
    }
    assert!(!q.join("timeseries.csv").exists() && !q.join("journal.csv").exists());
}

/// `sweep` with `--quick` (and `--shard`) into `out`, which must succeed.
fn swept(case: &str, shard: Option<&str>, out: &Path) {
    let mut args = vec!["sweep", case, "--quick", "--out", out.to_str().unwrap()];
    if let Some(s) = shard {
        args.extend(["--shard", s]);
    }
    let done = dyncontact(&args);
    assert!(done.status.success(), "{}", stderr(&done));
}

/// `merge` of `files` into `out`.
fn merged(files: &[&Path], out: &Path) -> Output {
    let mut args = vec!["merge".to_string()];
    args.extend(files.iter().map(|f| f.to_str().unwrap().to_string()));
    args.extend(["--out".to_string(), out.to_str().unwrap().to_string()]);
    dyncontact(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

/// Found by a seventh round of hostile inputs: `merge` joined shard 1 of 2 of spring_mass with
/// shard 2 of 2 of two_bars (or of a spring_mass.toml of another stiffness, or of a sweep
/// without --quick) into incomplete series. Each shard's manifest names its study; shards of
/// different studies, and records without their manifest, are refused naming the files.
#[test]
fn merge_refuses_shards_of_different_studies() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    swept("cases/spring_mass.toml", Some("1/2"), &d.join("c"));
    let first = d.join("c/records-1-of-2.csv");
    let stiff = edited(
        d,
        "spring_mass.toml",
        &[("stiffness = 1.0", "stiffness = 4.0")],
    );
    swept("cases/two_bars.toml", Some("2/2"), &d.join("c"));
    swept(&stiff, Some("2/2"), &d.join("d"));
    let full = d.join("e");
    let args = ["sweep", "cases/spring_mass.toml", "--shard", "2/2", "--out"];
    let done = dyncontact(&[&args[..], &[full.to_str().unwrap()]].concat());
    assert!(done.status.success(), "{}", stderr(&done));
    for other in ["c", "d", "e"] {
        let second = d.join(other).join("records-2-of-2.csv");
        let out = merged(&[&first, &second], &d.join("m"));
        let names = [first.to_str().unwrap(), second.to_str().unwrap()];
        assert_clear_error(
            &out,
            &[&names[..], &["another study", "in no file"]].concat(),
        );
    }
    assert!(!d.join("m").exists());
    let manifest = d.join("c/manifest-2-of-2.txt");
    std::fs::remove_file(&manifest).unwrap();
    let out = merged(&[&first, &d.join("c/records-2-of-2.csv")], &d.join("m"));
    assert_clear_error(&out, &[manifest.to_str().unwrap(), "no manifest"]);
}

/// Found by a seventh round of hostile inputs: the merged summary depended on the order of the
/// files and on the sharding. The rows come in the enumeration order of the study.
#[test]
fn merged_outputs_do_not_depend_on_the_sharding_or_the_file_order() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases = "cases/spring_mass.toml";
    for shard in ["1/2", "2/2", "1/1"] {
        swept(cases, Some(shard), &d.join("s"));
    }
    let [one, two, whole] =
        ["1-of-2", "2-of-2", "1-of-1"].map(|s| d.join(format!("s/records-{s}.csv")));
    let runs: [&[&Path]; 3] = [&[&one, &two], &[&two, &one], &[&whole]];
    let outputs: Vec<(String, String)> = runs
        .iter()
        .enumerate()
        .map(|(k, files)| {
            let m = d.join(format!("m{k}"));
            let out = merged(files, &m);
            assert!(out.status.success(), "{}", stderr(&out));
            let read = |f: &str| std::fs::read_to_string(m.join(f)).unwrap();
            (read("summary.csv"), read("orders.csv"))
        })
        .collect();
    assert_eq!(outputs[0], outputs[1]);
    assert_eq!(outputs[0], outputs[2]);
}

/// Found by a seventh round of hostile inputs: `sweep --resume` took a journal row whose dt and
/// steps were not its run's (dt 0.5, 7 steps under a key of dt 0.01), and the last of two rows
/// of one key. Both are refused, naming the key, the column, both values and the journal.
#[test]
fn resume_refuses_journal_rows_that_contradict_their_run() {
    let dir = tempfile::tempdir().unwrap();
    let r = dir.path().join("r");
    swept("cases/spring_mass.toml", None, &r);
    let journal = r.join("journal.csv");
    let good = std::fs::read_to_string(&journal).unwrap();
    let header: Vec<&str> = good.lines().next().unwrap().split(',').collect();
    let key = "spring_mass-orders-standard-newmark-beta=0.5;gamma=0.5-L0";
    // The journal with the columns `edits` of `key`'s row set, or its row appended again.
    let with = |edits: &[(&str, &str)], twice: bool| {
        let mut lines: Vec<String> = good.lines().map(String::from).collect();
        let k = lines.iter().position(|l| l.starts_with(key)).unwrap();
        let mut row: Vec<String> = lines[k].split(',').map(String::from).collect();
        for (column, value) in edits {
            row[header.iter().position(|h| h == column).unwrap()] = value.to_string();
        }
        if twice {
            lines.push(row.join(","));
        } else {
            lines[k] = row.join(",");
        }
        std::fs::write(&journal, lines.join("\n") + "\n").unwrap();
    };
    let resume = || {
        let args = [
            "sweep",
            "cases/spring_mass.toml",
            "--quick",
            "--resume",
            "--out",
        ];
        dyncontact(&[&args[..], &[r.to_str().unwrap()]].concat())
    };
    let path = journal.to_str().unwrap();
    for (edits, needles) in [
        (
            &[("dt", "0.5"), ("steps", "7")][..],
            &["column `dt`: 5e-1", "1e-2"][..],
        ),
        (
            &[("steps", "7"), ("energy_drift", "0.0")],
            &["column `steps`: 7", "1000"],
        ),
        (&[("dofs", "3")], &["column `dofs`: 3", "with 1 "]),
    ] {
        with(edits, false);
        assert_clear_error(&resume(), &[&[path, key][..], needles].concat());
    }
    with(&[("energy_drift", "0.5")], true);
    assert_clear_error(
        &resume(),
        &[path, key, "is the key of row", "one run, one row"],
    );
    std::fs::write(&journal, &good).unwrap();
    let out = resume();
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Found by a seventh round of hostile inputs: the case files `a.toml` (sweep `x-s`) and
/// `a-x.toml` (sweep `s`) give the same keys, and the error named neither file; `dyncontact
/// list` of a missing directory or of a file said "no case files" and exited 0.
#[test]
fn colliding_keys_name_both_files_and_list_refuses_a_path_that_is_no_directory() {
    let dir = tempfile::tempdir().unwrap();
    let table = |name: &str| {
        format!(
            "\n[[sweep]]\nname = \"{name}\"\nspaces = [\"standard\"]\n\
             schemes = [{{ scheme = \"newmark\", beta = 0.5, gamma = 0.5 }}]\n\
             elements = 2\ndt = 0.05\nt_end = 0.5\nratio = 2\nlevels = 2\n"
        )
    };
    let mut files = Vec::new();
    for (file, kind, sweep) in [("a.toml", "block2d", "x-s"), ("a-x.toml", "block3d", "s")] {
        let text = std::fs::read_to_string(format!("cases/{kind}.toml")).unwrap();
        let keep = text.split("\n[[").next().unwrap().to_string();
        let path = dir.path().join(file);
        std::fs::write(&path, keep + &table(sweep)).unwrap();
        files.push(path.to_str().unwrap().to_string());
    }
    let o = dir.path().join("o");
    let out = dyncontact(&["sweep", &files[0], &files[1], "--out", o.to_str().unwrap()]);
    assert_clear_error(
        &out,
        &[
            &files[0],
            &files[1],
            "a `-` in a case file's or a sweep's name",
        ],
    );
    assert!(!o.exists());
    let missing = dir.path().join("nonexist");
    assert_clear_error(
        &dyncontact(&["list", missing.to_str().unwrap()]),
        &["nonexist"],
    );
    assert_clear_error(
        &dyncontact(&["list", "cases/spring_mass.toml"]),
        &["cases/spring_mass.toml", "not a directory of case files"],
    );
}

/// `sweep --resume` kept the rows of a case file whose `[mesh] file` had been replaced (1290
/// dofs recorded, 814 in the new mesh): the journal's key was the hash of the case file's text
/// alone. It now covers the mesh file's bytes.
#[test]
fn a_replaced_mesh_file_is_a_new_case_for_the_journal() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("disc.msh");
    std::fs::copy("cases/meshes/disc.msh", &mesh).unwrap();
    let text = std::fs::read_to_string("cases/hertz2d.toml").unwrap();
    let at = text.find("[mesh]").unwrap();
    let end = at + text[at..].find("\n\n").unwrap();
    let path = dir.path().join("hd.toml");
    let edited = format!("{}[mesh]\nfile = \"disc.msh\"{}", &text[..at], &text[end..]);
    std::fs::write(&path, edited).unwrap();
    let hash = || dyncontact::cases::CaseFile::read(&path).unwrap().hash;
    let before = hash();
    let mut bytes = std::fs::read(&mesh).unwrap();
    bytes.extend_from_slice(b"\n");
    std::fs::write(&mesh, bytes).unwrap();
    assert_ne!(before, hash(), "the mesh file changed, the key did not");
}

/// Memory estimates far beyond the machine are printed short (`2.2e10 GiB`, was
/// `23737550107687714816.0 GiB`).
#[test]
fn an_absurd_memory_estimate_is_printed_short() {
    if !Path::new("/proc/meminfo").exists() {
        return; // no estimate of the memory available: the run would start
    }
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let out = run(
        &["cases/block3d.toml", "--elements", "100000000"],
        &["--out", o.to_str().unwrap()],
    );
    assert_clear_error(
        &out,
        &["`mesh.elements (--elements)`: 100000000", "e1", "GiB"],
    );
    let longest = stderr(&out)
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max();
    assert!(longest < Some(10), "{}", stderr(&out));
}

/// An energy that falls without bound is a divergence too: Nitsche's contact with γ₀ below
/// its stability bound gives the stiffness a negative mode, whose energy backward Euler
/// multiplies each step keeping its sign (hertz2d, 8 elements, γ₀ = 3.5: E from 1.5e-4 to
/// −3.3e83 at t = 8.5).
#[test]
fn an_energy_falling_without_bound_is_a_divergence() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let out = run(
        &[
            "cases/hertz2d.toml",
            "--contact",
            "nitsche",
            "--nitsche-gamma",
            "3.5",
            "--scheme",
            "backward_euler",
            "--dt",
            "0.001",
            "--elements",
            "8",
        ],
        &["--out", o.to_str().unwrap()],
    );
    assert_clear_error(
        &out,
        &[
            "diverged at step 1437",
            "the energy moved from E(0) by more than 100 |E(0)|",
        ],
    );
}

/// A case file's text up to its first `[[sweep]]` with `sweep` after it, written into `dir`.
fn with_sweep(dir: &Path, file: &str, sweep: &str) -> String {
    let text = std::fs::read_to_string(format!("cases/{file}")).unwrap();
    let head = &text[..text.find("[[sweep]]").unwrap()];
    let path = dir.join(file);
    std::fs::write(&path, format!("{head}{sweep}")).unwrap();
    path.to_str().unwrap().to_string()
}

/// Found by a fourth round of hostile inputs: the solvers of a sweep's scheme entry entered
/// neither the run's key nor its records, so two entries differing by their solver were refused
/// as "one run listed twice" and one entry's run was recorded without its solver (`parameters`
/// empty). Every solver other than its default is a parameter now, in the key, the records and
/// `run`'s summary; the contact multiplier already was (`contact=weak_p0`).
#[test]
fn a_sweep_compares_solvers_each_run_keyed_and_recorded_with_its_own() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let table = |schemes: &str| {
        format!(
            "[[sweep]]\nname = \"solvers\"\nspaces = [\"standard\"]\nschemes = [{schemes}]\n\
             elements = 8\ndt = 0.01\nlevels = 1\nt_end = 0.5\n"
        )
    };
    let records = |case: &str| {
        let out = dyncontact(&["sweep", case, "--out", o]);
        assert!(out.status.success(), "{}", stderr(&out));
        std::fs::read_to_string(dir.path().join("o/records.csv")).unwrap()
    };
    let be = "{ scheme = \"backward_euler\"";
    let slide = with_sweep(
        dir.path(),
        "slide2d.toml",
        &table(&format!(
            "{be}, contact_solver = \"projected_gauss_seidel\" }}, \
             {be}, contact_solver = \"alart_curnier\" }}, {be} }}"
        )),
    );
    let text = records(&slide);
    for row in [
        "slide2d-solvers-standard-backward_euler-contact_solver=projected_gauss_seidel-L0,\
         solvers,0,ok,,slide2d,standard,backward_euler,contact_solver=projected_gauss_seidel,",
        "slide2d-solvers-standard-backward_euler-contact_solver=alart_curnier-L0,solvers,0,ok,,\
         slide2d,standard,backward_euler,contact_solver=alart_curnier,",
        // No solver set: the key and records as before (alart_curnier, friction's default).
        "slide2d-solvers-standard-backward_euler-L0,solvers,0,ok,,slide2d,standard,\
         backward_euler,,nodal,",
    ] {
        assert!(text.contains(row), "{row} not in\n{text}");
    }
    let block = with_sweep(
        dir.path(),
        "block2d.toml",
        &table(
            "{ scheme = \"newmark\", linear_solver = \"cg\" }, \
             { scheme = \"newmark\", linear_solver = \"direct\" }, \
             { scheme = \"newmark\", contact = \"weak\", contact_multiplier = \"p0\" }, \
             { scheme = \"newmark\", contact = \"weak\", contact_multiplier = \"p1\" }",
        ),
    );
    let text = records(&block);
    for key in [
        "block2d-solvers-standard-newmark-beta=0.5;gamma=0.5;linear_solver=cg-L0,",
        "block2d-solvers-standard-newmark-beta=0.5;gamma=0.5;linear_solver=direct-L0,",
        "block2d-solvers-standard-newmark-beta=0.5;gamma=0.5;contact=weak_p0-L0,",
        "block2d-solvers-standard-newmark-beta=0.5;gamma=0.5;contact=weak_p1-L0,",
    ] {
        assert!(text.contains(key), "{key} not in\n{text}");
    }
    // The same solver twice is still one run listed twice.
    let twice = with_sweep(
        dir.path(),
        "slide2d.toml",
        &table(&format!(
            "{be}, contact_solver = \"de_saxce\" }}, {be}, contact_solver = \"de_saxce\" }}"
        )),
    );
    let out = dyncontact(&["sweep", &twice, "--out", o]);
    assert_clear_error(
        &out,
        &["contact_solver=de_saxce-L0", "one run listed twice"],
    );
    // `run`'s summary names the solver too.
    let out = run(
        &[
            "cases/slide2d.toml",
            "--contact-solver",
            "projected_gauss_seidel",
        ],
        &["--t-end", "0.1", "--out", o],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let summary = std::fs::read_to_string(dir.path().join("o/summary.csv")).unwrap();
    assert!(
        summary.contains(",backward_euler,contact_solver=projected_gauss_seidel,nodal,"),
        "{summary}"
    );
}

/// Found by a fourth round of hostile inputs: a slide on a slope ran against the flat slide's
/// rigid reference (slide2d at slope 0.2: `slide_velocity_err` 0.81, `stop_time` empty,
/// `stop_distance` 4.42, all against the deceleration μ g where the slope gives
/// g (μ cos α − sin α)), exit 0. The slides refuse a slope, naming it; the cases without a
/// reference (the blocks, disc2d) and roll2d, whose reference has it, keep it.
#[test]
fn a_slide_on_a_slope_is_refused_for_its_flat_reference() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    let tilted = "gravity = 1.0\nslope = 0.2";
    for file in ["slide2d.toml", "slide3d.toml"] {
        let case = edited(dir.path(), file, &[("gravity = 1.0", tilted)]);
        let out = run(&[&case], &["--t-end", "0.1", "--out", o]);
        assert_clear_error(
            &out,
            &[&case, "`geometry.slope`: 0.2", "flat plane", "roll2d"],
        );
    }
    let block = edited(dir.path(), "block2d.toml", &[("gravity = 0.0", tilted)]);
    let out = run(&[&block], &["--t-end", "0.01", "--out", o]);
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Nitsche on a pair said it "needs σ_N on Γ_C, which this case does not provide (bar1d and
/// the meshed bodies do)" of two meshed bodies: the reason is that Nitsche between two bodies
/// is not implemented, and the message says so (the spring–mass: it has no Γ_C).
#[test]
fn nitsche_on_two_bodies_is_refused_as_not_implemented() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let o = o.to_str().unwrap();
    for case in [
        "cases/two_discs.toml",
        "cases/slide_on_block2d.toml",
        "cases/two_bars.toml",
    ] {
        let out = run(&[case, "--contact", "nitsche"], &["--out", o]);
        assert_clear_error(
            &out,
            &[
                case,
                "nitsche contact between two bodies is not implemented",
            ],
        );
        assert!(
            !stderr(&out).contains("meshed bodies do"),
            "{}",
            stderr(&out)
        );
    }
    let out = run(
        &["cases/spring_mass.toml", "--contact", "nitsche"],
        &["--out", o],
    );
    assert_clear_error(&out, &["a point mass has none"]);
}

/// A Gmsh mesh with a node below the plane was refused as `error: /path/below.msh: node 1 …`
/// without the case file, which every other error of `run` names first: now the case file,
/// then the mesh file, each once.
#[test]
fn a_mesh_error_of_a_run_names_the_case_file_then_the_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let mesh = dir.path().join("below.msh");
    let below = fan_msh([0.5, 0.5]).replace("0 0 0\n1 0 0\n", "0 -0.1 0\n1 0 0\n");
    std::fs::write(&mesh, below).unwrap();
    let m = mesh.to_str().unwrap();
    let out = run(
        &["cases/block2d.toml", "--mesh", m, "--t-end", "0.01"],
        &["--out", o.to_str().unwrap()],
    );
    assert_clear_error(&out, &["below the plane"]);
    let e = stderr(&out);
    assert!(
        e.starts_with(&format!("error: cases/block2d.toml: {m}: node 1 ")),
        "{e}"
    );
    assert_eq!(e.matches("cases/block2d.toml").count(), 1, "{e}");
    assert_eq!(e.matches(m).count(), 1, "{e}");
}

/// An element of a Gmsh file through a node tag the file does not list said only "element
/// refers to unknown node 999": the element is named by its tag, with the file (a cell and a
/// face of the contact group).
#[test]
fn an_element_through_an_unknown_node_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    let mesh = dir.path().join("unknown.msh");
    let m = mesh.to_str().unwrap();
    for (from, to, element) in [
        ("4 3 4 5\n", "4 3 999 5\n", "element 4 refers to node 999"),
        ("1 1 2\n", "1 1 777\n", "element 1 refers to node 777"),
    ] {
        std::fs::write(&mesh, fan_msh([0.5, 0.5]).replace(from, to)).unwrap();
        let out = run(
            &["cases/block2d.toml", "--mesh", m, "--t-end", "0.01"],
            &["--out", o.to_str().unwrap()],
        );
        assert_clear_error(&out, &[&format!("{m}: {element}")]);
    }
}

/// oblique3d at `--elements 2` (grading 25, inside its documented range [1, 1e10]) failed in
/// the sphere generator's own mesh ("cell 28 … is inverted or degenerate"): refused naming
/// mesh.elements (--elements) and mesh.grading, with the range of each at the other's value.
#[test]
fn a_sphere_too_coarse_for_its_grading_is_refused_naming_both_fields() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("o");
    for (n, grading, next) in [("2", "[1, 21.3]", "3"), ("1", "[1, 4.86]", "3")] {
        let out = run(
            &["cases/oblique3d.toml", "--elements", n, "--dt", "0.2"],
            &["--out", o.to_str().unwrap()],
        );
        assert_clear_error(
            &out,
            &[
                &format!(
                    "cases/oblique3d.toml: invalid value for `mesh.elements (--elements)`: {n}"
                ),
                "fold at mesh.grading = 25",
                &format!("at mesh.elements = {n} mesh.grading must lie in {grading}"),
                &format!("next count that holds is mesh.elements = {next}"),
            ],
        );
    }
}
