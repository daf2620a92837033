//! A coarse space on the interface dofs, for the first Newton pass of an
//! increment when the passes are condensed onto the interface.
//!
//! Why: from a state far from the new equilibrium (the unloaded vessel at
//! its first output time, or a load step that moves the lift-off under the
//! weld) the linearised solution carries an opening as a concentrated
//! tension at the first closed node, so each Newton step moves the front by
//! a few interface points and the first pass takes a number of iterations
//! that grows with the mesh (28 on `t1e5` against 11 on level 2; see
//! `front`). A displacement field that is smooth along the interface cannot
//! concentrate like that: in a space of such fields the front moves by a
//! coarse segment per step.
//!
//! What: every k-th node along each face of an interface (the
//! corners of the elements at the same stations on both faces, so that a
//! closed zone of the coarse field is a closed zone of the fine one) is a
//! coarse node with two dofs, the normal and the tangential displacement
//! in the face's frame at each fine node; the fine nodes between two
//! coarse nodes of a face interpolate them linearly in arc length, in that
//! local frame. (Interpolated in x and y instead, a coarse tangential slip
//! along a curved face has a normal part between the coarse nodes, which
//! the stiff penalty of a closed zone forbids: measured on `t1e5`, the
//! coarse iteration then opened nearly every point and the first pass got
//! slower, 21 → 31 iterations at the second output time.) P maps the coarse
//! dofs to the interface dofs Γ; the coarse problem is the Galerkin one,
//! the energy of the pass restricted to δ₀ + range(P): tangent
//! Pᵀ (S + K_c) P with S the bulk's Schur complement, gradient Pᵀ r, and
//! the exact energy line search of the pass along P dc (see
//! `condensed`). Its Newton steps are solved densely (the coarse system
//! has at most [`MAX_COARSE_DOFS`] dofs: k is the smallest power of two
//! that keeps it there), and they
//! stop once Pᵀ r has fallen by [`COARSE_TOLERANCE`], or no status changed
//! in a step, or after [`COARSE_MAX_ITERATIONS`]; the fine pass then goes
//! on from there with its own convergence test, so the answer is the fine
//! one (only the path changes). A frictionless joint's first pass takes
//! them on a second level four times as wide first (see
//! [`crate::SolverOptions::coarse_levels`]): the front moves by the wide
//! segments, then by the narrow ones. Only passes without any frozen slip
//! limit above zero take coarse steps (frictionless joints, and a frictional
//! joint's first increment from the unloaded state): with stick zones in
//! place, the smooth coarse field undoes them, and the high-friction
//! counts got worse (level 4 at μ = 1: 69 iterations in one increment
//! instead of 54).

use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector};
use tecon_fem::CondensedCholesky;
use tecon_mesh::Point;

use crate::model::ModelInterface;

/// Most coarse dofs: the coarse nodes are every 2nd, 4th, 8th, ... face
/// node, the first spacing that keeps the coarse system this small (its
/// dense Cholesky factorisation, made at every coarse step, then costs a
/// few milliseconds). Measured (most Newton iterations in one increment,
/// frictionless / μ = 0.3, without coarse steps 13 / 26 on level 2,
/// 22 / 30 on level 3, 30 / 30 on level 4, 30 / 42 on `t1e5`): every 2nd
/// node 11 / 18, 11 / 18, 15 / 21 and (not definite in round-off before
/// the diagonal shift) –; every 4th 18 / 24, 16 / 20, 20 / 28, 14 / 18;
/// every 8th 21 / 29, 20 / 26, 18 / 24, 15 / 25; every 16th on level 4
/// and `t1e5` 25 / 29 and 24 / 30. The finest spacing does best where
/// it is affordable; this cap gives every 2nd node on levels 2 and 3 and
/// every 4th on level 4 and `t1e5`.
pub(super) const MAX_COARSE_DOFS: usize = 512;

/// The ratio of the node spacings of two successive coarse levels (a power
/// of two).
pub(super) const COARSE_LEVEL_SPACING: u32 = 4;

/// Fewest dofs of a coarser level.
const MIN_COARSE_DOFS: usize = 8;

/// Shift of the coarse system's diagonal, relative to the largest diagonal
/// entry of the bulk's coarse system Pᵀ S_b P, when it is not definite in
/// round-off without: Pᵀ (S + K_c) P is a difference of large numbers
/// (S = A_ΓΓ − C). (Relative to the largest entry of Pᵀ (S + K_c) P,
/// which the joint's penalty sets, the shift slowed the coarse steps on
/// `t1e5` to their limit of 30.)
const COARSE_SHIFT: f64 = 1e-8;

