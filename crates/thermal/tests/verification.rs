//! Verification of `tecon-thermal` against closed-form solutions.
//!
//! Run: `CARGO_TARGET_DIR=target-thermal cargo test -p tecon-thermal --test verification -- --nocapture`
//! (each test prints its error table and fitted order).

mod common;

use approx::assert_relative_eq;
use common::{distorted, fitted_slope, two_blocks};
use tecon_mesh::{Mesh, RingLayer, layered_annulus, rectangle};
use tecon_thermal::analytical::{ConcentricRings, SlabConvectionSeries};
use tecon_thermal::{
    CapacityKind, ConductanceLaw, EdgeBc, InterfacePointState, InterfaceQuadrature, Material,
    ThermalModel, ThermalSystem, ThetaScheme, TimeSchedule,
};

// --------------------------------------------------------------------------
// 1D transient slab with a convective face
// --------------------------------------------------------------------------

/// Slab data (nondimensional): L = 1, k = 1, ρc = 1 (a = 1), h = 2
/// (Bi = 2), T∞ = 0, T₀ = 1. The run starts at Fo = 0.05 from the series
/// solution (a smooth field) and ends at Fo = 0.45.
const SLAB_T0: f64 = 0.05;
const SLAB_T1: f64 = 0.45;

fn slab_series() -> SlabConvectionSeries {
    SlabConvectionSeries::new(1.0, 1.0, 1.0, 2.0, 0.0, 1.0, 400)
}

fn slab_system(mesh: &Mesh, capacity: CapacityKind) -> ThermalSystem<'_> {
    let mut model = ThermalModel::new(mesh);
    model
        .set_material_everywhere(Material::new(1.0, 1.0, 1.0))
        .unwrap()
        .set_capacity(capacity)
        .add_edge_bc("right", EdgeBc::convection(2.0, 0.0))
        .unwrap();
    model.assemble().unwrap()
}

/// Runs the slab from SLAB_T0 with `steps` and returns (max nodal error at
/// the end, largest relative heat-balance residual over the steps).
fn slab_run(nx: usize, capacity: CapacityKind, scheme: ThetaScheme, n_steps: usize) -> (f64, f64) {
    let series = slab_series();
    let mesh = rectangle(0.0, 0.0, 1.0, 1.0 / nx as f64, nx, 1).unwrap();
    let system = slab_system(&mesh, capacity);
    let t0: Vec<f64> = mesh
        .nodes()
        .iter()
        .map(|p| series.temperature(p[0], SLAB_T0))
        .collect();
    let schedule =
        TimeSchedule::from_steps_at(SLAB_T0, vec![(SLAB_T1 - SLAB_T0) / n_steps as f64; n_steps])
            .unwrap();
    let mut stepper = system.stepper(t0, SLAB_T0).unwrap();
    let mut worst_balance: f64 = 0.0;
    for (k, &dt) in schedule.steps().iter().enumerate() {
        stepper.step(dt, scheme.theta_at(k)).unwrap();
        worst_balance = worst_balance.max(stepper.balance().relative_residual());
    }
    assert_relative_eq!(stepper.time(), SLAB_T1, epsilon = 1e-12);
    // One factorisation per θ (start-up BE, then the scheme's θ).
    let expected_factorisations = if scheme.startup_steps() > 0 && scheme.theta() != 1.0 {
        2
    } else {
        1
    };
    assert_eq!(stepper.stats().factorisations, expected_factorisations);
    let err = mesh
        .nodes()
        .iter()
        .zip(stepper.temperature())
        .map(|(p, t)| (t - series.temperature(p[0], SLAB_T1)).abs())
        .fold(0.0, f64::max);
    (err, worst_balance)
}

