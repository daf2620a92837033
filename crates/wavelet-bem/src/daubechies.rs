//! Periodised Daubechies wavelets: filters by spectral factorisation, the
//! periodised fast wavelet transform, moments, the exact logarithmic
//! integrals a(d) and the Galerkin matrix of ln|2 sin π(t − s)|.
//!
//! Conventions: φ(x) = √2 Σ_k h_k φ(2x − k), Σ h_k = √2, support [0, 2N − 1];
//! c_k = √2 h_k; Φ(y) = ∫ φ(x + y) φ(x) dx (autocorrelation) satisfies
//! Φ(y) = Σ_j p_j Φ(2y − j) with p_j = ½ Σ_k c_k c_{k+j}; M_m = ∫ y^m Φ(y) dy.

use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

/// Daubechies wavelet dbN (N vanishing moments, filter length 2N).
#[derive(Clone, Debug)]
pub struct Daubechies {
    /// N
    pub order: usize,
    /// low-pass filter h_0 … h_{2N−1}
    pub h: Vec<f64>,
    /// high-pass filter g_k = (−1)^k h_{2N−1−k}
    pub g: Vec<f64>,
    /// moments μ_0 … μ_8 of φ (for φ̂ near 0)
    moments_small: Vec<f64>,
}

/// Roots of the complex polynomial Σ a_k z^k (Aberth–Ehrlich iteration, then Newton polish).
fn poly_roots(a: &[Complex64]) -> Vec<Complex64> {
    let deg = a.len() - 1;
    if deg == 0 {
        return vec![];
    }
    let lead = a[deg];
    let eval = |z: Complex64| -> (Complex64, Complex64) {
        let mut p = Complex64::new(0.0, 0.0);
        let mut dp = Complex64::new(0.0, 0.0);
        for k in (0..=deg).rev() {
            dp = dp * z + p;
            p = p * z + a[k];
        }
        (p, dp)
    };
    // initial guesses on a circle of the Cauchy-bound radius
    let r = 1.0
        + a[..deg]
            .iter()
            .map(|c| (c / lead).norm())
            .fold(0.0, f64::max);
    let mut z: Vec<Complex64> = (0..deg)
        .map(|k| Complex64::from_polar(0.5 * r, 2.0 * PI * (k as f64 + 0.25) / deg as f64 + 0.4))
        .collect();
    for _ in 0..500 {
        let mut maxstep: f64 = 0.0;
        for i in 0..deg {
            let (p, dp) = eval(z[i]);
            if p.norm() == 0.0 {
                continue;
            }
            let ratio = p / dp;
            let mut s = Complex64::new(0.0, 0.0);
            for j in 0..deg {
                if j != i {
                    s += Complex64::new(1.0, 0.0) / (z[i] - z[j]);
                }
            }
            let w = ratio / (Complex64::new(1.0, 0.0) - ratio * s);
            z[i] -= w;
            maxstep = maxstep.max(w.norm() / z[i].norm().max(1e-300));
        }
        if maxstep < 1e-17 {
            break;
        }
    }
    for zi in z.iter_mut() {
        for _ in 0..3 {
            let (p, dp) = eval(*zi);
            if dp.norm() > 0.0 {
                *zi -= p / dp;
            }
        }
    }
    z
}

fn binom(n: usize, k: usize) -> f64 {
    let mut r = 1.0;
    for i in 0..k {
        r = r * (n - i) as f64 / (i + 1) as f64;
    }
    r
}

