//! `tecon mesh`: generate the vessel mesh (or read a Gmsh file), validate it,
//! print a summary and write it as VTK.

use std::path::PathBuf;

use tecon_mesh::vtk::{Field, VtuPiece, write_vtu};
use tecon_mesh::{Mesh, VesselGeometry, VesselMeshSpec, read_msh, vessel_mesh};

/// Arguments of `tecon mesh`.
#[derive(clap::Args, Debug)]
pub struct MeshArgs {
    /// Vessel mesh density (default `paper`): `paper` (the published
    /// 108-node mesh: 136 triangles, 17 interface elements), a uniform
    /// refinement level 0–9 (136·4^level triangles), `gL` (graded toward
    /// the weld corners, made for 6-node triangles: 2 784·4^L triangles,
    /// L = 0–5, order 2), `xF` (every paper interval in F parts, 136·F²
    /// triangles) or `tN` (about N triangles, e.g. `t1e5`). Not with --msh.
    #[arg(long)]
    pub preset: Option<String>,
    /// Fuse the weld to the core (no interface under the weld). Not with --msh.
    #[arg(long)]
    pub fused_weld: bool,
    /// Read this Gmsh MSH 4.1 file instead of generating the vessel.
    #[arg(long)]
    pub msh: Option<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = "tecon-out/mesh")]
    pub out: PathBuf,
}

/// The vessel mesh `tecon mesh` generates without `--preset`.
pub const DEFAULT_PRESET: &str = "paper";

/// Refuses the options that would be ignored: `--preset` and
/// `--fused-weld` describe the generated vessel, not a mesh read with `--msh`.
pub fn check(args: &MeshArgs) -> Result<(), String> {
    if let Some(path) = &args.msh {
        let file = path.display();
        if let Some(p) = &args.preset {
            return Err(format!(
                "--preset {p} cannot be used with --msh {file}: the mesh is read from the file, not generated (drop --preset, or --msh to generate the vessel)"
            ));
        }
        if args.fused_weld {
            return Err(format!(
                "--fused-weld cannot be used with --msh {file}: the file's mesh has its own regions and interfaces (drop --fused-weld, or --msh to generate the vessel)"
            ));
        }
    }
    Ok(())
}

/// Parses a `--mesh`/`--preset` value into a vessel mesh spec.
pub fn parse_preset(preset: &str) -> Result<VesselMeshSpec, String> {
    let bad = || {
        format!(
            "--preset '{preset}': expected 'paper', a refinement level 0-9, 'gL' (graded level L = 0-5, order 2, about 2784·4^L triangles), 'xF' (every paper interval in F parts) or 'tN' (about N triangles)"
        )
    };
    let spec = match preset {
        "paper" => Ok(VesselMeshSpec::paper()),
        other => {
            if let Some(l) = other.strip_prefix('g') {
                VesselMeshSpec::graded(l.parse().map_err(|_| bad())?)
            } else if let Some(f) = other.strip_prefix('x') {
                VesselMeshSpec::subdivided(f.parse().map_err(|_| bad())?)
            } else if let Some(n) = other.strip_prefix('t') {
                let n: f64 = n.parse().map_err(|_| bad())?;
                if !(n.is_finite() && n >= 1.0) {
                    return Err(bad());
                }
                VesselMeshSpec::with_triangles(n as usize)
            } else {
                VesselMeshSpec::refined(other.parse().map_err(|_| bad())?)
            }
        }
    };
    spec.map_err(|e| format!("--preset '{preset}': {e}"))
}

/// Runs `tecon mesh`.
pub fn run(args: MeshArgs) -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
    check(&args)?;
    let mesh = match &args.msh {
        Some(path) => read_msh(path)?,
        None => {
            let preset = args.preset.as_deref().unwrap_or(DEFAULT_PRESET);
            let spec = VesselMeshSpec {
                fused_weld: args.fused_weld,
                ..parse_preset(preset)?
            };
            crate::memory::check_generation(&spec)
                .map_err(|e| format!("--preset '{preset}': {e}"))?;
            vessel_mesh(&VesselGeometry::default(), &spec)?
        }
    };
    print!("{}", summary(&mesh));
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let path = args.out.join("mesh.vtu");
    write_mesh_vtu(&mesh, &path)?;
    println!("wrote {}", path.display());
    Ok(())
}

/// A human-readable summary of a mesh: counts, regions, bodies, sets.
pub fn summary(mesh: &Mesh) -> String {
    let mut s = format!(
        "mesh: {} nodes, {} triangles, {} interface elements\n",
        mesh.n_nodes(),
        mesh.n_triangles(),
        mesh.interfaces()
            .values()
            .map(|i| i.elements.len())
            .sum::<usize>()
    );
    for n in mesh.notices() {
        s += &format!("note: {n}\n");
    }
    let areas = mesh.areas();
    for (r, name) in mesh.region_names().iter().enumerate() {
        let (count, area) = mesh
            .element_regions()
            .iter()
            .zip(&areas)
            .filter(|(reg, _)| **reg == r)
            .fold((0, 0.0), |(c, a), (_, x)| (c + 1, a + x));
        s += &format!("  region {name:<12} {count:>8} triangles, area {area:.6e} m^2\n");
    }
    for b in mesh.bodies() {
        s += &format!("  body   {:<12} {:>8} nodes\n", b.name, b.nodes.len());
    }
    for (name, edges) in mesh.edge_sets() {
        s += &format!("  edges  {name:<12} {:>8} edges\n", edges.len());
    }
    for (name, i) in mesh.interfaces() {
        s += &format!(
            "  interface {name} ({} / {}): {} elements\n",
            i.bottom_set,
            i.top_set,
            i.elements.len()
        );
    }
    s
}

fn write_mesh_vtu(
    mesh: &Mesh,
    path: &std::path::Path,
) -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
    let quads: Vec<[usize; 4]> = mesh
        .interfaces()
        .values()
        .flat_map(|i| i.elements.iter().copied())
        .collect();
    let mut region: Vec<f64> = mesh.element_regions().iter().map(|&r| r as f64).collect();
    region.extend(std::iter::repeat_n(-1.0, quads.len()));
    let body: Vec<f64> = mesh.node_bodies().iter().map(|&b| b as f64).collect();
    write_vtu(
        path,
        &VtuPiece {
            points: mesh.nodes(),
            triangles: mesh.triangles(),
            quads: &quads,
            point_data: &[("body", Field::Scalars(&body))],
            cell_data: &[("region", Field::Scalars(&region))],
        },
    )?;
    Ok(())
}
