//! The 4-node mechanical interface element.

use crate::error::ContactError;
use crate::law::{Augmentation, ContactLaw, ContactStatus};
use nalgebra::{Matrix2, Point2, SMatrix, SVector, Vector2};
use tecon_fem::interface::{InterfaceGeometry, InterfacePoint, InterfaceQuadrature};

/// Element vector: 8 dofs `[u1x, u1y, u2x, u2y, u3x, u3y, u4x, u4y]`.
pub type Vector8 = SVector<f64, 8>;
/// Element matrix, same dof order as [`Vector8`].
pub type Matrix8 = SMatrix<f64, 8, 8>;

/// Output of one integration point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointOutput<S> {
    /// Local coordinate `ζ` of the point (m).
    pub zeta: f64,
    /// Jump `⟦u⟧ = [Δu_t, Δu_n]` (m), local frame.
    pub jump: Vector2<f64>,
    /// Traction `[τ, σ]` (Pa), local frame, tension positive.
    pub traction: Vector2<f64>,
    /// Open / stick / slip.
    pub status: ContactStatus,
    /// Plastic tangential slip `g_s` (m).
    pub slip: f64,
    /// Trial history state (commit at a converged increment).
    pub state: S,
}

/// Internal force, tangent and per-point output of an interface element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElementResponse<S> {
    /// Internal force `f = ∫ Bᵀ [τ, σ] dζ` (N per unit thickness), global x, y.
    pub force: Vector8,
    /// Consistent tangent `K = ∫ Bᵀ C B dζ` (N/m per unit thickness), global.
    pub tangent: Matrix8,
    /// The two integration points.
    pub points: [PointOutput<S>; 2],
}

/// A 4-node interface element (Goodman type) of unit out-of-plane thickness.
///
/// ```text
///        4 ●───────────────● 3      top face    (upper body)
///        1 ●───────────────● 2      bottom face (lower body)
/// ```
///
/// Nodes 1, 2 on the bottom face, 3, 4 on the top face; 4 faces 1 and 3
/// faces 2; the top body lies on the left of 1 → 2. With the frame
/// `R = [tᵀ; nᵀ]` of the bottom face and `b = [−N₁, −N₂, N₂, N₁]`, the
/// local jump at `ζ` is
///
/// ```text
///   ⟦u⟧ = [Δu_t, Δu_n] = R (N₁ (u₄ − u₁) + N₂ (u₃ − u₂)) = B u,
///   B   = [b₁ R, b₂ R, b₃ R, b₄ R]    (2 × 8)
/// ```
///
/// and the element returns `f = ∫ Bᵀ t dζ` and `K = ∫ Bᵀ C B dζ` with
/// `C = ∂t/∂⟦u⟧` from the law, in global components. Small displacements:
/// the frame is that of the reference configuration. Integration is nodal
/// (Newton–Cotes/Lobatto) by default, which avoids traction oscillations
/// with stiff joints; 2-point Gauss is an option.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfaceElement {
    geometry: InterfaceGeometry,
    quadrature: InterfaceQuadrature,
    /// Local frame `[t; n]` of each integration point (the element's chord
    /// frame unless smoothed normals were given).
    rotations: [Matrix2<f64>; 2],
    points: [InterfacePoint; 2],
}

impl InterfaceElement {
    /// Element from node coordinates `[x₁, x₂, x₃, x₄]` with nodal integration.
    ///
    /// # Errors
    /// [`ContactError::Geometry`] if the geometry is rejected (zero length,
    /// nodes not facing, non-finite coordinates).
    pub fn new(nodes: &[Point2<f64>; 4]) -> Result<Self, ContactError> {
        Self::with_quadrature(nodes, InterfaceQuadrature::Nodal)
    }

    /// Element with the integration rule `quadrature`.
    ///
    /// # Errors
    /// As [`InterfaceElement::new`].
    pub fn with_quadrature(
        nodes: &[Point2<f64>; 4],
        quadrature: InterfaceQuadrature,
    ) -> Result<Self, ContactError> {
        Ok(Self::from_geometry(
            InterfaceGeometry::new(nodes)?,
            quadrature,
        ))
    }

    /// Element from an already checked geometry.
    pub fn from_geometry(geometry: InterfaceGeometry, quadrature: InterfaceQuadrature) -> Self {
        Self {
            geometry,
            quadrature,
            rotations: [geometry.rotation(); 2],
            points: geometry.points(quadrature),
        }
    }

    /// The same element with smoothed normals: `node_normals` are the
    /// normals at the bottom nodes 1 and 2 (e.g. averaged over the elements
    /// that share each node); each integration point takes their
    /// interpolation, normalised, as its normal, and the tangent follows
    /// (normal = tangent turned +90°).
    ///
    /// On a curved interface the chord frames of two neighbouring elements
    /// differ, so a tangential slip `s` at a shared node shows up as normal
    /// jumps `±s·sin(Δθ/2)` of opposite sign in the two elements: with
    /// nodal integration one point opens while its twin stays closed. With
    /// one normal per node both elements see the same jump there.
    ///
    /// # Errors
    /// [`ContactError::Normal`] if a normal is not finite, has zero length
    /// or turns 60° or more away from the element's chord normal.
    pub fn with_node_normals(
        mut self,
        node_normals: [Vector2<f64>; 2],
    ) -> Result<Self, ContactError> {
        let chord = self.geometry.normal();
        for (node, n) in node_normals.iter().enumerate() {
            let len = n.norm();
            if !(len.is_finite() && len > 0.0) || n.dot(&chord) < 0.5 * len {
                return Err(ContactError::Normal {
                    node: node + 1,
                    normal: [n.x, n.y],
                    chord: [chord.x, chord.y],
                });
            }
        }
        for (q, p) in self.points.iter().enumerate() {
            let [n1, n2] = p.shape;
            let n = (node_normals[0] / node_normals[0].norm()) * n1
                + (node_normals[1] / node_normals[1].norm()) * n2;
            let n = n / n.norm();
            self.rotations[q] = Matrix2::new(n.y, -n.x, n.x, n.y);
        }
        Ok(self)
    }

