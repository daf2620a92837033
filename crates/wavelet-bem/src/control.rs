//! Error control: a starting resolution from the geometry, refinement until
//! the estimated errors of J, τ_max, the shear centre and the warping
//! constant Γ meet the tolerance, and those estimates for the reported
//! (finest) result.
//!
//! **Estimates.** With two rungs n′ = n/2 < n, the estimate of a result at n
//! is its difference d from the result at n′: for a method converging like
//! n^{−k} with k ≥ 1 that difference bounds the error of the n′ result up to
//! the factor 1/(1 − 2^{−k}), and so bounds the error of the n result with
//! room to spare. With three rungs (n/4, n/2, n; Daubechies only) the
//! observed ratio ρ = d_n / d_{n/2} of successive differences, when at most
//! ¼, scales it: e_n ≈ 2 d_n ρ_e/(1 − ρ_e) with ρ_e = max(ρ, 2^{−min(2N, p, 8)})
//! for J, and max(ρ, 2^{−(min(2N, p, 8) − 1)}) for τ_max and for the warping
//! outputs (shear centre, Γ), which follow the warping function ω on the
//! boundary, a point value like τ (Aitken's estimate with a safety factor 2, never assuming a faster rate
//! than the graded corners allow, see [`rate_floor`]), and never below
//! min(d_n, 1e-12) nor N ε (round-off). The ladder starts at n0/4 so that the
//! estimate at the geometry's n0 already has three rungs. It is an
//! *estimate*, not a proof: pre-asymptotic agreement of two wrong results is
//! possible, which is why the starting resolution comes from the geometry
//! (pieces, corners, slenderness) and the result is never taken below it;
//! `tests/hollow_and_control.rs` checks that it bounds the true error on
//! every section with a closed form at tolerances 1e-6, 1e-8 and 1e-10.
//!
//! **Fewer rungs.** n doubles from rung to rung. The last two rungs cost
//! nearly everything (a dense solve costs n³, so the last one 8 × the one
//! before), and jumping by 4 when the observed order predicted that 2n would
//! still miss the tolerance was measured to cost more than it saves: on the
//! groove and the hexagon at 1e-10 the prediction (pre-asymptotic orders of
//! 1–6) skipped n = 1024, which would have agreed with 512, and went to 2048
//! (1.2–1.3 s instead of 0.3 s). The warping function (shear centre, Γ:
//! n² work with logarithms) is computed only once the estimates of J and
//! τ_max meet the tolerance, and only for the rungs of that estimate.

use std::borrow::Cow;

use crate::error::SolveError;
use crate::geometry::Section;
use crate::solve::{MaxShear, Method, Options, TorsionSolution, solve};
use crate::warping::Warping;

/// The τ the refinement and the `converged` flag follow: τ_max; for a
/// singular section the largest value away from its singular points
/// ([`MaxShear::away`]) only when the distance was given
/// ([`Options::corner_distance`]). By default that value is reported with
/// its estimate but not followed: on thin walls it converges far more
/// slowly than J (the sectionproperties I: n = 4096 and 4.1 s against
/// n = 512 and 0.26 s for J, Γ and the shear centre at 1e-8).
fn followed(m: &MaxShear, opts: &Options) -> Option<f64> {
    if m.singular && opts.corner_distance.is_none() {
        None
    } else {
        m.controlled()
    }
}

/// One solved resolution: the solution, its τ_max (None: not computed, a
/// singular τ_max at a rung that is not reported) and its warping outputs.
type Solved = (TorsionSolution, Option<MaxShear>, Warping);

/// A resolution of the ladder whose warping outputs are computed on demand.
struct Rung {
    sol: TorsionSolution,
    /// τ_max, or for a singular section (a re-entrant corner or an inward
    /// cusp, where τ is infinite) the largest value away from its singular
    /// points, which the control follows instead
    ms: Option<MaxShear>,
    warp: Option<Warping>,
}

impl Rung {
    fn new(section: &Section, opts: &Options) -> Result<Rung, SolveError> {
        let sol = solve(section, opts)?;
        let ms = Some(sol.max_shear());
        Ok(Rung {
            sol,
            ms,
            warp: None,
        })
    }
    /// The τ the refinement follows (see [`followed`]).
    fn tau(&self) -> Option<f64> {
        self.ms.and_then(|m| followed(&m, &self.sol.options))
    }
    /// Computes the warping outputs if not done yet; records them in `level`.
    fn with_warping(&mut self, level: &mut Level) {
        let w = self.warp.get_or_insert_with(|| self.sol.warping());
        level.shear_centre = Some(w.shear_centre);
        level.warping_constant = Some(w.warping_constant);
    }
    fn solved(&self) -> Solved {
        let warp = self.warp.clone().unwrap_or_else(|| self.sol.warping());
        (self.sol.clone(), self.ms, warp)
    }
}

fn solve_level(section: &Section, opts: &Options) -> Result<Solved, SolveError> {
    let sol = solve(section, opts)?;
    let ms = sol.max_shear();
    let w = sol.warping();
    Ok((sol, Some(ms), w))
}

/// One resolution of a refinement sequence.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Level {
    /// number of unknowns per boundary curve
    pub n: usize,
    /// torsional rigidity J at this n
    pub torsional_rigidity: f64,
    /// τ_max at this n; for a singular section the largest value away
    /// from its singular points ([`MaxShear::away`])
    pub max_shear_stress: Option<f64>,
    /// shear centre at this n (None: not computed, J or τ_max of this
    /// resolution did not yet agree with a neighbour)
    pub shear_centre: Option<[f64; 2]>,
    /// warping constant Γ at this n (None: not computed), as reported:
    /// max(Γ, 0) in [`Controlled::levels`]
    pub warping_constant: Option<f64>,
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
    /// estimated relative error of τ_max, or for a singular section of its
    /// value away from the singular points (None when it has none)
    pub tau_error: Option<f64>,
    /// warping function, shear centre and warping constant of the finest
    /// solution, as reported ([`Warping::reported`]: Γ ≥ 0)
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
    /// the resolutions the estimates come from, coarse to fine: two (the
    /// difference of the last two) or three (that difference scaled by the
    /// observed rate of convergence, see [`rate_floor`])
    pub estimated_from: Vec<usize>,
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
/// slender sections with corners get about 8 nodes per mean thickness 2A/P
/// along each curve (4 on curves without grading for Shannon and Nyström;
/// none for the Daubechies method, whose estimates resolve smooth walls).
pub fn starting_n(section: &Section, opts: &Options) -> usize {
    starting_nodes(section, opts).next_power_of_two()
}

