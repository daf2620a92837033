//! `tecon-elastic`: plane elasticity on linear triangles with thermal strain
//! and nonlinear interface (contact) elements.
//!
//! * [`ElasticModel`]: materials per region, supports (fixed components,
//!   symmetry on edges of any orientation), pressure and body loads,
//!   interfaces with a [`Joint`] law; plane strain (default), plane stress,
//!   generalised plane strain.
//! * [`StaticSolver`]: load increments from the committed state, Newton with
//!   the consistent tangent (Cholesky when symmetric, LU when friction
//!   slips), backtracking line search, status-aware convergence, ping-pong
//!   guard, step cut-back, augmented-Lagrangian outer loop, free-body
//!   detection that names the body.
//! * [`TiedMesh`]: bonded (tied) interfaces, whose facing node pairs share
//!   their displacement unknowns (no penalty).
//! * Stress recovery: element and nodal stresses, polar components, von Mises;
//!   for 6-node triangles SPR per region and the ZZ indicator ([`recovery`]).
//! * [`analytical`]: closed-form solutions used for verification.
//! * Staged construction (layer after layer): [`ElasticModel::active_regions`]
//!   keeps the other triangles out of the system (their free nodes held),
//!   [`ElasticModel::interface_reference`] lets an interface activated on a
//!   deformed assembly measure its jumps from the displacements at
//!   activation, [`StaticSolver::state`] / [`StaticSolver::resume`] carry
//!   the state from one stage's solver to the next.
//!
//! # Glossary
//! * u = (u_x, u_y): displacement; ε = (ε_xx, ε_yy, γ_xy), ε_zz; σ = (σ_xx, σ_yy, σ_xy), σ_zz.
//! * E, ν, α: Young's modulus, Poisson's ratio, thermal expansion; λ, μ: Lamé constants.
//! * ΔT = T − T_ref: temperature change of an element from its stress-free reference.
//! * Plane strain free thermal strain in the plane: (1 + ν) α ΔT.
//! * σ_rr, σ_θθ, σ_rθ: polar components about a centre; σ_θθ is the hoop stress.
//! * ⟦u⟧ = [Δu_t, Δu_n]: interface jump; [τ, σ]: interface traction (σ > 0 tension).
//! * u_ref: reference displacements of an interface, ⟦u⟧ = B (u − u_ref)
//!   (zero unless the interface was activated on a deformed assembly).
//! * R: residual f_ext − f_int; K_T: consistent tangent.
//! * σ*: recovered (SPR) stress; η_e: Zienkiewicz–Zhu indicator of element e.

pub mod analytical;
mod error;
mod joint;
mod kernels;
mod material;
mod model;
pub mod recovery;
mod rotation;
mod solver;
mod staging;
mod tie;

pub use error::{ElasticError, IterationRecord};
pub use joint::Joint;
pub use kernels::{
    P2_RULE, element_stress, gps_triangle, gps_triangle6, plane_triangle, plane_triangle6,
    plane_triangle6_load, triangle6_stresses,
};
pub use material::{Analysis, Material};
pub use model::{Component, ElasticModel, InterfaceNormals, ModelInterface};
pub use solver::{
    COARSE_LEVELS, COUPLED_TAIL_MAX_ITERATIONS, IncrementReport, InterfacePointResult, Loads,
    PASS_FORCING, PointStates, QuadraticStresses, SolverOptions, SolverState, StaticSolver,
    StressField, nodal_displacement, polar, quadratic_stresses, stresses, von_mises,
};
pub use tie::TiedMesh;
