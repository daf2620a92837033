//! Quadratic (P2) elements through `StaticSolver`: curved 6-node triangles,
//! consistent pressure on 3-node edges, symmetry on mid nodes, nodal
//! temperature changes, and the 6-node (three-pair) interface element.
//!
//! Run: `cargo test -p tecon-elastic --test p2_solver -- --nocapture`
//!
//! References: Lamé (thick cylinder under internal pressure); the
//! two-cylinder shrink fit (`analytical::ShrinkFit`); Mohr–Coulomb sliding
//! of a block.
//!
//! ```text
//!   quarter rings (layered_annulus_of_order, order 2: every mid node on
//!   its circle), symmetry on θ = 0 ("start") and θ = π/2 ("end")
//!
//!      θ = π/2 ┆╲__            one ring: Lamé, p on r = a
//!              ┆   ╲__         two rings with an interface at r = c:
//!        r = a ╲      ╲          shrink fit (ΔT of the inner ring),
//!               ╲      │         bonded (stiff linear joint)
//!                ╰─────┘ θ = 0
//! ```

mod common;

use std::f64::consts::PI;

use nalgebra::Vector3;
use tecon_contact::{ContactStatus, GhaboussiNormal, LinearJoint, PaperJoint};
use tecon_elastic::analytical::{Cylinders, LameCylinder, ShrinkFit};
use tecon_elastic::{
    Analysis, Component, ElasticError, ElasticModel, Joint, Loads, Material, SolverOptions,
    StaticSolver, polar,
};
use tecon_fem::quadrature::TriangleRule;
use tecon_fem::triangle6::Triangle6;
use tecon_mesh::{Mesh, RingLayer, layered_annulus_of_order};

use common::STEEL;

fn rings(layers: &[(&str, f64, f64)], rows: usize, segments: usize, order: usize) -> Mesh {
    let layers: Vec<RingLayer> = layers
        .iter()
        .map(|&(name, r_in, r_out)| RingLayer {
            name: name.into(),
            r_in,
            r_out,
            rows,
        })
        .collect();
    layered_annulus_of_order(&layers, 0.0, PI / 2.0, segments, order).unwrap()
}

/// L2 error of u and energy-norm error against a radial field `u_r(r)`
/// (with `du_r/dr`), integrated on the curved elements with the degree-5
/// rule; and the L2 norm of the exact u.
fn radial_errors(
    mesh: &Mesh,
    u: &[f64],
    d: &nalgebra::Matrix3<f64>,
    ur: &dyn Fn(f64) -> f64,
    dur: &dyn Fn(f64) -> f64,
) -> (f64, f64, f64) {
    let x = mesh.nodes();
    let (mut l2, mut en, mut norm) = (0.0, 0.0, 0.0);
    for t in mesh.triangles6().unwrap() {
        let g = Triangle6::new(t.map(|v| x[v])).unwrap();
        let ue = nalgebra::SVector::<f64, 12>::from_fn(|k, _| u[2 * t[k / 2] + k % 2]);
        for q in g.points(TriangleRule::Degree5) {
            let p = g.position(q.xi);
            let r = p[0].hypot(p[1]);
            let (c, s) = (p[0] / r, p[1] / r);
            let uh = [
                (0..6).map(|a| q.shape[a] * ue[2 * a]).sum::<f64>(),
                (0..6).map(|a| q.shape[a] * ue[2 * a + 1]).sum::<f64>(),
            ];
            let ex = [ur(r) * c, ur(r) * s];
            l2 += q.weight * ((uh[0] - ex[0]).powi(2) + (uh[1] - ex[1]).powi(2));
            norm += q.weight * (ex[0].powi(2) + ex[1].powi(2));
            let (err, ett) = (dur(r), ur(r) / r);
            let eps = Vector3::new(
                err * c * c + ett * s * s,
                err * s * s + ett * c * c,
                2.0 * (err - ett) * s * c,
            );
            let de = q.strain_matrix() * ue - eps;
            en += q.weight * (de.transpose() * d * de)[0];
        }
    }
    (l2.sqrt(), en.sqrt(), norm.sqrt())
}

