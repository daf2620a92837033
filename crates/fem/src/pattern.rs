//! CSR sparsity pattern (built once) and the CSR matrix that refills its values.

use std::sync::Arc;

use rayon::prelude::*;

use crate::error::FemError;

/// Compressed-sparse-row pattern of a square matrix with sorted column indices.
///
/// Built from element connectivity it is structurally symmetric, so it is also
/// the compressed-sparse-column pattern of the same matrix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SparsityPattern {
    n: usize,
    indptr: Vec<usize>,
    indices: Vec<usize>,
    /// Node block size c: rows c·m … c·m+c−1 share their columns, which come
    /// in whole node groups (1 for a scalar pattern).
    block: usize,
    /// For c ≥ 2: the node columns of every node row (row m's are
    /// `node_indices[node_indptr[m]..node_indptr[m + 1]]`), 32-bit, for
    /// [`CsrMatrix::mul_vec`]: one index per c² values instead of one per
    /// value (empty for c = 1).
    node_indptr: Vec<usize>,
    node_indices: Vec<u32>,
}

impl SparsityPattern {
    /// Builds the pattern of the union of dense element blocks.
    ///
    /// `blocks` are flattened element dof lists, `ndof` dofs per element.
    /// Diagonal entries are always present.
    pub fn from_blocks(n: usize, blocks: &[(usize, &[usize])]) -> Result<Self, FemError> {
        for (k, &(ndof, dofs)) in blocks.iter().enumerate() {
            if ndof == 0 || !dofs.len().is_multiple_of(ndof) {
                return Err(FemError::LengthMismatch {
                    what: format!("element block {k}"),
                    got: dofs.len(),
                    expected: ndof * (dofs.len() / ndof.max(1)),
                });
            }
            if let Some(&d) = dofs.iter().find(|&&d| d >= n) {
                return Err(FemError::DofOutOfRange {
                    what: format!("element block {k}"),
                    dof: d,
                    n_dofs: n,
                });
            }
        }
        // Interleaved node blocks (dof = node·c + k, all components of a node
        // together, as a DofMap numbers them): build the node pattern and
        // expand it, 1/c² of the sorting work.
        if let Some(c) = detect_block_size(n, blocks) {
            let node_dofs: Vec<Vec<usize>> = blocks
                .iter()
                .map(|&(_, dofs)| dofs.iter().step_by(c).map(|d| d / c).collect())
                .collect();
            let node_blocks: Vec<(usize, &[usize])> = blocks
                .iter()
                .zip(&node_dofs)
                .map(|(&(ndof, _), d)| (ndof / c, d.as_slice()))
                .collect();
            let (np, node_indices) = scalar_pattern(n / c, &node_blocks);
            let mut indptr = Vec::with_capacity(n + 1);
            let mut indices = Vec::with_capacity(node_indices.len() * c * c);
            indptr.push(0);
            for a in 0..n / c {
                let row = &node_indices[np[a]..np[a + 1]];
                for _ in 0..c {
                    for &m in row {
                        indices.extend((0..c).map(|l| m as usize * c + l));
                    }
                    indptr.push(indices.len());
                }
            }
            return Ok(SparsityPattern {
                n,
                indptr,
                indices,
                block: c,
                node_indptr: np,
                node_indices,
            });
        }
        let (indptr, indices) = scalar_pattern(n, blocks);
        let indices = indices.into_iter().map(|j| j as usize).collect();
        Ok(SparsityPattern {
            n,
            indptr,
            indices,
            block: 1,
            node_indptr: Vec::new(),
            node_indices: Vec::new(),
        })
    }

    /// A pattern from CSR arrays (rows sorted, in range, each with its
    /// diagonal), node block size 1.
    pub fn from_csr(n: usize, indptr: Vec<usize>, indices: Vec<usize>) -> Result<Self, FemError> {
        let ok = indptr.len() == n + 1
            && indptr.first() == Some(&0)
            && indptr.last() == Some(&indices.len())
            && (0..n).all(|i| {
                let row = indices.get(indptr[i]..indptr[i + 1]).unwrap_or(&[]);
                indptr[i] <= indptr[i + 1]
                    && row.windows(2).all(|w| w[0] < w[1])
                    && row.last().is_none_or(|&j| j < n)
                    && row.binary_search(&i).is_ok()
            });
        if !ok {
            return Err(FemError::Solver("malformed CSR pattern".into()));
        }
        Ok(SparsityPattern {
            n,
            indptr,
            indices,
            block: 1,
            node_indptr: Vec::new(),
            node_indices: Vec::new(),
        })
    }

    /// Number of rows (= columns).
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.indices.len()
    }

    /// Row pointers (length n + 1).
    pub fn indptr(&self) -> &[usize] {
        &self.indptr
    }

    /// Column indices, sorted within each row.
    pub fn indices(&self) -> &[usize] {
        &self.indices
    }

    /// Node block size (see [`SparsityPattern::from_blocks`]).
    pub fn block_size(&self) -> usize {
        self.block
    }

    /// Slot of entry (i, j) in the value array, if stored.
    #[inline]
    pub fn slot(&self, i: usize, j: usize) -> Option<usize> {
        let (a, b) = (self.indptr[i], self.indptr[i + 1]);
        self.indices[a..b].binary_search(&j).ok().map(|k| a + k)
    }
}

