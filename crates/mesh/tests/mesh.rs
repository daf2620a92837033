//! Mesh construction, validation, generators and VTK output.
//!
//! Reference: DESIGN.md §2 (the published vessel mesh: 108 nodes, about 134
//! triangles, 17 interface elements) and the geometry of the annulus.
//! Goal: every generator yields a valid mesh with the right counts, areas and
//! interface orientation; every error path names what is wrong.

use std::f64::consts::PI;

use tecon_mesh::{
    Mesh, MeshError, MeshNotice, RingLayer, VesselGeometry, VesselMeshSpec, layered_annulus,
    rectangle, vessel_mesh,
};

fn total_area(m: &Mesh) -> f64 {
    m.areas().iter().sum()
}

fn region_area(m: &Mesh, name: &str) -> f64 {
    let a = m.areas();
    m.region_elements(name).unwrap().iter().map(|&e| a[e]).sum()
}

/// ```text
///   layer  ro ┌──────── ... ──┐   18 stations θ = 0 … π, 2 rows per body
///          rc ├────────  ... ─┤   (separate nodes on the interface rc)
///   core   rc ├────────  ... ─┤
///          ri └──────── ... ──┘
/// ```
#[test]
fn paper_vessel_mesh_has_the_published_density() {
    let g = VesselGeometry::default();
    let m = vessel_mesh(&g, &VesselMeshSpec::paper()).unwrap();
    assert_eq!(m.n_nodes(), 108);
    assert_eq!(m.n_triangles(), 136);
    assert_eq!(m.interface("core_layer").unwrap().elements.len(), 17);
    assert!(m.notices().is_empty(), "generator must emit CCW triangles");
    let names: Vec<&str> = m.bodies().iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["core", "layer+weld"]);
    let (ri, rc, ro) = (g.inner_radius, g.interface_radius(), g.outer_radius());
    // The mesh is the polygonal annulus through the stations.
    let t = tecon_mesh::vessel::station_angles(&g, &VesselMeshSpec::paper());
    let exact: f64 = t
        .windows(2)
        .map(|w| 0.5 * (ro * ro - ri * ri) * (w[1] - w[0]).sin())
        .sum();
    assert!((total_area(&m) - exact).abs() / exact < 1e-13);
    // The weld is the layer's first interval, of half-angle θ_w.
    let weld = 0.5 * g.weld_half_angle().sin() * (ro * ro - rc * rc);
    assert!((region_area(&m, "weld") - weld).abs() / weld < 1e-12);
}

#[test]
fn interface_elements_face_and_point_outward() {
    let m = vessel_mesh(
        &VesselGeometry::default(),
        &VesselMeshSpec::refined(1).unwrap(),
    )
    .unwrap();
    let x = m.nodes();
    for el in &m.interface("core_layer").unwrap().elements {
        let [n1, n2, n3, n4] = *el;
        let d =
            |a: usize, b: usize| ((x[a][0] - x[b][0]).powi(2) + (x[a][1] - x[b][1]).powi(2)).sqrt();
        assert!(d(n1, n4) < 1e-12 && d(n2, n3) < 1e-12);
        // left normal of 1→2 points away from the centre (into the layer)
        let t = [x[n2][0] - x[n1][0], x[n2][1] - x[n1][1]];
        let nrm = [-t[1], t[0]];
        let mid = [(x[n1][0] + x[n2][0]) / 2.0, (x[n1][1] + x[n2][1]) / 2.0];
        assert!(nrm[0] * mid[0] + nrm[1] * mid[1] > 0.0);
        assert_eq!(m.node_bodies()[n1], 0);
        assert_eq!(m.node_bodies()[n4], 1);
    }
}

#[test]
fn refined_presets_and_fused_weld() {
    for level in 0..4 {
        let spec = VesselMeshSpec::refined(level).unwrap();
        let m = vessel_mesh(&VesselGeometry::default(), &spec).unwrap();
        assert_eq!(m.n_triangles(), 136 * 4usize.pow(level));
        assert_eq!(m.n_triangles(), spec.n_triangles());
    }
    assert_eq!(VesselMeshSpec::refined(7).unwrap().n_triangles(), 2_228_224);
    let spec = VesselMeshSpec {
        fused_weld: true,
        ..VesselMeshSpec::paper()
    };
    let m = vessel_mesh(&VesselGeometry::default(), &spec).unwrap();
    assert_eq!(m.bodies().len(), 1);
    assert_eq!(m.bodies()[0].name, "core+layer+weld");
    assert_eq!(m.interface("core_layer").unwrap().elements.len(), 16);
    // the layer nodes at θ = 0 and θ = θ_w on the interface are the core's
    assert_eq!(m.n_nodes(), 106);
}

#[test]
fn station_angles_are_graded_away_from_the_weld() {
    let g = VesselGeometry::default();
    let t = tecon_mesh::vessel::station_angles(&g, &VesselMeshSpec::paper());
    assert_eq!(t.len(), 18);
    assert_eq!(t[0], 0.0);
    assert!((t[1] - g.weld_half_angle()).abs() < 1e-15);
    assert_eq!(*t.last().unwrap(), PI);
    let h: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    for w in h[1..].windows(2) {
        assert!(w[1] > w[0], "intervals grow toward θ = π: {h:?}");
    }
    assert!((h[1] / h[0] - 1.5).abs() < 1e-12);
}

