//! Lagrange elements on a segment: P1 (nodes 0, 1) and P2 (nodes 0, ½, 1, in that local order).

/// Equispaced Lagrange basis of degree `p` on the reference segment [0, 1]. Local node k sits at
/// ξ_k = k/p, so local order is left-to-right (P2: left, mid, right).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Segment {
    /// Polynomial degree (1 or 2).
    pub degree: usize,
}

impl Segment {
    /// Number of local nodes, `p + 1`.
    pub fn n_nodes(&self) -> usize {
        self.degree + 1
    }

    /// Reference coordinate ξ_k = k/p of local node k.
    pub fn node(&self, k: usize) -> f64 {
        k as f64 / self.degree as f64
    }

    /// φ̂_k(ξ) = ∏_{m≠k} (ξ − ξ_m)/(ξ_k − ξ_m).
    pub fn value(&self, k: usize, xi: f64) -> f64 {
        (0..self.n_nodes())
            .filter(|&m| m != k)
            .map(|m| (xi - self.node(m)) / (self.node(k) - self.node(m)))
            .product()
    }

    /// dφ̂_k/dξ = Σ_{j≠k} 1/(ξ_k − ξ_j) ∏_{m≠k,j} (ξ − ξ_m)/(ξ_k − ξ_m) (product rule).
    pub fn derivative(&self, k: usize, xi: f64) -> f64 {
        let n = self.n_nodes();
        let (xk, node) = (self.node(k), |m| self.node(m));
        (0..n)
            .filter(|&j| j != k)
            .map(|j| {
                (0..n)
                    .filter(|&m| m != k && m != j)
                    .map(|m| (xi - node(m)) / (xk - node(m)))
                    .product::<f64>()
                    / (xk - node(j))
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_nodal_and_a_partition_of_unity() {
        for degree in 1..=2 {
            let s = Segment { degree };
            for k in 0..s.n_nodes() {
                for m in 0..s.n_nodes() {
                    let expect = if k == m { 1.0 } else { 0.0 };
                    assert!((s.value(k, s.node(m)) - expect).abs() < 1e-15);
                }
            }
            for xi in [0.1, 0.33, 0.8] {
                let sum: f64 = (0..s.n_nodes()).map(|k| s.value(k, xi)).sum();
                let dsum: f64 = (0..s.n_nodes()).map(|k| s.derivative(k, xi)).sum();
                assert!((sum - 1.0).abs() < 1e-14 && dsum.abs() < 1e-13);
            }
        }
    }
}
