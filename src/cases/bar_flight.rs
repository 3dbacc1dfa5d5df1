//! `bar_flight`: a free elastic bar flying onto a rigid plane, the single-impact benchmark
//! ([`crate::exact::bar_flight`]; `bar1d` is the multiple-impact one).
//!
//! Bar (0, L) of unit cross-section, no clamp, unilateral contact at x = 0: `g = u(0, t) ≥ 0`.
//! Initial state: the rigid translation `u₀ = d` (the gap, ≥ 0) at velocity `−v₀`. Units:
//! whatever consistent system the file states (the canonical file is non-dimensional,
//! E = ρ = L = v₀ = 1, d = 0).

use super::bar::{Bar, BarExact, Material, MeshSpec};
use super::{Overrides, RunSpec};
use crate::error::{non_negative, positive, Result};
use crate::exact::bar_flight::BarFlight;
use serde::Deserialize;

/// `[geometry]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// Length L.
    pub length: f64,
    /// Gap d = u₀ between the end x = 0 and the plane at t = 0 (≥ 0).
    pub gap: f64,
}

/// `[initial]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// Speed v₀ > 0 towards the plane.
    pub speed: f64,
}

/// The whole `bar_flight` case file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BarFlightSpec {
    /// Always `bar_flight`.
    pub case: String,
    /// Units statement.
    pub units: String,
    /// Material.
    pub material: Material,
    /// Length and gap.
    pub geometry: Geometry,
    /// Initial speed.
    pub initial: InitialSpec,
    /// Mesh.
    pub mesh: MeshSpec,
    /// Run defaults.
    pub run: RunSpec,
    /// Sweeps run by `dyncontact sweep` and `report`.
    #[serde(default)]
    pub sweep: Vec<super::sweep::SweepSpec>,
}

impl BarExact for BarFlight {
    const KIND: &'static str = "bar_flight";
}

/// The free bar's flight case.
pub type BarFlightCase = Bar<BarFlight>;

impl BarFlightCase {
    /// Validates the spec, applies the overrides and builds the (free) discretisation.
    pub fn from_spec(spec: BarFlightSpec, o: &Overrides) -> Result<Self> {
        let own = || {
            non_negative("geometry.gap", spec.geometry.gap)?;
            positive("initial.speed", spec.initial.speed)
        };
        let (elements, degree, run) = super::bar::validate(
            (&spec.material, spec.geometry.length),
            own,
            (&spec.mesh, spec.run),
            o,
        )?;
        let exact = BarFlight {
            length: spec.geometry.length,
            young: spec.material.young,
            density: spec.material.density,
            speed: spec.initial.speed,
            gap: spec.geometry.gap,
        };
        Ok(Self::new(exact, elements, degree, false, run)?.with_sweeps(spec.sweep))
    }
}
