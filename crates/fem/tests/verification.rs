//! Verification of the shared machinery: pattern, assembly, constraints,
//! rigid-mode detection and the faer solvers.
//!
//! References: a dense assembly of the same element matrices; the exact
//! reproduction of a linear field by linear triangles (patch test); dense LU
//! solutions of the same systems.
//!
//! ```text
//!   rectangle meshes, two bodies joined by 4-node "springs":
//!   ┌──────┐┌──────┐
//!   │  A   ││  B   │   interface on x = 1 (separate nodes)
//!   └──────┘└──────┘
//! ```

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, SVector};
use tecon_fem::reference::{ElasticSet, LaplaceSet};
use tecon_fem::triangle::plane_strain_d;
use tecon_fem::{
    AssemblerBuilder, CholeskySolver, Dirichlet, DofMap, Element, FemError, LocalSystem, LuSolver,
    Parallelism, check_rigid_modes, plane_rigid_modes, scalar_mode,
};
use tecon_mesh::{Mesh, rectangle};

fn laplace(mesh: &Mesh, k: f64, source: f64) -> LaplaceSet<'_> {
    LaplaceSet {
        nodes: mesh.nodes(),
        triangles: mesh.triangles(),
        k,
        source,
    }
}

fn elastic(mesh: &Mesh, d: Matrix3<f64>) -> ElasticSet<'_> {
    ElasticSet {
        nodes: mesh.nodes(),
        triangles: mesh.triangles(),
        d,
    }
}

/// Scalar springs between node pairs (a, b): k (u_b − u_a)².
struct Springs {
    pairs: Vec<[usize; 2]>,
    k: f64,
}

impl Element<2> for Springs {
    fn n_elements(&self) -> usize {
        self.pairs.len()
    }
    fn dofs(&self, e: usize) -> [usize; 2] {
        self.pairs[e]
    }
    fn local(&self, _e: usize) -> LocalSystem<2> {
        LocalSystem {
            matrix: SMatrix::<f64, 2, 2>::new(self.k, -self.k, -self.k, self.k),
            vector: SVector::zeros(),
        }
    }
}

fn dense_reference<const N: usize, E: Element<N>>(
    n: usize,
    el: &E,
) -> (DMatrix<f64>, DVector<f64>) {
    let mut a = DMatrix::zeros(n, n);
    let mut f = DVector::zeros(n);
    for e in 0..el.n_elements() {
        let d = el.dofs(e);
        let ls = el.local(e);
        for i in 0..N {
            f[d[i]] += ls.vector[i];
            for j in 0..N {
                a[(d[i], d[j])] += ls.matrix[(i, j)];
            }
        }
    }
    (a, f)
}

#[test]
fn assembly_matches_dense_reference() {
    let mesh = rectangle(0.0, 0.0, 2.0, 1.0, 7, 5).unwrap();
    let lap = laplace(&mesh, 2.5, 3.0);
    let mut b = AssemblerBuilder::new(mesh.n_nodes());
    let id = b.add_elements(&lap);
    let asm = b.build().unwrap();
    let mut a = asm.new_matrix();
    let mut f = vec![0.0; mesh.n_nodes()];
    asm.add(id, &lap, &mut a, Some(&mut f), Parallelism::Rayon)
        .unwrap();
    let (ad, fd) = dense_reference(mesh.n_nodes(), &lap);
    assert!((a.to_dense() - &ad).amax() < 1e-13 * ad.amax());
    assert!((DVector::from_vec(f) - fd).amax() < 1e-14);
    // the pattern holds exactly the pairs of nodes that share a triangle
    let mut structural = std::collections::BTreeSet::new();
    for t in mesh.triangles() {
        for &i in t {
            for &j in t {
                structural.insert((i, j));
            }
        }
    }
    let p = a.pattern();
    let stored: std::collections::BTreeSet<(usize, usize)> = (0..p.n())
        .flat_map(|i| (p.indptr()[i]..p.indptr()[i + 1]).map(move |k| (i, p.indices()[k])))
        .collect();
    assert_eq!(stored, structural);

    let el = elastic(&mesh, plane_strain_d(200e9, 0.3));
    let mut b = AssemblerBuilder::new(2 * mesh.n_nodes());
    let id = b.add_elements(&el);
    let asm = b.build().unwrap();
    let mut k = asm.new_matrix();
    asm.add(id, &el, &mut k, None, Parallelism::Serial).unwrap();
    let (kd, _) = dense_reference(2 * mesh.n_nodes(), &el);
    assert!((k.to_dense() - &kd).amax() < 1e-13 * kd.amax());
    assert!(k.asymmetry() < 1e-15);
}

