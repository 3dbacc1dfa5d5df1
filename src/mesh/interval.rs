//! Uniform mesh of the interval (0, L): N segments of Lagrange degree p (1 or 2), nodes numbered
//! left to right (node `p·e + k` is local node k of segment e, at `x = (p·e + k) h / p`).

use super::Mesh;
use crate::element::reference::RefElement;
use crate::error::{positive, Error, Result};

/// The mesh of (0, `length`) with `elements` segments of degree `degree`; its `h` is `L / N`.
pub fn interval(length: f64, elements: usize, degree: usize) -> Result<Mesh> {
    positive("geometry.length", length)?;
    if elements == 0 {
        return Err(Error::invalid("mesh.elements", elements, "must be >= 1"));
    }
    if !(1..=2).contains(&degree) {
        return Err(Error::invalid("mesh.degree", degree, "must be 1 or 2"));
    }
    let h = length / elements as f64;
    let nodes = (0..=elements * degree)
        .map(|i| [i as f64 * h / degree as f64, 0.0, 0.0])
        .collect();
    let connectivity = (0..elements)
        .map(|e| (degree * e..=degree * e + degree).collect())
        .collect();
    Ok(Mesh {
        origin: format!("interval (0, {length}), {elements} segments"),
        element: RefElement::segment(degree),
        nodes,
        connectivity,
        h,
        contact_faces: None,
        tags: None,
    })
}
