//! Methods' numerical parameters, declared once: the generic declarations every method file
//! uses ([`Param`], the registry [`Entry`]), the values a run sets ([`Params`]) and the method
//! choices a `[run]` table or the command line makes ([`Options`]).
//!
//! A method (space, time scheme, contact formulation) declares its parameters as [`Param`]
//! constants in its own file and registers itself with one [`Entry`] line in its family's
//! registry (`space::SPACES`, `time::SCHEMES`, `contact::FORMULATIONS`). This module knows no
//! registry: what reads them all (the command-line flags, the validation of case-file keys, the
//! sweep labels) is [`crate::methods`], above the method modules.

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
            .map(|p| format!("{}={}", p.name, value_text(values.get(p))))
            .collect::<Vec<_>>()
            .join(";")
    }
}

/// A parameter's value as the records write it: as Rust prints it, in exponent form outside
/// [1e-4, 1e16) (`penalty=1e300`, not 301 digits).
pub fn value_text(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e16).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
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

    /// True when parameter `name` was set.
    pub fn is_set(&self, name: &str) -> bool {
        self.0.contains_key(name)
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

    /// Every key one of `known` and every value finite; `table` names where they were read
    /// (`run`, `sweep.orders`, …).
    pub fn check_keys(&self, table: &str, known: &[&Param]) -> Result<()> {
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

    /// `label=value, …` of the set values, in the order of `order`.
    pub fn label<'a>(&self, order: impl IntoIterator<Item = &'a Param>) -> String {
        order
            .into_iter()
            .filter_map(|p| {
                self.value(p)
                    .map(|v| format!("{}={}", p.label, value_text(v)))
            })
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
    #[serde(default, deserialize_with = "names::contact")]
    pub contact: Option<String>,
    /// Multiplier space of the `weak` formulation on Γ_C: p1 (vertices, default) or p0 (faces).
    #[arg(long = "contact-multiplier")]
    #[serde(default, deserialize_with = "names::contact_multiplier")]
    pub contact_multiplier: Option<String>,
    /// Solver of the per-step contact problem: active_set, clarabel (the LCP), alart_curnier,
    /// projected_gauss_seidel, de_saxce (Coulomb friction, or the LCP without it).
    #[arg(long = "contact-solver")]
    #[serde(default, deserialize_with = "names::contact_solver")]
    pub contact_solver: Option<String>,
    /// Linear solver of the step matrix: auto (CG from 5·10⁴ dofs on 2D and 3D meshes with a
    /// sparse mass and nodal contact or Nitsche's at θ = 1, unless the stiffness dominates a 2D
    /// step matrix; direct otherwise), direct (sparse Cholesky / LU) or cg.
    #[arg(long = "linear-solver")]
    #[serde(default, deserialize_with = "names::linear_solver")]
    pub linear_solver: Option<String>,
    /// Numerical parameters of the methods.
    #[serde(flatten)]
    #[command(flatten)]
    pub params: Params,
}

/// The name fields of [`Options`], read so that a wrong type names its key: flattened into
/// `[run]` and the sweeps' scheme entries, serde's own error would point at the table only.
mod names {
    use serde::{Deserialize, Deserializer};

    fn name<'de, D: Deserializer<'de>>(d: D, key: &str) -> Result<Option<String>, D::Error> {
        match toml::Value::deserialize(d)? {
            toml::Value::String(s) => Ok(Some(s)),
            other => Err(serde::de::Error::custom(format!(
                "`{key}`: expected a name (a string), found {}",
                other.type_str()
            ))),
        }
    }

    macro_rules! named {
        ($($key:ident),*) => {$(
            pub fn $key<'de, D: Deserializer<'de>>(d: D) -> Result<Option<String>, D::Error> {
                name(d, stringify!($key))
            }
        )*};
    }

    named!(contact, contact_multiplier, contact_solver, linear_solver);
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
}

#[cfg(test)]
mod tests {
    use super::value_text;

    #[test]
    fn values_keep_their_text_and_extremes_take_an_exponent() {
        for (v, text) in [
            (0.5, "0.5"),
            (1.0, "1"),
            (1e-3, "0.001"),
            (-100.0, "-100"),
            (0.0, "0"),
            (1e300, "1e300"),
            (1e-5, "1e-5"),
        ] {
            assert_eq!(value_text(v), text);
        }
    }
}
