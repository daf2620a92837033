//! Warm start of a contact solve ([`StaticSolver::resume_warm`]): the same
//! step from the same committed state, its Newton iterations started from
//! a guess extrapolated from the two states before, gives the cold start's
//! answer within the solver's tolerances, in fewer iterations; and the
//! committed output until the next solve is the resumed state's.
//!
//! ```text
//!   core + one layer (half ring, frictional joint), weld at s·ΔT:
//!   s = 0.6 → A, s = 0.8 → B (friction history), then s = 1 from B:
//!   cold: resume(B)            warm: resume_warm(B, B + (B − A))
//! ```

use tecon_contact::{GhaboussiNormal, PaperJoint};
use tecon_elastic::{
    Analysis, ElasticModel, IncrementReport, Joint, Loads, Material, SolverOptions, SolverState,
    StaticSolver,
};
use tecon_mesh::{Mesh, MultilayerGeometry, MultilayerMeshSpec, multilayer_vessel_mesh};

const E: f64 = 207e9;
const DT: f64 = 21.0 - 1132.0;

fn model<'m>(mesh: &'m Mesh, h: f64) -> ElasticModel<'m> {
    let k = 10.0 * E / h;
    let joint = Joint::Frictional(
        PaperJoint::new(GhaboussiNormal::penalty(k).unwrap(), k, 0.0, 0.3f64.atan()).unwrap(),
    );
    ElasticModel::new(mesh, Analysis::PlaneStrain)
        .material_everywhere(Material {
            youngs_modulus: E,
            poisson_ratio: 0.3,
            expansion: 12.51e-6,
        })
        .unwrap()
        .symmetry("sym0")
        .unwrap()
        .symmetry("sym180")
        .unwrap()
        .remove_free_translations(true)
        .interface("core_layer1", joint)
        .unwrap()
}

fn options() -> SolverOptions {
    SolverOptions {
        augmented_lagrangian: Some(1e-4),
        max_iterations: 150,
        ..SolverOptions::default()
    }
}

/// The weld at `s` ΔT, the rest at zero.
fn loads(mesh: &Mesh, s: f64) -> Loads {
    let names = mesh.region_names();
    Loads {
        delta_t: mesh
            .element_regions()
            .iter()
            .map(|&r| if names[r] == "weld1" { s * DT } else { 0.0 })
            .collect(),
        ..Loads::zero()
    }
}

fn iterations(r: &[IncrementReport]) -> usize {
    r.iter().map(|r| r.iterations).sum()
}

fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
    v.map(f64::abs).fold(0.0, f64::max)
}

/// The one-layer ring of these tests and its interface penalty's element size.
fn ring() -> (Mesh, f64) {
    let geo = MultilayerGeometry::staggered(0.762, 12.7e-3, 1, 6.4e-3, 3.8e-3);
    let mesh = multilayer_vessel_mesh(&geo, &MultilayerMeshSpec::default()).unwrap();
    (mesh, geo.layers[0].thickness / 2.0)
}

