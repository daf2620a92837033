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
//! Rows are computed in parallel, in fixed blocks whose right-hand-side
//! sums are added in block order, so the result does not depend on the
//! number of threads.

use crate::geometry::V2;
use crate::grading::BPoint;
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

/// Row-major N×N kernel matrix for K curves of `n` nodes each (N = K n,
/// curve after curve), and the right-hand side f at the nodes (the
/// trapezoidal rule over every curve, see [`rhs_blocks`]): within a curve
/// the smooth log remainder L, between two curves the full (smooth) kernel
/// ln|x − y|.
///
/// The matrix is symmetric (swapping the nodes negates x − y exactly, so
/// both triangles hold the same bits): the upper triangle is computed, one
/// logarithm per pair, and copied to the lower one.
pub fn log_remainder_blocks(nodes: &[BPoint], n: usize, x0: V2) -> (Vec<f64>, Vec<f64>) {
    let big = nodes.len();
    let (mut out, f) = log_remainder_upper(nodes, n, x0);
    mirror_upper(&mut out, big);
    (out, f)
}

/// The upper triangle (j ≥ i) of [`log_remainder_blocks`] (the entries
/// below the diagonal are 0) and the right-hand side f, from one pass over
/// the pairs i < j.
pub fn log_remainder_upper(nodes: &[BPoint], n: usize, x0: V2) -> (Vec<f64>, Vec<f64>) {
    let big = nodes.len();
    let mut out = crate::linalg::dense_zeroed(big * big);
    let sines = log_sines(n);
    let arrays = NodeArrays::new(nodes);
    let block = pair_block(big);
    let parts: Vec<Vec<f64>> = out
        .par_chunks_mut(block * big)
        .enumerate()
        .map(|(b, block_rows)| {
            let mut f = vec![0.0; big];
            let rows = UpperRows {
                a: &arrays,
                n,
                sines: &sines,
                x0,
                first: b * block,
            };
            #[cfg(target_arch = "x86_64")]
            if crate::logarithm::has_avx2() {
                // SAFETY: the CPU has AVX2, the only feature it is compiled for
                unsafe { rows.fill_avx2(block_rows, &mut f) };
                return f;
            }
            rows.fill(block_rows, &mut f);
            f
        })
        .collect();
    (out, add_parts(&parts, n))
}

/// The folded log remainder of a boundary invariant under the shift by
/// m = n/k nodes on each of its K curves (see [`crate::symmetry`]): the
/// row-major K m × K m matrix L_f[(a,i),(b,j)] = Σ_q L[(a,i),(b,j+qm)]
/// (i, j < m), and the right-hand side f at the first m nodes of each
/// curve. L_f is symmetric (L is, and invariant under the shift): only
/// its upper triangle is computed (half the logarithms; the lower one is
/// left 0, and the caller reads the upper one), each row folded in a fixed
/// order, one row per task, so the result does not depend on the number
/// of threads.
pub fn log_remainder_folded(nodes: &[BPoint], n: usize, m: usize, x0: V2) -> (Vec<f64>, Vec<f64>) {
    let big = nodes.len();
    let curves = big / n;
    let small = curves * m;
    let sines = log_sines(n);
    let arrays = NodeArrays::new(nodes);
    let mut out = vec![0.0; small * small];
    let mut f = vec![0.0; small];
    let h = 1.0 / n as f64;
    out.par_chunks_mut(small)
        .zip(f.par_iter_mut())
        .enumerate()
        .for_each_init(
            || (vec![0.0; big], vec![0.0; big]),
            |(row, terms), (r, (folded, fr))| {
                let i = (r / m) * n + r % m;
                let rows = FoldedRow {
                    a: &arrays,
                    n,
                    m,
                    sines: &sines,
                    x0,
                    i,
                };
                #[cfg(target_arch = "x86_64")]
                if crate::logarithm::has_avx2() {
                    // SAFETY: the CPU has AVX2, the only feature it is compiled for
                    *fr = unsafe { rows.fill_avx2(row, terms, folded) } * h;
                    return;
                }
                *fr = rows.fill(row, terms, folded) * h;
            },
        );
    (out, f)
}

