//! Kress Nyström method with logarithmic product weights (the reference solver).
//!
//! On the half-shifted nodes t_j = (j + ½)/n the augmented system reads
//!
//! ```text
//! −(1/2π) Σ_j [R_{i−j} + L(t_i, t_j)/n] μ_j + c = f(t_i),     (1/n) Σ_j μ_j = 0,
//! ```
//!
//! with R_k = −(1/n) Σ_{m=1}^{n/2−1} cos(2πmk/n)/m − (−1)^k/n² the exact
//! integrals of ln|2 sin π(t_i − s)| against the trigonometric interpolant.

use crate::error::SolveError;
use crate::grading::BPoint;
use crate::kernels;
use crate::linalg::dense_lu_solve;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Kress weights R_k, k = 0..n−1, by one FFT of the coefficients 1/m
/// (symmetric in m ↦ n − m, so the transform is 2 Σ cos(2πmk/n)/m).
pub fn kress_weights(n: usize) -> Vec<f64> {
    use rustfft::FftPlanner;
    use rustfft::num_complex::Complex64;
    let nf = n as f64;
    let mut buf = vec![Complex64::new(0.0, 0.0); n];
    for m in 1..n / 2 {
        buf[m] = Complex64::new(1.0 / m as f64, 0.0);
        buf[n - m] = buf[m];
    }
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);
    buf.iter()
        .enumerate()
        .map(|(k, z)| {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            -0.5 * z.re / nf - sign / (nf * nf)
        })
        .collect()
}

/// Assembled Nyström system (row-major, right-hand side).
pub struct NystromSystem {
    /// row-major augmented matrix of order N + K (N = K n nodes, K curves)
    pub matrix: Vec<f64>,
    /// right-hand side (f, 0, …, 0)
    pub rhs: Vec<f64>,
}

/// Assembles the augmented Nyström system on the nodes of one curve.
pub fn assemble(nodes: &[BPoint], x0: [f64; 2]) -> NystromSystem {
    assemble_blocks(nodes, nodes.len(), x0)
}

/// Assembles the augmented system for K curves of `n` nodes each: one
/// multiplier c_k per curve (the constant the single layer takes on curve k)
/// and one constraint ∮_{Γ_k} q_v ds = 0 per curve (single-valued warping).
pub fn assemble_blocks(nodes: &[BPoint], n: usize, x0: [f64; 2]) -> NystromSystem {
    let big = nodes.len();
    let kc = big / n;
    let (l, f) = kernels::log_remainder_blocks(nodes, n, x0);
    let r = kress_weights(n);
    let nn = big + kc;
    let mut a = vec![0.0; nn * nn];
    let inv = 1.0 / n as f64;
    a.par_chunks_mut(nn).enumerate().for_each(|(i, row)| {
        if i < big {
            for j in 0..big {
                let w = if i / n == j / n {
                    r[(i + n - j) % n]
                } else {
                    0.0
                };
                row[j] = -(w + inv * l[i * big + j]) / (2.0 * PI);
            }
            row[big + i / n] = 1.0;
        } else {
            let k = i - big;
            for v in row.iter_mut().skip(k * n).take(n) {
                *v = inv;
            }
        }
    });
    let mut rhs = f;
    rhs.resize(nn, 0.0);
    NystromSystem { matrix: a, rhs }
}

/// Solves for (μ_j, c) on one curve.
pub fn solve(nodes: &[BPoint], x0: [f64; 2]) -> Result<(Vec<f64>, f64), SolveError> {
    let (mu, c) = solve_blocks(nodes, nodes.len(), x0)?;
    Ok((mu, c[0]))
}

/// Solves for (μ_j, c_k) on K curves of `n` nodes each.
pub fn solve_blocks(
    nodes: &[BPoint],
    n: usize,
    x0: [f64; 2],
) -> Result<(Vec<f64>, Vec<f64>), SolveError> {
    let big = nodes.len();
    let sys = assemble_blocks(nodes, n, x0);
    let nn = sys.rhs.len();
    let sol = dense_lu_solve(nn, &sys.matrix, &sys.rhs)?;
    Ok((sol[..big].to_vec(), sol[big..].to_vec()))
}
