//! Verification of tecon-elastic against closed-form solutions.
//!
//! References: Lamé (thick cylinder under pressure); Timoshenko & Goodier
//! §150 (cylinder with a logarithmic temperature profile); the two-cylinder
//! shrink fit (Lamé with an interference); Mohr–Coulomb sliding of a block.

mod common;

use std::f64::consts::PI;

use tecon_contact::{FrictionBound, GhaboussiNormal, LinearJoint, PaperJoint};
use tecon_elastic::analytical::{Cylinders, LameCylinder, ShrinkFit, ThermalCylinder};
use tecon_elastic::{
    Analysis, Component, ElasticError, ElasticModel, InterfacePointResult, Joint, Loads, Material,
    SolverOptions, StaticSolver, polar,
};
use tecon_mesh::{Mesh, RingLayer, layered_annulus};

use common::STEEL;

fn quarter_ring(a: f64, b: f64, rows: usize, segments: usize, t0: f64, t1: f64) -> Mesh {
    layered_annulus(
        &[RingLayer {
            name: "ring".into(),
            r_in: a,
            r_out: b,
            rows,
        }],
        t0,
        t1,
        segments,
    )
    .unwrap()
}

/// L2 errors of displacement and of (σ_rr, σ_θθ) over the mesh, by the
/// edge-midpoint rule (exact for quadratics).
fn l2_errors(
    mesh: &Mesh,
    u: &[f64],
    s: &[[f64; 4]],
    ur: &dyn Fn(f64) -> f64,
    srr: &dyn Fn(f64) -> f64,
    stt: &dyn Fn(f64) -> f64,
) -> (f64, f64) {
    let x = mesh.nodes();
    let (mut eu, mut es) = (0.0, 0.0);
    for (e, t) in mesh.triangles().iter().enumerate() {
        let area = tecon_mesh::signed_area(x[t[0]], x[t[1]], x[t[2]]);
        for k in 0..3 {
            let (i, j) = (t[k], t[(k + 1) % 3]);
            let p = [(x[i][0] + x[j][0]) / 2.0, (x[i][1] + x[j][1]) / 2.0];
            let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
            let uh = [
                (u[2 * i] + u[2 * j]) / 2.0,
                (u[2 * i + 1] + u[2 * j + 1]) / 2.0,
            ];
            let ue = [ur(r) * p[0] / r, ur(r) * p[1] / r];
            eu += area / 3.0 * ((uh[0] - ue[0]).powi(2) + (uh[1] - ue[1]).powi(2));
            let sp = polar(s[e], p, [0.0, 0.0]);
            es += area / 3.0 * ((sp[0] - srr(r)).powi(2) + (sp[1] - stt(r)).powi(2));
        }
    }
    (eu.sqrt(), es.sqrt())
}

/// Lamé cylinder, plane strain, internal pressure 100 MPa.
///
/// ```text
///   quarter ring a = 1 ≤ r ≤ b = 2, 0 ≤ θ ≤ π/2
///   θ = 0 edge: u_y = 0; θ = π/2 edge: u_x = 0; p on r = a
/// ```
/// Goal: L2 displacement error of order 2, L2 stress error of order 1.
#[test]
fn lame_cylinder_converges_at_orders_two_and_one() {
    let (a, b, p) = (1.0, 2.0, 100e6);
    let exact = LameCylinder {
        a,
        b,
        p,
        e: STEEL.youngs_modulus,
        nu: STEEL.poisson_ratio,
    };
    let (mut hs, mut eus, mut ess) = (vec![], vec![], vec![]);
    for n in [4, 8, 16, 32] {
        let mesh = quarter_ring(a, b, n, 2 * n, 0.0, PI / 2.0);
        let model = common::lame_sector(&mesh, p);
        let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
        solver.advance(&Loads::mechanical()).unwrap();
        let s = solver.stresses();
        let (eu, es) = l2_errors(
            &mesh,
            solver.displacement(),
            &s.element,
            &|r| exact.u_r(r),
            &|r| exact.sigma_rr(r),
            &|r| exact.sigma_tt(r),
        );
        hs.push(1.0 / n as f64);
        eus.push(eu / exact.u_r(a));
        ess.push(es / p);
    }
    let (ku, ks) = (common::slope(&hs, &eus), common::slope(&hs, &ess));
    eprintln!("Lamé: u errors {eus:.3?} slope {ku:.3}; σ errors {ess:.3?} slope {ks:.3}");
    assert!((ku - 2.0).abs() < 0.15, "displacement order {ku}");
    assert!((ks - 1.0).abs() < 0.15, "stress order {ks}");
    assert!(eus[3] < 2e-3);
}

