//! Continuous Lagrange space P_p on a 1D interval mesh, with optional Dirichlet dofs eliminated.

use crate::element::segment::Segment;
use crate::error::Result;
use crate::fem::assembly::assemble;
use crate::linalg::SpMat;
use crate::mesh::interval::IntervalMesh;
use nalgebra::DMatrix;

/// P_p on `mesh`: global node `p·e + k` is local node k of element e (left-to-right numbering).
/// Nodes listed in `fixed` (u = 0 there) are eliminated; the others are renumbered in order.
#[derive(Debug, Clone)]
pub struct Lagrange1d {
    /// The mesh.
    pub mesh: IntervalMesh,
    /// The reference element.
    pub element: Segment,
    /// Global node → reduced dof (None: eliminated Dirichlet node).
    pub dof_of_node: Vec<Option<usize>>,
    /// Number of free dofs.
    pub n_dofs: usize,
}

impl Lagrange1d {
    /// The space of degree `degree` with the nodes at the positions `fixed_x` clamped.
    pub fn new(mesh: IntervalMesh, degree: usize, fixed_x: &[f64]) -> Self {
        let element = Segment { degree };
        let n_nodes = mesh.n_elements * degree + 1;
        let h_node = mesh.h() / degree as f64;
        let mut next = 0;
        let dof_of_node = (0..n_nodes)
            .map(|i| {
                let x = i as f64 * h_node;
                if fixed_x.iter().any(|&f| (f - x).abs() < 1e-9 * mesh.length) {
                    None
                } else {
                    next += 1;
                    Some(next - 1)
                }
            })
            .collect();
        Self {
            mesh,
            element,
            dof_of_node,
            n_dofs: next,
        }
    }

    /// Number of nodes including eliminated ones.
    pub fn n_nodes(&self) -> usize {
        self.dof_of_node.len()
    }

    /// Coordinate of global node `i`.
    pub fn node_x(&self, i: usize) -> f64 {
        i as f64 * self.mesh.h() / self.element.degree as f64
    }

    /// Global node numbers of element `e`.
    pub fn element_nodes(&self, e: usize) -> std::ops::Range<usize> {
        let p = self.element.degree;
        p * e..p * e + p + 1
    }

    /// Reduced dofs of element `e` (None for eliminated nodes).
    pub fn element_dofs(&self, e: usize) -> Vec<Option<usize>> {
        self.element_nodes(e).map(|i| self.dof_of_node[i]).collect()
    }

    /// Assembles `Σ_K local(K)` with rows and columns in this space.
    pub fn assemble(&self, local: impl Fn(usize) -> DMatrix<f64>) -> Result<SpMat> {
        let mats: Vec<DMatrix<f64>> = (0..self.mesh.n_elements).map(&local).collect();
        assemble(
            self.n_dofs,
            self.n_dofs,
            mats.iter()
                .enumerate()
                .map(|(e, m)| (self.element_dofs(e), self.element_dofs(e), m)),
        )
    }

    /// Value of the free-dof vector `u` at node `i` (0 at eliminated nodes).
    pub fn nodal(&self, u: &[f64], i: usize) -> f64 {
        self.dof_of_node[i].map_or(0.0, |d| u[d])
    }

    /// `(u_h(x), u_h'(x))` in element `e` at reference coordinate ξ.
    pub fn eval_in(&self, u: &[f64], e: usize, xi: f64) -> (f64, f64) {
        let h = self.mesh.h();
        self.element_nodes(e)
            .enumerate()
            .fold((0.0, 0.0), |(v, d), (k, i)| {
                let ui = self.nodal(u, i);
                (
                    v + ui * self.element.value(k, xi),
                    d + ui * self.element.derivative(k, xi) / h,
                )
            })
    }
}
