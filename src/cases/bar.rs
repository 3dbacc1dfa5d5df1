//! What the 1D bar cases share ([`super::bar1d`], [`super::bar_flight`]): the `[material]` and
//! `[mesh]` tables, the case itself ([`Bar`]: an exact solution, the bar's discretisation — a
//! uniform interval mesh of P1/P2 segments through [`Discretisation`], ν = 0 so that `σ = E u'`,
//! Γ_C its end x = 0 — started from the exact state at t = 0) and the exact-field errors against
//! a solution that is piecewise linear in x ([`BarFieldError`]).

use super::sweep::SweepSpec;
use super::{Case, FieldError, Overrides, RunSpec};
use crate::element::quadrature::gauss_legendre_01;
use crate::element::segment::Segment;
use crate::error::{positive, Error, Result};
use crate::exact::{ExactContact, PiecewiseLinearBar};
use crate::fem::assembly::{segment_mass, segment_stiffness};
use crate::fem::discretisation::{Discretisation, Initial};
use crate::fem::elasticity::Lame;
use crate::mesh::interval::interval;
use crate::mesh::{ContactRule, FACING};
use crate::problem::Problem;
use crate::space::{MassModel, Space};
use serde::Deserialize;

/// `[material]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E.
    pub young: f64,
    /// Density ρ.
    pub density: f64,
}

impl Material {
    /// E > 0 and ρ > 0.
    pub fn validate(&self) -> Result<()> {
        positive("material.young", self.young)?;
        positive("material.density", self.density)?;
        Ok(())
    }

    /// [`super::check_time_scale`] for elements of length `h` and the step `dt`.
    pub fn check_time_scale(&self, h: f64, dt: f64) -> Result<()> {
        super::check_time_scale(
            ("material.density", self.density),
            ("material.young", self.young),
            h,
            dt,
        )
    }
}

/// `[mesh]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// Number of elements.
    pub elements: usize,
    /// Polynomial degree of the displacement (1 or 2).
    pub degree: usize,
}

impl MeshSpec {
    /// `(elements, degree)` with the overrides applied; the degree must be 1 or 2.
    pub fn resolve(&self, o: &Overrides) -> Result<(usize, usize)> {
        let degree = o.degree.unwrap_or(self.degree);
        if !(1..=2).contains(&degree) {
            return Err(Error::invalid("mesh.degree", degree, "must be 1 or 2"));
        }
        Ok((o.elements.unwrap_or(self.elements), degree))
    }
}

/// What the one-bar case files validate alike, in this order: the material, `geometry.length`,
/// the kind's own fields (`own`), the mesh and the run with the overrides, and the time scale
/// of elements of length `length / elements` ([`Material::check_time_scale`]). Returns
/// `(elements, degree, run)`.
pub fn validate<T>(
    (material, length): (&Material, f64),
    own: impl FnOnce() -> Result<T>,
    (mesh, mut run): (&MeshSpec, RunSpec),
    o: &Overrides,
) -> Result<(usize, usize, RunSpec)> {
    material.validate()?;
    crate::error::length("geometry.length", length)?;
    own()?;
    let (elements, degree) = mesh.resolve(o)?;
    check_memory(elements, (elements * degree) as f64)?;
    o.apply(&mut run);
    run.validate()?;
    material.check_time_scale(length / elements.max(1) as f64, run.dt)?;
    Ok((elements, degree, run))
}

/// The exact solution a bar case kind is built on, and the kind's name.
pub trait BarExact: PiecewiseLinearBar + Clone + std::fmt::Debug + 'static {
    /// The case kind (`case = "…"` of its files).
    const KIND: &'static str;
}

/// A 1D bar case: the exact solution `X`, the bar's discretisation (every node free, or clamped
/// at x = L), the run settings and the sweeps. The discrete run starts from the exact
/// displacement and velocity at t = 0, interpolated at the nodes.
#[derive(Debug, Clone)]
pub struct Bar<X> {
    /// The exact solution with the case's parameters.
    pub exact: X,
    /// The bar's discretisation: a uniform interval mesh of P1/P2 segments, Γ_C its end x = 0
    /// (ν = 0: `σ = E u'`).
    pub fem: Discretisation,
    run: RunSpec,
    sweeps: Vec<SweepSpec>,
}

