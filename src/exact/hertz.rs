//! Quasi-static Hertz theory for the impact of an elastic sphere (3D) or disc (2D, plane strain)
//! on a rigid plane (Johnson, *Contact Mechanics*, 1985, §4.2, §11.4;
//! `shared/reference/hertz_impact.md`). `E* = E/(1 − ν²)`, R the radius, v the impact speed.
//!
//! Sphere: `F = k δ^{3/2}`, `k = (4/3) E* √R`; energy balance `½ m v² = (2/5) k δ_max^{5/2}` gives
//! `δ_max = (15 m v² / (16 E* √R))^{2/5}`, `F_max = k δ_max^{3/2}`, `t_c = 2.9433 δ_max / v`;
//! contact radius `a = (3 F R / (4 E*))^{1/3}`, peak pressure `p₀ = 3F / (2π a²)`.
//!
//! A finite body (compliance `c_f > 0`, measured by [`crate::study::finite_body`]): Hertz's δ is
//! the approach of points at infinity of a half-space; the centre of a sphere lies at depth R, so
//! its approach is `δ(F) = (F/k)^{2/3} − c_f F`. The quasi-static impact `m δ̈ = −F(δ)` then has
//! `W(F) = ∫F dδ = (2/5) k^{−2/3} F^{5/3} − ½ c_f F²`, `W(F_max) = ½ m v²`, and
//! `t_c = 2 ∫₀^{F_max} δ'(F) dF / √(v² − 2 W(F)/m)`; `c_f = 0` gives the closed forms above.
//!
//! Disc (line contact, per unit length): half-width `b = √(4 P R / (π E*))`, `p₀ = 2P / (π b)`;
//! the approach law has no closed form (it depends on the whole body), so neither have δ_max,
//! F_max nor t_c.

/// `2 ∫₀¹ dx / √(1 − x^{5/2})` (the sphere's duration factor; midpoint rule in x = 1 − s²).
pub const DURATION_FACTOR: f64 = 2.943_275_184;

/// Hertz impact of a sphere (`dim = 3`) or disc (`dim = 2`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hertz {
    /// 2 (disc, plane strain) or 3 (sphere).
    pub dim: usize,
    /// Radius R.
    pub radius: f64,
    /// `E* = E / (1 − ν²)`.
    pub e_star: f64,
    /// Mass (2D: per unit thickness).
    pub mass: f64,
    /// Impact speed v > 0.
    pub speed: f64,
    /// Finite-body compliance `c_f` (length per force): `δ(F) = (F/k)^{2/3} − c_f F` (0:
    /// Hertz's half-space; > 0 a stiffer body, < 0 a softer one).
    pub compliance: f64,
}

/// Quadrature points of the finite body's duration integral (smooth after the substitution).
const DURATION_POINTS: usize = 4000;

impl Hertz {
    /// The impact of a body of radius R, density ρ, Young's modulus E and Poisson ratio ν.
    pub fn new(
        dim: usize,
        radius: f64,
        density: f64,
        young: f64,
        poisson: f64,
        speed: f64,
    ) -> Self {
        let volume = if dim == 3 {
            4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
        } else {
            std::f64::consts::PI * radius * radius
        };
        Self {
            dim,
            radius,
            e_star: young / (1.0 - poisson * poisson),
            mass: density * volume,
            speed,
            compliance: 0.0,
        }
    }

    /// The same impact of a body of mass `mass` whose approach law has the finite-body
    /// compliance `c_f` (an error when the law stops increasing before F_max).
    pub fn finite_body(self, mass: f64, compliance: f64) -> crate::error::Result<Self> {
        crate::error::positive("finite body: mass", mass)?;
        crate::error::finite("finite body: compliance", compliance)?;
        let h = Self {
            mass,
            compliance,
            ..self
        };
        if h.dim == 3 && compliance > 0.0 && h.work(h.turning_force()) <= h.kinetic_energy() {
            return Err(crate::error::Error::invalid(
                "finite body: compliance",
                compliance,
                "the approach law δ(F) = (F/k)^{2/3} − c_f F must increase up to F_max",
            ));
        }
        Ok(h)
    }

    /// `k = (4/3) E* √R` (sphere).
    fn stiffness(&self) -> f64 {
        4.0 / 3.0 * self.e_star * self.radius.sqrt()
    }

    /// The approach under a total force F (sphere): `δ(F) = (F/k)^{2/3} − c_f F`.
    pub fn approach(&self, force: f64) -> f64 {
        (force / self.stiffness()).powf(2.0 / 3.0) - self.compliance * force
    }

