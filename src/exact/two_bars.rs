//! Exact solution of two elastic bars meeting end to end (`shared/reference/bar_flight_and_two_bars.md`;
//! Hughes, Taylor, Sackman, Curnier & Kanoknukulchai 1976), by characteristics.
//!
//! Bar 1 on (−L₁, 0) at velocity +v₀, bar 2 on (0, L₂) at −v₀, same E, ρ (c = √(E/ρ),
//! impedance z = ρc), unstressed and touching at t = 0, free at their far ends, Signorini contact
//! at x = 0. Each bar is described in its own coordinate y ∈ (0, L) pointing away from the
//! interface (bar 1: y = −x, so u = −u_y, v = −v_y, σ unchanged), where it approaches the interface
//! at speed v₀. The Riemann invariants `R = σ − z v_y` (constant along dy/dt = +c) and
//! `Λ = σ + z v_y` (along dy/dt = −c) are `R⁰ = z v₀`, `Λ⁰ = −z v₀` at t = 0; the free end
//! reflects `Λ = −R`; the interface emits `r_k(t)` (piecewise constant) into bar k given the
//! arriving `l_k(t)`:
//! - contact (`l₁ + l₂ ≤ 0`, gap closed): `σ = (l₁ + l₂)/2`, both ends at the same velocity,
//!   `r₁ = l₂`, `r₂ = l₁` (equal impedances: full transmission);
//! - separated: `σ = 0`, `v_y = l_k / z`, `r_k = −l_k`, the gap opening at `(l₁ + l₂)/z`.
//!
//! Then `σ = (R + Λ)/2`, `v_y = (Λ − R)/(2z)` and `u_y = ∫₀ᵗ v_y` exactly (integrals of piecewise
//! constants). Equal bars: contact on (0, 2L/c) with σ = −ρcv₀, then both leave with reversed
//! velocities, at rest inside. Lengths L₁ < L₂: contact with σ = −ρcv₀ on (0, 2L₁/c), then the
//! short bar moves at −v₀ with σ = 0 while the long bar's end follows it with zero force and zero
//! gap (grazing) on (2L₁/c, 2L₂/c), separation at 2L₂/c (not 4L₁/c: the two coincide for
//! L₂ = 2L₁); the long bar keeps the momentum ρ(2L₁ − L₂)v₀ and the vibration energy
//! `½ρL₂v₀² − ½ρ(2L₁ − L₂)²v₀²/L₂` (1 for L = 1, 2 and E = ρ = v₀ = 1).

use super::{ContactValues, ExactContact};

/// One interval of constant interface state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Start time.
    pub t0: f64,
    /// End time.
    pub t1: f64,
    /// The invariant `r_k` emitted into bar k.
    pub r: [f64; 2],
    /// True while the bars are in contact (possibly with zero force).
    pub contact: bool,
    /// Interface stress σ (≤ 0; 0 when separated).
    pub sigma: f64,
    /// The gap at t0 and its rate.
    pub gap: (f64, f64),
    /// `∫₀^{t0} r_k` (prefix integrals).
    cum: [f64; 2],
}

/// The two-bar impact with its interface history up to a horizon.
#[derive(Debug, Clone, PartialEq)]
pub struct TwoBars {
    /// L₁, L₂.
    pub lengths: [f64; 2],
    /// E.
    pub young: f64,
    /// ρ.
    pub density: f64,
    /// v₀ (each bar approaches the interface at v₀).
    pub speed: f64,
    /// The interface history, consecutive segments from t = 0 to the horizon.
    pub segments: Vec<Segment>,
}

impl TwoBars {
    /// The solution up to time `horizon` (beyond it the last interface state is extended).
    pub fn new(lengths: [f64; 2], young: f64, density: f64, speed: f64, horizon: f64) -> Self {
        let mut s = Self {
            lengths,
            young,
            density,
            speed,
            segments: Vec::new(),
        };
        s.build(horizon);
        s
    }

