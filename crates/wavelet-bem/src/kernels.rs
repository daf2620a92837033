//! Kernel samples on a grid of boundary nodes, shared by all solvers.
//!
//! With nodes t_a = (a + ½)/n (so t_a − t_b = (a − b)/n exactly):
//!
//! * `L(t_a, t_b) = ln|x(t_a) − x(t_b)| − ln|2 sin π(t_a − t_b)|`, with the
//!   diagonal limit `L(t, t) = ln(|x′(t)| / 2π)`;
//! * `f(t_a) = ∮ (g(y) − g(x_a)) ∂w/∂n_y ds_y`, g = |x − x₀|²/2, by the
//!   trapezoidal rule (the integrand is smooth and vanishes at y = x_a);
//! * `g2(t_a) = |x(t_a) − x₀|²` for the functional J.
//!
//! Rows are computed independently in parallel, so the result does not
//! depend on the number of threads.

use crate::grading::{BPoint, diff};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Blocked transpose of a row-major n×n matrix (parallel over output row
/// blocks; every entry is a copy, so the result is thread-count independent).
pub fn transpose<T: Copy + Default + Send + Sync>(m: &[T], n: usize) -> Vec<T> {
    const B: usize = 64;
    let mut out = vec![T::default(); n * n];
    out.par_chunks_mut(B * n)
        .enumerate()
        .for_each(|(kb, chunk)| {
            let k0 = kb * B;
            let rows = chunk.len() / n;
            for a0 in (0..n).step_by(B) {
                let a1 = (a0 + B).min(n);
                for dk in 0..rows {
                    let k = k0 + dk;
                    let dst = &mut chunk[dk * n..(dk + 1) * n];
                    for a in a0..a1 {
                        dst[a] = m[a * n + k];
                    }
                }
            }
        });
    out
}

/// Row-major n×n matrix of the smooth log remainder L at the nodes of one curve.
pub fn log_remainder(nodes: &[BPoint]) -> Vec<f64> {
    log_remainder_blocks(nodes, nodes.len())
}

/// Row-major N×N kernel matrix for K curves of `n` nodes each (N = K n,
/// curve after curve): within a curve the smooth log remainder L, between
/// two curves the full (smooth) kernel ln|x − y|.
///
/// The matrix is symmetric (swapping the nodes negates x − y exactly, so
/// both triangles hold the same bits): the upper triangle is computed, one
/// logarithm per pair, and copied to the lower one.
pub fn log_remainder_blocks(nodes: &[BPoint], n: usize) -> Vec<f64> {
    let big = nodes.len();
    let mut out = log_remainder_upper(nodes, n);
    mirror_upper(&mut out, big);
    out
}

/// The upper triangle (j ≥ i) of [`log_remainder_blocks`]; the entries
/// below the diagonal are 0.
pub fn log_remainder_upper(nodes: &[BPoint], n: usize) -> Vec<f64> {
    let big = nodes.len();
    let mut out = crate::linalg::dense_zeroed(big * big);
    let sines = log_sines(n);
    out.par_chunks_mut(big)
        .enumerate()
        .for_each(|(i, row)| log_remainder_upper_row(nodes, n, &sines, i, row));
    out
}

/// Copies the upper triangle of the row-major n × n matrix `m` to its lower
/// triangle, tile by tile (no allocation; a copy is exact).
fn mirror_upper(m: &mut [f64], n: usize) {
    const B: usize = 64;
    for i0 in (0..n).step_by(B) {
        for j0 in (0..=i0).step_by(B) {
            for i in i0..(i0 + B).min(n) {
                for j in j0..(j0 + B).min(i) {
                    m[i * n + j] = m[j * n + i];
                }
            }
        }
    }
}

/// Entries j ≥ i of row i of [`log_remainder_blocks`] (`row[..i]` is not
/// touched).
fn log_remainder_upper_row(nodes: &[BPoint], n: usize, sines: &[f64], i: usize, row: &mut [f64]) {
    let xi = &nodes[i];
    row[i] = (xi.speed() / (2.0 * PI)).max(f64::MIN_POSITIVE).ln();
    // the rest of i's curve: L = ln r − ln|2 sin π(t_i − t_j)|
    let end = (i / n + 1) * n;
    for j in i + 1..end {
        let d = diff(xi, &nodes[j]);
        let lg = 0.5 * (d[0] * d[0] + d[1] * d[1]).max(f64::MIN_POSITIVE).ln();
        row[j] = lg - sines[j - i];
    }
    // later curves: ln r
    for j in end..row.len() {
        let d = diff(xi, &nodes[j]);
        row[j] = 0.5 * (d[0] * d[0] + d[1] * d[1]).max(f64::MIN_POSITIVE).ln();
    }
}

/// ln|2 sin(πk/n)| for k = 0..n (the k = 0 entry is −∞ and never used).
pub fn log_sines(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| (2.0 * (PI * k as f64 / n as f64).sin()).abs().ln())
        .collect()
}