/// [`starting_n`] before it is rounded up to a rung of the ladder.
fn starting_nodes(section: &Section, opts: &Options) -> usize {
    let mut n = min_n(opts).max(64);
    for curve in section.curves() {
        let m = curve.pieces.len();
        if curve.nearly_smooth_polygon() {
            // arc length, no grading: about one node per edge
            n = n.max(m);
        } else if m > 1 || curve.junctions.iter().any(|j| !j.is_smooth()) {
            n = n.max(32 * m);
        }
    }
    // Mean thickness 2A/P (a strip of width t has A ≈ tP/2, P the total
    // perimeter): nodes per thickness along each curve, so that the
    // near-singular interaction of the two faces of a thin wall is resolved
    // (error about e^{−2πd/h} for a wall d thick and node spacing h). Graded
    // panels have twice the mean spacing in their middle: 8 nodes per
    // thickness. Curves without grading (tubes, ellipses) need no floor with
    // the Daubechies method: its three-rung estimates see the thin-wall
    // error, which falls exponentially from rung to rung. Measured without
    // the floor (it was 4 per thickness), at 1e-6, 1e-8 and 1e-10: every
    // estimate bounds the true error of J (and of Γ where there is one) on
    // the ellipses 1 × 0.01 … 0.2, the tubes 1/0.9 … 1/0.99 and four
    // eccentric thin tubes (thinnest walls 0.01 … 0.05); the ellipses and eccentric
    // tubes climb to the same n as before (their estimates set it), and the
    // concentric tubes stop at n = 128, exact to 3e-14 (1/0.99: 5.9 → 0.02 s).
    let mean_wall = 2.0 * section.area / section.total_perimeter();
    let graded = section.curves().iter().any(|c| c.any_graded());
    // the corner zones follow each piece's own wall where some wall is much
    // thinner than the mean (see `zone_walls`): the floor then counts nodes
    // per thickness of the thinnest wall
    let walls = match opts.method {
        Method::Daubechies if opts.corner_zones => crate::grading::zone_walls(section),
        _ => None,
    };
    let thick = walls.as_ref().map_or(mean_wall, |w| {
        w.iter().flatten().copied().fold(mean_wall, f64::min)
    });
    // long graded panels of thin-walled sections with re-entrant corners
    // have corner zones and the mean spacing in their middle: 4 per thickness
    let zoned = walls.as_ref().is_some_and(|w| {
        section
            .curves()
            .iter()
            .zip(w)
            .any(|(c, wc)| crate::grading::Parametrisation::would_zone(c, wc))
    });
    let per_thickness = match (graded, opts.method) {
        (true, _) if zoned => 4.0,
        (true, _) => 8.0,
        (false, Method::Daubechies) => 0.0,
        (false, _) => 4.0,
    };
    for curve in section.curves() {
        n = n.max((per_thickness * curve.perimeter() / thick).min(1e9) as usize);
    }
    n
}

/// The odd factor q of the ladder's resolutions n = q 2^j: the largest odd
/// d > 1 dividing the number of pieces of the outer boundary such that the
/// nodes at n = 64 d are turned onto themselves by a rotation whose order
/// is a multiple of d (a regular 25-gon: 25, so that a shift by n/25
/// nodes is its rotation by 2π/25 and the system folds to order n/25 or
/// less; see [`crate::symmetry`] and [`Parametrisation::exact_for`]); 1
/// otherwise, and always for other methods than the dense Daubechies one
/// or with `opts.symmetry` off. The Daubechies Galerkin method takes any
/// even n; powers of two fold only by rotations of order 2, 4, 8, ….
///
/// [`Parametrisation::exact_for`]: crate::grading::Parametrisation::exact_for
pub fn rung_base(section: &Section, opts: &Options) -> usize {
    if !crate::solve::may_fold(opts) {
        return 1;
    }
    let outer = section.curves()[0];
    // nearly flat polygons are parametrised by arc length, never exactly
    if outer.nearly_smooth_polygon() {
        return 1;
    }
    let pieces = outer.pieces.len();
    (3..=pieces)
        .rev()
        .filter(|d| d % 2 == 1 && pieces.is_multiple_of(*d))
        .find(|&d| {
            let n = 64 * d;
            crate::solve::symmetry_order(section, &Options { n, ..*opts }).is_multiple_of(d)
        })
        .unwrap_or(1)
}

