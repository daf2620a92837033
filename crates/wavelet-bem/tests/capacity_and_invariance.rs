//! The capacity trap and invariance of the torsion solution.
//!
//! Reference: WAVELET_BEM.md §2 (logarithmic capacity; the bare first-kind
//! system V q = f is singular when cap(Γ) = 1: unit circle, ellipse 1.5 × 0.5)
//! and §5 (translation, rotation: J to 1e-13; scaling by λ: J ↦ λ⁴J, τ ↦ λτ).
//!
//! Goal: show that the bare matrices are singular at capacity 1 while the
//! augmented ones are not, and that the solution transforms correctly across
//! capacity 1.
//!
//! ```text
//!   cap = 1:  ( V ) singular        ( V  e ) regular       e_i = ∫ φ_i
//!                                   ( eᵀ 0 )
//! ```
//!
//! Checked: smallest singular values (bare ≈ 0 relative to the largest,
//! augmented bounded away), J and τ under translation, rotation and scaling
//! for all three methods.

use tecon_wavelet_bem::daubechies::Daubechies;
use tecon_wavelet_bem::grading::Parametrisation;
use tecon_wavelet_bem::linalg::singular_values;
use tecon_wavelet_bem::*;

fn smallest_ratio(n: usize, a: &[f64]) -> f64 {
    let sv = singular_values(n, a).unwrap();
    sv[sv.len() - 1] / sv[0]
}

#[test]
fn bare_system_singular_at_capacity_one_augmented_not() {
    for (name, sec) in [
        ("unit circle", sections::circle(1.0).unwrap()),
        ("ellipse 1.5x0.5", sections::ellipse(1.5, 0.5).unwrap()),
    ] {
        let param = Parametrisation::new(&sec, 6.0);
        let n = 64;
        // Daubechies Galerkin
        let sys = galerkin::assemble(
            &sec,
            std::slice::from_ref(&param),
            n,
            Daubechies::new(4).unwrap(),
        )
        .unwrap();
        let bare = smallest_ratio(n, &sys.matrix);
        let mut aug = vec![0.0; (n + 1) * (n + 1)];
        for i in 0..n {
            aug[i * (n + 1)..i * (n + 1) + n].copy_from_slice(&sys.matrix[i * n..(i + 1) * n]);
            aug[i * (n + 1) + n] = sys.constraint[i];
            aug[n * (n + 1) + i] = sys.constraint[i];
        }
        let augr = smallest_ratio(n + 1, &aug);
        assert!(bare < 1e-13, "{name}: bare Galerkin σ_min/σ_max = {bare:e}");
        assert!(
            augr > 1e-4,
            "{name}: augmented Galerkin σ_min/σ_max = {augr:e}"
        );
        // Nyström
        let nodes = param.nodes(&sec, n);
        let ny = nystrom::assemble(&nodes, sec.centroid);
        let bare_ny: Vec<f64> = (0..n)
            .flat_map(|i| ny.matrix[i * (n + 1)..i * (n + 1) + n].to_vec())
            .collect();
        let b = smallest_ratio(n, &bare_ny);
        let g = smallest_ratio(n + 1, &ny.matrix);
        assert!(b < 1e-13, "{name}: bare Nyström {b:e}");
        assert!(g > 1e-4, "{name}: augmented Nyström {g:e}");
    }
    // away from capacity 1 the bare system is regular (so the test above can fail)
    let sec = sections::circle(0.5).unwrap();
    let param = Parametrisation::new(&sec, 6.0);
    let sys = galerkin::assemble(
        &sec,
        std::slice::from_ref(&param),
        64,
        Daubechies::new(4).unwrap(),
    )
    .unwrap();
    assert!(smallest_ratio(64, &sys.matrix) > 1e-4);
}

fn all_methods(sec: &Section, n: usize) -> Vec<(f64, f64)> {
    [Method::Daubechies, Method::Shannon, Method::Nystrom]
        .iter()
        .map(|&m| {
            let s = solve(
                sec,
                &Options {
                    n,
                    method: m,
                    ..Options::default()
                },
            )
            .unwrap();
            (s.torsional_rigidity, s.max_shear().value.unwrap())
        })
        .collect()
}

