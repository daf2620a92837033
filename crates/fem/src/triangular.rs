//! The two triangular halves of a Cholesky solve, and the forward solve of
//! a unit vector along the elimination tree.
//!
//! With A = Pᵀ L Lᵀ P (P the fill-reducing permutation of the analysis), a
//! solve is x = Pᵀ L⁻ᵀ L⁻¹ P b. The low-rank corrections of
//! [`crate::UpdatedCholesky`] need A⁻¹'s entries between a few changed
//! dofs and its action on a right-hand side. Both follow from the forward
//! halves gᵢ = L⁻¹ P eᵢ: (A⁻¹)ᵢⱼ = gᵢ · gⱼ and (A⁻¹ b)ᵢ = gᵢ · (L⁻¹ P b).
//! The forward solve of a unit vector is sparse: its nonzeros lie on the
//! path from the dof's column to the root of the elimination tree, so it
//! costs a few supernodes instead of a whole solve.

use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::{MatMut, MatRef, Par};

use crate::error::FemError;
use crate::solver::CholeskySolver;

/// A sparse vector in the factor's elimination order: sorted positions
/// and their values.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SparseColumn {
    /// Positions, increasing.
    pub indices: Vec<usize>,
    /// Values at `indices`.
    pub values: Vec<f64>,
}

impl SparseColumn {
    /// The dot product with another sparse column.
    pub fn dot(&self, other: &SparseColumn) -> f64 {
        let (mut a, mut b, mut s) = (0, 0, 0.0);
        while a < self.indices.len() && b < other.indices.len() {
            match self.indices[a].cmp(&other.indices[b]) {
                std::cmp::Ordering::Less => a += 1,
                std::cmp::Ordering::Greater => b += 1,
                std::cmp::Ordering::Equal => {
                    s += self.values[a] * other.values[b];
                    a += 1;
                    b += 1;
                }
            }
        }
        s
    }

    /// The dot product with a dense vector.
    pub fn dot_dense(&self, x: &[f64]) -> f64 {
        self.indices
            .iter()
            .zip(&self.values)
            .map(|(&i, &v)| v * x[i])
            .sum()
    }

    /// x ← x − a · self.
    pub fn subtract_from(&self, a: f64, x: &mut [f64]) {
        for (&i, &v) in self.indices.iter().zip(&self.values) {
            x[i] -= a * v;
        }
    }
}

impl CholeskySolver {
    fn numeric(&self) -> Result<(), FemError> {
        if self.is_factorised() {
            Ok(())
        } else {
            Err(FemError::NotFactorised)
        }
    }

    fn check_len(&self, x: &[f64]) -> Result<(), FemError> {
        let n = self.pattern().n();
        if x.len() == n {
            Ok(())
        } else {
            Err(FemError::LengthMismatch {
                what: "right-hand side".into(),
                got: x.len(),
                expected: n,
            })
        }
    }

    /// x ← L⁻¹ P x: the forward half of a solve (the result is in the
    /// elimination order).
    pub fn forward_in_place(&self, x: &mut [f64]) -> Result<(), FemError> {
        self.forward_with(x, self.tree_split())
    }

    /// [`CholeskySolver::forward_in_place`] with a given split of the tree
    /// (None: one thread).
    fn forward_with(&self, x: &mut [f64], split: Option<TreeSplit>) -> Result<(), FemError> {
        self.numeric()?;
        self.check_len(x)?;
        if let Some(p) = self.symbolic_ref().perm() {
            let fwd = p.arrays().0;
            let b = x.to_vec();
            for (xk, &f) in x.iter_mut().zip(fwd) {
                *xk = b[f];
            }
        }
        let v = self.values();
        match self.symbolic_ref().raw() {
            SymbolicCholeskyRaw::Simplicial(sym) => {
                let (ptr, idx) = (sym.col_ptr(), sym.row_idx());
                for j in 0..x.len() {
                    let (a, b) = (ptr[j], ptr[j + 1]);
                    x[j] /= v[a];
                    let xj = x[j];
                    if xj != 0.0 {
                        for k in a + 1..b {
                            x[idx[k]] -= v[k] * xj;
                        }
                    }
                }
            }
            SymbolicCholeskyRaw::Supernodal(sym) => match split {
                Some(split) => forward_split(sym, v, split, x),
                None => {
                    let mut tmp = Vec::new();
                    for s in 0..sym.n_supernodes() {
                        let (b, w, below, rows, l) = supernode(sym, v, s);
                        forward_supernode(b, w, below, rows, l, x, &mut tmp);
                    }
                }
            },
        }
        crate::solver::check_finite("forward solve", x)
    }