/// `section` as the ladder solves it with `opts`: a
/// [`Section::flat_polygon`] (a 2000-gon) whose turn by 2π/N, N its number
/// of edges, maps its graded nodes onto themselves is solved with every
/// vertex graded ([`Section::with_flat_vertices_graded`]): the system folds
/// to n/N unknowns, one edge, and the vertices are resolved like those of
/// any polygon (the regular 2000-gon reaches 1e-10 at n = 128 000, 64
/// nodes per edge, instead of being flagged with τ_max about 7e-4 off at
/// n = 2048). Otherwise (no such rotation, holes, `--no-symmetry`, other
/// methods) `section` itself: grading 2000 vertices of a system solved
/// whole would take n ≥ 64 000, and it keeps the arc-length
/// parametrisation and the floors of [`flat_vertex_floors`]. So does a run
/// whose largest n, `largest`, is below the ladder's start on the graded
/// vertices, 32 nodes per edge: at n = 2048 (one node per edge) the graded
/// 2000-gon's τ_max was 2.3e-4 off while n and n/2 agreed to 7.4e-6, an
/// estimate that arc length's floors do not understate.
pub fn prepared<'a>(section: &'a Section, opts: &Options, largest: usize) -> Cow<'a, Section> {
    if !crate::solve::may_fold(opts)
        || !section.holes.is_empty()
        || !section.nearly_smooth_polygon()
    {
        return Cow::Borrowed(section);
    }
    let m = section.pieces.len();
    if largest < 32 * m || !section.pieces_of_equal_length() {
        return Cow::Borrowed(section);
    }
    let graded = section.with_flat_vertices_graded();
    // 16 nodes per edge: every edge a panel, the breaks exactly k/N; the
    // ladder starts at 32 per edge (`starting_nodes`), which must be allowed
    let n = 16 * m;
    if 2 * n <= crate::solve::FOLDED_N_MAX
        && crate::solve::symmetry_order(&graded, &Options { n, ..*opts }).is_multiple_of(m)
    {
        Cow::Owned(graded)
    } else {
        Cow::Borrowed(section)
    }
}

/// The resolutions q 2^j of a ladder with odd factor q.
#[derive(Clone, Copy)]
struct Rungs {
    q: usize,
}

impl Rungs {
    /// The smallest rung ≥ n.
    fn at_least(self, n: usize) -> usize {
        let mut r = self.q;
        while r < n {
            r *= 2;
        }
        r
    }
    /// The largest rung ≤ n (the smallest rung if none is).
    fn at_most(self, n: usize) -> usize {
        let r = self.at_least(n);
        if r > n && r > self.q { r / 2 } else { r }
    }
}

/// Largest n the dense solvers are run at by default (a dense order-4096 solve takes seconds).
pub const DEFAULT_N_MAX: usize = 4096;

/// The default largest n for `section`: the largest rung (see
/// [`rung_base`]) up to [`DEFAULT_N_MAX`], or beyond where the system is
/// folded by a rotational symmetry ([`crate::symmetry`]) so that its order
/// per curve, n/k, stays within [`DEFAULT_N_MAX`] and its assembly within
/// [`DEFAULT_WORK`]: up to 16 384 (the regular 64-gon reaches 1e-10 at
/// n = 8192, a folded order of 128; the 96-gon at 12 288), and up to
/// [`crate::solve::FOLDED_N_MAX`] for a polygon graded at thousands of
/// flat vertices ([`prepared`]; the 2000-gon: 256 000).
pub fn default_max_n(section: &Section, opts: &Options) -> usize {
    let prepared = prepared(section, opts, crate::solve::FOLDED_N_MAX);
    let section = &*prepared;
    let rungs = Rungs {
        q: rung_base(section, opts),
    };
    // a polygon graded at thousands of flat vertices folds by its number of
    // edges N on every rung with 16 nodes per edge or more (tested at
    // 16 N by `prepared`, and again by each solve): the largest rung whose
    // folded assembly stays within the work bound (the rungs below 16 per
    // edge fold by less and are never the top)
    if section.flat_vertices_graded() {
        let edges = section.pieces.len();
        let mut n = rungs.at_most(crate::solve::FOLDED_N_MAX);
        while n / 2 >= 16 * edges && (n / edges > DEFAULT_N_MAX || n / edges * n > DEFAULT_WORK) {
            n /= 2;
        }
        return n;
    }
    let mut n = rungs.at_most(DEFAULT_N_MAX);
    // a rotation maps the pieces of a curve of several onto each other: its
    // order divides their number, which bounds n/k from below (no need to
    // test the nodes of an n whose work would be too large whatever k)
    let pieces = section.pieces.len();
    let most = |n: usize| if pieces > 1 { pieces } else { n };
    while 2 * n <= DEFAULT_FOLDED_N_MAX && 2 * n / most(2 * n) * 2 * n <= DEFAULT_WORK && {
        let order = 2 * n / crate::solve::symmetry_order(section, &Options { n: 2 * n, ..*opts });
        order <= DEFAULT_N_MAX && order * 2 * n <= DEFAULT_WORK
    } {
        n *= 2;
    }
    n
}

/// The default largest n of a folded section without flat graded vertices.
const DEFAULT_FOLDED_N_MAX: usize = 1 << 14;

/// Largest n/k × n (the logarithms of a folded assembly per curve pair)
/// of the default largest n: that of n = 16 384 folded to 4096, about a
/// second (the regular 2000-gon may go to n = 256 000, folded to 128).
const DEFAULT_WORK: usize = 4096 * 16384;

/// The scale Γ's error is relative to: max(|Γ|, 10⁻⁶ I_p²/A) (Γ vanishes
/// on circles and concentric tubes).
fn gamma_scale(sec: &Section, gamma: f64) -> f64 {
    let ip = sec.polar_moment();
    gamma.abs().max(1e-6 * ip * ip / sec.area)
}

/// The round-off of Γ's double integral relative to [`gamma_scale`]: a
/// floor no finer n lowers.
fn gamma_floor(sec: &Section, w: &Warping) -> f64 {
    w.round_off / gamma_scale(sec, w.warping_constant)
}

fn rel(a: f64, b: f64) -> f64 {
    let s = a.abs().max(b.abs());
    if s == 0.0 { 0.0 } else { (a - b).abs() / s }
}

fn level(s: &Solved) -> Level {
    Level {
        n: s.0.options.n,
        torsional_rigidity: s.0.torsional_rigidity,
        max_shear_stress: s.1.and_then(|m| m.controlled()),
        shear_centre: Some(s.2.shear_centre),
        warping_constant: Some(s.2.warping_constant),
    }
}

fn rung_level(r: &Rung) -> Level {
    Level {
        n: r.sol.options.n,
        torsional_rigidity: r.sol.torsional_rigidity,
        max_shear_stress: r.tau(),
        shear_centre: r.warp.as_ref().map(|w| w.shear_centre),
        warping_constant: r.warp.as_ref().map(|w| w.warping_constant),
    }
}

