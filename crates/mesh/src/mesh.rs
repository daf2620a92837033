//! The triangle mesh: nodes, triangles, regions, edge sets, node sets, interfaces.

use std::collections::{BTreeMap, HashMap};

use crate::error::MeshError;

/// A 2D point `[x, y]`.
pub type Point = [f64; 2];

/// A named interface: ordered 4-node elements joining two bodies.
///
/// Node order of each element (DESIGN.md §2): 1, 2 on the bottom face, 3, 4 on
/// the top face, 4 facing 1 and 3 facing 2. The bottom face is ordered so that
/// the top body lies on the left of 1→2: the left normal of 1→2 points from
/// the bottom body into the top body.
#[derive(Debug, Clone, PartialEq)]
pub struct Interface {
    /// Edge set of the bottom face.
    pub bottom_set: String,
    /// Edge set of the top face.
    pub top_set: String,
    /// Elements `[n1, n2, n3, n4]`.
    pub elements: Vec<[usize; 4]>,
}

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

/// A 2D mesh of linear triangles with named sets.
///
/// Build it with [`Mesh::new`], which validates and normalises the input.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    nodes: Vec<Point>,
    triangles: Vec<[usize; 3]>,
    element_region: Vec<usize>,
    region_names: Vec<String>,
    edge_sets: BTreeMap<String, Vec<[usize; 2]>>,
    node_sets: BTreeMap<String, Vec<usize>>,
    interfaces: BTreeMap<String, Interface>,
    node_body: Vec<usize>,
    bodies: Vec<Body>,
    notices: Vec<MeshNotice>,
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

    /// Triangles (counter-clockwise node ids).
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
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

    /// The nodes of an edge set, ascending and unique.
    pub fn edge_set_nodes(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        let mut v: Vec<usize> = self.edge_set(name)?.iter().flatten().copied().collect();
        v.sort_unstable();
        v.dedup();
        Ok(v)
    }

    /// Declares an interface between two edge sets and pairs their nodes by geometry.
    ///
    /// Each bottom edge becomes one 4-node element (see [`Interface`]); its
    /// nodes must face nodes of the top set within `tolerance` (absolute
    /// distance; `None` takes 1e-6 of the shortest bottom edge), and the facing
    /// nodes must form an edge of the top set in another body.
    pub fn add_interface(
        &mut self,
        name: &str,
        bottom_set: &str,
        top_set: &str,
        tolerance: Option<f64>,
    ) -> Result<(), MeshError> {
        let bottom = self.edge_set(bottom_set)?.to_vec();
        let top = self.edge_set(top_set)?.to_vec();
        let min_len = bottom
            .iter()
            .map(|&[a, b]| dist(self.nodes[a], self.nodes[b]))
            .fold(f64::INFINITY, f64::min);
        let tol = tolerance.unwrap_or(1e-6 * if min_len.is_finite() { min_len } else { 1.0 });
        let mut top_nodes: Vec<usize> = top.iter().flatten().copied().collect();
        top_nodes.sort_unstable();
        top_nodes.dedup();
        let grid = PointGrid::new(&self.nodes, &top_nodes, tol);
        let top_edges: HashMap<(usize, usize), ()> = top
            .iter()
            .flat_map(|&[a, b]| [((a, b), ()), ((b, a), ())])
            .collect();
        let mut elements = Vec::with_capacity(bottom.len());
        for &[a, b] in &bottom {
            // The bottom body is on the left of a→b (edge sets are stored
            // counter-clockwise); the top body must be on the left of 1→2.
            let (n1, n2) = (b, a);
            let facing = |v: usize| {
                grid.nearest(&self.nodes, self.nodes[v], tol)
                    .ok_or_else(|| MeshError::InterfaceNotFacing {
                        interface: name.into(),
                        bottom_set: bottom_set.into(),
                        top_set: top_set.into(),
                        bottom: v,
                        x: self.nodes[v][0],
                        y: self.nodes[v][1],
                        tolerance: tol,
                    })
            };
            let n4 = facing(n1)?;
            let n3 = facing(n2)?;
            if !top_edges.contains_key(&(n3, n4)) {
                return Err(MeshError::InterfaceEdgeMissing {
                    interface: name.into(),
                    top_set: top_set.into(),
                    a,
                    b,
                    c: n3,
                    d: n4,
                });
            }
            if n1 == n4 && n2 == n3 {
                return Err(MeshError::InterfaceSameEdge {
                    interface: name.into(),
                    a,
                    b,
                });
            }
            elements.push([n1, n2, n3, n4]);
        }
        self.interfaces.insert(
            name.into(),
            Interface {
                bottom_set: bottom_set.into(),
                top_set: top_set.into(),
                elements,
            },
        );
        Ok(())
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

    /// Area of each triangle.
    pub fn areas(&self) -> Vec<f64> {
        self.triangles
            .iter()
            .map(|t| signed_area(self.nodes[t[0]], self.nodes[t[1]], self.nodes[t[2]]))
            .collect()
    }

    /// Node → triangles adjacency in CSR form.
    fn node_triangles(&self) -> (Vec<usize>, Vec<usize>) {
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
    fn has_directed_edge(&self, adj: &(Vec<usize>, Vec<usize>), a: usize, b: usize) -> bool {
        adj.1[adj.0[a]..adj.0[a + 1]].iter().any(|&e| {
            let t = self.triangles[e];
            (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b)
        })
    }

    fn directed_edges(&self) -> HashMap<(usize, usize), usize> {
        let mut map = HashMap::with_capacity(3 * self.triangles.len());
        for (e, t) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                map.insert((t[k], t[(k + 1) % 3]), e);
            }
        }
        map
    }
}

