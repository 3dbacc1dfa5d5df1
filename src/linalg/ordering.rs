//! Fill-reducing orderings of the sparse factorisations ([`super::Factor`]), chosen by
//! [`Ordering::of`]:
//! - a narrow band (1D meshes) keeps its own order, which has no fill;
//! - below [`NESTED_DISSECTION_DOFS`], faer's approximate minimum degree (AMD: Amestoy, Davis &
//!   Duff, SIAM J. Matrix Anal. Appl. 17, 1996);
//! - from there on, nested dissection (George, SIAM J. Numer. Anal. 10, 1973) by METIS
//!   (`METIS_NodeND`, Karypis & Kumar, SIAM J. Sci. Comput. 20, 1998): a vertex separator of the
//!   matrix graph is numbered last and each half ordered the same way, so that the fill stays
//!   within the separators. On 3D meshes its factors are about half AMD's, and never larger on
//!   the 2D ones measured. Entries of L, AMD → nested dissection: the singular dynamic Q2 sphere
//!   (hertz3d n = 8, saddle system of 58 470 unknowns) 168.8M → 85.0M, that run 86 → 53 s wall,
//!   2.5 → 1.6 GB; K of the default sphere (51 651 dofs) 104.3M → 55.5M; the n = 8 sphere (6 819
//!   dofs) 5.5M → 3.2M, oblique3d's run 5.3 → 3.8 s; hertz2d n = 24 (3 554 dofs) 241k → 179k.
//!   Below [`NESTED_DISSECTION_DOFS`] either is instant.
//!
//! METIS runs on the graph of the pattern without the diagonal, with its default options. Its
//! random generator is global state reseeded with a fixed seed at each call, and each call
//! replaces the process's SIGTERM and SIGABRT handlers until it returns: the calls are serialised
//! ([`METIS`]), so that the same matrix gets the same ordering on any thread and the handlers
//! are restored in order. (The `dyncontact` binary receives SIGTERM on a thread of its own,
//! `main.rs`, so that a kill during an ordering terminates the process as usual.)

use super::sparse::{bandwidth, SpMat, NARROW_BAND};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::SymmetricOrdering;

/// One METIS call at a time (global random state and signal handlers, see the module doc).
static METIS: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Order from which [`Ordering::of`] takes nested dissection instead of AMD.
pub const NESTED_DISSECTION_DOFS: usize = 1_000;

/// A symmetric fill-reducing ordering.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Ordering {
    /// The matrix's own order.
    Natural,
    /// faer's approximate minimum degree.
    Amd,
    /// A permutation `(forward, inverse)`: position k of the factored matrix is row
    /// `forward[k]` of A, and `inverse[forward[k]] = k`.
    Permutation(Vec<usize>, Vec<usize>),
}

impl Ordering {
    /// The ordering for factoring `a` (symmetric pattern): its own for a narrow band, AMD below
    /// [`NESTED_DISSECTION_DOFS`], nested dissection above (AMD when METIS cannot order it).
    pub fn of(a: &SpMat) -> Self {
        let n = a.nrows();
        if bandwidth(a) <= NARROW_BAND {
            Self::Natural
        } else if n < NESTED_DISSECTION_DOFS {
            Self::Amd
        } else {
            nested_dissection(a).map_or(Self::Amd, |(fwd, inv)| Self::Permutation(fwd, inv))
        }
    }

    /// faer's view of the ordering of a matrix of order n (`identity`: 0..n, for
    /// [`Ordering::Natural`]).
    pub fn faer<'a>(&'a self, identity: &'a [usize]) -> SymmetricOrdering<'a, usize> {
        let n = identity.len();
        match self {
            Self::Natural => SymmetricOrdering::Custom(PermRef::new_checked(identity, identity, n)),
            Self::Amd => SymmetricOrdering::Amd,
            Self::Permutation(fwd, inv) => {
                SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, n))
            }
        }
    }
}