/// The coarse iteration stops once ‖Pᵀ r‖ is this fraction of its start.
pub(super) const COARSE_TOLERANCE: f64 = 1e-3;

/// Most coarse iterations before a pass.
pub(super) const COARSE_MAX_ITERATIONS: usize = 30;

/// The coarse iteration runs only when the pass starts at a relative
/// residual of at least this: close to an equilibrium (a later output time
/// that moves little) the fine statuses, stick zones most of all, are
/// better than anything the smooth coarse field can make of them
/// (measured on `t1e5` at μ = 0.3: without this gate the last two output
/// times took 22 and 54 iterations instead of 8).
pub(super) const COARSE_GATE: f64 = 1e-2;

/// Per Γ position, its (coarse dof, weight) entries.
pub(super) type Rows = Vec<Vec<(usize, f64)>>;

/// Per fine node: its (coarse node, weight) entries and the face tangent
/// there.
type NodeRules = BTreeMap<usize, (Vec<(usize, f64)>, [f64; 2])>;

/// The faces of one interface element: the bottom face's nodes in order
/// (corner, [mid,] corner) and the top face's nodes facing them.
pub(super) type Faces = (Vec<usize>, Vec<usize>);

/// The faces of every element of `interface`.
pub(super) fn element_faces(interface: &ModelInterface) -> Vec<Faces> {
    if interface.is_quadratic() {
        interface
            .quadratic_nodes
            .iter()
            .map(|n| (vec![n[0], n[4], n[1]], vec![n[3], n[5], n[2]]))
            .collect()
    } else {
        interface
            .nodes
            .iter()
            .map(|n| (vec![n[0], n[1]], vec![n[3], n[2]]))
            .collect()
    }
}

/// The interpolation P: for every Γ position (dof `gamma[a]` = 2 node +
/// component) its (coarse dof, weight) entries, none for a constrained
/// position (`fixed`), and the number of coarse dofs. None when the
/// interfaces' elements do not form simple chains (an element with more
/// than two neighbours along its face), when a Γ node lies on no
/// interface face, or when the coarse space would not be smaller than Γ.
pub(super) fn interpolation(
    interfaces: &[Vec<Faces>],
    coords: &[Point],
    gamma: &[usize],
    fixed: &[bool],
    spacing: usize,
) -> Option<(Rows, usize)> {
    // fine node → (coarse node, weight) entries and the face tangent there
    let mut rule = NodeRules::new();
    let mut coarse_nodes = 0usize;
    for faces in interfaces {
        for (chain, cycle) in chains(faces)? {
            // the nodes of each face along the chain, the elements oriented
            // so that each ends where the next begins
            let mut seq: [Vec<usize>; 2] = [Vec::new(), Vec::new()];
            for (j, &e) in chain.iter().enumerate() {
                let (bottom, top) = &faces[e];
                let first = bottom[0];
                let shared_with = |other: usize| {
                    let b = &faces[other].0;
                    b[0] == first || b[b.len() - 1] == first
                };
                // reversed when its first corner is the one it shares with
                // the next element, or not the one it shares with the one
                // before
                let reversed = if j + 1 < chain.len() {
                    shared_with(chain[j + 1])
                } else if j > 0 {
                    !shared_with(chain[j - 1])
                } else {
                    false
                };
                for (s, face) in [bottom, top].into_iter().enumerate() {
                    let mut nodes = face.clone();
                    if reversed {
                        nodes.reverse();
                    }
                    // the last node is the next element's first
                    seq[s].extend_from_slice(&nodes[..nodes.len() - 1]);
                    if j + 1 == chain.len() && !cycle {
                        seq[s].push(nodes[nodes.len() - 1]);
                    }
                }
            }
            for nodes in &seq {
                coarse_nodes = face_rule(nodes, cycle, coords, spacing, coarse_nodes, &mut rule);
            }
        }
    }
    let mut p = Vec::with_capacity(gamma.len());
    for (a, &d) in gamma.iter().enumerate() {
        if fixed[a] {
            p.push(Vec::new());
            continue;
        }
        let (entries, t) = rule.get(&(d / 2))?;
        let c = d % 2;
        let n = [-t[1], t[0]];
        let mut row = Vec::with_capacity(2 * entries.len());
        for &(j, w) in entries {
            row.push((2 * j, w * n[c]));
            row.push((2 * j + 1, w * t[c]));
        }
        p.push(row);
    }
    let mc = 2 * coarse_nodes;
    (mc > 0 && mc < gamma.len()).then_some((p, mc))
}

