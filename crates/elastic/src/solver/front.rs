//! Opening-front prediction for the Newton passes.
//!
//! Why: on the vessel, the gap under the weld opens like a plate lifting
//! off its support. With the points ahead of the opening front closed, the
//! linearised solution carries the lift-off as a concentrated tension at
//! the first closed node and compression behind it, so an exact Newton step
//! (with any penalty: measured with penalty factors 0.01 to 10) opens one
//! node, two integration points, per iteration: the iteration count grows
//! with the number of interface nodes the front crosses (60 on 34 816
//! triangles against 28 on 2 176).
//!
//! What: when the last iterate opened points, the elements within `reach`
//! element hops of them along the interface are *predicted* open: the
//! Newton step is taken on the piecewise-linear branch where those points
//! are open (their contact traction and stiffness dropped, by a multiplier
//! of −∞ in a copy of the committed states). The step is kept if it is a
//! descent direction of the (exact) energy, with the exact line-search
//! step along it however short. Each front (a connected run of elements
//! whose points just opened) keeps its own reach: if every point it
//! predicted is open at the end of the step, its reach doubles (the front
//! crosses n nodes in O(log n) iterations), otherwise it halves. (One
//! reach for all fronts, until session 22, was halved whenever any front
//! fell short — the lift-off under the weld forms a main band and short
//! islands ahead of it that open and close again — and the main front
//! crept.) A step that is no descent direction is discarded: the trial
//! counts as an iteration, the exact Newton step is taken, and every front
//! starts again from reach 1. Measured, the most iterations in one
//! increment (frictionless / μ = 0.3): level 2 18 / 30 → 13 / 25, level 4
//! 33 / 46 → 30 / 43, `t1e5` 35 / 49 → 30 / 44; the order-2 meshes g0, g1
//! and `t2.5e5` within ±5 % of before. (Keeping half the reach after a
//! discarded trial gave level 4 24 / 37 but `t2.5e5` at order 2 120
//! instead of 77: not kept.) (Until session 18 a kept step also
//! had to reach half its length; the rejections cost one iteration in five
//! of the first pass on `t1e5`, whose first increment, frictionless, took
//! 45 iterations then and 35 now.)
//!
//! Stick prediction (session 22): a closed point whose slip direction
//! reversed in the last step is tried as sticking in the same predicted
//! branch (an unbounded frozen slip limit in the copy of the states: stick
//! traction and stiffness), once per pass, and not once the pass's secant
//! slip damping is on (with both, μ = 5 on the paper mesh stopped after
//! 30 outer updates; it converges without). Why: after the first update of
//! the frozen friction limits (from 0 to μ p) a block of points that must
//! stick (near the symmetry plane opposite the weld, on the default mesh
//! g0) slid back and forth as a whole, every point reversing at every
//! iteration: with the exact slip tangent (0) nothing holds them at the
//! thin stick band, and the line search stops just past it. The predicted
//! branch also takes the secant slip tangent of the damped points, like
//! the exact step (it took the undamped one before). Measured, most
//! iterations in one increment (fl / 0.3 / 1 / 2): g0 14 / 83 / 171 / 549
//! → 14 / 49 / 211 / 510 (in all 63 / 151 / 545 / 1547 → 63 / 116 / 451 /
//! 1273), level 4 30 / 43 / 92 / 274 → 30 / 43 / 99 / 289, `t1e5` 30 / 44
//! / 105 / 380 → 30 / 44 / 108 / 423; the
//! two-way g0 run 2 989 → 2 614 Newton iterations and 301 → 182
//! factorisations. Tried every time a point reverses (not once per pass),
//! it cut g0 as well but raised μ = 2 on `t1e5` to 602.
//!
//! The exact energy line search follows every step, so the pass stays a
//! descent method on the convex energy of the pass; the converged answer
//! does not depend on the prediction (the convergence test is unchanged).

use super::tracker::PassTracker;
use super::*;

/// Elements that share a bottom corner node, per element, of one interface.
pub(super) fn element_neighbours(nodes: &[[usize; 4]]) -> Vec<Vec<usize>> {
    let mut by_node: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for (e, n) in nodes.iter().enumerate() {
        for &v in &n[..2] {
            by_node.entry(v).or_default().push(e);
        }
    }
    let mut out = vec![Vec::new(); nodes.len()];
    for els in by_node.values() {
        for &a in els {
            for &b in els {
                if a != b && !out[a].contains(&b) {
                    out[a].push(b);
                }
            }
        }
    }
    for o in &mut out {
        o.sort_unstable();
    }
    out
}

