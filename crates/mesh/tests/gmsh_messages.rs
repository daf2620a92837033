//! Messages about a Gmsh mesh in the user's terms, against meshes written by
//! Gmsh 4.15 (`python3 tests/data/make_msh.py diagnostics`).
//!
//! Reference: the .msh files themselves: a Gmsh node tag an error gives must
//! be, in the file's `$Nodes`, the node at the coordinates the error gives
//! (read here by a separate little parser of the ASCII format).
//! Goal: errors name nodes and triangles by their Gmsh tags too; an empty
//! physical group is reported as empty (with its dimension), not missing; a
//! surface in two physical surfaces is refused naming both; a curve in two
//! physical curves is in both edge sets; physical points become node sets;
//! bodies touching at coincident nodes without an interface, and a mesh that
//! looks like millimetres, get warnings.
//!
//! ```text
//!  groups.msh:   4 ┌─────┐ 3     plate; bottom = 1–2; supported = 1–2, 2–3;
//!                  │  ·5 │       corner = point 1; centre = point 5 (not
//!                1 └─────┘ 2     embedded); ghost (curve), vol: no entity
//!  unmerged.msh: ┌───┐┌───┐      one physical surface, separate nodes on x = 1
//! ```

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use tecon_mesh::{Mesh, MeshError, MeshNotice, read_msh};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Node tag → (x, y) of an ASCII MSH 4.1 file, read block by block.
fn file_nodes(path: &Path) -> HashMap<u64, [f64; 2]> {
    let text = std::fs::read_to_string(path).unwrap();
    let start = text.find("$Nodes").unwrap();
    let end = text.find("$EndNodes").unwrap();
    let mut lines = text[start..end].lines().skip(1);
    let head: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    let mut out = HashMap::new();
    for _ in 0..head[0] {
        let block: Vec<usize> = lines
            .next()
            .unwrap()
            .split_whitespace()
            .map(|w| w.parse().unwrap())
            .collect();
        let n = block[3];
        let tags: Vec<u64> = (0..n)
            .map(|_| lines.next().unwrap().trim().parse().unwrap())
            .collect();
        for tag in tags {
            let c: Vec<f64> = lines
                .next()
                .unwrap()
                .split_whitespace()
                .map(|w| w.parse().unwrap())
                .collect();
            out.insert(tag, [c[0], c[1]]);
        }
    }
    out
}

/// Every number that follows `key` in `s`.
fn numbers_after(s: &str, key: &str) -> Vec<u64> {
    s.match_indices(key)
        .map(|(i, _)| {
            s[i + key.len()..]
                .chars()
                .take_while(char::is_ascii_digit)
                .collect::<String>()
                .parse()
                .unwrap()
        })
        .collect()
}

/// The first "(x, y)" in `s`.
fn first_point(s: &str) -> [f64; 2] {
    let i = s.find(" at (").unwrap() + 5;
    let j = i + s[i..].find(')').unwrap();
    let v: Vec<f64> = s[i..j].split(", ").map(|w| w.parse().unwrap()).collect();
    [v[0], v[1]]
}

#[test]
fn the_mesh_keeps_the_gmsh_tags_of_its_nodes_and_triangles() {
    let path = data("two_blocks.msh");
    let m = read_msh(&path).unwrap();
    let file = file_nodes(&path);
    let tags = m
        .gmsh_tags()
        .expect("a mesh read from a .msh file has tags");
    assert_eq!(tags.nodes.len(), m.n_nodes());
    assert_eq!(tags.elements.len(), m.n_triangles());
    for (i, p) in m.nodes().iter().enumerate() {
        assert_eq!(file[&tags.nodes[i]], *p, "node {i}");
    }
    // element tags are unique and the labels give them
    let mut e = tags.elements.clone();
    e.sort_unstable();
    e.dedup();
    assert_eq!(e.len(), m.n_triangles());
    assert_eq!(
        m.node_label(3),
        format!("node 3 (Gmsh node tag {})", tags.nodes[3])
    );
    assert_eq!(
        m.triangle_label(0),
        format!("triangle 0 (Gmsh element tag {})", tags.elements[0])
    );
    // a generated mesh has none, and its labels are the indices
    let g = tecon_mesh::rectangle(0.0, 0.0, 1.0, 1.0, 2, 2).unwrap();
    assert!(g.gmsh_tags().is_none());
    assert_eq!(g.node_label(3), "node 3");
    assert_eq!(g.triangle_label(0), "triangle 0");
    // promoted to 6-node triangles, the corners keep their tags, the new mid
    // nodes have none
    let p2 = m.to_quadratic(&[]).unwrap();
    assert_eq!(p2.gmsh_tags(), m.gmsh_tags());
    assert_eq!(p2.node_label(3), m.node_label(3));
    assert_eq!(p2.node_label(m.n_nodes()), format!("node {}", m.n_nodes()));
}

