//! `COLUMNS.md`: every column of every CSV file a report (and `run`, `sweep`) writes, with its
//! meaning and unit, generated from the column lists themselves so that a new column without a
//! description fails the test below. `reports/COLUMNS.md` is a checked-in copy.

use crate::study::{orders, peers, records, run, trajectory};
use std::fmt::Write as _;

/// Units: "1" for a dimensionless ratio, "case" for the case file's units (every shipped case
/// is non-dimensional), "—" for text and counts.
const DOCS: &[(&str, &str, &str)] = &[
    // Identification.
    ("key", "—", "the run's name, `<case file>-<sweep>-<space>-<scheme>[-<parameters>]-L<level>`; its probe series (cases without exact solution) is `probes/<key>.csv`"),
    ("case_hash", "—", "FNV-1a hash of the case file's text when the run was made (`--resume` reuses a run only when key and hash match)"),
    ("sweep", "—", "the `[[sweep]]` table's name"),
    ("level", "—", "refinement level, 0 = coarsest"),
    ("status", "—", "`ok`, `diverged` (state not finite, or an energy that moved from E(0), either way, by more than 100 max(|E(0)|, W), W the loads' work across the bodies' extent), `failed` (an error: unstable time step, solver failure, a two-body vertex past small sliding), `unsupported` (the combination is not defined), `internal` (a fault of dyncontact itself, which says nothing about the method: please report it)"),
    ("reason", "—", "why the run is not `ok` (empty otherwise)"),
    ("case", "—", "the case kind (`case` of the case file)"),
    ("space", "—", "space discretisation of the inertia (`dyncontact list`)"),
    ("scheme", "—", "time scheme"),
    ("parameters", "—", "the scheme's parameters `name=value;…`, then for a formulation other than `nodal` `contact=<label>` and its parameters, then `contact_solver=<name>` for a contact solver other than `active_set` (a friction run without one set takes `alart_curnier`, written as nothing) and `linear_solver=<name>` for a linear solver other than `auto` with a scheme that solves a linear system"),
    ("contact", "—", "contact formulation as labelled: `nodal`, `weak_p1`, `weak_p0`, `nitsche`, `penalty`"),
    ("degree", "—", "polynomial degree of the displacement (empty for the 0D spring)"),
    ("cells", "—", "cell shape: `segment` (1D), `triangle`, `quad`, `tet`, `hex` (empty for the 0D spring)"),
    ("h", "case (length)", "mesh size (empty for the 0D spring)"),
    ("dt", "case (time)", "time step"),
    ("dofs", "—", "displacement degrees of freedom"),
    ("steps", "—", "time steps taken"),
    ("contact_iterations", "—", "contact-solver iterations summed over the steps"),
    ("kind", "—", "`run` (one simulation) or `section` (a report section, its runs included)"),
    ("task", "—", "a run: its case, space, scheme, parameters, h, dt, steps, dofs and status (`ok` or `error`); a section: its name"),
    ("start_s", "s", "start of the task since the profile began"),
    ("end_s", "s", "end of the task since the profile began"),
    ("wall_s", "s", "wall time of the task"),
    ("cpu_s", "s", "user + system CPU time of the whole process over the task (the task's own when tasks do not overlap: `RAYON_NUM_THREADS=1`)"),
    ("thread_cpu_s", "s", "CPU time of the thread that ran the task"),
    ("rss_mb", "MB", "resident memory of the process at the end of the task"),
    ("wall_time_s", "s", "wall time of the run (assembly, factorisation and time loop); machine-dependent"),
    ("max_rss_mb", "MiB", "peak resident memory of the process when the run ended (`VmHWM`); with runs in parallel, an upper bound of the run's own"),
    ("time_per_step_s", "s", "`wall_time_s / steps`"),
    ("time_per_dof_step_s", "s", "`wall_time_s / (steps · dofs)`"),
    // Metrics.
    ("energy_drift", "1", "`max_n |E_n − E_0| / |E_0|` over every sample (absolute, `max_n |E_n − E_0|`, when E_0 = 0)"),
    ("energy_ratio", "1", "`E_N / E_0` at the final time (`1 + E_N` when E_0 = 0)"),
    ("energy_drift_free", "1", "`energy_drift` over the samples away from contact (no contact force at n nor n − 1); read it beside `energy_drift` for the three-level schemes, whose midpoint energy dips during an impact step"),
    ("momentum_drift", "case (mass·length/time)", "multi-body cases: `max_n |P_n − P_0|`, P the total linear momentum `(M̃1_d)ᵀV` along the line of impact (`momentum` of `timeseries.csv`), an invariant of a free pair"),
    ("max_penetration", "case (length)", "`max(0, max_n −g_n)` at the probe"),
    ("err_u_linf_l2", "case (length · length^(d/2))", "`max_n ‖u_h − u‖_{L²(Ω)}` against the exact solution (0D: `max_n |u_h − u|`)"),
    ("err_u_l2_h1", "case (length^(d/2) · time^(1/2))", "`(Σ_n Δt |u_h − u|²_{H¹(Ω)})^{1/2}` (H¹ seminorm) against the exact solution"),
    ("err_sigma_l2", "case (stress · time^(1/2))", "`(Σ_n Δt (σ_h − σ)²)^{1/2}` at the probe: against the exact stress, or (no exact solution) against the finest level of the same space × scheme"),
    ("err_energy", "1", "`max_n |E_n − E(t_n)| / |E(0)|` against the exact energy (absolute when E(0) = 0)"),
    ("err_u_contact", "case (length)", "`max_n |u_h − u|` at the probe: against the exact solution, or against the finest level of the same space × scheme"),
    ("sigma_total_variation", "1", "total variation of σ_N over [0, T] over the exact one (1: as smooth as the exact stress); without exact stress, over `2 max|σ_N|`"),
    ("restitution_eff", "1", "effective restitution `−v(after release) / v(before first contact)`, v the probe's velocity at the first sample with σ = 0 and a positive gap after the first contact (a bar's discrete end lifts off over a few steps: it reads the sharpness of the release, not the bar's rebound, which the energy gives); the impact cases: the centre of mass's normal velocities (a body under a load: the probe's)"),
    ("impact_time_err", "case (time)", "`|t̂ − t*|` of the first impact, t̂ extrapolated from the last free step, t* exact"),
    ("err_u_contact_ref", "case (length)", "`err_u_contact` against the sweep's common reference (the finest level of mass redistribution with the sweep's first scheme)"),
    ("err_sigma_l2_ref", "case (stress · time^(1/2))", "`err_sigma_l2` against the sweep's common reference"),
    ("err_contact_duration", "1", "`|t_c,h − t_c| / t_c` against Hertz (sphere); empty while the contact is still on at the last sample"),
    ("err_peak_force", "1", "`|F_max,h − F_max| / F_max` against Hertz (sphere); empty while the force still rises at the last sample (the peak not reached)"),
    ("err_max_approach", "1", "`|δ_max,h − δ_max| / δ_max` against Hertz, δ the centre of mass's approach since the first touch (sphere); empty while the force still rises at the last sample"),
    ("err_contact_radius", "1", "at peak force, `|a_h − a(F_h)| / a(F_h)`, a_h from the second moment of the nodal forces (2D: the half-width); empty while the force still rises at the last sample"),
    ("err_peak_pressure", "1", "at peak force, `|p_h − p₀(F_h)| / p₀(F_h)`, p_h the largest `λ_i / area_i`; empty while the force still rises at the last sample"),
    ("slide_velocity_err", "case (length/time)", "slide cases with friction: `max_n |v_h − max(v₀ − μgt_n, 0)|`, the centre of mass's tangential velocity against the rigid slide"),
    ("stop_time", "case (time)", "slide cases with friction: the first sample with centre-of-mass velocity ≤ v₀/100 (the rigid block stops at `v₀/(μg)`); empty when it never does"),
    ("stop_distance", "case (length)", "slide cases with friction: the distance the centre of mass travels over the run (trapezoidal rule on its velocity; the rigid block stops after `v₀²/(2μg)`)"),
    ("friction_balance", "1", "runs with friction: `max_n |E_n + W_f,n − E_0| / |E_0|`, the energy balance with the friction work (0 for a scheme that conserves energy up to what friction dissipates)"),
    ("friction_work_min_step", "case (energy)", "runs with friction: `min_n (W_f,n+1 − W_f,n)`, the least friction work of a step (negative: friction gave energy back)"),
    ("tangential_restitution", "1", "oblique impact (a sphere or disc with friction and no load, released by the final time): `e_t = v_t(T) / v_t(0)`, the centre of mass's tangential velocity after over before"),
    ("rebound_spin", "case (1/time)", "oblique impact (no load): the angular velocity ω at the final time (`angular_velocity`; positive: rolling forwards)"),
    ("normal_impulse", "case (mass·length/time)", "oblique impact (no load): `J_n = m_n (v_n(T) − v_n(0))`, the impulse of the contact forces along the normal from the momentum they changed (`m_n = 1ᵀM̃1` along the normal)"),
    ("tangential_impulse", "case (mass·length/time)", "oblique impact (no load): `J_t = m_t (v_t(T) − v_t(0))` along the first tangent (negative: against the motion); `|J_t| = μ J_n` when the contact slides throughout"),
    // orders.csv
    ("quantity", "—", "the metric column fitted"),
    ("order", "1", "least-squares slope of ln(error) against ln(h) (ln(dt) for the 0D spring) over the usable levels (status `ok`, error finite and > 0), fitted only where their sizes span at least 1.1 times; read it with `verdict`"),
    ("fit_residual", "1", "RMS residual of that fit, in ln (above 0.25 the errors do not lie on a line)"),
    ("points", "—", "levels used by the fit"),
    ("literature", "1", "the order expected from theory, where known (`1`, `1/3-1/2`)"),
    ("reference", "—", "what the errors are measured against: `exact`, `own finest level`, `Hertz theory`, or the common reference `<space> <scheme> (<parameters>) finest level`"),
    ("finest_error", "as the quantity", "the error at the finest usable level"),
    ("verdict", "—", "`meets` (≥ 70 % of the expected lower end, or ≥ 0.2 where none is known), `below` (converges more slowly), `stalls` (order below 0.2), `grows`, `flat` (finest error within 10 % of the coarsest), `irregular` (residual above 0.25), `too_few_levels` (fewer than two usable levels, or sizes within 1.1 times): only the first three make `order` an order"),
    // probes and timeseries.csv
    ("t", "case (time)", "time"),
    ("u_contact", "case (length)", "displacement of the probe's contact dof (the end x = 0 of the bar, the spring's mass, the vertex of Γ_C nearest the plane for the bodies)"),
    ("v_contact", "case (length/time)", "velocity of the probe; of a massless probe dof (mass redistribution's Γ_C normal dofs, whose velocity variable has no inertia), its mean over the last step `(u_n − u_{n−1})/Δt`"),
    ("sigma_contact", "case (stress)", "normal contact stress σ_N = −λ / area at the probe (compression < 0)"),
    ("energy", "case (energy)", "total energy of the body: kinetic + elastic + potential of the loads"),
    ("gap", "case (length)", "gap g = g₀ − B_N U at the probe"),
    ("force_contact", "case (force)", "total contact force Σλ (per unit thickness in 2D)"),
    ("approach", "case (length)", "displacement of the centre of mass towards the plane since the first touch, Hertz's approach δ: less the initial gap g₀ (`geometry.lift` and the mesh's height; two bodies: relative, body 2's towards body 1), so −g₀ at t = 0 (curved bodies)"),
    ("momentum", "case (mass·length/time)", "total linear momentum `(M̃1)ᵀV` along the line of impact, with the space's own mass (two free bodies: two_bars, two_discs, two_spheres; not slide_on_block2d, whose block rests on the plane)"),
    ("u_contact_master", "case (length)", "multi-body cases: displacement along the line of impact of the master's contact point facing the probe, `Σ N_k u_k,d` on the master face the probe's slave vertex projects on (the master bar's end in 1D); the master's probe, as `u_contact` is the slave's"),
    ("v_contact_master", "case (length/time)", "multi-body cases: velocity of that point, `Σ N_k v_k,d` (inertial velocity dofs; the H_h vertices for the singular dynamic method; with a massless dof among them, the mean over the last step of `u_contact_master`, as `v_contact`)"),
    ("com_velocity_t", "case (length/time)", "velocity of the centre of mass along the first tangent of the plane, `(M̃1)ᵀV / 1ᵀM̃1` with the space's own mass (runs with friction)"),
    ("friction_work", "case (energy)", "work dissipated by Coulomb friction so far, `W_f = Σ −r_T · u_T ≥ 0` on the slip each scheme measures (runs with friction); `energy + friction_work` is E(0) for an energy-conserving scheme"),
    ("com_velocity_n", "case (length/time)", "velocity of the centre of mass along the plane's normal, `(M̃1)ᵀV / 1ᵀM̃1` (a disc or sphere with friction)"),
    ("angular_velocity", "case (1/time)", "angular velocity ω of a disc or sphere with friction, `(M̃φ)ᵀV / φᵀM̃φ` with φ the rotation rolling it along the first tangent made M̃-orthogonal to the translations (angular momentum about the centre of mass over the moment of inertia, the space's own mass); the contact point slips at `com_velocity_t − R ω`"),
    ("u_contact_exact", "case (length)", "exact `u_contact`"),
    ("sigma_contact_exact", "case (stress)", "exact `sigma_contact`"),
    ("energy_exact", "case (energy)", "exact `energy`"),
    // cross_code.csv
    ("file", "—", "the GetFEM trajectory (repository's `golden/peers/`)"),
    ("brick", "—", "GetFEM's contact brick: `nodal` or `integral` (P1 multiplier)"),
    ("elements", "—", "elements per direction"),
    ("t_end", "case (time)", "final time"),
    ("samples", "—", "samples compared"),
    ("horizon", "case (time)", "first time a relative difference exceeds 1e-6 (the final time if none does)"),
    ("max_rel_u", "1", "`max |Δu| / max |u_GetFEM|`"),
    ("max_rel_sigma", "1", "`max |Δσ| / max |σ_GetFEM|`"),
    ("max_rel_energy", "1", "`max |ΔE| / E_GetFEM(0)`"),
    ("energy_growth_getfem", "1", "`max_t E / E(0)`, GetFEM"),
    ("energy_growth_dyncontact", "1", "`max_t E / E(0)`, dyncontact"),
    ("sigma_peak_getfem", "case (stress)", "`max_t |σ|`, GetFEM"),
    ("sigma_peak_dyncontact", "case (stress)", "`max_t |σ|`, dyncontact"),
    // <case>_finite_body.csv
    ("force", "case (force)", "total body force F of a static solve (the sphere pressed on the plane)"),
    ("approach_hertz", "case (length)", "Hertz's approach `(F/k)^{2/3}`"),
    ("coefficient", "1", "`c = (δ_Hertz − δ) E* R / F` of that solve"),
];

