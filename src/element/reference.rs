//! Reference Lagrange elements in 1D, 2D and 3D (the geometry is isoparametric: see
//! [`super::geometry::jacobian`]):
//! - tensor elements Q1/Q2 on [0, 1]^d, local nodes in lexicographic order (x fastest) on the
//!   (p + 1)^d grid of equispaced points; in 1D the segment P1/P2 ([`RefElement::segment`],
//!   local nodes left to right as in [`super::segment::Segment`]);
//! - simplices P1/P2 (triangles, tetrahedra) on {ξ ≥ 0, Σ ξ_k ≤ 1}: the vertices 0 and e_k, then
//!   for P2 the edge midpoints in [`EDGES_2D`] / [`EDGES_3D`] order.
//!
//! Quadrature: tensor Gauss–Legendre with p + 2 points per direction; simplices through the
//! collapsed (Duffy) map of a tensor rule, exact for the polynomial degrees used here.

use super::quadrature::gauss_legendre_01;

/// Cell shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// Simplex: triangle (d = 2) or tetrahedron (d = 3).
    Simplex,
    /// Quadrilateral (d = 2) or hexahedron (d = 3).
    Tensor,
}

/// A reference element: shape, spatial dimension and polynomial degree (1 or 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RefElement {
    /// Shape.
    pub shape: Shape,
    /// Spatial dimension (1, 2 or 3; the segment is the tensor element of dimension 1).
    pub dim: usize,
    /// Degree.
    pub degree: usize,
}

/// A reference element's basis at a list of points: its quadrature points
/// ([`RefElement::tabulate`], what the element integrals expect) or any
/// ([`RefElement::tabulate_at`]).
#[derive(Debug, Clone)]
pub struct Tabulation {
    /// The element.
    pub element: RefElement,
    /// The points, in the order given ([`RefElement::quadrature`]'s for `tabulate`).
    pub points: Vec<TabulatedPoint>,
}

/// One point: its weight, and the values and reference gradients of every basis
/// function there ([`RefElement::eval`]).
#[derive(Debug, Clone)]
pub struct TabulatedPoint {
    /// Weight.
    pub weight: f64,
    /// `φ_a(ξ)`.
    pub values: Vec<f64>,
    /// `∇̂φ_a(ξ)`.
    pub gradients: Vec<[f64; 3]>,
    /// `ψ_i(ξ)`: the degree-1 basis of the same shape ([`RefElement::linear`]).
    pub linear: Vec<f64>,
}

/// The unit square's corners in counter-clockwise order.
const SQUARE: [[usize; 2]; 4] = [[0, 0], [1, 0], [1, 1], [0, 1]];
/// Edges of the triangle (P2 midpoint order).
pub const EDGES_2D: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];
/// Edges of the tetrahedron (P2 midpoint order).
pub const EDGES_3D: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// 1D Lagrange basis of degree 1 or 2 on [0, 1] at equispaced nodes: (value, derivative).
fn lagrange_1d(degree: usize, i: usize, x: f64) -> (f64, f64) {
    match (degree, i) {
        (1, 0) => (1.0 - x, -1.0),
        (1, _) => (x, 1.0),
        (_, 0) => (2.0 * (x - 0.5) * (x - 1.0), 4.0 * x - 3.0),
        (_, 1) => (4.0 * x * (1.0 - x), 4.0 - 8.0 * x),
        _ => (2.0 * x * (x - 0.5), 4.0 * x - 1.0),
    }
}

impl RefElement {
    /// The segment of degree `degree` (1 or 2): the tensor element of dimension 1.
    pub fn segment(degree: usize) -> Self {
        Self {
            shape: Shape::Tensor,
            dim: 1,
            degree,
        }
    }

