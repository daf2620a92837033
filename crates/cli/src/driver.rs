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
//! Errors are typed ([`DriverError`]) and name the phase (and the time of a
//! failed contact solve); the front doors add the case file or option.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use tecon_elastic::{
    ElasticError, ElasticModel, IncrementReport, InterfacePointResult, Loads, SolverOptions,
    StaticSolver, StressField,
};
use tecon_mesh::Mesh;
use tecon_thermal::{
    HeatBalance, InterfacePointState, ThermalError, ThermalModel, ThetaScheme, TimeSchedule,
};

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
    /// A contact solve failed.
    #[error("mechanical solve at t = {time} s: {source}")]
    ContactSolve {
        /// Time of the state being solved, s.
        time: f64,
        /// The solver's error.
        source: Box<ElasticError>,
    },
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
    /// Stress-free temperature of every element (None: each element's
    /// initial temperature).
    pub reference_temperature: Option<f64>,
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

/// Staggered two-way coupling: per block of thermal steps, the thermal
/// step takes every interface point's conductance from the current contact
/// state, the contact is solved at the new temperatures, and the block is
/// repeated until the conductances settle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoWay {
    /// Thermal steps per contact solve (1: every step).
    pub sync_interval: usize,
    /// Settled when no interface conductance changes by more than this
    /// fraction of the largest one.
    pub tolerance: f64,
    /// Most coupling iterations per block.
    pub max_iterations: usize,
}

impl Default for TwoWay {
    fn default() -> Self {
        TwoWay {
            sync_interval: 1,
            tolerance: 1e-4,
            max_iterations: 30,
        }
    }
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
    /// The mesh.
    pub mesh: &'m Mesh,
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
    /// Most Newton iterations of any increment, counting all its passes.
    pub max_iterations: usize,
    /// Most augmented-Lagrangian updates in any increment.
    pub max_augmentations: usize,
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
    /// Tangent factorisations / reused factors / low-rank corrected solves.
    pub solves: tecon_fem::UpdateStats,
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

/// Summary of the heat conduction.
#[derive(Debug, Clone, Copy)]
pub struct ThermalInfo {
    /// Mode.
    pub mode: ThermalMode,
    /// Time steps (transient).
    pub steps: usize,
    /// Largest relative heat-balance residual (None: held / no heat conduction).
    pub max_balance_residual: Option<f64>,
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
}

/// What the two-way coupling did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CouplingStats {
    /// Blocks of thermal steps (each ending in a contact solve).
    pub blocks: usize,
    /// Coupling iterations in all.
    pub iterations: usize,
    /// Most iterations of one block.
    pub max_iterations: usize,
    /// Blocks that reached the iteration limit without settling.
    pub unsettled: usize,
    /// Largest final relative change of the conductances of any block.
    pub max_final_change: f64,
}

