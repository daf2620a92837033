//! Stress recovery: element and nodal stresses, polar components, von Mises.

use nalgebra::{Vector2, Vector3};
use tecon_fem::triangle::TriangleGeometry;

use crate::kernels::element_stress;
use crate::material::Material;
use crate::model::ElasticModel;

/// Element and nodal stresses (σ_xx, σ_yy, σ_xy, σ_zz).
#[derive(Debug, Clone, PartialEq)]
pub struct StressField {
    /// Per element.
    pub element: Vec<[f64; 4]>,
    /// Per node, area-weighted mean of the elements around it (nodes belong
    /// to one body, so nothing is averaged across an interface).
    pub nodal: Vec<[f64; 4]>,
}

/// Stresses (σ_xx, σ_yy, σ_xy, σ_zz) per element and per node for
/// displacements `u`, ε_zz and element temperature changes.
pub fn stresses(
    model: &ElasticModel<'_>,
    materials: &[Material],
    u: &[f64],
    eps_zz: f64,
    delta_t: &[f64],
) -> StressField {
    let mesh = model.mesh;
    let x = mesh.nodes();
    let mut element = Vec::with_capacity(mesh.n_triangles());
    let mut acc = vec![[0.0; 5]; mesh.n_nodes()];
    for (e, t) in mesh.triangles().iter().enumerate() {
        let g = TriangleGeometry::new(t.map(|v| x[v]));
        let mut ue = nalgebra::SVector::<f64, 6>::zeros();
        for (a, &v) in t.iter().enumerate() {
            ue[2 * a] = u[2 * v];
            ue[2 * a + 1] = u[2 * v + 1];
        }
        let strain: Vector3<f64> = g.strain_matrix() * ue;
        let s = element_stress(
            model.analysis,
            &materials[e],
            strain,
            eps_zz,
            delta_t.get(e).copied().unwrap_or(0.0),
        );
        for &v in t {
            for k in 0..4 {
                acc[v][k] += g.area * s[k];
            }
            acc[v][4] += g.area;
        }
        element.push(s);
    }
    let nodal = acc
        .iter()
        .map(|a| [a[0] / a[4], a[1] / a[4], a[2] / a[4], a[3] / a[4]])
        .collect();
    StressField { element, nodal }
}

/// Polar components (σ_rr, σ_θθ, σ_rθ) of (σ_xx, σ_yy, σ_xy) at point `p` about `centre`.
pub fn polar(s: [f64; 4], p: [f64; 2], centre: [f64; 2]) -> [f64; 3] {
    let th = (p[1] - centre[1]).atan2(p[0] - centre[0]);
    let (sn, c) = th.sin_cos();
    let (sx, sy, t) = (s[0], s[1], s[2]);
    [
        sx * c * c + sy * sn * sn + 2.0 * t * sn * c,
        sx * sn * sn + sy * c * c - 2.0 * t * sn * c,
        (sy - sx) * sn * c + t * (c * c - sn * sn),
    ]
}

/// Von Mises equivalent stress of (σ_xx, σ_yy, σ_xy, σ_zz).
pub fn von_mises(s: [f64; 4]) -> f64 {
    let (a, b, c, t) = (s[0], s[1], s[3], s[2]);
    (0.5 * ((a - b).powi(2) + (b - c).powi(2) + (c - a).powi(2)) + 3.0 * t * t).sqrt()
}

/// Displacement of node `i` as a vector.
pub fn nodal_displacement(u: &[f64], i: usize) -> Vector2<f64> {
    Vector2::new(u[2 * i], u[2 * i + 1])
}
