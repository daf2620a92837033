//! The figures of a vessel run, built from plain data (so that any driver
//! can draw them): temperature around the layer (fig6) and through the wall
//! (fig7), hoop prestress through the wall (fig8, fig11) and around the
//! circumference (fig9), the interface after cooling, and the mesh study.
//!
//! Conventions: θ in degrees from the weld centre, stresses in MPa, one
//! colour per time, solid for an inner surface and dashed for an outer one,
//! core and layer always as separate segments (never joined across the
//! interface), and the weld zone in a panel of its own beside the full range.

use tecon_contact::ContactStatus;
use tecon_elastic::InterfacePointResult;

use crate::plot::{Axis, Figure, LegendAt, Line, OffScale, Panel, fmt_value};

/// Width of the weld-zone panels, degrees.
pub const WELD_ZONE_DEG: f64 = 20.0;

/// Range of the weld panel of the interface and displacement figures (°):
/// the lift-off under the weld and the slip it drives lie within 0–3°
/// (the weld edge at 0.28°, the open zone to about 2.2° on the published
/// case), which a 0–20° panel squeezed against its axis.
pub const WELD_DETAIL_DEG: f64 = 3.0;

/// Temperature around the layer at one time: (θ°, T °C) on its inner and outer surfaces.
#[derive(Clone, Debug)]
pub struct RingTemperature {
    /// time, s
    pub time: f64,
    /// (θ, T) on the layer's inner surface, sorted by θ
    pub inner: Vec<(f64, f64)>,
    /// (θ, T) on the layer's outer surface, sorted by θ
    pub outer: Vec<(f64, f64)>,
}

/// The legend label of a time: `t = 1 s`, `t = 72000 s`.
pub fn time_label(t: f64) -> String {
    format!("t = {} s", fmt_value(t))
}

/// Fig. 6: temperature around the layer, the weld zone (0–20°) beside the
/// half circumference; one colour per time, solid inner and dashed outer.
pub fn fig6(rings: &[RingTemperature]) -> Figure {
    let panel = |title: &str, range: (f64, f64), legend: LegendAt| {
        let mut lines = Vec::new();
        for (k, r) in rings.iter().enumerate() {
            lines.push(Line::solid(time_label(r.time), k, r.inner.clone()));
            lines.push(Line::dashed("", k, r.outer.clone()));
        }
        Panel {
            title: title.into(),
            x: Axis::linear("θ from the weld centre [°]").range(range.0, range.1),
            y: Axis::linear("T [°C]"),
            lines,
            notes: vec!["solid: layer inner surface, dashed: outer surface".into()],
            legend,
            ..Default::default()
        }
    };
    Figure {
        title: "Temperature around the layer".into(),
        panels: vec![
            panel("weld zone", (0.0, WELD_ZONE_DEG), LegendAt::None),
            panel("half circumference", (0.0, 180.0), LegendAt::UpperRight),
        ],
        size: (1300, 600),
    }
}

/// Temperature through the wall at one angle and one time: (wall %, T °C)
/// for the core and for the layer (separate segments).
#[derive(Clone, Debug)]
pub struct WallTemperature {
    /// time, s
    pub time: f64,
    /// θ of the node column, degrees
    pub angle: f64,
    /// (position through the wall %, T) in the core
    pub core: Vec<(f64, f64)>,
    /// (position through the wall %, T) in the layer
    pub layer: Vec<(f64, f64)>,
}

/// Core then layer as one line broken at the interface (the jump is not joined).
fn two_segments(core: &[(f64, f64)], layer: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut v = core.to_vec();
    v.push((f64::NAN, f64::NAN));
    v.extend_from_slice(layer);
    v
}