/// One row of [`log_remainder_folded`].
struct FoldedRow<'a> {
    a: &'a NodeArrays,
    n: usize,
    m: usize,
    sines: &'a [f64],
    x0: V2,
    /// the row's node
    i: usize,
}

impl FoldedRow<'_> {
    /// Fills the upper triangle of `folded` (K m entries: the columns from
    /// the row's own position on; the others, which the caller never
    /// reads, are 0) and returns the row's right-hand-side sum (before the
    /// weight 1/n) over the whole row; `row` and `terms` are work space (N
    /// entries). The logarithms are taken only for the columns folded into
    /// that triangle: on the row's own curve the nodes q m + jj with
    /// jj ≥ ii (its index), and every node of the curves after it, half
    /// of the row.
    #[inline(always)]
    fn fill(&self, row: &mut [f64], terms: &mut [f64], folded: &mut [f64]) -> f64 {
        let (a, i, n, m) = (self.a, self.i, self.n, self.m);
        let big = a.len();
        let (pxi, pyi, x0) = (a.px[i], a.py[i], self.x0);
        let (start, ii) = ((i / n) * n, i % n);
        let k = n / m;
        for j in 0..big {
            let (dx, dy) = a.diff(i, j);
            let rr = dx * dx + dy * dy;
            row[j] = rr.max(f64::MIN_POSITIVE);
            let w = -0.5
                * (dx * (pxi + a.px[j] - 2.0 * x0[0]) + dy * (pyi + a.py[j] - 2.0 * x0[1]))
                / (2.0 * PI * rr);
            // coincident nodes (and j = i) add nothing
            let w = if rr > 0.0 { w } else { 0.0 };
            terms[j] = w * (dx * a.ty[j] - dy * a.tx[j]);
        }
        let fi = sum_lanes(terms);
        // ½ ln r² on the columns of the triangle
        for q in 0..k {
            let seg = &mut row[start + q * m + ii..start + (q + 1) * m];
            crate::logarithm::ln_slice(seg);
            for v in seg.iter_mut() {
                *v *= 0.5;
            }
        }
        let later = &mut row[start + n..];
        crate::logarithm::ln_slice(later);
        for v in later.iter_mut() {
            *v *= 0.5;
        }
        // ln|2 sin π(t_i − t_j)| on i's own curve (index |i − j|, as the
        // full matrix's triangles)
        for q in 0..k {
            for jj in q * m + ii..(q + 1) * m {
                if jj != ii {
                    row[start + jj] -= self.sines[ii.abs_diff(jj)];
                }
            }
        }
        let speed = a.tx[i].hypot(a.ty[i]);
        row[i] = (speed / (2.0 * PI)).max(f64::MIN_POSITIVE).ln();
        let c = i / n;
        for (b, (blk, out)) in row.chunks(n).zip(folded.chunks_mut(m)).enumerate() {
            let from = match b.cmp(&c) {
                std::cmp::Ordering::Less => m,
                std::cmp::Ordering::Equal => ii,
                std::cmp::Ordering::Greater => 0,
            };
            out[..from].fill(0.0);
            out[from..].copy_from_slice(&blk[from..m]);
            for period in blk.chunks(m).skip(1) {
                for (o, v) in out[from..].iter_mut().zip(&period[from..]) {
                    *o += v;
                }
            }
        }
        fi
    }
    /// [`FoldedRow::fill`] compiled for AVX2 (the same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn fill_avx2(&self, row: &mut [f64], terms: &mut [f64], folded: &mut [f64]) -> f64 {
        self.fill(row, terms, folded)
    }
}

/// A block of rows of [`log_remainder_upper`], from row `first` on.
struct UpperRows<'a> {
    a: &'a NodeArrays,
    n: usize,
    sines: &'a [f64],
    x0: V2,
    first: usize,
}

