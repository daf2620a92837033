//! A nested-dissection elimination order for the sparse Cholesky factor.
//!
//! [`nested_dissection`] is George's automatic nested dissection on the
//! node graph of a pattern (the dofs of a node stay together):
//!
//! * a connected part is split by one level of its breadth-first level
//!   structure, rooted at a pseudo-peripheral node: of the levels with 30 %
//!   of the part or more on either side, the one with the fewest nodes
//!   that touch the next level; its other nodes join the first side;
//! * the two sides are ordered recursively, the separator after them;
//! * parts of at most [`LEAF`] nodes are ordered by approximate minimum
//!   degree (faer's AMD on the graph they induce); the components of a
//!   disconnected part are ordered one after the other.
//!
//! On the large vessel meshes this factor holds fewer entries than AMD's
//! (the thermal system of 506 198 nodes of 6-node triangles: 34.2 million
//! against 48.8 million); on small meshes or thin strips AMD does better,
//! so [`crate::CholeskySolver`] keeps whichever of the two is smaller.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::amd;

use crate::error::FemError;
use crate::pattern::SparsityPattern;

/// Parts of at most this many nodes are ordered by AMD.
pub const LEAF: usize = 256;

/// The separator is the smallest level with at least this fraction of the
/// part on either side of it. Measured (factor entries against the middle
/// level's): `t1e5` heat conduction 2.53 M against 2.65 M, elasticity
/// 9.10 M against 9.59 M; 0.1 and 0.3 did less.
const BALANCE: f64 = 0.3;

/// Breadth-first searches from a candidate root while its eccentricity grows.
const ROOT_SEARCHES: usize = 4;

/// The node graph of a pattern (CSR, no self loops).
struct Graph {
    ptr: Vec<usize>,
    adj: Vec<usize>,
}

impl Graph {
    fn of(pattern: &SparsityPattern, c: usize) -> Graph {
        let (indptr, indices) = (pattern.indptr(), pattern.indices());
        let nodes = pattern.n() / c;
        let mut ptr = Vec::with_capacity(nodes + 1);
        let mut adj = Vec::with_capacity(indices.len() / (c * c));
        ptr.push(0);
        for m in 0..nodes {
            let row = &indices[indptr[m * c]..indptr[m * c + 1]];
            adj.extend(row.iter().step_by(c).map(|&j| j / c).filter(|&j| j != m));
            ptr.push(adj.len());
        }
        Graph { ptr, adj }
    }

    fn n(&self) -> usize {
        self.ptr.len() - 1
    }

    fn neighbours(&self, v: usize) -> &[usize] {
        &self.adj[self.ptr[v]..self.ptr[v + 1]]
    }
}

/// Scratch of the dissection: which part a node is in, and its level.
struct Marks {
    part: Vec<u32>,
    level: Vec<u32>,
    next: u32,
}

impl Marks {
    /// A fresh tag for the nodes of `nodes`.
    fn tag(&mut self, nodes: &[usize]) -> u32 {
        self.next += 1;
        for &v in nodes {
            self.part[v] = self.next;
        }
        self.next
    }

    /// Breadth-first search from `root` within the nodes tagged `tag`:
    /// `order` gets the nodes reached, `level` their level; returns the
    /// number of levels. The reached nodes are tagged `tag` again after.
    fn levels(&mut self, g: &Graph, tag: u32, root: usize, order: &mut Vec<usize>) -> usize {
        self.next += 1;
        let seen = self.next;
        order.clear();
        order.push(root);
        self.part[root] = seen;
        self.level[root] = 0;
        let mut head = 0;
        let mut depth = 0;
        while head < order.len() {
            let v = order[head];
            head += 1;
            let l = self.level[v] + 1;
            for &w in g.neighbours(v) {
                if self.part[w] == tag {
                    self.part[w] = seen;
                    self.level[w] = l;
                    depth = depth.max(l);
                    order.push(w);
                }
            }
        }
        for &v in order.iter() {
            self.part[v] = tag;
        }
        depth as usize + 1
    }
}

