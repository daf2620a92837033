//! The solver front end: options, [`solve`], and the [`TorsionSolution`]
//! with its outputs (J, τ_max and its location, |q| along Γ, interior u and
//! stresses, the multiplier c).

use crate::density::FourierDensity;
use crate::error::SolveError;
use crate::geometry::{PointLocation, Section, V2};
use crate::grading::{BPoint, Parametrisation};
use crate::{galerkin, kernels, nystrom, shannon};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Discretisation method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// periodised Daubechies wavelet Galerkin (default)
    Daubechies,
    /// harmonic (Shannon) wavelet Galerkin with oversampled quadrature:
    /// spectral, the independent cross-check
    Shannon,
    /// Kress Nyström with log product weights: reference
    Nystrom,
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Daubechies => "daubechies",
            Method::Shannon => "shannon",
            Method::Nystrom => "nystrom",
        })
    }
}

/// How the linear system is solved (compression applies to Daubechies Galerkin only).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinearSolver {
    /// dense direct solve of the augmented system (faer: Bunch–Kaufman LBLᵀ for the
    /// symmetric Galerkin systems, partial-pivoting LU for Nyström)
    Dense,
    /// wavelet-basis matrix thresholded at ε·max|a|, projected PCG with level
    /// (diagonal) scaling to relative residual `tol`
    Compressed {
        /// threshold ε
        eps: f64,
        /// CG tolerance
        tol: f64,
    },
}

/// Options of [`solve`].
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// number of unknowns n, 8 ≤ n ≤ 8192 (a power of two ≥ the wavelet's minimum for Daubechies)
    pub n: usize,
    /// method
    pub method: Method,
    /// Daubechies order N (dbN has N vanishing moments)
    pub wavelet_order: usize,
    /// Kress grading exponent p at corners and cusps
    pub grading: f64,
    /// linear solver
    pub linear: LinearSolver,
    /// Daubechies on thin-walled sections with re-entrant corners: the long
    /// graded panels get the corner-zone map ([`crate::grading::ZoneMap`],
    /// the mean node spacing in their middle) instead of Kress's (twice
    /// it); false keeps Kress's map everywhere (a cross-check)
    pub corner_zones: bool,
    /// Singular sections: the distance from the singular points (re-entrant
    /// corners, inward cusps) outside which the largest boundary shear
    /// stress is reported and controlled, [`MaxShear::away`] (None: the
    /// section's [`Section::default_corner_distance`])
    pub corner_distance: Option<f64>,
    /// Daubechies with the dense solver: fold the system by the rotational
    /// symmetry of the discrete boundary where it has one
    /// ([`crate::symmetry`]; the same solution to rounding, at a fraction
    /// of the cost); false solves the whole system (a cross-check)
    pub symmetry: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            n: 256,
            method: Method::Daubechies,
            wavelet_order: 4,
            grading: 8.0,
            linear: LinearSolver::Dense,
            corner_zones: true,
            corner_distance: None,
            symmetry: true,
        }
    }
}

/// Statistics of the compressed wavelet-basis matrix.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CompressionReport {
    /// threshold ε (relative to max|a_ij|)
    pub eps: f64,
    /// kept entries per row
    pub entries_per_row: f64,
    /// ‖A − A_ε‖₂ / ‖A‖₂ (power iteration)
    pub operator_error: f64,
    /// CG iterations
    pub iterations: usize,
    /// final relative residual
    pub residual: f64,
}

/// Where τ is largest.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct MaxShear {
    /// τ_max (None when a re-entrant corner or inward cusp makes it infinite)
    pub value: Option<f64>,
    /// location: the maximiser, or the singular point
    pub at: Option<V2>,
    /// τ → ∞ somewhere on Γ
    pub singular: bool,
    /// singular sections: the largest boundary τ at least a set distance
    /// from every singular point, the stress an engineer reads off a wall
    /// (None when not singular)
    pub away: Option<AwayShear>,
}

impl MaxShear {
    /// The value the error control follows: τ_max, or for a singular
    /// section the largest value away from its singular points.
    pub fn controlled(&self) -> Option<f64> {
        self.value.or(self.away.map(|a| a.value))
    }
}

