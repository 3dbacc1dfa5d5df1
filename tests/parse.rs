//! The case-file parser on hostile input: mutations of the shipped `cases/*.toml` (a key
//! deleted or misspelt, or its value replaced by another type, an extreme, negative, NaN, infinite or huge
//! number, or an unknown name) with command-line overrides (extreme values, unknown names,
//! special files). Property: no panic, and either a valid run specification, whose sweeps
//! enumerate too, or an error that names the mutated key or an overridden field.

use dyncontact::cases::{CaseFile, Overrides};
use dyncontact::study::jobs;
use proptest::prelude::*;
use std::path::Path;
use std::sync::Arc;
use toml::Value;

const CASES: [&str; 7] = [
    "bar1d",
    "spring_mass",
    "block2d",
    "block3d",
    "hertz2d",
    "hertz3d",
    "disc2d",
];

/// The case file's table, its body mesh made coarse (`[mesh] elements = 3`, the coarsest
/// valid sphere) so that building it is cheap; the mutation may set it again.
fn base(case: &str) -> toml::Table {
    let text = std::fs::read_to_string(format!("cases/{case}.toml")).unwrap();
    let mut table: toml::Table = text.parse().unwrap();
    if case != "bar1d" {
        if let Some(Value::Table(mesh)) = table.get_mut("mesh") {
            mesh.insert("elements".into(), Value::Integer(3));
        }
    }
    table
}

/// One step of a path into a TOML document.
#[derive(Debug, Clone)]
enum Step {
    Key(String),
    Index(usize),
}

/// The path of every leaf value (arrays of tables are entered, arrays of values are leaves).
fn leaves(v: &Value, path: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    match v {
        Value::Table(t) => {
            for (k, x) in t {
                path.push(Step::Key(k.clone()));
                leaves(x, path, out);
                path.pop();
            }
        }
        Value::Array(a) if a.iter().any(Value::is_table) => {
            for (i, x) in a.iter().enumerate() {
                path.push(Step::Index(i));
                leaves(x, path, out);
                path.pop();
            }
        }
        _ => out.push(path.clone()),
    }
}

/// A mutation of one key.
#[derive(Debug, Clone)]
enum Edit {
    Delete,
    /// The key misspelt (`density_typo`), its value kept: an unknown key and a missing one.
    Rename,
    Set(Value),
}

fn edit() -> impl Strategy<Value = Edit> {
    let numbers = [
        0.0,
        -1.0,
        1e-300,
        -1e-300,
        1e300,
        -1e300,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.07,
        3.0,
    ];
    prop_oneof![
        Just(Edit::Delete),
        Just(Edit::Rename),
        prop::sample::select(numbers.to_vec()).prop_map(|x| Edit::Set(Value::Float(x))),
        prop::sample::select(vec![0, -1, 1, 2, 3, i64::MAX, i64::MIN, 1_000_000_000_000])
            .prop_map(|x| Edit::Set(Value::Integer(x))),
        prop::sample::select(vec![
            "nonesuch", "", "newmark", "tet", "weak", "nitsche", "cg"
        ])
        .prop_map(|s| Edit::Set(Value::String(s.into()))),
        Just(Edit::Set(Value::Boolean(true))),
        Just(Edit::Set(Value::Array(vec![]))),
        Just(Edit::Set(Value::Table(toml::Table::new()))),
    ]
}

/// The value at `path` under `v`.
fn at<'a>(v: &'a mut Value, path: &[Step]) -> &'a mut Value {
    path.iter().fold(v, |v, step| match (step, v) {
        (Step::Key(k), Value::Table(t)) => t.get_mut(k).unwrap(),
        (Step::Index(i), Value::Array(a)) => &mut a[*i],
        _ => unreachable!("paths come from `leaves`"),
    })
}