#[test]
fn assembly_is_bitwise_identical_for_any_thread_count() {
    // large enough for several parallel batches
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 80, 70).unwrap();
    assert!(mesh.n_triangles() > 2 * tecon_fem::assembler::BATCH);
    let el = elastic(&mesh, plane_strain_d(1.0, 0.3));
    let lap = laplace(&mesh, 1.0, 1.0);
    let run = |threads: usize, par: Parallelism| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut b = AssemblerBuilder::new(2 * mesh.n_nodes());
            let id = b.add_elements(&el);
            let asm = b.build().unwrap();
            let mut k = asm.new_matrix();
            asm.add(id, &el, &mut k, None, par).unwrap();
            let mut b = AssemblerBuilder::new(mesh.n_nodes());
            let id = b.add_elements(&lap);
            let asm = b.build().unwrap();
            let mut a = asm.new_matrix();
            let mut f = vec![0.0; mesh.n_nodes()];
            asm.add(id, &lap, &mut a, Some(&mut f), par).unwrap();
            (k.values().to_vec(), a.values().to_vec(), f)
        })
    };
    let reference = run(1, Parallelism::Serial);
    for threads in [1, 2, 3, 4] {
        let r = run(threads, Parallelism::Rayon);
        let same = |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(
            same(&r.0, &reference.0) && same(&r.1, &reference.1) && same(&r.2, &reference.2),
            "threads = {threads}"
        );
    }
}

/// Patch test: u = 1 + 2x − 3y on the boundary, −∇²u = 0 inside: the linear
/// field is reproduced to round-off at every interior node.
///
/// ```text
///   u = 1 + 2x − 3y on all four sides of [0,1.5]×[0,1], 9×6 cells
/// ```
#[test]
fn patch_test_reproduces_a_linear_field() {
    let mut mesh = rectangle(0.0, 0.0, 1.5, 1.0, 9, 6).unwrap();
    // perturb interior nodes to make the patch irregular
    let nodes: Vec<[f64; 2]> = mesh
        .nodes()
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let interior = p[0] > 1e-12 && p[0] < 1.5 - 1e-12 && p[1] > 1e-12 && p[1] < 1.0 - 1e-12;
            if interior {
                let s = ((i * 7919) % 13) as f64 / 13.0 - 0.5;
                [p[0] + 0.05 * s, p[1] - 0.04 * s]
            } else {
                *p
            }
        })
        .collect();
    mesh = Mesh::new(
        nodes,
        mesh.triangles().to_vec(),
        mesh.element_regions().to_vec(),
        mesh.region_names().to_vec(),
    )
    .unwrap();
    let exact = |p: [f64; 2]| 1.0 + 2.0 * p[0] - 3.0 * p[1];
    let lap = laplace(&mesh, 1.0, 0.0);
    let mut b = AssemblerBuilder::new(mesh.n_nodes());
    let id = b.add_elements(&lap);
    let asm = b.build().unwrap();
    let mut a = asm.new_matrix();
    let mut f = vec![0.0; mesh.n_nodes()];
    asm.add(id, &lap, &mut a, Some(&mut f), Parallelism::Rayon)
        .unwrap();
    let mut bc = Dirichlet::new();
    for [p, q] in mesh.boundary_edges() {
        bc.set(p, exact(mesh.nodes()[p]));
        bc.set(q, exact(mesh.nodes()[q]));
    }
    let prepared = bc.prepare(a.pattern()).unwrap();
    prepared.apply(&mut a, &mut f);
    assert!(a.asymmetry() == 0.0, "elimination keeps symmetry");
    let mut solver = CholeskySolver::analyse(a.pattern().clone()).unwrap();
    solver.factorise(&a).unwrap();
    solver.solve(&mut f).unwrap();
    let err = mesh
        .nodes()
        .iter()
        .zip(&f)
        .map(|(p, u)| (u - exact(*p)).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-13, "max error {err:e}");
}

