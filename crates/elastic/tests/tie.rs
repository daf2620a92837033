//! Bonded (tied) interfaces.
//!
//! Reference: the Lamé thick cylinder under internal pressure p
//! (`LameCylinder`, plane strain), a ≤ r ≤ b with a = 1, b = 1.2, made of
//! two rings 1 ≤ r ≤ 1.1 and 1.1 ≤ r ≤ 1.2 joined at r = 1.1 (no
//! interference: shrink-free).
//!
//! Goal: a tied interface (facing nodes merged, [`TiedMesh`]) is the
//! single-body cylinder: equal, to round-off, to the fused one-ring mesh of
//! the same nodes; u_r at the bore converges to Lamé at the observed order
//! of linear triangles (slope of log error against log h fitted and
//! asserted); a linear joint converges to the tied answer as its penalty
//! grows (difference ∝ 1/k, the tie has none); on a P2 mesh the mid nodes
//! are tied too.
//!
//! ```text
//!   quarter ring, θ ∈ [0, π/2]; u_y = 0 on "start" (θ = 0), u_x = 0 on "end"
//!   outer ring 1.1 … 1.2 ── tied "inner_outer" ── inner ring 1 … 1.1 ← p
//! ```

mod common;

use std::f64::consts::FRAC_PI_2;

use tecon_contact::LinearJoint;
use tecon_elastic::analytical::LameCylinder;
use tecon_elastic::{Joint, Loads, SolverOptions, StaticSolver, TiedMesh};
use tecon_mesh::{Mesh, RingLayer, layered_annulus, layered_annulus_of_order};

use common::STEEL;
const P: f64 = 10e6;

fn layer(name: &str, r_in: f64, r_out: f64, rows: usize) -> RingLayer {
    RingLayer {
        name: name.into(),
        r_in,
        r_out,
        rows,
    }
}

fn two_rings(rows: usize, segments: usize) -> Mesh {
    layered_annulus(
        &[
            layer("inner", 1.0, 1.1, rows),
            layer("outer", 1.1, 1.2, rows),
        ],
        0.0,
        FRAC_PI_2,
        segments,
    )
    .unwrap()
}

/// Displacements under the internal pressure, with `joint` on the interface
/// (None: the mesh has no interface left).
fn solve(mesh: &Mesh, joint: Option<Joint>) -> Vec<f64> {
    let mut model = common::lame_sector(mesh, P);
    if let Some(j) = joint {
        model = model.interface("inner_outer", j).unwrap();
    }
    let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
    solver
        .advance(&Loads {
            pressure: 1.0,
            ..Loads::zero()
        })
        .unwrap();
    solver.displacement().to_vec()
}

fn lame() -> LameCylinder {
    LameCylinder {
        a: 1.0,
        b: 1.2,
        p: P,
        e: STEEL.youngs_modulus,
        nu: STEEL.poisson_ratio,
    }
}

/// Largest |u_r − u_r,Lamé| over the bore nodes, relative to u_r,Lamé(a).
fn bore_error(mesh: &Mesh, u: &[f64]) -> f64 {
    let exact = lame().u_r(1.0);
    (0..mesh.n_nodes())
        .filter(|&i| {
            let x = mesh.nodes()[i];
            (x[0].hypot(x[1]) - 1.0).abs() < 1e-12
        })
        .map(|i| {
            let x = mesh.nodes()[i];
            let ur = (u[2 * i] * x[0] + u[2 * i + 1] * x[1]) / x[0].hypot(x[1]);
            (ur - exact).abs() / exact
        })
        .fold(0.0, f64::max)
}

