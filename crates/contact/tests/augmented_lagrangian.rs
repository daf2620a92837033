//! # Augmented Lagrangian: contact pressure independent of the penalty
//!
//! Reference: the Uzawa / augmented-Lagrangian treatment of unilateral
//! contact (Simo & Laursen, Computers & Structures 42 (1992) 97–116;
//! Wriggers, *Computational Contact Mechanics*, §6.3): with the penalty
//! `k_n` fixed, the multiplier update `λ ← max(0, λ − k_n Δu_n)` after each
//! converged solve drives the penetration to zero.
//!
//! Goal: show that the contact pressure of a frictional joint depends on the
//! penalty with pure penalty, and does not after the AL outer loop.
//!
//! ```text
//!      rigid plate ──┬───────────┬──  pushed down by δ, slid by s₀
//!                   K_b         K_b    (springs in x and y, per node)
//!        4 ●────────┴───────────┴──● 3   top face (free)
//!        1 ●───────────────────────● 2   bottom face (fixed)
//! ```
//!
//! Closed form with a rigid joint: each top node carries `K_b δ`, so the
//! pressure is `p = K_b δ / (L/2)` (nodal rule); a pure penalty gives
//! `p_k = p · w k /(K_b + w k)`, `w = L/2`. Sliding: `τ = p tan φ`.
//!
//! Checked: the pure-penalty pressure matches `p_k` (so the penalty error
//! is real and measured), the AL-converged pressure matches `p` to 1e-8 for
//! two penalties 100× apart, the joint slips with `τ = p tan φ`, and slip
//! history is untouched by the multiplier updates.

use approx::assert_relative_eq;
use tecon_contact::nalgebra::{Matrix4, Point2, Vector4};
use tecon_contact::{
    ContactStatus, GhaboussiNormal, InterfaceElement, JointState, PaperJoint, Vector8,
};

const L: f64 = 0.1;
const KB: f64 = 5.0e9; // N/m per node
const DELTA: f64 = 2.0e-6; // m
const S0: f64 = 50.0e-6; // m
const PHI_DEG: f64 = 25.0;

struct Result {
    pressure: f64,
    shear: f64,
    status: ContactStatus,
    outer_iterations: usize,
    states: [JointState; 2],
}

/// Newton solve of the four top dofs for committed `states`.
fn newton(e: &InterfaceElement, law: &PaperJoint, states: &[JointState; 2]) -> Vector8 {
    let plate = Vector4::new(S0, -DELTA, S0, -DELTA);
    let mut u = Vector8::zeros();
    for _ in 0..50 {
        let r = e.evaluate(law, &u, states);
        let top = u.fixed_rows::<4>(4).into_owned();
        let res = r.force.fixed_rows::<4>(4).into_owned() + (top - plate) * KB;
        if res.norm() <= 1e-12 * KB * DELTA {
            return u;
        }
        let k: Matrix4<f64> =
            r.tangent.fixed_view::<4, 4>(4, 4).into_owned() + Matrix4::identity() * KB;
        let du = k.lu().solve(&(-res)).expect("tangent is regular (springs)");
        let mut top = u.fixed_rows_mut::<4>(4);
        top += du;
    }
    panic!("Newton did not converge");
}

fn solve(k_n: f64, augmented: bool) -> Result {
    let nodes = [[0.0, 0.0], [L, 0.0], [L, 0.0], [0.0, 0.0]].map(|p| Point2::new(p[0], p[1]));
    let e = InterfaceElement::new(&nodes).unwrap();
    let law = PaperJoint::new(
        GhaboussiNormal::penalty(k_n).unwrap(),
        k_n,
        0.0,
        PHI_DEG.to_radians(),
    )
    .unwrap();
    let mut states = [JointState::default(); 2];
    let mut outer = 0;
    loop {
        let u = newton(&e, &law, &states);
        let r = e.evaluate(&law, &u, &states);
        if !augmented {
            return report(&r.points, 0, r.points.map(|p| p.state));
        }
        let (next, change) = e.augment(&law, &u, &states);
        outer += 1;
        let p = -r.points[0].traction.y;
        if change <= 1e-10 * p {
            return report(&r.points, outer, r.points.map(|p| p.state));
        }
        assert!(outer < 200, "AL loop did not converge");
        states = next;
    }
}

fn report(
    points: &[tecon_contact::PointOutput<JointState>; 2],
    outer: usize,
    states: [JointState; 2],
) -> Result {
    Result {
        pressure: -points[0].traction.y,
        shear: points[0].traction.x,
        status: points[0].status,
        outer_iterations: outer,
        states,
    }
}

#[test]
fn augmented_lagrangian_pressure_is_penalty_independent() {
    let w = L / 2.0;
    let exact = KB * DELTA / w;
    let tan_phi = PHI_DEG.to_radians().tan();
    let mut al = Vec::new();
    for k in [1.0e11, 1.0e13] {
        let pen = solve(k, false);
        let predicted = exact * w * k / (KB + w * k);
        assert_relative_eq!(pen.pressure, predicted, max_relative = 1e-9);
        let a = solve(k, true);
        println!(
            "k_n = {k:.0e} Pa/m: penalty p error {:.2e}, AL p error {:.2e} after {} updates",
            (pen.pressure - exact).abs() / exact,
            (a.pressure - exact).abs() / exact,
            a.outer_iterations
        );
        assert_relative_eq!(a.pressure, exact, max_relative = 1e-8);
        // Slipping at the friction limit of the converged pressure.
        assert_eq!(a.status, ContactStatus::Slip);
        assert_relative_eq!(a.shear, a.pressure * tan_phi, max_relative = 1e-12);
        // The multiplier carries the pressure; slip history is the trial's.
        assert_relative_eq!(a.states[0].lambda_n, a.pressure, max_relative = 1e-6);
        assert!(a.states[0].slip > 0.0);
        al.push(a.pressure);
    }
    assert_relative_eq!(al[0], al[1], max_relative = 1e-8);
}