    /// Wave speed c.
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }

    fn impedance(&self) -> f64 {
        self.density * self.wave_speed()
    }

    /// The interface history by events: the arriving invariants change at `τ + 2L_k/c` for every
    /// segment start τ; a separated gap may close.
    fn build(&mut self, horizon: f64) {
        let (c, z) = (self.wave_speed(), self.impedance());
        let eps = 1e-12 * (horizon + self.lengths[0] + self.lengths[1]) / c;
        let (mut t, mut gap, mut cum) = (0.0, 0.0, [0.0; 2]);
        while t < horizon {
            let delays = self.lengths.map(|l| 2.0 * l / c);
            let mut next = self
                .segments
                .iter()
                .map(|s| s.t0)
                .chain([t])
                .flat_map(|t0| delays.map(|d| t0 + d))
                .filter(|&x| x > t + eps)
                .fold(horizon.max(t + eps), f64::min);
            let mid = 0.5 * (t + next);
            let l = [self.arriving(0, mid), self.arriving(1, mid)];
            let sum = l[0] + l[1];
            let (contact, r, rate) = if gap <= 0.0 && sum <= 0.0 {
                (true, [l[1], l[0]], 0.0)
            } else {
                (false, [-l[0], -l[1]], sum / z)
            };
            let mut closes = false;
            if rate < 0.0 && t + gap / -rate < next {
                next = t + gap / -rate;
                closes = true;
            }
            self.segments.push(Segment {
                t0: t,
                t1: next,
                r,
                contact,
                sigma: if contact { 0.5 * sum } else { 0.0 },
                gap: (gap, rate),
                cum,
            });
            for (k, ck) in cum.iter_mut().enumerate() {
                *ck += r[k] * (next - t);
            }
            gap = if closes {
                0.0
            } else {
                (gap + rate * (next - t)).max(0.0)
            };
            t = next;
        }
    }

    /// The segment containing time t (the first for t < 0, the last beyond the horizon).
    pub fn segment(&self, t: f64) -> &Segment {
        let i = self.segments.partition_point(|s| s.t0 <= t);
        &self.segments[i.saturating_sub(1)]
    }

    /// `∫₀^τ r_k` (0 for τ ≤ 0).
    fn emitted_integral(&self, k: usize, tau: f64) -> f64 {
        if tau <= 0.0 {
            return 0.0;
        }
        let s = self.segment(tau);
        s.cum[k] + s.r[k] * (tau - s.t0)
    }

    /// `(R, ∫₀ᵗ R)` at (y, t) in bar k: `R⁰` until the first front from the interface, then
    /// `r_k(t − y/c)`.
    fn right(&self, k: usize, y: f64, t: f64) -> (f64, f64) {
        let (c, r0) = (self.wave_speed(), self.impedance() * self.speed);
        let delay = y / c;
        let before = r0 * t.min(delay).max(0.0);
        if t < delay {
            return (r0, before + self.emitted_integral(k, t - delay));
        }
        // One search for the value and the integral (the report's field errors of the two-bar
        // cases call this a few times per quadrature point and step).
        let (tau, s) = (t - delay, self.segment(t - delay));
        let integral = if tau <= 0.0 {
            0.0
        } else {
            s.cum[k] + s.r[k] * (tau - s.t0)
        };
        (s.r[k], before + integral)
    }

    /// `(Λ, ∫₀ᵗ Λ)` at (y, t) in bar k: `Λ⁰` until the reflection from the free end arrives,
    /// then `−R(L, t − (L − y)/c)`.
    fn left(&self, k: usize, y: f64, t: f64) -> (f64, f64) {
        let l0 = -self.impedance() * self.speed;
        let delay = (self.lengths[k] - y) / self.wave_speed();
        if t < delay {
            return (l0, l0 * t.max(0.0));
        }
        let (r, int_r) = self.right(k, self.lengths[k], t - delay);
        (-r, l0 * delay - int_r)
    }

    /// The invariant Λ arriving at the interface from bar k at time t.
    fn arriving(&self, k: usize, t: f64) -> f64 {
        self.left(k, 0.0, t).0
    }

    /// `(u_y, σ, v_y)` at distance y ∈ [0, L_k] from the interface in bar k, in its own
    /// coordinate (pointing away from the interface).
    pub fn local(&self, k: usize, y: f64, t: f64) -> (f64, f64, f64) {
        let z = self.impedance();
        let (r, int_r) = self.right(k, y, t);
        let (l, int_l) = self.left(k, y, t);
        (
            (int_l - int_r) / (2.0 * z),
            0.5 * (r + l),
            (l - r) / (2.0 * z),
        )
    }

    /// `(u, σ, v)` at x ∈ [−L₁, L₂] (x < 0: bar 1, x ≥ 0: bar 2).
    pub fn field(&self, x: f64, t: f64) -> (f64, f64, f64) {
        if x < 0.0 {
            let (u, s, v) = self.local(0, -x, t);
            (-u, s, -v)
        } else {
            self.local(1, x, t)
        }
    }

    /// The positions y (bar k's coordinate) of the fronts at time t: every change of `r_k` at τ,
    /// at `y = c(t − τ)` on its way out and `2L − c(t − τ)` after its reflection (a front that
    /// came back to the interface is a later change of the emitted invariants). Sorted.
    pub fn fronts(&self, k: usize, t: f64) -> Vec<f64> {
        let (c, l) = (self.wave_speed(), self.lengths[k]);
        let r0 = self.impedance() * self.speed;
        let mut prev = r0;
        let mut out = Vec::new();
        for s in self.segments.iter().take_while(|s| s.t0 < t) {
            if s.r[k] != prev {
                let d = c * (t - s.t0);
                if d < l {
                    out.push(d);
                } else if d < 2.0 * l {
                    out.push(2.0 * l - d);
                }
            }
            prev = s.r[k];
        }
        out.sort_by(f64::total_cmp);
        out
    }

    /// The exact `u_y(·, t)` of bar k as the linear function it is between consecutive fronts
    /// (R and Λ are constant there): `(right end, value at y = 0 of the line, slope σ/E)`, left
    /// to right, the last ending at L_k; one evaluation per piece.
    pub fn linear_pieces(&self, k: usize, t: f64) -> Vec<(f64, f64, f64)> {
        let ends = self.fronts(k, t).into_iter().chain([self.lengths[k]]);
        super::lines_between(ends, self.young, |y| {
            let (u, sigma, _) = self.local(k, y, t);
            (u, sigma)
        })
    }

    /// The end of the first contact: the start of the first separated segment whose gap opens.
    pub fn separation(&self) -> Option<f64> {
        self.segments
            .iter()
            .find(|s| !s.contact && s.gap.1 > 0.0)
            .map(|s| s.t0)
    }

    /// `(∫ρ v_y, ½∫ρ v² + σ²/E)` of bar k at time t: exact, the fields being constant between
    /// the fronts. The momentum is along the bar's own y (bar 1: −x).
    pub fn momentum_energy(&self, k: usize, t: f64) -> (f64, f64) {
        let l = self.lengths[k];
        let mut cuts = vec![0.0];
        cuts.extend(self.fronts(k, t));
        cuts.push(l);
        let (mut p, mut e) = (0.0, 0.0);
        for w in cuts.windows(2) {
            let (_, s, v) = self.local(k, 0.5 * (w[0] + w[1]), t);
            let len = w[1] - w[0];
            p += self.density * v * len;
            e += 0.5 * (self.density * v * v + s * s / self.young) * len;
        }
        (p, e)
    }
}

