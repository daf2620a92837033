//! Flexible GMRES for the coupled friction law's non-symmetric tangents.
//!
//! Why: in the coupled tail of the outer loop (see `increment`) the slip
//! limit of a point follows its current pressure, so a slipping point's
//! tangent has the non-symmetric rank-one term sign(τ) μ ∂p/∂Δu_n. The
//! frozen limits' tangent at the same statuses (the limits set to the
//! current pressures) is that tangent without those terms: symmetric, and
//! factorised already for the frozen passes (sparse or dense Cholesky with
//! low-rank corrections). Preconditioned by it, GMRES needs a few
//! iterations (6–10 on the vessel) where an LU factorisation of the whole
//! tangent would cost more than the pass.
//!
//! How: right preconditioning, the preconditioned directions kept (the
//! flexible variant: the corrected Cholesky solves stop at a residual,
//! so the preconditioner is not exactly one linear map), modified
//! Gram–Schmidt, Givens rotations, restarts. Every sum runs in a fixed
//! order, so the result does not depend on the thread count.

use crate::error::ElasticError;

use super::{dot, norm};

/// Restart length.
const RESTART: usize = 40;

/// Most iterations of one solve: a solve that needs more is reported as
/// not converged (the caller falls back on another method).
pub(super) const MAX_ITERATIONS: usize = 200;

/// Solves A x = b, with `apply` = A and `precondition` an approximate
/// inverse applied in place, until ‖b − A x‖ ≤ max(`accept`, 1e-12 ‖b‖).
/// Returns `None` if that is not reached within [`MAX_ITERATIONS`] (or a
/// whole restart cycle makes no progress).
pub(super) fn solve(
    b: &[f64],
    accept: f64,
    mut apply: impl FnMut(&[f64]) -> Result<Vec<f64>, ElasticError>,
    mut precondition: impl FnMut(&mut [f64]) -> Result<(), ElasticError>,
) -> Result<Option<Vec<f64>>, ElasticError> {
    let m = b.len();
    let target = accept.max(1e-12 * norm(b));
    let mut x = vec![0.0; m];
    let mut r = b.to_vec();
    let mut beta = norm(&r);
    let mut total = 0;
    while beta > target && total < MAX_ITERATIONS {
        let mut v: Vec<Vec<f64>> = vec![r.iter().map(|a| a / beta).collect()];
        let mut z: Vec<Vec<f64>> = Vec::with_capacity(RESTART);
        // Hessenberg columns (rotated), Givens rotations, rotated right-hand side
        let mut h: Vec<Vec<f64>> = Vec::with_capacity(RESTART);
        let mut rotations: Vec<(f64, f64)> = Vec::with_capacity(RESTART);
        let mut g = vec![0.0; RESTART + 1];
        g[0] = beta;
        let mut j = 0;
        while j < RESTART && total < MAX_ITERATIONS {
            let mut zj = v[j].clone();
            precondition(&mut zj)?;
            let mut w = apply(&zj)?;
            let mut col = vec![0.0; j + 2];
            for (i, vi) in v.iter().enumerate() {
                let hij = dot(&w, vi);
                col[i] = hij;
                for (a, b) in w.iter_mut().zip(vi) {
                    *a -= hij * b;
                }
            }
            let wn = norm(&w);
            col[j + 1] = wn;
            for (i, &(c, s)) in rotations.iter().enumerate() {
                let (a, b) = (col[i], col[i + 1]);
                col[i] = c * a + s * b;
                col[i + 1] = -s * a + c * b;
            }
            let d = col[j].hypot(col[j + 1]);
            let (c, s) = if d == 0.0 {
                (1.0, 0.0)
            } else {
                (col[j] / d, col[j + 1] / d)
            };
            col[j] = d;
            col[j + 1] = 0.0;
            rotations.push((c, s));
            g[j + 1] = -s * g[j];
            g[j] *= c;
            h.push(col);
            z.push(zj);
            j += 1;
            total += 1;
            if g[j].abs() <= target || wn == 0.0 {
                break;
            }
            v.push(w.iter().map(|a| a / wn).collect());
        }
        // H y = g (upper triangular), x += Z y
        let mut y = vec![0.0; j];
        for i in (0..j).rev() {
            let mut acc = g[i];
            for (l, yl) in y.iter().enumerate().skip(i + 1) {
                acc -= h[l][i] * yl;
            }
            y[i] = if h[i][i] != 0.0 { acc / h[i][i] } else { 0.0 };
        }
        for (zi, yi) in z.iter().zip(&y) {
            for (a, b) in x.iter_mut().zip(zi) {
                *a += yi * b;
            }
        }
        let ax = apply(&x)?;
        r = b.iter().zip(&ax).map(|(p, q)| p - q).collect();
        let new_beta = norm(&r);
        if new_beta.is_nan() || new_beta >= beta {
            // no progress over a whole cycle (or a product that overflowed)
            return Ok(None);
        }
        beta = new_beta;
    }
    Ok((beta <= target).then_some(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-symmetric 3 × 3 system, preconditioned by the inverse of its
    /// diagonal: the solution to the tolerance, against the exact one.
    #[test]
    fn solves_a_non_symmetric_system() {
        let a = [[4.0, 1.0, 0.0], [2.0, 5.0, 1.5], [0.0, -3.0, 6.0]];
        let x_exact = [1.0, -2.0, 0.5];
        let b: Vec<f64> = a
            .iter()
            .map(|row| row.iter().zip(&x_exact).map(|(p, q)| p * q).sum())
            .collect();
        let mut applied = 0;
        let x = solve(
            &b,
            0.0,
            |v| {
                applied += 1;
                Ok(a.iter()
                    .map(|row| row.iter().zip(v).map(|(p, q)| p * q).sum())
                    .collect())
            },
            |v| {
                for (vi, row) in v.iter_mut().zip(&a) {
                    *vi /= row[0].max(row[1]).max(row[2]);
                }
                Ok(())
            },
        )
        .unwrap()
        .expect("converged");
        for (p, q) in x.iter().zip(&x_exact) {
            assert!((p - q).abs() < 1e-10, "{x:?}");
        }
        // three Krylov directions span the space, plus the final product
        assert!(applied <= 4, "{applied} products");
    }

    /// An operator that maps everything to zero: no progress, `None`.
    #[test]
    fn reports_a_solve_that_does_not_converge() {
        let b = [1.0, 2.0];
        let x = solve(&b, 0.0, |v| Ok(vec![0.0; v.len()]), |_| Ok(())).unwrap();
        assert!(x.is_none());
    }
}
