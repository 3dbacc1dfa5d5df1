//! `spring_mass`: one mass on a spring above a rigid obstacle (`shared/reference/spring_mass.md`),
//! `m ü + k u = f + k u_r − B_Nᵀ λ`, discretised by [`PointMass`].

use super::{Case, FieldError, Overrides, RunSpec};
use crate::error::{Error, Result};
use crate::exact::spring_mass::{SpringMass, SpringMassParams};
use crate::exact::ExactContact;
use crate::fem::point_mass::{PointInitial, PointMass};
use crate::problem::Problem;
use crate::space::{MassModel, Space};
use serde::Deserialize;

/// `[system]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct System {
    /// m > 0.
    pub mass: f64,
    /// k ≥ 0.
    pub stiffness: f64,
    /// u_r.
    #[serde(default)]
    pub rest_position: f64,
    /// f (e.g. −m g).
    #[serde(default)]
    pub force: f64,
    /// u₀ ≥ 0.
    pub u0: f64,
    /// v₀.
    #[serde(default)]
    pub v0: f64,
    /// Restitution e of the exact reference trajectory.
    #[serde(default = "one")]
    pub restitution: f64,
}

fn one() -> f64 {
    1.0
}

/// The whole `spring_mass` case file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringMassSpec {
    /// Always `spring_mass`.
    pub case: String,
    /// Units statement.
    pub units: String,
    /// Physical parameters.
    pub system: System,
    /// Run defaults.
    pub run: RunSpec,
    /// Sweeps run by `dyncontact sweep` and `report`.
    #[serde(default)]
    pub sweep: Vec<super::sweep::SweepSpec>,
}

/// A validated spring–mass case.
#[derive(Debug, Clone)]
pub struct SpringMassCase {
    /// Exact trajectory on [0, t_end].
    pub exact: SpringMass,
    run: RunSpec,
    sweeps: Vec<super::sweep::SweepSpec>,
}

/// The schemes with a restitution law use the physical one, `system.restitution`, unless told
/// otherwise (the run, and the key a study gives it, say the one used).
pub(super) fn physical_restitution(run: &mut RunSpec, e: f64) -> Result<()> {
    let restitution = &crate::time::paoli_schatzman::RESTITUTION;
    if super::applicable(&run.scheme, &run.options)?.contains(&restitution.name) {
        run.options.params.or_set(restitution, e);
    }
    Ok(())
}

impl SpringMassCase {
    /// Validates the spec and precomputes the exact trajectory.
    pub fn from_spec(spec: SpringMassSpec, o: &Overrides) -> Result<Self> {
        let s = spec.system;
        let mut run = spec.run;
        o.apply(&mut run);
        physical_restitution(&mut run, s.restitution)?;
        run.validate()?;
        super::check_time_scale(
            ("system.mass", s.mass),
            ("system.stiffness", s.stiffness),
            1.0,
            run.dt,
        )?;
        let p = SpringMassParams {
            mass: s.mass,
            stiffness: s.stiffness,
            rest_position: s.rest_position,
            force: s.force,
            u0: s.u0,
            v0: s.v0,
            restitution: s.restitution,
        };
        let exact = SpringMass::new(p, run.t_end).map_err(|e| e.in_table("system"))?;
        Ok(Self {
            exact,
            run,
            sweeps: spec.sweep,
        })
    }
}

impl Case for SpringMassCase {
    fn kind(&self) -> &'static str {
        "spring_mass"
    }

    fn h(&self) -> f64 {
        f64::NAN
    }

    fn problem(&self, space: &dyn Space) -> Result<Problem> {
        let p = &self.exact.p;
        let shift = if p.stiffness > 0.0 {
            let ue = p.rest_position + p.force / p.stiffness;
            0.5 * p.stiffness * ue * ue
        } else {
            0.0
        };
        let point = PointMass {
            mass: p.mass,
            stiffness: p.stiffness,
        };
        let initial = PointInitial {
            displacement: p.u0,
            velocity: p.v0,
            load: p.force + p.stiffness * p.rest_position,
            energy_shift: shift,
        };
        // The single dof is the contact dof: a space must leave it its mass.
        let keeps_inertia = |model: &MassModel| match space.inertia(model) {
            Ok(inertia) if inertia.sparse().is_some() && !inertia.massless()[0] => Ok(inertia),
            _ => Err(Error::Unsupported(format!(
                "spring_mass has a single dof, which is the contact dof: space `{}` would remove \
                 its inertia (use standard or lumped)",
                space.name()
            ))),
        };
        point.problem(keeps_inertia, &initial)
    }

    fn exact(&self) -> Option<&dyn ExactContact> {
        Some(&self.exact)
    }

    fn field_error(&self) -> Option<Box<dyn FieldError + '_>> {
        Some(Box::new(PointError(&self.exact)))
    }

    fn stress_is_function(&self) -> bool {
        false
    }

    fn run(&self) -> &RunSpec {
        &self.run
    }

    fn sweeps(&self) -> &[super::sweep::SweepSpec] {
        &self.sweeps
    }
}

/// For one dof the "field" error is `|u_h − u|` (no gradient).
struct PointError<'a>(&'a SpringMass);

impl FieldError for PointError<'_> {
    fn errors(&self, u: &[f64], t: f64) -> (f64, f64) {
        ((u[0] - self.0.eval(t).0).abs(), f64::NAN)
    }
}
