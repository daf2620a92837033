//! The writers shared by every front door: per-state files (VTK series,
//! interface and nodal CSV, probes), the per-state summary JSON, CSV tables,
//! line plots, and staged output (written into a temporary folder, moved
//! into place at the end, `summary.json` last).
//!
//! A writer takes the output folder and returns the names of the files it
//! wrote, so that a front door can add its own files (figures, reports) and
//! [`staged`] moves them all.

use std::path::Path;

use serde_json::{Value, json};
use tecon_contact::ContactStatus;
use tecon_elastic::{InterfacePointResult, StressField, polar, von_mises};
use tecon_mesh::Mesh;
use tecon_mesh::vtk::{Field, cell_type, write_cells_vtu, write_pvd};

use crate::driver::{State, TemperatureHistory};
use crate::plot::{LinePlot, Series};

/// Boxed error of the command layer.
pub type CliResult<T> = Result<T, Box<dyn std::error::Error + Send + Sync>>;

/// Which per-state files to write.
#[derive(Debug, Clone, Copy)]
pub struct StateFiles<'a> {
    /// File stem of the VTK series: `<stem>_NNN.vtu` and the `.pvd` below.
    pub vtu_stem: &'a str,
    /// Name of the `.pvd` collection.
    pub pvd: &'a str,
    /// Write the VTK series.
    pub vtk: bool,
    /// Write `nodal_NNN.csv`.
    pub csv_nodal: bool,
    /// Write `interface_NNN.csv` (for states with interface points).
    pub csv_interface: bool,
}

/// Numbers in CSV files: 10 significant digits.
pub fn csv_line(v: &[f64]) -> String {
    let s: Vec<String> = v.iter().map(|x| format!("{x:.9e}")).collect();
    s.join(",")
}

/// Writes `text` to `path`, naming the path in the error.
pub fn write(path: &Path, text: &str) -> CliResult<()> {
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()).into())
}

/// A CSV table with a header line.
pub fn csv(path: &Path, header: &str, rows: impl IntoIterator<Item = Vec<f64>>) -> CliResult<()> {
    let mut s = String::from(header);
    s.push('\n');
    for r in rows {
        s += &csv_line(&r);
        s.push('\n');
    }
    write(path, &s)
}

/// A line plot as `<dir>/<name>.svg` and `.png`.
pub fn plot(
    dir: &Path,
    name: &str,
    title: &str,
    x: &str,
    y: &str,
    series: Vec<Series>,
) -> CliResult<()> {
    LinePlot {
        title: title.into(),
        x_label: x.into(),
        y_label: y.into(),
        series,
    }
    .write_svg_png(&dir.join(name))?;
    Ok(())
}

/// Contact status as a number for CSV files (0 open, 1 stick, 2 slip).
pub fn status_code(s: ContactStatus) -> f64 {
    match s {
        ContactStatus::Open => 0.0,
        ContactStatus::Stick => 1.0,
        ContactStatus::Slip => 2.0,
    }
}

/// The mesh's nodes split per region, so that a recovered stress may jump
/// across a region border (the weld edge) or an interface: one point per
/// (node, region) pair, in order of first appearance over the elements.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionPoints {
    /// Mesh node of each point.
    pub node: Vec<usize>,
    /// Region of each point.
    pub region: Vec<usize>,
    /// Per element node (3 or 6 per element, connectivity order): its point.
    pub cell: Vec<usize>,
    /// Nodes per element (3 on linear triangles, 6 on 6-node ones).
    pub per_element: usize,
}

impl RegionPoints {
    /// The points of `mesh` (all its element nodes, mid nodes included).
    pub fn new(mesh: &Mesh) -> Self {
        let conn: Vec<&[usize]> = match mesh.triangles6() {
            Some(t6) => t6.iter().map(|t| &t[..]).collect(),
            None => mesh.triangles().iter().map(|t| &t[..]).collect(),
        };
        let per_element = if mesh.triangles6().is_some() { 6 } else { 3 };
        let mut seen: Vec<Vec<(usize, usize)>> = vec![Vec::new(); mesh.n_nodes()];
        let (mut node, mut region) = (Vec::new(), Vec::new());
        let mut cell = Vec::with_capacity(per_element * conn.len());
        for (t, &r) in conn.iter().zip(mesh.element_regions()) {
            for &v in t.iter() {
                let k = match seen[v].iter().find(|(g, _)| *g == r) {
                    Some(&(_, k)) => k,
                    None => {
                        node.push(v);
                        region.push(r);
                        seen[v].push((r, node.len() - 1));
                        node.len() - 1
                    }
                };
                cell.push(k);
            }
        }
        RegionPoints {
            node,
            region,
            cell,
            per_element,
        }
    }

