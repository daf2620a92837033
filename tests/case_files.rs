//! End-to-end tests of `tecon run CASE.toml` (the case-file format).
//!
//! Reference: issue 6 ("`tecon run`" and "Bad input"); the two-cylinder
//! Lamé shrink fit (`tecon_elastic::analytical::ShrinkFit`, interference
//! δ = (1+ν) α ΔT c, plane strain) and the Lamé thick cylinder
//! (`LameCylinder`).
//!
//! Goal: every shipped case in `examples/cases/` runs through the library
//! (`case::load` + `case::execute`) and reproduces one number: the shrink
//! fit's mean contact pressure within 1 % of the analytical 8.390324e6 Pa;
//! the Lamé cylinder's bore displacement within 1 %; the Gmsh two-block
//! case carries its 1 MPa across the contact (0.1 %); the published vessel
//! on the paper mesh cools into a compressive core and a tensile layer and
//! reproduces `tecon vessel` (contact pressure within 0.1 %).
//! Every bad input (unknown key, missing region material, an edge set or
//! region the mesh lacks, a negative thickness or modulus, a mesh file that
//! does not parse) gives a one-line error naming the case file and the
//! key/group and leaves no output behind (the binary's exit code 2 is
//! tested in crates/cli/tests/binary.rs).

use std::path::{Path, PathBuf};

use serde_json::Value;
use tecon_cli::case::{self, Case};
use tecon_elastic::analytical::{Cylinders, LameCylinder, ShrinkFit};

fn cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cases")
}

fn run_example(name: &str) -> (Case, case::CaseResult) {
    let path = cases_dir().join(name);
    let c = case::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let res = case::execute(&c, &cases_dir()).unwrap_or_else(|e| panic!("{name}: {e}"));
    (c, res)
}

fn num(v: &Value, pointer: &str) -> f64 {
    v.pointer(pointer)
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("summary has no number at {pointer}: {v}"))
}

#[test]
fn shrink_fit_matches_the_two_cylinder_solution() {
    let (c, res) = run_example("shrink_fit.toml");
    // the analytical answer from the case's own data
    let m = &c.material[0];
    let alpha = m.expansion.unwrap();
    let fit = ShrinkFit {
        a: 1.0,
        c: 1.1,
        b: 1.2,
        delta: (1.0 + m.poisson_ratio) * alpha * 50.0 * 1.1,
        e: m.youngs_modulus,
        nu: m.poisson_ratio,
        state: Cylinders::PlaneStrain,
    };
    let p_exact = fit.pressure();
    assert!((p_exact / 8.390324e6 - 1.0).abs() < 1e-6, "{p_exact}");
    assert_eq!(res.states.len(), 1);
    let p = num(
        &res.summary,
        "/times/0/interfaces/inner_outer/contact_pressure_mean",
    );
    eprintln!("shrink fit: p = {p:.6e}, analytical {p_exact:.6e}");
    assert!((p / p_exact - 1.0).abs() < 0.01, "p = {p}");
    // and the inner ring is in hoop compression, the outer in tension
    assert!(num(&res.summary, "/times/0/regions/inner/stress_mean/tt") < 0.0);
    assert!(num(&res.summary, "/times/0/regions/outer/stress_mean/tt") > 0.0);
}

#[test]
fn lame_cylinder_bore_displacement() {
    let (c, res) = run_example("lame.toml");
    let m = &c.material[0];
    let exact = LameCylinder {
        a: 1.0,
        b: 1.5,
        p: c.mechanical.pressure[0].value,
        e: m.youngs_modulus,
        nu: m.poisson_ratio,
    };
    let (p, node) = res.probes[0];
    assert_eq!(p, [1.0, 0.0]);
    let u = res.states[0].displacement[2 * node];
    eprintln!("Lamé: u_r(a) = {u:.6e}, exact {:.6e}", exact.u_r(1.0));
    assert!((u / exact.u_r(1.0) - 1.0).abs() < 0.01, "u = {u}");
    assert!(res.summary["thermal"].is_null());
}