/// The largest boundary shear stress of a singular section outside discs
/// around its singular points: a point value that converges with n (the
/// stress at the singular points themselves is infinite, and the largest
/// sampled value next to them only grows as n does).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct AwayShear {
    /// largest |q| = τ/(Gθ) on Γ at least `distance` from every singular point
    pub value: f64,
    /// where it is attained
    pub at: V2,
    /// the distance used: `requested`, or the extent of the singular
    /// points' graded clusters if that is larger
    pub distance: f64,
    /// the distance asked for
    pub requested: f64,
}

/// One sample of the boundary traction.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct BoundarySample {
    /// parameter t ∈ [0, 1)
    pub t: f64,
    /// arc length from the start of the boundary
    pub s: f64,
    /// position
    pub x: V2,
    /// q = ∂u/∂n (≤ 0)
    pub q: f64,
}

/// Prandtl function and stresses at an interior point.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct InteriorValue {
    /// point
    pub x: V2,
    /// u (Gθ = 1)
    pub u: f64,
    /// τ_xz = ∂u/∂y
    pub tau_xz: f64,
    /// τ_yz = −∂u/∂x
    pub tau_yz: f64,
    /// distance to the boundary (to the nearest quadrature node, within
    /// a factor of about 1.1 of the true one)
    pub distance: f64,
    /// Round-off of u's derivatives relative to the section's size L (the
    /// largest distance of Γ from the centroid): ε L / distance. The
    /// representation formula sums terms of size 1/distance to a result of
    /// size 1, and the point's own coordinates carry ε of absolute error;
    /// the measured errors on the ellipse, the tube and the triangle are
    /// 0.02–0.1 of this.
    pub round_off: f64,
}

/// The solution of one torsion problem.
#[derive(Clone, Debug)]
pub struct TorsionSolution {
    /// the section
    pub section: Section,
    /// the graded parametrisation used
    pub param: Parametrisation,
    /// options used
    pub options: Options,
    /// torsional rigidity J (torque T = GθJ)
    pub torsional_rigidity: f64,
    /// Lagrange multiplier c of the augmented system (exactly 0)
    pub multiplier: f64,
    /// density μ(t) = q_v |x′| as a trigonometric polynomial
    pub density: FourierDensity,
    /// compression statistics when the compressed solver was used
    pub compression: Option<CompressionReport>,
    /// centroid x₀ used by the particular solution
    pub centroid: V2,
    /// the solution on each hole boundary (same order as `section.holes`)
    pub holes: Vec<HoleSolution>,
    /// the order k of the rotational symmetry the system was folded by
    /// (1: solved whole; see [`crate::symmetry`])
    pub symmetry_order: usize,
}

/// The solution on one hole boundary.
#[derive(Clone, Debug)]
pub struct HoleSolution {
    /// its graded parametrisation
    pub param: Parametrisation,
    /// density μ(t) = q_v |x′| on it
    pub density: FourierDensity,
    /// the constant value C_k of the Prandtl function u on it (and in the hole)
    pub stress_function: f64,
}

/// Raw output of a discretisation: densities and multipliers per curve
/// (outer first) and Σ ∫ g2 μ dt.
pub(crate) struct RawSolution {
    pub densities: Vec<FourierDensity>,
    pub multipliers: Vec<f64>,
    pub j_integral: f64,
    /// the rotational symmetry order the system was folded by (1: none)
    pub fold: usize,
    pub compression: Option<CompressionReport>,
}

/// The polar moments (length⁴) a solve accepts: J is of their size, and
/// [1e-300, 1e300] keeps it and the products formed on the way (the load
/// ∝ L², the J integral ∝ L⁴) within the normal range of double precision.
const POLAR_MOMENT_RANGE: (f64, f64) = (1e-300, 1e300);

/// Largest order per curve of a solve's dense matrix, n/k for a system
/// folded by a k-fold rotation (8192² doubles are 0.5 GB).
pub const HARD_N_MAX: usize = 1 << 13;

/// Largest n a solve accepts at all (the boundary arrays and the density
/// evaluations are O(n) and O(n log n); a folded system's matrix is
/// smaller than n², see [`HARD_N_MAX`], and its assembly takes n/k × n
/// logarithms per curve pair): 2^19, room for a regular 2000-gon graded at
/// every vertex (256 nodes per edge, folded to order 256).
pub const FOLDED_N_MAX: usize = 1 << 19;

