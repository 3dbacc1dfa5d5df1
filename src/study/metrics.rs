//! Run metrics (DESIGN.md §6), computed from the probe time series and the field errors.

use super::trajectory::Row;
use crate::cases::Impact;
use crate::exact::hertz::Hertz;
use crate::exact::slide::Slide;

/// Metrics of one run. `None` where a metric does not apply (no exact solution, 0D case, …).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Metrics {
    /// `max_n |E_n − E_0| / |E_0|`; absolute, `max_n |E_n − E_0|`, when E_0 = 0 (a body at
    /// rest in its reference state: a relative drift would be 0/0).
    pub energy_drift: f64,
    /// `E_N / E_0` (`1 + E_N` when E_0 = 0).
    pub energy_ratio: f64,
    /// `max |E_n − E_0| / |E_0|` over the samples away from contact (no contact force at n nor
    /// at n − 1): the drift without the one-step dip of the three-level schemes' midpoint energy
    /// at each impact; None when the body is never free for two samples in a row. Absolute
    /// when E_0 = 0, as `energy_drift`.
    pub energy_drift_free: Option<f64>,
    /// `max(0, max_n −g_n)` at the probe.
    pub max_penetration: f64,
    /// `max_n ‖u_h − u‖_{L²(Ω)}` (0D: `max_n |u_h − u|`).
    pub err_u_linf_l2: Option<f64>,
    /// `(Σ_n Δt |u_h − u|²_{H¹(Ω)})^{1/2}` (H¹ seminorm).
    pub err_u_l2_h1: Option<f64>,
    /// `(Σ_n Δt (σ_h − σ)²)^{1/2}` at the contact point.
    pub err_sigma_l2: Option<f64>,
    /// `max_n |E_n − E(t_n)| / |E(0)|` against the exact energy (absolute when E(0) = 0).
    pub err_energy: Option<f64>,
    /// `max_n |u_h(0, t_n) − u(0, t_n)|` at the contact point.
    pub err_u_contact: Option<f64>,
    /// Total variation of σ_N over [0, T] divided by the exact one (1: as smooth as the exact
    /// stress); without an exact stress, divided by `2 max|σ_N|` (one clean pulse = 1).
    pub sigma_total_variation: f64,
    /// Effective restitution `−v(t⁺)/v(t⁻)` of the first impact (velocity at the last step
    /// before contact and at the first step after release).
    pub restitution_eff: Option<f64>,
    /// `|t̂ − t*|` for the first impact: t̂ = t_{n−1} + g_{n−1}/(−v_{n−1}) before the first
    /// active step, t* exact.
    pub impact_time_err: Option<f64>,
    /// Without exact solution: `err_u_contact` against the sweep's common reference
    /// ([`super::reference`]).
    pub err_u_contact_ref: Option<f64>,
    /// Without exact solution: `err_sigma_l2` against the sweep's common reference.
    pub err_sigma_l2_ref: Option<f64>,
    /// Hertz (sphere): `|t_c,h − t_c| / t_c`, t_c,h from the first to the last sample with a
    /// contact force, plus one step.
    pub err_contact_duration: Option<f64>,
    /// Hertz (sphere): `|F_max,h − F_max| / F_max`.
    pub err_peak_force: Option<f64>,
    /// Hertz (sphere): `|δ_max,h − δ_max| / δ_max`, δ the centre of mass's approach.
    pub err_max_approach: Option<f64>,
    /// Hertz: at peak force F_h, `|a_h − a(F_h)| / a(F_h)`, the computed contact radius (2D:
    /// half-width) from the second moment of the nodal forces, `a_h² = Σλ|x − x̄|² / (Σλ · c)`,
    /// c = 2/5 (sphere) or 1/4 (disc), the moment of the Hertz pressure.
    pub err_contact_radius: Option<f64>,
    /// Hertz: at peak force, `|p_h − p₀(F_h)| / p₀(F_h)`, p_h the largest `λ_i / area_i`.
    pub err_peak_pressure: Option<f64>,
    /// Slide (with friction): `max_n |v_h(t_n) − v(t_n)|`, the centre of mass's tangential
    /// velocity against the rigid slide `v = max(v₀ − μ g t, 0)` ([`Slide`]).
    pub slide_velocity_err: Option<f64>,
    /// Slide: the first sample with `v_h ≤ v₀/100` (the rigid body stops at `v₀/(μ g)`); None
    /// when the block still slides at the final time.
    pub stop_time: Option<f64>,
    /// Slide: the distance travelled by the centre of mass, `Σ_n Δt (v_h,n + v_h,n+1)/2` over
    /// the run (the rigid body stops after `v₀²/(2 μ g)`).
    pub stop_distance: Option<f64>,
    /// With friction: `max_n |E_n + W_f,n − E_0| / |E_0|`, the energy balance with the friction
    /// work (0 for a scheme that conserves the energy up to what friction dissipates).
    pub friction_balance: Option<f64>,
    /// With friction: `min_n (W_f,n+1 − W_f,n)`, the least work dissipated in a step (≥ 0: friction
    /// never gives energy back).
    pub friction_work_min_step: Option<f64>,
    /// Multi-body cases: `max_n |P_n − P_0|`, P the total linear momentum `(M̃1_d)ᵀV` along the
    /// line of impact (an invariant: no external force, equal and opposite contact forces).
    pub momentum_drift: Option<f64>,
    /// Oblique impact (a sphere with friction, released): `e_t = v_t(T)/v_t(0)`, the centre of
    /// mass's tangential restitution.
    pub tangential_restitution: Option<f64>,
    /// Oblique impact: the rebound angular velocity `ω(T)` (positive: rolling forwards).
    pub rebound_spin: Option<f64>,
    /// Oblique impact: the normal impulse of the contact forces, `J_n = m_n (v_n(T) − v_n(0))`
    /// (momentum balance: no other force acts; `m_n = 1_dᵀM̃1_d`).
    pub normal_impulse: Option<f64>,
    /// Oblique impact: the tangential impulse `J_t = m_t (v_t(T) − v_t(0))` (negative: against
    /// the motion; `m_t = 1_1ᵀM̃1_1`).
    pub tangential_impulse: Option<f64>,
}

