//! Singular dynamic method (Renard 2010, J. Comput. Appl. Math. 234:906–923).
//!
//! Displacement in V_h (P2), velocity in H_h (P1) on the same mesh:
//! `C_ij = ∫ρ ψ_i ψ_j`, `B_ij = ∫ρ ψ_i φ_j`, `M = Bᵀ C⁻¹ B` (dense, rank dim H_h: never formed; the
//! schemes carry `w = C⁻¹ B U` as unknowns). The contact dofs keep some mass (`M₀₀ ≠ 0`); the
//! problem is well posed when the inf-sup condition holds: some `u ∈ ker M` has a non-zero contact
//! trace, i.e. `rank [B; e_cᵀ] = rank B + 1` for each contact dof c ([`inf_sup_holds`]).
//!
//! The schemes carry the inertial variables `w = C⁻¹ B U` ∈ H_h: the inertial force of y is
//! `Bᵀ y`, the kinetic energy `½ vᵀ C v`, and the step matrix `m M + k K` becomes the sparse
//! saddle system `[k K, m Bᵀ; m B, −m C] (U, w) = (r, 0)` (second block row: `m (C w − B U) = 0`,
//! scaled by m so that the matrix is symmetric), factored once by LBLᵀ ([`SaddleMass`]).

use super::{MassModel, Space, VelocitySpace};
use crate::error::{Error, Result};
use crate::fem::assembly::assemble;
use crate::linalg::{self, Factor, SpMat, TripletBuilder};
use crate::param::Entry;
use crate::problem::{Inertia, StepOperator};
use nalgebra::DMatrix;

/// The singular dynamic method with the velocity space of the [`MassModel`].
#[derive(Debug, Clone, Copy)]
pub struct SingularDynamic;

/// Registry entry: `singular_dynamic` (no parameter).
pub const ENTRY: Entry<dyn Space> = Entry {
    name: "singular_dynamic",
    params: &[],
    build: |_| Ok(Box::new(SingularDynamic)),
};

impl Space for SingularDynamic {
    fn name(&self) -> &'static str {
        "singular_dynamic"
    }

    fn inertia(&self, model: &MassModel) -> Result<Box<dyn Inertia>> {
        let (b, c) = mixed_matrices(model)?;
        Ok(Box::new(SaddleMass {
            b,
            c,
            consistent: model.assemble(|el, _| el.mass.clone())?,
            dof_of: velocity_space(model)?.dof_of.clone(),
        }))
    }
}

/// `M = Bᵀ C⁻¹ B`, never formed: the inertial variables are `w = C⁻¹ B U`, the L²(ρ)
/// projection of U on the velocity space H_h.
#[derive(Debug)]
pub struct SaddleMass {
    /// `B_ij = ∫ρ ψ_i φ_j` (rows: H_h dofs, columns: V_h dofs).
    pub b: SpMat,
    /// `C_ij = ∫ρ ψ_i ψ_j` (H_h mass, SPD).
    pub c: SpMat,
    /// The consistent V_h mass, used only to start from a consistent initial acceleration.
    pub consistent: SpMat,
    /// The H_h dof at the node of each displacement dof, when that node is a vertex.
    dof_of: Vec<Option<usize>>,
}

impl Inertia for SaddleMass {
    fn dim(&self) -> usize {
        self.c.nrows()
    }

    fn project(&self, u: &[f64]) -> Result<Vec<f64>> {
        let mut w = linalg::mul(&self.b, u);
        Factor::cholesky(&self.c, "velocity-space mass C")?.solve_in_place(&mut w);
        Ok(w)
    }

    fn apply_add(&self, out: &mut [f64], y: &[f64], alpha: f64) {
        linalg::mul_t_add(out, &self.b, y, alpha);
    }

    /// The unknowns are `(U, w)` and the matrix is the sparse saddle system
    /// `[k_coef K, m_coef Bᵀ; m_coef B, −m_coef C]` (second block row: `C w = B U` scaled by
    /// m_coef, so that the matrix is symmetric), factored by [`Factor::symmetric_indefinite`]; with
    /// m_coef = 0 the row is left unscaled (`[k K, 0; B, −C]`) and factored by LU.
    fn step_operator(&self, k: &SpMat, m_coef: f64, k_coef: f64) -> Result<Box<dyn StepOperator>> {
        let (n, nh) = (k.nrows(), self.c.nrows());
        let mut t = TripletBuilder::new(n + nh, n + nh);
        t.add_scaled(0, 0, k_coef, k);
        // The second block row scaled by m_coef (its right-hand side is 0): a symmetric matrix.
        let row = if m_coef != 0.0 { m_coef } else { 1.0 };
        for (i, j, v) in linalg::triplets(&self.b) {
            t.add(j, n + i, m_coef * v);
            t.add(n + i, j, row * v);
        }
        t.add_scaled(n, n, -row, &self.c);
        let (a, name) = (t.build()?, "singular dynamic saddle system");
        Ok(Box::new(SaddleStep {
            factor: if m_coef != 0.0 {
                Factor::symmetric_indefinite(&a, name)?
            } else {
                Factor::lu(&a, name)?
            },
            n,
            x: vec![0.0; n + nh],
        }))
    }

