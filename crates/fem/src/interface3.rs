//! Geometry of the 6-node (three node pairs, quadratic) interface element.
//!
//! The quadratic counterpart of [`crate::interface`], shared by the
//! mechanical element (`tecon-contact`) and the thermal one
//! (`tecon-thermal`).
//!
//! ```text
//!        4 ●───────● 6 ──────● 3      top face    (upper body)
//!          ┆       ┆         ┆        4 faces 1, 6 faces 5, 3 faces 2
//!        1 ●───────● 5 ──────● 2      bottom face (lower body)
//!          s = −1   s = 0    s = +1
//! ```
//!
//! Node order `[x₁, x₂, x₃, x₄, x₅, x₆]`: the corners as for the 4-node
//! element, then the bottom mid node 5 (between 1 and 2) and the top mid
//! node 6 (between 4 and 3) — the mesh's `Interface::mid_nodes` pair.
//! The frame is taken from the **bottom face**, a 3-node edge
//! ([`crate::edge3::Edge3`] on `[x₁, x₂, x₅]`): at a point `s` the tangent
//! is `x'(s)/|x'(s)|` and the normal its left normal, pointing into the
//! top body. Shape functions `N₁ = s(s − 1)/2`, `N₂ = s(s + 1)/2`,
//! `N₅ = 1 − s²`; the jump of a nodal field `a` is
//!
//! ```text
//!   ⟦a⟧(s) = N₁ (a₄ − a₁) + N₂ (a₃ − a₂) + N₅ (a₆ − a₅) = b(s) · a,
//!   b(s)   = [−N₁, −N₂, N₂, N₁, −N₅, N₅]
//! ```
//!
//! Integration, with the isoparametric arc length `|x'(s)| ds`:
//! * nodal (default): one point per node pair, weight `∫ N_i |x'| ds` —
//!   Simpson's `L/6, 4L/6, L/6` on a straight face;
//! * Gauss: 3-point Gauss–Legendre (chosen by
//!   [`InterfaceQuadrature::Gauss2`], whose 4-node meaning is "Gauss";
//!   three points integrate `∫ b bᵀ` exactly on a straight face).

use nalgebra::{Matrix2, Point2, SMatrix, SVector, Vector2};

use crate::edge3::{Edge3, shape as shape3};
use crate::interface::{InterfaceGeometryError, InterfaceQuadrature};
use crate::quadrature::GaussLegendre;

/// Nodal vector of the 6-node interface element, order 1..6.
pub type Vector6 = SVector<f64, 6>;
/// Matrix of the 6-node interface element, order 1..6.
pub type Matrix6 = SMatrix<f64, 6, 6>;

/// One integration point of a 3-pair interface element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interface3Point {
    /// Reference coordinate `s ∈ [−1, 1]` along the bottom face.
    pub s: f64,
    /// Weight in arc length (m).
    pub weight: f64,
    /// `[N₁, N₂, N₅]` (pairs (1, 4), (2, 3), (5, 6)).
    pub shape: [f64; 3],
    /// Unit normal of the bottom face at the point (into the top body).
    pub normal: Vector2<f64>,
}

impl Interface3Point {
    /// The scalar jump operator `b = [−N₁, −N₂, N₂, N₁, −N₅, N₅]`.
    #[inline]
    pub fn jump_operator(&self) -> Vector6 {
        let [n1, n2, n5] = self.shape;
        Vector6::new(-n1, -n2, n2, n1, -n5, n5)
    }

    /// Rotation `[tᵀ; nᵀ]` of the point's frame (tangent = normal turned −90°).
    #[inline]
    pub fn rotation(&self) -> Matrix2<f64> {
        let n = self.normal;
        Matrix2::new(n.y, -n.x, n.x, n.y)
    }
}

/// Geometry of a 3-pair interface element: its bottom face and the
/// integration points of both rules.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interface3Geometry {
    bottom: Edge3,
}

impl Interface3Geometry {
    /// Geometry from `[x₁, …, x₆]` with the default facing tolerance
    /// ([`crate::interface::DEFAULT_FACING_TOLERANCE`]).
    ///
    /// # Errors
    /// See [`Interface3Geometry::with_tolerance`].
    pub fn new(nodes: &[Point2<f64>; 6]) -> Result<Self, InterfaceGeometryError> {
        Self::with_tolerance(nodes, crate::interface::DEFAULT_FACING_TOLERANCE)
    }

