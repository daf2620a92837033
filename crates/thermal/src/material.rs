//! Isotropic thermal material of a region and the capacity-matrix choice.

use crate::error::ThermalError;

/// Isotropic conduction material (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Conductivity k, W/(m K).
    pub conductivity: f64,
    /// Density ρ, kg/m³.
    pub density: f64,
    /// Specific heat c, J/(kg K).
    pub specific_heat: f64,
}

impl Material {
    /// A material with conductivity `k`, density `rho` and specific heat `c`
    /// (validated when it is given to a region).
    pub fn new(conductivity: f64, density: f64, specific_heat: f64) -> Self {
        Material {
            conductivity,
            density,
            specific_heat,
        }
    }

    /// The carbon steel of the published vessel case (DESIGN.md §2):
    /// k = 63.9 W/(m K), ρ = 7832 kg/m³, c = 434 J/(kg K).
    pub fn vessel_steel() -> Self {
        Material::new(63.9, 7832.0, 434.0)
    }

    /// Volumetric heat capacity ρc, J/(m³ K).
    pub fn volumetric_capacity(&self) -> f64 {
        self.density * self.specific_heat
    }

    /// Thermal diffusivity k/(ρc), m²/s.
    pub fn diffusivity(&self) -> f64 {
        self.conductivity / self.volumetric_capacity()
    }

    /// Checks that k, ρ and c are positive and finite; errors name `region`.
    pub fn validate(&self, region: &str) -> Result<(), ThermalError> {
        for (property, value) in [
            ("conductivity k", self.conductivity),
            ("density ρ", self.density),
            ("specific heat c", self.specific_heat),
        ] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(ThermalError::InvalidMaterial {
                    region: region.into(),
                    property,
                    value,
                });
            }
        }
        Ok(())
    }
}

/// Which capacity matrix to assemble.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum CapacityKind {
    /// Consistent: ρcA/12 · [2 1 1; 1 2 1; 1 1 2]. The default.
    #[default]
    Consistent,
    /// Lumped (row sums on the diagonal): ρcA/3 · I. With backward Euler it
    /// keeps the discrete maximum principle on non-obtuse meshes.
    Lumped,
}
