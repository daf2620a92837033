//! The solver front end: options, [`solve`], and the [`TorsionSolution`]
//! with its outputs (J, τ_max and its location, |q| along Γ, interior u and
//! stresses, the multiplier c).

use crate::density::FourierDensity;
use crate::error::SolveError;
use crate::geometry::{Section, V2};
use crate::grading::{BPoint, Parametrisation};
use crate::{galerkin, kernels, nystrom, shannon};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Discretisation method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// periodised Daubechies wavelet Galerkin (default)
    Daubechies,
    /// harmonic (Shannon) wavelet Galerkin: spectral
    Shannon,
    /// Kress Nyström with log product weights: reference
    Nystrom,
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Daubechies => "daubechies",
            Method::Shannon => "shannon",
            Method::Nystrom => "nystrom",
        })
    }
}

/// How the linear system is solved (compression applies to Daubechies Galerkin only).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinearSolver {
    /// dense direct solve of the augmented system (faer: Bunch–Kaufman LBLᵀ for the
    /// symmetric Galerkin systems, partial-pivoting LU for Nyström)
    Dense,
    /// wavelet-basis matrix thresholded at ε·max|a|, projected PCG with level
    /// (diagonal) scaling to relative residual `tol`
    Compressed {
        /// threshold ε
        eps: f64,
        /// CG tolerance
        tol: f64,
    },
}

/// Options of [`solve`].
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// number of unknowns n, 8 ≤ n ≤ 8192 (a power of two ≥ the wavelet's minimum for Daubechies)
    pub n: usize,
    /// method
    pub method: Method,
    /// Daubechies order N (dbN has N vanishing moments)
    pub wavelet_order: usize,
    /// Kress grading exponent p at corners and cusps
    pub grading: f64,
    /// linear solver
    pub linear: LinearSolver,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            n: 256,
            method: Method::Daubechies,
            wavelet_order: 4,
            grading: 6.0,
            linear: LinearSolver::Dense,
        }
    }
}

/// Statistics of the compressed wavelet-basis matrix.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CompressionReport {
    /// threshold ε (relative to max|a_ij|)
    pub eps: f64,
    /// kept entries per row
    pub entries_per_row: f64,
    /// ‖A − A_ε‖₂ / ‖A‖₂ (power iteration)
    pub operator_error: f64,
    /// CG iterations
    pub iterations: usize,
    /// final relative residual
    pub residual: f64,
}

/// Where τ is largest.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct MaxShear {
    /// τ_max (None when a re-entrant corner or inward cusp makes it infinite)
    pub value: Option<f64>,
    /// location: the maximiser, or the singular point
    pub at: Option<V2>,
    /// τ → ∞ somewhere on Γ
    pub singular: bool,
    /// largest |q| found on the regular part of Γ (equals `value` when not singular)
    pub regular_max: f64,
    /// where `regular_max` is attained
    pub regular_at: V2,
}

/// One sample of the boundary traction.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct BoundarySample {
    /// parameter t ∈ [0, 1)
    pub t: f64,
    /// arc length from the start of the boundary
    pub s: f64,
    /// position
    pub x: V2,
    /// q = ∂u/∂n (≤ 0)
    pub q: f64,
}

/// Prandtl function and stresses at an interior point.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct InteriorValue {
    /// point
    pub x: V2,
    /// u (Gθ = 1)
    pub u: f64,
    /// τ_xz = ∂u/∂y
    pub tau_xz: f64,
    /// τ_yz = −∂u/∂x
    pub tau_yz: f64,
}

/// The solution of one torsion problem.
#[derive(Clone, Debug)]
pub struct TorsionSolution {
    /// the section
    pub section: Section,
    /// the graded parametrisation used
    pub param: Parametrisation,
    /// options used
    pub options: Options,
    /// torsional rigidity J (torque T = GθJ)
    pub torsional_rigidity: f64,
    /// Lagrange multiplier c of the augmented system (exactly 0)
    pub multiplier: f64,
    /// density μ(t) = q_v |x′| as a trigonometric polynomial
    pub density: FourierDensity,
    /// compression statistics when the compressed solver was used
    pub compression: Option<CompressionReport>,
    /// centroid x₀ used by the particular solution
    pub centroid: V2,
}

/// Raw output of a discretisation: density, multiplier and ∫ g2 μ dt.
pub(crate) struct RawSolution {
    pub density: FourierDensity,
    pub multiplier: f64,
    pub j_integral: f64,
    pub compression: Option<CompressionReport>,
}