/// Right-hand side f(t_a) = ((½I + K) g)(x_a) in subtracted form, trapezoidal rule.
pub fn rhs(nodes: &[BPoint], x0: [f64; 2]) -> Vec<f64> {
    rhs_blocks(nodes, nodes.len(), x0)
}

/// [`rhs`] for K curves of `n` nodes each: the integral runs over every
/// curve of Γ (∮_Γ ∂w/∂n_y ds_y = −½ on Γ holds for the whole boundary of Ω).
pub fn rhs_blocks(nodes: &[BPoint], n: usize, x0: [f64; 2]) -> Vec<f64> {
    let h = 1.0 / n as f64;
    (0..nodes.len())
        .into_par_iter()
        .map(|i| {
            let xi = &nodes[i];
            let pi = xi.x();
            let mut acc = 0.0;
            for (j, yj) in nodes.iter().enumerate() {
                if j == i {
                    continue;
                }
                let d = diff(xi, yj); // x − y
                let py = yj.x();
                // g(y) − g(x) = ½ (y − x)·(y + x − 2x₀)
                let dg = -0.5
                    * (d[0] * (py[0] + pi[0] - 2.0 * x0[0]) + d[1] * (py[1] + pi[1] - 2.0 * x0[1]));
                // (x − y)·n_y |y′| = (x−y)₁ y′₂ − (x−y)₂ y′₁
                let num = d[0] * yj.d1[1] - d[1] * yj.d1[0];
                let r2 = d[0] * d[0] + d[1] * d[1];
                if r2 > 0.0 {
                    acc += dg * num / (2.0 * PI * r2);
                }
            }
            acc * h
        })
        .collect()
}

/// g2(t_a) = |x(t_a) − x₀|².
pub fn radius_sq(nodes: &[BPoint], x0: [f64; 2]) -> Vec<f64> {
    nodes
        .iter()
        .map(|p| {
            let x = p.x();
            (x[0] - x0[0]).powi(2) + (x[1] - x0[1]).powi(2)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` nodes t_a = (a + ½)/n on the circle of radius `r` about `c`.
    fn circle(n: usize, r: f64, c: [f64; 2]) -> Vec<BPoint> {
        (0..n)
            .map(|a| {
                let th = 2.0 * PI * (a as f64 + 0.5) / n as f64;
                let (s, co) = th.sin_cos();
                let w = 2.0 * PI * r;
                BPoint {
                    anchor: c,
                    offset: [r * co, r * s],
                    d1: [-w * s, w * co],
                    d2: [-2.0 * PI * w * co, -2.0 * PI * w * s],
                }
            })
            .collect()
    }

    #[test]
    fn the_symmetric_fill_equals_the_kernel_entry_by_entry() {
        let n = 16;
        let mut nodes = circle(n, 1.0, [0.0, 0.0]);
        nodes.extend(circle(n, 0.3, [0.1, -0.05]));
        let big = nodes.len();
        let l = log_remainder_blocks(&nodes, n);
        let sines = log_sines(n);
        for i in 0..big {
            for j in 0..big {
                let expected = if i == j {
                    (nodes[i].speed() / (2.0 * PI)).ln()
                } else {
                    let d = diff(&nodes[i], &nodes[j]);
                    let lg = 0.5 * (d[0] * d[0] + d[1] * d[1]).ln();
                    if i / n == j / n {
                        lg - sines[(i % n).abs_diff(j % n)]
                    } else {
                        lg
                    }
                };
                assert_eq!(
                    l[i * big + j].to_bits(),
                    expected.to_bits(),
                    "entry ({i}, {j})"
                );
            }
        }
    }
}
