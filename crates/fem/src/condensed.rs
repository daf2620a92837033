//! A direct solver for matrices that change only on a small set of dofs Γ
//! (the dofs of the interface elements): the rest is condensed out once.
//!
//! Why: in a contact Newton loop the bulk stiffness never changes; only the
//! interface points' tangents do, on a few thousand dofs out of 10⁵–10⁶. A
//! sparse refactorisation per status change (or a low-rank correction whose
//! columns are sparse solves of the whole system) then costs the whole
//! mesh at every iteration.
//!
//! With I the other dofs, the matrix in blocks is
//!
//! ```text
//!   A = [A_II  A_IΓ]      S = A_ΓΓ − C,   C = A_ΓI A_II⁻¹ A_IΓ
//!       [A_ΓI  A_ΓΓ]
//! ```
//!
//! One sparse Cholesky factorisation of A that eliminates I (in A_II's own
//! minimum-degree order) before Γ gives both: its trailing block is the
//! factor of S, from which the dense `C` (m × m, m = |Γ|) is built, and its
//! leading block is the factor of A_II, kept for the interior solves
//! ([`crate::solver::LeadingFactor`]); they are reused as
//! long as the rows and columns of I keep their values (checked bitwise at
//! every solve). A system is then solved by
//!
//! ```text
//!   y = A_II⁻¹ b_I,   S x_Γ = b_Γ − A_ΓI y,   x_I = y − A_II⁻¹ A_IΓ x_Γ
//! ```
//!
//! and the dense Schur system is handled like [`crate::UpdatedCholesky`]
//! handles the sparse one: a dense Cholesky factor of S is reused for a
//! later S that differs in few rows and columns of Γ, with a Woodbury
//! correction whose columns S⁻¹ e_g are dense solves (cached), refined
//! against the new S; a larger change factorises S again.

use std::collections::BTreeMap;
use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::{MatMut, MatRef, Par};
use nalgebra::{DMatrix, DVector};

use crate::error::FemError;
use crate::pattern::{CsrMatrix, SparsityPattern};
use crate::solver::{CholeskySolver, LeadingFactor, schur_complement_and_leading};
use crate::update::{SolveKind, UpdateStats};

/// Rounds of iterative refinement of a corrected Schur solution.
const REFINEMENTS: usize = 4;

/// Shift of the Γ diagonal, relative to its largest entry, while S is
/// factorised (S is only semidefinite for a body held by Γ alone).
const SCHUR_SHIFT: f64 = 1e-8;

/// Sparse Cholesky of the condensed-out dofs and dense Cholesky of the
/// Schur complement on Γ, with low-rank reuse of the latter.
#[derive(Debug)]
pub struct CondensedCholesky {
    n: usize,
    /// Γ dofs, sorted.
    gamma: Vec<usize>,
    /// I dofs, sorted.
    interior: Vec<usize>,
    /// Elimination order of I (AMD of A_II): I positions.
    ii_order: Vec<usize>,
    /// L_II, the leading block of the factorisation that built C (in
    /// `ii_order`; None: not condensed yet).
    leading: Option<LeadingFactor>,
    /// Slot in the full matrix of every stored entry of A_II.
    ii_slots: Vec<usize>,
    /// Per Γ row: its entries in I columns (I position, slot), CSR-like.
    gi_ptr: Vec<usize>,
    gi_col: Vec<usize>,
    gi_slot: Vec<usize>,
    /// Per Γ row: its entries in Γ columns (Γ position, slot), CSR-like.
    gg_ptr: Vec<usize>,
    gg_col: Vec<usize>,
    gg_slot: Vec<usize>,
    /// Values of A_II and A_ΓI when C was built (None: not built yet).
    constant_base: Option<Vec<f64>>,
    /// C = A_ΓI A_II⁻¹ A_IΓ, m × m column-major.
    c: Vec<f64>,
    /// Values of A_ΓΓ (entries in `gg_slot` order) of the factorised S.
    gg_base: Option<Vec<f64>>,
    /// Dense Cholesky factor of S (lower triangle), m × m column-major.
    factor: Vec<f64>,
    /// S⁻¹ e_g of the Γ positions met so far in a change.
    columns: BTreeMap<usize, Vec<f64>>,
    max_rank: usize,
    tolerance: f64,
    stats: UpdateStats,
    condensations: usize,
}

