//! Validation helpers shared by the P1 and P2 constructors: connected bodies,
//! coincident nodes, and a hash grid for near-point queries.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use crate::error::{GmshRefs, MeshError};
use crate::mesh::{Body, COINCIDENCE_TOLERANCE, Point};

/// A hasher for integer keys (node ids, edges): multiply-xor per word and a
/// shift-xor-multiply finish, so the low bits the table uses are mixed.
/// Deterministic (no random seed), which the mesh does not rely on.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct IdHasher(u64);

const MIX: u64 = 0x9e37_79b9_7f4a_7c15;

impl Hasher for IdHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(23) ^ i).wrapping_mul(MIX);
    }
    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
    #[inline]
    fn finish(&self) -> u64 {
        let mut x = self.0;
        x ^= x >> 32;
        x = x.wrapping_mul(0xd6e8_feb8_6659_fd93);
        x ^ (x >> 32)
    }
}

/// A hash map keyed by node ids.
pub(crate) type IdMap<K, V> = HashMap<K, V, BuildHasherDefault<IdHasher>>;

pub(crate) fn unknown<'a>(
    kind: &'static str,
    name: &str,
    keys: impl Iterator<Item = &'a String>,
) -> MeshError {
    let available: Vec<&str> = keys.map(|s| s.as_str()).collect();
    MeshError::UnknownName {
        kind,
        name: name.into(),
        available: if available.is_empty() {
            "none".into()
        } else {
            available.join(", ")
        },
    }
}

pub(crate) fn dist(a: Point, b: Point) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

pub(crate) fn longest_edge_sq(a: Point, b: Point, c: Point) -> f64 {
    let d = |p: Point, q: Point| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    d(a, b).max(d(b, c)).max(d(c, a))
}

