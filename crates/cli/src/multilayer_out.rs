//! The multilayer run's outputs and the `tecon vessel --layers` command;
//! the outputs are shared by `tecon vessel --layers` and
//! `tecon run` with `[[stage]]` entries. Per stage, each figure as CSV, SVG
//! and PNG:
//!
//! * the hoop stress through the wall (circumferential means per element
//!   row against the sequential shrink fit), and through the wall at every
//!   seam and far from the seams (nodal σ_θθ of one node column);
//! * every interface's contact pressure, and its opening and slip, around
//!   the circumference, each beside a detail of ±3° about the weld of the
//!   layer above the interface;
//! * for a layer stage, the temperature around layer k's inner and outer
//!   surfaces at each output time of weld k's cooling;
//!
//! then the VTU and a summary; the whole run's summary and the text report.

use std::path::Path;

use serde_json::{Value, json};
use tecon_elastic::polar;

use crate::figures::{self, InterfaceRow, WELD_DETAIL_DEG, WELD_ZONE_DEG, time_label};
use crate::multilayer::{MultilayerRun, in_ring, interface_name, wall_lame};
use crate::plot::{Axis, Figure, LegendAt, Line, Panel, fmt_value};
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

/// The angle from the seam at `seam` (°) to `theta` (°): wrapped into
/// (−180°, 180°] on a full ring; its magnitude on a half section, where
/// the two sides of a seam on y = 0 are mirror images.
pub fn from_seam(theta: f64, seam: f64, half: bool) -> f64 {
    let d = (theta - seam).rem_euclid(360.0);
    let d = if d > 180.0 { d - 360.0 } else { d };
    if half { d.abs() } else { d }
}

/// The seam angle of layer `k` (1-based), degrees.
fn seam_deg(run: &MultilayerRun, k: usize) -> f64 {
    run.options.geometry.layers[k - 1].seam_angle.to_degrees()
}

/// θ of a point about the vessel axis, degrees in (−180°, 180°].
fn theta_of(p: [f64; 2]) -> f64 {
    p[1].atan2(p[0]).to_degrees()
}

/// The nodes of ring `ring` (0 = core) on the circle of radius `r`,
/// sorted by θ about the axis.
fn ring_nodes_at(run: &MultilayerRun, ring: usize, r: f64) -> Vec<usize> {
    let mesh = &run.mesh;
    let names = mesh.region_names();
    let mut mine = vec![false; mesh.n_nodes()];
    for (e, t) in mesh.triangles().iter().enumerate() {
        if in_ring(&names[mesh.element_regions()[e]], ring) {
            for &v in t {
                mine[v] = true;
            }
        }
    }
    let x = mesh.nodes();
    let mut v: Vec<usize> = (0..mesh.n_nodes())
        .filter(|&i| mine[i] && (x[i][0].hypot(x[i][1]) - r).abs() <= 1e-9 * r)
        .collect();
    v.sort_by(|&a, &b| theta_of(x[a]).total_cmp(&theta_of(x[b])).then(a.cmp(&b)));
    v
}

/// The x ranges of a weld panel (half width `w`°) and of the whole
/// circumference, from the seam on a half section (0…w, 0…180) or about
/// it on a full ring (−w…w, −180…180).
fn seam_ranges(half: bool, w: f64) -> [(f64, f64); 2] {
    if half {
        [(0.0, w), (0.0, 180.0)]
    } else {
        [(-w, w), (-180.0, 180.0)]
    }
}

/// Header of [`temperature_rows`].
pub const TEMPERATURE_HEADER: [&str; 5] = [
    "time_s",
    "theta_deg",
    "theta_from_weld_deg",
    "T_layer_inner_C",
    "T_layer_outer_C",
];

