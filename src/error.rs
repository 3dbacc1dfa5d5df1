//! One error type for the whole crate: every failure names the file, field, step or value at fault.

use std::path::PathBuf;

/// Result alias used throughout dyncontact.
pub type Result<T> = std::result::Result<T, Error>;

/// Everything that can go wrong between a case file and a report.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The directory of case files cannot be read (run outside the repository).
    #[error(
        "no case files at {} ({source}): give a folder that holds case files (`*.toml`; they \
         ship in the `cases/` folder of the dyncontact repository, found from its root): \
         `dyncontact list DIR`, `dyncontact report --cases DIR`",
        .dir.display()
    )]
    NoCaseDirectory {
        dir: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// An input file (case file, mesh, a CSV table read back) that cannot be read or used: not a
    /// regular file, too large, unreadable or malformed.
    #[error("{role} {path}: {message}")]
    Input {
        role: &'static str,
        path: PathBuf,
        message: String,
    },
    /// The case file is not valid TOML or does not match the case schema.
    #[error("{path}: malformed case file: {message}")]
    CaseSyntax { path: PathBuf, message: String },
    /// A field has a value outside its admissible range (negative density, dt ≤ 0, NaN, …).
    #[error("invalid value for `{field}`: {value} ({requirement})")]
    InvalidField {
        field: String,
        value: String,
        requirement: String,
    },
    /// A name (space, scheme, case) that is not known.
    #[error("unknown {kind} `{name}` (known: {known})")]
    UnknownName {
        kind: &'static str,
        name: String,
        known: String,
    },
    /// A combination that is well formed but refused by design (e.g. singular_dynamic with P1),
    /// with the reason.
    #[error("unsupported combination: {0}")]
    Unsupported(String),
    /// An internal fault: a state the code should never reach (inconsistent shapes, a worker
    /// thread that stopped). A bug, not a property of the input: please report it.
    #[error("internal error (a bug, please report it): {0}")]
    Internal(String),
    /// A matrix that must be SPD is not, or a factorisation failed.
    #[error("factorisation of {matrix} failed: {reason}")]
    Factorisation { matrix: String, reason: String },
    /// The contact solver did not converge or produced an inadmissible answer.
    #[error("contact solver failed at step {step} (t = {time:.6e}): {reason}")]
    ContactSolver {
        step: usize,
        time: f64,
        #[source]
        reason: SolverError,
    },
    /// A two-body state past the small-sliding limit of the interface's pairing
    /// ([`crate::fem::sliding`]).
    #[error("small sliding exceeded at step {step} (t = {time:.6e}): {reason}")]
    SmallSliding {
        step: usize,
        time: f64,
        reason: String,
    },

    /// The discrete solution blew up (NaN or infinite values).
    #[error("solution diverged at step {step} (t = {time:.6e}): {reason}")]
    Diverged {
        step: usize,
        time: f64,
        reason: String,
    },
    /// The step matrix `m M + k K` whose stiffness term `k max K_ii` (`stiff`) is below the
    /// round-off of its mass term (`mass`): a time step too small for K to enter the step.
    /// [`Error::at_time_step`] names the case's `run.dt` for it.
    #[error(
        "the stiffness term of the step matrix m M + k K (k = {k:e}: {stiff:.3e}) is below the \
         round-off of its mass term ({mass:.3e})"
    )]
    StepMatrix { k: f64, stiff: f64, mass: f64 },
    /// Writing CSV output failed (reading one is an [`Error::Input`]).
    #[error("csv output {path}: {message}")]
    Csv { path: PathBuf, message: String },
    /// A mesh (file or generator) is unusable: inverted cell, missing group, unknown element…
    #[error("{origin}: {message}")]
    Mesh { origin: String, message: String },
    /// Writing or reading VTK field output failed.
    #[error("vtk output {path}: {message}")]
    Vtk { path: PathBuf, message: String },
    /// An error with where it arose: the case file, the sweep.
    #[error("{context}: {source}")]
    Context {
        context: String,
        #[source]
        source: Box<Error>,
    },
    /// Plotting failed.
    #[error("plot {path}: {message}")]
    Plot { path: PathBuf, message: String },
}

/// Why a per-step contact solver failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolverError {
    /// The Delassus block of the active set is not positive definite.
    #[error("Delassus block not positive definite (pivot {pivot:e})")]
    NotPositiveDefinite {
        /// The failing pivot.
        pivot: f64,
    },
    /// A Newton-type active-set iteration met a singular active block.
    #[error("{method}: singular active block")]
    Singular {
        /// The method.
        method: &'static str,
    },
    /// No solution after the allowed iterations.
    #[error("{method} did not converge: {detail}")]
    NotConverged {
        /// The method.
        method: &'static str,
        /// What was exhausted, with its measure (iterations, residual).
        detail: String,
    },
    /// The external solver (Clarabel) stopped with a status other than solved.
    #[error("clarabel status {status}")]
    Clarabel {
        /// Its status (and what followed).
        status: String,
    },
}

impl Error {
    /// An [`Error::InvalidField`] with the offending value printed with `{:?}`.
    pub fn invalid(field: impl Into<String>, value: impl std::fmt::Debug, req: &str) -> Self {
        Error::InvalidField {
            field: field.into(),
            value: format!("{value:?}"),
            requirement: req.to_string(),
        }
    }

    /// The error as met in the case file `path`, named in front unless the error names it
    /// already (malformed TOML, an unreadable file).
    pub fn in_case_file(self, path: &std::path::Path) -> Self {
        match &self {
            Error::CaseSyntax { path: p, .. } | Error::Input { path: p, .. } if p == path => self,
            _ => self.context(path.display()),
        }
    }

