//! # tecon-wavelet-bem: Saint-Venant torsion by a wavelet boundary integral method
//!
//! Prandtl stress function u (Gθ = 1): ∇²u = −2 in Ω, u = 0 on Γ. With the
//! particular solution u_p = −|x − x₀|²/2, v = u − u_p is harmonic with
//! v = g = |x − x₀|²/2 on Γ, and its flux q_v solves the augmented first-kind
//! system (never the bare one, which is singular at logarithmic capacity 1)
//!
//! ```text
//! V q_v + c = (½I + K) g,   ∮ q_v ds = 0,   J = I_p − ½ ∮ |x − x₀|² q_v ds.
//! ```
//!
//! Three discretisations share the graded periodic parametrisation
//! ([`grading`]) and the log-kernel split ln|x(s) − x(t)| = ln|2 sin π(s − t)| + L(s, t):
//! periodised Daubechies wavelet Galerkin ([`galerkin`], the default), harmonic
//! (Shannon) wavelet Galerkin with oversampled quadrature ([`shannon`],
//! spectral, the independent cross-check) and Kress Nyström
//! ([`nystrom`], the reference).
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use tecon_wavelet_bem::{sections, solve, Options};
//! let sec = sections::ellipse(2.0, 1.0)?;
//! let sol = solve(&sec, &Options::default())?;
//! println!("J = {}", sol.torsional_rigidity);
//! # Ok(()) }
//! ```
//!
//! ## Glossary
//!
//! | symbol | meaning |
//! |---|---|
//! | Ω, Γ | section and its boundary (counter-clockwise) |
//! | u | Prandtl stress function, ∇²u = −2, u = 0 on Γ (Gθ = 1) |
//! | q | ∂u/∂n on Γ (≤ 0); boundary shear stress τ = \|q\| |
//! | x₀ | centroid; u_p = −\|x − x₀\|²/2 |
//! | g | \|x − x₀\|²/2, Dirichlet data of v = u − u_p |
//! | q_v | ∂v/∂n, unknown of the boundary equation; q = q_v − (x − x₀)·n |
//! | w | fundamental solution −(1/2π) ln\|x − y\| |
//! | V, K | single- and double-layer operators |
//! | c | Lagrange multiplier of the augmented system (exactly 0) |
//! | J | torsional rigidity 2∫u dA; torque T = GθJ |
//! | I_p | polar moment ¼∮\|x − x₀\|² (x − x₀)·n ds |
//! | t | periodic boundary parameter in [0, 1) |
//! | μ | density per parameter q_v(x(t)) \|x′(t)\| |
//! | L | smooth log remainder ln\|x(t) − x(s)\| − ln\|2 sin π(t − s)\| |
//! | p | Kress grading exponent |
//! | n, J | number of unknowns, n = 2^J for Daubechies |
//! | N (N_v) | Daubechies order = number of vanishing moments (dbN) |
//! | h_k, g_k | low- and high-pass filters; c_k = √2 h_k |
//! | φ, ψ, φ̂ | scaling function, wavelet, Fourier transform of φ |
//! | Φ, p_j, M_m | autocorrelation of φ, its filter and moments |
//! | a(d) | ∫∫ φ(X) φ(Y) ln\|X − Y + d\| dX dY |
//! | W | periodised fast wavelet transform (orthogonal) |
//! | ε | compression threshold relative to max\|a_ij\| |
//! | ω | warping function, ∇²ω = 0, ∂ω/∂n = Y n_x − X n_y (X, Y from x₀); conjugate of v = u + \|x − x₀\|²/2 |
//! | ω̃, C_k | −∫μ dt along curve k, and its constant (C_0 = 0 before normalising) |
//! | ω_n | normalised warping function about the shear centre (∫ω_n dA = 0) |
//! | x_S | shear centre (Trefftz): ∫ X ω_S dA = ∫ Y ω_S dA = 0 |
//! | Γ | warping constant ∫ ω_n² dA |
//! | Φ | r²(1 − ln r)/8π, ∇²Φ = w; gives ∫ω² dA from boundary data |

pub mod analytical;
pub mod control;
pub mod daubechies;
pub mod density;
pub mod error;
pub mod galerkin;
pub mod geometry;
pub mod grading;
pub mod kernels;
pub mod linalg;
mod logarithm;
pub mod memory;
pub mod nystrom;
pub mod polyline;
pub mod quadrature;
pub mod sections;
pub mod shannon;
pub mod solve;
pub mod symmetry;
pub mod warping;

pub use control::{Controlled, solve_to_tolerance, solve_with_estimate};
pub use error::{GeometryError, SolveError, SpecError};
pub use geometry::{Piece, Section};
pub use solve::{LinearSolver, Method, Options, TorsionSolution, solve};
pub use warping::{Warping, WarpingSample};
