//! The time-stepping machinery: factorisation reuse, output times,
//! determinism and the coupling output.
//!
//! Reference: issue 3 (factorise once per distinct Δt; outputs at requested
//! times; per-element reference temperature) and STYLE.md convention 7.
//! Mesh: unit square, 12 × 12 cells, steel, convection on `right`, a hot
//! corner node set at the start.

use tecon_mesh::{Mesh, rectangle};
use tecon_thermal::{
    BorderRule, CapacityKind, EdgeBc, Material, ThermalModel, ThetaScheme, TimeSchedule,
};

fn square() -> Mesh {
    rectangle(0.0, 0.0, 0.1, 0.1, 12, 12).unwrap()
}

fn model(mesh: &Mesh) -> ThermalModel<'_> {
    let mut m = ThermalModel::new(mesh);
    m.set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .add_edge_bc("right", EdgeBc::convection(500.0, 20.0))
        .unwrap()
        .set_initial_default(20.0)
        .unwrap();
    for (i, p) in mesh.nodes().iter().enumerate() {
        if p[0] < 0.03 && p[1] < 0.03 {
            m.set_initial_node(i, 800.0).unwrap();
        }
    }
    m
}

#[test]
fn one_factorisation_per_distinct_step_and_theta() {
    let mesh = square();
    let m = model(&mesh);
    let sch = TimeSchedule::segments(&[(1.0, 0.1), (10.0, 1.0), (100.0, 10.0)]).unwrap();
    let be = m
        .solve_transient(&sch, ThetaScheme::backward_euler(), &[], |_| {})
        .unwrap();
    assert_eq!(be.factorisations, 3);
    assert_eq!(be.steps, sch.len());
    let cn = m
        .solve_transient(&sch, ThetaScheme::crank_nicolson(), &[], |_| {})
        .unwrap();
    assert_eq!(cn.factorisations, 4, "BE start-up + 3 CN step sizes");
    // Output times inside steps split them (two more step sizes per split).
    let snaps = m
        .solve_transient_collect(&sch, ThetaScheme::backward_euler(), &[0.35, 55.0, 100.0])
        .unwrap();
    let times: Vec<f64> = snaps.iter().map(|s| s.time).collect();
    assert!((times[0] - 0.35).abs() < 1e-12 && (times[1] - 55.0).abs() < 1e-9);
    assert!((times[2] - 100.0).abs() < 1e-9);
    // Alternating step sizes within the pool size never refactorise.
    let system = m.assemble().unwrap();
    let mut st = system
        .stepper(system.initial_temperature().unwrap().to_vec(), 0.0)
        .unwrap();
    for k in 0..20 {
        st.step(if k % 3 == 0 { 0.5 } else { 0.25 }, 1.0).unwrap();
    }
    assert_eq!(st.stats().factorisations, 2);
    assert_eq!(st.stats().analyses, 1, "the second slot shares the first's");
    // A pool of one refactorises on every change but never re-analyses.
    let mut st = system
        .stepper(system.initial_temperature().unwrap().to_vec(), 0.0)
        .unwrap();
    st.set_pool_size(1);
    for k in 0..6 {
        st.step(if k % 2 == 0 { 0.5 } else { 0.25 }, 1.0).unwrap();
    }
    assert_eq!(st.stats().factorisations, 6);
    assert_eq!(st.stats().analyses, 1);
    // Dropped operators are factorised again when a step needs them; the
    // kept one is reused.
    let mut st = system
        .stepper(system.initial_temperature().unwrap().to_vec(), 0.0)
        .unwrap();
    st.step(0.5, 1.0).unwrap();
    st.step(0.25, 1.0).unwrap();
    assert_eq!(st.stats().factorisations, 2);
    st.retain_operators(|dt, _| dt == 0.25f64.to_bits());
    st.step(0.25, 1.0).unwrap();
    assert_eq!(st.stats().factorisations, 2, "the kept one reused");
    st.step(0.5, 1.0).unwrap();
    assert_eq!(
        st.stats().factorisations,
        3,
        "the dropped one factorised anew"
    );
    assert_eq!(st.stats().analyses, 1, "but not analysed anew");
}

