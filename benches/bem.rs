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
use tecon::wavelet_bem::control::default_max_n;
use tecon::wavelet_bem::daubechies::Daubechies;
use tecon::wavelet_bem::grading::Parametrisation;
use tecon::wavelet_bem::{
    LinearSolver, Method, Options, galerkin, nystrom, sections, shannon, solve, solve_to_tolerance,
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
                            shannon::assemble(&sec, std::slice::from_ref(&param), n)
                                .map(|s| black_box(s.matrix.len()))
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

/// Every built-in section (hollow ones included) solved by the default error
/// control to the relative tolerance 1e-10 (goal: under 0.2 s each), the
/// sectionproperties comparison sections (box, monosymmetric I, channel of
/// tests/data/sectionproperties.toml) to 1e-10, and 2000-vertex polygons
/// (goal: under 1 s): the regular 2000-gon to 1e-10 (graded at every vertex
/// and folded to one edge, n = 128 000), and 2000 points on the ellipse
/// 2 × 1 at the default 1e-8 (no rotation of order 2000: parametrised by arc
/// length, its flat vertices not resolved, flagged with their error floors;
/// the bench measures what that costs). Each with the CLI's default
/// largest n.
fn bench_sections(c: &mut Criterion) {
    let mut g = c.benchmark_group("bem_sections");
    g.sample_size(10);
    g.measurement_time(std::time::Duration::from_secs(2));
    g.warm_up_time(std::time::Duration::from_millis(200));
    let cases: Vec<(&str, tecon::wavelet_bem::Section, f64)> = vec![
        ("circle", sections::circle(1.0).expect("circle"), 1e-10),
        (
            "ellipse",
            sections::ellipse(2.0, 1.0).expect("ellipse"),
            1e-10,
        ),
        (
            "rectangle",
            sections::rectangle(1.0, 2.0).expect("rectangle"),
            1e-10,
        ),
        (
            "triangle",
            sections::triangle(1.0).expect("triangle"),
            1e-10,
        ),
        (
            "regular6",
            sections::regular_polygon(6, 1.0).expect("hexagon"),
            1e-10,
        ),
        ("groove", sections::groove(1.0, 0.5).expect("groove"), 1e-10),
        (
            "limacon0.3",
            sections::limacon(1.0, 0.3).expect("limacon"),
            1e-10,
        ),
        ("tube", sections::tube(1.0, 0.6).expect("tube"), 1e-10),
        (
            "thin_tube",
            sections::tube(1.0, 0.98).expect("thin tube"),
            1e-10,
        ),
        (
            "box",
            sections::hollow_rectangle(2.0, 1.0, 0.1, 0.05).expect("box"),
            1e-10,
        ),
        (
            "thin_box",
            sections::hollow_rectangle(2.0, 1.0, 0.02, 0.02).expect("thin box"),
            1e-10,
        ),
        (
            "sp_box",
            sections::parse_spec("box:w=2,h=1,tf=0.12,tw=0.08").expect("box"),
            1e-10,
        ),
        (
            "sp_I",
            sections::parse_spec(
                "polygon:-0.25,0;0.25,0;0.25,0.08;0.025,0.08;0.025,0.92;0.4,0.92;0.4,1;\
                 -0.4,1;-0.4,0.92;-0.025,0.92;-0.025,0.08;-0.25,0.08",
            )
            .expect("I"),
            1e-10,
        ),
        (
            "sp_channel",
            sections::parse_spec(
                "polygon:0,0;0.5,0;0.5,0.08;0.06,0.08;0.06,0.92;0.5,0.92;0.5,1;0,1",
            )
            .expect("channel"),
            1e-10,
        ),
        (
            "polygon2000",
            sections::regular_polygon(2000, 1.0).expect("2000-gon"),
            1e-10,
        ),
        (
            "ellipse_points2000",
            sections::polygon(
                &(0..2000)
                    .map(|k| {
                        let a = 2.0 * std::f64::consts::PI * k as f64 / 2000.0;
                        [2.0 * a.cos(), a.sin()]
                    })
                    .collect::<Vec<_>>(),
            )
            .expect("2000 points on an ellipse"),
            1e-8,
        ),
        (
            "regular12",
            sections::regular_polygon(12, 1.0).expect("12-gon"),
            1e-10,
        ),
        (
            "regular24",
            sections::regular_polygon(24, 1.0).expect("24-gon"),
            1e-10,
        ),
        (
            "regular25",
            sections::regular_polygon(25, 1.0).expect("25-gon"),
            1e-10,
        ),
    ];
    for (name, sec, tol) in &cases {
        g.bench_function(BenchmarkId::new("to_tolerance", name), |b| {
            b.iter(|| {
                let opts = Options::default();
                solve_to_tolerance(sec, &opts, *tol, default_max_n(sec, &opts))
                    .map(|c| black_box(c.solution.torsional_rigidity))
            })
        });
    }
    // the same without folding by the rotational symmetry (the whole system)
    for name in ["box", "regular12", "regular24", "regular25"] {
        let Some((_, sec, tol)) = cases.iter().find(|c| c.0 == name) else {
            continue;
        };
        let whole = Options {
            symmetry: false,
            ..Options::default()
        };
        g.bench_function(BenchmarkId::new("to_tolerance_whole", name), |b| {
            b.iter(|| {
                solve_to_tolerance(sec, &whole, *tol, default_max_n(sec, &whole))
                    .map(|c| black_box(c.solution.torsional_rigidity))
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench, bench_sections);
criterion_main!(benches);
