//! The one analysis driver behind `tecon run` and `tecon vessel`.
//!
//! A front door builds a [`Setup`] — the mesh, the thermal model and its
//! procedure, the elastic model, the solver options and the load stages —
//! and hands it to [`run`], which reads like the physics:
//!
//! ```text
//! heat conduction (transient, steady or the initial field held)
//!   → for every stage, for every output time of the stage:
//!       thermoelastic contact solve from the previous converged state
//!   → Outcome (states, statistics, notes, timings) → writers
//! ```
//!
//! One-way, the heat conduction runs on a thread of its own, ahead of the
//! contact solves: each output state goes to the contact as soon as it is
//! computed ([`ThermalFeed`]). Two-way coupling alternates the two
//! ([`crate::coupling_loop`]).
//!
//! Errors are typed ([`DriverError`]) and name the phase (and the time of a
//! failed contact solve); the front doors add the case file or option.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use tecon_elastic::{
    ElasticError, ElasticModel, IncrementReport, InterfacePointResult, Loads, SolverOptions,
    StaticSolver, StressField, TiedMesh,
};
use tecon_mesh::Mesh;
use tecon_thermal::{ThermalError, ThermalModel, ThetaScheme, TimeSchedule};

pub use crate::coupling_loop::{CouplingStats, TwoWay};

/// Errors of the driver, by phase.
#[derive(Debug, thiserror::Error)]
pub enum DriverError {
    /// Assembling the thermal system failed.
    #[error("thermal: {0}")]
    ThermalAssembly(ThermalError),
    /// The thermal system has no initial temperature.
    #[error("thermal.initial: no initial temperature")]
    NoInitialTemperature,
    /// The steady heat conduction failed.
    #[error("thermal (steady): {0}")]
    Steady(ThermalError),
    /// The transient heat conduction failed (schedule or output times).
    #[error("output.times / thermal.schedule: {0}")]
    Transient(ThermalError),
    /// The elastic model could not be set up.
    #[error("mechanical: {0}")]
    Mechanical(Box<ElasticError>),
    /// The coupling cannot be done as asked.
    #[error("coupling: {0}")]
    Coupling(String),
    /// A node of the temperature history is not in the mesh.
    #[error("temperature history: node {node} is not in the mesh ({nodes} nodes)")]
    HistoryNode {
        /// The node asked for.
        node: usize,
        /// Nodes of the mesh.
        nodes: usize,
    },
    /// A contact solve failed.
    #[error("mechanical solve at t = {time} s: {source}")]
    ContactSolve {
        /// Time of the state being solved, s.
        time: f64,
        /// The solver's error.
        source: Box<ElasticError>,
    },
}

impl DriverError {
    /// The elastic solver's error, for a model that could not be set up or
    /// a contact solve that failed.
    pub(crate) fn elastic(&self) -> Option<&ElasticError> {
        match self {
            DriverError::Mechanical(e) | DriverError::ContactSolve { source: e, .. } => Some(e),
            _ => None,
        }
    }
}

/// How the temperature field is obtained.
#[derive(Debug, Clone)]
pub enum Procedure {
    /// The initial field is held (no boundary conditions, no schedule).
    Held,
    /// The steady state of the boundary conditions.
    Steady,
    /// A transient with output times.
    Transient {
        /// Time steps.
        schedule: TimeSchedule,
        /// θ-method.
        scheme: ThetaScheme,
        /// Output times, s (sorted, distinct).
        times: Vec<f64>,
    },
}

/// The heat-conduction part of a setup.
#[derive(Debug)]
pub struct ThermalSetup<'m> {
    /// The thermal model (assembled by the driver).
    pub model: ThermalModel<'m>,
    /// How the temperatures are obtained.
    pub procedure: Procedure,
    /// Stress-free temperature of the elements.
    pub reference_temperature: Reference,
}

/// Stress-free (reference) temperature of the elements: the thermal strain
/// is α (T_e − T_ref,e).
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Reference {
    /// Each element's mean initial temperature.
    #[default]
    Initial,
    /// One value for every element.
    Uniform(f64),
    /// One value per element (e.g. a region cooler than the rest: an
    /// interference fit as an eigenstrain).
    Elements(Vec<f64>),
}

impl From<Option<f64>> for Reference {
    fn from(v: Option<f64>) -> Self {
        v.map_or(Reference::Initial, Reference::Uniform)
    }
}

/// The element reference temperatures of `reference` for a system.
pub(crate) fn reference_field(
    reference: &Reference,
    system: &tecon_thermal::ThermalSystem<'_>,
) -> Result<Vec<f64>, DriverError> {
    let n = system.mesh().n_triangles();
    match reference {
        Reference::Initial => system
            .reference_temperature()
            .ok_or(DriverError::NoInitialTemperature),
        Reference::Uniform(r) => Ok(vec![*r; n]),
        Reference::Elements(v) if v.len() == n && v.iter().all(|x| x.is_finite()) => Ok(v.clone()),
        Reference::Elements(v) => Err(DriverError::Coupling(format!(
            "reference temperature: {} finite element values needed, got {} values",
            n,
            v.len()
        ))),
    }
}

/// Factors on the model's mechanical loads during a stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadFactors {
    /// Factor on the pressures.
    pub pressure: f64,
    /// Factor on the prescribed displacements.
    pub displacement: f64,
    /// Factor on the body forces.
    pub body_force: f64,
}

impl LoadFactors {
    /// All mechanical loads off.
    pub const OFF: LoadFactors = LoadFactors {
        pressure: 0.0,
        displacement: 0.0,
        body_force: 0.0,
    };
    /// All mechanical loads at full value.
    pub const FULL: LoadFactors = LoadFactors {
        pressure: 1.0,
        displacement: 1.0,
        body_force: 1.0,
    };
}

