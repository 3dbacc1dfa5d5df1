//! Small grouping helpers shared by the study layer and the report: outputs follow the
//! enumeration order of the runs, so groups keep first-appearance order.

/// Distinct items in first-appearance order.
pub fn unique<T: PartialEq>(items: impl IntoIterator<Item = T>) -> Vec<T> {
    let mut v = Vec::new();
    for x in items {
        if !v.contains(&x) {
            v.push(x);
        }
    }
    v
}

/// Items grouped by `key`, groups and members in first-appearance order.
pub fn group_by<K: PartialEq, T>(
    items: impl IntoIterator<Item = T>,
    key: impl Fn(&T) -> K,
) -> Vec<(K, Vec<T>)> {
    let mut groups: Vec<(K, Vec<T>)> = Vec::new();
    for x in items {
        let k = key(&x);
        match groups.iter_mut().find(|(g, _)| *g == k) {
            Some((_, v)) => v.push(x),
            None => groups.push((k, vec![x])),
        }
    }
    groups
}

/// 64-bit FNV-1a hash of `bytes`, printed as 16 hex digits: a stable content key (unlike
/// `std`'s `DefaultHasher`, whose algorithm may change between Rust releases).
pub fn content_hash(bytes: &[u8]) -> String {
    let h = bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{h:016x}")
}

/// Memory this process can still allocate (bytes): the least of what the system can give
/// (`MemAvailable` of `/proc/meminfo`), what its address-space limit leaves (`ulimit -v`: the
/// soft `Max address space` of `/proc/self/limits` less `VmSize` and what the threads will
/// reserve beyond it, [`thread_reserve`]) and what its memory cgroups leave
/// ([`cgroup_memory_left`]: a batch scheduler's limit); `None` where none can be read.
pub fn available_memory() -> Option<f64> {
    let system = proc_field("/proc/meminfo", "MemAvailable:").map(|kib| kib * 1024.0);
    // The soft `Max address space` (bytes; `None` when unlimited).
    let status = |f: &str| proc_field("/proc/self/status", f).map(|kib| kib * 1024.0);
    let address_space = proc_field("/proc/self/limits", "Max address space")
        .zip(status("VmSize:"))
        .map(|(limit, size)| {
            let reserved = size - status("VmRSS:").unwrap_or(size);
            (limit - size - thread_reserve(reserved)).max(0.0)
        });
    [system, address_space, cgroup_memory_left()]
        .into_iter()
        .flatten()
        .reduce(f64::min)
}

/// The least memory left under this process's memory cgroup and its ancestors (from
/// `/proc/self/cgroup`): the limit less the usage without the page cache, which the kernel
/// reclaims (cgroup v2: `memory.max`, `memory.current`, `file` of `memory.stat`; v1:
/// `memory.limit_in_bytes`, `memory.usage_in_bytes`, `total_cache`). `None` without a limit.
fn cgroup_memory_left() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    let mut least: Option<f64> = None;
    for line in text.lines() {
        let mut parts = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) = (parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        let (root, limit, usage, cache) = if controllers.is_empty() {
            ("/sys/fs/cgroup", "memory.max", "memory.current", "file ")
        } else if controllers.split(',').any(|c| c == "memory") {
            (
                "/sys/fs/cgroup/memory",
                "memory.limit_in_bytes",
                "memory.usage_in_bytes",
                "total_cache ",
            )
        } else {
            continue;
        };
        let mut dir = std::path::Path::new(root).join(path.trim_start_matches('/'));
        loop {
            let file = |f: &str| dir.join(f).display().to_string();
            if let (Some(l), Some(u)) = (number_in(&file(limit)), number_in(&file(usage))) {
                let cached = proc_field(&file("memory.stat"), cache).unwrap_or(0.0);
                let left = (l - (u - cached).max(0.0)).max(0.0);
                least = Some(least.map_or(left, |m| m.min(left)));
            }
            if dir == std::path::Path::new(root) || !dir.pop() {
                break;
            }
        }
    }
    least
}

/// The number after `key` on its line of the file `path` (kiB in `/proc`'s status files, bytes
/// in `/proc/self/limits` and a cgroup's `memory.stat`); `None` for `unlimited` or unreadable.
fn proc_field(path: &str, key: &str) -> Option<f64> {
    let text = std::fs::read_to_string(path).ok()?;
    let line = text.lines().find(|l| l.starts_with(key))?;
    line[key.len()..].split_whitespace().next()?.parse().ok()
}

/// The number a whole file holds (a cgroup's limit or usage); `None` for `max` or unreadable.
fn number_in(path: &str) -> Option<f64> {
    std::fs::read_to_string(path).ok()?.trim().parse().ok()
}