/// Fig. 7: temperature through the wall, one panel per angle, one colour per time.
pub fn fig7(profiles: &[WallTemperature]) -> Figure {
    let mut angles: Vec<f64> = Vec::new();
    let mut times: Vec<f64> = Vec::new();
    for p in profiles {
        if !angles.contains(&p.angle) {
            angles.push(p.angle);
        }
        if !times.contains(&p.time) {
            times.push(p.time);
        }
    }
    let panels = angles
        .iter()
        .enumerate()
        .map(|(a, &angle)| Panel {
            title: format!("θ = {}°", fmt_value((angle * 100.0).round() / 100.0)),
            x: Axis::linear("through the wall [%]; core 0–67 %, layer 67–100 %").range(0.0, 100.0),
            y: Axis::linear("T [°C]"),
            lines: profiles
                .iter()
                .filter(|p| p.angle == angle)
                .map(|p| {
                    let k = times.iter().position(|&t| t == p.time).unwrap_or(0);
                    Line::solid(time_label(p.time), k, two_segments(&p.core, &p.layer))
                        .with_markers()
                })
                .collect(),
            legend: if a + 1 == angles.len() {
                LegendAt::UpperRight
            } else {
                LegendAt::None
            },
            ..Default::default()
        })
        .collect::<Vec<_>>();
    let n = panels.len().max(1) as u32;
    Figure {
        title: "Temperature through the wall".into(),
        panels,
        size: (450 * n + 100, 600),
    }
}

/// The temperature of one point against time (every thermal step).
#[derive(Clone, Debug)]
pub struct HistoryLine {
    /// legend label
    pub label: String,
    /// (time s, T °C), in time order
    pub points: Vec<(f64, f64)>,
}

/// Temperature against time at a few points, on a logarithmic time axis
/// (the start, t = 0, lies off it), one colour per point; a marker where a
/// record falls on one of the `output_times` (the states written in full).
/// When some points stay far cooler than the hottest (their rise above the
/// lowest temperature under a fifth of the whole span, as the core beside
/// a cooling weld), a second panel shows the same lines on their scale.
pub fn temperature_history(lines: &[HistoryLine], output_times: &[f64]) -> Figure {
    let mut drawn = Vec::new();
    for (k, l) in lines.iter().enumerate() {
        drawn.push(Line::solid(l.label.clone(), k, l.points.clone()));
        let marks: Vec<(f64, f64)> = l
            .points
            .iter()
            .filter(|(t, _)| output_times.contains(t))
            .copied()
            .collect();
        if !marks.is_empty() {
            drawn.push(Line::solid("", k, marks).points_only());
        }
    }
    let range = |v: &mut dyn Iterator<Item = f64>| {
        v.filter(|x| x.is_finite())
            .fold(None, |r: Option<(f64, f64)>, x| {
                Some(r.map_or((x, x), |(a, b)| (a.min(x), b.max(x))))
            })
    };
    let all = range(&mut lines.iter().flat_map(|l| l.points.iter().map(|p| p.1)));
    let cool: Vec<&HistoryLine> = match all {
        Some((lo, hi)) if hi > lo => lines
            .iter()
            .filter(|l| {
                range(&mut l.points.iter().map(|p| p.1))
                    .is_some_and(|(_, m)| m - lo < 0.2 * (hi - lo))
            })
            .collect(),
        _ => Vec::new(),
    };
    let panel = |title: String, y: Axis, legend: LegendAt, notes: Vec<String>| Panel {
        title,
        x: Axis::log("time [s]"),
        y,
        lines: drawn.clone(),
        notes,
        legend,
        ..Default::default()
    };
    let marks = vec!["markers: the output times (the states written in full)".to_string()];
    let mut panels = vec![panel(
        "all points".into(),
        Axis::linear("T [°C]"),
        LegendAt::UpperRight,
        marks.clone(),
    )];
    let detail = range(&mut cool.iter().flat_map(|l| l.points.iter().map(|p| p.1)));
    if !cool.is_empty()
        && cool.len() < lines.len()
        && let Some((a, b)) = detail
    {
        let pad = 0.08 * (b - a).max(1.0);
        panels.push(panel(
            format!(
                "the cooler points ({} – {} °C)",
                fmt_value(a.floor()),
                fmt_value(b.ceil())
            ),
            Axis::linear("T [°C]").range(a - pad, b + pad),
            LegendAt::None,
            Vec::new(),
        ));
    }
    let n = panels.len() as u32;
    Figure {
        title: "Temperature history (every thermal step)".into(),
        panels,
        size: (if n > 1 { 1400 } else { 900 }, 600),
    }
}

