//! Newton passes on the interface dofs alone (static condensation).
//!
//! Why: the bulk is linear and its stiffness never changes; only the
//! interface points' forces and tangents do, on the dofs Γ of the interface
//! nodes (1 840 of 101 000 on `t1e5`). A full Newton iteration costs sparse
//! solves and matrix passes over the whole mesh; on Γ it costs dense
//! operations of size m = |Γ|.
//!
//! How: the bulk (rotated, with the homogeneous constraints) is condensed
//! once per solver onto Γ ([`tecon_fem::CondensedCholesky`]): S = A_ΓΓ − C.
//! A pass first puts the interior in equilibrium with the interface dofs
//! (one solve with A_II: the residual on I becomes zero). As long as the
//! interior follows the interface dofs (Δu_I = −A_II⁻¹ A_IΓ δ), the residual
//! on I stays zero and the bulk residual on Γ is `r_b − S δ`, with δ the
//! change of the interface dofs since the start of the pass. The pass then
//! iterates on δ alone — statuses, convergence test, front prediction,
//! damping and the exact energy line search as in the full pass
//! ([`PassTracker`]). The next pass of the increment goes on from where
//! this one ended (δ counted from the same start), and the interior is
//! recovered once, when the increment ends, by one more solve
//! ([`Pending`]). The converged state is the same as the full pass's: the
//! condensed equations are the full equations with the interior
//! eliminated exactly.
//!
//! What differs: the iterates' interior dofs are always in equilibrium
//! (the full pass takes them along the line-search step), so the path, and
//! the iteration counts, can differ slightly; the force scale and the
//! round-off floor of the convergence test are taken at the start of the
//! pass (the interior forces equal the external ones within it).

use tecon_contact::FrictionBound;
use tecon_fem::{CondensedCholesky, FemError};

use crate::error::{ElasticError, IterationRecord};

use super::coarse::{COARSE_GATE, COARSE_MAX_ITERATIONS, COARSE_TOLERANCE, CoarseSpace};
use super::front::{CoupledNext, REOPENED_MIN_STEP};
use super::line_search::{backtrack, root_along_ray};
use super::newton::ROUND_OFF_FACTOR;
use super::tracker::PassTracker;
use super::*;

/// Largest interface system condensed (dense m × m arrays, three of them:
/// 1.5 GB at this size).
const MAX_CONDENSED: usize = 8192;

/// The bulk condensed onto the interface dofs.
#[derive(Debug)]
pub(super) struct Condensed {
    chol: CondensedCholesky,
    /// A_ΓΓ of the constrained, rotated bulk (in `gamma_entries` order);
    /// the rows and columns of constrained Γ dofs are zero but for their
    /// diagonal.
    bulk_gg: Vec<f64>,
    /// Constrained Γ positions.
    fixed: Vec<bool>,
    /// Full-pattern matrix the interface tangents are assembled into; only
    /// its Γ × Γ entries are read (and zeroed before each assembly).
    scratch: CsrMatrix,
    /// The coarse spaces of the first passes, coarsest first (empty: off, or
    /// the interfaces are no simple chains; see `coarse`).
    coarse: Vec<CoarseSpace>,
}

/// The state at the end of a condensed pass, kept so that the next pass of
/// the increment goes on from it and the interior is recovered once per
/// increment instead of once per pass (the recovery is a sparse solve with
/// A_II: on `t1e5`, about half of the contact solve when made after every
/// pass). Only Γ's entries of the vector a pass hands back are current;
/// [`StaticSolver::settle_interior`] makes the rest.
#[derive(Debug)]
pub(super) struct Pending {
    /// The vector the pass handed back: Γ entries current, the interior
    /// entries those of `start`.
    uf: Vec<f64>,
    /// The increment's external forces.
    f_ext: Vec<f64>,
    /// Where the chain of passes started, the interior in equilibrium.
    chain: Chain,
}

/// A chain of condensed passes from `start` (its interior in equilibrium
/// with its interface dofs): the interface dofs moved by `delta` since, the
/// bulk residual on Γ at `start`, and the start's interior parts of the
/// force scale and of the round-off floor.
#[derive(Debug, Clone)]
struct Chain {
    start: Vec<f64>,
    rb0: Vec<f64>,
    delta: Vec<f64>,
    s_delta: Vec<f64>,
    floor_i2: f64,
    f_int_i2: f64,
    interior_norm2: f64,
}

/// How a condensed pass ended.
pub(super) enum Outcome {
    Done(Vec<f64>, Vec<IterationRecord>),
    /// The Schur system lost positive definiteness (a body held by no
    /// closed point): the full pass, which names the body or stabilises
    /// the step, takes over.
    FullPass,
}

