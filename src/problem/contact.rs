//! The contact rows of the semi-discrete problem: `g = g₀ − B_N U` at the contact points, their
//! tributary areas (`σ_N = −λ/area`), the faces of Γ_C and its boundary quadrature.

use crate::error::{Error, Result};
use crate::linalg::{self, SpMat, TripletBuilder};
use std::borrow::Cow;

/// Contact points: `g = g₀ − B_N U`, tributary areas for the stress `σ_N = −λ/area`.
///
/// A case builds the nodal rows (one per vertex of Γ_C) and the faces of Γ_C; a contact
/// formulation ([`crate::contact::Formulation`]) may replace the rows (weak multipliers).
#[derive(Debug, Clone)]
pub struct Contact {
    /// `B_N` (n_c × n): normal displacement (outward normal) at each contact point.
    pub b_n: SpMat,
    /// Initial gaps g₀.
    pub g0: Vec<f64>,
    /// Tributary length/area of each contact point (1 for a bar of unit section or a point mass).
    pub area: Vec<f64>,
    /// The faces of Γ_C on the vertex rows (a point for a 1D or 0D case).
    pub faces: Vec<ContactFace>,
    /// When the rows are not the vertices of Γ_C (P0 multipliers): how their forces spread to
    /// the vertices; None when row i is vertex i.
    pub vertices: Option<VertexMap>,
    /// Quadrature points of Γ_C for boundary integrals, or why the case provides none.
    pub quadrature: std::result::Result<Vec<BoundaryPoint>, NoQuadrature>,
    /// The rows whose transpose applies the contact force (`−Qᵀ λ`) when they are not `B_N`
    /// (Nitsche's `Q`); the Delassus operator `c B_N A⁻¹ Qᵀ` is then not symmetric.
    pub force: Option<SpMat>,
    /// The rows `U ↦ u_N(x_i)` of the physical gap `g₀_i − u_N(x_i)` when the rows of `B_N` are
    /// not (Nitsche's law rows `u_N − γ σ_N`).
    pub normal: Option<Vec<Vec<(usize, f64)>>>,
    /// Energy stored in the contact rows, part of the conserved energy (Nitsche's boundary
    /// energy).
    pub energy: Vec<ContactEnergy>,
    /// Coulomb friction at the contact points (None: frictionless).
    pub friction: Option<Friction>,
}

/// Coulomb friction with coefficient μ at the contact points (vertices, weak multipliers or
/// Nitsche's quadrature points): the tangential rows `B_T` (n_c·(d − 1) × n, point-major: row
/// `i (d − 1) + k` is the displacement of point i along the tangent t_k of the plane) beside
/// the normal rows `B_N`. The reaction `r_T` of point i acts
/// on the body as `+B_Tᵀ r_T` and obeys `|r_T| ≤ μ λ_N`, `r_T = −μ λ_N s/|s|` when its slip
/// `s ≠ 0` (the slip each scheme measures is said in its file).
#[derive(Debug, Clone)]
pub struct Friction {
    /// Friction coefficient μ > 0.
    pub mu: f64,
    /// `B_T`.
    pub b_t: SpMat,
    /// Tangents per point, d − 1.
    pub tangents: usize,
    /// The last points that are frictionless (μ = 0: their `r_T` vanishes), e.g. a
    /// frictionless rigid plane under a pair whose interface has friction (0: none).
    pub frictionless: usize,
    /// The unit translation of the body along the first tangent (dof layout of U): the
    /// centre of mass's tangential velocity is `(M̃1)ᵀV / 1ᵀM̃1`.
    pub translation: Vec<f64>,
    /// The rows whose transpose applies the tangential force (`+Q_Tᵀ r_T`) when they are not
    /// `B_T` (Nitsche's `Q_T = B_T − θ γ S_T`).
    pub force: Option<SpMat>,
    /// The rows `U ↦ u_T(x_i)` of the physical slip when the rows of `B_T` are not (Nitsche's
    /// law rows `u_T − γ σ_T`).
    pub slip: Option<SpMat>,
}

impl Friction {
    /// μ on every point of `b_t` (none frictionless), `tangents` per point, the centre of mass's
    /// tangential velocity along `translation`.
    pub fn new(mu: f64, b_t: SpMat, tangents: usize, translation: Vec<f64>) -> Self {
        Self {
            mu,
            b_t,
            tangents,
            frictionless: 0,
            translation,
            force: None,
            slip: None,
        }
    }