impl ExactContact for TwoBars {
    /// At bar 1's end (the slave, x = 0⁻): its displacement and velocity, the interface stress.
    fn contact(&self, t: f64) -> ContactValues {
        let (u, _, v) = self.local(0, 0.0, t);
        ContactValues {
            u: -u,
            v: -v,
            sigma: self.segment(t).sigma,
        }
    }

    /// `½ρ(L₁ + L₂)v₀²` (unit section).
    fn energy(&self, _t: f64) -> f64 {
        0.5 * self.density * (self.lengths[0] + self.lengths[1]) * self.speed * self.speed
    }

    /// The bars touch at t = 0.
    fn first_impact(&self) -> Option<f64> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(l2: f64) -> TwoBars {
        TwoBars::new([1.0, l2], 1.0, 1.0, 1.0, 12.0)
    }

    /// Equal bars: contact with σ = −ρcv₀ on (0, 2), separation at 2 with reversed velocities and
    /// no vibration (both bars uniform at −v₀ in their own coordinate, σ = 0), the interface at
    /// rest during contact.
    #[test]
    fn equal_bars_leave_with_reversed_velocities() {
        let ex = pair(1.0);
        assert_eq!(ex.separation(), Some(2.0));
        for t in [0.3, 1.0, 1.7] {
            let s = ex.segment(t);
            assert!(s.contact && s.sigma == -1.0, "{s:?}");
            assert!(ex.field(0.0, t).0.abs() < 1e-14);
        }
        for t in [2.5, 5.0, 11.0] {
            for x in [-0.9, -0.4, -0.01, 0.0, 0.3, 0.99] {
                let (_, s, v) = ex.field(x, t);
                assert!(s.abs() < 1e-15 && (v.abs() - 1.0).abs() < 1e-15, "{x} {t}");
                assert_eq!(v.signum(), if x < 0.0 { -1.0 } else { 1.0 });
            }
            let c = ex.contact(t);
            assert!((c.u + (t - 2.0)).abs() < 1e-12 && c.sigma == 0.0, "{c:?}");
        }
    }

