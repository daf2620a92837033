//! Typed errors of the elastic crate.

use tecon_fem::FemError;
use tecon_mesh::MeshError;

/// One Newton iteration, for histories in reports and errors.
#[derive(Debug, Clone, PartialEq)]
pub struct IterationRecord {
    /// Iteration number (0 = the predictor).
    pub iteration: usize,
    /// ‖R‖ / reference force.
    pub residual: f64,
    /// ‖Δu‖ / max(‖u‖, reference length·1e-12) of the correction applied after this iterate.
    pub correction: f64,
    /// Line-search step length used.
    pub step: f64,
    /// Interface points open / stick / slip.
    pub status: [usize; 3],
    /// Points whose status changed since the previous iterate.
    pub changed: usize,
}

impl std::fmt::Display for IterationRecord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "it {:>2}: |R|/ref = {:.3e}, |du|/|u| = {:.3e}, step {:.3}, open/stick/slip = {}/{}/{}, changed {}",
            self.iteration,
            self.residual,
            self.correction,
            self.step,
            self.status[0],
            self.status[1],
            self.status[2],
            self.changed
        )
    }
}

fn format_history(h: &[IterationRecord]) -> String {
    h.iter().map(|r| format!("\n  {r}")).collect()
}

/// Everything that can go wrong in setting up or solving an elastic model.
#[derive(Debug, thiserror::Error)]
pub enum ElasticError {
    /// A mesh lookup failed (unknown region, edge set, interface …).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Assembly or linear algebra failed.
    #[error(transparent)]
    Fem(#[from] FemError),
    /// A material parameter out of range.
    #[error("material of region '{region}': {message}")]
    Material {
        /// Region.
        region: String,
        /// What is wrong.
        message: String,
    },
    /// A region has no material.
    #[error("region '{0}' has no material")]
    MissingMaterial(String),
    /// An interface element that cannot be built.
    #[error("interface '{interface}', element {element}: {message}")]
    Interface {
        /// Interface name.
        interface: String,
        /// Element index within it.
        element: usize,
        /// What is wrong.
        message: String,
    },
    /// An input array of the wrong length or with bad values.
    #[error("{what}: {message}")]
    Input {
        /// Which input.
        what: String,
        /// What is wrong.
        message: String,
    },
    /// Newton did not converge even after cutting the increment.
    #[error("Newton did not converge at load fraction {fraction:.4} (increment {increment:.3e}): {reason}; iteration history:{}", format_history(.history))]
    NotConverged {
        /// Load fraction of the increment that failed.
        fraction: f64,
        /// Size of the smallest increment tried.
        increment: f64,
        /// Why it stopped.
        reason: String,
        /// Iterations of the last attempt.
        history: Vec<IterationRecord>,
    },
}