/// The graded parametrisation of every curve of `section` (outer first)
/// that a solve with `opts` uses.
fn parametrisations(section: &Section, opts: &Options) -> Vec<Parametrisation> {
    // corner zones (a flat panel middle for thin walls): Daubechies only,
    // whose error control was measured with them
    let walls = match opts.method {
        Method::Daubechies if opts.corner_zones => crate::grading::zone_walls(section),
        _ => None,
    };
    section
        .curves()
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let p = Parametrisation::with_zones(
                c,
                opts.grading,
                walls.as_ref().map(|w| w[i].as_slice()),
            );
            // the rungs q 2^j of an odd rotational symmetry: exact panels
            if opts.method == Method::Daubechies {
                p.exact_for(c, opts.n)
            } else {
                p
            }
        })
        .collect()
}

/// Whether a solve with `opts` may fold its system by a rotational
/// symmetry: the dense Daubechies solver with `opts.symmetry` on.
pub fn may_fold(opts: &Options) -> bool {
    opts.symmetry && opts.method == Method::Daubechies && opts.linear == LinearSolver::Dense
}

/// The order k of the rotational symmetry a solve folds its system by
/// (1: none, or not [`may_fold`]).
fn fold_order(section: &Section, params: &[Parametrisation], opts: &Options) -> usize {
    if !may_fold(opts) {
        return 1;
    }
    let nodes: Vec<BPoint> = section
        .curves()
        .iter()
        .zip(params)
        .flat_map(|(c, p)| p.nodes(c, opts.n))
        .collect();
    crate::symmetry::rotation_order(
        &nodes,
        opts.n,
        section.centroid,
        section.radius(),
        crate::symmetry::relative_tolerance(section),
    )
}

/// The order k of the rotational symmetry that a solve of `section` with
/// `opts` (at `opts.n`) folds its system by, 1 if none: its dense matrix is
/// of order K n/k (see [`crate::symmetry`]).
pub fn symmetry_order(section: &Section, opts: &Options) -> usize {
    fold_order(section, &parametrisations(section, opts), opts)
}