/// A through-the-wall profile in MPa, core and layer apart.
#[derive(Clone, Debug, Default)]
pub struct WallProfile {
    /// legend label
    pub label: String,
    /// (wall %, value) in the core
    pub core: Vec<(f64, f64)>,
    /// (wall %, value) in the layer
    pub layer: Vec<(f64, f64)>,
}

/// Fig. 8 / Fig. 11: hoop stress through the wall, the FE profile (markers)
/// beside analytical ones (dashed), core and layer as separate segments.
pub fn through_wall(title: &str, fe: &WallProfile, analytical: &[WallProfile]) -> Figure {
    let mut lines =
        vec![Line::solid(fe.label.clone(), 0, two_segments(&fe.core, &fe.layer)).with_markers()];
    for (k, a) in analytical.iter().enumerate() {
        lines.push(Line::dashed(
            a.label.clone(),
            k + 1,
            two_segments(&a.core, &a.layer),
        ));
    }
    Figure {
        title: String::new(),
        panels: vec![Panel {
            title: title.into(),
            x: Axis::linear("through the wall [%]; core 0–67 %, layer 67–100 %").range(0.0, 100.0),
            y: Axis::linear("σ_θθ [MPa]"),
            lines,
            legend: LegendAt::UpperLeft,
            ..Default::default()
        }],
        size: (900, 600),
    }
}

/// Fig. 9: hoop stress around the circumference on the inner and outer
/// surfaces: the weld zone beside the far field (θ ≥ 20°), whose scale is
/// set by the far field; values beyond it are marked at the frame.
pub fn fig9(inner: &[(f64, f64)], outer: &[(f64, f64)]) -> Figure {
    let lines = || {
        vec![
            Line::solid("inner surface (core)", 0, inner.to_vec()),
            Line::dashed("outer surface (layer)", 1, outer.to_vec()),
        ]
    };
    let far = |p: &&(f64, f64)| p.0 >= WELD_ZONE_DEG;
    let far_range = inner
        .iter()
        .chain(outer)
        .filter(far)
        .map(|p| p.1)
        .filter(|v| v.is_finite())
        .fold(None, |r: Option<(f64, f64)>, v| {
            Some(r.map_or((v, v), |(a, b)| (a.min(v), b.max(v))))
        });
    let mut far_axis = Axis::linear("σ_θθ [MPa]");
    if let Some((a, b)) = far_range {
        let pad = 0.1 * (b - a).max(0.1 * a.abs().max(b.abs())).max(1e-3);
        far_axis = far_axis.range(a - pad, b + pad);
    }
    // the peak of each surface, marked where it leaves the far-field scale
    let mut off = Vec::new();
    for (name, pts) in [("inner", inner), ("outer", outer)] {
        if let Some(&(x, y)) = pts
            .iter()
            .filter(|p| p.1.is_finite())
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            && let Some((lo, hi)) = far_axis.range
            && (y > hi || y < lo)
        {
            off.push(OffScale {
                x: x.max(WELD_ZONE_DEG),
                y,
                label: format!(
                    "{name}: {} MPa at θ = {}°",
                    fmt_value(y.round()),
                    fmt_value((x * 100.0).round() / 100.0)
                ),
            });
        }
    }
    Figure {
        title: "Hoop prestress around the circumference after cooling".into(),
        panels: vec![
            Panel {
                title: "weld zone (full scale)".into(),
                x: Axis::linear("θ from the weld centre [°]").range(0.0, WELD_ZONE_DEG),
                y: Axis::linear("σ_θθ [MPa]"),
                lines: lines(),
                legend: LegendAt::UpperRight,
                ..Default::default()
            },
            Panel {
                title: "far field (θ ≥ 20°)".into(),
                x: Axis::linear("θ from the weld centre [°]").range(WELD_ZONE_DEG, 180.0),
                y: far_axis,
                lines: lines(),
                off_scale: off,
                legend: LegendAt::None,
                ..Default::default()
            },
        ],
        size: (1300, 600),
    }
}