    /// The rows of the tangential force: `B_T`, or Nitsche's `Q_T`.
    pub fn force_rows(&self) -> &SpMat {
        self.force.as_ref().unwrap_or(&self.b_t)
    }

    /// The rows of the physical slip: `B_T`, or Nitsche's `u_T` rows.
    pub fn slip_rows(&self) -> &SpMat {
        self.slip.as_ref().unwrap_or(&self.b_t)
    }
}

/// Why a contact has no boundary quadrature ([`Contact::quadrature`]), which Nitsche's method
/// integrates σ_N over: a formulation that needs one refuses the case for its own reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoQuadrature {
    /// A point mass: no Γ_C to integrate over.
    PointMass,
    /// Contact between two bodies (node-to-node or node-to-segment rows, a second body's plane
    /// appended): integrals over their interface are not implemented.
    TwoBodies,
    /// A formulation took the points already (it replaced the rows: a bug to ask again).
    Taken,
}

/// A quadrature point `x_q` of Γ_C for boundary integrals (Nitsche's method,
/// [`crate::contact::nitsche`]): `∫_{Γ_C} f ≈ Σ_q w_q f(x_q)`.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryPoint {
    /// `w_q`: the quadrature weight times the face's measure element at x_q.
    pub weight: f64,
    /// Initial gap `g₀(x_q)`: signed distance to the plane.
    pub g0: f64,
    /// Row `U ↦ u_N(x_q)`, the displacement along the plane's outward normal (as `B_N`).
    pub u_n: Vec<(usize, f64)>,
    /// Row `U ↦ σ_N(U)(x_q) = n·σ(U)n`, the stress of the cell x_q lies in.
    pub sigma_n: Vec<(usize, f64)>,
    /// Rows `U ↦ u·t_k(x_q)`, the displacement along the plane's tangents t_k (as `B_T`;
    /// d − 1 of them, none at a 1D end point).
    pub u_t: Vec<Vec<(usize, f64)>>,
    /// Rows `U ↦ σ_{T,k}(U)(x_q) = t_k·σ(U)n`, the shear stress along each tangent.
    pub sigma_t: Vec<Vec<(usize, f64)>>,
    /// Local mesh size over Young's modulus (Nitsche's `γ = h / (γ₀ E)`).
    pub h_over_e: f64,
    /// The vertex rows of its face with their degree-1 hat functions at x_q (shares summing to 1).
    pub vertices: Vec<(usize, f64)>,
}

/// One contact point's stored energy `a Σ_k (s_k · U)² + b [r · U − g₀]₊²` (Nitsche's boundary
/// term: `s = S_i` and, with friction, the shear rows `S_{T,i}`; `r = (B_N − γS)_i`).
#[derive(Debug, Clone)]
pub struct ContactEnergy {
    /// Rows s_k.
    pub s: Vec<Vec<(usize, f64)>>,
    /// Row r.
    pub r: Vec<(usize, f64)>,
    /// g₀_i.
    pub g0: f64,
    /// Coefficient of `Σ_k (s_k U)²`.
    pub a: f64,
    /// Coefficient of the positive part squared.
    pub b: f64,
}

impl ContactEnergy {
    /// Its value at U.
    pub fn eval(&self, u: &[f64]) -> f64 {
        let dot = |row: &[(usize, f64)]| crate::linalg::row_dot(row, u);
        let p = (dot(&self.r) - self.g0).max(0.0);
        self.a * self.s.iter().map(|s| dot(s).powi(2)).sum::<f64>() + self.b * p * p
    }
}

/// A face of Γ_C in terms of the vertex rows it joins: `mass[a·k + b] = ∫_F ψ_a ψ_b` of the
/// degree-1 hat functions of its k vertices (a point: k = 1, `[1]`).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactFace {
    /// Vertex rows of the face.
    pub rows: Vec<usize>,
    /// Its P1 mass matrix, row-major.
    pub mass: Vec<f64>,
}

impl ContactFace {
    /// A point of Γ_C (1D end point, point mass): `∫ψ ψ = 1`.
    pub fn point(row: usize) -> Self {
        Self {
            rows: vec![row],
            mass: vec![1.0],
        }
    }
}

/// How contact rows that are not vertices spread to the vertices of Γ_C.
#[derive(Debug, Clone)]
pub struct VertexMap {
    /// Per row, `(vertex, share)` with shares summing to 1.
    pub shares: Vec<Vec<(usize, f64)>>,
    /// The vertices' tributary areas.
    pub area: Vec<f64>,
}

