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
            SymbolicCholeskyRaw::Supernodal(sym) => {
                let mut tmp = Vec::new();
                for s in 0..sym.n_supernodes() {
                    let (b, w, below, rows, l) = supernode(sym, v, s);
                    forward_supernode(b, w, below, rows, l, x, &mut tmp);
                }
            }
        }
        crate::solver::check_finite("forward solve", x)
    }

    /// x ← Pᵀ L⁻ᵀ x: the backward half of a solve (x in the elimination
    /// order; the result in the dofs' order).
    pub fn backward_in_place(&self, x: &mut [f64]) -> Result<(), FemError> {
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
            SymbolicCholeskyRaw::Supernodal(sym) => {
                let mut tmp = Vec::new();
                for s in (0..sym.n_supernodes()).rev() {
                    let (b, w, below, rows, l) = supernode(sym, v, s);
                    // x's rows below, gathered once for the block's columns
                    tmp.clear();
                    tmp.extend(below.iter().map(|&r| x[r]));
                    for j in 0..w {
                        let col = &l[j * rows + w..(j + 1) * rows];
                        let acc: f64 = tmp.iter().zip(col).map(|(&t, &c)| c * t).sum();
                        x[b + j] -= acc;
                    }
                    let lm = MatRef::from_column_major_slice(l, rows, w);
                    faer::linalg::triangular_solve::solve_upper_triangular_in_place(
                        lm.submatrix(0, 0, w, w).transpose(),
                        MatMut::from_column_major_slice_mut(&mut x[b..b + w], w, 1),
                        Par::Seq,
                    );
                }
            }
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
