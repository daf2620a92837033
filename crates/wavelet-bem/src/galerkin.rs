//! Periodised Daubechies wavelet Galerkin discretisation (the default solver).
//!
//! Trial and test space V_J = span{φ_{J,k}}, n = 2^J, μ = Σ α_k φ_{J,k}.
//! The Galerkin matrix of V = −(1/2π) ln|x(t) − x(s)| is split as
//!
//! ```text
//! A = −(1/2π) [ C + P L Pᵀ ],
//! ```
//!
//! * C: the circulant Galerkin matrix of ln|2 sin π(t − s)|, exact from the
//!   refinement-equation integrals a(d) ([`Daubechies::log_circulant`]);
//! * L: the smooth remainder sampled at the half-shifted nodes, P the exact
//!   Galerkin projection of the trigonometric interpolant on those nodes:
//!   P[i, a] = p(i − a), p(d) = (2^{−J/2}/n) Σ′_{|r|≤n/2} φ̂(−r/n) e^{2πir(d − ½)/n}
//!   (spectrally accurate for smooth L, no singular quadrature anywhere).
//!
//! The right-hand side is F = P f, the constraint row e_k = ∫ φ_{J,k} = 2^{−J/2},
//! and J uses ∫ g2 μ = αᵀ P g2. The solution is mapped to a trigonometric
//! density by μ̂(r) = 2^{−J/2} φ̂(r/n) α̂(r) for |r| ≤ 3n/8 (the Galerkin
//! functionals ⟨μ, e^{2πirt}⟩ are superconvergent for low r; the top of the
//! band, where φ̂ decays, is left out).

use crate::daubechies::Daubechies;
use crate::density::FourierDensity;
use crate::error::SolveError;
use crate::geometry::Section;
use crate::grading::Parametrisation;
use crate::kernels;
use crate::linalg::{projected_pcg, shifted_saddle_solve, threshold};
use crate::solve::{CompressionReport, LinearSolver, Options, RawSolution};
use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::PI;
use std::sync::Arc;

/// The assembled Daubechies Galerkin system in the scaling basis: K boundary
/// curves with n = 2^J scaling functions each (order N = K n), curve after curve.
pub struct GalerkinSystem {
    /// scaling functions per curve
    pub n: usize,
    /// the order k of the rotational symmetry the system is folded by
    /// ([`crate::symmetry`]; 1: not folded) and its period m = n/k: the
    /// matrix is of order K m and the vectors hold the first m entries of
    /// each curve
    pub fold: usize,
    pub period: usize,
    /// number of curves K
    pub curves: usize,
    /// row-major symmetric N×N matrix A
    pub matrix: Vec<f64>,
    /// an N×N work array left from the assembly (its pages are touched:
    /// the solve keeps its copy of the matrix there instead of allocating)
    pub spare: Vec<f64>,
    /// load vector F = P f
    pub load: Vec<f64>,
    /// constraint vector e (∫ φ_{J,k}) of one curve
    pub constraint: Vec<f64>,
    /// functional vector P g2 (∫ φ_{J,k} |x − x₀|²)
    pub functional: Vec<f64>,
    /// the wavelet
    pub wavelet: Daubechies,
}

/// The projection kernel p(d), d = 0..n.
pub fn projection_kernel(w: &Daubechies, n: usize) -> Vec<f64> {
    projection_kernel_folded(w, n, 1)
}

/// The folded projection kernel p_f(d) = Σ_q p(d + q m), d = 0..m, m = n/k
/// (see [`crate::symmetry::fold_kernel`]), from the m + 1 frequencies of p
/// that are multiples of k: p(d) = (1/n) Σ_r ĉ_r e^{2πi r d/n} and
/// Σ_q e^{2πi r q/k} = k when k divides r, 0 otherwise, so
/// p_f(d) = (1/m) Σ_s ĉ_{ks} e^{2πi s d/m}. The kernel of a 2000-gon folded
/// to one edge takes 65 frequencies instead of 128 001.
pub fn projection_kernel_folded(w: &Daubechies, n: usize, k: usize) -> Vec<f64> {
    let m = n / k;
    let nf = n as f64;
    let s = 1.0 / nf.sqrt();
    let mut buf = vec![Complex64::new(0.0, 0.0); m];
    let half = (n / 2) as i64;
    let k = k as i64;
    let top = half / k;
    for r in (-top..=top).map(|q| q * k) {
        let mut c =
            s * w.phi_hat(-(r as f64) / nf) * Complex64::from_polar(1.0, -PI * r as f64 / nf);
        if r.abs() == half {
            c *= 0.5;
        }
        buf[(r / k).rem_euclid(m as i64) as usize] += c;
    }
    FftPlanner::new().plan_fft_inverse(m).process(&mut buf);
    buf.iter().map(|v| v.re / m as f64).collect()
}