    /// x ← Pᵀ L⁻ᵀ x: the backward half of a solve (x in the elimination
    /// order; the result in the dofs' order).
    pub fn backward_in_place(&self, x: &mut [f64]) -> Result<(), FemError> {
        self.backward_with(x, self.tree_split())
    }

    /// [`CholeskySolver::backward_in_place`] with a given split of the
    /// tree (None: one thread).
    fn backward_with(&self, x: &mut [f64], split: Option<TreeSplit>) -> Result<(), FemError> {
        self.numeric()?;
        self.check_len(x)?;
        let v = self.values();
        match self.symbolic_ref().raw() {
            SymbolicCholeskyRaw::Simplicial(sym) => {
                let (ptr, idx) = (sym.col_ptr(), sym.row_idx());
                for j in (0..x.len()).rev() {
                    let (a, b) = (ptr[j], ptr[j + 1]);
                    let mut acc = x[j];
                    for k in a + 1..b {
                        acc -= v[k] * x[idx[k]];
                    }
                    x[j] = acc / v[a];
                }
            }
            SymbolicCholeskyRaw::Supernodal(sym) => match split {
                Some(split) => backward_split(sym, v, split, x),
                None => {
                    let mut tmp = Vec::new();
                    for s in (0..sym.n_supernodes()).rev() {
                        backward_supernode(sym, v, s, &mut Rows::whole(x), &mut tmp);
                    }
                }
            },
        }
        if let Some(p) = self.symbolic_ref().perm() {
            let fwd = p.arrays().0;
            let y = x.to_vec();
            for (&f, &yk) in fwd.iter().zip(&y) {
                x[f] = yk;
            }
        }
        crate::solver::check_finite("backward solve", x)
    }

    /// L⁻¹ P e_dof, sparse: only the columns on the path from the dof's
    /// column to the root of the elimination tree are touched. `work` is a
    /// scratch vector (resized to n and left all zero).
    pub fn forward_unit(&self, dof: usize, work: &mut Vec<f64>) -> Result<SparseColumn, FemError> {
        self.numeric()?;
        let n = self.pattern().n();
        if dof >= n {
            return Err(FemError::Solver(format!(
                "unit vector of dof {dof} in a system of {n}"
            )));
        }
        work.clear();
        work.resize(n, 0.0);
        let start = match self.symbolic_ref().perm() {
            Some(p) => p.arrays().1[dof],
            None => dof,
        };
        let v = self.values();
        let mut indices = Vec::new();
        work[start] = 1.0;
        match self.symbolic_ref().raw() {
            SymbolicCholeskyRaw::Simplicial(sym) => {
                let (ptr, idx) = (sym.col_ptr(), sym.row_idx());
                // the path: each column's parent is its first row below the
                // diagonal (rows sorted, the diagonal first)
                let mut j = Some(start);
                while let Some(c) = j {
                    let (a, b) = (ptr[c], ptr[c + 1]);
                    work[c] /= v[a];
                    let xc = work[c];
                    for k in a + 1..b {
                        work[idx[k]] -= v[k] * xc;
                    }
                    indices.push(c);
                    j = (a + 1 < b).then(|| idx[a + 1]);
                }
            }
            SymbolicCholeskyRaw::Supernodal(sym) => {
                let of = self.supernode_of();
                let mut s = Some(of[start] as usize);
                let mut tmp = Vec::new();
                while let Some(k) = s {
                    let (b, w, below, rows, l) = supernode(sym, v, k);
                    forward_supernode(b, w, below, rows, l, work, &mut tmp);
                    indices.extend(b..b + w);
                    // the parent supernode holds the first row below
                    s = below.first().map(|&r| of[r] as usize);
                }
            }
        }
        let values: Vec<f64> = indices.iter().map(|&i| work[i]).collect();
        for &i in &indices {
            work[i] = 0.0;
        }
        if values.iter().any(|x| !x.is_finite()) {
            return Err(FemError::NonFinite {
                what: "forward solve of a unit vector".into(),
                index: dof,
            });
        }
        Ok(SparseColumn { indices, values })
    }
}

