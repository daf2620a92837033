//! Sparse direct solvers through `faer`: symbolic analysis once, numeric
//! refactorisation whenever the values change, many solves.
//!
//! * [`CholeskySolver`]: LLᵀ with a fill-reducing ordering (AMD, or nested
//!   dissection for large systems) for symmetric positive
//!   definite systems (conduction, elasticity with stick/linear joints).
//! * [`LuSolver`]: LU with partial pivoting for general systems (the
//!   non-symmetric friction tangent).
//!
//! The CSR arrays are handed to faer without a copy: a structurally symmetric
//! CSR pattern is the CSC pattern of the transpose, so the values are those
//! of Aᵀ in CSC form. Cholesky reads the lower triangle of Aᵀ (the upper of
//! A, equal for symmetric A); LU factorises Aᵀ and solves with the transpose.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::error::FemError;
use crate::pattern::{CsrMatrix, SparsityPattern};

/// Systems smaller than this are factorised and solved on one thread: on
/// the 2-core reference machine faer's parallel supernodal factorisation of
/// a 2D plane-strain system is slower below ~1e6 unknowns (1.0e5 dofs:
/// numeric 0.21 s serial vs 0.29 s on 2 threads; 1.0e6: 5.55 s vs 5.29 s),
/// and in a Newton loop the idle threads' spinning costs more again.
const PARALLEL_MIN_UNKNOWNS: usize = 500_000;

/// Systems of at least this many unknowns are also ordered by nested
/// dissection ([`crate::ordering`]), and the order whose factor holds fewer
/// entries is kept. Measured (factor entries, AMD against nested
/// dissection): the order-2 `t2.5e5` vessel's thermal system (506 198
/// unknowns) 48.8 against 34.2 million, its elastic system (1 012 396)
/// 187 against 128 million, the condensed interior of it 151 against 112
/// million; the graded g2 thermal system (92 202) 4.50 against 3.34
/// million; `t1e5`'s thermal system (50 600) 2.77 against 2.53 million,
/// the condensed interior of its elastic system (99 360) 7.36 against 7.52
/// million (AMD kept). Below about 10⁵ unknowns AMD mostly wins (g1's
/// thermal system, 23 766 unknowns: 0.62 against 0.71 million); systems
/// under the threshold keep AMD alone, and their answers bit for bit.
pub const NESTED_DISSECTION_MIN_UNKNOWNS: usize = 50_000;

/// faer parallelism for a system of `n` unknowns.
fn par(n: usize) -> Par {
    let t = rayon::current_num_threads();
    if t <= 1 || n < PARALLEL_MIN_UNKNOWNS {
        Par::Seq
    } else {
        Par::rayon(t)
    }
}

/// The CSR pattern viewed as a CSC pattern (valid by construction: sorted,
/// in-range indices).
fn symbolic_view(p: &SparsityPattern) -> SymbolicSparseColMatRef<'_, usize> {
    SymbolicSparseColMatRef::new_checked(p.n(), p.n(), p.indptr(), None, p.indices())
}

/// The analysed pattern, checked cheaply when the matrix shares it.
fn same_pattern(
    matrix: &CsrMatrix,
    pattern: &std::sync::Arc<SparsityPattern>,
) -> Result<(), FemError> {
    if std::sync::Arc::ptr_eq(matrix.pattern(), pattern) || **matrix.pattern() == **pattern {
        Ok(())
    } else {
        Err(FemError::Solver(
            "matrix pattern differs from the analysed one".into(),
        ))
    }
}

fn scratch(req: faer::dyn_stack::StackReq) -> Result<MemBuffer, FemError> {
    MemBuffer::try_new(req).map_err(|_| FemError::Solver("out of memory for solver scratch".into()))
}

pub(crate) fn check_finite(what: &str, v: &[f64]) -> Result<(), FemError> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(FemError::NonFinite {
            what: what.into(),
            index,
        }),
        None => Ok(()),
    }
}

fn as_col(rhs: &mut [f64]) -> MatMut<'_, f64> {
    let n = rhs.len();
    MatMut::from_column_major_slice_mut(rhs, n, 1)
}

/// The fill-reducing elimination order of a [`CholeskySolver`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FillOrdering {
    /// Approximate minimum degree (faer's).
    Amd,
    /// Nested dissection ([`crate::ordering::nested_dissection`]).
    NestedDissection,
    /// AMD; from [`NESTED_DISSECTION_MIN_UNKNOWNS`] unknowns on, whichever
    /// of AMD and nested dissection gives the factor with fewer entries.
    Auto,
}

/// Sparse Cholesky (LLᵀ) of a symmetric positive definite matrix.
#[derive(Debug)]
pub struct CholeskySolver {
    pattern: std::sync::Arc<SparsityPattern>,
    symbolic: std::sync::Arc<SymbolicCholesky<usize>>,
    /// The supernode of each column of a supernodal factor (empty for a
    /// simplicial one), for the forward solves of unit vectors.
    supernode_of: std::sync::Arc<Vec<u32>>,
    /// The matrix in the elimination order (None: no permutation), and
    /// the values gathered into it at the last factorisation.
    permuted: Option<std::sync::Arc<Permuted>>,
    gathered: Vec<f64>,
    l_values: Vec<f64>,
    factorised: bool,
}

