//! # 4-node interface element: kinematics, tangent, invariance
//!
//! Reference: DESIGN.md §2 "Interface element" (Goodman et al. 1968 joint
//! element; jump `⟦u⟧ = R (N₁ (u₄ − u₁) + N₂ (u₃ − u₂))`,
//! `f = ∫ Bᵀ t dζ`, `K = ∫ Bᵀ C B dζ`).
//!
//! Goal: the element's force and tangent are consistent with each other and
//! with the law, and independent of how the element lies in the plane.
//!
//! ```text
//!        4 ●───────────────● 3      top      (jump = top − bottom)
//!        1 ●───────────────● 2      bottom   t = (x₂−x₁)/L, n = left normal
//! ```
//!
//! Checked:
//! * FD element tangent (8 × 8, central differences) for the linear joint
//!   and the paper's joint in stick and in slip (non-symmetric), nodal and
//!   Gauss rules, random orientation (proptest), relative error ≤ 1e-7;
//! * rigid translation (any element) and infinitesimal rigid rotation
//!   (zero-thickness element) give zero jump and zero force (for a joint
//!   with slip history: the force of the undisplaced element);
//! * a uniform jump gives exactly the law's traction at both points and
//!   nodal forces `± Rᵀ t L/2`;
//! * rotating + translating the element and rotating its displacements
//!   rotates the force and the tangent (`Q f`, `Q K Qᵀ`), tractions unchanged;
//! * the linear element equals `∫ b bᵀ dζ ⊗ Rᵀ C R` built from the shared
//!   geometry, and the nodal rule couples only facing node pairs;
//! * geometry errors surface as typed errors.

use approx::assert_relative_eq;
use proptest::prelude::*;
use tecon_contact::nalgebra::{Matrix2, Point2, Rotation2, Vector2};
use tecon_contact::{
    ContactError, ContactLaw, ContactStatus, GhaboussiNormal, InterfaceElement,
    InterfaceGeometryError, InterfaceQuadrature, JointState, LinearJoint, Matrix8, NormalLaw,
    PaperJoint, Vector8,
};

const RULES: [InterfaceQuadrature; 2] = [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2];

/// Zero-thickness element of length `l` at angle `a` starting at `x0`.
fn element_nodes(x0: Vector2<f64>, a: f64, l: f64) -> [Point2<f64>; 4] {
    let p1 = Point2::from(x0);
    let p2 = p1 + Vector2::new(a.cos(), a.sin()) * l;
    [p1, p2, p2, p1]
}

fn paper_joint() -> PaperJoint {
    // Rough joint: crushing E = 2 GPa, contact E_f = 200 GPa, t = 1 mm,
    // ε_n^c = −1e-3, k_s = 3e11 Pa/m, c = 0.5 MPa, φ = 30°.
    let g = GhaboussiNormal::new(2.0e9, 2.0e11, 1.0e-3, -1.0e-3).unwrap();
    PaperJoint::new(g, 3.0e11, 0.5e6, 30f64.to_radians()).unwrap()
}

/// Global displacements giving local jumps `j1` at node pair (1,4) and `j2`
/// at pair (2,3), bottom nodes moved by `ub`.
fn displacements(
    e: &InterfaceElement,
    ub: Vector2<f64>,
    j1: Vector2<f64>,
    j2: Vector2<f64>,
) -> Vector8 {
    let rt = e.geometry().rotation().transpose();
    let (g1, g2) = (rt * j1, rt * j2);
    Vector8::from_column_slice(&[
        ub.x,
        ub.y,
        ub.x,
        ub.y,
        ub.x + g2.x,
        ub.y + g2.y,
        ub.x + g1.x,
        ub.y + g1.y,
    ])
}

fn fd_tangent<L: ContactLaw>(
    e: &InterfaceElement,
    law: &L,
    u: &Vector8,
    s: &[L::State; 2],
    h: f64,
) -> Matrix8 {
    let mut k = Matrix8::zeros();
    for c in 0..8 {
        let mut d = Vector8::zeros();
        d[c] = h;
        let fp = e.evaluate(law, &(u + d), s).force;
        let fm = e.evaluate(law, &(u - d), s).force;
        k.set_column(c, &((fp - fm) / (2.0 * h)));
    }
    k
}

