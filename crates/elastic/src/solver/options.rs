//! Loads, solver settings and what an increment reports.

use tecon_contact::{ContactStatus, FrictionBound};

use crate::error::IterationRecord;

/// The loads of one state, all scaled by the solver's load path.
#[derive(Debug, Clone, PartialEq)]
pub struct Loads {
    /// Temperature change (K); empty means zero everywhere.
    ///
    /// * Order-1 mesh: one value per element, `T_e − T_ref,e`
    ///   (`n_triangles` values).
    /// * Order-2 mesh: six values per element, element-major, in the node
    ///   order of `Mesh::triangles6()`: `delta_t[6e + a] = T_a − T_ref,e`,
    ///   the temperature of the element's node `a` less the element's own
    ///   stress-free reference, so that a weld element keeps its eigenstrain
    ///   jump at nodes it shares with its neighbours (`6 · n_triangles`
    ///   values). The kernels interpolate them to the integration points.
    ///
    /// Any other length is an error of [`crate::StaticSolver::advance`]
    /// naming the expected lengths.
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

    /// Loads `a + s (b − a)`; `n` values of ΔT (when either has any).
    pub(crate) fn lerp(a: &Loads, b: &Loads, s: f64, n: usize) -> Loads {
        let dt = |l: &Loads, e: usize| l.delta_t.get(e).copied().unwrap_or(0.0);
        Loads {
            delta_t: if a.delta_t.is_empty() && b.delta_t.is_empty() {
                Vec::new()
            } else {
                (0..n)
                    .map(|e| dt(a, e) + s * (dt(b, e) - dt(a, e)))
                    .collect()
            },
            pressure: a.pressure + s * (b.pressure - a.pressure),
            displacement: a.displacement + s * (b.displacement - a.displacement),
            body_force: a.body_force + s * (b.body_force - a.body_force),
        }
    }
}

/// Default [`SolverOptions::pass_forcing`]. Measured on the vessel (Newton
/// iterations of whole runs, frictional joints, μ = 0.3, 1 and 2 on paper,
/// levels 2 and 4, `t1e5`, g0 and the two-way g0): 0.03 after the first
/// pass and 3e-3 in it lowered every total but two (g0 at μ = 0.3 and
/// level 2 at μ = 0.3 within ±2 %): `t1e5` at μ = 2 1 561 → 1 103, μ = 1
/// 353 → 256, two-way g0 2 489 → 2 120. The same forcing in the first pass
/// as in the later ones raised some totals at 0.03 (g0 at μ = 1 464 →
/// 632) and most at 0.1: the first pass finds the contact zone of the new
/// load, and an update from a zone far from settled undoes much of it.
pub const PASS_FORCING: f64 = 0.03;

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
    /// Opening-front and stick prediction in the Newton passes (see the
    /// solver's `front` module): steps that open the points ahead of an
    /// opening front together, and that try closed points whose slip just
    /// reversed as sticking, kept only when they are descent steps. The
    /// converged answer is the same either way; only the path changes.
    pub front_prediction: bool,
    /// Secant slip damping in the Newton passes, as a fallback: once a
    /// status pattern repeats two iterates later (ping-pong), points whose
    /// stick/slip status oscillates take the secant shear stiffness
    /// `k_s s/|τ_trial|` in the tangent (never in the residual) until the
    /// statuses settle. The converged answer is the same either way; only
    /// the path of a pass that would ping-pong changes.
    pub slip_damping: bool,
    /// Newton passes on the interface dofs alone, the bulk condensed onto
    /// them once (see the solver's `condensed` module), where that is
    /// cheaper than the full passes. The converged answer is the same
    /// either way (to the tolerances); only the cost changes.
    pub condensation: bool,
    /// With condensed passes: the first pass of an increment that starts
    /// far from equilibrium (relative residual ≥ 1e-2), with no frozen
    /// slip limit above zero (frictionless joints, or a frictional joint's
    /// first increment from the unloaded state), is preceded by
    /// Newton steps in a coarse space of fields smooth along the interface
    /// (every 2nd, 4th, … face node; see the solver's `coarse` module),
    /// which move an opening front by a coarse segment per step. The
    /// converged answer is the same either way (to the tolerances); only
    /// the path changes.
    /// The coarse steps are counted apart from the Newton iterations
    /// ([`IncrementReport::coarse_iterations`]).
    pub coarse_space: bool,
    /// Coarse levels of the coarse iteration before a first pass without
    /// any slip limit (frictionless joints): the finest spacing within the
    /// coarse system's size cap, and `coarse_levels − 1` more, each four
    /// times as wide, taken coarsest first. A joint with a friction
    /// coefficient or a cohesion takes the finest level alone. Default
    /// [`COARSE_LEVELS`] (1: the finest level alone).
    pub coarse_levels: u32,
    /// The coupled tail of the outer loop under frozen friction limits:
    /// once a pass solved exactly changes no status after its first
    /// iterate, the outer updates are in their linear regime, where the
    /// frozen limits converge by a constant factor per update (about ½ at
    /// μ = 1). The rest of the increment then takes Newton passes with the
    /// coupled law (the slip limit follows the current pressure; the
    /// non-symmetric steps by GMRES preconditioned with the frozen
    /// tangent), whose fixed point is the same Coulomb solution; only the
    /// normal multipliers are updated between them. A coupled pass that
    /// does not converge within [`COUPLED_TAIL_MAX_ITERATIONS`] hands the
    /// increment back to the frozen passes. The converged answer is the
    /// same either way (to the outer loop's tolerance); only the path
    /// changes. False also turns off [`SolverOptions::early_coupled_pass`].
    pub coupled_tail: bool,
    /// With [`SolverOptions::coupled_tail`]: at a friction coefficient of
    /// at least 1, one coupled pass early in the increment, once a frozen
    /// pass ends with at most a quarter of its closed points sticking; the
    /// frozen passes then go on from its pressures (the same fixed point).
    /// Measured on the vessel's high-friction runs (docs/vessel.md §6):
    /// level 4 at μ = 2 216 → 40 Newton iterations in one increment; where
    /// the coupled pass does not converge its 20 iterations are lost (the
    /// two-ring test of the coupled tail, μ = 1: 47 iterations against 23
    /// without it).
    pub early_coupled_pass: bool,
    /// Inexact passes under frozen friction limits: a Newton pass that an
    /// outer update will follow may stop once its residual is below this ×
    /// the residual it started from, statuses still changing (points near
    /// their stick/slip kink chatter there for tens of iterations at a
    /// residual the next update moves far more); the update then follows
    /// at once. The pass whose update changes nothing is solved to the full
    /// tolerances, so the converged answer is the same (to them); 0 solves
    /// every pass fully. The first pass of an increment takes a tenth of
    /// it.
    pub pass_forcing: f64,
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
            front_prediction: true,
            slip_damping: true,
            condensation: true,
            coarse_space: true,
            coarse_levels: COARSE_LEVELS,
            coupled_tail: true,
            early_coupled_pass: true,
            pass_forcing: PASS_FORCING,
        }
    }
}

