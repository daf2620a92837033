//! Stress recovery per group of elements (a region: never across the weld
//! edge or an interface) and the Zienkiewicz–Zhu error indicator, for
//! 3-node and 6-node triangles.
//!
//! * **Nodal averaging** (linear triangles, [`nodal_average`]): σ* linear
//!   in each element, its value at a corner the area-weighted mean of the
//!   constant stresses of the group's elements around the node; η_e
//!   integrated exactly with `∫_e N_a N_b dA = A (1 + δ_ab) / 12`
//!   ([`zz_indicator_linear`]).
//! * **SPR** (Zienkiewicz & Zhu 1992): around each corner node, the
//!   integration-point stresses of the elements of one group (a region:
//!   never across the weld edge or an interface) that share the node are
//!   fitted by least squares with a complete quadratic
//!   `σ*(x) = P(x) a`, `P = [1, x̂, ŷ, x̂², x̂ŷ, ŷ²]` in coordinates centred at
//!   the node and scaled by the patch size; the fit is evaluated at every
//!   node of the patch's elements, and each element node averages the
//!   values of the patches (of its own group) that reached it. The result
//!   is continuous inside a group and discontinuous between groups, so it
//!   is returned per element (six nodal values each).
//! * **ZZ indicator**: `η_e² = ∫_e (σ* − σ_h)ᵀ D⁻¹ (σ* − σ_h) dA` over the
//!   in-plane components, σ* interpolated from the element's recovered
//!   nodal values; `η = (Σ η_e²)^{1/2}` estimates the energy-norm error
//!   ([`ErrorEstimate`], with the relative value `η / (‖σ_h‖² + η²)^{1/2}`,
//!   ‖σ_h‖² = Σ ∫_e σ_hᵀ D⁻¹ σ_h dA).

// Stress components are indexed alongside several arrays; ranges read best.
#![allow(clippy::needless_range_loop)]

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use tecon_fem::triangle6::{Triangle6, shape};

use crate::kernels::P2_RULE;

/// Stress at one integration point: position, weight (m²) and
/// `(σ_xx, σ_yy, σ_xy, σ_zz)`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PointStress {
    /// Physical position.
    pub x: [f64; 2],
    /// Integration weight (area).
    pub weight: f64,
    /// `(σ_xx, σ_yy, σ_xy, σ_zz)`.
    pub stress: [f64; 4],
}

/// Recovered nodal stresses of each 6-node triangle by SPR within the
/// element's group (`groups[e]`, e.g. its region index).
///
/// `nodes` are the mesh coordinates, `triangles` the 6-node connectivity,
/// `points[e]` the stresses at the element's integration points (any
/// number ≥ 1 per element, e.g. the six of [`P2_RULE`]). A patch whose
/// points do not determine a quadratic falls back to a linear fit, then to
/// the mean.
pub fn spr_recovery(
    nodes: &[[f64; 2]],
    triangles: &[[usize; 6]],
    groups: &[usize],
    points: &[Vec<PointStress>],
) -> Vec<[[f64; 4]; 6]> {
    let n_nodes = nodes.len();
    // Corner node → elements, per group (sorted by element: deterministic).
    let mut node_elements: Vec<Vec<usize>> = vec![Vec::new(); n_nodes];
    for (e, t) in triangles.iter().enumerate() {
        for &a in &t[..3] {
            node_elements[a].push(e);
        }
    }
    let mut sum = vec![[[0.0; 4]; 6]; triangles.len()];
    let mut count = vec![[0usize; 6]; triangles.len()];
    let mut patch = Vec::new();
    for (a, elems) in node_elements.iter().enumerate() {
        let mut seen_groups: Vec<usize> = elems.iter().map(|&e| groups[e]).collect();
        seen_groups.sort_unstable();
        seen_groups.dedup();
        for g in seen_groups {
            patch.clear();
            patch.extend(elems.iter().copied().filter(|&e| groups[e] == g));
            let centre = nodes[a];
            let size = patch
                .iter()
                .flat_map(|&e| triangles[e].iter())
                .map(|&b| {
                    let d = [nodes[b][0] - centre[0], nodes[b][1] - centre[1]];
                    d[0].hypot(d[1])
                })
                .fold(0.0, f64::max)
                .max(f64::MIN_POSITIVE);
            let local = |x: [f64; 2]| [(x[0] - centre[0]) / size, (x[1] - centre[1]) / size];
            let fit = fit_patch(
                patch
                    .iter()
                    .flat_map(|&e| points[e].iter())
                    .map(|p| (local(p.x), p.stress)),
            );
            for &e in patch.iter() {
                for (k, &b) in triangles[e].iter().enumerate() {
                    let v = fit.eval(local(nodes[b]));
                    for c in 0..4 {
                        sum[e][k][c] += v[c];
                    }
                    count[e][k] += 1;
                }
            }
        }
    }
    // Each element node averages the patches of its group that reached it:
    // gather per (node, group) so the element copies of one node agree.
    let mut by_node: std::collections::BTreeMap<(usize, usize), ([f64; 4], usize)> =
        std::collections::BTreeMap::new();
    for (e, t) in triangles.iter().enumerate() {
        for (k, &b) in t.iter().enumerate() {
            let entry = by_node.entry((b, groups[e])).or_insert(([0.0; 4], 0));
            for c in 0..4 {
                entry.0[c] += sum[e][k][c];
            }
            entry.1 += count[e][k];
        }
    }
    triangles
        .iter()
        .enumerate()
        .map(|(e, t)| {
            t.map(|b| {
                let (s, n) = by_node[&(b, groups[e])];
                s.map(|v| v / n.max(1) as f64)
            })
        })
        .collect()
}

