//! The `Element` trait and the `Assembler`: pattern once, values many times.
//!
//! Element kernels are evaluated in parallel (rayon) in fixed-size batches and
//! scattered into the CSR values strictly in element order, one batch while
//! the next is being computed — when the kernels cost more than the scatter
//! (timed on the first batch); cheap kernels are scattered as they are
//! computed. The scatter order never depends on the number of threads or on
//! that choice, so the assembled values are bitwise identical for any
//! `RAYON_NUM_THREADS` (and identical to the serial path).

use std::sync::Arc;

use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;

use crate::error::FemError;
use crate::pattern::{CsrMatrix, SparsityPattern};

/// Local matrix and vector of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalSystem<const N: usize> {
    /// Local matrix (stiffness, conductivity, capacity, tangent …).
    pub matrix: SMatrix<f64, N, N>,
    /// Local vector (load, residual …).
    pub vector: SVector<f64, N>,
}

impl<const N: usize> LocalSystem<N> {
    /// A zero system.
    pub fn zeros() -> Self {
        LocalSystem {
            matrix: SMatrix::zeros(),
            vector: SVector::zeros(),
        }
    }
}

/// A set of elements of one kind with `N` local dofs: a local kernel plus its
/// connectivity. Kernels are pure: they read the element's coordinates and
/// state and allocate nothing.
pub trait Element<const N: usize>: Sync {
    /// Number of elements.
    fn n_elements(&self) -> usize;
    /// Global dof indices of element `e`, in local order.
    fn dofs(&self, e: usize) -> [usize; N];
    /// Local matrix and vector of element `e`.
    fn local(&self, e: usize) -> LocalSystem<N>;
    /// Local vector of element `e` alone (what [`Assembler::add_vector`]
    /// takes); elements whose matrix costs more than their vector override
    /// it.
    fn local_vector(&self, e: usize) -> SVector<f64, N> {
        self.local(e).vector
    }
}

/// Handle of an element block registered in an [`AssemblerBuilder`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockId(usize);

#[derive(Debug, Clone)]
struct Block {
    ndof: usize,
    n_elements: usize,
    dofs: Vec<usize>,
    /// Value slot of each local entry (row-major N×N per element).
    slots: Vec<u32>,
}

/// Collects the connectivity of element blocks and builds an [`Assembler`].
#[derive(Debug, Default)]
pub struct AssemblerBuilder {
    n_dofs: usize,
    blocks: Vec<(usize, Vec<usize>)>,
}

impl AssemblerBuilder {
    /// A builder for a system with `n_dofs` unknowns.
    pub fn new(n_dofs: usize) -> Self {
        AssemblerBuilder {
            n_dofs,
            blocks: Vec::new(),
        }
    }

    /// Registers a block of elements with `ndof` dofs each; `dofs` is the
    /// flattened list of their global dofs.
    pub fn add_block(&mut self, ndof: usize, dofs: Vec<usize>) -> BlockId {
        self.blocks.push((ndof, dofs));
        BlockId(self.blocks.len() - 1)
    }

    /// Registers the connectivity of an element set.
    pub fn add_elements<const N: usize, E: Element<N>>(&mut self, elements: &E) -> BlockId {
        let mut dofs = Vec::with_capacity(N * elements.n_elements());
        for e in 0..elements.n_elements() {
            dofs.extend_from_slice(&elements.dofs(e));
        }
        self.add_block(N, dofs)
    }