/// The differences of one quantity between successive rungs.
struct Differences {
    /// between the finest two rungs
    last: f64,
    /// between the two rungs before (None: only two rungs)
    before: Option<f64>,
}

/// The differences `f(finer, coarser)` of one quantity over `rungs`
/// (coarse to fine; None when fewer than two or the quantity is missing).
fn diffs<T>(rungs: &[T], f: impl Fn(&T, &T) -> Option<f64>) -> Option<Differences> {
    let k = rungs.len();
    if k < 2 {
        return None;
    }
    let last = f(&rungs[k - 1], &rungs[k - 2])?;
    let before = if k >= 3 {
        f(&rungs[k - 2], &rungs[k - 3])
    } else {
        None
    };
    Some(Differences { last, before })
}

/// Smallest ratio of successive differences the extrapolated estimate
/// assumes for the integral quantities (J, the shear centre, Γ), for
/// `opts`: 2^−min(2N, p, 8) for dbN with grading exponent p; τ_max, a point
/// value, gets twice that. None: no extrapolation
/// (Shannon and Nyström keep the plain difference).
///
/// Measured with db4, p = 8 (log₂ of the ratios of successive differences
/// between n = 128 and 2048 above round-off, on the rectangles 2 × 1 and
/// 1 × 0.1, the triangle, the hexagon, two grooves, an L, a flat triangle,
/// two boxes and a channel): J and Γ −8.1 to −15 (the slowest: the
/// hexagon's Γ at 128–512), τ_max −6.9 to −12.5 (the slowest: the groove
/// b = 0.3 at 128–512, which a floor of 2^−8 underestimated by 10 %). With
/// p = 6 every rate is about one order slower.
///
/// Higher orders are capped at the measured 2^−8: with db8 and p = 12 (a
/// floor of 2^−12 uncapped) the sectionproperties I at 1e-6 reported a Γ
/// error of 2.5e-11 where its error against db4 at 1e-10 is 1.3e-10.
pub fn rate_floor(opts: &Options) -> Option<f64> {
    match opts.method {
        Method::Daubechies => {
            // (a grading outside 2..=12 is refused by the solve itself)
            let k = (2.0 * opts.wavelet_order as f64)
                .min(opts.grading.floor())
                .min(MEASURED_RATE_ORDER)
                - 1.0;
            (k >= 1.0).then(|| 0.5f64.powf(k + 1.0))
        }
        _ => None,
    }
}

/// The fastest rate (as −log₂ of the ratio of successive differences) the
/// floors were measured at: db4 with p = 8.
const MEASURED_RATE_ORDER: f64 = 8.0;

/// The floor for τ_max, the shear centre and Γ: twice [`rate_floor`] (one
/// order slower). Γ = ∫ω² and the shear centre follow the warping function
/// ω, whose boundary values converge like a point value: the box 2 × 1 with
/// flanges 0.12 and webs 0.08 (db4, p = 8) has Γ errors of 3.6e-8 at
/// n = 256 and 3.7e-10 at 512 (2^−6.6 per doubling), which the integral
/// floor 2^−8 underestimated (2.9e-10 reported at 512).
fn pointwise_floor(integral: Option<f64>) -> Option<f64> {
    integral.map(|f| 2.0 * f)
}

/// Largest observed ratio of successive differences for which the
/// extrapolated estimate is used (above it: the plain difference).
const EXTRAPOLATE_BELOW: f64 = 0.25;

/// The estimated error of the finest rung from its differences.
///
/// Plain: the last difference d_k. Extrapolated (three rungs, a rate floor,
/// and an observed ratio ρ = d_k / d_{k−1} ≤ ¼): with errors e_n shrinking
/// by a factor ρ per doubling, e_n = d_k ρ/(1 − ρ) (Aitken). We use
/// ρ_e = max(ρ, floor) and a safety factor 2: e_n ≈ 2 d_k ρ_e/(1 − ρ_e).
/// Round-off does not shrink with n, so the estimate never goes below
/// min(d_k, noise), noise = max([`DIFFERENCE_NOISE`], the noise level of
/// [`round_off`]): a difference at that level may be round-off, and then
/// it is the plain difference. Every estimate is at least the round-off
/// scale of a dense solve, which no difference of rungs can see.
///
/// `pre_asymptotic`: the oldest rung lies below the geometry's starting n
/// n0 (the ladder starts at n0/4), where walls and corners are not yet
/// resolved. A ratio faster than the floor from it says only that its
/// error has collapsed, not how fast the error goes on falling, and the
/// ratio assumed is then √floor (2^−4; used for J only: τ_max, the shear
/// centre and Γ assume the pointwise floor 2^−7, which bounded every one
/// of them in the sweep of `examples/estimate_sweep.rs`). Measured with the
/// floor:
/// the channel 0.5 × 1 with walls of 0.1 (n0 = 256) had J differences
/// 2.8e-3 and 2.8e-7 (128 → 256 → 512, ratio 2^−13) and J at 512 5.6e-9
/// off, reported 2.2e-9; a star-shaped 40-gon (n0 = 2048) ratio 2^−9.3,
/// J at 2048 2.9e-10 off (the next ratio was 2^−3.9), reported 3.6e-11.
fn estimate(d: &Differences, floor: Option<f64>, round_off: RoundOff, pre_asymptotic: bool) -> f64 {
    // a quantity that is not finite (NaN: over- or underflow at an extreme
    // scale) has no error estimate: never let `max` turn NaN into round-off
    if !d.last.is_finite() {
        return f64::INFINITY;
    }
    let e = match (d.before, floor) {
        (Some(before), Some(f)) if before > 0.0 && d.last <= EXTRAPOLATE_BELOW * before => {
            let observed = d.last / before;
            let rho = if pre_asymptotic && observed < f {
                f.sqrt()
            } else {
                observed.max(f)
            };
            let noise = DIFFERENCE_NOISE.max(round_off.noise);
            (2.0 * d.last * rho / (1.0 - rho)).max(d.last.min(noise))
        }
        _ => d.last,
    };
    e.max(round_off.scale)
}

