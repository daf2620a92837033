//! One Newton pass at fixed multipliers and friction limits.

use tecon_contact::FrictionBound;
use tecon_fem::FemError;

use crate::error::{ElasticError, IterationRecord};

use super::front;
use super::*;

impl StaticSolver<'_> {
    pub(super) fn newton(
        &mut self,
        f_ext: &[f64],
        loads: &Loads,
        committed: &[PointStates],
        mut u: Vec<f64>,
        pass: usize,
    ) -> Result<(Vec<f64>, Vec<IterationRecord>), ElasticError> {
        // Prescribed values at this load level. A rotated node's constrained
        // dof is its component along the constraint's normal, so the values
        // are set in the rotated frame: writing 0 into the global x component
        // of a node on a skew symmetry edge would move it off that edge.
        self.rotations.rotate_vector(&mut u);
        for (d, v) in self.dirichlet.iter() {
            u[d] = v * loads.displacement;
        }
        self.rotations.unrotate_vector(&mut u);
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
        // front prediction (see `front`): element hops ahead of the points
        // that just opened, doubled after every kept prediction
        let mut reach = 1usize;
        let per_element: Vec<usize> = committed.iter().map(|s| s.per_element()).collect();
        // points whose stick/slip status oscillated in this pass: their
        // slipping tangent is the secant one from then on (see below)
        let mut damped: Vec<bool> = Vec::new();
        // The damping is a fallback: it starts at the first status pattern
        // repeated two iterates later (a pass that converges without a
        // repeat keeps the exact path, bit for bit), and the ping-pong guard
        // then counts afresh, once.
        let mut damping = false;
        while history.len() < opts.max_iterations {
            let it = history.len();
            let (kt, f_int) = self.tangent_and_force(&u, committed, true)?;
            let mut kt = kt.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
            let status = self.statuses(&u, committed);
            let status_t = status.clone();
            let r = self.residual(f_ext, &f_int);
            reference = reference.max(norm(&f_int));
            let rel = norm(&r) / reference;
            // The residual cannot fall below the round-off of the sums that
            // form it: with a stiff joint (a bonded interface with penalty
            // 1e5 E/h) that floor lies above the tolerance, and a linear
            // problem would otherwise iterate forever at it.
            let floor = round_off_floor(&kt, &u, f_ext) / reference;
            let tolerance = opts.residual_tolerance.max(floor);
            // a corrected linear solve need not beat the convergence test
            let accept = LINEAR_SHARE * tolerance * reference;
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
                if !damping && opts.slip_damping {
                    damping = true;
                    ping_pong = 0;
                }
            }
            // A point back where it was two iterates ago, via another
            // status, with slip on one side: the exact slip tangent (0)
            // sends it across the kink again and the line search stops it
            // there — a zigzag of short steps (high friction). Such points
            // take the secant slip stiffness k_s s/|τ_trial| until the
            // statuses settle: a positive definite tangent, so still a
            // descent direction for the exact energy line search, and the
            // converged answer does not change.
            if let (Some(p), Some(p2)) = (&prev, &prev2) {
                damped.resize(status.len(), false);
                for (i, s) in status.iter().enumerate() {
                    let was = p[i].0;
                    if *s == p2[i] && *s != was && (s.1 != 0 || was.1 != 0) {
                        damped[i] = true;
                    }
                }
            }
            let counts = count(&status);
            let last_correction = history.last().map_or(f64::INFINITY, |h| h.correction);
            // After a full step with no status change the linearisation was
            // exact (the problem is piecewise linear), so the residual alone
            // measures the error; otherwise the correction must be small too.
            let full_step = history.last().is_some_and(|h| h.step == 1.0);
            let converged = it > 0
                && rel <= tolerance
                && changed == 0
                && (last_correction <= opts.correction_tolerance
                    || rel <= tolerance * 1e-3
                    || full_step);
            history.push(IterationRecord {
                pass,
                iteration: it,
                residual: rel,
                correction: 0.0,
                step: 0.0,
                status: counts,
                changed,
                floor,
                predicted: 0,
                rejected: false,
            });
            if converged || (rel == 0.0 && changed == 0) {
                return Ok((u, history));
            }
            if ping_pong > opts.max_ping_pong {
                return Err(failure(
                    format!("contact status ping-pong ({ping_pong} repeats)"),
                    history,
                ));
            }
            if changed == 0 {
                // statuses settled: the exact tangent converges in one step
                // (the secant one only linearly)
                damped.fill(false);
            }
            if damping && damped.iter().any(|&d| d) {
                let flagged = self.with_secant_slip(committed, &damped);
                let (k2, _) = self.tangent_and_force(&u, &flagged, true)?;
                kt = k2.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
            }
            // Tangent in the rotated frame, homogeneous constraints on the correction.
            self.rotations.rotate_matrix(&mut kt);
            let mut du = r.clone();
            self.prepared.apply_scaled(&mut kt, &mut du, 0.0);
            if !self.modes_checked {
                self.check_modes(&kt)?;
                if !self.modes_checked {
                    // a minimal constraint was added: start over
                    return self.newton(f_ext, loads, committed, u, pass);
                }
            }
            let symmetric = counts[2] == 0 || opts.friction_bound == FrictionBound::Frozen;
            let predicted = match &prev {
                Some(p) if symmetric && opts.front_prediction => {
                    let before: Vec<PointStatus> = p.iter().map(|s| s.0).collect();
                    front::predicted_openings(
                        &self.neighbours,
                        &per_element,
                        &before,
                        &status,
                        reach,
                    )
                }
                _ => Vec::new(),
            };
            let trial = if predicted.is_empty() {
                None
            } else {
                self.predicted_step(f_ext, committed, &u, &r, &predicted, accept)?
            };
            let (du, du_rotated, known_step) = match trial {
                Some((du, du_rotated, step, all_open)) => {
                    // a front that was not reached by all predicted points
                    // is near: look less far ahead next time
                    reach = if all_open {
                        2 * reach
                    } else {
                        (reach / 2).max(1)
                    };
                    if let Some(h) = history.last_mut() {
                        h.predicted = predicted.len();
                    }
                    (du, du_rotated, Some(step))
                }
                None => {
                    if !predicted.is_empty() {
                        // the trial cost a solve: it counts as an iteration
                        reach = 1;
                        if let Some(mut again) = history.last().cloned() {
                            if let Some(h) = history.last_mut() {
                                h.predicted = predicted.len();
                                h.rejected = true;
                            }
                            again.iteration += 1;
                            history.push(again);
                        }
                        if history.len() >= opts.max_iterations {
                            break;
                        }
                    }
                    match self.solve(&kt, &mut du, symmetric, accept) {
                        Err(ElasticError::Fem(FemError::Unconstrained { .. }))
                            if symmetric && self.has_friction() =>
                        {
                            // Every joint point holding a body slips or is open at
                            // this iterate (a full ring held only by its
                            // interface): the energy is linear along the body's
                            // rigid mode up to the next kink. This step uses a
                            // weak shear stiffness at the slipping points, so it
                            // moves far along the mode and the line search (on the
                            // true energy) stops it at the kink; the next tangent
                            // has a sticking point again. A body that stays free
                            // with it fails below, named.
                            // (the failed factorisation may have left the factor unusable)
                            self.cholesky = None;
                            let mut ks =
                                self.slip_stabilised_tangent(&u, committed, SLIP_STABILISATION)?;
                            self.rotations.rotate_matrix(&mut ks);
                            du.clone_from(&r);
                            self.prepared.apply_scaled(&mut ks, &mut du, 0.0);
                            self.solve(&ks, &mut du, true, accept)?;
                        }
                        other => other?,
                    }
                    let du_rotated = du.clone();
                    self.rotations.unrotate_vector(&mut du);
                    (du, du_rotated, None)
                }
            };
            let step = if let Some(step) = known_step {
                step
            } else if symmetric {
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
                return Err(failure(
                    "the line search keeps cutting the Newton step (stagnation)",
                    history,
                ));
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
        Err(failure(
            format!("no convergence in {} iterations", opts.max_iterations),
            history,
        ))
    }
}

