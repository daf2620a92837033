//! Joints made of a normal law and a tangential law: an elastic joint and
//! the Mohr–Coulomb (elastic–perfectly plastic) frictional joint. The
//! paper's joint is [`PaperJoint`] = Ghaboussi normal + Mohr–Coulomb.

use crate::error::{LawError, finite, positive};
use crate::law::{Augmentation, ContactLaw, ContactStatus, LawResponse};
use crate::normal::{GhaboussiNormal, NormalLaw, NormalResponse, NormalStage, default_penalty};
use nalgebra::{Matrix2, Vector2};

/// History state of one integration point of a [`MohrCoulomb`] or
/// [`ElasticJoint`] law.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointState {
    /// Plastic tangential slip `g_s` (m, signed): the part of `Δu_t` that
    /// does not stretch the shear spring, `τ = k_s (Δu_t − g_s)` in stick.
    pub slip: f64,
    /// Accumulated (dissipative) slip `∫ |dg_s|` while in contact (m).
    /// Free sliding of open faces is not counted.
    pub accumulated_slip: f64,
    /// Augmented-Lagrangian normal multiplier `λ` (Pa), updated only by
    /// [`ContactLaw::augment`]. Zero for a pure penalty.
    pub lambda_n: f64,
    /// Contact pressure `p_f ≥ 0` (Pa) that a [`MohrCoulomb`] law with
    /// [`FrictionBound::Frozen`] puts in its limit `c + p_f tan φ`; updated
    /// only by [`ContactLaw::update_friction`].
    pub friction_pressure: f64,
    /// The point's cohesion is gone ([`MohrCoulomb`], "Debonding"): it was
    /// open at a [`ContactLaw::update_friction`], and its slip limit is
    /// `σ_c tan φ` alone from then on. False (bonded) from the unloaded
    /// state; set only by that update (for a law with cohesion), and never
    /// unset.
    pub cohesion_lost: bool,
    /// Newton damping hook, never committed: when true, a slipping point of
    /// a [`FrictionBound::Frozen`] law reports the secant shear stiffness
    /// `k_s s / |τ_trial|` (between the stick value `k_s` and the exact 0)
    /// as its tangent; the traction and the trial state do not change. A
    /// solver sets it on a copy of the committed states, used only for the
    /// tangent, at points whose stick/slip status oscillates between
    /// Newton iterates.
    pub secant_slip: bool,
    /// Newton prediction hook, never committed: when true, the normal law
    /// takes its contact branch whatever the jump (continued into tension
    /// where the faces are apart; [`NormalLaw::normal_closed`]). A solver
    /// sets it on a copy of the committed states, used for a predicted
    /// Newton step only.
    pub forced_closed: bool,
    /// Newton prediction hook, never committed: when true, a point whose
    /// slip limit is positive (closed, or open under a frozen limit)
    /// sticks whatever its trial traction (the stick branch of the return
    /// mapping continued past the limit).
    /// A solver sets it on a copy of the committed states, used for a
    /// predicted Newton step only.
    pub forced_stick: bool,
}

/// Relative distance from the slip limit within which a slipping point of a
/// frozen-limit law takes the stick stiffness as its tangent.
const KINK_TOLERANCE: f64 = 1e-6;

/// How far past its limit [`MohrCoulomb::slipping_state`] puts a point's
/// trial traction, relative to the limit: well past [`KINK_TOLERANCE`], so
/// the point takes the slipping tangent.
const FORCED_SLIP_MARGIN: f64 = 1e-3;

/// How a [`MohrCoulomb`] law takes the normal pressure into its slip limit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FrictionBound {
    /// The limit `c + σ_c tan φ` follows the current normal traction; the
    /// tangent of a slipping point couples shear to the normal jump and is
    /// not symmetric.
    #[default]
    Coupled,
    /// The limit uses the pressure stored in the state
    /// ([`JointState::friction_pressure`]): within one Newton pass the law is
    /// Tresca friction, the increment is the minimum of a convex energy and
    /// the tangent is symmetric. Between passes the solver calls
    /// [`ContactLaw::update_friction`]; at the fixed point the stored
    /// pressure equals the contact pressure and the answer is the
    /// Mohr–Coulomb one.
    Frozen,
}

/// The slip limit `s` of the state `st`: infinite where a positive limit
/// is forced to stick ([`JointState::forced_stick`]).
#[inline]
fn limit_of(s: f64, st: &JointState) -> f64 {
    if st.forced_stick && s > 0.0 {
        f64::INFINITY
    } else {
        s
    }
}

