//! The static nonlinear solver: load increments, Newton iterations with the
//! consistent tangent, line search, contact-status convergence, ping-pong
//! guard, step cut-back, and an outer loop of augmented-Lagrangian
//! multiplier updates and frozen friction limits.
//!
//! Friction (default [`FrictionBound::Frozen`]): within one Newton pass the
//! Mohr–Coulomb limit of every point is frozen at the pressure of the
//! previous pass, so the pass minimises a convex, piecewise-quadratic energy
//! (bulk + penalty contact + Tresca friction). Its tangent is symmetric
//! (Cholesky) and the step is the exact minimiser along the Newton
//! direction (root of the directional derivative, kept bracketed). Passes
//! repeat, with the limits set to the new pressures, until they settle: the
//! fixed point is the Mohr–Coulomb solution. The coupled alternative
//! ([`FrictionBound::Coupled`]) is one Newton pass on the non-symmetric
//! tangent with backtracking on ‖R‖: the fallback for an outer loop that
//! stalls (sparse LU), and the tail of every outer loop once the frozen
//! passes' statuses settle (GMRES preconditioned with the frozen tangent;
//! [`SolverOptions::coupled_tail`]).
//!
//! Rhythm per increment (deal.II step-42 style): the predictor is the
//! first Newton iterate from the last converged state; an increment has
//! converged only when the residual is small, the correction is small
//! *and* no interface point changed status in the last iteration. History
//! states (friction slip) are committed only at converged increments.
//!
//! Files: [`options`] (loads, settings, reports), `assembly` (bulk and
//! interface element loops, residual), `increment` (load increments,
//! cut-back, outer multiplier / friction-limit passes), `newton` (one
//! Newton pass), `front` (opening-front prediction), `gmres` (the
//! coupled tail's non-symmetric steps), `line_search`,
//! `recovery` (stresses).

mod assembly;
mod coarse;
mod condensed;
mod front;
mod gmres;
mod increment;
mod line_search;
mod newton;
pub mod options;
mod recovery;
mod staging;
mod states;
mod tracker;

pub use options::{
    COARSE_LEVELS, COUPLED_TAIL_MAX_ITERATIONS, IncrementReport, InterfacePointResult, Loads,
    PASS_FORCING, SolverOptions,
};
pub use recovery::{
    QuadraticStresses, StressField, nodal_displacement, polar, quadratic_stresses, stresses,
    von_mises,
};
pub use staging::SolverState;
pub use states::PointStates;

use tecon_contact::ContactStatus;
use tecon_fem::{
    Assembler, AssemblerBuilder, BlockId, CsrMatrix, Dirichlet, FemError, LuSolver, Parallelism,
    PreparedDirichlet, RigidMode, UpdateStats, UpdatedCholesky, check_rigid_modes,
    plane_rigid_modes,
};

use crate::error::ElasticError;
use crate::joint::Joint;
use crate::material::{Analysis, Material};
use crate::model::ElasticModel;
use crate::rotation::Rotations;
use assembly::{Bulk, Bulk6};
use tecon_fem::edge3::Edge3;
use tecon_fem::triangle6::Triangle6;

