//! The multilayer run's outputs and the `tecon vessel --layers` command;
//! the outputs are shared by `tecon vessel --layers` and
//! `tecon run` with `[[stage]]` entries: per stage the hoop stress through
//! the wall (circumferential means per element row against the sequential
//! shrink fit) as CSV and figure, every interface's contact pressure around
//! the circumference (one row per interface point, sorted by angle) as CSV
//! and figure, the VTU and a summary; the whole run's summary and the text
//! report.

use std::path::Path;

use serde_json::{Value, json};
use tecon_elastic::polar;

use crate::figures::{self, InterfaceRow};
use crate::multilayer::{MultilayerRun, interface_name, wall_lame};
use crate::plot::{Axis, Figure, LegendAt, Line, Panel};
use crate::writers::{self, CliResult, csv, write_state_vtu};

/// The closed-form hoop stress at radius `r` of ring `ring` after stage
/// `stage`: the sequential shrink fit, plus for a pressure stage the Lamé
/// field of the whole wall.
fn closed_form_hoop(run: &MultilayerRun, stage: usize, ring: usize, r: f64) -> f64 {
    let st = &run.stages[stage - 1];
    let pressure_part = if st.pressure == 0.0 {
        0.0
    } else {
        wall_lame(&run.options, st.pressure).sigma_tt(r)
    };
    run.fit.sigma_tt(st.layers, ring, r) + pressure_part
}

/// Hoop-stress rows through the wall after stage `stage`: per ring and
/// element row (band between node rows), (ring, mid radius, FE band mean
/// of σ_θθ, closed form at the mid radius).
fn hoop_rows(run: &MultilayerRun, stage: usize) -> Vec<Vec<f64>> {
    let k = run.stages[stage - 1].layers;
    let mut rows = Vec::new();
    for ring in 0..=k {
        for (r, fe) in band_means(run, stage, ring) {
            rows.push(vec![
                ring as f64,
                r,
                fe,
                closed_form_hoop(run, stage, ring, r),
            ]);
        }
    }
    rows
}

/// The summary of stage `stage` (1-based) as JSON (SI units).
pub fn stage_summary(run: &MultilayerRun, stage: usize) -> Value {
    let st = &run.stages[stage - 1];
    let k = st.layers;
    let rings: Vec<Value> = (0..=k)
        .map(|r| {
            let (fe, an) = (st.ring_means[r], st.analytical_means[r]);
            json!({
                "ring": if r == 0 { "core".to_string() } else { format!("layer{r}") },
                "mean_hoop_fe": fe,
                "mean_hoop_analytical": an,
                "relative_error": (fe - an) / an,
            })
        })
        .collect();
    let interfaces: Vec<Value> = (1..=k)
        .map(|j| {
            let (fe, an) = (st.pressures[j - 1], st.analytical_pressures[j - 1]);
            json!({
                "interface": interface_name(j),
                "mean_pressure_fe": fe,
                "pressure_analytical": an,
                "relative_error": (fe - an) / an,
            })
        })
        .collect();
    json!({
        "stage": stage,
        "kind": if st.pressure == 0.0 { "layer" } else { "pressure" },
        "layers_active": k,
        "internal_pressure": st.pressure,
        "rings": rings,
        "interfaces": interfaces,
        "newton_iterations": st.newton_iterations,
        "thermal_steps": st.thermal_steps,
        "max_heat_balance_residual": st.heat_balance,
        "end_time_s": st.state.time,
    })
}

/// The summary of the whole run.
pub fn summary(run: &MultilayerRun) -> Value {
    let g = &run.options.geometry;
    let worst = run
        .stages
        .iter()
        .flat_map(|s| {
            (0..=s.layers).map(move |r| {
                ((s.ring_means[r] - s.analytical_means[r]) / s.analytical_means[r]).abs()
            })
        })
        .fold(0.0, f64::max);
    json!({
        "geometry": {
            "inner_radius": g.inner_radius,
            "core_thickness": g.core_thickness,
            "layers": g.layers.iter().map(|l| json!({
                "thickness": l.thickness,
                "weld_half_width": l.weld_half_width,
                "seam_angle_deg": l.seam_angle.to_degrees(),
            })).collect::<Vec<_>>(),
            "half_section": run.options.half_section(),
            "internal_pressure": run.options.pressure,
            "shear_penalty_ratio": run.options.effective_shear_ratio(),
        },
        "mesh": { "triangles": run.mesh.n_triangles(), "nodes": run.mesh.n_nodes() },
        "stages": (1..=run.stages.len()).map(|k| stage_summary(run, k)).collect::<Vec<_>>(),
        "max_relative_error_ring_means": worst,
    })
}

