//! The `dyncontact` command line.

use clap::{Parser, Subcommand};
use dyncontact::cases::{self, Overrides};
use dyncontact::study::manifest::{self, Manifest};
use dyncontact::study::{jobs, journal, orders, records, reference, run};
use dyncontact::{Error, Result};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

/// `println!` that ends the program quietly when stdout is a closed pipe (`dyncontact list |
/// head -1`), as Unix tools do, instead of panicking; another write error is reported (exit 1).
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            if e.kind() != std::io::ErrorKind::BrokenPipe {
                eprintln!("error: writing to stdout: {e}");
                std::process::exit(1);
            }
            std::process::exit(0);
        }
    }};
}

/// Verification and benchmark suite for elastodynamics with unilateral contact.
#[derive(Parser)]
#[command(name = "dyncontact", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// Parsed once per process: the size of the `run` variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// List the case files in a directory and the known spaces, schemes and contact solvers.
    List {
        /// Directory of case files (default: the repository's `cases/`).
        dir: Option<PathBuf>,
    },
    /// Run every [[sweep]] of the case files; write summary.csv, timings.csv, orders.csv, PNGs,
    /// index.md and index.html.
    Report {
        /// Output directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
        /// Directory of the case files (the repository's `cases/`).
        #[arg(long, default_value = "cases")]
        cases: PathBuf,
        /// Only this case (a case file's name without `.toml`, e.g. `bar1d`); repeat the flag
        /// for several.
        #[arg(long = "case", value_name = "NAME")]
        case: Vec<String>,
        /// Only the first `quick_levels` levels of every sweep (under a minute).
        #[arg(long)]
        quick: bool,
        /// Skip the runs already recorded in OUT/journal.csv (same case file content, space,
        /// scheme, parameters and level) and run the others.
        #[arg(long)]
        resume: bool,
        /// Write the wall and CPU time of every run and report section, as each ends, to this
        /// CSV (`study::profile`); with `RAYON_NUM_THREADS=1` the runs do not overlap and each
        /// line's `cpu_s` is that run's own.
        #[arg(long, value_name = "FILE")]
        profile: Option<PathBuf>,
    },
    /// Join record files of `sweep --shard i/n` runs into a report (no time histories).
    Merge {
        /// records-*.csv files.
        #[arg(required = true)]
        records: Vec<PathBuf>,
        /// Output directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
    },
    /// Run the [[sweep]] tables of case files in parallel; write records.csv and orders.csv.
    Sweep {
        /// Case files (TOML) with [[sweep]] tables.
        #[arg(required = true)]
        cases: Vec<PathBuf>,
        /// Output directory.
        #[arg(long, default_value = "reports/sweep")]
        out: PathBuf,
        /// Only the first levels of each sweep (`quick_levels`).
        #[arg(long)]
        quick: bool,
        /// Run only shard i of n (1-based), e.g. `--shard 2/8`; writes records-i-of-n.csv.
        #[arg(long, value_parser = parse_shard)]
        shard: Option<(usize, usize)>,
        /// Skip the runs already recorded in the journal of OUT (journal.csv, or
        /// journal-i-of-n.csv for a shard).
        #[arg(long)]
        resume: bool,
    },
    /// Run one case and write timeseries.csv, summary.csv, energy.png and contact.png.
    Run {
        /// Case file (TOML).
        case: PathBuf,
        /// Space discretisation (`dyncontact list` lists them).
        #[arg(long)]
        space: Option<String>,
        /// Time scheme (`dyncontact list` lists them with their parameters).
        #[arg(long)]
        scheme: Option<String>,
        /// Contact formulation, solvers and the methods' parameters.
        #[command(flatten)]
        options: cases::Options,
        /// Polynomial degree of the displacement (1 or 2).
        #[arg(long)]
        degree: Option<usize>,
        /// Number of elements.
        #[arg(long)]
        elements: Option<usize>,
        /// Cell shape of a generated 2D/3D mesh: quad or triangle (2D), hex or tet (3D).
        #[arg(long)]
        cells: Option<String>,
        /// A Gmsh mesh (MSH 4.1) replacing the case's mesh (2D/3D body cases; Γ_C is the
        /// physical group `contact`, or the case's `[contact] group`; two_discs/two_spheres:
        /// both bodies, groups `body1`, `body2`, `contact1`, `contact2`, body 1 the slave).
        #[arg(long)]
        mesh: Option<PathBuf>,
        /// Time step.
        #[arg(long, allow_negative_numbers = true)]
        dt: Option<f64>,
        /// Final time.
        #[arg(long = "t-end", allow_negative_numbers = true)]
        t_end: Option<f64>,
        /// Coulomb friction coefficient μ at the plane or between two bodies (2D/3D body cases
        /// and pairs; 0: frictionless), replacing the case's `[contact] friction`.
        #[arg(long, allow_negative_numbers = true)]
        friction: Option<f64>,
        /// Incidence θ in degrees from the normal of a body case's initial velocity, its speed
        /// kept (`velocity = −V cos θ`, `tangential_velocity = V sin θ`; the oblique impact).
        #[arg(long, allow_negative_numbers = true)]
        incidence: Option<f64>,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Write the fields (displacement, velocity, von Mises stress, contact pressure) for
        /// ParaView into DIR: `<case>_<sample>.vtu` files and their `<case>.pvd` collection
        /// (2D/3D body cases; two_discs/two_spheres: both bodies in one grid, cell array `body`);
        /// an earlier run's `<case>_<sample>.vtu` files there that the new collection does not
        /// list are removed.
        #[arg(long, value_name = "DIR")]
        vtu: Option<PathBuf>,
        /// With --vtu, write every K-th sample (the initial state included).
        #[arg(long = "vtu-every", value_name = "K", default_value_t = 1, requires = "vtu",
              value_parser = clap::value_parser!(u64).range(1..))]
        vtu_every: u64,
    },
}

