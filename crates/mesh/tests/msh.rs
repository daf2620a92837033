//! Gmsh MSH 4.1 import against meshes written by Gmsh 4.15 (tests/data/make_msh.py).
//!
//! Reference: node/triangle counts and areas computed by the generating script
//! from Gmsh's own data (tests/data/reference.json).
//! Goal: ASCII and binary files give the same mesh; physical groups become
//! regions and edge sets; interfaces pair by geometry; every failure names the
//! file and the place.
//!
//! ```text
//!  two_blocks:  ┌────┐┌────┐   left | right, separate nodes on x = 1
//!               │left││rght│   curves west, east, left_face, right_face,
//!               └────┘└────┘   bottom, top
//! ```

use std::path::PathBuf;

use tecon_mesh::{MeshError, read_msh};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn reference(case: &str, key: &str) -> f64 {
    let text = std::fs::read_to_string(data("reference.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v[case][key].as_f64().unwrap()
}

#[test]
fn ascii_two_blocks_matches_gmsh() {
    let m = read_msh(data("two_blocks.msh")).unwrap();
    assert_eq!(
        m.n_nodes() as f64,
        reference("two_blocks", "nodes_used_by_triangles")
    );
    assert_eq!(m.n_triangles() as f64, reference("two_blocks", "triangles"));
    let area: f64 = m.areas().iter().sum();
    assert!((area - reference("two_blocks", "area")).abs() < 1e-12);
    assert_eq!(m.region_names(), ["left", "right"]);
    assert_eq!(m.bodies().len(), 2);
    for set in ["west", "east", "left_face", "right_face"] {
        assert_eq!(m.edge_set(set).unwrap().len(), 4, "{set}");
    }
    assert_eq!(m.edge_set("bottom").unwrap().len(), 8);
    let left: f64 = m
        .region_elements("left")
        .unwrap()
        .iter()
        .map(|&e| m.areas()[e])
        .sum();
    assert!((left - 1.0).abs() < 1e-12);
}

#[test]
fn binary_equals_ascii() {
    let a = read_msh(data("two_blocks.msh")).unwrap();
    let b = read_msh(data("two_blocks_bin.msh")).unwrap();
    // ASCII carries 16 significant digits, binary the full double.
    assert_eq!(a.triangles(), b.triangles());
    assert_eq!(a.edge_sets(), b.edge_sets());
    assert_eq!(a.region_names(), b.region_names());
    assert_eq!(a.element_regions(), b.element_regions());
    for (p, q) in a.nodes().iter().zip(b.nodes()) {
        assert!((p[0] - q[0]).abs() < 1e-15 && (p[1] - q[1]).abs() < 1e-15);
    }
}

#[test]
fn interface_from_two_physical_curves() {
    let mut m = read_msh(data("two_blocks.msh")).unwrap();
    m.add_interface("joint", "left_face", "right_face", None)
        .unwrap();
    let els = &m.interface("joint").unwrap().elements;
    assert_eq!(els.len(), 4);
    for &[n1, n2, n3, n4] in els {
        let x = m.nodes();
        // Gmsh places the nodes of the two coincident curves 1e-12 apart
        assert!((x[n1][1] - x[n4][1]).abs() < 1e-9 && x[n1][0] == x[n4][0]);
        assert!((x[n2][1] - x[n3][1]).abs() < 1e-9 && x[n2][0] == x[n3][0]);
        // the top (right) body lies on the left of 1→2: 1→2 runs downward (−y)
        assert!(x[n2][1] < x[n1][1]);
        assert!((x[n1][0] - 1.0).abs() < 1e-14);
    }
}

#[test]
fn unstructured_plate_with_hole() {
    let m = read_msh(data("plate_hole.msh")).unwrap();
    assert_eq!(
        m.n_nodes() as f64,
        reference("plate_hole", "nodes_used_by_triangles")
    );
    assert_eq!(m.n_triangles() as f64, reference("plate_hole", "triangles"));
    let area: f64 = m.areas().iter().sum();
    assert!((area - reference("plate_hole", "area")).abs() < 1e-12);
    // polygonal hole of radius 0.2: area close to 1 − π 0.04
    assert!((area - (1.0 - std::f64::consts::PI * 0.04)).abs() < 2e-3);
    let hole_len: f64 = m
        .edge_set("hole")
        .unwrap()
        .iter()
        .map(|&[a, b]| {
            let (p, q) = (m.nodes()[a], m.nodes()[b]);
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
        })
        .sum();
    assert!((hole_len - 0.4 * std::f64::consts::PI).abs() < 5e-3);
}

#[test]
fn unsupported_element_type_is_named() {
    let e = read_msh(data("quads.msh")).unwrap_err();
    assert!(
        matches!(e, MeshError::UnsupportedElement { type_id: 3, .. }),
        "{e}"
    );
    let s = e.to_string();
    assert!(s.contains("quads.msh") && s.contains("Qua4"), "{s}");
}

#[test]
fn old_version_is_rejected_with_advice() {
    let e = read_msh(data("old_format.msh")).unwrap_err();
    let s = e.to_string();
    assert!(
        s.contains("old_format.msh: line 2") && s.contains("'2.2'") && s.contains("msh41"),
        "{s}"
    );
}

#[test]
fn truncated_file_reports_a_line() {
    let bytes = std::fs::read(data("two_blocks.msh")).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    let cut = text.find("$EndNodes").unwrap();
    // drop the last node line's coordinates: the $Nodes section no longer parses
    let broken = format!("{}garbage here\n{}", &text[..cut], &text[cut..]);
    let line_of_garbage = text[..cut].matches('\n').count() + 1;
    let e = tecon_mesh::msh::parse_msh(broken.as_bytes(), std::path::Path::new("broken.msh"))
        .unwrap_err();
    match &e {
        MeshError::MshParse { location, .. } => {
            let line: usize = location.trim_start_matches("line ").parse().unwrap();
            assert_eq!(line, line_of_garbage, "{e}");
        }
        other => panic!("unexpected {other}"),
    }
    assert!(e.to_string().starts_with("broken.msh: line "), "{e}");
    let e = read_msh(data("missing.msh")).unwrap_err();
    assert!(
        matches!(e, MeshError::Io { .. }) && e.to_string().contains("missing.msh"),
        "{e}"
    );
    let e = tecon_mesh::msh::parse_msh(b"hello", std::path::Path::new("x.msh")).unwrap_err();
    assert!(e.to_string().contains("not a Gmsh file"), "{e}");
}