    /// The cell shape's name as `--cells` and the records write it: `segment`, `triangle`,
    /// `quad`, `tet`, `hex`.
    pub fn cells(&self) -> &'static str {
        match (self.shape, self.dim) {
            (_, 1) => "segment",
            (Shape::Simplex, 2) => "triangle",
            (Shape::Tensor, 2) => "quad",
            (Shape::Simplex, _) => "tet",
            (Shape::Tensor, _) => "hex",
        }
    }

    /// Number of local nodes.
    pub fn n_nodes(&self) -> usize {
        match self.shape {
            Shape::Simplex => {
                let v = self.dim + 1;
                if self.degree == 1 {
                    v
                } else {
                    v + self.edges().len()
                }
            }
            Shape::Tensor => (self.degree + 1).pow(self.dim as u32),
        }
    }

    /// Tensor index (i, j, k) of local node `a`.
    fn tensor_index(&self, a: usize) -> [usize; 3] {
        let p = self.degree + 1;
        [a % p, (a / p) % p, a / (p * p)]
    }

    /// Reference coordinates of local node `a`.
    pub fn node(&self, a: usize) -> [f64; 3] {
        match self.shape {
            Shape::Tensor => {
                let ix = self.tensor_index(a);
                let p = self.degree as f64;
                let c = |k: usize| if k < self.dim { ix[k] as f64 / p } else { 0.0 };
                [c(0), c(1), c(2)]
            }
            Shape::Simplex => {
                let vertex = |v: usize| std::array::from_fn(|k| f64::from(v > 0 && k + 1 == v));
                if a <= self.dim {
                    vertex(a)
                } else {
                    let (p, q) = self.edges()[a - self.dim - 1];
                    let (x, y): ([f64; 3], [f64; 3]) = (vertex(p), vertex(q));
                    std::array::from_fn(|k| 0.5 * (x[k] + y[k]))
                }
            }
        }
    }

    /// Reference coordinates of the cell's centroid.
    pub fn centre(&self) -> [f64; 3] {
        let c = match self.shape {
            Shape::Tensor => 0.5,
            Shape::Simplex => 1.0 / (self.dim + 1) as f64,
        };
        std::array::from_fn(|k| if k < self.dim { c } else { 0.0 })
    }

    /// True when local node `a` is a vertex of the cell.
    pub fn is_vertex(&self, a: usize) -> bool {
        match self.shape {
            Shape::Simplex => a <= self.dim,
            Shape::Tensor => self.tensor_index(a)[..self.dim]
                .iter()
                .all(|&i| i == 0 || i == self.degree),
        }
    }

    /// Values and reference gradients of every basis function at ξ.
    pub fn eval(&self, xi: [f64; 3]) -> (Vec<f64>, Vec<[f64; 3]>) {
        let n = self.n_nodes();
        let mut v = vec![0.0; n];
        let mut g = vec![[0.0; 3]; n];
        match self.shape {
            Shape::Tensor => {
                for a in 0..n {
                    let ix = self.tensor_index(a);
                    let f: [(f64, f64); 3] =
                        std::array::from_fn(|k| lagrange_1d(self.degree, ix[k], xi[k]));
                    let f = &f[..self.dim];
                    v[a] = f.iter().map(|x| x.0).product();
                    for (k, gk) in g[a].iter_mut().enumerate().take(self.dim) {
                        *gk = (0..self.dim)
                            .map(|l| if l == k { f[l].1 } else { f[l].0 })
                            .product();
                    }
                }
            }
            Shape::Simplex => {
                let d = self.dim;
                let mut l = [0.0; 4];
                let mut dl = [[0.0; 3]; 4];
                l[0] = 1.0 - xi[..d].iter().sum::<f64>();
                for k in 0..d {
                    l[k + 1] = xi[k];
                    dl[0][k] = -1.0;
                    dl[k + 1][k] = 1.0;
                }
                for a in 0..=d {
                    let s = if self.degree == 1 {
                        1.0
                    } else {
                        4.0 * l[a] - 1.0
                    };
                    v[a] = if self.degree == 1 {
                        l[a]
                    } else {
                        l[a] * (2.0 * l[a] - 1.0)
                    };
                    g[a] = std::array::from_fn(|k| s * dl[a][k]);
                }
                if self.degree == 2 {
                    for (m, &(p, q)) in self.edges().iter().enumerate() {
                        v[d + 1 + m] = 4.0 * l[p] * l[q];
                        g[d + 1 + m] =
                            std::array::from_fn(|k| 4.0 * (dl[p][k] * l[q] + l[p] * dl[q][k]));
                    }
                }
            }
        }
        (v, g)
    }

    /// The basis at every quadrature point, computed once for all the cells of a mesh.
    pub fn tabulate(&self) -> Tabulation {
        self.tabulate_at(self.quadrature())
    }

    /// The basis at the points `(ξ, weight)`.
    pub fn tabulate_at(&self, points: Vec<([f64; 3], f64)>) -> Tabulation {
        let (linear, _) = self.linear();
        let points = (points.into_iter())
            .map(|(xi, weight)| {
                let (values, gradients) = self.eval(xi);
                TabulatedPoint {
                    weight,
                    values,
                    gradients,
                    linear: linear.eval(xi).0,
                }
            })
            .collect();
        Tabulation {
            element: *self,
            points,
        }
    }

    /// Quadrature points and weights on the reference cell (weights sum to its measure).
    pub fn quadrature(&self) -> Vec<([f64; 3], f64)> {
        let rule = gauss_legendre_01(self.degree + 2);
        match self.shape {
            Shape::Tensor if self.dim == 1 => {
                rule.iter().map(|&(x, w)| ([x, 0.0, 0.0], w)).collect()
            }
            Shape::Tensor => {
                let mut out = Vec::new();
                let kmax = if self.dim == 3 { rule.len() } else { 1 };
                for k in 0..kmax {
                    for &(y, wy) in &rule {
                        for &(x, wx) in &rule {
                            let (z, wz) = if self.dim == 3 { rule[k] } else { (0.0, 1.0) };
                            out.push(([x, y, z], wx * wy * wz));
                        }
                    }
                }
                out
            }
            Shape::Simplex => {
                // (u, v, w) ∈ [0,1]^d ↦ (u, v(1 − u), w(1 − u)(1 − v)), Jacobian
                // (1 − u)^{d−1} (1 − v)^{d−2}.
                let mut out = Vec::new();
                let wmax = if self.dim == 3 { rule.len() } else { 1 };
                for &(u, wu) in &rule {
                    for &(v, wv) in &rule {
                        for &(w, ww) in rule.iter().take(wmax) {
                            if self.dim == 2 {
                                out.push(([u, v * (1.0 - u), 0.0], wu * wv * (1.0 - u)));
                            } else {
                                let (a, b) = (1.0 - u, 1.0 - v);
                                out.push(([u, v * a, w * a * b], wu * wv * ww * a * a * b));
                            }
                        }
                    }
                }
                out
            }
        }
    }

    /// Local index of the tensor corner with bits `c` (0 or 1 per direction).
    fn corner(&self, c: [usize; 3]) -> usize {
        let (p, q) = (self.degree, self.degree + 1);
        c[0] * p + q * (c[1] * p + q * c[2] * p)
    }

    /// Local indices of the cell's vertices (simplex: 0..=d; tensor: corners, x fastest).
    pub fn vertices(&self) -> Vec<usize> {
        match self.shape {
            Shape::Simplex => (0..=self.dim).collect(),
            Shape::Tensor => (0..1 << self.dim)
                .map(|b: usize| self.corner([b & 1, (b >> 1) & 1, (b >> 2) & 1]))
                .collect(),
        }
    }

    /// Local indices of the vertices in the conventional order of Gmsh and VTK: a simplex's
    /// 0..=d; a segment's left to right; a quadrilateral's counter-clockwise; a hexahedron's
    /// bottom face counter-clockwise, then its top face.
    pub fn cyclic_vertices(&self) -> Vec<usize> {
        match self.shape {
            Shape::Simplex => (0..=self.dim).collect(),
            Shape::Tensor if self.dim == 1 => self.vertices(),
            Shape::Tensor => (0..self.dim - 1)
                .flat_map(|z| SQUARE.iter().map(move |&[x, y]| self.corner([x, y, z])))
                .collect(),
        }
    }

    /// The faces (edges in 2D, end points in 1D) as local vertex indices, quadrilaterals in
    /// cyclic order.
    pub fn faces(&self) -> Vec<Vec<usize>> {
        match (self.shape, self.dim) {
            (_, 1) => self.vertices().into_iter().map(|a| vec![a]).collect(),
            (Shape::Simplex, 2) => vec![vec![0, 1], vec![1, 2], vec![2, 0]],
            (Shape::Simplex, _) => vec![vec![1, 2, 3], vec![0, 2, 3], vec![0, 1, 3], vec![0, 1, 2]],
            (Shape::Tensor, d) => {
                let cyc: &[[usize; 2]] = if d == 2 { &SQUARE[..2] } else { &SQUARE };
                let mut out = Vec::new();
                for axis in 0..d {
                    for side in 0..2 {
                        let free: Vec<usize> = (0..d).filter(|&k| k != axis).collect();
                        out.push(
                            cyc.iter()
                                .map(|uv| {
                                    let mut c = [0; 3];
                                    c[axis] = side;
                                    for (f, &k) in free.iter().enumerate() {
                                        c[k] = uv[f];
                                    }
                                    self.corner(c)
                                })
                                .collect(),
                        );
                    }
                }
                out
            }
        }
    }

    /// The edges of a simplex (P2 midpoint order).
    pub fn edges(&self) -> &'static [(usize, usize)] {
        if self.dim == 2 {
            &EDGES_2D
        } else {
            &EDGES_3D
        }
    }

    /// Every element family: P1/P2 triangles and tetrahedra, Q1/Q2 quadrilaterals and hexahedra.
    pub fn every() -> Vec<RefElement> {
        let mut v = Vec::new();
        for degree in [1, 2] {
            for shape in [Shape::Simplex, Shape::Tensor] {
                for dim in [2, 3] {
                    v.push(RefElement { shape, dim, degree });
                }
            }
        }
        v
    }

    /// The element of degree 1 on the same shape (the velocity space of the singular dynamic
    /// method), with the local index in `self` of each of its nodes (the vertices).
    pub fn linear(&self) -> (RefElement, Vec<usize>) {
        let lin = RefElement { degree: 1, ..*self };
        let map = (0..lin.n_nodes())
            .map(|b| {
                let x = lin.node(b);
                (0..self.n_nodes())
                    .find(|&a| self.node(a) == x)
                    .expect("every vertex is a node")
            })
            .collect();
        (lin, map)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_nodal_and_a_partition_of_unity() {
        for e in RefElement::every() {
            for a in 0..e.n_nodes() {
                let (v, g) = e.eval(e.node(a));
                for (b, vb) in v.iter().enumerate() {
                    assert!((vb - f64::from(a == b)).abs() < 1e-14, "{e:?} a={a} b={b}");
                }
                let gs: [f64; 3] = std::array::from_fn(|k| g.iter().map(|x| x[k]).sum());
                assert!(gs.iter().all(|x| x.abs() < 1e-13), "{e:?}: Σ∇φ = {gs:?}");
            }
        }
    }

    /// The segment is the 1D tensor element: nodes left to right, basis nodal, quadrature exact
    /// for x², its faces the two end points.
    #[test]
    fn the_segment_is_the_one_dimensional_tensor_element() {
        for degree in [1, 2] {
            let e = RefElement::segment(degree);
            let x: Vec<f64> = (0..e.n_nodes()).map(|a| e.node(a)[0]).collect();
            let want: Vec<f64> = (0..=degree).map(|k| k as f64 / degree as f64).collect();
            assert_eq!(x, want);
            for a in 0..e.n_nodes() {
                let (v, g) = e.eval(e.node(a));
                for (b, vb) in v.iter().enumerate() {
                    assert!((vb - f64::from(a == b)).abs() < 1e-14);
                }
                assert!(g.iter().map(|x| x[0]).sum::<f64>().abs() < 1e-13);
            }
            let q = e.quadrature();
            assert!((q.iter().map(|p| p.1).sum::<f64>() - 1.0).abs() < 1e-15);
            let x2: f64 = q.iter().map(|p| p.1 * p.0[0] * p.0[0]).sum();
            assert!((x2 - 1.0 / 3.0).abs() < 1e-15);
            assert_eq!(e.vertices(), vec![0, degree]);
            assert_eq!(e.faces(), vec![vec![0], vec![degree]]);
        }
    }

    #[test]
    fn quadrature_integrates_the_measure_and_quadratics() {
        for e in RefElement::every() {
            let q = e.quadrature();
            let area: f64 = q.iter().map(|p| p.1).sum();
            let simplex = e.shape == Shape::Simplex;
            let want = match (simplex, e.dim) {
                (false, _) => 1.0,
                (true, 2) => 0.5,
                _ => 1.0 / 6.0,
            };
            assert!((area - want).abs() < 1e-14);
            // ∫ x² over the cell: 1/12 (triangle), 1/60 (tetrahedron), 1/3 (box).
            let x2: f64 = q.iter().map(|p| p.1 * p.0[0] * p.0[0]).sum();
            let want = match (simplex, e.dim) {
                (false, _) => 1.0 / 3.0,
                (true, 2) => 1.0 / 12.0,
                _ => 1.0 / 60.0,
            };
            assert!((x2 - want).abs() < 1e-14);
        }
    }
}
