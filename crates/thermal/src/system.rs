//! The assembled spatial operator: conductivity K (conduction, convection
//! and interfaces), capacity C, load F, prescribed temperatures — assembled
//! once, combined per time step by the stepper.

use std::sync::Arc;

use rayon::prelude::*;
use tecon_fem::interface::{InterfaceGeometry, InterfaceQuadrature};
use tecon_fem::{
    Assembler, BlockId, CholeskySolver, CsrMatrix, Dirichlet, DofMap, FemError, Parallelism,
    PreparedDirichlet, RigidMode, check_rigid_modes, scalar_mode,
};
use tecon_mesh::Mesh;

use crate::error::ThermalError;
use crate::kernels::{
    CapacityElements, ConductionElements, ConvectionEdges, InterfaceElements, triangle_geometry,
};
use crate::kernels6::{
    Capacity6Elements, Conduction6Elements, Convection3Edges, Interface3Elements,
    convective_weights3,
};
use crate::output::{BodyBalance, HeatBalance, InterfaceFlux, InterfaceResult, Snapshot};
use crate::stepper::ThetaStepper;
use tecon_fem::interface3::Interface3Geometry;
use tecon_fem::quadrature::TriangleRule;
use tecon_fem::triangle6::Triangle6;

/// One row of the unconstrained C and K at a prescribed-temperature dof
/// (for the reaction in the heat balance).
#[derive(Debug, Clone)]
pub(crate) struct ConstrainedRow {
    pub dof: usize,
    pub cols: Vec<usize>,
    pub c: Vec<f64>,
    pub k: Vec<f64>,
}

/// Flows into each body accumulated by a run (or rates of a steady state).
#[derive(Debug, Clone, Default)]
pub(crate) struct BodyFlows {
    pub convection: Vec<f64>,
    pub flux: Vec<f64>,
    pub prescribed: Vec<f64>,
    pub interface: Vec<f64>,
    pub gross: Vec<f64>,
}

impl BodyFlows {
    pub fn new(n_bodies: usize) -> Self {
        BodyFlows {
            convection: vec![0.0; n_bodies],
            flux: vec![0.0; n_bodies],
            prescribed: vec![0.0; n_bodies],
            interface: vec![0.0; n_bodies],
            gross: vec![0.0; n_bodies],
        }
    }
}

/// The quadratic (P2) parts of a system: element geometry and the 3-pair
/// interface elements (the P1 lists are then empty).
#[derive(Debug)]
pub(crate) struct P2Parts<'m> {
    pub triangles: &'m [[usize; 6]],
    pub geometry: Vec<Triangle6>,
    pub interfaces: Interface3Elements,
}

/// What the model hands over for a P2 mesh.
pub(crate) struct P2Input<'m> {
    pub triangles: &'m [[usize; 6]],
    pub geometry: Vec<Triangle6>,
    pub convection: Convection3Edges,
    pub interfaces: Interface3Elements,
}

/// Range of one named interface inside the flattened interface elements.
#[derive(Debug, Clone)]
pub(crate) struct InterfaceRange {
    pub name: String,
    pub range: std::ops::Range<usize>,
}

