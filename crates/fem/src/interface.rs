//! Geometry of the 4-node (zero- or finite-thickness) interface element.
//!
//! This module is the single home of the 1D geometry shared by the
//! mechanical interface element (`tecon-contact`) and the thermal interface
//! element (`tecon-thermal`): the length and local frame of the element, the
//! two integration rules, and the scalar jump operator.
//!
//! ```text
//!        4 ●───────────────● 3      top face    (upper body)
//!          ┆               ┆        4 faces 1, 3 faces 2
//!        1 ●───────────────● 2      bottom face (lower body)
//!          ζ = −L/2   →    ζ = +L/2
//!
//!   t = (x₂ − x₁)/L       n = (−t_y, t_x)   (left normal of t, bottom → top)
//! ```
//!
//! The frame is taken from the **bottom face**: the mesh orders nodes 1 → 2
//! so that the top body lies on the left of that direction, hence `n` points
//! from the bottom body into the top body and a positive normal jump is an
//! opening.
//!
//! Shape functions along the element, `ζ ∈ [−L/2, L/2]`:
//! `N₁ = (1 − 2ζ/L)/2`, `N₂ = (1 + 2ζ/L)/2`. The jump of any nodal field
//! `a` (a temperature, or one displacement component) at `ζ` is
//!
//! ```text
//!   ⟦a⟧(ζ) = N₁ (a₄ − a₁) + N₂ (a₃ − a₂) = b(ζ) · [a₁, a₂, a₃, a₄],
//!   b(ζ)   = [−N₁, −N₂, N₂, N₁]                    (the scalar jump operator)
//! ```
//!
//! A thermal interface element with conductance `h_c` is then
//! `h_c ∫ b bᵀ dζ` ([`InterfaceGeometry::jump_gram`]); the mechanical
//! element applies `b` to each displacement component and rotates with the
//! frame `R = [tᵀ; nᵀ]` ([`InterfaceGeometry::rotation`]).

use nalgebra::{Matrix2, Matrix4, Point2, Vector2, Vector4};

/// Relative tolerance used by [`InterfaceGeometry::new`] for the facing
/// check: the tangential offset of a facing node pair may be at most this
/// fraction of the element length.
///
/// The value admits finite-thickness joints on a curved interface (on a
/// circle of radius `R` a joint of thickness `t` offsets facing nodes by
/// about `t/(2R)·L` along the chord) and rejects swapped or shifted node
/// numbering, which offsets a pair by a sizeable fraction of `L`.
pub const DEFAULT_FACING_TOLERANCE: f64 = 1.0e-2;

/// Integration rule along an interface element. Both rules have two points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum InterfaceQuadrature {
    /// Nodal (2-point Newton–Cotes / Lobatto) rule: points at the element
    /// ends `ζ = ∓L/2`, weights `L/2`. Each point sees only one node pair,
    /// which decouples the pairs and avoids the traction oscillations that
    /// Gauss integration produces with stiff joints. The default.
    #[default]
    Nodal,
    /// 2-point Gauss rule: `ζ = ∓L/(2√3)`, weights `L/2`. Integrates
    /// `∫ b bᵀ dζ` exactly (the "consistent" coupling of the node pairs).
    Gauss2,
}

impl InterfaceQuadrature {
    /// Number of integration points (both rules have two).
    pub const POINTS: usize = 2;

    /// Reference coordinates `ξ = 2ζ/L ∈ [−1, 1]` of the two points.
    pub fn reference_points(self) -> [f64; 2] {
        match self {
            InterfaceQuadrature::Nodal => [-1.0, 1.0],
            InterfaceQuadrature::Gauss2 => {
                let g = 1.0 / 3.0_f64.sqrt();
                [-g, g]
            }
        }
    }
}

/// One integration point of an interface element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfacePoint {
    /// Local coordinate `ζ ∈ [−L/2, L/2]` (metres).
    pub zeta: f64,
    /// Integration weight (metres; the weights of a rule sum to `L`).
    pub weight: f64,
    /// Shape function values `[N₁(ζ), N₂(ζ)]`.
    pub shape: [f64; 2],
}