/// The static nonlinear solver of one model, holding the committed state.
pub struct StaticSolver<'a> {
    model: &'a ElasticModel<'a>,
    /// Joint law of each interface, with the friction bound of the options.
    laws: Vec<Joint>,
    materials: Vec<Material>,
    options: SolverOptions,
    assembler: Assembler,
    bulk: BlockId,
    interface_blocks: Vec<BlockId>,
    k_bulk: CsrMatrix,
    dirichlet: Dirichlet,
    prepared: PreparedDirichlet,
    rotations: Rotations,
    modes: Vec<RigidMode>,
    modes_checked: bool,
    /// The statuses of the last converged state whose tangent was found to
    /// hold every body (see `StaticSolver::check_held`): a converged state
    /// whose statuses are no softer ([`no_softer`]) is held too, so it is
    /// not checked again (the check clones and constrains the tangent: 18 %
    /// of a two-way run when made at every converged pass).
    held_statuses: Option<Vec<PointStatus>>,
    cholesky: Option<UpdatedCholesky>,
    /// The bulk condensed onto the interface dofs (see `condensed`).
    condensed: Option<condensed::Condensed>,
    /// The last condensed pass's state, its interior not recovered yet (see
    /// `StaticSolver::settle_interior`).
    pending: Option<condensed::Pending>,
    /// Condensation was tried and the interior was not positive definite.
    condensed_failed: bool,
    /// Coarse-space iterations (see `coarse`) of the current increment, and
    /// of the solver's life (failed attempts included).
    coarse_in_increment: usize,
    coarse_total: usize,
    /// True while the coupled tail of an increment's outer loop runs (see
    /// `increment`): its non-symmetric steps are solved by GMRES.
    coupled_tail: bool,
    /// Whether the passes run condensed (decided once, on the first pass).
    condensed_choice: Option<bool>,
    /// Dofs of the interface elements' nodes: the only rows of the tangent
    /// that change within a contact solve.
    interface_dofs: Vec<usize>,
    /// The largest row sum of |K_bulk| over the rows that no interface
    /// touches (there the tangent is K_bulk): with the interface rows' sums
    /// of the tangent, a bound of ‖ |K_t| ‖ (see [`newton::floor_or_bound`]).
    rest_row_abs: f64,
    /// Tangents' storage for reuse (see [`StaticSolver::bulk_copy`]).
    spare_tangents: std::sync::Mutex<Vec<CsrMatrix>>,
    lu: Option<LuSolver>,
    /// The last failed increment stopped in its outer loop (frozen friction
    /// limits or multipliers still changing), not in a Newton pass.
    outer_stalled: bool,
    /// The forcing of the next Newton pass (0: exact; see
    /// [`SolverOptions::pass_forcing`]).
    pass_forcing: f64,
    /// The statuses at the end of the last pass, when an outer update
    /// lies between it and the next one (see
    /// [`StaticSolver::reopened_points`]).
    previous_end: Option<Vec<PointStatus>>,
    /// Floor of the outer loop's stopping tolerances, as a fraction of the
    /// largest contact pressure (see [`StaticSolver::set_outer_tolerance_floor`]).
    outer_floor: f64,
    /// The last ratio of two successive outer changes of an increment (0:
    /// none seen yet): the contraction of the outer loop, for the floor's
    /// error estimate when an increment has made one update only.
    outer_contraction: f64,
    u: Vec<f64>,
    /// `u` in the output gauge (see [`StaticSolver::displacement`]).
    gauged: Vec<f64>,
    /// Translations fixed by a minimal constraint, removed again from the
    /// output displacements.
    gauges: Vec<Gauge>,
    states: States,
    /// Per interface, the elements next to each element (front prediction).
    neighbours: Vec<Vec<Vec<usize>>>,
    /// Order-2 meshes: the curved element geometry and pressure edges.
    p2: Option<P2Data<'a>>,
    loads: Loads,
    notes: Vec<String>,
    points: Vec<InterfacePointResult>,
}

/// Share of the Newton residual tolerance that a corrected linear solve may
/// leave in the step: after a full step on unchanged statuses the next
/// residual is the solve's, so it stays 100× under the tolerance.
const LINEAR_SHARE: f64 = 0.01;

