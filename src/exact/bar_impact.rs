//! Exact solution of the 1D bar impact (`shared/reference/bar_impact.md`, Doyen–Ern–Piperno 2011).
//!
//! Unit problem: bar (0, 1), E = ρ = 1, clamped at x = 1, `u(0, t) ≥ 0`, `u₀ = ½ − x/2`, `v₀ = 0`.
//! Period 3; with τ = t mod 3, phase n = ⌊τ⌋, s = τ − n and the zones of the characteristics
//! x = s, x = 1 − s, `u` is piecewise linear (table of the reference). Scaled problem (bar (0, L),
//! E, ρ, c = √(E/ρ), `u₀ = a (1 − x/L)`): `u(x, t) = 2a U(x/L, c t/L)` (`methods.md`).

use super::{ContactValues, ExactContact, PiecewiseLinearBar};

/// The bar impact solution for length `length`, modulus `young`, density `density`, lift `lift`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarImpact {
    /// L.
    pub length: f64,
    /// E.
    pub young: f64,
    /// ρ.
    pub density: f64,
    /// a = u₀(0).
    pub lift: f64,
}

/// `(u, u_x, u_t)` of the unit solution at (x, t).
pub fn unit(x: f64, t: f64) -> (f64, f64, f64) {
    let tau = t.rem_euclid(3.0);
    let phase = (tau.floor() as usize).min(2);
    let s = tau - phase as f64;
    let from_left = s > x;
    let from_right = s > 1.0 - x;
    // (u, u_x, u_t) per phase and zone I (neither), II (left only), III (right only), IV (both).
    match (phase, from_left, from_right) {
        (0, false, _) => (0.5 - x / 2.0, -0.5, 0.0),
        (0, true, _) => (0.5 - s / 2.0, 0.0, -0.5),
        (1, false, false) => (-s / 2.0, 0.0, -0.5),
        (1, true, false) => (-x / 2.0, -0.5, 0.0),
        (1, false, true) => (-0.5 + x / 2.0, 0.5, 0.0),
        (1, true, true) => (-0.5 + s / 2.0, 0.0, 0.5),
        (_, _, false) => (s / 2.0, 0.0, 0.5),
        (_, _, true) => (0.5 - x / 2.0, -0.5, 0.0),
    }
}

impl BarImpact {
    /// Wave speed c = √(E/ρ).
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }
}

impl PiecewiseLinearBar for BarImpact {
    fn length(&self) -> f64 {
        self.length
    }

    fn young(&self) -> f64 {
        self.young
    }

    fn density(&self) -> f64 {
        self.density
    }

    fn field(&self, x: f64, t: f64) -> (f64, f64, f64) {
        let (l, c, a) = (self.length, self.wave_speed(), self.lift);
        let (u, ux, ut) = unit(x / l, c * t / l);
        (
            2.0 * a * u,
            self.young * 2.0 * a * ux / l,
            2.0 * a * ut * c / l,
        )
    }

    /// The characteristics x = sL, (1 − s)L of the current phase (s = frac(c t / L)).
    fn kinks(&self, t: f64) -> [f64; 2] {
        let l = self.length;
        let frac = (self.wave_speed() * t / l).rem_euclid(3.0).fract();
        let mut kinks = [frac * l, (1.0 - frac) * l];
        kinks.sort_by(f64::total_cmp);
        kinks
    }
}

impl ExactContact for BarImpact {
    /// At x = 0. Where the gap is open the end is traction free (σ_N = 0); this also fixes the
    /// instants t = 3k L/c, where the table's zone I would give the bulk value σ = −E a/L.
    fn contact(&self, t: f64) -> ContactValues {
        let (u, sigma, v) = self.field(0.0, t);
        let sigma = if u > 0.0 { 0.0 } else { sigma };
        ContactValues { u, v, sigma }
    }

    /// `E a² / (2L)` (unit section).
    fn energy(&self, _t: f64) -> f64 {
        self.young * self.lift * self.lift / (2.0 * self.length)
    }

