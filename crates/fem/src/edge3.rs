//! The 3-node (quadratic, possibly curved) edge: the boundary of a 6-node
//! triangle, used for convective and pressure loads and as the face of the
//! 3-pair interface element.
//!
//! ```text
//!   a ●──────●──────● b        s ∈ [−1, 1]: a at s = −1, b at s = +1,
//!          m (s = 0)           the mid node m at s = 0
//! ```
//!
//! `N_a = s(s − 1)/2`, `N_b = s(s + 1)/2`, `N_m = 1 − s²`;
//! `x(s) = Σ N x`, `ds_phys = |x'(s)| ds` (the isoparametric arc length),
//! unit tangent `t = x'/|x'|`, left normal `n = (−t_y, t_x)`.

// Kernels index several parallel arrays by node number; ranges read best.
#![allow(clippy::needless_range_loop)]

use nalgebra::{Matrix3, Vector2, Vector3};

use crate::quadrature::GaussLegendre;

/// Why a 3-node edge was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Edge3Error {
    /// A coordinate is NaN or infinite.
    #[error("edge node {node} (local: 0 = a, 1 = b, 2 = mid) has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// Local node 0..=2.
        node: usize,
    },
    /// The edge has (nearly) zero length or folds back on itself (the mid
    /// node lies outside the middle half of the chord).
    #[error("the 3-node edge is degenerate: |dx/ds| = {jacobian:e} at s = {s}")]
    Degenerate {
        /// `|x'(s)|` or its projection on the chord found.
        jacobian: f64,
        /// Where.
        s: f64,
    },
}

/// Shape functions `[N_a, N_b, N_m]` at `s`.
#[inline]
pub fn shape(s: f64) -> [f64; 3] {
    [0.5 * s * (s - 1.0), 0.5 * s * (s + 1.0), 1.0 - s * s]
}

/// Derivatives `[N_a', N_b', N_m']` at `s`.
#[inline]
pub fn shape_derivative(s: f64) -> [f64; 3] {
    [s - 0.5, s + 0.5, -2.0 * s]
}

/// One integration point of a 3-node edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge3Point {
    /// Reference coordinate `s ∈ [−1, 1]`.
    pub s: f64,
    /// `[N_a, N_b, N_m]`.
    pub shape: [f64; 3],
    /// Weight in arc length, `w |x'(s)|` (m).
    pub weight: f64,
    /// Unit tangent (a → b).
    pub tangent: Vector2<f64>,
    /// Unit left normal of the tangent.
    pub normal: Vector2<f64>,
}

/// A 3-node edge `[x_a, x_b, x_m]` (coordinates kept relative to `x_a`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge3 {
    origin: [f64; 2],
    rel: [[f64; 2]; 3],
}

