//! Quadratic (P2) meshes: mid nodes, curved edges, sets, interfaces, areas.
//!
//! Reference: the geometry of the annulus (area π(r_o² − r_i²)); the
//! isoparametric quadratic arc has position error O(h³) and the area error
//! of a curved mesh is O(h⁴).
//! Goal: promoted and generated P2 meshes put mid nodes on their circles to
//! rounding, share them between triangles, keep bodies, sets and interfaces
//! consistent, and their areas converge at order 4 (asserted slope).
//!
//! ```text
//!   outer ro ┌───────────┐  two concentric rings, separate nodes on rm,
//!   top   rm ├───────────┤  joined by the interface inner_outer
//!   bot   rm ├───────────┤
//!   inner ri └───────────┘
//! ```

use std::collections::HashSet;
use std::f64::consts::PI;

use tecon_mesh::quadratic::p2_area;
use tecon_mesh::{
    Arc, Mesh, MeshError, MeshNotice, PairingTolerance, RingLayer, VesselGeometry, VesselMeshSpec,
    layered_annulus, layered_annulus_of_order, rectangle_of_order, vessel_mesh,
};

fn rings(rows: usize) -> Vec<RingLayer> {
    vec![
        RingLayer {
            name: "inner".into(),
            r_in: 1.0,
            r_out: 1.5,
            rows,
        },
        RingLayer {
            name: "outer".into(),
            r_in: 1.5,
            r_out: 2.0,
            rows,
        },
    ]
}

fn radius(p: [f64; 2]) -> f64 {
    p[0].hypot(p[1])
}

/// Least-squares slope of log(e) against log(h).
fn slope(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (x, y): (Vec<f64>, Vec<f64>) = (
        h.iter().map(|v| v.ln()).collect(),
        e.iter().map(|v| v.ln()).collect(),
    );
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn annulus_mid_nodes_lie_on_their_circles_and_are_shared() {
    let p1 = layered_annulus(&rings(2), 0.0, 2.0 * PI, 24).unwrap();
    let m = layered_annulus_of_order(&rings(2), 0.0, 2.0 * PI, 24, 2).unwrap();
    assert_eq!(p1.order(), 1);
    assert!(p1.triangles6().is_none());
    assert_eq!(m.order(), 2);
    // corners keep their ids and coordinates
    assert_eq!(m.triangles(), p1.triangles());
    assert_eq!(&m.nodes()[..p1.n_nodes()], p1.nodes());
    let t6 = m.triangles6().unwrap();
    // one mid node per edge: per ring 24 stations × (rows + 1) circumferential
    // edges + 24 × rows radial + 24 × rows diagonals; all mid nodes are polar
    // midpoints (the rows on their circles, diagonals on the polar map)
    let edges = 2 * (24 * 3 + 24 * 2 + 24 * 2);
    assert_eq!(m.n_nodes(), p1.n_nodes() + edges);
    let mut worst: f64 = 0.0;
    for t in t6 {
        for (i, j, k) in [(0, 1, 3), (1, 2, 4), (2, 0, 5)] {
            let (a, b, c) = (t[i], t[j], t[k]);
            assert_eq!(m.edge_mid_node(a, b), Some(c));
            assert_eq!(m.edge_mid_node(b, a), Some(c));
            let (ra, rb, rc) = (
                radius(m.nodes()[a]),
                radius(m.nodes()[b]),
                radius(m.nodes()[c]),
            );
            if (ra - rb).abs() < 1e-12 {
                worst = worst.max((rc - ra).abs());
            } else {
                // radial and diagonal edges: the polar midpoint (mean radius)
                assert!((rc - 0.5 * (ra + rb)).abs() < 2e-15, "{rc} {ra} {rb}");
            }
        }
    }
    assert!(
        worst < 1e-15,
        "distance of mid nodes to their circle {worst:e}"
    );
    assert_eq!(m.edge_mid_node(0, 0), None);
    assert!(m.notices().is_empty());
    // mid nodes belong to the body of their triangle
    for b in m.bodies() {
        let nodes: HashSet<usize> = b.nodes.iter().copied().collect();
        for &e in &b.elements {
            assert!(t6[e].iter().all(|v| nodes.contains(v)));
        }
    }
    let names: Vec<&str> = m.bodies().iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["inner", "outer"]);
    assert_eq!(
        m.bodies().iter().map(|b| b.nodes.len()).sum::<usize>(),
        m.n_nodes()
    );
}

