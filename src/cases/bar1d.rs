//! `bar1d`: the Doyen–Ern–Piperno bar impact (`shared/reference/bar_impact.md`).
//!
//! Bar (0, L) of unit cross-section, clamped at x = L, unilateral contact at x = 0 with a rigid
//! obstacle at the end's reference position: `g = u(0, t) ≥ 0`. Initial state `u₀ = a (1 − x/L)`,
//! `v₀ = 0`. Units: whatever consistent system the file states (the canonical file is
//! non-dimensional, E = ρ = L = 1).

use super::{Case, FieldError, Overrides, RunSpec};
use crate::error::{positive, Error, Result};
use crate::exact::bar_impact::BarImpact;
use crate::exact::ExactContact;
use crate::fem::assembly::{segment_mass, segment_mixed_mass, segment_stiffness};
use crate::fem::lagrange1d::Lagrange1d;
use crate::fem::quadrature::gauss_legendre_01;
use crate::fem::segment::Segment;
use crate::linalg::TripletBuilder;
use crate::mesh::interval::IntervalMesh;
use crate::problem::{Contact, Probe, Problem};
use crate::space::{ElementMass, ElementMixed, MassModel, Space};
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
    /// Displacement space (clamped at x = L unless `clamped` is false).
    pub space: Lagrange1d,
    run: RunSpec,
    sweeps: Vec<super::sweep::SweepSpec>,
}

impl Bar1d {
    /// Validates the spec, applies the overrides and builds the FE space.
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
        let mesh = IntervalMesh::new(exact.length, elements)?;
        let fixed: &[f64] = if clamped { &[exact.length] } else { &[] };
        Ok(Self {
            exact,
            space: Lagrange1d::new(mesh, degree, fixed),
            run,
            sweeps: Vec::new(),
        })
    }

    /// Element data for the spaces: consistent P_p masses and, for P2, the P1 velocity space.
    pub fn mass_model(&self) -> MassModel {
        let s = &self.space;
        let (h, rho) = (s.mesh.h(), self.exact.density);
        let local = segment_mass(s.element, h, rho);
        let n_el = s.mesh.n_elements;
        let elements = (0..n_el)
            .map(|e| ElementMass {
                x: s.element_nodes(e)
                    .map(|i| [s.node_x(i), 0.0, 0.0])
                    .collect(),
                mass: local.clone(),
                dofs: vec![s.element_dofs(e)],
            })
            .collect();
        let velocity = (s.element.degree == 2).then(|| {
            let p1 = Segment { degree: 1 };
            let c = segment_mass(p1, h, rho);
            let b = segment_mixed_mass(p1, s.element, h, rho);
            let mixed = (0..n_el)
                .map(|e| ElementMixed {
                    c: c.clone(),
                    b: b.clone(),
                    vdofs: vec![vec![e, e + 1]],
                })
                .collect();
            (mixed, n_el + 1)
        });
        MassModel {
            n_dofs: s.n_dofs,
            dim: 1,
            elements,
            contact_dofs: self.contact_dof().into_iter().collect(),
            velocity,
        }
    }

    /// The dof of u(0) (the contact end).
    fn contact_dof(&self) -> Option<usize> {
        self.space.dof_of_node[0]
    }
}

impl Case for Bar1d {
    fn kind(&self) -> &'static str {
        "bar1d"
    }

    fn h(&self) -> f64 {
        self.space.mesh.h()
    }

    fn problem(&self, space: &dyn Space) -> Result<Problem> {
        let s = &self.space;
        let n = s.n_dofs;
        let c0 = self
            .contact_dof()
            .ok_or_else(|| Error::Unsupported("bar1d: the contact end is clamped".into()))?;
        let young = self.exact.young;
        let k = s.assemble(|_| segment_stiffness(s.element, s.mesh.h(), young))?;
        let inertia = space.inertia(&self.mass_model())?;
        // Outward normal at x = 0 is −e_x: u_N = −u(0), g = 0 − B_N U = u(0).
        let mut b_n = TripletBuilder::new(1, n);
        b_n.add(0, c0, -1.0);
        let mut u0 = vec![0.0; n];
        for (i, d) in s.dof_of_node.iter().enumerate() {
            if let Some(d) = d {
                u0[*d] = self.exact.field(s.node_x(i), 0.0).0;
            }
        }
        Ok(Problem {
            inertia,
            k,
            f: vec![0.0; n],
            contact: Contact {
                b_n: b_n.build()?,
                g0: vec![0.0],
                area: vec![1.0],
            },
            u0,
            v0: vec![0.0; n],
            probe: Probe {
                contact: 0,
                u_dof: c0,
                w_dof: 0,
            },
            energy_shift: 0.0,
        })
    }

    fn exact(&self) -> Option<&dyn ExactContact> {
        Some(&self.exact)
    }

    fn field_error(&self) -> Option<Box<dyn FieldError + '_>> {
        Some(Box::new(BarFieldError {
            bar: self,
            rule: gauss_legendre_01(3),
        }))
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

/// L² and H¹-seminorm errors of a P_p field against the exact bar solution. Each element is split
/// at the characteristics x = sL, (1 − s)L of the current phase, where the exact solution has kinks,
/// so the 3-point Gauss rule is exact on every piece (integrand of degree ≤ 4).
struct BarFieldError<'a> {
    bar: &'a Bar1d,
    rule: Vec<(f64, f64)>,
}

impl FieldError for BarFieldError<'_> {
    fn errors(&self, u: &[f64], t: f64) -> (f64, f64) {
        let s = &self.bar.space;
        let ex = &self.bar.exact;
        let (l, h) = (ex.length, s.mesh.h());
        let frac = (ex.wave_speed() * t / l).rem_euclid(3.0).fract();
        let kinks = [frac * l, (1.0 - frac) * l];
        let (mut l2, mut h1) = (0.0, 0.0);
        for e in 0..s.mesh.n_elements {
            let (xa, xb) = (s.mesh.x_left(e), s.mesh.x_left(e) + h);
            let mut cuts = vec![xa, xb];
            cuts.extend(kinks.iter().copied().filter(|&k| k > xa && k < xb));
            cuts.sort_by(f64::total_cmp);
            for piece in cuts.windows(2) {
                let len = piece[1] - piece[0];
                for &(q, w) in &self.rule {
                    let x = piece[0] + q * len;
                    let (uh, duh) = s.eval_in(u, e, (x - xa) / h);
                    let (ue, sigma, _) = ex.field(x, t);
                    l2 += w * len * (uh - ue).powi(2);
                    h1 += w * len * (duh - sigma / ex.young).powi(2);
                }
            }
        }
        (l2.sqrt(), h1.sqrt())
    }
}
