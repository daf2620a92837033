//! Stress recovery: element and nodal stresses, polar components, von Mises.

use nalgebra::{Matrix3, Vector2, Vector3};
use tecon_fem::triangle::TriangleGeometry;
use tecon_fem::triangle6::{Triangle6, Vector12};
use tecon_mesh::Mesh;

use crate::kernels::{element_stress, triangle6_stresses};
use crate::material::Material;
use crate::model::ElasticModel;
use crate::recovery::{
    ErrorEstimate, PointStress, compliance, energy_density, nodal_average, spr_recovery,
    zz_indicator, zz_indicator_linear,
};

/// Element and nodal stresses (σ_xx, σ_yy, σ_xy, σ_zz), the recovered
/// stresses of each region and the Zienkiewicz–Zhu error estimate.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StressField {
    /// Per element (on 6-node triangles the area mean over the
    /// integration points).
    pub element: Vec<[f64; 4]>,
    /// Per node, area-weighted mean of the elements around it (nodes belong
    /// to one body, so nothing is averaged across an interface, but a node
    /// on a region border, such as the weld edge, mixes the regions: use
    /// [`StressField::recovered`] where regions must stay apart).
    pub nodal: Vec<[f64; 4]>,
    /// Per element node, in connectivity order (3 per element on linear
    /// triangles, 6 on 6-node ones, element after element): the recovered
    /// stress σ* of the element's own region (nodal averaging on linear
    /// triangles, SPR on 6-node ones), never averaged across a region
    /// border or an interface.
    pub recovered: Vec<[f64; 4]>,
    /// Zienkiewicz–Zhu estimate ‖σ* − σ_h‖ in the energy norm.
    pub error: ErrorEstimate,
}

impl StressField {
    /// Nodes per element of [`StressField::recovered`] (3 or 6; 0 if empty).
    pub fn nodes_per_element(&self) -> usize {
        self.recovered
            .len()
            .checked_div(self.element.len())
            .unwrap_or(0)
    }

    /// The recovered stresses of element `e`'s nodes (its own region).
    pub fn recovered_of(&self, e: usize) -> &[[f64; 4]] {
        let k = self.nodes_per_element();
        &self.recovered[k * e..k * (e + 1)]
    }
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
        .map(|a| {
            if a[4] > 0.0 {
                [a[0] / a[4], a[1] / a[4], a[2] / a[4], a[3] / a[4]]
            } else {
                [0.0; 4]
            }
        })
        .collect();
    let areas = mesh.areas();
    let recovered = nodal_average(
        mesh.n_nodes(),
        mesh.triangles(),
        mesh.element_regions(),
        &areas,
        &element,
    );
    let c: Vec<Matrix3<f64>> = materials
        .iter()
        .map(|m| compliance(&model.analysis.d(m)))
        .collect();
    let indicator = zz_indicator_linear(&areas, &c, &element, &recovered);
    let norm2: Vec<f64> = element
        .iter()
        .enumerate()
        .map(|(e, s)| energy_density(&c[e], *s, areas[e].abs()))
        .collect();
    StressField {
        error: ErrorEstimate::new(indicator, &norm2),
        element,
        nodal,
        recovered: recovered.into_iter().flatten().collect(),
    }
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

/// Stresses of an order-2 (6-node) model.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadraticStresses {
    /// Per element, the stresses at its [`crate::P2_RULE`] points
    /// (position, weight, `(σ_xx, σ_yy, σ_xy, σ_zz)`).
    pub points: Vec<Vec<PointStress>>,
    /// Per element, the SPR-recovered stresses at its six nodes (node order
    /// of `Mesh::triangles6()`), fitted within the element's region only:
    /// never across a region boundary (the weld edge) or an interface.
    pub recovered: Vec<[[f64; 4]; 6]>,
    /// Zienkiewicz–Zhu indicator `η_e` of each element (energy norm of
    /// `σ* − σ_h`, √(J/m) per unit thickness).
    pub indicator: Vec<f64>,
    /// `‖σ_h‖²_e = ∫_e σ_hᵀ D⁻¹ σ_h dA` of each element (in-plane).
    pub energy: Vec<f64>,
}