/// The case files of `dir` (default `cases`) and the registries. Where the default cannot be
/// read (outside the repository), the registries and, on stderr, where the case files are
/// expected and how to point at them; a `dir` given that is no directory is an error.
fn list(given: Option<&Path>) -> Result<()> {
    let dir = given.unwrap_or(Path::new("cases"));
    let entries = match given {
        Some(d) if d.exists() && !d.is_dir() => {
            return Err(Error::invalid(
                "list DIR",
                d.display().to_string(),
                "is a file, not a directory of case files (`dyncontact run FILE` runs one)",
            ))
        }
        Some(d) => cases::case_paths(d)?,
        None => cases::case_paths(dir).unwrap_or_else(|e| {
            eprintln!("{e}");
            Vec::new()
        }),
    };
    if entries.is_empty() && dir.is_dir() {
        eprintln!("no case files (*.toml) in {}", dir.display());
    }
    for p in entries {
        match cases::load(&p, &Overrides::default()) {
            Ok(c) => say!(
                "{}  ({}, space {}, scheme {})",
                p.display(),
                c.kind(),
                c.run().space,
                c.run().scheme
            ),
            Err(e) => say!("{}  (invalid: {e})", p.display()),
        }
    }
    say!("spaces: {}", dyncontact::space::names().join(", "));
    print_registry("schemes", dyncontact::time::SCHEMES);
    print_registry("contact formulations", dyncontact::contact::FORMULATIONS);
    say!(
        "weak multiplier spaces (--contact-multiplier): {} (default {})",
        dyncontact::contact::weak::MULTIPLIERS.join(", "),
        dyncontact::contact::weak::MULTIPLIERS[0]
    );
    say!(
        "contact solvers: {}",
        dyncontact::contact::SOLVERS.join(", ")
    );
    say!(
        "linear solvers: {}",
        dyncontact::time::LINEAR_SOLVERS.join(", ")
    );
    Ok(())
}

/// `kind: a (p=default;…), b, …` of a method registry (parameters spelt as in the records).
fn print_registry<T: ?Sized, I>(kind: &str, registry: &[dyncontact::param::Entry<T, I>]) {
    let entries: Vec<String> = registry
        .iter()
        .map(|e| run::method_label(e.name, &e.describe(&Default::default())))
        .collect();
    say!("{kind}: {}", entries.join(", "));
}

fn parse_shard(s: &str) -> std::result::Result<(usize, usize), String> {
    let (i, n) = s.split_once('/').ok_or("expected i/n, e.g. 2/8")?;
    let parse = |x: &str| x.trim().parse::<usize>().map_err(|e| format!("{x:?}: {e}"));
    Ok((parse(i)?, parse(n)?))
}