/// Shear stiffness of slipping joint points, as a fraction of k_s, in the
/// fallback tangent of an iterate where a body is held by slipping points
/// only (see [`StaticSolver::slip_stabilised_tangent`]).
const SLIP_STABILISATION: f64 = 1e-6;

/// Safety factor of the round-off floor over `ε · ‖ |K| |u| + |f| ‖` (the
/// error of a sum of n terms grows like √n ε in practice, n ≤ ~30 per row
/// here, and the tangent's entries carry their own assembly round-off).
const ROUND_OFF_FACTOR: f64 = 64.0;

/// Round-off floor of ‖R‖ = ‖f_ext − K u‖: `ε · ‖ |K| |u| + |f_ext| ‖`
/// (row-wise sums of magnitudes), times [`ROUND_OFF_FACTOR`].
fn round_off_floor(k: &CsrMatrix, u: &[f64], f_ext: &[f64]) -> f64 {
    let (ptr, idx, val) = (k.pattern().indptr(), k.pattern().indices(), k.values());
    let s: f64 = (0..k.n())
        .map(|i| {
            let row: f64 = (ptr[i]..ptr[i + 1])
                .map(|q| (val[q] * u[idx[q]]).abs())
                .sum();
            (row + f_ext[i].abs()).powi(2)
        })
        .sum();
    ROUND_OFF_FACTOR * f64::EPSILON * s.sqrt()
}

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

