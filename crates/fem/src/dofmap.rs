//! Node × component numbering of unknowns.

/// Interleaved dof numbering: dof = node · n_components + component.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DofMap {
    n_nodes: usize,
    n_components: usize,
}

impl DofMap {
    /// `n_components` unknowns per node (1 for temperature, 2 for plane displacement).
    pub const fn new(n_nodes: usize, n_components: usize) -> Self {
        DofMap {
            n_nodes,
            n_components,
        }
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.n_nodes
    }

    /// Unknowns per node.
    pub fn n_components(&self) -> usize {
        self.n_components
    }

    /// Total number of dofs.
    pub fn n_dofs(&self) -> usize {
        self.n_nodes * self.n_components
    }

    /// Dof of `component` at `node`.
    #[inline]
    pub fn dof(&self, node: usize, component: usize) -> usize {
        node * self.n_components + component
    }

    /// (node, component) of a dof.
    #[inline]
    pub fn node_component(&self, dof: usize) -> (usize, usize) {
        (dof / self.n_components, dof % self.n_components)
    }

    /// All dofs of the nodes of an element, node by node.
    #[inline]
    pub fn element_dofs<const K: usize, const N: usize>(&self, nodes: [usize; K]) -> [usize; N] {
        let mut out = [0; N];
        let c = self.n_components;
        for (a, &n) in nodes.iter().enumerate() {
            for k in 0..c {
                if a * c + k < N {
                    out[a * c + k] = n * c + k;
                }
            }
        }
        out
    }
}
