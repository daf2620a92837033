//! The temperature history and the operating state, as a user meets them.
//!
//! Goal: `tecon vessel` and `tecon run` record the temperature of a few
//! points at every thermal step (one-way and two-way), and at the output
//! times those records are the output states' temperatures exactly; the
//! operating state of `--pressure` is written like the other states, and
//! its hoop stress is the one the summary reports.

use std::path::Path;
use std::process::Command;

use serde_json::Value;
use tecon_cli::vessel::{self, VesselOptions};
use tecon_mesh::VesselMeshSpec;

fn tecon() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tecon"))
}

fn run_ok(c: &mut Command) {
    let o = c.output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// A CSV file as its header and its rows of fields.
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

/// Every record of the history at an output time holds the output state's
/// nodal temperatures bit for bit; the records are the start and every
/// thermal step, in time order.
fn check_history_against_states(o: &VesselOptions) {
    let run = vessel::analyse(o).unwrap();
    let h = run.history.as_ref().expect("a history");
    let nodes: Vec<usize> = run.history_probes.iter().map(|p| p.node).collect();
    assert_eq!(h.nodes, nodes);
    assert_eq!(
        h.times.len(),
        run.thermal_steps + 1,
        "the start and every step"
    );
    assert_eq!(h.times[0], 0.0);
    assert!(h.times.windows(2).all(|w| w[1] > w[0]), "in time order");
    assert_eq!(h.times.last(), o.times.last());
    assert_eq!(run.results.len(), o.times.len());
    for r in &run.results {
        let k = h
            .times
            .iter()
            .position(|&t| t == r.time)
            .unwrap_or_else(|| panic!("no record at the output time {} s", r.time));
        let t = r.temperature.as_ref().unwrap();
        let expected: Vec<f64> = nodes.iter().map(|&i| t[i]).collect();
        assert_eq!(h.values[k], expected, "t = {} s", r.time);
    }
    // the weld cools from its initial temperature, the core side of the
    // joint warms up from the ambient and comes back to it
    let col = |name: &str| {
        let j = run
            .history_probes
            .iter()
            .position(|p| p.name == name)
            .unwrap();
        h.values.iter().map(|v| v[j]).collect::<Vec<_>>()
    };
    let (weld, core) = (col("weld_centre"), col("interface_core"));
    let d = &o.data;
    assert_eq!(weld[0], d.weld_temperature);
    assert_eq!(core[0], d.ambient);
    let peak = core.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert!(
        peak > d.ambient + 10.0,
        "core side of the joint peaks at {peak} °C"
    );
    if o.times.last() == Some(&72000.0) {
        // back to the ambient at the end of the cooling
        assert!((core.last().unwrap() - d.ambient).abs() < 0.01);
        assert!((weld.last().unwrap() - d.ambient).abs() < 0.01);
    }
}

#[test]
fn the_vessel_history_is_the_output_states_at_the_output_times_one_way_and_two_way() {
    let paper = VesselOptions {
        mesh: VesselMeshSpec::paper(),
        ..VesselOptions::default()
    };
    check_history_against_states(&paper);
    // output times that split thermal steps (0.5 s and 7 s lie inside steps)
    check_history_against_states(&VesselOptions {
        times: vec![0.5, 7.0, 600.0],
        ..paper.clone()
    });
    check_history_against_states(&VesselOptions {
        contact_conductance: true,
        two_way: Some(tecon_cli::driver::TwoWay::default()),
        ..paper
    });
}

#[test]
fn tecon_vessel_writes_the_history_and_the_operating_state() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("v");
    run_ok(
        tecon()
            .args(["vessel", "--quiet", "--pressure", "10e6", "--out"])
            .arg(&out),
    );
    let v = summary(&out);
    // the history: the start and every thermal step
    let (header, rows) = csv(&out.join("temperature_history.csv"));
    assert_eq!(
        header,
        [
            "time_s",
            "T_weld_centre_C",
            "T_interface_layer_C",
            "T_interface_core_C",
            "T_core_inner_C",
            "T_far_field_90deg_C"
        ]
    );
    assert_eq!(
        rows.len() as u64,
        v["thermal"]["steps"].as_u64().unwrap() + 1
    );
    assert!(out.join("temperature_history.svg").exists());
    assert!(out.join("temperature_history.png").exists());
    let th = &v["temperature_history"];
    assert_eq!(th["records"].as_u64(), Some(rows.len() as u64));
    assert_eq!(th["probes"][0]["name"], "weld_centre");
    assert_eq!(th["probes"][0]["max"].as_f64(), Some(1132.0));
    // the README's numbers (default mesh g0): the peaks of the core side
    // of the joint and of the inner surface, and the inner surface's dip
    // below the initial 21 °C between output times
    assert_eq!(rows.len(), 293);
    let point = |name: &str| {
        th["probes"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == name)
            .unwrap()
            .clone()
    };
    let near = |v: &Value, want: f64, tol: f64| (v.as_f64().unwrap() - want).abs() <= tol;
    let (joint, inner) = (point("interface_core"), point("core_inner"));
    assert!(
        near(&joint["max"], 51.40, 0.005) && near(&joint["time_of_max"], 1.0, 0.0),
        "{joint}"
    );
    assert!(
        near(&inner["max"], 47.25, 0.005) && near(&inner["time_of_max"], 26.0, 0.0),
        "{inner}"
    );
    let j = header.iter().position(|c| c == "T_core_inner_C").unwrap();
    let (t_min, v_min) = rows
        .iter()
        .map(|r| (r[0].parse::<f64>().unwrap(), r[j].parse::<f64>().unwrap()))
        .fold(
            (f64::NAN, f64::INFINITY),
            |a, b| if b.1 < a.1 { b } else { a },
        );
    assert!(
        (v_min - 20.91).abs() <= 0.005 && t_min == 0.12,
        "{v_min} °C at {t_min} s"
    );
    let report = std::fs::read_to_string(out.join("report.txt")).unwrap();
    assert!(report.contains("temperature history at"), "{report}");

    // the operating state: its own VTU and interface table
    assert!(out.join("interface_operating.csv").exists());
    let pvd = std::fs::read_to_string(out.join("vessel.pvd")).unwrap();
    assert!(
        !pvd.contains("operating"),
        "the series holds the cooling only"
    );
    let vtu = std::fs::read_to_string(out.join("vessel_operating.vtu")).unwrap();
    let op = &v["operating"]["hoop_mean_with_prestress"];
    let g = tecon_mesh::VesselGeometry::default();
    // the circumferential mean of the VTU's σ_θθ on the inner surface is
    // the summary's (the VTU prints 16 digits). On the inner surface every
    // node has one point; the layer's surfaces cross the weld edge, where
    // the VTU splits a node into a weld and a layer point, each with its
    // region's stress, and the summary takes the node's mean.
    let mean = ring_mean_hoop(&vtu, g.inner_radius);
    let want = op["core_inner"].as_f64().unwrap();
    assert!(
        (mean / want - 1.0).abs() < 1e-12,
        "core_inner: VTU {mean} against summary {want}"
    );
    // and it is the pressurised state: some 400 MPa at 10 MPa, far above
    // the prestress of the cooled state
    let cooled = v["final"]["hoop_mean"]["core_inner"].as_f64().unwrap();
    let cooled_vtu = ring_mean_hoop(
        &std::fs::read_to_string(out.join("vessel_005.vtu")).unwrap(),
        g.inner_radius,
    );
    assert!((cooled_vtu / cooled - 1.0).abs() < 1e-12);
    assert!(op["core_inner"].as_f64().unwrap() > 3.5e8);
    // interface rows: one per interface point, as interface_005.csv
    let (h_op, rows_op) = csv(&out.join("interface_operating.csv"));
    let (h_5, rows_5) = csv(&out.join("interface_005.csv"));
    assert_eq!(h_op, h_5);
    assert_eq!(rows_op.len(), rows_5.len());
    let p = h_op
        .iter()
        .position(|c| c == "contact_pressure_Pa")
        .unwrap();
    let sum =
        |rows: &[Vec<String>]| -> f64 { rows.iter().map(|r| r[p].parse::<f64>().unwrap()).sum() };
    assert!(
        sum(&rows_op) > sum(&rows_5),
        "the internal pressure presses the core onto the layer"
    );
}