impl UpperRows<'_> {
    /// Fills the rows (`rows`, row-major, N wide) and adds their
    /// right-hand-side terms to `f`.
    #[inline(always)]
    fn fill(&self, rows: &mut [f64], f: &mut [f64]) {
        let big = self.a.len();
        let mut scratch = vec![0.0; big];
        for (r, row) in rows.chunks_mut(big).enumerate() {
            let i = self.first + r;
            log_remainder_upper_row(self.a, self.n, self.sines, self.x0, i, row, f, &mut scratch);
        }
    }
    /// [`UpperRows::fill`] compiled for AVX2 (the same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn fill_avx2(&self, rows: &mut [f64], f: &mut [f64]) {
        self.fill(rows, f)
    }
}

/// Rows per block of a pass over the pairs i < j: 64 blocks, each summing
/// the right-hand-side contributions of its pairs into its own vector.
fn pair_block(big: usize) -> usize {
    big.div_ceil(64).max(1)
}

/// The blocks' right-hand-side sums, added in block order (so the result
/// does not depend on the number of threads), times the weight 1/n.
fn add_parts(parts: &[Vec<f64>], n: usize) -> Vec<f64> {
    let big = parts.first().map_or(0, Vec::len);
    let h = 1.0 / n as f64;
    (0..big)
        .map(|k| parts.iter().map(|p| p[k]).sum::<f64>() * h)
        .collect()
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

/// The nodes by component, so that the loops over j read contiguous
/// arrays (vector instructions).
pub(crate) struct NodeArrays {
    /// anchors and offsets (x = anchor + offset, see [`BPoint`])
    pub ax: Vec<f64>,
    pub ay: Vec<f64>,
    pub ox: Vec<f64>,
    pub oy: Vec<f64>,
    /// positions anchor + offset
    pub px: Vec<f64>,
    pub py: Vec<f64>,
    /// x′
    pub tx: Vec<f64>,
    pub ty: Vec<f64>,
}

impl NodeArrays {
    pub(crate) fn new(nodes: &[BPoint]) -> NodeArrays {
        let comp = |f: &dyn Fn(&BPoint) -> f64| nodes.iter().map(f).collect::<Vec<f64>>();
        NodeArrays {
            ax: comp(&|p| p.anchor[0]),
            ay: comp(&|p| p.anchor[1]),
            ox: comp(&|p| p.offset[0]),
            oy: comp(&|p| p.offset[1]),
            px: comp(&|p| p.x()[0]),
            py: comp(&|p| p.x()[1]),
            tx: comp(&|p| p.d1[0]),
            ty: comp(&|p| p.d1[1]),
        }
    }
    pub(crate) fn len(&self) -> usize {
        self.ax.len()
    }
    /// x_i − x_j, exact for a shared anchor (the anchors then cancel to 0
    /// exactly, as in [`diff`]).
    #[inline(always)]
    pub(crate) fn diff(&self, i: usize, j: usize) -> (f64, f64) {
        (
            (self.ax[i] - self.ax[j]) + (self.ox[i] - self.ox[j]),
            (self.ay[i] - self.ay[j]) + (self.oy[i] - self.oy[j]),
        )
    }
}

/// Σ v in a fixed order: four interleaved partial sums (the lanes of a
/// vector register), then added pairwise.
#[inline(always)]
pub(crate) fn sum_lanes(v: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let chunks = v.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for k in 0..4 {
            acc[k] += c[k];
        }
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for x in rest {
        s += x;
    }
    s
}

/// The pairs (i, j > i) of one row: r² (at least `f64::MIN_POSITIVE`)
/// into `r2[j]`, the right-hand-side terms of f_j added to `f[j]`, and the
/// sum of the terms of f_i returned (`scratch` holds them on the way).
///
/// The integrand of f at x is (g(y) − g(x)) (x − y)·n_y |y′| / (2π r²),
/// with g(y) − g(x) = ½ (y − x)·(y + x − 2x₀) antisymmetric in the pair and
/// (x − y)·n_y |y′| = (x − y) × y′: with d = x_i − x_j, f_i gets
/// w (d × x_j′) and f_j gets w (d × x_i′), w = −½ d·(x_i + x_j − 2x₀) / (2π r²).
#[inline(always)]
fn pair_row(
    a: &NodeArrays,
    x0: V2,
    i: usize,
    r2: &mut [f64],
    f: &mut [f64],
    scratch: &mut [f64],
) -> f64 {
    let big = a.len();
    let (pxi, pyi, txi, tyi) = (a.px[i], a.py[i], a.tx[i], a.ty[i]);
    for j in i + 1..big {
        let (dx, dy) = a.diff(i, j);
        let rr = dx * dx + dy * dy;
        r2[j] = rr.max(f64::MIN_POSITIVE);
        let w = -0.5 * (dx * (pxi + a.px[j] - 2.0 * x0[0]) + dy * (pyi + a.py[j] - 2.0 * x0[1]))
            / (2.0 * PI * rr);
        // coincident nodes (r = 0) add nothing
        let w = if rr > 0.0 { w } else { 0.0 };
        scratch[j] = w * (dx * a.ty[j] - dy * a.tx[j]);
        f[j] += w * (dx * tyi - dy * txi);
    }
    sum_lanes(&scratch[(i + 1).min(big)..big])
}

/// Entries j ≥ i of row i of [`log_remainder_blocks`] (`row[..i]` is not
/// touched), and the right-hand-side terms of the pairs (i, j > i) added
/// to `f`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn log_remainder_upper_row(
    a: &NodeArrays,
    n: usize,
    sines: &[f64],
    x0: V2,
    i: usize,
    row: &mut [f64],
    f: &mut [f64],
    scratch: &mut [f64],
) {
    let speed = a.tx[i].hypot(a.ty[i]);
    row[i] = (speed / (2.0 * PI)).max(f64::MIN_POSITIVE).ln();
    // r² first, its logarithms at once (vector instructions), then
    // L = ln r − ln|2 sin π(t_i − t_j)| on the rest of i's curve and ln r on
    // later curves
    let fi = pair_row(a, x0, i, row, f, scratch);
    f[i] += fi;
    crate::logarithm::ln_slice(&mut row[i + 1..]);
    let end = ((i / n + 1) * n).min(row.len());
    for (v, s) in row[i + 1..end].iter_mut().zip(&sines[1..]) {
        *v = 0.5 * *v - s;
    }
    for v in &mut row[end..] {
        *v *= 0.5;
    }
}

