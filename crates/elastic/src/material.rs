//! Isotropic linear elastic material and the plane analysis types.

use nalgebra::{Matrix3, Matrix4};

/// Isotropic linear elastic material with thermal expansion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
    /// Linear thermal expansion coefficient α (1/K).
    pub expansion: f64,
}

impl Material {
    /// Checks E > 0, −1 < ν < 0.5, α finite; the message says which is wrong.
    pub fn check(&self) -> Result<(), String> {
        let Material {
            youngs_modulus: e,
            poisson_ratio: nu,
            expansion: a,
        } = *self;
        if !(e.is_finite() && e > 0.0) {
            return Err(format!("Young's modulus must be positive, got {e}"));
        }
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(format!("Poisson's ratio must lie in (-1, 0.5), got {nu}"));
        }
        if !a.is_finite() {
            return Err(format!("thermal expansion must be finite, got {a}"));
        }
        Ok(())
    }

    /// Lamé λ.
    pub fn lambda(&self) -> f64 {
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// Shear modulus μ = G.
    pub fn mu(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// 3D modulus on (ε_xx, ε_yy, γ_xy, ε_zz).
    pub fn d4(&self) -> Matrix4<f64> {
        let (l, m) = (self.lambda(), self.mu());
        Matrix4::new(
            l + 2.0 * m,
            l,
            0.0,
            l, //
            l,
            l + 2.0 * m,
            0.0,
            l, //
            0.0,
            0.0,
            m,
            0.0, //
            l,
            l,
            0.0,
            l + 2.0 * m,
        )
    }
}

/// The plane analysis type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Analysis {
    /// ε_zz = 0 (long body with fixed ends); the default.
    #[default]
    PlaneStrain,
    /// σ_zz = 0 (thin plate).
    PlaneStress,
    /// ε_zz uniform and unknown, zero net axial force (long body with free ends).
    GeneralisedPlaneStrain,
}

impl Analysis {
    /// The in-plane modulus D (3×3) on (ε_xx, ε_yy, γ_xy).
    pub fn d(&self, m: &Material) -> Matrix3<f64> {
        match self {
            Analysis::PlaneStress => {
                let (e, nu) = (m.youngs_modulus, m.poisson_ratio);
                let f = e / (1.0 - nu * nu);
                Matrix3::new(
                    f,
                    f * nu,
                    0.0,
                    f * nu,
                    f,
                    0.0,
                    0.0,
                    0.0,
                    f * (1.0 - nu) / 2.0,
                )
            }
            _ => m.d4().fixed_view::<3, 3>(0, 0).into_owned(),
        }
    }

    /// Free in-plane thermal strain per kelvin, on ε_xx and ε_yy: (1 + ν)α in
    /// plane strain (ε_zz = 0 is enforced), α in plane stress and in
    /// generalised plane strain (where ε_zz takes its own share).
    pub fn in_plane_expansion(&self, m: &Material) -> f64 {
        match self {
            Analysis::PlaneStrain => (1.0 + m.poisson_ratio) * m.expansion,
            _ => m.expansion,
        }
    }
}
