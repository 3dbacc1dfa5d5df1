//! The semi-discrete contact problem every scheme consumes (DESIGN.md §1):
//!
//! `M Ü + K U = F − B_Nᵀ λ`,  `g = g₀ − B_N U ≥ 0`,  `λ ≥ 0`,  `λ · g = 0`.
//!
//! Sign convention: `B_N U` is the normal displacement along the body's *outward* normal at the
//! contact points (it closes the gap), `λ` is the contact pressure (nodal force, compression
//! positive) and the obstacle pushes the body with `−B_Nᵀ λ`, which opens the gap. (DESIGN.md §1
//! writes `+B_Nᵀ λ`; with `g = g₀ − B_N U` and `λ ≥ 0` only `−B_Nᵀ λ` does no work on a closing gap.)
//! The normal contact stress reported is `σ_N = −λ / (tributary area)` (≤ 0).

use crate::error::{Error, Result};
use crate::linalg::{self, Factor, SpMat, TripletBuilder};
use std::borrow::Cow;

/// The mass operator as a space produces it (built once per run: variant sizes do not matter).
#[derive(Debug)]
#[allow(clippy::large_enum_variant)]
pub enum Inertia {
    /// A sparse, symmetric, positive semi-definite `M` (consistent, lumped, redistributed, …).
    /// The inertial variables are the displacements themselves: `w = U`.
    Sparse {
        /// The mass matrix M.
        m: SpMat,
    },
    /// Singular dynamic method (Renard 2010): `M = Bᵀ C⁻¹ B`, never formed. The inertial variables
    /// are `w = C⁻¹ B U`, the L²(ρ) projection of U on the velocity space H_h.
    Mixed {
        /// `B_ij = ∫ρ ψ_i φ_j` (rows: H_h dofs, columns: V_h dofs).
        b: SpMat,
        /// `C_ij = ∫ρ ψ_i ψ_j` (H_h mass, SPD).
        c: SpMat,
        /// The consistent V_h mass, used only to start from a consistent initial acceleration.
        consistent: SpMat,
    },
}

impl Inertia {
    /// Number of inertial variables (n for a sparse mass, dim H_h for the mixed one).
    pub fn dim(&self) -> usize {
        match self {
            Inertia::Sparse { m } => m.nrows(),
            Inertia::Mixed { c, .. } => c.nrows(),
        }
    }

    /// Inertial variables of a displacement field: `w = U` or `w = C⁻¹ B U`.
    pub fn project(&self, u: &[f64]) -> Result<Vec<f64>> {
        match self {
            Inertia::Sparse { .. } => Ok(u.to_vec()),
            Inertia::Mixed { b, c, .. } => {
                let mut w = linalg::mul(b, u);
                Factor::cholesky(c, "velocity-space mass C")?.solve_in_place(&mut w);
                Ok(w)
            }
        }
    }

    /// `out += alpha · Lᵀ y` with `L = M` (sparse) or `L = B` (mixed): the inertial force of the
    /// inertial vector `y`, as a force on the displacement dofs.
    pub fn apply_add(&self, out: &mut [f64], y: &[f64], alpha: f64) {
        match self {
            // M is symmetric: the gather form `Mᵀ y` has no scattered stores.
            Inertia::Sparse { m } => linalg::mul_t_add(out, m, y, alpha),
            Inertia::Mixed { b, .. } => linalg::mul_t_add(out, b, y, alpha),
        }
    }

    /// `M x` on displacement dofs (mixed: `Bᵀ C⁻¹ B x`, applied, never formed).
    pub fn mass_times(&self, x: &[f64]) -> Result<Vec<f64>> {
        let mut out = vec![0.0; x.len()];
        self.apply_add(&mut out, &self.project(x)?, 1.0);
        Ok(out)
    }

    /// Factors the constant step matrix `m_coef · M + k_coef · K` once. For the mixed mass the
    /// unknowns are `(U, w)` and the matrix is the sparse saddle system
    /// `[k_coef K, m_coef Bᵀ; B, −C]` (second block row: `C w = B U`), factored by LU.
    pub fn step_operator(&self, k: &SpMat, m_coef: f64, k_coef: f64) -> Result<StepOperator> {
        let n = k.nrows();
        match self {
            Inertia::Sparse { m } => {
                let a = linalg::lin_comb(m_coef, m, k_coef, k)?;
                Ok(StepOperator {
                    factor: Factor::cholesky(&a, "step matrix m·M + k·K")?,
                    n,
                    mixed: false,
                    x: vec![0.0; n],
                })
            }
            Inertia::Mixed { b, c, .. } => {
                let nh = c.nrows();
                let mut t = TripletBuilder::new(n + nh, n + nh);
                t.add_scaled(0, 0, k_coef, k);
                for (i, j, v) in linalg::triplets(b) {
                    t.add(j, n + i, m_coef * v);
                    t.add(n + i, j, v);
                }
                t.add_scaled(n, n, -1.0, c);
                Ok(StepOperator {
                    factor: Factor::lu(&t.build()?, "singular dynamic saddle system")?,
                    n,
                    mixed: true,
                    x: vec![0.0; n + nh],
                })
            }
        }
    }

