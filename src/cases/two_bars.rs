//! `two_bars`: two free elastic bars meeting end to end (`shared/reference/bar_flight_and_two_bars.md`,
//! exact solution [`crate::exact::two_bars`]).
//!
//! Bar 1 on (−L₁, 0) at +v₀ (the slave), bar 2 on (0, L₂) at −v₀ (the master), unit section, the
//! same material, unstressed and touching at t = 0; one node-to-node contact row at x = 0,
//! `g = u₂(0) − u₁(0) ≥ 0` ([`crate::fem::bodies`]). Bar 1 has `mesh.elements` elements, bar 2
//! `round(elements · L₂/L₁)`. No external force: the momentum `(M̃1)ᵀV` is an invariant.

use super::bar::{Material, MeshSpec, SegmentNorms};
use super::{Case, FieldError, Overrides, RunSpec};
use crate::element::quadrature::gauss_legendre_01;
use crate::element::segment::Segment;
use crate::error::{positive, Error, Result};
use crate::exact::two_bars::TwoBars as Exact;
use crate::exact::ExactContact;
use crate::fem::bodies::Bodies;
use crate::fem::discretisation::{Discretisation, Initial};
use crate::fem::elasticity::Lame;
use crate::mesh::interval::interval;
use crate::mesh::ContactRule;
use crate::problem::Problem;
use crate::space::Space;
use serde::Deserialize;

/// `[geometry]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// L₁, L₂ (a list: serde's `[f64; 2]` let TOML's extra entries pass unread).
    pub lengths: Vec<f64>,
    /// v₀: bar 1 moves at +v₀, bar 2 at −v₀.
    pub velocity: f64,
}

/// The whole `two_bars` case file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TwoBarsSpec {
    /// Always `two_bars`.
    pub case: String,
    /// Units statement.
    pub units: String,
    /// Material of both bars (as bar1d's).
    pub material: Material,
    /// Lengths and velocity.
    pub geometry: Geometry,
    /// Mesh (as bar1d's; `elements` counts bar 1's).
    pub mesh: MeshSpec,
    /// Run defaults.
    pub run: RunSpec,
    /// Sweeps run by `dyncontact sweep` and `report`.
    #[serde(default)]
    pub sweep: Vec<super::sweep::SweepSpec>,
}

/// A validated two-bar case.
#[derive(Debug, Clone)]
pub struct TwoBars {
    /// The exact solution up to the run's final time.
    pub exact: Exact,
    /// Bar 1 (slave) and bar 2 (master).
    pub bodies: Bodies,
    run: RunSpec,
    sweeps: Vec<super::sweep::SweepSpec>,
}

/// `geometry.lengths` `[L₁, L₂]`: exactly two entries, each a [`crate::error::length`].
fn bar_lengths(lengths: &[f64]) -> Result<[f64; 2]> {
    let [l1, l2] = lengths else {
        return Err(Error::invalid(
            "geometry.lengths",
            lengths,
            "needs 2 entries, the lengths L₁ and L₂ of the two bars",
        ));
    };
    crate::error::length("geometry.lengths[0]", *l1)?;
    crate::error::length("geometry.lengths[1]", *l2)?;
    Ok([*l1, *l2])
}

/// The most wave crossings of a bar the exact solution follows (`t_end·c/L`; about 6 s at 10⁵).
pub const MAX_CROSSINGS: f64 = 1e5;

impl TwoBars {
    /// Validates the spec, applies the overrides and builds the discretisations.
    pub fn from_spec(spec: TwoBarsSpec, o: &Overrides) -> Result<Self> {
        let m = &spec.material;
        m.validate()?;
        let [l1, l2] = bar_lengths(&spec.geometry.lengths)?;
        positive("geometry.velocity", spec.geometry.velocity)?;
        let degree = o.degree.unwrap_or(spec.mesh.degree);
        let elements = o.elements.unwrap_or(spec.mesh.elements);
        let mut run = spec.run;
        o.apply(&mut run);
        run.validate()?;
        bar2_elements(elements, degree, [l1, l2])?;
        m.check_time_scale(l1 / elements.max(1) as f64, run.dt)?;
        // The exact solution follows the waves across each bar, t_end·c/L crossings: a bar this
        // short against t_end took minutes (L₂ = 1e-6) or panicked (L₂ ≤ 1e-15) building it.
        let c = (m.young / m.density).sqrt();
        for (k, l) in [l1, l2].into_iter().enumerate() {
            let crossings = run.t_end * c / l;
            if crossings > MAX_CROSSINGS {
                return Err(Error::invalid(
                    format!("geometry.lengths[{k}]"),
                    l,
                    &format!(
                        "the exact solution follows the waves across each bar: t_end·c/L = \
                         {crossings:.3e} crossings of this one, above {MAX_CROSSINGS:e}"
                    ),
                ));
            }
        }
        let exact = Exact::new(
            [l1, l2],
            m.young,
            m.density,
            spec.geometry.velocity,
            run.t_end,
        );
        let mut case = Self::new(exact, elements, degree, run)?;
        case.sweeps = spec.sweep;
        Ok(case)
    }