/// A least-squares fit over a patch: quadratic, linear or constant.
enum Fit {
    Quadratic(SMatrix<f64, 6, 4>),
    Linear(SMatrix<f64, 3, 4>),
    Mean([f64; 4]),
}

impl Fit {
    fn eval(&self, x: [f64; 2]) -> [f64; 4] {
        match self {
            Fit::Quadratic(a) => {
                let p = SVector::<f64, 6>::from([
                    1.0,
                    x[0],
                    x[1],
                    x[0] * x[0],
                    x[0] * x[1],
                    x[1] * x[1],
                ]);
                let v = a.transpose() * p;
                [v[0], v[1], v[2], v[3]]
            }
            Fit::Linear(a) => {
                let v = a.transpose() * Vector3::new(1.0, x[0], x[1]);
                [v[0], v[1], v[2], v[3]]
            }
            Fit::Mean(m) => *m,
        }
    }
}

fn fit_patch(samples: impl Iterator<Item = ([f64; 2], [f64; 4])> + Clone) -> Fit {
    let mut a6 = SMatrix::<f64, 6, 6>::zeros();
    let mut b6 = SMatrix::<f64, 6, 4>::zeros();
    let mut a3 = Matrix3::<f64>::zeros();
    let mut b3 = SMatrix::<f64, 3, 4>::zeros();
    let mut mean = [0.0; 4];
    let mut n = 0usize;
    for (x, s) in samples {
        let p6 = SVector::<f64, 6>::from([1.0, x[0], x[1], x[0] * x[0], x[0] * x[1], x[1] * x[1]]);
        let p3 = Vector3::new(1.0, x[0], x[1]);
        let sv = nalgebra::RowVector4::from(s);
        a6 += p6 * p6.transpose();
        b6 += p6 * sv;
        a3 += p3 * p3.transpose();
        b3 += p3 * sv;
        for c in 0..4 {
            mean[c] += s[c];
        }
        n += 1;
    }
    // Accept a fit only when the normal matrix is well conditioned.
    let well = |d: f64, m: f64| d > 1e-10 * m;
    if n >= 6 {
        let ev = a6.symmetric_eigenvalues();
        if well(ev.min(), ev.max())
            && let Some(c) = a6.cholesky()
        {
            return Fit::Quadratic(c.solve(&b6));
        }
    }
    if n >= 3 {
        let ev = a3.symmetric_eigenvalues();
        if well(ev.min(), ev.max())
            && let Some(c) = a3.cholesky()
        {
            return Fit::Linear(c.solve(&b3));
        }
    }
    Fit::Mean(mean.map(|v| v / n.max(1) as f64))
}