/// True if no point changes status, slip direction or normal stage within
/// ±h of `u` in any dof (the law is piecewise linear between such kinks).
fn away_from_kinks(
    e: &InterfaceElement,
    law: &PaperJoint,
    u: &Vector8,
    s: &[JointState; 2],
    h: f64,
) -> bool {
    let st = |v: &Vector8| {
        e.evaluate(law, v, s).points.map(|p| {
            let stage = law.normal_law().normal(p.jump.y, p.state.lambda_n).stage;
            (p.status, p.traction.x >= 0.0, stage)
        })
    };
    let s0 = st(u);
    (0..8).all(|c| {
        let mut d = Vector8::zeros();
        d[c] = h;
        st(&(u + d)) == s0 && st(&(u - d)) == s0
    })
}

fn fd_error<L: ContactLaw>(e: &InterfaceElement, law: &L, u: &Vector8, s: &[L::State; 2]) -> f64 {
    let k = e.evaluate(law, u, s).tangent;
    let k_fd = fd_tangent(e, law, u, s, 1e-11);
    (k - k_fd).norm() / k.norm().max(1.0)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn element_tangent_matches_fd_paper_joint(
        a in 0.0..std::f64::consts::TAU,
        l in 0.01..0.5_f64,
        gauss in any::<bool>(),
        jt in prop::array::uniform2(-30.0e-6..30.0e-6_f64),
        jn in prop::array::uniform2(-1.8e-6..0.3e-6_f64),
        slip in prop::array::uniform2(-20.0e-6..20.0e-6_f64),
    ) {
        let rule = if gauss { InterfaceQuadrature::Gauss2 } else { InterfaceQuadrature::Nodal };
        let e = InterfaceElement::with_quadrature(&element_nodes(Vector2::new(0.3, -0.2), a, l), rule).unwrap();
        let law = paper_joint();
        let u = displacements(&e, Vector2::new(1e-4, -2e-4), Vector2::new(jt[0], jn[0]), Vector2::new(jt[1], jn[1]));
        let s = slip.map(|g| JointState { slip: g, ..Default::default() });
        prop_assume!(away_from_kinks(&e, &law, &u, &s, 1e-10));
        let err = fd_error(&e, &law, &u, &s);
        prop_assert!(err < 1e-7, "FD error {err:e}");
    }

    #[test]
    fn rotating_the_element_rotates_force_and_tangent(
        a in 0.0..std::f64::consts::TAU,
        theta in 0.0..std::f64::consts::TAU,
        shift in prop::array::uniform2(-10.0..10.0_f64),
        gauss in any::<bool>(),
        u in prop::array::uniform8(-20.0e-6..20.0e-6_f64),
    ) {
        let rule = if gauss { InterfaceQuadrature::Gauss2 } else { InterfaceQuadrature::Nodal };
        let nodes = element_nodes(Vector2::new(0.1, 0.2), a, 0.2);
        let q = Rotation2::new(theta);
        let moved = nodes.map(|p| q * p + Vector2::new(shift[0], shift[1]));
        let e0 = InterfaceElement::with_quadrature(&nodes, rule).unwrap();
        let e1 = InterfaceElement::with_quadrature(&moved, rule).unwrap();
        let u0 = Vector8::from_column_slice(&u);
        let mut qq = Matrix8::zeros();
        for n in 0..4 {
            qq.fixed_view_mut::<2, 2>(2 * n, 2 * n).copy_from(q.matrix());
        }
        let u1 = qq * u0;
        let law = paper_joint();
        let s = [JointState { slip: 3e-6, ..Default::default() }; 2];
        let (r0, r1) = (e0.evaluate(&law, &u0, &s), e1.evaluate(&law, &u1, &s));
        let fscale = r0.force.norm().max(1e-3);
        prop_assert!((r1.force - qq * r0.force).norm() <= 1e-9 * fscale);
        let kscale = r0.tangent.norm().max(1.0);
        prop_assert!((r1.tangent - qq * r0.tangent * qq.transpose()).norm() <= 1e-9 * kscale);
        for (p0, p1) in r0.points.iter().zip(r1.points.iter()) {
            prop_assert_eq!(p0.status, p1.status);
            prop_assert!((p0.jump - p1.jump).norm() <= 1e-12 * p0.jump.norm().max(1e-9));
            prop_assert!((p0.traction - p1.traction).norm() <= 1e-9 * p0.traction.norm().max(1.0));
        }
    }
}