impl QuadraticStresses {
    /// Element means (area-weighted over the integration points), nodal
    /// values (area-weighted mean over the elements at the node of their
    /// recovered values; where regions meet this mixes their values, which
    /// stay apart in [`StressField::recovered`]), the recovered values per
    /// element node and the error estimate.
    pub fn field(&self, mesh: &Mesh) -> StressField {
        let element = self
            .points
            .iter()
            .map(|pts| {
                let area: f64 = pts.iter().map(|p| p.weight).sum();
                let mut s = [0.0; 4];
                for p in pts {
                    for (sk, pk) in s.iter_mut().zip(p.stress) {
                        *sk += p.weight * pk;
                    }
                }
                s.map(|v| v / area)
            })
            .collect();
        let mut acc = vec![[0.0; 5]; mesh.n_nodes()];
        if let Some(t6) = mesh.triangles6() {
            for (e, t) in t6.iter().enumerate() {
                let area: f64 = self.points[e].iter().map(|p| p.weight).sum();
                for (a, &v) in t.iter().enumerate() {
                    for (ak, rk) in acc[v].iter_mut().zip(self.recovered[e][a]) {
                        *ak += area * rk;
                    }
                    acc[v][4] += area;
                }
            }
        }
        let nodal = acc
            .iter()
            .map(|a| {
                if a[4] > 0.0 {
                    [a[0] / a[4], a[1] / a[4], a[2] / a[4], a[3] / a[4]]
                } else {
                    [0.0; 4]
                }
            })
            .collect();
        StressField {
            element,
            nodal,
            recovered: self.recovered.iter().flatten().copied().collect(),
            error: ErrorEstimate::new(self.indicator.clone(), &self.energy),
        }
    }
}

/// Stresses of an order-2 model at the integration points, recovered per
/// region by SPR, and the ZZ indicator, for displacements `u`, ε_zz and the
/// nodal temperature changes `delta_t` (empty, or six per element as in
/// [`crate::Loads::delta_t`]). `geometry[e]` is element `e`'s 6-node
/// triangle. An order-1 mesh gives empty lists.
pub fn quadratic_stresses(
    model: &ElasticModel<'_>,
    geometry: &[Triangle6],
    materials: &[Material],
    u: &[f64],
    eps_zz: f64,
    delta_t: &[f64],
) -> QuadraticStresses {
    let mesh = model.mesh;
    let Some(t6) = mesh.triangles6() else {
        return QuadraticStresses {
            points: Vec::new(),
            recovered: Vec::new(),
            indicator: Vec::new(),
            energy: Vec::new(),
        };
    };
    let points: Vec<Vec<PointStress>> = t6
        .iter()
        .zip(geometry)
        .enumerate()
        .map(|(e, (t, g))| {
            let ue = Vector12::from_fn(|k, _| u[2 * t[k / 2] + k % 2]);
            let dt: [f64; 6] = delta_t
                .get(6 * e..6 * e + 6)
                .map_or([0.0; 6], |s| std::array::from_fn(|a| s[a]));
            triangle6_stresses(g, model.analysis, &materials[e], &ue, eps_zz, &dt)
                .iter()
                .map(|(s, p)| PointStress {
                    x: g.position(p.xi),
                    weight: p.weight,
                    stress: *s,
                })
                .collect()
        })
        .collect();
    let recovered = spr_recovery(mesh.nodes(), t6, mesh.element_regions(), &points);
    let c: Vec<Matrix3<f64>> = materials
        .iter()
        .map(|m| compliance(&model.analysis.d(m)))
        .collect();
    let indicator = zz_indicator(geometry, &c, &points, &recovered);
    let energy = points
        .iter()
        .zip(&c)
        .map(|(pts, c)| {
            pts.iter()
                .map(|p| energy_density(c, p.stress, p.weight))
                .sum()
        })
        .collect();
    QuadraticStresses {
        points,
        recovered,
        indicator,
        energy,
    }
}
