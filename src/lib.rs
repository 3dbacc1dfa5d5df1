//! dyncontact: a verification and benchmark suite for finite element elastodynamics with
//! frictionless unilateral (Signorini) contact.
//!
//! Data flow (DESIGN.md §2): case file ([`cases`]) → mesh ([`mesh`]) → elements and assembly
//! ([`fem`]) → space discretisation of the inertia ([`space`]) → [`problem::Problem`] → time scheme
//! ([`time`]) with a contact solver ([`contact`]) → the [`study`] layer (runs, metrics, sweeps, records, orders) →
//! [`report`] (figures, tables, index), writing CSV and PNG through [`output`]. Exact reference solutions live in [`exact`].

pub mod cases;
pub mod contact;
pub mod element;
pub mod error;
pub mod exact;
pub mod fem;
pub mod input;
pub mod linalg;
pub mod mesh;
pub mod methods;
pub mod output;
pub mod param;
pub mod problem;
pub mod report;
pub mod space;
pub mod study;
pub mod time;
pub mod util;

pub use error::{Error, Result};
