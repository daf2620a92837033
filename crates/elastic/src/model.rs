//! The elastic model: mesh, materials per region, supports, loads and
//! interfaces. Built with checked builder calls that name what is wrong.

use std::collections::HashMap;
use tecon_contact::nalgebra::{Point2, Vector2};
use tecon_contact::{InterfaceElement, InterfaceQuadrature, QuadraticInterfaceElement, Vector8};
use tecon_fem::DofMap;
use tecon_mesh::Mesh;

use crate::error::ElasticError;
use crate::joint::Joint;
use crate::material::{Analysis, Material};

/// Displacement component.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Component {
    /// u_x.
    X,
    /// u_y.
    Y,
}

/// Which normal the interface points use.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum InterfaceNormals {
    /// One normal per interface node, averaged over the elements meeting
    /// there (weights 1/length, which gives the exact radial normal on a
    /// circle); across a corner sharper than 45° each element keeps its own.
    /// Two elements sharing a node then see the same jump at that node, so
    /// a slip along a curved interface opens neither of them.
    #[default]
    Smoothed,
    /// Each element's chord normal (the classical Goodman element): on a
    /// curved interface a tangential slip `s` gives normal jumps
    /// `±s·sin(Δθ/2)` of opposite sign in two neighbouring elements.
    Element,
}

/// Corner angle beyond which interface normals are not averaged.
const FEATURE_ANGLE_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// One interface of the model: its elements and joint law. On an order-1
/// mesh the elements are 4-node ([`InterfaceElement`], two integration
/// points each); on an order-2 mesh they are 6-node
/// ([`QuadraticInterfaceElement`], three points each) and `elements` is
/// empty.
#[derive(Debug, Clone)]
pub struct ModelInterface {
    /// Interface name in the mesh.
    pub name: String,
    /// Joint law.
    pub law: Joint,
    /// Corner node ids [1, 2, 3, 4] of each element (either order).
    pub nodes: Vec<[usize; 4]>,
    /// Order 1: element kernels (geometry and quadrature).
    pub elements: Vec<InterfaceElement>,
    /// Order 2: node ids [1, 2, 3, 4, 5, 6] of each element — the corners
    /// as in `nodes`, then the bottom and the top mid node.
    pub quadratic_nodes: Vec<[usize; 6]>,
    /// Order 2: element kernels (geometry and quadrature).
    pub quadratic: Vec<QuadraticInterfaceElement>,
    /// Reference displacements (2 per node, the whole mesh) from which the
    /// jumps are measured: ⟦u⟧ = B (u − u_ref). None: u_ref = 0. A layer
    /// wrapped onto a deformed assembly takes the displacements at its
    /// activation, so it starts with a zero jump (tight, stress free).
    pub reference: Option<Vec<f64>>,
}

impl ModelInterface {
    /// True for the 6-node (order-2) elements.
    pub fn is_quadratic(&self) -> bool {
        !self.quadratic_nodes.is_empty()
    }

    /// Integration points per element: 2 (4-node) or 3 (6-node).
    pub fn points_per_element(&self) -> usize {
        if self.is_quadratic() { 3 } else { 2 }
    }

    /// Local displacement vector of element `e` relative to the reference,
    /// in the node order [1, 2, 3, 4] (x, y each).
    #[inline]
    pub fn local_u(&self, e: usize, u: &[f64]) -> Vector8 {
        let n = self.nodes[e];
        match &self.reference {
            None => Vector8::from_fn(|i, _| u[2 * n[i / 2] + i % 2]),
            Some(r) => Vector8::from_fn(|i, _| {
                let d = 2 * n[i / 2] + i % 2;
                u[d] - r[d]
            }),
        }
    }
}

/// A plane elastic model on a mesh.
#[derive(Debug, Clone)]
pub struct ElasticModel<'m> {
    pub(crate) mesh: &'m Mesh,
    pub(crate) analysis: Analysis,
    pub(crate) materials: Vec<Option<Material>>,
    pub(crate) fixed: Vec<(usize, f64)>,
    pub(crate) rotated: Vec<(usize, [f64; 2])>,
    pub(crate) pressure: Vec<([usize; 2], f64)>,
    pub(crate) body_force: Vec<[f64; 2]>,
    pub(crate) interfaces: Vec<ModelInterface>,
    pub(crate) quadrature: InterfaceQuadrature,
    pub(crate) normals: InterfaceNormals,
    pub(crate) remove_free_translations: bool,
    /// Which triangles are in the system (None: all). See
    /// [`ElasticModel::active_regions`].
    pub(crate) active: Option<Vec<bool>>,
}

