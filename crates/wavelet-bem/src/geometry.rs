//! Boundary pieces and sections: closed, counter-clockwise, piecewise
//! parametrisations with analytic x, x′, x″ on every piece.
//!
//! Each piece is parametrised by a local w ∈ [0, 1]. Points are returned as an
//! *offset from the nearer end* of the piece, computed without cancellation, so
//! that graded nodes which approach a corner to within 1e-22 keep their relative
//! position exactly (see [`crate::grading`]).

use crate::error::GeometryError;
use crate::polyline::{first_crossing, polyline, polyline_distance, polylines_cross, winding};
use crate::quadrature::{composite_gauss_01, gauss_legendre_01};
use std::f64::consts::{PI, TAU};
use std::sync::Arc;

/// A 2-vector.
pub type V2 = [f64; 2];

/// Which end of a piece a local offset is measured from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// The start, w = 0; the point is at w = ω.
    Start,
    /// The end, w = 1; the point is at w = 1 − ω.
    End,
}

/// A user curve: τ ∈ [0, 1] ↦ (x, dx/dτ, d²x/dτ²).
pub type CurveFn = dyn Fn(f64) -> [V2; 3] + Send + Sync;

/// One piece of a boundary.
#[derive(Clone)]
pub enum Piece {
    /// Straight segment from `a` to `b`.
    Segment {
        /// start point
        a: V2,
        /// end point
        b: V2,
    },
    /// Circular arc x = c + r (cos θ, sin θ), θ from `theta0` to `theta1`
    /// (counter-clockwise when `theta1 > theta0`).
    Arc {
        /// centre
        center: V2,
        /// radius r > 0
        radius: f64,
        /// start angle (rad)
        theta0: f64,
        /// end angle (rad)
        theta1: f64,
    },
    /// Elliptic arc x = c + R(φ) (a cos t, b sin t), t from `t0` to `t1`.
    Ellipse {
        /// centre
        center: V2,
        /// semi-axis along the rotated x axis
        a: f64,
        /// semi-axis along the rotated y axis
        b: f64,
        /// rotation φ (rad)
        rotation: f64,
        /// start parameter
        t0: f64,
        /// end parameter
        t1: f64,
    },
    /// The closed limaçon z = A (e^{iθ} + c e^{2iθ}) + z₀, θ from `theta0` to
    /// `theta0 + 2π` (reversed when `reversed`).
    Limacon {
        /// scale A > 0
        scale: f64,
        /// shape parameter 0 ≤ c ≤ ½ (½ is the cardioid)
        c: f64,
        /// translation z₀
        shift: V2,
        /// starting angle
        theta0: f64,
        /// traversed clockwise (w ↦ θ0 − 2πw)
        reversed: bool,
    },
    /// A smooth user curve (offsets by plain subtraction).
    Parametric {
        /// the curve
        curve: Arc<CurveFn>,
        /// traversed backwards (w ↦ 1 − w)
        reversed: bool,
    },
}

impl std::fmt::Debug for Piece {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Piece::Segment { a, b } => write!(f, "Segment({a:?} -> {b:?})"),
            Piece::Arc {
                center,
                radius,
                theta0,
                theta1,
            } => {
                write!(f, "Arc(c={center:?}, r={radius}, {theta0} -> {theta1})")
            }
            Piece::Ellipse {
                center,
                a,
                b,
                rotation,
                t0,
                t1,
            } => {
                write!(
                    f,
                    "Ellipse(c={center:?}, a={a}, b={b}, rot={rotation}, {t0} -> {t1})"
                )
            }
            Piece::Limacon { scale, c, .. } => write!(f, "Limacon(A={scale}, c={c})"),
            Piece::Parametric { .. } => write!(f, "Parametric"),
        }
    }
}