#[test]
fn bad_generator_parameters_are_named() {
    let spec = VesselMeshSpec {
        core_rows: 0,
        ..VesselMeshSpec::paper()
    };
    let e = vessel_mesh(&VesselGeometry::default(), &spec).unwrap_err();
    assert!(e.to_string().contains("core_rows"), "{e}");
    let geo = VesselGeometry {
        layer_thickness: -1.0,
        ..Default::default()
    };
    let e = vessel_mesh(&geo, &VesselMeshSpec::paper()).unwrap_err();
    assert!(e.to_string().contains("layer_thickness"), "{e}");
    assert!(VesselMeshSpec::refined(10).is_err());
}

#[test]
fn layered_annulus_closed_and_sector() {
    let layers = [
        RingLayer {
            name: "a".into(),
            r_in: 1.0,
            r_out: 2.0,
            rows: 3,
        },
        RingLayer {
            name: "b".into(),
            r_in: 2.0,
            r_out: 3.0,
            rows: 2,
        },
    ];
    let m = layered_annulus(&layers, 0.0, 2.0 * PI, 64).unwrap();
    assert_eq!(m.bodies().len(), 2);
    assert_eq!(m.interface("a_b").unwrap().elements.len(), 64);
    assert_eq!(m.n_nodes(), 64 * 4 + 64 * 3);
    let exact = PI * (9.0 - 1.0);
    let chord = 64.0 / 2.0 * (2.0 * PI / 64.0).sin() / PI; // polygon/circle area ratio
    assert!((total_area(&m) - exact * chord).abs() < 1e-12 * exact);
    assert!(m.edge_set("start").is_err());
    let s = layered_annulus(&layers, 0.0, 0.5 * PI, 8).unwrap();
    assert_eq!(s.edge_set("start").unwrap().len(), 5);
    assert_eq!(s.node_set("end").unwrap().len(), 4 + 3);
}

#[test]
fn rectangle_sets_and_area() {
    let m = rectangle(1.0, 2.0, 3.0, 2.0, 6, 4).unwrap();
    assert_eq!(m.n_triangles(), 48);
    assert!((total_area(&m) - 6.0).abs() < 1e-13);
    assert_eq!(m.edge_set("top").unwrap().len(), 6);
    assert_eq!(m.node_set("left").unwrap().len(), 5);
    // boundary edges are oriented CCW: outward normal (right normal) of "bottom" points −y
    for &[a, b] in m.edge_set("bottom").unwrap() {
        let t = [
            m.nodes()[b][0] - m.nodes()[a][0],
            m.nodes()[b][1] - m.nodes()[a][1],
        ];
        assert!(t[0] > 0.0);
    }
    assert_eq!(m.boundary_edges().len(), 2 * (6 + 4));
}

