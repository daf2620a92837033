//! The figures of `tecon vessel --layers N` that an engineer assesses a
//! multilayer vessel with: per stage the temperature around the new layer
//! while its weld cools, the opening and slip of every interface (with the
//! detail at the weld above it), the hoop stress through the wall at every
//! seam and far from the seams, each figure with its CSV.
//!
//! Goal: every figure has its CSV and PNG beside it; the numbers of each
//! figure's CSV are those of the run (the interface table, summary.json,
//! the state's temperatures and nodal stresses, the sequential shrink fit
//! plus the Lamé field), looked up here independently of the writers; the
//! physics they show holds (the gaps open only at the weld above each
//! interface, the weld is hot at t = 1 s and ambient far from it, the seam
//! carries stresses far above the far field); a half section is drawn
//! from the seam (angles ≥ 0).

use std::collections::BTreeMap;
use std::path::Path;

use tecon_cli::multilayer::{MultilayerOptions, MultilayerRun, analyse, in_ring, wall_lame};
use tecon_cli::multilayer_out::{from_seam, temperature_figure, wall_locations, write_outputs};
use tecon_elastic::polar;

/// The data rows of a CSV written by tecon (numbers only after the header).
fn rows(dir: &Path, name: &str) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(dir.join(name)).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or_else(|_| panic!("{name}: {l}")))
                .collect()
        })
        .collect()
}

fn json(dir: &Path, name: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join(name)).unwrap()).unwrap()
}

/// The node of ring `ring` at `p` (within 1e-9 m), found from the regions.
fn node_of_ring(run: &MultilayerRun, ring: usize, p: [f64; 2]) -> usize {
    let mesh = &run.mesh;
    let names = mesh.region_names();
    let x = mesh.nodes();
    mesh.triangles()
        .iter()
        .enumerate()
        .filter(|(e, _)| in_ring(&names[mesh.element_regions()[*e]], ring))
        .flat_map(|(_, t)| t.iter().copied())
        .find(|&v| (x[v][0] - p[0]).hypot(x[v][1] - p[1]) < 1e-9)
        .unwrap_or_else(|| panic!("no node of ring {ring} at {p:?}"))
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300)
}

#[test]
fn angles_from_a_seam() {
    assert_eq!(from_seam(350.0, 0.0, false), -10.0);
    assert_eq!(from_seam(-170.0, 180.0, false), 10.0);
    assert_eq!(from_seam(170.0, 180.0, true), 10.0);
    assert_eq!(from_seam(10.0, 0.0, true), 10.0);
    assert_eq!(from_seam(180.0, 0.0, false), 180.0);
}

