//! Typed errors of the mesh crate.

use std::path::PathBuf;

/// Everything that can be wrong with a mesh, its sets or its files.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum MeshError {
    /// A triangle with (numerically) zero area.
    #[error("triangle {element} has zero area ({area:.3e}); nodes {nodes:?}")]
    DegenerateTriangle {
        /// Element index (0-based).
        element: usize,
        /// Signed area.
        area: f64,
        /// Its node ids.
        nodes: [usize; 3],
    },
    /// An element refers to a node that does not exist.
    #[error("{what} {element} refers to node {node}, but the mesh has {n_nodes} nodes")]
    NodeOutOfRange {
        /// "triangle", "edge set 'x'", ...
        what: String,
        /// Index of the element or edge within its list.
        element: usize,
        /// The bad node id.
        node: usize,
        /// Number of nodes.
        n_nodes: usize,
    },
    /// Two nodes of one region sit at the same point.
    #[error(
        "nodes {a} and {b} coincide at ({x}, {y}) in region '{region}' (an unmerged mesh? coincident nodes are only allowed between different regions, as on an interface)"
    )]
    DuplicateNodes {
        /// First node.
        a: usize,
        /// Second node.
        b: usize,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
        /// Region using both.
        region: String,
    },
    /// A node that no triangle uses.
    #[error("node {node} at ({x}, {y}) is used by no triangle")]
    OrphanNode {
        /// The node.
        node: usize,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
    },
    /// A node coordinate that is NaN or infinite.
    #[error("node {node} has a non-finite coordinate ({x}, {y})")]
    NonFiniteCoordinate {
        /// The node.
        node: usize,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
    },
    /// A name that was looked up but does not exist.
    #[error("the mesh has no {kind} named '{name}' (it has: {available})")]
    UnknownName {
        /// "region", "edge set", "node set", "interface".
        kind: &'static str,
        /// The missing name.
        name: String,
        /// Comma-separated list of the names that exist.
        available: String,
    },
    /// An edge of an edge set that is not an edge of any triangle.
    #[error("edge set '{set}': edge ({a}, {b}) is not an edge of any triangle")]
    EdgeNotInMesh {
        /// Edge set name.
        set: String,
        /// First node.
        a: usize,
        /// Second node.
        b: usize,
    },
    /// Interface edges whose nodes do not face each other.
    #[error(
        "interface '{interface}': node {bottom} at ({x}, {y}) on '{bottom_set}' has no facing node on '{top_set}': facing nodes must coincide (within {tolerance:.3e}){}",
        nearest_text(*.nearest, *.distance)
    )]
    InterfaceNotFacing {
        /// Interface name.
        interface: String,
        /// Bottom edge set.
        bottom_set: String,
        /// Top edge set.
        top_set: String,
        /// The bottom node without a partner.
        bottom: usize,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
        /// The nearest node of the top set (`usize::MAX` if it has none).
        nearest: usize,
        /// Its distance (infinite if the top set has no nodes).
        distance: f64,
        /// Distance tolerance used.
        tolerance: f64,
    },
    /// The mid nodes of a quadratic interface element do not face each other.
    #[error(
        "interface '{interface}': mid node {bottom} of the bottom face and mid node {top} of the top face are {distance:.3e} apart (tolerance {tolerance:.3e}); facing nodes must coincide"
    )]
    InterfaceMidNotFacing {
        /// Interface name.
        interface: String,
        /// Bottom mid node.
        bottom: usize,
        /// Top mid node.
        top: usize,
        /// Their distance.
        distance: f64,
        /// Tolerance used.
        tolerance: f64,
    },
    /// A mid node of a 6-node triangle that does not fit the mesh.
    #[error("triangle {element}: node {mid}, the mid node of edge ({a}, {b}), is wrong: {reason}")]
    InconsistentMidNode {
        /// Element index.
        element: usize,
        /// Edge corner.
        a: usize,
        /// Edge corner.
        b: usize,
        /// The mid node.
        mid: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A curved triangle whose isoparametric map folds over.
    #[error(
        "triangle {element} is inverted or too distorted by its curved edges: det J at node {node} is {det_ratio:.3e} of the straight triangle's (a mid node too far from its edge's midpoint?)"
    )]
    InvertedCurvedTriangle {
        /// Element index.
        element: usize,
        /// The node where det J is not positive.
        node: usize,
        /// det J there over det J of the straight-sided triangle.
        det_ratio: f64,
    },
    /// Interface edge pair whose top edge is missing from the top set.
    #[error(
        "interface '{interface}': bottom edge ({a}, {b}) faces nodes ({c}, {d}), which are not an edge of '{top_set}'"
    )]
    InterfaceEdgeMissing {
        /// Interface name.
        interface: String,
        /// Top edge set name.
        top_set: String,
        /// Bottom edge nodes.
        a: usize,
        /// Bottom edge nodes.
        b: usize,
        /// Facing top nodes.
        c: usize,
        /// Facing top nodes.
        d: usize,
    },
    /// An interface element whose bottom and top faces are the same edge.
    #[error(
        "interface '{interface}': edge ({a}, {b}) faces itself; an interface needs separate nodes on its two faces"
    )]
    InterfaceSameEdge {
        /// Interface name.
        interface: String,
        /// Bottom edge node.
        a: usize,
        /// Bottom edge node.
        b: usize,
    },
    /// A generator parameter that makes no sense.
    #[error("invalid mesh parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Its value as text.
        value: String,
        /// Why it is rejected.
        reason: String,
    },
    /// A mesh too large for the memory available.
    #[error(
        "a mesh of {triangles} triangles and {nodes} nodes needs about {:.1} GB to generate, but only {:.1} GB are available; choose a coarser mesh",
        *.estimated_bytes as f64 / 1e9,
        *.available_bytes as f64 / 1e9
    )]
    TooLarge {
        /// Triangles requested.
        triangles: usize,
        /// Nodes requested.
        nodes: usize,
        /// Estimated peak bytes.
        estimated_bytes: u64,
        /// Bytes available.
        available_bytes: u64,
    },
    /// A mesh file that could not be read.
    #[error("{path}: {message}")]
    Io {
        /// File.
        path: PathBuf,
        /// OS message.
        message: String,
    },
    /// A Gmsh file that could not be parsed.
    #[error("{path}: {location}: {message}")]
    MshParse {
        /// File.
        path: PathBuf,
        /// "line N" (ASCII) or "byte offset N" (binary).
        location: String,
        /// What went wrong.
        message: String,
    },
    /// A Gmsh element type Tecon does not take.
    #[error(
        "{path}: element type {type_name} (Gmsh type {type_id}) on entity {entity} is not supported; Tecon takes 3- or 6-node triangles and 2- or 3-node lines (and ignores points)"
    )]
    UnsupportedElement {
        /// File.
        path: PathBuf,
        /// Gmsh type name.
        type_name: String,
        /// Gmsh type number.
        type_id: u32,
        /// Entity tag.
        entity: i32,
    },
    /// Other semantic problems in a Gmsh file.
    #[error("{path}: {message}")]
    MshContent {
        /// File.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

fn nearest_text(nearest: usize, distance: f64) -> String {
    if distance.is_finite() {
        format!("; the nearest, node {nearest}, is {distance:.3e} away")
    } else {
        "; the top set has no nodes".into()
    }
}
