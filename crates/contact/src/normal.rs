//! Normal laws `σ(Δu_n)`: the Ghaboussi three-stage law (unilateral) and
//! a bilateral linear spring, both with an augmented-Lagrangian multiplier.

use crate::error::{LawError, finite, non_negative, positive};
use std::fmt::Debug;

/// Stage of a normal law at one point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NormalStage {
    /// Faces separated (`ε_n > 0` with no multiplier): zero traction, zero
    /// normal and tangential stiffness.
    Separation,
    /// Ghaboussi crushing stage `ε_n^c < ε_n ≤ 0`: `k_n = E/t`.
    Crushing,
    /// Ghaboussi contact stage `ε_n < ε_n^c` (or a positive penalty /
    /// multiplier pressure): `k_n = E_f/t`, the stiff (penalty) stage.
    Contact,
    /// A bilateral (glued) spring, which transmits tension as well.
    Bonded,
}

/// Normal traction of a normal law at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalResponse {
    /// Normal traction `σ` (Pa, tension positive).
    pub sigma: f64,
    /// Consistent normal stiffness `∂σ/∂Δu_n` (Pa/m).
    pub stiffness: f64,
    /// Stage reached.
    pub stage: NormalStage,
}

/// A normal law `σ(Δu_n; λ)` with an augmented-Lagrangian multiplier `λ`.
///
/// Pure and history free apart from `λ`, which the caller stores in the
/// point's state and updates only through [`NormalLaw::updated_multiplier`].
pub trait NormalLaw: Clone + Debug + Send + Sync {
    /// Normal traction and its derivative at the normal jump `du_n` with
    /// multiplier `lambda`.
    fn normal(&self, du_n: f64, lambda: f64) -> NormalResponse;

    /// The response on the contact branch whatever `du_n` (continued into
    /// tension where the faces are apart): the branch a Newton prediction
    /// tries for a point it expects to close. The default is
    /// [`NormalLaw::normal`] (a law without a separation branch).
    fn normal_closed(&self, du_n: f64, lambda: f64) -> NormalResponse {
        self.normal(du_n, lambda)
    }

    /// Multiplier after an augmented-Lagrangian update from the converged
    /// `du_n` (the default keeps `lambda`: pure penalty).
    fn updated_multiplier(&self, du_n: f64, lambda: f64) -> f64 {
        let _ = du_n;
        lambda
    }
}

/// Ghaboussi–Wilson–Witherspoon three-stage normal law of a joint of
/// thickness `t`, in terms of the normal strain `ε_n = Δu_n / t`:
///
/// ```text
///   separation  ε_n > 0            σ = 0                     k_n = 0 (and k_s = 0)
///   crushing    ε_n^c < ε_n ≤ 0    σ = E ε_n                 k_n = E/t
///   contact     ε_n ≤ ε_n^c        σ = E ε_n^c + E_f (ε_n − ε_n^c)   k_n = E_f/t
/// ```
///
/// The traction is continuous; at a stage boundary the stiffer (closed)
/// branch is taken, so faces that just touch (`ε_n = 0`, e.g. the
/// undeformed state) are closed and carry `k_n > 0` (and `k_s`, and the
/// cohesion) from the first Newton iteration. The paper's stage ranges
/// share their end points, so this only fixes which tangent is used there.
///
/// `ε_n^c ≤ 0`; smooth surfaces have `ε_n^c = 0` (no crushing stage) and
/// the law is then a unilateral penalty with `k_n = E_f/t`.
///
/// **Augmented Lagrangian.** The contact stage is a penalty enforcement of
/// `ε_n ≥ ε_n^c`. With a multiplier `λ ≥ 0` the extra pressure beyond the
/// crushing stage is `p_x = max(0, λ − (E_f/t)(Δu_n − t ε_n^c))`, and
/// [`NormalLaw::updated_multiplier`] returns `p_x`; with `λ = 0` this is
/// the law above. At a converged outer loop the penetration below
/// `t ε_n^c` vanishes for any `E_f`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GhaboussiNormal {
    youngs_modulus: f64,
    contact_modulus: f64,
    thickness: f64,
    crushing_strain: f64,
    k_crush: f64,
    k_contact: f64,
    closure: f64,
}

