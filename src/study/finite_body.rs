//! The discrete body's own quasi-static impact: the reference that separates Hertz's model error
//! (a half-space) from the discretisation and the dynamics of a sphere's impact.
//!
//! A quasi-static impact decelerates the body as a rigid body, so its inertia is a uniform body
//! force balancing the contact force F. At rest under a uniform body force of total F, pressed on
//! the plane, the approach of the centre of mass is Hertz's less a finite-body term:
//!
//! `δ(F) = (F/k)^{2/3} − c F / (E* R)`, `k = (4/3) E* √R`.
//!
//! Hertz measures δ to points at infinity of a half-space; a sphere's centre lies at depth R,
//! where Boussinesq's point load has already moved the half-space by
//! `(3 − 2ν) F / (2π (1 − ν) E* R)` (c ≈ 0.55 at ν = 0.3), less what the body force compresses
//! the sphere by. [`finite_body`] measures c on the case's own mesh by static solves and returns
//! the Hertz reference with the body's mass and that compliance ([`Hertz::finite_body`]):
//! the impact `m δ̈ = −F(δ)` it predicts differs from a dynamic run only by the vibrations.
//!
//! A static solve is backward Euler from rest with `Δt = 10 t_c`: each step
//! `(M/Δt² + K) U_{n+1} = F + M (U_n + Δt V_n)/Δt² − B_Nᵀλ` contracts towards the equilibrium
//! `K U = F − B_Nᵀλ` (independent of M) by about `(ω Δt)⁻² ≈ 10⁻³` per step, ω the contact
//! frequency; it stops when the approach changes by less than [`TOLERANCE`] of itself.
//!
//! A law is measured once per process and static problem: a body that is the same problem as one
//! measured before (the default hertz3d sphere and each sphere of two_spheres) reuses its law
//! ([`finite_body`]).

use super::schedule::Estimate;
use crate::cases::{Case, Impact, Size};
use crate::error::{Error, Result};
use crate::exact::hertz::Hertz;
use crate::linalg::SpMat;
use crate::problem::Problem;
use crate::time::backward_euler::BackwardEuler;
use crate::time::step::ContactStep;
use crate::time::{Integrator, LinearSolver, Solvers};
use std::hash::{DefaultHasher, Hash, Hasher};
use std::sync::{Arc, Mutex, PoisonError};

/// The loads of [`finite_body`], as fractions of Hertz's peak force.
pub const LOADS: [f64; 2] = [0.5, 1.0];
/// Relative change of the approach between two steps at which a static solve stops.
pub const TOLERANCE: f64 = 1e-12;
/// Steps a static solve may take.
const MAX_STEPS: usize = 60;
/// The static solves' time step, in Hertz contact durations.
const STEP_IN_DURATIONS: f64 = 10.0;

/// The body at rest under a uniform body force of total `force`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticPoint {
    /// Total contact force F (= the body force).
    pub force: f64,
    /// Approach δ of the centre of mass.
    pub approach: f64,
    /// Hertz's approach `(F/k)^{2/3}` under the same force.
    pub hertz: f64,
}

/// The measured finite-body law and the impact it predicts.
#[derive(Debug, Clone)]
pub struct FiniteBody {
    /// The static solves, by increasing force.
    pub points: Vec<StaticPoint>,
    /// `c = (δ_Hertz − δ) E* R / F`, least squares over the points.
    pub coefficient: f64,
    /// Hertz with the discrete body's mass, half-space.
    pub half_space: Hertz,
    /// Hertz with the discrete body's mass and compliance `c / (E* R)`.
    pub hertz: Hertz,
}

impl StaticPoint {
    /// `(δ_Hertz − δ) E* R / F` of this point.
    pub fn coefficient(&self, h: &Hertz) -> f64 {
        (self.hertz - self.approach) * h.e_star * h.radius / self.force
    }
}

