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
//! tangent (LU) with backtracking on ‖R‖.
//!
//! Rhythm per increment (deal.II step-42 style): the predictor is the
//! first Newton iterate from the last converged state; an increment has
//! converged only when the residual is small, the correction is small
//! *and* no interface point changed status in the last iteration. History
//! states (friction slip) are committed only at converged increments.

use nalgebra::{Vector2, Vector3};
use tecon_contact::{
    ContactStatus, ElementResponse, FrictionBound, InterfaceElement, JointState, Vector8,
};
use tecon_fem::triangle::TriangleGeometry;
use tecon_fem::{
    Assembler, AssemblerBuilder, BlockId, CsrMatrix, Dirichlet, Element, FemError, LocalSystem,
    LuSolver, Parallelism, PreparedDirichlet, RigidMode, UpdateStats, UpdatedCholesky,
    check_rigid_modes, plane_rigid_modes,
};

use crate::error::{ElasticError, IterationRecord};
use crate::joint::Joint;
use crate::kernels::{element_stress, gps_triangle, plane_triangle};
use crate::material::{Analysis, Material};
use crate::model::ElasticModel;
use crate::rotation::Rotations;

/// The loads of one state, all scaled by the solver's load path.
#[derive(Debug, Clone, PartialEq)]
pub struct Loads {
    /// Temperature change T − T_ref per element (K); empty means zero.
    pub delta_t: Vec<f64>,
    /// Factor on the model's pressures.
    pub pressure: f64,
    /// Factor on the model's prescribed displacements.
    pub displacement: f64,
    /// Factor on the model's body forces.
    pub body_force: f64,
}

impl Loads {
    /// No load.
    pub fn zero() -> Self {
        Loads {
            delta_t: Vec::new(),
            pressure: 0.0,
            displacement: 0.0,
            body_force: 0.0,
        }
    }

    /// Mechanical loads at factor 1 and no temperature change.
    pub fn mechanical() -> Self {
        Loads {
            pressure: 1.0,
            displacement: 1.0,
            body_force: 1.0,
            ..Self::zero()
        }
    }

    fn lerp(a: &Loads, b: &Loads, s: f64, n_el: usize) -> Loads {
        let dt = |l: &Loads, e: usize| l.delta_t.get(e).copied().unwrap_or(0.0);
        Loads {
            delta_t: if a.delta_t.is_empty() && b.delta_t.is_empty() {
                Vec::new()
            } else {
                (0..n_el)
                    .map(|e| dt(a, e) + s * (dt(b, e) - dt(a, e)))
                    .collect()
            },
            pressure: a.pressure + s * (b.pressure - a.pressure),
            displacement: a.displacement + s * (b.displacement - a.displacement),
            body_force: a.body_force + s * (b.body_force - a.body_force),
        }
    }
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    /// Converged when ‖R‖ ≤ this × reference force …
    pub residual_tolerance: f64,
    /// … and ‖Δu‖ ≤ this × ‖u‖ …
    pub correction_tolerance: f64,
    /// … and no status changed in the last iteration.
    pub max_iterations: usize,
    /// Increments per `advance` to start with.
    pub increments: usize,
    /// Smallest increment (as a fraction of the step) before giving up.
    pub min_increment: f64,
    /// A status pattern seen again two iterations later counts as ping-pong;
    /// after this many the increment is cut.
    pub max_ping_pong: usize,
    /// Augmented-Lagrangian outer loop: stop when the largest multiplier
    /// change is below this × the largest contact pressure (None: pure penalty).
    pub augmented_lagrangian: Option<f64>,
    /// Most outer updates (augmented-Lagrangian multipliers and frozen
    /// friction limits) per increment.
    pub max_augmentations: usize,
    /// How Mohr–Coulomb joints take the contact pressure into their slip
    /// limit. [`FrictionBound::Frozen`] (default): each Newton pass solves
    /// a Tresca problem (limit from the pressure of the previous pass) —
    /// convex, symmetric tangent (Cholesky), exact line search on the
    /// energy — and passes repeat until the limits settle, which gives the
    /// Mohr–Coulomb answer. [`FrictionBound::Coupled`]: one Newton pass on
    /// the coupled law with its non-symmetric tangent (LU) and a line search
    /// on ‖R‖.
    pub friction_bound: FrictionBound,
    /// Frozen friction limits: stop the passes when the largest change of a
    /// limit is below this × the largest contact pressure.
    pub friction_tolerance: f64,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            residual_tolerance: 1e-8,
            correction_tolerance: 1e-8,
            max_iterations: 30,
            increments: 1,
            min_increment: 1.0 / 1024.0,
            max_ping_pong: 4,
            augmented_lagrangian: None,
            max_augmentations: 30,
            friction_bound: FrictionBound::Frozen,
            friction_tolerance: 1e-4,
        }
    }
}

