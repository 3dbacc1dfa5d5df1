//! A solid disc released at rest on a plane of slope α with Coulomb friction μ, as a rigid body
//! (`notes/papers/friction.md` §5, derived; `shared/reference/friction.md`). Mass m, radius R,
//! I = ½ m R², friction force f up the slope, normal force m g cos α:
//! - rolling without slip: `m a = m g sin α − f`, `I a / R = f R` ⇒ `a = ⅔ g sin α`,
//!   `f = ⅓ m g sin α`, admissible iff `f ≤ μ m g cos α`, i.e. **μ ≥ tan α / 3**;
//! - otherwise it slides: `f = μ m g cos α`, `a = g (sin α − μ cos α)`, and the contact point's
//!   slip velocity grows at `g (sin α − 3 μ cos α) > 0`.

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
}