/// The address space the run's threads (the workers and the sampling one) will still reserve
/// beyond their resident memory, [`THREAD_ADDRESS_SPACE`] each less what the process holds so
/// already (`reserved`, `VmSize` less `VmRSS`: the threads started so far). Counted as rayon
/// will size its pool, from the first of [`THREAD_VARIABLES`] set (0: one per core) or the
/// cores, without starting it (which would panic if a thread could not start).
fn thread_reserve(reserved: f64) -> f64 {
    let workers = thread_setting(|v| std::env::var(v).ok())
        .and_then(|(_, t)| t.parse::<usize>().ok())
        .filter(|&t| t > 0)
        .or_else(|| std::thread::available_parallelism().ok().map(|n| n.get()))
        .unwrap_or(1);
    ((workers + 1) as f64 * THREAD_ADDRESS_SPACE - reserved).max(0.0)
}

/// Refuses, before anything is allocated, a size `value` of `field` whose estimated memory
/// `bytes` exceeds the memory available.
pub fn check_memory(field: &str, value: impl std::fmt::Debug, bytes: f64) -> crate::Result<()> {
    match available_memory() {
        Some(avail) if bytes > avail => Err(crate::Error::invalid(
            field,
            value,
            &format!(
                "the run would need about {}, more than the {} available (free memory, ulimit \
                 -v and the memory cgroups' limits)",
                memory(bytes),
                memory(avail)
            ),
        )),
        _ => Ok(()),
    }
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Address space a run takes beyond its resident memory, per thread (the worker threads and
/// the sampling one): malloc's arenas and the stacks. Measured on two threads, `VmPeak` less
/// `VmHWM` of `/proc/<pid>/status`: 360 MB for hertz3d at n = 12, 225 MB for a bar of 10⁶
/// elements; under `ulimit -v` near its resident memory a run was refused by no check and
/// aborted in an allocation instead.
const THREAD_ADDRESS_SPACE: f64 = 128.0 * 1024.0 * 1024.0;

/// `bytes` in MiB below 0.1 GiB, else in GiB with one decimal, in exponent form from 10⁴ GiB
/// (`2.4e19 GiB` for an absurd count).
fn memory(bytes: f64) -> String {
    match bytes / GIB {
        g if g < 0.1 => format!("{:.0} MiB", g * 1024.0),
        g if g < 1e4 => format!("{g:.1} GiB"),
        g => format!("{g:.1e} GiB"),
    }
}

/// Refuses a `value` of `field` that cannot name a file of its own: names of sweeps and cases
/// become parts of the report's file names (`<case>_<sweep>_orders.png`), so they are 1 to 64
/// ASCII letters, digits, `_`, `-` or `.`, not starting with `.` (no `/`, no `..`).
pub fn check_name(field: &str, value: &str) -> crate::Result<()> {
    let ok = (1..=64).contains(&value.len())
        && !value.starts_with('.')
        && value
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
    if ok {
        Ok(())
    } else {
        Err(crate::Error::invalid(
            field,
            value,
            "1 to 64 ASCII letters, digits, `_`, `-` or `.`, not starting with `.`: it becomes \
             part of file names",
        ))
    }
}

/// `n` and the noun, plural unless `n` is 1: `count(1, "run")` is `1 run`.
pub fn count(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

/// The first item of `items` equal to an earlier one.
pub fn first_repeated<T: PartialEq>(items: &[T]) -> Option<&T> {
    items
        .iter()
        .enumerate()
        .find(|(i, x)| items[..*i].contains(x))
        .map(|(_, x)| x)
}

/// Creates the output directory `dir` given by the flag `flag` (`--out`), refusing a path that is
/// not a directory, cannot be created or cannot be written to, by the flag's name: called before
/// the work, which it would otherwise lose.
pub fn output_dir(dir: &std::path::Path, flag: &str) -> crate::Result<()> {
    let refuse = |why: &str| crate::Error::invalid(flag, dir.display().to_string(), why);
    if dir.exists() && !dir.is_dir() {
        return Err(refuse("exists and is not a directory"));
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| refuse(&format!("cannot be created as a directory: {e}")))?;
    // Writable: a file created and removed now, not a failure after the work (`/proc`).
    let probe = dir.join(format!(".dyncontact-probe-{}", std::process::id()));
    std::fs::write(&probe, b"")
        .and_then(|()| std::fs::remove_file(&probe))
        .map_err(|e| refuse(&format!("cannot be written to: {e}")))
}

/// Worker threads per core that `RAYON_NUM_THREADS` may ask for (at least [`MIN_THREAD_CAP`]
/// in all).
pub const THREADS_PER_CORE: usize = 4;

/// The fewest worker threads `RAYON_NUM_THREADS` may always ask for.
pub const MIN_THREAD_CAP: usize = 64;

/// The environment variables rayon sizes its pool from, in the order it reads them: the
/// second (deprecated) only when the first is unset, empty or not a whole number.
pub const THREAD_VARIABLES: [&str; 2] = ["RAYON_NUM_THREADS", "RAYON_RS_NUM_CPUS"];

/// Refuses the worker-thread count rayon would take from `lookup` (the environment): each of
/// [`THREAD_VARIABLES`] that rayon reads, when not empty, must be a whole number (rayon would
/// silently fall back to one thread per core) of at most [`THREADS_PER_CORE`] per core of
/// `cores`: each worker takes a stack and the report schedules a run on each (10⁴ made a
/// one-step spring take 35 s, 10⁵ never started). The error names the variable.
pub fn check_threads(lookup: impl Fn(&str) -> Option<String>, cores: usize) -> crate::Result<()> {
    // Parsed as rayon parses it (no trimming); a valid first variable is the one rayon takes.
    match thread_setting(lookup) {
        Some((name, text)) => check_thread_count(name, &text, cores),
        None => Ok(()),
    }
}

/// The first of [`THREAD_VARIABLES`] set and not empty, with its text, as rayon reads them
/// (unset or empty: the next variable, then rayon's default).
fn thread_setting(lookup: impl Fn(&str) -> Option<String>) -> Option<(&'static str, String)> {
    THREAD_VARIABLES
        .into_iter()
        .find_map(|name| Some((name, lookup(name).filter(|t| !t.is_empty())?)))
}

/// One variable of [`check_threads`]: `text` a whole number up to the cap.
fn check_thread_count(name: &str, text: &str, cores: usize) -> crate::Result<()> {
    let cap = (THREADS_PER_CORE * cores).max(MIN_THREAD_CAP);
    let refuse = |why: &str| crate::Error::invalid(name, text, why);
    match text.parse::<usize>() {
        Err(_) => Err(refuse(
            "must be a whole number of worker threads (0: one per core)",
        )),
        Ok(n) if n > cap => Err(refuse(&format!(
            "at most {cap} worker threads on this machine (the larger of {THREADS_PER_CORE} per \
             core and {MIN_THREAD_CAP}): each takes a stack, and the report runs a case on each"
        ))),
        Ok(_) => Ok(()),
    }
}

/// Peak resident memory of this process so far (`VmHWM` of `/proc/self/status`, bytes).
pub fn peak_memory() -> Option<f64> {
    proc_field("/proc/self/status", "VmHWM:").map(|kib| kib * 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An environment of `(name, value)` pairs for [`check_threads`].
    fn env(pairs: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let pairs: Vec<(String, String)> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        move |name| {
            pairs
                .iter()
                .find(|(k, _)| k == name)
                .map(|(_, v)| v.clone())
        }
    }

    #[test]
    fn worker_threads_are_whole_numbers_up_to_four_per_core() {
        for name in THREAD_VARIABLES {
            for ok in ["", "0", "1", "64"] {
                assert!(check_threads(env(&[(name, ok)]), 2).is_ok(), "{name}={ok}");
            }
            assert!(check_threads(env(&[(name, "512")]), 128).is_ok());
            for bad in ["65", "100000", "abc", "-1", "1.5", " 8 "] {
                let e = check_threads(env(&[(name, bad)]), 2)
                    .unwrap_err()
                    .to_string();
                assert!(e.contains(name), "{name}={bad}: {e}");
            }
        }
        assert!(check_threads(env(&[]), 2).is_ok());
    }

    /// rayon reads the deprecated variable only when the first is unset, empty or unparsable
    /// (and the last is refused before it gets there).
    #[test]
    fn the_deprecated_variable_counts_only_where_rayon_reads_it() {
        let (first, second) = (THREAD_VARIABLES[0], THREAD_VARIABLES[1]);
        assert!(check_threads(env(&[(first, "2"), (second, "100000")]), 2).is_ok());
        let e = check_threads(env(&[(first, ""), (second, "100000")]), 2).unwrap_err();
        assert!(e.to_string().contains(second), "{e}");
    }

    #[test]
    fn fnv1a_matches_its_published_test_vectors() {
        assert_eq!(content_hash(b""), "cbf29ce484222325");
        assert_eq!(content_hash(b"a"), "af63dc4c8601ec8c");
        assert_eq!(content_hash(b"foobar"), "85944171f73967e8");
    }

    #[test]
    fn a_size_beyond_the_available_memory_is_refused_with_the_estimate() {
        let Some(avail) = available_memory() else {
            return;
        };
        // Never more than the system's free memory, never nothing on a machine that runs.
        let system = proc_field("/proc/meminfo", "MemAvailable:").map(|kib| kib * 1024.0);
        assert!(avail > 0.0 && system.is_none_or(|s| avail <= s), "{avail}");
        assert!(check_memory("mesh.elements", 10, avail / 2.0).is_ok());
        let e = check_memory("mesh.elements", 10, 2.0 * avail)
            .unwrap_err()
            .to_string();
        assert!(e.contains("mesh.elements") && e.contains("GiB"), "{e}");
        assert!(peak_memory().is_some_and(|p| p > 0.0));
    }

    #[test]
    fn groups_keep_first_appearance_order() {
        let g = group_by([3, 1, 3, 2, 1], |x| *x);
        assert_eq!(g, vec![(3, vec![3, 3]), (1, vec![1, 1]), (2, vec![2])]);
        assert_eq!(unique([2, 2, 1, 2]), vec![2, 1]);
    }
}
