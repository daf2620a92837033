//! End-to-end verification of the welded-vessel case (`tecon vessel`).
//!
//! Reference: DESIGN.md §2 (published data) and the two-cylinder shrink-fit
//! model. Goal: the published case runs on the paper mesh; the cooled
//! vessel has a compressive core and a tensile layer in the circumferential
//! mean; the net hoop force of the half section vanishes; the prestress
//! converges under mesh refinement; the heat balance closes.
//!
//! ```text
//!   half cross-section θ ∈ [0, π], weld at θ = 0 (layer only)
//!   layer ─────────────  h = 10.25 W/m²K outside, 850 W/m²K to the core
//!   core  ─────────────  h = 10.25 W/m²K inside; u_y = 0 on y = 0
//! ```

use serde_json::Value;
use tecon_cli::builtin::InterfaceKind;
use tecon_cli::vessel::{VesselOptions, analyse, summary, write_outputs};
use tecon_elastic::InterfaceNormals;
use tecon_mesh::VesselMeshSpec;

fn run(spec: VesselMeshSpec) -> (Value, tecon_cli::vessel::VesselRun) {
    run_with(spec, InterfaceNormals::Smoothed)
}

fn run_with(
    spec: VesselMeshSpec,
    normals: InterfaceNormals,
) -> (Value, tecon_cli::vessel::VesselRun) {
    let o = VesselOptions {
        mesh: spec,
        normals,
        quiet: true,
        ..Default::default()
    };
    let run = analyse(&o).expect("vessel run");
    (summary(&run), run)
}

/// The largest contact pressure at the interface points of an output state.
fn largest_pressure(state: &tecon_cli::vessel::TimeResult) -> f64 {
    state
        .interface
        .iter()
        .map(|q| -q.traction[1])
        .fold(0.0, f64::max)
}

fn f(v: &Value, k: &str) -> f64 {
    v.pointer(k)
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("missing key {k}"))
}

/// The numbers of the `<DataArray Name="name">` inside `<section>` of a VTU.
fn vtu_array(text: &str, section: &str, name: &str) -> Vec<f64> {
    let start = text
        .find(&format!("<{section}>"))
        .unwrap_or_else(|| panic!("no {section}"));
    let s = &text[start..];
    let at = s
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("no {name} in {section}"));
    let s = &s[at..];
    let body = &s[s.find('>').unwrap() + 1..s.find("</DataArray>").unwrap()];
    body.split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect()
}

/// VTU of a P2 state (paper mesh at order 2): quadratic cells, the ZZ
/// indicator per cell, and points split per region: a node on the weld
/// edge has one point in the weld and one in the layer, each carrying its
/// own region's recovered (SPR) stress, never their average.
#[test]
fn p2_vtu_keeps_the_weld_edge_regions_apart() {
    let (_, run) = run(VesselMeshSpec {
        order: 2,
        ..VesselMeshSpec::paper()
    });
    let mesh = &run.mesh;
    let last = run.results.last().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p2.vtu");
    tecon_cli::writers::write_state_vtu(mesh, &path, last).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let n_el = mesh.n_triangles();
    let types = vtu_array(&text, "Cells", "types");
    assert_eq!(types.len(), n_el);
    assert!(types.iter().all(|&t| t == 22.0), "VTK_QUADRATIC_TRIANGLE");
    let zz = vtu_array(&text, "CellData", "zz_error_indicator");
    assert_eq!(zz.len(), n_el);
    assert!(zz.iter().all(|v| v.is_finite() && *v >= 0.0));
    assert!(zz.iter().any(|v| *v > 0.0));
    let conn = vtu_array(&text, "Cells", "connectivity");
    let node = vtu_array(&text, "PointData", "node");
    let polar = vtu_array(&text, "PointData", "stress_rr_tt_rt_Pa");
    let hoop = |p: usize| polar[3 * p + 1];
    let weld = mesh.region_index("weld").unwrap();
    let layer = mesh.region_index("layer").unwrap();
    let regions = mesh.element_regions();
    let t6 = mesh.triangles6().unwrap();
    // every cell's points are its own nodes and carry its region's σ*
    let mut point_of = std::collections::BTreeMap::new();
    for (e, t) in t6.iter().enumerate() {
        for a in 0..6 {
            let p = conn[6 * e + a] as usize;
            assert_eq!(node[p] as usize, t[a]);
            let x = mesh.nodes()[t[a]];
            let own = tecon_elastic::polar(last.stress.recovered_of(e)[a], x, [0.0; 2])[1];
            assert!(
                (hoop(p) - own).abs() <= 1e-9 * own.abs().max(1.0),
                "element {e} node {}: VTU {} vs recovered {own}",
                t[a],
                hoop(p)
            );
            point_of.insert((t[a], regions[e]), p);
        }
    }
    // the weld edge: nodes in both regions have two points, two values
    let mut edge = 0;
    let mut largest_jump: f64 = 0.0;
    for v in 0..mesh.n_nodes() {
        if let (Some(&pw), Some(&pl)) = (point_of.get(&(v, weld)), point_of.get(&(v, layer))) {
            edge += 1;
            assert_ne!(pw, pl);
            largest_jump = largest_jump.max((hoop(pw) - hoop(pl)).abs());
        }
    }
    assert!(edge >= 5, "weld edge nodes: {edge}");
    assert!(
        largest_jump > 1e6,
        "hoop jump across the weld edge {largest_jump} Pa"
    );
}

