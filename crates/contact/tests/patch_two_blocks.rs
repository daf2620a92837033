//! # Stiff-joint two-block patch test: nodal vs Gauss integration
//!
//! Reference: J.C.J. Schellekens & R. de Borst, "On the numerical
//! integration of interface elements", IJNME 36 (1993) 43–66: with a high
//! (dummy) joint stiffness, Gauss-integrated linear interface elements give
//! spurious traction oscillations; nodal (Newton–Cotes/Lobatto) integration
//! does not. DESIGN.md §2 asks for nodal integration by default.
//!
//! Goal: (1) a genuine patch test — a uniform stress state passes through
//! the joint exactly with either rule; (2) with a traction gradient (a
//! notched joint) and a stiff joint, the Gauss-integrated traction profile oscillates from point
//! to point while the nodal one is smooth.
//!
//! Sketch (plane strain, unit thickness, E = 200 GPa, ν = 0.3):
//!
//! ```text
//!            load on the top edge (uniform pressure, or a uniform pull)
//!        ┌──────────────────────────────┐  y = H
//!   u=0  │  top block    (CST, own nodes)│
//!        ├┄┄┄┄┄┄┄┬══════════════════════┤  y = 0: NX interface elements, k_n = k_s = k
//!   u=0  │  bottom block (CST, own nodes)│  notched case: none on 0 ≤ x < W/4 (┄ crack)
//!        └──────────────────────────────┘  y = −H, v = 0
//!        x = 0                         x = W
//! ```
//!
//! Boundary conditions: v = 0 on y = −H, u = 0 on x = 0 (both blocks): the
//! uniform-pressure case then has the exact solution σ_yy = −p, σ_xx = 0,
//! which linear triangles reproduce exactly.
//!
//! Checked:
//! * uniform pressure p: every interface point has traction exactly
//!   [0, −p] (to 1e-9 relative) with both rules;
//! * notched joint (the first quarter of the interface has no interface
//!   elements: an open crack), uniform pull p0 on the top edge, joint
//!   stiffness k = β·E/h for β = 0.1 … 1e4. The traction is singular at the
//!   crack tip and decays monotonically away from it. Oscillation measure:
//!   half the total variation of the point tractions in excess of a monotone
//!   profile's, over p0 (zero for a monotone profile), and the number of
//!   interior local extrema. For β ≥ 100: nodal — zero extrema, measure
//!   < 1e-6; Gauss — at least 3 extrema and measure > 0.5 (a Gauss point
//!   next to the tip even turns compressive in a pure pull). For β = 0.1
//!   neither rule oscillates: the stiffness triggers it. The resultant of
//!   the tractions equals p0·W in every case (equilibrium, 1e-9).
//!
//! Why: with the nodal rule each integration point sees one facing node
//! pair, so a point's traction is the interface nodal force divided by its
//! tributary length — a local, smooth quantity. With Gauss the element
//! matrix couples neighbouring pairs like a consistent mass matrix
//! (`L/6·[2 1; 1 2]`); in the stiff limit the tractions are obtained by
//! inverting that matrix on the bulk's nodal forces, which amplifies their
//! point-to-point (zig-zag) component by up to 3× per element and with
//! alternating sign. Measured here (printed by the test): Gauss oscillation
//! measure 1.27 already at β = 10 (the default penalty factor), 2.00 at
//! β = 100, 2.11 at β = 1e4; nodal 0 throughout.

use tecon_contact::nalgebra::{DMatrix, DVector, Matrix3, Point2, SMatrix};
use tecon_contact::{InterfaceElement, InterfaceQuadrature, LinearJoint, Vector8};

const E: f64 = 200.0e9;
const NU: f64 = 0.3;
const W: f64 = 1.0;
const H: f64 = 0.25;
const NX: usize = 16;
const NY: usize = 4;

/// Plane-strain CST stiffness (unit thickness): `A Bᵀ D B`.
fn cst_stiffness(x: [Point2<f64>; 3]) -> SMatrix<f64, 6, 6> {
    let f = E / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let d = Matrix3::new(
        1.0 - NU,
        NU,
        0.0,
        NU,
        1.0 - NU,
        0.0,
        0.0,
        0.0,
        0.5 * (1.0 - 2.0 * NU),
    ) * f;
    let two_a = (x[1].x - x[0].x) * (x[2].y - x[0].y) - (x[2].x - x[0].x) * (x[1].y - x[0].y);
    assert!(two_a > 0.0, "triangle must be counter-clockwise");
    let mut b = SMatrix::<f64, 3, 6>::zeros();
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let bi = (x[j].y - x[k].y) / two_a; // ∂N_i/∂x
        let ci = (x[k].x - x[j].x) / two_a; // ∂N_i/∂y
        b[(0, 2 * i)] = bi;
        b[(1, 2 * i + 1)] = ci;
        b[(2, 2 * i)] = ci;
        b[(2, 2 * i + 1)] = bi;
    }
    b.transpose() * d * b * (0.5 * two_a)
}

