//! Exact spring–mass impact (`shared/reference/spring_mass.md`):
//! `m ü + k (u − u_r) = f + λ`, `u ≥ 0, λ ≥ 0, λ u = 0`, with Newton's impact law
//! `u̇(t⁺) = −e u̇(t⁻)`. Between impacts, free flight `u = u_e + A cos ωτ + (v/ω) sin ωτ`
//! (ω = √(k/m), u_e = u_r + f/k; a parabola when k = 0). With e = 0 and a force pushing the mass
//! onto the obstacle, it rests there with the static pressure `λ = −(f + k u_r)`.
//! The trajectory is precomputed as a list of free-flight segments up to `t_end`.

use super::{ContactValues, ExactContact};
use crate::error::{non_negative, positive, Error, Result};

/// Parameters of the spring–mass impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringMassParams {
    /// Mass m > 0.
    pub mass: f64,
    /// Stiffness k ≥ 0.
    pub stiffness: f64,
    /// Rest position u_r of the spring.
    pub rest_position: f64,
    /// Constant force f (e.g. −m g).
    pub force: f64,
    /// Initial height u₀ ≥ 0.
    pub u0: f64,
    /// Initial velocity.
    pub v0: f64,
    /// Restitution coefficient e ∈ [0, 1].
    pub restitution: f64,
}

impl SpringMassParams {
    /// ω = √(k/m).
    pub fn omega(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// Acceleration of the free mass at height u: (f − k(u − u_r))/m.
    fn accel(&self, u: f64) -> f64 {
        (self.force - self.stiffness * (u - self.rest_position)) / self.mass
    }
}

/// A piece of the exact trajectory starting at `t0` from `(u0, v0)`.
#[derive(Debug, Clone, Copy)]
struct Segment {
    t0: f64,
    u0: f64,
    v0: f64,
    /// Resting on the obstacle (e = 0 and the force pushes into it).
    resting: bool,
}

/// The exact trajectory with Newton's law of restitution `e`.
#[derive(Debug, Clone)]
pub struct SpringMass {
    /// Parameters.
    pub p: SpringMassParams,
    segments: Vec<Segment>,
    /// Impact times in [0, t_end].
    pub impacts: Vec<f64>,
}

/// At most this many impacts are resolved (0 < e < 1 accumulates impacts: Zeno behaviour).
const MAX_IMPACTS: usize = 100_000;

impl SpringMass {
    /// Precomputes the trajectory on [0, t_end].
    pub fn new(p: SpringMassParams, t_end: f64) -> Result<Self> {
        positive("mass", p.mass)?;
        non_negative("stiffness", p.stiffness)?;
        non_negative("u0", p.u0)?;
        crate::error::in_range("restitution", p.restitution, 0.0, 1.0)?;
        for (f, v) in [
            ("rest_position", p.rest_position),
            ("force", p.force),
            ("v0", p.v0),
        ] {
            crate::error::finite(f, v)?;
        }
        let mut segments = vec![Segment {
            t0: 0.0,
            u0: p.u0,
            v0: p.v0,
            resting: false,
        }];
        let mut impacts = Vec::new();
        let mut seg = segments[0];
        while impacts.len() < MAX_IMPACTS {
            let Some(tau) = next_impact(&p, seg.u0, seg.v0) else {
                break;
            };
            let t_imp = seg.t0 + tau;
            if t_imp > t_end {
                break;
            }
            impacts.push(t_imp);
            let (_, v_minus) = flight(&p, seg.u0, seg.v0, tau);
            let v_plus = -p.restitution * v_minus;
            let resting = v_plus <= 1e-14 * v_minus.abs() && p.accel(0.0) <= 0.0;
            seg = Segment {
                t0: t_imp,
                u0: 0.0,
                v0: if resting { 0.0 } else { v_plus },
                resting,
            };
            segments.push(seg);
            if resting {
                break;
            }
        }
        if impacts.len() == MAX_IMPACTS {
            return Err(Error::Unsupported(format!(
                "exact spring-mass trajectory has more than {MAX_IMPACTS} impacts before \
                 run.t_end = {t_end:?} (their rate is set by system.stiffness, system.mass and \
                 system.restitution)"
            )));
        }
        Ok(Self {
            p,
            segments,
            impacts,
        })
    }

    /// `(u, u̇, λ)` at time t (λ: contact force, 0 in flight, impulsive at impacts).
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        let i = self.segments.partition_point(|s| s.t0 <= t).max(1) - 1;
        let s = self.segments[i];
        if s.resting {
            return (
                0.0,
                0.0,
                -(self.p.force + self.p.stiffness * self.p.rest_position),
            );
        }
        let (u, v) = flight(&self.p, s.u0, s.v0, t - s.t0);
        (u.max(0.0), v, 0.0)
    }
}

/// Free flight from `(u0, v0)` after time τ.
fn flight(p: &SpringMassParams, u0: f64, v0: f64, tau: f64) -> (f64, f64) {
    if p.stiffness == 0.0 {
        let g = p.force / p.mass;
        return (u0 + v0 * tau + 0.5 * g * tau * tau, v0 + g * tau);
    }
    let w = p.omega();
    let ue = p.rest_position + p.force / p.stiffness;
    let (c, s) = ((w * tau).cos(), (w * tau).sin());
    let a = u0 - ue;
    (ue + a * c + v0 / w * s, -a * w * s + v0 * c)
}