#[test]
fn published_vessel_case_on_the_paper_mesh() {
    let (_, res) = run_example("vessel.toml");
    let v = &res.summary;
    assert_eq!(num(v, "/mesh/nodes"), 108.0);
    assert_eq!(num(v, "/mesh/triangles"), 136.0);
    let times = v["times"].as_array().unwrap();
    assert_eq!(times.len(), 6);
    let last = times.last().unwrap();
    let core = num(last, "/regions/core/stress_mean/tt");
    let layer = num(last, "/regions/layer/stress_mean/tt");
    eprintln!("vessel: mean hoop core {core:.4e} Pa, layer {layer:.4e} Pa");
    assert!(core < 0.0, "core hoop {core}");
    assert!(layer > 0.0, "layer hoop {layer}");
    assert!(num(last, "/interfaces/core_layer/contact_pressure_mean") > 0.0);
    assert!(num(v, "/thermal/heat_balance_max_rel_error") < 1e-10);
    // cooled back to ambient
    assert!((num(last, "/temperature_max") - 21.0).abs() < 1e-3);
}

/// The case file of the published vessel is the `tecon vessel` analysis:
/// same mesh, data, schedule and joint, so the same interface state.
#[test]
fn vessel_case_file_agrees_with_tecon_vessel() {
    let (_, res) = run_example("vessel.toml");
    let o = tecon_cli::vessel::VesselOptions {
        mesh: tecon_mesh::VesselMeshSpec::paper(),
        quiet: true,
        ..Default::default()
    };
    let run = tecon_cli::vessel::analyse(&o).unwrap();
    let reference = tecon_cli::vessel::summary(&run);
    let p_vessel = num(&reference, "/final/contact_pressure_mean");
    let times = res.summary["times"].as_array().unwrap();
    let p_case = num(
        times.last().unwrap(),
        "/interfaces/core_layer/contact_pressure_mean",
    );
    eprintln!("vessel contact pressure: case file {p_case:.6e}, tecon vessel {p_vessel:.6e}");
    assert!(
        (p_case / p_vessel - 1.0).abs() < 1e-3,
        "{p_case} vs {p_vessel}"
    );
    assert_eq!(num(times.last().unwrap(), "/time"), 72000.0);
}

