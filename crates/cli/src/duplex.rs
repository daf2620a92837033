//! The steady duplex tube: one-dimensional solution of two concentric tubes
//! in contact, heat flowing radially through a pressure-dependent joint
//! conductance (it couples heat conduction and elasticity, so it lives in
//! the command layer rather than in `tecon-thermal` or `tecon-elastic`).
//!
//! ```text
//!   r = a ── inner tube ── r = c (joint, h(p)) ── outer tube ── r = b
//!   T(a) = T_a                                                T(b) = T_b
//! ```
//!
//! For a given conductance h the temperatures are logarithmic in each tube,
//! `T = A + B ln r`, with one heat rate per unit length
//! `Q = (T_a − T_b) / (R₁ + R_c + R₂)`, `R₁ = ln(c/a)/(2πk₁)`,
//! `R_c = 1/(2πc h)`, `R₂ = ln(b/c)/(2πk₂)` and the jump `T₁(c) − T₂(c) = Q R_c`.
//! In plane strain with ΔT = T − T_ref and `β = (1+ν)α/(1−ν)`:
//!
//! ```text
//!   u(r)  = β I(r)/r + C₁ r + C₂/r,       I(r) = ∫_{r₀}^{r} ΔT s ds
//!   σ_rr = 2(λ+μ) C₁ − 2μ β I(r)/r² − 2μ C₂/r²
//! ```
//!
//! (r₀ the tube's inner radius). Free surfaces σ_rr(a) = σ_rr(b) = 0, the
//! joint σ_rr(c) = −p on both sides and closed, `u₂(c) − u₁(c) = δ` (δ the
//! radial interference, the inner tube oversize), give five linear
//! equations for C₁, C₂ of each tube and p: the contact pressure g(h) for a
//! given conductance. With h = h(p) the steady state is a scalar fixed
//! point p = g(h(p)). A fixed point is stable under the thermal transient
//! when the map's slope g'(p) < 1 (a small pressure rise returns).

use std::f64::consts::PI;

use nalgebra::{Matrix5, Vector5};

/// Data of the duplex tube (SI units, temperatures in °C).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DuplexTube {
    /// Inner radius a.
    pub a: f64,
    /// Joint radius c.
    pub c: f64,
    /// Outer radius b.
    pub b: f64,
    /// Conductivities k₁, k₂.
    pub conductivity: [f64; 2],
    /// Young's moduli E₁, E₂.
    pub youngs_modulus: [f64; 2],
    /// Poisson's ratios ν₁, ν₂.
    pub poisson_ratio: [f64; 2],
    /// Expansion coefficients α₁, α₂.
    pub expansion: [f64; 2],
    /// Prescribed temperature of the bore, T_a.
    pub t_inner: f64,
    /// Prescribed temperature of the outside, T_b.
    pub t_outer: f64,
    /// Stress-free temperature T_ref.
    pub t_ref: f64,
    /// Radial interference δ (m): inner tube oversize at T_ref.
    pub interference: f64,
}

/// The state for one conductance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DuplexState {
    /// Contact pressure p (Pa); negative: the joint would open.
    pub pressure: f64,
    /// Temperature of the inner tube at the joint, T₁(c).
    pub t_joint_inner: f64,
    /// Temperature of the outer tube at the joint, T₂(c).
    pub t_joint_outer: f64,
    /// Heat rate from inside out per unit length, W/m.
    pub heat_rate: f64,
}

/// A steady state of the coupled problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyState {
    /// The state.
    pub state: DuplexState,
    /// Conductance h(p).
    pub conductance: f64,
    /// Slope g'(p) of the fixed-point map.
    pub slope: f64,
    /// Stable: g'(p) < 1.
    pub stable: bool,
}