/// Solves Saint-Venant torsion (Gθ = 1) of `section`.
pub fn solve(section: &Section, opts: &Options) -> Result<TorsionSolution, SolveError> {
    if !(opts.grading >= 2.0 && opts.grading <= 12.0 && opts.grading.fract() == 0.0) {
        return Err(SolveError::BadGrading(opts.grading));
    }
    // dense n×n work arrays: 8192² doubles are 0.5 GB each (a folded
    // system's are n/k × n/k, checked below)
    if opts.n < 8 || opts.n > FOLDED_N_MAX {
        return Err(SolveError::BadN {
            n: opts.n,
            reason: format!(
                "need 8 ≤ n ≤ {HARD_N_MAX} (dense matrices; up to {FOLDED_N_MAX} for a section solved on a part of its boundary by its rotational symmetry)"
            ),
        });
    }
    // J is about the polar moment (∝ L⁴): refuse a size whose J leaves the
    // normal range of double precision (measured: a circle of radius 1e-78
    // gave J in subnormals, 6e-12 off, 1e-100 gave 0, 1e77 overflowed)
    let ip = section.polar_moment();
    // an area within round-off of the perimeter's square: no area at all
    let (area, perimeter) = (section.area, section.total_perimeter());
    if area.is_finite()
        && perimeter.is_finite()
        && area <= 64.0 * f64::EPSILON * perimeter * perimeter
    {
        return Err(SolveError::NoArea { area, perimeter });
    }
    if !(POLAR_MOMENT_RANGE.0..=POLAR_MOMENT_RANGE.1).contains(&ip) {
        return Err(SolveError::Scale { polar_moment: ip });
    }
    let curves = section.curves();
    let params = parametrisations(section, opts);
    let fold = fold_order(section, &params, opts);
    if opts.n / fold > HARD_N_MAX {
        return Err(SolveError::BadN {
            n: opts.n,
            reason: if fold > 1 {
                format!(
                    "need n/k ≤ {HARD_N_MAX} (dense matrices of order n/k: this section folds by its {fold}-fold rotation)"
                )
            } else {
                format!("need 8 ≤ n ≤ {HARD_N_MAX} (dense matrices)")
            },
        });
    }
    // refuse what cannot fit before anything of size n² is allocated (a
    // folded system is of order K n/k)
    crate::memory::check(opts.method, curves.len(), opts.n / fold)?;
    let x0 = section.centroid;
    let raw = match opts.method {
        Method::Nystrom => {
            if !opts.n.is_multiple_of(2) {
                return Err(SolveError::BadN {
                    n: opts.n,
                    reason: "Nyström needs an even n".into(),
                });
            }
            let nodes: Vec<BPoint> = curves
                .iter()
                .zip(&params)
                .flat_map(|(c, p)| p.nodes(c, opts.n))
                .collect();
            let (mu, c) = nystrom::solve_blocks(&nodes, opts.n, x0)?;
            let g2 = kernels::radius_sq(&nodes, x0);
            let ji = mu.iter().zip(&g2).map(|(a, b)| a * b).sum::<f64>() / opts.n as f64;
            RawSolution {
                densities: mu.chunks(opts.n).map(FourierDensity::from_nodes).collect(),
                multipliers: c,
                j_integral: ji,
                compression: None,
                fold: 1,
            }
        }
        Method::Daubechies => galerkin::solve(section, &params, opts, fold)?,
        Method::Shannon => shannon::solve(section, &params, opts)?,
    };
    let ip = section.polar_moment();
    let j = ip - 0.5 * raw.j_integral;
    if !j.is_finite() || raw.multipliers.iter().any(|c| !c.is_finite()) {
        return Err(SolveError::NonFinite);
    }
    let mut params = params.into_iter();
    let mut dens = raw.densities.into_iter();
    let param = params.next().ok_or(SolveError::NonFinite)?;
    let density = dens.next().ok_or(SolveError::NonFinite)?;
    let holes = params
        .zip(dens)
        .zip(raw.multipliers.iter().skip(1))
        .map(|((param, density), &c)| HoleSolution {
            param,
            density,
            stress_function: -c,
        })
        .collect();
    Ok(TorsionSolution {
        section: section.clone(),
        param,
        options: *opts,
        torsional_rigidity: j,
        multiplier: raw.multipliers[0],
        density,
        compression: raw.compression,
        centroid: x0,
        holes,
        symmetry_order: raw.fold,
    })
}

impl TorsionSolution {
    /// Number of boundary curves (1 + holes).
    pub fn curve_count(&self) -> usize {
        1 + self.holes.len()
    }

    /// Curve k (0: outer), its parametrisation and density.
    fn curve(&self, k: usize) -> (&Section, &Parametrisation, &FourierDensity) {
        if k == 0 {
            (&self.section, &self.param, &self.density)
        } else {
            let h = &self.holes[k - 1];
            (&self.section.holes[k - 1], &h.param, &h.density)
        }
    }

    /// Number of graded panels, over all curves, that use the corner-zone
    /// map instead of Kress's (see [`Options::corner_zones`]).
    pub fn zoned_panels(&self) -> usize {
        std::iter::once(&self.param)
            .chain(self.holes.iter().map(|h| &h.param))
            .map(|p| p.zoned_panels())
            .sum()
    }

    /// q = ∂u/∂n at boundary parameter t of the outer boundary.
    pub fn flux_at(&self, t: f64) -> (BPoint, f64) {
        self.flux_on(0, t)
    }

    /// q = ∂u/∂n (n out of Ω) at parameter t of curve k (0: outer, k ≥ 1: hole k).
    pub fn flux_on(&self, k: usize, t: f64) -> (BPoint, f64) {
        let (sec, param, dens) = self.curve(k);
        let p = param.eval(sec, t);
        let mu = dens.eval(t);
        let x = p.x();
        let nrm = p.normal();
        let qv = mu / p.speed();
        let q = qv - ((x[0] - self.centroid[0]) * nrm[0] + (x[1] - self.centroid[1]) * nrm[1]);
        (p, q)
    }

    /// Whether t lies in a graded corner cluster of the outer boundary.
    pub fn in_cluster(&self, t: f64) -> bool {
        self.in_cluster_on(0, t)
    }