    /// Geometry with a facing tolerance (fraction of the chord length `L`).
    ///
    /// # Errors
    /// The errors of the 4-node geometry, with local node numbers 1..=6:
    /// non-finite coordinates, a zero-length (or folded) bottom face, a
    /// reversed top face, a pair (1, 4), (2, 3) or (5, 6) offset along the
    /// chord by more than `tolerance · L`, a bad tolerance.
    pub fn with_tolerance(
        nodes: &[Point2<f64>; 6],
        tolerance: f64,
    ) -> Result<Self, InterfaceGeometryError> {
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(InterfaceGeometryError::InvalidTolerance(tolerance));
        }
        for (i, x) in nodes.iter().enumerate() {
            if !(x.x.is_finite() && x.y.is_finite()) {
                return Err(InterfaceGeometryError::NonFiniteCoordinate { node: i + 1 });
            }
        }
        let p = |i: usize| [nodes[i].x, nodes[i].y];
        let chord = nodes[1] - nodes[0];
        let length = chord.norm();
        let scale = nodes
            .iter()
            .map(|x| x.x.abs().max(x.y.abs()))
            .fold(0.0_f64, f64::max);
        if length == 0.0 || length <= 1.0e3 * f64::EPSILON * scale {
            return Err(InterfaceGeometryError::ZeroLength { length });
        }
        let bottom = Edge3::new([p(0), p(1), p(4)])
            .map_err(|e| InterfaceGeometryError::FoldedFace(e.to_string()))?;
        let t = chord / length;
        if (nodes[2] - nodes[3]).dot(&t) <= 0.0 {
            return Err(InterfaceGeometryError::ReversedTopFace);
        }
        let allowed = tolerance * length;
        for (bottom_node, top_node) in [(1usize, 4usize), (2, 3), (5, 6)] {
            let offset = (nodes[top_node - 1] - nodes[bottom_node - 1]).dot(&t);
            if offset.abs() > allowed {
                return Err(InterfaceGeometryError::NotFacing {
                    bottom: bottom_node,
                    top: top_node,
                    offset,
                    allowed,
                });
            }
        }
        Ok(Self { bottom })
    }

    /// The bottom face as a 3-node edge `[x₁, x₂, x₅]`.
    pub fn bottom(&self) -> &Edge3 {
        &self.bottom
    }

    /// Arc length of the bottom face (m).
    pub fn length(&self) -> f64 {
        self.bottom.length()
    }

    /// The isoparametric normals of the bottom face at nodes 1, 2 and 5
    /// (`s = −1, +1, 0`). Averaging the corner normals of neighbouring
    /// elements gives the smoothed nodal normals.
    pub fn node_normals(&self) -> [Vector2<f64>; 3] {
        [-1.0, 1.0, 0.0].map(|s| self.bottom.point(s, 1.0).normal)
    }

    /// The three integration points of `rule`.
    pub fn points(&self, rule: InterfaceQuadrature) -> [Interface3Point; 3] {
        match rule {
            InterfaceQuadrature::Nodal => {
                let w = self.bottom.nodal_weights();
                // Pair order 1, 5, 2 along the face; shape = Kronecker.
                [(-1.0, 0usize), (0.0, 2), (1.0, 1)].map(|(s, a)| {
                    let mut shape = [0.0; 3];
                    shape[a] = 1.0;
                    Interface3Point {
                        s,
                        weight: w[a],
                        shape,
                        normal: self.bottom.point(s, 1.0).normal,
                    }
                })
            }
            InterfaceQuadrature::Gauss2 => {
                let g = GaussLegendre::Three.points();
                [0, 1, 2].map(|q| {
                    let (s, w) = g[q];
                    let p = self.bottom.point(s, w);
                    Interface3Point {
                        s,
                        weight: p.weight,
                        shape: shape3(s),
                        normal: p.normal,
                    }
                })
            }
        }
    }

    /// `∫ b bᵀ ds` with `rule` (node order 1..6): times `h_c` the thermal
    /// interface conductance matrix.
    pub fn jump_gram(&self, rule: InterfaceQuadrature) -> Matrix6 {
        let mut m = Matrix6::zeros();
        for p in self.points(rule) {
            let b = p.jump_operator();
            m += b * b.transpose() * p.weight;
        }
        m
    }
}

#[cfg(test)]
mod tests {
    //! Goal: Simpson weights on a straight face, arc-length weights on a
    //! curved one, exact Gram matrix with Gauss, normals from the bottom
    //! face into the top body, and every rejection of the 4-node geometry.
    use super::*;

    fn pts(x: [[f64; 2]; 6]) -> [Point2<f64>; 6] {
        x.map(|p| Point2::new(p[0], p[1]))
    }

