//! How the report names the fitted quantities ([`crate::study::orders::FITTED`]): a short symbol
//! for table headers and legends, and what is measured, for axis labels and captions. Plot text
//! carries no markup (no literal underscores: subscripts are Unicode or words).

/// A fitted quantity as the report names it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Named {
    /// Metric column.
    pub key: &'static str,
    /// Short symbol (table headers, sentences).
    pub symbol: &'static str,
    /// Shortest symbol (matrix cells).
    pub short: &'static str,
    /// What is measured (axis label).
    pub axis: &'static str,
}

/// Every fitted quantity, in [`crate::study::orders::FITTED`] order.
pub const NAMED: [Named; 12] = [
    Named {
        key: "err_u_linf_l2",
        short: "u",
        symbol: "u in L∞(L²)",
        axis: "max over t of ‖uₕ − u‖ in L²(Ω)",
    },
    Named {
        key: "err_u_contact",
        short: "u",
        symbol: "u at the probe",
        axis: "max over t of |uₕ − u| at the contact probe",
    },
    Named {
        key: "err_u_l2_h1",
        short: "u",
        symbol: "u in L²(H¹)",
        axis: "‖uₕ − u‖ in L²(0, T; H¹(Ω)) (seminorm)",
    },
    Named {
        key: "err_energy",
        short: "E",
        symbol: "energy",
        axis: "max over t of |Eₕ − E| / E(0)",
    },
    Named {
        key: "err_sigma_l2",
        short: "σₙ",
        symbol: "σₙ in L²(0,T)",
        axis: "‖σₙ,ₕ − σₙ‖ in L²(0, T) at the contact probe",
    },
    Named {
        key: "impact_time_err",
        short: "t_{imp}",
        symbol: "first impact time",
        axis: "|first impact time − exact|",
    },
    Named {
        key: "err_u_contact_ref",
        short: "u",
        symbol: "u at the probe (common ref.)",
        axis: "max over t of |uₕ − u of the reference run| at the contact probe",
    },
    Named {
        key: "err_sigma_l2_ref",
        short: "σₙ",
        symbol: "σₙ in L²(0,T) (common ref.)",
        axis: "‖σₙ,ₕ − σₙ of the reference run‖ in L²(0, T) at the probe",
    },
    Named {
        key: "err_contact_duration",
        short: "t_{c}",
        symbol: "contact duration",
        axis: "|contact duration − Hertz| / Hertz",
    },
    Named {
        key: "err_peak_force",
        short: "F_{max}",
        symbol: "peak force",
        axis: "|Fmax − Hertz| / Hertz",
    },
    Named {
        key: "err_contact_radius",
        short: "a",
        symbol: "contact radius at peak force",
        axis: "|a − Hertz(F)| / Hertz(F) at peak force",
    },
    Named {
        key: "err_peak_pressure",
        short: "p_{0}",
        symbol: "peak pressure at peak force",
        axis: "|p₀ − Hertz(F)| / Hertz(F) at peak force",
    },
];

/// The report's name of the fitted quantity `key`.
pub fn named(key: &str) -> Option<Named> {
    NAMED.iter().copied().find(|n| n.key == key)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::orders::FITTED;

    /// Every fitted quantity has a name, in the same order.
    #[test]
    fn every_fitted_quantity_is_named() {
        let keys: Vec<&str> = NAMED.iter().map(|n| n.key).collect();
        assert_eq!(keys, FITTED);
        for n in NAMED {
            assert!(!n.axis.contains('_'), "{}: literal underscore", n.key);
        }
    }
}
