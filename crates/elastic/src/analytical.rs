//! Closed-form solutions (one struct per solution) used by the verification
//! tests and the vessel report. Radii: a inner, b outer (c for the
//! interface of two cylinders). Plane strain unless said otherwise.

/// Lamé thick cylinder a ≤ r ≤ b under internal pressure p (plane strain).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LameCylinder {
    /// Inner radius.
    pub a: f64,
    /// Outer radius.
    pub b: f64,
    /// Internal pressure.
    pub p: f64,
    /// Young's modulus.
    pub e: f64,
    /// Poisson's ratio.
    pub nu: f64,
}

impl LameCylinder {
    fn coefficients(&self) -> (f64, f64) {
        let d = self.b * self.b - self.a * self.a;
        (
            self.p * self.a * self.a / d,
            self.p * self.a * self.a * self.b * self.b / d,
        )
    }
    /// σ_rr(r).
    pub fn sigma_rr(&self, r: f64) -> f64 {
        let (a, b) = self.coefficients();
        a - b / (r * r)
    }
    /// σ_θθ(r).
    pub fn sigma_tt(&self, r: f64) -> f64 {
        let (a, b) = self.coefficients();
        a + b / (r * r)
    }
    /// Radial displacement u_r(r) in plane strain.
    pub fn u_r(&self, r: f64) -> f64 {
        let (a, b) = self.coefficients();
        (1.0 + self.nu) / self.e * ((1.0 - 2.0 * self.nu) * a * r + b / r)
    }
}

/// Long hollow cylinder a ≤ r ≤ b with the steady temperature
/// T(r) = T_a + (T_b − T_a) ln(r/a)/ln(b/a) above a stress-free reference 0
/// (Timoshenko & Goodier §150).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermalCylinder {
    /// Inner radius.
    pub a: f64,
    /// Outer radius.
    pub b: f64,
    /// Temperature change at r = a.
    pub t_a: f64,
    /// Temperature change at r = b.
    pub t_b: f64,
    /// Young's modulus.
    pub e: f64,
    /// Poisson's ratio.
    pub nu: f64,
    /// Thermal expansion.
    pub alpha: f64,
}

impl ThermalCylinder {
    /// T(r).
    pub fn temperature(&self, r: f64) -> f64 {
        self.t_a + (self.t_b - self.t_a) * (r / self.a).ln() / (self.b / self.a).ln()
    }
    /// ∫_a^r T ρ dρ.
    fn moment(&self, r: f64) -> f64 {
        let k = (self.t_b - self.t_a) / (self.b / self.a).ln();
        let a2 = self.a * self.a;
        self.t_a * (r * r - a2) / 2.0 + k * (r * r / 2.0 * (r / self.a).ln() - (r * r - a2) / 4.0)
    }
    fn factor(&self) -> f64 {
        self.e * self.alpha / (1.0 - self.nu)
    }
    /// σ_rr(r).
    pub fn sigma_rr(&self, r: f64) -> f64 {
        let (a2, b2) = (self.a * self.a, self.b * self.b);
        self.factor()
            * (-self.moment(r) / (r * r) + (r * r - a2) / (r * r * (b2 - a2)) * self.moment(self.b))
    }
    /// σ_θθ(r).
    pub fn sigma_tt(&self, r: f64) -> f64 {
        let (a2, b2) = (self.a * self.a, self.b * self.b);
        self.factor()
            * (self.moment(r) / (r * r) + (r * r + a2) / (r * r * (b2 - a2)) * self.moment(self.b)
                - self.temperature(r))
    }
    /// σ_zz(r) in plane strain (ε_zz = 0).
    pub fn sigma_zz_plane_strain(&self, r: f64) -> f64 {
        self.nu * (self.sigma_rr(r) + self.sigma_tt(r)) - self.e * self.alpha * self.temperature(r)
    }
    /// σ_zz(r) with free ends (generalised plane strain, zero axial force).
    pub fn sigma_zz_free_ends(&self, r: f64) -> f64 {
        let (a2, b2) = (self.a * self.a, self.b * self.b);
        self.factor() * (2.0 / (b2 - a2) * self.moment(self.b) - self.temperature(r))
    }
}

/// Which stress state the cylinders of a [`ShrinkFit`] are in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cylinders {
    /// ε_zz = 0.
    PlaneStrain,
    /// σ_zz = 0.
    PlaneStress,
}

/// Two concentric cylinders (inner a..c, outer c..b) with a radial
/// interference δ at r = c: contact pressure and stresses (Lamé).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShrinkFit {
    /// Inner radius of the inner cylinder.
    pub a: f64,
    /// Interface radius.
    pub c: f64,
    /// Outer radius of the outer cylinder.
    pub b: f64,
    /// Radial interference (m).
    pub delta: f64,
    /// Young's modulus (both).
    pub e: f64,
    /// Poisson's ratio (both).
    pub nu: f64,
    /// Stress state.
    pub state: Cylinders,
}

