//! Finite element building blocks: quadrature, reference elements, local and global assembly.

pub mod assembly;
pub mod boundary;
pub mod discretisation;
pub mod elasticity;
pub mod lagrange1d;
pub mod quadrature;
pub mod reference;
pub mod segment;