/// The same cylinder on a sector whose symmetry edges are inclined
/// (π/6 ≤ θ ≤ 2π/3): the mesh is the quarter-ring mesh rotated by π/6, so
/// with local nodal frames the radial displacements must equal the
/// axis-aligned ones to round-off and the tangential ones vanish.
#[test]
fn symmetry_on_inclined_edges() {
    inclined_symmetry_matches_aligned(1);
}

/// The same after a second solve that starts from the converged state (a
/// later increment, or an augmented-Lagrangian pass): the constrained
/// components must be set in the nodal frames. Writing the prescribed 0 into
/// the global x component instead moved the nodes of the inclined edge off
/// it (the Gmsh 8° sector's contact multipliers then never settled).
#[test]
fn symmetry_on_inclined_edges_holds_when_a_solve_restarts_from_a_converged_state() {
    inclined_symmetry_matches_aligned(3);
}

fn inclined_symmetry_matches_aligned(solves: usize) {
    let (a, b, p) = (1.0, 2.0, 100e6);
    let solve = |t0: f64| {
        let mesh = quarter_ring(a, b, 8, 16, t0, t0 + PI / 2.0);
        let model = common::lame_sector(&mesh, p);
        let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
        for _ in 0..solves {
            solver.advance(&Loads::mechanical()).unwrap();
        }
        let (u, x) = (solver.displacement(), mesh.nodes());
        (0..mesh.n_nodes())
            .map(|i| {
                let r = (x[i][0].powi(2) + x[i][1].powi(2)).sqrt();
                let (ux, uy) = (u[2 * i], u[2 * i + 1]);
                [
                    (ux * x[i][0] + uy * x[i][1]) / r,
                    (-ux * x[i][1] + uy * x[i][0]) / r,
                ]
            })
            .collect::<Vec<_>>()
    };
    let aligned = solve(0.0);
    let inclined = solve(PI / 6.0);
    let scale = LameCylinder {
        a,
        b,
        p,
        e: STEEL.youngs_modulus,
        nu: STEEL.poisson_ratio,
    }
    .u_r(a);
    for (i, (q, r)) in aligned.iter().zip(&inclined).enumerate() {
        assert!(
            (q[0] - r[0]).abs() < 1e-9 * scale,
            "node {i}: radial {} vs {}",
            r[0],
            q[0]
        );
        assert!(
            (q[1] - r[1]).abs() < 1e-9 * scale,
            "node {i}: tangential {} vs {}",
            r[1],
            q[1]
        );
    }
}