    /// Lengths 1 and 2: contact on (0, 2) at σ = −1, grazing (zero force, zero gap) on (2, 4),
    /// separation at 4 = 2L₂/c; after it the short bar flies at −v₀ undeformed, the long bar
    /// keeps momentum ρ(2L₁ − L₂)v₀ = 0 and vibration energy 1; total energy 3/2 and momentum
    /// ρ(L₁ − L₂)v₀ = −1 at every time.
    #[test]
    fn bars_of_lengths_one_and_two_graze_then_separate() {
        let ex = pair(2.0);
        assert_eq!(ex.separation(), Some(4.0));
        for t in [0.5, 1.5] {
            assert_eq!(ex.segment(t).sigma, -1.0);
        }
        for t in [2.2, 3.0, 3.9] {
            let s = ex.segment(t);
            assert!(s.sigma == 0.0 && s.gap == (0.0, 0.0), "{s:?}");
            let (u1, _, v1) = ex.field(-1e-300, t);
            let (u2, _, v2) = ex.field(0.0, t);
            assert!((u1 - u2).abs() < 1e-12 && v1 == -1.0 && v2 == -1.0, "{t}");
        }
        for t in [4.5, 7.3, 11.9] {
            let (p1, e1) = ex.momentum_energy(0, t);
            let (p2, e2) = ex.momentum_energy(1, t);
            // Bar 1's y is −x: momentum along x is −p1.
            assert!((-p1 + 1.0).abs() < 1e-12 && (e1 - 0.5).abs() < 1e-12, "{t}");
            assert!(p2.abs() < 1e-12 && (e2 - 1.0).abs() < 1e-12, "{t}");
            assert!(ex.segment(t).gap.0 + ex.segment(t).gap.1 * (t - ex.segment(t).t0) > 0.0);
        }
        for t in [0.0, 0.7, 1.3, 2.9, 3.5, 5.5, 9.1] {
            let (p1, e1) = ex.momentum_energy(0, t);
            let (p2, e2) = ex.momentum_energy(1, t);
            assert!((-p1 + p2 + 1.0).abs() < 1e-12, "momentum at {t}");
            assert!((e1 + e2 - 1.5).abs() < 1e-12, "energy at {t}");
        }
    }

