//! Global periodic parametrisation t ∈ [0, 1) of a section with Kress's
//! sigmoidal grading at corners and cusps.
//!
//! Piece k occupies the panel [b_k, b_{k+1}] of t (its share is half its
//! fraction of the arc length plus half of 1/m for m pieces, rounded to multiples of 2⁻²⁰ so that half-shifted nodes (j + ½)/n
//! never fall on a corner for n ≤ 2¹⁹). On a graded panel the local
//! s = (t − b_k)/(b_{k+1} − b_k) is mapped by
//!
//! ```text
//! v(s) = (1/p − 1/2)(1 − 2s)³ + (1/p)(2s − 1) + 1/2,   w(s) = v^p / (v^p + (1 − v)^p)
//! ```
//!
//! whose derivatives vanish to order p − 1 at s = 0, 1. For s ≤ ½ we use the
//! cancellation-free form v = s[(3 − 4/p) + (1/p − 1/2)(12s − 8s²)] and the
//! symmetry v(1 − s) = 1 − v(s); points are stored as offsets from the nearer
//! corner ([`BPoint`]), so graded nodes keep full relative precision even
//! within 1e-22 of the vertex.

use crate::geometry::{End, Section, V2};
use rayon::prelude::*;
use std::sync::Arc;

/// A boundary point: position `anchor + offset`, with derivatives in t.
#[derive(Clone, Copy, Debug)]
pub struct BPoint {
    /// nearest junction (or piece end) the point is measured from
    pub anchor: V2,
    /// offset from the anchor, computed without cancellation
    pub offset: V2,
    /// dx/dt
    pub d1: V2,
    /// d²x/dt²
    pub d2: V2,
}

impl BPoint {
    /// Absolute position.
    #[inline]
    pub fn x(&self) -> V2 {
        [
            self.anchor[0] + self.offset[0],
            self.anchor[1] + self.offset[1],
        ]
    }
    /// |dx/dt|.
    #[inline]
    pub fn speed(&self) -> f64 {
        self.d1[0].hypot(self.d1[1])
    }
    /// Outward unit normal (boundary traversed counter-clockwise).
    #[inline]
    pub fn normal(&self) -> V2 {
        let s = self.speed();
        [self.d1[1] / s, -self.d1[0] / s]
    }
}

/// x(a) − x(b), exact when both points share an anchor.
#[inline]
pub fn diff(a: &BPoint, b: &BPoint) -> V2 {
    if a.anchor == b.anchor {
        [a.offset[0] - b.offset[0], a.offset[1] - b.offset[1]]
    } else {
        [
            (a.anchor[0] - b.anchor[0]) + (a.offset[0] - b.offset[0]),
            (a.anchor[1] - b.anchor[1]) + (a.offset[1] - b.offset[1]),
        ]
    }
}

/// Kress sigmoid on [0, ½]: (w, dw/ds, d²w/ds²) for s ≤ ½ with w(s) ≤ ½.
pub fn kress(s: f64, p: f64) -> (f64, f64, f64) {
    if s <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let a = 1.0 / p - 0.5;
    let v = s * ((3.0 - 4.0 / p) + a * (12.0 * s - 8.0 * s * s));
    let dv = (3.0 - 4.0 / p) + a * (24.0 * s - 24.0 * s * s);
    let ddv = a * (24.0 - 48.0 * s);
    let omv = 1.0 - v;
    let r = (v / omv).powf(p);
    let w = r / (1.0 + r);
    // w' = p r/(1+r)² · v'/(v(1−v))
    let lr = p * dv / (v * omv);
    let dw = r / ((1.0 + r) * (1.0 + r)) * lr;
    // (ln w')' = (1 − 2r/(1+r)) p v'/(v(1−v)) + v''/v' − v'/v + v'/(1−v)
    let g = (1.0 - 2.0 * r / (1.0 + r)) * lr + ddv / dv - dv / v + dv / omv;
    (w, dw, dw * g)
}

/// Corner-zone width of [`ZoneMap`] panels, in mean wall thicknesses.
pub const ZONE_WALLS: f64 = 3.0;