#[test]
fn tied_rings_are_the_fused_ring() {
    let (rows, segments) = (2, 12);
    let mesh = two_rings(rows, segments);
    let tied = TiedMesh::new(&mesh, &["inner_outer"]).unwrap();
    // every interface node pair merged
    assert_eq!(
        tied.mesh().n_nodes(),
        mesh.n_nodes() - (segments + 1),
        "one node per facing pair"
    );
    assert_eq!(tied.mesh().bodies().len(), 1);
    assert!(tied.mesh().interfaces().is_empty());
    let u_tied = tied.expand_displacement(&solve(tied.mesh(), None));

    let fused = layered_annulus(
        &[layer("ring", 1.0, 1.2, 2 * rows)],
        0.0,
        FRAC_PI_2,
        segments,
    )
    .unwrap();
    let u_fused = solve(&fused, None);
    let scale = u_fused.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst: f64 = 0.0;
    for (i, x) in mesh.nodes().iter().enumerate() {
        let j = (0..fused.n_nodes())
            .find(|&j| {
                let y = fused.nodes()[j];
                (x[0] - y[0]).hypot(x[1] - y[1]) < 1e-12
            })
            .expect("the fused mesh has the same node positions");
        for c in 0..2 {
            worst = worst.max((u_tied[2 * i + c] - u_fused[2 * j + c]).abs() / scale);
        }
    }
    assert!(worst < 1e-9, "tied vs fused: {worst:e}");
}

#[test]
fn tied_shrink_free_cylinder_converges_to_lame() {
    let mut hs = Vec::new();
    let mut errors = Vec::new();
    for k in 0..3 {
        let f = 1 << k;
        let mesh = two_rings(2 * f, 12 * f);
        let tied = TiedMesh::new(&mesh, &["inner_outer"]).unwrap();
        let u = tied.expand_displacement(&solve(tied.mesh(), None));
        hs.push(1.0 / f as f64);
        errors.push(bore_error(&mesh, &u));
    }
    let slope = (errors[2] / errors[0]).ln() / (hs[2] / hs[0]).ln();
    assert!(errors[2] < 2e-3, "bore u_r error {errors:?}");
    assert!(
        (slope - 2.0).abs() < 0.2,
        "observed order {slope} ({errors:?})"
    );
}

#[test]
fn stiff_linear_joint_converges_to_the_tie_as_one_over_k() {
    let mesh = two_rings(2, 12);
    let tied = TiedMesh::new(&mesh, &["inner_outer"]).unwrap();
    let u_tied = tied.expand_displacement(&solve(tied.mesh(), None));
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let k0 = STEEL.youngs_modulus / 0.05;
    let diffs: Vec<f64> = [1e2, 1e4]
        .iter()
        .map(|&beta| {
            let j = Joint::Linear(LinearJoint::new(beta * k0, beta * k0).unwrap());
            let u = solve(&mesh, Some(j));
            let d: Vec<f64> = u.iter().zip(&u_tied).map(|(a, b)| a - b).collect();
            norm(&d) / norm(&u_tied)
        })
        .collect();
    // 100× the penalty: 100× closer (1/k), and close already
    let ratio = diffs[0] / diffs[1];
    assert!((ratio / 100.0 - 1.0).abs() < 0.05, "{diffs:?}");
    assert!(diffs[1] < 1e-5, "{diffs:?}");
}

#[test]
fn p2_tie_merges_the_mid_nodes_too() {
    let segments = 6;
    let mesh = layered_annulus_of_order(
        &[layer("inner", 1.0, 1.1, 1), layer("outer", 1.1, 1.2, 1)],
        0.0,
        FRAC_PI_2,
        segments,
        2,
    )
    .unwrap();
    let tied = TiedMesh::new(&mesh, &["inner_outer"]).unwrap();
    // corner pairs and mid-node pairs
    assert_eq!(tied.mesh().n_nodes(), mesh.n_nodes() - (2 * segments + 1));
    assert_eq!(tied.mesh().order(), 2);
    assert_eq!(tied.mesh().bodies().len(), 1);
    let iface = mesh.interface("inner_outer").unwrap();
    let map = tied.node_map();
    for (el, mid) in iface.elements.iter().zip(&iface.mid_nodes) {
        assert_eq!(map[el[0]], map[el[3]]);
        assert_eq!(map[el[1]], map[el[2]]);
        assert_eq!(map[mid[0]], map[mid[1]]);
    }
    // node positions are kept
    for (v, &m) in map.iter().enumerate() {
        let (a, b) = (mesh.nodes()[v], tied.mesh().nodes()[m]);
        assert!((a[0] - b[0]).hypot(a[1] - b[1]) < 1e-12);
    }
}

#[test]
fn unknown_interface_is_an_error_naming_it() {
    let mesh = two_rings(1, 4);
    let e = TiedMesh::new(&mesh, &["nope"]).unwrap_err().to_string();
    assert!(e.contains("nope"), "{e}");
}
