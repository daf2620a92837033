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

fn time_it(reps: usize, mut f: impl FnMut()) -> f64 {
    f();
    median(
        (0..reps)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .collect(),
    )
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
    println!(
        "thermal bench: {n} nodes, {} triangles",
        mesh.n_triangles()
    );

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
    let step = time_it(30, || stepper.step(DT, 1.0).expect("step"));

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
    let solve = time_it(30, || {
        x.copy_from_slice(&b);
        solver.solve(&mut x).expect("solve");
    });
    let k = system.conductivity_matrix();
    let mut y = vec![0.0; n];
    let matvec = time_it(30, || k.mul_vec(&b, &mut y));
    println!(
        "first step (with factorisation) {:.2} ms; bare factorisation {:.2} ms; factor nnz {}",
        first * 1e3,
        factorise * 1e3,
        solver.factor_nnz()
    );
    println!(
        "median: step {:.3} ms, solve {:.3} ms, mat-vec {:.3} ms; step / (solve + mat-vec) = {:.3}",
        step * 1e3,
        solve * 1e3,
        matvec * 1e3,
        step / (solve + matvec)
    );
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