fn sweep(
    cases: &[PathBuf],
    out: &Path,
    quick: bool,
    shard: Option<(usize, usize)>,
    resume: bool,
) -> Result<()> {
    let files: Vec<Arc<cases::CaseFile>> = cases
        .iter()
        .map(|c| cases::CaseFile::read(c).map(Arc::new))
        .collect::<Result<_>>()?;
    jobs::distinct_cases(&files)?;
    let mut all = Vec::new();
    for f in &files {
        let runs = jobs::jobs(f, quick)?;
        if runs.is_empty() {
            return Err(dyncontact::Error::invalid(
                "sweep",
                f.path.display().to_string(),
                "the case file has no [[sweep]] table",
            ));
        }
        all.extend(runs);
    }
    jobs::distinct_keys(&all)?;
    let study = Manifest::new(&files, quick, &all, shard)?;
    if let Some(s) = shard {
        all = jobs::shard(all, s)?;
    }
    let journal = shard.map_or("journal.csv".to_string(), |(i, n)| {
        format!("journal-{i}-of-{n}.csv")
    });
    let records_path = out.join(manifest::records_name(shard));
    let manifest_path = manifest::path_beside(&records_path)
        .ok_or_else(|| Error::Internal("a records file named without `records`".into()))?;
    let mut outputs = journal::outputs(out, &journal, &all);
    outputs.extend(
        [&records_path, &manifest_path, &out.join("orders.csv")].map(|p| ("--out", p.clone())),
    );
    let inputs: Vec<_> = files
        .iter()
        .flat_map(|f| f.inputs(&Overrides::default()))
        .collect();
    dyncontact::input::refuse_overwrite(&inputs, &outputs)?;
    dyncontact::util::output_dir(out, "--out")?;
    eprintln!("running {}", dyncontact::util::count(all.len(), "run"));
    let _lock = dyncontact::study::lock::Lock::acquire(out, &journal)?;
    let mut records = journal::run_study(&all, out, &journal, resume, true)?;
    if shard.is_none() {
        reference::reference_errors(&mut records);
    }
    journal::rewrite(out, &journal, &all, &records)?;
    records::write_records(&records_path, &records, true)?;
    study.write(&manifest_path)?;
    let failed = records
        .iter()
        .filter(|r| r.status != jobs::Status::Ok)
        .count();
    say!(
        "wrote {} ({}, {failed} not ok)",
        records_path.display(),
        dyncontact::util::count(records.len(), "run")
    );
    if shard.is_none() {
        let orders = orders::orders(&records);
        orders::write_orders(&out.join("orders.csv"), &orders)?;
        say!("wrote {}", out.join("orders.csv").display());
    }
    Ok(())
}

/// The files `run` writes: [`run::RUN_FILES`] and the lock in `out`, and with `--vtu` the
/// collection `<case>.pvd` and the inputs that its `<case>_<sample>.vtu` files would replace
/// or remove (an earlier run's samples that the new collection does not list).
fn run_outputs(
    out: &Path,
    vtu: Option<&Path>,
    case: &str,
    inputs: &[dyncontact::input::Named],
) -> Vec<dyncontact::input::Named> {
    let mut outputs: Vec<dyncontact::input::Named> = run::RUN_FILES
        .iter()
        .chain(["journal.csv.lock"].iter())
        .map(|f| ("--out", out.join(f)))
        .collect();
    if let Some(dir) = vtu {
        outputs.push(("--vtu", dir.join(format!("{case}.pvd"))));
        // The series' files a run writes, and removes when its collection does not list them.
        outputs.extend(inputs.iter().filter_map(|(_, p)| {
            let name = p.file_name()?.to_str()?;
            dyncontact::output::vtu::series_index(case, name).map(|_| ("--vtu", dir.join(name)))
        }));
    }
    outputs
}