#[test]
fn published_case_on_the_paper_mesh() {
    let (v, run) = run(VesselMeshSpec::paper());
    assert_eq!(f(&v, "/mesh/nodes"), 108.0);
    assert_eq!(f(&v, "/mesh/triangles"), 136.0);
    assert_eq!(f(&v, "/mesh/interface_elements"), 17.0);
    // core compressive, layer tensile, everywhere in the circumferential mean
    for k in ["core_inner", "core_outer"] {
        assert!(f(&v, &format!("/final/hoop_mean/{k}")) < 0.0, "{k}");
    }
    for k in ["layer_inner", "layer_outer"] {
        assert!(f(&v, &format!("/final/hoop_mean/{k}")) > 0.0, "{k}");
    }
    let profile = tecon_cli::vessel::hoop_profile(&run, &run.results.last().unwrap().stress);
    for &(_, is_core, r, m) in &profile {
        assert!(if is_core { m < 0.0 } else { m > 0.0 }, "r = {r}: {m}");
    }
    // the half section carries no net hoop force (2 rows per body: trapezoid error)
    assert!(f(&v, "/final/hoop_force_balance_relative").abs() < 0.02);
    assert!(f(&v, "/thermal/heat_balance_max_rel_error") < 1e-10);
    assert!(f(&v, "/coupling_delta") < 0.02 && f(&v, "/coupling_delta") > 0.01);
    assert!(f(&v, "/final/contact_pressure_mean") > 0.0);
    // the ZZ estimate of the cooled state: a fraction, not zero
    let zz = f(&v, "/final/zz_error/relative");
    assert!(zz > 0.0 && zz < 1.0, "ZZ relative {zz}");
    assert!(
        f(&v, "/final/max_temperature_change") < 1e-3,
        "cooled to ambient"
    );
    // the analytical interference α ΔT w / 2π
    let delta = 12.51e-6 * 1111.0 * 7.6e-3 / (2.0 * std::f64::consts::PI);
    assert!((f(&v, "/analytical/interference") / delta - 1.0).abs() < 1e-12);
    // FE and analytical agree in sign and order of magnitude
    let ratio = f(&v, "/final/hoop_mean/layer_outer") / f(&v, "/analytical/hoop/layer_outer");
    assert!(ratio > 0.5 && ratio < 3.0, "FE / analytical = {ratio}");
    let keys = [
        "/final/hoop_force_balance",
        "/analytical/contact_pressure",
        "/analytical/hoop/core_inner",
        "/analytical/hoop/core_outer",
        "/analytical/hoop/layer_inner",
        "/analytical/hoop/layer_outer",
        "/newton/max_iterations_per_increment",
        "/newton/max_iterations_per_pass",
    ];
    for k in keys {
        f(&v, k);
    }
    // outputs
    let dir = tempfile::tempdir().unwrap();
    write_outputs(&run, &v, dir.path()).unwrap();
    for name in [
        "summary.json",
        "fig6_temperature_circumference.csv",
        "fig6_temperature_circumference.svg",
        "fig6_temperature_circumference.png",
        "fig7_temperature_through_wall.csv",
        "fig8_hoop_prestress_through_wall.csv",
        "fig9_hoop_circumference.csv",
        "fig10_tangential_displacement.csv",
        "fig11_hoop_fe_vs_analytical.png",
        "fig11_hoop_fe_vs_analytical.csv",
        "interface_final.csv",
        "interface_contact_pressure.csv",
        "interface_contact_pressure.svg",
        "interface_slip.csv",
        "interface_slip.png",
        "vessel.pvd",
        "vessel_000.vtu",
    ] {
        assert!(dir.path().join(name).exists(), "{name} missing");
    }
    // every figure (SVG) has its data (CSV) beside it
    for e in std::fs::read_dir(dir.path()).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().to_string();
        if let Some(stem) = name.strip_suffix(".svg") {
            assert!(
                dir.path().join(format!("{stem}.csv")).exists(),
                "{name} has no {stem}.csv"
            );
        }
    }
    let back: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(back["mesh"]["nodes"], 108);
}