fn thermal_cylinder_errors(analysis: Analysis, n: usize) -> (f64, f64, f64, f64) {
    let (a, b) = (1.0, 1.5);
    let exact = ThermalCylinder {
        a,
        b,
        t_a: 100.0,
        t_b: 0.0,
        e: STEEL.youngs_modulus,
        nu: STEEL.poisson_ratio,
        alpha: STEEL.expansion,
    };
    let mesh = quarter_ring(a, b, n, 4 * n, 0.0, PI / 2.0);
    let model = ElasticModel::new(&mesh, analysis)
        .material_everywhere(STEEL)
        .unwrap()
        .symmetry("start")
        .unwrap()
        .symmetry("end")
        .unwrap();
    let x = mesh.nodes();
    let t_node: Vec<f64> = x
        .iter()
        .map(|p| exact.temperature((p[0] * p[0] + p[1] * p[1]).sqrt()))
        .collect();
    let delta_t: Vec<f64> = mesh
        .triangles()
        .iter()
        .map(|t| t.iter().map(|&v| t_node[v]).sum::<f64>() / 3.0)
        .collect();
    let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
    solver
        .advance(&Loads {
            delta_t,
            ..Loads::zero()
        })
        .unwrap();
    let s = solver.stresses();
    let scale = STEEL.youngs_modulus * STEEL.expansion * 100.0;
    // relative L2 errors by the edge-midpoint rule
    let (mut err_rr, mut err_tt, mut err_zz, mut area_sum) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (e, t) in mesh.triangles().iter().enumerate() {
        let area = tecon_mesh::signed_area(x[t[0]], x[t[1]], x[t[2]]);
        area_sum += area;
        for k in 0..3 {
            let (i, j) = (t[k], t[(k + 1) % 3]);
            let c = [(x[i][0] + x[j][0]) / 2.0, (x[i][1] + x[j][1]) / 2.0];
            let r = (c[0] * c[0] + c[1] * c[1]).sqrt();
            let sp = polar(s.element[e], c, [0.0, 0.0]);
            let zz = match analysis {
                Analysis::GeneralisedPlaneStrain => exact.sigma_zz_free_ends(r),
                _ => exact.sigma_zz_plane_strain(r),
            };
            err_rr += area / 3.0 * (sp[0] - exact.sigma_rr(r)).powi(2);
            err_tt += area / 3.0 * (sp[1] - exact.sigma_tt(r)).powi(2);
            err_zz += area / 3.0 * (s.element[e][3] - zz).powi(2);
        }
    }
    let n = |v: f64| (v / area_sum).sqrt() / scale;
    let (err_rr, err_tt, err_zz) = (n(err_rr), n(err_tt), n(err_zz));
    (err_rr, err_tt, err_zz, solver.eps_zz())
}

/// Long cylinder 1 ≤ r ≤ 1.5 with T = 100 K ln(1.5/r)/ln 1.5, plane strain
/// and generalised plane strain (free ends).
///
/// ```text
///   quarter ring, symmetry on both straight edges, no other support
/// ```
/// Goal: RMS errors of σ_rr, σ_θθ, σ_zz within 1.5 % of E α ΔT_max on a
/// 32-row mesh, falling at order 1 (a wrong plane-strain thermal
/// strain (α instead of (1 + ν) α) is off by 30 %).
#[test]
fn thermal_cylinder_plane_strain_and_free_ends() {
    for analysis in [Analysis::PlaneStrain, Analysis::GeneralisedPlaneStrain] {
        let coarse = thermal_cylinder_errors(analysis, 16);
        let fine = thermal_cylinder_errors(analysis, 32);
        eprintln!("{analysis:?}: coarse {coarse:.3?}, fine {fine:.3?}");
        for (c, f) in [(coarse.0, fine.0), (coarse.1, fine.1), (coarse.2, fine.2)] {
            // piecewise-constant stresses: first order; a wrong plane-strain
            // thermal strain would stall near 30 % instead
            assert!(f < 0.015, "{analysis:?}: error {f}");
            let order = (c / f).log2();
            assert!(
                (order - 1.0).abs() < 0.15,
                "{analysis:?}: order {order} ({c} → {f})"
            );
        }
        if analysis == Analysis::GeneralisedPlaneStrain {
            // ε_zz = α · mean temperature (area-weighted) for free ends
            let (a, b) = (1.0f64, 1.5f64);
            let k = -100.0 / (b / a).ln();
            let mean = (100.0 * (b * b - a * a) / 2.0
                + k * (b * b / 2.0 * (b / a).ln() - (b * b - a * a) / 4.0))
                * 2.0
                / (b * b - a * a);
            let eps = fine.3;
            assert!(
                (eps - STEEL.expansion * mean).abs() < 5e-3 * STEEL.expansion * mean,
                "ε_zz {eps} vs {}",
                STEEL.expansion * mean
            );
        }
    }
}

fn two_rings(rows: usize, segments: usize) -> Mesh {
    layered_annulus(
        &[
            RingLayer {
                name: "inner".into(),
                r_in: 1.0,
                r_out: 1.1,
                rows,
            },
            RingLayer {
                name: "outer".into(),
                r_in: 1.1,
                r_out: 1.2,
                rows,
            },
        ],
        0.0,
        PI / 2.0,
        segments,
    )
    .unwrap()
}

