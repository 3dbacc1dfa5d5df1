//! The stability limit of the explicit schemes: `Δt ≤ 2/ω_max`, `ω²_max` the largest eigenvalue
//! of `(K', M)` on the dofs with mass, estimated before the run by a power iteration with the
//! Rayleigh quotient (`K'` the stiffness of the step: K, or K plus a penalty stiffness).

use crate::error::{Error, Result};

/// Power iterations of the CFL estimate (the Rayleigh quotient converges from below).
pub const CFL_ITERATIONS: usize = 300;
/// Safety factor on the estimated limit (the Rayleigh quotient underestimates ω²_max slightly).
pub const CFL_SAFETY: f64 = 0.99;

/// `2/ω_max` with `ω²_max` the largest eigenvalue of `(K', M)` restricted to the dofs that are not
/// `massless`, by the power iteration `x ← M⁻¹ K' x` and its Rayleigh quotient
/// `xᵀK'x / xᵀMx` (which converges from below). `stiffness(x, kx)` writes `K' x`, `mass(x)` is
/// `xᵀ M x` and `solve(r, x)` writes `M⁻¹ r` on the massive dofs. Infinite when `K'` or `M`
/// vanishes on every iterate.
pub fn critical_time_step(
    massless: &[bool],
    mut stiffness: impl FnMut(&[f64], &mut [f64]),
    mass: impl Fn(&[f64]) -> f64,
    mut solve: impl FnMut(&[f64], &mut [f64]) -> Result<()>,
) -> Result<f64> {
    let n = massless.len();
    // A deterministic start with every mode present.
    let mut x: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i * 7919) % 13) as f64 / 13.0)
        .collect();
    zero_where(&mut x, massless);
    let mut kx = vec![0.0; n];
    let mut omega2 = 0.0;
    for _ in 0..CFL_ITERATIONS {
        stiffness(&x, &mut kx);
        let mx = mass(&x);
        if mx <= 0.0 {
            return Ok(f64::INFINITY);
        }
        omega2 = f64::max(omega2, crate::linalg::dot(&x, &kx) / mx);
        zero_where(&mut kx, massless);
        solve(&kx, &mut x)?;
        zero_where(&mut x, massless);
        let norm = crate::linalg::dot(&x, &x).sqrt();
        if norm == 0.0 || !norm.is_finite() {
            break;
        }
        x.iter_mut().for_each(|v| *v /= norm);
    }
    Ok(if omega2 > 0.0 {
        2.0 / omega2.sqrt()
    } else {
        f64::INFINITY
    })
}

/// Refuses `run.dt` above `dt_max` (already scaled by [`CFL_SAFETY`]) for `scheme`, naming the
/// limit and what sets it (`of`: "this mesh and mass", …).
pub fn check_time_step(scheme: &str, dt: f64, dt_max: f64, of: &str) -> Result<()> {
    if dt > dt_max {
        return Err(Error::invalid(
            "run.dt",
            dt,
            &format!(
                "unstable time step: {scheme} needs dt ≤ {CFL_SAFETY}·2/ω_max = {dt_max:.6e} \
                 (CFL limit of {of})"
            ),
        ));
    }
    Ok(())
}

/// `x_i = 0` wherever `mask_i`.
pub fn zero_where(x: &mut [f64], mask: &[bool]) {
    for (xi, &m) in x.iter_mut().zip(mask) {
        if m {
            *xi = 0.0;
        }
    }
}
