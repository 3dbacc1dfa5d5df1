//! Maw, Barber & Fawcett's oblique impact of an elastic sphere on a rigid plane, computed by the
//! method of dimensionality reduction: Hertz normally, Cattaneo–Mindlin tangentially with
//! microslip and the whole loading history, the sphere a rigid body (translation and spin).
//!
//! **Model** (Maw, Barber & Fawcett, Wear 38 (1976) 101–114: friction the only dissipation,
//! contact laid down free of tangential traction as it grows, the history followed in small time
//! increments). The method of dimensionality reduction (Popov & Heß, *Method of dimensionality
//! reduction in contact mechanics and friction*, Springer 2015; "A users handbook I",
//! Facta Universitatis ME 12 (2014) 1–14) replaces the contact by a row of independent springs
//! at x with normal stiffness `E* dx` and tangential `G* dx` under the transformed profile
//! `g(x) = x²/R` of a sphere; `1/E* = (1 − ν²)/E`, `1/G* = (2 − ν)/(4G)`, `G = E/(2(1 + ν))`
//! (a rigid plane). A spring in contact (`δ > g(x)`) carries `q_z = E* (δ − g(x))` and
//! `q_x = G* u(x)`; it sticks (u follows the contact point's tangential displacement) while
//! `|u| ≤ μ (E*/G*) (δ − g(x))` and slides at that bound; it enters with u = 0 and leaves with
//! it. Jäger's theorem (Jäger, Appl. Mech. Rev. 47 (1994) 35–54, tangential solutions for
//! arbitrary load histories) makes this exact for Cattaneo–Mindlin with varying normal and
//! tangential load. The totals are `F_n = E* ∫ (δ − x²/R) dx = 4/3 E* √R δ^{3/2}` (Hertz, used
//! in closed form) and `F_t = −G* ∫ u dx`, `k_t = 2 G* a = 8 G a/(2 − ν)` (Mindlin). Assumed, as by
//! MBF: no coupling of normal and tangential tractions (Dundurs' β = 0; an elastic sphere on a
//! rigid plane has `β = (1 − 2ν)/(2(1 − ν))`, 0.35 at ν = 0.23) and a quasi-static contact.
//!
//! **Dynamics**: `m δ̈ = −F_n`, `m v̇ = F_t`, `I ω̇ = −R F_t` (ω > 0 rolling forwards), so the
//! contact point's tangential velocity `w = v − ω R` obeys `ẇ = (1 + m R²/I) F_t/m`. Velocity
//! Verlet in time; a spring that enters during a step takes the part of the step's displacement
//! after its entry (linear in δ), so both the time step and the spring spacing converge at
//! second order (halving both changes e_t by < 1e-6 at the report's resolution).
//!
//! **Limits** (`tests/oblique.rs`): e_n = 1 and Hertz's contact time; gross slip
//! `|J_t| = μ J_n`; `G* → ∞` the rigid stick e_t = 5/7; and at small incidence the sticking
//! contact, linear in w, whose ratio w'/w depends only on `κ = (1 + m R²/I) G*/E*`. For κ = 1 the
//! tangential problem is the normal one scaled (both the same functional of the contact's
//! history): `u = (w/v_n)(δ − g)` stays inside the bound iff `ψ₁ = (G*/E*) w/(μ v_n) ≤ 1`, and
//! then w' = −w exactly. The linear-oscillator estimate `w'/w = cos(π√κ)` (a spring of constant
//! stiffness ratio κ) is exact there only: at κ = 3.045 (ν = 0.23) it gives 0.696, the
//! history-dependent stick 0.296.
//!
//! Papers read here: the MDR handbook's abstract and MBF 1976's introduction (excerpts); Jäger
//! 1994's summary; MBF (1981, J. Lubr. Technol. 103, 74–80)'s normalisation excerpt. The
//! formulas above were checked against each other (`k_t/k_n = G*/E* = 2(1 − ν)/(2 − ν)`, the χ of
//! [`super::oblique::maw_incidence`]).

use super::hertz::{Hertz, DURATION_FACTOR};
use crate::error::{positive, Error, Result};

/// A sphere (radius, mass, moment of inertia) against a rigid plane: contact moduli and μ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mbf {
    /// Radius R.
    pub radius: f64,
    /// Mass m.
    pub mass: f64,
    /// `I/(m R²)`: 2/5 for a solid sphere.
    pub inertia: f64,
    /// `E* = E/(1 − ν²)`.
    pub e_star: f64,
    /// `G* = 4G/(2 − ν)`.
    pub g_star: f64,
    /// Friction coefficient μ.
    pub mu: f64,
}

/// The resolution of an [`Mbf::impact`]: time steps per Hertz contact time and springs over
/// the largest contact radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolution {
    /// Steps per Hertz contact time t_c.
    pub steps: usize,
    /// Springs on `0 ≤ x ≤ 1.05 a_max` (the row is symmetric in x).
    pub springs: usize,
}