impl<'a> StaticSolver<'a> {
    /// Sets up the pattern, the bulk stiffness and the constraints.
    pub fn new(model: &'a ElasticModel<'a>, options: SolverOptions) -> Result<Self, ElasticError> {
        let mesh = model.mesh;
        let mut materials = model.element_materials()?;
        // staged construction: an inactive triangle has no stiffness and no
        // thermal load (E = 0), and its nodes are held (below)
        for (e, m) in materials.iter_mut().enumerate() {
            if !model.is_active(e) {
                m.youngs_modulus = 0.0;
            }
        }
        let inactive = model.inactive_nodes();
        staging::check_interfaces_active(model, &inactive)?;
        let n = model.n_dofs();
        let p2 = P2Data::new(model)?;
        let mut builder = AssemblerBuilder::new(n);
        let gps = model.analysis == Analysis::GeneralisedPlaneStrain;
        let eps_zz = model.eps_zz_dof().unwrap_or(0);
        let bulk_set = Bulk {
            nodes: mesh.nodes(),
            triangles: mesh.triangles(),
            materials: &materials,
            analysis: model.analysis,
            delta_t: &[],
            eps_zz,
        };
        let bulk = match (&p2, gps) {
            (None, true) => builder.add_elements::<7, _>(&bulk_set),
            (None, false) => builder.add_elements::<6, _>(&bulk_set),
            (Some(p), true) => {
                builder.add_elements::<13, _>(&p.bulk(&materials, model.analysis, &[], eps_zz))
            }
            (Some(p), false) => {
                builder.add_elements::<12, _>(&p.bulk(&materials, model.analysis, &[], eps_zz))
            }
        };
        let interface_blocks = model
            .interfaces
            .iter()
            .map(|i| {
                let dofs = |nodes: &[usize]| {
                    nodes
                        .iter()
                        .flat_map(|&v| [2 * v, 2 * v + 1])
                        .collect::<Vec<_>>()
                };
                if i.is_quadratic() {
                    builder.add_block(12, i.quadratic_nodes.iter().flat_map(|n| dofs(n)).collect())
                } else {
                    builder.add_block(8, i.nodes.iter().flat_map(|n| dofs(n)).collect())
                }
            })
            .collect();
        let mut interface_dofs: Vec<usize> = model
            .interfaces
            .iter()
            .flat_map(|i| {
                let nodes: Vec<usize> = if i.is_quadratic() {
                    i.quadratic_nodes.iter().flatten().copied().collect()
                } else {
                    i.nodes.iter().flatten().copied().collect()
                };
                nodes.into_iter().flat_map(|v| [2 * v, 2 * v + 1])
            })
            .collect();
        interface_dofs.sort_unstable();
        interface_dofs.dedup();
        let assembler = builder.build()?;
        let mut k_bulk = assembler.new_matrix();
        match (&p2, gps) {
            (None, true) => {
                assembler.add::<7, _>(bulk, &bulk_set, &mut k_bulk, None, Parallelism::Rayon)?
            }
            (None, false) => {
                assembler.add::<6, _>(bulk, &bulk_set, &mut k_bulk, None, Parallelism::Rayon)?
            }
            (Some(p), true) => {
                let set = p.bulk(&materials, model.analysis, &[], eps_zz);
                assembler.add::<13, _>(bulk, &set, &mut k_bulk, None, Parallelism::Rayon)?
            }
            (Some(p), false) => {
                let set = p.bulk(&materials, model.analysis, &[], eps_zz);
                assembler.add::<12, _>(bulk, &set, &mut k_bulk, None, Parallelism::Rayon)?
            }
        }
        let mut dirichlet = Dirichlet::new();
        for &(d, v) in &model.fixed {
            dirichlet.set(d, v);
        }
        let rotations = Rotations::new(&model.rotated, assembler.pattern());
        for &(node, _) in &model.rotated {
            if !dirichlet.contains(2 * node) {
                dirichlet.set(2 * node, 0.0);
            }
        }
        for &node in &inactive {
            // not in the system yet: both components held at zero (in the
            // rotated frame too: both zero either way)
            dirichlet.set(2 * node, 0.0);
            dirichlet.set(2 * node + 1, 0.0);
        }
        let prepared = dirichlet.prepare(assembler.pattern())?;
        let dm = model.dofmap();
        let mut modes = Vec::new();
        for body in mesh.bodies() {
            for mut m in plane_rigid_modes(&dm, &body.name, &body.nodes, mesh.nodes()) {
                rotations.rotate_sparse(&mut m.entries);
                modes.push(m);
            }
        }
        let states = model
            .interfaces
            .iter()
            .map(|i| PointStates::new(i.nodes.len(), i.points_per_element()))
            .collect();
        let neighbours = model
            .interfaces
            .iter()
            .map(|i| front::element_neighbours(&i.nodes))
            .collect();
        let laws = model
            .interfaces
            .iter()
            .map(|i| i.law.with_friction_bound(options.friction_bound))
            .collect();
        let rest_row_abs = newton::max_row_abs(
            &k_bulk,
            (0..n).filter(|i| interface_dofs.binary_search(i).is_err()),
        );
        Ok(StaticSolver {
            model,
            laws,
            materials,
            options,
            assembler,
            bulk,
            interface_blocks,
            k_bulk,
            dirichlet,
            prepared,
            rotations,
            modes,
            modes_checked: false,
            held_statuses: None,
            cholesky: None,
            condensed: None,
            pending: None,
            condensed_failed: false,
            coarse_in_increment: 0,
            coarse_total: 0,
            coupled_tail: false,
            condensed_choice: None,
            rest_row_abs,
            spare_tangents: std::sync::Mutex::new(Vec::new()),
            interface_dofs,
            lu: None,
            outer_stalled: false,
            pass_forcing: 0.0,
            previous_end: None,
            outer_floor: 0.0,
            outer_contraction: 0.0,
            u: vec![0.0; n],
            gauged: vec![0.0; n],
            gauges: Vec::new(),
            states,
            neighbours,
            p2,
            loads: Loads::zero(),
            notes: Vec::new(),
            points: Vec::new(),
        })
    }