/// Flat point indices (all interfaces, element-major, as in
/// `StaticSolver::statuses`) predicted to open, per front: the elements
/// with a point that opened between `before` and `now` form connected runs
/// (one per front), and each run predicts the closed points of the
/// elements within its reach: `carry` (per flat point; 0: none) of its
/// points, else 1. At most half the closed points are taken (none if more
/// would be), so that the predicted branch keeps the bodies supported.
/// Returns `(points, reach)` per front.
pub(super) fn predicted_openings(
    neighbours: &[Vec<Vec<usize>>],
    per_element: &[usize],
    before: &[PointStatus],
    now: &[PointStatus],
    carry: &[usize],
) -> Vec<(Vec<usize>, usize)> {
    let open = |s: &PointStatus| s.0 == ContactStatus::Open;
    let fronts = fronts_of(
        neighbours,
        per_element,
        (before, now, carry),
        |b, n| open(n) && !open(b),
        |n| !open(n),
    );
    let closed = now.iter().filter(|s| !open(s)).count();
    let total: usize = fronts.iter().map(|f| f.0.len()).sum();
    if 2 * total > closed {
        return Vec::new();
    }
    fronts
}

/// Flat point indices predicted to slip, per front, as
/// [`predicted_openings`] does for openings: the elements with a point
/// that went from stick to slip between `before` and `now` form the
/// fronts, and each predicts the sticking points within its reach. Why:
/// where a stick zone shrinks (the pass after an update of the frozen
/// limits), an exact Newton step with the zone's points sticking loads
/// the first sticking point past its limit, which slips in the next
/// iterate, and the zone shrinks by one node per iteration (`t1e5` at
/// μ = 1: 28 full steps in one pass, two points each). The prediction
/// leaves at least one point of every interface sticking (a body held by
/// friction alone would be free on the branch): where the reach would
/// take them all, it is halved until it does not (none at reach 1).
pub(super) fn predicted_slips(
    neighbours: &[Vec<Vec<usize>>],
    per_element: &[usize],
    before: &[PointStatus],
    now: &[PointStatus],
    carry: &[usize],
) -> Vec<(Vec<usize>, usize)> {
    let stick = |s: &PointStatus| s.0 == ContactStatus::Stick;
    let mut out = Vec::new();
    let mut offset = 0;
    // interface by interface: each keeps a sticking point (a full ring
    // held by one interface turns freely when all of its points slip)
    for (adj, &per) in neighbours.iter().zip(per_element) {
        let range = offset..offset + per * adj.len();
        let (b, n) = (&before[range.clone()], &now[range.clone()]);
        let sticking = n.iter().filter(|s| stick(s)).count();
        let mut c: Vec<usize> = (0..range.len())
            .map(|i| carry.get(offset + i).copied().unwrap_or(0))
            .collect();
        loop {
            let fronts = fronts_of(
                std::slice::from_ref(adj),
                &[per],
                (b, n, &c),
                |b, n| n.0 == ContactStatus::Slip && stick(b),
                stick,
            );
            let total: usize = fronts.iter().map(|f| f.0.len()).sum();
            if total < sticking {
                out.extend(
                    fronts
                        .into_iter()
                        .map(|(p, r)| (p.into_iter().map(|i| i + offset).collect(), r)),
                );
                break;
            }
            if c.iter().all(|&r| r <= 1) {
                break;
            }
            // too far: the fronts look half as far ahead
            for r in &mut c {
                *r /= 2;
            }
        }
        offset = range.end;
    }
    out
}