/// Reference: Carslaw & Jaeger §3.11 (slab with a convective face), series
/// in `analytical::SlabConvectionSeries`.
/// Goal: observed spatial order 2 (max nodal error at Fo = 0.45), both
/// capacity matrices; the time error is made negligible (CN, Δt = 1e-4).
///
/// ```text
///   x = 0 (adiabatic)                    x = L (−k T' = h (T − T∞))
///   +----+----+----+----+ ... +----+
///   | \  | /  | \  | /  |     |  / |     one row of nx cells, height L/nx
///   +----+----+----+----+ ... +----+
///   top, bottom: adiabatic (the field is 1D)
/// ```
/// BCs: `right` convective (h = 2, T∞ = 0), all other edges adiabatic;
/// initial field = the series at Fo = 0.05.
#[test]
fn slab_spatial_order_is_two() {
    for capacity in [CapacityKind::Consistent, CapacityKind::Lumped] {
        let nxs = [8usize, 16, 32, 64];
        let mut errs = Vec::new();
        for &nx in &nxs {
            let (e, bal) = slab_run(nx, capacity, ThetaScheme::crank_nicolson(), 4000);
            assert!(bal < 1e-10, "heat balance residual {bal:e} (nx = {nx})");
            println!("slab space {capacity:?}: nx = {nx:3}, max error {e:.3e}, balance {bal:.1e}");
            errs.push(e);
        }
        let h: Vec<f64> = nxs.iter().map(|&n| 1.0 / n as f64).collect();
        let p = fitted_slope(&h, &errs);
        println!("slab space {capacity:?}: fitted order {p:.3}");
        assert!((p - 2.0).abs() < 0.15, "spatial order {p} ({capacity:?})");
    }
}

/// Reference: as above.
/// Goal: observed temporal order 1 for backward Euler and 2 for
/// Crank–Nicolson started with two backward-Euler steps (max nodal error
/// at Fo = 0.45, Δt = 0.4/20 … 0.4/160); the space error is made
/// negligible (nx = 1000).
///
/// ```text
///   +--+--+--+-- ... --+--+   1000 cells, one row
///   adiabatic          convective face
/// ```
/// BCs: `right` convective (h = 2, T∞ = 0); other edges adiabatic.
#[test]
fn slab_temporal_orders_backward_euler_one_crank_nicolson_two() {
    let ns = [20usize, 40, 80, 160];
    let dts: Vec<f64> = ns.iter().map(|&n| (SLAB_T1 - SLAB_T0) / n as f64).collect();
    for (scheme, order, name) in [
        (ThetaScheme::backward_euler(), 1.0, "backward Euler"),
        (
            ThetaScheme::crank_nicolson(),
            2.0,
            "Crank-Nicolson (2 BE start-up steps)",
        ),
    ] {
        let mut errs = Vec::new();
        for &n in &ns {
            let (e, bal) = slab_run(1000, CapacityKind::Consistent, scheme, n);
            assert!(
                bal < 1e-10,
                "heat balance residual {bal:e} ({name}, {n} steps)"
            );
            println!("slab time {name}: {n:4} steps, max error {e:.3e}, balance {bal:.1e}");
            errs.push(e);
        }
        let p = fitted_slope(&dts, &errs);
        println!("slab time {name}: fitted order {p:.3}");
        assert!((p - order).abs() < 0.15, "temporal order {p} for {name}");
    }
}

// --------------------------------------------------------------------------
// Steady concentric rings joined by an interface
// --------------------------------------------------------------------------

const RINGS: ConcentricRings = ConcentricRings {
    r_a: 1.0,
    r_b: 1.5,
    r_c: 2.0,
    k1: 1.0,
    k2: 2.0,
    h_c: 2.0,
    h: 5.0,
    t_inner: 100.0,
    ambient: 0.0,
};

fn rings_mesh(level: u32) -> Mesh {
    let f = 1usize << level;
    layered_annulus(
        &[
            RingLayer {
                name: "a".into(),
                r_in: RINGS.r_a,
                r_out: RINGS.r_b,
                rows: 2 * f,
            },
            RingLayer {
                name: "b".into(),
                r_in: RINGS.r_b,
                r_out: RINGS.r_c,
                rows: 2 * f,
            },
        ],
        0.0,
        2.0 * std::f64::consts::PI,
        32 * f,
    )
    .unwrap()
}

