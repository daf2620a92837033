//! The 6-node (quadratic, isoparametric) triangle and its reference kernels.
//!
//! ```text
//!   η
//!   2 ●                node order: corners 0, 1, 2, then the mid-edge
//!     │ ╲              nodes of edges (0,1), (1,2), (2,0) — the order of
//!   5 ●   ● 4          VTK_QUADRATIC_TRIANGLE and Gmsh element type 9
//!     │     ╲
//!   0 ●──●──● 1  ξ
//!        3
//! ```
//!
//! With `L₁ = 1 − ξ − η`, `L₂ = ξ`, `L₃ = η`:
//! `N₀ = L₁(2L₁ − 1)`, `N₁ = L₂(2L₂ − 1)`, `N₂ = L₃(2L₃ − 1)`,
//! `N₃ = 4L₁L₂`, `N₄ = 4L₂L₃`, `N₅ = 4L₃L₁`.
//! The geometry is interpolated with the same functions, `x(ξ) = Σ N_a x_a`,
//! so a mid node placed on a circle makes the edge a parabola through three
//! points of the circle (a curved element). `J = ∂x/∂ξ` (2×2),
//! `∇N = J⁻ᵀ ∂N/∂ξ`, `dA = det J dξ dη`.
//!
//! Kernels integrate with a [`TriangleRule`]; on a straight-sided element
//! `det J` is constant, so stiffness (degree 2) is exact with
//! [`TriangleRule::Degree2`] and mass (degree 4) with [`TriangleRule::Degree4`].

// Kernels index several parallel arrays by node number; ranges read best.
#![allow(clippy::needless_range_loop)]

use nalgebra::{Matrix3, SMatrix, SVector};

use crate::quadrature::TriangleRule;

/// Element vector of a scalar field on a 6-node triangle.
pub type Vector6 = SVector<f64, 6>;
/// Element matrix of a scalar field on a 6-node triangle.
pub type Matrix6 = SMatrix<f64, 6, 6>;
/// Element matrix of plane displacement, dofs `[u0x, u0y, …, u5x, u5y]`.
pub type Matrix12 = SMatrix<f64, 12, 12>;
/// Element vector of plane displacement.
pub type Vector12 = SVector<f64, 12>;

/// Why a 6-node triangle's geometry was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Triangle6Error {
    /// A node coordinate is NaN or infinite.
    #[error("node {node} (local 0..5) has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// Local node number 0..=5.
        node: usize,
    },
    /// The isoparametric map folds over or is degenerate somewhere in the
    /// element (clockwise corners, or a mid node too far off its edge).
    #[error(
        "the isoparametric map is not one-to-one: det J = {det:e} ≤ 0 at (ξ, η) = ({}, {}) (clockwise nodes or a misplaced mid node)",
        xi[0],
        xi[1]
    )]
    NonPositiveJacobian {
        /// det J found.
        det: f64,
        /// Reference point where it was found.
        xi: [f64; 2],
    },
}

/// Shape functions `N_a(ξ, η)`, `a = 0..5`.
#[inline]
pub fn shape(xi: [f64; 2]) -> [f64; 6] {
    let (l2, l3) = (xi[0], xi[1]);
    let l1 = 1.0 - l2 - l3;
    [
        l1 * (2.0 * l1 - 1.0),
        l2 * (2.0 * l2 - 1.0),
        l3 * (2.0 * l3 - 1.0),
        4.0 * l1 * l2,
        4.0 * l2 * l3,
        4.0 * l3 * l1,
    ]
}

/// Reference derivatives `(∂N_a/∂ξ, ∂N_a/∂η)`.
#[inline]
pub fn shape_derivatives(xi: [f64; 2]) -> ([f64; 6], [f64; 6]) {
    let (l2, l3) = (xi[0], xi[1]);
    let l1 = 1.0 - l2 - l3;
    // ∂L₁/∂ξ = −1, ∂L₂/∂ξ = 1, ∂L₃/∂ξ = 0 (and η alike with L₃).
    let d1 = 1.0 - 4.0 * l1; // ∂N₀/∂L₁ · ∂L₁/∂· = −(4L₁ − 1)
    (
        [
            d1,
            4.0 * l2 - 1.0,
            0.0,
            4.0 * (l1 - l2),
            4.0 * l3,
            -4.0 * l3,
        ],
        [
            d1,
            0.0,
            4.0 * l3 - 1.0,
            -4.0 * l2,
            4.0 * l2,
            4.0 * (l1 - l3),
        ],
    )
}

