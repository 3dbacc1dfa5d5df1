//! Reference Lagrange elements in 2D and 3D, with affine geometry (the structured meshes have
//! parallelogram/box cells and straight triangles, so the Jacobian is constant on a cell):
//! - tensor elements Q1/Q2 on [0, 1]^d, local nodes in lexicographic order (x fastest) on the
//!   (p + 1)^d grid of equispaced points;
//! - triangles P1/P2 on {ξ, η ≥ 0, ξ + η ≤ 1}: vertices (0,0), (1,0), (0,1), then for P2 the edge
//!   midpoints of edges 01, 12, 20.
//!
//! Quadrature: tensor Gauss–Legendre with p + 2 points per direction; triangles through the
//! collapsed (Duffy) map of a tensor rule, exact for the polynomial degrees used here.

use super::quadrature::gauss_legendre_01;

/// Cell shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// Triangle (2D simplex).
    Triangle,
    /// Quadrilateral (d = 2) or hexahedron (d = 3).
    Tensor,
}

/// A reference element: shape, spatial dimension and polynomial degree (1 or 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RefElement {
    /// Shape.
    pub shape: Shape,
    /// Spatial dimension (2 or 3; triangles only in 2D).
    pub dim: usize,
    /// Degree.
    pub degree: usize,
}

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
    /// Number of local nodes.
    pub fn n_nodes(&self) -> usize {
        match self.shape {
            Shape::Triangle => (self.degree + 1) * (self.degree + 2) / 2,
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
            Shape::Triangle => [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.5, 0.0, 0.0],
                [0.5, 0.5, 0.0],
                [0.0, 0.5, 0.0],
            ][a],
        }
    }

    /// True when local node `a` is a vertex of the cell.
    pub fn is_vertex(&self, a: usize) -> bool {
        match self.shape {
            Shape::Triangle => a < 3,
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
                    let f: Vec<(f64, f64)> = (0..self.dim)
                        .map(|k| lagrange_1d(self.degree, ix[k], xi[k]))
                        .collect();
                    v[a] = f.iter().map(|x| x.0).product();
                    for (k, gk) in g[a].iter_mut().enumerate().take(self.dim) {
                        *gk = (0..self.dim)
                            .map(|l| if l == k { f[l].1 } else { f[l].0 })
                            .product();
                    }
                }
            }
            Shape::Triangle => {
                let (x, y) = (xi[0], xi[1]);
                let l = [1.0 - x - y, x, y];
                let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
                for a in 0..3 {
                    if self.degree == 1 {
                        v[a] = l[a];
                        g[a] = [dl[a][0], dl[a][1], 0.0];
                    } else {
                        v[a] = l[a] * (2.0 * l[a] - 1.0);
                        let s = 4.0 * l[a] - 1.0;
                        g[a] = [s * dl[a][0], s * dl[a][1], 0.0];
                    }
                }
                if self.degree == 2 {
                    for (m, (p, q)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                        v[3 + m] = 4.0 * l[p] * l[q];
                        for k in 0..2 {
                            g[3 + m][k] = 4.0 * (dl[p][k] * l[q] + l[p] * dl[q][k]);
                        }
                    }
                }
            }
        }
        (v, g)
    }

    /// Quadrature points and weights on the reference cell (weights sum to its measure).
    pub fn quadrature(&self) -> Vec<([f64; 3], f64)> {
        let rule = gauss_legendre_01(self.degree + 2);
        match self.shape {
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
            Shape::Triangle => {
                // (u, v) ∈ [0,1]² ↦ (u, v (1 − u)), Jacobian 1 − u.
                let mut out = Vec::new();
                for &(u, wu) in &rule {
                    for &(s, ws) in &rule {
                        out.push(([u, s * (1.0 - u), 0.0], wu * ws * (1.0 - u)));
                    }
                }
                out
            }
        }
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

    fn elements() -> Vec<RefElement> {
        let mut v = Vec::new();
        for degree in [1, 2] {
            v.push(RefElement {
                shape: Shape::Triangle,
                dim: 2,
                degree,
            });
            v.push(RefElement {
                shape: Shape::Tensor,
                dim: 2,
                degree,
            });
            v.push(RefElement {
                shape: Shape::Tensor,
                dim: 3,
                degree,
            });
        }
        v
    }

    #[test]
    fn basis_is_nodal_and_a_partition_of_unity() {
        for e in elements() {
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

    #[test]
    fn quadrature_integrates_the_measure_and_quadratics() {
        for e in elements() {
            let q = e.quadrature();
            let area: f64 = q.iter().map(|p| p.1).sum();
            let want = if e.shape == Shape::Triangle { 0.5 } else { 1.0 };
            assert!((area - want).abs() < 1e-14);
            // ∫ x² over the cell: 1/12 (triangle), 1/3 (box).
            let x2: f64 = q.iter().map(|p| p.1 * p.0[0] * p.0[0]).sum();
            let want = if e.shape == Shape::Triangle {
                1.0 / 12.0
            } else {
                1.0 / 3.0
            };
            assert!((x2 - want).abs() < 1e-14);
        }
    }
}