    /// Local frame `[t; n]` (rows) of integration point `q`.
    pub fn point_rotation(&self, q: usize) -> &Matrix2<f64> {
        &self.rotations[q]
    }

    /// The shared geometry (length, frame).
    pub fn geometry(&self) -> &InterfaceGeometry {
        &self.geometry
    }

    /// The integration rule.
    pub fn quadrature(&self) -> InterfaceQuadrature {
        self.quadrature
    }

    /// The integration points (`ζ`, weight, shape values).
    pub fn points(&self) -> &[InterfacePoint; 2] {
        &self.points
    }

    /// The 2 × 8 jump operator `B` at integration point `q` (0 or 1).
    pub fn b_matrix(&self, q: usize) -> SMatrix<f64, 2, 8> {
        let b = self.points[q].jump_operator();
        let mut out = SMatrix::<f64, 2, 8>::zeros();
        for a in 0..4 {
            out.fixed_view_mut::<2, 2>(0, 2 * a)
                .copy_from(&(self.rotations[q] * b[a]));
        }
        out
    }

    /// Local jump `[Δu_t, Δu_n]` at integration point `q` (0 or 1) for
    /// nodal displacements `u`.
    #[inline]
    pub fn jump_at(&self, q: usize, u: &Vector8) -> Vector2<f64> {
        let [n1, n2] = self.points[q].shape;
        let d = Vector2::new(
            n1 * (u[6] - u[0]) + n2 * (u[4] - u[2]),
            n1 * (u[7] - u[1]) + n2 * (u[5] - u[3]),
        );
        self.rotations[q] * d
    }

    /// Local jumps at both integration points.
    #[inline]
    pub fn jumps(&self, u: &Vector8) -> [Vector2<f64>; 2] {
        [self.jump_at(0, u), self.jump_at(1, u)]
    }

    /// Internal force, consistent tangent and point output for nodal
    /// displacements `u` (global, dof order of [`Vector8`]) and the
    /// committed states of the two points. Pure; no allocation.
    pub fn evaluate<L: ContactLaw>(
        &self,
        law: &L,
        u: &Vector8,
        committed: &[L::State; 2],
    ) -> ElementResponse<L::State> {
        let mut force = Vector8::zeros();
        let mut tangent = Matrix8::zeros();
        let outputs = [0usize, 1].map(|q| {
            let p = &self.points[q];
            let r = &self.rotations[q];
            let jump = self.jump_at(q, u);
            let resp = law.evaluate(&jump, &committed[q]);
            let b = p.jump_operator();
            // Global traction and tangent: Rᵀ t, Rᵀ C R.
            let tg = r.transpose() * resp.traction * p.weight;
            let kg = r.transpose() * resp.tangent * r * p.weight;
            for a in 0..4 {
                if b[a] == 0.0 {
                    continue;
                }
                let fa = tg * b[a];
                force[2 * a] += fa.x;
                force[2 * a + 1] += fa.y;
                for c in 0..4 {
                    if b[c] == 0.0 {
                        continue;
                    }
                    let mut blk = tangent.fixed_view_mut::<2, 2>(2 * a, 2 * c);
                    blk += kg * (b[a] * b[c]);
                }
            }
            PointOutput {
                zeta: p.zeta,
                jump,
                traction: resp.traction,
                status: resp.status,
                slip: resp.slip,
                state: resp.state,
            }
        });
        ElementResponse {
            force,
            tangent,
            points: outputs,
        }
    }

    /// Augmented-Lagrangian update of both points from converged
    /// displacements `u` (see [`ContactLaw::augment`]): the new committed
    /// states and the largest multiplier change (Pa).
    pub fn augment<L: ContactLaw>(
        &self,
        law: &L,
        u: &Vector8,
        states: &[L::State; 2],
    ) -> ([L::State; 2], f64) {
        self.update_points(u, states, |j, s| law.augment(j, s))
    }

    /// Friction fixed-point update of both points' states from the jumps at
    /// `u` (see [`ContactLaw::update_friction`]); returns the new states and
    /// the larger change.
    pub fn update_friction<L: ContactLaw>(
        &self,
        law: &L,
        u: &Vector8,
        states: &[L::State; 2],
    ) -> ([L::State; 2], f64) {
        self.update_points(u, states, |j, s| law.update_friction(j, s))
    }

    /// Applies a between-passes update to both points' states at their
    /// jumps; the new states and the larger change.
    fn update_points<S: Copy>(
        &self,
        u: &Vector8,
        states: &[S; 2],
        update: impl Fn(&Vector2<f64>, &S) -> Augmentation<S>,
    ) -> ([S; 2], f64) {
        let j = self.jumps(u);
        let a = [update(&j[0], &states[0]), update(&j[1], &states[1])];
        (
            [a[0].state, a[1].state],
            a[0].multiplier_change.max(a[1].multiplier_change),
        )
    }
}