/// Reference coordinates of the six nodes.
pub const NODES: [[f64; 2]; 6] = [
    [0.0, 0.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [0.5, 0.0],
    [0.5, 0.5],
    [0.0, 0.5],
];

/// Shape values and physical gradients at one integration point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle6Point {
    /// Reference coordinates `(ξ, η)`.
    pub xi: [f64; 2],
    /// `N_a`.
    pub shape: [f64; 6],
    /// `∂N_a/∂x`.
    pub dndx: [f64; 6],
    /// `∂N_a/∂y`.
    pub dndy: [f64; 6],
    /// `det J`.
    pub det_j: f64,
    /// Integration weight in physical area, `w_q det J` (m²).
    pub weight: f64,
}

impl Triangle6Point {
    /// `Σ_a N_a v_a`: a nodal field interpolated to the point.
    #[inline]
    pub fn interpolate(&self, v: &[f64; 6]) -> f64 {
        (0..6).map(|a| self.shape[a] * v[a]).sum()
    }

    /// Strain–displacement matrix B (3×12), dofs `[u0x, u0y, …]`, strains
    /// `[ε_xx, ε_yy, γ_xy]`.
    #[inline]
    pub fn strain_matrix(&self) -> SMatrix<f64, 3, 12> {
        let mut b = SMatrix::<f64, 3, 12>::zeros();
        for a in 0..6 {
            b[(0, 2 * a)] = self.dndx[a];
            b[(1, 2 * a + 1)] = self.dndy[a];
            b[(2, 2 * a)] = self.dndy[a];
            b[(2, 2 * a + 1)] = self.dndx[a];
        }
        b
    }
}

/// A 6-node triangle's geometry: node coordinates relative to node 0 (which
/// keeps gradients accurate far from the origin) and the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle6 {
    origin: [f64; 2],
    rel: [[f64; 2]; 6],
}

