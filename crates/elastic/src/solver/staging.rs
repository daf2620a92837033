//! Staged construction: a solver started from the committed state of
//! another solver of the same mesh, and the check that a staged model's
//! interfaces join active triangles only.

use tecon_contact::JointState;

use crate::error::ElasticError;
use crate::model::ElasticModel;

use super::{Loads, PointStates, StaticSolver};

/// Every interface of a staged model must join active triangles only.
pub(super) fn check_interfaces_active(
    model: &ElasticModel<'_>,
    inactive: &[usize],
) -> Result<(), ElasticError> {
    if inactive.is_empty() {
        return Ok(());
    }
    for itf in &model.interfaces {
        for (k, n) in itf.nodes.iter().enumerate() {
            if let Some(v) = n.iter().find(|v| inactive.binary_search(v).is_ok()) {
                return Err(ElasticError::Interface {
                    interface: itf.name.clone(),
                    element: k,
                    message: format!(
                        "node {v} belongs to no active triangle: an interface can join active regions only"
                    ),
                });
            }
        }
    }
    Ok(())
}

/// The committed state of a solver, owned, to start another solver of the
/// same mesh from it (staged construction: the next stage's model has more
/// active regions and interfaces).
#[derive(Debug, Clone)]
pub struct SolverState {
    /// Committed displacements as solved (no output gauge).
    pub displacement: Vec<f64>,
    /// Committed joint states by interface name (a seed may hold one state
    /// per element, given to each of the element's points on resuming).
    pub interfaces: Vec<(String, PointStates)>,
    /// Committed loads.
    pub loads: Loads,
}

impl SolverState {
    /// The unloaded state of a model with `n_dofs` unknowns.
    pub fn unloaded(n_dofs: usize) -> Self {
        SolverState {
            displacement: vec![0.0; n_dofs],
            interfaces: Vec::new(),
            loads: Loads::zero(),
        }
    }

    /// Seeds the frozen friction limit (the pressure in c + p tan φ) of
    /// every point of interface `name` (`elements` elements) with
    /// `pressure`, for an interface about to be activated. With frozen
    /// limits the first Tresca pass of a new interface would see the limit
    /// c = 0 everywhere: every point slips and a ring held by nothing else
    /// (a full ring, no symmetry plane) is free to spin, a singular
    /// tangent. The seed is only the starting guess of the outer loop:
    /// the passes go on until the limits equal the computed pressures.
    pub fn seed_friction_pressure(&mut self, name: &str, elements: usize, pressure: f64) {
        let st = JointState {
            friction_pressure: pressure.max(0.0),
            ..JointState::default()
        };
        self.interfaces.retain(|(n, _)| n != name);
        let mut seed = PointStates::new(elements, 1);
        for e in 0..elements {
            seed.element_mut(e)[0] = st;
        }
        self.interfaces.push((name.to_string(), seed));
    }

    /// A starting guess extrapolated from `older` through `self`:
    /// `self + w (self − older)` for the displacements, the normal
    /// multipliers λ_n and the frozen friction limits, of the interfaces
    /// both states hold with the same shape (others: `self`'s). A value
    /// whose extrapolation leaves the sign of `self`'s value (or moves a
    /// zero) keeps `self`'s value: a point that opened keeps λ_n = 0, and a
    /// friction limit stays ≥ 0. Slips and loads are `self`'s. Only a guess
    /// for [`StaticSolver::resume_warm`]; `w = 0` returns `self`.
    pub fn extrapolated(&self, older: &SolverState, w: f64) -> SolverState {
        let mut out = self.clone();
        if older.displacement.len() == self.displacement.len() {
            for (x, o) in out.displacement.iter_mut().zip(&older.displacement) {
                *x += w * (*x - o);
            }
        }
        let keep_sign = |now: f64, old: f64| {
            let v = now + w * (now - old);
            if now != 0.0 && v.signum() == now.signum() {
                v
            } else {
                now
            }
        };
        for (name, st) in &mut out.interfaces {
            let Some((_, old)) = older.interfaces.iter().find(|(n, _)| n == name) else {
                continue;
            };
            if old.n_elements() != st.n_elements() || old.per_element() != st.per_element() {
                continue;
            }
            for e in 0..st.n_elements() {
                for (p, q) in st.element_mut(e).iter_mut().zip(old.element(e)) {
                    p.lambda_n = keep_sign(p.lambda_n, q.lambda_n);
                    p.friction_pressure = keep_sign(p.friction_pressure, q.friction_pressure);
                }
            }
        }
        out
    }
}

