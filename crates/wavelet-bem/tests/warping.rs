//! Warping function ω, shear centre and warping constant Γ.
//!
//! Reference: ω of the ellipse x²/a² + y²/b² ≤ 1 is −(a² − b²)/(a² + b²) xy, so
//! Γ = k² π a³ b³ / 24; ω of the rectangle |x| ≤ a, |y| ≤ b is
//! xy + Σ_n c_n sin(k_n x) sinh(k_n y)/cosh(k_n b), k_n = (2n + 1)π/(2a),
//! c_n = −32 a² (−1)ⁿ/((2n + 1)³ π³) (Timoshenko & Goodier §109), whose Γ is
//! integrated term by term below. Goal: ω on Γ, the shear centre and Γ from
//! the torsion solution, Galerkin and Nyström alike, solid and hollow.
//!
//! ```text
//!   ellipse          rectangle 2a × 2b        box (hollow)       channel
//!    .-""-.          +-----------+          +---------+        +------
//!   (   +  )         |     +     |          | +-----+ |        | +----
//!    '-..-'          +-----------+          | +-----+ |        | |  x_S left of the web
//!                                           +---------+        | +----
//!                                                              +------
//! ```
use std::f64::consts::PI;
use tecon_wavelet_bem::{Method, Options, Section, sections, solve, solve_to_tolerance};

fn opts(method: Method, n: usize) -> Options {
    Options {
        n,
        method,
        ..Options::default()
    }
}

/// ω of the rectangle |x| ≤ a, |y| ≤ b (series; for |y| well inside, fast).
fn rectangle_omega(a: f64, b: f64, x: f64, y: f64) -> f64 {
    let mut s = x * y;
    for n in 0..2000 {
        let m = (2 * n + 1) as f64;
        let k = m * PI / (2.0 * a);
        let c = -32.0 * a * a * if n % 2 == 0 { 1.0 } else { -1.0 } / (m.powi(3) * PI.powi(3));
        // sinh(ky)/cosh(kb) without overflow
        let r = ((k * (y.abs() - b)).exp() - (-k * (y.abs() + b)).exp())
            / (1.0 + (-2.0 * k * b).exp())
            * y.signum();
        s += c * (k * x).sin() * r;
    }
    s
}

/// Γ of the rectangle 2a × 2b about its centre (the library's series).
fn rectangle_gamma(a: f64, b: f64) -> f64 {
    tecon_wavelet_bem::analytical::Rectangle {
        w: 2.0 * a,
        h: 2.0 * b,
    }
    .warping_constant()
}

#[test]
fn ellipse_warping_is_exact_in_galerkin_and_nystrom() {
    let (a, b) = (2.0, 1.0);
    let k = -(a * a - b * b) / (a * a + b * b);
    let exact = k * k * PI * a.powi(3) * b.powi(3) / 24.0;
    for (method, n) in [(Method::Daubechies, 128), (Method::Nystrom, 64)] {
        let sec = sections::ellipse(a, b).unwrap();
        let sol = solve(&sec, &opts(method, n)).unwrap();
        let w = sol.warping();
        let err = sol
            .warping_samples(&w, 97)
            .iter()
            .map(|p| (p.omega - k * p.x[0] * p.x[1]).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-12, "{method}: max |ω − ω_exact| = {err:e}");
        let rel = (w.warping_constant - exact).abs() / exact;
        assert!(rel < 1e-12, "{method}: Γ relative error {rel:e}");
        assert!(w.shear_centre[0].hypot(w.shear_centre[1]) < 1e-13);
        // moved and turned: the shear centre follows the centroid, Γ is invariant
        let moved = sec.rotated(0.7).unwrap().translated([3.0, -1.5]).unwrap();
        let wm = solve(&moved, &opts(method, n)).unwrap().warping();
        let d = [wm.shear_centre[0] - 3.0, wm.shear_centre[1] + 1.5];
        assert!(
            d[0].hypot(d[1]) < 1e-12,
            "{method}: shear centre {d:?} off the centroid"
        );
        assert!((wm.warping_constant - exact).abs() < 1e-12 * exact);
    }
}