/// The fronts of `seed` points (a status change between `before` and
/// `now`) and the `eligible` points within their reach (see
/// [`predicted_openings`]).
fn fronts_of(
    neighbours: &[Vec<Vec<usize>>],
    per_element: &[usize],
    (before, now, carry): (&[PointStatus], &[PointStatus], &[usize]),
    seeds: impl Fn(&PointStatus, &PointStatus) -> bool,
    eligible: impl Fn(&PointStatus) -> bool,
) -> Vec<(Vec<usize>, usize)> {
    let mut fronts = Vec::new();
    let mut taken = vec![false; now.len()];
    let mut offset = 0;
    for (adj, &per) in neighbours.iter().zip(per_element) {
        let n_el = adj.len();
        let point = |e: usize, q: usize| offset + per * e + q;
        let seed: Vec<bool> = (0..n_el)
            .map(|e| (0..per).any(|q| seeds(&before[point(e, q)], &now[point(e, q)])))
            .collect();
        let mut run_of = vec![usize::MAX; n_el];
        for e0 in 0..n_el {
            if !seed[e0] || run_of[e0] != usize::MAX {
                continue;
            }
            // the run of seed elements connected to e0
            let mut run = vec![e0];
            run_of[e0] = e0;
            let mut k = 0;
            while k < run.len() {
                for &f in &adj[run[k]] {
                    if seed[f] && run_of[f] == usize::MAX {
                        run_of[f] = e0;
                        run.push(f);
                    }
                }
                k += 1;
            }
            let reach = run
                .iter()
                .flat_map(|&e| (0..per).map(move |q| point(e, q)))
                .map(|i| carry.get(i).copied().unwrap_or(0))
                .max()
                .unwrap_or(0)
                .max(1);
            // hop distance from the run
            let mut distance = vec![usize::MAX; n_el];
            let mut queue = std::collections::VecDeque::new();
            for &e in &run {
                distance[e] = 0;
                queue.push_back(e);
            }
            while let Some(e) = queue.pop_front() {
                if distance[e] >= reach {
                    continue;
                }
                for &f in &adj[e] {
                    if distance[f] == usize::MAX {
                        distance[f] = distance[e] + 1;
                        queue.push_back(f);
                    }
                }
            }
            let mut points = Vec::new();
            for (e, &d) in distance.iter().enumerate() {
                if d <= reach {
                    for i in (0..per).map(|q| point(e, q)) {
                        if eligible(&now[i]) && !taken[i] {
                            taken[i] = true;
                            points.push(i);
                        }
                    }
                }
            }
            if !points.is_empty() {
                fronts.push((points, reach));
            }
        }
        offset += per * n_el;
    }
    fronts
}

impl StaticSolver<'_> {
    /// A copy of `committed` in which the flat points `open` are open
    /// whatever their jump (normal multiplier −∞: no contact traction, no
    /// contact stiffness) and the flat points `stick` stick whatever their
    /// shear (an unbounded frozen slip limit: traction k_s (Δu_t − g_s),
    /// tangent k_s), and the flat points `slip` slip at the jump of `u` in
    /// the direction of their shear there (their plastic slip moved to just
    /// past the frozen limit: traction ±s, the slipping tangent; see
    /// [`crate::Joint::slipping_state`]). All lists sorted.
    pub(super) fn forced_branch(
        &self,
        committed: &[PointStates],
        (open, stick, slip): (&[usize], &[usize], &[usize]),
        damped: Option<&[bool]>,
        u: &[f64],
    ) -> Vec<PointStates> {
        let mut forced = match damped {
            // the secant slip tangent of the damped points, as in the
            // exact step
            Some(d) => self.with_secant_slip(committed, d),
            None => committed.to_vec(),
        };
        if !slip.is_empty() {
            // the predicted slipping points: their plastic slip moved to
            // just past the limit at the iterate's jump
            let outputs = self.point_outputs(u, committed);
            each_point(&mut forced, slip, |k, local, state| {
                if let Some(s) = self.laws[k].slipping_state(&outputs[k][local].jump, state) {
                    *state = s;
                }
            });
        }
        each_point(&mut forced, open, |_, _, state| {
            state.lambda_n = f64::NEG_INFINITY;
        });
        each_point(&mut forced, stick, |_, _, state| {
            state.forced_stick = true;
        });
        forced
    }
}

