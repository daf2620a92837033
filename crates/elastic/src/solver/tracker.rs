//! The bookkeeping of one Newton pass, shared by the full and the condensed
//! iteration: the history, the counted status changes, the convergence
//! test, the ping-pong and stagnation guards, the secant slip damping and
//! the reach of the opening-front prediction.

use crate::error::{ElasticError, IterationRecord};

use super::*;

/// What one iterate's statuses and residual say.
pub(super) struct Observation {
    /// Converged: stop with this iterate.
    pub done: bool,
    /// Statuses of the iterate.
    pub status: Vec<PointStatus>,
    /// Open / stick / slip counts.
    pub counts: [usize; 3],
}

/// A Newton step whose energy line search expanded it to at least this
/// (doubling from the full step while the energy still fell) and that
/// changed the displacement by at least [`DRIFT_CORRECTION`] of itself
/// has found a direction along which the pass's frozen problem has no
/// minimum nearby: a body held by friction alone (a ring of the
/// multilayer vessel turning about the axis) whose frozen slip limits,
/// set from the pressures of the last outer update, cannot hold it. Such
/// a pass never came back: on the five-layer vessel (`tecon vessel
/// --layers 5`) two passes of stage 5 went on for 150 iterations each
/// (302 of the 442 in the increment at t = 1 s) before the outer loop's
/// fallbacks for a failed pass (the update undone, the limits relaxed)
/// took over and converged. The pass now fails at that step and the
/// fallbacks act at once: 144 iterations in that increment, the answers
/// the same to the last digit. A long step of round-off size (step 32 at
/// a relative change of 1e-12, at convergence) is left alone.
const DRIFT_STEP: f64 = 16.0;

/// See [`DRIFT_STEP`].
const DRIFT_CORRECTION: f64 = 0.1;

pub(super) struct PassTracker {
    pub history: Vec<IterationRecord>,
    prev: Option<Vec<(PointStatus, f64)>>,
    prev2: Option<Vec<PointStatus>>,
    /// The last observed iterate's statuses, `prev` once its step is taken.
    prev_pending: Option<Vec<(PointStatus, f64)>>,
    ping_pong: usize,
    short_steps: usize,
    /// The force scale of this increment: the largest external or internal
    /// force norm seen so far (the internal force alone can vanish, e.g.
    /// when bodies separate and move rigidly).
    pub reference: f64,
    /// Front prediction (see `front`): the fronts of the last prediction
    /// (their predicted points and reach), and the reach each flat point
    /// carries into the next one (0: none), doubled where a front's
    /// predicted points all opened, halved where they did not.
    fronts: Vec<(Vec<usize>, usize)>,
    carry: Vec<usize>,
    /// The same for the slip fronts (see `front::predicted_slips`).
    slip_fronts: Vec<(Vec<usize>, usize)>,
    slip_carry: Vec<usize>,
    /// Points whose stick/slip status oscillated in this pass: their
    /// slipping tangent is the secant one from then on.
    pub damped: Vec<bool>,
    /// The damping is a fallback: it starts at the first status pattern
    /// repeated two iterates later (a pass that converges without a
    /// repeat keeps the exact path, bit for bit), and the ping-pong guard
    /// then counts afresh, once.
    damping: bool,
    /// Points already tried as sticking in this pass.
    stick_tried: Vec<bool>,
    /// Points that slip at the iterate of the last short step and that
    /// its full step made stick or reversed (see `short_step`).
    stick_at_full: Vec<usize>,
    pass: usize,
    /// Inexact pass: the residual below which it may stop with statuses
    /// still changing, as a multiple of the residual of its first iterate
    /// (0: an exact pass), and whether it stopped there.
    forcing: f64,
    loose: f64,
    /// The round-off floor at the first iterate of the pass.
    floor0: f64,
    pub inexact: bool,
}

