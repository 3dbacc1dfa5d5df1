//! The canonical curved bodies of the Hertz cases: a disc (2D, an O-grid of quadrilaterals or
//! triangles) and a ball (3D, a cubed sphere of hexahedra or tetrahedra), of radius R, touching
//! the plane `x_d = 0` at their pole `(0, …, 0)` with centre `(0, …, R)`.
//!
//! Built as an O-grid of the cube `[−1, 1]^d` (so that no cell has two faces on the curved
//! boundary): an inner cube `[−½, ½]^d` of n cells per direction and, on each of its 2d faces, a
//! shell block of n^{d−1} × ⌈n/2⌉ cells whose points are `c = (½ + ½ρ) P`, P on the face of the
//! unit cube, ρ ∈ [0, 1] (structured blocks, P2/Q2 nodes included, merged where they meet). The
//! cube is then mapped onto the body by
//! 1. the cube-to-ball map `X = q ((1 − t) + t²/‖q‖₂)`, `t = ‖q‖_∞`: the identity at the centre,
//!    the radial projection `q/‖q‖₂` on the boundary, monotone along every ray;
//! 2. a grading towards the pole `−e_d`: the Möbius automorphism of the unit ball sending 0 to
//!    `b = −α e_d`, `M_b(X) = ((1 − |b|²) X + (1 + 2⟨b,X⟩ + |X|²) b) / (1 + 2⟨b,X⟩ + |b|²|X|²)`.
//!    It is conformal (cells keep their shape, only their size changes: no cell is flattened or
//!    inverted) and maps the sphere onto itself; spacing is multiplied by `(1 − α)/(1 + α) = 1/√r`
//!    at the pole and by `√r` at the opposite pole, `r ≥ 1` the grading ratio.
//!
//! Every node, P2/Q2 midpoints included, is mapped, so the boundary nodes lie on the circle or
//! sphere (isoparametric curved cells). Scaled by R and lifted by R, the pole touches the plane at
//! the origin. The pole spacing is `h = R (2/n) / √r`.

use super::structured::box_mesh;
use super::Mesh;
use crate::element::reference::RefElement;
use crate::error::{Error, Result};

/// The Möbius automorphism of the unit ball sending 0 to `b`.
fn mobius(x: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let (bx, bb, xx) = (dot(b, x), dot(b, b), dot(x, x));
    let den = 1.0 + 2.0 * bx + bb * xx;
    std::array::from_fn(|k| ((1.0 - bb) * x[k] + (1.0 + 2.0 * bx + xx) * b[k]) / den)
}

/// The cube-to-ball map `q ((1 − t) + t²/‖q‖₂)`, `t = ‖q‖_∞`.
fn ball(q: [f64; 3]) -> [f64; 3] {
    let t = q.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let r = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if r == 0.0 {
        return q;
    }
    let f = (1.0 - t) + t * t / r;
    q.map(|v| v * f)
}

/// Half-width of the inner cube of the O-grid.
const INNER: f64 = 0.5;

/// Node coordinates and cell connectivity.
type Cells = (Vec<[f64; 3]>, Vec<Vec<usize>>);

/// The O-grid of `[−1, 1]^d`: nodes (merged where blocks meet) and connectivity.
fn o_grid(element: RefElement, n: usize) -> Result<Cells> {
    let d = element.dim;
    let layers = n.div_ceil(2);
    let mut blocks: Vec<Cells> = Vec::new();
    let inner = box_mesh(element, [n; 3], [2.0 * INNER; 3])?;
    let shift = |x: [f64; 3]| std::array::from_fn(|k| if k < d { x[k] - INNER } else { 0.0 });
    blocks.push((
        inner.nodes.iter().map(|&x| shift(x)).collect(),
        inner.connectivity,
    ));
    let mut cells = [n; 3];
    cells[d - 1] = layers;
    let mut size = [2.0; 3];
    size[d - 1] = 1.0;
    let shell = box_mesh(element, cells, size)?;
    for axis in 0..d {
        for side in [-1.0, 1.0] {
            let nodes = shell
                .nodes
                .iter()
                .map(|x| {
                    let rho = x[d - 1];
                    let mut t = (0..d - 1).map(|k| x[k] - 1.0);
                    let p: [f64; 3] = std::array::from_fn(|j| match j {
                        _ if j >= d => 0.0,
                        _ if j == axis => side,
                        _ => t.next().unwrap_or(0.0),
                    });
                    p.map(|v| v * (INNER + (1.0 - INNER) * rho))
                })
                .collect();
            blocks.push((nodes, shell.connectivity.clone()));
        }
    }
    // Merge coincident nodes (blocks share faces node for node).
    let key = |x: &[f64; 3]| x.map(|v| (v * 1e9).round() as i64);
    let mut index = std::collections::HashMap::new();
    let (mut nodes, mut connectivity) = (Vec::new(), Vec::new());
    for (bn, bc) in blocks {
        let ids: Vec<usize> = bn
            .iter()
            .map(|x| {
                *index.entry(key(x)).or_insert_with(|| {
                    nodes.push(*x);
                    nodes.len() - 1
                })
            })
            .collect();
        connectivity.extend(
            bc.into_iter()
                .map(|c| c.into_iter().map(|a| ids[a]).collect::<Vec<_>>()),
        );
    }
    Ok((nodes, connectivity))
}

