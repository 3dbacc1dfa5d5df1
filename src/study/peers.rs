//! Cross-code check against GetFEM (`golden/peers/README.md`): trajectories GetFEM computes on
//! the discretisations of dyncontact's cases — same mesh, consistent mass, Newmark ½, ½, a contact
//! brick — checked in as CSV (`t, u_contact, sigma_contact, energy`), and dyncontact's run with the
//! same settings, compared sample by sample.
//!
//! Agreement is measured relative to the scale of each peer series:
//! `max_t |x − x_peer| / max_t |x_peer|` for the probe displacement and contact stress, and
//! `max_t |E − E_peer| / E_peer(0)` for the energy.

use crate::cases::{self, Overrides};
use crate::error::{Error, Result};
use crate::study::run::run;
use crate::study::trajectory::Row;
use std::path::Path;

/// Relative difference below which two trajectories are taken as the same (the horizon).
pub const SYNC: f64 = 1e-6;

/// One GetFEM reference run and the dyncontact settings that reproduce its discretisation.
#[derive(Debug, Clone, PartialEq)]
pub struct PeerRun {
    /// CSV file under the peers directory.
    pub file: String,
    /// Case file under the cases directory.
    pub case: &'static str,
    /// GetFEM contact brick: `integral` (P1 multiplier) or `nodal`.
    pub brick: &'static str,
    /// dyncontact's contact formulation for that brick (`weak` P1 or `nodal`).
    pub contact: &'static str,
    /// Cell shape of the generated mesh (2D cases).
    pub cells: Option<&'static str>,
    /// Elements (per direction).
    pub elements: usize,
    /// Time step.
    pub dt: f64,
    /// Final time.
    pub t_end: f64,
}

/// The runs of `golden/peers/generate.py`:
/// - bar1d, P1, 20/40/80/160 elements, dt = h/2, T = 3, integral brick (the end point);
/// - block2d, Q1 and P1 triangles 10 × 10, dt = 10⁻³ and 10⁻⁴, T = 2, nodal and integral bricks.
pub fn getfem_runs() -> Vec<PeerRun> {
    let mut runs: Vec<PeerRun> = [20, 40, 80, 160]
        .into_iter()
        .map(|n| PeerRun {
            file: format!("bar1d_p1_n{n}_integral.csv"),
            case: "bar1d.toml",
            brick: "integral",
            contact: "weak",
            cells: None,
            elements: n,
            dt: 0.5 / n as f64,
            t_end: 3.0,
        })
        .collect();
    for (cells, shape) in [("q1", "quad"), ("p1", "triangle")] {
        for (dt, tag) in [(1e-3, "1e-03"), (1e-4, "1e-04")] {
            for (brick, contact) in [("nodal", "nodal"), ("integral", "weak")] {
                runs.push(PeerRun {
                    file: format!("block2d_{cells}_dt{tag}_{brick}.csv"),
                    case: "block2d.toml",
                    brick,
                    contact,
                    cells: Some(shape),
                    elements: 10,
                    dt,
                    t_end: 2.0,
                });
            }
        }
    }
    runs
}

/// One sample of a peer trajectory.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
pub struct PeerRow {
    /// Time.
    pub t: f64,
    /// Normal displacement of the probe.
    pub u_contact: f64,
    /// Normal contact stress at the probe (compression negative).
    pub sigma_contact: f64,
    /// `½ V·M V + ½ U·K U`.
    pub energy: f64,
}

/// Reads a peer CSV.
pub fn read_peer(path: &Path) -> Result<Vec<PeerRow>> {
    let kind = crate::input::TABLE.named("peer trajectory");
    let err = |m: String| kind.error(path, m);
    let text = kind.read(path)?;
    let mut reader = csv::Reader::from_reader(text.as_slice());
    let rows = reader
        .deserialize()
        .collect::<std::result::Result<Vec<PeerRow>, _>>()
        .map_err(|e| err(e.to_string()))?;
    if rows.is_empty() {
        return Err(err("no samples".into()));
    }
    Ok(rows)
}

/// How far dyncontact is from a peer run.
#[derive(Debug, Clone, PartialEq)]
pub struct Agreement {
    /// The peer run.
    pub run: PeerRun,
    /// Samples compared.
    pub samples: usize,
    /// The first sample time at which a relative difference exceeds [`SYNC`] (the final time
    /// if none does).
    pub horizon: f64,
    /// `max |Δu| / max |u_peer|`.
    pub u: f64,
    /// `max |Δσ| / max |σ_peer|`.
    pub sigma: f64,
    /// `max |ΔE| / E_peer(0)`.
    pub energy: f64,
    /// `max_t E / E(0)` of the peer and of dyncontact (energy growth, seed figure 3).
    pub energy_growth: (f64, f64),
    /// `max_t |σ|` of the peer and of dyncontact (stress peaks).
    pub sigma_peak: (f64, f64),
}

