//! `tecon run` on Gmsh meshes with the mistakes Gmsh users make: the
//! warnings and errors reach the user naming what they can find in their
//! model (group names, Gmsh tags, the fix).
//!
//! Reference: the meshes of `crates/mesh/tests/data` written by Gmsh 4.15
//! (`make_msh.py`, `make_msh.py diagnostics`).
//! Goal: two bodies touching without an interface run with a warning
//! (stdout, `--quiet` stderr, summary.json) and without it once the
//! interface is declared; a mesh in millimetres runs with a units warning;
//! a physical point is a node set `[[mechanical.fix]]` can hold; a case that
//! names an empty physical group is refused saying it is empty; an unmerged
//! mesh is refused naming the Gmsh node tags.
//!
//! ```text
//!  two_blocks.msh: ┌────┐┌────┐  left | right, separate nodes on x = 1
//!                  │left││rght│
//!                  └────┘└────┘
//! ```

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn data(name: &str) -> String {
    let p: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../mesh/tests/data")
        .join(name);
    p.display().to_string()
}

fn run(dir: &Path, text: &str, quiet: bool) -> Output {
    let file = dir.join("case.toml");
    std::fs::write(&file, text).unwrap();
    let mut c = Command::new(env!("CARGO_BIN_EXE_tecon"));
    c.arg("run").arg(&file).arg("--out").arg(dir.join("out"));
    if quiet {
        c.arg("--quiet");
    }
    c.output().unwrap()
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap()).unwrap()
}

/// The two blocks, each held on its own (x on its outer side, y at the
/// bottom), squeezed by 1 MPa on top; `interface` is inserted as given.
fn two_blocks(interface: &str) -> String {
    format!(
        r#"
[mesh]
file = "{msh}"

[[material]]
region = "left"
youngs_modulus = 207e9
poisson_ratio = 0.3

[[material]]
region = "right"
youngs_modulus = 207e9
poisson_ratio = 0.3

{interface}

[mechanical]
analysis = "plane-strain"
[[mechanical.fix]]
set = "west"
component = "x"
[[mechanical.fix]]
set = "east"
component = "x"
[[mechanical.fix]]
set = "bottom"
component = "y"
[[mechanical.pressure]]
edges = "top"
value = 1e6
"#,
        msh = data("two_blocks.msh")
    )
}

#[test]
fn bodies_touching_without_an_interface_run_with_a_warning() {
    let d = tempfile::tempdir().unwrap();
    let o = run(d.path(), &two_blocks(""), false);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let expected =
        "warning: mesh: bodies 'left' and 'right' touch at 5 pair(s) of coincident nodes";
    assert!(stdout.contains(expected), "{stdout}");
    assert!(stdout.contains("(Gmsh node tag "), "{stdout}");
    let w = summary(d.path())["warnings"].clone();
    assert!(
        w.as_array()
            .is_some_and(|w| w.len() == 1 && w[0].as_str().unwrap().contains("no interface joins")),
        "{w}"
    );
    // --quiet: the warning on stderr
    let d = tempfile::tempdir().unwrap();
    let o = run(d.path(), &two_blocks(""), true);
    assert!(o.status.success());
    assert!(o.stdout.is_empty());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains(expected), "{stderr}");
    // the interface declared: no warning
    let d = tempfile::tempdir().unwrap();
    let joint = "[[interface]]\nname = \"joint\"\nbottom = \"left_face\"\ntop = \"right_face\"\n[interface.joint]\nlaw = \"frictional\"\nfriction = 0.5";
    let o = run(d.path(), &two_blocks(joint), false);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{stdout}");
    assert!(!stdout.contains("warning"), "{stdout}");
    assert!(summary(d.path()).get("warnings").is_none());
}

fn plate(file: &str) -> String {
    format!(
        r#"
[mesh]
file = "{msh}"

[[material]]
region = "plate"
youngs_modulus = 207e9
poisson_ratio = 0.3

[mechanical]
analysis = "plane-stress"
[[mechanical.fix]]
set = "left"
component = "x"
[[mechanical.fix]]
set = "left"
component = "y"
[[mechanical.pressure]]
edges = "right"
value = -1e6
"#,
        msh = data(file)
    )
}