impl StaticSolver<'_> {
    /// True when this solver's passes run condensed: a symmetric pass
    /// (frozen friction limits), no rotated interface node, and a dense
    /// interface system that is cheaper than the sparse factor of the
    /// whole mesh: m² ≤ nnz(L) (the dense operations per iteration against
    /// the sparse solves and refactorisations of the full pass). Measured
    /// on the vessel: level 4 (m = 1 092, 36 036 dofs) and `t1e5` (m =
    /// 1 840, 101 200 dofs) run 2× and 4× faster condensed; g0 (order 2, m
    /// = 1 396, 12 564 dofs) 2× slower, and it stays full.
    fn condensable(&mut self) -> Result<bool, ElasticError> {
        if let Some(c) = self.condensed_choice {
            return Ok(c);
        }
        let m = self.interface_dofs.len();
        let frozen = self.options.friction_bound == FrictionBound::Frozen || !self.has_friction();
        let mut choice = frozen
            && m > 0
            && m <= MAX_CONDENSED
            && self
                .interface_dofs
                .iter()
                .all(|&d| !self.rotations.contains(d / 2))
            && self.options.condensation;
        if choice {
            // the full pass's analysis (the fall-back needs it anyway)
            let c = match &mut self.cholesky {
                Some(c) => c,
                None => self.cholesky.insert(self.tangent_cholesky()?),
            };
            choice = m * m <= c.factor_nnz();
        }
        self.condensed_choice = Some(choice);
        Ok(choice)
    }

    /// The number of interface dofs the passes are condensed onto, if they
    /// are.
    pub fn condensed_dofs(&self) -> Option<usize> {
        self.condensed.as_ref().map(|c| c.chol.gamma().len())
    }

    /// Newton steps taken in the coarse interface space before first passes
    /// (see `coarse`), over the solver's life, failed attempts included;
    /// not counted as Newton iterations.
    pub fn coarse_iterations(&self) -> usize {
        self.coarse_total
    }

    /// The coarse interface space's dofs, if the condensed passes have one.
    pub fn coarse_dofs(&self) -> Option<usize> {
        self.condensed
            .as_ref()
            .and_then(|c| c.coarse.last())
            .map(CoarseSpace::dofs)
    }

    /// How the condensed passes' dense interface systems were solved, and
    /// how many times the bulk was condensed.
    pub(super) fn condensed_stats(&self) -> Option<(UpdateStats, usize)> {
        self.condensed
            .as_ref()
            .map(|c| (c.chol.stats(), c.chol.condensations()))
    }

    /// One Newton pass, condensed onto the interface dofs when it can be.
    pub(super) fn newton_pass(
        &mut self,
        f_ext: &[f64],
        loads: &Loads,
        committed: &[PointStates],
        mut u: Vec<f64>,
        pass: usize,
    ) -> Result<(Vec<f64>, Vec<IterationRecord>), ElasticError> {
        if self.condensed_failed || !self.condensable()? {
            self.settle_interior(&mut u)?;
            return self.newton(f_ext, loads, committed, u, pass);
        }
        self.impose_prescribed(&mut u, loads);
        if !self.modes_checked {
            // the rigid-mode check (which may add a minimal constraint) is
            // made on the full tangent, as in the full pass
            let (kt, _) = self.tangent_and_force(&u, committed, true)?;
            let mut kt = kt.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
            self.rotations.rotate_matrix(&mut kt);
            let mut zero = vec![0.0; u.len()];
            self.prepared.apply_scaled(&mut kt, &mut zero, 0.0);
            self.check_modes(&kt)?;
            if !self.modes_checked {
                // a minimal constraint was added (and the condensation
                // dropped): start over
                return self.newton_pass(f_ext, loads, committed, u, pass);
            }
        }
        if self.condensed.is_none() {
            match self.condense() {
                Ok(c) => self.condensed = Some(c),
                // an interior held by nothing (a body without interface
                // and constraints): the full pass names it
                Err(ElasticError::Fem(FemError::NotPositiveDefinite { .. })) => {
                    self.condensed_failed = true;
                    return self.newton(f_ext, loads, committed, u, pass);
                }
                Err(e) => return Err(e),
            }
        }
        let Some(mut cx) = self.condensed.take() else {
            self.settle_interior(&mut u)?;
            return self.newton(f_ext, loads, committed, u, pass);
        };
        // the chain of the passes before, if `u` is where the last one ended
        // (kept until this pass ends: a pass that fails or hands over to
        // the full pass leaves `u` as it was)
        let chain = self
            .pending
            .as_ref()
            .filter(|p| same_bits(&p.uf, &u) && same_bits(&p.f_ext, f_ext))
            .map(|p| p.chain.clone());
        let outcome = self.condensed_pass(&mut cx, f_ext, committed, u.clone(), chain, pass);
        self.condensed = Some(cx);
        match outcome? {
            Outcome::Done(u, history) => Ok((u, history)),
            Outcome::FullPass => {
                self.settle_interior(&mut u)?;
                self.newton(f_ext, loads, committed, u, pass)
            }
        }
    }

    /// Recovers the interior of `u` when it is the vector the last condensed
    /// pass handed back (see [`Pending`]): Δu_I = −A_II⁻¹ A_IΓ δ from the
    /// start of the chain. Any other `u` is complete already.
    pub(super) fn settle_interior(&mut self, u: &mut Vec<f64>) -> Result<(), ElasticError> {
        let Some(p) = self.pending.take() else {
            return Ok(());
        };
        if !same_bits(&p.uf, u) {
            return Ok(());
        }
        let cx = self.condensed.as_mut().ok_or_else(|| {
            FemError::Solver("condensed pass state without its condensation".into())
        })?;
        let Chain {
            mut start, delta, ..
        } = p.chain;
        let mut d_i = cx.chol.mul_interior_gamma(&delta);
        cx.chol.solve_interior(&mut d_i)?;
        let mut dv = vec![0.0; start.len()];
        for (&d, &x) in cx.chol.interior().iter().zip(&d_i) {
            dv[d] = -x;
        }
        self.rotations.unrotate_vector(&mut dv);
        for (a, &d) in cx.chol.gamma().iter().enumerate() {
            dv[d] = delta[a];
        }
        for (a, b) in start.iter_mut().zip(&dv) {
            *a += b;
        }
        *u = start;
        Ok(())
    }

    /// Condenses the constrained, rotated bulk onto the interface dofs.
    fn condense(&self) -> Result<Condensed, ElasticError> {
        let n = self.u.len();
        let mut kb = self.k_bulk.clone();
        self.rotations.rotate_matrix(&mut kb);
        let mut zero = vec![0.0; n];
        self.prepared.apply_scaled(&mut kb, &mut zero, 0.0);
        let m = self.interface_dofs.len();
        let mut chol = CondensedCholesky::analyse(
            kb.pattern().clone(),
            &self.interface_dofs,
            (m / 8).max(MAX_UPDATE_RANK),
        )?;
        chol.prepare(&kb)?;
        let fixed: Vec<bool> = chol
            .gamma()
            .iter()
            .map(|&d| self.dirichlet.contains(d))
            .collect();
        let (ptr, col, slot) = chol.gamma_entries();
        let v = kb.values();
        let mut bulk_gg = vec![0.0; slot.len()];
        for a in 0..m {
            for k in ptr[a]..ptr[a + 1] {
                let b = col[k];
                bulk_gg[k] = if (fixed[a] || fixed[b]) && a != b {
                    0.0
                } else {
                    v[slot[k]]
                };
            }
        }
        let mut scratch = kb;
        scratch.values_mut().fill(0.0);
        let coarse = if self.options.coarse_space {
            let faces: Vec<_> = self
                .model
                .interfaces
                .iter()
                .map(super::coarse::element_faces)
                .collect();
            CoarseSpace::hierarchy(
                &faces,
                self.model.mesh.nodes(),
                &chol,
                &bulk_gg,
                &fixed,
                self.options.coarse_levels,
            )
        } else {
            Vec::new()
        };
        Ok(Condensed {
            chol,
            bulk_gg,
            fixed,
            scratch,
            coarse,
        })
    }

    /// The interface forces on Γ at `uf` (a full vector whose Γ entries are
    /// current) and, if asked, the Γ × Γ tangent values (bulk + interface,
    /// constrained rows and columns zero but the bulk diagonal).
    fn gamma_force(
        &self,
        cx: &mut Condensed,
        uf: &[f64],
        states: &[PointStates],
        fc: &mut [f64],
        tangent: bool,
    ) -> Result<(Vec<f64>, Option<Vec<f64>>), ElasticError> {
        self.gamma_force_with(&self.laws, cx, uf, states, fc, tangent)
    }

    /// [`StaticSolver::gamma_force`] with the joint laws `laws`.
    fn gamma_force_with(
        &self,
        laws: &[Joint],
        cx: &mut Condensed,
        uf: &[f64],
        states: &[PointStates],
        fc: &mut [f64],
        tangent: bool,
    ) -> Result<(Vec<f64>, Option<Vec<f64>>), ElasticError> {
        let gamma = cx.chol.gamma();
        for &d in gamma {
            fc[d] = 0.0;
        }
        let gg = if tangent {
            let (ptr, col, slot) = cx.chol.gamma_entries();
            let values = cx.scratch.values_mut();
            for &k in slot {
                values[k] = 0.0;
            }
            self.add_interfaces_with(laws, uf, states, Some(&mut cx.scratch), fc)?;
            let values = cx.scratch.values();
            let mut gg = cx.bulk_gg.clone();
            for a in 0..gamma.len() {
                if cx.fixed[a] {
                    continue;
                }
                for k in ptr[a]..ptr[a + 1] {
                    if !cx.fixed[col[k]] {
                        gg[k] += values[slot[k]];
                    }
                }
            }
            Some(gg)
        } else {
            self.add_interfaces_with(laws, uf, states, None, fc)?;
            None
        };
        let f: Vec<f64> = gamma.iter().map(|&d| fc[d]).collect();
        Ok((f, gg))
    }

    /// The pass on Γ (see the module notes).
    fn condensed_pass(
        &mut self,
        cx: &mut Condensed,
        f_ext: &[f64],
        committed: &[PointStates],
        u: Vec<f64>,
        chain: Option<Chain>,
        pass: usize,
    ) -> Result<Outcome, ElasticError> {
        // the first pass of an increment may start with the coarse space
        let first = chain.is_none();
        let chain = match chain {
            Some(c) => c,
            None => self.chain_start(cx, f_ext, committed, u)?,
        };
        let Chain {
            start: u,
            rb0,
            mut delta,
            mut s_delta,
            floor_i2,
            f_int_i2,
            interior_norm2,
        } = chain;
        let opts = self.options;
        let n = u.len();
        let gamma: Vec<usize> = cx.chol.gamma().to_vec();
        let m = gamma.len();
        let mut t = PassTracker::new(norm(f_ext), pass).with_forcing(self.pass_forcing);
        // The coupled Mohr–Coulomb law (the slip limit follows the current
        // pressure): its tangent is not symmetric where points slip, and
        // those steps are solved by GMRES preconditioned with the frozen
        // limits' tangent at the same statuses (see `gmres`), the
        // residual line search of the full pass's coupled steps.
        let coupled = opts.friction_bound == FrictionBound::Coupled && self.has_friction();
        let frozen_laws: Vec<Joint> = if coupled {
            self.laws
                .iter()
                .map(|j| j.with_friction_bound(FrictionBound::Frozen))
                .collect()
        } else {
            Vec::new()
        };
        let mut in_gamma = vec![false; n];
        for &d in &gamma {
            in_gamma[d] = true;
        }
        let kb = &self.k_bulk;
        let (kp, ki, kv) = (kb.pattern().indptr(), kb.pattern().indices(), kb.values());
        let row_abs = |i: usize| -> f64 {
            (kp[i]..kp[i + 1])
                .filter(|&q| !in_gamma[ki[q]])
                .map(|q| (kv[q] * u[ki[q]]).abs())
                .sum::<f64>()
        };
        let gi_abs: Vec<f64> = gamma.iter().map(|&d| row_abs(d)).collect();
        let (gg_ptr, gg_col, _) = cx.chol.gamma_entries();
        let (gg_ptr, gg_col) = (gg_ptr.to_vec(), gg_col.to_vec());
        let scale = |gg: &[f64], r_g: &[f64], uf: &[f64]| -> (f64, f64) {
            let (mut floor2, mut f2) = (floor_i2, f_int_i2);
            for (a, &d) in gamma.iter().enumerate() {
                let row: f64 = (gg_ptr[a]..gg_ptr[a + 1])
                    .map(|k| (gg[k] * uf[gamma[gg_col[k]]]).abs())
                    .sum();
                floor2 += (gi_abs[a] + row + f_ext[d].abs()).powi(2);
                f2 += (f_ext[d] - r_g[a]).powi(2);
            }
            (ROUND_OFF_FACTOR * f64::EPSILON * floor2.sqrt(), f2.sqrt())
        };
        let mut fc = vec![0.0; n];
        let per_element: Vec<usize> = committed.iter().map(|s| s.per_element()).collect();
        // coupled passes: what the last cut-short step predicts for the next
        // (see `front::CoupledNext`)
        let mut contact_next = CoupledNext::default();
        let mut uf = u.clone();
        for (a, &d) in gamma.iter().enumerate() {
            uf[d] = u[d] + delta[a];
        }
        let residual = |s_delta: &[f64], fcg: &[f64], fixed: &[bool]| -> Vec<f64> {
            (0..m)
                .map(|a| {
                    if fixed[a] {
                        0.0
                    } else {
                        rb0[a] - s_delta[a] - fcg[a]
                    }
                })
                .collect()
        };
        // (with frozen slip limits in place the smooth coarse field undoes
        // the stick zones: see `coarse`)
        if first && !coupled && self.without_slip_limits(committed) && !cx.coarse.is_empty() {
            let spaces = std::mem::take(&mut cx.coarse);
            // (a joint with slip limits takes the finest level alone: see
            // `SolverOptions::coarse_levels`)
            let levels = if self.has_slip_limits() {
                &spaces[spaces.len() - 1..]
            } else {
                &spaces[..]
            };
            // far from the new equilibrium: the coarse iteration first
            let (fcg, _) = self.gamma_force(cx, &uf, committed, &mut fc, false)?;
            let r_g = residual(&s_delta, &fcg, &cx.fixed);
            let (_, f_int_norm) = scale(&cx.bulk_gg, &r_g, &uf);
            let outcome: Result<usize, ElasticError> =
                if norm(&r_g) >= COARSE_GATE * t.reference.max(f_int_norm) {
                    levels.iter().try_fold(0, |steps, space| {
                        let ray = CoarseRay {
                            gamma: &gamma,
                            start: &u,
                            rb0: &rb0,
                        };
                        let n = self.coarse_iteration(
                            cx,
                            space,
                            committed,
                            ray,
                            (&mut delta, &mut s_delta),
                            &mut uf,
                        )?;
                        Ok(steps + n)
                    })
                } else {
                    Ok(0)
                };
            cx.coarse = spaces;
            let its = outcome?;
            self.coarse_in_increment += its;
            self.coarse_total += its;
        }
        let mut converged = false;
        while t.history.len() < opts.max_iterations {
            let (fcg, gg) = self.gamma_force(cx, &uf, committed, &mut fc, true)?;
            let mut gg = gg.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
            let r_g = residual(&s_delta, &fcg, &cx.fixed);
            let (floor_abs, f_int_norm) = scale(&gg, &r_g, &uf);
            t.reference = t.reference.max(f_int_norm);
            let rel = norm(&r_g) / t.reference;
            let floor = floor_abs / t.reference;
            let tolerance = opts.residual_tolerance.max(floor);
            // a corrected linear solve need not beat the convergence test
            let accept = LINEAR_SHARE * tolerance * t.reference;
            let status_t = self.statuses(&uf, committed);
            let obs = match t.observe(status_t, rel, (floor, false), tolerance, &opts) {
                Ok(o) => o,
                Err(e) => return Err(self.floating_or(e, &uf, committed)),
            };
            if obs.done {
                // as in the full pass: a body that every interface point
                // holding it has let go of is held by nothing
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
                    self.check_held_at(&uf, committed)?;
                    self.held_statuses = Some(obs.status);
                }
                converged = true;
                break;
            }
            if let Some(damped) = t.damped_points() {
                let flagged = self.with_secant_slip(committed, damped);
                gg = self
                    .gamma_force(cx, &uf, &flagged, &mut fc, true)?
                    .1
                    .ok_or_else(|| FemError::Solver("tangent missing".into()))?;
            }
            // (as in the full pass, the predicted branches are tried on
            // symmetric tangents only)
            let symmetric = !coupled || obs.counts[2] == 0;
            // (a coupled step cut short where points open or close, stick
            // or reverse: see below)
            let trial = self.step_trial(
                &mut t,
                (&obs.status, &per_element),
                (symmetric, true),
                std::mem::take(&mut contact_next),
            );
            let ray = Ray {
                gamma: &gamma,
                uf: &uf,
                s_delta: &s_delta,
                rb0: &rb0,
                r: &r_g,
            };

            // A coupled step cut short where points open or close (the
            // residual line search stops a few points into a closing or
            // opening front, which then moves two points per step): the
            // next step tries those points closed or open, as the primal-
            // dual active set would (the forced branch's tangent, solved
            // by the dense LU of the Schur system, and the same line search)
            let counts = trial.counts();
            let tried = if trial.coupled {
                let next = &trial.next;
                let mut forced =
                    self.forced_branch(committed, (&next.open, &next.stick, &[]), None, &uf);
                self.force_closed(&mut forced, &next.close);
                let (fcp, gp) = self.gamma_force(cx, &uf, &forced, &mut fc, true)?;
                let gp = gp.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
                let mut du = residual(&s_delta, &fcp, &cx.fixed);
                cx.chol.solve_schur_lu(&gp, &mut du)?;
                let s_du = cx.chol.mul_schur(&cx.bulk_gg, &du);
                let step = self.gamma_line_search(cx, committed, &ray, (&du, &s_du), false)?;
                if step < 1.0 {
                    contact_next =
                        self.coupled_next(|a| ray.at(&du, a), step, committed, &obs.status);
                }
                let end = ray.at(&du, step);
                let at_end: Vec<PointStatus> =
                    self.statuses(&end, committed).iter().map(|s| s.0).collect();
                Some((du, s_du, step, at_end))
            } else if trial.frozen_empty() {
                None
            } else {
                // the Newton step of the branch where the predicted points
                // are open or slip (and the reversed ones stick, the
                // reopened ones are closed): its tangent and its residual
                let mut forced = self.forced_branch(
                    committed,
                    (&trial.predicted, &trial.sticks, &trial.slips),
                    t.damped_points(),
                    &uf,
                );
                self.force_closed(&mut forced, &trial.reopened);
                let (fcp, gp) = self.gamma_force(cx, &uf, &forced, &mut fc, true)?;
                let gp = gp.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
                let mut du = residual(&s_delta, &fcp, &cx.fixed);
                match cx.chol.solve_schur(&gp, &mut du, accept) {
                    Ok((_, sx)) if dot(&r_g, &du) > 0.0 => {
                        let s_du = Self::bulk_product(cx, &gp, &du, sx);
                        // kept with its exact line-search step, however
                        // short (see `StaticSolver::predicted_step`)
                        let step =
                            self.gamma_line_search(cx, committed, &ray, (&du, &s_du), true)?;
                        let end = ray.at(&du, step);
                        let at_end: Vec<PointStatus> =
                            self.statuses(&end, committed).iter().map(|s| s.0).collect();
                        Some((du, s_du, step, at_end))
                    }
                    _ => None,
                }
            };
            // (the reopened points tried closed: kept only if they close in a
            // full step, see `front::REOPENED_MIN_STEP`)
            let tried = tried.filter(|p| trial.reopened.is_empty() || p.2 >= REOPENED_MIN_STEP);
            let fronts = trial.fronts();
            let (du, s_du, step) = match tried {
                Some((du, s_du, step, at_end)) => {
                    t.kept_prediction(counts, &at_end);
                    (du, s_du, step)
                }
                None => {
                    if fronts > 0 && t.rejected_prediction(counts, opts.max_iterations) {
                        break;
                    }
                    if !symmetric {
                        // the frozen law with its limits at the current
                        // pressures: the coupled statuses, and the coupled
                        // tangent less its rank-one friction terms
                        let mut at_current = committed.to_vec();
                        self.update_outer(&uf, &mut at_current, (true, false));
                        let pre = self
                            .gamma_force_with(&frozen_laws, cx, &uf, &at_current, &mut fc, true)?
                            .1
                            .ok_or_else(|| FemError::Solver("tangent missing".into()))?;
                        let chol = &mut cx.chol;
                        let solved = {
                            let chol = std::cell::RefCell::new(chol);
                            super::gmres::solve(
                                &r_g,
                                accept,
                                |v| Ok(chol.borrow().mul_schur(&gg, v)),
                                |v| {
                                    chol.borrow_mut().solve_schur(&pre, v, 0.0)?;
                                    Ok(())
                                },
                            )
                        };
                        let du = match solved {
                            Ok(Some(du)) => du,
                            Err(ElasticError::Fem(FemError::NotPositiveDefinite { .. })) => {
                                return Ok(Outcome::FullPass);
                            }
                            Err(e) => return Err(e),
                            // GMRES did not converge (the frozen tangent
                            // at the current statuses is a poor
                            // preconditioner after many status changes):
                            // the dense LU of the coupled Schur system
                            Ok(None) => {
                                let mut du = r_g.clone();
                                cx.chol.solve_schur_lu(&gg, &mut du)?;
                                du
                            }
                        };
                        let s_du = cx.chol.mul_schur(&cx.bulk_gg, &du);
                        let step =
                            self.gamma_line_search(cx, committed, &ray, (&du, &s_du), false)?;
                        if step < 1.0 {
                            contact_next =
                                self.coupled_next(|a| ray.at(&du, a), step, committed, &obs.status);
                        }
                        (du, s_du, step)
                    } else {
                        let mut du = r_g.clone();
                        let sx = match cx.chol.solve_schur(&gg, &mut du, accept) {
                            Ok((_, sx)) => sx,
                            Err(FemError::NotPositiveDefinite { .. }) => {
                                return Ok(Outcome::FullPass);
                            }
                            Err(e) => return Err(e.into()),
                        };
                        let s_du = Self::bulk_product(cx, &gg, &du, sx);
                        let step =
                            self.gamma_line_search(cx, committed, &ray, (&du, &s_du), true)?;
                        (du, s_du, step)
                    }
                }
            };
            if symmetric && opts.front_prediction && step < 1.0 && t.predicts_from_full_steps() {
                let full = ray.at(&du, 1.0);
                t.short_step(&obs.status, &self.statuses(&full, committed));
            }
            for a in 0..m {
                delta[a] += step * du[a];
                s_delta[a] += step * s_du[a];
                uf[gamma[a]] = u[gamma[a]] + delta[a];
            }
            let gamma_norm2: f64 = gamma.iter().map(|&d| uf[d] * uf[d]).sum();
            let unorm = (interior_norm2 + gamma_norm2).sqrt().max(f64::MIN_POSITIVE);
            if let Err(e) = t.stepped(step, step * norm(&du) / unorm) {
                return Err(self.floating_or(e, &uf, committed));
            }
            t.check_drift()?;
        }
        if !converged {
            let e = super::tracker::failure(
                format!("no convergence in {} iterations", opts.max_iterations),
                t.history,
            );
            return Err(self.floating_or(e, &uf, committed));
        }
        // the interior follows the interface (Δu_I = −A_II⁻¹ A_IΓ δ): it is
        // recovered when the increment ends (`settle_interior`); the next
        // pass goes on from here
        self.pending = Some(Pending {
            uf: uf.clone(),
            f_ext: f_ext.to_vec(),
            chain: Chain {
                start: u,
                rb0,
                delta,
                s_delta,
                floor_i2,
                f_int_i2,
                interior_norm2,
            },
        });
        Ok(Outcome::Done(uf, t.history))
    }

    /// The start of a chain of condensed passes from `u`: the interior put
    /// in equilibrium with the interface dofs (one solve with A_II, skipped
    /// when its residual is already below what the linear solves may
    /// leave), the bulk residual on Γ there, and the interior's parts of
    /// the force scale and of the round-off floor. The force scale and the
    /// floor are those of the full pass, ‖f_int‖ and
    /// ε ‖ |K_t| |u| + |f_ext| ‖: the rows of I at the start of the chain
    /// (their internal forces equal the external ones while the interior
    /// follows the interface), the rows of Γ at every iterate (|K_ΓI| |u_I|
    /// from the start). The rows of I and the columns of I in the rows of
    /// Γ are the bulk's alone.
    fn chain_start(
        &mut self,
        cx: &mut Condensed,
        f_ext: &[f64],
        committed: &[PointStates],
        mut u: Vec<f64>,
    ) -> Result<Chain, ElasticError> {
        let opts = self.options;
        let n = u.len();
        let (_, f_int) = self.tangent_and_force(&u, committed, false)?;
        let r = self.residual(f_ext, &f_int);
        let mut d_i: Vec<f64> = cx.chol.interior().iter().map(|&d| r[d]).collect();
        let reference0 = norm(f_ext).max(norm(&f_int)).max(f64::MIN_POSITIVE);
        if norm(&d_i) > LINEAR_SHARE * opts.residual_tolerance * reference0 {
            cx.chol.solve_interior(&mut d_i)?;
        } else {
            d_i.fill(0.0);
        }
        let coupling = cx.chol.mul_gamma_interior(&d_i);
        let mut dv = vec![0.0; n];
        for (&d, &x) in cx.chol.interior().iter().zip(&d_i) {
            dv[d] = x;
        }
        self.rotations.unrotate_vector(&mut dv);
        for (a, b) in u.iter_mut().zip(&dv) {
            *a += b;
        }
        let mut f_int = f_int;
        if d_i.iter().any(|&x| x != 0.0) {
            let mut kdv = vec![0.0; n];
            self.k_bulk.mul_vec(&dv, &mut kdv);
            for (a, b) in f_int.iter_mut().zip(&kdv) {
                *a += b;
            }
        }
        let kb = &self.k_bulk;
        let (kp, ki, kv) = (kb.pattern().indptr(), kb.pattern().indices(), kb.values());
        let (mut floor_i2, mut f_int_i2) = (0.0, 0.0);
        for &i in cx.chol.interior() {
            let row: f64 = (kp[i]..kp[i + 1]).map(|q| (kv[q] * u[ki[q]]).abs()).sum();
            floor_i2 += (row + f_ext[i].abs()).powi(2);
            f_int_i2 += f_int[i] * f_int[i];
        }
        let gamma = cx.chol.gamma().to_vec();
        let mut fc = vec![0.0; n];
        let (fc0, _) = self.gamma_force(cx, &u, committed, &mut fc, false)?;
        // bulk residual on Γ at the start: r_Γ − A_ΓI d_I + f_c
        let rb0: Vec<f64> = (0..gamma.len())
            .map(|a| {
                if cx.fixed[a] {
                    0.0
                } else {
                    r[gamma[a]] - coupling[a] + fc0[a]
                }
            })
            .collect();
        let interior_norm2: f64 = cx.chol.interior().iter().map(|&d| u[d] * u[d]).sum();
        Ok(Chain {
            start: u,
            rb0,
            delta: vec![0.0; gamma.len()],
            s_delta: vec![0.0; gamma.len()],
            floor_i2,
            f_int_i2,
            interior_norm2,
        })
    }

    /// [`StaticSolver::check_held`] on the full tangent at `uf` (a full
    /// vector whose Γ entries are current; the tangent depends on them
    /// alone, the bulk being linear). Made only where the condensed pass
    /// cannot see it: the Schur complement carries a small shift that keeps
    /// it definite for a body held by the interface alone, so a body that
    /// every point lets go of drifts instead of failing the solve.
    fn check_held_at(&self, uf: &[f64], committed: &[PointStates]) -> Result<(), ElasticError> {
        // (the frozen limits' tangent: the same as the pass's with frozen
        // limits; with the coupled law, whose slip tangent is not
        // symmetric, the one with the same normal stiffness)
        self.check_held_or_sliding(self.frozen_tangent(uf, committed)?, uf, committed)
    }

    /// A pass that failed (status ping-pong, stagnation, no convergence,
    /// a singular step) at `uf`: if a body is held by nothing there, that
    /// is the error to report (the level-4 vessel under a vacuum ended in a
    /// ping-pong of a drifting layer); otherwise `e`.
    pub(super) fn floating_or(
        &self,
        e: ElasticError,
        uf: &[f64],
        committed: &[PointStates],
    ) -> ElasticError {
        match self.check_held_at(uf, committed) {
            Err(f @ ElasticError::Floating { .. }) => f,
            _ => e,
        }
    }

    /// The coarse iteration before the first pass of an increment (see
    /// `coarse`): Newton steps in the coarse space, δ ← δ + α P dc with
    /// Pᵀ (S + K_c) P dc = Pᵀ r and the pass's exact energy line search,
    /// until ‖Pᵀ r‖ has fallen by [`COARSE_TOLERANCE`], a step changes no
    /// status, or [`COARSE_MAX_ITERATIONS`] steps; `delta`, `s_delta` (its
    /// bulk product S δ) and `uf` move along. Returns the steps taken.
    fn coarse_iteration(
        &self,
        cx: &mut Condensed,
        space: &CoarseSpace,
        committed: &[PointStates],
        ray: CoarseRay<'_>,
        (delta, s_delta): (&mut [f64], &mut [f64]),
        uf: &mut [f64],
    ) -> Result<usize, ElasticError> {
        let CoarseRay { gamma, start, rb0 } = ray;
        let m = gamma.len();
        let mut fc = vec![0.0; uf.len()];
        let mut first_norm = None;
        let mut before: Option<Vec<PointStatus>> = None;
        let mut steps = 0;
        while steps < COARSE_MAX_ITERATIONS {
            let (fcg, gg) = self.gamma_force(cx, uf, committed, &mut fc, true)?;
            let gg = gg.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
            let r: Vec<f64> = (0..m)
                .map(|a| {
                    if cx.fixed[a] {
                        0.0
                    } else {
                        rb0[a] - s_delta[a] - fcg[a]
                    }
                })
                .collect();
            let rc = space.restrict(&r);
            let rn = norm(&rc);
            let r0 = *first_norm.get_or_insert(rn);
            let status: Vec<PointStatus> = self
                .statuses(uf, committed)
                .into_iter()
                .map(|s| s.0)
                .collect();
            if rn <= COARSE_TOLERANCE * r0 || before.as_ref() == Some(&status) {
                break;
            }
            before = Some(status);
            let (ptr, col, _) = cx.chol.gamma_entries();
            let Some(dc) = space.solve(ptr, col, &gg, rc) else {
                // no coarse stiffness holds a body: the fine pass sees why
                break;
            };
            let du = space.prolong(&dc);
            if dot(&r, &du) <= 0.0 {
                break;
            }
            let s_du = space.bulk_product(&dc);
            let line = Ray {
                gamma,
                uf,
                s_delta,
                rb0,
                r: &r,
            };
            let step = self.gamma_line_search(cx, committed, &line, (&du, &s_du), true)?;
            if step == 0.0 {
                break;
            }
            for a in 0..m {
                delta[a] += step * du[a];
                s_delta[a] += step * s_du[a];
                uf[gamma[a]] = start[gamma[a]] + delta[a];
            }
            steps += 1;
        }
        Ok(steps)
    }

    /// The step along `du` (on Γ): the bulk residual along the ray is
    /// `r_b − S δ − α S du`, with S the bulk's Schur complement and `s_du`
    /// = S du. With a symmetric tangent, the exact energy line search;
    /// for the coupled law's non-symmetric steps, backtracking on the
    /// residual (as the full pass's
    /// [`StaticSolver::residual_line_search`]).
    fn gamma_line_search(
        &self,
        cx: &Condensed,
        committed: &[PointStates],
        ray: &Ray<'_>,
        (du, s_du): (&[f64], &[f64]),
        symmetric: bool,
    ) -> Result<f64, ElasticError> {
        let mut along = RayResidual::new(ray);
        if symmetric {
            root_along_ray(-dot(ray.r, du), |alpha| {
                let r = along.at(self, cx, committed, (du, s_du), alpha)?;
                Ok(-dot(&r, du))
            })
        } else {
            backtrack(norm(ray.r), |step| {
                Ok(norm(&along.at(self, cx, committed, (du, s_du), step)?))
            })
        }
    }

    /// The bulk part S_b du of a Schur product: `sx` = (S_b + K_c) du less
    /// the interface tangent K_c = `gg` − `bulk_gg` (sparse).
    fn bulk_product(cx: &Condensed, gg: &[f64], du: &[f64], mut sx: Vec<f64>) -> Vec<f64> {
        let (ptr, col, _) = cx.chol.gamma_entries();
        for (a, y) in sx.iter_mut().enumerate() {
            for k in ptr[a]..ptr[a + 1] {
                let d = gg[k] - cx.bulk_gg[k];
                if d != 0.0 {
                    *y -= d * du[col[k]];
                }
            }
        }
        sx
    }
}

