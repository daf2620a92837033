//! The multilayer welded vessel generator (`multilayer_vessel_mesh`).
//!
//! ```text
//!   core + N layers, separate bodies, interfaces between adjacent rings;
//!   staggered seams → full ring; seams on y = 0 → half ring with sym0/sym180
//! ```
//! Goal: the topology the staged analysis relies on (bodies, interfaces with
//! coincident facing nodes, weld regions bounded by stations at the weld
//! edges), areas that converge to the exact ring areas at the order of the
//! elements, and every bad input refused by name.

use std::f64::consts::PI;
use tecon_mesh::{
    MeshError, MultilayerGeometry, MultilayerMeshSpec, WeldedLayer, multilayer_station_angles,
    multilayer_vessel_mesh,
};

fn five_staggered() -> MultilayerGeometry {
    MultilayerGeometry::staggered(0.762, 0.0127, 5, 0.0064, 0.0038)
}

#[test]
fn staggered_layers_make_a_full_ring_of_separate_bodies() {
    let geo = five_staggered();
    assert!(!geo.is_symmetric());
    let spec = MultilayerMeshSpec::default();
    let mesh = multilayer_vessel_mesh(&geo, &spec).unwrap();
    assert_eq!(mesh.bodies().len(), 6, "core and five layers");
    let names: Vec<&str> = mesh.interfaces().keys().map(|s| s.as_str()).collect();
    assert_eq!(
        names,
        [
            "core_layer1",
            "layer1_layer2",
            "layer2_layer3",
            "layer3_layer4",
            "layer4_layer5"
        ]
    );
    // facing nodes coincide; every interface runs all the way round
    let st = multilayer_station_angles(&geo, &spec).unwrap();
    for (name, i) in mesh.interfaces() {
        assert_eq!(i.elements.len(), st.len(), "{name}");
        for e in &i.elements {
            let x = mesh.nodes();
            for (a, b) in [(e[0], e[3]), (e[1], e[2])] {
                let d = ((x[a][0] - x[b][0]).powi(2) + (x[a][1] - x[b][1]).powi(2)).sqrt();
                assert!(d < 1e-12, "{name}: nodes {a} and {b} are {d} m apart");
            }
        }
    }
    assert!(mesh.edge_sets().get("sym0").is_none());
    // each weld is the sector within its half angle of its seam, bounded by stations
    let areas = mesh.areas();
    for k in 0..5 {
        let r = geo.radii();
        let (r0, r1) = (r[k + 1], r[k + 2]);
        let t = geo.weld_half_angle(k);
        let weld: f64 = mesh
            .region_elements(&format!("weld{}", k + 1))
            .unwrap()
            .iter()
            .map(|&e| areas[e])
            .sum();
        let exact = t * (r1 * r1 - r0 * r0); // sector of angle 2t
        assert!(
            (weld / exact - 1.0).abs() < 1e-4,
            "weld {}: {weld} vs {exact}",
            k + 1
        );
        for sign in [-1.0, 1.0] {
            let edge = (geo.layers[k].seam_angle + sign * t).rem_euclid(2.0 * PI);
            assert!(
                st.iter().any(|&s| (s - edge).abs() < 1e-12),
                "weld edge {edge} of layer {} is a station",
                k + 1
            );
        }
    }
}

#[test]
fn seams_on_the_symmetry_plane_make_a_half_ring() {
    let mut geo = five_staggered();
    for (k, l) in geo.layers.iter_mut().enumerate() {
        l.seam_angle = if k % 2 == 0 { 0.0 } else { PI };
    }
    assert!(geo.is_symmetric());
    let mesh = multilayer_vessel_mesh(&geo, &MultilayerMeshSpec::default()).unwrap();
    let x = mesh.nodes();
    for name in ["sym0", "sym180"] {
        let set = mesh.node_set(name).unwrap();
        assert_eq!(
            set.len(),
            6 * 3,
            "{name}: 3 nodes per ring through the thickness"
        );
        assert!(set.iter().all(|&n| x[n][1].abs() < 1e-12));
    }
    assert!(x.iter().all(|p| p[1] >= -1e-12), "upper half only");
    assert_eq!(mesh.interfaces().len(), 5);
}

