//! The periodised Daubechies machinery and the convergence of the methods.
//!
//! Reference: Daubechies, *Ten Lectures on Wavelets* (1992), §6.1 (spectral
//! factorisation), §5 (multiresolution, FWT); Beylkin, Coifman & Rokhlin
//! (1991) for compression; WAVELET_BEM.md §3 for a(d) and the Haar values
//! a(0) = −3/2, a(1) = (4 ln 2 − 3)/2; the Galerkin functional error
//! O(h^{2N+1}) for dbN.
//!
//! Goal: filters and transforms exact to rounding; the observed order of the
//! Daubechies Galerkin method 2N + 1 (fitted slope within 0.15); spectral
//! convergence (≥ 100× per doubling) of the harmonic-wavelet method.
//!
//! ```text
//!   a_J ──h──▶ a_{J−1} ──h──▶ … ▶ a_{j0}      periodised analysis (orthogonal)
//!        └─g──▶ d_{J−1}  └─g──▶ d_{J−2} …
//! ```
//!
//! Checked: Σh = √2, Σ h_k h_{k+2m} = δ_m, Σ (−1)^k k^m h_{L−1−k} = 0 (m < N),
//! FWT round trip and isometry, a(d) by the refinement equation against
//! closed forms and the far-field expansion, moment-exact rules, fitted
//! orders, Shannon error ratios, compression statistics.

use tecon_wavelet_bem::analytical::Ellipse;
use tecon_wavelet_bem::daubechies::{Daubechies, zeta_pair};
use tecon_wavelet_bem::*;

#[test]
fn filters_db1_to_db10_satisfy_the_defining_identities() {
    // db2 closed form
    let s3 = 3f64.sqrt();
    let d2 = Daubechies::new(2).unwrap();
    let want = [(1.0 + s3), (3.0 + s3), (3.0 - s3), (1.0 - s3)].map(|v| v / (4.0 * 2f64.sqrt()));
    let direct = d2.h.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-15);
    let reversed =
        d2.h.iter()
            .rev()
            .zip(&want)
            .all(|(a, b)| (a - b).abs() < 1e-15);
    assert!(direct || reversed, "db2 = {:?}", d2.h);
    for n in 1..=10 {
        let w = Daubechies::new(n).unwrap();
        assert_eq!(w.len(), 2 * n);
        let (sum, orth, vm) = w.check();
        // f64 limits: sums of 2N products of O(1) numbers; moments in the scaled variable k/(2N−1)
        assert!(sum < 1e-15, "db{n}: |Σh − √2| = {sum:e}");
        assert!(orth < 1e-15, "db{n}: orthonormality {orth:e}");
        assert!(vm < 5e-15, "db{n}: vanishing moments {vm:e}");
    }
    assert!(Daubechies::new(0).is_none() && Daubechies::new(21).is_none());
    assert!(Daubechies::from_name("db7").is_some() && Daubechies::from_name("sym4").is_none());
}

#[test]
fn fwt_round_trip_and_isometry() {
    for n in [1usize, 2, 4, 7, 10] {
        let w = Daubechies::new(n).unwrap();
        for len in [64usize, 256, 1024] {
            let x: Vec<f64> = (0..len)
                .map(|i| ((i * 37 + 11) % 101) as f64 / 50.0 - 1.0 + (i as f64 * 0.1).sin())
                .collect();
            let mut y = x.clone();
            w.fwt(&mut y, 2);
            let nx: f64 = x.iter().map(|v| v * v).sum();
            let ny: f64 = y.iter().map(|v| v * v).sum();
            assert!(
                (nx - ny).abs() < 1e-13 * nx,
                "db{n} len {len}: not orthogonal"
            );
            w.ifwt(&mut y, 2);
            let err = x
                .iter()
                .zip(&y)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-14, "db{n} len {len}: round trip {err:e}");
        }
    }
    // wavelets integrate to zero: the transform of the constant lives in the coarse block
    let w = Daubechies::new(4).unwrap();
    let mut e = vec![1.0; 256];
    w.fwt(&mut e, 3);
    assert!(e[8..].iter().all(|v| v.abs() < 1e-13));
}