#[inline]
fn rot(v: V2, phi: f64) -> V2 {
    let (s, c) = phi.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

/// cos(α + δ) − cos α and sin(α + δ) − sin α without cancellation.
#[inline]
fn trig_diff(alpha: f64, delta: f64) -> V2 {
    let s = (0.5 * delta).sin();
    let mid = alpha + 0.5 * delta;
    [-2.0 * mid.sin() * s, 2.0 * mid.cos() * s]
}

impl Piece {
    /// Offset of the point at distance ω (in w) from the given end, measured
    /// from that end point, with dx/dw and d²x/dw² there.
    pub fn eval(&self, end: End, omega: f64) -> [V2; 3] {
        let w = match end {
            End::Start => omega,
            End::End => 1.0 - omega,
        };
        match *self {
            Piece::Segment { a, b } => {
                let d = [b[0] - a[0], b[1] - a[1]];
                let sgn = if end == End::Start { 1.0 } else { -1.0 };
                [[sgn * omega * d[0], sgn * omega * d[1]], d, [0.0, 0.0]]
            }
            Piece::Arc {
                radius,
                theta0,
                theta1,
                ..
            } => {
                let dth = theta1 - theta0;
                let off = match end {
                    End::Start => trig_diff(theta0, omega * dth),
                    End::End => trig_diff(theta1, -omega * dth),
                };
                let th = theta0 + w * dth;
                let (s, c) = th.sin_cos();
                [
                    [radius * off[0], radius * off[1]],
                    [-radius * dth * s, radius * dth * c],
                    [-radius * dth * dth * c, -radius * dth * dth * s],
                ]
            }
            Piece::Ellipse {
                a,
                b,
                rotation,
                t0,
                t1,
                ..
            } => {
                let dt = t1 - t0;
                let off = match end {
                    End::Start => trig_diff(t0, omega * dt),
                    End::End => trig_diff(t1, -omega * dt),
                };
                let t = t0 + w * dt;
                let (s, c) = t.sin_cos();
                [
                    rot([a * off[0], b * off[1]], rotation),
                    rot([-a * dt * s, b * dt * c], rotation),
                    rot([-a * dt * dt * c, -b * dt * dt * s], rotation),
                ]
            }
            Piece::Limacon {
                scale,
                c,
                theta0,
                reversed,
                ..
            } => {
                let dth = if reversed { -TAU } else { TAU };
                // start and end are the same point (θ0 and θ0 ± 2π)
                let (base, delta) = match end {
                    End::Start => (theta0, omega * dth),
                    End::End => (theta0, -omega * dth),
                };
                let d1 = trig_diff(base, delta);
                let d2 = trig_diff(2.0 * base, 2.0 * delta);
                let th = base + delta;
                let (s1, c1) = th.sin_cos();
                let (s2, c2) = (2.0 * th).sin_cos();
                [
                    [scale * (d1[0] + c * d2[0]), scale * (d1[1] + c * d2[1])],
                    [
                        scale * dth * (-s1 - 2.0 * c * s2),
                        scale * dth * (c1 + 2.0 * c * c2),
                    ],
                    [
                        scale * dth * dth * (-c1 - 4.0 * c * c2),
                        scale * dth * dth * (-s1 - 4.0 * c * s2),
                    ],
                ]
            }
            Piece::Parametric {
                ref curve,
                reversed,
            } => {
                let tau = if reversed { 1.0 - w } else { w };
                let sg = if reversed { -1.0 } else { 1.0 };
                let [x, d1, d2] = curve(tau);
                let e = self.endpoint(end);
                [[x[0] - e[0], x[1] - e[1]], [sg * d1[0], sg * d1[1]], d2]
            }
        }
    }

    /// Absolute end point of the piece.
    pub fn endpoint(&self, end: End) -> V2 {
        match *self {
            Piece::Segment { a, b } => match end {
                End::Start => a,
                End::End => b,
            },
            Piece::Arc {
                center,
                radius,
                theta0,
                theta1,
            } => {
                let th = if end == End::Start { theta0 } else { theta1 };
                [center[0] + radius * th.cos(), center[1] + radius * th.sin()]
            }
            Piece::Ellipse {
                center,
                a,
                b,
                rotation,
                t0,
                t1,
            } => {
                let t = if end == End::Start { t0 } else { t1 };
                let p = rot([a * t.cos(), b * t.sin()], rotation);
                [center[0] + p[0], center[1] + p[1]]
            }
            Piece::Limacon {
                scale,
                c,
                shift,
                theta0,
                ..
            } => {
                let th = theta0;
                [
                    shift[0] + scale * (th.cos() + c * (2.0 * th).cos()),
                    shift[1] + scale * (th.sin() + c * (2.0 * th).sin()),
                ]
            }
            Piece::Parametric {
                ref curve,
                reversed,
            } => {
                let tau = match (end, reversed) {
                    (End::Start, false) | (End::End, true) => 0.0,
                    _ => 1.0,
                };
                curve(tau)[0]
            }
        }
    }

    /// Absolute point, dx/dw and d²x/dw² at local parameter w ∈ [0, 1].
    pub fn point(&self, w: f64) -> [V2; 3] {
        let (end, om) = if w <= 0.5 {
            (End::Start, w)
        } else {
            (End::End, 1.0 - w)
        };
        let [o, d1, d2] = self.eval(end, om);
        let e = self.endpoint(end);
        [[e[0] + o[0], e[1] + o[1]], d1, d2]
    }

    /// The same curve traversed in the opposite direction.
    pub fn reversed(&self) -> Piece {
        match self.clone() {
            Piece::Segment { a, b } => Piece::Segment { a: b, b: a },
            Piece::Arc {
                center,
                radius,
                theta0,
                theta1,
            } => Piece::Arc {
                center,
                radius,
                theta0: theta1,
                theta1: theta0,
            },
            Piece::Ellipse {
                center,
                a,
                b,
                rotation,
                t0,
                t1,
            } => Piece::Ellipse {
                center,
                a,
                b,
                rotation,
                t0: t1,
                t1: t0,
            },
            Piece::Limacon {
                scale,
                c,
                shift,
                theta0,
                reversed,
            } => Piece::Limacon {
                scale,
                c,
                shift,
                theta0,
                reversed: !reversed,
            },
            Piece::Parametric { curve, reversed } => Piece::Parametric {
                curve,
                reversed: !reversed,
            },
        }
    }

    /// Whether the piece is a closed curve on its own (start = end by construction).
    pub fn is_closed_curve(&self) -> bool {
        matches!(self, Piece::Limacon { .. })
            || matches!(*self, Piece::Ellipse { t0, t1, .. } if ((t1 - t0).abs() - TAU).abs() < 1e-14)
            || matches!(*self, Piece::Arc { theta0, theta1, .. } if ((theta1 - theta0).abs() - TAU).abs() < 1e-14)
    }

    /// Integral of `f(x, dx/dw)` over w ∈ [0, 1] by composite Gauss–Legendre;
    /// on a segment by 3-point Gauss–Legendre, exact for the integrands
    /// used here (the section's moments: polynomials of degree ≤ 4 in x,
    /// so of degree ≤ 4 in w on a segment, where dx/dw is constant). The
    /// 384-point rule on every side made a 100 000-gon's moments take
    /// seconds.
    fn integrate(&self, f: &dyn Fn(V2, V2) -> f64) -> f64 {
        // the rules are built once: rebuilding one per piece took 46 % of a
        // 2000-gon's run (section moments over 2000 pieces, several times)
        static RULE: std::sync::OnceLock<(Vec<f64>, Vec<f64>)> = std::sync::OnceLock::new();
        static SEGMENT: std::sync::OnceLock<(Vec<f64>, Vec<f64>)> = std::sync::OnceLock::new();
        let (xs, ws) = if matches!(self, Piece::Segment { .. }) {
            SEGMENT.get_or_init(|| gauss_legendre_01(3))
        } else {
            RULE.get_or_init(|| composite_gauss_01(16, 24))
        };
        xs.iter()
            .zip(ws)
            .map(|(&w, &wt)| {
                let [x, d, _] = self.point(w);
                wt * f(x, d)
            })
            .sum()
    }

    /// Arc length of the piece.
    pub fn length(&self) -> f64 {
        match *self {
            Piece::Segment { a, b } => (b[0] - a[0]).hypot(b[1] - a[1]),
            Piece::Arc {
                radius,
                theta0,
                theta1,
                ..
            } => radius * (theta1 - theta0).abs(),
            _ => self.integrate(&|_, d| d[0].hypot(d[1])),
        }
    }
}

/// Largest turn (rad) at every vertex of a polygon parametrised without
/// grading (see [`Section::nearly_smooth_polygon`]): 1°.
pub const FLAT_TURN: f64 = PI / 180.0;

/// Kind of a junction between consecutive pieces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Junction {
    /// position of the junction
    pub point: V2,
    /// interior angle α ∈ [0, 2π] (π: smooth; < π convex corner; > π re-entrant; 2π inward cusp)
    pub interior_angle: f64,
}

