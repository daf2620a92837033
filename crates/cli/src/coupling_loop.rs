//! Staggered two-way thermoelastic coupling: the interface conductance of
//! the heat conduction follows the contact state, the contact follows the
//! temperatures.
//!
//! The time line is cut into **blocks** of thermal steps, each ending in a
//! contact solve (and always at an output time). A block is taken from the
//! converged state at its start:
//!
//! ```text
//!   s_used  ← interface states (gap g, pressure p, face temperature) used for h_c
//!   thermal θ-steps of the block with h_c(s_used)   (re-assembled once per attempt)
//!   contact solve at the block end → s_new          (from the start of the block:
//!                                                    the contact is rolled back)
//!   accept, or correct s_used and repeat
//! ```
//!
//! Two ways to choose blocks ([`TwoWay::sync_tolerance`]):
//!
//! * **fixed** (`None`): `sync_interval` steps per block; the block uses the
//!   end-of-block state, iterated until no conductance changes by more than
//!   `tolerance` of the largest (a backward-Euler coupling per block);
//! * **adaptive** (`Some(τ)`): the conductance over a block is evaluated at
//!   the state *extrapolated to the block midpoint* from the last two
//!   contact solves (a midpoint rule, second order in the block length).
//!   After the contact solve the midpoint state is known,
//!   `s_mid = (s_start + s_new)/2`, and the relative conductance error
//!   `e = max |h_c(s_mid) − h_c(s_used)| / max h_c` is the error made in the
//!   block. `e ≤ τ`: accepted, the next block grows by
//!   `min(2, 0.9 √(τ/e))`; `e > τ`: rejected, the contact and the
//!   temperatures are rolled back and the block is shortened. A one-step
//!   block that still misses τ is iterated (s_used ← s_mid) until the
//!   conductances settle to `tolerance`, as in the fixed mode. The contact
//!   is solved only when it matters and always at output times; the
//!   largest accepted `e` is reported.
//!
//! A steady case is one block: a fixed-point iteration p = g(h(p)), each
//! contact solve rolled back to the initial state. It converges to a
//! stable steady state (map slope g′ < 1), the one on whose side of the
//! unstable states the initial contact state lies.

use indicatif::ProgressBar;
use tecon_elastic::SolverState;
use tecon_thermal::{HeatBalance, InterfacePointState, ThermalError, ThermalModel, ThetaScheme};

use crate::driver::{
    Contact, DriverError, Outcome, Procedure, Setup, State, StepExtremes, TemperatureHistory,
    ThermalFeed, ThermalInfo, ThermalMode, ThermalSetup, ThermalState, run_stages,
};

/// Staggered two-way coupling settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoWay {
    /// Thermal steps per contact solve (fixed mode), or of the first block
    /// (adaptive mode).
    pub sync_interval: usize,
    /// A block has settled when no interface conductance changes by more
    /// than this fraction of the largest between two iterations.
    pub tolerance: f64,
    /// Most coupling iterations (contact solves) per block.
    pub max_iterations: usize,
    /// Adaptive blocks: the largest relative conductance error accepted in
    /// a block (None: fixed blocks of `sync_interval` steps).
    pub sync_tolerance: Option<f64>,
}

/// Default [`TwoWay::sync_tolerance`]: 1 % of the largest conductance.
pub const DEFAULT_SYNC_TOLERANCE: f64 = 1e-2;

/// Longest adaptive block, in thermal steps.
const MAX_BLOCK: usize = 64;

impl Default for TwoWay {
    fn default() -> Self {
        TwoWay {
            sync_interval: 1,
            tolerance: 1e-4,
            max_iterations: 30,
            sync_tolerance: Some(DEFAULT_SYNC_TOLERANCE),
        }
    }
}

