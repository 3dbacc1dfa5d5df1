//! Weak (integral) contact: `∫_{Γ_C} μ (g − u·n) ≥ 0` for every `μ ≥ 0` of a multiplier space
//! on Γ_C, with the contact pressure λ in that space and `∫_{Γ_C} λ (g − u·n) = 0`
//! (Hild & Renard; GetFEM's integral contact brick).
//!
//! On the straight faces of Γ_C, with `u·n` and g interpolated at the vertices by the degree-1
//! hat functions ψ_j (the displacement's vertex trace, as for the nodal contact), row i of the
//! constraint is `Σ_j S_ij (g₀_j − (B_N U)_j) ≥ 0` on the nodal rows, with
//! - `p1` (vertex multipliers): `S_ij = ∫ψ_i ψ_j / ∫ψ_i` (the Γ_C mass, row-normalised);
//! - `p0` (face multipliers): `S_Fj = ∫_F ψ_j / |F|`.
//!
//! Each row is scaled by its measure `a_i = ∫ψ_i` (p1) or `|F|` (p0), which does not change the
//! complementarity solution, so that the unknown is the row's force `a_i p_i` (its sum is the total
//! force, as for the nodal rows) and `σ_N = −λ_i / a_i` is the multiplier itself: P1 at the
//! vertices, P0 per face. The Delassus matrix `S D_nodal Sᵀ` is no longer diagonal-dominant in the
//! contact rows. In 1D (Γ_C a point) both coincide with the nodal contact.
//!
//! Coulomb friction: the tangential multipliers live on the same space, rows `S B_T` per tangent,
//! and Coulomb's law holds per multiplier, `|r_{T,i}| ≤ μ λ_i` against the multiplier's slip
//! `Σ_j S_ij Δs_j` (`S` sums to 1 per row, so the total tangential force is `Σ_i r_{T,i}`, as for
//! the nodal rows).

use super::{Formulation, Solver};
use crate::error::{Error, Result};
use crate::linalg::{self, TripletBuilder};
use crate::param::{Entry, Options};
use crate::problem::{Problem, VertexMap};

/// Registry entry: `weak`, with `contact_multiplier` p1 (default) or p0.
pub const ENTRY: Entry<dyn Formulation, Options> = Entry {
    name: "weak",
    params: &[],
    build: |o| Ok(Box::new(Weak::new(o.contact_multiplier.as_deref())?)),
};

/// Multiplier spaces accepted by `contact_multiplier`.
pub const MULTIPLIERS: &[&str] = &["p1", "p0"];

/// The multiplier space on Γ_C.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Multiplier {
    /// Continuous, degree 1: one multiplier per vertex.
    P1,
    /// Piecewise constant: one multiplier per face.
    P0,
}

/// Weak contact with multiplier space P1 or P0.
#[derive(Debug, Clone, Copy)]
pub struct Weak {
    /// The multiplier space.
    pub multiplier: Multiplier,
}

impl Weak {
    /// The multiplier called `name` (`p1` when None).
    pub fn new(name: Option<&str>) -> Result<Self> {
        let multiplier = match name.unwrap_or("p1") {
            "p1" => Multiplier::P1,
            "p0" => Multiplier::P0,
            other => {
                return Err(Error::UnknownName {
                    kind: "contact multiplier",
                    name: other.to_string(),
                    known: MULTIPLIERS.join(", "),
                })
            }
        };
        Ok(Self { multiplier })
    }

    /// Rows of `S` (see the module documentation) with their measures.
    fn rows(&self, problem: &Problem) -> (Vec<Vec<(usize, f64)>>, Vec<f64>) {
        let faces = &problem.contact.faces;
        let n_c = problem.contact.len();
        let mut rows: Vec<Vec<(usize, f64)>> = Vec::new();
        let mut measure = Vec::new();
        match self.multiplier {
            Multiplier::P1 => {
                rows.resize(n_c, Vec::new());
                for f in faces {
                    let k = f.rows.len();
                    for (a, &i) in f.rows.iter().enumerate() {
                        for (b, &j) in f.rows.iter().enumerate() {
                            rows[i].push((j, f.mass[a * k + b]));
                        }
                    }
                }
                for r in &mut rows {
                    r.sort_unstable_by_key(|e| e.0);
                    r.dedup_by(|e, kept| {
                        let same = e.0 == kept.0;
                        if same {
                            kept.1 += e.1;
                        }
                        same
                    });
                    measure.push(r.iter().map(|e| e.1).sum::<f64>());
                }
            }
            Multiplier::P0 => {
                for f in faces {
                    let k = f.rows.len();
                    let row: Vec<(usize, f64)> = f
                        .rows
                        .iter()
                        .enumerate()
                        .map(|(a, &j)| (j, f.mass[a * k..(a + 1) * k].iter().sum()))
                        .collect();
                    measure.push(row.iter().map(|e| e.1).sum::<f64>());
                    rows.push(row);
                }
            }
        }
        for (r, m) in rows.iter_mut().zip(&measure) {
            for e in r.iter_mut() {
                e.1 /= m;
            }
        }
        (rows, measure)
    }
}