/// Max nodal error of the rings and error of the interface jump
/// (largest over the facing pairs).
fn rings_errors<L: ConductanceLaw + 'static>(
    mesh: &Mesh,
    law: L,
    rule: InterfaceQuadrature,
    rings: &ConcentricRings,
    states: Option<Vec<[InterfacePointState; 2]>>,
) -> (f64, f64, f64) {
    let mut model = ThermalModel::new(mesh);
    model
        .set_material("a", Material::new(rings.k1, 1.0, 1.0))
        .unwrap()
        .set_material("b", Material::new(rings.k2, 1.0, 1.0))
        .unwrap()
        .add_edge_bc("inner", EdgeBc::temperature(rings.t_inner))
        .unwrap()
        .add_edge_bc("outer", EdgeBc::convection(rings.h, rings.ambient))
        .unwrap()
        .set_interface_law("a_b", law, rule)
        .unwrap();
    if let Some(s) = states {
        model.set_interface_state("a_b", s).unwrap();
    }
    let snap = model.solve_steady().unwrap();
    // Nodes of ring a: those of the body holding region a's first triangle.
    let first = mesh.triangles()[mesh.region_elements("a").unwrap()[0]][0];
    let body_a = mesh.node_bodies()[first];
    let in_a: Vec<bool> = mesh.node_bodies().iter().map(|&b| b == body_a).collect();
    let err_t = mesh
        .nodes()
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
            let exact = if in_a[i] {
                rings.inner(r)
            } else {
                rings.outer(r)
            };
            (snap.temperature[i] - exact).abs()
        })
        .fold(0.0, f64::max);
    let itf = &snap.interfaces[0];
    assert_eq!(itf.name, "a_b");
    // ⟦T⟧ = T_top − T_bottom = T(r_b⁺) − T(r_b⁻) = −q/h_c.
    let err_jump = itf
        .elements
        .iter()
        .flat_map(|f| f.jump)
        .map(|j| (j + rings.jump()).abs())
        .fold(0.0, f64::max);
    // Total heat through the interface (top → bottom is inward: −Q).
    let err_q = (itf.heat_rate + rings.heat_rate()).abs() / rings.heat_rate();
    assert!(
        snap.balance.relative_residual() < 1e-10,
        "steady balance {:e}",
        snap.balance.relative_residual()
    );
    // Steady per-body balances (rates): ring a passes on through the
    // interface what it receives at r_a; ring b convects it away.
    for b in &snap.bodies {
        assert!(
            b.relative_residual() < 1e-10,
            "body {} residual {:e}",
            b.body,
            b.relative_residual()
        );
    }
    let (a, b) = (&snap.bodies[0], &snap.bodies[1]);
    assert_eq!((a.body.as_str(), b.body.as_str()), ("a", "b"));
    // Bottom = ring a receives q (top → bottom) = −Q.
    assert_relative_eq!(a.interface_in, itf.heat_rate, max_relative = 1e-12);
    assert_relative_eq!(b.interface_in, -itf.heat_rate, max_relative = 1e-12);
    assert_relative_eq!(b.convection_in, itf.heat_rate, max_relative = 1e-9);
    (err_t, err_jump, err_q)
}

