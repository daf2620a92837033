//! Typed errors of the contact crate.

use tecon_fem::interface::InterfaceGeometryError;

/// An invalid parameter of a contact law.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LawError {
    /// A parameter is NaN or infinite.
    #[error("contact law parameter `{name}` is not finite ({value})")]
    NonFinite {
        /// Parameter name as in the glossary (`k_n`, `c`, `phi`, ...).
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A stiffness (or modulus) is negative.
    #[error("contact law stiffness `{name}` must be non-negative, got {value}")]
    NegativeStiffness {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A stiffness that must carry load is zero.
    #[error("contact law stiffness `{name}` must be positive, got {value}")]
    NonPositiveStiffness {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// The cohesion is negative.
    #[error("cohesion c must be non-negative, got {0} Pa")]
    NegativeCohesion(f64),
    /// The friction angle is outside `[0, 90°)`.
    #[error("friction angle phi must lie in [0, 90°), got {degrees}°")]
    FrictionAngle {
        /// The angle given, in degrees.
        degrees: f64,
    },
    /// The joint thickness is zero or negative.
    #[error("joint thickness t must be positive, got {0} m")]
    NonPositiveThickness(f64),
    /// The crushing strain limit `ε_n^c` is positive (it is a compressive strain).
    #[error("crushing strain eps_n^c must be <= 0, got {0}")]
    PositiveCrushingStrain(f64),
    /// A length used to size a penalty is zero or negative.
    #[error("element size h must be positive, got {0} m")]
    NonPositiveElementSize(f64),
}

/// An error building or evaluating an interface element.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ContactError {
    /// The element's geometry was rejected.
    #[error(transparent)]
    Geometry(#[from] InterfaceGeometryError),
    /// A law parameter was rejected.
    #[error(transparent)]
    Law(#[from] LawError),
    /// A smoothed normal given to an element is unusable.
    #[error(
        "normal ({:e}, {:e}) at interface node {node} is zero, not finite or turns 60° or more away from the element normal ({:e}, {:e})",
        normal[0], normal[1], chord[0], chord[1]
    )]
    Normal {
        /// Bottom node 1 or 2 of the element.
        node: usize,
        /// The normal given.
        normal: [f64; 2],
        /// The element's chord normal.
        chord: [f64; 2],
    },
}

/// Check that `value` is finite.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64, LawError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(LawError::NonFinite { name, value })
    }
}

/// Check that `value` is finite and `>= 0`.
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64, LawError> {
    let v = finite(name, value)?;
    if v < 0.0 {
        Err(LawError::NegativeStiffness { name, value })
    } else {
        Ok(v)
    }
}

/// Check that `value` is finite and `> 0`.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, LawError> {
    let v = finite(name, value)?;
    if v <= 0.0 {
        Err(LawError::NonPositiveStiffness { name, value })
    } else {
        Ok(v)
    }
}