impl<X: BarExact> Bar<X> {
    /// The bar of `exact` with `elements` elements of degree `degree`, clamped at x = L when
    /// `clamped`.
    pub fn new(
        exact: X,
        elements: usize,
        degree: usize,
        clamped: bool,
        run: RunSpec,
    ) -> Result<Self> {
        let length = exact.length();
        let fem = discretisation(length, exact.young(), exact.density(), elements, degree)?;
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

    /// `self` with the case file's `[[sweep]]` tables.
    pub fn with_sweeps(mut self, sweeps: Vec<SweepSpec>) -> Self {
        self.sweeps = sweeps;
        self
    }

    /// Element data for the spaces: consistent P_p masses and, for P2, the P1 velocity space.
    pub fn mass_model(&self) -> MassModel {
        self.fem.mass_model()
    }
}

impl<X: BarExact> Case for Bar<X> {
    fn kind(&self) -> &'static str {
        X::KIND
    }

    fn h(&self) -> f64 {
        self.fem.mesh.h
    }

    fn element(&self) -> Option<(&'static str, usize)> {
        let e = self.fem.mesh.element;
        Some((e.cells(), e.degree))
    }

    fn problem(&self, space: &dyn Space) -> Result<Problem> {
        let start = |pick: fn((f64, f64, f64)) -> f64| {
            self.fem
                .interpolate(|x| [pick(self.exact.field(x[0], 0.0)), 0.0, 0.0])
        };
        let initial = Initial {
            displacement: start(|(u, _, _)| u),
            velocity: start(|(_, _, v)| v),
            gravity: None,
            lift: 0.0,
        };
        let problem = self.fem.problem(|m| space.inertia(m), &initial)?;
        // One P1 element of a clamped bar: the contact dof is the only free dof, and a space
        // that makes it massless would leave a bar without mass.
        let ones = vec![1.0; problem.n()];
        if problem.inertia.mass_times(&ones)?.iter().all(|&m| m == 0.0) {
            return Err(Error::invalid(
                "mesh.elements",
                self.fem.mesh.connectivity.len(),
                &format!(
                    "space `{}` leaves the bar without mass: its only free dof is the contact \
                     dof, which this space makes massless; use 2 elements or more (or degree 2)",
                    space.name()
                ),
            ));
        }
        Ok(problem)
    }

    fn exact(&self) -> Option<&dyn ExactContact> {
        Some(&self.exact)
    }

    fn field_error(&self) -> Option<Box<dyn FieldError + '_>> {
        Some(Box::new(BarFieldError::new(&self.fem, &self.exact)))
    }

    fn run(&self) -> &RunSpec {
        &self.run
    }

    fn sweeps(&self) -> &[SweepSpec] {
        &self.sweeps
    }
}

/// Refuses `mesh.elements` = `elements` when a bar's `dofs` would not fit in the available
/// memory: [`BYTES_PER_DOF`] each. Checked before the time scale, which a huge count would
/// otherwise blame on the density.
pub fn check_memory(elements: usize, dofs: f64) -> Result<()> {
    crate::util::check_memory("mesh.elements", elements, dofs * BYTES_PER_DOF)
}

/// A bar's peak resident memory per dof, the time series aside (checked apart, by `run.t_end`):
/// K, M, the step matrix and its factor, the vectors. Measured (`VmHWM`) 630–745 B per dof on
/// bar1d at 10⁶ P1 and 2·10⁶ P2 dofs; the estimate (440 B) had been below it, by 1.8 times on
/// two bars.
const BYTES_PER_DOF: f64 = 800.0;

/// The bar (0, `length`) of modulus `young` and density `density` with `elements` segments of
/// degree `degree`, every node free, Γ_C its end x = 0 (ν = 0: λ = 0, 2μ = E exactly).
fn discretisation(
    length: f64,
    young: f64,
    density: f64,
    elements: usize,
    degree: usize,
) -> Result<Discretisation> {
    check_memory(elements, (elements * degree) as f64)?;
    let mesh = interval(length, elements, degree)?;
    let lame = Lame {
        lambda: 0.0,
        mu: 0.5 * young,
    };
    Discretisation::new(mesh, lame, density, ContactRule::Facing(FACING))
}

