//! Verification of Saint-Venant torsion against closed forms.
//!
//! Reference: WAVELET_BEM.md §4 (Timoshenko & Goodier, *Theory of
//! Elasticity*, ch. 10: circle, ellipse, equilateral triangle, rectangle
//! series; semicircle J = (π/2 − 4/π)R⁴); the limaçon from the conformal map z = A(ζ + cζ²) (v = A²(1 + c² +
//! 2c Re ζ)/2 in the ζ-disc); the grooved shaft u = a x − r²/2 − a b² x/r² + b²/2.
//!
//! Goal: J, τ_max and the boundary distribution |q| to the tolerances of §5
//! (smooth 1e-12 with a few hundred unknowns, polygons 1e-8, cusp 1e-6) for
//! every method, including the capacity-1 sections.
//!
//! ```text
//!        ____                 /\              ________
//!      /      \              /  \            |        |       Γ counter-clockwise,
//!     |   Ω    |            / Ω  \           |   Ω    |       u = 0 on Γ,
//!      \ ____ /            /______\          |________|       ∇²u = −2 in Ω (Gθ = 1)
//!   circle, ellipse     equilateral triangle   square, rectangle
//! ```
//!
//! Checked: relative errors of J and τ_max, |q| at every boundary sample
//! against the exact distribution, u and stresses at interior points, the
//! multiplier c ≈ 0, singular corners/cusps reported as singular.

use tecon_wavelet_bem::analytical::*;
use tecon_wavelet_bem::*;

const METHODS: [Method; 3] = [Method::Daubechies, Method::Shannon, Method::Nystrom];