/// 3 staggered layers (full ring), contact at 1 s, 60 s and 72 000 s of
/// every cooling, then 0.05 MPa on the bore.
#[test]
fn every_stage_figure_has_its_data_and_agrees_with_the_run() {
    let mut o = MultilayerOptions::new(3, 6.4e-3, None).unwrap();
    o.quiet = true;
    o.times = vec![1.0, 60.0, 72000.0];
    o.pressure = Some(0.05e6);
    let run = analyse(&o).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("ml");
    let names = write_outputs(&run, &dir).unwrap();

    // every figure has its CSV and PNG, and every stage its figures
    for n in names.iter().filter(|n| n.ends_with(".svg")) {
        let stem = n.trim_end_matches(".svg");
        for ext in ["csv", "png"] {
            let f = format!("{stem}.{ext}");
            assert!(names.contains(&f) && dir.join(&f).is_file(), "{f}");
        }
    }
    for k in 1..=4 {
        let mut stems = vec![
            "hoop_through_wall",
            "hoop_at_seams",
            "interface_pressure",
            "interface_opening_slip",
        ];
        if k <= 3 {
            stems.push("temperature_circumference");
        }
        for s in stems {
            assert!(
                dir.join(format!("stage{k}_{s}.svg")).is_file(),
                "stage {k} {s}"
            );
        }
    }
    // the pressure stage holds the temperatures: no temperature figure
    assert!(!dir.join("stage4_temperature_circumference.csv").exists());

    let x = run.mesh.nodes();
    let radii = o.geometry.radii();
    for k in 1..=4 {
        let st = &run.stages[k - 1];
        let layers = st.layers;
        let summary = json(&dir, &format!("stage{k}_summary.json"));

        // opening and slip: the figure's CSV against the interface table
        // and the summary
        let table = rows(&dir, &format!("stage{k}_interface_pressure.csv"));
        let fig = rows(&dir, &format!("stage{k}_interface_opening_slip.csv"));
        assert_eq!(table.len(), fig.len());
        for j in 1..=layers {
            let t: Vec<&Vec<f64>> = table.iter().filter(|r| r[0] == j as f64).collect();
            let f: Vec<&Vec<f64>> = fig.iter().filter(|r| r[0] == j as f64).collect();
            assert!(t.len() > 100, "stage {k} interface {j}: {} points", t.len());
            let max = |v: &[&Vec<f64>], c: usize, abs: bool| {
                v.iter()
                    .map(|r| if abs { r[c].abs() } else { r[c] })
                    .fold(f64::NEG_INFINITY, f64::max)
            };
            let (gap, slip) = (max(&f, 3, false), max(&f, 4, true));
            assert_eq!(gap, max(&t, 5, false), "stage {k} interface {j}: gap");
            assert_eq!(slip, max(&t, 8, true), "stage {k} interface {j}: slip");
            let s = &summary["interfaces"][j - 1];
            assert!(close(gap, s["max_opening_m"].as_f64().unwrap(), 1e-9));
            assert!(close(slip, s["max_abs_slip_m"].as_f64().unwrap(), 1e-9));
            let open = f.iter().filter(|r| r[5] == 0.0).count();
            assert_eq!(open as u64, s["open_points"].as_u64().unwrap());
            // the figure's angles are the table's, and the gap opens at
            // the weld of the layer above only (tens of µm)
            for (a, b) in t.iter().zip(&f) {
                assert_eq!((a[1], a[10]), (b[1], b[2]));
            }
            assert!(gap > 10e-6 && open > 0, "stage {k} interface {j}: {gap:e}");
            for r in f.iter().filter(|r| r[5] == 0.0) {
                assert!(r[2].abs() < 3.0, "stage {k} interface {j} open at {r:?}");
            }
            eprintln!(
                "stage {k} {}: opening up to {:.2} µm ({open} points open), slip up to {:.2} µm",
                s["interface"],
                gap * 1e6,
                slip * 1e6
            );
        }

        // hoop stress through the wall at the seams and far from them
        let prof = rows(&dir, &format!("stage{k}_hoop_at_seams.csv"));
        let locations = wall_locations(&run, k);
        assert_eq!(locations.len(), layers + 1);
        let far = locations[0].1;
        for j in 1..=layers {
            let s = o.geometry.layers[j - 1].seam_angle.to_degrees();
            let d = from_seam(far, s, false).abs();
            assert!(
                d > 55.0,
                "stage {k}: far point {far}° only {d}° from seam {j}"
            );
        }
        let lame = wall_lame(&o, st.pressure);
        for r in &prof {
            let (ring, rad, th) = (r[2] as usize, r[3], r[1].to_radians());
            assert!(ring <= layers);
            let v = node_of_ring(&run, ring, [rad * th.cos(), rad * th.sin()]);
            let fe = polar(st.state.stress.nodal[v], x[v], [0.0, 0.0])[1];
            assert!(close(r[4], fe, 1e-9), "stage {k}: {r:?} against {fe}");
            let lame_part = if st.pressure == 0.0 {
                0.0
            } else {
                lame.sigma_tt(rad)
            };
            let an = run.fit.sigma_tt(layers, ring, rad) + lame_part;
            assert!(close(r[5], an, 1e-9), "stage {k}: {r:?} against {an}");
        }
        let column = |loc: usize| prof.iter().filter(move |r| r[0] == loc as f64);
        let far_peak = column(0).map(|r| r[4].abs()).fold(0.0, f64::max);
        for j in 1..=layers {
            let peak = column(j)
                .max_by(|a, b| a[4].abs().total_cmp(&b[4].abs()))
                .unwrap();
            assert_eq!(
                peak[2], j as f64,
                "stage {k}: seam {j} peaks in ring {}",
                peak[2]
            );
            assert!(
                peak[4].abs() > 10.0 * far_peak,
                "stage {k}: seam {j} {:.1} MPa, far {:.1} MPa",
                peak[4] / 1e6,
                far_peak / 1e6
            );
            eprintln!(
                "stage {k} seam {j}: |σ_θθ| up to {:.1} MPa in layer {j} (far from the seams, θ = {far:.2}°: up to {:.2} MPa)",
                peak[4].abs() / 1e6,
                far_peak / 1e6
            );
        }

        // temperatures around the new layer (layer stages)
        if st.pressure != 0.0 {
            continue;
        }
        let temps = rows(&dir, &format!("stage{k}_temperature_circumference.csv"));
        let per_time = temps.len() / 3;
        assert_eq!(temps.len(), 3 * per_time);
        let peaks = summary["layer_surface_temperature"].as_array().unwrap();
        assert_eq!(peaks.len(), 3);
        let half_angle = o.geometry.weld_half_angle(layers - 1).to_degrees();
        let end = &st.state.temperature.as_ref().unwrap();
        let mut by_time: BTreeMap<u64, Vec<&Vec<f64>>> = BTreeMap::new();
        for r in &temps {
            by_time.entry(r[0].to_bits()).or_default().push(r);
        }
        for (i, (&bits, rs)) in by_time.iter().enumerate() {
            let t = f64::from_bits(bits);
            assert_eq!(rs.len(), per_time);
            let hottest = rs
                .iter()
                .map(|r| (r[3].max(r[4]), r))
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .unwrap();
            let p = &peaks[i];
            assert_eq!(p["time_s"].as_f64().unwrap(), t);
            assert!(close(hottest.0, p["max_C"].as_f64().unwrap(), 1e-9));
            if t == 1.0 {
                // the weld is hot and the hottest point lies in it; far
                // from it the layer is at the ambient 21 °C
                assert!(hottest.0 > 400.0, "stage {k}: {}", hottest.0);
                assert!(hottest.1[2].abs() <= half_angle, "{:?}", hottest.1);
                for r in rs.iter().filter(|r| r[2].abs() > 20.0) {
                    assert!(
                        (r[3] - 21.0).abs() < 0.5 && (r[4] - 21.0).abs() < 0.5,
                        "{r:?}"
                    );
                }
            }
            if t == 72000.0 {
                // the end of the cooling: the state's temperatures
                for r in rs {
                    let th = r[1].to_radians();
                    for (c, rad) in [(3, radii[layers]), (4, radii[layers + 1])] {
                        let v = node_of_ring(&run, layers, [rad * th.cos(), rad * th.sin()]);
                        assert!(close(r[c], end[v], 1e-9), "stage {k}: {r:?}, {}", end[v]);
                        assert!((r[c] - 21.0).abs() < 1.0, "stage {k}: {r:?}");
                    }
                }
            }
            eprintln!(
                "stage {k}, t = {t} s: hottest {:.1} °C at {:.2}° from weld {layers}",
                hottest.0, hottest.1[2]
            );
        }
    }
}