impl Edge3 {
    /// Edge from `[x_a, x_b, x_m]`.
    ///
    /// # Errors
    /// [`Edge3Error::NonFiniteCoordinate`]; [`Edge3Error::Degenerate`] if the
    /// tangent's component along the chord is not positive at the ends
    /// (zero length, or a fold when the mid node is off the middle half).
    pub fn new(x: [[f64; 2]; 3]) -> Result<Self, Edge3Error> {
        for (node, p) in x.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(Edge3Error::NonFiniteCoordinate { node });
            }
        }
        let origin = x[0];
        let rel = x.map(|p| [p[0] - origin[0], p[1] - origin[1]]);
        let e = Edge3 { origin, rel };
        let chord = Vector2::new(rel[1][0], rel[1][1]);
        let scale = origin[0].abs().max(origin[1].abs()).max(chord.norm());
        let len = chord.norm();
        if len.is_nan() || len <= 1e3 * f64::EPSILON * scale {
            return Err(Edge3Error::Degenerate {
                jacobian: len,
                s: 0.0,
            });
        }
        for s in [-1.0, 1.0] {
            let along = e.derivative(s).dot(&chord) / len;
            if along.is_nan() || along <= 1e-9 * len {
                return Err(Edge3Error::Degenerate { jacobian: along, s });
            }
        }
        Ok(e)
    }

    /// `x'(s) = dx/ds`.
    #[inline]
    pub fn derivative(&self, s: f64) -> Vector2<f64> {
        let d = shape_derivative(s);
        Vector2::new(
            (0..3).map(|a| d[a] * self.rel[a][0]).sum(),
            (0..3).map(|a| d[a] * self.rel[a][1]).sum(),
        )
    }

    /// `x(s)`.
    #[inline]
    pub fn position(&self, s: f64) -> [f64; 2] {
        let n = shape(s);
        let mut x = self.origin;
        for a in 0..3 {
            x[0] += n[a] * self.rel[a][0];
            x[1] += n[a] * self.rel[a][1];
        }
        x
    }

    /// Point data at `s` with reference weight `w`.
    #[inline]
    pub fn point(&self, s: f64, w: f64) -> Edge3Point {
        let d = self.derivative(s);
        let j = d.norm();
        let t = d / j;
        Edge3Point {
            s,
            shape: shape(s),
            weight: w * j,
            tangent: t,
            normal: Vector2::new(-t.y, t.x),
        }
    }

    /// The points of the Gauss–Legendre rule `rule`.
    #[inline]
    pub fn gauss_points(&self, rule: GaussLegendre) -> impl Iterator<Item = Edge3Point> + '_ {
        rule.points().iter().map(|&(s, w)| self.point(s, w))
    }

    /// Arc length `∫ |x'| ds` (4-point Gauss: exact on a straight edge; on a
    /// circular arc of 30° with the mid node on it, relative error < 1e-9).
    pub fn length(&self) -> f64 {
        self.gauss_points(GaussLegendre::Four)
            .map(|p| p.weight)
            .sum()
    }

    /// Chord length `|x_b − x_a|`.
    pub fn chord_length(&self) -> f64 {
        Vector2::new(self.rel[1][0], self.rel[1][1]).norm()
    }

    /// `∫ N_i |x'| ds` per node, with 4-point Gauss: the nodal (Simpson)
    /// weights `L/6, L/6, 4L/6` on a straight edge (order a, b, m); on a
    /// curved edge they sum to the isoparametric arc length.
    pub fn nodal_weights(&self) -> [f64; 3] {
        let mut w = [0.0; 3];
        for p in self.gauss_points(GaussLegendre::Four) {
            for a in 0..3 {
                w[a] += p.weight * p.shape[a];
            }
        }
        w
    }

    /// `∫ h N Nᵀ ds` (3-point Gauss: exact on a straight edge), node order
    /// a, b, m: e.g. the convective matrix of a film coefficient `h`.
    pub fn mass_matrix(&self, h: f64) -> Matrix3<f64> {
        let mut m = Matrix3::zeros();
        for p in self.gauss_points(GaussLegendre::Three) {
            let n = Vector3::from(p.shape);
            m += n * n.transpose() * (h * p.weight);
        }
        m
    }

    /// `∫ q N ds` (3-point Gauss), node order a, b, m: the load of a uniform
    /// line density `q`.
    pub fn load_vector(&self, q: f64) -> Vector3<f64> {
        let mut f = Vector3::zeros();
        for p in self.gauss_points(GaussLegendre::Three) {
            f += Vector3::from(p.shape) * (q * p.weight);
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_edge_has_simpson_weights_and_closed_form_matrices() {
        let e = Edge3::new([[1.0, 2.0], [4.0, 6.0], [2.5, 4.0]]).unwrap();
        let l = 5.0;
        assert!((e.length() - l).abs() < 1e-14);
        let w = e.nodal_weights();
        for (a, b) in w.iter().zip([l / 6.0, l / 6.0, 4.0 * l / 6.0]) {
            assert!((a - b).abs() < 1e-14);
        }
        // ∫ N Nᵀ = L/30 [4 −1 2; −1 4 2; 2 2 16].
        let m = e.mass_matrix(30.0 / l);
        let exact = Matrix3::new(4.0, -1.0, 2.0, -1.0, 4.0, 2.0, 2.0, 2.0, 16.0);
        assert!((m - exact).amax() < 1e-13);
        assert!((e.load_vector(1.0) - Vector3::from(w)).amax() < 1e-14);
        let p = e.point(0.3, 1.0);
        assert!((p.normal - Vector2::new(-0.8, 0.6)).norm() < 1e-15);
    }

    #[test]
    fn circular_arc_length_converges_to_the_circle() {
        // Arc of radius 2, angle φ, mid node on the circle: the parabola's
        // length differs from Rφ by O(φ⁵) relative O(φ⁴).
        let mut errs = Vec::new();
        for k in 0..4 {
            let phi = 0.4 / 2f64.powi(k);
            let p = |a: f64| [2.0 * a.cos(), 2.0 * a.sin()];
            let e = Edge3::new([p(0.0), p(phi), p(0.5 * phi)]).unwrap();
            errs.push((e.length() - 2.0 * phi).abs() / (2.0 * phi));
        }
        for w in errs.windows(2) {
            let rate = (w[0] / w[1]).log2();
            assert!((rate - 4.0).abs() < 0.2, "rate {rate}, errors {errs:?}");
        }
    }

    #[test]
    fn rejects_degenerate_edges() {
        assert!(matches!(
            Edge3::new([[1.0, 1.0], [1.0, 1.0], [1.0, 1.0]]),
            Err(Edge3Error::Degenerate { .. })
        ));
        assert!(matches!(
            Edge3::new([[0.0, 0.0], [1.0, 0.0], [0.1, 0.0]]),
            Err(Edge3Error::Degenerate { .. })
        ));
        assert_eq!(
            Edge3::new([[0.0, 0.0], [1.0, 0.0], [f64::INFINITY, 0.0]]),
            Err(Edge3Error::NonFiniteCoordinate { node: 2 })
        );
    }
}