impl Junction {
    /// True when the tangent is continuous here (|α − π| < 1e-9).
    pub fn is_smooth(&self) -> bool {
        (self.interior_angle - PI).abs() < 1e-9
    }
    /// True for re-entrant corners and inward cusps, where |∇u| → ∞.
    pub fn is_singular(&self) -> bool {
        self.interior_angle > PI + 1e-9
    }
}

/// Geometric section properties (about the centroid; x, y the input axes).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SectionProperties {
    /// area A
    pub area: f64,
    /// centroid (x_c, y_c)
    pub centroid: V2,
    /// I_xx = ∫ (y − y_c)² dA
    pub ixx: f64,
    /// I_yy = ∫ (x − x_c)² dA
    pub iyy: f64,
    /// I_xy = ∫ (x − x_c)(y − y_c) dA
    pub ixy: f64,
    /// polar moment I_xx + I_yy
    pub polar: f64,
    /// larger principal moment I_11
    pub i11: f64,
    /// smaller principal moment I_22
    pub i22: f64,
    /// angle of the I_11 axis from x, counter-clockwise, in (−π/2, π/2] (rad)
    pub phi: f64,
}

/// Where a point lies relative to a section.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointLocation {
    /// strictly inside Ω
    Inside,
    /// on Γ (to 1e-12 of the section's size)
    OnBoundary,
    /// outside Ω (or inside a hole)
    Outside,
}

