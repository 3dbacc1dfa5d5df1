//! The study layer: one [`run`] (its probe [`trajectory`] and [`metrics`]), the [`jobs`] of the
//! `[[sweep]]` tables run in parallel (longest first within a memory budget: [`schedule`]),
//! streamed to a [`journal`] (resumable), their [`records`], [`reference`] errors for cases
//! without an exact solution, and observed [`orders`]; the
//! [`finite_body`] law of a sphere (static solves), the reference beside Hertz's half-space.
//!
//! Data flows one way: `trajectory` ← `metrics` ← `run` ← `jobs` ← `records`, `reference`,
//! `orders`. The report ([`crate::report`]) reads this layer; nothing here reads the report.

pub mod finite_body;
pub mod jobs;
pub mod journal;
pub mod lock;
pub mod manifest;
pub mod metrics;
pub mod orders;
pub mod peers;
pub mod profile;
pub mod records;
pub mod reference;
pub mod run;
pub mod schedule;
pub mod trajectory;
