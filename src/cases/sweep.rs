//! `[[sweep]]` tables of a case file: the combinations the harness runs.
//!
//! ```toml
//! [[sweep]]
//! name = "orders"
//! spaces = ["standard", "mass_redistribution"]
//! schemes = [{ scheme = "newmark", beta = 0.5, gamma = 0.5 }, { scheme = "hht", alpha = -0.1 }]
//! degree = { singular_dynamic = 2 }   # per-space polynomial degree (optional)
//! elements = 20                         # coarsest level (omit for a 0D case)
//! dt = 0.025
//! ratio = 2                             # elements × ratioᵏ, dt / ratioᵏ
//! levels = 5
//! quick_levels = 3                      # levels kept by `--quick` (default 2)
//! friction = 0.0                       # μ instead of the case's (optional)
//! # or: refinements = [{ elements = 20, dt = 0.025 }, { elements = 40, dt = 0.0125 }]
//! ```

use super::{Options, Origin, Overrides};
use crate::error::{positive, Error, Result};
use serde::Deserialize;
use std::collections::BTreeMap;

/// One scheme with its options (unset ones take the case's `[run]` values): the same keys as
/// `[run]` (`beta`, `contact`, `contact_solver`, …). Every option that changes the run is in
/// its key and its records' `parameters` ([`super::RunSpec::parameters`]): two entries that
/// differ by a solver alone are two runs.
#[derive(Debug, Clone, Deserialize, PartialEq)]
pub struct SchemeChoice {
    /// Scheme name.
    pub scheme: String,
    /// Contact formulation, solvers and parameters.
    #[serde(flatten)]
    pub options: Options,
}

impl HistorySpec {
    /// Overrides of one curve: `space` at time step `dt`.
    pub fn overrides(&self, space: &str, dt: f64) -> Overrides {
        let level = Refinement {
            elements: self.elements,
            dt,
        };
        let origin = Origin {
            table: self.field(""),
            levels: ["dts", "elements"],
            choice: "scheme",
        };
        combination(space, &self.scheme, &self.degree, level, None, origin)
    }

    /// The table (`history.<name>`, or `history` unnamed), or its field `f` when not empty, as
    /// named in errors.
    pub fn field(&self, f: &str) -> String {
        let table = if self.name.is_empty() {
            "history".to_string()
        } else {
            format!("history.{}", self.name)
        };
        if f.is_empty() {
            table
        } else {
            format!("{table}.{f}")
        }
    }

    /// Refuses a table that would draw nothing or misname its files: no space, no time step, a
    /// time step that is not finite and positive, a name that cannot be part of a file name
    /// (`<case>_<name>_energy.png`).
    pub fn validate(&self) -> Result<()> {
        let field = |f: &str| self.field(f);
        if !self.name.is_empty() {
            crate::util::check_name("history.name", &self.name)?;
        }
        if self.spaces.is_empty() {
            return Err(Error::invalid(field("spaces"), "[]", "at least one space"));
        }
        if self.dts.is_empty() {
            return Err(Error::invalid(field("dts"), "[]", "at least one time step"));
        }
        for &dt in &self.dts {
            positive(&field("dts"), dt)?;
        }
        if let Some(twice) = crate::util::first_repeated(&self.spaces) {
            return Err(Error::invalid(field("spaces"), twice, "listed twice"));
        }
        if let Some(twice) = crate::util::first_repeated(&self.dts) {
            return Err(Error::invalid(field("dts"), twice, "listed twice"));
        }
        unused_degree(&self.degree, &self.spaces, field)
    }
}

/// Refuses `[[history]]` tables that would write the same figures: each validated, and no
/// name twice (unnamed twice included: both would write `<case>_energy.png`).
pub fn validate_histories(histories: &[HistorySpec]) -> Result<()> {
    for h in histories {
        h.validate()?;
    }
    let names: Vec<&str> = histories.iter().map(|h| h.name.as_str()).collect();
    let again = crate::util::first_repeated(&names);
    match again.and_then(|name| histories.iter().find(|h| h.name == *name)) {
        Some(h) => Err(Error::invalid(
            h.field("name"),
            &h.name,
            "two [[history]] tables of one name (or two unnamed) would write the same figures",
        )),
        None => Ok(()),
    }
}