    /// The point of mesh node `node` in region `region`, if there is one.
    pub fn point(&self, node: usize, region: usize) -> Option<usize> {
        (0..self.node.len()).find(|&k| self.node[k] == node && self.region[k] == region)
    }

    /// A per-point stress from the field's per-region recovered values
    /// (the mesh's nodal values where the field has none).
    pub fn stresses(&self, s: &StressField) -> Vec<[f64; 4]> {
        if s.nodes_per_element() != self.per_element {
            return self.node.iter().map(|&v| s.nodal[v]).collect();
        }
        let mut out = vec![[0.0; 4]; self.node.len()];
        for (&k, r) in self.cell.iter().zip(&s.recovered) {
            out[k] = *r;
        }
        out
    }
}

/// One state as VTU: temperature (if any), displacement, Cartesian and polar
/// stresses, von Mises at the points; element stresses, regions and the
/// Zienkiewicz–Zhu indicator η_e per cell. Cells are VTK_TRIANGLE on linear
/// meshes and VTK_QUADRATIC_TRIANGLE on 6-node ones; points are the mesh
/// nodes split per region ([`RegionPoints`]), so the point stresses are the
/// recovered values of each region, never averaged across a region border
/// or an interface (`node` names the mesh node of each point).
pub fn write_state_vtu(mesh: &Mesh, path: &Path, state: &State) -> CliResult<()> {
    let rp = RegionPoints::new(mesh);
    let u = &state.displacement;
    let s = &state.stress;
    let x: Vec<[f64; 2]> = rp.node.iter().map(|&v| mesh.nodes()[v]).collect();
    let disp: Vec<[f64; 2]> = rp.node.iter().map(|&v| [u[2 * v], u[2 * v + 1]]).collect();
    let st = rp.stresses(s);
    let nodal: Vec<f64> = st.iter().flat_map(|v| v.iter().copied()).collect();
    let polar_n: Vec<f64> = st
        .iter()
        .zip(&x)
        .flat_map(|(v, p)| polar(*v, *p, [0.0; 2]))
        .collect();
    let vm: Vec<f64> = st.iter().map(|v| von_mises(*v)).collect();
    let node_id: Vec<f64> = rp.node.iter().map(|&v| v as f64).collect();
    let cell: Vec<f64> = s.element.iter().flat_map(|v| v.iter().copied()).collect();
    let region: Vec<f64> = mesh.element_regions().iter().map(|&r| r as f64).collect();
    let temperature: Option<Vec<f64>> = state
        .temperature
        .as_ref()
        .map(|t| rp.node.iter().map(|&v| t[v]).collect());
    let mut point_data = vec![
        ("displacement_m", Field::Vectors(&disp)),
        (
            "stress_xx_yy_xy_zz_Pa",
            Field::Components {
                n: 4,
                values: &nodal,
            },
        ),
        (
            "stress_rr_tt_rt_Pa",
            Field::Components {
                n: 3,
                values: &polar_n,
            },
        ),
        ("von_mises_Pa", Field::Scalars(&vm)),
        ("node", Field::Scalars(&node_id)),
    ];
    if let Some(t) = &temperature {
        point_data.insert(0, ("temperature_C", Field::Scalars(t)));
    }
    let mut cell_data = vec![
        (
            "stress_xx_yy_xy_zz_Pa",
            Field::Components {
                n: 4,
                values: &cell,
            },
        ),
        ("region", Field::Scalars(&region)),
    ];
    if s.error.element.len() == mesh.n_triangles() {
        cell_data.push(("zz_error_indicator", Field::Scalars(&s.error.element)));
    }
    let kind = if rp.per_element == 6 {
        cell_type::QUADRATIC_TRIANGLE
    } else {
        cell_type::TRIANGLE
    };
    let cells: Vec<(u8, Vec<usize>)> = rp
        .cell
        .chunks_exact(rp.per_element)
        .map(|c| (kind, c.to_vec()))
        .collect();
    write_cells_vtu(path, &x, &cells, &point_data, &cell_data)?;
    Ok(())
}

