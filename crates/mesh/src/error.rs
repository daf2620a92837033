//! Typed errors of the mesh crate.

use std::path::PathBuf;

/// Everything that can be wrong with a mesh, its sets or its files.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum MeshError {
    /// A triangle with (numerically) zero area.
    #[error(
        "triangle {} has zero area ({area:.3e}); nodes {}",
        .gmsh.element(*.element),
        .gmsh.nodes(.nodes)
    )]
    DegenerateTriangle {
        /// Element index (0-based).
        element: usize,
        /// Signed area.
        area: f64,
        /// Its node ids.
        nodes: [usize; 3],
        /// Gmsh tags of the element and nodes (a mesh read from a .msh file).
        gmsh: GmshRefs,
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
        "nodes {} and {} coincide at ({x}, {y}) in region '{region}' (an unmerged mesh? coincident nodes are only allowed between different regions, as on an interface){}",
        .gmsh.node(*.a),
        .gmsh.node(*.b),
        .gmsh.merge_hint()
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
        /// Gmsh tags of the nodes (a mesh read from a .msh file).
        gmsh: GmshRefs,
    },
    /// A node that no triangle uses.
    #[error("node {} at ({x}, {y}) is used by no triangle", .gmsh.node(*.node))]
    OrphanNode {
        /// The node.
        node: usize,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
        /// Gmsh tag of the node (a mesh read from a .msh file).
        gmsh: GmshRefs,
    },
    /// A node coordinate that is NaN or infinite.
    #[error("node {} has a non-finite coordinate ({x}, {y})", .gmsh.node(*.node))]
    NonFiniteCoordinate {
        /// The node.
        node: usize,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
        /// Gmsh tag of the node (a mesh read from a .msh file).
        gmsh: GmshRefs,
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
    /// A name looked up in a mesh read from a Gmsh file whose physical group
    /// exists in the file but holds no element Tecon reads.
    #[error(
        "the mesh has no {kind} named '{name}': the Gmsh file declares '{name}' as a {} (dimension {dim}), but that group holds {} (the {kind}s the mesh has: {available})",
        group_words(*.dim),
        empty_words(*.dim)
    )]
    EmptyGroup {
        /// "region", "edge set", "node set".
        kind: &'static str,
        /// The group's name.
        name: String,
        /// Its dimension in the Gmsh file (0 point, 1 curve, 2 surface, 3 volume).
        dim: i32,
        /// Comma-separated list of the names of that kind that exist.
        available: String,
    },
    /// An edge of an edge set that is not an edge of any triangle.
    #[error(
        "edge set '{set}': edge between nodes {} and {} is not an edge of any triangle",
        .gmsh.node(*.a),
        .gmsh.node(*.b)
    )]
    EdgeNotInMesh {
        /// Edge set name.
        set: String,
        /// First node.
        a: usize,
        /// Second node.
        b: usize,
        /// Gmsh tags of the nodes (a mesh read from a .msh file).
        gmsh: GmshRefs,
    },
    /// Interface edges whose nodes do not face each other.
    #[error(
        "interface '{interface}': node {} at ({x}, {y}) on '{bottom_set}' has no facing node on '{top_set}': facing nodes must coincide (within {tolerance:.3e}){}",
        .gmsh.node(*.bottom),
        nearest_text(.gmsh, *.nearest, *.distance)
    )]
    InterfaceNotFacing {
        /// Interface name.
        interface: String,
        /// Bottom edge set.
        bottom_set: Box<str>,
        /// Top edge set.
        top_set: Box<str>,
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
        /// Gmsh tags of the nodes (a mesh read from a .msh file).
        gmsh: GmshRefs,
    },
    /// The mid nodes of a quadratic interface element do not face each other.
    #[error(
        "interface '{interface}': mid node {} of the bottom face and mid node {} of the top face are {distance:.3e} apart (tolerance {tolerance:.3e}); facing nodes must coincide",
        .gmsh.node(*.bottom),
        .gmsh.node(*.top)
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
        /// Gmsh tags of the nodes (a mesh read from a .msh file).
        gmsh: GmshRefs,
    },
    /// A mid node of a 6-node triangle that does not fit the mesh.
    #[error(
        "triangle {}: node {}, the mid node of the edge between nodes {} and {}, is wrong: {reason}",
        .gmsh.element(*.element),
        .gmsh.node(*.mid),
        .gmsh.node(*.a),
        .gmsh.node(*.b)
    )]
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
        /// Gmsh tags of the element and nodes (a mesh read from a .msh file).
        gmsh: GmshRefs,
    },
    /// A curved triangle whose isoparametric map folds over.
    #[error(
        "triangle {} is inverted or too distorted by its curved edges: det J at node {} is {det_ratio:.3e} of the straight triangle's (a mid node too far from its edge's midpoint?)",
        .gmsh.element(*.element),
        .gmsh.node(*.node)
    )]
    InvertedCurvedTriangle {
        /// Element index.
        element: usize,
        /// The node where det J is not positive.
        node: usize,
        /// det J there over det J of the straight-sided triangle.
        det_ratio: f64,
        /// Gmsh tags of the element and node (a mesh read from a .msh file).
        gmsh: GmshRefs,
    },
    /// Interface edge pair whose top edge is missing from the top set.
    #[error(
        "interface '{interface}': the bottom edge between nodes {} and {} faces nodes {} and {}, which are not an edge of '{top_set}'",
        .gmsh.node(*.a),
        .gmsh.node(*.b),
        .gmsh.node(*.c),
        .gmsh.node(*.d)
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
        /// Gmsh tags of the nodes (a mesh read from a .msh file).
        gmsh: GmshRefs,
    },
    /// An interface element whose bottom and top faces are the same edge.
    #[error(
        "interface '{interface}': the edge between nodes {} and {} faces itself; an interface needs separate nodes on its two faces",
        .gmsh.node(*.a),
        .gmsh.node(*.b)
    )]
    InterfaceSameEdge {
        /// Interface name.
        interface: String,
        /// Bottom edge node.
        a: usize,
        /// Bottom edge node.
        b: usize,
        /// Gmsh tags of the nodes (a mesh read from a .msh file).
        gmsh: GmshRefs,
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
        "{path}: element type {type_name} (Gmsh type {type_id}) on entity {entity} is not supported; Tecon takes 3- or 6-node triangles, 2- or 3-node lines and points"
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

fn nearest_text(gmsh: &GmshRefs, nearest: usize, distance: f64) -> String {
    if distance.is_finite() {
        format!(
            "; the nearest, node {}, is {distance:.3e} away",
            gmsh.node(nearest)
        )
    } else {
        "; the top set has no nodes".into()
    }
}

/// "physical curve" for dimension 1, ...
pub(crate) fn group_words(dim: i32) -> &'static str {
    match dim {
        0 => "physical point",
        1 => "physical curve",
        2 => "physical surface",
        _ => "physical volume",
    }
}

