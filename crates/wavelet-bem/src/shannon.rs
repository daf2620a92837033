//! Harmonic (Shannon) wavelet Galerkin: the spectral method.
//!
//! The periodic harmonic wavelets of Newland span, level by level, the
//! octave bands 2^{j−1} ≤ |r| < 2^j of the trigonometric space
//! T_R = span{e^{2πirt} : |r| ≤ R}; the scaling space at level J is T_R itself
//! and every harmonic-wavelet basis of it is a unitary (block-DFT) image of
//! the real Fourier basis {1, √2 cos 2πrt, √2 sin 2πrt}. Galerkin solutions do
//! not depend on the orthonormal basis chosen for the trial/test space, so we
//! assemble in the real Fourier basis, where the log part is exactly diagonal:
//! ln|2 sin π(t − s)| has eigenvalue −1/(2|r|) (0 for r = 0). The smooth part
//! L is transformed by a 2-D FFT of its samples at the half-shifted nodes.
//! With R = n/2 − 1 there are n − 1 unknowns plus the multiplier.

use crate::density::FourierDensity;
use crate::error::SolveError;
use crate::geometry::Section;
use crate::grading::Parametrisation;
use crate::kernels;
use crate::linalg::dense_symmetric_solve;
use crate::solve::{Options, RawSolution};
use rayon::prelude::*;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;
use std::f64::consts::{PI, SQRT_2};

/// Fourier coefficients ĥ(r) = (1/n) Σ_a h_a e^{−2πir t_a}, t_a = (a + ½)/n, stored at r mod n.
fn dft_shifted(h: &[f64], fft: &dyn rustfft::Fft<f64>) -> Vec<Complex64> {
    let n = h.len();
    let mut buf: Vec<Complex64> = h.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    fft.process(&mut buf);
    for (k, b) in buf.iter_mut().enumerate() {
        let r = if k <= n / 2 {
            k as f64
        } else {
            k as f64 - n as f64
        };
        *b *= Complex64::from_polar(1.0 / n as f64, -PI * r / n as f64);
    }
    buf
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

/// The assembled harmonic-wavelet Galerkin system (real Fourier basis, augmented).
pub struct ShannonSystem {
    /// row-major augmented matrix of order n
    pub matrix: Vec<f64>,
    /// right-hand side
    pub rhs: Vec<f64>,
    /// basis projections of |x − x₀|² (for J)
    pub functional: Vec<f64>,
}

/// Assembles the augmented harmonic-wavelet Galerkin system with n − 1 basis functions.
pub fn assemble(
    section: &Section,
    param: &Parametrisation,
    n: usize,
) -> Result<ShannonSystem, SolveError> {
    if !n.is_multiple_of(2) {
        return Err(SolveError::BadN {
            n,
            reason: "the Shannon method needs an even n".into(),
        });
    }
    let x0 = section.centroid;
    let nodes = param.nodes(section, n);
    let l = kernels::log_remainder(&nodes);
    let f = kernels::rhs(&nodes, x0);
    let g2 = kernels::radius_sq(&nodes, x0);
    // 2-D transform Â[r, s] = (1/n²) Σ_ab e^{−2πi r t_a} L_ab e^{+2πi s t_b}:
    // rows: conj of the forward transform of each row (L real ⇒ Σ_b L_ab e^{+…} = conj(dft)).
    let fwd = FftPlanner::<f64>::new().plan_fft_forward(n);
    // rows: Σ_b L_ab e^{+2πi s t_b} = conj(dft of row a), L real
    let mut rows = vec![Complex64::new(0.0, 0.0); n * n];
    rows.par_chunks_mut(n).enumerate().for_each(|(a, out)| {
        let r = dft_shifted(&l[a * n..(a + 1) * n], fwd.as_ref());
        for (o, v) in out.iter_mut().zip(&r) {
            *o = v.conj();
        }
    });
    // columns: after a transpose, row s holds (Σ_b …)_a; its shifted DFT over a gives Â[r, s]
    let mut cols = kernels::transpose(&rows, n);
    drop(rows);
    cols.par_chunks_mut(n).for_each(|c| {
        fwd.process(c);
        for (k, b) in c.iter_mut().enumerate() {
            let r = if k <= n / 2 {
                k as f64
            } else {
                k as f64 - n as f64
            };
            *b *= Complex64::from_polar(1.0 / n as f64, -PI * r / n as f64);
        }
    });
    // cols[s n + r] = Â[r, s]; L symmetric ⇒ Â[r, s] = conj(Â[s, r]) = conj(cols[r n + s]): rows read contiguously
    let idx = |r: i64| r.rem_euclid(n as i64) as usize;
    let dim = n - 1;
    let nn = dim + 1;
    let mut m = vec![0.0; nn * nn];
    m.par_chunks_mut(nn).enumerate().for_each(|(al, row)| {
        if al == dim {
            row[0] = 1.0;
            return;
        }
        let ba = basis(al);
        for (be, v) in row.iter_mut().enumerate().take(dim) {
            let bb = basis(be);
            let mut acc = Complex64::new(0.0, 0.0);
            for &(r, ur) in &ba {
                for &(s, us) in &bb {
                    if ur.norm() == 0.0 || us.norm() == 0.0 {
                        continue;
                    }
                    let mut a = cols[idx(r) * n + idx(s)].conj();
                    if r == s && r != 0 {
                        a += -1.0 / (2.0 * r.abs() as f64);
                    }
                    acc += ur.conj() * us * a;
                }
            }
            *v = -acc.re / (2.0 * PI);
        }
        if al == 0 {
            row[dim] = 1.0;
        }
    });
    let fh = dft_shifted(&f, fwd.as_ref());
    let gh = dft_shifted(&g2, fwd.as_ref());
    let proj = |h: &[Complex64], al: usize| -> f64 {
        basis(al)
            .iter()
            .map(|&(r, u)| (u.conj() * h[idx(r)]).re)
            .sum()
    };
    let mut rhs: Vec<f64> = (0..dim).map(|al| proj(&fh, al)).collect();
    rhs.push(0.0);
    let functional = (0..dim).map(|al| proj(&gh, al)).collect();
    Ok(ShannonSystem {
        matrix: m,
        rhs,
        functional,
    })
}

/// Solves the harmonic-wavelet (spectral) Galerkin system.
pub(crate) fn solve(
    section: &Section,
    param: &Parametrisation,
    opts: &Options,
) -> Result<RawSolution, SolveError> {
    if !section.holes.is_empty() {
        return Err(SolveError::Unsupported(
            "the Shannon method handles simply connected sections only (use daubechies or nystrom)"
                .into(),
        ));
    }
    let n = opts.n;
    let sys = assemble(section, param, n)?;
    let dim = n - 1;
    let sol = dense_symmetric_solve(n, &sys.matrix, &sys.rhs)?;
    let j_integral: f64 = (0..dim).map(|al| sol[al] * sys.functional[al]).sum();
    let rmax = n / 2 - 1;
    let mut coef = vec![Complex64::new(0.0, 0.0); 2 * rmax + 1];
    for (al, x) in sol.iter().enumerate().take(dim) {
        for &(r, u) in &basis(al) {
            if u.norm() > 0.0 {
                coef[(r + rmax as i64) as usize] += u * x;
            }
        }
    }
    Ok(RawSolution {
        densities: vec![FourierDensity {
            coef,
            max_freq: rmax,
        }],
        multipliers: vec![sol[dim]],
        j_integral,
        compression: None,
    })
}