    /// The bars of the exact solution `exact`, bar 1 with `elements` elements of degree `degree`.
    pub fn new(exact: Exact, elements: usize, degree: usize, run: RunSpec) -> Result<Self> {
        if elements == 0 {
            return Err(Error::invalid("mesh.elements", elements, "must be >= 1"));
        }
        let [l1, l2] = exact.lengths;
        let n2 = bar2_elements(elements, degree, [l1, l2])?;
        // ν = 0: λ = 0, 2μ = E exactly.
        let lame = Lame {
            lambda: 0.0,
            mu: 0.5 * exact.young,
        };
        let bar = |x0: f64, length: f64, n: usize| -> Result<Discretisation> {
            let mut mesh = interval(length, n, degree)?;
            for x in &mut mesh.nodes {
                x[0] += x0;
            }
            // Γ_C: the end at x = 0 (bar 1's last node, bar 2's first).
            let end = if x0 < 0.0 { mesh.nodes.len() - 1 } else { 0 };
            mesh.contact_faces = Some(vec![vec![end]]);
            Discretisation::new(mesh, lame, exact.density, ContactRule::Tagged)
        };
        let bodies = Bodies::new(vec![bar(-l1, l1, elements)?, bar(0.0, l2, n2)?])?;
        Ok(Self {
            exact,
            bodies,
            run,
            sweeps: Vec::new(),
        })
    }

    /// The unit translation along the bars: the momentum is `(M̃ 1)ᵀ V`.
    pub fn translation(&self) -> Vec<f64> {
        self.bodies.translation()
    }
}

/// Bar 2's elements for bar 1's `elements` of the `lengths` (about the same size), once the
/// `degree` (1 or 2) and the memory of both bars' dofs are checked
/// ([`super::bar::check_memory`]; the count in floating point, which a length ratio of 1e30 or
/// a huge degree cannot wrap).
fn bar2_elements(elements: usize, degree: usize, [l1, l2]: [f64; 2]) -> Result<usize> {
    if !(1..=2).contains(&degree) {
        return Err(Error::invalid("mesh.degree", degree, "must be 1 or 2"));
    }
    let n2 = (elements as f64 * l2 / l1).round().max(1.0);
    super::bar::check_memory(elements, (elements as f64 + n2) * degree as f64)?;
    Ok(n2 as usize)
}

impl Case for TwoBars {
    /// `two_bars` for equal lengths, `two_bars_unequal` otherwise (the two canonical files'
    /// runs stay apart in the summaries and the report).
    fn kind(&self) -> &'static str {
        let [l1, l2] = self.exact.lengths;
        if l1 == l2 {
            "two_bars"
        } else {
            "two_bars_unequal"
        }
    }

    /// The larger of the two bars' element lengths.
    fn h(&self) -> f64 {
        self.bodies.h()
    }

    fn element(&self) -> Option<(&'static str, usize)> {
        Some(self.bodies.element())
    }

    fn problem(&self, space: &dyn Space) -> Result<Problem> {
        let v0 = self.exact.speed;
        let initial: Vec<Initial> = self
            .bodies
            .parts
            .iter()
            .zip([v0, -v0])
            .map(|(p, v)| Initial {
                displacement: vec![0.0; p.n_dofs()],
                velocity: vec![v; p.n_dofs()],
                gravity: None,
                lift: 0.0,
            })
            .collect();
        self.bodies.problem(|m| space.inertia(m), &initial)
    }

    fn exact(&self) -> Option<&dyn ExactContact> {
        Some(&self.exact)
    }

    fn field_error(&self) -> Option<Box<dyn FieldError + '_>> {
        let norms = self.bodies.parts.iter();
        Some(Box::new(TwoBarsFieldError {
            case: self,
            rule: gauss_legendre_01(3),
            norms: norms
                .map(|p| SegmentNorms::new(p.mesh.element.degree, 1.0))
                .collect(),
        }))
    }

    fn run(&self) -> &RunSpec {
        &self.run
    }

    fn sweeps(&self) -> &[super::sweep::SweepSpec] {
        &self.sweeps
    }

    fn momentum(&self) -> Option<Vec<f64>> {
        Some(self.translation())
    }

    fn multi_body(&self) -> Option<&Bodies> {
        Some(&self.bodies)
    }
}

