//! `ThermalModel`: a mesh plus materials per region, conditions per edge
//! set, interfaces with conductance laws and an initial temperature — the
//! entry point for the vessel-like use.

use std::collections::BTreeMap;
use std::sync::Arc;

use nalgebra::Point2;
use tecon_fem::Dirichlet;
use tecon_fem::interface::{InterfaceGeometry, InterfaceQuadrature};
use tecon_mesh::{Mesh, signed_area};

use crate::bc::EdgeBc;
use crate::conductance::{ConductanceLaw, ConstantConductance, InterfacePointState};
use crate::error::ThermalError;
use crate::initial::{BorderRule, InitialTemperature};
use crate::kernels::{ConvectionEdges, InterfaceElements};
use crate::kernels6::{Convection3Edges, Interface3Elements};
use crate::material::{CapacityKind, Material};
use crate::output::Snapshot;
use crate::schedule::{ThetaScheme, TimeSchedule};
use crate::stepper::StepperStats;
use crate::system::{InterfaceRange, P2Input, SystemInput, ThermalSystem};
use tecon_fem::edge3::Edge3;
use tecon_fem::interface3::Interface3Geometry;
use tecon_fem::triangle6::Triangle6;

/// Thermal coupling of one interface.
#[derive(Debug, Clone)]
enum InterfaceSpec {
    /// No heat crosses (a perfect insulator).
    Adiabatic,
    /// Heat crosses with `q = h_c ⟦T⟧`, `h_c` from the law.
    Law {
        law: Arc<dyn ConductanceLaw>,
        rule: InterfaceQuadrature,
        states: Option<Vec<[InterfacePointState; 2]>>,
    },
}

/// What a transient run did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransientSummary {
    /// End time reached.
    pub end_time: f64,
    /// Steps taken (schedule steps, plus the extra sub-steps that land on
    /// output times inside a step).
    pub steps: usize,
    /// Numeric factorisations of `C/Δt + θK`.
    pub factorisations: usize,
    /// Largest relative heat-balance residual seen at the output times.
    pub max_balance_residual: f64,
}

/// A heat-conduction model on a mesh.
///
/// ```text
///   ρc Ṫ = ∇·(k∇T)   in each region          adiabatic by default on edges
///   −k ∂T/∂n = h (T − T∞)   convective edge sets
///   k ∂T/∂n = q_in          prescribed-flux edge sets
///   T = T̄                   prescribed-temperature edge / node sets
///   q = h_c (T_top − T_bottom)   across interfaces (top → bottom)
/// ```
#[derive(Debug, Clone)]
pub struct ThermalModel<'m> {
    mesh: &'m Mesh,
    materials: Vec<Option<Material>>,
    capacity: CapacityKind,
    edge_bcs: Vec<(String, EdgeBc)>,
    node_temperatures: Vec<(String, f64)>,
    single_nodes: Vec<(usize, f64)>,
    interfaces: BTreeMap<String, InterfaceSpec>,
    initial: InitialTemperature,
    has_initial: bool,
    /// Changed by every setter but [`ThermalModel::set_interface_state`]
    /// (a fresh number from [`REVISIONS`]): a system assembled at the same
    /// revision differs from this model in its interface states at most
    /// ([`ThermalModel::reassemble`]).
    revision: u64,
}

/// The source of model revisions (unique across models; a clone keeps its
/// original's, as it has the same content).
static REVISIONS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

