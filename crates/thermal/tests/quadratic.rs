//! Verification of the quadratic (P2) heat-conduction kernels on curved
//! 6-node triangles.
//!
//! Run: `cargo test -p tecon-thermal --test quadratic -- --nocapture`
//! (prints the error table and the fitted orders).
//!
//! Reference: steady radial conduction in an annulus, `T = A + B ln r`.
//! Goal: the L2 error of P2 falls as h³ and the H1 error as h² on meshes
//! whose outer and inner boundaries are curved (isoparametric), with a
//! convective curved boundary (3-node edges). Measured: L2 2.99, H1 1.96.
//!
//! ```text
//!        θ = π/2  ┆ adiabatic (symmetry)
//!                 ┆╲___
//!                 ┆    ╲__        outer r_o = 2: convection h = 3, T∞ = 0
//!   inner r_i = 1 ╲       ╲
//!    T = 100       ╲       │
//!                   ╰──────┘  θ = 0 adiabatic (symmetry)
//! ```
//! The mesh is the polar image of a uniform (2n_r + 1) × (2n_θ + 1) grid of
//! nodes: every mid node lies on the polar image of its edge (curved edges
//! on both circles and along the diagonals).

use std::sync::Arc;

use tecon_fem::edge3::Edge3;
use tecon_fem::quadrature::TriangleRule;
use tecon_fem::triangle6::Triangle6;
use tecon_fem::{AssemblerBuilder, CholeskySolver, Dirichlet, Parallelism};
use tecon_thermal::kernels6::{Conduction6Elements, Convection3Edges};

const R_I: f64 = 1.0;
const R_O: f64 = 2.0;
const K: f64 = 2.0;
const H: f64 = 3.0;
const T_I: f64 = 100.0;

/// `T(r) = T_i + B ln(r/r_i)` with `−k T'(r_o) = h T(r_o)`.
fn exact(r: f64) -> (f64, f64) {
    let b = -H * T_I / (K / R_O + H * (R_O / R_I).ln());
    (T_I + b * (r / R_I).ln(), b / r)
}

struct P2Mesh {
    nodes: Vec<[f64; 2]>,
    triangles: Vec<[usize; 6]>,
    inner: Vec<usize>,
    outer_edges: Vec<[usize; 3]>,
}

fn quarter_annulus(nr: usize, nt: usize) -> P2Mesh {
    let (gr, gt) = (2 * nr + 1, 2 * nt + 1);
    let id = |i: usize, j: usize| i * gt + j;
    let mut nodes = Vec::with_capacity(gr * gt);
    for i in 0..gr {
        let r = R_I + (R_O - R_I) * i as f64 / (gr - 1) as f64;
        for j in 0..gt {
            let t = std::f64::consts::FRAC_PI_2 * j as f64 / (gt - 1) as f64;
            nodes.push([r * t.cos(), r * t.sin()]);
        }
    }
    let mut triangles = Vec::new();
    for a in 0..nr {
        for b in 0..nt {
            let (i, j) = (2 * a, 2 * b);
            triangles.push([
                id(i, j),
                id(i + 2, j),
                id(i + 2, j + 2),
                id(i + 1, j),
                id(i + 2, j + 1),
                id(i + 1, j + 1),
            ]);
            triangles.push([
                id(i, j),
                id(i + 2, j + 2),
                id(i, j + 2),
                id(i + 1, j + 1),
                id(i + 1, j + 2),
                id(i, j + 1),
            ]);
        }
    }
    let inner = (0..gt).map(|j| id(0, j)).collect();
    let outer_edges = (0..nt)
        .map(|b| {
            [
                id(gr - 1, 2 * b),
                id(gr - 1, 2 * b + 2),
                id(gr - 1, 2 * b + 1),
            ]
        })
        .collect();
    P2Mesh {
        nodes,
        triangles,
        inner,
        outer_edges,
    }
}