    /// Builds the pattern and the element→slot maps.
    pub fn build(self) -> Result<Assembler, FemError> {
        let views: Vec<(usize, &[usize])> = self
            .blocks
            .iter()
            .map(|(n, d)| (*n, d.as_slice()))
            .collect();
        let pattern = Arc::new(SparsityPattern::from_blocks(self.n_dofs, &views)?);
        if pattern.nnz() > u32::MAX as usize {
            return Err(FemError::Solver(format!(
                "{} stored entries exceed the 32-bit slot map",
                pattern.nnz()
            )));
        }
        let blocks = self
            .blocks
            .into_iter()
            .map(|(ndof, dofs)| {
                let n_elements = dofs.len() / ndof;
                let mut slots = vec![0u32; n_elements * ndof * ndof];
                let c = pattern.block_size();
                let (indptr, indices) = (pattern.indptr(), pattern.indices());
                slots
                    .par_chunks_mut(ndof * ndof)
                    .zip(dofs.par_chunks(ndof))
                    .for_each(|(s, el)| {
                        // Node blocks: one search per node pair, c² slots from it.
                        for a in (0..ndof).step_by(c) {
                            let row = el[a];
                            let (lo, hi) = (indptr[row], indptr[row + 1]);
                            for b in (0..ndof).step_by(c) {
                                // Present by construction of the pattern.
                                let k = indices[lo..hi].binary_search(&el[b]).unwrap_or(0);
                                for ka in 0..c {
                                    let base = indptr[row + ka] + k;
                                    for kb in 0..c {
                                        s[(a + ka) * ndof + b + kb] = (base + kb) as u32;
                                    }
                                }
                            }
                        }
                    });
                Block {
                    ndof,
                    n_elements,
                    dofs,
                    slots,
                }
            })
            .collect();
        Ok(Assembler { pattern, blocks })
    }
}

/// Elements per batch of the parallel path (fixed, so the work split never
/// depends on the thread count).
pub const BATCH: usize = 4096;

/// Scatters element systems into a CSR matrix with a fixed pattern.
#[derive(Debug, Clone)]
pub struct Assembler {
    pattern: Arc<SparsityPattern>,
    blocks: Vec<Block>,
}

/// How to run the fill.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Parallelism {
    /// One thread: compute and scatter element by element.
    Serial,
    /// Kernels in parallel on the current rayon pool, scatter in element order.
    Rayon,
}

impl Assembler {
    /// The shared sparsity pattern.
    pub fn pattern(&self) -> &Arc<SparsityPattern> {
        &self.pattern
    }

    /// A zero matrix with this assembler's pattern.
    pub fn new_matrix(&self) -> CsrMatrix {
        CsrMatrix::zeros(self.pattern.clone())
    }

    /// Number of dofs.
    pub fn n_dofs(&self) -> usize {
        self.pattern.n()
    }

    /// Adds the element systems of `elements` (registered as `block`) into
    /// `matrix` and, if given, `rhs`. Call `matrix.values_mut().fill(0.0)`
    /// first for a fresh assembly.
    pub fn add<const N: usize, E: Element<N>>(
        &self,
        block: BlockId,
        elements: &E,
        matrix: &mut CsrMatrix,
        rhs: Option<&mut [f64]>,
        par: Parallelism,
    ) -> Result<(), FemError> {
        let b = self.check(block, N, elements.n_elements(), matrix, rhs.as_deref())?;
        let values = matrix.values_mut();
        let mut rhs = rhs;
        let scatter =
            |values: &mut [f64], rhs: &mut Option<&mut [f64]>, e: usize, ls: &LocalSystem<N>| {
                let slots = &b.slots[e * N * N..(e + 1) * N * N];
                for a in 0..N {
                    for c in 0..N {
                        values[slots[a * N + c] as usize] += ls.matrix[(a, c)];
                    }
                }
                if let Some(r) = rhs.as_deref_mut() {
                    let dofs = &b.dofs[e * N..(e + 1) * N];
                    for a in 0..N {
                        r[dofs[a]] += ls.vector[a];
                    }
                }
            };
        let ne = b.n_elements;
        if par == Parallelism::Serial || rayon::current_num_threads() == 1 || ne <= BATCH {
            for e in 0..ne {
                let ls = elements.local(e);
                scatter(values, &mut rhs, e, &ls);
            }
            return Ok(());
        }
        let compute = |start: usize, buf: &mut Vec<LocalSystem<N>>| {
            let end = (start + BATCH).min(ne);
            buf.clear();
            (start..end)
                .into_par_iter()
                .with_min_len(256)
                .map(|e| elements.local(e))
                .collect_into_vec(buf);
        };
        // The first batch, serially, timing kernels against the scatter:
        // overlapping them only pays when the kernels are the larger part
        // (on two cores a cheap kernel such as the CST stiffness loses more
        // to the buffer traffic than it gains). Either path scatters in
        // element order, so the values are the same bit for bit.
        let mut cur: Vec<LocalSystem<N>> = Vec::with_capacity(BATCH);
        let mut next = Vec::with_capacity(BATCH);
        let first = BATCH.min(ne);
        let t0 = std::time::Instant::now();
        cur.extend((0..first).map(|e| elements.local(e)));
        let t_kernel = t0.elapsed();
        let t1 = std::time::Instant::now();
        for (e, ls) in cur.iter().enumerate() {
            scatter(values, &mut rhs, e, ls);
        }
        let t_scatter = t1.elapsed();
        if t_kernel <= t_scatter {
            for e in first..ne {
                let ls = elements.local(e);
                scatter(values, &mut rhs, e, &ls);
            }
            return Ok(());
        }
        compute(first, &mut cur);
        let mut start = first;
        while start < ne {
            let next_start = start + BATCH;
            let cur_ref = &cur;
            rayon::join(
                || {
                    for (k, ls) in cur_ref.iter().enumerate() {
                        scatter(values, &mut rhs, start + k, ls);
                    }
                },
                || {
                    if next_start < ne {
                        compute(next_start, &mut next);
                    }
                },
            );
            std::mem::swap(&mut cur, &mut next);
            start = next_start;
        }
        Ok(())
    }

