//! The report end to end on the quick sweeps: deterministic CSVs (also after a kill and
//! `--resume`), every figure listed in the index, and `sweep --shard` + `merge` giving the same
//! orders as one sweep.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

fn dyncontact(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_dyncontact"))
        .args(args)
        .output()
        .expect("binary runs");
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stderr).to_string()
}

/// Starts `report --quick` into `out` on one thread and kills it (SIGKILL) once its journal
/// holds more than `runs` records; returns how many it held. Panics if the report ends first.
fn killed_report(out: &Path, runs: usize) -> usize {
    let mut child = Command::new(env!("CARGO_BIN_EXE_dyncontact"))
        .args(["report", "--quick", "--out", out.to_str().unwrap()])
        .env("RAYON_NUM_THREADS", "1")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("binary starts");
    let journal = out.join("journal.csv");
    loop {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the report ended before it could be killed"
        );
        let recorded =
            std::fs::read_to_string(&journal).map_or(0, |t| t.lines().count().max(1) - 1);
        if recorded > runs {
            child.kill().unwrap();
            child.wait().unwrap();
            return recorded;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// One report uninterrupted, one killed after some runs and resumed: the same bytes.
#[test]
fn quick_report_is_deterministic_resumable_and_indexed() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    dyncontact(&["report", "--quick", "--out", a.to_str().unwrap()]);
    let recorded = killed_report(&b, 10);
    let total = read(&a.join("summary.csv")).lines().count() - 1;
    assert!(recorded < total, "killed after {recorded} of {total} runs");
    let log = dyncontact(&[
        "report",
        "--quick",
        "--resume",
        "--out",
        b.to_str().unwrap(),
    ]);
    assert!(
        log.contains(&format!(
            "resuming: {recorded} of {total} runs already recorded"
        )),
        "{log}"
    );
    for csv in ["summary.csv", "orders.csv"] {
        assert_eq!(read(&a.join(csv)), read(&b.join(csv)), "{csv} differs");
    }
    let index = read(&a.join("index.md"));
    let html = read(&a.join("index.html"));
    let pngs: Vec<String> = std::fs::read_dir(&a)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .filter(|n| n.ends_with(".png"))
        .collect();
    for must in [
        "bar1d_energy.png",
        "bar1d_contact_stress.png",
        "spring_mass_energy.png",
        "bar1d_orders_err_u_linf_l2_spaces.png",
        "bar1d_orders_err_energy_schemes.png",
        "bar1d_orders_err_sigma_l2_spaces.png",
    ] {
        assert!(pngs.iter().any(|p| p == must), "{must} missing: {pngs:?}");
    }
    for p in &pngs {
        assert!(index.contains(&format!("]({p})")), "{p} not in index.md");
        assert!(
            html.contains(&format!("<img src=\"{p}\"")),
            "{p} not in index.html"
        );
    }
    for table in ["summary.csv", "timings.csv", "orders.csv"] {
        assert!(index.contains(table), "{table} not described in index.md");
    }
    check_csvs(&a);
    let findings = index.find("\n## Findings").expect("a Findings section");
    let first_case = index.find("\n## bar1d").expect("a bar1d section");
    assert!(findings < first_case, "Findings come first");
    assert!(index[findings..first_case].contains("mass_redistribution"));
    // The two-body invariants: a row per case × space × scheme of each two-body case, the pairs'
    // force figures linked.
    let two = &index[index.find("\n## Two bodies").expect("a Two bodies section")..];
    let two = &two[..two[1..].find("\n## ").map_or(two.len(), |e| e + 1)];
    for case in ["two_bars", "two_discs", "two_spheres"] {
        assert!(
            two.contains(&format!("| {case} | mass_redistribution |")),
            "{case}"
        );
    }
    assert!(two.contains("](two_spheres_force.png)"));
    check_page(&a);
}

/// A CSV file as a header and rows (no quoted commas in the columns compared).
fn table(p: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv_rows(&read(p));
    let header = r.remove(0);
    (header, r)
}

fn csv_rows(text: &str) -> Vec<Vec<String>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(text.as_bytes());
    reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect()
}

