//! The `tecon` command.
//!
//! ```text
//! tecon vessel                                  # the published welded-vessel case
//! tecon mesh --preset paper --out tecon-out/mesh
//! tecon torsion --section ellipse:a=2,b=1
//! ```
//!
//! Every command that writes an output folder checks it first (writable,
//! tecon's own or `--force`), and after a successful run writes
//! `report.html` and the folder's manifest (see [`tecon_cli::outdir`]).
//! A closed pipe on stdout (`tecon mesh --preset 3 | head -1`) ends the
//! program quietly.

use std::path::Path;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use tecon_cli::outdir::OutDir;
use tecon_cli::report_html::{self, ReportInputs};
use tecon_cli::{case, cmdline, front, mesh_cmd, torsion, vessel};

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

/// Options every command that writes a folder has.
#[derive(clap::Args, Debug, Clone, Copy)]
struct FolderArgs {
    /// Write into an output folder that holds files tecon did not write
    /// (they are kept; without --force such a folder is refused).
    #[arg(long)]
    force: bool,
}

#[derive(clap::Args, Debug)]
struct VesselCmd {
    #[command(flatten)]
    args: vessel::VesselArgs,
    #[command(flatten)]
    folder: FolderArgs,
    /// Yield stress, Pa: report the regions where the von Mises stress exceeds it.
    #[arg(long = "yield", value_name = "PA", allow_hyphen_values = true)]
    yield_stress: Option<f64>,
}

#[derive(clap::Args, Debug)]
struct MeshCmd {
    #[command(flatten)]
    args: mesh_cmd::MeshArgs,
    #[command(flatten)]
    folder: FolderArgs,
}

#[derive(clap::Args, Debug)]
struct TorsionCmd {
    #[command(flatten)]
    args: torsion::TorsionArgs,
    #[command(flatten)]
    folder: FolderArgs,
}

#[derive(clap::Args, Debug)]
struct RunCmd {
    #[command(flatten)]
    args: case::RunArgs,
    #[command(flatten)]
    folder: FolderArgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// The welded monolayer vessel: cooling weld, thermoelastic contact, prestress.
    Vessel(VesselCmd),
    /// Generate the welded-vessel mesh (or read a Gmsh file), validate it and write VTK.
    Mesh(MeshCmd),
    /// Saint-Venant torsion of a prismatic bar by the wavelet boundary integral method.
    Torsion(TorsionCmd),
    /// Run a case file.
    Run(RunCmd),
}

type BoxErr = Box<dyn std::error::Error + Send + Sync>;