/// The triangle of the analysed matrix that faer's numeric factorisation
/// reads, in the elimination order: its pattern, found once per analysis,
/// and for each of its entries the CSR entry it comes from. A numeric
/// factorisation then gathers the values, where faer's own entry point
/// permutes the whole matrix again (pattern included) every time: about
/// 40 % of a factorisation of the default vessel's elastic system. The
/// pattern is faer's own permutation of it, so the factor is the same bit
/// for bit.
#[derive(Debug)]
struct Permuted {
    /// The pattern, checked once here (faer's view of it is free).
    pattern: faer::sparse::SymbolicSparseColMat<usize>,
    source: Vec<u32>,
}

impl Permuted {
    /// None when the analysis has no permutation (or the matrix has 2³²
    /// entries or more: faer's own permutation then).
    fn new(pattern: &SparsityPattern, symbolic: &SymbolicCholesky<usize>) -> Option<Self> {
        use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
        let perm = symbolic.perm()?;
        u32::try_from(pattern.indices().len()).ok()?;
        let n = pattern.n();
        let (ptr, idx) = (pattern.indptr(), pattern.indices());
        // the CSC view's lower triangle (see `factorise`)
        let nnz: usize = (0..n)
            .map(|j| idx[ptr[j]..ptr[j + 1]].iter().filter(|&&i| i >= j).count())
            .sum();
        // each entry tagged with its own index (exact in f64 below 2^53)
        let tags: Vec<f64> = (0..idx.len()).map(|k| k as f64).collect();
        let out_side = match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => Side::Upper,
            SymbolicCholeskyRaw::Supernodal(_) => Side::Lower,
        };
        let mut values = vec![0.0; nnz];
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = vec![0usize; nnz];
        let mut mem = MemBuffer::try_new(
            faer::sparse::utils::permute_self_adjoint_scratch::<usize>(n),
        )
        .ok()?;
        faer::sparse::utils::permute_self_adjoint_to_unsorted(
            &mut values,
            &mut col_ptr,
            &mut row_idx,
            SparseColMatRef::new(symbolic_view(pattern), &tags),
            perm,
            Side::Lower,
            out_side,
            MemStack::new(&mut mem),
        );
        let source = values.iter().map(|&v| v as u32).collect();
        Some(Permuted {
            pattern: faer::sparse::SymbolicSparseColMat::new_unsorted_checked(
                n, n, col_ptr, None, row_idx,
            ),
            source,
        })
    }
}

impl CholeskySolver {
    /// Symbolic analysis (AMD ordering — or nested dissection for large
    /// systems when its factor is smaller —, elimination tree, supernodes), with
    /// faer's own choice between the simplicial and the supernodal factor:
    /// for systems solved many times per factorisation (time stepping).
    pub fn analyse(pattern: std::sync::Arc<SparsityPattern>) -> Result<Self, FemError> {
        Self::analyse_with(pattern, SupernodalThreshold::AUTO)
    }

    /// [`CholeskySolver::analyse`] with the fill-reducing order given.
    pub fn analyse_ordered(
        pattern: std::sync::Arc<SparsityPattern>,
        ordering: FillOrdering,
    ) -> Result<Self, FemError> {
        Self::analyse_full(pattern, SupernodalThreshold::AUTO, ordering)
    }

    /// Symbolic analysis for a system that is factorised again and again
    /// (a Newton loop): the supernodal factor from half faer's flop ratio
    /// on. Its numeric factorisation is faster, its solves a little slower
    /// (more stored entries). Measured (release, the welded vessel's contact
    /// solve): graded g0 at order 2, 12 564 unknowns, contact 1.44–1.63 s →
    /// 1.18–1.29 s; level 2 at order 1, 0.135–0.152 s → 0.123 s; larger
    /// systems (level 4: 36 036 unknowns) are supernodal either way. The
    /// thermal stepper, which solves hundreds of times per factorisation,
    /// was slower with it (level 4: 0.58 → 0.67 s) and keeps
    /// [`CholeskySolver::analyse`].
    pub fn analyse_for_refactorisation(
        pattern: std::sync::Arc<SparsityPattern>,
    ) -> Result<Self, FemError> {
        Self::analyse_with(pattern, SupernodalThreshold(0.5))
    }

    pub(crate) fn analyse_with(
        pattern: std::sync::Arc<SparsityPattern>,
        supernodal: SupernodalThreshold,
    ) -> Result<Self, FemError> {
        Self::analyse_full(pattern, supernodal, FillOrdering::Auto)
    }