fn next_revision() -> u64 {
    REVISIONS.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl<'m> ThermalModel<'m> {
    /// An empty model on `mesh` (consistent capacity, adiabatic edges).
    pub fn new(mesh: &'m Mesh) -> Self {
        ThermalModel {
            mesh,
            materials: vec![None; mesh.region_names().len()],
            capacity: CapacityKind::default(),
            edge_bcs: Vec::new(),
            node_temperatures: Vec::new(),
            single_nodes: Vec::new(),
            interfaces: BTreeMap::new(),
            initial: InitialTemperature::default(),
            has_initial: false,
            revision: next_revision(),
        }
    }

    /// The mesh.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    /// Gives `region` a material (k, ρ, c validated: positive and finite).
    pub fn set_material(
        &mut self,
        region: &str,
        material: Material,
    ) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        material.validate(region)?;
        let r = self.mesh.region_index(region)?;
        self.materials[r] = Some(material);
        Ok(self)
    }

    /// Gives every region the same material.
    pub fn set_material_everywhere(
        &mut self,
        material: Material,
    ) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        for name in self.mesh.region_names() {
            material.validate(name)?;
        }
        self.materials.iter_mut().for_each(|m| *m = Some(material));
        Ok(self)
    }

    /// Chooses the consistent (default) or lumped capacity matrix.
    pub fn set_capacity(&mut self, kind: CapacityKind) -> &mut Self {
        self.revision = next_revision();
        self.capacity = kind;
        self
    }

    /// Applies a condition to the edges of `edge_set` (validated; conditions
    /// on one edge add up, e.g. convection and a flux).
    pub fn add_edge_bc(&mut self, edge_set: &str, bc: EdgeBc) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        bc.validate(edge_set)?;
        self.mesh.edge_set(edge_set)?;
        self.edge_bcs.push((edge_set.into(), bc));
        Ok(self)
    }

    /// Prescribes the temperature of every node of `node_set`.
    pub fn prescribe_node_set(
        &mut self,
        node_set: &str,
        value: f64,
    ) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        EdgeBc::temperature(value).validate(node_set)?;
        self.mesh.node_set(node_set)?;
        self.node_temperatures.push((node_set.into(), value));
        Ok(self)
    }

    /// Prescribes the temperature of one node.
    pub fn prescribe_node(&mut self, node: usize, value: f64) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        let what = format!("node {node}");
        EdgeBc::temperature(value).validate(&what)?;
        if node >= self.mesh.n_nodes() {
            return Err(ThermalError::NodeOutOfRange {
                what: "prescribed temperature".into(),
                node,
                n_nodes: self.mesh.n_nodes(),
            });
        }
        self.single_nodes.push((node, value));
        Ok(self)
    }

    fn check_interface(&self, name: &str) -> Result<(), ThermalError> {
        self.mesh.interface(name)?;
        Ok(())
    }

    /// Couples the two sides of interface `name` with a conductance law,
    /// integrated with `rule` ([`InterfaceQuadrature::Nodal`] is the default
    /// choice).
    pub fn set_interface_law<L: ConductanceLaw + 'static>(
        &mut self,
        name: &str,
        law: L,
        rule: InterfaceQuadrature,
    ) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        self.check_interface(name)?;
        self.interfaces.insert(
            name.into(),
            InterfaceSpec::Law {
                law: Arc::new(law),
                rule,
                states: None,
            },
        );
        Ok(self)
    }

    /// Couples interface `name` with a constant conductance `h_c` (W/(m² K),
    /// positive), nodal integration.
    pub fn set_interface_conductance(
        &mut self,
        name: &str,
        h_c: f64,
    ) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        self.check_interface(name)?;
        let law = ConstantConductance::new(h_c).map_err(|_| ThermalError::InvalidConductance {
            interface: name.into(),
            element: None,
            requirement: "positive and finite",
            value: h_c,
        })?;
        self.set_interface_law(name, law, InterfaceQuadrature::Nodal)
    }

    /// Declares interface `name` adiabatic (no heat crosses it).
    pub fn set_interface_adiabatic(&mut self, name: &str) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        self.check_interface(name)?;
        self.interfaces
            .insert(name.into(), InterfaceSpec::Adiabatic);
        Ok(self)
    }

    /// Sets the mechanical state (gap, pressure) of each integration point of
    /// interface `name`, read by its conductance law at the next assembly.
    ///
    /// On a P2 mesh (3-pair elements) the two states of an element are those
    /// of its corner pairs (1, 4) and (2, 3); the mid pair's law sees their
    /// mean (gap and pressure averaged).
    pub fn set_interface_state(
        &mut self,
        name: &str,
        states: Vec<[InterfacePointState; 2]>,
    ) -> Result<&mut Self, ThermalError> {
        let expected = self.mesh.interface(name)?.elements.len();
        if states.len() != expected {
            return Err(ThermalError::InterfaceStateLength {
                interface: name.into(),
                got: states.len(),
                expected,
            });
        }
        match self.interfaces.get_mut(name) {
            Some(InterfaceSpec::Law { states: s, .. }) => {
                *s = Some(states);
                Ok(self)
            }
            _ => Err(ThermalError::MissingInterfaceLaw {
                interface: name.into(),
            }),
        }
    }

    /// The conductance h_c at each integration point of interface `name`
    /// in its current states (what the next assembly uses; the default
    /// state where none was set). Errors if the interface has no law.
    pub fn interface_conductance_values(&self, name: &str) -> Result<Vec<[f64; 2]>, ThermalError> {
        let n = self.mesh.interface(name)?.elements.len();
        match self.interfaces.get(name) {
            Some(InterfaceSpec::Law { law, states, .. }) => Ok((0..n)
                .map(|e| element_h2(law.as_ref(), states.as_deref(), e))
                .collect()),
            _ => Err(ThermalError::MissingInterfaceLaw {
                interface: name.into(),
            }),
        }
    }

    /// Initial temperature of every region not given one explicitly.
    pub fn set_initial_default(&mut self, value: f64) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        check_finite("default", value)?;
        self.initial.default = Some(value);
        self.has_initial = true;
        Ok(self)
    }

    /// Initial temperature of `region`.
    pub fn set_initial_region(
        &mut self,
        region: &str,
        value: f64,
    ) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        check_finite(&format!("region '{region}'"), value)?;
        self.mesh.region_index(region)?;
        self.initial.regions.retain(|(r, _)| r != region);
        self.initial.regions.push((region.into(), value));
        self.has_initial = true;
        Ok(self)
    }

    /// Initial temperature of one node (overrides the region values and the
    /// border rule).
    pub fn set_initial_node(&mut self, node: usize, value: f64) -> Result<&mut Self, ThermalError> {
        self.revision = next_revision();
        check_finite(&format!("node {node}"), value)?;
        if node >= self.mesh.n_nodes() {
            return Err(ThermalError::NodeOutOfRange {
                what: "initial temperature".into(),
                node,
                n_nodes: self.mesh.n_nodes(),
            });
        }
        self.initial.nodes.push((node, value));
        Ok(self)
    }

    /// Rule for nodes on a border between regions of different initial
    /// temperature (default [`BorderRule::CapacityWeighted`]).
    pub fn set_border_rule(&mut self, rule: BorderRule) -> &mut Self {
        self.revision = next_revision();
        self.initial.border = rule;
        self
    }

    /// The bounds of the maximum principle: with conduction, interface
    /// exchange (`h_c ≥ 0`), convection and prescribed temperatures only,
    /// no temperature can leave `[lower, upper]`, the smallest and largest
    /// of the initial temperatures (every element's region value and every
    /// per-node override: the nodal initial field lies between them), the
    /// convection ambients and the prescribed temperatures. A prescribed
    /// heat flux into the body removes the upper bound (`None`), one out of
    /// it the lower. `None` without an initial temperature (or with a region
    /// that has none).
    pub fn temperature_bounds(&self) -> Option<(Option<f64>, Option<f64>)> {
        if !self.has_initial {
            return None;
        }
        let names = self.mesh.region_names();
        let mut used = vec![false; names.len()];
        for &r in self.mesh.element_regions() {
            used[r] = true;
        }
        let mut values = Vec::new();
        for (name, _) in names.iter().zip(&used).filter(|(_, u)| **u) {
            let given = self.initial.regions.iter().find(|(n, _)| n == name);
            values.push(given.map(|(_, v)| *v).or(self.initial.default)?);
        }
        values.extend(self.initial.nodes.iter().map(|(_, v)| *v));
        values.extend(self.node_temperatures.iter().map(|(_, v)| *v));
        values.extend(self.single_nodes.iter().map(|(_, v)| *v));
        let (mut heated, mut cooled) = (false, false);
        for (_, bc) in &self.edge_bcs {
            match *bc {
                EdgeBc::Convection { ambient, .. } => values.push(ambient),
                EdgeBc::Temperature { value } => values.push(value),
                EdgeBc::Flux { q_in } => {
                    heated |= q_in > 0.0;
                    cooled |= q_in < 0.0;
                }
            }
        }
        let lower = values.iter().copied().fold(f64::INFINITY, f64::min);
        let upper = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Some(((!cooled).then_some(lower), (!heated).then_some(upper)))
    }

    /// Per-element region temperature and the nodal initial field.
    fn initial_fields(&self, rho_c: &[f64]) -> Result<(Vec<f64>, Vec<f64>), ThermalError> {
        let mesh = self.mesh;
        let names = mesh.region_names();
        let mut per_region = vec![None; names.len()];
        for (name, v) in &self.initial.regions {
            per_region[mesh.region_index(name)?] = Some(*v);
        }
        let per_region: Vec<f64> = per_region
            .iter()
            .enumerate()
            .map(|(r, v)| {
                v.or(self.initial.default)
                    .ok_or_else(|| ThermalError::MissingInitialTemperature {
                        region: names[r].clone(),
                    })
            })
            .collect::<Result<_, _>>()?;
        let regions = mesh.element_regions();
        let element: Vec<f64> = regions.iter().map(|&r| per_region[r]).collect();
        let n = mesh.n_nodes();
        let nodes = mesh.nodes();
        let (mut num, mut den) = (vec![0.0; n], vec![0.0; n]);
        let mut lo = vec![f64::INFINITY; n];
        let mut hi = vec![f64::NEG_INFINITY; n];
        let tris6 = mesh.triangles6().unwrap_or(&[]);
        for (e, t) in mesh.triangles().iter().enumerate() {
            let w = rho_c[e] * signed_area(nodes[t[0]], nodes[t[1]], nodes[t[2]]).abs();
            // P2: mid nodes take part like corners (a mid node inside a
            // region gets the region's value, one on a border the rule's).
            let all: &[usize] = match tris6.get(e) {
                Some(t6) => t6,
                None => t,
            };
            for &i in all {
                num[i] += w * element[e];
                den[i] += w;
                lo[i] = lo[i].min(element[e]);
                hi[i] = hi[i].max(element[e]);
            }
        }
        let mut t0: Vec<f64> = (0..n)
            .map(|i| match self.initial.border {
                // Exact for interior nodes: equal values give the value itself.
                BorderRule::CapacityWeighted => {
                    if lo[i] == hi[i] {
                        lo[i]
                    } else {
                        num[i] / den[i]
                    }
                }
                BorderRule::Maximum => hi[i],
                BorderRule::Minimum => lo[i],
            })
            .collect();
        for &(i, v) in &self.initial.nodes {
            t0[i] = v;
        }
        Ok((t0, element))
    }

    /// Assembles the system: validates that every region has a material and
    /// every interface a law, pairs the prescribed temperatures, builds K, C, F.
    pub fn assemble(&self) -> Result<ThermalSystem<'m>, ThermalError> {
        let mesh = self.mesh;
        let names = mesh.region_names();
        let mats: Vec<Material> = self
            .materials
            .iter()
            .enumerate()
            .map(|(r, m)| {
                m.ok_or_else(|| ThermalError::MissingMaterial {
                    region: names[r].clone(),
                })
            })
            .collect::<Result<_, _>>()?;
        let regions = mesh.element_regions();
        let conductivity: Vec<f64> = regions.iter().map(|&r| mats[r].conductivity).collect();
        let rho_c: Vec<f64> = regions
            .iter()
            .map(|&r| mats[r].volumetric_capacity())
            .collect();
        let nodes = mesh.nodes();
        let len = |a: usize, b: usize| {
            let (p, q) = (nodes[a], nodes[b]);
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
        };
        // Edge conditions.
        let mut convection = ConvectionEdges::default();
        let mut flux_loads = Vec::new();
        let mut dirichlet = Dirichlet::new();
        let mut source: BTreeMap<usize, (f64, String)> = BTreeMap::new();
        let mut prescribe = |node: usize, v: f64, set: &str| -> Result<(), ThermalError> {
            if let Some((first, first_set)) = source.get(&node)
                && *first != v
            {
                return Err(ThermalError::ConflictingTemperature {
                    node,
                    first: *first,
                    first_set: first_set.clone(),
                    second: v,
                    second_set: set.into(),
                });
            }
            source.insert(node, (v, set.into()));
            dirichlet.set(node, v);
            Ok(())
        };
        let quadratic = mesh.order() == 2;
        let mut convection3 = Convection3Edges::default();
        for (set, bc) in &self.edge_bcs {
            let edges = mesh.edge_set(set)?;
            if quadratic {
                for &[a, b] in edges {
                    let edge_error = |reason: String| ThermalError::InvalidEdge {
                        set: set.clone(),
                        a,
                        b,
                        reason,
                    };
                    let m = mesh.edge_mid_node(a, b).ok_or_else(|| {
                        edge_error("no mid node (not an edge of the P2 mesh)".into())
                    })?;
                    let geometry = Edge3::new([nodes[a], nodes[b], nodes[m]])
                        .map_err(|e| edge_error(e.to_string()))?;
                    match *bc {
                        EdgeBc::Convection { h, ambient } => {
                            convection3.edges.push([a, b, m]);
                            convection3.geometry.push(geometry);
                            convection3.h.push(h);
                            convection3.ambient.push(ambient);
                        }
                        EdgeBc::Flux { q_in } => {
                            let f = geometry.load_vector(q_in);
                            for (k, node) in [a, b, m].into_iter().enumerate() {
                                flux_loads.push((node, f[k]));
                            }
                        }
                        EdgeBc::Temperature { value } => {
                            for node in [a, b, m] {
                                prescribe(node, value, set)?;
                            }
                        }
                    }
                }
                continue;
            }
            match *bc {
                EdgeBc::Convection { h, ambient } => {
                    for &[a, b] in edges {
                        convection.edges.push([a, b]);
                        convection.length.push(len(a, b));
                        convection.h.push(h);
                        convection.ambient.push(ambient);
                    }
                }
                EdgeBc::Flux { q_in } => {
                    for &[a, b] in edges {
                        let f = 0.5 * q_in * len(a, b);
                        flux_loads.push((a, f));
                        flux_loads.push((b, f));
                    }
                }
                EdgeBc::Temperature { value } => {
                    for &[a, b] in edges {
                        prescribe(a, value, set)?;
                        prescribe(b, value, set)?;
                    }
                }
            }
        }
        for (set, v) in &self.node_temperatures {
            for &i in mesh.node_set(set)? {
                prescribe(i, *v, set)?;
            }
        }
        for &(i, v) in &self.single_nodes {
            prescribe(i, v, &format!("node {i}"))?;
        }
        // Interfaces.
        let mut interfaces = InterfaceElements::default();
        let mut interfaces3 = Interface3Elements::default();
        let mut ranges = Vec::new();
        for name in mesh.interfaces().keys() {
            let spec =
                self.interfaces
                    .get(name)
                    .ok_or_else(|| ThermalError::MissingInterfaceLaw {
                        interface: name.clone(),
                    })?;
            let InterfaceSpec::Law { law, rule, states } = spec else {
                continue;
            };
            let itf = mesh.interface(name)?;
            let elements = &itf.elements;
            if quadratic {
                let start = interfaces3.nodes.len();
                for (e, (&el, &mid)) in elements.iter().zip(&itf.mid_nodes).enumerate() {
                    let n6 = [el[0], el[1], el[2], el[3], mid[0], mid[1]];
                    let pts = n6.map(|i| Point2::new(nodes[i][0], nodes[i][1]));
                    let g = Interface3Geometry::new(&pts).map_err(|source| {
                        ThermalError::InterfaceGeometry {
                            interface: name.clone(),
                            element: e,
                            source,
                        }
                    })?;
                    let h = element_h3(law.as_ref(), states.as_deref(), e);
                    check_h(name, e, &h)?;
                    interfaces3.nodes.push(n6);
                    interfaces3.geometry.push(g);
                    interfaces3.rule.push(*rule);
                    interfaces3.h_c.push(h);
                }
                ranges.push(InterfaceRange {
                    name: name.clone(),
                    range: start..interfaces3.nodes.len(),
                });
                continue;
            }
            let start = interfaces.nodes.len();
            for (e, &el) in elements.iter().enumerate() {
                let pts = el.map(|i| Point2::new(nodes[i][0], nodes[i][1]));
                let g = InterfaceGeometry::new(&pts).map_err(|source| {
                    ThermalError::InterfaceGeometry {
                        interface: name.clone(),
                        element: e,
                        source,
                    }
                })?;
                let h = element_h2(law.as_ref(), states.as_deref(), e);
                check_h(name, e, &h)?;
                interfaces.nodes.push(el);
                interfaces.geometry.push(g);
                interfaces.rule.push(*rule);
                interfaces.h_c.push(h);
            }
            ranges.push(InterfaceRange {
                name: name.clone(),
                range: start..interfaces.nodes.len(),
            });
        }
        let initial = if self.has_initial {
            Some(self.initial_fields(&rho_c)?)
        } else {
            None
        };
        let p2 = match mesh.triangles6() {
            Some(tris6) => {
                let geometry = tris6
                    .iter()
                    .enumerate()
                    .map(|(e, t)| {
                        Triangle6::new(t.map(|i| nodes[i]))
                            .map_err(|source| ThermalError::InvalidElement { element: e, source })
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Some(P2Input {
                    triangles: tris6,
                    geometry,
                    convection: convection3,
                    interfaces: interfaces3,
                })
            }
            None => None,
        };
        ThermalSystem::build(SystemInput {
            mesh,
            conductivity,
            rho_c,
            capacity: self.capacity,
            convection,
            flux_loads,
            dirichlet,
            interfaces,
            interface_ranges: ranges,
            initial,
            p2,
            revision: self.revision,
            // only a state-dependent conductance is ever re-assembled
            keep_bulk: self.interfaces.values().any(|i| {
                matches!(
                    i,
                    InterfaceSpec::Law {
                        states: Some(_),
                        ..
                    }
                )
            }),
        })
    }

    /// The system of this model, made from `previous` (assembled from this
    /// model or a clone of it; consumed) when the model has changed since in its
    /// interface states only ([`ThermalModel::set_interface_state`]): then
    /// only the interface elements are re-assembled, onto the stored bulk
    /// K, and the result equals [`ThermalModel::assemble`]'s bit for bit.
    /// Otherwise (another setter was called, or `previous` had no interface
    /// states set, so did not keep its bulk K) it is a full assembly. The
    /// two-way coupling re-assembles at every block attempt with new
    /// conductances, and the full assembly was about 5 % of its time.
    pub fn reassemble(
        &self,
        previous: ThermalSystem<'m>,
    ) -> Result<ThermalSystem<'m>, ThermalError> {
        if previous.revision != self.revision || !std::ptr::eq(previous.mesh, self.mesh) {
            return self.assemble();
        }
        let Some(k_bulk) = previous.k_bulk.clone() else {
            return self.assemble();
        };
        let quadratic = previous.p2.is_some();
        let (mut h1, mut h3) = (Vec::new(), Vec::new());
        for r in &previous.interface_ranges {
            let Some(InterfaceSpec::Law { law, states, .. }) = self.interfaces.get(&r.name) else {
                return self.assemble();
            };
            for e in 0..r.range.len() {
                if quadratic {
                    let h = element_h3(law.as_ref(), states.as_deref(), e);
                    check_h(&r.name, e, &h)?;
                    h3.push(h);
                } else {
                    let h = element_h2(law.as_ref(), states.as_deref(), e);
                    check_h(&r.name, e, &h)?;
                    h1.push(h);
                }
            }
        }
        previous.with_interface_conductances(k_bulk, h1, h3)
    }

    /// Assembles and solves the steady problem.
    pub fn solve_steady(&self) -> Result<Snapshot, ThermalError> {
        self.assemble()?.solve_steady()
    }

    /// Assembles and runs a transient analysis from the initial temperature,
    /// calling `on_output` at each of `output_times` (sorted, duplicates
    /// removed; a step that straddles an output time is split there so the
    /// output is exact). Returns what the run did.
    pub fn solve_transient<F: FnMut(&Snapshot)>(
        &self,
        schedule: &TimeSchedule,
        scheme: ThetaScheme,
        output_times: &[f64],
        on_output: F,
    ) -> Result<TransientSummary, ThermalError> {
        let system = self.assemble()?;
        run_transient(&system, schedule, scheme, output_times, on_output)
    }

    /// As [`ThermalModel::solve_transient`], collecting the snapshots.
    pub fn solve_transient_collect(
        &self,
        schedule: &TimeSchedule,
        scheme: ThetaScheme,
        output_times: &[f64],
    ) -> Result<Vec<Snapshot>, ThermalError> {
        let mut out = Vec::new();
        self.solve_transient(schedule, scheme, output_times, |s| out.push(s.clone()))?;
        Ok(out)
    }
}

