//! Closed polylines of section boundaries: the self-intersection test and the
//! crossing test between two boundaries on a uniform grid (expected O(P) for
//! evenly spread edges; 10⁵ vertices in well under a second), winding numbers
//! and distances for locating points.

use crate::geometry::{Piece, V2};

/// The boundary as a closed polyline: segments by their end points, other
/// pieces subdivided into `per` chords.
pub(crate) fn polyline(pieces: &[Piece], per: usize) -> Vec<V2> {
    let mut poly: Vec<V2> = Vec::new();
    for p in pieces {
        let k = if matches!(p, Piece::Segment { .. }) {
            1
        } else {
            per
        };
        for i in 0..k {
            poly.push(p.point(i as f64 / k as f64)[0]);
        }
    }
    poly
}

/// Uniform grid over the bounding box of a set of segments: for each
/// segment the cells its bounding box covers. Returns the candidate pairs
/// (i < j) that share a cell, each pair once (only in the cell holding the
/// lower-left corner of the overlap of their boxes).
fn grid_pairs(segs: &[(V2, V2)], mut visit: impl FnMut(usize, usize) -> bool) -> bool {
    let ns = segs.len();
    if ns < 2 {
        return false;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (a, b) in segs {
        for d in 0..2 {
            lo[d] = lo[d].min(a[d]).min(b[d]);
            hi[d] = hi[d].max(a[d]).max(b[d]);
        }
    }
    let g = ((ns as f64).sqrt().ceil() as usize).clamp(1, 2048);
    let size = [
        ((hi[0] - lo[0]) / g as f64).max(f64::MIN_POSITIVE),
        ((hi[1] - lo[1]) / g as f64).max(f64::MIN_POSITIVE),
    ];
    let cell = |x: f64, d: usize| (((x - lo[d]) / size[d]) as usize).min(g - 1);
    let bbox = |i: usize| {
        let (a, b) = segs[i];
        (
            [a[0].min(b[0]), a[1].min(b[1])],
            [a[0].max(b[0]), a[1].max(b[1])],
        )
    };
    let mut cells: Vec<Vec<usize>> = vec![Vec::new(); g * g];
    for i in 0..ns {
        let (l, h) = bbox(i);
        for cx in cell(l[0], 0)..=cell(h[0], 0) {
            for cy in cell(l[1], 1)..=cell(h[1], 1) {
                cells[cx * g + cy].push(i);
            }
        }
    }
    for (c, list) in cells.iter().enumerate() {
        for (ii, &i) in list.iter().enumerate() {
            let (li, _) = bbox(i);
            for &j in &list[ii + 1..] {
                let (lj, _) = bbox(j);
                let corner = [li[0].max(lj[0]), li[1].max(lj[1])];
                if cell(corner[0], 0) * g + cell(corner[1], 1) != c {
                    continue;
                }
                if visit(i.min(j), i.max(j)) {
                    return true;
                }
            }
        }
    }
    false
}

/// First crossing of a closed polyline with itself (non-adjacent edges that
/// meet), in O(P) expected time for evenly spread edges: a point both edges
/// hold (their crossing, or where they touch).
pub(crate) fn first_crossing(poly: &[V2]) -> Option<V2> {
    let np = poly.len();
    let segs: Vec<(V2, V2)> = (0..np).map(|i| (poly[i], poly[(i + 1) % np])).collect();
    let mut near = None;
    grid_pairs(&segs, |i, j| {
        let adjacent = j == i + 1 || (i == 0 && j == np - 1);
        if adjacent {
            return false;
        }
        near = seg_intersection(segs[i].0, segs[i].1, segs[j].0, segs[j].1);
        near.is_some()
    });
    near
}

/// First crossing between two closed polylines (any edges that meet): a
/// point both polylines hold (where two edges cross, or touch).
pub(crate) fn polylines_cross(a: &[V2], b: &[V2]) -> Option<V2> {
    let mut segs: Vec<(V2, V2)> = (0..a.len()).map(|i| (a[i], a[(i + 1) % a.len()])).collect();
    let na = segs.len();
    segs.extend((0..b.len()).map(|i| (b[i], b[(i + 1) % b.len()])));
    let mut near = None;
    grid_pairs(&segs, |i, j| {
        if !(i < na && j >= na) {
            return false;
        }
        near = seg_intersection(segs[i].0, segs[i].1, segs[j].0, segs[j].1);
        near.is_some()
    });
    near
}

/// Winding number of a closed polyline about `p` (non-zero: inside).
pub(crate) fn winding(poly: &[V2], p: V2) -> i32 {
    let n = poly.len();
    let mut w = 0;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let cross = (b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1]);
        if a[1] <= p[1] {
            if b[1] > p[1] && cross > 0.0 {
                w += 1;
            }
        } else if b[1] <= p[1] && cross < 0.0 {
            w -= 1;
        }
    }
    w
}

