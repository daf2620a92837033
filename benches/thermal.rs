//! Transient heat conduction on 10⁵ nodes: the cost of a time step against
//! its two ingredients (one pair of triangular solves, one sparse mat-vec).
//!
//! ```text
//! cargo bench -p tecon --bench thermal
//! ```
//!
//! Mesh: the unit square, 315 × 315 cells (99 856 nodes, 198 450 linear
//! triangles), steel (k = 63.9, ρ = 7832, c = 434), convection h = 10.25 to
//! 21 °C on all four sides, a hot square (1132 °C) in one corner, backward
//! Euler with Δt = 1 s.
//!
//! Printed first (own timing, medians): the whole run of 1000 steps of one
//! Δt through `ThermalModel::solve_transient` (one factorisation), then a
//! step after the first, a bare solve with the same factorisation, a bare
//! mat-vec with K, and the ratio step / (solve + mat-vec). Then criterion
//! measures the same three pieces.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use criterion::Criterion;
use tecon::fem::CholeskySolver;
use tecon::mesh::rectangle;
use tecon::thermal::{EdgeBc, Material, ThermalModel, ThetaScheme, TimeSchedule};

const CELLS: usize = 315;
const DT: f64 = 1.0;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn minimum(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Seconds per call of `f`, averaged over `inner` calls.
fn time_once(inner: usize, f: &mut impl FnMut()) -> f64 {
    let t = Instant::now();
    for _ in 0..inner {
        f();
    }
    t.elapsed().as_secs_f64() / inner as f64
}

fn main() {
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0, CELLS, CELLS).expect("mesh");
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .expect("material");
    for side in ["left", "right", "bottom", "top"] {
        model
            .add_edge_bc(side, EdgeBc::convection(10.25, 21.0))
            .expect("bc");
    }
    model.set_initial_default(21.0).expect("initial");
    for (i, p) in mesh.nodes().iter().enumerate() {
        if p[0] < 0.2 && p[1] < 0.2 {
            model.set_initial_node(i, 1132.0).expect("initial");
        }
    }
    let n = mesh.n_nodes();
    println!("thermal bench: {n} nodes, {} triangles", mesh.n_triangles());

    // The whole run: 1000 steps of one Δt, output at the end.
    let schedule = TimeSchedule::uniform(DT, 1000).expect("schedule");
    let t = Instant::now();
    let summary = model
        .solve_transient(&schedule, ThetaScheme::backward_euler(), &[1000.0], |s| {
            black_box(s.balance.residual);
        })
        .expect("run");
    let total = t.elapsed().as_secs_f64();
    println!(
        "1000 steps (assembly + 1 factorisation + 1000 steps): {total:.2} s, {} factorisation(s), balance residual {:.1e}",
        summary.factorisations, summary.max_balance_residual
    );

    let system = model.assemble().expect("assemble");
    let t0 = system.initial_temperature().expect("initial").to_vec();
    let mut stepper = system.stepper(t0.clone(), 0.0).expect("stepper");
    let t = Instant::now();
    stepper.step(DT, 1.0).expect("first step");
    let first = t.elapsed().as_secs_f64();

    // The same factorisation, built by hand.
    let mut a = system.assembler().new_matrix();
    let inv = 1.0 / DT;
    for ((a, c), k) in a
        .values_mut()
        .iter_mut()
        .zip(system.capacity_matrix().values())
        .zip(system.conductivity_matrix().values())
    {
        *a = c * inv + k;
    }
    let mut solver =
        CholeskySolver::analyse(Arc::clone(system.assembler().pattern())).expect("analyse");
    let t = Instant::now();
    solver.factorise(&a).expect("factorise");
    let factorise = t.elapsed().as_secs_f64();
    let b = stepper.temperature().to_vec();
    let mut x = b.clone();
    let k = system.conductivity_matrix();
    let mut y = vec![0.0; n];
    // Interleaved rounds (the machine is shared: the minimum over rounds is
    // the least disturbed estimate, the median is printed beside it).
    let (mut ts, mut tv, mut tm) = (Vec::new(), Vec::new(), Vec::new());
    let mut step_f = || stepper.step(DT, 1.0).expect("step");
    let mut solve_f = || {
        x.copy_from_slice(&b);
        solver.solve(&mut x).expect("solve");
    };
    let mut matvec_f = || k.mul_vec(&b, &mut y);
    for _ in 0..20 {
        ts.push(time_once(5, &mut step_f));
        tv.push(time_once(5, &mut solve_f));
        tm.push(time_once(5, &mut matvec_f));
    }
    println!(
        "first step (with factorisation) {:.2} ms; bare factorisation {:.2} ms; factor nnz {}",
        first * 1e3,
        factorise * 1e3,
        solver.factor_nnz()
    );
    for (label, f) in [
        ("minimum", minimum as fn(&[f64]) -> f64),
        ("median", |v: &[f64]| median(v.to_vec())),
    ] {
        let (s, v, m) = (f(&ts), f(&tv), f(&tm));
        println!(
            "{label:>7}: step {:.3} ms, solve {:.3} ms, mat-vec {:.3} ms; step / (solve + mat-vec) = {:.3}",
            s * 1e3,
            v * 1e3,
            m * 1e3,
            s / (v + m)
        );
    }
    println!(
        "1000-step run per step (incl. assembly and factorisation): {:.3} ms",
        total * 1e3 / 1000.0
    );

    let mut c = Criterion::default().configure_from_args().sample_size(30);
    c.bench_function("thermal/step_1e5_nodes", |bch| {
        bch.iter(|| stepper.step(DT, 1.0).expect("step"))
    });
    c.bench_function("thermal/solve_1e5_nodes", |bch| {
        bch.iter(|| {
            x.copy_from_slice(&b);
            solver.solve(&mut x).expect("solve");
        })
    });
    c.bench_function("thermal/matvec_1e5_nodes", |bch| {
        bch.iter(|| k.mul_vec(black_box(&b), &mut y))
    });
    c.final_summary();
}
