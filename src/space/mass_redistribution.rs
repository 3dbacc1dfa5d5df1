//! Mass redistribution (Khenous, Laborde, Renard 2008, Eur. J. Mech. A/Solids 27:918–932).
//!
//! On every element touching Γ_C and every displacement component, the element mass `M` is
//! replaced by the symmetric `M̃` closest to it in the Frobenius norm with
//! - `M̃_ab = 0` whenever a or b is a contact dof of that component (no normal inertia there),
//! - the total mass `1ᵀM̃1 = 1ᵀM1`,
//! - the first moments `x_kᵀM̃1 = x_kᵀM1`,
//! - the second moments `x_kᵀM̃x_l = x_kᵀMx_l`,
//!
//! as far as the remaining nodes can carry them: moment groups are added in that order while the
//! constraints stay independent, keeping the highest level whose `M̃` is positive semi-definite. The unknowns are the entries
//! `m_ab, a ≤ b` of the remaining nodes (symmetric by construction; the constraints are written in
//! symmetric form, weight `x_a + x_b` on `m_ab`), the objective weights off-diagonal entries twice.
//! 1D P1 keeps the total mass only (one node left: `M̃ = [[0, 0], [0, ρh]]`); 1D P2 keeps total
//! mass, first and second moment (two nodes left, three unknowns). Kept moments sum over elements,
//! so the global `M̃` keeps them too.
//!
//! Only the normal component of the contact nodes is made massless (their contact dofs are the
//! normal ones): the tangential components keep their inertia, and every moment above holds for
//! them too. With Coulomb friction ([`crate::problem::Friction`]) the tangential rows therefore
//! act on dofs with mass, as in the standard space; only the normal inertia is removed.

use super::sparse_mass::SparseMass;
use super::{MassModel, Space};
use crate::error::Result;
use crate::param::Entry;
use crate::problem::Inertia;
use nalgebra::{DMatrix, DVector};

/// Mass redistribution on the elements touching Γ_C.
#[derive(Debug, Clone, Copy)]
pub struct MassRedistribution;

/// Registry entry: `mass_redistribution` (no parameter).
pub const ENTRY: Entry<dyn Space> = Entry {
    name: "mass_redistribution",
    params: &[],
    build: |_| Ok(Box::new(MassRedistribution)),
};

impl Space for MassRedistribution {
    fn name(&self) -> &'static str {
        "mass_redistribution"
    }

    fn inertia(&self, model: &MassModel) -> Result<Box<dyn Inertia>> {
        let m = model.assemble(|el, comp| {
            let massless: Vec<bool> = (0..el.x.len())
                .map(|a| model.is_contact(el, comp, a))
                .collect();
            if massless.iter().any(|&b| b) {
                redistribute(&el.mass, &el.x, model.dim, &massless).0
            } else {
                el.mass.clone()
            }
        })?;
        model.check_inertia(self.name(), &m)?;
        Ok(SparseMass::boxed(m))
    }
}

/// Which moments a redistributed element matrix keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kept {
    /// Nothing (no node left to carry mass).
    Nothing,
    /// Total mass only.
    Total,
    /// Total mass and first moments.
    FirstMoments,
    /// Total mass, first and second moments.
    SecondMoments,
}

/// One linear functional of the element matrix: `Σ_ab f(x_a, x_b) M_ab`.
pub(crate) type Moment = Box<dyn Fn(&[f64; 3], &[f64; 3]) -> f64>;

/// The moment functionals by group: total mass, first moments, second moments (in `dim`
/// coordinates), in the order of [`Kept`].
pub(crate) fn moment_groups(dim: usize) -> Vec<Vec<Moment>> {
    let total: Vec<Moment> = vec![Box::new(|_, _| 1.0)];
    let first: Vec<Moment> = (0..dim)
        .map(|k| Box::new(move |a: &[f64; 3], b: &[f64; 3]| 0.5 * (a[k] + b[k])) as Moment)
        .collect();
    let second: Vec<Moment> = (0..dim)
        .flat_map(|k| (k..dim).map(move |l| (k, l)))
        .map(|(k, l)| {
            Box::new(move |a: &[f64; 3], b: &[f64; 3]| 0.5 * (a[k] * b[l] + a[l] * b[k])) as Moment
        })
        .collect();
    vec![total, first, second]
}