/// `nodal_NNN.csv`: one row per mesh node and region it belongs to (a node
/// on a region border or an interface has one row per region, each with
/// its region's recovered stresses).
fn nodal_csv(mesh: &Mesh, r: &State) -> String {
    let rp = RegionPoints::new(mesh);
    let st = rp.stresses(&r.stress);
    let names = mesh.region_names();
    let mut s = String::from(
        "node,region,x_m,y_m,T_C,ux_m,uy_m,sxx_Pa,syy_Pa,sxy_Pa,szz_Pa,von_mises_Pa\n",
    );
    let mut order: Vec<usize> = (0..rp.node.len()).collect();
    order.sort_by_key(|&k| (rp.node[k], rp.region[k]));
    for k in order {
        let i = rp.node[k];
        let t = r.temperature.as_ref().map_or(f64::NAN, |t| t[i]);
        let sk = st[k];
        let name = names.get(rp.region[k]).map_or("", String::as_str);
        s += &format!("{i},{name},");
        s += &csv_line(&[
            mesh.nodes()[i][0],
            mesh.nodes()[i][1],
            t,
            r.displacement[2 * i],
            r.displacement[2 * i + 1],
            sk[0],
            sk[1],
            sk[2],
            sk[3],
            von_mises(sk),
        ]);
        s.push('\n');
    }
    s
}

/// `interface_NNN.csv`: one row per interface point, in order along each
/// interface (see [`crate::interface_table`]).
fn interface_csv(names: &[String], r: &State) -> String {
    crate::interface_table::csv(names, &r.interface)
}

/// The files of one state into `dir`, named by `tag`: `nodal_<tag>.csv`,
/// `interface_<tag>.csv` (with interface points) and `<stem>_<tag>.vtu`, as
/// `files` asks; returns the names written (no `.pvd` entry: a state of
/// its own, e.g. the vessel's operating state, stands beside the series).
pub fn write_state_files(
    dir: &Path,
    mesh: &Mesh,
    interfaces: &[String],
    r: &State,
    tag: &str,
    files: StateFiles<'_>,
) -> CliResult<Vec<String>> {
    let mut names = Vec::new();
    if files.csv_nodal {
        let name = format!("nodal_{tag}.csv");
        write(&dir.join(&name), &nodal_csv(mesh, r))?;
        names.push(name);
    }
    if files.csv_interface && !r.interface.is_empty() {
        let name = format!("interface_{tag}.csv");
        write(&dir.join(&name), &interface_csv(interfaces, r))?;
        names.push(name);
    }
    if files.vtk {
        let name = format!("{}_{tag}.vtu", files.vtu_stem);
        write_state_vtu(mesh, &dir.join(&name), r)?;
        names.push(name);
    }
    Ok(names)
}

/// The per-state files of `states` into `dir`; returns the names written.
pub fn write_states(
    dir: &Path,
    mesh: &Mesh,
    interfaces: &[String],
    states: &[State],
    files: StateFiles<'_>,
) -> CliResult<Vec<String>> {
    // the states' files are independent: written in parallel (large
    // meshes spend most of their output time formatting the VTU text)
    use rayon::prelude::*;
    // per state: the names written and its `.pvd` entry
    type Written = (Vec<String>, Option<(f64, String)>);
    let per_state: Vec<CliResult<Written>> = states
        .par_iter()
        .enumerate()
        .map(|(k, r)| {
            let names = write_state_files(dir, mesh, interfaces, r, &format!("{k:03}"), files)?;
            let vtu = format!("{}_{k:03}.vtu", files.vtu_stem);
            let entry = files.vtk.then_some((r.time, vtu));
            Ok((names, entry))
        })
        .collect();
    let mut written = Vec::new();
    let mut pvd = Vec::new();
    for r in per_state {
        let (names, entry) = r?;
        written.extend(names);
        pvd.extend(entry);
    }
    if !pvd.is_empty() {
        write_pvd(dir.join(files.pvd), &pvd)?;
        written.push(files.pvd.into());
    }
    Ok(written)
}