    fn analyse_full(
        pattern: std::sync::Arc<SparsityPattern>,
        supernodal: SupernodalThreshold,
        ordering: FillOrdering,
    ) -> Result<Self, FemError> {
        fn symbolic_for(
            pattern: &SparsityPattern,
            supernodal: SupernodalThreshold,
            ordering: SymmetricOrdering<'_, usize>,
        ) -> Result<SymbolicCholesky<usize>, FemError> {
            factorize_symbolic_cholesky(
                symbolic_view(pattern),
                Side::Lower,
                ordering,
                CholeskySymbolicParams {
                    supernodal_flop_ratio_threshold: supernodal,
                    ..Default::default()
                },
            )
            .map_err(|e| FemError::Solver(format!("{e:?}")))
        }
        let analyse = |ordering| symbolic_for(&pattern, supernodal, ordering);
        let dissected = || {
            let fwd = crate::ordering::nested_dissection(&pattern)?;
            let mut inv = vec![0; fwd.len()];
            for (k, &d) in fwd.iter().enumerate() {
                inv[d] = k;
            }
            symbolic_for(
                &pattern,
                supernodal,
                SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(&fwd, &inv, fwd.len())),
            )
        };
        let symbolic = match ordering {
            FillOrdering::Amd => analyse(SymmetricOrdering::Amd)?,
            FillOrdering::NestedDissection => dissected()?,
            FillOrdering::Auto => {
                let amd = analyse(SymmetricOrdering::Amd)?;
                if pattern.n() >= NESTED_DISSECTION_MIN_UNKNOWNS {
                    let nd = dissected()?;
                    if nd.len_val() < amd.len_val() {
                        nd
                    } else {
                        amd
                    }
                } else {
                    amd
                }
            }
        };
        let l_values = vec![0.0; symbolic.len_val()];
        let supernode_of = match symbolic.raw() {
            faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(sym) => {
                let mut of = vec![0u32; pattern.n()];
                for (s, (&b, &e)) in sym
                    .supernode_begin()
                    .iter()
                    .zip(sym.supernode_end())
                    .enumerate()
                {
                    let s = u32::try_from(s)
                        .map_err(|_| FemError::Solver("more than 2^32 supernodes".into()))?;
                    of[b..e].fill(s);
                }
                of
            }
            _ => Vec::new(),
        };
        let permuted = Permuted::new(&pattern, &symbolic).map(std::sync::Arc::new);
        Ok(CholeskySolver {
            pattern,
            symbolic: std::sync::Arc::new(symbolic),
            supernode_of: std::sync::Arc::new(supernode_of),
            permuted,
            gathered: Vec::new(),
            l_values,
            factorised: false,
        })
    }

    /// A second solver on the same symbolic analysis (no new ordering), for
    /// keeping several numeric factorisations (e.g. one per time step size).
    pub fn share_symbolic(&self) -> CholeskySolver {
        CholeskySolver {
            pattern: self.pattern.clone(),
            symbolic: self.symbolic.clone(),
            supernode_of: self.supernode_of.clone(),
            permuted: self.permuted.clone(),
            gathered: Vec::new(),
            l_values: vec![0.0; self.l_values.len()],
            factorised: false,
        }
    }

    /// The elimination order of the analysis (the dof eliminated k-th is
    /// `ordering()[k]`).
    pub fn ordering(&self) -> Vec<usize> {
        match self.symbolic.perm() {
            Some(p) => p.arrays().0.to_vec(),
            None => (0..self.pattern.n()).collect(),
        }
    }

    /// The analysed pattern.
    pub fn pattern(&self) -> &std::sync::Arc<SparsityPattern> {
        &self.pattern
    }

    /// True once a numeric factorisation succeeded.
    pub(crate) fn is_factorised(&self) -> bool {
        self.factorised
    }

    /// The symbolic analysis.
    pub(crate) fn symbolic_ref(&self) -> &SymbolicCholesky<usize> {
        &self.symbolic
    }

    /// The factor's values (faer's layout of the symbolic analysis).
    pub(crate) fn values(&self) -> &[f64] {
        &self.l_values
    }

    /// The supernode of each column (supernodal factors only).
    pub(crate) fn supernode_of(&self) -> &[u32] {
        &self.supernode_of
    }

    /// Number of stored entries in the factor.
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }

    /// Numeric factorisation of `matrix` (same pattern as analysed).
    pub fn factorise(&mut self, matrix: &CsrMatrix) -> Result<(), FemError> {
        same_pattern(matrix, &self.pattern)?;
        check_finite("matrix", matrix.values())?;
        self.factorised = false;
        let p = par(self.pattern.n());
        let req = self
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(p, Default::default());
        let mut mem = MemBuffer::try_new(req)
            .map_err(|_| FemError::Solver("out of memory for factorisation scratch".into()))?;
        let res = match &self.permuted {
            Some(q) => {
                use faer::sparse::linalg::cholesky::{SymbolicCholeskyRaw, simplicial, supernodal};
                let v = matrix.values();
                self.gathered.clear();
                self.gathered
                    .extend(q.source.iter().map(|&k| v[k as usize]));
                let a = SparseColMatRef::new(q.pattern.as_ref(), &self.gathered);
                let stack = MemStack::new(&mut mem);
                match self.symbolic.raw() {
                    SymbolicCholeskyRaw::Simplicial(s) => {
                        simplicial::factorize_simplicial_numeric_llt(
                            &mut self.l_values,
                            a,
                            LltRegularization::default(),
                            s,
                            stack,
                        )
                    }
                    SymbolicCholeskyRaw::Supernodal(s) => {
                        supernodal::factorize_supernodal_numeric_llt(
                            &mut self.l_values,
                            a,
                            LltRegularization::default(),
                            s,
                            p,
                            stack,
                            Default::default(),
                        )
                    }
                }
                .map(|_| ())
            }
            None => self
                .symbolic
                .factorize_numeric_llt(
                    &mut self.l_values,
                    SparseColMatRef::new(symbolic_view(&self.pattern), matrix.values()),
                    Side::Lower,
                    LltRegularization::default(),
                    p,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .map(|_| ()),
        };
        match res {
            Ok(_) => {
                self.factorised = true;
                Ok(())
            }
            Err(e) => {
                let faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } = e;
                // faer counts the failed pivot from 1 in a simplicial
                // factor and from 0 in a supernodal one (faer 0.24)
                let pivot = match self.symbolic.raw() {
                    faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Simplicial(_) => {
                        index.saturating_sub(1)
                    }
                    _ => index,
                };
                let dof = self
                    .symbolic
                    .perm()
                    .and_then(|perm| perm.arrays().0.get(pivot).copied())
                    .unwrap_or(pivot);
                Err(FemError::NotPositiveDefinite {
                    pivot,
                    dof,
                    hint: "check for an unconstrained body or an indefinite tangent (use LU)"
                        .into(),
                })
            }
        }
    }

    /// Solves A x = b in place (b ← x).
    pub fn solve(&self, rhs: &mut [f64]) -> Result<(), FemError> {
        self.solve_many(rhs, 1)
    }

    /// Solves A X = B in place for `k` right-hand sides stored one after the
    /// other (column-major n × k); one pass over the factor for all of them.
    pub fn solve_many(&self, rhs: &mut [f64], k: usize) -> Result<(), FemError> {
        if !self.factorised {
            return Err(FemError::NotFactorised);
        }
        let n = self.pattern.n();
        if rhs.len() != n * k {
            return Err(FemError::LengthMismatch {
                what: "right-hand sides".into(),
                got: rhs.len(),
                expected: n * k,
            });
        }
        if k == 0 {
            return Ok(());
        }
        let p = par(n);
        let req = self.symbolic.solve_in_place_scratch::<f64>(k, p);
        let mut mem = scratch(req)?;
        let llt = LltRef::<'_, usize, f64>::new(&self.symbolic, &self.l_values);
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, k),
            p,
            MemStack::new(&mut mem),
        );
        check_finite("solution", rhs)
    }
}

