//! Staged construction (layer after layer): which triangles are in the
//! system and the reference displacements that an interface activated on a
//! deformed assembly measures its jumps from.
//!
//! A stage's model is the base model with [`ElasticModel::active_regions`]
//! set to the regions built so far and the interfaces between them, each
//! new one with [`ElasticModel::interface_reference`] = the displacements
//! at its activation; its solver starts from the previous stage's
//! [`crate::SolverState`] ([`crate::StaticSolver::resume`]).

use crate::error::ElasticError;
use crate::model::ElasticModel;

impl ElasticModel<'_> {
    /// Puts only the triangles of `regions` in the system (staged
    /// construction): the other triangles have no stiffness and no load, and
    /// the nodes that no active triangle touches are held at zero
    /// displacement (their dofs are not solved). An unknown region is an
    /// error naming it.
    pub fn active_regions(mut self, regions: &[&str]) -> Result<Self, ElasticError> {
        let mut on = vec![false; self.mesh.region_names().len()];
        for name in regions {
            on[self.mesh.region_index(name)?] = true;
        }
        self.active = Some(self.mesh.element_regions().iter().map(|&r| on[r]).collect());
        Ok(self)
    }

    /// Whether triangle `e` is in the system.
    pub fn is_active(&self, e: usize) -> bool {
        self.active.as_ref().is_none_or(|a| a[e])
    }

    /// Nodes that no active triangle touches (sorted); empty when every
    /// triangle is active.
    pub fn inactive_nodes(&self) -> Vec<usize> {
        let Some(active) = &self.active else {
            return Vec::new();
        };
        let mut used = vec![false; self.mesh.n_nodes()];
        let mark = |used: &mut Vec<bool>, nodes: &[usize]| {
            for &v in nodes {
                used[v] = true;
            }
        };
        match self.mesh.triangles6() {
            Some(t6) => t6
                .iter()
                .zip(active)
                .filter(|(_, a)| **a)
                .for_each(|(t, _)| mark(&mut used, t)),
            None => self
                .mesh
                .triangles()
                .iter()
                .zip(active)
                .filter(|(_, a)| **a)
                .for_each(|(t, _)| mark(&mut used, t)),
        }
        (0..used.len()).filter(|&v| !used[v]).collect()
    }

    /// Measures the jumps of interface `name` from the displacements
    /// `reference` (2 per node of the whole mesh, as
    /// [`crate::StaticSolver::raw_displacement`] gives them): an interface
    /// activated on a deformed assembly starts closed with a zero jump.
    pub fn interface_reference(
        mut self,
        name: &str,
        reference: Vec<f64>,
    ) -> Result<Self, ElasticError> {
        let n = 2 * self.mesh.n_nodes();
        if reference.len() < n || reference.iter().take(n).any(|v| !v.is_finite()) {
            return Err(ElasticError::Input {
                what: format!("reference displacements of interface '{name}'"),
                message: format!(
                    "need {n} finite values (2 per node), got {} (or a non-finite one)",
                    reference.len()
                ),
            });
        }
        let Some(itf) = self.interfaces.iter_mut().find(|i| i.name == name) else {
            return Err(ElasticError::Input {
                what: format!("interface '{name}'"),
                message: "not in the model (add it with `interface` first)".into(),
            });
        };
        itf.reference = Some(reference[..n].to_vec());
        Ok(self)
    }
    /// Holds the three rigid modes of a body with no symmetry supports (a
    /// full ring) by a statically determinate support on the nodes of
    /// `edge_set`: u_y = 0 at the node of largest x, u_x = 0 at the node of
    /// largest y, u_y = 0 at the node of smallest x. Three independent
    /// constraints on three rigid modes: their reactions vanish when the
    /// loads on the body are self-equilibrated (eigenstrain, contact), so
    /// the stresses do not depend on them. Errors if the three constraints
    /// are not independent (e.g. fewer than three nodes).
    pub fn hold_rigid_modes(self, edge_set: &str) -> Result<Self, ElasticError> {
        let x = self.mesh.nodes();
        let nodes = self.mesh.edge_set_nodes(edge_set)?;
        let pick = |key: &dyn Fn(usize) -> f64| {
            nodes
                .iter()
                .copied()
                .max_by(|&a, &b| key(a).total_cmp(&key(b)).then(b.cmp(&a)))
        };
        let (Some(east), Some(north), Some(west)) =
            (pick(&|v| x[v][0]), pick(&|v| x[v][1]), pick(&|v| -x[v][0]))
        else {
            return Err(ElasticError::Input {
                what: format!("edge set '{edge_set}'"),
                message: "no nodes to hold the rigid modes on".into(),
            });
        };
        // rows: the constraint applied to (t_x, t_y, ω) about the origin;
        // u = (t_x − ω y, t_y + ω x)
        let rows = [
            [0.0, 1.0, x[east][0]],
            [1.0, 0.0, -x[north][1]],
            [0.0, 1.0, x[west][0]],
        ];
        let det = rows[0][0] * (rows[1][1] * rows[2][2] - rows[1][2] * rows[2][1])
            - rows[0][1] * (rows[1][0] * rows[2][2] - rows[1][2] * rows[2][0])
            + rows[0][2] * (rows[1][0] * rows[2][1] - rows[1][1] * rows[2][0]);
        let scale = x[east][0]
            .abs()
            .max(x[west][0].abs())
            .max(x[north][1].abs());
        if det.is_nan() || det.abs() <= 1e-6 * scale {
            return Err(ElasticError::Input {
                what: format!("edge set '{edge_set}'"),
                message: format!(
                    "nodes {east}, {north}, {west} cannot hold the three rigid modes (not spread around the ring)"
                ),
            });
        }
        let mut m = self;
        m.fixed.push((2 * east + 1, 0.0));
        m.fixed.push((2 * north, 0.0));
        m.fixed.push((2 * west + 1, 0.0));
        Ok(m)
    }
}