/// Supernode `s`: first column, width, rows below its diagonal block,
/// total rows, values (rows × width, column-major).
fn supernode<'a>(
    sym: &'a faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    v: &'a [f64],
    s: usize,
) -> (usize, usize, &'a [usize], usize, &'a [f64]) {
    let (b, e) = (sym.supernode_begin()[s], sym.supernode_end()[s]);
    let w = e - b;
    let rp = sym.col_ptr_for_row_idx();
    let below = &sym.row_idx()[rp[s]..rp[s + 1]];
    let rows = w + below.len();
    let vp = sym.col_ptr_for_val()[s];
    (b, w, below, rows, &v[vp..vp + rows * w])
}

/// A split of a supernodal elimination tree for the two halves of a solve
/// on two threads: supernodes `[a0, a1)` and `[a1, b1)` are two unions of
/// whole subtrees (the order is a postorder, so a subtree is a contiguous
/// range), neither holding an ancestor of the other's. Their forward and
/// backward steps are independent but for the rows of their common
/// ancestors (columns from `b1` on).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TreeSplit {
    a0: usize,
    a1: usize,
    b1: usize,
    /// First column of supernode `a1` and of supernode `b1` (`n` if none).
    col_a1: usize,
    col_b1: usize,
}

/// Least share of the factor's entries in the smaller half for a split to
/// be worth two threads.
const SPLIT_MIN_SHARE: f64 = 0.2;
/// Fewest factor entries for a split (below, a thread's start costs more
/// than half a solve saves).
const SPLIT_MIN_ENTRIES: usize = 100_000;

/// The split of the tree that puts the most work in the smaller half, if
/// that half holds at least [`SPLIT_MIN_SHARE`] of the entries. From the
/// roots down: the children of a node (the roots, first), in order, are
/// cut into a leading and a trailing group as evenly as possible; if the
/// smaller group is too small, the search goes on in the largest child.
pub(crate) fn tree_split(
    sym: &faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    supernode_of: &[u32],
) -> Option<TreeSplit> {
    let ns = sym.n_supernodes();
    let (begin, end) = (sym.supernode_begin(), sym.supernode_end());
    let rp = sym.col_ptr_for_row_idx();
    let rows_below = sym.row_idx();
    let mut parent = vec![usize::MAX; ns];
    let mut work = vec![0usize; ns];
    for s in 0..ns {
        let below = &rows_below[rp[s]..rp[s + 1]];
        let w = end[s] - begin[s];
        work[s] = w * (w + below.len());
        if let Some(&r) = below.first() {
            let p = supernode_of[r] as usize;
            if p <= s {
                return None; // not a postorder
            }
            parent[s] = p;
        }
    }
    // subtree work and first supernode; a postorder makes each subtree
    // the contiguous range [first, s]
    let mut total = work.clone();
    let mut first: Vec<usize> = (0..ns).collect();
    let mut size = vec![1usize; ns];
    for s in 0..ns {
        let p = parent[s];
        if p != usize::MAX {
            total[p] += total[s];
            first[p] = first[p].min(first[s]);
            size[p] += size[s];
        }
    }
    if (0..ns).any(|s| s + 1 - first[s] != size[s]) {
        return None;
    }
    let entries: usize = work.iter().sum();
    if entries < SPLIT_MIN_ENTRIES {
        return None;
    }
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); ns];
    let mut roots = Vec::new();
    for (s, &p) in parent.iter().enumerate() {
        match p {
            usize::MAX => roots.push(s),
            p => children[p].push(s),
        }
    }
    let col = |s: usize| if s < ns { begin[s] } else { sym.nrows() };
    let mut group = roots;
    loop {
        if group.is_empty() {
            return None;
        }
        let sum: usize = group.iter().map(|&c| total[c]).sum();
        if (sum as f64) < 2.0 * SPLIT_MIN_SHARE * entries as f64 {
            return None;
        }
        // the most even cut of the group, in order
        let (mut best, mut best_k, mut acc) = (0, 0, 0);
        for (k, &c) in group.iter().enumerate().take(group.len() - 1) {
            acc += total[c];
            let smaller = acc.min(sum - acc);
            if smaller > best {
                (best, best_k) = (smaller, k + 1);
            }
        }
        if best as f64 >= SPLIT_MIN_SHARE * entries as f64 {
            let a0 = first[group[0]];
            let a1 = first[group[best_k]];
            let b1 = group[group.len() - 1] + 1;
            return Some(TreeSplit {
                a0,
                a1,
                b1,
                col_a1: col(a1),
                col_b1: col(b1),
            });
        }
        let &largest = group
            .iter()
            .max_by_key(|&&c| (total[c], std::cmp::Reverse(c)))
            .expect("a group is not empty");
        group = std::mem::take(&mut children[largest]);
    }
}