#[test]
fn slipping_element_tangent_is_non_symmetric_and_matches_fd() {
    let law = paper_joint();
    for rule in RULES {
        let e = InterfaceElement::with_quadrature(
            &element_nodes(Vector2::new(1.0, 2.0), 2.2, 0.1),
            rule,
        )
        .unwrap();
        // Both pairs in the crushing stage, sheared far past the limit.
        let u = displacements(
            &e,
            Vector2::zeros(),
            Vector2::new(40e-6, -0.6e-6),
            Vector2::new(35e-6, -0.4e-6),
        );
        let s = [JointState::default(); 2];
        let r = e.evaluate(&law, &u, &s);
        assert!(r.points.iter().all(|p| p.status == ContactStatus::Slip));
        assert!(away_from_kinks(&e, &law, &u, &s, 1e-10));
        let asym = (r.tangent - r.tangent.transpose()).norm() / r.tangent.norm();
        assert!(
            asym > 0.1,
            "slipping tangent should be non-symmetric: {asym}"
        );
        let err = fd_error(&e, &law, &u, &s);
        println!("{rule:?}: slipping element FD tangent error {err:.2e} (asymmetry {asym:.2})");
        assert!(err < 1e-7, "{err}");
        // Stick and linear joint too.
        let u_st = displacements(
            &e,
            Vector2::zeros(),
            Vector2::new(0.1e-6, -0.6e-6),
            Vector2::new(-0.2e-6, -1.4e-6),
        );
        let r_st = e.evaluate(&law, &u_st, &s);
        assert!(r_st.points.iter().all(|p| p.status == ContactStatus::Stick));
        let err_st = fd_error(&e, &law, &u_st, &s);
        let lin = LinearJoint::new(3e11, 7e11).unwrap();
        let err_lin = fd_error(&e, &lin, &u, &[(); 2]);
        println!("{rule:?}: stick element FD error {err_st:.2e}, linear joint {err_lin:.2e}");
        assert!(err_st < 1e-7 && err_lin < 1e-7);
    }
}

#[test]
fn rigid_body_motion_gives_zero_force() {
    let law = paper_joint();
    let lin = LinearJoint::new(3e11, 7e11).unwrap();
    // Finite-thickness element (1 mm gap): rigid translation.
    let nodes =
        [[0.0, 0.0], [0.3, 0.1], [0.3, 0.101], [0.0, 0.001]].map(|p| Point2::new(p[0], p[1]));
    for rule in RULES {
        let e = InterfaceElement::with_quadrature(&nodes, rule).unwrap();
        let u = Vector8::from_fn(|i, _| if i % 2 == 0 { 1.7e-3 } else { -4.2e-3 });
        let r = e.evaluate(&lin, &u, &[(); 2]);
        assert!(r.points.iter().all(|p| p.jump.norm() < 1e-18));
        assert!(r.force.norm() < 1e-6, "{}", r.force.norm());
        // Zero-thickness element: infinitesimal rigid rotation ω about c.
        let e0 = InterfaceElement::with_quadrature(
            &element_nodes(Vector2::new(0.4, 0.7), 0.9, 0.25),
            rule,
        )
        .unwrap();
        let (omega, c) = (1e-4, Vector2::new(-3.0, 5.0));
        let nodes0 = element_nodes(Vector2::new(0.4, 0.7), 0.9, 0.25);
        let mut u = Vector8::zeros();
        for (n, p) in nodes0.iter().enumerate() {
            let d = p.coords - c;
            u[2 * n] = -omega * d.y;
            u[2 * n + 1] = omega * d.x;
        }
        for s in [
            [JointState::default(); 2],
            [JointState {
                slip: 1e-6,
                ..Default::default()
            }; 2],
        ] {
            // Rigid motion changes nothing: the force is that of the
            // undisplaced element with the same history (zero for a virgin
            // joint; a residual shear for a committed slip, since touching
            // faces are closed).
            let r = e0.evaluate(&law, &u, &s);
            let r0 = e0.evaluate(&law, &Vector8::zeros(), &s);
            assert_eq!(r.force, r0.force);
            assert!(r.points.iter().all(|p| p.jump == Vector2::zeros()));
        }
        let virgin = e0.evaluate(&law, &u, &[JointState::default(); 2]);
        assert_eq!(virgin.force, Vector8::zeros());
        let r = e0.evaluate(&lin, &u, &[(); 2]);
        assert_eq!(r.force, Vector8::zeros());
    }
}

