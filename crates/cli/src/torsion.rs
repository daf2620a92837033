//! `tecon torsion`: filled by the torsion issue.

/// Arguments of `tecon torsion`.
#[derive(clap::Args, Debug)]
pub struct TorsionArgs {}

/// Runs `tecon torsion`.
pub fn run(_args: TorsionArgs) -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
    Err("tecon torsion is not implemented yet".into())
}
