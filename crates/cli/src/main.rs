//! The `tecon` command.
//!
//! ```text
//! tecon vessel                                  # the published welded-vessel case
//! tecon mesh --preset paper --out tecon-out/mesh
//! tecon torsion --section ellipse:a=2,b=1
//! ```

use clap::{Parser, Subcommand};
use tecon_cli::{case, mesh_cmd, torsion, vessel};

#[derive(Parser, Debug)]
#[command(
    name = "tecon",
    version,
    about = "Thermoelastic contact of layered vessels, and wavelet-BEM torsion"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// The welded monolayer vessel: cooling weld, thermoelastic contact, prestress.
    Vessel(vessel::VesselArgs),
    /// Generate the welded-vessel mesh (or read a Gmsh file), validate it and write VTK.
    Mesh(mesh_cmd::MeshArgs),
    /// Saint-Venant torsion of a prismatic bar by the wavelet boundary integral method.
    Torsion(torsion::TorsionArgs),
    /// Run a case file.
    Run(case::RunArgs),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Vessel(args) => vessel::run(args),
        Command::Mesh(args) => mesh_cmd::run(args),
        Command::Torsion(args) => torsion::run(args),
        Command::Run(args) => case::run(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}