/// The temperature around layer `k`'s inner and outer surfaces during
/// stage `stage` (a layer stage, layer k = its last layer): per output
/// time and node station, (time, θ about the axis, θ from the centre of
/// weld k, T inner, T outer), sorted by time and θ. Empty for the
/// pressure stage.
pub fn temperature_rows(run: &MultilayerRun, stage: usize) -> CliResult<Vec<Vec<f64>>> {
    let st = &run.stages[stage - 1];
    if st.temperatures.is_empty() {
        return Ok(Vec::new());
    }
    let k = st.layers;
    let radii = run.options.geometry.radii();
    let inner = ring_nodes_at(run, k, radii[k]);
    let outer = ring_nodes_at(run, k, radii[k + 1]);
    let x = run.mesh.nodes();
    if inner.is_empty()
        || inner.len() != outer.len()
        || inner
            .iter()
            .zip(&outer)
            .any(|(&a, &b)| (theta_of(x[a]) - theta_of(x[b])).abs() > 1e-6)
    {
        return Err(format!(
            "stage {stage}: the nodes of layer {k}'s inner and outer surfaces do not pair up by angle"
        )
        .into());
    }
    let (seam, half) = (seam_deg(run, k), run.options.half_section());
    let mut rows = Vec::new();
    for (t, temperature) in &st.temperatures {
        for (&a, &b) in inner.iter().zip(&outer) {
            let th = theta_of(x[a]);
            rows.push(vec![
                *t,
                th,
                from_seam(th, seam, half),
                temperature[a],
                temperature[b],
            ]);
        }
    }
    Ok(rows)
}

/// Figure: the temperature around layer k during weld k's cooling (stage
/// `stage`), against the angle from the weld centre: the weld zone (±20°)
/// beside the whole circumference; one colour per output time, solid the
/// layer's inner surface, dashed its outer one. None for the pressure stage.
pub fn temperature_figure(run: &MultilayerRun, stage: usize) -> CliResult<Option<Figure>> {
    let rows = temperature_rows(run, stage)?;
    if rows.is_empty() {
        return Ok(None);
    }
    let k = run.stages[stage - 1].layers;
    let half = run.options.half_section();
    let times: Vec<f64> = run.stages[stage - 1]
        .temperatures
        .iter()
        .map(|t| t.0)
        .collect();
    let side = |t: f64, column: usize| {
        let mut pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r[0] == t)
            .map(|r| (r[2], r[column]))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        pts
    };
    let [zone, whole] = seam_ranges(half, WELD_ZONE_DEG);
    let panel = |title: String, range: (f64, f64), legend: LegendAt| {
        let mut lines = Vec::new();
        for (c, &t) in times.iter().enumerate() {
            lines.push(Line::solid(time_label(t), c, side(t, 3)));
            lines.push(Line::dashed("", c, side(t, 4)));
        }
        Panel {
            title,
            x: Axis::linear(format!("θ from the centre of weld {k} [°]")).range(range.0, range.1),
            y: Axis::linear("T [°C]"),
            lines,
            notes: vec![format!(
                "solid: layer {k} inner surface, dashed: outer surface"
            )],
            legend,
            ..Default::default()
        }
    };
    Ok(Some(Figure {
        title: format!("Stage {stage}: temperature around layer {k} while weld {k} cools"),
        panels: vec![
            panel(format!("weld {k} zone"), zone, LegendAt::None),
            panel(
                if half {
                    "half circumference".into()
                } else {
                    "whole circumference".into()
                },
                whole,
                LegendAt::UpperRight,
            ),
        ],
        size: (1300, 600),
    }))
}

/// Header of [`opening_slip_rows`].
pub const OPENING_SLIP_HEADER: [&str; 6] = [
    "interface (1: core/layer 1, k: layer k-1/layer k)",
    "theta_deg",
    "theta_from_weld_deg (weld of the layer above)",
    "opening_jump_n_m",
    "slip_m",
    "status (0 open; 1 stick; 2 slip)",
];

/// The opening ⟦u⟧_n and the plastic slip g_s of every interface point
/// after stage `stage`, the rows of [`stage_interface_rows`] (same order):
/// (interface, θ about the axis, θ from the weld of the layer above the
/// interface, opening, slip, status).
pub fn opening_slip_rows(run: &MultilayerRun, stage: usize) -> Vec<Vec<f64>> {
    let half = run.options.half_section();
    stage_interface_rows(run, stage)
        .iter()
        .map(|r| {
            let j = r.interface + 1;
            vec![
                j as f64,
                r.theta_deg,
                from_seam(r.theta_deg, seam_deg(run, j), half),
                r.jump_n,
                r.slip,
                f64::from(r.status),
            ]
        })
        .collect()
}