#[test]
fn uniform_jump_gives_exact_traction_and_nodal_forces() {
    let (ks, kn) = (3e11, 7e11);
    let lin = LinearJoint::new(ks, kn).unwrap();
    let law = paper_joint();
    for rule in RULES {
        for a in [0.0, 0.7, 2.0, -2.5] {
            let l = 0.15;
            let e = InterfaceElement::with_quadrature(
                &element_nodes(Vector2::new(2.0, -1.0), a, l),
                rule,
            )
            .unwrap();
            let j = Vector2::new(2.0e-6, -1.1e-6);
            let u = displacements(&e, Vector2::new(0.3, 0.2), j, j);
            let r = e.evaluate(&lin, &u, &[(); 2]);
            let t = Vector2::new(ks * j.x, kn * j.y);
            for p in &r.points {
                assert_relative_eq!(p.jump, j, max_relative = 1e-9);
                assert_relative_eq!(p.traction, t, max_relative = 1e-9);
            }
            // Each node carries half the resultant, bottom pulled by −Rᵀt.
            let fg = e.geometry().rotation().transpose() * t * (l / 2.0);
            for (n, sign) in [(0, -1.0), (1, -1.0), (2, 1.0), (3, 1.0)] {
                assert_relative_eq!(
                    r.force.fixed_rows::<2>(2 * n).into_owned(),
                    fg * sign,
                    max_relative = 1e-9
                );
            }
            // The nonlinear law too: traction = law's traction at j.
            let rp = e.evaluate(&law, &u, &[JointState::default(); 2]);
            let t_law = law.evaluate(&j, &JointState::default()).traction;
            for p in &rp.points {
                assert_relative_eq!(p.traction, t_law, max_relative = 1e-9);
            }
        }
    }
}

#[test]
fn linear_tangent_is_jump_gram_times_rotated_stiffness() {
    let lin = LinearJoint::new(3e11, 7e11).unwrap();
    let e_nodes = element_nodes(Vector2::new(0.0, 0.0), 1.1, 0.3);
    for rule in RULES {
        let e = InterfaceElement::with_quadrature(&e_nodes, rule).unwrap();
        let k = e.evaluate(&lin, &Vector8::zeros(), &[(); 2]).tangent;
        let gram = e.geometry().jump_gram(rule);
        let r = e.geometry().rotation();
        let c = r.transpose() * Matrix2::new(3e11, 0.0, 0.0, 7e11) * r;
        let mut expected = Matrix8::zeros();
        for i in 0..4 {
            for j in 0..4 {
                expected
                    .fixed_view_mut::<2, 2>(2 * i, 2 * j)
                    .copy_from(&(c * gram[(i, j)]));
            }
        }
        assert_relative_eq!(k, expected, max_relative = 1e-12, epsilon = 1e-3);
        // Nodal rule: only facing pairs (1,4), (2,3) and self blocks couple.
        let coupled = |i: usize, j: usize| k.fixed_view::<2, 2>(2 * i, 2 * j).norm() > 0.0;
        let facing = |i: usize, j: usize| i == j || i + j == 3;
        for i in 0..4 {
            for j in 0..4 {
                if rule == InterfaceQuadrature::Nodal {
                    assert_eq!(coupled(i, j), facing(i, j), "blocks ({i},{j})");
                } else {
                    assert!(coupled(i, j));
                }
            }
        }
    }
}