impl PassTracker {
    pub fn new(f_ext_norm: f64, pass: usize) -> Self {
        PassTracker {
            history: Vec::new(),
            prev: None,
            prev2: None,
            prev_pending: None,
            ping_pong: 0,
            short_steps: 0,
            reference: f_ext_norm.max(f64::MIN_POSITIVE),
            fronts: Vec::new(),
            carry: Vec::new(),
            slip_fronts: Vec::new(),
            slip_carry: Vec::new(),
            damped: Vec::new(),
            damping: false,
            stick_tried: Vec::new(),
            stick_at_full: Vec::new(),
            pass,
            forcing: 0.0,
            loose: 0.0,
            floor0: 0.0,
            inexact: false,
        }
    }

    /// This pass may stop once its residual is below `forcing` × that of
    /// its first iterate (see [`SolverOptions::pass_forcing`]).
    pub fn with_forcing(mut self, forcing: f64) -> Self {
        self.forcing = forcing;
        self
    }

    /// Records an iterate: its statuses (with the traction each point
    /// carries), relative residual, round-off floor (or a bound of it below
    /// the tolerance: `floor_is_bound`) and tolerance. Fails on status
    /// ping-pong.
    pub fn observe(
        &mut self,
        status_t: Vec<(PointStatus, f64)>,
        rel: f64,
        (floor, floor_is_bound): (f64, bool),
        tolerance: f64,
        opts: &SolverOptions,
    ) -> Result<Observation, ElasticError> {
        let it = self.history.len();
        // A status change counts only where the point carries traction
        // before or after it: points at zero load (e.g. far from a local
        // thermal load) flip between touching and open at round-off level.
        let t_max = status_t.iter().map(|s| s.1).fold(0.0, f64::max);
        let changed = match &self.prev {
            Some(p) => p
                .iter()
                .zip(&status_t)
                .filter(|(a, b)| a.0 != b.0 && a.1.max(b.1) > STATUS_TRACTION_FLOOR * t_max)
                .count(),
            None => status_t.len(),
        };
        let status: Vec<PointStatus> = status_t.iter().map(|s| s.0).collect();
        if self.prev2.as_ref().is_some_and(|p2| *p2 == status) && changed > 0 {
            self.ping_pong += 1;
            if !self.damping && opts.slip_damping {
                self.damping = true;
                self.ping_pong = 0;
            }
        }
        // A point back where it was two iterates ago, via another status,
        // with slip on one side: the exact slip tangent (0) sends it across
        // the kink again and the line search stops it there — a zigzag of
        // short steps (high friction). Such points take the secant slip
        // stiffness k_s s/|τ_trial| until the statuses settle: a positive
        // definite tangent, so still a descent direction for the exact
        // energy line search, and the converged answer does not change.
        if let (Some(p), Some(p2)) = (&self.prev, &self.prev2) {
            self.damped.resize(status.len(), false);
            for (i, s) in status.iter().enumerate() {
                let was = p[i].0;
                if *s == p2[i] && *s != was && (s.1 != 0 || was.1 != 0) {
                    self.damped[i] = true;
                }
            }
        }
        let counts = count(&status);
        let last_correction = self.history.last().map_or(f64::INFINITY, |h| h.correction);
        // After a full step with no status change the linearisation was
        // exact (the problem is piecewise linear), so the residual alone
        // measures the error; otherwise the correction must be small too.
        let full_step = self.history.last().is_some_and(|h| h.step == 1.0);
        let converged = it > 0
            && rel <= tolerance
            && changed == 0
            && (last_correction <= opts.correction_tolerance
                || rel <= tolerance * 1e-3
                || full_step);
        if it == 0 {
            self.loose = self.forcing * rel;
            self.floor0 = floor;
        }
        // An inexact pass stops once it is well below where it started,
        // unless the iterate has moved so far that its round-off floor has
        // grown past the tolerance (a body drifting along a mode that
        // friction alone holds; see [`DRIFT_FLOOR_GROWTH`]).
        let loose = !converged
            && it > 0
            && self.loose > tolerance
            && rel <= self.loose
            && floor
                <= opts
                    .residual_tolerance
                    .max(DRIFT_FLOOR_GROWTH * self.floor0);
        self.inexact = loose;
        self.history.push(IterationRecord {
            pass: self.pass,
            iteration: it,
            residual: rel,
            correction: 0.0,
            step: 0.0,
            status: counts,
            changed,
            floor,
            floor_is_bound,
            predicted: [0; 4],
            rejected: false,
            inexact: loose,
        });
        if !rel.is_finite() {
            // no step can mend an overflow: Newton would iterate on NaN to
            // its limit
            return Err(failure(
                format!(
                    "the residual is not finite ({rel}) at iteration {it}: a load, temperature or material value overflows double precision"
                ),
                std::mem::take(&mut self.history),
            ));
        }
        let done = converged || loose || (rel == 0.0 && changed == 0);
        if !done && self.ping_pong > opts.max_ping_pong {
            return Err(failure(
                format!("contact status ping-pong ({} repeats)", self.ping_pong),
                std::mem::take(&mut self.history),
            ));
        }
        if changed == 0 {
            // statuses settled: the exact tangent converges in one step
            // (the secant one only linearly)
            self.damped.fill(false);
        }
        self.prev_pending = Some(status_t);
        Ok(Observation {
            done,
            status,
            counts,
        })
    }