/// The files and their columns: name, what one row is, columns.
fn files() -> Vec<(&'static str, &'static str, Vec<&'static str>)> {
    let mut timeseries: Vec<&str> = trajectory::TIMESERIES_COLUMNS.to_vec();
    timeseries.extend(["approach", "momentum"]);
    timeseries.extend(trajectory::MASTER_COLUMNS);
    timeseries.extend(trajectory::FRICTION_COLUMNS);
    timeseries.extend(trajectory::SPIN_COLUMNS);
    timeseries.extend(trajectory::EXACT_COLUMNS);
    vec![
        (
            "summary.csv",
            "one row per run, in the order of the case files and their `[[sweep]]` tables; deterministic (no timing columns)",
            records::record_header(false),
        ),
        (
            "orders.csv",
            "one row per case × sweep × space × scheme × fitted quantity",
            orders::ORDER_COLUMNS.to_vec(),
        ),
        (
            "timings.csv",
            "one row per run that started stepping; machine-dependent",
            records::TIMINGS_COLUMNS.to_vec(),
        ),
        (
            "journal.csv",
            "one row per run, appended as runs finish, rewritten in run order at the end, then the recorded runs a narrower `--resume` (`--case`, `--quick`) left out (`sweep` writes the same file, and `records.csv` with these columns but `case_hash`)",
            crate::study::journal::header(),
        ),
        (
            "probes/<key>.csv",
            "one row per sample of a run without exact solution (the reference errors read them)",
            crate::study::journal::PROBE_COLUMNS.to_vec(),
        ),
        (
            "cross_code.csv",
            "one row per GetFEM trajectory",
            peers::COLUMNS.to_vec(),
        ),
        (
            "<case>_finite_body.csv",
            "one row per static solve of the sphere's finite-body law",
            super::impact::FINITE_BODY_COLUMNS.to_vec(),
        ),
        (
            "timeseries.csv (dyncontact run)",
            "one row per sample (every step and t = 0); `approach` for curved bodies, `momentum` for two free bodies, `com_velocity_t` and `friction_work` for runs with friction, `com_velocity_n` and `angular_velocity` for a disc or sphere with friction, the `_exact` columns when the case has an exact solution",
            timeseries,
        ),
        (
            "summary.csv (dyncontact run)",
            "the run's one row, with its timing columns",
            run::summary_columns(),
        ),
        (
            "report --profile FILE",
            "one row per simulation and per report section as it ends; machine-dependent",
            crate::study::profile::COLUMNS.to_vec(),
        ),
    ]
}