#[test]
fn ring_areas_converge_at_the_order_of_the_elements() {
    let geo = five_staggered();
    let r = geo.radii();
    let exact = PI * (r[6] * r[6] - r[0] * r[0]);
    for (order, rate) in [(1usize, 2.0), (2, 4.0)] {
        let mut errs = Vec::new();
        let mut hs = Vec::new();
        for max_deg in [4.0f64, 2.0, 1.0] {
            let spec = MultilayerMeshSpec {
                order,
                growth: 1.0,
                first_ratio: 1e3, // every interval outside the welds at max_interval
                weld_divisions: 1,
                max_interval: max_deg.to_radians(),
                ..MultilayerMeshSpec::default()
            };
            let mesh = multilayer_vessel_mesh(&geo, &spec).unwrap();
            let area: f64 = mesh.areas().iter().sum();
            errs.push((area / exact - 1.0).abs());
            hs.push(max_deg);
        }
        let slope = (errs[0] / errs[2]).ln() / (hs[0] / hs[2]).ln();
        eprintln!("order {order}: area errors {errs:?}, observed order {slope:.3}");
        assert!(
            (slope - rate).abs() < 0.2,
            "order {order}: area errors {errs:?}, observed order {slope:.2}"
        );
    }
}

#[test]
fn one_layer_with_the_seam_at_zero_is_the_half_monolayer_section() {
    let geo = MultilayerGeometry {
        inner_radius: 0.762,
        core_thickness: 0.0127,
        layers: vec![WeldedLayer {
            thickness: 0.0064,
            weld_half_width: 0.0038,
            seam_angle: 0.0,
        }],
    };
    let spec = MultilayerMeshSpec::default();
    let st = multilayer_station_angles(&geo, &spec).unwrap();
    let tw = geo.weld_half_angle(0);
    assert_eq!(st[0], 0.0);
    assert_eq!(*st.last().unwrap(), PI);
    assert!(
        (st[2] - tw).abs() < 1e-15,
        "two intervals across the weld half"
    );
    // intervals grow from the weld edge by the growth ratio, capped at max_interval
    let h: Vec<f64> = st.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(h.iter().all(|&d| d <= spec.max_interval * (1.0 + 1e-9)));
    assert!(h[3] / h[2] > 1.2 && h[3] / h[2] < 1.4, "{h:?}");
    let mesh = multilayer_vessel_mesh(&geo, &spec).unwrap();
    assert_eq!(mesh.region_names(), ["core", "layer1", "weld1"]);
    assert!(mesh.edge_set("core_outer").is_ok() && mesh.edge_set("layer1_inner").is_ok());
}

#[test]
fn bad_layers_are_refused_by_name() {
    let spec = MultilayerMeshSpec::default();
    let err = |f: &dyn Fn(&mut MultilayerGeometry)| {
        let mut g = five_staggered();
        f(&mut g);
        match multilayer_vessel_mesh(&g, &spec) {
            Err(MeshError::InvalidParameter { name, value, .. }) => format!("{name}: {value}"),
            other => panic!("expected an error, got {other:?}"),
        }
    };
    assert_eq!(
        err(&|g| g.layers[2].thickness = 0.0),
        "layer thickness: layer 3: 0"
    );
    assert_eq!(
        err(&|g| g.layers[1].thickness = -1e-3),
        "layer thickness: layer 2: -0.001"
    );
    assert!(err(&|g| g.layers[4].seam_angle = 7.0).starts_with("seam_angle: layer 5"));
    assert!(err(&|g| g.layers[0].seam_angle = -0.1).starts_with("seam_angle: layer 1"));
    assert!(err(&|g| g.layers[0].weld_half_width = 1.0).starts_with("weld_half_width: layer 1"));
    assert!(err(&|g| g.layers.clear()).starts_with("layers"));
    assert!(err(&|g| g.core_thickness = f64::NAN).starts_with("core_thickness"));
    let bad_spec = MultilayerMeshSpec {
        growth: 0.5,
        ..spec
    };
    assert!(multilayer_vessel_mesh(&five_staggered(), &bad_spec).is_err());
}

