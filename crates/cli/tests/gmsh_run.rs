//! `tecon run` on a real Gmsh mesh with a curved interface, and the case
//! keys that check results against the domain and the material.
//!
//! Reference: the two-cylinder shrink fit (Lamé), plane strain, interference
//! δ = (1 + ν) α ΔT c for an inner ring ΔT warmer than the stress-free state.
//! Goal: the 8° sector of the vessel's core and layer, meshed by Gmsh 4.15
//! itself at lc = 0.002 m (0.5 mm at θ = 0; the two faces of the joint meshed
//! separately, so their nodes are a few nm apart:
//! `crates/mesh/tests/data/make_msh.py`), pairs from its two physical curves
//! and carries the Lamé contact pressure; a probe outside the mesh and a bad
//! `yield` are refused naming them; a yield stress is checked.
//!
//! The joint is the Mohr–Coulomb one (μ = 0.3, augmented Lagrangian, as a
//! user would set it); the sticking, frictionless and linear joints are run
//! too. The fit stays closed everywhere, so every law carries the Lamé
//! pressure (observed: mean 1.016003e6 Pa against 1.016019e6 Pa, −0.0016 %;
//! the point values scatter by ±2.5 % on this unstructured mesh, the shear by
//! 3.6e4 Pa). The 8° edge is inclined, so its nodes have rotated frames: the
//! contact multipliers had never settled on this mesh because every Newton
//! pass wrote the prescribed 0 into the global x component of those nodes.
//!
//! ```text
//!        end (θ = 8°, symmetry)
//!         \  outer  0.7747–0.7811 m
//!          \ inner  0.762–0.7747 m, 50 K warm
//!   ────────  start (θ = 0, symmetry)
//! ```

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;
use tecon_elastic::analytical::{Cylinders, ShrinkFit};

fn msh() -> PathBuf {
    data("vessel_sector_lc002.msh")
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../mesh/tests/data")
        .join(name)
}

const E: f64 = 207e9;
const NU: f64 = 0.3;
const ALPHA: f64 = 12.51e-6;
const DT: f64 = 50.0;

/// The two-cylinder (Lamé) contact pressure of the sector's shrink fit,
/// plane strain, interference (1 + ν) α ΔT c.
fn lame_pressure() -> f64 {
    ShrinkFit {
        a: 0.762,
        c: 0.7747,
        b: 0.7811,
        delta: (1.0 + NU) * ALPHA * DT * 0.7747,
        e: E,
        nu: NU,
        state: Cylinders::PlaneStrain,
    }
    .pressure()
}

/// The case file with the Mohr–Coulomb joint (μ = 0.3); `extra_material`
/// goes into the inner ring's material, `probes` into `[output]`.
fn case(extra_material: &str, probes: &str) -> String {
    case_with(
        extra_material,
        probes,
        "law = \"frictional\"\nfriction = 0.3",
    )
}

/// The case file with the joint table `joint`.
fn case_with(extra_material: &str, probes: &str, joint: &str) -> String {
    format!(
        r#"
[mesh]
file = "{msh}"

[[material]]
region = "inner"
conductivity = 63.9
density = 7832.0
specific_heat = 434.0
youngs_modulus = {E:e}
poisson_ratio = {NU}
expansion = {ALPHA:e}
{extra_material}

[[material]]
region = "outer"
conductivity = 63.9
density = 7832.0
specific_heat = 434.0
youngs_modulus = {E:e}
poisson_ratio = {NU}
expansion = {ALPHA:e}

[[interface]]
name = "joint"
bottom = "inner_face"
top = "outer_face"
[interface.joint]
{joint}

[thermal.initial]
default = 21.0
[[thermal.initial.region]]
region = "inner"
value = {hot}

[mechanical]
analysis = "plane-strain"
reference_temperature = 21.0
[[mechanical.symmetry]]
edges = "start"
[[mechanical.symmetry]]
edges = "end"

[output]
vtk = false
probes = {probes}
"#,
        msh = msh().display(),
        hot = 21.0 + DT,
    )
}

fn run(dir: &Path, text: &str) -> std::process::Output {
    let file = dir.join("sector.toml");
    std::fs::write(&file, text).unwrap();
    Command::new(env!("CARGO_BIN_EXE_tecon"))
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap()
}

