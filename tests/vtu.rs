//! Field output for ParaView (`run --vtu DIR --vtu-every K`): the `.vtu` files read back with
//! vtkio agree with the run's own time series, and the `.pvd` collection lists them with their
//! times.

use dyncontact::cases::{load, Case, Overrides};
use dyncontact::output::vtu::read_array;
use dyncontact::study::run::{run_with_output, FieldOutput};
use std::path::Path;

fn case(file: &str, o: Overrides) -> Box<dyn Case> {
    load(Path::new(file), &o).unwrap()
}

/// The disc of `hertz2d` (coarse mesh) through its first contact, a file every 25 steps: in each
/// file, the contact pressure integrated over Γ_C (Σ p_r |Γ_C|_r) is the run's total contact
/// force and the probe's displacement is the run's `u_contact`, to round-off; the von Mises
/// stress is zero in the undeformed body and positive under load; the `.pvd` lists every file
/// with its time.
#[test]
fn fields_read_back_agree_with_the_time_series() {
    let dir = tempfile::tempdir().unwrap();
    let o = Overrides {
        elements: Some(16),
        t_end: Some(4.0),
        ..Default::default()
    };
    let c = case("cases/hertz2d.toml", o);
    let every = 25;
    let out = FieldOutput {
        dir: dir.path().to_path_buf(),
        every,
    };
    let r = run_with_output(c.as_ref(), false, Some(&out)).unwrap();
    let fem = c.discretisation().unwrap();
    let space = dyncontact::space::by_name(&c.run().space).unwrap();
    let probe = c.problem(space.as_ref()).unwrap().probe;
    let pvd = std::fs::read_to_string(dir.path().join("hertz2d.pvd")).unwrap();
    let mut loaded = 0;
    for (index, row) in r.rows.iter().enumerate().step_by(every) {
        let file = format!("hertz2d_{index:06}.vtu");
        assert!(
            pvd.contains(&format!(
                "timestep=\"{:.12e}\" group=\"\" part=\"0\" file=\"{file}\"",
                row.t
            )),
            "{file} missing from the collection"
        );
        let path = dir.path().join(&file);
        let pressure = read_array(&path, "contact_pressure").unwrap();
        let force: f64 = fem
            .contact_vertices
            .iter()
            .map(|&(i, area)| pressure[i] * area)
            .sum();
        let scale = r.rows.iter().map(|r| r.force_contact).fold(0.0, f64::max);
        assert!(
            (force - row.force_contact).abs() <= 1e-12 * scale,
            "{file}: Σ p |Γ_C| = {force:e}, force_contact {:e}",
            row.force_contact
        );
        let u = read_array(&path, "displacement").unwrap();
        let node = probe.u_dof / 2;
        assert_eq!(u[3 * node + 1], row.u_contact, "{file}");
        let von_mises = read_array(&path, "von_mises").unwrap();
        assert_eq!(von_mises.len(), fem.mesh.connectivity.len());
        let max = von_mises.iter().copied().fold(0.0, f64::max);
        if index == 0 {
            assert_eq!(max, 0.0, "stress in the undeformed body");
        } else if row.force_contact > 0.0 {
            assert!(max > 0.0, "{file}: no stress under load");
        }
        loaded += 1;
    }
    assert!(loaded >= 8, "{loaded} files");
    assert!(r.rows.iter().any(|r| r.force_contact > 0.0), "no contact");
}

/// GetFEM's disc with the singular dynamic method (Q2 displacement, Q1 velocity): in free fall
/// under gravity every node, the Q2 mid-nodes included (velocity interpolated from H_h), moves
/// at `v = −g t` (Newmark ½, ½ is exact for a constant acceleration).
#[test]
fn singular_dynamic_velocity_is_interpolated_at_every_node() {
    let dir = tempfile::tempdir().unwrap();
    let o = Overrides {
        elements: Some(2),
        space: Some("singular_dynamic".into()),
        t_end: Some(0.1),
        ..Default::default()
    };
    let c = case("cases/disc2d.toml", o);
    let out = FieldOutput {
        dir: dir.path().to_path_buf(),
        every: 5,
    };
    let r = run_with_output(c.as_ref(), false, Some(&out)).unwrap();
    let last = r.rows.len() - 1;
    assert_eq!(last % 5, 0);
    let v = read_array(
        &dir.path().join(format!("disc2d_{last:06}.vtu")),
        "velocity",
    )
    .unwrap();
    let nodes = c.discretisation().unwrap().mesh.nodes.len();
    assert_eq!(v.len(), 3 * nodes);
    let expected = -0.1 * r.rows[last].t;
    for (i, vi) in v.chunks(3).enumerate() {
        assert!(vi[0].abs() < 1e-12 && vi[2] == 0.0, "node {i}: {vi:?}");
        assert!(
            (vi[1] - expected).abs() < 1e-10,
            "node {i}: {vi:?}, expected {expected}"
        );
    }
}
