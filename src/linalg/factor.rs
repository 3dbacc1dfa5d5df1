//! The direct factor: sparse Cholesky (SPD) or LU (square, e.g. a saddle system) by faer,
//! analysed and factored once, then solved in place without allocating (faer's `MemStack`); a
//! simplicial Cholesky factor is solved by plain column sweeps.

use super::ordering::Ordering;
use super::sparse::{triplets, SpMat};
use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, IntranodeLbltRef, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::SparseColMatRef;
use faer::{Conj, MatMut, Par, Side};

/// Which factorisation a [`Factor`] holds.
pub(super) enum Kind {
    /// `P A Pᵀ = L Lᵀ` (A SPD), P the fill-reducing [`Ordering`].
    Llt {
        symbolic: SymbolicCholesky<usize>,
        values: Vec<f64>,
    },
    /// `P A Pᵀ = L B Lᵀ` (A symmetric indefinite), the fill-reducing [`Ordering`], Bunch–Kaufman pivoting within
    /// faer's supernodes.
    Lblt {
        symbolic: SymbolicCholesky<usize>,
        values: Vec<f64>,
        subdiag: Vec<f64>,
        /// The pivoting permutation, forward and inverse.
        perm: (Vec<usize>, Vec<usize>),
    },
    /// `P A Q = L U` with partial pivoting (A square, possibly indefinite).
    Lu {
        symbolic: SymbolicLu<usize>,
        numeric: NumericLu<usize, f64>,
    },
}

/// Largest relative residual of the check solve of [`Factor::symmetric_indefinite`].
const LBLT_RESIDUAL: f64 = 1e-10;
/// Order from which [`Factor::symmetric_indefinite`] tries LBLᵀ: below it LU's fill costs little
/// (the singular dynamic Q2 sphere at n = 4, 7 638 unknowns: 2.4 s for the whole run), and the
/// golden snapshots (coarsest levels) keep LU's round-off.
const LBLT_DOFS: usize = 10_000;

impl Kind {
    /// The faer view of an LBLᵀ factor (panics on another kind: called on [`Kind::Lblt`] only).
    fn lblt(&self) -> IntranodeLbltRef<'_, usize, f64> {
        let Kind::Lblt {
            symbolic,
            values,
            subdiag,
            perm,
        } = self
        else {
            unreachable!("an LBLt factor")
        };
        let n = subdiag.len();
        IntranodeLbltRef::new(
            symbolic,
            values,
            subdiag,
            PermRef::new_checked(&perm.0, &perm.1, n),
        )
    }
}

/// Index arrays of a simplicial Cholesky factor computed by faer (`L` in CSC form, diagonal
/// first in each column, and the fill-reducing permutation `P A Pᵀ = L Lᵀ`).
struct Simplicial {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    perm_fwd: Vec<usize>,
    /// `1 / L_jj`: the sweeps are a serial dependency chain, and a multiplication has a quarter
    /// of a division's latency.
    inv_diag: Vec<f64>,
    /// For a bidiagonal L (1D P1 in its natural order): `(l_{j−1,j}... )` scaled couplings
    /// `f_j = l_{j,j−1}/l_jj` and `b_j = l_{j+1,j}/l_jj`, so that each sweep step is one FMA on
    /// the critical path: `w_j = w_j/l_jj − f_j w_{j−1}`.
    band: Option<(Vec<f64>, Vec<f64>)>,
    perm_is_identity: bool,
    work: Vec<f64>,
}

/// A sparse factorisation computed once; [`Factor::solve_in_place`] then performs the triangular
/// solves with a preallocated workspace (no allocation per call).
pub struct Factor {
    pub(super) kind: Kind,
    pub(super) n: usize,
    buffer: MemBuffer,
    /// When faer chose a simplicial factor, its arrays: the solves then run as two plain
    /// column sweeps over faer's `L` (faer's generic multi-column solve costs ≈ 18 ns per dof on a
    /// tridiagonal factor, the sweeps ≈ 3 ns).
    simplicial: Option<Simplicial>,
}

impl std::fmt::Debug for Factor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = match self.kind {
            Kind::Llt { .. } => "LLt",
            Kind::Lblt { .. } => "LBLt",
            Kind::Lu { .. } => "LU",
        };
        let path = if self.simplicial.is_some() {
            ", simplicial sweeps"
        } else {
            ""
        };
        write!(f, "Factor({kind}, n = {}{path})", self.n)
    }
}