#[test]
fn nonhomogeneous_dirichlet_matches_a_reduced_dense_solve() {
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 4, 3).unwrap();
    let lap = laplace(&mesh, 1.7, 2.0);
    let n = mesh.n_nodes();
    let mut b = AssemblerBuilder::new(n);
    let id = b.add_elements(&lap);
    let asm = b.build().unwrap();
    let mut a = asm.new_matrix();
    let mut f = vec![0.0; n];
    asm.add(id, &lap, &mut a, Some(&mut f), Parallelism::Serial)
        .unwrap();
    let (ad, fd) = dense_reference(n, &lap);
    let fixed: Vec<(usize, f64)> = mesh
        .node_set("left")
        .unwrap()
        .iter()
        .map(|&i| (i, 0.3 + i as f64 * 0.1))
        .collect();
    let mut bc = Dirichlet::new();
    for &(i, g) in &fixed {
        bc.set(i, g);
    }
    bc.prepare(a.pattern()).unwrap().apply(&mut a, &mut f);
    let mut lu = LuSolver::analyse(a.pattern().clone()).unwrap();
    lu.factorise(&a).unwrap();
    lu.solve(&mut f).unwrap();
    // reduced dense solve
    let free: Vec<usize> = (0..n).filter(|i| !bc.contains(*i)).collect();
    let mut g = DVector::zeros(n);
    for &(i, v) in &fixed {
        g[i] = v;
    }
    let rhs = &fd - &ad * &g;
    let aff = DMatrix::from_fn(free.len(), free.len(), |r, c| ad[(free[r], free[c])]);
    let rf = DVector::from_fn(free.len(), |r, _| rhs[free[r]]);
    let uf = aff.lu().solve(&rf).unwrap();
    for (r, &i) in free.iter().enumerate() {
        assert!((f[i] - uf[r]).abs() < 1e-12, "node {i}");
    }
    for &(i, v) in &fixed {
        assert!((f[i] - v).abs() < 1e-14);
    }
}

#[test]
fn lu_solves_a_nonsymmetric_system_and_cholesky_refactorises() {
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 5, 5).unwrap();
    let lap = laplace(&mesh, 1.0, 1.0);
    let n = mesh.n_nodes();
    let mut b = AssemblerBuilder::new(n);
    let id = b.add_elements(&lap);
    let asm = b.build().unwrap();
    let mut a = asm.new_matrix();
    let mut f = vec![0.0; n];
    asm.add(id, &lap, &mut a, Some(&mut f), Parallelism::Serial)
        .unwrap();
    let mut bc = Dirichlet::new();
    for &i in mesh.node_set("bottom").unwrap() {
        bc.set(i, 0.0);
    }
    let bc = bc.prepare(a.pattern()).unwrap();
    bc.apply(&mut a, &mut f);
    // add a convection-like non-symmetric term a_ij += 0.1 (j − i) on stored off-diagonals
    let mut ns = a.clone();
    let p = ns.pattern().clone();
    for i in 0..n {
        for k in p.indptr()[i]..p.indptr()[i + 1] {
            let j = p.indices()[k];
            if i != j && !bc_contains(&mesh, i) && !bc_contains(&mesh, j) {
                ns.values_mut()[k] += 0.05 * (j as f64 - i as f64).signum();
            }
        }
    }
    assert!(ns.asymmetry() > 1e-3);
    let mut x = f.clone();
    let mut lu = LuSolver::analyse(p.clone()).unwrap();
    lu.factorise(&ns).unwrap();
    lu.solve(&mut x).unwrap();
    let dense = ns
        .to_dense()
        .lu()
        .solve(&DVector::from_vec(f.clone()))
        .unwrap();
    assert!((DVector::from_vec(x.clone()) - dense).amax() < 1e-12);
    assert!(tecon_fem::relative_residual(&ns, &x, &f) < 1e-13);
    // Cholesky: symbolic once, two numeric factorisations with scaled values
    let mut ch = CholeskySolver::analyse(p).unwrap();
    let mut y = f.clone();
    ch.factorise(&a).unwrap();
    ch.solve(&mut y).unwrap();
    for v in a.values_mut() {
        *v *= 2.0;
    }
    let mut z = f.clone();
    ch.factorise(&a).unwrap();
    ch.solve(&mut z).unwrap();
    for (y, z) in y.iter().zip(&z) {
        assert!((y - 2.0 * z).abs() < 1e-12 * y.abs().max(1e-12));
    }
}

fn bc_contains(mesh: &Mesh, i: usize) -> bool {
    mesh.node_set("bottom").unwrap().contains(&i)
}