#[test]
fn rectangle_against_the_series() {
    let (a, b) = (1.0, 0.5);
    let exact = rectangle_gamma(a, b);
    for method in [Method::Daubechies, Method::Nystrom] {
        let sec = sections::rectangle(2.0 * a, 2.0 * b).unwrap();
        let sol = solve(&sec, &opts(method, 512)).unwrap();
        let w = sol.warping();
        let rel = (w.warping_constant - exact).abs() / exact;
        assert!(
            rel < 1e-11,
            "{method}: Γ = {} vs {exact}: {rel:e}",
            w.warping_constant
        );
        assert!(w.shear_centre[0].hypot(w.shear_centre[1]) < 1e-13);
        // ω on the short sides x = ±a, |y| ≤ 0.3 (series converges fast there)
        let mut worst = 0.0f64;
        for s in sol.warping_samples(&w, 256) {
            if (s.x[0].abs() - a).abs() < 1e-12 && s.x[1].abs() <= 0.3 {
                let e = (s.omega - rectangle_omega(a, b, s.x[0], s.x[1])).abs();
                worst = worst.max(e);
            }
        }
        assert!(worst > 0.0 && worst < 1e-11, "{method}: ω error {worst:e}");
    }
}

/// Γ error of the rectangle against n: fitted slope of log error vs log n.
#[test]
fn rectangle_observed_order() {
    let (a, b) = (1.0, 0.5);
    let exact = rectangle_gamma(a, b);
    let sec = sections::rectangle(2.0 * a, 2.0 * b).unwrap();
    let ns = [64usize, 128, 256];
    let errs: Vec<f64> = ns
        .iter()
        .map(|&n| {
            let o = Options {
                wavelet_order: 2,
                ..opts(Method::Daubechies, n)
            };
            let w = solve(&sec, &o).unwrap().warping();
            (w.warping_constant - exact).abs() / exact
        })
        .collect();
    let xs: Vec<f64> = ns.iter().map(|&n| (n as f64).ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / 3.0, ys.iter().sum::<f64>() / 3.0);
    let slope = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    println!("db2 Γ errors {errs:?}, slope {slope:.2}");
    assert!(
        -slope > 4.5,
        "observed order {:.2} (errors {errs:?})",
        -slope
    );
}

#[test]
fn hollow_sections_galerkin_and_nystrom_agree() {
    // box symmetric in x and y: the shear centre is at its centre
    let bx = sections::parse_spec("box:w=2,h=1,t=0.1").unwrap();
    let g = solve(&bx, &opts(Method::Daubechies, 512))
        .unwrap()
        .warping();
    let ny = solve(&bx, &opts(Method::Nystrom, 512)).unwrap().warping();
    assert!(g.shear_centre[0].hypot(g.shear_centre[1]) < 1e-12);
    let rel = (g.warping_constant - ny.warping_constant).abs() / g.warping_constant;
    assert!(
        rel < 1e-10,
        "box Γ: {} vs {}",
        g.warping_constant,
        ny.warping_constant
    );
    // thick concentric tube: ω ≡ 0, Γ = 0 (to the scale I_p²/A)
    let tube = sections::tube(1.0, 0.6).unwrap();
    let w = solve(&tube, &opts(Method::Daubechies, 128))
        .unwrap()
        .warping();
    let scale = tube.polar_moment().powi(2) / tube.area;
    assert!(
        w.warping_constant.abs() < 1e-13 * scale,
        "tube Γ {}",
        w.warping_constant
    );
    // eccentric hole in a disc: symmetric about y = 0 only
    let outer = sections::circle(1.0).unwrap();
    let hole = sections::circle(0.3)
        .unwrap()
        .translated([0.35, 0.0])
        .unwrap();
    let sec = tecon_wavelet_bem::Section::with_holes(outer, vec![hole]).unwrap();
    let g = solve(&sec, &opts(Method::Daubechies, 256))
        .unwrap()
        .warping();
    let ny = solve(&sec, &opts(Method::Nystrom, 256)).unwrap().warping();
    assert!(g.shear_centre[1].abs() < 1e-12, "off the axis of symmetry");
    assert!((g.shear_centre[0] - ny.shear_centre[0]).abs() < 1e-11);
    assert!((g.warping_constant - ny.warping_constant).abs() < 1e-10 * g.warping_constant);
    assert!(g.warping_constant > 0.0);
}

