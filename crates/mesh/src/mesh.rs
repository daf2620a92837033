//! The triangle mesh: nodes, triangles, regions, edge sets, node sets, interfaces.

use std::collections::BTreeMap;

use crate::checks::{IdMap, check_duplicates, find_bodies, longest_edge_sq, unknown};
use crate::error::{GmshRefs, GmshTags, MeshError};
pub use crate::interface::Interface;

/// A 2D point `[x, y]`.
pub type Point = [f64; 2];

/// A connected body: the triangles reachable from each other through shared nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Name: the names of the regions it contains, joined by `+`.
    pub name: String,
    /// Its triangles.
    pub elements: Vec<usize>,
    /// Its nodes, ascending.
    pub nodes: Vec<usize>,
}

/// Something the mesh constructor changed or noticed and the user should hear about.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshNotice {
    /// Clockwise triangles were renumbered counter-clockwise.
    ReorientedTriangles {
        /// How many.
        count: usize,
    },
    /// A physical point of a Gmsh file on a node that no triangle uses: left
    /// out of the node set named after its group.
    PointOffMesh {
        /// The physical point's name.
        group: String,
        /// Gmsh tag of its node.
        node_tag: u64,
        /// x coordinate.
        x: f64,
        /// y coordinate.
        y: f64,
    },
    /// A Gmsh mesh so large in metres that it is probably in millimetres.
    LooksLikeMillimetres {
        /// The largest extent of its bounding box.
        size: f64,
    },
    /// Two bodies whose boundaries have coincident nodes that no interface
    /// joins (see [`Mesh::unjoined_touching_bodies`]).
    UnjoinedTouchingBodies {
        /// The first body's name (its regions joined by `+`).
        first: String,
        /// The second body's name.
        second: String,
        /// How many pairs of coincident nodes no interface joins.
        pairs: usize,
        /// One such pair, as "node 3 and node 40 at (1, 0.5)".
        example: String,
    },
}

impl MeshNotice {
    /// Whether the notice is a warning (something may be wrong with the
    /// model) rather than a note on what the constructor did.
    pub fn is_warning(&self) -> bool {
        !matches!(self, MeshNotice::ReorientedTriangles { .. })
    }
}

impl std::fmt::Display for MeshNotice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MeshNotice::ReorientedTriangles { count } => write!(
                f,
                "{count} clockwise triangle(s) were renumbered counter-clockwise"
            ),
            MeshNotice::PointOffMesh {
                group,
                node_tag,
                x,
                y,
            } => write!(
                f,
                "physical point '{group}': its node (Gmsh node tag {node_tag}) at ({x}, {y}) is no node of a triangle, so node set '{group}' leaves it out (embed the point in its surface before meshing: Gmsh `Point{{..}} In Surface{{..}};` or gmsh.model.mesh.embed)"
            ),
            MeshNotice::LooksLikeMillimetres { size } => write!(
                f,
                "the mesh is {size} across: does it use millimetres? Tecon takes every length in metres, like the SI material data (Pa, W/(m K), ...), so a mesh in millimetres gives results off by factors of 1000 without any error. To convert it, set Gmsh's option Mesh.ScalingFactor = 0.001 before saving the mesh (gmsh.option.setNumber(\"Mesh.ScalingFactor\", 0.001) in Python; -setnumber Mesh.ScalingFactor 0.001 on the command line) or scale the CAD model; ignore this if the structure really is that large"
            ),
            MeshNotice::UnjoinedTouchingBodies {
                first,
                second,
                pairs,
                example,
            } => write!(
                f,
                "bodies '{first}' and '{second}' touch at {pairs} pair(s) of coincident nodes (e.g. {example}) that no interface joins: they are separate bodies and no force or heat passes between them. If they should act together, declare an [[interface]] between their two faces (bottom and top edge sets) or merge the nodes in the mesh; if they are meant to be apart, ignore this"
            ),
        }
    }
}

