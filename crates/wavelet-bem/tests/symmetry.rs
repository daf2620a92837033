//! Folding the Daubechies system by the rotational symmetry of the
//! boundary (see `symmetry.rs`): the folded solve gives the whole
//! system's answers to rounding, and is used only where the discrete
//! boundary is symmetric.

use tecon_wavelet_bem::geometry::Section;
use tecon_wavelet_bem::grading::Parametrisation;
use tecon_wavelet_bem::solve::{Options, solve};
use tecon_wavelet_bem::*;

fn order_of(sec: &Section, n: usize) -> usize {
    let params: Vec<Parametrisation> = sec
        .curves()
        .iter()
        .map(|c| Parametrisation::with_zones(c, 8.0, None).exact_for(c, n))
        .collect();
    let nodes: Vec<_> = sec
        .curves()
        .iter()
        .zip(&params)
        .flat_map(|(c, p)| p.nodes(c, n))
        .collect();
    symmetry::rotation_order(
        &nodes,
        n,
        sec.centroid,
        sec.radius(),
        symmetry::relative_tolerance(sec),
    )
}

/// The solves of `sec` at n whole and folded, and their relative J difference.
fn whole_and_folded(
    sec: &Section,
    n: usize,
) -> (
    tecon_wavelet_bem::solve::TorsionSolution,
    tecon_wavelet_bem::solve::TorsionSolution,
    f64,
) {
    let whole = solve(
        sec,
        &Options {
            n,
            symmetry: false,
            ..Default::default()
        },
    )
    .unwrap();
    let folded = solve(
        sec,
        &Options {
            n,
            ..Default::default()
        },
    )
    .unwrap();
    let dj =
        (whole.torsional_rigidity - folded.torsional_rigidity).abs() / whole.torsional_rigidity;
    (whole, folded, dj)
}

#[test]
fn folded_and_whole_solves_agree() {
    let cases: Vec<(&str, Section, usize)> = vec![
        ("square", sections::rectangle(1.0, 1.0).unwrap(), 4),
        ("rectangle 2 x 1", sections::rectangle(2.0, 1.0).unwrap(), 2),
        (
            "regular 12-gon",
            sections::regular_polygon(12, 1.0).unwrap(),
            4,
        ),
        (
            "regular 24-gon",
            sections::regular_polygon(24, 1.0).unwrap(),
            8,
        ),
        ("hexagon", sections::regular_polygon(6, 1.0).unwrap(), 2),
        ("ellipse", sections::ellipse(2.0, 1.0).unwrap(), 2),
        ("tube", sections::tube(1.0, 0.6).unwrap(), 8),
        (
            "box",
            sections::hollow_rectangle(2.0, 1.0, 0.1, 0.05).unwrap(),
            2,
        ),
        (
            "square box",
            sections::hollow_rectangle(1.0, 1.0, 0.1, 0.1).unwrap(),
            4,
        ),
    ];
    for (name, sec, expect) in cases {
        for n in [128usize, 512] {
            let k = order_of(&sec, n);
            println!("{name} n = {n}: order {k}");
            let (whole, folded, dj) = whole_and_folded(&sec, n);
            let (tw, tf) = (whole.max_shear().value, folded.max_shear().value);
            println!(
                "  J {:.15e} vs {:.15e}: {dj:.2e}; tau {tw:?} vs {tf:?}",
                whole.torsional_rigidity, folded.torsional_rigidity
            );
            assert!(
                k >= expect.min(n / symmetry::MIN_PERIOD),
                "{name}: order {k}"
            );
            assert!(dj < 1e-13, "{name} n = {n}: J differs by {dj:e}");
            let (ww, wf) = (whole.warping(), folded.warping());
            // relative to Γ (on the tube, where Γ is 0, to the size Γ would have)
            let scale = ww
                .centroidal_constant
                .abs()
                .max(1e-12 * sec.polar_moment() * sec.area);
            let dg = (ww.centroidal_constant - wf.centroidal_constant).abs() / scale;
            println!(
                "  Gamma {:.6e} vs {:.6e}: {dg:.2e}",
                ww.centroidal_constant, wf.centroidal_constant
            );
            assert!(dg < 1e-11, "{name} n = {n}: Γ differs by {dg:e}");
        }
    }
}

