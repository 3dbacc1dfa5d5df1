//! Methods and their numerical parameters, each declared once.
//!
//! A method (a time scheme, a contact formulation) declares its parameters as [`Param`] constants in
//! its own file and registers itself with one [`Entry`] line in its family's registry
//! (`time::SCHEMES`, `contact::FORMULATIONS`). Everything else reads those declarations:
//! the command line (`--beta`, `--nitsche-gamma`, … through [`Params`]' clap implementation), the
//! case files (`[run]` and the `[[sweep]]` scheme entries take the same keys, see
//! [`crate::cases::Options`]), the sweep labels ([`Params::label`]), and the `parameters` column of
//! the records ([`Entry::describe`]).

use crate::error::{Error, Result};
use serde::{Deserialize, Deserializer};
use std::collections::BTreeMap;

/// One numerical parameter of a method.
#[derive(Debug, PartialEq)]
pub struct Param {
    /// Key in case files and records, `--name` on the command line (with `-` for `_`).
    pub name: &'static str,
    /// Short name in sweep labels and figure legends.
    pub label: &'static str,
    /// Value when neither the case file nor the command line sets it.
    pub default: f64,
    /// One line of help (command line and `list`).
    pub help: &'static str,
}

/// A method in a registry: its name, its parameters and how to build it from the run's choices
/// `I` (the parameter values for a scheme, the [`Options`] for a contact formulation).
pub struct Entry<T: ?Sized, I = Params> {
    /// Name on the command line, in case files and in records.
    pub name: &'static str,
    /// Its parameters, in the order of its records' `parameters` column.
    pub params: &'static [&'static Param],
    /// Builds the method from the choices (validated by the method itself).
    pub build: fn(&I) -> Result<Box<T>>,
}

impl<T: ?Sized, I> Entry<T, I> {
    /// `name=value;…` of this method's parameters (set or default), as in the records.
    pub fn describe(&self, values: &Params) -> String {
        self.params
            .iter()
            .map(|p| format!("{}={}", p.name, values.get(p)))
            .collect::<Vec<_>>()
            .join(";")
    }
}

/// The entry called `name` of a registry (`kind` names the family in the error).
pub fn find<'r, T: ?Sized, I>(
    registry: &'r [Entry<T, I>],
    kind: &'static str,
    name: &str,
) -> Result<&'r Entry<T, I>> {
    registry
        .iter()
        .find(|e| e.name == name)
        .ok_or_else(|| Error::UnknownName {
            kind,
            name: name.to_string(),
            known: names(registry).join(", "),
        })
}

/// The names of a registry's entries.
pub fn names<T: ?Sized, I>(registry: &[Entry<T, I>]) -> Vec<&'static str> {
    registry.iter().map(|e| e.name).collect()
}

/// Every parameter of every registered method, each once, in registry order.
pub fn all_params() -> Vec<&'static Param> {
    let schemes = crate::time::SCHEMES.iter().flat_map(|e| e.params.iter());
    let contact = crate::contact::FORMULATIONS
        .iter()
        .flat_map(|e| e.params.iter());
    let mut all: Vec<&'static Param> = Vec::new();
    for p in schemes.chain(contact) {
        if !all.iter().any(|q| q.name == p.name) {
            all.push(p);
        }
    }
    all
}

/// Parameter values set explicitly (by a case file or the command line); the others take their
/// declared default.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Params(BTreeMap<String, f64>);

impl Params {
    /// The value of `p`: set, or its default.
    pub fn get(&self, p: &Param) -> f64 {
        self.0.get(p.name).copied().unwrap_or(p.default)
    }

    /// The value of `p` if it was set.
    pub fn value(&self, p: &Param) -> Option<f64> {
        self.0.get(p.name).copied()
    }

    /// Sets parameter `name`.
    pub fn set(&mut self, name: &str, value: f64) -> &mut Self {
        self.0.insert(name.to_string(), value);
        self
    }

    /// `self` with parameter `name` set (builder form).
    pub fn with(mut self, name: &str, value: f64) -> Self {
        self.set(name, value);
        self
    }

    /// Sets `p` to `value` unless it is set already (a case's physical default).
    pub fn or_set(&mut self, p: &Param, value: f64) {
        self.0.entry(p.name.to_string()).or_insert(value);
    }

    /// The values of `other` replace those of `self`.
    pub fn overlay(&mut self, other: &Params) {
        self.0.extend(other.0.iter().map(|(k, v)| (k.clone(), *v)));
    }

    /// Every key a registered parameter and every value finite; `table` names where they were
    /// read (`run`, `sweep.orders`, …).
    pub fn validate(&self, table: &str) -> Result<()> {
        let known = all_params();
        for (k, v) in &self.0 {
            if !known.iter().any(|p| p.name == k) {
                let names: Vec<_> = known.iter().map(|p| p.name).collect();
                return Err(Error::invalid(
                    format!("{table}.{k}"),
                    v,
                    &format!("unknown key; parameters: {}", names.join(", ")),
                ));
            }
            crate::error::finite(&format!("{table}.{k}"), *v)?;
        }
        Ok(())
    }