fn run(sec: &Section, method: Method, n: usize) -> TorsionSolution {
    let o = Options {
        n,
        method,
        ..Options::default()
    };
    match solve(sec, &o) {
        Ok(s) => s,
        Err(e) => panic!("{method} n={n} on {}: {e}", sec.name),
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn circles_including_capacity_one() {
    for r in [1.0, 0.5, 2.0] {
        let ex = Circle { r };
        let sec = sections::circle(r).unwrap();
        for m in METHODS {
            let s = run(&sec, m, 128);
            assert!(
                rel(s.torsional_rigidity, ex.rigidity()) < 1e-13,
                "{m} R={r}: J {}",
                s.torsional_rigidity
            );
            let t = s.max_shear();
            assert!(!t.singular);
            assert!(
                rel(t.value.unwrap(), ex.max_shear()) < 1e-12,
                "{m} R={r}: τ {:?}",
                t.value
            );
            assert!(s.multiplier.abs() < 1e-13);
            for b in s.boundary_samples(64) {
                assert!((b.q.abs() - r).abs() < 1e-12 * r);
            }
        }
    }
}

#[test]
fn ellipses_rigidity_max_shear_and_distribution() {
    // (1.5, 0.5) has logarithmic capacity (a + b)/2 = 1: the bare system is singular there
    for (a, b) in [(2.0, 1.0), (1.5, 0.5), (1.0, 3.0), (0.3, 0.2)] {
        let ex = Ellipse { a, b };
        let sec = sections::ellipse(a, b).unwrap();
        for m in METHODS {
            let s = run(&sec, m, 256);
            let ej = rel(s.torsional_rigidity, ex.rigidity());
            assert!(ej < 1e-12, "{m} ellipse {a},{b}: J error {ej:e}");
            let t = s.max_shear();
            let et = rel(t.value.unwrap(), ex.max_shear());
            assert!(et < 1e-12, "{m} ellipse {a},{b}: τ error {et:e}");
            // at the ends of the minor axis
            let at = t.at.unwrap();
            if a > b {
                assert!(
                    at[0].abs() < 1e-6 * a && (at[1].abs() - b).abs() < 1e-9,
                    "{at:?}"
                );
            } else {
                assert!(
                    at[1].abs() < 1e-6 * b && (at[0].abs() - a).abs() < 1e-9,
                    "{at:?}"
                );
            }
            let mut worst: f64 = 0.0;
            for smp in s.boundary_samples(200) {
                let tt = (smp.x[1] / b).atan2(smp.x[0] / a);
                worst = worst.max((smp.q.abs() - ex.shear_at(tt)).abs() / ex.max_shear());
                assert!(smp.q <= 0.0);
            }
            assert!(worst < 1e-11, "{m} ellipse {a},{b}: |q| error {worst:e}");
        }
    }
}

#[test]
fn ellipse_interior_stress_function_and_stresses() {
    let (a, b) = (2.0, 1.0);
    let k = a * a * b * b / (a * a + b * b);
    let sec = sections::ellipse(a, b).unwrap();
    let s = run(&sec, Method::Daubechies, 256);
    let pts = [[0.0, 0.0], [0.7, 0.3], [-1.2, -0.5], [1.5, 0.2]];
    for v in s.interior(&pts) {
        let (x, y) = (v.x[0], v.x[1]);
        let u = k * (1.0 - x * x / (a * a) - y * y / (b * b));
        let txz = -2.0 * k * y / (b * b);
        let tyz = 2.0 * k * x / (a * a);
        assert!((v.u - u).abs() < 1e-10, "u at {:?}: {} vs {u}", v.x, v.u);
        assert!(
            (v.tau_xz - txz).abs() < 1e-9 && (v.tau_yz - tyz).abs() < 1e-9,
            "{v:?}"
        );
    }
}

#[test]
fn equilateral_triangle() {
    let a = 1.0;
    let ex = EquilateralTriangle { a };
    let sec = sections::triangle(a).unwrap();
    let verts: Vec<[f64; 2]> = sec.junctions.iter().map(|j| j.point).collect();
    for m in METHODS {
        let s = run(&sec, m, 512);
        let ej = rel(s.torsional_rigidity, ex.rigidity());
        assert!(ej < 1e-8, "{m}: J error {ej:e}");
        let t = s.max_shear();
        assert!(!t.singular);
        let et = rel(t.value.unwrap(), ex.max_shear());
        assert!(et < 1e-8, "{m}: τ error {et:e}");
        // the maximum sits at a mid-side
        let at = t.at.unwrap();
        let mid_ok = (0..3).any(|k| {
            let (p, q) = (verts[k], verts[(k + 1) % 3]);
            ((at[0] - 0.5 * (p[0] + q[0])).hypot(at[1] - 0.5 * (p[1] + q[1]))) < 1e-4
        });
        assert!(mid_ok, "{m}: τ_max at {at:?}");
        // |q| = √3 s (a − s)/a along every side
        let mut worst: f64 = 0.0;
        for smp in s.boundary_samples(600) {
            let sdist = verts
                .iter()
                .map(|v| (smp.x[0] - v[0]).hypot(smp.x[1] - v[1]))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max((smp.q.abs() - ex.shear_at(sdist)).abs());
        }
        assert!(worst < 1e-7, "{m}: |q| error {worst:e}");
    }
}

#[test]
fn square_and_rectangle() {
    let sq = sections::rectangle(1.0, 1.0).unwrap();
    let ex = Rectangle { w: 1.0, h: 1.0 };
    // the series reproduces the tabulated square values
    assert!((ex.rigidity() - 0.140577014955154).abs() < 1e-15);
    assert!((ex.max_shear() - 0.675314483313568).abs() < 1e-15);
    for m in METHODS {
        let s = run(&sq, m, 512);
        assert!(
            rel(s.torsional_rigidity, ex.rigidity()) < 1e-8,
            "{m}: J {}",
            s.torsional_rigidity
        );
        let t = s.max_shear();
        assert!(
            rel(t.value.unwrap(), ex.max_shear()) < 1e-8,
            "{m}: τ {:?}",
            t.value
        );
        // convex corners: τ → 0 there
        let near_corner = s
            .boundary_samples(2048)
            .iter()
            .map(|b| {
                (
                    b.x[0].abs().max(b.x[1].abs()),
                    b.x[0].abs().min(b.x[1].abs()),
                    b.q,
                )
            })
            .filter(|(_, m, _)| *m > 0.499)
            .map(|(_, _, q)| q.abs())
            .fold(0.0f64, f64::max);
        assert!(near_corner < 1e-2, "{m}: |q| near a corner {near_corner}");
    }
    for (w, h) in [(1.0, 2.0), (3.0, 1.0)] {
        let ex = Rectangle { w, h };
        let sec = sections::rectangle(w, h).unwrap();
        let s = run(&sec, Method::Daubechies, 512);
        assert!(
            rel(s.torsional_rigidity, ex.rigidity()) < 1e-8,
            "{w}x{h}: J {}",
            s.torsional_rigidity
        );
        assert!(
            rel(s.max_shear().value.unwrap(), ex.max_shear()) < 1e-8,
            "{w}x{h}"
        );
    }
}

#[test]
fn limacon_and_cardioid() {
    for c in [0.2, 0.35] {
        let ex = Limacon { a: 1.3, c };
        let sec = sections::limacon(1.3, c).unwrap();
        for m in METHODS {
            let s = run(&sec, m, 256);
            assert!(
                rel(s.torsional_rigidity, ex.rigidity()) < 1e-12,
                "{m} c={c}: J {}",
                s.torsional_rigidity
            );
            let t = s.max_shear();
            assert!(
                rel(t.value.unwrap(), ex.max_shear()) < 1e-11,
                "{m} c={c}: τ {:?} vs {}",
                t.value,
                ex.max_shear()
            );
        }
    }
    // cardioid: inward cusp, J to 1e-6, τ reported singular at the cusp
    let ex = Limacon { a: 1.0, c: 0.5 };
    let sec = sections::limacon(1.0, 0.5).unwrap();
    assert!(sec.is_singular());
    let o = Options {
        n: 512,
        grading: 4.0,
        ..Options::default()
    };
    let s = solve(&sec, &o).unwrap();
    assert!(
        rel(s.torsional_rigidity, ex.rigidity()) < 1e-6,
        "cardioid J {}",
        s.torsional_rigidity
    );
    let t = s.max_shear();
    assert!(t.singular && t.value.is_none());
    let at = t.at.unwrap();
    assert!((at[0] + 0.5).abs() < 1e-12 && at[1].abs() < 1e-12);
}

#[test]
fn grooved_shaft() {
    let (a, b) = (1.0, 0.5);
    let ex = Groove { a, b };
    let sec = sections::groove(a, b).unwrap();
    assert!(!sec.is_singular(), "the groove's corners are convex");
    for m in METHODS {
        let s = run(&sec, m, 512);
        assert!(
            rel(s.torsional_rigidity, ex.rigidity()) < 1e-8,
            "{m}: J {} vs {}",
            s.torsional_rigidity,
            ex.rigidity()
        );
        let t = s.max_shear();
        assert!(
            rel(t.value.unwrap(), ex.max_shear()) < 1e-8,
            "{m}: τ {:?}",
            t.value
        );
        let at = t.at.unwrap();
        assert!((at[0] - b).abs() < 1e-6 && at[1].abs() < 1e-4, "{at:?}");
        let mut worst: f64 = 0.0;
        for smp in s.boundary_samples(1000) {
            let g = ex.grad(smp.x);
            worst = worst.max((smp.q.abs() - g[0].hypot(g[1])).abs());
        }
        assert!(worst < 1e-6, "{m}: |q| error {worst:e}");
    }
}

#[test]
fn reentrant_corner_is_singular() {
    // L-shape: one re-entrant corner at (1, 1)
    let sec = sections::polygon(&[
        [0.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
    ])
    .unwrap();
    assert!(sec.is_singular());
    let s = run(&sec, Method::Daubechies, 256);
    let t = s.max_shear();
    assert!(t.singular && t.value.is_none());
    assert_eq!(t.at.unwrap(), [1.0, 1.0]);
    // J agrees between methods (no closed form; the methods are independent discretisations)
    let s2 = run(&sec, Method::Nystrom, 512);
    assert!(rel(s.torsional_rigidity, s2.torsional_rigidity) < 1e-6);
}

#[test]
fn semicircle_from_a_file_thin_ellipse_and_near_cusp_limacon() {
    // semicircle of radius R (segment + arc): J = (π/2 − 4/π) R⁴ (Saint-Venant)
    let text = "[[piece]]\nkind = \"segment\"\nfrom = [-2.0, 0.0]\nto = [2.0, 0.0]\n\
                [[piece]]\nkind = \"arc\"\ncenter = [0.0, 0.0]\nradius = 2.0\nstart_deg = 0.0\nend_deg = 180.0\n";
    let sec = sections::parse_section_toml(text, "semicircle.toml").unwrap();
    let j = (std::f64::consts::FRAC_PI_2 - 4.0 / std::f64::consts::PI) * 16.0;
    for m in METHODS {
        let s = run(&sec, m, 512);
        assert!(
            rel(s.torsional_rigidity, j) < 1e-8,
            "{m}: semicircle J {} vs {j}",
            s.torsional_rigidity
        );
    }
    // aspect ratio 10 with a few hundred unknowns
    let ex = Ellipse { a: 10.0, b: 1.0 };
    let sec = sections::ellipse(10.0, 1.0).unwrap();
    for m in METHODS {
        let s = run(&sec, m, 256);
        assert!(
            rel(s.torsional_rigidity, ex.rigidity()) < 1e-12,
            "{m}: J {}",
            s.torsional_rigidity
        );
        assert!(
            rel(s.max_shear().value.unwrap(), ex.max_shear()) < 1e-12,
            "{m}: τ"
        );
    }
    // limaçon close to the cardioid (c = 0.45): still smooth, τ_max = 5.05 A in the dimple
    let ex = Limacon { a: 1.0, c: 0.45 };
    let sec = sections::limacon(1.0, 0.45).unwrap();
    for m in METHODS {
        let s = run(&sec, m, 256);
        assert!(
            rel(s.torsional_rigidity, ex.rigidity()) < 1e-12,
            "{m}: J {}",
            s.torsional_rigidity
        );
        assert!(
            rel(s.max_shear().value.unwrap(), ex.max_shear()) < 1e-12,
            "{m}: τ {:?}",
            s.max_shear().value
        );
    }
}
