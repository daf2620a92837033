//! # The `shear_path` example, run and pinned
//!
//! Reference: `examples/shear_path.rs` (one interface element under normal
//! pressure driven in shear through stick, slip and unloading) and the
//! closed form of a 1D elastic–perfectly plastic spring.
//!
//! Goal: the documented example runs and its traction path is the
//! analytical one.
//!
//! ```text
//!   τ   +s ┤    ┌──────┐           s = c + p tan φ
//!          │   ╱       │
//!        0 ┼──╱────────┼────╱── Δu_t
//!          │           │   ╱
//!       −s ┤           └──┘
//!          0      s_max   −s_max   0
//! ```
//!
//! Checked: σ = −p at every step; stick at the first step with
//! τ = k_s Δu_t; τ = ±s while slipping; the accumulated slip at the end
//! of the path equals the closed form (pinned number): the three legs slip
//! by s_max − s/k_s, 2 s_max − 2s/k_s and s_max − 2s/k_s (each reversal
//! first unloads elastically through 2s/k_s), in total 4 s_max − 5 s/k_s.

#[allow(dead_code)]
#[path = "../examples/shear_path.rs"]
mod shear_path;

use approx::assert_relative_eq;
use shear_path::{ShearPath, law};
use tecon_contact::ContactStatus;

#[test]
fn shear_path_follows_the_elastic_perfectly_plastic_closed_form() {
    let p = ShearPath::default();
    let law = law(&p).unwrap();
    let path = shear_path::shear_path(&p).unwrap();
    let n = p.steps_per_leg;
    assert_eq!(path.len(), 4 * n + 1);
    let s = p.cohesion + p.pressure * p.friction_deg.to_radians().tan();
    let k_s = law.k_s();
    let s_max = p.peak_over_elastic * s / k_s;
    for q in &path {
        assert_relative_eq!(q.sigma, -p.pressure, max_relative = 1e-10);
    }
    // Step 1: Δu_t = s_max/10 = s/(2 k_s): sticking.
    assert_eq!(path[1].status, ContactStatus::Stick);
    assert_relative_eq!(path[1].tau, k_s * path[1].du_t, max_relative = 1e-10);
    // Peak: slipping forward on the limit.
    assert_eq!(path[n].status, ContactStatus::Slip);
    assert_relative_eq!(path[n].tau, s, max_relative = 1e-10);
    // First unloading step: back in stick, slip frozen.
    assert_eq!(path[n + 1].status, ContactStatus::Stick);
    assert_eq!(path[n + 1].state.slip, path[n].state.slip);
    // Reverse peak: on the negative limit.
    assert_relative_eq!(path[3 * n].tau, -s, max_relative = 1e-10);
    // Pinned number: total dissipative slip of the closed path.
    let acc = path[4 * n].state.accumulated_slip;
    let expected = 4.0 * s_max - 5.0 * s / k_s;
    println!("accumulated slip {acc:.6e} m, closed form {expected:.6e} m");
    assert_relative_eq!(acc, expected, max_relative = 1e-9);
}