/// A temperature state before the contact solve.
struct ThermalState {
    time: f64,
    temperature: Vec<f64>,
    element_temperature: Vec<f64>,
    heat_balance: Option<f64>,
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

/// Runs the analysis: heat conduction, then the stages' contact solves.
pub fn run(setup: &Setup<'_>) -> Result<Outcome, DriverError> {
    let n_out = match setup.thermal.as_ref().map(|t| &t.procedure) {
        Some(Procedure::Transient { times, .. }) => times.len(),
        _ => 1,
    };
    let pb = progress((2 * n_out + setup.stages.len() + 1) as u64, setup.progress);

    if let (Coupling::TwoWay(c), Some(th)) = (setup.coupling, &setup.thermal) {
        return two_way(setup, th, c, &pb);
    }
    pb.set_message("heat conduction");
    let clock = std::time::Instant::now();
    let (thermal_states, reference, thermal) = heat_conduction(setup, &pb)?;
    let thermal_seconds = clock.elapsed().as_secs_f64();

    let clock = std::time::Instant::now();
    let mut contact = Contact::new(setup, reference)?;
    let mut states: Vec<State> = Vec::new();
    run_stages(setup, &mut contact, &thermal_states, 0, &mut states, &pb)?;
    let contact_seconds = clock.elapsed().as_secs_f64();
    pb.inc(1);
    pb.finish_and_clear();
    Ok(Outcome {
        interfaces: contact.interfaces(),
        states,
        thermal,
        newton: contact.stats(),
        notes: contact.solver.notes().to_vec(),
        thermal_seconds,
        contact_seconds,
        coupling: None,
    })
}

/// The stages from `first` on: one contact solve per thermal state (or the
/// held last state).
fn run_stages(
    setup: &Setup<'_>,
    contact: &mut Contact<'_>,
    thermal_states: &[ThermalState],
    first: usize,
    states: &mut Vec<State>,
    pb: &ProgressBar,
) -> Result<(), DriverError> {
    for (k, stage) in setup.stages.iter().enumerate().skip(first) {
        match stage.temperature {
            StageTemperature::FollowThermal if thermal_states.is_empty() => {
                pb.set_message(format!("contact: {}", stage.name));
                states.push(contact.solve(k, stage, None, pb)?);
            }
            StageTemperature::FollowThermal => {
                for th in thermal_states {
                    pb.set_message(format!("contact at t = {:.0} s", th.time));
                    states.push(contact.solve(k, stage, Some(th), pb)?);
                    pb.inc(1);
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
                states.push(contact.solve(k, stage, held.as_ref(), pb)?);
            }
        }
    }
    Ok(())
}

type HeatConduction = (Vec<ThermalState>, Option<Vec<f64>>, ThermalInfo);

/// Heat conduction of the whole procedure (one-way: before any contact solve).
fn heat_conduction(setup: &Setup<'_>, pb: &ProgressBar) -> Result<HeatConduction, DriverError> {
    let Some(th) = &setup.thermal else {
        let info = ThermalInfo {
            mode: ThermalMode::None,
            steps: 0,
            max_balance_residual: None,
        };
        return Ok((Vec::new(), None, info));
    };
    let system = th.model.assemble().map_err(DriverError::ThermalAssembly)?;
    let reference = match th.reference_temperature {
        Some(r) => vec![r; setup.mesh.n_triangles()],
        None => system
            .reference_temperature()
            .ok_or(DriverError::NoInitialTemperature)?,
    };
    let mut states = Vec::new();
    let info = match &th.procedure {
        Procedure::Held => {
            let t0 = system
                .initial_temperature()
                .ok_or(DriverError::NoInitialTemperature)?
                .to_vec();
            states.push(ThermalState {
                time: 0.0,
                element_temperature: system.element_means(&t0),
                temperature: t0,
                heat_balance: None,
            });
            ThermalInfo {
                mode: ThermalMode::Held,
                steps: 0,
                max_balance_residual: None,
            }
        }
        Procedure::Steady => {
            let s = system.solve_steady().map_err(DriverError::Steady)?;
            let res = s.balance.relative_residual();
            states.push(ThermalState {
                time: 0.0,
                temperature: s.temperature,
                element_temperature: s.element_temperature,
                heat_balance: Some(res),
            });
            ThermalInfo {
                mode: ThermalMode::Steady,
                steps: 0,
                max_balance_residual: Some(res),
            }
        }
        Procedure::Transient {
            schedule,
            scheme,
            times,
        } => {
            let summary = tecon_thermal::run_transient(&system, schedule, *scheme, times, |s| {
                // report the requested output time (the stepper's clock
                // carries round-off from summing steps)
                let k = states.len();
                states.push(ThermalState {
                    time: times.get(k).copied().unwrap_or(s.time),
                    temperature: s.temperature.clone(),
                    element_temperature: s.element_temperature.clone(),
                    heat_balance: Some(s.balance.relative_residual()),
                });
                pb.inc(1);
            })
            .map_err(DriverError::Transient)?;
            ThermalInfo {
                mode: ThermalMode::Transient,
                steps: summary.steps,
                max_balance_residual: Some(summary.max_balance_residual),
            }
        }
    };
    Ok((states, Some(reference), info))
}

/// The contact solver with its path-dependent state and statistics.
struct Contact<'s> {
    setup: &'s Setup<'s>,
    solver: StaticSolver<'s>,
    reference: Option<Vec<f64>>,
    newton: NewtonStats,
}

impl<'s> Contact<'s> {
    fn new(setup: &'s Setup<'s>, reference: Option<Vec<f64>>) -> Result<Self, DriverError> {
        let solver = StaticSolver::new(&setup.model, setup.solver)
            .map_err(|e| DriverError::Mechanical(Box::new(e)))?;
        Ok(Contact {
            setup,
            solver,
            reference,
            newton: NewtonStats::default(),
        })
    }

    fn interfaces(&self) -> Vec<String> {
        self.setup
            .model
            .interfaces()
            .iter()
            .map(|i| i.name.clone())
            .collect()
    }

