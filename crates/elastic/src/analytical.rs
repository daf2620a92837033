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
