//! Quadratic (P2) meshes: 6-node triangles with curved edges on circular arcs.
//!
//! ```text
//!        2
//!        | \         node order (VTK_QUADRATIC_TRIANGLE, Gmsh type 9):
//!        5   4       corners 0, 1, 2 counter-clockwise,
//!        |     \     then the mid nodes of (0,1), (1,2), (2,0)
//!        0 - 3 - 1
//! ```
//!
//! A P1 mesh is promoted by [`Mesh::to_quadratic`]; a P2 mesh read from a
//! file is built by [`Mesh::new_quadratic`].

use crate::checks::{IdMap, check_duplicates, dist, find_bodies, longest_edge_sq};
use crate::error::MeshError;
use crate::mesh::{Interface, Mesh, MeshNotice, Point, signed_area};

/// A circle on which mid nodes of curved edges are placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    /// Centre.
    pub centre: Point,
    /// Radius (> 0).
    pub radius: f64,
}

/// Relative tolerance (to the radius) for a node to lie on an [`Arc`].
pub const ARC_TOLERANCE: f64 = 1e-6;

impl Arc {
    /// Whether `p` lies on the circle within [`ARC_TOLERANCE`] × radius.
    pub fn contains(&self, p: Point) -> bool {
        (dist(p, self.centre) - self.radius).abs() <= ARC_TOLERANCE * self.radius
    }

    /// The point of the circle on the bisector of the chord a–b, on the side
    /// of the chord's midpoint (the mid point of the shorter arc).
    pub fn midpoint(&self, a: Point, b: Point) -> Point {
        let m = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let d = [m[0] - self.centre[0], m[1] - self.centre[1]];
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        [
            self.centre[0] + self.radius * d[0] / l,
            self.centre[1] + self.radius * d[1] / l,
        ]
    }
}