/// Temperatures a stage solves with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StageTemperature {
    /// One contact solve per state of the thermal procedure.
    FollowThermal,
    /// One contact solve with the temperatures of the last state solved so
    /// far held (e.g. operating pressure after cooling).
    HoldLast,
}

/// A load stage.
#[derive(Debug, Clone, PartialEq)]
pub struct Stage {
    /// Name (summary and progress).
    pub name: String,
    /// Mechanical load factors of the stage.
    pub loads: LoadFactors,
    /// Which temperatures the stage solves with.
    pub temperature: StageTemperature,
}

/// How heat conduction and contact are coupled.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Coupling {
    /// All heat conduction first, then the contact solves (today's).
    #[default]
    OneWay,
    /// Staggered per block of time steps (steady: iterated to a fixed point).
    TwoWay(TwoWay),
}

/// Everything the driver needs; the mesh is borrowed from the front door.
#[derive(Debug)]
pub struct Setup<'m> {
    /// The mesh (heat conduction and every result live on it).
    pub mesh: &'m Mesh,
    /// Bonded interfaces: the elastic model is built on this mesh (facing
    /// nodes merged) and its results are carried back to `mesh`.
    pub tie: Option<&'m TiedMesh>,
    /// Heat conduction (None: purely mechanical, one solve per stage).
    pub thermal: Option<ThermalSetup<'m>>,
    /// The elastic model with its interfaces.
    pub model: ElasticModel<'m>,
    /// Contact solver options.
    pub solver: SolverOptions,
    /// Load stages, in order.
    pub stages: Vec<Stage>,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Print the Newton history of every increment to stderr.
    pub verbose: bool,
    /// One-way or staggered two-way coupling.
    pub coupling: Coupling,
    /// Thermal interfaces whose conductance law reads the contact state
    /// (two-way), with the index of the same interface in the elastic model.
    pub coupled_interfaces: Vec<(String, usize)>,
}

/// The state at one output time of one stage.
#[derive(Debug, Clone)]
pub struct State {
    /// Time, s (0 for a steady, held or purely mechanical state).
    pub time: f64,
    /// Index of the stage in [`Setup::stages`].
    pub stage: usize,
    /// Nodal temperatures (None without heat conduction).
    pub temperature: Option<Vec<f64>>,
    /// Element mean temperatures (None without heat conduction).
    pub element_temperature: Option<Vec<f64>>,
    /// Relative heat-balance residual of the thermal state.
    pub heat_balance: Option<f64>,
    /// Displacements (2 per node).
    pub displacement: Vec<f64>,
    /// Out-of-plane strain (generalised plane strain; 0 otherwise).
    pub eps_zz: f64,
    /// Stresses.
    pub stress: StressField,
    /// Interface points (all interfaces, in model order).
    pub interface: Vec<InterfacePointResult>,
    /// Integration weight (arc length, m) of each interface point, parallel
    /// to `interface` ([`interface_point_weights`]).
    pub interface_weights: Vec<f64>,
    /// Most Newton iterations of any increment of this state's solve,
    /// counting all its passes (the run's largest over every solve is
    /// [`NewtonStats::max_per_increment`]).
    pub max_iterations: usize,
    /// Two-way: coupling iterations of the block that ended here.
    pub coupling_iterations: usize,
}

/// Work done by the contact analysis.
#[derive(Debug, Clone, Copy, Default)]
pub struct NewtonStats {
    /// Newton iterations in all (every pass of every increment).
    pub iterations: usize,
    /// Converged increments (with cut-backs, more than the output times).
    pub increments: usize,
    /// Most Newton iterations in one increment, all its passes counted,
    /// over every contact solve (two-way coupling solves the contact far
    /// more often than it writes a state).
    pub max_per_increment: usize,
    /// Most Newton iterations in one pass (between two outer updates),
    /// over every contact solve.
    pub max_per_pass: usize,
    /// Most outer updates (multipliers, friction limits) in one increment,
    /// over every contact solve.
    pub max_augmentations: usize,
    /// Tangent factorisations / reused factors / low-rank corrected solves.
    pub solves: tecon_fem::UpdateStats,
    /// Interface dofs the Newton passes were condensed onto (None: full
    /// passes).
    pub condensed_dofs: Option<usize>,
    /// Dofs of the coarse interface space of the condensed passes (None:
    /// none).
    pub coarse_dofs: Option<usize>,
    /// Newton steps in the coarse interface space before first passes,
    /// failed attempts included (not in `iterations`).
    pub coarse_iterations: usize,
    /// Most coarse steps before one increment, over every contact solve.
    pub max_coarse_per_increment: usize,
    /// Newton iterations of failed attempts (cut back, or a stalled outer
    /// loop of frozen friction limits), not counted in `iterations`.
    pub failed_iterations: usize,
    /// Increments solved by the coupled Mohr–Coulomb Newton after the
    /// outer loop of the frozen friction limits stalled.
    pub coupled_increments: usize,
    /// Newton passes with the coupled law in the tail of an outer loop
    /// (see `SolverOptions::coupled_tail`), the early ones included.
    pub coupled_tail_passes: usize,
    /// Of those, the early coupled passes (see
    /// `SolverOptions::early_coupled_pass`).
    pub early_coupled_passes: usize,
    /// Augmented-Lagrangian multiplier updates replaced by the Anderson
    /// mix of the last few (settled statuses).
    pub mixed_multiplier_updates: usize,
    /// Newton passes that stopped before the full tolerance because a
    /// friction-limit update followed (inexact passes).
    pub inexact_passes: usize,
}

/// What the heat conduction did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ThermalMode {
    /// No heat conduction.
    None,
    /// Initial field held.
    Held,
    /// Steady state.
    Steady,
    /// Transient.
    Transient,
}