impl Daubechies {
    /// dbN filters for 1 ≤ N ≤ 20 by spectral factorisation of
    /// |m₀(ξ)|² = cos^{2N}(πξ) P(sin²πξ), P(y) = Σ_{k<N} C(N−1+k, k) yᵏ,
    /// keeping the roots inside the unit circle (extremal phase).
    pub fn new(order: usize) -> Option<Daubechies> {
        if !(1..=20).contains(&order) {
            return None;
        }
        let n = order;
        // roots y_k of P
        let pc: Vec<Complex64> = (0..n)
            .map(|k| Complex64::new(binom(n - 1 + k, k), 0.0))
            .collect();
        let ys = poly_roots(&pc);
        // polynomial in z: (1 + z)^N Π (z − z_k)
        let mut poly = vec![Complex64::new(1.0, 0.0)];
        let mul = |poly: &mut Vec<Complex64>, root: Complex64| {
            let mut out = vec![Complex64::new(0.0, 0.0); poly.len() + 1];
            for (k, c) in poly.iter().enumerate() {
                out[k + 1] += c;
                out[k] -= c * root;
            }
            *poly = out;
        };
        for _ in 0..n {
            mul(&mut poly, Complex64::new(-1.0, 0.0));
        }
        for y in ys {
            // z + 1/z = 2 − 4y
            let b = Complex64::new(2.0, 0.0) - 4.0 * y;
            let disc = (b * b - 4.0).sqrt();
            let z1 = 0.5 * (b + disc);
            let z2 = 0.5 * (b - disc);
            let zk = if z1.norm() < 1.0 { z1 } else { z2 };
            mul(&mut poly, zk);
        }
        let sum: f64 = poly.iter().map(|c| c.re).sum();
        let h: Vec<f64> = poly.iter().map(|c| c.re * 2f64.sqrt() / sum).collect();
        let l = h.len();
        let g = (0..l)
            .map(|k| {
                if k % 2 == 0 {
                    h[l - 1 - k]
                } else {
                    -h[l - 1 - k]
                }
            })
            .collect();
        let mut w = Daubechies {
            order,
            h,
            g,
            moments_small: vec![],
        };
        w.moments_small = w.phi_moments(8);
        Some(w)
    }

    /// Parses "db4" etc.
    pub fn from_name(name: &str) -> Option<Daubechies> {
        let n: usize = name.trim().strip_prefix("db")?.parse().ok()?;
        Daubechies::new(n)
    }

    /// Filter length 2N.
    pub fn len(&self) -> usize {
        self.h.len()
    }

    /// Always false (a filter has at least two taps).
    pub fn is_empty(&self) -> bool {
        self.h.is_empty()
    }

    /// Residuals of the defining identities: (|Σh − √2|, max_m |Σ h_k h_{k+2m} − δ_m|,
    /// max_{m<N} |Σ (−1)^k (k/(2N−1))^m h_k|) — the moments in the scaled
    /// variable k/(2N−1) ∈ [0, 1] so that rounding is not amplified by k^m.
    pub fn check(&self) -> (f64, f64, f64) {
        let l = self.h.len();
        let s = (self.h.iter().sum::<f64>() - 2f64.sqrt()).abs();
        let mut orth: f64 = 0.0;
        for m in 0..l / 2 {
            let v: f64 = (0..l - 2 * m).map(|k| self.h[k] * self.h[k + 2 * m]).sum();
            orth = orth.max((v - if m == 0 { 1.0 } else { 0.0 }).abs());
        }
        let mut vm: f64 = 0.0;
        let scale = (l - 1).max(1) as f64;
        for m in 0..self.order {
            let v: f64 = (0..l)
                .map(|k| self.g[k] * (k as f64 / scale).powi(m as i32))
                .sum();
            vm = vm.max(v.abs());
        }
        (s, orth, vm)
    }

    /// m₀(ξ) = (1/√2) Σ h_k e^{−2πikξ} (Horner in z = e^{−2πiξ}).
    pub fn m0(&self, xi: f64) -> Complex64 {
        let z = Complex64::from_polar(1.0, -2.0 * PI * xi.rem_euclid(1.0));
        let mut s = Complex64::new(0.0, 0.0);
        for &hk in self.h.iter().rev() {
            s = s * z + hk;
        }
        s / 2f64.sqrt()
    }

    /// φ̂(ξ) = ∫ φ(x) e^{−2πiξx} dx = Π_{j=1}^{12} m₀(ξ/2ʲ) · φ̂(ξ/2¹²), the last
    /// factor from the moment series φ̂(η) = Σ_m μ_m (−2πiη)^m / m!
    /// (|η| ≤ 2⁻¹² |ξ|: 8 terms reach rounding for |ξ| ≤ 4).
    pub fn phi_hat(&self, xi: f64) -> Complex64 {
        let mut p = Complex64::new(1.0, 0.0);
        let mut x = xi;
        for _ in 0..12 {
            x *= 0.5;
            p *= self.m0(x);
        }
        let mu = &self.moments_small;
        let w = Complex64::new(0.0, -2.0 * PI * x);
        let mut term = Complex64::new(1.0, 0.0);
        let mut tail = Complex64::new(0.0, 0.0);
        for (m, mum) in mu.iter().enumerate() {
            if m > 0 {
                term = term * w / m as f64;
            }
            tail += mum * term;
        }
        p * tail
    }

