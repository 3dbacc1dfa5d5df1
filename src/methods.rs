//! Every registered method at once: the registries' parameters as command-line flags and
//! case-file keys, and the choices that need to know the registries (default formulation, sweep
//! labels). This module sits above the method families (`space`, `time`, `contact`), which
//! import only the generic declarations of [`crate::param`]; the impls here complete
//! [`Params`] and [`Options`] with what reads the registries.

use crate::error::Result;
use crate::param::{Options, Param, Params};

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

impl Params {
    /// Every key a registered parameter and every value finite; `table` names where they were
    /// read (`run`, `sweep.orders`, …).
    pub fn validate(&self, table: &str) -> Result<()> {
        self.check_keys(table, &all_params())
    }

    /// `label=value, …` of the set values, those of `first` (a scheme's own) first, then the
    /// others in registry order.
    pub fn label_with(&self, first: &[&Param]) -> String {
        let rest = all_params().into_iter().filter(|p| !first.contains(p));
        self.label(first.iter().copied().chain(rest))
    }
}

impl Options {
    /// Contact formulation name (default `nodal`).
    pub fn contact(&self) -> &str {
        self.contact
            .as_deref()
            .unwrap_or(crate::contact::DEFAULT_FORMULATION)
    }

    /// LCP solver name (default `active_set`).
    pub fn contact_solver(&self) -> &str {
        self.contact_solver
            .as_deref()
            .unwrap_or(crate::contact::DEFAULT_SOLVER)
    }

    /// The contact solver of a run with or without Coulomb friction: the one set, else
    /// `active_set`, or with friction [`crate::contact::friction::DEFAULT_SOLVER`].
    pub fn contact_solver_with(&self, friction: bool) -> &str {
        match (&self.contact_solver, friction) {
            (None, true) => crate::contact::friction::DEFAULT_SOLVER,
            _ => self.contact_solver(),
        }
    }

    /// Linear solver name (default `auto`).
    pub fn linear_solver(&self) -> &str {
        self.linear_solver
            .as_deref()
            .unwrap_or(crate::time::DEFAULT_LINEAR_SOLVER)
    }

    /// `key=value, …` of what is set (sweep labels): the parameters, `scheme`'s own first, then
    /// the contact choices.
    pub fn label(&self, scheme: &str) -> String {
        let own = crate::time::entry(scheme).map_or(&[][..], |e| e.params);
        let mut parts: Vec<String> = [self.params.label_with(own)]
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
                    .help(format!(
                        "{} (default {} where the case file does not set it)",
                        p.help, p.default
                    )),
            )
        })
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}
