//! The documentation's form as claims that can fail (README.md and docs/*.md):
//! - no line over 100 characters, tables and code blocks included;
//! - README.md stays a page (at most 150 lines);
//! - every relative link points to a file that exists and, when it names a heading of a Markdown
//!   file (`file.md#heading`), to a heading that exists (GitHub's anchors);
//! - every command in a code block (`cargo run --release -- …` or `dyncontact …`) names a
//!   subcommand that `dyncontact --help` lists, flags that its `--help` lists, and case files
//!   that exist;
//! - every name in the README's method table is one that `dyncontact list` prints.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Longest line, in characters.
const MAX_WIDTH: usize = 100;
/// Longest README, in lines.
const MAX_README_LINES: usize = 150;

/// README.md and every `.md` file of docs/.
fn documents() -> Vec<PathBuf> {
    let mut out = vec![PathBuf::from("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir("docs")
        .expect("docs/ exists")
        .map(|e| e.expect("docs/ is readable").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    out.extend(docs);
    out
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Lines of a Markdown text with their 1-based numbers.
type Lines<'a> = Vec<(usize, &'a str)>;

/// The lines of a Markdown text, split into those outside fenced code blocks (prose, tables,
/// headings) and those inside.
fn split_fences(text: &str) -> (Lines<'_>, Lines<'_>) {
    let mut fence: Option<&str> = None;
    let (mut prose, mut code) = (Vec::new(), Vec::new());
    for (i, line) in text.lines().enumerate() {
        let t = line.trim_start();
        let marker = ["```", "~~~"].into_iter().find(|m| t.starts_with(m));
        match (fence, marker) {
            (None, Some(m)) => fence = Some(m),
            (Some(f), Some(m)) if f == m => fence = None,
            (None, None) => prose.push((i + 1, line)),
            (Some(_), _) => code.push((i + 1, line)),
        }
    }
    (prose, code)
}

fn prose_lines(text: &str) -> Lines<'_> {
    split_fences(text).0
}

/// `line` without its inline code spans.
fn without_code(line: &str) -> String {
    line.split('`').step_by(2).collect::<Vec<_>>().join(" ")
}

/// The targets of the inline links and images `[text](target "title")` and of the reference
/// definitions `[label]: target` in `line`.
fn link_targets(line: &str) -> Vec<String> {
    let line = without_code(line);
    let mut out = Vec::new();
    let mut rest = line.as_str();
    while let Some(i) = rest.find("](") {
        let after = &rest[i + 2..];
        let end = after.find(')').unwrap_or(after.len());
        if let Some(target) = after[..end].split_whitespace().next() {
            out.push(target.trim_matches(|c| c == '<' || c == '>').to_string());
        }
        rest = &after[end..];
    }
    let t = line.trim_start();
    if let (true, Some(i)) = (t.starts_with('['), t.find("]:")) {
        if let Some(target) = t[i + 2..].split_whitespace().next() {
            out.push(target.to_string());
        }
    }
    out
}

/// GitHub's anchor of a heading: lower case, letters, digits, `-` and `_` kept, spaces to `-`,
/// everything else dropped.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .flat_map(char::to_lowercase)
        .collect()
}

/// The anchors of the headings of a Markdown text.
fn anchors(text: &str) -> BTreeSet<String> {
    prose_lines(text)
        .into_iter()
        .filter_map(|(_, l)| {
            let t = l.trim_start();
            let level = t.chars().take_while(|&c| c == '#').count();
            (1..=6)
                .contains(&level)
                .then(|| t[level..].strip_prefix(' '))
                .flatten()
                .map(anchor)
        })
        .collect()
}

/// A command of a code block: the `dyncontact` subcommand and the words after it.
#[derive(Debug, PartialEq)]
struct Invocation {
    at: String,
    words: Vec<String>,
}

/// The `dyncontact` commands of the code blocks of `text`: lines starting (after an optional
/// `$ `) with `cargo run --release --` or `dyncontact`, joined with their `\` continuations,
/// comments dropped.
fn invocations(doc: &str, text: &str) -> Vec<Invocation> {
    let mut out = Vec::new();
    let mut pending: Option<(usize, String)> = None;
    for (n, line) in split_fences(text).1 {
        let line = line.split(" #").next().unwrap_or("").trim();
        let (start, text) = match pending.take() {
            Some((start, before)) => (start, format!("{before} {line}")),
            None => (n, line.trim_start_matches("$ ").to_string()),
        };
        if let Some(joined) = text.strip_suffix('\\') {
            pending = Some((start, joined.to_string()));
            continue;
        }
        let rest = ["cargo run --release -- ", "dyncontact "]
            .into_iter()
            .find_map(|p| text.strip_prefix(p));
        if let Some(rest) = rest {
            out.push(Invocation {
                at: format!("{doc}:{start}"),
                words: rest.split_whitespace().map(String::from).collect(),
            });
        }
    }
    out
}

/// What the binary prints for `args` (its standard output).
fn dyncontact(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_dyncontact"))
        .args(args)
        .output()
        .expect("the dyncontact binary runs");
    assert!(out.status.success(), "dyncontact {args:?} failed");
    String::from_utf8(out.stdout).expect("UTF-8 output")
}

/// The `--flags` a help text names.
fn flags(help: &str) -> BTreeSet<String> {
    help.split(|c: char| !(c.is_alphanumeric() || c == '-' || c == '_'))
        .filter(|w| w.starts_with("--") && w.len() > 2)
        .map(String::from)
        .collect()
}

/// The subcommands `dyncontact --help` lists.
fn subcommands(help: &str) -> BTreeSet<String> {
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .map(String::from)
        .collect()
}

#[test]
fn lines_are_at_most_100_characters() {
    let mut long = Vec::new();
    for doc in documents() {
        for (n, line) in read(&doc).lines().enumerate() {
            let width = line.chars().count();
            if width > MAX_WIDTH {
                long.push(format!("{}:{}: {width} characters", doc.display(), n + 1));
            }
        }
    }
    assert!(
        long.is_empty(),
        "lines over {MAX_WIDTH} characters:\n{}",
        long.join("\n")
    );
}

#[test]
fn the_readme_is_a_page() {
    let lines = read(Path::new("README.md")).lines().count();
    println!("README.md: {lines} lines");
    assert!(
        lines <= MAX_README_LINES,
        "README.md has {lines} lines (at most {MAX_README_LINES}: move the rest to docs/)"
    );
}

#[test]
fn relative_links_resolve() {
    let mut broken = Vec::new();
    for doc in documents() {
        let text = read(&doc);
        let dir = doc.parent().unwrap_or(Path::new(""));
        for (n, line) in prose_lines(&text) {
            for target in link_targets(line) {
                if target.contains("://") || target.starts_with("mailto:") {
                    continue;
                }
                let (file, fragment) = match target.split_once('#') {
                    Some((f, a)) => (f, Some(a)),
                    None => (target.as_str(), None),
                };
                let path = if file.is_empty() {
                    doc.clone()
                } else {
                    dir.join(file)
                };
                let here = format!("{}:{n}: `{target}`", doc.display());
                if !path.exists() {
                    broken.push(format!("{here}: no file {}", path.display()));
                    continue;
                }
                let markdown = path.extension().is_some_and(|e| e == "md");
                if let (Some(a), true) = (fragment, markdown) {
                    if !anchors(&read(&path)).contains(a) {
                        broken.push(format!("{here}: no heading #{a} in {}", path.display()));
                    }
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn documented_commands_exist_in_the_cli() {
    let commands = subcommands(&dyncontact(&["--help"]));
    assert!(commands.contains("report"), "{commands:?}");
    let mut wrong = Vec::new();
    let mut seen = 0;
    for doc in documents() {
        for call in invocations(&doc.display().to_string(), &read(&doc)) {
            seen += 1;
            let sub = call.words.first().map_or("", String::as_str);
            if !commands.contains(sub) {
                wrong.push(format!(
                    "{}: no command `{sub}` in dyncontact --help",
                    call.at
                ));
                continue;
            }
            let known = flags(&dyncontact(&[sub, "--help"]));
            for word in &call.words[1..] {
                let flag = word.split('=').next().unwrap_or("");
                if flag.starts_with("--") && !known.contains(flag) {
                    wrong.push(format!("{}: `{sub} --help` lists no {flag}", call.at));
                }
                if word.starts_with("cases/") && !Path::new(word).exists() {
                    wrong.push(format!("{}: no case file {word}", call.at));
                }
            }
        }
    }
    println!("{seen} documented commands checked");
    assert!(
        seen >= 10,
        "only {seen} commands found in the documentation"
    );
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn the_readme_table_names_what_the_cli_lists() {
    let listed = dyncontact(&["list"]);
    let names: BTreeSet<&str> = listed
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .collect();
    let readme = read(Path::new("README.md"));
    let rows: Vec<&str> = prose_lines(&readme)
        .into_iter()
        .map(|(_, l)| l)
        .filter(|l| {
            ["| space |", "| scheme |", "| contact |", "| case |"]
                .iter()
                .any(|k| l.starts_with(k))
        })
        .collect();
    assert!(
        rows.len() >= 20,
        "the README's method table has {} rows",
        rows.len()
    );
    let mut unknown = Vec::new();
    for row in rows {
        let name_cell = row.split('|').nth(2).unwrap_or("");
        // The names are the code spans of the cell; parameter names are code spans too.
        for name in name_cell.split('`').skip(1).step_by(2) {
            if !names.contains(name) {
                unknown.push(format!("`{name}` in the row {row}"));
            }
        }
    }
    assert!(
        unknown.is_empty(),
        "not in `dyncontact list`:\n{}",
        unknown.join("\n")
    );
}

#[test]
fn the_rules_see_what_they_check() {
    let text = "a [x](docs/a.md#b) `[no](c)` ![p](d.png \"t\")\n```\n| not a row\n```\n| row |";
    let lines = prose_lines(text);
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert_eq!(link_targets(lines[0].1), ["docs/a.md#b", "d.png"]);
    assert_eq!(anchor("Time schemes (`--scheme`)"), "time-schemes---scheme");
    assert_eq!(
        anchor("The seed figures (block2d)"),
        "the-seed-figures-block2d"
    );
    let code = "```sh\n$ dyncontact run a.toml \\\n    --dt 1 # why\ncargo test\n```\n";
    let calls = invocations("x", code);
    assert_eq!(calls.len(), 1, "{calls:?}");
    assert_eq!(calls[0].at, "x:2");
    assert_eq!(calls[0].words, ["run", "a.toml", "--dt", "1"]);
    assert!(flags("  --t-end <T_END>  Final\n  -h, --help").contains("--t-end"));
    let help = "Usage: x\n\nCommands:\n  list  List\n  run   Run\n\nOptions:\n  -h";
    assert_eq!(subcommands(help), ["list", "run"].map(String::from).into());
}