/// Largest grading ratio. The disc at n = 48 is a valid mesh up to 1e10 (measured: 1e4 to 1e10
/// by decades); at 1e12 a cell near the pole inverts (det J down to −3e-12, refused by the
/// mesh's check), and at 1e300 the pole's cells were 1e-152 and the run was refused for a
/// density too small against them.
pub const MAX_GRADING: f64 = 1e10;

/// A generated disc or ball by [`round_body`]'s parameters (its radius aside: the cells fold
/// or not whatever the scale), kept beside its mesh to explain a failed check of the mesh.
///
/// The Möbius map is conformal, but the cells are not the map's image: their vertices (and
/// P2/Q2 nodes) are, joined as the element joins them. Where a cell spans a large part of the
/// map's variation its image folds: at the count n, every grading above a largest one (measured
/// for every family on n ≤ 8 by steps of 0.05 decade: below it every grading holds, above it
/// none), which grows with n overall but not monotonically. Hex Q1: n = 1, 2, 3, 4, 5, 8 hold
/// up to 4.86, 21.3, 34.3, 335, 95.6, 10 900; P2 tetrahedra: n = 2, 8 up to 6.38, 136; the disc
/// of Q1 cells at n = 1 up to 9.5. So the range [1, 1e10] of `mesh.grading` holds on fine
/// meshes only, and [`RoundBody::explain`] finds the limits of the count at hand by building
/// the meshes. The shipped spheres (grading 25: hex Q1 at n = 4, 8, 16, Q2 at 4, 8) hold.
#[derive(Debug, Clone, Copy)]
pub struct RoundBody {
    /// Element family of the cells.
    pub element: RefElement,
    /// Cells along each edge of the O-grid's inner cube (`mesh.elements`).
    pub n: usize,
    /// Top-over-pole spacing ratio (`mesh.grading`).
    pub grading: f64,
}

/// Size of the meshes, in cells times nodes per cell, up to which [`RoundBody::explain`]
/// builds them freely: the finer counts it tries, and the bisection's full precision (a
/// second or two on two cores for every family).
const SEARCH_SIZE: usize = 800_000;

/// `x > 0` rounded down to 3 significant digits (a limit that still holds, printed short).
fn floor3(x: f64) -> f64 {
    let e = x.log10().floor() - 2.0;
    let k = (x / 10f64.powf(e)).floor();
    format!("{k}e{e}").parse().unwrap_or(x)
}

impl RoundBody {
    /// The mesh, of radius `radius` ([`round_body`]).
    pub fn mesh(&self, radius: f64) -> Result<Mesh> {
        round_body(self.element, self.n, radius, self.grading)
    }

    /// Whether the mesh of `n` cells at `grading` fails its check ([`Mesh::check`]).
    fn folds(&self, n: usize, grading: f64) -> bool {
        round_body(self.element, n, 1.0, grading)
            .and_then(|m| m.check())
            .is_err()
    }

    /// The size of the mesh at `n`: its cells (`(1 + d) n^d` boxes of the O-grid, each split
    /// into d! simplices for triangles and tetrahedra) times the nodes per cell.
    fn size(&self, n: usize) -> usize {
        let d = self.element.dim;
        let split = match self.element.shape {
            crate::element::reference::Shape::Simplex => (1..=d).product(),
            crate::element::reference::Shape::Tensor => 1,
        };
        (1 + d) * n.pow(d as u32) * split * self.element.n_nodes()
    }

