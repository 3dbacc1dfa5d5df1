//! Reference elements and quadrature, at the bottom of the finite element layers (meshes are
//! made of them, [`crate::fem`] assembles on them): the segment of 1D Lagrange elements, the
//! simplices and tensor cells of 2D/3D, and Gauss rules.

pub mod geometry;
pub mod quadrature;
pub mod reference;
pub mod segment;
