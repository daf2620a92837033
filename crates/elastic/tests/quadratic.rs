//! Verification of the quadratic (P2) elastic kernels on curved 6-node
//! triangles.
//!
//! Run: `cargo test -p tecon-elastic --test quadratic -- --nocapture`
//!
//! 1. Lamé thick cylinder (plane strain, internal pressure), quarter
//!    annulus with curved (isoparametric) boundaries, symmetry on both
//!    cut planes:
//!
//!    ```text
//!      θ = π/2: u_x = 0 ┆╲___
//!                       ┆    ╲__     r_o = 2: free
//!      r_i = 1: p = 100 ╲       ╲
//!      MPa               ╲       │
//!                         ╰──────┘  θ = 0: u_y = 0
//!    ```
//!    Goal: displacement error O(h³) in L2 and O(h²) in energy (slopes
//!    fitted and asserted within 0.2; measured 3.09 and 1.95).
//! 2. Thermal patch test: a free square with a temperature change linear in
//!    x and y. Its thermal strain is compatible, so the exact solution is
//!    stress free; with ΔT interpolated from the nodes to the integration
//!    points P2 reproduces it to round-off (a kernel that used the element
//!    mean ΔT would not). Plane strain, plane stress and generalised plane
//!    strain.

use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};
use tecon_elastic::analytical::LameCylinder;
use tecon_elastic::recovery::{PointStress, spr_recovery, zz_indicator};
use tecon_elastic::{
    Analysis, Material, P2_RULE, gps_triangle6, plane_triangle6, plane_triangle6_load,
    triangle6_stresses,
};
use tecon_fem::edge3::Edge3;
use tecon_fem::quadrature::TriangleRule;
use tecon_fem::triangle6::{Triangle6, Vector12, shape};
use tecon_fem::{AssemblerBuilder, CholeskySolver, Dirichlet, Element, LocalSystem, Parallelism};

const R_I: f64 = 1.0;
const R_O: f64 = 2.0;
const P: f64 = 100.0e6;

fn steel() -> Material {
    Material {
        youngs_modulus: 207.0e9,
        poisson_ratio: 0.3,
        expansion: 12.51e-6,
    }
}

struct P2Mesh {
    nodes: Vec<[f64; 2]>,
    triangles: Vec<[usize; 6]>,
    /// (i, j) grid index of every node.
    grid: Vec<(usize, usize)>,
    gr: usize,
    gt: usize,
}

/// Polar image of a uniform grid: r ∈ [R_I, R_O], θ ∈ [0, π/2].
fn quarter_annulus(nr: usize, nt: usize) -> P2Mesh {
    let (gr, gt) = (2 * nr + 1, 2 * nt + 1);
    let id = |i: usize, j: usize| i * gt + j;
    let mut nodes = Vec::new();
    let mut grid = Vec::new();
    for i in 0..gr {
        let r = R_I + (R_O - R_I) * i as f64 / (gr - 1) as f64;
        for j in 0..gt {
            let t = std::f64::consts::FRAC_PI_2 * j as f64 / (gt - 1) as f64;
            nodes.push([r * t.cos(), r * t.sin()]);
            grid.push((i, j));
        }
    }
    let mut triangles = Vec::new();
    for a in 0..nr {
        for b in 0..nt {
            let (i, j) = (2 * a, 2 * b);
            triangles.push([
                id(i, j),
                id(i + 2, j),
                id(i + 2, j + 2),
                id(i + 1, j),
                id(i + 2, j + 1),
                id(i + 1, j + 1),
            ]);
            triangles.push([
                id(i, j),
                id(i + 2, j + 2),
                id(i, j + 2),
                id(i + 1, j + 1),
                id(i + 1, j + 2),
                id(i, j + 1),
            ]);
        }
    }
    P2Mesh {
        nodes,
        triangles,
        grid,
        gr,
        gt,
    }
}

/// Plane P2 elements with one D and nodal ΔT per element.
struct Plane6<'a> {
    geometry: &'a [Triangle6],
    triangles: &'a [[usize; 6]],
    d: Matrix3<f64>,
    expansion: f64,
    delta_t: &'a [[f64; 6]],
}

impl Element<12> for Plane6<'_> {
    fn n_elements(&self) -> usize {
        self.triangles.len()
    }
    fn dofs(&self, e: usize) -> [usize; 12] {
        let t = self.triangles[e];
        std::array::from_fn(|k| 2 * t[k / 2] + k % 2)
    }
    fn local(&self, e: usize) -> LocalSystem<12> {
        let (matrix, vector) =
            plane_triangle6(&self.geometry[e], &self.d, self.expansion, &self.delta_t[e]);
        LocalSystem { matrix, vector }
    }
}