/// The command line as typed (for the manifest and the report), quoted where needed.
fn command_line() -> String {
    std::env::args()
        .skip(1)
        .map(|a| {
            if a.is_empty() || a.contains([' ', '\'', '"']) {
                format!("'{}'", a.replace('\'', "'\\''"))
            } else {
                a
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs `body` with the output folder `out` claimed first, then writes
/// `report.html` (when `report` is given, with the warnings `body` returns)
/// and the manifest.
fn in_folder(
    out: &Path,
    force: bool,
    report: Option<ReportInputs>,
    body: impl FnOnce() -> Result<Vec<String>, BoxErr>,
) -> Result<(), BoxErr> {
    let dir = OutDir::prepare(out, &command_line(), force)?;
    match body() {
        Ok(warnings) => {
            if let Some(mut r) = report {
                r.warnings.extend(warnings);
                report_html::write(out, &r).map_err(|e| format!("{}: {e}", out.display()))?;
            }
            dir.finish()?;
            Ok(())
        }
        Err(e) => {
            dir.abandon();
            Err(e)
        }
    }
}

fn inputs_of(args: &impl std::fmt::Debug) -> Vec<(String, String)> {
    // one row per option given a value, from the parsed arguments: options
    // left unset (None) are not inputs; values are shown without Rust's
    // quotes, and nested values (Some( … ), lists, tables) as their lines
    let text = format!("{args:#?}");
    let mut rows: Vec<(String, String)> = Vec::new();
    let mut open: Option<(String, String)> = None;
    for l in text.lines().skip(1).map(str::trim) {
        if let Some((k, v)) = open.as_mut() {
            if l == ")," || l == "]," || l == "}," {
                rows.push((std::mem::take(k), std::mem::take(v)));
                open = None;
            } else {
                if !v.is_empty() {
                    v.push(' ');
                }
                v.push_str(l.trim_end_matches(',').trim_matches('"'));
            }
            continue;
        }
        let Some((k, v)) = l.split_once(": ") else {
            continue;
        };
        let v = v.trim_end_matches(',');
        if v == "None" {
            continue;
        }
        if v.ends_with('(') || v.ends_with('[') || v.ends_with('{') {
            open = Some((k.to_string(), String::new()));
            continue;
        }
        rows.push((k.to_string(), v.trim_matches('"').to_string()));
    }
    rows
}

/// Which options with a default were given on the command line.
#[derive(Debug, Clone, Copy, Default)]
struct Given {
    /// `tecon vessel --layer-thickness`.
    layer_thickness: bool,
}

impl Given {
    fn of(matches: &clap::ArgMatches) -> Self {
        let on_command_line = |sub: &str, id: &str| {
            matches
                .subcommand_matches(sub)
                .and_then(|m| m.value_source(id))
                == Some(clap::parser::ValueSource::CommandLine)
        };
        Given {
            layer_thickness: on_command_line("vessel", "layer_thickness"),
        }
    }
}

fn run(cli: Cli, given: Given) -> Result<(), BoxErr> {
    match cli.command {
        Command::Vessel(c) => {
            cmdline::check_times(&c.args.times)?;
            vessel::check_combinations(&c.args, given.layer_thickness)?;
            if let Some(y) = c.yield_stress {
                cmdline::check_yield(y)?;
            }
            let out = c.args.out.clone();
            let report = ReportInputs {
                title: match c.args.layers {
                    Some(n) => format!("tecon vessel: the welded multilayer vessel ({n} layers)"),
                    None => "tecon vessel: the welded monolayer vessel".into(),
                },
                command: format!("tecon {}", command_line()),
                inputs: front::vessel_inputs(&c.args).unwrap_or_else(|| inputs_of(&c.args)),
                ..Default::default()
            };
            in_folder(&out, c.folder.force, Some(report), || {
                front::vessel(c.args, c.yield_stress)
            })
        }
        Command::Mesh(c) => {
            mesh_cmd::check(&c.args)?;
            let out = c.args.out.clone();
            in_folder(&out, c.folder.force, None, || {
                mesh_cmd::run(c.args).map(|_| Vec::new())
            })
        }
        Command::Torsion(c) => match c.args.out.clone() {
            Some(out) => {
                let report = ReportInputs {
                    title: format!("tecon torsion: {}", c.args.section),
                    command: format!("tecon {}", command_line()),
                    inputs: inputs_of(&c.args),
                    ..Default::default()
                };
                in_folder(&out, c.folder.force, Some(report), || torsion::run(c.args))
            }
            None => torsion::run(c.args).map(|_| ()),
        },
        Command::Run(c) => {
            let out = c
                .args
                .out
                .clone()
                .unwrap_or_else(|| case::default_out(&c.args.case));
            let source = std::fs::read_to_string(&c.args.case)
                .ok()
                .map(|t| (c.args.case.display().to_string(), t));
            let report = ReportInputs {
                title: format!("tecon run {}", c.args.case.display()),
                command: format!("tecon {}", command_line()),
                source,
                ..Default::default()
            };
            let mut args = c.args;
            args.out = Some(out.clone());
            in_folder(&out, c.folder.force, Some(report), || {
                case::run(args).map(|_| Vec::new())
            })
        }
    }
}

fn main() {
    cmdline::quiet_on_broken_pipe();
    let matches = Cli::command().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| {
        // as Cli::parse
        e.format(&mut Cli::command()).exit()
    });
    if let Err(e) = run(cli, Given::of(&matches)) {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}
