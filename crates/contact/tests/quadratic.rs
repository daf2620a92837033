//! # 6-node (three-pair, quadratic) interface element
//!
//! Reference: the 4-node element's definitions (DESIGN.md §2 "Interface
//! element") with quadratic shape functions along the face:
//! `⟦u⟧ = R (N₁ (u₄ − u₁) + N₂ (u₃ − u₂) + N₅ (u₆ − u₅))`,
//! `f = ∫ Bᵀ t ds`, `K = ∫ Bᵀ C B ds`.
//!
//! ```text
//!        4 ●───────● 6 ──────● 3      top
//!        1 ●───────● 5 ──────● 2      bottom  (s = −1, 0, +1)
//! ```
//!
//! Checked:
//! * patch test: a uniform jump gives exactly the law's traction at every
//!   point, nodal and Gauss rules, and nodal forces `± Rᵀ t w_i` with the
//!   Simpson weights `L/6, 4L/6, L/6` (their sum `Rᵀ t L`);
//! * FD element tangent (12 × 12, central differences) for the linear joint
//!   and the paper's joint in stick and in slip (non-symmetric), nodal and
//!   Gauss, straight and curved faces, with smoothed normals: relative
//!   error < 1e-6;
//! * rigid translation gives zero jump and zero force;
//! * an unusable smoothed normal is a typed error naming the node.

use tecon_contact::nalgebra::{Point2, Vector2};
use tecon_contact::{
    ContactError, ContactLaw, ContactStatus, GhaboussiNormal, InterfaceQuadrature, JointState,
    LinearJoint, Matrix12, PaperJoint, QuadraticInterfaceElement, Vector12,
};

const RULES: [InterfaceQuadrature; 2] = [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2];

fn paper_joint() -> PaperJoint {
    // As the 4-node tests: crushing E = 2 GPa, contact E_f = 200 GPa,
    // t = 1 mm, ε_n^c = −1e-3, k_s = 3e11 Pa/m, c = 0.5 MPa, φ = 30°.
    let g = GhaboussiNormal::new(2.0e9, 2.0e11, 1.0e-3, -1.0e-3).unwrap();
    PaperJoint::new(g, 3.0e11, 0.5e6, 30f64.to_radians()).unwrap()
}

/// Straight zero-thickness element of length `l` at angle `a`.
fn straight(a: f64, l: f64) -> [Point2<f64>; 6] {
    let p1 = Point2::new(0.3, -0.2);
    let d = Vector2::new(a.cos(), a.sin()) * l;
    let (p2, p5) = (p1 + d, p1 + d * 0.5);
    [p1, p2, p2, p1, p5, p5]
}

/// Curved zero-thickness element on a circle of radius `r` spanning
/// `span` radians (walked clockwise: the outside is the top body).
fn curved(r: f64, span: f64) -> [Point2<f64>; 6] {
    let p = |a: f64| Point2::new(r * a.cos(), r * a.sin());
    let (a1, a0) = (0.4 + span, 0.4);
    let am = 0.5 * (a0 + a1);
    [p(a1), p(a0), p(a0), p(a1), p(am), p(am)]
}

/// Displacements: bottom nodes moved by `ub`, top node of pair k moved by
/// `ub + Rₖᵀ jₖ` with each point's frame (nodal rule: point k sees pair k
/// in the order (1,4), (5,6), (2,3)).
fn displacements(
    e: &QuadraticInterfaceElement,
    ub: Vector2<f64>,
    j: [Vector2<f64>; 3],
) -> Vector12 {
    let g = [0, 1, 2].map(|q| e.point_rotation(q).transpose() * j[q]);
    // Pair (bottom, top) local indices for points 0, 1, 2.
    let pairs = [(0usize, 3usize), (4, 5), (1, 2)];
    let mut u = Vector12::zeros();
    for (q, &(b, t)) in pairs.iter().enumerate() {
        u[2 * b] = ub.x;
        u[2 * b + 1] = ub.y;
        u[2 * t] = ub.x + g[q].x;
        u[2 * t + 1] = ub.y + g[q].y;
    }
    u
}