    /// `δ'(F) = (2/3) k^{−2/3} F^{−1/3} − c_f`.
    fn approach_slope(&self, force: f64) -> f64 {
        2.0 / 3.0 * self.stiffness().powf(-2.0 / 3.0) * force.cbrt().recip() - self.compliance
    }

    /// The work `W(F) = ∫₀^F F dδ = (2/5) k^{−2/3} F^{5/3} − ½ c_f F²`.
    fn work(&self, force: f64) -> f64 {
        0.4 * self.stiffness().powf(-2.0 / 3.0) * force.powf(5.0 / 3.0)
            - 0.5 * self.compliance * force * force
    }

    /// `F* = (2 / (3 c_f k^{2/3}))³`, where δ(F) stops increasing (c_f > 0).
    fn turning_force(&self) -> f64 {
        (2.0 / (3.0 * self.compliance * self.stiffness().powf(2.0 / 3.0))).powi(3)
    }

    /// `½ m v²`.
    fn kinetic_energy(&self) -> f64 {
        0.5 * self.mass * self.speed * self.speed
    }

    /// The force at approach δ ≥ 0 (sphere; a finite body's δ below the maximum of its law):
    /// `k δ^{3/2}` for the half-space; for a finite body
    /// Newton on the concave, increasing `δ(F) − δ` from `k δ^{3/2}`: every iterate after the
    /// first lies below the root and increases to it.
    pub fn force(&self, approach: f64) -> f64 {
        let mut f = self.stiffness() * approach.max(0.0).powf(1.5);
        if self.compliance == 0.0 || f == 0.0 {
            return f;
        }
        for _ in 0..100 {
            let step = (self.approach(f) - approach) / self.approach_slope(f);
            f -= step;
            if step.abs() <= 1e-15 * f {
                break;
            }
        }
        f
    }

    /// Maximum approach δ_max (sphere only).
    pub fn max_approach(&self) -> Option<f64> {
        if self.compliance != 0.0 {
            return self.peak_force().map(|f| self.approach(f));
        }
        (self.dim == 3).then(|| {
            (15.0 * self.mass * self.speed.powi(2) / (16.0 * self.e_star * self.radius.sqrt()))
                .powf(0.4)
        })
    }