/// Two panels of interface values after stage `stage`, one colour per
/// interface: a detail of ±[`WELD_DETAIL_DEG`] about the weld of the layer
/// above each interface (x: θ from that weld's centre), and the whole
/// circumference (x: θ about the axis). `lines` gives an interface's
/// lines from its rows (θ, θ from its weld, row) sorted by the x used.
fn interface_panels(
    run: &MultilayerRun,
    stage: usize,
    y: &str,
    notes: Vec<String>,
    lines: impl Fn(usize, &[(f64, &InterfaceRow)]) -> Vec<Line>,
) -> Vec<Panel> {
    let st = &run.stages[stage - 1];
    let rows = stage_interface_rows(run, stage);
    let half = run.options.half_section();
    let [detail, _] = seam_ranges(half, WELD_DETAIL_DEG);
    let whole = if half { (0.0, 180.0) } else { (-180.0, 180.0) };
    let of = |j: usize, near: bool| {
        let mut v: Vec<(f64, &InterfaceRow)> = rows
            .iter()
            .filter(|r| r.interface == j - 1)
            .map(|r| {
                let x = if near {
                    from_seam(r.theta_deg, seam_deg(run, j), half)
                } else {
                    r.theta_deg
                };
                (x, r)
            })
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    let panel = |near: bool| Panel {
        title: if near {
            format!("at the weld of the layer above (±{WELD_DETAIL_DEG}°)")
        } else if half {
            "half circumference".into()
        } else {
            "whole circumference".into()
        },
        x: if near {
            Axis::linear("θ from the centre of the weld above the interface [°]")
                .range(detail.0, detail.1)
        } else {
            Axis::linear("θ about the vessel axis [°] (seam of layer 1 at 0°)")
                .range(whole.0, whole.1)
        },
        y: Axis::linear(y),
        lines: (1..=st.layers)
            .flat_map(|j| lines(j, &of(j, near)))
            .collect(),
        notes: if near { notes.clone() } else { Vec::new() },
        legend: if near {
            LegendAt::None
        } else {
            LegendAt::UpperRight
        },
        ..Default::default()
    };
    vec![panel(true), panel(false)]
}

/// Figure: the opening and the plastic slip of every interface after stage
/// `stage` (µm; solid slip, dashed opening, one colour per interface),
/// the weld detail beside the whole circumference.
pub fn opening_slip_figure(run: &MultilayerRun, stage: usize) -> Figure {
    let panels = interface_panels(
        run,
        stage,
        "plastic slip, opening [µm]",
        vec!["solid: plastic slip g_s, dashed: opening ⟦u⟧_n".into()],
        |j, pts| {
            vec![
                Line::solid(
                    interface_name(j),
                    j - 1,
                    pts.iter().map(|(x, r)| (*x, r.slip * 1e6)).collect(),
                ),
                Line::dashed(
                    "",
                    j - 1,
                    pts.iter().map(|(x, r)| (*x, r.jump_n * 1e6)).collect(),
                ),
            ]
        },
    );
    Figure {
        title: format!("Interfaces after stage {stage}: slip and opening"),
        panels,
        size: (1400, 600),
    }
}

/// The through-wall locations of stage `stage`: first the node station
/// nearest the middle of the widest gap between the active seams (far
/// from every seam; of equally wide gaps, within 1e-9°, the first from 0°),
/// then the seam of each active layer; (0 for far or k for the seam of
/// layer k, θ°).
pub fn wall_locations(run: &MultilayerRun, stage: usize) -> Vec<(usize, f64)> {
    let k = run.stages[stage - 1].layers;
    let seams: Vec<f64> = (1..=k).map(|j| seam_deg(run, j)).collect();
    let mut sorted = seams.clone();
    sorted.sort_by(f64::total_cmp);
    let mut middle = (0.0, -1.0);
    for (i, &a) in sorted.iter().enumerate() {
        let b = if i + 1 < sorted.len() {
            sorted[i + 1]
        } else {
            sorted[0] + 360.0
        };
        if b - a > middle.1 + 1e-9 {
            middle = ((0.5 * (a + b)).rem_euclid(360.0), b - a);
        }
    }
    let x = run.mesh.nodes();
    let bore = ring_nodes_at(run, 0, run.options.geometry.inner_radius);
    let far = bore
        .iter()
        .map(|&i| theta_of(x[i]))
        .min_by(|a, b| {
            from_seam(*a, middle.0, false)
                .abs()
                .total_cmp(&from_seam(*b, middle.0, false).abs())
        })
        .unwrap_or(middle.0);
    let mut v = vec![(0, far)];
    v.extend(seams.iter().enumerate().map(|(j, &s)| (j + 1, s)));
    v
}

/// Header of [`seam_profile_rows`].
pub const SEAM_PROFILE_HEADER: [&str; 6] = [
    "location (0: far from the seams; k: seam of layer k)",
    "theta_deg",
    "ring (0 core; k layer k)",
    "r_m",
    "hoop_fe_nodal_Pa",
    "hoop_closed_form_Pa",
];

/// The hoop stress through the wall after stage `stage` at each of
/// [`wall_locations`]: per location, ring and node row, the node of the
/// ring on that row nearest the location's angle: (location, θ of the
/// node, ring, r, nodal σ_θθ (the area-weighted mean of the elements
/// around the node), the closed form at r (the sequential shrink fit,
/// which knows no seam)).
pub fn seam_profile_rows(run: &MultilayerRun, stage: usize) -> Vec<Vec<f64>> {
    let st = &run.stages[stage - 1];
    let radii = run.options.geometry.radii();
    let x = run.mesh.nodes();
    let mut rows = Vec::new();
    for (loc, angle) in wall_locations(run, stage) {
        for ring in 0..=st.layers {
            let n = if ring == 0 {
                run.options.spec.core_rows
            } else {
                run.options.spec.layer_rows
            };
            for j in 0..=n {
                let r = radii[ring] + (radii[ring + 1] - radii[ring]) * j as f64 / n as f64;
                let near = ring_nodes_at(run, ring, r).into_iter().min_by(|&a, &b| {
                    from_seam(theta_of(x[a]), angle, false)
                        .abs()
                        .total_cmp(&from_seam(theta_of(x[b]), angle, false).abs())
                });
                if let Some(i) = near {
                    rows.push(vec![
                        loc as f64,
                        theta_of(x[i]),
                        ring as f64,
                        r,
                        polar(st.state.stress.nodal[i], x[i], [0.0, 0.0])[1],
                        closed_form_hoop(run, stage, ring, r),
                    ]);
                }
            }
        }
    }
    rows
}

/// Figure: the hoop stress through the wall after stage `stage` at every
/// seam (one colour per seam) and far from the seams, FE nodal values
/// (markers, one segment per ring) against the sequential shrink fit
/// (dashed; a model of the ring means, without seams).
pub fn seam_profile_figure(run: &MultilayerRun, stage: usize) -> Figure {
    let rows = seam_profile_rows(run, stage);
    let r0 = run.options.geometry.inner_radius;
    let k = run.stages[stage - 1].layers;
    let profile = |loc: usize, column: usize| {
        let mut v = Vec::new();
        for ring in 0..=k {
            if ring > 0 {
                v.push((f64::NAN, f64::NAN));
            }
            v.extend(
                rows.iter()
                    .filter(|r| r[0] == loc as f64 && r[2] == ring as f64)
                    .map(|r| ((r[3] - r0) * 1e3, r[column] / 1e6)),
            );
        }
        v
    };
    let far = rows
        .iter()
        .find(|r| r[0] == 0.0)
        .map_or(f64::NAN, |r| r[1].rem_euclid(360.0));
    let closed = Line::dashed(
        "sequential shrink fit (closed form of the ring means)",
        7,
        profile(0, 5),
    );
    let mut at_seams: Vec<Line> = (1..=k)
        .map(|j| {
            Line::solid(
                format!("seam of layer {j} (θ = {}°)", fmt_value(seam_deg(run, j))),
                j - 1,
                profile(j, 4),
            )
            .with_markers()
        })
        .collect();
    at_seams.push(closed.clone());
    let x = || Axis::linear("distance from the bore [mm]; core, then layer 1, 2, …");
    let st = &run.stages[stage - 1];
    let what = if st.pressure == 0.0 {
        format!("after layer {k} is welded")
    } else {
        format!(
            "under {} MPa internal pressure",
            fmt_value(st.pressure / 1e6)
        )
    };
    Figure {
        title: format!("Hoop stress through the wall at the seams, stage {stage} ({what})"),
        panels: vec![
            Panel {
                title: "at each seam".into(),
                x: x(),
                y: Axis::linear("σ_θθ [MPa]"),
                lines: at_seams,
                legend: LegendAt::UpperLeft,
                ..Default::default()
            },
            Panel {
                title: format!(
                    "far from the seams (θ = {}°)",
                    fmt_value((far * 100.0).round() / 100.0)
                ),
                x: x(),
                y: Axis::linear("σ_θθ [MPa]"),
                lines: vec![
                    Line::solid("FE (nodal σ_θθ of one node column)", 0, profile(0, 4))
                        .with_markers(),
                    closed,
                ],
                legend: LegendAt::UpperLeft,
                ..Default::default()
            },
        ],
        size: (1400, 600),
    }
}

/// Per interface (1-based) after stage `stage`: (largest opening ⟦u⟧_n,
/// largest |slip|, open points), over the rows of [`stage_interface_rows`].
pub fn interface_extremes(run: &MultilayerRun, stage: usize) -> Vec<(f64, f64, usize)> {
    let rows = stage_interface_rows(run, stage);
    (1..=run.stages[stage - 1].layers)
        .map(|j| {
            let mine = rows.iter().filter(|r| r.interface == j - 1);
            (
                mine.clone()
                    .map(|r| r.jump_n)
                    .fold(f64::NEG_INFINITY, f64::max),
                mine.clone().map(|r| r.slip.abs()).fold(0.0, f64::max),
                mine.filter(|r| r.status == 0).count(),
            )
        })
        .collect()
}

/// Per output time of stage `stage` (a layer stage, layer k its last):
/// the hottest point of layer k's inner and outer surfaces, (time s, its
/// θ about the axis, T °C); empty for the pressure stage (and if the
/// surfaces do not pair up, which [`temperature_rows`] reports).
pub fn layer_surface_peaks(run: &MultilayerRun, stage: usize) -> Vec<(f64, f64, f64)> {
    let rows = temperature_rows(run, stage).unwrap_or_default();
    let mut v: Vec<(f64, f64, f64)> = Vec::new();
    for r in &rows {
        let hottest = r[3].max(r[4]);
        match v.last_mut() {
            Some(last) if last.0 == r[0] => {
                if hottest > last.2 {
                    *last = (r[0], r[1], hottest);
                }
            }
            _ => v.push((r[0], r[1], hottest)),
        }
    }
    v
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
    let extremes = interface_extremes(run, stage);
    let interfaces: Vec<Value> = (1..=k)
        .map(|j| {
            let (fe, an) = (st.pressures[j - 1], st.analytical_pressures[j - 1]);
            let (opening, slip, open) = extremes[j - 1];
            json!({
                "interface": interface_name(j),
                "mean_pressure_fe": fe,
                "pressure_analytical": an,
                "relative_error": (fe - an) / an,
                "max_opening_m": opening,
                "max_abs_slip_m": slip,
                "open_points": open,
            })
        })
        .collect();
    let temperatures: Vec<Value> = layer_surface_peaks(run, stage)
        .into_iter()
        .map(|(t, theta, peak)| json!({ "time_s": t, "max_C": peak, "theta_deg": theta }))
        .collect();
    json!({
        "stage": stage,
        "kind": if st.pressure == 0.0 { "layer" } else { "pressure" },
        "layers_active": k,
        "internal_pressure": st.pressure,
        "rings": rings,
        "interfaces": interfaces,
        "newton_iterations": st.newton_iterations,
        // steps in the coarse interface space (not in newton_iterations)
        "coarse_iterations": st.coarse_iterations,
        "thermal_steps": st.thermal_steps,
        "max_heat_balance_residual": st.heat_balance,
        // K outside the bounds of the maximum principle, at any time step
        // and at the output states (0: inside)
        "bound_violation": st.bound_violation.as_ref().map_or(0.0, |b| b.excursion),
        "bound_violation_at_outputs": st.bound_violation.as_ref().map_or(0.0, |b| b.output_excursion),
        "end_time_s": st.state.time,
        "layer_surface_temperature": temperatures,
    })
}

/// A note when the mesh does not resolve the stresses at the seams: the
/// convergence study of docs/vessel.md (3 staggered layers; 2 layers at
/// 0°/180°; one layer to level 3 at order 2, where the seam converges to
/// +411 / −619 MPa within 0.3 %) found the default mesh (level 0, 3-node
/// triangles) at a third of the mid-thickness tension and a sixth of the
/// surface compression; 3-node triangles within about 4 % from level 3
/// (3 staggered layers: −602 / +399 against −627 / +409 MPa at order 2,
/// level 2), 6-node triangles within about 10 % from level 1 (−681 /
/// +425) and a few per cent from level 2. The ring means and interface
/// pressures are resolved on every mesh (within 5e-4 of the converged
/// values).
pub fn seam_note(run: &MultilayerRun) -> Option<String> {
    let order = run.mesh.order();
    let level = run.options.mesh_level?;
    let resolved = (order == 2 && level >= 1) || (order == 1 && level >= 3);
    (!resolved).then(|| {
        format!(
            "the stresses at the seams are not resolved by this mesh ({}-node triangles, level {level}): the mesh study (docs/vessel.md) found the default mesh at a third of the converged mid-thickness tension and a sixth of the surface compression at a seam; --order 2 --mesh 1 reads them within about 10 %, --order 2 --mesh 2 within a few per cent. The ring means and interface pressures are resolved on every mesh (within 5e-4)",
            3 * order
        )
    })
}

/// The run's notes: the seams' resolution, and every stage whose heat
/// conduction left the bounds of the maximum principle.
pub fn notes(run: &MultilayerRun) -> Vec<String> {
    let mut v: Vec<String> = seam_note(run).into_iter().collect();
    for (i, st) in run.stages.iter().enumerate() {
        if let Some(b) = &st.bound_violation {
            v.push(format!("stage {}: {}", i + 1, b.note()));
        }
    }
    v
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
            // the heat conduction's capacity matrix (consistent or lumped)
            "thermal_capacity_matrix": run.options.capacity.name(),
        },
        "mesh": {
            "triangles": run.mesh.n_triangles(),
            "nodes": run.mesh.n_nodes(),
            "order": run.mesh.order(),
            "level": run.options.mesh_level,
            "rows_per_layer": run.options.spec.layer_rows,
        },
        "stages": (1..=run.stages.len()).map(|k| stage_summary(run, k)).collect::<Vec<_>>(),
        "max_relative_error_ring_means": worst,
        "notes": notes(run),
    })
}