fn empty_words(dim: i32) -> &'static str {
    match dim {
        0 => "no point on a node of the triangles (a point element Tecon reads as a node set)",
        1 => "no 2- or 3-node line (the elements of an edge set)",
        2 => "no 3- or 6-node triangle (the elements of a region)",
        _ => "nothing Tecon reads (Tecon reads 2D meshes: triangles, lines and points)",
    }
}

/// The Gmsh tags of the nodes and triangles an error names, so that the
/// message gives them next to Tecon's 0-based indices (empty for a mesh not
/// read from a Gmsh file, and then the message names the indices alone).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GmshRefs(Option<Box<Refs>>);

#[derive(Debug, Clone, PartialEq)]
struct Refs {
    /// (node index, Gmsh node tag).
    nodes: Vec<(usize, u64)>,
    /// (triangle index, Gmsh element tag).
    elements: Vec<(usize, u64)>,
}

impl GmshRefs {
    /// No tags: the message names Tecon's indices alone.
    pub const NONE: GmshRefs = GmshRefs(None);

    /// The tags of `nodes` and `elements` from a mesh's [`GmshTags`]; the
    /// indices without one (a node Tecon added, as the mid nodes of a
    /// promoted mesh) are left out.
    pub(crate) fn of(tags: &GmshTags, nodes: &[usize], elements: &[usize]) -> GmshRefs {
        GmshRefs(Some(Box::new(Refs {
            nodes: nodes
                .iter()
                .filter_map(|&i| tags.node(i).map(|t| (i, t)))
                .collect(),
            elements: elements
                .iter()
                .filter_map(|&e| tags.element(e).map(|t| (e, t)))
                .collect(),
        })))
    }

    /// Whether no tag is known (the mesh was not read from a Gmsh file).
    pub fn is_empty(&self) -> bool {
        self.0
            .as_ref()
            .is_none_or(|r| r.nodes.is_empty() && r.elements.is_empty())
    }

