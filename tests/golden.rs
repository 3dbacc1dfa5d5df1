//! Golden snapshots (insta, stored in `golden/`): the summary metrics of every case × space ×
//! scheme declared in the `[[sweep]]` tables of `cases/*.toml`, at the coarsest level of each
//! sweep, rounded to 6 significant digits (runs that fail are snapshotted with their status and
//! reason, unstable runs, whose digits are amplified round-off, with that verdict only). Review an intended change with `cargo insta review`, or accept all with
//! `INSTA_UPDATE=always cargo test --release --test golden`.

use dyncontact::output::sig6;
use dyncontact::study::jobs::{self, RunRecord};

fn opt(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), value)
}

/// 6 significant digits; values below 1e-10 in magnitude (round-off: the penetration of an exact
/// contact solve, the energy drift of a conservative scheme, a vanished velocity) only by order.
fn value(x: f64) -> String {
    if x.abs() < 1e-10 {
        "< 1e-10".into()
    } else {
        sig6(x)
    }
}

/// Energy drift above which a run is unstable and only that verdict is snapshotted.
const UNSTABLE: f64 = 1.0;

fn snapshot_text(r: &RunRecord) -> String {
    let (s, m) = (&r.summary, &r.summary.metrics);
    let mut lines = vec![
        format!(
            "case: {}  space: {}  scheme: {} ({})",
            s.case, s.space, s.scheme, s.parameters
        ),
        format!("status: {}  {}", r.status.as_str(), r.reason)
            .trim_end()
            .to_string(),
        format!(
            "h: {}  dt: {}  dofs: {}  steps: {}",
            sig6(s.h),
            sig6(s.dt),
            s.dofs,
            s.steps
        ),
    ];
    let finished = r.status != jobs::Status::Unsupported && r.status != jobs::Status::Failed;
    if finished && m.energy_drift > UNSTABLE {
        // An energy that grows by O(1) is amplified round-off: its digits change with any
        // summation order, so only the verdict is pinned.
        lines.push(format!("unstable: energy drift > {UNSTABLE}"));
    } else if finished {
        lines.extend([
            format!("energy_drift: {}", value(m.energy_drift)),
            format!("energy_ratio: {}", value(m.energy_ratio)),
            format!("max_penetration: {}", value(m.max_penetration)),
            format!("err_u_linf_l2: {}", opt(m.err_u_linf_l2)),
            format!("err_u_l2_h1: {}", opt(m.err_u_l2_h1)),
            format!("err_sigma_l2: {}", opt(m.err_sigma_l2)),
            format!("err_energy: {}", opt(m.err_energy)),
            format!("err_u_contact: {}", opt(m.err_u_contact)),
            format!("sigma_total_variation: {}", value(m.sigma_total_variation)),
            format!("restitution_eff: {}", opt(m.restitution_eff)),
            format!("impact_time_err: {}", opt(m.impact_time_err)),
        ]);
        // Errors against Hertz (curved-body cases only) and the friction metrics (runs with
        // friction only), so that the others stay as they were.
        let groups = [
            vec![
                ("err_contact_duration", m.err_contact_duration),
                ("err_peak_force", m.err_peak_force),
                ("err_max_approach", m.err_max_approach),
                ("err_contact_radius", m.err_contact_radius),
                ("err_peak_pressure", m.err_peak_pressure),
            ],
            vec![
                ("slide_velocity_err", m.slide_velocity_err),
                ("stop_time", m.stop_time),
                ("stop_distance", m.stop_distance),
                ("friction_balance", m.friction_balance),
                ("friction_work_min_step", m.friction_work_min_step),
            ],
            vec![
                ("tangential_restitution", m.tangential_restitution),
                ("rebound_spin", m.rebound_spin),
                ("normal_impulse", m.normal_impulse),
                ("tangential_impulse", m.tangential_impulse),
            ],
        ];
        for group in groups.iter().filter(|g| g.iter().any(|x| x.1.is_some())) {
            lines.extend(group.iter().map(|(k, v)| format!("{k}: {}", opt(*v))));
        }
    }
    lines.join("\n")
}

#[test]
fn summary_metrics_of_every_combination_are_unchanged() {
    let mut count = 0;
    for case in dyncontact::report::case_files(std::path::Path::new("cases")).unwrap() {
        let all: Vec<_> = jobs::jobs(&case, true)
            .unwrap()
            .into_iter()
            .filter(|j| j.level == 0)
            .collect();
        for record in jobs::run_jobs(&all, false) {
            let s = &record.summary;
            let params = s.parameters.replace(['=', ';'], "_");
            let name = format!(
                "{}__{}__{}__{}_{params}",
                s.case, record.sweep, s.space, s.scheme
            )
            .trim_end_matches('_')
            .to_string();
            insta::with_settings!({snapshot_path => "../golden", prepend_module_to_snapshot => false}, {
                insta::assert_snapshot!(name, snapshot_text(&record));
            });
            count += 1;
        }
    }
    // bar1d 6 spaces × 15 schemes and 3 spaces × 4 contact formulations, bar_flight 6 × 15,
    // block2d 5 × 2 and 3 × 9, block3d 5 × 1, spring_mass 7 schemes, hertz2d 3 spaces, hertz3d
    // 2 + 1, two_bars and two_bars_unequal 5 × 8 each, slide2d 5 × 6 with friction and 5 × 4
    // without, slide3d 4 × 5 and 4 × 4, two_discs 5 × 6, two_spheres 4 × 4, oblique3d 2 × 4,
    // roll2d 1 × 1 rolling and 1 × 1 sliding.
    assert_eq!(
        count,
        6 * 15
            + 3 * 4
            + 6 * 15
            + 5 * 2
            + 3 * 9
            + 5
            + 7
            + 3
            + 3
            + 2 * 5 * 8
            + 5 * 6
            + 5 * 4
            + 4 * 5
            + 4 * 4
            + 5 * 6
            + 4 * 4
            + 2 * 4
            + 2,
        "one snapshot per case × space × scheme"
    );
}