/// Reference: four thermal resistances in series (`analytical::ConcentricRings`):
/// ln(r_b/r_a)/(2πk₁) + 1/(2π r_b h_c) + ln(r_c/r_b)/(2πk₂) + 1/(2π r_c h).
/// Goal: the temperature jump q/h_c at the interface, the ring temperatures
/// and the interface heat rate converge at order 2 (polygonal rings),
/// for nodal and Gauss integration of the interface element.
///
/// ```text
///            .-~~~~~~~-.          ring b (k₂ = 2), r 1.5 … 2.0
///          /  .-~~~~~-.  \        ---- interface a_b, h_c = 2 ----
///         |  |  .---.  |  |       ring a (k₁ = 1), r 1.0 … 1.5
///         |  | ( T_a ) |  |
///          \  '-~~~~~-'  /        32·2^l segments, 2·2^l rows per ring
///            '-~~~~~~~-'
/// ```
/// BCs: `inner` T = 100; `outer` convective h = 5, T∞ = 0.
#[test]
fn rings_with_interface_jump_and_temperatures_converge_at_order_two() {
    for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
        let (mut et, mut ej, mut eq, mut hs) = (vec![], vec![], vec![], vec![]);
        for level in 0..4 {
            let mesh = rings_mesh(level);
            let law = tecon_thermal::ConstantConductance::new(RINGS.h_c).unwrap();
            let (t, j, q) = rings_errors(&mesh, law, rule, &RINGS, None);
            println!(
                "rings {rule:?}: level {level}, T error {t:.3e}, jump error {j:.3e} (exact jump {:.4}), Q rel. error {q:.3e}",
                RINGS.jump()
            );
            et.push(t);
            ej.push(j);
            eq.push(q);
            hs.push(1.0 / (1u64 << level) as f64);
        }
        let (pt, pj, pq) = (
            fitted_slope(&hs, &et),
            fitted_slope(&hs, &ej),
            fitted_slope(&hs, &eq),
        );
        println!("rings {rule:?}: fitted orders T {pt:.3}, jump {pj:.3}, Q {pq:.3}");
        for (p, what) in [(pt, "temperature"), (pj, "jump"), (pq, "heat rate")] {
            assert!((p - 2.0).abs() < 0.15, "{what} order {p} ({rule:?})");
        }
        // The finest level is close to the closed form.
        assert!(ej[3] < 1e-3 * RINGS.jump(), "jump error {}", ej[3]);
    }
}

/// A pressure-dependent law, h_c = h₀ + s·p: plugs into the same element.
#[derive(Debug)]
struct PressureLaw {
    h0: f64,
    slope: f64,
}

impl ConductanceLaw for PressureLaw {
    fn conductance(&self, state: &InterfacePointState) -> f64 {
        self.h0 + self.slope * state.pressure.max(0.0)
    }
}

/// Reference: `ConcentricRings` with h_c = h₀ + s·p.
/// Goal: a state-dependent conductance law plugs in without changing the
/// element: with a uniform pressure p the rings behave as with the
/// constant h_c = h₀ + s·p, and without the state (p = 0) as with h₀.
/// Sketch and BCs: as the rings test above (level 2).
#[test]
fn pressure_dependent_conductance_law_plugs_in() {
    let mesh = rings_mesh(2);
    let n = mesh.interface("a_b").unwrap().elements.len();
    let p = 5.0e5;
    let law = || PressureLaw {
        h0: 0.5,
        slope: 3.0e-6,
    };
    let with_p = ConcentricRings {
        h_c: 0.5 + 3.0e-6 * p,
        ..RINGS
    };
    let without = ConcentricRings { h_c: 0.5, ..RINGS };
    let states = vec![
        [InterfacePointState {
            gap: 0.0,
            pressure: p,
            temperature: 0.0,
        }; 2];
        n
    ];
    let (_, ej, _) = rings_errors(
        &mesh,
        law(),
        InterfaceQuadrature::Nodal,
        &with_p,
        Some(states),
    );
    let (_, ej0, _) = rings_errors(&mesh, law(), InterfaceQuadrature::Nodal, &without, None);
    println!(
        "pressure law: jump errors {ej:.3e} (h_c = {}), {ej0:.3e} (h_c = 0.5)",
        with_p.h_c
    );
    assert!(ej < 2e-3 * with_p.jump());
    assert!(ej0 < 2e-3 * without.jump());
    assert!((with_p.jump() - without.jump()).abs() > 0.3 * without.jump());
}

// --------------------------------------------------------------------------
// Patch tests
// --------------------------------------------------------------------------

fn linear(p: [f64; 2]) -> f64 {
    3.0 + 2.0 * p[0] - 5.0 * p[1]
}