fn square() -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
    (
        vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

#[test]
fn clockwise_triangles_are_reoriented_and_said() {
    let (n, _) = square();
    let m = Mesh::new(n, vec![[0, 2, 1], [0, 2, 3]], vec![0, 0], vec!["r".into()]).unwrap();
    assert_eq!(m.notices(), &[MeshNotice::ReorientedTriangles { count: 1 }]);
    assert!(m.areas().iter().all(|&a| a > 0.0));
}

#[test]
fn validation_errors_name_the_culprit() {
    let (n, t) = square();
    let r = || vec!["r".to_string()];
    // zero area
    let e = Mesh::new(n.clone(), vec![[0, 1, 2], [0, 2, 0]], vec![0, 0], r()).unwrap_err();
    assert!(
        matches!(e, MeshError::DegenerateTriangle { element: 1, .. }),
        "{e}"
    );
    let mut collinear = n.clone();
    collinear.push([2.0, 0.0]);
    let e = Mesh::new(
        collinear,
        vec![[0, 1, 2], [0, 2, 3], [0, 1, 4]],
        vec![0; 3],
        r(),
    )
    .unwrap_err();
    assert!(
        matches!(e, MeshError::DegenerateTriangle { element: 2, .. }),
        "{e}"
    );
    // out of range
    let e = Mesh::new(n.clone(), vec![[0, 1, 2], [0, 2, 7]], vec![0, 0], r()).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::NodeOutOfRange {
                element: 1,
                node: 7,
                ..
            }
        ),
        "{e}"
    );
    // orphan
    let mut extra = n.clone();
    extra.push([5.0, 5.0]);
    let e = Mesh::new(extra, t.clone(), vec![0, 0], r()).unwrap_err();
    assert!(matches!(e, MeshError::OrphanNode { node: 4, .. }), "{e}");
    // duplicate in one body
    let mut dup = n.clone();
    dup.push([1.0, 1.0]);
    let e = Mesh::new(dup, vec![[0, 1, 2], [0, 4, 3]], vec![0, 0], r()).unwrap_err();
    assert!(
        matches!(e, MeshError::DuplicateNodes { a: 2, b: 4, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("region 'r'"));
    // non-finite
    let mut nan = n.clone();
    nan[2][0] = f64::NAN;
    let e = Mesh::new(nan, t.clone(), vec![0, 0], r()).unwrap_err();
    assert!(
        matches!(e, MeshError::NonFiniteCoordinate { node: 2, .. }),
        "{e}"
    );
    // unknown names
    let mut m = Mesh::new(n, t, vec![0, 0], r()).unwrap();
    let e = m.edge_set("outer").unwrap_err();
    assert!(e.to_string().contains("no edge set named 'outer'"), "{e}");
    assert!(
        m.region_index("weld")
            .unwrap_err()
            .to_string()
            .contains("(it has: r)")
    );
    let e = m.add_edge_set("diag_bad", vec![[1, 3]]).unwrap_err();
    assert!(
        matches!(e, MeshError::EdgeNotInMesh { a: 1, b: 3, .. }),
        "{e}"
    );
    // CCW orientation of boundary edges is restored
    m.add_edge_set("b", vec![[1, 0]]).unwrap();
    assert_eq!(m.edge_set("b").unwrap(), &[[0, 1]]);
}

#[test]
fn coincident_nodes_across_bodies_are_allowed_and_paired() {
    // two unit squares side by side with separate nodes on x = 1
    let nodes = vec![
        [0.0, 0.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
    ];
    let tris = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
    let mut m = Mesh::new(
        nodes,
        tris,
        vec![0, 0, 1, 1],
        vec!["left".into(), "right".into()],
    )
    .unwrap();
    m.add_edge_set("l_face", vec![[1, 2]]).unwrap();
    m.add_edge_set("r_face", vec![[4, 7]]).unwrap();
    m.add_interface("joint", "l_face", "r_face", None).unwrap();
    // bottom = left body; 1→2 must have the right body on its left: 1 = node 2 (top), 2 = node 1
    assert_eq!(m.interface("joint").unwrap().elements, vec![[2, 1, 4, 7]]);
    // not facing
    let nodes = vec![
        [0.0, 0.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [1.1, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [1.1, 1.0],
    ];
    let mut m = Mesh::new(
        nodes,
        vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
        vec![0, 0, 1, 1],
        vec!["l".into(), "r".into()],
    )
    .unwrap();
    m.add_edge_set("l_face", vec![[1, 2]]).unwrap();
    m.add_edge_set("r_face", vec![[4, 7]]).unwrap();
    let e = m
        .add_interface("joint", "l_face", "r_face", None)
        .unwrap_err();
    assert!(
        matches!(e, MeshError::InterfaceNotFacing { bottom: 2, .. }),
        "{e}"
    );
    // an edge facing itself is rejected
    let (n, t) = square();
    let mut m = Mesh::new(n, t, vec![0, 0], vec!["r".into()]).unwrap();
    m.add_edge_set("a", vec![[0, 1]]).unwrap();
    let e = m.add_interface("self", "a", "a", None).unwrap_err();
    assert!(matches!(e, MeshError::InterfaceSameEdge { .. }), "{e}");
}

#[test]
fn vtu_and_pvd_are_written() {
    let m = rectangle(0.0, 0.0, 1.0, 1.0, 2, 1).unwrap();
    let t: Vec<f64> = m.nodes().iter().map(|p| p[0] + p[1]).collect();
    let u: Vec<[f64; 2]> = m.nodes().iter().map(|p| [p[0], -p[1]]).collect();
    let s: Vec<f64> = (0..m.n_triangles()).map(|e| e as f64).collect();
    use tecon_mesh::vtk::{Field, VtuPiece, vtu_string, write_pvd, write_vtu};
    let piece = VtuPiece {
        points: m.nodes(),
        triangles: m.triangles(),
        quads: &[],
        point_data: &[("T", Field::Scalars(&t)), ("u", Field::Vectors(&u))],
        cell_data: &[("id", Field::Scalars(&s))],
    };
    let text = vtu_string(&piece).unwrap();
    assert!(text.contains("NumberOfPoints=\"6\" NumberOfCells=\"4\""));
    assert_eq!(text.matches("<DataArray").count(), 1 + 3 + 2 + 1);
    let dir = std::env::temp_dir().join(format!("tecon-vtk-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    write_vtu(dir.join("a.vtu"), &piece).unwrap();
    write_pvd(
        dir.join("a.pvd"),
        &[(0.0, "a.vtu".into()), (1.5, "a.vtu".into())],
    )
    .unwrap();
    let pvd = std::fs::read_to_string(dir.join("a.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 2);
    let short = [1.0];
    let bad = VtuPiece {
        point_data: &[("T", Field::Scalars(&short))],
        ..piece
    };
    assert!(
        vtu_string(&bad)
            .unwrap_err()
            .contains("point field 'T' has 1 entries for 6 points")
    );
    std::fs::remove_dir_all(&dir).ok();
}
