//! `report --profile FILE`: where a report's time goes. One CSV line per simulation and per
//! report section as it ends: `kind` (`run` or `section`), `task`, `start_s` and `end_s` since
//! the profile began, `wall_s`, `cpu_s` (user + system time of the whole process over the task,
//! from `/proc/self/stat`: the task's own CPU time when tasks do not overlap, e.g. under
//! `RAYON_NUM_THREADS=1`, which gives the report one worker), `thread_cpu_s` (the calling
//! thread's alone) and `rss_mb` (the process's resident memory at the end). A section's line
//! includes its runs. Off unless [`start`] was called; the report's outputs do not change.

use crate::error::{Error, Result};

/// The profile's columns (their meanings in `COLUMNS.md`).
pub const COLUMNS: [&str; 8] = [
    "kind",
    "task",
    "start_s",
    "end_s",
    "wall_s",
    "cpu_s",
    "thread_cpu_s",
    "rss_mb",
];
use std::io::Write;
use std::path::Path;
use std::sync::{Mutex, OnceLock};
use std::time::Instant;

/// The open profile and the instant it began.
static PROFILE: OnceLock<(Mutex<std::fs::File>, Instant)> = OnceLock::new();

/// Clock ticks per second of `/proc/*/stat` (`USER_HZ`, 100 on every Linux ABI).
const TICKS: f64 = 100.0;

/// Starts profiling into `path` (a new CSV with its header), outside the report's directory
/// `out`, whose files the report writes, locks and replaces (`out` is created first, so that a
/// symlink or a relative path is compared where it leads).
pub fn start(path: &Path, out: &Path) -> Result<()> {
    // Named by its flag: the file is created before the work, and `report --profile` is its
    // only caller.
    let refuse = |e: std::io::Error| {
        Error::invalid(
            "--profile",
            path.display().to_string(),
            &format!("cannot be written: {e}"),
        )
    };
    crate::util::output_dir(out, "--out")?;
    let parent = path.parent().filter(|d| !d.as_os_str().is_empty());
    let target = path.canonicalize().ok().or_else(|| {
        let dir = parent.unwrap_or(Path::new(".")).canonicalize().ok()?;
        Some(dir.join(path.file_name()?))
    });
    if target
        .zip(out.canonicalize().ok())
        .is_some_and(|(t, o)| t.starts_with(o))
    {
        return Err(Error::invalid(
            "--profile",
            path.display().to_string(),
            "inside --out, whose files the report writes, locks and replaces: write the \
             profile elsewhere",
        ));
    }
    // A FIFO would block the open until a reader comes; a device (/dev/null, a terminal's
    // /dev/stdout) takes the lines.
    if let Some(kind @ ("a FIFO" | "a directory")) = crate::input::not_regular(path) {
        return Err(Error::invalid(
            "--profile",
            path.display().to_string(),
            &format!("not a regular file ({kind}): refused"),
        ));
    }
    refuse_other_file(path)?;
    let mut file = std::fs::File::create(path).map_err(refuse)?;
    writeln!(file, "{}", COLUMNS.join(",")).map_err(refuse)?;
    // A second start keeps the first profile.
    let _ = PROFILE.set((Mutex::new(file), Instant::now()));
    Ok(())
}

/// Refuses to replace a regular file that holds something else than a profile (its first line
/// not the profile's header): `--profile cases/bar1d.toml` would destroy the case file. An
/// empty file, a device and a path not there yet are taken.
fn refuse_other_file(path: &Path) -> Result<()> {
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.len() > 0) {
        return Ok(());
    }
    let header = COLUMNS.join(",");
    let first = crate::input::TABLE
        .named("profile")
        .read(path)
        .ok()
        .and_then(|bytes| {
            let line = bytes.split(|&b| b == b'\n').next()?.to_vec();
            String::from_utf8(line).ok()
        });
    if first.as_deref() == Some(header.as_str()) {
        return Ok(());
    }
    Err(Error::invalid(
        "--profile",
        path.display().to_string(),
        &format!(
            "exists and is not a profile (its first line is not `{header}`): refused, to keep \
             it; remove it or write the profile elsewhere"
        ),
    ))
}

/// CPU time (user + system) of this process so far, seconds (NaN where `/proc/self/stat`
/// cannot be read): beside the wall time on a shared machine.
pub fn cpu_seconds() -> f64 {
    cpu("self")
}

/// User + system seconds of `/proc/<which>/stat` (`self` or `thread-self`).
fn cpu(which: &str) -> f64 {
    let Ok(stat) = std::fs::read_to_string(format!("/proc/{which}/stat")) else {
        return f64::NAN;
    };
    // Fields after the command name (in parentheses, which may hold spaces): utime and stime
    // are the 14th and 15th fields, the 12th and 13th after it.
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    let ticks: Vec<f64> = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|t| t.parse().ok())
        .collect();
    match ticks[..] {
        [u, s] => (u + s) / TICKS,
        _ => f64::NAN,
    }
}

/// Resident memory of the process now, MB (`VmRSS`).
fn rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let line = s.lines().find(|l| l.starts_with("VmRSS:"))?;
            line.split_whitespace().nth(1)?.parse::<f64>().ok()
        })
        .map_or(f64::NAN, |kib| kib / 1024.0)
}

/// A task being timed.
pub struct Timer {
    start: Instant,
    cpu: f64,
    thread_cpu: f64,
}

impl Timer {
    /// Starts timing a task (None when not profiling).
    pub fn start() -> Option<Self> {
        PROFILE.get()?;
        Some(Self {
            start: Instant::now(),
            cpu: cpu_seconds(),
            thread_cpu: cpu("thread-self"),
        })
    }

    /// Writes the task's line: `kind` and its name `task`.
    pub fn stop(self, kind: &str, task: &str) {
        let Some((file, began)) = PROFILE.get() else {
            return;
        };
        let at = |i: Instant| i.duration_since(*began).as_secs_f64();
        let now = Instant::now();
        let line = format!(
            "{kind},\"{}\",{:.3},{:.3},{:.3},{:.2},{:.2},{:.0}\n",
            task.replace('"', "'"),
            at(self.start),
            at(now),
            now.duration_since(self.start).as_secs_f64(),
            cpu_seconds() - self.cpu,
            cpu("thread-self") - self.thread_cpu,
            rss_mb()
        );
        if let Ok(mut f) = file.lock() {
            // The profile is a diagnostic: a failed write does not stop the report.
            let _ = f.write_all(line.as_bytes());
        }
    }
}

/// Runs `f` as the section `task` of the profile.
pub fn section<R>(task: &str, f: impl FnOnce() -> R) -> R {
    let timer = Timer::start();
    let r = f();
    if let Some(t) = timer {
        t.stop("section", task);
    }
    r
}