fn solve(
    n_dofs: usize,
    set: &Plane6<'_>,
    extra_load: &[(usize, f64)],
    fixed: &Dirichlet,
) -> Vec<f64> {
    let mut builder = AssemblerBuilder::new(n_dofs);
    let id = builder.add_elements(set);
    let asm = builder.build().unwrap();
    let mut k = asm.new_matrix();
    let mut f = vec![0.0; n_dofs];
    asm.add(id, set, &mut k, Some(&mut f), Parallelism::Rayon)
        .unwrap();
    for &(dof, v) in extra_load {
        f[dof] += v;
    }
    fixed.prepare(asm.pattern()).unwrap().apply(&mut k, &mut f);
    let mut solver = CholeskySolver::analyse(Arc::clone(asm.pattern())).unwrap();
    solver.factorise(&k).unwrap();
    solver.solve(&mut f).unwrap();
    f
}

fn fitted_slope(h: &[f64], e: &[f64]) -> f64 {
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// Errors of one Lamé solve.
struct LameErrors {
    /// L2 error of u (m).
    l2: f64,
    /// Energy-norm error (√J per m).
    energy: f64,
    /// L2 error of the in-plane stresses at the integration points (Pa·m).
    stress_raw: f64,
    /// L2 error of the SPR-recovered stresses (Pa·m).
    stress_spr: f64,
    /// ZZ estimate of the energy-norm error.
    zz: f64,
}

/// Solves the Lamé cylinder on `mesh` and measures its errors.
fn lame_errors(mesh: &P2Mesh) -> LameErrors {
    let m = steel();
    let analysis = Analysis::PlaneStrain;
    let d = analysis.d(&m);
    let exact = LameCylinder {
        a: R_I,
        b: R_O,
        p: P,
        e: m.youngs_modulus,
        nu: m.poisson_ratio,
    };
    let geometry: Vec<Triangle6> = mesh
        .triangles
        .iter()
        .map(|t| Triangle6::new(t.map(|a| mesh.nodes[a])).unwrap())
        .collect();
    let zero = vec![[0.0; 6]; mesh.triangles.len()];
    let set = Plane6 {
        geometry: &geometry,
        triangles: &mesh.triangles,
        d,
        expansion: 0.0,
        delta_t: &zero,
    };
    let n = mesh.nodes.len();
    let id = |i: usize, j: usize| i * mesh.gt + j;
    // Pressure on the inner arc: traction p e_r = −p n (n the left normal
    // of the edge walked in +θ, i.e. pointing out of the body), 3-point Gauss.
    let mut load = Vec::new();
    for b in 0..(mesh.gt - 1) / 2 {
        let nodes = [id(0, 2 * b), id(0, 2 * b + 2), id(0, 2 * b + 1)];
        let edge = Edge3::new(nodes.map(|a| mesh.nodes[a])).unwrap();
        for p in edge.gauss_points(tecon_fem::quadrature::GaussLegendre::Three) {
            for (k, &a) in nodes.iter().enumerate() {
                load.push((2 * a, -P * p.normal.x * p.shape[k] * p.weight));
                load.push((2 * a + 1, -P * p.normal.y * p.shape[k] * p.weight));
            }
        }
    }
    let mut fixed = Dirichlet::new();
    for (a, &(_, j)) in mesh.grid.iter().enumerate() {
        if j == 0 {
            fixed.set(2 * a + 1, 0.0);
        }
        if j == mesh.gt - 1 {
            fixed.set(2 * a, 0.0);
        }
    }
    let u = solve(2 * n, &set, &load, &fixed);
    let (mut l2, mut energy) = (0.0, 0.0);
    for (g, t) in geometry.iter().zip(&mesh.triangles) {
        let ue = Vector12::from_fn(|k, _| u[2 * t[k / 2] + k % 2]);
        for q in g.points(TriangleRule::Degree5) {
            let x = g.position(q.xi);
            let r = x[0].hypot(x[1]);
            let (c, s) = (x[0] / r, x[1] / r);
            let ur = exact.u_r(r);
            let uh = [
                (0..6).map(|a| q.shape[a] * ue[2 * a]).sum::<f64>(),
                (0..6).map(|a| q.shape[a] * ue[2 * a + 1]).sum::<f64>(),
            ];
            l2 += q.weight * ((uh[0] - ur * c).powi(2) + (uh[1] - ur * s).powi(2));
            // Exact strain: ε_rr = u', ε_θθ = u/r, rotated to x, y.
            let h = 1e-6 * r;
            let err_ = (exact.u_r(r + h) - exact.u_r(r - h)) / (2.0 * h);
            let ett = ur / r;
            let ex = Vector3::new(
                err_ * c * c + ett * s * s,
                err_ * s * s + ett * c * c,
                2.0 * (err_ - ett) * s * c,
            );
            let eh = q.strain_matrix() * ue;
            let de = eh - ex;
            energy += q.weight * (de.transpose() * d * de)[0];
        }
    }
    let _ = mesh.gr;
    // Stresses at the integration points, SPR per group (two groups split
    // at θ = π/4, so the recovery must work without crossing them), ZZ.
    let points: Vec<Vec<PointStress>> = geometry
        .iter()
        .zip(&mesh.triangles)
        .map(|(g, t)| {
            let ue = Vector12::from_fn(|k, _| u[2 * t[k / 2] + k % 2]);
            triangle6_stresses(g, analysis, &m, &ue, 0.0, &[0.0; 6])
                .iter()
                .map(|(s, p)| PointStress {
                    x: g.position(p.xi),
                    weight: p.weight,
                    stress: *s,
                })
                .collect()
        })
        .collect();
    let groups: Vec<usize> = mesh
        .triangles
        .iter()
        .map(|t| {
            let c = mesh.nodes[t[4]];
            usize::from(c[1] > c[0])
        })
        .collect();
    let recovered = spr_recovery(&mesh.nodes, &mesh.triangles, &groups, &points);
    let compliance = vec![d.try_inverse().unwrap(); geometry.len()];
    let eta = zz_indicator(&geometry, &compliance, &points, &recovered);
    let (mut raw, mut spr) = (0.0, 0.0);
    for (e, g) in geometry.iter().enumerate() {
        for (q, p) in g.points(P2_RULE).enumerate() {
            let x = g.position(p.xi);
            let r = x[0].hypot(x[1]);
            let (c, s) = (x[0] / r, x[1] / r);
            let (srr, stt) = (exact.sigma_rr(r), exact.sigma_tt(r));
            let ex = [
                srr * c * c + stt * s * s,
                srr * s * s + stt * c * c,
                (srr - stt) * s * c,
            ];
            let n = shape(p.xi);
            for k in 0..3 {
                let star: f64 = (0..6).map(|a| n[a] * recovered[e][a][k]).sum();
                raw += p.weight * (points[e][q].stress[k] - ex[k]).powi(2);
                spr += p.weight * (star - ex[k]).powi(2);
            }
        }
    }
    LameErrors {
        l2: l2.sqrt(),
        energy: energy.sqrt(),
        stress_raw: raw.sqrt(),
        stress_spr: spr.sqrt(),
        zz: eta.iter().map(|v| v * v).sum::<f64>().sqrt(),
    }
}

#[test]
fn p2_lame_cylinder_converges_at_order_3_in_l2_and_2_in_energy() {
    let (mut hs, mut l2s, mut ens) = (Vec::new(), Vec::new(), Vec::new());
    println!(
        "  n_r  elements     L2 error u (m)   energy error   stress raw   stress SPR   ZZ / energy"
    );
    let (mut raws, mut sprs, mut eff) = (Vec::new(), Vec::new(), Vec::new());
    // n_θ = 4 n_r: elements of aspect ≈ 1 at the bore. The coarsest
    // meshes converge faster than h³ (local rates 3.2–3.4 from n_r = 2 with
    // n_θ = 2 n_r, measured): the level n_r = 2 is left out and the rates
    // 3.19, 3.08, 3.02 of the levels kept approach 3.
    for nr in [4usize, 8, 16, 32] {
        let mesh = quarter_annulus(nr, 4 * nr);
        let LameErrors {
            l2,
            energy: en,
            stress_raw,
            stress_spr,
            zz,
        } = lame_errors(&mesh);
        println!(
            "{nr:5} {:9} {l2:16.6e} {en:14.6e} {stress_raw:12.4e} {stress_spr:12.4e} {:13.3}",
            mesh.triangles.len(),
            zz / en
        );
        raws.push(stress_raw);
        sprs.push(stress_spr);
        eff.push(zz / en);
        hs.push(1.0 / nr as f64);
        l2s.push(l2);
        ens.push(en);
    }
    let (p_l2, p_en) = (fitted_slope(&hs, &l2s), fitted_slope(&hs, &ens));
    let (p_raw, p_spr) = (fitted_slope(&hs, &raws), fitted_slope(&hs, &sprs));
    println!(
        "fitted orders: L2 {p_l2:.3}, energy {p_en:.3}, stress raw {p_raw:.3}, stress SPR {p_spr:.3}"
    );
    // Raw stresses converge as h². SPR (quadratic fits of the degree-4
    // points, boundary patches included) measured 2.33: faster than raw,
    // not the interior h³; the recovered error is 3.9× smaller on the finest
    // mesh. The ZZ estimate is asymptotically exact: effectivity 0.77, 0.84,
    // 0.91, 0.95, its distance to 1 falling at every refinement.
    assert!((p_raw - 2.0).abs() < 0.2, "raw stress order {p_raw}");
    assert!(p_spr > p_raw + 0.2, "SPR order {p_spr} vs raw {p_raw}");
    let last = eff.len() - 1;
    assert!(
        sprs[last] < 0.3 * raws[last],
        "SPR {} vs raw {}",
        sprs[last],
        raws[last]
    );
    for w in eff.windows(2) {
        assert!(
            (1.0 - w[1]).abs() < (1.0 - w[0]).abs(),
            "effectivities {eff:?}"
        );
    }
    assert!((eff[last] - 1.0).abs() < 0.1, "ZZ effectivity {eff:?}");
    assert!((p_l2 - 3.0).abs() < 0.2, "L2 order {p_l2}");
    assert!((p_en - 2.0).abs() < 0.2, "energy order {p_en}");
    // The solve is the right problem: the finest L2 error is below 1e-6 of
    // the bore displacement times the domain size.
    let ub = LameCylinder {
        a: R_I,
        b: R_O,
        p: P,
        e: steel().youngs_modulus,
        nu: steel().poisson_ratio,
    }
    .u_r(R_I);
    assert!(
        l2s[3] < 1e-5 * ub,
        "finest L2 error {} vs u_r(a) {ub}",
        l2s[3]
    );
}

/// Square [0, 1]² of 2·n² straight 6-node triangles.
fn square(n: usize) -> (Vec<[f64; 2]>, Vec<[usize; 6]>) {
    let g = 2 * n + 1;
    let id = |i: usize, j: usize| j * g + i;
    let nodes = (0..g * g)
        .map(|k| {
            [
                (k % g) as f64 / (g - 1) as f64,
                (k / g) as f64 / (g - 1) as f64,
            ]
        })
        .collect();
    let mut tris = Vec::new();
    for a in 0..n {
        for b in 0..n {
            let (i, j) = (2 * a, 2 * b);
            tris.push([
                id(i, j),
                id(i + 2, j),
                id(i + 2, j + 2),
                id(i + 1, j),
                id(i + 2, j + 1),
                id(i + 1, j + 1),
            ]);
            tris.push([
                id(i, j),
                id(i + 2, j + 2),
                id(i, j + 2),
                id(i + 1, j + 1),
                id(i + 1, j + 2),
                id(i, j + 1),
            ]);
        }
    }
    (nodes, tris)
}

#[test]
fn linear_temperature_on_a_free_body_is_stress_free() {
    let m = steel();
    let (nodes, tris) = square(3);
    let geometry: Vec<Triangle6> = tris
        .iter()
        .map(|t| Triangle6::new(t.map(|a| nodes[a])).unwrap())
        .collect();
    // ΔT = 50 + 300 x − 200 y (K), reference per element: 0.
    let dt = |p: [f64; 2]| 50.0 + 300.0 * p[0] - 200.0 * p[1];
    let delta_t: Vec<[f64; 6]> = tris.iter().map(|t| t.map(|a| dt(nodes[a]))).collect();
    let n = nodes.len();
    // Minimal support: node 0 fixed, node at (1, 0) fixed in y.
    let right = 2 * 3;
    let mut fixed = Dirichlet::new();
    fixed.set(0, 0.0);
    fixed.set(1, 0.0);
    fixed.set(2 * right + 1, 0.0);
    for analysis in [Analysis::PlaneStrain, Analysis::PlaneStress] {
        let set = Plane6 {
            geometry: &geometry,
            triangles: &tris,
            d: analysis.d(&m),
            expansion: analysis.in_plane_expansion(&m),
            delta_t: &delta_t,
        };
        let u = solve(2 * n, &set, &[], &fixed);
        let scale = m.youngs_modulus * m.expansion * 350.0;
        let mut worst: f64 = 0.0;
        for (e, t) in tris.iter().enumerate() {
            let ue = Vector12::from_fn(|k, _| u[2 * t[k / 2] + k % 2]);
            for (s, _) in triangle6_stresses(&geometry[e], analysis, &m, &ue, 0.0, &delta_t[e]) {
                worst = worst.max(s[0].abs()).max(s[1].abs()).max(s[2].abs());
                if analysis == Analysis::PlaneStress {
                    assert_eq!(s[3], 0.0);
                }
            }
        }
        println!(
            "{analysis:?}: largest in-plane stress / (E α ΔT) = {:.2e}",
            worst / scale
        );
        assert!(worst < 1e-9 * scale, "{analysis:?}: {worst} Pa");
        // Element-mean ΔT would not be stress free: the control.
        let mean: Vec<[f64; 6]> = delta_t
            .iter()
            .map(|v| [v.iter().sum::<f64>() / 6.0; 6])
            .collect();
        let set_mean = Plane6 {
            delta_t: &mean,
            ..set
        };
        let um = solve(2 * n, &set_mean, &[], &fixed);
        let mut worst_mean: f64 = 0.0;
        for (e, t) in tris.iter().enumerate() {
            let ue = Vector12::from_fn(|k, _| um[2 * t[k / 2] + k % 2]);
            for (s, _) in triangle6_stresses(&geometry[e], analysis, &m, &ue, 0.0, &mean[e]) {
                worst_mean = worst_mean.max(s[0].abs()).max(s[1].abs());
            }
        }
        assert!(worst_mean > 1e-3 * scale, "control: {worst_mean}");
    }
}

#[test]
fn gps_triangle6_is_consistent_with_plane_kernel_and_free_thermal_expansion() {
    // One straight element; a uniform ΔT with u = α ΔT x (in plane) and
    // ε_zz = α ΔT is the free expansion: zero residual K u − f.
    let m = steel();
    let x = [
        [0.0, 0.0],
        [0.3, 0.05],
        [0.1, 0.4],
        [0.15, 0.025],
        [0.2, 0.225],
        [0.05, 0.2],
    ];
    let g = Triangle6::new(x).unwrap();
    let dt = [80.0; 6];
    let (k, f) = gps_triangle6(&g, &m, &dt);
    let a = m.expansion * 80.0;
    let mut u = nalgebra::SVector::<f64, 13>::zeros();
    for (n, p) in x.iter().enumerate() {
        u[2 * n] = a * p[0];
        u[2 * n + 1] = a * p[1];
    }
    u[12] = a;
    let r = k * u - f;
    assert!(r.amax() < 1e-9 * f.amax(), "{}", r.amax());
    // The in-plane block is the plane-strain-modulus stiffness.
    let (k12, _) = plane_triangle6(&g, &Analysis::GeneralisedPlaneStrain.d(&m), 0.0, &dt);
    assert!((k.fixed_view::<12, 12>(0, 0) - k12).amax() < 1e-12 * k12.amax());
    let s = triangle6_stresses(
        &g,
        Analysis::GeneralisedPlaneStrain,
        &m,
        &u.fixed_rows::<12>(0).into_owned(),
        a,
        &dt,
    );
    for (s, _) in s {
        assert!(s.iter().all(|v| v.abs() < 1e-3), "{s:?}");
    }
}

#[test]
fn the_load_only_kernel_equals_the_thermal_load_of_the_full_one() {
    // a curved element (mid-side nodes off the chords) and a ΔT that
    // varies quadratically: the load alone, as the contact solves of a
    // two-way run recompute it, equals the full kernel's vector
    let m = steel();
    let x = [
        [0.0, 0.0],
        [0.3, 0.05],
        [0.1, 0.4],
        [0.16, 0.01],
        [0.21, 0.24],
        [0.04, 0.21],
    ];
    let g = Triangle6::new(x).unwrap();
    let dt = [80.0, -20.0, 310.0, 5.5, 140.0, -75.0];
    for analysis in [Analysis::PlaneStrain, Analysis::PlaneStress] {
        let d = analysis.d(&m);
        let alpha = analysis.in_plane_expansion(&m);
        let (_, f) = plane_triangle6(&g, &d, alpha, &dt);
        let f_load = plane_triangle6_load(&g, &d, alpha, &dt);
        assert!(
            (f - f_load).amax() <= 1e-14 * f.amax(),
            "{:?}: {}",
            analysis,
            (f - f_load).amax() / f.amax()
        );
    }
}