/// The elements of one interface in chains along their faces (neighbours:
/// elements sharing a bottom corner), each with whether it closes on
/// itself; None if an element has more than two neighbours.
fn chains(faces: &[Faces]) -> Option<Vec<(Vec<usize>, bool)>> {
    let mut by_node: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (e, (bottom, _)) in faces.iter().enumerate() {
        for v in [bottom[0], bottom[bottom.len() - 1]] {
            by_node.entry(v).or_default().push(e);
        }
    }
    let mut next: Vec<Vec<usize>> = vec![Vec::new(); faces.len()];
    for els in by_node.values() {
        for &a in els {
            for &b in els {
                if a != b && !next[a].contains(&b) {
                    next[a].push(b);
                }
            }
        }
    }
    if next.iter().any(|n| n.len() > 2) {
        return None;
    }
    for n in &mut next {
        n.sort_unstable();
    }
    let mut visited = vec![false; faces.len()];
    let mut out = Vec::new();
    // open chains from their ends first, then the closed ones
    let starts: Vec<usize> = (0..faces.len())
        .filter(|&e| next[e].len() < 2)
        .chain(0..faces.len())
        .collect();
    for s in starts {
        if visited[s] {
            continue;
        }
        let open = next[s].len() < 2;
        let mut chain = vec![s];
        visited[s] = true;
        let mut cur = s;
        while let Some(&n) = next[cur].iter().find(|&&n| !visited[n]) {
            visited[n] = true;
            chain.push(n);
            cur = n;
        }
        let cycle = !open && chain.len() > 2 && next[cur].contains(&s);
        out.push((chain, cycle));
    }
    Some(out)
}

/// Adds the interpolation rule of the nodes `nodes` of one face (in order
/// along it; `cycle`: the last is followed by the first) to `rule`, with
/// coarse nodes numbered from `first`; returns the next free number. A
/// node that already has a rule (a node on two faces) keeps it.
fn face_rule(
    nodes: &[usize],
    cycle: bool,
    coords: &[Point],
    spacing: usize,
    first: usize,
    rule: &mut NodeRules,
) -> usize {
    let n = nodes.len();
    let at = |i: usize| coords[nodes[i % n]];
    let dist = |a: Point, b: Point| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
    // arc length at every node, and at the wrap-around for a cycle
    let mut s = vec![0.0; n + 1];
    for i in 1..=n {
        s[i] = s[i - 1] + dist(at(i - 1), at(i));
    }
    // coarse positions: every `spacing`-th node, and the last of an open face
    let mut coarse: Vec<usize> = (0..n).step_by(spacing.max(1)).collect();
    if !cycle && coarse.last() != Some(&(n - 1)) {
        coarse.push(n - 1);
    }
    let id = |k: usize| first + k % coarse.len();
    for (k, &ia) in coarse.iter().enumerate() {
        let ib = match coarse.get(k + 1) {
            Some(&b) => b,
            None if cycle => n,
            None => ia + 1,
        };
        for i in ia..ib.min(n) {
            let span = s[ib.min(n)] - s[ia];
            let w = if i == ia {
                0.0
            } else if span > 0.0 {
                (s[i] - s[ia]) / span
            } else {
                (i - ia) as f64 / (ib - ia) as f64
            };
            let mut entries = vec![(id(k), 1.0 - w)];
            if w != 0.0 {
                entries.push((id(k + 1), w));
            }
            // the face tangent from the neighbours (one-sided at open ends)
            let (a, b) = match (i, cycle) {
                (0, false) => (at(0), at(1.min(n - 1))),
                (i, false) if i + 1 == n => (at(i - 1), at(i)),
                (i, _) => (at(i + n - 1), at(i + 1)),
            };
            let l = dist(a, b);
            let t = if l > 0.0 {
                [(b[0] - a[0]) / l, (b[1] - a[1]) / l]
            } else {
                [1.0, 0.0]
            };
            rule.entry(nodes[i]).or_insert((entries, t));
        }
    }
    first + coarse.len()
}