fn shrink_fit_solve(
    mesh: &Mesh,
    al: Option<f64>,
    k_scale: f64,
) -> (f64, [f64; 2], f64, Vec<[f64; 4]>) {
    let h = 0.1 / 8.0;
    let law =
        PaperJoint::with_default_penalty(STEEL.youngs_modulus * k_scale, h, 0.0, 0.3).unwrap();
    let model = common::steel_sector(mesh)
        .interface("inner_outer", Joint::Frictional(law))
        .unwrap();
    let opts = SolverOptions {
        augmented_lagrangian: al,
        ..Default::default()
    };
    let mut solver = StaticSolver::new(&model, opts).unwrap();
    let inner = mesh.region_index("inner").unwrap();
    let delta_t: Vec<f64> = mesh
        .element_regions()
        .iter()
        .map(|&r| if r == inner { 50.0 } else { 0.0 })
        .collect();
    let reports = solver
        .advance(&Loads {
            delta_t,
            ..Loads::zero()
        })
        .unwrap();
    let its = reports.iter().map(|r| r.iterations).max().unwrap_or(0) as f64;
    let pts = solver.interface_results();
    let p_mean = -pts.iter().map(|p| p.traction[1]).sum::<f64>() / pts.len() as f64;
    // largest pointwise deviation from the mean away from the symmetry planes
    // (not in the first or last interface element), and at the planes
    let last = pts.iter().map(|p| p.element).max().unwrap_or(0);
    let dev = |ends: bool| {
        pts.iter()
            .filter(|p| (p.element == 0 || p.element == last) == ends)
            .map(|p| (-p.traction[1] - p_mean).abs())
            .fold(0.0, f64::max)
    };
    (
        p_mean,
        [dev(false), dev(true)],
        its,
        solver.stresses().element,
    )
}

/// Shrink fit: inner ring 1 ≤ r ≤ 1.1 heated by 50 K inside the outer ring
/// 1.1 ≤ r ≤ 1.2, joined by the paper's joint; interference
/// δ = (1 + ν) α ΔT c (plane strain).
///
/// ```text
///   quarter rings, separate nodes at r = 1.1, symmetry on θ = 0 and π/2
/// ```
/// Goal: contact pressure resultant within 0.1 %, pointwise within 1 % (1.5 %
/// in the elements touching the symmetry planes), hoop stresses within 1 % of the two-cylinder
/// solution on an 8-row mesh; with the augmented-Lagrangian update the pressure is within
/// 0.1 % of its penalty-free value and independent of the penalty.
#[test]
fn shrink_fit_matches_two_cylinder_lame_solution() {
    let mesh = two_rings(8, 64);
    let fit = ShrinkFit {
        a: 1.0,
        c: 1.1,
        b: 1.2,
        delta: (1.0 + STEEL.poisson_ratio) * STEEL.expansion * 50.0 * 1.1,
        e: STEEL.youngs_modulus,
        nu: STEEL.poisson_ratio,
        state: Cylinders::PlaneStrain,
    };
    let p_exact = fit.pressure();
    let (p_pen, dev, its, s) = shrink_fit_solve(&mesh, None, 1.0);
    eprintln!(
        "shrink fit: p = {p_pen:.6e} vs {p_exact:.6e} ({:.3e}), deviation {:.3e} inside, {:.3e} at the symmetry planes, {its} iterations",
        p_pen / p_exact - 1.0,
        dev[0] / p_exact,
        dev[1] / p_exact
    );
    assert!(
        (p_pen / p_exact - 1.0).abs() < 1e-3,
        "resultant contact force"
    );
    // The diagonals of the structured mesh lean one way, so the mesh is not
    // mirror-symmetric about the symmetry planes: the pressure near them is
    // off by O(h) (largest next to the planes: 2.0 % at 4 rows, 1.1 % at 8),
    // decaying into the interior (0.66 % at 8 rows).
    assert!(
        dev[0] < 0.01 * p_exact,
        "pointwise pressure away from the symmetry planes"
    );
    assert!(
        dev[1] < 0.015 * p_exact,
        "pointwise pressure next to the symmetry planes"
    );
    assert!(its <= 8.0);
    // hoop stresses at element centroids
    let x = mesh.nodes();
    let inner = mesh.region_index("inner").unwrap();
    let mut worst: f64 = 0.0;
    for (e, t) in mesh.triangles().iter().enumerate() {
        let c = [
            (x[t[0]][0] + x[t[1]][0] + x[t[2]][0]) / 3.0,
            (x[t[0]][1] + x[t[1]][1] + x[t[2]][1]) / 3.0,
        ];
        let r = (c[0] * c[0] + c[1] * c[1]).sqrt();
        let tt = polar(s[e], c, [0.0; 2])[1];
        let exact = fit.sigma_tt(r, mesh.element_regions()[e] == inner);
        worst = worst.max((tt - exact).abs() / fit.sigma_tt(1.1, false).abs());
    }
    eprintln!("shrink fit: worst hoop error {worst:.3e}");
    assert!(worst < 0.01);
    // augmented Lagrangian: pressure independent of the penalty
    // (multiplier changes below 1e-4 of the pressure: the nodal rule's two
    // points per node pair make the last digits converge slowly)
    let (p_al1, _, _, _) = shrink_fit_solve(&mesh, Some(1e-4), 1.0);
    let (p_al2, _, _, _) = shrink_fit_solve(&mesh, Some(1e-4), 0.01);
    let (p_pen2, _, _, _) = shrink_fit_solve(&mesh, None, 0.01);
    eprintln!("AL: {p_al1:.8e} {p_al2:.8e}; penalty ×0.01: {p_pen2:.6e}");
    assert!((p_al1 / p_al2 - 1.0).abs() < 1e-3);
    assert!(
        (p_pen2 / p_al1 - 1.0).abs() > 1e-3,
        "a soft penalty alone is visibly off"
    );
    assert!((p_al1 / p_exact - 1.0).abs() < 0.01);
}