/// The assembled thermal system of a [`crate::ThermalModel`].
///
/// Holds the matrices `K` (conduction, convective edges, interface
/// elements) and `C` (capacity) on one sparsity pattern, the load `F`
/// (convective ambient and prescribed fluxes), the prescribed
/// temperatures, and what the heat balance and the output need.
#[derive(Debug)]
pub struct ThermalSystem<'m> {
    pub(crate) mesh: &'m Mesh,
    /// The revision of the model it was assembled from (see
    /// [`crate::ThermalModel::reassemble`]).
    pub(crate) revision: u64,
    /// K without the interface elements (conduction and convection), to
    /// re-assemble the interfaces alone; kept only when an interface's
    /// conductance depends on its state (one K more in memory).
    pub(crate) k_bulk: Option<CsrMatrix>,
    /// The interface elements' block of the assembler.
    pub(crate) interface_block: BlockId,
    pub(crate) element_conductivity: Vec<f64>,
    pub(crate) assembler: Assembler,
    pub(crate) k: CsrMatrix,
    pub(crate) c: CsrMatrix,
    pub(crate) load: Vec<f64>,
    pub(crate) dirichlet: Dirichlet,
    pub(crate) prepared: PreparedDirichlet,
    pub(crate) constrained: Vec<ConstrainedRow>,
    pub(crate) capacity_weights: Vec<f64>,
    /// Column sums of the convective matrix and convective load per node,
    /// `(node, Σ_e hL/2, Σ_e hT∞L/2)`.
    pub(crate) convective_weights: Vec<(usize, f64, f64)>,
    /// Row sums of K as the operator sees them: the convective column
    /// sums (conduction and interface rows sum to zero in exact arithmetic).
    pub(crate) row_sums: Vec<f64>,
    /// `Σ_i w_i`.
    pub(crate) total_capacity: f64,
    /// Prescribed-flux load per node, `(node, Σ_e q_in L/2)`.
    pub(crate) flux_nodes: Vec<(usize, f64)>,
    /// `Σ_e q_in L`.
    pub(crate) flux_load: f64,
    pub(crate) interface_elements: InterfaceElements,
    pub(crate) interface_ranges: Vec<InterfaceRange>,
    pub(crate) modes: Vec<RigidMode>,
    pub(crate) initial: Option<Vec<f64>>,
    /// The initial nodal field as given, before the prescribed
    /// temperatures override it (the state that is free of thermal strain).
    pub(crate) initial_given: Option<Vec<f64>>,
    pub(crate) region_initial: Option<Vec<f64>>,
    pub(crate) p2: Option<P2Parts<'m>>,
}

/// Everything the model hands to [`ThermalSystem::build`].
pub(crate) struct SystemInput<'m> {
    pub mesh: &'m Mesh,
    pub conductivity: Vec<f64>,
    pub rho_c: Vec<f64>,
    pub capacity: crate::CapacityKind,
    pub convection: ConvectionEdges,
    /// (node, q_in L/2) contributions.
    pub flux_loads: Vec<(usize, f64)>,
    pub dirichlet: Dirichlet,
    pub interfaces: InterfaceElements,
    pub interface_ranges: Vec<InterfaceRange>,
    pub initial: Option<(Vec<f64>, Vec<f64>)>,
    /// `Some` for a P2 mesh (`convection` and `interfaces` are then empty).
    pub p2: Option<P2Input<'m>>,
    /// The model's revision.
    pub revision: u64,
    /// Keep K without the interfaces ([`ThermalSystem::k_bulk`]).
    pub keep_bulk: bool,
}