/// Connected bodies through shared nodes of the elements (all of their nodes,
/// so the mid nodes of a P2 mesh belong to the body of their triangle).
pub(crate) fn find_bodies<T: AsRef<[usize]>>(
    n: usize,
    elements: &[T],
    element_region: &[usize],
    region_names: &[String],
) -> (Vec<usize>, Vec<Body>) {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for t in elements {
        let t = t.as_ref();
        for &v in &t[1..] {
            let (ra, rb) = (root(&mut parent, t[0]), root(&mut parent, v));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // Bodies numbered in order of their smallest node.
    let mut body_of_root = vec![usize::MAX; n];
    let mut nb = 0;
    let mut node_body = vec![0; n];
    for (i, b) in node_body.iter_mut().enumerate() {
        let r = root(&mut parent, i);
        if body_of_root[r] == usize::MAX {
            body_of_root[r] = nb;
            nb += 1;
        }
        *b = body_of_root[r];
    }
    let mut body_elements = vec![Vec::new(); nb];
    let mut nodes = vec![Vec::new(); nb];
    let mut regions = vec![Vec::<usize>::new(); nb];
    for (e, t) in elements.iter().enumerate() {
        let b = node_body[t.as_ref()[0]];
        body_elements[b].push(e);
        if !regions[b].contains(&element_region[e]) {
            regions[b].push(element_region[e]);
        }
    }
    for (i, &b) in node_body.iter().enumerate() {
        nodes[b].push(i);
    }
    let bodies = (0..nb)
        .map(|b| {
            let mut r = regions[b].clone();
            r.sort_unstable();
            Body {
                name: r
                    .iter()
                    .map(|&k| region_names[k].as_str())
                    .collect::<Vec<_>>()
                    .join("+"),
                elements: std::mem::take(&mut body_elements[b]),
                nodes: std::mem::take(&mut nodes[b]),
            }
        })
        .collect();
    (node_body, bodies)
}

/// Coincident nodes are an error when both are used by elements of one
/// region (an unmerged mesh); across regions they are allowed, as on an
/// interface or at the tip of an interface crack.
pub(crate) fn check_duplicates<T: AsRef<[usize]>>(
    nodes: &[Point],
    elements: &[T],
    element_region: &[usize],
    region_names: &[String],
) -> Result<(), MeshError> {
    if nodes.is_empty() {
        return Ok(());
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    let tol = COINCIDENCE_TOLERANCE * size;
    let all: Vec<usize> = (0..nodes.len()).collect();
    let grid = PointGrid::new(nodes, &all, tol);
    let mut pairs = grid.close_pairs(nodes, tol);
    pairs.sort_unstable();
    if pairs.is_empty() {
        return Ok(());
    }
    let mut regions_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for &(i, j) in &pairs {
        regions_of.entry(i).or_default();
        regions_of.entry(j).or_default();
    }
    for (e, t) in elements.iter().enumerate() {
        for v in t.as_ref() {
            if let Some(r) = regions_of.get_mut(v)
                && !r.contains(&element_region[e])
            {
                r.push(element_region[e]);
            }
        }
    }
    for (i, j) in pairs {
        if let Some(&r) = regions_of[&i].iter().find(|r| regions_of[&j].contains(r)) {
            return Err(MeshError::DuplicateNodes {
                a: i,
                b: j,
                x: nodes[i][0],
                y: nodes[i][1],
                region: region_names[r].clone(),
                gmsh: GmshRefs::NONE,
            });
        }
    }
    Ok(())
}

/// A uniform grid over a subset of nodes, for near-point queries: the nodes
/// sorted by cell, found by binary search (no allocation per cell).
pub(crate) struct PointGrid {
    cell: f64,
    /// (cell key, node), sorted.
    sorted: Vec<((i64, i64), usize)>,
}

impl PointGrid {
    /// A grid whose queries find every point within `tol` (or less).
    pub(crate) fn new(nodes: &[Point], subset: &[usize], tol: f64) -> Self {
        let cell = (4.0 * tol).max(f64::MIN_POSITIVE);
        let mut sorted: Vec<((i64, i64), usize)> = subset
            .iter()
            .map(|&i| (Self::key(nodes[i], cell), i))
            .collect();
        sorted.sort_unstable();
        PointGrid { cell, sorted }
    }

    fn key(p: Point, cell: f64) -> (i64, i64) {
        ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64)
    }

    /// The points within `tol` of `p` (`tol` at most the grid's tolerance).
    pub(crate) fn within(&self, nodes: &[Point], p: Point, tol: f64) -> Vec<usize> {
        let (kx, ky) = Self::key(p, self.cell);
        let mut out = Vec::new();
        for dx in -1..=1 {
            // cells (kx+dx, ky-1 ..= ky+1) are contiguous in the sorted order
            let lo = self.sorted.partition_point(|&(k, _)| k < (kx + dx, ky - 1));
            for &(k, j) in &self.sorted[lo..] {
                if k > (kx + dx, ky + 1) {
                    break;
                }
                if dist(nodes[j], p) <= tol {
                    out.push(j);
                }
            }
        }
        out
    }

    /// Every pair (i < j) of the grid's points within `tol` of each other, in
    /// one sweep: a point meets the later points of its own column of cells
    /// and, through a cursor that only moves forward, those of the next column.
    pub(crate) fn close_pairs(&self, nodes: &[Point], tol: f64) -> Vec<(usize, usize)> {
        let s = &self.sorted;
        let mut out = Vec::new();
        let mut cursor = 0;
        for (i, &((kx, ky), a)) in s.iter().enumerate() {
            let mut check = |b: usize| {
                if dist(nodes[a], nodes[b]) <= tol {
                    out.push((a.min(b), a.max(b)));
                }
            };
            for &(k, b) in &s[i + 1..] {
                if k > (kx, ky + 1) {
                    break;
                }
                check(b);
            }
            while cursor < s.len() && s[cursor].0 < (kx + 1, ky - 1) {
                cursor += 1;
            }
            for &(k, b) in &s[cursor..] {
                if k > (kx + 1, ky + 1) {
                    break;
                }
                check(b);
            }
        }
        out
    }

    /// The nearest point within `tol` of `p` (ties: the smaller id).
    pub(crate) fn nearest(&self, nodes: &[Point], p: Point, tol: f64) -> Option<usize> {
        self.within(nodes, p, tol).into_iter().min_by(|&a, &b| {
            dist(nodes[a], p)
                .total_cmp(&dist(nodes[b], p))
                .then(a.cmp(&b))
        })
    }
}