    /// Galerkin acceleration `A` on the displacement dofs from `M A = r` (r = F − K U₀ at zero
    /// contact force). Sparse: solved on the dofs with mass, massless dofs get 0 (their equation
    /// is quasi-static). Mixed: `M_V A = r` with the consistent V_h mass M_V.
    pub fn acceleration(&self, r: &[f64]) -> Result<Vec<f64>> {
        match self {
            Inertia::Sparse { m } => solve_on_massive_dofs(m, r),
            Inertia::Mixed { consistent, .. } => {
                let mut a = r.to_vec();
                Factor::cholesky(consistent, "consistent mass")?.solve_in_place(&mut a);
                Ok(a)
            }
        }
    }
}

/// From this many dofs the mass is solved by Jacobi-PCG (a mass matrix is well conditioned:
/// tens of iterations) instead of a sparse Cholesky, which fills in heavily in 3D.
const MASS_CG_DOFS: usize = 50_000;
/// Relative residual of that solve.
const MASS_CG_TOLERANCE: f64 = 1e-12;

/// Solves `M_rr a_r = r_r` on the dofs with `M_ii > 0`; `a = 0` on massless dofs.
fn solve_on_massive_dofs(m: &SpMat, r: &[f64]) -> Result<Vec<f64>> {
    let n = m.nrows();
    let diag = linalg::diagonal(m);
    if n >= MASS_CG_DOFS {
        let massive: Vec<bool> = diag.iter().map(|&d| d > 0.0).collect();
        let mut a = vec![0.0; n];
        linalg::Pcg::new(m, "mass matrix")?
            .solve(r, &mut a, &massive, (MASS_CG_TOLERANCE, 10 * n))
            .map_err(|res| Error::Factorisation {
                matrix: "mass matrix on its massive dofs".into(),
                reason: format!("cg did not converge (relative residual {res:.3e})"),
            })?;
        return Ok(a);
    }
    let mut reduced = vec![None; n];
    let mut count = 0;
    for (i, d) in diag.iter().enumerate() {
        if *d > 0.0 {
            reduced[i] = Some(count);
            count += 1;
        }
    }
    let mut a = vec![0.0; n];
    if count == 0 {
        return Ok(a);
    }
    let mut t = TripletBuilder::new(count, count);
    for (i, j, v) in linalg::triplets(m) {
        if let (Some(p), Some(q)) = (reduced[i], reduced[j]) {
            t.add(p, q, v);
        }
    }
    let mut x: Vec<f64> = (0..n)
        .filter(|&i| reduced[i].is_some())
        .map(|i| r[i])
        .collect();
    Factor::cholesky(&t.build()?, "mass matrix on its massive dofs")?.solve_in_place(&mut x);
    for (i, ri) in reduced.iter().enumerate() {
        if let Some(p) = ri {
            a[i] = x[*p];
        }
    }
    Ok(a)
}

/// The factored step matrix of [`Inertia::step_operator`]; solves for `(U, w)`.
#[derive(Debug)]
pub struct StepOperator {
    factor: Factor,
    n: usize,
    mixed: bool,
    x: Vec<f64>,
}

impl StepOperator {
    /// Solves for `ncols` displacement right-hand sides at once: `rhs` holds them column-major
    /// (length `n · ncols`) and receives the displacements; `w` (length `dim w · ncols`) receives
    /// the inertial variables (setup only: allocates).
    pub fn solve_columns(&mut self, rhs: &mut [f64], w: &mut [f64], ncols: usize) {
        let (n, big) = (self.n, self.x.len());
        let mut x = vec![0.0; big * ncols];
        for c in 0..ncols {
            x[c * big..c * big + n].copy_from_slice(&rhs[c * n..(c + 1) * n]);
        }
        self.factor.solve_columns(&mut x, ncols);
        let nw = w.len() / ncols.max(1);
        for c in 0..ncols {
            let col = &x[c * big..(c + 1) * big];
            rhs[c * n..(c + 1) * n].copy_from_slice(&col[..n]);
            let wsrc = if self.mixed { &col[n..] } else { &col[..n] };
            w[c * nw..(c + 1) * nw].copy_from_slice(wsrc);
        }
    }