/// Largest corner zone, as a fraction of its panel, that replaces Kress's
/// map: panels shorter than `ZONE_WALLS / ZONE_MAX_DELTA` = 10 wall
/// thicknesses keep it.
pub const ZONE_MAX_DELTA: f64 = 0.3;

/// Smallest corner zone, as a fraction of its panel, that is used: a wall
/// 1/3000 of its panel long needs more than 12 000 nodes per curve.
pub const ZONE_MIN_DELTA: f64 = 1e-3;

/// The wall thickness of every piece of every curve of `section` (outer
/// boundary, then holes) when its graded panels may use [`ZoneMap`]: only
/// for sections with a re-entrant corner (boxes, I, channels, L: their
/// τ_max is singular and not reported). On a thin rectangle the zone map
/// made τ_max, the boundary maximum, converge at 2^−5.4 per doubling
/// between n = 512 and 1024 (1 × 0.02), slower than τ's rate floor 2^−7,
/// so that its estimate fell short (5.8e-9 reported, 8.7e-9 true); convex
/// sections keep Kress's map.
///
/// Every piece gets the mean wall thickness 2A/P of the whole section,
/// unless some wall is much thinner than that mean (below 1/[`MIXED_WALLS`]
/// of it) on a section of at most [`MIXED_WALLS_MAX_PIECES`] pieces: then
/// every piece gets its own thickness, see [`local_walls`].
/// Measured (2026-11-27, `--tol 1e-8`): the box 2 × 1 with flanges 0.1 and
/// webs 0.02 needed n = 4096 per curve with the mean (7.4 s); boxes whose
/// walls differ less converge as fast or faster with the mean (the bench
/// box, flanges 0.1 and webs 0.05: n = 1024 at 1e-10 with the mean, 2048
/// with local walls).
pub fn zone_walls(section: &Section) -> Option<Vec<Vec<f64>>> {
    if !section.is_singular() {
        return None;
    }
    let mean = 2.0 * section.area / section.total_perimeter();
    if !(mean.is_finite() && mean > 0.0) {
        return None;
    }
    let pieces: usize = section.curves().iter().map(|c| c.pieces.len()).sum();
    let everywhere = |w: f64| -> Vec<Vec<f64>> {
        section
            .curves()
            .iter()
            .map(|c| vec![w; c.pieces.len()])
            .collect()
    };
    // the local thickness costs (pieces)² distances, at every rung: only
    // for sections of few pieces (boxes, I, channels: 4–16)
    if pieces > MIXED_WALLS_MAX_PIECES {
        return Some(everywhere(mean));
    }
    let local = local_walls(section);
    let thinnest = local
        .iter()
        .flatten()
        .copied()
        .fold(f64::INFINITY, f64::min);
    if thinnest.is_finite() && thinnest > 0.0 && thinnest * MIXED_WALLS < mean {
        Some(local)
    } else {
        Some(everywhere(mean))
    }
}

/// Sections of more pieces than this (over all curves) keep the mean wall
/// thickness in [`zone_walls`]: a polygon of 2400 vertices with a
/// re-entrant corner took 5.5 s instead of 2.2 s computing the local
/// thickness at every rung.
pub const MIXED_WALLS_MAX_PIECES: usize = 64;

/// A wall thinner than 1/`MIXED_WALLS` of the section's mean wall
/// thickness makes [`zone_walls`] take every piece's own thickness.
pub const MIXED_WALLS: f64 = 3.0;

