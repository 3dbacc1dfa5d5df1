//! The `dyncontact` command line.

use clap::{Parser, Subcommand};
use dyncontact::cases::{self, Overrides};
use dyncontact::{output, run, Result};
use std::path::PathBuf;
use std::process::ExitCode;

/// Verification and benchmark suite for elastodynamics with unilateral contact.
#[derive(Parser)]
#[command(name = "dyncontact", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the case files in a directory and the known spaces, schemes and contact solvers.
    List {
        /// Directory of case files.
        #[arg(default_value = "cases")]
        dir: PathBuf,
    },
    /// Run the bar1d convergence study and the spring-mass table; write CSVs, PNGs and index.md.
    Report {
        /// Output directory.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
        /// Directory of the case files (bar1d.toml, spring_mass.toml).
        #[arg(long, default_value = "cases")]
        cases: PathBuf,
    },
    /// Run one case and write timeseries.csv, summary.csv, energy.png and contact.png.
    Run {
        /// Case file (TOML).
        case: PathBuf,
        /// Space discretisation (standard, lumped, mass_redistribution, mass_elimination,
        /// singular_dynamic).
        #[arg(long)]
        space: Option<String>,
        /// Time scheme (newmark).
        #[arg(long)]
        scheme: Option<String>,
        /// Newmark β.
        #[arg(long, allow_negative_numbers = true)]
        beta: Option<f64>,
        /// Newmark γ.
        #[arg(long, allow_negative_numbers = true)]
        gamma: Option<f64>,
        /// Polynomial degree of the displacement (1 or 2).
        #[arg(long)]
        degree: Option<usize>,
        /// Number of elements.
        #[arg(long)]
        elements: Option<usize>,
        /// Time step.
        #[arg(long, allow_negative_numbers = true)]
        dt: Option<f64>,
        /// Final time.
        #[arg(long = "t-end", allow_negative_numbers = true)]
        t_end: Option<f64>,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
}

fn list(dir: &PathBuf) -> Result<()> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| dyncontact::Error::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    entries.sort();
    for p in entries {
        match cases::load(&p, &Overrides::default()) {
            Ok(c) => println!(
                "{}  ({}, space {}, scheme {})",
                p.display(),
                c.kind(),
                c.run().space,
                c.run().scheme
            ),
            Err(e) => println!("{}  (invalid: {e})", p.display()),
        }
    }
    println!("spaces: {}", dyncontact::space::SPACES.join(", "));
    println!("schemes: {}", dyncontact::time::SCHEMES.join(", "));
    println!(
        "contact solvers: {}",
        dyncontact::contact::SOLVERS.join(", ")
    );
    Ok(())
}

fn main_result(cli: Cli) -> Result<()> {
    match cli.command {
        Command::List { dir } => list(&dir),
        Command::Report { out, cases } => {
            dyncontact::report::report(&cases, &out, &mut |msg| eprintln!("running {msg}"))?;
            println!("wrote {}/index.md", out.display());
            Ok(())
        }
        Command::Run {
            case,
            space,
            scheme,
            beta,
            gamma,
            degree,
            elements,
            dt,
            t_end,
            out,
        } => {
            let overrides = Overrides {
                space,
                scheme,
                beta,
                gamma,
                degree,
                elements,
                dt,
                t_end,
            };
            let case = cases::load(&case, &overrides)?;
            let result = run::run(case.as_ref())?;
            output::write_run(&out, &result)?;
            let s = &result.summary;
            let m = &s.metrics;
            println!(
                "{} {} {} ({}): {} dofs, {} steps in {:.3} s; energy drift {:.3e}, max penetration {:.3e}",
                s.case, s.space, s.scheme, s.parameters, s.dofs, s.steps, s.wall_time, m.energy_drift, m.max_penetration
            );
            println!(
                "wrote {}/{{timeseries.csv, summary.csv, energy.png, contact.png}}",
                out.display()
            );
            Ok(())
        }
    }
}

fn main() -> ExitCode {
    match main_result(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
