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

/// Stiffness ∫ Bᵀ D B dA = A Bᵀ D B of a plane triangle (unit thickness),
/// for a symmetric D.
///
/// Written block by block (B_i = [[b_i, 0], [0, c_i], [c_i, b_i]] with
/// b_i = ∂N_i/∂x, c_i = ∂N_i/∂y) so the zeros of B cost nothing; equal to
/// the dense product to round-off (tested).
#[inline]
pub fn elasticity_stiffness(g: &TriangleGeometry, d: &Matrix3<f64>) -> SMatrix<f64, 6, 6> {
    let mut k = SMatrix::<f64, 6, 6>::zeros();
    // D B_j, a 3×2 block per node j, scaled by A.
    let mut db = [[[0.0; 2]; 3]; 3];
    for (j, dbj) in db.iter_mut().enumerate() {
        let (bj, cj) = (g.dndx[j] * g.area, g.dndy[j] * g.area);
        for (r, row) in dbj.iter_mut().enumerate() {
            *row = [
                d[(r, 0)] * bj + d[(r, 2)] * cj,
                d[(r, 1)] * cj + d[(r, 2)] * bj,
            ];
        }
    }
    for i in 0..3 {
        let (bi, ci) = (g.dndx[i], g.dndy[i]);
        for j in i..3 {
            let m = &db[j];
            let k00 = bi * m[0][0] + ci * m[2][0];
            let k01 = bi * m[0][1] + ci * m[2][1];
            let k10 = ci * m[1][0] + bi * m[2][0];
            let k11 = ci * m[1][1] + bi * m[2][1];
            k[(2 * i, 2 * j)] = k00;
            k[(2 * i, 2 * j + 1)] = k01;
            k[(2 * i + 1, 2 * j)] = k10;
            k[(2 * i + 1, 2 * j + 1)] = k11;
            if j != i {
                k[(2 * j, 2 * i)] = k00;
                k[(2 * j + 1, 2 * i)] = k01;
                k[(2 * j, 2 * i + 1)] = k10;
                k[(2 * j + 1, 2 * i + 1)] = k11;
            }
        }
    }
    k
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_stiffness_equals_dense_product() {
        let g = TriangleGeometry::new([[0.1, 0.2], [1.3, -0.1], [0.4, 0.9]]);
        let d = plane_strain_d(207e9, 0.3)
            + Matrix3::new(0.0, 0.0, 1e9, 0.0, 0.0, -2e9, 1e9, -2e9, 0.0);
        let b = g.strain_matrix();
        let dense = b.transpose() * d * b * g.area;
        let k = elasticity_stiffness(&g, &d);
        assert!(
            (k - dense).amax() < 1e-15 * dense.amax(),
            "{}",
            (k - dense).amax()
        );
    }

    #[test]
    fn gradients_sum_to_zero_and_reproduce_linear_fields() {
        let p = [[0.1, 0.2], [1.3, -0.1], [0.4, 0.9]];
        let g = TriangleGeometry::new(p);
        assert!((g.dndx.iter().sum::<f64>()).abs() < 1e-15);
        assert!((g.dndy.iter().sum::<f64>()).abs() < 1e-15);
        let f = |q: [f64; 2]| 3.0 * q[0] - 2.0 * q[1];
        let gx: f64 = (0..3).map(|i| g.dndx[i] * f(p[i])).sum();
        let gy: f64 = (0..3).map(|i| g.dndy[i] * f(p[i])).sum();
        assert!((gx - 3.0).abs() < 1e-14 && (gy + 2.0).abs() < 1e-14);
        let m = consistent_mass(&g, 2.0);
        assert!((m.sum() - 2.0 * g.area).abs() < 1e-15);
        assert!((lumped_mass(&g, 2.0).sum() - 2.0 * g.area).abs() < 1e-15);
    }
}
