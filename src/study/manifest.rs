//! The manifest of a sweep: which study its records belong to. `sweep` writes it beside its
//! records (`manifest-i-of-n.txt` beside `records-i-of-n.csv`, `manifest.txt` beside
//! `records.csv`): the study's fingerprint (a hash of every case file's bytes and of its mesh
//! file, of `--quick` and of the run keys), the shard, and the keys of the whole study in
//! enumeration order.
//!
//! `merge` reads the manifest beside each records file ([`in_study_order`]) and refuses a file
//! without one, a file that does not hold exactly its shard's runs, shards of one study cut two
//! ways and a study whose shards are not all given (shards of different case files, or of
//! `--quick` and full sweeps, are different studies); it returns the rows in enumeration
//! order, so that the merged outputs do not depend on the sharding or on the order of the files.

use super::jobs::{in_shard, Job, RunRecord};
use crate::cases::CaseFile;
use crate::error::{Error, Result};
use crate::input::{Input, TABLE};
use crate::util::content_hash;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A manifest read back.
const MANIFEST: Input = TABLE.named("manifest");

/// The first line of every manifest.
const FIRST_LINE: &str = "dyncontact sweep manifest";

/// Shard `i` of `n` (1-based), or None for a sweep without `--shard`.
pub type Shard = Option<(usize, usize)>;

/// What a sweep's records belong to.
#[derive(Debug, Clone, PartialEq)]
pub struct Manifest {
    /// The study's fingerprint (its case files, mesh files, `--quick` and keys).
    pub study: String,
    /// The shard whose records the manifest is beside.
    pub shard: Shard,
    /// The keys of every run of the study, in enumeration order.
    pub keys: Vec<String>,
}

/// `records.csv`, or `records-i-of-n.csv` for a shard.
pub fn records_name(shard: Shard) -> String {
    named("records", shard, "csv")
}

/// `<prefix>.<ext>`, or `<prefix>-i-of-n.<ext>` for a shard.
fn named(prefix: &str, shard: Shard, ext: &str) -> String {
    match shard {
        None => format!("{prefix}.{ext}"),
        Some((i, n)) => format!("{prefix}-{i}-of-{n}.{ext}"),
    }
}

/// The manifest beside the records file `records` (`records<rest>.csv` →
/// `manifest<rest>.txt`); None for a name `sweep` does not give its records.
pub fn path_beside(records: &Path) -> Option<PathBuf> {
    let name = records.file_name()?.to_str()?;
    let rest = name.strip_prefix("records")?.strip_suffix(".csv")?;
    Some(records.with_file_name(format!("manifest{rest}.txt")))
}

impl Manifest {
    /// The manifest of `shard` of the study of `files` with `quick`, whose runs, all of them
    /// in enumeration order, are `jobs`.
    pub fn new(files: &[Arc<CaseFile>], quick: bool, jobs: &[Job], shard: Shard) -> Result<Self> {
        let mut text = format!("quick {quick}\n");
        // Each case file's hash covers its mesh file's bytes.
        for f in files {
            text += &format!("case file {}\n", f.hash);
        }
        let keys: Vec<String> = jobs.iter().map(|j| j.key.clone()).collect();
        text += &keys.join("\n");
        Ok(Self {
            study: content_hash(text.as_bytes()),
            shard,
            keys,
        })
    }

    /// The manifest's text.
    fn text(&self) -> String {
        let shard = self
            .shard
            .map_or("none".to_string(), |(i, n)| format!("{i} of {n}"));
        let mut text = format!("{FIRST_LINE}\nstudy {}\nshard {shard}\n", self.study);
        for k in &self.keys {
            text += k;
            text.push('\n');
        }
        text
    }

    /// Writes the manifest (whole or not at all).
    pub fn write(&self, path: &Path) -> Result<()> {
        crate::output::atomic::write_bytes(path, self.text())
    }

    /// Reads the manifest at `path`, as [`Manifest::write`] wrote it.
    pub fn read(path: &Path) -> Result<Self> {
        let text = MANIFEST.read_to_string(path)?;
        let err = |m: &str| MANIFEST.error(path, m);
        let mut lines = text.lines();
        if lines.next() != Some(FIRST_LINE) {
            return Err(err(&format!(
                "line 1 is not `{FIRST_LINE}`: not a manifest written by `sweep`"
            )));
        }
        let field = |line: Option<&str>, name: &str, at: usize| -> Result<String> {
            line.and_then(|l| l.strip_prefix(name))
                .and_then(|v| v.strip_prefix(' '))
                .map(String::from)
                .ok_or_else(|| err(&format!("line {at} is not `{name} …`")))
        };
        let study = field(lines.next(), "study", 2)?;
        let shard = field(lines.next(), "shard", 3)?;
        let shard = match shard.as_str() {
            "none" => None,
            s => Some(parse_shard(s).ok_or_else(|| {
                err(&format!(
                    "line 3: shard `{s}` is not `none` nor `i of n`, 1 ≤ i ≤ n"
                ))
            })?),
        };
        let keys: Vec<String> = lines.map(String::from).collect();
        if let Some(at) = keys.iter().position(String::is_empty) {
            return Err(err(&format!(
                "line {}: an empty line where a key is due",
                at + 4
            )));
        }
        if let Some(k) = crate::util::first_repeated(&keys) {
            return Err(err(&format!(
                "the key `{k}` is listed twice (one run, one key)"
            )));
        }
        Ok(Self { study, shard, keys })
    }

