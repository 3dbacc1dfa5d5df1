//! A solid disc released at rest on a plane of slope α with Coulomb friction μ, as a rigid body
//! (`notes/papers/friction.md` §5, derived; `shared/reference/friction.md`). Mass m, radius R,
//! I = ½ m R², friction force f up the slope, normal force m g cos α:
//! - rolling without slip: `m a = m g sin α − f`, `I a / R = f R` ⇒ `a = ⅔ g sin α`,
//!   `f = ⅓ m g sin α`, admissible iff `f ≤ μ m g cos α`, i.e. **μ ≥ tan α / 3**;
//! - otherwise it slides: `f = μ m g cos α`, `a = g (sin α − μ cos α)`, and the contact point's
//!   slip velocity grows at `g (sin α − 3 μ cos α) > 0`.
//!
//! The suite's bodies are linearly elastic in small displacements, and their rigid modes are
//! `u = d + θ e_z × (X − c)`: the rotation by θ stretches the circle to radius `R √(1 + θ²)`.
//! Rolling without slip, this disc keeps touching the plane with its centre at height
//! `R √(1 + θ²)` (lifted by `R θ²/2`) and `ẋ_c = R θ̇ / √(1 + θ²)`; its kinetic energy is
//! `½ (m R² + I) θ̇²` and Lagrange's equation (gravity's work on `x_c`, `y_c`)
//! `θ̈ = (2g / 3R) (sin α − θ cos α) / √(1 + θ²)` ([`Roll::small_displacement`]). To first
//! order `a = ⅔ g (sin α − θ cos α)` with `θ = tan α (1 − cos ωt)`, `ω² = 2 g cos α / 3R`:
//! the lift's work takes a fraction `θ / tan α` of the rolling acceleration, first order in the
//! angle, and the friction it needs grows to `f/N = tan α / 3 + ⅔ θ`. This is the limit of the
//! finite element disc as h → 0 and E → ∞; the rigid disc is its θ → 0 limit.

/// The rigid disc on the slope: g, α, μ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Roll {
    /// Gravity g.
    pub gravity: f64,
    /// Slope α (radians).
    pub slope: f64,
    /// Friction coefficient μ.
    pub mu: f64,
}

impl Roll {
    /// Whether it rolls without slipping: μ ≥ tan α / 3.
    pub fn rolls(&self) -> bool {
        self.mu >= self.slope.tan() / 3.0
    }

    /// The centre's acceleration down the slope.
    pub fn acceleration(&self) -> f64 {
        let (s, c) = self.slope.sin_cos();
        if self.rolls() {
            2.0 / 3.0 * self.gravity * s
        } else {
            self.gravity * (s - self.mu * c)
        }
    }

    /// The contact point's slip acceleration (0 when it rolls).
    pub fn slip_acceleration(&self) -> f64 {
        let (s, c) = self.slope.sin_cos();
        if self.rolls() {
            0.0
        } else {
            self.gravity * (s - 3.0 * self.mu * c)
        }
    }
}

impl Roll {
    /// The disc of radius `radius` rolling without slip in small-displacement kinematics (module
    /// doc): `(θ, ẋ_c)` at time `t`, released at rest, by RK4 on
    /// `θ̈ = (2g / 3R) (sin α − θ cos α) / √(1 + θ²)` with steps ≤ 1e-3 (error below 1e-12).
    pub fn small_displacement(&self, radius: f64, t: f64) -> (f64, f64) {
        let (s, c) = self.slope.sin_cos();
        let k = 2.0 * self.gravity / (3.0 * radius);
        let f = |y: [f64; 2]| [y[1], k * (s - y[0] * c) / (1.0 + y[0] * y[0]).sqrt()];
        let steps = (t / 1e-3).ceil().max(1.0);
        let h = t / steps;
        let mut y = [0.0, 0.0];
        for _ in 0..steps as usize {
            let at = |y: [f64; 2], k: [f64; 2], a: f64| [y[0] + a * k[0], y[1] + a * k[1]];
            let k1 = f(y);
            let k2 = f(at(y, k1, 0.5 * h));
            let k3 = f(at(y, k2, 0.5 * h));
            let k4 = f(at(y, k3, h));
            y = std::array::from_fn(|i| {
                y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
        }
        (y[0], radius * y[1] / (1.0 + y[0] * y[0]).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_threshold_separates_rolling_from_sliding() {
        let alpha = 0.3_f64;
        let at = |mu| Roll {
            gravity: 1.0,
            slope: alpha,
            mu,
        };
        let mu_star = alpha.tan() / 3.0;
        assert!(at(mu_star).rolls() && !at(0.99 * mu_star).rolls());
        // Both laws give the same acceleration at the threshold.
        let (a, b) = (
            at(mu_star).acceleration(),
            at(mu_star * (1.0 - 1e-12)).acceleration(),
        );
        assert!((a - b).abs() < 1e-12, "{a} against {b}");
        assert_eq!(at(mu_star).slip_acceleration(), 0.0);
        assert!(at(0.5 * mu_star).slip_acceleration() > 0.0);
    }

    /// The small-displacement roll starts at ⅔ g sin α, keeps its energy
    /// `¾ m v² (1 + θ²) = m g R (sin α asinh θ − cos α (√(1 + θ²) − 1))` and follows the
    /// first-order `θ = tan α (1 − cos ωt)` to O(θ³).
    #[test]
    fn the_small_displacement_roll_lifts_the_disc_and_slows_it() {
        let (alpha, radius) = (0.3_f64, 1.0);
        let disc = Roll {
            gravity: 1.0,
            slope: alpha,
            mu: 0.3,
        };
        let (_, v) = disc.small_displacement(radius, 1e-3);
        assert!((v / 1e-3 - disc.acceleration()).abs() < 1e-6, "{v}");
        let omega = (2.0 * alpha.cos() / 3.0).sqrt();
        for t in [0.4, 0.8, 2.0] {
            let (theta, v) = disc.small_displacement(radius, t);
            let kinetic = 0.75 * v * v * (1.0 + theta * theta);
            let work =
                alpha.sin() * theta.asinh() - alpha.cos() * ((1.0 + theta * theta).sqrt() - 1.0);
            assert!(
                (kinetic - work).abs() < 1e-12,
                "t = {t}: {kinetic} against {work}"
            );
            let first = alpha.tan() * (1.0 - (omega * t).cos());
            assert!(
                (theta - first).abs() < theta.powi(3),
                "t = {t}: {theta} against {first}"
            );
        }
        // At T = 0.8 the rolling disc has turned by 0.061 and lost 7 % of its velocity.
        let (theta, v) = disc.small_displacement(radius, 0.8);
        assert!(
            (theta - 0.0609).abs() < 1e-4 && (v / 0.8 - 0.1835).abs() < 1e-4,
            "{theta} {v}"
        );
    }
}