/// Applies `edit` to the key at the end of `path`; returns the key's name.
fn mutate(doc: &mut Value, path: &[Step], edit: Edit) -> String {
    let (Step::Key(key), parent) = path.split_last().unwrap() else {
        unreachable!("a leaf is a key of a table")
    };
    let Value::Table(table) = at(doc, parent) else {
        unreachable!("a leaf's parent is a table")
    };
    let old = table.remove(key).expect("a leaf exists");
    match edit {
        Edit::Delete => {}
        Edit::Rename => {
            table.insert(format!("{key}_typo"), old);
        }
        Edit::Set(v) => {
            table.insert(key.clone(), v);
        }
    }
    key.clone()
}

/// Command-line overrides, each set with probability ¼, and the names an error about them
/// may use.
fn overrides() -> impl Strategy<Value = (Overrides, Vec<&'static str>)> {
    let name = |names: Vec<&'static str>| prop::option::weighted(0.25, prop::sample::select(names));
    let number = || {
        prop::option::weighted(
            0.25,
            prop::sample::select(vec![-1.0, 0.0, 1e-300, 1e300, f64::NAN, 0.01, 0.3, 0.5]),
        )
    };
    let count = || {
        prop::option::weighted(
            0.25,
            prop::sample::select(vec![0usize, 1, 2, 3, usize::MAX, 1_000_000_000_000]),
        )
    };
    let param = prop::option::weighted(
        0.25,
        (
            prop::sample::select(dyncontact::methods::all_params()),
            prop::sample::select(vec![-1.0, 0.0, 0.25, 0.5, 1.0, 1e300, f64::NAN]),
        ),
    );
    (
        (
            name(vec![
                "standard",
                "lumped",
                "mass_redistribution",
                "singular_dynamic",
                "x",
            ]),
            name(vec![
                "newmark",
                "hht",
                "backward_euler",
                "central_difference",
                "rk4",
            ]),
            name(vec!["nodal", "weak", "nitsche", "penalty", "mortar"]),
            name(vec!["active_set", "clarabel", "simplex"]),
            name(vec!["auto", "direct", "cg", "lu"]),
            param,
        ),
        (
            count(),
            prop::option::weighted(0.25, 0usize..4),
            name(vec!["quad", "triangle", "hex", "tet", "blob"]),
            name(vec![
                "cases/meshes/disc.msh",
                "cases/meshes/sphere.msh",
                "/dev/zero",
                "missing.msh",
            ]),
            number(),
            number(),
        ),
    )
        .prop_map(
            |(
                (space, scheme, contact, solver, linear, param),
                (elements, degree, cells, mesh, dt, t_end),
            )| {
                let mut o = Overrides {
                    space: space.map(Into::into),
                    scheme: scheme.map(Into::into),
                    degree,
                    elements,
                    cells: cells.map(Into::into),
                    mesh: mesh.map(Into::into),
                    dt,
                    t_end,
                    ..Default::default()
                };
                o.options.contact = contact.map(Into::into);
                o.options.contact_solver = solver.map(Into::into);
                o.options.linear_solver = linear.map(Into::into);
                let mut touched = Vec::new();
                if let Some((p, v)) = param {
                    o.options.params.set(p.name, v);
                    touched.push(p.name);
                }
                for (set, names) in [
                    (o.space.is_some(), &["space"][..]),
                    (o.scheme.is_some(), &["scheme"]),
                    (o.options.contact.is_some(), &["contact"]),
                    (o.options.contact_solver.is_some(), &["contact solver"]),
                    (o.options.linear_solver.is_some(), &["linear solver"]),
                    (o.elements.is_some(), &["elements"]),
                    (o.degree.is_some(), &["degree"]),
                    (o.cells.is_some(), &["cells"]),
                    (o.mesh.is_some(), &["mesh"]),
                    (o.dt.is_some(), &["dt"]),
                    (o.t_end.is_some(), &["t_end"]),
                ] {
                    if set {
                        touched.extend_from_slice(names);
                    }
                }
                (o, touched)
            },
        )
}

