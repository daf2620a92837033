//! Interfaces: pairing the facing nodes of two edge sets into 4-node (P1) or
//! 6-node (P2: 4 corners and two facing mid nodes) interface elements.

use std::collections::{BTreeMap, HashMap, HashSet};

use crate::checks::{PointGrid, dist};
use crate::error::{GmshRefs, MeshError};
use crate::mesh::{Mesh, MeshNotice};

/// A named interface: ordered interface elements joining two bodies.
///
/// Node order of each element: 1, 2 on the bottom face, 3, 4 on the top face,
/// 4 facing 1 and 3 facing 2. The bottom face is ordered so that the top body
/// lies on the left of 1→2: the left normal of 1→2 points from the bottom
/// body into the top body. On a P2 mesh each element also has two facing mid
/// nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Interface {
    /// Edge set of the bottom face.
    pub bottom_set: String,
    /// Edge set of the top face.
    pub top_set: String,
    /// Elements `[n1, n2, n3, n4]` (corner nodes).
    pub elements: Vec<[usize; 4]>,
    /// P2 only (empty for P1), one per element: `[mid of 1–2, mid of 4–3]`,
    /// the bottom and top mid nodes, facing each other.
    pub mid_nodes: Vec<[usize; 2]>,
}

/// Default relative pairing tolerance: facing nodes must coincide within
/// this fraction of the local element size (the shortest bottom-face edge
/// at the node). Gmsh places the nodes of two separately meshed arcs a few
/// 1e-9 m apart at lc = 5 mm (≈ 1e-6 of the size), well inside it.
pub const DEFAULT_PAIRING_TOLERANCE: f64 = 1e-4;

/// How close facing interface nodes must be.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PairingTolerance {
    /// A distance, in mesh units.
    Absolute(f64),
    /// A fraction of the local element size: the shortest bottom-face edge
    /// at the node (for a mid node, its own edge).
    Relative(f64),
}

impl Default for PairingTolerance {
    fn default() -> Self {
        PairingTolerance::Relative(DEFAULT_PAIRING_TOLERANCE)
    }
}

impl Mesh {
    /// Declares an interface between two edge sets and pairs their nodes by geometry.
    ///
    /// `tolerance`: an absolute distance, or `None` for the default relative
    /// tolerance ([`DEFAULT_PAIRING_TOLERANCE`] × the local element size).
    /// See [`Mesh::add_interface_with`].
    pub fn add_interface(
        &mut self,
        name: &str,
        bottom_set: &str,
        top_set: &str,
        tolerance: Option<f64>,
    ) -> Result<(), MeshError> {
        let tol = match tolerance {
            Some(t) => PairingTolerance::Absolute(t),
            None => PairingTolerance::default(),
        };
        self.add_interface_with(name, bottom_set, top_set, tol)
    }

    /// Declares an interface between two edge sets and pairs their nodes by geometry.
    ///
    /// Each bottom edge becomes one interface element (see [`Interface`]);
    /// its nodes must face (coincide with) nodes of the top set within the
    /// tolerance, and the facing nodes must form an edge of the top set. On a
    /// P2 mesh the two mid nodes must face each other too. On a mesh read
    /// from a Gmsh file the errors name the nodes also by their Gmsh tags.
    pub fn add_interface_with(
        &mut self,
        name: &str,
        bottom_set: &str,
        top_set: &str,
        tolerance: PairingTolerance,
    ) -> Result<(), MeshError> {
        self.pair_interface(name, bottom_set, top_set, tolerance)
            .map_err(|e| self.tagged(e))
    }

