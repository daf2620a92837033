//! `tecon-fem`: the shared finite-element machinery of Tecon.
//!
//! * [`Element`]: a set of elements with a pure local kernel (fixed-size
//!   `nalgebra` matrix and vector) and its dof connectivity.
//! * [`Assembler`]: the CSR pattern built once from all element blocks
//!   (interface elements included), an element→slot map, values refilled in
//!   parallel with bitwise identical results for any thread count.
//! * [`DofMap`], [`Dirichlet`] constraints (symmetric elimination inside the
//!   pattern), [`modes`] rigid-mode detection naming the free body.
//! * [`CholeskySolver`] and [`LuSolver`] (faer): symbolic once, numeric many times.
//! * [`triangle`]: linear-triangle geometry and reference kernels;
//!   [`interface`]: geometry of 4-node interface elements.
//! * [`triangle6`]: the 6-node isoparametric (curved) triangle and its
//!   kernels; [`edge3`]: the 3-node (curved) edge; [`interface3`]: geometry
//!   of the 3-pair quadratic interface element; [`quadrature`]: Gauss rules
//!   on the triangle (degrees 2, 4, 5) and on the segment.
//!
//! # Glossary
//! * N_i: shape functions; B: strain–displacement matrix; D: elasticity matrix.
//! * A: triangle area; k: conductivity; ρc: volumetric heat capacity.
//! * dof: global unknown index, `node · n_components + component`.
//! * slot: index of a stored entry in the CSR value array.
//! * (ξ, η): reference coordinates of a triangle, L₁ = 1 − ξ − η, L₂ = ξ,
//!   L₃ = η its barycentric coordinates; J = ∂x/∂ξ the isoparametric Jacobian.
//! * s ∈ [−1, 1]: reference coordinate of a 3-node edge or interface face;
//!   |x'(s)| its arc-length Jacobian.
//! * w_q: quadrature weight (reference measure; times det J or |x'| in physical units).
//! * HRZ: Hinton–Rock–Zienkiewicz lumping (the consistent diagonal, scaled to the total).

pub mod assembler;
pub mod condensed;
pub mod constraints;
pub mod dofmap;
pub mod edge3;
pub mod error;
pub mod interface;
pub mod interface3;
pub mod modes;
pub mod ordering;
pub mod pattern;
pub mod quadrature;
pub mod reference;
pub mod solver;
pub mod triangle;
pub mod triangle6;
pub mod triangular;
pub mod update;

pub use assembler::{Assembler, AssemblerBuilder, BlockId, Element, LocalSystem, Parallelism};
pub use condensed::CondensedCholesky;
pub use constraints::{Dirichlet, PreparedDirichlet};
pub use dofmap::DofMap;
pub use error::FemError;
pub use modes::{RigidMode, check_rigid_modes, plane_rigid_modes, scalar_mode};
pub use pattern::{CsrMatrix, SparsityPattern};
pub use solver::{CholeskySolver, FillOrdering, LuSolver, relative_residual};
pub use update::{SolveKind, UpdateStats, UpdatedCholesky};
