//! Accuracy of the default P2 vessel mesh: the judged quantities on
//! `VesselMeshSpec::graded(0)` against the finer meshes of the same family.
//!
//! Reference: the convergence study of docs/vessel.md §9 (graded levels 0,
//! 1, 2: 2 784, 11 168 and 44 672 six-node triangles), run in release by
//! `cargo run --release -p tecon --example p2_accuracy -- bonded g0,g1,g2`
//! (and `frictionless`). Levels 1 and 2 are too slow for a test (5 s and
//! 33 s bonded, 23 s and 150 s frictionless): their values are committed
//! below; level 0 is recomputed here and must reproduce the study.
//! Goal: the observed orders of the far-field hoop stresses are about 2
//! (fitted on the three levels), the Richardson estimate of the level-0
//! error is below the targets (bonded far field 1 %, frictionless far field
//! 0.3 %), and the weld plane, the gap and the temperatures are within
//! their targets of the finest level; no temperature is below the ambient
//! after the first second. The full study runs live in the ignored test.
//!
//! ```text
//!   half cross-section θ ∈ [0, π], weld at θ = 0 (layer only)
//!   layer  6 rows  ─────  stations graded to 0.08 mm at the weld edge θ_w,
//!   core   2 rows  ─────  growing by ≤ 1.25 to 1.2° in the far field
//!   quantities: σ_θθ at 45°, 90°, 180° on the bore and the outer surface,
//!   σ_θθ at θ = 0 on the layer faces, Δu_n at 0.4°, T at 0°, 0.5°, 2°
//! ```

use tecon_cli::accuracy::{Judged, judged, observed_order, richardson};
use tecon_cli::builtin::{InterfaceKind, VesselOptions};
use tecon_cli::vessel::analyse;
use tecon_mesh::VesselMeshSpec;

/// (name, level 0, level 1, level 2) of the release study.
type Study = &'static [(&'static str, f64, f64, f64)];

include!("data/p2_accuracy_study.rs");

fn run(interface: InterfaceKind, level: u32) -> Vec<Judged> {
    let o = VesselOptions {
        mesh: VesselMeshSpec::graded(level).unwrap(),
        interface,
        quiet: true,
        ..VesselOptions::default()
    };
    judged(&analyse(&o).expect("vessel run"))
}

fn value(j: &[Judged], name: &str) -> f64 {
    j.iter()
        .find(|q| q.name == name)
        .unwrap_or_else(|| panic!("no judged quantity {name}"))
        .value
}

/// Level 0 recomputed reproduces the study's level 0 (so the committed
/// finer levels still describe this code).
fn reproduces(live: &[Judged], study: Study) {
    for &(name, q0, ..) in study {
        let v = value(live, name);
        let tol = 1e-7 * q0.abs().max(1e-12);
        assert!(
            (v - q0).abs() <= tol,
            "{name}: {v:e} against the study's {q0:e}"
        );
    }
}

/// Observed order and the Richardson estimate of the level-0 error (relative).
fn far_field(study: Study, name: &str) -> (f64, f64) {
    let &(_, q0, q1, q2) = study.iter().find(|q| q.0 == name).unwrap();
    let p = observed_order([q0, q1, q2]).unwrap_or(f64::NAN);
    let limit = richardson(q1, q2, p);
    (p, ((q0 - limit) / limit).abs())
}

const FAR: [&str; 6] = [
    "hoop_core_inner_45",
    "hoop_core_inner_90",
    "hoop_core_inner_180",
    "hoop_layer_outer_45",
    "hoop_layer_outer_90",
    "hoop_layer_outer_180",
];

fn check_far_field(study: Study, target: f64, orders: (f64, f64)) {
    for name in FAR {
        let (p, err) = far_field(study, name);
        eprintln!(
            "{name}: observed order {p:.2}, level-0 error {:.3} %",
            100.0 * err
        );
        assert!(
            (orders.0..=orders.1).contains(&p),
            "{name}: observed order {p}"
        );
        assert!(err < target, "{name}: level-0 error {err}");
    }
}

