//! Typed errors of the finite-element machinery.

/// Errors from assembly, constraints and linear solves.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum FemError {
    /// A dof index outside the system.
    #[error("{what}: dof {dof} is outside the system of {n_dofs} dofs")]
    DofOutOfRange {
        /// Where it was found.
        what: String,
        /// The dof.
        dof: usize,
        /// Size of the system.
        n_dofs: usize,
    },
    /// A vector or slice of the wrong length.
    #[error("{what}: length {got}, expected {expected}")]
    LengthMismatch {
        /// Which vector.
        what: String,
        /// Its length.
        got: usize,
        /// The length it should have.
        expected: usize,
    },
    /// A body (or a group of bodies) that the constraints leave free to move.
    #[error(
        "the system is singular: {description} is not constrained (normalised energy {energy:.2e}); add a support, a symmetry condition, or ask for the minimal constraint"
    )]
    Unconstrained {
        /// Human-readable description, e.g. "body 'layer' in x-translation".
        description: String,
        /// Which bodies take part in the free mode.
        bodies: Vec<String>,
        /// Which mode names take part.
        modes: Vec<String>,
        /// Normalised energy of the free mode (≈ 0).
        energy: f64,
    },
    /// The matrix is not positive definite at the given pivot.
    #[error(
        "Cholesky factorisation failed at pivot {pivot} (dof {dof}): the matrix is not positive definite; {hint}"
    )]
    NotPositiveDefinite {
        /// Pivot index in the permuted order.
        pivot: usize,
        /// The original dof, when known.
        dof: usize,
        /// What to check.
        hint: String,
    },
    /// The matrix is singular (LU could not find a pivot, or the solution is not finite).
    #[error("the linear system is singular: {detail}")]
    Singular {
        /// What was observed.
        detail: String,
    },
    /// Solve called before a numeric factorisation.
    #[error("solve called before factorise")]
    NotFactorised,
    /// Failure inside the sparse solver library.
    #[error("sparse solver: {0}")]
    Solver(String),
    /// A non-finite value in a matrix or vector.
    #[error("{what} contains a non-finite value at index {index}")]
    NonFinite {
        /// Which array.
        what: String,
        /// First bad index.
        index: usize,
    },
}