/// True when the error message names one of `names` (`_` and spaces alike).
fn names_one_of(message: &str, names: &[impl AsRef<str>]) -> bool {
    let m = message.to_lowercase().replace('_', " ");
    names
        .iter()
        .any(|n| m.contains(&n.as_ref().to_lowercase().replace('_', " ")))
}

/// A mutated case file and the names of its key: `(case, text, [key, its table])` (an error
/// may name the table: "geometry and mesh", "sweep `orders`").
fn mutated_case() -> impl Strategy<Value = (&'static str, String, Vec<String>)> {
    prop::sample::select(CASES.to_vec()).prop_flat_map(|case| {
        let doc = Value::Table(base(case));
        let mut paths = Vec::new();
        leaves(&doc, &mut Vec::new(), &mut paths);
        (prop::sample::select(paths), edit()).prop_map(move |(path, edit)| {
            let mut doc = doc.clone();
            let key = mutate(&mut doc, &path, edit);
            let mut names = vec![key];
            if let (Some(Step::Key(table)), true) = (path.first(), path.len() > 1) {
                names.push(table.clone());
            }
            (case, toml::to_string(&doc).unwrap(), names)
        })
    })
}

proptest! {
    #[test]
    fn a_mutated_case_file_parses_to_a_valid_run_or_an_error_naming_a_field(
        (case, text, keys) in mutated_case(),
        (o, touched) in overrides(),
    ) {
        let path = format!("cases/{case}.toml");
        let file = match CaseFile::parse(text.clone(), Path::new(&path)) {
            Ok(f) => Arc::new(f),
            Err(e) => {
                let e = e.to_string();
                prop_assert!(names_one_of(&e, &keys), "{keys:?} in {case}: {e}\n{text}");
                return Ok(());
            }
        };
        // The file alone, and its sweeps.
        match file.build(&Overrides::default()) {
            Err(e) => {
                let e = e.to_string();
                prop_assert!(names_one_of(&e, &keys), "{keys:?} in {case}: {e}\n{text}");
            }
            Ok(c) => {
                prop_assert!(c.run().validate().is_ok());
                prop_assert!(c.run().steps() >= 1);
                if !c.sweeps().is_empty() {
                    if let Err(e) = jobs::jobs(&file, true) {
                        let e = e.to_string();
                        prop_assert!(names_one_of(&e, &keys), "{keys:?} in {case}: {e}\n{text}");
                    }
                }
            }
        }
        // With the overrides.
        match file.build(&o) {
            Err(e) => {
                let e = e.to_string();
                let mut names: Vec<&str> = touched.clone();
                names.extend(keys.iter().map(String::as_str));
                prop_assert!(
                    names_one_of(&e, &names),
                    "{keys:?} in {case} with {touched:?} ({o:?}): {e}\n{text}"
                );
            }
            Ok(c) => prop_assert!(c.run().validate().is_ok()),
        }
    }
}