/// Reference: a linear field T = 3 + 2x − 5y solves the steady equation
/// exactly and lies in the element space.
/// Goal: reproduced to round-off on a distorted mesh (a) with the field
/// prescribed on the whole boundary, (b) with it prescribed on `left` only
/// and the matching fluxes q_in = k ∂T/∂n on the other sides, (c) in a
/// transient run started from it (the field must not move).
///
/// ```text
///   +--+--+--+--+--+--+   interior nodes moved by up to 0.3 h
///   | / \ |/ \/ | ...  |   6 × 5 cells, [0, 1.2] × [0, 1]
///   +--+--+--+--+--+--+
/// ```
/// BCs: see (a), (b), (c); k = 4.
#[test]
fn patch_test_linear_field_is_reproduced() {
    let base = rectangle(0.0, 0.0, 1.2, 1.0, 6, 5).unwrap();
    let mesh = distorted(&base, 0.2, 0.3);
    let k = 4.0;
    let check = |t: &[f64], what: &str| {
        let err = mesh
            .nodes()
            .iter()
            .zip(t)
            .map(|(p, v)| (v - linear(*p)).abs())
            .fold(0.0, f64::max);
        println!("patch {what}: max error {err:.2e}");
        assert!(err < 1e-11, "patch {what}: error {err:e}");
    };
    // (a) Dirichlet everywhere.
    let mut model_a = ThermalModel::new(&mesh);
    model_a
        .set_material_everywhere(Material::new(k, 2.0, 3.0))
        .unwrap();
    for name in ["left", "right", "bottom", "top"] {
        for &i in mesh.node_set(name).unwrap() {
            model_a.prescribe_node(i, linear(mesh.nodes()[i])).unwrap();
        }
    }
    let snap = model_a.solve_steady().unwrap();
    check(&snap.temperature, "(a) Dirichlet boundary");
    for g in &snap.gradient {
        assert_relative_eq!(g[0], 2.0, epsilon = 1e-10);
        assert_relative_eq!(g[1], -5.0, epsilon = 1e-10);
    }
    for q in &snap.flux {
        assert_relative_eq!(q[0], -2.0 * k, epsilon = 1e-9);
        assert_relative_eq!(q[1], 5.0 * k, epsilon = 1e-9);
    }
    assert!(snap.balance.relative_residual() < 1e-12);
    // (b) Dirichlet on the left, fluxes elsewhere: q_in = k ∇T·n.
    let mut model_b = ThermalModel::new(&mesh);
    model_b
        .set_material_everywhere(Material::new(k, 2.0, 3.0))
        .unwrap();
    for &i in mesh.node_set("left").unwrap() {
        model_b.prescribe_node(i, linear(mesh.nodes()[i])).unwrap();
    }
    model_b
        .add_edge_bc("right", EdgeBc::flux(k * 2.0))
        .unwrap()
        .add_edge_bc("top", EdgeBc::flux(k * -5.0))
        .unwrap()
        .add_edge_bc("bottom", EdgeBc::flux(k * 5.0))
        .unwrap();
    let snap = model_b.solve_steady().unwrap();
    check(&snap.temperature, "(b) fluxes");
    assert!(snap.balance.relative_residual() < 1e-12);
    // (c) transient from the linear field with the boundary prescribed.
    let system = model_a
        .set_initial_default(0.0)
        .unwrap()
        .assemble()
        .unwrap();
    let t0: Vec<f64> = mesh.nodes().iter().map(|p| linear(*p)).collect();
    let mut stepper = system.stepper(t0, 0.0).unwrap();
    for k in 0..5 {
        stepper
            .step(0.01 * (k + 1) as f64, if k < 2 { 1.0 } else { 0.5 })
            .unwrap();
    }
    check(stepper.temperature(), "(c) transient");
    assert!(stepper.balance().stored_change.abs() < 1e-10);
}

