//! Pattern build and value fill of the shared assembler.
//!
//! ```text
//! cargo bench -p tecon --bench assembly
//! ```
//!
//! Unit-square meshes of 2·n² linear triangles (n = 71, 224, 708: 1.0e4,
//! 1.0e5, 1.0e6 triangles); the 3×3 Laplace and the 6×6 plane-strain kernels;
//! fill on one thread (`serial`) and on the rayon pool (`parallel`, batched
//! kernels with an element-ordered scatter: bitwise identical results).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use tecon::fem::reference::{ElasticSet, LaplaceSet};
use tecon::fem::triangle::plane_strain_d;
use tecon::fem::{AssemblerBuilder, Element, Parallelism};
use tecon::mesh::rectangle;

const SIZES: [usize; 3] = [71, 224, 708];

fn bench_kernel<const N: usize, E: Element<N>>(
    c: &mut Criterion,
    name: &str,
    n_dofs: usize,
    set: &E,
    n: usize,
) {
    let mut g = c.benchmark_group(name);
    g.sample_size(10);
    g.throughput(Throughput::Elements(set.n_elements() as u64));
    let tag = format!("{}tri", set.n_elements());
    g.bench_function(BenchmarkId::new("pattern", &tag), |b| {
        b.iter(|| {
            let mut builder = AssemblerBuilder::new(n_dofs);
            builder.add_elements(set);
            builder.build().expect("pattern")
        })
    });
    let mut builder = AssemblerBuilder::new(n_dofs);
    let id = builder.add_elements(set);
    let asm = builder.build().expect("pattern");
    let mut m = asm.new_matrix();
    for (label, par) in [
        ("fill_serial", Parallelism::Serial),
        ("fill_parallel", Parallelism::Rayon),
    ] {
        g.bench_function(BenchmarkId::new(label, &tag), |b| {
            b.iter(|| {
                m.values_mut().fill(0.0);
                asm.add(id, set, &mut m, None, par).expect("fill");
            })
        });
    }
    let _ = n;
    g.finish();
}

fn assembly(c: &mut Criterion) {
    for n in SIZES {
        let mesh = rectangle(0.0, 0.0, 1.0, 1.0, n, n).expect("mesh");
        let lap = LaplaceSet {
            nodes: mesh.nodes(),
            triangles: mesh.triangles(),
            k: 1.0,
            source: 1.0,
        };
        bench_kernel(c, "laplace3x3", mesh.n_nodes(), &lap, n);
        let el = ElasticSet {
            nodes: mesh.nodes(),
            triangles: mesh.triangles(),
            d: plane_strain_d(207e9, 0.3),
        };
        bench_kernel(c, "plane_strain6x6", 2 * mesh.n_nodes(), &el, n);
    }
}

criterion_group!(benches, assembly);
criterion_main!(benches);