    /// Autocorrelation coefficients p_j, j = −(2N−1) … 2N−1 (index j + 2N − 1).
    pub fn autocorrelation(&self) -> Vec<f64> {
        let l = self.h.len() as i64;
        (-(l - 1)..l)
            .map(|j| {
                let mut s = 0.0;
                for k in 0..l {
                    let kj = k + j;
                    if (0..l).contains(&kj) {
                        s += 2.0 * self.h[k as usize] * self.h[kj as usize];
                    }
                }
                0.5 * s
            })
            .collect()
    }

    /// Moments μ_m = ∫ x^m φ(x) dx, m = 0..=mmax, from the refinement equation.
    pub fn phi_moments(&self, mmax: usize) -> Vec<f64> {
        let c: Vec<f64> = self.h.iter().map(|v| v * 2f64.sqrt()).collect();
        let mut mu = vec![1.0];
        for m in 1..=mmax {
            let mut s = 0.0;
            for (r, mur) in mu.iter().enumerate() {
                let ck: f64 = c
                    .iter()
                    .enumerate()
                    .map(|(k, ck)| ck * (k as f64).powi((m - r) as i32))
                    .sum();
                s += binom(m, r) * mur * ck;
            }
            let v = s * 0.5f64.powi(m as i32 + 1) / (1.0 - 0.5f64.powi(m as i32));
            mu.push(v);
        }
        mu
    }

    /// Moments M_m = ∫ y^m Φ(y) dy of the autocorrelation, m = 0..=mmax (odd ones vanish).
    pub fn autocorrelation_moments(&self, mmax: usize) -> Vec<f64> {
        let p = self.autocorrelation();
        let off = (p.len() as i64 - 1) / 2;
        let psum = |q: usize| -> f64 {
            p.iter()
                .enumerate()
                .map(|(i, pj)| pj * ((i as i64 - off) as f64).powi(q as i32))
                .sum()
        };
        let ps: Vec<f64> = (0..=mmax).map(psum).collect();
        let mut mm = vec![1.0];
        for m in 1..=mmax {
            if m % 2 == 1 {
                mm.push(0.0);
                continue;
            }
            let mut s = 0.0;
            for r in 0..m {
                s += binom(m, r) * mm[r] * ps[m - r];
            }
            // Φ is interpolating (Φ(k) = δ_k): its moments 1 … 2N − 1 vanish exactly
            mm.push(if m < 2 * self.order {
                0.0
            } else {
                s * 0.5f64.powi(m as i32 + 1) / (1.0 - 0.5f64.powi(m as i32))
            });
        }
        mm
    }

    /// Moment-exact quadrature on the support of φ: nodes x_q = q (q = 0..k−1)
    /// and weights with Σ w_q x_q^m = μ_m for m < k, so that
    /// ∫ φ(x) F(x) dx ≈ Σ w_q F(q) is exact for polynomials of degree < k.
    pub fn moment_rule(&self, k: usize) -> Vec<f64> {
        let mu = self.phi_moments(k);
        // Vandermonde in the centred, scaled variable ξ = (x − c)/s for stability
        let c = 0.5 * (k as f64 - 1.0);
        let s = c.max(1.0);
        // moments of φ in ξ
        let mut m_xi = vec![0.0; k];
        for (m, mx) in m_xi.iter_mut().enumerate() {
            // ∫ ((x − c)/s)^m φ = Σ_r C(m,r) μ_r (−c)^{m−r} / s^m
            let mut acc = 0.0;
            for (r, mur) in mu.iter().enumerate().take(m + 1) {
                acc += binom(m, r) * mur * (-c).powi((m - r) as i32);
            }
            *mx = acc / s.powi(m as i32);
        }
        let v = nalgebra::DMatrix::from_fn(k, k, |m, q| ((q as f64 - c) / s).powi(m as i32));
        let rhs = nalgebra::DVector::from_vec(m_xi);
        match v.lu().solve(&rhs) {
            Some(w) => w.iter().copied().collect(),
            None => vec![f64::NAN; k],
        }
    }