/// The values of the `DataArray` named `name` of an ASCII VTU.
fn data_array(vtu: &str, name: &str) -> Vec<f64> {
    let tag = if name == "Points" {
        vtu.find("<Points>").unwrap()
    } else {
        vtu.find(&format!("Name=\"{name}\"")).unwrap()
    };
    let start = tag + vtu[tag..].find('>').unwrap() + 1;
    let start = if name == "Points" {
        start + vtu[start..].find('>').unwrap() + 1
    } else {
        start
    };
    let end = start + vtu[start..].find("</DataArray>").unwrap();
    vtu[start..end]
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect()
}

/// Trapezoid mean over θ ∈ [0, π] of the VTU's σ_θθ at its points on the
/// circle of radius `r`.
fn ring_mean_hoop(vtu: &str, r: f64) -> f64 {
    let x = data_array(vtu, "Points");
    let s = data_array(vtu, "stress_rr_tt_rt_Pa");
    let mut pts: Vec<(f64, f64)> = (0..x.len() / 3)
        .filter(|&k| (x[3 * k].hypot(x[3 * k + 1]) - r).abs() < 1e-9 * r)
        .map(|k| (x[3 * k + 1].atan2(x[3 * k]), s[3 * k + 1]))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts.dedup_by(|a, b| a.0 == b.0);
    assert!(pts.len() > 10, "{} points on r = {r}", pts.len());
    let (mut sum, mut w) = (0.0, 0.0);
    for p in pts.windows(2) {
        let dt = p[1].0 - p[0].0;
        sum += 0.5 * dt * (p[0].1 + p[1].1);
        w += dt;
    }
    sum / w
}