/// A stepper sharing the symbolic analysis of a solver made on another
/// (re-)assembly of the same pattern never analyses and gives bitwise the
/// temperatures of one that analyses its own; a solver of another pattern
/// is refused at the factorisation with an error.
#[test]
fn a_shared_symbolic_analysis_gives_the_same_steps() {
    let mesh = square();
    let m = model(&mesh);
    let first = m.assemble().unwrap();
    let analysed =
        tecon_fem::CholeskySolver::analyse(std::sync::Arc::clone(first.assembler().pattern()))
            .unwrap();
    let system = m.assemble().unwrap();
    let t0 = system.initial_temperature().unwrap().to_vec();
    let mut own = system.stepper(t0.clone(), 0.0).unwrap();
    let mut shared = system.stepper(t0.clone(), 0.0).unwrap();
    shared.share_symbolic(&analysed);
    for k in 0..8 {
        let dt = if k % 3 == 0 { 0.5 } else { 0.25 };
        own.step(dt, 0.5).unwrap();
        shared.step(dt, 0.5).unwrap();
    }
    assert_eq!(own.temperature(), shared.temperature());
    assert_eq!(shared.stats().analyses, 0);
    assert_eq!(own.stats().analyses, 1);
    assert_eq!(shared.stats().factorisations, 2);
    let other = rectangle(0.0, 0.0, 0.1, 0.1, 5, 5).unwrap();
    let other = model(&other).assemble().unwrap();
    let wrong =
        tecon_fem::CholeskySolver::analyse(std::sync::Arc::clone(other.assembler().pattern()))
            .unwrap();
    let mut bad = system.stepper(t0, 0.0).unwrap();
    bad.share_symbolic(&wrong);
    let e = bad.step(0.5, 1.0).unwrap_err().to_string();
    assert!(e.contains("pattern"), "{e}");
}

#[test]
fn results_are_bitwise_identical_for_any_thread_count() {
    let mesh = rectangle(0.0, 0.0, 0.1, 0.1, 80, 80).unwrap(); // > one assembly batch
    let m = model(&mesh);
    let sch = TimeSchedule::uniform(0.5, 10).unwrap();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                m.solve_transient_collect(&sch, ThetaScheme::crank_nicolson(), &[5.0])
                    .unwrap()
            })
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a[0].temperature, b[0].temperature);
    assert_eq!(a[0].flux, b[0].flux);
    assert_eq!(a[0].balance, b[0].balance);
}

#[test]
fn coupling_output_reference_and_element_temperatures() {
    // Two regions by hand: left half "hot" (500), right half "cold" (20).
    let base = square();
    let regions: Vec<usize> = base
        .triangles()
        .iter()
        .map(|t| {
            let x = t.iter().map(|&i| base.nodes()[i][0]).sum::<f64>() / 3.0;
            usize::from(x > 0.05)
        })
        .collect();
    let mesh = Mesh::new(
        base.nodes().to_vec(),
        base.triangles().to_vec(),
        regions,
        vec!["hot".into(), "cold".into()],
    )
    .unwrap();
    for (rule, border) in [
        (BorderRule::CapacityWeighted, 260.0),
        (BorderRule::Maximum, 500.0),
        (BorderRule::Minimum, 20.0),
    ] {
        let mut m = ThermalModel::new(&mesh);
        m.set_material_everywhere(Material::vessel_steel())
            .unwrap()
            .set_capacity(CapacityKind::Lumped)
            .set_initial_region("hot", 500.0)
            .unwrap()
            .set_initial_region("cold", 20.0)
            .unwrap()
            .set_border_rule(rule);
        let system = m.assemble().unwrap();
        let t0 = system.initial_temperature().unwrap();
        for (i, p) in mesh.nodes().iter().enumerate() {
            let expect = if (p[0] - 0.05).abs() < 1e-12 {
                border
            } else if p[0] < 0.05 {
                500.0
            } else {
                20.0
            };
            assert!(
                (t0[i] - expect).abs() < 1e-9,
                "{rule:?}: node {i} at x = {}: {}",
                p[0],
                t0[i]
            );
        }
        // T_ref = element mean of the initial field: a snapshot at t = 0 has
        // element temperatures equal to T_ref (zero thermal strain).
        let t_ref = system.reference_temperature().unwrap();
        let sch = TimeSchedule::uniform(1.0, 2).unwrap();
        let snaps = m
            .solve_transient_collect(&sch, ThetaScheme::backward_euler(), &[0.0, 2.0])
            .unwrap();
        assert_eq!(snaps[0].element_temperature, t_ref);
        assert_eq!(snaps[0].step, 0);
        assert_eq!(snaps[1].step, 2);
        // Adiabatic body: heat only moves, the content is kept.
        assert!(snaps[1].balance.stored_change.abs() < 1e-9 * snaps[1].balance.scale);
        assert!(snaps[1].balance.relative_residual() < 1e-10);
        let reg = system.region_initial_temperature().unwrap();
        assert!(reg.iter().all(|&t| t == 500.0 || t == 20.0));
    }
}

