//! Rotational symmetry of the discrete boundary: folding the Galerkin system.
//!
//! If shifting the nodes of every curve by m = n/k places (forwards or
//! backwards) rotates them by 2π/k about the centroid x₀, every part of
//! the Daubechies system is invariant under that shift: the log remainder
//! L (it depends on |x_i − x_j| and t_i − t_j only), the circulants C and
//! P, the load, the constraint and the functional. The solution is then
//! invariant too (m-periodic on every curve), and it solves the *folded*
//! system of order K m,
//!
//! ```text
//! A_f = −(C_f + P_f L_f P_fᵀ)/2π,   L_f[(a,i),(b,j)] = Σ_q L[(a,i),(b,j+qm)],
//! ```
//!
//! with C_f and P_f the circulants of length m whose kernels are the
//! folded sums c_f(d) = Σ_q c(d + qm) (a circulant maps an m-periodic vector
//! to an m-periodic one, by the folded kernel). A_f is symmetric, and its
//! definiteness is that of A on the invariant subspace. The shift term
//! κ E Eᵀ of the saddle solve becomes k κ E_f E_fᵀ (Eᵀ of a periodic vector
//! is k times E_fᵀ of its period); the constraints and the multipliers are
//! unchanged.
//!
//! Cost: the rows of the first period only (m N logarithms instead of
//! N²/2), convolutions of length m, and a factorisation of order K m: a
//! regular 24-gon at n = 4096 (k = 8) factorises a 512 × 512 matrix.
//! Only rotations by 2π/k with k a power of two can be used (n is one),
//! and only those that map the nodes onto nodes; reflections cannot (the
//! Daubechies scaling functions are not symmetric). The shift is tested on
//! the nodes themselves, so a section is folded only when its discrete
//! boundary is symmetric to round-off: the anchors and positions to
//! [`POSITION_TOLERANCE`] of the section's size, and the offsets from the
//! anchors (which resolve the graded corners) and the tangents to
//! [`RELATIVE_TOLERANCE`] of their own length.

use crate::geometry::V2;
use crate::grading::BPoint;

/// Positions and anchors: largest distance, relative to the section's
/// radius, between a shifted node and the rotated node.
pub const POSITION_TOLERANCE: f64 = 1e-13;

/// Offsets from the anchors and tangents: largest difference relative to
/// their own length.
pub const RELATIVE_TOLERANCE: f64 = 1e-12;

/// Node spacing |x′|/n (relative to the radius) from which a node is
/// placed precisely enough by its position alone.
const COARSE_SPACING: f64 = 1e-6;

/// Smallest period m = n/k worth folding to.
pub const MIN_PERIOD: usize = 16;

/// The largest power of two k (1 if none) such that, on every curve of n
/// nodes (`nodes`, curve after curve), a shift by n/k places (or by −n/k)
/// rotates the nodes by 2π/k about `x0`. `radius` is the section's
/// largest distance from `x0` (the scale of the position test).
pub fn rotation_order(nodes: &[BPoint], n: usize, x0: V2, radius: f64) -> usize {
    if n == 0 || !nodes.len().is_multiple_of(n) || nodes.is_empty() {
        return 1;
    }
    let mut order = 1;
    let mut k = 2;
    while n / k >= MIN_PERIOD && n.is_multiple_of(k) {
        if !nodes
            .chunks(n)
            .all(|curve| curve_invariant(curve, k, x0, radius))
        {
            break;
        }
        order = k;
        k *= 2;
    }
    order
}

/// Whether the shift by n/k or by −n/k rotates the curve by 2π/k.
fn curve_invariant(curve: &[BPoint], k: usize, x0: V2, radius: f64) -> bool {
    let n = curve.len();
    let m = n / k;
    let angle = 2.0 * std::f64::consts::PI / k as f64;
    let (s, c) = angle.sin_cos();
    // exact for the half turn (k = 2): cos π = −1, sin π = 0
    let (s, c) = if k == 2 { (0.0, -1.0) } else { (s, c) };
    let rot = |v: V2| -> V2 { [c * v[0] - s * v[1], s * v[0] + c * v[1]] };
    let tol = POSITION_TOLERANCE * radius;
    let close = |a: V2, b: V2, t: f64| (a[0] - b[0]).hypot(a[1] - b[1]) <= t;
    let rel = |a: V2, b: V2| close(a, b, RELATIVE_TOLERANCE * b[0].hypot(b[1]));
    let maps = |shift: usize| {
        curve.iter().enumerate().all(|(i, p)| {
            let q = &curve[(i + shift) % n];
            let centred = |v: V2| [v[0] - x0[0], v[1] - x0[1]];
            let (px, qx) = (rot(centred(p.x())), centred(q.x()));
            let (pa, qa) = (rot(centred(p.anchor)), centred(q.anchor));
            // in a graded cluster (nodes far closer together than the
            // position tolerance can tell) the anchors must agree and the
            // offsets, which resolve the cluster, to their own length;
            // elsewhere the anchor may differ (a smooth curve has one
            // anchor for all its nodes, a tie mid-panel may pick either
            // end) and the position test is fine enough
            let local = if close(qa, pa, tol) {
                rel(q.offset, rot(p.offset))
            } else {
                p.speed() / n as f64 >= COARSE_SPACING * radius
            };
            close(qx, px, tol) && rel(q.d1, rot(p.d1)) && local
        })
    };
    maps(m) || maps(n - m)
}

/// The folded kernel f(d) = Σ_q v(d + q m), d = 0..m, of a circulant's
/// kernel `v` of length n = k m.
pub fn fold_kernel(v: &[f64], m: usize) -> Vec<f64> {
    let mut out = vec![0.0; m];
    for chunk in v.chunks(m) {
        for (o, x) in out.iter_mut().zip(chunk) {
            *o += x;
        }
    }
    out
}

/// The first period (m entries) of every curve's block of `v` (K blocks of n).
pub fn first_periods(v: &[f64], n: usize, m: usize) -> Vec<f64> {
    v.chunks(n).flat_map(|b| b[..m].iter().copied()).collect()
}

/// The periodic vector (K blocks of n) whose every block repeats its period
/// (K blocks of m in `v`).
pub fn unfold(v: &[f64], n: usize, m: usize) -> Vec<f64> {
    v.chunks(m)
        .flat_map(|b| b.iter().copied().cycle().take(n))
        .collect()
}