/// The states of element `e` (the default state where none were set).
fn element_states(
    states: Option<&[[InterfacePointState; 2]]>,
    e: usize,
) -> [InterfacePointState; 2] {
    states
        .and_then(|s| s.get(e).copied())
        .unwrap_or([InterfacePointState::default(); 2])
}

/// The conductances at the two points of element `e` of a P1 interface.
fn element_h2(
    law: &dyn ConductanceLaw,
    states: Option<&[[InterfacePointState; 2]]>,
    e: usize,
) -> [f64; 2] {
    let st = element_states(states, e);
    [law.conductance(&st[0]), law.conductance(&st[1])]
}

/// The conductances at the three pairs of element `e` of a P2 interface:
/// the law sees the corner states at the end pairs and their mean at the
/// mid pair.
fn element_h3(
    law: &dyn ConductanceLaw,
    states: Option<&[[InterfacePointState; 2]]>,
    e: usize,
) -> [f64; 3] {
    let st = element_states(states, e);
    let mid_state = InterfacePointState {
        gap: 0.5 * (st[0].gap + st[1].gap),
        pressure: 0.5 * (st[0].pressure + st[1].pressure),
        temperature: 0.5 * (st[0].temperature + st[1].temperature),
    };
    [
        law.conductance(&st[0]),
        law.conductance(&mid_state),
        law.conductance(&st[1]),
    ]
}