    /// The symbolic analysis of the tangents' sparse Cholesky factor, with
    /// low-rank reuse. The tangents differ in the interface nodes' rows
    /// only (the bulk, its supports and the rotations of skew supports are
    /// the same at every iteration), so only those rows are searched for
    /// changes.
    fn tangent_cholesky(&self) -> Result<UpdatedCholesky, ElasticError> {
        Ok(
            UpdatedCholesky::analyse(self.assembler.pattern().clone(), MAX_UPDATE_RANK)?
                .with_candidate_rows(self.interface_dofs.clone()),
        )
    }

    /// Lets the outer loop of the next solves (the multiplier updates and
    /// the frozen friction limits) stop once its distance to the fixed
    /// point is below `floor` × the largest contact pressure, where that is
    /// looser than the options' tolerances (0, the default: the options'
    /// tolerances). The distance is estimated from the last change and the
    /// contraction ρ of the last two, change · ρ/(1 − ρ), and never taken
    /// below the change itself: at μ = 0.3 ρ ≈ 0.3, so the change decides;
    /// high friction contracts slowly and stops later. For solves whose
    /// answer is needed only to a known accuracy, such as the contact
    /// states between the output times of a two-way coupling, which feed
    /// only the interface conductance (and the friction history, which
    /// keeps errors of up to the floor); the last pass is still solved to
    /// the Newton tolerances.
    pub fn set_outer_tolerance_floor(&mut self, floor: f64) {
        self.outer_floor = floor.max(0.0);
    }

    /// Committed displacements (and ε_zz last in generalised plane strain),
    /// in the output gauge: when the solver fixed a free rigid translation
    /// by a minimal constraint (one node), that translation is removed
    /// again so that the area-weighted mean of the translated component
    /// over the constrained body is zero, and shifted equally on every
    /// body of the free mode. Jumps, strains and stresses do not change;
    /// the answer no longer depends on which node carried the constraint
    /// nor on the local deformation there.
    pub fn displacement(&self) -> &[f64] {
        &self.gauged
    }

    /// Committed displacements as solved, with the minimal constraint's
    /// node at zero (no output gauge).
    pub fn raw_displacement(&self) -> &[f64] {
        &self.u
    }