/// Tolerance on |n_x| or |n_y| ≈ 1 for treating a symmetry edge as axis-aligned.
const AXIS_TOLERANCE: f64 = 1e-9;

impl<'m> ElasticModel<'m> {
    /// An empty model (no materials, supports or loads) of `analysis` type on `mesh`.
    pub fn new(mesh: &'m Mesh, analysis: Analysis) -> Self {
        ElasticModel {
            mesh,
            analysis,
            materials: vec![None; mesh.region_names().len()],
            fixed: Vec::new(),
            rotated: Vec::new(),
            pressure: Vec::new(),
            body_force: vec![[0.0; 2]; mesh.region_names().len()],
            interfaces: Vec::new(),
            quadrature: InterfaceQuadrature::default(),
            normals: InterfaceNormals::default(),
            remove_free_translations: false,
            active: None,
        }
    }

    /// The mesh.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    /// The analysis type.
    pub fn analysis(&self) -> Analysis {
        self.analysis
    }

    /// The dof numbering (2 per node; generalised plane strain adds ε_zz last).
    pub fn dofmap(&self) -> DofMap {
        DofMap::new(self.mesh.n_nodes(), 2)
    }

    /// Total number of unknowns.
    pub fn n_dofs(&self) -> usize {
        2 * self.mesh.n_nodes() + usize::from(self.analysis == Analysis::GeneralisedPlaneStrain)
    }

    /// Index of the ε_zz unknown (generalised plane strain).
    pub fn eps_zz_dof(&self) -> Option<usize> {
        (self.analysis == Analysis::GeneralisedPlaneStrain).then(|| 2 * self.mesh.n_nodes())
    }

    /// Material of region `region`.
    pub fn material(mut self, region: &str, m: Material) -> Result<Self, ElasticError> {
        let r = self.mesh.region_index(region)?;
        m.check().map_err(|message| ElasticError::Material {
            region: region.into(),
            message,
        })?;
        self.materials[r] = Some(m);
        Ok(self)
    }

    /// The same material for every region.
    pub fn material_everywhere(mut self, m: Material) -> Result<Self, ElasticError> {
        for name in self.mesh.region_names().to_vec() {
            self = self.material(&name, m)?;
        }
        Ok(self)
    }

    /// Material of each triangle (errors name a region without one).
    pub fn element_materials(&self) -> Result<Vec<Material>, ElasticError> {
        let names = self.mesh.region_names();
        self.mesh
            .element_regions()
            .iter()
            .map(|&r| {
                self.materials[r].ok_or_else(|| ElasticError::MissingMaterial(names[r].clone()))
            })
            .collect()
    }

    fn set_nodes(&self, set: &str) -> Result<Vec<usize>, ElasticError> {
        match self.mesh.node_set(set) {
            Ok(n) => Ok(n.to_vec()),
            Err(_) => Ok(self.mesh.edge_set_nodes(set)?),
        }
    }

    /// Prescribes displacement `value` (m, at load factor 1) of `component`
    /// on the nodes of a node set or edge set.
    pub fn fix(
        mut self,
        set: &str,
        component: Component,
        value: f64,
    ) -> Result<Self, ElasticError> {
        if !value.is_finite() {
            return Err(ElasticError::Input {
                what: format!("fixed displacement on '{set}'"),
                message: format!("value {value} is not finite"),
            });
        }
        let c = match component {
            Component::X => 0,
            Component::Y => 1,
        };
        for n in self.set_nodes(set)? {
            self.fixed.push((2 * n + c, value));
        }
        Ok(self)
    }

