//! Conductance laws of thermal interfaces.
//!
//! The thermal interface element asks its law for `h_c` at each integration
//! point, handing it the point's [`InterfacePointState`]. The constant law
//! ignores the state; a pressure- or gap-dependent law (contact conductance)
//! reads it, and the caller updates the states (from the mechanical
//! solution) and re-assembles: the element itself does not change.

use std::fmt::Debug;

use crate::error::ThermalError;

/// Mechanical state of an interface integration point, as seen by a
/// conductance law.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InterfacePointState {
    /// Normal opening ⟦u_n⟧ (m); positive is a gap, negative an overlap.
    pub gap: f64,
    /// Contact pressure σ_c (Pa), compressive positive.
    pub pressure: f64,
}

/// A law giving the interface conductance `h_c` (W/(m² K)) at a point.
///
/// Must return a finite, non-negative value (zero means the point conducts
/// no heat, e.g. an open gap); the model checks this before assembly and
/// reports the interface and element otherwise.
pub trait ConductanceLaw: Debug + Send + Sync {
    /// Conductance h_c at a point in the given state.
    fn conductance(&self, state: &InterfacePointState) -> f64;
}

/// A constant conductance, independent of the interface state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantConductance {
    h_c: f64,
}

impl ConstantConductance {
    /// A constant conductance `h_c` (W/(m² K)), which must be positive and finite.
    pub fn new(h_c: f64) -> Result<Self, ThermalError> {
        if !(h_c > 0.0 && h_c.is_finite()) {
            return Err(ThermalError::InvalidConductance {
                interface: "(constant law)".into(),
                element: None,
                requirement: "positive and finite",
                value: h_c,
            });
        }
        Ok(ConstantConductance { h_c })
    }

    /// The conductance value.
    pub fn value(&self) -> f64 {
        self.h_c
    }
}

impl ConductanceLaw for ConstantConductance {
    fn conductance(&self, _state: &InterfacePointState) -> f64 {
        self.h_c
    }
}