/// The redistributed element matrix and the moments it keeps. `massless[a]`: node a is a contact
/// dof. Coordinates are taken relative to the element's first node ([`relative_coords`]).
pub fn redistribute(
    m: &DMatrix<f64>,
    x: &[[f64; 3]],
    dim: usize,
    massless: &[bool],
) -> (DMatrix<f64>, Kept) {
    let n = m.nrows();
    let xs = relative_coords(x);
    let free: Vec<usize> = (0..n).filter(|&a| !massless[a]).collect();
    let vars: Vec<(usize, usize)> = free
        .iter()
        .enumerate()
        .flat_map(|(i, &a)| free[i..].iter().map(move |&b| (a, b)))
        .collect();
    let m0 = DVector::from_iterator(vars.len(), vars.iter().map(|&(a, b)| m[(a, b)]));
    let weight = DVector::from_iterator(
        vars.len(),
        vars.iter().map(|&(a, b)| if a == b { 1.0 } else { 2.0 }),
    );
    let mut best = (DMatrix::zeros(n, n), Kept::Nothing);
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut targets: Vec<f64> = Vec::new();
    let levels = [Kept::Total, Kept::FirstMoments, Kept::SecondMoments];
    for (group, kept) in moment_groups(dim).into_iter().zip(levels) {
        for f in &group {
            rows.push(
                vars.iter()
                    .map(|&(a, b)| weight_of(a, b) * f(&xs[a], &xs[b]))
                    .collect(),
            );
            targets.push(
                (0..n)
                    .flat_map(|a| (0..n).map(move |b| (a, b)))
                    .map(|(a, b)| m[(a, b)] * f(&xs[a], &xs[b]))
                    .sum(),
            );
        }
        let Some(sol) = project(&rows, &targets, &m0, &weight) else {
            break;
        };
        let mut mt = DMatrix::zeros(n, n);
        for (&(a, b), v) in vars.iter().zip(sol.iter()) {
            mt[(a, b)] = *v;
            mt[(b, a)] = *v;
        }
        // A level whose projection is indefinite is skipped; a higher one may be PSD again
        // (1D P2: total + first moment alone is indefinite, all three moments give a Gram matrix).
        if is_psd(&mt) {
            best = (mt, kept);
        }
    }
    best
}

/// Node coordinates relative to the first node, divided by the largest offset (moments are
/// affine-invariant as a group, and this keeps the constraint matrix well scaled).
pub(crate) fn relative_coords(x: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let x0 = x[0];
    let scale = x
        .iter()
        .flat_map(|p| (0..3).map(move |k| (p[k] - x0[k]).abs()))
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    x.iter()
        .map(|p| std::array::from_fn(|k| (p[k] - x0[k]) / scale))
        .collect()
}

/// Weight of the unknown `m_ab` in a symmetric functional `Σ_ab f M_ab` (off-diagonal counted twice).
fn weight_of(a: usize, b: usize) -> f64 {
    if a == b {
        1.0
    } else {
        2.0
    }
}

/// `argmin Σ w_k (m_k − m0_k)²` subject to `G m = c`: `m = m0 + W⁻¹Gᵀ(G W⁻¹ Gᵀ)⁻¹(c − G m0)`.
/// None when the constraints are dependent or more numerous than the unknowns.
fn project(
    rows: &[Vec<f64>],
    c: &[f64],
    m0: &DVector<f64>,
    w: &DVector<f64>,
) -> Option<DVector<f64>> {
    let (k, nv) = (rows.len(), m0.len());
    if k > nv {
        return None;
    }
    let g = DMatrix::from_fn(k, nv, |i, j| rows[i][j]);
    let winv_gt = DMatrix::from_fn(nv, k, |j, i| g[(i, j)] / w[j]);
    let s = &g * &winv_gt;
    let svd = s.clone().svd(false, false);
    let smax = svd.singular_values.max();
    if svd.singular_values.min() <= 1e-12 * smax {
        return None;
    }
    let r = DVector::from_column_slice(c) - &g * m0;
    let mu = s.lu().solve(&r)?;
    Some(m0 + winv_gt * mu)
}

fn is_psd(m: &DMatrix<f64>) -> bool {
    let eig = m.clone().symmetric_eigen();
    let scale = eig.eigenvalues.amax().max(f64::MIN_POSITIVE);
    eig.eigenvalues.iter().all(|&l| l >= -1e-12 * scale)
}
