//! The 6-node (three node pairs, quadratic) mechanical interface element.

use crate::element::PointOutput;
use crate::error::ContactError;
use crate::law::{Augmentation, ContactLaw};
use nalgebra::{Matrix2, Point2, SMatrix, SVector, Vector2};
use tecon_fem::interface::InterfaceQuadrature;
use tecon_fem::interface3::{Interface3Geometry, Interface3Point};

/// Element vector of the quadratic interface element: 12 dofs
/// `[u1x, u1y, u2x, u2y, u3x, u3y, u4x, u4y, u5x, u5y, u6x, u6y]`.
pub type Vector12 = SVector<f64, 12>;
/// Element matrix, same dof order as [`Vector12`].
pub type Matrix12 = SMatrix<f64, 12, 12>;

/// Internal force, tangent and per-point output of a quadratic interface
/// element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadraticElementResponse<S> {
    /// Internal force `f = ∫ Bᵀ [τ, σ] ds` (N per unit thickness), global x, y.
    pub force: Vector12,
    /// Consistent tangent `K = ∫ Bᵀ C B ds` (N/m per unit thickness), global.
    pub tangent: Matrix12,
    /// The three integration points (nodal rule: pairs (1,4), (5,6), (2,3)
    /// in this order, i.e. along the face).
    pub points: [PointOutput<S>; 3],
}

/// A 6-node interface element: three node pairs on quadratic (possibly
/// curved) faces, unit out-of-plane thickness.
///
/// ```text
///        4 ●───────● 6 ──────● 3      top face    (upper body)
///        1 ●───────● 5 ──────● 2      bottom face (lower body)
///          s = −1   s = 0    s = +1
/// ```
///
/// Node order 1..6 as in [`tecon_fem::interface3`]. With the frame
/// `R(s) = [tᵀ; nᵀ]` of the bottom face at the point and
/// `b = [−N₁, −N₂, N₂, N₁, −N₅, N₅]` (quadratic `N`), the local jump is
///
/// ```text
///   ⟦u⟧ = [Δu_t, Δu_n] = R (N₁ (u₄ − u₁) + N₂ (u₃ − u₂) + N₅ (u₆ − u₅)) = B u,
///   B   = [b₁ R, …, b₆ R]    (2 × 12)
/// ```
///
/// and the element returns `f = ∫ Bᵀ t ds`, `K = ∫ Bᵀ C B ds`, `C` from the
/// law. Integration is nodal by default (one point per pair, weights
/// `∫ N_i ds` — Simpson's `L/6, 4L/6, L/6` on a straight face, with the
/// isoparametric arc length on a curved one): each point sees one pair,
/// which avoids traction oscillations with stiff joints; 3-point Gauss is
/// the option ([`InterfaceQuadrature::Gauss2`] selects "Gauss").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadraticInterfaceElement {
    geometry: Interface3Geometry,
    quadrature: InterfaceQuadrature,
    rotations: [Matrix2<f64>; 3],
    points: [Interface3Point; 3],
}

impl QuadraticInterfaceElement {
    /// Element from `[x₁, …, x₆]` with nodal integration.
    ///
    /// # Errors
    /// [`ContactError::Geometry`] if the geometry is rejected.
    pub fn new(nodes: &[Point2<f64>; 6]) -> Result<Self, ContactError> {
        Self::with_quadrature(nodes, InterfaceQuadrature::Nodal)
    }

    /// Element with the integration rule `quadrature`.
    ///
    /// # Errors
    /// As [`QuadraticInterfaceElement::new`].
    pub fn with_quadrature(
        nodes: &[Point2<f64>; 6],
        quadrature: InterfaceQuadrature,
    ) -> Result<Self, ContactError> {
        Ok(Self::from_geometry(
            Interface3Geometry::new(nodes)?,
            quadrature,
        ))
    }

    /// Element from an already checked geometry; each point's frame is the
    /// bottom face's own (isoparametric) frame there.
    pub fn from_geometry(geometry: Interface3Geometry, quadrature: InterfaceQuadrature) -> Self {
        let points = geometry.points(quadrature);
        Self {
            geometry,
            quadrature,
            rotations: points.map(|p| p.rotation()),
            points,
        }
    }

    /// The same element with smoothed normals at the bottom nodes 1, 2 and 5
    /// (`node_normals = [n₁, n₂, n₅]`, e.g. the corner normals averaged over
    /// the elements sharing the node; the mid node's own normal is usually
    /// kept). Each point takes `Σ N_a(s) n̂_a`, normalised, as its normal.
    ///
    /// # Errors
    /// [`ContactError::Normal`] (node 1, 2 or 5) if a normal is not finite,
    /// has zero length or turns 60° or more away from the face's own normal
    /// at that node.
    pub fn with_node_normals(
        mut self,
        node_normals: [Vector2<f64>; 3],
    ) -> Result<Self, ContactError> {
        let own = self.geometry.node_normals();
        for (k, n) in node_normals.iter().enumerate() {
            let len = n.norm();
            if !(len.is_finite() && len > 0.0) || n.dot(&own[k]) < 0.5 * len {
                return Err(ContactError::Normal {
                    node: [1, 2, 5][k],
                    normal: [n.x, n.y],
                    chord: [own[k].x, own[k].y],
                });
            }
        }
        let unit = node_normals.map(|n| n / n.norm());
        for (q, p) in self.points.iter_mut().enumerate() {
            let shape = tecon_fem::edge3::shape(p.s);
            let n = unit[0] * shape[0] + unit[1] * shape[1] + unit[2] * shape[2];
            p.normal = n / n.norm();
            self.rotations[q] = p.rotation();
        }
        Ok(self)
    }

