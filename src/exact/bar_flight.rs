//! Exact solution of a free bar flying onto a rigid plane (d'Alembert; issue 23 §2).
//!
//! Bar (0, L) of unit cross-section, E, ρ, c = √(E/ρ), no clamp; unilateral contact at x = 0,
//! `g = u(0, t) ≥ 0`. Initial state: a rigid translation `u₀ = d ≥ 0` (the gap) at velocity
//! `−v₀` (towards the plane). The end touches at `t₀ = d / v₀`; with `τ = t − t₀`:
//!
//! | τ | x < a(τ) (compressed, at rest) | x > a(τ) |
//! |---|---|---|
//! | τ ≤ 0 | — | `u = −v₀ τ`, σ = 0, `u_t = −v₀` |
//! | 0 < τ < L/c, a = cτ | `u = −v₀ x / c`, `σ = −ρ c v₀`, `u_t = 0` | `u = −v₀ τ`, σ = 0, `u_t = −v₀` |
//! | L/c ≤ τ < 2L/c, a = 2L − cτ | same | `u = v₀ (τ − 2L/c)`, σ = 0, `u_t = +v₀` |
//! | τ ≥ 2L/c | — | `u = v₀ (τ − 2L/c)`, σ = 0, `u_t = +v₀` |
//!
//! The compression front leaves the contact end at τ = 0, is reflected by the free end at
//! τ = L/c as an unloading front, and reaches x = 0 at τ = 2L/c: the contact lasts 2L/c with the
//! end stress `−ρ c v₀`, then the bar leaves at `+v₀` as a rigid body, with no vibration left.
//! The energy `½ ρ L v₀²` (kinetic density ½ρv₀² turned into the equal strain density
//! `σ² / (2E)`) is conserved; the momentum changes from `−ρ L v₀` to `+ρ L v₀` by the impulse
//! `ρ c v₀ · 2L/c`.

use super::{ContactValues, ExactContact, PiecewiseLinearBar};

/// The free bar's flight: length `length`, modulus `young`, density `density`, speed `speed`
/// towards the plane and initial gap `gap`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarFlight {
    /// L.
    pub length: f64,
    /// E.
    pub young: f64,
    /// ρ.
    pub density: f64,
    /// v₀ > 0 (the bar moves towards the plane at `−v₀`).
    pub speed: f64,
    /// d = u₀ ≥ 0, the gap at t = 0.
    pub gap: f64,
}

impl BarFlight {
    /// Wave speed c = √(E/ρ).
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }

    /// Time of contact t₀ = d / v₀.
    pub fn touch(&self) -> f64 {
        self.gap / self.speed
    }

    /// Duration of the contact 2L/c.
    pub fn duration(&self) -> f64 {
        2.0 * self.length / self.wave_speed()
    }

    /// The end of the compressed zone (0, a) at time t (0 out of contact).
    fn front(&self, t: f64) -> f64 {
        let (l, c) = (self.length, self.wave_speed());
        let ct = c * (t - self.touch());
        if ct > 0.0 && ct < 2.0 * l {
            l - (l - ct).abs()
        } else {
            0.0
        }
    }
}

impl PiecewiseLinearBar for BarFlight {
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
        let (c, v0) = (self.wave_speed(), self.speed);
        let tau = t - self.touch();
        // Written so that u = +0 (not −0) at x = 0 and at τ = 0.
        if x < self.front(t) {
            (0.0 - v0 * x / c, -self.density * c * v0, 0.0)
        } else if c * tau < self.length {
            (v0 * (self.touch() - t), 0.0, -v0)
        } else {
            (v0 * (tau - self.duration()), 0.0, v0)
        }
    }

    /// The front, twice, while in contact; L (no kink inside) otherwise.
    fn kinks(&self, t: f64) -> [f64; 2] {
        let a = self.front(t);
        let a = if a > 0.0 { a } else { self.length };
        [a, a]
    }
}

impl ExactContact for BarFlight {
    /// At x = 0: σ_N = −ρ c v₀ on (t₀, t₀ + 2L/c), 0 elsewhere.
    fn contact(&self, t: f64) -> ContactValues {
        let (u, sigma, v) = self.field(0.0, t);
        ContactValues { u, v, sigma }
    }

    /// `½ ρ L v₀²` (unit section).
    fn energy(&self, _t: f64) -> f64 {
        0.5 * self.density * self.length * self.speed * self.speed
    }

    /// t₀ = d / v₀.
    fn first_impact(&self) -> Option<f64> {
        Some(self.touch())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bar (touching at t = 0), and a scaled one with a gap: c = 2, t₀ = 0.6,
    /// contact until 2.6, end stress −ρ c v₀ = −2.
    const UNIT: BarFlight = BarFlight {
        length: 1.0,
        young: 1.0,
        density: 1.0,
        speed: 1.0,
        gap: 0.0,
    };
    const GAP: BarFlight = BarFlight {
        length: 2.0,
        young: 8.0,
        density: 2.0,
        speed: 0.5,
        gap: 0.3,
    };

    fn sample_times(bar: &BarFlight) -> impl Iterator<Item = f64> + '_ {
        let end = bar.touch() + 2.0 * bar.duration();
        (0..=800).map(move |k| k as f64 / 800.0 * end + 0.00137)
    }

