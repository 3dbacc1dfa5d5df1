//! Gauss–Legendre quadrature.

/// Gauss–Legendre rule with `n` points on the reference interval [0, 1]: exact for polynomials of
/// degree ≤ 2n − 1. Nodes are the roots of the Legendre polynomial P_n (Newton iteration).
pub fn gauss_legendre_01(n: usize) -> Vec<(f64, f64)> {
    assert!(n >= 1, "a quadrature rule needs at least one point");
    (0..n)
        .map(|i| {
            // Chebyshev-like initial guess of the i-th root on [-1, 1], then Newton on P_n.
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(n, x);
            dp = if d != 0.0 { d } else { dp };
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            (0.5 * (1.0 - x), 0.5 * w)
        })
        .collect()
}

/// `(P_n(x), P_n'(x))` by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    if n == 0 {
        return (1.0, 0.0);
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_rules_integrate_monomials_up_to_degree_2n_minus_1() {
        for n in 1..=6 {
            let rule = gauss_legendre_01(n);
            for deg in 0..2 * n {
                let q: f64 = rule.iter().map(|(x, w)| w * x.powi(deg as i32)).sum();
                let exact = 1.0 / (deg as f64 + 1.0);
                assert!((q - exact).abs() < 1e-14, "n={n} deg={deg}: {q} vs {exact}");
            }
        }
    }
}