/// Γ = ∫ ω_n² dA of the circle and the concentric tube, where ω vanishes, is
/// round-off: the controlled result reports max(Γ, 0) (the circle's came out
/// as −4.3e-33), at every level too, while the Γ estimate, measured against
/// the floor 10⁻⁶ I_p²/A, still uses the computed values and converges.
#[test]
fn a_vanishing_warping_constant_is_never_reported_negative() {
    use tecon_wavelet_bem::warping::nonnegative;
    for sec in [
        sections::circle(1.0).unwrap(),
        sections::tube(1.0, 0.6).unwrap(),
    ] {
        // the CLI's starting options
        let o = Options {
            n: 8,
            ..Options::default()
        };
        let c = solve_to_tolerance(&sec, &o, 1e-8, 4096).unwrap();
        let raw = c.solution.warping();
        let scale = sec.polar_moment().powi(2) / sec.area;
        assert!(raw.warping_constant.abs() < 1e-13 * scale, "{}", sec.name);
        assert_eq!(c.warping.warping_constant, raw.warping_constant.max(0.0));
        assert_eq!(
            c.warping.centroidal_constant,
            raw.centroidal_constant.max(0.0)
        );
        for l in &c.levels {
            assert!(l.warping_constant.is_none_or(|g| g >= 0.0), "{l:?}");
        }
        assert!(c.converged, "{}: {:?}", sec.name, c.warnings);
        assert!(
            c.warping_error.is_finite() && c.warping_error <= 1e-8,
            "{}: Γ estimate {}",
            sec.name,
            c.warping_error
        );
        // the mechanism, on a value made negative
        let mut neg = raw.clone();
        neg.warping_constant = -4.3e-33;
        neg.centroidal_constant = -1e-40;
        let r = neg.reported();
        assert_eq!((r.warping_constant, r.centroidal_constant), (0.0, 0.0));
    }
    // a value that is not finite is kept, to be flagged
    assert_eq!(nonnegative(-4.3e-33), 0.0);
    assert_eq!(nonnegative(2.0e-3), 2.0e-3);
    assert!(nonnegative(f64::NAN).is_nan());
    assert_eq!(nonnegative(f64::NEG_INFINITY), f64::NEG_INFINITY);
}

#[test]
fn channel_shear_centre_lies_on_the_axis_and_outside_the_web() {
    // web x ∈ [0, 0.1], flanges 0.1 thick to x = 1; symmetric about y = 0.5
    let sec = sections::parse_spec("polygon:0,0;1,0;1,0.1;0.1,0.1;0.1,0.9;1,0.9;1,1;0,1").unwrap();
    let c = solve_to_tolerance(&sec, &opts(Method::Daubechies, 8), 1e-8, 2048).unwrap();
    assert!(c.converged, "{:?}", c.warnings);
    let s = c.warping.shear_centre;
    assert!((s[1] - 0.5).abs() < 1e-8, "y_S = {}", s[1]);
    assert!(s[0] < 0.0, "x_S = {} should lie outside the web", s[0]);
    // Nyström at the same n agrees within the reported estimate
    let ny = solve(&sec, &opts(Method::Nystrom, c.solution.options.n))
        .unwrap()
        .warping();
    let rg = (sec.polar_moment() / sec.area).sqrt();
    assert!((ny.shear_centre[0] - s[0]).abs() / rg < 10.0 * c.shear_centre_error.max(1e-12));
    assert!(
        (ny.warping_constant - c.warping.warping_constant).abs() / c.warping.warping_constant
            < 10.0 * c.warping_error.max(1e-12)
    );
}

/// The oversampled Shannon method is a discretisation of its own (it does not
/// reproduce the Nyström numbers at the same n) and converges to the same J
/// and Γ on solid and hollow sections.
#[test]
fn shannon_is_an_independent_cross_check() {
    for spec in ["box:w=2,h=1,t=0.1", "rectangle:w=2,h=1"] {
        let sec = sections::parse_spec(spec).unwrap();
        let g = solve(&sec, &opts(Method::Daubechies, 512)).unwrap();
        let s = solve(&sec, &opts(Method::Shannon, 512)).unwrap();
        let (gw, sw) = (g.warping(), s.warping());
        let dj = (s.torsional_rigidity / g.torsional_rigidity - 1.0).abs();
        let dg = (sw.warping_constant / gw.warping_constant - 1.0).abs();
        assert!(dj < 1e-10 && dg < 1e-10, "{spec}: J {dj:e}, Γ {dg:e}");
        // at a coarse n the two collocation-free and collocation results differ
        let s64 = solve(&sec, &opts(Method::Shannon, 64)).unwrap();
        let n64 = solve(&sec, &opts(Method::Nystrom, 64)).unwrap();
        let d = (s64.torsional_rigidity / n64.torsional_rigidity - 1.0).abs();
        assert!(
            d > 1e-9,
            "{spec}: Shannon and Nyström agree to {d:e} at n = 64"
        );
    }
    // eccentric hole: Shannon against Galerkin on J, shear centre and Γ
    let outer = sections::circle(1.0).unwrap();
    let hole = sections::circle(0.3)
        .unwrap()
        .translated([0.35, 0.0])
        .unwrap();
    let sec = tecon_wavelet_bem::Section::with_holes(outer, vec![hole]).unwrap();
    let g = solve(&sec, &opts(Method::Daubechies, 256)).unwrap();
    let s = solve(&sec, &opts(Method::Shannon, 128)).unwrap();
    assert!((s.torsional_rigidity / g.torsional_rigidity - 1.0).abs() < 1e-12);
    let (gw, sw) = (g.warping(), s.warping());
    assert!((gw.shear_centre[0] - sw.shear_centre[0]).abs() < 1e-12);
    assert!((gw.warping_constant / sw.warping_constant - 1.0).abs() < 1e-11);
}