/// Time to the next impact (u = 0 with u̇ < 0) of the free flight from `(u0, v0)`, if any.
fn next_impact(p: &SpringMassParams, u0: f64, v0: f64) -> Option<f64> {
    if u0 <= 0.0 && v0 < 0.0 {
        return Some(0.0);
    }
    if p.stiffness == 0.0 {
        let g = p.force / p.mass;
        if g >= 0.0 {
            return None;
        }
        // u0 + v0 τ + g τ²/2 = 0, larger root.
        let disc = v0 * v0 - 2.0 * g * u0;
        return Some((-v0 - disc.sqrt()) / g);
    }
    let w = p.omega();
    let ue = p.rest_position + p.force / p.stiffness;
    let a = u0 - ue;
    let r = (a * a + (v0 / w).powi(2)).sqrt();
    if ue - r >= 0.0 {
        return None;
    }
    // u = ue + r cos(θ), θ = ωτ − φ; impact with u̇ < 0 at θ* = arccos(−ue/r) ∈ [0, π].
    let phi = (v0 / w).atan2(a);
    let theta = (-ue / r).clamp(-1.0, 1.0).acos();
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut tau = (theta + phi).rem_euclid(two_pi) / w;
    if tau <= 1e-12 / w {
        tau += two_pi / w;
    }
    Some(tau)
}

impl ExactContact for SpringMass {
    fn contact(&self, t: f64) -> ContactValues {
        let (u, v, lambda) = self.eval(t);
        ContactValues {
            u,
            v,
            sigma: -lambda,
        }
    }

    /// `½ m u̇² + ½ k (u − u_e)²`, or `½ m u̇² − f u` when k = 0; constant for e = 1.
    fn energy(&self, t: f64) -> f64 {
        let (u, v, _) = self.eval(t);
        let p = &self.p;
        let kinetic = 0.5 * p.mass * v * v;
        if p.stiffness == 0.0 {
            kinetic - p.force * u
        } else {
            let ue = p.rest_position + p.force / p.stiffness;
            kinetic + 0.5 * p.stiffness * (u - ue).powi(2)
        }
    }

    fn first_impact(&self) -> Option<f64> {
        self.impacts.first().copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> SpringMassParams {
        SpringMassParams {
            mass: 1.0,
            stiffness: 1.0,
            rest_position: 0.0,
            force: 0.0,
            u0: 1.0,
            v0: 0.0,
            restitution: 1.0,
        }
    }

    #[test]
    fn elastic_bounce_is_abs_cos() {
        let s = SpringMass::new(params(), 20.0).unwrap();
        for k in 0..2000 {
            let t = k as f64 * 0.01;
            let (u, v, l) = s.eval(t);
            assert!((u - t.cos().abs()).abs() < 1e-12, "t={t}");
            assert!((v.abs() - t.sin().abs()).abs() < 1e-12);
            assert_eq!(l, 0.0);
            assert!((s.energy(t) - 0.5).abs() < 1e-12);
        }
        for (k, t) in s.impacts.iter().enumerate() {
            assert!((t - (k as f64 + 0.5) * std::f64::consts::PI).abs() < 1e-12);
        }
    }

    #[test]
    fn impacts_repeat_every_two_theta_star_over_omega() {
        // methods.md: θ* = π − arccos(u_r/A), impact speed ω√(A² − u_r²).
        let p = SpringMassParams {
            stiffness: 4.0,
            rest_position: 0.3,
            u0: 1.0,
            ..params()
        };
        let s = SpringMass::new(p, 30.0).unwrap();
        let (w, amp) = (2.0, 0.7);
        let theta = std::f64::consts::PI - (0.3f64 / amp).acos();
        for pair in s.impacts.windows(2) {
            assert!((pair[1] - pair[0] - 2.0 * theta / w).abs() < 1e-10);
        }
        let (_, v, _) = s.eval(s.impacts[1] - 1e-9);
        assert!((v + w * (amp * amp - 0.09f64).sqrt()).abs() < 1e-7);
    }

    #[test]
    fn gravity_drop_bounces_with_the_published_times_and_plastic_impact_rests() {
        let p = SpringMassParams {
            stiffness: 0.0,
            force: -9.81,
            u0: 2.0,
            v0: 1.0,
            ..params()
        };
        let s = SpringMass::new(p, 10.0).unwrap();
        let big_v = (1.0f64 + 2.0 * 9.81 * 2.0).sqrt();
        assert!((s.impacts[0] - (1.0 + big_v) / 9.81).abs() < 1e-12);
        assert!((s.impacts[1] - s.impacts[0] - 2.0 * big_v / 9.81).abs() < 1e-12);
        let plastic = SpringMass::new(
            SpringMassParams {
                restitution: 0.0,
                ..p
            },
            10.0,
        )
        .unwrap();
        let (u, v, l) = plastic.eval(5.0);
        assert_eq!((u, v), (0.0, 0.0));
        assert!((l - 9.81).abs() < 1e-12);
    }
}
