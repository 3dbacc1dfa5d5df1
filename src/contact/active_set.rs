//! Exact LCP solver: block principal pivoting (Júdice & Pires 1994) on the Delassus matrix, with
//! Murty's single-pivot rule as the safeguard that guarantees termination.
//!
//! Each iterate is a complementary basis: for the active set 𝒜, `D_𝒜𝒜 λ_𝒜 = −q_𝒜`, λ = 0
//! elsewhere; the infeasible set is `{i ∈ 𝒜 : λ_i < 0} ∪ {i ∉ 𝒜 : g_i < 0}` with `g = q + D λ`.
//! All infeasible indices are flipped at once (a semi-smooth Newton step on
//! `min(λ, q + Dλ) = 0`) while their number decreases; after [`BACKUP_TRIES`] steps without
//! decrease only the largest infeasible index is flipped (Murty 1974), which terminates for any
//! P-matrix (D SPD) from any starting basis, so the previous step's active set is a valid warm
//! start. Points with `q_i = +∞` are excluded (λ_i = 0). The result satisfies complementarity to
//! round-off: λ_i = 0 or g_i = 0 up to the dense Cholesky solve of the active block.

use super::{SolveInfo, Solver};
use crate::error::SolverError;
use nalgebra::DMatrix;

/// Block-pivoting steps allowed without a decrease of the infeasible count before falling back
/// to single pivots.
pub const BACKUP_TRIES: usize = 3;

/// Workspace for the pivoting method; allocated once for `n_c` contact points.
#[derive(Debug, Clone)]
pub struct ActiveSet {
    active: Vec<bool>,
    index: Vec<usize>,
    /// Active set and matrix fingerprint of the factor held in `chol` (reused while unchanged:
    /// during persistent contact the active set rarely changes from step to step).
    factored: Vec<usize>,
    fingerprint: Option<(usize, f64)>,
    infeasible: Vec<usize>,
    chol: Vec<f64>,
    rhs: Vec<f64>,
    g: Vec<f64>,
}

impl ActiveSet {
    /// Workspace for `n_c` contact points.
    pub fn new(n_c: usize) -> Self {
        Self {
            active: vec![false; n_c],
            index: Vec::with_capacity(n_c),
            factored: Vec::with_capacity(n_c),
            fingerprint: None,
            infeasible: Vec::with_capacity(n_c),
            chol: vec![0.0; n_c * n_c],
            rhs: vec![0.0; n_c],
            g: vec![0.0; n_c],
        }
    }

    /// Solves `D_𝒜𝒜 λ_𝒜 = −q_𝒜` by a dense Cholesky of the active block (in the workspace).
    fn solve_active(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> Result<(), SolverError> {
        self.index.clear();
        self.index.extend((0..q.len()).filter(|&i| self.active[i]));
        let k = self.index.len();
        let fingerprint = (d.as_ptr() as usize, d.diagonal().sum());
        if self.fingerprint != Some(fingerprint) || self.factored != self.index {
            self.fingerprint = None;
            self.factor_active(d, k)?;
            self.factored.clear();
            self.factored.extend_from_slice(&self.index);
            self.fingerprint = Some(fingerprint);
        }
        let l = &self.chol[..k * k];
        let y = &mut self.rhs[..k];
        for a in 0..k {
            let mut s = -q[self.index[a]];
            for c in 0..a {
                s -= l[a * k + c] * y[c];
            }
            y[a] = s / l[a * k + a];
        }
        for a in (0..k).rev() {
            let mut s = y[a];
            for c in a + 1..k {
                s -= l[c * k + a] * y[c];
            }
            y[a] = s / l[a * k + a];
        }
        lambda.fill(0.0);
        for (a, &i) in self.index.iter().enumerate() {
            lambda[i] = y[a];
        }
        Ok(())
    }

    /// Dense Cholesky `L Lᵀ = D_𝒜𝒜` of the active block into `chol` (row-major k × k).
    fn factor_active(&mut self, d: &DMatrix<f64>, k: usize) -> Result<(), SolverError> {
        let l = &mut self.chol[..k * k];
        for a in 0..k {
            for b in 0..=a {
                let mut s = d[(self.index[a], self.index[b])];
                for c in 0..b {
                    s -= l[a * k + c] * l[b * k + c];
                }
                if a == b {
                    if s <= 0.0 || !s.is_finite() {
                        return Err(SolverError::NotPositiveDefinite { pivot: s });
                    }
                    l[a * k + a] = s.sqrt();
                } else {
                    l[a * k + b] = s / l[b * k + b];
                }
            }
        }
        Ok(())
    }

    /// Collects the infeasible indices of the current basis into `self.infeasible`.
    fn find_infeasible(&mut self, d: &DMatrix<f64>, q: &[f64], lambda: &[f64], tol: (f64, f64)) {
        let n = q.len();
        self.infeasible.clear();
        for i in 0..n {
            let bad = if self.active[i] {
                lambda[i] < -tol.1
            } else {
                self.g[i] = q[i] + (0..n).map(|j| d[(i, j)] * lambda[j]).sum::<f64>();
                self.g[i] < -tol.0
            };
            if bad {
                self.infeasible.push(i);
            }
        }
    }
}

/// Absolute tolerances `(gap, pressure)` relative to the data scale.
fn tolerances(d: &DMatrix<f64>, q: &[f64]) -> (f64, f64) {
    let scale = q
        .iter()
        .filter(|x| x.is_finite())
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .max(f64::MIN_POSITIVE);
    let dmax = (0..q.len()).fold(0.0f64, |m, i| m.max(d[(i, i)]));
    (1e-13 * scale, 1e-13 * scale / dmax.max(f64::MIN_POSITIVE))
}

impl Solver for ActiveSet {
    fn name(&self) -> &'static str {
        "active_set"
    }

