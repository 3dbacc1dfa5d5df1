//! Meshes. Only what the cases need: a uniform subdivision of an interval, and structured meshes
//! of a rectangle or a box.

pub mod interval;
pub mod structured;
