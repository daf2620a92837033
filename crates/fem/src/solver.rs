//! Sparse direct solvers through `faer`: symbolic analysis once, numeric
//! refactorisation whenever the values change, many solves.
//!
//! * [`CholeskySolver`]: LLᵀ with AMD ordering for symmetric positive
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

fn check_finite(what: &str, v: &[f64]) -> Result<(), FemError> {
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

/// Sparse Cholesky (LLᵀ) of a symmetric positive definite matrix.
#[derive(Debug)]
pub struct CholeskySolver {
    pattern: std::sync::Arc<SparsityPattern>,
    symbolic: std::sync::Arc<SymbolicCholesky<usize>>,
    l_values: Vec<f64>,
    factorised: bool,
}

impl CholeskySolver {
    /// Symbolic analysis (AMD ordering, elimination tree, supernodes), with
    /// faer's own choice between the simplicial and the supernodal factor:
    /// for systems solved many times per factorisation (time stepping).
    pub fn analyse(pattern: std::sync::Arc<SparsityPattern>) -> Result<Self, FemError> {
        Self::analyse_with(pattern, SupernodalThreshold::AUTO)
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

    fn analyse_with(
        pattern: std::sync::Arc<SparsityPattern>,
        supernodal: SupernodalThreshold,
    ) -> Result<Self, FemError> {
        let symbolic = factorize_symbolic_cholesky(
            symbolic_view(&pattern),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: supernodal,
                ..Default::default()
            },
        )
        .map_err(|e| FemError::Solver(format!("{e:?}")))?;
        let l_values = vec![0.0; symbolic.len_val()];
        Ok(CholeskySolver {
            pattern,
            symbolic: std::sync::Arc::new(symbolic),
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
            l_values: vec![0.0; self.l_values.len()],
            factorised: false,
        }
    }

    /// The analysed pattern.
    pub fn pattern(&self) -> &std::sync::Arc<SparsityPattern> {
        &self.pattern
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
        let sym = symbolic_view(&self.pattern);
        let a = SparseColMatRef::new(sym, matrix.values());
        let req = self
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(p, Default::default());
        let mut mem = MemBuffer::try_new(req)
            .map_err(|_| FemError::Solver("out of memory for factorisation scratch".into()))?;
        let res = self.symbolic.factorize_numeric_llt(
            &mut self.l_values,
            a,
            Side::Lower,
            LltRegularization::default(),
            p,
            MemStack::new(&mut mem),
            Default::default(),
        );
        match res {
            Ok(_) => {
                self.factorised = true;
                Ok(())
            }
            Err(e) => {
                let faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot {
                    index: pivot,
                } = e;
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
