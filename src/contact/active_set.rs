//! Exact LCP solver: Murty's least-index principal pivoting method on the Delassus matrix.
//!
//! Each iterate is a complementary basis: for the active set 𝒜, `D_𝒜𝒜 λ_𝒜 = −q_𝒜`, λ = 0 elsewhere.
//! The least index violating `λ_i ≥ 0` (i ∈ 𝒜) or `g_i ≥ 0` (i ∉ 𝒜) is flipped. For a P-matrix
//! (D SPD) this terminates from any starting basis (Murty 1974), so the previous step's active set
//! is a valid warm start. The result satisfies complementarity to round-off: λ_i = 0 or g_i = 0
//! exactly up to the solve of the active block.

use super::{SolveInfo, Solver};
use nalgebra::DMatrix;

/// Workspace for Murty's method; allocated once for `n_c` contact points.
#[derive(Debug, Clone)]
pub struct ActiveSet {
    active: Vec<bool>,
    index: Vec<usize>,
    chol: Vec<f64>,
    rhs: Vec<f64>,
    max_iterations: usize,
}

impl ActiveSet {
    /// Workspace for `n_c` contact points.
    pub fn new(n_c: usize) -> Self {
        Self {
            active: vec![false; n_c],
            index: Vec::with_capacity(n_c),
            chol: vec![0.0; n_c * n_c],
            rhs: vec![0.0; n_c],
            max_iterations: 50 * n_c + 50,
        }
    }

    /// Solves `D_𝒜𝒜 λ_𝒜 = −q_𝒜` by a dense Cholesky of the active block (in the workspace).
    fn solve_active(
        &mut self,
        d: &DMatrix<f64>,
        q: &[f64],
        lambda: &mut [f64],
    ) -> Result<(), String> {
        self.index.clear();
        self.index.extend((0..q.len()).filter(|&i| self.active[i]));
        let k = self.index.len();
        let l = &mut self.chol[..k * k];
        for a in 0..k {
            for b in 0..=a {
                let mut s = d[(self.index[a], self.index[b])];
                for c in 0..b {
                    s -= l[a * k + c] * l[b * k + c];
                }
                if a == b {
                    if s <= 0.0 || !s.is_finite() {
                        return Err(format!(
                            "Delassus block not positive definite (pivot {s:e})"
                        ));
                    }
                    l[a * k + a] = s.sqrt();
                } else {
                    l[a * k + b] = s / l[b * k + b];
                }
            }
        }
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
    ) -> Result<SolveInfo, String> {
        let n = q.len();
        if n == 0 {
            return Ok(SolveInfo::default());
        }
        let scale = q
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()))
            .max(f64::MIN_POSITIVE);
        let dmax = (0..n).fold(0.0f64, |m, i| m.max(d[(i, i)]));
        let (tol_g, tol_l) = (1e-13 * scale, 1e-13 * scale / dmax.max(f64::MIN_POSITIVE));
        for (a, l) in self.active.iter_mut().zip(lambda.iter()) {
            *a = *l > 0.0;
        }
        for it in 0..self.max_iterations {
            self.solve_active(d, q, lambda)?;
            let violating = (0..n).find(|&i| {
                if self.active[i] {
                    lambda[i] < -tol_l
                } else {
                    q[i] + (0..n).map(|j| d[(i, j)] * lambda[j]).sum::<f64>() < -tol_g
                }
            });
            match violating {
                Some(i) => self.active[i] = !self.active[i],
                None => {
                    for l in lambda.iter_mut() {
                        *l = l.max(0.0);
                    }
                    let active = self.active.iter().filter(|a| **a).count();
                    return Ok(SolveInfo {
                        iterations: it + 1,
                        active,
                    });
                }
            }
        }
        Err(format!(
            "no complementary solution after {} pivots",
            self.max_iterations
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(d: &DMatrix<f64>, q: &[f64], l: &[f64]) {
        for i in 0..q.len() {
            let g = q[i] + (0..q.len()).map(|j| d[(i, j)] * l[j]).sum::<f64>();
            assert!(
                l[i] >= 0.0 && g >= -1e-12 && (l[i] * g).abs() < 1e-12,
                "i={i} λ={} g={g}",
                l[i]
            );
        }
    }

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
        check(&d, &q, &l);
        assert!(l[0] > 0.0 && l[1] == 0.0);
    }
}