/// The thickness of every piece of every curve: the least distance from its
/// points at 0.3 … 0.7 of its length to the other pieces of every curve,
/// its two neighbours on its own curve excluded (they meet it at its
/// corners). Segments are exact, curved pieces are taken as 32 chords.
fn local_walls(section: &Section) -> Vec<Vec<f64>> {
    let curves = section.curves();
    let lines: Vec<Vec<Vec<V2>>> = curves
        .iter()
        .map(|c| {
            c.pieces
                .iter()
                .map(|q| match q {
                    crate::geometry::Piece::Segment { a, b } => vec![*a, *b],
                    _ => (0..=32).map(|i| q.point(i as f64 / 32.0)[0]).collect(),
                })
                .collect()
        })
        .collect();
    let dist = |x: V2, line: &[V2]| -> f64 {
        line.windows(2)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                let d = [b[0] - a[0], b[1] - a[1]];
                let l2 = d[0] * d[0] + d[1] * d[1];
                let t = if l2 > 0.0 {
                    (((x[0] - a[0]) * d[0] + (x[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (x[0] - a[0] - t * d[0]).hypot(x[1] - a[1] - t * d[1])
            })
            .fold(f64::INFINITY, f64::min)
    };
    curves
        .iter()
        .enumerate()
        .map(|(ci, c)| {
            let m = c.pieces.len();
            (0..m)
                .map(|k| {
                    let mut best = f64::INFINITY;
                    for i in 0..5 {
                        let x = c.pieces[k].point(0.3 + 0.1 * i as f64)[0];
                        for (cj, other) in lines.iter().enumerate() {
                            for (j, line) in other.iter().enumerate() {
                                let near =
                                    cj == ci && (j == k || j == (k + 1) % m || (j + 1) % m == k);
                                if !near {
                                    best = best.min(dist(x, line));
                                }
                            }
                        }
                    }
                    best
                })
                .collect()
        })
        .collect()
}

/// The corner zone δ (a fraction of the panel) of a graded panel `len`
/// long on walls `wall` thick, if it gets one: below [`ZONE_MIN_DELTA`] the
/// wall would need more nodes than a dense solve reaches (and the table
/// would be large), above [`ZONE_MAX_DELTA`] the panel is too short.
fn zone_delta(len: f64, wall: f64) -> Option<f64> {
    let delta = ZONE_WALLS * wall / len;
    (delta.is_finite() && (ZONE_MIN_DELTA..=ZONE_MAX_DELTA).contains(&delta)).then_some(delta)
}

/// Gauss–Legendre points per cell of [`ZoneMap`]'s cumulative integral.
const ZONE_POINTS: usize = 8;

/// A graded panel map with a short corner zone and a flat middle: speed
/// σ(s) = [tanh(s/δ) tanh((1 − s)/δ)]^{p−1}, w(s) = ∫₀ˢ σ / ∫₀¹ σ.
///
/// Near a corner σ ≈ (s/δ)^{p−1}, so w ~ s^p: graded to the same order p as
/// [`kress`]. Beyond a few δ the speed is 1/∫₀¹σ ≈ 1 + O(δ): the middle of
/// the panel gets the mean node spacing, where Kress's map gives it twice
/// that (w′(½) = 2). Thin walls need their node spacing in the middle of
/// the panels (about 4 nodes per thickness), so for them the zone map
/// halves the n that the walls ask for. The integral is tabulated on cells
/// of width ≤ δ/8 (σ is analytic within πδ/2 of the real axis, 12 cell
/// half-widths) and completed per point by 8-point Gauss–Legendre, which
/// keeps full relative precision near s = 0 (σ ~ s^{p−1} there).
#[derive(Clone, Debug)]
pub struct ZoneMap {
    p: f64,
    delta: f64,
    cell: f64,
    /// ∫₀^{c·cell} σ for c = 0..=cells
    cum: Vec<f64>,
    /// ∫₀¹ σ = 2 ∫₀^½ σ
    total: f64,
    gl: (Vec<f64>, Vec<f64>),
}

impl ZoneMap {
    /// The map of grading order `p` with corner zone `delta` (in panel units, 0 < δ ≤ ½).
    pub fn new(p: f64, delta: f64) -> ZoneMap {
        let cells = ((0.5 / (0.125 * delta)).ceil() as usize).clamp(1, 8192);
        let cell = 0.5 / cells as f64;
        let mut z = ZoneMap {
            p,
            delta,
            cell,
            cum: Vec::with_capacity(cells + 1),
            total: 0.0,
            gl: crate::quadrature::gauss_legendre_01(ZONE_POINTS),
        };
        let mut acc = 0.0;
        z.cum.push(0.0);
        for c in 0..cells {
            acc += z.integral_between(c as f64 * cell, (c + 1) as f64 * cell);
            z.cum.push(acc);
        }
        z.total = 2.0 * acc;
        z
    }

    fn speed(&self, s: f64) -> f64 {
        let a = (s / self.delta).tanh();
        let b = ((1.0 - s) / self.delta).tanh();
        self.speed_of(a, b)
    }

    /// [tanh(s/δ) tanh((1 − s)/δ)]^{p−1} from the two factors a, b.
    fn speed_of(&self, a: f64, b: f64) -> f64 {
        let e = self.p - 1.0;
        if e == e.round() && (0.0..=32.0).contains(&e) {
            (a * b).powi(e as i32)
        } else {
            (a * b).powf(e)
        }
    }

    fn integral_between(&self, a: f64, b: f64) -> f64 {
        let (x, w) = &self.gl;
        (b - a)
            * x.iter()
                .zip(w)
                .map(|(xi, wi)| wi * self.speed(a + (b - a) * xi))
                .sum::<f64>()
    }

    /// dw/ds for 0 ≤ s ≤ ½: the second entry of [`ZoneMap::eval`], the
    /// same bits.
    pub fn eval_speed(&self, s: f64) -> f64 {
        if s <= 0.0 {
            return 0.0;
        }
        self.speed(s.min(0.5)) / self.total
    }

    /// (w, dw/ds, d²w/ds²) for 0 ≤ s ≤ ½ (w(½) = ½ exactly).
    pub fn eval(&self, s: f64) -> (f64, f64, f64) {
        if s <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let s = s.min(0.5);
        let c = ((s / self.cell) as usize).min(self.cum.len() - 2);
        let w = if s == 0.5 {
            0.5
        } else {
            (self.cum[c] + self.integral_between(c as f64 * self.cell, s)) / self.total
        };
        let (a, b) = ((s / self.delta).tanh(), ((1.0 - s) / self.delta).tanh());
        let sp = self.speed_of(a, b);
        // (ln σ)′ = (p − 1)/δ [(1 − a²)/a − (1 − b²)/b]
        let g = (self.p - 1.0) / self.delta * ((1.0 - a * a) / a - (1.0 - b * b) / b);
        (w, sp / self.total, sp * g / self.total)
    }
}

/// The graded periodic parametrisation of a section.
#[derive(Clone, Debug)]
pub struct Parametrisation {
    /// panel break points b_0 = 0 < b_1 < … < b_m = 1
    pub breaks: Vec<f64>,
    /// grading exponent per panel (None: identity map)
    pub grading: Vec<Option<f64>>,
    /// the corner-zone map of a graded panel, where it replaces Kress's
    zones: Vec<Option<Arc<ZoneMap>>>,
    anchors: Vec<V2>,
    /// Some(m): the breaks are exactly k/m (pieces of equal length, see
    /// [`Parametrisation::exact_for`]), and the nodes of an n divisible by
    /// m take their panel coordinates from their indices
    uniform: Option<usize>,
}

impl Parametrisation {
    /// Builds the parametrisation with grading exponent `p` at graded junctions.
    pub fn new(section: &Section, p: f64) -> Parametrisation {
        let m = section.pieces.len();
        let lens: Vec<f64> = section.pieces.iter().map(|q| q.length()).collect();
        let total: f64 = lens.iter().sum();
        let scale = (1u64 << 20) as f64;
        // panel shares: half by arc length, half uniform, so that short
        // pieces (each with two graded corner clusters) keep enough nodes
        let mut breaks = vec![0.0];
        let mut acc = 0.0;
        // ungraded polygons: by arc length alone (the speed is then the same on every panel)
        let by_length = section.nearly_smooth_polygon();
        for (k, l) in lens.iter().enumerate() {
            acc += if by_length {
                l / total
            } else {
                0.5 * (l / total + 1.0 / m as f64)
            };
            let b = if k + 1 == m {
                1.0
            } else if by_length {
                // no corner cluster to keep off the nodes; rounding would make the speed jump
                acc
            } else {
                (acc * scale).round() / scale
            };
            let prev = *breaks.last().unwrap_or(&0.0);
            breaks.push(if b > prev { b } else { prev + 1.0 / scale });
        }
        let grading = section
            .graded_junctions()
            .into_iter()
            .map(|g| if g { Some(p) } else { None })
            .collect();
        let anchors = section.junctions.iter().map(|j| j.point).collect();
        Parametrisation {
            breaks,
            grading,
            zones: vec![None; m],
            anchors,
            uniform: None,
        }
    }

    /// For `n` nodes that are not a power of two (the rungs q 2^j of a
    /// section with a rotational symmetry of odd order q, see
    /// [`crate::control::rung_base`]): on a curve of m pieces of equal
    /// length with m dividing n, the breaks become exactly k/m (instead of
    /// multiples of 2^−20, which keep the panel coordinates of dyadic
    /// nodes exact) and every panel holds n/m nodes whose panel coordinates
    /// (i + ½)/(n/m) come from their indices: the same on every panel, so
    /// that a rotation of the section by 2π/m is a shift by n/m nodes to
    /// round-off. Otherwise unchanged.
    pub fn exact_for(mut self, section: &Section, n: usize) -> Parametrisation {
        let m = section.pieces.len();
        if n.is_power_of_two() || m < 2 || !n.is_multiple_of(m) {
            return self;
        }
        if !section.pieces_of_equal_length() || section.nearly_smooth_polygon() {
            return self;
        }
        self.breaks = (0..=m).map(|k| k as f64 / m as f64).collect();
        self.uniform = Some(m);
        self
    }

    /// [`Parametrisation::new`] with corner zones: with `walls = Some(d)`
    /// (the wall thickness of each piece of this curve, see [`zone_walls`])
    /// every graded panel at least `ZONE_WALLS / ZONE_MAX_DELTA` of its wall
    /// thicknesses long gets the [`ZoneMap`] with a corner zone of
    /// [`ZONE_WALLS`] wall thicknesses instead of Kress's map.
    pub fn with_zones(section: &Section, p: f64, walls: Option<&[f64]>) -> Parametrisation {
        let mut par = Parametrisation::new(section, p);
        let Some(walls) = walls else { return par };
        for (k, piece) in section.pieces.iter().enumerate() {
            let Some(p) = par.grading[k] else { continue };
            let Some(&wall) = walls.get(k) else { continue };
            if let Some(delta) = zone_delta(piece.length(), wall) {
                par.zones[k] = Some(Arc::new(ZoneMap::new(p, delta)));
            }
        }
        par
    }

    /// Whether [`Parametrisation::with_zones`] gives some panel of the
    /// curve `section` a corner zone for the piece walls `walls` (without
    /// building the maps).
    pub fn would_zone(section: &Section, walls: &[f64]) -> bool {
        section
            .graded_junctions()
            .iter()
            .zip(&section.pieces)
            .zip(walls)
            .any(|((&graded, piece), &wall)| graded && zone_delta(piece.length(), wall).is_some())
    }

    /// Number of panels that use the corner-zone map.
    pub fn zoned_panels(&self) -> usize {
        self.zones.iter().filter(|z| z.is_some()).count()
    }

    /// (w, dw/ds, d²w/ds²) of panel k's map at σ ≤ ½ from its nearer end.
    pub fn panel_map(&self, k: usize, sig: f64) -> (f64, f64, f64) {
        match (&self.zones[k], self.grading[k]) {
            (Some(z), _) => z.eval(sig),
            (None, Some(p)) => kress(sig, p),
            (None, None) => (sig, 1.0, 0.0),
        }
    }

    /// dw/ds of panel k's map at σ ≤ ½ from its nearer end: the second
    /// entry of [`Parametrisation::panel_map`], without the map itself (a
    /// corner zone's map is an integral, its speed a closed form).
    pub fn panel_speed(&self, k: usize, sig: f64) -> f64 {
        match (&self.zones[k], self.grading[k]) {
            (Some(z), _) => z.eval_speed(sig),
            (None, Some(p)) => kress(sig, p).1,
            (None, None) => 1.0,
        }
    }

    /// Index of the panel holding t ∈ [0, 1).
    pub fn panel(&self, t: f64) -> usize {
        let m = self.breaks.len() - 1;
        let idx = self.breaks.partition_point(|&b| b <= t);
        idx.saturating_sub(1).min(m - 1)
    }

    /// Local coordinate of t in its panel, for excluding graded clusters:
    /// returns (panel, s ∈ [0, 1]).
    pub fn local(&self, t: f64) -> (usize, f64) {
        let t = t.rem_euclid(1.0);
        let k = self.panel(t);
        (
            k,
            (t - self.breaks[k]) / (self.breaks[k + 1] - self.breaks[k]),
        )
    }

    /// Evaluates the boundary at t (taken modulo 1).
    pub fn eval(&self, section: &Section, t: f64) -> BPoint {
        let t = t.rem_euclid(1.0);
        let k = self.panel(t);
        let (b0, b1) = (self.breaks[k], self.breaks[k + 1]);
        let db = b1 - b0;
        let s0 = (t - b0) / db;
        let (end, sig) = if s0 <= 0.5 {
            (End::Start, s0)
        } else {
            (End::End, (b1 - t) / db)
        };
        self.eval_local(section, k, end, sig, db)
    }

    /// The point of panel k (parameter length `db`) at the coordinate
    /// `sig` ≤ ½ from its end `end`.
    fn eval_local(&self, section: &Section, k: usize, end: End, sig: f64, db: f64) -> BPoint {
        self.eval_mapped(section, k, end, self.panel_map(k, sig), db)
    }

    /// [`Parametrisation::eval_local`] with the panel map's values
    /// (w, dw/ds, d²w/ds²) at the coordinate given.
    fn eval_mapped(
        &self,
        section: &Section,
        k: usize,
        end: End,
        (om, dw, ddw): (f64, f64, f64),
        db: f64,
    ) -> BPoint {
        let m = self.breaks.len() - 1;
        let piece = &section.pieces[k];
        // dw/ds for the global direction: w = ω near the start, w = 1 − ω(σ) with σ = 1 − s near the end
        let ddw = if end == End::Start { ddw } else { -ddw };
        let [off, xw, xww] = piece.eval(end, om);
        let anchor = if end == End::Start {
            self.anchors[k]
        } else {
            self.anchors[(k + 1) % m]
        };
        let ws = dw / db;
        let wss = ddw / (db * db);
        BPoint {
            anchor,
            offset: off,
            d1: [xw[0] * ws, xw[1] * ws],
            d2: [
                xww[0] * ws * ws + xw[0] * wss,
                xww[1] * ws * ws + xw[1] * wss,
            ],
        }
    }

    /// The half-shifted nodes t_j = (j + ½)/n evaluated on the boundary.
    pub fn nodes(&self, section: &Section, n: usize) -> Vec<BPoint> {
        self.nodes_upto(section, n, n)
    }

    /// The first `count` (≤ n) of [`Parametrisation::nodes`].
    pub fn nodes_upto(&self, section: &Section, n: usize, count: usize) -> Vec<BPoint> {
        if let Some(m) = self.uniform.filter(|m| n.is_multiple_of(*m)) {
            // n/m nodes per panel, their coordinates from their indices
            let per = n / m;
            let (pf, db) = (per as f64, 1.0 / m as f64);
            let at = |i: usize| {
                if 2 * i < per {
                    (End::Start, (i as f64 + 0.5) / pf)
                } else {
                    (End::End, ((per - i) as f64 - 0.5) / pf)
                }
            };
            // every panel with the same map (a regular N-gon): the map's
            // values once per position in the panel, not once per node
            let same = self.zones.iter().all(|z| z.is_none())
                && self.grading.iter().all(|g| *g == self.grading[0]);
            if same {
                let maps: Vec<(f64, f64, f64)> =
                    (0..per).map(|i| self.panel_map(0, at(i).1)).collect();
                return (0..count)
                    .into_par_iter()
                    .map(|j| {
                        let (k, i) = (j / per, j % per);
                        self.eval_mapped(section, k, at(i).0, maps[i], db)
                    })
                    .collect();
            }
            return (0..count)
                .map(|j| {
                    let (k, i) = (j / per, j % per);
                    let (end, sig) = at(i);
                    self.eval_local(section, k, end, sig, db)
                })
                .collect();
        }
        (0..count)
            .into_par_iter()
            .map(|j| self.eval(section, (j as f64 + 0.5) / n as f64))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn kress_derivatives_match_finite_differences() {
        for &p in &[4.0, 6.0, 8.0] {
            for &s in &[0.05, 0.2, 0.37, 0.49] {
                let h = 1e-6;
                let (w, dw, ddw) = kress(s, p);
                let (wp, dwp, _) = kress(s + h, p);
                let (wm, dwm, _) = kress(s - h, p);
                assert!(
                    ((wp - wm) / (2.0 * h) - dw).abs() < 1e-7 * (1.0 + dw.abs()),
                    "p={p} s={s}"
                );
                assert!(
                    ((dwp - dwm) / (2.0 * h) - ddw).abs() < 1e-6 * (1.0 + ddw.abs()),
                    "p={p} s={s}"
                );
                assert!(w > 0.0 && w <= 0.5);
            }
            // symmetric point
            let (w, _, _) = kress(0.5, p);
            assert!((w - 0.5).abs() < 1e-15);
            // tiny s: w ~ C s^p with full relative precision (no cancellation)
            let (w1, _, _) = kress(1e-4, p);
            let (w2, _, _) = kress(2e-4, p);
            assert!((w2 / w1 - 2f64.powf(p)).abs() / 2f64.powf(p) < 1e-3);
        }
    }

    #[test]
    fn zone_map_is_graded_flat_in_the_middle_and_consistent() {
        for &(p, delta) in &[(8.0, 0.01), (8.0, 0.08), (6.0, 0.03), (4.0, 0.2)] {
            let z = ZoneMap::new(p, delta);
            // derivatives against central differences of w and w′
            for s in [0.3 * delta, delta, 3.0 * delta, 0.2, 0.45] {
                if s >= 0.49 {
                    continue;
                }
                let h = 1e-6 * delta.min(s);
                let (_, dw, ddw) = z.eval(s);
                // the speed alone is the same number
                assert_eq!(z.eval_speed(s).to_bits(), dw.to_bits(), "speed at {s}");
                let (wp, dwp, _) = z.eval(s + h);
                let (wm, dwm, _) = z.eval(s - h);
                assert!(
                    ((wp - wm) / (2.0 * h) - dw).abs() <= 1e-7 * (1.0 + dw),
                    "p={p} δ={delta} s={s}"
                );
                assert!(
                    ((dwp - dwm) / (2.0 * h) - ddw).abs() <= 1e-5 * (1.0 + ddw.abs() + dw / delta),
                    "p={p} δ={delta} s={s}"
                );
            }
            // w(½) = ½, monotone, and the tabulated integral matches a fresh
            // quadrature on [0, s] (cell boundaries do not show)
            assert_eq!(z.eval(0.5).0, 0.5);
            let mut last = 0.0;
            for i in 1..=1000 {
                let s = 0.5 * i as f64 / 1000.0;
                let (w, dw, _) = z.eval(s);
                assert!(w > last && dw > 0.0, "p={p} δ={delta} s={s}");
                last = w;
            }
            // graded to order p: w(2s)/w(s) → 2^p as s → 0, to full relative precision
            let (w1, _, _) = z.eval(1e-3 * delta);
            let (w2, _, _) = z.eval(2e-3 * delta);
            assert!((w2 / w1 - 2f64.powf(p)).abs() / 2f64.powf(p) < 1e-4);
            // the middle speed is the mean one up to O(δ) (1/(1 − 3.3δ) at
            // p = 8): Kress's is 2
            let (_, mid, _) = z.eval(0.5);
            assert!(mid > 1.0, "p={p} δ={delta}: {mid}");
            if delta <= 0.08 {
                assert!(mid < 1.0 + 5.0 * delta, "p={p} δ={delta}: {mid}");
            }
        }
    }
}
