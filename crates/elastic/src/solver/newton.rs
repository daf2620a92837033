//! One Newton pass at fixed multipliers and friction limits.

use tecon_contact::FrictionBound;
use tecon_fem::FemError;

use crate::error::{ElasticError, IterationRecord};

use super::front::{CoupledNext, REOPENED_MIN_STEP};
use super::tracker::{PassTracker, failure};
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
        self.impose_prescribed(&mut u, loads);
        let opts = self.options;
        let mut t = PassTracker::new(norm(f_ext), pass).with_forcing(self.pass_forcing);
        let per_element: Vec<usize> = committed.iter().map(|s| s.per_element()).collect();
        // coupled passes: what the last cut-short step predicts for the next
        // (see `front::CoupledNext`)
        let mut contact_next = CoupledNext::default();
        // K u of the next iterate, when the line search has it already
        let mut next_ku: Option<Vec<f64>> = None;
        while t.history.len() < opts.max_iterations {
            // K u once per iterate: the tangent, the predicted branch and
            // the line search all start from it
            let ku = next_ku.take().unwrap_or_else(|| self.bulk_force(&u));
            let (kt, f_int) = self.tangent_and_force_from(&u, &ku, committed, true)?;
            let mut kt = kt.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
            let status_t = self.statuses(&u, committed);
            let r = self.residual(f_ext, &f_int);
            t.reference = t.reference.max(norm(&f_int));
            let rel = norm(&r) / t.reference;
            // The residual cannot fall below the round-off of the sums that
            // form it: with a stiff joint (a bonded interface with penalty
            // 1e5 E/h) that floor lies above the tolerance, and a linear
            // problem would otherwise iterate forever at it.
            let (floor, bound) = self.floor_or_bound(&kt, &u, f_ext, t.reference);
            let tolerance = opts.residual_tolerance.max(floor);
            // a corrected linear solve need not beat the convergence test
            let accept = LINEAR_SHARE * tolerance * t.reference;
            let obs = t.observe(status_t, rel, (floor, bound), tolerance, &opts)?;
            if obs.done {
                // open points carry no stiffness: a body that every one of
                // its interface points has let go of is held by nothing,
                // and the converged answer moves it arbitrarily
                // (an inexact pass's statuses are still moving: a body held
                // by friction alone may slip everywhere there; one whose
                // points are all open is free whatever follows)
                if obs.counts[0] > 0
                    && (!t.inexact || obs.counts[0] == obs.status.len())
                    && !self
                        .held_statuses
                        .as_ref()
                        .is_some_and(|h| no_softer(&obs.status, h))
                {
                    let kt = if opts.friction_bound == FrictionBound::Coupled && self.has_friction()
                    {
                        // the coupled slip tangent is not symmetric (its
                        // symmetric part is indefinite at high friction):
                        // the frozen limits' tangent has the same normal
                        // stiffness and shows what holds the bodies
                        self.frozen_tangent(&u, committed)?
                    } else {
                        kt
                    };
                    self.check_held_or_sliding(kt, &u, committed)?;
                    self.held_statuses = Some(obs.status);
                }
                return Ok((u, t.history));
            }
            if let Some(damped) = t.damped_points() {
                let flagged = self.with_secant_slip(committed, damped);
                let (k2, _) = self.tangent_and_force_from(&u, &ku, &flagged, true)?;
                let exact = std::mem::replace(
                    &mut kt,
                    k2.ok_or_else(|| FemError::Solver("tangent missing".into()))?,
                );
                self.recycle(exact);
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
            let symmetric = obs.counts[2] == 0 || opts.friction_bound == FrictionBound::Frozen;
            // (a coupled step of the tail cut short where points open or
            // close: the next step tries them so, as in the condensed pass)
            let trial = self.step_trial(
                &mut t,
                (&obs.status, &per_element),
                (symmetric, self.coupled_tail),
                std::mem::take(&mut contact_next),
            );
            let counts = trial.counts();
            let tried = if trial.coupled {
                self.coupled_predicted_step(
                    f_ext,
                    committed,
                    (&u, &ku, &r),
                    &trial.next,
                    &obs.status,
                    accept,
                    &mut contact_next,
                )?
            } else if trial.frozen_empty() {
                None
            } else {
                self.predicted_step(
                    f_ext,
                    committed,
                    (&u, &ku, &r),
                    (
                        &trial.predicted,
                        &trial.sticks,
                        &trial.slips,
                        &trial.reopened,
                    ),
                    t.damped_points(),
                    accept,
                )?
            };
            // (the reopened points tried closed: kept only if they close in a
            // full step, see `front::REOPENED_MIN_STEP`)
            let tried = tried.filter(|p| trial.reopened.is_empty() || p.step >= REOPENED_MIN_STEP);
            let fronts = trial.fronts();
            let (du, du_rotated, known_step) = match tried {
                Some(p) => {
                    t.kept_prediction(counts, &p.at_end);
                    next_ku = Some(p.ku_end);
                    (p.du, p.du_rotated, Some(p.step))
                }
                None => {
                    if fronts > 0 && t.rejected_prediction(counts, opts.max_iterations) {
                        break;
                    }
                    let solved = if !symmetric && self.coupled_tail {
                        // (a failed solve fails the pass, with its history)
                        self.coupled_tail_solve(&kt, &mut du, (&u, committed), accept)
                            .map_err(|e| match e {
                                ElasticError::NotConverged { reason, .. } => {
                                    failure(reason, t.history.clone())
                                }
                                e => e,
                            })
                    } else {
                        self.solve(&kt, &mut du, symmetric, accept)
                    };
                    match solved {
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
                            // (the failed factorisation may have left the factor
                            // unusable; its symbolic analysis stays)
                            if let Some(c) = self.cholesky.as_mut() {
                                c.invalidate();
                            }
                            let mut ks =
                                self.slip_stabilised_tangent(&u, committed, SLIP_STABILISATION)?;
                            self.rotations.rotate_matrix(&mut ks);
                            du.clone_from(&r);
                            self.prepared.apply_scaled(&mut ks, &mut du, 0.0);
                            if let Err(e) = self.solve(&ks, &mut du, true, accept) {
                                // a body that every interface point holding
                                // it has let go of: say so, not merely that
                                // the system is singular
                                return Err(self.floating_or(e, &u, committed));
                            }
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
                // the bulk is linear: K (u + α du) = K u + α K du, for the
                // line search and for the next iterate
                let kdu = self.bulk_force(&du);
                let step = self.energy_line_search(
                    f_ext,
                    committed,
                    (&u, &ku),
                    (&du, &kdu),
                    &du_rotated,
                    &r,
                )?;
                next_ku = Some(ku.iter().zip(&kdu).map(|(a, b)| a + step * b).collect());
                step
            } else {
                let step = self.residual_line_search(f_ext, committed, &u, &du, &r)?;
                if step < 1.0 && self.coupled_tail {
                    let at = |a: f64| u.iter().zip(&du).map(|(x, d)| x + a * d).collect();
                    contact_next = self.coupled_next(at, step, committed, &obs.status);
                }
                step
            };
            if symmetric && opts.front_prediction && step < 1.0 && t.predicts_from_full_steps() {
                let full: Vec<f64> = u.iter().zip(&du).map(|(a, b)| a + b).collect();
                t.short_step(&obs.status, &self.statuses(&full, committed));
            }
            self.recycle(kt);
            for (a, b) in u.iter_mut().zip(&du) {
                *a += step * b;
            }
            let unorm = norm(&u).max(f64::MIN_POSITIVE);
            t.stepped(step, step * norm(&du) / unorm)?;
            t.check_drift()?;
        }
        Err(failure(
            format!("no convergence in {} iterations", opts.max_iterations),
            t.history,
        ))
    }
}

impl StaticSolver<'_> {
    /// Solves the coupled law's non-symmetric step `kt du = rhs` (rotated,
    /// constrained) in the coupled tail of the outer loop by GMRES,
    /// preconditioned with the sparse Cholesky factor of the frozen limits'
    /// tangent at the same statuses (the limits set to the current
    /// pressures at `u`): see `gmres`. Where GMRES does not converge (many
    /// statuses changed since the preconditioner's), the sparse LU of the
    /// coupled tangent solves the step.
    fn coupled_tail_solve(
        &mut self,
        kt: &CsrMatrix,
        rhs: &mut [f64],
        (u, committed): (&[f64], &[PointStates]),
        accept: f64,
    ) -> Result<(), ElasticError> {
        let mut at_current = committed.to_vec();
        self.update_outer(u, &mut at_current, (true, false));
        let mut pre = self.frozen_tangent(u, &at_current)?;
        self.rotations.rotate_matrix(&mut pre);
        let mut zero = vec![0.0; rhs.len()];
        self.prepared.apply_scaled(&mut pre, &mut zero, 0.0);
        let chol = match &mut self.cholesky {
            Some(c) => c,
            None => self.cholesky.insert(self.tangent_cholesky()?),
        };
        let solved = super::gmres::solve(
            rhs,
            accept,
            |v| {
                let mut out = vec![0.0; v.len()];
                kt.mul_vec(v, &mut out);
                Ok(out)
            },
            |v| {
                chol.solve_within(&pre, v, 0.0)?;
                Ok(())
            },
        );
        match solved {
            Ok(Some(x)) => {
                rhs.copy_from_slice(&x);
                Ok(())
            }
            // GMRES did not converge: the sparse LU of the coupled tangent
            Ok(None) => self.solve(kt, rhs, false, accept),
            Err(e) => Err(failure(format!("coupled step: {e}"), Vec::new())),
        }
    }

    /// Errors with [`ElasticError::Floating`] when the tangent `k` (global
    /// frame, before the constraints) leaves a body free: at a converged
    /// state, one that no closed interface point holds any more.
    pub(super) fn check_held(&self, mut k: CsrMatrix) -> Result<(), ElasticError> {
        self.rotations.rotate_matrix(&mut k);
        let mut rhs = vec![0.0; k.n()];
        self.prepared.apply_scaled(&mut k, &mut rhs, 0.0);
        match check_rigid_modes(&k, &self.modes) {
            Err(FemError::Unconstrained {
                description,
                energy,
                ..
            }) => Err(ElasticError::Floating {
                description,
                energy,
            }),
            Err(e) => Err(e.into()),
            Ok(()) => Ok(()),
        }
    }

    /// [`StaticSolver::check_held`] on `k`; where that finds a body free,
    /// again on the frozen limits' tangent with a weak shear stiffness at
    /// the slipping points ([`StaticSolver::sliding_held_tangent`]). A body
    /// whose closed points all slide at their friction limit is held: its
    /// rigid mode costs no energy in the tangent (a slipping point has no
    /// shear stiffness, and a ring's rotation opens no gap), but friction
    /// resists it up to the limit, and the state is an equilibrium (only
    /// its rigid position is not unique; the stresses are). Only a body
    /// that every point holding it has let go of is free. Until session
    /// 44 such a state failed the run: `tecon vessel --layers 3 --mesh 2`
    /// stopped at stage 1, t = 10 s, its first ring (one seam, symmetric
    /// about it) "held by nothing" where it slid everywhere.
    pub(super) fn check_held_or_sliding(
        &self,
        k: CsrMatrix,
        u: &[f64],
        committed: &[PointStates],
    ) -> Result<(), ElasticError> {
        match self.check_held(k) {
            Err(ElasticError::Floating { .. }) => {
                self.check_held(self.sliding_held_tangent(u, committed, SLIP_STABILISATION)?)
            }
            other => other,
        }
    }

    /// Prescribed values at this load level. A rotated node's constrained
    /// dof is its component along the constraint's normal, so the values
    /// are set in the rotated frame: writing 0 into the global x component
    /// of a node on a skew symmetry edge would move it off that edge.
    pub(super) fn impose_prescribed(&self, u: &mut [f64], loads: &Loads) {
        self.rotations.rotate_vector(u);
        for (d, v) in self.dirichlet.iter() {
            u[d] = v * loads.displacement;
        }
        self.rotations.unrotate_vector(u);
    }
}