/// What the two-way coupling did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CouplingStats {
    /// Accepted blocks of thermal steps (each ending in a contact solve).
    pub blocks: usize,
    /// Coupling iterations (= contact solves of the coupling) in all,
    /// rejected attempts included.
    pub iterations: usize,
    /// Most iterations of one block.
    pub max_iterations: usize,
    /// Blocks that reached the iteration limit without settling.
    pub unsettled: usize,
    /// Largest final relative change of the conductances of any block
    /// (adaptive: the largest accepted conductance error of a block).
    pub max_final_change: f64,
    /// Adaptive: rejected block attempts (rolled back and shortened).
    pub rejected: usize,
    /// Adaptive: the sync tolerance τ (None: fixed blocks).
    pub sync_tolerance: Option<f64>,
    /// Adaptive: the outer-loop tolerance of the contact solves that end a
    /// block short of an output time, as a fraction of the largest contact
    /// pressure ([`INTERMEDIATE_OUTER_SHARE`] × τ; None: fixed blocks, every
    /// solve to the solver's own tolerances).
    pub intermediate_outer_tolerance: Option<f64>,
}

/// The share of the block error budget τ (a fraction of the largest
/// conductance) that the outer loop (multiplier updates and frozen
/// friction limits) of a contact solve between the output times may leave
/// in the contact pressures, as a fraction of the largest pressure. Such a
/// solve feeds only the conductance of the next blocks (the power-law
/// conductance changes about in proportion to the pressure) and the
/// friction history: a point that slips there and sticks from then on
/// keeps an error of up to this floor in its shear. Measured on the
/// default vessel in docs/coupling.md ("Staggered two-way coupling"); the
/// whole of τ saved no more Newton iterations there.
pub const INTERMEDIATE_OUTER_SHARE: f64 = 1.0 / 3.0;

/// Interface point states of the coupled interfaces: per interface, per
/// element, the two points.
type PointStates = Vec<Vec<[InterfacePointState; 2]>>;