/// A stage mesh is the prefix of the whole mesh: same stations and
/// numbering, the first nodes, triangles and regions, its own outer surface.
#[test]
fn stage_meshes_are_prefixes_of_the_whole_mesh() {
    use tecon_mesh::multilayer_stage_mesh;
    let geo = MultilayerGeometry::staggered(0.762, 12.7e-3, 3, 6.4e-3, 3.8e-3);
    let spec = MultilayerMeshSpec::default();
    let whole = multilayer_vessel_mesh(&geo, &spec).unwrap();
    for k in 1..=3 {
        let m = multilayer_stage_mesh(&geo, &spec, k).unwrap();
        assert_eq!(m.nodes(), &whole.nodes()[..m.n_nodes()]);
        assert_eq!(m.triangles(), &whole.triangles()[..m.n_triangles()]);
        assert_eq!(m.region_names(), &whole.region_names()[..1 + 2 * k]);
        assert_eq!(
            m.element_regions(),
            &whole.element_regions()[..m.n_triangles()]
        );
        assert_eq!(m.interfaces().len(), k);
        let r_out = geo.radii()[k + 1];
        for v in m.edge_set_nodes("outer").unwrap() {
            let p = m.nodes()[v];
            assert!((p[0].hypot(p[1]) - r_out).abs() < 1e-12);
        }
    }
    assert_eq!(
        multilayer_stage_mesh(&geo, &spec, 3).unwrap().n_triangles(),
        whole.n_triangles()
    );
    for bad in [0, 4] {
        let e = multilayer_stage_mesh(&geo, &spec, bad)
            .unwrap_err()
            .to_string();
        assert!(e.contains("layers"), "{e}");
    }
}

/// At order 2 a stage mesh is a prefix of the whole mesh too (nodes ring
/// after ring, each ring's mid nodes right after its corners), and the
/// whole mesh is the polar promotion of the linear one: same corner
/// positions, every mid node at the mean radius and angle of its edge.
#[test]
fn stage_meshes_are_prefixes_of_the_whole_mesh_at_order_2() {
    use tecon_mesh::multilayer_stage_mesh;
    for geo in [
        MultilayerGeometry::staggered(0.762, 12.7e-3, 3, 6.4e-3, 3.8e-3),
        MultilayerGeometry {
            layers: vec![
                WeldedLayer {
                    thickness: 6.4e-3,
                    weld_half_width: 3.8e-3,
                    seam_angle: 0.0,
                },
                WeldedLayer {
                    thickness: 6.4e-3,
                    weld_half_width: 3.8e-3,
                    seam_angle: PI,
                },
            ],
            ..five_staggered()
        },
    ] {
        let n = geo.layers.len();
        let spec = MultilayerMeshSpec::refined(1, 2).unwrap();
        let whole = multilayer_vessel_mesh(&geo, &spec).unwrap();
        let t6 = whole.triangles6().expect("6-node triangles");
        for k in 1..=n {
            let m = multilayer_stage_mesh(&geo, &spec, k).unwrap();
            assert_eq!(m.order(), 2);
            assert_eq!(m.nodes(), &whole.nodes()[..m.n_nodes()], "stage {k}");
            assert_eq!(m.triangles6().unwrap(), &t6[..m.n_triangles()]);
            assert_eq!(m.bodies().len(), k + 1);
            // the stage's triangles use exactly its nodes
            let mut used = vec![false; m.n_nodes()];
            m.triangles6()
                .unwrap()
                .iter()
                .flatten()
                .for_each(|&v| used[v] = true);
            assert!(
                used.iter().all(|&u| u),
                "stage {k}: a node no triangle uses"
            );
            for (name, itf) in m.interfaces() {
                assert_eq!(itf, whole.interface(name).unwrap(), "{name}");
                assert_eq!(itf.mid_nodes.len(), itf.elements.len());
            }
            if geo.is_symmetric() {
                assert_eq!(
                    m.node_set("sym0").unwrap(),
                    &whole.node_set("sym0").unwrap()[..m.node_set("sym0").unwrap().len()]
                );
            }
        }
        // against the plain promotion of the linear mesh
        let linear =
            multilayer_vessel_mesh(&geo, &MultilayerMeshSpec { order: 1, ..spec }).unwrap();
        assert_eq!(whole.n_triangles(), linear.n_triangles());
        let x = whole.nodes();
        for (t, l) in t6.iter().zip(linear.triangles()) {
            for a in 0..3 {
                assert_eq!(x[t[a]], linear.nodes()[l[a]]);
            }
            for (m, (a, b)) in [(3, (0, 1)), (4, (1, 2)), (5, (2, 0))] {
                let (p, q, c) = (x[t[a]], x[t[b]], x[t[m]]);
                let r = 0.5 * (p[0].hypot(p[1]) + q[0].hypot(q[1]));
                assert!((c[0].hypot(c[1]) - r).abs() < 1e-12 * r);
                let mut dt = q[1].atan2(q[0]) - p[1].atan2(p[0]);
                if dt > PI {
                    dt -= 2.0 * PI;
                } else if dt <= -PI {
                    dt += 2.0 * PI;
                }
                let tm = p[1].atan2(p[0]) + 0.5 * dt;
                let d = (c[1].atan2(c[0]) - tm).rem_euclid(2.0 * PI);
                assert!(
                    d.min(2.0 * PI - d) < 1e-12,
                    "mid node off its polar midpoint"
                );
            }
        }
        for v in whole.edge_set_nodes("sym0").into_iter().flatten() {
            assert!(x[v][1].abs() < 1e-12);
        }
    }
}