    /// The error named after the case file `path` when it is about the case's input (a field's
    /// value, an unknown name, a refused combination, its mesh: a node below the plane, named
    /// after the mesh file or generator next) or its run (a divergence, a solver or
    /// factorisation failure, each with its step), as the errors of reading the file are; an
    /// output file's error names that file instead, an internal error the bug.
    pub fn from_case_input(self, path: &std::path::Path) -> Self {
        match self {
            Error::InvalidField { .. }
            | Error::UnknownName { .. }
            | Error::Unsupported(_)
            | Error::Mesh { .. }
            | Error::ContactSolver { .. }
            | Error::Diverged { .. }
            | Error::SmallSliding { .. }
            | Error::Factorisation { .. }
            | Error::StepMatrix { .. } => self.in_case_file(path),
            _ => self,
        }
    }

    /// An invalid field of a case file's `table` named as it is there (`beta` → `run.beta`):
    /// for the errors of code that knows the parameter, not the table.
    pub fn in_table(self, table: &str) -> Self {
        self.with_field(|f| match f.contains('.') {
            true => f.to_string(),
            false => format!("{table}.{f}"),
        })
    }

    /// An invalid field renamed by `rename` (any other error as it is).
    pub fn with_field(self, rename: impl FnOnce(&str) -> String) -> Self {
        match self {
            Error::InvalidField {
                field,
                value,
                requirement,
            } => Error::InvalidField {
                field: rename(&field),
                value,
                requirement,
            },
            e => e,
        }
    }

    /// The error preceded by `context` (`<context>: <error>`).
    pub fn context(self, context: impl std::fmt::Display) -> Self {
        Error::Context {
            context: context.to_string(),
            source: Box::new(self),
        }
    }

    /// An [`Error::StepMatrix`] named as the case's `run.dt` = `dt`, with the scheme's
    /// parameters `params` (`beta=0.5;gamma=0.5`) and `k/dt²`; any other error as it is.
    pub fn at_time_step(self, dt: f64, params: &str) -> Self {
        let Error::StepMatrix { k, stiff, mass } = self else {
            return self;
        };
        let with = if params.is_empty() {
            String::new()
        } else {
            format!(" with {params}")
        };
        let k = match k {
            0.0 => "0 (it underflows)".to_string(),
            k => format!("{k:.3e} = {:.3e} dt²", k / dt / dt),
        };
        Error::invalid(
            "run.dt",
            dt,
            &format!(
                "too small against the mass{with}: the step matrix m M + k K has k = {k}, and its \
                 stiffness term ({stiff:.3e}) is below the round-off of its mass term \
                 ({mass:.3e}), so K would not enter the step; increase run.dt (or the scheme's \
                 factor of dt² in k: newmark's or hht's run.beta), or check the mass (density) \
                 against the stiffness"
            ),
        )
    }

    /// Wraps an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn positive(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(field, value, "must be finite and > 0"))
    }
}

/// A float for messages: as `{}` prints it from 1e-4 to 1e15 (`0.8`, `2`, `12.5`), in the
/// short `{:e}` form beyond (`1e-318`, not its 330 decimal digits).
pub fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Lengths accepted by [`length`]: the geometry forms up to third powers of the lengths and
/// their inverses (cell volumes, Jacobians, stiffness entries), which stay far inside the
/// floating-point range (1e±308) for lengths in `[1e-50, 1e50]`.
pub const LENGTH_RANGE: (f64, f64) = (1e-50, 1e50);

/// Checks that the length `value` lies in [`LENGTH_RANGE`].
pub fn length(field: &str, value: f64) -> Result<f64> {
    let (lo, hi) = LENGTH_RANGE;
    if (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            value,
            &format!(
                "a length must lie in [{lo:e}, {hi:e}]: choose units in which the body is of \
                 moderate size"
            ),
        ))
    }
}

/// The least penalty stiffness accepted, relative to the stiffness it is declared against: a
/// softer penalty leaves a contact force lost against the step's, far below what a compliance
/// study uses. Only the absurd: a penalty above it may still be too soft to hold the body
/// (block2d falls through at r = 1e6), which `max_penetration` reports.
pub const MIN_PENALTY: f64 = 1e-12;

/// Checks a penalty parameter `value` (finite, > 0) whose penalty stiffness is `relative` times
/// the stiffness `scale` describes: refused below [`MIN_PENALTY`].
pub fn penalty(field: &str, value: f64, relative: f64, scale: &str) -> Result<f64> {
    positive(field, value)?;
    if relative >= MIN_PENALTY {
        return Ok(value);
    }
    Err(Error::invalid(
        field,
        value,
        &format!(
            "makes the penalty stiffness {relative:e} times {scale}, below {MIN_PENALTY:e}: the \
             contact force would be negligible and the body fall through the obstacle"
        ),
    ))
}

/// Checks that `value` is finite and ≥ 0.
pub fn non_negative(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(field, value, "must be finite and >= 0"))
    }
}

/// Checks that `value` is finite.
pub fn finite(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::invalid(field, value, "must be finite"))
    }
}

/// Checks that `value` lies in `[lo, hi]` (and is finite).
pub fn in_range(field: &str, value: f64, lo: f64, hi: f64) -> Result<f64> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(Error::invalid(
            field,
            value,
            &format!("must lie in [{}, {}]", short(lo), short(hi)),
        ))
    }
}
