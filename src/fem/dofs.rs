//! The numbering of a discretisation's degrees of freedom.

/// The dof map `(node i, component c) ↦ i·d + c`, renumbered without the fixed (clamped) nodes.
#[derive(Debug, Clone)]
pub struct DofMap {
    d: usize,
    of: Vec<Option<usize>>,
    n: usize,
}

impl DofMap {
    /// Every component of the nodes where `fixed` is true eliminated, the others numbered in
    /// order.
    pub fn new(d: usize, fixed: &[bool]) -> Self {
        let mut n = 0;
        let of = fixed
            .iter()
            .flat_map(|&f| std::iter::repeat_n(f, d))
            .map(|f| {
                (!f).then(|| {
                    n += 1;
                    n - 1
                })
            })
            .collect();
        Self { d, of, n }
    }

    /// Every component of `nodes` nodes free: dof `(i, c)` is `i·d + c`.
    pub fn free(nodes: usize, d: usize) -> Self {
        Self::new(d, &vec![false; nodes])
    }

    /// The dof of node i, component c (None: fixed).
    pub fn get(&self, i: usize, c: usize) -> Option<usize> {
        self.of[i * self.d + c]
    }

    /// Number of free dofs.
    pub fn len(&self) -> usize {
        self.n
    }

    /// True when every node is fixed.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }
}