impl<'m> ThermalSystem<'m> {
    pub(crate) fn build(input: SystemInput<'m>) -> Result<Self, ThermalError> {
        let mesh = input.mesh;
        let n = mesh.n_nodes();
        let nodes = mesh.nodes();
        let triangles = mesh.triangles();
        let mut load = vec![0.0; n];
        let mut builder = tecon_fem::AssemblerBuilder::new(n);
        let (assembler, k_bulk, k, c, p2, interface_block) = match input.p2 {
            None => {
                let cond = ConductionElements {
                    nodes,
                    triangles,
                    conductivity: &input.conductivity,
                };
                let cap = CapacityElements {
                    nodes,
                    triangles,
                    rho_c: &input.rho_c,
                    kind: input.capacity,
                };
                let b_tri = builder.add_elements(&cond);
                let b_conv = builder.add_elements(&input.convection);
                let b_int = builder.add_elements(&input.interfaces);
                let assembler = builder.build()?;
                let mut k = assembler.new_matrix();
                let mut c = assembler.new_matrix();
                assembler.add(b_tri, &cond, &mut k, None, Parallelism::Rayon)?;
                assembler.add(
                    b_conv,
                    &input.convection,
                    &mut k,
                    Some(&mut load),
                    Parallelism::Rayon,
                )?;
                let k_bulk = input.keep_bulk.then(|| k.clone());
                assembler.add(b_int, &input.interfaces, &mut k, None, Parallelism::Rayon)?;
                assembler.add(b_tri, &cap, &mut c, None, Parallelism::Rayon)?;
                (assembler, k_bulk, k, c, None, b_int)
            }
            Some(p2) => {
                let cond = Conduction6Elements {
                    geometry: &p2.geometry,
                    triangles: p2.triangles,
                    conductivity: &input.conductivity,
                };
                let cap = Capacity6Elements {
                    geometry: &p2.geometry,
                    triangles: p2.triangles,
                    rho_c: &input.rho_c,
                    kind: input.capacity,
                };
                let b_tri = builder.add_elements(&cond);
                let b_conv = builder.add_elements(&p2.convection);
                let b_int = builder.add_elements(&p2.interfaces);
                let assembler = builder.build()?;
                let mut k = assembler.new_matrix();
                let mut c = assembler.new_matrix();
                assembler.add(b_tri, &cond, &mut k, None, Parallelism::Rayon)?;
                assembler.add(
                    b_conv,
                    &p2.convection,
                    &mut k,
                    Some(&mut load),
                    Parallelism::Rayon,
                )?;
                let k_bulk = input.keep_bulk.then(|| k.clone());
                assembler.add(b_int, &p2.interfaces, &mut k, None, Parallelism::Rayon)?;
                assembler.add(b_tri, &cap, &mut c, None, Parallelism::Rayon)?;
                (assembler, k_bulk, k, c, Some(p2), b_int)
            }
        };
        let mut flux_load = 0.0;
        let mut flux_node = vec![0.0; n];
        for &(node, f) in &input.flux_loads {
            load[node] += f;
            flux_node[node] += f;
            flux_load += f;
        }
        let flux_nodes = flux_node
            .iter()
            .enumerate()
            .filter(|(_, f)| **f != 0.0)
            .map(|(i, &f)| (i, f))
            .collect();
        let mut conv_w = vec![0.0; n];
        let mut conv_f = vec![0.0; n];
        let cv = &input.convection;
        for e in 0..cv.edges.len() {
            let w = 0.5 * cv.h[e] * cv.length[e];
            for a in cv.edges[e] {
                conv_w[a] += w;
                conv_f[a] += w * cv.ambient[e];
            }
        }
        if let Some(p2) = &p2 {
            // Column sums of each 3-node edge's ∫ h N Nᵀ ds (same rule as K).
            let cv = &p2.convection;
            for e in 0..cv.edges.len() {
                let w = convective_weights3(&cv.geometry[e], cv.h[e]);
                for (&a, wa) in cv.edges[e].iter().zip(w) {
                    conv_w[a] += wa;
                    conv_f[a] += wa * cv.ambient[e];
                }
            }
        }
        let row_sums = conv_w.clone();
        let convective_weights = conv_w
            .iter()
            .zip(&conv_f)
            .enumerate()
            .filter(|(_, (w, _))| **w != 0.0)
            .map(|(i, (&w, &f))| (i, w, f))
            .collect();
        let ones = vec![1.0; n];
        let mut capacity_weights = vec![0.0; n];
        c.mul_vec(&ones, &mut capacity_weights);
        let prepared = input.dirichlet.prepare(assembler.pattern())?;
        let p = assembler.pattern();
        let constrained = input
            .dirichlet
            .iter()
            .map(|(dof, _)| {
                let r = p.indptr()[dof]..p.indptr()[dof + 1];
                ConstrainedRow {
                    dof,
                    cols: p.indices()[r.clone()].to_vec(),
                    c: c.values()[r.clone()].to_vec(),
                    k: k.values()[r].to_vec(),
                }
            })
            .collect();
        let dofmap = DofMap::new(n, 1);
        let modes = mesh
            .bodies()
            .iter()
            .map(|b| scalar_mode(&dofmap, &b.name, &b.nodes, "uniform temperature"))
            .collect();
        let (initial, initial_given, region_initial) = match input.initial {
            Some((given, reg)) => {
                // Prescribed temperatures override the initial field at t = 0
                // (the stepper starts there); the field as given stays the
                // stress-free state
                let mut t0 = given.clone();
                for (dof, v) in input.dirichlet.iter() {
                    t0[dof] = v;
                }
                (Some(t0), Some(given), Some(reg))
            }
            None => (None, None, None),
        };
        let total_capacity: f64 = capacity_weights.iter().sum();
        Ok(ThermalSystem {
            mesh,
            revision: input.revision,
            k_bulk,
            interface_block,
            element_conductivity: input.conductivity,
            assembler,
            k,
            c,
            load,
            dirichlet: input.dirichlet,
            prepared,
            constrained,
            capacity_weights,
            convective_weights,
            flux_load,
            flux_nodes,
            row_sums,
            total_capacity,
            interface_elements: input.interfaces,
            interface_ranges: input.interface_ranges,
            modes,
            initial,
            initial_given,
            region_initial,
            p2: p2.map(|p| P2Parts {
                triangles: p.triangles,
                geometry: p.geometry,
                interfaces: p.interfaces,
            }),
        })
    }

