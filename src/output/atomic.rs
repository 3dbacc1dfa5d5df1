//! Output files appear complete or not at all: [`write_with`] writes a file under a temporary
//! name in its own directory, `.<stem>.tmp<pid>-<n>.<ext>` (hidden, with the final extension,
//! which the PNG and VTK writers read to choose the format), and renames it over the final name
//! once complete. A kill (SIGINT, SIGTERM, SIGKILL) or a write error (a full disk) leaves the
//! previous file, if any, under the final name; a failed write removes its temporary file, a
//! killed one leaves it behind under its hidden name.
//!
//! The rename is atomic on one file system (POSIX `rename`). There is no fsync: a full disk is
//! reported by the writes themselves on ext4, XFS and tmpfs (delayed allocation reserves the
//! blocks at write time); durability across a power cut is not sought.

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Temporary files made by this process so far (names stay distinct across threads).
static COUNTER: AtomicUsize = AtomicUsize::new(0);

/// The temporary name of `path`: `.<stem>.tmp<pid>-<n>.<ext>` in the same directory.
fn temporary(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or("out".into(), |s| s.to_string_lossy());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let mut name = format!(".{stem}.tmp{}-{n}", std::process::id());
    if let Some(ext) = path.extension() {
        name.push('.');
        name.push_str(&ext.to_string_lossy());
    }
    path.with_file_name(name)
}

/// Writes the file `path` through `write`, which writes a complete file at the path it is
/// given (a temporary one), then renames that file to `path`. On an error of `write` or of the
/// rename, the temporary file is removed and `path` is left as it was.
pub fn write_with<T>(path: &Path, write: impl FnOnce(&Path) -> Result<T>) -> Result<T> {
    let tmp = temporary(path);
    let done = write(&tmp).and_then(|value| {
        std::fs::rename(&tmp, path)
            .map(|()| value)
            .map_err(|e| Error::io(path, e))
    });
    if done.is_err() {
        // Nothing may be there (the writer failed before creating it).
        let _ = std::fs::remove_file(&tmp);
    }
    done
}

/// Writes `bytes` to the file `path` through [`write_with`].
pub fn write_bytes(path: &Path, bytes: impl AsRef<[u8]>) -> Result<()> {
    write_with(path, |tmp| {
        std::fs::write(tmp, bytes.as_ref()).map_err(|e| Error::io(path, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_final_name_holds_the_old_file_until_the_new_one_is_complete() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("timeseries.csv");
        write_bytes(&path, "old\n").unwrap();
        write_with(&path, |tmp| {
            assert_eq!(tmp.parent(), path.parent());
            assert_eq!(tmp.extension(), path.extension());
            std::fs::write(tmp, "new, half").unwrap();
            // Killed here: the final name still holds the old file.
            assert_eq!(std::fs::read_to_string(&path).unwrap(), "old\n");
            std::fs::write(tmp, "new\n").map_err(|e| Error::io(tmp, e))
        })
        .unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new\n");
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "temporary file left: {names:?}");
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_removes_the_temporary_one() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("energy.png");
        write_bytes(&path, "old").unwrap();
        let e = write_with(&path, |tmp| -> Result<()> {
            std::fs::write(tmp, "partial").unwrap();
            Err(Error::io(tmp, std::io::ErrorKind::StorageFull.into()))
        })
        .unwrap_err();
        assert!(e.to_string().contains("energy"), "{e}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_csv_written_row_by_row_never_shows_under_its_final_name_half_done() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.csv");
        write_bytes(&path, "a\nold\n").unwrap();
        let rows = (0..1000).map(|k| {
            if k == 500 {
                assert_eq!(std::fs::read_to_string(&path).unwrap(), "a\nold\n");
            }
            vec![k.to_string()]
        });
        super::super::csv::write_rows(&path, &["a"], rows).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().count(), 1001);
    }
}