/// Sorted, deduplicated CSR pattern (with diagonal) of the union of element cliques.
/// (Column indices in 32 bits, as they are sorted.)
fn scalar_pattern(n: usize, blocks: &[(usize, &[usize])]) -> (Vec<usize>, Vec<u32>) {
    // Upper bound of entries per row: 1 (diagonal) + ndof per element touching it.
    let mut count = vec![1usize; n];
    for &(ndof, dofs) in blocks {
        for &d in dofs {
            count[d] += ndof;
        }
    }
    let mut start = Vec::with_capacity(n + 1);
    start.push(0usize);
    for c in &count {
        start.push(start.last().copied().unwrap_or(0) + c);
    }
    let total = start[n];
    let mut cand = vec![0u32; total];
    let mut fill = start[..n].to_vec();
    for (i, f) in fill.iter_mut().enumerate() {
        cand[*f] = i as u32;
        *f += 1;
    }
    for &(ndof, dofs) in blocks {
        for el in dofs.chunks_exact(ndof) {
            for &r in el {
                let f = &mut fill[r];
                for (k, &c) in el.iter().enumerate() {
                    cand[*f + k] = c as u32;
                }
                *f += ndof;
            }
        }
    }
    // Sort and dedup each row in parallel (each row is independent: deterministic).
    let mut rows: Vec<&mut [u32]> = Vec::with_capacity(n);
    let mut rest: &mut [u32] = &mut cand;
    for i in 0..n {
        let (head, tail) = rest.split_at_mut(start[i + 1] - start[i]);
        rows.push(head);
        rest = tail;
    }
    let lens: Vec<usize> = rows
        .par_iter_mut()
        .map(|row| {
            row.sort_unstable();
            let mut w = 0;
            for r in 0..row.len() {
                if r == 0 || row[r] != row[w - 1] {
                    row[w] = row[r];
                    w += 1;
                }
            }
            w
        })
        .collect();
    let mut indptr = Vec::with_capacity(n + 1);
    indptr.push(0);
    for l in &lens {
        indptr.push(indptr.last().copied().unwrap_or(0) + l);
    }
    let mut indices = Vec::with_capacity(indptr[n]);
    for i in 0..n {
        indices.extend_from_slice(&cand[start[i]..start[i] + lens[i]]);
    }
    (indptr, indices)
}

/// The common node block size c ≥ 2 of all element blocks, if every element
/// lists whole nodes (dofs c·m, c·m+1, …, c·m+c−1 in order).
fn detect_block_size(n: usize, blocks: &[(usize, &[usize])]) -> Option<usize> {
    (2..=3).find(|&c| {
        n.is_multiple_of(c)
            && blocks.iter().all(|&(ndof, dofs)| {
                ndof.is_multiple_of(c)
                    && dofs.chunks_exact(c).all(|g| {
                        g[0].is_multiple_of(c) && g.iter().enumerate().all(|(k, &d)| d == g[0] + k)
                    })
            })
    })
}

/// A CSR matrix over a shared pattern.
#[derive(Debug, Clone, PartialEq)]
pub struct CsrMatrix {
    pattern: Arc<SparsityPattern>,
    values: Vec<f64>,
}

/// Fewest rows per task of [`CsrMatrix::mul_vec`]: a task per row costs more
/// in scheduling than the products on systems of a few thousand unknowns
/// (the contact Newton's line search and residual checks run several per
/// iteration; 13 % of a two-way vessel run went to rayon's splitting).
const MUL_VEC_MIN_ROWS: usize = 4096;

impl CsrMatrix {
    /// A zero matrix with the given pattern.
    pub fn zeros(pattern: Arc<SparsityPattern>) -> Self {
        let values = vec![0.0; pattern.nnz()];
        CsrMatrix { pattern, values }
    }

    /// The pattern.
    pub fn pattern(&self) -> &Arc<SparsityPattern> {
        &self.pattern
    }