    /// The same system with new interface conductances (h at the points
    /// of each P1 element, or of each 3-pair P2 element, in the system's
    /// order): K is `k_bulk` (this system's K without its interfaces) with
    /// the interface elements added again, everything else kept. The result
    /// equals a full assembly with those conductances bit for bit (the same
    /// sums in the same order).
    pub(crate) fn with_interface_conductances(
        mut self,
        k_bulk: CsrMatrix,
        h1: Vec<[f64; 2]>,
        h3: Vec<[f64; 3]>,
    ) -> Result<Self, ThermalError> {
        self.k = k_bulk;
        match &mut self.p2 {
            None => {
                self.interface_elements.h_c = h1;
                self.assembler.add(
                    self.interface_block,
                    &self.interface_elements,
                    &mut self.k,
                    None,
                    Parallelism::Rayon,
                )?;
            }
            Some(p2) => {
                p2.interfaces.h_c = h3;
                self.assembler.add(
                    self.interface_block,
                    &p2.interfaces,
                    &mut self.k,
                    None,
                    Parallelism::Rayon,
                )?;
            }
        }
        // the prescribed rows keep their K values for the heat balance
        let p = self.assembler.pattern();
        for row in &mut self.constrained {
            let r = p.indptr()[row.dof]..p.indptr()[row.dof + 1];
            row.k = self.k.values()[r].to_vec();
        }
        Ok(self)
    }

    /// Element order of the system: 1 (linear) or 2 (6-node triangles).
    pub fn order(&self) -> usize {
        if self.p2.is_some() { 2 } else { 1 }
    }

    /// Number of nodal unknowns.
    pub fn n_nodes(&self) -> usize {
        self.mesh.n_nodes()
    }

    /// The mesh.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    /// Conductivity matrix K (conduction + convective edges + interfaces),
    /// without the prescribed temperatures applied.
    pub fn conductivity_matrix(&self) -> &CsrMatrix {
        &self.k
    }

    /// Capacity matrix C (consistent or lumped), on the same pattern as K.
    pub fn capacity_matrix(&self) -> &CsrMatrix {
        &self.c
    }

    /// Load vector F (convective `hT∞L/2` and prescribed-flux `q L/2` terms).
    pub fn load(&self) -> &[f64] {
        &self.load
    }

    /// The prescribed temperatures (dof = node).
    pub fn prescribed(&self) -> &Dirichlet {
        &self.dirichlet
    }

    /// The assembler (pattern and element→slot maps).
    pub fn assembler(&self) -> &Assembler {
        &self.assembler
    }

    /// Initial nodal temperatures (prescribed values imposed), if the model
    /// has an initial temperature.
    pub fn initial_temperature(&self) -> Option<&[f64]> {
        self.initial.as_deref()
    }

    /// Reference temperature of each element for the thermal strain
    /// `α (T_e − T_ref,e)`: the element mean of the initial nodal field as
    /// given, so that the initial state is exactly free of thermal strain.
    /// A prescribed temperature that differs from the initial field is a
    /// load applied at t = 0⁺, not part of the stress-free state: with it
    /// in the reference, the elements along a held boundary were strained
    /// too little (a shrink fit heated from a held bore lost 3–14 % of its
    /// contact pressure on linear triangles).
    pub fn reference_temperature(&self) -> Option<Vec<f64>> {
        self.initial_given.as_ref().map(|t| self.element_means(t))
    }