/// First column of the per-stage interface CSVs (then
/// [`figures::INTERFACE_HEADER`]).
pub const STAGE_INTERFACE_COLUMN: &str = "interface (1: core/layer 1, k: layer k-1/layer k)";

/// Last column of the per-stage interface CSVs: θ from the centre of the
/// weld of the layer above the interface (the x of the figures' detail).
pub const THETA_FROM_WELD_COLUMN: &str = "theta_from_weld_deg (weld of the layer above)";

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
        let w = crate::multilayer::element_area(mesh, e) / rc;
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

/// Figure: every active interface's contact pressure after stage `stage`
/// (one colour per interface) with its closed-form mean (dashed, same
/// colour): the detail about the weld of the layer above each interface
/// beside the whole circumference.
pub fn pressure_figure(run: &MultilayerRun, stage: usize) -> Figure {
    let st = &run.stages[stage - 1];
    let panels = interface_panels(
        run,
        stage,
        "contact pressure [MPa]",
        Vec::new(),
        |j, pts| {
            let (lo, hi) = (
                pts.first().map_or(0.0, |p| p.0),
                pts.last().map_or(0.0, |p| p.0),
            );
            let p = st.analytical_pressures[j - 1] / 1e6;
            vec![
                Line::solid(
                    interface_name(j),
                    j - 1,
                    pts.iter().map(|(x, r)| (*x, r.pressure / 1e6)).collect(),
                ),
                Line::dashed("", j - 1, vec![(lo, p), (hi, p)]),
            ]
        },
    );
    Figure {
        title: format!("Contact pressure of every interface, stage {stage} (dashed: closed form)"),
        panels,
        size: (1400, 600),
    }
}