impl CondensedCholesky {
    /// Splits `pattern` into the dofs `gamma` (those whose rows may change
    /// from one solve to the next) and the rest, and analyses the rest.
    /// Corrections of at most `max_rank` Γ dofs reuse the dense factor.
    pub fn analyse(
        pattern: Arc<SparsityPattern>,
        gamma: &[usize],
        max_rank: usize,
    ) -> Result<Self, FemError> {
        let n = pattern.n();
        let mut gamma = gamma.to_vec();
        gamma.sort_unstable();
        gamma.dedup();
        if let Some(&d) = gamma.iter().find(|&&d| d >= n) {
            return Err(FemError::DofOutOfRange {
                what: "condensation dofs".into(),
                dof: d,
                n_dofs: n,
            });
        }
        const NONE: usize = usize::MAX;
        let mut gpos = vec![NONE; n];
        for (k, &d) in gamma.iter().enumerate() {
            gpos[d] = k;
        }
        let interior: Vec<usize> = (0..n).filter(|&d| gpos[d] == NONE).collect();
        let mut ipos = vec![NONE; n];
        for (k, &d) in interior.iter().enumerate() {
            ipos[d] = k;
        }
        let (ptr, idx) = (pattern.indptr(), pattern.indices());
        // A_II: rows and columns of I, renumbered
        let mut ii_ptr = Vec::with_capacity(interior.len() + 1);
        let mut ii_idx = Vec::new();
        let mut ii_slots = Vec::new();
        ii_ptr.push(0);
        for &d in &interior {
            for k in ptr[d]..ptr[d + 1] {
                let j = ipos[idx[k]];
                if j != NONE {
                    ii_idx.push(j);
                    ii_slots.push(k);
                }
            }
            ii_ptr.push(ii_idx.len());
        }
        let ii_pattern = Arc::new(SparsityPattern::from_csr(interior.len(), ii_ptr, ii_idx)?);
        let (mut gi_ptr, mut gi_col, mut gi_slot) = (vec![0], Vec::new(), Vec::new());
        let (mut gg_ptr, mut gg_col, mut gg_slot) = (vec![0], Vec::new(), Vec::new());
        for &d in &gamma {
            for (k, &j) in idx.iter().enumerate().take(ptr[d + 1]).skip(ptr[d]) {
                if gpos[j] != NONE {
                    gg_col.push(gpos[j]);
                    gg_slot.push(k);
                } else {
                    gi_col.push(ipos[j]);
                    gi_slot.push(k);
                }
            }
            gi_ptr.push(gi_col.len());
            gg_ptr.push(gg_col.len());
        }
        let m = gamma.len();
        Ok(CondensedCholesky {
            n,
            gamma,
            interior,
            ii_order: CholeskySolver::analyse(ii_pattern)?.ordering(),
            leading: None,
            ii_slots,
            gi_ptr,
            gi_col,
            gi_slot,
            gg_ptr,
            gg_col,
            gg_slot,
            constant_base: None,
            c: vec![0.0; m * m],
            gg_base: None,
            factor: vec![0.0; m * m],
            columns: BTreeMap::new(),
            max_rank,
            tolerance: 1e-10,
            stats: UpdateStats::default(),
            condensations: 0,
        })
    }

    /// Number of Γ dofs (the size of the dense Schur system).
    pub fn schur_size(&self) -> usize {
        self.gamma.len()
    }

    /// How the systems so far were solved; a factorisation is one of the
    /// dense Schur system (the condensations are counted apart).
    pub fn stats(&self) -> UpdateStats {
        self.stats
    }

    /// How many times the bulk was factorised and C built.
    pub fn condensations(&self) -> usize {
        self.condensations
    }

    /// Solves `matrix · x = rhs` in place (rhs ← x). `matrix` must be
    /// symmetric positive definite with the analysed pattern.
    pub fn solve(&mut self, matrix: &CsrMatrix, rhs: &mut [f64]) -> Result<SolveKind, FemError> {
        self.solve_within(matrix, rhs, 0.0)
    }

    /// [`CondensedCholesky::solve`], where a corrected Schur solution is
    /// refined only until its residual is at most the larger of `accept`
    /// (absolute) and 1e-10 of the right-hand side.
    pub fn solve_within(
        &mut self,
        matrix: &CsrMatrix,
        rhs: &mut [f64],
        accept: f64,
    ) -> Result<SolveKind, FemError> {
        if matrix.n() != self.n || rhs.len() != self.n {
            return Err(FemError::LengthMismatch {
                what: "condensed system".into(),
                got: rhs.len().min(matrix.n()),
                expected: self.n,
            });
        }
        let v = matrix.values();
        if !self.constant_unchanged(v) {
            self.condense(matrix)?;
        }
        let m = self.gamma.len();
        // y = A_II⁻¹ b_I, s = b_Γ − A_ΓI y
        let mut y: Vec<f64> = self.interior.iter().map(|&d| rhs[d]).collect();
        self.solve_interior(&mut y)?;
        let mut s: Vec<f64> = self.gamma.iter().map(|&d| rhs[d]).collect();
        for (a, sa) in s.iter_mut().enumerate() {
            for k in self.gi_ptr[a]..self.gi_ptr[a + 1] {
                *sa -= v[self.gi_slot[k]] * y[self.gi_col[k]];
            }
        }
        let gg: Vec<f64> = self.gg_slot.iter().map(|&k| v[k]).collect();
        let (kind, _) = self.schur_solve(&gg, &mut s, accept)?;
        // x_I = y − A_II⁻¹ A_IΓ x_Γ
        let mut t = vec![0.0; self.interior.len()];
        for (a, &xa) in s.iter().enumerate() {
            if xa != 0.0 {
                for k in self.gi_ptr[a]..self.gi_ptr[a + 1] {
                    t[self.gi_col[k]] += v[self.gi_slot[k]] * xa;
                }
            }
        }
        self.solve_interior(&mut t)?;
        for ((&d, yi), ti) in self.interior.iter().zip(&y).zip(&t) {
            rhs[d] = yi - ti;
        }
        for (&d, &x) in self.gamma.iter().zip(&s) {
            rhs[d] = x;
        }
        debug_assert_eq!(s.len(), m);
        Ok(kind)
    }