impl InterfacePoint {
    /// The scalar jump operator `b = [−N₁, −N₂, N₂, N₁]` over nodes 1..4:
    /// `⟦a⟧ = b · [a₁, a₂, a₃, a₄]`.
    #[inline]
    pub fn jump_operator(&self) -> Vector4<f64> {
        let [n1, n2] = self.shape;
        Vector4::new(-n1, -n2, n2, n1)
    }
}

/// Why an interface element's geometry was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InterfaceGeometryError {
    /// A node coordinate is NaN or infinite.
    #[error("interface node {node} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// Local node number, 1..=4.
        node: usize,
    },
    /// The bottom face (nodes 1 → 2), which defines the frame, has no length.
    #[error("interface bottom face 1→2 has zero length ({length:e} m)")]
    ZeroLength {
        /// The computed length |x₂ − x₁|.
        length: f64,
    },
    /// The top face runs opposite to the bottom face: 4 → 3 must point the
    /// same way as 1 → 2 (4 faces 1, 3 faces 2).
    #[error("interface top face 4→3 runs opposite to the bottom face 1→2 (nodes 3 and 4 swapped?)")]
    ReversedTopFace,
    /// A facing node pair is offset along the element by more than the
    /// tolerance: node 4 must face node 1 and node 3 must face node 2.
    #[error(
        "interface node {top} does not face node {bottom}: tangential offset {offset:e} m exceeds {allowed:e} m"
    )]
    NotFacing {
        /// The bottom node of the pair (1 or 2).
        bottom: usize,
        /// The top node of the pair (4 or 3).
        top: usize,
        /// Offset of the pair along the bottom face, `(x_top − x_bottom)·t`.
        offset: f64,
        /// Largest offset admitted, `tolerance · L`.
        allowed: f64,
    },
    /// The bottom face of a 3-pair element folds back on itself: its mid
    /// node lies outside the middle half of the chord 1→2.
    #[error(
        "interface bottom face 1→5→2 folds back (mid node 5 outside the middle half of the face): {0}"
    )]
    FoldedFace(String),
    /// The facing tolerance is negative or not finite.
    #[error("interface facing tolerance must be finite and non-negative, got {0}")]
    InvalidTolerance(f64),
}

/// Length, frame and integration points of a 4-node interface element,
/// computed once from its reference coordinates (small-displacement
/// kinematics: the frame does not follow the deformation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfaceGeometry {
    length: f64,
    tangent: Vector2<f64>,
    normal: Vector2<f64>,
}

impl InterfaceGeometry {
    /// Geometry from the node coordinates `[x₁, x₂, x₃, x₄]` (1, 2 bottom,
    /// 3, 4 top; 4 faces 1, 3 faces 2), with the default facing tolerance
    /// [`DEFAULT_FACING_TOLERANCE`].
    ///
    /// # Errors
    /// See [`InterfaceGeometry::with_tolerance`].
    pub fn new(nodes: &[Point2<f64>; 4]) -> Result<Self, InterfaceGeometryError> {
        Self::with_tolerance(nodes, DEFAULT_FACING_TOLERANCE)
    }