#[test]
fn log_integrals_by_the_refinement_equation() {
    let haar = Daubechies::new(1).unwrap();
    let a = haar.log_integrals(40);
    assert!((a[0] + 1.5).abs() < 1e-14, "a(0) = {}", a[0]);
    assert!(
        (a[1] - (4.0 * 2f64.ln() - 3.0) / 2.0).abs() < 1e-14,
        "a(1) = {}",
        a[1]
    );
    // Haar, d ≥ 1: ∫_{-1}^{1} (1 − |y|) ln(d + y) dy in closed form
    let exact = |d: f64| {
        let f = |x: f64| {
            if x > 0.0 {
                x * x * x.ln() / 2.0 - x * x * 0.25
            } else {
                0.0
            }
        };
        let g = |x: f64| if x > 0.0 { x * x.ln() - x } else { 0.0 };
        // ∫ (1 − |y|) ln(d + y) = Σ with x = d + y
        (1.0 - d) * (g(d) - g(d - 1.0)) + (f(d) - f(d - 1.0)) + (1.0 + d) * (g(d + 1.0) - g(d))
            - (f(d + 1.0) - f(d))
    };
    // (the closed form cancels terms of size d² ln d: kept to d ≤ 7, the far field covers the rest)
    for d in [2usize, 3, 5, 7] {
        assert!(
            (a[d] - exact(d as f64)).abs() < 1e-13,
            "Haar a({d}) = {} vs {}",
            a[d],
            exact(d as f64)
        );
    }
    // dbN: the solved values join the far-field expansion smoothly
    for n in [1usize, 2, 3, 4, 8] {
        let w = Daubechies::new(n).unwrap();
        let a = w.log_integrals(200);
        let mm = w.autocorrelation_moments(80);
        for d in [4 * (2 * n - 1), 4 * (2 * n - 1) + 4, 200] {
            let e = d as f64;
            let mut far = e.ln();
            for k in 1..40 {
                far -= mm[2 * k] / (2.0 * k as f64) / e.powi(2 * k as i32);
            }
            assert!(
                (a[d] - far).abs() < 1e-13,
                "db{n} a({d}) = {} vs far field {far}",
                a[d]
            );
        }
        // the autocorrelation is interpolating: moments 1 … 2N − 1 vanish
        assert!(mm[1..2 * n].iter().all(|v| *v == 0.0) && mm[2 * n].abs() > 1e-6);
    }
}

#[test]
fn log_circulant_matches_the_fourier_series_for_haar() {
    // C(d) = −(1/n) Σ_{m≥1} |φ̂(m/n)|² cos(2πmd/n)/m; for Haar |φ̂(ξ)|² = sinc²(πξ),
    // and the tail beyond M decays like n/(2π²M²): summed with M = 2·10⁶ (tail < 1e-12 at n = 16)
    let w = Daubechies::new(1).unwrap();
    let n = 16;
    let c = w.log_circulant(n);
    for d in [0usize, 1, 3, 8] {
        let mut s = 0.0;
        for m in (1..2_000_000usize).rev() {
            let x = std::f64::consts::PI * m as f64 / n as f64;
            let sinc2 = (x.sin() / x).powi(2);
            s += sinc2 * (2.0 * std::f64::consts::PI * ((m * d) % n) as f64 / n as f64).cos()
                / m as f64;
        }
        assert!(
            (c[d] + s / n as f64).abs() < 1e-11,
            "d={d}: {} vs {}",
            c[d],
            -s / n as f64
        );
    }
    // Z_2(x) = π²/sin²(πx) − 1/x²
    for x in [0.1, 0.25, 0.5] {
        let pi = std::f64::consts::PI;
        let z = pi * pi / (pi * x).sin().powi(2) - 1.0 / (x * x);
        assert!((zeta_pair(2, x) - z).abs() < 1e-13, "Z_2({x})");
    }
}

#[test]
fn moment_exact_rules() {
    for n in [2usize, 3, 4] {
        let w = Daubechies::new(n).unwrap();
        let k = 2 * n;
        let rule = w.moment_rule(k);
        let mu = w.phi_moments(k);
        for (m, mum) in mu.iter().enumerate().take(k) {
            let q: f64 = rule
                .iter()
                .enumerate()
                .map(|(q, wq)| wq * (q as f64).powi(m as i32))
                .sum();
            assert!(
                (q - mum).abs() < 1e-11 * mum.abs().max(1.0),
                "db{n} moment {m}: {q} vs {mum}"
            );
        }
    }
    // Haar moments are 1/(m+1)
    let mu = Daubechies::new(1).unwrap().phi_moments(5);
    for (m, v) in mu.iter().enumerate() {
        assert!((v - 1.0 / (m as f64 + 1.0)).abs() < 1e-15);
    }
}