/// Zienkiewicz–Zhu indicator per element:
/// `η_e = (∫_e (σ* − σ_h)ᵀ C (σ* − σ_h) dA)^{1/2}` over the in-plane
/// components, with `C = compliance[e]` (the inverse of the in-plane D),
/// σ* from the recovered nodal values interpolated to the [`P2_RULE`]
/// points, σ_h the element's stresses at the same points (in rule order).
pub fn zz_indicator(
    geometry: &[Triangle6],
    compliance: &[Matrix3<f64>],
    points: &[Vec<PointStress>],
    recovered: &[[[f64; 4]; 6]],
) -> Vec<f64> {
    geometry
        .iter()
        .enumerate()
        .map(|(e, g)| {
            let mut eta2 = 0.0;
            for (q, p) in g.points(P2_RULE).enumerate() {
                let n = shape(p.xi);
                let mut d = Vector3::zeros();
                for c in 0..3 {
                    let star: f64 = (0..6).map(|a| n[a] * recovered[e][a][c]).sum();
                    d[c] = star - points[e][q].stress[c];
                }
                eta2 += p.weight * (d.transpose() * compliance[e] * d)[0];
            }
            eta2.max(0.0).sqrt()
        })
        .collect()
}

/// Recovered nodal stresses of each linear triangle: at each corner, the
/// area-weighted mean of the constant stresses `element` of the elements of
/// the same group (`groups[e]`) around the node. Continuous inside a group,
/// never averaged across groups. `areas` may be signed.
pub fn nodal_average(
    n_nodes: usize,
    triangles: &[[usize; 3]],
    groups: &[usize],
    areas: &[f64],
    element: &[[f64; 4]],
) -> Vec<[[f64; 4]; 3]> {
    // (node, group) → slot, in order of first appearance (deterministic)
    let mut first: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n_nodes];
    let mut acc: Vec<[f64; 5]> = Vec::new();
    let mut slots = Vec::with_capacity(3 * triangles.len());
    for (e, t) in triangles.iter().enumerate() {
        let w = areas[e].abs();
        for &v in t {
            let slot = match first[v].iter().find(|(g, _)| *g == groups[e]) {
                Some(&(_, k)) => k,
                None => {
                    acc.push([0.0; 5]);
                    first[v].push((groups[e], acc.len() - 1));
                    acc.len() - 1
                }
            };
            for c in 0..4 {
                acc[slot][c] += w * element[e][c];
            }
            acc[slot][4] += w;
            slots.push(slot);
        }
    }
    let mean = |a: &[f64; 5]| {
        if a[4] > 0.0 {
            [a[0] / a[4], a[1] / a[4], a[2] / a[4], a[3] / a[4]]
        } else {
            [0.0; 4]
        }
    };
    slots
        .chunks_exact(3)
        .map(|s| [mean(&acc[s[0]]), mean(&acc[s[1]]), mean(&acc[s[2]])])
        .collect()
}

/// Zienkiewicz–Zhu indicator of linear triangles:
/// `η_e = (∫_e (σ* − σ_h)ᵀ C (σ* − σ_h) dA)^{1/2}` with σ* linear through
/// the recovered corner values and σ_h the constant element stress,
/// integrated exactly (`∫ N_a N_b dA = A (1 + δ_ab) / 12`); in-plane
/// components, `C = compliance[e]`.
pub fn zz_indicator_linear(
    areas: &[f64],
    compliance: &[Matrix3<f64>],
    element: &[[f64; 4]],
    recovered: &[[[f64; 4]; 3]],
) -> Vec<f64> {
    recovered
        .iter()
        .enumerate()
        .map(|(e, r)| {
            let d = r.map(|s| {
                Vector3::new(
                    s[0] - element[e][0],
                    s[1] - element[e][1],
                    s[2] - element[e][2],
                )
            });
            let mut eta2 = 0.0;
            for a in 0..3 {
                for b in 0..3 {
                    let w = if a == b { 2.0 } else { 1.0 };
                    eta2 += w * (d[a].transpose() * compliance[e] * d[b])[0];
                }
            }
            (areas[e].abs() / 12.0 * eta2).max(0.0).sqrt()
        })
        .collect()
}

/// Energy norm squared `∫_e σᵀ C σ dA` of a stress over a weight (area).
pub fn energy_density(compliance: &Matrix3<f64>, s: [f64; 4], weight: f64) -> f64 {
    let v = Vector3::new(s[0], s[1], s[2]);
    weight * (v.transpose() * compliance * v)[0]
}