/// A view of x for one part of a split solve: the rows of its own
/// columns, and (if it has them) the rows of the common ancestors. Row r
/// is `own[r - own_start]` or `top[r - top_start]`.
struct Rows<'a> {
    own: &'a mut [f64],
    own_start: usize,
    top: Top<'a>,
    top_start: usize,
}

/// The common ancestors' rows in a [`Rows`]: written (the forward half's
/// first part), read (the backward half's parts) or absent.
enum Top<'a> {
    Absent,
    Written(&'a mut [f64]),
    Read(&'a [f64]),
}

impl<'a> Rows<'a> {
    fn whole(x: &'a mut [f64]) -> Self {
        let n = x.len();
        Rows {
            own: x,
            own_start: 0,
            top: Top::Absent,
            top_start: n,
        }
    }

    #[inline]
    fn get(&self, r: usize) -> f64 {
        if r < self.top_start {
            return self.own[r - self.own_start];
        }
        match &self.top {
            Top::Written(t) => t[r - self.top_start],
            Top::Read(t) => t[r - self.top_start],
            Top::Absent => unreachable!("a part reads no row of the common ancestors"),
        }
    }

    #[inline]
    fn set(&mut self, r: usize, v: f64) {
        if r < self.top_start {
            self.own[r - self.own_start] = v;
        } else if let Top::Written(t) = &mut self.top {
            t[r - self.top_start] = v;
        } else {
            unreachable!("a part writes no row of the common ancestors")
        }
    }
}

/// The forward step of supernode `s` on the rows of `x` below `limit`
/// (the rows from `limit` on are left for [`forward_replay`]).
fn forward_part(
    sym: &faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    v: &[f64],
    s: usize,
    x: &mut Rows<'_>,
    limit: usize,
    tmp: &mut Vec<f64>,
) {
    let (b, w, below, rows, l) = supernode(sym, v, s);
    let own = &mut x.own[b - x.own_start..b - x.own_start + w];
    let lm = MatRef::from_column_major_slice(l, rows, w);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        lm.submatrix(0, 0, w, w),
        MatMut::from_column_major_slice_mut(own, w, 1),
        Par::Seq,
    );
    let kept = below.partition_point(|&r| r < limit);
    tmp.clear();
    tmp.extend(below[..kept].iter().map(|&r| x.get(r)));
    for j in 0..w {
        let xj = x.own[b - x.own_start + j];
        if xj != 0.0 {
            let col = &l[j * rows + w..j * rows + w + kept];
            for (t, &c) in tmp.iter_mut().zip(col) {
                *t -= c * xj;
            }
        }
    }
    for (&r, &t) in below[..kept].iter().zip(tmp.iter()) {
        x.set(r, t);
    }
}

/// The updates of supernode `s` to the rows of `x` from `limit` on, in the
/// order of [`forward_supernode`] (the same bits as done there).
fn forward_replay(
    sym: &faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    v: &[f64],
    s: usize,
    x: &mut [f64],
    limit: usize,
    tmp: &mut Vec<f64>,
) {
    let (b, w, below, rows, l) = supernode(sym, v, s);
    let kept = below.partition_point(|&r| r < limit);
    let rest = &below[kept..];
    if rest.is_empty() {
        return;
    }
    tmp.clear();
    tmp.extend(rest.iter().map(|&r| x[r]));
    for j in 0..w {
        let xj = x[b + j];
        if xj != 0.0 {
            let col = &l[j * rows + w + kept..(j + 1) * rows];
            for (t, &c) in tmp.iter_mut().zip(col) {
                *t -= c * xj;
            }
        }
    }
    for (&r, &t) in rest.iter().zip(tmp.iter()) {
        x[r] = t;
    }
}

