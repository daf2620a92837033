//! The [`ContactLaw`] trait and what a law returns.

use nalgebra::{Matrix2, Vector2};
use std::fmt::Debug;

/// Contact status of an integration point, for statistics and output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ContactStatus {
    /// The faces are separated and transmit no traction.
    Open,
    /// Closed (or bonded) and the tangential response is elastic.
    #[default]
    Stick,
    /// Closed and the tangential traction is on the slip limit.
    Slip,
}

/// What a law returns for one jump: value, consistent tangent, trial state
/// and status.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawResponse<S> {
    /// Traction `[τ, σ]` = `[t_s, t_n]` (Pa); `σ > 0` is tension.
    pub traction: Vector2<f64>,
    /// Consistent tangent `∂[τ, σ]/∂[Δu_t, Δu_n]` (Pa/m). Row 0 is `τ`,
    /// column 0 is `Δu_t`. Not symmetric for a slipping frictional law.
    pub tangent: Matrix2<f64>,
    /// Trial (updated) history state: commit it only at a converged increment.
    pub state: S,
    /// Open / stick / slip.
    pub status: ContactStatus,
    /// Plastic tangential slip `g_s` (m, signed) after this evaluation; zero
    /// for laws without slip.
    pub slip: f64,
}

/// Result of an augmented-Lagrangian multiplier update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Augmentation<S> {
    /// The state with the updated multiplier (other history unchanged).
    pub state: S,
    /// `|λ_new − λ_old|` (Pa): the caller's outer loop stops when this is
    /// small against the contact pressure.
    pub multiplier_change: f64,
}

/// Constitutive law of an interface: traction from displacement jump.
///
/// Conventions (see the crate glossary): the jump is `⟦u⟧ = [Δu_t, Δu_n]`
/// in the element's local frame, `Δu_n > 0` is opening; the traction is
/// `[τ, σ]` with `σ > 0` tension, so `σ_c = −σ ≥ 0` is the contact pressure.
///
/// Laws are pure: [`ContactLaw::evaluate`] takes the *committed* state of
/// the point (the state at the last converged increment) and returns the
/// trial state; the caller commits it only when the increment converges.
/// Implementations do not allocate.
pub trait ContactLaw: Send + Sync + Debug {
    /// History state of one integration point (committed between increments).
    type State: Clone + Copy + Debug + Default + PartialEq + Send + Sync;

    /// Traction, consistent tangent, trial state and status for `jump`
    /// starting from the `committed` state.
    fn evaluate(&self, jump: &Vector2<f64>, committed: &Self::State) -> LawResponse<Self::State>;

    /// Augmented-Lagrangian hook: a new committed state whose normal
    /// multiplier is updated from the converged jump.
    ///
    /// Usage in an outer (Uzawa) loop of one load increment: solve the
    /// increment by Newton from committed states `S`; with the converged
    /// jumps set `S ← augment(jump, S)` for every point; repeat until the
    /// largest [`Augmentation::multiplier_change`] is small. The converged
    /// contact pressure then no longer depends on the penalty. Other history
    /// (slip) is not touched. Laws without a multiplier return the state
    /// unchanged and a zero change (the default).
    fn augment(&self, jump: &Vector2<f64>, state: &Self::State) -> Augmentation<Self::State> {
        let _ = jump;
        Augmentation {
            state: *state,
            multiplier_change: 0.0,
        }
    }

    /// Friction fixed-point hook: a new committed state whose frozen slip
    /// limit is updated from the normal traction at the converged jump, and
    /// the change of the limit (Pa).
    ///
    /// Laws whose slip limit is frozen during a Newton pass (Tresca
    /// friction; see [`crate::FrictionBound::Frozen`]) turn the
    /// non-symmetric Coulomb increment into a sequence of convex, symmetric
    /// problems; the solver repeats passes, calling this between them, until
    /// the change is small. Other laws return the state unchanged and a zero
    /// change (the default).
    fn update_friction(
        &self,
        jump: &Vector2<f64>,
        state: &Self::State,
    ) -> Augmentation<Self::State> {
        let _ = jump;
        Augmentation {
            state: *state,
            multiplier_change: 0.0,
        }
    }
}
