//! # Contact laws: values, consistent tangents, history, errors
//!
//! Reference: DESIGN.md §2 "Contact laws" (Ghaboussi–Wilson–Witherspoon
//! three-stage normal law; Mohr–Coulomb elastic–perfectly plastic
//! tangential law), and the return-mapping algorithm for perfect
//! plasticity (Simo & Hughes, *Computational Inelasticity*, ch. 1, 1D case).
//!
//! Goal: every law returns the traction of its defining formula, a tangent
//! equal to the finite-difference derivative of its traction (away from
//! kinks), and the history behaviour of friction.
//!
//! Sketch (Mohr–Coulomb in the (σ, τ) plane):
//!
//! ```text
//!          τ
//!          │   slip  ╱  τ = c + σ_c tan φ
//!          │       ╱
//!          │     ╱  stick
//!   ───────┼───╱─────────────────── σ   (σ > 0 tension)
//!      σ_c │ ╲  apex σ = c/tan φ (tension cut-off)
//! ```
//!
//! Checked:
//! * FD tangents (central differences, relative error ≤ 1e-7) for the linear
//!   joint, both normal laws in every stage, the elastic joint and the
//!   Mohr–Coulomb joint in stick and in slip (non-symmetric), on random
//!   points (proptest) that are not within one FD step of a kink;
//! * Mohr–Coulomb: stick below the limit, traction on the limit while
//!   slipping, irreversible slip on unloading, zero traction when open,
//!   cohesion, tension cut-off at the apex;
//! * augmented-Lagrangian multiplier update; typed parameter errors.

use approx::assert_relative_eq;
use proptest::prelude::*;
use tecon_contact::nalgebra::{Matrix2, Vector2};
use tecon_contact::{
    ContactLaw, ContactStatus, ElasticJoint, FrictionBound, GhaboussiNormal, JointState, LawError,
    LinearJoint, LinearNormal, MohrCoulomb, NormalLaw, NormalStage, PaperJoint, default_penalty,
};

const K: f64 = 1.0e12; // typical penalty, Pa/m
const FD_TOL: f64 = 1.0e-7;

/// Central-difference tangent of `law` at `jump` with committed `state`.
fn fd_tangent<L: ContactLaw>(
    law: &L,
    jump: &Vector2<f64>,
    state: &L::State,
    h: f64,
) -> Matrix2<f64> {
    let mut c = Matrix2::zeros();
    for k in 0..2 {
        let mut e = Vector2::zeros();
        e[k] = h;
        let tp = law.evaluate(&(jump + e), state).traction;
        let tm = law.evaluate(&(jump - e), state).traction;
        c.set_column(k, &((tp - tm) / (2.0 * h)));
    }
    c
}

/// Relative FD error `‖C − C_fd‖ / max(‖C‖, k_ref)`.
fn fd_error<L: ContactLaw>(
    law: &L,
    jump: &Vector2<f64>,
    state: &L::State,
    h: f64,
    k_ref: f64,
) -> f64 {
    let c = law.evaluate(jump, state).tangent;
    let c_fd = fd_tangent(law, jump, state, h);
    (c - c_fd).norm() / c.norm().max(k_ref)
}

/// "Regime" of a law response, to skip points within one FD step of a kink.
fn same_regime<N: NormalLaw>(
    law: &MohrCoulomb<N>,
    jump: &Vector2<f64>,
    state: &JointState,
    h: f64,
) -> bool {
    let regime = |j: Vector2<f64>| {
        let r = law.evaluate(&j, state);
        let nr = law.normal_law().normal(j.y, state.lambda_n);
        (
            r.status,
            nr.stage,
            law.strength(nr.sigma) > 0.0,
            r.traction.x >= 0.0,
        )
    };
    let r0 = regime(*jump);
    [Vector2::new(h, 0.0), Vector2::new(0.0, h)]
        .iter()
        .all(|e| regime(jump + e) == r0 && regime(jump - e) == r0)
}

fn rough_ghaboussi() -> GhaboussiNormal {
    // E = 2e9 Pa, E_f = 2e11 Pa, t = 1 mm, crushing to ε_n^c = −1e-3.
    GhaboussiNormal::new(2.0e9, 2.0e11, 1.0e-3, -1.0e-3).unwrap()
}

#[test]
fn linear_joint_values_and_tangent() {
    let law = LinearJoint::new(3.0e11, 7.0e11).unwrap();
    let j = Vector2::new(2.0e-6, -1.0e-6);
    let r = law.evaluate(&j, &());
    assert_relative_eq!(
        r.traction,
        Vector2::new(6.0e5, -7.0e5),
        max_relative = 1e-15
    );
    assert_eq!(r.status, ContactStatus::Stick);
    // Bonded: tension too.
    let r = law.evaluate(&Vector2::new(0.0, 1.0e-6), &());
    assert_relative_eq!(r.traction.y, 7.0e5, max_relative = 1e-15);
    let e = fd_error(&law, &j, &(), 1e-12, 0.0);
    println!("linear joint FD tangent error {e:.2e}");
    assert!(e < FD_TOL, "{e}");
}

#[test]
fn ghaboussi_three_stages() {
    let g = rough_ghaboussi();
    let (e, e_f, t, eps_c) = (2.0e9, 2.0e11, 1.0e-3, -1.0e-3);
    // Separation.
    let r = g.normal(0.5e-6, 0.0);
    assert_eq!(
        (r.sigma, r.stiffness, r.stage),
        (0.0, 0.0, NormalStage::Separation)
    );
    // Crushing: σ = E ε_n.
    let du = -0.4e-6;
    let r = g.normal(du, 0.0);
    assert_eq!(r.stage, NormalStage::Crushing);
    assert_relative_eq!(r.sigma, e * du / t, max_relative = 1e-14);
    assert_relative_eq!(r.stiffness, e / t, max_relative = 1e-14);
    // Contact: σ = E ε^c + E_f (ε − ε^c).
    let du = -1.3e-6;
    let r = g.normal(du, 0.0);
    assert_eq!(r.stage, NormalStage::Contact);
    assert_relative_eq!(
        r.sigma,
        e * eps_c + e_f * (du / t - eps_c),
        max_relative = 1e-14
    );
    assert_relative_eq!(r.stiffness, e_f / t, max_relative = 1e-14);
    // Continuous at both stage boundaries.
    for b in [0.0, t * eps_c] {
        // A discontinuity would be at least E |ε_n^c| = 2 MPa; the slopes
        // bound the change over the 2d-wide bracket.
        let d = 1e-15;
        let (lo, hi) = (g.normal(b - d, 0.0), g.normal(b + d, 0.0));
        let bound = 2.0 * d * (g.contact_stiffness() + g.crushing_stiffness());
        assert!(
            (lo.sigma - hi.sigma).abs() <= bound,
            "jump at {b}: {} vs {}",
            lo.sigma,
            hi.sigma
        );
    }
    assert_relative_eq!(g.shear_stiffness(8.0e8), 8.0e8 / t, max_relative = 1e-15);
    // Smooth surfaces: no crushing stage.
    let s = GhaboussiNormal::smooth(2.0e11, 1.0e-3).unwrap();
    assert_eq!(s.normal(-1e-9, 0.0).stage, NormalStage::Contact);
    assert_relative_eq!(
        s.normal(-1e-9, 0.0).sigma,
        -2.0e11 / 1.0e-3 * 1e-9,
        max_relative = 1e-14
    );
}