/// A validated, closed, counter-clockwise section boundary.
#[derive(Clone, Debug)]
pub struct Section {
    /// human-readable name
    pub name: String,
    /// pieces in counter-clockwise order; piece k ends where piece k+1 starts
    pub pieces: Vec<Piece>,
    /// junction k is the start of piece k
    pub junctions: Vec<Junction>,
    /// messages about fixes applied during validation (e.g. orientation reversed)
    pub notes: Vec<String>,
    /// enclosed area |Ω|
    pub area: f64,
    /// centroid x₀
    pub centroid: V2,
    /// hole boundaries, each traversed clockwise (the section Ω on its left, so
    /// that normals point out of Ω into the hole); their `area` and `centroid`
    /// are those of the hole, while `area` and `centroid` above are those of Ω
    pub holes: Vec<Section>,
    /// a [`Section::flat_polygon`] whose vertices are graded all the same
    /// (see [`Section::with_flat_vertices_graded`])
    flat_vertices_graded: bool,
}

fn unit(v: V2) -> V2 {
    let n = v[0].hypot(v[1]);
    [v[0] / n, v[1] / n]
}

impl Section {
    /// Validates the pieces (closure, degeneracy, self-intersection,
    /// orientation) and builds the section. A clockwise boundary is reversed
    /// and a note is recorded.
    pub fn new(name: impl Into<String>, pieces: Vec<Piece>) -> Result<Section, GeometryError> {
        if pieces.is_empty() {
            return Err(GeometryError::Empty);
        }
        // finite parameters
        for (k, p) in pieces.iter().enumerate() {
            let ok = match *p {
                Piece::Segment { a, b } => a.iter().chain(&b).all(|v| v.is_finite()),
                Piece::Arc {
                    center,
                    radius,
                    theta0,
                    theta1,
                } => {
                    center.iter().all(|v| v.is_finite())
                        && radius.is_finite()
                        && theta0.is_finite()
                        && theta1.is_finite()
                        && radius > 0.0
                }
                Piece::Ellipse {
                    center,
                    a,
                    b,
                    rotation,
                    t0,
                    t1,
                } => {
                    center.iter().all(|v| v.is_finite())
                        && [a, b, rotation, t0, t1].iter().all(|v| v.is_finite())
                        && a > 0.0
                        && b > 0.0
                }
                Piece::Limacon {
                    scale,
                    c,
                    shift,
                    theta0,
                    ..
                } => {
                    scale.is_finite()
                        && scale > 0.0
                        && (0.0..=0.5).contains(&c)
                        && shift.iter().all(|v| v.is_finite())
                        && theta0.is_finite()
                }
                Piece::Parametric { .. } => true,
            };
            if !ok {
                return Err(GeometryError::InvalidParameter { piece: k });
            }
        }
        let lengths: Vec<f64> = pieces.iter().map(|p| p.length()).collect();
        let total: f64 = lengths.iter().sum();
        if !(total.is_finite() && total > 0.0) {
            return Err(GeometryError::Degenerate {
                piece: 0,
                length: total,
            });
        }
        for (k, &l) in lengths.iter().enumerate() {
            if l.is_nan() || l <= 1e-10 * total {
                return Err(GeometryError::Degenerate {
                    piece: k,
                    length: l,
                });
            }
        }
        let m = pieces.len();
        for k in 0..m {
            let e = pieces[k].endpoint(End::End);
            let s = pieces[(k + 1) % m].endpoint(End::Start);
            let gap = (e[0] - s[0]).hypot(e[1] - s[1]);
            if gap > 1e-9 * total {
                return Err(GeometryError::NotClosed { piece: k, gap });
            }
        }
        // self-intersection on a polyline (segments exact, curves subdivided), grid-accelerated
        let per = if m > 200 { 8 } else { 48 };
        let poly = polyline(&pieces, per);
        if let Some(near) = first_crossing(&poly) {
            return Err(GeometryError::SelfIntersecting { near });
        }
        let mut sec = Section {
            name: name.into(),
            pieces,
            junctions: vec![],
            notes: vec![],
            area: 0.0,
            centroid: [0.0; 2],
            holes: vec![],
            flat_vertices_graded: false,
        };
        let area = sec.signed_area();
        if area.abs() < 1e-12 * total * total {
            return Err(GeometryError::ZeroArea);
        }
        if area < 0.0 {
            sec.pieces = sec.pieces.iter().rev().map(|p| p.reversed()).collect();
            sec.notes
                .push("boundary was clockwise; reversed to counter-clockwise".into());
        }
        sec.area = area.abs();
        let (mx, my) = sec.first_moments(sec.area);
        sec.centroid = [mx / sec.area, my / sec.area];
        sec.junctions = sec.compute_junctions();
        for (k, j) in sec.junctions.iter().enumerate() {
            if j.interior_angle < 1e-6 && sec.pieces.len() > 1 {
                return Err(GeometryError::ZeroAngle { junction: k });
            }
        }
        Ok(sec)
    }