/// The normal response at `du_n` for the state `st` (its contact branch
/// when [`JointState::forced_closed`]).
#[inline]
fn normal_of<N: NormalLaw>(normal: &N, du_n: f64, st: &JointState) -> NormalResponse {
    if st.forced_closed {
        normal.normal_closed(du_n, st.lambda_n)
    } else {
        normal.normal(du_n, st.lambda_n)
    }
}

/// Shared augmented-Lagrangian update of a joint with normal law `N`.
#[inline]
fn augment_normal<N: NormalLaw>(
    normal: &N,
    jump: &Vector2<f64>,
    state: &JointState,
) -> Augmentation<JointState> {
    let lambda = normal.updated_multiplier(jump.y, state.lambda_n);
    Augmentation {
        state: JointState {
            lambda_n: lambda,
            ..*state
        },
        multiplier_change: (lambda - state.lambda_n).abs(),
    }
}

/// A joint with normal law `N` and a linear shear spring `k_s` that
/// transmits shear only while the faces are not separated (in the
/// separation stage `k_n = k_s = 0` and the traction is zero). No slip
/// limit: the Ghaboussi joint of the paper below its Mohr–Coulomb limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElasticJoint<N: NormalLaw = GhaboussiNormal> {
    normal: N,
    k_s: f64,
}

impl<N: NormalLaw> ElasticJoint<N> {
    /// Joint with normal law `normal` and shear stiffness `k_s > 0` (Pa/m).
    ///
    /// # Errors
    /// [`LawError`] if `k_s` is not positive and finite.
    pub fn new(normal: N, k_s: f64) -> Result<Self, LawError> {
        Ok(Self {
            normal,
            k_s: positive("k_s", k_s)?,
        })
    }
    /// The normal law.
    pub fn normal_law(&self) -> &N {
        &self.normal
    }
    /// Shear stiffness `k_s` (Pa/m).
    pub fn k_s(&self) -> f64 {
        self.k_s
    }
}

impl<N: NormalLaw> ContactLaw for ElasticJoint<N> {
    type State = JointState;

    #[inline]
    fn evaluate(&self, jump: &Vector2<f64>, committed: &JointState) -> LawResponse<JointState> {
        let nr = normal_of(&self.normal, jump.y, committed);
        let (tau, k_s, status) = if nr.stage == NormalStage::Separation {
            (0.0, 0.0, ContactStatus::Open)
        } else {
            (self.k_s * jump.x, self.k_s, ContactStatus::Stick)
        };
        LawResponse {
            traction: Vector2::new(tau, nr.sigma),
            tangent: Matrix2::new(k_s, 0.0, 0.0, nr.stiffness),
            state: *committed,
            status,
            slip: committed.slip,
        }
    }

    fn augment(&self, jump: &Vector2<f64>, state: &JointState) -> Augmentation<JointState> {
        augment_normal(&self.normal, jump, state)
    }
}

/// Mohr–Coulomb joint: normal law `N` and an elastic–perfectly plastic
/// tangential law with shear stiffness `k_s`, cohesion `c` and friction
/// angle `φ`.
///
/// Shear strength (the slip limit) from the compressive normal traction
/// `σ_c = −σ`:
///
/// ```text
///   s(σ_c) = max(0, c + σ_c tan φ),     |τ| ≤ s.
/// ```
///
/// Return mapping from the committed slip `g_s`: trial
/// `τ_tr = k_s (Δu_t − g_s)`; if `|τ_tr| ≤ s` the point sticks
/// (`τ = τ_tr`); otherwise it slips, `τ = sign(τ_tr) s`,
/// `g_s ← g_s + sign(τ_tr)(|τ_tr| − s)/k_s`. Exact consistent tangent:
///
/// ```text
///   stick: [[k_s, 0], [0, k_n]]
///   slip:  [[0, sign(τ_tr) ∂s/∂Δu_n], [0, k_n]],   ∂s/∂Δu_n = −tan φ · k_n  (s > 0)
/// ```
///
/// non-symmetric when slipping. `k_n = ∂σ/∂Δu_n` from the normal law.
///
/// **Open faces and tension cut-off.** When the normal law is in its
/// separation stage (Ghaboussi, `ε_n > 0`) the joint transmits no traction
/// at all, whatever the cohesion (`k_n = k_s = 0`); the faces slide freely,
/// so `g_s` follows `Δu_t` and the shear spring is unstretched when the
/// faces close again (this free sliding is not added to
/// [`JointState::accumulated_slip`]). Exception, [`FrictionBound::Frozen`]:
/// an open point keeps its frozen limit `max(0, c_f + p_f tan φ)` (stored
/// pressure `p_f`, held cohesion `c_f`) while open, as a Tresca shear
/// (return mapping as above, normal traction 0), so the shear traction is
/// continuous at opening and a Newton pass minimises a convex energy with a
/// continuous gradient (a limit that vanished at opening made the exact
/// line search stop at the kink of points about to open). At the fixed
/// point of the passes an open point has `p_f = 0` (the pressure it
/// carries) and `c_f = 0` (below), and transmits nothing, as above.
///
/// **Debonding.** The cohesion is a bond that breaks for good: a point
/// that is open at a friction update ([`ContactLaw::update_friction`],
/// which frozen-limit solvers call between passes and at the end of an
/// increment) loses it ([`JointState::cohesion_lost`]), and from then on
/// its limit is `σ_c tan φ` alone, closed or open, frozen or coupled. A
/// bond that healed whenever the faces touched let a point at the edge of
/// a lift-off flip for ever between open without shear and closed with
/// the cohesion (no equilibrium exists for such a point). Without
/// cohesion the flag changes nothing. With a bilateral normal law
/// ([`crate::LinearNormal`]) the strength falls linearly in tension and is
/// cut off at zero beyond the apex `σ = c / tan φ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MohrCoulomb<N: NormalLaw = GhaboussiNormal> {
    normal: N,
    k_s: f64,
    cohesion: f64,
    friction_angle: f64,
    tan_phi: f64,
    bound: FrictionBound,
}

