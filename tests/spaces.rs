//! Properties of the space discretisations on the 1D bar (DESIGN.md §3, methods.md worked numbers).

mod common;

use common::{run_spec, UNIT_BAR};
use dyncontact::cases::bar1d::Bar1d;
use dyncontact::linalg::to_dense;
use dyncontact::space::singular_dynamic::{inf_sup_holds, mixed_matrices, rank};
use dyncontact::space::{self, by_name, MassModel};
use nalgebra::{DMatrix, DVector};

/// An unclamped bar (0, 1), ρ = 1, with `n` elements of degree `degree` (no Dirichlet dof, so the
/// full mass is visible).
fn free_bar(n: usize, degree: usize) -> Bar1d {
    Bar1d::new(
        UNIT_BAR,
        n,
        degree,
        false,
        run_spec("standard", 0.5, 0.5, 0.01, 1.0),
    )
    .unwrap()
}

/// Dense M of a space (tests only: small sizes).
fn dense_mass(model: &MassModel, space: &str) -> DMatrix<f64> {
    let inertia = by_name(space).unwrap().inertia(model).unwrap();
    match inertia.sparse() {
        Some(m) => to_dense(m),
        None => {
            let n = model.n_dofs;
            DMatrix::from_fn(n, n, |i, j| {
                let mut e = vec![0.0; n];
                e[j] = 1.0;
                inertia.mass_times(&e).unwrap()[i]
            })
        }
    }
}

fn coords(bar: &Bar1d) -> DVector<f64> {
    DVector::from_iterator(
        bar.fem.mesh.nodes.len(),
        bar.fem.mesh.nodes.iter().map(|x| x[0]),
    )
}

fn assert_symmetric_psd(m: &DMatrix<f64>, what: &str) {
    assert!((m - m.transpose()).amax() < 1e-14, "{what}: not symmetric");
    let min = m.clone().symmetric_eigen().eigenvalues.min();
    assert!(min > -1e-13, "{what}: not PSD (λ_min = {min:e})");
}

#[test]
fn every_space_but_mass_elimination_conserves_the_total_mass() {
    for degree in [1, 2] {
        let bar = free_bar(4, degree);
        let model = bar.mass_model();
        let ones = DVector::from_element(model.n_dofs, 1.0);
        for space in &space::names() {
            if *space == "singular_dynamic" && degree == 1 {
                continue;
            }
            let total = (ones.transpose() * dense_mass(&model, space) * &ones)[0];
            let expected = if *space == "mass_elimination" {
                1.0 - 0.25
            } else {
                1.0
            };
            assert!(
                (total - expected).abs() < 1e-13,
                "{space} P{degree}: total mass {total}"
            );
        }
    }
}

#[test]
fn mass_redistribution_p1_matches_the_worked_numbers_and_keeps_the_total_mass() {
    // methods.md: first element becomes [[0, 0], [0, h]], so M̃₁₁ = h + h/3 = 4h/3.
    let bar = free_bar(4, 1);
    let m = dense_mass(&bar.mass_model(), "mass_redistribution");
    let h = 0.25;
    assert!(
        m.row(0).amax() == 0.0 && m.column(0).amax() == 0.0,
        "contact dof has inertia"
    );
    assert!((m[(1, 1)] - 4.0 * h / 3.0).abs() < 1e-15);
    assert_symmetric_psd(&m, "P1 M̃");
    let rank = rank(&m);
    assert_eq!(rank, m.nrows() - 1, "ker M̃ must be exactly the contact dof");
}

#[test]
fn mass_redistribution_p2_keeps_total_mass_and_first_and_second_moments() {
    for n in [2, 4, 8] {
        let bar = free_bar(n, 2);
        let model = bar.mass_model();
        let m0 = dense_mass(&model, "standard");
        let m = dense_mass(&model, "mass_redistribution");
        let x = coords(&bar);
        let one = DVector::from_element(x.len(), 1.0);
        assert!(m.row(0).amax() < 1e-15 && m.column(0).amax() < 1e-15);
        assert_symmetric_psd(&m, "P2 M̃");
        assert_eq!(rank(&m), m.nrows() - 1);
        for (name, a, b) in [
            ("total", &one, &one),
            ("first", &x, &one),
            ("second", &x, &x),
        ] {
            let kept = (a.transpose() * &m * b)[0];
            let orig = (a.transpose() * &m0 * b)[0];
            assert!(
                (kept - orig).abs() < 1e-14,
                "N={n}: {name} moment {kept} vs {orig}"
            );
        }
    }
}