    /// The free end reaches the obstacle at t = L/c (if lifted).
    fn first_impact(&self) -> Option<f64> {
        (self.lift > 0.0).then(|| self.length / self.wave_speed())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BAR: BarImpact = BarImpact {
        length: 1.0,
        young: 1.0,
        density: 1.0,
        lift: 0.5,
    };

    fn sample_times() -> impl Iterator<Item = f64> {
        (0..=600).map(|k| k as f64 * 0.01 + 0.0013)
    }

    /// Distance of (x, t) to the characteristics x = s, x = 1 − s of its phase.
    fn off_characteristics(x: f64, t: f64, d: f64) -> bool {
        let s = t.rem_euclid(3.0).fract();
        (s - x).abs() > d && (1.0 - s - x).abs() > d && s > d && s < 1.0 - d
    }

    #[test]
    fn bar_solution_satisfies_the_wave_equation_away_from_characteristics() {
        let h = 1e-3;
        let mut checked = 0;
        for t in sample_times() {
            for k in 1..20 {
                let x = k as f64 / 20.0;
                if !off_characteristics(x, t, 3.0 * h) {
                    continue;
                }
                let u = |x: f64, t: f64| BAR.field(x, t).0;
                let utt = (u(x, t + h) - 2.0 * u(x, t) + u(x, t - h)) / (h * h);
                let uxx = (u(x + h, t) - 2.0 * u(x, t) + u(x - h, t)) / (h * h);
                assert!((utt - uxx).abs() < 1e-6, "x={x} t={t}: {utt} vs {uxx}");
                let ut_fd = (u(x, t + h) - u(x, t - h)) / (2.0 * h);
                assert!((ut_fd - BAR.field(x, t).2).abs() < 1e-9);
                checked += 1;
            }
        }
        assert!(checked > 5000);
    }

    #[test]
    fn bar_solution_satisfies_the_boundary_and_contact_conditions() {
        for t in sample_times() {
            assert_eq!(BAR.field(1.0, t).0, 0.0, "clamp at t={t}");
            let c = BAR.contact(t);
            assert!(
                c.u >= 0.0 && c.sigma <= 0.0 && (c.u * c.sigma).abs() < 1e-15,
                "t={t}: {c:?}"
            );
        }
        assert_eq!(BAR.contact(1.5).sigma, -0.5);
        assert_eq!(BAR.contact(0.5).v, -0.5);
    }

    #[test]
    fn bar_solution_is_continuous_periodic_and_conserves_energy() {
        for t in sample_times() {
            let n = 2000;
            let energy: f64 = (0..n)
                .map(|i| {
                    let x = (i as f64 + 0.5) / n as f64;
                    let (_, sigma, v) = BAR.field(x, t);
                    0.5 * (v * v + sigma * sigma) / n as f64
                })
                .sum();
            assert!((energy - 0.125).abs() < 2e-3, "t={t}: E={energy}");
            for k in 0..=10 {
                let x = k as f64 / 10.0;
                assert!((BAR.field(x, t).0 - BAR.field(x, t + 3.0).0).abs() < 1e-12);
                let eps = 1e-9;
                assert!((BAR.field(x, t).0 - BAR.field(x + eps, t).0).abs() < 1e-8);
            }
        }
        for tc in [1.0, 2.0, 3.0] {
            for k in 0..=10 {
                let x = k as f64 / 10.0;
                let jump = BAR.field(x, tc - 1e-10).0 - BAR.field(x, tc + 1e-10).0;
                assert!(jump.abs() < 1e-9, "jump at t={tc}, x={x}");
            }
        }
    }

    #[test]
    fn scaled_bar_has_the_published_period_pressure_and_energy() {
        let bar = BarImpact {
            length: 2.0,
            young: 4.0,
            density: 1.0,
            lift: 0.1,
        };
        // c = 2, period 3L/c = 3, contact phase t ∈ (1, 2), pressure E a / L = 0.2.
        assert!((bar.contact(1.5).sigma + 0.2).abs() < 1e-14);
        assert!((bar.contact(4.5).sigma + 0.2).abs() < 1e-14);
        assert_eq!(bar.contact(2.5).sigma, 0.0);
        assert!((bar.energy(0.0) - 4.0 * 0.01 / 4.0).abs() < 1e-15);
    }
}