    /// The keys of this manifest's shard, in enumeration order.
    fn shard_keys(&self) -> impl Iterator<Item = &String> {
        let shard = self.shard;
        self.keys
            .iter()
            .enumerate()
            .filter(move |(k, _)| shard.is_none_or(|s| in_shard(*k, s)))
            .map(|(_, key)| key)
    }

    /// Shards the study is cut into (1 without `--shard`).
    fn shards(&self) -> usize {
        self.shard.map_or(1, |s| s.1)
    }
}

/// `i of n` with 1 ≤ i ≤ n.
fn parse_shard(s: &str) -> Option<(usize, usize)> {
    let (i, n) = s.split_once(" of ")?;
    let (i, n) = (i.parse().ok()?, n.parse().ok()?);
    (1..=n).contains(&i).then_some((i, n))
}

/// Up to five of `keys`, then `…` if there are more.
fn some(keys: &[&String]) -> String {
    let mut shown: Vec<&str> = keys.iter().take(5).map(|k| k.as_str()).collect();
    if keys.len() > 5 {
        shown.push("…");
    }
    shown.join(", ")
}

/// One records file of a merge with its manifest.
struct ShardFile {
    path: PathBuf,
    manifest: Manifest,
    records: Vec<RunRecord>,
}

/// Reads the manifest beside the records file `path` and checks that the file is named as
/// `sweep` names that shard's records and holds exactly that shard's runs.
fn checked(path: PathBuf, records: Vec<RunRecord>) -> Result<ShardFile> {
    let manifest_path = path_beside(&path).ok_or_else(|| {
        super::records::RECORDS_FILE.error(
            &path,
            "not named as `sweep` names records (records.csv, records-i-of-n.csv), so there is \
             no manifest beside it to tell its study: keep the names `sweep` writes",
        )
    })?;
    if !manifest_path.exists() {
        return Err(super::records::RECORDS_FILE.error(
            &path,
            format!(
                "no manifest {} beside it (`sweep` writes one beside its records, naming the \
                 study they belong to): run the sweep again",
                manifest_path.display()
            ),
        ));
    }
    let manifest = Manifest::read(&manifest_path)?;
    let err = |m: String| super::records::RECORDS_FILE.error(&path, m);
    let expected = records_name(manifest.shard);
    if path.file_name().and_then(|n| n.to_str()) != Some(expected.as_str()) {
        return Err(err(format!(
            "its manifest {} is of {expected}: renamed? give each file its own name back",
            manifest_path.display()
        )));
    }
    let mine: HashSet<&String> = manifest.shard_keys().collect();
    if let Some((row, r)) = records
        .iter()
        .enumerate()
        .find(|(_, r)| !mine.contains(&r.key))
    {
        return Err(err(format!(
            "row {}, column `key`: `{}` is not a run of this shard of the study in {} (a \
             file of another sweep, or edited by hand?)",
            row + 2,
            r.key,
            manifest_path.display()
        )));
    }
    let held: HashSet<&String> = records.iter().map(|r| &r.key).collect();
    let missing: Vec<&String> = manifest
        .shard_keys()
        .filter(|k| !held.contains(k))
        .collect();
    if !missing.is_empty() {
        return Err(err(format!(
            "lacks {} of its shard listed in {}: {}",
            crate::util::count(missing.len(), "run"),
            manifest_path.display(),
            some(&missing)
        )));
    }
    Ok(ShardFile {
        path,
        manifest,
        records,
    })
}

