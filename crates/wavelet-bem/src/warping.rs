//! The warping function ω, the shear centre and the warping constant Γ,
//! from the torsion solution itself (no second solve).
//!
//! ω is harmonic in Ω with ∂ω/∂n = Y n_x − X n_y on every curve (X, Y taken
//! from the centroid x₀). The harmonic part of the Prandtl function,
//! v = u + |x − x₀|²/2, equals |x − x₀|²/2 (+ the hole constant) on Γ, so
//! ∂v/∂s = Y n_x − X n_y = ∂ω/∂n there: ω and v are harmonic conjugates,
//! ∇ω = (∂v/∂y, −∂v/∂x). Along a curve, in the direction of its parameter
//! (Ω on the left, n = (y′, −x′)/|x′|),
//!
//! ```text
//! dω/dt = −∂v/∂n |x′| = −μ(t),   so   ω̂(r) = −μ̂(r) / (2πi r),  r ≠ 0,
//! ```
//!
//! single valued because every curve carries ∮ q_v ds = 0 (the constraint of
//! the augmented system). Every discretisation (Daubechies, Shannon,
//! Nyström) therefore yields ω on Γ from its own density μ, to the accuracy
//! of μ; the Nyström result is the cross-check of the Galerkin one.
//!
//! **Constants between curves.** On hole k, ω = ω̃_k + C_k. Green's second
//! identity with h = ln|x − z_k|, z_k inside hole k (h harmonic in Ω), gives
//!
//! ```text
//! C_k − C_0 = (1/2π) [ Σ_m ∮_{Γ_m} ω̃ ∂h/∂n ds − ∮_Γ h ∂ω/∂n ds ],
//! ```
//!
//! (∮_{Γ_0} ∂h/∂n = 2π, ∮_{Γ_k} ∂h/∂n = −2π with n out of Ω, 0 on other holes).
//!
//! **Area integrals from boundary data.** With ∇²φ = f and ω harmonic,
//! ∫ f ω dA = ∮ (ω ∂φ/∂n − φ ∂ω/∂n) ds: φ = |X|²/4 (f = 1), X³/6 (f = X),
//! Y³/6 (f = Y). For ∫ ω² dA, ψ = ∮ [Φ ∂ω/∂n − ω ∂Φ/∂n_y] ds_y with
//! Φ(r) = r²(1 − ln r)/8π (∇²Φ = −ln r/2π, the fundamental solution) solves
//! ∇²ψ = ω in Ω, so ∫ ω² dA = ∮ (ω ∂ψ/∂n − ψ ∂ω/∂n) ds. Φ is C¹, so ψ and
//! ∂ψ/∂n are continuous up to Γ; their kernels are A + B ln|2 sin π(t − s)|
//! with A, B smooth, integrated with Kress's product weights on the graded
//! nodes (spectral on smooth curves, the grading's order at corners).
//!
//! **Shear centre (Trefftz)** x_S − x₀ = (x_p, y_p) makes the warping about
//! it, ω_S = ω − y_p X + x_p Y, orthogonal to X and Y:
//!
//! ```text
//! x_p = (I_xy I_Xω − I_yy I_Yω)/Δ,   y_p = (I_xx I_Xω − I_xy I_Yω)/Δ,   Δ = I_xx I_yy − I_xy²
//! ```
//!
//! (I_xx = ∫Y², I_yy = ∫X², I_xy = ∫XY, I_Xω = ∫Xω, I_Yω = ∫Yω). The
//! warping constant is Γ = ∫ ω_n² dA with ω_n = ω_S − (1/A)∫ω_S dA, the
//! normalised warping function about the shear centre.

use crate::density::FourierDensity;
use crate::geometry::{PointLocation, Section, V2};
use crate::grading::BPoint;
use crate::kernels::{NodeArrays, sum_lanes};
use crate::nystrom::kress_weights;
use crate::solve::TorsionSolution;
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

/// Warping outputs of one torsion solution.
#[derive(Clone, Debug)]
pub struct Warping {
    /// shear centre x_S (absolute coordinates)
    pub shear_centre: V2,
    /// warping constant Γ = ∫ ω_n² dA about the shear centre (as computed:
    /// where ω vanishes, circles and concentric tubes, round-off can make it
    /// slightly negative, e.g. −4e-33; [`Warping::reported`] makes it 0)
    pub warping_constant: f64,
    /// ∫ X ω dA, ∫ Y ω dA with ω about the centroid (X = x − x₀)
    pub product_integrals: V2,
    /// ∫ ω₀² dA, ω₀ the normalised warping function about the centroid (as
    /// computed, like `warping_constant`)
    pub centroidal_constant: f64,
    /// ω₀ on every curve (outer first): the normalised warping function about
    /// the centroid as a trigonometric polynomial in the curve's parameter
    pub curves: Vec<FourierDensity>,
    /// the centroid x₀ the curves' ω₀ refers to
    pub centroid: V2,
    /// number of quadrature nodes per curve
    pub nodes: usize,
    /// Round-off scale of Γ (absolute): ε Σ|terms| of the ω² double
    /// integral, whose terms cancel to Γ (by a factor of 10⁶ on the
    /// 1 × 0.01 ellipse), times [`GAMMA_ROUND_OFF`] (one curve) or
    /// [`GAMMA_ROUND_OFF_HOLES`].
    pub round_off: f64,
}

