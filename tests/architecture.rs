//! The architecture as a claim that can fail (docs/architecture.md): no import cycle in `src/`,
//! between top-level modules or between files (a `mod.rs` aside, which declares its children),
//! reading the `crate::` and `super::` paths of the non-test code, as
//! `../shared/tools/cycles.py src` does.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a file: `src/a/b.rs` and `src/a/b/mod.rs` are `[a, b]`.
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    if parts == ["lib"] || parts == ["main"] {
        parts.clear();
    }
    parts
}

/// The code of a file before its test module, without line comments.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The `crate::a::b…` and `super::a…` paths of `code`, as (root, segments).
fn paths(code: &str) -> Vec<(&str, Vec<&str>)> {
    let mut out = Vec::new();
    for root in ["crate", "super"] {
        let pattern = format!("{root}::");
        let mut rest = code;
        while let Some(i) = rest.find(&pattern) {
            let before = rest[..i].chars().last();
            let after = &rest[i + pattern.len()..];
            if !before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                let segments: Vec<&str> = after
                    .split("::")
                    .map(|s| {
                        let end = s
                            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                            .unwrap_or(s.len());
                        &s[..end]
                    })
                    .take_while(|s| !s.is_empty())
                    .collect();
                out.push((root, segments));
            }
            rest = after;
        }
    }
    out
}

/// Strongly connected components with more than one node (Tarjan).
fn cycles(edges: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'a> {
        edges: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        for w in s.edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w.as_str()) {
                visit(s, w);
                let lw = s.low[w.as_str()];
                s.low.entry(v).and_modify(|l| *l = (*l).min(lw));
            } else if s.stack.contains(&w.as_str()) {
                let iw = s.index[w.as_str()];
                s.low.entry(v).and_modify(|l| *l = (*l).min(iw));
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = s.stack.pop() {
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        out: Vec::new(),
    };
    for v in edges.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.out
}

#[test]
fn no_import_cycle_between_modules_or_files() {
    let src = Path::new("src");
    let mut files = Vec::new();
    sources(src, &mut files);
    let by_path: BTreeMap<Vec<String>, &PathBuf> =
        files.iter().map(|f| (module_path(src, f), f)).collect();
    let resolve = |parts: &[String]| {
        (1..=parts.len())
            .rev()
            .find_map(|k| by_path.get(&parts[..k]).copied())
    };
    let name = |f: &Path| f.to_string_lossy().into_owned();
    let top = |f: &Path| {
        module_path(src, f)
            .first()
            .cloned()
            .unwrap_or_else(|| "<root>".into())
    };
    let (mut file_edges, mut module_edges) = (BTreeMap::new(), BTreeMap::new());
    for f in &files {
        let me = module_path(src, f);
        let text = std::fs::read_to_string(f).unwrap();
        for (root, segments) in paths(&code(&text)) {
            let mut target: Vec<String> = if root == "crate" {
                Vec::new()
            } else {
                me[..me.len().saturating_sub(1)].to_vec()
            };
            target.extend(segments.iter().map(|s| s.to_string()));
            let Some(to) = resolve(&target) else { continue };
            if to == f {
                continue;
            }
            let is_mod = |p: &Path| p.file_name().is_some_and(|n| n == "mod.rs");
            if !is_mod(f) && !is_mod(to) {
                file_edges
                    .entry(name(f))
                    .or_insert_with(BTreeSet::new)
                    .insert(name(to));
            }
            let (a, b) = (top(f), top(to));
            if a != b && a != "<root>" {
                module_edges
                    .entry(a)
                    .or_insert_with(BTreeSet::new)
                    .insert(b);
            }
        }
    }
    let (modules, files) = (cycles(&module_edges), cycles(&file_edges));
    assert!(
        modules.is_empty() && files.is_empty(),
        "import cycles: modules {modules:?}, files {files:?}"
    );
    // The layers are seen at all: the method families import the generic declarations.
    assert!(module_edges["time"].contains("param"));
    assert!(!module_edges["param"].contains("time"));
}