    /// Sets the output displacements from the committed ones (see
    /// [`StaticSolver::displacement`]).
    pub(super) fn update_gauge(&mut self) {
        self.gauged.clone_from(&self.u);
        let mesh = self.model.mesh;
        let x = mesh.nodes();
        for g in &self.gauges {
            let (mut area, mut sum) = (0.0, 0.0);
            for &e in &g.elements {
                if let Some(p2) = &self.p2 {
                    // ∫ u dA on the curved 6-node triangle
                    let t = p2.triangles[e];
                    for q in p2.geometry[e].points(crate::kernels::P2_RULE) {
                        area += q.weight;
                        sum += q.weight
                            * (0..6)
                                .map(|a| q.shape[a] * self.u[2 * t[a] + g.component])
                                .sum::<f64>();
                    }
                    continue;
                }
                let t = mesh.triangles()[e];
                let a = tecon_fem::triangle::TriangleGeometry::new(t.map(|v| x[v])).area;
                area += a;
                sum += a * t.iter().map(|&v| self.u[2 * v + g.component]).sum::<f64>() / 3.0;
            }
            if area > 0.0 {
                let mean = sum / area;
                for &v in &g.nodes {
                    self.gauged[2 * v + g.component] -= mean;
                }
            }
        }
    }

    /// Uniform axial strain ε_zz (generalised plane strain), else 0.
    pub fn eps_zz(&self) -> f64 {
        self.model.eps_zz_dof().map_or(0.0, |d| self.u[d])
    }

    /// Committed loads.
    pub fn loads(&self) -> &Loads {
        &self.loads
    }

    /// Notes about what the solver did on its own (minimal constraints added).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// How the symmetric tangents so far were solved (factorised, reused,
    /// corrected by a low-rank update): the sparse factor of the full
    /// passes and the dense interface factor of the condensed ones (a
    /// condensation counts as one factorisation).
    pub fn solve_stats(&self) -> UpdateStats {
        let mut s = self
            .cholesky
            .as_ref()
            .map(UpdatedCholesky::stats)
            .unwrap_or_default();
        if let Some((c, condensations)) = self.condensed_stats() {
            s.factorisations += c.factorisations + condensations;
            s.reused += c.reused;
            s.corrected += c.corrected;
        }
        s
    }

    /// Committed interface states, one [`PointStates`] per interface.
    pub fn interface_states(&self) -> &[PointStates] {
        &self.states
    }

    /// True if an interface has a Mohr–Coulomb joint.
    fn has_friction(&self) -> bool {
        self.laws.iter().any(|l| matches!(l, Joint::Frictional(_)))
    }

    /// True if an interface has a Mohr–Coulomb joint whose slip limit can
    /// be other than zero (a friction coefficient or a cohesion): only such
    /// joints need the outer updates of frozen friction limits. A
    /// frictionless one (μ = 0, c = 0) has none, so its passes are exact,
    /// as a frictionless joint's should be (see `SolverOptions::pass_forcing`).
    fn has_slip_limits(&self) -> bool {
        self.laws.iter().any(|l| match l {
            Joint::Frictional(j) => j.tan_phi() > 0.0 || j.cohesion() > 0.0,
            _ => false,
        })
    }

    /// No point of `committed` has a frozen slip limit above zero (no
    /// cohesion, and no friction pressure recorded yet): the frictional
    /// pass is the frictionless problem, as in the first increment from an
    /// unloaded state.
    fn without_slip_limits(&self, committed: &[PointStates]) -> bool {
        self.laws.iter().zip(committed).all(|(l, s)| match l {
            Joint::Frictional(j) => {
                j.cohesion() == 0.0
                    && (j.tan_phi() == 0.0
                        || s.as_slice().iter().all(|p| p.friction_pressure == 0.0))
            }
            _ => true,
        })
    }

