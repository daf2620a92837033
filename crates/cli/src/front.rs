//! What `tecon vessel` adds around the analysis: the readable figures, the
//! yield check, the operating-pressure lines of the printed report, the
//! printed report saved as `report.txt`, and the wall-clock times in their
//! own `timing.json` (so that `summary.json` is bitwise the same for any
//! number of threads).

use std::path::Path;

use serde_json::{Value, json};
use tecon_elastic::polar;

use crate::figures::{self, RingTemperature, WallProfile, WallTemperature};
use crate::report_html::REPORT_TEXT;
use crate::vessel::{self, CliResult, VesselArgs, VesselRun};
use crate::yield_check::{self, YieldReport};

/// Keys of the vessel summary that are wall-clock times (moved to `timing.json`).
pub const TIMING_KEYS: [&str; 3] = ["seconds", "seconds_heat_conduction", "seconds_contact"];

/// Moves the wall-clock entries of a summary into a separate object.
pub fn split_timing(v: &mut Value) -> Value {
    let mut t = serde_json::Map::new();
    if let Some(m) = v.as_object_mut() {
        for k in TIMING_KEYS {
            if let Some(x) = m.remove(k) {
                t.insert(k.to_string(), x);
            }
        }
    }
    Value::Object(t)
}

fn write(path: &Path, text: &str) -> CliResult<()> {
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()).into())
}

/// Printed lines of the operating state (`--pressure`): mean hoop stress at
/// the four surfaces with the weld prestress and with the pressure alone.
pub fn pressure_lines(v: &Value) -> Vec<String> {
    let Some(op) = v.get("operating") else {
        return Vec::new();
    };
    let f = |k: &str| op.pointer(k).and_then(Value::as_f64).unwrap_or(f64::NAN) / 1e6;
    let mut s = vec![format!(
        "operating pressure {} MPa after cooling (circumferential mean of σ_θθ, MPa):  with prestress  pressure alone  prestress effect",
        crate::plot::fmt_value(op["pressure"].as_f64().unwrap_or(f64::NAN) / 1e6)
    )];
    for (k, label) in [
        ("core_inner", "core inner"),
        ("core_outer", "core outer"),
        ("layer_inner", "layer inner"),
        ("layer_outer", "layer outer"),
    ] {
        let a = f(&format!("/hoop_mean_with_prestress/{k}"));
        let b = f(&format!("/hoop_mean_pressure_only/{k}"));
        s.push(format!(
            "  {label:<12} {a:>14.2} {b:>15.2} {:>+16.2}",
            a - b
        ));
    }
    s
}