    fn stats(&self) -> NewtonStats {
        NewtonStats {
            solves: self.solver.solve_stats(),
            ..self.newton
        }
    }

    /// One contact solve from the previous converged state.
    fn solve(
        &mut self,
        stage_index: usize,
        stage: &Stage,
        th: Option<&ThermalState>,
        pb: &ProgressBar,
    ) -> Result<State, DriverError> {
        let delta_t = match (th, &self.reference) {
            (Some(s), Some(r)) => s
                .element_temperature
                .iter()
                .zip(r)
                .map(|(t, r)| t - r)
                .collect(),
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
        if self.setup.verbose {
            pb.suspend(|| print_history(time, &reports));
        }
        Ok(State {
            time,
            stage: stage_index,
            temperature: th.map(|s| s.temperature.clone()),
            element_temperature: th.map(|s| s.element_temperature.clone()),
            heat_balance: th.and_then(|s| s.heat_balance),
            displacement: self.solver.displacement().to_vec(),
            eps_zz: self.solver.eps_zz(),
            stress: self.solver.stresses(),
            interface: self.solver.interface_results(),
            max_iterations: reports.iter().map(|r| r.iterations).max().unwrap_or(0),
            max_augmentations: reports.iter().map(|r| r.augmentations).max().unwrap_or(0),
            coupling_iterations: 0,
        })
    }
}

/// The Newton history of the increments of one contact solve, on stderr.
fn print_history(time: f64, reports: &[IncrementReport]) {
    for r in reports {
        eprintln!(
            "t = {time} s, load fraction {:.3}: {} Newton iterations in {} passes, {} multiplier updates:",
            r.fraction,
            r.iterations,
            r.passes.len(),
            r.augmentations
        );
        for c in &r.cutbacks {
            eprintln!("  cut back: {c}");
        }
        for (k, pass) in r.passes.iter().enumerate() {
            eprintln!("  pass {}:", k + 1);
            for h in pass {
                eprintln!("    {h}");
            }
        }
    }
}

/// One mechanical solve from the unloaded state with the given load factors
/// and no temperature change (e.g. the operating pressure alone).
pub fn solve_mechanical(
    model: &ElasticModel<'_>,
    options: SolverOptions,
    loads: LoadFactors,
) -> Result<(StressField, Vec<f64>), DriverError> {
    let mut s =
        StaticSolver::new(model, options).map_err(|e| DriverError::Mechanical(Box::new(e)))?;
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
    Ok((s.stresses(), s.displacement().to_vec()))
}

// ---------------------------------------------------------------------------
// Two-way coupling
// ---------------------------------------------------------------------------

/// Conductance states of the coupled interfaces from the contact solver's
/// current interface points and the nodal temperatures `t`.
fn interface_states(
    setup: &Setup<'_>,
    contact: &Contact<'_>,
    t: &[f64],
) -> Vec<Vec<[InterfacePointState; 2]>> {
    let points = contact.solver.interface_results();
    setup
        .coupled_interfaces
        .iter()
        .map(|(name, index)| {
            let elements = setup
                .mesh
                .interfaces()
                .get(name)
                .map(|i| i.elements.clone())
                .unwrap_or_default();
            let mut out = vec![[InterfacePointState::default(); 2]; elements.len()];
            for p in points.iter().filter(|p| p.interface == *index) {
                let (Some(el), Some(slot)) = (elements.get(p.element), out.get_mut(p.element))
                else {
                    continue;
                };
                let k = p.point.min(1);
                // point k pairs bottom node k with top node 3 − k
                let temperature = 0.5 * (t[el[k]] + t[el[3 - k]]);
                slot[k] = InterfacePointState {
                    gap: p.jump[1],
                    pressure: (-p.traction[1]).max(0.0),
                    temperature,
                };
            }
            out
        })
        .collect()
}

/// Conductances of the coupled interfaces in `model` for the states.
fn conductances(
    setup: &Setup<'_>,
    model: &mut ThermalModel<'_>,
    states: &[Vec<[InterfacePointState; 2]>],
) -> Result<Vec<f64>, DriverError> {
    for ((name, _), st) in setup.coupled_interfaces.iter().zip(states) {
        model
            .set_interface_state(name, st.clone())
            .map_err(DriverError::ThermalAssembly)?;
    }
    let mut h = Vec::new();
    for (name, _) in &setup.coupled_interfaces {
        let v = model
            .interface_conductance_values(name)
            .map_err(DriverError::ThermalAssembly)?;
        h.extend(v.into_iter().flatten());
    }
    Ok(h)
}

fn max_rel_change(a: &[f64], b: &[f64]) -> f64 {
    let scale = a
        .iter()
        .chain(b)
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// One step of the two-way schedule: Δt, θ, and whether an output time ends it.
struct Step {
    dt: f64,
    theta: f64,
    output: Option<f64>,
}

/// The schedule's steps split at the output times (as the one-way transient
/// does).
fn split_steps(
    schedule: &TimeSchedule,
    scheme: ThetaScheme,
    times: &[f64],
) -> Result<Vec<Step>, DriverError> {
    let (start, end) = (schedule.start(), schedule.end());
    let slack = 1e-9 * (end - start);
    for &t in times {
        if !(t.is_finite() && t >= start - slack && t <= end + slack) {
            return Err(DriverError::Transient(ThermalError::OutputTimeOutOfRange {
                time: t,
                start,
                end,
            }));
        }
    }
    let mut steps = Vec::new();
    let mut now = start;
    let mut next = 0;
    while next < times.len() && times[next] <= now + slack {
        steps.push(Step {
            dt: 0.0,
            theta: 1.0,
            output: Some(times[next]),
        });
        next += 1;
    }
    for (k, &dt) in schedule.steps().iter().enumerate() {
        let theta = scheme.theta_at(k);
        let tol = 1e-9 * dt;
        let step_end = now + dt;
        let mut split = false;
        while next < times.len() && times[next] < step_end - tol {
            let sub = times[next] - now;
            if sub > tol {
                steps.push(Step {
                    dt: sub,
                    theta,
                    output: None,
                });
                now += sub;
                split = true;
            }
            if let Some(last) = steps.last_mut() {
                last.output = Some(times[next]);
            }
            next += 1;
        }
        let last = if split { step_end - now } else { dt };
        now += last;
        steps.push(Step {
            dt: last,
            theta,
            output: None,
        });
        while next < times.len() && times[next] <= now + tol {
            if let Some(s) = steps.last_mut() {
                s.output = Some(times[next]);
            }
            next += 1;
        }
    }
    Ok(steps)
}

/// Staggered two-way coupling (transient or steady), then the later stages.
fn two_way(
    setup: &Setup<'_>,
    th: &ThermalSetup<'_>,
    c: TwoWay,
    pb: &ProgressBar,
) -> Result<Outcome, DriverError> {
    let mut model = th.model.clone();
    let system = model.assemble().map_err(DriverError::ThermalAssembly)?;
    let reference = match th.reference_temperature {
        Some(r) => vec![r; setup.mesh.n_triangles()],
        None => system
            .reference_temperature()
            .ok_or(DriverError::NoInitialTemperature)?,
    };
    let initial = system
        .initial_temperature()
        .ok_or(DriverError::NoInitialTemperature)?
        .to_vec();
    drop(system);
    let mut contact = Contact::new(setup, Some(reference))?;
    let stage = &setup.stages[0];
    let mut stats = CouplingStats::default();
    let mut states: Vec<State> = Vec::new();
    let (mut thermal_seconds, mut contact_seconds) = (0.0, 0.0);
    let mut balance = HeatBalance::default();
    let mut max_res: f64 = 0.0;
    let mut steps_taken = 0;

    // One block: thermal (from `t0` over `steps`, or steady) with the
    // conductances of the current contact state, contact solve, repeat.
    let mut block = |t0: &[f64],
                     time0: f64,
                     steps: &[Step],
                     contact: &mut Contact<'_>,
                     model: &mut ThermalModel<'_>|
     -> Result<(ThermalState, HeatBalance, State), DriverError> {
        let mut guess = t0.to_vec();
        let mut h_used = conductances(setup, model, &interface_states(setup, contact, &guess))?;
        let mut iterations = 0;
        loop {
            iterations += 1;
            let clock = std::time::Instant::now();
            let system = model.assemble().map_err(DriverError::ThermalAssembly)?;
            let (temperature, time, bal) = if steps.is_empty() {
                let s = system.solve_steady().map_err(DriverError::Steady)?;
                (s.temperature, 0.0, s.balance)
            } else {
                let mut stepper = system
                    .stepper(t0.to_vec(), time0)
                    .map_err(DriverError::Transient)?;
                for s in steps.iter().filter(|s| s.dt > 0.0) {
                    stepper
                        .step(s.dt, s.theta)
                        .map_err(DriverError::Transient)?;
                }
                (
                    stepper.temperature().to_vec(),
                    stepper.time(),
                    stepper.balance(),
                )
            };
            let element_temperature = system.element_means(&temperature);
            drop(system);
            thermal_seconds += clock.elapsed().as_secs_f64();
            let th_state = ThermalState {
                time: steps.last().and_then(|s| s.output).unwrap_or(time),
                temperature,
                element_temperature,
                heat_balance: Some(bal.relative_residual()),
            };
            let clock = std::time::Instant::now();
            let mut state = contact.solve(0, stage, Some(&th_state), pb)?;
            contact_seconds += clock.elapsed().as_secs_f64();
            guess.clone_from(&th_state.temperature);
            let h_new = conductances(setup, model, &interface_states(setup, contact, &guess))?;
            let change = max_rel_change(&h_new, &h_used);
            h_used = h_new;
            if change <= c.tolerance || iterations >= c.max_iterations {
                if change > c.tolerance {
                    stats.unsettled += 1;
                }
                stats.blocks += 1;
                stats.iterations += iterations;
                stats.max_iterations = stats.max_iterations.max(iterations);
                stats.max_final_change = stats.max_final_change.max(change);
                state.coupling_iterations = iterations;
                return Ok((th_state, bal, state));
            }
        }
    };

    let info = match &th.procedure {
        Procedure::Held => {
            return Err(DriverError::Coupling(
                "two-way coupling needs heat conduction: give thermal boundary conditions (steady) or a schedule (transient)".into(),
            ));
        }
        Procedure::Steady => {
            let (ts, bal, state) = block(&initial, 0.0, &[], &mut contact, &mut model)?;
            max_res = bal.relative_residual();
            let _ = ts;
            states.push(state);
            ThermalInfo {
                mode: ThermalMode::Steady,
                steps: 0,
                max_balance_residual: Some(max_res),
            }
        }
        Procedure::Transient {
            schedule,
            scheme,
            times,
        } => {
            let all = split_steps(schedule, *scheme, times)?;
            let mut t = initial.clone();
            let mut time = schedule.start();
            let mut first = 0;
            let mut since_output = Vec::new();
            while first < all.len() {
                // a block: up to `sync_interval` steps, ending at an output time
                let mut last = first;
                let mut n = 0;
                while last < all.len() {
                    if all[last].dt > 0.0 {
                        n += 1;
                    }
                    if all[last].output.is_some() || n >= c.sync_interval {
                        break;
                    }
                    last += 1;
                }
                let last = last.min(all.len() - 1);
                let steps = &all[first..=last];
                let (ts, bal, state) = block(&t, time, steps, &mut contact, &mut model)?;
                steps_taken += steps.iter().filter(|s| s.dt > 0.0).count();
                time += steps.iter().map(|s| s.dt).sum::<f64>();
                balance.stored_change += bal.stored_change;
                balance.convection_in += bal.convection_in;
                balance.flux_in += bal.flux_in;
                balance.prescribed_in += bal.prescribed_in;
                balance.scale += bal.scale;
                since_output.push(state.coupling_iterations);
                t = ts.temperature.clone();
                if steps[steps.len() - 1].output.is_some() {
                    balance.residual = balance.stored_change
                        - (balance.convection_in + balance.flux_in + balance.prescribed_in);
                    let res = balance.relative_residual();
                    max_res = max_res.max(res);
                    let mut state = state;
                    state.heat_balance = Some(res);
                    state.coupling_iterations = since_output.iter().copied().max().unwrap_or(0);
                    since_output.clear();
                    states.push(state);
                    pb.inc(2);
                }
                first = last + 1;
            }
            ThermalInfo {
                mode: ThermalMode::Transient,
                steps: steps_taken,
                max_balance_residual: Some(max_res),
            }
        }
    };
    // Later stages (e.g. operating pressure) from the coupled history.
    let clock = std::time::Instant::now();
    run_stages(setup, &mut contact, &[], 1, &mut states, pb)?;
    contact_seconds += clock.elapsed().as_secs_f64();
    pb.finish_and_clear();
    Ok(Outcome {
        interfaces: contact.interfaces(),
        states,
        thermal: info,
        newton: contact.stats(),
        notes: contact.solver.notes().to_vec(),
        thermal_seconds,
        contact_seconds,
        coupling: Some(stats),
    })
}
