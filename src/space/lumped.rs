//! Diagonal (lumped) mass by HRZ scaling (Hinton–Rock–Zienkiewicz 1976):
//! `M^K_aa = m_K · M^K_aa / Σ_b M^K_bb` with `m_K = Σ_ab M^K_ab` the element mass.
//! For P1 (and Q1) this is the row-sum lumping; for P2 it stays positive where row sums are not.

use super::sparse_mass::SparseMass;
use super::{MassModel, Space};
use crate::error::Result;
use crate::param::Entry;
use crate::problem::Inertia;
use nalgebra::DMatrix;

/// Lumped mass.
#[derive(Debug, Clone, Copy)]
pub struct Lumped;

/// HRZ-lumped copy of an element mass.
pub fn hrz(m: &DMatrix<f64>) -> DMatrix<f64> {
    let total = m.sum();
    let trace = m.trace();
    DMatrix::from_diagonal(&(m.diagonal() * (total / trace)))
}

/// Registry entry: `lumped` (no parameter).
pub const ENTRY: Entry<dyn Space> = Entry {
    name: "lumped",
    params: &[],
    build: |_| Ok(Box::new(Lumped)),
};

impl Space for Lumped {
    fn name(&self) -> &'static str {
        "lumped"
    }

    fn inertia(&self, model: &MassModel) -> Result<Box<dyn Inertia>> {
        Ok(SparseMass::boxed(model.assemble(|el, _| hrz(&el.mass))?))
    }
}
