//! The sequential shrink fit of concentric rings (`analytical::SequentialShrinkFit`),
//! checked against a second, independent derivation.
//!
//! Reference: Lamé's thick cylinder. The model treats the already wrapped rings as one
//! cylinder of one material; the check below instead solves every ring on its own, with an
//! unknown pressure at each interface and radial compatibility at each interface (continuity,
//! or the new layer's interference at its own interface), stage by stage, and sums the stages.
//!
//! ```text
//!   r0 ──core── r1 ──layer 1── r2 ──layer 2── r3 … r_{N+1}
//!   stage k: rings 0..k, interfaces 1..k; δ_k at interface k, continuity elsewhere
//! ```
//! Goal: the two agree to 1e-10 (relative); the wall is in equilibrium (∫σ_θθ dr = 0) after
//! every stage; with one layer the model is the two-cylinder fit exactly.

use nalgebra::{DMatrix, DVector};
use tecon_elastic::analytical::{
    Cylinders, SequentialFitError, SequentialShrinkFit, ShrinkFit, weld_interference,
};

const E: f64 = 207e9;
const NU: f64 = 0.3;

/// Radial displacement of a ring a ≤ r ≤ b under internal pressure pi and external po.
fn ring_u(a: f64, b: f64, pi: f64, po: f64, r: f64, state: Cylinders) -> f64 {
    let d = b * b - a * a;
    let big_a = (pi * a * a - po * b * b) / d;
    let big_b = (pi - po) * a * a * b * b / d;
    match state {
        Cylinders::PlaneStrain => (1.0 + NU) / E * r * ((1.0 - 2.0 * NU) * big_a + big_b / (r * r)),
        Cylinders::PlaneStress => r / E * ((1.0 - NU) * big_a + (1.0 + NU) * big_b / (r * r)),
    }
}

/// Hoop stress of that ring.
fn ring_hoop(a: f64, b: f64, pi: f64, po: f64, r: f64) -> f64 {
    let d = b * b - a * a;
    (pi * a * a - po * b * b) / d + (pi - po) * a * a * b * b / d / (r * r)
}

/// Interface pressures q_1..q_k of stage k, ring by ring (compatibility at each interface).
fn stage_pressures(radii: &[f64], k: usize, delta: f64, state: Cylinders) -> Vec<f64> {
    // unknowns q_1..q_k; ring j (0..=k) has internal q_j (q_0 = 0), external q_{j+1} (q_{k+1} = 0)
    let u = |j: usize, q: &[f64], r: f64| {
        let pi = if j == 0 { 0.0 } else { q[j - 1] };
        let po = if j == k { 0.0 } else { q[j] };
        ring_u(radii[j], radii[j + 1], pi, po, r, state)
    };
    // u is linear in q: build the matrix column by column
    let residual = |q: &[f64]| -> Vec<f64> {
        (1..=k)
            .map(|i| {
                let gap = u(i, q, radii[i]) - u(i - 1, q, radii[i]);
                gap - if i == k { delta } else { 0.0 }
            })
            .collect()
    };
    let r0 = residual(&vec![0.0; k]);
    let mut m = DMatrix::zeros(k, k);
    for c in 0..k {
        let mut q = vec![0.0; k];
        q[c] = 1e6;
        let rc = residual(&q);
        for i in 0..k {
            m[(i, c)] = (rc[i] - r0[i]) / 1e6;
        }
    }
    let rhs = DVector::from_iterator(k, r0.iter().map(|v| -v));
    m.lu().solve(&rhs).unwrap().iter().copied().collect()
}

fn vessel_like(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut radii = vec![0.762, 0.762 + 0.0127];
    let mut deltas = Vec::new();
    for j in 0..n {
        radii.push(radii.last().unwrap() + 0.0064 + 0.0005 * j as f64);
        deltas.push(weld_interference(
            12.51e-6,
            1111.0,
            0.0076,
            NU,
            Cylinders::PlaneStrain,
        ));
    }
    (radii, deltas)
}

#[test]
fn one_layer_is_the_two_cylinder_fit() {
    let (radii, deltas) = vessel_like(1);
    let model =
        SequentialShrinkFit::new(radii.clone(), deltas.clone(), E, NU, Cylinders::PlaneStrain)
            .unwrap();
    let fit = ShrinkFit {
        a: radii[0],
        c: radii[1],
        b: radii[2],
        delta: deltas[0],
        e: E,
        nu: NU,
        state: Cylinders::PlaneStrain,
    };
    assert_eq!(model.contact_pressure(1, 1), -fit.sigma_rr(radii[1], false));
    assert!((model.contact_pressure(1, 1) / fit.pressure() - 1.0).abs() < 1e-12);
    for (ring, inner) in [(0, true), (1, false)] {
        let r = 0.5 * (radii[ring] + radii[ring + 1]);
        assert_eq!(model.sigma_tt(1, ring, r), fit.sigma_tt(r, inner));
        // mean hoop against a 2000-interval Simpson rule
        let (a, b) = (radii[ring], radii[ring + 1]);
        let n = 2000;
        let h = (b - a) / n as f64;
        let s: f64 = (0..=n)
            .map(|i| {
                let w = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * fit.sigma_tt(a + i as f64 * h, inner)
            })
            .sum::<f64>()
            * h
            / 3.0;
        let mean = s / (b - a);
        assert!(
            (model.mean_hoop(1, ring) / mean - 1.0).abs() < 1e-12,
            "ring {ring}"
        );
    }
    // the vessel's published case: 0.035 MPa in the plane-strain consistent model
    assert!((model.contact_pressure(1, 1) / 35249.0 - 1.0).abs() < 1e-3);
}

