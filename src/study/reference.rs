//! Reference errors for cases without an exact solution, at the probe, against two references:
//! - `err_u_contact`, `err_sigma_l2`: the finest finished level of the same case × sweep × space
//!   × scheme (a series converges to itself);
//! - `err_u_contact_ref`, `err_sigma_l2_ref`: one common reference per case × sweep, the finest
//!   finished level of [`common_reference`], so that the spaces' errors compare with each other.

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

/// A run series within a case × sweep: `(space, scheme, parameters)`.
pub type Series = (String, String, String);

/// The common reference series of a case × sweep: mass redistribution when swept (else the
/// first space), with the first scheme of the sweep.
pub fn common_reference<'a>(group: impl Iterator<Item = &'a RunRecord> + Clone) -> Option<Series> {
    let space = group
        .clone()
        .map(|r| &r.summary.space)
        .find(|s| *s == crate::space::REFERENCE)
        .or_else(|| group.clone().map(|r| &r.summary.space).next())?
        .clone();
    let first = group.clone().next()?;
    Some((
        space,
        first.summary.scheme.clone(),
        first.summary.parameters.clone(),
    ))
}

/// `(max_n |u − u_ref|, (Σ_n Δt (σ − σ_ref)²)^{1/2})` of a probe series against a reference
/// probe series (interpolated linearly in time; the probe must sit at the same point on every
/// level: the block sweeps use even cell counts so that the centre of Γ_C is a vertex).
fn probe_errors(probe: &[(f64, f64, f64)], reference: &[(f64, f64, f64)], dt: f64) -> (f64, f64) {
    let u_ref: Vec<(f64, f64)> = reference.iter().map(|p| (p.0, p.1)).collect();
    let s_ref: Vec<(f64, f64)> = reference.iter().map(|p| (p.0, p.2)).collect();
    let du = probe.iter().map(|p| (p.1 - interpolate(&u_ref, p.0)).abs());
    let ds = probe
        .iter()
        .skip(1)
        .map(|p| dt * (p.2 - interpolate(&s_ref, p.0)).powi(2));
    (du.fold(0.0, f64::max), ds.sum::<f64>().sqrt())
}

/// `set(metrics, err_u, err_σ)` of every record of `members` but the reference itself, the
/// finest level of `series`, against that reference's probe series.
fn against_finest(
    records: &mut [RunRecord],
    members: &[usize],
    series: &[usize],
    set: impl Fn(&mut super::metrics::Metrics, f64, f64),
) {
    let Some(top) = series.iter().copied().max_by_key(|&i| records[i].level) else {
        return;
    };
    let reference = std::mem::take(&mut records[top].probe);
    for &i in members.iter().filter(|&&i| i != top) {
        let r = &mut records[i];
        let (eu, es) = probe_errors(&r.probe, &reference, r.summary.dt);
        set(&mut r.summary.metrics, eu, es);
    }
    records[top].probe = reference;
}

/// For cases without an exact solution (records carrying a probe series): the errors of the
/// module doc, computed afresh (values read back from a journal are dropped first); a reference
/// run gets no error against itself. Frees the probe series.
pub fn reference_errors(records: &mut [RunRecord]) {
    for r in records.iter_mut().filter(|r| !r.probe.is_empty()) {
        let m = &mut r.summary.metrics;
        (m.err_u_contact, m.err_sigma_l2) = (None, None);
        (m.err_u_contact_ref, m.err_sigma_l2_ref) = (None, None);
    }
    let with_probe = |records: &[RunRecord], idx: Vec<usize>| -> Vec<usize> {
        idx.into_iter()
            .filter(|&i| !records[i].probe.is_empty())
            .collect()
    };
    for (_, indices) in group_by(0..records.len(), |&i| records[i].series_key()) {
        let members = with_probe(records, indices);
        against_finest(records, &members, &members, |m, eu, es| {
            m.err_u_contact = Some(eu);
            m.err_sigma_l2 = Some(es);
        });
    }
    let by_sweep = |i: &usize| (records[*i].summary.case.clone(), records[*i].sweep.clone());
    for (_, indices) in group_by(0..records.len(), by_sweep) {
        let Some(key) = common_reference(indices.iter().map(|&i| &records[i])) else {
            continue;
        };
        let in_reference = |r: &RunRecord| {
            (&r.summary.space, &r.summary.scheme, &r.summary.parameters) == (&key.0, &key.1, &key.2)
        };
        let members = with_probe(records, indices);
        let series: Vec<usize> = members
            .iter()
            .copied()
            .filter(|&i| in_reference(&records[i]))
            .collect();
        against_finest(records, &members, &series, |m, eu, es| {
            m.err_u_contact_ref = Some(eu);
            m.err_sigma_l2_ref = Some(es);
        });
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
            contact: "nodal".into(),
            degree: Some(1),
            cells: "quad".into(),
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
            key: format!("block2d-s-standard-newmark-{level}"),
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

    #[test]
    fn the_common_reference_is_the_finest_mass_redistribution_level() {
        let mut mr = record(1, 0.01, 0.5);
        mr.summary.space = "mass_redistribution".into();
        let mut r = vec![record(0, 0.1, 0.0), record(1, 0.01, 0.0), mr];
        reference_errors(&mut r);
        let m = |i: usize| r[i].summary.metrics;
        // Against its own finest level the standard series converges to itself ...
        assert!(m(0).err_u_contact.unwrap() < 2e-5);
        // ... and against the common reference both levels are 0.5 away.
        for i in [0, 1] {
            assert!((m(i).err_u_contact_ref.unwrap() - 0.5).abs() < 2e-5, "{i}");
        }
        assert!(m(2).err_u_contact_ref.is_none() && m(2).err_u_contact.is_none());
    }
}