/// Fine enough for the report: e_t within 1e-6 of twice the steps and springs (measured).
pub const REPORT_RESOLUTION: Resolution = Resolution {
    steps: 4000,
    springs: 2000,
};

/// The rebound: velocities after the contact over the incoming ones, and the impulses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rebound {
    /// `e_n = −v_n'/v_n`.
    pub normal_restitution: f64,
    /// `e_t = v_t'/v_t` of the centre.
    pub tangential_restitution: f64,
    /// `ω' R / V`, rolling forwards positive.
    pub spin: f64,
    /// The contact point's `w'/w = (v_t' − ω' R)/v_t` (no spin before).
    pub contact_point: f64,
    /// `J_n = ∫ F_n dt`.
    pub normal_impulse: f64,
    /// `J_t = ∫ F_t dt` (negative: against v_t).
    pub tangential_impulse: f64,
    /// Contact time.
    pub duration: f64,
}

impl Mbf {
    /// A solid sphere of radius R, density ρ, Young's modulus E and Poisson ratio ν on a rigid
    /// plane with friction μ.
    pub fn sphere(radius: f64, density: f64, young: f64, poisson: f64, mu: f64) -> Result<Self> {
        positive("mbf: radius", radius)?;
        positive("mbf: density", density)?;
        positive("mbf: young", young)?;
        positive("mbf: mu", mu)?;
        if !(0.0..0.5).contains(&poisson) {
            return Err(Error::invalid("mbf: poisson", poisson, "0 ≤ ν < 1/2"));
        }
        let hertz = Hertz::new(3, radius, density, young, poisson, 1.0);
        let shear = young / (2.0 * (1.0 + poisson));
        Ok(Self {
            radius,
            mass: hertz.mass,
            inertia: 0.4,
            e_star: hertz.e_star,
            g_star: 4.0 * shear / (2.0 - poisson),
            mu,
        })
    }

    /// `1 + m R²/I`: how much more the contact point's tangential velocity changes than the
    /// centre's.
    pub fn contact_factor(&self) -> f64 {
        1.0 + 1.0 / self.inertia
    }

    /// `κ = (1 + m R²/I) G*/E*`: the sticking contact point's w'/w depends on κ only.
    pub fn kappa(&self) -> f64 {
        self.contact_factor() * self.g_star / self.e_star
    }

    /// MBF's normalised incidence `ψ₁ = (G*/E*) tan θ/μ` (θ from the normal, no spin before).
    pub fn psi(&self, incidence: f64) -> f64 {
        self.g_star / self.e_star * incidence.tan() / self.mu
    }

    /// The normal impact at speed v_n: Hertz's.
    pub fn hertz(&self, normal_speed: f64) -> Hertz {
        Hertz {
            dim: 3,
            radius: self.radius,
            e_star: self.e_star,
            mass: self.mass,
            speed: normal_speed,
            compliance: 0.0,
        }
    }

    /// The impact at speed V and incidence θ (radians from the normal, in (0, π/2)), no spin
    /// before.
    pub fn impact(&self, speed: f64, incidence: f64, res: Resolution) -> Result<Rebound> {
        positive("mbf: speed", speed)?;
        if !(incidence > 0.0 && incidence < std::f64::consts::FRAC_PI_2) {
            return Err(Error::invalid("mbf: incidence", incidence, "0 < θ < π/2"));
        }
        if res.steps == 0 || res.springs == 0 {
            return Err(Error::invalid(
                "mbf: resolution",
                (res.steps, res.springs),
                "steps and springs ≥ 1",
            ));
        }
        let (vt, vn) = (speed * incidence.sin(), speed * incidence.cos());
        let delta_max = self.hertz(vn).max_approach().unwrap_or(0.0);
        let dt = DURATION_FACTOR * delta_max / vn / res.steps as f64;
        let dx = 1.05 * (self.radius * delta_max).sqrt() / res.springs as f64;
        let mut row = Row::new(self, dx, res.springs);
        let (m, r, i) = (
            self.mass,
            self.radius,
            self.inertia * self.mass * self.radius.powi(2),
        );
        // (δ, δ̇ approaching, v, ω) and the forces at the start of the step.
        let (mut delta, mut rate, mut v, mut omega) = (0.0, vn, vt, 0.0);
        let (mut f_n, mut f_t) = (0.0, 0.0);
        let (mut j_n, mut j_t, mut steps) = (0.0, 0.0, 0usize);
        loop {
            let half = |rate: &mut f64, v: &mut f64, omega: &mut f64, f_n: f64, f_t: f64| {
                *rate -= 0.5 * dt * f_n / m;
                *v += 0.5 * dt * f_t / m;
                *omega -= 0.5 * dt * r * f_t / i;
            };
            half(&mut rate, &mut v, &mut omega, f_n, f_t);
            j_n += 0.5 * dt * f_n;
            j_t += 0.5 * dt * f_t;
            let next = delta + dt * rate;
            row.step(delta, next, dt * (v - omega * r));
            delta = next;
            f_n = hertz_force(self, delta);
            f_t = row.force();
            half(&mut rate, &mut v, &mut omega, f_n, f_t);
            j_n += 0.5 * dt * f_n;
            j_t += 0.5 * dt * f_t;
            steps += 1;
            if delta <= 0.0 {
                break;
            }
            if steps > 4 * res.steps {
                return Err(Error::invalid(
                    "mbf: impact",
                    steps,
                    "the sphere has not left the plane after 4 Hertz contact times",
                ));
            }
        }
        Ok(Rebound {
            normal_restitution: -rate / vn,
            tangential_restitution: v / vt,
            spin: omega * r / speed,
            contact_point: (v - omega * r) / vt,
            normal_impulse: j_n,
            tangential_impulse: j_t,
            duration: steps as f64 * dt,
        })
    }
}