#[test]
fn interface_mid_nodes_face_each_other() {
    let m = layered_annulus_of_order(&rings(1), 0.0, 0.5 * PI, 6, 2).unwrap();
    let itf = m.interface("inner_outer").unwrap();
    assert_eq!(itf.elements.len(), 6);
    assert_eq!(itf.mid_nodes.len(), 6);
    let x = m.nodes();
    for (el, &[mb, mt]) in itf.elements.iter().zip(&itf.mid_nodes) {
        let [n1, n2, n3, n4] = *el;
        assert_eq!(m.edge_mid_node(n1, n2), Some(mb));
        assert_eq!(m.edge_mid_node(n4, n3), Some(mt));
        assert_ne!(mb, mt);
        assert_eq!(x[mb], x[mt], "facing mid nodes coincide");
        assert!((radius(x[mb]) - 1.5).abs() < 1e-15);
        assert_eq!(m.node_bodies()[mb], m.node_bodies()[n1]);
        assert_eq!(m.node_bodies()[mt], m.node_bodies()[n4]);
        assert_ne!(m.node_bodies()[mb], m.node_bodies()[mt]);
    }
    // edge sets stay corner pairs; their nodes and same-named node sets gain the mids
    let edges = m.edge_set("start").unwrap();
    assert_eq!(edges.len(), 2);
    let nodes = m.edge_set_nodes("start").unwrap();
    assert_eq!(nodes.len(), 6, "two radial edges: 4 corners, 2 mids");
    assert_eq!(m.node_set("start").unwrap(), nodes.as_slice());
    // a P1 interface has no mid nodes
    let p1 = layered_annulus(&rings(1), 0.0, 0.5 * PI, 6).unwrap();
    assert!(p1.interface("inner_outer").unwrap().mid_nodes.is_empty());
}

#[test]
fn p2_annulus_area_converges_at_order_four() {
    let exact = PI * (4.0 - 1.0);
    let mut h = Vec::new();
    let mut err = Vec::new();
    for segments in [8, 16, 32, 64] {
        let m = layered_annulus_of_order(&rings(1), 0.0, 2.0 * PI, segments, 2).unwrap();
        let area: f64 = m.areas().iter().sum();
        h.push(2.0 * PI / segments as f64);
        err.push((area - exact).abs() / exact);
        // the P1 polygon is only second order
        let p1: f64 = layered_annulus(&rings(1), 0.0, 2.0 * PI, segments)
            .unwrap()
            .areas()
            .iter()
            .sum();
        assert!((p1 - exact).abs() / exact > 10.0 * err.last().unwrap());
    }
    let s = slope(&h, &err);
    eprintln!("P2 annulus area: relative errors {err:?}, slope {s:.3}");
    assert!((s - 4.0).abs() < 0.2, "observed order {s}, errors {err:?}");
}

#[test]
fn p2_vessel_area_converges_and_order_one_is_unchanged() {
    let g = VesselGeometry::default();
    let (ri, ro) = (g.inner_radius, g.outer_radius());
    let exact = 0.5 * PI * (ro * ro - ri * ri);
    let mut h = Vec::new();
    let mut err = Vec::new();
    for f in [1, 2, 4, 8] {
        let spec = VesselMeshSpec::subdivided(f).unwrap();
        let p1 = vessel_mesh(&g, &spec).unwrap();
        let p2 = vessel_mesh(&g, &VesselMeshSpec { order: 2, ..spec }).unwrap();
        assert_eq!(p2.order(), 2);
        assert_eq!(p2.triangles(), p1.triangles());
        assert_eq!(&p2.nodes()[..p1.n_nodes()], p1.nodes());
        let itf = p2.interface("core_layer").unwrap();
        assert_eq!(itf.mid_nodes.len(), itf.elements.len());
        // sym0 gains the mid nodes of its radial edges
        assert_eq!(
            p2.node_set("sym0").unwrap().len(),
            2 * p1.node_set("sym0").unwrap().len() - 2
        );
        h.push(1.0 / f as f64);
        err.push(((p2.areas().iter().sum::<f64>() - exact) / exact).abs());
    }
    let s = slope(&h, &err);
    eprintln!("P2 vessel area: relative errors {err:?}, slope {s:.3}");
    assert!((s - 4.0).abs() < 0.2, "observed order {s}, errors {err:?}");
    // the fused weld: the mid nodes under the weld are shared by core and weld
    let spec = VesselMeshSpec {
        fused_weld: true,
        order: 2,
        ..VesselMeshSpec::paper()
    };
    let m = vessel_mesh(&g, &spec).unwrap();
    assert_eq!(m.bodies().len(), 1);
    assert_eq!(m.interface("core_layer").unwrap().mid_nodes.len(), 16);
    let e = vessel_mesh(&g, &VesselMeshSpec { order: 3, ..spec }).unwrap_err();
    assert!(e.to_string().contains("order"), "{e}");
}