/// The coarse space of a condensation: P, Pᵀ C P and S_b P (S_b the bulk's
/// Schur complement), made once per condensation (C and S_b do not change
/// within a solver).
#[derive(Debug)]
pub(super) struct CoarseSpace {
    /// Per Γ position: its (coarse dof, weight) entries.
    rows: Rows,
    mc: usize,
    /// Pᵀ C P, mc × mc column-major.
    ptcp: Vec<f64>,
    /// S_b P, m × mc column-major.
    sbp: Vec<f64>,
    /// [`COARSE_SHIFT`] × the largest diagonal entry of Pᵀ S_b P.
    shift: f64,
}

impl CoarseSpace {
    /// The coarse spaces of `interfaces` (see [`interpolation`]) on the Γ
    /// of `chol`, whose bulk A_ΓΓ values are `bulk_gg` (in
    /// [`CondensedCholesky::gamma_entries`] order), coarsest first: the
    /// finest spacing within [`MAX_COARSE_DOFS`], then up to `levels` − 1
    /// coarser ones, each [`COARSE_LEVEL_SPACING`] times as wide, while
    /// they keep [`MIN_COARSE_DOFS`]. Empty when the interfaces are no
    /// simple chains.
    pub fn hierarchy(
        interfaces: &[Vec<Faces>],
        coords: &[Point],
        chol: &CondensedCholesky,
        bulk_gg: &[f64],
        fixed: &[bool],
        levels: u32,
    ) -> Vec<Self> {
        let gamma = chol.gamma();
        // the finest spacing within the size cap
        let Some((e0, (rows, mc))) = (1..=16u32)
            .map_while(|e| interpolation(interfaces, coords, gamma, fixed, 1 << e).map(|r| (e, r)))
            .find(|(_, (_, mc))| *mc <= MAX_COARSE_DOFS)
        else {
            return Vec::new();
        };
        let mut out = vec![Self::new(rows, mc, chol, bulk_gg)];
        for level in 1..levels {
            let e = e0 + level * COARSE_LEVEL_SPACING.ilog2();
            match interpolation(interfaces, coords, gamma, fixed, 1 << e) {
                Some((rows, mc)) if mc >= MIN_COARSE_DOFS => {
                    out.push(Self::new(rows, mc, chol, bulk_gg));
                }
                _ => break,
            }
        }
        out.reverse();
        out
    }

    /// The coarse space whose Γ positions interpolate the `mc` coarse dofs
    /// by `rows`.
    fn new(rows: Rows, mc: usize, chol: &CondensedCholesky, bulk_gg: &[f64]) -> Self {
        let gamma = chol.gamma();
        let m = gamma.len();
        let c = chol.coupling_matrix();
        // S_b P = A_ΓΓ P − C P, column by column
        let mut sbp = vec![0.0; m * mc];
        for (a, row) in rows.iter().enumerate() {
            let col = &c[a * m..(a + 1) * m];
            for &(j, w) in row {
                for (o, x) in sbp[j * m..(j + 1) * m].iter_mut().zip(col) {
                    *o -= w * x;
                }
            }
        }
        let mut space = CoarseSpace {
            rows,
            mc,
            ptcp: Vec::new(),
            sbp,
            shift: 0.0,
        };
        // Pᵀ C P = −Pᵀ (the C P part of S_b P, before A_ΓΓ P is added)
        let mut ptcp = vec![0.0; mc * mc];
        for j in 0..mc {
            let r = space.restrict(&space.sbp[j * m..(j + 1) * m]);
            for (o, x) in ptcp[j * mc..(j + 1) * mc].iter_mut().zip(r) {
                *o = -x;
            }
        }
        let (ptr, col, _) = chol.gamma_entries();
        for a in 0..m {
            for k in ptr[a]..ptr[a + 1] {
                let g = bulk_gg[k];
                if g == 0.0 {
                    continue;
                }
                for &(j, w) in &space.rows[col[k]] {
                    space.sbp[j * m + a] += g * w;
                }
            }
        }
        space.ptcp = ptcp;
        // the diagonal of Pᵀ S_b P, one pass over P's entries
        let mut diag = vec![0.0; mc];
        for (a, row) in space.rows.iter().enumerate() {
            for &(j, w) in row {
                diag[j] += w * space.sbp[j * m + a];
            }
        }
        space.shift = COARSE_SHIFT * diag.iter().map(|d| d.abs()).fold(0.0, f64::max);
        space
    }