impl StaticSolver<'_> {
    /// The committed state, owned.
    pub fn state(&self) -> SolverState {
        SolverState {
            displacement: self.u.clone(),
            interfaces: self
                .model
                .interfaces
                .iter()
                .map(|i| i.name.clone())
                .zip(self.states.iter().cloned())
                .collect(),
            loads: self.loads.clone(),
        }
    }

    /// Starts from `state` (of a solver on the same mesh): displacements,
    /// loads and the joint states of the interfaces of the same name; an
    /// interface new to this model starts from its initial state. Errors: a
    /// different number of unknowns, an interface of another length, or a
    /// node held by this model (inactive) that moved.
    pub fn resume(&mut self, state: &SolverState) -> Result<(), ElasticError> {
        let n = self.model.n_dofs();
        if state.displacement.len() != n {
            return Err(ElasticError::Input {
                what: "resumed state".into(),
                message: format!(
                    "{} displacement values for {n} unknowns (another mesh?)",
                    state.displacement.len()
                ),
            });
        }
        for node in self.model.inactive_nodes() {
            let (x, y) = (
                state.displacement[2 * node],
                state.displacement[2 * node + 1],
            );
            if x != 0.0 || y != 0.0 {
                return Err(ElasticError::Input {
                    what: "resumed state".into(),
                    message: format!(
                        "node {node} is inactive in this model but moved ({x:e}, {y:e}) m: stages can only add regions"
                    ),
                });
            }
        }
        for (k, itf) in self.model.interfaces.iter().enumerate() {
            if let Some((_, st)) = state.interfaces.iter().find(|(name, _)| *name == itf.name) {
                if st.n_elements() != itf.nodes.len() {
                    return Err(ElasticError::Interface {
                        interface: itf.name.clone(),
                        element: st.n_elements().min(itf.nodes.len()),
                        message: format!(
                            "the resumed state has {} elements, the model {}",
                            st.n_elements(),
                            itf.nodes.len()
                        ),
                    });
                }
                let per_element = self.states[k].per_element();
                if st.per_element() == per_element {
                    self.states[k].clone_from(st);
                } else if st.per_element() == 1 {
                    self.states[k] = st.broadcast(per_element);
                } else {
                    return Err(ElasticError::Interface {
                        interface: itf.name.clone(),
                        element: 0,
                        message: format!(
                            "the resumed state has {} integration points per element, the model {per_element} (another element order?)",
                            st.per_element()
                        ),
                    });
                }
            }
        }
        self.u.clone_from(&state.displacement);
        self.loads = state.loads.clone();
        self.points.clear();
        self.update_gauge();
        Ok(())
    }

    /// [`StaticSolver::resume`] from `state`, with a warm start for the next
    /// [`StaticSolver::advance`]: its Newton iterations start from
    /// `guess`'s displacements, and its outer passes from `guess`'s normal
    /// multipliers λ_n and frozen friction limits (of the interfaces whose
    /// shape matches). The history (slips, loads) is `state`'s, so the
    /// friction path is the same as after a plain resume; each Newton pass
    /// minimises a convex energy whose minimiser does not depend on where
    /// the iterations start, and the outer passes converge to the same
    /// fixed point, so the answer changes only within the solver's
    /// tolerances. Until the next `advance` the committed displacements,
    /// displacement output and interface results are `state`'s. Errors: as
    /// `resume`, or a guess with another number of unknowns.
    pub fn resume_warm(
        &mut self,
        state: &SolverState,
        guess: &SolverState,
    ) -> Result<(), ElasticError> {
        let n = self.model.n_dofs();
        if guess.displacement.len() != n {
            return Err(ElasticError::Input {
                what: "warm-start guess".into(),
                message: format!(
                    "{} displacement values for {n} unknowns (another mesh?)",
                    guess.displacement.len()
                ),
            });
        }
        if let Some(i) = guess.displacement.iter().position(|v| !v.is_finite()) {
            return Err(ElasticError::Input {
                what: "warm-start guess".into(),
                message: format!("displacement value {i} is not finite"),
            });
        }
        self.resume(state)?;
        // the committed point output stays the resumed state's
        self.points = self.point_results(&self.u, &self.states);
        for (k, itf) in self.model.interfaces.iter().enumerate() {
            let Some((_, g)) = guess.interfaces.iter().find(|(name, _)| *name == itf.name) else {
                continue;
            };
            let st = &mut self.states[k];
            if g.n_elements() != st.n_elements() || g.per_element() != st.per_element() {
                continue;
            }
            for e in 0..st.n_elements() {
                for (p, q) in st.element_mut(e).iter_mut().zip(g.element(e)) {
                    p.lambda_n = q.lambda_n;
                    p.friction_pressure = q.friction_pressure;
                }
            }
        }
        // the Newton start is the guess; inactive (held) nodes stay at zero
        self.u.clone_from(&guess.displacement);
        for node in self.model.inactive_nodes() {
            self.u[2 * node] = 0.0;
            self.u[2 * node + 1] = 0.0;
        }
        Ok(())
    }
}