/// One metric column of `summary.csv`: its name, and how to read and set it (`None` is an empty
/// field; a metric that always applies reads and writes NaN for a run that did not finish).
#[derive(Debug, Clone, Copy)]
pub struct MetricColumn {
    /// Column name (the field's name).
    pub name: &'static str,
    /// The value, None where it does not apply.
    pub get: fn(&Metrics) -> Option<f64>,
    /// Sets the value read back (an absent value of an always-applying metric is NaN).
    pub set: fn(&mut Metrics, Option<f64>),
}

/// The table of metric columns from the fields: `name: value` (an f64 field) or
/// `name: optional` (an `Option<f64>` field).
macro_rules! metric_columns {
    ($($name:ident: $kind:ident),* $(,)?) => {
        &[$(MetricColumn {
            name: stringify!($name),
            get: |m| metric_columns!(@get $kind, m.$name),
            set: |m, v| metric_columns!(@set $kind, m.$name, v),
        }),*]
    };
    (@get value, $field:expr) => { Some($field) };
    (@get optional, $field:expr) => { $field };
    (@set value, $field:expr, $v:expr) => { $field = $v.unwrap_or(f64::NAN) };
    (@set optional, $field:expr, $v:expr) => { $field = $v };
}

/// The metric columns of `summary.csv`, in order (DESIGN.md §6; the Hertz ones last).
pub const METRIC_COLUMNS: &[MetricColumn] = metric_columns![
    energy_drift: value,
    energy_ratio: value,
    max_penetration: value,
    err_u_linf_l2: optional,
    err_u_l2_h1: optional,
    err_sigma_l2: optional,
    err_energy: optional,
    err_u_contact: optional,
    sigma_total_variation: value,
    restitution_eff: optional,
    impact_time_err: optional,
    err_u_contact_ref: optional,
    err_sigma_l2_ref: optional,
    err_contact_duration: optional,
    err_peak_force: optional,
    err_max_approach: optional,
    err_contact_radius: optional,
    err_peak_pressure: optional,
    energy_drift_free: optional,
    slide_velocity_err: optional,
    stop_time: optional,
    stop_distance: optional,
    friction_balance: optional,
    friction_work_min_step: optional,
    momentum_drift: optional,
    tangential_restitution: optional,
    rebound_spin: optional,
    normal_impulse: optional,
    tangential_impulse: optional,
];