/// The mean hoop prestress converges under refinement: from level 0 to 1 to
/// 2 the values move monotonically and by less each time (observed change
/// ratios 0.21 core inner, 0.12 layer outer, 0.23 contact pressure).
#[test]
fn prestress_converges_under_refinement() {
    let vals: Vec<[f64; 3]> = (0..3)
        .map(|l| {
            let (v, _) = run(VesselMeshSpec::refined(l).unwrap());
            [
                f(&v, "/final/hoop_mean/core_inner"),
                f(&v, "/final/hoop_mean/layer_outer"),
                f(&v, "/final/contact_pressure_mean"),
            ]
        })
        .collect();
    eprintln!("levels 0..2: {vals:?}");
    #[allow(clippy::needless_range_loop)] // k indexes three quantities across three meshes
    for k in 0..3 {
        let d1 = (vals[1][k] - vals[0][k]).abs();
        let d2 = (vals[2][k] - vals[1][k]).abs();
        let (s1, s2) = (vals[1][k] - vals[0][k], vals[2][k] - vals[1][k]);
        assert!(s1 * s2 > 0.0, "quantity {k}: not monotone ({s1:e}, {s2:e})");
        assert!(d2 < d1, "quantity {k}: changes {d1:e} then {d2:e}");
    }
}

/// Level 2 (2176 triangles) against the two-cylinder model that is
/// consistent with plane strain (free in-plane shrinkage (1 + ν) α ΔT of the
/// weld, interference (1 + ν) α ΔT w / 2π): the circumferential means agree
/// although the FE contact is not uniform (observed: pressure −0.1 %, hoop
/// stresses +0.0 … +0.8 %). And the contact is closed everywhere away from
/// the weld: with one (smoothed) normal per interface node, a tangential
/// slip on the curved interface does not open every other point (with chord
/// normals it did: half the points open by ±slip·sin(Δθ/2)).
#[test]
fn level_2_matches_the_plane_strain_consistent_shrink_fit() {
    let (v, run) = run(VesselMeshSpec::refined(2).unwrap());
    let c = "/analytical_variants/plane_strain_consistent";
    let rel = |fe: &str, an: &str| f(&v, fe) / f(&v, &format!("{c}/{an}")) - 1.0;
    let p = rel("/final/contact_pressure_mean", "contact_pressure");
    eprintln!("pressure {p:+.2e}");
    assert!(p.abs() < 0.01, "contact pressure {p:+.3e}");
    for k in ["core_inner", "core_outer", "layer_inner", "layer_outer"] {
        let d = rel(&format!("/final/hoop_mean/{k}"), &format!("hoop/{k}"));
        eprintln!("{k} {d:+.2e}");
        assert!(d.abs() < 0.02, "{k}: {d:+.3e}");
    }
    let last = run.results.last().unwrap();
    let mut closed_beyond = 0;
    for pt in &last.interface {
        let theta = pt.position[1].atan2(pt.position[0]).to_degrees();
        if theta > 5.0 {
            assert_ne!(
                pt.status,
                tecon_contact::ContactStatus::Open,
                "open at θ = {theta:.2}°"
            );
            closed_beyond += 1;
        }
    }
    assert!(
        2 * closed_beyond > last.interface.len(),
        "{closed_beyond} of {}",
        last.interface.len()
    );
}

/// The classical element (each element's chord normal) overestimates the
/// prestress on coarse meshes — the slip over the curved core opens every
/// other interface point — and the excess over the smoothed-normal result
/// vanishes at first order (observed layer outer: +0.95, +0.44, +0.21 MPa
/// on the paper mesh, level 1, level 2).
#[test]
fn chord_normals_converge_to_the_smoothed_result() {
    let excess: Vec<f64> = (0..3)
        .map(|l| {
            let spec = VesselMeshSpec::refined(l).unwrap();
            let (e, _) = run_with(spec, InterfaceNormals::Element);
            let (s, _) = run(spec);
            f(&e, "/final/hoop_mean/layer_outer") - f(&s, "/final/hoop_mean/layer_outer")
        })
        .collect();
    eprintln!("chord-normal excess, layer outer: {excess:?} Pa");
    assert!(excess.iter().all(|&d| d > 0.0));
    for w in excess.windows(2) {
        let ratio = w[1] / w[0];
        assert!(ratio > 0.3 && ratio < 0.65, "halving h: ratio {ratio}");
    }
}

/// The same numbers whatever the thread count (level 1; bitwise).
#[test]
fn results_do_not_depend_on_the_thread_count() {
    let runs: Vec<[f64; 3]> = [1, 2, 3]
        .iter()
        .map(|&t| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .unwrap();
            let (v, _) = pool.install(|| run(VesselMeshSpec::refined(1).unwrap()));
            [
                f(&v, "/final/hoop_mean/layer_outer"),
                f(&v, "/final/contact_pressure_mean"),
                f(&v, "/final/hoop_force_balance"),
            ]
        })
        .collect();
    assert_eq!(runs[0], runs[1]);
    assert_eq!(runs[0], runs[2]);
}

