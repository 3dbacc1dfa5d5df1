//! The probe time series of a run (one [`Row`] per step, and t = 0) and its `timeseries.csv`.
//!
//! `timeseries.csv`: `t, u_contact, v_contact, sigma_contact, energy, gap, force_contact` (the total
//! contact force Σλ), then `approach` (the centre of mass's displacement towards the plane) for
//! the curved-body cases, `momentum` (the total linear momentum `(M̃1_d)ᵀV` along the line of
//! impact, with the space's own mass) and `u_contact_master, v_contact_master` (the master's
//! contact point facing the probe, along the line of impact) for the multi-body cases,
//! `com_velocity_t` (the centre of
//! mass's velocity along the first tangent of the plane) and `friction_work` (`W_f ≥ 0`, the
//! work dissipated by Coulomb friction) for the runs with friction, `com_velocity_n` (the centre
//! of mass's velocity along the plane's normal) and `angular_velocity` (ω, positive rolling along
//! +e_1) for a disc or sphere with friction and, when the case has an exact solution,
//! `u_contact_exact, sigma_contact_exact, energy_exact`. `sigma_contact` is the
//! normal contact stress σ_N = −λ/area (compression negative). Units are those of the case file
//! (time, length, length/time, force/area, energy, length).

use crate::error::Result;
use crate::output::{csv::write_rows, fmt_float};
use std::path::Path;

/// One sample of the probe time series (one per step, and t = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Time.
    pub t: f64,
    /// Displacement of the contact dof.
    pub u_contact: f64,
    /// Velocity of the contact point (inertial velocity dof of the probe).
    pub v_contact: f64,
    /// Normal contact stress σ_N = −λ/area (≤ 0).
    pub sigma_contact: f64,
    /// Total energy.
    pub energy: f64,
    /// Gap g = g₀ − B_N U at the probe.
    pub gap: f64,
    /// Total contact force Σ_i λ_i (≥ 0; per unit thickness in 2D).
    pub force_contact: f64,
    /// Rigid approach δ of the body: displacement of its centre of mass towards the plane
    /// (curved-body cases).
    pub approach: Option<f64>,
    /// Total linear momentum `(M̃1_d)ᵀV` along the line of impact (multi-body cases).
    pub momentum: Option<f64>,
    /// Displacement and velocity along the line of impact of the master's contact point facing
    /// the probe (multi-body cases).
    pub master: Option<(f64, f64)>,
    /// With friction: the centre of mass's velocity along the first tangent and the friction
    /// work `W_f` so far.
    pub friction: Option<(f64, f64)>,
    /// A disc or sphere with friction: the centre of mass's normal velocity and the angular
    /// velocity ω ([`crate::cases::Spin`]).
    pub spin: Option<(f64, f64)>,
    /// Exact `(u, σ_N, E)` at the contact point, when the case has an exact solution.
    pub exact: Option<(f64, f64, f64)>,
}

impl Row {
    /// The first quantity the run computed for this sample (the exact columns aside) that is
    /// not finite, as `(column, value)`.
    pub fn non_finite(&self) -> Option<(&'static str, f64)> {
        let computed = TIMESERIES_COLUMNS.iter().zip([
            self.t,
            self.u_contact,
            self.v_contact,
            self.sigma_contact,
            self.energy,
            self.gap,
            self.force_contact,
        ]);
        computed
            .map(|(c, v)| (*c, v))
            .chain(self.approach.map(|a| ("approach", a)))
            .chain(self.master.map(|m| ("u_contact_master", m.0)))
            .chain(self.master.map(|m| ("v_contact_master", m.1)))
            .find(|(_, v)| !v.is_finite())
    }
}

/// Columns of `timeseries.csv` (then the `_exact` columns when present).
pub const TIMESERIES_COLUMNS: &[&str] = &[
    "t",
    "u_contact",
    "v_contact",
    "sigma_contact",
    "energy",
    "gap",
    "force_contact",
];
/// The master's probe columns of `timeseries.csv` (multi-body cases, after `momentum`).
pub const MASTER_COLUMNS: &[&str] = &["u_contact_master", "v_contact_master"];
/// Friction columns of `timeseries.csv` (runs with friction only).
pub const FRICTION_COLUMNS: &[&str] = &["com_velocity_t", "friction_work"];
/// Rigid-motion columns of `timeseries.csv` (a disc or sphere with friction).
pub const SPIN_COLUMNS: &[&str] = &["com_velocity_n", "angular_velocity"];
/// Exact-solution columns of `timeseries.csv`.
pub const EXACT_COLUMNS: &[&str] = &["u_contact_exact", "sigma_contact_exact", "energy_exact"];
/// Writes `timeseries.csv`.
pub fn write_timeseries(path: &Path, rows: &[Row]) -> Result<()> {
    let exact = rows.first().is_some_and(|r| r.exact.is_some());
    let approach = rows.first().is_some_and(|r| r.approach.is_some());
    let momentum = rows.first().is_some_and(|r| r.momentum.is_some());
    let friction = rows.first().is_some_and(|r| r.friction.is_some());
    let spin = rows.first().is_some_and(|r| r.spin.is_some());
    let mut header = TIMESERIES_COLUMNS.to_vec();
    if approach {
        header.push("approach");
    }
    if momentum {
        header.push("momentum");
    }
    if rows.first().is_some_and(|r| r.master.is_some()) {
        header.extend_from_slice(MASTER_COLUMNS);
    }
    if friction {
        header.extend_from_slice(FRICTION_COLUMNS);
    }
    if spin {
        header.extend_from_slice(SPIN_COLUMNS);
    }
    if exact {
        header.extend_from_slice(EXACT_COLUMNS);
    }
    write_rows(
        path,
        &header,
        rows.iter().map(|r| {
            let mut v = vec![
                r.t,
                r.u_contact,
                r.v_contact,
                r.sigma_contact,
                r.energy,
                r.gap,
                r.force_contact,
            ];
            v.extend(r.approach);
            v.extend(r.momentum);
            if let Some((u, w)) = r.master {
                v.extend([u, w]);
            }
            if let Some((c, w)) = r.friction {
                v.extend([c, w]);
            }
            if let Some((n, w)) = r.spin {
                v.extend([n, w]);
            }
            if let Some((u, s, e)) = r.exact {
                v.extend([u, s, e]);
            }
            v.into_iter().map(|x| fmt_float(Some(x)))
        }),
    )
}