    #[test]
    fn flight_solution_satisfies_the_wave_equation_away_from_the_front() {
        let h = 1e-4;
        for bar in [UNIT, GAP] {
            let (l, c) = (bar.length, bar.wave_speed());
            let mut checked = 0;
            for t in sample_times(&bar) {
                for k in 1..20 {
                    let x = k as f64 / 20.0 * l;
                    // The front and its passage through the ends.
                    let a = bar.front(t);
                    let tau = t - bar.touch();
                    let near = [a - x, tau * c, tau * c - l, tau * c - 2.0 * l];
                    if near.iter().any(|d| d.abs() < 4.0 * c * h) {
                        continue;
                    }
                    let u = |x: f64, t: f64| bar.field(x, t).0;
                    let utt = (u(x, t + h) - 2.0 * u(x, t) + u(x, t - h)) / (h * h);
                    let uxx = (u(x + h, t) - 2.0 * u(x, t) + u(x - h, t)) / (h * h);
                    assert!((utt - c * c * uxx).abs() < 1e-5, "x={x} t={t}");
                    let (_, sigma, ut) = bar.field(x, t);
                    let ut_fd = (u(x, t + h) - u(x, t - h)) / (2.0 * h);
                    let ux_fd = (u(x + h, t) - u(x - h, t)) / (2.0 * h);
                    assert!((ut_fd - ut).abs() < 1e-9, "u_t at x={x} t={t}");
                    assert!((bar.young * ux_fd - sigma).abs() < 1e-9, "σ at x={x} t={t}");
                    checked += 1;
                }
            }
            assert!(checked > 12_000, "{checked}");
        }
    }

    #[test]
    fn flight_solution_satisfies_the_boundary_and_contact_conditions() {
        for bar in [UNIT, GAP] {
            let (t0, tc) = (bar.touch(), bar.duration());
            let stress = -bar.density * bar.wave_speed() * bar.speed;
            for t in sample_times(&bar) {
                assert_eq!(bar.field(bar.length, t).1, 0.0, "free end at t={t}");
                let c = bar.contact(t);
                assert!(
                    c.u >= 0.0 && c.sigma <= 0.0 && c.u * c.sigma == 0.0,
                    "{c:?}"
                );
                let in_contact = t > t0 && t < t0 + tc;
                assert_eq!(c.sigma, if in_contact { stress } else { 0.0 }, "t={t}");
                assert_eq!(c.u == 0.0, in_contact, "t={t}");
                // Before: rigid flight at −v₀; after: at +v₀ with no vibration (σ = 0 and
                // u_t = v₀ at every point).
                if !in_contact {
                    let v = if t <= t0 { -bar.speed } else { bar.speed };
                    for k in 0..=10 {
                        let (_, s, ut) = bar.field(k as f64 / 10.0 * bar.length, t);
                        assert_eq!((s, ut), (0.0, v), "t={t}");
                    }
                }
            }
            assert_eq!(bar.contact(0.0).u, bar.gap);
            assert_eq!(bar.first_impact(), Some(t0));
        }
        assert_eq!(GAP.contact(0.7).sigma, -2.0);
        assert_eq!((GAP.touch(), GAP.duration()), (0.6, 2.0));
    }

    #[test]
    fn flight_solution_is_continuous_and_conserves_energy_with_newtons_law() {
        for bar in [UNIT, GAP] {
            let (l, rho, v0) = (bar.length, bar.density, bar.speed);
            let e0 = bar.energy(0.0);
            assert_eq!(e0, 0.5 * rho * l * v0 * v0);
            let n = 4000;
            let dx = l / n as f64;
            let mid = |i: usize| (i as f64 + 0.5) * dx;
            for t in sample_times(&bar) {
                let (energy, momentum) = (0..n).fold((0.0, 0.0), |(e, p), i| {
                    let (_, sigma, v) = bar.field(mid(i), t);
                    let density = 0.5 * rho * v * v + 0.5 * sigma * sigma / bar.young;
                    (e + density * dx, p + rho * v * dx)
                });
                // The strain energy density σ²/(2E) of the compressed zone equals the kinetic
                // ½ρv₀² it replaces: the density is uniform, the sum exact to round-off.
                assert!((energy - e0).abs() < 1e-12 * e0, "E={energy} at t={t}");
                // dp/dt = −σ(0, t): the impulse ρ c v₀ (t − t₀) on the contact interval.
                let tau = (t - bar.touch()).clamp(0.0, bar.duration());
                let p = -rho * l * v0 + rho * bar.wave_speed() * v0 * tau;
                assert!(
                    (momentum - p).abs() < 2.0 * rho * v0 * dx,
                    "p={momentum} at t={t}"
                );
                for k in 0..=10 {
                    let x = k as f64 / 10.0 * l;
                    let jump = bar.field(x + 1e-10, t).0 - bar.field(x, t).0;
                    assert!(jump.abs() < 1e-9, "x={x} t={t}");
                    let jump = bar.field(x, t + 1e-10).0 - bar.field(x, t).0;
                    assert!(jump.abs() < 1e-9, "x={x} t={t}");
                }
            }
        }
    }

    #[test]
    fn kinks_are_the_front_in_contact_and_none_in_flight() {
        assert_eq!(UNIT.kinks(0.25), [0.25, 0.25]);
        assert_eq!(UNIT.kinks(1.25), [0.75, 0.75]);
        assert_eq!(UNIT.kinks(2.5), [1.0, 1.0]);
        assert_eq!(GAP.kinks(0.5), [2.0, 2.0]);
        assert!((GAP.kinks(0.7)[0] - 0.2).abs() < 1e-12);
    }
}