/// J, Γ and the Trefftz shear centre of a box, a monosymmetric I and a
/// channel against our own sectionproperties 3.10.2 runs
/// (tests/data/sectionproperties.toml: versions, meshes, procedure).
/// sectionproperties converges slowly at the re-entrant corners, so its error
/// is judged by its own last mesh-to-mesh difference d: our converged value
/// must lie within 3 d (+ 1e-9 of the section's scale) of its finest result.
#[test]
fn against_sectionproperties() {
    let text = include_str!("data/sectionproperties.toml");
    let data: toml::Table = text.parse().unwrap();
    let cases = data["case"].as_array().unwrap();
    assert_eq!(cases.len(), 3);
    for c in cases {
        let spec = c["spec"].as_str().unwrap();
        let sec = sections::parse_spec(spec).unwrap();
        let ctl = solve_to_tolerance(&sec, &opts(Method::Daubechies, 8), 1e-8, 2048).unwrap();
        assert!(ctl.converged, "{spec}: {:?}", ctl.warnings);
        let rg = (sec.polar_moment() / sec.area).sqrt();
        let ours = [
            (
                "j",
                ctl.solution.torsional_rigidity,
                ctl.solution.torsional_rigidity,
            ),
            (
                "gamma",
                ctl.warping.warping_constant,
                ctl.warping.warping_constant,
            ),
            ("sc_x", ctl.warping.shear_centre[0], rg),
            ("sc_y", ctl.warping.shear_centre[1], rg),
        ];
        for (key, v, scale) in ours {
            let sp: Vec<f64> = c[key]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_float().unwrap())
                .collect();
            let (fine, prev) = (sp[sp.len() - 1], sp[sp.len() - 2]);
            let d = (fine - prev).abs();
            let dev = (v - fine).abs();
            println!(
                "{spec} {key}: ours {v:.12e} (n = {}), sectionproperties {fine:.12e}, \
                 |ours − sp| = {dev:.2e}, sp last difference {d:.2e}",
                ctl.solution.options.n
            );
            assert!(
                dev <= 3.0 * d + 1e-9 * scale.abs(),
                "{spec} {key}: ours {v} vs sectionproperties {fine} (its last difference {d:e})"
            );
        }
    }
}

/// The reported error of Γ (three-rung estimate, floor 2^−8 for db4) bounds
/// its true error on rectangles (the series) and the thin box (against its
/// own n = 2048 solution, whose Γ differs from n = 1024 by 2e-15) at
/// tolerances 1e-6, 1e-8 and 1e-10.
#[test]
fn reported_warping_errors_bound_the_true_errors() {
    let box_section = sections::hollow_rectangle(2.0, 1.0, 0.1, 0.1).unwrap();
    let box_gamma = solve(&box_section, &opts(Method::Daubechies, 2048))
        .unwrap()
        .warping()
        .warping_constant;
    let mut cases: Vec<(Section, f64)> = [(1.0, 0.5), (0.5, 0.5), (0.5, 0.05)]
        .iter()
        .map(|&(a, b)| {
            (
                sections::rectangle(2.0 * a, 2.0 * b).unwrap(),
                rectangle_gamma(a, b),
            )
        })
        .collect();
    cases.push((box_section, box_gamma));
    for (sec, exact) in &cases {
        let ip = sec.polar_moment();
        let scale = exact.abs().max(1e-6 * ip * ip / sec.area);
        for tol in [1e-6, 1e-8, 1e-10] {
            let c = solve_to_tolerance(sec, &Options::default(), tol, 2048).unwrap();
            let e = (c.warping.warping_constant - exact).abs() / scale;
            eprintln!(
                "{} tol {tol:.0e}: n {} Γ err {e:.1e} est {:.1e} converged {}",
                sec.name, c.solution.options.n, c.warping_error, c.converged
            );
            assert!(
                e <= c.warping_error,
                "{} tol {tol:e}: Γ error {e:e} > estimate {:e}",
                sec.name,
                c.warping_error
            );
        }
    }
}