    /// Far-field value a(e) = ln|e| − Σ_k M_{2k} / (2k e^{2k}) for |e| beyond the support.
    /// (M_2 … M_{2N−2} vanish, so the early terms are zero and the loop
    /// only stops on a small term beyond them.)
    fn a_far(&self, e: f64, mm: &[f64]) -> f64 {
        let e = e.abs();
        let mut s = e.ln();
        let inv2 = 1.0 / (e * e);
        let mut pw = inv2;
        for k in 1..mm.len() / 2 {
            let term = mm[2 * k] / (2.0 * k as f64) * pw;
            s -= term;
            if k >= self.order && term.abs() < 1e-19 * s.abs().max(1.0) {
                break;
            }
            pw *= inv2;
        }
        s
    }

    /// a(d) = ∫∫ φ(X) φ(Y) ln|X − Y + d| dX dY for d = 0..=dmax, exactly (to
    /// rounding) from the refinement equation a(d) = ½ Σ_j p_j a(2d + j) − ln 2,
    /// closed by the far-field expansion beyond D = 4(2N − 1) + 4.
    pub fn log_integrals(&self, dmax: usize) -> Vec<f64> {
        let l = self.h.len();
        let big = 4 * (l - 1) + 4;
        let mm = self.autocorrelation_moments(80);
        let p = self.autocorrelation();
        let off = (l - 1) as i64;
        let nd = big + 1;
        let mut a = nalgebra::DMatrix::<f64>::zeros(nd, nd);
        let mut b = nalgebra::DVector::<f64>::from_element(nd, -2f64.ln());
        for d in 0..nd {
            a[(d, d)] += 1.0;
            for (i, pj) in p.iter().enumerate() {
                let e = (2 * d as i64 + i as i64 - off).unsigned_abs() as usize;
                if e <= big {
                    a[(d, e)] -= 0.5 * pj;
                } else {
                    b[d] += 0.5 * pj * self.a_far(e as f64, &mm);
                }
            }
        }
        let sol = a
            .lu()
            .solve(&b)
            .unwrap_or_else(|| nalgebra::DVector::from_element(nd, f64::NAN));
        (0..=dmax)
            .map(|d| {
                if d <= big {
                    sol[d]
                } else {
                    self.a_far(d as f64, &mm)
                }
            })
            .collect()
    }

    /// Smallest n = 2^J for which the periodised log-kernel Galerkin row is
    /// evaluated by a convergent expansion (n ≥ 8(2N − 1), at least 16).
    pub fn min_n(&self) -> usize {
        (8 * (self.h.len() - 1)).max(16).next_power_of_two()
    }

    /// The circulant row C(d) = ∫∫ φ_{J,i}(t) φ_{J,k}(s) ln|2 sin π(t − s)| ds dt,
    /// d = i − k mod n, for periodised scaling functions at level n = 2^J:
    ///
    /// n C(d) = ln 2π − ln n + a(d) + S(d/n) − Σ_{k≥1} M_{2k} Z_{2k}(d/n) / (2k n^{2k}),
    ///
    /// S(x) = ln(sin πx / πx), Z_{2k}(x) = Σ_{m≥1} (m + x)^{−2k} + (m − x)^{−2k}
    /// (Taylor expansion of S over the support of Φ; d taken in (−n/2, n/2]).
    pub fn log_circulant(&self, n: usize) -> Vec<f64> {
        let half = n / 2;
        let a = self.log_integrals(half);
        let mm = self.autocorrelation_moments(80);
        let nf = n as f64;
        // even in d: the entries d = 0..=n/2, in parallel (each on its own)
        let row: Vec<f64> = (0..=half)
            .into_par_iter()
            .map(|d| {
                let x = d as f64 / nf;
                let s = if d == 0 {
                    0.0
                } else {
                    ((PI * x).sin() / (PI * x)).ln()
                };
                let mut corr = 0.0;
                let inv = 1.0 / (nf * nf);
                let mut pw = inv;
                for k in 1..mm.len() / 2 {
                    // the moments below 2N vanish exactly: their terms are 0
                    if mm[2 * k] == 0.0 {
                        pw *= inv;
                        continue;
                    }
                    let term = mm[2 * k] / (2.0 * k as f64) * pw * zeta_pair(2 * k as i32, x);
                    corr += term;
                    if k >= self.order && term.abs() < 1e-19 {
                        break;
                    }
                    pw *= inv;
                }
                ((2.0 * PI).ln() - nf.ln() + a[d] + s - corr) / nf
            })
            .collect();
        (0..n).map(|i| row[i.min(n - i)]).collect()
    }
}