/// The temperatures of a few nodes at every thermal step of a transient:
/// the start, then the end of every step (a step split at an output time
/// counts as two). At an output time the record carries the output time
/// and the output state's temperatures exactly.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TemperatureHistory {
    /// The nodes recorded.
    pub nodes: Vec<usize>,
    /// Time of each record, s.
    pub times: Vec<f64>,
    /// Per record, the temperature of each node (in `nodes` order), °C.
    pub values: Vec<Vec<f64>>,
}

impl TemperatureHistory {
    /// An empty history of `nodes`.
    pub fn new(nodes: &[usize]) -> Self {
        TemperatureHistory {
            nodes: nodes.to_vec(),
            ..Default::default()
        }
    }

    /// Records the nodes' values of the nodal field `temperature` at `time`.
    pub fn record(&mut self, time: f64, temperature: &[f64]) {
        self.times.push(time);
        self.values
            .push(self.nodes.iter().map(|&i| temperature[i]).collect());
    }

    /// The records appended to this history, in order.
    pub fn extend(&mut self, records: Vec<(f64, Vec<f64>)>) {
        for (t, v) in records {
            self.times.push(t);
            self.values.push(v);
        }
    }
}

/// Summary of the heat conduction.
#[derive(Debug, Clone, Copy)]
pub struct ThermalInfo {
    /// Mode.
    pub mode: ThermalMode,
    /// Time steps (transient).
    pub steps: usize,
    /// Largest relative heat-balance residual (None: held / no heat conduction).
    pub max_balance_residual: Option<f64>,
    /// Transient: the lowest and highest nodal temperature of every time
    /// step, not only of the output states (None: no transient).
    pub extremes: Option<StepExtremes>,
}

/// The lowest and highest nodal temperature over the time steps of a
/// transient: each as (value °C, time s, node).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepExtremes {
    /// Lowest.
    pub lowest: (f64, f64, usize),
    /// Highest.
    pub highest: (f64, f64, usize),
}

impl StepExtremes {
    /// Takes in the nodal field `temperature` at `time`.
    pub fn observe(this: &mut Option<StepExtremes>, time: f64, temperature: &[f64]) {
        for (i, &v) in temperature.iter().enumerate() {
            match this {
                None => {
                    *this = Some(StepExtremes {
                        lowest: (v, time, i),
                        highest: (v, time, i),
                    })
                }
                Some(e) => {
                    if v < e.lowest.0 {
                        e.lowest = (v, time, i);
                    }
                    if v > e.highest.0 {
                        e.highest = (v, time, i);
                    }
                }
            }
        }
    }

    /// The extremes of both.
    pub fn merge(this: &mut Option<StepExtremes>, other: Option<StepExtremes>) {
        let Some(o) = other else { return };
        match this {
            None => *this = Some(o),
            Some(e) => {
                if o.lowest.0 < e.lowest.0 {
                    e.lowest = o.lowest;
                }
                if o.highest.0 > e.highest.0 {
                    e.highest = o.highest;
                }
            }
        }
    }
}

/// A finished analysis.
#[derive(Debug)]
pub struct Outcome {
    /// Names of the model interfaces (index of [`InterfacePointResult::interface`]).
    pub interfaces: Vec<String>,
    /// One state per output time and stage, in order.
    pub states: Vec<State>,
    /// Heat conduction summary.
    pub thermal: ThermalInfo,
    /// Contact work.
    pub newton: NewtonStats,
    /// Notes from the solvers.
    pub notes: Vec<String>,
    /// Wall-clock seconds of heat conduction.
    pub thermal_seconds: f64,
    /// Wall-clock seconds of the contact solves.
    pub contact_seconds: f64,
    /// Two-way coupling statistics (None: one-way).
    pub coupling: Option<CouplingStats>,
    /// The worst output temperature outside the bounds of the maximum
    /// principle (set by [`run`]; None: none, or no bound applies).
    pub bound_violation: Option<BoundViolation>,
    /// The temperatures of the nodes asked for ([`run_recording`]) at every
    /// thermal step (None: none asked for, or no transient).
    pub history: Option<TemperatureHistory>,
}

/// A temperature state before the contact solve.
pub(crate) struct ThermalState {
    pub(crate) time: f64,
    pub(crate) temperature: Vec<f64>,
    pub(crate) element_temperature: Vec<f64>,
    pub(crate) heat_balance: Option<f64>,
}

fn progress(len: u64, show: bool) -> ProgressBar {
    let target = if show {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let pb = ProgressBar::with_draw_target(Some(len), target);
    if let Ok(style) =
        ProgressStyle::with_template("{spinner} {msg:40} [{bar:30}] {pos}/{len} {elapsed}")
    {
        pb.set_style(style.progress_chars("=> "));
    }
    pb
}

/// Why a two-way case runs one-way when no interface conductance reads the
/// contact state.
const CONSTANT_TWO_WAY_NOTE: &str = "two-way coupling asked for, but no interface conductance depends on the contact (constant conductances only, without radiation): the temperatures do not depend on the contact, so the case was solved one-way (heat conduction first, the contact at the output times); a pressure- or gap-dependent law (`[interface.conductance]` with `law = ...`, or `tecon vessel --conductance contact`) makes the coupling two-way";

/// Runs the analysis: heat conduction, and beside it the stages' contact
/// solves.
///
/// One-way, the contact at an output time needs the temperatures up to that
/// time only, so the heat conduction runs on a thread of its own and hands
/// each output state over as soon as it is computed; the contact solves
/// follow on this thread. Each side computes exactly what it computes alone
/// (the same numbers), and the run takes about the longer of the two instead
/// of their sum.
///
/// Every output state's temperatures are checked against the bounds of the
/// maximum principle ([`temperature_bound_violation`]); a state outside them
/// adds a note.
pub fn run(setup: &Setup<'_>) -> Result<Outcome, DriverError> {
    run_recording(setup, &[])
}

/// As [`run`], recording the temperatures of `history_nodes` at every
/// thermal step of a transient ([`Outcome::history`]; one-way and two-way
/// alike).
pub fn run_recording(setup: &Setup<'_>, history_nodes: &[usize]) -> Result<Outcome, DriverError> {
    let nodes = setup.mesh.n_nodes();
    if let Some(&node) = history_nodes.iter().find(|&&i| i >= nodes) {
        return Err(DriverError::HistoryNode { node, nodes });
    }
    let mut outcome = run_analysis(setup, history_nodes)?;
    outcome.bound_violation =
        temperature_bound_violation(setup, &outcome.states, outcome.thermal.extremes);
    if let Some(v) = &outcome.bound_violation {
        outcome.notes.push(v.note());
    }
    Ok(outcome)
}

/// The worst temperature of the output states outside the bounds of the
/// maximum principle ([`tecon_thermal::ThermalModel::temperature_bounds`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BoundViolation {
    /// How far the temperature lies outside the bound, K (positive).
    pub excursion: f64,
    /// The temperature, °C.
    pub value: f64,
    /// The bound it crosses, °C.
    pub bound: f64,
    /// True: below the lower bound; false: above the upper one.
    pub below: bool,
    /// Time of the state, s.
    pub time: f64,
    /// The node.
    pub node: usize,
    /// The node as the note names it: "node 17", with its Gmsh node tag on
    /// a mesh read from a Gmsh file.
    pub node_label: String,
    /// Position of the node, m.
    pub position: [f64; 2],
    /// The states come from a transient (false: a steady state).
    pub transient: bool,
    /// The worst excursion of the output states alone, K (0: inside): the
    /// stresses are computed from them, not from the steps between.
    pub output_excursion: f64,
}