/// The Zienkiewicz–Zhu error estimate of a stress field: per element and
/// global, absolute and relative to the energy norm of the stresses.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ErrorEstimate {
    /// η_e per element (√(J/m): energy per unit thickness).
    pub element: Vec<f64>,
    /// η = (Σ η_e²)^{1/2}.
    pub eta: f64,
    /// ‖σ_h‖ = (Σ ∫_e σ_hᵀ C σ_h dA)^{1/2}, the same norm.
    pub norm: f64,
}

impl ErrorEstimate {
    /// From the per-element η_e and the per-element ‖σ_h‖²_e.
    pub fn new(element: Vec<f64>, norm_squared: &[f64]) -> Self {
        let eta = element.iter().map(|v| v * v).sum::<f64>().sqrt();
        let norm = norm_squared.iter().sum::<f64>().max(0.0).sqrt();
        ErrorEstimate { element, eta, norm }
    }

    /// The relative estimate `η / (‖σ_h‖² + η²)^{1/2}` (0 for a zero field).
    pub fn relative(&self) -> f64 {
        let d = self.norm.hypot(self.eta);
        if d > 0.0 { self.eta / d } else { 0.0 }
    }
}

/// In-plane compliance `C = D⁻¹` (zero for a singular D, which a checked
/// material never has).
pub fn compliance(d: &Matrix3<f64>) -> Matrix3<f64> {
    d.try_inverse().unwrap_or_else(Matrix3::zeros)
}

#[cfg(test)]
mod tests {
    //! Goal: SPR reproduces a field the fit contains (a linear stress,
    //! exactly) and never averages across groups: two groups with different
    //! uniform stresses keep their own values at the nodes they share.
    use super::*;

    /// Square [0, 2] × [0, 1] of 4 straight 6-node triangles (two cells).
    fn mesh() -> (Vec<[f64; 2]>, Vec<[usize; 6]>) {
        let g = |i: usize, j: usize| j * 5 + i; // 5 × 3 node grid, step 0.5
        let nodes = (0..15)
            .map(|k| [(k % 5) as f64 * 0.5, (k / 5) as f64 * 0.5])
            .collect();
        let mut tris = Vec::new();
        for c in 0..2 {
            let i = 2 * c;
            tris.push([
                g(i, 0),
                g(i + 2, 0),
                g(i + 2, 2),
                g(i + 1, 0),
                g(i + 2, 1),
                g(i + 1, 1),
            ]);
            tris.push([
                g(i, 0),
                g(i + 2, 2),
                g(i, 2),
                g(i + 1, 1),
                g(i + 1, 2),
                g(i, 1),
            ]);
        }
        (nodes, tris)
    }