/// The forward half on two threads: the supernodes before the split, the
/// two parts at once (the first updates the common ancestors' rows as it
/// goes, the second leaves them), the second part's updates of those rows
/// after the first's, then the rest: every row gets the same updates in
/// the same order as in the sequential loop, so the same bits.
fn forward_split(
    sym: &faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    v: &[f64],
    split: TreeSplit,
    x: &mut [f64],
) {
    let TreeSplit {
        a0,
        a1,
        b1,
        col_a1,
        col_b1,
    } = split;
    let n = x.len();
    let mut tmp = Vec::new();
    for s in 0..a0 {
        let (b, w, below, rows, l) = supernode(sym, v, s);
        forward_supernode(b, w, below, rows, l, x, &mut tmp);
    }
    {
        let (head, top) = x.split_at_mut(col_b1);
        let (xa, xb) = head.split_at_mut(col_a1);
        let mut ra = Rows {
            own: xa,
            own_start: 0,
            top: Top::Written(top),
            top_start: col_b1,
        };
        let mut rb = Rows {
            own: xb,
            own_start: col_a1,
            top: Top::Absent,
            top_start: col_b1,
        };
        rayon::join(
            || {
                let mut tmp = Vec::new();
                for s in a0..a1 {
                    forward_part(sym, v, s, &mut ra, n, &mut tmp);
                }
            },
            || {
                let mut tmp = Vec::new();
                for s in a1..b1 {
                    forward_part(sym, v, s, &mut rb, col_b1, &mut tmp);
                }
            },
        );
    }
    for s in a1..b1 {
        forward_replay(sym, v, s, x, col_b1, &mut tmp);
    }
    for s in b1..sym.n_supernodes() {
        let (b, w, below, rows, l) = supernode(sym, v, s);
        forward_supernode(b, w, below, rows, l, x, &mut tmp);
    }
}

/// The backward step of supernode `s` (its rows below are read only).
fn backward_supernode(
    sym: &faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    v: &[f64],
    s: usize,
    x: &mut Rows<'_>,
    tmp: &mut Vec<f64>,
) {
    let (b, w, below, rows, l) = supernode(sym, v, s);
    // x's rows below, gathered once for the block's columns
    tmp.clear();
    tmp.extend(below.iter().map(|&r| x.get(r)));
    let own = &mut x.own[b - x.own_start..b - x.own_start + w];
    for (j, o) in own.iter_mut().enumerate() {
        let col = &l[j * rows + w..(j + 1) * rows];
        let acc: f64 = tmp.iter().zip(col).map(|(&t, &c)| c * t).sum();
        *o -= acc;
    }
    let lm = MatRef::from_column_major_slice(l, rows, w);
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(
        lm.submatrix(0, 0, w, w).transpose(),
        MatMut::from_column_major_slice_mut(own, w, 1),
        Par::Seq,
    );
}

/// The backward half on two threads: the common ancestors first, then the
/// two parts at once (each reads the ancestors' rows, final by then, and
/// writes its own), then the supernodes before the split.
fn backward_split(
    sym: &faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    v: &[f64],
    split: TreeSplit,
    x: &mut [f64],
) {
    let TreeSplit {
        a0,
        a1,
        b1,
        col_a1,
        col_b1,
    } = split;
    let mut tmp = Vec::new();
    for s in (b1..sym.n_supernodes()).rev() {
        backward_supernode(sym, v, s, &mut Rows::whole(x), &mut tmp);
    }
    {
        let (head, top) = x.split_at_mut(col_b1);
        let (xa, xb) = head.split_at_mut(col_a1);
        let top: &[f64] = top;
        let mut ra = Rows {
            own: xa,
            own_start: 0,
            top: Top::Read(top),
            top_start: col_b1,
        };
        let mut rb = Rows {
            own: xb,
            own_start: col_a1,
            top: Top::Read(top),
            top_start: col_b1,
        };
        rayon::join(
            || {
                let mut tmp = Vec::new();
                for s in (a0..a1).rev() {
                    backward_supernode(sym, v, s, &mut ra, &mut tmp);
                }
            },
            || {
                let mut tmp = Vec::new();
                for s in (a1..b1).rev() {
                    backward_supernode(sym, v, s, &mut rb, &mut tmp);
                }
            },
        );
    }
    for s in (0..a0).rev() {
        backward_supernode(sym, v, s, &mut Rows::whole(x), &mut tmp);
    }
}

