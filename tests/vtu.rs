//! Field output for ParaView (`run --vtu DIR --vtu-every K`): the `.vtu` files read back with
//! vtkio agree with the run's own time series, and the `.pvd` collection lists them with their
//! times.

use dyncontact::cases::{load, Case, Overrides};
use dyncontact::output::vtu::read_array;
use dyncontact::study::run::{run_with_output, FieldOutput, RunResult};
use std::path::Path;

/// Runs the case file `file` with `o`, writing its fields every `every` steps into a new
/// temporary directory (kept alive by the returned guard).
fn run_fields(
    file: &str,
    o: Overrides,
    every: usize,
) -> (tempfile::TempDir, Box<dyn Case>, RunResult) {
    let dir = tempfile::tempdir().unwrap();
    let c = load(Path::new(file), &o).unwrap();
    let out = FieldOutput {
        dir: dir.path().to_path_buf(),
        every,
    };
    let r = run_with_output(c.as_ref(), false, Some(&out)).unwrap();
    (dir, c, r)
}

/// The disc of `hertz2d` (coarse mesh) through its first contact, a file every 25 steps: in each
/// file, the contact pressure integrated over Γ_C (Σ p_r |Γ_C|_r) is the run's total contact
/// force and the probe's displacement is the run's `u_contact`, to round-off; the von Mises
/// stress is zero in the undeformed body and positive under load; the `.pvd` lists every file
/// with its time.
#[test]
fn fields_read_back_agree_with_the_time_series() {
    let o = Overrides {
        elements: Some(16),
        t_end: Some(4.0),
        ..Default::default()
    };
    let every = 25;
    let (dir, c, r) = run_fields("cases/hertz2d.toml", o, every);
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
    let o = Overrides {
        elements: Some(2),
        space: Some("singular_dynamic".into()),
        t_end: Some(0.1),
        ..Default::default()
    };
    let (dir, c, r) = run_fields("cases/disc2d.toml", o, 5);
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

/// Two discs (`two_discs`, coarse pair) through their impact, a file every 25 steps: one grid
/// holds both bodies (the slave's points then the master's, the cell array `body` 1 then 2);
/// the contact pressure integrated over each body's Γ_C is the run's total contact force (the
/// slave's rows and the master's reaction spread by its shape functions), to round-off; the
/// slave's probe displacement is `u_contact`; at t = 0 the slave's nodes move at −0.01 along y
/// and the master's at +0.01; von Mises is zero at rest and positive under load.
#[test]
fn both_bodies_read_back_in_one_grid() {
    let o = Overrides {
        elements: Some(12),
        t_end: Some(4.0),
        ..Default::default()
    };
    let every = 25;
    let (dir, c, r) = run_fields("cases/two_discs.toml", o, every);
    let parts = &c.multi_body().unwrap().parts;
    let (slave, master) = (&parts[0], &parts[1]);
    let (n1, n2) = (slave.mesh.nodes.len(), master.mesh.nodes.len());
    let space = dyncontact::space::by_name(&c.run().space).unwrap();
    let probe = c.problem(space.as_ref()).unwrap().probe;
    let scale = r.rows.iter().map(|r| r.force_contact).fold(0.0, f64::max);
    let mut loaded = 0;
    for (index, row) in r.rows.iter().enumerate().step_by(every) {
        let path = dir.path().join(format!("two_discs_{index:06}.vtu"));
        let body = read_array(&path, "body").unwrap();
        let cells = [slave, master].map(|b| b.mesh.connectivity.len());
        assert_eq!(body.len(), cells[0] + cells[1]);
        assert!(body[..cells[0]].iter().all(|&b| b == 1.0));
        assert!(body[cells[0]..].iter().all(|&b| b == 2.0));
        let pressure = read_array(&path, "contact_pressure").unwrap();
        assert_eq!(pressure.len(), n1 + n2);
        for (fem, first) in [(slave, 0), (master, n1)] {
            let force: f64 = fem
                .contact_vertices
                .iter()
                .map(|&(i, area)| pressure[first + i] * area)
                .sum();
            assert!(
                (force - row.force_contact).abs() <= 1e-12 * scale,
                "{index}: Σ p |Γ_C| = {force:e} on body {}, force_contact {:e}",
                1 + first / n1.max(1),
                row.force_contact
            );
        }
        let u = read_array(&path, "displacement").unwrap();
        assert_eq!(u[3 * (probe.u_dof / 2) + 1], row.u_contact, "{index}");
        let von_mises = read_array(&path, "von_mises").unwrap();
        let max = von_mises.iter().copied().fold(0.0, f64::max);
        if index == 0 {
            assert_eq!(max, 0.0, "stress at rest");
            let v = read_array(&path, "velocity").unwrap();
            assert!(v[..3 * n1].chunks(3).all(|x| x[1] == -0.01));
            assert!(v[3 * n1..].chunks(3).all(|x| x[1] == 0.01));
        } else if row.force_contact > 0.0 {
            assert!(max > 0.0, "{index}: no stress under load");
            loaded += 1;
        }
    }
    assert!(loaded >= 4, "{loaded} files under load");
}

/// The singular dynamic method on both discs (Q2 displacement, Q1 velocity): each body's H_h
/// velocity is its own block of the run's, interpolated at every node of its Q2 mesh: ∓0.01
/// along y on the slave's and the master's nodes, before contact.
#[test]
fn both_bodies_velocity_from_their_own_h_h() {
    let o = Overrides {
        elements: Some(4),
        degree: Some(2),
        space: Some("singular_dynamic".into()),
        t_end: Some(0.04),
        ..Default::default()
    };
    let (dir, c, _) = run_fields("cases/two_discs.toml", o, 1);
    let n1 = c.multi_body().unwrap().parts[0].mesh.nodes.len();
    let v = read_array(&dir.path().join("two_discs_000000.vtu"), "velocity").unwrap();
    for (i, x) in v.chunks(3).enumerate() {
        let want = if i < n1 { -0.01 } else { 0.01 };
        assert!(
            x[0].abs() < 1e-15 && (x[1] - want).abs() < 1e-15,
            "node {i}: {x:?}"
        );
    }
}

/// A second run into the same `--vtu` directory left the first run's files beside its `.pvd`
/// (every sample, then every 5th: `block2d_000001.vtu` … stayed, and ParaView's grouping by
/// name mixed the two runs): the files of the case's series that the new collection does not
/// list go, every other file (another pattern, another case, a directory) stays.
#[test]
fn a_second_run_removes_the_first_runs_samples_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let o = Overrides {
        dt: Some(0.001),
        t_end: Some(0.01),
        ..Default::default()
    };
    let c = load(Path::new("cases/block2d.toml"), &o).unwrap();
    let run = |every| {
        let out = FieldOutput {
            dir: dir.path().to_path_buf(),
            every,
        };
        run_with_output(c.as_ref(), false, Some(&out)).unwrap();
    };
    run(1);
    let mine = [
        "block2d_12.vtu",
        "block2d_0000003.vtu",
        "block2d_000003.vtu.bak",
        "block3d_000003.vtu",
        "notes.txt",
    ];
    for f in mine {
        std::fs::write(dir.path().join(f), "mine").unwrap();
    }
    std::fs::create_dir(dir.path().join("block2d_000099.vtu")).unwrap();
    run(5);
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    let mut expected: Vec<&str> = [
        "block2d.pvd",
        "block2d_000000.vtu",
        "block2d_000005.vtu",
        "block2d_000010.vtu",
        "block2d_000099.vtu",
    ]
    .into_iter()
    .chain(mine)
    .collect();
    expected.sort();
    assert_eq!(names, expected);
    let pvd = std::fs::read_to_string(dir.path().join("block2d.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 3, "{pvd}");
}
