//! Element kernels: the linear triangle with thermal strain.
//!
//! Plane strain / stress: K = A Bᵀ D B, thermal load f = A Bᵀ D ε₀ with
//! ε₀ = κ α ΔT (1, 1, 0), κ = 1 + ν (plane strain) or 1 (plane stress).
//! Generalised plane strain adds one global unknown ε_zz: with
//! B₇ = [[B, 0], [0, 1]] (4×7) and the 3D modulus D₄ on (ε_xx, ε_yy, γ_xy, ε_zz),
//! K = A B₇ᵀ D₄ B₇ and f = A B₇ᵀ D₄ α ΔT (1, 1, 0, 1); the ε_zz row states
//! ∫ σ_zz dA = 0.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use tecon_fem::triangle::{TriangleGeometry, elasticity_stiffness};

use crate::material::{Analysis, Material};

/// Stiffness and thermal load of one plane triangle.
#[inline]
pub fn plane_triangle(
    g: &TriangleGeometry,
    d: &Matrix3<f64>,
    thermal_strain: f64,
) -> (SMatrix<f64, 6, 6>, SVector<f64, 6>) {
    let k = elasticity_stiffness(g, d);
    let sigma0 = d * Vector3::new(thermal_strain, thermal_strain, 0.0);
    let f = g.strain_matrix().transpose() * sigma0 * g.area;
    (k, f)
}

/// Stiffness and thermal load of one generalised-plane-strain triangle
/// (dofs: 6 displacements then ε_zz).
#[inline]
pub fn gps_triangle(
    g: &TriangleGeometry,
    m: &Material,
    delta_t: f64,
) -> (SMatrix<f64, 7, 7>, SVector<f64, 7>) {
    let (l, mu) = (m.lambda(), m.mu());
    let d3 = Analysis::GeneralisedPlaneStrain.d(m);
    let k6 = elasticity_stiffness(g, &d3);
    let b = g.strain_matrix();
    let coupling = b.transpose() * Vector3::new(l, l, 0.0) * g.area;
    let mut k = SMatrix::<f64, 7, 7>::zeros();
    k.fixed_view_mut::<6, 6>(0, 0).copy_from(&k6);
    for i in 0..6 {
        k[(i, 6)] = coupling[i];
        k[(6, i)] = coupling[i];
    }
    k[(6, 6)] = (l + 2.0 * mu) * g.area;
    let s0 = (3.0 * l + 2.0 * mu) * m.expansion * delta_t;
    let f6 = b.transpose() * Vector3::new(s0, s0, 0.0) * g.area;
    let mut f = SVector::<f64, 7>::zeros();
    f.fixed_rows_mut::<6>(0).copy_from(&f6);
    f[6] = s0 * g.area;
    (k, f)
}

/// Stresses (σ_xx, σ_yy, σ_xy, σ_zz) of an element from its strain
/// (ε_xx, ε_yy, γ_xy), ε_zz (generalised plane strain only) and ΔT.
pub fn element_stress(
    analysis: Analysis,
    m: &Material,
    strain: Vector3<f64>,
    eps_zz: f64,
    delta_t: f64,
) -> [f64; 4] {
    let a = m.expansion * delta_t;
    match analysis {
        Analysis::PlaneStrain => {
            let d = analysis.d(m);
            let e0 = (1.0 + m.poisson_ratio) * a;
            let s = d * (strain - Vector3::new(e0, e0, 0.0));
            let szz = m.poisson_ratio * (s[0] + s[1]) - m.youngs_modulus * a;
            [s[0], s[1], s[2], szz]
        }
        Analysis::PlaneStress => {
            let d = analysis.d(m);
            let s = d * (strain - Vector3::new(a, a, 0.0));
            [s[0], s[1], s[2], 0.0]
        }
        Analysis::GeneralisedPlaneStrain => {
            let d4 = m.d4();
            let e = nalgebra::Vector4::new(strain[0] - a, strain[1] - a, strain[2], eps_zz - a);
            let s = d4 * e;
            [s[0], s[1], s[2], s[3]]
        }
    }
}