    /// Geometry with an explicit facing tolerance (a fraction of `L`).
    ///
    /// # Errors
    /// * [`InterfaceGeometryError::NonFiniteCoordinate`] for NaN/∞ input,
    /// * [`InterfaceGeometryError::ZeroLength`] if `|x₂ − x₁|` is zero or
    ///   negligible against the coordinates' magnitude,
    /// * [`InterfaceGeometryError::ReversedTopFace`] if `(x₃ − x₄)·t ≤ 0`,
    /// * [`InterfaceGeometryError::NotFacing`] if `|(x₄ − x₁)·t|` or
    ///   `|(x₃ − x₂)·t|` exceeds `tolerance · L`,
    /// * [`InterfaceGeometryError::InvalidTolerance`] for a bad tolerance.
    pub fn with_tolerance(
        nodes: &[Point2<f64>; 4],
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
        let d = nodes[1] - nodes[0];
        let length = d.norm();
        // Scale of the coordinates, so that "zero length" is relative to
        // round-off of the input rather than an absolute number of metres.
        let scale = nodes
            .iter()
            .map(|x| x.x.abs().max(x.y.abs()))
            .fold(0.0_f64, f64::max);
        if length == 0.0 || length <= 1.0e3 * f64::EPSILON * scale {
            return Err(InterfaceGeometryError::ZeroLength { length });
        }
        let tangent = d / length;
        let normal = Vector2::new(-tangent.y, tangent.x);
        if (nodes[2] - nodes[3]).dot(&tangent) <= 0.0 {
            return Err(InterfaceGeometryError::ReversedTopFace);
        }
        let allowed = tolerance * length;
        for (bottom, top) in [(1usize, 4usize), (2, 3)] {
            let offset = (nodes[top - 1] - nodes[bottom - 1]).dot(&tangent);
            if offset.abs() > allowed {
                return Err(InterfaceGeometryError::NotFacing {
                    bottom,
                    top,
                    offset,
                    allowed,
                });
            }
        }
        Ok(Self {
            length,
            tangent,
            normal,
        })
    }

    /// Element length `L = |x₂ − x₁|` (metres).
    #[inline]
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Unit tangent `t = (x₂ − x₁)/L`.
    #[inline]
    pub fn tangent(&self) -> Vector2<f64> {
        self.tangent
    }

    /// Unit normal `n = (−t_y, t_x)`, from the bottom body into the top body.
    #[inline]
    pub fn normal(&self) -> Vector2<f64> {
        self.normal
    }

    /// Rotation from global to local components, `R = [tᵀ; nᵀ]`:
    /// `[v_t, v_n] = R [v_x, v_y]`.
    #[inline]
    pub fn rotation(&self) -> Matrix2<f64> {
        Matrix2::new(self.tangent.x, self.tangent.y, self.normal.x, self.normal.y)
    }

    /// The two integration points of `rule`: `ζ`, weight and `[N₁, N₂]`.
    #[inline]
    pub fn points(&self, rule: InterfaceQuadrature) -> [InterfacePoint; 2] {
        let half = 0.5 * self.length;
        rule.reference_points().map(|xi| InterfacePoint {
            zeta: xi * half,
            weight: half,
            shape: [0.5 * (1.0 - xi), 0.5 * (1.0 + xi)],
        })
    }

    /// `∫ b bᵀ dζ` over the element with `rule`, `b = [−N₁, −N₂, N₂, N₁]`.
    ///
    /// With [`InterfaceQuadrature::Gauss2`] this is the exact (consistent)
    /// matrix, `L/6` times the `[2 1; 1 2]` pattern per face pair; with
    /// [`InterfaceQuadrature::Nodal`] it is the lumped one, `L/2` per facing
    /// pair. A thermal interface element with conductance `h_c` (W/(m² K))
    /// has conductance matrix `h_c · jump_gram` (unit out-of-plane
    /// thickness), node order 1, 2, 3, 4.
    pub fn jump_gram(&self, rule: InterfaceQuadrature) -> Matrix4<f64> {
        let mut m = Matrix4::zeros();
        for p in self.points(rule) {
            let b = p.jump_operator();
            m += (b * b.transpose()) * p.weight;
        }
        m
    }
}

#[cfg(test)]
mod tests {
    //! Reference: the definitions in DESIGN.md §2 "Interface element".
    //! Goal: the shared geometry gives the frame, rules and jump operator the
    //! mechanical and thermal elements rely on, and rejects bad elements.
    //! Checked: frame orientation for arbitrary directions, partition of
    //! unity and exactness of both rules, the closed-form Gram matrices, and
    //! every error variant.
    use super::*;
    use approx::assert_relative_eq;

    fn quad(x1: [f64; 2], x2: [f64; 2], x3: [f64; 2], x4: [f64; 2]) -> [Point2<f64>; 4] {
        [x1, x2, x3, x4].map(|p| Point2::new(p[0], p[1]))
    }