    /// ∮ over the outer chain only.
    fn integrate(&self, f: &dyn Fn(V2, V2) -> f64) -> f64 {
        self.pieces.iter().map(|p| p.integrate(f)).sum()
    }

    /// ∮ over every boundary curve of Ω (holes clockwise).
    fn integrate_all(&self, f: &dyn Fn(V2, V2) -> f64) -> f64 {
        self.integrate(f) + self.holes.iter().map(|h| h.integrate(f)).sum::<f64>()
    }

    /// Area, centroid and second moments of Ω (holes subtracted) by Green's
    /// theorem on the boundary, about the centroid, with the principal axes.
    pub fn properties(&self) -> SectionProperties {
        let c = self.centroid;
        let ixx = self.integrate_all(&|x, d| -(x[1] - c[1]).powi(3) / 3.0 * d[0]);
        let iyy = self.integrate_all(&|x, d| (x[0] - c[0]).powi(3) / 3.0 * d[1]);
        let ixy = self.integrate_all(&|x, d| 0.5 * (x[0] - c[0]).powi(2) * (x[1] - c[1]) * d[1]);
        let mean = 0.5 * (ixx + iyy);
        let rad = (0.25 * (ixx - iyy).powi(2) + ixy * ixy).sqrt();
        SectionProperties {
            area: self.area,
            centroid: c,
            ixx,
            iyy,
            ixy,
            polar: ixx + iyy,
            i11: mean + rad,
            i22: mean - rad,
            phi: 0.5 * (-2.0 * ixy).atan2(ixx - iyy),
        }
    }

    /// The boundary curves: the outer chain (this section) first, then the holes.
    pub fn curves(&self) -> Vec<&Section> {
        std::iter::once(self).chain(self.holes.iter()).collect()
    }

    /// Total boundary length, holes included.
    pub fn total_perimeter(&self) -> f64 {
        self.perimeter() + self.holes.iter().map(|h| h.perimeter()).sum::<f64>()
    }

    /// The points where τ is singular: re-entrant corners and inward cusps,
    /// of the outer boundary and of the holes (a hole's convex-looking
    /// corner is re-entrant for the section around it).
    pub fn singular_points(&self) -> Vec<V2> {
        self.curves()
            .iter()
            .flat_map(|c| c.junctions.iter())
            .filter(|j| j.is_singular())
            .map(|j| j.point)
            .collect()
    }

    /// Default distance from the singular points outside which the
    /// boundary shear stress of a singular section is reported: A/P, half
    /// the mean wall thickness 2A/P (the wall thickness of a thin-walled
    /// section, where the stress near a re-entrant corner has fallen to
    /// within tens of per cent of the wall's own).
    pub fn default_corner_distance(&self) -> f64 {
        self.area / self.total_perimeter()
    }

    /// Whether `p` lies inside Ω (strictly, at a distance above `1e-12`
    /// times the size of the section). Curved pieces are judged on an
    /// inscribed polyline of 4096 chords per piece, so points within about
    /// 3e-7 of the radius of curvature of a convex curved boundary may be
    /// called outside (never an outside point inside).
    pub fn locate(&self, p: V2) -> PointLocation {
        let tol = 1e-12 * self.radius().max(f64::MIN_POSITIVE);
        let mut inside = false;
        let mut dist = f64::INFINITY;
        for (k, c) in self.curves().into_iter().enumerate() {
            let poly = polyline(&c.pieces, 4096);
            dist = dist.min(polyline_distance(&poly, p));
            let w = winding(&poly, p) != 0;
            if k == 0 {
                inside = w;
            } else if w {
                inside = false;
            }
        }
        if dist <= tol {
            PointLocation::OnBoundary
        } else if inside {
            PointLocation::Inside
        } else {
            PointLocation::Outside
        }
    }