/// The round-off of a solve: its scale (the floor of every estimate) and
/// the level below which a difference between rungs may be round-off.
#[derive(Clone, Copy, Debug)]
struct RoundOff {
    scale: f64,
    noise: f64,
}

/// Round-off level of a result with `unknowns` unknowns on `section`:
/// N ε s, with the shape factor s = P²/4πA on a single curve and its square
/// root on a section with holes (P all boundary curves, A the area; s is 1
/// for a disc and grows with slenderness). It is a scale, not a bound.
///
/// Measured as the spread of J and Γ when the section is translated,
/// rotated by 30° and 90°, or its vertices renumbered (the exact answers
/// and the discretisation stay, round-off moves), over N ε:
///
/// * single curves with walls of 0.02 (an angle and an I 1 deep, N = 4096,
///   P²/4πA = 32): J 15–20, Γ up to 32; the angle with walls of 0.05
///   (N = 2048, 13): J 4, Γ 6.4; the strip 1 × 0.02 (N = 2048, 16.6): 3.4.
///   The square root (5.7) under-estimated the thin angle 6-fold;
/// * the box 2 × 1 with walls of 0.02 (two curves, N = 4096, P²/4πA = 94):
///   0.1, and the box with flanges 0.1 and webs 0.05: 0.03. The walls of a
///   box lie between two curves, and its round-off does not grow with its
///   slenderness: the square root (9.7, 4.4) bounds it with room;
/// * the rectangle 1 × 2 and the hexagon: below 3 (the factor 1.4, 1.1).
///
/// Before that: τ_max of the 1 × 0.05 ellipse at n = 1024 is 1.3e-13 off
/// while its rungs agree to 8.6e-14, J of the 1 × 0.02 ellipse at n = 2048
/// 1.6e-12 off while they agree to 5.5e-13 (N ε: 4.5e-13; the factor 20
/// gives 9e-12).
///
/// A section far from the origin carries its coordinates with the absolute
/// round-off ε|x₀|, a relative error ε|x₀|/R of its size R = P_outer/2π, and
/// the kernel sees it at the node spacing R/n: the scale adds
/// ε (|x₀|/R) n/8 (n per curve). Measured (the tube 1/0.6 at (10⁵, 0),
/// ε|x₀|/R = 2.2e-11): τ_max 2.1e-10 off at n = 256 and 2.9e-9 at 4096
/// (about ε (|x₀|/R) n/30), J 1.2e-12, the shear centre 1.8e-11, while the
/// rungs agreed to 2e-13 and the scale was 2.3e-13; the tube at
/// (10³, −10³): τ_max 1.1e-12 off, reported 3.2e-13. Near the origin
/// (|x₀| ≲ R) the term is below N ε and changes nothing.
fn round_off(section: &Section, unknowns: usize) -> RoundOff {
    let p = section.total_perimeter();
    let slenderness = (p * p / (4.0 * std::f64::consts::PI * section.area)).max(1.0);
    let n = unknowns / section.curves().len().max(1);
    let c = section.centroid;
    let size = section.perimeter() / (2.0 * std::f64::consts::PI);
    let offset = f64::EPSILON * c[0].hypot(c[1]) / size * n as f64 / 8.0;
    let scale = unknowns as f64 * f64::EPSILON;
    if section.holes.is_empty() {
        let scale = scale * slenderness + offset;
        RoundOff {
            scale,
            noise: NOISE_OVER_ROUND_OFF * scale,
        }
    } else {
        // the square root is already 40-300 × the measured spread of boxes
        let scale = scale * slenderness.sqrt() + offset;
        RoundOff {
            scale,
            noise: scale,
        }
    }
}

/// Whether `section` is so large or so small that the products of second
/// moments in the shear centre (∝ L⁸) may leave the range of double
/// precision: a radius of gyration outside [1e-30, 1e30].
fn extreme_scale(section: &Section) -> bool {
    let rg = (section.polar_moment() / section.area).sqrt();
    !(1e-30..=1e30).contains(&rg)
}

/// Relative level below which differences between rungs may be round-off
/// (measured: up to 5e-14 on the 1 × 0.05 ellipse at n = 1024, where the
/// rungs agree to 1e-14): extrapolated estimates stop there.
const DIFFERENCE_NOISE: f64 = 1e-12;

/// How far above the [`round_off`] scale of a single curve a difference
/// between rungs may still be round-off (sections with holes: 1, their
/// scale is far above their measured round-off). The scale is not a
/// bound: on slender single curves (an angle, a T and an I with walls of
/// 0.02, n = 4096) the previous scale N ε √(P²/4πA) gave
/// 5.2e-12 while J moves by 1.2e-11 – 1.9e-11 and Γ by up to 3e-11 when
/// the same section is translated, rotated or its vertices renumbered
/// (changes that leave the exact answers and the discretisation as they
/// are: what moves is round-off). Extrapolating such a difference as if it
/// were discretisation error reported 5.2e-12.
const NOISE_OVER_ROUND_OFF: f64 = 10.0;