/// One interface point (a node pair of the interface), averaged over the
/// interface elements that meet there.
#[derive(Clone, Debug, PartialEq)]
pub struct InterfaceRow {
    /// interface index in the model
    pub interface: usize,
    /// θ of the point from the weld centre, degrees
    pub theta_deg: f64,
    /// x, y of the point, m
    pub position: [f64; 2],
    /// tangential jump ⟦u⟧_t, m
    pub jump_t: f64,
    /// normal jump (opening) ⟦u⟧_n, m
    pub jump_n: f64,
    /// shear traction t_s, Pa
    pub shear: f64,
    /// contact pressure −t_n, Pa
    pub pressure: f64,
    /// plastic slip g_s, m
    pub slip: f64,
    /// status: 0 open, 1 stick, 2 slip (the most open of the merged points)
    pub status: u8,
}

/// The status code of the CSV: 0 open, 1 stick, 2 slip.
pub fn status_code(s: ContactStatus) -> u8 {
    match s {
        ContactStatus::Open => 0,
        ContactStatus::Stick => 1,
        ContactStatus::Slip => 2,
    }
}

/// Interface points merged per position (each interior node is a point of
/// two elements) and sorted by angle about `centre` (θ in (−180°, 180°]).
/// Points of different interfaces are never merged (sorted by interface first).
/// Values of coinciding points are averaged; a point open in either element
/// is reported open, otherwise slip wins over stick.
pub fn interface_rows(points: &[InterfacePointResult], centre: [f64; 2]) -> Vec<InterfaceRow> {
    let scale = points
        .iter()
        .map(|p| (p.position[0] - centre[0]).hypot(p.position[1] - centre[1]))
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let tol = 1e-9 * scale;
    let theta = |p: [f64; 2]| (p[1] - centre[1]).atan2(p[0] - centre[0]).to_degrees();
    let mut idx: Vec<usize> = (0..points.len()).collect();
    idx.sort_by(|&a, &b| {
        let (pa, pb) = (points[a].position, points[b].position);
        points[a]
            .interface
            .cmp(&points[b].interface)
            .then(theta(pa).total_cmp(&theta(pb)))
            .then(pa[0].total_cmp(&pb[0]))
            .then(pa[1].total_cmp(&pb[1]))
            .then(a.cmp(&b))
    });
    let mut rows: Vec<(InterfaceRow, usize)> = Vec::new();
    let rank = |s: u8| match s {
        0 => 2,
        2 => 1,
        _ => 0,
    };
    for i in idx {
        let p = &points[i];
        let row = InterfaceRow {
            interface: p.interface,
            theta_deg: theta(p.position),
            position: p.position,
            jump_t: p.jump[0],
            jump_n: p.jump[1],
            shear: p.traction[0],
            pressure: -p.traction[1],
            slip: p.slip,
            status: status_code(p.status),
        };
        // coinciding points are adjacent after the sort, or within a few places (same θ)
        let same = rows.iter_mut().rev().take(4).find(|(r, _)| {
            r.interface == p.interface
                && (r.position[0] - p.position[0]).abs() <= tol
                && (r.position[1] - p.position[1]).abs() <= tol
        });
        match same {
            Some((r, n)) => {
                let w = *n as f64;
                let avg = |a: f64, b: f64| (a * w + b) / (w + 1.0);
                r.jump_t = avg(r.jump_t, row.jump_t);
                r.jump_n = avg(r.jump_n, row.jump_n);
                r.shear = avg(r.shear, row.shear);
                r.pressure = avg(r.pressure, row.pressure);
                r.slip = avg(r.slip, row.slip);
                if rank(row.status) > rank(r.status) {
                    r.status = row.status;
                }
                *n += 1;
            }
            None => rows.push((row, 1)),
        }
    }
    rows.into_iter().map(|(r, _)| r).collect()
}

/// One CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// A CSV document: a header row and numeric rows (`{:.9e}`), every field valid.
pub fn csv_text(header: &[&str], rows: impl IntoIterator<Item = Vec<f64>>) -> String {
    let mut s = header
        .iter()
        .map(|h| csv_field(h))
        .collect::<Vec<_>>()
        .join(",");
    s.push('\n');
    for r in rows {
        s += &r
            .iter()
            .map(|v| format!("{v:.9e}"))
            .collect::<Vec<_>>()
            .join(",");
        s.push('\n');
    }
    s
}