impl Triangle6 {
    /// Geometry from the six node coordinates (corners counter-clockwise).
    ///
    /// # Errors
    /// [`Triangle6Error::NonFiniteCoordinate`] for NaN/∞ input;
    /// [`Triangle6Error::NonPositiveJacobian`] if `det J ≤ 0` at a node or at
    /// a point of the degree-5 rule (the map folds over: clockwise corners,
    /// or a mid node moved more than about a quarter of the edge off it).
    pub fn new(x: [[f64; 2]; 6]) -> Result<Self, Triangle6Error> {
        for (node, p) in x.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(Triangle6Error::NonFiniteCoordinate { node });
            }
        }
        let origin = x[0];
        let rel = x.map(|p| [p[0] - origin[0], p[1] - origin[1]]);
        let t = Triangle6 { origin, rel };
        // Scale for a relative "zero": the corner triangle's doubled area.
        let scale = (rel[1][0] * rel[2][1] - rel[2][0] * rel[1][1]).abs().max(
            rel.iter()
                .map(|p| p[0] * p[0] + p[1] * p[1])
                .fold(0.0, f64::max),
        );
        let checks = NODES
            .iter()
            .copied()
            .chain(TriangleRule::Degree5.points().iter().map(|p| p.xi));
        for xi in checks {
            let det = t.jacobian(xi).determinant();
            if det.is_nan() || det <= 1e-12 * scale {
                return Err(Triangle6Error::NonPositiveJacobian { det, xi });
            }
        }
        Ok(t)
    }

    /// The Jacobian `J = ∂(x, y)/∂(ξ, η)` at `xi`.
    #[inline]
    pub fn jacobian(&self, xi: [f64; 2]) -> nalgebra::Matrix2<f64> {
        let (dxi, deta) = shape_derivatives(xi);
        let mut j = nalgebra::Matrix2::zeros();
        for a in 0..6 {
            let p = self.rel[a];
            j[(0, 0)] += dxi[a] * p[0];
            j[(0, 1)] += deta[a] * p[0];
            j[(1, 0)] += dxi[a] * p[1];
            j[(1, 1)] += deta[a] * p[1];
        }
        j
    }

    /// Physical position `x(ξ, η)`.
    #[inline]
    pub fn position(&self, xi: [f64; 2]) -> [f64; 2] {
        let n = shape(xi);
        let mut x = self.origin;
        for a in 0..6 {
            x[0] += n[a] * self.rel[a][0];
            x[1] += n[a] * self.rel[a][1];
        }
        x
    }

    /// Shape values and physical gradients at `xi`, integration weight `w`
    /// (reference measure) times `det J`.
    #[inline]
    pub fn point(&self, xi: [f64; 2], w: f64) -> Triangle6Point {
        let (dxi, deta) = shape_derivatives(xi);
        let j = self.jacobian(xi);
        let det = j.determinant();
        // J⁻ᵀ = 1/det [[J11, −J10], [−J01, J00]].
        let (a, b, c, d) = (j[(0, 0)], j[(0, 1)], j[(1, 0)], j[(1, 1)]);
        let inv = 1.0 / det;
        let mut dndx = [0.0; 6];
        let mut dndy = [0.0; 6];
        for k in 0..6 {
            dndx[k] = inv * (d * dxi[k] - c * deta[k]);
            dndy[k] = inv * (-b * dxi[k] + a * deta[k]);
        }
        Triangle6Point {
            xi,
            shape: shape(xi),
            dndx,
            dndy,
            det_j: det,
            weight: w * det,
        }
    }

    /// The integration points of `rule` on this element (no allocation).
    #[inline]
    pub fn points(&self, rule: TriangleRule) -> impl Iterator<Item = Triangle6Point> + '_ {
        rule.points().iter().map(|p| self.point(p.xi, p.weight))
    }

    /// Area `∫ dA` (exact with [`TriangleRule::Degree2`]: `det J` is a
    /// quadratic polynomial of `(ξ, η)`).
    pub fn area(&self) -> f64 {
        self.points(TriangleRule::Degree2).map(|p| p.weight).sum()
    }

    /// Conductivity matrix `∫ k ∇N ∇Nᵀ dA`.
    pub fn laplace_matrix(&self, k: f64, rule: TriangleRule) -> Matrix6 {
        let mut m = Matrix6::zeros();
        for p in self.points(rule) {
            let s = k * p.weight;
            for i in 0..6 {
                for j in i..6 {
                    m[(i, j)] += s * (p.dndx[i] * p.dndx[j] + p.dndy[i] * p.dndy[j]);
                }
            }
        }
        m.fill_lower_triangle_with_upper_triangle();
        m
    }

    /// Consistent mass/capacity matrix `∫ ρc N Nᵀ dA`.
    pub fn mass_matrix(&self, rho_c: f64, rule: TriangleRule) -> Matrix6 {
        let mut m = Matrix6::zeros();
        for p in self.points(rule) {
            let s = rho_c * p.weight;
            for i in 0..6 {
                for j in i..6 {
                    m[(i, j)] += s * p.shape[i] * p.shape[j];
                }
            }
        }
        m.fill_lower_triangle_with_upper_triangle();
        m
    }

    /// Lumped mass by HRZ diagonal scaling (Hinton, Rock & Zienkiewicz):
    /// the diagonal of the consistent matrix scaled so that it sums to the
    /// element's `∫ ρc dA`. Row sums would give zero (or negative) corner
    /// masses for this element; HRZ gives `A/19` at corners and `16A/57` at
    /// mid nodes of a straight element, all positive.
    pub fn lumped_mass_hrz(&self, rho_c: f64, rule: TriangleRule) -> Matrix6 {
        let m = self.mass_matrix(rho_c, rule);
        let total = rho_c * self.area();
        let diag: f64 = m.diagonal().sum();
        Matrix6::from_diagonal(&(m.diagonal() * (total / diag)))
    }

    /// `∫ s N dA`: a nodal load vector of a uniform source density `s`.
    pub fn source_vector(&self, s: f64, rule: TriangleRule) -> Vector6 {
        let mut f = Vector6::zeros();
        for p in self.points(rule) {
            for a in 0..6 {
                f[a] += s * p.weight * p.shape[a];
            }
        }
        f
    }

    /// Stiffness `∫ Bᵀ D B dA` (unit thickness) for a symmetric `D` on
    /// `[ε_xx, ε_yy, γ_xy]`.
    pub fn elasticity_stiffness(&self, d: &Matrix3<f64>, rule: TriangleRule) -> Matrix12 {
        let mut k = Matrix12::zeros();
        for p in self.points(rule) {
            let b = p.strain_matrix();
            let db = d * b * p.weight;
            k += b.transpose() * db;
        }
        // Symmetrise round-off so Cholesky sees an exactly symmetric matrix.
        (k + k.transpose()) * 0.5
    }
}