/// Solves Saint-Venant torsion (Gθ = 1) of `section`.
pub fn solve(section: &Section, opts: &Options) -> Result<TorsionSolution, SolveError> {
    if !(opts.grading >= 2.0 && opts.grading <= 12.0 && opts.grading.fract() == 0.0) {
        return Err(SolveError::BadGrading(opts.grading));
    }
    // dense n×n work arrays: 8192² doubles are 0.5 GB each
    if opts.n < 8 || opts.n > 1 << 13 {
        return Err(SolveError::BadN {
            n: opts.n,
            reason: "need 8 ≤ n ≤ 8192 (dense matrices)".into(),
        });
    }
    let param = Parametrisation::new(section, opts.grading);
    let x0 = section.centroid;
    let raw = match opts.method {
        Method::Nystrom => {
            if !opts.n.is_multiple_of(2) {
                return Err(SolveError::BadN {
                    n: opts.n,
                    reason: "Nyström needs an even n".into(),
                });
            }
            let nodes = param.nodes(section, opts.n);
            let (mu, c) = nystrom::solve(&nodes, x0)?;
            let g2 = kernels::radius_sq(&nodes, x0);
            let ji = mu.iter().zip(&g2).map(|(a, b)| a * b).sum::<f64>() / opts.n as f64;
            RawSolution {
                density: FourierDensity::from_nodes(&mu),
                multiplier: c,
                j_integral: ji,
                compression: None,
            }
        }
        Method::Daubechies => galerkin::solve(section, &param, opts)?,
        Method::Shannon => shannon::solve(section, &param, opts)?,
    };
    let ip = section.polar_moment();
    let j = ip - 0.5 * raw.j_integral;
    if !j.is_finite() || !raw.multiplier.is_finite() {
        return Err(SolveError::NonFinite);
    }
    Ok(TorsionSolution {
        section: section.clone(),
        param,
        options: *opts,
        torsional_rigidity: j,
        multiplier: raw.multiplier,
        density: raw.density,
        compression: raw.compression,
        centroid: x0,
    })
}

impl TorsionSolution {
    /// q = ∂u/∂n at boundary parameter t.
    pub fn flux_at(&self, t: f64) -> (BPoint, f64) {
        let p = self.param.eval(&self.section, t);
        let mu = self.density.eval(t);
        let x = p.x();
        let nrm = p.normal();
        let qv = mu / p.speed();
        let q = qv - ((x[0] - self.centroid[0]) * nrm[0] + (x[1] - self.centroid[1]) * nrm[1]);
        (p, q)
    }

    /// Whether t lies in a graded corner cluster where μ/|x′| is 0/0 and
    /// must not be trusted (|dw/ds| < 0.1 next to a corner, < 1e-3 next to a
    /// tangent-continuous junction).
    pub fn in_cluster(&self, t: f64) -> bool {
        let (k, s) = self.param.local(t);
        let Some(p) = self.param.grading[k] else {
            return false;
        };
        let m = self.section.pieces.len();
        let (sig, junc) = if s <= 0.5 {
            (s, k)
        } else {
            (1.0 - s, (k + 1) % m)
        };
        let (_, dw, _) = crate::grading::kress(sig, p);
        let limit = if self.section.junctions[junc].is_smooth() {
            1e-3
        } else {
            0.1
        };
        dw < limit
    }

    /// |q| sampled at `m` equally spaced parameters with arc length, graded clusters skipped.
    pub fn boundary_samples(&self, m: usize) -> Vec<BoundarySample> {
        let ts: Vec<f64> = (0..m).map(|k| (k as f64 + 0.5) / m as f64).collect();
        let mu = self.density.sample(m, 0.5);
        let pts: Vec<BPoint> = ts
            .par_iter()
            .map(|&t| self.param.eval(&self.section, t))
            .collect();
        // arc length by the trapezoidal rule on the same grid (exact spectrally for smooth |x′|)
        let mut s = 0.0;
        let mut out = Vec::with_capacity(m);
        for k in 0..m {
            if k > 0 {
                s += 0.5 * (pts[k - 1].speed() + pts[k].speed()) / m as f64;
            } else {
                s = 0.5 * pts[0].speed() / m as f64;
            }
            if self.in_cluster(ts[k]) {
                continue;
            }
            let x = pts[k].x();
            let nrm = pts[k].normal();
            let q = mu[k] / pts[k].speed()
                - ((x[0] - self.centroid[0]) * nrm[0] + (x[1] - self.centroid[1]) * nrm[1]);
            out.push(BoundarySample { t: ts[k], s, x, q });
        }
        out
    }