/// A square turned by `angle` and moved by `shift`, optionally with one
/// vertex moved by `nudge`.
fn square(angle: f64, shift: [f64; 2], nudge: f64) -> Section {
    let (s, c) = angle.sin_cos();
    let corners = [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5 + nudge], [-0.5, 0.5]];
    let v: Vec<[f64; 2]> = corners
        .iter()
        .map(|p| {
            [
                c * p[0] - s * p[1] + shift[0],
                s * p[0] + c * p[1] + shift[1],
            ]
        })
        .collect();
    sections::polygon(&v).unwrap()
}

#[test]
fn only_symmetric_boundaries_are_folded() {
    let n = 512;
    // a turn and a move keep the square's 4-fold rotation (about its centroid)
    assert_eq!(order_of(&square(0.3, [2.0, -7.0], 0.0), n), 4);
    // no rotation by 2π/k with k a power of two maps these onto themselves
    let none: Vec<(&str, Section)> = vec![
        ("triangle (3-fold)", sections::triangle(1.0).unwrap()),
        ("regular 9-gon", sections::regular_polygon(9, 1.0).unwrap()),
        ("groove", sections::groove(1.0, 0.5).unwrap()),
        ("limaçon", sections::limacon(1.0, 0.3).unwrap()),
        (
            "L",
            sections::polygon(&[
                [0.0, 0.0],
                [2.0, 0.0],
                [2.0, 1.0],
                [1.0, 1.0],
                [1.0, 2.0],
                [0.0, 2.0],
            ])
            .unwrap(),
        ),
        (
            "square, one corner moved by 1e-9",
            square(0.0, [0.0, 0.0], 1e-9),
        ),
    ];
    for (name, sec) in none {
        assert_eq!(order_of(&sec, n), 1, "{name}");
    }
    // a box whose hole is off centre: the outer curve has the half turn, the
    // hole does not
    let centred = sections::hollow_rectangle(2.0, 1.0, 0.1, 0.1).unwrap();
    let whole = solve(
        &centred,
        &Options {
            n: 256,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(whole.symmetry_order, 2);
    let off = Section::with_holes(
        sections::rectangle(2.0, 1.0).unwrap(),
        vec![sections::polygon(&[[-0.9, -0.4], [0.8, -0.4], [0.8, 0.4], [-0.9, 0.4]]).unwrap()],
    )
    .unwrap();
    let s = solve(
        &off,
        &Options {
            n: 256,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(s.symmetry_order, 1);
    // the reported order is the one used, and --no-symmetry solves whole
    let sq = solve(
        &square(0.0, [0.0, 0.0], 0.0),
        &Options {
            n: 256,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(sq.symmetry_order, 4);
    let sq = solve(
        &square(0.0, [0.0, 0.0], 0.0),
        &Options {
            n: 256,
            symmetry: false,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(sq.symmetry_order, 1);
}

/// Odd rotational symmetries: at n = q 2^j the panels of equal pieces are
/// exact (`Parametrisation::exact_for`) and a shift by n/N nodes turns a
/// regular N-gon by 2π/N; folded and whole solves agree, and the ladder
/// runs on the rungs q 2^j with estimates that bound the true errors.
#[test]
fn odd_rotations_fold_on_their_own_rungs() {
    for (name, sec, n, order) in [
        ("triangle", sections::triangle(1.0).unwrap(), 192, 3),
        (
            "hexagon",
            sections::regular_polygon(6, 1.0).unwrap(),
            192,
            6,
        ),
        ("9-gon", sections::regular_polygon(9, 1.0).unwrap(), 576, 9),
        (
            "25-gon",
            sections::regular_polygon(25, 1.0).unwrap(),
            800,
            25,
        ),
    ] {
        assert_eq!(order_of(&sec, n), order, "{name}");
        let (_, folded, dj) = whole_and_folded(&sec, n);
        assert_eq!(folded.symmetry_order, order, "{name}");
        assert!(dj < 1e-13, "{name}: J differs by {dj:e}");
        // at a power of two the panels stay dyadic: only the rotations of
        // order 2, 4, … remain (the hexagon's half turn)
        let dyadic = if order == 6 { 2 } else { 1 };
        assert_eq!(order_of(&sec, 512), dyadic, "{name}");
    }
    // the ladder of the 25-gon: rungs 25·2^j; its estimates against the
    // solution at n = 6400 (256 nodes per side)
    let sec = sections::regular_polygon(25, 1.0).unwrap();
    assert_eq!(control::rung_base(&sec, &Options::default()), 25);
    let reference = solve(
        &sec,
        &Options {
            n: 6400,
            ..Default::default()
        },
    )
    .unwrap();
    let tau_ref = reference.max_shear().value.unwrap();
    for tol in [1e-6, 1e-8, 1e-10] {
        let c = control::solve_to_tolerance(&sec, &Options::default(), tol, 4096).unwrap();
        let n = c.solution.options.n;
        assert!(
            n.is_multiple_of(25) && (n / 25).is_power_of_two(),
            "n = {n}"
        );
        assert!(c.converged, "tol {tol:e}");
        let ej = (c.solution.torsional_rigidity - reference.torsional_rigidity).abs()
            / reference.torsional_rigidity;
        let et = (c.solution.max_shear().value.unwrap() - tau_ref).abs() / tau_ref;
        assert!(
            ej <= c.j_error,
            "tol {tol:e}: J off by {ej:e}, estimate {:e}",
            c.j_error
        );
        let tau_est = c.tau_error.unwrap();
        assert!(
            et <= tau_est,
            "tol {tol:e}: τ off by {et:e}, estimate {tau_est:e}"
        );
    }
}

/// The tangents and offsets of short edges carry their end points' rounding
/// over their length: the regular 3000-gon's edges (2.1e-3 long, vertices
/// from cos and sin) differ by 1.0e-12 of their length, beyond the plain
/// relative tolerance 1e-12. Scaled by the shortest piece
/// (`symmetry::relative_tolerance`: 1e-13 R / L = 4.8e-11 here), its graded
/// nodes at 16 per edge keep their 3000-fold rotation. The test stays a
/// test: one node's tangent stretched by 1e-11 (within it) keeps the
/// rotation, by 1e-9 (20 times it) breaks every one; the square keeps 1e-12.
#[test]
fn short_edges_keep_their_rotation_to_round_off() {
    let p = sections::regular_polygon(3000, 1.0).unwrap();
    let tol = symmetry::relative_tolerance(&p);
    assert!(tol > 1e-12 && tol < 1e-10, "{tol:e}");
    let graded = p.with_flat_vertices_graded();
    assert!(graded.pieces_of_equal_length());
    let n = 48_000;
    assert_eq!(order_of(&graded, n), 3000);
    let nodes = Parametrisation::with_zones(&graded, 8.0, None)
        .exact_for(&graded, n)
        .nodes(&graded, n);
    let stretched = |factor: f64| {
        let mut v = nodes.clone();
        v[123].d1 = [v[123].d1[0] * factor, v[123].d1[1] * factor];
        symmetry::rotation_order(&v, n, graded.centroid, graded.radius(), tol)
    };
    assert_eq!(stretched(1.0 + 1e-11), 3000);
    assert_eq!(stretched(1.0 + 1e-9), 1);
    let square = sections::rectangle(1.0, 1.0).unwrap();
    assert_eq!(
        symmetry::relative_tolerance(&square),
        symmetry::RELATIVE_TOLERANCE
    );
}