    fn check_modes(&mut self, kt: &CsrMatrix) -> Result<(), ElasticError> {
        match check_rigid_modes(kt, &self.modes) {
            Ok(()) => {
                self.modes_checked = true;
                Ok(())
            }
            Err(FemError::Unconstrained {
                bodies,
                modes,
                description,
                energy,
            }) => {
                let translation = modes
                    .iter()
                    .all(|m| m == "x-translation" || m == "y-translation");
                let fixable = self.model.remove_free_translations && translation;
                if !fixable {
                    return Err(FemError::Unconstrained {
                        bodies,
                        modes,
                        description,
                        energy,
                    }
                    .into());
                }
                let c = usize::from(modes.iter().all(|m| m == "y-translation"));
                let body = self
                    .model
                    .mesh
                    .bodies()
                    .iter()
                    .find(|b| b.name == bodies[0]);
                let node = body.and_then(|b| {
                    b.nodes.iter().copied().find(|&n| {
                        !self.dirichlet.contains(2 * n + c) && !self.rotations.contains(n)
                    })
                });
                let Some(node) = node else {
                    return Err(FemError::Unconstrained {
                        bodies,
                        modes,
                        description,
                        energy,
                    }
                    .into());
                };
                self.dirichlet.set(2 * node + c, 0.0);
                self.prepared = self.dirichlet.prepare(self.assembler.pattern())?;
                // a condensation of the old constraints no longer holds,
                // and the used tangents kept for their storage were
                // constrained elsewhere
                self.condensed = None;
                if let Ok(mut v) = self.spare_tangents.lock() {
                    v.clear();
                }
                let all = self.model.mesh.bodies();
                let mut nodes: Vec<usize> = all
                    .iter()
                    .filter(|b| bodies.contains(&b.name))
                    .flat_map(|b| b.nodes.iter().copied())
                    .collect();
                nodes.sort_unstable();
                nodes.dedup();
                self.gauges.push(Gauge {
                    component: c,
                    elements: body.map(|b| b.elements.clone()).unwrap_or_default(),
                    nodes,
                });
                self.notes.push(format!(
                    "{description} was free: fixed u_{c} = 0 at {n} of body '{b}' (a minimal constraint); output displacements are then shifted so that the mean u_{c} of body '{b}' is zero",
                    n = self.model.mesh.node_label(node),
                    c = if c == 0 { "x" } else { "y" },
                    b = bodies[0]
                ));
                Ok(())
            }
            Err(e) => Err(e.into()),
        }
    }

    /// Solves `kt · x = rhs` in place; a low-rank corrected Cholesky solve
    /// may leave a residual (force) of `accept` (see [`LINEAR_SHARE`]).
    fn solve(
        &mut self,
        kt: &CsrMatrix,
        rhs: &mut [f64],
        symmetric: bool,
        accept: f64,
    ) -> Result<(), ElasticError> {
        // symbolic analyses are made once, on first use of each kind
        if symmetric {
            let c = match &mut self.cholesky {
                Some(c) => c,
                None => self.cholesky.insert(self.tangent_cholesky()?),
            };
            // a tangent that differs from the factorised one only where a
            // few interface points changed branch is solved by a low-rank
            // correction of the old factor
            if let Err(e) = c.solve_within(kt, rhs, accept) {
                // a tangent that lost positive definiteness mid-solve (an
                // interface that opened or slipped everywhere can leave a
                // body held by nothing): name the free body if there is one
                if let (tecon_fem::FemError::NotPositiveDefinite { .. }, Err(free)) =
                    (&e, check_rigid_modes(kt, &self.modes))
                {
                    return Err(free.into());
                }
                return Err(e.into());
            }
        } else {
            let l = match &mut self.lu {
                Some(l) => l,
                None => self.lu.insert(LuSolver::analyse(kt.pattern().clone())?),
            };
            l.factorise(kt)?;
            l.solve(rhs)?;
        }
        Ok(())
    }