/// Z_p(x) = Σ_{m≥1} (m + x)^{−p} + (m − x)^{−p}, |x| ≤ ½, p ≥ 2 even
/// (direct sum to m = 15, Euler–Maclaurin tail).
pub fn zeta_pair(p: i32, x: f64) -> f64 {
    fn tail(p: i32, y: f64) -> f64 {
        // Σ_{m≥K} (m + y)^{−p}
        const K: f64 = 16.0;
        let b2r = [
            1.0 / 6.0,
            -1.0 / 30.0,
            1.0 / 42.0,
            -1.0 / 30.0,
            5.0 / 66.0,
            -691.0 / 2730.0,
            7.0 / 6.0,
        ];
        let z = K + y;
        let pf = p as f64;
        let mut s = z.powf(1.0 - pf) / (pf - 1.0) + 0.5 * z.powf(-pf);
        // − Σ B_{2r}/(2r)! f^{(2r−1)}(K), f^{(q)} = (−1)^q (p)_q z^{−p−q}
        let mut fact = 1.0; // (2r)!
        for (r, b) in b2r.iter().enumerate() {
            let r1 = r + 1;
            let q = 2 * r1 - 1;
            fact *= (2 * r1 - 1) as f64 * (2 * r1) as f64;
            let mut rising = 1.0;
            for i in 0..q {
                rising *= pf + i as f64;
            }
            let deriv = -rising * z.powf(-pf - q as f64); // (−1)^q with q odd
            s -= b / fact * deriv;
        }
        s
    }
    let mut s = 0.0;
    for m in 1..16 {
        let mf = m as f64;
        s += (mf + x).powi(-p) + (mf - x).powi(-p);
    }
    s + tail(p, x) + tail(p, -x)
}

/// One level of the periodised analysis: (a, d) from the coefficients `x` (even length).
fn analysis_step(x: &[f64], h: &[f64], g: &[f64], out: &mut [f64]) {
    let n = x.len();
    let half = n / 2;
    for i in 0..half {
        let (mut a, mut d) = (0.0, 0.0);
        for k in 0..h.len() {
            let v = x[(2 * i + k) % n];
            a += h[k] * v;
            d += g[k] * v;
        }
        out[i] = a;
        out[half + i] = d;
    }
}

fn synthesis_step(y: &[f64], h: &[f64], g: &[f64], out: &mut [f64]) {
    let n = y.len();
    let half = n / 2;
    out.iter_mut().for_each(|v| *v = 0.0);
    for i in 0..half {
        let (a, d) = (y[i], y[half + i]);
        for k in 0..h.len() {
            out[(2 * i + k) % n] += h[k] * a + g[k] * d;
        }
    }
}

impl Daubechies {
    /// Periodised fast wavelet transform of level-J scaling coefficients
    /// (length n = 2^J) down to 2^{j0} coarse coefficients:
    /// output [a_{j0} | d_{j0} | d_{j0+1} | … | d_{J−1}]. Orthogonal.
    pub fn fwt(&self, x: &mut [f64], j0: usize) {
        let mut len = x.len();
        let mut buf = vec![0.0; len];
        while len > (1 << j0) && len >= 2 {
            analysis_step(&x[..len], &self.h, &self.g, &mut buf[..len]);
            x[..len].copy_from_slice(&buf[..len]);
            len /= 2;
        }
    }

    /// Inverse of [`Daubechies::fwt`].
    pub fn ifwt(&self, x: &mut [f64], j0: usize) {
        let n = x.len();
        let mut len = 1 << j0;
        let mut buf = vec![0.0; n];
        while len < n {
            synthesis_step(&x[..2 * len], &self.h, &self.g, &mut buf[..2 * len]);
            x[..2 * len].copy_from_slice(&buf[..2 * len]);
            len *= 2;
        }
    }

    /// Level of each coefficient in the [`Daubechies::fwt`] layout (coarse scaling block: j0).
    pub fn levels(n: usize, j0: usize) -> Vec<usize> {
        let mut lv = vec![j0; n];
        let mut len = 1 << j0;
        let mut j = j0;
        while len < n {
            for v in lv.iter_mut().take(2 * len).skip(len) {
                *v = j;
            }
            len *= 2;
            j += 1;
        }
        lv
    }
}