    fn pair_interface(
        &mut self,
        name: &str,
        bottom_set: &str,
        top_set: &str,
        tolerance: PairingTolerance,
    ) -> Result<(), MeshError> {
        let value = match tolerance {
            PairingTolerance::Absolute(v) | PairingTolerance::Relative(v) => v,
        };
        let relative = matches!(tolerance, PairingTolerance::Relative(_));
        if !(value.is_finite() && value > 0.0) || (relative && value >= 0.5) {
            return Err(MeshError::InvalidParameter {
                name: "pairing_tolerance",
                value: value.to_string(),
                reason: if relative {
                    "a relative pairing tolerance lies in (0, 0.5)".into()
                } else {
                    "a pairing distance must be positive and finite".into()
                },
            });
        }
        let bottom = self.edge_set(bottom_set)?.to_vec();
        let top = self.edge_set(top_set)?.to_vec();
        // Local size: the shortest bottom edge at each bottom node.
        let mut size: HashMap<usize, f64> = HashMap::new();
        for &[a, b] in &bottom {
            let l = dist(self.nodes[a], self.nodes[b]);
            for v in [a, b] {
                let s = size.entry(v).or_insert(f64::INFINITY);
                *s = s.min(l);
            }
        }
        let tol_at = |len: f64| match tolerance {
            PairingTolerance::Absolute(t) => t,
            PairingTolerance::Relative(r) => r * len,
        };
        let max_tol = size.values().map(|&l| tol_at(l)).fold(0.0, f64::max);
        let mut top_nodes: Vec<usize> = top.iter().flatten().copied().collect();
        top_nodes.sort_unstable();
        top_nodes.dedup();
        let grid = PointGrid::new(&self.nodes, &top_nodes, max_tol);
        let top_edges: HashSet<(usize, usize)> =
            top.iter().flat_map(|&[a, b]| [(a, b), (b, a)]).collect();
        let mut elements = Vec::with_capacity(bottom.len());
        let mut mid_nodes = Vec::new();
        for &[a, b] in &bottom {
            // The bottom body is on the left of a→b (edge sets are stored
            // counter-clockwise); the top body must be on the left of 1→2.
            let (n1, n2) = (b, a);
            let facing = |v: usize| {
                let tol = tol_at(size[&v]);
                grid.nearest(&self.nodes, self.nodes[v], tol)
                    .ok_or_else(|| {
                        let nearest = top_nodes.iter().copied().min_by(|&p, &q| {
                            dist(self.nodes[p], self.nodes[v])
                                .total_cmp(&dist(self.nodes[q], self.nodes[v]))
                        });
                        MeshError::InterfaceNotFacing {
                            interface: name.into(),
                            bottom_set: bottom_set.into(),
                            top_set: top_set.into(),
                            bottom: v,
                            x: self.nodes[v][0],
                            y: self.nodes[v][1],
                            nearest: nearest.unwrap_or(usize::MAX),
                            distance: nearest
                                .map_or(f64::INFINITY, |p| dist(self.nodes[p], self.nodes[v])),
                            tolerance: tol,
                            gmsh: GmshRefs::NONE,
                        }
                    })
            };
            let n4 = facing(n1)?;
            let n3 = facing(n2)?;
            if !top_edges.contains(&(n3, n4)) {
                return Err(MeshError::InterfaceEdgeMissing {
                    interface: name.into(),
                    top_set: top_set.into(),
                    a,
                    b,
                    c: n3,
                    d: n4,
                    gmsh: GmshRefs::NONE,
                });
            }
            if n1 == n4 && n2 == n3 {
                return Err(MeshError::InterfaceSameEdge {
                    interface: name.into(),
                    a,
                    b,
                    gmsh: GmshRefs::NONE,
                });
            }
            elements.push([n1, n2, n3, n4]);
            if self.order() == 2 {
                let mid = |p: usize, q: usize| {
                    self.edge_mid_node(p, q).ok_or(MeshError::EdgeNotInMesh {
                        set: name.into(),
                        a: p,
                        b: q,
                        gmsh: GmshRefs::NONE,
                    })
                };
                let (mb, mt) = (mid(n1, n2)?, mid(n4, n3)?);
                let d = dist(self.nodes[mb], self.nodes[mt]);
                let tol = tol_at(dist(self.nodes[n1], self.nodes[n2]));
                if d > tol {
                    return Err(MeshError::InterfaceMidNotFacing {
                        interface: name.into(),
                        bottom: mb,
                        top: mt,
                        distance: d,
                        tolerance: tol,
                        gmsh: GmshRefs::NONE,
                    });
                }
                mid_nodes.push([mb, mt]);
            }
        }
        self.interfaces.insert(
            name.into(),
            crate::mesh::Interface {
                bottom_set: bottom_set.into(),
                top_set: top_set.into(),
                elements,
                mid_nodes,
            },
        );
        Ok(())
    }
}