/// Two stacked blocks [0,1]×[0,1] (fixed at its base) and a thin lid block
/// [0,1]×[1,1.1] (thin, so the shear couple cannot lift an edge),
/// joined on y = 1 by a Mohr–Coulomb joint (c = 0.1 MPa, φ = 30°); 1 MPa on
/// the top, then the top edge is pushed sideways, then partly back.
///
/// ```text
///      ↓↓↓↓ p      → u_x = d on the top edge
///   ┌────────┐
///   │  top   │
///   ├════════┤ joint
///   │ bottom │
///   └────────┘ fixed
/// ```
/// Goal: σ = −p after the pressure stage; stick below the limit; τ = c + σ_c tan φ
/// at every point while sliding (σ_c of that point: the push tilts the
/// pressure distribution); the slip stays when the push is partly released.
/// Both friction iterations: the coupled law (one non-symmetric Newton pass)
/// and frozen limits (Tresca passes to the fixed point, tolerance 1e-12 so
/// the limit is met to 1e-8), which must also agree with each other.
#[test]
fn block_on_mohr_coulomb_joint() {
    let coupled = block_on_mohr_coulomb_joint_with(FrictionBound::Coupled);
    let frozen = block_on_mohr_coulomb_joint_with(FrictionBound::Frozen);
    for (a, b) in coupled.iter().zip(&frozen) {
        assert!((a.traction[0] - b.traction[0]).abs() < 1e-7 * a.traction[0].abs());
        assert!((a.slip - b.slip).abs() < 1e-7 * a.slip.abs());
    }
}

fn block_on_mohr_coulomb_joint_with(bound: FrictionBound) -> Vec<InterfacePointResult> {
    let mesh = common::stacked_blocks(0.1);
    let (c, phi, p) = (1e5, 30f64.to_radians(), 1e6);
    let k = 1e13;
    let law = PaperJoint::new(GhaboussiNormal::penalty(k).unwrap(), k, c, phi).unwrap();
    // ν = 0: the pressure stage is exactly uniform whatever the lateral supports
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
            friction_bound: bound,
            friction_tolerance: 1e-12,
            ..Default::default()
        },
    )
    .unwrap();
    // shear strength of a point with normal traction σ (σ < 0 compression)
    let limit = |sigma: f64| c - sigma * phi.tan();
    // 1: pressure only
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
        assert!(pt.traction[0].abs() < 1e-6 * p);
    }
    // 2: a small push: stick
    solver
        .advance(&Loads {
            pressure: 1.0,
            displacement: 1e-3,
            ..Loads::zero()
        })
        .unwrap();
    for pt in solver.interface_results() {
        assert_eq!(pt.status, tecon_contact::ContactStatus::Stick);
        assert!(pt.traction[0] > 0.0 && pt.traction[0] < limit(pt.traction[1]));
    }
    // 3: a large push: every point slides at the limit
    solver
        .advance(&Loads {
            pressure: 1.0,
            displacement: 1.0,
            ..Loads::zero()
        })
        .unwrap();
    let slid = solver.interface_results();
    for pt in &slid {
        assert_eq!(pt.status, tecon_contact::ContactStatus::Slip);
        let s = limit(pt.traction[1]);
        assert!(
            (pt.traction[0] - s).abs() < 1e-8 * s,
            "τ {} vs {s}",
            pt.traction[0]
        );
        assert!(pt.slip > 0.0);
    }
    // 4: push released by 0.1 %: elastic unloading, slip unchanged
    solver
        .advance(&Loads {
            pressure: 1.0,
            displacement: 0.999,
            ..Loads::zero()
        })
        .unwrap();
    for (a, b) in solver.interface_results().iter().zip(&slid) {
        assert_eq!(a.status, tecon_contact::ContactStatus::Stick);
        assert!(a.traction[0] < limit(a.traction[1]));
        assert_eq!(a.slip, b.slip, "slip is irreversible");
    }
    slid
}