/// First column of the per-stage interface CSVs (then
/// [`figures::INTERFACE_HEADER`]).
pub const STAGE_INTERFACE_COLUMN: &str = "interface (1: core/layer 1, k: layer k-1/layer k)";

/// The interface points of stage `k` (1-based): one row per point, merged
/// where two elements meet, sorted by interface and then by θ about the
/// vessel axis (θ in (−180°, 180°]).
pub fn stage_interface_rows(run: &MultilayerRun, stage: usize) -> Vec<InterfaceRow> {
    figures::interface_rows(&run.stages[stage - 1].state.interface, [0.0, 0.0])
}

/// Circumferential means of the element hoop stress in each band between
/// node rows of `ring` (0 = core, its weld included): (mid radius, mean
/// σ_θθ), weighted by area / r as the ring means. Elements are constant
/// stress at order 1, so band means carry no node-row zig-zag.
pub fn band_means(run: &MultilayerRun, stage: usize, ring: usize) -> Vec<(f64, f64)> {
    let mesh = &run.mesh;
    let stress = &run.stages[stage - 1].state.stress.element;
    let radii = run.options.geometry.radii();
    let rows_n = if ring == 0 {
        run.options.spec.core_rows
    } else {
        run.options.spec.layer_rows
    };
    let (r_in, r_out) = (radii[ring], radii[ring + 1]);
    let dr = (r_out - r_in) / rows_n as f64;
    let mut acc = vec![(0.0, 0.0); rows_n];
    let names = mesh.region_names();
    let x = mesh.nodes();
    for (e, t) in mesh.triangles().iter().enumerate() {
        if !crate::multilayer::in_ring(&names[mesh.element_regions()[e]], ring) {
            continue;
        }
        let p = t.map(|v| x[v]);
        let c = [
            (p[0][0] + p[1][0] + p[2][0]) / 3.0,
            (p[0][1] + p[1][1] + p[2][1]) / 3.0,
        ];
        let rc = c[0].hypot(c[1]);
        let band = (((rc - r_in) / dr).floor().max(0.0) as usize).min(rows_n - 1);
        let area = 0.5
            * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
                .abs();
        let w = area / rc;
        acc[band].0 += polar(stress[e], c, [0.0, 0.0])[1] * w;
        acc[band].1 += w;
    }
    acc.iter()
        .enumerate()
        .filter(|(_, (_, w))| *w > 0.0)
        .map(|(j, (s, w))| (r_in + (j as f64 + 0.5) * dr, s / w))
        .collect()
}

/// Figure: the hoop stress through the wall after stage `stage`, the FE
/// circumferential means per element row (markers, one segment per ring)
/// against the sequential shrink fit (dashed).
pub fn hoop_figure(run: &MultilayerRun, stage: usize) -> Figure {
    let r0 = run.options.geometry.inner_radius;
    let st = &run.stages[stage - 1];
    let mut fe = Vec::new();
    for ring in 0..=st.layers {
        if ring > 0 {
            fe.push((f64::NAN, f64::NAN));
        }
        fe.extend(
            band_means(run, stage, ring)
                .into_iter()
                .map(|(r, s)| ((r - r0) * 1e3, s / 1e6)),
        );
    }
    let radii = run.options.geometry.radii();
    let mut an = Vec::new();
    for ring in 0..=st.layers {
        if ring > 0 {
            an.push((f64::NAN, f64::NAN));
        }
        const SAMPLES: usize = 16;
        for j in 0..=SAMPLES {
            let r = radii[ring] + (radii[ring + 1] - radii[ring]) * j as f64 / SAMPLES as f64;
            an.push(((r - r0) * 1e3, closed_form_hoop(run, stage, ring, r) / 1e6));
        }
    }
    let what = if st.pressure == 0.0 {
        format!("after layer {} is welded", st.layers)
    } else {
        format!("under {} MPa internal pressure", st.pressure / 1e6)
    };
    Figure {
        title: String::new(),
        panels: vec![Panel {
            title: format!("Hoop stress through the wall, stage {stage} ({what})"),
            x: Axis::linear("distance from the bore [mm]; core, then layer 1, 2, …"),
            y: Axis::linear("σ_θθ [MPa]"),
            lines: vec![
                Line::solid("FE (circumferential mean per element row)", 0, fe).with_markers(),
                Line::dashed("sequential shrink fit (closed form)", 1, an),
            ],
            legend: LegendAt::UpperLeft,
            ..Default::default()
        }],
        size: (900, 600),
    }
}