/// The round-off of Γ on a single boundary curve, as a multiple of
/// ε Σ|terms| of its double integral (sampled, see
/// `OmegaPairs::magnitude`). Measured (2026-11-28, db4): against the closed
/// form on the ellipses 1 × b (n = 2048 … 8192) Γ is off by 1.2 – 2.7
/// ε Σ|terms| — 4e-13 of Γ at b = 0.1, 2.3e-10 at b = 0.01, the same at
/// every n (a bias of the arithmetic, not of the discretisation), growing
/// like b⁻³ as Γ shrinks like b³ while Σ|terms| stays; as the spread of Γ
/// over five frames (turned by 0 – 45°, moved) 1.2 – 3.7 ε Σ|terms| on the
/// square, the rectangles 2 × 1 and 30 × 1, the triangle and the
/// sectionproperties I. The differences between rungs do not see a bias
/// that does not change with n: the 1 × 0.01 ellipse reported 1.8e-10 for
/// a true 2.1e-10 at 1e-8.
pub const GAMMA_ROUND_OFF: f64 = 4.0;

/// [`GAMMA_ROUND_OFF`] for sections with holes. The frame spread of Γ,
/// over ε Σ|terms|: box 2 × 1 with walls 0.1 2.9, walls 0.02 13; the
/// square box 1 × 1 with walls 0.02 18 (1.4e-9 of Γ), 0.4 × 0.4 with walls
/// 0.01 51 (3.8e-9 of Γ: a square box hardly warps, Γ is 4e-5 of I_p²/A,
/// and its terms cancel the more). Those two had reported Γ converged to
/// 1e-10 with estimates of 1.4e-11.
pub const GAMMA_ROUND_OFF_HOLES: f64 = 64.0;

/// An integral of a square as reported: max(x, 0). A negative finite value
/// can only be round-off (of a vanishing ω: Γ of the circle came out as
/// −4.3e-33); a non-finite one is kept, to be flagged.
pub fn nonnegative(x: f64) -> f64 {
    if x < 0.0 && x.is_finite() { 0.0 } else { x }
}

impl Warping {
    /// The outputs as reported: Γ and the centroidal constant, integrals of
    /// squares, through [`nonnegative`]. The error estimates use the
    /// values as computed (their differences measure the convergence).
    pub fn reported(mut self) -> Warping {
        self.warping_constant = nonnegative(self.warping_constant);
        self.centroidal_constant = nonnegative(self.centroidal_constant);
        self
    }
}

/// One sample of ω along a boundary curve.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct WarpingSample {
    /// boundary curve (0: outer, k ≥ 1: hole k)
    pub curve: usize,
    /// parameter t ∈ [0, 1)
    pub t: f64,
    /// position
    pub x: V2,
    /// ω_n, the normalised warping function about the shear centre
    pub omega: f64,
}

impl Warping {
    /// ω_n (normalised, about the shear centre) at parameter t of curve k,
    /// given the position x there.
    pub fn omega_at(&self, k: usize, t: f64, x: V2) -> f64 {
        let (xp, yp) = (
            self.shear_centre[0] - self.centroid[0],
            self.shear_centre[1] - self.centroid[1],
        );
        let (dx, dy) = (x[0] - self.centroid[0], x[1] - self.centroid[1]);
        self.curves[k].eval(t) - yp * dx + xp * dy
    }
}

/// Antiderivative −∫ μ dt of a zero-mean trigonometric density.
fn antiderivative(mu: &FourierDensity) -> FourierDensity {
    let r_max = mu.max_freq as i64;
    let coef = mu
        .coef
        .iter()
        .enumerate()
        .map(|(idx, c)| {
            let r = idx as i64 - r_max;
            if r == 0 {
                Complex64::new(0.0, 0.0)
            } else {
                -c / Complex64::new(0.0, 2.0 * PI * r as f64)
            }
        })
        .collect();
    FourierDensity {
        coef,
        max_freq: mu.max_freq,
    }
}