/// Cyclic convolution with the real kernel p of every length-n block of two
/// real rows at once: they are packed as the real and imaginary parts of one
/// complex FFT (p real, so the convolution keeps them apart). `phat_n` is
/// the FFT of p divided by n (the inverse FFT's scaling).
fn convolve_pair(
    r0: &mut [f64],
    r1: &mut [f64],
    phat_n: &[Complex64],
    fft: &(Arc<dyn Fft<f64>>, Arc<dyn Fft<f64>>),
    buf: &mut [Complex64],
    scratch: &mut [Complex64],
) {
    let n = phat_n.len();
    for (b0, b1) in r0.chunks_mut(n).zip(r1.chunks_mut(n)) {
        for ((z, &x), &y) in buf.iter_mut().zip(b0.iter()).zip(b1.iter()) {
            *z = Complex64::new(x, y);
        }
        fft.0.process_with_scratch(buf, scratch);
        for (z, ph) in buf.iter_mut().zip(phat_n) {
            *z *= ph;
        }
        fft.1.process_with_scratch(buf, scratch);
        for ((z, x), y) in buf.iter().zip(b0.iter_mut()).zip(b1.iter_mut()) {
            *x = z.re;
            *y = z.im;
        }
    }
}

/// Rows gathered and convolved per task: 8 doubles fill a cache line, so
/// a gathered column segment uses every byte it loads.
const TILE: usize = 8;

/// Writes into the rows of the row-major N × N matrix `dst` the columns of
/// `src`, cyclically convolved block by block with p (see
/// [`convolve_pair`]; N even), then applies `finish(i, row)` to each row i
/// while it is still in cache. Row i of `dst` is gathered from column i of
/// `src` above row `upper_from(i)` and from row i of `src` from column
/// `upper_from(i)` on: with `upper_from(i) = i` the rows of a symmetric
/// matrix of which `src` holds the upper triangle, with `upper_from(i) = N`
/// the rows of `srcᵀ` (a transpose fused with the convolution). Tiles are
/// fixed, so the result does not depend on the number of threads.
fn convolve_gathered(
    src: &[f64],
    dst: &mut [f64],
    big: usize,
    phat_n: &[Complex64],
    upper_from: impl Fn(usize) -> usize + Sync,
    finish: impl Fn(usize, &mut [f64]) + Sync,
) {
    let n = phat_n.len();
    let mut planner = FftPlanner::<f64>::new();
    let fft = (planner.plan_fft_forward(n), planner.plan_fft_inverse(n));
    let len = fft
        .0
        .get_inplace_scratch_len()
        .max(fft.1.get_inplace_scratch_len());
    let zero = Complex64::new(0.0, 0.0);
    dst.par_chunks_mut(TILE * big).enumerate().for_each_init(
        || (vec![zero; n], vec![zero; len]),
        |(buf, scratch), (k, tile)| {
            let i0 = k * TILE;
            let rows = tile.len() / big;
            let from: Vec<usize> = (0..rows).map(|r| upper_from(i0 + r).min(big)).collect();
            let lower = from.iter().copied().max().unwrap_or(0);
            // column parts: one cache line of src per j for the whole tile
            for j in 0..lower {
                let line = &src[j * big + i0..j * big + i0 + rows];
                for (r, &v) in line.iter().enumerate() {
                    if j < from[r] {
                        tile[r * big + j] = v;
                    }
                }
            }
            // row parts
            for (r, &f) in from.iter().enumerate() {
                let i = i0 + r;
                tile[r * big + f..(r + 1) * big].copy_from_slice(&src[i * big + f..(i + 1) * big]);
            }
            for (q, pair) in tile.chunks_mut(2 * big).enumerate() {
                let (r0, r1) = pair.split_at_mut(big);
                convolve_pair(r0, r1, phat_n, &fft, buf, scratch);
                finish(i0 + 2 * q, r0);
                finish(i0 + 2 * q + 1, r1);
            }
        },
    );
}