pub(super) fn factor_err(name: &str, e: impl std::fmt::Debug) -> Error {
    Error::Factorisation {
        matrix: name.to_string(),
        reason: format!("{e:?}"),
    }
}

/// From this order on, faer factors and solves on the rayon pool (both cores); below it the
/// threads would cost more than they save.
const PARALLEL_FACTOR_DOFS: usize = 50_000;

/// faer's parallelism for a matrix of order `n`.
pub(super) fn par_for(n: usize) -> Par {
    if n >= PARALLEL_FACTOR_DOFS {
        Par::rayon(0)
    } else {
        Par::Seq
    }
}

/// The values of the Cholesky factor of `a` on its analysed pattern `symbolic` (`a` of the
/// pattern it was analysed for); `name` in the error when `a` is not numerically SPD.
pub(super) fn numeric_llt(
    symbolic: &SymbolicCholesky<usize>,
    a: SparseColMatRef<'_, usize, f64>,
    par: Par,
    name: &str,
) -> Result<Vec<f64>> {
    let mut values = vec![0.0; symbolic.len_val()];
    let req = symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default());
    let mut buffer = MemBuffer::try_new(req).map_err(|e| factor_err(name, e))?;
    symbolic
        .factorize_numeric_llt(
            &mut values,
            a,
            Side::Lower,
            Default::default(),
            par,
            MemStack::new(&mut buffer),
            Default::default(),
        )
        .map_err(|e| {
            let faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } = e;
            Error::Factorisation {
                matrix: name.to_string(),
                reason: format!(
                    "not symmetric positive definite (a pivot ≤ 0 at column {index} of its \
                     fill-reducing order)"
                ),
            }
        })?;
    Ok(values)
}

/// The symbolic analysis of the symmetric `a` (lower triangle) in its fill-reducing
/// [`Ordering`].
fn analyse(a: &SpMat, name: &str) -> Result<SymbolicCholesky<usize>> {
    let identity: Vec<usize> = (0..a.nrows()).collect();
    let ordering = Ordering::of(a);
    factorize_symbolic_cholesky(
        a.symbolic(),
        Side::Lower,
        ordering.faer(&identity),
        Default::default(),
    )
    .map_err(|e| factor_err(name, e))
}