/// Conductances must be non-negative and finite.
fn check_h(interface: &str, element: usize, h: &[f64]) -> Result<(), ThermalError> {
    match h.iter().find(|v| !(**v >= 0.0 && v.is_finite())) {
        Some(&value) => Err(ThermalError::InvalidConductance {
            interface: interface.into(),
            element: Some(element),
            requirement: "non-negative and finite",
            value,
        }),
        None => Ok(()),
    }
}

fn check_finite(what: &str, value: f64) -> Result<(), ThermalError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(ThermalError::InvalidInitialTemperature {
            what: what.into(),
            value,
        })
    }
}

/// Runs `schedule` on an assembled system from its initial temperature.
pub fn run_transient<F: FnMut(&Snapshot)>(
    system: &ThermalSystem<'_>,
    schedule: &TimeSchedule,
    scheme: ThetaScheme,
    output_times: &[f64],
    on_output: F,
) -> Result<TransientSummary, ThermalError> {
    run_transient_while(system, schedule, scheme, output_times, on_output, || true)
}

/// As [`run_transient`], asking `keep_going` before every step: when it
/// says no, the run stops there (its summary's `end_time` tells how far it
/// got). For a consumer of the snapshots that may give up, e.g. a contact
/// solve running beside the heat conduction that failed.
pub fn run_transient_while<F: FnMut(&Snapshot), G: Fn() -> bool>(
    system: &ThermalSystem<'_>,
    schedule: &TimeSchedule,
    scheme: ThetaScheme,
    output_times: &[f64],
    on_output: F,
    keep_going: G,
) -> Result<TransientSummary, ThermalError> {
    run_transient_observed(
        system,
        schedule,
        scheme,
        output_times,
        on_output,
        |_, _| {},
        keep_going,
    )
}

