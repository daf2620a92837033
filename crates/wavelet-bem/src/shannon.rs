//! Harmonic (Shannon) wavelet Galerkin with oversampled quadrature: the
//! spectral method and the independent cross-check.
//!
//! The periodic harmonic wavelets of Newland span, level by level, the
//! octave bands 2^{j−1} ≤ |r| < 2^j of the trigonometric space
//! T_R = span{e^{2πirt} : |r| ≤ R}; the scaling space at level J is T_R itself
//! and every harmonic-wavelet basis of it is a unitary (block-DFT) image of
//! the real Fourier basis {1, √2 cos 2πrt, √2 sin 2πrt}. Galerkin solutions do
//! not depend on the orthonormal basis chosen for the trial/test space, so we
//! assemble in the real Fourier basis, where the log part is exactly diagonal:
//! ln|2 sin π(t − s)| has eigenvalue −1/(2|r|) (0 for r = 0).
//!
//! **Oversampling.** With R = n/2 − 1 (n − 1 unknowns per curve) the smooth
//! double integrals ∫∫ e^{−2πirt} L(t, s) e^{2πiss} dt ds, the load
//! ∫ f e^{−2πirt} dt and the functional are computed by the trapezoidal rule
//! on Q n = [`OVERSAMPLING`] n nodes per curve (a 2-D FFT of the kernel
//! samples), not on the n collocation nodes of the Nyström method: the
//! Galerkin integrals are then resolved beyond the trial band (the aliasing
//! of frequencies above Qn − R into the band is what is left), and the
//! method no longer reduces to the Nyström system in another basis. It is
//! therefore an independent check of the Daubechies and Nyström results.
//! Holes: one real Fourier basis per curve, one multiplier and one
//! constraint ∮ q_v ds = 0 per curve; between curves the full (smooth)
//! kernel ln|x − y|.

use crate::density::FourierDensity;
use crate::error::SolveError;
use crate::geometry::Section;
use crate::grading::{BPoint, Parametrisation, diff};
use crate::kernels;
use crate::linalg::dense_symmetric_solve;
use crate::solve::{Options, RawSolution};
use rayon::prelude::*;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;
use std::f64::consts::{PI, SQRT_2};

/// Quadrature nodes per curve = `OVERSAMPLING` × n.
pub const OVERSAMPLING: usize = 2;

/// Largest n per curve (the transformed kernel is stored densely: at
/// n = 2048 about 0.3 GB).
pub const MAX_N: usize = 2048;

/// Shifted DFT in place: b_r = (1/m) Σ_a h_a e^{−2πir t_a}, t_a = (a + ½)/m, stored at r mod m.
fn dft_shifted(buf: &mut [Complex64], fft: &dyn rustfft::Fft<f64>) {
    let m = buf.len();
    fft.process(buf);
    for (k, b) in buf.iter_mut().enumerate() {
        let r = if k <= m / 2 {
            k as f64
        } else {
            k as f64 - m as f64
        };
        *b *= Complex64::from_polar(1.0 / m as f64, -PI * r / m as f64);
    }
}

/// Basis coefficients: b_α = Σ u e_r; returns [(r, u)] (at most two terms).
fn basis(alpha: usize) -> [(i64, Complex64); 2] {
    if alpha == 0 {
        return [(0, Complex64::new(1.0, 0.0)), (0, Complex64::new(0.0, 0.0))];
    }
    let r = alpha.div_ceil(2) as i64;
    let s = 1.0 / SQRT_2;
    if alpha % 2 == 1 {
        [(r, Complex64::new(s, 0.0)), (-r, Complex64::new(s, 0.0))]
    } else {
        [(r, Complex64::new(0.0, -s)), (-r, Complex64::new(0.0, s))]
    }
}

/// One row of the kernel matrix of [`kernels::log_remainder_blocks`] (m nodes per curve).
fn kernel_row(nodes: &[BPoint], m: usize, sines: &[f64], i: usize, row: &mut [f64]) {
    let xi = &nodes[i];
    for (j, r) in row.iter_mut().enumerate() {
        if i == j {
            *r = (xi.speed() / (2.0 * PI)).max(f64::MIN_POSITIVE).ln();
        } else {
            let d = diff(xi, &nodes[j]);
            let lg = 0.5 * (d[0] * d[0] + d[1] * d[1]).max(f64::MIN_POSITIVE).ln();
            *r = if i / m == j / m {
                lg - sines[(i % m).abs_diff(j % m)]
            } else {
                lg
            };
        }
    }
}

/// The assembled harmonic-wavelet Galerkin system (real Fourier basis per curve, augmented).
pub struct ShannonSystem {
    /// basis functions per curve, n − 1
    pub dim: usize,
    /// number of curves K
    pub curves: usize,
    /// row-major augmented matrix of order K (n − 1) + K
    pub matrix: Vec<f64>,
    /// right-hand side
    pub rhs: Vec<f64>,
    /// basis projections of |x − x₀|² (for J)
    pub functional: Vec<f64>,
}