    /// The initial temperature of each element's region (the piecewise
    /// constant field before the border rule), e.g. 1132 °C for every weld
    /// element. An alternative reference for the thermal strain.
    pub fn region_initial_temperature(&self) -> Option<&[f64]> {
        self.region_initial.as_deref()
    }

    /// Capacity weights `w = C·1` (the stored heat is `Σ w_i T_i`).
    pub fn capacity_weights(&self) -> &[f64] {
        &self.capacity_weights
    }

    /// A θ-method stepper starting from `initial` at time `t0`.
    pub fn stepper(
        &self,
        initial: Vec<f64>,
        t0: f64,
    ) -> Result<ThetaStepper<'_, 'm>, ThermalError> {
        ThetaStepper::new(self, initial, t0)
    }

    /// Solves the steady problem `K T = F` with the prescribed temperatures.
    ///
    /// Errors with [`ThermalError::SingularSteady`] naming the body (or the
    /// bodies joined by interfaces) that has neither a prescribed
    /// temperature nor convection.
    pub fn solve_steady(&self) -> Result<Snapshot, ThermalError> {
        let mut a = self.k.clone();
        let mut rhs = self.load.clone();
        self.prepared.apply(&mut a, &mut rhs);
        check_rigid_modes(&a, &self.modes).map_err(|e| match e {
            FemError::Unconstrained {
                description,
                bodies,
                ..
            } => ThermalError::SingularSteady {
                description,
                bodies,
            },
            other => ThermalError::Fem(other),
        })?;
        let mut solver = CholeskySolver::analyse(Arc::clone(self.assembler.pattern()))?;
        solver.factorise(&a)?;
        solver.solve(&mut rhs)?;
        let t = rhs;
        // Steady balance (rates): 0 = convection + flux + reactions.
        let mut kt = vec![0.0; t.len()];
        self.k.mul_vec(&t, &mut kt);
        let reactions: Vec<f64> = self
            .constrained
            .iter()
            .map(|r| kt[r.dof] - self.load[r.dof])
            .collect();
        let (convection_in, conv_gross) = self.convection_in_rate(&t);
        let mut flows = BodyFlows::new(self.mesh.bodies().len());
        self.add_body_flows(&mut flows, &t, 1.0);
        for (row, r) in self.constrained.iter().zip(&reactions) {
            let b = self.mesh.node_bodies()[row.dof];
            flows.prescribed[b] += r;
            flows.gross[b] += r.abs();
        }
        let balance = HeatBalance {
            stored_change: 0.0,
            convection_in,
            flux_in: self.flux_load,
            prescribed_in: reactions.iter().sum(),
            residual: 0.0,
            scale: conv_gross + self.flux_gross() + reactions.iter().map(|r| r.abs()).sum::<f64>(),
        }
        .close();
        Ok(self.snapshot(0.0, 0, t, balance, &flows, None))
    }

    /// Convective heat gain rate `−Σ_e ∫ h (T − T∞) ds` for nodal field `t`,
    /// and its gross value `Σ_i |per-node gain|`.
    pub(crate) fn convection_in_rate(&self, t: &[f64]) -> (f64, f64) {
        let (mut net, mut gross) = (0.0, 0.0);
        for &(i, w, f) in &self.convective_weights {
            let g = f - w * t[i];
            net += g;
            gross += g.abs();
        }
        (net, gross)
    }