    /// Symmetry on an edge set of any orientation: zero displacement normal
    /// to the edges (at the corner nodes and, on an order-2 mesh, at the mid
    /// nodes). Axis-aligned edges constrain u_x or u_y directly; other
    /// nodes get a local (n, t) frame in which u_n = 0.
    pub fn symmetry(mut self, edge_set: &str) -> Result<Self, ElasticError> {
        let x = self.mesh.nodes();
        let mut normals: std::collections::BTreeMap<usize, [f64; 2]> = Default::default();
        for &[a, b] in self.mesh.edge_set(edge_set)? {
            let (dx, dy) = (x[b][0] - x[a][0], x[b][1] - x[a][1]);
            // outward normal of a CCW boundary edge: right normal of a→b
            let n = [dy, -dx];
            for v in [a, b] {
                let e = normals.entry(v).or_insert([0.0; 2]);
                e[0] += n[0];
                e[1] += n[1];
            }
            // order 2: the mid node's normal is the chord's (x'(0) of a
            // 3-node edge is (x_b − x_a)/2 whatever the mid node)
            if let Some(m) = self.mesh.edge_mid_node(a, b) {
                normals.insert(m, n);
            }
        }
        for (node, n) in normals {
            let len = (n[0] * n[0] + n[1] * n[1]).sqrt();
            if len == 0.0 {
                return Err(ElasticError::Input {
                    what: format!("symmetry edge set '{edge_set}'"),
                    message: format!("node {node} has no defined normal"),
                });
            }
            let n = [n[0] / len, n[1] / len];
            if (n[0].abs() - 1.0).abs() < AXIS_TOLERANCE {
                self.fixed.push((2 * node, 0.0));
            } else if (n[1].abs() - 1.0).abs() < AXIS_TOLERANCE {
                self.fixed.push((2 * node + 1, 0.0));
            } else {
                self.rotated.push((node, n));
            }
        }
        Ok(self)
    }

    /// Uniform pressure `p` (Pa, at load factor 1) on an edge set, pushing
    /// against the outward normal.
    pub fn pressure(mut self, edge_set: &str, p: f64) -> Result<Self, ElasticError> {
        if !p.is_finite() {
            return Err(ElasticError::Input {
                what: format!("pressure on '{edge_set}'"),
                message: format!("value {p} is not finite"),
            });
        }
        for &e in self.mesh.edge_set(edge_set)? {
            self.pressure.push((e, p));
        }
        Ok(self)
    }

    /// Body force per unit volume (N/m³) in a region.
    pub fn body_force(mut self, region: &str, f: [f64; 2]) -> Result<Self, ElasticError> {
        let r = self.mesh.region_index(region)?;
        self.body_force[r] = f;
        Ok(self)
    }

    /// Interface integration rule (nodal by default); set it before adding interfaces.
    pub fn interface_quadrature(mut self, q: InterfaceQuadrature) -> Self {
        self.quadrature = q;
        self
    }

    /// Interface point normals (smoothed by default); set it before adding
    /// interfaces.
    pub fn interface_normals(mut self, n: InterfaceNormals) -> Self {
        self.normals = n;
        self
    }

    /// Joins the two faces of the mesh interface `name` with `law`: 4-node
    /// elements on an order-1 mesh, 6-node (three node pairs) on an
    /// order-2 mesh.
    pub fn interface(self, name: &str, law: Joint) -> Result<Self, ElasticError> {
        if self.mesh.order() == 2 {
            return self.quadratic_interface(name, law);
        }
        self.linear_interface(name, law)
    }