#[test]
fn coincident_nodes_in_one_region_name_their_gmsh_tags() {
    let path = data("unmerged.msh");
    let e = read_msh(&path).unwrap_err();
    let s = e.to_string();
    assert!(
        s.starts_with(&format!("{}: nodes ", path.display()))
            && s.contains("coincide")
            && s.contains("region 'plate'")
            && s.contains("Coherence"),
        "{s}"
    );
    let tags = numbers_after(&s, "(Gmsh node tag ");
    assert_eq!(tags.len(), 2, "{s}");
    assert_ne!(tags[0], tags[1]);
    let p = first_point(&s);
    assert_eq!(p[0], 1.0, "{s}");
    let file = file_nodes(&path);
    for t in tags {
        let q = file[&t];
        assert!(
            (q[0] - p[0]).abs() < 1e-12 && (q[1] - p[1]).abs() < 1e-12,
            "tag {t} is at {q:?}, the message says {p:?}: {s}"
        );
    }
}

#[test]
fn interface_errors_name_gmsh_tags() {
    let path = data("two_blocks.msh");
    let mut m = read_msh(&path).unwrap();
    // the left face against the top: no node of left_face faces one of top
    let e = m
        .add_interface("joint", "left_face", "top", None)
        .unwrap_err();
    assert!(
        matches!(e, MeshError::InterfaceNotFacing { .. }),
        "the error keeps its kind: {e}"
    );
    let s = e.to_string();
    let tags = numbers_after(&s, "(Gmsh node tag ");
    // the bottom node and the nearest top node
    assert_eq!(tags.len(), 2, "{s}");
    let file = file_nodes(&path);
    let p = first_point(&s);
    let q = file[&tags[0]];
    assert!(
        (q[0] - p[0]).abs() < 1e-12 && (q[1] - p[1]).abs() < 1e-12,
        "{s}"
    );
    if let MeshError::InterfaceNotFacing {
        bottom, nearest, ..
    } = e
    {
        let t = m.gmsh_tags().unwrap();
        assert_eq!(tags, [t.nodes[bottom], t.nodes[nearest]]);
    }
    // a generated mesh: the same error without tags
    let mut g = tecon_mesh::rectangle(0.0, 0.0, 1.0, 1.0, 2, 2).unwrap();
    let b = g.boundary_edges();
    g.add_edge_set("a", b[..1].to_vec()).unwrap();
    g.add_edge_set("b", b[3..4].to_vec()).unwrap();
    let s = g
        .add_interface("j", "a", "b", None)
        .unwrap_err()
        .to_string();
    assert!(!s.contains("Gmsh"), "{s}");
}

/// A hand-written file: one degenerate triangle (three collinear nodes) with
/// node tags 101..104 and element tags 7, 8.
const DEGENERATE: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
1
2 1 \"plate\"
$EndPhysicalNames
$Entities
0 0 1 0
1 0 0 0 2 1 0 1 1 0
$EndEntities
$Nodes
1 4 101 104
2 1 0 4
101
102
103
104
0 0 0
1 0 0
2 0 0
0 1 0
$EndNodes
$Elements
1 2 7 8
2 1 2 2
7 101 102 104
8 101 102 103
$EndElements
";

#[test]
fn a_degenerate_triangle_names_its_gmsh_element_and_node_tags() {
    let e = tecon_mesh::msh::parse_msh(DEGENERATE.as_bytes(), Path::new("flat.msh")).unwrap_err();
    let s = e.to_string();
    assert!(
        s.starts_with("flat.msh: triangle 1 (Gmsh element tag 8) has zero area")
            && s.contains(
                "nodes 0 (Gmsh node tag 101), 1 (Gmsh node tag 102), 2 (Gmsh node tag 103)"
            ),
        "{s}"
    );
}

