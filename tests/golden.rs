//! Golden snapshots (insta, stored in `golden/`) of the summary metrics of bar1d × every space ×
//! Newmark {(¼, ½), (½, ½)} at a coarse resolution (10 elements, dt = h/2, T = 12), rounded to 6
//! significant digits. Review an intended change with `cargo insta review`, or accept all with
//! `INSTA_UPDATE=always cargo test --release --test golden`.

mod common;

use common::run_bar;
use dyncontact::output::sig6;
use dyncontact::space::SPACES;

fn opt(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), sig6)
}

/// Penetration is round-off (exact complementarity): only its order is platform independent.
fn penetration(p: f64) -> String {
    if p < 1e-12 {
        "< 1e-12".into()
    } else {
        sig6(p)
    }
}

#[test]
fn bar1d_summary_metrics_are_unchanged() {
    for space in SPACES {
        let degree = if *space == "singular_dynamic" { 2 } else { 1 };
        for (beta, gamma) in [(0.25, 0.5), (0.5, 0.5)] {
            let s = run_bar(space, 10, degree, beta, gamma, 0.05, 12.0).summary;
            let m = s.metrics;
            let text = [
                format!(
                    "case: {}  space: {}  scheme: {} ({})",
                    s.case, s.space, s.scheme, s.parameters
                ),
                format!(
                    "h: {}  dt: {}  dofs: {}  steps: {}",
                    sig6(s.h),
                    sig6(s.dt),
                    s.dofs,
                    s.steps
                ),
                format!("energy_drift: {}", sig6(m.energy_drift)),
                format!("energy_ratio: {}", sig6(m.energy_ratio)),
                format!("max_penetration: {}", penetration(m.max_penetration)),
                format!("err_u_linf_l2: {}", opt(m.err_u_linf_l2)),
                format!("err_u_l2_h1: {}", opt(m.err_u_l2_h1)),
                format!("err_sigma_l2: {}", opt(m.err_sigma_l2)),
                format!("err_energy: {}", opt(m.err_energy)),
                format!("err_u_contact: {}", opt(m.err_u_contact)),
                format!("sigma_total_variation: {}", sig6(m.sigma_total_variation)),
                format!("restitution_eff: {}", opt(m.restitution_eff)),
                format!("impact_time_err: {}", opt(m.impact_time_err)),
            ]
            .join("\n");
            let name = format!("bar1d__{space}__newmark_beta{beta}_gamma{gamma}");
            insta::with_settings!({snapshot_path => "../golden", prepend_module_to_snapshot => false}, {
                insta::assert_snapshot!(name, text);
            });
        }
    }
}