/// 2 layers with seams at 0° and 180°: a half section, drawn from the seam.
#[test]
fn a_half_section_is_drawn_from_the_seam() {
    let mut o = MultilayerOptions::new(2, 6.4e-3, Some(&[0.0, 180.0])).unwrap();
    o.quiet = true;
    o.times = vec![1.0, 72000.0];
    assert!(o.half_section());
    let run = analyse(&o).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("ml");
    write_outputs(&run, &dir).unwrap();
    for k in 1..=2 {
        for r in rows(&dir, &format!("stage{k}_temperature_circumference.csv")) {
            assert!(r[2] >= 0.0 && r[2] <= 180.0, "{r:?}");
            let seam = if k == 1 { 0.0 } else { 180.0 };
            // (the CSV's ten digits of θ about the axis: 1e-7° apart)
            assert!((r[2] - (r[1] - seam).abs()).abs() < 1e-6, "{r:?}");
        }
        for r in rows(&dir, &format!("stage{k}_interface_opening_slip.csv")) {
            assert!(r[2] >= 0.0 && r[2] <= 180.0, "{r:?}");
        }
        let fig = temperature_figure(&run, k).unwrap().unwrap();
        assert_eq!(fig.panels[0].x.range, Some((0.0, 20.0)));
        assert_eq!(fig.panels[1].x.range, Some((0.0, 180.0)));
    }
    // far from the seams: θ = 180° after layer 1, 90° once the seam at
    // 180° is there
    let far = |k: usize| wall_locations(&run, k)[0].1;
    assert!(close(far(1).abs(), 180.0, 1e-12), "{}", far(1));
    let f2 = far(2);
    assert!((f2 - 90.0).abs() < 3.0, "{f2}");
}
