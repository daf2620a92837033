//! Load increments: cut-back on failure, and per increment the outer
//! passes (augmented-Lagrangian multipliers, frozen friction limits).

use tecon_contact::FrictionBound;

use crate::joint::Joint;

use crate::error::{ElasticError, IterationRecord};

use super::*;

impl StaticSolver<'_> {
    /// Advances from the committed loads to `target` in increments (cut back
    /// on failure), committing the state at each converged increment.
    pub fn advance(&mut self, target: &Loads) -> Result<Vec<IncrementReport>, ElasticError> {
        let n_el = self.model.mesh.n_triangles();
        // one value per element (order 1) or per element node (order 2)
        let per_element = if self.p2.is_some() { 6 } else { 1 };
        let n_values = per_element * n_el;
        if !target.delta_t.is_empty() && target.delta_t.len() != n_values {
            return Err(ElasticError::Input {
                what: "temperature change".into(),
                message: if per_element == 1 {
                    format!(
                        "{} values for {n_el} triangles: an order-1 mesh takes one value per element ({n_el}) or none",
                        target.delta_t.len()
                    )
                } else {
                    format!(
                        "{} values for {n_el} triangles: an order-2 mesh takes six per element, element-major in the triangles6() node order (6 × {n_el} = {n_values}), or none",
                        target.delta_t.len()
                    )
                },
            });
        }
        if let Some(i) = target.delta_t.iter().position(|t| !t.is_finite()) {
            return Err(ElasticError::Input {
                what: "temperature change".into(),
                message: if per_element == 1 {
                    format!("element {i} has a non-finite value")
                } else {
                    format!(
                        "element {} (its local node {}) has a non-finite value",
                        i / 6,
                        i % 6
                    )
                },
            });
        }
        let start = self.loads.clone();
        let mut s = 0.0;
        let mut ds = 1.0 / self.options.increments.max(1) as f64;
        let mut cutbacks = Vec::new();
        let mut failed_iterations = 0;
        let mut reports = Vec::new();
        // the iteration history of the last failed attempt
        let mut last_failure: Option<Vec<IterationRecord>> = None;
        while s < 1.0 - 1e-14 {
            let s_try = (s + ds).min(1.0);
            let loads = Loads::lerp(&start, target, s_try, n_values);
            self.outer_stalled = false;
            let attempt = match self.increment(&loads) {
                Err(ElasticError::NotConverged {
                    number,
                    from,
                    fraction,
                    increment,
                    reason,
                    attempts,
                    history,
                }) if std::mem::take(&mut self.outer_stalled) => {
                    // The outer loop of the frozen friction limits stalled
                    // (high friction: the statuses of a few points flip
                    // between updates and the limits keep changing by ~1e-4
                    // of the pressure). The same increment by the coupled
                    // Newton, whose fixed point is the same Coulomb
                    // solution; if it fails too, the frozen loop's failure
                    // is cut back as before.
                    match self.coupled_increment(&loads) {
                        Ok(r) => {
                            failed_iterations += history.len();
                            cutbacks.push(format!(
                                "fraction {s:.4} → {s_try:.4} (increment {ds:.3e}) with frozen friction limits: {reason}; solved by the coupled Mohr–Coulomb Newton instead"
                            ));
                            Ok(r)
                        }
                        Err(ElasticError::NotConverged {
                            reason: why,
                            history: coupled,
                            ..
                        }) => {
                            // its iterations are failed work too (the
                            // cut-back below counts the frozen attempt's)
                            failed_iterations += coupled.len();
                            Err(ElasticError::NotConverged {
                                number,
                                from,
                                fraction,
                                increment,
                                reason: format!(
                                    "{reason}; the coupled Mohr–Coulomb Newton from the same state failed too ({why})"
                                ),
                                attempts,
                                history,
                            })
                        }
                        Err(e) => Err(e),
                    }
                }
                other => other,
            };
            match attempt {
                Ok((u, states, start, mut report)) => {
                    // point output of the converged increment, evaluated from
                    // the states its last Newton pass started from
                    self.points = self.point_results(&u, &start);
                    self.u = u;
                    self.update_gauge();
                    self.states = states;
                    self.loads = loads;
                    s = s_try;
                    report.cutbacks = std::mem::take(&mut cutbacks);
                    report.failed_iterations = std::mem::take(&mut failed_iterations);
                    // a later failure starts from another state
                    last_failure = None;
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
                    // A halved increment that fails along the same history
                    // (relative residuals, statuses) is the same problem
                    // scaled: from an unloaded state every joint law without
                    // cohesion is positively homogeneous in the load, so no
                    // smaller increment can differ either.
                    let same_problem = last_failure
                        .as_ref()
                        .is_some_and(|prev| same_history(prev, &history));
                    if 0.5 * ds < self.options.min_increment || same_problem {
                        let overflow = history.last().is_some_and(|h| !h.residual.is_finite());
                        let reason = if same_problem && overflow {
                            format!("{reason}; the halved increment overflowed too")
                        } else if same_problem {
                            format!(
                                "{reason}; the halved increment failed along the same iteration history (the same problem at every load fraction: from an unloaded state the joint laws are homogeneous in the load), so no smaller increment was tried"
                            )
                        } else {
                            reason
                        };
                        return Err(ElasticError::NotConverged {
                            number: reports.len() + 1,
                            from: s,
                            fraction: s_try,
                            increment: ds,
                            reason,
                            attempts: cutbacks,
                            history,
                        });
                    }
                    failed_iterations += history.len();
                    last_failure = Some(history.clone());
                    let tail: Vec<String> = history
                        .iter()
                        .rev()
                        .take(4)
                        .rev()
                        .map(|h| format!("pass {} {h}", h.pass))
                        .collect();
                    cutbacks.push(format!(
                        "fraction {s:.4} → {s_try:.4} (increment {ds:.3e}): {reason}; last iterations: {}",
                        tail.join(" | ")
                    ));
                    ds *= 0.5;
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

    /// One increment: converged displacements, the trial (new committed)
    /// states, the states the last Newton pass started from (the old
    /// committed ones with updated multipliers), and a report. The laws
    /// and options a coupled tail changes are restored whatever happens.
    #[allow(clippy::type_complexity)]
    pub(super) fn increment(
        &mut self,
        loads: &Loads,
    ) -> Result<(Vec<f64>, States, States, IncrementReport), ElasticError> {
        let (laws, options) = (self.laws.clone(), self.options);
        let result = self.increment_passes(loads);
        self.laws = laws;
        self.options = options;
        self.coupled_tail = false;
        result
    }

    /// The coupled law in place of the frozen one for the rest of the
    /// increment (see [`SolverOptions::coupled_tail`]); returns the frozen
    /// laws.
    fn enter_coupled_tail(&mut self) -> Vec<Joint> {
        let frozen = std::mem::take(&mut self.laws);
        self.laws = frozen
            .iter()
            .map(|j| j.with_friction_bound(FrictionBound::Coupled))
            .collect();
        self.options.friction_bound = FrictionBound::Coupled;
        self.options.max_iterations = self.options.max_iterations.min(COUPLED_TAIL_MAX_ITERATIONS);
        self.coupled_tail = true;
        frozen
    }

    /// True if the frozen passes of this increment should take one coupled
    /// Mohr–Coulomb pass now, the statuses at the end of the last pass
    /// being `end`: a frictional joint with a friction coefficient of at
    /// least [`EARLY_COUPLED_MIN_FRICTION`], and at most
    /// [`EARLY_COUPLED_MAX_STICK_SHARE`] of the closed points sticking.
    ///
    /// Why: at high friction the frozen limits converge slowly to the
    /// Coulomb fixed point (each update moves the limits by μ Δp), and the
    /// passes between the updates rebuild stick zones that the next update
    /// undoes (level 4 at μ = 2: 12 updates and 216 Newton iterations in
    /// one increment). One coupled pass, whose slip limit follows the
    /// pressure, lands near that fixed point in one go; the frozen passes
    /// then go on from its pressures, so the answer is theirs. Where most
    /// closed points stick, the coupled Newton steps turn dozens of points
    /// between stick and slip per step and seldom converge; at μ < 1 the
    /// frozen loop settles in a few updates anyway and the coupled pass
    /// cost more than it saved (measured, docs/vessel.md §10).
    fn early_coupled_pass(&self, end: &[super::PointStatus]) -> bool {
        let mu = self
            .laws
            .iter()
            .map(|l| match l {
                Joint::Frictional(j) => j.tan_phi(),
                _ => 0.0,
            })
            .fold(0.0, f64::max);
        if mu < EARLY_COUPLED_MIN_FRICTION * (1.0 - 1e-9) {
            return false;
        }
        let (mut stick, mut closed) = (0usize, 0usize);
        for s in end {
            match s.0 {
                ContactStatus::Stick => {
                    stick += 1;
                    closed += 1;
                }
                ContactStatus::Slip => closed += 1,
                ContactStatus::Open => {}
            }
        }
        closed > 0 && (stick as f64) <= EARLY_COUPLED_MAX_STICK_SHARE * closed as f64
    }

    /// The frozen laws back (see [`StaticSolver::enter_coupled_tail`]).
    fn leave_coupled_tail(&mut self, frozen: Vec<Joint>, options: SolverOptions) {
        self.laws = frozen;
        self.options = options;
        self.coupled_tail = false;
    }

    #[allow(clippy::type_complexity)]
    fn increment_passes(
        &mut self,
        loads: &Loads,
    ) -> Result<(Vec<f64>, States, States, IncrementReport), ElasticError> {
        let options = self.options;
        let f_ext = self.external_force(loads)?;
        let mut committed = self.states.clone();
        let mut total_iterations = 0;
        let mut max_pass = 0;
        let mut passes: Vec<Vec<IterationRecord>> = Vec::new();
        let mut augmentations = 0;
        // the friction-limit changes of the outer updates so far, and
        // whether they are under-relaxed (see `FRICTION_RELAXATION`)
        let mut friction_changes: Vec<f64> = Vec::new();
        let mut relaxing = false;
        // the larger outer change (multipliers, friction limits) of every update
        let mut outer_changes: Vec<f64> = Vec::new();
        // the states the last converged pass started from (before its
        // outer update), and the outer cut-backs taken so far
        let mut last_start: Option<States> = None;
        let mut outer_cuts = 0;
        let mut frozen_friction =
            self.options.friction_bound == FrictionBound::Frozen && self.has_slip_limits();
        // the frozen laws while the coupled tail runs, whether it was tried,
        // and its passes
        let mut tail: Option<Vec<Joint>> = None;
        // (not in a solve whose outer loop may stop at a floor, between
        // the output times of a two-way run: at that tolerance the tail's
        // non-symmetric steps cost more than the frozen passes they save)
        let mut tail_tried =
            !(frozen_friction && self.options.coupled_tail) || self.outer_floor > 0.0;
        let mut tail_passes = Vec::new();
        let mut early_passes = Vec::new();
        // the multiplier updates of settled passes (see `MultiplierMixing`)
        let mut mixing = MultiplierMixing::default();
        let mut mixed_updates = 0;
        // the early coupled pass: tried in this increment, and running
        let mut early_tried = false;
        // while the early coupled pass runs: the states it started from
        let mut early_entry: Option<States> = None;
        // the last converged pass was settled (no failed pass since), and
        // the statuses at the end of the last converged pass
        let mut previous_settled = false;
        let mut last_end: Option<Vec<super::PointStatus>> = None;
        self.previous_end = None;
        let mut u = self.u.clone();
        // (a condensed pass of an earlier attempt is not continued)
        self.pending = None;
        self.coarse_in_increment = 0;
        // Inexact passes while friction-limit updates follow (see
        // `SolverOptions::pass_forcing`); the next pass is exact once an
        // update after an inexact one changed almost nothing. Without
        // friction every pass is exact: a normal multiplier update from an
        // unsettled contact zone undoes what the pass had found.
        let mut exact_next = !frozen_friction;
        // a pass that stopped inexactly marks its last iterate
        let inexact = |h: &[IterationRecord]| h.last().is_some_and(|r| r.inexact);
        // Newton passes; with the augmented Lagrangian, each pass is followed
        // by a multiplier update until the multipliers settle. `start` is the
        // state set the accepted pass started from.
        let (mut start, history) = loop {
            let pass = passes.len() + 1;
            self.pass_forcing = if exact_next {
                0.0
            } else if pass == 1 {
                // the first pass finds the contact zone of the new load:
                // an update from a zone far from settled undoes much of it
                FIRST_PASS_FORCING * self.options.pass_forcing
            } else {
                self.options.pass_forcing
            };
            let (u_new, history) =
                match self.newton_pass(&f_ext, loads, &committed, u.clone(), pass) {
                    Ok(r) => r,
                    // A coupled pass that fails: the frozen passes take the
                    // increment up again from the start of that pass.
                    Err(ElasticError::NotConverged { history, .. }) if tail.is_some() => {
                        tail_passes.push(passes.len());
                        if early_entry.is_some() {
                            early_passes.push(passes.len());
                        }
                        total_iterations += history.len();
                        max_pass = max_pass.max(history.len());
                        passes.push(history);
                        if let Some(frozen) = tail.take() {
                            self.leave_coupled_tail(frozen, options);
                        }
                        frozen_friction = true;
                        if let Some(entry) = early_entry.take() {
                            // an early pass: the frozen passes go on from
                            // where it started (the update after the
                            // frozen pass before it), with an exact pass
                            // (inexact there: g0 at μ = 2 256 instead of
                            // 243 in one increment), and the usual coupled
                            // tail may still come
                            tail_tried = false;
                            committed = entry;
                            exact_next = true;
                            previous_settled = false;
                            last_end = None;
                            continue;
                        }
                        if let Some(prev) = &last_start {
                            committed.clone_from(prev);
                        }
                        exact_next = true;
                        previous_settled = false;
                        last_end = None;
                        continue;
                    }
                    // A pass that fails after an update from an inexact pass
                    // (its statuses not settled; once on g0 at μ = 2, twice
                    // on level 2 at μ = 5): the update is undone and the
                    // pass it came from solved exactly, as before inexact
                    // passes.
                    Err(ElasticError::NotConverged { history, .. })
                        if passes.last().is_some_and(|h| inexact(h)) && last_start.is_some() =>
                    {
                        total_iterations += history.len();
                        max_pass = max_pass.max(history.len());
                        passes.push(history);
                        if let Some(prev) = &last_start {
                            committed.clone_from(prev);
                        }
                        exact_next = true;
                        previous_settled = false;
                        last_end = None;
                        continue;
                    }
                    // A pass after an outer update that fails: the update moved
                    // the friction limits too far for Newton (high friction: a
                    // stick zone appears at once where everything slipped).
                    // The load cannot be cut (from an unloaded state the problem
                    // is the same at every load fraction), the update can: the
                    // limits go halfway back towards those of the last converged
                    // pass, and every later update is under-relaxed. The fixed
                    // point, and so the answer, is the same.
                    Err(ElasticError::NotConverged { history, .. })
                        if frozen_friction
                            && outer_cuts < MAX_OUTER_CUTS
                            && last_start.is_some() =>
                    {
                        total_iterations += history.len();
                        max_pass = max_pass.max(history.len());
                        passes.push(history);
                        if let Some(prev) = &last_start {
                            relax_friction(prev, &mut committed);
                        }
                        relaxing = true;
                        outer_cuts += 1;
                        previous_settled = false;
                        last_end = None;
                        continue;
                    }
                    // the failed pass comes with the passes before it
                    Err(ElasticError::NotConverged {
                        reason, history, ..
                    }) => {
                        let mut all: Vec<IterationRecord> = passes.concat();
                        all.extend(history);
                        return Err(super::tracker::failure(
                            if pass > 1 {
                                format!("{reason} (pass {pass})")
                            } else {
                                reason
                            },
                            all,
                        ));
                    }
                    Err(e) => return Err(e),
                };
            total_iterations += history.len();
            max_pass = max_pass.max(history.len());
            passes.push(history.clone());
            if tail.is_some() {
                tail_passes.push(passes.len() - 1);
                if early_entry.is_some() {
                    early_passes.push(passes.len() - 1);
                }
            }
            let after_early = early_entry.take().is_some();
            if after_early {
                // back to the frozen passes, their limits set below to the
                // pressures of the coupled pass
                if let Some(frozen) = tail.take() {
                    self.leave_coupled_tail(frozen, options);
                }
                tail_tried = false;
                frozen_friction = true;
            }
            u = u_new;
            let al = self.options.augmented_lagrangian;
            if al.is_none() && !frozen_friction {
                break (committed, history);
            }
            let start = committed.clone();
            last_start = Some(start.clone());
            // Outer updates from the converged jumps: Uzawa update of the
            // normal multipliers, and the frozen friction limits set to the
            // pressure of this pass.
            let mut max_p: f64 = 0.0;
            for p in self.point_outputs(&u, &start).iter().flatten() {
                max_p = max_p.max(-p.traction.y);
            }
            let (max_friction_change, max_change) =
                self.update_outer(&u, &mut committed, (frozen_friction, al.is_some()));
            // (an update of the multipliers alone: frictionless, or the
            // coupled tail)
            let multipliers_alone = al.is_some() && !frozen_friction;
            let scale = max_p.max(f64::MIN_POSITIVE);
            // the floor bounds the estimated distance to the fixed point (see
            // `StaticSolver::set_outer_tolerance_floor`)
            let change = max_change.max(max_friction_change);
            if let Some(&previous) = outer_changes.last()
                && previous > 0.0
            {
                self.outer_contraction = change / previous;
            }
            let rho = self.outer_contraction.min(MAX_ESTIMATED_CONTRACTION);
            let floor = self.outer_floor / (rho / (1.0 - rho)).max(1.0);
            let al_done = al.is_none_or(|tol| max_change <= tol.max(floor) * scale);
            let friction_done =
                max_friction_change <= self.options.friction_tolerance.max(floor) * scale;
            if al_done && friction_done {
                if !inexact(&history) {
                    // The last update changed almost nothing: the converged u
                    // stands, with the multipliers and limits it was computed with.
                    break (start, history);
                }
                // an inexact pass: solved again, exactly, from the
                // (almost unchanged) multipliers and limits
                exact_next = true;
            }
            // Past the limit, the outer updates go on while they still
            // converge: the larger change (multipliers, friction limits)
            // halved over the last PROGRESS_WINDOW updates, up to
            // OUTER_EXTENSION × the limit. High friction (μ ≳ 3) converges
            // slowly but surely there; a stagnating loop still stops at the
            // limit.
            let progressing = outer_changes.len() >= PROGRESS_WINDOW
                && change <= 0.5 * outer_changes[outer_changes.len() - PROGRESS_WINDOW];
            outer_changes.push(change);
            let limit = self.options.max_augmentations;
            if augmentations >= limit && !(progressing && augmentations < OUTER_EXTENSION * limit) {
                self.outer_stalled = frozen_friction;
                return Err(super::tracker::failure(
                    format!(
                        "after {augmentations} outer updates the multipliers still change by {max_change:.3e} Pa and the friction limits by {max_friction_change:.3e} Pa (largest contact pressure {max_p:.3e} Pa)"
                    ),
                    passes.concat(),
                ));
            }
            friction_changes.push(max_friction_change);
            let k = friction_changes.len() - 1;
            if frozen_friction
                && k >= PLAIN_FRICTION_UPDATES
                && friction_changes[k] > STAGNATION * friction_changes[k - 2]
            {
                relaxing = true;
            }
            if relaxing {
                relax_friction(&start, &mut committed);
            }
            // Multiplier updates of passes that all end with the same
            // statuses are an affine fixed-point iteration: from the third
            // on, the next multipliers are the Anderson mix of the last few
            // (see `MultiplierMixing`). The stopping test above is on the
            // plain change, so only the path changes.
            let mix = multipliers_alone && !inexact(&history);
            // the statuses this pass ended with (evaluated once, for the
            // mixing and for the tail's tests below)
            let ended: Option<Vec<super::PointStatus>> = (mix || !tail_tried).then(|| {
                self.statuses(&u, &start)
                    .into_iter()
                    .map(|(s, _)| s)
                    .collect()
            });
            match ended.as_ref().filter(|_| mix) {
                Some(now) => {
                    let quiet_pass = history.iter().skip(1).all(|r| r.changed == 0);
                    let (x, g) = (multipliers(&start), multipliers(&committed));
                    if let Some(mixed) = mixing.observe(now.clone(), quiet_pass, x, g) {
                        set_multipliers(&mut committed, &mixed);
                        mixed_updates += 1;
                    }
                }
                None => mixing = MultiplierMixing::default(),
            }
            // A pass solved exactly whose statuses did not change after its
            // first iterate, or that ended with the statuses the pass before
            // it ended with: the outer updates are linear from here on, and
            // the coupled passes find their fixed point directly.
            let end: Option<Vec<super::PointStatus>> = if tail_tried { None } else { ended };
            let same_end = end.is_some() && end == last_end;
            // one coupled pass early at high friction (see
            // `early_coupled_pass`), once per increment
            let early = !early_tried
                && self.options.early_coupled_pass
                && !tail_tried
                && frozen_friction
                && end.as_ref().is_some_and(|e| self.early_coupled_pass(e));
            // (the next pass tries closed the points that the update after
            // an early coupled pass opens: see `reopened_points`)
            self.previous_end = if after_early { end.clone() } else { None };
            last_end = end;
            let quiet = history.iter().skip(1).all(|r| r.changed == 0);
            let settled = !inexact(&history) && (quiet || same_end);
            // two settled passes in a row, or one that is settled both
            // ways: quiet after its first iterate and ending with the
            // statuses the pass before it ended with
            if !tail_tried && settled && (previous_settled || (quiet && same_end)) {
                tail = Some(self.enter_coupled_tail());
                tail_tried = true;
                frozen_friction = false;
                exact_next = true;
            } else if early {
                early_entry = Some(committed.clone());
                tail = Some(self.enter_coupled_tail());
                early_tried = true;
                tail_tried = true;
                frozen_friction = false;
                // (it may stop inexactly: the frozen passes go on from it)
                exact_next = false;
            }
            previous_settled = settled;
            augmentations += 1;
        };
        // the interior of the condensed passes' interface dofs
        self.settle_interior(&mut u)?;
        let mut states = self.trial_states(&u, &start);
        if let Some(frozen) = tail.take() {
            // the converged pressures become the frozen limits of the next
            // increment, as after a coupled increment, and of the states
            // the point output is evaluated from (with the frozen law, the
            // limits the coupled law had: the same tractions)
            self.leave_coupled_tail(frozen, options);
            self.update_outer(&u, &mut states, (true, false));
            self.update_outer(&u, &mut start, (true, false));
        }
        Ok((
            u,
            states,
            start,
            IncrementReport {
                fraction: 0.0,
                iterations: total_iterations,
                max_pass_iterations: max_pass,
                passes,
                augmentations,
                cutbacks: Vec::new(),
                failed_iterations: 0,
                history,
                coarse_iterations: self.coarse_in_increment,
                coupled: false,
                coupled_tail_passes: tail_passes,
                early_coupled_passes: early_passes,
                mixed_multiplier_updates: mixed_updates,
            },
        ))
    }

    /// [`StaticSolver::increment`] with the coupled Mohr–Coulomb bound:
    /// full Newton passes on the non-symmetric tangent, with only the
    /// multipliers updated between passes. The converged pressures are
    /// stored as the frozen limits, so the next increment starts from them.
    #[allow(clippy::type_complexity)]
    fn coupled_increment(
        &mut self,
        loads: &Loads,
    ) -> Result<(Vec<f64>, States, States, IncrementReport), ElasticError> {
        let frozen_laws = self.laws.clone();
        self.laws = frozen_laws
            .iter()
            .map(|j| j.with_friction_bound(FrictionBound::Coupled))
            .collect();
        let (bound, choice) = (self.options.friction_bound, self.condensed_choice);
        self.options.friction_bound = FrictionBound::Coupled;
        // the condensed passes take symmetric (frozen) tangents only
        self.condensed_choice = Some(false);
        // (no coupled tail inside: the whole increment is coupled)
        let result = self.increment(loads);
        self.laws = frozen_laws;
        self.options.friction_bound = bound;
        self.condensed_choice = choice;
        let (u, mut states, mut start, mut report) = result?;
        // the converged pressures as frozen limits: of the next increment,
        // and of the states the point output is evaluated from with the
        // frozen law (the coupled law's tractions; with the limits of the
        // increment's start, slipping points showed stale shear tractions)
        self.update_outer(&u, &mut states, (true, false));
        self.update_outer(&u, &mut start, (true, false));
        report.coupled = true;
        Ok((u, states, start, report))
    }
}

/// Largest contraction of the outer loop taken in the error estimate of
/// [`StaticSolver::set_outer_tolerance_floor`]: the floor is divided by at
/// most ρ/(1 − ρ) = 19.
const MAX_ESTIMATED_CONTRACTION: f64 = 0.95;

/// Least friction coefficient (tan φ) for the early coupled pass (see
/// `StaticSolver::early_coupled_pass`). Measured over paper, levels 2 and
/// 4, `t1e5` and g0: at μ = 0.3 and 0.6 the early pass cost iterations
/// (level 4 at μ = 0.3 28 → 35 in one increment, level 2 and `t1e5` 8
/// apart instead of 5), from μ = 1 on it saved them.
const EARLY_COUPLED_MIN_FRICTION: f64 = 1.0;

/// Largest share of the closed points that may stick for the early coupled
/// pass (see `StaticSolver::early_coupled_pass`).
const EARLY_COUPLED_MAX_STICK_SHARE: f64 = 0.25;

/// The forcing of the first pass of an increment, as a fraction of
/// [`SolverOptions::pass_forcing`] (see there).
const FIRST_PASS_FORCING: f64 = 0.1;

/// Outer updates over which a loop past its limit must have halved its
/// change to go on (see [`StaticSolver::increment`]).
const PROGRESS_WINDOW: usize = 20;

/// How far past [`SolverOptions::max_augmentations`] a loop that still
/// converges may go, as a multiple of it.
const OUTER_EXTENSION: usize = 10;

/// Plain fixed-point updates of the frozen friction limits before the
/// under-relaxation may start (μ ≤ 0.3 settles within these on the vessel).
const PLAIN_FRICTION_UPDATES: usize = 5;

/// The under-relaxation starts (for the rest of the increment) at the
/// first update after [`PLAIN_FRICTION_UPDATES`] whose friction-limit
/// change is more than this × the change two updates before: the plain
/// updates alternate and no longer contract (μ = 1 on the vessel contracts
/// by ~0.25 per two updates and keeps its plain path; μ = 2 by ~0.87).
const STAGNATION: f64 = 0.5;

/// Most outer cut-backs in one increment: the last outer update halved
/// after a failed pass, up to 1/16 of it (see [`StaticSolver::increment`]).
const MAX_OUTER_CUTS: usize = 4;

/// Under-relaxation factor ω of the frozen friction limits once the plain
/// updates stagnate (see [`STAGNATION`]): `p_f ← p_f + ω (p − p_f)`. At high friction
/// (μ = 2 on the vessel) the plain update `p_f ← p` keeps alternating (the
/// limit changes fell by only ~0.87 per two updates, still 5·10⁻³ of the
/// largest pressure after 30); ω = ½ maps a factor of −0.9 to 0.05. An
/// Aitken (Irons–Tuck) factor was tried and oscillated between its bounds:
/// the map is piecewise linear (statuses change), so its secant estimate
/// is poor. The fixed point (`p = p_f`) is the same.
const FRICTION_RELAXATION: f64 = 0.5;

/// Replaces the friction pressures of `updated` (the plain update of
/// `old`) by the under-relaxed ones (see [`FRICTION_RELAXATION`]).
fn relax_friction(old: &[PointStates], updated: &mut [PointStates]) {
    for (a, b) in old.iter().zip(updated.iter_mut()) {
        let per = b.per_element();
        let mut flat = b.as_slice().to_vec();
        for (s, o) in flat.iter_mut().zip(a.as_slice()) {
            s.friction_pressure = o.friction_pressure
                + FRICTION_RELAXATION * (s.friction_pressure - o.friction_pressure);
        }
        *b = PointStates::from_flat(per, flat);
    }
}

/// Two failed attempts' histories agree: the same passes, statuses and
/// status changes at every iterate, and relative residuals within 1e-6 of
/// each other (the residuals are relative to the increment's force scale,
/// so a scaled problem gives the same numbers up to round-off), or both
/// not finite (an overflow that a smaller load fraction does not mend).
fn same_history(a: &[IterationRecord], b: &[IterationRecord]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.pass == y.pass
                && x.status == y.status
                && x.changed == y.changed
                && ((x.residual - y.residual).abs()
                    <= 1e-6 * x.residual.abs().max(y.residual.abs())
                    || !(x.residual.is_finite() || y.residual.is_finite()))
        })
}

/// Anderson mixing of the augmented-Lagrangian multiplier updates. Where
/// the statuses no longer change between passes, the Uzawa update
/// λ ← G(λ) = max(0, λ − k_n (Δu_n − closure)) is an affine map of λ, and
/// its changes shrink by the factors of its slow modes; where the penalty is
/// soft against the structure around it (the fused weld's corner on g0:
/// ρ ≈ 0.75–0.78) the plain updates take some thirty passes to 1e-4. From
/// the third update of a run of passes that end with the same statuses,
/// each quiet after its first iterate, the next multipliers are the
/// Anderson (type II) mix of the last [`MIXING_DEPTH`] + 1 updates:
/// x ← g_k − ΔG γ with γ the least-squares fit of f_k = g_k − x_k by the
/// differences ΔF of the f's (for an affine map, a Krylov method on its
/// fixed-point equation), kept ≥ 0. A status change starts the run afresh.
/// Two safeguards (since session 44): only a contracting loop is mixed (the
/// plain change smaller than the one before), and a mixed step more than
/// [`MAX_MIXED_STEP`] plain changes beyond the plain update is refused.
/// Without them, `--element-normals` on g0 (chord normals on curved
/// 6-node faces, whose multiplier loop cycles at t = 60 s) fitted γ of
/// 10¹⁴ and stepped 10¹⁷ Pa: the coupled fallback failed, the increment was
/// cut, and the run took 12 s instead of 2.4 s.
#[derive(Debug, Default)]
pub(super) struct MultiplierMixing {
    statuses: Option<Vec<super::PointStatus>>,
    /// The multipliers a settled pass started from (x) and their plain
    /// update (g), the last [`MIXING_DEPTH`] + 1.
    history: Vec<(Vec<f64>, Vec<f64>)>,
    /// Settled updates in the current run.
    run: usize,
}

impl MultiplierMixing {
    /// The pass that started from the multipliers `x` ended with
    /// `statuses` (`quiet`: no status changed after its first iterate), and
    /// its plain update is `g`: the multipliers to go on with instead, if
    /// it is time to mix.
    pub(super) fn observe(
        &mut self,
        statuses: Vec<super::PointStatus>,
        quiet: bool,
        x: Vec<f64>,
        g: Vec<f64>,
    ) -> Option<Vec<f64>> {
        if !quiet || self.statuses.as_ref() != Some(&statuses) {
            self.history.clear();
            self.run = 0;
        }
        self.statuses = Some(statuses);
        if !quiet {
            return None;
        }
        self.run += 1;
        self.history.push((x, g));
        if self.history.len() > MIXING_DEPTH + 1 {
            self.history.remove(0);
        }
        if self.run < MIXING_AFTER {
            return None;
        }
        let h = &self.history;
        let m = h.len() - 1;
        let f = |i: usize| -> Vec<f64> { h[i].1.iter().zip(&h[i].0).map(|(g, x)| g - x).collect() };
        let fs: Vec<Vec<f64>> = (0..=m).map(f).collect();
        let d_f: Vec<Vec<f64>> = (0..m)
            .map(|j| fs[j + 1].iter().zip(&fs[j]).map(|(a, b)| a - b).collect())
            .collect();
        // γ = argmin ‖f_k − ΔF γ‖ (least squares by the SVD of ΔF, its
        // singular values below 1e-10 of the largest dropped: a single slow
        // mode makes the differences parallel)
        // only a contracting iteration is mixed: where the plain changes
        // no longer shrink (a loop that cycles between two states) the
        // differences of the f's vanish against f and the fit is noise
        if norm(&fs[m]) >= norm(&fs[m - 1]) {
            return None;
        }
        let rows = fs[m].len();
        let d_f_mat = nalgebra::DMatrix::from_fn(rows, m, |r, c| d_f[c][r]);
        let svd = d_f_mat.svd(true, true);
        let largest = svd.singular_values.max();
        if !(largest.is_finite() && largest > 0.0) {
            return None;
        }
        let gamma = svd
            .solve(
                &nalgebra::DVector::from_column_slice(&fs[m]),
                1e-10 * largest,
            )
            .ok()?;
        let (_, g_k) = &h[m];
        let mut out = g_k.clone();
        for (j, gj) in gamma.iter().enumerate() {
            for (o, (a, b)) in out.iter_mut().zip(h[j + 1].1.iter().zip(&h[j].1)) {
                *o -= gj * (a - b);
            }
        }
        out.iter_mut().for_each(|v| *v = v.max(0.0));
        // a mixed step far beyond the plain one is an extrapolation the
        // fit cannot back (for a contraction ρ the remaining distance is
        // ρ/(1 − ρ) of the plain change: 9 at ρ = 0.9)
        let beyond: Vec<f64> = out.iter().zip(g_k).map(|(a, b)| a - b).collect();
        let step = norm(&beyond);
        (step.is_finite() && step <= MAX_MIXED_STEP * norm(&fs[m])).then_some(out)
    }
}

/// The largest mixed step beyond the plain update, as a multiple of the
/// plain change (see [`MultiplierMixing::observe`]).
const MAX_MIXED_STEP: f64 = 10.0;

/// Updates of the multipliers the mixing looks back on.
const MIXING_DEPTH: usize = 3;
/// The settled update from which on the updates are mixed (the earlier
/// ones are plain: most loops end within them, unchanged).
const MIXING_AFTER: usize = 3;

/// The multipliers of `states`, flat.
fn multipliers(states: &[PointStates]) -> Vec<f64> {
    states
        .iter()
        .flat_map(|s| s.as_slice().iter().map(|p| p.lambda_n))
        .collect()
}

/// `states` with the flat multipliers `lambda`.
fn set_multipliers(states: &mut [PointStates], lambda: &[f64]) {
    let mut k = 0;
    for b in states.iter_mut() {
        let per = b.per_element();
        let mut flat = b.as_slice().to_vec();
        for s in flat.iter_mut() {
            s.lambda_n = lambda[k];
            k += 1;
        }
        *b = PointStates::from_flat(per, flat);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn closed(n: usize) -> Vec<super::super::PointStatus> {
        vec![(ContactStatus::Stick, 0); n]
    }

    /// An affine map λ ← A λ + b with three slow modes (0.8, 0.6, 0.3; a
    /// multiplier update at settled statuses): mixed from its third update
    /// on, it is at its fixed point to 1e-10 after seven updates, where the
    /// plain iteration is still 4 % away.
    #[test]
    fn mixed_multiplier_updates_reach_the_fixed_point_of_an_affine_map() {
        let a = [0.8, 0.6, 0.3];
        let b = [1.0, 2.0, 0.5];
        let fixed: Vec<f64> = a.iter().zip(&b).map(|(a, b)| b / (1.0 - a)).collect();
        let g = |x: &[f64]| -> Vec<f64> {
            x.iter()
                .zip(a.iter().zip(&b))
                .map(|(x, (a, b))| a * x + b)
                .collect()
        };
        let err = |x: &[f64]| {
            x.iter()
                .zip(&fixed)
                .map(|(x, f)| (x - f).abs() / f)
                .fold(0.0, f64::max)
        };
        let mut mixing = MultiplierMixing::default();
        let (mut x, mut plain) = (vec![0.0; 3], vec![0.0; 3]);
        let mut mixed = 0;
        for _ in 0..7 {
            let gx = g(&x);
            x = match mixing.observe(closed(3), true, x.clone(), gx.clone()) {
                Some(m) => {
                    mixed += 1;
                    m
                }
                None => gx,
            };
            plain = g(&plain);
        }
        // (the seventh update, at the fixed point to round-off, no longer
        // contracts and stays plain)
        assert_eq!(mixed, 4);
        assert!(
            err(&x) < 1e-10,
            "mixed: {:.1e} from the fixed point",
            err(&x)
        );
        assert!(err(&plain) > 0.04, "plain: {:.1e}", err(&plain));
    }

    /// A loop whose plain changes do not shrink is not mixed: the
    /// multipliers of a joint point that alternates between two values
    /// (λ ← c − λ, its change the same size every time) gave differences
    /// of f that vanish against f, and fits of 10¹⁴ (`--element-normals`
    /// on g0: mixed steps of 10¹⁷ Pa, a failed increment, 12 s instead of
    /// 2.4 s).
    #[test]
    fn a_loop_that_does_not_contract_is_not_mixed() {
        let mut mixing = MultiplierMixing::default();
        let mut x = vec![0.0];
        for _ in 0..8 {
            let g: Vec<f64> = vec![3.0 - x[0]];
            assert!(
                mixing
                    .observe(closed(1), true, x.clone(), g.clone())
                    .is_none(),
                "mixed a cycling loop"
            );
            x = g;
        }
    }

    /// A mixed step more than `MAX_MIXED_STEP` times the plain change
    /// beyond the plain update is refused: λ ← 0.999 λ + 1 (ρ = 0.999)
    /// would be extrapolated by about 1 000 plain changes. A faster one
    /// (ρ = 0.8, four changes) is mixed.
    #[test]
    fn a_mixed_step_far_beyond_the_plain_update_is_refused() {
        let run = |rho: f64| {
            let mut mixing = MultiplierMixing::default();
            let mut x = vec![0.0];
            let mut mixed = 0;
            for _ in 0..6 {
                let g = vec![rho * x[0] + 1.0];
                x = match mixing.observe(closed(1), true, x.clone(), g.clone()) {
                    Some(m) => {
                        mixed += 1;
                        m
                    }
                    None => g,
                };
            }
            (mixed, x[0])
        };
        let (mixed, _) = run(0.999);
        assert_eq!(mixed, 0);
        let (mixed, x) = run(0.8);
        assert!(mixed > 0);
        assert!((x - 5.0).abs() < 1e-9, "{x}");
    }

    /// No mixing before the third settled update of a run: a status change
    /// between passes, or a pass that changed statuses after its first
    /// iterate, starts the run afresh. Mixed multipliers stay ≥ 0.
    #[test]
    fn only_runs_of_settled_passes_are_mixed() {
        let observe = |m: &mut MultiplierMixing, open: usize, quiet: bool, k: f64| {
            let mut st = closed(2);
            st[open].0 = ContactStatus::Open;
            // a map whose fixed point is negative: λ ← 0.5 λ − 1
            let x = vec![k, k];
            let g = x.iter().map(|v| 0.5 * v - 1.0).collect();
            m.observe(st, quiet, x, g)
        };
        let mut m = MultiplierMixing::default();
        assert!(observe(&mut m, 0, true, 4.0).is_none());
        assert!(observe(&mut m, 0, true, 3.0).is_none());
        // statuses moved: afresh
        assert!(observe(&mut m, 1, true, 2.5).is_none());
        assert!(observe(&mut m, 1, true, 2.0).is_none());
        // a pass that changed statuses: afresh
        assert!(observe(&mut m, 1, false, 1.5).is_none());
        assert!(observe(&mut m, 1, true, 1.2).is_none());
        assert!(observe(&mut m, 1, true, 1.1).is_none());
        let mixed = observe(&mut m, 1, true, 1.0).expect("the third settled update");
        assert_eq!(mixed, vec![0.0, 0.0]);
    }
}