/// A kept step on a predicted branch (see [`StaticSolver::predicted_step`]).
pub(super) struct PredictedStep {
    /// The step direction (global frame) and the same in the rotated frame.
    du: Vec<f64>,
    du_rotated: Vec<f64>,
    /// The exact line search's step along it.
    step: f64,
    /// The statuses of the flat points at the end of the step.
    at_end: Vec<PointStatus>,
    /// The bulk force K u at the end of the step.
    ku_end: Vec<f64>,
}

/// Shear stiffness of slipping joint points, as a fraction of k_s, in the
/// fallback tangent of an iterate where a body is held by slipping points
/// only (see [`StaticSolver::slip_stabilised_tangent`]).
pub(super) const SLIP_STABILISATION: f64 = 1e-6;

/// Safety factor of the round-off floor over `ε · ‖ |K| |u| + |f| ‖` (the
/// error of a sum of n terms grows like √n ε in practice, n ≤ ~30 per row
/// here, and the tangent's entries carry their own assembly round-off).
pub(super) const ROUND_OFF_FACTOR: f64 = 64.0;

/// Round-off floor of ‖R‖ = ‖f_ext − K u‖: `ε · ‖ |K| |u| + |f_ext| ‖`
/// (row-wise sums of magnitudes), times [`ROUND_OFF_FACTOR`].
///
/// The rows are summed in fixed chunks of [`FLOOR_CHUNK`], in parallel, and
/// the chunks' sums added in order: the same number whatever the thread
/// count (it decides convergence).
pub(super) fn round_off_floor(k: &CsrMatrix, u: &[f64], f_ext: &[f64]) -> f64 {
    use rayon::prelude::*;
    let (ptr, idx, val) = (k.pattern().indptr(), k.pattern().indices(), k.values());
    let rows = |r: std::ops::Range<usize>| -> f64 {
        r.map(|i| {
            let row: f64 = (ptr[i]..ptr[i + 1])
                .map(|q| (val[q] * u[idx[q]]).abs())
                .sum();
            (row + f_ext[i].abs()).powi(2)
        })
        .sum()
    };
    let n = k.n();
    let chunks: Vec<f64> = (0..n.div_ceil(FLOOR_CHUNK))
        .into_par_iter()
        .map(|c| rows(c * FLOOR_CHUNK..((c + 1) * FLOOR_CHUNK).min(n)))
        .collect();
    let s: f64 = chunks.iter().sum();
    ROUND_OFF_FACTOR * f64::EPSILON * s.sqrt()
}