impl Factor {
    /// Sparse Cholesky of a symmetric positive definite matrix (both triangles stored; the lower
    /// one is read). `name` is used in the error when `A` is not numerically SPD.
    pub fn cholesky(a: &SpMat, name: &str) -> Result<Self> {
        check_finite(a, name)?;
        let n = a.nrows();
        let par = par_for(n);
        let symbolic = analyse(a, name)?;
        let values = numeric_llt(&symbolic, a.as_ref(), par, name)?;
        let buffer = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, par))
            .map_err(|e| factor_err(name, e))?;
        let simplicial = match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(l) => {
                let mut path = Simplicial {
                    inv_diag: (0..n).map(|j| 1.0 / values[l.col_ptr()[j]]).collect(),
                    col_ptr: l.col_ptr().to_vec(),
                    row_idx: l.row_idx().to_vec(),
                    perm_fwd: symbolic
                        .perm()
                        .map_or_else(|| (0..n).collect(), |p| p.arrays().0.to_vec()),
                    band: None,
                    perm_is_identity: false,
                    work: vec![0.0; n],
                };
                path.perm_is_identity = path.perm_fwd.iter().enumerate().all(|(i, &p)| i == p);
                path.band = path.band_couplings(&values);
                Some(path)
            }
            SymbolicCholeskyRaw::Supernodal(_) => None,
        };
        Ok(Self {
            kind: Kind::Llt { symbolic, values },
            n,
            buffer,
            simplicial,
        })
    }

    /// Sparse LU with partial pivoting of a square matrix.
    pub fn lu(a: &SpMat, name: &str) -> Result<Self> {
        check_finite(a, name)?;
        let n = a.nrows();
        let par = par_for(n);
        let symbolic = factorize_symbolic_lu(a.symbolic(), Default::default())
            .map_err(|e| factor_err(name, e))?;
        let mut numeric = NumericLu::new();
        let req = symbolic
            .factorize_numeric_lu_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let mut buffer = MemBuffer::try_new(req).map_err(|e| factor_err(name, e))?;
        symbolic
            .factorize_numeric_lu(
                &mut numeric,
                a.as_ref(),
                par,
                MemStack::new(&mut buffer),
                Default::default(),
            )
            .map_err(|e| factor_err(name, e))?;
        Ok(Self {
            kind: Kind::Lu { symbolic, numeric },
            n,
            buffer,
            simplicial: None,
        })
    }

    /// Sparse `P A Pᵀ = L B Lᵀ` of a symmetric, possibly indefinite matrix (both triangles
    /// stored; the lower one is read): ordered as for Cholesky ([`Ordering`]), Bunch–Kaufman pivoting within
    /// faer's supernodes. Far less fill than [`Factor::lu`]'s column ordering on a symmetric
    /// saddle system (the singular dynamic Q2 sphere, n = 8, 58 470 unknowns: see
    /// [`Factor::symmetric_indefinite`]). The pivoting does not cross supernodes, so a pivot can be
    /// poor: [`Factor::symmetric_indefinite`] checks a solve.
    pub fn lblt(a: &SpMat, name: &str) -> Result<Self> {
        check_finite(a, name)?;
        let n = a.nrows();
        let par = par_for(n);
        let symbolic = analyse(a, name)?;
        let mut values = vec![0.0; symbolic.len_val()];
        let mut subdiag = vec![0.0; n];
        let (mut fwd, mut inv) = (vec![0usize; n], vec![0usize; n]);
        let req = symbolic
            .factorize_numeric_intranode_lblt_scratch::<f64>(par, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, par));
        let mut buffer = MemBuffer::try_new(req).map_err(|e| factor_err(name, e))?;
        symbolic.factorize_numeric_intranode_lblt(
            &mut values,
            &mut subdiag,
            &mut fwd,
            &mut inv,
            a.as_ref(),
            Side::Lower,
            par,
            MemStack::new(&mut buffer),
            Default::default(),
        );
        Ok(Self {
            kind: Kind::Lblt {
                symbolic,
                values,
                subdiag,
                perm: (fwd, inv),
            },
            n,
            buffer,
            simplicial: None,
        })
    }

    /// A symmetric indefinite matrix of order ≥ [`LBLT_DOFS`] factored by [`Factor::lblt`] when a
    /// solve with it is accurate (relative residual below [`LBLT_RESIDUAL`] for `A x` with a fixed
    /// smooth x), by [`Factor::lu`] otherwise. Measured on the singular dynamic Q2 sphere, n = 8
    /// (58 470 unknowns): LU 186 s and 10.7 GB peak, LBLᵀ 31 s of CPU for the whole run and 2.5 GB.
    pub fn symmetric_indefinite(a: &SpMat, name: &str) -> Result<Self> {
        if a.nrows() < LBLT_DOFS {
            return Self::lu(a, name);
        }
        let mut f = Self::lblt(a, name)?;
        let x: Vec<f64> = (0..a.nrows())
            .map(|i| 1.0 + (0.37 * i as f64).sin())
            .collect();
        let mut y = super::mul(a, &x);
        let b = y.clone();
        f.solve_in_place(&mut y);
        let ay = super::mul(a, &y);
        let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|t| t * t).sum::<f64>().sqrt();
        let res = norm(&mut ay.iter().zip(&b).map(|(p, q)| p - q)) / norm(&mut b.iter().copied());
        if res.is_finite() && res < LBLT_RESIDUAL {
            Ok(f)
        } else {
            Self::lu(a, name)
        }
    }

    /// Order of the factored matrix.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Solves `A X = B` in place for `ncols` right-hand sides stored column-major in `x`
    /// (blocked triangular solves; allocates its workspace: for setup, not for time steps).
    pub fn solve_columns(&mut self, x: &mut [f64], ncols: usize) {
        assert_eq!(
            x.len(),
            self.n * ncols,
            "right-hand sides of the wrong length"
        );
        let rhs = MatMut::from_column_major_slice_mut(x, self.n, ncols);
        // Setup-time blocked solves use every core from the order at which the factor does
        // (the per-step solves stay sequential). Below it they are sequential too: in parallel on
        // a pool busy with other runs (a report's runs side by side) faer's solve rounded
        // differently from one report to the next (the singular dynamic hertz2d run of
        // `report --quick`, 3 554 dofs: energy drift 9.820381432741e-4 against …859e-4).
        let par = par_for(self.n);
        let req = match &self.kind {
            Kind::Llt { symbolic, .. } | Kind::Lblt { symbolic, .. } => {
                symbolic.solve_in_place_scratch::<f64>(ncols, par)
            }
            Kind::Lu { symbolic, .. } => symbolic.solve_in_place_scratch::<f64>(ncols, par),
        };
        let mut buffer = MemBuffer::new(req);
        let stack = MemStack::new(&mut buffer);
        match &self.kind {
            Kind::Llt { symbolic, values } => {
                LltRef::new(symbolic, values).solve_in_place_with_conj(Conj::No, rhs, par, stack)
            }
            Kind::Lblt { .. } => {
                self.kind
                    .lblt()
                    .solve_in_place_with_conj(Conj::No, rhs, par, stack)
            }
            Kind::Lu { symbolic, numeric } => LuRef::new_unchecked(symbolic, numeric)
                .solve_in_place_with_conj(Conj::No, rhs, par, stack),
        }
    }

    /// Solves `A x = b` in place (`x` holds `b` on entry).
    pub fn solve_in_place(&mut self, x: &mut [f64]) {
        assert_eq!(x.len(), self.n, "right-hand side of the wrong length");
        if let (Some(s), Kind::Llt { values, .. }) = (&mut self.simplicial, &self.kind) {
            s.solve(values, x);
            return;
        }
        let rhs = MatMut::from_column_major_slice_mut(x, self.n, 1);
        let stack = MemStack::new(&mut self.buffer);
        match &self.kind {
            Kind::Llt { symbolic, values } => LltRef::new(symbolic, values)
                .solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack),
            Kind::Lblt { .. } => {
                self.kind
                    .lblt()
                    .solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack)
            }
            Kind::Lu { symbolic, numeric } => LuRef::new_unchecked(symbolic, numeric)
                .solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack),
        }
    }
}