/// Lamé cylinder a = 1, b = 2, p = 100 MPa, plane strain, on curved P2
/// meshes of 4, 8, 16 rows (4 × rows segments) through `StaticSolver`
/// (consistent pressure on the curved bore edges, symmetry on the mid
/// nodes). Goal: fitted slopes ≈ 3 (L2 of u) and ≈ 2 (energy), within 0.2.
#[test]
fn p2_lame_cylinder_through_the_solver_converges_at_orders_3_and_2() {
    let (a, b, p) = (1.0, 2.0, 100e6);
    let exact = LameCylinder {
        a,
        b,
        p,
        e: STEEL.youngs_modulus,
        nu: STEEL.poisson_ratio,
    };
    let d = Analysis::PlaneStrain.d(&STEEL);
    let (mut hs, mut l2s, mut ens) = (vec![], vec![], vec![]);
    for n in [4, 8, 16] {
        let mesh = rings(&[("ring", a, b)], n, 4 * n, 2);
        let model = common::lame_sector(&mesh, p);
        let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
        solver.advance(&Loads::mechanical()).unwrap();
        let hdur = |r: f64| {
            let h = 1e-5 * r;
            (exact.u_r(r + h) - exact.u_r(r - h)) / (2.0 * h)
        };
        let (l2, en, norm) =
            radial_errors(&mesh, solver.displacement(), &d, &|r| exact.u_r(r), &hdur);
        hs.push(1.0 / n as f64);
        l2s.push(l2 / norm);
        ens.push(en);
        // the quadratic stress output is there and the indicator is finite
        let q = solver.quadratic_stresses().unwrap();
        assert_eq!(q.points.len(), mesh.n_triangles());
        assert!(q.indicator.iter().all(|v| v.is_finite()));
    }
    let (k2, ke) = (common::slope(&hs, &l2s), common::slope(&hs, &ens));
    eprintln!("P2 Lamé via StaticSolver: L2 {l2s:?} slope {k2:.3}; energy {ens:?} slope {ke:.3}");
    assert!((k2 - 3.0).abs() < 0.2, "L2 order {k2}");
    assert!((ke - 2.0).abs() < 0.2, "energy order {ke}");
    assert!(l2s[2] < 1e-5, "finest relative L2 error {}", l2s[2]);
}

/// Nodal ΔT (six per element) equal to `dt` in region `region`, 0 elsewhere.
fn region_delta_t(mesh: &Mesh, region: &str, dt: f64) -> Vec<f64> {
    let r = mesh.region_index(region).unwrap();
    mesh.element_regions()
        .iter()
        .flat_map(|&e| [if e == r { dt } else { 0.0 }; 6])
        .collect()
}

/// Shrink fit on P2: inner ring 1 ≤ r ≤ 1.1 heated by 50 K inside the
/// outer ring 1.1 ≤ r ≤ 1.2, joined by 6-node interface elements with the
/// paper's joint (augmented Lagrangian, so the answer does not depend on
/// the penalty); frictionless (φ = 0) and with friction (φ = 0.3).
/// Returns the largest relative contact-pressure error over the points,
/// the largest hoop-stress error at the integration points (relative to
/// the outer ring's hoop stress at r = c), and the iterations.
fn p2_shrink_fit(rows: usize, segments: usize, phi: f64) -> (f64, f64, usize) {
    let mesh = rings(
        &[("inner", 1.0, 1.1), ("outer", 1.1, 1.2)],
        rows,
        segments,
        2,
    );
    let fit = ShrinkFit {
        a: 1.0,
        c: 1.1,
        b: 1.2,
        delta: (1.0 + STEEL.poisson_ratio) * STEEL.expansion * 50.0 * 1.1,
        e: STEEL.youngs_modulus,
        nu: STEEL.poisson_ratio,
        state: Cylinders::PlaneStrain,
    };
    let law = PaperJoint::with_default_penalty(STEEL.youngs_modulus, 0.1 / rows as f64, 0.0, phi)
        .unwrap();
    let model = common::steel_sector(&mesh)
        .interface("inner_outer", Joint::Frictional(law))
        .unwrap();
    let mut solver = StaticSolver::new(
        &model,
        SolverOptions {
            augmented_lagrangian: Some(1e-8),
            ..Default::default()
        },
    )
    .unwrap();
    let reports = solver
        .advance(&Loads {
            delta_t: region_delta_t(&mesh, "inner", 50.0),
            ..Loads::zero()
        })
        .unwrap();
    let its = reports.iter().map(|r| r.iterations).sum();
    let pts = solver.interface_results();
    assert_eq!(pts.len(), 3 * segments, "three points per element");
    let p = fit.pressure();
    let mut p_err: f64 = 0.0;
    for pt in &pts {
        assert_ne!(pt.status, ContactStatus::Open);
        let r = pt.position[0].hypot(pt.position[1]);
        assert!((r - 1.1).abs() < 1e-12, "points lie on the interface arc");
        p_err = p_err.max((-pt.traction[1] / p - 1.0).abs());
    }
    let inner = mesh.region_index("inner").unwrap();
    let q = solver.quadratic_stresses().unwrap();
    let scale = fit.sigma_tt(1.1, false).abs();
    let mut s_err: f64 = 0.0;
    for (e, points) in q.points.iter().enumerate() {
        for sp in points {
            let r = sp.x[0].hypot(sp.x[1]);
            let tt = polar(sp.stress, sp.x, [0.0; 2])[1];
            let exact = fit.sigma_tt(r, mesh.element_regions()[e] == inner);
            s_err = s_err.max((tt - exact).abs() / scale);
        }
    }
    (p_err, s_err, its)
}