impl StaticSolver<'_> {
    /// The Newton step from `u` on the branch where the flat points
    /// `predicted` are open (see `front`), if it is a descent direction of
    /// the exact energy (`r` is the exact residual at `u`, rotated frame; `accept` as for [`StaticSolver::solve`])
    /// whose exact line-search step is at least [`KEEP_PREDICTED_STEP`]:
    /// `(du, du_rotated, step, every predicted point open at u + step du)`;
    /// `None` otherwise.
    #[allow(clippy::type_complexity)]
    fn predicted_step(
        &mut self,
        f_ext: &[f64],
        committed: &[PointStates],
        u: &[f64],
        r: &[f64],
        predicted: &[usize],
        accept: f64,
    ) -> Result<Option<(Vec<f64>, Vec<f64>, f64, bool)>, ElasticError> {
        let forced = self.forced_open(committed, predicted);
        let (kt, f_int) = self.tangent_and_force(u, &forced, true)?;
        let mut kt = kt.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
        self.rotations.rotate_matrix(&mut kt);
        let mut du = self.residual(f_ext, &f_int);
        self.prepared.apply_scaled(&mut kt, &mut du, 0.0);
        if self.solve(&kt, &mut du, true, accept).is_err() {
            // e.g. a body left without support: start the factor afresh
            self.cholesky = None;
            return Ok(None);
        }
        if dot(r, &du) <= 0.0 {
            return Ok(None);
        }
        let du_rotated = du.clone();
        self.rotations.unrotate_vector(&mut du);
        let step = self.energy_line_search(f_ext, committed, u, &du, &du_rotated, r)?;
        if step < KEEP_PREDICTED_STEP {
            return Ok(None);
        }
        let end: Vec<f64> = u.iter().zip(&du).map(|(a, b)| a + step * b).collect();
        let status = self.statuses(&end, committed);
        let all_open = predicted
            .iter()
            .all(|&i| status[i].0.0 == ContactStatus::Open);
        Ok(Some((du, du_rotated, step, all_open)))
    }
}

/// Shortest exact line-search step for which a predicted step is kept
/// (shorter: the prediction was far off, the exact Newton step is taken).
const KEEP_PREDICTED_STEP: f64 = 0.5;