impl GhaboussiNormal {
    /// Law with crushing modulus `E` (Pa), contact modulus `E_f` (Pa), joint
    /// thickness `t` (m) and crushing strain `ε_n^c ≤ 0`.
    ///
    /// # Errors
    /// [`LawError`] if a modulus is negative (`E_f` must be positive), the
    /// thickness is not positive, `ε_n^c > 0`, or any value is not finite.
    pub fn new(
        youngs_modulus: f64,
        contact_modulus: f64,
        thickness: f64,
        crushing_strain: f64,
    ) -> Result<Self, LawError> {
        let e = non_negative("E", youngs_modulus)?;
        let e_f = positive("E_f", contact_modulus)?;
        let t = finite("t", thickness)?;
        if t <= 0.0 {
            return Err(LawError::NonPositiveThickness(t));
        }
        let eps_c = finite("eps_n^c", crushing_strain)?;
        if eps_c > 0.0 {
            return Err(LawError::PositiveCrushingStrain(eps_c));
        }
        Ok(Self {
            youngs_modulus: e,
            contact_modulus: e_f,
            thickness: t,
            crushing_strain: eps_c,
            k_crush: e / t,
            k_contact: e_f / t,
            closure: t * eps_c,
        })
    }

    /// Smooth surfaces (`ε_n^c = 0`): a unilateral penalty `k_n = E_f/t`.
    ///
    /// # Errors
    /// As [`GhaboussiNormal::new`].
    pub fn smooth(contact_modulus: f64, thickness: f64) -> Result<Self, LawError> {
        Self::new(contact_modulus, contact_modulus, thickness, 0.0)
    }

    /// A unilateral penalty with stiffness `k_n` per unit area (Pa/m): the
    /// smooth law with `t = 1 m` and `E_f = k_n · 1 m`.
    ///
    /// # Errors
    /// [`LawError`] if `k_n` is not positive and finite.
    pub fn penalty(k_n: f64) -> Result<Self, LawError> {
        let k = positive("k_n", k_n)?;
        Self::smooth(k, 1.0)
    }

    /// The documented default penalty for bodies of Young's modulus `E`
    /// meshed with element size `h`: `k_n = `[`DEFAULT_PENALTY_FACTOR`]` · E/h`
    /// (see [`default_penalty`]).
    ///
    /// # Errors
    /// As [`default_penalty`].
    pub fn default_penalty(youngs_modulus: f64, element_size: f64) -> Result<Self, LawError> {
        Self::penalty(default_penalty(youngs_modulus, element_size)?)
    }

    /// Crushing modulus `E` (Pa).
    pub fn youngs_modulus(&self) -> f64 {
        self.youngs_modulus
    }
    /// Contact modulus `E_f` (Pa).
    pub fn contact_modulus(&self) -> f64 {
        self.contact_modulus
    }
    /// Joint thickness `t` (m).
    pub fn thickness(&self) -> f64 {
        self.thickness
    }
    /// Crushing strain limit `ε_n^c ≤ 0`.
    pub fn crushing_strain(&self) -> f64 {
        self.crushing_strain
    }
    /// Contact-stage stiffness `E_f/t` (Pa/m), the penalty of the AL update.
    pub fn contact_stiffness(&self) -> f64 {
        self.k_contact
    }
    /// Crushing-stage stiffness `E/t` (Pa/m).
    pub fn crushing_stiffness(&self) -> f64 {
        self.k_crush
    }
    /// Normal strain `ε_n = Δu_n / t`.
    pub fn strain(&self, du_n: f64) -> f64 {
        du_n / self.thickness
    }
    /// Shear stiffness per unit area `k_s = G/t` (Pa/m) of this joint for a
    /// joint shear modulus `G` (Pa): the paper's "k_s = G" in strain form,
    /// to pass to [`crate::MohrCoulomb::new`] or [`crate::ElasticJoint::new`].
    pub fn shear_stiffness(&self, shear_modulus: f64) -> f64 {
        shear_modulus / self.thickness
    }
}