/// A point well inside the (simply connected) region bounded by `hole`: the
/// hole's centroid if it lies inside, else the inside point of a 48 × 48
/// grid over its bounding box farthest from its boundary.
fn point_inside(hole: &Section) -> V2 {
    let poly = crate::polyline::polyline(&hole.pieces, 64);
    let c = hole.centroid;
    if crate::polyline::winding(&poly, c) != 0 {
        return c;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &poly {
        lo = [lo[0].min(p[0]), lo[1].min(p[1])];
        hi = [hi[0].max(p[0]), hi[1].max(p[1])];
    }
    let g = 48;
    let mut best = (0.0, c);
    for i in 0..g {
        for j in 0..g {
            let p = [
                lo[0] + (hi[0] - lo[0]) * (i as f64 + 0.5) / g as f64,
                lo[1] + (hi[1] - lo[1]) * (j as f64 + 0.5) / g as f64,
            ];
            if crate::polyline::winding(&poly, p) != 0 {
                let d = crate::polyline::polyline_distance(&poly, p);
                if d > best.0 {
                    best = (d, p);
                }
            }
        }
    }
    best.1
}

/// Boundary data at the quadrature nodes of all curves.
struct Nodes {
    pts: Vec<BPoint>,
    /// ω on each node (about the centroid)
    omega: Vec<f64>,
    /// ∂ω/∂n = Y n_x − X n_y
    flux: Vec<f64>,
    /// nodes per curve
    m: usize,
}

impl Nodes {
    /// Σ over all nodes of f(x, n, |x′|, ω, ∂ω/∂n) |x′| / m: ∮ f ds.
    fn integrate(&self, f: impl Fn(V2, V2, f64, f64) -> f64) -> f64 {
        let h = 1.0 / self.m as f64;
        self.pts
            .iter()
            .zip(&self.omega)
            .zip(&self.flux)
            .map(|((p, &w), &q)| f(p.x(), p.normal(), w, q) * p.speed() * h)
            .sum()
    }
}

/// ∫ ω² dA by the Φ double integral (see the module notes). With `fold`
/// k > 1 the nodes and ω are invariant under the shift by p = m/k nodes on
/// every curve (a k-fold rotation about the centroid, see
/// [`crate::symmetry`]): ψ and χ are then invariant too, and the integral
/// is k times the sum over the rows of each curve's first p nodes (the set
/// P). Each of those rows sums over every node j, and the pairs (i, j)
/// fall into orbits under the rotation: the orbit of (j, i) has its own
/// representative (j′, i′) with j′ in P, whose row term is the j side of
/// the pair (i, j). So each pair is evaluated once, for both of its rows,
/// by the row of P whose position (curve, index within the period) comes
/// first ([`OmegaPairs::half_row`]): half the logarithms of whole rows.
///
/// Returns the integral and the size of its terms
/// ([`OmegaPairs::magnitude`], for its round-off).
fn omega_squared_integral(nd: &Nodes, fold: usize) -> (f64, f64) {
    let m = nd.m;
    let big = nd.pts.len();
    let pairs = OmegaPairs::new(nd);
    let magnitude = pairs.magnitude();
    let h = 1.0 / m as f64;
    if fold > 1 {
        let period = m / fold;
        let rows: Vec<usize> = (0..big / m).flat_map(|c| c * m..c * m + period).collect();
        let terms: Vec<f64> = rows
            .par_iter()
            .map_init(
                || RowWork::new(big),
                |work, &i| {
                    #[cfg(target_arch = "x86_64")]
                    if crate::logarithm::has_avx2() {
                        // SAFETY: the CPU has AVX2, the only feature it is compiled for
                        return unsafe { pairs.half_row_avx2(i, period, work) };
                    }
                    pairs.half_row(i, period, work)
                },
            )
            .collect();
        return (fold as f64 * h * terms.iter().sum::<f64>(), magnitude);
    }
    // Every kernel depends on the pair through r², ln r and the two normal
    // projections of x_i − x_j, and swapping i and j swaps the projections
    // (d·n_i ↔ −d·n_j): each pair i < j is evaluated once (one logarithm)
    // and adds to ψ, χ of both rows. Rows are cut into a fixed number of
    // blocks, each summing into its own (ψ, χ), added in block order: the
    // result does not depend on the thread count.
    const BLOCKS: usize = 64;
    let block = big.div_ceil(BLOCKS).max(1);
    let partial: Vec<(Vec<f64>, Vec<f64>)> = (0..big.div_ceil(block))
        .into_par_iter()
        .map(|b| {
            let rows = b * block..((b + 1) * block).min(big);
            #[cfg(target_arch = "x86_64")]
            if crate::logarithm::has_avx2() {
                // SAFETY: the CPU has AVX2, the only feature it is compiled for
                return unsafe { pairs.rows_avx2(rows) };
            }
            pairs.rows(rows)
        })
        .collect();
    let mut psi = vec![0.0; big];
    let mut chi = vec![0.0; big];
    for (p, c) in &partial {
        for k in 0..big {
            psi[k] += p[k];
            chi[k] += c[k];
        }
    }
    let integral = (0..big)
        .map(|i| (nd.omega[i] * chi[i] - psi[i] * nd.flux[i]) * pairs.speeds[i] * h)
        .sum();
    (integral, magnitude)
}

/// Rows and columns sampled by `OmegaPairs::magnitude`.
const MAGNITUDE_SAMPLES: usize = 256;

/// The node data of [`omega_squared_integral`], by component.
struct OmegaPairs {
    /// nodes per curve
    m: usize,
    /// Kress's weights R(k/m), R((m − k)/m) and ln|2 sin π k/m|
    r: Vec<f64>,
    r_back: Vec<f64>,
    sines: Vec<f64>,
    /// the nodes by component (anchors and offsets for x_i − x_j)
    arrays: NodeArrays,
    /// unit normals
    nxs: Vec<f64>,
    nys: Vec<f64>,
    /// ∂ω/∂n |x′| and ω |x′|
    qs: Vec<f64>,
    ws: Vec<f64>,
    /// |x′|
    speeds: Vec<f64>,
}

impl OmegaPairs {
    /// The node data of `nd`, by component.
    fn new(nd: &Nodes) -> OmegaPairs {
        let m = nd.m;
        let speeds: Vec<f64> = nd.pts.iter().map(|p| p.speed()).collect();
        let normals: Vec<V2> = nd.pts.iter().map(|p| p.normal()).collect();
        // per node: the node by component, unit normal, speed, ∂ω/∂n |x′|
        // and ω |x′| (contiguous loops over j)
        OmegaPairs {
            m,
            r_back: {
                // R((t_i − t_j) mod 1) for j = i + k: R at m − k, read forwards
                let r = kress_weights(m);
                (0..m).map(|k| r[(m - k) % m]).collect()
            },
            r: kress_weights(m),
            sines: crate::kernels::log_sines(m),
            arrays: NodeArrays::new(&nd.pts),
            nxs: normals.iter().map(|v| v[0]).collect(),
            nys: normals.iter().map(|v| v[1]).collect(),
            qs: nd.flux.iter().zip(&speeds).map(|(q, s)| q * s).collect(),
            ws: nd.omega.iter().zip(&speeds).map(|(w, s)| w * s).collect(),
            speeds,
        }
    }
}

/// Work arrays of [`OmegaPairs::half_row`], one entry per node.
struct RowWork {
    dx: Vec<f64>,
    dy: Vec<f64>,
    lnr: Vec<f64>,
    /// the weighted terms of the row's pairs
    terms: Vec<f64>,
    /// the columns the row evaluates
    cols: Vec<usize>,
}

impl RowWork {
    fn new(big: usize) -> RowWork {
        RowWork {
            dx: vec![0.0; big],
            dy: vec![0.0; big],
            lnr: vec![0.0; big],
            terms: vec![0.0; big],
            cols: Vec::with_capacity(big),
        }
    }
}

/// The smooth-part (A) terms of one pair for rows i and j, and the pair's
/// geometry for the B terms.
struct PairTerms {
    psi_i: f64,
    chi_i: f64,
    psi_j: f64,
    chi_j: f64,
    r2: f64,
    dnx: f64,
    dny: f64,
    nn: f64,
}

impl PairTerms {
    /// The coefficients of ln|2 sin π(t − s)| (the B terms, weighted by
    /// Kress's R) of the four kernels: Φ, ∂Φ/∂n_j, ∂Φ/∂n_i, ∂²Φ/∂n_i∂n_j.
    #[inline(always)]
    fn singular(&self) -> [f64; 4] {
        let c8 = 1.0 / (8.0 * PI);
        [
            -self.r2 * c8,
            2.0 * self.dny * c8,
            -2.0 * self.dnx * c8,
            2.0 * self.nn * c8,
        ]
    }
}

impl OmegaPairs {
    /// (ψ, χ) of the pairs (i, j > i) for the rows i in `rows` (both rows'
    /// terms), one vector each over all nodes.
    #[inline(always)]
    fn rows(&self, rows: std::ops::Range<usize>) -> (Vec<f64>, Vec<f64>) {
        let (m, r, sines) = (self.m, &self.r, &self.sines);
        let big = self.arrays.len();
        let h = 1.0 / m as f64;
        let c8 = 1.0 / (8.0 * PI);
        let (qs, ws) = (&self.qs, &self.ws);
        let mut psi = vec![0.0; big];
        let mut chi = vec![0.0; big];
        // per row: the pairs' difference vectors and ln r², and row i's own
        // terms (summed at the end of the row)
        let mut dx = vec![0.0; big];
        let mut dy = vec![0.0; big];
        let mut lnr = vec![0.0; big];
        let mut own_psi = vec![0.0; big];
        let mut own_chi = vec![0.0; big];
        for i in rows {
            // the diagonal limit: only the double-normal kernel survives
            let l = (self.speeds[i] / (2.0 * PI)).max(f64::MIN_POSITIVE).ln();
            let a_dd = -(1.0 - 2.0 * l) * c8;
            let b_dd = 2.0 * c8;
            chi[i] -= h * a_dd * ws[i] + r[0] * b_dd * ws[i];
            let (qi, wi) = (qs[i], ws[i]);
            // x_i − x_j, exact for a shared anchor (the anchors then cancel
            // to 0 exactly, as in `diff`)
            for j in i + 1..big {
                (dx[j], dy[j]) = self.arrays.diff(i, j);
                lnr[j] = (dx[j] * dx[j] + dy[j] * dy[j]).max(f64::MIN_POSITIVE);
            }
            // ln r², all at once (vector instructions); halved below
            crate::logarithm::ln_slice(&mut lnr[i + 1..]);
            // the nodes after i on its curve: A and B (the coefficient of
            // ln|2 sin π(t − s)|, with Kress's weights R((t_i − t_j) mod 1)
            // and R((t_j − t_i) mod 1)); ln r = S + L there
            let end = (i / m + 1) * m;
            for j in i + 1..end {
                let t = self.smooth(i, j, dx[j], dy[j], 0.5 * lnr[j] - sines[j - i]);
                let (qj, wj) = (qs[j], ws[j]);
                let k = j - i;
                let wr_i = self.r_back[k];
                let wr_j = r[k];
                let [b_phi, b_dny, b_dnx, b_dd] = t.singular();
                own_psi[j] = t.psi_i + wr_i * (b_phi * qj - b_dny * wj);
                own_chi[j] = t.chi_i + wr_i * (b_dnx * qj - b_dd * wj);
                psi[j] += t.psi_j + wr_j * (b_phi * qi - b_dnx * wi);
                chi[j] += t.chi_j + wr_j * (b_dny * qi - b_dd * wi);
            }
            // the other curves: A only, L = ln r
            for j in end..big {
                let t = self.smooth(i, j, dx[j], dy[j], 0.5 * lnr[j]);
                own_psi[j] = t.psi_i;
                own_chi[j] = t.chi_i;
                psi[j] += t.psi_j;
                chi[j] += t.chi_j;
            }
            psi[i] += sum_lanes(&own_psi[(i + 1).min(big)..]);
            chi[i] += sum_lanes(&own_chi[(i + 1).min(big)..]);
        }
        (psi, chi)
    }

    /// Row i's share, over h, of the folded ∫ ω² (see
    /// [`omega_squared_integral`]; i in the first `period` nodes of its
    /// curve, k = m/period): Σ over the pairs (i, j) it evaluates of
    /// ω|x′| χ − ∂ω/∂n |x′| ψ for row i and, but for the pairs a half turn
    /// maps onto themselves, for row j. It evaluates, on i's own curve, the
    /// nodes q p + r of every period q with r > i's index ii, and r = ii
    /// for 1 ≤ q ≤ k/2 (the rotations of i itself: q and k − q are one
    /// pair, read from both ends); on the curves after i's, every node.
    #[inline(always)]
    fn half_row(&self, i: usize, period: usize, work: &mut RowWork) -> f64 {
        let (m, r, sines) = (self.m, &self.r, &self.sines);
        let big = self.arrays.len();
        let h = 1.0 / m as f64;
        let c8 = 1.0 / (8.0 * PI);
        let (qs, ws) = (&self.qs, &self.ws);
        let k = m / period;
        let RowWork {
            dx,
            dy,
            lnr,
            terms,
            cols,
        } = work;
        let (start, ii) = ((i / m) * m, i % m);
        cols.clear();
        for q in 0..k {
            let base = start + q * period;
            if q > 0 && 2 * q <= k {
                cols.push(base + ii);
            }
            cols.extend(base + ii + 1..base + period);
        }
        let own = cols.len();
        cols.extend(start + m..big);
        let count = cols.len();
        for (t, &j) in cols.iter().enumerate() {
            (dx[t], dy[t]) = self.arrays.diff(i, j);
            lnr[t] = (dx[t] * dx[t] + dy[t] * dy[t]).max(f64::MIN_POSITIVE);
        }
        crate::logarithm::ln_slice(&mut lnr[..count]);
        let (qi, wi) = (qs[i], ws[i]);
        // i's own curve: A and B, Kress's weights R((t_i − t_j) mod 1) for
        // row i and R((t_j − t_i) mod 1) for row j
        for t in 0..own {
            let j = cols[t];
            let jj = j - start;
            let pair = self.smooth(i, j, dx[t], dy[t], 0.5 * lnr[t] - sines[ii.abs_diff(jj)]);
            let (qj, wj) = (qs[j], ws[j]);
            let wr_i = r[(ii + m - jj) % m];
            let [b_phi, b_dny, b_dnx, b_dd] = pair.singular();
            let psi_i = pair.psi_i + wr_i * (b_phi * qj - b_dny * wj);
            let chi_i = pair.chi_i + wr_i * (b_dnx * qj - b_dd * wj);
            let mut v = wi * chi_i - qi * psi_i;
            // a half turn maps the pair (i, j) onto (j, i): one orbit, one row
            if !(jj % period == ii && 2 * (jj / period) == k) {
                let wr_j = r[(jj + m - ii) % m];
                let psi_j = pair.psi_j + wr_j * (b_phi * qi - b_dnx * wi);
                let chi_j = pair.chi_j + wr_j * (b_dny * qi - b_dd * wi);
                v += wj * chi_j - qj * psi_j;
            }
            terms[t] = v;
        }
        // the curves after i's: A only, L = ln r
        for t in own..count {
            let j = cols[t];
            let pair = self.smooth(i, j, dx[t], dy[t], 0.5 * lnr[t]);
            terms[t] = wi * pair.chi_i - qi * pair.psi_i + ws[j] * pair.chi_j - qs[j] * pair.psi_j;
        }
        // the diagonal limit: only the double-normal kernel survives
        let l = (self.speeds[i] / (2.0 * PI)).max(f64::MIN_POSITIVE).ln();
        let diag_chi = -(h * (-(1.0 - 2.0 * l) * c8) * wi + r[0] * (2.0 * c8) * wi);
        sum_lanes(&terms[..count]) + wi * diag_chi
    }

    /// [`OmegaPairs::half_row`] compiled for AVX2 (the same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn half_row_avx2(&self, i: usize, period: usize, work: &mut RowWork) -> f64 {
        self.half_row(i, period, work)
    }

    /// [`OmegaPairs::rows`] compiled for AVX2 (the same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn rows_avx2(&self, rows: std::ops::Range<usize>) -> (Vec<f64>, Vec<f64>) {
        self.rows(rows)
    }

    /// Σ over the pairs (i ≠ j) of |ω|x′| χ_ij| + |∂ω/∂n |x′| ψ_ij| (row i's
    /// share of each pair, A terms with the whole ln r, h-weighted as the
    /// integral), sampled on every k-th row and column (at most 256 of
    /// each) and scaled up: the size of the terms that cancel to ∫ ω² dA.
    /// An order of magnitude is all it has to be.
    fn magnitude(&self) -> f64 {
        let big = self.arrays.len();
        let stride = big.div_ceil(MAGNITUDE_SAMPLES).max(1);
        let h = 1.0 / self.m as f64;
        let sampled: Vec<usize> = (0..big).step_by(stride).collect();
        let total: f64 = sampled
            .iter()
            .map(|&i| {
                sampled
                    .iter()
                    .filter(|&&j| j != i)
                    .map(|&j| {
                        let (ex, ey) = self.arrays.diff(i, j);
                        let r2 = ex * ex + ey * ey;
                        if r2 > 0.0 {
                            let t = self.smooth(i, j, ex, ey, 0.5 * r2.ln());
                            (self.ws[i] * t.chi_i).abs() + (self.qs[i] * t.psi_i).abs()
                        } else {
                            0.0
                        }
                    })
                    .sum::<f64>()
            })
            .sum();
        let k = sampled.len().max(1) as f64;
        h * total * (big as f64 / k).powi(2)
    }

    /// The A terms of the pair (i, j), d = x_i − x_j = (ex, ey), with the
    /// smooth part l of ln r (row j swaps a_dny and a_dnx).
    #[inline(always)]
    fn smooth(&self, i: usize, j: usize, ex: f64, ey: f64, l: f64) -> PairTerms {
        let c8 = 1.0 / (8.0 * PI);
        let h = 1.0 / self.m as f64;
        let (qi, wi, qj, wj) = (self.qs[i], self.ws[i], self.qs[j], self.ws[j]);
        let (nxi, nyi, nxj, nyj) = (self.nxs[i], self.nys[i], self.nxs[j], self.nys[j]);
        let nn = nxi * nxj + nyi * nyj;
        let r2 = ex * ex + ey * ey;
        // d·n_i and d·n_j (for row j: −d·n_j and −d·n_i)
        let dnx = ex * nxi + ey * nyi;
        let dny = ex * nxj + ey * nyj;
        let cross = if r2 > 0.0 { 2.0 * dnx * dny / r2 } else { 0.0 };
        let a_phi = r2 * (1.0 - l) * c8;
        let a_dny = -(1.0 - 2.0 * l) * dny * c8;
        let a_dnx = (1.0 - 2.0 * l) * dnx * c8;
        let a_dd = (cross - (1.0 - 2.0 * l) * nn) * c8;
        PairTerms {
            psi_i: h * (a_phi * qj - a_dny * wj),
            chi_i: h * (a_dnx * qj - a_dd * wj),
            psi_j: h * (a_phi * qi - a_dnx * wi),
            chi_j: h * (a_dny * qi - a_dd * wi),
            r2,
            dnx,
            dny,
            nn,
        }
    }
}