/// The paper's joint: Ghaboussi three-stage normal law + Mohr–Coulomb
/// tangential law, zero traction when open.
pub type PaperJoint = MohrCoulomb<GhaboussiNormal>;

impl<N: NormalLaw> MohrCoulomb<N> {
    /// Mohr–Coulomb joint with normal law `normal`, shear stiffness
    /// `k_s > 0` (Pa/m), cohesion `c ≥ 0` (Pa) and friction angle
    /// `φ ∈ [0, π/2)` in **radians**.
    ///
    /// # Errors
    /// [`LawError`] for a non-positive `k_s`, negative `c`, `φ` outside
    /// `[0, 90°)`, or non-finite values.
    pub fn new(normal: N, k_s: f64, cohesion: f64, friction_angle: f64) -> Result<Self, LawError> {
        let k_s = positive("k_s", k_s)?;
        let c = finite("c", cohesion)?;
        if c < 0.0 {
            return Err(LawError::NegativeCohesion(c));
        }
        let phi = finite("phi", friction_angle)?;
        if !(0.0..std::f64::consts::FRAC_PI_2).contains(&phi) {
            return Err(LawError::FrictionAngle {
                degrees: phi.to_degrees(),
            });
        }
        Ok(Self {
            normal,
            k_s,
            cohesion: c,
            friction_angle: phi,
            tan_phi: phi.tan(),
            bound: FrictionBound::Coupled,
        })
    }

    /// The same law with the slip limit taken as `bound` says.
    pub fn with_friction_bound(mut self, bound: FrictionBound) -> Self {
        self.bound = bound;
        self
    }

    /// How the slip limit takes the normal pressure.
    pub fn friction_bound(&self) -> FrictionBound {
        self.bound
    }

    /// The normal law.
    pub fn normal_law(&self) -> &N {
        &self.normal
    }
    /// Shear stiffness `k_s` (Pa/m).
    pub fn k_s(&self) -> f64 {
        self.k_s
    }
    /// Cohesion `c` (Pa).
    pub fn cohesion(&self) -> f64 {
        self.cohesion
    }
    /// Friction angle `φ` (radians).
    pub fn friction_angle(&self) -> f64 {
        self.friction_angle
    }
    /// Friction coefficient `tan φ`.
    pub fn tan_phi(&self) -> f64 {
        self.tan_phi
    }
    /// The cohesion in the point's slip limit: `c` unless its bond broke
    /// (it was open at a friction update: [`JointState::cohesion_lost`]).
    #[inline]
    fn held_cohesion(&self, st: &JointState) -> f64 {
        if st.cohesion_lost { 0.0 } else { self.cohesion }
    }

    /// The frozen slip limit of the state `st`, the same closed or open:
    /// `max(0, c_f + p_f tan φ)` with the stored pressure `p_f` and the
    /// held cohesion `c_f` (see [`MohrCoulomb::held_cohesion`]).
    #[inline]
    fn frozen_limit(&self, st: &JointState) -> f64 {
        (self.held_cohesion(st) + self.tan_phi * st.friction_pressure).max(0.0)
    }