#[test]
fn b_matrix_maps_displacements_to_jumps() {
    for rule in RULES {
        let e = InterfaceElement::with_quadrature(
            &element_nodes(Vector2::new(0.5, 0.1), -1.2, 0.3),
            rule,
        )
        .unwrap();
        let u = Vector8::from_fn(|i, _| 1e-6 * ((i * 7 % 5) as f64 - 2.0));
        for (q, j) in e.jumps(&u).into_iter().enumerate() {
            assert_relative_eq!(e.b_matrix(q) * u, j, max_relative = 1e-12);
        }
    }
}

#[test]
fn point_output_reports_jump_traction_status_slip() {
    let law = paper_joint();
    let e = InterfaceElement::new(&element_nodes(Vector2::zeros(), 0.0, 0.2)).unwrap();
    // Pair (1,4) open, pair (2,3) slipping in the crushing stage.
    let u = displacements(
        &e,
        Vector2::zeros(),
        Vector2::new(3e-6, 0.5e-6),
        Vector2::new(40e-6, -0.5e-6),
    );
    let r = e.evaluate(&law, &u, &[JointState::default(); 2]);
    let [p1, p2] = r.points;
    assert_eq!((p1.zeta, p2.zeta), (-0.1, 0.1));
    assert_eq!(p1.status, ContactStatus::Open);
    assert_eq!(p1.traction, Vector2::zeros());
    assert_eq!(p2.status, ContactStatus::Slip);
    assert_relative_eq!(p2.jump, Vector2::new(40e-6, -0.5e-6), max_relative = 1e-12);
    let s = law.strength(p2.traction.y);
    assert_relative_eq!(p2.traction.x, s, max_relative = 1e-12);
    assert_relative_eq!(p2.slip, 40e-6 - s / law.k_s(), max_relative = 1e-12);
    assert_eq!(p2.slip, p2.state.slip);
}

#[test]
fn element_augment_updates_multipliers() {
    let law = PaperJoint::new(GhaboussiNormal::penalty(1e12).unwrap(), 1e12, 0.0, 0.3).unwrap();
    let e = InterfaceElement::new(&element_nodes(Vector2::zeros(), 0.4, 0.1)).unwrap();
    let u = displacements(
        &e,
        Vector2::zeros(),
        Vector2::new(0.0, -1e-6),
        Vector2::new(0.0, -2e-6),
    );
    let (s, change) = e.augment(&law, &u, &[JointState::default(); 2]);
    assert_relative_eq!(s[0].lambda_n, 1e6, max_relative = 1e-9);
    assert_relative_eq!(s[1].lambda_n, 2e6, max_relative = 1e-9);
    assert_relative_eq!(change, 2e6, max_relative = 1e-9);
}

#[test]
fn bad_geometry_is_a_typed_error() {
    let p = Point2::new(1.0, 1.0);
    assert!(matches!(
        InterfaceElement::new(&[p, p, p, p]),
        Err(ContactError::Geometry(
            InterfaceGeometryError::ZeroLength { .. }
        ))
    ));
    let mut nodes = element_nodes(Vector2::zeros(), 0.0, 1.0);
    nodes.swap(2, 3);
    assert_eq!(
        InterfaceElement::new(&nodes),
        Err(ContactError::Geometry(
            InterfaceGeometryError::ReversedTopFace
        ))
    );
}

/// Two chords of a circle of radius `r` sharing the node at angle 0, each
/// spanning `d` radians, running counter-clockwise: the normal (left of
/// 1→2) points inwards, into the top body.
fn arc_elements(r: f64, d: f64) -> [[Point2<f64>; 4]; 2] {
    let p = |a: f64| Point2::new(r * a.cos(), r * a.sin());
    [[p(-d), p(0.0), p(0.0), p(-d)], [p(0.0), p(d), p(d), p(0.0)]]
}