    /// The flat points whose tangent takes the secant slip stiffness, if
    /// the damping is on and any point needs it.
    pub fn damped_points(&self) -> Option<&[bool]> {
        (self.damping && self.damped.iter().any(|&d| d)).then_some(&self.damped[..])
    }

    /// The points the next step tries on its predicted branch (see
    /// `front`): `[open, stick, slip]` — ahead of the opening fronts, the
    /// reversed or full-step sticking points, ahead of the slip fronts.
    /// None when not `enabled` (the predicted branches need a symmetric
    /// tangent).
    pub fn predictions(
        &mut self,
        neighbours: &[Vec<Vec<usize>>],
        per_element: &[usize],
        status: &[PointStatus],
        enabled: bool,
    ) -> [Vec<usize>; 3] {
        let open = self.predicted_openings(neighbours, per_element, status, enabled);
        let stick = if enabled {
            self.stick_predictions(status)
        } else {
            Vec::new()
        };
        let slip = self.predicted_slips(neighbours, per_element, status, enabled);
        [open, stick, slip]
    }

    /// Points predicted open ahead of the fronts (see `front`).
    fn predicted_openings(
        &mut self,
        neighbours: &[Vec<Vec<usize>>],
        per_element: &[usize],
        status: &[PointStatus],
        enabled: bool,
    ) -> Vec<usize> {
        predict_fronts(
            &self.prev,
            (&mut self.carry, &mut self.fronts),
            enabled,
            |before, carry| {
                front::predicted_openings(neighbours, per_element, before, status, carry)
            },
        )
    }