    /// `error`, a failed check of this body's mesh, as a refusal of `mesh.elements` at its
    /// `mesh.grading` when the generator's own cells fold there, with the largest grading that
    /// holds at this count (bisection in log scale) and the next count that holds at this
    /// grading (tried upwards while the meshes stay below [`SEARCH_SIZE`]); any other error
    /// as it is.
    pub fn explain(&self, error: Error) -> Error {
        let Self {
            element,
            n,
            grading,
        } = *self;
        if !self.folds(n, grading) {
            return error;
        }
        let what = if element.dim == 2 { "disc" } else { "sphere" };
        let fold = match &error {
            Error::Mesh { message, .. } => message.clone(),
            e => e.to_string(),
        };
        let g = crate::error::short(grading);
        let at_count = if self.folds(n, 1.0) {
            format!("no mesh.grading holds at mesh.elements = {n}")
        } else {
            let steps = if self.size(n) <= SEARCH_SIZE { 14 } else { 6 };
            let (mut lo, mut hi) = (1.0_f64, grading);
            for _ in 0..steps {
                let mid = (lo * hi).sqrt();
                match self.folds(n, mid) {
                    true => hi = mid,
                    false => lo = mid,
                }
            }
            format!(
                "at mesh.elements = {n} mesh.grading must lie in [1, {}]",
                crate::error::short(floor3(lo))
            )
        };
        let tried: Vec<usize> = (n + 1..)
            .take_while(|&m| self.size(m) <= SEARCH_SIZE)
            .collect();
        let at_grading = match tried.iter().find(|&&m| !self.folds(m, grading)) {
            Some(m) => {
                format!("at mesh.grading = {g} the next count that holds is mesh.elements = {m}")
            }
            None if tried.is_empty() => format!("at mesh.grading = {g} try a finer mesh"),
            None => format!(
                "at mesh.grading = {g} no mesh.elements from {} to {} holds",
                n + 1,
                tried[tried.len() - 1]
            ),
        };
        Error::invalid(
            "mesh.elements",
            n,
            &format!(
                "the {what} generator's own cells fold at mesh.grading = {g}: {at_count}, and \
                 {at_grading}; mesh.grading's range [1, {MAX_GRADING:e}] holds on fine meshes \
                 only. The check: {fold}"
            ),
        )
    }
}