/// Block-wise [`convolve`] of a vector of K blocks of length n.
fn convolve_blocks(v: &[f64], n: usize, phat: &[Complex64]) -> Vec<f64> {
    v.chunks(n).flat_map(|b| convolve(b, phat)).collect()
}

/// (P v)_i = Σ_a p(i − a) v_a by FFT.
fn convolve(v: &[f64], phat: &[Complex64]) -> Vec<f64> {
    let n = v.len();
    let mut buf: Vec<Complex64> = v.iter().map(|&x| Complex64::new(x, 0.0)).collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);
    for (b, ph) in buf.iter_mut().zip(phat) {
        *b *= ph;
    }
    FftPlanner::new().plan_fft_inverse(n).process(&mut buf);
    buf.iter().map(|z| z.re / n as f64).collect()
}

/// Assembles the Daubechies Galerkin system for the curves of `section`
/// (outer boundary, then holes) with their parametrisations `params`.
pub fn assemble(
    section: &Section,
    params: &[Parametrisation],
    n: usize,
    w: Daubechies,
) -> Result<GalerkinSystem, SolveError> {
    assemble_with(section, params, n, w, 1)
}

/// [`assemble`], folded by a rotational symmetry of order `fold` (1: not
/// folded) that the nodes must have ([`crate::symmetry::rotation_order`]
/// at least `fold`; checked, an error otherwise).
pub fn assemble_with(
    section: &Section,
    params: &[Parametrisation],
    n: usize,
    w: Daubechies,
    fold: usize,
) -> Result<GalerkinSystem, SolveError> {
    if !n.is_multiple_of(2) || n < w.min_n() {
        return Err(SolveError::BadN {
            n,
            reason: format!("db{} needs an even n ≥ {}", w.order, w.min_n()),
        });
    }
    let x0 = section.centroid;
    let curves = section.curves();
    let nodes: Vec<_> = curves
        .iter()
        .zip(params)
        .flat_map(|(c, p)| p.nodes(c, n))
        .collect();
    let big = nodes.len();
    let g2 = kernels::radius_sq(&nodes, x0);
    if fold > 1 {
        let order = crate::symmetry::rotation_order(
            &nodes,
            n,
            x0,
            section.radius(),
            crate::symmetry::relative_tolerance(section),
        );
        if !(n.is_multiple_of(fold) && order.is_multiple_of(fold)) {
            return Err(SolveError::BadN {
                n,
                reason: format!(
                    "the nodes have a rotational symmetry of order {order}, not {fold}"
                ),
            });
        }
        let pf = projection_kernel_folded(&w, n, fold);
        return Ok(assemble_folded(&nodes, n, fold, &pf, &g2, x0, w));
    }
    let p = projection_kernel(&w, n);
    let mut phat: Vec<Complex64> = p.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut phat);
    let phat_n: Vec<Complex64> = phat.iter().map(|z| z / n as f64).collect();
    // L (symmetric, one logarithm per pair: its upper triangle), the rows
    // of M = L Pᵀ, then the rows of A from the columns of M (P L Pᵀ = P M):
    // peak memory 2 N² doubles, and the second array is kept for the solve
    let (upper, f) = kernels::log_remainder_upper(&nodes, n, x0);
    let mut m = crate::linalg::dense_zeroed(big * big);
    convolve_gathered(&upper, &mut m, big, &phat_n, |i| i, |_, _| {});
    let mut a = upper;
    let c = w.log_circulant(n);
    // A = −(C + P L Pᵀ)/2π (symmetric up to rounding; L is symmetric); C on diagonal blocks
    let s = -1.0 / (2.0 * PI);
    convolve_gathered(
        &m,
        &mut a,
        big,
        &phat_n,
        |_| big,
        |i, row| {
            // C[ii, k] = c[(ii − k) mod n] on the diagonal block, split
            // where the index wraps (no division per entry)
            let (bi, ii) = (i / n, i % n);
            let (before, after) = row[bi * n..(bi + 1) * n].split_at_mut(ii + 1);
            for (v, &ck) in before.iter_mut().zip(c[..=ii].iter().rev()) {
                *v += ck;
            }
            for (v, &ck) in after.iter_mut().zip(c[ii + 1..].iter().rev()) {
                *v += ck;
            }
            for v in row.iter_mut() {
                *v *= s;
            }
        },
    );
    let load = convolve_blocks(&f, n, &phat);
    let functional = convolve_blocks(&g2, n, &phat);
    let constraint = vec![1.0 / (n as f64).sqrt(); n];
    Ok(GalerkinSystem {
        n,
        fold: 1,
        period: n,
        curves: curves.len(),
        matrix: a,
        spare: m,
        load,
        constraint,
        functional,
        wavelet: w,
    })
}