/// Refinement levels halve every interval: twice the rows and weld
/// intervals, about twice the stations (each level's stations interleave
/// the level before's), level 0 the default density; levels beyond the
/// largest and bad orders are refused by name.
#[test]
fn refinement_levels_halve_every_interval() {
    use tecon_mesh::multilayer::MULTILAYER_MAX_LEVEL;
    let geo = MultilayerGeometry::staggered(0.762, 12.7e-3, 3, 6.4e-3, 3.8e-3);
    assert_eq!(
        MultilayerMeshSpec::refined(0, 1).unwrap(),
        MultilayerMeshSpec::default()
    );
    let mut last: Option<(Vec<f64>, MultilayerMeshSpec)> = None;
    for level in 0..=3 {
        let spec = MultilayerMeshSpec::refined(level, 1).unwrap();
        let st = multilayer_station_angles(&geo, &spec).unwrap();
        let widest = st
            .windows(2)
            .map(|w| w[1] - w[0])
            .chain([2.0 * PI - st[st.len() - 1]])
            .fold(0.0, f64::max);
        assert!(widest <= spec.max_interval * (1.0 + 1e-12));
        if let Some((prev, p)) = &last {
            assert_eq!(spec.core_rows, 2 * p.core_rows);
            assert_eq!(spec.layer_rows, 2 * p.layer_rows);
            assert_eq!(spec.weld_divisions, 2 * p.weld_divisions);
            let ratio = st.len() as f64 / prev.len() as f64;
            assert!((1.9..2.1).contains(&ratio), "level {level}: {ratio}");
            // every weld edge and seam stays a station at every level
            for k in 0..3 {
                let (s, t) = (geo.layers[k].seam_angle, geo.weld_half_angle(k));
                for a in [s - t, s, s + t] {
                    let a = a.rem_euclid(2.0 * PI);
                    assert!(st.iter().any(|&x| (x - a).abs() < 1e-9), "level {level}");
                }
            }
        }
        last = Some((st, spec));
    }
    for (level, order) in [(MULTILAYER_MAX_LEVEL + 1, 1), (1, 3), (0, 0)] {
        let e = MultilayerMeshSpec::refined(level, order)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(if order == 1 { "level" } else { "order" }),
            "{e}"
        );
    }
}
