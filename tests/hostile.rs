//! Hostile inputs (issue 27): special files, non-finite states, tangled meshes, time grids that
//! miss t_end, interrupted output. Each test runs the binary and asserts a clear error (exit ≠ 0,
//! no panic, the field or file named) within a time limit, or the documented outcome.

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