/// A line for the yield check when the peak of a region lies at a corner
/// of the weld (where its edge meets the interface or the outer surface):
/// the elastic stress is singular there, so that peak grows as the mesh is
/// refined and is no material value.
fn weld_corner_note(run: &VesselRun, r: &YieldReport) -> Option<String> {
    let g = &run.options.geometry;
    let theta = g.weld_half_angle();
    let corners =
        [g.interface_radius(), g.outer_radius()].map(|rad| [rad * theta.cos(), rad * theta.sin()]);
    // the longest edge of an element
    let size = |e: usize| {
        let t = run.mesh.triangles().get(e)?;
        let x = |k: usize| run.mesh.nodes()[t[k]];
        (0..3)
            .map(|k| {
                let (a, b) = (x(k), x((k + 1) % 3));
                (a[0] - b[0]).hypot(a[1] - b[1])
            })
            .reduce(f64::max)
    };
    // within a tenth of the layer thickness, or the size of the peak's
    // element, of a corner
    let near = |p: [f64; 2], e: usize| {
        let d = (0.1 * g.layer_thickness).max(size(e).unwrap_or(0.0));
        corners.iter().any(|c| (p[0] - c[0]).hypot(p[1] - c[1]) < d)
    };
    // each peak near a corner, with the angle it lies at (on a coarse mesh
    // the peak's element spans the corner, and its peak is a node or two
    // away from it)
    let at: Vec<String> = r
        .regions
        .iter()
        .filter(|y| near(y.peak_at, y.peak_element))
        .map(|y| {
            format!(
                "{} (θ = {:.2}°)",
                y.region,
                y.peak_at[1].atan2(y.peak_at[0]).to_degrees()
            )
        })
        .collect();
    (!at.is_empty()).then(|| {
        let (which, verb) = if at.len() > 1 {
            ("peaks of regions", "lie")
        } else {
            ("peak of region", "lies")
        };
        let d = &run.options.data;
        // the axial stress of a weld that cannot shorten (ε_zz = 0) as it
        // cools from the weld temperature: E α ΔT
        let axial = d.youngs_modulus * d.expansion * (d.weld_temperature - d.ambient);
        format!(
            "the {which} {} {verb} at or within one element of a weld corner (the weld edge at θ = {:.2}°), where the elastic stress is singular: such a peak grows as the mesh is refined (the real weld yields locally there, which an elastic analysis cannot resolve). The weld's von Mises stress is high everywhere, not only at the corner: in plane strain the weld cannot shorten along its axis as it cools, so its axial stress is about E α ΔT = {:.1} GPa, far above any yield stress (a real weld yields along its axis). The mean hoop prestress converges with the mesh; the hoop stress at the weld plane needs fine meshes (docs/vessel.md §9: within about 1 % on the default g0, 29 % off on the linear level 2, and coarser meshes worse)",
            at.join(" and "),
            theta.to_degrees(),
            axial / 1e9
        )
    })
}

/// The yield check of the cooled state (and of the operating state with `--pressure`).
pub fn yield_reports(run: &VesselRun, yield_stress: Option<f64>) -> Vec<(String, YieldReport)> {
    let y = |_: &str| yield_stress;
    let mut v = Vec::new();
    if let Some(last) = run.results.last() {
        v.push((
            format!(
                "after cooling (t = {} s)",
                crate::plot::fmt_value(last.time)
            ),
            yield_check::check(&run.mesh, &last.stress, &y),
        ));
    }
    if let Some(op) = run.operating.as_ref().map(|s| &s.stress) {
        v.push((
            "operating (with prestress)".to_string(),
            yield_check::check(&run.mesh, op, &y),
        ));
    }
    v
}

fn body_index(run: &VesselRun, name: &str) -> usize {
    run.mesh
        .bodies()
        .iter()
        .position(|b| b.name.split('+').any(|n| n == name))
        .unwrap_or(0)
}

/// Nodes of a body on the circle of radius r, sorted by θ.
fn ring(run: &VesselRun, body: usize, r: f64) -> Vec<usize> {
    let m = &run.mesh;
    let th = |i: usize| m.nodes()[i][1].atan2(m.nodes()[i][0]);
    let mut v: Vec<usize> = (0..m.n_nodes())
        .filter(|&i| {
            m.node_bodies()[i] == body
                && (m.nodes()[i][0].hypot(m.nodes()[i][1]) - r).abs() < 1e-9 * r
        })
        .collect();
    v.sort_by(|&a, &b| th(a).total_cmp(&th(b)));
    v
}

/// Nodal temperature of a state (NaN without a thermal field).
fn temp_at(r: &crate::driver::State, i: usize) -> f64 {
    r.temperature.as_ref().map_or(f64::NAN, |t| t[i])
}