/// L² and H¹-seminorm errors of a P_p field on a bar discretisation against an exact solution
/// that is piecewise linear in x ([`PiecewiseLinearBar`]), exact per element.
///
/// At time t the exact `u(·, t)` is linear in x between its kinks (the wave fronts). On an
/// element K that no kink cuts, `u_h − u` is therefore the P_p function with nodal values
/// `e_k = u_h(x_k) − u(x_k, t)`, and `‖u_h − u‖²_{L²(K)} = h eᵀ M̂ e`,
/// `|u_h − u|²_{H¹(K)} = eᵀ K̂ e / h` with the reference mass `M̂_ij = ∫₀¹ φ̂_i φ̂_j` and stiffness
/// `K̂_ij = ∫₀¹ φ̂_i' φ̂_j'`. The (at most two) cut elements are split at the kinks and integrated
/// with the 3-point Gauss rule, exact on every piece (integrand of degree ≤ 4). Cost O(n) per
/// sample with no allocation but one node buffer.
pub struct BarFieldError<'a> {
    fem: &'a Discretisation,
    exact: &'a dyn PiecewiseLinearBar,
    rule: Vec<(f64, f64)>,
    /// `(h M̂, K̂ / h)`.
    reference: SegmentNorms,
}

impl<'a> BarFieldError<'a> {
    /// The evaluator of fields on `fem` (a uniform interval mesh) against `exact`.
    pub fn new(fem: &'a Discretisation, exact: &'a dyn PiecewiseLinearBar) -> Self {
        let (p, h) = (fem.mesh.element.degree, fem.mesh.h);
        Self {
            fem,
            exact,
            rule: gauss_legendre_01(3),
            reference: SegmentNorms::new(p, h),
        }
    }

    /// The degree p, the element length h and the number of elements.
    fn layout(&self) -> (usize, f64, usize) {
        let mesh = &self.fem.mesh;
        (mesh.element.degree, mesh.h, mesh.connectivity.len())
    }

    /// Value of the free-dof vector `u` at node `i` (0 at a clamped node).
    fn nodal(&self, u: &[f64], i: usize) -> f64 {
        self.fem.dofs.get(i, 0).map_or(0.0, |d| u[d])
    }

    /// `(u_h(x), u_h'(x))` in element `e` at reference coordinate ξ.
    fn eval_in(&self, u: &[f64], e: usize, xi: f64) -> (f64, f64) {
        let (p, h, _) = self.layout();
        let seg = Segment { degree: p };
        (p * e..=p * e + p)
            .enumerate()
            .fold((0.0, 0.0), |(v, d), (k, i)| {
                let ui = self.nodal(u, i);
                (
                    v + ui * seg.value(k, xi),
                    d + ui * seg.derivative(k, xi) / h,
                )
            })
    }

    /// `∫_K (u_h − u)²` and `∫_K (u_h' − u')²` on element `e` by Gauss on its pieces between
    /// the kinks.
    fn by_quadrature(&self, u: &[f64], e: usize, t: f64, kinks: [f64; 2]) -> (f64, f64) {
        let ex = self.exact;
        let (_, h, _) = self.layout();
        let xa = e as f64 * h;
        let mut cuts = [xa, kinks[0], kinks[1], xa + h];
        for c in &mut cuts[1..3] {
            *c = c.clamp(xa, xa + h);
        }
        cuts.sort_by(f64::total_cmp);
        let (mut l2, mut h1) = (0.0, 0.0);
        for piece in cuts.windows(2) {
            let len = piece[1] - piece[0];
            for &(q, w) in &self.rule {
                let x = piece[0] + q * len;
                let (uh, duh) = self.eval_in(u, e, (x - xa) / h);
                let (ue, sigma, _) = ex.field(x, t);
                l2 += w * len * (uh - ue).powi(2);
                h1 += w * len * (duh - sigma / ex.young()).powi(2);
            }
        }
        (l2, h1)
    }
}