    /// A section with holes. `outer` and every hole are simply connected
    /// sections (either orientation given, validated on their own); holes
    /// must lie inside `outer`, clear of its boundary and of each other.
    /// Errors and notes name the holes by their 0-based position in `holes`
    /// (`hole[k]`, as the field errors of a section file do).
    /// Each hole is stored clockwise (Ω on its left); `area`, `centroid`
    /// and the moments become those of Ω.
    pub fn with_holes(outer: Section, holes: Vec<Section>) -> Result<Section, GeometryError> {
        if !outer.holes.is_empty() || holes.iter().any(|h| !h.holes.is_empty()) {
            return Err(GeometryError::NestedHoles);
        }
        let outer_poly = polyline(&outer.pieces, 48);
        let polys: Vec<Vec<V2>> = holes.iter().map(|h| polyline(&h.pieces, 48)).collect();
        for (k, hp) in polys.iter().enumerate() {
            if let Some(near) = polylines_cross(&outer_poly, hp) {
                return Err(GeometryError::HoleTouchesBoundary { hole: k, near });
            }
            if winding(&outer_poly, hp[0]) == 0 {
                return Err(GeometryError::HoleOutside { hole: k });
            }
            for (l, lp) in polys.iter().enumerate().take(k) {
                if polylines_cross(lp, hp).is_some()
                    || winding(lp, hp[0]) != 0
                    || winding(hp, lp[0]) != 0
                {
                    return Err(GeometryError::HolesOverlap { a: l, b: k });
                }
            }
        }
        let mut sec = outer;
        let (mut a, mut mx, mut my) = (
            sec.area,
            sec.area * sec.centroid[0],
            sec.area * sec.centroid[1],
        );
        for (k, h) in holes.into_iter().enumerate() {
            // a hole's notes (merged or dropped vertices) name it as the
            // errors do: hole[k], 0-based
            sec.notes
                .extend(h.notes.iter().map(|n| format!("hole[{k}]: {n}")));
            a -= h.area;
            mx -= h.area * h.centroid[0];
            my -= h.area * h.centroid[1];
            let mut cw = h.clone();
            cw.pieces = h.pieces.iter().rev().map(|p| p.reversed()).collect();
            cw.junctions = cw.compute_junctions();
            cw.notes.clear();
            sec.holes.push(cw);
        }
        sec.area = a;
        sec.centroid = [mx / a, my / a];
        Ok(sec)
    }

    /// A point of the boundary: the area and first moments are integrated
    /// about it, so a section far from the origin keeps its centroid to
    /// round-off of its own size. About the origin, ∮ x²/2 dy of a unit
    /// triangle at (10⁴, 10⁴) cancelled from 4e7 to 4e3, and its centroid
    /// (and so its shear centre) was 2.4e-8 of its size off.
    fn reference_point(&self) -> V2 {
        self.pieces[0].endpoint(End::Start)
    }

    fn signed_area(&self) -> f64 {
        let p = self.reference_point();
        0.5 * self.integrate(&|x, d| (x[0] - p[0]) * d[1] - (x[1] - p[1]) * d[0])
    }

    /// (∫ x dA, ∫ y dA) by Green's theorem, about the boundary's
    /// [`reference_point`](Self::reference_point) and shifted back (`a`
    /// the signed area).
    fn first_moments(&self, a: f64) -> (f64, f64) {
        let p = self.reference_point();
        let mx = self.integrate(&|x, d| 0.5 * (x[0] - p[0]).powi(2) * d[1]);
        let my = self.integrate(&|x, d| -0.5 * (x[1] - p[1]).powi(2) * d[0]);
        (mx + p[0] * a, my + p[1] * a)
    }

    /// I_p = ¼ ∮ |x − x₀|² (x − x₀)·n ds about the centroid (= polar moment of area).
    pub fn polar_moment(&self) -> f64 {
        let c = self.centroid;
        0.25 * self.integrate_all(&|x, d| {
            let r = [x[0] - c[0], x[1] - c[1]];
            (r[0] * r[0] + r[1] * r[1]) * (r[0] * d[1] - r[1] * d[0])
        })
    }

    /// Total boundary length.
    pub fn perimeter(&self) -> f64 {
        self.pieces.iter().map(|p| p.length()).sum()
    }

    /// Largest distance of a boundary point from the centroid (a length scale).
    pub fn radius(&self) -> f64 {
        let mut r: f64 = 0.0;
        for p in &self.pieces {
            for i in 0..=32 {
                let x = p.point(i as f64 / 32.0)[0];
                r = r.max((x[0] - self.centroid[0]).hypot(x[1] - self.centroid[1]));
            }
        }
        r
    }