    /// Whether t lies in a graded corner cluster of curve k where μ/|x′| is
    /// 0/0 and must not be trusted (|dw/ds| < 0.1 next to a corner, < 1e-3
    /// next to a tangent-continuous junction).
    pub fn in_cluster_on(&self, k: usize, t: f64) -> bool {
        self.cluster_junction(k, t).is_some()
    }

    /// The junction of curve k whose graded cluster holds t, if any (see
    /// [`TorsionSolution::in_cluster_on`]).
    fn cluster_junction(&self, k: usize, t: f64) -> Option<usize> {
        let (sec, param, _) = self.curve(k);
        let (pk, s) = param.local(t);
        // (ungraded panels have no cluster)
        param.grading[pk]?;
        let m = sec.pieces.len();
        let (sig, junc) = if s <= 0.5 {
            (s, pk)
        } else {
            (1.0 - s, (pk + 1) % m)
        };
        let dw = param.panel_speed(pk, sig);
        let limit = if sec.junctions[junc].is_smooth() {
            1e-3
        } else {
            0.1
        };
        (dw < limit).then_some(junc)
    }

    /// How far the graded clusters of the singular points reach from them:
    /// there the boundary values are not resolved (0/0 in μ/|x′|) and are
    /// never evaluated, whatever n (the cluster is a fixed part of its
    /// panels).
    pub fn singular_cluster_extent(&self) -> f64 {
        let m = (8 * self.options.n).max(2048);
        let mut extent = 0.0f64;
        for k in 0..self.curve_count() {
            let (sec, param, _) = self.curve(k);
            for j in 0..m {
                let t = (j as f64 + 0.5) / m as f64;
                if let Some(junc) = self.cluster_junction(k, t) {
                    let jn = &sec.junctions[junc];
                    if jn.is_singular() {
                        let x = param.eval(sec, t).x();
                        extent = extent.max((x[0] - jn.point[0]).hypot(x[1] - jn.point[1]));
                    }
                }
            }
        }
        extent
    }

    /// |q| on the outer boundary, see [`TorsionSolution::boundary_samples_on`].
    pub fn boundary_samples(&self, m: usize) -> Vec<BoundarySample> {
        self.boundary_samples_on(0, m)
    }

    /// q sampled at `m` equally spaced parameters of curve k with arc length,
    /// graded clusters skipped.
    pub fn boundary_samples_on(&self, k: usize, m: usize) -> Vec<BoundarySample> {
        self.boundary_samples_upto(k, m, m)
    }

    /// The first `count` of [`TorsionSolution::boundary_samples_on`] (one
    /// period of a solution folded by a rotation: the others repeat it).
    fn boundary_samples_upto(&self, k: usize, m: usize, count: usize) -> Vec<BoundarySample> {
        let (sec, param, dens) = self.curve(k);
        let ts: Vec<f64> = (0..count).map(|k| (k as f64 + 0.5) / m as f64).collect();
        let mu = if count < m {
            dens.sample_period(m, 0.5, m / count)
        } else {
            dens.sample(m, 0.5)
        };
        let nodes = param.nodes_upto(sec, m, count);
        let pts: Vec<(BPoint, bool)> = ts
            .par_iter()
            .zip(nodes)
            .map(|(&t, p)| (p, self.in_cluster_on(k, t)))
            .collect();
        // arc length by the trapezoidal rule on the same grid (exact spectrally for smooth |x′|)
        let mut s = 0.0;
        let mut out = Vec::with_capacity(count);
        for j in 0..count {
            let (p, in_cluster) = &pts[j];
            if j > 0 {
                s += 0.5 * (pts[j - 1].0.speed() + p.speed()) / m as f64;
            } else {
                s = 0.5 * p.speed() / m as f64;
            }
            if *in_cluster {
                continue;
            }
            let x = p.x();
            let nrm = p.normal();
            let q = mu[j] / p.speed()
                - ((x[0] - self.centroid[0]) * nrm[0] + (x[1] - self.centroid[1]) * nrm[1]);
            out.push(BoundarySample { t: ts[j], s, x, q });
        }
        out
    }