/// Measures the finite-body law of `case` (a sphere against Hertz: an error otherwise) at the
/// [`LOADS`] and fits its coefficient; for two bodies ([`Case::bodies`]), [`in_series`]. A body
/// whose static problem was measured before in this process reuses that law ([`measured`]):
/// the solves are deterministic, so it is the law this body would measure.
pub fn finite_body(case: &dyn Case) -> Result<FiniteBody> {
    let parts = case.bodies();
    if !parts.is_empty() {
        return in_series(case, &parts);
    }
    let impact = case.impact().filter(|i| i.hertz.dim == 3).ok_or_else(|| {
        Error::Unsupported(format!(
            "the finite-body law needs a sphere against Hertz, not {}",
            case.kind()
        ))
    })?;
    let half_space = impact.hertz.finite_body(impact.mass, 0.0)?;
    let (Some(f_max), Some(t_c)) = (half_space.peak_force(), half_space.duration()) else {
        return Err(Error::Unsupported("Hertz gives no peak force".into()));
    };
    let dt = STEP_IN_DURATIONS * t_c;
    let problem = Statics::at_rest(case)?;
    let slot = measured(fingerprint(&problem, &impact, dt))?;
    // Held while measuring: a second request for the same body waits for this law.
    let mut law = slot.lock().map_err(poisoned)?;
    if let Some(law) = law.as_ref() {
        return Ok(law.clone());
    }
    let mut statics = Statics::new(case, &impact, problem, dt)?;
    let points = LOADS
        .iter()
        .map(|&x| statics.point(x * f_max))
        .collect::<Result<Vec<_>>>()?;
    // Least squares of (δ_H − δ) = c_f F.
    let compliance = points
        .iter()
        .map(|p| (p.hertz - p.approach) * p.force)
        .sum::<f64>()
        / points.iter().map(|p| p.force * p.force).sum::<f64>();
    let measured = FiniteBody {
        coefficient: compliance * half_space.e_star * half_space.radius,
        hertz: half_space.finite_body(impact.mass, compliance)?,
        half_space,
        points,
    };
    *law = Some(measured.clone());
    Ok(measured)
}

/// A law of [`finite_body`], measured or being measured, under the fingerprint of its static
/// problem.
type Slot = Arc<Mutex<Option<FiniteBody>>>;

/// The slot of the static problem of fingerprint `key` among those of this process (a new,
/// empty one the first time).
fn measured(key: u64) -> Result<Slot> {
    static LAWS: Mutex<Vec<(u64, Slot)>> = Mutex::new(Vec::new());
    let mut laws = LAWS.lock().map_err(poisoned)?;
    if let Some((_, slot)) = laws.iter().find(|(k, _)| *k == key) {
        return Ok(slot.clone());
    }
    let slot = Slot::default();
    laws.push((key, slot.clone()));
    Ok(slot)
}

fn poisoned<T>(_: PoisonError<T>) -> Error {
    Error::Internal("a finite-body law panicked while it was measured".into())
}

/// A hash of everything the static solves of [`Statics`] read: K, M, the contact rows and gaps
/// (and friction), U₀, the centre's weights, Hertz's reference and the step, bit for bit.
fn fingerprint(problem: &Problem, impact: &Impact, dt: f64) -> u64 {
    let mut h = DefaultHasher::new();
    let bits = |h: &mut DefaultHasher, x: &[f64]| x.iter().for_each(|v| v.to_bits().hash(h));
    let matrix = |h: &mut DefaultHasher, a: &SpMat| {
        let a = a.as_ref();
        (a.nrows(), a.ncols()).hash(h);
        a.symbolic().col_ptr().hash(h);
        a.symbolic().col_nnz().hash(h);
        a.symbolic().row_idx().hash(h);
        bits(h, a.val());
    };
    matrix(&mut h, &problem.k);
    match problem.inertia.sparse() {
        Some(m) => matrix(&mut h, m),
        None => format!("{:?}", problem.inertia).hash(&mut h),
    }
    let contact = &problem.contact;
    matrix(&mut h, &contact.b_n);
    bits(&mut h, &contact.g0);
    if let Some(f) = &contact.friction {
        bits(&mut h, &[f.mu]);
        matrix(&mut h, &f.b_t);
    }
    bits(&mut h, &problem.u0);
    for &(j, w) in &impact.centre {
        j.hash(&mut h);
        bits(&mut h, &[w]);
    }
    format!("{:?}", impact.hertz).hash(&mut h);
    bits(&mut h, &[impact.mass, dt]);
    h.finish()
}

/// Two bodies in series: each body's law measured alone against the plane, the approaches of
/// their centres add, so the pair's far-field terms add to Hertz's approach of the pair (its
/// `R*`, `E*`): `δ(F) = (F/k*)^{2/3} − (c_{f,1} + c_{f,2}) F`. For two equal bodies this is
/// exactly `δ₁(F) + δ₂(F)` (`(F/k*)^{2/3} = 2 (F/k₁)^{2/3}`: each body sees the contact radius
/// and pressure of its impact on the plane); otherwise the far-field terms are taken at the
/// bodies' own contact radii. `points` are body 1's then body 2's; `coefficient` is
/// `(c_{f,1} + c_{f,2}) E* R*` of the pair. A body that is the same case as one before it
/// (twins) reuses its law.
pub fn in_series(case: &dyn Case, parts: &[&dyn Case]) -> Result<FiniteBody> {
    let impact = case.impact().filter(|i| i.hertz.dim == 3).ok_or_else(|| {
        Error::Unsupported(format!(
            "the finite-body law of two bodies needs two spheres against Hertz, not {}",
            case.kind()
        ))
    })?;
    // A body listed twice (twins: [`Case::bodies`]) is measured once.
    let mut laws: Vec<FiniteBody> = Vec::with_capacity(parts.len());
    for (i, &p) in parts.iter().enumerate() {
        let same = parts[..i].iter().position(|&q| std::ptr::addr_eq(p, q));
        laws.push(match same {
            Some(k) => laws[k].clone(),
            None => finite_body(p)?,
        });
    }
    let compliance: f64 = laws.iter().map(|l| l.hertz.compliance).sum();
    let half_space = impact.hertz.finite_body(impact.mass, 0.0)?;
    Ok(FiniteBody {
        points: laws.iter().flat_map(|l| l.points.iter().copied()).collect(),
        coefficient: compliance * half_space.e_star * half_space.radius,
        hertz: half_space.finite_body(impact.mass, compliance)?,
        half_space,
    })
}