fn two_blocks() -> Mesh {
    common::stacked_blocks(1.0)
}

/// The top block pulled up by 1 mm: the joint opens, carries no traction,
/// and neither block is stressed.
#[test]
fn separation_transmits_nothing() {
    let mesh = two_blocks();
    let law = PaperJoint::new(GhaboussiNormal::penalty(1e13).unwrap(), 1e13, 0.0, 0.5).unwrap();
    let model = ElasticModel::new(&mesh, Analysis::PlaneStrain)
        .material_everywhere(STEEL)
        .unwrap()
        .fix("base", Component::X, 0.0)
        .unwrap()
        .fix("base", Component::Y, 0.0)
        .unwrap()
        .fix("lid", Component::X, 0.0)
        .unwrap()
        .fix("lid", Component::Y, 1e-3)
        .unwrap()
        .interface("joint", Joint::Frictional(law))
        .unwrap();
    let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
    solver.advance(&Loads::mechanical()).unwrap();
    for pt in solver.interface_results() {
        assert_eq!(pt.status, tecon_contact::ContactStatus::Open);
        assert_eq!(pt.traction, [0.0, 0.0]);
        assert!((pt.jump[1] - 1e-3).abs() < 1e-15);
    }
    let s = solver.stresses();
    let smax = s
        .element
        .iter()
        .flat_map(|v| v.iter())
        .fold(0.0f64, |a, b| a.max(b.abs()));
    assert!(smax < 1e-3, "stress {smax} Pa in separated blocks");
}

#[test]
fn a_free_body_is_named() {
    let mesh = two_blocks();
    // linear joint, bottom fixed, nothing else: fine; remove the base: both free
    let law = Joint::Linear(LinearJoint::new(1e12, 1e12).unwrap());
    let model = ElasticModel::new(&mesh, Analysis::PlaneStrain)
        .material_everywhere(STEEL)
        .unwrap()
        .pressure("lid", 1e6)
        .unwrap()
        .interface("joint", law)
        .unwrap();
    let mut solver = StaticSolver::new(&model, SolverOptions::default()).unwrap();
    let e = solver.advance(&Loads::mechanical()).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("bottom") && msg.contains("top") && msg.contains("not constrained"),
        "{msg}"
    );
    // a missing material names the region
    let model = ElasticModel::new(&mesh, Analysis::PlaneStrain)
        .material("bottom", STEEL)
        .unwrap();
    let e = StaticSolver::new(&model, SolverOptions::default())
        .err()
        .unwrap();
    assert!(
        matches!(&e, ElasticError::MissingMaterial(r) if r == "top"),
        "{e}"
    );
    // bad material values are named
    let e = ElasticModel::new(&mesh, Analysis::PlaneStrain)
        .material(
            "top",
            Material {
                poisson_ratio: 0.5,
                ..STEEL
            },
        )
        .unwrap_err();
    assert!(
        e.to_string().contains("region 'top'") && e.to_string().contains("Poisson"),
        "{e}"
    );
    let e = ElasticModel::new(&mesh, Analysis::PlaneStrain)
        .symmetry("nowhere")
        .unwrap_err();
    assert!(e.to_string().contains("nowhere"), "{e}");
}