    /// Stored values.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Stored values, mutable.
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.values
    }

    /// Number of rows.
    pub fn n(&self) -> usize {
        self.pattern.n
    }

    /// Entry (i, j), zero when not stored.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.pattern.slot(i, j).map_or(0.0, |s| self.values[s])
    }

    /// y = A x (rows in tasks of at least [`MUL_VEC_MIN_ROWS`]; each row's
    /// sum is formed in one task, so the result does not depend on the
    /// thread count). A node-blocked pattern (block size c ≥ 2) reads its
    /// 32-bit node columns instead of the per-entry ones: the same sums in
    /// the same order (the same bits), with a sixteenth of the index
    /// traffic for c = 2.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        let p = &self.pattern;
        match p.block {
            2 => return self.mul_vec_blocked::<2>(x, y),
            3 => return self.mul_vec_blocked::<3>(x, y),
            _ => {}
        }
        y.par_iter_mut()
            .with_min_len(MUL_VEC_MIN_ROWS)
            .enumerate()
            .for_each(|(i, yi)| {
                let mut s = 0.0;
                for k in p.indptr[i]..p.indptr[i + 1] {
                    s += self.values[k] * x[p.indices[k]];
                }
                *yi = s;
            });
    }

    /// [`CsrMatrix::mul_vec`] of a pattern with node blocks of `C` dofs:
    /// dof row `C·m + r` holds, for every node column `k` of node row `m`,
    /// the `C` entries of columns `C·k … C·k + C − 1`, in that order.
    fn mul_vec_blocked<const C: usize>(&self, x: &[f64], y: &mut [f64]) {
        let p = &self.pattern;
        let v = &self.values;
        y.par_chunks_mut(C)
            .with_min_len(MUL_VEC_MIN_ROWS / C)
            .enumerate()
            .for_each(|(m, ym)| {
                let nodes = &p.node_indices[p.node_indptr[m]..p.node_indptr[m + 1]];
                // the C rows of node m side by side: C independent sums
                // (each in its own order) instead of one chain of additions
                let rows: [&[f64]; C] = std::array::from_fn(|r| {
                    let a = p.indptr[C * m + r];
                    &v[a..a + C * nodes.len()]
                });
                let mut s = [0.0; C];
                for (j, &k) in nodes.iter().enumerate() {
                    let xk = &x[C * k as usize..C * k as usize + C];
                    for r in 0..C {
                        for l in 0..C {
                            s[r] += rows[r][C * j + l] * xk[l];
                        }
                    }
                }
                ym.copy_from_slice(&s);
            });
    }

    /// Dense copy (for tests and small systems).
    pub fn to_dense(&self) -> nalgebra::DMatrix<f64> {
        let n = self.n();
        let mut d = nalgebra::DMatrix::zeros(n, n);
        for i in 0..n {
            for k in self.pattern.indptr[i]..self.pattern.indptr[i + 1] {
                d[(i, self.pattern.indices[k])] += self.values[k];
            }
        }
        d
    }

    /// A copy as a `sprs` CSR matrix (e.g. for Matrix Market output).
    pub fn to_sprs(&self) -> sprs::CsMat<f64> {
        sprs::CsMat::new(
            (self.n(), self.n()),
            self.pattern.indptr.clone(),
            self.pattern.indices.clone(),
            self.values.clone(),
        )
    }

    /// Largest |a_ij − a_ji| relative to the largest |a_ij|.
    pub fn asymmetry(&self) -> f64 {
        let p = &self.pattern;
        let mut amax: f64 = 0.0;
        let mut dmax: f64 = 0.0;
        for i in 0..p.n {
            for k in p.indptr[i]..p.indptr[i + 1] {
                let j = p.indices[k];
                amax = amax.max(self.values[k].abs());
                if let Some(s) = p.slot(j, i) {
                    dmax = dmax.max((self.values[k] - self.values[s]).abs());
                }
            }
        }
        if amax == 0.0 { 0.0 } else { dmax / amax }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A[i][j] by the definition, row by row and left to right.
    fn reference(m: &CsrMatrix, x: &[f64]) -> Vec<f64> {
        let p = m.pattern();
        (0..p.n())
            .map(|i| {
                let mut s = 0.0;
                for k in p.indptr()[i]..p.indptr()[i + 1] {
                    s += m.values()[k] * x[p.indices()[k]];
                }
                s
            })
            .collect()
    }

    /// Pseudo-random values in [-1, 1) (a fixed linear congruential sequence).
    fn values(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            })
            .collect()
    }

    #[test]
    fn node_blocked_products_are_the_plain_products_bit_for_bit() {
        // a strip of triangles: nodes (i, j) of an nx × 3 grid, two
        // triangles per cell, with c dofs per node (c = 2, 3), and a scalar
        // pattern of the same mesh (block size 1)
        let nx = 3000;
        let node = |i: usize, j: usize| i * 3 + j;
        let mut tris = Vec::new();
        for i in 0..nx - 1 {
            for j in 0..2 {
                tris.push([node(i, j), node(i + 1, j), node(i + 1, j + 1)]);
                tris.push([node(i, j), node(i + 1, j + 1), node(i, j + 1)]);
            }
        }
        for c in [1, 2, 3] {
            let dofs: Vec<usize> = tris
                .iter()
                .flat_map(|t| t.iter().flat_map(move |&a| (0..c).map(move |l| a * c + l)))
                .collect();
            let n = 3 * nx * c;
            let p = Arc::new(SparsityPattern::from_blocks(n, &[(3 * c, &dofs)]).unwrap());
            assert_eq!(p.block_size(), c);
            let mut m = CsrMatrix::zeros(Arc::clone(&p));
            m.values_mut().copy_from_slice(&values(p.nnz(), 7));
            let x = values(n, 11);
            let mut y = vec![0.0; n];
            m.mul_vec(&x, &mut y);
            let want = reference(&m, &x);
            for (i, (a, b)) in y.iter().zip(&want).enumerate() {
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "c = {c}, row {i}: {a} against {b}"
                );
            }
        }
    }
}