    /// Condenses `matrix` (factorises it [I, Γ] and builds C) unless its rows
    /// and columns of I hold the values of the last condensation; true if
    /// it condensed anew. For the Γ-space operations below.
    pub fn prepare(&mut self, matrix: &CsrMatrix) -> Result<bool, FemError> {
        if matrix.n() != self.n {
            return Err(FemError::LengthMismatch {
                what: "condensed system".into(),
                got: matrix.n(),
                expected: self.n,
            });
        }
        if self.constant_unchanged(matrix.values()) {
            return Ok(false);
        }
        self.condense(matrix)?;
        Ok(true)
    }

    /// The Γ dofs, sorted (Γ position k is dof `gamma()[k]`).
    pub fn gamma(&self) -> &[usize] {
        &self.gamma
    }

    /// The condensed-out dofs I, sorted.
    pub fn interior(&self) -> &[usize] {
        &self.interior
    }

    /// The stored Γ × Γ entries, row by row: per Γ row `a` the entries
    /// `ptr[a]..ptr[a + 1]`, each with its Γ column and its slot in the
    /// full matrix. The Γ-space operations take A_ΓΓ as values in this
    /// order.
    pub fn gamma_entries(&self) -> (&[usize], &[usize], &[usize]) {
        (&self.gg_ptr, &self.gg_col, &self.gg_slot)
    }

    /// Solves S x = s in place, S = A_ΓΓ − C with A_ΓΓ given as `gg`
    /// (values in [`CondensedCholesky::gamma_entries`] order); the dense
    /// factor is reused with a Woodbury correction as by
    /// [`CondensedCholesky::solve_within`]. Also returns S x: the product
    /// the refinement checked, or the right-hand side after a solve with a
    /// factor of S itself (equal to within its backward error).
    pub fn solve_schur(
        &mut self,
        gg: &[f64],
        s: &mut [f64],
        accept: f64,
    ) -> Result<(SolveKind, Vec<f64>), FemError> {
        if self.constant_base.is_none() {
            return Err(FemError::NotFactorised);
        }
        let b = s.to_vec();
        let (kind, sx) = self.schur_solve(gg, s, accept)?;
        Ok((kind, sx.unwrap_or(b)))
    }

    /// C = A_ΓI A_II⁻¹ A_IΓ of the last condensation, m × m column-major
    /// and exactly symmetric (zero before the first one).
    pub fn coupling_matrix(&self) -> &[f64] {
        &self.c
    }

    /// S x, S = A_ΓΓ (values `gg`) − C.
    pub fn mul_schur(&self, gg: &[f64], x: &[f64]) -> Vec<f64> {
        self.schur_mul(gg, x)
    }