impl BoundViolation {
    /// The warning for the notes.
    pub fn note(&self) -> String {
        let (side, of) = if self.below {
            ("below", "lowest")
        } else {
            ("above", "highest")
        };
        let cause = if self.transient {
            "the mesh does not resolve the initial temperature jump (a discrete maximum-principle violation of the first time steps; a finer mesh near the jump removes it, and so does a lumped capacity matrix: `--capacity lumped`, or capacity = \"lumped\" in [thermal])"
        } else {
            "the mesh does not resolve the temperature field there (a discrete maximum-principle violation; a finer mesh there removes it)"
        };
        // a step's time carries the round-off of summed steps (0.4000000000000001)
        let time = format!("{:.9}", self.time);
        let time = time.trim_end_matches('0').trim_end_matches('.');
        format!(
            "temperature outside its physical bounds: {:.3} °C at t = {time} s, {} at (x, y) = ({:.6}, {:.6}) m, lies {:.3} K {side} {:.3} °C, the {of} of the initial temperatures, the convection ambients and the prescribed temperatures, which heat conduction without sources cannot leave: {cause}; {}",
            self.value,
            self.node_label,
            self.position[0],
            self.position[1],
            self.excursion,
            self.bound,
            if self.output_excursion >= self.excursion {
                "the thermal stresses of that state carry that error".to_string()
            } else if self.output_excursion > 0.0 {
                format!(
                    "that is between the output times; the output states, whose thermal stresses are computed, lie up to {:.3} K outside",
                    self.output_excursion
                )
            } else {
                "that is between the output times; the output states, whose thermal stresses are computed, stay inside the bounds".to_string()
            },
        )
    }
}

/// The worst nodal temperature of `states`, and of every time step of a
/// transient (`extremes`: the lowest and highest of all its steps), outside
/// the bounds of the maximum principle, by more than 10⁻⁶ of their range
/// (at least 10⁻⁶ K); None when every temperature lies inside, without heat
/// conduction, with the initial field held, or when the model has no bound
/// (a prescribed heat flux into the body removes the upper bound, one out
/// of it the lower).
pub fn temperature_bound_violation(
    setup: &Setup<'_>,
    states: &[State],
    extremes: Option<StepExtremes>,
) -> Option<BoundViolation> {
    let th = setup.thermal.as_ref()?;
    let transient = match th.procedure {
        Procedure::Held => return None,
        Procedure::Steady => false,
        Procedure::Transient { .. } => true,
    };
    let outputs: Vec<(f64, &[f64])> = states
        .iter()
        .filter_map(|s| s.temperature.as_deref().map(|t| (s.time, t)))
        .collect();
    bound_violation_of(&th.model, setup.mesh, transient, &outputs, extremes)
}

/// [`temperature_bound_violation`] of a heat conduction `model` on `mesh`
/// (whose first nodes the temperatures are): `outputs` the output states
/// (time, nodal temperatures), `extremes` those of every time step.
pub fn bound_violation_of(
    model: &tecon_thermal::ThermalModel<'_>,
    mesh: &Mesh,
    transient: bool,
    outputs: &[(f64, &[f64])],
    extremes: Option<StepExtremes>,
) -> Option<BoundViolation> {
    let (lower, upper) = model.temperature_bounds()?;
    let range = match (lower, upper) {
        (Some(l), Some(u)) => u - l,
        _ => 0.0,
    };
    let tol = 1e-6 * range.max(1.0);
    let nodes = mesh.nodes();
    let mut worst: Option<BoundViolation> = None;
    let take = |worst: &mut Option<BoundViolation>, v: f64, time: f64, i: usize| {
        let cand = [
            lower.map(|l| (l - v, l, true)),
            upper.map(|u| (v - u, u, false)),
        ];
        for (excursion, bound, below) in cand.into_iter().flatten() {
            if excursion > tol && worst.as_ref().is_none_or(|w| excursion > w.excursion) {
                *worst = Some(BoundViolation {
                    excursion,
                    value: v,
                    bound,
                    below,
                    time,
                    node: i,
                    node_label: mesh.node_label(i),
                    position: nodes[i],
                    transient,
                    output_excursion: 0.0,
                });
            }
        }
    };
    for &(time, t) in outputs {
        for (i, &v) in t.iter().enumerate() {
            take(&mut worst, v, time, i);
        }
    }
    let output_excursion = worst.as_ref().map_or(0.0, |w| w.excursion);
    // between the output times too (the g0 vessel dips 0.72 K below the
    // ambient at t = 0.04 s, between its outputs)
    if let Some(e) = extremes {
        for (v, time, i) in [e.lowest, e.highest] {
            take(&mut worst, v, time, i);
        }
    }
    worst.map(|w| BoundViolation {
        output_excursion,
        ..w
    })
}