    /// The shared geometry.
    pub fn geometry(&self) -> &Interface3Geometry {
        &self.geometry
    }

    /// The integration rule.
    pub fn quadrature(&self) -> InterfaceQuadrature {
        self.quadrature
    }

    /// The integration points.
    pub fn points(&self) -> &[Interface3Point; 3] {
        &self.points
    }

    /// Local frame `[t; n]` (rows) of integration point `q`.
    pub fn point_rotation(&self, q: usize) -> &Matrix2<f64> {
        &self.rotations[q]
    }

    /// The 2 × 12 jump operator `B` at integration point `q` (0..3).
    pub fn b_matrix(&self, q: usize) -> SMatrix<f64, 2, 12> {
        let b = self.points[q].jump_operator();
        let mut out = SMatrix::<f64, 2, 12>::zeros();
        for a in 0..6 {
            out.fixed_view_mut::<2, 2>(0, 2 * a)
                .copy_from(&(self.rotations[q] * b[a]));
        }
        out
    }

    /// Local jump `[Δu_t, Δu_n]` at integration point `q` for nodal
    /// displacements `u`.
    #[inline]
    pub fn jump_at(&self, q: usize, u: &Vector12) -> Vector2<f64> {
        let [n1, n2, n5] = self.points[q].shape;
        let d = Vector2::new(
            n1 * (u[6] - u[0]) + n2 * (u[4] - u[2]) + n5 * (u[10] - u[8]),
            n1 * (u[7] - u[1]) + n2 * (u[5] - u[3]) + n5 * (u[11] - u[9]),
        );
        self.rotations[q] * d
    }

    /// Local jumps at the three integration points.
    #[inline]
    pub fn jumps(&self, u: &Vector12) -> [Vector2<f64>; 3] {
        [0, 1, 2].map(|q| self.jump_at(q, u))
    }

    /// Internal force, consistent tangent and point output for nodal
    /// displacements `u` and the committed states of the three points.
    /// Pure; no allocation.
    pub fn evaluate<L: ContactLaw>(
        &self,
        law: &L,
        u: &Vector12,
        committed: &[L::State; 3],
    ) -> QuadraticElementResponse<L::State> {
        let mut force = Vector12::zeros();
        let mut tangent = Matrix12::zeros();
        let half = 0.5 * self.geometry.length();
        let outputs = [0usize, 1, 2].map(|q| {
            let p = &self.points[q];
            let r = &self.rotations[q];
            let jump = self.jump_at(q, u);
            let resp = law.evaluate(&jump, &committed[q]);
            let b = p.jump_operator();
            let tg = r.transpose() * resp.traction * p.weight;
            let kg = r.transpose() * resp.tangent * r * p.weight;
            for a in 0..6 {
                if b[a] == 0.0 {
                    continue;
                }
                let fa = tg * b[a];
                force[2 * a] += fa.x;
                force[2 * a + 1] += fa.y;
                for c in 0..6 {
                    if b[c] == 0.0 {
                        continue;
                    }
                    let mut blk = tangent.fixed_view_mut::<2, 2>(2 * a, 2 * c);
                    blk += kg * (b[a] * b[c]);
                }
            }
            PointOutput {
                zeta: p.s * half,
                jump,
                traction: resp.traction,
                status: resp.status,
                slip: resp.slip,
                state: resp.state,
            }
        });
        QuadraticElementResponse {
            force,
            tangent,
            points: outputs,
        }
    }

    /// Augmented-Lagrangian update of the three points from converged
    /// displacements (see [`ContactLaw::augment`]): new states and the
    /// largest multiplier change (Pa).
    pub fn augment<L: ContactLaw>(
        &self,
        law: &L,
        u: &Vector12,
        states: &[L::State; 3],
    ) -> ([L::State; 3], f64) {
        self.update_points(u, states, |j, s| law.augment(j, s))
    }

    /// Friction fixed-point update of the three points' states (see
    /// [`ContactLaw::update_friction`]); new states and the largest change.
    pub fn update_friction<L: ContactLaw>(
        &self,
        law: &L,
        u: &Vector12,
        states: &[L::State; 3],
    ) -> ([L::State; 3], f64) {
        self.update_points(u, states, |j, s| law.update_friction(j, s))
    }

    fn update_points<S: Copy>(
        &self,
        u: &Vector12,
        states: &[S; 3],
        update: impl Fn(&Vector2<f64>, &S) -> Augmentation<S>,
    ) -> ([S; 3], f64) {
        let j = self.jumps(u);
        let a = [0, 1, 2].map(|q| update(&j[q], &states[q]));
        (
            a.map(|x| x.state),
            a.iter().map(|x| x.multiplier_change).fold(0.0, f64::max),
        )
    }
}