/// What one converged increment took.
#[derive(Debug, Clone, PartialEq)]
pub struct IncrementReport {
    /// Load fraction reached (within the `advance` call).
    pub fraction: f64,
    /// Newton iterations of the increment, counting all of its passes.
    pub iterations: usize,
    /// Most Newton iterations of one pass (each augmented-Lagrangian update
    /// starts a new pass from the converged state).
    pub max_pass_iterations: usize,
    /// Augmented-Lagrangian updates made.
    pub augmentations: usize,
    /// Iteration history of every Newton pass of the increment, in order
    /// (the last one is [`IncrementReport::history`]).
    pub passes: Vec<Vec<IterationRecord>>,
    /// Iteration history of the last Newton pass.
    pub history: Vec<IterationRecord>,
    /// Failed attempts (and why) cut back before this increment converged.
    pub cutbacks: Vec<String>,
    /// Newton iterations of those failed attempts (not in `iterations`).
    pub failed_iterations: usize,
    /// Newton steps in the coarse interface space before the increment's
    /// first pass (condensed passes; see [`SolverOptions::coarse_space`]),
    /// not in `iterations`.
    pub coarse_iterations: usize,
    /// The increment was solved by the coupled Mohr–Coulomb Newton (the
    /// slip limit a function of the current pressure, non-symmetric
    /// tangent) after the outer loop of the frozen limits stalled.
    pub coupled: bool,
    /// The passes (indices into `passes`) with the coupled law in the tail
    /// of the outer loop (see [`SolverOptions::coupled_tail`]), a failed
    /// one included, and the early coupled passes.
    pub coupled_tail_passes: Vec<usize>,
    /// Of those, the early coupled passes (see
    /// [`SolverOptions::early_coupled_pass`]), a failed one included.
    pub early_coupled_passes: Vec<usize>,
    /// Multiplier updates replaced by the Anderson mix of the last few
    /// (settled statuses: see the solver's outer loop).
    pub mixed_multiplier_updates: usize,
}

/// Default of [`SolverOptions::coarse_levels`]. A frictionless first pass
/// takes Newton steps on each level, coarsest first, then the fine ones.
/// Measured on the vessel, frictionless (most Newton iterations in one
/// increment / in one pass, and the coarse steps of the run; one level →
/// two levels four times as wide apart): level 2 12 / 7 → 11 / 6 (32 →
/// 63), level 3 10 / 8 → 11 / 8, level 4 20 / 18 → 12 / 9 (62 → 83),
/// level 5 15 / 10 → 17 / 11, `x12` 13 / 10 → 13 / 8, `t1e5` 14 / 12 →
/// 14 / 9 (74 → 103; 0.94× the wall time), `t3e5` 28 / 26 → 17 / 9,
/// `t1e6` 21 / 15 → 23 / 17: the worst pass 26 → 17, the mean of the
/// worst passes 13.3 → 9.6, the fine iterations of the eight runs 496 →
/// 466; the two quarter rings of the elastic tests (256 segments) 5 → 7
/// in the first pass. Two levels twice as wide apart: level 2, 4 and
/// `t1e5` 12 / 7, 13 / 11, 14 / 8; three levels four times apart 11 / 7,
/// 12 / 9, 14 / 11. A joint with slip limits keeps the finest level alone:
/// the high-friction counts, which depend on where the first pass ends,
/// moved either way (level 4 at μ = 1: 50 → 71 in one increment; `t1e5`
/// at μ = 1: 171 → 72).
pub const COARSE_LEVELS: u32 = 2;

/// Most Newton iterations of one pass in the coupled tail of the outer
/// loop (see [`SolverOptions::coupled_tail`]): one that needs more hands
/// the increment back to the frozen passes.
pub const COUPLED_TAIL_MAX_ITERATIONS: usize = 20;

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
    /// The joint's cohesion is gone here for good (debonded; see
    /// `tecon_contact::JointState::cohesion_lost`).
    pub debonded: bool,
}