/// summary.csv names each run (`key`, its probe file), its degree, cells and contact; the
/// journal holds the same values in every column they share; the peak memory is filled; no CSV
/// writes a missing value as anything but an empty field.
fn check_csvs(dir: &Path) {
    let (sh, summary) = table(&dir.join("summary.csv"));
    let (jh, journal) = table(&dir.join("journal.csv"));
    for c in ["key", "degree", "cells", "contact"] {
        assert!(sh.iter().any(|h| h == c), "summary.csv has no `{c}`");
    }
    assert_eq!(summary.len(), journal.len());
    for (s, j) in summary.iter().zip(&journal) {
        for (k, name) in sh.iter().enumerate() {
            let at = jh
                .iter()
                .position(|h| h == name)
                .expect("journal has the column");
            assert_eq!(s[k], j[at], "{}: `{name}` differs in journal.csv", s[0]);
        }
    }
    let col = |h: &[String], name: &str| h.iter().position(|x| x == name).unwrap();
    let (key, cells) = (col(&sh, "key"), col(&sh, "cells"));
    let block = summary
        .iter()
        .find(|r| r[key].starts_with("block2d-"))
        .expect("a block run");
    assert!(dir.join(format!("probes/{}.csv", block[key])).exists());
    assert_eq!(block[cells], "quad");
    let (th, timings) = table(&dir.join("timings.csv"));
    let rss = col(&th, "max_rss_mb");
    assert!(timings
        .iter()
        .all(|r| r[rss].parse::<f64>().is_ok_and(|m| m > 0.0)));
    for f in std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()) {
        let name = f.file_name().to_string_lossy().to_string();
        if name.ends_with(".csv") {
            for row in csv_rows(&read(&f.path())) {
                assert!(
                    !row.iter()
                        .any(|v| ["NaN", "-", "–", "nan"].contains(&v.as_str())),
                    "{name}: a missing value written as NaN or a dash: {row:?}"
                );
            }
        }
    }
}

/// The values of every `name="…"` attribute of `html`.
fn attributes<'a>(html: &'a str, name: &str) -> Vec<&'a str> {
    let key = format!(" {name}=\"");
    html.match_indices(&key)
        .map(|(k, _)| {
            let rest = &html[k + key.len()..];
            &rest[..rest.find('"').expect("closed attribute")]
        })
        .collect()
}

/// The text of `html` outside tags.
fn text_content(html: &str) -> String {
    let mut out = String::new();
    let mut in_tag = false;
    for c in html.chars() {
        match c {
            '<' => in_tag = true,
            '>' => in_tag = false,
            _ if !in_tag => out.push(c),
            _ => {}
        }
    }
    out
}

/// The rendered page of a report directory: no unrendered Markdown in the text, every link and
/// image inside the directory and present (with its SVG), every `#anchor` an id of the page,
/// the same links in `index.md`.
fn check_page(dir: &Path) {
    let html = read(&dir.join("index.html"));
    let style_end = html.find("</style>").expect("a style element") + "</style>".len();
    let text = text_content(&html[style_end..]);
    for mark in ["`", "**", "](", "![", "\\_", "\\*", "_{"] {
        let at = text
            .find(mark)
            .map(|k| &text[k.saturating_sub(80)..(k + 80).min(text.len())]);
        assert!(
            at.is_none(),
            "unrendered markup {mark:?} in index.html: …{}…",
            at.unwrap()
        );
    }
    let ids: BTreeSet<&str> = attributes(&html, "id").into_iter().collect();
    let mut targets: Vec<&str> = attributes(&html, "href");
    let images = attributes(&html, "src");
    targets.extend(&images);
    assert!(targets.len() > 20, "{} links", targets.len());
    for t in &targets {
        if let Some(id) = t.strip_prefix('#') {
            assert!(ids.contains(id), "link to #{id}: no such id");
            continue;
        }
        assert!(
            !t.contains("://") && !t.starts_with('/') && !t.contains(".."),
            "{t}: points outside the report directory"
        );
        assert!(dir.join(t).exists(), "{t}: linked from index.html, missing");
    }
    for img in images {
        let svg = img.replace(".png", ".svg");
        assert!(dir.join(&svg).exists(), "{svg} missing beside {img}");
        let alt = html[html.find(img).unwrap()..]
            .split("alt=\"")
            .nth(1)
            .unwrap();
        assert!(
            !alt.starts_with(img),
            "{img}: its alt text is its file name"
        );
    }
    for csv in std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()) {
        let name = csv.file_name().to_string_lossy().to_string();
        if name.ends_with(".csv") {
            assert!(targets.contains(&name.as_str()), "{name} not linked");
        }
    }
    let md = read(&dir.join("index.md"));
    for (k, _) in md.match_indices("](") {
        let target = &md[k + 2..k + 2 + md[k + 2..].find(')').unwrap()];
        let ok = match target.strip_prefix('#') {
            Some(id) => ids.contains(id),
            None => dir.join(target).exists(),
        };
        assert!(ok, "index.md links to {target}, missing");
    }
}