fn check_frictionless(study: Study) {
    // far field: 0.3 %
    check_far_field(study, 3e-3, (1.4, 2.5));
    let row = |n: &str| *study.iter().find(|q| q.0 == n).unwrap();
    // weld plane (3 %): not yet asymptotic (it drifts by about 0.35 % per
    // level); bounded by twice the level-0 to level-2 change
    for n in ["weld_plane_hoop_layer_inner", "weld_plane_hoop_layer_outer"] {
        let (_, q0, q1, q2) = row(n);
        assert!(
            q0 < -6.0e8 && q2 < q1 && q1 < q0,
            "{n}: {q0:e} {q1:e} {q2:e}"
        );
        let bound = 2.0 * ((q0 - q2) / q2).abs();
        assert!(bound < 0.03, "{n}: level-0 error bound {bound}");
    }
    // gap at 0.4° (5 %)
    let (_, g0, g1, g2) = row("gap_0.4");
    let bound = 2.0 * ((g0 - g2) / g2).abs().max(((g1 - g2) / g2).abs());
    assert!(g0 > 0.0 && bound < 0.05, "gap: {g0:e} {g1:e} {g2:e}");
    // temperatures (0.1 °C) against the finest level
    for &(n, t0, _, t2) in study
        .iter()
        .filter(|q| q.0.starts_with("T_") && q.0 != "T_min_after_1s")
    {
        assert!((t0 - t2).abs() < 0.1, "{n}: {t0} °C against {t2} °C");
    }
    // never below the ambient (21 °C) after the first second
    for level in [
        row("T_min_after_1s").1,
        row("T_min_after_1s").2,
        row("T_min_after_1s").3,
    ] {
        assert!(level > 21.0 - 1e-6, "lowest temperature {level} °C");
    }
}

#[test]
fn bonded_far_field_of_the_default_mesh_converges_at_order_two() {
    let live = run(InterfaceKind::Bonded, 0);
    reproduces(&live, BONDED);
    check_far_field(BONDED, 1e-2, (1.5, 2.5));
    // One material, tied: the hoop stress is continuous across the
    // interface, so its two faces must agree (they took element means and
    // differed by 1.5 MPa at 90° before the tied nodes were recovered).
    for th in [45.0, 90.0, 180.0] {
        let core = value(&live, &format!("hoop_core_outer_{th}"));
        let layer = value(&live, &format!("hoop_layer_inner_{th}"));
        eprintln!("bonded interface at {th}°: core face {core:e}, layer face {layer:e}");
        assert!(
            (core - layer).abs() < TIED_FACES_AGREE,
            "{th}°: {core:e} against {layer:e}"
        );
    }
}

/// Largest difference of the hoop stress of the two faces of the bonded
/// interface on level 0, Pa (observed 2.4 kPa at 180°, 1.7 kPa at 45°).
const TIED_FACES_AGREE: f64 = 5e3;

#[test]
fn frictionless_default_mesh_meets_the_targets() {
    reproduces(&run(InterfaceKind::Frictionless, 0), FRICTIONLESS);
    check_frictionless(FRICTIONLESS);
}

/// The whole study, live (release: about 4 minutes).
#[test]
#[ignore]
fn accuracy_study_levels_0_to_2() {
    for (kind, study) in [
        (InterfaceKind::Bonded, BONDED),
        (InterfaceKind::Frictionless, FRICTIONLESS),
    ] {
        let levels: Vec<Vec<Judged>> = (0..3).map(|l| run(kind, l)).collect();
        for &(name, q0, q1, q2) in study {
            for (l, q) in [q0, q1, q2].iter().enumerate() {
                let v = value(&levels[l], name);
                assert!(
                    (v - q).abs() <= 1e-7 * q.abs(),
                    "{name} level {l}: {v:e} against {q:e}"
                );
            }
        }
    }
    check_far_field(BONDED, 1e-2, (1.5, 2.5));
    check_frictionless(FRICTIONLESS);
}
