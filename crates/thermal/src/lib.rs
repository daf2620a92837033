//! `tecon-thermal`: steady and transient heat conduction on linear
//! triangles, with convective, prescribed-flux and prescribed-temperature
//! edges and thermal interface elements between bodies.
//!
//! The rhythm follows deal.II step-26: the conductivity K and capacity C
//! are assembled **once** on one sparsity pattern ([`ThermalSystem`]); the
//! time stepper ([`ThetaStepper`]) combines them per step size,
//! `C/Δt + θK`, factorises once per distinct (Δt, θ) and then costs one
//! mat-vec and one pair of triangular solves per step.
//!
//! ```
//! use tecon_mesh::{vessel_mesh, VesselGeometry, VesselMeshSpec};
//! use tecon_thermal::{EdgeBc, Material, ThermalModel, ThetaScheme, TimeSchedule};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let mesh = vessel_mesh(&VesselGeometry::default(), &VesselMeshSpec::paper())?;
//! let mut model = ThermalModel::new(&mesh);
//! model.set_material_everywhere(Material::vessel_steel())?;
//! model.add_edge_bc("inner", EdgeBc::convection(10.25, 21.0))?;
//! model.add_edge_bc("outer", EdgeBc::convection(10.25, 21.0))?;
//! model.set_interface_conductance("core_layer", 850.0)?;
//! model.set_initial_default(21.0)?.set_initial_region("weld", 1132.0)?;
//! let schedule = TimeSchedule::segments(&[(10.0, 0.1), (600.0, 5.0), (36000.0, 120.0)])?;
//! let snaps = model.solve_transient_collect(&schedule, ThetaScheme::crank_nicolson(), &[60.0, 36000.0])?;
//! // After 10 h the vessel is back at ambient; the heat balance closed.
//! assert!(snaps[1].temperature.iter().all(|t| (t - 21.0).abs() < 1e-3));
//! assert!(snaps[1].balance.relative_residual() < 1e-10);
//! // Coupling to the elastic solve: element temperatures and references.
//! let system = model.assemble()?;
//! let t_ref = system.reference_temperature().ok_or("no initial temperature")?;
//! assert_eq!(t_ref.len(), snaps[1].element_temperature.len());
//! # Ok(()) }
//! ```
//!
//! # Rules worth knowing
//! * Edges without a condition are adiabatic.
//! * Initial temperature: per region (with a default), nodes on a border
//!   between regions by [`BorderRule`] (default: capacity-weighted mean of
//!   the adjacent elements, which keeps the initial heat content with the
//!   lumped capacity), then per-node overrides; prescribed temperatures
//!   override all of these at t = 0.
//! * Reference temperature of an element (for the thermal strain): the
//!   element mean of the initial nodal field
//!   ([`ThermalSystem::reference_temperature`]); the region value is also
//!   available ([`ThermalSystem::region_initial_temperature`]).
//! * Interface flux sign: `q = h_c (T_top − T_bottom)` is heat flowing from
//!   the top body (left of the bottom face 1→2) into the bottom body.
//! * Boundary data are constant in time.
//! * Element order follows the mesh: on a P2 mesh (`Mesh::order() == 2`)
//!   the model assembles 6-node triangles, 3-node edges (mid node from
//!   `Mesh::edge_mid_node`) and 3-pair interfaces (`Interface::mid_nodes`);
//!   nothing else changes in its use.
//!
//! # Glossary
//! * T: temperature (nodal); T∞: ambient; T₀: initial; T_ref,e: element
//!   reference temperature (its initial temperature).
//! * k: conductivity, W/(m K); ρ: density; c: specific heat; ρc:
//!   volumetric capacity; a = k/(ρc): diffusivity.
//! * h: film coefficient, W/(m² K); h_c: interface conductance, W/(m² K);
//!   p: contact pressure; g: gap; g₀: temperature-jump distance; k_g: gas
//!   conductivity; h₀, p₀, m: power law; σ, m, H_c, k_s: Mikic/Yovanovich;
//!   ε: emissivity; σ_SB: Stefan–Boltzmann constant;
//!   q: heat flux, W/m² (`q = −k∇T` in elements, `q = h_c ⟦T⟧` at interfaces).
//! * ⟦T⟧ = T_top − T_bottom: temperature jump across an interface;
//!   b = [−N₁, −N₂, N₂, N₁]: the scalar jump operator.
//! * N_i: shape functions; A: triangle area; L: edge or interface length;
//!   ζ: coordinate along an interface element.
//! * K: conductivity matrix (conduction + convection + interfaces); C:
//!   capacity matrix; F: load vector; w = C·1: capacity weights.
//! * θ: θ-method parameter (1 backward Euler, 1/2 Crank–Nicolson); Δt: time step.
//! * Bi = hL/k: Biot number; Fo = a t/L²: Fourier number.
//! * Heat amounts are per metre of out-of-plane thickness (J/m, W/m).
//! * P2: 6-node triangles (corners, then mid nodes of edges (0,1), (1,2),
//!   (2,0)), 3-node edges `[a, b, mid]`, 3-pair interfaces with
//!   b = [−N₁, −N₂, N₂, N₁, −N₅, N₅] ([`kernels6`]); HRZ: lumped capacity
//!   by diagonal scaling.

pub mod analytical;
mod bc;
mod conductance;
mod error;
mod initial;
pub mod kernels;
pub mod kernels6;
mod material;
mod model;
mod output;
mod schedule;
mod stepper;
mod system;

pub use bc::EdgeBc;
pub use conductance::{
    ConductanceLaw, ConstantConductance, ContactPart, GasGap, InterfacePointState,
    JointConductance, MikicYovanovich, PowerLaw, Radiation, STEFAN_BOLTZMANN,
};
pub use error::ThermalError;
pub use initial::{BorderRule, InitialTemperature};
pub use material::{CapacityKind, Material};
pub use model::{
    ThermalModel, TransientSummary, run_transient, run_transient_observed, run_transient_while,
};
pub use output::{BodyBalance, HeatBalance, InterfaceFlux, InterfaceResult, Snapshot};
pub use schedule::{MAX_STEPS, ThetaScheme, TimeSchedule};
pub use stepper::{DEFAULT_POOL, StepperStats, ThetaStepper};
pub use system::ThermalSystem;
pub use tecon_fem::interface::InterfaceQuadrature;
