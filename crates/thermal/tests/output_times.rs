//! Output snapshots carry exactly the requested times.
//!
//! Goal: a schedule whose steps do not add up exactly in floating point
//! (fifty steps of 0.02 s end at 1.0000000000000004 s) still reports the
//! outputs at 1 s, 10 s, … bitwise, so that legends, file names and
//! summaries show the times the user asked for.
//!
//! Mesh: the published welded vessel (paper preset, 108 nodes); weld at
//! 1132 °C, the rest at 21 °C, convection inside and outside.

use tecon_mesh::{VesselGeometry, VesselMeshSpec, vessel_mesh};
use tecon_thermal::{
    EdgeBc, Material, ThermalModel, ThetaScheme, TimeSchedule, run_transient, run_transient_while,
};

fn paper_model(mesh: &tecon_mesh::Mesh) -> ThermalModel<'_> {
    let mut model = ThermalModel::new(mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .add_edge_bc("inner", EdgeBc::convection(10.25, 21.0))
        .unwrap()
        .add_edge_bc("outer", EdgeBc::convection(10.25, 21.0))
        .unwrap()
        .set_interface_conductance("core_layer", 850.0)
        .unwrap()
        .set_initial_default(21.0)
        .unwrap()
        .set_initial_region("weld", 1132.0)
        .unwrap();
    model
}

#[test]
fn snapshots_carry_the_requested_times_bitwise() {
    let mesh = vessel_mesh(&VesselGeometry::default(), &VesselMeshSpec::paper()).unwrap();
    let model = paper_model(&mesh);
    let schedule = TimeSchedule::segments(&[
        (1.0, 0.02),
        (10.0, 0.2),
        (100.0, 2.0),
        (1000.0, 20.0),
        (10000.0, 200.0),
        (72000.0, 1000.0),
    ])
    .unwrap();
    // the sum of the steps is not exactly 1 s after the first segment
    let first: f64 = schedule.steps()[..50].iter().sum();
    assert_ne!(first, 1.0, "the test needs a clock that drifts");
    let outs = [1.0, 10.0, 60.0, 600.0, 3600.0, 72000.0];
    let mut times = Vec::new();
    model
        .solve_transient(&schedule, ThetaScheme::crank_nicolson(), &outs, |s| {
            times.push(s.time)
        })
        .unwrap();
    assert_eq!(times, outs, "bitwise the requested times");
}

/// Goal: a run told to stop (a consumer of its snapshots gave up) stops at
/// the next step, with the snapshots before it those of a full run.
#[test]
fn a_run_told_to_stop_stops_at_its_next_step() {
    let mesh = vessel_mesh(&VesselGeometry::default(), &VesselMeshSpec::paper()).unwrap();
    let system = paper_model(&mesh).assemble().unwrap();
    let schedule = TimeSchedule::segments(&[(1.0, 0.1), (10.0, 1.0)]).unwrap();
    let outs = [0.5, 1.0, 5.0, 10.0];
    let scheme = ThetaScheme::crank_nicolson();
    let mut full = Vec::new();
    let whole = run_transient(&system, &schedule, scheme, &outs, |s| full.push(s.clone())).unwrap();
    assert_eq!(whole.steps, 19);
    assert_eq!(full.len(), 4);
    // stop once the second snapshot (t = 1 s, after 10 steps) is out
    let seen = std::cell::Cell::new(0);
    let mut part = Vec::new();
    let stopped = run_transient_while(
        &system,
        &schedule,
        scheme,
        &outs,
        |s| {
            part.push(s.clone());
            seen.set(part.len());
        },
        || seen.get() < 2,
    )
    .unwrap();
    assert_eq!(stopped.steps, 10, "no step after the stop");
    assert!(
        (stopped.end_time - 1.0).abs() < 1e-12,
        "{}",
        stopped.end_time
    );
    assert_eq!(part.len(), 2);
    for (a, b) in part.iter().zip(&full) {
        assert_eq!(a.time, b.time);
        assert_eq!(
            a.temperature, b.temperature,
            "the same bits as the full run"
        );
    }
}
