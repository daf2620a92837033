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

/// The graded periodic parametrisation of a section.
#[derive(Clone, Debug)]
pub struct Parametrisation {
    /// panel break points b_0 = 0 < b_1 < … < b_m = 1
    pub breaks: Vec<f64>,
    /// grading exponent per panel (None: identity map)
    pub grading: Vec<Option<f64>>,
    anchors: Vec<V2>,
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
            anchors,
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
        let m = self.breaks.len() - 1;
        let (b0, b1) = (self.breaks[k], self.breaks[k + 1]);
        let db = b1 - b0;
        let piece = &section.pieces[k];
        let s0 = (t - b0) / db;
        let (end, sig) = if s0 <= 0.5 {
            (End::Start, s0)
        } else {
            (End::End, (b1 - t) / db)
        };
        let (om, dw, ddw) = match self.grading[k] {
            Some(p) => kress(sig, p),
            None => (sig, 1.0, 0.0),
        };
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
        (0..n)
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
}