/// Reference: 1D conduction through two blocks in series joined by an
/// interface of conductance h_c: a piecewise-linear field with a jump
/// ⟦T⟧ = T(x_m⁺) − T(x_m⁻) = −q/h_c, q = −k₁ T'₁ = −k₂ T'₂.
/// Goal: reproduced to round-off on distorted blocks, nodal and Gauss
/// interface integration (the element reproduces a uniform jump).
///
/// ```text
///   x = 0 (T = 10)   left k₁ = 1   ║ h_c = 4 ║  right k₂ = 3   x = 1 (T = 0)
///   +--+--+--+--+--+--+--+--+--+--╫--+--+--+--+--+--+--+--+--+--+
/// ```
/// BCs: `west` T = 10, `east` T = 0, `south`/`north` adiabatic.
#[test]
fn patch_test_two_bodies_across_an_interface() {
    let (k1, k2, hc, ta, tb, xm) = (1.0, 3.0, 4.0, 10.0, 0.0, 0.4);
    // Series resistances per unit area.
    let q = (ta - tb) / (xm / k1 + 1.0 / hc + (1.0 - xm) / k2);
    let exact = |p: [f64; 2], left: bool| {
        if left {
            ta - q * p[0] / k1
        } else {
            tb + q * (1.0 - p[0]) / k2
        }
    };
    let base = two_blocks(1.0, xm, 0.6, 4, 5);
    let mesh = distorted(&base, 0.1, 0.25);
    for rule in [InterfaceQuadrature::Nodal, InterfaceQuadrature::Gauss2] {
        let mut model = ThermalModel::new(&mesh);
        model
            .set_material("left", Material::new(k1, 1.0, 1.0))
            .unwrap()
            .set_material("right", Material::new(k2, 1.0, 1.0))
            .unwrap()
            .add_edge_bc("west", EdgeBc::temperature(ta))
            .unwrap()
            .add_edge_bc("east", EdgeBc::temperature(tb))
            .unwrap()
            .set_interface_law(
                "mid",
                tecon_thermal::ConstantConductance::new(hc).unwrap(),
                rule,
            )
            .unwrap();
        let snap = model.solve_steady().unwrap();
        let left_body =
            mesh.node_bodies()[mesh.triangles()[mesh.region_elements("left").unwrap()[0]][0]];
        let err = mesh
            .nodes()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                (snap.temperature[i] - exact(*p, mesh.node_bodies()[i] == left_body)).abs()
            })
            .fold(0.0, f64::max);
        println!(
            "two-body patch {rule:?}: max error {err:.2e}, jump {:.6} (exact {:.6})",
            snap.interfaces[0].elements[0].jump[0],
            -q / hc
        );
        assert!(err < 1e-11 * ta, "two-body patch {rule:?}: error {err:e}");
        for f in &snap.interfaces[0].elements {
            for p in 0..2 {
                assert_relative_eq!(f.jump[p], -q / hc, epsilon = 1e-11);
                assert_relative_eq!(f.flux[p], -q, epsilon = 1e-10);
            }
        }
        // Heat through the interface: −q × height 0.6 (top → bottom is −x).
        assert_relative_eq!(snap.interfaces[0].heat_rate, -q * 0.6, epsilon = 1e-10);
    }
}

// --------------------------------------------------------------------------
// The vessel: a transient run through the model entry point
// --------------------------------------------------------------------------

