//! dyncontact: a verification and benchmark suite for finite element elastodynamics with
//! frictionless unilateral (Signorini) contact.
//!
//! Data flow (DESIGN.md §2): case file ([`cases`]) → mesh ([`mesh`]) → elements and assembly
//! ([`fem`]) → space discretisation of the inertia ([`space`]) → [`problem::Problem`] → time scheme
//! ([`time`]) with a contact solver ([`contact`]) → time series and [`metrics`] ([`run`]) →
//! CSV and PNG ([`output`]). Exact reference solutions live in [`exact`].

pub mod cases;
pub mod contact;
pub mod error;
pub mod exact;
pub mod fem;
pub mod harness;
pub mod linalg;
pub mod mesh;
pub mod metrics;
pub mod orders;
pub mod output;
pub mod problem;
pub mod report;
pub mod run;
pub mod space;
pub mod time;

pub use error::{Error, Result};
