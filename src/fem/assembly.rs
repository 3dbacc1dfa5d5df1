//! Local element matrices by quadrature and their scatter into global sparse matrices.

use crate::element::quadrature::gauss_legendre_01;
use crate::element::segment::Segment;
use crate::error::Result;
use crate::linalg::{SpMat, TripletBuilder};
use nalgebra::DMatrix;

/// Element mass `M^K_ij = ∫_K ρ φ_i φ_j dx = ρ h ∫₀¹ φ̂_i φ̂_j dξ` for a segment of length `h`
/// (Gauss rule with p + 1 points: exact for the degree-2p integrand).
pub fn segment_mass(seg: Segment, h: f64, rho: f64) -> DMatrix<f64> {
    segment_mixed_mass(seg, seg, h, rho)
}

/// Element stiffness `K^K_ij = ∫_K E φ_i' φ_j' dx = (E/h) ∫₀¹ φ̂_i' φ̂_j' dξ`.
pub fn segment_stiffness(seg: Segment, h: f64, young: f64) -> DMatrix<f64> {
    let rule = gauss_legendre_01(seg.degree.max(1));
    let n = seg.n_nodes();
    DMatrix::from_fn(n, n, |i, j| {
        rule.iter()
            .map(|&(xi, w)| w * seg.derivative(i, xi) * seg.derivative(j, xi))
            .sum::<f64>()
            * young
            / h
    })
}

/// Mixed element mass `B^K_ij = ∫_K ρ ψ_i φ_j dx` (rows: basis `psi`, columns: basis `phi`).
pub fn segment_mixed_mass(psi: Segment, phi: Segment, h: f64, rho: f64) -> DMatrix<f64> {
    let rule = gauss_legendre_01((psi.degree + phi.degree) / 2 + 1);
    DMatrix::from_fn(psi.n_nodes(), phi.n_nodes(), |i, j| {
        rule.iter()
            .map(|&(xi, w)| w * psi.value(i, xi) * phi.value(j, xi))
            .sum::<f64>()
            * rho
            * h
    })
}

/// Scatters element matrices into an `nrows × ncols` sparse matrix. `rows`/`cols` map a local
/// index to the global one, or `None` for an eliminated (Dirichlet) dof, whose row/column is dropped.
pub fn assemble<'a>(
    nrows: usize,
    ncols: usize,
    elements: impl IntoIterator<Item = (Vec<Option<usize>>, Vec<Option<usize>>, &'a DMatrix<f64>)>,
) -> Result<SpMat> {
    let mut t = TripletBuilder::new(nrows, ncols);
    for (rows, cols, local) in elements {
        for (a, ra) in rows.iter().enumerate() {
            let Some(i) = *ra else { continue };
            for (b, cb) in cols.iter().enumerate() {
                if let Some(j) = *cb {
                    let v = local[(a, b)];
                    if v != 0.0 {
                        t.add(i, j, v);
                    }
                }
            }
        }
    }
    t.build()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &DMatrix<f64>, b: &DMatrix<f64>) -> bool {
        (a - b).abs().max() < 1e-14
    }

    #[test]
    fn p1_and_p2_element_matrices_match_the_closed_forms() {
        let (h, rho, e) = (0.25, 2.0, 3.0);
        let m1 = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]) * (rho * h / 6.0);
        let k1 = DMatrix::from_row_slice(2, 2, &[1.0, -1.0, -1.0, 1.0]) * (e / h);
        let m2 = DMatrix::from_row_slice(3, 3, &[4.0, 2.0, -1.0, 2.0, 16.0, 2.0, -1.0, 2.0, 4.0])
            * (rho * h / 30.0);
        let k2 = DMatrix::from_row_slice(3, 3, &[7.0, -8.0, 1.0, -8.0, 16.0, -8.0, 1.0, -8.0, 7.0])
            * (e / (3.0 * h));
        assert!(close(&segment_mass(Segment { degree: 1 }, h, rho), &m1));
        assert!(close(&segment_stiffness(Segment { degree: 1 }, h, e), &k1));
        assert!(close(&segment_mass(Segment { degree: 2 }, h, rho), &m2));
        assert!(close(&segment_stiffness(Segment { degree: 2 }, h, e), &k2));
    }
}