    fn points_of(
        nodes: &[[f64; 2]],
        tris: &[[usize; 6]],
        f: impl Fn(usize, [f64; 2]) -> [f64; 4],
    ) -> Vec<Vec<PointStress>> {
        tris.iter()
            .enumerate()
            .map(|(e, t)| {
                let g = Triangle6::new(t.map(|a| nodes[a])).unwrap();
                g.points(P2_RULE)
                    .map(|p| {
                        let x = g.position(p.xi);
                        PointStress {
                            x,
                            weight: p.weight,
                            stress: f(e, x),
                        }
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn reproduces_a_linear_field_and_keeps_groups_apart() {
        let (nodes, tris) = mesh();
        let lin = |x: [f64; 2]| [1.0 + 2.0 * x[0], 3.0 - x[1], x[0] * 0.5 + x[1], 7.0];
        let pts = points_of(&nodes, &tris, |_, x| lin(x));
        let rec = spr_recovery(&nodes, &tris, &[0; 4], &pts);
        for (e, t) in tris.iter().enumerate() {
            for (k, &a) in t.iter().enumerate() {
                let exact = lin(nodes[a]);
                for c in 0..4 {
                    assert!((rec[e][k][c] - exact[c]).abs() < 1e-12, "e{e} node {a}");
                }
            }
        }
        // Cell 0 (elements 0, 1) uniform 10, cell 1 (elements 2, 3) uniform
        // −4: the shared column x = 1 keeps both values.
        let groups = [0, 0, 1, 1];
        let pts = points_of(&nodes, &tris, |e, _| [if e < 2 { 10.0 } else { -4.0 }; 4]);
        let rec = spr_recovery(&nodes, &tris, &groups, &pts);
        for (e, r) in rec.iter().enumerate() {
            let want = if e < 2 { 10.0 } else { -4.0 };
            for v in r {
                assert!(v.iter().all(|s| (s - want).abs() < 1e-12), "e{e}: {v:?}");
            }
        }
        // One group: the shared nodes mix the two values.
        let mixed = spr_recovery(&nodes, &tris, &[0; 4], &pts);
        let shared = tris[0].iter().position(|&a| a == 2).unwrap();
        assert!((mixed[0][shared][0] - 10.0).abs() > 1.0);
    }

    #[test]
    fn zz_indicator_vanishes_for_a_recovered_field_equal_to_the_raw_one() {
        let (nodes, tris) = mesh();
        let geometry: Vec<Triangle6> = tris
            .iter()
            .map(|t| Triangle6::new(t.map(|a| nodes[a])).unwrap())
            .collect();
        let lin = |x: [f64; 2]| [1.0 + 2.0 * x[0], 3.0 - x[1], x[0] * 0.5 + x[1], 7.0];
        let pts = points_of(&nodes, &tris, |_, x| lin(x));
        let rec = spr_recovery(&nodes, &tris, &[0; 4], &pts);
        let c = vec![Matrix3::identity(); 4];
        let eta = zz_indicator(&geometry, &c, &pts, &rec);
        assert!(eta.iter().all(|v| *v < 1e-12), "{eta:?}");
        // A uniform offset of 1 in σ_xx on element 0: η₀² = ∫ 1 dA = A.
        let mut off = rec.clone();
        for v in off[0].iter_mut() {
            v[0] += 1.0;
        }
        let eta = zz_indicator(&geometry, &c, &pts, &off);
        assert!((eta[0] - geometry[0].area().sqrt()).abs() < 1e-12);
    }

    /// Unit square of 4 linear triangles around the centre node 4.
    fn square3() -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
        let nodes = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]];
        let tris = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
        (nodes, tris)
    }

    #[test]
    fn nodal_average_keeps_groups_apart_and_zz_linear_is_exact() {
        let (nodes, tris) = square3();
        let areas = vec![0.25; 4];
        // uniform per group, two groups: no error, nothing mixed
        let groups = [0, 0, 1, 1];
        let el: Vec<[f64; 4]> = (0..4)
            .map(|e| [if e < 2 { 5.0 } else { -3.0 }, 1.0, 2.0, 0.5])
            .collect();
        let rec = nodal_average(nodes.len(), &tris, &groups, &areas, &el);
        for (e, r) in rec.iter().enumerate() {
            assert!(r.iter().all(|v| *v == el[e]), "e{e}: {r:?}");
        }
        let c = vec![Matrix3::identity(); 4];
        let eta = zz_indicator_linear(&areas, &c, &el, &rec);
        assert!(eta.iter().all(|v| *v == 0.0));
        // One group: σ*_xx is 1 at node 0 (e0: 5, e3: −3), 5 at node 1
        // (e0, e1) and 1 at the centre, so on element 0 σ* − σ_h is
        // d = (−4, 0, −4) in σ_xx only and
        // ∫ d² dA = A/12 (2 Σ d_a² + Σ_{a≠b} d_a d_b) = 0.25/12 · 96 = 2.
        let rec = nodal_average(nodes.len(), &tris, &[0; 4], &areas, &el);
        let eta = zz_indicator_linear(&areas, &c, &el, &rec);
        assert!((eta[0] - 2f64.sqrt()).abs() < 1e-12, "{eta:?}");
        let est = ErrorEstimate::new(eta.clone(), &[1.0; 4]);
        assert!((est.eta - eta.iter().map(|v| v * v).sum::<f64>().sqrt()).abs() < 1e-12);
        assert!((est.norm - 2.0).abs() < 1e-12);
        assert!((est.relative() - est.eta / (4.0 + est.eta.powi(2)).sqrt()).abs() < 1e-15);
        assert_eq!(ErrorEstimate::default().relative(), 0.0);
    }
}