#[test]
fn shards_merge_into_the_orders_of_one_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let one = d.join("one");
    let case = "cases/spring_mass.toml";
    dyncontact(&["sweep", case, "--quick", "--out", one.to_str().unwrap()]);
    let shards = d.join("shards");
    for s in ["1/3", "2/3", "3/3"] {
        dyncontact(&[
            "sweep",
            case,
            "--quick",
            "--shard",
            s,
            "--out",
            shards.to_str().unwrap(),
        ]);
    }
    let files: Vec<String> = (1..=3)
        .map(|i| {
            shards
                .join(format!("records-{i}-of-3.csv"))
                .to_string_lossy()
                .to_string()
        })
        .collect();
    let merged = d.join("merged");
    let mut args = vec!["merge", "--out", merged.to_str().unwrap()];
    args.extend(files.iter().map(String::as_str));
    dyncontact(&args);
    let lines = |p: &Path| read(p).lines().map(String::from).collect::<BTreeSet<_>>();
    assert_eq!(
        lines(&one.join("orders.csv")),
        lines(&merged.join("orders.csv"))
    );
    let index = read(&merged.join("index.md"));
    assert!(
        index.contains("## spring_mass") && index.contains("Observed orders, sweep `orders`"),
        "{index}"
    );
}

/// The "Friction" section of slide2d's quick report: one row per space × scheme of its
/// `friction` sweep (the refused schemes as `unsupported`), each finished run beside its
/// frictionless twin, the conclusions computed from them, and the velocity figure linked.
#[test]
fn the_friction_section_has_its_rows_conclusions_and_figure() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path();
    dyncontact(&[
        "report",
        "--quick",
        "--case",
        "slide2d",
        "--out",
        out.to_str().unwrap(),
    ]);
    let index = read(&out.join("index.md"));
    let start = index.find("\n## Friction").expect("a Friction section");
    let end = index[start + 1..]
        .find("\n## ")
        .map_or(index.len(), |k| start + 1 + k);
    let section = &index[start..end];
    let spaces = [
        "standard",
        "lumped",
        "mass_redistribution",
        "mass_elimination",
        "singular_dynamic",
    ];
    for space in spaces {
        for scheme in ["backward_euler", "newmark", "hht", "moreau_jean"] {
            // Moreau–Jean at θ = ½ needs inertia at the contact dofs.
            if scheme == "moreau_jean" && !["standard", "lumped"].contains(&space) {
                let row = format!("| {space} | {scheme}");
                let refused = |l: &str| l.starts_with(&row) && l.ends_with("| unsupported |");
                assert!(section.lines().any(refused), "{row}:\n{section}");
                continue;
            }
            let row = section
                .lines()
                .find(|l| l.starts_with(&format!("| {space} | {scheme}")))
                .unwrap_or_else(|| panic!("no row {space} {scheme}:\n{section}"));
            // Every cell filled (stop time and deceleration aside: a run may not stop), the
            // iterations and times beside the frictionless run's.
            let cells: Vec<&str> = row.trim_matches(['|', ' ']).split(" | ").collect();
            assert_eq!(cells.len(), 11, "{row}");
            assert_eq!(cells[10], "ok", "{row}");
            assert!(cells[8].ends_with(')') && cells[9].ends_with(')'), "{row}");
            for k in [2, 5, 6, 7] {
                assert!(!cells[k].is_empty(), "{row}");
            }
        }
        for refused in ["central_difference", "paoli_schatzman"] {
            let row = format!("| {space} | {refused}");
            assert!(
                section
                    .lines()
                    .any(|l| l.starts_with(&row) && l.ends_with("| unsupported |")),
                "{row} not refused:\n{section}"
            );
        }
    }
    for conclusion in [
        "No scheme makes `E + W_f = E(0)` exact",
        "Friction never gives energy back",
        "Mass elimination decelerates at about 4/3 μg",
    ] {
        assert!(section.contains(conclusion), "{conclusion}:\n{section}");
    }
    let png = "friction_slide2d_friction_com_velocity.png";
    assert!(section.contains(&format!("]({png})")), "{png} not linked");
    assert!(out.join(png).exists(), "{png} not written");
}