/// Goal: the contact pressure at every point and the hoop stresses at
/// every integration point converge to the two-cylinder solution
/// (errors fall with refinement and are small on the finer mesh), with
/// and without friction.
#[test]
fn p2_shrink_fit_converges_to_the_two_cylinder_solution() {
    for phi in [0.0, 0.3] {
        let coarse = p2_shrink_fit(1, 8, phi);
        let fine = p2_shrink_fit(2, 16, phi);
        eprintln!(
            "P2 shrink fit φ = {phi}: pressure error {:.3e} → {:.3e}, hoop error {:.3e} → {:.3e}, iterations {} / {}",
            coarse.0, fine.0, coarse.1, fine.1, coarse.2, fine.2
        );
        assert!(fine.0 < coarse.0 && fine.1 < coarse.1, "errors fall");
        assert!(fine.0 < 1e-3, "pointwise contact pressure {}", fine.0);
        assert!(fine.1 < 5e-3, "hoop stresses {}", fine.1);
        assert!(fine.2 <= 40, "iterations {}", fine.2);
    }
}

/// Bonded: the Lamé cylinder 1 ≤ r ≤ 2 cut at r = 1.5 into two rings
/// joined by a stiff linear joint (k = 1e6 E per m: the joint's
/// compliance adds |σ_rr|/k ≈ 1e-10 m, about 1e-6 of u) must give the
/// one-piece answer: the displacement error falls at order 3 like the
/// one-piece cylinder's (measured 2.36e-4, 2.64e-5 of ‖u‖ on 2 + 2 and
/// 4 + 4 rows), and the joint's normal traction at every point tends to
/// σ_rr(1.5) (largest deviation measured 3.5 %, then 0.83 %).
#[test]
fn p2_bonded_rings_match_the_single_cylinder() {
    let (a, b, p) = (1.0, 2.0, 100e6);
    let exact = LameCylinder {
        a,
        b,
        p,
        e: STEEL.youngs_modulus,
        nu: STEEL.poisson_ratio,
    };
    let d = Analysis::PlaneStrain.d(&STEEL);
    let k = 1e6 * STEEL.youngs_modulus;
    let (mut errs, mut t_errs) = (Vec::new(), Vec::new());
    for n in [2, 4] {
        let mesh = rings(&[("core", a, 1.5), ("layer", 1.5, b)], n, 8 * n, 2);
        let model = common::lame_sector(&mesh, p)
            .interface("core_layer", Joint::Linear(LinearJoint::new(k, k).unwrap()))
            .unwrap();
        let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
        solver.advance(&Loads::mechanical()).unwrap();
        let dur = |r: f64| {
            let h = 1e-5 * r;
            (exact.u_r(r + h) - exact.u_r(r - h)) / (2.0 * h)
        };
        let (l2, _, norm) =
            radial_errors(&mesh, solver.displacement(), &d, &|r| exact.u_r(r), &dur);
        // the joint carries σ_rr(1.5) as its normal traction
        let s_rr = exact.sigma_rr(1.5);
        let t_err = solver
            .interface_results()
            .iter()
            .map(|pt| (pt.traction[1] / s_rr - 1.0).abs())
            .fold(0.0, f64::max);
        errs.push(l2 / norm);
        t_errs.push(t_err);
    }
    eprintln!("P2 bonded rings: relative L2 error of u {errs:?}; joint traction {t_errs:?}");
    // the one-piece cylinder on the same total rows has the same error
    // (2.36e-4 and 2.64e-5 on 4 and 8 rows): the stiff joint adds nothing,
    // and the error falls at order ≈ 3
    let order = (errs[0] / errs[1]).log2();
    assert!(order > 2.8 && errs[1] < 3e-5, "{errs:?}, order {order}");
    assert!(t_errs[1] < t_errs[0] && t_errs[1] < 1e-2, "{t_errs:?}");
}