/// What one converged increment took.
#[derive(Debug, Clone, PartialEq)]
pub struct IncrementReport {
    /// Load fraction reached (within the `advance` call).
    pub fraction: f64,
    /// Newton iterations (summed over augmented-Lagrangian passes).
    pub iterations: usize,
    /// Most Newton iterations of one pass (each augmented-Lagrangian update
    /// starts a new pass from the converged state).
    pub max_pass_iterations: usize,
    /// Augmented-Lagrangian updates made.
    pub augmentations: usize,
    /// Iteration history of the last Newton pass.
    pub history: Vec<IterationRecord>,
    /// Failed attempts (and why) cut back before this increment converged.
    pub cutbacks: Vec<String>,
}

/// Output of one interface integration point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfacePointResult {
    /// Interface index in the model.
    pub interface: usize,
    /// Element index within the interface.
    pub element: usize,
    /// Point (0 or 1).
    pub point: usize,
    /// Position on the bottom face.
    pub position: [f64; 2],
    /// Jump [Δu_t, Δu_n] (m).
    pub jump: [f64; 2],
    /// Traction [τ, σ] (Pa), σ > 0 tension.
    pub traction: [f64; 2],
    /// Open / stick / slip.
    pub status: ContactStatus,
    /// Plastic slip g_s (m).
    pub slip: f64,
}

/// Element and nodal stresses (σ_xx, σ_yy, σ_xy, σ_zz).
#[derive(Debug, Clone, PartialEq)]
pub struct StressField {
    /// Per element.
    pub element: Vec<[f64; 4]>,
    /// Per node, area-weighted mean of the elements around it (nodes belong
    /// to one body, so nothing is averaged across an interface).
    pub nodal: Vec<[f64; 4]>,
}

struct Bulk<'a> {
    nodes: &'a [[f64; 2]],
    triangles: &'a [[usize; 3]],
    materials: &'a [Material],
    analysis: Analysis,
    delta_t: &'a [f64],
    eps_zz: usize,
}

impl Element<6> for Bulk<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 6] {
        PLANE.element_dofs(self.triangles[e])
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<6> {
        let g = TriangleGeometry::new(self.triangles[e].map(|v| self.nodes[v]));
        let m = &self.materials[e];
        let dt = self.delta_t.get(e).copied().unwrap_or(0.0);
        let (matrix, vector) = plane_triangle(
            &g,
            &self.analysis.d(m),
            self.analysis.in_plane_expansion(m) * dt,
        );
        LocalSystem { matrix, vector }
    }
}

impl Element<7> for Bulk<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 7] {
        let d: [usize; 6] = PLANE.element_dofs(self.triangles[e]);
        [d[0], d[1], d[2], d[3], d[4], d[5], self.eps_zz]
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<7> {
        let g = TriangleGeometry::new(self.triangles[e].map(|v| self.nodes[v]));
        let dt = self.delta_t.get(e).copied().unwrap_or(0.0);
        let (matrix, vector) = gps_triangle(&g, &self.materials[e], dt);
        LocalSystem { matrix, vector }
    }
}

struct InterfaceSet<'a> {
    nodes: &'a [[usize; 4]],
    elements: &'a [InterfaceElement],
    law: &'a Joint,
    u: &'a [f64],
    committed: &'a [[JointState; 2]],
}

impl InterfaceSet<'_> {
    fn local_u(&self, e: usize) -> Vector8 {
        let n = self.nodes[e];
        Vector8::from_fn(|i, _| self.u[2 * n[i / 2] + i % 2])
    }
}

impl Element<8> for InterfaceSet<'_> {
    fn n_elements(&self) -> usize {
        self.nodes.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 8] {
        PLANE.element_dofs(self.nodes[e])
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<8> {
        let r = self.elements[e].evaluate(self.law, &self.local_u(e), &self.committed[e]);
        LocalSystem {
            matrix: r.tangent,
            vector: r.force,
        }
    }
}

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
    cholesky: Option<UpdatedCholesky>,
    lu: Option<LuSolver>,
    u: Vec<f64>,
    states: Vec<Vec<[JointState; 2]>>,
    loads: Loads,
    notes: Vec<String>,
    points: Vec<InterfacePointResult>,
}