#[test]
fn outputs_are_written_and_complete() {
    let (c, res) = run_example("shrink_fit.toml");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    case::write_outputs(&c, &res, &out).unwrap();
    for f in [
        "summary.json",
        "case.pvd",
        "state_000.vtu",
        "interface_000.csv",
        "probes.csv",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    assert!(
        names.iter().all(|n| !n.starts_with(".partial")),
        "{names:?}"
    );
    let probes = std::fs::read_to_string(out.join("probes.csv")).unwrap();
    assert_eq!(probes.lines().count(), 3);
}

// ---------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------

/// The shrink-fit case text with `from` replaced by `to` (must occur).
fn edited(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(cases_dir().join("shrink_fit.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

/// Writes `text` as `bad.toml` in a fresh folder and runs it; returns the error.
fn error_of(text: &str) -> (String, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let e = match case::load(&path) {
        Err(e) => e.to_string(),
        Ok(c) => match case::execute(&c, dir.path()) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("the bad case ran:\n{text}"),
        },
    };
    assert!(!e.contains('\n'), "one line: {e}");
    assert!(e.contains("bad.toml"), "names the file: {e}");
    (e, dir)
}

#[test]
fn unknown_key_is_named() {
    let (e, _d) = error_of(&edited("conductivity = 63.9", "condutcivity = 63.9"));
    assert!(e.contains("condutcivity"), "{e}");
    let (e, _d) = error_of(&edited("[output]", "[outputs]"));
    assert!(e.contains("outputs"), "{e}");
}

/// `[thermal] capacity`: consistent (default) or lumped; another word is
/// an error with the file, line and key.
#[test]
fn capacity_key() {
    let text = std::fs::read_to_string(cases_dir().join("vessel.toml")).unwrap();
    let with = |v: &str| {
        text.replacen(
            "[[thermal.bc]]",
            &format!("[thermal]\ncapacity = \"{v}\"\n\n[[thermal.bc]]"),
            1,
        )
    };
    let (e, _d) = error_of(&with("lumpy"));
    assert!(e.contains("thermal.capacity") && e.contains("lumpy"), "{e}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lumped.toml");
    std::fs::write(&path, with("lumped")).unwrap();
    let c = case::load(&path).unwrap();
    let r = case::execute(&c, dir.path()).unwrap();
    assert_eq!(r.summary["thermal"]["capacity"], "lumped");
    // the paper mesh's undershoot of the first steps is gone
    assert_eq!(num(&r.summary, "/thermal/bound_violation"), 0.0);
}

#[test]
fn region_without_material_is_named() {
    let text = edited(
        "region = \"outer\"\nconductivity",
        "region = \"inner\"\nconductivity",
    );
    // two entries for inner: the duplicate is reported; drop the second instead
    let (e, _d) = error_of(&text);
    assert!(e.contains("inner"), "{e}");
    let text = std::fs::read_to_string(cases_dir().join("shrink_fit.toml")).unwrap();
    let cut = text.find("[[material]]\nregion = \"outer\"").unwrap();
    let end = text[cut..].find("# The annulus").unwrap() + cut;
    let text = format!("{}{}", &text[..cut], &text[end..]);
    let (e, _d) = error_of(&text);
    assert!(e.contains("region 'outer' has no [[material]]"), "{e}");
}

#[test]
fn material_for_a_region_the_mesh_lacks() {
    let (e, _d) = error_of(&edited(
        "region = \"outer\"\nconductivity",
        "region = \"outre\"\nconductivity",
    ));
    assert!(
        e.contains("material[1].region") && e.contains("outre"),
        "{e}"
    );
}

#[test]
fn edge_set_the_mesh_lacks_is_named() {
    let (e, _d) = error_of(&edited("edges = \"end\"", "edges = \"ends\""));
    assert!(
        e.contains("mechanical.symmetry[1].edges") && e.contains("'ends'"),
        "{e}"
    );
    let (e, _d) = error_of(&edited("name = \"inner_outer\"", "name = \"inner_outre\""));
    assert!(e.contains("inner_outre"), "{e}");
}

#[test]
fn negative_thickness_and_modulus_are_named() {
    let (e, _d) = error_of(&edited("r_out = 1.2", "r_out = 1.05"));
    assert!(
        e.contains("mesh.layer[1]") && e.contains("thickness"),
        "{e}"
    );
    let (e, _d) = error_of(&edited("youngs_modulus = 207e9", "youngs_modulus = -207e9"));
    assert!(
        e.contains("youngs_modulus") && e.contains("region 'inner'"),
        "{e}"
    );
    let vessel = std::fs::read_to_string(cases_dir().join("vessel.toml")).unwrap();
    let (e, _d) =
        error_of(&vessel.replacen("layer_thickness = 0.0064", "layer_thickness = -0.0064", 1));
    assert!(e.contains("mesh.layer_thickness"), "{e}");
}

#[test]
fn mesh_file_that_does_not_parse_is_named() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("broken.msh"),
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\ngarbage\n",
    )
    .unwrap();
    let text = "[mesh]\nfile = \"broken.msh\"\n";
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let c = case::load(&path).unwrap();
    let e = case::execute(&c, dir.path()).unwrap_err().to_string();
    assert!(!e.contains('\n'), "{e}");
    assert!(
        e.contains("bad.toml") && e.contains("mesh.file") && e.contains("broken.msh"),
        "{e}"
    );
    // a missing mesh file too
    let c = case::parse("[mesh]\nfile = \"nowhere.msh\"\n", &path).unwrap();
    let e = case::execute(&c, dir.path()).unwrap_err().to_string();
    assert!(e.contains("nowhere.msh"), "{e}");
}

#[test]
fn gmsh_physical_group_the_mesh_lacks_is_named() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/mesh/tests/data");
    let text = "[mesh]\nfile = \"two_blocks.msh\"\n[[interface]]\nname = \"joint\"\nbottom = \"left_face\"\ntop = \"no_such_face\"\n";
    let c = case::parse(text, Path::new("gmsh.toml")).unwrap();
    let e = case::execute(&c, &data).unwrap_err().to_string();
    assert!(e.contains("gmsh.toml") && e.contains("no_such_face"), "{e}");
}