fn two_blocks() -> Mesh {
    let a = rectangle(0.0, 0.0, 1.0, 1.0, 3, 3).unwrap();
    let mut nodes = a.nodes().to_vec();
    let off = nodes.len();
    nodes.extend(a.nodes().iter().map(|p| [p[0] + 1.0, p[1]]));
    let mut tris = a.triangles().to_vec();
    tris.extend(a.triangles().iter().map(|t| t.map(|v| v + off)));
    let regions: Vec<usize> = (0..tris.len())
        .map(|e| usize::from(e >= a.n_triangles()))
        .collect();
    Mesh::new(nodes, tris, regions, vec!["A".into(), "B".into()]).unwrap()
}

#[test]
fn free_body_is_named() {
    let mesh = two_blocks();
    let dm = DofMap::new(mesh.n_nodes(), 2);
    let el = elastic(&mesh, plane_strain_d(1.0, 0.25));
    let mut b = AssemblerBuilder::new(dm.n_dofs());
    let id = b.add_elements(&el);
    let asm = b.build().unwrap();
    let modes: Vec<_> = mesh
        .bodies()
        .iter()
        .flat_map(|body| plane_rigid_modes(&dm, &body.name, &body.nodes, mesh.nodes()))
        .collect();
    let assemble = |bc: &Dirichlet| {
        let mut k = asm.new_matrix();
        let mut f = vec![0.0; dm.n_dofs()];
        asm.add(id, &el, &mut k, Some(&mut f), Parallelism::Serial)
            .unwrap();
        bc.prepare(k.pattern()).unwrap().apply(&mut k, &mut f);
        k
    };
    // body A clamped on its left side, body B fully free
    let mut bc = Dirichlet::new();
    for &i in mesh.bodies()[0]
        .nodes
        .iter()
        .filter(|&&i| mesh.nodes()[i][0] == 0.0)
    {
        bc.set(dm.dof(i, 0), 0.0);
        bc.set(dm.dof(i, 1), 0.0);
    }
    let e = check_rigid_modes(&assemble(&bc), &modes).unwrap_err();
    match &e {
        FemError::Unconstrained { bodies, .. } => assert_eq!(bodies, &["B".to_string()]),
        other => panic!("{other}"),
    }
    assert!(e.to_string().contains("body 'B'"), "{e}");
    // B held only in y along its bottom: x-translation remains free
    for &i in mesh.bodies()[1]
        .nodes
        .iter()
        .filter(|&&i| mesh.nodes()[i][1] == 0.0)
    {
        bc.set(dm.dof(i, 1), 0.0);
    }
    let e = check_rigid_modes(&assemble(&bc), &modes).unwrap_err();
    match &e {
        FemError::Unconstrained { bodies, modes, .. } => {
            assert_eq!(bodies, &["B".to_string()]);
            assert_eq!(modes, &["x-translation".to_string()]);
        }
        other => panic!("{other}"),
    }
    // fix one x dof of B: no free mode left, and Cholesky succeeds
    let corner = mesh.bodies()[1]
        .nodes
        .iter()
        .copied()
        .find(|&i| mesh.nodes()[i] == [2.0, 0.0])
        .unwrap();
    bc.set(dm.dof(corner, 0), 0.0);
    let k = assemble(&bc);
    check_rigid_modes(&k, &modes).unwrap();
    let mut ch = CholeskySolver::analyse(k.pattern().clone()).unwrap();
    ch.factorise(&k).unwrap();
}