/// Rows per chunk of [`round_off_floor`].
const FLOOR_CHUNK: usize = 2048;

/// The largest sum of magnitudes Σⱼ |k_ij| over the rows `rows` of `k`.
pub(super) fn max_row_abs(k: &CsrMatrix, rows: impl Iterator<Item = usize>) -> f64 {
    let (ptr, val) = (k.pattern().indptr(), k.values());
    rows.map(|i| val[ptr[i]..ptr[i + 1]].iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// An upper bound of [`round_off_floor`] for a symmetric matrix whose
/// largest row sum of magnitudes is `rows`: ‖ |K| |u| + |f| ‖ ≤
/// ‖ |K| ‖₂ ‖u‖ + ‖f‖ ≤ rows ‖u‖ + ‖f‖, with a factor 2 for the rounding
/// of the bound itself.
pub(super) fn floor_bound(rows: f64, u: &[f64], f_ext: &[f64]) -> f64 {
    2.0 * ROUND_OFF_FACTOR * f64::EPSILON * (rows * norm(u) + norm(f_ext))
}

impl StaticSolver<'_> {
    /// The round-off floor of the residual at `u` relative to `reference`
    /// (see [`round_off_floor`]), or an upper bound of it, with `true`,
    /// when that bound is below the residual tolerance: the floor enters
    /// every decision only through its comparison with the tolerance (the
    /// convergence test takes the larger of the two), so the exact value
    /// cannot change anything then, and the pass over the tangent with
    /// the products |k_ij u_j| (about 5 % of a two-way vessel run) is
    /// saved.
    ///
    /// The bound: ‖ |K| |u| + |f| ‖ ≤ ‖ |K| ‖₂ ‖u‖ + ‖f‖, and for the
    /// symmetric |K| the spectral norm is at most its largest row sum,
    /// which is that of K_bulk outside the interface rows (computed once)
    /// or that of an interface row of the tangent. A non-symmetric tangent
    /// (the coupled friction law) takes the exact floor.
    fn floor_or_bound(
        &self,
        kt: &CsrMatrix,
        u: &[f64],
        f_ext: &[f64],
        reference: f64,
    ) -> (f64, bool) {
        if self.options.friction_bound != FrictionBound::Coupled {
            let rows = max_row_abs(kt, self.interface_dofs.iter().copied()).max(self.rest_row_abs);
            let bound = floor_bound(rows, u, f_ext) / reference;
            if bound <= self.options.residual_tolerance {
                return (bound, true);
            }
        }
        (round_off_floor(kt, u, f_ext) / reference, false)
    }
}

impl StaticSolver<'_> {
    /// A coupled tail step on the branch where the points `closing` are
    /// closed and `opening` open (see `front::COUPLED_PREDICTION_REACH`):
    /// the coupled tangent there, solved as the tail's steps are, and the
    /// residual line search on the true laws; `next` gets the points whose
    /// contact changes a little further along it if it is cut short. None
    /// if the step cannot be solved (the exact step is taken instead).
    #[allow(clippy::too_many_arguments)]
    fn coupled_predicted_step(
        &mut self,
        f_ext: &[f64],
        committed: &[PointStates],
        (u, ku, r): (&[f64], &[f64], &[f64]),
        predicted: &CoupledNext,
        now: &[PointStatus],
        accept: f64,
        next: &mut CoupledNext,
    ) -> Result<Option<PredictedStep>, ElasticError> {
        let mut forced =
            self.forced_branch(committed, (&predicted.open, &predicted.stick, &[]), None, u);
        self.force_closed(&mut forced, &predicted.close);
        let (kt, f_int) = self.tangent_and_force_from(u, ku, &forced, true)?;
        let mut kt = kt.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
        self.rotations.rotate_matrix(&mut kt);
        let mut du = self.residual(f_ext, &f_int);
        self.prepared.apply_scaled(&mut kt, &mut du, 0.0);
        let solved = self.coupled_tail_solve(&kt, &mut du, (u, committed), accept);
        self.recycle(kt);
        if solved.is_err() {
            return Ok(None);
        }
        let du_rotated = du.clone();
        self.rotations.unrotate_vector(&mut du);
        let step = self.residual_line_search(f_ext, committed, u, &du, r)?;
        if step < 1.0 {
            let at = |a: f64| u.iter().zip(&du).map(|(x, d)| x + a * d).collect();
            *next = self.coupled_next(at, step, committed, now);
        }
        let kdu = self.bulk_force(&du);
        Ok(Some(self.kept_step(
            committed,
            (u, ku),
            (du, du_rotated, kdu),
            step,
        )))
    }

    /// A predicted step `du` (global and rotated frame, `kdu` = K du) kept
    /// with the line-search step `step` from `u` (`ku` = K u).
    fn kept_step(
        &self,
        committed: &[PointStates],
        (u, ku): (&[f64], &[f64]),
        (du, du_rotated, kdu): (Vec<f64>, Vec<f64>, Vec<f64>),
        step: f64,
    ) -> PredictedStep {
        let end: Vec<f64> = u.iter().zip(&du).map(|(a, b)| a + step * b).collect();
        let at_end = self.statuses(&end, committed).iter().map(|s| s.0).collect();
        let ku_end = ku.iter().zip(&kdu).map(|(a, b)| a + step * b).collect();
        PredictedStep {
            du,
            du_rotated,
            step,
            at_end,
            ku_end,
        }
    }

    /// The Newton step from `u` on the branch where the flat points
    /// `predicted` are open, `sticks` stick, `slips` slip and `closed` are
    /// closed (see `front`), if it is a descent direction of
    /// the exact energy (`r` is the exact residual at `u`, rotated frame;
    /// `accept` as for [`StaticSolver::solve`]), with the exact line-search
    /// step along it (which lowers the energy, however short), as a
    /// [`PredictedStep`]; `None` otherwise. A short step is kept too: rejecting it (as below
    /// half a step, before) cost a second solve for the exact Newton step,
    /// one iteration in five of the first pass on `t1e5`.
    #[allow(clippy::type_complexity, clippy::too_many_arguments)]
    fn predicted_step(
        &mut self,
        f_ext: &[f64],
        committed: &[PointStates],
        (u, ku, r): (&[f64], &[f64], &[f64]),
        (predicted, sticks, slips, closed): (&[usize], &[usize], &[usize], &[usize]),
        damped: Option<&[bool]>,
        accept: f64,
    ) -> Result<Option<PredictedStep>, ElasticError> {
        let mut forced = self.forced_branch(committed, (predicted, sticks, slips), damped, u);
        self.force_closed(&mut forced, closed);
        let (kt, f_int) = self.tangent_and_force_from(u, ku, &forced, true)?;
        let mut kt = kt.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
        self.rotations.rotate_matrix(&mut kt);
        let mut du = self.residual(f_ext, &f_int);
        self.prepared.apply_scaled(&mut kt, &mut du, 0.0);
        let solved = self.solve(&kt, &mut du, true, accept);
        self.recycle(kt);
        if solved.is_err() {
            // e.g. a body left without support: start the factor afresh
            // (the symbolic analysis stays)
            if let Some(c) = self.cholesky.as_mut() {
                c.invalidate();
            }
            return Ok(None);
        }
        if dot(r, &du) <= 0.0 {
            return Ok(None);
        }
        let du_rotated = du.clone();
        self.rotations.unrotate_vector(&mut du);
        let kdu = self.bulk_force(&du);
        let step =
            self.energy_line_search(f_ext, committed, (u, ku), (&du, &kdu), &du_rotated, r)?;
        Ok(Some(self.kept_step(
            committed,
            (u, ku),
            (du, du_rotated, kdu),
            step,
        )))
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use tecon_fem::SparsityPattern;

    use super::*;

    /// A symmetric matrix on a 2D grid graph with entries of both signs and
    /// very different sizes (stiff springs on a few rows), as a tangent
    /// with penalty springs has.
    fn matrix(m: usize) -> CsrMatrix {
        let n = m * m;
        let mut blocks = Vec::new();
        for j in 0..m - 1 {
            for i in 0..m - 1 {
                let a = j * m + i;
                blocks.push(vec![a, a + 1, a + m + 1, a + m]);
            }
        }
        let refs: Vec<(usize, &[usize])> = blocks.iter().map(|b| (4, b.as_slice())).collect();
        let p = Arc::new(SparsityPattern::from_blocks(n, &refs).unwrap());
        let mut k = CsrMatrix::zeros(p.clone());
        let (ptr, idx) = (p.indptr(), p.indices());
        let v = k.values_mut();
        for i in 0..n {
            for q in ptr[i]..ptr[i + 1] {
                let j = idx[q];
                let (a, b) = (i.min(j), i.max(j));
                let x = ((a * 7919 + b * 104_729) % 1000) as f64 / 1000.0 - 0.5;
                let stiff = if a == b && a % 97 == 0 { 1e9 } else { 1.0 };
                v[q] = if a == b { 4.0 * stiff } else { x };
            }
        }
        k
    }

    #[test]
    fn the_floor_bound_is_above_the_floor() {
        let k = matrix(40);
        let n = k.n();
        let rows = max_row_abs(&k, 0..n);
        for seed in 0..5usize {
            let u: Vec<f64> = (0..n)
                .map(|i| (((i + 3) * (seed + 11) * 2_654_435_761usize) % 2001) as f64 - 1000.0)
                .collect();
            let f: Vec<f64> = (0..n)
                .map(|i| if i % 13 == seed { 1e3 } else { 0.0 })
                .collect();
            let exact = round_off_floor(&k, &u, &f);
            let bound = floor_bound(rows, &u, &f);
            assert!(
                exact > 0.0 && bound >= exact,
                "bound {bound:e} below the floor {exact:e}"
            );
            // and not vacuous: within two orders of magnitude here
            assert!(bound <= 100.0 * exact, "bound {bound:e}, floor {exact:e}");
        }
        // the largest row sum split as the solver splits it (the interface
        // rows of the tangent, the other rows once) is the same
        let (a, b) = (0..n / 3, n / 3..n);
        assert_eq!(max_row_abs(&k, a).max(max_row_abs(&k, b)), rows);
    }
}