#[test]
fn an_empty_physical_group_is_reported_as_empty_with_its_dimension() {
    let m = read_msh(data("groups.msh")).unwrap();
    let e = m.edge_set("ghost").unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::EmptyGroup {
                dim: 1,
                kind: "edge set",
                ..
            }
        ),
        "{e}"
    );
    let s = e.to_string();
    assert!(
        s.contains("'ghost' as a physical curve (dimension 1)")
            && s.contains("no 2- or 3-node line")
            && s.contains("bottom, supported"),
        "{s}"
    );
    let e = m.region_index("vol").unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::EmptyGroup {
                dim: 3,
                kind: "region",
                ..
            }
        ),
        "{e}"
    );
    assert!(
        e.to_string().contains("physical volume (dimension 3)"),
        "{e}"
    );
    // a name the file does not have at all is missing, as before
    let e = m.edge_set("nothing").unwrap_err();
    assert!(matches!(e, MeshError::UnknownName { .. }), "{e}");
    // the same names on a generated mesh: missing
    let g = tecon_mesh::rectangle(0.0, 0.0, 1.0, 1.0, 2, 2).unwrap();
    assert!(matches!(
        g.edge_set("ghost").unwrap_err(),
        MeshError::UnknownName { .. }
    ));
    // the groups that hold something are not listed as empty
    let empty: Vec<&str> = m
        .gmsh_tags()
        .unwrap()
        .empty_groups
        .iter()
        .map(|(_, n)| n.as_str())
        .collect();
    assert_eq!(empty, ["centre", "ghost", "vol"]);
}

#[test]
fn a_curve_in_two_physical_curves_is_in_both_edge_sets() {
    let m = read_msh(data("groups.msh")).unwrap();
    let bottom = m.edge_set("bottom").unwrap().to_vec();
    let supported = m.edge_set("supported").unwrap();
    let x = m.nodes();
    assert!(!bottom.is_empty());
    for e in &bottom {
        assert!(supported.contains(e), "{e:?}");
        assert!(x[e[0]][1] == 0.0 && x[e[1]][1] == 0.0);
    }
    // the rest of `supported` is the side x = 1
    let side: Vec<_> = supported.iter().filter(|e| !bottom.contains(e)).collect();
    assert!(!side.is_empty());
    for e in side {
        assert!((x[e[0]][0] - 1.0).abs() < 1e-12 && (x[e[1]][0] - 1.0).abs() < 1e-12);
    }
}

#[test]
fn a_surface_in_two_physical_surfaces_is_refused_naming_both() {
    let e = read_msh(data("surface_two_groups.msh")).unwrap_err();
    let s = e.to_string();
    assert!(
        s.contains("surface_two_groups.msh: surface 1 is in 2 physical surfaces, 'plate' (tag 1) and 'steel' (tag 2)")
            && s.contains("keep the surface in one physical surface"),
        "{s}"
    );
}

#[test]
fn physical_points_become_node_sets_and_points_off_the_mesh_are_named() {
    let path = data("groups.msh");
    let m = read_msh(&path).unwrap();
    let corner = m.node_set("corner").unwrap();
    assert_eq!(corner.len(), 1);
    assert_eq!(m.nodes()[corner[0]], [0.0, 0.0]);
    // the centre point is no node of the triangles: a warning, and its set
    // is an empty group
    let off: Vec<&MeshNotice> = m
        .notices()
        .iter()
        .filter(|n| matches!(n, MeshNotice::PointOffMesh { .. }))
        .collect();
    assert_eq!(off.len(), 1, "{:?}", m.notices());
    let MeshNotice::PointOffMesh {
        group,
        node_tag,
        x,
        y,
    } = off[0]
    else {
        unreachable!()
    };
    assert_eq!((group.as_str(), *x, *y), ("centre", 0.5, 0.5));
    assert_eq!(file_nodes(&path)[node_tag], [0.5, 0.5]);
    assert!(off[0].is_warning());
    let s = off[0].to_string();
    assert!(
        s.starts_with("physical point 'centre': its node (Gmsh node tag 5)") && s.contains("embed"),
        "{s}"
    );
    let e = m.node_set("centre").unwrap_err();
    assert!(matches!(e, MeshError::EmptyGroup { dim: 0, .. }), "{e}");
    // a physical point named like a physical curve is refused
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("0 4 \"corner\"", "0 4 \"bottom\"");
    let e = tecon_mesh::msh::parse_msh(text.as_bytes(), Path::new("clash.msh")).unwrap_err();
    assert!(
        e.to_string()
            .contains("'bottom' names both a physical point and a physical curve"),
        "{e}"
    );
}