impl Mesh {
    /// Pairs of bodies whose boundaries touch at coincident nodes that no
    /// interface joins, one [`MeshNotice::UnjoinedTouchingBodies`] per pair
    /// of bodies (ordered by body).
    ///
    /// Two nodes coincide when they are closer than
    /// [`DEFAULT_PAIRING_TOLERANCE`] × the shorter of the shortest triangle
    /// edges at either node, the tolerance interfaces pair with by default
    /// (Gmsh's separately meshed curves place facing nodes a few nm apart).
    /// A pair is joined when an interface element has the two nodes facing
    /// each other. Such bodies run as separate bodies, which may be meant
    /// (two parts apart), or may be a forgotten `[[interface]]` or an
    /// unmerged mesh.
    pub fn unjoined_touching_bodies(&self) -> Vec<MeshNotice> {
        if self.bodies.len() < 2 {
            return Vec::new();
        }
        let n = self.nodes.len();
        let mut size = vec![f64::INFINITY; n];
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let l = dist(self.nodes[a], self.nodes[b]);
                size[a] = size[a].min(l);
                size[b] = size[b].min(l);
            }
        }
        let tol_at = |v: usize| DEFAULT_PAIRING_TOLERANCE * size[v];
        // the corners (the mid nodes of a P2 mesh follow their edges)
        let corners: Vec<usize> = (0..n).filter(|&v| size[v].is_finite()).collect();
        let max_tol = corners.iter().map(|&v| tol_at(v)).fold(0.0, f64::max);
        let grid = PointGrid::new(&self.nodes, &corners, max_tol);
        let mut joined: HashSet<(usize, usize)> = HashSet::new();
        let key = |a: usize, b: usize| (a.min(b), a.max(b));
        for itf in self.interfaces.values() {
            for &[n1, n2, n3, n4] in &itf.elements {
                joined.insert(key(n1, n4));
                joined.insert(key(n2, n3));
            }
            for &[b, t] in &itf.mid_nodes {
                joined.insert(key(b, t));
            }
        }
        // (body, body) -> (count, first pair)
        let mut found: BTreeMap<(usize, usize), (usize, (usize, usize))> = BTreeMap::new();
        let mut pairs = grid.close_pairs(&self.nodes, max_tol);
        pairs.sort_unstable();
        for (i, j) in pairs {
            let (bi, bj) = (self.node_body[i], self.node_body[j]);
            if bi == bj
                || dist(self.nodes[i], self.nodes[j]) > tol_at(i).min(tol_at(j))
                || joined.contains(&key(i, j))
            {
                continue;
            }
            let (i, j, bi, bj) = if bi < bj {
                (i, j, bi, bj)
            } else {
                (j, i, bj, bi)
            };
            found.entry((bi, bj)).or_insert((0, (i, j))).0 += 1;
        }
        found
            .into_iter()
            .map(
                |((bi, bj), (count, (i, j)))| MeshNotice::UnjoinedTouchingBodies {
                    first: self.bodies[bi].name.clone(),
                    second: self.bodies[bj].name.clone(),
                    pairs: count,
                    example: format!(
                        "{} and {} at ({}, {})",
                        self.node_label(i),
                        self.node_label(j),
                        self.nodes[i][0],
                        self.nodes[i][1]
                    ),
                },
            )
            .collect()
    }
}