impl NormalLaw for GhaboussiNormal {
    #[inline]
    fn normal(&self, du_n: f64, lambda: f64) -> NormalResponse {
        // Crushing part: E·clamp(−ε_n, 0, −ε_n^c), written with Δu_n = t ε_n.
        // Touching faces (ε_n = 0) are closed, as in the contact branch below.
        let crushing = du_n <= 0.0 && du_n > self.closure;
        let p_crush = self.k_crush * (-du_n).clamp(0.0, -self.closure);
        // Contact (penalty) part beyond the crushing limit, with multiplier.
        let p_trial = lambda - self.k_contact * (du_n - self.closure);
        // Touching faces (p_trial = 0, e.g. the undeformed state) count as
        // closed: the kink belongs to the contact branch, so bodies that touch
        // initially are supported from the first Newton iteration.
        let contact = p_trial >= 0.0;
        let p_x = if contact { p_trial } else { 0.0 };
        let mut stiffness = 0.0;
        if crushing {
            stiffness += self.k_crush;
        }
        if contact {
            stiffness += self.k_contact;
        }
        let stage = if contact {
            NormalStage::Contact
        } else if crushing {
            NormalStage::Crushing
        } else {
            NormalStage::Separation
        };
        NormalResponse {
            sigma: -(p_crush + p_x),
            stiffness,
            stage,
        }
    }

    #[inline]
    fn updated_multiplier(&self, du_n: f64, lambda: f64) -> f64 {
        (lambda - self.k_contact * (du_n - self.closure)).max(0.0)
    }

    fn normal_closed(&self, du_n: f64, lambda: f64) -> NormalResponse {
        let crushing = du_n <= 0.0 && du_n > self.closure;
        let p_crush = self.k_crush * (-du_n).clamp(0.0, -self.closure);
        let p_trial = lambda - self.k_contact * (du_n - self.closure);
        let mut stiffness = self.k_contact;
        if crushing {
            stiffness += self.k_crush;
        }
        NormalResponse {
            sigma: -(p_crush + p_trial),
            stiffness,
            stage: NormalStage::Contact,
        }
    }
}

/// Bilateral linear normal spring `σ = λ + k_n Δu_n` (a glued, Goodman
/// joint that also transmits tension). With the multiplier update
/// `λ ← λ + k_n Δu_n` it enforces a tied joint (`Δu_n → 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearNormal {
    k_n: f64,
}

impl LinearNormal {
    /// Spring of stiffness `k_n ≥ 0` per unit area (Pa/m).
    ///
    /// # Errors
    /// [`LawError`] if `k_n` is negative or not finite.
    pub fn new(k_n: f64) -> Result<Self, LawError> {
        Ok(Self {
            k_n: non_negative("k_n", k_n)?,
        })
    }
    /// Stiffness `k_n` (Pa/m).
    pub fn stiffness(&self) -> f64 {
        self.k_n
    }
}

impl NormalLaw for LinearNormal {
    #[inline]
    fn normal(&self, du_n: f64, lambda: f64) -> NormalResponse {
        NormalResponse {
            sigma: lambda + self.k_n * du_n,
            stiffness: self.k_n,
            stage: NormalStage::Bonded,
        }
    }

    #[inline]
    fn updated_multiplier(&self, du_n: f64, lambda: f64) -> f64 {
        lambda + self.k_n * du_n
    }
}

/// Factor `β` of the default penalty `k_n = β E / h`.
///
/// `E/h` is the stiffness per unit area of a layer of bulk elements of size
/// `h`; `β = 10` makes the joint ten times stiffer than that layer, so the
/// penalty adds a compliance of about 1/β of one element layer (the same
/// order as common commercial defaults). The remaining penalty dependence
/// is removed by the augmented-Lagrangian update ([`crate::ContactLaw::augment`]).
pub const DEFAULT_PENALTY_FACTOR: f64 = 10.0;

/// Default penalty stiffness per unit area `k_n = β E/h` (Pa/m) with
/// `β = `[`DEFAULT_PENALTY_FACTOR`], Young's modulus `E` (Pa) of the stiffer
/// body and element size `h` (m) along the interface.
///
/// # Errors
/// [`LawError`] if `E` is not positive or `h` not positive (or not finite).
pub fn default_penalty(youngs_modulus: f64, element_size: f64) -> Result<f64, LawError> {
    let e = positive("E", youngs_modulus)?;
    let h = finite("h", element_size)?;
    if h <= 0.0 {
        return Err(LawError::NonPositiveElementSize(h));
    }
    Ok(DEFAULT_PENALTY_FACTOR * e / h)
}