impl ShrinkFit {
    /// Radial compliance terms: u_outer(c) = p·co, u_inner(c) = −p·ci.
    fn compliances(&self) -> (f64, f64) {
        let (a2, b2, c2, nu, e, c) = (
            self.a * self.a,
            self.b * self.b,
            self.c * self.c,
            self.nu,
            self.e,
            self.c,
        );
        match self.state {
            Cylinders::PlaneStrain => (
                (1.0 + nu) * c / (e * (b2 - c2)) * ((1.0 - 2.0 * nu) * c2 + b2),
                (1.0 + nu) * c / (e * (c2 - a2)) * ((1.0 - 2.0 * nu) * c2 + a2),
            ),
            Cylinders::PlaneStress => (
                c / (e * (b2 - c2)) * ((1.0 - nu) * c2 + (1.0 + nu) * b2),
                c / (e * (c2 - a2)) * ((1.0 - nu) * c2 + (1.0 + nu) * a2),
            ),
        }
    }
    /// Contact pressure p.
    pub fn pressure(&self) -> f64 {
        let (co, ci) = self.compliances();
        self.delta / (co + ci)
    }
    /// Hoop stress σ_θθ(r) (inner cylinder for r < c, outer for r ≥ c).
    pub fn sigma_tt(&self, r: f64, in_inner: bool) -> f64 {
        let p = self.pressure();
        let (a2, b2, c2) = (self.a * self.a, self.b * self.b, self.c * self.c);
        if in_inner {
            -p * c2 / (c2 - a2) * (1.0 + a2 / (r * r))
        } else {
            p * c2 / (b2 - c2) * (1.0 + b2 / (r * r))
        }
    }
    /// Radial stress σ_rr(r).
    pub fn sigma_rr(&self, r: f64, in_inner: bool) -> f64 {
        let p = self.pressure();
        let (a2, b2, c2) = (self.a * self.a, self.b * self.b, self.c * self.c);
        if in_inner {
            -p * c2 / (c2 - a2) * (1.0 - a2 / (r * r))
        } else {
            p * c2 / (b2 - c2) * (1.0 - b2 / (r * r))
        }
    }
    /// Radial displacement of the inner cylinder's outer surface (negative)
    /// and of the outer cylinder's inner surface, relative to their free
    /// (interfering) positions.
    pub fn interface_displacements(&self) -> (f64, f64) {
        let (co, ci) = self.compliances();
        let p = self.pressure();
        (-p * ci, p * co)
    }
}

/// Radial interference of a welded wrap: the weld of width `w` cooling by `delta_t` shrinks
/// the layer's circumference by α ΔT w (plane stress) or (1 + ν) α ΔT w (plane strain, where
/// ε_zz = 0 adds ν α ΔT to the free in-plane shrinkage); spread round the ring it is a radial
/// interference of that length over 2π.
pub fn weld_interference(alpha: f64, delta_t: f64, w: f64, nu: f64, state: Cylinders) -> f64 {
    let free = match state {
        Cylinders::PlaneStrain => (1.0 + nu) * alpha * delta_t * w,
        Cylinders::PlaneStress => alpha * delta_t * w,
    };
    free / (2.0 * std::f64::consts::PI)
}

/// Why a [`SequentialShrinkFit`] cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SequentialFitError {
    /// Fewer than three radii, or not one interference per layer.
    #[error("{radii} radii need {} interferences (one per layer), got {deltas}", .radii.saturating_sub(2))]
    Counts {
        /// Number of radii given.
        radii: usize,
        /// Number of interferences given.
        deltas: usize,
    },
    /// Radii not positive and strictly increasing (a zero-thickness or overlapping ring).
    #[error("radius {index} ({value} m) must be positive and larger than the one before it")]
    Radii {
        /// Index of the offending radius.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A negative or non-finite interference: the ring would not close (a gap), outside the model.
    #[error("interference of layer {layer} is {value} m: the model needs δ ≥ 0 (a closed fit)")]
    Interference {
        /// Layer number (1-based).
        layer: usize,
        /// Its value.
        value: f64,
    },
}