/// What the coarse iteration needs of a chain: Γ, the chain's start and
/// the bulk residual on Γ there.
struct CoarseRay<'a> {
    gamma: &'a [usize],
    start: &'a [f64],
    rb0: &'a [f64],
}

/// The bulk residual on Γ along a [`Ray`] (zero at constrained
/// positions), with its scratch vectors.
struct RayResidual<'r, 'a> {
    ray: &'r Ray<'a>,
    trial: Vec<f64>,
    fc: Vec<f64>,
}

impl<'r, 'a> RayResidual<'r, 'a> {
    fn new(ray: &'r Ray<'a>) -> Self {
        RayResidual {
            ray,
            trial: ray.uf.to_vec(),
            fc: vec![0.0; ray.uf.len()],
        }
    }

    /// `r_b − S δ − α S du − f_c(u + α du)` on Γ.
    fn at(
        &mut self,
        solver: &StaticSolver<'_>,
        cx: &Condensed,
        committed: &[PointStates],
        (du, s_du): (&[f64], &[f64]),
        alpha: f64,
    ) -> Result<Vec<f64>, ElasticError> {
        let ray = self.ray;
        for (a, &d) in ray.gamma.iter().enumerate() {
            self.trial[d] = ray.uf[d] + alpha * du[a];
            self.fc[d] = 0.0;
        }
        solver.add_interfaces(&self.trial, committed, None, &mut self.fc)?;
        Ok((0..ray.gamma.len())
            .map(|a| {
                if cx.fixed[a] {
                    0.0
                } else {
                    ray.rb0[a] - ray.s_delta[a] - alpha * s_du[a] - self.fc[ray.gamma[a]]
                }
            })
            .collect())
    }
}

/// A Newton ray on Γ: the iterate (full vector with current Γ entries),
/// its bulk state and residual.
struct Ray<'a> {
    gamma: &'a [usize],
    uf: &'a [f64],
    s_delta: &'a [f64],
    rb0: &'a [f64],
    r: &'a [f64],
}

impl Ray<'_> {
    /// The full vector at step `alpha` along `du` (Γ entries moved).
    fn at(&self, du: &[f64], alpha: f64) -> Vec<f64> {
        let mut v = self.uf.to_vec();
        for (a, &d) in self.gamma.iter().enumerate() {
            v[d] += alpha * du[a];
        }
        v
    }
}

/// The two vectors hold the same bits (a vector a pass handed back, not one
/// that merely compares equal).
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}