    /// Adds `scale ×` (convective, flux and interface inflow rates of field
    /// `t`) to the per-body flows (prescribed-temperature reactions are
    /// added by the caller).
    pub(crate) fn add_body_flows(&self, flows: &mut BodyFlows, t: &[f64], scale: f64) {
        let nb = self.mesh.node_bodies();
        for &(i, w, f) in &self.convective_weights {
            let g = scale * (f - w * t[i]);
            flows.convection[nb[i]] += g;
            flows.gross[nb[i]] += g.abs();
        }
        for &(i, f) in &self.flux_nodes {
            flows.flux[nb[i]] += scale * f;
            flows.gross[nb[i]] += (scale * f).abs();
        }
        let ie = &self.interface_elements;
        for e in 0..ie.nodes.len() {
            let n = ie.nodes[e];
            let q = scale * interface_flux(&ie.geometry[e], ie.rule[e], ie.h_c[e], n, t).heat_rate;
            // q flows from the top body (nodes 3, 4) into the bottom body (1, 2).
            flows.interface[nb[n[0]]] += q;
            flows.interface[nb[n[3]]] -= q;
            flows.gross[nb[n[0]]] += q.abs();
            flows.gross[nb[n[3]]] += q.abs();
        }
        if let Some(p2) = &self.p2 {
            let ie = &p2.interfaces;
            for e in 0..ie.nodes.len() {
                let n = ie.nodes[e];
                let q =
                    scale * interface3_flux(&ie.geometry[e], ie.rule[e], ie.h_c[e], n, t).heat_rate;
                flows.interface[nb[n[0]]] += q;
                flows.interface[nb[n[3]]] -= q;
                flows.gross[nb[n[0]]] += q.abs();
                flows.gross[nb[n[3]]] += q.abs();
            }
        }
    }

    /// Per-body balances from the accumulated flows and the stored change
    /// `Σ_{i ∈ body} w_i (T_i − T_i⁰)` (`t0 = None` for a steady state).
    pub(crate) fn body_balances(
        &self,
        t: &[f64],
        t0: Option<&[f64]>,
        flows: &BodyFlows,
    ) -> Vec<BodyBalance> {
        let w = &self.capacity_weights;
        self.mesh
            .bodies()
            .iter()
            .enumerate()
            .map(|(b, body)| {
                let (stored, gross_stored) = match t0 {
                    Some(t0) => body.nodes.iter().fold((0.0, 0.0), |(s, g), &i| {
                        let d = w[i] * (t[i] - t0[i]);
                        (s + d, g + d.abs())
                    }),
                    None => (0.0, 0.0),
                };
                let inflow =
                    flows.convection[b] + flows.flux[b] + flows.prescribed[b] + flows.interface[b];
                BodyBalance {
                    body: body.name.clone(),
                    stored_change: stored,
                    convection_in: flows.convection[b],
                    flux_in: flows.flux[b],
                    prescribed_in: flows.prescribed[b],
                    interface_in: flows.interface[b],
                    residual: stored - inflow,
                    scale: gross_stored.max(flows.gross[b]),
                }
            })
            .collect()
    }

    /// `Σ_i |prescribed-flux load at node i|`.
    pub(crate) fn flux_gross(&self) -> f64 {
        self.flux_nodes.iter().map(|(_, f)| f.abs()).sum()
    }

    /// Element means of a nodal field (`∫T dA / A` on 6-node triangles).
    pub fn element_means(&self, t: &[f64]) -> Vec<f64> {
        if let Some(p2) = &self.p2 {
            return p2
                .triangles
                .par_iter()
                .zip(p2.geometry.par_iter())
                .map(|(tri, g)| {
                    let v = tri.map(|a| t[a]);
                    let (mut s, mut area) = (0.0, 0.0);
                    for q in g.points(TriangleRule::Degree2) {
                        s += q.weight * q.interpolate(&v);
                        area += q.weight;
                    }
                    s / area
                })
                .collect();
        }
        self.mesh
            .triangles()
            .par_iter()
            .map(|tri| (t[tri[0]] + t[tri[1]] + t[tri[2]]) / 3.0)
            .collect()
    }