impl DuplexTube {
    /// The temperatures and the contact pressure for a conductance `h`.
    pub fn at(&self, h: f64) -> DuplexState {
        let (a, b, c) = (self.a, self.b, self.c);
        let [k1, k2] = self.conductivity;
        let r1 = (c / a).ln() / (2.0 * PI * k1);
        let rc = 1.0 / (2.0 * PI * c * h);
        let r2 = (b / c).ln() / (2.0 * PI * k2);
        let q = (self.t_inner - self.t_outer) / (r1 + rc + r2);
        // T = A + B ln r in each tube
        let b1 = -q / (2.0 * PI * k1);
        let a1 = self.t_inner - b1 * a.ln();
        let b2 = -q / (2.0 * PI * k2);
        let a2 = self.t_outer - b2 * b.ln();
        let tr = self.t_ref;
        let integral = |aa: f64, bb: f64, r0: f64, r: f64| {
            let f = |s: f64| (aa - tr) * s * s / 2.0 + bb * (s * s / 2.0 * s.ln() - s * s / 4.0);
            f(r) - f(r0)
        };
        let lame = |k: usize| {
            let (e, nu) = (self.youngs_modulus[k], self.poisson_ratio[k]);
            let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
            let mu = e / (2.0 * (1.0 + nu));
            let beta = (1.0 + nu) * self.expansion[k] / (1.0 - nu);
            (lambda, mu, beta)
        };
        let (l1, m1, be1) = lame(0);
        let (l2, m2, be2) = lame(1);
        let i1c = integral(a1, b1, a, c);
        let i2b = integral(a2, b2, c, b);
        // unknowns C₁ᵃ, C₂ᵃ (inner), C₁ᵇ, C₂ᵇ (outer), p
        #[rustfmt::skip]
        let m = Matrix5::new(
            2.0 * (l1 + m1), -2.0 * m1 / (a * a), 0.0, 0.0, 0.0,
            0.0, 0.0, 2.0 * (l2 + m2), -2.0 * m2 / (b * b), 0.0,
            2.0 * (l1 + m1), -2.0 * m1 / (c * c), 0.0, 0.0, 1.0,
            0.0, 0.0, 2.0 * (l2 + m2), -2.0 * m2 / (c * c), 1.0,
            c, 1.0 / c, -c, -1.0 / c, 0.0,
        );
        let rhs = Vector5::new(
            0.0,
            2.0 * m2 * be2 * i2b / (b * b),
            2.0 * m1 * be1 * i1c / (c * c),
            0.0,
            -be1 * i1c / c - self.interference,
        );
        let x = m
            .lu()
            .solve(&rhs)
            .unwrap_or_else(|| Vector5::repeat(f64::NAN));
        DuplexState {
            pressure: x[4],
            t_joint_inner: a1 + b1 * c.ln(),
            t_joint_outer: a2 + b2 * c.ln(),
            heat_rate: q,
        }
    }

    /// Every steady state with p in (0, p_max] for the conductance law
    /// `h(p)`: sign changes of g(h(p)) − p on `n` intervals, each refined
    /// by bisection to 1e-12 relative. (An open state, p = 0, exists
    /// besides when g(h(0)) ≤ 0.)
    pub fn steady_states(&self, h: &dyn Fn(f64) -> f64, p_max: f64, n: usize) -> Vec<SteadyState> {
        let f = |p: f64| self.at(h(p)).pressure - p;
        let mut out = Vec::new();
        let mut p0 = p_max * 1e-9;
        let mut f0 = f(p0);
        for k in 1..=n {
            let p1 = p_max * k as f64 / n as f64;
            let f1 = f(p1);
            if f0 * f1 <= 0.0 && f0 != f1 {
                let (mut lo, mut hi, mut flo) = (p0, p1, f0);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    let fm = f(mid);
                    if fm * flo > 0.0 {
                        lo = mid;
                        flo = fm;
                    } else {
                        hi = mid;
                    }
                    if hi - lo <= 1e-12 * hi {
                        break;
                    }
                }
                let p = 0.5 * (lo + hi);
                let dp = 1e-6 * p;
                let slope =
                    (self.at(h(p + dp)).pressure - self.at(h(p - dp)).pressure) / (2.0 * dp);
                out.push(SteadyState {
                    state: self.at(h(p)),
                    conductance: h(p),
                    slope,
                    stable: slope < 1.0,
                });
            }
            p0 = p1;
            f0 = f1;
        }
        out
    }
}