/// Writes every stage's files and the summaries into `dir`; returns the
/// names of the files written.
pub fn write_outputs(run: &MultilayerRun, dir: &Path) -> CliResult<Vec<String>> {
    let mut names = Vec::new();
    let half = run.options.half_section();
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
                        &[THETA_FROM_WELD_COLUMN][..],
                    ]
                    .concat(),
                    rows.iter().map(|r| {
                        let mut v = vec![(r.interface + 1) as f64];
                        v.extend(figures::interface_values(r));
                        v.push(from_seam(r.theta_deg, seam_deg(run, r.interface + 1), half));
                        v
                    }),
                ),
            )?;
            names.push(name);
            let stem = format!("stage{k}_interface_pressure");
            pressure_figure(run, k).write_svg_png(&tmp.join(&stem))?;
            names.extend([format!("{stem}.svg"), format!("{stem}.png")]);
            let stem = format!("stage{k}_interface_opening_slip");
            writers::write(
                &tmp.join(format!("{stem}.csv")),
                &figures::csv_text(&OPENING_SLIP_HEADER, opening_slip_rows(run, k)),
            )?;
            opening_slip_figure(run, k).write_svg_png(&tmp.join(&stem))?;
            names.extend(["csv", "svg", "png"].map(|e| format!("{stem}.{e}")));
            let stem = format!("stage{k}_hoop_at_seams");
            writers::write(
                &tmp.join(format!("{stem}.csv")),
                &figures::csv_text(&SEAM_PROFILE_HEADER, seam_profile_rows(run, k)),
            )?;
            seam_profile_figure(run, k).write_svg_png(&tmp.join(&stem))?;
            names.extend(["csv", "svg", "png"].map(|e| format!("{stem}.{e}")));
            if let Some(fig) = temperature_figure(run, k)? {
                let stem = format!("stage{k}_temperature_circumference");
                writers::write(
                    &tmp.join(format!("{stem}.csv")),
                    &figures::csv_text(&TEMPERATURE_HEADER, temperature_rows(run, k)?),
                )?;
                fig.write_svg_png(&tmp.join(&stem))?;
                names.extend(["csv", "svg", "png"].map(|e| format!("{stem}.{e}")));
            }
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
        "multilayer vessel: {} layers, {} {}-node triangles{}, {}, {:.1} s\n",
        run.options.geometry.layers.len(),
        run.mesh.n_triangles(),
        3 * run.mesh.order(),
        run.options
            .mesh_level
            .map_or(String::new(), |l| format!(", mesh level {l}")),
        if run.options.half_section() {
            "half section"
        } else {
            "full section"
        },
        run.seconds
    );
    for n in notes(run) {
        s += &format!("note: {n}\n");
    }
    for (i, st) in run.stages.iter().enumerate() {
        let k = st.layers;
        let what = if st.pressure == 0.0 {
            format!("layer {k} welded")
        } else {
            format!("internal pressure {:.3} MPa", st.pressure / 1e6)
        };
        s += &format!(
            "stage {} ({what}): {} Newton iterations{}, {} thermal steps\n",
            i + 1,
            st.newton_iterations,
            match st.coarse_iterations {
                0 => String::new(),
                c => format!(" (and {c} coarse interface steps)"),
            },
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
        let extremes = interface_extremes(run, i + 1);
        for j in 1..=k {
            let an = st.analytical_pressures[j - 1];
            let (opening, slip, open) = extremes[j - 1];
            s += &format!(
                "  {:>13} mean pressure {:.5} MPa (closed form {:.5} MPa); opening up to {:.2} µm ({open} points open), slip up to {:.2} µm\n",
                interface_name(j),
                st.pressures[j - 1] / 1e6,
                an / 1e6,
                opening * 1e6,
                slip * 1e6
            );
        }
        let peaks = layer_surface_peaks(run, i + 1);
        if let (Some(first), Some(last)) = (peaks.first(), peaks.last()) {
            s += &format!(
                "  layer {k} surfaces: hottest {:.1} °C at t = {} s (θ = {:.2}°), {:.2} °C at t = {} s\n",
                first.2,
                fmt_value(first.0),
                first.1,
                last.2,
                fmt_value(last.0)
            );
        }
    }
    s
}

