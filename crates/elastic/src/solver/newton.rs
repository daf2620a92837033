//! One Newton pass at fixed multipliers and friction limits.

use tecon_contact::FrictionBound;
use tecon_fem::FemError;

use crate::error::{ElasticError, IterationRecord};

use super::*;

impl StaticSolver<'_> {
    pub(super) fn newton(
        &mut self,
        f_ext: &[f64],
        loads: &Loads,
        committed: &[PointStates],
        mut u: Vec<f64>,
    ) -> Result<(Vec<f64>, Vec<IterationRecord>), ElasticError> {
        // Prescribed values at this load level (global frame; rotated dofs are 0).
        for (d, v) in self.dirichlet.iter() {
            u[d] = v * loads.displacement;
        }
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
        for it in 0..opts.max_iterations {
            let (kt, f_int) = self.tangent_and_force(&u, committed, true)?;
            let mut kt = kt.ok_or_else(|| FemError::Solver("tangent missing".into()))?;
            let status = self.statuses(&u, committed);
            let status_t = status.clone();
            let r = self.residual(f_ext, &f_int);
            reference = reference.max(norm(&f_int));
            let rel = norm(&r) / reference;
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
            }
            let counts = count(&status);
            let last_correction = history.last().map_or(f64::INFINITY, |h| h.correction);
            // After a full step with no status change the linearisation was
            // exact (the problem is piecewise linear), so the residual alone
            // measures the error; otherwise the correction must be small too.
            let full_step = history.last().is_some_and(|h| h.step == 1.0);
            let converged = it > 0
                && rel <= opts.residual_tolerance
                && changed == 0
                && (last_correction <= opts.correction_tolerance
                    || rel <= opts.residual_tolerance * 1e-3
                    || full_step);
            history.push(IterationRecord {
                iteration: it,
                residual: rel,
                correction: 0.0,
                step: 0.0,
                status: counts,
                changed,
            });
            if converged || (rel == 0.0 && changed == 0) {
                return Ok((u, history));
            }
            if ping_pong > opts.max_ping_pong {
                return Err(ElasticError::NotConverged {
                    fraction: 0.0,
                    increment: 0.0,
                    reason: format!("contact status ping-pong ({ping_pong} repeats)"),
                    history,
                });
            }
            // Tangent in the rotated frame, homogeneous constraints on the correction.
            self.rotations.rotate_matrix(&mut kt);
            let mut du = r.clone();
            self.prepared.apply_scaled(&mut kt, &mut du, 0.0);
            if !self.modes_checked {
                self.check_modes(&kt)?;
                if !self.modes_checked {
                    // a minimal constraint was added: start over
                    return self.newton(f_ext, loads, committed, u);
                }
            }
            let symmetric = counts[2] == 0 || opts.friction_bound == FrictionBound::Frozen;
            self.solve(&kt, &mut du, symmetric)?;
            let du_rotated = du.clone();
            self.rotations.unrotate_vector(&mut du);
            let step = if symmetric {
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
                return Err(ElasticError::NotConverged {
                    fraction: 0.0,
                    increment: 0.0,
                    reason: "the line search keeps cutting the Newton step (stagnation)".into(),
                    history,
                });
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
        Err(ElasticError::NotConverged {
            fraction: 0.0,
            increment: 0.0,
            reason: format!("no convergence in {} iterations", opts.max_iterations),
            history,
        })
    }
}