enum Work {
    Split(Vec<usize>),
    Emit(Vec<usize>),
}

/// The nested-dissection elimination order of a structurally symmetric
/// `pattern`: entry k is the dof eliminated k-th. A pattern of node blocks
/// ([`SparsityPattern::block_size`]) is dissected on its nodes.
pub fn nested_dissection(pattern: &SparsityPattern) -> Result<Vec<usize>, FemError> {
    let c = node_block(pattern);
    let g = Graph::of(pattern, c);
    let n = g.n();
    let mut marks = Marks {
        part: vec![0; n],
        level: vec![0; n],
        next: 0,
    };
    let mut order = Vec::with_capacity(n);
    let mut work = vec![Work::Split((0..n).collect())];
    let (mut bfs, mut best) = (Vec::new(), Vec::new());
    while let Some(item) = work.pop() {
        let nodes = match item {
            Work::Emit(separator) => {
                order.extend(separator);
                continue;
            }
            Work::Split(nodes) => nodes,
        };
        if nodes.len() <= LEAF {
            amd_part(&g, &nodes, &mut order)?;
            continue;
        }
        let tag = marks.tag(&nodes);
        let mut depth = marks.levels(&g, tag, nodes[0], &mut bfs);
        if bfs.len() < nodes.len() {
            // a disconnected part: its components one after the other
            let mut parts = Vec::new();
            let done = marks.tag(&[]);
            for &v in &nodes {
                if marks.part[v] == tag {
                    marks.levels(&g, tag, v, &mut bfs);
                    for &u in &bfs {
                        marks.part[u] = done;
                    }
                    parts.push(std::mem::take(&mut bfs));
                }
            }
            work.extend(parts.into_iter().rev().map(Work::Split));
            continue;
        }
        // pseudo-peripheral root: from the last level, the node of least
        // degree, while the number of levels grows
        std::mem::swap(&mut bfs, &mut best);
        // whether `level` holds a rejected search's levels instead of best's
        let mut stale = false;
        for _ in 0..ROOT_SEARCHES {
            let last = (depth - 1) as u32;
            let Some(far) = best
                .iter()
                .rev()
                .take_while(|&&v| marks.level[v] == last)
                .copied()
                .min_by_key(|&v| (g.neighbours(v).len(), v))
            else {
                break;
            };
            let d = marks.levels(&g, tag, far, &mut bfs);
            if d > depth {
                depth = d;
                std::mem::swap(&mut bfs, &mut best);
            } else {
                stale = true;
                break;
            }
        }
        if stale {
            // the levels of the kept root (the first node of `best`)
            let root = best[0];
            marks.levels(&g, tag, root, &mut best);
        }
        if depth < 3 {
            amd_part(&g, &nodes, &mut order)?;
            continue;
        }
        // per level: its nodes, and those that touch the next level (the
        // separator that level would give)
        let (mut count, mut cut) = (vec![0usize; depth], vec![0usize; depth]);
        for &v in &best {
            let l = marks.level[v];
            count[l as usize] += 1;
            if g.neighbours(v)
                .iter()
                .any(|&w| marks.part[w] == tag && marks.level[w] == l + 1)
            {
                cut[l as usize] += 1;
            }
        }
        // the smallest separator among the levels (not the first or last)
        // that leave 30–70 % of the part before them, else the level where
        // half is reached
        let total = nodes.len() as f64;
        let (mut before, mut mid, mut smallest) = (0usize, None, usize::MAX);
        let mut half = None;
        for l in 0..depth {
            let f = before as f64 / total;
            if half.is_none() && before + count[l] > nodes.len() / 2 {
                half = Some(l);
            }
            if (1..depth - 1).contains(&l)
                && (BALANCE..=1.0 - BALANCE).contains(&f)
                && cut[l] < smallest
            {
                (mid, smallest) = (Some(l), cut[l]);
            }
            before += count[l];
        }
        let mid = mid.unwrap_or_else(|| half.unwrap_or(depth - 2).clamp(1, depth - 2)) as u32;
        let (mut first, mut second, mut separator) = (Vec::new(), Vec::new(), Vec::new());
        for &v in &best {
            let l = marks.level[v];
            if l < mid {
                first.push(v);
            } else if l > mid {
                second.push(v);
            } else if g
                .neighbours(v)
                .iter()
                .any(|&w| marks.part[w] == tag && marks.level[w] == mid + 1)
            {
                separator.push(v);
            } else {
                first.push(v);
            }
        }
        work.push(Work::Emit(separator));
        work.push(Work::Split(second));
        work.push(Work::Split(first));
    }
    if order.len() != n {
        return Err(FemError::Solver(format!(
            "nested dissection ordered {} of {n} nodes",
            order.len()
        )));
    }
    Ok(order
        .into_iter()
        .flat_map(|m| (0..c).map(move |k| m * c + k))
        .collect())
}