#[test]
fn mass_elimination_makes_the_contact_dof_massless_and_loses_the_first_element() {
    let bar = free_bar(4, 1);
    let m = dense_mass(&bar.mass_model(), "mass_elimination");
    assert!(m.row(0).amax() == 0.0);
    assert!((m[(1, 1)] - 0.25 / 3.0).abs() < 1e-15);
}

#[test]
fn lumped_mass_is_diagonal_and_positive_for_p1_and_p2() {
    for degree in [1, 2] {
        let m = dense_mass(&free_bar(4, degree).mass_model(), "lumped");
        assert!((&m - DMatrix::from_diagonal(&m.diagonal())).amax() == 0.0);
        assert!(m.diagonal().min() > 0.0);
    }
}

#[test]
fn singular_dynamic_reproduces_the_worked_numbers() {
    // methods.md: rank M = N + 1, M symmetric PSD, 1ᵀM1 = 1, M₀₀·N = 7/72, 97/1008, 0.096225045,
    // and the inf-sup rank condition at the contact dof.
    for (n, m00n) in [(2, 7.0 / 72.0), (4, 97.0 / 1008.0), (8, 0.096225045)] {
        let bar = free_bar(n, 2);
        let model = bar.mass_model();
        let m = dense_mass(&model, "singular_dynamic");
        assert_symmetric_psd(&m, "Bᵀ C⁻¹ B");
        assert_eq!(rank(&m), n + 1, "rank M = dim H_h");
        let one = DVector::from_element(m.nrows(), 1.0);
        assert!(((one.transpose() * &m * &one)[0] - 1.0).abs() < 1e-13);
        assert!(
            (m[(0, 0)] * n as f64 - m00n).abs() < 1e-9,
            "N={n}: M00·N = {}",
            m[(0, 0)] * n as f64
        );
        let (b, _) = mixed_matrices(&model).unwrap();
        assert!(
            inf_sup_holds(&to_dense(&b), &model.contact_dofs),
            "inf-sup fails for N={n}"
        );
        // The contact dof keeps mass, and M is dense: row 0 reaches the far end.
        assert!(m[(0, 0)] > 0.0 && m[(0, m.ncols() - 1)].abs() > 0.0);
    }
}

#[test]
fn singular_dynamic_with_p1_displacement_is_a_clear_error() {
    let err = by_name("singular_dynamic")
        .unwrap()
        .inertia(&free_bar(4, 1).mass_model())
        .unwrap_err();
    assert!(err.to_string().contains("degree 2"), "{err}");
}

/// Modified quadrature (notes/papers/modified_quadrature.md §3, N = 4, ρ = 1, contact at x = 0):
/// the contact dof massless, M̃ symmetric PSD, total mass 1 exactly; P1 first and second moments
/// 0.53125 and 0.34375 (the first element's mass at its far node), P2 first moment ½ exactly and
/// second 0.332031 (= ⅓ − h³/12). The P2 first element puts no weight on its far node, which
/// keeps the mass of the next element: only the contact dof is massless (rank n − 1).
#[test]
fn modified_quadrature_matches_the_worked_numbers() {
    for (degree, first, second) in [(1, 0.53125, 0.34375), (2, 0.5, 0.33203125)] {
        let bar = free_bar(4, degree);
        let m = dense_mass(&bar.mass_model(), "modified_quadrature");
        let x = coords(&bar);
        let one = DVector::from_element(x.len(), 1.0);
        assert!(m.row(0).amax() == 0.0 && m.column(0).amax() == 0.0);
        assert_symmetric_psd(&m, "modified quadrature");
        assert_eq!(rank(&m), m.nrows() - 1, "P{degree}");
        let moment = |a: &DVector<f64>, b: &DVector<f64>| (a.transpose() * &m * b)[0];
        assert!((moment(&one, &one) - 1.0).abs() < 1e-14, "P{degree} mass");
        assert!(
            (moment(&x, &one) - first).abs() < 1e-14,
            "P{degree} first moment"
        );
        assert!(
            (moment(&x, &x) - second).abs() < 1e-14,
            "P{degree} second moment"
        );
    }
}