/// Conductance states of the coupled interfaces from the contact solver's
/// current interface points and the nodal temperatures `t`.
fn interface_states(setup: &Setup<'_>, contact: &Contact<'_>, t: &[f64]) -> PointStates {
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

/// `a + w (b − a)` point by point (pressure kept ≥ 0).
fn blend(a: &PointStates, b: &PointStates, w: f64) -> PointStates {
    a.iter()
        .zip(b)
        .map(|(ia, ib)| {
            ia.iter()
                .zip(ib)
                .map(|(ea, eb)| {
                    [0, 1].map(|k| {
                        let (x, y) = (ea[k], eb[k]);
                        InterfacePointState {
                            gap: x.gap + w * (y.gap - x.gap),
                            pressure: (x.pressure + w * (y.pressure - x.pressure)).max(0.0),
                            temperature: x.temperature + w * (y.temperature - x.temperature),
                        }
                    })
                })
                .collect()
        })
        .collect()
}

/// Sets the states on the coupled interfaces of `model` and returns their
/// conductances (all points, interface by interface).
fn conductances(
    setup: &Setup<'_>,
    model: &mut ThermalModel<'_>,
    states: &PointStates,
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

/// Largest |a − b| relative to the largest |a|, |b|.
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

/// The length (s) of the block after an accepted one of `span` seconds
/// whose error allows it to grow by `grow`, given the `target` it was cut
/// from. A block that an output time cut short of its target does not set
/// the next one's length, unless that is shorter. A block that ends short
/// of its target only because the next thermal step would overshoot it
/// does: its span times `grow` (blocks are whole steps, so a target kept
/// instead would never reach two steps of a schedule whose steps are
/// longer than half of it).
fn next_target(target: Option<f64>, span: f64, grow: f64, at_output: bool) -> f64 {
    // (a shrinking block, grow < 1, is shorter than the target anyway)
    match target {
        Some(d) if at_output && span < 0.999 * d && grow >= 1.0 => d,
        _ => span * grow,
    }
}

/// Aitken's dynamic relaxation of the coupling iteration (Irons and Tuck):
/// the next state is `used + ω (G(used) − used)`, with ω from the last two
/// conductance residuals `r = h(G(used)) − h(used)`,
///
/// ```text
/// ω_k = −ω_{k−1} r_{k−1}·(r_k − r_{k−1}) / |r_k − r_{k−1}|²,
/// ```
///
/// kept in [ω_MIN, 1]. A plain iteration (ω = 1) of a map whose slope is
/// below −1 (a joint point whose conductance rises steeply with the
/// pressure its own cooling lowers) alternates between two states for
/// ever; for a two-cycle r_k = −r_{k−1} this gives ω = ω_{k−1}/2, and for
/// a scalar affine map with slope g′ < 0 the exact 1/(1 − g′) in one step
/// (for 0 < g′ < 1 that would exceed 1: the plain step is kept). Only
/// the path changes: the fixed point, and the settle test on the
/// unrelaxed change, are those of the plain iteration.
#[derive(Default)]
struct Aitken {
    /// the last factor and residual
    last: Option<(f64, Vec<f64>)>,
}

/// Smallest relaxation factor.
const OMEGA_MIN: f64 = 0.05;

impl Aitken {
    /// The factor for the residual `h_next − h_used`.
    fn factor(&mut self, h_next: &[f64], h_used: &[f64]) -> f64 {
        let r: Vec<f64> = h_next.iter().zip(h_used).map(|(a, b)| a - b).collect();
        let omega = match &self.last {
            None => 1.0,
            Some((w, r0)) => {
                let (mut num, mut den) = (0.0, 0.0);
                for (a, b) in r.iter().zip(r0) {
                    let d = a - b;
                    num += b * d;
                    den += d * d;
                }
                if den > 0.0 {
                    (-w * num / den).clamp(OMEGA_MIN, 1.0)
                } else {
                    *w
                }
            }
        };
        self.last = Some((omega, r));
        omega
    }
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
    schedule: &tecon_thermal::TimeSchedule,
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
        let theta = scheme.theta_for(k, schedule.steps());
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

/// The coupling loop's working state.
struct Loop<'a, 's> {
    setup: &'s Setup<'s>,
    model: ThermalModel<'s>,
    contact: Contact<'s>,
    pb: &'a ProgressBar,
    stats: CouplingStats,
    thermal_seconds: f64,
    contact_seconds: f64,
    /// The symbolic analysis of the thermal matrices (the pattern is the
    /// same at every re-assembly): made once, shared by every stepper.
    thermal_symbolic: Option<tecon_fem::CholeskySolver>,
    /// Nodes whose temperatures are recorded at every thermal step.
    history_nodes: &'a [usize],
    /// The thermal system of the last attempt ([`ThermalModel::reassemble`]).
    system: Option<tecon_thermal::ThermalSystem<'s>>,
}

/// A block of thermal steps from its start.
#[derive(Clone, Copy)]
struct Block<'b> {
    /// Nodal temperatures at the start.
    t0: &'b [f64],
    /// Time at the start, s.
    time0: f64,
    /// The steps (empty: steady).
    steps: &'b [Step],
}

/// What one attempt of a block produced.
struct Attempt {
    thermal: ThermalState,
    balance: HeatBalance,
    state: State,
    /// Interface states after the contact solve.
    states: PointStates,
    /// The temperatures of the history nodes after every step of the
    /// block (time, values); kept only if the attempt is accepted.
    history: Vec<(f64, Vec<f64>)>,
    /// The lowest and highest nodal temperature of the block's steps.
    extremes: Option<StepExtremes>,
}

/// Where the Newton iterations of a block's contact solve start.
#[derive(Clone, Copy)]
enum Guess<'g> {
    /// The block's start (the checkpoint).
    Start,
    /// A contact state (the solve before, of the same block).
    State(&'g SolverState),
    /// The block's start extrapolated along the change since the block
    /// before (`older`, at the temperatures `t_older`), by the weight that
    /// projects the block's temperature change onto that block's
    /// ([`load_weight`]).
    Extrapolated {
        older: &'g SolverState,
        t_older: &'g [f64],
    },
}

/// The weight w of the extrapolated guess `start + w (start − older)`:
/// the least-squares fit of the block's temperature change `t_end − t_start`
/// by the change of the block before, `t_start − t_older`, in [0,
/// [`MAX_GUESS_WEIGHT`]]. The mechanical load is linear in the temperatures,
/// so this scales the last change by the load actually applied, where the
/// ratio of the block lengths (the guess until 2026-11-28) overshoots
/// once the cooling slows down: the first Newton step then pulled back
/// the slip of hundreds of points, which the next passes had to undo.
fn load_weight(t_end: &[f64], t_start: &[f64], t_older: &[f64]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for ((e, s), o) in t_end.iter().zip(t_start).zip(t_older) {
        num += (e - s) * (s - o);
        den += (s - o) * (s - o);
    }
    if den > 0.0 {
        (num / den).clamp(0.0, MAX_GUESS_WEIGHT)
    } else {
        0.0
    }
}

/// Largest weight of an extrapolated guess ([`load_weight`]).
const MAX_GUESS_WEIGHT: f64 = 4.0;

impl Loop<'_, '_> {
    /// Thermal steps from `t0` at `time0` (steady when `steps` is empty) with
    /// the conductances of `used`, then the contact solve at the new
    /// temperatures from the checkpoint `start`, its Newton iterations
    /// started from `guess` (see [`SolverState::resume_warm`]).
    fn attempt(
        &mut self,
        b: Block<'_>,
        used: &PointStates,
        start: &SolverState,
        guess: Guess<'_>,
    ) -> Result<Attempt, DriverError> {
        let clock = std::time::Instant::now();
        conductances(self.setup, &mut self.model, used)?;
        // only the interface conductances changed since the last attempt:
        // the interfaces alone are re-assembled
        let system = match self.system.take() {
            Some(previous) => self.model.reassemble(previous),
            None => self.model.assemble(),
        }
        .map_err(DriverError::ThermalAssembly)?;
        let Block { t0, time0, steps } = b;
        let mut history = Vec::new();
        let mut extremes = None;
        let (temperature, time, balance) = if steps.is_empty() {
            let s = system.solve_steady().map_err(DriverError::Steady)?;
            (s.temperature, 0.0, s.balance)
        } else {
            let mut stepper = system
                .stepper(t0.to_vec(), time0)
                .map_err(DriverError::Transient)?;
            let analysed = match &mut self.thermal_symbolic {
                Some(a) => a,
                None => self.thermal_symbolic.insert(
                    tecon_fem::CholeskySolver::analyse(std::sync::Arc::clone(
                        system.assembler().pattern(),
                    ))
                    .map_err(|e| DriverError::Transient(e.into()))?,
                ),
            };
            stepper.share_symbolic(analysed);
            for s in steps.iter().filter(|s| s.dt > 0.0) {
                stepper
                    .step(s.dt, s.theta)
                    .map_err(DriverError::Transient)?;
                StepExtremes::observe(&mut extremes, stepper.time(), stepper.temperature());
                if !self.history_nodes.is_empty() {
                    let t = stepper.temperature();
                    history.push((
                        s.output.unwrap_or(stepper.time()),
                        self.history_nodes.iter().map(|&i| t[i]).collect(),
                    ));
                }
            }
            (
                stepper.temperature().to_vec(),
                stepper.time(),
                stepper.balance(),
            )
        };
        let element_temperature = system.element_means(&temperature);
        self.system = Some(system);
        self.thermal_seconds += clock.elapsed().as_secs_f64();
        let thermal = ThermalState {
            time: steps.last().and_then(|s| s.output).unwrap_or(time),
            temperature,
            element_temperature,
            heat_balance: Some(balance.relative_residual()),
        };
        let clock = std::time::Instant::now();
        // every attempt starts the contact from the start of the block (the
        // friction history), its iterations from the guess
        match guess {
            Guess::Start => self.contact.solver.resume(start),
            Guess::State(g) => self.contact.solver.resume_warm(start, g),
            Guess::Extrapolated { older, t_older } => {
                let w = load_weight(&thermal.temperature, t0, t_older);
                self.contact
                    .solver
                    .resume_warm(start, &start.extrapolated(older, w))
            }
        }
        .map_err(|e| DriverError::Mechanical(Box::new(e)))?;
        let stage = &self.setup.stages[0];
        // the states written are those of the blocks that end at an output
        // time (a steady block is one): only they need the stresses
        let output = steps.last().is_none_or(|s| s.output.is_some());
        // between the output times the outer loop may stop at its share of
        // the block's error budget (see `INTERMEDIATE_OUTER_SHARE`)
        let floor = match self.stats.intermediate_outer_tolerance {
            Some(f) if !output => f,
            _ => 0.0,
        };
        self.contact.solver.set_outer_tolerance_floor(floor);
        let state = self
            .contact
            .solve(0, stage, Some(&thermal), self.pb, output)?;
        self.contact_seconds += clock.elapsed().as_secs_f64();
        self.stats.iterations += 1;
        let states = interface_states(self.setup, &self.contact, &thermal.temperature);
        Ok(Attempt {
            thermal,
            balance,
            state,
            states,
            history,
            extremes,
        })
    }

    /// A block iterated until the conductances settle: `used` ← the states
    /// `target` makes of the attempt's end states.
    /// The contact solves start from `checkpoint`, the first one's
    /// iterations from `first_guess`, the later ones' from the solve before.
    #[allow(clippy::too_many_arguments)]
    fn iterate(
        &mut self,
        b: Block<'_>,
        first_used: PointStates,
        start_states: &PointStates,
        midpoint: bool,
        c: TwoWay,
        checkpoint: &SolverState,
        first_guess: Guess<'_>,
    ) -> Result<(Attempt, usize, f64), DriverError> {
        let mut used = first_used;
        let mut h_used = conductances(self.setup, &mut self.model, &used)?;
        let mut iterations = 0;
        let mut guess: Option<SolverState> = None;
        let mut relax = Aitken::default();
        loop {
            iterations += 1;
            let a = self.attempt(
                b,
                &used,
                checkpoint,
                guess.as_ref().map_or(first_guess, Guess::State),
            )?;
            guess = Some(self.contact.solver.state());
            let next = if midpoint {
                blend(start_states, &a.states, 0.5)
            } else {
                a.states.clone()
            };
            let h_next = conductances(self.setup, &mut self.model, &next)?;
            let change = max_rel_change(&h_next, &h_used);
            if change <= c.tolerance || iterations >= c.max_iterations {
                if change > c.tolerance {
                    self.stats.unsettled += 1;
                }
                return Ok((a, iterations, change));
            }
            let w = relax.factor(&h_next, &h_used);
            used = if w == 1.0 {
                next
            } else {
                blend(&used, &next, w)
            };
            h_used = conductances(self.setup, &mut self.model, &used)?;
        }
    }

    fn finish_block(&mut self, iterations: usize, change: f64) {
        self.stats.blocks += 1;
        self.stats.max_iterations = self.stats.max_iterations.max(iterations);
        self.stats.max_final_change = self.stats.max_final_change.max(change);
    }
}

/// Staggered two-way coupling (transient or steady), then the later stages.
pub(crate) fn two_way<'s>(
    setup: &'s Setup<'s>,
    th: &ThermalSetup<'s>,
    c: TwoWay,
    pb: &ProgressBar,
    history_nodes: &[usize],
) -> Result<Outcome, DriverError> {
    let model = th.model.clone();
    let system = model.assemble().map_err(DriverError::ThermalAssembly)?;
    let reference = crate::driver::stress_free_reference(setup.mesh, th, &system)?;
    let initial = system
        .initial_temperature()
        .ok_or(DriverError::NoInitialTemperature)?
        .to_vec();
    drop(system);
    let contact = Contact::new(setup, Some(reference))?;
    let mut lp = Loop {
        setup,
        model,
        contact,
        pb,
        stats: CouplingStats {
            sync_tolerance: c.sync_tolerance,
            intermediate_outer_tolerance: c.sync_tolerance.map(|t| t * INTERMEDIATE_OUTER_SHARE),
            ..CouplingStats::default()
        },
        thermal_seconds: 0.0,
        contact_seconds: 0.0,
        thermal_symbolic: None,
        history_nodes,
        system: None,
    };
    let mut history = None;
    let mut states: Vec<State> = Vec::new();
    let mut max_res: f64 = 0.0;
    let mut steps_taken = 0;

    let info = match &th.procedure {
        Procedure::Held => {
            return Err(DriverError::Coupling(
                "two-way coupling needs heat conduction: give thermal boundary conditions (steady) or a schedule (transient)".into(),
            ));
        }
        Procedure::Steady => {
            let s0 = interface_states(setup, &lp.contact, &initial);
            let block = Block {
                t0: &initial,
                time0: 0.0,
                steps: &[],
            };
            let checkpoint = lp.contact.solver.state();
            let (a, iterations, change) =
                lp.iterate(block, s0.clone(), &s0, false, c, &checkpoint, Guess::Start)?;
            lp.finish_block(iterations, change);
            max_res = a.balance.relative_residual();
            let mut state = a.state;
            state.coupling_iterations = iterations;
            debug_assert!(
                !state.stress.element.is_empty(),
                "steady state without stresses"
            );
            states.push(state);
            ThermalInfo {
                mode: ThermalMode::Steady,
                steps: 0,
                max_balance_residual: Some(max_res),
                extremes: None,
            }
        }
        Procedure::Transient {
            schedule,
            scheme,
            times,
        } => {
            let all = split_steps(schedule, *scheme, times)?;
            let mut recorded = TemperatureHistory::new(history_nodes);
            recorded.record(schedule.start(), &initial);
            let mut extremes = None;
            let mut t = initial.clone();
            let mut time = schedule.start();
            let mut first = 0;
            let mut since_output = Vec::new();
            let mut balance = HeatBalance::default();
            // interface states now and at the previous contact solve (time)
            let mut s_now = interface_states(setup, &lp.contact, &t);
            let mut previous: Option<(f64, PointStates)> = None;
            // the contact state and the temperatures at the previous block
            // start (time): the contact solves start from the state
            // extrapolated from it
            let mut older: Option<(f64, SolverState, Vec<f64>)> = None;
            // fixed: `n` steps per block; adaptive: blocks of about
            // `target` seconds (at least one step, at most MAX_BLOCK)
            let n = c.sync_interval.max(1);
            let mut target: Option<f64> = None;
            while first < all.len() {
                // a block: ending at an output time
                let mut last = first;
                let mut k = 0;
                let mut length = 0.0;
                while last < all.len() {
                    if all[last].dt > 0.0 {
                        k += 1;
                        length += all[last].dt;
                    }
                    let full = match target {
                        None => k >= n,
                        Some(d) => {
                            k >= MAX_BLOCK
                                || all
                                    .get(last + 1)
                                    .is_some_and(|s| k > 0 && length + s.dt > d * (1.0 + 1e-9))
                        }
                    };
                    if all[last].output.is_some() || full {
                        break;
                    }
                    last += 1;
                }
                let last = last.min(all.len() - 1);
                let steps = &all[first..=last];
                let span: f64 = steps.iter().map(|s| s.dt).sum();
                let block = Block {
                    t0: &t,
                    time0: time,
                    steps,
                };
                let checkpoint = lp.contact.solver.state();
                let guess = match &older {
                    Some((to, so, t_older)) if time > *to && span > 0.0 => {
                        Guess::Extrapolated { older: so, t_older }
                    }
                    _ => Guess::Start,
                };
                let (a, iterations, change) = match c.sync_tolerance {
                    None => {
                        lp.iterate(block, s_now.clone(), &s_now, false, c, &checkpoint, guess)?
                    }
                    Some(tau) => {
                        // midpoint state extrapolated from the last two solves
                        let used = match &previous {
                            Some((tp, sp)) if time > *tp && span > 0.0 => {
                                blend(sp, &s_now, 1.0 + 0.5 * span / (time - tp))
                            }
                            _ => s_now.clone(),
                        };
                        let h_used = conductances(setup, &mut lp.model, &used)?;
                        let a = lp.attempt(block, &used, &checkpoint, guess)?;
                        let mid = blend(&s_now, &a.states, 0.5);
                        let h_mid = conductances(setup, &mut lp.model, &mid)?;
                        let e = max_rel_change(&h_mid, &h_used);
                        if e > tau && k > 1 {
                            // rejected: roll back and shorten the block
                            lp.contact
                                .solver
                                .resume(&checkpoint)
                                .map_err(|e| DriverError::Mechanical(Box::new(e)))?;
                            lp.stats.rejected += 1;
                            let f = (0.9 * (tau / e).sqrt()).clamp(0.2, 0.9);
                            target = Some(span * f);
                            continue;
                        }
                        let grow = if e > 0.0 {
                            (0.9 * (tau / e).sqrt()).min(2.0)
                        } else {
                            2.0
                        };
                        if e > tau {
                            // a one-step block: iterate the midpoint state,
                            // the solves started from this one's answer
                            let solved = lp.contact.solver.state();
                            lp.contact
                                .solver
                                .resume(&checkpoint)
                                .map_err(|e| DriverError::Mechanical(Box::new(e)))?;
                            let (a, it, change) = lp.iterate(
                                block,
                                mid,
                                &s_now,
                                true,
                                c,
                                &checkpoint,
                                Guess::State(&solved),
                            )?;
                            target = Some(span * grow.max(0.2));
                            (a, it + 1, change.max(0.0))
                        } else {
                            let at_output = steps.last().is_some_and(|s| s.output.is_some());
                            target = Some(next_target(target, span, grow, at_output));
                            (a, 1, e)
                        }
                    }
                };
                lp.finish_block(iterations, change);
                recorded.extend(a.history);
                StepExtremes::merge(&mut extremes, a.extremes);
                steps_taken += steps.iter().filter(|s| s.dt > 0.0).count();
                if span > 0.0 {
                    previous = Some((time, std::mem::take(&mut s_now)));
                    older = Some((time, checkpoint, t.clone()));
                }
                time += span;
                s_now = a.states;
                let bal = a.balance;
                balance.stored_change += bal.stored_change;
                balance.convection_in += bal.convection_in;
                balance.flux_in += bal.flux_in;
                balance.prescribed_in += bal.prescribed_in;
                balance.scale += bal.scale;
                since_output.push(iterations);
                t = a.thermal.temperature;
                if steps[steps.len() - 1].output.is_some() {
                    balance.residual = balance.stored_change
                        - (balance.convection_in + balance.flux_in + balance.prescribed_in);
                    let res = balance.relative_residual();
                    max_res = max_res.max(res);
                    let mut state = a.state;
                    state.heat_balance = Some(res);
                    state.coupling_iterations = since_output.iter().copied().max().unwrap_or(0);
                    since_output.clear();
                    debug_assert!(!state.stress.element.is_empty(), "output without stresses");
                    states.push(state);
                    pb.inc(2);
                }
                first = last + 1;
            }
            if !history_nodes.is_empty() {
                history = Some(recorded);
            }
            ThermalInfo {
                mode: ThermalMode::Transient,
                steps: steps_taken,
                max_balance_residual: Some(max_res),
                extremes,
            }
        }
    };
    // Later stages (e.g. operating pressure) from the coupled history, to
    // the solver's own tolerances.
    lp.contact.solver.set_outer_tolerance_floor(0.0);
    let clock = std::time::Instant::now();
    run_stages(
        setup,
        &mut lp.contact,
        &mut ThermalFeed::ready(Vec::new()),
        1,
        &mut states,
        pb,
    )?;
    lp.contact_seconds += clock.elapsed().as_secs_f64();
    pb.finish_and_clear();
    let mut notes = lp.contact.solver.notes().to_vec();
    if lp.stats.unsettled > 0 {
        // never silently wrong: a block accepted at the iteration limit
        notes.push(format!(
            "two-way coupling: {} blocks did not settle within the limit of {} coupling iterations per block; the interface conductance still changed by up to {:.0} % between the last two (tolerance {} %), so the temperatures and contact state there carry that error (a joint point that alternates between open and closed does this; a smaller --sync-tolerance or more coupling iterations may settle it)",
            lp.stats.unsettled,
            c.max_iterations,
            100.0 * lp.stats.max_final_change,
            100.0 * c.tolerance
        ));
    }
    Ok(Outcome {
        interfaces: lp.contact.interfaces(),
        states,
        thermal: info,
        newton: lp.contact.stats(),
        notes,
        thermal_seconds: lp.thermal_seconds,
        contact_seconds: lp.contact_seconds,
        coupling: Some(lp.stats),
        bound_violation: None,
        history,
    })
}

#[cfg(test)]
mod tests {
    use super::{Aitken, MAX_GUESS_WEIGHT, load_weight, next_target};

    /// Iterates x ← x + ω (g(x) − x) with Aitken's ω until |g(x) − x| ≤ 1e-12;
    /// returns the iterations and the final x.
    fn relaxed(g: impl Fn(f64) -> f64, x0: f64) -> (usize, f64) {
        let mut relax = Aitken::default();
        let mut x = x0;
        for k in 1..=100 {
            let gx = g(x);
            if (gx - x).abs() <= 1e-12 {
                return (k, x);
            }
            let w = relax.factor(&[gx], &[x]);
            x += w * (gx - x);
        }
        (usize::MAX, x)
    }

    #[test]
    fn the_guess_weight_fits_the_temperature_change() {
        let older = [20.0, 40.0, 60.0];
        let start = [21.0, 38.0, 63.0];
        // the same change again, scaled by 0.4: the fit recovers the scale
        let end: Vec<f64> = start
            .iter()
            .zip(&older)
            .map(|(s, o)| s + 0.4 * (s - o))
            .collect();
        assert!((load_weight(&end, &start, &older) - 0.4).abs() < 1e-14);
        // a change orthogonal to the last one: no extrapolation
        let end = [start[0] + 2.0, start[1] + 1.0, start[2]];
        assert!(load_weight(&end, &start, &older).abs() < 1e-14);
        // a reversal is not extrapolated backwards, a jump is capped
        let back: Vec<f64> = start.iter().zip(&older).map(|(s, o)| s - (s - o)).collect();
        assert_eq!(load_weight(&back, &start, &older), 0.0);
        let jump: Vec<f64> = start
            .iter()
            .zip(&older)
            .map(|(s, o)| s + 10.0 * (s - o))
            .collect();
        assert_eq!(load_weight(&jump, &start, &older), MAX_GUESS_WEIGHT);
        // no change in the block before: no direction to extrapolate along
        assert_eq!(load_weight(&end, &start, &start), 0.0);
    }

    #[test]
    fn a_block_short_of_its_target_by_a_step_still_lets_the_next_grow() {
        // 20 s steps, target 25.4 s: the block is one step (a second would
        // overshoot); with a small error the next target is 40 s (two
        // steps), not 25.4 s again (which kept every block at one step
        // from 100 s to 1000 s of the vessel's schedule)
        assert_eq!(next_target(Some(25.4), 20.0, 2.0, false), 40.0);
        // a large error shortens it
        assert_eq!(next_target(Some(25.4), 20.0, 0.5, false), 10.0);
        // cut short by an output time: the target stands (or shrinks)
        assert_eq!(next_target(Some(25.4), 20.0, 2.0, true), 25.4);
        assert_eq!(next_target(Some(25.4), 20.0, 0.5, true), 10.0);
        // a block that reached its target at an output time grows as usual
        assert_eq!(next_target(Some(20.0), 20.0, 2.0, true), 40.0);
        assert_eq!(next_target(None, 0.02, 2.0, false), 0.04);
    }

    #[test]
    fn aitken_settles_a_map_that_the_plain_iteration_cycles_or_diverges_on() {
        // slope −1: the plain iteration alternates 0, 2, 0, 2, … for ever
        let (k, x) = relaxed(|x| 2.0 - x, 0.0);
        assert!(k <= 3, "{k} iterations");
        assert!((x - 1.0).abs() < 1e-12, "{x}");
        // slope −3: the plain iteration diverges; Aitken needs one secant step
        let (k, x) = relaxed(|x| 4.0 - 3.0 * x, 0.0);
        assert!(k <= 3, "{k} iterations");
        assert!((x - 1.0).abs() < 1e-12, "{x}");
        // a nonlinear map with slope −2.2 at its fixed point x* = 1
        let g = |x: f64| 1.0 - 2.2 * (x - 1.0) + 0.3 * (x - 1.0).powi(2);
        let (k, x) = relaxed(g, 1.3);
        assert!(k <= 12, "{k} iterations");
        assert!((x - 1.0).abs() < 1e-11, "{x}");
    }

    #[test]
    fn aitken_never_turns_an_unstable_fixed_point_into_an_attractor() {
        // slope +2 at x* = 1: ω ∈ [0.05, 1] keeps the relaxed map's slope
        // 1 + ω (g′ − 1) > 1, so the iteration still leaves x* (a steady state
        // that a transient cannot reach is not reported as the answer)
        let (k, x) = relaxed(|x| 1.0 + 2.0 * (x - 1.0), 1.001);
        assert_eq!(k, usize::MAX);
        assert!((x - 1.0).abs() > 0.001, "{x}");
    }

    #[test]
    fn aitken_keeps_a_converging_iteration_plain() {
        // slope +0.5: the residuals shrink monotonically; ω stays ≤ 1 and
        // the iteration converges as fast as the plain one or faster
        let (k, x) = relaxed(|x| 0.5 * x + 0.5, 0.0);
        assert!(k <= 42, "{k} iterations");
        assert!((x - 1.0).abs() < 1e-11, "{x}");
    }
}