    /// Sticking points predicted to slip ahead of the slip fronts (see
    /// `front::predicted_slips`).
    fn predicted_slips(
        &mut self,
        neighbours: &[Vec<Vec<usize>>],
        per_element: &[usize],
        status: &[PointStatus],
        enabled: bool,
    ) -> Vec<usize> {
        // Only after a full step, and in a long pass (the gate of the
        // stick predictions). Where the line search cuts the steps short,
        // the statuses change for other reasons (an opening front,
        // reversing slips), and slip predictions there were kept with
        // steps of nearly 0 (two-way g0: 1 493 → 1 556 Newton iterations,
        // 124 → 215 factorisations). Without the gate μ = 0.3 changed
        // (`t1e5` 92 → 94, level 4 99 → 97 iterations) and the
        // two-way g0 took 179 factorisations; with it μ = 0.3 is the same
        // byte for byte and the full-step slip fronts of high friction
        // (tens of iterations) reach the gate anyway. Since session 40 a
        // short pass predicts as well once its front creeps: two full
        // steps in a row that both changed statuses (the two-way g0's
        // solves between the output times lost a stick zone two or three
        // points per full step: 1 487 → 1 443 Newton iterations; the 30
        // runs of `predicted_slips` 10 119 → 10 032, μ = 0.3 the same but
        // level 4, 99 → 100).
        let n = self.history.len();
        let creeping = n >= 3 && self.history[n - 3].step == 1.0 && self.history[n - 2].changed > 0;
        let full = n >= 2
            && self.history[n - 2].step == 1.0
            && (self.predicts_from_full_steps() || creeping);
        predict_fronts(
            &self.prev,
            (&mut self.slip_carry, &mut self.slip_fronts),
            enabled && full,
            |before, carry| front::predicted_slips(neighbours, per_element, before, status, carry),
        )
    }

    /// The points tried as sticking in the next step (see `front`): the
    /// closed points whose slip reversed in the last step
    /// ([`PassTracker::reversed_points`]) and, in a long pass, those that
    /// the full Newton step would have made stick or reversed (see
    /// [`PassTracker::short_step`]).
    pub fn stick_predictions(&mut self, status: &[PointStatus]) -> Vec<usize> {
        let mut out = self.reversed_points(status);
        out.append(&mut self.stick_at_full);
        out.sort_unstable();
        out.dedup();
        out
    }

    /// True once the pass is long enough for [`PassTracker::short_step`]
    /// to predict: the callers evaluate the laws at the full step only then.
    pub fn predicts_from_full_steps(&self) -> bool {
        self.history.len() >= FULL_STEP_PREDICTION_AFTER
    }

    /// The line search cut the last step short (`step` < 1) at an iterate
    /// with the statuses `now`; `at_full`: the statuses at the end of the
    /// full Newton step. From the [`FULL_STEP_PREDICTION_AFTER`]-th
    /// iteration of a pass on, the points that slide now and that the full
    /// step makes stick, or slide the other way, are tried as sticking in
    /// the next step. Sliding: closed and slipping, or open and sliding on
    /// a frozen limit (the friction part of the limit stays while the
    /// faces open; such points reverse among the slipping ones where a
    /// stick zone forms, and counting them, since session 39, cut the 30
    /// runs of `front::predicted_slips` from 10 610 to 10 119 Newton
    /// iterations, level 4 at μ = 1 from 53 / 26 to 42 / 21 in one
    /// increment / pass; μ = 0.3 the same).
    ///
    /// Why: where a stick zone forms (high friction, the pass after an
    /// update of the frozen limits), the exact energy line search stops
    /// where the first slipping point whose slip the step reverses enters
    /// its stick band (2 s/k_s wide), and the stick zone grows by about one
    /// point per iteration (`t1e5` at μ = 1: 117 iterations in one pass
    /// while about 60 points come to stick). A step cut to a few per cent
    /// ends far past the band, so a reversal there marks a point as surely
    /// as a stick status. Short passes (low friction) do not need it and
    /// took longer paths with it (μ = 0.3: level 4 11 → 19 iterations in
    /// one pass), hence the gate.
    pub fn short_step(&mut self, now: &[PointStatus], at_full: &[(PointStatus, f64)]) {
        if !self.predicts_from_full_steps() {
            return;
        }
        self.stick_at_full = now
            .iter()
            .zip(at_full)
            .enumerate()
            .filter(|(_, (n, f))| {
                // sliding now (closed or open), sticking or sliding the
                // other way at the full step
                n.1 != 0 && (f.0.0 == ContactStatus::Stick || f.0.1 * n.1 < 0)
            })
            .map(|(i, _)| i)
            .collect();
    }

