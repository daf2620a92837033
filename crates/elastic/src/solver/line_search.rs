//! Line searches along a Newton direction.

use crate::error::ElasticError;

use super::*;

impl StaticSolver<'_> {
    /// Step along `du` to the minimum of the (convex) incremental energy:
    /// the root of `g(α) = −R(u + α du)·du`, which increases with `α`. The
    /// full step is taken when it does not overshoot; otherwise a few
    /// Illinois (false-position) steps find the root. `du_rotated` is `du`
    /// in the frame of the residual `r`; `ku` = K u, the bulk force at `u`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn energy_line_search(
        &self,
        f_ext: &[f64],
        committed: &[PointStates],
        (u, ku): (&[f64], &[f64]),
        (du, kdu): (&[f64], &[f64]),
        du_rotated: &[f64],
        r: &[f64],
    ) -> Result<f64, ElasticError> {
        // the bulk is linear: K (u + α du) = K u + α K du
        let g = |alpha: f64| -> Result<f64, ElasticError> {
            let trial: Vec<f64> = u.iter().zip(du).map(|(a, b)| a + alpha * b).collect();
            let mut fi: Vec<f64> = ku.iter().zip(kdu).map(|(a, b)| a + alpha * b).collect();
            self.add_interfaces(&trial, committed, None, &mut fi)?;
            let rt = self.residual(f_ext, &fi);
            Ok(-dot(&rt, du_rotated))
        };
        let g0 = -dot(r, du_rotated);
        root_along_ray(g0, g)
    }

    /// Backtracking on ‖R‖ (for the non-symmetric coupled friction law):
    /// halve the step until the residual falls, keeping the best of five.
    pub(super) fn residual_line_search(
        &self,
        f_ext: &[f64],
        committed: &[PointStates],
        u: &[f64],
        du: &[f64],
        r: &[f64],
    ) -> Result<f64, ElasticError> {
        backtrack(norm(r), |step| {
            let trial: Vec<f64> = u.iter().zip(du).map(|(a, b)| a + step * b).collect();
            let (_, fi) = self.tangent_and_force(&trial, committed, false)?;
            Ok(norm(&self.residual(f_ext, &fi)))
        })
    }
}

/// Backtracking on ‖R‖ from the full step: halve the step until the
/// residual norm `residual(α)` falls below (1 − 1e-4 α) `r0`, keeping the
/// best of five.
pub(super) fn backtrack(
    r0: f64,
    mut residual: impl FnMut(f64) -> Result<f64, ElasticError>,
) -> Result<f64, ElasticError> {
    let mut step = 1.0;
    let mut best = (f64::INFINITY, 1.0);
    for _ in 0..5 {
        let rt = residual(step)?;
        if rt < best.0 {
            best = (rt, step);
        }
        if rt <= (1.0 - 1e-4 * step) * r0 || r0 == 0.0 {
            break;
        }
        step *= 0.5;
    }
    Ok(if best.0.is_finite() { best.1 } else { 1.0 })
}

/// The step along a Newton ray to the root of the directional derivative
/// `g(α) = −R(u + α du)·du` of a convex energy, which increases with `α`;
/// `g0 = g(0)`. The full step is taken when it does not overshoot;
/// otherwise a few Illinois (false-position) steps find the root.
pub(super) fn root_along_ray(
    g0: f64,
    mut g: impl FnMut(f64) -> Result<f64, ElasticError>,
) -> Result<f64, ElasticError> {
    if g0.is_nan() || g0 >= 0.0 {
        // not a descent direction (round-off at convergence): full step
        return Ok(1.0);
    }
    let g1 = g(1.0)?;
    if g1.abs() <= 0.05 * g0.abs() {
        return Ok(1.0);
    }
    let (mut a, mut ga, mut b, mut gb) = (0.0, g0, 1.0, g1);
    if g1 < 0.0 {
        // The minimum lies beyond the full step: statuses changed along
        // the ray made the energy softer than the linearisation. Go on
        // along the ray (doubling) until the slope turns.
        let mut x = 1.0;
        let mut gx = g1;
        while gx < 0.0 && x < MAX_STEP {
            (a, ga) = (x, gx);
            x *= 2.0;
            gx = g(x)?;
        }
        if gx < 0.0 {
            return Ok(a);
        }
        if gx.abs() <= 0.05 * g0.abs() {
            return Ok(x);
        }
        (b, gb) = (x, gx);
    }
    // Root of g in (0, 1), g(0) < 0 < g(1), kept bracketed: false
    // position, with a bisection whenever one end has stayed put twice
    // (g is piecewise linear with kinks of very different slopes, where
    // false position alone creeps). If the bracket gets tight first, the
    // right end is taken: just past a kink, so the point that changed
    // branch there starts the next iteration on its new branch.
    let mut stuck = 0i32;
    for _ in 0..60 {
        let fp = a - ga * (b - a) / (gb - ga);
        let x = if stuck.abs() >= 2 || !(fp > a && fp < b) {
            stuck = 0;
            0.5 * (a + b)
        } else {
            fp
        };
        let gx = g(x)?;
        if gx.abs() <= 0.05 * g0.abs() {
            return Ok(x);
        }
        if gx < 0.0 {
            (a, ga) = (x, gx);
            stuck = if stuck < 0 { stuck - 1 } else { -1 };
        } else {
            (b, gb) = (x, gx);
            stuck = if stuck > 0 { stuck + 1 } else { 1 };
        }
        if b - a <= 1e-3 * b {
            break;
        }
    }
    Ok(b)
}

/// Largest step along a Newton direction the energy line search looks at.
const MAX_STEP: f64 = 64.0;
