//! Contact solvers on random LCPs: the exact active-set solver and Clarabel's QP agree to 1e-8,
//! every solver agrees with the active set in any units, and every solver's output satisfies its
//! complementarity conditions.

use dyncontact::contact::penalty::Penalty;
use dyncontact::contact::{by_name, check_solution, Solver, SOLVERS};
use nalgebra::DMatrix;
use proptest::prelude::*;

/// A random SPD matrix `GᵀG/n + 0.1 I` (eigenvalues ≥ 0.1, moderate condition number).
fn spd(n: usize, g: &[f64]) -> DMatrix<f64> {
    let g = DMatrix::from_column_slice(n, n, &g[..n * n]);
    g.transpose() * &g / n as f64 + DMatrix::identity(n, n) * 0.1
}

fn lcp() -> impl Strategy<Value = (DMatrix<f64>, Vec<f64>)> {
    (1usize..12).prop_flat_map(|n| {
        (
            prop::collection::vec(-1.0f64..1.0, n * n),
            prop::collection::vec(-1.0f64..1.0, n),
        )
            .prop_map(move |(g, q)| (spd(n, &g), q))
    })
}

fn solve(name: &str, d: &DMatrix<f64>, q: &[f64]) -> Vec<f64> {
    let mut lambda = vec![0.0; q.len()];
    let exact = by_name(name.trim_start_matches("penalty_"), q.len()).unwrap();
    let mut solver: Box<dyn Solver> = if name.starts_with("penalty_") {
        Box::new(Penalty::new(1e-3, exact))
    } else {
        exact
    };
    solver.solve(d, q, &mut lambda).unwrap();
    lambda
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn active_set_and_clarabel_agree((d, q) in lcp()) {
        let exact = solve("active_set", &d, &q);
        let qp = solve("clarabel", &d, &q);
        check_solution(&d, &q, &exact, 1e-12).map_err(TestCaseError::fail)?;
        check_solution(&d, &q, &qp, 1e-8).map_err(TestCaseError::fail)?;
        for (a, b) in exact.iter().zip(&qp) {
            prop_assert!((a - b).abs() <= 1e-8, "active_set {a} vs clarabel {b}");
        }
    }

    /// Every solver of the LCP (the friction solvers without friction) agrees with the exact
    /// active set whatever the units: q and D scaled by 10^a and 10^b, a, b ∈ [−6, 6] (a step's
    /// forces are about 1e-4 on block2d). The bound, 1e-5 of the largest of ‖λ‖∞ and ‖q‖∞/‖D‖,
    /// is the solvers' tolerance on the residual relative to that scale, 1e-7 (De Saxcé's, the
    /// loosest), times D's condition number (up to about 100 here). An interior point with
    /// absolute tolerances failed on its first step at 1e-4.
    #[test]
    fn every_solver_agrees_with_the_active_set_in_any_units(
        (d, q) in lcp(), a in -6i32..=6, b in -6i32..=6,
    ) {
        let d = d * 10f64.powi(b);
        let q: Vec<f64> = q.iter().map(|v| v * 10f64.powi(a)).collect();
        let exact = solve("active_set", &d, &q);
        let qmax = q.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
        let scale = exact.iter().fold(qmax / d.amax(), |m: f64, v| m.max(v.abs()));
        for name in SOLVERS {
            let lambda = solve(name, &d, &q);
            let err = exact
                .iter()
                .zip(&lambda)
                .fold(0.0, |m: f64, (x, y)| m.max((x - y).abs()));
            prop_assert!(err <= 1e-5 * scale, "{name}: {err:e} against a scale of {scale:e}");
        }
    }

    /// Penalty: λ ≥ 0, and it solves the regularised LCP (D + εI), so g = −ελ ≥ −ε max λ.
    #[test]
    fn penalty_is_the_regularised_lcp((d, q) in lcp()) {
        let lambda = solve("penalty_active_set", &d, &q);
        let eps = 1e-3 * (0..q.len()).map(|i| d[(i, i)]).fold(0.0, f64::max);
        let reg = &d + DMatrix::identity(q.len(), q.len()) * eps;
        check_solution(&reg, &q, &lambda, 1e-12).map_err(TestCaseError::fail)?;
        let lmax = lambda.iter().copied().fold(0.0, f64::max);
        for i in 0..q.len() {
            let g = q[i] + (0..q.len()).map(|j| d[(i, j)] * lambda[j]).sum::<f64>();
            prop_assert!(lambda[i] >= 0.0 && g >= -eps * lmax - 1e-12);
        }
    }

    /// Points with q = +∞ are excluded (λ = 0) by every solver; the others are unaffected.
    #[test]
    fn excluded_points_get_no_pressure((d, mut q) in lcp()) {
        q[0] = f64::INFINITY;
        for name in ["active_set", "clarabel", "penalty_active_set", "penalty_clarabel"] {
            let lambda = solve(name, &d, &q);
            prop_assert_eq!(lambda[0], 0.0);
        }
        let exact = solve("active_set", &d, &q);
        check_solution(&d, &q, &exact, 1e-12).map_err(TestCaseError::fail)?;
    }
}

/// Points of compliances 1e-12 apart, `D = diag(1, ε)`, `q = (−1, −0.1 ε)`, both pressed: the
/// interior-point solvers give λ = (1, 0.1) to 1e-9 relative on each point. With one factor of
/// units for every point Clarabel saw the second point's terms at ε, and De Saxcé's residual
/// was 0.65 of the solution at ε = 1e-12 (one factor per point: `clarabel_qp::Units`). The
/// other solvers' tolerances are relative to the largest force (`active_set` leaves the second
/// point at 0, a penetration of 1e-13 against gaps of order one).
#[test]
fn points_of_very_different_compliance_are_solved_alike() {
    for eps in [1e-4, 1e-8, 1e-12] {
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![1.0, eps]));
        for name in ["clarabel", "de_saxce"] {
            let lambda = solve(name, &d, &[-1.0, -0.1 * eps]);
            let err = ((lambda[0] - 1.0).abs()).max((lambda[1] - 0.1).abs() / 0.1);
            assert!(err < 1e-9, "{name}, ε = {eps:e}: {lambda:?}");
        }
    }
}