/// A tiny two-block model assembled by hand into dense matrices.
struct Model {
    nodes: Vec<Point2<f64>>,
    triangles: Vec<[usize; 3]>,
    /// Interface elements as node quadruples [b_i, b_i+1, t_i+1, t_i].
    interfaces: Vec<[usize; 4]>,
    /// Top-edge nodes of the top block, left to right.
    top_edge: Vec<usize>,
    fixed: Vec<usize>, // constrained dofs
}

fn block(nodes: &mut Vec<Point2<f64>>, tris: &mut Vec<[usize; 3]>, y0: f64) -> Vec<Vec<usize>> {
    // grid[j][i], j = 0 bottom row, i = 0 left.
    let grid: Vec<Vec<usize>> = (0..=NY)
        .map(|j| {
            (0..=NX)
                .map(|i| {
                    nodes.push(Point2::new(
                        W * i as f64 / NX as f64,
                        y0 + H * j as f64 / NY as f64,
                    ));
                    nodes.len() - 1
                })
                .collect()
        })
        .collect();
    for j in 0..NY {
        for i in 0..NX {
            let (a, b, c, d) = (
                grid[j][i],
                grid[j][i + 1],
                grid[j + 1][i + 1],
                grid[j + 1][i],
            );
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    grid
}

fn model() -> Model {
    let (mut nodes, mut triangles) = (Vec::new(), Vec::new());
    let bottom = block(&mut nodes, &mut triangles, -H);
    let top = block(&mut nodes, &mut triangles, 0.0);
    let interfaces = (0..NX)
        .map(|i| [bottom[NY][i], bottom[NY][i + 1], top[0][i + 1], top[0][i]])
        .collect();
    let mut fixed: Vec<usize> = bottom[0].iter().map(|&n| 2 * n + 1).collect();
    for g in [&bottom, &top] {
        fixed.extend(g.iter().map(|row| 2 * row[0]));
    }
    Model {
        nodes,
        triangles,
        interfaces,
        top_edge: top[NY].clone(),
        fixed,
    }
}

/// Interface output of a solve.
struct Solution {
    /// Points (x, σ, τ) sorted by x (nodal rule: one value per node pair).
    points: Vec<(f64, f64, f64)>,
    /// `∫ σ dx` over the interface with the element's own rule.
    resultant: f64,
}

/// Solve the linear problem with joint stiffness `k`, rule `rule`, the first
/// `notch` interface elements left out (an open crack), and a pressure
/// `p(x)` on the top edge (consistent load of piecewise-linear p).
fn solve(k: f64, rule: InterfaceQuadrature, notch: usize, p: impl Fn(f64) -> f64) -> Solution {
    let m = model();
    let n = 2 * m.nodes.len();
    let mut kk = DMatrix::<f64>::zeros(n, n);
    let mut f = DVector::<f64>::zeros(n);
    for t in &m.triangles {
        let ke = cst_stiffness(t.map(|i| m.nodes[i]));
        for a in 0..3 {
            for b in 0..3 {
                for (r, c) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    kk[(2 * t[a] + r, 2 * t[b] + c)] += ke[(2 * a + r, 2 * b + c)];
                }
            }
        }
    }
    let law = LinearJoint::new(k, k).unwrap();
    let interfaces = &m.interfaces[notch..];
    let elements: Vec<InterfaceElement> = interfaces
        .iter()
        .map(|q| InterfaceElement::with_quadrature(&q.map(|i| m.nodes[i]), rule).unwrap())
        .collect();
    for (q, e) in interfaces.iter().zip(&elements) {
        let ke = e.evaluate(&law, &Vector8::zeros(), &[(); 2]).tangent;
        for a in 0..4 {
            for b in 0..4 {
                for (r, c) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    kk[(2 * q[a] + r, 2 * q[b] + c)] += ke[(2 * a + r, 2 * b + c)];
                }
            }
        }
    }
    // Pressure (downwards) on the top edge: consistent load of linear p.
    for w in m.top_edge.windows(2) {
        let (xa, xb) = (m.nodes[w[0]].x, m.nodes[w[1]].x);
        let (pa, pb) = (p(xa), p(xb));
        let l = xb - xa;
        f[2 * w[0] + 1] -= l * (2.0 * pa + pb) / 6.0;
        f[2 * w[1] + 1] -= l * (pa + 2.0 * pb) / 6.0;
    }
    for &d in &m.fixed {
        kk.row_mut(d).fill(0.0);
        kk.column_mut(d).fill(0.0);
        kk[(d, d)] = 1.0;
        f[d] = 0.0;
    }
    let u = kk.lu().solve(&f).expect("the two-block system is regular");
    let mut out = Vec::new();
    let mut resultant = 0.0;
    for (q, e) in interfaces.iter().zip(&elements) {
        let ue = Vector8::from_fn(|i, _| u[2 * q[i / 2] + i % 2]);
        let r = e.evaluate(&law, &ue, &[(); 2]);
        let x0 = m.nodes[q[0]].x;
        for (p, ip) in r.points.iter().zip(e.points()) {
            resultant += ip.weight * p.traction.y;
            out.push((
                x0 + 0.5 * e.geometry().length() + p.zeta,
                p.traction.y,
                p.traction.x,
            ));
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Nodal rule: neighbouring elements share node positions; keep one value.
    out.dedup_by(|a, b| {
        (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() <= 1e-9 * a.1.abs().max(1.0)
    });
    Solution {
        points: out,
        resultant,
    }
}

/// Oscillation of a sampled profile: half the total variation in excess of
/// a monotone profile's, `(Σ|v_{i+1} − v_i| − |v_last − v_first|)/2`
/// (zero for a monotone profile, the sum of the overshoot amplitudes
/// otherwise), and the number of interior local extrema.
fn oscillation(v: &[f64]) -> (f64, usize) {
    let tv: f64 = v.windows(2).map(|w| (w[1] - w[0]).abs()).sum();
    let excess = 0.5 * (tv - (v[v.len() - 1] - v[0]).abs());
    let extrema = v
        .windows(3)
        .filter(|w| (w[1] - w[0]) * (w[2] - w[1]) < 0.0)
        .count();
    (excess, extrema)
}

#[test]
fn uniform_pressure_passes_the_joint_exactly_with_both_rules() {
    let p = 10.0e6;
    for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
        for k in [1.0e9, 1.0e16] {
            let sol = solve(k, rule, 0, |_| p);
            let worst = sol
                .points
                .iter()
                .map(|&(_, s, t)| ((s + p).abs() + t.abs()) / p)
                .fold(0.0, f64::max);
            println!(
                "{rule:?}, k = {k:.0e}: uniform pressure, worst relative traction error {worst:.1e}"
            );
            assert!(worst < 1e-9, "{rule:?} k={k}: {worst}");
        }
    }
}

/// Tractions of a notched, stiff joint under a uniform pull `p0` on the top edge.
fn notched(factor: f64, rule: InterfaceQuadrature, p0: f64) -> Vec<f64> {
    let k = factor * E / (W / NX as f64);
    let sol = solve(k, rule, NX / 4, |_| -p0);
    // Equilibrium: Σ w σ over the bonded part equals the applied pull p0·W.
    assert!(
        (sol.resultant - p0 * W).abs() < 1e-9 * p0 * W,
        "{rule:?}: resultant {}",
        sol.resultant
    );
    sol.points.iter().map(|p| p.1 / p0).collect()
}

#[test]
fn stiff_joint_traction_oscillates_with_gauss_not_with_nodal() {
    let p0 = 10.0e6;
    let mut table = Vec::new();
    for factor in [0.1, 1.0, 10.0, 1.0e2, 1.0e4] {
        let (vn, en) = oscillation(&notched(factor, InterfaceQuadrature::Nodal, p0));
        let (vg, eg) = oscillation(&notched(factor, InterfaceQuadrature::Gauss2, p0));
        println!(
            "k = {factor:.0e}·E/h: oscillation/p0 nodal {vn:.2e} ({en} extrema), Gauss {vg:.2e} ({eg} extrema)"
        );
        table.push((factor, vn, en, vg, eg));
    }
    let stiff = table.iter().filter(|r| r.0 >= 1.0e2);
    for &(factor, vn, en, vg, eg) in stiff {
        // Nodal: monotone profile away from the crack tip.
        assert_eq!(en, 0, "nodal rule oscillates at k = {factor}·E/h");
        assert!(vn < 1e-6, "nodal {vn}");
        // Gauss: repeated extrema, and an oscillation of the order of the
        // far-field traction itself.
        assert!(eg >= 3, "Gauss shows {eg} extrema at k = {factor}·E/h");
        assert!(vg > 0.5, "Gauss oscillation {vg} at k = {factor}·E/h");
    }
    // A soft joint does not oscillate with either rule: it is the stiffness
    // that triggers the Gauss oscillation.
    let soft = table[0];
    assert_eq!((soft.2, soft.4), (0, 0), "soft joint: {soft:?}");
}
