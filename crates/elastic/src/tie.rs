//! Bonded (tied) interfaces: the two faces of an interface share their
//! degrees of freedom.
//!
//! A tied interface is not a stiff spring: each facing node pair (corner
//! pairs, and on 6-node triangles the facing mid-node pairs too) is one
//! node of the elastic problem, so its two displacement unknowns are
//! eliminated from the dof map and the answer cannot depend on a penalty.
//! [`TiedMesh`] is the mesh the elastic model is built on (facing nodes
//! merged, the tied interfaces gone, every other set and interface kept);
//! its node map carries results back to the original mesh, on which heat
//! conduction (with the interface conductance) and the outputs run.
//! Elements keep their numbers and node order, so per-element data
//! (`Loads::delta_t`, element stresses, regions) needs no mapping.
//!
//! ```text
//!   original:  core ── n4 n3 ── layer        tied:  core ── m ── layer
//!                     n1 n2                             (n1 = n4 = m, n2 = n3 = m')
//! ```

use tecon_mesh::{Mesh, PairingTolerance};

use crate::error::ElasticError;

/// A mesh with some interfaces tied, and the map from its parent's nodes.
#[derive(Debug, Clone)]
pub struct TiedMesh {
    mesh: Mesh,
    node_map: Vec<usize>,
    tied: Vec<String>,
}

/// Root of `a` in a union–find forest (path halving).
fn find(parent: &mut [usize], mut a: usize) -> usize {
    while parent[a] != a {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    a
}

impl TiedMesh {
    /// Ties the interfaces `names` of `mesh`: every facing node pair becomes
    /// one node (numbered by its lowest original id, in ascending order).
    ///
    /// The tied mesh keeps the regions and element numbering, every edge set
    /// and node set (renumbered) and the interfaces not tied (re-paired on
    /// the tied mesh, with their elements in the original order). Errors: an
    /// interface the mesh lacks, or a mesh the merge makes invalid (named).
    pub fn new(mesh: &Mesh, names: &[&str]) -> Result<TiedMesh, ElasticError> {
        let n = mesh.n_nodes();
        let mut parent: Vec<usize> = (0..n).collect();
        let union = |parent: &mut Vec<usize>, a: usize, b: usize| {
            let (ra, rb) = (find(parent, a), find(parent, b));
            // the lower id is the root, so each class is named by its minimum
            if ra < rb {
                parent[rb] = ra;
            } else if rb < ra {
                parent[ra] = rb;
            }
        };
        for &name in names {
            let iface = mesh.interface(name)?;
            for el in &iface.elements {
                union(&mut parent, el[0], el[3]);
                union(&mut parent, el[1], el[2]);
            }
            for &[b, t] in &iface.mid_nodes {
                union(&mut parent, b, t);
            }
        }
        let mut node_map = vec![usize::MAX; n];
        let mut nodes = Vec::new();
        for v in 0..n {
            let r = find(&mut parent, v);
            if r == v {
                node_map[v] = nodes.len();
                nodes.push(mesh.nodes()[v]);
            } else {
                node_map[v] = node_map[r];
            }
        }
        let regions = mesh.element_regions().to_vec();
        let region_names = mesh.region_names().to_vec();
        let map = |v: usize| node_map[v];
        let merge_error = |e: tecon_mesh::MeshError| ElasticError::Input {
            what: format!("tied interface(s) {}", names.join(", ")),
            message: e.to_string(),
        };
        let mut tied = match mesh.triangles6() {
            Some(t6) => Mesh::new_quadratic(
                nodes,
                t6.iter().map(|t| t.map(map)).collect(),
                regions,
                region_names,
            ),
            None => Mesh::new(
                nodes,
                mesh.triangles().iter().map(|t| t.map(map)).collect(),
                regions,
                region_names,
            ),
        }
        .map_err(merge_error)?;
        for (name, edges) in mesh.edge_sets() {
            tied.add_edge_set(name, edges.iter().map(|e| e.map(map)).collect())
                .map_err(merge_error)?;
        }
        for (name, set) in mesh.node_sets() {
            tied.add_node_set(name, set.iter().map(|&v| map(v)).collect())
                .map_err(merge_error)?;
        }
        for (name, iface) in mesh.interfaces() {
            if names.contains(&name.as_str()) {
                continue;
            }
            tied.add_interface_with(
                name,
                &iface.bottom_set,
                &iface.top_set,
                PairingTolerance::default(),
            )
            .map_err(merge_error)?;
            let again = tied.interface(name)?;
            let expected: Vec<[usize; 4]> = iface.elements.iter().map(|e| e.map(map)).collect();
            if again.elements != expected {
                return Err(ElasticError::Input {
                    what: format!("interface '{name}'"),
                    message: "its elements pair differently once the tied interfaces are merged; tie it too or keep the others apart".into(),
                });
            }
        }
        Ok(TiedMesh {
            mesh: tied,
            node_map,
            tied: names.iter().map(|s| s.to_string()).collect(),
        })
    }

    /// The tied mesh (build the elastic model on it).
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Tied-mesh node of each original node.
    pub fn node_map(&self) -> &[usize] {
        &self.node_map
    }

    /// Names of the tied interfaces.
    pub fn tied_interfaces(&self) -> &[String] {
        &self.tied
    }

    /// Displacements (2 per node, then any global unknowns such as ε_zz) of
    /// the tied mesh, expanded to the original nodes: both nodes of a tied
    /// pair get the displacement of their shared node.
    pub fn expand_displacement(&self, u: &[f64]) -> Vec<f64> {
        let tail = u.get(2 * self.mesh.n_nodes()..).unwrap_or(&[]);
        let mut out = Vec::with_capacity(2 * self.node_map.len() + tail.len());
        for &m in &self.node_map {
            out.push(u[2 * m]);
            out.push(u[2 * m + 1]);
        }
        out.extend_from_slice(tail);
        out
    }

    /// A nodal field of the tied mesh at the original nodes.
    pub fn expand_nodal<T: Copy>(&self, values: &[T]) -> Vec<T> {
        self.node_map.iter().map(|&m| values[m]).collect()
    }
}