impl StaticSolver<'_> {
    /// The points that the outer update after an early coupled pass opened
    /// (see [`reopened`]), at the first iterate `now` of the pass after it;
    /// the pass's first step tries them closed (the contact branch
    /// continued into tension, as [`StaticSolver::force_closed`]). None for
    /// a later iterate, another pass, a non-symmetric (coupled) pass or
    /// without front predictions.
    ///
    /// Why: an update of the normal multipliers (λ ← the pressure) opens
    /// the points held closed by their multiplier that pressed less than
    /// it did, and after a pass that moved as far as the early coupled one
    /// many do: `t1e5` at μ = 2, t = 1 s, 175. The next pass's first
    /// Newton step then has them free (no normal, and sliding on a frozen
    /// limit no shear stiffness): it drives them through each other, and
    /// the exact line search stops at the first of them to close, a step
    /// of 3e-9 that closes some 60; four such steps before the pass moves
    /// on (7 iterations in that pass). Tried closed, they close in the
    /// first step: 1 iteration. Over the 30 high-friction runs of
    /// docs/vessel.md §6 5 865 → 5 741 Newton iterations, the most in one
    /// increment summed 2 002 → 1 941, μ ≤ 0.6 unchanged. After every
    /// outer update it saved iterations at μ = 0.3 as well (the default
    /// run 91 → 89), but the multilayer vessel lost: its layers lift off
    /// their neighbours for good, the tried branch pulled them back (steps
    /// of 0.009 and less), and the five-layer test took 323 Newton
    /// iterations in one stage instead of at most 250.
    pub(super) fn reopened_points(
        &self,
        now: &[PointStatus],
        first: bool,
        symmetric: bool,
    ) -> Vec<usize> {
        match self.previous_end.as_ref() {
            Some(before) if first && symmetric && self.options.front_prediction => {
                reopened(before, now)
            }
            _ => Vec::new(),
        }
    }
}

/// What the next Newton step of a pass tries besides the exact step: the
/// frozen passes' predictions (to open, to stick, to slip; see
/// [`PassTracker::predictions`]), the points that the update before the
/// pass opened (first step only, [`StaticSolver::reopened_points`]) and,
/// in a coupled pass, what its last cut-short step predicted
/// ([`CoupledNext`]).
pub(super) struct StepTrial {
    pub predicted: Vec<usize>,
    pub sticks: Vec<usize>,
    pub slips: Vec<usize>,
    pub reopened: Vec<usize>,
    pub next: CoupledNext,
    /// The step is a coupled one on the branch `next` predicted.
    pub coupled: bool,
}

impl StepTrial {
    /// The counts an iteration record keeps (to open, stick, slip, close).
    pub(super) fn counts(&self) -> [usize; 4] {
        if self.coupled {
            self.next.counts()
        } else {
            [
                self.predicted.len(),
                self.sticks.len(),
                self.slips.len(),
                self.reopened.len(),
            ]
        }
    }

    /// No frozen-pass prediction to try.
    pub(super) fn frozen_empty(&self) -> bool {
        self.predicted.is_empty()
            && self.sticks.is_empty()
            && self.slips.is_empty()
            && self.reopened.is_empty()
    }

    /// The predictions whose discarded trial counts as an iteration.
    pub(super) fn fronts(&self) -> usize {
        self.predicted.len() + self.slips.len() + self.reopened.len()
    }
}

impl StaticSolver<'_> {
    /// The [`StepTrial`] of the next step of a pass at the statuses `now`
    /// (`per_element`: points per element of each interface; `symmetric`:
    /// frozen limits or no slipping point; `coupled_ok`: a coupled step
    /// may take the predictions `next` of the last one).
    pub(super) fn step_trial(
        &self,
        t: &mut PassTracker,
        (now, per_element): (&[PointStatus], &[usize]),
        (symmetric, coupled_ok): (bool, bool),
        next: CoupledNext,
    ) -> StepTrial {
        let [predicted, sticks, slips] = t.predictions(
            &self.neighbours,
            per_element,
            now,
            symmetric && self.options.front_prediction,
        );
        let next = next.still_to_change(now);
        let coupled = coupled_ok && !symmetric && !next.is_empty();
        StepTrial {
            predicted,
            sticks,
            slips,
            reopened: self.reopened_points(now, t.history.len() == 1, symmetric),
            next,
            coupled,
        }
    }
}

/// The flat points open in `now` and closed in `before` (none if the two
/// differ in length).
pub(super) fn reopened(before: &[PointStatus], now: &[PointStatus]) -> Vec<usize> {
    if before.len() != now.len() {
        return Vec::new();
    }
    let open = |s: &PointStatus| s.0 == ContactStatus::Open;
    now.iter()
        .zip(before)
        .enumerate()
        .filter(|(_, (n, b))| open(n) && !open(b))
        .map(|(i, _)| i)
        .collect()
}