impl Contact {
    /// The boundary quadrature of Γ_C, taken out of the contact (a formulation that replaces
    /// the rows by its own), or why there is none.
    pub fn take_quadrature(&mut self) -> std::result::Result<Vec<BoundaryPoint>, NoQuadrature> {
        std::mem::replace(&mut self.quadrature, Err(NoQuadrature::Taken))
    }

    /// The rows whose transpose applies the contact force (`−Qᵀ λ`): B_N, or Nitsche's Q.
    pub fn force_rows(&self) -> &SpMat {
        self.force.as_ref().unwrap_or(&self.b_n)
    }

    /// The contact forces per vertex of Γ_C and the vertices' areas (λ and `area` themselves when
    /// the rows are the vertices).
    pub fn vertex_forces<'a>(&'a self, lambda: &'a [f64]) -> (Cow<'a, [f64]>, &'a [f64]) {
        match &self.vertices {
            None => (Cow::Borrowed(lambda), &self.area),
            Some(map) => {
                let mut f = vec![0.0; map.area.len()];
                for (l, row) in lambda.iter().zip(&map.shares) {
                    for &(v, w) in row {
                        f[v] += w * l;
                    }
                }
                (Cow::Owned(f), &map.area)
            }
        }
    }
}

/// `[a; b]`, b's columns shifted by `offset`.
fn stack(a: &SpMat, b: &SpMat, offset: usize) -> Result<SpMat> {
    let mut t = TripletBuilder::new(a.nrows() + b.nrows(), a.ncols());
    t.add_scaled(0, 0, 1.0, a);
    t.add_scaled(a.nrows(), offset, 1.0, b);
    t.build()
}

impl Contact {
    /// Appends the nodal rows of `other`, a contact of a body whose dofs start at `offset` (a
    /// second body's rigid plane): its rows of `B_N`, g₀, areas and faces follow these; the
    /// boundary quadrature (of one Γ_C, for Nitsche's method) is dropped
    /// ([`NoQuadrature::TwoBodies`]). Friction with frictionless appended points
    /// ([`Friction::frictionless`]): `other`'s `B_T`, or refused when it has none.
    pub fn append(&mut self, other: &Contact, offset: usize) -> Result<()> {
        let plain = |c: &Contact| {
            c.vertices.is_none() && c.force.is_none() && c.normal.is_none() && c.energy.is_empty()
        };
        if !plain(self) || !plain(other) {
            return Err(Error::Internal(
                "only nodal contact rows are appended".into(),
            ));
        }
        let n = self.len();
        self.b_n = stack(&self.b_n, &other.b_n, offset)?;
        self.g0.extend(&other.g0);
        self.area.extend(&other.area);
        self.faces.extend(other.faces.iter().map(|f| ContactFace {
            rows: f.rows.iter().map(|r| r + n).collect(),
            mass: f.mass.clone(),
        }));
        self.quadrature = Err(NoQuadrature::TwoBodies);
        if let Some(f) = self.friction.as_mut() {
            let Some(o) = &other.friction else {
                return Err(Error::Internal(
                    "appended contact rows without tangential rows under friction".into(),
                ));
            };
            f.b_t = stack(&f.b_t, &o.b_t, offset)?;
            f.frictionless += other.len();
        }
        Ok(())
    }

    /// Number of contact points n_c.
    pub fn len(&self) -> usize {
        self.g0.len()
    }

    /// True when there is no contact point.
    pub fn is_empty(&self) -> bool {
        self.g0.is_empty()
    }

    /// Gaps `g = g₀ − B_N U`, written to `out`.
    pub fn gap(&self, u: &[f64], out: &mut [f64]) {
        out.copy_from_slice(&self.g0);
        linalg::mul_add(out, &self.b_n, u, -1.0);
    }

    /// The row of the physical gap `g_i = g₀_i − Σ v u_dof` at contact point `i`: row `i` of
    /// [`Contact::normal`] when set, of `B_N` otherwise.
    pub fn gap_row(&self, i: usize) -> Vec<(usize, f64)> {
        match &self.normal {
            Some(rows) => rows[i].clone(),
            None => self.row(i),
        }
    }

    /// Row `i` of `B_N` as `(dof, value)` pairs (a pass over B_N: extract once, then
    /// `g_i = g₀_i − Σ v u_dof` costs the row's length).
    pub fn row(&self, i: usize) -> Vec<(usize, f64)> {
        linalg::triplets(&self.b_n)
            .filter(|&(r, _, _)| r == i)
            .map(|(_, j, v)| (j, v))
            .collect()
    }
}