    /// x ← S⁻¹ x by a dense partial-pivoting LU (faer) of S = A_ΓΓ − C,
    /// A_ΓΓ given as `gg` (values in [`CondensedCholesky::gamma_entries`]
    /// order, symmetric or not). The direct fall-back of the iterative
    /// solves of a non-symmetric Schur system: O(m³), made afresh at
    /// every call, nothing kept.
    pub fn solve_schur_lu(&self, gg: &[f64], x: &mut [f64]) -> Result<(), FemError> {
        use faer::prelude::Solve;
        if self.constant_base.is_none() {
            return Err(FemError::NotFactorised);
        }
        let m = self.gamma.len();
        if x.len() != m || gg.len() != self.gg_col.len() {
            return Err(FemError::LengthMismatch {
                what: "dense Schur solve".into(),
                got: x.len(),
                expected: m,
            });
        }
        // C is exactly symmetric: row or column order alike
        let mut s = faer::Mat::<f64>::from_fn(m, m, |i, j| -self.c[i * m + j]);
        for a in 0..m {
            for k in self.gg_ptr[a]..self.gg_ptr[a + 1] {
                s[(a, self.gg_col[k])] += gg[k];
            }
        }
        let rhs = faer::Mat::<f64>::from_fn(m, 1, |i, _| x[i]);
        let y = s.partial_piv_lu().solve(&rhs);
        for (i, v) in x.iter_mut().enumerate() {
            *v = y[(i, 0)];
        }
        if x.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(FemError::Solver(
                "the dense LU of the Schur system is singular".into(),
            ))
        }
    }

    /// x ← A_II⁻¹ x for a vector over I.
    pub fn solve_interior(&self, x: &mut [f64]) -> Result<(), FemError> {
        let leading = self.leading.as_ref().ok_or(FemError::NotFactorised)?;
        if x.len() != leading.n() {
            return Err(FemError::LengthMismatch {
                what: "interior solve".into(),
                got: x.len(),
                expected: leading.n(),
            });
        }
        let mut y: Vec<f64> = self.ii_order.iter().map(|&k| x[k]).collect();
        leading.solve(&mut y)?;
        for (&k, v) in self.ii_order.iter().zip(y) {
            x[k] = v;
        }
        Ok(())
    }

    /// A_ΓI y for a vector y over I (the values of the last condensation).
    pub fn mul_gamma_interior(&self, y: &[f64]) -> Vec<f64> {
        let gi = self.gi_values();
        (0..self.gamma.len())
            .map(|a| {
                (self.gi_ptr[a]..self.gi_ptr[a + 1])
                    .map(|k| gi[k] * y[self.gi_col[k]])
                    .sum()
            })
            .collect()
    }

    /// A_IΓ x for a vector x over Γ (the values of the last condensation).
    pub fn mul_interior_gamma(&self, x: &[f64]) -> Vec<f64> {
        let gi = self.gi_values();
        let mut t = vec![0.0; self.interior.len()];
        for (a, &xa) in x.iter().enumerate() {
            if xa != 0.0 {
                for k in self.gi_ptr[a]..self.gi_ptr[a + 1] {
                    t[self.gi_col[k]] += gi[k] * xa;
                }
            }
        }
        t
    }

    /// Values of A_ΓI (in `gi` order) of the last condensation.
    fn gi_values(&self) -> &[f64] {
        self.constant_base
            .as_deref()
            .map_or(&[][..], |b| &b[self.ii_slots.len()..])
    }

    /// True if A_II and A_ΓI hold the values C was built with.
    fn constant_unchanged(&self, v: &[f64]) -> bool {
        let Some(base) = &self.constant_base else {
            return false;
        };
        let bits = self
            .ii_slots
            .iter()
            .chain(&self.gi_slot)
            .zip(base)
            .fold(0u64, |acc, (&k, b)| acc | (v[k].to_bits() ^ b.to_bits()));
        bits == 0
    }

    /// Factorises the matrix [I, Γ] (keeping L_II) and builds C; the dense
    /// factor of S is dropped.
    fn condense(&mut self, matrix: &CsrMatrix) -> Result<(), FemError> {
        self.constant_base = None;
        self.gg_base = None;
        self.leading = None;
        let v = matrix.values();
        let m = self.gamma.len();
        // C = A_ΓΓ − S, with S from one factorisation that eliminates I (in
        // A_II's own order) before Γ; its leading block serves the solves
        // with A_II
        let order: Vec<usize> = self.ii_order.iter().map(|&k| self.interior[k]).collect();
        let max_diag = self
            .gamma
            .iter()
            .filter_map(|&d| matrix.pattern().slot(d, d))
            .map(|k| v[k].abs())
            .fold(0.0, f64::max);
        let shift = (SCHUR_SHIFT * max_diag).max(f64::MIN_POSITIVE);
        // S into the storage of C, then C = A_ΓΓ − S
        let leading =
            schur_complement_and_leading(matrix, &order, &self.gamma, shift, &mut self.c)?;
        self.leading = Some(leading);
        for c in self.c.iter_mut() {
            *c = -*c;
        }
        for a in 0..m {
            for k in self.gg_ptr[a]..self.gg_ptr[a + 1] {
                self.c[self.gg_col[k] * m + a] += v[self.gg_slot[k]];
            }
        }
        // exact symmetry (the two triangles differ by round-off)
        for j in 0..m {
            for i in j + 1..m {
                let avg = 0.5 * (self.c[j * m + i] + self.c[i * m + j]);
                self.c[j * m + i] = avg;
                self.c[i * m + j] = avg;
            }
        }
        self.constant_base = Some(
            self.ii_slots
                .iter()
                .chain(&self.gi_slot)
                .map(|&k| v[k])
                .collect(),
        );
        self.gg_base = None;
        self.columns.clear();
        self.condensations += 1;
        Ok(())
    }

    /// Solves S x = s in place, S = A_ΓΓ (values `gg`) − C.
    fn schur_solve(
        &mut self,
        gg: &[f64],
        s: &mut [f64],
        accept: f64,
    ) -> Result<(SolveKind, Option<Vec<f64>>), FemError> {
        if let Some(changed) = self.changed_gamma(gg) {
            if changed.is_empty() {
                self.factor_solve(s);
                self.stats.reused += 1;
                return Ok((SolveKind::Reused, None));
            }
            let b = s.to_vec();
            if changed.len() <= self.max_rank
                && let Some(sx) = self.refined_solve(gg, &changed, s, &b, accept)
            {
                self.stats.corrected += 1;
                return Ok((SolveKind::Corrected(changed.len()), Some(sx)));
            }
            s.copy_from_slice(&b);
        }
        self.factorise(gg)?;
        self.factor_solve(s);
        Ok((SolveKind::Factorised, None))
    }

    /// Γ positions whose rows differ from the factorised S (None: nothing
    /// factorised, or a change that is not symmetric in its dofs).
    fn changed_gamma(&self, gg: &[f64]) -> Option<Vec<usize>> {
        let base = self.gg_base.as_ref()?;
        let m = self.gamma.len();
        let rows: Vec<usize> = (0..m)
            .filter(|&a| {
                (self.gg_ptr[a]..self.gg_ptr[a + 1])
                    .any(|k| gg[k].to_bits() != base[k].to_bits() && gg[k] != base[k])
            })
            .collect();
        for &a in &rows {
            for k in self.gg_ptr[a]..self.gg_ptr[a + 1] {
                if gg[k] != base[k] && rows.binary_search(&self.gg_col[k]).is_err() {
                    return None;
                }
            }
        }
        Some(rows)
    }

    /// Dense Cholesky of S = A_ΓΓ − C.
    fn factorise(&mut self, gg: &[f64]) -> Result<(), FemError> {
        let m = self.gamma.len();
        for (f, c) in self.factor.iter_mut().zip(&self.c) {
            *f = -c;
        }
        for a in 0..m {
            let row = self.gg_ptr[a]..self.gg_ptr[a + 1];
            for (&b, &g) in self.gg_col[row.clone()].iter().zip(&gg[row]) {
                self.factor[b * m + a] += g;
            }
        }
        self.gg_base = None;
        self.columns.clear();
        if let Err(index) = blocked_cholesky(&mut self.factor, m) {
            return Err(FemError::NotPositiveDefinite {
                pivot: index,
                dof: self.gamma.get(index).copied().unwrap_or(index),
                hint: "check for an unconstrained body or an indefinite tangent (use LU)".into(),
            });
        }
        self.gg_base = Some(gg.to_vec());
        self.stats.factorisations += 1;
        Ok(())
    }

    /// Solves with the dense factor, `k` columns stored one after another
    /// (in fixed blocks of columns, one sequential solve each).
    fn factor_solve_many(&self, x: &mut [f64], k: usize) {
        use rayon::prelude::*;
        let m = self.gamma.len();
        if m == 0 || k == 0 {
            return;
        }
        let l = MatRef::from_column_major_slice(&self.factor, m, m);
        x.par_chunks_mut(SOLVE_BLOCK * m).for_each(|chunk| {
            let cols = chunk.len() / m;
            let mut buf =
                MemBuffer::new(llt::solve::solve_in_place_scratch::<f64>(m, cols, Par::Seq));
            llt::solve::solve_in_place(
                l,
                MatMut::from_column_major_slice_mut(chunk, m, cols),
                Par::Seq,
                MemStack::new(&mut buf),
            );
        });
    }

    fn factor_solve(&self, x: &mut [f64]) {
        self.factor_solve_many(x, 1);
    }

    /// S x with S = A_ΓΓ (values `gg`) − C. C is symmetric, so entry a of
    /// C x is column a of C dotted with x: contiguous, one task per block
    /// of columns, each dot in a fixed order (the same bits on any number
    /// of threads).
    fn schur_mul(&self, gg: &[f64], x: &[f64]) -> Vec<f64> {
        use rayon::prelude::*;
        let m = self.gamma.len();
        let mut y = vec![0.0; m];
        y.par_chunks_mut(SCHUR_MUL_CHUNK)
            .enumerate()
            .for_each(|(c, out)| {
                for (i, ya) in out.iter_mut().enumerate() {
                    let a = c * SCHUR_MUL_CHUNK + i;
                    let mut acc = -dot8(&self.c[a * m..(a + 1) * m], x);
                    for k in self.gg_ptr[a]..self.gg_ptr[a + 1] {
                        acc += gg[k] * x[self.gg_col[k]];
                    }
                    *ya = acc;
                }
            });
        y
    }

    /// Woodbury solve refined against the new S; S x if the residual
    /// reached the tolerance (or `accept`, absolute, if larger).
    fn refined_solve(
        &mut self,
        gg: &[f64],
        changed: &[usize],
        x: &mut [f64],
        b: &[f64],
        accept: f64,
    ) -> Option<Vec<f64>> {
        if !self.corrected_solve(gg, changed, x) {
            return None;
        }
        let target = (self.tolerance * norm(b).max(f64::MIN_POSITIVE)).max(accept);
        for _ in 0..REFINEMENTS {
            let sx = self.schur_mul(gg, x);
            let mut r: Vec<f64> = b.iter().zip(&sx).map(|(p, q)| p - q).collect();
            if norm(&r) <= target {
                return Some(sx);
            }
            if !self.corrected_solve(gg, changed, &mut r) {
                return None;
            }
            for (xi, d) in x.iter_mut().zip(&r) {
                *xi += d;
            }
        }
        let sx = self.schur_mul(gg, x);
        let r: Vec<f64> = b.iter().zip(&sx).map(|(p, q)| p - q).collect();
        (norm(&r) <= target).then_some(sx)
    }

    /// x ← S⁻¹ x by the factorised S and a Woodbury correction on
    /// `changed`; false if the small system is singular.
    fn corrected_solve(&mut self, gg: &[f64], changed: &[usize], x: &mut [f64]) -> bool {
        let Some(base) = &self.gg_base else {
            return false;
        };
        let m = self.gamma.len();
        let r = changed.len();
        let mut dm = DMatrix::<f64>::zeros(r, r);
        for (a, &g) in changed.iter().enumerate() {
            for k in self.gg_ptr[g]..self.gg_ptr[g + 1] {
                if let Ok(b) = changed.binary_search(&self.gg_col[k]) {
                    dm[(a, b)] = gg[k] - base[k];
                }
            }
        }
        let new: Vec<usize> = changed
            .iter()
            .copied()
            .filter(|g| !self.columns.contains_key(g))
            .collect();
        if !new.is_empty() {
            let mut block = vec![0.0; m * new.len()];
            for (c, &g) in new.iter().enumerate() {
                block[c * m + g] = 1.0;
            }
            self.factor_solve_many(&mut block, new.len());
            for (c, &g) in new.iter().enumerate() {
                self.columns.insert(g, block[c * m..(c + 1) * m].to_vec());
            }
        }
        self.factor_solve(x);
        let cols: Vec<&Vec<f64>> = changed.iter().map(|g| &self.columns[g]).collect();
        let wd = DMatrix::from_fn(r, r, |a, b| cols[b][changed[a]]);
        let xd = DVector::from_iterator(r, changed.iter().map(|&g| x[g]));
        let cap = DMatrix::<f64>::identity(r, r) + &dm * &wd;
        let Some(z) = cap.lu().solve(&(&dm * xd)) else {
            return false;
        };
        for (b, col) in cols.iter().enumerate() {
            let zb = z[b];
            if zb != 0.0 {
                for (xi, w) in x.iter_mut().zip(col.iter()) {
                    *xi -= w * zb;
                }
            }
        }
        true
    }
}

