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

/// Kress weights R_k, k = 0..n−1.
pub fn kress_weights(n: usize) -> Vec<f64> {
    let nf = n as f64;
    (0..n)
        .into_par_iter()
        .map(|k| {
            let mut s = 0.0;
            for m in 1..n / 2 {
                let ph = ((m * k) % n) as f64 / nf;
                s += (2.0 * PI * ph).cos() / m as f64;
            }
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            -s / nf - sign / (nf * nf)
        })
        .collect()
}

/// Assembled Nyström system (row-major (n+1)², right-hand side, J weights).
pub struct NystromSystem {
    /// row-major augmented matrix of order n + 1
    pub matrix: Vec<f64>,
    /// right-hand side (f, 0)
    pub rhs: Vec<f64>,
}

/// Assembles the augmented Nyström system on `nodes`.
pub fn assemble(nodes: &[BPoint], x0: [f64; 2]) -> NystromSystem {
    let n = nodes.len();
    let l = kernels::log_remainder(nodes);
    let r = kress_weights(n);
    let f = kernels::rhs(nodes, x0);
    let nn = n + 1;
    let mut a = vec![0.0; nn * nn];
    let inv = 1.0 / n as f64;
    a.par_chunks_mut(nn).enumerate().for_each(|(i, row)| {
        if i < n {
            for j in 0..n {
                let k = (i + n - j) % n;
                row[j] = -(r[k] + inv * l[i * n + j]) / (2.0 * PI);
            }
            row[n] = 1.0;
        } else {
            for v in row.iter_mut().take(n) {
                *v = inv;
            }
        }
    });
    let mut rhs = f;
    rhs.push(0.0);
    NystromSystem { matrix: a, rhs }
}

/// Solves for (μ_j, c).
pub fn solve(nodes: &[BPoint], x0: [f64; 2]) -> Result<(Vec<f64>, f64), SolveError> {
    let n = nodes.len();
    let sys = assemble(nodes, x0);
    let sol = dense_lu_solve(n + 1, &sys.matrix, &sys.rhs)?;
    Ok((sol[..n].to_vec(), sol[n]))
}