/// Issue #12: the default run's answers (level 2, order 1, μ = 0.3) are
/// path independent — the Newton changes (front prediction, secant slip
/// damping) must not move them: reference values to 1e-6 relative.
/// High friction: μ = 1 (cohesion 0) converges on level 2; before the
/// secant slip damping (switched on at the first status ping-pong of a
/// pass) it stopped with "contact status ping-pong" in the first
/// increment. Measured: 209 iterations, at most 59 per increment (the
/// issue's goal of 40 is not met yet; μ = 2 still fails in the outer
/// friction-limit loop).
#[test]
fn default_answers_stay_and_mu_1_converges_on_level_2() {
    let (v, _) = run(VesselMeshSpec::refined(2).unwrap());
    let reference = [
        ("/final/hoop_mean/core_inner", -2164867.0139),
        ("/final/hoop_mean/core_outer", -2131646.2969),
        ("/final/hoop_mean/layer_inner", 4333583.0057),
        ("/final/hoop_mean/layer_outer", 4299948.2182),
        ("/final/contact_pressure_mean", 35183.126481),
    ];
    for (k, want) in reference {
        let got = f(&v, k);
        assert!(
            ((got - want) / want).abs() < 1e-6,
            "{k}: {got} against the reference {want}"
        );
    }
    let o = VesselOptions {
        mesh: VesselMeshSpec::refined(2).unwrap(),
        friction: 1.0,
        quiet: true,
        ..Default::default()
    };
    let run = analyse(&o).expect("μ = 1 converges on level 2");
    let v = summary(&run);
    let per_increment = f(&v, "/newton/max_iterations_per_increment");
    eprintln!("μ = 1, level 2: at most {per_increment} Newton iterations per increment");
    assert!(per_increment <= 60.0, "{per_increment}");
}

/// μ = 2 (cohesion 0): the frozen friction limits' outer updates used to
/// alternate without settling (after 30 updates the limits still changed
/// by 5·10⁻³ of the largest contact pressure, in the first increment at
/// any load fraction); once they stagnate they are under-relaxed and
/// settle to the friction tolerance. A pass that fails after an update is
/// retried with the update halved (the outer cut-back). Measured: paper
/// 303 Newton iterations (at most 91 per increment, 21 outer updates),
/// level 2 539 (165; before the outer cut-back 734, through load
/// cut-backs) — far above the issue's goal of 40 per increment.
#[test]
fn mu_2_converges_on_paper_and_level_2() {
    for spec in [VesselMeshSpec::paper(), VesselMeshSpec::refined(2).unwrap()] {
        let o = VesselOptions {
            mesh: spec,
            friction: 2.0,
            quiet: true,
            ..Default::default()
        };
        let run = analyse(&o).expect("μ = 2 converges");
        let v = summary(&run);
        let p = f(&v, "/final/contact_pressure_mean");
        let hoop = f(&v, "/final/hoop_mean/layer_inner");
        eprintln!(
            "μ = 2: {} Newton iterations, at most {} per increment, {} outer updates; p = {p:.6e} Pa, layer hoop {hoop:.6e} Pa",
            f(&v, "/newton/iterations"),
            f(&v, "/newton/max_iterations_per_increment"),
            f(&v, "/newton/max_augmentations_per_increment")
        );
        assert!(p > 0.0 && hoop > 0.0, "p = {p}, hoop = {hoop}");
    }
}

/// μ = 10 (cohesion 0) on level 2 stopped after 30 outer updates of the
/// frozen friction limits in the first increment, still converging: the
/// relaxed updates of so high a friction shrink slowly. Past the limit the
/// updates now go on while their change halves every 20 updates (up to
/// 10 × the limit). Measured: 81 outer updates in the worst increment, 937
/// Newton iterations; the mean contact pressure continues the trend of
/// lower friction (35 183 Pa at μ = 0.3, 35 263 Pa at μ = 2, 35 599 Pa at
/// μ = 10). Since session 38's stick predictions from cut-short steps μ =
/// 10 takes 25 outer updates (489 Newton iterations, the same pressure)
/// and no longer needs the extension; μ = 7 did (33 updates) until session
/// 40's coupled tail after a single pass settled both ways (24 updates);
/// μ = 9 did (34 updates) until session 42's stick predictions in coupled
/// passes (8 updates; level 2 at μ = 6 to 15 now takes at most 25), so
/// the extension is checked in the elastic crate's tests
/// (`an_outer_loop_that_still_converges_goes_past_its_update_limit`,
/// with a lower limit). μ = 5 on the paper mesh converged too, through 397 load
/// increments and 16 101 Newton iterations, on a path that any change of
/// the solves' rounding could break (the statuses of a few points flip
/// between outer updates); on level 2 it failed, its change stopped
/// shrinking. An increment whose frozen limits stall is now solved by the
/// coupled Mohr–Coulomb Newton (non-symmetric tangent, the same Coulomb
/// fixed point): μ = 5 on the paper mesh takes 6 increments, 252 Newton
/// iterations plus 401 in the stalled attempts; on level 2, 13 increments
/// (4 of them coupled), 1 974 plus 3 208 in failed attempts, with the mean contact pressure
/// between those of μ = 2 and μ = 10 and every point within 1e-4 of the
/// largest pressure of the Coulomb conditions (|τ| ≤ μp sticking,
/// |τ| = μp slipping).
#[test]
fn high_friction_converges_past_the_outer_limit() {
    let run = |mesh: VesselMeshSpec, friction: f64| {
        let o = VesselOptions {
            mesh,
            friction,
            quiet: true,
            ..Default::default()
        };
        summary(&analyse(&o).unwrap_or_else(|e| panic!("μ = {friction}: {e}")))
    };
    let level2 = || VesselMeshSpec::refined(2).unwrap();
    let (v2, v10) = (run(level2(), 2.0), run(level2(), 10.0));
    // μ = 5 on the paper mesh (it stopped after 30 updates too)
    let v5 = run(VesselMeshSpec::paper(), 5.0);
    assert!(f(&v5, "/final/contact_pressure_mean") > 0.0);
    // μ = 5 on level 2: the stalled increments go to the coupled Newton
    let o5 = VesselOptions {
        mesh: level2(),
        friction: 5.0,
        quiet: true,
        ..Default::default()
    };
    let r5 = analyse(&o5).unwrap_or_else(|e| panic!("μ = 5 on level 2: {e}"));
    let s5 = summary(&r5);
    assert!(f(&s5, "/newton/coupled_increments") > 0.0);
    assert!(f(&s5, "/newton/failed_attempt_iterations") > 0.0);
    let last = r5.results.last().expect("a final state");
    let p_max = largest_pressure(last);
    let mut worst: f64 = 0.0;
    for q in &last.interface {
        let (tau, p) = (q.traction[0].abs(), (-q.traction[1]).max(0.0));
        let violation = match q.status {
            tecon_contact::ContactStatus::Stick => tau - 5.0 * p,
            tecon_contact::ContactStatus::Slip => (tau - 5.0 * p).abs(),
            tecon_contact::ContactStatus::Open => tau,
        };
        worst = worst.max(violation / p_max);
    }
    assert!(
        worst < 2e-4,
        "Coulomb violated by {worst:.2e} of the largest pressure"
    );
    let (p2, p10) = (
        f(&v2, "/final/contact_pressure_mean"),
        f(&v10, "/final/contact_pressure_mean"),
    );
    assert!(
        p10 > p2 && p10 < 1.05 * p2,
        "p = {p10} at μ = 10, {p2} at μ = 2"
    );
    let p5 = f(&s5, "/final/contact_pressure_mean");
    assert!(
        p5 > p2 && p5 < p10,
        "p = {p5} at μ = 5, {p2} at μ = 2, {p10} at μ = 10"
    );
}