/// As [`run_transient_while`], also calling `on_step(time, temperature)`
/// with the nodal temperatures at the start and after every step (a step
/// split at an output time counts as two), e.g. to record a temperature
/// history at a few points. After a step that ends at an output time,
/// `time` is that output time exactly, as the snapshot's, and the
/// temperatures are the snapshot's.
pub fn run_transient_observed<F, S, G>(
    system: &ThermalSystem<'_>,
    schedule: &TimeSchedule,
    scheme: ThetaScheme,
    output_times: &[f64],
    mut on_output: F,
    mut on_step: S,
    keep_going: G,
) -> Result<TransientSummary, ThermalError>
where
    F: FnMut(&Snapshot),
    S: FnMut(f64, &[f64]),
    G: Fn() -> bool,
{
    let initial = system
        .initial_temperature()
        .ok_or(ThermalError::NoInitialTemperature)?
        .to_vec();
    let (start, end) = (schedule.start(), schedule.end());
    let slack = 1e-9 * (end - start);
    let mut outs: Vec<f64> = output_times.to_vec();
    for &t in &outs {
        if !(t.is_finite() && t >= start - slack && t <= end + slack) {
            return Err(ThermalError::OutputTimeOutOfRange {
                time: t,
                start,
                end,
            });
        }
    }
    outs.sort_by(f64::total_cmp);
    outs.dedup();
    let mut stepper = system.stepper(initial, start)?;
    let mut next = 0;
    let mut max_res: f64 = 0.0;
    // emits the outputs reached; returns the last output time emitted
    let mut emit = |stepper: &crate::ThetaStepper<'_, '_>, next: &mut usize, tol: f64| {
        let mut at = None;
        while *next < outs.len() && outs[*next] <= stepper.time() + tol {
            // The clock sums the steps (1.0000000000000004 after fifty steps
            // of 0.02 s); within the tolerance the output is the requested
            // time, so it carries that time exactly.
            let mut s = stepper.snapshot();
            s.time = outs[*next];
            max_res = max_res.max(s.balance.relative_residual());
            on_output(&s);
            at = Some(outs[*next]);
            *next += 1;
        }
        at
    };
    let at = emit(&stepper, &mut next, slack);
    on_step(at.unwrap_or(stepper.time()), stepper.temperature());
    let steps = schedule.steps();
    let thetas: Vec<f64> = (0..steps.len())
        .map(|k| scheme.theta_for(k, steps))
        .collect();
    // the last step that uses each (Δt, θ): a factorisation no later step
    // uses is dropped (the segments of a schedule do not come back; kept,
    // they held memory for nothing, e.g. 1.1 GB of 506 198 nodes at order 2)
    let mut last_use: std::collections::BTreeMap<(u64, u64), usize> = Default::default();
    for (k, (dt, theta)) in steps.iter().zip(&thetas).enumerate() {
        last_use.insert((dt.to_bits(), theta.to_bits()), k);
    }
    for (k, &dt) in steps.iter().enumerate() {
        if !keep_going() {
            break;
        }
        let theta = thetas[k];
        stepper.retain_operators(|a, b| last_use.get(&(a, b)).is_some_and(|&j| j >= k));
        let tol = 1e-9 * dt;
        let step_end = stepper.time() + dt;
        let mut split = false;
        while next < outs.len() && outs[next] < step_end - tol {
            let sub = outs[next] - stepper.time();
            let stepped = sub > tol;
            if stepped {
                stepper.step(sub, theta)?;
                split = true;
            }
            let at = emit(&stepper, &mut next, tol);
            if stepped {
                on_step(at.unwrap_or(stepper.time()), stepper.temperature());
            }
        }
        // Unsplit steps keep their exact Δt (the factorisation key).
        let last = if split { step_end - stepper.time() } else { dt };
        stepper.step(last, theta)?;
        let at = emit(&stepper, &mut next, tol);
        on_step(at.unwrap_or(stepper.time()), stepper.temperature());
    }
    let stats: StepperStats = stepper.stats();
    Ok(TransientSummary {
        end_time: stepper.time(),
        steps: stats.steps,
        factorisations: stats.factorisations,
        max_balance_residual: max_res,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Goal: the step observer sees the start and every step (a step split
    /// at an output time as two), ends at the end of the schedule, and at
    /// an output time carries the output time and the snapshot's
    /// temperatures bit for bit.
    #[test]
    fn the_step_observer_sees_every_step_and_the_outputs_exactly() {
        let mesh = tecon_mesh::rectangle(0.0, 0.0, 0.1, 0.02, 8, 2).unwrap();
        let mut m = ThermalModel::new(&mesh);
        m.set_material_everywhere(Material::vessel_steel())
            .unwrap()
            .set_initial_default(20.0)
            .unwrap()
            .set_initial_node(0, 900.0)
            .unwrap()
            .add_edge_bc("right", EdgeBc::convection(50.0, 20.0))
            .unwrap();
        let system = m.assemble().unwrap();
        // 10 steps of 1 s; 2.5 splits the third, 4 ends the fourth
        let schedule = TimeSchedule::uniform(1.0, 10).unwrap();
        let outs = [2.5, 4.0];
        let mut snapshots = Vec::new();
        let mut seen: Vec<(f64, Vec<f64>)> = Vec::new();
        let summary = run_transient_observed(
            &system,
            &schedule,
            ThetaScheme::crank_nicolson(),
            &outs,
            |s| snapshots.push(s.clone()),
            |t, v| seen.push((t, v.to_vec())),
            || true,
        )
        .unwrap();
        assert_eq!(summary.steps, 11);
        assert_eq!(seen.len(), 12, "the start and 11 steps");
        assert_eq!(seen[0].0, 0.0);
        assert_eq!(seen[0].1, system.initial_temperature().unwrap());
        assert!((seen[11].0 - 10.0).abs() < 1e-12);
        assert!(seen.windows(2).all(|w| w[1].0 > w[0].0));
        for s in &snapshots {
            let (_, v) = seen
                .iter()
                .find(|(t, _)| *t == s.time)
                .expect("an output time among the steps");
            assert_eq!(v, &s.temperature);
        }
        assert_eq!(snapshots.iter().map(|s| s.time).collect::<Vec<_>>(), outs);
        // without the observer, the same outputs
        let plain = m
            .solve_transient_collect(&schedule, ThetaScheme::crank_nicolson(), &outs)
            .unwrap();
        for (a, b) in plain.iter().zip(&snapshots) {
            assert_eq!(a.temperature, b.temperature);
        }
    }

    /// Goal: the bounds are the extremes of the initial temperatures, the
    /// ambients and the prescribed temperatures; a heat flux in removes the
    /// upper one, a flux out the lower one; no initial temperature, none.
    #[test]
    fn temperature_bounds_follow_the_initial_field_ambients_and_fluxes() {
        let mesh = tecon_mesh::rectangle(0.0, 0.0, 1.0, 1.0, 2, 2).unwrap();
        let mut m = ThermalModel::new(&mesh);
        assert_eq!(m.temperature_bounds(), None);
        m.set_initial_default(50.0).unwrap();
        m.set_initial_node(0, 60.0).unwrap();
        m.add_edge_bc("left", EdgeBc::convection(10.0, 20.0))
            .unwrap();
        m.prescribe_node(1, 70.0).unwrap();
        assert_eq!(m.temperature_bounds(), Some((Some(20.0), Some(70.0))));
        let mut heated = m.clone();
        heated.add_edge_bc("top", EdgeBc::flux(5.0)).unwrap();
        assert_eq!(heated.temperature_bounds(), Some((Some(20.0), None)));
        m.add_edge_bc("top", EdgeBc::flux(-5.0)).unwrap();
        assert_eq!(m.temperature_bounds(), Some((None, Some(70.0))));
    }
}
