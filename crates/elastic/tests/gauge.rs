//! The output gauge of a free rigid translation.
//!
//! Reference: a half ring pair (inner ring 1 ≤ r ≤ 1.1 heated by 50 K,
//! outer ring 1.1 ≤ r ≤ 1.2, frictional joint), symmetric about the
//! y-axis. Goal: the x-translation left free by u_y = 0 on y = 0 is fixed
//! by one node and removed again from the output, so the mean u_x of the
//! constrained body is zero and the output is the symmetric solution,
//! u_x(θ = 0) = −u_x(θ = π), whichever node carried the constraint.
//!
//! ```text
//!   θ ∈ [0, π], u_y = 0 on both ends (edge sets "start", "end")
//!   outer ring ───  joint "inner_outer"  ─── inner ring (+50 K)
//! ```

mod common;

use std::f64::consts::PI;

use tecon_contact::PaperJoint;
use tecon_elastic::{Joint, Loads, SolverOptions, StaticSolver};
use tecon_mesh::{RingLayer, layered_annulus};

use common::STEEL;

#[test]
fn free_translation_is_removed_from_the_output() {
    let layer = |name: &str, r_in: f64, r_out: f64| RingLayer {
        name: name.into(),
        r_in,
        r_out,
        rows: 2,
    };
    let mesh = layered_annulus(
        &[layer("inner", 1.0, 1.1), layer("outer", 1.1, 1.2)],
        0.0,
        PI,
        24,
    )
    .unwrap();
    let law = PaperJoint::with_default_penalty(STEEL.youngs_modulus, 0.05, 0.0, 0.3).unwrap();
    let model = common::steel_sector(&mesh)
        .remove_free_translations(true)
        .interface("inner_outer", Joint::Frictional(law))
        .unwrap();
    let opts = SolverOptions {
        augmented_lagrangian: Some(1e-4),
        ..Default::default()
    };
    let mut solver = StaticSolver::new(&model, opts).unwrap();
    let inner = mesh.region_index("inner").unwrap();
    let delta_t: Vec<f64> = mesh
        .element_regions()
        .iter()
        .map(|&r| if r == inner { 50.0 } else { 0.0 })
        .collect();
    solver
        .advance(&Loads {
            delta_t,
            ..Loads::zero()
        })
        .unwrap();
    assert!(
        solver.notes().iter().any(|n| n.contains("mean u_x")),
        "{:?}",
        solver.notes()
    );
    let u = solver.displacement();
    let raw = solver.raw_displacement();
    let x = mesh.nodes();
    // a rigid shift of every node
    let shift = u[0] - raw[0];
    for v in 0..mesh.n_nodes() {
        assert!((u[2 * v] - raw[2 * v] - shift).abs() <= 1e-15 * shift.abs().max(1e-9));
        assert_eq!(u[2 * v + 1], raw[2 * v + 1]);
    }
    // mean u_x of the body that carries the constraint is zero
    let u_max = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let means: Vec<f64> = mesh
        .bodies()
        .iter()
        .map(|body| {
            let (mut area, mut sum) = (0.0, 0.0);
            for &e in &body.elements {
                let t = mesh.triangles()[e];
                let p = t.map(|v| x[v]);
                let a = 0.5
                    * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                        - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
                        .abs();
                area += a;
                sum += a * t.iter().map(|&v| u[2 * v]).sum::<f64>() / 3.0;
            }
            sum / area
        })
        .collect();
    assert!(
        means.iter().any(|m| m.abs() <= 1e-12 * u_max),
        "mean u_x per body {means:?}"
    );
    // symmetric answer: the bore moves out by the same amount at θ = 0 and π
    let at = |px: f64| {
        (0..mesh.n_nodes())
            .min_by(|&a, &b| {
                let d = |v: usize| (x[v][0] - px).hypot(x[v][1]);
                d(a).total_cmp(&d(b))
            })
            .unwrap()
    };
    let (a, b) = (at(1.0), at(-1.0));
    let asym = (u[2 * a] + u[2 * b]).abs() / u[2 * a].abs();
    eprintln!(
        "bore u_x at θ = 0: {:.6e}, at θ = π: {:.6e} (raw {:.6e}, {:.6e}); asymmetry {asym:.2e}",
        u[2 * a],
        u[2 * b],
        raw[2 * a],
        raw[2 * b]
    );
    assert!(u[2 * a] > 0.0 && asym < 1e-2, "asymmetry {asym}");
}