fn run_analysis(setup: &Setup<'_>, history_nodes: &[usize]) -> Result<Outcome, DriverError> {
    let n_out = match setup.thermal.as_ref().map(|t| &t.procedure) {
        Some(Procedure::Transient { times, .. }) => times.len(),
        _ => 1,
    };
    let pb = progress((2 * n_out + setup.stages.len() + 1) as u64, setup.progress);

    let mut notes = Vec::new();
    if let (Coupling::TwoWay(c), Some(th)) = (setup.coupling, &setup.thermal) {
        if !setup.coupled_interfaces.is_empty() {
            // on a worker of the thread pool: the parallel loops of the
            // contact solves then run on the pool directly instead of
            // waking it from outside (and waiting) every time. (Nothing
            // else runs beside the two-way loop, so even a pool of one
            // worker cannot wait on itself; the one-way contact side below
            // waits for the heat conduction's thread and stays off the
            // pool.)
            return rayon::scope(|_| {
                crate::coupling_loop::two_way(setup, th, c, &pb, history_nodes)
            });
        }
        notes.push(CONSTANT_TWO_WAY_NOTE.to_string());
    }
    pb.set_message("heat conduction");
    let clock = std::time::Instant::now();
    let prepared = match &setup.thermal {
        Some(th) => {
            let system = th.model.assemble().map_err(DriverError::ThermalAssembly)?;
            let reference = stress_free_reference(setup.mesh, th, &system)?;
            Some((th, system, reference))
        }
        None => None,
    };
    let prepare_seconds = clock.elapsed().as_secs_f64();
    let reference = prepared.as_ref().map(|p| p.2.clone());
    // the contact side gave up: the heat conduction stops at its next step
    let stop = std::sync::atomic::AtomicBool::new(false);
    let (contact_side, heat_side) = std::thread::scope(|scope| {
        let (send, incoming) = std::sync::mpsc::channel();
        let heat = scope.spawn(|| {
            let clock = std::time::Instant::now();
            let info = match &prepared {
                Some((th, system, _)) => {
                    heat_conduction(th, system, send, &stop, &pb, history_nodes)
                }
                None => Ok((
                    ThermalInfo {
                        mode: ThermalMode::None,
                        steps: 0,
                        max_balance_residual: None,
                        extremes: None,
                    },
                    None,
                )),
            };
            info.map(|i| (i, clock.elapsed().as_secs_f64()))
        });
        // (on this thread, not a worker of the pool: with one worker, a
        // worker waiting here for the heat conduction's states would hold
        // the heat conduction's own parallel loops up forever)
        let contact_side = (|| {
            let clock = std::time::Instant::now();
            let mut contact = Contact::new(setup, reference)?;
            let mut feed = ThermalFeed::incoming(incoming);
            let mut states: Vec<State> = Vec::new();
            run_stages(setup, &mut contact, &mut feed, 0, &mut states, &pb)?;
            let seconds = clock.elapsed().as_secs_f64() - feed.waited.as_secs_f64();
            Ok::<_, DriverError>((contact, states, seconds))
            // (`feed` drops here: a heat conduction still running sends
            // into nothing)
        })();
        if contact_side.is_err() {
            stop.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        let heat_side = match heat.join() {
            Ok(r) => r,
            Err(panic) => std::panic::resume_unwind(panic),
        };
        (contact_side, heat_side)
    });
    // A failed heat conduction comes first: the contact then saw its states
    // end early.
    let ((thermal, history), heat_seconds) = heat_side?;
    let (contact, states, contact_seconds) = contact_side?;
    pb.inc(1);
    pb.finish_and_clear();
    Ok(Outcome {
        interfaces: contact.interfaces(),
        states,
        thermal,
        newton: contact.stats(),
        notes: [contact.solver.notes(), &notes[..]].concat(),
        thermal_seconds: prepare_seconds + heat_seconds,
        contact_seconds,
        coupling: None,
        bound_violation: None,
        history,
    })
}

/// The thermal states as the contact solves take them: all at hand, or
/// arriving from the heat conduction that runs beside the contact.
pub(crate) struct ThermalFeed {
    states: Vec<ThermalState>,
    incoming: Option<std::sync::mpsc::Receiver<ThermalState>>,
    /// Time spent waiting for the heat conduction.
    waited: std::time::Duration,
}

impl ThermalFeed {
    /// States all at hand.
    pub(crate) fn ready(states: Vec<ThermalState>) -> Self {
        ThermalFeed {
            states,
            incoming: None,
            waited: std::time::Duration::ZERO,
        }
    }

    /// States sent by a heat conduction that is still running.
    fn incoming(incoming: std::sync::mpsc::Receiver<ThermalState>) -> Self {
        ThermalFeed {
            states: Vec::new(),
            incoming: Some(incoming),
            waited: std::time::Duration::ZERO,
        }
    }

    /// The `k`-th state, waiting for it if the heat conduction has not got
    /// there yet; None past the last one.
    fn get(&mut self, k: usize) -> Option<&ThermalState> {
        while self.states.len() <= k {
            let clock = std::time::Instant::now();
            let next = self.incoming.as_ref().and_then(|r| r.recv().ok());
            self.waited += clock.elapsed();
            match next {
                Some(s) => self.states.push(s),
                None => {
                    self.incoming = None;
                    return None;
                }
            }
        }
        self.states.get(k)
    }
}

/// The stages from `first` on: one contact solve per thermal state (or the
/// held last state).
pub(crate) fn run_stages(
    setup: &Setup<'_>,
    contact: &mut Contact<'_>,
    feed: &mut ThermalFeed,
    first: usize,
    states: &mut Vec<State>,
    pb: &ProgressBar,
) -> Result<(), DriverError> {
    for (k, stage) in setup.stages.iter().enumerate().skip(first) {
        match stage.temperature {
            StageTemperature::FollowThermal => {
                if feed.get(0).is_none() {
                    pb.set_message(format!("contact: {}", stage.name));
                    states.push(contact.solve(k, stage, None, pb, true)?);
                }
                let mut i = 0;
                while let Some(th) = feed.get(i) {
                    pb.set_message(format!("contact at t = {:.0} s", th.time));
                    states.push(contact.solve(k, stage, Some(th), pb, true)?);
                    pb.inc(1);
                    i += 1;
                }
            }
            StageTemperature::HoldLast => {
                pb.set_message(format!("contact: {}", stage.name));
                let held = states.last().and_then(|s| {
                    Some(ThermalState {
                        time: s.time,
                        temperature: s.temperature.clone()?,
                        element_temperature: s.element_temperature.clone()?,
                        heat_balance: s.heat_balance,
                    })
                });
                states.push(contact.solve(k, stage, held.as_ref(), pb, true)?);
            }
        }
    }
    Ok(())
}

/// Heat conduction of the whole procedure (one-way), each output state sent
/// as soon as it is computed; it stops early when `stop` is set. A
/// transient records the temperatures of `history_nodes` at every step
/// (none asked for: no history).
fn heat_conduction(
    th: &ThermalSetup<'_>,
    system: &tecon_thermal::ThermalSystem<'_>,
    send: std::sync::mpsc::Sender<ThermalState>,
    stop: &std::sync::atomic::AtomicBool,
    pb: &ProgressBar,
    history_nodes: &[usize],
) -> Result<(ThermalInfo, Option<TemperatureHistory>), DriverError> {
    let mut history = None;
    // (a contact side that gave up no longer receives: nothing to do then)
    let deliver = |s: ThermalState| {
        let _ = send.send(s);
    };
    let info = match &th.procedure {
        Procedure::Held => {
            let t0 = system
                .initial_temperature()
                .ok_or(DriverError::NoInitialTemperature)?
                .to_vec();
            deliver(ThermalState {
                time: 0.0,
                element_temperature: system.element_means(&t0),
                temperature: t0,
                heat_balance: None,
            });
            ThermalInfo {
                mode: ThermalMode::Held,
                steps: 0,
                max_balance_residual: None,
                extremes: None,
            }
        }
        Procedure::Steady => {
            let s = system.solve_steady().map_err(DriverError::Steady)?;
            let res = s.balance.relative_residual();
            deliver(ThermalState {
                time: 0.0,
                temperature: s.temperature,
                element_temperature: s.element_temperature,
                heat_balance: Some(res),
            });
            ThermalInfo {
                mode: ThermalMode::Steady,
                steps: 0,
                max_balance_residual: Some(res),
                extremes: None,
            }
        }
        Procedure::Transient {
            schedule,
            scheme,
            times,
        } => {
            let mut k = 0;
            let mut recorded = TemperatureHistory::new(history_nodes);
            let mut extremes = None;
            let summary = tecon_thermal::run_transient_observed(
                system,
                schedule,
                *scheme,
                times,
                |s| {
                    // report the requested output time (the stepper's clock
                    // carries round-off from summing steps)
                    deliver(ThermalState {
                        time: times.get(k).copied().unwrap_or(s.time),
                        temperature: s.temperature.clone(),
                        element_temperature: s.element_temperature.clone(),
                        heat_balance: Some(s.balance.relative_residual()),
                    });
                    k += 1;
                    pb.inc(1);
                },
                |time, temperature| {
                    StepExtremes::observe(&mut extremes, time, temperature);
                    if !history_nodes.is_empty() {
                        recorded.record(time, temperature);
                    }
                },
                || !stop.load(std::sync::atomic::Ordering::Relaxed),
            )
            .map_err(DriverError::Transient)?;
            if !history_nodes.is_empty() {
                history = Some(recorded);
            }
            ThermalInfo {
                mode: ThermalMode::Transient,
                steps: summary.steps,
                max_balance_residual: Some(summary.max_balance_residual),
                extremes,
            }
        }
    };
    Ok((info, history))
}

/// The stress-free temperature T_ref,e of every element: the case's
/// `reference_temperature` if given; otherwise, on linear triangles, the
/// element mean of the initial nodal field (the initial state is exactly
/// free of thermal strain), and on 6-node triangles the initial temperature
/// of the element's region (the piecewise constant field before the border
/// rule), so that the eigenstrain α (T − T_ref,e) of the weld keeps its jump
/// at the weld edge when the temperature varies inside the element.
pub(crate) fn stress_free_reference(
    mesh: &Mesh,
    th: &ThermalSetup<'_>,
    system: &tecon_thermal::ThermalSystem<'_>,
) -> Result<Vec<f64>, DriverError> {
    if !matches!(th.reference_temperature, Reference::Initial) {
        return reference_field(&th.reference_temperature, system);
    }
    let region = (mesh.order() == 2)
        .then(|| system.region_initial_temperature().map(<[f64]>::to_vec))
        .flatten();
    region
        .or_else(|| system.reference_temperature())
        .ok_or(DriverError::NoInitialTemperature)
}

/// The thermal load `Loads::delta_t` of the elastic solver: on linear
/// triangles one value per element, `T̄_e − T_ref,e` (element mean
/// temperature); on 6-node triangles six values per element, element-major
/// in [`Mesh::triangles6`] node order, `T_a − T_ref,e` (nodal temperature
/// minus the element's reference), so the temperature is interpolated to
/// the integration points inside the element.
pub fn thermal_load(
    mesh: &Mesh,
    nodal: &[f64],
    element_mean: &[f64],
    reference: &[f64],
) -> Vec<f64> {
    match mesh.triangles6() {
        Some(t6) => t6
            .iter()
            .zip(reference)
            .flat_map(|(t, r)| t.map(|a| nodal[a] - r))
            .collect(),
        None => element_mean
            .iter()
            .zip(reference)
            .map(|(t, r)| t - r)
            .collect(),
    }
}

/// The contact solver with its path-dependent state and statistics.
pub(crate) struct Contact<'s> {
    setup: &'s Setup<'s>,
    pub(crate) solver: StaticSolver<'s>,
    reference: Option<Vec<f64>>,
    newton: NewtonStats,
}