    /// `label=value, …` of the set values, those of `first` (a scheme's own) first, then the
    /// others in registry order.
    pub fn label(&self, first: &[&Param]) -> String {
        let rest = all_params();
        let ordered = first
            .iter()
            .copied()
            .chain(rest.into_iter().filter(|p| !first.contains(p)));
        ordered
            .filter_map(|p| self.value(p).map(|v| format!("{}={v}", p.label)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl<'de> Deserialize<'de> for Params {
    /// A table of numbers (integers are accepted as reals); the keys are checked by
    /// [`Params::validate`], which names the table.
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let raw = BTreeMap::<String, toml::Value>::deserialize(d)?;
        let mut out = BTreeMap::new();
        for (k, v) in raw {
            let x = match v {
                toml::Value::Float(x) => x,
                toml::Value::Integer(i) => i as f64,
                other => {
                    return Err(serde::de::Error::custom(format!(
                        "`{k}`: expected a number or a known key, found {}",
                        other.type_str()
                    )))
                }
            };
            out.insert(k, x);
        }
        Ok(Self(out))
    }
}

/// Method choices and numerical parameters: the keys a `[run]` table, a `[[sweep]]` scheme entry
/// and the command line share. The parameters (`beta`, `penalty`, …) are those the methods declare
/// ([`crate::method`]); unset ones take the declared default.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, clap::Args)]
pub struct Options {
    /// Contact formulation (`dyncontact list` lists them with their parameters).
    #[arg(long)]
    pub contact: Option<String>,
    /// Multiplier space of the `weak` formulation on Γ_C: p1 (vertices, default) or p0 (faces).
    #[arg(long = "contact-multiplier")]
    pub contact_multiplier: Option<String>,
    /// Solver of the per-step contact LCP (active_set, clarabel).
    #[arg(long = "contact-solver")]
    pub contact_solver: Option<String>,
    /// Linear solver of the step matrix: auto (CG for large 3D problems with nodal contact,
    /// direct otherwise), direct (sparse Cholesky / LU) or cg.
    #[arg(long = "linear-solver")]
    pub linear_solver: Option<String>,
    /// Numerical parameters of the methods.
    #[serde(flatten)]
    #[command(flatten)]
    pub params: Params,
}

impl Options {
    /// The values set in `other` replace those of `self`.
    pub fn overlay(&mut self, other: &Options) {
        let pick = |a: &mut Option<String>, b: &Option<String>| {
            if b.is_some() {
                a.clone_from(b);
            }
        };
        pick(&mut self.contact, &other.contact);
        pick(&mut self.contact_multiplier, &other.contact_multiplier);
        pick(&mut self.contact_solver, &other.contact_solver);
        pick(&mut self.linear_solver, &other.linear_solver);
        self.params.overlay(&other.params);
    }

    /// Contact formulation name (default `nodal`).
    pub fn contact(&self) -> &str {
        self.contact
            .as_deref()
            .unwrap_or(crate::contact::DEFAULT_FORMULATION)
    }

    /// LCP solver name (default `active_set`).
    pub fn contact_solver(&self) -> &str {
        self.contact_solver.as_deref().unwrap_or("active_set")
    }

    /// Linear solver name (default `auto`).
    pub fn linear_solver(&self) -> &str {
        self.linear_solver.as_deref().unwrap_or("auto")
    }

    /// `key=value, …` of what is set (sweep labels): the parameters, `scheme`'s own first, then
    /// the contact choices.
    pub fn label(&self, scheme: &str) -> String {
        let own = crate::time::entry(scheme).map_or(&[][..], |e| e.params);
        let mut parts: Vec<String> = [self.params.label(own)]
            .into_iter()
            .filter(|s| !s.is_empty())
            .collect();
        for (k, v) in [
            ("contact", &self.contact),
            ("contact_multiplier", &self.contact_multiplier),
            ("contact_solver", &self.contact_solver),
            ("linear_solver", &self.linear_solver),
        ] {
            if let Some(v) = v {
                parts.push(format!("{k}={v}"));
            }
        }
        parts.join(", ")
    }
}

/// The command-line flag of a parameter: `nitsche_gamma` → `nitsche-gamma`.
fn flag(p: &Param) -> String {
    p.name.replace('_', "-")
}

impl clap::FromArgMatches for Params {
    fn from_arg_matches(m: &clap::ArgMatches) -> std::result::Result<Self, clap::Error> {
        let mut out = Self::default();
        out.update_from_arg_matches(m)?;
        Ok(out)
    }

    fn update_from_arg_matches(
        &mut self,
        m: &clap::ArgMatches,
    ) -> std::result::Result<(), clap::Error> {
        for p in all_params() {
            if let Some(v) = m.get_one::<f64>(p.name) {
                self.set(p.name, *v);
            }
        }
        Ok(())
    }
}

impl clap::Args for Params {
    /// One `--flag VALUE` per registered parameter, with its declared help.
    fn augment_args(cmd: clap::Command) -> clap::Command {
        all_params().into_iter().fold(cmd, |cmd, p| {
            cmd.arg(
                clap::Arg::new(p.name)
                    .long(flag(p))
                    .value_name("VALUE")
                    .value_parser(clap::value_parser!(f64))
                    .allow_negative_numbers(true)
                    .help(format!("{} (default {})", p.help, p.default)),
            )
        })
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}