/// A 2D mesh of linear (P1, 3-node) or quadratic (P2, 6-node) triangles
/// with named sets.
///
/// Build a P1 mesh with [`Mesh::new`], which validates and normalises the
/// input; a P2 mesh with [`Mesh::new_quadratic`] or [`Mesh::to_quadratic`].
/// [`Mesh::triangles`] always returns the corner nodes, so P1 code runs on
/// the corners of any mesh; [`Mesh::triangles6`] gives the 6-node triangles.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub(crate) nodes: Vec<Point>,
    pub(crate) triangles: Vec<[usize; 3]>,
    /// P2 only: corners 0, 1, 2, then the mid nodes of (0,1), (1,2), (2,0).
    pub(crate) triangles6: Option<Vec<[usize; 6]>>,
    /// P2 only: mid node of each edge, keyed by its sorted corner pair.
    pub(crate) edge_mid: IdMap<(usize, usize), usize>,
    pub(crate) element_region: Vec<usize>,
    pub(crate) region_names: Vec<String>,
    pub(crate) edge_sets: BTreeMap<String, Vec<[usize; 2]>>,
    pub(crate) node_sets: BTreeMap<String, Vec<usize>>,
    pub(crate) interfaces: BTreeMap<String, Interface>,
    pub(crate) node_body: Vec<usize>,
    pub(crate) bodies: Vec<Body>,
    pub(crate) notices: Vec<MeshNotice>,
    /// A mesh read from a Gmsh file: its node and element tags.
    pub(crate) gmsh: Option<Box<GmshTags>>,
}

/// Relative tolerance (to the mesh's bounding-box size) for coincident nodes.
pub const COINCIDENCE_TOLERANCE: f64 = 1e-9;

/// Signed area of a triangle (positive when counter-clockwise).
#[inline]
pub fn signed_area(a: Point, b: Point, c: Point) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
}