/// Columns of S per task of the product L Lᵀ in [`schur_complement`].
const SCHUR_BLOCK: usize = 128;

/// The Schur complement S = A_ΓΓ − A_ΓI A_II⁻¹ A_IΓ of a symmetric
/// positive semidefinite `matrix` onto the dofs `gamma`, by one sparse
/// Cholesky factorisation with the other dofs eliminated first, in the
/// order `interior` (an elimination order of A_II, e.g. its AMD ordering),
/// and Γ last: the trailing block of the factor is then the Cholesky
/// factor of S. `shift` (> 0, added to the Γ diagonal and taken off S
/// again) keeps the trailing block definite when S is only semidefinite (a
/// body held by the Γ dofs alone). S is returned dense, m × m column-major.
pub fn schur_complement(
    matrix: &CsrMatrix,
    interior: &[usize],
    gamma: &[usize],
    shift: f64,
) -> Result<Vec<f64>, FemError> {
    let mut out = vec![0.0; gamma.len() * gamma.len()];
    schur_complement_and_leading(matrix, interior, gamma, shift, &mut out)?;
    Ok(out)
}

/// [`schur_complement`] into `out` (m × m, column-major), keeping the
/// factor's leading block L_II for solves with A_II ([`LeadingFactor`]):
/// A_II need not be factorised a second time.
pub fn schur_complement_and_leading(
    matrix: &CsrMatrix,
    interior: &[usize],
    gamma: &[usize],
    shift: f64,
    out: &mut [f64],
) -> Result<LeadingFactor, FemError> {
    use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
    use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
    let pattern = matrix.pattern();
    let n = pattern.n();
    let (ni, m) = (interior.len(), gamma.len());
    if ni + m != n {
        return Err(FemError::LengthMismatch {
            what: "Schur complement dofs".into(),
            got: ni + m,
            expected: n,
        });
    }
    if out.len() != m * m {
        return Err(FemError::LengthMismatch {
            what: "Schur complement".into(),
            got: out.len(),
            expected: m * m,
        });
    }
    let fwd: Vec<usize> = interior.iter().chain(gamma).copied().collect();
    let mut inv = vec![usize::MAX; n];
    for (k, &d) in fwd.iter().enumerate() {
        if d >= n || inv[d] != usize::MAX {
            return Err(FemError::Solver(
                "Schur complement dofs are not a permutation".into(),
            ));
        }
        inv[d] = k;
    }
    let perm = faer::perm::PermRef::new_checked(&fwd, &inv, n);
    let symbolic = factorize_symbolic_cholesky(
        symbolic_view(pattern),
        Side::Lower,
        SymmetricOrdering::Custom(perm),
        CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        },
    )
    .map_err(|e| FemError::Solver(format!("{e:?}")))?;
    let mut values = matrix.values().to_vec();
    for &d in gamma {
        let k = pattern
            .slot(d, d)
            .ok_or_else(|| FemError::Solver(format!("no diagonal entry at dof {d}")))?;
        values[k] += shift;
    }
    check_finite("matrix", &values)?;
    let mut l_values = vec![0.0; symbolic.len_val()];
    let p = par(n);
    let req = symbolic.factorize_numeric_llt_scratch::<f64>(p, Default::default());
    let mut mem = scratch(req)?;
    if let Err(faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index }) = symbolic
        .factorize_numeric_llt(
            &mut l_values,
            SparseColMatRef::new(symbolic_view(pattern), &values),
            Side::Lower,
            LltRegularization::default(),
            p,
            MemStack::new(&mut mem),
            Default::default(),
        )
    {
        return Err(FemError::NotPositiveDefinite {
            pivot: index,
            dof: fwd.get(index).copied().unwrap_or(index),
            hint: "check for an unconstrained body".into(),
        });
    }
    drop(mem);
    drop(values);
    let SymbolicCholeskyRaw::Supernodal(sym) = symbolic.raw() else {
        return Err(FemError::Solver("expected a supernodal factor".into()));
    };
    let (begin, end) = (sym.supernode_begin(), sym.supernode_end());
    let (val_ptr, row_ptr) = (sym.col_ptr_for_val(), sym.col_ptr_for_row_idx());
    // the trailing m × m block of L (lower triangle), column-major: Γ's
    // own supernode when it is one (used in place, its upper triangle
    // zeroed), a copy otherwise
    let whole = (0..sym.n_supernodes())
        .find(|&s| begin[s] == ni && end[s] == n && row_ptr[s + 1] == row_ptr[s])
        .map(|s| val_ptr[s]);
    if let Some(off) = whole {
        for j in 0..m {
            l_values[off + j * m..off + j * m + j].fill(0.0);
        }
    }
    let mut copy = Vec::new();
    if whole.is_none() {
        copy = vec![0.0; m * m];
        let llt = SupernodalLltRef::<'_, usize, f64>::new(sym, &l_values);
        for s in 0..sym.n_supernodes() {
            let node = llt.supernode(s);
            let (start, val, below) = (node.start(), node.val(), node.pattern());
            let width = val.ncols();
            for j in 0..width {
                let col = start + j;
                if col < ni {
                    continue;
                }
                let jl = col - ni;
                for i in j..width {
                    copy[jl * m + (start + i - ni)] = val[(i, j)];
                }
                for (q, &row) in below.iter().enumerate() {
                    copy[jl * m + (row - ni)] = val[(width + q, j)];
                }
            }
        }
    }
    let l: &[f64] = match whole {
        Some(off) => &l_values[off..off + m * m],
        None => &copy,
    };
    // S = L Lᵀ − shift I (its lower triangle), in fixed blocks of columns (one sequential product
    // each, on any thread: the same bits whatever the thread count)
    let lm = faer::MatRef::from_column_major_slice(l, m, m);
    {
        use rayon::prelude::*;
        out.par_chunks_mut(SCHUR_BLOCK * m.max(1))
            .enumerate()
            .for_each(|(b, chunk)| {
                let cols = chunk.len() / m.max(1);
                let start = b * SCHUR_BLOCK;
                // rows from the block's diagonal down (S is symmetric)
                faer::linalg::matmul::matmul(
                    faer::MatMut::from_column_major_slice_with_stride_mut(
                        &mut chunk[start..],
                        m - start,
                        cols,
                        m,
                    ),
                    faer::Accum::Replace,
                    // (L[j, k] = 0 for k > j: the sum ends at the block)
                    lm.submatrix(start, 0, m - start, start + cols),
                    lm.submatrix(start, 0, cols, start + cols).transpose(),
                    1.0,
                    Par::Seq,
                );
            });
    }
    // the upper triangle from the lower one
    for j in 0..m {
        for i in j + 1..m {
            out[i * m + j] = out[j * m + i];
        }
    }
    for a in 0..m {
        out[a * m + a] -= shift;
    }
    drop(copy);
    // keep the values of the columns of I only (a prefix: the supernodes
    // are stored in column order)
    let mut keep = 0;
    for s in 0..sym.n_supernodes() {
        let (b, e) = (begin[s], end[s]);
        if b < ni {
            let rows = (e - b) + (row_ptr[s + 1] - row_ptr[s]);
            keep = keep.max(val_ptr[s] + rows * (e.min(ni) - b));
        }
    }
    l_values.truncate(keep);
    l_values.shrink_to_fit();
    Ok(LeadingFactor {
        symbolic,
        l_values,
        ni,
    })
}