/// The pairing tolerance of a Gmsh interface: a valid fraction pairs the
/// faces as before; a value outside (0, 0.5), or one given for an interface
/// the generator makes, is an error naming the key.
#[test]
fn pairing_tolerance_key() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/mesh/tests/data");
    let gmsh = |tol: &str| {
        format!(
            "[mesh]\nfile = \"two_blocks.msh\"\n[[interface]]\nname = \"joint\"\nbottom = \"left_face\"\ntop = \"right_face\"\npairing_tolerance = {tol}\n"
        )
    };
    let base = std::fs::read_to_string(cases_dir().join("two_blocks.toml")).unwrap();
    let with_tol = base.replacen(
        "[[interface]]\n",
        "[[interface]]\npairing_tolerance = 1e-3\n",
        1,
    );
    assert_ne!(with_tol, base, "two_blocks.toml declares an interface");
    let c = case::parse(&with_tol, &cases_dir().join("two_blocks.toml")).unwrap();
    let res = case::execute(&c, &cases_dir()).unwrap();
    assert_eq!(num(&res.summary, "/mesh/interface_elements"), 4.0);
    for bad in ["0.7", "0.0", "-1e-3"] {
        let c = case::parse(&gmsh(bad), Path::new("tol.toml")).unwrap();
        let e = case::execute(&c, &data).unwrap_err().to_string();
        assert!(
            e.contains("tol.toml") && e.contains("pairing_tolerance") && e.contains("(0, 0.5)"),
            "{bad}: {e}"
        );
    }
    let (e, _dir) = error_of(&edited(
        "name = \"inner_outer\"",
        "name = \"inner_outer\"\npairing_tolerance = 1e-3",
    ));
    assert!(
        e.contains("pairing_tolerance") && e.contains("generator"),
        "{e}"
    );
}

/// A Gmsh mesh with an interface declared from two physical curves: two
/// blocks pushed together by a uniform pressure carry it unchanged across
/// the contact.
#[test]
fn gmsh_two_blocks_transmit_the_pressure() {
    let (c, res) = run_example("two_blocks.toml");
    let p = c.mechanical.pressure[0].value;
    let v = &res.summary;
    assert_eq!(num(v, "/mesh/interface_elements"), 4.0);
    let pc = num(v, "/times/0/interfaces/joint/contact_pressure_mean");
    eprintln!("two blocks: contact pressure {pc:.6e} for {p:.6e}");
    assert!((pc / p - 1.0).abs() < 1e-3, "{pc}");
    for r in ["left", "right"] {
        let sxx = num(v, &format!("/times/0/regions/{r}/stress_mean/xx"));
        assert!((sxx / -p - 1.0).abs() < 1e-3, "{r}: {sxx}");
    }
}