/// The exact `u(·, t)` as the linear function it is on each of the (up to three) intervals
/// between 0, the two kinks and L: `(right end, value at 0 of the line, slope)`.
fn linear_pieces(ex: &dyn PiecewiseLinearBar, t: f64, kinks: [f64; 2]) -> Vec<(f64, f64, f64)> {
    let ends = [kinks[0], kinks[1], ex.length()];
    crate::exact::lines_between(ends, ex.young(), |x| {
        let (u, sigma, _) = ex.field(x, t);
        (u, sigma)
    })
}

/// The reference forms of a P_p segment of length h, `m = h M̂` and `k = K̂ / h` in local node
/// order (left to right), padded to 3 × 3: for the P_p function with nodal values e on the
/// segment, `‖e‖²_{L²} = eᵀ m e` and `|e|²_{H¹} = eᵀ k e`.
pub(super) struct SegmentNorms {
    m: [[f64; 3]; 3],
    k: [[f64; 3]; 3],
}

impl SegmentNorms {
    pub(super) fn new(degree: usize, h: f64) -> Self {
        let el = Segment { degree };
        let pad = |m: nalgebra::DMatrix<f64>| {
            let mut a = [[0.0; 3]; 3];
            for (i, row) in a.iter_mut().enumerate().take(m.nrows()) {
                for (j, x) in row.iter_mut().enumerate().take(m.ncols()) {
                    *x = m[(i, j)];
                }
            }
            a
        };
        Self {
            m: pad(segment_mass(el, h, 1.0)),
            k: pad(segment_stiffness(el, h, 1.0)),
        }
    }

    /// `(eᵀ m e, eᵀ k e)` for the nodal values e of one element (p + 1 ≤ 3 of them).
    pub(super) fn sums(&self, e: &[f64]) -> (f64, f64) {
        let (mut l2, mut h1) = (0.0, 0.0);
        for (i, ei) in e.iter().enumerate() {
            for (j, ej) in e.iter().enumerate() {
                l2 += self.m[i][j] * ei * ej;
                h1 += self.k[i][j] * ei * ej;
            }
        }
        (l2, h1)
    }

    /// `Σ_K (eᵀ m e, eᵀ k e)` over the elements of `nodes` nodes (nodes − 1 = degree) whose
    /// nodal values are consecutive windows of `err`.
    fn over_windows(&self, err: &[f64], nodes: usize) -> (f64, f64) {
        err.windows(nodes)
            .step_by(nodes - 1)
            .map(|w| self.sums(w))
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y))
    }
}

impl FieldError for BarFieldError<'_> {
    fn errors(&self, u: &[f64], t: f64) -> (f64, f64) {
        let ex = self.exact;
        let (p, h, n_el) = self.layout();
        let kinks = ex.kinks(t);
        let pieces = linear_pieces(ex, t, kinks);
        let mut piece = 0;
        let mut exact_at = |x: f64| {
            while x > pieces[piece].0 && piece < 2 {
                piece += 1;
            }
            pieces[piece].1 + pieces[piece].2 * x
        };
        let h_node = h / p as f64;
        let nodal_error: Vec<f64> = (0..=p * n_el)
            .map(|i| self.nodal(u, i) - exact_at(i as f64 * h_node))
            .collect();
        let norms = &self.reference;
        let (mut l2, mut h1) = norms.over_windows(&nodal_error, p + 1);
        // The elements cut by a kink: their nodal sums replaced by the piecewise rule.
        for e in crate::util::unique(kinks.map(|c| (c / h).floor() as usize)) {
            if e >= n_el {
                continue;
            }
            let xa = e as f64 * h;
            if !kinks.iter().any(|&c| c > xa && c < xa + h) {
                continue;
            }
            let (nm, nk) = norms.sums(&nodal_error[p * e..=p * e + p]);
            let (a, b) = self.by_quadrature(u, e, t, kinks);
            l2 += a - nm;
            h1 += b - nk;
        }
        (l2.sqrt(), h1.sqrt())
    }
}
