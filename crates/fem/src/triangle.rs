//! Linear (3-node) triangle geometry and the reference kernels built on it.
//!
//! N_i = (a_i + b_i x + c_i y) / 2A with b_i = y_j − y_k, c_i = x_k − x_j
//! (i, j, k cyclic), so ∂N_i/∂x = b_i / 2A and ∂N_i/∂y = c_i / 2A.

use nalgebra::{Matrix3, SMatrix};

/// Area and shape-function gradients of a linear triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleGeometry {
    /// Signed area (positive for counter-clockwise nodes).
    pub area: f64,
    /// ∂N_i/∂x.
    pub dndx: [f64; 3],
    /// ∂N_i/∂y.
    pub dndy: [f64; 3],
}

impl TriangleGeometry {
    /// Geometry of the triangle with vertices `p`.
    #[inline]
    pub fn new(p: [[f64; 2]; 3]) -> Self {
        let b = [p[1][1] - p[2][1], p[2][1] - p[0][1], p[0][1] - p[1][1]];
        let c = [p[2][0] - p[1][0], p[0][0] - p[2][0], p[1][0] - p[0][0]];
        let area = 0.5 * (p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
            - 0.5 * (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        let inv = 1.0 / (2.0 * area);
        TriangleGeometry {
            area,
            dndx: [b[0] * inv, b[1] * inv, b[2] * inv],
            dndy: [c[0] * inv, c[1] * inv, c[2] * inv],
        }
    }

    /// Strain–displacement matrix B (3×6) for plane displacement, dofs
    /// [u1x, u1y, u2x, u2y, u3x, u3y], strains [ε_xx, ε_yy, γ_xy].
    #[inline]
    pub fn strain_matrix(&self) -> SMatrix<f64, 3, 6> {
        let mut b = SMatrix::<f64, 3, 6>::zeros();
        for i in 0..3 {
            b[(0, 2 * i)] = self.dndx[i];
            b[(1, 2 * i + 1)] = self.dndy[i];
            b[(2, 2 * i)] = self.dndy[i];
            b[(2, 2 * i + 1)] = self.dndx[i];
        }
        b
    }
}

/// Conductivity (Laplace) matrix ∫ k ∇N_i·∇N_j dA = k A (∇N ∇Nᵀ).
#[inline]
pub fn laplace_matrix(g: &TriangleGeometry, k: f64) -> Matrix3<f64> {
    let mut m = Matrix3::zeros();
    let s = k * g.area;
    for i in 0..3 {
        for j in 0..3 {
            m[(i, j)] = s * (g.dndx[i] * g.dndx[j] + g.dndy[i] * g.dndy[j]);
        }
    }
    m
}

/// Consistent mass/capacity matrix ∫ ρc N_i N_j dA = ρc A/12 [2 1 1; 1 2 1; 1 1 2].
#[inline]
pub fn consistent_mass(g: &TriangleGeometry, rho_c: f64) -> Matrix3<f64> {
    let s = rho_c * g.area / 12.0;
    Matrix3::new(2.0 * s, s, s, s, 2.0 * s, s, s, s, 2.0 * s)
}

/// Lumped mass/capacity matrix ρc A/3 · I.
#[inline]
pub fn lumped_mass(g: &TriangleGeometry, rho_c: f64) -> Matrix3<f64> {
    Matrix3::identity() * (rho_c * g.area / 3.0)
}

/// Stiffness ∫ Bᵀ D B dA = A Bᵀ D B of a plane triangle (unit thickness).
#[inline]
pub fn elasticity_stiffness(g: &TriangleGeometry, d: &Matrix3<f64>) -> SMatrix<f64, 6, 6> {
    let b = g.strain_matrix();
    let db = d * b;
    b.transpose() * db * g.area
}

/// Plane-strain elasticity matrix D for isotropic E, ν.
pub fn plane_strain_d(e: f64, nu: f64) -> Matrix3<f64> {
    let f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    Matrix3::new(
        f * (1.0 - nu),
        f * nu,
        0.0,
        f * nu,
        f * (1.0 - nu),
        0.0,
        0.0,
        0.0,
        f * (1.0 - 2.0 * nu) / 2.0,
    )
}