    /// True for the singular dynamic saddle system (inertial variables distinct from U).
    pub fn is_mixed(&self) -> bool {
        self.mixed
    }

    /// Solves the step system with displacement right-hand side `rhs_u` (inertial rows 0),
    /// writing the displacements to `u` and the inertial variables to `w`. Allocates nothing.
    pub fn solve(&mut self, rhs_u: &[f64], u: &mut [f64], w: &mut [f64]) {
        if !self.mixed {
            u.copy_from_slice(rhs_u);
            self.factor.solve_in_place(u);
            w.copy_from_slice(u);
            return;
        }
        self.x[..self.n].copy_from_slice(rhs_u);
        self.x[self.n..].fill(0.0);
        self.factor.solve_in_place(&mut self.x);
        u.copy_from_slice(&self.x[..self.n]);
        w.copy_from_slice(&self.x[self.n..]);
    }
}

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
    /// Quadrature points of Γ_C for boundary integrals, when the case provides them (Nitsche).
    pub quadrature: Option<Vec<BoundaryPoint>>,
    /// Set by the Nitsche formulation: force rows and compliances differ from the gap rows.
    pub nitsche: Option<NitscheRows>,
}

/// A quadrature point `x_q` of Γ_C for the boundary integrals of Nitsche's method
/// ([`crate::contact::nitsche`]): `∫_{Γ_C} f ≈ Σ_q w_q f(x_q)`.
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
    /// Local mesh size over Young's modulus (Nitsche's `γ = h / (γ₀ E)`).
    pub h_over_e: f64,
    /// The vertex rows of its face with their degree-1 hat functions at x_q (shares summing to 1).
    pub vertices: Vec<(usize, f64)>,
}

/// The Nitsche form of the contact rows ([`crate::contact::nitsche`]): with the gap rows
/// `B_N − γ S`, the force is `Qᵀ λ` (`Q = B_N − θ γ S`) and `λ_i = (w_i/γ_i) [−g_i]₊`, i.e. the
/// LCP with matrix `D + diag(compliance)`.
#[derive(Debug, Clone)]
pub struct NitscheRows {
    /// Q (n_c × n).
    pub force: SpMat,
    /// `γ_i / w_i`.
    pub compliance: Vec<f64>,
    /// The boundary part of the energy, per point.
    pub energy: Vec<BoundaryEnergy>,
    /// The rows `U ↦ u_N(x_i)` of the physical gap `g₀_i − u_N(x_i)`.
    pub normal: Vec<Vec<(usize, f64)>>,
}

/// One point's boundary energy `a (S_i U)² + b [(B_N − γS)_i U − g₀_i]₊²`.
#[derive(Debug, Clone)]
pub struct BoundaryEnergy {
    /// Row `S_i`.
    pub s: Vec<(usize, f64)>,
    /// Row `(B_N − γ S)_i`.
    pub r: Vec<(usize, f64)>,
    /// g₀_i.
    pub g0: f64,
    /// Coefficient of `(S_i U)²`.
    pub a: f64,
    /// Coefficient of the positive part squared.
    pub b: f64,
}

