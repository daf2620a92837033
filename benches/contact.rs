//! Contact-law evaluation and interface-element kernel throughput.
//!
//! ```text
//! cargo bench --bench contact
//! ```
//!
//! Each benchmark evaluates a batch of 1024 integration points (laws) or
//! elements (kernels: 8-dof force + 8×8 tangent + 2 law calls) with
//! precomputed inputs; criterion reports the throughput in elements/s.
//! The element batch lies on a circle (the vessel's interface), with a
//! mixture of open, sticking and slipping points for the paper's joint.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use tecon::contact::nalgebra::{Point2, Vector2};
use tecon::contact::{
    ContactLaw, GhaboussiNormal, InterfaceElement, InterfaceQuadrature, JointState, LinearJoint,
    PaperJoint, Vector8,
};

const N: usize = 1024;

fn paper_joint() -> PaperJoint {
    let g = GhaboussiNormal::new(2.0e9, 2.0e11, 1.0e-3, -1.0e-3).expect("valid law");
    PaperJoint::new(g, 3.0e11, 0.5e6, 30f64.to_radians()).expect("valid law")
}

/// Deterministic pseudo-random numbers in [−1, 1) (no extra dependency).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

fn bench_laws(c: &mut Criterion) {
    let mut seed = 7;
    // Jumps: stick (small shear, closed) and slip (large shear, closed).
    let stick: Vec<Vector2<f64>> = (0..N)
        .map(|_| Vector2::new(1e-7 * lcg(&mut seed), -1.5e-6 + 1e-7 * lcg(&mut seed)))
        .collect();
    let slip: Vec<Vector2<f64>> = (0..N)
        .map(|_| {
            Vector2::new(
                5e-5 * lcg(&mut seed).signum(),
                -0.5e-6 + 1e-7 * lcg(&mut seed),
            )
        })
        .collect();
    let lin = LinearJoint::new(3.0e11, 7.0e11).expect("valid law");
    let law = paper_joint();
    let state = JointState::default();
    let mut g = c.benchmark_group("contact_law");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("linear_joint", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for j in &stick {
                acc += lin.evaluate(black_box(j), &()).traction.y;
            }
            acc
        })
    });
    for (name, jumps) in [("paper_joint_stick", &stick), ("paper_joint_slip", &slip)] {
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for j in jumps.iter() {
                    let r = law.evaluate(black_box(j), &state);
                    acc += r.traction.x + r.state.slip;
                }
                acc
            })
        });
    }
    g.finish();
}

fn bench_elements(c: &mut Criterion) {
    let (r, dtheta) = (0.775, std::f64::consts::PI / N as f64);
    let mut seed = 11;
    let law = paper_joint();
    let mut g = c.benchmark_group("interface_element");
    g.throughput(Throughput::Elements(N as u64));
    for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
        let elements: Vec<InterfaceElement> = (0..N)
            .map(|i| {
                let p = |a: f64| Point2::new(r * a.cos(), r * a.sin());
                let (a0, a1) = (i as f64 * dtheta, (i + 1) as f64 * dtheta);
                InterfaceElement::with_quadrature(&[p(a1), p(a0), p(a0), p(a1)], rule)
                    .expect("valid element")
            })
            .collect();
        let disp: Vec<Vector8> = (0..N)
            .map(|_| Vector8::from_fn(|_, _| 2e-6 * lcg(&mut seed)))
            .collect();
        let states = [JointState::default(); 2];
        g.bench_function(format!("paper_joint_{rule:?}"), |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for (e, u) in elements.iter().zip(&disp) {
                    let out = e.evaluate(&law, black_box(u), &states);
                    acc += out.force[0] + out.tangent[(0, 0)];
                }
                acc
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench_laws, bench_elements);
criterion_main!(benches);