/// μ = 2 (cohesion 0) on the default mesh (g0, order 2) failed in the first
/// increment: after the first outer update the friction limits jump from 0
/// (everything slips) to 2p, pass 2's Newton stalls (slip directions
/// reversing across the thin stick band), and a smaller load increment is
/// the same problem scaled. The outer cut-back retries that pass with the
/// update halved (the same fixed point). Measured: converged in 9
/// increments, 2 818 Newton iterations (at most 889 in one increment,
/// counting the failed passes); 1 988 (at most 693) since open points that
/// slide on their frozen limit count as sliding. The answer continues the trend of lower
/// friction (mean contact pressure 35 258.2 Pa at μ = 0.3, 35 257.7 Pa at
/// μ = 1, 35 257.3 Pa at μ = 2): checked to 1e-4.
#[test]
fn mu_2_converges_on_the_default_mesh() {
    let p = mu_2_contact_pressure(VesselOptions::default().mesh, "the default mesh");
    assert!(((p - 35257.7) / 35257.7).abs() < 1e-4, "p = {p}");
}

/// The mean contact pressure of a μ = 2 run on `mesh` (which must converge),
/// with its Newton counts printed.
fn mu_2_contact_pressure(mesh: VesselMeshSpec, name: &str) -> f64 {
    let o = VesselOptions {
        mesh,
        friction: 2.0,
        quiet: true,
        ..Default::default()
    };
    let run = analyse(&o).unwrap_or_else(|e| panic!("μ = 2 on {name}: {e}"));
    let v = summary(&run);
    let p = f(&v, "/final/contact_pressure_mean");
    eprintln!(
        "μ = 2, {name}: {} Newton iterations, at most {} per increment; p = {p:.6e} Pa",
        f(&v, "/newton/iterations"),
        f(&v, "/newton/max_iterations_per_increment"),
    );
    p
}

/// μ = 2 on `t1e5` (99 144 linear triangles) stopped in the first
/// increment, pass 12, with short line-search steps and no status change:
/// open points near the opening front that slide on their frozen friction
/// limit crossed their stick/slip kinks unseen. Their status now records
/// it. Measured then: 1 822 Newton iterations, at most 530 per increment,
/// about 280 s (release), p = 35 256.75 Pa (μ = 0.3: 35 256.32, μ = 1:
/// 35 256.82). Issue #12's goal, at most 40 Newton iterations in one
/// increment and 15 in one pass, is met since session 42 (30 / 13, 159
/// iterations, about 8 s in release; 26 / 13 since the reopened-point
/// step), and checked here with the pressure.
#[test]
fn mu_2_converges_on_t1e5() {
    let o = VesselOptions {
        mesh: VesselMeshSpec::with_triangles(100_000).unwrap(),
        friction: 2.0,
        quiet: true,
        ..Default::default()
    };
    let v = summary(&analyse(&o).unwrap_or_else(|e| panic!("μ = 2 on t1e5: {e}")));
    let p = f(&v, "/final/contact_pressure_mean");
    assert!(((p - 35256.75) / 35256.75).abs() < 1e-4, "p = {p}");
    let (inc, pass) = (
        f(&v, "/newton/max_iterations_per_increment"),
        f(&v, "/newton/max_iterations_per_pass"),
    );
    assert!(
        inc <= 40.0 && pass <= 15.0,
        "{inc} / {pass} Newton iterations in one increment / pass"
    );
}