    #[test]
    fn frame_is_left_normal_of_bottom_face_for_any_direction() {
        for k in 0..16 {
            let a = 0.3 + k as f64 * std::f64::consts::TAU / 16.0;
            let (s, c) = a.sin_cos();
            let x1 = Point2::new(1.0, -2.0);
            let x2 = x1 + Vector2::new(c, s) * 0.5;
            let g = InterfaceGeometry::new(&[x1, x2, x2, x1]).unwrap();
            assert_relative_eq!(g.length(), 0.5, epsilon = 1e-15);
            assert_relative_eq!(g.tangent(), Vector2::new(c, s), epsilon = 1e-15);
            assert_relative_eq!(g.normal(), Vector2::new(-s, c), epsilon = 1e-15);
            // R is a proper rotation: R Rᵀ = I, det R = +1.
            let r = g.rotation();
            assert_relative_eq!(r * r.transpose(), Matrix2::identity(), epsilon = 1e-15);
            assert_relative_eq!(r.determinant(), 1.0, epsilon = 1e-15);
            assert_relative_eq!(r * g.normal(), Vector2::new(0.0, 1.0), epsilon = 1e-15);
        }
    }

    #[test]
    fn normal_points_into_the_top_body() {
        // Bottom face along +x, top body above (finite thickness 0.01).
        let g = InterfaceGeometry::new(&quad([0., 0.], [2., 0.], [2., 0.01], [0., 0.01])).unwrap();
        assert_relative_eq!(g.normal(), Vector2::new(0.0, 1.0));
    }