    /// Adds only the element vectors of `elements` into `rhs` (e.g. a load
    /// or residual with an unchanged matrix).
    pub fn add_vector<const N: usize, E: Element<N>>(
        &self,
        block: BlockId,
        elements: &E,
        rhs: &mut [f64],
    ) -> Result<(), FemError> {
        let b = self.block(block, N, elements.n_elements())?;
        if rhs.len() != self.pattern.n() {
            return Err(FemError::LengthMismatch {
                what: "right-hand side".into(),
                got: rhs.len(),
                expected: self.pattern.n(),
            });
        }
        for e in 0..b.n_elements {
            let v = elements.local_vector(e);
            let dofs = &b.dofs[e * N..(e + 1) * N];
            for a in 0..N {
                rhs[dofs[a]] += v[a];
            }
        }
        Ok(())
    }

    fn block(&self, block: BlockId, n: usize, ne: usize) -> Result<&Block, FemError> {
        let b = self
            .blocks
            .get(block.0)
            .ok_or_else(|| FemError::LengthMismatch {
                what: "block id".into(),
                got: block.0,
                expected: self.blocks.len(),
            })?;
        if b.ndof != n {
            return Err(FemError::LengthMismatch {
                what: format!("dofs per element of block {}", block.0),
                got: n,
                expected: b.ndof,
            });
        }
        if b.n_elements != ne {
            return Err(FemError::LengthMismatch {
                what: format!("element count of block {}", block.0),
                got: ne,
                expected: b.n_elements,
            });
        }
        Ok(b)
    }

    fn check(
        &self,
        block: BlockId,
        n: usize,
        ne: usize,
        matrix: &CsrMatrix,
        rhs: Option<&[f64]>,
    ) -> Result<&Block, FemError> {
        let b = self.block(block, n, ne)?;
        if !Arc::ptr_eq(matrix.pattern(), &self.pattern) && **matrix.pattern() != *self.pattern {
            return Err(FemError::LengthMismatch {
                what: "matrix pattern (not this assembler's)".into(),
                got: matrix.pattern().nnz(),
                expected: self.pattern.nnz(),
            });
        }
        if let Some(r) = rhs
            && r.len() != self.pattern.n()
        {
            return Err(FemError::LengthMismatch {
                what: "right-hand side".into(),
                got: r.len(),
                expected: self.pattern.n(),
            });
        }
        Ok(b)
    }
}
