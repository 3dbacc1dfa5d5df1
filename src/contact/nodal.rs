//! Nodal contact (the default): one multiplier per vertex of Γ_C, the Signorini conditions
//! `g_i = g₀_i − (B_N U)_i ≥ 0, λ_i ≥ 0, λ_i g_i = 0` at each vertex, λ_i the nodal force, solved
//! exactly per step by the LCP solver (Khenous, Laborde, Renard 2008; DESIGN.md §1). With
//! Coulomb friction, the tangential rows at the same vertices and a friction solver
//! ([`super::friction`]).

use super::{Formulation, Solver};
use crate::error::Result;
use crate::param::{Entry, Options};
use crate::problem::Problem;

/// Registry entry: `nodal` (no parameter).
pub const ENTRY: Entry<dyn Formulation, Options> = Entry {
    name: "nodal",
    params: &[],
    build: |_| Ok(Box::new(Nodal)),
};

/// Nodal multipliers.
#[derive(Debug, Clone, Copy)]
pub struct Nodal;

impl Formulation for Nodal {
    fn name(&self) -> &'static str {
        "nodal"
    }

    fn setup(&self, problem: &mut Problem, solver: &str) -> Result<Box<dyn Solver>> {
        super::law(&problem.contact, solver)
    }

    fn friction(&self) -> std::result::Result<(), &'static str> {
        Ok(())
    }
}