#[cfg(test)]
mod tests {
    //! Goal: the 6-node triangle interpolates exactly what it should
    //! (partition of unity, Kronecker property, quadratics), the kernels
    //! match the closed forms of the straight element, and a curved element
    //! has the isoparametric area.
    use super::*;

    fn straight(p: [[f64; 2]; 3]) -> [[f64; 2]; 6] {
        let m = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        [
            p[0],
            p[1],
            p[2],
            m(p[0], p[1]),
            m(p[1], p[2]),
            m(p[2], p[0]),
        ]
    }

    #[test]
    fn partition_of_unity_kronecker_and_derivatives() {
        for (a, xa) in NODES.iter().enumerate() {
            let n = shape(*xa);
            for (b, v) in n.iter().enumerate() {
                assert!((v - if a == b { 1.0 } else { 0.0 }).abs() < 1e-15);
            }
        }
        // Random points: Σ N = 1, Σ ∂N = 0, derivatives match differences.
        let mut s = 0.123_f64;
        for _ in 0..50 {
            s = (s * 97.31).fract();
            let t = (s * 13.7).fract() * (1.0 - s);
            let xi = [s, t];
            let n = shape(xi);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            let (dx, dy) = shape_derivatives(xi);
            assert!(dx.iter().sum::<f64>().abs() < 1e-13);
            assert!(dy.iter().sum::<f64>().abs() < 1e-13);
            let h = 1e-6;
            let (np, nm) = (shape([s + h, t]), shape([s - h, t]));
            let (mp, mm) = (shape([s, t + h]), shape([s, t - h]));
            for a in 0..6 {
                assert!(((np[a] - nm[a]) / (2.0 * h) - dx[a]).abs() < 1e-8);
                assert!(((mp[a] - mm[a]) / (2.0 * h) - dy[a]).abs() < 1e-8);
            }
        }
    }