/// The leading block L_II of a sparse Cholesky factor of a matrix ordered
/// [I, Γ] (see [`schur_complement_and_leading`]): solves with A_II = L_II
/// L_IIᵀ, in the factor's order of I. Only the values of I's columns are
/// kept.
pub struct LeadingFactor {
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    ni: usize,
}

impl std::fmt::Debug for LeadingFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LeadingFactor")
            .field("ni", &self.ni)
            .field("stored", &self.l_values.len())
            .finish()
    }
}

impl LeadingFactor {
    /// Number of I dofs.
    pub fn n(&self) -> usize {
        self.ni
    }

    /// Stored entries of L_II.
    pub fn nnz(&self) -> usize {
        self.l_values.len()
    }

    /// x ← A_II⁻¹ x, x over I in the factor's elimination order.
    pub fn solve(&self, x: &mut [f64]) -> Result<(), FemError> {
        use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
        let ni = self.ni;
        if x.len() != ni {
            return Err(FemError::LengthMismatch {
                what: "interior solve".into(),
                got: x.len(),
                expected: ni,
            });
        }
        let SymbolicCholeskyRaw::Supernodal(sym) = self.symbolic.raw() else {
            return Err(FemError::Solver("expected a supernodal factor".into()));
        };
        let (begin, end) = (sym.supernode_begin(), sym.supernode_end());
        let (val_ptr, row_ptr, row_idx) = (
            sym.col_ptr_for_val(),
            sym.col_ptr_for_row_idx(),
            sym.row_idx(),
        );
        // supernode s: columns b..b + wi of I, its values (rows × wi, column-major)
        let node = |s: usize| {
            let (b, e) = (begin[s], end[s]);
            let w = e - b;
            let wi = e.min(ni) - b;
            let below = &row_idx[row_ptr[s]..row_ptr[s + 1]];
            let rows = w + below.len();
            let v = &self.l_values[val_ptr[s]..val_ptr[s] + rows * wi];
            (b, w, wi, below, rows, v)
        };
        let live: Vec<usize> = (0..sym.n_supernodes()).filter(|&s| begin[s] < ni).collect();
        // forward: L_II y = x (rows of Γ below are dropped)
        for &s in &live {
            let (b, w, wi, below, rows, v) = node(s);
            let lm = faer::MatRef::from_column_major_slice(v, rows, wi);
            faer::linalg::triangular_solve::solve_lower_triangular_in_place(
                lm.submatrix(0, 0, wi, wi),
                MatMut::from_column_major_slice_mut(&mut x[b..b + wi], wi, 1),
                Par::Seq,
            );
            for j in 0..wi {
                let xj = x[b + j];
                if xj != 0.0 {
                    let col = &v[j * rows + w..(j + 1) * rows];
                    for (&r, &l) in below.iter().zip(col) {
                        if r < ni {
                            x[r] -= l * xj;
                        }
                    }
                }
            }
        }
        // backward: L_IIᵀ x = y
        for &s in live.iter().rev() {
            let (b, w, wi, below, rows, v) = node(s);
            for j in 0..wi {
                let col = &v[j * rows + w..(j + 1) * rows];
                let mut acc = 0.0;
                for (&r, &l) in below.iter().zip(col) {
                    if r < ni {
                        acc += l * x[r];
                    }
                }
                x[b + j] -= acc;
            }
            let lm = faer::MatRef::from_column_major_slice(v, rows, wi);
            faer::linalg::triangular_solve::solve_upper_triangular_in_place(
                lm.submatrix(0, 0, wi, wi).transpose(),
                MatMut::from_column_major_slice_mut(&mut x[b..b + wi], wi, 1),
                Par::Seq,
            );
        }
        check_finite("solution", x)
    }
}