    /// The 6-node elements of an order-2 mesh. Smoothed normals: at each
    /// corner node the isoparametric normals of the elements sharing it
    /// are summed (not across a corner sharper than 45°); a mid node keeps
    /// its element's own normal.
    fn quadratic_interface(mut self, name: &str, law: Joint) -> Result<Self, ElasticError> {
        let mesh_itf = self.mesh.interface(name)?;
        let nodes = mesh_itf.elements.clone();
        let error = |k: usize, message: String| ElasticError::Interface {
            interface: name.into(),
            element: k,
            message,
        };
        if mesh_itf.mid_nodes.len() != nodes.len() {
            return Err(error(
                mesh_itf.mid_nodes.len().min(nodes.len()),
                format!(
                    "the mesh is of order 2 but the interface has {} pairs of mid nodes for {} elements",
                    mesh_itf.mid_nodes.len(),
                    nodes.len()
                ),
            ));
        }
        let quadratic_nodes: Vec<[usize; 6]> = nodes
            .iter()
            .zip(&mesh_itf.mid_nodes)
            .map(|(n, m)| [n[0], n[1], n[2], n[3], m[0], m[1]])
            .collect();
        let x = self.mesh.nodes();
        let mut elements = Vec::with_capacity(nodes.len());
        for (k, el) in quadratic_nodes.iter().enumerate() {
            let p = el.map(|v| Point2::new(x[v][0], x[v][1]));
            let e = QuadraticInterfaceElement::with_quadrature(&p, self.quadrature)
                .map_err(|e| error(k, e.to_string()))?;
            elements.push(e);
        }
        if self.normals == InterfaceNormals::Smoothed {
            // (element, local corner 0 or 1) at each bottom corner node
            let mut at_node: HashMap<usize, Vec<(usize, usize)>> = HashMap::new();
            for (k, el) in nodes.iter().enumerate() {
                at_node.entry(el[0]).or_default().push((k, 0));
                at_node.entry(el[1]).or_default().push((k, 1));
            }
            let own: Vec<[Vector2<f64>; 3]> = elements
                .iter()
                .map(|e| e.geometry().node_normals())
                .collect();
            for (k, el) in nodes.iter().enumerate() {
                let smoothed = [0usize, 1].map(|c| {
                    let mine = own[k][c];
                    at_node[&el[c]]
                        .iter()
                        .map(|&(f, cf)| own[f][cf])
                        .filter(|n| n.dot(&mine) >= FEATURE_ANGLE_COS)
                        .fold(Vector2::zeros(), |acc, n| acc + n)
                });
                elements[k] = elements[k]
                    .with_node_normals([smoothed[0], smoothed[1], own[k][2]])
                    .map_err(|e| error(k, e.to_string()))?;
            }
        }
        self.interfaces.push(ModelInterface {
            name: name.into(),
            law,
            nodes,
            elements: Vec::new(),
            quadratic_nodes,
            quadratic: elements,
            reference: None,
        });
        Ok(self)
    }

    /// The 4-node elements of an order-1 mesh.
    fn linear_interface(mut self, name: &str, law: Joint) -> Result<Self, ElasticError> {
        let nodes = self.mesh.interface(name)?.elements.clone();
        let x = self.mesh.nodes();
        let error = |k: usize, message: String| ElasticError::Interface {
            interface: name.into(),
            element: k,
            message,
        };
        let mut elements = Vec::with_capacity(nodes.len());
        for (k, el) in nodes.iter().enumerate() {
            let p = el.map(|v| Point2::new(x[v][0], x[v][1]));
            let e = InterfaceElement::with_quadrature(&p, self.quadrature)
                .map_err(|e| error(k, e.to_string()))?;
            elements.push(e);
        }
        if self.normals == InterfaceNormals::Smoothed {
            // elements meeting at each bottom node
            let mut at_node: HashMap<usize, Vec<usize>> = HashMap::new();
            for (k, el) in nodes.iter().enumerate() {
                at_node.entry(el[0]).or_default().push(k);
                at_node.entry(el[1]).or_default().push(k);
            }
            let chord: Vec<(Vector2<f64>, f64)> = elements
                .iter()
                .map(|e| (e.geometry().normal(), e.geometry().length()))
                .collect();
            for (k, el) in nodes.iter().enumerate() {
                let own = chord[k].0;
                let smoothed = [el[0], el[1]].map(|v| {
                    at_node[&v]
                        .iter()
                        .map(|&f| chord[f])
                        .filter(|(n, _)| n.dot(&own) >= FEATURE_ANGLE_COS)
                        .fold(Vector2::zeros(), |acc, (n, l)| acc + n / l)
                });
                elements[k] = elements[k]
                    .with_node_normals(smoothed)
                    .map_err(|e| error(k, e.to_string()))?;
            }
        }
        self.interfaces.push(ModelInterface {
            name: name.into(),
            law,
            nodes,
            elements,
            quadratic_nodes: Vec::new(),
            quadratic: Vec::new(),
            reference: None,
        });
        Ok(self)
    }

    /// Lets the solver remove rigid translations that the supports leave
    /// free by fixing one displacement component of one node per free mode
    /// (a minimal constraint: its reaction vanishes when the loads are
    /// self-equilibrated, so the stresses do not change). Off by default:
    /// then a free body is an error that names it.
    pub fn remove_free_translations(mut self, yes: bool) -> Self {
        self.remove_free_translations = yes;
        self
    }

    /// The interfaces of the model.
    pub fn interfaces(&self) -> &[ModelInterface] {
        &self.interfaces
    }
}