/// Refuses a `degree` key for a space the table does not run (it would be ignored).
fn unused_degree(
    degree: &BTreeMap<String, usize>,
    spaces: &[String],
    field: impl Fn(&str) -> String,
) -> Result<()> {
    match degree.keys().find(|k| !spaces.contains(k)) {
        Some(other) => Err(Error::invalid(
            field(&format!("degree.{other}")),
            degree[other],
            &format!("not a space of this table ({})", spaces.join(", ")),
        )),
        None => Ok(()),
    }
}

impl SchemeChoice {
    /// `scheme (key=value, …)` with the options set in the table.
    pub fn label(&self) -> String {
        let options = self.options.label(&self.scheme);
        if options.is_empty() {
            self.scheme.clone()
        } else {
            format!("{} ({options})", self.scheme)
        }
    }
}

/// One refinement level: number of elements (None for a 0D case) and time step.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Refinement {
    /// Elements along the mesh's first direction.
    pub elements: Option<usize>,
    /// Time step.
    pub dt: f64,
}

/// A `[[sweep]]` table.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// Name (used in records and orders).
    pub name: String,
    /// Space names.
    pub spaces: Vec<String>,
    /// Schemes with parameters.
    pub schemes: Vec<SchemeChoice>,
    /// Per-space polynomial degree.
    #[serde(default)]
    pub degree: BTreeMap<String, usize>,
    /// Explicit refinement list (instead of elements/dt/ratio/levels).
    #[serde(default)]
    pub refinements: Vec<Refinement>,
    /// Coarsest number of elements.
    pub elements: Option<usize>,
    /// Coarsest time step.
    pub dt: Option<f64>,
    /// Refinement ratio (integer ≥ 2; default 2).
    pub ratio: Option<usize>,
    /// Number of levels.
    pub levels: Option<usize>,
    /// Levels kept by `--quick`.
    #[serde(default = "two")]
    pub quick_levels: usize,
    /// Final time (default: the case's `[run] t_end`).
    pub t_end: Option<f64>,
    /// Coulomb friction coefficient μ (default: the case's `[contact] friction`); `friction = 0`
    /// runs the same combinations frictionless, the baseline of the cost of friction.
    pub friction: Option<f64>,
}

fn two() -> usize {
    2
}

impl SweepSpec {
    /// The field `f` of this table as named in errors, `sweep.<name>.<f>`.
    pub fn field(&self, f: &str) -> String {
        format!("sweep.{}.{f}", self.name)
    }

    /// Refuses a table that would run nothing (no space, no scheme, no level kept by `--quick`)
    /// or ignore what it says: a name that is not a file-name part (it names the report's
    /// files), a space listed twice, a degree for a space it does not run or other than 1 or 2,
    /// `refinements` beside the fields they replace.
    fn validate(&self) -> Result<()> {
        let field = |f: &str| self.field(f);
        crate::util::check_name("sweep.name", &self.name)?;
        if self.spaces.is_empty() {
            return Err(Error::invalid(field("spaces"), "[]", "at least one space"));
        }
        if let Some(mu) = self.friction {
            crate::error::non_negative(&field("friction"), mu)?;
        }
        if let Some(twice) = crate::util::first_repeated(&self.spaces) {
            return Err(Error::invalid(field("spaces"), twice, "listed twice"));
        }
        unused_degree(&self.degree, &self.spaces, field)?;
        if let Some((space, d)) = self.degree.iter().find(|(_, d)| !(1..=2).contains(*d)) {
            return Err(Error::invalid(
                field("degree"),
                format_args!("{{ {space} = {d} }}"),
                "a degree must be 1 or 2",
            ));
        }
        if let Some(twice) = crate::util::first_repeated(&self.refinements) {
            let elements = twice.elements.map(|n| format!("elements = {n}, "));
            return Err(Error::invalid(
                field("refinements"),
                format_args!("{{ {}dt = {} }}", elements.unwrap_or_default(), twice.dt),
                "a level listed twice: the levels must refine (no order is fitted otherwise)",
            ));
        }
        if !self.refinements.is_empty() {
            let beside = [
                ("elements", self.elements.is_some()),
                ("dt", self.dt.is_some()),
                ("ratio", self.ratio.is_some()),
                ("levels", self.levels.is_some()),
            ];
            if let Some((name, _)) = beside.iter().find(|(_, set)| *set) {
                return Err(Error::invalid(
                    field(name),
                    "set",
                    "not with `refinements`, which lists every level's elements and dt",
                ));
            }
        }
        if self.schemes.is_empty() {
            return Err(Error::invalid(
                field("schemes"),
                "[]",
                "at least one scheme",
            ));
        }
        if self.quick_levels == 0 {
            return Err(Error::invalid(field("quick_levels"), 0, "≥ 1"));
        }
        Ok(())
    }

