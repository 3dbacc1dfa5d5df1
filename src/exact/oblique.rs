//! Oblique impact of a sphere on a rigid plane with Coulomb friction: the rigid-body (Routh)
//! limits, Maw, Barber & Fawcett's normalised incidence, and Chung & Ooi's reference curve
//! (`shared/reference/friction.md`, `notes/papers/friction.md` §4).
//!
//! Solid sphere (I = ⅖ m R²), incidence θ from the normal, `v_n = V cos θ`, `v_t = V sin θ`,
//! normal restitution e. A tangential impulse J_t changes the centre's tangential velocity by
//! `J_t/m` and the contact point's by `(1 + m R²/I) J_t/m = 7/2 · J_t/m`, so:
//! - it slides throughout iff `tan θ ≥ 7/2 μ (1 + e)`; then `|J_t| = μ J_n`,
//!   `e_t := v_t'/v_t = 1 − μ (1 + e)/tan θ` and `ω' R = 5/2 μ (1 + e) v_n`;
//! - otherwise (rigid, no compliance) the contact point ends at rest: `e_t = 5/7`,
//!   `ω' R = 5/7 v_t`.
//!
//! With tangential compliance (Maw, Barber & Fawcett, Wear 38 (1976) 101–114; the paper is not
//! readable here) the contact point's final tangential velocity `w'` lies in `[−w, w]` while the
//! contact sticks (the tangential compliance returns at most the energy it stored; microslip
//! dissipates), so `e_t = 1 − (1 − w'/w)·2/7 ∈ [3/7, 1]`: the band of the stick regime. Maw's
//! normalised incidence is `ψ₁ = χ tan θ / μ`, `χ = 2(1 − ν)/(2 − ν)` the Mindlin-over-Hertz
//! stiffness ratio of a sphere on a rigid plane (derived in `notes/papers/friction.md` §4.1).
//!
//! Chung & Ooi, Granular Matter 13 (2011) 643–656, test 4 (aluminium oxide, ν = 0.23,
//! μ = 0.092, normal restitution 0.98 in the DEM codes): the paper is not readable here;
//! [`CHUNG_OOI_ET`] and [`CHUNG_OOI_SPIN`] are its finite element curves **as digitised by the
//! Kratos developers** from the paper's figure (`DEMApplication/tests/DEM3D_chung_ooi_tests/
//! test4_data/paper_data/benchmark4_graph{1,2}_ref.dat`): a digitised figure, not a table.

/// The sphere's `1 + m R²/I` (I = ⅖ m R²): the contact point's tangential velocity changes
/// 7/2 times as much as the centre's.
const CONTACT_FACTOR: f64 = 3.5;

/// The rigid-body oblique impact: μ, incidence θ (radians), normal restitution e.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oblique {
    /// Friction coefficient μ.
    pub mu: f64,
    /// Incidence θ from the normal, radians.
    pub incidence: f64,
    /// Normal restitution e.
    pub restitution: f64,
}

impl Oblique {
    /// Whether the contact point slides throughout: `tan θ ≥ 7/2 μ (1 + e)`.
    pub fn slides(&self) -> bool {
        self.incidence.tan() >= CONTACT_FACTOR * self.mu * (1.0 + self.restitution)
    }

    /// `e_t` when it slides throughout, `1 − μ (1 + e)/tan θ` (whatever the regime).
    pub fn sliding_restitution(&self) -> f64 {
        1.0 - self.mu * (1.0 + self.restitution) / self.incidence.tan()
    }

    /// The rigid body's tangential restitution `v_t'/v_t`: sliding, or 5/7.
    pub fn tangential_restitution(&self) -> f64 {
        if self.slides() {
            self.sliding_restitution()
        } else {
            1.0 - 1.0 / CONTACT_FACTOR
        }
    }

    /// The rigid body's rebound spin `ω' R / V` (positive: rolling forwards).
    pub fn spin(&self) -> f64 {
        let (s, c) = self.incidence.sin_cos();
        (CONTACT_FACTOR - 1.0)
            * if self.slides() {
                self.mu * (1.0 + self.restitution) * c
            } else {
                s / CONTACT_FACTOR
            }
    }
}

/// The stick regime's band of `e_t` with tangential compliance, `[3/7, 1]` (module doc).
pub const STICK_BAND: (f64, f64) = (1.0 - 2.0 / CONTACT_FACTOR, 1.0);

/// Maw's normalised incidence `ψ₁ = χ tan θ / μ`, `χ = 2(1 − ν)/(2 − ν)`.
pub fn maw_incidence(poisson: f64, mu: f64, incidence: f64) -> f64 {
    2.0 * (1.0 - poisson) / (2.0 - poisson) * incidence.tan() / mu
}