/// The smallest line-search step at which a step that tries closed the
/// points an outer update opened is kept (see
/// [`StaticSolver::reopened_points`]); a shorter one is discarded for the
/// exact step. Where the update opened points that are about to close
/// again, the step is full (the vessel: 1 in every pass); where they lift
/// off for good (a layer of the multilayer vessel leaving its neighbour),
/// the tried branch pulls them back and its step was 0.009 or less, and
/// keeping it left the five-layer vessel's third layer held by nothing.
pub(super) const REOPENED_MIN_STEP: f64 = 0.5;

/// How far along a cut-short coupled step the statuses for the next step
/// are read, as a multiple of the step taken (at most the full step): the
/// open points that are closed there are tried closed in the next step,
/// the closed ones that are open there are tried open. Measured (session
/// 41, the 30 high-friction runs of docs/vessel.md §10): at the full step
/// a closing front overshot (level 4 at μ = 2: 59 points closed at once,
/// then reopened two per step, 16 iterations in that pass), at 4× the
/// step it lands (12); 2× gave the same on level 4 and worse on level 2.
pub(super) const COUPLED_PREDICTION_REACH: f64 = 4.0;

impl StaticSolver<'_> {
    /// Marks the flat points `list` (sorted) of `states` to take their
    /// normal law's contact branch whatever the jump (a predicted step).
    pub(super) fn force_closed(&self, states: &mut [PointStates], list: &[usize]) {
        each_point(states, list, |_, _, state| state.forced_closed = true);
    }

    /// What a coupled step cut short at `step` predicts for the next step,
    /// `at(α)` being the iterate at α times the step along its ray and
    /// `now` the statuses where it starts: the points whose contact
    /// changes at [`COUPLED_PREDICTION_REACH`] times the step (open now and
    /// closed there, to close; closed now and open there, to open) and
    /// the slipping points that the full step makes stick or slip the
    /// other way (to stick, see [`CoupledNext`]).
    pub(super) fn coupled_next(
        &self,
        at: impl Fn(f64) -> Vec<f64>,
        step: f64,
        committed: &[PointStates],
        now: &[PointStatus],
    ) -> CoupledNext {
        let mut next = CoupledNext::default();
        let reach = (COUPLED_PREDICTION_REACH * step).min(1.0);
        let full = self.statuses(&at(1.0), committed);
        let at_reach = if reach < 1.0 {
            self.statuses(&at(reach), committed)
        } else {
            full.clone()
        };
        for (i, (there, here)) in at_reach.iter().zip(now).enumerate() {
            let (o_here, o_there) = (
                here.0 == ContactStatus::Open,
                there.0.0 == ContactStatus::Open,
            );
            if o_here && !o_there {
                next.close.push(i);
            } else if !o_here && o_there {
                next.open.push(i);
            }
        }
        for (i, (there, here)) in full.iter().zip(now).enumerate() {
            if here.0 == ContactStatus::Slip
                && (there.0.0 == ContactStatus::Stick || there.0.1 == -here.1)
            {
                next.stick.push(i);
            }
        }
        next
    }
}

/// The points a cut-short coupled step predicts for the next step (flat
/// indices, sorted; see [`StaticSolver::coupled_next`]).
///
/// Why the sticking points: the coupled slip tangent has no shear
/// stiffness, so a coupled Newton step moves a slipping point's shear
/// freely, and where the frozen pass before it left the slip going one
/// way and the coupled law wants it the other, the full step reverses
/// dozens of points at once. Between the two slip branches lies the stick
/// band (2 s/k_s wide, the traction swinging from +s to −s), and the
/// residual at the full step was up to 10³ times the start's: the
/// backtracking cut every step to ½ or less (`t1e5` at μ = 2, t = 600 s:
/// an early coupled pass of 20 iterations that did not converge, 144 in
/// the increment; with the stick branch tried, 13 and 33). Read at the
/// full step, not at the contact predictions' reach: over the 30
/// high-friction runs of docs/vessel.md §6 5 944 Newton iterations
/// against 6 016 (6 672 without), μ ≤ 1.5 unchanged bit for bit.
#[derive(Clone, Debug, Default)]
pub(super) struct CoupledNext {
    /// Open now, closed at the reach: tried on the contact branch
    /// continued into tension ([`StaticSolver::force_closed`]).
    pub close: Vec<usize>,
    /// Closed now, open at the reach: tried open.
    pub open: Vec<usize>,
    /// Slipping now, sticking or slipping the other way at the full step:
    /// tried on the stick branch continued past the limit
    /// (`JointState::forced_stick`).
    pub stick: Vec<usize>,
}