/// Sparse LU with partial pivoting of a general square matrix.
#[derive(Debug)]
pub struct LuSolver {
    pattern: std::sync::Arc<SparsityPattern>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    factorised: bool,
}

impl LuSolver {
    /// Symbolic analysis (COLAMD ordering).
    pub fn analyse(pattern: std::sync::Arc<SparsityPattern>) -> Result<Self, FemError> {
        let symbolic = factorize_symbolic_lu(symbolic_view(&pattern), Default::default())
            .map_err(|e| FemError::Solver(format!("{e:?}")))?;
        Ok(LuSolver {
            pattern,
            symbolic,
            numeric: NumericLu::new(),
            factorised: false,
        })
    }

    /// Numeric factorisation of `matrix`.
    pub fn factorise(&mut self, matrix: &CsrMatrix) -> Result<(), FemError> {
        same_pattern(matrix, &self.pattern)?;
        check_finite("matrix", matrix.values())?;
        self.factorised = false;
        let p = par(self.pattern.n());
        let sym = symbolic_view(&self.pattern);
        let a = SparseColMatRef::new(sym, matrix.values());
        let req = self
            .symbolic
            .factorize_numeric_lu_scratch::<f64>(p, Default::default());
        let mut mem = MemBuffer::try_new(req)
            .map_err(|_| FemError::Solver("out of memory for factorisation scratch".into()))?;
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                a,
                p,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| match e {
                faer::sparse::linalg::LuError::SymbolicSingular { index } => FemError::Singular {
                    detail: format!("no pivot found at step {index} (structurally singular)"),
                },
                other => FemError::Solver(format!("{other:?}")),
            })?;
        self.factorised = true;
        Ok(())
    }

    /// Solves A x = b in place (b ← x). The stored CSC matrix is Aᵀ, so
    /// this uses the transposed solve.
    pub fn solve(&self, rhs: &mut [f64]) -> Result<(), FemError> {
        if !self.factorised {
            return Err(FemError::NotFactorised);
        }
        if rhs.len() != self.pattern.n() {
            return Err(FemError::LengthMismatch {
                what: "right-hand side".into(),
                got: rhs.len(),
                expected: self.pattern.n(),
            });
        }
        let p = par(self.pattern.n());
        let req = self.symbolic.solve_transpose_in_place_scratch::<f64>(1, p);
        let mut mem = scratch(req)?;
        // `factorise` filled `numeric` from this `symbolic`.
        let lu = LuRef::new_unchecked(&self.symbolic, &self.numeric);
        lu.solve_transpose_in_place_with_conj(Conj::No, as_col(rhs), p, MemStack::new(&mut mem));
        check_finite("solution (the matrix is singular)", rhs)
    }
}

