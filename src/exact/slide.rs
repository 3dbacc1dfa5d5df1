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

    #[test]
    fn bad_data_names_the_field() {
        let e = Slide::new(1.0, 1.0, -0.1).unwrap_err().to_string();
        assert!(e.contains("contact.friction"), "{e}");
    }
}