    #[test]
    fn rules_have_partition_of_unity_and_integrate_linears_exactly() {
        let g = InterfaceGeometry::new(&quad([0., 0.], [3., 4.], [3., 4.], [0., 0.])).unwrap();
        let l = g.length();
        for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
            let pts = g.points(rule);
            let w: f64 = pts.iter().map(|p| p.weight).sum();
            assert_relative_eq!(w, l, epsilon = 1e-14);
            for p in pts {
                assert_relative_eq!(p.shape[0] + p.shape[1], 1.0, epsilon = 1e-15);
                assert_relative_eq!(p.shape[0], 0.5 * (1.0 - 2.0 * p.zeta / l), epsilon = 1e-15);
                // b sums to zero: a uniform field has no jump.
                assert_relative_eq!(p.jump_operator().sum(), 0.0, epsilon = 1e-15);
            }
            // ∫ ζ dζ = 0 and ∫ N₂ dζ = L/2 for both rules.
            let m1: f64 = pts.iter().map(|p| p.weight * p.zeta).sum();
            let n2: f64 = pts.iter().map(|p| p.weight * p.shape[1]).sum();
            assert_relative_eq!(m1, 0.0, epsilon = 1e-14);
            assert_relative_eq!(n2, 0.5 * l, epsilon = 1e-14);
        }
        let nodal = g.points(InterfaceQuadrature::Nodal);
        assert_eq!(nodal[0].zeta, -0.5 * l);
        assert_eq!(nodal[1].zeta, 0.5 * l);
        assert_eq!(nodal[0].shape, [1.0, 0.0]);
        assert_eq!(nodal[1].shape, [0.0, 1.0]);
        // Gauss integrates ζ² exactly: ∫ ζ² dζ = L³/12; the nodal rule gives L³/4.
        let g2: f64 = g
            .points(InterfaceQuadrature::Gauss2)
            .iter()
            .map(|p| p.weight * p.zeta * p.zeta)
            .sum();
        assert_relative_eq!(g2, l.powi(3) / 12.0, epsilon = 1e-13);
    }

    #[test]
    fn jump_gram_matches_closed_forms() {
        let l = 0.7;
        let g = InterfaceGeometry::new(&quad([0., 0.], [0., l], [0., l], [0., 0.])).unwrap();
        // Consistent: ∫ Nᵢ Nⱼ = L/6 [2 1; 1 2]; b = [−N₁, −N₂, N₂, N₁].
        let s = l / 6.0;
        let consistent = Matrix4::new(
            2. * s,
            s,
            -s,
            -2. * s, //
            s,
            2. * s,
            -2. * s,
            -s, //
            -s,
            -2. * s,
            2. * s,
            s, //
            -2. * s,
            -s,
            s,
            2. * s,
        );
        assert_relative_eq!(
            g.jump_gram(InterfaceQuadrature::Gauss2),
            consistent,
            epsilon = 1e-14
        );
        let h = l / 2.0;
        let lumped = Matrix4::new(
            h, 0., 0., -h, //
            0., h, -h, 0., //
            0., -h, h, 0., //
            -h, 0., 0., h,
        );
        assert_relative_eq!(
            g.jump_gram(InterfaceQuadrature::Nodal),
            lumped,
            epsilon = 1e-14
        );
    }

    #[test]
    fn rejects_bad_elements() {
        let nan = f64::NAN;
        assert_eq!(
            InterfaceGeometry::new(&quad([0., 0.], [1., 0.], [1., nan], [0., 0.])),
            Err(InterfaceGeometryError::NonFiniteCoordinate { node: 3 })
        );
        assert!(matches!(
            InterfaceGeometry::new(&quad([5., 5.], [5., 5.], [5., 5.], [5., 5.])),
            Err(InterfaceGeometryError::ZeroLength { .. })
        ));
        // Length at round-off level of large coordinates is also "zero".
        assert!(matches!(
            InterfaceGeometry::new(&quad(
                [1e6, 0.],
                [1e6 + 1e-9, 0.],
                [1e6 + 1e-9, 0.],
                [1e6, 0.]
            )),
            Err(InterfaceGeometryError::ZeroLength { .. })
        ));
        // Nodes 3 and 4 swapped.
        assert_eq!(
            InterfaceGeometry::new(&quad([0., 0.], [1., 0.], [0., 0.], [1., 0.])),
            Err(InterfaceGeometryError::ReversedTopFace)
        );
        // Top face shifted by a quarter element: node 4 does not face node 1.
        assert!(matches!(
            InterfaceGeometry::new(&quad([0., 0.], [1., 0.], [1.25, 0.], [0.25, 0.])),
            Err(InterfaceGeometryError::NotFacing {
                bottom: 1,
                top: 4,
                ..
            })
        ));
        // Only node 3 is off.
        assert!(matches!(
            InterfaceGeometry::new(&quad([0., 0.], [1., 0.], [1.1, 0.], [0., 0.])),
            Err(InterfaceGeometryError::NotFacing {
                bottom: 2,
                top: 3,
                ..
            })
        ));
        // ...but accepted with a looser tolerance.
        assert!(
            InterfaceGeometry::with_tolerance(&quad([0., 0.], [1., 0.], [1.1, 0.], [0., 0.]), 0.2)
                .is_ok()
        );
        assert_eq!(
            InterfaceGeometry::with_tolerance(&quad([0., 0.], [1., 0.], [1., 0.], [0., 0.]), -1.0),
            Err(InterfaceGeometryError::InvalidTolerance(-1.0))
        );
    }

    #[test]
    fn finite_thickness_joint_on_a_circle_is_accepted() {
        // Chord of a circle r = 0.775 m, 10° apart, joint thickness 1 mm:
        // facing nodes along the radius, offset ~ t/(2R)·L along the chord.
        let (r, t) = (0.775, 1.0e-3);
        let (a0, a1) = (0.3_f64, 0.3_f64 + 10f64.to_radians());
        let p = |rad: f64, a: f64| Point2::new(rad * a.cos(), rad * a.sin());
        // Walking clockwise keeps the outside (the layer, top body) on the
        // left: node 1 at a1, node 2 at a0.
        let nodes = [p(r, a1), p(r, a0), p(r + t, a0), p(r + t, a1)];
        let g = InterfaceGeometry::new(&nodes).unwrap();
        // Normal points outwards (from core to layer) at the chord midpoint.
        let mid = 0.5 * (a0 + a1);
        assert_relative_eq!(
            g.normal(),
            Vector2::new(mid.cos(), mid.sin()),
            epsilon = 1e-12
        );
    }
}