/// `probes.csv` (nearest-node values per state) and, with two or more
/// states, the histories `probes_von_mises` (and `probes_temperature`) as
/// SVG + PNG; returns the names written.
pub fn write_probes(
    dir: &Path,
    mesh: &Mesh,
    probes: &[([f64; 2], usize)],
    states: &[State],
) -> CliResult<Vec<String>> {
    let mut files = Vec::new();
    if probes.is_empty() {
        return Ok(files);
    }
    // each probe reads the recovered stress of the region it lies in
    let rp = RegionPoints::new(mesh);
    // (the first element slot of its (node, region) point)
    let slot_of: Vec<Option<usize>> = probes
        .iter()
        .map(|(p, i)| {
            let q = crate::probes::locate(mesh, *p)
                .ok()
                .and_then(|e| rp.point(*i, mesh.element_regions()[e]))?;
            rp.cell.iter().position(|&c| c == q)
        })
        .collect();
    let stress_at = |r: &State, k: usize, i: usize| -> [f64; 4] {
        match slot_of[k] {
            Some(slot) if r.stress.nodes_per_element() == rp.per_element => r
                .stress
                .recovered
                .get(slot)
                .copied()
                .unwrap_or(r.stress.nodal[i]),
            _ => r.stress.nodal[i],
        }
    };
    let mut s = String::from(
        "time_s,probe,x_m,y_m,node,node_x_m,node_y_m,T_C,ux_m,uy_m,sxx_Pa,syy_Pa,sxy_Pa,szz_Pa,von_mises_Pa\n",
    );
    for r in states {
        for (k, (p, i)) in probes.iter().enumerate() {
            let st = stress_at(r, k, *i);
            let q = mesh.nodes()[*i];
            s += &format!("{:.9e},{k},", r.time);
            s += &csv_line(&[p[0], p[1]]);
            s += &format!(",{i},");
            s += &csv_line(&[
                q[0],
                q[1],
                r.temperature.as_ref().map_or(f64::NAN, |t| t[*i]),
                r.displacement[2 * i],
                r.displacement[2 * i + 1],
                st[0],
                st[1],
                st[2],
                st[3],
                von_mises(st),
            ]);
            s.push('\n');
        }
    }
    write(&dir.join("probes.csv"), &s)?;
    files.push("probes.csv".into());
    if states.len() < 2 {
        return Ok(files);
    }
    let mut plots = vec![(
        "probes_von_mises",
        "von Mises stress at the probes",
        "σ_vM [MPa]",
        false,
    )];
    if states.iter().all(|r| r.temperature.is_some()) {
        plots.push((
            "probes_temperature",
            "Temperature at the probes",
            "T [°C]",
            true,
        ));
    }
    for (stem, title, y, temperature) in plots {
        let series = probes
            .iter()
            .enumerate()
            .map(|(k, (p, i))| Series {
                label: format!("probe {k} ({}, {})", p[0], p[1]),
                points: states
                    .iter()
                    .map(|r| {
                        let v = match (temperature, &r.temperature) {
                            (true, Some(t)) => t[*i],
                            _ => von_mises(stress_at(r, k, *i)) / 1e6,
                        };
                        (r.time.max(f64::MIN_POSITIVE).log10(), v)
                    })
                    .collect(),
            })
            .collect();
        plot(dir, stem, title, "log10(time [s])", y, series)?;
        files.push(format!("{stem}.svg"));
        files.push(format!("{stem}.png"));
    }
    Ok(files)
}

/// A point of a temperature history: a column of `temperature_history.csv`
/// and a line of its figure.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryProbe {
    /// Column name (`T_<name>_C`) and key in the summary, e.g. `weld_centre`.
    pub name: String,
    /// Legend label, e.g. `weld centre (layer outer surface, θ = 0°)`.
    pub label: String,
    /// The mesh node recorded.
    pub node: usize,
}

