//! Conductance laws of thermal interfaces.
//!
//! The thermal interface element asks its law for `h_c` at each integration
//! point, handing it the point's [`InterfacePointState`]. The constant law
//! ignores the state; a pressure- or gap-dependent law (contact conductance)
//! reads it, and the caller updates the states (from the mechanical
//! solution) and re-assembles: the element itself does not change.
//!
//! Laws: [`ConstantConductance`]; contact conductance as a function of the
//! contact pressure p — [`PowerLaw`] `h₀ (p/p₀)^m` and [`MikicYovanovich`]
//! `1.25 k_s (m/σ) (p/H_c)^0.95`; gas-gap conductance [`GasGap`]
//! `k_g / (g + g₀)`; linearised [`Radiation`] `4 σ_SB ε T_m³`. A
//! [`JointConductance`] adds a contact part, a gas part and radiation:
//! the contact parts vanish at p = 0 and the gas part reads the gap
//! `max(g, 0)`, so the sum is continuous at touch-down (g = 0, p = 0).

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
    /// Mean temperature of the two faces (°C), for radiation.
    pub temperature: f64,
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

fn check(
    law: &'static str,
    name: &'static str,
    v: f64,
    positive: bool,
) -> Result<(), ThermalError> {
    let ok = v.is_finite() && if positive { v > 0.0 } else { v >= 0.0 };
    if ok {
        Ok(())
    } else {
        Err(ThermalError::InvalidLawParameter {
            law,
            parameter: name,
            requirement: if positive {
                "positive and finite"
            } else {
                "non-negative and finite"
            },
            value: v,
        })
    }
}

/// Contact conductance `h = h₀ (p/p₀)^m` for `p > 0`, zero for `p ≤ 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerLaw {
    /// h₀, W/(m² K): the conductance at p = p₀.
    pub h0: f64,
    /// p₀, Pa: the reference pressure.
    pub p0: f64,
    /// m: the exponent (> 0, so that h(0) = 0).
    pub exponent: f64,
}

impl PowerLaw {
    /// Checks the parameters (h₀ ≥ 0, p₀ > 0, m > 0).
    pub fn new(h0: f64, p0: f64, exponent: f64) -> Result<Self, ThermalError> {
        check("power", "h0", h0, false)?;
        check("power", "p0", p0, true)?;
        check("power", "exponent", exponent, true)?;
        Ok(PowerLaw { h0, p0, exponent })
    }

    /// h(p).
    pub fn at(&self, p: f64) -> f64 {
        if p > 0.0 {
            self.h0 * (p / self.p0).powf(self.exponent)
        } else {
            0.0
        }
    }
}

/// Mikic / Yovanovich plastic contact conductance of rough surfaces,
/// `h = 1.25 k_s (m/σ) (p/H_c)^0.95` for `p > 0`, zero for `p ≤ 0`
/// (σ the combined RMS roughness √(σ₁² + σ₂²), m the combined asperity slope
/// √(m₁² + m₂²), H_c the microhardness of the softer surface, k_s the
/// harmonic-mean conductivity 2 k₁ k₂ / (k₁ + k₂)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MikicYovanovich {
    /// σ, m: combined RMS surface roughness.
    pub roughness: f64,
    /// m: combined mean asperity slope.
    pub slope: f64,
    /// H_c, Pa: microhardness.
    pub microhardness: f64,
    /// k_s, W/(m K): harmonic-mean conductivity of the two solids.
    pub conductivity: f64,
}

impl MikicYovanovich {
    /// Checks the parameters (all positive).
    pub fn new(
        roughness: f64,
        slope: f64,
        microhardness: f64,
        conductivity: f64,
    ) -> Result<Self, ThermalError> {
        let l = "mikic-yovanovich";
        check(l, "roughness", roughness, true)?;
        check(l, "slope", slope, true)?;
        check(l, "microhardness", microhardness, true)?;
        check(l, "harmonic_conductivity", conductivity, true)?;
        Ok(MikicYovanovich {
            roughness,
            slope,
            microhardness,
            conductivity,
        })
    }