/// Header of the interface CSVs.
pub const INTERFACE_HEADER: [&str; 9] = [
    "theta_deg",
    "x_m",
    "y_m",
    "jump_t_m",
    "jump_n_m",
    "shear_Pa",
    "contact_pressure_Pa",
    "slip_m",
    "status (0 open; 1 stick; 2 slip)",
];

/// The values of one interface row in the order of [`INTERFACE_HEADER`].
pub fn interface_values(r: &InterfaceRow) -> Vec<f64> {
    vec![
        r.theta_deg,
        r.position[0],
        r.position[1],
        r.jump_t,
        r.jump_n,
        r.shear,
        r.pressure,
        r.slip,
        f64::from(r.status),
    ]
}

/// The interface CSV: one row per interface point, sorted by θ.
pub fn interface_csv(rows: &[InterfaceRow]) -> String {
    csv_text(&INTERFACE_HEADER, rows.iter().map(interface_values))
}

/// The interface after cooling: contact pressure against the consistent
/// analytical value, weld zone beside the half circumference.
pub fn interface_pressure(rows: &[InterfaceRow], analytical: Option<(&str, f64)>) -> Figure {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.theta_deg, r.pressure / 1e6))
        .collect();
    let panel = |title: &str, range: (f64, f64), legend: LegendAt| {
        let mut lines = vec![Line::solid("FE", 0, pts.clone()).with_markers()];
        if let Some((label, p)) = analytical {
            lines.push(Line::dashed(
                label,
                1,
                vec![(range.0, p / 1e6), (range.1, p / 1e6)],
            ));
        }
        Panel {
            title: title.into(),
            x: Axis::linear("θ from the weld centre [°]").range(range.0, range.1),
            y: Axis::linear("contact pressure [MPa]"),
            lines,
            legend,
            ..Default::default()
        }
    };
    Figure {
        title: "Core/layer interface after cooling: contact pressure".into(),
        panels: vec![
            panel("weld zone (0–3°)", (0.0, WELD_DETAIL_DEG), LegendAt::None),
            panel("half circumference", (0.0, 180.0), LegendAt::UpperRight),
        ],
        size: (1300, 600),
    }
}

/// Fig. 10: tangential displacement u_θ (µm) of the outer surface after
/// cooling, sorted by θ, against the free shrinkage of the half weld
/// (−κ α ΔT w/2, µm, κ = 1 + ν in plane strain, else 1); weld zone beside
/// the half circumference.
pub fn fig10(u_theta: &[(f64, f64)], free_shrinkage: f64) -> Figure {
    let panel = |title: &str, range: (f64, f64), legend: LegendAt| Panel {
        title: title.into(),
        x: Axis::linear("θ from the weld centre [°]").range(range.0, range.1),
        y: Axis::linear("u_θ [µm]"),
        lines: vec![
            Line::solid("FE, outer surface", 0, u_theta.to_vec()),
            Line::dashed(
                "free shrinkage of the half weld, −κ α ΔT w/2 (κ = 1 + ν in plane strain, else 1)",
                1,
                vec![(range.0, free_shrinkage), (range.1, free_shrinkage)],
            ),
        ],
        legend,
        ..Default::default()
    };
    Figure {
        title: "Tangential displacement of the outer surface after cooling".into(),
        panels: vec![
            panel("weld zone (0–3°)", (0.0, WELD_DETAIL_DEG), LegendAt::None),
            panel("half circumference", (0.0, 180.0), LegendAt::LowerRight),
        ],
        size: (1300, 600),
    }
}

