//! The Zienkiewicz–Zhu error estimate of [`StaticSolver::stresses`] on the
//! Lamé thick cylinder, linear and quadratic triangles.
//!
//! Run: `cargo test -p tecon-elastic --test zz_indicator -- --nocapture`
//!
//! Reference: Lamé (thick cylinder a = 1, b = 2 under internal pressure
//! p = 100 MPa, plane strain); Zienkiewicz & Zhu (1987, 1992) for the
//! estimate: η = ‖σ* − σ_h‖ in the energy norm ‖s‖² = ∫ sᵀ D⁻¹ s dA, σ*
//! recovered per region (nodal averaging on 3-node triangles, SPR on
//! 6-node ones).
//!
//! ```text
//!   quarter ring, n rows × 4n segments (layered_annulus_of_order),
//!   symmetry on θ = 0 ("start") and θ = π/2 ("end"), p on r = a
//!
//!      θ = π/2 ┆╲__
//!              ┆   ╲__
//!        r = a ╲      ╲  r = b free
//!               ╲      │
//!                ╰─────┘ θ = 0
//! ```
//!
//! Goal: η falls as the true energy error does, O(h) on P1 and O(h²) on P2
//! (fitted slopes within 0.2), and the effectivity index η / ‖σ − σ_h‖ is
//! near 1 on the finest mesh (asserted within 0.1 of 1 for P2, 0.25 for
//! P1, whose boundary nodes average one-sided).
//!
//! Measured (n = 4, 8, 16, 32): P1 η slope 0.97 (true error 0.98),
//! effectivity 0.968, 0.988, 0.992, 0.991; P2 η slope 1.87 (true error
//! 1.98), effectivity 0.753, 0.832, 0.898, 0.941.

mod common;

use std::f64::consts::PI;

use nalgebra::{Matrix3, Vector3};
use tecon_elastic::analytical::LameCylinder;
use tecon_elastic::{Analysis, Loads, SolverOptions, StaticSolver};
use tecon_fem::quadrature::TriangleRule;
use tecon_mesh::{Mesh, RingLayer, layered_annulus_of_order};

use common::STEEL;
const A: f64 = 1.0;
const B: f64 = 2.0;
const P: f64 = 100e6;

fn exact() -> LameCylinder {
    LameCylinder {
        a: A,
        b: B,
        p: P,
        e: STEEL.youngs_modulus,
        nu: STEEL.poisson_ratio,
    }
}

/// Exact in-plane (σ_xx, σ_yy, σ_xy) at x.
fn sigma(x: [f64; 2]) -> Vector3<f64> {
    let l = exact();
    let r = x[0].hypot(x[1]);
    let (c, s) = (x[0] / r, x[1] / r);
    let (srr, stt) = (l.sigma_rr(r), l.sigma_tt(r));
    Vector3::new(
        srr * c * c + stt * s * s,
        srr * s * s + stt * c * c,
        (srr - stt) * s * c,
    )
}

fn mesh(n: usize, order: usize) -> Mesh {
    let layer = RingLayer {
        name: "ring".into(),
        r_in: A,
        r_out: B,
        rows: n,
    };
    layered_annulus_of_order(&[layer], 0.0, PI / 2.0, 4 * n, order).unwrap()
}

/// (h, η, true energy error ‖σ − σ_h‖, relative η) of one solve.
fn solve(n: usize, order: usize) -> (f64, f64, f64, f64) {
    let mesh = mesh(n, order);
    let model = common::lame_sector(&mesh, P);
    let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
    solver.advance(&Loads::mechanical()).unwrap();
    let field = solver.stresses();
    let c: Matrix3<f64> = Analysis::PlaneStrain.d(&STEEL).try_inverse().unwrap();
    let mut err2 = 0.0;
    match solver.quadratic_stresses() {
        // P2: the stresses at the solver's integration points (degree 4)
        Some(q) => {
            for p in q.points.iter().flatten() {
                let d = Vector3::new(p.stress[0], p.stress[1], p.stress[2]) - sigma(p.x);
                err2 += p.weight * (d.transpose() * c * d)[0];
            }
        }
        // P1: constant element stress against the exact one, degree 5
        None => {
            let x = mesh.nodes();
            for (e, t) in mesh.triangles().iter().enumerate() {
                let (a, b, cc) = (x[t[0]], x[t[1]], x[t[2]]);
                let jac = ((b[0] - a[0]) * (cc[1] - a[1]) - (b[1] - a[1]) * (cc[0] - a[0])).abs();
                let s = field.element[e];
                for q in TriangleRule::Degree5.points() {
                    let p = [
                        a[0] + q.xi[0] * (b[0] - a[0]) + q.xi[1] * (cc[0] - a[0]),
                        a[1] + q.xi[0] * (b[1] - a[1]) + q.xi[1] * (cc[1] - a[1]),
                    ];
                    let d = Vector3::new(s[0], s[1], s[2]) - sigma(p);
                    err2 += q.weight * jac * (d.transpose() * c * d)[0];
                }
            }
        }
    }
    assert_eq!(field.error.element.len(), mesh.n_triangles());
    assert_eq!(
        field.recovered.len(),
        mesh.n_triangles() * if order == 2 { 6 } else { 3 }
    );
    (
        1.0 / n as f64,
        field.error.eta,
        err2.sqrt(),
        field.error.relative(),
    )
}

fn study(order: usize, levels: &[usize]) -> (f64, f64, Vec<f64>) {
    let (mut hs, mut etas, mut errs, mut eff) = (vec![], vec![], vec![], vec![]);
    eprintln!("P{order}:  n  elements          η      ‖σ − σ_h‖   η/error  η relative");
    for &n in levels {
        let (h, eta, err, rel) = solve(n, order);
        eprintln!(
            "   {n:4} {:9} {eta:12.5e} {err:12.5e} {:9.4} {:10.3e}",
            2 * n * 4 * n,
            eta / err,
            rel
        );
        hs.push(h);
        etas.push(eta);
        errs.push(err);
        eff.push(eta / err);
    }
    let (k_eta, k_err) = (common::slope(&hs, &etas), common::slope(&hs, &errs));
    eprintln!("P{order}: fitted slopes η {k_eta:.3}, true error {k_err:.3}; effectivity {eff:?}");
    (k_eta, k_err, eff)
}

#[test]
fn p1_zz_estimate_falls_as_h_with_effectivity_near_1() {
    let (k_eta, k_err, eff) = study(1, &[4, 8, 16, 32]);
    assert!((k_err - 1.0).abs() < 0.2, "P1 true error order {k_err}");
    assert!((k_eta - 1.0).abs() < 0.2, "P1 η order {k_eta}");
    let last = eff[eff.len() - 1];
    assert!((last - 1.0).abs() < 0.25, "P1 effectivity {eff:?}");
}

#[test]
fn p2_zz_estimate_falls_as_h2_with_effectivity_near_1() {
    let (k_eta, k_err, eff) = study(2, &[4, 8, 16, 32]);
    assert!((k_err - 2.0).abs() < 0.2, "P2 true error order {k_err}");
    assert!((k_eta - 2.0).abs() < 0.2, "P2 η order {k_eta}");
    // SPR is asymptotically exact here: the effectivity approaches 1 at
    // every refinement
    for w in eff.windows(2) {
        assert!((1.0 - w[1]).abs() < (1.0 - w[0]).abs(), "{eff:?}");
    }
    let last = eff[eff.len() - 1];
    assert!((last - 1.0).abs() < 0.1, "P2 effectivity {eff:?}");
}