/// Distance from `p` to a closed polyline.
pub(crate) fn polyline_distance(poly: &[V2], p: V2) -> f64 {
    let n = poly.len();
    let mut d = f64::INFINITY;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let ab = [b[0] - a[0], b[1] - a[1]];
        let ap = [p[0] - a[0], p[1] - a[1]];
        let l2 = ab[0] * ab[0] + ab[1] * ab[1];
        let t = if l2 > 0.0 {
            ((ap[0] * ab[0] + ap[1] * ab[1]) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        d = d.min((ap[0] - t * ab[0]).hypot(ap[1] - t * ab[1]));
    }
    d
}

/// A point the segments p1p2 and q1q2 share, if they meet: their crossing
/// when they cross, else an end point lying on the other segment (they
/// touch, or overlap along a line).
fn seg_intersection(p1: V2, p2: V2, q1: V2, q2: V2) -> Option<V2> {
    let cross = |o: V2, a: V2, b: V2| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let on_seg = |a: V2, b: V2, p: V2| {
        p[0] >= a[0].min(b[0])
            && p[0] <= a[0].max(b[0])
            && p[1] >= a[1].min(b[1])
            && p[1] <= a[1].max(b[1])
    };
    let d1 = cross(q1, q2, p1);
    let d2 = cross(q1, q2, p2);
    let d3 = cross(p1, p2, q1);
    let d4 = cross(p1, p2, q2);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        // p1 + s (p2 − p1) with s = d1/(d1 − d2) ∈ (0, 1): d1 and d2 are the
        // signed distances of p1 and p2 from the line q1q2 (times |q2 − q1|)
        let s = d1 / (d1 - d2);
        return Some([p1[0] + s * (p2[0] - p1[0]), p1[1] + s * (p2[1] - p1[1])]);
    }
    // touching or collinear overlap (non-adjacent polyline segments must not meet at all)
    if d1 == 0.0 && on_seg(q1, q2, p1) {
        Some(p1)
    } else if d2 == 0.0 && on_seg(q1, q2, p2) {
        Some(p2)
    } else if d3 == 0.0 && on_seg(p1, p2, q1) {
        Some(q1)
    } else if d4 == 0.0 && on_seg(p1, p2, q2) {
        Some(q2)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The point reported is one both segments hold: their crossing, or
    /// the end point where they touch.
    #[test]
    fn segments_meet_where_they_cross_or_touch() {
        // the side x = 1 of the unit square against the bottom side of the
        // hole (0.5 … 1.5) × (0.5 … 0.7)
        let p = seg_intersection([1.0, 0.0], [1.0, 1.0], [0.5, 0.5], [1.5, 0.5]).unwrap();
        assert_eq!(p, [1.0, 0.5]);
        let p = seg_intersection([0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]).unwrap();
        assert!(
            (p[0] - 0.5).abs() < 1e-15 && (p[1] - 0.5).abs() < 1e-15,
            "{p:?}"
        );
        // touching: the end (0.5, 0) of one lies on the other
        let p = seg_intersection([0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [0.5, 1.0]).unwrap();
        assert_eq!(p, [0.5, 0.0]);
        // collinear overlap (0.5 … 1 on the x axis): an end point inside the other segment
        let p = seg_intersection([0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [2.0, 0.0]).unwrap();
        assert_eq!(p, [1.0, 0.0]);
        // apart
        assert!(seg_intersection([0.0, 0.0], [1.0, 0.0], [0.0, 0.1], [1.0, 0.1]).is_none());
        assert!(seg_intersection([0.0, 0.0], [1.0, 0.0], [2.0, -1.0], [2.0, 1.0]).is_none());
    }

    /// A self-crossing polyline (a bow tie) reports its crossing point.
    #[test]
    fn a_bow_tie_crosses_at_its_middle() {
        let p = first_crossing(&[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]).unwrap();
        assert!(
            (p[0] - 0.5).abs() < 1e-15 && (p[1] - 0.5).abs() < 1e-15,
            "{p:?}"
        );
        assert!(first_crossing(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]).is_none());
    }
}