/// Error floors of the unresolved nearly flat vertices of a polygon
/// parametrised by arc length without grading
/// ([`Section::nearly_smooth_polygon`], such as a 2000-gon), at `n` unknowns
/// per curve: (J, the shear centre and Γ; τ_max), relative. 0 for every
/// other section.
///
/// At a vertex of interior angle α = π − turn the flux varies like r^ε,
/// ε = |π − α|/α (≈ 1e-3 on a 2000-gon): on every edge it rises by about ε
/// from the vertices to the middle, where τ_max sits. With about one node per
/// edge the density cannot show that rise at all, and the rungs agree with
/// each other while all missing it, so their differences say nothing. The
/// floors model the error instead, from m edges and n nodes (r = m/n ≤ 1):
///
/// * τ_max: ε · min(1, 2r). Measured against graded solutions of the
///   regular 100-gon (ε = 0.020): 0.68 ε at one node per edge (also the
///   200-gon), 0.17 ε at 10 nodes per edge, 0.045 ε at 41;
/// * J (and, assumed alike, the shear centre and Γ): 0.05 ε² r². Measured
///   (regular N-gons: graded solutions, and for N = 2000 the expansion
///   J = π/2 (1 − a/N² − b/N⁴) fitted to the graded 100- and 200-gon):
///   0.031 ε² r² on the 100-gon from 2.5 to 41 nodes per edge (the error
///   falls like r²), 0.008–0.03 ε² r² on the 2000-gon at 1–2 nodes per edge,
///   where the rungs 512 to 2048 agree to 1e-13 and J is 8.0e-9 off.
pub fn flat_vertex_floors(section: &Section, n: usize) -> (f64, f64) {
    let (mut j, mut tau): (f64, f64) = (0.0, 0.0);
    for (eps, m) in flat_curves(section) {
        let r = (m as f64 / n.max(1) as f64).min(1.0);
        j = j.max(FLAT_VERTEX_J * eps * eps * r * r);
        tau = tau.max(eps * (2.0 * r).min(1.0));
    }
    (j, tau)
}

/// (ε, number of edges) of every curve of `section` that is a nearly
/// smooth polygon, ε = |π − α|/α the largest over its vertices.
fn flat_curves(section: &Section) -> Vec<(f64, usize)> {
    section
        .curves()
        .into_iter()
        .filter(|c| c.nearly_smooth_polygon())
        .map(|c| {
            let eps = c
                .junctions
                .iter()
                .map(|jn| (std::f64::consts::PI - jn.interior_angle).abs() / jn.interior_angle)
                .fold(0.0, f64::max);
            (eps, c.pieces.len())
        })
        .collect()
}

/// Factor of the J floor of [`flat_vertex_floors`] (measured up to 0.031).
const FLAT_VERTEX_J: f64 = 0.05;

/// Estimated errors of J and τ_max (None when singular) of the finest of
/// the rungs' (J, τ_max), coarse to fine, at least two.
fn jt_estimates(
    values: &[(f64, Option<f64>)],
    floor: Option<f64>,
    round_off: RoundOff,
    pre_asymptotic: bool,
) -> (f64, Option<f64>) {
    let j = diffs(values, |a, b| Some(rel(a.0, b.0)));
    let tau = diffs(values, |a, b| Some(rel(a.1?, b.1?)));
    (
        j.map_or(0.0, |d| estimate(&d, floor, round_off, pre_asymptotic)),
        // τ_max, like the shear centre and Γ, already assumes the slower
        // pointwise floor, which held on every section of the sweep
        tau.map(|d| estimate(&d, pointwise_floor(floor), round_off, false)),
    )
}