/// `normals` of a joint: "smoothed" (default) or "element"; anything else
/// is named. On the axisymmetric shrink fit (no slip) both give the Lamé
/// pressure to the same 0.1 %.
#[test]
fn joint_normals_choice() {
    let (e, _d) = error_of(&edited(
        "cohesion = 0.0",
        "cohesion = 0.0\nnormals = \"nodal\"",
    ));
    assert!(e.contains("normals") && e.contains("nodal"), "{e}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("element.toml");
    std::fs::write(
        &path,
        edited("cohesion = 0.0", "cohesion = 0.0\nnormals = \"element\""),
    )
    .unwrap();
    let c = case::load(&path).unwrap();
    let res = case::execute(&c, &cases_dir()).unwrap();
    let p = num(
        &res.summary,
        "/times/0/interfaces/inner_outer/contact_pressure_mean",
    );
    assert!((p / 8.390324e6 - 1.0).abs() < 1e-3, "{p}");
}

// ---------------------------------------------------------------------------
// Element order and bonded interfaces
// ---------------------------------------------------------------------------

/// `[mesh] order = 1 | 2`: the generators make 6-node triangles on request,
/// a Gmsh file of 6-node triangles is order 2 by itself (an explicit
/// `order = 1` contradicting it is an error naming the key and the file),
/// `order = 2` promotes a file of 3-node triangles, and other values are an
/// error naming the key.
#[test]
fn mesh_order_key() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/mesh/tests/data");
    let lame = std::fs::read_to_string(cases_dir().join("lame.toml")).unwrap();
    let order = |text: &str, base: &Path| {
        let c = case::parse(text, Path::new("order.toml")).unwrap();
        tecon_cli::setup::build_mesh(&c, base).map(|m| (m.order(), m.n_nodes(), m.n_triangles()))
    };
    let p1 = order(&lame, &cases_dir()).unwrap();
    assert_eq!(p1.0, 1);
    let with = |o: &str| {
        lame.replacen(
            "generator = \"annulus\"",
            &format!("generator = \"annulus\"\norder = {o}"),
            1,
        )
    };
    let p2 = order(&with("2"), &cases_dir()).unwrap();
    assert_eq!((p2.0, p2.2), (2, p1.2), "same triangles, 6 nodes each");
    // 24 × 12 cells: (25·13) corners + 25·12 + 24·13 + 24·12 mid nodes
    assert_eq!(p2.1, 25 * 13 + 25 * 12 + 24 * 13 + 24 * 12);
    assert_eq!(order(&with("1"), &cases_dir()).unwrap(), p1);
    for bad in ["3", "0"] {
        let e = order(&with(bad), &cases_dir()).unwrap_err().to_string();
        assert!(e.contains("order.toml") && e.contains("mesh.order"), "{e}");
    }
    let vessel = std::fs::read_to_string(cases_dir().join("vessel.toml")).unwrap();
    let v2 = vessel.replacen(
        "generator = \"vessel\"",
        "generator = \"vessel\"\norder = 2",
        1,
    );
    assert_ne!(v2, vessel);
    assert_eq!(order(&v2, &cases_dir()).unwrap().0, 2);
    // Gmsh: the file's order, or the key's when it promotes a linear file
    let gmsh = |file: &str, o: &str| format!("[mesh]\nfile = \"{file}\"\n{o}");
    assert_eq!(order(&gmsh("rings_p2.msh", ""), &data).unwrap().0, 2);
    assert_eq!(
        order(&gmsh("rings_p2.msh", "order = 2\n"), &data)
            .unwrap()
            .0,
        2
    );
    let e = order(&gmsh("rings_p2.msh", "order = 1\n"), &data)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("mesh.order = 1") && e.contains("rings_p2.msh") && e.contains("6-node"),
        "{e}"
    );
    assert_eq!(order(&gmsh("two_blocks.msh", ""), &data).unwrap().0, 1);
    assert_eq!(
        order(&gmsh("two_blocks.msh", "order = 2\n"), &data)
            .unwrap()
            .0,
        2
    );
}