/// The file the temperature history is written to.
pub const HISTORY_CSV: &str = "temperature_history.csv";

/// `temperature_history.csv` (one row per record: the start and every
/// thermal step; a column `T_<name>_C` per probe) and the figure
/// `temperature_history` (SVG + PNG, log time axis, the output times
/// marked); returns the names written. `probes` name the nodes of
/// `history`, in its order.
pub fn write_temperature_history(
    dir: &Path,
    probes: &[HistoryProbe],
    history: &TemperatureHistory,
    output_times: &[f64],
) -> CliResult<Vec<String>> {
    if probes.len() != history.nodes.len()
        || probes.iter().zip(&history.nodes).any(|(p, &n)| p.node != n)
    {
        return Err(format!(
            "{HISTORY_CSV}: {} probes named for a history of {} nodes",
            probes.len(),
            history.nodes.len()
        )
        .into());
    }
    if probes.is_empty() || history.times.is_empty() {
        return Ok(Vec::new());
    }
    let header: Vec<String> = std::iter::once("time_s".to_string())
        .chain(probes.iter().map(|p| format!("T_{}_C", p.name)))
        .collect();
    csv(
        &dir.join(HISTORY_CSV),
        &header.join(","),
        history
            .times
            .iter()
            .zip(&history.values)
            .map(|(&t, v)| std::iter::once(t).chain(v.iter().copied()).collect()),
    )?;
    let lines: Vec<crate::figures::HistoryLine> = probes
        .iter()
        .enumerate()
        .map(|(k, p)| crate::figures::HistoryLine {
            label: p.label.clone(),
            points: history
                .times
                .iter()
                .zip(&history.values)
                .map(|(&t, v)| (t, v[k]))
                .collect(),
        })
        .collect();
    let stem = HISTORY_CSV.trim_end_matches(".csv");
    crate::figures::temperature_history(&lines, output_times).write_svg_png(&dir.join(stem))?;
    Ok(vec![
        HISTORY_CSV.to_string(),
        format!("{stem}.svg"),
        format!("{stem}.png"),
    ])
}

/// The history in the summary: per probe its node and position, the
/// highest temperature and the first time it is reached, and the last
/// value; the number of records.
pub fn history_summary(
    mesh: &Mesh,
    probes: &[HistoryProbe],
    history: &TemperatureHistory,
) -> Value {
    let points: Vec<Value> = probes
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let (mut peak, mut at) = (f64::NEG_INFINITY, f64::NAN);
            for (&t, v) in history.times.iter().zip(&history.values) {
                if v[k] > peak {
                    (peak, at) = (v[k], t);
                }
            }
            json!({
                "name": p.name,
                "node": p.node,
                "position": mesh.nodes()[p.node],
                "max": peak,
                "time_of_max": at,
                "last": history.values.last().map(|v| v[k]),
            })
        })
        .collect();
    json!({
        "file": HISTORY_CSV,
        "records": history.times.len(),
        "probes": points,
    })
}

/// Printed lines of the history: the peak of every probe and when.
pub fn history_lines(summary: &Value) -> Vec<String> {
    let Some(points) = summary["probes"].as_array() else {
        return Vec::new();
    };
    let mut s = vec![format!(
        "temperature history at {} records (the start and every thermal step, {HISTORY_CSV}); highest temperature of each point:",
        summary["records"]
    )];
    for p in points {
        let f = |k: &str| p[k].as_f64().unwrap_or(f64::NAN);
        s.push(format!(
            "  {:<28} {:>9.2} °C at t = {} s (last {:.2} °C)",
            p["name"].as_str().unwrap_or_default(),
            f("max"),
            crate::plot::fmt_value(f("time_of_max")),
            f("last")
        ));
    }
    s
}