#[test]
fn warm_start_gives_the_cold_answer_in_fewer_iterations() {
    let (mesh, h) = ring();
    let m = model(&mesh, h);
    let mut solver = StaticSolver::new(&m, options()).unwrap();
    solver.advance(&loads(&mesh, 0.6)).unwrap();
    let a = solver.state();
    solver.advance(&loads(&mesh, 0.8)).unwrap();
    let b = solver.state();
    let b_output = solver.displacement().to_vec();

    solver.resume(&b).unwrap();
    let b_points = solver.interface_results();
    let cold = iterations(&solver.advance(&loads(&mesh, 1.0)).unwrap());
    let (u_cold, p_cold) = (
        solver.raw_displacement().to_vec(),
        solver.interface_results(),
    );

    let guess = b.extrapolated(&a, 1.0);
    solver.resume_warm(&b, &guess).unwrap();
    // until the next solve, the committed output is B's, as after resume
    assert_eq!(solver.displacement(), &b_output[..]);
    assert_eq!(solver.interface_results(), b_points);
    let warm = iterations(&solver.advance(&loads(&mesh, 1.0)).unwrap());
    let (u_warm, p_warm) = (
        solver.raw_displacement().to_vec(),
        solver.interface_results(),
    );

    let du = max_abs(u_cold.iter().zip(&u_warm).map(|(x, y)| x - y)) / max_abs(u_cold.into_iter());
    let p_max = max_abs(p_cold.iter().map(|p| p.traction[1]));
    let dp = max_abs(
        p_cold
            .iter()
            .zip(&p_warm)
            .flat_map(|(x, y)| [x.traction[0] - y.traction[0], x.traction[1] - y.traction[1]]),
    ) / p_max;
    let slip_max = max_abs(p_cold.iter().map(|p| p.slip));
    let ds = max_abs(p_cold.iter().zip(&p_warm).map(|(x, y)| x.slip - y.slip)) / slip_max;
    eprintln!(
        "cold {cold} Newton iterations, warm {warm}; relative differences: u {du:.2e}, traction {dp:.2e}, slip {ds:.2e}"
    );
    // the outer passes stop when the multipliers and friction limits change
    // by at most 1e-4 of the largest pressure, so the two answers may differ
    // by that much (measured with frozen limits to the end: u 1.2e-5,
    // traction 1.4e-5, slip 9.7e-7; the cold solve now ends in the coupled
    // tail of its outer loop, within 2e-8 of a frozen loop run to 1e-10:
    // u 1.4e-8, traction 3.1e-7, slip 5.3e-9)
    assert!(du < 1e-4, "{du:e}");
    assert!(dp < 1e-4, "{dp:e}");
    assert!(ds < 1e-4, "{ds:e}");
    assert!(warm < cold, "warm {warm}, cold {cold}");
    // w = 0 is the state itself
    assert_eq!(b.extrapolated(&a, 0.0).displacement, b.displacement);
}

#[test]
fn a_guess_of_another_mesh_is_refused() {
    let (mesh, h) = ring();
    let m = model(&mesh, h);
    let mut solver = StaticSolver::new(&m, options()).unwrap();
    let state = solver.state();
    let e = solver
        .resume_warm(&state, &SolverState::unloaded(7))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("warm-start guess") && e.contains("7 displacement values"),
        "{e}"
    );
    let mut bad = state.clone();
    bad.displacement[3] = f64::NAN;
    let e = solver.resume_warm(&state, &bad).unwrap_err().to_string();
    assert!(e.contains("displacement value 3 is not finite"), "{e}");
}

/// Most outer updates of any increment.
fn outer_updates(r: &[IncrementReport]) -> usize {
    r.iter().map(|r| r.augmentations).max().unwrap_or(0)
}

#[test]
fn an_outer_tolerance_floor_stops_the_outer_loop_sooner_within_that_floor() {
    let (mesh, h) = ring();
    let m = model(&mesh, h);
    let mut solver = StaticSolver::new(&m, options()).unwrap();
    solver.advance(&loads(&mesh, 0.8)).unwrap();
    let b = solver.state();

    let tight = solver.advance(&loads(&mesh, 1.0)).unwrap();
    let (u_tight, p_tight) = (
        solver.raw_displacement().to_vec(),
        solver.interface_results(),
    );

    let floor = 3e-3;
    solver.resume(&b).unwrap();
    solver.set_outer_tolerance_floor(floor);
    let loose = solver.advance(&loads(&mesh, 1.0)).unwrap();
    let p_loose = solver.interface_results();
    let p_max = max_abs(p_tight.iter().map(|p| p.traction[1]));
    let dp = max_abs(
        p_tight
            .iter()
            .zip(&p_loose)
            .flat_map(|(x, y)| [x.traction[0] - y.traction[0], x.traction[1] - y.traction[1]]),
    ) / p_max;
    eprintln!(
        "outer updates: tight {}, floor {floor:e}: {}; Newton iterations {} and {}; traction difference {dp:.2e} of the largest pressure",
        outer_updates(&tight),
        outer_updates(&loose),
        iterations(&tight),
        iterations(&loose)
    );
    assert!(outer_updates(&loose) < outer_updates(&tight));
    // the loop stops once an update changes the multipliers and limits by
    // less than the floor × the largest pressure; with a contraction
    // below 1/2 per update the answer is within that of the fixed point
    assert!(dp > 0.0 && dp < floor, "{dp:e}");

    // the floor set back to 0: the solver's own tolerances, the same bits
    solver.resume(&b).unwrap();
    solver.set_outer_tolerance_floor(0.0);
    solver.advance(&loads(&mesh, 1.0)).unwrap();
    assert_eq!(solver.raw_displacement(), &u_tight[..]);
}
