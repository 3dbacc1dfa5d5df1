//! The inertia of every space whose mass is a sparse matrix (standard, lumped, mass
//! redistribution, mass elimination): a symmetric positive semi-definite `M`, with the
//! displacements themselves as inertial variables (`w = U`). The step matrix `m M + k K` is SPD
//! and factored by a sparse Cholesky.

use crate::error::{Error, Result};
use crate::linalg::{self, Factor, SpMat, TripletBuilder};
use crate::problem::{Inertia, StepOperator};

/// A sparse, symmetric, positive semi-definite mass matrix.
#[derive(Debug)]
pub struct SparseMass {
    /// The mass matrix M.
    pub m: SpMat,
}

impl SparseMass {
    /// The inertia of the mass matrix `m`.
    pub fn boxed(m: SpMat) -> Box<dyn Inertia> {
        Box::new(Self { m })
    }
}

impl Inertia for SparseMass {
    fn dim(&self) -> usize {
        self.m.nrows()
    }

    fn project(&self, u: &[f64]) -> Result<Vec<f64>> {
        Ok(u.to_vec())
    }

    fn apply_add(&self, out: &mut [f64], y: &[f64], alpha: f64) {
        // M is symmetric: the gather form `Mᵀ y` has no scattered stores.
        linalg::mul_t_add(out, &self.m, y, alpha);
    }

    fn step_operator(&self, k: &SpMat, m_coef: f64, k_coef: f64) -> Result<Box<dyn StepOperator>> {
        let a = linalg::lin_comb(m_coef, &self.m, k_coef, k)?;
        Ok(Box::new(CholeskyStep(Factor::cholesky(
            &a,
            "step matrix m·M + k·K",
        )?)))
    }

    /// Solved on the dofs with mass, massless dofs get 0 (their equation is quasi-static).
    fn acceleration(&self, r: &[f64]) -> Result<Vec<f64>> {
        solve_on_massive_dofs(&self.m, r)
    }

    fn kinetic(&self) -> &SpMat {
        &self.m
    }

    fn sparse(&self) -> Option<&SpMat> {
        Some(&self.m)
    }

    fn velocity_dof(&self, u_dof: usize) -> usize {
        u_dof
    }

    fn massless(&self) -> Vec<bool> {
        let mut massless = vec![true; self.m.nrows()];
        for (i, _, v) in linalg::triplets(&self.m) {
            if v != 0.0 {
                massless[i] = false;
            }
        }
        massless
    }
}

/// `m M + k K` factored by Cholesky; the inertial variables are the displacements.
#[derive(Debug)]
struct CholeskyStep(Factor);

impl StepOperator for CholeskyStep {
    fn is_mixed(&self) -> bool {
        false
    }

    fn solve(&mut self, rhs_u: &[f64], u: &mut [f64], w: &mut [f64]) {
        u.copy_from_slice(rhs_u);
        self.0.solve_in_place(u);
        w.copy_from_slice(u);
    }

    fn solve_columns(&mut self, rhs: &mut [f64], w: &mut [f64], ncols: usize) {
        self.0.solve_columns(rhs, ncols);
        w.copy_from_slice(rhs);
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