/// Chung & Ooi's test 4 (aluminium oxide): ν and μ.
pub const CHUNG_OOI: (f64, f64) = (0.23, 0.092);

/// Chung & Ooi's speed and radius (3.9 m/s, 2.5 mm), to put the digitised ω' (rad/s) as
/// `ω' R / V`.
const CHUNG_OOI_R_OVER_V: f64 = 0.0025 / 3.9;

/// Chung & Ooi test 4, aluminium oxide: `(θ in degrees, e_t)`, digitised by the Kratos
/// developers (module doc).
pub const CHUNG_OOI_ET: [(f64, f64); 13] = [
    (5.168316831683168, 0.9481054365733115),
    (10.158415841584159, 0.6869851729818782),
    (14.990099009900987, 0.6243822075782538),
    (20.059405940594054, 0.6161449752883033),
    (25.04950495049505, 0.6342668863261945),
    (30.118811881188115, 0.6836902800658979),
    (35.02970297029702, 0.7372322899505768),
    (40.01980198019801, 0.7808896210873147),
    (50.0, 0.8451400329489293),
    (59.98019801980197, 0.8929159802306426),
    (69.96039603960395, 0.9316309719934104),
    (80.01980198019803, 0.9662273476112028),
    (85.009900990099, 0.9827018121911039),
];

/// Chung & Ooi test 4, aluminium oxide: `(θ in degrees, ω' in rad/s)` (Kratos' sign: negative
/// is rolling forwards), digitised by the Kratos developers (module doc).
pub const CHUNG_OOI_SPIN: [(f64, f64); 13] = [
    (4.950690335305719, -19.266055045871674),
    (10.07889546351085, -212.99694189602457),
    (14.970414201183434, -377.8287461773701),
    (19.94082840236687, -510.5504587155963),
    (24.911242603550292, -599.388379204893),
    (29.960552268244577, -616.5137614678899),
    (34.93096646942801, -582.2629969418961),
    (39.98027613412229, -544.8012232415903),
    (50.0, -457.03363914373097),
    (60.01972386587771, -357.4923547400612),
    (69.96055226824458, -246.17737003058113),
    (80.05917159763312, -126.29969418960255),
    (85.02958579881656, -63.14984709480133),
];

/// [`CHUNG_OOI_SPIN`] as `(θ in degrees, ω' R / V)`, rolling forwards positive.
pub fn chung_ooi_spin() -> Vec<(f64, f64)> {
    CHUNG_OOI_SPIN
        .iter()
        .map(|&(t, w)| (t, -w * CHUNG_OOI_R_OVER_V))
        .collect()
}

/// The digitised point of `curve` nearest to θ (degrees), if within 1°.
pub fn nearest(curve: &[(f64, f64)], theta: f64) -> Option<(f64, f64)> {
    curve
        .iter()
        .copied()
        .filter(|p| (p.0 - theta).abs() <= 1.0)
        .min_by(|a, b| (a.0 - theta).abs().total_cmp(&(b.0 - theta).abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(degrees: f64) -> Oblique {
        Oblique {
            mu: CHUNG_OOI.1,
            incidence: degrees.to_radians(),
            restitution: 1.0,
        }
    }

    /// Above the sliding threshold (θ* = 32.78° for μ = 0.092, e = 1) the digitised curve is the
    /// rigid slide to 0.0015 in e_t and 2 % in ω' (friction.md §4.2; 1.7 % at 80°): a check of
    /// the digitisation, of μ, and of these formulas.
    #[test]
    fn the_digitised_curve_is_the_rigid_slide_at_large_incidence() {
        let threshold = (3.5 * 0.092 * 2.0_f64).atan().to_degrees();
        assert!((threshold - 32.78).abs() < 0.01, "{threshold}");
        let spin = chung_ooi_spin();
        for (&(t, et), &(ts, w)) in CHUNG_OOI_ET.iter().zip(&spin).filter(|p| p.0 .0 > 35.0) {
            let o = at(t);
            assert!(o.slides());
            assert!(
                (et - o.tangential_restitution()).abs() < 1.5e-3,
                "θ = {t}: e_t {et}"
            );
            assert!(
                (w / at(ts).spin() - 1.0).abs() < 0.02,
                "θ = {ts}: ω'R/V {w}"
            );
        }
        assert!(!at(20.0).slides() && at(20.0).tangential_restitution() == 5.0 / 7.0);
        assert!(
            (maw_incidence(0.23, 0.092, 5.168316831683168_f64.to_radians()) - 0.855).abs() < 1e-3
        );
        assert_eq!(
            nearest(&CHUNG_OOI_ET, 10.0).map(|p| p.1),
            Some(0.6869851729818782)
        );
        assert_eq!(nearest(&CHUNG_OOI_ET, 45.0), None);
    }
}