/// The records of a merge, `(file, its records)`, checked against the manifest beside each
/// file ([`checked`]) and grouped by study: the shards of one study must agree on its keys and
/// on n, and all of them must be given (the error names the first file of the study and the
/// files of other studies given). Returns the rows of each study in its enumeration order, the
/// studies in the order of their first keys: the same rows whatever the sharding and the order
/// of the files.
pub fn in_study_order(files: Vec<(PathBuf, Vec<RunRecord>)>) -> Result<Vec<RunRecord>> {
    let mut studies: Vec<Vec<ShardFile>> = Vec::new();
    for (path, records) in files {
        let shard = checked(path, records)?;
        match studies
            .iter_mut()
            .find(|s| s[0].manifest.study == shard.manifest.study)
        {
            Some(study) => study.push(shard),
            None => studies.push(vec![shard]),
        }
    }
    for (k, study) in studies.iter().enumerate() {
        let others: Vec<&Path> = studies
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != k)
            .map(|(_, s)| s[0].path.as_path())
            .collect();
        complete(study, &others)?;
    }
    studies.sort_by(|a, b| a[0].manifest.keys.first().cmp(&b[0].manifest.keys.first()));
    let mut out = Vec::new();
    for study in studies {
        let place: HashMap<String, usize> = study[0]
            .manifest
            .keys
            .iter()
            .enumerate()
            .map(|(k, key)| (key.clone(), k))
            .collect();
        let mut rows: Vec<RunRecord> = study.into_iter().flat_map(|s| s.records).collect();
        rows.sort_by_key(|r| place.get(&r.key).copied());
        out.extend(rows);
    }
    Ok(out)
}

/// Refuses the shards of one study that disagree on its keys or on n, or do not cover it;
/// `others` are the first files of the other studies given, named as the likely cause.
fn complete(study: &[ShardFile], others: &[&Path]) -> Result<()> {
    let first = &study[0];
    let (m, n) = (&first.manifest, first.manifest.shards());
    for s in &study[1..] {
        let differs = if s.manifest.keys != m.keys {
            "list other runs".to_string()
        } else if s.manifest.shards() != n {
            format!("cut it into {} shards, not {n}", s.manifest.shards())
        } else {
            continue;
        };
        return Err(Error::invalid(
            "records",
            s.path.display().to_string(),
            &format!(
                "its manifest and that of {} name one study but {differs} (edited by hand?)",
                first.path.display(),
            ),
        ));
    }
    let given: HashSet<usize> = study
        .iter()
        .map(|s| s.manifest.shard.map_or(1, |x| x.0))
        .collect();
    let missing: Vec<usize> = (1..=n).filter(|i| !given.contains(i)).collect();
    if missing.is_empty() {
        return Ok(());
    }
    let runs: Vec<&String> = m
        .keys
        .iter()
        .enumerate()
        .filter(|(k, _)| missing.iter().any(|&i| in_shard(*k, (i, n))))
        .map(|(_, key)| key)
        .collect();
    let shards: Vec<String> = missing
        .iter()
        .take(5)
        .map(|&i| records_name(Some((i, n))))
        .collect();
    let mut why = format!(
        "a shard of a study cut into {n}, given without {}{}: the runs {} are in no file",
        shards.join(", "),
        if missing.len() > 5 { ", …" } else { "" },
        some(&runs)
    );
    if !others.is_empty() {
        let names: Vec<String> = others.iter().map(|p| p.display().to_string()).collect();
        why += &format!(
            "; given beside it: {}, of another study (other case files, case file contents, \
             mesh files or --quick): merge the shards of one study",
            names.join(", ")
        );
    }
    Err(Error::invalid(
        "records",
        first.path.display().to_string(),
        &why,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A manifest reads back as written, beside the records of its name, and a file that is
    /// not one is refused naming its first line.
    #[test]
    fn a_manifest_reads_back_as_written() {
        let dir = tempfile::tempdir().unwrap();
        let records = dir.path().join(records_name(Some((2, 3))));
        let path = path_beside(&records).unwrap();
        assert!(path.ends_with("manifest-2-of-3.txt"), "{}", path.display());
        assert_eq!(
            path_beside(&dir.path().join("records.csv")).unwrap(),
            dir.path().join("manifest.txt")
        );
        assert_eq!(path_beside(&dir.path().join("mine.csv")), None);
        let m = Manifest {
            study: "0123456789abcdef".into(),
            shard: Some((2, 3)),
            keys: vec![
                "a-s-standard-newmark-L0".into(),
                "a-s-lumped-newmark-L0".into(),
            ],
        };
        m.write(&path).unwrap();
        assert_eq!(Manifest::read(&path).unwrap(), m);
        std::fs::write(&path, "key,sweep\n").unwrap();
        let e = Manifest::read(&path).unwrap_err().to_string();
        assert!(e.contains("manifest") && e.contains("line 1"), "{e}");
        // Blank lines appended were read as a key `` listed twice.
        m.write(&path).unwrap();
        let mut text = std::fs::read_to_string(&path).unwrap();
        text.push_str("\n\n");
        std::fs::write(&path, text).unwrap();
        let e = Manifest::read(&path).unwrap_err().to_string();
        assert!(e.contains("empty line"), "{e}");
    }
}
