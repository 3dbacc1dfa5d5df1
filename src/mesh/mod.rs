//! Meshes. Only what the cases need: a uniform subdivision of an interval.

pub mod interval;