#[test]
fn rectangle_p2_has_straight_edges_and_exact_area() {
    let m = rectangle_of_order(0.0, 0.0, 2.0, 1.0, 3, 2, 2).unwrap();
    assert_eq!(m.order(), 2);
    assert_eq!(m.n_nodes(), 7 * 5);
    assert!((m.areas().iter().sum::<f64>() - 2.0).abs() < 1e-14);
    assert_eq!(m.node_set("left").unwrap().len(), 5);
    assert_eq!(m.node_set("bottom").unwrap().len(), 7);
    assert!(rectangle_of_order(0.0, 0.0, 1.0, 1.0, 1, 1, 0).is_err());
}

fn unit_square_p2() -> (Vec<[f64; 2]>, Vec<[usize; 6]>) {
    // 3 ---- 2
    // | \  1 |    corners 0..3, mids 4 (0-1), 5 (1-2), 6 (2-0), 7 (2-3), 8 (3-0)
    // | 0 \  |
    // 0 ---- 1
    (
        vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.5, 0.0],
            [1.0, 0.5],
            [0.5, 0.5],
            [0.5, 1.0],
            [0.0, 0.5],
        ],
        vec![[0, 1, 2, 4, 5, 6], [0, 2, 3, 6, 7, 8]],
    )
}

#[test]
fn new_quadratic_validates_and_reorients() {
    let r = || vec!["r".to_string()];
    let (n, t) = unit_square_p2();
    let m = Mesh::new_quadratic(n.clone(), t.clone(), vec![0, 0], r()).unwrap();
    assert!((m.areas().iter().sum::<f64>() - 1.0).abs() < 1e-15);
    // clockwise: corners 1 and 2 swapped and the mids with them
    let m =
        Mesh::new_quadratic(n.clone(), vec![[0, 2, 1, 6, 5, 4], t[1]], vec![0, 0], r()).unwrap();
    assert_eq!(m.notices(), &[MeshNotice::ReorientedTriangles { count: 1 }]);
    assert_eq!(m.triangles6().unwrap()[0], [0, 1, 2, 4, 5, 6]);
    // two triangles give one edge different mid nodes
    let mut n2 = n.clone();
    n2.push([0.5, 0.5]);
    let e = Mesh::new_quadratic(n2, vec![t[0], [0, 2, 3, 9, 7, 8]], vec![0, 0], r()).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::InconsistentMidNode {
                element: 1,
                mid: 9,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("mid node 6"), "{e}");
    // a corner used as a mid node
    let e = Mesh::new_quadratic(n.clone(), vec![[0, 1, 2, 4, 5, 3], t[1]], vec![0, 0], r())
        .unwrap_err();
    assert!(matches!(e, MeshError::InconsistentMidNode { .. }), "{e}");
    // a mid node pulled across its triangle folds the map
    let mut bad = n.clone();
    bad[5] = [0.2, 0.5];
    let e = Mesh::new_quadratic(bad, t.clone(), vec![0, 0], r()).unwrap_err();
    assert!(
        matches!(e, MeshError::InvertedCurvedTriangle { element: 0, .. }),
        "{e}"
    );
    // out of range, orphan
    let e = Mesh::new_quadratic(n.clone(), vec![[0, 1, 2, 4, 5, 16], t[1]], vec![0, 0], r())
        .unwrap_err();
    assert!(
        matches!(e, MeshError::NodeOutOfRange { node: 16, .. }),
        "{e}"
    );
    let mut extra = n.clone();
    extra.push([3.0, 3.0]);
    let e = Mesh::new_quadratic(extra, t, vec![0, 0], r()).unwrap_err();
    assert!(matches!(e, MeshError::OrphanNode { node: 9, .. }), "{e}");
}