/// The energy drift to read first, and the other one ([`Metrics::drift`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drift {
    /// The drift to read first.
    pub value: f64,
    /// True when `value` is `energy_drift_free` (the samples away from contact).
    pub outside_impacts: bool,
    /// The other drift (`energy_drift` when `value` is the free one, and conversely), if any.
    pub other: Option<f64>,
}

/// `energy_drift` above this multiple of `energy_drift_free`: the impact steps' one-step dips
/// (three-level schemes' midpoint energy) dominate, and the drift outside them is the one that
/// says whether the energy holds.
pub const IMPACT_DIPS: f64 = 10.0;

impl Metrics {
    /// The energy drift to read first: `energy_drift_free` when the impact steps would mislead
    /// (`energy_drift` > [`IMPACT_DIPS`] × it), `energy_drift` otherwise; the other beside it.
    pub fn drift(&self) -> Drift {
        match self.energy_drift_free {
            Some(free) if self.energy_drift > IMPACT_DIPS * free => Drift {
                value: free,
                outside_impacts: true,
                other: Some(self.energy_drift),
            },
            free => Drift {
                value: self.energy_drift,
                outside_impacts: false,
                other: free,
            },
        }
    }

    /// Every metric that is not finite made absent (NaN for the ones that always apply, written
    /// as an empty field): a ratio over a near-zero reference that overflows (a tangential
    /// restitution over a subnormal tangential speed) measures nothing, and the states of the
    /// run are finite (a non-finite one stops it as diverged).
    pub fn drop_non_finite(&mut self) {
        for c in METRIC_COLUMNS {
            if (c.get)(self).is_some_and(|v| !v.is_finite()) {
                (c.set)(self, None);
            }
        }
    }

    /// Metrics of a run that did not finish: NaN or absent everywhere.
    pub fn unavailable() -> Self {
        Self {
            energy_drift: f64::NAN,
            energy_ratio: f64::NAN,
            max_penetration: f64::NAN,
            sigma_total_variation: f64::NAN,
            ..Self::default()
        }
    }
}

impl std::fmt::Display for Drift {
    /// `2.500e-5 outside impact steps (9.931e-1 over every step)`, or `4.8e-2 (4.8e-2 outside
    /// impact steps)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.outside_impacts, self.other) {
            (true, Some(all)) => write!(
                f,
                "{:.3e} outside impact steps ({all:.3e} over every step)",
                self.value
            ),
            (false, Some(free)) => {
                write!(f, "{:.3e} ({free:.3e} outside impact steps)", self.value)
            }
            _ => write!(f, "{:.3e}", self.value),
        }
    }
}

/// `x / |scale|`, or `x` itself when the scale is 0: the energy errors are relative to the
/// initial energy, and absolute for a run that starts without energy.
fn relative(x: f64, scale: f64) -> f64 {
    if scale == 0.0 {
        x
    } else {
        x / scale.abs()
    }
}

/// The first sample whose energy departs from E(0) by more than `factor` × `max(|E(0)|, w)` (by
/// more than `factor` when both are 0, as `energy_drift`): `(sample, t, |E − E(0)| / scale)`.
/// Every step is a sample, so the sample is the step. A loss counts too: the energy holds −Fᵀu
/// and Nitsche's −½γσ², so an unstable mode can drive it to −∞ (hertz2d, Nitsche γ₀ = 3.5,
/// backward Euler: −2.2e146). `w`, the loads' work across the bodies, is the scale of a run
/// whose E(0) is near 0 against that work (roll2d at a slope of nearly π/2: E(0) = 7.7e-8):
/// relative to |E(0)| alone, a scheme's dissipation would exceed it.
pub fn first_blowup(rows: &[Row], factor: f64, w: f64) -> Option<(usize, f64, f64)> {
    let e0 = rows.first()?.energy;
    let scale = e0.abs().max(w);
    rows.iter()
        .enumerate()
        .map(|(i, r)| (i, r.t, relative((r.energy - e0).abs(), scale)))
        .find(|(_, _, drift)| *drift > factor)
}