/// The faults this property found, each kept as a case: an error naming the field (on main,
/// five named none and a huge `levels` aborted the process allocating 85 GB).
#[test]
fn the_inputs_the_property_found_are_refused_naming_their_field() {
    let set = |case: &str, path: &[Step], v: Option<Value>| {
        let mut doc = Value::Table(base(case));
        mutate(&mut doc, path, v.map_or(Edit::Delete, Edit::Set));
        let file = CaseFile::parse(toml::to_string(&doc).unwrap(), Path::new(case))?;
        file.build(&Overrides::default())?;
        jobs::jobs(&Arc::new(file), true).map(|_| ())
    };
    let key = |k: &str| Step::Key(k.into());
    for (case, path, value, field) in [
        // A name given a number in a flattened table: the error pointed at `[run]` only.
        (
            "bar1d",
            vec![key("run"), key("contact_solver")],
            Some(Value::Integer(2)),
            "`contact_solver`",
        ),
        // ratio^levels elements: a Vec of 2^63 levels, and an overflow.
        (
            "bar1d",
            vec![key("sweep"), Step::Index(0), key("levels")],
            Some(Value::Integer(i64::MAX)),
            "sweep.orders.levels",
        ),
        // A ratio whose first refinement overflows was blamed on the levels.
        (
            "bar1d",
            vec![key("sweep"), Step::Index(0), key("ratio")],
            Some(Value::Integer(i64::MAX)),
            "sweep.orders.ratio",
        ),
        (
            "hertz2d",
            vec![key("contact"), key("facing")],
            Some(Value::Float(1.0)),
            "contact.facing",
        ),
        (
            "hertz2d",
            vec![key("geometry"), key("shape")],
            None,
            "geometry.shape",
        ),
        (
            "hertz2d",
            vec![key("geometry"), key("radius")],
            Some(Value::Float(1e-300)),
            "geometry.radius",
        ),
        (
            "spring_mass",
            vec![key("system"), key("stiffness")],
            Some(Value::Float(1e300)),
            "system.stiffness",
        ),
        (
            "hertz3d",
            vec![key("mesh"), key("elements")],
            Some(Value::Integer(2)),
            "mesh.elements",
        ),
    ] {
        let e = set(case, &path, value).expect_err(case).to_string();
        assert!(e.contains(field), "{case} {path:?}: {e}");
    }
}

/// An error about a value the overrides set names where it came from: the command line's flag,
/// or the table's field (a sweep's `refinements` gives both dt and elements, a history's `dts`
/// the time step); a field the overrides did not set is named as it is.
#[test]
fn an_overridden_field_is_named_where_it_was_set() {
    use dyncontact::cases::Origin;
    use dyncontact::error::Error;
    let named = |o: &Overrides, field: &str| o.named(Error::invalid(field, 1, "x")).to_string();
    let cli = Overrides {
        elements: Some(1),
        dt: Some(1.0),
        ..Default::default()
    };
    assert!(named(&cli, "mesh.elements").contains("`mesh.elements (--elements)`"));
    assert!(named(&cli, "run.dt").contains("`run.dt (--dt)`"));
    assert!(named(&cli, "run.t_end").contains("`run.t_end`"));
    // Every override a field can come from: the mesh's cells and the scheme's options too.
    let mut given = Overrides {
        cells: Some("quad".into()),
        ..cli.clone()
    };
    given.options.params.set("alpha", -0.1);
    given.options.contact_solver = Some("clarabel".into());
    assert!(named(&given, "mesh.cells").contains("`mesh.cells (--cells)`"));
    assert!(named(&given, "run.alpha").contains("`run.alpha (--alpha)`"));
    assert!(named(&given, "run.contact_solver").contains("(--contact-solver)`"));
    // A parameter the overrides did not set is the case file's own.
    assert!(named(&given, "run.beta").contains("`run.beta`"));
    assert!(named(&given, "run.linear_solver").contains("`run.linear_solver`"));
    let table = |table: &str, levels| Overrides {
        origin: Some(Origin {
            table: table.into(),
            levels,
            choice: if table.starts_with("sweep") {
                "schemes"
            } else {
                "scheme"
            },
        }),
        ..given.clone()
    };
    let refined = table("sweep.r", ["refinements"; 2]);
    assert!(named(&refined, "mesh.elements").contains("(sweep.r.refinements)`"));
    assert!(named(&refined, "run.dt").contains("(sweep.r.refinements)`"));
    let sweep = table("sweep.orders", ["dt", "elements"]);
    assert!(named(&sweep, "mesh.elements").contains("(sweep.orders.elements)`"));
    let history = table("history.energy", ["dts", "elements"]);
    assert!(named(&history, "run.dt").contains("`run.dt (history.energy.dts)`"));
    assert!(named(&sweep, "run.alpha").contains("`run.alpha (sweep.orders.schemes)`"));
    assert!(named(&history, "run.alpha").contains("`run.alpha (history.energy.scheme)`"));
}