#[test]
fn touching_faces_are_closed() {
    // ε_n = 0 exactly: no traction yet, but the closed branch's stiffness,
    // so a Newton solver starting from touching bodies has support.
    let smooth = GhaboussiNormal::smooth(2.0e11, 1.0e-3).unwrap();
    let r = smooth.normal(0.0, 0.0);
    assert_eq!((r.sigma, r.stage), (-0.0, NormalStage::Contact));
    assert_eq!(r.stiffness, smooth.contact_stiffness());
    let rough = rough_ghaboussi();
    let r = rough.normal(0.0, 0.0);
    assert_eq!((r.sigma, r.stage), (-0.0, NormalStage::Crushing));
    assert_eq!(r.stiffness, rough.crushing_stiffness());
    // The smallest opening separates.
    assert_eq!(smooth.normal(1e-300, 0.0).stage, NormalStage::Separation);
    assert_eq!(rough.normal(1e-300, 0.0).stage, NormalStage::Separation);
    // Mohr–Coulomb at touching: the shear spring and the cohesion act.
    let law = MohrCoulomb::new(rough, 3.0e11, 0.4e6, 0.5).unwrap();
    let r = law.evaluate(&Vector2::new(2.0e-6, 0.0), &JointState::default());
    assert_eq!(r.status, ContactStatus::Slip);
    assert_relative_eq!(r.traction.x, 0.4e6, max_relative = 1e-14);
}