impl TorsionSolution {
    /// The warping function, shear centre and warping constant from this
    /// solution's densities (see [`crate::warping`]), with quadrature on the
    /// solve's n nodes per curve.
    pub fn warping(&self) -> Warping {
        let m = self.options.n.max(16);
        let x0 = self.centroid;
        let kc = self.curve_count();
        let sec = &self.section;
        let curves = sec.curves();
        // ω̃ per curve and its node values
        let mut tilde: Vec<FourierDensity> = (0..kc)
            .map(|k| {
                let dens = if k == 0 {
                    &self.density
                } else {
                    &self.holes[k - 1].density
                };
                antiderivative(dens)
            })
            .collect();
        let params: Vec<_> = std::iter::once(&self.param)
            .chain(self.holes.iter().map(|h| &h.param))
            .collect();
        let mut pts = Vec::with_capacity(kc * m);
        let mut omega = Vec::with_capacity(kc * m);
        for ((p, c), t) in params.iter().zip(&curves).zip(&tilde) {
            pts.extend(p.nodes(c, m));
            omega.extend(t.sample(m, 0.5));
        }
        let flux: Vec<f64> = pts
            .iter()
            .map(|p| {
                let x = p.x();
                let n = p.normal();
                (x[1] - x0[1]) * n[0] - (x[0] - x0[0]) * n[1]
            })
            .collect();
        let mut nd = Nodes {
            pts,
            omega,
            flux,
            m,
        };
        // constants of the holes relative to the outer curve
        for k in 1..kc {
            let z = point_inside(curves[k]);
            match sec.holes[k - 1].locate(z) {
                PointLocation::Inside => {}
                _ => continue,
            }
            let d = nd.integrate(|x, n, w, q| {
                let dx = [x[0] - z[0], x[1] - z[1]];
                let r2 = dx[0] * dx[0] + dx[1] * dx[1];
                w * (dx[0] * n[0] + dx[1] * n[1]) / r2 - 0.5 * r2.ln() * q
            });
            let ck = d / (2.0 * PI);
            for w in &mut nd.omega[k * m..(k + 1) * m] {
                *w += ck;
            }
            let r0 = tilde[k].max_freq;
            tilde[k].coef[r0] += Complex64::new(ck, 0.0);
        }
        // mean over the area, then normalise
        let area = sec.area;
        let int_w = nd.integrate(|x, n, w, q| {
            let dx = [x[0] - x0[0], x[1] - x0[1]];
            w * 0.5 * (dx[0] * n[0] + dx[1] * n[1]) - 0.25 * (dx[0] * dx[0] + dx[1] * dx[1]) * q
        });
        let mean = int_w / area;
        for w in &mut nd.omega {
            *w -= mean;
        }
        for t in &mut tilde {
            let r0 = t.max_freq;
            t.coef[r0] -= Complex64::new(mean, 0.0);
        }
        let ixw = nd.integrate(|x, n, w, q| {
            let dx = x[0] - x0[0];
            0.5 * w * dx * dx * n[0] - dx.powi(3) / 6.0 * q
        });
        let iyw = nd.integrate(|x, n, w, q| {
            let dy = x[1] - x0[1];
            0.5 * w * dy * dy * n[1] - dy.powi(3) / 6.0 * q
        });
        // the solve's rotational symmetry, where these nodes have it too
        let fold = if self.symmetry_order > 1 {
            let order = crate::symmetry::rotation_order(
                &nd.pts,
                m,
                x0,
                sec.radius(),
                crate::symmetry::relative_tolerance(sec),
            );
            self.symmetry_order.min(order)
        } else {
            1
        };
        let (iww, magnitude) = omega_squared_integral(&nd, fold);
        let factor = if sec.holes.is_empty() {
            GAMMA_ROUND_OFF
        } else {
            GAMMA_ROUND_OFF_HOLES
        };
        let round_off = factor * f64::EPSILON * magnitude;
        let props = sec.properties();
        let delta = props.ixx * props.iyy - props.ixy * props.ixy;
        let xp = (props.ixy * ixw - props.iyy * iyw) / delta;
        let yp = (props.ixx * ixw - props.ixy * iyw) / delta;
        let gamma =
            iww - 2.0 * yp * ixw + 2.0 * xp * iyw + yp * yp * props.iyy + xp * xp * props.ixx
                - 2.0 * xp * yp * props.ixy;
        Warping {
            shear_centre: [x0[0] + xp, x0[1] + yp],
            warping_constant: gamma,
            product_integrals: [ixw, iyw],
            centroidal_constant: iww,
            curves: tilde,
            centroid: x0,
            nodes: m,
            round_off,
        }
    }