    /// The Gmsh tag of node `i`, if known.
    pub fn node_tag(&self, i: usize) -> Option<u64> {
        let r = self.0.as_ref()?;
        r.nodes.iter().find(|&&(k, _)| k == i).map(|&(_, t)| t)
    }

    /// The Gmsh tag of triangle `e`, if known.
    pub fn element_tag(&self, e: usize) -> Option<u64> {
        let r = self.0.as_ref()?;
        r.elements.iter().find(|&&(k, _)| k == e).map(|&(_, t)| t)
    }

    /// "17" or "17 (Gmsh node tag 1234)".
    pub fn node(&self, i: usize) -> String {
        match self.node_tag(i) {
            Some(t) => format!("{i} (Gmsh node tag {t})"),
            None => i.to_string(),
        }
    }

    /// "5" or "5 (Gmsh element tag 901)".
    pub fn element(&self, e: usize) -> String {
        match self.element_tag(e) {
            Some(t) => format!("{e} (Gmsh element tag {t})"),
            None => e.to_string(),
        }
    }

    /// "1, 2, 3" with the tags of those that have one.
    pub fn nodes(&self, list: &[usize]) -> String {
        list.iter()
            .map(|&i| self.node(i))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// How to merge coincident nodes in Gmsh (only for a Gmsh mesh).
    fn merge_hint(&self) -> &'static str {
        if self.is_empty() {
            ""
        } else {
            "; in Gmsh, let the surfaces share their curves (Coherence, or BooleanFragments with the OpenCASCADE kernel) or merge the duplicate nodes after meshing (`Coherence Mesh;` in a .geo file, gmsh.model.mesh.removeDuplicateNodes() in Python)"
        }
    }
}

/// What a mesh read from a .msh file keeps of it: the Gmsh node tag of each
/// node and element tag of each triangle (in Tecon's numbering), and the
/// physical groups that hold nothing Tecon reads.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GmshTags {
    /// Gmsh node tag of each node (nodes Tecon added later, as mid nodes of
    /// a promoted mesh, lie past its end).
    pub nodes: Vec<u64>,
    /// Gmsh element tag of each triangle.
    pub elements: Vec<u64>,
    /// (dimension, name) of the physical groups declared in the file that
    /// hold no element Tecon reads.
    pub empty_groups: Vec<(i32, String)>,
}

impl GmshTags {
    /// The Gmsh tag of node `i`.
    pub fn node(&self, i: usize) -> Option<u64> {
        self.nodes.get(i).copied()
    }

    /// The Gmsh tag of triangle `e`.
    pub fn element(&self, e: usize) -> Option<u64> {
        self.elements.get(e).copied()
    }
}

impl MeshError {
    /// The same error, naming the nodes and triangles also by their Gmsh
    /// tags (other errors are returned unchanged).
    pub fn with_gmsh_tags(mut self, tags: &GmshTags) -> MeshError {
        use MeshError as E;
        let (nodes, elements, slot): (Vec<usize>, Vec<usize>, &mut GmshRefs) = match &mut self {
            E::DegenerateTriangle {
                element,
                nodes,
                gmsh,
                ..
            } => (nodes.to_vec(), vec![*element], gmsh),
            E::DuplicateNodes { a, b, gmsh, .. }
            | E::EdgeNotInMesh { a, b, gmsh, .. }
            | E::InterfaceSameEdge { a, b, gmsh, .. } => (vec![*a, *b], vec![], gmsh),
            E::OrphanNode { node, gmsh, .. } | E::NonFiniteCoordinate { node, gmsh, .. } => {
                (vec![*node], vec![], gmsh)
            }
            E::InterfaceNotFacing {
                bottom,
                nearest,
                gmsh,
                ..
            } => (vec![*bottom, *nearest], vec![], gmsh),
            E::InterfaceMidNotFacing {
                bottom, top, gmsh, ..
            } => (vec![*bottom, *top], vec![], gmsh),
            E::InconsistentMidNode {
                element,
                a,
                b,
                mid,
                gmsh,
                ..
            } => (vec![*mid, *a, *b], vec![*element], gmsh),
            E::InvertedCurvedTriangle {
                element,
                node,
                gmsh,
                ..
            } => (vec![*node], vec![*element], gmsh),
            E::InterfaceEdgeMissing {
                a, b, c, d, gmsh, ..
            } => (vec![*a, *b, *c, *d], vec![], gmsh),
            _ => return self,
        };
        *slot = GmshRefs::of(tags, &nodes, &elements);
        self
    }
}