    fn tangent(p: &Piece, end: End) -> V2 {
        let [_, d1, _] = p.eval(end, 0.0);
        let sg = if end == End::Start { 1.0 } else { -1.0 };
        let scale = p.length();
        if d1[0].hypot(d1[1]) > 1e-8 * scale {
            return unit(d1);
        }
        // vanishing speed (cusp): direction of a small chord
        let [o, _, _] = p.eval(end, 1e-4);
        unit([sg * o[0], sg * o[1]])
    }

    fn compute_junctions(&self) -> Vec<Junction> {
        let m = self.pieces.len();
        (0..m)
            .map(|k| {
                let prev = &self.pieces[(k + m - 1) % m];
                let cur = &self.pieces[k];
                let din = Self::tangent(prev, End::End);
                let dout = Self::tangent(cur, End::Start);
                let cross = din[0] * dout[1] - din[1] * dout[0];
                let dot = din[0] * dout[0] + din[1] * dout[1];
                let turn = cross.atan2(dot);
                Junction {
                    point: cur.endpoint(End::Start),
                    interior_angle: PI - turn,
                }
            })
            .collect()
    }

    /// Whether junction k must be graded: every junction of a multi-piece
    /// boundary (corners, and curvature jumps), and cusps of single pieces.
    /// O(pieces) (it checks [`Section::nearly_smooth_polygon`]): loops over
    /// the junctions take [`Section::graded_junctions`].
    pub fn graded(&self, k: usize) -> bool {
        !self.nearly_smooth_polygon() && self.junction_needs_grading(k)
    }

    /// [`Section::graded`] for every junction, in one pass.
    pub fn graded_junctions(&self) -> Vec<bool> {
        let smooth_polygon = self.nearly_smooth_polygon();
        (0..self.pieces.len())
            .map(|k| !smooth_polygon && self.junction_needs_grading(k))
            .collect()
    }

    /// Whether any junction of this curve is graded.
    pub fn any_graded(&self) -> bool {
        !self.nearly_smooth_polygon()
            && (0..self.pieces.len()).any(|k| self.junction_needs_grading(k))
    }

    fn junction_needs_grading(&self, k: usize) -> bool {
        self.pieces.len() > 1 || !self.junctions[k].is_smooth()
    }

    /// A boundary of straight segments that all turn by less than
    /// [`FLAT_TURN`] (a fine polygonal approximation of a smooth convex
    /// curve, such as a 2000-gon): it is parametrised by arc length without
    /// grading. Its corners are nearly flat (interior angle α = π − turn),
    /// the stress function is u ~ r^{π/α} there, so the flux varies like
    /// r^{turn/(π − turn)} ≤ r^{0.006}: grading each corner would cost
    /// thousands of nodes per corner for nothing the error control can see.
    pub fn nearly_smooth_polygon(&self) -> bool {
        !self.flat_vertices_graded && self.flat_polygon()
    }

    /// The shape test of [`Section::nearly_smooth_polygon`]: at least 8
    /// segments, every vertex turning by less than [`FLAT_TURN`].
    pub fn flat_polygon(&self) -> bool {
        self.pieces.len() >= 8
            && self
                .pieces
                .iter()
                .all(|p| matches!(p, Piece::Segment { .. }))
            && self
                .junctions
                .iter()
                .all(|j| (PI - j.interior_angle).abs() < FLAT_TURN)
    }