/// Reference: the steady solution of the same model; conservation of
/// energy with heat supplied through prescribed temperatures.
/// Goal: a transient run with a prescribed inner temperature, an interface
/// and outer convection closes its balance (global and per body) at every
/// output with the reactions accounted for, and tends to the steady state.
///
/// ```text
///   ring a (T = 100 at r = 1) ║ h_c = 2 ║ ring b, convection h = 5 to 0 at r = 2
/// ```
#[test]
fn transient_with_prescribed_temperature_tends_to_the_steady_state() {
    use tecon_mesh::{RingLayer, layered_annulus};
    let mesh = layered_annulus(
        &[
            RingLayer {
                name: "a".into(),
                r_in: 1.0,
                r_out: 1.5,
                rows: 4,
            },
            RingLayer {
                name: "b".into(),
                r_in: 1.5,
                r_out: 2.0,
                rows: 4,
            },
        ],
        0.0,
        std::f64::consts::FRAC_PI_2,
        16,
    )
    .unwrap();
    let mut m = ThermalModel::new(&mesh);
    m.set_material("a", Material::new(1.0, 1.0, 1.0))
        .unwrap()
        .set_material("b", Material::new(2.0, 1.0, 2.0))
        .unwrap()
        .add_edge_bc("inner", EdgeBc::temperature(100.0))
        .unwrap()
        .add_edge_bc("outer", EdgeBc::convection(5.0, 0.0))
        .unwrap()
        .set_interface_conductance("a_b", 2.0)
        .unwrap()
        .set_initial_default(0.0)
        .unwrap();
    let steady = m.solve_steady().unwrap();
    let sch = TimeSchedule::geometric(1e-3, 2.0, 4, 200.0).unwrap();
    let snaps = m
        .solve_transient_collect(
            &sch,
            ThetaScheme::crank_nicolson(),
            &[0.01, 0.5, 5.0, 200.0],
        )
        .unwrap();
    for s in &snaps {
        let b = &s.balance;
        println!(
            "t = {:6.2}: stored {:.6e}, from T̄ {:.6e}, convected {:.6e}, residual {:.1e}",
            s.time,
            b.stored_change,
            b.prescribed_in,
            b.convection_in,
            b.relative_residual()
        );
        assert!(b.relative_residual() < 1e-10);
        assert!(b.prescribed_in > 0.0);
        for body in &s.bodies {
            assert!(body.relative_residual() < 1e-10, "{body:?}");
        }
    }
    let last = snaps.last().unwrap();
    let err = last
        .temperature
        .iter()
        .zip(&steady.temperature)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("distance to the steady state at t = 200: {err:.2e}");
    assert!(err < 1e-6 * 100.0);
}

/// Goal: on the vessel's large quadratic meshes the solver's automatic
/// order keeps nested dissection, whose factor is far smaller than AMD's
/// (graded level 2 at order 2, 92 202 nodes: 3.34 against 4.50 million
/// entries, measured 2026-11-29), and the steps solve the same.
#[test]
fn a_large_vessel_mesh_takes_the_smaller_nested_dissection_factor() {
    use tecon_fem::{CholeskySolver, FillOrdering};
    use tecon_mesh::{VesselGeometry, VesselMeshSpec, vessel_mesh};
    let mesh = vessel_mesh(
        &VesselGeometry::default(),
        &VesselMeshSpec::graded(2).unwrap(),
    )
    .unwrap();
    let mut m = ThermalModel::new(&mesh);
    m.set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .add_edge_bc("outer", EdgeBc::convection(10.25, 21.0))
        .unwrap()
        .set_interface_conductance("core_layer", 850.0)
        .unwrap()
        .set_initial_default(21.0)
        .unwrap()
        .set_initial_region("weld", 1132.0)
        .unwrap();
    let system = m.assemble().unwrap();
    let pattern = std::sync::Arc::clone(system.assembler().pattern());
    assert!(pattern.n() > 90_000);
    let entries = |o| {
        CholeskySolver::analyse_ordered(pattern.clone(), o)
            .unwrap()
            .factor_nnz()
    };
    let (amd, nd) = (
        entries(FillOrdering::Amd),
        entries(FillOrdering::NestedDissection),
    );
    let auto = CholeskySolver::analyse(pattern.clone())
        .unwrap()
        .factor_nnz();
    assert_eq!(auto, nd, "AMD {amd}, nested dissection {nd}");
    assert!(
        (nd as f64) < 0.85 * amd as f64,
        "AMD {amd}, nested dissection {nd}"
    );
    // two steps with an AMD-ordered factor shared in, against the default
    let t0 = system.initial_temperature().unwrap().to_vec();
    let mut own = system.stepper(t0.clone(), 0.0).unwrap();
    let mut amd_steps = system.stepper(t0, 0.0).unwrap();
    amd_steps.share_symbolic(&CholeskySolver::analyse_ordered(pattern, FillOrdering::Amd).unwrap());
    for _ in 0..2 {
        own.step(0.02, 1.0).unwrap();
        amd_steps.step(0.02, 1.0).unwrap();
    }
    let worst = own
        .temperature()
        .iter()
        .zip(amd_steps.temperature())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "temperatures differ by {worst:e} K");
}