    /// ω_n (normalised, about the shear centre) at `m` equally spaced
    /// parameters of every curve.
    pub fn warping_samples(&self, w: &Warping, m: usize) -> Vec<WarpingSample> {
        let curves = self.section.curves();
        let params: Vec<_> = std::iter::once(&self.param)
            .chain(self.holes.iter().map(|h| &h.param))
            .collect();
        let mut out = Vec::new();
        for (k, (c, p)) in curves.iter().zip(params).enumerate() {
            let vals = w.curves[k].sample(m, 0.5);
            for (j, v) in vals.iter().enumerate() {
                let t = (j as f64 + 0.5) / m as f64;
                let x = p.eval(c, t).x();
                let (xp, yp) = (
                    w.shear_centre[0] - w.centroid[0],
                    w.shear_centre[1] - w.centroid[1],
                );
                let omega = v - yp * (x[0] - w.centroid[0]) + xp * (x[1] - w.centroid[1]);
                out.push(WarpingSample {
                    curve: k,
                    t,
                    x,
                    omega,
                });
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::tests::circle;

    /// The folded ∫ ω² (each pair once, for both rows, by the row of the
    /// first period that comes first) equals the whole double sum on node
    /// data with a k-fold symmetry: two concentric circles of 48 nodes,
    /// ω and ∂ω/∂n repeating every 48/k nodes, for k = 2 (pairs a half turn
    /// maps onto themselves), 3 (odd) and 4.
    #[test]
    fn the_folded_pair_sum_equals_the_whole_one() {
        let m = 48;
        for k in [2usize, 3, 4] {
            let p = m / k;
            let mut pts = circle(m, 1.0, [0.0, 0.0]);
            pts.extend(circle(m, 0.4, [0.0, 0.0]));
            let big = pts.len();
            let nd = Nodes {
                omega: (0..big)
                    .map(|i| (0.37 * (i % p) as f64 + 0.1 * (i / m) as f64).sin())
                    .collect(),
                flux: (0..big)
                    .map(|i| (0.21 * (i % p) as f64 - 0.3 * (i / m) as f64).cos())
                    .collect(),
                pts,
                m,
            };
            let whole = omega_squared_integral(&nd, 1).0;
            let folded = omega_squared_integral(&nd, k).0;
            assert!(whole.abs() > 1e-3, "{whole}");
            assert!(
                (whole - folded).abs() < 1e-13 * whole.abs(),
                "k = {k}: {whole} vs {folded}"
            );
        }
    }

    /// The AVX2 copy of the pair loop gives the same bits as the baseline
    /// copy (no fused multiply-adds, no reordering), on two curves.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_avx2_pair_loop_equals_the_baseline_bit_for_bit() {
        if !crate::logarithm::has_avx2() {
            return;
        }
        let m = 40;
        let mut pts = circle(m, 1.0, [0.0, 0.0]);
        pts.extend(circle(m, 0.3, [0.1, -0.05]));
        let big = pts.len();
        let nd = Nodes {
            omega: (0..big).map(|i| (0.37 * i as f64).sin()).collect(),
            flux: (0..big).map(|i| (0.21 * i as f64).cos()).collect(),
            pts,
            m,
        };
        let pairs = OmegaPairs::new(&nd);
        let base = pairs.rows(0..big);
        // SAFETY: the CPU has AVX2 (checked above)
        let avx = unsafe { pairs.rows_avx2(0..big) };
        let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same(&base.0, &avx.0) && same(&base.1, &avx.1));
        assert!(base.0.iter().all(|v| v.is_finite()) && base.0.iter().any(|v| *v != 0.0));
    }
}