/// The system folded by a rotational symmetry of order `k` of the `nodes`
/// (n per curve), from the folded projection kernel `pf`
/// ([`projection_kernel_folded`]) and |x − x₀|² at the nodes (`g2`): see
/// [`crate::symmetry`].
fn assemble_folded(
    nodes: &[crate::grading::BPoint],
    n: usize,
    k: usize,
    pf: &[f64],
    g2: &[f64],
    x0: crate::geometry::V2,
    w: Daubechies,
) -> GalerkinSystem {
    use crate::symmetry::{first_periods, fold_kernel};
    let m = n / k;
    let curves = nodes.len() / n;
    let small = curves * m;
    let mut phat: Vec<Complex64> = pf.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    FftPlanner::new().plan_fft_forward(m).process(&mut phat);
    let phat_m: Vec<Complex64> = phat.iter().map(|z| z / m as f64).collect();
    let (folded, f) = kernels::log_remainder_folded(nodes, n, m, x0);
    let mut rows = vec![0.0; small * small];
    convolve_gathered(&folded, &mut rows, small, &phat_m, |i| i, |_, _| {});
    let mut a = folded;
    let c = fold_kernel(&w.log_circulant(n), m);
    let s = -1.0 / (2.0 * PI);
    convolve_gathered(
        &rows,
        &mut a,
        small,
        &phat_m,
        |_| small,
        |i, row| {
            let (bi, ii) = (i / m, i % m);
            for (j, v) in row[bi * m..(bi + 1) * m].iter_mut().enumerate() {
                *v += c[(ii + m - j) % m];
            }
            for v in row.iter_mut() {
                *v *= s;
            }
        },
    );
    let load = convolve_blocks(&f, m, &phat);
    let functional = convolve_blocks(&first_periods(g2, n, m), m, &phat);
    GalerkinSystem {
        n,
        fold: k,
        period: m,
        curves,
        matrix: a,
        spare: rows,
        load,
        constraint: vec![1.0 / (n as f64).sqrt(); m],
        functional,
        wavelet: w,
    }
}

/// Wavelet-basis matrix W A Wᵀ (row transforms, transpose, row transforms).
pub fn to_wavelet_basis(sys: &GalerkinSystem, j0: usize) -> Vec<f64> {
    let n = sys.n;
    let tr = |m: &[f64]| -> Vec<f64> {
        let mut rows = m.to_vec();
        rows.par_chunks_mut(n).for_each(|r| sys.wavelet.fwt(r, j0));
        kernels::transpose(&rows, n)
    };
    tr(&tr(&sys.matrix))
}

/// Coarsest level used by the wavelet transform: 2^{j0} ≥ 2 × filter length.
pub fn coarse_level(w: &Daubechies) -> usize {
    let mut j0 = 1;
    while (1usize << j0) < 2 * w.len() {
        j0 += 1;
    }
    j0
}

/// ‖A − B‖₂ / ‖A‖₂ for symmetric A (dense) and B (CSR), by power iteration.
fn operator_error(n: usize, a: &[f64], b: &crate::linalg::Csr) -> f64 {
    let norm = |apply: &dyn Fn(&[f64], &mut [f64])| -> f64 {
        let mut x: Vec<f64> = (0..n)
            .map(|i| 1.0 + 0.37 * ((i * 7919) % 101) as f64 / 101.0)
            .collect();
        let mut y = vec![0.0; n];
        let mut lam = 0.0;
        for _ in 0..30 {
            let nx = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            x.iter_mut().for_each(|v| *v /= nx);
            apply(&x, &mut y);
            lam = y.iter().map(|v| v * v).sum::<f64>().sqrt();
            std::mem::swap(&mut x, &mut y);
        }
        lam
    };
    let dense = |x: &[f64], y: &mut [f64]| {
        y.par_iter_mut()
            .enumerate()
            .for_each(|(i, yi)| *yi = (0..n).map(|j| a[i * n + j] * x[j]).sum());
    };
    let diff = |x: &[f64], y: &mut [f64]| {
        dense(x, y);
        let mut by = vec![0.0; n];
        b.matvec(x, &mut by);
        y.iter_mut().zip(&by).for_each(|(v, w)| *v -= w);
    };
    norm(&diff) / norm(&dense)
}