fn main_result(cli: Cli) -> Result<()> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    dyncontact::util::check_threads(
        |name| std::env::var_os(name).map(|t| t.to_string_lossy().into_owned()),
        cores,
    )?;
    match cli.command {
        Command::List { dir } => list(dir.as_deref()),
        Command::Sweep {
            cases,
            out,
            quick,
            shard,
            resume,
        } => sweep(&cases, &out, quick, shard, resume),
        Command::Report {
            out,
            cases,
            case,
            quick,
            resume,
            profile,
        } => {
            if let Some(p) = &profile {
                dyncontact::study::profile::start(p, &out)?;
            }
            let opts = dyncontact::report::Options {
                quick,
                progress: true,
                resume,
                cases: case,
            };
            let records = dyncontact::report::report(&cases, &out, &opts)?;
            say!(
                "{}; wrote {}/index.md and index.html",
                dyncontact::util::count(records.len(), "run"),
                shown(&out)
            );
            Ok(())
        }
        Command::Merge { records, out } => {
            let records = dyncontact::report::merge(&records, &out)?;
            say!(
                "{} merged; wrote {}/index.md and index.html",
                dyncontact::util::count(records.len(), "run"),
                shown(&out)
            );
            Ok(())
        }
        Command::Run {
            case,
            space,
            scheme,
            options,
            degree,
            elements,
            cells,
            mesh,
            dt,
            t_end,
            friction,
            incidence,
            out,
            vtu,
            vtu_every,
        } => {
            let overrides = Overrides {
                space,
                scheme,
                options,
                degree,
                elements,
                cells,
                mesh,
                dt,
                t_end,
                friction,
                incidence,
                origin: None,
            };
            let path = case;
            let file = cases::CaseFile::read(&path).map_err(|e| e.in_case_file(&path))?;
            let case = file.build(&overrides).map_err(|e| e.in_case_file(&path))?;
            case.run().refuse_unused_flags(&overrides.options)?;
            let inputs = file.inputs(&overrides);
            let outputs = run_outputs(&out, vtu.as_deref(), case.kind(), &inputs);
            dyncontact::input::refuse_overwrite(&inputs, &outputs)?;
            dyncontact::util::output_dir(&out, "--out")?;
            // Two runs (or a run and a study) into one directory would mix their files.
            let _lock = dyncontact::study::lock::Lock::acquire(&out, "journal.csv")?;
            if let Some(dir) = &vtu {
                dyncontact::util::output_dir(dir, "--vtu")?;
            }
            let fields = vtu.map(|dir| run::FieldOutput {
                dir,
                every: vtu_every as usize,
            });
            let result = run::run_with_output(
                case.as_ref(),
                std::io::stdout().is_terminal(),
                fields.as_ref(),
            )
            .map_err(|e| overrides.named(e).from_case_input(&path))?;
            run::write_run(&out, &result)?;
            let s = &result.summary;
            let m = &s.metrics;
            say!(
                "{} {} {}: {} dofs, {} steps in {:.3} s; energy drift {}; max penetration {:.3e}",
                s.case,
                s.space,
                s.method(),
                s.dofs,
                s.steps,
                s.wall_time,
                m.drift(),
                m.max_penetration
            );
            say!(
                "wrote {}/{{timeseries.csv, summary.csv, energy.png, contact.png}} (and the PNGs as SVG)",
                shown(&out)
            );
            if let Some(f) = &fields {
                say!("wrote {}", f.dir.join(format!("{}.pvd", s.case)).display());
            }
            if case.impact().is_some() && result.rows.iter().all(|r| r.force_contact == 0.0) {
                say!("note: no contact force in this run: the Hertz errors are empty");
            }
            // Finite but blown up: written (the curves show it), and refused as a study does.
            match jobs::blowup(&result) {
                Some((step, time, reason)) => Err(Error::Diverged {
                    step,
                    time,
                    reason: format!(
                        "{reason}; a study records this run as diverged, and the files above \
                         show it"
                    ),
                }
                .from_case_input(&path)),
                None => Ok(()),
            }
        }
    }
}

/// SIGTERM is taken on a thread of its own: blocked in every thread (set before any other thread
/// starts, so that all inherit it) and awaited by one, which ends the process by SIGTERM's
/// default action. METIS (`linalg::ordering`) replaces the SIGTERM handler while it orders a
/// matrix, with one that would jump into its own stack from whichever thread the signal reached;
/// a blocked signal never runs a handler, so a kill during an ordering ends the run as any other.
#[cfg(unix)]
fn take_sigterm_on_its_own_thread() {
    use nix::sys::signal::{raise, sigaction, SaFlags, SigAction, SigHandler, SigSet, Signal};
    let mut term = SigSet::empty();
    term.add(Signal::SIGTERM);
    if term.thread_block().is_err() {
        return;
    }
    std::thread::spawn(move || {
        if term.wait().is_ok() {
            let default = SigAction::new(SigHandler::SigDfl, SaFlags::empty(), SigSet::empty());
            // SAFETY: restoring the default action installs no handler code.
            let _ = unsafe { sigaction(Signal::SIGTERM, &default) };
            let _ = term.thread_unblock();
            let _ = raise(Signal::SIGTERM);
        }
    });
}

fn main() -> ExitCode {
    #[cfg(unix)]
    take_sigterm_on_its_own_thread();
    match main_result(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// A directory as the user gave it, without a trailing separator (`sweep/` → `sweep`), to
/// name the files written into it.
fn shown(dir: &Path) -> String {
    dir.components().as_path().display().to_string()
}
