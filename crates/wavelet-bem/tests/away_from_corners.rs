//! The shear stress of a section with re-entrant corners, away from them:
//! the largest boundary value at least R from every singular point.
//!
//! τ is infinite at a re-entrant corner; at a distance R from it the
//! boundary value is finite and converges with n like any point value.
//! Checked here: the reported point keeps its distance, the value converges
//! (also when it lies on the circle of radius R, found by bisection), its
//! estimate bounds its error against a finer resolution, a second method
//! (Nyström) gives the same value, and giving R makes the control follow
//! it.

use tecon_wavelet_bem::sections::{self, parse_spec};
use tecon_wavelet_bem::*;

const L_SPEC: &str = "polygon:0,0;2,0;2,1;1,1;1,2;0,2";

fn away(sec: &geometry::Section, method: Method, n: usize, r: f64) -> solve::AwayShear {
    let opts = Options {
        n,
        method,
        corner_distance: Some(r),
        ..Options::default()
    };
    let sol = solve(sec, &opts).unwrap();
    let ms = sol.max_shear();
    assert!(ms.singular && ms.value.is_none());
    ms.away.expect("a boundary part away from the corners")
}

fn distance_to_corners(sec: &geometry::Section, x: geometry::V2) -> f64 {
    sec.singular_points()
        .iter()
        .map(|p| (x[0] - p[0]).hypot(x[1] - p[1]))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn the_value_away_from_a_re_entrant_corner_converges_and_keeps_its_distance() {
    let sec = parse_spec(L_SPEC).unwrap();
    assert_eq!(sec.singular_points(), vec![[1.0, 1.0]]);
    // R = 0.05: the largest value lies on the circle around the corner
    // (τ falls with the distance from it); default R = A/P = 3/8: on the
    // outer edge
    for r in [0.05, sec.default_corner_distance()] {
        let v: Vec<solve::AwayShear> = [256, 512, 1024, 2048]
            .iter()
            .map(|&n| away(&sec, Method::Daubechies, n, r))
            .collect();
        for a in &v {
            assert!(
                distance_to_corners(&sec, a.at) >= r * (1.0 - 1e-12),
                "R = {r}: {a:?}"
            );
            assert_eq!(a.distance, r);
        }
        let d: Vec<f64> = v
            .windows(2)
            .map(|w| (w[1].value - w[0].value).abs())
            .collect();
        // each doubling shrinks the change by well over 8 (measured: by
        // 60–120 on the circle); a value that followed the sample
        // positions would shrink like 1/n
        assert!(d[1] < d[0] / 8.0 && d[2] < d[1] / 8.0, "R = {r}: {d:?}");
        assert!(d[2] < 1e-8 * v[3].value, "R = {r}: {d:?}");
    }
    // on the circle: the point is R from the corner to round-off
    let a = away(&sec, Method::Daubechies, 1024, 0.05);
    assert!(
        (distance_to_corners(&sec, a.at) - 0.05).abs() < 1e-12,
        "{a:?}"
    );
    // more than τ at the default distance (τ grows toward the corner)
    assert!(
        a.value
            > away(
                &sec,
                Method::Daubechies,
                1024,
                sec.default_corner_distance()
            )
            .value
    );
}

#[test]
fn nystrom_gives_the_same_value_away_from_the_corners() {
    // a second method, its own discretisation of the same integral equation
    let sec = parse_spec(L_SPEC).unwrap();
    for r in [0.05, 0.375] {
        let d = away(&sec, Method::Daubechies, 2048, r).value;
        let ny = away(&sec, Method::Nystrom, 1024, r).value;
        assert!((d - ny).abs() < 1e-8 * d, "R = {r}: db4 {d} Nyström {ny}");
    }
    // and on the inner corners of a box (a hole's corners are re-entrant
    // for the wall around them)
    let sec = sections::hollow_rectangle(1.0, 1.0, 0.1, 0.1).unwrap();
    assert_eq!(sec.singular_points().len(), 4);
    let r = sec.default_corner_distance();
    let d = away(&sec, Method::Daubechies, 1024, r);
    let ny = away(&sec, Method::Nystrom, 1024, r);
    assert!((d.value - ny.value).abs() < 1e-7 * d.value, "{d:?} {ny:?}");
    // the wall's stress, not a corner's: between Bredt's mean over the
    // wall, T/(2 A_m t) = J/(2 A_m t) with A_m = 0.9², and twice it
    let ctl = solve_to_tolerance(&sec, &Options::default(), 1e-8, 4096).unwrap();
    let bredt = ctl.solution.torsional_rigidity / (2.0 * 0.81 * 0.1);
    assert!(
        d.value > bredt && d.value < 2.0 * bredt,
        "{} vs {bredt}",
        d.value
    );
}

#[test]
fn its_estimate_bounds_its_error_and_giving_r_makes_the_control_follow_it() {
    let sec = parse_spec(L_SPEC).unwrap();
    let r = 0.05;
    let reference = away(&sec, Method::Daubechies, 4096, r).value;
    // default: reported with its estimate, not followed
    let ctl = solve_to_tolerance(&sec, &Options::default(), 1e-10, 4096).unwrap();
    let a = ctl.max_shear.away.unwrap();
    assert_eq!(a.distance, sec.default_corner_distance());
    let e = ctl.tau_error.unwrap();
    let reference_default = away(&sec, Method::Daubechies, 4096, a.distance).value;
    assert!(
        (a.value - reference_default).abs() / reference_default <= e,
        "error {:e} > estimate {e:e}",
        (a.value - reference_default).abs() / reference_default
    );
    // given R: followed until it meets the tolerance
    for tol in [1e-6, 1e-8, 1e-10] {
        let opts = Options {
            corner_distance: Some(r),
            ..Options::default()
        };
        let ctl = solve_to_tolerance(&sec, &opts, tol, 4096).unwrap();
        let a = ctl.max_shear.away.unwrap();
        let e = ctl.tau_error.unwrap();
        assert!(ctl.converged && e <= tol, "tol {tol:e}: estimate {e:e}");
        let err = (a.value - reference).abs() / reference;
        assert!(
            err <= e.max(1e-13),
            "tol {tol:e}: error {err:e} > estimate {e:e}"
        );
        // the levels carry the followed value
        let last = ctl.levels.last().unwrap();
        assert_eq!(last.max_shear_stress, Some(a.value));
    }
}

#[test]
fn a_distance_inside_the_unresolved_corner_cluster_is_raised_and_says_so() {
    // next to a singular point the graded cluster's boundary values are
    // never evaluated (0/0), whatever n: a smaller R would report the
    // cluster's edge as if it were R away
    let sec = parse_spec(L_SPEC).unwrap();
    for n in [512, 1024] {
        let a = away(&sec, Method::Daubechies, n, 1e-6);
        assert_eq!(a.requested, 1e-6);
        assert!(a.distance > 1e-3 && a.distance < 1e-2, "{a:?}");
        assert!(distance_to_corners(&sec, a.at) >= a.distance, "{a:?}");
        // a distance beyond the cluster is kept as asked
        let b = away(&sec, Method::Daubechies, n, 0.05);
        assert_eq!((b.distance, b.requested), (0.05, 0.05));
    }
}
