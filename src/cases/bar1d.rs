//! `bar1d`: the Doyen–Ern–Piperno bar impact (`shared/reference/bar_impact.md`).
//!
//! Bar (0, L) of unit cross-section, clamped at x = L, unilateral contact at x = 0 with a rigid
//! obstacle at the end's reference position: `g = u(0, t) ≥ 0`. Initial state `u₀ = a (1 − x/L)`,
//! `v₀ = 0`. Units: whatever consistent system the file states (the canonical file is
//! non-dimensional, E = ρ = L = 1).

use super::{Case, FieldError, Overrides, RunSpec};
use crate::element::quadrature::gauss_legendre_01;
use crate::element::segment::Segment;
use crate::error::{positive, Error, Result};
use crate::exact::bar_impact::BarImpact;
use crate::exact::ExactContact;
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

/// `[geometry]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// Length L.
    pub length: f64,
    /// Initial lift a = u₀(0) (≥ 0).
    pub lift: f64,
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
        let degree = o.degree.unwrap_or(spec.mesh.degree);
        if !(1..=2).contains(&degree) {
            return Err(Error::invalid("mesh.degree", degree, "must be 1 or 2"));
        }
        let elements = o.elements.unwrap_or(spec.mesh.elements);
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
        // K, M and the step matrix (≤ 2p + 1 entries per row, 16 B each), and the vectors.
        let dofs = (elements * degree) as f64;
        crate::util::check_memory("mesh.elements", elements, dofs * (3.0 * 5.0 * 16.0 + 200.0))?;
        let mesh = interval(exact.length, elements, degree)?;
        // ν = 0: λ = 0, 2μ = E exactly.
        let lame = Lame {
            lambda: 0.0,
            mu: 0.5 * exact.young,
        };
        let fem = Discretisation::new(mesh, lame, exact.density, ContactRule::Facing(FACING))?;
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

    /// The degree p, the element length h and the number of elements.
    fn layout(&self) -> (usize, f64, usize) {
        let mesh = &self.fem.mesh;
        (mesh.element.degree, mesh.h, mesh.connectivity.len())
    }

    /// Value of the free-dof vector `u` at node `i` (0 at the clamped node).
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
        Some(Box::new(BarFieldError::new(self)))
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

/// L² and H¹-seminorm errors of a P_p field against the exact bar solution, exact per element.
///
/// At time t the exact `u(·, t)` is linear in x between the characteristics x = sL, (1 − s)L of
/// the current phase. On an element K that no characteristic cuts, `u_h − u` is therefore the
/// P_p function with nodal values `e_k = u_h(x_k) − u(x_k, t)`, and
/// `‖u_h − u‖²_{L²(K)} = h eᵀ M̂ e`, `|u_h − u|²_{H¹(K)} = eᵀ K̂ e / h` with the reference mass
/// `M̂_ij = ∫₀¹ φ̂_i φ̂_j` and stiffness `K̂_ij = ∫₀¹ φ̂_i' φ̂_j'`. The (at most two) cut elements
/// are split at the characteristics and integrated with the 3-point Gauss rule, exact on every
/// piece (integrand of degree ≤ 4). Cost O(n) per sample with no allocation but one node buffer.
struct BarFieldError<'a> {
    bar: &'a Bar1d,
    rule: Vec<(f64, f64)>,
    /// `(h M̂, K̂ / h)` in local node order (left to right), padded to 3 × 3.
    reference: ([[f64; 3]; 3], [[f64; 3]; 3]),
}

impl<'a> BarFieldError<'a> {
    fn new(bar: &'a Bar1d) -> Self {
        let (p, h, _) = bar.layout();
        let el = Segment { degree: p };
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
            bar,
            rule: gauss_legendre_01(3),
            reference: (
                pad(segment_mass(el, h, 1.0)),
                pad(segment_stiffness(el, h, 1.0)),
            ),
        }
    }

    /// `∫_K (u_h − u)²` and `∫_K (u_h' − u')²` on element `e` by Gauss on its pieces between
    /// the characteristics `kinks`.
    fn by_quadrature(&self, u: &[f64], e: usize, t: f64, kinks: [f64; 2]) -> (f64, f64) {
        let ex = &self.bar.exact;
        let (_, h, _) = self.bar.layout();
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
                let (uh, duh) = self.bar.eval_in(u, e, (x - xa) / h);
                let (ue, sigma, _) = ex.field(x, t);
                l2 += w * len * (uh - ue).powi(2);
                h1 += w * len * (duh - sigma / ex.young).powi(2);
            }
        }
        (l2, h1)
    }
}

/// The exact `u(·, t)` as the linear function it is on each of the (up to three) intervals
/// between 0, the two characteristics and L: `(right end, value at 0 of the line, slope)`.
fn linear_pieces(ex: &BarImpact, t: f64, kinks: [f64; 2]) -> [(f64, f64, f64); 3] {
    let l = ex.length;
    let ends = [kinks[0], kinks[1], l];
    let mut left = 0.0;
    ends.map(|right| {
        let mid = 0.5 * (left + right);
        let (u, sigma, _) = ex.field(mid, t);
        let slope = sigma / ex.young;
        left = right;
        (right, u - slope * mid, slope)
    })
}

/// `Σ_K (eᵀ m e, eᵀ k e)` over the elements of N nodes (N − 1 = degree) whose nodal values are
/// consecutive windows of `err` (m = h M̂, k = K̂ / h).
fn nodal_sums<const N: usize>(err: &[f64], m: &[[f64; 3]; 3], k: &[[f64; 3]; 3]) -> (f64, f64) {
    let (mut l2, mut h1) = (0.0, 0.0);
    for w in err.windows(N).step_by(N - 1) {
        let e: [f64; N] = w.try_into().unwrap_or([0.0; N]);
        for i in 0..N {
            for j in 0..N {
                l2 += m[i][j] * e[i] * e[j];
                h1 += k[i][j] * e[i] * e[j];
            }
        }
    }
    (l2, h1)
}

impl FieldError for BarFieldError<'_> {
    fn errors(&self, u: &[f64], t: f64) -> (f64, f64) {
        let ex = &self.bar.exact;
        let (p, h, n_el) = self.bar.layout();
        let l = ex.length;
        let frac = (ex.wave_speed() * t / l).rem_euclid(3.0).fract();
        let mut kinks = [frac * l, (1.0 - frac) * l];
        kinks.sort_by(f64::total_cmp);
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
            .map(|i| self.bar.nodal(u, i) - exact_at(i as f64 * h_node))
            .collect();
        let (m, k) = &self.reference;
        let (mut l2, mut h1) = match p {
            1 => nodal_sums::<2>(&nodal_error, m, k),
            _ => nodal_sums::<3>(&nodal_error, m, k),
        };
        // The elements cut by a characteristic: their nodal sums replaced by the piecewise rule.
        for e in crate::util::unique(kinks.map(|c| (c / h).floor() as usize)) {
            if e >= n_el {
                continue;
            }
            let xa = e as f64 * h;
            if !kinks.iter().any(|&c| c > xa && c < xa + h) {
                continue;
            }
            let (nm, nk) = match p {
                1 => nodal_sums::<2>(&nodal_error[e..e + 2], m, k),
                _ => nodal_sums::<3>(&nodal_error[2 * e..2 * e + 3], m, k),
            };
            let (a, b) = self.by_quadrature(u, e, t, kinks);
            l2 += a - nm;
            h1 += b - nk;
        }
        (l2.sqrt(), h1.sqrt())
    }
}