    /// `M_V A = r` with the consistent V_h mass M_V.
    fn acceleration(&self, r: &[f64]) -> Result<Vec<f64>> {
        let mut a = r.to_vec();
        Factor::cholesky(&self.consistent, "consistent mass")?.solve_in_place(&mut a);
        Ok(a)
    }

    fn kinetic(&self) -> &SpMat {
        &self.c
    }

    fn sparse(&self) -> Option<&SpMat> {
        None
    }

    fn velocity_dof(&self, u_dof: usize) -> usize {
        self.dof_of.get(u_dof).copied().flatten().unwrap_or(u_dof)
    }

    /// None: `M = Bᵀ C⁻¹ B` has no zero row (B's columns are the displacement dofs).
    fn massless(&self) -> Vec<bool> {
        vec![false; self.b.ncols()]
    }
}

/// The factored saddle system of [`SaddleMass::step_operator`], solving for `(U, w)`.
#[derive(Debug)]
struct SaddleStep {
    factor: Factor,
    n: usize,
    x: Vec<f64>,
}

impl StepOperator for SaddleStep {
    fn is_mixed(&self) -> bool {
        true
    }

    fn solve(&mut self, rhs_u: &[f64], u: &mut [f64], w: &mut [f64]) {
        self.x[..self.n].copy_from_slice(rhs_u);
        self.x[self.n..].fill(0.0);
        self.factor.solve_in_place(&mut self.x);
        u.copy_from_slice(&self.x[..self.n]);
        w.copy_from_slice(&self.x[self.n..]);
    }

    fn solve_columns(&mut self, rhs: &mut [f64], w: &mut [f64], ncols: usize) {
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
            w[c * nw..(c + 1) * nw].copy_from_slice(&col[n..]);
        }
    }
}

/// The velocity space of the model, or why there is none.
fn velocity_space(model: &MassModel) -> Result<&VelocitySpace> {
    model.velocity.as_ref().ok_or_else(|| {
        Error::Unsupported(
            "singular_dynamic needs a displacement of degree 2 (P2 displacement / P1 velocity): \
             use --degree 2 on a generated mesh, or a second-order mesh file (Tri6, Qua9, Tet10, \
             Hex27: `gmsh -order 2`)"
                .into(),
        )
    })
}

/// Assembles `(B, C)` from the velocity-space element data.
pub fn mixed_matrices(model: &MassModel) -> Result<(SpMat, SpMat)> {
    let VelocitySpace {
        elements, dim: nh, ..
    } = velocity_space(model)?;
    let pairs = model.elements.iter().zip(elements);
    let b = assemble(
        *nh,
        model.n_dofs,
        pairs.clone().flat_map(|(el, mx)| {
            el.dofs
                .iter()
                .zip(&mx.vdofs)
                .map(move |(d, v)| (v.iter().map(|&i| Some(i)).collect(), d.clone(), &mx.b))
        }),
    )?;
    let c = assemble(
        *nh,
        *nh,
        pairs.flat_map(|(_, mx)| {
            mx.vdofs.iter().map(move |v| {
                let v: Vec<Option<usize>> = v.iter().map(|&i| Some(i)).collect();
                (v.clone(), v, &mx.c)
            })
        }),
    )?;
    Ok((b, c))
}

/// Numerical rank of a dense matrix (relative tolerance 1e-10 on the singular values).
pub fn rank(m: &DMatrix<f64>) -> usize {
    let sv = m.clone().svd(false, false).singular_values;
    let tol = 1e-10 * sv.max().max(f64::MIN_POSITIVE);
    sv.iter().filter(|&&s| s > tol).count()
}

/// The inf-sup rank condition `rank [B; e_cᵀ] = rank B + 1` for every contact dof c (dense SVD:
/// a diagnostic for small meshes only).
pub fn inf_sup_holds(b: &DMatrix<f64>, contact_dofs: &[usize]) -> bool {
    let rows: Vec<Vec<(usize, f64)>> = contact_dofs.iter().map(|&c| vec![(c, 1.0)]).collect();
    inf_sup_holds_rows(b, &rows)
}

/// The inf-sup rank condition on constraint rows `b_c` that may couple several dofs (two
/// bodies: a slave dof and its master face's, [`crate::fem::bodies`]):
/// `rank [B; b_cᵀ] = rank B + 1` for every row.
pub fn inf_sup_holds_rows(b: &DMatrix<f64>, rows: &[Vec<(usize, f64)>]) -> bool {
    let rb = rank(b);
    rows.iter().all(|row| {
        let mut ext = b.clone().insert_row(b.nrows(), 0.0);
        for &(j, v) in row {
            ext[(b.nrows(), j)] = v;
        }
        rank(&ext) == rb + 1
    })
}