    fn solve(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> Result<SolveInfo, SolverError> {
        let n = q.len();
        if n == 0 {
            return Ok(SolveInfo::default());
        }
        let tol = tolerances(d, q);
        for ((a, l), qi) in self.active.iter_mut().zip(lambda.iter()).zip(q) {
            *a = *l > 0.0 && qi.is_finite();
        }
        let (mut best, mut tries) = (n + 1, BACKUP_TRIES);
        let max_iterations = 50 * n + 50;
        for it in 0..max_iterations {
            self.solve_active(d, q, lambda)?;
            self.find_infeasible(d, q, lambda, tol);
            let count = self.infeasible.len();
            if count == 0 {
                for l in lambda.iter_mut() {
                    *l = l.max(0.0);
                }
                return Ok(SolveInfo {
                    iterations: it + 1,
                    active: self.active.iter().filter(|a| **a).count(),
                });
            }
            if count < best {
                (best, tries) = (count, BACKUP_TRIES);
            } else if tries > 0 {
                tries -= 1;
            } else {
                let last = self.infeasible[count - 1];
                self.infeasible.clear();
                self.infeasible.push(last);
            }
            for &i in &self.infeasible {
                self.active[i] = !self.active[i];
            }
        }
        Err(SolverError::NotConverged {
            method: "block principal pivoting",
            detail: format!("no complementary solution after {max_iterations} pivots"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::check_solution;

    #[test]
    fn scalar_lcp_is_max_of_zero_and_minus_q_over_d() {
        let d = DMatrix::from_element(1, 1, 4.0);
        let mut s = ActiveSet::new(1);
        let mut l = [0.0];
        s.solve(&d, &[-2.0], &mut l).unwrap();
        assert_eq!(l[0], 0.5);
        s.solve(&d, &[3.0], &mut l).unwrap();
        assert_eq!(l[0], 0.0);
    }

    #[test]
    fn coupled_lcp_with_one_active_and_one_free_point() {
        let d = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0]);
        let q = [-1.0, 0.5, -0.3];
        let mut l = [1.0, 1.0, 0.0];
        ActiveSet::new(3).solve(&d, &q, &mut l).unwrap();
        check_solution(&d, &q, &l, 1e-12).unwrap();
        assert!(l[0] > 0.0 && l[1] == 0.0);
    }

    #[test]
    fn excluded_point_gets_no_pressure() {
        let d = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
        let q = [-1.0, f64::INFINITY];
        let mut l = [0.0, 5.0];
        ActiveSet::new(2).solve(&d, &q, &mut l).unwrap();
        assert!((l[0] - 0.5).abs() < 1e-15 && l[1] == 0.0, "{l:?}");
    }
}