    /// τ_max = max |q| over every boundary curve on the interpolant (graded
    /// clusters excluded), refined by golden-section search; singular corners
    /// and cusps reported as such, with the largest value at least
    /// [`Options::corner_distance`] from them ([`MaxShear::away`]).
    pub fn max_shear(&self) -> MaxShear {
        let singular_at = self.section.singular_points().first().copied();
        match singular_at {
            Some(p) => {
                let distance = self
                    .options
                    .corner_distance
                    .unwrap_or_else(|| self.section.default_corner_distance());
                MaxShear {
                    value: None,
                    at: Some(p),
                    singular: true,
                    away: self.max_shear_away(distance),
                }
            }
            None => {
                let (value, at) = self.largest_flux(|_| true).unwrap_or((0.0, [0.0, 0.0]));
                MaxShear {
                    value: Some(value),
                    at: Some(at),
                    singular: false,
                    away: None,
                }
            }
        }
    }

    /// The largest boundary τ at least `requested` from every singular
    /// point (None when no part of the boundary is that far from them). A
    /// distance inside the graded clusters of the singular points, where
    /// the boundary values are not resolved, is raised to their extent
    /// ([`TorsionSolution::singular_cluster_extent`]; `AwayShear::distance`
    /// says what was used).
    pub fn max_shear_away(&self, requested: f64) -> Option<AwayShear> {
        let distance = requested.max(self.singular_cluster_extent());
        let points = self.section.singular_points();
        let clear = |x: V2| {
            points
                .iter()
                .all(|p| (x[0] - p[0]).hypot(x[1] - p[1]) >= distance)
        };
        self.largest_flux(clear).map(|(value, at)| AwayShear {
            value,
            at,
            distance,
            requested,
        })
    }

    /// max |q| over the boundary points x with `clear(x)`, graded clusters
    /// excluded: the largest of m = max(8n, 2048) samples per curve, refined
    /// by golden-section search between its neighbours. Where a neighbour
    /// is not clear, the search interval ends where the boundary stops
    /// being clear (found by bisection), and that end is a candidate too:
    /// next to a singular corner the largest value away from it lies on
    /// that edge, and a sample position would make it depend on n.
    fn largest_flux(&self, clear: impl Fn(V2) -> bool) -> Option<(f64, V2)> {
        let m = (8 * self.options.n).max(2048);
        // a solution folded by a k-fold rotation repeats every 1/k of each
        // curve (the boundary and |q| alike): its first period holds the
        // largest value
        let fold = self.symmetry_order.max(1);
        let count = if m.is_multiple_of(fold) { m / fold } else { m };
        let mut best: Option<(f64, f64, V2, usize)> = None;
        for k in 0..self.curve_count() {
            for s in &self.boundary_samples_upto(k, m, count) {
                if best.is_none_or(|b| s.q.abs() > b.0) && clear(s.x) {
                    best = Some((s.q.abs(), s.t, s.x, k));
                }
            }
        }
        let mut best = best?;
        let kc = best.3;
        let (sec, param, _) = self.curve(kc);
        let x_at = |t: f64| param.eval(sec, t).x();
        let f = |t: f64| -> f64 {
            if self.in_cluster_on(kc, t) || !clear(x_at(t)) {
                0.0
            } else {
                self.flux_on(kc, t).1.abs()
            }
        };
        // the bracket [t − 1/m, t + 1/m], each end pulled in to where the
        // boundary is still clear
        let h = 1.0 / m as f64;
        let clip = |inside: f64, outside: f64| -> (f64, bool) {
            if clear(x_at(outside)) {
                return (outside, false);
            }
            let (mut a, mut b) = (inside, outside);
            for _ in 0..60 {
                let c = 0.5 * (a + b);
                if clear(x_at(c)) {
                    a = c;
                } else {
                    b = c;
                }
            }
            (a, true)
        };
        let ((a0, clipped_a), (b0, clipped_b)) =
            (clip(best.1, best.1 - h), clip(best.1, best.1 + h));
        for (t, clipped) in [(a0, clipped_a), (b0, clipped_b)] {
            let v = f(t);
            if clipped && v > best.0 {
                best = (v, t, x_at(t), kc);
            }
        }
        // golden section on [a, b]
        let (mut a, mut b) = (a0, b0);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let (mut fc, mut fd) = (f(c), f(d));
        for _ in 0..80 {
            if fc > fd {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = f(c);
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = f(d);
            }
        }
        let tm = 0.5 * (a + b);
        let vm = f(tm);
        if vm > best.0 {
            best = (vm, tm, x_at(tm), kc);
        }
        Some((best.0, best.2))
    }

