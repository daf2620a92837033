//! Trigonometric representation of the solved density μ(t) = q_v(x(t)) |x′(t)|.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

/// μ(t) = Re Σ_{|r| ≤ R} ĉ_r e^{2πirt}.
#[derive(Clone, Debug)]
pub struct FourierDensity {
    /// coefficients ĉ_r stored at index r + R
    pub coef: Vec<Complex64>,
    /// highest frequency R
    pub max_freq: usize,
}

impl FourierDensity {
    /// From nodal values at t_j = (j + ½)/n: trigonometric interpolant
    /// (Nyquist term split evenly between ±n/2).
    pub fn from_nodes(mu: &[f64]) -> FourierDensity {
        let n = mu.len();
        let mut buf: Vec<Complex64> = mu.iter().map(|&v| Complex64::new(v, 0.0)).collect();
        FftPlanner::new().plan_fft_forward(n).process(&mut buf);
        let r_max = n / 2;
        let mut coef = vec![Complex64::new(0.0, 0.0); 2 * r_max + 1];
        for r in -(r_max as i64)..=(r_max as i64) {
            let k = r.rem_euclid(n as i64) as usize;
            // half shift: t_j = (j + ½)/n → factor e^{−πir/n}
            let ph = Complex64::from_polar(1.0, -PI * r as f64 / n as f64);
            let mut c = buf[k] * ph / n as f64;
            if r.unsigned_abs() as usize == r_max && n.is_multiple_of(2) {
                c *= 0.5;
            }
            coef[(r + r_max as i64) as usize] = c;
        }
        FourierDensity {
            coef,
            max_freq: r_max,
        }
    }

    /// Value at t.
    pub fn eval(&self, t: f64) -> f64 {
        let r_max = self.max_freq as i64;
        let step = Complex64::from_polar(1.0, 2.0 * PI * t);
        // start from e^{−2πiRt} computed directly, then rotate; re-anchor every 64 steps
        let mut s = 0.0;
        let mut z = Complex64::from_polar(1.0, -2.0 * PI * (r_max as f64) * t);
        for (idx, c) in self.coef.iter().enumerate() {
            if idx % 64 == 0 {
                let r = idx as i64 - r_max;
                z = Complex64::from_polar(1.0, 2.0 * PI * ((r as f64 * t).rem_euclid(1.0)));
            }
            s += (c * z).re;
            z *= step;
        }
        s
    }

    /// Values at t_k = (k + shift)/m for k = 0..m (m ≥ 2R + 1), by one FFT.
    pub fn sample(&self, m: usize, shift: f64) -> Vec<f64> {
        let r_max = self.max_freq as i64;
        let mut buf = vec![Complex64::new(0.0, 0.0); m];
        for (idx, c) in self.coef.iter().enumerate() {
            let r = idx as i64 - r_max;
            let ph = Complex64::from_polar(1.0, 2.0 * PI * r as f64 * shift / m as f64);
            buf[r.rem_euclid(m as i64) as usize] += c * ph;
        }
        FftPlanner::new().plan_fft_inverse(m).process(&mut buf);
        buf.iter().map(|v| v.re).collect()
    }

    /// The first m/k of [`FourierDensity::sample`]`(m, shift)`: one period
    /// of a density of period 1/k (every ĉ_r with r not a multiple of k
    /// exactly 0, as for a folded solve), from the m/k-point transform of
    /// the coefficients ĉ_{ks} (μ at t = (j + shift)/m is
    /// Re Σ_s ĉ_{ks} e^{2πi s (j + shift)/(m/k)}); any other density is
    /// sampled whole and cut.
    pub fn sample_period(&self, m: usize, shift: f64, k: usize) -> Vec<f64> {
        let r_max = self.max_freq as i64;
        let periodic = k > 1
            && m.is_multiple_of(k)
            && self.coef.iter().enumerate().all(|(idx, c)| {
                (idx as i64 - r_max) % k as i64 == 0 || (c.re == 0.0 && c.im == 0.0)
            });
        if !periodic {
            let mut all = self.sample(m, shift);
            all.truncate(if m.is_multiple_of(k.max(1)) {
                m / k.max(1)
            } else {
                m
            });
            return all;
        }
        let p = m / k;
        let mut buf = vec![Complex64::new(0.0, 0.0); p];
        for (idx, c) in self.coef.iter().enumerate() {
            let r = idx as i64 - r_max;
            if r % k as i64 != 0 {
                continue;
            }
            let s = r / k as i64;
            let ph = Complex64::from_polar(1.0, 2.0 * PI * s as f64 * shift / p as f64);
            buf[s.rem_euclid(p as i64) as usize] += c * ph;
        }
        FftPlanner::new().plan_fft_inverse(p).process(&mut buf);
        buf.iter().map(|v| v.re).collect()
    }

    /// ∫₀¹ μ dt = ĉ₀.
    pub fn mean(&self) -> f64 {
        self.coef[self.max_freq].re
    }
}
