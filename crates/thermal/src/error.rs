//! Typed errors of the heat-conduction crate.

use tecon_fem::FemError;
use tecon_fem::interface::InterfaceGeometryError;
use tecon_mesh::MeshError;

/// Everything that can go wrong when building or solving a thermal model.
///
/// Every variant that stems from user input names the region, edge set,
/// node set, interface or element concerned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ThermalError {
    /// A mesh look-up failed (unknown region, edge set, node set, interface).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Assembly or a linear solve failed.
    #[error(transparent)]
    Fem(#[from] FemError),
    /// A 6-node triangle of a P2 mesh is inverted or folded.
    #[error("triangle {element} (6-node): {source}")]
    InvalidElement {
        /// Element (triangle) index.
        element: usize,
        /// What is wrong with its geometry.
        source: tecon_fem::triangle6::Triangle6Error,
    },
    /// An edge of a P2 mesh's edge set has no mid node, or its 3-node
    /// geometry is degenerate.
    #[error("edge set '{set}', edge {a}–{b}: {reason}")]
    InvalidEdge {
        /// Edge set name.
        set: String,
        /// First corner node.
        a: usize,
        /// Second corner node.
        b: usize,
        /// What is wrong.
        reason: String,
    },
    /// A material property that must be positive and finite is not.
    #[error("region '{region}': {property} must be positive and finite, got {value}")]
    InvalidMaterial {
        /// Region name.
        region: String,
        /// "conductivity k", "density ρ" or "specific heat c".
        property: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A region of the mesh has no material.
    #[error("region '{region}' has no thermal material (set one with ThermalModel::set_material)")]
    MissingMaterial {
        /// Region name.
        region: String,
    },
    /// A boundary condition value is not admissible.
    #[error("edge or node set '{set}': {what} {reason}, got {value}")]
    InvalidBoundary {
        /// Edge or node set name.
        set: String,
        /// Which quantity ("film coefficient h", "ambient temperature T∞", ...).
        what: &'static str,
        /// Why it was rejected.
        reason: &'static str,
        /// The offending value.
        value: f64,
    },
    /// Two prescribed temperatures disagree at one node.
    #[error(
        "node {node} receives two different prescribed temperatures: {first} (from '{first_set}') and {second} (from '{second_set}')"
    )]
    ConflictingTemperature {
        /// Node id.
        node: usize,
        /// First value.
        first: f64,
        /// Set giving the first value.
        first_set: String,
        /// Second value.
        second: f64,
        /// Set giving the second value.
        second_set: String,
    },
    /// An interface conductance is negative, zero (for a constant law) or not finite.
    #[error(
        "interface '{interface}'{}: conductance h_c must be {requirement}, got {value}",
        element.map(|e| format!(", element {e}")).unwrap_or_default()
    )]
    InvalidConductance {
        /// Interface name ("(constant law)" when the law itself is rejected).
        interface: String,
        /// Element index within the interface (`None` for the law itself).
        element: Option<usize>,
        /// What is required.
        requirement: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A parameter of a conductance law is out of range.
    #[error("conductance law '{law}': {parameter} must be {requirement}, got {value}")]
    InvalidLawParameter {
        /// The law.
        law: &'static str,
        /// The parameter (as named in case files).
        parameter: &'static str,
        /// What is required.
        requirement: &'static str,
        /// The offending value.
        value: f64,
    },
    /// An interface of the mesh was given neither a conductance law nor
    /// declared adiabatic.
    #[error(
        "interface '{interface}' has no conductance law (give one with set_interface_law, or declare it adiabatic)"
    )]
    MissingInterfaceLaw {
        /// Interface name.
        interface: String,
    },
    /// The geometry of an interface element is invalid.
    #[error("interface '{interface}', element {element}: {source}")]
    InterfaceGeometry {
        /// Interface name.
        interface: String,
        /// Element index within the interface.
        element: usize,
        /// What the shared geometry rejected.
        source: InterfaceGeometryError,
    },
    /// The number of interface states given does not match the interface.
    #[error(
        "interface '{interface}': {got} point states given, the interface has {expected} elements"
    )]
    InterfaceStateLength {
        /// Interface name.
        interface: String,
        /// States given.
        got: usize,
        /// Elements of the interface.
        expected: usize,
    },
    /// A region has no initial temperature (and no default was given).
    #[error("region '{region}' has no initial temperature (set one per region or a default)")]
    MissingInitialTemperature {
        /// Region name.
        region: String,
    },
    /// A transient run was asked of a model without any initial temperature.
    #[error("no initial temperature was given (set a default, per region or per node)")]
    NoInitialTemperature,
    /// An initial temperature is not finite.
    #[error("initial temperature of {what} is not finite: {value}")]
    InvalidInitialTemperature {
        /// "region 'weld'", "node 12", "default".
        what: String,
        /// The offending value.
        value: f64,
    },
    /// A node id outside the mesh.
    #[error("{what}: node {node} is outside the mesh of {n_nodes} nodes")]
    NodeOutOfRange {
        /// Where it was given.
        what: String,
        /// The node id.
        node: usize,
        /// Number of nodes.
        n_nodes: usize,
    },
    /// A steady problem in which some body (or group of bodies joined by
    /// interfaces) has neither a prescribed temperature nor convection: its
    /// temperature level is undetermined and the conductivity matrix is singular.
    #[error(
        "singular steady problem: {description} has no prescribed temperature and no convection, so its temperature level is undetermined; prescribe a temperature or add a convective edge"
    )]
    SingularSteady {
        /// Which body or bodies, as found by the free-mode check.
        description: String,
        /// Names of the bodies taking part.
        bodies: Vec<String>,
    },
    /// The time schedule asks for more steps than [`crate::MAX_STEPS`].
    #[error("the time schedule has {steps} steps (more than the limit {limit}); use larger steps")]
    TooManySteps {
        /// Steps requested.
        steps: f64,
        /// The limit.
        limit: usize,
    },
    /// The time schedule does not advance time.
    #[error("the time schedule does not advance: {reason}")]
    ScheduleDoesNotAdvance {
        /// Which step or segment, and why.
        reason: String,
    },
    /// θ outside [1/2, 1] (the unconditionally stable range).
    #[error("θ = {theta} is outside [0.5, 1] (θ < 1/2 is only conditionally stable)")]
    InvalidTheta {
        /// The offending θ.
        theta: f64,
    },
    /// A requested output time lies outside the schedule.
    #[error("output time {time} lies outside the schedule [{start}, {end}]")]
    OutputTimeOutOfRange {
        /// The requested time.
        time: f64,
        /// Schedule start.
        start: f64,
        /// Schedule end.
        end: f64,
    },
    /// A vector of the wrong length (initial field, per-node data).
    #[error("{what}: length {got}, expected {expected}")]
    LengthMismatch {
        /// Which vector.
        what: String,
        /// Its length.
        got: usize,
        /// The expected length.
        expected: usize,
    },
}
