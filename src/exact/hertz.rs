//! Quasi-static Hertz theory for the impact of an elastic sphere (3D) or disc (2D, plane strain)
//! on a rigid plane (Johnson, *Contact Mechanics*, 1985, §4.2, §11.4;
//! `shared/reference/hertz_impact.md`). `E* = E/(1 − ν²)`, R the radius, v the impact speed.
//!
//! Sphere: `F = k δ^{3/2}`, `k = (4/3) E* √R`; energy balance `½ m v² = (2/5) k δ_max^{5/2}` gives
//! `δ_max = (15 m v² / (16 E* √R))^{2/5}`, `F_max = k δ_max^{3/2}`, `t_c = 2.9433 δ_max / v`;
//! contact radius `a = (3 F R / (4 E*))^{1/3}`, peak pressure `p₀ = 3F / (2π a²)`.
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
}

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
        }
    }

    /// `k = (4/3) E* √R` (sphere).
    fn stiffness(&self) -> f64 {
        4.0 / 3.0 * self.e_star * self.radius.sqrt()
    }

    /// Maximum approach δ_max (sphere only).
    pub fn max_approach(&self) -> Option<f64> {
        (self.dim == 3).then(|| {
            (15.0 * self.mass * self.speed.powi(2) / (16.0 * self.e_star * self.radius.sqrt()))
                .powf(0.4)
        })
    }

    /// Peak force `F_max = k δ_max^{3/2}` (sphere only).
    pub fn peak_force(&self) -> Option<f64> {
        self.max_approach().map(|d| self.stiffness() * d.powf(1.5))
    }

    /// Contact duration `t_c = 2.9433 δ_max / v` (sphere only).
    pub fn duration(&self) -> Option<f64> {
        self.max_approach()
            .map(|d| DURATION_FACTOR * d / self.speed)
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

    /// The quasi-static force history `F(t) = k δ^{3/2}` of the impact (sphere only), `steps + 1`
    /// samples over `[0, t_c]`: `m δ̈ = −k δ^{3/2}`, `δ(0) = 0`, `δ̇(0) = v`, integrated by RK4
    /// (error O(1/steps⁴) away from the ends).
    pub fn force_history(&self, steps: usize) -> Option<Vec<(f64, f64)>> {
        let t_c = self.duration()?;
        let k = self.stiffness();
        let dt = t_c / steps as f64;
        // (δ, δ̇) ↦ (δ̇, −k δ^{3/2} / m), δ clamped at 0 after release.
        let rhs = |y: [f64; 2]| [y[1], -k * y[0].max(0.0).powf(1.5) / self.mass];
        let mut y = [0.0, self.speed];
        let mut out = Vec::with_capacity(steps + 1);
        for n in 0..=steps {
            out.push((n as f64 * dt, k * y[0].max(0.0).powf(1.5)));
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
}