    /// u and the stresses at interior points, each checked to lie inside Ω
    /// (a point outside, in a hole or on Γ is an error naming it).
    pub fn interior_checked(&self, points: &[V2]) -> Result<Vec<InteriorValue>, SolveError> {
        for (i, &p) in points.iter().enumerate() {
            let where_ = match self.section.locate(p) {
                PointLocation::Inside => continue,
                PointLocation::Outside => "outside",
                PointLocation::OnBoundary => "on the boundary of",
            };
            return Err(SolveError::PointOutside {
                index: i + 1,
                point: p,
                where_,
            });
        }
        Ok(self.interior(points))
    }

    /// u and the stresses at interior points by the representation formula
    /// over every boundary curve,
    /// u = g(x) − |x − x₀|²/2 + ∮ w q_v ds − ∮ (g(y) − g(x)) ∂w/∂n_y ds
    /// (the hole constants drop out: ∮_{Γ_k} ∂w/∂n_y = 0 outside hole k).
    ///
    /// Quadrature: [`CLOSE_ORDER`]-point Gauss–Legendre on panels of the
    /// parameter, 1/R long on a density of highest frequency R (half a
    /// period of its fastest mode per half panel), and near the point each
    /// panel is halved until its arc length is at most the point's
    /// distance to its nodes. A panel no longer than the distance of the
    /// nearest singularity of the kernel converges like 2.4^{−2·16}
    /// (about 1e-12) or faster, whatever that distance: points 1e-10 from
    /// Γ take about 30 halvings. (The trapezoidal rule on m nodes per curve
    /// used before needed m ∝ 1/distance and was capped at 2²² nodes: past
    /// about 2e-5 of Γ it returned τ up to 50 % off, unflagged.) The
    /// density is a trigonometric polynomial, evaluated exactly at any
    /// parameter.
    pub fn interior(&self, points: &[V2]) -> Vec<InteriorValue> {
        // the panels cost O(n²) density evaluations: none without points
        if points.is_empty() {
            return Vec::new();
        }
        let (gx, gw) = crate::quadrature::gauss_legendre_01(CLOSE_ORDER);
        let rule = Rule { x: &gx, w: &gw };
        let base: Vec<Vec<Panel>> = (0..self.curve_count())
            .map(|k| {
                let (sec, param, dens) = self.curve(k);
                let count = dens.max_freq.max(MIN_PANELS);
                (0..count)
                    .into_par_iter()
                    .map(|i| {
                        let span = (i as f64 / count as f64, (i + 1) as f64 / count as f64);
                        Panel::new(sec, param, dens, span, &rule)
                    })
                    .collect()
            })
            .collect();
        let x0 = self.centroid;
        let size = base
            .iter()
            .flatten()
            .flat_map(|p| &p.nodes)
            .map(|n| (n.y[0] - x0[0]).hypot(n.y[1] - x0[1]))
            .fold(0.0f64, f64::max);
        points
            .par_iter()
            .map(|&x| {
                let mut sum = [0.0; 3];
                let mut distance = f64::INFINITY;
                for (k, panels) in base.iter().enumerate() {
                    let curve = self.curve(k);
                    for p in panels {
                        distance = distance.min(self.panel_sum(x, p, curve, &rule, 0, &mut sum));
                    }
                }
                InteriorValue {
                    x,
                    u: sum[0],
                    tau_xz: sum[2],
                    tau_yz: -sum[1],
                    distance,
                    round_off: f64::EPSILON * size / distance,
                }
            })
            .collect()
    }

