//! The order in which a study runs its tasks: longest first on a few worker threads (Graham's
//! LPT rule, "Bounds on multiprocessing timing anomalies", SIAM J. Appl. Math. 17, 1969: within
//! 4/3 of the shortest makespan), a task starting only while the estimated memory of the
//! running ones plus its own stays within a budget (a task alone always starts), so that two
//! heavy 3D runs do not overlap beyond it. A task that needs more than half the budget starts
//! before the others, longest first among such: the others that do not fit beside it would
//! otherwise keep passing it over, each one starting as another ends, and it would end the
//! study alone (the full report's singular dynamic sphere: it started at 70 % of the report
//! and its last 37 s ran alone).
//!
//! The workers are threads of their own, not rayon's: a run's own parallel loops (the CG
//! products, the element matrices) go to the rayon pool, and a worker waiting on them never
//! picks up another whole run meanwhile, as a rayon worker inside `par_iter` would. Results
//! come back in task order, whatever order the tasks ran in.

use std::sync::{Condvar, Mutex};

/// What a task is estimated to cost before it runs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Estimate {
    /// Seconds of one core (only the order matters).
    pub seconds: f64,
    /// Peak memory, bytes.
    pub bytes: f64,
}

/// The estimated memory a study's runs may take together, bytes: the full report's peak stays
/// under 4 GB with the process's own memory on top.
pub const MEMORY_BUDGET: f64 = 3.5e9;

/// The workers and the memory budget of a study: one worker per thread of the rayon pool
/// (`RAYON_NUM_THREADS`, by default one per core), and [`MEMORY_BUDGET`] or 80 % of the memory
/// available now, the smaller.
pub fn workers() -> (usize, f64) {
    let available = crate::util::available_memory().map_or(f64::INFINITY, |a| 0.8 * a);
    (rayon::current_num_threads(), MEMORY_BUDGET.min(available))
}

/// The scheduler's state: the tasks not started, longest first, and the memory of the running
/// ones.
struct Queue {
    pending: Vec<usize>,
    running: usize,
    bytes: f64,
}

/// Takes a task off the queue when it is done, even if it panicked, and wakes the waiting workers.
struct Done<'a> {
    queue: &'a (Mutex<Queue>, Condvar),
    bytes: f64,
}

impl Drop for Done<'_> {
    fn drop(&mut self) {
        let (lock, wake) = self.queue;
        let mut q = lock.lock().unwrap_or_else(|e| e.into_inner());
        q.running -= 1;
        q.bytes -= self.bytes;
        wake.notify_all();
    }
}