impl Formulation for Weak {
    fn name(&self) -> &'static str {
        "weak"
    }

    fn label(&self) -> String {
        match self.multiplier {
            Multiplier::P1 => "weak_p1".into(),
            Multiplier::P0 => "weak_p0".into(),
        }
    }

    /// Replaces the nodal rows by `S B_N`, `S g₀`, measures `a_i`; with P0 the probe becomes the
    /// face of lowest initial gap among those containing the probe vertex. The law is
    /// Signorini's on the new rows; with Coulomb friction, the tangential rows on the same
    /// multipliers, `S B_T` per tangent ([`tangential`]), and Coulomb's law per multiplier: the
    /// multiplier's slip `Σ_j S_ij Δs_j` against its tangential force.
    fn setup(&self, problem: &mut Problem, solver: &str) -> Result<Box<dyn Solver>> {
        if problem
            .contact
            .friction
            .as_ref()
            .is_some_and(|f| f.frictionless > 0)
        {
            return Err(Error::Unsupported(
                "weak contact with friction on rows of which some are frictionless (a pair on a \
                 plane): the multipliers would mix them; use contact = \"nodal\""
                    .into(),
            ));
        }
        let n_c = problem.contact.len();
        let mut on_a_face = vec![false; n_c];
        for f in &problem.contact.faces {
            f.rows.iter().for_each(|&i| on_a_face[i] = true);
        }
        if let Some(i) = on_a_face.iter().position(|&on| !on) {
            return Err(Error::Unsupported(format!(
                "weak contact: contact point {i} of {n_c} is on no face of Γ_C, which its \
                 multipliers are built on (the node-to-segment rows of two bodies in 2D and 3D \
                 carry no faces); use contact = \"nodal\""
            )));
        }
        let (rows, measure) = self.rows(problem);
        if self.multiplier == Multiplier::P0 && rows.len() > n_c {
            return Err(Error::Unsupported(format!(
                "weak contact with P0 multipliers: Γ_C has {} faces but {n_c} vertices, so the \
                 multipliers are not controlled by the vertex displacements (no inf-sup \
                 stability); use contact_multiplier = \"p1\"",
                rows.len()
            )));
        }
        let contact = &mut problem.contact;
        let nodal = linalg::rows(&contact.b_n);
        let mut b = TripletBuilder::new(rows.len(), contact.b_n.ncols());
        let mut g0: Vec<f64> = Vec::with_capacity(rows.len());
        for (r, row) in rows.iter().enumerate() {
            for &(j, s) in row {
                for &(dof, v) in &nodal[j] {
                    b.add(r, dof, s * v);
                }
            }
            g0.push(row.iter().map(|&(j, s)| s * contact.g0[j]).sum());
        }
        if let Some(f) = contact.friction.as_mut() {
            f.b_t = tangential(&rows, &f.b_t, f.tangents)?;
        }
        if self.multiplier == Multiplier::P0 {
            let probe = problem.probe.contact;
            problem.probe.contact = (0..rows.len())
                .filter(|&r| rows[r].iter().any(|e| e.0 == probe))
                .min_by(|&a, &b| g0[a].total_cmp(&g0[b]))
                .ok_or_else(|| Error::Internal("the probe vertex is on no face of Γ_C".into()))?;
            contact.vertices = Some(VertexMap {
                shares: rows,
                area: contact.area.clone(),
            });
        }
        contact.b_n = b.build()?;
        contact.g0 = g0;
        contact.area = measure;
        super::law(contact, solver)
    }

    fn friction(&self) -> std::result::Result<(), &'static str> {
        Ok(())
    }
}

/// The tangential rows on the multiplier space: row `i (d − 1) + k` is `Σ_j S_ij` times the
/// nodal row `j (d − 1) + k` of `B_T`, the slip of multiplier i along t_k.
fn tangential(
    rows: &[Vec<(usize, f64)>],
    b_t: &crate::linalg::SpMat,
    tangents: usize,
) -> Result<crate::linalg::SpMat> {
    let nodal = linalg::rows(b_t);
    let mut t = TripletBuilder::new(rows.len() * tangents, b_t.ncols());
    for (r, row) in rows.iter().enumerate() {
        for k in 0..tangents {
            for &(j, s) in row {
                for &(dof, v) in &nodal[j * tangents + k] {
                    t.add(r * tangents + k, dof, s * v);
                }
            }
        }
    }
    t.build()
}