    /// General lengths: the long bar's momentum and vibration energy after separation are
    /// `ρ(2L₁ − L₂)v₀` and `½ρL₂v₀² − ½ρ(2L₁ − L₂)²v₀²/L₂`, separation at 2L₂/c.
    #[test]
    fn the_long_bar_keeps_the_momentum_and_vibration_of_characteristics() {
        for l2 in [1.3, 1.7, 2.6, 3.0] {
            let ex = TwoBars::new([1.0, l2], 1.0, 1.0, 1.0, 4.0 * l2);
            assert!((ex.separation().unwrap() - 2.0 * l2).abs() < 1e-12, "{l2}");
            let t = 2.0 * l2 + 0.37;
            let (p2, e2) = ex.momentum_energy(1, t);
            let p = -(2.0 - l2);
            // Bar 2's y is x; its momentum along x is p2 = ρ(2L₁ − L₂)v₀ (towards −x when < 0).
            assert!((p2 + p).abs() < 1e-12, "{l2}: {p2}");
            let vibration = 0.5 * l2 - 0.5 * p * p / l2;
            assert!((e2 - 0.5 * p2 * p2 / l2 - vibration).abs() < 1e-12, "{l2}");
            let (_, s, v) = ex.local(0, 0.5, t);
            assert!(s == 0.0 && v == 1.0, "short bar at −v₀: {s} {v}");
        }
    }

    /// The pieces between the fronts reproduce the field: `u_y` and `σ = E u_y'` at points away
    /// from the fronts, at times of contact, grazing and flight.
    #[test]
    fn linear_pieces_reproduce_the_field_between_the_fronts() {
        let ex = TwoBars::new([1.0, 1.7], 2.0, 0.5, 0.8, 12.0);
        for k in 0..2 {
            for i in 0..60 {
                let t = 0.017 + 0.19 * i as f64;
                let pieces = ex.linear_pieces(k, t);
                assert_eq!(pieces.last().map(|p| p.0), Some(ex.lengths[k]));
                for j in 0..41 {
                    let y = ex.lengths[k] * j as f64 / 40.0;
                    if ex.fronts(k, t).iter().any(|f| (f - y).abs() < 1e-9) {
                        continue;
                    }
                    let p = pieces[pieces.partition_point(|p| p.0 < y).min(pieces.len() - 1)];
                    let (u, s, _) = ex.local(k, y, t);
                    assert!((p.1 + p.2 * y - u).abs() < 1e-12, "u at {k} {y} {t}");
                    assert!((ex.young * p.2 - s).abs() < 1e-12, "σ at {k} {y} {t}");
                }
            }
        }
    }

    /// The field solves the problem: u_t = v and E u_x = σ by centred differences away from the
    /// fronts (u is piecewise linear), σ = 0 at the free ends, gap ≥ 0 and σ ≤ 0 at the
    /// interface, equal velocities and stresses while in contact.
    #[test]
    fn the_field_satisfies_the_wave_equation_and_the_contact_law() {
        let ex = pair(2.0);
        let d = 1e-6;
        for k in 0..2 {
            for i in 0..40 {
                let t = 0.013 + 0.29 * i as f64;
                let l = ex.lengths[k];
                for j in 0..17 {
                    let y = l * (0.011 + 0.058 * j as f64);
                    let near = |tt: f64| ex.fronts(k, tt).iter().any(|f| (f - y).abs() < 4.0 * d);
                    if near(t) || near(t - d) || near(t + d) {
                        continue;
                    }
                    let (_, s, v) = ex.local(k, y, t);
                    let ut = (ex.local(k, y, t + d).0 - ex.local(k, y, t - d).0) / (2.0 * d);
                    let ux = (ex.local(k, y + d, t).0 - ex.local(k, y - d, t).0) / (2.0 * d);
                    assert!((ut - v).abs() < 1e-7, "u_t at {k} {y} {t}: {ut} vs {v}");
                    assert!((ux - s).abs() < 1e-7, "u_x at {k} {y} {t}: {ux} vs {s}");
                }
                assert!(ex.local(k, l, t).1.abs() < 1e-14, "free end {k} at {t}");
            }
        }
        for i in 0..200 {
            let t = 0.031 + 0.06 * i as f64;
            let (a, b) = (ex.local(0, 0.0, t), ex.local(1, 0.0, t));
            let gap = a.0 + b.0;
            assert!(gap > -1e-12 && b.1 <= 0.0, "{t}");
            if ex.segment(t).contact {
                assert!(
                    gap.abs() < 1e-12 && (a.2 + b.2).abs() < 1e-12 && a.1 == b.1,
                    "{t}"
                );
            } else {
                assert!(a.1 == 0.0 && b.1 == 0.0, "{t}");
            }
        }
    }
}