/// Solves the annulus on `mesh`; returns (L2 error, H1-seminorm error).
fn solve_and_measure(mesh: &P2Mesh) -> (f64, f64) {
    let n = mesh.nodes.len();
    let geometry: Vec<Triangle6> = mesh
        .triangles
        .iter()
        .map(|t| Triangle6::new(t.map(|a| mesh.nodes[a])).expect("valid element"))
        .collect();
    let conductivity = vec![K; mesh.triangles.len()];
    let cond = Conduction6Elements {
        geometry: &geometry,
        triangles: &mesh.triangles,
        conductivity: &conductivity,
    };
    let mut conv = Convection3Edges::default();
    for e in &mesh.outer_edges {
        conv.edges.push(*e);
        conv.geometry
            .push(Edge3::new(e.map(|a| mesh.nodes[a])).expect("valid edge"));
        conv.h.push(H);
        conv.ambient.push(0.0);
    }
    let mut builder = AssemblerBuilder::new(n);
    let b_cond = builder.add_elements(&cond);
    let b_conv = builder.add_elements(&conv);
    let asm = builder.build().unwrap();
    let mut k = asm.new_matrix();
    let mut f = vec![0.0; n];
    asm.add(b_cond, &cond, &mut k, None, Parallelism::Rayon)
        .unwrap();
    asm.add(b_conv, &conv, &mut k, Some(&mut f), Parallelism::Rayon)
        .unwrap();
    let mut dirichlet = Dirichlet::new();
    for &i in &mesh.inner {
        dirichlet.set(i, T_I);
    }
    dirichlet
        .prepare(asm.pattern())
        .unwrap()
        .apply(&mut k, &mut f);
    let mut solver = CholeskySolver::analyse(Arc::clone(asm.pattern())).unwrap();
    solver.factorise(&k).unwrap();
    solver.solve(&mut f).unwrap();
    let t = f;
    let (mut l2, mut h1) = (0.0, 0.0);
    for (g, tri) in geometry.iter().zip(&mesh.triangles) {
        let v = tri.map(|a| t[a]);
        for q in g.points(TriangleRule::Degree5) {
            let x = g.position(q.xi);
            let r = x[0].hypot(x[1]);
            let (te, dte) = exact(r);
            let (gx, gy) = (dte * x[0] / r, dte * x[1] / r);
            let th = q.interpolate(&v);
            let dx: f64 = (0..6).map(|a| q.dndx[a] * v[a]).sum();
            let dy: f64 = (0..6).map(|a| q.dndy[a] * v[a]).sum();
            l2 += q.weight * (th - te).powi(2);
            h1 += q.weight * ((dx - gx).powi(2) + (dy - gy).powi(2));
        }
    }
    (l2.sqrt(), h1.sqrt())
}