    /// Closed points whose slip direction reversed in the last step, each
    /// at most once per pass and none once the secant damping is on: they
    /// are tried as sticking in the next step (see `front`). A point tried
    /// once that reverses again is left to the exact step and the damping.
    /// (Open points sliding on a frozen limit taken as well, session 39:
    /// over the 30 runs of `front::predicted_slips` 10 119 → 9 879 Newton
    /// iterations, but μ = 0.3 changed — g0 91 → 97 — and level 2 at μ = 6
    /// took 7 994 iterations in 124 increments instead of 537 in 6.)
    fn reversed_points(&mut self, status: &[PointStatus]) -> Vec<usize> {
        let Some(p) = &self.prev else {
            return Vec::new();
        };
        if self.damping {
            // the pass has met a status ping-pong: the secant damping
            // handles the oscillating points (with stick predictions on
            // top, μ = 5 on the paper mesh no longer converged)
            return Vec::new();
        }
        self.stick_tried.resize(status.len(), false);
        let out: Vec<usize> = status
            .iter()
            .zip(p)
            .enumerate()
            .filter(|(i, (s, q))| {
                s.0 == ContactStatus::Slip && s.1 * q.0.1 < 0 && !self.stick_tried[*i]
            })
            .map(|(i, _)| i)
            .collect();
        for &i in &out {
            self.stick_tried[i] = true;
        }
        out
    }

    /// A predicted step of `n` points (to open, stick, slip, close) was kept;
    /// `at_end`: the statuses at its end. Each opening or slip front
    /// reaches twice or half as far next time (see [`next_reach`]).
    pub fn kept_prediction(&mut self, n: [usize; 4], at_end: &[PointStatus]) {
        let fronts = std::mem::take(&mut self.fronts);
        self.carry = next_reach(fronts, at_end, ContactStatus::Open);
        let fronts = std::mem::take(&mut self.slip_fronts);
        self.slip_carry = next_reach(fronts, at_end, ContactStatus::Slip);
        if let Some(h) = self.history.last_mut() {
            h.predicted = n;
        }
    }

    /// A predicted step of `n` points (to open, stick, slip, close) was
    /// discarded: the trial cost a solve, so it counts as an iteration.
    /// True if that used up the iterations of the pass.
    pub fn rejected_prediction(&mut self, n: [usize; 4], max_iterations: usize) -> bool {
        // every front starts again from reach 1
        self.fronts.clear();
        self.carry.clear();
        self.slip_fronts.clear();
        self.slip_carry.clear();
        if let Some(mut again) = self.history.last().cloned() {
            if let Some(h) = self.history.last_mut() {
                h.predicted = n;
                h.rejected = true;
            }
            again.iteration += 1;
            self.history.push(again);
        }
        self.history.len() >= max_iterations
    }

    /// Records the step taken from the last iterate (its relative size
    /// `correction`), after the stagnation guard: Newton that only creeps
    /// (the line search keeps cutting while no status changes) will not
    /// converge, so the increment is given back early to be cut. Short
    /// steps that move a stick/slip or contact front by a point or two are
    /// progress.
    pub fn stepped(&mut self, step: f64, correction: f64) -> Result<(), ElasticError> {
        let changed = self.history.last().map_or(0, |h| h.changed);
        self.short_steps = if step < 0.2 && changed == 0 {
            self.short_steps + 1
        } else {
            0
        };
        if self.short_steps >= 4 {
            return Err(failure(
                "the line search keeps cutting the Newton step (stagnation)",
                std::mem::take(&mut self.history),
            ));
        }
        if let Some(h) = self.history.last_mut() {
            h.correction = correction;
            h.step = step;
        }
        self.prev2 = self
            .prev
            .take()
            .map(|p: Vec<(PointStatus, f64)>| p.iter().map(|s| s.0).collect());
        self.prev = self.prev_pending.take();
        Ok(())
    }