/// Issue #12: the most Newton iterations in one increment on level 2
/// (2 176 linear triangles, 276 interface dofs) and on `t1e5` (99 144,
/// 1 840 interface dofs) differ by at most 5, frictionless, at μ = 0.3
/// (the default joint) and at μ = 1 (18 and 20 since session 42), and
/// bonded. Both condense their passes onto the interface, and
/// both get there through the coarse interface space before the first
/// pass of an increment that has no friction limit yet (counted apart:
/// `newton.coarse_iterations`), without which they took 13 / 26 and
/// 30 / 42. Measured: level 2 11 / 16, `t1e5` 14 / 21, after at most 25
/// / 12 and 48 / 30 coarse steps (a frictionless joint's first passes
/// take two coarse levels). (At μ = 2 they still differ, by 8: README,
/// "Known limits".)
#[test]
fn level_2_and_t1e5_take_as_many_newton_iterations() {
    for (interface, friction) in [
        (InterfaceKind::Frictionless, 0.0),
        (InterfaceKind::Frictional, 0.3),
        (InterfaceKind::Frictional, 1.0),
        (InterfaceKind::Bonded, 0.0),
    ] {
        let go = |mesh: VesselMeshSpec| {
            let o = VesselOptions {
                mesh,
                interface,
                friction,
                quiet: true,
                ..Default::default()
            };
            summary(&analyse(&o).expect("vessel run"))
        };
        let coarse = go(VesselMeshSpec::refined(2).unwrap());
        let fine = go(VesselMeshSpec::with_triangles(100_000).unwrap());
        let (a, b) = (
            f(&coarse, "/newton/max_iterations_per_increment"),
            f(&fine, "/newton/max_iterations_per_increment"),
        );
        let steps = f(&fine, "/newton/max_coarse_iterations_per_increment");
        eprintln!("{interface:?} μ = {friction}: level 2 {a}, t1e5 {b} (+{steps} coarse steps)");
        // (a bonded joint is linear: two iterations, no coarse space)
        assert!(
            steps > 0.0 || interface == InterfaceKind::Bonded,
            "t1e5 took no coarse steps"
        );
        assert!((a - b).abs() <= 5.0, "level 2 {a} against t1e5 {b}");
        assert!(b <= 40.0, "t1e5: {b} in one increment");
    }
}

/// Issue #12, at most 15 Newton iterations in a pass: a frictionless
/// joint's first pass from the unloaded state on level 4 (34 816 linear
/// triangles, 1 092 interface dofs, passes condensed) took 18 after the
/// coarse steps of one coarse level (every 4th face node); with a second
/// level four times as wide taken first (the default) it takes 9, and the
/// answers are the same to the Newton tolerances (frictionless: no
/// friction path). Measured: 20 / 18 → 12 / 9 most iterations in one
/// increment / pass, 62 → 83 coarse steps, hoop means within 1e-9.
#[test]
fn two_coarse_levels_shorten_the_frictionless_first_pass_on_level_4() {
    let go = |coarse_levels: u32| {
        let o = VesselOptions {
            mesh: VesselMeshSpec::refined(4).unwrap(),
            interface: InterfaceKind::Frictionless,
            coarse_levels,
            quiet: true,
            ..Default::default()
        };
        summary(&analyse(&o).expect("level 4 converges"))
    };
    let one = go(1);
    let two = go(2);
    let pass = |s: &Value| f(s, "/newton/max_iterations_per_pass");
    eprintln!(
        "most in one pass: one level {}, two levels {}; coarse steps {} and {}",
        pass(&one),
        pass(&two),
        f(&one, "/newton/coarse_iterations"),
        f(&two, "/newton/coarse_iterations")
    );
    assert!(pass(&two) <= 15.0 && pass(&two) < pass(&one));
    assert!(f(&two, "/newton/max_iterations_per_increment") <= 40.0);
    for k in [
        "/final/hoop_mean/core_inner",
        "/final/hoop_mean/layer_outer",
        "/final/contact_pressure_mean",
    ] {
        let (a, b) = (f(&one, k), f(&two, k));
        assert!(((a - b) / a).abs() < 1e-7, "{k}: one level {a}, two {b}");
    }
}

