//! Boundary conditions on edge sets. Edges with no condition are adiabatic.

use crate::error::ThermalError;

/// A thermal condition on the edges of an edge set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EdgeBc {
    /// Convection `−k ∂T/∂n = h (T − T∞)`.
    Convection {
        /// Film coefficient h, W/(m² K), positive.
        h: f64,
        /// Ambient temperature T∞.
        ambient: f64,
    },
    /// Prescribed heat flux **into** the body, `q_in = k ∂T/∂n`, W/m²
    /// (negative for a loss).
    Flux {
        /// Inward flux, W/m².
        q_in: f64,
    },
    /// Prescribed temperature at every node of the edge set.
    Temperature {
        /// The temperature.
        value: f64,
    },
}

impl EdgeBc {
    /// Convection with film coefficient `h` to ambient `ambient`.
    pub fn convection(h: f64, ambient: f64) -> Self {
        EdgeBc::Convection { h, ambient }
    }

    /// Inward heat flux `q_in` (W/m²).
    pub fn flux(q_in: f64) -> Self {
        EdgeBc::Flux { q_in }
    }

    /// Prescribed temperature.
    pub fn temperature(value: f64) -> Self {
        EdgeBc::Temperature { value }
    }

    /// Checks the values; errors name the edge set `set`.
    pub fn validate(&self, set: &str) -> Result<(), ThermalError> {
        let bad = |what, reason, value| ThermalError::InvalidBoundary {
            set: set.into(),
            what,
            reason,
            value,
        };
        match *self {
            EdgeBc::Convection { h, ambient } => {
                if !(h > 0.0 && h.is_finite()) {
                    return Err(bad("film coefficient h", "must be positive and finite", h));
                }
                if !ambient.is_finite() {
                    return Err(bad("ambient temperature T∞", "must be finite", ambient));
                }
            }
            EdgeBc::Flux { q_in } => {
                if !q_in.is_finite() {
                    return Err(bad("heat flux q", "must be finite", q_in));
                }
            }
            EdgeBc::Temperature { value } => {
                if !value.is_finite() {
                    return Err(bad("prescribed temperature", "must be finite", value));
                }
            }
        }
        Ok(())
    }
}
