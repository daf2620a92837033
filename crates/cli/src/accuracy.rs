//! The quantities the vessel's accuracy is judged on, read from a finished
//! run at fixed points (so that meshes of any density and order compare),
//! and the convergence arithmetic of a study over graded meshes.
//!
//! * hoop stress σ_θθ of the cooled state on the four surfaces (core inner
//!   and outer, layer inner and outer) at θ = 45°, 90°, 180° (the far field)
//!   and on the layer's faces at θ = 0 (the weld plane);
//! * the opening Δu_n of the joint at θ = 0.4° (beside the weld);
//! * temperatures at fixed points of the weld plane and beside it, at the
//!   output times up to 3600 s, and the lowest nodal temperature after 1 s.
//!
//! Point values are interpolated along the node ring of the surface in θ:
//! through the three nodes of the element edge at order 2 (quadratic), the
//! two nodes at order 1 (linear). Stresses are the per-region recovered
//! nodal values of the body the ring belongs to.

use tecon_mesh::Mesh;

use crate::vessel::{VesselRun, bodies, r_theta, ring_nodes};

/// One judged quantity of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Judged {
    /// Name, e.g. `hoop_layer_outer_90` or `T_layer_outer_0_at_10s`.
    pub name: String,
    /// Value (Pa, m or °C).
    pub value: f64,
}