/// Solves with the options' linear solver and returns the raw solution.
pub(crate) fn solve(
    section: &Section,
    params: &[Parametrisation],
    opts: &Options,
    fold: usize,
) -> Result<RawSolution, SolveError> {
    let w = Daubechies::new(opts.wavelet_order)
        .ok_or_else(|| SolveError::BadWavelet(format!("db{}", opts.wavelet_order)))?;
    let n = opts.n;
    let mut sys = assemble_with(section, params, n, w, fold)?;
    let kc = sys.curves;
    let (alpha, c, compression) = match opts.linear {
        LinearSolver::Dense => {
            // the shifted matrix (kernel −(1/2π) ln(|x − y|/ρ), ρ = 4 × the largest
            // distance of Γ from the centroid ≥ 4 × capacity): Cholesky on smooth
            // boundaries, LU on boundaries with corners
            let kappa = (4.0 * section.radius()).ln() / (2.0 * PI);
            let mut matrix = std::mem::take(&mut sys.matrix);
            let mut spare = std::mem::take(&mut sys.spare);
            // graded corners can leave the discrete matrix slightly indefinite: LU there
            let smooth = section.curves().iter().all(|c| !c.any_graded());
            // folded: the shift term of the periodic vector is k times its period's
            let (x, c) = shifted_saddle_solve(
                &mut matrix,
                &mut spare,
                sys.period,
                &sys.constraint,
                &sys.load,
                kappa * sys.fold as f64,
                smooth,
            )?;
            (x, c, None)
        }
        LinearSolver::Compressed { eps, tol } => {
            if kc > 1 {
                return Err(SolveError::Unsupported(
                    "the compressed solver handles simply connected sections only".into(),
                ));
            }
            let j0 = coarse_level(&sys.wavelet);
            let aw = to_wavelet_basis(&sys, j0);
            let csr = threshold(n, &aw, eps);
            let op_err = operator_error(n, &aw, &csr);
            let mut e = sys.constraint.clone();
            sys.wavelet.fwt(&mut e, j0);
            let mut fw = sys.load.clone();
            sys.wavelet.fwt(&mut fw, j0);
            let d: Vec<f64> = (0..n)
                .map(|i| aw[i * n + i].abs().max(f64::MIN_POSITIVE))
                .collect();
            let (xw, c, iters, res) = projected_pcg(&csr, &e, &fw, &d, tol, 10 * n)?;
            let mut alpha = xw;
            sys.wavelet.ifwt(&mut alpha, j0);
            let rep = CompressionReport {
                eps,
                entries_per_row: csr.nnz() as f64 / n as f64,
                operator_error: op_err,
                iterations: iters,
                residual: res,
            };
            (alpha, vec![c], Some(rep))
        }
    };
    // a folded solution's functional: k times its period's
    let j_integral: f64 = sys.fold as f64
        * alpha
            .iter()
            .zip(&sys.functional)
            .map(|(a, b)| a * b)
            .sum::<f64>();
    // density per curve: μ̂(r) = 2^{−J/2} φ̂(r/n) α̂(r), |r| ≤ 3n/8. A
    // folded solution's α repeats its period of m = n/k: α̂(r) is k times
    // the period's transform at r/k when k divides r, and exactly 0
    // otherwise (the transform of length m, and φ̂ at those r only)
    let (k, m) = (sys.fold.max(1), sys.period);
    let rmax = 3 * n / 8;
    let s = 1.0 / (n as f64).sqrt();
    let densities = alpha
        .chunks(m)
        .map(|blk| {
            let mut ah: Vec<Complex64> = blk.iter().map(|&v| Complex64::new(v, 0.0)).collect();
            FftPlanner::new().plan_fft_forward(m).process(&mut ah);
            let coef: Vec<Complex64> = (-(rmax as i64)..=rmax as i64)
                .map(|r| {
                    if r % k as i64 != 0 {
                        return Complex64::new(0.0, 0.0);
                    }
                    s * sys.wavelet.phi_hat(r as f64 / n as f64)
                        * (k as f64 * ah[(r / k as i64).rem_euclid(m as i64) as usize])
                })
                .collect();
            FourierDensity {
                coef,
                max_freq: rmax,
            }
        })
        .collect();
    Ok(RawSolution {
        densities,
        multipliers: c,
        j_integral,
        compression,
        fold: sys.fold,
    })
}
