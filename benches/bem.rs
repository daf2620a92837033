//! Criterion bench of the wavelet-BEM torsion solvers.
//!
//! ```text
//! cargo bench --bench bem -p tecon
//! ```
//!
//! Assembly and full solve (assembly + dense LU or compressed CG + J) for the
//! Daubechies (db4), Shannon and Nyström methods at n = 256, 1024 (4096 for
//! assembly and the compressed Daubechies solve only: a dense LU of order 4096
//! takes seconds), serial (1 rayon thread) and parallel (2 threads), on an
//! ellipse a = 2, b = 1.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use tecon::wavelet_bem::daubechies::Daubechies;
use tecon::wavelet_bem::grading::Parametrisation;
use tecon::wavelet_bem::{
    LinearSolver, Method, Options, galerkin, nystrom, sections, shannon, solve,
};

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn bench(c: &mut Criterion) {
    let sec = sections::ellipse(2.0, 1.0).expect("ellipse");
    let param = Parametrisation::new(&sec, 6.0);
    let mut g = c.benchmark_group("bem");
    g.sample_size(10);
    g.measurement_time(std::time::Duration::from_secs(3));
    g.warm_up_time(std::time::Duration::from_millis(500));
    for threads in [1usize, 2] {
        let p = pool(threads);
        let tag = if threads == 1 { "serial" } else { "parallel" };
        for n in [256usize, 1024, 4096] {
            g.bench_with_input(
                BenchmarkId::new(format!("assemble/daubechies/{tag}"), n),
                &n,
                |b, &n| {
                    b.iter(|| {
                        p.install(|| {
                            galerkin::assemble(
                                &sec,
                                std::slice::from_ref(&param),
                                n,
                                Daubechies::new(4).expect("db4"),
                            )
                            .map(|s| black_box(s.matrix.len()))
                        })
                    })
                },
            );
            g.bench_with_input(
                BenchmarkId::new(format!("assemble/nystrom/{tag}"), n),
                &n,
                |b, &n| {
                    b.iter(|| {
                        p.install(|| {
                            black_box(
                                nystrom::assemble(&param.nodes(&sec, n), sec.centroid)
                                    .matrix
                                    .len(),
                            )
                        })
                    })
                },
            );
            g.bench_with_input(
                BenchmarkId::new(format!("assemble/shannon/{tag}"), n),
                &n,
                |b, &n| {
                    b.iter(|| {
                        p.install(|| {
                            shannon::assemble(&sec, &param, n).map(|s| black_box(s.matrix.len()))
                        })
                    })
                },
            );
            let methods: &[(&str, Method, LinearSolver)] = if n <= 1024 {
                &[
                    ("daubechies-lu", Method::Daubechies, LinearSolver::Dense),
                    (
                        "daubechies-cg1e-9",
                        Method::Daubechies,
                        LinearSolver::Compressed {
                            eps: 1e-9,
                            tol: 1e-12,
                        },
                    ),
                    ("shannon", Method::Shannon, LinearSolver::Dense),
                    ("nystrom", Method::Nystrom, LinearSolver::Dense),
                ]
            } else {
                &[(
                    "daubechies-cg1e-9",
                    Method::Daubechies,
                    LinearSolver::Compressed {
                        eps: 1e-9,
                        tol: 1e-12,
                    },
                )]
            };
            for &(name, method, linear) in methods {
                let opts = Options {
                    n,
                    method,
                    linear,
                    ..Options::default()
                };
                g.bench_with_input(
                    BenchmarkId::new(format!("solve/{name}/{tag}"), n),
                    &n,
                    |b, _| {
                        b.iter(|| {
                            p.install(|| {
                                solve(&sec, &opts).map(|s| black_box(s.torsional_rigidity))
                            })
                        })
                    },
                );
            }
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