/// Two stacked blocks on an order-2 (straight-sided) mesh.
fn p2_blocks(h: f64) -> Mesh {
    common::stacked_blocks(h).to_quadratic(&[]).unwrap()
}

/// Patch test: a uniform pressure p on the lid of two stacked blocks
/// (ν = 0, base fixed) joined by a linear joint: the stress is −p
/// everywhere and every interface point carries exactly σ = −p, τ = 0,
/// with the jump −p / k_n; Gauss (3-point) integration as well as nodal.
#[test]
fn p2_interface_patch_test() {
    let mesh = p2_blocks(1.0);
    let m = Material {
        poisson_ratio: 0.0,
        ..STEEL
    };
    let (p, k) = (1e6, 1e12);
    for quadrature in [
        tecon_contact::InterfaceQuadrature::Nodal,
        tecon_contact::InterfaceQuadrature::Gauss2,
    ] {
        let model = ElasticModel::new(&mesh, Analysis::PlaneStrain)
            .material_everywhere(m)
            .unwrap()
            .fix("base", Component::X, 0.0)
            .unwrap()
            .fix("base", Component::Y, 0.0)
            .unwrap()
            .fix("lid", Component::X, 0.0)
            .unwrap()
            .pressure("lid", p)
            .unwrap()
            .interface_quadrature(quadrature)
            .interface("joint", Joint::Linear(LinearJoint::new(k, k).unwrap()))
            .unwrap();
        let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
        solver.advance(&Loads::mechanical()).unwrap();
        let pts = solver.interface_results();
        assert_eq!(pts.len(), 12);
        for pt in &pts {
            assert!(
                (pt.traction[1] + p).abs() < 1e-8 * p,
                "σ {}",
                pt.traction[1]
            );
            assert!(pt.traction[0].abs() < 1e-8 * p, "τ {}", pt.traction[0]);
            assert!((pt.jump[1] + p / k).abs() < 1e-8 * p / k);
        }
        for sp in solver.quadratic_stresses().unwrap().points.iter().flatten() {
            assert!((sp.stress[1] + p).abs() < 1e-8 * p, "σ_yy {}", sp.stress[1]);
            assert!(sp.stress[0].abs() < 1e-8 * p && sp.stress[2].abs() < 1e-8 * p);
        }
    }
}

