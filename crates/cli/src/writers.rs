//! The writers shared by every front door: per-state files (VTK series,
//! interface and nodal CSV, probes), the per-state summary JSON, CSV tables,
//! line plots, and staged output (written into a temporary folder, moved
//! into place at the end, `summary.json` last).
//!
//! A writer takes the output folder and returns the names of the files it
//! wrote, so that a front door can add its own files (figures, reports) and
//! [`staged`] moves them all.

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::{Value, json};
use tecon_contact::ContactStatus;
use tecon_elastic::{InterfacePointResult, StressField, polar, von_mises};
use tecon_mesh::Mesh;
use tecon_mesh::vtk::{Field, VtuPiece, write_pvd, write_vtu};

use crate::driver::State;
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

/// One state as VTU: temperature (if any), displacement, Cartesian and polar
/// stresses, von Mises; element stresses and regions.
pub fn write_state_vtu(mesh: &Mesh, path: &Path, state: &State) -> CliResult<()> {
    let n = mesh.n_nodes();
    let u = &state.displacement;
    let s = &state.stress;
    let disp: Vec<[f64; 2]> = (0..n).map(|i| [u[2 * i], u[2 * i + 1]]).collect();
    let nodal: Vec<f64> = s.nodal.iter().flat_map(|v| v.iter().copied()).collect();
    let polar_n: Vec<f64> = (0..n)
        .flat_map(|i| polar(s.nodal[i], mesh.nodes()[i], [0.0; 2]))
        .collect();
    let vm: Vec<f64> = s.nodal.iter().map(|v| von_mises(*v)).collect();
    let cell: Vec<f64> = s.element.iter().flat_map(|v| v.iter().copied()).collect();
    let region: Vec<f64> = mesh.element_regions().iter().map(|&r| r as f64).collect();
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
    ];
    if let Some(t) = &state.temperature {
        point_data.insert(0, ("temperature_C", Field::Scalars(t)));
    }
    write_vtu(
        path,
        &VtuPiece {
            points: mesh.nodes(),
            triangles: mesh.triangles(),
            quads: &[],
            point_data: &point_data,
            cell_data: &[
                (
                    "stress_xx_yy_xy_zz_Pa",
                    Field::Components {
                        n: 4,
                        values: &cell,
                    },
                ),
                ("region", Field::Scalars(&region)),
            ],
        },
    )?;
    Ok(())
}

fn nodal_csv(mesh: &Mesh, r: &State) -> String {
    let mut s =
        String::from("node,x_m,y_m,T_C,ux_m,uy_m,sxx_Pa,syy_Pa,sxy_Pa,szz_Pa,von_mises_Pa\n");
    for i in 0..mesh.n_nodes() {
        let t = r.temperature.as_ref().map_or(f64::NAN, |t| t[i]);
        let st = r.stress.nodal[i];
        s += &format!("{i},");
        s += &csv_line(&[
            mesh.nodes()[i][0],
            mesh.nodes()[i][1],
            t,
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
    s
}

fn interface_csv(names: &[String], r: &State) -> String {
    let mut s = String::from(
        "interface,element,point,x_m,y_m,jump_t_m,jump_n_m,shear_Pa,contact_pressure_Pa,slip_m,status(0=open,1=stick,2=slip)\n",
    );
    for p in &r.interface {
        s += &format!("{},{},{},", names[p.interface], p.element, p.point);
        s += &csv_line(&[
            p.position[0],
            p.position[1],
            p.jump[0],
            p.jump[1],
            p.traction[0],
            -p.traction[1],
            p.slip,
            status_code(p.status),
        ]);
        s.push('\n');
    }
    s
}

/// The per-state files of `states` into `dir`; returns the names written.
pub fn write_states(
    dir: &Path,
    mesh: &Mesh,
    interfaces: &[String],
    states: &[State],
    files: StateFiles<'_>,
) -> CliResult<Vec<String>> {
    let mut written = Vec::new();
    let mut pvd = Vec::new();
    for (k, r) in states.iter().enumerate() {
        if files.csv_nodal {
            let name = format!("nodal_{k:03}.csv");
            write(&dir.join(&name), &nodal_csv(mesh, r))?;
            written.push(name);
        }
        if files.csv_interface && !r.interface.is_empty() {
            let name = format!("interface_{k:03}.csv");
            write(&dir.join(&name), &interface_csv(interfaces, r))?;
            written.push(name);
        }
        if files.vtk {
            let name = format!("{}_{k:03}.vtu", files.vtu_stem);
            write_state_vtu(mesh, &dir.join(&name), r)?;
            pvd.push((r.time, name.clone()));
            written.push(name);
        }
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
    let mut s = String::from(
        "time_s,probe,x_m,y_m,node,node_x_m,node_y_m,T_C,ux_m,uy_m,sxx_Pa,syy_Pa,sxy_Pa,szz_Pa,von_mises_Pa\n",
    );
    for r in states {
        for (k, (p, i)) in probes.iter().enumerate() {
            let st = r.stress.nodal[*i];
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
                            _ => von_mises(r.stress.nodal[*i]) / 1e6,
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

/// Arc-length weighted mean contact pressure (open points count as 0) and
/// point counts of one interface.
pub fn interface_summary(points: &[InterfacePointResult], index: usize) -> Value {
    let pts: Vec<&InterfacePointResult> = points.iter().filter(|p| p.interface == index).collect();
    let mut by_el: BTreeMap<usize, Vec<&InterfacePointResult>> = BTreeMap::new();
    for p in &pts {
        by_el.entry(p.element).or_default().push(p);
    }
    let (mut s, mut w) = (0.0, 0.0);
    for el in by_el.values() {
        if el.len() < 2 {
            continue;
        }
        let (a, b) = (el[0].position, el[el.len() - 1].position);
        let len = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        let mean = -el.iter().map(|p| p.traction[1]).sum::<f64>() / el.len() as f64;
        s += len * mean;
        w += len;
    }
    let count = |st: ContactStatus| pts.iter().filter(|p| p.status == st).count();
    json!({
        "contact_pressure_mean": if w > 0.0 { s / w } else { 0.0 },
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
        ifaces.insert(name.clone(), interface_summary(&r.interface, k));
    }
    let mut v = json!({
        "time": r.time,
        "max_displacement": umax,
        "max_von_mises": vm_max,
        "eps_zz": r.eps_zz,
        "interfaces": ifaces,
        "regions": region_means(mesh, &r.stress),
        "newton_max_iterations": r.max_iterations,
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