/// Columns per task of the multi-column dense solves.
const SOLVE_BLOCK: usize = 16;

/// Block size of [`blocked_cholesky`].
const CHOLESKY_BLOCK: usize = 192;

/// Cholesky factorisation in place of the dense m × m column-major `a`
/// (lower triangle), right-looking by blocks of [`CHOLESKY_BLOCK`]: each
/// diagonal block, panel row block and trailing column block is one
/// sequential faer kernel call, the independent ones run in parallel. faer's
/// own parallel kernels round differently on different thread counts; in
/// this fixed partition every entry is computed by the same operations in
/// the same order whatever the thread count. Err: the index of a pivot
/// that is not positive.
fn blocked_cholesky(a: &mut [f64], m: usize) -> Result<(), usize> {
    use rayon::prelude::*;
    let nb = CHOLESKY_BLOCK;
    let mut j0 = 0;
    while j0 < m {
        let jb = nb.min(m - j0);
        let (left, right) = a.split_at_mut((j0 + jb) * m);
        let panel_cols = &mut left[j0 * m..];
        // the diagonal block
        {
            let d =
                MatMut::from_column_major_slice_with_stride_mut(&mut panel_cols[j0..], jb, jb, m);
            let req =
                llt::factor::cholesky_in_place_scratch::<f64>(jb, Par::Seq, Default::default());
            let mut buf = MemBuffer::new(req);
            if let Err(llt::factor::LltError::NonPositivePivot { index }) =
                llt::factor::cholesky_in_place(
                    d,
                    Default::default(),
                    Par::Seq,
                    MemStack::new(&mut buf),
                    Default::default(),
                )
            {
                return Err(j0 + index);
            }
        }
        let below = m - j0 - jb;
        if below == 0 {
            break;
        }
        // the panel below it: X L_jjᵀ = A, i.e. L_jj Xᵀ = Aᵀ, by row blocks
        {
            // (a copy: the diagonal block shares its columns with the panel)
            let mut diag = vec![0.0; jb * jb];
            for c in 0..jb {
                diag[c * jb..(c + 1) * jb]
                    .copy_from_slice(&panel_cols[c * m + j0..c * m + j0 + jb]);
            }
            let l_jj = MatRef::from_column_major_slice(&diag, jb, jb);
            let p = MatMut::from_column_major_slice_with_stride_mut(
                &mut panel_cols[j0 + jb..],
                below,
                jb,
                m,
            );
            let mut blocks = Vec::new();
            let mut rest = p;
            while rest.nrows() > 0 {
                let rows = nb.min(rest.nrows());
                let (top, bottom) = rest.split_at_row_mut(rows);
                blocks.push(top);
                rest = bottom;
            }
            blocks.into_par_iter().for_each(|block| {
                faer::linalg::triangular_solve::solve_lower_triangular_in_place(
                    l_jj,
                    block.transpose_mut(),
                    Par::Seq,
                );
            });
        }
        // the trailing matrix, by column blocks: A[c.., C] −= P[c.., :] P[C, :]ᵀ
        let p = MatRef::from_column_major_slice_with_stride(&panel_cols[j0 + jb..], below, jb, m);
        right
            .par_chunks_mut(nb * m)
            .enumerate()
            .for_each(|(b, chunk)| {
                let cols = chunk.len() / m;
                let c0 = b * nb;
                let target = MatMut::from_column_major_slice_with_stride_mut(
                    &mut chunk[j0 + jb + c0..],
                    below - c0,
                    cols,
                    m,
                );
                faer::linalg::matmul::matmul(
                    target,
                    faer::Accum::Add,
                    p.subrows(c0, below - c0),
                    p.subrows(c0, cols).transpose(),
                    -1.0,
                    Par::Seq,
                );
            });
        j0 += jb;
    }
    Ok(())
}