fn fitted_slope(ns: &[usize], errs: &[f64]) -> f64 {
    let xs: Vec<f64> = ns.iter().map(|&n| (n as f64).ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let k = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / k;
    let my = ys.iter().sum::<f64>() / k;
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    -sxy / sxx
}

#[test]
fn daubechies_galerkin_order_is_2n_plus_1() {
    let ex = Ellipse { a: 3.0, b: 1.0 };
    let sec = sections::ellipse(3.0, 1.0).unwrap();
    for (nv, ns) in [
        (1usize, vec![32usize, 64, 128, 256]),
        (2, vec![32, 64, 128, 256]),
        (3, vec![64, 128, 256]),
    ] {
        let errs: Vec<f64> = ns
            .iter()
            .map(|&n| {
                let s = solve(
                    &sec,
                    &Options {
                        n,
                        wavelet_order: nv,
                        ..Options::default()
                    },
                )
                .unwrap();
                (s.torsional_rigidity / ex.rigidity() - 1.0).abs()
            })
            .collect();
        let slope = fitted_slope(&ns, &errs);
        let theory = (2 * nv + 1) as f64;
        assert!(
            (slope - theory).abs() < 0.15,
            "db{nv}: fitted order {slope:.3} (theory {theory}), errors {errs:?}"
        );
    }
}

#[test]
fn harmonic_wavelets_converge_spectrally() {
    let ex = Ellipse { a: 3.0, b: 1.0 };
    let sec = sections::ellipse(3.0, 1.0).unwrap();
    let mut prev: Option<f64> = None;
    for n in [8usize, 16, 32, 64] {
        let s = solve(
            &sec,
            &Options {
                n,
                method: Method::Shannon,
                ..Options::default()
            },
        )
        .unwrap();
        let e = (s.torsional_rigidity / ex.rigidity() - 1.0).abs();
        if let Some(p) = prev
            && p > 1e-13
        {
            assert!(e < p / 100.0 || e < 1e-13, "n={n}: error {e:e} after {p:e}");
        }
        prev = Some(e);
    }
    assert!(prev.unwrap() < 1e-13);
}

#[test]
fn compressed_wavelet_matrix_and_cg() {
    let ex = Ellipse { a: 2.0, b: 1.0 };
    let sec = sections::ellipse(2.0, 1.0).unwrap();
    let mut epr = Vec::new();
    for n in [256usize, 512] {
        let dense = solve(
            &sec,
            &Options {
                n,
                ..Options::default()
            },
        )
        .unwrap();
        for eps in [1e-6, 1e-9] {
            let s = solve(
                &sec,
                &Options {
                    n,
                    linear: LinearSolver::Compressed { eps, tol: 1e-13 },
                    ..Options::default()
                },
            )
            .unwrap();
            let c = s.compression.clone().unwrap();
            // the thresholding error is bounded by ε relative to max|a|, and J follows it
            assert!(
                c.operator_error < 100.0 * eps,
                "n={n} ε={eps}: operator error {:e}",
                c.operator_error
            );
            assert!(
                (s.torsional_rigidity - dense.torsional_rigidity).abs() < 1e3 * eps * ex.rigidity(),
                "n={n} ε={eps}"
            );
            assert!(
                c.entries_per_row < n as f64 / 2.0,
                "n={n} ε={eps}: {} entries/row",
                c.entries_per_row
            );
            assert!(
                c.iterations < 100,
                "level-scaled CG took {} iterations",
                c.iterations
            );
            epr.push((n, eps, c.entries_per_row));
        }
    }
    // entries per row grow slowly (not like n) from n = 256 to 512
    for eps in [1e-6, 1e-9] {
        let v: Vec<f64> = epr.iter().filter(|e| e.1 == eps).map(|e| e.2).collect();
        assert!(v[1] < 1.3 * v[0], "ε={eps}: entries/row {v:?}");
    }
}