    /// Element and nodal stresses of the committed state. On an order-2
    /// mesh the element value is the area mean over the integration points
    /// and the nodal value the mean of the elements' recovered (SPR, per
    /// region) values at the node; the per-point and per-region values are
    /// in [`StaticSolver::quadratic_stresses`].
    pub fn stresses(&self) -> StressField {
        match self.quadratic_stresses() {
            Some(q) => q.field(self.model.mesh),
            None => stresses(
                self.model,
                &self.materials,
                &self.u,
                self.eps_zz(),
                &self.loads.delta_t,
            ),
        }
    }

    /// Order-2 meshes: stresses at the integration points, recovered per
    /// region (SPR) and the Zienkiewicz–Zhu indicator of each element, for
    /// the committed state; `None` on an order-1 mesh.
    pub fn quadratic_stresses(&self) -> Option<QuadraticStresses> {
        let p2 = self.p2.as_ref()?;
        Some(quadratic_stresses(
            self.model,
            &p2.geometry,
            &self.materials,
            &self.u,
            self.eps_zz(),
            &self.loads.delta_t,
        ))
    }

    /// Per-point interface output of the last converged increment (status,
    /// traction and slip as the increment left them); before any increment,
    /// the unloaded state.
    pub fn interface_results(&self) -> Vec<InterfacePointResult> {
        if self.points.is_empty() {
            return self.point_results(&self.u, &self.states);
        }
        self.points.clone()
    }
}

/// What the solver keeps of an order-2 mesh: the 6-node triangles with
/// their (checked) curved geometry, and the pressure edges as 3-node edges.
struct P2Data<'m> {
    pub(super) triangles: &'m [[usize; 6]],
    pub(super) geometry: Vec<Triangle6>,
    /// Nodes (a, b, mid), the edge and the pressure (Pa at load factor 1).
    pub(super) pressure: Vec<([usize; 3], Edge3, f64)>,
}