    /// Adds the representation formula's terms (u, ∂u/∂x, ∂u/∂y) of
    /// `panel` at `x` to `sum`, halving the panel (to [`MAX_HALVINGS`])
    /// while it is longer than the distance from x to its nodes; returns
    /// the least distance from x to the nodes used.
    fn panel_sum(
        &self,
        x: V2,
        panel: &Panel,
        curve: (&Section, &Parametrisation, &FourierDensity),
        rule: &Rule<'_>,
        depth: usize,
        sum: &mut [f64; 3],
    ) -> f64 {
        let near = panel
            .nodes
            .iter()
            .map(|n| (x[0] - n.y[0]).hypot(x[1] - n.y[1]))
            .fold(f64::INFINITY, f64::min);
        if panel.length > near && depth < MAX_HALVINGS {
            let (a, b) = panel.span;
            let mid = 0.5 * (a + b);
            let (sec, param, dens) = curve;
            return [(a, mid), (mid, b)]
                .into_iter()
                .map(|span| {
                    let half = Panel::new(sec, param, dens, span, rule);
                    self.panel_sum(x, &half, curve, rule, depth + 1, sum)
                })
                .fold(f64::INFINITY, f64::min);
        }
        let x0 = self.centroid;
        // v(x) = g(x) + ∮ [w μ − (g(y) − g(x)) k] dt, with ∮ ∂w/∂n_y = −1 inside Ω;
        // u = v − g
        let gx = 0.5 * ((x[0] - x0[0]).powi(2) + (x[1] - x0[1]).powi(2));
        let grad_g = [x[0] - x0[0], x[1] - x0[1]];
        for nd in &panel.nodes {
            let (y, d1) = (nd.y, nd.d1);
            let d = [x[0] - y[0], x[1] - y[1]];
            let r2 = d[0] * d[0] + d[1] * d[1];
            let nl = [d1[1], -d1[0]]; // n |y′|
            let w = -(r2.ln()) / (4.0 * PI);
            let gw = [-d[0] / (2.0 * PI * r2), -d[1] / (2.0 * PI * r2)];
            let dn = d[0] * nl[0] + d[1] * nl[1];
            let kk = dn / (2.0 * PI * r2);
            let gk = [
                (nl[0] - 2.0 * d[0] * dn / r2) / (2.0 * PI * r2),
                (nl[1] - 2.0 * d[1] * dn / r2) / (2.0 * PI * r2),
            ];
            let gy = 0.5 * ((y[0] - x0[0]).powi(2) + (y[1] - x0[1]).powi(2));
            let dg = gy - gx;
            sum[0] += nd.weight * (w * nd.mu - dg * kk);
            sum[1] += nd.weight * (gw[0] * nd.mu + grad_g[0] * kk - dg * gk[0]);
            sum[2] += nd.weight * (gw[1] * nd.mu + grad_g[1] * kk - dg * gk[1]);
        }
        near
    }
}

/// Gauss–Legendre points per panel of the interior evaluation.
const CLOSE_ORDER: usize = 16;

/// Fewest panels per curve in the interior evaluation.
const MIN_PANELS: usize = 64;

/// Most halvings of a panel toward an interior point (2^−60 of a panel:
/// far below the distance at which a point counts as on Γ).
const MAX_HALVINGS: usize = 60;

/// A Gauss–Legendre rule on [0, 1].
struct Rule<'a> {
    x: &'a [f64],
    w: &'a [f64],
}

/// One quadrature node: position, x′(t), density μ(t) and weight (dt).
struct Node {
    y: V2,
    d1: V2,
    mu: f64,
    weight: f64,
}

/// A panel [a, b] of a curve's parameter with its Gauss–Legendre nodes.
struct Panel {
    span: (f64, f64),
    nodes: Vec<Node>,
    /// arc length (by the same rule)
    length: f64,
}

impl Panel {
    fn new(
        sec: &Section,
        param: &Parametrisation,
        dens: &FourierDensity,
        span: (f64, f64),
        rule: &Rule<'_>,
    ) -> Panel {
        let (a, b) = span;
        let nodes: Vec<Node> = rule
            .x
            .iter()
            .zip(rule.w)
            .map(|(&s, &w)| {
                let t = a + (b - a) * s;
                let p = param.eval(sec, t);
                Node {
                    y: p.x(),
                    d1: p.d1,
                    mu: dens.eval(t),
                    weight: w * (b - a),
                }
            })
            .collect();
        let length = nodes
            .iter()
            .map(|n| n.weight * n.d1[0].hypot(n.d1[1]))
            .sum();
        Panel {
            span,
            nodes,
            length,
        }
    }
}