/// The controlled result from the finest rung `fine`, its estimates from
/// `coarse` and, if given, the rung before it (`older`); an `older` rung
/// below `resolved_from` is pre-asymptotic (see [`estimate`]).
fn finish(
    older: Option<Solved>,
    coarse: Solved,
    fine: Solved,
    tol: f64,
    levels: Vec<Level>,
    reached_cap: bool,
    resolved_from: usize,
) -> Controlled {
    let pre_asymptotic = older
        .as_ref()
        .is_some_and(|o| o.0.options.n < resolved_from);
    let refs: Vec<&Solved> = older.iter().chain([&coarse, &fine]).collect();
    let estimated_from = refs.iter().map(|r| r.0.options.n).collect();
    let floor = rate_floor(&fine.0.options);
    let jt: Vec<(f64, Option<f64>)> = refs
        .iter()
        .map(|r| (r.0.torsional_rigidity, r.1.and_then(|m| m.controlled())))
        .collect();
    let round_off = round_off(&fine.0.section, fine.0.options.n * fine.0.curve_count());
    let (j_error, tau_error) = jt_estimates(&jt, floor, round_off, pre_asymptotic);
    let (flat_j, flat_tau) = flat_vertex_floors(&fine.0.section, fine.0.options.n);
    let j_error = j_error.max(flat_j);
    let tau_error = tau_error.map(|e| e.max(flat_tau));
    let sec = &fine.0.section;
    let ip = sec.polar_moment();
    let rg = (ip / sec.area).sqrt();
    let g_scale = gamma_scale(sec, fine.2.warping_constant);
    let g_floor = gamma_floor(sec, &fine.2);
    let shear_centre_error = diffs(&refs, |a, b| {
        let (x, y) = (a.2.shear_centre, b.2.shear_centre);
        Some((x[0] - y[0]).hypot(x[1] - y[1]) / rg)
    })
    .map_or(0.0, |d| {
        estimate(&d, pointwise_floor(floor), round_off, false)
    })
    .max(flat_j);
    let warping_error = diffs(&refs, |a, b| {
        Some((a.2.warping_constant - b.2.warping_constant).abs() / g_scale)
    })
    .map_or(0.0, |d| {
        estimate(&d, pointwise_floor(floor), round_off, false)
    })
    .max(flat_j)
    // the arithmetic of Γ's double integral: a bias the rungs share
    .max(g_floor);
    // the τ away from the singular points is reported with its estimate,
    // and counts only when followed (see `followed`)
    let tau_counts = !sec.is_singular() || fine.0.options.corner_distance.is_some();
    let converged = j_error <= tol
        && (!tau_counts || tau_error.is_none_or(|e| e <= tol))
        && shear_centre_error <= tol
        && warping_error <= tol;
    let mut warnings = Vec::new();
    let shear_centre = fine.2.shear_centre;
    if !(fine.2.warping_constant.is_finite() && shear_centre.iter().all(|v| v.is_finite())) {
        // Γ ∝ L⁶ and the products of second moments in the shear centre ∝ L⁸
        let size = rg.max(f64::MIN_POSITIVE);
        if extreme_scale(sec) {
            warnings.push(format!(
                "the shear centre and the warping constant Γ are not finite: at this scale (radius of gyration {size:.1e}) the products of second moments (∝ L⁸) and Γ (∝ L⁶) leave the range of double precision; give the section in units that make its size nearer 1 (J and τ_max are unaffected)"
            ));
        } else {
            warnings.push(format!(
                "the shear centre and the warping constant Γ are not finite at n = {}: the warping function is not resolved on this boundary (J and τ_max carry their own estimates)",
                fine.0.options.n
            ));
        }
    }
    if let (false, Some(e)) = (tau_counts, tau_error)
        && e > tol
    {
        warnings.push(format!(
            "τ away from the singular points: estimated relative error {e:.1e}, above the tolerance {tol:.1e}; the refinement follows J, the shear centre and Γ of a section with re-entrant corners or cusps, and this value only when --corner-distance is given (on thin walls it needs a much finer n)"
        ));
    }
    if g_floor > tol {
        warnings.push(format!(
            "Γ: the round-off of its double integral, about {g_floor:.1e} of Γ (its terms cancel to Γ; a bias every n shares), exceeds the tolerance {tol:.1e}: no finer n reduces it"
        ));
    }
    if !converged {
        let n = fine.0.options.n;
        let mut w = format!(
            "not converged to the tolerance {tol:.1e} at n = {n}: estimated relative error of J {j_error:.1e}"
        );
        if let Some(t) = tau_error {
            if sec.is_singular() {
                w += &format!(", of τ away from the singular corners {t:.1e}");
            } else {
                w += &format!(", of τ_max {t:.1e}");
            }
        }
        w += &format!(", of the shear centre {shear_centre_error:.1e}, of Γ {warping_error:.1e}");
        if reached_cap {
            w += " (the largest n allowed was reached)";
        }
        warnings.push(w);
        if let Some(&(eps, m)) = flat_curves(sec)
            .iter()
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .filter(|_| flat_tau > tol || flat_j > tol)
        {
            warnings.push(format!(
                "the polygon's nearly flat vertices are not resolved (parametrised by arc length, {:.1} nodes per edge): the flux rises by about ε = {eps:.1e} from each vertex to the middle of an edge, which the density cannot show; the estimates include it (τ_max {flat_tau:.1e}, J {flat_j:.1e}), and it would take a graded corner, tens of nodes, at every vertex to resolve",
                n as f64 / m as f64,
            ));
        }
    }
    // the reported rung's τ_max (with its value away from the singular
    // points when singular)
    let max_shear = fine.1.unwrap_or_else(|| fine.0.max_shear());
    // Γ = ∫ω_n² dA is reported as max(Γ, 0), at every level too: a negative
    // value is round-off of a vanishing ω (circles, tubes). The estimates
    // above used the values as computed.
    let mut levels = levels;
    for l in &mut levels {
        l.warping_constant = l.warping_constant.map(crate::warping::nonnegative);
    }
    Controlled {
        solution: fine.0,
        max_shear,
        j_error,
        tau_error,
        warping: fine.2.reported(),
        shear_centre_error,
        warping_error,
        tol,
        converged,
        levels,
        estimated_from,
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
    // graded from 16 nodes per edge (the coarse solve at 8; at 1 per edge
    // the graded 2000-gon's estimate missed its error 30-fold, at 16 per
    // edge it bounds it 25-fold)
    let prepared = prepared(section, opts, 2 * opts.n);
    let section = &*prepared;
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
    Ok(finish(None, coarse, fine, tol, levels, false, 0))
}

/// Refines from [`starting_n`] / 4 (or `opts.n` if larger) by doubling until,
/// at n ≥ the starting n, the estimated errors of J, τ_max, the shear
/// centre and Γ (from the last three rungs, see the module notes) meet the
/// relative tolerance `tol`, or `n_max` is reached (then `converged` is
/// false and a warning says so).
pub fn solve_to_tolerance(
    section: &Section,
    opts: &Options,
    tol: f64,
    n_max: usize,
) -> Result<Controlled, SolveError> {
    let prepared = prepared(section, opts, n_max);
    let section = &*prepared;
    if !(tol > 0.0 && tol < 1.0) {
        return Err(SolveError::BadN {
            n: opts.n,
            reason: format!("the tolerance must lie in (0, 1), got {tol:e}"),
        });
    }
    // the ladder needs two rungs: n/2 and n, both at least the method's smallest n
    if n_max < 2 * min_n(opts) {
        return Err(SolveError::BadN {
            n: n_max,
            reason: format!(
                "the largest n (--max-n) must be at least {} for this method and wavelet (two resolutions, n/2 and n, each at least {})",
                2 * min_n(opts),
                min_n(opts)
            ),
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
    // every rung is q 2^j: a power of two, or with the odd factor of a
    // rotational symmetry (if its ladder has room for two rungs)
    let odd = Rungs {
        q: rung_base(section, opts),
    };
    let rungs = if odd.q > 1 && odd.at_most(n_max) >= 2 * odd.at_least(min_n(opts)) {
        odd
    } else {
        Rungs { q: 1 }
    };
    let asked = n_max;
    let mut n_max = rungs.at_most(n_max.min(crate::solve::FOLDED_N_MAX));
    // (a folded system is of order K n/k)
    let order = |n: usize| n / crate::solve::symmetry_order(section, &Options { n, ..*opts });
    // the largest rung a solve accepts (n/k ≤ HARD_N_MAX, n ≤ FOLDED_N_MAX;
    // a larger --max-n ran the ladder into a solve that refused it: the
    // ellipse 1 × 0.01 at 1e-14 stopped with an error at n = 32 768), then
    // the largest whose dense solve fits in memory; the fold order of each
    // rung tried is found once
    let mut limited = asked > crate::solve::FOLDED_N_MAX;
    let mut memory = None;
    while n_max / 2 >= min_n(opts) {
        let k_order = order(n_max);
        if k_order > crate::solve::HARD_N_MAX {
            limited = true;
        } else if crate::memory::check(opts.method, curves, k_order).is_err() {
            memory = Some((n_max, k_order));
        } else {
            break;
        }
        n_max /= 2;
    }
    let limit_note = limited.then(|| {
        format!(
            "--max-n {asked} lowered to n = {n_max}: a solve takes at most {} unknowns per curve, n/k for a section it folds by a k-fold rotation, and n ≤ {}",
            crate::solve::HARD_N_MAX,
            crate::solve::FOLDED_N_MAX
        )
    });
    // the rung that did not fit, and its order
    let memory_note = memory.map(|(n, k_order)| {
        format!(
            "at most n = {n_max} per curve fits in the memory available (n = {n} on {curves} curve(s) would need about {:.1} GB)",
            crate::memory::dense_bytes(opts.method, curves, k_order) as f64 / 1e9
        )
    });
    let n0 = rungs.at_least(starting_nodes(section, opts).max(opts.n));
    let mut start_warning = None;
    if n0 > n_max {
        start_warning = Some(format!(
            "the geometry asks for n ≥ {n0} (pieces, slenderness) but at most n = {n_max} is allowed"
        ));
    }
    // the result is never taken below n0 (nor n_max when n0 exceeds it);
    // the ladder starts two rungs below so that the estimate at n0 can use
    // the rate of three rungs (the rung n0/4 costs 1/64 of n0's solve)
    let accept_from = n0.min(n_max);
    let mut n = (n0 / 4).min(n_max / 2).max(rungs.at_least(min_n(opts)));
    let with_start = |mut c: Controlled| {
        if let Some(w) = &start_warning {
            c.warnings.push(w.clone());
        }
        if let (false, Some(w)) = (c.converged, &memory_note) {
            c.warnings.push(w.clone());
        }
        if let (false, Some(w)) = (c.converged, &limit_note) {
            c.warnings.push(w.clone());
        }
        c
    };
    let floor = rate_floor(opts);
    // the last three rungs at most, coarse to fine
    let mut ladder: Vec<Rung> = Vec::new();
    let mut levels: Vec<Level> = Vec::new();
    loop {
        let cur = Rung::new(section, &Options { n, ..*opts })?;
        levels.push(rung_level(&cur));
        if ladder.is_empty() && 2 * n > n_max {
            // cannot refine at all: estimate from n/2
            let coarse = solve_level(section, &Options { n: n / 2, ..*opts })?;
            levels.insert(0, level(&coarse));
            let fine = cur.solved();
            let last = levels.len() - 1;
            levels[last] = level(&fine);
            return Ok(with_start(finish(None, coarse, fine, tol, levels, true, 0)));
        }
        ladder.push(cur);
        if ladder.len() > 3 {
            ladder.remove(0);
        }
        if ladder.len() >= 2 {
            let at_cap = 2 * n > n_max;
            let jt: Vec<(f64, Option<f64>)> = ladder
                .iter()
                .map(|r| (r.sol.torsional_rigidity, r.tau()))
                .collect();
            let round_off = round_off(section, n * section.curves().len());
            // rungs below n0 are below the resolution the geometry asks
            // for: a fast ratio from them is pre-asymptotic
            let pre_asymptotic = ladder.len() == 3 && ladder[0].sol.options.n < accept_from;
            let (ej_rungs, etau) = jt_estimates(&jt, floor, round_off, pre_asymptotic);
            let (flat_j, flat_tau) = flat_vertex_floors(section, n);
            let ej = ej_rungs.max(flat_j);
            let etau = etau.map(|e| e.max(flat_tau));
            // floors that refining up to n_max cannot bring under the
            // tolerance: stop once the rungs agree on J (flagged result)
            let (cap_j, cap_tau) = flat_vertex_floors(section, n_max);
            let hopeless = cap_j > tol || (etau.is_some() && cap_tau > tol);
            let settled = if hopeless {
                ej_rungs <= tol
            } else {
                ej <= tol && etau.is_none_or(|e| e <= tol)
            };
            if (n >= accept_from && settled) || at_cap {
                // the warping outputs of the rungs the estimate uses
                let k = levels.len();
                let used = ladder.len();
                for (r, l) in ladder.iter_mut().zip(&mut levels[k - used..]) {
                    r.with_warping(l);
                }
                let fine = ladder[used - 1].solved();
                let coarse = ladder[used - 2].solved();
                let older = (used == 3).then(|| ladder[0].solved());
                let c = finish(
                    older,
                    coarse,
                    fine,
                    tol,
                    levels.clone(),
                    at_cap,
                    accept_from,
                );
                // a shear centre or Γ that is not finite at an extreme
                // scale stays so at every n: flagged now, not after the
                // largest n (at a plain scale a finer n may resolve it)
                let out_of_range = extreme_scale(section)
                    && !(c.warping.warping_constant.is_finite()
                        && c.warping.shear_centre.iter().all(|v| v.is_finite()));
                // Γ's round-off does not fall with n: a Γ held above the
                // tolerance by it alone is flagged now, not after the
                // largest n
                if c.converged
                    || at_cap
                    || hopeless
                    || out_of_range
                    || gamma_floor(section, &c.warping) > tol
                {
                    return Ok(with_start(c));
                }
            }
        }
        n *= 2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Only sizes far from 1 blame the scale for a non-finite shear centre
    /// or Γ (the squares of side 1e40 and 1e-60 lose them, side 1e30 and
    /// 1e-25 keep them).
    #[test]
    fn extreme_scales_are_told_apart_from_plain_ones() {
        let square = crate::sections::rectangle(1.0, 1.0).unwrap();
        for (side, extreme) in [
            (1.0, false),
            (1e30, false),
            (1e-25, false),
            (1e40, true),
            (1e-60, true),
        ] {
            let s = square.scaled(side).unwrap();
            assert_eq!(extreme_scale(&s), extreme, "side {side:e}");
        }
    }
}