fn fitted_slope(h: &[f64], e: &[f64]) -> f64 {
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

#[test]
fn p2_conduction_on_a_curved_annulus_converges_at_order_3_in_l2_and_2_in_h1() {
    let levels = [2usize, 4, 8, 16];
    let (mut hs, mut l2s, mut h1s) = (Vec::new(), Vec::new(), Vec::new());
    println!("  n_r  elements        L2 error        H1 error");
    for &nr in &levels {
        let mesh = quarter_annulus(nr, 2 * nr);
        let (l2, h1) = solve_and_measure(&mesh);
        println!("{nr:5} {:9} {l2:15.6e} {h1:15.6e}", mesh.triangles.len());
        hs.push(1.0 / nr as f64);
        l2s.push(l2);
        h1s.push(h1);
    }
    let (p_l2, p_h1) = (fitted_slope(&hs, &l2s), fitted_slope(&hs, &h1s));
    println!("fitted orders: L2 {p_l2:.3}, H1 {p_h1:.3}");
    assert!((p_l2 - 3.0).abs() < 0.2, "L2 order {p_l2}");
    assert!((p_h1 - 2.0).abs() < 0.2, "H1 order {p_h1}");
    // Absolute size: the finest mesh is within 1e-5 of T_i in L2 (a check
    // that the solve is the right problem, not only a right rate).
    assert!(l2s[3] < 1e-5 * T_I, "finest L2 error {}", l2s[3]);
}

// --------------------------------------------------------------------------
// Through the model: concentric rings joined by a 3-pair interface (P2 mesh)
// --------------------------------------------------------------------------

use tecon_mesh::{RingLayer, layered_annulus_of_order};
use tecon_thermal::analytical::ConcentricRings;
use tecon_thermal::{EdgeBc, InterfaceQuadrature, Material, ThermalModel};

const RINGS: ConcentricRings = ConcentricRings {
    r_a: 1.0,
    r_b: 1.5,
    r_c: 2.0,
    k1: 1.0,
    k2: 2.0,
    h_c: 2.0,
    h: 5.0,
    t_inner: 100.0,
    ambient: 0.0,
};

/// Full rings, `rows` element rows per ring and `segments` around, P2.
fn rings_p2(rows: usize, segments: usize) -> tecon_mesh::Mesh {
    let layer = |name: &str, r_in, r_out| RingLayer {
        name: name.into(),
        r_in,
        r_out,
        rows,
    };
    layered_annulus_of_order(
        &[
            layer("a", RINGS.r_a, RINGS.r_b),
            layer("b", RINGS.r_b, RINGS.r_c),
        ],
        0.0,
        2.0 * std::f64::consts::PI,
        segments,
        2,
    )
    .unwrap()
}

/// (L2 error of T, largest error of the interface jump at the node pairs,
/// relative error of the interface heat rate) of the steady rings.
fn rings_p2_errors(mesh: &tecon_mesh::Mesh, rule: InterfaceQuadrature) -> (f64, f64, f64) {
    let mut model = ThermalModel::new(mesh);
    model
        .set_material("a", Material::new(RINGS.k1, 1.0, 1.0))
        .unwrap()
        .set_material("b", Material::new(RINGS.k2, 1.0, 1.0))
        .unwrap()
        .add_edge_bc("inner", EdgeBc::temperature(RINGS.t_inner))
        .unwrap()
        .add_edge_bc("outer", EdgeBc::convection(RINGS.h, RINGS.ambient))
        .unwrap()
        .set_interface_law(
            "a_b",
            tecon_thermal::ConstantConductance::new(RINGS.h_c).unwrap(),
            rule,
        )
        .unwrap();
    let system = model.assemble().unwrap();
    assert_eq!(system.order(), 2);
    let snap = system.solve_steady().unwrap();
    assert!(snap.balance.relative_residual() < 1e-10);
    for b in &snap.bodies {
        assert!(
            b.relative_residual() < 1e-10,
            "{}: {:e}",
            b.body,
            b.relative_residual()
        );
    }
    let region_a = mesh.region_index("a").unwrap();
    let mut l2 = 0.0;
    for ((t6, &reg), _) in mesh
        .triangles6()
        .unwrap()
        .iter()
        .zip(mesh.element_regions())
        .zip(0..)
    {
        let g = Triangle6::new(t6.map(|a| mesh.nodes()[a])).unwrap();
        let v = t6.map(|a| snap.temperature[a]);
        for q in g.points(TriangleRule::Degree5) {
            let x = g.position(q.xi);
            let r = x[0].hypot(x[1]);
            let exact = if reg == region_a {
                RINGS.inner(r)
            } else {
                RINGS.outer(r)
            };
            l2 += q.weight * (q.interpolate(&v) - exact).powi(2);
        }
    }
    let itf = &snap.interfaces[0];
    let err_jump = itf
        .elements
        .iter()
        .flat_map(|f| f.jump.into_iter().chain(f.mid.map(|m| m[0])))
        .map(|j| (j + RINGS.jump()).abs())
        .fold(0.0, f64::max);
    let err_q = (itf.heat_rate + RINGS.heat_rate()).abs() / RINGS.heat_rate();
    (l2.sqrt(), err_jump, err_q)
}

#[test]
fn p2_model_rings_with_interface_converge_at_order_3() {
    for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
        let (mut hs, mut l2s) = (Vec::new(), Vec::new());
        println!("{rule:?}: rows  segments  L2 error   jump error   heat-rate error");
        for level in 0..4 {
            let f = 1usize << level;
            let mesh = rings_p2(f, 16 * f);
            let (l2, ej, eq) = rings_p2_errors(&mesh, rule);
            println!("{f:10} {:9} {l2:10.3e} {ej:12.3e} {eq:16.3e}", 16 * f);
            hs.push(1.0 / f as f64);
            l2s.push(l2);
            if level == 3 {
                assert!(ej < 1e-3 * RINGS.jump().abs(), "jump error {ej}");
                assert!(eq < 1e-4, "heat-rate error {eq}");
            }
        }
        let p = fitted_slope(&hs, &l2s);
        println!("{rule:?}: fitted L2 order {p:.3}");
        assert!((p - 3.0).abs() < 0.2, "{rule:?}: L2 order {p}");
    }
}