#[test]
fn bodies_free_together_are_named_together() {
    // two scalar bodies joined by springs, nothing anchored: the common constant is free
    let mesh = two_blocks();
    let lap = laplace(&mesh, 1.0, 0.0);
    let pairs: Vec<[usize; 2]> = (0..mesh.n_nodes())
        .filter(|&i| mesh.nodes()[i][0] == 1.0 && mesh.node_bodies()[i] == 0)
        .map(|i| {
            let j = (0..mesh.n_nodes())
                .find(|&j| j != i && mesh.nodes()[j] == mesh.nodes()[i])
                .unwrap();
            [i, j]
        })
        .collect();
    let springs = Springs { pairs, k: 10.0 };
    let dm = DofMap::new(mesh.n_nodes(), 1);
    let mut b = AssemblerBuilder::new(mesh.n_nodes());
    let i1 = b.add_elements(&lap);
    let i2 = b.add_elements(&springs);
    let asm = b.build().unwrap();
    let mut a = asm.new_matrix();
    asm.add(i1, &lap, &mut a, None, Parallelism::Serial)
        .unwrap();
    asm.add(i2, &springs, &mut a, None, Parallelism::Serial)
        .unwrap();
    let modes: Vec<_> = mesh
        .bodies()
        .iter()
        .map(|b| scalar_mode(&dm, &b.name, &b.nodes, "uniform temperature"))
        .collect();
    let e = check_rigid_modes(&a, &modes).unwrap_err();
    match &e {
        FemError::Unconstrained { bodies, .. } => {
            assert_eq!(bodies, &["A".to_string(), "B".to_string()])
        }
        other => panic!("{other}"),
    }
    // the singular matrix is also caught by the factorisation itself
    let mut ch = CholeskySolver::analyse(a.pattern().clone()).unwrap();
    assert!(matches!(
        ch.factorise(&a),
        Err(FemError::NotPositiveDefinite { .. })
    ));
    // without the springs each body is free on its own: the error names one body
    let mut a2 = asm.new_matrix();
    asm.add(i1, &lap, &mut a2, None, Parallelism::Serial)
        .unwrap();
    let mut f = vec![0.0; mesh.n_nodes()];
    let mut bc = Dirichlet::new();
    bc.set(0, 1.0);
    bc.prepare(a2.pattern()).unwrap().apply(&mut a2, &mut f);
    let e = check_rigid_modes(&a2, &modes).unwrap_err();
    assert!(
        e.to_string().contains("body 'B' (uniform temperature)"),
        "{e}"
    );
}

#[test]
fn error_paths() {
    let mut b = AssemblerBuilder::new(3);
    b.add_block(2, vec![0, 5]);
    assert!(matches!(
        b.build(),
        Err(FemError::DofOutOfRange { dof: 5, .. })
    ));
    let mut b = AssemblerBuilder::new(3);
    b.add_block(2, vec![0, 1, 2]);
    assert!(matches!(b.build(), Err(FemError::LengthMismatch { .. })));
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 2, 2).unwrap();
    let lap = laplace(&mesh, 1.0, 0.0);
    let mut b = AssemblerBuilder::new(mesh.n_nodes());
    let id = b.add_elements(&lap);
    let asm = b.build().unwrap();
    let mut a = asm.new_matrix();
    let mut short = vec![0.0; 2];
    assert!(matches!(
        asm.add(id, &lap, &mut a, Some(&mut short), Parallelism::Serial),
        Err(FemError::LengthMismatch { .. })
    ));
    let mut bc = Dirichlet::new();
    bc.set(99, 0.0);
    assert!(matches!(
        bc.prepare(a.pattern()),
        Err(FemError::DofOutOfRange { dof: 99, .. })
    ));
    let mut bc = Dirichlet::new();
    bc.set(0, f64::NAN);
    assert!(matches!(
        bc.prepare(a.pattern()),
        Err(FemError::NonFinite { .. })
    ));
    let ch = CholeskySolver::analyse(a.pattern().clone()).unwrap();
    let mut x = vec![0.0; mesh.n_nodes()];
    assert!(matches!(ch.solve(&mut x), Err(FemError::NotFactorised)));
    // a zero matrix is not positive definite
    let mut ch = CholeskySolver::analyse(a.pattern().clone()).unwrap();
    assert!(matches!(
        ch.factorise(&a),
        Err(FemError::NotPositiveDefinite { .. })
    ));
    // LU on a singular matrix is reported, never returned as numbers
    let mut lu = LuSolver::analyse(a.pattern().clone()).unwrap();
    let r = lu.factorise(&a).and_then(|_| lu.solve(&mut x));
    assert!(r.is_err(), "LU of the zero matrix must fail");
}

