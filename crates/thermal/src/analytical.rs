//! Closed-form solutions used by the verification tests (one struct per
//! solution).

/// Transient 1D slab `0 ≤ x ≤ L`, insulated at `x = 0`, convection
/// `−k ∂T/∂x = h (T − T∞)` at `x = L`, uniform initial temperature `T₀`.
///
/// ```text
///   (T − T∞)/(T₀ − T∞) = Σ_n C_n exp(−λ_n² Fo) cos(λ_n x/L),
///   λ_n tan λ_n = Bi = hL/k,  C_n = 4 sin λ_n / (2λ_n + sin 2λ_n),
///   Fo = a t / L²,  a = k/(ρc)
/// ```
/// (Carslaw & Jaeger §3.11; Incropera, Ch. 5.)
#[derive(Debug, Clone, PartialEq)]
pub struct SlabConvectionSeries {
    /// Thickness L.
    pub length: f64,
    /// Conductivity k.
    pub conductivity: f64,
    /// Diffusivity a = k/(ρc).
    pub diffusivity: f64,
    /// Film coefficient h.
    pub h: f64,
    /// Ambient T∞.
    pub ambient: f64,
    /// Initial temperature T₀.
    pub initial: f64,
    /// Eigenvalues λ_n.
    lambdas: Vec<f64>,
}

impl SlabConvectionSeries {
    /// The series with `terms` eigenvalues.
    pub fn new(
        length: f64,
        conductivity: f64,
        diffusivity: f64,
        h: f64,
        ambient: f64,
        initial: f64,
        terms: usize,
    ) -> Self {
        let bi = h * length / conductivity;
        let f = |l: f64| l * l.sin() - bi * l.cos();
        let lambdas = (0..terms)
            .map(|n| {
                let (mut a, mut b) = (
                    n as f64 * std::f64::consts::PI,
                    n as f64 * std::f64::consts::PI + std::f64::consts::FRAC_PI_2,
                );
                let fa = f(a);
                for _ in 0..200 {
                    let m = 0.5 * (a + b);
                    if f(m) * fa > 0.0 {
                        a = m;
                    } else {
                        b = m;
                    }
                    if b - a <= 4.0 * f64::EPSILON * b {
                        break;
                    }
                }
                0.5 * (a + b)
            })
            .collect();
        SlabConvectionSeries {
            length,
            conductivity,
            diffusivity,
            h,
            ambient,
            initial,
            lambdas,
        }
    }

    /// Biot number hL/k.
    pub fn biot(&self) -> f64 {
        self.h * self.length / self.conductivity
    }

    /// The eigenvalues λ_n.
    pub fn eigenvalues(&self) -> &[f64] {
        &self.lambdas
    }

    /// Temperature at `x`, time `t > 0`.
    pub fn temperature(&self, x: f64, t: f64) -> f64 {
        let fo = self.diffusivity * t / (self.length * self.length);
        let s: f64 = self
            .lambdas
            .iter()
            .map(|&l| {
                let c = 4.0 * l.sin() / (2.0 * l + (2.0 * l).sin());
                c * (-l * l * fo).exp() * (l * x / self.length).cos()
            })
            .sum();
        self.ambient + (self.initial - self.ambient) * s
    }
}

/// Steady conduction through two concentric rings `r_a ≤ r ≤ r_b`
/// (conductivity k₁) and `r_b ≤ r ≤ r_c` (k₂), joined at `r_b` by an
/// interface of conductance h_c, with `T = T_a` at `r_a` and convection
/// `h (T − T∞)` at `r_c`. Heat rate per unit length Q through four
/// resistances in series:
///
/// ```text
///   Q = (T_a − T∞) / (ln(r_b/r_a)/(2πk₁) + 1/(2π r_b h_c)
///                     + ln(r_c/r_b)/(2πk₂) + 1/(2π r_c h))
///   jump at r_b:  T(r_b⁻) − T(r_b⁺) = q/h_c,  q = Q/(2π r_b)
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConcentricRings {
    /// Inner radius r_a.
    pub r_a: f64,
    /// Interface radius r_b.
    pub r_b: f64,
    /// Outer radius r_c.
    pub r_c: f64,
    /// Conductivity of the inner ring.
    pub k1: f64,
    /// Conductivity of the outer ring.
    pub k2: f64,
    /// Interface conductance h_c.
    pub h_c: f64,
    /// Outer film coefficient h.
    pub h: f64,
    /// Inner surface temperature T_a.
    pub t_inner: f64,
    /// Ambient T∞.
    pub ambient: f64,
}

impl ConcentricRings {
    /// Heat rate per unit length Q (W/m), outward.
    pub fn heat_rate(&self) -> f64 {
        let tau = 2.0 * std::f64::consts::PI;
        let r = (self.r_b / self.r_a).ln() / (tau * self.k1)
            + 1.0 / (tau * self.r_b * self.h_c)
            + (self.r_c / self.r_b).ln() / (tau * self.k2)
            + 1.0 / (tau * self.r_c * self.h);
        (self.t_inner - self.ambient) / r
    }

    /// Interface flux q = Q/(2π r_b) (W/m²), outward.
    pub fn interface_flux(&self) -> f64 {
        self.heat_rate() / (2.0 * std::f64::consts::PI * self.r_b)
    }

    /// Temperature jump `T(r_b⁻) − T(r_b⁺) = q/h_c`.
    pub fn jump(&self) -> f64 {
        self.interface_flux() / self.h_c
    }

    /// Temperature in the inner ring at radius r.
    pub fn inner(&self, r: f64) -> f64 {
        self.t_inner
            - self.heat_rate() * (r / self.r_a).ln() / (2.0 * std::f64::consts::PI * self.k1)
    }

    /// Temperature in the outer ring at radius r.
    pub fn outer(&self, r: f64) -> f64 {
        self.inner(self.r_b)
            - self.jump()
            - self.heat_rate() * (r / self.r_b).ln() / (2.0 * std::f64::consts::PI * self.k2)
    }
}