#[test]
fn smoothed_normals_give_one_jump_at_a_shared_node() {
    // A tangential slip s of the top face at the shared node: with chord
    // frames the two elements see normal jumps ±s·sin(d/2) (one opens, one
    // penetrates); with the nodal normal (radial) both see Δu_n = 0.
    let (r, d, s) = (0.5, 0.1, 40e-6);
    let [a, b] = arc_elements(r, d);
    let radial = Vector2::new(-1.0, 0.0);
    // top node of the shared pair moves tangentially (+y at angle 0)
    let ua = Vector8::from_column_slice(&[0., 0., 0., 0., 0., s, 0., 0.]);
    let ub = Vector8::from_column_slice(&[0., 0., 0., 0., 0., 0., 0., s]);
    for rule in RULES {
        let ea = InterfaceElement::with_quadrature(&a, rule).unwrap();
        let eb = InterfaceElement::with_quadrature(&b, rule).unwrap();
        if rule == InterfaceQuadrature::Nodal {
            let (ja, jb) = (ea.jump_at(1, &ua), eb.jump_at(0, &ub));
            let expected = s * (0.5 * d).sin();
            assert_relative_eq!(ja.y, expected, max_relative = 1e-12);
            assert_relative_eq!(jb.y, -expected, max_relative = 1e-12);
        }
        let na = -Vector2::new((-d).cos(), (-d).sin());
        let nb = -Vector2::new(d.cos(), d.sin());
        let sa = ea.with_node_normals([na, radial]).unwrap();
        let sb = eb.with_node_normals([radial, nb]).unwrap();
        if rule == InterfaceQuadrature::Nodal {
            let (ja, jb) = (sa.jump_at(1, &ua), sb.jump_at(0, &ub));
            assert!(ja.y.abs() < 1e-20 && jb.y.abs() < 1e-20, "{ja} {jb}");
            // tangent = normal turned −90°: (0, 1) at angle 0
            assert_relative_eq!(ja.x, s, max_relative = 1e-14);
            assert_relative_eq!(jb.x, s, max_relative = 1e-14);
        }
        // frames stay orthonormal with normal = tangent turned +90°
        for e in [&sa, &sb] {
            for q in 0..2 {
                let m = e.point_rotation(q);
                assert_relative_eq!(m * m.transpose(), Matrix2::identity(), epsilon = 1e-15);
                assert_relative_eq!(m.determinant(), 1.0, epsilon = 1e-15);
            }
        }
        // consistent tangent with smoothed frames, stick and slip
        let law = paper_joint();
        let st = [JointState::default(); 2];
        for (jt, jn) in [(0.1e-6, -0.6e-6), (40e-6, -0.5e-6)] {
            let u = displacements(
                &sa,
                Vector2::new(1e-5, 2e-5),
                Vector2::new(jt, jn),
                Vector2::new(0.8 * jt, 1.3 * jn),
            );
            assert!(away_from_kinks(&sa, &law, &u, &st, 1e-10));
            let err = fd_error(&sa, &law, &u, &st);
            assert!(err < 1e-7, "{rule:?}: FD error {err:e}");
        }
    }
}

#[test]
fn unusable_smoothed_normal_is_a_typed_error() {
    let [a, _] = arc_elements(0.5, 0.1);
    let e = InterfaceElement::new(&a).unwrap();
    let n = e.geometry().normal();
    for bad in [
        Vector2::zeros(),
        Vector2::new(f64::NAN, 1.0),
        -n,
        Rotation2::new(1.1) * n,
    ] {
        let err = e.with_node_normals([n, bad]).unwrap_err();
        assert!(matches!(err, ContactError::Normal { node: 2, .. }), "{err}");
        assert!(err.to_string().contains("interface node 2"), "{err}");
    }
    assert!(e.with_node_normals([Rotation2::new(0.9) * n, n]).is_ok());
}