    /// Builds the output of nodal field `t` at `time`; `t0` is the initial
    /// field of a transient run (`None` for a steady state).
    pub(crate) fn snapshot(
        &self,
        time: f64,
        step: usize,
        t: Vec<f64>,
        balance: HeatBalance,
        flows: &BodyFlows,
        t0: Option<&[f64]>,
    ) -> Snapshot {
        let nodes = self.mesh.nodes();
        let tris = self.mesh.triangles();
        let (gradient, flux): (Vec<[f64; 2]>, Vec<[f64; 2]>) = match &self.p2 {
            Some(p2) => p2
                .triangles
                .par_iter()
                .zip(p2.geometry.par_iter())
                .zip(self.element_conductivity.par_iter())
                .map(|((tri, g), &k)| {
                    let q = g.point([1.0 / 3.0, 1.0 / 3.0], 0.0);
                    let mut grad = [0.0; 2];
                    for a in 0..6 {
                        grad[0] += q.dndx[a] * t[tri[a]];
                        grad[1] += q.dndy[a] * t[tri[a]];
                    }
                    (grad, [-k * grad[0], -k * grad[1]])
                })
                .unzip(),
            None => tris
                .par_iter()
                .zip(self.element_conductivity.par_iter())
                .map(|(tri, &k)| {
                    let g = triangle_geometry(nodes, *tri);
                    let mut grad = [0.0; 2];
                    for a in 0..3 {
                        grad[0] += g.dndx[a] * t[tri[a]];
                        grad[1] += g.dndy[a] * t[tri[a]];
                    }
                    (grad, [-k * grad[0], -k * grad[1]])
                })
                .unzip(),
        };
        let ie = &self.interface_elements;
        let interfaces = self
            .interface_ranges
            .iter()
            .map(|r| {
                let elements: Vec<InterfaceFlux> = match &self.p2 {
                    Some(p2) => {
                        let i3 = &p2.interfaces;
                        r.range
                            .clone()
                            .map(|e| {
                                interface3_flux(
                                    &i3.geometry[e],
                                    i3.rule[e],
                                    i3.h_c[e],
                                    i3.nodes[e],
                                    &t,
                                )
                            })
                            .collect()
                    }
                    None => r
                        .range
                        .clone()
                        .map(|e| {
                            interface_flux(&ie.geometry[e], ie.rule[e], ie.h_c[e], ie.nodes[e], &t)
                        })
                        .collect(),
                };
                let heat_rate = elements.iter().map(|f| f.heat_rate).sum();
                InterfaceResult {
                    name: r.name.clone(),
                    elements,
                    heat_rate,
                }
            })
            .collect();
        let bodies = self.body_balances(&t, t0, flows);
        Snapshot {
            time,
            step,
            bodies,
            element_temperature: self.element_means(&t),
            temperature: t,
            gradient,
            flux,
            interfaces,
            balance,
        }
    }
}

fn interface_flux(
    g: &InterfaceGeometry,
    rule: InterfaceQuadrature,
    h_c: [f64; 2],
    nodes: [usize; 4],
    t: &[f64],
) -> InterfaceFlux {
    let tv = nalgebra::Vector4::new(t[nodes[0]], t[nodes[1]], t[nodes[2]], t[nodes[3]]);
    let pts = g.points(rule);
    let mut jump = [0.0; 2];
    let mut flux = [0.0; 2];
    let mut heat_rate = 0.0;
    for (p, pt) in pts.iter().enumerate() {
        jump[p] = pt.jump_operator().dot(&tv);
        flux[p] = h_c[p] * jump[p];
        heat_rate += pt.weight * flux[p];
    }
    InterfaceFlux {
        jump,
        flux,
        heat_rate,
        mid: None,
    }
}

/// Jumps and fluxes at the three node pairs of a 3-pair interface element
/// (`h_c` of the point that belongs to each pair: points are ordered along
/// the face, pair (1,4), mid pair, pair (2,3)), and the heat rate
/// `Σ_p w_p h_c,p ⟦T⟧_p` integrated with the element's rule.
fn interface3_flux(
    g: &Interface3Geometry,
    rule: InterfaceQuadrature,
    h_c: [f64; 3],
    nodes: [usize; 6],
    t: &[f64],
) -> InterfaceFlux {
    let tv = tecon_fem::interface3::Vector6::from_fn(|i, _| t[nodes[i]]);
    let heat_rate = g
        .points(rule)
        .iter()
        .zip(h_c)
        .map(|(p, h)| p.weight * h * p.jump_operator().dot(&tv))
        .sum();
    let pair = |bottom: usize, top: usize| t[nodes[top]] - t[nodes[bottom]];
    let (j1, j2, j5) = (pair(0, 3), pair(1, 2), pair(4, 5));
    InterfaceFlux {
        jump: [j1, j2],
        flux: [h_c[0] * j1, h_c[2] * j2],
        heat_rate,
        mid: Some([j5, h_c[1] * j5]),
    }
}