#[test]
fn p2_area_of_a_quarter_disc_sector() {
    // one curved triangle: centre, (1,0), (0,1) with the arc mid node
    let s = 0.5_f64.sqrt();
    let x = [
        [0.0, 0.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [0.5, 0.0],
        [s, s],
        [0.0, 0.5],
    ];
    // the quadratic through (1,0), (s,s), (0,1): area by its own closed form
    // (the triangle 0.5 plus the parabolic segment 2/3 · chord · sagitta)
    let sagitta = s - 0.5;
    let chord = 2.0_f64.sqrt();
    let exact = 0.5 + 2.0 / 3.0 * chord * (sagitta * 2.0_f64.sqrt());
    assert!(
        (p2_area(&x) - exact).abs() < 1e-15,
        "{} vs {exact}",
        p2_area(&x)
    );
    // a 90° arc by one parabola: 1.1 % short of the quarter disc
    assert!((p2_area(&x) - PI / 4.0).abs() / (PI / 4.0) < 0.012);
}

#[test]
fn to_quadratic_curves_only_boundary_and_region_edges() {
    let p1 = layered_annulus(&rings(2), 0.0, PI, 8).unwrap();
    let arcs = [1.0, 1.25, 1.5, 2.0].map(|r| Arc {
        centre: [0.0, 0.0],
        radius: r,
    });
    let m = p1.to_quadratic(&arcs).unwrap();
    let x = m.nodes();
    let t6 = m.triangles6().unwrap();
    let (mut curved, mut straight_on_row) = (0, 0);
    for t in t6 {
        for (i, j, k) in [(0, 1, 3), (1, 2, 4), (2, 0, 5)] {
            let (ra, rb) = (radius(x[t[i]]), radius(x[t[j]]));
            if (ra - rb).abs() < 1e-12 {
                if (radius(x[t[k]]) - ra).abs() < 1e-15 {
                    curved += 1;
                    assert!([1.0, 1.5, 2.0].iter().any(|r| (r - ra).abs() < 1e-12));
                } else {
                    // an interior row: 1.25 has both ends on a listed arc
                    // but lies inside one region, 1.75 is not listed
                    straight_on_row += 1;
                    assert!((ra - 1.25).abs() < 1e-12 || (ra - 1.75).abs() < 1e-12);
                }
            }
        }
    }
    assert_eq!(straight_on_row, 2 * 2 * 8);
    assert!(curved > 0);
    let bad = [Arc {
        centre: [0.0, 0.0],
        radius: -1.0,
    }];
    assert!(p1.to_quadratic(&bad).is_err());
    // promoting twice changes nothing
    assert_eq!(m.to_quadratic(&arcs).unwrap(), m);
}

/// Two unit squares side by side, separate nodes on x = 1, the right one
/// shifted by `jitter` along y (a mesher's round-off on the shared face).
fn two_squares(jitter: f64, h: f64) -> Mesh {
    let nodes = vec![
        [0.0, 0.0],
        [h, 0.0],
        [h, h],
        [0.0, h],
        [h, jitter],
        [2.0 * h, 0.0],
        [2.0 * h, h],
        [h, h + jitter],
    ];
    let tris = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
    let mut m = Mesh::new(nodes, tris, vec![0, 0, 1, 1], vec!["l".into(), "r".into()]).unwrap();
    m.add_edge_set("l_face", vec![[1, 2]]).unwrap();
    m.add_edge_set("r_face", vec![[4, 7]]).unwrap();
    m
}

#[test]
fn pairing_tolerance_is_relative_to_the_local_size() {
    // A jitter of 1e-6 of the element size pairs by default at any scale
    // (the old rule, 1e-6 × the shortest edge, sat right at the limit).
    for h in [1e-3, 1.0, 1e3] {
        let mut m = two_squares(1e-6 * h, h);
        m.add_interface("joint", "l_face", "r_face", None).unwrap();
        assert_eq!(m.interface("joint").unwrap().elements, vec![[2, 1, 4, 7]]);
    }
    // a jitter beyond the relative tolerance is refused, naming node and distance
    let mut m = two_squares(2e-4, 1.0);
    let e = m
        .add_interface_with(
            "joint",
            "l_face",
            "r_face",
            PairingTolerance::Relative(1e-4),
        )
        .unwrap_err();
    let s = e.to_string();
    assert!(
        matches!(
            e,
            MeshError::InterfaceNotFacing {
                bottom: 2,
                nearest: 7,
                ..
            }
        ),
        "{s}"
    );
    assert!(
        s.contains("must coincide") && s.contains("node 7") && s.contains("2.000e-4"),
        "{s}"
    );
    // … and accepted with a looser one
    m.add_interface_with(
        "joint",
        "l_face",
        "r_face",
        PairingTolerance::Relative(1e-3),
    )
    .unwrap();
    for bad in [0.0, -1.0, 0.5, f64::NAN] {
        let e = m
            .add_interface_with("j", "l_face", "r_face", PairingTolerance::Relative(bad))
            .unwrap_err();
        assert!(e.to_string().contains("pairing_tolerance"), "{e}");
    }
    // P2: the mid nodes pair too
    let m2 = two_squares(1e-7, 1.0).to_quadratic(&[]).unwrap();
    let mut m2b = m2.clone();
    m2b.add_interface("joint", "l_face", "r_face", None)
        .unwrap();
    let itf = m2b.interface("joint").unwrap();
    assert_eq!(itf.mid_nodes.len(), 1);
    let [mb, mt] = itf.mid_nodes[0];
    assert_eq!(m2b.edge_mid_node(1, 2), Some(mb));
    assert_eq!(m2b.edge_mid_node(4, 7), Some(mt));
}

/// FNV-1a over the bits of every coordinate, triangle, edge set, node set
/// and interface element: a node-for-node fingerprint of a mesh.
fn fingerprint(m: &Mesh) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |v: u64| {
        for b in v.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    for p in m.nodes() {
        eat(p[0].to_bits());
        eat(p[1].to_bits());
    }
    for t in m.triangles() {
        t.iter().for_each(|&v| eat(v as u64));
    }
    m.element_regions().iter().for_each(|&r| eat(r as u64));
    for edges in m.edge_sets().values() {
        edges.iter().flatten().for_each(|&v| eat(v as u64));
    }
    for nodes in m.node_sets().values() {
        nodes.iter().for_each(|&v| eat(v as u64));
    }
    for itf in m.interfaces().values() {
        itf.elements.iter().flatten().for_each(|&v| eat(v as u64));
    }
    h
}

#[test]
fn order_one_vessel_presets_are_unchanged_node_for_node() {
    // Fingerprints computed by the same function on main at fa766ad, before
    // element orders and grading existed.
    let g = VesselGeometry::default();
    let cases: Vec<(&str, VesselMeshSpec, u64)> = vec![
        ("paper", VesselMeshSpec::paper(), 0x51ce_c94c_52fc_985b),
        (
            "1",
            VesselMeshSpec::refined(1).unwrap(),
            0xa798_5f65_ebdb_a7c5,
        ),
        (
            "2",
            VesselMeshSpec::refined(2).unwrap(),
            0xdf23_7171_5bda_2c03,
        ),
        (
            "3",
            VesselMeshSpec::refined(3).unwrap(),
            0xeeba_7a71_ab63_674f,
        ),
        (
            "x3",
            VesselMeshSpec::subdivided(3).unwrap(),
            0x0ffb_cea8_492d_f167,
        ),
        (
            "t5000",
            VesselMeshSpec::with_triangles(5000).unwrap(),
            0xfbd7_7f55_153b_ec7b,
        ),
        (
            "paper fused",
            VesselMeshSpec {
                fused_weld: true,
                ..VesselMeshSpec::paper()
            },
            0xb3d3_72e0_3571_773f,
        ),
    ];
    let mut got = Vec::new();
    for (name, spec, want) in &cases {
        let f = fingerprint(&vessel_mesh(&g, spec).unwrap());
        got.push(format!("{name}: {f:#x}"));
        assert_eq!(f, *want, "preset {name}");
    }
    eprintln!("{}", got.join("\n"));
}

#[test]
fn graded_mesh_shrinks_toward_the_weld_edge() {
    let g = VesselGeometry::default();
    let tw = g.weld_half_angle();
    for level in 0..3 {
        let spec = VesselMeshSpec::graded(level).unwrap();
        let t = tecon_mesh::vessel::station_angles(&g, &spec);
        let nw = spec.weld_divisions;
        assert_eq!(t.len(), spec.stations);
        assert_eq!(t[0], 0.0);
        assert_eq!(t[nw], tw);
        assert_eq!(*t.last().unwrap(), PI);
        let h: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
        let r = spec.weld_grading;
        for k in 0..nw - 1 {
            assert!((h[k] / h[k + 1] - r).abs() < 1e-9, "weld interval {k}");
        }
        assert!((h[nw] / h[nw - 1] - spec.first_ratio).abs() < 1e-9);
        let cap = spec.max_interval;
        for k in nw..h.len() - 1 {
            assert!(
                h[k + 1] >= h[k] * (1.0 - 1e-12),
                "outside the weld intervals grow"
            );
            assert!(h[k + 1] / h[k] < 1.3, "gentle growth {}", h[k + 1] / h[k]);
            assert!(h[k] <= cap * (1.0 + 1e-12), "interval {k} above the cap");
        }
        // the far field is uniform at the cap (1.2°/2^L)
        assert!((cap - (1.2 / (1 << level) as f64).to_radians()).abs() < 1e-15);
        assert!((h[h.len() - 2] - cap).abs() < 1e-12 * cap);
        let m = vessel_mesh(&g, &spec).unwrap();
        assert_eq!(m.order(), 2);
        assert_eq!(m.n_triangles(), spec.n_triangles());
        let n0 = 2784.0 * 4f64.powi(level as i32);
        assert!(
            (m.n_triangles() as f64 - n0).abs() < 0.02 * n0,
            "about 2784·4^L triangles: {}",
            m.n_triangles()
        );
        let rc = g.interface_radius();
        eprintln!(
            "graded({level}): {} triangles, {} nodes; intervals at r_c: {:.2e} m at the weld edge, {:.2e} m at θ = π",
            m.n_triangles(),
            m.n_nodes(),
            rc * h[nw - 1],
            rc * h.last().unwrap()
        );
        // level L + 1 has the stations of level L inside the weld
        if level < 2 {
            let finer =
                tecon_mesh::vessel::station_angles(&g, &VesselMeshSpec::graded(level + 1).unwrap());
            for k in 0..=nw {
                assert!((finer[2 * k] - t[k]).abs() < 1e-15, "station {k}");
            }
        }
    }
    assert!(VesselMeshSpec::graded(6).is_err());
    let bad = VesselMeshSpec {
        weld_grading: 0.5,
        ..VesselMeshSpec::paper()
    };
    let e = vessel_mesh(&g, &bad).unwrap_err();
    assert!(e.to_string().contains("weld_grading"), "{e}");
}

#[test]
fn sizes_are_predicted_and_too_large_meshes_refused() {
    let g = VesselGeometry::default();
    for spec in [
        VesselMeshSpec::paper(),
        VesselMeshSpec::refined(2).unwrap(),
        VesselMeshSpec::graded(1).unwrap(),
        VesselMeshSpec {
            order: 2,
            ..VesselMeshSpec::paper()
        },
        VesselMeshSpec {
            order: 2,
            fused_weld: true,
            ..VesselMeshSpec::subdivided(3).unwrap()
        },
        VesselMeshSpec {
            fused_weld: true,
            ..VesselMeshSpec::paper()
        },
    ] {
        let m = vessel_mesh(&g, &spec).unwrap();
        assert_eq!(spec.n_nodes(), m.n_nodes(), "{spec:?}");
        assert_eq!(spec.n_triangles(), m.n_triangles());
    }
    // level 9 (3.6e7 triangles): about 3.6 GB to generate at order 1
    let big = VesselMeshSpec::refined(9).unwrap();
    assert_eq!(big.n_triangles(), 35_651_584);
    let need = big.estimated_bytes();
    assert!((3.5e9..3.7e9).contains(&(need as f64)), "{need}");
    let e = tecon_mesh::check_memory(&big, 2_000_000_000).unwrap_err();
    let s = e.to_string();
    assert!(
        matches!(
            e,
            MeshError::TooLarge {
                triangles: 35_651_584,
                ..
            }
        ) && s.contains("3.6 GB")
            && s.contains("only 2.0 GB are available"),
        "{s}"
    );
    let p2 = VesselMeshSpec { order: 2, ..big };
    assert!(p2.estimated_bytes() > 7 * need);
    tecon_mesh::check_memory(&VesselMeshSpec::paper(), 2_000_000_000).unwrap();
    // the probe reads /proc/meminfo where there is one
    if std::path::Path::new("/proc/meminfo").exists() {
        assert!(tecon_mesh::available_memory_bytes().unwrap() > 0);
    }
}