    /// Shear strength `s = max(0, c + σ_c tan φ)` at normal traction `σ`
    /// (tension positive).
    pub fn strength(&self, sigma: f64) -> f64 {
        (self.cohesion - sigma * self.tan_phi).max(0.0)
    }

    /// A copy of `committed` in which a closed point with a frozen slip
    /// limit `s > 0` slips at `jump`, in the direction of its shear there:
    /// its plastic slip set so that the trial traction is just past the
    /// limit (by [`FORCED_SLIP_MARGIN`]). Evaluated at `jump` the copy
    /// gives the traction ±s and the slipping tangent. For a solver that
    /// tries a Newton step on the branch where a sticking point slips (a
    /// copy used for that step only, never committed). None where the law
    /// has no frozen limit, the point is open, its limit is 0 or its shear
    /// is exactly 0 (no direction).
    pub fn slipping_state(
        &self,
        jump: &Vector2<f64>,
        committed: &JointState,
    ) -> Option<JointState> {
        if self.bound != FrictionBound::Frozen {
            return None;
        }
        let nr = normal_of(&self.normal, jump.y, committed);
        if nr.stage == NormalStage::Separation {
            return None;
        }
        let s = self.frozen_limit(committed);
        let tau_trial = self.k_s * (jump.x - committed.slip);
        if s <= 0.0 || tau_trial == 0.0 || !tau_trial.is_finite() {
            return None;
        }
        Some(JointState {
            slip: jump.x - tau_trial.signum() * s * (1.0 + FORCED_SLIP_MARGIN) / self.k_s,
            ..*committed
        })
    }

    /// Tresca return mapping with limit `s > 0` from the committed slip
    /// `g_s`: `(τ, ∂τ/∂Δu_t, new g_s)` (stick: `k_s`; slip: 0).
    #[inline]
    fn tresca(&self, du_t: f64, slip: f64, s: f64) -> (f64, f64, f64) {
        let tau_trial = self.k_s * (du_t - slip);
        if tau_trial.abs() <= s {
            (tau_trial, self.k_s, slip)
        } else {
            let sign = tau_trial.signum();
            (
                sign * s,
                0.0,
                slip + sign * (tau_trial.abs() - s) / self.k_s,
            )
        }
    }
}

impl PaperJoint {
    /// Frictional contact with the documented default penalty: smooth
    /// Ghaboussi normal law with `k_n = `[`default_penalty`]`(E, h)` and
    /// `k_s = k_n`, cohesion `c` (Pa) and friction angle `φ` (radians).
    ///
    /// # Errors
    /// As [`default_penalty`] and [`MohrCoulomb::new`].
    pub fn with_default_penalty(
        youngs_modulus: f64,
        element_size: f64,
        cohesion: f64,
        friction_angle: f64,
    ) -> Result<Self, LawError> {
        let k = default_penalty(youngs_modulus, element_size)?;
        Self::new(GhaboussiNormal::penalty(k)?, k, cohesion, friction_angle)
    }
}

impl<N: NormalLaw> ContactLaw for MohrCoulomb<N> {
    type State = JointState;