#[test]
fn stages_agree_with_ring_by_ring_compatibility() {
    for state in [Cylinders::PlaneStrain, Cylinders::PlaneStress] {
        for n in 2..=5 {
            let (radii, deltas) = vessel_like(n);
            let model =
                SequentialShrinkFit::new(radii.clone(), deltas.clone(), E, NU, state).unwrap();
            for after in 1..=n {
                // ring-by-ring sum of stages 1..=after
                let mut q_total = vec![0.0; n];
                let mut hoop = vec![[0.0; 2]; n + 1];
                for k in 1..=after {
                    let q = stage_pressures(&radii, k, deltas[k - 1], state);
                    for j in 0..=k {
                        let pi = if j == 0 { 0.0 } else { q[j - 1] };
                        let po = if j == k { 0.0 } else { q[j] };
                        for (s, r) in [radii[j], radii[j + 1]].into_iter().enumerate() {
                            hoop[j][s] += ring_hoop(radii[j], radii[j + 1], pi, po, r);
                        }
                    }
                    for (j, qj) in q.iter().enumerate() {
                        q_total[j] += qj;
                    }
                }
                let scale = hoop.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                for (j, h) in hoop.iter().enumerate() {
                    for (s, r) in [radii[j], radii[j + 1]].into_iter().enumerate() {
                        let m = model.sigma_tt(after, j, r);
                        assert!(
                            (m - h[s]).abs() < 1e-10 * scale,
                            "{state:?} N={n} after {after}: ring {j} r={r}: {m} vs {}",
                            h[s]
                        );
                    }
                }
                for j in 1..=n {
                    let p = model.contact_pressure(after, j);
                    assert!((p - q_total[j - 1]).abs() < 1e-10 * scale, "interface {j}");
                    assert!(p >= 0.0);
                    if j > after {
                        assert_eq!(p, 0.0);
                    }
                }
            }
        }
    }
}

#[test]
fn the_wall_is_in_equilibrium_after_every_stage() {
    let (radii, deltas) = vessel_like(5);
    let model =
        SequentialShrinkFit::new(radii.clone(), deltas, E, NU, Cylinders::PlaneStrain).unwrap();
    for after in 1..=5 {
        // ∫ σ_θθ dr over the wrapped wall = [r σ_rr] = 0: no net hoop force
        let (force, scale) = (0..=after).fold((0.0, 0.0), |(f, s), ring| {
            let t = radii[ring + 1] - radii[ring];
            let m = model.mean_hoop(after, ring);
            (f + m * t, s + m.abs() * t)
        });
        assert!(
            force.abs() < 1e-12 * scale,
            "after {after}: {force} of {scale}"
        );
        // free surfaces
        assert!(model.sigma_rr(after, 0, radii[0]).abs() < 1e-6);
        assert!(model.sigma_rr(after, after, radii[after + 1]).abs() < 1e-6);
        // the core is compressed more with every layer
        if after > 1 {
            assert!(model.mean_hoop(after, 0) < model.mean_hoop(after - 1, 0));
        }
    }
}

#[test]
fn bad_geometry_is_refused_by_name() {
    let e =
        |r: Vec<f64>, d: Vec<f64>| SequentialShrinkFit::new(r, d, E, NU, Cylinders::PlaneStrain);
    assert_eq!(
        e(vec![1.0, 1.1], vec![]).unwrap_err(),
        SequentialFitError::Counts {
            radii: 2,
            deltas: 0
        }
    );
    assert!(matches!(
        e(vec![1.0, 1.1, 1.1], vec![1e-5]).unwrap_err(),
        SequentialFitError::Radii { index: 2, .. }
    ));
    assert!(matches!(
        e(vec![1.0, 1.2, 1.1], vec![1e-5]).unwrap_err(),
        SequentialFitError::Radii { index: 2, .. }
    ));
    assert!(matches!(
        e(vec![1.0, 1.1, 1.2], vec![-1e-5]).unwrap_err(),
        SequentialFitError::Interference { layer: 1, .. }
    ));
    let msg = e(vec![1.0, 1.1, 1.2, 1.3], vec![1e-5])
        .unwrap_err()
        .to_string();
    assert!(msg.contains("4 radii need 2"), "{msg}");
}