impl<'s> Contact<'s> {
    pub(crate) fn new(
        setup: &'s Setup<'s>,
        reference: Option<Vec<f64>>,
    ) -> Result<Self, DriverError> {
        let solver = StaticSolver::new(&setup.model, setup.solver)
            .map_err(|e| DriverError::Mechanical(Box::new(e)))?;
        Ok(Contact {
            setup,
            solver,
            reference,
            newton: NewtonStats::default(),
        })
    }

    pub(crate) fn interfaces(&self) -> Vec<String> {
        self.setup
            .model
            .interfaces()
            .iter()
            .map(|i| i.name.clone())
            .collect()
    }

    pub(crate) fn stats(&self) -> NewtonStats {
        NewtonStats {
            solves: self.solver.solve_stats(),
            condensed_dofs: self.solver.condensed_dofs(),
            coarse_dofs: self.solver.coarse_dofs(),
            coarse_iterations: self.solver.coarse_iterations(),
            ..self.newton
        }
    }

    /// One contact solve from the previous converged state. The stresses
    /// (recovery and error estimate: an eighth of a two-way run's time when
    /// made after every solve) are made only `with_stress`; otherwise the
    /// state's stress field is empty and the state must not be written.
    pub(crate) fn solve(
        &mut self,
        stage_index: usize,
        stage: &Stage,
        th: Option<&ThermalState>,
        pb: &ProgressBar,
        with_stress: bool,
    ) -> Result<State, DriverError> {
        let delta_t = match (th, &self.reference) {
            (Some(s), Some(r)) => {
                thermal_load(self.setup.mesh, &s.temperature, &s.element_temperature, r)
            }
            _ => Vec::new(),
        };
        let loads = Loads {
            delta_t,
            pressure: stage.loads.pressure,
            displacement: stage.loads.displacement,
            body_force: stage.loads.body_force,
        };
        let time = th.map_or(0.0, |s| s.time);
        let reports = self
            .solver
            .advance(&loads)
            .map_err(|e| DriverError::ContactSolve {
                time,
                source: Box::new(e),
            })?;
        self.newton.iterations += reports.iter().map(|r| r.iterations).sum::<usize>();
        self.newton.increments += reports.len();
        for r in &reports {
            self.newton.failed_iterations += r.failed_iterations;
            self.newton.coupled_increments += usize::from(r.coupled);
            self.newton.coupled_tail_passes += r.coupled_tail_passes.len();
            self.newton.early_coupled_passes += r.early_coupled_passes.len();
            self.newton.mixed_multiplier_updates += r.mixed_multiplier_updates;
            self.newton.inexact_passes += r
                .passes
                .iter()
                .filter(|p| p.last().is_some_and(|h| h.inexact))
                .count();
            self.newton.max_per_increment = self.newton.max_per_increment.max(r.iterations);
            self.newton.max_per_pass = self.newton.max_per_pass.max(r.max_pass_iterations);
            self.newton.max_coarse_per_increment = self
                .newton
                .max_coarse_per_increment
                .max(r.coarse_iterations);
            self.newton.max_augmentations = self.newton.max_augmentations.max(r.augmentations);
        }
        if self.setup.verbose {
            pb.suspend(|| print_history(time, &reports));
        }
        Ok(State {
            time,
            stage: stage_index,
            temperature: th.map(|s| s.temperature.clone()),
            element_temperature: th.map(|s| s.element_temperature.clone()),
            heat_balance: th.and_then(|s| s.heat_balance),
            displacement: on_mesh_displacement(self.setup, self.solver.displacement()),
            eps_zz: self.solver.eps_zz(),
            stress: if with_stress {
                on_mesh_stress(self.setup, self.solver.stresses())
            } else {
                StressField::default()
            },
            interface: self.solver.interface_results(),
            interface_weights: interface_point_weights(&self.setup.model),
            max_iterations: reports.iter().map(|r| r.iterations).max().unwrap_or(0),
            coupling_iterations: 0,
        })
    }
}