#[test]
fn tecon_run_records_its_probes_at_every_thermal_step() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("c");
    let case = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/cases/vessel.toml"
    );
    run_ok(tecon().args(["run", case, "--quiet", "--out"]).arg(&out));
    let v = summary(&out);
    let (header, rows) = csv(&out.join("temperature_history.csv"));
    assert_eq!(header, ["time_s", "T_probe0_C", "T_probe1_C"]);
    assert_eq!(
        rows.len() as u64,
        v["thermal"]["steps"].as_u64().unwrap() + 1
    );
    assert_eq!(
        v["temperature_history"]["records"].as_u64(),
        Some(rows.len() as u64)
    );
    // at every output time, the same text as probes.csv's T_C (the same
    // node, the same number, the same format)
    let (ph, prows) = csv(&out.join("probes.csv"));
    let (ti, pi, ci) = (
        ph.iter().position(|c| c == "time_s").unwrap(),
        ph.iter().position(|c| c == "probe").unwrap(),
        ph.iter().position(|c| c == "T_C").unwrap(),
    );
    let times = v["times"].as_array().unwrap();
    assert_eq!(prows.len(), 2 * times.len());
    for p in &prows {
        let row = rows
            .iter()
            .find(|r| r[0] == p[ti])
            .unwrap_or_else(|| panic!("no history record at t = {}", p[ti]));
        let k: usize = p[pi].parse().unwrap();
        assert_eq!(row[1 + k], p[ci], "probe {k} at t = {}", p[ti]);
    }
    assert!(out.join("temperature_history.png").exists());
}

#[test]
fn a_case_without_probes_or_without_a_transient_writes_no_history() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("c");
    // the Lamé cylinder: no heat conduction
    let case = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/cases/lame.toml"
    );
    run_ok(tecon().args(["run", case, "--quiet", "--out"]).arg(&out));
    assert!(!out.join("temperature_history.csv").exists());
    assert!(summary(&out).get("temperature_history").is_none());
}
