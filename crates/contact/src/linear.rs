//! The linear (Goodman) joint.

use crate::error::{LawError, non_negative};
use crate::law::{ContactLaw, ContactStatus, LawResponse};
use nalgebra::{Matrix2, Vector2};

/// Linear joint of Goodman type: `[τ, σ] = diag(k_s, k_n) [Δu_t, Δu_n]`
/// with constant stiffnesses per unit area (Pa/m). Bonded: it transmits
/// tension and never opens or slips (status is always
/// [`ContactStatus::Stick`]). No history (`State = ()`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearJoint {
    k_s: f64,
    k_n: f64,
}

impl LinearJoint {
    /// Joint with shear stiffness `k_s` and normal stiffness `k_n` (Pa/m).
    ///
    /// # Errors
    /// [`LawError`] if a stiffness is negative or not finite.
    pub fn new(k_s: f64, k_n: f64) -> Result<Self, LawError> {
        Ok(Self {
            k_s: non_negative("k_s", k_s)?,
            k_n: non_negative("k_n", k_n)?,
        })
    }
    /// Shear stiffness `k_s` (Pa/m).
    pub fn k_s(&self) -> f64 {
        self.k_s
    }
    /// Normal stiffness `k_n` (Pa/m).
    pub fn k_n(&self) -> f64 {
        self.k_n
    }
}

impl ContactLaw for LinearJoint {
    type State = ();

    #[inline]
    fn evaluate(&self, jump: &Vector2<f64>, _committed: &()) -> LawResponse<()> {
        let tangent = Matrix2::new(self.k_s, 0.0, 0.0, self.k_n);
        LawResponse {
            traction: tangent * jump,
            tangent,
            state: (),
            status: ContactStatus::Stick,
            slip: 0.0,
        }
    }
}