/// METIS's nested dissection of the graph of `a` (its pattern without the diagonal, made
/// symmetric), as `(forward, inverse)`; None when the graph is too large for METIS's 32-bit
/// indices or METIS fails.
pub fn nested_dissection(a: &SpMat) -> Option<(Vec<usize>, Vec<usize>)> {
    let n = a.nrows();
    let (mut xadj, mut adjncy) = graph(a)?;
    let mut nvtxs = i32::try_from(n).ok()?;
    let (mut perm, mut iperm) = (vec![0_i32; n], vec![0_i32; n]);
    let mut options = [0_i32; metis_sys::METIS_NOPTIONS as usize];
    // SAFETY: METIS reads `nvtxs`, `xadj` (n + 1 offsets) and `adjncy` (xadj[n] neighbours, each
    // in 0..n, no self-loop: `graph`) and writes n entries to each of `perm` and `iperm`; the
    // options array has METIS_NOPTIONS entries, set to the defaults first. A null vertex weight
    // means unit weights. METIS keeps no pointer after returning.
    let _one_at_a_time = METIS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return None;
    }
    let to_usize = |v: Vec<i32>| v.into_iter().map(|k| usize::try_from(k).ok()).collect();
    let (fwd, inv): (Option<Vec<usize>>, Option<Vec<usize>>) = (to_usize(perm), to_usize(iperm));
    let (fwd, inv) = (fwd?, inv?);
    // A permutation, and `inv` its inverse (faer checks this too, by panicking).
    (fwd.iter().enumerate().all(|(k, &i)| i < n && inv[i] == k)).then_some((fwd, inv))
}

/// The adjacency of the symmetrised pattern of `a` without its diagonal, in METIS's compressed
/// form `(xadj, adjncy)`; None past 32-bit indices.
fn graph(a: &SpMat) -> Option<(Vec<i32>, Vec<i32>)> {
    let n = a.nrows();
    let a = a.as_ref();
    let mut neighbours: Vec<Vec<i32>> = vec![Vec::new(); n];
    for j in 0..n {
        let j32 = i32::try_from(j).ok()?;
        for &i in a.row_idx_of_col_raw(j).iter().filter(|&&i| i != j) {
            neighbours[j].push(i32::try_from(i).ok()?);
            neighbours[i].push(j32);
        }
    }
    let mut xadj = Vec::with_capacity(n + 1);
    let mut adjncy = Vec::new();
    xadj.push(0);
    for mut list in neighbours {
        list.sort_unstable();
        list.dedup();
        adjncy.extend(list);
        xadj.push(i32::try_from(adjncy.len()).ok()?);
    }
    Some((xadj, adjncy))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::TripletBuilder;
    use faer::sparse::linalg::cholesky::factorize_symbolic_cholesky;
    use faer::Side;

    /// The 5-point Laplacian pattern of an m × m grid.
    fn grid(m: usize) -> SpMat {
        let mut t = TripletBuilder::new(m * m, m * m);
        for i in 0..m {
            for j in 0..m {
                let k = i * m + j;
                t.add(k, k, 4.0);
                if i + 1 < m {
                    t.add(k, k + m, -1.0);
                    t.add(k + m, k, -1.0);
                }
                if j + 1 < m {
                    t.add(k, k + 1, -1.0);
                    t.add(k + 1, k, -1.0);
                }
            }
        }
        t.build().unwrap()
    }

    fn fill(a: &SpMat, ordering: &Ordering) -> usize {
        let identity: Vec<usize> = (0..a.nrows()).collect();
        let s = factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Lower,
            ordering.faer(&identity),
            Default::default(),
        )
        .unwrap();
        s.len_val()
    }

    /// Nested dissection is a permutation with its inverse, the same on every call, and on a
    /// 2D grid its factor is smaller than the natural (banded) order's, whose fill grows as
    /// m³ against nested dissection's m² log m.
    #[test]
    fn nested_dissection_is_a_deterministic_permutation_with_less_fill() {
        let a = grid(60);
        let (fwd, inv) = nested_dissection(&a).unwrap();
        assert!(fwd.iter().enumerate().all(|(k, &i)| inv[i] == k));
        assert_eq!(nested_dissection(&a), Some((fwd.clone(), inv.clone())));
        let (natural, nd) = (
            fill(&a, &Ordering::Natural),
            fill(&a, &Ordering::Permutation(fwd, inv)),
        );
        assert!(
            2 * nd < natural,
            "nested dissection {nd}, natural {natural}"
        );
    }

    /// The choice by size and band.
    #[test]
    fn the_ordering_follows_the_size_and_the_band() {
        let mut t = TripletBuilder::new(30_000, 30_000);
        for i in 0..30_000 {
            t.add(i, i, 2.0);
            if i > 0 {
                t.add(i, i - 1, -1.0);
                t.add(i - 1, i, -1.0);
            }
        }
        assert_eq!(Ordering::of(&t.build().unwrap()), Ordering::Natural);
        assert_eq!(Ordering::of(&grid(20)), Ordering::Amd);
        assert!(matches!(
            Ordering::of(&grid(110)),
            Ordering::Permutation(..)
        ));
    }
}
