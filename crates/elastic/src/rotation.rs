//! Local nodal frames for symmetry on inclined edges.
//!
//! A rotated node i with unit normal n = (c, s) has local unknowns
//! u' = (u_n, u_t) with u = R u', R = [[c, −s], [s, c]]. The system becomes
//! Tᵀ K T u' = Tᵀ f; u_n = 0 is then an ordinary Dirichlet constraint. The
//! transformation acts on values in place and keeps the pattern.

use std::collections::{BTreeMap, BTreeSet};

use tecon_fem::{CsrMatrix, SparsityPattern};

#[derive(Debug, Clone)]
struct RotatedNode {
    node: usize,
    c: f64,
    s: f64,
    /// Slots of row 2i (row 2i+1 has the same columns at +offset).
    row0: std::ops::Range<usize>,
    row1_start: usize,
    /// Slots (j, 2i) for every row j coupled to the node (slot + 1 is (j, 2i+1)).
    col: Vec<usize>,
}

/// The rotated nodes of a model and their slots in the pattern.
#[derive(Debug, Clone, Default)]
pub(crate) struct Rotations {
    nodes: Vec<RotatedNode>,
    set: BTreeSet<usize>,
}

impl Rotations {
    pub(crate) fn new(rotated: &[(usize, [f64; 2])], pattern: &SparsityPattern) -> Self {
        let (ip, ix) = (pattern.indptr(), pattern.indices());
        let mut nodes = Vec::new();
        let mut set = BTreeSet::new();
        for &(node, n) in rotated {
            if !set.insert(node) {
                continue;
            }
            let r0 = 2 * node;
            let row0 = ip[r0]..ip[r0 + 1];
            let col = ix[row0.clone()]
                .iter()
                .filter_map(|&j| pattern.slot(j, r0))
                .collect();
            nodes.push(RotatedNode {
                node,
                c: n[0],
                s: n[1],
                row0,
                row1_start: ip[r0 + 1],
                col,
            });
        }
        Rotations { nodes, set }
    }

    pub(crate) fn contains(&self, node: usize) -> bool {
        self.set.contains(&node)
    }

    /// Calls `f` with every range of value slots that
    /// [`Rotations::rotate_matrix`] changes: the rotated nodes' rows and
    /// their columns' entries in other rows.
    pub(crate) fn for_each_touched(&self, mut f: impl FnMut(std::ops::Range<usize>)) {
        for r in &self.nodes {
            f(r.row0.clone());
            f(r.row1_start..r.row1_start + r.row0.len());
            for &s0 in &r.col {
                f(s0..s0 + 2);
            }
        }
    }

    /// K ← Tᵀ K T.
    pub(crate) fn rotate_matrix(&self, k: &mut CsrMatrix) {
        let v = k.values_mut();
        for r in &self.nodes {
            for (q, s0) in r.row0.clone().enumerate() {
                let s1 = r.row1_start + q;
                let (a, b) = (v[s0], v[s1]);
                v[s0] = r.c * a + r.s * b;
                v[s1] = -r.s * a + r.c * b;
            }
        }
        for r in &self.nodes {
            for &s0 in &r.col {
                let (a, b) = (v[s0], v[s0 + 1]);
                v[s0] = a * r.c + b * r.s;
                v[s0 + 1] = -a * r.s + b * r.c;
            }
        }
    }

    /// f ← Tᵀ f.
    pub(crate) fn rotate_vector(&self, f: &mut [f64]) {
        for r in &self.nodes {
            let (a, b) = (f[2 * r.node], f[2 * r.node + 1]);
            f[2 * r.node] = r.c * a + r.s * b;
            f[2 * r.node + 1] = -r.s * a + r.c * b;
        }
    }

    /// u ← T u'.
    pub(crate) fn unrotate_vector(&self, u: &mut [f64]) {
        for r in &self.nodes {
            let (a, b) = (u[2 * r.node], u[2 * r.node + 1]);
            u[2 * r.node] = r.c * a - r.s * b;
            u[2 * r.node + 1] = r.s * a + r.c * b;
        }
    }

    /// A sparse vector (dof, value) expressed in the rotated frame.
    pub(crate) fn rotate_sparse(&self, entries: &mut Vec<(usize, f64)>) {
        if self.nodes.is_empty() {
            return;
        }
        let mut map: BTreeMap<usize, f64> = entries.iter().copied().collect();
        for r in &self.nodes {
            let (a, b) = (
                map.get(&(2 * r.node)).copied().unwrap_or(0.0),
                map.get(&(2 * r.node + 1)).copied().unwrap_or(0.0),
            );
            if a != 0.0 || b != 0.0 {
                map.insert(2 * r.node, r.c * a + r.s * b);
                map.insert(2 * r.node + 1, -r.s * a + r.c * b);
            }
        }
        *entries = map.into_iter().collect();
    }
}
