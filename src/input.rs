//! Reading the files a user names: case files, Gmsh meshes, and the CSV tables read back (the
//! records of `merge`, the journal and probe series of `--resume`, the peers' trajectories).
//!
//! Every reader goes through [`Input::read`], which
//! - refuses anything that is not a regular file **before opening it** (opening a FIFO without a
//!   writer blocks forever; `/dev/zero` and `/dev/urandom` never end), then opens without
//!   blocking and checks the opened file again (a path swapped in between);
//! - caps the size per kind of file ([`CASE_FILE`], [`MESH_FILE`], [`TABLE`]): refused from the
//!   size the file system reports, and the read stops one byte past the cap (a file that grows,
//!   or reports no size, as `/proc` files do).
//!
//! Every error names the file's role and path, and the cap when it is exceeded.

use crate::error::{Error, Result};
use std::io::Read;
use std::path::Path;

/// A kind of input file: its role in messages and its size cap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Input {
    /// What the file is, in messages (`case file`, `mesh file`, …).
    pub role: &'static str,
    /// Largest accepted size, bytes.
    pub cap: u64,
}

const MIB: u64 = 1 << 20;

/// Case files (TOML): the shipped ones are 1–4 KiB.
pub const CASE_FILE: Input = Input {
    role: "case file",
    cap: MIB,
};

/// Gmsh meshes: 1 GiB is an ASCII mesh of some 2·10⁷ dofs, beyond what a run of this machine's
/// memory can hold.
pub const MESH_FILE: Input = Input {
    role: "mesh file",
    cap: 1024 * MIB,
};

/// CSV tables read back (records, journal, probe series, peer trajectories): a probe series of
/// 10⁶ steps is 60 MiB.
pub const TABLE: Input = Input {
    role: "input file",
    cap: 256 * MIB,
};

impl Input {
    /// The same limits under another role (`records file`, `journal`, …).
    pub const fn named(self, role: &'static str) -> Self {
        Self { role, ..self }
    }

    /// An error about the file at `path`.
    pub fn error(&self, path: &Path, message: impl Into<String>) -> Error {
        Error::Input {
            role: self.role,
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// The bytes of the regular file at `path`, at most [`Input::cap`] of them.
    pub fn read(&self, path: &Path) -> Result<Vec<u8>> {
        let io = |e: std::io::Error| self.error(path, e.to_string());
        self.check(path, &std::fs::metadata(path).map_err(io)?)?;
        let file = open_nonblocking(path).map_err(io)?;
        self.check(path, &file.metadata().map_err(io)?)?;
        let mut bytes = Vec::new();
        file.take(self.cap + 1)
            .read_to_end(&mut bytes)
            .map_err(io)?;
        if bytes.len() as u64 > self.cap {
            return Err(self.too_large(path, "more than that read"));
        }
        Ok(bytes)
    }

    /// The text of the regular file at `path` (UTF-8), at most [`Input::cap`] bytes.
    pub fn read_to_string(&self, path: &Path) -> Result<String> {
        String::from_utf8(self.read(path)?)
            .map_err(|e| self.error(path, format!("not UTF-8 text: {}", e.utf8_error())))
    }

    /// Refuses what is not a regular file, or is larger than the cap.
    fn check(&self, path: &Path, meta: &std::fs::Metadata) -> Result<()> {
        if !meta.is_file() {
            return Err(self.error(
                path,
                format!("not a regular file ({}): refused", file_kind(meta)),
            ));
        }
        if meta.len() > self.cap {
            return Err(self.too_large(path, &format!("{} bytes", meta.len())));
        }
        Ok(())
    }

    fn too_large(&self, path: &Path, size: &str) -> Error {
        self.error(
            path,
            format!(
                "larger than the limit of {} for a {} ({size})",
                human(self.cap),
                self.role
            ),
        )
    }
}

/// `n MiB` for whole mebibytes, else `n bytes`.
fn human(bytes: u64) -> String {
    if bytes.is_multiple_of(MIB) {
        format!("{} MiB", bytes / MIB)
    } else {
        format!("{bytes} bytes")
    }
}

/// What the existing file at `path` is when it is not a regular file (a FIFO, a device, a
/// directory): a file the program writes in place must be refused first, as opening a FIFO for
/// writing waits for a reader forever. None when `path` is a regular file or does not exist.
pub fn not_regular(path: &Path) -> Option<&'static str> {
    let meta = std::fs::metadata(path).ok()?;
    (!meta.is_file()).then(|| file_kind(&meta))
}

/// What a file that is not regular is, for messages.
fn file_kind(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if meta.is_dir() {
        "a directory"
    } else {
        "a special file"
    }
}

/// Opens for reading without blocking on a FIFO (a regular file reads as usual).
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // The flag's bits are a C int.
        options.custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32);
    }
    options.open(path)
}

/// An input of a command: its role in messages (`case file`, `mesh file`, …) and its path.
pub type Named = (&'static str, std::path::PathBuf);

/// Refuses, before any work, to write an output where it would replace one of the command's
/// `inputs` (`run case.toml --out DIR` where `DIR/summary.csv` is the case file): each output
/// that exists is compared with each input by where its path leads, and the error names both.
/// `outputs` are the files the command writes, each with the flag that places it.
pub fn refuse_overwrite(inputs: &[Named], outputs: &[Named]) -> Result<()> {
    let inputs: Vec<(&Named, std::path::PathBuf)> = inputs
        .iter()
        .filter_map(|i| Some((i, i.1.canonicalize().ok()?)))
        .collect();
    for (flag, out) in outputs {
        let Ok(target) = out.canonicalize() else {
            continue;
        };
        if let Some(((role, path), _)) = inputs.iter().find(|(_, p)| *p == target) {
            return Err(Error::invalid(
                *flag,
                out.display().to_string(),
                &format!(
                    "is the {role} {} this command reads: writing it would destroy its input \
                     (choose another {flag})",
                    path.display()
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_and_directories_are_refused_before_any_read() {
        for (path, kind) in [
            ("/dev/zero", "a character device"),
            ("/dev/urandom", "a character device"),
            ("/", "a directory"),
        ] {
            let e = CASE_FILE.read(Path::new(path)).unwrap_err().to_string();
            assert!(
                e.contains("case file") && e.contains(path) && e.contains(kind),
                "{e}"
            );
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_without_writer_is_refused_without_blocking() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("case.toml");
        let status = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(status.success());
        let e = MESH_FILE.read(&fifo).unwrap_err().to_string();
        assert!(e.contains("mesh file") && e.contains("a FIFO"), "{e}");
    }

    #[test]
    fn a_file_over_the_cap_is_refused_with_the_cap() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.csv");
        std::fs::write(&path, vec![b'x'; 2 * MIB as usize + 1]).unwrap();
        let small = Input {
            role: "records file",
            cap: 2 * MIB,
        };
        let e = small.read(&path).unwrap_err().to_string();
        assert!(
            e.contains("records file") && e.contains("limit of 2 MiB") && e.contains("2097153"),
            "{e}"
        );
        std::fs::write(&path, b"t\n1\n").unwrap();
        assert_eq!(small.read(&path).unwrap(), b"t\n1\n");
    }

    #[test]
    fn a_file_without_a_size_is_read_up_to_the_cap() {
        // /proc files report a size of 0 and are regular: the read itself stops at the cap.
        let tiny = Input {
            role: "input file",
            cap: 16,
        };
        let path = Path::new("/proc/self/status");
        if path.exists() {
            let e = tiny.read(path).unwrap_err().to_string();
            assert!(e.contains("limit of 16 bytes"), "{e}");
        }
    }
}