    /// Coarse dofs.
    pub fn dofs(&self) -> usize {
        self.mc
    }

    /// Pᵀ x for x on Γ.
    pub fn restrict(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.mc];
        for (row, xa) in self.rows.iter().zip(x) {
            for &(j, w) in row {
                y[j] += w * xa;
            }
        }
        y
    }

    /// P y on Γ.
    pub fn prolong(&self, y: &[f64]) -> Vec<f64> {
        self.rows
            .iter()
            .map(|row| row.iter().map(|&(j, w)| w * y[j]).sum())
            .collect()
    }

    /// S_b P y.
    pub fn bulk_product(&self, y: &[f64]) -> Vec<f64> {
        let m = self.rows.len();
        let mut out = vec![0.0; m];
        for (j, &yj) in y.iter().enumerate() {
            if yj != 0.0 {
                for (o, x) in out.iter_mut().zip(&self.sbp[j * m..(j + 1) * m]) {
                    *o += yj * x;
                }
            }
        }
        out
    }

    /// Solves Pᵀ (A_ΓΓ − C) P y = b, A_ΓΓ the Γ × Γ tangent values `gg` in
    /// the (`ptr`, `col`) layout of [`CondensedCholesky::gamma_entries`];
    /// None if that matrix is not positive definite (a body every point
    /// has let go of).
    pub fn solve(&self, ptr: &[usize], col: &[usize], gg: &[f64], b: Vec<f64>) -> Option<Vec<f64>> {
        let mc = self.mc;
        let mut h: Vec<f64> = self.ptcp.iter().map(|x| -x).collect();
        for (a, row) in self.rows.iter().enumerate() {
            for k in ptr[a]..ptr[a + 1] {
                let g = gg[k];
                if g == 0.0 {
                    continue;
                }
                for &(i, wi) in row {
                    for &(j, wj) in &self.rows[col[k]] {
                        h[j * mc + i] += wi * g * wj;
                    }
                }
            }
        }
        let chol = match DMatrix::from_column_slice(mc, mc, &h).cholesky() {
            Some(c) => c,
            None => {
                for i in 0..mc {
                    h[i * mc + i] += self.shift;
                }
                DMatrix::from_column_slice(mc, mc, &h).cholesky()?
            }
        };
        Some(chol.solve(&DVector::from_vec(b)).as_slice().to_vec())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring sector of `n` linear interface elements at radius 1 between
    /// θ = 0 and `sweep`: bottom nodes 0..=n, top nodes n+1..=2n+1 (facing
    /// them); element `e` reversed if `flip(e)`.
    fn arc(n: usize, sweep: f64, flip: impl Fn(usize) -> bool) -> (Vec<Faces>, Vec<Point>) {
        let mut coords = Vec::new();
        for _ in 0..2 {
            for i in 0..=n {
                let t = sweep * i as f64 / n as f64;
                coords.push([t.cos(), t.sin()]);
            }
        }
        let faces = (0..n)
            .map(|e| {
                let (b, t) = (vec![e, e + 1], vec![n + 1 + e, n + 2 + e]);
                if flip(e) {
                    (b.into_iter().rev().collect(), t.into_iter().rev().collect())
                } else {
                    (b, t)
                }
            })
            .collect();
        (faces, coords)
    }

    fn all_dofs(nodes: usize) -> Vec<usize> {
        (0..2 * nodes).collect()
    }

    #[test]
    fn a_coarse_slip_along_a_curved_face_has_no_normal_part() {
        let n = 40;
        let (faces, coords) = arc(n, 1.2, |e| e % 3 == 1);
        let gamma = all_dofs(2 * (n + 1));
        let fixed = vec![false; gamma.len()];
        let (rows, mc) = interpolation(&[faces], &coords, &gamma, &fixed, 8).unwrap();
        // 41 nodes per face: coarse at 0, 8, ..., 40 → 6 per face, 2 dofs each
        assert_eq!(mc, 2 * 2 * 6);
        let space = CoarseSpace {
            rows,
            mc,
            ptcp: Vec::new(),
            sbp: Vec::new(),
            shift: 0.0,
        };
        // every coarse tangential dof 1 (per face, the same direction of
        // travel on both faces), normal 0: a tangential field of unit
        // length, the same on facing nodes (the tangent of an inner node is
        // the chord of its neighbours, exact on this uniform arc; at the
        // two ends it is the chord of the end segment)
        let y: Vec<f64> = (0..mc).map(|j| (j % 2) as f64).collect();
        let d = space.prolong(&y);
        for v in 0..2 * (n + 1) {
            let x = coords[v];
            let (dx, dy) = (d[2 * v], d[2 * v + 1]);
            let normal = dx * x[0] + dy * x[1];
            let end = v % (n + 1) == 0 || v % (n + 1) == n;
            let bound = if end {
                (0.6f64 / n as f64).sin()
            } else {
                1e-14
            };
            assert!(normal.abs() <= bound, "node {v}: normal part {normal:e}");
            assert!(((dx * dx + dy * dy).sqrt() - 1.0).abs() < 1e-12, "node {v}");
        }
        for v in 0..=n {
            let w = v + n + 1;
            assert!(
                (d[2 * v] - d[2 * w]).abs() < 1e-14 && (d[2 * v + 1] - d[2 * w + 1]).abs() < 1e-14
            );
        }
        // a coarse normal field linear along the coarse nodes is linear in
        // arc length on the fine nodes between them (uniform arc here)
        let y: Vec<f64> = (0..mc)
            .map(|j| if j % 2 == 0 { (j / 2 % 6) as f64 } else { 0.0 })
            .collect();
        let d = space.prolong(&y);
        for (v, x) in coords.iter().enumerate().take(n + 1) {
            // the face normal is the inward one here: −x
            let normal = -(d[2 * v] * x[0] + d[2 * v + 1] * x[1]);
            // (the end nodes' chord frame is 0.015 rad off the radius)
            let tol = if v == 0 || v == n {
                2e-4 * normal
            } else {
                1e-12
            };
            assert!((normal - v as f64 / 8.0).abs() <= tol, "node {v}: {normal}");
        }
    }

    #[test]
    fn constrained_positions_and_branched_faces() {
        let n = 20;
        let (mut faces, coords) = arc(n, 0.5, |_| false);
        let gamma = all_dofs(2 * (n + 1));
        let mut fixed = vec![false; gamma.len()];
        fixed[0] = true;
        let (rows, _) = interpolation(&[faces.clone()], &coords, &gamma, &fixed, 8).unwrap();
        assert!(rows[0].is_empty() && !rows[1].is_empty());
        // a Γ node on no face
        assert!(
            interpolation(
                &[faces.clone()],
                &coords,
                &all_dofs(2 * (n + 1) + 1),
                &{
                    let mut f = fixed.clone();
                    f.extend([false, false]);
                    f
                },
                8
            )
            .is_none()
        );
        // a third element at node 5 of the bottom face: no chain
        faces.push((vec![5, 0], vec![30, 31]));
        assert!(interpolation(&[faces], &coords, &gamma, &fixed, 8).is_none());
    }

    #[test]
    fn a_closed_ring_is_one_cycle() {
        // 32 elements round a full circle: node 32 is node 0
        let n = 32;
        let (faces, mut coords) = arc(n, 2.0 * std::f64::consts::PI, |_| false);
        let faces: Vec<Faces> = faces
            .into_iter()
            .map(|(b, t)| {
                let wrap = |v: usize| {
                    if v == n {
                        0
                    } else if v == 2 * n + 1 {
                        n + 1
                    } else {
                        v
                    }
                };
                (
                    b.into_iter().map(wrap).collect(),
                    t.into_iter().map(wrap).collect(),
                )
            })
            .collect();
        coords[n] = coords[0];
        let gamma: Vec<usize> = (0..2 * (2 * n + 2))
            .filter(|d| d / 2 != n && d / 2 != 2 * n + 1)
            .collect();
        let fixed = vec![false; gamma.len()];
        let (rows, mc) = interpolation(&[faces], &coords, &gamma, &fixed, 8).unwrap();
        // 32 nodes per face, coarse every 8th: 4 per face
        assert_eq!(mc, 2 * 2 * 4);
        // the node before the wrap interpolates the last and the first
        // coarse nodes of its face
        let last = gamma.iter().position(|&d| d == 2 * (n - 1)).unwrap();
        let coarse: Vec<usize> = rows[last].iter().map(|e| e.0 / 2).collect();
        assert!(coarse.contains(&0) && coarse.contains(&3), "{coarse:?}");
    }
}
