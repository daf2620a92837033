//! Typed errors of the elastic crate.

use tecon_fem::FemError;
use tecon_mesh::MeshError;

/// One Newton iteration, for histories in reports and errors.
#[derive(Debug, Clone, PartialEq)]
pub struct IterationRecord {
    /// Newton pass of the increment (1-based; each outer update of the
    /// multipliers or friction limits starts a new pass).
    pub pass: usize,
    /// Iteration number within the pass (0 = the predictor).
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
    /// Round-off floor of the residual, relative to the same reference:
    /// `ε · ‖ |K_t| |u| + |f_ext| ‖` times a safety factor. A residual at
    /// this level cannot be reduced by more iterations (stiff penalties
    /// make it large), so the iteration converges at the larger of the
    /// tolerance and this floor.
    pub floor: f64,
    /// True when `floor` is an upper bound of the floor (below the
    /// tolerance, where the exact value changes nothing) rather than the
    /// floor itself.
    pub floor_is_bound: bool,
    /// Points the step assumed open (ahead of an opening front, or open a
    /// little further along a cut-short coupled step), sticking (reversed
    /// slips, sticking or reversed at the end of a cut-short full step),
    /// slipping (ahead of a slip front) and closed (closed a little
    /// further along a cut-short coupled step): see the solver's
    /// predictions; all 0 for an exact Newton step.
    pub predicted: [usize; 4],
    /// True for a predicted step that was tried and discarded (a linear
    /// solve that did not move the iterate).
    pub rejected: bool,
    /// True for the last iterate of a pass that stopped before its full
    /// tolerance because an outer update follows (see
    /// `SolverOptions::pass_forcing`).
    pub inexact: bool,
}

impl std::fmt::Display for IterationRecord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "it {:>2}: |R|/ref = {:.3e} (floor {}{:.1e}), |du|/|u| = {:.3e}, step {:.3}, open/stick/slip = {}/{}/{}, changed {}",
            self.iteration,
            self.residual,
            if self.floor_is_bound { "≤ " } else { "" },
            self.floor,
            self.correction,
            self.step,
            self.status[0],
            self.status[1],
            self.status[2],
            self.changed
        )?;
        let parts: Vec<String> = self
            .predicted
            .iter()
            .zip(["open", "stick", "slip", "close"])
            .filter(|(n, _)| **n > 0)
            .map(|(n, what)| format!("{n} to {what}"))
            .collect();
        if !parts.is_empty() {
            write!(
                f,
                ", predicted {}{}",
                parts.join(", "),
                if self.rejected { " (rejected)" } else { "" }
            )?;
        }
        if self.inexact {
            write!(f, ", inexact stop (an outer update follows)")?;
        }
        Ok(())
    }
}

/// The iterations one a line, with a header whenever a new pass starts.
fn format_history(h: &[IterationRecord]) -> String {
    let mut out = String::new();
    let mut pass = usize::MAX;
    for r in h {
        if r.pass != pass {
            pass = r.pass;
            out.push_str(&format!("\n  pass {pass}:"));
        }
        out.push_str(&format!("\n    {r}"));
    }
    out
}

fn format_attempts(a: &[String]) -> String {
    if a.is_empty() {
        return String::new();
    }
    let lines: String = a.iter().map(|x| format!("\n  {x}")).collect();
    format!("; attempts cut back before:{lines}")
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
    /// The contact converged with every interface point that held a body
    /// open: nothing holds it, and its displacement is arbitrary.
    #[error(
        "the contact solve left {description} held by nothing (normalised energy {energy:.2e}): every interface point that could hold it is open, so its displacement is arbitrary; support it (a fixed point or a symmetry condition), or load it so that it stays in contact"
    )]
    Floating {
        /// Which bodies and modes are free, e.g. "body 'ring_in' in x-translation".
        description: String,
        /// Normalised energy of the free mode (≈ 0).
        energy: f64,
    },
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
    #[error("Newton did not converge in increment {number} (load fraction {from:.4} → {fraction:.4}, increment {increment:.3e}): {reason}{}; iteration history of the last attempt:{}", format_attempts(.attempts), format_history(.history))]
    NotConverged {
        /// Increment number within the `advance` call (1-based: the
        /// converged increments before it, plus one).
        number: usize,
        /// Load fraction reached before the failed increment (the last
        /// converged one).
        from: f64,
        /// Load fraction the failed increment aimed at.
        fraction: f64,
        /// Size of the smallest increment tried.
        increment: f64,
        /// Why it stopped.
        reason: String,
        /// Every earlier attempt of this increment that failed and was cut
        /// back: size, fraction, reason and its last iterations.
        attempts: Vec<String>,
        /// Iterations of the last attempt, all of its passes.
        history: Vec<IterationRecord>,
    },
}