#[test]
fn factorisation_and_solve_are_bitwise_identical_for_any_thread_count() {
    // big enough for faer to choose the supernodal (parallel) path
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 90, 90).unwrap();
    let dm = DofMap::new(mesh.n_nodes(), 2);
    let el = elastic(&mesh, plane_strain_d(1.0, 0.3));
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut b = AssemblerBuilder::new(dm.n_dofs());
            let id = b.add_elements(&el);
            let asm = b.build().unwrap();
            let mut k = asm.new_matrix();
            let mut f: Vec<f64> = (0..dm.n_dofs())
                .map(|i| ((i * 37) % 11) as f64 - 5.0)
                .collect();
            asm.add(id, &el, &mut k, None, Parallelism::Rayon).unwrap();
            let mut bc = Dirichlet::new();
            for &i in mesh.node_set("left").unwrap() {
                bc.set(dm.dof(i, 0), 0.0);
                bc.set(dm.dof(i, 1), 0.0);
            }
            bc.prepare(k.pattern()).unwrap().apply(&mut k, &mut f);
            let mut ch = CholeskySolver::analyse(k.pattern().clone()).unwrap();
            ch.factorise(&k).unwrap();
            let mut x = f.clone();
            ch.solve(&mut x).unwrap();
            let mut lu = LuSolver::analyse(k.pattern().clone()).unwrap();
            lu.factorise(&k).unwrap();
            let mut y = f.clone();
            lu.solve(&mut y).unwrap();
            (x, y)
        })
    };
    let (x1, y1) = run(1);
    for t in [2, 3] {
        let (x, y) = run(t);
        assert!(
            x.iter().zip(&x1).all(|(a, b)| a.to_bits() == b.to_bits()),
            "Cholesky, {t} threads"
        );
        assert!(
            y.iter().zip(&y1).all(|(a, b)| a.to_bits() == b.to_bits()),
            "LU, {t} threads"
        );
    }
}

#[test]
fn shared_symbolic_analysis_factorises_two_matrices() {
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 6, 6).unwrap();
    let lap = laplace(&mesh, 1.0, 1.0);
    let mut b = AssemblerBuilder::new(mesh.n_nodes());
    let id = b.add_elements(&lap);
    let asm = b.build().unwrap();
    let mut a = asm.new_matrix();
    let mut f = vec![0.0; mesh.n_nodes()];
    asm.add(id, &lap, &mut a, Some(&mut f), Parallelism::Serial)
        .unwrap();
    let mut bc = Dirichlet::new();
    bc.set(0, 0.0);
    bc.prepare(a.pattern()).unwrap().apply(&mut a, &mut f);
    let mut a2 = a.clone();
    for v in a2.values_mut() {
        *v *= 4.0;
    }
    let mut s1 = CholeskySolver::analyse(a.pattern().clone()).unwrap();
    let mut s2 = s1.share_symbolic();
    s1.factorise(&a).unwrap();
    s2.factorise(&a2).unwrap();
    let (mut x1, mut x2) = (f.clone(), f.clone());
    s1.solve(&mut x1).unwrap();
    s2.solve(&mut x2).unwrap();
    for (p, q) in x1.iter().zip(&x2) {
        assert!((p - 4.0 * q).abs() < 1e-12 * p.abs().max(1e-12));
    }
}

/// A deliberately expensive kernel, so the assembler takes its pipelined
/// path (kernels in parallel, scatter in element order).
struct Expensive<'a>(LaplaceSet<'a>);

impl Element<3> for Expensive<'_> {
    fn n_elements(&self) -> usize {
        self.0.n_elements()
    }
    fn dofs(&self, e: usize) -> [usize; 3] {
        self.0.dofs(e)
    }
    fn local(&self, e: usize) -> LocalSystem<3> {
        let mut ls = self.0.local(e);
        // about a microsecond of deterministic work per element
        let mut x = e as f64 * 1e-3;
        for _ in 0..400 {
            x = (x + 0.5).sin();
        }
        ls.matrix *= 1.0 + 1e-3 * x;
        ls
    }
}

#[test]
fn pipelined_assembly_is_bitwise_identical_for_any_thread_count() {
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, 60, 60).unwrap();
    let set = Expensive(laplace(&mesh, 1.0, 1.0));
    let run = |threads: usize, par: Parallelism| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut b = AssemblerBuilder::new(mesh.n_nodes());
            let id = b.add_elements(&set);
            let asm = b.build().unwrap();
            let mut a = asm.new_matrix();
            let mut f = vec![0.0; mesh.n_nodes()];
            asm.add(id, &set, &mut a, Some(&mut f), par).unwrap();
            (a.values().to_vec(), f)
        })
    };
    let reference = run(1, Parallelism::Serial);
    for threads in [2, 3] {
        let r = run(threads, Parallelism::Rayon);
        assert!(
            r.0.iter()
                .zip(&reference.0)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{threads} threads"
        );
        assert!(
            r.1.iter()
                .zip(&reference.1)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{threads} threads"
        );
    }
}
