//! Element kernels: the linear and the quadratic (6-node) triangle with thermal strain.
//!
//! Plane strain / stress: K = A Bᵀ D B, thermal load f = A Bᵀ D ε₀ with
//! ε₀ = κ α ΔT (1, 1, 0), κ = 1 + ν (plane strain) or 1 (plane stress).
//! Generalised plane strain adds one global unknown ε_zz: with
//! B₇ = [[B, 0], [0, 1]] (4×7) and the 3D modulus D₄ on (ε_xx, ε_yy, γ_xy, ε_zz),
//! K = A B₇ᵀ D₄ B₇ and f = A B₇ᵀ D₄ α ΔT (1, 1, 0, 1); the ε_zz row states
//! ∫ σ_zz dA = 0.
//!
//! The 6-node (P2, isoparametric) kernels integrate the same expressions
//! with the degree-4 rule ([`P2_RULE`]), the temperature change
//! interpolated from the six nodes to each point.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use tecon_fem::quadrature::TriangleRule;
use tecon_fem::triangle::{TriangleGeometry, elasticity_stiffness};
use tecon_fem::triangle6::{Matrix12, Triangle6, Triangle6Point, Vector12};

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

// ---------------------------------------------------------------------------
// Quadratic (6-node, isoparametric) triangles
// ---------------------------------------------------------------------------

/// Integration rule of the P2 elastic kernels: degree 4 integrates the
/// thermal load `∫ Bᵀ D ε₀(T) dA` of a straight element exactly (B linear,
/// ΔT quadratic) and the stiffness of a curved one to O(h⁴).
pub const P2_RULE: TriangleRule = TriangleRule::Degree4;

/// Stiffness and thermal load of one plane 6-node triangle.
///
/// `K = ∫ Bᵀ D B dA`, `f = ∫ Bᵀ D ε₀ dA` with `ε₀ = κα ΔT(x) (1, 1, 0)`,
/// `κα = Analysis::in_plane_expansion`, and `ΔT(x) = Σ N_a ΔT_a` the
/// temperature change interpolated from the six nodes to each integration
/// point. `delta_t[a] = T_a − T_ref,e`: the stress-free reference is the
/// element's own, so a weld element and its neighbour see different
/// eigenstrains at a shared node (the jump at the weld edge is kept).
pub fn plane_triangle6(
    g: &Triangle6,
    d: &Matrix3<f64>,
    in_plane_expansion: f64,
    delta_t: &[f64; 6],
) -> (Matrix12, Vector12) {
    let mut k = Matrix12::zeros();
    let mut f = Vector12::zeros();
    for p in g.points(P2_RULE) {
        let b = p.strain_matrix();
        let db = d * b * p.weight;
        k += b.transpose() * db;
        let e0 = in_plane_expansion * p.interpolate(delta_t);
        f += db.transpose() * Vector3::new(e0, e0, 0.0);
    }
    ((k + k.transpose()) * 0.5, f)
}

/// The thermal load of [`plane_triangle6`] alone:
/// `f = Σ_p w_p Bᵀ D [e₀, e₀, 0]`, without the stiffness (a sixth of the
/// work; the load is recomputed at every contact solve of a two-way run,
/// the stiffness never).
pub fn plane_triangle6_load(
    g: &Triangle6,
    d: &Matrix3<f64>,
    in_plane_expansion: f64,
    delta_t: &[f64; 6],
) -> Vector12 {
    let mut f = Vector12::zeros();
    for p in g.points(P2_RULE) {
        let e0 = in_plane_expansion * p.interpolate(delta_t);
        let s0 = d * Vector3::new(e0, e0, 0.0) * p.weight;
        f += p.strain_matrix().transpose() * s0;
    }
    f
}

/// Stiffness and thermal load of one generalised-plane-strain 6-node
/// triangle (dofs: 12 displacements, then ε_zz), as [`gps_triangle`] with
/// `ΔT` interpolated to the integration points.
pub fn gps_triangle6(
    g: &Triangle6,
    m: &Material,
    delta_t: &[f64; 6],
) -> (SMatrix<f64, 13, 13>, SVector<f64, 13>) {
    let (l, mu) = (m.lambda(), m.mu());
    let d3 = Analysis::GeneralisedPlaneStrain.d(m);
    let (k12, _) = plane_triangle6(g, &d3, 0.0, delta_t);
    let mut k = SMatrix::<f64, 13, 13>::zeros();
    k.fixed_view_mut::<12, 12>(0, 0).copy_from(&k12);
    let mut f = SVector::<f64, 13>::zeros();
    let three_k = 3.0 * l + 2.0 * mu;
    for p in g.points(P2_RULE) {
        let b = p.strain_matrix();
        let coupling = b.transpose() * Vector3::new(l, l, 0.0) * p.weight;
        for i in 0..12 {
            k[(i, 12)] += coupling[i];
            k[(12, i)] += coupling[i];
        }
        k[(12, 12)] += (l + 2.0 * mu) * p.weight;
        let s0 = three_k * m.expansion * p.interpolate(delta_t);
        let f12 = b.transpose() * Vector3::new(s0, s0, 0.0) * p.weight;
        for i in 0..12 {
            f[i] += f12[i];
        }
        f[12] += s0 * p.weight;
    }
    (k, f)
}

/// Stresses (σ_xx, σ_yy, σ_xy, σ_zz) at the [`P2_RULE`] points of a 6-node
/// triangle from its nodal displacements `u`, ε_zz (generalised plane
/// strain) and the nodal `ΔT` (interpolated to each point), with the
/// points' reference coordinates and weights (for recovery).
pub fn triangle6_stresses(
    g: &Triangle6,
    analysis: Analysis,
    m: &Material,
    u: &Vector12,
    eps_zz: f64,
    delta_t: &[f64; 6],
) -> [([f64; 4], Triangle6Point); 6] {
    let mut out = [([0.0; 4], g.point([1.0 / 3.0, 1.0 / 3.0], 0.0)); 6];
    for (q, p) in g.points(P2_RULE).enumerate() {
        let strain = p.strain_matrix() * u;
        out[q] = (
            element_stress(analysis, m, strain, eps_zz, p.interpolate(delta_t)),
            p,
        );
    }
    out
}