    /// Fails the pass if its last step drifted (see [`DRIFT_STEP`]): the
    /// failure goes to the outer loop's fallbacks as it is (not turned
    /// into a floating body: the drift, not the iterate it reached, is
    /// what went wrong).
    pub fn check_drift(&mut self) -> Result<(), ElasticError> {
        let Some(h) = self.history.last() else {
            return Ok(());
        };
        let (step, correction) = (h.step, h.correction);
        if step >= DRIFT_STEP && correction >= DRIFT_CORRECTION {
            return Err(failure(
                format!(
                    "a body drifts: the energy fell along the Newton direction to a line-search step of {step} and the displacement changed by {correction:.2} of itself (a body held by friction alone that its frozen slip limits cannot hold)"
                ),
                std::mem::take(&mut self.history),
            ));
        }
        Ok(())
    }
}

/// Fronts from the statuses before the last step and now (`predict`,
/// given those and the reach each point carries), stored in `fronts`;
/// none before the first step or when not `enabled`. A prediction that
/// makes no front keeps the carried reach for the next one. Returns the
/// predicted points, sorted.
fn predict_fronts(
    prev: &Option<Vec<(PointStatus, f64)>>,
    (carry, fronts): (&mut Vec<usize>, &mut Vec<(Vec<usize>, usize)>),
    enabled: bool,
    predict: impl FnOnce(&[PointStatus], &[usize]) -> Vec<(Vec<usize>, usize)>,
) -> Vec<usize> {
    let carried = std::mem::take(carry);
    *fronts = match prev {
        Some(p) if enabled => {
            let before: Vec<PointStatus> = p.iter().map(|s| s.0).collect();
            predict(&before, &carried)
        }
        _ => Vec::new(),
    };
    if fronts.is_empty() {
        // no prediction made: the reach waits for the next front
        *carry = carried;
    }
    let mut all: Vec<usize> = fronts.iter().flat_map(|f| f.0.iter().copied()).collect();
    all.sort_unstable();
    all
}

/// The reach each flat point carries into the next prediction: a front
/// whose predicted points all reached `target` at the end of the step looks
/// twice as far ahead next time; one that was not reached by all of them
/// is near: half as far.
fn next_reach(
    fronts: Vec<(Vec<usize>, usize)>,
    at_end: &[PointStatus],
    target: ContactStatus,
) -> Vec<usize> {
    let mut carry = vec![0; at_end.len()];
    for (points, reach) in fronts {
        let next = if points.iter().all(|&i| at_end[i].0 == target) {
            2 * reach
        } else {
            (reach / 2).max(1)
        };
        for i in points {
            carry[i] = carry[i].max(next);
        }
    }
    carry
}

/// How far the round-off floor of an iterate may grow from the pass's
/// first before an inexact pass may no longer stop early: a floor above
/// the Newton tolerance that grew within the pass is a body drifting
/// along a mode that friction alone holds (a multilayer ring: stopped
/// early there, one stage of the five-layer ring took 251 iterations).
/// A floor that is merely above the tolerance from the start is the
/// mesh's (its stiffness times its displacements: `t1e5` 2.6e-8 against
/// the tolerance 1e-8 from t = 600 s on), and the test on the tolerance
/// alone kept every pass of `t1e5` exact there while level 4's stopped
/// early (session 42: `t1e5` at μ = 2 43 / 23 → 30 / 13 in one increment
/// / pass, at μ = 1.5 35 / 18 → 30 / 13; every other run of the 30
/// unchanged, μ ≤ 1 bit for bit).
const DRIFT_FLOOR_GROWTH: f64 = 2.0;

/// Iterations of a pass after which the statuses at the end of a full
/// Newton step that the line search cut short are used to predict
/// sticking points (see [`PassTracker::short_step`]). Measured over 25
/// runs (paper, levels 2 and 4, `t1e5`, g0 at μ = 0.6, 1, 1.5, 2, 2.5):
/// Newton iterations 13 497 → 10 691, the sum of the most in one
/// increment 4 392 → 3 474; μ = 0.3 byte for byte the same. Without the
/// gate the high friction gained as much but μ = 0.3 and 0.6 lost.
pub(super) const FULL_STEP_PREDICTION_AFTER: usize = 8;