impl CoupledNext {
    /// Of the points that a cut-short coupled step predicted, those still
    /// open (to close), still closed (to open) and still slipping (to
    /// stick) at the statuses `now`.
    pub(super) fn still_to_change(self, now: &[PointStatus]) -> CoupledNext {
        let is_open = |i: &usize| now[*i].0 == ContactStatus::Open;
        CoupledNext {
            close: self.close.into_iter().filter(is_open).collect(),
            open: self.open.into_iter().filter(|i| !is_open(i)).collect(),
            stick: self
                .stick
                .into_iter()
                .filter(|i| now[*i].0 == ContactStatus::Slip)
                .collect(),
        }
    }

    /// The counts as an iteration record keeps them: to open, to stick, to
    /// slip (none), to close.
    pub(super) fn counts(&self) -> [usize; 4] {
        [self.open.len(), self.stick.len(), 0, self.close.len()]
    }

    pub(super) fn is_empty(&self) -> bool {
        self.close.is_empty() && self.open.is_empty() && self.stick.is_empty()
    }
}

/// Calls `f(interface, index within it, state)` for the flat points `list`
/// (sorted, all interfaces, element-major) of `states`.
fn each_point(
    states: &mut [PointStates],
    list: &[usize],
    mut f: impl FnMut(usize, usize, &mut tecon_contact::JointState),
) {
    let mut offset = 0;
    let mut k = 0;
    for &i in list {
        while i >= offset + states[k].as_slice().len() {
            offset += states[k].as_slice().len();
            k += 1;
        }
        let per = states[k].per_element();
        let local = i - offset;
        f(
            k,
            local,
            &mut states[k].element_mut(local / per)[local % per],
        );
    }
}