/// L² and H¹-seminorm errors of both bars against the exact field, exact per element as for one
/// bar ([`super::bar::BarFieldError`]): the exact u is linear between the fronts
/// ([`Exact::linear_pieces`]), so on an element no front cuts the error is the P_p function of
/// its nodal values (reference forms [`SegmentNorms`]); a cut element is split at the fronts
/// and integrated by 3-point Gauss, exact on every piece.
struct TwoBarsFieldError<'a> {
    case: &'a TwoBars,
    rule: Vec<(f64, f64)>,
    /// Each bar's reference forms on a unit element (scaled by its length, element by element).
    norms: Vec<SegmentNorms>,
}

impl FieldError for TwoBarsFieldError<'_> {
    fn errors(&self, u: &[f64], t: f64) -> (f64, f64) {
        let (bodies, ex) = (&self.case.bodies, &self.case.exact);
        let (mut l2, mut h1) = (0.0, 0.0);
        for (k, fem) in bodies.parts.iter().enumerate() {
            let (o, mesh) = (bodies.offset(k), &fem.mesh);
            let seg = Segment {
                degree: mesh.element.degree,
            };
            // Bar 1's own coordinate is y = −x, bar 2's y = x.
            let sign = if k == 0 { -1.0 } else { 1.0 };
            let pieces = ex.linear_pieces(k, t);
            let last = pieces.len() - 1;
            // u_x and u_x' at x: u_x = sign u_y(sign x), u_x' = u_y'.
            let exact = |x: f64| {
                let y = sign * x;
                let (_, at0, slope) = pieces[pieces.partition_point(|p| p.0 < y).min(last)];
                (sign * (at0 + slope * y), slope)
            };
            let fronts: Vec<f64> = pieces[..last].iter().map(|p| sign * p.0).collect();
            // Buffers reused over the cells (this runs at every step of every two-bar run).
            let (mut nodal, mut cuts) = (Vec::new(), Vec::new());
            for cell in &mesh.connectivity {
                let (xa, xb) = (mesh.nodes[cell[0]][0], mesh.nodes[cell[cell.len() - 1]][0]);
                nodal.clear();
                nodal.extend(
                    cell.iter()
                        .map(|&i| fem.dofs.get(i, 0).map_or(0.0, |d| u[o + d])),
                );
                cuts.clear();
                cuts.extend(fronts.iter().copied().filter(|&f| f > xa && f < xb));
                if cuts.is_empty() {
                    for (e, &i) in nodal.iter_mut().zip(cell) {
                        *e -= exact(mesh.nodes[i][0]).0;
                    }
                    let (a, b) = self.norms[k].sums(&nodal);
                    l2 += (xb - xa) * a;
                    h1 += b / (xb - xa);
                    continue;
                }
                cuts.extend([xa, xb]);
                cuts.sort_by(f64::total_cmp);
                for piece in cuts.windows(2) {
                    let len = piece[1] - piece[0];
                    for &(q, w) in &self.rule {
                        let x = piece[0] + q * len;
                        let xi = (x - xa) / (xb - xa);
                        let (uh, duh) = nodal.iter().enumerate().fold((0.0, 0.0), |acc, (a, v)| {
                            (
                                acc.0 + v * seg.value(a, xi),
                                acc.1 + v * seg.derivative(a, xi) / (xb - xa),
                            )
                        });
                        let (ue, strain) = exact(x);
                        l2 += w * len * (uh - ue).powi(2);
                        h1 += w * len * (duh - strain).powi(2);
                    }
                }
            }
        }
        (l2.sqrt(), h1.sqrt())
    }
}