/// A shrink-free thick cylinder of two bonded rings is the one-piece Lamé
/// cylinder: u_r at the bore within 0.5 % of Lamé on this coarse mesh (the
/// observed order of the tie is asserted in crates/elastic/tests/tie.rs).
/// A bonded joint takes no penalty, friction or normals key, and its
/// conductance must be a constant.
#[test]
fn bonded_rings_are_the_lame_cylinder() {
    let text = "[mesh]\ngenerator = \"annulus\"\ntheta0 = 0.0\ntheta1 = 90.0\nsegments = 24\n\
[[mesh.layer]]\nname = \"inner\"\nr_in = 1.0\nr_out = 1.25\nrows = 6\n\
[[mesh.layer]]\nname = \"outer\"\nr_in = 1.25\nr_out = 1.5\nrows = 6\n\
[[material]]\nregion = \"inner\"\nyoungs_modulus = 207e9\npoisson_ratio = 0.3\n\
[[material]]\nregion = \"outer\"\nyoungs_modulus = 207e9\npoisson_ratio = 0.3\n\
[[interface]]\nname = \"inner_outer\"\n[interface.joint]\nlaw = \"bonded\"\n\
[mechanical]\n[[mechanical.symmetry]]\nedges = \"start\"\n[[mechanical.symmetry]]\nedges = \"end\"\n\
[[mechanical.pressure]]\nedges = \"inner\"\nvalue = 100e6\n\
[output]\nprobes = [[1.0, 0.0]]\n";
    let c = case::parse(text, Path::new("bonded.toml")).unwrap();
    let res = case::execute(&c, &cases_dir()).unwrap();
    let lame = LameCylinder {
        a: 1.0,
        b: 1.5,
        p: 100e6,
        e: 207e9,
        nu: 0.3,
    };
    let node = res.probes[0].1;
    let ux = res.states[0].displacement[2 * node];
    let err = ux / lame.u_r(1.0) - 1.0;
    assert!(
        err.abs() < 5e-3,
        "bore u_r {ux} against Lamé {}: {err:e}",
        lame.u_r(1.0)
    );
    assert_eq!(res.summary["joints"]["inner_outer"]["law"], "bonded");
    assert!(
        res.states[0].interface.is_empty(),
        "a tie has no interface points"
    );

    for (extra, key) in [
        ("k_n = 1e15\n", "k_n"),
        ("penalty_factor = 100.0\n", "penalty_factor"),
        ("friction = 0.3\n", "friction"),
        ("normals = \"element\"\n", "normals"),
    ] {
        let bad = text.replacen(
            "law = \"bonded\"\n",
            &format!("law = \"bonded\"\n{extra}"),
            1,
        );
        let c = case::parse(&bad, Path::new("bonded.toml")).unwrap();
        let e = case::execute(&c, &cases_dir()).unwrap_err().to_string();
        assert!(
            e.contains("bonded.toml") && e.contains(key) && e.contains("bonded"),
            "{e}"
        );
    }
}