#[test]
fn translation_and_rotation_invariance() {
    let cases = [
        (sections::ellipse(2.0, 1.0).unwrap(), 256),
        (sections::triangle(1.0).unwrap(), 256),
        (sections::groove(1.0, 0.6).unwrap(), 256),
        (sections::limacon(1.0, 0.3).unwrap(), 256),
    ];
    for (sec, n) in cases {
        let base = all_methods(&sec, n);
        for moved in [
            sec.translated([3.7, -1.2]).unwrap(),
            sec.rotated(0.7316).unwrap(),
            sec.rotated(2.0).unwrap().translated([-5.0, 2.5]).unwrap(),
        ] {
            let m = all_methods(&moved, n);
            for (k, ((j0, t0), (j1, t1))) in base.iter().zip(&m).enumerate() {
                assert!(
                    (j1 - j0).abs() < 1e-13 * j0.abs(),
                    "{} method {k}: J {j0} → {j1}",
                    sec.name
                );
                assert!(
                    (t1 - t0).abs() < 1e-11 * t0,
                    "{} method {k}: τ {t0} → {t1}",
                    sec.name
                );
            }
        }
    }
}

#[test]
fn scaling_across_capacity_one() {
    // ellipse 3:1, capacity (a + b)/2 = 0.5 λ: λ = 2 crosses capacity 1
    let base = sections::ellipse(0.75, 0.25).unwrap(); // capacity 0.5
    let b0 = all_methods(&base, 256);
    for lambda in [0.5, 2.0, 2.0 + 1e-9, 4.0] {
        let sec = base.scaled(lambda).unwrap(); // λ = 2: capacity exactly 1
        let b = all_methods(&sec, 256);
        for (k, ((j0, t0), (j1, t1))) in b0.iter().zip(&b).enumerate() {
            assert!(
                (j1 / (j0 * lambda.powi(4)) - 1.0).abs() < 1e-12,
                "λ={lambda} method {k}: {j1} vs {}",
                j0 * lambda.powi(4)
            );
            assert!(
                (t1 / (t0 * lambda) - 1.0).abs() < 1e-12,
                "λ={lambda} method {k}"
            );
        }
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let sec = sections::rectangle(1.0, 2.0).unwrap();
    let run = |threads: usize, method: Method, linear: LinearSolver| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let s = solve(
                &sec,
                &Options {
                    n: 256,
                    method,
                    linear,
                    ..Options::default()
                },
            )
            .unwrap();
            let coef: Vec<(u64, u64)> = s
                .density
                .coef
                .iter()
                .map(|c| (c.re.to_bits(), c.im.to_bits()))
                .collect();
            // the warping outputs (pair sums in parallel blocks) too
            let w = s.warping();
            (
                s.torsional_rigidity.to_bits(),
                s.multiplier.to_bits(),
                coef,
                w.warping_constant.to_bits(),
                w.shear_centre.map(f64::to_bits),
            )
        })
    };
    for (m, lin) in [
        (Method::Daubechies, LinearSolver::Dense),
        (
            Method::Daubechies,
            LinearSolver::Compressed {
                eps: 1e-9,
                tol: 1e-12,
            },
        ),
        (Method::Shannon, LinearSolver::Dense),
        (Method::Nystrom, LinearSolver::Dense),
    ] {
        let a = run(1, m, lin);
        let b = run(2, m, lin);
        let c = run(3, m, lin);
        assert!(
            a == b && b == c,
            "{m} {lin:?}: results differ between 1, 2 and 3 threads"
        );
    }
}

/// The blocked LDLᵀ of a graded two-curve boundary (box, order 2 × 512 =
/// 1024, several faer blocks updated in parallel) gives bitwise the same J
/// and densities with 1, 2 and 3 threads.
#[test]
fn ldlt_of_a_hollow_section_does_not_depend_on_the_thread_count() {
    let sec = sections::hollow_rectangle(2.0, 1.0, 0.1, 0.1).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let s = solve(
                &sec,
                &Options {
                    n: 512,
                    ..Options::default()
                },
            )
            .unwrap();
            let mut bits = vec![s.torsional_rigidity.to_bits()];
            for d in std::iter::once(&s.density).chain(s.holes.iter().map(|h| &h.density)) {
                bits.extend(d.coef.iter().flat_map(|c| [c.re.to_bits(), c.im.to_bits()]));
            }
            bits
        })
    };
    let (a, b, c) = (run(1), run(2), run(3));
    assert!(
        a == b && b == c,
        "results differ between 1, 2 and 3 threads"
    );
}