/// Runs `work` on every task on `threads` workers, those of more than half the `budget` of
/// [`Estimate::bytes`] first, then longest [`Estimate::seconds`] first, starting a task only
/// while the bytes of the running ones plus its own are within `budget` (the first task that
/// fits in that order; one task at a time always runs). Returns the results in task order.
pub fn run<T: Sync, R: Send>(
    tasks: &[T],
    estimate: impl Fn(&T) -> Estimate,
    (threads, budget): (usize, f64),
    work: impl Fn(&T) -> R + Sync,
) -> Vec<R> {
    let estimates: Vec<Estimate> = tasks.iter().map(estimate).collect();
    let mut pending: Vec<usize> = (0..tasks.len()).collect();
    // Heavy first, then longest first; ties in task order (a stable sort).
    let heavy = |i: usize| estimates[i].bytes > 0.5 * budget;
    pending.sort_by(|&a, &b| {
        heavy(b)
            .cmp(&heavy(a))
            .then(estimates[b].seconds.total_cmp(&estimates[a].seconds))
    });
    let queue = (
        Mutex::new(Queue {
            pending,
            running: 0,
            bytes: 0.0,
        }),
        Condvar::new(),
    );
    let next = || -> Option<(usize, Done<'_>)> {
        let (lock, wake) = &queue;
        let mut q = lock.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            if q.pending.is_empty() {
                return None;
            }
            let fits = |i: &usize| q.running == 0 || q.bytes + estimates[*i].bytes <= budget;
            if let Some(k) = q.pending.iter().position(fits) {
                let i = q.pending.remove(k);
                q.running += 1;
                q.bytes += estimates[i].bytes;
                let bytes = estimates[i].bytes;
                return Some((
                    i,
                    Done {
                        queue: &queue,
                        bytes,
                    },
                ));
            }
            q = wake.wait(q).unwrap_or_else(|e| e.into_inner());
        }
    };
    let mut done: Vec<(usize, R)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads.max(1))
            .map(|_| {
                scope.spawn(|| {
                    let mut mine = Vec::new();
                    while let Some((i, _done)) = next() {
                        mine.push((i, work(&tasks[i])));
                    }
                    mine
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    done.sort_by_key(|d| d.0);
    done.into_iter().map(|d| d.1).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Results come back in task order; the longest task starts first; two tasks whose memory
    /// together exceeds the budget never run at the same time, while small ones run beside them.
    #[test]
    fn longest_first_within_the_memory_budget() {
        let tasks: Vec<(f64, f64)> =
            vec![(1.0, 1.0), (5.0, 6.0), (2.0, 1.0), (4.0, 6.0), (3.0, 1.0)];
        let started = Mutex::new(Vec::new());
        let (heavy, max_heavy) = (AtomicUsize::new(0), AtomicUsize::new(0));
        let out = run(
            &tasks,
            |&(seconds, bytes)| Estimate { seconds, bytes },
            (2, 10.0),
            |&(seconds, bytes)| {
                started.lock().unwrap().push(seconds);
                let big = bytes > 5.0;
                if big {
                    let now = heavy.fetch_add(1, Ordering::SeqCst) + 1;
                    max_heavy.fetch_max(now, Ordering::SeqCst);
                }
                std::thread::sleep(std::time::Duration::from_millis(20));
                if big {
                    heavy.fetch_sub(1, Ordering::SeqCst);
                }
                seconds * 10.0
            },
        );
        assert_eq!(out, vec![10.0, 50.0, 20.0, 40.0, 30.0]);
        assert_eq!(started.lock().unwrap()[0], 5.0);
        assert_eq!(max_heavy.load(Ordering::SeqCst), 1);
    }

    /// A task of more than half the budget starts first, before a longer light one, so that
    /// it is not passed over while another heavy task runs.
    #[test]
    fn a_heavy_task_starts_first() {
        let tasks: Vec<(f64, f64)> = vec![(3.0, 1.0), (2.0, 6.0), (9.0, 5.0), (1.0, 1.0)];
        let started = Mutex::new(Vec::new());
        run(
            &tasks,
            |&(seconds, bytes)| Estimate { seconds, bytes },
            (1, 10.0),
            |&(seconds, _)| started.lock().unwrap().push(seconds),
        );
        assert_eq!(*started.lock().unwrap(), vec![2.0, 9.0, 3.0, 1.0]);
    }

    /// A task larger than the budget still runs, alone, and no task is lost.
    #[test]
    fn a_task_over_the_budget_runs_alone() {
        let tasks = [3.0, 1.0, 2.0, 1.0];
        let (running, beside_big) = (AtomicUsize::new(0), AtomicUsize::new(0));
        let out = run(
            &tasks,
            |&b| Estimate {
                seconds: b,
                bytes: b,
            },
            (3, 2.5),
            |&b| {
                let now = running.fetch_add(1, Ordering::SeqCst) + 1;
                std::thread::sleep(std::time::Duration::from_millis(20));
                if b > 2.5 {
                    beside_big.fetch_max(now.max(running.load(Ordering::SeqCst)), Ordering::SeqCst);
                }
                running.fetch_sub(1, Ordering::SeqCst);
                b
            },
        );
        assert_eq!(out, tasks);
        assert_eq!(beside_big.load(Ordering::SeqCst), 1);
    }
}
