//! Finite element assembly on meshes of reference elements ([`crate::element`]): element
//! kernels, local-to-global scatter, boundary quadrature and the discretisation of a body.

pub mod assembly;
pub mod bodies;
pub mod boundary;
pub mod discretisation;
pub mod dofs;
pub mod elasticity;
pub mod mass_model;
pub mod point_mass;
pub mod sliding;