/// Writes the vessel's figures (SVG and PNG, each once) and `interface_final.csv`
/// (one row per interface point, sorted by θ) into `dir`.
pub fn write_figures(run: &VesselRun, dir: &Path) -> CliResult<()> {
    let Some(last) = run.results.last() else {
        return Ok(());
    };
    let m = &run.mesh;
    let g = &run.options.geometry;
    let o = &run.options;
    let (core, layer) = (body_index(run, "core"), body_index(run, "layer"));
    let deg = |i: usize| m.nodes()[i][1].atan2(m.nodes()[i][0]).to_degrees();
    let (ri, rc, ro) = (g.inner_radius, g.interface_radius(), g.outer_radius());
    let wall = |r: f64| 100.0 * (r - ri) / (ro - ri);

    // fig6
    let l_in = ring(run, layer, rc);
    let l_out = ring(run, layer, ro);
    let rings: Vec<RingTemperature> = run
        .results
        .iter()
        .map(|r| RingTemperature {
            time: r.time,
            inner: l_in.iter().map(|&i| (deg(i), temp_at(r, i))).collect(),
            outer: l_out.iter().map(|&i| (deg(i), temp_at(r, i))).collect(),
        })
        .collect();
    figures::fig6(&rings).write_svg_png(&dir.join("fig6_temperature_circumference"))?;

    // fig7: weld centre and two angles beside it, every time
    let core_r: Vec<f64> = (0..=o.mesh.core_rows)
        .map(|j| ri + (rc - ri) * j as f64 / o.mesh.core_rows as f64)
        .collect();
    let layer_r: Vec<f64> = (0..=o.mesh.layer_rows)
        .map(|j| rc + (ro - rc) * j as f64 / o.mesh.layer_rows as f64)
        .collect();
    let column = |body: usize, radii: &[f64], angle: f64| -> Vec<usize> {
        radii
            .iter()
            .filter_map(|&r| {
                ring(run, body, r)
                    .into_iter()
                    .min_by(|&p, &q| (deg(p) - angle).abs().total_cmp(&(deg(q) - angle).abs()))
            })
            .collect()
    };
    let mut profiles = Vec::new();
    for angle in [0.0, 2.0, 10.0] {
        let (cc, lc) = (column(core, &core_r, angle), column(layer, &layer_r, angle));
        let actual = lc.first().map_or(angle, |&i| deg(i));
        for r in &run.results {
            let pts = |nodes: &[usize]| -> Vec<(f64, f64)> {
                nodes
                    .iter()
                    .map(|&i| (wall(m.nodes()[i][0].hypot(m.nodes()[i][1])), temp_at(r, i)))
                    .collect()
            };
            profiles.push(WallTemperature {
                time: r.time,
                angle: actual,
                core: pts(&cc),
                layer: pts(&lc),
            });
        }
    }
    figures::fig7(&profiles).write_svg_png(&dir.join("fig7_temperature_through_wall"))?;

    // fig8 and fig11: the circumferential means of the recovered nodal hoop
    // stress on every node ring, the numbers of the report, summary.json and
    // the figures' CSV (element-row means, plotted before, differed from
    // them by up to 28 % on the paper mesh)
    let profile = vessel::hoop_profile(run, &last.stress);
    let side = |in_core: bool| -> Vec<(f64, f64)> {
        profile
            .iter()
            .filter(|p| p.1 == in_core)
            .map(|&(w, _, _, m)| (w, m / 1e6))
            .collect()
    };
    let fe = WallProfile {
        label: "FE (circumferential mean on each node ring)".into(),
        core: side(true),
        layer: side(false),
    };
    let an = vessel::analytical(o);
    let model = |label: &str, f: &tecon_elastic::analytical::ShrinkFit| {
        let pts = |a: f64, b: f64, in_core: bool| -> Vec<(f64, f64)> {
            (0..=24)
                .map(|k| a + (b - a) * k as f64 / 24.0)
                .map(|r| (wall(r), f.sigma_tt(r, in_core) / 1e6))
                .collect()
        };
        WallProfile {
            label: label.into(),
            core: pts(f.a, f.c, true),
            layer: pts(f.c, f.b, false),
        }
    };
    let consistent = model(
        "two cylinders, plane-strain consistent δ = (1+ν)αΔTw/2π",
        &an[2].1,
    );
    figures::through_wall(
        "Hoop prestress through the wall after cooling",
        &fe,
        std::slice::from_ref(&consistent),
    )
    .write_svg_png(&dir.join("fig8_hoop_prestress_through_wall"))?;
    figures::through_wall(
        "Hoop prestress: FE against the shrink-fit models",
        &fe,
        &[
            consistent,
            model("two cylinders, plane strain δ = αΔTw/2π", &an[0].1),
            model("two cylinders, classical plane stress", &an[1].1),
        ],
    )
    .write_svg_png(&dir.join("fig11_hoop_fe_vs_analytical"))?;

    // fig9
    let hoop = |i: usize| polar(last.stress.nodal[i], m.nodes()[i], [0.0, 0.0])[1] / 1e6;
    let c_in = ring(run, core, ri);
    figures::fig9(
        &c_in.iter().map(|&i| (deg(i), hoop(i))).collect::<Vec<_>>(),
        &l_out.iter().map(|&i| (deg(i), hoop(i))).collect::<Vec<_>>(),
    )
    .write_svg_png(&dir.join("fig9_hoop_circumference"))?;

    // fig10: tangential displacement of the outer surface
    let u = &last.displacement;
    let ut = |i: usize| {
        let t = m.nodes()[i][1].atan2(m.nodes()[i][0]);
        -u[2 * i] * t.sin() + u[2 * i + 1] * t.cos()
    };
    let kappa = if o.analysis == tecon_elastic::Analysis::PlaneStrain {
        1.0 + o.data.poisson_ratio
    } else {
        1.0
    };
    let shrink =
        kappa * o.data.expansion * (o.data.weld_temperature - o.data.ambient) * g.weld_half_width;
    figures::fig10(
        &l_out
            .iter()
            .map(|&i| (deg(i), ut(i) * 1e6))
            .collect::<Vec<_>>(),
        -shrink * 1e6,
    )
    .write_svg_png(&dir.join("fig10_tangential_displacement"))?;

    // interface: one row per point, sorted by θ
    let rows = figures::interface_rows(&last.interface, [0.0, 0.0]);
    write(
        &dir.join("interface_final.csv"),
        &figures::interface_csv(&rows),
    )?;
    // (a bonded interface has no interface points: nothing to plot)
    if !rows.is_empty() {
        // each figure beside its own data (the full table is interface_final.csv)
        let consistent = an[2].1.pressure();
        write(
            &dir.join("interface_contact_pressure.csv"),
            &figures::csv_text(
                &[
                    "theta_deg",
                    "contact_pressure_Pa",
                    "analytical_plane_strain_consistent_Pa",
                ],
                rows.iter()
                    .map(|r| vec![r.theta_deg, r.pressure, consistent]),
            ),
        )?;
        figures::interface_pressure(
            &rows,
            Some(("two cylinders, plane-strain consistent", consistent)),
        )
        .write_svg_png(&dir.join("interface_contact_pressure"))?;
        write(
            &dir.join("interface_slip.csv"),
            &figures::csv_text(
                &["theta_deg", "slip_m", "jump_t_m"],
                rows.iter().map(|r| vec![r.theta_deg, r.slip, r.jump_t]),
            ),
        )?;
        figures::interface_slip(&rows).write_svg_png(&dir.join("interface_slip"))?;
    }
    Ok(())
}