/// The surfaces: (name, is core, radius).
fn surfaces(run: &VesselRun) -> [(&'static str, bool, f64); 4] {
    let g = &run.options.geometry;
    [
        ("core_inner", true, g.inner_radius),
        ("core_outer", true, g.interface_radius()),
        ("layer_inner", false, g.interface_radius()),
        ("layer_outer", false, g.outer_radius()),
    ]
}

/// Lagrange interpolation at `t` through the points `(x_k, y_k)`.
fn lagrange(xs: &[f64], ys: &[f64], t: f64) -> f64 {
    let mut s = 0.0;
    for (i, (&xi, &yi)) in xs.iter().zip(ys).enumerate() {
        let mut l = 1.0;
        for (j, &xj) in xs.iter().enumerate() {
            if j != i {
                l *= (t - xj) / (xi - xj);
            }
        }
        s += l * yi;
    }
    s
}

/// A nodal quantity `f` on the sorted node ring `nodes` at angle `theta`:
/// quadratic through the element edge (corner, mid, corner) at order 2,
/// linear at order 1.
pub fn on_ring(mesh: &Mesh, nodes: &[usize], theta: f64, f: &dyn Fn(usize) -> f64) -> f64 {
    let th: Vec<f64> = nodes.iter().map(|&i| r_theta(mesh.nodes()[i]).1).collect();
    let n = th.len();
    if n < 2 {
        return f64::NAN;
    }
    let k = th
        .partition_point(|&x| x <= theta)
        .saturating_sub(1)
        .min(n - 2);
    let quadratic = mesh.triangles6().is_some() && n >= 3;
    let range = if quadratic {
        let j = (k / 2).min((n - 3) / 2);
        2 * j..2 * j + 3
    } else {
        k..k + 2
    };
    let ys: Vec<f64> = nodes[range.clone()].iter().map(|&i| f(i)).collect();
    lagrange(&th[range], &ys, theta)
}

/// Hoop stress of the final state on surface `surface` at `theta_deg`.
pub fn hoop_at(run: &VesselRun, surface: usize, theta_deg: f64) -> f64 {
    let (core, layer) = bodies(&run.mesh);
    let (_, is_core, r) = surfaces(run)[surface];
    let nodes = ring_nodes(&run.mesh, if is_core { core } else { layer }, r);
    let Some(last) = run.results.last() else {
        return f64::NAN;
    };
    on_ring(&run.mesh, &nodes, theta_deg.to_radians(), &|i| {
        tecon_elastic::polar(last.stress.nodal[i], run.mesh.nodes()[i], [0.0, 0.0])[1]
    })
}

/// Normal opening Δu_n of the joint in the final state at `theta_deg`,
/// interpolated through the points of the interface element that spans it
/// (NaN without interface points there).
pub fn gap_at(run: &VesselRun, theta_deg: f64) -> f64 {
    let Some(last) = run.results.last() else {
        return f64::NAN;
    };
    let t = theta_deg.to_radians();
    let mut by_element: std::collections::BTreeMap<(usize, usize), Vec<(f64, f64)>> =
        Default::default();
    for p in &last.interface {
        by_element
            .entry((p.interface, p.element))
            .or_default()
            .push((r_theta(p.position).1, p.jump[1]));
    }
    for pts in by_element.values() {
        let lo = pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
        let hi = pts.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
        if lo <= t && t <= hi && pts.len() >= 2 {
            let xs: Vec<f64> = pts.iter().map(|p| p.0).collect();
            let ys: Vec<f64> = pts.iter().map(|p| p.1).collect();
            return lagrange(&xs, &ys, t);
        }
    }
    f64::NAN
}

/// Temperature at time index `k` on surface `surface` at `theta_deg`.
pub fn temperature_at(run: &VesselRun, k: usize, surface: usize, theta_deg: f64) -> f64 {
    let (core, layer) = bodies(&run.mesh);
    let (_, is_core, r) = surfaces(run)[surface];
    let nodes = ring_nodes(&run.mesh, if is_core { core } else { layer }, r);
    let Some(t) = run.results.get(k).and_then(|s| s.temperature.as_ref()) else {
        return f64::NAN;
    };
    on_ring(&run.mesh, &nodes, theta_deg.to_radians(), &|i| t[i])
}

/// Angles of the far field, degrees.
pub const FAR_FIELD_DEG: [f64; 3] = [45.0, 90.0, 180.0];
/// Angle of the judged gap, degrees.
pub const GAP_DEG: f64 = 0.4;
/// Angles of the judged temperatures, degrees.
pub const TEMPERATURE_DEG: [f64; 3] = [0.0, 0.5, 2.0];

/// Every judged quantity of a run: far-field hoop (4 surfaces × 3 angles),
/// weld-plane hoop (layer faces), the gap, temperatures (4 surfaces × 3
/// angles × output times up to 3600 s) and the lowest temperature after 1 s.
pub fn judged(run: &VesselRun) -> Vec<Judged> {
    let mut out = Vec::new();
    let mut push = |name: String, value: f64| out.push(Judged { name, value });
    let names = surfaces(run).map(|s| s.0);
    for (s, name) in names.iter().enumerate() {
        for th in FAR_FIELD_DEG {
            push(format!("hoop_{name}_{th}"), hoop_at(run, s, th));
        }
    }
    for s in [2, 3] {
        push(
            format!("weld_plane_hoop_{}", names[s]),
            hoop_at(run, s, 0.0),
        );
    }
    push(format!("gap_{GAP_DEG}"), gap_at(run, GAP_DEG));
    for (k, r) in run.results.iter().enumerate() {
        if r.time > 3600.0 || r.temperature.is_none() {
            continue;
        }
        for (s, name) in names.iter().enumerate() {
            for th in TEMPERATURE_DEG {
                push(
                    format!("T_{name}_{th}_at_{}s", r.time),
                    temperature_at(run, k, s, th),
                );
            }
        }
    }
    push("T_min_after_1s".into(), min_temperature_after(run, 1.0));
    out
}

/// Lowest nodal temperature over the output times t ≥ `t0`.
pub fn min_temperature_after(run: &VesselRun, t0: f64) -> f64 {
    run.results
        .iter()
        .filter(|r| r.time >= t0)
        .filter_map(|r| r.temperature.as_ref())
        .flat_map(|t| t.iter().copied())
        .fold(f64::INFINITY, f64::min)
}

/// Observed order of convergence from three values on meshes whose size
/// halves each time: log₂ |q₁ − q₀| / |q₂ − q₁| (None when a difference
/// vanishes or the values do not converge monotonically in size).
pub fn observed_order(q: [f64; 3]) -> Option<f64> {
    let (d1, d2) = ((q[1] - q[0]).abs(), (q[2] - q[1]).abs());
    if d1 > 0.0 && d2 > 0.0 && d1.is_finite() && d2.is_finite() {
        Some((d1 / d2).log2())
    } else {
        None
    }
}

/// Richardson estimate of the limit from the two finest values and the order p:
/// q₂ + (q₂ − q₁) / (2^p − 1).
pub fn richardson(q1: f64, q2: f64, p: f64) -> f64 {
    q2 + (q2 - q1) / (2f64.powf(p) - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lagrange_is_exact_on_quadratics() {
        let f = |x: f64| 3.0 - 2.0 * x + 0.5 * x * x;
        let xs = [0.1, 0.4, 1.0];
        let ys = xs.map(f);
        for t in [0.0, 0.25, 0.7, 1.3] {
            assert!((lagrange(&xs, &ys, t) - f(t)).abs() < 1e-13);
        }
    }

    #[test]
    fn richardson_recovers_the_limit_of_a_power_law() {
        // q(h) = 2 + 0.3 h^2.5 on h = 1, 1/2, 1/4
        let q = [1.0, 0.5, 0.25].map(|h: f64| 2.0 + 0.3 * h.powf(2.5));
        let p = observed_order(q).unwrap();
        assert!((p - 2.5).abs() < 1e-12);
        assert!((richardson(q[1], q[2], p) - 2.0).abs() < 1e-12);
        assert_eq!(observed_order([1.0, 1.0, 1.0]), None);
    }
}
