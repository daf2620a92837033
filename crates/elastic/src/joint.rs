//! A joint law chosen at run time, for models whose interfaces are set from
//! input (case files).

use tecon_contact::nalgebra::Vector2;
use tecon_contact::{
    Augmentation, ContactLaw, ElasticJoint, FrictionBound, GhaboussiNormal, JointState,
    LawResponse, LinearJoint, PaperJoint,
};

/// The interface laws an elastic model can use.
#[derive(Debug, Clone)]
pub enum Joint {
    /// Goodman linear joint (bilateral springs).
    Linear(LinearJoint),
    /// Ghaboussi normal law with elastic shear (no slip limit: bonded in shear).
    Sticking(ElasticJoint<GhaboussiNormal>),
    /// The paper's joint: Ghaboussi normal law + Mohr–Coulomb friction.
    Frictional(PaperJoint),
}

impl Joint {
    /// The same joint with a frictional law's slip limit taken as `bound`
    /// says (the other laws have no slip limit and are unchanged).
    pub fn with_friction_bound(&self, bound: FrictionBound) -> Joint {
        match self {
            Joint::Frictional(l) => Joint::Frictional(l.with_friction_bound(bound)),
            other => other.clone(),
        }
    }

    /// A copy of `committed` that slips at `jump` (see
    /// [`tecon_contact::MohrCoulomb::slipping_state`]); None for the laws
    /// without a frozen slip limit.
    pub fn slipping_state(
        &self,
        jump: &Vector2<f64>,
        committed: &JointState,
    ) -> Option<JointState> {
        match self {
            Joint::Frictional(l) => l.slipping_state(jump, committed),
            _ => None,
        }
    }
}

impl ContactLaw for Joint {
    type State = JointState;

    #[inline]
    fn evaluate(&self, jump: &Vector2<f64>, committed: &JointState) -> LawResponse<JointState> {
        match self {
            Joint::Linear(l) => {
                let r = l.evaluate(jump, &());
                LawResponse {
                    traction: r.traction,
                    tangent: r.tangent,
                    state: *committed,
                    status: r.status,
                    slip: r.slip,
                }
            }
            Joint::Sticking(l) => l.evaluate(jump, committed),
            Joint::Frictional(l) => l.evaluate(jump, committed),
        }
    }

    fn augment(&self, jump: &Vector2<f64>, state: &JointState) -> Augmentation<JointState> {
        match self {
            Joint::Linear(_) => Augmentation {
                state: *state,
                multiplier_change: 0.0,
            },
            Joint::Sticking(l) => l.augment(jump, state),
            Joint::Frictional(l) => l.augment(jump, state),
        }
    }

    fn update_friction(&self, jump: &Vector2<f64>, state: &JointState) -> Augmentation<JointState> {
        match self {
            Joint::Frictional(l) => l.update_friction(jump, state),
            _ => Augmentation {
                state: *state,
                multiplier_change: 0.0,
            },
        }
    }
}
