//! Set-ups shared by the elastic integration tests.
#![allow(dead_code)] // each test crate uses a part

use tecon_elastic::{Analysis, ElasticModel, Material};
use tecon_mesh::Mesh;

/// The steel of the tests (the vessel's: E = 207 GPa, ν = 0.3,
/// α = 12.51e-6 /K).
pub const STEEL: Material = Material {
    youngs_modulus: 207e9,
    poisson_ratio: 0.3,
    expansion: 12.51e-6,
};

/// A plane-strain steel model of an annulus sector `mesh` with symmetry on
/// its edge sets `start` and `end`.
pub fn steel_sector(mesh: &Mesh) -> ElasticModel<'_> {
    ElasticModel::new(mesh, Analysis::PlaneStrain)
        .material_everywhere(STEEL)
        .unwrap()
        .symmetry("start")
        .unwrap()
        .symmetry("end")
        .unwrap()
}

/// The same under the internal pressure `p` on the edge set `inner` (the
/// Lamé cylinder).
pub fn lame_sector(mesh: &Mesh, p: f64) -> ElasticModel<'_> {
    steel_sector(mesh).pressure("inner", p).unwrap()
}

/// Least-squares slope of log(e) against log(h).
pub fn slope(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (x, y): (Vec<f64>, Vec<f64>) = h.iter().zip(e).map(|(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// [0,1]×[0,1] below (region `bottom`), [0,1]×[1,1+h] above (`top`), 4
/// cells across; edge sets `base`, `bottom_face`, `top_face`, `lid` and the
/// interface `joint` between the faces.
pub fn stacked_blocks(h: f64) -> Mesh {
    let a = tecon_mesh::rectangle(0.0, 0.0, 1.0, 1.0, 4, 4).unwrap();
    let top = tecon_mesh::rectangle(0.0, 1.0, 1.0, h, 4, 2).unwrap();
    let mut nodes = a.nodes().to_vec();
    let off = nodes.len();
    nodes.extend_from_slice(top.nodes());
    let mut tris = a.triangles().to_vec();
    tris.extend(top.triangles().iter().map(|t| t.map(|v| v + off)));
    let regions = (0..tris.len())
        .map(|e| usize::from(e >= a.n_triangles()))
        .collect();
    let mut m = Mesh::new(nodes, tris, regions, vec!["bottom".into(), "top".into()]).unwrap();
    let shift = |e: &[[usize; 2]]| {
        e.iter()
            .map(|&[p, q]| [p + off, q + off])
            .collect::<Vec<_>>()
    };
    m.add_edge_set("base", a.edge_set("bottom").unwrap().to_vec())
        .unwrap();
    m.add_edge_set("bottom_face", a.edge_set("top").unwrap().to_vec())
        .unwrap();
    m.add_edge_set("top_face", shift(top.edge_set("bottom").unwrap()))
        .unwrap();
    m.add_edge_set("lid", shift(top.edge_set("top").unwrap()))
        .unwrap();
    m.add_interface("joint", "bottom_face", "top_face", None)
        .unwrap();
    m
}