impl Mesh {
    /// Validates and builds a mesh.
    ///
    /// * `regions`: one region index per triangle, into `region_names`.
    /// * Clockwise triangles are renumbered counter-clockwise and a
    ///   [`MeshNotice`] says how many.
    /// * Errors: a non-finite coordinate, a node id out of range, a zero-area
    ///   triangle (relative to the element's size), a node used by no triangle,
    ///   two coincident nodes within one body.
    pub fn new(
        nodes: Vec<Point>,
        mut triangles: Vec<[usize; 3]>,
        element_region: Vec<usize>,
        region_names: Vec<String>,
    ) -> Result<Mesh, MeshError> {
        let n = nodes.len();
        for (i, p) in nodes.iter().enumerate() {
            if !p[0].is_finite() || !p[1].is_finite() {
                return Err(MeshError::NonFiniteCoordinate {
                    node: i,
                    x: p[0],
                    y: p[1],
                    gmsh: GmshRefs::NONE,
                });
            }
        }
        if element_region.len() != triangles.len() {
            return Err(MeshError::InvalidParameter {
                name: "element_region",
                value: element_region.len().to_string(),
                reason: format!("needs one region per triangle ({})", triangles.len()),
            });
        }
        for (e, &r) in element_region.iter().enumerate() {
            if r >= region_names.len() {
                return Err(MeshError::InvalidParameter {
                    name: "element_region",
                    value: r.to_string(),
                    reason: format!(
                        "triangle {e} names region {r}, but there are {} regions",
                        region_names.len()
                    ),
                });
            }
        }
        let mut flipped = 0;
        for (e, t) in triangles.iter_mut().enumerate() {
            for &v in t.iter() {
                if v >= n {
                    return Err(MeshError::NodeOutOfRange {
                        what: "triangle".into(),
                        element: e,
                        node: v,
                        n_nodes: n,
                    });
                }
            }
            let (a, b, c) = (nodes[t[0]], nodes[t[1]], nodes[t[2]]);
            let area = signed_area(a, b, c);
            let scale = longest_edge_sq(a, b, c);
            if area.abs() <= 1e-12 * scale || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(MeshError::DegenerateTriangle {
                    element: e,
                    area,
                    nodes: *t,
                    gmsh: GmshRefs::NONE,
                });
            }
            if area < 0.0 {
                t.swap(1, 2);
                flipped += 1;
            }
        }
        let mut used = vec![false; n];
        for t in &triangles {
            for &v in t {
                used[v] = true;
            }
        }
        if let Some(i) = used.iter().position(|u| !u) {
            return Err(MeshError::OrphanNode {
                node: i,
                x: nodes[i][0],
                y: nodes[i][1],
                gmsh: GmshRefs::NONE,
            });
        }
        let (node_body, bodies) = find_bodies(n, &triangles, &element_region, &region_names);
        check_duplicates(&nodes, &triangles, &element_region, &region_names)?;
        let mut notices = Vec::new();
        if flipped > 0 {
            notices.push(MeshNotice::ReorientedTriangles { count: flipped });
        }
        Ok(Mesh {
            nodes,
            triangles,
            triangles6: None,
            edge_mid: IdMap::default(),
            element_region,
            region_names,
            edge_sets: BTreeMap::new(),
            node_sets: BTreeMap::new(),
            interfaces: BTreeMap::new(),
            node_body,
            bodies,
            notices,
            gmsh: None,
        })
    }

    /// Node coordinates.
    pub fn nodes(&self) -> &[Point] {
        &self.nodes
    }

    /// Triangles by their corner nodes (counter-clockwise), for either order.
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// Element order: 1 (3-node triangles) or 2 (6-node triangles).
    pub fn order(&self) -> usize {
        if self.triangles6.is_some() { 2 } else { 1 }
    }

    /// The 6-node triangles of a P2 mesh (`None` for P1): corners 0, 1, 2
    /// counter-clockwise, then the mid nodes of edges (0,1), (1,2), (2,0)
    /// (the order of VTK_QUADRATIC_TRIANGLE and Gmsh type 9).
    pub fn triangles6(&self) -> Option<&[[usize; 6]]> {
        self.triangles6.as_deref()
    }

    /// The mid node of the edge a–b (either orientation) of a P2 mesh;
    /// `None` for a P1 mesh or when a–b is not an edge.
    pub fn edge_mid_node(&self, a: usize, b: usize) -> Option<usize> {
        self.edge_mid.get(&(a.min(b), a.max(b))).copied()
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Number of triangles.
    pub fn n_triangles(&self) -> usize {
        self.triangles.len()
    }

    /// Region index of each triangle.
    pub fn element_regions(&self) -> &[usize] {
        &self.element_region
    }

    /// Region names, indexed by region index.
    pub fn region_names(&self) -> &[String] {
        &self.region_names
    }

    /// Index of the region called `name`.
    pub fn region_index(&self, name: &str) -> Result<usize, MeshError> {
        self.region_names
            .iter()
            .position(|r| r == name)
            .ok_or_else(|| self.missing("region", name, self.region_names.iter()))
    }

    /// Triangles of the region called `name`.
    pub fn region_elements(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        let r = self.region_index(name)?;
        Ok((0..self.triangles.len())
            .filter(|&e| self.element_region[e] == r)
            .collect())
    }

    /// The Gmsh tags of a mesh read from a .msh file (`None` for a
    /// generated mesh).
    pub fn gmsh_tags(&self) -> Option<&GmshTags> {
        self.gmsh.as_deref()
    }

    /// "node 17", or "node 17 (Gmsh node tag 1234)" on a mesh read from a
    /// Gmsh file: how messages name a node so that the user finds it.
    pub fn node_label(&self, i: usize) -> String {
        match self.gmsh.as_ref().and_then(|g| g.node(i)) {
            Some(t) => format!("node {i} (Gmsh node tag {t})"),
            None => format!("node {i}"),
        }
    }

    /// "triangle 5", or "triangle 5 (Gmsh element tag 901)" on a mesh read
    /// from a Gmsh file.
    pub fn triangle_label(&self, e: usize) -> String {
        match self.gmsh.as_ref().and_then(|g| g.element(e)) {
            Some(t) => format!("triangle {e} (Gmsh element tag {t})"),
            None => format!("triangle {e}"),
        }
    }

    /// The error naming its nodes and triangles also by their Gmsh tags
    /// (on a mesh read from a Gmsh file; otherwise unchanged).
    pub(crate) fn tagged(&self, e: MeshError) -> MeshError {
        match &self.gmsh {
            Some(g) => e.with_gmsh_tags(g),
            None => e,
        }
    }

    /// The error for a name that is not there: an empty physical group of
    /// the Gmsh file says so, any other name lists the names that exist.
    fn missing<'a>(
        &self,
        kind: &'static str,
        name: &str,
        keys: impl Iterator<Item = &'a String>,
    ) -> MeshError {
        let e = unknown(kind, name, keys);
        let empty = self
            .gmsh
            .as_ref()
            .and_then(|g| g.empty_groups.iter().find(|(_, n)| n == name));
        match (empty, e) {
            (Some((dim, _)), MeshError::UnknownName { available, .. }) => MeshError::EmptyGroup {
                kind,
                name: name.into(),
                dim: *dim,
                available,
            },
            (_, e) => e,
        }
    }

    /// Notices produced when the mesh was built (and, for a Gmsh file,
    /// when it was read: physical points off the mesh, a size that looks
    /// like millimetres).
    pub fn notices(&self) -> &[MeshNotice] {
        &self.notices
    }

    /// The warnings a run should print once its interfaces are declared: the
    /// notices that are warnings ([`MeshNotice::is_warning`]) and the bodies
    /// that touch without an interface ([`Mesh::unjoined_touching_bodies`]).
    pub fn warnings(&self) -> Vec<MeshNotice> {
        let mut out: Vec<MeshNotice> = self
            .notices
            .iter()
            .filter(|n| n.is_warning())
            .cloned()
            .collect();
        out.extend(self.unjoined_touching_bodies());
        out
    }

    /// The connected bodies.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Body index of each node.
    pub fn node_bodies(&self) -> &[usize] {
        &self.node_body
    }

    /// All edge sets.
    pub fn edge_sets(&self) -> &BTreeMap<String, Vec<[usize; 2]>> {
        &self.edge_sets
    }

    /// All node sets.
    pub fn node_sets(&self) -> &BTreeMap<String, Vec<usize>> {
        &self.node_sets
    }

    /// All interfaces.
    pub fn interfaces(&self) -> &BTreeMap<String, Interface> {
        &self.interfaces
    }

    /// The edge set called `name`.
    pub fn edge_set(&self, name: &str) -> Result<&[[usize; 2]], MeshError> {
        self.edge_sets
            .get(name)
            .map(|v| v.as_slice())
            .ok_or_else(|| self.missing("edge set", name, self.edge_sets.keys()))
    }

    /// The node set called `name`.
    pub fn node_set(&self, name: &str) -> Result<&[usize], MeshError> {
        self.node_sets
            .get(name)
            .map(|v| v.as_slice())
            .ok_or_else(|| self.missing("node set", name, self.node_sets.keys()))
    }

    /// The interface called `name`.
    pub fn interface(&self, name: &str) -> Result<&Interface, MeshError> {
        self.interfaces
            .get(name)
            .ok_or_else(|| self.missing("interface", name, self.interfaces.keys()))
    }

    /// Adds (or replaces) an edge set.
    ///
    /// Every edge must be an edge of a triangle. Boundary edges are oriented
    /// like their triangle (counter-clockwise), so the body lies on the left
    /// and the right normal points outward.
    pub fn add_edge_set(&mut self, name: &str, edges: Vec<[usize; 2]>) -> Result<(), MeshError> {
        let adj = self.node_triangles();
        let mut out = Vec::with_capacity(edges.len());
        for (k, [a, b]) in edges.into_iter().enumerate() {
            for v in [a, b] {
                if v >= self.nodes.len() {
                    return Err(MeshError::NodeOutOfRange {
                        what: format!("edge set '{name}' edge"),
                        element: k,
                        node: v,
                        n_nodes: self.nodes.len(),
                    });
                }
            }
            match (
                self.has_directed_edge(&adj, a, b),
                self.has_directed_edge(&adj, b, a),
            ) {
                (true, false) => out.push([a, b]),
                (false, true) => out.push([b, a]),
                // An interior edge (both directions exist): keep as given.
                (true, true) => out.push([a, b]),
                (false, false) => {
                    return Err(self.tagged(MeshError::EdgeNotInMesh {
                        set: name.into(),
                        a,
                        b,
                        gmsh: GmshRefs::NONE,
                    }));
                }
            }
        }
        self.edge_sets.insert(name.into(), out);
        Ok(())
    }

    /// Adds (or replaces) a node set.
    pub fn add_node_set(&mut self, name: &str, mut nodes: Vec<usize>) -> Result<(), MeshError> {
        for (k, &v) in nodes.iter().enumerate() {
            if v >= self.nodes.len() {
                return Err(MeshError::NodeOutOfRange {
                    what: format!("node set '{name}' entry"),
                    element: k,
                    node: v,
                    n_nodes: self.nodes.len(),
                });
            }
        }
        nodes.sort_unstable();
        nodes.dedup();
        self.node_sets.insert(name.into(), nodes);
        Ok(())
    }

    /// The nodes of an edge set (with their mid nodes on a P2 mesh),
    /// ascending and unique.
    pub fn edge_set_nodes(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        let edges = self.edge_set(name)?;
        let mut v: Vec<usize> = edges.iter().flatten().copied().collect();
        v.extend(edges.iter().filter_map(|&[a, b]| self.edge_mid_node(a, b)));
        v.sort_unstable();
        v.dedup();
        Ok(v)
    }

    /// Boundary edges (edges of exactly one triangle), counter-clockwise.
    pub fn boundary_edges(&self) -> Vec<[usize; 2]> {
        let map = self.directed_edges();
        let mut out: Vec<[usize; 2]> = map
            .keys()
            .filter(|&&(a, b)| !map.contains_key(&(b, a)))
            .map(|&(a, b)| [a, b])
            .collect();
        out.sort_unstable();
        out
    }

    /// Area of each triangle; on a P2 mesh the area of the curved
    /// (isoparametric) triangle, integrated exactly.
    pub fn areas(&self) -> Vec<f64> {
        match &self.triangles6 {
            None => self
                .triangles
                .iter()
                .map(|t| signed_area(self.nodes[t[0]], self.nodes[t[1]], self.nodes[t[2]]))
                .collect(),
            Some(t6) => t6
                .iter()
                .map(|t| crate::quadratic::p2_area(&t.map(|v| self.nodes[v])))
                .collect(),
        }
    }

    /// Node → triangles adjacency in CSR form.
    pub(crate) fn node_triangles(&self) -> (Vec<usize>, Vec<usize>) {
        let mut start = vec![0usize; self.nodes.len() + 1];
        for t in &self.triangles {
            for &v in t {
                start[v + 1] += 1;
            }
        }
        for i in 0..self.nodes.len() {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut list = vec![0usize; start[self.nodes.len()]];
        for (e, t) in self.triangles.iter().enumerate() {
            for &v in t {
                list[fill[v]] = e;
                fill[v] += 1;
            }
        }
        (start, list)
    }

    /// Whether some triangle runs a→b in its counter-clockwise order.
    pub(crate) fn has_directed_edge(
        &self,
        adj: &(Vec<usize>, Vec<usize>),
        a: usize,
        b: usize,
    ) -> bool {
        adj.1[adj.0[a]..adj.0[a + 1]].iter().any(|&e| {
            let t = self.triangles[e];
            (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b)
        })
    }

    pub(crate) fn directed_edges(&self) -> IdMap<(usize, usize), usize> {
        let mut map = IdMap::default();
        map.reserve(3 * self.triangles.len());
        for (e, t) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                map.insert((t[k], t[(k + 1) % 3]), e);
            }
        }
        map
    }
}
