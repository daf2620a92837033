//! The accuracy study of the vessel on graded meshes: every judged quantity
//! (see `tecon_cli::accuracy`) on a list of meshes, one column per mesh.
//!
//! ```text
//! cargo run --release -p tecon --example p2_accuracy -- frictionless g0,g1,g2,g3
//! cargo run --release -p tecon --example p2_accuracy -- bonded 2,3,4 1   # order 1
//! ```
//! Arguments: interface (frictional | frictionless | bonded), meshes (as
//! `tecon vessel --mesh`), optional element order (default: the mesh's).

use tecon_cli::accuracy::judged;
use tecon_cli::builtin::{InterfaceKind, VesselOptions};
use tecon_cli::mesh_cmd::parse_preset;
use tecon_cli::vessel::analyse;

fn main() -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let interface = InterfaceKind::parse(args.first().map_or("frictional", |s| s))?;
    let meshes: Vec<String> = args
        .get(1)
        .map_or("g0,g1,g2", |s| s)
        .split(',')
        .map(String::from)
        .collect();
    let order: Option<usize> = args.get(2).map(|s| s.parse()).transpose()?;
    let mut columns = Vec::new();
    for m in &meshes {
        let mut spec = match m.strip_prefix("c:") {
            // c:core_rows:layer_rows:stations:weld_divisions:first_ratio:weld_grading:max_interval_deg
            Some(c) => {
                let v: Vec<f64> = c.split(':').map(|x| x.parse()).collect::<Result<_, _>>()?;
                tecon_mesh::VesselMeshSpec {
                    core_rows: v[0] as usize,
                    layer_rows: v[1] as usize,
                    stations: v[2] as usize,
                    weld_divisions: v[3] as usize,
                    first_ratio: v[4],
                    weld_grading: v[5],
                    max_interval: v[6].to_radians(),
                    fused_weld: false,
                    order: 2,
                }
            }
            None => parse_preset(m)?,
        };
        if let Some(o) = order {
            spec.order = o;
        }
        let o = VesselOptions {
            mesh: spec,
            interface,
            quiet: true,
            ..VesselOptions::default()
        };
        let run = analyse(&o)?;
        eprintln!(
            "{m}: {} triangles, {} nodes, {:.2} s (thermal {:.2}, contact {:.2}), {} Newton iterations",
            run.mesh.n_triangles(),
            run.mesh.n_nodes(),
            run.seconds,
            run.thermal_seconds,
            run.contact_seconds,
            run.newton.iterations
        );
        for r in &run.results {
            if let Some(t) = &r.temperature {
                let (i, tmin) =
                    t.iter().enumerate().fold(
                        (0, f64::INFINITY),
                        |a, (i, &v)| if v < a.1 { (i, v) } else { a },
                    );
                let x = run.mesh.nodes()[i];
                eprintln!(
                    "  t = {} s: lowest temperature {tmin:.6} °C at node {i} (r = {:.5} m, θ = {:.3}°)",
                    r.time,
                    x[0].hypot(x[1]),
                    x[1].atan2(x[0]).to_degrees()
                );
            }
        }
        columns.push((m.clone(), run.mesh.n_triangles(), run.seconds, judged(&run)));
    }
    print!("{:<36}", "quantity");
    for (m, ..) in &columns {
        print!(" {m:>16}");
    }
    println!();
    print!("{:<36}", "triangles");
    for (_, t, ..) in &columns {
        print!(" {t:>16}");
    }
    println!();
    print!("{:<36}", "seconds");
    for (_, _, s, _) in &columns {
        print!(" {s:>16.3}");
    }
    println!();
    for (k, q) in columns[0].3.iter().enumerate() {
        print!("{:<36}", q.name);
        for (.., j) in &columns {
            print!(" {:>16.9e}", j[k].value);
        }
        println!();
    }
    Ok(())
}