/// Figure: every active interface's contact pressure around the
/// circumference after stage `stage` (one colour per interface), with its
/// closed-form mean (dashed, same colour).
pub fn pressure_figure(run: &MultilayerRun, stage: usize) -> Figure {
    let st = &run.stages[stage - 1];
    let rows = stage_interface_rows(run, stage);
    let half = run.options.half_section();
    let (lo, hi) = if half { (0.0, 180.0) } else { (-180.0, 180.0) };
    let mut lines = Vec::new();
    for j in 1..=st.layers {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.interface == j - 1)
            .map(|r| (r.theta_deg, r.pressure / 1e6))
            .collect();
        lines.push(Line::solid(interface_name(j), j - 1, pts));
        let p = st.analytical_pressures[j - 1] / 1e6;
        lines.push(Line::dashed("", j - 1, vec![(lo, p), (hi, p)]));
    }
    Figure {
        title: String::new(),
        panels: vec![Panel {
            title: format!(
                "Contact pressure of every interface, stage {stage} (dashed: closed form)"
            ),
            x: Axis::linear("θ about the vessel axis [°] (seam of layer 1 at 0°)").range(lo, hi),
            y: Axis::linear("contact pressure [MPa]"),
            lines,
            legend: LegendAt::UpperRight,
            ..Default::default()
        }],
        size: (1100, 600),
    }
}

/// Writes every stage's files and the summaries into `dir`; returns the
/// names of the files written.
pub fn write_outputs(run: &MultilayerRun, dir: &Path) -> CliResult<Vec<String>> {
    let mut names = Vec::new();
    writers::staged(dir, |tmp| {
        let mut pvd = Vec::new();
        for k in 1..=run.stages.len() {
            let st = &run.stages[k - 1];
            let name = format!("stage{k}_hoop_through_wall.csv");
            csv(
                &tmp.join(&name),
                "ring (0 core; k layer k),r_mid_m,hoop_fe_row_mean_Pa,hoop_closed_form_Pa",
                hoop_rows(run, k),
            )?;
            names.push(name);
            let stem = format!("stage{k}_hoop_through_wall");
            hoop_figure(run, k).write_svg_png(&tmp.join(&stem))?;
            names.extend([format!("{stem}.svg"), format!("{stem}.png")]);
            let name = format!("stage{k}_interface_pressure.csv");
            let rows = stage_interface_rows(run, k);
            writers::write(
                &tmp.join(&name),
                &figures::csv_text(
                    &[
                        &[STAGE_INTERFACE_COLUMN][..],
                        &figures::INTERFACE_HEADER[..],
                    ]
                    .concat(),
                    rows.iter().map(|r| {
                        let mut v = vec![(r.interface + 1) as f64];
                        v.extend(figures::interface_values(r));
                        v
                    }),
                ),
            )?;
            names.push(name);
            let stem = format!("stage{k}_interface_pressure");
            pressure_figure(run, k).write_svg_png(&tmp.join(&stem))?;
            names.extend([format!("{stem}.svg"), format!("{stem}.png")]);
            let name = format!("multilayer_{k:03}.vtu");
            write_state_vtu(&run.mesh, &tmp.join(&name), &st.state)?;
            pvd.push((k as f64, name.clone()));
            names.push(name);
            let name = format!("stage{k}_summary.json");
            writers::write(
                &tmp.join(&name),
                &serde_json::to_string_pretty(&stage_summary(run, k))?,
            )?;
            names.push(name);
        }
        tecon_mesh::vtk::write_pvd(tmp.join("multilayer.pvd"), &pvd)?;
        names.push("multilayer.pvd".into());
        writers::write(
            &tmp.join("summary.json"),
            &serde_json::to_string_pretty(&summary(run))?,
        )?;
        names.push("summary.json".into());
        // wall times apart, so that summary.json is bitwise the same for
        // any thread count (as for `tecon vessel` and `tecon run`)
        writers::write(
            &tmp.join("timing.json"),
            &(serde_json::to_string_pretty(&timing(run))? + "\n"),
        )?;
        names.push("timing.json".into());
        Ok(names.clone())
    })?;
    Ok(names)
}

/// Wall-clock seconds of the run and of each stage's heat conduction and
/// contact solves.
pub fn timing(run: &MultilayerRun) -> Value {
    json!({
        "seconds": run.seconds,
        "stages": run.stages.iter().enumerate().map(|(i, st)| json!({
            "stage": i + 1,
            "seconds_heat_conduction": st.seconds.0,
            "seconds_contact": st.seconds.1,
        })).collect::<Vec<_>>(),
    })
}