    /// h(p).
    pub fn at(&self, p: f64) -> f64 {
        if p > 0.0 {
            1.25 * self.conductivity * self.slope / self.roughness
                * (p / self.microhardness).powf(0.95)
        } else {
            0.0
        }
    }
}

/// Conductance of a gas-filled gap, `h = k_g / (max(g, 0) + g₀)` (g₀ the
/// temperature-jump distance: the gas between asperities when closed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GasGap {
    /// k_g, W/(m K): conductivity of the gas.
    pub conductivity: f64,
    /// g₀, m: temperature-jump distance (> 0).
    pub jump_distance: f64,
}

impl GasGap {
    /// Checks the parameters (both positive).
    pub fn new(conductivity: f64, jump_distance: f64) -> Result<Self, ThermalError> {
        check("gap", "gas_conductivity", conductivity, true)?;
        check("gap", "jump_distance", jump_distance, true)?;
        Ok(GasGap {
            conductivity,
            jump_distance,
        })
    }

    /// h(g).
    pub fn at(&self, gap: f64) -> f64 {
        self.conductivity / (gap.max(0.0) + self.jump_distance)
    }
}

/// Stefan–Boltzmann constant, W/(m² K⁴).
pub const STEFAN_BOLTZMANN: f64 = 5.670_374_419e-8;

/// Radiation across the gap, linearised about the mean face temperature:
/// `h = 4 σ_SB ε T_m³` (T_m in kelvin, ε the effective emissivity
/// 1/(1/ε₁ + 1/ε₂ − 1) of two parallel grey surfaces).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Radiation {
    /// ε: effective emissivity in (0, 1].
    pub emissivity: f64,
}

impl Radiation {
    /// Checks 0 < ε ≤ 1.
    pub fn new(emissivity: f64) -> Result<Self, ThermalError> {
        check("radiation", "emissivity", emissivity, true)?;
        if emissivity > 1.0 {
            return Err(ThermalError::InvalidLawParameter {
                law: "radiation",
                parameter: "emissivity",
                requirement: "at most 1",
                value: emissivity,
            });
        }
        Ok(Radiation { emissivity })
    }

    /// h at the mean temperature `t` (°C).
    pub fn at(&self, t: f64) -> f64 {
        let tk = (t + 273.15).max(0.0);
        4.0 * STEFAN_BOLTZMANN * self.emissivity * tk.powi(3)
    }
}

/// The contact part of a [`JointConductance`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactPart {
    /// No conduction through the contact spots.
    None,
    /// A constant (state-independent) conductance.
    Constant(f64),
    /// [`PowerLaw`].
    Power(PowerLaw),
    /// [`MikicYovanovich`].
    MikicYovanovich(MikicYovanovich),
}

/// Conductance of a joint: a contact part (from the pressure), a gas part
/// (from the gap) and radiation, added.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointConductance {
    /// Contact part.
    pub contact: ContactPart,
    /// Gas in the gap (None: vacuum).
    pub gas: Option<GasGap>,
    /// Radiation (None: none).
    pub radiation: Option<Radiation>,
}

impl JointConductance {
    /// The contact part of the sum at pressure `p`.
    pub fn contact_part(&self, p: f64) -> f64 {
        match self.contact {
            ContactPart::None => 0.0,
            ContactPart::Constant(h) => h,
            ContactPart::Power(l) => l.at(p),
            ContactPart::MikicYovanovich(l) => l.at(p),
        }
    }

    /// True if the value depends on the mechanical state (pressure or gap).
    pub fn depends_on_contact(&self) -> bool {
        self.gas.is_some()
            || matches!(
                self.contact,
                ContactPart::Power(_) | ContactPart::MikicYovanovich(_)
            )
    }
}

impl ConductanceLaw for JointConductance {
    fn conductance(&self, s: &InterfacePointState) -> f64 {
        self.contact_part(s.pressure)
            + self.gas.map_or(0.0, |g| g.at(s.gap))
            + self.radiation.map_or(0.0, |r| r.at(s.temperature))
    }
}