/// At extreme scales J (∝ L⁴) and τ_max (∝ L) stay exact, but Γ (∝ L⁶) and
/// the products of second moments in the shear centre (∝ L⁸) leave double
/// precision. Those results are flagged at once (no climb to the largest
/// n), with a warning that names the cause, instead of NaN reported as
/// converged with a round-off estimate.
#[test]
fn quantities_out_of_double_range_are_flagged_not_converged() {
    for l in [1e40, 1e-60] {
        let sec = sections::rectangle(l, l).unwrap();
        let c = solve_to_tolerance(&sec, &Options::default(), 1e-8, 4096).unwrap();
        let j = c.solution.torsional_rigidity / l.powi(4);
        assert!(
            (j - 0.140_577_014_955_153_7).abs() < 1e-11,
            "L = {l:e}: J/L⁴ = {j}"
        );
        assert!(!c.warping.warping_constant.is_finite(), "L = {l:e}");
        assert!(!c.converged, "L = {l:e}");
        assert!(c.warping_error.is_infinite() && c.shear_centre_error.is_infinite());
        assert!(c.solution.options.n < 4096, "n = {}", c.solution.options.n);
        assert!(
            c.warnings.iter().any(|w| w.contains("not finite")),
            "{:?}",
            c.warnings
        );
    }
    // at L = 1e30 every quantity is finite and converged
    let sec = sections::rectangle(1e30, 1e30).unwrap();
    let c = solve_to_tolerance(&sec, &Options::default(), 1e-8, 4096).unwrap();
    assert!(c.converged && c.warping.warping_constant.is_finite());
}

/// A section whose J (about its polar moment, ∝ L⁴) leaves the normal
/// range of double precision is refused with an error that names the
/// polar moment and says what to do; before, a circle of radius 1e-100
/// gave J = 0 (flagged only for its shear centre) and one of 1e77 failed
/// with "the solution is not finite (ill-posed geometry …)".
#[test]
fn sizes_whose_rigidity_leaves_double_precision_are_refused() {
    for r in [1e-100, 1e-78, 1e77, 1e100] {
        let sec = sections::circle(r).unwrap();
        match solve_to_tolerance(&sec, &Options::default(), 1e-8, 4096) {
            Err(e @ tecon_wavelet_bem::SolveError::Scale { .. }) => {
                let msg = e.to_string();
                assert!(
                    msg.contains("polar moment") && msg.contains("units"),
                    "{msg}"
                );
            }
            other => panic!("r = {r:e}: expected a scale error, got {other:?}"),
        }
    }
    // the edges of the range still solve: J = π r⁴/2 to round-off
    for r in [1e-74, 1e74] {
        let sec = sections::circle(r).unwrap();
        let c = solve_to_tolerance(&sec, &Options::default(), 1e-8, 4096).unwrap();
        let j = c.solution.torsional_rigidity / r.powi(4);
        assert!(
            (j / std::f64::consts::FRAC_PI_2 - 1.0).abs() < 1e-12,
            "r = {r:e}: J/r⁴ = {j}"
        );
    }
}

/// The error control needs two resolutions, n/2 and n, each at least the
/// method's smallest n: a smaller largest n is an error that names
/// `--max-n` and its least value (it said "n = 32" for `--max-n 3`).
#[test]
fn a_largest_n_below_two_resolutions_is_refused_by_name() {
    let sec = sections::circle(1.0).unwrap();
    for max_n in [3, 64] {
        let e = solve_to_tolerance(&sec, &Options::default(), 1e-8, max_n).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("--max-n") && msg.contains("at least 128"),
            "{msg}"
        );
    }
    assert!(solve_to_tolerance(&sec, &Options::default(), 1e-8, 128).is_ok());
}

/// A largest n above what a solve accepts (n ≤ 2^19, n/k ≤ 8192) is
/// lowered to the largest rung a solve takes, with a warning when the
/// result is not converged: the ellipse 1 × 0.01 at 1e-14 with
/// `--max-n 2000000` stopped with an error at n = 32 768 (n/k = 16 384).
/// The circle at an unreachable 1e-17 climbs to n = 2^19 (folded to 16).
#[test]
fn a_largest_n_above_what_a_solve_takes_is_lowered_with_a_warning() {
    let sec = sections::circle(1.0).unwrap();
    let c = solve_to_tolerance(&sec, &Options::default(), 1e-17, 2_000_000).unwrap();
    assert!(!c.converged);
    assert_eq!(c.solution.options.n, 1 << 19);
    assert!(
        c.warnings
            .iter()
            .any(|w| w.contains("--max-n 2000000 lowered to n = 524288")),
        "{:?}",
        c.warnings
    );
    assert!((c.solution.torsional_rigidity / std::f64::consts::FRAC_PI_2 - 1.0).abs() < 1e-12);
}

/// A tube whose wall is below the rounding of its radii encloses no area
/// to round-off: the error says so (it was reported as a polar moment
/// out of range, I_p = −4.4e-16).
#[test]
fn a_wall_below_round_off_is_said_to_enclose_no_area() {
    let sec = sections::parse_spec("tube:ro=1,ri=0.9999999999999999").unwrap();
    let e = solve_to_tolerance(&sec, &Options::default(), 1e-8, 4096).unwrap_err();
    assert!(
        matches!(e, tecon_wavelet_bem::SolveError::NoArea { .. }),
        "{e}"
    );
    assert!(e.to_string().contains("no area"), "{e}");
}