/// A P2 frictional contact case: the lid (thin block) pressed by 1 MPa on
/// a Mohr–Coulomb joint (c = 0.1 MPa, φ = 30°), then pushed sideways far
/// enough to slide. Goal: the increments converge; while sliding every
/// point carries τ = c + σ_c tan φ of its own σ; the slip is positive.
#[test]
fn p2_block_slides_on_a_mohr_coulomb_joint() {
    let mesh = p2_blocks(0.1);
    let (c, phi, p) = (1e5, 30f64.to_radians(), 1e6);
    let k = 1e13;
    let law = PaperJoint::new(GhaboussiNormal::penalty(k).unwrap(), k, c, phi).unwrap();
    let m = Material {
        poisson_ratio: 0.0,
        ..STEEL
    };
    let model = ElasticModel::new(&mesh, Analysis::PlaneStrain)
        .material_everywhere(m)
        .unwrap()
        .fix("base", Component::X, 0.0)
        .unwrap()
        .fix("base", Component::Y, 0.0)
        .unwrap()
        .fix("lid", Component::X, 1e-4)
        .unwrap()
        .pressure("lid", p)
        .unwrap()
        .interface("joint", Joint::Frictional(law))
        .unwrap();
    let mut solver = StaticSolver::new(
        &model,
        SolverOptions {
            increments: 4,
            friction_tolerance: 1e-12,
            ..Default::default()
        },
    )
    .unwrap();
    let limit = |sigma: f64| c - sigma * phi.tan();
    solver
        .advance(&Loads {
            pressure: 1.0,
            ..Loads::zero()
        })
        .unwrap();
    for pt in solver.interface_results() {
        assert!(
            (pt.traction[1] + p).abs() < 1e-6 * p,
            "σ = −p: {}",
            pt.traction[1]
        );
    }
    let reports = solver
        .advance(&Loads {
            pressure: 1.0,
            displacement: 1.0,
            ..Loads::zero()
        })
        .unwrap();
    let its: usize = reports.iter().map(|r| r.iterations).sum();
    eprintln!(
        "P2 sliding block: {its} Newton iterations over {} increments",
        reports.len()
    );
    let pts = solver.interface_results();
    assert_eq!(pts.len(), 12);
    for pt in &pts {
        assert_eq!(pt.status, ContactStatus::Slip);
        let s = limit(pt.traction[1]);
        assert!(
            (pt.traction[0] - s).abs() < 1e-8 * s,
            "τ {} vs {s}",
            pt.traction[0]
        );
        assert!(pt.slip > 0.0);
    }
}

/// The thermal-load contract: an order-2 mesh takes six ΔT per element;
/// one per element is refused with a message naming both lengths, and a
/// non-finite value names its element and local node.
#[test]
fn p2_temperature_change_of_the_wrong_length_is_a_clear_error() {
    let mesh = rings(&[("ring", 1.0, 2.0)], 1, 2, 2);
    let model = common::steel_sector(&mesh);
    let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
    let n = mesh.n_triangles();
    let e = solver
        .advance(&Loads {
            delta_t: vec![1.0; n],
            ..Loads::zero()
        })
        .unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, ElasticError::Input { .. }));
    assert!(
        msg.contains(&format!("6 × {n} = {}", 6 * n)) && msg.contains("six per element"),
        "{msg}"
    );
    let mut dt = vec![1.0; 6 * n];
    dt[6 + 4] = f64::NAN;
    let msg = solver
        .advance(&Loads {
            delta_t: dt,
            ..Loads::zero()
        })
        .unwrap_err()
        .to_string();
    assert!(msg.contains("element 1 (its local node 4)"), "{msg}");
}

/// A free ring heated uniformly (ΔT interpolated from the nodes) expands
/// freely: plane stress, u_r = α ΔT r, no stress — through the solver with
/// the minimal constraints it adds itself; the gauge (mean u_x of the
/// body zero) is integrated on the curved elements.
#[test]
fn p2_free_thermal_expansion_is_stress_free() {
    let mesh = rings(&[("ring", 1.0, 2.0)], 2, 8, 2);
    let model = ElasticModel::new(&mesh, Analysis::PlaneStress)
        .material_everywhere(STEEL)
        .unwrap()
        .symmetry("start")
        .unwrap()
        .symmetry("end")
        .unwrap();
    let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
    let dt = 100.0;
    solver
        .advance(&Loads {
            delta_t: vec![dt; 6 * mesh.n_triangles()],
            ..Loads::zero()
        })
        .unwrap();
    let x = mesh.nodes();
    let u = solver.displacement();
    for (i, p) in x.iter().enumerate() {
        let want = [STEEL.expansion * dt * p[0], STEEL.expansion * dt * p[1]];
        assert!((u[2 * i] - want[0]).abs() < 1e-12 && (u[2 * i + 1] - want[1]).abs() < 1e-12);
    }
    let smax = solver
        .quadratic_stresses()
        .unwrap()
        .points
        .iter()
        .flatten()
        .flat_map(|p| p.stress)
        .fold(0.0f64, |a, b| a.max(b.abs()));
    assert!(smax < 1e-3, "stress {smax} Pa");
}