/// The disc (`element.dim == 2`) or ball (3) of radius `radius` with `n` cells along each edge
/// of the O-grid's inner cube and grading ratio `grading_ratio ≥ 1` towards the pole.
pub fn round_body(element: RefElement, n: usize, radius: f64, grading_ratio: f64) -> Result<Mesh> {
    if n == 0 {
        return Err(Error::invalid("mesh.elements", n, "must be ≥ 1"));
    }
    crate::error::positive("geometry.radius", radius)?;
    if !(1.0..=MAX_GRADING).contains(&grading_ratio) {
        return Err(Error::invalid(
            "mesh.grading",
            grading_ratio,
            &format!(
                "must be in [1, {MAX_GRADING:e}] (largest over smallest spacing; beyond, the \
                 generator's cells near the pole invert)"
            ),
        ));
    }
    let d = element.dim;
    let (mut nodes, connectivity) = o_grid(element, n)?;
    let root = grading_ratio.sqrt();
    let mut pole = [0.0; 3];
    pole[d - 1] = -(root - 1.0) / (root + 1.0);
    for x in &mut nodes {
        let b = mobius(ball(*x), pole);
        *x = std::array::from_fn(|k| {
            if k + 1 < d {
                radius * b[k]
            } else if k + 1 == d {
                radius * (b[k] + 1.0)
            } else {
                0.0
            }
        });
    }
    Ok(Mesh {
        origin: format!(
            "{} generator (mesh.elements = {n}, mesh.grading = {grading_ratio})",
            if d == 2 { "disc" } else { "sphere" }
        ),
        element,
        nodes,
        connectivity,
        h: radius * 2.0 / n as f64 / root,
        contact_faces: None,
        tags: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::reference::Shape;
    use crate::mesh::{ContactRule, FACING};

    /// Every family: valid cells, the volume of the disc/ball (P1: inscribed polygon, O(h²);
    /// P2/Q2: curved cells, O(h³) and better), boundary nodes on the circle/sphere, the pole a
    /// Γ_C vertex at distance 0 from the plane, and the pole spacing h as stated.
    #[test]
    fn disc_and_ball_have_the_right_volume_and_a_pole_on_the_plane() {
        for dim in [2, 3] {
            for shape in [Shape::Tensor, Shape::Simplex] {
                for degree in [1, 2] {
                    let e = RefElement { shape, dim, degree };
                    let m = round_body(e, 8, 2.0, 3.0).unwrap();
                    m.check().unwrap();
                    let exact = if dim == 2 {
                        std::f64::consts::PI * 4.0
                    } else {
                        4.0 / 3.0 * std::f64::consts::PI * 8.0
                    };
                    let rel = (m.volume() - exact).abs() / exact;
                    let tol = if degree == 1 { 0.05 } else { 2e-3 };
                    assert!(rel < tol, "{e:?}: volume error {rel:.2e}");
                    let centre = if dim == 2 { [0.0, 2.0] } else { [0.0, 0.0] };
                    for f in m.boundary_faces() {
                        for v in f.vertices {
                            let x = m.nodes[v];
                            let r: f64 = (0..dim)
                                .map(|k| (x[k] - centre.get(k).copied().unwrap_or(2.0)).powi(2))
                                .sum::<f64>()
                                .sqrt();
                            assert!((r - 2.0).abs() < 1e-12, "{e:?}: node {v} at r = {r}");
                        }
                    }
                    let faces = m.contact_faces(ContactRule::Facing(FACING)).unwrap();
                    let cv = m.tributary(&faces);
                    let lowest = cv
                        .iter()
                        .map(|&(i, _)| m.nodes[i][dim - 1])
                        .fold(f64::INFINITY, f64::min);
                    assert!(lowest.abs() < 1e-14, "{e:?}: pole at {lowest}");
                    // Γ_C is the lower half: its measure is about half the boundary's.
                    let gc: f64 = cv.iter().map(|v| v.1).sum();
                    let all: f64 = m.boundary_faces().iter().map(|f| f.measure).sum();
                    assert!((gc / all - 0.5).abs() < 0.1, "{e:?}: {gc} / {all}");
                }
            }
        }
    }

    /// The grading refines the pole: spacing there is `h`, and r times larger at the top.
    #[test]
    fn grading_refines_towards_the_pole() {
        let e = RefElement {
            shape: Shape::Tensor,
            dim: 2,
            degree: 1,
        };
        let (n, r) = (16, 4.0);
        let m = round_body(e, n, 1.0, r).unwrap();
        let pole = (0..m.nodes.len())
            .min_by(|&a, &b| m.nodes[a][1].total_cmp(&m.nodes[b][1]))
            .unwrap();
        // The nearest other node on the boundary (y below the pole's neighbours' height).
        let dx = m
            .nodes
            .iter()
            .filter(|x| x[0] > 0.0 && x[1] < 0.1 * m.h)
            .map(|x| x[0])
            .fold(f64::INFINITY, f64::min)
            - m.nodes[pole][0];
        assert!((dx - m.h).abs() < 0.05 * m.h, "{dx} vs {}", m.h);
        let uniform = round_body(e, n, 1.0, 1.0).unwrap();
        assert!(
            (m.h - 0.5 * uniform.h).abs() < 1e-15,
            "{} vs {}",
            m.h,
            uniform.h
        );
    }

    /// A count and grading whose own cells fold (hex Q1, n = 2 at 25: oblique3d's
    /// `--elements 2`, which said only "cell 28 … is inverted") are refused naming
    /// mesh.elements, mesh.grading, the largest grading at this count (21.3, the mesh at it
    /// valid) and the next count at this grading (3); an error of a mesh that holds is
    /// returned as it is.
    #[test]
    fn a_folding_count_and_grading_are_refused_with_the_range_of_each() {
        let element = RefElement {
            shape: Shape::Tensor,
            dim: 3,
            degree: 1,
        };
        let body = RoundBody {
            element,
            n: 2,
            grading: 25.0,
        };
        let check = body.mesh(1.0).unwrap().check().unwrap_err();
        let e = body.explain(check).to_string();
        for needle in [
            "`mesh.elements`: 2",
            "sphere generator's own cells fold at mesh.grading = 25",
            "at mesh.elements = 2 mesh.grading must lie in [1, 21.3]",
            "next count that holds is mesh.elements = 3",
            "cell 28",
        ] {
            assert!(e.contains(needle), "{needle}: {e}");
        }
        assert!(round_body(element, 2, 1.0, 21.3).unwrap().check().is_ok());
        assert!(round_body(element, 3, 1.0, 25.0).unwrap().check().is_ok());
        let holds = RoundBody { n: 3, ..body };
        let other = Error::Internal("another failure".into());
        assert!(matches!(holds.explain(other), Error::Internal(_)));
    }
}