#[test]
fn a_gmsh_mesh_with_a_curved_interface_at_lc_2mm_runs_through_tecon_run() {
    let d = tempfile::tempdir().unwrap();
    // yield 2 MPa: the core's hoop compression (≈ 3 MPa von Mises) exceeds it
    let o = run(
        d.path(),
        &case("yield = 2e6", "[[0.768, 0.001], [0.778, 0.05]]"),
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stdout}\n{stderr}");
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("out/summary.json")).unwrap())
            .unwrap();
    assert!(
        v["mesh"]["triangles"].as_u64().unwrap() > 1000,
        "{}",
        v["mesh"]
    );
    let p = v
        .pointer("/times/0/interfaces/joint/contact_pressure_mean")
        .and_then(Value::as_f64)
        .unwrap();
    let exact = lame_pressure();
    eprintln!(
        "gmsh sector: p = {p:.6e} Pa, Lamé {exact:.6e} Pa ({:+.3} %)",
        100.0 * (p / exact - 1.0)
    );
    assert!((p / exact - 1.0).abs() < 1e-4, "p = {p}, Lamé {exact}");
    // the yield check names the inner ring and the warning reaches the report
    assert!(
        stdout.contains("region inner: peak von Mises") && stdout.contains("EXCEEDED"),
        "{stdout}"
    );
    // its element is named as the user's Gmsh file knows it
    let line = stdout
        .lines()
        .find(|l| l.contains("region inner: peak von Mises"))
        .unwrap();
    assert!(line.contains("(Gmsh element tag "), "{line}");
    let w = v["warnings"].as_array().expect("warnings");
    assert!(
        w.iter()
            .any(|w| w.as_str().unwrap().contains("in region inner")),
        "{w:?}"
    );
    assert!(v["yield_check"][0]["regions"].is_array());
    // timings apart
    let t: Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("out/timing.json")).unwrap())
            .unwrap();
    assert!(t["seconds"].as_f64().is_some() && v.get("seconds").is_none());
}

/// Every joint law carries the Lamé pressure on the Gmsh sector, with every
/// point closed.
#[test]
fn every_joint_law_converges_on_the_gmsh_sector_with_the_lame_pressure() {
    let exact = lame_pressure();
    for joint in [
        "law = \"sticking\"",
        "law = \"frictional\"\nfriction = 0.0",
        "law = \"frictional\"\nfriction = 1.0",
        "law = \"linear\"",
    ] {
        let d = tempfile::tempdir().unwrap();
        let o = run(d.path(), &case_with("", "[]", joint));
        assert!(
            o.status.success(),
            "{joint}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let v: Value = serde_json::from_str(
            &std::fs::read_to_string(d.path().join("out/summary.json")).unwrap(),
        )
        .unwrap();
        let j = &v["times"][0]["interfaces"]["joint"];
        let mean = j["contact_pressure_mean"].as_f64().unwrap();
        let max = j["contact_pressure_max"].as_f64().unwrap();
        eprintln!(
            "{joint}: mean {mean:.6e} ({:+.2e}), max {max:.6e} Pa, open {}",
            mean / exact - 1.0,
            j["open"]
        );
        assert!(
            (mean / exact - 1.0).abs() < 1e-4,
            "{joint}: {mean} vs {exact}"
        );
        // node-to-node scatter of the unstructured mesh: ±2.5 % observed
        assert!(max / exact - 1.0 < 0.05, "{joint}: max {max}");
        assert_eq!(j["open"].as_u64(), Some(0), "{joint}: {j}");
    }
}

/// The same fit on Gmsh's second-order sector (3°, 6-node triangles, mid
/// nodes on the arcs) with the Mohr–Coulomb joint: every interface point
/// carries the Lamé pressure (observed: mean −5e-7, points within 3e-5).
#[test]
fn the_second_order_gmsh_sector_carries_the_lame_pressure_at_every_point() {
    let exact = lame_pressure();
    let d = tempfile::tempdir().unwrap();
    let text = case("", "[]").replace(
        &msh().display().to_string(),
        &data("vessel_sector_lc002_p2.msh").display().to_string(),
    );
    let o = run(d.path(), &text);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(d.path().join("out/interface_000.csv")).unwrap();
    let p: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(7).unwrap().parse().unwrap())
        .collect();
    assert!(p.len() > 50, "{} points", p.len());
    let worst = p
        .iter()
        .map(|x| (x / exact - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "P2 Gmsh sector: {} points, worst {worst:.2e} from Lamé",
        p.len()
    );
    assert!(worst < 1e-4, "worst point {worst:.2e} from Lamé");
}

#[test]
fn a_probe_outside_the_mesh_and_a_bad_yield_are_refused_naming_them() {
    let d = tempfile::tempdir().unwrap();
    // (0.77, -0.001) lies below the sector (y < 0), 1 mm outside
    let o = run(d.path(), &case("", "[[0.768, 0.001], [0.77, -0.001]]"));
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("sector.toml: output.probes[1]: the point (0.77, -0.001) lies outside the mesh"),
        "{e}"
    );
    assert!(!d.path().join("out/summary.json").exists());

    let o = run(d.path(), &case("yield = -5.0", "[]"));
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("material[0].yield (region 'inner'): -5 is not a yield stress > 0"),
        "{e}"
    );
}