/// Assembles the augmented harmonic-wavelet Galerkin system with n − 1 basis
/// functions per curve, integrals on [`OVERSAMPLING`] n nodes per curve.
pub fn assemble(
    section: &Section,
    params: &[Parametrisation],
    n: usize,
) -> Result<ShannonSystem, SolveError> {
    if !n.is_multiple_of(2) || n > MAX_N {
        return Err(SolveError::BadN {
            n,
            reason: format!("the Shannon method needs an even n ≤ {MAX_N}"),
        });
    }
    let x0 = section.centroid;
    let curves = section.curves();
    let kc = curves.len();
    let m = OVERSAMPLING * n;
    let nodes: Vec<BPoint> = curves
        .iter()
        .zip(params)
        .flat_map(|(c, p)| p.nodes(c, m))
        .collect();
    let big = kc * m;
    let rr = n / 2 - 1;
    let w = 2 * rr + 1; // kept frequencies −R..R per curve
    let kw = kc * w;
    let f = kernels::rhs_blocks(&nodes, m, x0);
    let g2 = kernels::radius_sq(&nodes, x0);
    let sines: Vec<f64> = (0..m)
        .map(|k| (2.0 * (PI * k as f64 / m as f64).sin()).abs().ln())
        .collect();
    let fwd = FftPlanner::<f64>::new().plan_fft_forward(m);
    let keep = |r: i64| r.rem_euclid(m as i64) as usize;
    // rows: Σ_b L_ab e^{+2πi s t_b}/m = conj(shifted DFT of the row block), L real
    let mut rows = vec![Complex64::new(0.0, 0.0); big * kw];
    rows.par_chunks_mut(kw).enumerate().for_each(|(a, out)| {
        let mut lrow = vec![0.0; big];
        kernel_row(&nodes, m, &sines, a, &mut lrow);
        let mut buf = vec![Complex64::new(0.0, 0.0); m];
        for l in 0..kc {
            for (b, &v) in buf.iter_mut().zip(&lrow[l * m..(l + 1) * m]) {
                *b = Complex64::new(v, 0.0);
            }
            dft_shifted(&mut buf, fwd.as_ref());
            for (si, s) in (-(rr as i64)..=rr as i64).enumerate() {
                out[l * w + si] = buf[keep(s)].conj();
            }
        }
    });
    // columns: hat[(l w + s) kw + k w + r] = Â_kl[r, s]
    let mut hat = vec![Complex64::new(0.0, 0.0); kw * kw];
    hat.par_chunks_mut(kw).enumerate().for_each(|(c, out)| {
        let mut buf = vec![Complex64::new(0.0, 0.0); m];
        for k in 0..kc {
            for (a, b) in buf.iter_mut().enumerate() {
                *b = rows[(k * m + a) * kw + c];
            }
            dft_shifted(&mut buf, fwd.as_ref());
            for (ri, r) in (-(rr as i64)..=rr as i64).enumerate() {
                out[k * w + ri] = buf[keep(r)];
            }
        }
    });
    drop(rows);
    let dim = n - 1;
    let nn = kc * dim + kc;
    let at = |r: i64| (r + rr as i64) as usize;
    let mut mat = vec![0.0; nn * nn];
    mat.par_chunks_mut(nn).enumerate().for_each(|(row_i, row)| {
        if row_i >= kc * dim {
            let k = row_i - kc * dim;
            row[k * dim] = 1.0;
            return;
        }
        let (k, al) = (row_i / dim, row_i % dim);
        let ba = basis(al);
        for (col, v) in row.iter_mut().enumerate().take(kc * dim) {
            let (l, be) = (col / dim, col % dim);
            let bb = basis(be);
            let mut acc = Complex64::new(0.0, 0.0);
            for &(r, ur) in &ba {
                for &(s, us) in &bb {
                    if ur.norm() == 0.0 || us.norm() == 0.0 {
                        continue;
                    }
                    let mut a = hat[(l * w + at(s)) * kw + k * w + at(r)];
                    if k == l && r == s && r != 0 {
                        a += -1.0 / (2.0 * r.abs() as f64);
                    }
                    acc += ur.conj() * us * a;
                }
            }
            *v = -acc.re / (2.0 * PI);
        }
        if al == 0 {
            row[kc * dim + k] = 1.0;
        }
    });
    // load and functional: shifted DFTs of f and g2 per curve on the fine nodes
    let proj = |h: &[f64]| -> Vec<f64> {
        let mut out = Vec::with_capacity(kc * dim);
        for k in 0..kc {
            let mut buf: Vec<Complex64> = h[k * m..(k + 1) * m]
                .iter()
                .map(|&v| Complex64::new(v, 0.0))
                .collect();
            dft_shifted(&mut buf, fwd.as_ref());
            for al in 0..dim {
                out.push(
                    basis(al)
                        .iter()
                        .map(|&(r, u)| (u.conj() * buf[keep(r)]).re)
                        .sum(),
                );
            }
        }
        out
    };
    let mut rhs = proj(&f);
    rhs.resize(nn, 0.0);
    let functional = proj(&g2);
    Ok(ShannonSystem {
        dim,
        curves: kc,
        matrix: mat,
        rhs,
        functional,
    })
}

/// Solves the harmonic-wavelet (spectral) Galerkin system.
pub(crate) fn solve(
    section: &Section,
    params: &[Parametrisation],
    opts: &Options,
) -> Result<RawSolution, SolveError> {
    let n = opts.n;
    let sys = assemble(section, params, n)?;
    let (dim, kc) = (sys.dim, sys.curves);
    let nn = kc * dim + kc;
    let sol = dense_symmetric_solve(nn, &sys.matrix, &sys.rhs)?;
    let j_integral: f64 = (0..kc * dim).map(|i| sol[i] * sys.functional[i]).sum();
    let rmax = n / 2 - 1;
    let densities = (0..kc)
        .map(|k| {
            let mut coef = vec![Complex64::new(0.0, 0.0); 2 * rmax + 1];
            for (al, x) in sol[k * dim..(k + 1) * dim].iter().enumerate() {
                for &(r, u) in &basis(al) {
                    if u.norm() > 0.0 {
                        coef[(r + rmax as i64) as usize] += u * x;
                    }
                }
            }
            FourierDensity {
                coef,
                max_freq: rmax,
            }
        })
        .collect();
    Ok(RawSolution {
        densities,
        multipliers: sol[kc * dim..].to_vec(),
        j_integral,
        compression: None,
        fold: 1,
    })
}