impl<'m> P2Data<'m> {
    /// `None` on an order-1 mesh; errors name the element or edge whose
    /// geometry is rejected.
    fn new(model: &ElasticModel<'m>) -> Result<Option<Self>, ElasticError> {
        let mesh = model.mesh;
        let Some(triangles) = mesh.triangles6() else {
            return Ok(None);
        };
        let x = mesh.nodes();
        let geometry = triangles
            .iter()
            .enumerate()
            .map(|(e, t)| {
                Triangle6::new(t.map(|v| x[v])).map_err(|err| ElasticError::Input {
                    what: format!("6-node triangle {e} (nodes {t:?})"),
                    message: err.to_string(),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut pressure = Vec::with_capacity(model.pressure.len());
        for &([a, b], p) in &model.pressure {
            let what = || format!("pressure edge ({a}, {b})");
            let m = mesh
                .edge_mid_node(a, b)
                .ok_or_else(|| ElasticError::Input {
                    what: what(),
                    message: "the order-2 mesh has no mid node on this edge (not an element edge)"
                        .into(),
                })?;
            let edge = Edge3::new([x[a], x[b], x[m]]).map_err(|err| ElasticError::Input {
                what: what(),
                message: err.to_string(),
            })?;
            pressure.push(([a, b, m], edge, p));
        }
        Ok(Some(P2Data {
            triangles,
            geometry,
            pressure,
        }))
    }

    /// The bulk element set with temperature changes `delta_t` (empty, or
    /// six per element).
    fn bulk<'s>(
        &'s self,
        materials: &'s [Material],
        analysis: Analysis,
        delta_t: &'s [f64],
        eps_zz: usize,
    ) -> Bulk6<'s> {
        Bulk6 {
            geometry: &self.geometry,
            triangles: self.triangles,
            materials,
            analysis,
            delta_t,
            eps_zz,
        }
    }
}

/// A rigid translation fixed by a minimal constraint and removed from the
/// output: component, the triangles whose mean is made zero, the nodes
/// shifted.
struct Gauge {
    component: usize,
    elements: Vec<usize>,
    nodes: Vec<usize>,
}

/// Joint states of every interface of the model.
type States = Vec<PointStates>;

/// Two displacement components per node (the node count is not needed to
/// number an element's dofs).
const PLANE: tecon_fem::DofMap = tecon_fem::DofMap::new(0, 2);

/// Relative traction below which a point's status change does not hold up
/// convergence.
const STATUS_TRACTION_FLOOR: f64 = 1e-6;

/// Most changed dofs solved by a low-rank correction of the last Cholesky
/// factor before the tangent is factorised again (each new dof costs one
/// column of a multi-column solve). Chosen on the vessel, level 4 (34 816
/// triangles), whole run: rank 8 → 8.0 s, 24 → 6.9 s, 48 → 7.7 s (noisy
/// machine, ±20 %); 32 on the 99 144-triangle mesh gives 40.7 s.
const MAX_UPDATE_RANK: usize = 32;

/// Status of an interface point and its sliding direction: 0 when it does
/// not slide on a friction limit, +1 or −1 (the sign of the shear traction)
/// when it does — a slipping point, or an open one that slides on its
/// frozen friction limit (see `MohrCoulomb`'s open branch). A reversal of
/// the direction, or an open point that starts or stops sliding, changes
/// the tangent as much as a change of status.
type PointStatus = (ContactStatus, i8);

/// True when a state with the statuses `new` is held at least as firmly
/// as one with `held`, point by point: its tangent is no softer, so a body
/// held at `held` is held at `new` (a positive semidefinite addition cannot
/// free a mode). Per point, a closed sticking point carries normal and
/// shear stiffness, a closed slipping one normal stiffness only, an open
/// sliding one none; an open point that does not slide may still carry the
/// shear stiffness of its frozen friction limit, or none, so it matches
/// only itself or a closed sticking point.
pub(super) fn no_softer(new: &[PointStatus], held: &[PointStatus]) -> bool {
    use ContactStatus::{Open, Slip, Stick};
    new.len() == held.len()
        && new.iter().zip(held).all(|(n, h)| {
            n == h
                || n.0 == Stick
                || (n.0 == Slip && (h.0 == Slip || (h.0 == Open && h.1 != 0)))
                || (n.0 == Open && n.1 != 0 && h.0 == Open && h.1 != 0)
        })
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn count(s: &[PointStatus]) -> [usize; 3] {
    let mut c = [0; 3];
    for (st, _) in s {
        c[match st {
            ContactStatus::Open => 0,
            ContactStatus::Stick => 1,
            ContactStatus::Slip => 2,
        }] += 1;
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use ContactStatus::{Open, Slip, Stick};

    #[test]
    fn a_stiffer_status_pattern_is_no_softer_and_a_softer_one_is() {
        let held = [(Open, 1), (Slip, -1), (Stick, 0), (Open, 0)];
        assert!(no_softer(&held, &held));
        // every point at least as stiff: closed sticking beats anything,
        // closed slipping beats open sliding
        assert!(no_softer(
            &[(Slip, 1), (Slip, 1), (Stick, 0), (Open, 0)],
            &held
        ));
        assert!(no_softer(
            &[(Stick, 0), (Stick, 0), (Stick, 0), (Stick, 0)],
            &held
        ));
        // one point softer: a sticking point that slides or opens, a
        // slipping one that opens
        assert!(!no_softer(
            &[(Open, 1), (Slip, -1), (Slip, 1), (Open, 0)],
            &held
        ));
        assert!(!no_softer(
            &[(Open, 1), (Open, 1), (Stick, 0), (Open, 0)],
            &held
        ));
        // an open point that does not slide may carry shear stiffness: only
        // itself or a closed sticking point stands in for it
        assert!(!no_softer(
            &[(Open, 1), (Slip, -1), (Stick, 0), (Slip, 1)],
            &held
        ));
        assert!(!no_softer(
            &[(Open, 1), (Slip, -1), (Stick, 0), (Open, 1)],
            &held
        ));
        // patterns of other interfaces do not compare
        assert!(!no_softer(&held[..3], &held));
    }
}