/// Mean contact pressure of one interface, `∫ p ds / ∫ ds` by the
/// elements' own quadrature (`weights`, parallel to `points`: see
/// [`crate::driver::interface_point_weights`]; open points count as 0),
/// the largest pressure and the point counts. A uniform pressure gives
/// itself and a pressure linear along the joint its exact mean, on 4-node
/// and 6-node elements, nodal or Gauss. `weights` of another length than
/// `points` (a caller error) give a NaN mean, never a wrong number.
pub fn interface_summary(points: &[InterfacePointResult], weights: &[f64], index: usize) -> Value {
    let (mut s, mut w) = (0.0, 0.0);
    let mean = if weights.len() == points.len() {
        for (p, &wq) in points.iter().zip(weights) {
            if p.interface == index {
                s += wq * -p.traction[1];
                w += wq;
            }
        }
        if w > 0.0 { s / w } else { 0.0 }
    } else {
        f64::NAN
    };
    let pts: Vec<&InterfacePointResult> = points.iter().filter(|p| p.interface == index).collect();
    let count = |st: ContactStatus| pts.iter().filter(|p| p.status == st).count();
    json!({
        "contact_pressure_mean": mean,
        "contact_pressure_max": pts.iter().map(|p| -p.traction[1]).fold(0.0, f64::max),
        "points": pts.len(),
        "open": count(ContactStatus::Open),
        "stick": count(ContactStatus::Stick),
        "slip": count(ContactStatus::Slip),
    })
}

/// Area-weighted region means of the element stresses (polar about the
/// origin) of one stress field.
pub fn region_means(mesh: &Mesh, stress: &StressField) -> Value {
    let areas = mesh.areas();
    let x = mesh.nodes();
    let mut regions = serde_json::Map::new();
    for (ri, name) in mesh.region_names().iter().enumerate() {
        let mut acc = [0.0f64; 8];
        let mut area = 0.0;
        for (e, t) in mesh.triangles().iter().enumerate() {
            if mesh.element_regions()[e] != ri {
                continue;
            }
            let a = areas[e].abs();
            let c = [
                (x[t[0]][0] + x[t[1]][0] + x[t[2]][0]) / 3.0,
                (x[t[0]][1] + x[t[1]][1] + x[t[2]][1]) / 3.0,
            ];
            let s = stress.element[e];
            let p = polar(s, c, [0.0, 0.0]);
            let v = [s[0], s[1], s[2], s[3], p[0], p[1], p[2], von_mises(s)];
            for (q, vi) in acc.iter_mut().zip(v) {
                *q += a * vi;
            }
            area += a;
        }
        let m = |k: usize| if area > 0.0 { acc[k] / area } else { 0.0 };
        regions.insert(
            name.clone(),
            json!({
                "area": area,
                "stress_mean": {
                    "xx": m(0), "yy": m(1), "xy": m(2), "zz": m(3),
                    "rr": m(4), "tt": m(5), "rt": m(6), "von_mises": m(7),
                }
            }),
        );
    }
    Value::Object(regions)
}