/// The multilayer refinement level of `--mesh` (with `--layers`): a level
/// `0..=4`, or the monolayer's default `g0` for level 0; the monolayer's
/// mesh names (`gL` but g0, `paper`, `xF`, `tN`) are refused by name.
pub fn mesh_level(mesh: &str) -> CliResult<u32> {
    if mesh == crate::builtin::DEFAULT_MESH {
        return Ok(0);
    }
    let max = tecon_mesh::multilayer::MULTILAYER_MAX_LEVEL;
    match mesh.parse::<u32>() {
        Ok(l) if l <= max => Ok(l),
        Ok(l) => Err(format!(
            "--mesh {l} with --layers: the multilayer mesh offers levels 0..={max} (each halves every interval of the one before, about 4 times the triangles)"
        )
        .into()),
        Err(_) => Err(format!(
            "--mesh {mesh} with --layers: give a refinement level 0..={max} of the multilayer mesh (0: two rows of triangles through every ring, two intervals across each weld half width, intervals up to 3°; each level halves every interval); the monolayer's meshes (gL, paper, xF, tN) do not apply to a multilayer vessel"
        )
        .into()),
    }
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
        ("--interface bonded", args.interface == "bonded"),
    ];
    if let Some((name, _)) = unsupported.iter().find(|(_, on)| *on) {
        return Err(format!("{name} is not available with --layers yet").into());
    }
    // frictionless joints: the frictional law with μ = 0 (as the monolayer)
    let frictionless = matches!(
        crate::builtin::InterfaceKind::parse(&args.interface)?,
        crate::builtin::InterfaceKind::Frictionless
    );
    if frictionless && args.friction.is_some() {
        return Err(
            "--friction: only with --interface frictional (this run is --interface frictionless)"
                .into(),
        );
    }
    let mut o =
        crate::multilayer::MultilayerOptions::new(n, args.layer_thickness, args.seams.as_deref())?;
    let level = mesh_level(&args.mesh)?;
    o.set_mesh(level, args.order.unwrap_or(1)).map_err(|e| {
        format!(
            "--mesh {} --order {}: {e}",
            args.mesh,
            args.order.unwrap_or(1)
        )
    })?;
    if let Some(f) = args.friction {
        if !(f.is_finite() && f >= 0.0) {
            return Err(format!("--friction {f}: must be non-negative").into());
        }
        o.friction = f;
    }
    if frictionless {
        o.friction = 0.0;
    }
    o.times = args.times.clone();
    o.quiet = args.quiet;
    o.verbose = args.verbose;
    o.condensation = !args.no_condensation;
    o.coarse_space = !args.no_coarse_space;
    o.coarse_levels = args.coarse_levels;
    o.coupled_tail = !args.no_coupled_tail;
    o.exact_passes = args.exact_passes;
    o.capacity = crate::case::Capacity::parse(&args.capacity)?;
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