/// The forward step of one supernode on a dense x.
fn forward_supernode(
    b: usize,
    w: usize,
    below: &[usize],
    rows: usize,
    l: &[f64],
    x: &mut [f64],
    tmp: &mut Vec<f64>,
) {
    let lm = MatRef::from_column_major_slice(l, rows, w);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        lm.submatrix(0, 0, w, w),
        MatMut::from_column_major_slice_mut(&mut x[b..b + w], w, 1),
        Par::Seq,
    );
    // the rows below updated in a dense copy (one gather and one scatter
    // instead of one per column; the same operations in the same order)
    tmp.clear();
    tmp.extend(below.iter().map(|&r| x[r]));
    for j in 0..w {
        let xj = x[b + j];
        if xj != 0.0 {
            let col = &l[j * rows + w..(j + 1) * rows];
            for (t, &c) in tmp.iter_mut().zip(col) {
                *t -= c * xj;
            }
        }
    }
    for (&r, &t) in below.iter().zip(tmp.iter()) {
        x[r] = t;
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::pattern::{CsrMatrix, SparsityPattern};

    /// A 2D five-point Laplacian on an m × m grid plus a shift: SPD, with a
    /// nontrivial ordering and elimination tree.
    fn grid(m: usize) -> CsrMatrix {
        let n = m * m;
        let id = |i: usize, j: usize| i * m + j;
        let mut rows: Vec<Vec<usize>> = vec![Vec::new(); n];
        for i in 0..m {
            for j in 0..m {
                let a = id(i, j);
                rows[a].push(a);
                if i + 1 < m {
                    rows[a].push(id(i + 1, j));
                    rows[id(i + 1, j)].push(a);
                }
                if j + 1 < m {
                    rows[a].push(id(i, j + 1));
                    rows[id(i, j + 1)].push(a);
                }
            }
        }
        let mut indptr = vec![0];
        let mut indices = Vec::new();
        for mut r in rows {
            r.sort_unstable();
            r.dedup();
            indices.extend(r);
            indptr.push(indices.len());
        }
        let p = Arc::new(SparsityPattern::from_csr(n, indptr, indices).unwrap());
        let mut k = CsrMatrix::zeros(p);
        let add = |k: &mut CsrMatrix, i: usize, j: usize, v: f64| {
            let s = k.pattern().slot(i, j).unwrap();
            k.values_mut()[s] += v;
        };
        for i in 0..m {
            for j in 0..m {
                let a = id(i, j);
                // varied diagonal so that no two columns are alike
                add(&mut k, a, a, 4.1 + 0.01 * (a % 7) as f64);
                for (di, dj) in [(1usize, 0usize), (0, 1)] {
                    if i + di < m && j + dj < m {
                        let b = id(i + di, j + dj);
                        let v = -1.0 - 0.001 * ((a + b) % 5) as f64;
                        add(&mut k, a, b, v);
                        add(&mut k, b, a, v);
                    }
                }
            }
        }
        k
    }

    fn solvers(k: &CsrMatrix) -> Vec<CholeskySolver> {
        // both layouts
        let mut out = Vec::new();
        use faer::sparse::linalg::SupernodalThreshold;
        for mut s in [
            CholeskySolver::analyse_with(
                k.pattern().clone(),
                SupernodalThreshold::FORCE_SUPERNODAL,
            )
            .unwrap(),
            CholeskySolver::analyse_with(
                k.pattern().clone(),
                SupernodalThreshold::FORCE_SIMPLICIAL,
            )
            .unwrap(),
        ] {
            s.factorise(k).unwrap();
            out.push(s);
        }
        out
    }

    #[test]
    fn both_layouts_are_tested() {
        let mut kinds = [0, 0];
        for m in [3, 12, 30] {
            for s in solvers(&grid(m)) {
                match s.symbolic_ref().raw() {
                    SymbolicCholeskyRaw::Simplicial(_) => kinds[0] += 1,
                    SymbolicCholeskyRaw::Supernodal(_) => kinds[1] += 1,
                }
            }
        }
        assert!(kinds[0] > 0 && kinds[1] > 0, "{kinds:?}");
    }

    #[test]
    fn the_halves_on_two_threads_give_the_bits_of_one_thread() {
        // a grid whose factor is large enough to be split
        let k = grid(110);
        let n = k.n();
        let s = &solvers(&k)[0];
        let split = s.tree_split().expect("a split of the tree");
        let (a, b, total) = {
            let TreeSplit { a0, a1, b1, .. } = split;
            let SymbolicCholeskyRaw::Supernodal(sym) = s.symbolic_ref().raw() else {
                panic!("supernodal")
            };
            let entries = |r: std::ops::Range<usize>| -> usize {
                r.map(|q| {
                    let (_, w, below, _, _) = supernode(sym, s.values(), q);
                    w * (w + below.len())
                })
                .sum()
            };
            (
                entries(a0..a1),
                entries(a1..b1),
                entries(0..sym.n_supernodes()),
            )
        };
        assert!(
            a.min(b) as f64 >= SPLIT_MIN_SHARE * total as f64,
            "{a} and {b} of {total}"
        );
        let rhs: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64) - 5.0).collect();
        let (mut one, mut two) = (rhs.clone(), rhs.clone());
        s.forward_with(&mut one, None).unwrap();
        s.forward_with(&mut two, Some(split)).unwrap();
        assert!(
            one.iter()
                .zip(&two)
                .all(|(p, q)| p.to_bits() == q.to_bits())
        );
        s.backward_with(&mut one, None).unwrap();
        s.backward_with(&mut two, Some(split)).unwrap();
        assert!(
            one.iter()
                .zip(&two)
                .all(|(p, q)| p.to_bits() == q.to_bits())
        );
        // and it is a solve
        let mut x = rhs.clone();
        s.solve(&mut x).unwrap();
        let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            x.iter()
                .zip(&two)
                .all(|(p, q)| (p - q).abs() <= 1e-12 * scale)
        );
        // small factors are not split
        assert!(solvers(&grid(12))[0].tree_split().is_none());
    }

    #[test]
    fn the_two_halves_make_a_solve() {
        for m in [3, 12, 30] {
            let k = grid(m);
            let n = k.n();
            let b: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64) - 5.0).collect();
            for s in solvers(&k) {
                let mut x = b.clone();
                s.solve(&mut x).unwrap();
                let mut y = b.clone();
                s.forward_in_place(&mut y).unwrap();
                s.backward_in_place(&mut y).unwrap();
                let scale = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                for (a, c) in x.iter().zip(&y) {
                    assert!((a - c).abs() <= 1e-13 * scale, "{a} vs {c}");
                }
            }
        }
    }

    #[test]
    fn unit_forward_solves_give_the_inverse_and_stay_on_their_path() {
        for m in [3, 12, 30] {
            let k = grid(m);
            let n = k.n();
            for s in solvers(&k) {
                let mut work = Vec::new();
                let dofs = [0, n / 3, n / 2, n - 1];
                let g: Vec<SparseColumn> = dofs
                    .iter()
                    .map(|&d| s.forward_unit(d, &mut work).unwrap())
                    .collect();
                assert!(work.iter().all(|&v| v == 0.0), "scratch left dirty");
                for (a, &da) in dofs.iter().enumerate() {
                    // the dense forward solve of the same unit vector
                    let mut e = vec![0.0; n];
                    e[da] = 1.0;
                    s.forward_in_place(&mut e).unwrap();
                    let dense = SparseColumn {
                        indices: (0..n).collect(),
                        values: e.clone(),
                    };
                    // nothing outside the path
                    let mut on_path = vec![false; n];
                    for &i in &g[a].indices {
                        on_path[i] = true;
                    }
                    for (i, v) in e.iter().enumerate() {
                        if !on_path[i] {
                            assert_eq!(*v, 0.0, "m = {m}: entry {i} off the path");
                        }
                    }
                    assert!(g[a].indices.windows(2).all(|w| w[0] < w[1]));
                    // (A⁻¹)_ab = g_a · g_b
                    let mut col = vec![0.0; n];
                    col[da] = 1.0;
                    s.solve(&mut col).unwrap();
                    for (b, &db) in dofs.iter().enumerate() {
                        let want = col[db];
                        let got = g[a].dot(&g[b]);
                        assert!(
                            (got - want).abs() <= 1e-13 * col[da].abs(),
                            "{got} vs {want}"
                        );
                        assert!((dense.dot(&g[b]) - want).abs() <= 1e-13 * col[da].abs());
                    }
                    if m == 30 {
                        assert!(
                            g[a].indices.len() < n / 2,
                            "path of {} entries in {n}",
                            g[a].indices.len()
                        );
                    }
                }
            }
        }
    }
}