/// Layers wrapped and welded one after another onto a core, all of one material: the
/// sequential shrink fit of concentric rings.
///
/// Ring 0 is the core (r₀ ≤ r ≤ r₁), ring j the j-th layer (r_j ≤ r ≤ r_{j+1}). Stage k
/// wraps layer k stress free and tight onto the *current* assembly (rings 0..k−1) and its weld
/// shrinkage brings a radial interference δ_k. With the interfaces closed the assembly of one
/// material acts as one Lamé cylinder r₀..r_k, so stage k is the two-cylinder fit
/// [`ShrinkFit`] { a: r₀, c: r_k, b: r_{k+1}, δ_k }, and linear elasticity lets the stages
/// superpose: the state after stage K is the sum of the stages 1..=K (a ring not yet wrapped
/// carries nothing). Valid while every interface stays closed, i.e. every contact pressure
/// stays positive (true for δ ≥ 0: each stage compresses the whole assembly radially).
#[derive(Debug, Clone, PartialEq)]
pub struct SequentialShrinkFit {
    radii: Vec<f64>,
    deltas: Vec<f64>,
    e: f64,
    nu: f64,
    state: Cylinders,
}

impl SequentialShrinkFit {
    /// Radii r₀ < r₁ < … < r_{N+1} and the N interferences δ_1..δ_N.
    pub fn new(
        radii: Vec<f64>,
        deltas: Vec<f64>,
        e: f64,
        nu: f64,
        state: Cylinders,
    ) -> Result<Self, SequentialFitError> {
        if radii.len() < 3 || deltas.len() + 2 != radii.len() {
            return Err(SequentialFitError::Counts {
                radii: radii.len(),
                deltas: deltas.len(),
            });
        }
        for (i, &r) in radii.iter().enumerate() {
            let prev = if i == 0 { 0.0 } else { radii[i - 1] };
            if !(r.is_finite() && r > prev) {
                return Err(SequentialFitError::Radii { index: i, value: r });
            }
        }
        for (j, &d) in deltas.iter().enumerate() {
            if !(d.is_finite() && d >= 0.0) {
                return Err(SequentialFitError::Interference {
                    layer: j + 1,
                    value: d,
                });
            }
        }
        Ok(Self {
            radii,
            deltas,
            e,
            nu,
            state,
        })
    }

    /// Number of layers N.
    pub fn n_layers(&self) -> usize {
        self.deltas.len()
    }

    /// Radii r₀..r_{N+1}.
    pub fn radii(&self) -> &[f64] {
        &self.radii
    }

    /// The two-cylinder fit of stage `k` (1..=N) alone.
    pub fn stage(&self, k: usize) -> ShrinkFit {
        ShrinkFit {
            a: self.radii[0],
            c: self.radii[k],
            b: self.radii[k + 1],
            delta: self.deltas[k - 1],
            e: self.e,
            nu: self.nu,
            state: self.state,
        }
    }

    /// Sum over the stages 1..=`after` that load `ring`: `f(stage fit, ring is in its inner cylinder)`.
    fn sum(&self, after: usize, ring: usize, f: impl Fn(&ShrinkFit, bool) -> f64) -> f64 {
        (1..=after.min(self.n_layers()))
            .filter(|&k| ring <= k)
            .map(|k| f(&self.stage(k), ring < k))
            .sum()
    }

    /// Hoop stress σ_θθ at radius `r` of `ring` (0 = core, j = layer j) after stage `after`.
    pub fn sigma_tt(&self, after: usize, ring: usize, r: f64) -> f64 {
        self.sum(after, ring, |s, inner| s.sigma_tt(r, inner))
    }

    /// Radial stress σ_rr at radius `r` of `ring` after stage `after`.
    pub fn sigma_rr(&self, after: usize, ring: usize, r: f64) -> f64 {
        self.sum(after, ring, |s, inner| s.sigma_rr(r, inner))
    }

    /// Contact pressure (positive in compression) at interface `j` (1..=N, between ring j−1
    /// and layer j) after stage `after`; zero before layer j is wrapped.
    pub fn contact_pressure(&self, after: usize, j: usize) -> f64 {
        if j == 0 || j > after.min(self.n_layers()) {
            return 0.0;
        }
        -self.sigma_rr(after, j, self.radii[j])
    }

    /// Mean hoop stress through the thickness of `ring` after stage `after`:
    /// (1/(r₂ − r₁)) ∫ σ_θθ dr, exact for the Lamé field A + B/r².
    pub fn mean_hoop(&self, after: usize, ring: usize) -> f64 {
        let (r1, r2) = (self.radii[ring], self.radii[ring + 1]);
        self.sum(after, ring, |s, inner| {
            // σ_θθ = A + B/r² with A, B read off at two radii.
            let (f1, f2) = (s.sigma_tt(r1, inner), s.sigma_tt(r2, inner));
            let b = (f1 - f2) / (1.0 / (r1 * r1) - 1.0 / (r2 * r2));
            let a = f1 - b / (r1 * r1);
            a + b / (r1 * r2)
        })
    }
}