fn fd_error<L: ContactLaw>(
    e: &QuadraticInterfaceElement,
    law: &L,
    u: &Vector12,
    s: &[L::State; 3],
) -> f64 {
    let k = e.evaluate(law, u, s).tangent;
    let h = 1e-11;
    let mut k_fd = Matrix12::zeros();
    for c in 0..12 {
        let mut d = Vector12::zeros();
        d[c] = h;
        let fp = e.evaluate(law, &(u + d), s).force;
        let fm = e.evaluate(law, &(u - d), s).force;
        k_fd.set_column(c, &((fp - fm) / (2.0 * h)));
    }
    (k - k_fd).norm() / k.norm().max(1.0)
}

#[test]
fn uniform_jump_gives_exact_traction_and_simpson_nodal_forces() {
    let law = paper_joint();
    let lin = LinearJoint::new(3e11, 7e11).unwrap();
    let (a, l) = (0.7, 0.12);
    for rule in RULES {
        let e = QuadraticInterfaceElement::with_quadrature(&straight(a, l), rule).unwrap();
        let r = e.point_rotation(0).transpose();
        // Uniform jump: every top node moved by the same Rᵀ j.
        let j = Vector2::new(3e-6, -0.5e-6);
        let u = displacements(&e, Vector2::new(1e-4, 2e-4), [j; 3]);
        for (name, t_law, out) in [
            (
                "paper",
                law.evaluate(&j, &JointState::default()).traction,
                e.evaluate(&law, &u, &[JointState::default(); 3])
                    .points
                    .map(|p| (p.jump, p.traction)),
            ),
            (
                "linear",
                lin.evaluate(&j, &()).traction,
                e.evaluate(&lin, &u, &[(); 3])
                    .points
                    .map(|p| (p.jump, p.traction)),
            ),
        ] {
            for (jump, traction) in out {
                assert!((jump - j).norm() < 1e-15, "{rule:?} {name}: jump {jump}");
                assert!(
                    (traction - t_law).norm() < 1e-12 * t_law.norm(),
                    "{rule:?} {name}: {traction} vs {t_law}"
                );
            }
        }
        let f = e.evaluate(&lin, &u, &[(); 3]).force;
        let tg = r * lin.evaluate(&j, &()).traction;
        // Pair weights: Simpson L/6, 4L/6, L/6 (both rules give ∫ N_i = these).
        for (b, t, w) in [
            (0usize, 3usize, l / 6.0),
            (1, 2, l / 6.0),
            (4, 5, 4.0 * l / 6.0),
        ] {
            for c in 0..2 {
                assert!(
                    (f[2 * t + c] - tg[c] * w).abs() < 1e-9 * tg.norm() * l,
                    "{rule:?}"
                );
                assert!(
                    (f[2 * b + c] + tg[c] * w).abs() < 1e-9 * tg.norm() * l,
                    "{rule:?}"
                );
            }
        }
    }
}

#[test]
fn rigid_translation_gives_zero_force() {
    let lin = LinearJoint::new(3e11, 7e11).unwrap();
    for rule in RULES {
        let e = QuadraticInterfaceElement::with_quadrature(&curved(0.775, 0.05), rule).unwrap();
        let mut u = Vector12::zeros();
        for n in 0..6 {
            u[2 * n] = 1.3e-3;
            u[2 * n + 1] = -0.4e-3;
        }
        let r = e.evaluate(&lin, &u, &[(); 3]);
        assert!(r.force.amax() < 1e-20, "{rule:?}: {}", r.force.amax());
        assert!(r.points.iter().all(|p| p.jump.norm() == 0.0));
    }
}