/// The integration weight (arc length of the bottom face, m) of every
/// interface point of `model`, in the order of
/// [`StaticSolver::interface_results`]: interface, element, point. 4-node
/// elements: two points of weight L/2 (nodal or Gauss); 6-node elements:
/// the three points of the element's rule (nodal: Simpson's L/6, 2L/3,
/// L/6 on a uniformly parametrised edge; Gauss: 5L/18, 8L/18, 5L/18).
pub fn interface_point_weights(model: &tecon_elastic::ElasticModel<'_>) -> Vec<f64> {
    let mut w = Vec::new();
    for itf in model.interfaces() {
        if itf.is_quadratic() {
            for e in &itf.quadratic {
                w.extend(e.points().iter().map(|p| p.weight));
            }
        } else {
            for e in &itf.elements {
                w.extend(e.points().iter().map(|p| p.weight));
            }
        }
    }
    w
}

/// The Newton history of the increments of one contact solve, on stderr.
pub(crate) fn print_history(time: f64, reports: &[IncrementReport]) {
    for r in reports {
        eprintln!(
            "{}, load fraction {:.3}: {} Newton iterations in {} passes{}, {} multiplier updates{}:",
            crate::figures::time_label(time),
            r.fraction,
            r.iterations,
            r.passes.len(),
            match r.coarse_iterations {
                0 => String::new(),
                k => format!(" after {k} steps in the coarse interface space"),
            },
            r.augmentations,
            if r.coupled {
                " (coupled Mohr–Coulomb Newton)"
            } else {
                ""
            }
        );
        for c in &r.cutbacks {
            eprintln!("  cut back: {c}");
        }
        for (k, pass) in r.passes.iter().enumerate() {
            if r.early_coupled_passes.contains(&k) {
                eprintln!("  pass {} (early coupled pass):", k + 1);
            } else if r.coupled_tail_passes.contains(&k) {
                eprintln!("  pass {} (coupled tail):", k + 1);
            } else {
                eprintln!("  pass {}:", k + 1);
            }
            for h in pass {
                eprintln!("    {h}");
            }
        }
    }
}