    /// The table's fields that give each level's dt and elements: `dt` and `elements`, or
    /// `refinements` for both.
    fn level_fields(&self) -> [&'static str; 2] {
        if self.refinements.is_empty() {
            ["dt", "elements"]
        } else {
            ["refinements"; 2]
        }
    }

    /// The refinement levels (the first `quick_levels` with `quick`), validated (dt > 0, at
    /// least one element).
    pub fn refinements(&self, quick: bool) -> Result<Vec<Refinement>> {
        self.validate()?;
        let field = |f: &str| self.field(f);
        for choice in &self.schemes {
            choice
                .options
                .params
                .validate(&format!("sweep.{}", self.name))?;
        }
        let mut levels = if self.refinements.is_empty() {
            let dt = self
                .dt
                .ok_or_else(|| Error::invalid(field("dt"), "missing", "dt or refinements"))?;
            let count = self
                .levels
                .ok_or_else(|| Error::invalid(field("levels"), "missing", "levels ≥ 1"))?;
            let ratio = self.ratio.unwrap_or(2);
            if ratio < 2 {
                return Err(Error::invalid(field("ratio"), ratio, "integer ≥ 2"));
            }
            // Level k: elements × ratioᵏ, dt / ratioᵏ, while they fit (k < 64 for ratio ≥ 2).
            let level = |k: usize| -> Option<Refinement> {
                let factor = ratio.checked_pow(u32::try_from(k).ok()?)?;
                let elements = match self.elements {
                    Some(n) => Some(n.checked_mul(factor)?),
                    None => None,
                };
                Some(Refinement {
                    elements,
                    dt: dt / factor as f64,
                })
            };
            let mut levels = Vec::new();
            for k in 0..count {
                let overflow =
                    format!("level {k} would take ratio^{k} times the elements or steps");
                levels.push(level(k).ok_or_else(|| match (k, self.elements) {
                    // The first refinement overflows: elements × ratio.
                    (1, Some(n)) => Error::invalid(
                        field("ratio"),
                        ratio,
                        &format!("{overflow}: elements × ratio = {n} × {ratio} overflows"),
                    ),
                    _ => Error::invalid(field("levels"), count, &overflow),
                })?);
            }
            levels
        } else {
            self.refinements.clone()
        };
        if levels.is_empty() {
            return Err(Error::invalid(field("levels"), 0, "at least one level"));
        }
        let given = self.level_fields();
        for r in &levels {
            positive(&field(given[0]), r.dt)?;
            if r.elements == Some(0) {
                return Err(Error::invalid(field(given[1]), 0, "must be ≥ 1"));
            }
        }
        if quick {
            levels.truncate(self.quick_levels);
        }
        Ok(levels)
    }

    /// Command-line-like overrides of one combination.
    pub fn overrides(&self, space: &str, choice: &SchemeChoice, level: Refinement) -> Overrides {
        let origin = Origin {
            table: format!("sweep.{}", self.name),
            levels: self.level_fields(),
            choice: "schemes",
        };
        Overrides {
            friction: self.friction,
            ..combination(space, choice, &self.degree, level, self.t_end, origin)
        }
    }
}

/// A `[[history]]` table: time series plotted by the report (seed figures 3–4).
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HistorySpec {
    /// Output name suffix: `<case>[_<name>]_energy.png`, `<case>[_<name>]_contact_stress.png`.
    #[serde(default)]
    pub name: String,
    /// Spaces compared.
    pub spaces: Vec<String>,
    /// Time steps compared.
    pub dts: Vec<f64>,
    /// Scheme (with parameters).
    pub scheme: SchemeChoice,
    /// Elements (default: the file's).
    pub elements: Option<usize>,
    /// Per-space degree.
    #[serde(default)]
    pub degree: std::collections::BTreeMap<String, usize>,
}

/// Command-line-like overrides of `space` × `choice` at one refinement level.
fn combination(
    space: &str,
    choice: &SchemeChoice,
    degree: &BTreeMap<String, usize>,
    level: Refinement,
    t_end: Option<f64>,
    origin: Origin,
) -> Overrides {
    Overrides {
        space: Some(space.to_string()),
        scheme: Some(choice.scheme.clone()),
        options: choice.options.clone(),
        degree: degree.get(space).copied(),
        elements: level.elements,
        cells: None,
        mesh: None,
        dt: Some(level.dt),
        t_end,
        friction: None,
        incidence: None,
        origin: Some(origin),
    }
}