/// Runs `tecon vessel` (one analysis; `--study` goes to [`vessel::study`]):
/// analysis, outputs, readable figures, yield check, report. Returns the
/// warnings for `report.html`.
pub fn vessel(args: VesselArgs, yield_stress: Option<f64>) -> CliResult<Vec<String>> {
    if let Some(n) = args.layers {
        return crate::multilayer_out::run(&args, n, yield_stress);
    }
    let base = vessel::options(&args)?;
    if let Some(s) = args.study.as_deref() {
        if s != "mesh" {
            return Err(format!("--study '{s}': the only study is 'mesh'").into());
        }
        vessel::study(&base, &args.out, args.mesh.starts_with('g'))?;
        return Ok(Vec::new());
    }
    let out = &args.out;
    let what = format!("--mesh {}", args.mesh);
    crate::memory::check_generation(&base.mesh).map_err(|e| format!("{what}: {e}"))?;
    crate::memory::check(&what, base.mesh.n_triangles(), base.mesh.order)?;
    let run = vessel::analyse(&base)?;
    let mut v = vessel::summary(&run);
    let timing = split_timing(&mut v);
    let checks = yield_reports(&run, yield_stress);
    v["yield_check"] = Value::Object(
        checks
            .iter()
            .map(|(k, r)| (k.clone(), r.to_json()))
            .collect(),
    );
    let mut warnings = Vec::new();
    for (when, r) in &checks {
        warnings.extend(r.warnings().into_iter().map(|w| format!("{when}: {w}")));
    }
    if !warnings.is_empty() {
        v["warnings"] = json!(warnings);
    }
    vessel::write_outputs(&run, &v, out)?;
    write(
        &out.join("timing.json"),
        &(serde_json::to_string_pretty(&timing)? + "\n"),
    )?;
    let mut text = vessel::report(&run, &v);
    for l in pressure_lines(&v) {
        text += &l;
        text.push('\n');
    }
    for (when, r) in &checks {
        text += &format!("yield check {when}:\n");
        for l in r.lines(true) {
            text += &format!("  {l}\n");
        }
        if let Some(l) = weld_corner_note(&run, r) {
            text += &format!("  {l}\n");
        }
    }
    for w in &warnings {
        text += &format!("warning: {w}\n");
    }
    write(&out.join(REPORT_TEXT), &text)?;
    if args.quiet {
        // nothing but the warnings (stderr); the report is in report.txt
        for w in &warnings {
            eprintln!("warning: {w}");
        }
    } else {
        print!("{text}");
        println!("results in {}", out.display());
    }
    Ok(warnings)
}