fn touching(m: &Mesh) -> Vec<MeshNotice> {
    m.warnings()
        .into_iter()
        .filter(|n| matches!(n, MeshNotice::UnjoinedTouchingBodies { .. }))
        .collect()
}

#[test]
fn bodies_touching_without_an_interface_get_a_warning() {
    let mut m = read_msh(data("two_blocks.msh")).unwrap();
    let w = touching(&m);
    assert_eq!(w.len(), 1, "{w:?}");
    let MeshNotice::UnjoinedTouchingBodies {
        first,
        second,
        pairs,
        ..
    } = &w[0]
    else {
        unreachable!()
    };
    // five nodes on each face x = 1 (transfinite curves of 5 nodes)
    assert_eq!(
        (first.as_str(), second.as_str(), *pairs),
        ("left", "right", 5)
    );
    let s = w[0].to_string();
    assert!(
        s.starts_with(
            "bodies 'left' and 'right' touch at 5 pair(s) of coincident nodes (e.g. node "
        ) && s.contains("(Gmsh node tag ")
            && s.contains("[[interface]]"),
        "{s}"
    );
    m.add_interface("joint", "left_face", "right_face", None)
        .unwrap();
    assert!(touching(&m).is_empty(), "{:?}", touching(&m));

    // Gmsh's separately meshed arcs: facing nodes a few nm apart still count
    let mut m = read_msh(data("vessel_sector_lc002.msh")).unwrap();
    let w = touching(&m);
    assert_eq!(w.len(), 1, "{w:?}");
    let faces = m.edge_set_nodes("inner_face").unwrap().len();
    assert!(
        matches!(&w[0], MeshNotice::UnjoinedTouchingBodies { pairs, .. } if *pairs == faces),
        "{w:?}, {faces} nodes on the face"
    );
    m.add_interface("joint", "inner_face", "outer_face", None)
        .unwrap();
    assert!(touching(&m).is_empty());

    // 6-node triangles: the corners are counted (the mid nodes follow them)
    let mut m = read_msh(data("rings_p2.msh")).unwrap();
    assert_eq!(touching(&m).len(), 1);
    m.add_interface("joint", "inner_face", "outer_face", None)
        .unwrap();
    assert!(touching(&m).is_empty());

    // one body: nothing to say; generated meshes join their bodies
    assert!(touching(&read_msh(data("plate_hole.msh")).unwrap()).is_empty());
    let v =
        tecon_mesh::vessel_mesh(&Default::default(), &tecon_mesh::VesselMeshSpec::paper()).unwrap();
    assert!(v.bodies().len() > 1);
    assert!(v.warnings().is_empty(), "{:?}", v.warnings());
}

#[test]
fn a_mesh_that_looks_like_millimetres_gets_a_units_hint() {
    let mm = read_msh(data("plate_mm.msh")).unwrap();
    let hints: Vec<&MeshNotice> = mm
        .notices()
        .iter()
        .filter(|n| matches!(n, MeshNotice::LooksLikeMillimetres { .. }))
        .collect();
    assert_eq!(
        hints,
        [&MeshNotice::LooksLikeMillimetres { size: 200.0 }],
        "{:?}",
        mm.notices()
    );
    assert_eq!(mm.warnings().len(), 1);
    let s = hints[0].to_string();
    assert!(
        s.starts_with("the mesh is 200 across: does it use millimetres?")
            && s.contains("in metres")
            && s.contains("Mesh.ScalingFactor = 0.001"),
        "{s}"
    );
    // saved with Mesh.ScalingFactor = 0.001: metres, no hint
    let m = read_msh(data("plate_m.msh")).unwrap();
    assert!(m.warnings().is_empty(), "{:?}", m.warnings());
    assert_eq!(m.n_nodes(), mm.n_nodes());
    for (p, q) in m.nodes().iter().zip(mm.nodes()) {
        assert!((1000.0 * p[0] - q[0]).abs() < 1e-9 && (1000.0 * p[1] - q[1]).abs() < 1e-9);
    }
}