/// The interface after cooling: plastic slip and opening, weld zone beside the half circumference.
pub fn interface_slip(rows: &[InterfaceRow]) -> Figure {
    let slip: Vec<(f64, f64)> = rows.iter().map(|r| (r.theta_deg, r.slip * 1e6)).collect();
    let open: Vec<(f64, f64)> = rows.iter().map(|r| (r.theta_deg, r.jump_n * 1e6)).collect();
    let panel = |title: &str, range: (f64, f64), legend: LegendAt| Panel {
        title: title.into(),
        x: Axis::linear("θ from the weld centre [°]").range(range.0, range.1),
        y: Axis::linear("plastic slip, opening [µm]"),
        lines: vec![
            Line::solid("plastic slip g_s", 0, slip.clone()),
            Line::dashed("opening ⟦u⟧_n", 1, open.clone()),
        ],
        legend,
        ..Default::default()
    };
    Figure {
        title: "Core/layer interface after cooling: slip and opening".into(),
        panels: vec![
            panel("weld zone (0–3°)", (0.0, WELD_DETAIL_DEG), LegendAt::None),
            panel("half circumference", (0.0, 180.0), LegendAt::UpperRight),
        ],
        size: (1300, 600),
    }
}

/// Least-squares slope of log e against log h (points with e ≤ 0 or h ≤ 0
/// left out); `None` with fewer than two usable points.
pub fn fit_order(h: &[f64], e: &[f64]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = h
        .iter()
        .zip(e)
        .filter(|(h, e)| **h > 0.0 && **e > 0.0 && h.is_finite() && e.is_finite())
        .map(|(h, e)| (h.ln(), e.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// One quantity of a mesh study: its value on each mesh, coarse to fine.
#[derive(Clone, Debug)]
pub struct StudyQuantity {
    /// name (legend)
    pub label: String,
    /// value per mesh
    pub values: Vec<f64>,
}

/// Observed order of one quantity: the change between successive meshes
/// |q(h) − q(h/2)| against h. For q(h) = q* + C hᵖ the change is
/// C (1 − 2⁻ᵖ) hᵖ, so its log–log slope is the order p.
pub fn successive_changes(h: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
    h.windows(2)
        .zip(values.windows(2))
        .map(|(h, v)| (h[0], (v[1] - v[0]).abs()))
        .collect()
}

/// Relative change between two meshes of a mesh study below which the
/// solvers' tolerances, not the discretisation, set it (`--study mesh`
/// prints no order from such changes). The contact solve's outer loop
/// stops once the multipliers change by 1e-4 of the largest contact
/// pressure, and two paths to its fixed point end up to about 1e-6 apart
/// in the study's means (the fused weld's mixed and plain multiplier
/// updates: hoop means 1e-7, the mean contact pressure 3e-7 apart).
pub const STUDY_TOLERANCE_FLOOR: f64 = 1e-5;

/// The changes of `values` between successive meshes, relative to the
/// coarser mesh's value.
pub fn relative_changes(values: &[f64]) -> Vec<f64> {
    values
        .windows(2)
        .map(|w| ((w[1] - w[0]) / w[0]).abs())
        .collect()
}

/// Every change of `values` between successive meshes is below
/// [`STUDY_TOLERANCE_FLOOR`] (and there is one): no order from them.
pub fn changes_at_tolerance(values: &[f64]) -> bool {
    let c = relative_changes(values);
    !c.is_empty() && c.iter().all(|&c| c < STUDY_TOLERANCE_FLOOR)
}

/// The mesh study on log–log axes: the change of each quantity between
/// successive meshes against the element size h of the coarser one, with
/// the fitted order in the legend. Returns the figure and the orders.
pub fn mesh_study(
    h: &[f64],
    quantities: &[StudyQuantity],
    unit: &str,
) -> (Figure, Vec<(String, Option<f64>)>) {
    let mut lines = Vec::new();
    let mut orders = Vec::new();
    for (k, q) in quantities.iter().enumerate() {
        let pts = successive_changes(h, &q.values);
        let (hs, es): (Vec<f64>, Vec<f64>) = pts.iter().copied().unzip();
        let p = fit_order(&hs, &es);
        let label = match p {
            Some(_) if changes_at_tolerance(&q.values) => {
                format!("{} (no order: changes at the solvers' tolerances)", q.label)
            }
            Some(p) => format!("{} (order {:.2})", q.label, p),
            None => format!("{} (no order: fewer than two changes)", q.label),
        };
        lines.push(Line::solid(label, k, pts).with_markers());
        orders.push((q.label.clone(), p));
    }
    let fig = Figure::single(Panel {
        title: "Mesh convergence: change between successive meshes".into(),
        x: Axis::log("element size h of the coarser mesh [m]"),
        y: Axis::log(format!("|q(h) − q(h/2)| [{unit}]")),
        lines,
        notes: vec!["slope = observed order of convergence".into()],
        legend: LegendAt::LowerRight,
        ..Default::default()
    });
    (fig, orders)
}

#[cfg(test)]
mod tests {
    //! Goal: figures say what they show (exact time labels, separate
    //! segments, sorted and merged interface rows, the fitted order).
    use super::*;
    use tecon_contact::ContactStatus;

    /// The history figure: a log time axis, markers at the output times
    /// only, and a panel on the cooler points' scale when one point is far
    /// hotter than the others (none when they are alike).
    #[test]
    fn the_history_shows_the_cool_points_on_their_own_scale() {
        let line = |label: &str, f: &dyn Fn(f64) -> f64| HistoryLine {
            label: label.into(),
            points: [0.0, 0.1, 1.0, 10.0, 100.0]
                .iter()
                .map(|&t| (t, f(t)))
                .collect(),
        };
        let weld = line("weld", &|t| 21.0 + 1100.0 / (1.0 + t));
        let core = line("core", &|t| 21.0 + 30.0 * t / (1.0 + t * t));
        let fig = temperature_history(&[weld.clone(), core.clone()], &[1.0, 100.0]);
        assert_eq!(fig.panels.len(), 2);
        assert_eq!(fig.panels[0].x.scale, crate::plot::Scale::Log);
        // the core peaks at 36 °C at t = 1 s: the detail spans 21–36 °C
        let (lo, hi) = fig.panels[1].y.range.unwrap();
        assert!(
            lo < 21.0 && lo > 19.0 && hi > 36.0 && hi < 38.0,
            "{lo} {hi}"
        );
        let marks: Vec<&Line> = fig.panels[0].lines.iter().filter(|l| l.no_line).collect();
        assert_eq!(marks.len(), 2);
        assert!(
            marks
                .iter()
                .all(|l| l.points.iter().map(|p| p.0).eq([1.0, 100.0]))
        );
        // two alike points: one panel
        let fig = temperature_history(&[core.clone(), core], &[]);
        assert_eq!(fig.panels.len(), 1);
        assert!(fig.panels[0].lines.iter().all(|l| !l.no_line));
    }

    fn point(x: f64, y: f64, p: f64, status: ContactStatus) -> InterfacePointResult {
        InterfacePointResult {
            position: [x, y],
            jump: [0.0, 0.0],
            traction: [0.0, -p],
            slip: 0.0,
            debonded: false,
            status,
            interface: 0,
            element: 0,
            point: 0,
        }
    }

    #[test]
    fn interface_rows_are_sorted_by_angle_and_merged_per_point() {
        let r = 2.0f64;
        let at = |deg: f64| [r * deg.to_radians().cos(), r * deg.to_radians().sin()];
        // two elements 10–20° and 0–10°, listed in that order: the 10° point twice
        let pts = vec![
            point(at(10.0)[0], at(10.0)[1], 2.0, ContactStatus::Stick),
            point(at(20.0)[0], at(20.0)[1], 3.0, ContactStatus::Stick),
            point(at(0.0)[0], at(0.0)[1], 1.0, ContactStatus::Slip),
            point(at(10.0)[0], at(10.0)[1], 4.0, ContactStatus::Open),
        ];
        let rows = interface_rows(&pts, [0.0, 0.0]);
        assert_eq!(rows.len(), 3);
        let th: Vec<f64> = rows.iter().map(|r| r.theta_deg).collect();
        assert!(
            (th[0] - 0.0).abs() < 1e-12
                && (th[1] - 10.0).abs() < 1e-12
                && (th[2] - 20.0).abs() < 1e-12,
            "{th:?}"
        );
        assert_eq!(rows[1].pressure, 3.0);
        assert_eq!(rows[1].status, 0, "open in either element: open");
        assert_eq!(rows[0].status, 2);
        let csv = interface_csv(&rows);
        let mut lines = csv.lines();
        let header = lines.next().unwrap();
        assert!(
            header.ends_with("\"status (0 open; 1 stick; 2 slip)\"")
                || header.ends_with("status (0 open; 1 stick; 2 slip)")
        );
        for l in lines {
            assert_eq!(l.split(',').count(), INTERFACE_HEADER.len(), "{l}");
        }
    }

    #[test]
    fn csv_fields_with_commas_are_quoted() {
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        assert_eq!(csv_field("say \"x\""), "\"say \"\"x\"\"\"");
        assert_eq!(csv_field("plain"), "plain");
    }

    #[test]
    fn fitted_order_recovers_the_exponent() {
        // q(h) = 1 + 3 h² : successive changes scale as h²
        let h = [0.1, 0.05, 0.025, 0.0125];
        let v: Vec<f64> = h.iter().map(|h| 1.0 + 3.0 * h * h).collect();
        let pts = successive_changes(&h, &v);
        let (hs, es): (Vec<f64>, Vec<f64>) = pts.into_iter().unzip();
        let p = fit_order(&hs, &es).unwrap();
        assert!((p - 2.0).abs() < 1e-10, "{p}");
        assert_eq!(fit_order(&[1.0], &[1.0]), None);
        let (fig, orders) = mesh_study(
            &h,
            &[StudyQuantity {
                label: "q".into(),
                values: v,
            }],
            "MPa",
        );
        assert!((orders[0].1.unwrap() - 2.0).abs() < 1e-10);
        let svg = fig.to_svg().unwrap();
        assert!(svg.contains("order 2.00"), "legend carries the order");
    }

    #[test]
    fn fig6_labels_times_exactly_and_shows_the_weld_zone() {
        let ring = |t: f64| RingTemperature {
            time: t,
            inner: (0..=180)
                .map(|d| (d as f64, 21.0 + 1000.0 * (-(d as f64)).exp() / t))
                .collect(),
            outer: (0..=180)
                .map(|d| (d as f64, 21.0 + 500.0 * (-(d as f64)).exp() / t))
                .collect(),
        };
        let fig = fig6(&[ring(1.0000000000000004), ring(600.0)]);
        assert_eq!(fig.panels.len(), 2);
        assert_eq!(fig.panels[0].x.range, Some((0.0, WELD_ZONE_DEG)));
        let svg = fig.to_svg().unwrap();
        assert!(svg.contains("t = 1 s") && svg.contains("t = 600 s"));
        assert!(!svg.contains("1.0000000000000004"));
        // inner solid and outer dashed share one colour per time
        assert_eq!(fig.panels[1].lines[0].colour, fig.panels[1].lines[1].colour);
        assert!(fig.panels[1].lines[1].dashed && !fig.panels[1].lines[0].dashed);
    }

    #[test]
    fn fig9_marks_the_spike_outside_the_far_field_scale() {
        let inner: Vec<(f64, f64)> = (0..=180)
            .map(|d| (d as f64, if d == 0 { 2300.0 } else { -2.0 }))
            .collect();
        let outer: Vec<(f64, f64)> = (0..=180)
            .map(|d| (d as f64, if d == 0 { -900.0 } else { 4.5 }))
            .collect();
        let fig = fig9(&inner, &outer);
        let (lo, hi) = fig.panels[1].y.range.unwrap();
        assert!(lo > -10.0 && hi < 10.0, "far-field scale {lo}..{hi}");
        assert_eq!(fig.panels[1].off_scale.len(), 2);
        assert!(fig.panels[1].off_scale[0].label.contains("2300 MPa"));
        fig.to_svg().unwrap();
    }

    #[test]
    fn through_wall_profiles_are_not_joined_across_the_interface() {
        let fe = WallProfile {
            label: "FE".into(),
            core: vec![(0.0, -2.0), (67.0, -2.1)],
            layer: vec![(67.0, 4.3), (100.0, 4.2)],
        };
        let fig = through_wall("Hoop", &fe, &[]);
        let pts = &fig.panels[0].lines[0].points;
        assert!(pts[2].0.is_nan(), "a break between core and layer");
        let pieces = crate::plot::clip_polyline(pts, (0.0, 100.0), (-10.0, 10.0));
        assert_eq!(pieces.len(), 2);
    }
}