    #[inline]
    fn evaluate(&self, jump: &Vector2<f64>, committed: &JointState) -> LawResponse<JointState> {
        let nr = normal_of(&self.normal, jump.y, committed);
        let k_n = nr.stiffness;
        if nr.stage == NormalStage::Separation {
            // Frozen limit: the stored pressure's part of the limit and the
            // held cohesion stay on while the faces open (see the type's
            // doc), so the shear traction does not jump at opening.
            let s_open = limit_of(self.frozen_limit(committed), committed);
            if self.bound == FrictionBound::Frozen && s_open > 0.0 {
                let (tau, k_t, slip) = self.tresca(jump.x, committed.slip, s_open);
                // sliding on the limit: the same tangent as a closed
                // slipping point (the stick one at the kink, the secant one
                // when the solver damps an oscillating point)
                let k_t = if k_t == 0.0 {
                    let trial = (self.k_s * (jump.x - committed.slip)).abs();
                    if trial - s_open <= KINK_TOLERANCE * s_open {
                        self.k_s
                    } else if committed.secant_slip {
                        self.k_s * s_open / trial
                    } else {
                        0.0
                    }
                } else {
                    k_t
                };
                return LawResponse {
                    traction: Vector2::new(tau, nr.sigma),
                    tangent: Matrix2::new(k_t, 0.0, 0.0, k_n),
                    state: JointState { slip, ..*committed },
                    status: ContactStatus::Open,
                    slip,
                };
            }
            // Open: no traction; the faces slide freely.
            let state = JointState {
                slip: jump.x,
                ..*committed
            };
            return LawResponse {
                traction: Vector2::new(0.0, nr.sigma),
                tangent: Matrix2::new(0.0, 0.0, 0.0, k_n),
                state,
                status: ContactStatus::Open,
                slip: state.slip,
            };
        }
        let (s, ds_dun) = match self.bound {
            FrictionBound::Coupled => {
                let s_raw = self.held_cohesion(committed) - nr.sigma * self.tan_phi;
                if s_raw > 0.0 {
                    (s_raw, -self.tan_phi * k_n)
                } else {
                    (0.0, 0.0)
                }
            }
            FrictionBound::Frozen => (self.frozen_limit(committed), 0.0),
        };
        let s = limit_of(s, committed);
        let tau_trial = self.k_s * (jump.x - committed.slip);
        // A point without strength (s = 0: frictionless, or no pressure and
        // no cohesion) slides freely: τ = 0 either way, and calling it
        // stuck when its trial traction is 0 to the last bit (Δu_t equal
        // to the committed slip) only flipped its status at round-off,
        // which kept converged Newton passes iterating. It keeps the stick
        // tangent there (the other one-sided derivative, as at the kink
        // below): from an unloaded state the first Newton step then holds
        // the faces together, which saves an iteration.
        if s > 0.0 && tau_trial.abs() <= s {
            LawResponse {
                traction: Vector2::new(tau_trial, nr.sigma),
                tangent: Matrix2::new(self.k_s, 0.0, 0.0, k_n),
                state: *committed,
                status: ContactStatus::Stick,
                slip: committed.slip,
            }
        } else {
            let sign = tau_trial.signum();
            let d_gamma = (tau_trial.abs() - s) / self.k_s;
            let state = JointState {
                slip: committed.slip + sign * d_gamma,
                accumulated_slip: committed.accumulated_slip + d_gamma,
                ..*committed
            };
            // Frozen limit: a point on the limit to round-off (e.g. one that
            // slipped in the last increment, whose trial traction is the old
            // limit again) takes the stick stiffness — the other one-sided
            // derivative at the kink. With the soft one, a Newton step that
            // turns the point back into stick overshoots and the line search
            // can only creep.
            let frozen = self.bound == FrictionBound::Frozen;
            let k_t = if (frozen || s <= 0.0) && tau_trial.abs() - s <= KINK_TOLERANCE * s {
                self.k_s
            } else if frozen && committed.secant_slip {
                self.k_s * s / tau_trial.abs()
            } else {
                0.0
            };
            LawResponse {
                traction: Vector2::new(sign * s, nr.sigma),
                tangent: Matrix2::new(k_t, sign * ds_dun, 0.0, k_n),
                state,
                status: ContactStatus::Slip,
                slip: state.slip,
            }
        }
    }

    fn augment(&self, jump: &Vector2<f64>, state: &JointState) -> Augmentation<JointState> {
        augment_normal(&self.normal, jump, state)
    }

    /// Stores the compressive normal traction at `jump` (with the state's
    /// multiplier) as the pressure of the frozen slip limit, and takes the
    /// cohesion of a point open at `jump` for good (see the type's doc,
    /// "Debonding"); the change is that of the limit, `tan φ |Δp_f|`, plus
    /// `c` where the cohesion goes (Pa). No change in
    /// [`FrictionBound::Coupled`] mode.
    fn update_friction(&self, jump: &Vector2<f64>, state: &JointState) -> Augmentation<JointState> {
        if self.bound == FrictionBound::Coupled {
            return Augmentation {
                state: *state,
                multiplier_change: 0.0,
            };
        }
        let nr = self.normal.normal(jump.y, state.lambda_n);
        let p = -nr.sigma;
        // debonding for good: a point open at an update keeps no cohesion
        // (without cohesion there is no bond, and the flag stays unset)
        let lost =
            state.cohesion_lost || (self.cohesion > 0.0 && nr.stage == NormalStage::Separation);
        // (a bond that breaks changes the limit by c)
        let cohesion_change = if lost == state.cohesion_lost {
            0.0
        } else {
            self.cohesion
        };
        Augmentation {
            state: JointState {
                friction_pressure: p,
                cohesion_lost: lost,
                ..*state
            },
            multiplier_change: self.tan_phi * (p - state.friction_pressure).abs() + cohesion_change,
        }
    }
}