    /// Whether every piece of this curve has the same length: to 1e-12 of
    /// it, or to 1e-13 of the section's radius (the rounding of their end
    /// points: the regular 3000-gon's edges, from cos and sin of 2πk/N,
    /// differ by 1.0e-12 of their length).
    pub fn pieces_of_equal_length(&self) -> bool {
        let (lo, hi) = self
            .pieces
            .iter()
            .map(|p| p.length())
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), l| {
                (lo.min(l), hi.max(l))
            });
        hi > 0.0 && hi - lo <= (1e-12 * hi).max(1e-13 * self.radius())
    }

    /// This section with the nearly flat vertices of a
    /// [`Section::flat_polygon`] graded like any corner (every vertex a
    /// panel end with Kress's grading) instead of the arc-length
    /// parametrisation of [`Section::nearly_smooth_polygon`]. Grading pays
    /// only where the system folds by a rotation that maps every edge onto
    /// the next (a regular N-gon: N n/N unknowns, solved on one edge; see
    /// [`crate::control::prepared`]).
    pub fn with_flat_vertices_graded(&self) -> Section {
        Section {
            flat_vertices_graded: true,
            ..self.clone()
        }
    }

    /// Whether [`Section::with_flat_vertices_graded`] made this section.
    pub fn flat_vertices_graded(&self) -> bool {
        self.flat_vertices_graded
    }

    /// True when some corner or cusp makes τ unbounded.
    pub fn is_singular(&self) -> bool {
        self.junctions.iter().any(|j| j.is_singular()) || self.holes.iter().any(|h| h.is_singular())
    }

    /// Copy translated by `d`.
    pub fn translated(&self, d: V2) -> Result<Section, GeometryError> {
        self.map(1.0, 0.0, d)
    }
    /// Copy rotated by `phi` about the origin.
    pub fn rotated(&self, phi: f64) -> Result<Section, GeometryError> {
        self.map(1.0, phi, [0.0, 0.0])
    }
    /// Copy scaled by `lambda` about the origin.
    pub fn scaled(&self, lambda: f64) -> Result<Section, GeometryError> {
        self.map(lambda, 0.0, [0.0, 0.0])
    }

    /// Image under x ↦ λ R(φ) x + d, holes included (they used to be
    /// dropped: a moved tube came back as the solid disc, J 6 % to 92 % off).
    fn map(&self, lambda: f64, phi: f64, d: V2) -> Result<Section, GeometryError> {
        let outer = self.map_curve(lambda, phi, d)?;
        if self.holes.is_empty() {
            return Ok(outer);
        }
        let holes = self
            .holes
            .iter()
            .map(|h| h.map_curve(lambda, phi, d))
            .collect::<Result<Vec<_>, _>>()?;
        let mut s = Section::with_holes(outer, holes)?;
        s.notes = self.notes.clone();
        Ok(s)
    }

    /// The image of this section's own boundary curve (no holes).
    fn map_curve(&self, lambda: f64, phi: f64, d: V2) -> Result<Section, GeometryError> {
        let f = |p: V2| {
            let q = rot([lambda * p[0], lambda * p[1]], phi);
            [q[0] + d[0], q[1] + d[1]]
        };
        let pieces = self
            .pieces
            .iter()
            .map(|p| match p.clone() {
                Piece::Segment { a, b } => Piece::Segment { a: f(a), b: f(b) },
                Piece::Arc {
                    center,
                    radius,
                    theta0,
                    theta1,
                } => Piece::Arc {
                    center: f(center),
                    radius: radius * lambda,
                    theta0: theta0 + phi,
                    theta1: theta1 + phi,
                },
                Piece::Ellipse {
                    center,
                    a,
                    b,
                    rotation,
                    t0,
                    t1,
                } => Piece::Ellipse {
                    center: f(center),
                    a: a * lambda,
                    b: b * lambda,
                    rotation: rotation + phi,
                    t0,
                    t1,
                },
                Piece::Limacon {
                    scale,
                    c,
                    shift,
                    theta0,
                    reversed,
                } => {
                    // rotation by φ: z ↦ e^{iφ} z; A(e^{iθ}+c e^{2iθ}) e^{iφ} is not a limaçon
                    // in θ + φ unless we re-parametrise; keep it as a user curve instead.
                    if phi != 0.0 {
                        let src = Piece::Limacon {
                            scale,
                            c,
                            shift,
                            theta0,
                            reversed,
                        };
                        let g = move |tau: f64| {
                            let [x, d1, d2] = src.point(tau);
                            let x = rot([lambda * x[0], lambda * x[1]], phi);
                            [
                                [x[0] + d[0], x[1] + d[1]],
                                rot([lambda * d1[0], lambda * d1[1]], phi),
                                rot([lambda * d2[0], lambda * d2[1]], phi),
                            ]
                        };
                        Piece::Parametric {
                            curve: Arc::new(g),
                            reversed: false,
                        }
                    } else {
                        Piece::Limacon {
                            scale: scale * lambda,
                            c,
                            shift: f(shift),
                            theta0,
                            reversed,
                        }
                    }
                }
                Piece::Parametric { curve, reversed } => {
                    let f2 = move |tau: f64| {
                        let [x, d1, d2] = curve(tau);
                        let x = rot([lambda * x[0], lambda * x[1]], phi);
                        [
                            [x[0] + d[0], x[1] + d[1]],
                            rot([lambda * d1[0], lambda * d1[1]], phi),
                            rot([lambda * d2[0], lambda * d2[1]], phi),
                        ]
                    };
                    Piece::Parametric {
                        curve: Arc::new(f2),
                        reversed,
                    }
                }
            })
            .collect();
        Section::new(self.name.clone(), pieces)
    }
}