    /// τ_max = max |q| on the interpolant (graded clusters excluded), refined by
    /// golden-section search; singular corners and cusps reported as such.
    pub fn max_shear(&self) -> MaxShear {
        let m = (8 * self.options.n).max(2048);
        let samples = self.boundary_samples(m);
        let mut best = (0.0f64, 0.5, [0.0, 0.0]);
        for s in &samples {
            if s.q.abs() > best.0 {
                best = (s.q.abs(), s.t, s.x);
            }
        }
        // golden section on [t − 1/m, t + 1/m]
        let f = |t: f64| -> f64 {
            if self.in_cluster(t) {
                0.0
            } else {
                self.flux_at(t).1.abs()
            }
        };
        let (mut a, mut b) = (best.1 - 1.0 / m as f64, best.1 + 1.0 / m as f64);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let (mut fc, mut fd) = (f(c), f(d));
        for _ in 0..80 {
            if fc > fd {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = f(c);
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = f(d);
            }
        }
        let tm = 0.5 * (a + b);
        let vm = f(tm);
        if vm > best.0 {
            best = (vm, tm, self.param.eval(&self.section, tm).x());
        }
        let singular_at = self
            .section
            .junctions
            .iter()
            .find(|j| j.is_singular())
            .map(|j| j.point);
        match singular_at {
            Some(p) => MaxShear {
                value: None,
                at: Some(p),
                singular: true,
                regular_max: best.0,
                regular_at: best.2,
            },
            None => MaxShear {
                value: Some(best.0),
                at: Some(best.2),
                singular: false,
                regular_max: best.0,
                regular_at: best.2,
            },
        }
    }

    /// u and the stresses at interior points by the representation formula
    /// u = g(x) − |x − x₀|²/2 + ∮ w q_v ds − ∮ (g(y) − g(x)) ∂w/∂n_y ds
    /// (trapezoidal rule on 4n graded nodes; accurate away from Γ, degrading
    /// within about one node spacing of it).
    pub fn interior(&self, points: &[V2]) -> Vec<InteriorValue> {
        let m = 4 * self.options.n;
        let mu = self.density.sample(m, 0.5);
        let nodes: Vec<BPoint> = (0..m)
            .map(|k| self.param.eval(&self.section, (k as f64 + 0.5) / m as f64))
            .collect();
        let x0 = self.centroid;
        let h = 1.0 / m as f64;
        points
            .par_iter()
            .map(|&x| {
                // v(x) = g(x) + Σ h [w μ − (g(y) − g(x)) k], with ∮ ∂w/∂n_y = −1 inside
                let gx = 0.5 * ((x[0] - x0[0]).powi(2) + (x[1] - x0[1]).powi(2));
                let grad_g = [x[0] - x0[0], x[1] - x0[1]];
                let (mut v, mut vx, mut vy) = (gx, grad_g[0], grad_g[1]);
                for (k, y) in nodes.iter().enumerate() {
                    let yx = y.x();
                    let d = [x[0] - yx[0], x[1] - yx[1]];
                    let r2 = d[0] * d[0] + d[1] * d[1];
                    let nl = [y.d1[1], -y.d1[0]]; // n |y′|
                    let w = -(r2.ln()) / (4.0 * PI);
                    let gw = [-d[0] / (2.0 * PI * r2), -d[1] / (2.0 * PI * r2)];
                    let dn = d[0] * nl[0] + d[1] * nl[1];
                    let kk = dn / (2.0 * PI * r2);
                    let gk = [
                        (nl[0] - 2.0 * d[0] * dn / r2) / (2.0 * PI * r2),
                        (nl[1] - 2.0 * d[1] * dn / r2) / (2.0 * PI * r2),
                    ];
                    let gy = 0.5 * ((yx[0] - x0[0]).powi(2) + (yx[1] - x0[1]).powi(2));
                    let dg = gy - gx;
                    v += h * (w * mu[k] - dg * kk);
                    vx += h * (gw[0] * mu[k] + grad_g[0] * kk - dg * gk[0]);
                    vy += h * (gw[1] * mu[k] + grad_g[1] * kk - dg * gk[1]);
                }
                let u = v - gx;
                let ux = vx - grad_g[0];
                let uy = vy - grad_g[1];
                InteriorValue {
                    x,
                    u,
                    tau_xz: uy,
                    tau_yz: -ux,
                }
            })
            .collect()
    }
}