/// Relative residual ‖b − A x‖ / ‖b‖ (∞-norms), for checks after a solve.
pub fn relative_residual(matrix: &CsrMatrix, x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; b.len()];
    matrix.mul_vec(x, &mut ax);
    let r = ax
        .iter()
        .zip(b)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let nb = b.iter().map(|v| v.abs()).fold(0.0, f64::max);
    if nb == 0.0 { r } else { r / nb }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Goal: a system above the nested-dissection threshold keeps the
    /// smaller of the two factors, and both orders solve to round-off.
    #[test]
    fn a_large_strip_keeps_the_smaller_factor_and_solves() {
        // the 6-node triangles of a square: 2 × 70 × 70 elements on a
        // 141 × 141 lattice (19 881 nodes), 3 unknowns per node (59 643),
        // the element cliques a Laplacian-like matrix plus a small mass
        let (cx, cy) = (400, 16);
        let side = 2 * cx + 1;
        let c = 2;
        let at = |i: usize, j: usize| j * side + i;
        let mut elements: Vec<[usize; 6]> = Vec::new();
        for j in 0..cy {
            for i in 0..cx {
                let (x, y) = (2 * i, 2 * j);
                elements.push([
                    at(x, y),
                    at(x + 2, y),
                    at(x, y + 2),
                    at(x + 1, y),
                    at(x + 1, y + 1),
                    at(x, y + 1),
                ]);
                elements.push([
                    at(x + 2, y + 2),
                    at(x, y + 2),
                    at(x + 2, y),
                    at(x + 1, y + 2),
                    at(x + 1, y + 1),
                    at(x + 2, y + 1),
                ]);
            }
        }
        let n = side * (2 * cy + 1) * c;
        assert!(n >= NESTED_DISSECTION_MIN_UNKNOWNS);
        let dofs: Vec<usize> = elements
            .iter()
            .flatten()
            .flat_map(|&m| (0..c).map(move |k| m * c + k))
            .collect();
        let pattern =
            std::sync::Arc::new(SparsityPattern::from_blocks(n, &[(6 * c, &dofs)]).unwrap());
        let mut pairs = Vec::new();
        for e in &elements {
            for a in 0..6 {
                for b in a + 1..6 {
                    for k in 0..c {
                        pairs.extend([e[a] * c + k, e[b] * c + k]);
                    }
                }
            }
        }
        let mut a = CsrMatrix::zeros(pattern.clone());
        for e in pairs.chunks(2) {
            let (p, q) = (e[0], e[1]);
            for (r, c, v) in [(p, p, 1.0), (q, q, 1.0), (p, q, -1.0), (q, p, -1.0)] {
                let s = a.pattern().slot(r, c).unwrap();
                a.values_mut()[s] += v;
            }
        }
        for d in 0..n {
            let s = a.pattern().slot(d, d).unwrap();
            a.values_mut()[s] += 1e-3;
        }
        let entries = |o| {
            CholeskySolver::analyse_ordered(pattern.clone(), o)
                .unwrap()
                .factor_nnz()
        };
        let (amd, nd) = (
            entries(FillOrdering::Amd),
            entries(FillOrdering::NestedDissection),
        );
        let mut solver = CholeskySolver::analyse(pattern.clone()).unwrap();
        // on this thin strip AMD wins (2.57 against 3.71 million entries)
        assert_eq!(solver.factor_nnz(), amd.min(nd), "AMD {amd}, ND {nd}");
        assert!(amd < nd, "AMD {amd}, ND {nd}");
        let mut dissected =
            CholeskySolver::analyse_ordered(pattern.clone(), FillOrdering::NestedDissection)
                .unwrap();
        dissected.factorise(&a).unwrap();
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let mut x = b.clone();
        dissected.solve(&mut x).unwrap();
        let r = relative_residual(&a, &x, &b);
        assert!(r < 1e-12, "nested dissection: relative residual {r:e}");
        solver.factorise(&a).unwrap();
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let mut x = b.clone();
        solver.solve(&mut x).unwrap();
        let r = relative_residual(&a, &x, &b);
        assert!(r < 1e-12, "relative residual {r:e}");
    }

    /// Goal: the factor from the gathered, pre-permuted matrix is faer's
    /// own (which permutes the matrix at every factorisation) bit for bit,
    /// simplicial and supernodal, and a non-positive pivot still names its
    /// dof.
    #[test]
    fn the_gathered_factorisation_is_faers_own_bit_for_bit() {
        // a 2D grid Laplacian with unequal diagonal entries
        let side = 30;
        let n = side * side;
        let mut a = crate::condensed::tests::grid(side);
        let pattern = a.pattern().clone();
        for d in 0..n {
            let s = a.pattern().slot(d, d).unwrap();
            a.values_mut()[s] += 1e-2 * (1 + d % 3) as f64;
        }
        for threshold in [
            SupernodalThreshold::FORCE_SIMPLICIAL,
            SupernodalThreshold::FORCE_SUPERNODAL,
        ] {
            let mut solver = CholeskySolver::analyse_with(pattern.clone(), threshold).unwrap();
            assert!(solver.permuted.is_some(), "an AMD order permutes");
            solver.factorise(&a).unwrap();
            // faer's entry point on the same analysis
            let mut own = vec![0.0; solver.l_values.len()];
            let req = solver
                .symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
            let mut mem = MemBuffer::try_new(req).unwrap();
            solver
                .symbolic
                .factorize_numeric_llt(
                    &mut own,
                    SparseColMatRef::new(symbolic_view(&pattern), a.values()),
                    Side::Lower,
                    LltRegularization::default(),
                    Par::Seq,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .unwrap();
            assert!(
                own.iter()
                    .zip(&solver.l_values)
                    .all(|(x, y)| x.to_bits() == y.to_bits()),
                "{threshold:?}: the factors differ"
            );
            // an indefinite matrix: the pivot of the one negative diagonal
            // entry fails (every pivot eliminated before it stays positive,
            // and its own is at most that entry), and its dof is named
            let mut bad = a.clone();
            let s = bad.pattern().slot(17, 17).unwrap();
            bad.values_mut()[s] = -1.0;
            match solver.factorise(&bad) {
                Err(FemError::NotPositiveDefinite { dof, pivot, .. }) => {
                    assert_eq!(dof, 17, "{threshold:?}: pivot {pivot}");
                    assert_eq!(solver.ordering()[pivot], 17, "{threshold:?}");
                }
                other => panic!("{threshold:?}: {other:?}"),
            }
        }
    }

    #[test]
    fn schur_complements_match_the_dense_formula_also_for_a_floating_body() {
        // a chain of 7 springs (a 1D bar); Γ = dofs 3 and 7; with dof 0
        // held the matrix is definite, without it the bar floats and S is
        // singular (the shift keeps the factorisation going)
        let n = 8;
        let pairs: Vec<usize> = (0..n - 1).flat_map(|i| [i, i + 1]).collect();
        let pattern = std::sync::Arc::new(SparsityPattern::from_blocks(n, &[(2, &pairs)]).unwrap());
        for held in [true, false] {
            let mut a = CsrMatrix::zeros(pattern.clone());
            for i in 0..n - 1 {
                let k = 1.0 + i as f64;
                for (r, c, v) in [(i, i, k), (i + 1, i + 1, k), (i, i + 1, -k), (i + 1, i, -k)] {
                    let s = a.pattern().slot(r, c).unwrap();
                    a.values_mut()[s] += v;
                }
            }
            if held {
                let s = a.pattern().slot(0, 0).unwrap();
                a.values_mut()[s] += 10.0;
            }
            let gamma = [3usize, 7];
            let interior: Vec<usize> = (0..n).filter(|d| !gamma.contains(d)).collect();
            let s = schur_complement(&a, &interior, &gamma, 1e-8).unwrap();
            // dense reference: A_ΓΓ − A_ΓI A_II⁻¹ A_IΓ
            let d = a.to_dense();
            let ii = d.select_rows(&interior).select_columns(&interior);
            let gi = d.select_rows(&gamma).select_columns(&interior);
            let gg = d.select_rows(&gamma).select_columns(&gamma);
            let want = &gg - &gi * ii.lu().solve(&gi.transpose()).unwrap();
            for r in 0..2 {
                for c in 0..2 {
                    let err = (s[c * 2 + r] - want[(r, c)]).abs();
                    assert!(err < 1e-12 * want.amax(), "held {held}: ({r}, {c}) {err:e}");
                }
            }
            if !held {
                // a floating bar: the rigid mode (1, 1) is in S's null space
                assert!((s[0] + s[2]).abs() < 1e-12 && (s[1] + s[3]).abs() < 1e-12);
            }
        }
    }

    /// Goal: S and the solves with A_II are right also when the factor's
    /// last supernode holds an interior column with the Γ ones (dof 0 is
    /// coupled to every Γ dof, Γ is dense, and 0 is eliminated last among I).
    #[test]
    fn the_leading_block_solves_with_a_ii_also_across_a_shared_supernode() {
        let n = 6;
        let gamma = [1usize, 2, 3, 4];
        let mut pairs = vec![5usize, 0];
        for &g in &gamma {
            pairs.extend([0, g]);
            for &h in &gamma {
                if g < h {
                    pairs.extend([g, h]);
                }
            }
        }
        let pattern = std::sync::Arc::new(SparsityPattern::from_blocks(n, &[(2, &pairs)]).unwrap());
        let mut a = CsrMatrix::zeros(pattern.clone());
        for (k, w) in pairs.chunks(2).enumerate() {
            let (i, j) = (w[0], w[1]);
            let v = 1.0 + 0.1 * k as f64;
            for (r, c, x) in [(i, i, v), (j, j, v), (i, j, -v), (j, i, -v)] {
                let s = a.pattern().slot(r, c).unwrap();
                a.values_mut()[s] += x;
            }
        }
        // held at dof 5 (and a little everywhere): definite
        for d in 0..n {
            let s = a.pattern().slot(d, d).unwrap();
            a.values_mut()[s] += if d == 5 { 5.0 } else { 0.01 };
        }
        let interior = [5usize, 0];
        let mut s = vec![0.0; 16];
        let leading = schur_complement_and_leading(&a, &interior, &gamma, 1e-8, &mut s).unwrap();
        assert_eq!(leading.n(), 2);
        let d = a.to_dense();
        let ii = d.select_rows(&interior).select_columns(&interior);
        let gi = d.select_rows(&gamma).select_columns(&interior);
        let gg = d.select_rows(&gamma).select_columns(&gamma);
        let want = &gg - &gi * ii.clone().lu().solve(&gi.transpose()).unwrap();
        for r in 0..4 {
            for c in 0..4 {
                let err = (s[c * 4 + r] - want[(r, c)]).abs();
                assert!(err < 1e-12 * want.amax(), "S ({r}, {c}) {err:e}");
            }
        }
        // A_II x = b, in the elimination order [5, 0]
        let b = [0.7, -1.3];
        let mut x = b.to_vec();
        leading.solve(&mut x).unwrap();
        let exact = ii
            .lu()
            .solve(&nalgebra::DVector::from_row_slice(&b))
            .unwrap();
        for k in 0..2 {
            assert!((x[k] - exact[k]).abs() < 1e-13 * exact.amax(), "x[{k}]");
        }
        assert!(
            leading.solve(&mut [0.0; 3]).is_err(),
            "a wrong length is refused"
        );
        let mut short = vec![0.0; 15];
        assert!(
            schur_complement_and_leading(&a, &interior, &gamma, 1e-8, &mut short).is_err(),
            "a wrong output size is refused"
        );
    }
}