/// A Newton failure inside an increment; [`StaticSolver::advance`] fills in
/// the increment's number, load fractions and earlier attempts.
pub(super) fn failure(reason: impl Into<String>, history: Vec<IterationRecord>) -> ElasticError {
    ElasticError::NotConverged {
        number: 0,
        from: 0.0,
        fraction: 0.0,
        increment: 0.0,
        reason: reason.into(),
        attempts: Vec::new(),
        history,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Observes `status` (every point carrying traction 1).
    fn look(t: &mut PassTracker, status: &[PointStatus]) {
        let opts = SolverOptions::default();
        let st = status.iter().map(|&s| (s, 1.0)).collect();
        t.observe(st, 1.0, (0.0, false), 1e-10, &opts).unwrap();
    }

    /// Observes `status` and takes a full step.
    fn iterate(t: &mut PassTracker, status: &[PointStatus]) {
        look(t, status);
        t.stepped(1.0, 1.0).unwrap();
    }

    #[test]
    fn reversed_slips_are_tried_as_sticking_once_per_pass() {
        let plus = (ContactStatus::Slip, 1);
        let minus = (ContactStatus::Slip, -1);
        let stick = (ContactStatus::Stick, 0);
        let open = (ContactStatus::Open, 0);
        let mut t = PassTracker::new(1.0, 1);
        // no previous iterate: nothing reversed
        assert!(t.reversed_points(&[plus, plus, stick, open]).is_empty());
        iterate(&mut t, &[plus, plus, stick, open]);
        // point 0 reversed; point 1 kept its direction; points 2, 3 are no
        // slipping points
        assert_eq!(t.reversed_points(&[minus, plus, plus, open]), vec![0]);
        iterate(&mut t, &[minus, plus, plus, open]);
        // point 0 reverses again: tried once already; point 1 now
        assert_eq!(t.reversed_points(&[plus, minus, plus, open]), vec![1]);
        // a new pass tries every point again
        let mut t = PassTracker::new(1.0, 2);
        iterate(&mut t, &[minus, plus, plus, open]);
        assert_eq!(t.reversed_points(&[plus, minus, plus, open]), vec![0, 1]);
    }

    /// The full step's stick and reversed statuses become stick
    /// predictions only from the gate on, once, beside the reversals.
    #[test]
    fn a_long_pass_tries_the_full_steps_sticking_points() {
        let plus = (ContactStatus::Slip, 1);
        let minus = (ContactStatus::Slip, -1);
        let stick = (ContactStatus::Stick, 0);
        let open = (ContactStatus::Open, 0);
        let now = [plus, plus, plus, stick, open, plus];
        // at the full step: 0 sticks, 1 slips the other way, 2 slips on,
        // 3 and 4 were not slipping, 5 opens
        let full: Vec<(PointStatus, f64)> = [stick, minus, plus, minus, stick, open]
            .iter()
            .map(|&s| (s, 1.0))
            .collect();
        let mut t = PassTracker::new(1.0, 2);
        for _ in 0..FULL_STEP_PREDICTION_AFTER - 2 {
            iterate(&mut t, &now);
        }
        // the iterate before the gate: its short step predicts nothing
        look(&mut t, &now);
        t.short_step(&now, &full);
        assert!(t.stick_predictions(&now).is_empty());
        t.stepped(0.01, 1e-3).unwrap();
        // from the gate on
        look(&mut t, &now);
        t.short_step(&now, &full);
        assert_eq!(t.stick_predictions(&now), vec![0, 1]);
        // used once
        assert!(t.stick_predictions(&now).is_empty());
    }
}