/// Issue #12: Newton passes condensed onto the interface dofs (the bulk
/// condensed once, the interior recovered after each pass) converge to the
/// full passes' answers, bit for bit the same on 1, 2 and 3 threads. Level 4
/// (34 816 linear triangles, 1 092 interface dofs) is condensed by the
/// solver's rule (m² ≤ the sparse factor's entries). The two differ by the
/// Newton and augmented-Lagrangian tolerances only: measured 2.9e-9 at most
/// on the hoop means and the mean contact pressure; the bound is 1e-7 (the
/// augmented-Lagrangian tolerance is 1e-4 of the largest pressure, the
/// Newton tolerance 1e-8 of the force scale).
#[test]
fn condensed_passes_give_the_full_passes_answers() {
    let spec = VesselMeshSpec::refined(4).unwrap();
    // exact passes: inexact ones stop wherever their residual first
    // falls below the forcing, which the rounding of the two solves moves
    // (see `inexact_passes_keep_the_answers`)
    let go = |condensation: bool, threads: usize| {
        let o = VesselOptions {
            mesh: spec,
            condensation,
            exact_passes: true,
            quiet: true,
            ..Default::default()
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        summary(&pool.install(|| analyse(&o)).expect("level 4 converges"))
    };
    let full = go(false, 2);
    let condensed = go(true, 2);
    assert!(
        full.pointer("/newton/condensed_interface_dofs")
            .is_some_and(Value::is_null)
    );
    assert_eq!(f(&condensed, "/newton/condensed_interface_dofs"), 1092.0);
    for k in [
        "/final/hoop_mean/core_inner",
        "/final/hoop_mean/core_outer",
        "/final/hoop_mean/layer_inner",
        "/final/hoop_mean/layer_outer",
        "/final/contact_pressure_mean",
    ] {
        let (a, b) = (f(&full, k), f(&condensed, k));
        assert!(((a - b) / a).abs() < 1e-7, "{k}: full {a}, condensed {b}");
    }
    for threads in [1, 3] {
        let other = go(true, threads);
        for k in [
            "/final/hoop_mean/layer_outer",
            "/final/contact_pressure_mean",
            "/final/hoop_force_balance",
            "/newton/iterations",
        ] {
            assert_eq!(f(&condensed, k), f(&other, k), "{threads} threads: {k}");
        }
    }
}

/// Passes that an update of the frozen friction limits follows stop once
/// their residual is a fraction of where it started (the forcing,
/// `SolverOptions::pass_forcing`); the pass that ends an increment is
/// exact. Goal (issue 12: the converged answers must not change, only the
/// path): on the default run the hoop means, the mean contact pressure and
/// the gap at 0.4° equal those of exact passes to 1e-6 relative, in fewer
/// Newton iterations. Measured: 91 iterations against 116, differences
/// 3.5e-9 (hoop), 8e-11 (pressure), 3.3e-9 (gap). At μ = 1 (level 2) the
/// path-dependent friction lets the two paths end anywhere within the
/// outer tolerance (friction limits settled to 1e-4 of the largest
/// pressure): bound 1e-4, measured 7e-11 here and 2e-6 on level 4.
#[test]
fn inexact_passes_keep_the_answers() {
    let go = |mesh: VesselMeshSpec, friction: f64, exact_passes: bool| {
        let o = VesselOptions {
            mesh,
            friction,
            exact_passes,
            quiet: true,
            ..Default::default()
        };
        let run = analyse(&o).expect("the vessel converges");
        let gap = tecon_cli::accuracy::gap_at(&run, 0.4);
        (summary(&run), gap)
    };
    let keys = [
        "/final/hoop_mean/core_inner",
        "/final/hoop_mean/core_outer",
        "/final/hoop_mean/layer_inner",
        "/final/hoop_mean/layer_outer",
        "/final/contact_pressure_mean",
    ];
    for (mesh, friction, bound) in [
        (VesselMeshSpec::graded(0).unwrap(), 0.3, 1e-6),
        (VesselMeshSpec::refined(2).unwrap(), 1.0, 1e-4),
    ] {
        let ((exact, gap_e), (inexact, gap_i)) =
            (go(mesh, friction, true), go(mesh, friction, false));
        let (n_e, n_i) = (
            f(&exact, "/newton/iterations"),
            f(&inexact, "/newton/iterations"),
        );
        eprintln!("μ = {friction}: {n_i} Newton iterations against {n_e} with exact passes");
        for k in keys {
            let (a, b) = (f(&exact, k), f(&inexact, k));
            eprintln!("  {k}: {:.2e}", ((a - b) / a).abs());
            assert!(((a - b) / a).abs() < bound, "{k}: exact {a}, inexact {b}");
        }
        eprintln!("  gap at 0.4°: {:.2e}", ((gap_e - gap_i) / gap_e).abs());
        assert!(
            ((gap_e - gap_i) / gap_e).abs() < bound,
            "gap: {gap_e} against {gap_i}"
        );
        if friction == 0.3 {
            assert!(n_i < n_e, "{n_i} iterations against {n_e}");
        }
        assert_eq!(f(&exact, "/newton/inexact_passes"), 0.0);
        assert!(f(&inexact, "/newton/inexact_passes") > 0.0);
    }
}

/// The early coupled passes are counted apart from the coupled tail: level
/// 2 at μ = 2 takes one in four of its six increments (session 42), each
/// among the coupled passes; without the coupled tail there are none.
#[test]
fn early_coupled_passes_are_counted() {
    let run = |coupled_tail: bool| {
        let o = VesselOptions {
            mesh: VesselMeshSpec::refined(2).unwrap(),
            friction: 2.0,
            coupled_tail,
            quiet: true,
            ..Default::default()
        };
        summary(&analyse(&o).expect("level 2 at μ = 2"))
    };
    let v = run(true);
    let (early, coupled) = (
        f(&v, "/newton/early_coupled_passes"),
        f(&v, "/newton/coupled_tail_passes"),
    );
    assert!(
        early > 0.0 && early <= coupled,
        "{early} early of {coupled}"
    );
    let v = run(false);
    assert_eq!(f(&v, "/newton/early_coupled_passes"), 0.0);
    assert_eq!(f(&v, "/newton/coupled_tail_passes"), 0.0);
}

/// A cohesive joint (c = 0.1 MPa, about three times the mean contact
/// pressure; μ = 0.3) converges on the paper mesh and on the default g0,
/// where it stopped before: a bond that healed whenever the faces touched
/// let a point at the edge of the lift-off flip between open without shear
/// and closed with the cohesion, and no equilibrium existed (paper: no
/// convergence at t = 1 s, g0 at the first load step). The cohesion now
/// breaks for good where the faces open (`JointState::cohesion_lost`), and
/// every output state obeys the law: open points carry no shear, sticking
/// ones at most c + μ p, and slipping ones sit on one of the two limits,
/// c + μ p (bonded) or μ p (debonded); both kinds occur. The summary
/// counts the debonded points, none without cohesion.
#[test]
fn a_cohesive_joint_debonds_and_converges() {
    let plain = analyse(&VesselOptions {
        mesh: VesselMeshSpec::paper(),
        quiet: true,
        ..Default::default()
    })
    .expect("the paper mesh without cohesion");
    assert_eq!(f(&summary(&plain), "/final/interface_points/debonded"), 0.0);
    let c = 1.0e5;
    for mesh in [VesselMeshSpec::paper(), tecon_cli::builtin::default_mesh()] {
        let o = VesselOptions {
            mesh,
            cohesion: c,
            quiet: true,
            ..Default::default()
        };
        let run = analyse(&o).unwrap_or_else(|e| panic!("c = 0.1 MPa on {mesh:?}: {e}"));
        let (mut bonded, mut debonded) = (0, 0);
        for state in &run.results {
            // (the frozen limits are within the outer loop's tolerance,
            // 1e-4 of the largest contact pressure, of the pressures)
            let p_max = largest_pressure(state);
            let mut worst: f64 = 0.0;
            for q in &state.interface {
                let (tau, p) = (q.traction[0].abs(), (-q.traction[1]).max(0.0));
                let (with, without) = (c + 0.3 * p, 0.3 * p);
                let violation = match q.status {
                    tecon_contact::ContactStatus::Stick => (tau - with).max(0.0),
                    tecon_contact::ContactStatus::Slip => {
                        if (tau - with).abs() < (tau - without).abs() {
                            bonded += 1;
                            (tau - with).abs()
                        } else {
                            debonded += 1;
                            (tau - without).abs()
                        }
                    }
                    tecon_contact::ContactStatus::Open => tau,
                };
                worst = worst.max(violation / p_max);
            }
            eprintln!(
                "t = {}: law violated by {worst:.2e} of the largest pressure",
                state.time
            );
            assert!(
                worst < 1e-4,
                "{mesh:?}: law violated by {worst:.2e} of p_max"
            );
        }
        eprintln!("{mesh:?}: slipping points on c + μp {bonded}, on μp {debonded}");
        assert!(f(&summary(&run), "/final/interface_points/debonded") > 0.0);
        assert!(
            bonded > 0 && debonded > 0,
            "{bonded} bonded, {debonded} debonded slipping points"
        );
    }
}

/// The fused weld on the default g0: near the weld's corner the penalty is
/// soft against the graded elements, and the multiplier updates of the
/// settled passes shrank by only ~0.78 each: 23 coupled-tail passes at
/// t = 1 s, 73 Newton iterations in that increment. Mixed (Anderson) from
/// the third settled update on, 39; the stopping test is the plain one.
#[test]
fn mixed_multiplier_updates_shorten_the_fused_weld() {
    let o = VesselOptions {
        mesh: VesselMeshSpec {
            fused_weld: true,
            ..tecon_cli::builtin::default_mesh()
        },
        quiet: true,
        ..Default::default()
    };
    let v = summary(&analyse(&o).expect("the fused weld on g0"));
    let (inc, mixed) = (
        f(&v, "/newton/max_iterations_per_increment"),
        f(&v, "/newton/mixed_multiplier_updates"),
    );
    eprintln!("fused weld: {inc} Newton iterations in one increment, {mixed} mixed updates");
    assert!(
        mixed > 0.0 && inc <= 45.0,
        "{inc} in one increment, {mixed} mixed"
    );
}