impl<'a> StaticSolver<'a> {
    /// Sets up the pattern, the bulk stiffness and the constraints.
    pub fn new(model: &'a ElasticModel<'a>, options: SolverOptions) -> Result<Self, ElasticError> {
        let mesh = model.mesh;
        let materials = model.element_materials()?;
        let n = model.n_dofs();
        let bulk_set = Bulk {
            nodes: mesh.nodes(),
            triangles: mesh.triangles(),
            materials: &materials,
            analysis: model.analysis,
            delta_t: &[],
            eps_zz: model.eps_zz_dof().unwrap_or(0),
        };
        let mut builder = AssemblerBuilder::new(n);
        let gps = model.analysis == Analysis::GeneralisedPlaneStrain;
        let bulk = if gps {
            builder.add_elements::<7, _>(&bulk_set)
        } else {
            builder.add_elements::<6, _>(&bulk_set)
        };
        let interface_blocks = model
            .interfaces
            .iter()
            .map(|i| {
                builder.add_block(
                    8,
                    i.nodes
                        .iter()
                        .flat_map(|n| n.iter().flat_map(|&v| [2 * v, 2 * v + 1]))
                        .collect(),
                )
            })
            .collect();
        let assembler = builder.build()?;
        let mut k_bulk = assembler.new_matrix();
        if gps {
            assembler.add::<7, _>(bulk, &bulk_set, &mut k_bulk, None, Parallelism::Rayon)?;
        } else {
            assembler.add::<6, _>(bulk, &bulk_set, &mut k_bulk, None, Parallelism::Rayon)?;
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
            .map(|i| vec![[JointState::default(); 2]; i.nodes.len()])
            .collect();
        let laws = model
            .interfaces
            .iter()
            .map(|i| match &i.law {
                Joint::Frictional(l) => {
                    Joint::Frictional(l.with_friction_bound(options.friction_bound))
                }
                other => other.clone(),
            })
            .collect();
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
            cholesky: None,
            lu: None,
            u: vec![0.0; n],
            states,
            loads: Loads::zero(),
            notes: Vec::new(),
            points: Vec::new(),
        })
    }

    /// Committed displacements (and ε_zz last in generalised plane strain).
    pub fn displacement(&self) -> &[f64] {
        &self.u
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
    /// corrected by a low-rank update).
    pub fn solve_stats(&self) -> UpdateStats {
        self.cholesky
            .as_ref()
            .map(UpdatedCholesky::stats)
            .unwrap_or_default()
    }

    /// Committed interface states.
    pub fn interface_states(&self) -> &[Vec<[JointState; 2]>] {
        &self.states
    }

    /// Advances from the committed loads to `target` in increments (cut back
    /// on failure), committing the state at each converged increment.
    pub fn advance(&mut self, target: &Loads) -> Result<Vec<IncrementReport>, ElasticError> {
        let n_el = self.model.mesh.n_triangles();
        if !target.delta_t.is_empty() && target.delta_t.len() != n_el {
            return Err(ElasticError::Input {
                what: "temperature change".into(),
                message: format!("{} values for {n_el} triangles", target.delta_t.len()),
            });
        }
        if let Some(e) = target.delta_t.iter().position(|t| !t.is_finite()) {
            return Err(ElasticError::Input {
                what: "temperature change".into(),
                message: format!("element {e} has a non-finite value"),
            });
        }
        let start = self.loads.clone();
        let mut s = 0.0;
        let mut ds = 1.0 / self.options.increments.max(1) as f64;
        let mut cutbacks = Vec::new();
        let mut reports = Vec::new();
        while s < 1.0 - 1e-14 {
            let s_try = (s + ds).min(1.0);
            let loads = Loads::lerp(&start, target, s_try, n_el);
            match self.increment(&loads) {
                Ok((u, states, start, mut report)) => {
                    // point output of the converged increment, evaluated from
                    // the states its last Newton pass started from
                    self.points = self.point_results(&u, &start);
                    self.u = u;
                    self.states = states;
                    self.loads = loads;
                    s = s_try;
                    report.cutbacks = std::mem::take(&mut cutbacks);
                    // an easy increment lets the next one grow back
                    if report.max_pass_iterations <= 4 && report.cutbacks.is_empty() {
                        ds = (2.0 * ds).min(1.0 / self.options.increments.max(1) as f64);
                    }
                    report.fraction = s;
                    reports.push(report);
                }
                Err(ElasticError::NotConverged {
                    reason, history, ..
                }) => {
                    let tail: Vec<String> = history
                        .iter()
                        .rev()
                        .take(4)
                        .rev()
                        .map(|h| h.to_string())
                        .collect();
                    cutbacks.push(format!(
                        "increment {ds:.3e} at fraction {s:.3}: {reason}; last iterations: {}",
                        tail.join(" | ")
                    ));
                    ds *= 0.5;
                    if ds < self.options.min_increment {
                        return Err(ElasticError::NotConverged {
                            fraction: s_try,
                            increment: 2.0 * ds,
                            reason,
                            history,
                        });
                    }
                }
                Err(e) => return Err(e),
            }
        }
        if reports.is_empty() {
            // target equal to the committed loads: nothing to do
            self.loads = target.clone();
        }
        Ok(reports)
    }

    fn external_force(&self, loads: &Loads) -> Result<Vec<f64>, ElasticError> {
        let mesh = self.model.mesh;
        let mut f = vec![0.0; self.model.n_dofs()];
        if !loads.delta_t.is_empty() {
            let set = Bulk {
                nodes: mesh.nodes(),
                triangles: mesh.triangles(),
                materials: &self.materials,
                analysis: self.model.analysis,
                delta_t: &loads.delta_t,
                eps_zz: self.model.eps_zz_dof().unwrap_or(0),
            };
            if self.model.analysis == Analysis::GeneralisedPlaneStrain {
                self.assembler.add_vector::<7, _>(self.bulk, &set, &mut f)?;
            } else {
                self.assembler.add_vector::<6, _>(self.bulk, &set, &mut f)?;
            }
        }
        let x = mesh.nodes();
        for &([a, b], p) in &self.model.pressure {
            let (dx, dy) = (x[b][0] - x[a][0], x[b][1] - x[a][1]);
            // traction −p n, n L = (dy, −dx); half to each node
            let fx = -0.5 * p * dy * loads.pressure;
            let fy = 0.5 * p * dx * loads.pressure;
            for v in [a, b] {
                f[2 * v] += fx;
                f[2 * v + 1] += fy;
            }
        }
        if loads.body_force != 0.0 {
            for (e, t) in mesh.triangles().iter().enumerate() {
                let bf = self.model.body_force[mesh.element_regions()[e]];
                if bf == [0.0; 2] {
                    continue;
                }
                let area = TriangleGeometry::new(t.map(|v| x[v])).area;
                for &v in t {
                    f[2 * v] += bf[0] * area / 3.0 * loads.body_force;
                    f[2 * v + 1] += bf[1] * area / 3.0 * loads.body_force;
                }
            }
        }
        Ok(f)
    }

    /// Tangent and internal force at `u` from `committed` states; also the statuses.
    fn tangent_and_force(
        &self,
        u: &[f64],
        committed: &[Vec<[JointState; 2]>],
        with_matrix: bool,
    ) -> Result<(Option<CsrMatrix>, Vec<f64>), ElasticError> {
        let mut f_int = vec![0.0; u.len()];
        self.k_bulk.mul_vec(u, &mut f_int);
        let mut kt = with_matrix.then(|| self.k_bulk.clone());
        self.add_interfaces(u, committed, kt.as_mut(), &mut f_int)?;
        Ok((kt, f_int))
    }

    /// Adds the interface forces at `u` (and their tangent, if asked) to
    /// `f_int` (and `kt`).
    fn add_interfaces(
        &self,
        u: &[f64],
        committed: &[Vec<[JointState; 2]>],
        mut kt: Option<&mut CsrMatrix>,
        f_int: &mut [f64],
    ) -> Result<(), ElasticError> {
        for (k, itf) in self.model.interfaces.iter().enumerate() {
            let set = InterfaceSet {
                nodes: &itf.nodes,
                elements: &itf.elements,
                law: &self.laws[k],
                u,
                committed: &committed[k],
            };
            match kt.as_deref_mut() {
                Some(m) => self.assembler.add::<8, _>(
                    self.interface_blocks[k],
                    &set,
                    m,
                    Some(&mut *f_int),
                    Parallelism::Rayon,
                )?,
                None => self
                    .assembler
                    .add_vector::<8, _>(self.interface_blocks[k], &set, f_int)?,
            }
        }
        Ok(())
    }

    /// Element responses of every interface at `u` from `committed` states.
    fn responses(
        &self,
        u: &[f64],
        committed: &[Vec<[JointState; 2]>],
    ) -> Vec<Vec<ElementResponse<JointState>>> {
        self.model
            .interfaces
            .iter()
            .zip(&self.laws)
            .zip(committed)
            .map(|((itf, law), states)| {
                itf.elements
                    .iter()
                    .zip(&itf.nodes)
                    .zip(states)
                    .map(|((el, n), st)| {
                        el.evaluate(law, &Vector8::from_fn(|i, _| u[2 * n[i / 2] + i % 2]), st)
                    })
                    .collect()
            })
            .collect()
    }

    /// Status (with the slip direction) and traction magnitude |τ| + |σ| of
    /// every interface point.
    fn statuses(&self, u: &[f64], committed: &[Vec<[JointState; 2]>]) -> Vec<(PointStatus, f64)> {
        self.responses(u, committed)
            .iter()
            .flatten()
            .flat_map(|r| {
                r.points.map(|p| {
                    let backward = p.status == ContactStatus::Slip && p.traction.x < 0.0;
                    (
                        (p.status, backward),
                        p.traction.x.abs() + p.traction.y.abs(),
                    )
                })
            })
            .collect()
    }

    fn trial_states(&self, u: &[f64], committed: &[Vec<[JointState; 2]>]) -> States {
        self.responses(u, committed)
            .iter()
            .map(|v| {
                v.iter()
                    .map(|r| [r.points[0].state, r.points[1].state])
                    .collect()
            })
            .collect()
    }

    /// Residual in the rotated frame with constrained entries zeroed, and its norm.
    fn residual(&self, f_ext: &[f64], f_int: &[f64]) -> Vec<f64> {
        let mut r: Vec<f64> = f_ext.iter().zip(f_int).map(|(a, b)| a - b).collect();
        self.rotations.rotate_vector(&mut r);
        self.prepared.zero(&mut r);
        r
    }

    /// One increment: converged displacements, the trial (new committed)
    /// states, the states the last Newton pass started from (the old
    /// committed ones with updated multipliers), and a report.
    #[allow(clippy::type_complexity)]
    fn increment(
        &mut self,
        loads: &Loads,
    ) -> Result<(Vec<f64>, States, States, IncrementReport), ElasticError> {
        let f_ext = self.external_force(loads)?;
        let mut committed = self.states.clone();
        let mut total_iterations = 0;
        let mut max_pass = 0;
        let mut augmentations = 0;
        let mut u = self.u.clone();
        // Newton passes; with the augmented Lagrangian, each pass is followed
        // by a multiplier update until the multipliers settle. `start` is the
        // state set the accepted pass started from.
        let (start, history) = loop {
            let (u_new, history) = self.newton(&f_ext, loads, &committed, u.clone())?;
            total_iterations += history.len();
            max_pass = max_pass.max(history.len());
            u = u_new;
            let al = self.options.augmented_lagrangian;
            let frozen =
                self.options.friction_bound == FrictionBound::Frozen && self.has_friction();
            if al.is_none() && !frozen {
                break (committed, history);
            }
            let start = committed.clone();
            // Outer updates from the converged jumps: Uzawa update of the
            // normal multipliers, and the frozen friction limits set to the
            // pressure of this pass.
            let mut max_change: f64 = 0.0;
            let mut max_friction_change: f64 = 0.0;
            let mut max_p: f64 = 0.0;
            for (((itf, law), states), responses) in self
                .model
                .interfaces
                .iter()
                .zip(&self.laws)
                .zip(committed.iter_mut())
                .zip(self.responses(&u, &start))
            {
                for (((el, n), st), r) in itf
                    .elements
                    .iter()
                    .zip(&itf.nodes)
                    .zip(states.iter_mut())
                    .zip(&responses)
                {
                    let ue = Vector8::from_fn(|i, _| u[2 * n[i / 2] + i % 2]);
                    for p in &r.points {
                        max_p = max_p.max(-p.traction.y);
                    }
                    if frozen {
                        let (new, change) = el.update_friction(law, &ue, st);
                        *st = new;
                        max_friction_change = max_friction_change.max(change);
                    }
                    if al.is_some() {
                        let (new, change) = el.augment(law, &ue, st);
                        *st = new;
                        max_change = max_change.max(change);
                    }
                }
            }
            let scale = max_p.max(f64::MIN_POSITIVE);
            let al_done = al.is_none_or(|tol| max_change <= tol * scale);
            let friction_done = max_friction_change <= self.options.friction_tolerance * scale;
            if al_done && friction_done {
                // The last update changed almost nothing: the converged u
                // stands, with the multipliers and limits it was computed with.
                break (start, history);
            }
            if augmentations >= self.options.max_augmentations {
                return Err(ElasticError::NotConverged {
                    fraction: 0.0,
                    increment: 0.0,
                    reason: format!(
                        "after {augmentations} outer updates the multipliers still change by {max_change:.3e} Pa and the friction limits by {max_friction_change:.3e} Pa (largest contact pressure {max_p:.3e} Pa)"
                    ),
                    history,
                });
            }
            augmentations += 1;
        };
        let states = self.trial_states(&u, &start);
        Ok((
            u,
            states,
            start,
            IncrementReport {
                fraction: 0.0,
                iterations: total_iterations,
                max_pass_iterations: max_pass,
                augmentations,
                cutbacks: Vec::new(),
                history,
            },
        ))
    }

    fn newton(
        &mut self,
        f_ext: &[f64],
        loads: &Loads,
        committed: &[Vec<[JointState; 2]>],
        mut u: Vec<f64>,
    ) -> Result<(Vec<f64>, Vec<IterationRecord>), ElasticError> {
        // Prescribed values at this load level (global frame; rotated dofs are 0).
        for (d, v) in self.dirichlet.iter() {
            u[d] = v * loads.displacement;
        }
        let mut history: Vec<IterationRecord> = Vec::new();
        let mut prev: Option<Vec<(PointStatus, f64)>> = None;
        let mut prev2: Option<Vec<PointStatus>> = None;
        let mut ping_pong = 0;
        let mut short_steps = 0;
        // The force scale of this increment: the largest external or internal
        // force norm seen so far (the internal force alone can vanish, e.g.
        // when bodies separate and move rigidly).
        let mut reference = norm(f_ext).max(f64::MIN_POSITIVE);
        let opts = self.options;
        for it in 0..opts.max_iterations {
            let (kt, f_int) = self.tangent_and_force(&u, committed, true)?;
            let mut kt = kt.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
            let status = self.statuses(&u, committed);
            let status_t = status.clone();
            let r = self.residual(f_ext, &f_int);
            reference = reference.max(norm(&f_int));
            let rel = norm(&r) / reference;
            // A status change counts only where the point carries traction
            // before or after it: points at zero load (e.g. far from a local
            // thermal load) flip between touching and open at round-off level.
            let t_max = status.iter().map(|s| s.1).fold(0.0, f64::max);
            let changed = match &prev {
                Some(p) => p
                    .iter()
                    .zip(&status)
                    .filter(|(a, b)| a.0 != b.0 && a.1.max(b.1) > STATUS_TRACTION_FLOOR * t_max)
                    .count(),
                None => status.len(),
            };
            let status: Vec<PointStatus> = status.iter().map(|s| s.0).collect();
            if prev2.as_ref().is_some_and(|p2| *p2 == status) && changed > 0 {
                ping_pong += 1;
            }
            let counts = count(&status);
            let last_correction = history.last().map_or(f64::INFINITY, |h| h.correction);
            // After a full step with no status change the linearisation was
            // exact (the problem is piecewise linear), so the residual alone
            // measures the error; otherwise the correction must be small too.
            let full_step = history.last().is_some_and(|h| h.step == 1.0);
            let converged = it > 0
                && rel <= opts.residual_tolerance
                && changed == 0
                && (last_correction <= opts.correction_tolerance
                    || rel <= opts.residual_tolerance * 1e-3
                    || full_step);
            history.push(IterationRecord {
                iteration: it,
                residual: rel,
                correction: 0.0,
                step: 0.0,
                status: counts,
                changed,
            });
            if converged || (rel == 0.0 && changed == 0) {
                return Ok((u, history));
            }
            if ping_pong > opts.max_ping_pong {
                return Err(ElasticError::NotConverged {
                    fraction: 0.0,
                    increment: 0.0,
                    reason: format!("contact status ping-pong ({ping_pong} repeats)"),
                    history,
                });
            }
            // Tangent in the rotated frame, homogeneous constraints on the correction.
            self.rotations.rotate_matrix(&mut kt);
            let mut du = r.clone();
            self.prepared.apply_scaled(&mut kt, &mut du, 0.0);
            if !self.modes_checked {
                self.check_modes(&kt)?;
                if !self.modes_checked {
                    // a minimal constraint was added: start over
                    return self.newton(f_ext, loads, committed, u);
                }
            }
            let symmetric = counts[2] == 0 || opts.friction_bound == FrictionBound::Frozen;
            self.solve(&kt, &mut du, symmetric)?;
            let du_rotated = du.clone();
            self.rotations.unrotate_vector(&mut du);
            let step = if symmetric {
                self.energy_line_search(f_ext, committed, &u, &du, &du_rotated, &r)?
            } else {
                self.residual_line_search(f_ext, committed, &u, &du, &r)?
            };
            // Newton that only creeps (the line search keeps cutting while no
            // status changes) will not converge: give the increment back early
            // so it can be cut. Short steps that move a stick/slip or contact
            // front by a point or two are progress.
            short_steps = if step < 0.2 && changed == 0 {
                short_steps + 1
            } else {
                0
            };
            if short_steps >= 4 {
                return Err(ElasticError::NotConverged {
                    fraction: 0.0,
                    increment: 0.0,
                    reason: "the line search keeps cutting the Newton step (stagnation)".into(),
                    history,
                });
            }
            for (a, b) in u.iter_mut().zip(&du) {
                *a += step * b;
            }
            let unorm = norm(&u).max(f64::MIN_POSITIVE);
            if let Some(h) = history.last_mut() {
                h.correction = step * norm(&du) / unorm;
                h.step = step;
            }
            prev2 = prev
                .take()
                .map(|p: Vec<(PointStatus, f64)>| p.iter().map(|s| s.0).collect());
            prev = Some(status_t);
        }
        Err(ElasticError::NotConverged {
            fraction: 0.0,
            increment: 0.0,
            reason: format!("no convergence in {} iterations", opts.max_iterations),
            history,
        })
    }

    /// Step along `du` to the minimum of the (convex) incremental energy:
    /// the root of `g(α) = −R(u + α du)·du`, which increases with `α`. The
    /// full step is taken when it does not overshoot; otherwise a few
    /// Illinois (false-position) steps find the root. `du_rotated` is `du`
    /// in the frame of the residual `r`.
    fn energy_line_search(
        &self,
        f_ext: &[f64],
        committed: &[Vec<[JointState; 2]>],
        u: &[f64],
        du: &[f64],
        du_rotated: &[f64],
        r: &[f64],
    ) -> Result<f64, ElasticError> {
        // the bulk is linear: K (u + α du) = K u + α K du
        let mut ku = vec![0.0; u.len()];
        let mut kdu = vec![0.0; u.len()];
        self.k_bulk.mul_vec(u, &mut ku);
        self.k_bulk.mul_vec(du, &mut kdu);
        let g = |alpha: f64| -> Result<f64, ElasticError> {
            let trial: Vec<f64> = u.iter().zip(du).map(|(a, b)| a + alpha * b).collect();
            let mut fi: Vec<f64> = ku.iter().zip(&kdu).map(|(a, b)| a + alpha * b).collect();
            self.add_interfaces(&trial, committed, None, &mut fi)?;
            let rt = self.residual(f_ext, &fi);
            Ok(-dot(&rt, du_rotated))
        };
        let g0 = -dot(r, du_rotated);
        if g0.is_nan() || g0 >= 0.0 {
            // not a descent direction (round-off at convergence): full step
            return Ok(1.0);
        }
        let g1 = g(1.0)?;
        if g1 <= 0.05 * g0.abs() {
            return Ok(1.0);
        }
        // Root of g in (0, 1), g(0) < 0 < g(1), kept bracketed: false
        // position, with a bisection whenever one end has stayed put twice
        // (g is piecewise linear with kinks of very different slopes, where
        // false position alone creeps). If the bracket gets tight first, the
        // right end is taken: just past a kink, so the point that changed
        // branch there starts the next iteration on its new branch.
        let (mut a, mut ga, mut b, mut gb) = (0.0, g0, 1.0, g1);
        let mut stuck = 0i32;
        for _ in 0..60 {
            let fp = a - ga * (b - a) / (gb - ga);
            let x = if stuck.abs() >= 2 || !(fp > a && fp < b) {
                stuck = 0;
                0.5 * (a + b)
            } else {
                fp
            };
            let gx = g(x)?;
            if gx.abs() <= 0.05 * g0.abs() {
                return Ok(x);
            }
            if gx < 0.0 {
                (a, ga) = (x, gx);
                stuck = if stuck < 0 { stuck - 1 } else { -1 };
            } else {
                (b, gb) = (x, gx);
                stuck = if stuck > 0 { stuck + 1 } else { 1 };
            }
            if b - a <= 1e-3 * b {
                break;
            }
        }
        Ok(b)
    }

    /// Backtracking on ‖R‖ (for the non-symmetric coupled friction law):
    /// halve the step until the residual falls, keeping the best of five.
    fn residual_line_search(
        &self,
        f_ext: &[f64],
        committed: &[Vec<[JointState; 2]>],
        u: &[f64],
        du: &[f64],
        r: &[f64],
    ) -> Result<f64, ElasticError> {
        let r0 = norm(r);
        let mut step = 1.0;
        let mut best = (f64::INFINITY, 1.0);
        for _ in 0..5 {
            let trial: Vec<f64> = u.iter().zip(du).map(|(a, b)| a + step * b).collect();
            let (_, fi) = self.tangent_and_force(&trial, committed, false)?;
            let rt = norm(&self.residual(f_ext, &fi));
            if rt < best.0 {
                best = (rt, step);
            }
            if rt <= (1.0 - 1e-4 * step) * r0 || r0 == 0.0 {
                break;
            }
            step *= 0.5;
        }
        Ok(if best.0.is_finite() { best.1 } else { 1.0 })
    }

    /// True if an interface has a Mohr–Coulomb joint.
    fn has_friction(&self) -> bool {
        self.laws.iter().any(|l| matches!(l, Joint::Frictional(_)))
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
                self.notes.push(format!(
                    "{description} was free: fixed u_{} = 0 at node {node} of body '{}' (a minimal constraint)",
                    if c == 0 { "x" } else { "y" },
                    bodies[0]
                ));
                Ok(())
            }
            Err(e) => Err(e.into()),
        }
    }

    fn solve(
        &mut self,
        kt: &CsrMatrix,
        rhs: &mut [f64],
        symmetric: bool,
    ) -> Result<(), ElasticError> {
        // symbolic analyses are made once, on first use of each kind
        if symmetric {
            let c = match &mut self.cholesky {
                Some(c) => c,
                None => self.cholesky.insert(UpdatedCholesky::analyse(
                    kt.pattern().clone(),
                    MAX_UPDATE_RANK,
                )?),
            };
            // a tangent that differs from the factorised one only where a
            // few interface points changed branch is solved by a low-rank
            // correction of the old factor
            c.solve(kt, rhs)?;
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

    /// Element and nodal stresses of the committed state.
    pub fn stresses(&self) -> StressField {
        stresses(
            self.model,
            &self.materials,
            &self.u,
            self.eps_zz(),
            &self.loads.delta_t,
        )
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
    fn point_results(
        &self,
        u: &[f64],
        committed: &[Vec<[JointState; 2]>],
    ) -> Vec<InterfacePointResult> {
        let x = self.model.mesh.nodes();
        let mut out = Vec::new();
        for (k, (itf, responses)) in self
            .model
            .interfaces
            .iter()
            .zip(self.responses(u, committed))
            .enumerate()
        {
            for (e, ((el, n), r)) in itf
                .elements
                .iter()
                .zip(&itf.nodes)
                .zip(&responses)
                .enumerate()
            {
                for (q, p) in r.points.iter().enumerate() {
                    let s = p.zeta / el.geometry().length() + 0.5;
                    let pos = [
                        x[n[0]][0] + s * (x[n[1]][0] - x[n[0]][0]),
                        x[n[0]][1] + s * (x[n[1]][1] - x[n[0]][1]),
                    ];
                    out.push(InterfacePointResult {
                        interface: k,
                        element: e,
                        point: q,
                        position: pos,
                        jump: [p.jump.x, p.jump.y],
                        traction: [p.traction.x, p.traction.y],
                        status: p.status,
                        slip: p.slip,
                    });
                }
            }
        }
        out
    }
}

type States = Vec<Vec<[JointState; 2]>>;

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

/// Status of an interface point and, when it slips, whether it slips
/// backwards (negative shear traction): a reversal of the slip direction
/// changes the tangent as much as a change of status.
type PointStatus = (ContactStatus, bool);

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

/// Stresses (σ_xx, σ_yy, σ_xy, σ_zz) per element and per node for
/// displacements `u`, ε_zz and element temperature changes.
pub fn stresses(
    model: &ElasticModel<'_>,
    materials: &[Material],
    u: &[f64],
    eps_zz: f64,
    delta_t: &[f64],
) -> StressField {
    let mesh = model.mesh;
    let x = mesh.nodes();
    let mut element = Vec::with_capacity(mesh.n_triangles());
    let mut acc = vec![[0.0; 5]; mesh.n_nodes()];
    for (e, t) in mesh.triangles().iter().enumerate() {
        let g = TriangleGeometry::new(t.map(|v| x[v]));
        let mut ue = nalgebra::SVector::<f64, 6>::zeros();
        for (a, &v) in t.iter().enumerate() {
            ue[2 * a] = u[2 * v];
            ue[2 * a + 1] = u[2 * v + 1];
        }
        let strain: Vector3<f64> = g.strain_matrix() * ue;
        let s = element_stress(
            model.analysis,
            &materials[e],
            strain,
            eps_zz,
            delta_t.get(e).copied().unwrap_or(0.0),
        );
        for &v in t {
            for k in 0..4 {
                acc[v][k] += g.area * s[k];
            }
            acc[v][4] += g.area;
        }
        element.push(s);
    }
    let nodal = acc
        .iter()
        .map(|a| [a[0] / a[4], a[1] / a[4], a[2] / a[4], a[3] / a[4]])
        .collect();
    StressField { element, nodal }
}

/// Polar components (σ_rr, σ_θθ, σ_rθ) of (σ_xx, σ_yy, σ_xy) at point `p` about `centre`.
pub fn polar(s: [f64; 4], p: [f64; 2], centre: [f64; 2]) -> [f64; 3] {
    let th = (p[1] - centre[1]).atan2(p[0] - centre[0]);
    let (sn, c) = th.sin_cos();
    let (sx, sy, t) = (s[0], s[1], s[2]);
    [
        sx * c * c + sy * sn * sn + 2.0 * t * sn * c,
        sx * sn * sn + sy * c * c - 2.0 * t * sn * c,
        (sy - sx) * sn * c + t * (c * c - sn * sn),
    ]
}

/// Von Mises equivalent stress of (σ_xx, σ_yy, σ_xy, σ_zz).
pub fn von_mises(s: [f64; 4]) -> f64 {
    let (a, b, c, t) = (s[0], s[1], s[3], s[2]);
    (0.5 * ((a - b).powi(2) + (b - c).powi(2) + (c - a).powi(2)) + 3.0 * t * t).sqrt()
}

/// Displacement of node `i` as a vector.
pub fn nodal_displacement(u: &[f64], i: usize) -> Vector2<f64> {
    Vector2::new(u[2 * i], u[2 * i + 1])
}