fn unknown<'a>(
    kind: &'static str,
    name: &str,
    keys: impl Iterator<Item = &'a String>,
) -> MeshError {
    let available: Vec<&str> = keys.map(|s| s.as_str()).collect();
    MeshError::UnknownName {
        kind,
        name: name.into(),
        available: if available.is_empty() {
            "none".into()
        } else {
            available.join(", ")
        },
    }
}

fn dist(a: Point, b: Point) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

fn longest_edge_sq(a: Point, b: Point, c: Point) -> f64 {
    let d = |p: Point, q: Point| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    d(a, b).max(d(b, c)).max(d(c, a))
}

fn find_bodies(
    n: usize,
    triangles: &[[usize; 3]],
    element_region: &[usize],
    region_names: &[String],
) -> (Vec<usize>, Vec<Body>) {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for t in triangles {
        for &v in &t[1..] {
            let (ra, rb) = (root(&mut parent, t[0]), root(&mut parent, v));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // Bodies numbered in order of their smallest node.
    let mut body_of_root = HashMap::new();
    let mut node_body = vec![0; n];
    for (i, nb) in node_body.iter_mut().enumerate() {
        let r = root(&mut parent, i);
        let next = body_of_root.len();
        *nb = *body_of_root.entry(r).or_insert(next);
    }
    let nb = body_of_root.len();
    let mut elements = vec![Vec::new(); nb];
    let mut nodes = vec![Vec::new(); nb];
    let mut regions = vec![Vec::<usize>::new(); nb];
    for (e, t) in triangles.iter().enumerate() {
        let b = node_body[t[0]];
        elements[b].push(e);
        if !regions[b].contains(&element_region[e]) {
            regions[b].push(element_region[e]);
        }
    }
    for (i, &b) in node_body.iter().enumerate() {
        nodes[b].push(i);
    }
    let bodies = (0..nb)
        .map(|b| {
            let mut r = regions[b].clone();
            r.sort_unstable();
            Body {
                name: r
                    .iter()
                    .map(|&k| region_names[k].as_str())
                    .collect::<Vec<_>>()
                    .join("+"),
                elements: std::mem::take(&mut elements[b]),
                nodes: std::mem::take(&mut nodes[b]),
            }
        })
        .collect();
    (node_body, bodies)
}

/// Coincident nodes are an error when both are used by triangles of one
/// region (an unmerged mesh); across regions they are allowed, as on an
/// interface or at the tip of an interface crack.
fn check_duplicates(
    nodes: &[Point],
    triangles: &[[usize; 3]],
    element_region: &[usize],
    region_names: &[String],
) -> Result<(), MeshError> {
    if nodes.is_empty() {
        return Ok(());
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    let tol = COINCIDENCE_TOLERANCE * size;
    let all: Vec<usize> = (0..nodes.len()).collect();
    let grid = PointGrid::new(nodes, &all, tol);
    let mut pairs = Vec::new();
    for (i, p) in nodes.iter().enumerate() {
        for j in grid.within(nodes, *p, tol) {
            if j > i {
                pairs.push((i, j));
            }
        }
    }
    if pairs.is_empty() {
        return Ok(());
    }
    let mut regions_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for &(i, j) in &pairs {
        regions_of.entry(i).or_default();
        regions_of.entry(j).or_default();
    }
    for (e, t) in triangles.iter().enumerate() {
        for v in t {
            if let Some(r) = regions_of.get_mut(v)
                && !r.contains(&element_region[e])
            {
                r.push(element_region[e]);
            }
        }
    }
    for (i, j) in pairs {
        if let Some(&r) = regions_of[&i].iter().find(|r| regions_of[&j].contains(r)) {
            return Err(MeshError::DuplicateNodes {
                a: i,
                b: j,
                x: nodes[i][0],
                y: nodes[i][1],
                region: region_names[r].clone(),
            });
        }
    }
    Ok(())
}

/// A uniform hash grid over a subset of nodes, for near-point queries.
struct PointGrid {
    cell: f64,
    map: HashMap<(i64, i64), Vec<usize>>,
}

impl PointGrid {
    fn new(nodes: &[Point], subset: &[usize], tol: f64) -> Self {
        let cell = (4.0 * tol).max(f64::MIN_POSITIVE);
        let mut map: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for &i in subset {
            map.entry(Self::key(nodes[i], cell)).or_default().push(i);
        }
        PointGrid { cell, map }
    }

    fn key(p: Point, cell: f64) -> (i64, i64) {
        ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64)
    }

    fn within(&self, nodes: &[Point], p: Point, tol: f64) -> Vec<usize> {
        let (kx, ky) = Self::key(p, self.cell);
        let mut out = Vec::new();
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(v) = self.map.get(&(kx + dx, ky + dy)) {
                    out.extend(v.iter().copied().filter(|&j| dist(nodes[j], p) <= tol));
                }
            }
        }
        out
    }

    fn nearest(&self, nodes: &[Point], p: Point, tol: f64) -> Option<usize> {
        self.within(nodes, p, tol).into_iter().min_by(|&a, &b| {
            dist(nodes[a], p)
                .total_cmp(&dist(nodes[b], p))
                .then(a.cmp(&b))
        })
    }
}
