//! Reference errors for cases without an exact solution.

use super::jobs::RunRecord;
use crate::util::group_by;

/// Linear interpolation of `(t, value)` samples (sorted by t) at `t`.
fn interpolate(series: &[(f64, f64)], t: f64) -> f64 {
    let k = series.partition_point(|p| p.0 < t);
    if k == 0 {
        return series[0].1;
    }
    if k == series.len() {
        return series[k - 1].1;
    }
    let ((t0, v0), (t1, v1)) = (series[k - 1], series[k]);
    v0 + (v1 - v0) * (t - t0) / (t1 - t0)
}

/// For cases without an exact solution: `err_u_contact = max_n |u_h(t_n) − u_ref(t_n)|` and
/// `err_sigma_l2 = (Σ_n Δt (σ_h − σ_ref)²)^{1/2}` at the probe, against the finest finished level
/// of the same case × sweep × space × scheme (interpolated linearly in time; the probe must sit at
/// the same point on every level: the block sweeps use even cell counts so that the centre of Γ_C
/// is a vertex). The reference run itself gets no error. Frees the probe series.
pub fn reference_errors(records: &mut [RunRecord]) {
    for (_, indices) in group_by(0..records.len(), |&i| records[i].series_key()) {
        let members: Vec<usize> = indices
            .into_iter()
            .filter(|&i| !records[i].probe.is_empty())
            .collect();
        let Some(&finest) = members.iter().max_by_key(|&&i| records[i].level) else {
            continue;
        };
        let u_ref: Vec<(f64, f64)> = records[finest].probe.iter().map(|p| (p.0, p.1)).collect();
        let s_ref: Vec<(f64, f64)> = records[finest].probe.iter().map(|p| (p.0, p.2)).collect();
        for &i in members.iter().filter(|&&i| i != finest) {
            let r = &mut records[i];
            let dt = r.summary.dt;
            let du = r
                .probe
                .iter()
                .map(|p| (p.1 - interpolate(&u_ref, p.0)).abs());
            let ds = r
                .probe
                .iter()
                .skip(1)
                .map(|p| dt * (p.2 - interpolate(&s_ref, p.0)).powi(2));
            r.summary.metrics.err_u_contact = Some(du.fold(0.0, f64::max));
            r.summary.metrics.err_sigma_l2 = Some(ds.sum::<f64>().sqrt());
        }
    }
    for r in records.iter_mut() {
        r.probe = Vec::new();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::jobs::Status;
    use crate::study::metrics::Metrics;
    use crate::study::run::Summary;

    fn record(level: usize, dt: f64, offset: f64) -> RunRecord {
        let summary = Summary {
            case: "block2d".into(),
            space: "standard".into(),
            scheme: "newmark".into(),
            parameters: String::new(),
            h: 0.1 / (level + 1) as f64,
            dt,
            dofs: 1,
            steps: (1.0 / dt) as usize,
            contact_iterations: 0,
            wall_time: 0.0,
            max_rss: f64::NAN,
            metrics: Metrics::default(),
        };
        let n = (1.0 / dt).round() as usize;
        let probe = (0..=n)
            .map(|k| {
                let t = k as f64 * dt;
                (t, t.sin() + offset, t.cos())
            })
            .collect();
        RunRecord {
            sweep: "s".into(),
            level,
            status: Status::Ok,
            reason: String::new(),
            summary,
            probe,
        }
    }

    #[test]
    fn reference_errors_compare_against_the_finest_level() {
        let mut r = vec![record(0, 0.1, 0.25), record(1, 0.01, 0.0)];
        reference_errors(&mut r);
        let (eu, es) = (
            r[0].summary.metrics.err_u_contact,
            r[0].summary.metrics.err_sigma_l2,
        );
        // u differs by 0.25 plus the interpolation error of sin at dt = 0.01 (< 1.3e-5).
        assert!((eu.unwrap() - 0.25).abs() < 2e-5, "{eu:?}");
        assert!(es.unwrap() < 1e-4, "{es:?}");
        assert!(r[1].summary.metrics.err_u_contact.is_none());
        assert!(r.iter().all(|x| x.probe.is_empty()));
    }
}