/// Displacements of the elastic model on the setup's mesh (a tied model's
/// expanded to both nodes of every tied pair).
fn on_mesh_displacement(setup: &Setup<'_>, u: &[f64]) -> Vec<f64> {
    match setup.tie {
        Some(t) => t.expand_displacement(u),
        None => u.to_vec(),
    }
}

/// Stresses of the elastic model on the setup's mesh. Elements keep their
/// numbers when interfaces are tied; a node of a tied pair takes the
/// area-weighted mean of its own body's elements (never averaged across
/// the interface): on 6-node meshes of their patch-recovered values
/// (second order), on linear meshes of the element values; every other
/// node the solver's value. The per-element fields (element, recovered,
/// error estimate) carry over unchanged.
fn on_mesh_stress(setup: &Setup<'_>, s: StressField) -> StressField {
    let Some(t) = setup.tie else {
        return s;
    };
    let mesh = setup.mesh;
    let map = t.node_map();
    let mut shared = vec![0u8; t.mesh().n_nodes()];
    for &m in map {
        shared[m] = shared[m].saturating_add(1);
    }
    let mut nodal = t.expand_nodal(&s.nodal);
    let mut acc = vec![[0.0; 5]; mesh.n_nodes()];
    let areas = mesh.areas();
    let mut add = |e: usize, v: usize| {
        if shared[map[v]] > 1 {
            let w = areas[e].abs();
            for (a, x) in acc[v].iter_mut().zip(&s.element[e]) {
                *a += w * x;
            }
            acc[v][4] += w;
        }
    };
    match mesh.triangles6() {
        // order 2: a tied node takes the patch-recovered values of its own
        // side (region), not the element means (first order only)
        Some(t6) if s.nodes_per_element() == 6 => {
            for (e, tri) in t6.iter().enumerate() {
                for (&v, r) in tri.iter().zip(s.recovered_of(e)) {
                    if shared[map[v]] > 1 {
                        let w = areas[e].abs();
                        for (x, r) in acc[v].iter_mut().zip(r) {
                            *x += w * r;
                        }
                        acc[v][4] += w;
                    }
                }
            }
        }
        Some(t6) => t6
            .iter()
            .enumerate()
            .for_each(|(e, tri)| tri.iter().for_each(|&v| add(e, v))),
        None => mesh
            .triangles()
            .iter()
            .enumerate()
            .for_each(|(e, tri)| tri.iter().for_each(|&v| add(e, v))),
    }
    for (v, a) in acc.iter().enumerate() {
        if a[4] > 0.0 {
            nodal[v] = [a[0] / a[4], a[1] / a[4], a[2] / a[4], a[3] / a[4]];
        }
    }
    StressField { nodal, ..s }
}

/// One mechanical solve from the unloaded state with the given load factors
/// and no temperature change (e.g. the operating pressure alone), with the
/// setup's elastic model and solver options; results on the setup's mesh.
pub fn solve_mechanical(
    setup: &Setup<'_>,
    loads: LoadFactors,
) -> Result<(StressField, Vec<f64>), DriverError> {
    let mut s = StaticSolver::new(&setup.model, setup.solver)
        .map_err(|e| DriverError::Mechanical(Box::new(e)))?;
    s.advance(&Loads {
        pressure: loads.pressure,
        displacement: loads.displacement,
        body_force: loads.body_force,
        ..Loads::zero()
    })
    .map_err(|e| DriverError::ContactSolve {
        time: 0.0,
        source: Box::new(e),
    })?;
    Ok((
        on_mesh_stress(setup, s.stresses()),
        on_mesh_displacement(setup, s.displacement()),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(time: f64) -> ThermalState {
        ThermalState {
            time,
            temperature: vec![time; 3],
            element_temperature: vec![time],
            heat_balance: None,
        }
    }

    /// Goal: the contact side gets the states in order as they arrive,
    /// waits for one not yet computed, and sees the end when the heat
    /// conduction is done (or gave up).
    #[test]
    fn a_feed_hands_over_the_states_in_order_and_ends_with_the_sender() {
        let (send, incoming) = std::sync::mpsc::channel();
        let heat = std::thread::spawn(move || {
            for t in [1.0, 10.0, 60.0] {
                std::thread::sleep(std::time::Duration::from_millis(20));
                send.send(state(t)).unwrap();
            }
        });
        let mut feed = ThermalFeed::incoming(incoming);
        assert_eq!(feed.get(1).map(|s| s.time), Some(10.0));
        assert_eq!(
            feed.get(0).map(|s| s.time),
            Some(1.0),
            "kept for later stages"
        );
        assert_eq!(feed.get(2).map(|s| s.temperature[0]), Some(60.0));
        assert!(feed.get(3).is_none());
        assert!(feed.waited > std::time::Duration::ZERO);
        heat.join().unwrap();
        let mut ready = ThermalFeed::ready(vec![state(5.0)]);
        assert_eq!(ready.get(0).map(|s| s.time), Some(5.0));
        assert!(ready.get(1).is_none());
    }
}
