//! Error control: a starting resolution from the geometry, refinement by
//! doubling n until two successive resolutions agree on J, τ_max, the shear
//! centre and the warping constant Γ, and the
//! estimated errors of the reported (finer) result.
//!
//! The estimate of a result at n is the difference from the result at n/2:
//! for a method converging like n^{−k} with k ≥ 1 that difference bounds the
//! error of the n/2 result up to the factor 1/(1 − 2^{−k}), and so bounds the
//! error of the n result with room to spare (2^{−k}·(1 − 2^{−k})^{−1} ≤ 1).
//! It is an *estimate*, not a proof: pre-asymptotic agreement of two wrong
//! results is possible, which is why the starting resolution comes from the
//! geometry (pieces, corners, slenderness) and never falls below it.

use crate::error::SolveError;
use crate::geometry::Section;
use crate::solve::{MaxShear, Method, Options, TorsionSolution, solve};
use crate::warping::Warping;

/// One solved resolution: the solution, its τ_max and its warping outputs.
type Solved = (TorsionSolution, MaxShear, Warping);

fn solve_level(section: &Section, opts: &Options) -> Result<Solved, SolveError> {
    let sol = solve(section, opts)?;
    let ms = sol.max_shear();
    let w = sol.warping();
    Ok((sol, ms, w))
}

/// One resolution of a refinement sequence.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Level {
    /// number of unknowns per boundary curve
    pub n: usize,
    /// torsional rigidity J at this n
    pub torsional_rigidity: f64,
    /// τ_max at this n (None when singular)
    pub max_shear_stress: Option<f64>,
    /// shear centre at this n
    pub shear_centre: [f64; 2],
    /// warping constant Γ at this n
    pub warping_constant: f64,
}

/// A result with its error estimate.
#[derive(Clone, Debug)]
pub struct Controlled {
    /// the finest solution computed
    pub solution: TorsionSolution,
    /// its τ_max
    pub max_shear: MaxShear,
    /// estimated relative error of J: |J(n) − J(n/2)| / |J(n)|
    pub j_error: f64,
    /// estimated relative error of τ_max (None when τ_max is singular)
    pub tau_error: Option<f64>,
    /// warping function, shear centre and warping constant of the finest solution
    pub warping: Warping,
    /// estimated error of the shear centre: |x_S(n) − x_S(n/2)| / r_g, with
    /// r_g = √(I_p/A) the polar radius of gyration
    pub shear_centre_error: f64,
    /// estimated relative error of Γ: |Γ(n) − Γ(n/2)| / max(|Γ(n)|, 10⁻⁶ I_p²/A)
    /// (the floor keeps sections with Γ = 0, circles and tubes, measurable)
    pub warping_error: f64,
    /// the requested relative tolerance
    pub tol: f64,
    /// every estimate (J, τ_max, shear centre, Γ) is within the tolerance
    pub converged: bool,
    /// every resolution computed, coarse to fine
    pub levels: Vec<Level>,
    /// why the result may not be trusted, if it may not
    pub warnings: Vec<String>,
}

/// Smallest n a method accepts for `opts` (a power of two for Daubechies).
fn min_n(opts: &Options) -> usize {
    match opts.method {
        Method::Daubechies => crate::daubechies::Daubechies::new(opts.wavelet_order)
            .map(|w| w.min_n())
            .unwrap_or(8)
            .max(16),
        _ => 16,
    }
}

/// Starting resolution from the geometry: every piece of a multi-piece
/// boundary gets about 16 nodes (each panel holds at least half its uniform
/// share n/(2m), and a graded panel needs nodes in both corner clusters), and
/// slender sections get about 8 nodes per mean thickness 2A/P along each curve.
pub fn starting_n(section: &Section, opts: &Options) -> usize {
    let mut n = min_n(opts).max(64);
    for curve in section.curves() {
        let m = curve.pieces.len();
        if m > 1 || curve.junctions.iter().any(|j| !j.is_smooth()) {
            n = n.max(32 * m);
        }
    }
    // mean thickness 2A/P (a strip of width t has A ≈ tP/2, P the total perimeter):
    // about 8 nodes per thickness along each curve, so that the near-singular
    // interaction of the two faces of a thin wall is resolved
    let thick = 2.0 * section.area / section.total_perimeter();
    for curve in section.curves() {
        n = n.max((8.0 * curve.perimeter() / thick).min(1e9) as usize);
    }
    n.next_power_of_two()
}

/// Largest n the dense solvers are run at by default (a dense order-4096 solve takes seconds).
pub const DEFAULT_N_MAX: usize = 4096;

fn rel(a: f64, b: f64) -> f64 {
    let s = a.abs().max(b.abs());
    if s == 0.0 { 0.0 } else { (a - b).abs() / s }
}

fn level(s: &Solved) -> Level {
    Level {
        n: s.0.options.n,
        torsional_rigidity: s.0.torsional_rigidity,
        max_shear_stress: s.1.value,
        shear_centre: s.2.shear_centre,
        warping_constant: s.2.warping_constant,
    }
}