#[test]
fn tangent_matches_finite_differences_in_stick_and_slip() {
    let law = paper_joint();
    let lin = LinearJoint::new(3e11, 7e11).unwrap();
    let geometries = [
        ("straight", straight(2.2, 0.1)),
        ("curved", curved(0.775, 0.04)),
    ];
    for (gname, nodes) in geometries {
        for rule in RULES {
            for smoothed in [false, true] {
                let mut e = QuadraticInterfaceElement::with_quadrature(&nodes, rule).unwrap();
                if smoothed {
                    let n = e.geometry().node_normals();
                    let tilt = |v: Vector2<f64>, a: f64| {
                        Vector2::new(v.x * a.cos() - v.y * a.sin(), v.x * a.sin() + v.y * a.cos())
                    };
                    e = e
                        .with_node_normals([tilt(n[0], 0.01), tilt(n[1], -0.02), n[2]])
                        .unwrap();
                }
                // Slip: all pairs crushed and sheared past the limit.
                let u = displacements(
                    &e,
                    Vector2::zeros(),
                    [
                        Vector2::new(40e-6, -0.6e-6),
                        Vector2::new(38e-6, -0.5e-6),
                        Vector2::new(35e-6, -0.4e-6),
                    ],
                );
                let s = [JointState::default(); 3];
                let r = e.evaluate(&law, &u, &s);
                let what = format!("{gname} {rule:?} smoothed={smoothed}");
                assert!(
                    r.points.iter().all(|p| p.status == ContactStatus::Slip),
                    "{what}: {:?}",
                    r.points.map(|p| p.status)
                );
                let asym = (r.tangent - r.tangent.transpose()).norm() / r.tangent.norm();
                assert!(asym > 0.05, "{what}: slipping tangent symmetric ({asym})");
                let err_slip = fd_error(&e, &law, &u, &s);
                // Stick.
                let u_st = displacements(
                    &e,
                    Vector2::zeros(),
                    [
                        Vector2::new(0.1e-6, -0.6e-6),
                        // (−1.0e-6 would sit on the crushing limit ε_n^c t, a kink)
                        Vector2::new(0.05e-6, -0.8e-6),
                        Vector2::new(-0.2e-6, -1.4e-6),
                    ],
                );
                let r_st = e.evaluate(&law, &u_st, &s);
                assert!(r_st.points.iter().all(|p| p.status == ContactStatus::Stick));
                let err_stick = fd_error(&e, &law, &u_st, &s);
                let err_lin = fd_error(&e, &lin, &u, &[(); 3]);
                println!(
                    "{what}: FD tangent error slip {err_slip:.2e}, stick {err_stick:.2e}, linear {err_lin:.2e}"
                );
                assert!(err_slip < 1e-6, "{what}: slip {err_slip}");
                assert!(err_stick < 1e-6, "{what}: stick {err_stick}");
                assert!(err_lin < 1e-6, "{what}: linear {err_lin}");
            }
        }
    }
}

#[test]
fn smoothed_normals_interpolate_and_bad_normals_are_typed_errors() {
    let e = QuadraticInterfaceElement::new(&curved(0.775, 0.05)).unwrap();
    let n = e.geometry().node_normals();
    // Nodal rule: point k takes exactly the given normal of its node.
    let given = [n[0] * 2.0, n[1] * 0.5, n[2]];
    let s = e.with_node_normals(given).unwrap();
    for (q, node) in [(0usize, 0usize), (1, 2), (2, 1)] {
        let rot = s.point_rotation(q);
        let normal = Vector2::new(rot[(1, 0)], rot[(1, 1)]);
        assert!((normal - given[node].normalize()).norm() < 1e-15);
    }
    let bad = Vector2::new(-n[1].y, n[1].x); // tangent: 90° off
    assert!(matches!(
        e.with_node_normals([n[0], bad, n[2]]),
        Err(ContactError::Normal { node: 2, .. })
    ));
    assert!(matches!(
        e.with_node_normals([n[0], n[1], Vector2::new(f64::NAN, 0.0)]),
        Err(ContactError::Normal { node: 5, .. })
    ));
}