/// ln|2 sin(πk/n)| for k = 0..n (the k = 0 entry is −∞ and never used).
pub fn log_sines(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| (2.0 * (PI * k as f64 / n as f64).sin()).abs().ln())
        .collect()
}

/// Right-hand side f(t_a) = ((½I + K) g)(x_a) in subtracted form, by the
/// trapezoidal rule for K curves of `n` nodes each: the integral runs over
/// every curve of Γ (∮_Γ ∂w/∂n_y ds_y = −½ on Γ holds for the whole
/// boundary of Ω). One pass over the pairs i < j.
pub fn rhs_blocks(nodes: &[BPoint], n: usize, x0: V2) -> Vec<f64> {
    let big = nodes.len();
    let arrays = NodeArrays::new(nodes);
    let block = pair_block(big);
    let parts: Vec<Vec<f64>> = (0..big.div_ceil(block))
        .into_par_iter()
        .map(|b| {
            let mut f = vec![0.0; big];
            let rows = b * block..((b + 1) * block).min(big);
            #[cfg(target_arch = "x86_64")]
            if crate::logarithm::has_avx2() {
                // SAFETY: the CPU has AVX2, the only feature it is compiled for
                unsafe { rhs_rows_avx2(&arrays, x0, rows, &mut f) };
                return f;
            }
            rhs_rows(&arrays, x0, rows, &mut f);
            f
        })
        .collect();
    add_parts(&parts, n)
}

/// The right-hand-side terms of the pairs (i, j > i) for the rows i in
/// `rows`, added to `f`.
#[inline(always)]
fn rhs_rows(a: &NodeArrays, x0: V2, rows: std::ops::Range<usize>, f: &mut [f64]) {
    let big = a.len();
    let mut r2 = vec![0.0; big];
    let mut scratch = vec![0.0; big];
    for i in rows {
        let fi = pair_row(a, x0, i, &mut r2, f, &mut scratch);
        f[i] += fi;
    }
}