/// Runs dyncontact on the discretisation of `peer` (standard mass, Newmark ½, ½) and compares
/// it with the peer CSV in `peers_dir`.
pub fn compare(peer: &PeerRun, peers_dir: &Path, cases_dir: &Path) -> Result<Agreement> {
    let reference = read_peer(&peers_dir.join(&peer.file))?;
    let mut o = Overrides {
        space: Some(crate::space::standard::ENTRY.name.into()),
        scheme: Some("newmark".into()),
        elements: Some(peer.elements),
        cells: peer.cells.map(Into::into),
        dt: Some(peer.dt),
        t_end: Some(peer.t_end),
        ..Default::default()
    }
    .with("beta", 0.5)
    .with("gamma", 0.5);
    o.options.contact = Some(peer.contact.into());
    let ours = run(cases::load(&cases_dir.join(peer.case), &o)?.as_ref())?.rows;
    let pairs = pair_samples(peer, &reference, &ours)?;
    let max = |f: &dyn Fn(&Pair) -> f64| pairs.iter().map(f).fold(0.0, f64::max);
    let scale = |x: f64| if x > 0.0 { x } else { 1.0 };
    let peak = max(&|(p, _)| p.sigma_contact.abs());
    let (su, ss, se) = (
        scale(max(&|(p, _)| p.u_contact.abs())),
        scale(peak),
        scale(reference[0].energy),
    );
    let du = |(p, r): &Pair| (r.u_contact - p.u_contact).abs() / su;
    let ds = |(p, r): &Pair| (r.sigma_contact - p.sigma_contact).abs() / ss;
    let de = |(p, r): &Pair| (r.energy - p.energy).abs() / se;
    let horizon = pairs
        .iter()
        .find(|x| du(x) > SYNC || ds(x) > SYNC || de(x) > SYNC)
        .map_or(peer.t_end, |(p, _)| p.t);
    Ok(Agreement {
        run: peer.clone(),
        samples: pairs.len(),
        horizon,
        u: max(&du),
        sigma: max(&ds),
        energy: max(&de),
        energy_growth: (
            max(&|(p, _)| p.energy) / se,
            max(&|(_, r)| r.energy) / scale(ours[0].energy),
        ),
        sigma_peak: (peak, max(&|(_, r)| r.sigma_contact.abs())),
    })
}

/// A peer sample and dyncontact's at the same time.
type Pair<'a> = (&'a PeerRow, &'a Row);

/// dyncontact's sample at each peer time (within dt/2); an error names the first peer time
/// without one.
fn pair_samples<'a>(
    peer: &PeerRun,
    reference: &'a [PeerRow],
    ours: &'a [Row],
) -> Result<Vec<Pair<'a>>> {
    let mut k = 0;
    reference
        .iter()
        .map(|p| {
            while k < ours.len() && ours[k].t < p.t - 0.5 * peer.dt {
                k += 1;
            }
            match ours.get(k) {
                Some(r) if (r.t - p.t).abs() <= 0.5 * peer.dt => Ok((p, r)),
                _ => Err(Error::Csv {
                    path: (&peer.file).into(),
                    message: format!("no dyncontact sample at t = {}", p.t),
                }),
            }
        })
        .collect()
}

/// Every run of [`getfem_runs`] whose case file is one of `stems` (`bar1d` for `bar1d.toml`),
/// compared in parallel; none when `peers_dir` does not exist.
pub fn compare_all(peers_dir: &Path, cases_dir: &Path, stems: &[String]) -> Result<Vec<Agreement>> {
    use rayon::prelude::*;
    if !peers_dir.is_dir() {
        return Ok(Vec::new());
    }
    let runs: Vec<PeerRun> = getfem_runs()
        .into_iter()
        .filter(|r| stems.iter().any(|s| r.case == format!("{s}.toml")))
        .collect();
    runs.par_iter()
        .map(|r| compare(r, peers_dir, cases_dir))
        .collect()
}

/// Columns of `cross_code.csv`.
pub const COLUMNS: &[&str] = &[
    "file",
    "brick",
    "contact",
    "cells",
    "elements",
    "dt",
    "t_end",
    "samples",
    "horizon",
    "max_rel_u",
    "max_rel_sigma",
    "max_rel_energy",
    "energy_growth_getfem",
    "energy_growth_dyncontact",
    "sigma_peak_getfem",
    "sigma_peak_dyncontact",
];

/// One row of `cross_code.csv` (floats to 12 significant digits, deterministic).
pub fn row(a: &Agreement) -> Vec<String> {
    let f = |x: f64| crate::output::fmt_float(Some(x));
    let r = &a.run;
    vec![
        r.file.clone(),
        r.brick.into(),
        r.contact.into(),
        r.cells.unwrap_or("").into(),
        r.elements.to_string(),
        f(r.dt),
        f(r.t_end),
        a.samples.to_string(),
        f(a.horizon),
        f(a.u),
        f(a.sigma),
        f(a.energy),
        f(a.energy_growth.0),
        f(a.energy_growth.1),
        f(a.sigma_peak.0),
        f(a.sigma_peak.1),
    ]
}

/// Writes `cross_code.csv`.
pub fn write_cross_code(path: &Path, agreements: &[Agreement]) -> Result<()> {
    crate::output::csv::write_rows(path, COLUMNS, agreements.iter().map(row))
}