    /// Peak force `F_max = k δ_max^{3/2}` (sphere only); for a finite body, the root of
    /// `W(F) = ½ m v²` by bisection, above the half-space's when c_f > 0, below it when c_f < 0.
    pub fn peak_force(&self) -> Option<f64> {
        let half_space = Self {
            compliance: 0.0,
            ..*self
        };
        let f_hertz = half_space
            .max_approach()
            .map(|d| self.stiffness() * d.powf(1.5))?;
        if self.compliance == 0.0 {
            return Some(f_hertz);
        }
        // c_f > 0: W(F) < W_Hertz(F), so F_max lies above Hertz's, and W increases up to F*
        // ([`Self::finite_body`] checks that it reaches ½ m v² there); c_f < 0: below.
        let kinetic = self.kinetic_energy();
        let (mut lo, mut hi) = if self.compliance > 0.0 {
            (f_hertz, self.turning_force())
        } else {
            (0.0, f_hertz)
        };
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.work(mid) < kinetic {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }

    /// Contact duration `t_c = 2.9433 δ_max / v` (sphere only); for a finite body the integral
    /// `2 ∫₀^{F_max} δ'(F) dF / √(v² − 2W(F)/m)` in `F = F_max (1 − (1 − s³)²)`, which makes
    /// the integrand smooth at both ends, by the midpoint rule.
    pub fn duration(&self) -> Option<f64> {
        if self.compliance == 0.0 {
            return self
                .max_approach()
                .map(|d| DURATION_FACTOR * d / self.speed);
        }
        let f_max = self.peak_force()?;
        let n = DURATION_POINTS;
        let v2 = self.speed * self.speed;
        let sum: f64 = (0..n)
            .map(|i| {
                let s = (i as f64 + 0.5) / n as f64;
                let q = 1.0 - s * s * s;
                let f = f_max * (1.0 - q * q);
                let df = f_max * 6.0 * q * s * s;
                let kinetic = (v2 - 2.0 * self.work(f) / self.mass).max(0.0);
                self.approach_slope(f) * df / kinetic.sqrt()
            })
            .sum();
        Some(2.0 * sum / n as f64)
    }

    /// Contact radius a (sphere) or half-width b (disc) under a total force F (per unit length
    /// in 2D).
    pub fn contact_radius(&self, force: f64) -> f64 {
        if self.dim == 3 {
            (3.0 * force * self.radius / (4.0 * self.e_star)).cbrt()
        } else {
            (4.0 * force * self.radius / (std::f64::consts::PI * self.e_star)).sqrt()
        }
    }

    /// Peak pressure p₀ under a total force F.
    pub fn peak_pressure(&self, force: f64) -> f64 {
        let a = self.contact_radius(force);
        if self.dim == 3 {
            3.0 * force / (2.0 * std::f64::consts::PI * a * a)
        } else {
            2.0 * force / (std::f64::consts::PI * a)
        }
    }

    /// The quasi-static force history `F(t) = F(δ(t))` of the impact (sphere only), `steps + 1`
    /// samples over `[0, t_c]`: `m δ̈ = −F(δ)`, `δ(0) = 0`, `δ̇(0) = v`, integrated by RK4
    /// (error O(1/steps⁴) away from the ends).
    pub fn force_history(&self, steps: usize) -> Option<Vec<(f64, f64)>> {
        let t_c = self.duration()?;
        let dt = t_c / steps as f64;
        // (δ, δ̇) ↦ (δ̇, −F(δ) / m), δ clamped at 0 after release.
        let rhs = |y: [f64; 2]| [y[1], -self.force(y[0]) / self.mass];
        let mut y = [0.0, self.speed];
        let mut out = Vec::with_capacity(steps + 1);
        for n in 0..=steps {
            out.push((n as f64 * dt, self.force(y[0])));
            let k1 = rhs(y);
            let k2 = rhs([y[0] + 0.5 * dt * k1[0], y[1] + 0.5 * dt * k1[1]]);
            let k3 = rhs([y[0] + 0.5 * dt * k2[0], y[1] + 0.5 * dt * k2[1]]);
            let k4 = rhs([y[0] + dt * k3[0], y[1] + dt * k3[1]]);
            for c in 0..2 {
                y[c] += dt / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
            }
        }
        Some(out)
    }

    /// The ratio `Σ r² p / Σ p` of the Hertz pressure to `a²`: 2/5 (sphere) or 1/4 (disc). The
    /// contact radius of a computed pressure is `√(Σ r² λ / (Σ λ · ratio))`.
    pub fn second_moment_ratio(&self) -> f64 {
        if self.dim == 3 {
            0.4
        } else {
            0.25
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The worked numbers of `shared/reference/hertz_impact.md` (R = E = ρ = 1, ν = 0.3).
    #[test]
    fn sphere_matches_the_reference_table() {
        for (v, d, f, a, tc, p0) in [
            (0.01, 4.1806e-2, 1.2524e-2, 0.2045, 12.305, 0.1430),
            (0.001, 6.6258e-3, 7.9024e-4, 0.0814, 19.502, 0.0570),
        ] {
            let h = Hertz::new(3, 1.0, 1.0, 1.0, 0.3, v);
            let close = |x: f64, y: f64| (x - y).abs() < 1e-3 * y.abs();
            assert!(close(h.max_approach().unwrap(), d));
            let fm = h.peak_force().unwrap();
            assert!(close(fm, f));
            assert!(close(h.contact_radius(fm), a));
            assert!(close(h.duration().unwrap(), tc));
            assert!(close(h.peak_pressure(fm), p0));
        }
        // The duration factor by a finer rule than the constant's.
        let n = 400_000;
        let s: f64 = (0..n)
            .map(|i| {
                let s = (i as f64 + 0.5) / n as f64;
                2.0 * s / (1.0 - (1.0 - s * s).powf(2.5)).sqrt() / n as f64
            })
            .sum();
        assert!((2.0 * s - DURATION_FACTOR).abs() < 1e-6, "{}", 2.0 * s);
    }

    /// The integrated force history peaks at F_max half-way through t_c and ends at zero force.
    #[test]
    fn force_history_peaks_at_the_closed_form() {
        let h = Hertz::new(3, 1.0, 1.0, 1.0, 0.3, 0.01);
        let f = h.force_history(2000).unwrap();
        let (t_peak, f_peak) = f
            .iter()
            .copied()
            .fold((0.0, 0.0), |m, p| if p.1 > m.1 { p } else { m });
        let (f_max, t_c) = (h.peak_force().unwrap(), h.duration().unwrap());
        assert!((f_peak - f_max).abs() < 1e-6 * f_max, "{f_peak} vs {f_max}");
        assert!((t_peak - 0.5 * t_c).abs() <= t_c / 2000.0, "{t_peak}");
        assert!(f.last().unwrap().1 < 1e-3 * f_max, "{:?}", f.last());
        assert!(Hertz::new(2, 1.0, 1.0, 1.0, 0.3, 0.01)
            .force_history(10)
            .is_none());
    }

    /// A vanishing compliance gives Hertz's closed forms through the finite body's energy
    /// bisection and duration quadrature.
    #[test]
    fn finite_body_tends_to_the_half_space() {
        let h = Hertz::new(3, 1.0, 1.0, 1.0, 0.3, 0.01);
        let f = h.finite_body(h.mass, 1e-12).unwrap();
        let close = |x: f64, y: f64, tol: f64| (x - y).abs() <= tol * y.abs();
        assert!(close(
            f.peak_force().unwrap(),
            h.peak_force().unwrap(),
            1e-9
        ));
        assert!(close(
            f.max_approach().unwrap(),
            h.max_approach().unwrap(),
            1e-9
        ));
        let (tc, tc_h) = (f.duration().unwrap(), h.duration().unwrap());
        assert!(close(tc, tc_h, 1e-6), "{tc} vs {tc_h}");
    }

    /// The finite body: energy balance at F_max, δ(F) inverted, a symmetric force history that
    /// peaks at F_max and ends at t_c, and the numbers of an independent RK4 integration of
    /// `m δ̈ = −F(δ)` (m = 3.95, c_f = 0.428, v = 0.01: t_c = 11.107, F_max = 1.34648e-2,
    /// δ_max = 3.81105e-2, Python, step 1e-3).
    #[test]
    fn finite_body_impact() {
        let h = Hertz::new(3, 1.0, 1.0, 1.0, 0.3, 0.01)
            .finite_body(3.95, 0.428)
            .unwrap();
        let (f_max, d_max, t_c) = (
            h.peak_force().unwrap(),
            h.max_approach().unwrap(),
            h.duration().unwrap(),
        );
        assert!((h.work(f_max) - h.kinetic_energy()).abs() < 1e-12 * h.kinetic_energy());
        for f in [1e-6, 1e-3, f_max] {
            assert!((h.force(h.approach(f)) - f).abs() < 1e-12 * f, "{f}");
        }
        let close = |x: f64, y: f64| (x - y).abs() < 1e-4 * y;
        assert!(close(t_c, 11.107) && close(f_max, 1.34648e-2) && close(d_max, 3.81105e-2));
        let history = h.force_history(4000).unwrap();
        let (t_peak, f_peak) =
            history
                .iter()
                .copied()
                .fold((0.0, 0.0), |m, p| if p.1 > m.1 { p } else { m });
        assert!((f_peak - f_max).abs() < 1e-6 * f_max, "{f_peak} vs {f_max}");
        assert!((t_peak - 0.5 * t_c).abs() <= t_c / 4000.0, "{t_peak}");
        assert!(history.last().unwrap().1 < 1e-3 * f_max);
        // Stiffer than the half-space of the same mass; a negative compliance, softer.
        let half = Hertz::new(3, 1.0, 1.0, 1.0, 0.3, 0.01)
            .finite_body(3.95, 0.0)
            .unwrap();
        assert!(f_max > half.peak_force().unwrap() && t_c < half.duration().unwrap());
        let soft = half.finite_body(3.95, -0.428).unwrap();
        let f_soft = soft.peak_force().unwrap();
        assert!((soft.work(f_soft) - soft.kinetic_energy()).abs() < 1e-12 * soft.kinetic_energy());
        assert!(
            f_soft < half.peak_force().unwrap()
                && soft.duration().unwrap() > half.duration().unwrap()
        );
        assert!((soft.force(soft.approach(f_soft)) - f_soft).abs() < 1e-12 * f_soft);
        assert_eq!(soft.max_approach(), Some(soft.approach(f_soft)));
        assert!(soft.max_approach().unwrap() > half.max_approach().unwrap());
    }

    /// A compliance whose approach law turns over before absorbing the kinetic energy is refused.
    #[test]
    fn finite_body_refuses_a_law_that_turns_over() {
        let h = Hertz::new(3, 1.0, 1.0, 1.0, 0.3, 0.01);
        let err = h.finite_body(h.mass, 50.0).unwrap_err().to_string();
        assert!(err.contains("compliance"), "{err}");
        assert!(h.finite_body(-1.0, 0.1).is_err());
        assert!(h.finite_body(h.mass, f64::NAN).is_err());
    }
}