/// The inputs of a `tecon vessel` run as the model resolves them (mesh size
/// and element order, joint law and its parameters, materials, schedule,
/// coupling), for the report's input table: defaults are shown by value,
/// not as options left unset. Command lines that do not resolve (the error
/// is reported by the run itself) and `--layers` runs list the options as
/// given.
pub fn vessel_inputs(args: &VesselArgs) -> Option<Vec<(String, String)>> {
    if let Some(n) = args.layers {
        return multilayer_inputs(args, n);
    }
    let o = vessel::options(args).ok()?;
    let g = &o.geometry;
    let d = &o.data;
    let mut rows: Vec<(String, String)> = Vec::new();
    let mut row = |k: &str, v: String| rows.push((k.to_string(), v));
    row(
        "mesh",
        format!(
            "{} ({} triangles, order {}{})",
            args.mesh,
            o.mesh.n_triangles(),
            o.mesh.order,
            if o.mesh.fused_weld {
                ", weld fused to the layer"
            } else {
                ""
            }
        ),
    );
    row(
        "geometry",
        format!(
            "inner radius {} m, core {} m, layer {} m, weld half width {} m",
            g.inner_radius, g.core_thickness, g.layer_thickness, g.weld_half_width
        ),
    );
    row(
        "analysis",
        match o.analysis {
            tecon_elastic::Analysis::PlaneStrain => "plane strain".into(),
            other => format!("{other:?}"),
        },
    );
    let joint = match o.interface {
        crate::builtin::InterfaceKind::Frictional => format!(
            "frictional: μ = {}, cohesion {} Pa, penalty factor {}{}",
            o.friction,
            o.cohesion,
            o.penalty_factor,
            match o.augmented_lagrangian {
                Some(t) => format!(", augmented Lagrangian to {t}"),
                None => ", pure penalty".into(),
            }
        ),
        crate::builtin::InterfaceKind::Frictionless => format!(
            "frictionless, penalty factor {}{}",
            o.penalty_factor,
            match o.augmented_lagrangian {
                Some(t) => format!(", augmented Lagrangian to {t}"),
                None => ", pure penalty".into(),
            }
        ),
        crate::builtin::InterfaceKind::Bonded => "bonded (tied nodes)".into(),
    };
    row("core/layer joint", joint);
    row(
        "interface normals",
        format!("{:?}", o.normals).to_lowercase(),
    );
    row("materials (all regions)", material_text(d));
    row(
        "temperatures",
        format!(
            "weld {} °C at t = 0, rest and ambient {} °C, film {} W/(m² K)",
            d.weld_temperature, d.ambient, d.film
        ),
    );
    row(
        "interface conductance",
        if o.contact_conductance {
            "contact law (pressure power law plus gas gap)".into()
        } else {
            format!("constant {} W/(m² K)", d.interface_conductance)
        },
    );
    row(
        "coupling",
        match &o.two_way {
            None => "one-way (heat conduction first, then the mechanics)".into(),
            Some(t) => match t.sync_tolerance {
                Some(tau) => format!("two-way, adaptive blocks (tolerance {tau})"),
                None => format!(
                    "two-way, {} thermal steps per contact solve",
                    t.sync_interval
                ),
            },
        },
    );
    row("output times", times_text(&o.times));
    row(
        "operating pressure",
        match o.pressure {
            Some(p) => format!("{p} Pa after cooling"),
            None => "none".into(),
        },
    );
    if let Some(s) = &args.study {
        row("study", s.clone());
    }
    Some(rows)
}