impl StaticSolver<'_> {
    /// A copy of `committed` with [`tecon_contact::JointState::secant_slip`]
    /// set at the flat points where `flags` is true (for the tangent only).
    pub(super) fn with_secant_slip(
        &self,
        committed: &[PointStates],
        flags: &[bool],
    ) -> Vec<PointStates> {
        let mut out = committed.to_vec();
        let mut offset = 0;
        for states in &mut out {
            let per = states.per_element();
            let n = states.as_slice().len();
            for (i, _) in flags[offset..offset + n]
                .iter()
                .enumerate()
                .filter(|f| *f.1)
            {
                states.element_mut(i / per)[i % per].secant_slip = true;
            }
            offset += n;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reopened_points_are_open_now_and_were_closed() {
        let open = (ContactStatus::Open, 0);
        let sliding_open = (ContactStatus::Open, 1);
        let stick = (ContactStatus::Stick, 0);
        let slip = (ContactStatus::Slip, -1);
        let before = [open, stick, slip, stick, open, slip];
        let now = [open, open, sliding_open, stick, stick, slip];
        // 1 and 2 opened (2 sliding on its frozen limit); 4 closed, 0 stayed open
        assert_eq!(reopened(&before, &now), vec![1, 2]);
        assert!(reopened(&now, &now).is_empty());
        // statuses of another interface layout: nothing
        assert!(reopened(&before[..5], &now).is_empty());
    }

    #[test]
    fn a_front_grows_by_reach_elements_ahead_of_the_points_that_opened() {
        // a chain of 10 elements, bottom nodes i, i + 1 (tops 100 + ...)
        let nodes: Vec<[usize; 4]> = (0..10).map(|i| [i, i + 1, 101 + i, 100 + i]).collect();
        let adj = element_neighbours(&nodes);
        assert_eq!(adj[0], vec![1]);
        assert_eq!(adj[4], vec![3, 5]);
        let closed = (ContactStatus::Slip, 1);
        let open = (ContactStatus::Open, 0);
        // points: 2 per element; elements 0, 1 open before, element 2 opened now
        let mut before = vec![closed; 20];
        before[..4].fill(open);
        let mut now = before.clone();
        now[4..6].fill(open);
        let mut carry = vec![0; 20];
        carry[4] = 2;
        let p = predicted_openings(std::slice::from_ref(&adj), &[2], &before, &now, &carry);
        assert_eq!(p, vec![(vec![6, 7, 8, 9], 2)]);
        // without a carried reach: one element ahead
        let p = predicted_openings(std::slice::from_ref(&adj), &[2], &before, &now, &[]);
        assert_eq!(p, vec![(vec![6, 7], 1)]);
        // nothing opened: no prediction
        assert!(
            predicted_openings(std::slice::from_ref(&adj), &[2], &now, &now, &carry).is_empty()
        );
        // more than half of the closed points: no prediction
        carry[5] = 8;
        assert!(
            predicted_openings(std::slice::from_ref(&adj), &[2], &before, &now, &carry).is_empty()
        );
        // two fronts on a chain of 20 elements, each with its own reach:
        // element 2 (reach 2) and element 7 (no carry: reach 1)
        let nodes: Vec<[usize; 4]> = (0..20).map(|i| [i, i + 1, 101 + i, 100 + i]).collect();
        let adj = element_neighbours(&nodes);
        let mut before = vec![closed; 40];
        before[..4].fill(open);
        let mut now = before.clone();
        now[4..6].fill(open);
        now[14] = open;
        let mut carry = vec![0; 40];
        carry[5] = 2;
        let p = predicted_openings(&[adj], &[2], &before, &now, &carry);
        assert_eq!(
            p,
            vec![(vec![6, 7, 8, 9], 2), (vec![12, 13, 15, 16, 17], 1)]
        );
    }

    #[test]
    fn a_slip_front_predicts_the_sticking_points_ahead_and_leaves_one_sticking() {
        // a chain of 10 elements, 2 points each: elements 0–2 slip, 3–9
        // stick; element 3 went from stick to slip in the last step
        let nodes: Vec<[usize; 4]> = (0..10).map(|i| [i, i + 1, 101 + i, 100 + i]).collect();
        let adj = element_neighbours(&nodes);
        let stick = (ContactStatus::Stick, 0);
        let slip = (ContactStatus::Slip, 1);
        let open = (ContactStatus::Open, 0);
        let mut before = vec![stick; 20];
        before[..6].fill(slip);
        let mut now = before.clone();
        now[6..8].fill(slip);
        let one = std::slice::from_ref(&adj);
        // reach 1: element 4; reach 2 carried: elements 4, 5
        assert_eq!(
            predicted_slips(one, &[2], &before, &now, &[]),
            vec![(vec![8, 9], 1)]
        );
        let mut carry = vec![0; 20];
        carry[6] = 2;
        assert_eq!(
            predicted_slips(one, &[2], &before, &now, &carry),
            vec![(vec![8, 9, 10, 11], 2)]
        );
        // reach 8 would take all 12 sticking points (elements 4–9): halved
        // to 4, elements 4–7, 8 points
        carry[6] = 8;
        assert_eq!(
            predicted_slips(one, &[2], &before, &now, &carry),
            vec![(vec![8, 9, 10, 11, 12, 13, 14, 15], 4)]
        );
        // an opening is no slip front, and open points are not predicted
        let mut opened = before.clone();
        opened[6..8].fill(open);
        assert!(predicted_slips(one, &[2], &before, &opened, &[]).is_empty());
        // a slip direction that reversed is no front either
        let mut reversed = before.clone();
        reversed[4] = (ContactStatus::Slip, -1);
        assert!(predicted_slips(one, &[2], &before, &reversed, &[]).is_empty());
        // one sticking element left: predicting it would free the body
        let mut last = vec![slip; 20];
        last[18..].fill(stick);
        let mut last_before = last.clone();
        last_before[16..18].fill(stick);
        assert!(predicted_slips(one, &[2], &last_before, &last, &[]).is_empty());
        // interface by interface: the same last sticking element, followed
        // by a second interface that sticks everywhere, is still kept
        // sticking (its ring would turn on the first interface), while the
        // second interface's own front is predicted, indices offset by 20
        let two = [adj.clone(), adj.clone()];
        let mut before2 = last_before.clone();
        before2.extend(before.iter().copied());
        let mut now2 = last.clone();
        now2.extend(now.iter().copied());
        assert_eq!(
            predicted_slips(&two, &[2, 2], &before2, &now2, &[]),
            vec![(vec![28, 29], 1)]
        );
    }
}