#[test]
fn a_mesh_in_millimetres_runs_with_a_units_warning() {
    let d = tempfile::tempdir().unwrap();
    let o = run(d.path(), &plate("plate_mm.msh"), false);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        stdout.contains("warning: mesh: the mesh is 200 across: does it use millimetres?")
            && stdout.contains("Mesh.ScalingFactor = 0.001"),
        "{stdout}"
    );
    // the same plate saved in metres: no warning, and the plate pulled by
    // 1 MPa stretches 1000 times less (uniform stress, u ∝ length)
    let u_mm = summary(d.path())["times"][0]["max_displacement"]
        .as_f64()
        .unwrap();
    let d = tempfile::tempdir().unwrap();
    let o = run(d.path(), &plate("plate_m.msh"), false);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && !stdout.contains("warning"),
        "{stdout}"
    );
    let u_m = summary(d.path())["times"][0]["max_displacement"]
        .as_f64()
        .unwrap();
    assert!((u_mm / u_m / 1000.0 - 1.0).abs() < 1e-6, "{u_mm} vs {u_m}");
}

fn groups(fix_set: &str, region: &str) -> String {
    format!(
        r#"
[mesh]
file = "{msh}"

[[material]]
region = "{region}"
youngs_modulus = 207e9
poisson_ratio = 0.3

[mechanical]
analysis = "plane-stress"
[[mechanical.fix]]
set = "{fix_set}"
component = "x"
[[mechanical.fix]]
set = "bottom"
component = "y"
[[mechanical.pressure]]
edges = "supported"
value = 1e6
"#,
        msh = data("groups.msh")
    )
}

#[test]
fn physical_points_hold_and_empty_groups_are_named_empty() {
    // the physical point `corner` holds x; the unembedded point `centre`
    // is named in a warning
    let d = tempfile::tempdir().unwrap();
    let o = run(d.path(), &groups("corner", "plate"), false);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        stdout.contains("warning: mesh: physical point 'centre': its node (Gmsh node tag 5)"),
        "{stdout}"
    );
    // an empty physical curve, an empty physical volume
    for (set, region, expected) in [
        (
            "ghost",
            "plate",
            "the Gmsh file declares 'ghost' as a physical curve (dimension 1), but that group holds no 2- or 3-node line",
        ),
        (
            "centre",
            "plate",
            "the Gmsh file declares 'centre' as a physical point (dimension 0)",
        ),
        (
            "corner",
            "vol",
            "material[0].region: the mesh has no region named 'vol': the Gmsh file declares 'vol' as a physical volume (dimension 3)",
        ),
    ] {
        let d = tempfile::tempdir().unwrap();
        let o = run(d.path(), &groups(set, region), false);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success());
        assert!(stderr.contains(expected), "{set}/{region}: {stderr}");
    }
}

#[test]
fn an_unmerged_mesh_is_refused_naming_the_gmsh_node_tags() {
    let d = tempfile::tempdir().unwrap();
    let text = format!(
        "[mesh]\nfile = \"{}\"\n[[material]]\nregion = \"plate\"\nyoungs_modulus = 1e9\npoisson_ratio = 0.3\n[mechanical]\nanalysis = \"plane-stress\"\n",
        data("unmerged.msh")
    );
    let o = run(d.path(), &text, false);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        stderr.contains("mesh.file: ")
            && stderr.contains("unmerged.msh: nodes ")
            && stderr.matches("(Gmsh node tag ").count() == 2
            && stderr.contains("in region 'plate'"),
        "{stderr}"
    );
    // a surface in two physical surfaces
    let text = text.replace("unmerged.msh", "surface_two_groups.msh");
    let o = run(d.path(), &text, false);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        stderr.contains("surface 1 is in 2 physical surfaces, 'plate' (tag 1) and 'steel' (tag 2)"),
        "{stderr}"
    );
}
