//! A body sliding on a rigid plane with Coulomb friction, as a rigid body
//! (`shared/reference/friction.md`, "A body sliding on the plane"): launched along the plane at
//! v₀ > 0 under gravity g, friction μ. While it slides the friction force is μ times the normal
//! force m g, so its centre of mass decelerates at μ g:
//!
//! `v(t) = v₀ − μ g t` for `t < t* = v₀/(μ g)`, then `v = 0` (it sticks);
//! `x(t) = v₀ t − ½ μ g t²` up to `x(t*) = v₀²/(2 μ g)`;
//! friction work `W_f(t) = ½ m (v₀² − v(t)²)`, all of the kinetic energy at t*.
//!
//! μ = 0: `v = v₀` for ever. An elastic body follows this up to its vibrations (the normal
//! force oscillates about m g).

use crate::error::{non_negative, positive, Result};

/// The rigid-body slide: v₀, g, μ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slide {
    /// Initial velocity v₀ > 0 along the plane.
    pub speed: f64,
    /// Gravity g > 0.
    pub gravity: f64,
    /// Friction coefficient μ ≥ 0.
    pub mu: f64,
}

impl Slide {
    /// Validated data.
    pub fn new(speed: f64, gravity: f64, mu: f64) -> Result<Self> {
        Ok(Self {
            speed: positive("geometry.tangential_velocity", speed)?,
            gravity: positive("geometry.gravity", gravity)?,
            mu: non_negative("contact.friction", mu)?,
        })
    }

    /// Deceleration μ g.
    pub fn deceleration(&self) -> f64 {
        self.mu * self.gravity
    }

    /// Stopping time `t* = v₀/(μ g)` (+∞ without friction).
    pub fn stopping_time(&self) -> f64 {
        self.speed / self.deceleration()
    }

    /// Distance travelled up to t*, `v₀²/(2 μ g)` (+∞ without friction).
    pub fn stopping_distance(&self) -> f64 {
        0.5 * self.speed * self.stopping_time()
    }

    /// Centre-of-mass velocity `v(t)`.
    pub fn velocity(&self, t: f64) -> f64 {
        (self.speed - self.deceleration() * t).max(0.0)
    }

    /// Centre-of-mass displacement `x(t)`.
    pub fn distance(&self, t: f64) -> f64 {
        let t = t.min(self.stopping_time());
        self.speed * t - 0.5 * self.deceleration() * t * t
    }

    /// Friction work per unit mass `(v₀² − v(t)²)/2`.
    pub fn work_per_mass(&self, t: f64) -> f64 {
        0.5 * (self.speed.powi(2) - self.velocity(t).powi(2))
    }
}

/// A block sliding on another with Coulomb friction between them, as two rigid bodies (issue 25
/// §1): the top block (mass m₁) is launched at v₀ along the top face of the bottom block (mass
/// m₂, at rest), which rests on a frictionless rigid plane; both carry their weight. Derived: the
/// interface carries the top's weight, `N = m₁ g`, so while they slip the friction force μ N
/// decelerates the top at μ g and accelerates the bottom at `μ g m₁/m₂` (the plane carries
/// `(m₁ + m₂) g` and no tangential force, and takes the friction torque on the bottom block, as
/// the interface's pressure takes it on the top); their relative velocity
/// `v_rel = v₀ − μ g (1 + m₁/m₂) t` vanishes at `t* = v₀ m₂/(μ g (m₁ + m₂))`, after which they move
/// together at `v_c = m₁ v₀/(m₁ + m₂)`. The tangential momentum `m₁ v₀` is conserved and the
/// friction work is the relative kinetic energy lost, `W_f(t) = ½ m* (v₀² − v_rel(t)²)`,
/// `m* = m₁ m₂/(m₁ + m₂)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlideOnBlock {
    /// The top block's slide on a fixed plane: v₀, g, μ.
    pub top: Slide,
    /// Masses (m₁ top, m₂ bottom), > 0.
    pub masses: [f64; 2],
}

impl SlideOnBlock {
    /// The relative deceleration `μ g (1 + m₁/m₂)`.
    fn relative_deceleration(&self) -> f64 {
        self.top.deceleration() * (1.0 + self.masses[0] / self.masses[1])
    }

    /// The time they stick, `t* = v₀/(μ g (1 + m₁/m₂))`.
    pub fn stick_time(&self) -> f64 {
        self.top.speed / self.relative_deceleration()
    }

    /// The relative velocity `v_rel(t)`.
    pub fn relative_velocity(&self, t: f64) -> f64 {
        (self.top.speed - self.relative_deceleration() * t).max(0.0)
    }

    /// The blocks' tangential velocities `(v₁(t), v₂(t))`.
    pub fn velocities(&self, t: f64) -> [f64; 2] {
        let [m1, m2] = self.masses;
        let (v0, rel) = (self.top.speed, self.relative_velocity(t));
        // m₁ v₁ + m₂ v₂ = m₁ v₀ and v₁ − v₂ = v_rel.
        let v2 = m1 * (v0 - rel) / (m1 + m2);
        [v2 + rel, v2]
    }

    /// Friction work `½ m* (v₀² − v_rel(t)²)`.
    pub fn work(&self, t: f64) -> f64 {
        let [m1, m2] = self.masses;
        0.5 * m1 * m2 / (m1 + m2) * (self.top.speed.powi(2) - self.relative_velocity(t).powi(2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_slide_stops_at_four_after_two() {
        let s = Slide::new(1.0, 1.0, 0.25).unwrap();
        assert_eq!((s.stopping_time(), s.stopping_distance()), (4.0, 2.0));
        assert_eq!((s.velocity(2.0), s.velocity(5.0)), (0.5, 0.0));
        assert_eq!((s.distance(2.0), s.distance(10.0)), (1.5, 2.0));
        assert_eq!(s.work_per_mass(4.0), 0.5);
    }

    #[test]
    fn without_friction_it_keeps_its_speed() {
        let s = Slide::new(1.0, 1.0, 0.0).unwrap();
        assert_eq!((s.velocity(100.0), s.stopping_time()), (1.0, f64::INFINITY));
    }

    /// Equal masses, v₀ = 1, g = 1, μ = 0.25: the top decelerates at μ g, the bottom
    /// accelerates at μ g, both at ½ from t* = 2; momentum m₁ v₀ throughout; W_f(t*) = ¼.
    #[test]
    fn the_blocks_meet_at_the_common_velocity() {
        let s = SlideOnBlock {
            top: Slide::new(1.0, 1.0, 0.25).unwrap(),
            masses: [1.0, 1.0],
        };
        assert_eq!(s.stick_time(), 2.0);
        assert_eq!(s.velocities(0.0), [1.0, 0.0]);
        assert_eq!(s.velocities(1.0), [0.75, 0.25]);
        assert_eq!(s.velocities(9.0), [0.5, 0.5]);
        assert_eq!((s.work(2.0), s.work(9.0)), (0.25, 0.25));
    }

    #[test]
    fn bad_data_names_the_field() {
        let e = Slide::new(1.0, 1.0, -0.1).unwrap_err().to_string();
        assert!(e.contains("contact.friction"), "{e}");
    }
}