/// The node block size of `pattern`: its own, or else the first of 3 and 2
/// for which every group of c consecutive rows has one column list made of
/// whole groups (a pattern cut out of a node-blocked one, e.g. the interior
/// of a condensed system, has lost its block size but not its blocks).
fn node_block(pattern: &SparsityPattern) -> usize {
    let n = pattern.n();
    let (indptr, indices) = (pattern.indptr(), pattern.indices());
    let blocked = |c: usize| {
        n.is_multiple_of(c)
            && (0..n / c).all(|m| {
                let first = &indices[indptr[m * c]..indptr[m * c + 1]];
                first.len().is_multiple_of(c)
                    && first
                        .chunks(c)
                        .all(|g| g[0] % c == 0 && g.iter().enumerate().all(|(k, &j)| j == g[0] + k))
                    && (1..c).all(|k| &indices[indptr[m * c + k]..indptr[m * c + k + 1]] == first)
            })
    };
    let own = pattern.block_size();
    if own > 1 && blocked(own) {
        return own;
    }
    [3, 2].into_iter().find(|&c| blocked(c)).unwrap_or(1)
}

/// Appends the AMD order of the graph induced by `nodes`.
fn amd_part(g: &Graph, nodes: &[usize], order: &mut Vec<usize>) -> Result<(), FemError> {
    let m = nodes.len();
    if m <= 2 {
        order.extend_from_slice(nodes);
        return Ok(());
    }
    // local numbers by binary search in a sorted copy
    let mut sorted: Vec<(usize, usize)> = nodes.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    sorted.sort_unstable();
    let local = |v: usize| {
        sorted
            .binary_search_by_key(&v, |&(w, _)| w)
            .ok()
            .map(|k| sorted[k].1)
    };
    let mut colptr = Vec::with_capacity(m + 1);
    let mut rows = Vec::new();
    colptr.push(0usize);
    for &v in nodes {
        let start = rows.len();
        rows.extend(g.neighbours(v).iter().filter_map(|&w| local(w)));
        rows[start..].sort_unstable();
        colptr.push(rows.len());
    }
    let a = SymbolicSparseColMatRef::new_checked(m, m, &colptr, None, &rows);
    let (mut perm, mut perm_inv) = (vec![0usize; m], vec![0usize; m]);
    let mut mem = MemBuffer::try_new(amd::order_scratch::<usize>(m, rows.len()))
        .map_err(|_| FemError::Solver("out of memory for the AMD ordering".into()))?;
    amd::order(
        &mut perm,
        &mut perm_inv,
        a,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| FemError::Solver(format!("AMD ordering: {e:?}")))?;
    order.extend(perm.iter().map(|&i| nodes[i]));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 5-point grid of nx × ny nodes, `c` dofs per node.
    fn grid(nx: usize, ny: usize, c: usize) -> SparsityPattern {
        let id = |i: usize, j: usize| j * nx + i;
        let mut blocks = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                if i + 1 < nx {
                    blocks.push([id(i, j), id(i + 1, j)]);
                }
                if j + 1 < ny {
                    blocks.push([id(i, j), id(i, j + 1)]);
                }
            }
        }
        let dofs: Vec<usize> = blocks
            .iter()
            .flatten()
            .flat_map(|&m| (0..c).map(move |k| m * c + k))
            .collect();
        SparsityPattern::from_blocks(nx * ny * c, &[(2 * c, &dofs)]).unwrap()
    }

    fn is_permutation(order: &[usize], n: usize) -> bool {
        let mut seen = vec![false; n];
        order.len() == n
            && order
                .iter()
                .all(|&d| d < n && !std::mem::replace(&mut seen[d], true))
    }

    /// Goal: a permutation of the dofs, each node's dofs together and in
    /// order, also for a disconnected pattern.
    #[test]
    fn the_order_is_a_permutation_that_keeps_node_blocks() {
        let p = grid(40, 30, 2);
        assert_eq!(p.block_size(), 2);
        let order = nested_dissection(&p).unwrap();
        assert!(is_permutation(&order, p.n()));
        for pair in order.chunks(2) {
            assert_eq!(pair[0] % 2, 0);
            assert_eq!(pair[1], pair[0] + 1);
        }
        // the same pattern without its block size: the blocks are found
        let plain =
            SparsityPattern::from_csr(p.n(), p.indptr().to_vec(), p.indices().to_vec()).unwrap();
        assert_eq!(plain.block_size(), 1);
        assert_eq!(node_block(&plain), 2);
        assert_eq!(nested_dissection(&plain).unwrap(), order);
        // two grids side by side, no edge between them
        let a = grid(30, 20, 1);
        let n = a.n();
        let mut blocks: Vec<usize> = Vec::new();
        for r in 0..n {
            for &j in &a.indices()[a.indptr()[r]..a.indptr()[r + 1]] {
                if j > r {
                    blocks.extend([r, j, r + n, j + n]);
                }
            }
        }
        let two = SparsityPattern::from_blocks(2 * n, &[(2, &blocks)]).unwrap();
        let order = nested_dissection(&two).unwrap();
        assert!(is_permutation(&order, 2 * n));
        // the components are ordered one after the other
        let first: Vec<bool> = order.iter().map(|&d| d < n).collect();
        assert!(first[..n].iter().all(|&f| f) || first[..n].iter().all(|&f| !f));
    }

    /// Goal: the dissection pays. On a square grid of 14 400 nodes the
    /// factor in its order holds less than half the entries of the natural
    /// (banded) order's, about n·nx.
    #[test]
    fn a_square_grid_fills_less_than_the_banded_order() {
        use faer::sparse::linalg::cholesky::{
            CholeskySymbolicParams, SymmetricOrdering, factorize_symbolic_cholesky,
        };
        let (nx, ny) = (120, 120);
        let p = grid(nx, ny, 1);
        let fwd = nested_dissection(&p).unwrap();
        let n = p.n();
        let mut inv = vec![0; n];
        for (k, &d) in fwd.iter().enumerate() {
            inv[d] = k;
        }
        let nnz = |perm: Option<(&[usize], &[usize])>| {
            let sym = SymbolicSparseColMatRef::new_checked(n, n, p.indptr(), None, p.indices());
            let ordering = match perm {
                Some((f, i)) => {
                    SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(f, i, n))
                }
                None => SymmetricOrdering::Identity,
            };
            factorize_symbolic_cholesky(
                sym,
                faer::Side::Lower,
                ordering,
                CholeskySymbolicParams::default(),
            )
            .unwrap()
            .len_val()
        };
        let (nd, banded) = (nnz(Some((&fwd, &inv))), nnz(None));
        // banded: about n·nx entries; nested dissection O(n log n)
        assert!(
            (nd as f64) < 0.5 * banded as f64,
            "nested dissection {nd} entries, banded {banded}"
        );
    }
}