/// A short text report.
pub fn report(run: &MultilayerRun) -> String {
    let mut s = format!(
        "multilayer vessel: {} layers, {} triangles ({}), {:.1} s\n",
        run.options.geometry.layers.len(),
        run.mesh.n_triangles(),
        if run.options.half_section() {
            "half section"
        } else {
            "full section"
        },
        run.seconds
    );
    for (i, st) in run.stages.iter().enumerate() {
        let k = st.layers;
        let what = if st.pressure == 0.0 {
            format!("layer {k} welded")
        } else {
            format!("internal pressure {:.3} MPa", st.pressure / 1e6)
        };
        s += &format!(
            "stage {} ({what}): {} Newton iterations, {} thermal steps\n",
            i + 1,
            st.newton_iterations,
            st.thermal_steps
        );
        for r in 0..=k {
            let an = st.analytical_means[r];
            s += &format!(
                "  {:>7} mean hoop {:>9.4} MPa (closed form {:>9.4} MPa, {:+.2} %)\n",
                if r == 0 {
                    "core".into()
                } else {
                    format!("layer{r}")
                },
                st.ring_means[r] / 1e6,
                an / 1e6,
                100.0 * (st.ring_means[r] - an) / an
            );
        }
        for j in 1..=k {
            let an = st.analytical_pressures[j - 1];
            s += &format!(
                "  {:>13} mean pressure {:.5} MPa (closed form {:.5} MPa)\n",
                interface_name(j),
                st.pressures[j - 1] / 1e6,
                an / 1e6
            );
        }
    }
    s
}

/// `tecon vessel --layers N …`: builds the options, runs, writes, reports.
/// Returns the warnings (a yield stress exceeded). The printed report is
/// also saved as `report.txt`; `--quiet` prints nothing but the warnings.
pub fn run(
    args: &crate::vessel::VesselArgs,
    n: usize,
    yield_stress: Option<f64>,
) -> CliResult<Vec<String>> {
    let unsupported = [
        ("--fused-weld", args.fused_weld),
        ("--free-ends", args.free_ends),
        ("--penalty-only", args.penalty_only),
        ("--element-normals", args.element_normals),
        ("--study", args.study.is_some()),
        ("--conductance contact", args.conductance != "constant"),
        ("--coupling two-way", args.coupling != "one-way"),
        ("--cohesion", args.cohesion.is_some_and(|c| c != 0.0)),
        ("--interface", args.interface != "frictional"),
        ("--order", args.order.is_some_and(|o| o != 1)),
        (
            "--mesh (the multilayer mesh has its own density)",
            args.mesh != crate::builtin::DEFAULT_MESH,
        ),
    ];
    if let Some((name, _)) = unsupported.iter().find(|(_, on)| *on) {
        return Err(format!("{name} is not available with --layers yet").into());
    }
    let mut o =
        crate::multilayer::MultilayerOptions::new(n, args.layer_thickness, args.seams.as_deref())?;
    if let Some(f) = args.friction {
        if !(f.is_finite() && f >= 0.0) {
            return Err(format!("--friction {f}: must be non-negative").into());
        }
        o.friction = f;
    }
    o.times = args.times.clone();
    o.quiet = args.quiet;
    o.condensation = !args.no_condensation;
    if let Some(p) = args.pressure {
        if !(p.is_finite() && p > 0.0) {
            return Err(format!("--pressure {p}: must be a positive pressure in Pa").into());
        }
        o.pressure = Some(p);
    }
    let run = crate::multilayer::analyse(&o)?;
    write_outputs(&run, &args.out)?;
    let mut text = report(&run);
    let mut warnings = Vec::new();
    let y = |_: &str| yield_stress;
    for (k, st) in run.stages.iter().enumerate() {
        let mut check = crate::yield_check::check(&run.mesh, &st.state.stress, &y);
        // the layers not wrapped yet carry no stress: not part of the check
        check
            .regions
            .retain(|r| (0..=st.layers).any(|ring| crate::multilayer::in_ring(&r.region, ring)));
        text += &format!("yield check after stage {}:\n", k + 1);
        for l in check.lines(true) {
            text += &format!("  {l}\n");
        }
        warnings.extend(
            check
                .warnings()
                .into_iter()
                .map(|w| format!("stage {}: {w}", k + 1)),
        );
    }
    for w in &warnings {
        text += &format!("warning: {w}\n");
    }
    crate::writers::write(&args.out.join(crate::report_html::REPORT_TEXT), &text)?;
    if args.quiet {
        for w in &warnings {
            eprintln!("warning: {w}");
        }
    } else {
        print!("{text}");
        println!("results in {}", args.out.display());
    }
    Ok(warnings)
}