/// Hertz's `F_n = 4/3 E* √R δ^{3/2}` (0 when δ ≤ 0): the springs' normal force in closed form.
fn hertz_force(s: &Mbf, delta: f64) -> f64 {
    4.0 / 3.0 * s.e_star * s.radius.sqrt() * delta.max(0.0).powf(1.5)
}

/// The springs at `x_k = (k + ½) dx ≥ 0` (the row is symmetric: each stands for ±x_k).
struct Row {
    /// `g(x_k) = x_k²/R`.
    profile: Vec<f64>,
    /// Tangential displacements u_k.
    shift: Vec<f64>,
    /// `μ E*/G*`: the bound on `u/(δ − g)`.
    bound: f64,
    /// `−2 G* dx`: the tangential force of a unit u over ±x_k.
    stiffness: f64,
}

impl Row {
    fn new(s: &Mbf, dx: f64, springs: usize) -> Self {
        Self {
            profile: (0..springs)
                .map(|k| ((k as f64 + 0.5) * dx).powi(2) / s.radius)
                .collect(),
            shift: vec![0.0; springs],
            bound: s.mu * s.e_star / s.g_star,
            stiffness: -2.0 * s.g_star * dx,
        }
    }

    /// The approach goes from δ to δ' while the contact point moves by Δ: a spring in contact
    /// adds Δ (an entering one the part after its entry) and is held within the Coulomb bound;
    /// one out of contact has u = 0.
    fn step(&mut self, delta: f64, next: f64, shift: f64) {
        for (u, &g) in self.shift.iter_mut().zip(&self.profile) {
            if next <= g {
                *u = 0.0;
                continue;
            }
            let part = if delta >= g {
                1.0
            } else {
                (next - g) / (next - delta)
            };
            let limit = self.bound * (next - g);
            *u = (*u + part * shift).clamp(-limit, limit);
        }
    }

    /// `F_t = −G* ∫ u dx`.
    fn force(&self) -> f64 {
        self.stiffness * self.shift.iter().sum::<f64>()
    }
}

/// The linear-oscillator estimate `w'/w = cos(π√κ)` of the sticking contact point (exact at
/// κ = 1 only; module doc).
pub fn linear_oscillator(kappa: f64) -> f64 {
    (std::f64::consts::PI * kappa.sqrt()).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chung & Ooi's aluminium oxide in the case's units (R = E = ρ = 1).
    fn alumina() -> Mbf {
        Mbf::sphere(1.0, 1.0, 1.0, 0.23, 0.092).unwrap()
    }

    /// `k_t/k_n = G*/E* = 2(1 − ν)/(2 − ν)`, Mindlin over Hertz, the χ of `maw_incidence`.
    #[test]
    fn stiffness_ratio_is_mindlins() {
        let s = alumina();
        let chi = 2.0 * (1.0 - 0.23) / (2.0 - 0.23);
        assert!((s.g_star / s.e_star - chi).abs() < 1e-14);
        assert!((s.kappa() - 3.5 * chi).abs() < 1e-14);
        let theta = 10f64.to_radians();
        assert!(
            (s.psi(theta) - super::super::oblique::maw_incidence(0.23, 0.092, theta)).abs() < 1e-14
        );
        assert!((linear_oscillator(1.0) + 1.0).abs() < 1e-15);
    }

    /// Bad input is refused with the field named.
    #[test]
    fn refuses_bad_input() {
        assert!(Mbf::sphere(1.0, 1.0, 1.0, 0.5, 0.1).is_err());
        assert!(Mbf::sphere(1.0, -1.0, 1.0, 0.2, 0.1).is_err());
        let s = alumina();
        let e = s.impact(0.01, 0.0, REPORT_RESOLUTION).unwrap_err();
        assert!(e.to_string().contains("incidence"), "{e}");
        let zero = Resolution {
            steps: 0,
            springs: 10,
        };
        assert!(s.impact(0.01, 0.1, zero).is_err());
    }
}