/// The summary of one state: extremes, interfaces, region means.
pub fn state_summary(mesh: &Mesh, interfaces: &[String], r: &State) -> Value {
    let n = mesh.n_nodes();
    let umax = (0..n)
        .map(|i| r.displacement[2 * i].hypot(r.displacement[2 * i + 1]))
        .fold(0.0, f64::max);
    let vm_max = r
        .stress
        .nodal
        .iter()
        .map(|s| von_mises(*s))
        .fold(0.0, f64::max);
    let mut ifaces = serde_json::Map::new();
    for (k, name) in interfaces.iter().enumerate() {
        ifaces.insert(
            name.clone(),
            interface_summary(&r.interface, &r.interface_weights, k),
        );
    }
    let mut v = json!({
        "time": r.time,
        "max_displacement": umax,
        "max_von_mises": vm_max,
        "eps_zz": r.eps_zz,
        "interfaces": ifaces,
        "regions": region_means(mesh, &r.stress),
        "newton_max_iterations": r.max_iterations,
        "zz_error": {
            "eta": r.stress.error.eta,
            "relative": r.stress.error.relative(),
        },
    });
    if let Some(t) = &r.temperature {
        v["temperature_min"] = json!(t.iter().copied().fold(f64::INFINITY, f64::min));
        v["temperature_max"] = json!(t.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    }
    if let Some(h) = r.heat_balance {
        v["heat_balance_rel_error"] = json!(h);
    }
    v
}

/// Writes all outputs into `out` through `write_all`: first into
/// `out/.partial-<pid>`, then moves each file `write_all` names into `out`
/// (in order: name `summary.json` last) and removes the temporary folder; on
/// failure nothing is moved and the temporary folder (and `out`, if this
/// call created it and it is empty) is removed.
pub fn staged(
    out: &Path,
    write_all: impl FnOnce(&Path) -> CliResult<Vec<String>>,
) -> CliResult<()> {
    let created = !out.exists();
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let tmp = out.join(format!(".partial-{}", std::process::id()));
    let cleanup = |tmp: &Path| {
        let _ = std::fs::remove_dir_all(tmp);
        if created {
            let _ = std::fs::remove_dir(out);
        }
    };
    if let Err(e) = std::fs::create_dir_all(&tmp) {
        cleanup(&tmp);
        return Err(format!("{}: {e}", tmp.display()).into());
    }
    let files = match write_all(&tmp) {
        Ok(f) => f,
        Err(e) => {
            cleanup(&tmp);
            return Err(e);
        }
    };
    for name in &files {
        if let Err(e) = std::fs::rename(tmp.join(name), out.join(name)) {
            cleanup(&tmp);
            return Err(format!("{}: {e}", out.join(name).display()).into());
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
    Ok(())
}

#[cfg(test)]
mod tests {
    //! Goal: the mean contact pressure integrates a uniform and a linear
    //! pressure exactly on 4-node and 6-node interface elements, nodal and
    //! Gauss (equal weights on the three points of a 6-node element would
    //! not: Simpson's 1/6, 2/3, 1/6); the weights of a model come in the
    //! order of its interface points.
    use super::*;
    use crate::driver::interface_point_weights;
    use tecon_contact::nalgebra::Point2;
    use tecon_contact::{InterfaceElement, InterfaceQuadrature, QuadraticInterfaceElement};
    use tecon_elastic::{Analysis, ElasticModel, Joint, Material, StaticSolver};

    fn point(element: usize, q: usize, x: [f64; 2], p: f64) -> InterfacePointResult {
        InterfacePointResult {
            interface: 0,
            element,
            point: q,
            position: x,
            jump: [0.0; 2],
            traction: [0.0, -p],
            status: ContactStatus::Stick,
            slip: 0.0,
            debonded: false,
        }
    }

    /// Two straight elements along y = 0.3 from x = 0 to 1 and 1 to 3
    /// (unequal lengths), pressure `p(x)`; points and weights of each rule.
    fn straight(
        quadratic: bool,
        rule: InterfaceQuadrature,
        p: &dyn Fn(f64) -> f64,
    ) -> (Vec<InterfacePointResult>, Vec<f64>) {
        let (mut pts, mut w) = (Vec::new(), Vec::new());
        for (e, (a, b)) in [(0.0, 1.0), (1.0, 3.0)].into_iter().enumerate() {
            let y = 0.3;
            let at = |s: f64| [a + 0.5 * (s + 1.0) * (b - a), y];
            if quadratic {
                let n = [
                    Point2::new(a, y),
                    Point2::new(b, y),
                    Point2::new(b, y),
                    Point2::new(a, y),
                    Point2::new(0.5 * (a + b), y),
                    Point2::new(0.5 * (a + b), y),
                ];
                let el = QuadraticInterfaceElement::with_quadrature(&n, rule).unwrap();
                for (q, ip) in el.points().iter().enumerate() {
                    let x = at(ip.s);
                    pts.push(point(e, q, x, p(x[0])));
                    w.push(ip.weight);
                }
            } else {
                let n = [
                    Point2::new(a, y),
                    Point2::new(b, y),
                    Point2::new(b, y),
                    Point2::new(a, y),
                ];
                let el = InterfaceElement::with_quadrature(&n, rule).unwrap();
                let s = match rule {
                    InterfaceQuadrature::Nodal => [-1.0, 1.0],
                    InterfaceQuadrature::Gauss2 => [-1.0 / 3f64.sqrt(), 1.0 / 3f64.sqrt()],
                };
                for (q, ip) in el.points().iter().enumerate() {
                    let x = at(s[q]);
                    pts.push(point(e, q, x, p(x[0])));
                    w.push(ip.weight);
                }
            }
        }
        (pts, w)
    }

    #[test]
    fn uniform_and_linear_pressures_integrate_exactly() {
        for quadratic in [false, true] {
            for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
                let (pts, w) = straight(quadratic, rule, &|_| 7.0e6);
                let m = interface_summary(&pts, &w, 0)["contact_pressure_mean"]
                    .as_f64()
                    .unwrap();
                assert!((m - 7.0e6).abs() < 1e-6, "{quadratic} {rule:?}: {m}");
                // p = 1 + 2x on [0, 3]: mean 1 + 2 · 1.5 = 4 (MPa)
                let (pts, w) = straight(quadratic, rule, &|x| 1e6 * (1.0 + 2.0 * x));
                let m = interface_summary(&pts, &w, 0)["contact_pressure_mean"]
                    .as_f64()
                    .unwrap();
                assert!((m - 4.0e6).abs() < 1e-6, "{quadratic} {rule:?}: {m}");
            }
        }
        // the old rule (equal weights per 6-node element) is off on the
        // linear pressure with unequal elements, and mismatched weights
        // give NaN rather than a number
        let (pts, _) = straight(true, InterfaceQuadrature::Nodal, &|x| 1e6 * (1.0 + 2.0 * x));
        let m = interface_summary(&pts, &[1.0], 0)["contact_pressure_mean"].as_f64();
        assert!(m.is_none_or(f64::is_nan), "{m:?}");
    }

    #[test]
    fn model_weights_follow_the_interface_points() {
        let layers =
            [("inner", 1.0, 1.1), ("outer", 1.1, 1.2)].map(|(n, a, b)| tecon_mesh::RingLayer {
                name: n.into(),
                r_in: a,
                r_out: b,
                rows: 1,
            });
        let steel = Material {
            youngs_modulus: 200e9,
            poisson_ratio: 0.3,
            expansion: 1e-5,
        };
        for order in [1, 2] {
            let mesh = tecon_mesh::layered_annulus_of_order(
                &layers,
                0.0,
                std::f64::consts::FRAC_PI_2,
                5,
                order,
            )
            .unwrap();
            for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
                let law = tecon_contact::LinearJoint::new(1e12, 1e12).unwrap();
                let model = ElasticModel::new(&mesh, Analysis::PlaneStrain)
                    .material_everywhere(steel)
                    .unwrap()
                    .interface_quadrature(rule)
                    .interface("inner_outer", Joint::Linear(law))
                    .unwrap()
                    .symmetry("start")
                    .unwrap()
                    .symmetry("end")
                    .unwrap();
                let solver = StaticSolver::new(&model, Default::default()).unwrap();
                let pts = solver.interface_results();
                let w = interface_point_weights(&model);
                assert_eq!(w.len(), pts.len());
                // Σ w = the arc length (P2: to the curved-edge accuracy;
                // P1: the chords)
                let arc = 1.1 * std::f64::consts::FRAC_PI_2;
                let sum: f64 = w.iter().sum();
                let tol = if order == 2 { 1e-4 } else { 2e-2 };
                assert!(
                    (sum / arc - 1.0).abs() < tol,
                    "order {order}: {sum} vs {arc}"
                );
                if order == 2 && rule == InterfaceQuadrature::Nodal {
                    // the heavy point (2L/3) is the middle one along θ
                    for (tri, wt) in pts.chunks(3).zip(w.chunks(3)) {
                        let th: Vec<f64> = tri
                            .iter()
                            .map(|p| p.position[1].atan2(p.position[0]))
                            .collect();
                        // (Simpson on the curved edge: 3.98 on these 18° arcs)
                        assert!((wt[1] / wt[0] - 4.0).abs() < 0.05, "{wt:?}");
                        assert!((th[1] - th[0]) * (th[2] - th[1]) > 0.0, "{th:?}");
                    }
                }
            }
        }
    }
}