fn finish(
    coarse: Solved,
    fine: Solved,
    tol: f64,
    levels: Vec<Level>,
    reached_cap: bool,
) -> Controlled {
    let j_error = rel(fine.0.torsional_rigidity, coarse.0.torsional_rigidity);
    let tau_error = match (fine.1.value, coarse.1.value) {
        (Some(a), Some(b)) => Some(rel(a, b)),
        _ => None,
    };
    let sec = &fine.0.section;
    let ip = sec.polar_moment();
    let rg = (ip / sec.area).sqrt();
    let (a, b) = (fine.2.shear_centre, coarse.2.shear_centre);
    let shear_centre_error = (a[0] - b[0]).hypot(a[1] - b[1]) / rg;
    let g_scale = fine.2.warping_constant.abs().max(1e-6 * ip * ip / sec.area);
    let warping_error = (fine.2.warping_constant - coarse.2.warping_constant).abs() / g_scale;
    let converged = j_error <= tol
        && tau_error.is_none_or(|e| e <= tol)
        && shear_centre_error <= tol
        && warping_error <= tol;
    let mut warnings = Vec::new();
    if !converged {
        let n = fine.0.options.n;
        let mut w = format!(
            "not converged to the tolerance {tol:.1e} at n = {n}: estimated relative error of J {j_error:.1e}"
        );
        if let Some(t) = tau_error {
            w += &format!(", of τ_max {t:.1e}");
        }
        w += &format!(", of the shear centre {shear_centre_error:.1e}, of Γ {warping_error:.1e}");
        if reached_cap {
            w += " (the largest n allowed was reached)";
        }
        warnings.push(w);
    }
    Controlled {
        solution: fine.0,
        max_shear: fine.1,
        j_error,
        tau_error,
        warping: fine.2,
        shear_centre_error,
        warping_error,
        tol,
        converged,
        levels,
        warnings,
    }
}

/// Solves at `opts.n` and at `opts.n / 2` and reports the difference as the
/// error estimate of the result at `opts.n` (the expert path, `--n`).
pub fn solve_with_estimate(
    section: &Section,
    opts: &Options,
    tol: f64,
) -> Result<Controlled, SolveError> {
    let fine = solve_level(section, opts)?;
    let half = opts.n / 2;
    if half < min_n(opts) {
        return Err(SolveError::BadN {
            n: opts.n,
            reason: format!(
                "the error estimate needs a solve at n/2 = {half}; use n ≥ {}",
                2 * min_n(opts)
            ),
        });
    }
    let coarse = solve_level(section, &Options { n: half, ..*opts })?;
    let levels = vec![level(&coarse), level(&fine)];
    Ok(finish(coarse, fine, tol, levels, false))
}

/// Refines from [`starting_n`] (or `opts.n` if larger) by doubling until J and
/// τ_max at n and n/2 agree to the relative tolerance `tol`, or `n_max` is
/// reached (then `converged` is false and a warning says so).
pub fn solve_to_tolerance(
    section: &Section,
    opts: &Options,
    tol: f64,
    n_max: usize,
) -> Result<Controlled, SolveError> {
    if !(tol > 0.0 && tol < 1.0) {
        return Err(SolveError::BadN {
            n: opts.n,
            reason: format!("the tolerance must lie in (0, 1), got {tol:e}"),
        });
    }
    // the oversampled Shannon method stores its transformed kernel densely
    let n_max = if opts.method == Method::Shannon {
        n_max.min(crate::shannon::MAX_N)
    } else {
        n_max
    };
    // the largest n whose dense solve fits in the memory available now
    let curves = section.curves().len();
    let requested_max = n_max;
    let mut n_max = n_max;
    while n_max / 2 >= min_n(opts) && crate::memory::check(opts.method, curves, n_max).is_err() {
        n_max /= 2;
    }
    let memory_note = (n_max < requested_max).then(|| {
        format!(
            "at most n = {n_max} per curve fits in the memory available (n = {} on {curves} curve(s) would need about {:.1} GB)",
            2 * n_max,
            crate::memory::dense_bytes(opts.method, curves, 2 * n_max) as f64 / 1e9
        )
    });
    let n0 = starting_n(section, opts).max(opts.n);
    let mut start_warning = None;
    if n0 > n_max {
        start_warning = Some(format!(
            "the geometry asks for n ≥ {n0} (pieces, slenderness) but at most n = {n_max} is allowed"
        ));
    }
    let mut n = (n0 / 2).min(n_max / 2).max(min_n(opts));
    let mut prev: Option<Solved> = None;
    let mut levels = Vec::new();
    let with_start = |mut c: Controlled| {
        if let Some(w) = &start_warning {
            c.warnings.push(w.clone());
        }
        if let (false, Some(w)) = (c.converged, &memory_note) {
            c.warnings.push(w.clone());
        }
        c
    };
    loop {
        let cur = solve_level(section, &Options { n, ..*opts })?;
        levels.push(level(&cur));
        if let Some(p) = prev.take() {
            let at_cap = 2 * n > n_max;
            let c = finish(p, cur.clone(), tol, levels.clone(), at_cap);
            if c.converged || at_cap {
                return Ok(with_start(c));
            }
        } else if 2 * n > n_max {
            // cannot refine at all: estimate from n/2
            let coarse = solve_level(section, &Options { n: n / 2, ..*opts })?;
            levels.insert(0, level(&coarse));
            return Ok(with_start(finish(coarse, cur, tol, levels, true)));
        }
        prev = Some(cur);
        n *= 2;
    }
}