fn total_variation(x: impl Iterator<Item = f64>) -> f64 {
    let mut prev: Option<f64> = None;
    let mut tv = 0.0;
    for v in x {
        if let Some(p) = prev {
            tv += (v - p).abs();
        }
        prev = Some(v);
    }
    tv
}

/// Computes the metrics. `field` holds the field errors at the same samples as `rows` (may be
/// empty); `stress_is_function` tells whether the exact σ_N is a function (not impulses).
/// `exact_first_impact` is the exact time of the first impact, when known.
pub fn compute(
    rows: &[Row],
    field: &[(f64, f64)],
    dt: f64,
    stress_is_function: bool,
    exact_first_impact: Option<f64>,
) -> Metrics {
    let e0 = rows[0].energy;
    let energy_drift = relative(
        rows.iter()
            .map(|r| (r.energy - e0).abs())
            .fold(0.0, f64::max),
        e0,
    );
    let e_n = rows[rows.len() - 1].energy;
    let energy_ratio = if e0 == 0.0 { 1.0 + e_n } else { e_n / e0 };
    let energy_drift_free = rows
        .windows(2)
        .filter(|w| w[0].force_contact == 0.0 && w[1].force_contact == 0.0)
        .map(|w| relative((w[1].energy - e0).abs(), e0))
        .reduce(f64::max);
    let max_penetration = rows.iter().map(|r| -r.gap).fold(0.0, f64::max);
    let tv = total_variation(rows.iter().map(|r| r.sigma_contact));
    let has_exact = rows[0].exact.is_some();
    let exact_tv = total_variation(rows.iter().filter_map(|r| r.exact.map(|e| e.1)));
    let sigma_total_variation = if has_exact && stress_is_function && exact_tv > 0.0 {
        tv / exact_tv
    } else {
        let peak = rows
            .iter()
            .map(|r| r.sigma_contact.abs())
            .fold(0.0, f64::max);
        if peak > 0.0 {
            tv / (2.0 * peak)
        } else {
            0.0
        }
    };
    let l2_time = |f: &dyn Fn(usize) -> f64| {
        (1..rows.len())
            .map(|i| dt * f(i).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let exact_metric = |f: &dyn Fn() -> f64| has_exact.then(f);
    let (impact, restitution_eff) = first_impact(rows);
    Metrics {
        energy_drift,
        energy_ratio,
        energy_drift_free,
        max_penetration,
        err_u_linf_l2: (!field.is_empty()).then(|| field.iter().map(|e| e.0).fold(0.0, f64::max)),
        err_u_l2_h1: (!field.is_empty() && !field[0].1.is_nan()).then(|| l2_time(&|i| field[i].1)),
        err_sigma_l2: (has_exact && stress_is_function)
            .then(|| l2_time(&|i| rows[i].sigma_contact - rows[i].exact.map_or(0.0, |e| e.1))),
        err_energy: exact_metric(&|| {
            let ref_e = rows[0].exact.map_or(1.0, |e| e.2);
            relative(
                rows.iter()
                    .map(|r| (r.energy - r.exact.map_or(0.0, |e| e.2)).abs())
                    .fold(0.0, f64::max),
                ref_e,
            )
        }),
        err_u_contact: exact_metric(&|| {
            rows.iter()
                .map(|r| (r.u_contact - r.exact.map_or(0.0, |e| e.0)).abs())
                .fold(0.0, f64::max)
        }),
        sigma_total_variation,
        restitution_eff,
        impact_time_err: impact.zip(exact_first_impact).map(|(a, b)| (a - b).abs()),
        err_u_contact_ref: None,
        err_sigma_l2_ref: None,
        err_contact_duration: None,
        err_peak_force: None,
        err_max_approach: None,
        err_contact_radius: None,
        err_peak_pressure: None,
        momentum_drift: rows[0].momentum.map(|p0| {
            rows.iter()
                .filter_map(|r| r.momentum)
                .map(|p| (p - p0).abs())
                .fold(0.0, f64::max)
        }),
        ..Metrics::default()
    }
}

/// The friction metrics of a run with Coulomb friction (rows with `friction`): the energy
/// balance `E + W_f = E(0)` and the least step of `W_f`, and with a rigid slide to compare with,
/// the centre of mass's velocity error, its stopping time and distance. Nothing for a
/// frictionless run.
pub fn friction(m: &mut Metrics, rows: &[Row], slide: Option<&Slide>) {
    let series: Vec<(f64, f64, f64)> = rows
        .iter()
        .filter_map(|r| r.friction.map(|(v, w)| (r.t, v, w)))
        .collect();
    if series.len() != rows.len() || rows.is_empty() {
        return;
    }
    let e0 = rows[0].energy;
    m.friction_balance = Some(relative(
        rows.iter()
            .zip(&series)
            .map(|(r, s)| (r.energy + s.2 - e0).abs())
            .fold(0.0, f64::max),
        e0,
    ));
    m.friction_work_min_step = series.windows(2).map(|w| w[1].2 - w[0].2).reduce(f64::min);
    let Some(slide) = slide else {
        return;
    };
    m.slide_velocity_err = Some(
        series
            .iter()
            .map(|s| (s.1 - slide.velocity(s.0)).abs())
            .fold(0.0, f64::max),
    );
    m.stop_time = series
        .iter()
        .find(|s| s.1 <= STOPPED * slide.speed)
        .map(|s| s.0);
    m.stop_distance = Some(
        series
            .windows(2)
            .map(|w| 0.5 * (w[1].0 - w[0].0) * (w[0].1 + w[1].1))
            .sum(),
    );
}

/// The oblique-impact metrics of a sphere thrown at the plane with friction (rows with
/// `friction` and `spin`, moving towards the plane at t = 0 and released at the last two
/// samples; nothing otherwise): `e_t`, `ω'`, the impulses from the momentum the contact changed
/// (`masses = (m_t, m_n)`), and the normal restitution `−v_n(T)/v_n(0)` of the centre of mass
/// (replaces the probe's). Not called for a body under a load: its momentum also holds the
/// load's impulse (a disc thrown under gravity).
pub fn oblique(m: &mut Metrics, rows: &[Row], (m_t, m_n): (f64, f64)) {
    let n = rows.len();
    let (Some(first), Some(last)) = (rows.first(), rows.last()) else {
        return;
    };
    let (Some((vt0, _)), Some((vn0, _)), Some((vt, _)), Some((vn, w))) =
        (first.friction, first.spin, last.friction, last.spin)
    else {
        return;
    };
    if vn0 >= 0.0 || n < 2 || rows[n - 2].force_contact != 0.0 || last.force_contact != 0.0 {
        return;
    }
    m.restitution_eff = Some(-vn / vn0);
    m.tangential_restitution = (vt0 != 0.0).then(|| vt / vt0);
    m.rebound_spin = Some(w);
    m.normal_impulse = Some(m_n * (vn - vn0));
    m.tangential_impulse = Some(m_t * (vt - vt0));
}

/// A block sliding slower than this fraction of v₀ has stopped ([`Metrics::stop_time`]).
pub const STOPPED: f64 = 0.01;

/// What an impact run measures against an impact model: the contact duration (first to last
/// sample with a contact force, plus one step), the peak total force and the maximum approach
/// of the centre of mass (None for a case without one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactMeasures {
    /// Contact duration t_c.
    pub duration: f64,
    /// Peak total contact force F_max.
    pub peak_force: f64,
    /// Maximum approach δ_max.
    pub max_approach: Option<f64>,
}

impl ImpactMeasures {
    /// The measures of a time series, None when it has no contact.
    pub fn of(rows: &[Row]) -> Option<Self> {
        let first = rows.iter().find(|r| r.force_contact > 0.0)?;
        let last = rows.iter().rev().find(|r| r.force_contact > 0.0)?;
        let dt = rows.get(1).map_or(0.0, |r| r.t - rows[0].t);
        Some(Self {
            duration: last.t - first.t + dt,
            peak_force: rows.iter().map(|r| r.force_contact).fold(0.0, f64::max),
            max_approach: rows.iter().filter_map(|r| r.approach).reduce(f64::max),
        })
    }

    /// Signed relative errors `(x_h − x) / x` of (t_c, F_max, δ_max) against `h` (sphere).
    pub fn errors(&self, h: &Hertz) -> [Option<f64>; 3] {
        let rel = |x: f64, y: Option<f64>| y.map(|y| (x - y) / y);
        [
            rel(self.duration, h.duration()),
            rel(self.peak_force, h.peak_force()),
            self.max_approach.and_then(|d| rel(d, h.max_approach())),
        ]
    }
}

/// The Hertz metrics of an impact run: duration (none while the contact is still on at the last
/// sample), peak force, maximum approach (sphere) and the profile (none while the force still
/// rises at the last sample), the
/// pressure profile at peak force (`peak`: the nodal forces λ at the sample of largest total
/// force and the tributary areas), and the restitution from the centre of mass's velocity
/// after release (`−(δ_N − δ_{N−1}) / (Δt v)`, when the force is zero at the last two samples;
/// replaces the probe's).
pub fn hertz(m: &mut Metrics, rows: &[Row], (lambda, area): (&[f64], &[f64]), impact: &Impact) {
    let h = &impact.hertz;
    let rel = |x: f64, y: Option<f64>| y.map(|y| (x - y).abs() / y);
    let Some(measures) = ImpactMeasures::of(rows) else {
        return;
    };
    [m.err_contact_duration, m.err_peak_force, m.err_max_approach] =
        measures.errors(h).map(|e| e.map(f64::abs));
    let n = rows.len();
    // A contact still on at t_end has lasted at least that long: no duration to compare; and
    // while its force still rises there, no peak either (the force, approach and profile at
    // the peak are compared below only when the peak lies before the last sample).
    let cut = rows.last().filter(|r| r.force_contact > 0.0);
    let rising = cut.is_some_and(|r| r.force_contact >= measures.peak_force);
    if cut.is_some() {
        m.err_contact_duration = None;
    }
    if rising {
        [m.err_peak_force, m.err_max_approach] = [None, None];
        return;
    }
    let dt = rows.get(1).map_or(0.0, |r| r.t - rows[0].t);
    if n >= 2 && rows[n - 1].force_contact == 0.0 && rows[n - 2].force_contact == 0.0 {
        if let (Some(a), Some(b)) = (rows[n - 1].approach, rows[n - 2].approach) {
            m.restitution_eff = Some(-(a - b) / (dt * h.speed));
        }
    }
    let force: f64 = lambda.iter().sum();
    if force > 0.0 && lambda.len() == impact.positions.len() {
        let (r, _) = impact.distances(lambda);
        let moment = lambda.iter().zip(&r).map(|(l, r)| l * r * r).sum::<f64>() / force;
        let radius = (moment / h.second_moment_ratio()).sqrt();
        m.err_contact_radius = rel(radius, Some(h.contact_radius(force)));
        let p = lambda
            .iter()
            .zip(area)
            .map(|(l, a)| l / a)
            .fold(0.0, f64::max);
        m.err_peak_pressure = rel(p, Some(h.peak_pressure(force)));
    }
}

/// Index of the first active step (σ_N < 0), the impact time estimate and the effective
/// restitution of the first impact.
fn first_impact(rows: &[Row]) -> (Option<f64>, Option<f64>) {
    let Some(first) = rows.iter().position(|r| r.sigma_contact < 0.0) else {
        return (None, None);
    };
    if first == 0 {
        return (None, None);
    }
    let before = rows[first - 1];
    let t_hat = if before.v_contact < 0.0 {
        Some(before.t + before.gap / (-before.v_contact))
    } else {
        None
    };
    let release = rows[first..]
        .iter()
        .position(|r| r.sigma_contact == 0.0 && r.gap > 0.0);
    // A body that touches at rest (a slide: v = 0 before the first contact) has no
    // restitution. Not `v < 0`: the probe's sign is the case's.
    let e = release
        .filter(|_| before.v_contact != 0.0)
        .map(|k| -rows[first + k].v_contact / before.v_contact);
    (t_hat, e)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ratio over a subnormal reference (a tangential restitution over a tangential speed of
    /// 1e-322) overflowed into `-inf`, which the journal then refused to read back.
    #[test]
    fn a_metric_that_overflows_is_absent() {
        let mut m = Metrics {
            energy_drift: f64::INFINITY,
            tangential_restitution: Some(f64::NEG_INFINITY),
            rebound_spin: Some(0.5),
            ..Metrics::default()
        };
        m.drop_non_finite();
        assert!(m.energy_drift.is_nan());
        assert_eq!(
            (m.tangential_restitution, m.rebound_spin),
            (None, Some(0.5))
        );
    }

    /// The README's spring example: one impact step dips the midpoint energy to 0.99 of E(0),
    /// while it holds to 2.5e-5 elsewhere; the headline is the latter, the other beside it.
    #[test]
    fn the_headline_drift_leaves_out_the_impact_dips_only_when_they_mislead() {
        let mut m = Metrics {
            energy_drift: 0.9931,
            energy_drift_free: Some(2.5e-5),
            ..Metrics::default()
        };
        let d = m.drift();
        assert!(d.outside_impacts && d.value == 2.5e-5 && d.other == Some(0.9931));
        assert_eq!(
            d.to_string(),
            "2.500e-5 outside impact steps (9.931e-1 over every step)"
        );
        m.energy_drift = 4.8e-2;
        m.energy_drift_free = Some(4.7e-2);
        let d = m.drift();
        assert!(!d.outside_impacts && d.value == 4.8e-2);
        assert_eq!(d.to_string(), "4.800e-2 (4.700e-2 outside impact steps)");
        m.energy_drift_free = None;
        assert_eq!(m.drift().to_string(), "4.800e-2");
    }

    fn rows(energy: &[f64]) -> Vec<Row> {
        energy
            .iter()
            .enumerate()
            .map(|(n, &e)| Row {
                t: n as f64,
                u_contact: 0.0,
                v_contact: 0.0,
                sigma_contact: 0.0,
                energy: e,
                gap: 0.0,
                force_contact: 0.0,
                approach: None,
                momentum: None,
                master: None,
                friction: None,
                spin: None,
                exact: Some((0.0, 0.0, 0.0)),
            })
            .collect()
    }

    /// The first step whose energy left `factor` × E(0), relative as `energy_drift` (absolute
    /// from E(0) = 0), and the same maximum as `energy_drift` past it.
    #[test]
    fn a_blow_up_is_dated_at_its_first_step() {
        let grown = rows(&[2.0, 3.0, 150.0, 1e9, 4.0]);
        assert_eq!(
            first_blowup(&grown, 100.0, 0.0),
            Some((3, 3.0, (1e9 - 2.0) / 2.0))
        );
        assert_eq!(first_blowup(&grown[..3], 100.0, 0.0), None);
        let m = compute(&grown, &[], 1.0, true, None);
        assert!(m.energy_drift > 100.0 && first_blowup(&grown, m.energy_drift, 0.0).is_none());
        assert_eq!(
            first_blowup(&rows(&[0.0, 50.0, -150.0]), 100.0, 0.0),
            Some((2, 2.0, 150.0))
        );
        assert_eq!(first_blowup(&[], 100.0, 0.0), None);
    }

    #[test]
    fn the_energy_errors_are_absolute_when_the_initial_energy_is_zero() {
        let m = compute(&rows(&[0.0, 0.0, 0.0]), &[], 1.0, true, None);
        assert_eq!(
            (
                m.energy_drift,
                m.energy_ratio,
                m.energy_drift_free,
                m.err_energy
            ),
            (0.0, 1.0, Some(0.0), Some(0.0))
        );
        let m = compute(&rows(&[0.0, 2e-3, 1e-3]), &[], 1.0, true, None);
        assert_eq!((m.energy_drift, m.energy_ratio), (2e-3, 1.0 + 1e-3));
        assert_eq!(
            (m.energy_drift_free, m.err_energy),
            (Some(2e-3), Some(2e-3))
        );
        // Relative otherwise.
        let m = compute(&rows(&[2.0, 2.5, 1.0]), &[], 1.0, false, None);
        assert_eq!((m.energy_drift, m.energy_ratio), (0.5, 0.5));
    }
}
