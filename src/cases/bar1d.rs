//! `bar1d`: the Doyen–Ern–Piperno bar impact (`shared/reference/bar_impact.md`).
//!
//! Bar (0, L) of unit cross-section, clamped at x = L, unilateral contact at x = 0 with a rigid
//! obstacle at the end's reference position: `g = u(0, t) ≥ 0`. Initial state `u₀ = a (1 − x/L)`,
//! `v₀ = 0`. Units: whatever consistent system the file states (the canonical file is
//! non-dimensional, E = ρ = L = 1).

use super::bar::{discretisation, BarFieldError, Material, MeshSpec};
use super::{Case, FieldError, Overrides, RunSpec};
use crate::error::{positive, Result};
use crate::exact::bar_impact::BarImpact;
use crate::exact::{ExactContact, PiecewiseLinearBar};
use crate::fem::discretisation::{Discretisation, Initial};
use crate::problem::Problem;
use crate::space::{MassModel, Space};
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

/// A validated bar case.
#[derive(Debug, Clone)]
pub struct Bar1d {
    /// The exact solution with the case's parameters.
    pub exact: BarImpact,
    /// The bar's discretisation: a uniform interval mesh of P1/P2 segments, clamped at x = L
    /// unless built free ([`Bar1d::new`]), Γ_C its end x = 0 (ν = 0: `σ = E u'`).
    pub fem: Discretisation,
    run: RunSpec,
    sweeps: Vec<super::sweep::SweepSpec>,
}

impl Bar1d {
    /// Validates the spec, applies the overrides and builds the discretisation.
    pub fn from_spec(spec: Bar1dSpec, o: &Overrides) -> Result<Self> {
        positive("material.young", spec.material.young)?;
        positive("material.density", spec.material.density)?;
        positive("geometry.length", spec.geometry.length)?;
        crate::error::non_negative("geometry.lift", spec.geometry.lift)?;
        let (elements, degree) = spec.mesh.resolve(o)?;
        let mut run = spec.run;
        o.apply(&mut run);
        run.validate()?;
        let exact = BarImpact {
            length: spec.geometry.length,
            young: spec.material.young,
            density: spec.material.density,
            lift: spec.geometry.lift,
        };
        let mut bar = Self::new(exact, elements, degree, true, run)?;
        bar.sweeps = spec.sweep;
        Ok(bar)
    }

    /// The bar with `elements` elements of degree `degree`, clamped at x = L when `clamped`.
    pub fn new(
        exact: BarImpact,
        elements: usize,
        degree: usize,
        clamped: bool,
        run: RunSpec,
    ) -> Result<Self> {
        let fem = discretisation(exact.length, exact.young, exact.density, elements, degree)?;
        let length = exact.length;
        let fem = if clamped {
            fem.clamped(|x| (x[0] - length).abs() < 1e-9 * length)?
        } else {
            fem
        };
        Ok(Self {
            exact,
            fem,
            run,
            sweeps: Vec::new(),
        })
    }

    /// Element data for the spaces: consistent P_p masses and, for P2, the P1 velocity space.
    pub fn mass_model(&self) -> MassModel {
        self.fem.mass_model()
    }
}

impl Case for Bar1d {
    fn kind(&self) -> &'static str {
        "bar1d"
    }

    fn h(&self) -> f64 {
        self.fem.mesh.h
    }

    fn element(&self) -> Option<(&'static str, usize)> {
        let e = self.fem.mesh.element;
        Some((e.cells(), e.degree))
    }

    fn problem(&self, space: &dyn Space) -> Result<Problem> {
        let initial = Initial {
            displacement: self
                .fem
                .interpolate(|x| [self.exact.field(x[0], 0.0).0, 0.0, 0.0]),
            velocity: vec![0.0; self.fem.n_dofs()],
            gravity: None,
            lift: 0.0,
        };
        self.fem.problem(|m| space.inertia(m), &initial)
    }

    fn exact(&self) -> Option<&dyn ExactContact> {
        Some(&self.exact)
    }

    fn field_error(&self) -> Option<Box<dyn FieldError + '_>> {
        Some(Box::new(BarFieldError::new(&self.fem, &self.exact)))
    }

    fn stress_is_function(&self) -> bool {
        true
    }

    fn run(&self) -> &RunSpec {
        &self.run
    }

    fn sweeps(&self) -> &[super::sweep::SweepSpec] {
        &self.sweeps
    }
}