/// The estimated cost of [`finite_body`] on a sphere of `size`, for the scheduler: a sparse
/// Cholesky factor and up to [`MAX_STEPS`] solves per load (measured on the default hertz3d
/// sphere at 661ce8a: 1.1 GB, about 20 s per load).
pub fn estimate(size: Size) -> Estimate {
    Estimate {
        seconds: LOADS.len() as f64 * size.dofs * MAX_STEPS as f64 * 6e-6,
        bytes: 250e6 + size.dofs * 15e3,
    }
}

/// The static solves of one body (standard mass, nodal contact, direct solver): its problem at
/// rest and the backward Euler step matrix of `dt`, factored once for every load.
pub struct Statics<'c> {
    case: &'c dyn Case,
    impact: &'c Impact,
    problem: Problem,
    dt: f64,
    /// The factored step (taken while a load is solved).
    system: Option<ContactStep>,
}

impl<'c> Statics<'c> {
    /// The problem of `case`'s body at rest (standard mass, no load).
    pub fn at_rest(case: &dyn Case) -> Result<Problem> {
        let space = crate::space::by_name(crate::space::standard::ENTRY.name)?;
        let mut problem = case.problem(space.as_ref())?;
        problem.v0.fill(0.0);
        problem.f.fill(0.0);
        Ok(problem)
    }

    /// The static solves of `case`'s body at rest ([`Statics::at_rest`]), its step matrix of
    /// `dt` factored.
    pub fn new(case: &'c dyn Case, impact: &'c Impact, problem: Problem, dt: f64) -> Result<Self> {
        let system = BackwardEuler::system(&problem, dt, Self::solvers(&problem)?)?;
        Ok(Self {
            case,
            impact,
            problem,
            dt,
            system: Some(system),
        })
    }

    /// The contact law (a fresh one for each load) and the direct solver.
    fn solvers(problem: &Problem) -> Result<Solvers> {
        Ok(Solvers {
            contact: crate::contact::by_name("active_set", problem.contact.len())?,
            linear: LinearSolver::Direct,
        })
    }

    /// The static state under a uniform body force of total `force` towards the plane, by
    /// backward Euler steps from rest.
    pub fn point(&mut self, force: f64) -> Result<StaticPoint> {
        let Self {
            case,
            impact,
            problem,
            dt,
            system,
        } = self;
        // The body force ρ b with ∫ρ b = −F e_d: the centre's weights are ∫ρ φ_i / m.
        for &(j, w) in &impact.centre {
            problem.f[j] = -force * w;
        }
        let mut step = system
            .take()
            .ok_or_else(|| Error::Internal("the static step is in use".into()))?;
        step.restart(Self::solvers(problem)?.contact)?;
        let mut integrator = BackwardEuler::with_system(problem, *dt, step)?;
        let approach = |u: &[f64]| -impact.centre.iter().map(|&(j, w)| w * u[j]).sum::<f64>();
        let mut last = 0.0;
        for _ in 0..MAX_STEPS {
            integrator.step()?;
            let s = integrator.state();
            let delta = approach(s.u);
            if (delta - last).abs() <= TOLERANCE * delta.abs() {
                let force: f64 = s.lambda.iter().sum();
                *system = Some(integrator.into_system());
                return Ok(StaticPoint {
                    force,
                    approach: delta,
                    hertz: impact.hertz.approach(force),
                });
            }
            last = delta;
        }
        Err(Error::Diverged {
            step: MAX_STEPS,
            time: MAX_STEPS as f64 * *dt,
            reason: format!(
                "{}: no static equilibrium under the body force {force:.4e} after {MAX_STEPS} \
                 backward Euler steps of {dt:.3e} (approach {last:.6e})",
                case.kind()
            ),
        })
    }
}