/// The shrink fit as a full ring (0°–360°, 128 intervals, no symmetry
/// edges): without supports the two rings are free and the error says
/// which keys supply them; with `hold_rigid_modes` on the bore (a
/// statically determinate support, whose reactions vanish under the
/// self-equilibrated shrink fit) the contact pressure is the two-cylinder
/// answer, 8.3903 MPa, to 4.5e-4 (the quarter ring of 32 intervals
/// gives the same to 1e-3).
#[test]
fn a_full_ring_is_held_by_a_statically_determinate_support() {
    let full = edited("theta1 = 90.0", "theta1 = 360.0")
        .replacen("segments = 32 ", "segments = 128", 1)
        .replacen(
            "[[mechanical.symmetry]]\nedges = \"start\"                # θ = 0\n[[mechanical.symmetry]]\nedges = \"end\"                  # θ = 90°\n",
            "",
            1,
        );
    assert!(
        !full.contains("mechanical.symmetry") && full.contains("segments = 128"),
        "the lines moved"
    );
    let (e, _d) = error_of(&full);
    assert!(
        e.contains("not constrained") && e.contains("hold_rigid_modes"),
        "{e}"
    );
    let held = full.replacen(
        "[mechanical]\n",
        "[mechanical]\nhold_rigid_modes = \"inner\"\n",
        1,
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("full_ring.toml");
    std::fs::write(&path, &held).unwrap();
    let c = case::load(&path).unwrap();
    let res = case::execute(&c, &cases_dir()).unwrap();
    let p = num(
        &res.summary,
        "/times/0/interfaces/inner_outer/contact_pressure_mean",
    );
    eprintln!("full-ring shrink fit: p = {p:.6e}");
    assert!((p / 8.390324e6 - 1.0).abs() < 1e-3, "p = {p}");
    // an edge set that does not exist is named
    let (e, _d) = error_of(&full.replacen(
        "[mechanical]\n",
        "[mechanical]\nhold_rigid_modes = \"bore\"\n",
        1,
    ));
    assert!(e.contains("hold_rigid_modes") && e.contains("bore"), "{e}");
}

/// A body that every interface point lets go of is held by nothing: the
/// shrink fit's inner ring made 50 K colder than the outer one, with only
/// the outer ring's outer surface fixed, parts from it. The contact solve
/// converges (every point open), but the inner ring's displacement is then
/// arbitrary: it used to run to exit 0 with the ring drifting and 130 MPa
/// of stress in a ring that no force acts on. Now an error names it.
#[test]
fn a_body_that_every_contact_lets_go_of_is_named() {
    let text = edited("value = 71.0", "value = -29.0").replacen(
        "[[mechanical.symmetry]]\nedges = \"start\"                # θ = 0\n[[mechanical.symmetry]]\nedges = \"end\"                  # θ = 90°",
        "[[mechanical.fix]]\nset = \"outer\"\ncomponent = \"x\"\nvalue = 0.0\n[[mechanical.fix]]\nset = \"outer\"\ncomponent = \"y\"\nvalue = 0.0",
        1,
    );
    assert!(
        text.contains("[[mechanical.fix]]"),
        "the symmetry lines moved"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("floating.toml");
    std::fs::write(&path, &text).unwrap();
    let c = case::load(&path).unwrap();
    let e = case::execute(&c, &cases_dir()).unwrap_err().to_string();
    assert!(
        e.contains("body 'inner'")
            && e.contains("held by nothing")
            && e.contains("every interface point"),
        "{e}"
    );
}

/// `mechanical.exact_passes = true` solves every Newton pass to the full
/// tolerances (the cross-check of the inexact passes that a friction-limit
/// update follows): the shrink fit (μ = 0.3) takes one inexact pass by
/// default and none with the key, and its contact pressure is the same to
/// the solver tolerances (the last pass is exact either way). A value that
/// is not a boolean is refused, naming the key.
#[test]
fn exact_passes_key_gives_the_same_shrink_fit() {
    let run = |text: &str| {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("fit.toml");
        std::fs::write(&path, text).unwrap();
        let c = case::load(&path).unwrap();
        case::execute(&c, dir.path()).unwrap().summary
    };
    let key = "/times/0/interfaces/inner_outer/contact_pressure_mean";
    let inexact = run(&edited("[mechanical]\n", "[mechanical]\n"));
    let exact = run(&edited(
        "[mechanical]\n",
        "[mechanical]\nexact_passes = true\n",
    ));
    assert_eq!(num(&exact, "/newton_inexact_passes"), 0.0);
    assert!(num(&inexact, "/newton_inexact_passes") > 0.0);
    let (a, b) = (num(&exact, key), num(&inexact, key));
    assert!(((a - b) / a).abs() < 1e-8, "exact {a}, inexact {b}");
    let (e, _d) = error_of(&edited(
        "[mechanical]\n",
        "[mechanical]\nexact_passes = 3\n",
    ));
    assert!(e.contains("exact_passes"), "{e}");
}

/// `mechanical.coarse_levels` outside 1 to 6 is refused, naming the key
/// and the range (the shrink fit's passes are not condensed, so a valid
/// value changes nothing there: it is only parsed).
#[test]
fn coarse_levels_key_is_checked() {
    for bad in ["0", "7"] {
        let (e, _d) = error_of(&edited(
            "[mechanical]\n",
            &format!("[mechanical]\ncoarse_levels = {bad}\n"),
        ));
        assert!(
            e.contains(&format!("mechanical.coarse_levels = {bad}")) && e.contains("1 to 6"),
            "{e}"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fit.toml");
    std::fs::write(
        &path,
        edited("[mechanical]\n", "[mechanical]\ncoarse_levels = 3\n"),
    )
    .unwrap();
    let c = case::load(&path).unwrap();
    assert!(case::execute(&c, dir.path()).is_ok());
}