impl Simplicial {
    /// `x ← A⁻¹ x` with `P A Pᵀ = L Lᵀ`: `w = P x`, `L Lᵀ w' = w`, `x = Pᵀ w'`.
    fn solve(&mut self, values: &[f64], x: &mut [f64]) {
        if self.perm_is_identity {
            self.sweeps(values, x);
            return;
        }
        let mut w = std::mem::take(&mut self.work);
        for (wi, &f) in w.iter_mut().zip(&self.perm_fwd) {
            *wi = x[f];
        }
        self.sweeps(values, &mut w);
        for (wi, &f) in w.iter().zip(&self.perm_fwd) {
            x[f] = *wi;
        }
        self.work = w;
    }

    /// The scaled couplings of a bidiagonal L (every column holds the diagonal and at most the
    /// next row: a tridiagonal matrix in a banded order, e.g. 1D P1), or None.
    fn band_couplings(&self, values: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
        let (cp, ri, n) = (&self.col_ptr, &self.row_idx, self.inv_diag.len());
        let sub = |j: usize| match cp[j + 1] - cp[j] {
            1 => Some(0.0),
            2 if ri[cp[j] + 1] == j + 1 => Some(values[cp[j] + 1]),
            _ => None,
        };
        let subs: Vec<f64> = (0..n).map(sub).collect::<Option<_>>()?;
        let fwd = (0..n)
            .map(|j| {
                if j == 0 {
                    0.0
                } else {
                    subs[j - 1] * self.inv_diag[j]
                }
            })
            .collect();
        let bwd = (0..n).map(|j| subs[j] * self.inv_diag[j]).collect();
        Some((fwd, bwd))
    }

    /// Column sweeps `L w = w`, then `Lᵀ w = w` (bidiagonal L: [`Simplicial::band_sweeps`]).
    fn sweeps(&self, values: &[f64], w: &mut [f64]) {
        if let Some(band) = &self.band {
            return self.band_sweeps(band, w);
        }
        let (cp, ri, inv) = (&self.col_ptr, &self.row_idx, &self.inv_diag);
        for j in 0..w.len() {
            let wj = w[j] * inv[j];
            w[j] = wj;
            for p in cp[j] + 1..cp[j + 1] {
                w[ri[p]] -= values[p] * wj;
            }
        }
        for j in (0..w.len()).rev() {
            let mut s = w[j];
            for p in cp[j] + 1..cp[j + 1] {
                s -= values[p] * w[ri[p]];
            }
            w[j] = s * inv[j];
        }
    }

    /// The same sweeps for a bidiagonal L, carrying the previous unknown in a register: one
    /// FMA per unknown on the critical path.
    fn band_sweeps(&self, (fwd, bwd): &(Vec<f64>, Vec<f64>), w: &mut [f64]) {
        let inv = &self.inv_diag;
        let mut prev = 0.0;
        for ((wj, ij), fj) in w.iter_mut().zip(inv).zip(fwd) {
            prev = (*wj * ij) - fj * prev;
            *wj = prev;
        }
        let mut next = 0.0;
        for ((wj, ij), bj) in w.iter_mut().zip(inv).zip(bwd).rev() {
            next = (*wj * ij) - bj * next;
            *wj = next;
        }
    }
}