/// Reference: DESIGN.md §2 (vessel data); conservation of energy.
/// Goal: the weld cooling run on the paper mesh closes its heat balance to
/// 1e-10 at every output time, hits the output times exactly, reuses one
/// factorisation per distinct Δt, cools monotonically towards ambient and
/// keeps the element reference temperatures of the initial field.
///
/// ```text
///            layer + weld (θ < θ_w), 1132 °C in the weld, 21 °C elsewhere
///   outer ---------------------------------------- h = 10.25, T∞ = 21
///   layer  |weld|                                   6.4 mm
///   ====== core_layer interface, h_c = 850 ========
///   core                                            12.7 mm
///   inner ---------------------------------------- h = 10.25, T∞ = 21
///   sym0 (θ = 0) adiabatic               sym180 (θ = π) adiabatic
/// ```
#[test]
fn vessel_weld_cooling_closes_the_heat_balance() {
    use tecon_mesh::{VesselGeometry, VesselMeshSpec, vessel_mesh};
    let mesh = vessel_mesh(&VesselGeometry::default(), &VesselMeshSpec::paper()).unwrap();
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::vessel_steel())
        .unwrap()
        .add_edge_bc("inner", EdgeBc::convection(10.25, 21.0))
        .unwrap()
        .add_edge_bc("outer", EdgeBc::convection(10.25, 21.0))
        .unwrap()
        .set_interface_conductance("core_layer", 850.0)
        .unwrap()
        .set_initial_default(21.0)
        .unwrap()
        .set_initial_region("weld", 1132.0)
        .unwrap();
    let schedule =
        TimeSchedule::segments(&[(2.0, 0.05), (60.0, 1.0), (3600.0, 30.0), (36000.0, 600.0)])
            .unwrap();
    let outs = [0.0, 1.0, 10.0, 45.5, 600.0, 3600.0, 36000.0];
    let mut snaps = Vec::new();
    let summary = model
        .solve_transient(&schedule, ThetaScheme::crank_nicolson(), &outs, |s| {
            snaps.push(s.clone())
        })
        .unwrap();
    println!("vessel: {summary:?}");
    assert_eq!(snaps.len(), outs.len());
    let mut prev_max = f64::INFINITY;
    for (s, &t) in snaps.iter().zip(&outs) {
        assert_relative_eq!(s.time, t, epsilon = 1e-9 * t.max(1.0));
        let r = s.balance.relative_residual();
        let tmax = s.temperature.iter().cloned().fold(f64::MIN, f64::max);
        println!(
            "vessel t = {t:8.1} s: T max {tmax:8.3}, stored {:.6e} J/m, convected {:.6e} J/m, residual {r:.1e}, interface {:.3e} W/m",
            s.balance.stored_change, s.balance.convection_in, s.interfaces[0].heat_rate
        );
        assert!(r < 1e-10, "balance residual {r:e} at t = {t}");
        // Per body: stored change = boundary + interface inflow; what the
        // core gains through the interface the layer loses.
        assert_eq!(s.bodies.len(), 2);
        for b in &s.bodies {
            println!(
                "    body {:10}: stored {:.6e}, convected {:.6e}, through interface {:.6e}, residual {:.1e}",
                b.body,
                b.stored_change,
                b.convection_in,
                b.interface_in,
                b.relative_residual()
            );
            assert!(
                b.relative_residual() < 1e-10,
                "body {} residual {:e}",
                b.body,
                b.relative_residual()
            );
        }
        let (core, layer) = (&s.bodies[0], &s.bodies[1]);
        assert_eq!(
            (core.body.as_str(), layer.body.as_str()),
            ("core", "layer+weld")
        );
        assert!(
            (core.interface_in + layer.interface_in).abs()
                <= 1e-12 * core.interface_in.abs().max(1.0)
        );
        if t > 0.0 {
            assert!(core.interface_in > 0.0, "the core is heated by the weld");
        }
        assert!(tmax <= prev_max, "the hottest point must cool");
        prev_max = tmax;
    }
    // Factorisations: start-up BE + CN for the first Δt, CN for each later
    // segment, plus the sub-step at 45.5 s (two pieces of a 1 s step).
    assert!(summary.factorisations <= 2 + 3 + 2, "{summary:?}");
    let last = snaps.last().unwrap();
    // After 10 h the interior is nearly uniform and has lost heat to the air.
    let (lo, hi) = last
        .temperature
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &t| (a.min(t), b.max(t)));
    assert!(
        hi - lo < 1e-3 && (lo - 21.0).abs() < 1e-3,
        "back at ambient: {lo} … {hi}"
    );
    // ... so the heat lost is the initial excess content of the weld,
    // Σ_weld ρc A (1132 − 21) (the border rule keeps the content).
    let rc = Material::vessel_steel().volumetric_capacity();
    let areas = mesh.areas();
    let excess: f64 = mesh
        .region_elements("weld")
        .unwrap()
        .iter()
        .map(|&e| rc * areas[e] * (1132.0 - 21.0))
        .sum();
    println!("vessel: excess heat of the weld {excess:.6e} J/m");
    assert_relative_eq!(-last.balance.stored_change, excess, max_relative = 1e-4);
    assert_relative_eq!(-last.balance.convection_in, excess, max_relative = 1e-4);
    // Reference temperatures: weld elements away from the border keep 1132.
    let system = model.assemble().unwrap();
    let t_ref = system.reference_temperature().unwrap();
    let weld = mesh.region_elements("weld").unwrap();
    let reg = system.region_initial_temperature().unwrap();
    for &e in &weld {
        assert_eq!(reg[e], 1132.0);
    }
    let tmax_ref = t_ref.iter().cloned().fold(f64::MIN, f64::max);
    assert!(tmax_ref > 21.0 && tmax_ref <= 1132.0);
    // Initial heat content with the lumped-equivalent weights equals the
    // region field's content (capacity-weighted border rule).
    let w = system.capacity_weights();
    let t0 = system.initial_temperature().unwrap();
    let content: f64 = w.iter().zip(t0).map(|(a, b)| a * b).sum();
    let exact: f64 = areas.iter().zip(reg).map(|(a, t)| rc * a * t).sum();
    assert_relative_eq!(content, exact, max_relative = 1e-12);
}

