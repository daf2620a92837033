//! # tecon-contact: interface elements and contact laws
//!
//! Constitutive laws of joints ([`ContactLaw`]), the 4-node interface
//! element ([`InterfaceElement`]) and the 6-node quadratic one with three
//! node pairs ([`QuadraticInterfaceElement`]) that join two bodies along a line in a
//! plane (strain) analysis. The crate knows nothing of meshes; the element
//! geometry (frame, integration rules, jump operator) is shared with the
//! thermal interface element through [`tecon_fem::interface`] and
//! re-exported here, as is [`nalgebra`], so that depending on
//! `tecon-contact` alone is enough to use laws and elements.
//!
//! ```
//! use tecon_contact::{ContactLaw, GhaboussiNormal, InterfaceElement, JointState, PaperJoint, Vector8};
//! use tecon_contact::nalgebra::Point2;
//!
//! // Smooth joint, k_n = k_s = 1e12 Pa/m, c = 0, φ = 30°.
//! let law = PaperJoint::new(GhaboussiNormal::penalty(1e12)?, 1e12, 0.0, 30f64.to_radians())?;
//! let nodes = [[0.0, 0.0], [0.1, 0.0], [0.1, 0.0], [0.0, 0.0]].map(|p| Point2::new(p[0], p[1]));
//! let element = InterfaceElement::new(&nodes)?;
//! // Top face pressed down by 1 µm and slid by 10 µm.
//! let u = Vector8::from_column_slice(&[0.0, 0.0, 0.0, 0.0, 10e-6, -1e-6, 10e-6, -1e-6]);
//! let r = element.evaluate(&law, &u, &[JointState::default(); 2]);
//! let [tau, sigma] = [r.points[0].traction.x, r.points[0].traction.y];
//! assert!((sigma + 1e6).abs() < 1e-6);                        // σ = −1 MPa
//! assert!((tau - 1e6 * 30f64.to_radians().tan()).abs() < 1e-6); // slipping: τ = σ_c tan φ
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Glossary (one symbol per quantity)
//!
//! | symbol | meaning | unit |
//! |---|---|---|
//! | `t`, `n` | unit tangent (1 → 2) and left normal of the bottom face; `n` points from bottom to top body | – |
//! | `R` | rotation global → local, rows `tᵀ`, `nᵀ` | – |
//! | `L`, `ζ` | element length, local coordinate `ζ ∈ [−L/2, L/2]` | m |
//! | `N₁`, `N₂` | `(1 ∓ 2ζ/L)/2` | – |
//! | `b` | scalar jump operator `[−N₁, −N₂, N₂, N₁]` over nodes 1..4 | – |
//! | `s`, `N₅` | quadratic element: face coordinate `s ∈ [−1, 1]`; `N₁ = s(s−1)/2`, `N₂ = s(s+1)/2`, `N₅ = 1 − s²`; `b = [−N₁, −N₂, N₂, N₁, −N₅, N₅]` over nodes 1..6 | – |
//! | `B` | 2 × 8 jump operator, `⟦u⟧ = B u` | – |
//! | `⟦u⟧ = [Δu_t, Δu_n]` | displacement jump top − bottom, local; `Δu_n > 0` opens | m |
//! | `[τ, σ]` = `[t_s, t_n]` | traction on the top face's bottom side, local; `σ > 0` tension | Pa |
//! | `σ_c = −σ` | compressive normal traction (contact pressure) | Pa |
//! | `C` | consistent tangent `∂[τ, σ]/∂⟦u⟧` | Pa/m |
//! | `k_n`, `k_s` | normal and shear stiffness per unit area | Pa/m |
//! | `t_j` (API: `thickness`) | joint thickness of the Ghaboussi law | m |
//! | `ε_n = Δu_n / t_j` | normal strain of the joint | – |
//! | `ε_n^c ≤ 0` | crushing strain limit (0 for smooth surfaces) | – |
//! | `E`, `E_f` | crushing and contact moduli of the Ghaboussi law | Pa |
//! | `c`, `φ` | cohesion, friction angle (radians in the API) | Pa, rad |
//! | `s = max(0, c + σ_c tan φ)` | shear strength (slip limit) | Pa |
//! | `g_s` | plastic tangential slip (history) | m |
//! | `λ` (API: `lambda_n`) | augmented-Lagrangian normal multiplier (a pressure) | Pa |
//! | `β` | default penalty factor, `k_n = β E/h` | – |
//!
//! ## Laws
//!
//! * [`LinearJoint`]: Goodman joint, `[τ, σ] = diag(k_s, k_n) ⟦u⟧`.
//! * [`GhaboussiNormal`]: the three-stage normal law (separation, crushing,
//!   contact); [`LinearNormal`]: a bilateral spring. Both implement
//!   [`NormalLaw`] and carry the augmented-Lagrangian multiplier.
//! * [`MohrCoulomb`]: elastic–perfectly plastic friction with cohesion
//!   on top of any normal law; [`PaperJoint`] is the paper's joint
//!   (Ghaboussi + Mohr–Coulomb); [`ElasticJoint`] has no slip limit.
//!
//! ## Using laws in a Newton solver
//!
//! Store one committed state per integration point; each iteration call
//! [`InterfaceElement::evaluate`] with trial displacements and the
//! committed states; commit the returned [`PointOutput::state`]s only when
//! the increment has converged. For penalty-independent contact pressure,
//! wrap the increment in an outer loop calling [`InterfaceElement::augment`]
//! (or [`ContactLaw::augment`]) until the multiplier change is small.

#![warn(missing_docs)]

mod element;
mod element3;
mod error;
mod joint;
mod law;
mod linear;
mod normal;

pub use element::{ElementResponse, InterfaceElement, Matrix8, PointOutput, Vector8};
pub use element3::{Matrix12, QuadraticElementResponse, QuadraticInterfaceElement, Vector12};
pub use error::{ContactError, LawError};
pub use joint::{ElasticJoint, FrictionBound, JointState, MohrCoulomb, PaperJoint};
pub use law::{Augmentation, ContactLaw, ContactStatus, LawResponse};
pub use linear::LinearJoint;
pub use normal::{
    DEFAULT_PENALTY_FACTOR, GhaboussiNormal, LinearNormal, NormalLaw, NormalResponse, NormalStage,
    default_penalty,
};

/// Re-export of `nalgebra`, whose types appear in this crate's API.
pub use nalgebra;
/// Re-export of the shared interface geometry (`tecon_fem::interface`).
pub use tecon_fem::interface::{
    DEFAULT_FACING_TOLERANCE, InterfaceGeometry, InterfaceGeometryError, InterfacePoint,
    InterfaceQuadrature,
};
/// Re-export of the shared 3-pair interface geometry (`tecon_fem::interface3`).
pub use tecon_fem::interface3::{Interface3Geometry, Interface3Point};