pub(super) fn check_finite(a: &SpMat, name: &str) -> Result<()> {
    if a.nrows() != a.ncols() {
        return Err(factor_err(
            name,
            format!("not square: {}x{}", a.nrows(), a.ncols()),
        ));
    }
    if triplets(a).any(|(_, _, v)| !v.is_finite()) {
        return Err(factor_err(name, "matrix has non-finite entries"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::{laplacian, max_diff};
    use crate::linalg::{mul, TripletBuilder};

    #[test]
    fn cholesky_and_lu_solve_the_same_system() {
        let a = laplacian(50);
        let x: Vec<f64> = (0..50).map(|i| (i as f64 * 0.37).sin()).collect();
        let b = mul(&a, &x);
        for mut f in [
            Factor::cholesky(&a, "A").unwrap(),
            Factor::lu(&a, "A").unwrap(),
        ] {
            let mut y = b.clone();
            f.solve_in_place(&mut y);
            let err = max_diff(&y, &x);
            assert!(err < 1e-11, "solve error {err}");
        }
    }

    /// A 2D Laplacian on a 12 × 12 grid with scrambled numbering (so that faer's ordering is a
    /// real permutation) plus a small shift: the simplicial sweeps match the exact solution.
    #[test]
    fn simplicial_sweeps_solve_a_permuted_system() {
        let m = 12;
        let n = m * m;
        let id = |i: usize, j: usize| (7 * (i * m + j) + 3) % n; // 7 is invertible mod 144
        let mut t = TripletBuilder::new(n, n);
        for i in 0..m {
            for j in 0..m {
                t.add(id(i, j), id(i, j), 4.1);
                for (a, b) in [(i + 1, j), (i, j + 1)] {
                    if a < m && b < m {
                        t.add(id(i, j), id(a, b), -1.0);
                        t.add(id(a, b), id(i, j), -1.0);
                    }
                }
            }
        }
        let a = t.build().unwrap();
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.61).cos()).collect();
        let mut y = mul(&a, &x);
        let mut f = Factor::cholesky(&a, "A").unwrap();
        assert!(
            f.simplicial.is_some(),
            "expected faer to choose a simplicial factor"
        );
        f.solve_in_place(&mut y);
        let err = max_diff(&y, &x);
        assert!(err < 1e-12, "solve error {err}");
    }

    /// A symmetric saddle system `[A, Bᵀ; B, −C]` (A a Laplacian, B a coupling of every other
    /// unknown, C diagonal) above [`LBLT_DOFS`]: LBLᵀ is chosen and solves it as LU does.
    #[test]
    fn lblt_solves_a_symmetric_saddle_system() {
        let (n, nh) = (LBLT_DOFS, LBLT_DOFS / 2);
        let a = laplacian(n);
        let mut t = TripletBuilder::new(n + nh, n + nh);
        t.add_scaled(0, 0, 1.0, &a);
        for i in 0..nh {
            for (j, v) in [(2 * i, 0.5), (2 * i + 1, 0.25)] {
                t.add(n + i, j, v);
                t.add(j, n + i, v);
            }
            t.add(n + i, n + i, -0.125);
        }
        let s = t.build().unwrap();
        let x: Vec<f64> = (0..n + nh).map(|i| (i as f64 * 0.37).sin()).collect();
        let b = mul(&s, &x);
        let f = Factor::symmetric_indefinite(&s, "S").unwrap();
        assert!(matches!(f.kind, Kind::Lblt { .. }), "{f:?}");
        for mut f in [f, Factor::lu(&s, "S").unwrap()] {
            let mut y = b.clone();
            f.solve_in_place(&mut y);
            let err = max_diff(&y, &x);
            assert!(err < 1e-8, "{f:?}: solve error {err}");
        }
    }

    #[test]
    fn cholesky_rejects_an_indefinite_matrix() {
        let mut t = TripletBuilder::new(2, 2);
        t.add(0, 0, 1.0);
        t.add(1, 1, -1.0);
        let err = Factor::cholesky(&t.build().unwrap(), "K").unwrap_err();
        assert!(
            err.to_string().contains("not symmetric positive definite"),
            "{err}"
        );
    }
}