    #[test]
    fn straight_face_has_simpson_weights_and_exact_gauss_gram() {
        let l = 0.9;
        let g = Interface3Geometry::new(&pts([
            [0.0, 0.0],
            [l, 0.0],
            [l, 0.0],
            [0.0, 0.0],
            [0.5 * l, 0.0],
            [0.5 * l, 0.0],
        ]))
        .unwrap();
        let nodal = g.points(InterfaceQuadrature::Nodal);
        let w: Vec<f64> = nodal.iter().map(|p| p.weight).collect();
        for (a, b) in w.iter().zip([l / 6.0, 4.0 * l / 6.0, l / 6.0]) {
            assert!((a - b).abs() < 1e-15, "{w:?}");
        }
        for p in nodal
            .iter()
            .chain(g.points(InterfaceQuadrature::Gauss2).iter())
        {
            assert!((p.normal - Vector2::new(0.0, 1.0)).norm() < 1e-15);
            assert!(p.jump_operator().sum().abs() < 1e-15);
            assert!((p.shape.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        }
        // Gauss: ∫ N Nᵀ = L/30 [4 −1 2; −1 4 2; 2 2 16] per pair block.
        let m = g.jump_gram(InterfaceQuadrature::Gauss2);
        let nn = |i: usize, j: usize| {
            let t = [[4.0, -1.0, 2.0], [-1.0, 4.0, 2.0], [2.0, 2.0, 16.0]];
            t[i][j] * l / 30.0
        };
        // Local node → (pair index, sign).
        let pair = [
            (0, -1.0),
            (1, -1.0),
            (1, 1.0),
            (0, 1.0),
            (2, -1.0),
            (2, 1.0),
        ];
        for i in 0..6 {
            for j in 0..6 {
                let e = pair[i].1 * pair[j].1 * nn(pair[i].0, pair[j].0);
                assert!((m[(i, j)] - e).abs() < 1e-15, "({i},{j})");
            }
        }
        // Nodal: diagonal per pair, h L/6, 4L/6.
        let m = g.jump_gram(InterfaceQuadrature::Nodal);
        assert!((m[(0, 3)] + l / 6.0).abs() < 1e-15);
        assert!((m[(4, 5)] + 4.0 * l / 6.0).abs() < 1e-15);
        assert_eq!(m[(0, 4)], 0.0);
    }

    #[test]
    fn curved_face_integrates_arc_length_and_normals_are_radial() {
        // Quarter of a 20° arc of radius 0.775 m (the vessel interface),
        // walked clockwise so the outside (top body) is on the left.
        let r = 0.775;
        let (a1, a0) = (0.5_f64, 0.5_f64 - 20f64.to_radians());
        let p = |a: f64| [r * a.cos(), r * a.sin()];
        let am = 0.5 * (a0 + a1);
        let g = Interface3Geometry::new(&pts([p(a1), p(a0), p(a0), p(a1), p(am), p(am)])).unwrap();
        let arc = r * 20f64.to_radians();
        for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
            let sum: f64 = g.points(rule).iter().map(|p| p.weight).sum();
            assert!((sum - arc).abs() < 2e-5 * arc, "{rule:?}: {sum} vs {arc}");
        }
        // Nodal normals at nodes 1, 2, 5 point radially outwards (within the
        // parabola's tangent error at the ends, O(φ²)).
        let n = g.node_normals();
        for (normal, a) in n.iter().zip([a1, a0, am]) {
            let radial = Vector2::new(a.cos(), a.sin());
            assert!((normal - radial).norm() < 1e-2, "{normal} vs {radial}");
        }
        assert!((n[2] - Vector2::new(am.cos(), am.sin())).norm() < 1e-14);
    }

    #[test]
    fn rejects_bad_elements() {
        let ok = [
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 0.0],
            [0.0, 0.0],
            [0.5, 0.0],
            [0.5, 0.0],
        ];
        assert!(Interface3Geometry::new(&pts(ok)).is_ok());
        let mut x = ok;
        x[5][0] = 0.7;
        assert!(matches!(
            Interface3Geometry::new(&pts(x)),
            Err(InterfaceGeometryError::NotFacing {
                bottom: 5,
                top: 6,
                ..
            })
        ));
        let mut x = ok;
        x.swap(2, 3);
        assert_eq!(
            Interface3Geometry::new(&pts(x)),
            Err(InterfaceGeometryError::ReversedTopFace)
        );
        let mut x = ok;
        x[4][1] = f64::NAN;
        assert_eq!(
            Interface3Geometry::new(&pts(x)),
            Err(InterfaceGeometryError::NonFiniteCoordinate { node: 5 })
        );
        assert!(matches!(
            Interface3Geometry::new(&pts([[2.0, 2.0]; 6])),
            Err(InterfaceGeometryError::ZeroLength { .. })
        ));
    }
}