/// Reference: the θ-method's amplification factor (1 − (1−θ)λΔt)/(1 + θλΔt)
/// tends to −1 for Crank–Nicolson and to 0 for backward Euler as λΔt → ∞.
/// Goal: with a discontinuous initial field and a large step (λ_maxΔt ≈ 80),
/// pure CN oscillates (the exact solution decreases monotonically in x;
/// CN's odd–even mode makes it rise from node to node), while CN started
/// with two backward-Euler steps is monotone up to a small fraction;
/// lumped backward Euler is monotone exactly.
///
/// ```text
///   T = 1 for x < 0.5, 0 for x ≥ 0.5      +--+--+-- ... --+  100 cells
/// ```
/// BCs: all edges adiabatic (the heat content is conserved).
#[test]
fn crank_nicolson_start_up_removes_the_oscillation_of_a_discontinuity() {
    let mesh = rectangle(0.0, 0.0, 1.0, 0.01, 100, 1).unwrap();
    let mut model = ThermalModel::new(&mesh);
    model
        .set_material_everywhere(Material::new(1.0, 1.0, 1.0))
        .unwrap()
        .set_capacity(CapacityKind::Lumped)
        .set_initial_default(0.0)
        .unwrap();
    for (i, p) in mesh.nodes().iter().enumerate() {
        if p[0] < 0.5 {
            model.set_initial_node(i, 1.0).unwrap();
        }
    }
    let schedule = TimeSchedule::uniform(2e-3, 5).unwrap();
    // Largest rise T(x_{i+1}) − T(x_i) along the bottom row (nodes 0..=100).
    let rise = |scheme: ThetaScheme| {
        let snaps = model
            .solve_transient_collect(&schedule, scheme, &[2e-3, 4e-3, 6e-3, 8e-3, 1e-2])
            .unwrap();
        let mut worst: f64 = 0.0;
        for s in &snaps {
            let r = s.balance.relative_residual();
            assert!(r < 1e-10, "balance residual {r:e}");
            assert!(s.bodies[0].relative_residual() < 1e-10);
            // Adiabatic: the content does not change.
            assert!(s.balance.stored_change.abs() < 1e-12);
            for w in s.temperature[..=100].windows(2) {
                worst = worst.max(w[1] - w[0]);
            }
        }
        worst
    };
    let pure = rise(ThetaScheme::new(0.5, 0).unwrap());
    let started = rise(ThetaScheme::crank_nicolson());
    let be = rise(ThetaScheme::backward_euler());
    println!("largest rise along x: pure CN {pure:.3e}, CN + 2 BE {started:.3e}, BE {be:.3e}");
    assert!(pure > 0.1, "pure CN should oscillate here ({pure})");
    assert!(started < 1e-3, "the start-up should remove it ({started})");
    assert!(be <= 1e-14, "lumped BE is monotone ({be})");
}