/// [`rhs_rows`] compiled for AVX2 (the same bits).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn rhs_rows_avx2(a: &NodeArrays, x0: V2, rows: std::ops::Range<usize>, f: &mut [f64]) {
    rhs_rows(a, x0, rows, f)
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
pub(crate) mod tests {
    use super::*;
    use crate::grading::diff;

    /// `n` nodes t_a = (a + ½)/n on the circle of radius `r` about `c`.
    pub(crate) fn circle(n: usize, r: f64, c: [f64; 2]) -> Vec<BPoint> {
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
        let (l, _) = log_remainder_blocks(&nodes, n, [0.0, 0.0]);
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
                let v = l[i * big + j];
                assert!(
                    (v - expected).abs() <= 1e-15 * expected.abs().max(1.0),
                    "entry ({i}, {j}): {v} vs {expected}"
                );
                assert_eq!(v.to_bits(), l[j * big + i].to_bits(), "symmetry ({i}, {j})");
            }
        }
    }

    /// The right-hand side of the one pass over the pairs (each pair's two
    /// terms at once, in blocks) against the integral at each node summed
    /// directly, on two curves (an off-centre hole).
    #[test]
    fn the_pair_pass_right_hand_side_equals_the_direct_sum() {
        let n = 64;
        let mut nodes = circle(n, 1.0, [0.0, 0.0]);
        nodes.extend(circle(n, 0.3, [0.1, -0.05]));
        let x0 = [0.02, -0.01];
        let direct: Vec<f64> = (0..nodes.len())
            .map(|i| {
                let pi = nodes[i].x();
                let mut acc = 0.0;
                for (j, yj) in nodes.iter().enumerate() {
                    if j != i {
                        let py = yj.x();
                        let d = diff(&nodes[i], yj);
                        let dg = -0.5
                            * (d[0] * (py[0] + pi[0] - 2.0 * x0[0])
                                + d[1] * (py[1] + pi[1] - 2.0 * x0[1]));
                        let num = d[0] * yj.d1[1] - d[1] * yj.d1[0];
                        acc += dg * num / (2.0 * PI * (d[0] * d[0] + d[1] * d[1]));
                    }
                }
                acc / n as f64
            })
            .collect();
        let (_, fused) = log_remainder_upper(&nodes, n, x0);
        let alone = rhs_blocks(&nodes, n, x0);
        let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (i, ((d, f), a)) in direct.iter().zip(&fused).zip(&alone).enumerate() {
            assert!((d - f).abs() <= 1e-14 * scale, "node {i}: {f} vs {d}");
            assert_eq!(f.to_bits(), a.to_bits(), "node {i}: the two passes differ");
        }
    }

    /// The AVX2 copy of the row loops gives the same bits as the baseline
    /// copy (no fused multiply-adds, no reordering), on two curves.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_avx2_fill_equals_the_baseline_fill_bit_for_bit() {
        if !crate::logarithm::has_avx2() {
            return;
        }
        let n = 48;
        let mut nodes = circle(n, 1.0, [0.0, 0.0]);
        nodes.extend(circle(n, 0.3, [0.1, -0.05]));
        let big = nodes.len();
        let arrays = NodeArrays::new(&nodes);
        let sines = log_sines(n);
        let rows = UpperRows {
            a: &arrays,
            n,
            sines: &sines,
            x0: [0.02, -0.01],
            first: 0,
        };
        let (mut base, mut avx) = (vec![0.0; big * big], vec![0.0; big * big]);
        let (mut f_base, mut f_avx) = (vec![0.0; big], vec![0.0; big]);
        rows.fill(&mut base, &mut f_base);
        // SAFETY: the CPU has AVX2 (checked above)
        unsafe { rows.fill_avx2(&mut avx, &mut f_avx) };
        assert!(
            base.iter()
                .zip(&avx)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
        assert!(
            f_base
                .iter()
                .zip(&f_avx)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
        // and the pass is not trivial (L vanishes between two points of the
        // unit circle: the hole's rows and the cross pairs are not 0)
        assert!(base.iter().filter(|v| **v != 0.0).count() > big * big / 8);
        assert!(f_base.iter().all(|v| v.is_finite() && *v != 0.0));
    }
}