/// The point at the mean radius and mean angle of a and b about `c` (the
/// angle difference taken in (−π, π]).
fn polar_midpoint(c: Point, a: Point, b: Point) -> Point {
    let (ax, ay, bx, by) = (a[0] - c[0], a[1] - c[1], b[0] - c[0], b[1] - c[1]);
    let (ra, rb) = (ax.hypot(ay), bx.hypot(by));
    if (ra - rb).abs() <= 1e-14 * ra.max(rb) {
        // on one circle: the arc midpoint, exactly symmetric in a and b
        return Arc {
            centre: c,
            radius: 0.5 * (ra + rb),
        }
        .midpoint(a, b);
    }
    let ta = ay.atan2(ax);
    let mut dt = by.atan2(bx) - ta;
    if dt > std::f64::consts::PI {
        dt -= 2.0 * std::f64::consts::PI;
    } else if dt <= -std::f64::consts::PI {
        dt += 2.0 * std::f64::consts::PI;
    }
    if dt == 0.0 {
        return [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    }
    let (r, t) = (0.5 * (ra + rb), ta + 0.5 * dt);
    [c[0] + r * t.cos(), c[1] + r * t.sin()]
}

/// Quadratic shape-function derivatives (∂N/∂ξ, ∂N/∂η) at (ξ, η) of the
/// reference triangle (0,0), (1,0), (0,1), in the node order above.
pub fn p2_shape_derivatives(xi: f64, eta: f64) -> ([f64; 6], [f64; 6]) {
    let l1 = 1.0 - xi - eta;
    (
        [
            1.0 - 4.0 * l1,
            4.0 * xi - 1.0,
            0.0,
            4.0 * (l1 - xi),
            4.0 * eta,
            -4.0 * eta,
        ],
        [
            1.0 - 4.0 * l1,
            0.0,
            4.0 * eta - 1.0,
            -4.0 * xi,
            4.0 * xi,
            4.0 * (l1 - eta),
        ],
    )
}

/// det J of the isoparametric map of a 6-node triangle at (ξ, η).
pub fn p2_jacobian_det(x: &[Point; 6], xi: f64, eta: f64) -> f64 {
    let (dxi, deta) = p2_shape_derivatives(xi, eta);
    let mut j = [[0.0; 2]; 2];
    for k in 0..6 {
        for c in 0..2 {
            j[c][0] += dxi[k] * x[k][c];
            j[c][1] += deta[k] * x[k][c];
        }
    }
    j[0][0] * j[1][1] - j[0][1] * j[1][0]
}

/// Area of a 6-node (isoparametric) triangle: ∫ det J over the reference
/// triangle, exact with the mid-edge rule since det J is quadratic.
pub fn p2_area(x: &[Point; 6]) -> f64 {
    (p2_jacobian_det(x, 0.5, 0.0) + p2_jacobian_det(x, 0.5, 0.5) + p2_jacobian_det(x, 0.0, 0.5))
        / 6.0
}

/// Reference coordinates of the six nodes, where det J is checked.
const NODE_REF: [(f64, f64); 6] = [
    (0.0, 0.0),
    (1.0, 0.0),
    (0.0, 1.0),
    (0.5, 0.0),
    (0.5, 0.5),
    (0.0, 0.5),
];

/// The local edges of a triangle as (corner, corner, mid slot).
const EDGES: [(usize, usize, usize); 3] = [(0, 1, 3), (1, 2, 4), (2, 0, 5)];

impl Mesh {
    /// Validates and builds a P2 mesh from 6-node triangles (corners 0, 1, 2,
    /// then the mid nodes of (0,1), (1,2), (2,0)).
    ///
    /// Clockwise triangles are renumbered counter-clockwise (with their mid
    /// nodes) and a [`MeshNotice`] says how many. Errors, besides those of
    /// [`Mesh::new`]: an edge whose two triangles name different mid nodes,
    /// a node that is a mid node and a corner, or the mid node of two edges,
    /// and a curved triangle whose Jacobian is not positive at its nodes.
    pub fn new_quadratic(
        nodes: Vec<Point>,
        mut triangles6: Vec<[usize; 6]>,
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
                    gmsh: Default::default(),
                });
            }
        }
        if element_region.len() != triangles6.len() {
            return Err(MeshError::InvalidParameter {
                name: "element_region",
                value: element_region.len().to_string(),
                reason: format!("needs one region per triangle ({})", triangles6.len()),
            });
        }
        if let Some((e, &r)) = element_region
            .iter()
            .enumerate()
            .find(|&(_, &r)| r >= region_names.len())
        {
            return Err(MeshError::InvalidParameter {
                name: "element_region",
                value: r.to_string(),
                reason: format!(
                    "triangle {e} names region {r}, but there are {} regions",
                    region_names.len()
                ),
            });
        }
        let mut flipped = 0;
        for (e, t) in triangles6.iter_mut().enumerate() {
            if let Some(&v) = t.iter().find(|&&v| v >= n) {
                return Err(MeshError::NodeOutOfRange {
                    what: "triangle".into(),
                    element: e,
                    node: v,
                    n_nodes: n,
                });
            }
            let (a, b, c) = (nodes[t[0]], nodes[t[1]], nodes[t[2]]);
            let area = signed_area(a, b, c);
            let mut distinct = t.to_vec();
            distinct.sort_unstable();
            distinct.dedup();
            if area.abs() <= 1e-12 * longest_edge_sq(a, b, c) || distinct.len() != 6 {
                return Err(MeshError::DegenerateTriangle {
                    element: e,
                    area,
                    nodes: [t[0], t[1], t[2]],
                    gmsh: Default::default(),
                });
            }
            if area < 0.0 {
                *t = [t[0], t[2], t[1], t[5], t[4], t[3]];
                flipped += 1;
            }
            let x = t.map(|v| nodes[v]);
            let scale = signed_area(x[0], x[1], x[2]).abs();
            for (k, &(xi, eta)) in NODE_REF.iter().enumerate() {
                let det = p2_jacobian_det(&x, xi, eta);
                if det <= 1e-3 * scale {
                    return Err(MeshError::InvertedCurvedTriangle {
                        element: e,
                        node: t[k],
                        det_ratio: det / (2.0 * scale),
                        gmsh: Default::default(),
                    });
                }
            }
        }
        // Mid nodes: one per edge, shared by its triangles, never a corner.
        let mut edge_mid: IdMap<(usize, usize), usize> = IdMap::default();
        edge_mid.reserve(2 * triangles6.len());
        let mut mid_edge: Vec<(usize, usize)> = vec![(usize::MAX, usize::MAX); n];
        let mut is_corner = vec![false; n];
        for t in &triangles6 {
            for &v in &t[..3] {
                is_corner[v] = true;
            }
        }
        for (e, t) in triangles6.iter().enumerate() {
            for &(i, j, m) in &EDGES {
                let key = (t[i].min(t[j]), t[i].max(t[j]));
                let mid = t[m];
                let bad = |other: String| MeshError::InconsistentMidNode {
                    element: e,
                    a: key.0,
                    b: key.1,
                    mid,
                    reason: other,
                    gmsh: Default::default(),
                };
                if is_corner[mid] {
                    return Err(bad("it is also a corner node of a triangle".into()));
                }
                match edge_mid.insert(key, mid) {
                    Some(old) if old != mid => {
                        return Err(bad(format!(
                            "another triangle gives this edge the mid node {old}"
                        )));
                    }
                    _ => {}
                }
                let old = std::mem::replace(&mut mid_edge[mid], key);
                if old.0 != usize::MAX && old != key {
                    return Err(bad(format!(
                        "it is also the mid node of edge ({}, {})",
                        old.0, old.1
                    )));
                }
            }
        }
        let mut used = vec![false; n];
        for t in &triangles6 {
            for &v in t {
                used[v] = true;
            }
        }
        if let Some(i) = used.iter().position(|u| !u) {
            return Err(MeshError::OrphanNode {
                node: i,
                x: nodes[i][0],
                y: nodes[i][1],
                gmsh: Default::default(),
            });
        }
        let (node_body, bodies) = find_bodies(n, &triangles6, &element_region, &region_names);
        check_duplicates(&nodes, &triangles6, &element_region, &region_names)?;
        let mut notices = Vec::new();
        if flipped > 0 {
            notices.push(MeshNotice::ReorientedTriangles { count: flipped });
        }
        Ok(Mesh {
            nodes,
            triangles: triangles6.iter().map(|t| [t[0], t[1], t[2]]).collect(),
            triangles6: Some(triangles6),
            edge_mid,
            element_region,
            region_names,
            edge_sets: Default::default(),
            node_sets: Default::default(),
            interfaces: Default::default(),
            node_body,
            bodies,
            notices,
            gmsh: None,
        })
    }

    /// Promotes a P1 mesh to P2 (a P2 mesh is returned unchanged).
    ///
    /// Adds one mid node per edge, shared by its two triangles, numbered
    /// after the existing nodes in the order the edges are first met
    /// (triangle by triangle, local edges (0,1), (1,2), (2,0)), so corner ids
    /// are unchanged. An edge whose two ends lie on one of `arcs` and that
    /// bounds its body or separates two regions gets its mid node on the arc
    /// (the first such arc); every other edge gets the chord midpoint.
    ///
    /// Edge sets keep their corner pairs; a node set named like an edge set
    /// gains that edge set's mid nodes (other node sets are kept as they
    /// are); interfaces keep their elements and gain their facing mid nodes.
    pub fn to_quadratic(&self, arcs: &[Arc]) -> Result<Mesh, MeshError> {
        self.promote(arcs, None)
    }

    /// [`Mesh::to_quadratic`] of the structured polar generators: every mid
    /// node is the polar midpoint (mean radius, mean angle about `centre`) of
    /// its edge, so edges along a node row lie on their circle, radial edges
    /// stay straight and the diagonals follow the polar map (a straight
    /// diagonal would leave a thin curved cell when the sagitta of an
    /// interval exceeds the row's thickness).
    pub(crate) fn to_quadratic_polar(&self, centre: Point) -> Result<Mesh, MeshError> {
        self.promote(&[], Some(centre))
    }

    fn promote(&self, arcs: &[Arc], polar: Option<Point>) -> Result<Mesh, MeshError> {
        if self.order() == 2 {
            return Ok(self.clone());
        }
        for (k, a) in arcs.iter().enumerate() {
            if !(a.radius.is_finite()
                && a.radius > 0.0
                && a.centre[0].is_finite()
                && a.centre[1].is_finite())
            {
                return Err(MeshError::InvalidParameter {
                    name: "arc",
                    value: format!("{k}: centre {:?}, radius {}", a.centre, a.radius),
                    reason: "an arc needs a finite centre and a positive radius".into(),
                });
            }
        }
        // region adjacency only matters when there are arcs to match
        let directed = if arcs.is_empty() {
            Default::default()
        } else {
            self.directed_edges()
        };
        let curvable = |a: usize, b: usize| match (directed.get(&(a, b)), directed.get(&(b, a))) {
            (Some(_), None) | (None, Some(_)) => true,
            (Some(&e), Some(&f)) => self.element_region[e] != self.element_region[f],
            (None, None) => false,
        };
        let mut nodes = self.nodes.clone();
        let mut mids: IdMap<(usize, usize), usize> = IdMap::default();
        mids.reserve(2 * self.triangles.len());
        let mut tri6 = Vec::with_capacity(self.triangles.len());
        for t in &self.triangles {
            let mut t6 = [t[0], t[1], t[2], 0, 0, 0];
            for &(i, j, m) in &EDGES {
                let (a, b) = (t[i], t[j]);
                let key = (a.min(b), a.max(b));
                t6[m] = *mids.entry(key).or_insert_with(|| {
                    let (pa, pb) = (self.nodes[key.0], self.nodes[key.1]);
                    if let Some(c) = polar {
                        nodes.push(polar_midpoint(c, pa, pb));
                        return nodes.len() - 1;
                    }
                    let on_arc = arcs
                        .iter()
                        .find(|arc| arc.contains(pa) && arc.contains(pb) && curvable(a, b));
                    nodes.push(match on_arc {
                        Some(arc) => arc.midpoint(pa, pb),
                        None => [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])],
                    });
                    nodes.len() - 1
                });
            }
            tri6.push(t6);
        }
        let mut out = Mesh::new_quadratic(
            nodes,
            tri6,
            self.element_region.clone(),
            self.region_names.clone(),
        )?;
        out.notices = self.notices.clone();
        out.gmsh = self.gmsh.clone();
        out.edge_sets = self.edge_sets.clone();
        for (name, set) in &self.node_sets {
            let mut set = set.clone();
            if let Some(edges) = self.edge_sets.get(name) {
                set.extend(edges.iter().filter_map(|&[a, b]| out.edge_mid_node(a, b)));
                set.sort_unstable();
                set.dedup();
            }
            out.node_sets.insert(name.clone(), set);
        }
        for (name, itf) in &self.interfaces {
            let mut mid_nodes = Vec::with_capacity(itf.elements.len());
            for &[n1, n2, n3, n4] in &itf.elements {
                let (mb, mt) = (out.edge_mid[&(n1.min(n2), n1.max(n2))], {
                    out.edge_mid[&(n3.min(n4), n3.max(n4))]
                });
                let x = &out.nodes;
                // Facing corners coincide within the pairing tolerance; the
                // mid nodes, built the same way, must as well.
                let tol = dist(x[n1], x[n4]).max(dist(x[n2], x[n3])) + 1e-9 * dist(x[n1], x[n2]);
                let d = dist(x[mb], x[mt]);
                if d > tol {
                    return Err(MeshError::InterfaceMidNotFacing {
                        interface: name.clone(),
                        bottom: mb,
                        top: mt,
                        distance: d,
                        tolerance: tol,
                        gmsh: Default::default(),
                    });
                }
                mid_nodes.push([mb, mt]);
            }
            out.interfaces.insert(
                name.clone(),
                Interface {
                    mid_nodes,
                    ..itf.clone()
                },
            );
        }
        Ok(out)
    }
}
