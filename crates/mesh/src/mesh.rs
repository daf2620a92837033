//! The triangle mesh: nodes, triangles, regions, edge sets, node sets, interfaces.

use std::collections::BTreeMap;

use crate::checks::{IdMap, check_duplicates, find_bodies, longest_edge_sq, unknown};
use crate::error::MeshError;
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
}

impl std::fmt::Display for MeshNotice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MeshNotice::ReorientedTriangles { count } => write!(
                f,
                "{count} clockwise triangle(s) were renumbered counter-clockwise"
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
            .ok_or_else(|| MeshError::UnknownName {
                kind: "region",
                name: name.into(),
                available: self.region_names.join(", "),
            })
    }

    /// Triangles of the region called `name`.
    pub fn region_elements(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        let r = self.region_index(name)?;
        Ok((0..self.triangles.len())
            .filter(|&e| self.element_region[e] == r)
            .collect())
    }

    /// Notices produced when the mesh was built.
    pub fn notices(&self) -> &[MeshNotice] {
        &self.notices
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
            .ok_or_else(|| unknown("edge set", name, self.edge_sets.keys()))
    }

    /// The node set called `name`.
    pub fn node_set(&self, name: &str) -> Result<&[usize], MeshError> {
        self.node_sets
            .get(name)
            .map(|v| v.as_slice())
            .ok_or_else(|| unknown("node set", name, self.node_sets.keys()))
    }

    /// The interface called `name`.
    pub fn interface(&self, name: &str) -> Result<&Interface, MeshError> {
        self.interfaces
            .get(name)
            .ok_or_else(|| unknown("interface", name, self.interfaces.keys()))
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
                    return Err(MeshError::EdgeNotInMesh {
                        set: name.into(),
                        a,
                        b,
                    });
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