#[test]
fn normal_law_fd_tangent_in_every_stage() {
    let g = rough_ghaboussi();
    let lin = LinearNormal::new(5.0e11).unwrap();
    let mut worst: f64 = 0.0;
    for (du, lambda, stage) in [
        (0.3e-6, 0.0, NormalStage::Separation),
        (-0.5e-6, 0.0, NormalStage::Crushing),
        (-1.7e-6, 0.0, NormalStage::Contact),
        (-0.2e-6, 2.0e8, NormalStage::Contact), // multiplier extends contact
    ] {
        let h = 1e-12;
        let r = g.normal(du, lambda);
        assert_eq!(r.stage, stage);
        let fd = (g.normal(du + h, lambda).sigma - g.normal(du - h, lambda).sigma) / (2.0 * h);
        let err = (fd - r.stiffness).abs() / g.contact_stiffness();
        worst = worst.max(err);
        assert!(err < FD_TOL, "{stage:?}: {fd} vs {}", r.stiffness);
    }
    let fd = (lin.normal(1e-6 + 1e-12, 3.0).sigma - lin.normal(1e-6 - 1e-12, 3.0).sigma) / 2e-12;
    let err = (fd - 5.0e11).abs() / 5.0e11;
    worst = worst.max(err);
    assert!(err < FD_TOL);
    println!("normal laws FD tangent error (worst) {worst:.2e}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

    /// Mohr–Coulomb with a rough Ghaboussi normal law, random jumps, slips
    /// and multipliers: tangent = FD tangent wherever no kink is near.
    #[test]
    fn mohr_coulomb_ghaboussi_fd_tangent(
        dut in -4.0e-6..4.0e-6_f64,
        dun in -3.0e-6..1.0e-6_f64,
        slip in -3.0e-6..3.0e-6_f64,
        lambda in prop_oneof![Just(0.0), 0.0..2.0e6_f64],
        c in prop_oneof![Just(0.0), 0.0..2.0e6_f64],
        phi_deg in 0.0..60.0_f64,
    ) {
        let law = MohrCoulomb::new(rough_ghaboussi(), 3.0e11, c, phi_deg.to_radians()).unwrap();
        let state = JointState { slip, accumulated_slip: 0.0, lambda_n: lambda, ..Default::default() };
        let j = Vector2::new(dut, dun);
        let h = 1e-13;
        prop_assume!(same_regime(&law, &j, &state, 10.0 * h));
        let e = fd_error(&law, &j, &state, h, law.k_s());
        prop_assert!(e < FD_TOL, "error {e:e} at {j:?} {state:?}");
    }

    /// Invariants of the return mapping for any jump and committed state:
    /// the traction is admissible (|τ| ≤ s), the elastic relation
    /// τ = k_s (Δu_t − g_s) holds with the updated slip whenever the faces
    /// are closed, slip only grows in the direction of τ, and the
    /// accumulated slip grows by exactly |Δg_s|.
    #[test]
    fn mohr_coulomb_return_mapping_invariants(
        dut in -1.0e-4..1.0e-4_f64,
        dun in -3.0e-6..1.0e-6_f64,
        slip in -5.0e-5..5.0e-5_f64,
        c in 0.0..2.0e6_f64,
        phi_deg in 0.0..60.0_f64,
    ) {
        let law = MohrCoulomb::new(rough_ghaboussi(), 3.0e11, c, phi_deg.to_radians()).unwrap();
        let st = JointState { slip, accumulated_slip: 1.0e-3, lambda_n: 0.0, ..Default::default() };
        let r = law.evaluate(&Vector2::new(dut, dun), &st);
        let s = law.strength(r.traction.y);
        prop_assert!(r.traction.x.abs() <= s * (1.0 + 1e-12) + 1e-9);
        if r.status != ContactStatus::Open {
            prop_assert!((r.traction.x - law.k_s() * (dut - r.state.slip)).abs() <= 1e-9 * s.max(1.0));
            let dg = r.state.slip - slip;
            prop_assert!(dg * r.traction.x >= 0.0);
            prop_assert!((r.state.accumulated_slip - 1.0e-3 - dg.abs()).abs() <= 1e-15);
        } else {
            prop_assert_eq!(r.traction, Vector2::zeros());
        }
    }

    /// Mohr–Coulomb with a bilateral normal spring (tension allowed): the
    /// strength decreases in tension down to the apex.
    #[test]
    fn mohr_coulomb_linear_normal_fd_tangent(
        dut in -4.0e-6..4.0e-6_f64,
        dun in -3.0e-6..3.0e-6_f64,
        slip in -3.0e-6..3.0e-6_f64,
        c in 0.0..2.0e6_f64,
        phi_deg in 0.0..60.0_f64,
    ) {
        let law = MohrCoulomb::new(LinearNormal::new(1.0e12).unwrap(), 3.0e11, c, phi_deg.to_radians()).unwrap();
        let state = JointState { slip, ..Default::default() };
        let j = Vector2::new(dut, dun);
        let h = 1e-13;
        prop_assume!(same_regime(&law, &j, &state, 10.0 * h));
        let e = fd_error(&law, &j, &state, h, law.k_s());
        prop_assert!(e < FD_TOL, "error {e:e} at {j:?} {state:?}");
    }
}

#[test]
fn slipping_tangent_is_non_symmetric_and_matches_fd() {
    let phi = 30f64.to_radians();
    let law = MohrCoulomb::new(rough_ghaboussi(), 3.0e11, 0.5e6, phi).unwrap();
    let state = JointState::default();
    // Contact stage, large forward shear: slipping.
    let j = Vector2::new(500.0e-6, -1.6e-6);
    let r = law.evaluate(&j, &state);
    assert_eq!(r.status, ContactStatus::Slip);
    let k_n = law.normal_law().normal(j.y, 0.0).stiffness;
    // ∂τ/∂Δu_t = 0, ∂τ/∂Δu_n = −tan φ k_n (more pressure → more strength).
    assert_eq!(r.tangent[(0, 0)], 0.0);
    assert_relative_eq!(r.tangent[(0, 1)], -phi.tan() * k_n, max_relative = 1e-14);
    assert_eq!(r.tangent[(1, 0)], 0.0);
    assert!((r.tangent - r.tangent.transpose()).norm() > 0.1 * k_n);
    let e_fwd = fd_error(&law, &j, &state, 1e-13, law.k_s());
    // Backward slip flips the sign of the coupling term.
    let jb = Vector2::new(-20.0e-6, -0.5e-6); // crushing stage
    let rb = law.evaluate(&jb, &state);
    assert_eq!(rb.status, ContactStatus::Slip);
    assert_relative_eq!(
        rb.tangent[(0, 1)],
        phi.tan() * law.normal_law().crushing_stiffness(),
        max_relative = 1e-14
    );
    let e_bwd = fd_error(&law, &jb, &state, 1e-13, law.k_s());
    println!("Mohr-Coulomb slipping FD tangent error: forward {e_fwd:.2e}, backward {e_bwd:.2e}");
    assert!(e_fwd < FD_TOL && e_bwd < FD_TOL, "{e_fwd} {e_bwd}");
    // Stick tangent is diagonal and matches FD too.
    let js = Vector2::new(1.0e-7, -1.6e-6);
    let rs = law.evaluate(&js, &state);
    assert_eq!(rs.status, ContactStatus::Stick);
    assert_eq!(rs.tangent, Matrix2::new(law.k_s(), 0.0, 0.0, k_n));
    let e_stick = fd_error(&law, &js, &state, 1e-13, law.k_s());
    println!("Mohr-Coulomb stick FD tangent error {e_stick:.2e}");
    assert!(e_stick < FD_TOL);
}

#[test]
fn elastic_joint_fd_and_open_release() {
    let law = ElasticJoint::new(rough_ghaboussi(), 3.0e11).unwrap();
    let s = JointState::default();
    for j in [Vector2::new(1e-6, -0.5e-6), Vector2::new(-2e-6, -1.5e-6)] {
        let r = law.evaluate(&j, &s);
        assert_eq!(r.status, ContactStatus::Stick);
        assert_relative_eq!(r.traction.x, 3.0e11 * j.x, max_relative = 1e-14);
        let e = fd_error(&law, &j, &s, 1e-13, law.k_s());
        assert!(e < FD_TOL, "{e}");
    }
    // Separation stage: k_n = k_s = 0 and zero traction.
    let r = law.evaluate(&Vector2::new(5e-6, 1e-7), &s);
    assert_eq!(r.status, ContactStatus::Open);
    assert_eq!(r.traction, Vector2::zeros());
    assert_eq!(r.tangent, Matrix2::zeros());
}

fn friction_law(c: f64, phi_deg: f64) -> PaperJoint {
    PaperJoint::new(
        GhaboussiNormal::penalty(K).unwrap(),
        K,
        c,
        phi_deg.to_radians(),
    )
    .unwrap()
}

#[test]
fn stick_below_the_limit_and_on_the_limit_when_slipping() {
    let (c, phi) = (0.2e6, 25.0_f64);
    let law = friction_law(c, phi);
    let dun = -2.0e-6; // σ_c = 2 MPa
    let limit = c + 2.0e6 * phi.to_radians().tan();
    let s0 = JointState::default();
    for frac in [-0.99, -0.5, 0.0, 0.3, 0.99] {
        let dut = frac * limit / K;
        let r = law.evaluate(&Vector2::new(dut, dun), &s0);
        assert_eq!(r.status, ContactStatus::Stick);
        assert_relative_eq!(r.traction.x, K * dut, max_relative = 1e-14);
        assert_eq!(r.state, s0);
    }
    for over in [1.01, 2.0, 50.0] {
        for sign in [1.0, -1.0] {
            let dut = sign * over * limit / K;
            let r = law.evaluate(&Vector2::new(dut, dun), &s0);
            assert_eq!(r.status, ContactStatus::Slip);
            assert_relative_eq!(r.traction.x, sign * limit, max_relative = 1e-14);
            // Elastic part + plastic slip = total tangential jump.
            assert_relative_eq!(r.traction.x / K + r.state.slip, dut, max_relative = 1e-12);
            assert_relative_eq!(
                r.state.accumulated_slip,
                r.state.slip.abs(),
                max_relative = 1e-14
            );
        }
    }
}

#[test]
fn a_point_without_strength_never_sticks() {
    // frictionless (φ = 0, c = 0), and frictional at zero frozen pressure:
    // τ = 0 whatever the tangential jump, status slip — also when the
    // trial traction is exactly 0 (Δu_t equal to the committed slip),
    // where a stick status used to flip with round-off; the tangent is
    // the stick one there (the one-sided derivative into the elastic
    // side), 0 elsewhere
    let dun = -1.0e-6;
    let frozen = friction_law(0.0, 30.0).with_friction_bound(FrictionBound::Frozen);
    let laws = [friction_law(0.0, 0.0), frozen];
    for law in &laws {
        for slip in [0.0, 3.0e-7, -2.0e-9] {
            let committed = JointState {
                slip,
                ..JointState::default()
            };
            for dut in [slip, slip + 1e-12, slip - 4e-6] {
                let r = law.evaluate(&Vector2::new(dut, dun), &committed);
                assert_eq!(r.status, ContactStatus::Slip, "{law:?} at Δu_t = {dut}");
                assert_eq!(r.traction.x, 0.0);
                let stick_side = if dut == slip { K } else { 0.0 };
                assert_eq!(r.tangent[(0, 0)], stick_side);
                assert_relative_eq!(r.slip, dut, epsilon = 1e-21, max_relative = 1e-14);
            }
        }
    }
}

#[test]
fn slip_is_irreversible_on_unloading() {
    let phi = 30.0_f64;
    let law = friction_law(0.0, phi);
    let dun = -1.0e-6; // σ_c = 1 MPa
    let limit = 1.0e6 * phi.to_radians().tan();
    // Load in 10 increments to 5× the elastic limit, committing each.
    let mut state = JointState::default();
    let peak = 5.0 * limit / K;
    for i in 1..=10 {
        let r = law.evaluate(&Vector2::new(peak * i as f64 / 10.0, dun), &state);
        state = r.state;
    }
    let slip = state.slip;
    assert_relative_eq!(slip, peak - limit / K, max_relative = 1e-12);
    // Unload to zero jump: the slip remains, the traction reverses (stick).
    let r = law.evaluate(&Vector2::new(0.0, dun), &state);
    assert_eq!(r.status, ContactStatus::Slip); // |−K·slip| = 4·limit > limit
    let r_half = law.evaluate(&Vector2::new(peak - 1.5 * limit / K, dun), &state);
    assert_eq!(r_half.status, ContactStatus::Stick);
    assert_relative_eq!(r_half.traction.x, -0.5 * limit, max_relative = 1e-12);
    assert_eq!(r_half.state.slip, slip);
    // Full unloading reverses the slip by exactly (peak − 2·limit/K).
    assert_relative_eq!(r.traction.x, -limit, max_relative = 1e-12);
    assert_relative_eq!(r.state.slip, limit / K, max_relative = 1e-9);
    assert_relative_eq!(
        r.state.accumulated_slip,
        slip + (slip - limit / K),
        max_relative = 1e-12
    );
}

#[test]
fn zero_traction_when_open_even_with_cohesion() {
    let law = friction_law(1.0e6, 35.0);
    let committed = JointState {
        slip: 2.0e-6,
        accumulated_slip: 3.0e-6,
        lambda_n: 0.0,
        friction_pressure: 0.0,
        ..Default::default()
    };
    let r = law.evaluate(&Vector2::new(-7.0e-6, 1.0e-8), &committed);
    assert_eq!(r.status, ContactStatus::Open);
    assert_eq!(r.traction, Vector2::zeros());
    assert_eq!(r.tangent, Matrix2::zeros());
    // Faces slide freely: the spring is unstretched on reclosing, and the
    // free sliding is not dissipative slip.
    assert_eq!(r.state.slip, -7.0e-6);
    assert_eq!(r.state.accumulated_slip, 3.0e-6);
    let re = law.evaluate(&Vector2::new(-7.0e-6, -1.0e-9), &r.state);
    assert_eq!(re.status, ContactStatus::Stick);
    assert_eq!(re.traction.x, 0.0);
}

#[test]
fn cohesion_gives_strength_at_zero_pressure() {
    let c = 0.8e6;
    // Bilateral normal: at Δu_n = 0 the pressure is zero, strength = c.
    let law = MohrCoulomb::new(LinearNormal::new(K).unwrap(), K, c, 20f64.to_radians()).unwrap();
    let s = JointState::default();
    let r = law.evaluate(&Vector2::new(0.9 * c / K, 0.0), &s);
    assert_eq!(r.status, ContactStatus::Stick);
    let r = law.evaluate(&Vector2::new(3.0 * c / K, 0.0), &s);
    assert_eq!(r.status, ContactStatus::Slip);
    assert_relative_eq!(r.traction.x, c, max_relative = 1e-14);
    // Pure cohesion (φ = 0, Tresca): strength independent of pressure.
    let tresca = MohrCoulomb::new(LinearNormal::new(K).unwrap(), K, c, 0.0).unwrap();
    for dun in [-5e-6, 0.0, 5e-6] {
        let r = tresca.evaluate(&Vector2::new(-1e-5, dun), &s);
        assert_relative_eq!(r.traction.x, -c, max_relative = 1e-14);
        assert_eq!(r.tangent[(0, 1)], 0.0);
    }
}

#[test]
fn tension_cut_off_at_the_apex() {
    let (c, phi) = (0.6e6, 30f64.to_radians());
    let law = MohrCoulomb::new(LinearNormal::new(K).unwrap(), K, c, phi).unwrap();
    let s = JointState::default();
    let apex = c / phi.tan(); // σ at which the strength vanishes
    // Below the apex the strength falls linearly with tension.
    let sigma = 0.5 * apex;
    let r = law.evaluate(&Vector2::new(1e-4, sigma / K), &s);
    assert_eq!(r.status, ContactStatus::Slip);
    assert_relative_eq!(r.traction.x, c - sigma * phi.tan(), max_relative = 1e-12);
    // Beyond the apex: no shear strength at all, and no coupling term.
    for sigma in [1.01 * apex, 3.0 * apex] {
        let r = law.evaluate(&Vector2::new(1e-4, sigma / K), &s);
        assert_eq!(r.traction.x, 0.0);
        assert_eq!(r.tangent.row(0).norm(), 0.0);
        assert_relative_eq!(r.traction.y, sigma, max_relative = 1e-12);
    }
    // The paper's joint (unilateral) cuts tension off at zero.
    let paper = friction_law(c, 30.0);
    let r = paper.evaluate(&Vector2::new(1e-4, 1e-6), &s);
    assert_eq!(
        (r.traction, r.status),
        (Vector2::zeros(), ContactStatus::Open)
    );
}

#[test]
fn augmented_lagrangian_update_removes_penetration_dependence() {
    let g = GhaboussiNormal::penalty(K).unwrap();
    // Converged penetration 1 µm under λ = 0: new λ = pressure 1 MPa.
    assert_relative_eq!(
        g.updated_multiplier(-1e-6, 0.0),
        1.0e6,
        max_relative = 1e-14
    );
    // With λ = 1 MPa the pressure at zero penetration is 1 MPa ...
    let r = g.normal(0.0, 1.0e6);
    assert_eq!(r.stage, NormalStage::Contact);
    assert_relative_eq!(r.sigma, -1.0e6, max_relative = 1e-14);
    // ... and a gap larger than λ/k releases the contact.
    assert_eq!(g.normal(2e-6, 1.0e6).stage, NormalStage::Separation);
    assert_eq!(g.updated_multiplier(2e-6, 1.0e6), 0.0);
    // Through the law: augment keeps the slip, changes λ only.
    let law = friction_law(0.0, 30.0);
    let st = JointState {
        slip: 1e-6,
        accumulated_slip: 2e-6,
        lambda_n: 0.5e6,
        friction_pressure: 0.0,
        ..Default::default()
    };
    let a = law.augment(&Vector2::new(0.0, -0.25e-6), &st);
    assert_relative_eq!(a.state.lambda_n, 0.75e6, max_relative = 1e-14);
    assert_relative_eq!(a.multiplier_change, 0.25e6, max_relative = 1e-12);
    assert_eq!(
        (a.state.slip, a.state.accumulated_slip),
        (st.slip, st.accumulated_slip)
    );
    // evaluate never changes λ.
    assert_eq!(
        law.evaluate(&Vector2::new(1e-5, -1e-6), &st).state.lambda_n,
        st.lambda_n
    );
    // Linear joint has no multiplier: unchanged, zero change.
    let lj = LinearJoint::new(1.0, 1.0).unwrap();
    assert_eq!(
        lj.augment(&Vector2::new(1.0, 1.0), &()).multiplier_change,
        0.0
    );
}

#[test]
fn invalid_parameters_are_typed_errors() {
    assert_eq!(
        LinearJoint::new(-1.0, 1.0),
        Err(LawError::NegativeStiffness {
            name: "k_s",
            value: -1.0
        })
    );
    assert!(matches!(
        LinearJoint::new(1.0, f64::NAN),
        Err(LawError::NonFinite { name: "k_n", .. })
    ));
    assert_eq!(
        GhaboussiNormal::new(1e9, 1e11, 0.0, 0.0),
        Err(LawError::NonPositiveThickness(0.0))
    );
    assert_eq!(
        GhaboussiNormal::new(1e9, 1e11, 1e-3, 1e-3),
        Err(LawError::PositiveCrushingStrain(1e-3))
    );
    assert_eq!(
        GhaboussiNormal::new(-1e9, 1e11, 1e-3, 0.0),
        Err(LawError::NegativeStiffness {
            name: "E",
            value: -1e9
        })
    );
    assert_eq!(
        GhaboussiNormal::new(1e9, 0.0, 1e-3, 0.0),
        Err(LawError::NonPositiveStiffness {
            name: "E_f",
            value: 0.0
        })
    );
    assert!(LinearNormal::new(-2.0).is_err());
    let g = GhaboussiNormal::penalty(K).unwrap();
    assert!(matches!(
        MohrCoulomb::new(g, K, 0.0, 90f64.to_radians()),
        Err(LawError::FrictionAngle { .. })
    ));
    assert!(matches!(
        MohrCoulomb::new(g, K, 0.0, -0.1),
        Err(LawError::FrictionAngle { .. })
    ));
    assert_eq!(
        MohrCoulomb::new(g, K, -1.0, 0.3),
        Err(LawError::NegativeCohesion(-1.0))
    );
    assert!(matches!(
        MohrCoulomb::new(g, 0.0, 0.0, 0.3),
        Err(LawError::NonPositiveStiffness { name: "k_s", .. })
    ));
    assert!(ElasticJoint::new(g, -1.0).is_err());
    assert_eq!(
        default_penalty(2e11, 0.0),
        Err(LawError::NonPositiveElementSize(0.0))
    );
    assert!(default_penalty(-2e11, 1e-3).is_err());
    // Messages name the parameter.
    let msg = MohrCoulomb::new(g, K, 0.0, 1.6).unwrap_err().to_string();
    assert!(
        msg.contains("friction angle") && msg.contains("91.67"),
        "{msg}"
    );
}

#[test]
fn default_penalty_is_beta_e_over_h() {
    let (e, h) = (207.0e9, 2.0e-3);
    assert_relative_eq!(
        default_penalty(e, h).unwrap(),
        tecon_contact::DEFAULT_PENALTY_FACTOR * e / h
    );
    let law = PaperJoint::with_default_penalty(e, h, 0.0, 0.3).unwrap();
    assert_relative_eq!(
        law.normal_law().contact_stiffness(),
        10.0 * e / h,
        max_relative = 1e-14
    );
    assert_relative_eq!(law.k_s(), 10.0 * e / h, max_relative = 1e-14);
}

#[test]
fn laws_and_states_are_thread_safe_plain_data() {
    fn check<L: ContactLaw + Clone + Send + Sync + 'static>() {}
    check::<LinearJoint>();
    check::<PaperJoint>();
    check::<MohrCoulomb<LinearNormal>>();
    check::<ElasticJoint>();
}

#[test]
fn frozen_bound_is_tresca_with_symmetric_tangent_and_its_fixed_point_is_coulomb() {
    let (c, phi) = (0.1e6, 30.0_f64);
    let coupled = friction_law(c, phi);
    let frozen = coupled.with_friction_bound(FrictionBound::Frozen);
    assert_eq!(coupled.friction_bound(), FrictionBound::Coupled);
    assert_eq!(frozen.friction_bound(), FrictionBound::Frozen);
    let jump = Vector2::new(30e-6, -2e-6); // closed and sheared past the limit
    let p = K * 2e-6;
    // a stored pressure p_f sets the limit c + p_f tan φ, whatever the jump
    let st = JointState {
        friction_pressure: 0.5 * p,
        ..Default::default()
    };
    let r = frozen.evaluate(&jump, &st);
    assert_eq!(r.status, ContactStatus::Slip);
    let tan = phi.to_radians().tan();
    assert_relative_eq!(r.traction.x, c + 0.5 * p * tan, max_relative = 1e-14);
    assert_relative_eq!(r.traction.y, -p, max_relative = 1e-14);
    // the tangent is symmetric (no shear–normal coupling) and exact
    assert_eq!(r.tangent[(0, 1)], 0.0);
    assert_eq!(r.tangent[(1, 0)], 0.0);
    assert!(fd_error(&frozen, &jump, &st, 1e-13, K) < FD_TOL);
    // one update stores the pressure; then the response is Coulomb's
    let a = frozen.update_friction(&jump, &st);
    assert_relative_eq!(a.state.friction_pressure, p, max_relative = 1e-14);
    assert_relative_eq!(a.multiplier_change, 0.5 * p * tan, max_relative = 1e-12);
    let r_fixed = frozen.evaluate(&jump, &a.state);
    let r_coulomb = coupled.evaluate(&jump, &a.state);
    assert_eq!(r_fixed.traction, r_coulomb.traction);
    assert_eq!(r_fixed.state.slip, r_coulomb.state.slip);
    assert_eq!(
        frozen.update_friction(&jump, &a.state).multiplier_change,
        0.0
    );
    // open faces store zero pressure; the coupled law never changes
    let open = frozen.update_friction(&Vector2::new(0.0, 1e-6), &a.state);
    assert_eq!(open.state.friction_pressure, 0.0);
    let none = coupled.update_friction(&jump, &st);
    assert_eq!((none.state, none.multiplier_change), (st, 0.0));
}

#[test]
fn secant_slip_changes_only_the_tangent_of_a_slipping_frozen_point() {
    let frozen = friction_law(0.1e6, 30.0).with_friction_bound(FrictionBound::Frozen);
    let jump = Vector2::new(30e-6, -2e-6);
    let st = JointState {
        friction_pressure: K * 1e-6,
        ..Default::default()
    };
    let damped = JointState {
        secant_slip: true,
        ..st
    };
    let (exact, secant) = (frozen.evaluate(&jump, &st), frozen.evaluate(&jump, &damped));
    assert_eq!(exact.status, ContactStatus::Slip);
    assert_eq!(
        (exact.traction, exact.status),
        (secant.traction, secant.status)
    );
    assert_eq!(exact.state.slip, secant.state.slip);
    assert_eq!(exact.tangent[(0, 0)], 0.0);
    // k_s s / |τ_trial|: the slope of the chord from τ = 0 to the limit
    let s = secant.traction.x.abs();
    let tau_trial = frozen.k_s() * jump.x;
    assert_relative_eq!(
        secant.tangent[(0, 0)],
        frozen.k_s() * s / tau_trial,
        max_relative = 1e-14
    );
    assert!(secant.tangent[(0, 0)] > 0.0 && secant.tangent[(0, 0)] < frozen.k_s());
    // the normal row and the shear–normal terms are those of the exact tangent
    assert_eq!(exact.tangent[(1, 1)], secant.tangent[(1, 1)]);
    assert_eq!(secant.tangent[(0, 1)], 0.0);
    // a sticking point keeps k_s
    let stick = frozen.evaluate(&Vector2::new(1e-9, -2e-6), &damped);
    assert_eq!(stick.status, ContactStatus::Stick);
    assert_eq!(stick.tangent[(0, 0)], frozen.k_s());
}

/// The state a solver uses to try a sticking point as slipping: at the same
/// jump it slips, in the direction of its shear, with the traction on the
/// limit and the slipping tangent; nothing else of the state changes. No
/// such state where the law has no frozen limit, the point is open or its
/// shear is 0.
#[test]
fn a_slipping_state_puts_a_sticking_point_on_its_limit() {
    let frozen = friction_law(0.1e6, 30.0).with_friction_bound(FrictionBound::Frozen);
    let st = JointState {
        friction_pressure: 1.0e6,
        slip: 1e-6,
        lambda_n: 5.0,
        ..Default::default()
    };
    let s = frozen.strength(-st.friction_pressure);
    for shear in [1e-9, -2e-8] {
        let jump = Vector2::new(st.slip + shear, -2e-6);
        let sticking = frozen.evaluate(&jump, &st);
        assert_eq!(sticking.status, ContactStatus::Stick);
        let forced = frozen.slipping_state(&jump, &st).unwrap();
        assert_eq!(
            JointState {
                slip: st.slip,
                ..forced
            },
            st
        );
        let r = frozen.evaluate(&jump, &forced);
        assert_eq!(r.status, ContactStatus::Slip);
        assert_relative_eq!(r.traction.x, shear.signum() * s, max_relative = 1e-14);
        assert_eq!(r.traction.y, sticking.traction.y);
        assert_eq!(r.tangent[(0, 0)], 0.0);
        assert_eq!(r.tangent[(1, 1)], sticking.tangent[(1, 1)]);
    }
    // no shear: no direction to slip in
    assert!(
        frozen
            .slipping_state(&Vector2::new(st.slip, -2e-6), &st)
            .is_none()
    );
    // open, or a coupled limit: none
    assert!(
        frozen
            .slipping_state(&Vector2::new(2e-6, 1e-3), &st)
            .is_none()
    );
    let coupled = friction_law(0.1e6, 30.0);
    assert!(
        coupled
            .slipping_state(&Vector2::new(2e-6, -2e-6), &st)
            .is_none()
    );
}

/// An open point sliding on its frozen limit takes the tangents of a closed
/// slipping one: the stick stiffness k_s within round-off of the kink, the
/// secant k_s s/|τ_trial| when the solver damps it, 0 otherwise; the
/// traction and the slip never change.
#[test]
fn an_open_point_sliding_on_a_frozen_limit_takes_the_slip_tangents() {
    let frozen = friction_law(0.1e6, 30.0).with_friction_bound(FrictionBound::Frozen);
    let st = JointState {
        friction_pressure: 2.0e6,
        ..Default::default()
    };
    // (the cohesion held: the point was closed at the last update)
    let s_open = 0.1e6 + 2.0e6 * 30.0_f64.to_radians().tan();
    let k_s = frozen.k_s();
    // opening 1 µm, sliding 3 × the elastic shear reach
    let jump = Vector2::new(3.0 * s_open / k_s, 1e-6);
    let exact = frozen.evaluate(&jump, &st);
    assert_eq!(exact.status, ContactStatus::Open);
    assert_relative_eq!(exact.traction.x, s_open, max_relative = 1e-14);
    assert_eq!(exact.tangent[(0, 0)], 0.0);
    let damped = frozen.evaluate(
        &jump,
        &JointState {
            secant_slip: true,
            ..st
        },
    );
    assert_eq!(
        (damped.traction, damped.state.slip),
        (exact.traction, exact.state.slip)
    );
    assert_relative_eq!(damped.tangent[(0, 0)], k_s / 3.0, max_relative = 1e-12);
    // on the limit to round-off: the stick side of the kink
    let at_kink = frozen.evaluate(&Vector2::new(s_open / k_s * (1.0 + 1e-9), 1e-6), &st);
    assert_eq!(at_kink.tangent[(0, 0)], k_s);
    assert_relative_eq!(at_kink.traction.x, s_open, max_relative = 1e-14);
}

/// Frozen limit, stored pressure p_f > 0 and the cohesion held (the point
/// was closed at the last update): the whole limit c + p_f tan φ stays on
/// while the faces open, so the shear traction is continuous across the
/// opening; the open point's tangent matches finite differences in stick
/// and in slip. The update after which the point is open stores its
/// pressure, 0, and takes its cohesion: then it carries nothing.
#[test]
fn frozen_limit_stays_on_while_opening() {
    let (c, phi) = (0.1e6, 30.0_f64);
    let frozen = friction_law(c, phi).with_friction_bound(FrictionBound::Frozen);
    let tan = phi.to_radians().tan();
    let p_f = 2.0e6;
    let limit = c + p_f * tan;
    let st = JointState {
        friction_pressure: p_f,
        slip: 1e-6,
        ..Default::default()
    };
    // sheared past the limit: slip on both sides of the opening
    let du_t = 1e-6 + 5.0 * limit / frozen.k_s();
    let closed = frozen.evaluate(&Vector2::new(du_t, -1e-15), &st);
    let open = frozen.evaluate(&Vector2::new(du_t, 1e-15), &st);
    assert_eq!(closed.status, ContactStatus::Slip);
    assert_eq!(open.status, ContactStatus::Open);
    assert_relative_eq!(closed.traction.x, limit, max_relative = 1e-14);
    assert_eq!(open.traction.x, closed.traction.x);
    // open, slipping: τ on the limit, slip returned to it, exact tangent
    let j_slip = Vector2::new(du_t, 1e-6);
    let r = frozen.evaluate(&j_slip, &st);
    assert_eq!((r.status, r.traction.y), (ContactStatus::Open, 0.0));
    assert_relative_eq!(
        r.state.slip,
        du_t - limit / frozen.k_s(),
        max_relative = 1e-12
    );
    assert!(fd_error(&frozen, &j_slip, &st, 1e-13, K) < FD_TOL);
    assert_eq!(r.tangent, Matrix2::zeros());
    // open, sticking: τ = k_s (Δu_t − g_s), tangent k_s
    let j_stick = Vector2::new(1e-6 + 0.5 * limit / frozen.k_s(), 1e-6);
    let r = frozen.evaluate(&j_stick, &st);
    assert_eq!(r.status, ContactStatus::Open);
    assert_relative_eq!(r.traction.x, 0.5 * limit, max_relative = 1e-9);
    assert_eq!(r.tangent[(0, 0)], frozen.k_s());
    assert!(fd_error(&frozen, &j_stick, &st, 1e-13, K) < FD_TOL);
    // the update stores the open point's pressure, 0, and its cohesion is
    // gone: then it carries nothing; the change is the limit's, p_f tan φ + c
    let a = frozen.update_friction(&j_slip, &st);
    assert_eq!(a.state.friction_pressure, 0.0);
    assert!(a.state.cohesion_lost);
    assert_relative_eq!(a.multiplier_change, limit, max_relative = 1e-14);
    let r = frozen.evaluate(&j_slip, &a.state);
    assert_eq!(r.traction, Vector2::zeros());
    assert_eq!(r.state.slip, j_slip.x);
    // the coupled law: open means no traction
    let coupled = friction_law(c, phi);
    assert_eq!(coupled.evaluate(&j_slip, &st).traction, Vector2::zeros());
}

/// Debonding: the cohesion of a point open at a friction update is gone
/// for good. Closed again, it has the friction limit p tan φ alone, in the
/// frozen and in the coupled law, and later updates do not give the
/// cohesion back (a bond that healed when the faces touched again let a
/// point at the edge of a lift-off flip for ever between open without
/// shear and closed with the cohesion: the vessel with c = 0.1 MPa on g0
/// found no equilibrium). A closed point's update keeps its cohesion, and
/// without cohesion the update is the friction-pressure update alone.
#[test]
fn a_point_open_at_an_update_loses_its_cohesion_for_good() {
    let (c, phi) = (0.1e6, 30.0_f64);
    let tan = phi.to_radians().tan();
    let frozen = friction_law(c, phi).with_friction_bound(FrictionBound::Frozen);
    let coupled = friction_law(c, phi);
    let st = JointState {
        friction_pressure: 1.0e6,
        ..Default::default()
    };
    let closing = Vector2::new(0.0, -1e-6);
    let p = -frozen.normal_law().normal(closing.y, 0.0).sigma;
    // closed at the update: the cohesion stays
    let kept = frozen.update_friction(&closing, &st);
    assert!(!kept.state.cohesion_lost);
    assert_relative_eq!(
        kept.multiplier_change,
        tan * (p - 1.0e6).abs(),
        max_relative = 1e-14
    );
    // open at the update: gone
    let lost = frozen.update_friction(&Vector2::new(0.0, 1e-6), &st).state;
    assert!(lost.cohesion_lost);
    // closed again, sheared far: on the friction limit alone
    let sheared = Vector2::new(1.0, -1e-6);
    let fr = frozen.evaluate(&sheared, &lost);
    assert_eq!(fr.status, ContactStatus::Slip);
    assert_relative_eq!(
        fr.traction.x,
        lost.friction_pressure * tan,
        max_relative = 1e-14
    );
    let co = coupled.evaluate(&sheared, &lost);
    assert_relative_eq!(co.traction.x, -co.traction.y * tan, max_relative = 1e-14);
    let bonded = coupled.evaluate(&sheared, &st);
    assert_relative_eq!(
        bonded.traction.x,
        c - bonded.traction.y * tan,
        max_relative = 1e-14
    );
    // a later update with the faces closed does not bring it back, and
    // changes the limit by its pressure part alone
    let again = frozen.update_friction(&closing, &lost);
    assert!(again.state.cohesion_lost);
    assert_relative_eq!(
        again.multiplier_change,
        tan * (p - lost.friction_pressure).abs(),
        max_relative = 1e-14
    );
    // no cohesion: no bond to break (the flag stays unset), and the flag
    // would change nothing
    let plain = friction_law(0.0, phi).with_friction_bound(FrictionBound::Frozen);
    let a = plain.update_friction(&Vector2::new(0.0, 1e-6), &st);
    assert_eq!(a.multiplier_change, tan * 1.0e6);
    assert!(!a.state.cohesion_lost);
    let flagged = JointState {
        cohesion_lost: true,
        ..st
    };
    for j in [Vector2::new(1.0, 1e-6), Vector2::new(1.0, -1e-6)] {
        let (x, y) = (plain.evaluate(&j, &st), plain.evaluate(&j, &flagged));
        assert_eq!(
            (x.traction, x.tangent, x.status),
            (y.traction, y.tangent, y.status)
        );
        assert_eq!(x.state.slip, y.state.slip);
    }
}

/// The contact branch continued into tension (`normal_closed`, the branch a
/// Newton prediction tries for a point it expects to close): equal to the
/// law wherever the law is in contact, and beyond the closure the linear
/// continuation of the contact branch (a tensile traction with the contact
/// stiffness), where the law itself is separated.
#[test]
fn the_closed_branch_continues_the_contact_branch_into_tension() {
    for law in [
        GhaboussiNormal::smooth(2.0e11, 1.0e-3).unwrap(),
        rough_ghaboussi(),
    ] {
        let lambda = 3.0e5;
        // where the contact spring acts (beyond the crushing range of the
        // rough law): the same response
        let mut compared = 0;
        for du_n in [-3.0e-3, -2.0e-3, -2.0e-6, -5.0e-7, -1.0e-9] {
            let (a, b) = (law.normal(du_n, lambda), law.normal_closed(du_n, lambda));
            if a.stage != NormalStage::Contact {
                continue;
            }
            compared += 1;
            assert_relative_eq!(a.sigma, b.sigma, max_relative = 1e-12);
            assert_relative_eq!(a.stiffness, b.stiffness, max_relative = 1e-12);
        }
        assert!(compared >= 2, "{compared} points in contact");
        // far apart: the law is separated, the closed branch in tension
        let du_n = 1.0e-3;
        let a = law.normal(du_n, lambda);
        let b = law.normal_closed(du_n, lambda);
        assert_eq!(a.stage, NormalStage::Separation);
        assert_eq!(a.sigma, 0.0);
        assert_eq!(b.stage, NormalStage::Contact);
        assert!(b.sigma > 0.0, "tension expected: {}", b.sigma);
        assert_relative_eq!(b.stiffness, law.contact_stiffness(), max_relative = 1e-12);
        // linear there: the tangent is the difference quotient
        let h = 1.0e-7;
        let fd = (law.normal_closed(du_n + h, lambda).sigma
            - law.normal_closed(du_n - h, lambda).sigma)
            / (2.0 * h);
        assert_relative_eq!(fd, b.stiffness, max_relative = 1e-6);
    }
}

/// The stick branch continued past the slip limit (`forced_stick`, the
/// branch a Newton prediction tries for a slipping point it expects to
/// stick): a closed point with a positive limit takes the elastic trial
/// traction and the stick tangent whatever its shear, in both friction
/// bounds, and the forced copy differs from the law only where the law
/// slips; a point without strength still slides freely.
#[test]
fn a_forced_stick_continues_the_stick_branch_past_the_slip_limit() {
    let coupled = friction_law(0.0, 2.0f64.atan().to_degrees()); // μ = 2
    let frozen = coupled.with_friction_bound(FrictionBound::Frozen);
    let p = 3.0e6;
    let du_n = -p / K;
    assert_relative_eq!(
        coupled
            .evaluate(&Vector2::new(0.0, du_n), &JointState::default())
            .traction
            .y,
        -p,
        max_relative = 1e-12
    );
    let limit = coupled.tan_phi() * p;
    // a committed state with the stored pressure, and its forced copy
    let states = |pressure: f64| {
        let st = JointState {
            slip: 1.0e-7,
            friction_pressure: pressure,
            ..JointState::default()
        };
        (
            st,
            JointState {
                forced_stick: true,
                ..st
            },
        )
    };
    for (law, pressure) in [(coupled, 0.0), (frozen, p)] {
        let (st, forced) = states(pressure);
        // within the limit: the law and its forced copy agree to the bit
        let inside = Vector2::new(st.slip + 0.5 * limit / K, du_n);
        let (a, b) = (law.evaluate(&inside, &st), law.evaluate(&inside, &forced));
        assert_eq!(a.status, ContactStatus::Stick);
        assert_eq!((a.traction, a.tangent), (b.traction, b.tangent));
        // three times past the limit, both ways: the law slips at ±limit,
        // the forced copy sticks with the trial traction and k_s
        for sign in [1.0, -1.0] {
            let past = Vector2::new(st.slip + sign * 3.0 * limit / K, du_n);
            let a = law.evaluate(&past, &st);
            assert_eq!(a.status, ContactStatus::Slip);
            assert_relative_eq!(a.traction.x, sign * limit, max_relative = 1e-9);
            let b = law.evaluate(&past, &forced);
            assert_eq!(b.status, ContactStatus::Stick);
            assert_relative_eq!(b.traction.x, sign * 3.0 * limit, max_relative = 1e-9);
            assert_eq!(b.traction.y, a.traction.y);
            assert_eq!(b.tangent, Matrix2::new(K, 0.0, 0.0, K));
            assert_eq!(b.state, forced, "a forced stick keeps the committed slip");
            assert!(fd_error(&law, &past, &forced, 1e-13, K) < FD_TOL);
        }
    }
    // open under a frozen limit (the friction part stays on at opening):
    // forced, the point sticks with the trial traction past that limit too
    let (st, forced) = states(p);
    let open_past = Vector2::new(st.slip + 3.0 * limit / K, 1.0e-6);
    let a = frozen.evaluate(&open_past, &st);
    assert_eq!(a.status, ContactStatus::Open);
    assert_relative_eq!(a.traction.x, limit, max_relative = 1e-9);
    let b = frozen.evaluate(&open_past, &forced);
    assert_eq!(b.status, ContactStatus::Open);
    assert_relative_eq!(b.traction.x, 3.0 * limit, max_relative = 1e-9);
    assert_eq!(b.tangent[(0, 0)], K);
    // frictionless: no strength, nothing to stick with
    let free = friction_law(0.0, 0.0);
    let st = JointState {
        forced_stick: true,
        ..JointState::default()
    };
    let r = free.evaluate(&Vector2::new(1.0e-6, -1.0e-6), &st);
    assert_eq!(r.status, ContactStatus::Slip);
    assert_eq!(r.traction.x, 0.0);
}