/// The inputs of a `tecon vessel --layers N` run as resolved (see
/// [`vessel_inputs`]).
fn multilayer_inputs(args: &VesselArgs, n: usize) -> Option<Vec<(String, String)>> {
    let mut o =
        crate::multilayer::MultilayerOptions::new(n, args.layer_thickness, args.seams.as_deref())
            .ok()?;
    o.set_mesh(
        crate::multilayer_out::mesh_level(&args.mesh).ok()?,
        args.order.unwrap_or(1),
    )
    .ok()?;
    let g = &o.geometry;
    let mut rows: Vec<(String, String)> = Vec::new();
    let mut row = |k: &str, v: String| rows.push((k.to_string(), v));
    row(
        "section",
        format!(
            "core: inner radius {} m, thickness {} m; {n} layers ({} section)",
            g.inner_radius,
            g.core_thickness,
            if o.half_section() { "half" } else { "full" }
        ),
    );
    for (k, l) in g.layers.iter().enumerate() {
        row(
            &format!("layer {}", k + 1),
            format!(
                "thickness {} m, weld half width {} m, seam at {}°",
                l.thickness,
                l.weld_half_width,
                crate::plot::fmt_value(l.seam_angle.to_degrees())
            ),
        );
    }
    row(
        "joints",
        format!(
            "frictional: μ = {}, cohesion 0 Pa, k_s/k_n = {}",
            args.friction.unwrap_or(o.friction),
            o.effective_shear_ratio()
        ),
    );
    let d = &o.data;
    row("materials (all regions)", material_text(d));
    row(
        "temperatures",
        format!(
            "each weld {} °C when welded, rest and ambient {} °C, film {} W/(m² K)",
            d.weld_temperature, d.ambient, d.film
        ),
    );
    row("output times of each stage", times_text(&args.times));
    row(
        "operating pressure",
        match args.pressure {
            Some(p) => format!("{p} Pa after the last layer"),
            None => "none".into(),
        },
    );
    Some(rows)
}

/// The published material data as one line of the report's input table.
fn material_text(d: &crate::builtin::VesselData) -> String {
    format!(
        "E = {} GPa, ν = {}, α = {:e} 1/K, k = {} W/(m K), ρ = {} kg/m³, c = {} J/(kg K)",
        d.youngs_modulus / 1e9,
        d.poisson_ratio,
        d.expansion,
        d.conductivity,
        d.density,
        d.specific_heat
    )
}

/// Output times as "1 s, 10 s, …".
fn times_text(times: &[f64]) -> String {
    times
        .iter()
        .map(|t| format!("{t} s"))
        .collect::<Vec<_>>()
        .join(", ")
}
