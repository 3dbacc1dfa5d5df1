//! `bar1d`: the Doyen–Ern–Piperno bar impact (`shared/reference/bar_impact.md`).
//!
//! Bar (0, L) of unit cross-section, clamped at x = L, unilateral contact at x = 0 with a rigid
//! obstacle at the end's reference position: `g = u(0, t) ≥ 0`. Initial state `u₀ = a (1 − x/L)`,
//! `v₀ = 0`. Units: whatever consistent system the file states (the canonical file is
//! non-dimensional, E = ρ = L = 1).

use super::bar::{Bar, BarExact, Material, MeshSpec};
use super::{Overrides, RunSpec};
use crate::error::Result;
use crate::exact::bar_impact::BarImpact;
use serde::Deserialize;

/// `[geometry]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// Length L.
    pub length: f64,
    /// Initial lift a = u₀(0) (≥ 0).
    pub lift: f64,
}

/// The whole `bar1d` case file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bar1dSpec {
    /// Always `bar1d`.
    pub case: String,
    /// Units statement.
    pub units: String,
    /// Material.
    pub material: Material,
    /// Geometry and initial lift.
    pub geometry: Geometry,
    /// Mesh.
    pub mesh: MeshSpec,
    /// Run defaults.
    pub run: RunSpec,
    /// Sweeps run by `dyncontact sweep` and `report`.
    #[serde(default)]
    pub sweep: Vec<super::sweep::SweepSpec>,
}

impl BarExact for BarImpact {
    const KIND: &'static str = "bar1d";
}

/// The bar impact case: clamped at x = L (unless built free, [`Bar::new`]).
pub type Bar1d = Bar<BarImpact>;

impl Bar1d {
    /// Validates the spec, applies the overrides and builds the discretisation.
    pub fn from_spec(spec: Bar1dSpec, o: &Overrides) -> Result<Self> {
        let (elements, degree, run) = super::bar::validate(
            (&spec.material, spec.geometry.length),
            || crate::error::non_negative("geometry.lift", spec.geometry.lift),
            (&spec.mesh, spec.run),
            o,
        )?;
        let exact = BarImpact {
            length: spec.geometry.length,
            young: spec.material.young,
            density: spec.material.density,
            lift: spec.geometry.lift,
        };
        Ok(Self::new(exact, elements, degree, true, run)?.with_sweeps(spec.sweep))
    }
}
