//! Dirichlet constraints applied by symmetric elimination inside a fixed pattern.
//!
//! For each constrained dof c with value g: the column c is moved to the
//! right-hand side (f_i −= a_ic g) and zeroed, the row c is zeroed, the
//! diagonal keeps its assembled value d (1 if it was 0) and f_c = d g. The
//! matrix stays symmetric when it was, and keeps its pattern.

use std::collections::BTreeMap;

use crate::error::FemError;
use crate::pattern::{CsrMatrix, SparsityPattern};

/// Prescribed values of individual dofs.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Dirichlet {
    values: BTreeMap<usize, f64>,
}

impl Dirichlet {
    /// No constraints.
    pub fn new() -> Self {
        Self::default()
    }

    /// Prescribes `value` at `dof` (a later call for the same dof wins).
    pub fn set(&mut self, dof: usize, value: f64) {
        self.values.insert(dof, value);
    }

    /// Whether `dof` is constrained.
    pub fn contains(&self, dof: usize) -> bool {
        self.values.contains_key(&dof)
    }

    /// Number of constrained dofs.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether nothing is constrained.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// (dof, value) pairs in dof order.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.values.iter().map(|(&d, &v)| (d, v))
    }

    /// Multiplies every prescribed value by `s` (load stepping).
    pub fn scaled(&self, s: f64) -> Dirichlet {
        Dirichlet {
            values: self.values.iter().map(|(&d, &v)| (d, v * s)).collect(),
        }
    }

    /// Precomputes the value slots touched by these constraints in `pattern`.
    pub fn prepare(&self, pattern: &SparsityPattern) -> Result<PreparedDirichlet, FemError> {
        let n = pattern.n();
        let mut rows = Vec::with_capacity(self.values.len());
        for (&c, &g) in &self.values {
            if c >= n {
                return Err(FemError::DofOutOfRange {
                    what: "Dirichlet constraint".into(),
                    dof: c,
                    n_dofs: n,
                });
            }
            if !g.is_finite() {
                return Err(FemError::NonFinite {
                    what: "Dirichlet value".into(),
                    index: c,
                });
            }
            let (a, b) = (pattern.indptr()[c], pattern.indptr()[c + 1]);
            let mut column = Vec::with_capacity(b - a);
            let mut diag = None;
            for k in a..b {
                let j = pattern.indices()[k];
                if j == c {
                    diag = Some(k);
                } else if let Some(s) = pattern.slot(j, c) {
                    column.push((j, s));
                }
            }
            let diag =
                diag.ok_or_else(|| FemError::Solver(format!("pattern lacks diagonal entry {c}")))?;
            rows.push(ConstrainedRow {
                dof: c,
                value: g,
                row: a..b,
                diag,
                column,
            });
        }
        Ok(PreparedDirichlet { rows })
    }
}

#[derive(Debug, Clone, PartialEq)]
struct ConstrainedRow {
    dof: usize,
    value: f64,
    row: std::ops::Range<usize>,
    diag: usize,
    column: Vec<(usize, usize)>,
}

/// Dirichlet constraints with their slots in a given pattern.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedDirichlet {
    rows: Vec<ConstrainedRow>,
}

impl PreparedDirichlet {
    /// Applies the constraints to an assembled matrix and right-hand side.
    pub fn apply(&self, matrix: &mut CsrMatrix, rhs: &mut [f64]) {
        self.apply_scaled(matrix, rhs, 1.0);
    }

    /// Applies the constraints with every prescribed value multiplied by `s`
    /// (`s = 0` gives homogeneous constraints, as for a Newton correction).
    pub fn apply_scaled(&self, matrix: &mut CsrMatrix, rhs: &mut [f64], s: f64) {
        let values = matrix.values_mut();
        for r in &self.rows {
            let g = s * r.value;
            for &(j, slot) in &r.column {
                rhs[j] -= values[slot] * g;
                values[slot] = 0.0;
            }
        }
        for r in &self.rows {
            let d = values[r.diag];
            let d = if d != 0.0 && d.is_finite() { d } else { 1.0 };
            for k in r.row.clone() {
                values[k] = 0.0;
            }
            values[r.diag] = d;
            rhs[r.dof] = d * s * r.value;
        }
    }

    /// Calls `f` with every range of value slots that
    /// [`PreparedDirichlet::apply_scaled`] may change: the constrained
    /// rows, and the constrained columns' entries in other rows.
    pub fn for_each_touched(&self, mut f: impl FnMut(std::ops::Range<usize>)) {
        for r in &self.rows {
            f(r.row.clone());
            for &(_, slot) in &r.column {
                f(slot..slot + 1);
            }
        }
    }

    /// Sets the constrained entries of `x` to their prescribed values × `s`.
    pub fn impose(&self, x: &mut [f64], s: f64) {
        for r in &self.rows {
            x[r.dof] = s * r.value;
        }
    }

    /// Zeroes the constrained entries of a vector (e.g. a residual).
    pub fn zero(&self, v: &mut [f64]) {
        for r in &self.rows {
            v[r.dof] = 0.0;
        }
    }
}