    #[test]
    fn curved_element_reproduces_quadratic_fields_and_gradients() {
        // A curved element far from the origin: mid node of edge (1,2) moved out.
        let mut x = straight([[1000.0, 2000.0], [1000.4, 2000.1], [1000.1, 2000.5]]);
        x[4][0] += 0.03;
        x[4][1] += 0.02;
        let t = Triangle6::new(x).unwrap();
        // f = 1 + 2x − 3y + x² − xy + 0.5 y² in local coordinates.
        let o = [1000.0, 2000.0];
        let f = |p: [f64; 2]| {
            let (u, v) = (p[0] - o[0], p[1] - o[1]);
            1.0 + 2.0 * u - 3.0 * v + u * u - u * v + 0.5 * v * v
        };
        let grad = |p: [f64; 2]| {
            let (u, v) = (p[0] - o[0], p[1] - o[1]);
            [2.0 + 2.0 * u - v, -3.0 - u + v]
        };
        // Linear fields are reproduced exactly on a curved element; a
        // quadratic in x only on a straight one (the map is quadratic).
        let lin = |p: [f64; 2]| 1.0 + 2.0 * (p[0] - o[0]) - 3.0 * (p[1] - o[1]);
        let vl = x.map(lin);
        for q in t.points(TriangleRule::Degree5) {
            let xq = t.position(q.xi);
            assert!((q.interpolate(&vl) - lin(xq)).abs() < 1e-12);
            let gx: f64 = (0..6).map(|a| q.dndx[a] * vl[a]).sum();
            let gy: f64 = (0..6).map(|a| q.dndy[a] * vl[a]).sum();
            assert!(
                (gx - 2.0).abs() < 1e-9 && (gy + 3.0).abs() < 1e-9,
                "{gx} {gy}"
            );
        }
        let s = Triangle6::new(straight([
            [1000.0, 2000.0],
            [1000.4, 2000.1],
            [1000.1, 2000.5],
        ]))
        .unwrap();
        let xs = straight([[1000.0, 2000.0], [1000.4, 2000.1], [1000.1, 2000.5]]);
        let vq = xs.map(f);
        for q in s.points(TriangleRule::Degree5) {
            let xq = s.position(q.xi);
            assert!((q.interpolate(&vq) - f(xq)).abs() < 1e-10);
            let gx: f64 = (0..6).map(|a| q.dndx[a] * vq[a]).sum();
            let gy: f64 = (0..6).map(|a| q.dndy[a] * vq[a]).sum();
            let g = grad(xq);
            assert!((gx - g[0]).abs() < 1e-8 && (gy - g[1]).abs() < 1e-8);
        }
    }

    #[test]
    fn curved_triangle_area_is_the_isoparametric_area() {
        // Sector-like element: corners (0,0), (1,0), (0,1); the edge (1,2)
        // bulges to the mid node at (c, c) with c = 1/√2 (a point of the
        // unit circle). Area = 1/2 + area between the chord and the parabola
        // through the three points = 1/2 + (2/3)·|chord|·sagitta,
        // |chord| = √2, sagitta = 1 − 1/√2 − ... measured along the normal:
        // the mid node is offset (c − 1/2)√2 from the chord midpoint.
        let c = std::f64::consts::FRAC_1_SQRT_2;
        let x = [
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [0.5, 0.0],
            [c, c],
            [0.0, 0.5],
        ];
        let t = Triangle6::new(x).unwrap();
        let sag = (c - 0.5) * 2f64.sqrt();
        let exact = 0.5 + 2.0 / 3.0 * 2f64.sqrt() * sag;
        for rule in [
            TriangleRule::Degree2,
            TriangleRule::Degree4,
            TriangleRule::Degree5,
        ] {
            let a: f64 = t.points(rule).map(|p| p.weight).sum();
            assert!((a - exact).abs() < 1e-15, "{rule:?}: {a} vs {exact}");
        }
        // The quarter disc has area π/4 = 0.7854; the parabola 0.7761.
        assert!((t.area() - std::f64::consts::FRAC_PI_4).abs() < 0.01);
    }