/// Columns of C per task of [`CondensedCholesky::schur_mul`].
const SCHUR_MUL_CHUNK: usize = 64;

/// Dot product with eight partial sums (vectorises; a fixed order).
fn dot8(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0f64; 8];
    let (ca, cb) = (a.chunks_exact(8), b.chunks_exact(8));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (p, q) in ca.zip(cb) {
        for l in 0..8 {
            acc[l] += p[l] * q[l];
        }
    }
    let mut tail = 0.0;
    for (p, q) in ra.iter().zip(rb) {
        tail += p * q;
    }
    ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) + tail
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A 2D 5-point Laplacian on a k × k grid with a shift: SPD, n = k².
    pub(crate) fn grid(k: usize) -> CsrMatrix {
        let n = k * k;
        let mut pairs = Vec::new();
        for i in 0..k {
            for j in 0..k {
                let p = i * k + j;
                if j + 1 < k {
                    pairs.extend([p, p + 1]);
                }
                if i + 1 < k {
                    pairs.extend([p, p + k]);
                }
            }
        }
        let pattern = Arc::new(SparsityPattern::from_blocks(n, &[(2, &pairs)]).unwrap());
        let mut m = CsrMatrix::zeros(pattern);
        for p in 0..n {
            set(&mut m, p, p, 4.2);
            for q in [p + 1, p + k] {
                if q < n && m.pattern().slot(p, q).is_some() {
                    set(&mut m, p, q, -1.0);
                    set(&mut m, q, p, -1.0);
                }
            }
        }
        m
    }

    fn set(m: &mut CsrMatrix, i: usize, j: usize, v: f64) {
        let k = m.pattern().slot(i, j).unwrap();
        m.values_mut()[k] = v;
    }

    fn add(m: &mut CsrMatrix, i: usize, j: usize, d: f64) {
        let v = m.get(i, j);
        set(m, i, j, v + d);
    }

    fn solve_fresh(m: &CsrMatrix, b: &[f64]) -> Vec<f64> {
        let mut c = CholeskySolver::analyse(m.pattern().clone()).unwrap();
        c.factorise(m).unwrap();
        let mut x = b.to_vec();
        c.solve(&mut x).unwrap();
        x
    }

    fn max_err(x: &[f64], y: &[f64]) -> f64 {
        x.iter()
            .zip(y)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn the_dense_lu_solves_a_non_symmetric_schur_system() {
        let k = 12;
        let a = grid(k);
        let gamma: Vec<usize> = (0..k).map(|j| (k / 2) * k + j).collect();
        let mut s = CondensedCholesky::analyse(a.pattern().clone(), &gamma, 4).unwrap();
        let mut x = vec![1.0; k];
        // nothing condensed yet
        assert!(matches!(
            s.solve_schur_lu(&[], &mut x),
            Err(FemError::NotFactorised)
        ));
        assert!(s.prepare(&a).unwrap());
        let (ptr, col, slot) = s.gamma_entries();
        let gg0: Vec<f64> = slot.iter().map(|&q| a.values()[q]).collect();
        // a non-symmetric change on Γ (like the coupled friction term)
        let mut gg = gg0.clone();
        for r in 0..k {
            for q in ptr[r]..ptr[r + 1] {
                if col[q] == r + 1 {
                    gg[q] += 0.7;
                }
            }
        }
        let b: Vec<f64> = (0..k).map(|i| (i as f64).sin() + 0.5).collect();
        let mut x = b.clone();
        s.solve_schur_lu(&gg, &mut x).unwrap();
        let err = max_err(&s.mul_schur(&gg, &x), &b);
        assert!(err < 1e-12, "{err:e}");
        // on the symmetric system it agrees with the Cholesky Schur solve
        let mut x_lu = b.clone();
        s.solve_schur_lu(&gg0, &mut x_lu).unwrap();
        let mut x_ch = b.clone();
        s.solve_schur(&gg0, &mut x_ch, 0.0).unwrap();
        assert!(max_err(&x_lu, &x_ch) < 1e-12, "{:e}", max_err(&x_lu, &x_ch));
        let mut short = vec![0.0; k - 1];
        assert!(matches!(
            s.solve_schur_lu(&gg, &mut short),
            Err(FemError::LengthMismatch { .. })
        ));
    }

    #[test]
    fn condensed_solves_match_fresh_factorisations_through_changes_on_gamma() {
        let k = 20;
        let a = grid(k);
        let n = k * k;
        // Γ: the middle row of the grid (an "interface" across the domain)
        let gamma: Vec<usize> = (0..k).map(|j| (k / 2) * k + j).collect();
        let b: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64) - 5.0).collect();
        let mut s = CondensedCholesky::analyse(a.pattern().clone(), &gamma, 4).unwrap();
        assert_eq!(s.schur_size(), k);
        let mut x = b.clone();
        assert_eq!(s.solve(&a, &mut x).unwrap(), SolveKind::Factorised);
        let exact = solve_fresh(&a, &b);
        let scale = exact.iter().map(|v| v.abs()).fold(0.0, f64::max);
        assert!(max_err(&x, &exact) < 1e-13 * scale);
        let mut x = b.clone();
        assert_eq!(s.solve(&a, &mut x).unwrap(), SolveKind::Reused);
        // a stiff spring between two Γ dofs: corrected
        let (g1, g2) = (gamma[3], gamma[4]);
        let mut a2 = a.clone();
        for (i, j, d) in [(g1, g1, 1e6), (g2, g2, 1e6), (g1, g2, -1e6), (g2, g1, -1e6)] {
            add(&mut a2, i, j, d);
        }
        let mut x = b.clone();
        assert_eq!(s.solve(&a2, &mut x).unwrap(), SolveKind::Corrected(2));
        // a corrected solve is refined to 1e-10 of the right-hand side
        let r = crate::solver::relative_residual(&a2, &x, &b);
        assert!(r < 1e-10, "{r:e}");
        // more than 4 Γ dofs change: the Schur system is factorised again
        let mut a3 = a2.clone();
        for &g in &gamma[8..14] {
            add(&mut a3, g, g, 3.0);
        }
        let mut x = b.clone();
        assert_eq!(s.solve(&a3, &mut x).unwrap(), SolveKind::Factorised);
        let exact = solve_fresh(&a3, &b);
        // (the stiff spring makes the condition number about 1e6)
        assert!(
            max_err(&x, &exact) < 1e-9 * scale,
            "{:e}",
            max_err(&x, &exact)
        );
        assert_eq!(s.condensations(), 1);
        // a change off Γ: condensed again
        let mut a4 = a3.clone();
        add(&mut a4, 0, 0, 1.0);
        let mut x = b.clone();
        assert_eq!(s.solve(&a4, &mut x).unwrap(), SolveKind::Factorised);
        assert_eq!(s.condensations(), 2);
        let exact = solve_fresh(&a4, &b);
        // (the stiff spring makes the condition number about 1e6)
        assert!(
            max_err(&x, &exact) < 1e-9 * scale,
            "{:e}",
            max_err(&x, &exact)
        );
    }

    #[test]
    fn an_indefinite_schur_system_names_a_gamma_dof() {
        let k = 6;
        let mut a = grid(k);
        let gamma = [14usize, 15];
        add(&mut a, 15, 15, -10.0);
        let mut s = CondensedCholesky::analyse(a.pattern().clone(), &gamma, 4).unwrap();
        let mut x = vec![1.0; k * k];
        match s.solve(&a, &mut x) {
            Err(FemError::NotPositiveDefinite { dof, .. }) => assert!(gamma.contains(&dof)),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn the_blocked_cholesky_matches_faer_and_not_the_thread_count() {
        // an SPD matrix B Bᵀ + m I of size 500 (blocks of 192: a partial
        // last block), pseudo-random entries
        let m = 500;
        let b: Vec<f64> = (0..m * m)
            .map(|i| ((i as u64 * 2654435761 % 1000) as f64) / 1000.0 - 0.5)
            .collect();
        let bm = faer::MatRef::from_column_major_slice(&b, m, m);
        let mut a = vec![0.0; m * m];
        faer::linalg::matmul::matmul(
            MatMut::from_column_major_slice_mut(&mut a, m, m),
            faer::Accum::Replace,
            bm,
            bm.transpose(),
            1.0,
            Par::Seq,
        );
        for i in 0..m {
            a[i * m + i] += m as f64;
        }
        let mut reference = a.clone();
        let req = llt::factor::cholesky_in_place_scratch::<f64>(m, Par::Seq, Default::default());
        llt::factor::cholesky_in_place(
            MatMut::from_column_major_slice_mut(&mut reference, m, m),
            Default::default(),
            Par::Seq,
            MemStack::new(&mut MemBuffer::new(req)),
            Default::default(),
        )
        .unwrap();
        let factor = |threads: usize| {
            let mut f = a.clone();
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| blocked_cholesky(&mut f, m))
                .unwrap();
            f
        };
        let (one, three) = (factor(1), factor(3));
        let scale = reference.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for j in 0..m {
            for i in j..m {
                let k = j * m + i;
                assert_eq!(one[k].to_bits(), three[k].to_bits(), "({i}, {j})");
                assert!((one[k] - reference[k]).abs() < 1e-12 * scale, "({i}, {j})");
            }
        }
        // a matrix that is not positive definite names its pivot
        let mut bad = a.clone();
        bad[300 * m + 300] = -1.0;
        assert_eq!(blocked_cholesky(&mut bad, m), Err(300));
    }
}
