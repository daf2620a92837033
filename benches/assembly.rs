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
//!
//! P2 (`laplace6x6_p2`): the same squares of 2·n² 6-node triangles (n = 224,
//! 708: 1.0e5 and 1.0e6 elements, 2.0e5 and 2.0e6 nodes) with a 6×6
//! isoparametric Laplace kernel written here (3-point rule, exact for
//! straight-sided triangles), until tecon-fem has its own P2 kernels.
//! P2 plane strain (`plane_strain12x12_p2`): the same meshes with the
//! solver's kernel (`Triangle6::elasticity_stiffness`, 6-point degree-4
//! rule, as for curved elements), pattern and fill.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::{Matrix2, SMatrix, SVector, Vector2};
use tecon::fem::quadrature::TriangleRule;
use tecon::fem::reference::{ElasticSet, LaplaceSet};
use tecon::fem::triangle::plane_strain_d;
use tecon::fem::triangle6::Triangle6;
use tecon::fem::{AssemblerBuilder, Element, LocalSystem, Parallelism};
use tecon::mesh::quadratic::p2_shape_derivatives;
use tecon::mesh::{rectangle, rectangle_of_order};

/// −∇·(k∇u) = s on 6-node triangles: k∫∇N∇Nᵀ and s∫N by the 3-point rule.
struct LaplaceP2Set<'a> {
    nodes: &'a [[f64; 2]],
    triangles: &'a [[usize; 6]],
    k: f64,
    source: f64,
}

impl Element<6> for LaplaceP2Set<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 6] {
        self.triangles[e]
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<6> {
        let x = self.triangles[e].map(|v| self.nodes[v]);
        let mut matrix = SMatrix::<f64, 6, 6>::zeros();
        let mut vector = SVector::<f64, 6>::zeros();
        for (xi, eta) in [
            (1.0 / 6.0, 1.0 / 6.0),
            (2.0 / 3.0, 1.0 / 6.0),
            (1.0 / 6.0, 2.0 / 3.0),
        ] {
            let (dxi, deta) = p2_shape_derivatives(xi, eta);
            let mut j = Matrix2::zeros();
            for a in 0..6 {
                j[(0, 0)] += dxi[a] * x[a][0];
                j[(0, 1)] += deta[a] * x[a][0];
                j[(1, 0)] += dxi[a] * x[a][1];
                j[(1, 1)] += deta[a] * x[a][1];
            }
            let det = j.determinant();
            let inv_t = j.try_inverse().expect("valid element").transpose();
            let grads: [Vector2<f64>; 6] =
                std::array::from_fn(|a| inv_t * Vector2::new(dxi[a], deta[a]));
            let w = det / 6.0;
            let l1 = 1.0 - xi - eta;
            let n = [
                l1 * (2.0 * l1 - 1.0),
                xi * (2.0 * xi - 1.0),
                eta * (2.0 * eta - 1.0),
                4.0 * l1 * xi,
                4.0 * xi * eta,
                4.0 * eta * l1,
            ];
            for a in 0..6 {
                vector[a] += w * self.source * n[a];
                for b in 0..6 {
                    matrix[(a, b)] += w * self.k * grads[a].dot(&grads[b]);
                }
            }
        }
        LocalSystem { matrix, vector }
    }
}

/// Plane strain on 6-node triangles: ∫BᵀDB by the solver's degree-4 rule.
struct ElasticP2Set<'a> {
    nodes: &'a [[f64; 2]],
    triangles: &'a [[usize; 6]],
    d: nalgebra::Matrix3<f64>,
}

impl Element<12> for ElasticP2Set<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    #[inline]
    fn dofs(&self, e: usize) -> [usize; 12] {
        let t = self.triangles[e];
        std::array::from_fn(|k| 2 * t[k / 2] + k % 2)
    }
    #[inline]
    fn local(&self, e: usize) -> LocalSystem<12> {
        let g = Triangle6::new(self.triangles[e].map(|v| self.nodes[v])).expect("valid element");
        LocalSystem {
            matrix: g.elasticity_stiffness(&self.d, TriangleRule::Degree4),
            vector: SVector::<f64, 12>::zeros(),
        }
    }
}

const SIZES: [usize; 3] = [71, 224, 708];
const P2_SIZES: [usize; 2] = [224, 708];

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
    for n in P2_SIZES {
        let mesh = rectangle_of_order(0.0, 0.0, 1.0, 1.0, n, n, 2).expect("mesh");
        let set = LaplaceP2Set {
            nodes: mesh.nodes(),
            triangles: mesh.triangles6().expect("a P2 mesh"),
            k: 1.0,
            source: 1.0,
        };
        // The kernel integrates: constants have no energy, u = x has k·area.
        let local = set.local(0);
        let x = mesh.triangles6().expect("P2")[0].map(|v| mesh.nodes()[v][0]);
        let u = SVector::<f64, 6>::from(x);
        let area = mesh.areas()[0];
        assert!(local.matrix.row_sum().norm() < 1e-9);
        assert!(((u.transpose() * local.matrix * u)[0] - area).abs() < 1e-9 * area);
        assert!((local.vector.sum() - area).abs() < 1e-12);
        bench_kernel(c, "laplace6x6_p2", mesh.n_nodes(), &set, n);
        let el = ElasticP2Set {
            nodes: mesh.nodes(),
            triangles: mesh.triangles6().expect("a P2 mesh"),
            d: plane_strain_d(207e9, 0.3),
        };
        // rigid translations carry no force
        let k = el.local(0).matrix;
        let tx = SVector::<f64, 12>::from_fn(|i, _| if i % 2 == 0 { 1.0 } else { 0.0 });
        assert!((k * tx).norm() < 1e-6 * k.norm());
        bench_kernel(c, "plane_strain12x12_p2", 2 * mesh.n_nodes(), &el, n);
    }
}

criterion_group!(benches, assembly);
criterion_main!(benches);