impl BoundaryEnergy {
    /// Its value at U.
    pub fn eval(&self, u: &[f64]) -> f64 {
        let dot = |row: &[(usize, f64)]| row.iter().map(|&(j, v)| v * u[j]).sum::<f64>();
        let p = (dot(&self.r) - self.g0).max(0.0);
        self.a * dot(&self.s).powi(2) + self.b * p * p
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
    /// The rows whose transpose applies the contact force (`−Qᵀ λ`): B_N, or Nitsche's Q.
    pub fn force_rows(&self) -> &SpMat {
        self.nitsche.as_ref().map_or(&self.b_n, |n| &n.force)
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

impl Contact {
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
    /// `B_N`, or for Nitsche (whose `B_N` rows are the law's `u_N − γ σ_N`) the row of `u_N`.
    pub fn gap_row(&self, i: usize) -> Vec<(usize, f64)> {
        match &self.nitsche {
            Some(n) => n.normal[i].clone(),
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

/// Where the time series are sampled: contact point `contact`, its displacement dof `u_dof`
/// (normal direction) and its inertial (velocity) dof `w_dof`.
#[derive(Debug, Clone, Copy)]
pub struct Probe {
    /// Index of the contact point.
    pub contact: usize,
    /// Displacement dof of the probe.
    pub u_dof: usize,
    /// Velocity dof of the probe in the inertial variables.
    pub w_dof: usize,
}

/// The total energy `E = ½ vᵀ M v + ½ Uᵀ K U − Fᵀ U (+ shift)`, with `v` the inertial velocity
/// (`C` in place of `M` for the mixed mass, v ∈ H_h), `M` (or `C`) and `K` stored as
/// [`linalg::QuadraticForm`]s.
#[derive(Debug)]
pub struct EnergyForm {
    kinetic: linalg::QuadraticForm,
    stiffness: linalg::QuadraticForm,
    /// F, when not zero.
    load: Option<Vec<f64>>,
    /// [`Problem::energy_shift`].
    shift: f64,
    /// Nitsche's boundary energy.
    boundary: Vec<BoundaryEnergy>,
    work: Vec<f64>,
}

impl EnergyForm {
    /// `E = ½ vᵀ M v + ½ Uᵀ K U − Fᵀ U (+ shift)` (+ Nitsche's boundary energy).
    pub fn energy(&mut self, u: &[f64], v: &[f64]) -> f64 {
        0.5 * self.kinetic.eval(v, &mut self.work)
            + 0.5 * self.stiffness.eval(u, &mut self.work)
            + self.boundary.iter().map(|b| b.eval(u)).sum::<f64>()
            - self
                .load
                .as_ref()
                .map_or(0.0, |f| linalg::dot_unordered(f, u))
            + self.shift
    }
}

/// `M Ü + K U = F − B_Nᵀ λ` with complementarity, and its initial data.
#[derive(Debug)]
pub struct Problem {
    /// Mass operator.
    pub inertia: Inertia,
    /// Stiffness K (SPD once Dirichlet dofs are removed, or PSD with M + K SPD).
    pub k: SpMat,
    /// Constant external load F.
    pub f: Vec<f64>,
    /// Contact points.
    pub contact: Contact,
    /// Initial displacement U₀.
    pub u0: Vec<f64>,
    /// Initial velocity V₀ (displacement dofs).
    pub v0: Vec<f64>,
    /// Time-series probe.
    pub probe: Probe,
    /// Constant added to the energy so that it is the physical one (e.g. ½ k u_e² for a spring
    /// whose rest position is not at u = 0).
    pub energy_shift: f64,
}

impl Problem {
    /// Number of displacement dofs n.
    pub fn n(&self) -> usize {
        self.k.nrows()
    }

    /// The total energy, as stored quadratic forms for evaluation at every step.
    pub fn energy_form(&self) -> EnergyForm {
        let kinetic = match &self.inertia {
            Inertia::Sparse { m } => m,
            Inertia::Mixed { c, .. } => c,
        };
        EnergyForm {
            kinetic: linalg::QuadraticForm::new(kinetic),
            stiffness: linalg::QuadraticForm::new(&self.k),
            load: self.f.iter().any(|&x| x != 0.0).then(|| self.f.clone()),
            shift: self.energy_shift,
            boundary: self
                .contact
                .nitsche
                .as_ref()
                .map_or_else(Vec::new, |n| n.energy.clone()),
            work: Vec::new(),
        }
    }

    /// Normal contact stress `σ_N = −λ / area` at contact point `i`.
    pub fn contact_stress(&self, lambda: &[f64], i: usize) -> f64 {
        // `+ 0.0` turns −0 into +0 so that a free contact prints as 0.
        -lambda[i] / self.contact.area[i] + 0.0
    }

    /// Checks shapes and finiteness; a space or case that builds an inconsistent problem is a bug,
    /// but a NaN from user data must surface as an error, not as a silent NaN trajectory.
    pub fn validate(&self) -> Result<()> {
        let n = self.n();
        let shape = |what: &str, len: usize, want: usize| {
            if len == want {
                Ok(())
            } else {
                Err(Error::Unsupported(format!(
                    "{what} has length {len}, expected {want}"
                )))
            }
        };
        shape("F", self.f.len(), n)?;
        shape("U0", self.u0.len(), n)?;
        shape("V0", self.v0.len(), n)?;
        shape("B_N columns", self.contact.b_n.ncols(), n)?;
        shape("B_N rows", self.contact.b_n.nrows(), self.contact.len())?;
        shape("contact areas", self.contact.area.len(), self.contact.len())?;
        for (name, v) in [
            ("F", &self.f),
            ("U0", &self.u0),
            ("V0", &self.v0),
            ("g0", &self.contact.g0),
        ] {
            if let Some(x) = v.iter().find(|x| !x.is_finite()) {
                return Err(Error::invalid(name, x, "must be finite"));
            }
        }
        Ok(())
    }
}
