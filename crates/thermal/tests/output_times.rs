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
use tecon_thermal::{EdgeBc, Material, ThermalModel, ThetaScheme, TimeSchedule};

#[test]
fn snapshots_carry_the_requested_times_bitwise() {
    let mesh = vessel_mesh(&VesselGeometry::default(), &VesselMeshSpec::paper()).unwrap();
    let mut model = ThermalModel::new(&mesh);
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