    #[test]
    fn straight_element_kernels_match_closed_forms() {
        let p = [[0.1, 0.2], [1.3, -0.1], [0.4, 0.9]];
        let t = Triangle6::new(straight(p)).unwrap();
        let area = 0.5
            * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));
        assert!((t.area() - area).abs() < 1e-15);
        // Consistent mass: A/180 [6 at corners, 32 at mids; −1 corner–corner,
        // 0 corner–adjacent mid, −4 corner–opposite mid, 16 mid–mid].
        let m = t.mass_matrix(1.0, TriangleRule::Degree4);
        let e = |i: usize, j: usize| -> f64 {
            let v = match (i < 3, j < 3) {
                (true, true) => {
                    if i == j {
                        6.0
                    } else {
                        -1.0
                    }
                }
                (false, false) => {
                    if i == j {
                        32.0
                    } else {
                        16.0
                    }
                }
                _ => {
                    let (c, mid) = if i < 3 { (i, j) } else { (j, i) };
                    // Mid node mid−3 lies on edge (mid−3, mid−2 mod 3).
                    let opposite = (mid - 3 + 2) % 3;
                    if c == opposite { -4.0 } else { 0.0 }
                }
            };
            v * area / 180.0
        };
        for i in 0..6 {
            for j in 0..6 {
                assert!((m[(i, j)] - e(i, j)).abs() < 1e-15, "M[{i},{j}]");
            }
        }
        assert!((m.sum() - area).abs() < 1e-15);
        // HRZ: A/19 at corners, 16A/57 at mids.
        let l = t.lumped_mass_hrz(1.0, TriangleRule::Degree4);
        for a in 0..6 {
            let e = if a < 3 {
                area / 19.0
            } else {
                16.0 * area / 57.0
            };
            assert!((l[(a, a)] - e).abs() < 1e-15);
        }
        assert!((l.sum() - area).abs() < 1e-15);
        // Laplace: rows sum to zero; the degree-2 rule is exact (= degree 5).
        let k2 = t.laplace_matrix(3.0, TriangleRule::Degree2);
        let k5 = t.laplace_matrix(3.0, TriangleRule::Degree5);
        assert!((k2 - k5).amax() < 1e-13 * k5.amax());
        for i in 0..6 {
            assert!(k2.row(i).sum().abs() < 1e-13);
        }
        // Energy of a linear field T = x: k ∫ |∇T|² = k A.
        let tx = Vector6::from_iterator(straight(p).iter().map(|q| q[0]));
        assert!(((tx.transpose() * k2 * tx)[0] - 3.0 * area).abs() < 1e-13);
        // Elastic: rigid modes have no energy; uniform strain energy exact.
        let d = Matrix3::new(3.0, 1.0, 0.0, 1.0, 3.0, 0.0, 0.0, 0.0, 1.0);
        let k = t.elasticity_stiffness(&d, TriangleRule::Degree2);
        let x = straight(p);
        let modes = [
            Vector12::from_iterator((0..12).map(|i| if i % 2 == 0 { 1.0 } else { 0.0 })),
            Vector12::from_iterator((0..12).map(|i| if i % 2 == 1 { 1.0 } else { 0.0 })),
            Vector12::from_iterator((0..12).map(|i| {
                if i % 2 == 0 {
                    -x[i / 2][1]
                } else {
                    x[i / 2][0]
                }
            })),
        ];
        for m in &modes {
            assert!((k * m).amax() < 1e-13);
        }
        // u = (x, 0): ε = (1, 0, 0), energy D₀₀ A.
        let u =
            Vector12::from_iterator((0..12).map(|i| if i % 2 == 0 { x[i / 2][0] } else { 0.0 }));
        assert!(((u.transpose() * k * u)[0] - 3.0 * area).abs() < 1e-13);
        // Source: ∫ N = 0 at corners, A/3 at mids.
        let f = t.source_vector(1.0, TriangleRule::Degree4);
        for a in 0..6 {
            let e = if a < 3 { 0.0 } else { area / 3.0 };
            assert!((f[a] - e).abs() < 1e-15);
        }
    }

    #[test]
    fn rejects_inverted_and_folded_elements() {
        let p = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let mut x = straight(p);
        x.swap(1, 2);
        x.swap(3, 5);
        assert!(matches!(
            Triangle6::new(x),
            Err(Triangle6Error::NonPositiveJacobian { .. })
        ));
        // Mid node of edge (0,1) pulled past the quarter point: folds.
        let mut x = straight(p);
        x[3] = [0.2, 0.0];
        assert!(matches!(
            Triangle6::new(x),
            Err(Triangle6Error::NonPositiveJacobian { .. })
        ));
        let mut x = straight(p);
        x[4][1] = f64::NAN;
        assert_eq!(
            Triangle6::new(x),
            Err(Triangle6Error::NonFiniteCoordinate { node: 4 })
        );
    }
}
