//! Contact iteration of the two-ring shrink fit (quarter rings, symmetry on
//! both straight edges, the inner ring heated by 50 K, the paper's joint).
//!
//! ```text
//! cargo bench -p tecon --bench elastic
//! ```
//!
//! Sizes: 2·2·rows·segments triangles with segments = 8·rows: rows = 18
//! (1.04e4 triangles) and rows = 56 (1.00e5). Before measuring, one solve
//! prints the Newton iterations per increment, so time per iteration =
//! time per solve / iterations.

use std::f64::consts::PI;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use tecon::contact::PaperJoint;
use tecon::elastic::{Analysis, ElasticModel, Joint, Loads, Material, SolverOptions, StaticSolver};
use tecon::mesh::{RingLayer, layered_annulus};

fn shrink_fit(c: &mut Criterion) {
    let steel = Material {
        youngs_modulus: 207e9,
        poisson_ratio: 0.3,
        expansion: 12.51e-6,
    };
    let mut g = c.benchmark_group("shrink_fit");
    g.sample_size(10);
    for rows in [18usize, 56] {
        let mesh = layered_annulus(
            &[
                RingLayer {
                    name: "inner".into(),
                    r_in: 1.0,
                    r_out: 1.1,
                    rows,
                },
                RingLayer {
                    name: "outer".into(),
                    r_in: 1.1,
                    r_out: 1.2,
                    rows,
                },
            ],
            0.0,
            PI / 2.0,
            8 * rows,
        )
        .expect("mesh");
        let law =
            PaperJoint::with_default_penalty(steel.youngs_modulus, 0.1 / rows as f64, 0.0, 0.3)
                .expect("law");
        let model = ElasticModel::new(&mesh, Analysis::PlaneStrain)
            .material_everywhere(steel)
            .and_then(|m| m.symmetry("start"))
            .and_then(|m| m.symmetry("end"))
            .and_then(|m| m.interface("inner_outer", Joint::Frictional(law)))
            .expect("model");
        let inner = mesh.region_index("inner").expect("region");
        let delta_t: Vec<f64> = mesh
            .element_regions()
            .iter()
            .map(|&r| if r == inner { 50.0 } else { 0.0 })
            .collect();
        let loads = Loads {
            delta_t,
            ..Loads::zero()
        };
        let solve = || {
            let mut s = StaticSolver::new(&model, SolverOptions::default()).expect("solver");
            s.advance(&loads).expect("converges")
        };
        let reports = solve();
        eprintln!(
            "shrink fit, {} triangles: {} increments, Newton iterations per increment {:?}",
            mesh.n_triangles(),
            reports.len(),
            reports
                .iter()
                .map(|r| r.max_pass_iterations)
                .collect::<Vec<_>>()
        );
        g.bench_function(
            BenchmarkId::new("solve", format!("{}tri", mesh.n_triangles())),
            |b| b.iter(solve),
        );
    }
    g.finish();
}

criterion_group!(benches, shrink_fit);
criterion_main!(benches);