/// The meaning and unit of `column`.
fn doc(column: &str) -> Option<(&'static str, &'static str)> {
    DOCS.iter().find(|d| d.0 == column).map(|d| (d.1, d.2))
}

/// The text of `COLUMNS.md`.
pub fn columns_md() -> String {
    let mut md = String::from(
        "# Columns of the CSV files\n\n\
         Generated by `dyncontact report` (a checked-in copy is the repository's \
         `reports/COLUMNS.md`). Every file has a header row; missing values are empty fields \
         (a metric that does not apply to the case, a run that did not finish). Units: `1` is a \
         dimensionless ratio, `case` the units stated in the case file (`units = …`; every \
         shipped case is non-dimensional), `—` text or a count; d is the space dimension.\n",
    );
    for (file, row, columns) in files() {
        let _ = write!(
            md,
            "\n## {file}\n\n{}.\n\n| column | unit | meaning |\n|---|---|---|\n",
            capitalise(row)
        );
        for c in columns {
            let (unit, meaning) = doc(c).unwrap_or(("?", "?"));
            // A pipe inside a table cell, code spans included, is escaped in GitHub's tables.
            let meaning = meaning.replace('|', "\\|");
            let _ = writeln!(md, "| `{c}` | {unit} | {meaning} |");
        }
    }
    md
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next().map_or(String::new(), |f| {
        f.to_uppercase().collect::<String>() + c.as_str()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::metrics;

    /// Every column of every file has a meaning and a unit.
    #[test]
    fn every_column_is_described() {
        for (file, _, columns) in files() {
            for c in columns {
                assert!(
                    doc(c).is_some(),
                    "{file}: column `{c}` has no description in DOCS"
                );
            }
        }
        for m in metrics::METRIC_COLUMNS {
            assert!(
                doc(m.name).is_some(),
                "metric `{}` has no description",
                m.name
            );
        }
    }

    /// The checked-in `reports/COLUMNS.md` is the generated one (after a change of columns:
    /// `cargo run --release -- report --quick --out /tmp/q && cp /tmp/q/COLUMNS.md reports/`).
    #[test]
    fn the_checked_in_sample_is_current() {
        let sample = include_str!("../../reports/COLUMNS.md");
        assert_eq!(sample, columns_md(), "reports/COLUMNS.md is out of date");
    }
}
