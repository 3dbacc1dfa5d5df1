//! One study at a time per journal: `report` and `sweep` hold `<journal>.lock` beside their
//! journal (`OUT/journal.csv.lock`; a shard's own journal has its own lock) while they run, and
//! `run` holds `OUT/journal.csv.lock` while it runs and writes (two runs into one directory
//! would mix their files: one's summary, the other's figures).
//! A second study into the same directory would empty the journal (or, with `--resume`, append
//! the same runs again) and redo every run; it is refused, naming the holder's process id.
//!
//! The lock is an advisory `flock` on the file, which the kernel releases when its holder
//! exits in any way (a SIGKILL included), so a lock file left behind by a killed study is taken
//! over; a study that ends removes it. On platforms without `flock` the file is written but
//! not locked.

use crate::error::{Error, Result};
use std::fs::File;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// A held lock; released (and its file removed) when dropped.
#[derive(Debug)]
pub struct Lock {
    path: PathBuf,
    // Holds the flock until the lock is dropped, after the file is removed.
    _file: File,
}

impl Lock {
    /// Takes the lock of the journal `dir/journal`, or fails naming the process holding it.
    pub fn acquire(dir: &Path, journal: &str) -> Result<Self> {
        let path = dir.join(format!("{journal}.lock"));
        let io = |e: std::io::Error| Error::io(&path, e);
        if let Some(kind) = crate::input::not_regular(&path) {
            return Err(io(std::io::Error::other(format!(
                "not a regular file ({kind}): remove it, or write into another directory"
            ))));
        }
        loop {
            let mut file = std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(io)?;
            if !try_lock(&file).map_err(io)? {
                let mut holder = String::new();
                let _ = file.read_to_string(&mut holder);
                return Err(io(std::io::Error::new(
                    std::io::ErrorKind::WouldBlock,
                    format!(
                        "held by another run, report or sweep into {} (process {}): wait for it to \
                         end, or write into another directory",
                        dir.display(),
                        holder.trim()
                    ),
                )));
            }
            // The file may have been removed by its previous holder between our open and our
            // lock: then the lock is on a file nobody else sees, so start again.
            if same_file(&file, &path) {
                file.set_len(0).map_err(io)?;
                write!(file, "{}", std::process::id()).map_err(io)?;
                return Ok(Self { path, _file: file });
            }
        }
    }
}

impl Drop for Lock {
    fn drop(&mut self) {
        // Removed while still locked; the flock goes with the file handle, dropped next.
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Takes an exclusive `flock` without waiting: false when another holds it.
#[cfg(unix)]
fn try_lock(file: &File) -> std::io::Result<bool> {
    use rustix::fs::{flock, FlockOperation};
    match flock(file, FlockOperation::NonBlockingLockExclusive) {
        Ok(()) => Ok(true),
        Err(rustix::io::Errno::WOULDBLOCK) => Ok(false),
        Err(e) => Err(e.into()),
    }
}

#[cfg(not(unix))]
fn try_lock(_: &File) -> std::io::Result<bool> {
    Ok(true)
}

/// True when `path` still names the open `file`.
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => (a.dev(), a.ino()) == (b.dev(), b.ino()),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    path.exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_study_is_refused_naming_the_holder_until_the_first_ends() {
        let dir = tempfile::tempdir().unwrap();
        let first = Lock::acquire(dir.path(), "journal.csv").unwrap();
        let lock = dir.path().join("journal.csv.lock");
        assert_eq!(
            std::fs::read_to_string(&lock).unwrap(),
            std::process::id().to_string()
        );
        let e = Lock::acquire(dir.path(), "journal.csv")
            .unwrap_err()
            .to_string();
        if cfg!(unix) {
            assert!(
                e.contains(&format!("(process {})", std::process::id())),
                "{e}"
            );
        }
        // Another journal (a shard) has its own lock.
        let shard = Lock::acquire(dir.path(), "journal-2-of-4.csv").unwrap();
        drop((first, shard));
        assert!(!lock.exists());
        Lock::acquire(dir.path(), "journal.csv").unwrap();
    }

    #[test]
    fn a_lock_file_left_by_a_killed_study_is_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let lock = dir.path().join("journal.csv.lock");
        std::fs::write(&lock, "4194304").unwrap();
        let held = Lock::acquire(dir.path(), "journal.csv").unwrap();
        assert_eq!(
            std::fs::read_to_string(&lock).unwrap(),
            std::process::id().to_string()
        );
        drop(held);
    }
}
