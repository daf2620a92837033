//! The `tecon` command.
//!
//! ```text
//! tecon mesh --preset paper --out tecon-out/mesh
//! tecon torsion --section ellipse:a=2,b=1
//! ```

mod mesh_cmd;
mod plot;
mod torsion;

use clap::{Parser, Subcommand};

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
    /// Generate the welded-vessel mesh (or read a Gmsh file), validate it and write VTK.
    Mesh(mesh_cmd::MeshArgs),
    /// Saint-Venant torsion of a prismatic bar by the wavelet boundary integral method.
    Torsion(torsion::TorsionArgs),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Mesh(args) => mesh_cmd::run(args),
        Command::Torsion(args) => torsion::run(args),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}
