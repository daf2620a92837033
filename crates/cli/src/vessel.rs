//! `tecon vessel`: the welded monolayer vessel of the first seed paper, end
//! to end: mesh → transient heat conduction of the cooling weld → plane-strain
//! thermoelastic contact at every output time → prestress, compared with the
//! analytical two-cylinder shrink fit.
//!
//! ```text
//! tecon vessel                                  # published case, default mesh
//! tecon vessel --mesh paper --out out/paper     # the published 108-node mesh
//! tecon vessel --pressure 10e6                  # operating hoop stress with and without prestress
//! tecon vessel --study mesh                     # mesh convergence
//! ```

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use serde_json::{Value, json};
use tecon_elastic::analytical::{Cylinders, ShrinkFit};
use tecon_elastic::{Analysis, InterfaceNormals, Material, StressField, polar};
use tecon_mesh::{Mesh, VesselMeshSpec, vessel_mesh};

use crate::driver::{self, LoadFactors};
use crate::setup;
use crate::writers::{self, HistoryProbe, StateFiles, csv};

pub use crate::builtin::{VesselData, VesselOptions, default_mesh, schedule};
pub use crate::driver::NewtonStats;
pub use crate::writers::CliResult;

/// Results at one output time of the cooling (the driver's state; the
/// temperatures are always present).
pub type TimeResult = crate::driver::State;

/// A finished vessel run.
#[derive(Debug)]
pub struct VesselRun {
    /// The options it ran with.
    pub options: VesselOptions,
    /// The mesh.
    pub mesh: Mesh,
    /// One result per output time; the last is the cooled state.
    pub results: Vec<TimeResult>,
    /// Operating state with the weld prestress (if a pressure was asked
    /// for): the internal pressure on the cooled state, its temperatures
    /// held.
    pub operating: Option<TimeResult>,
    /// Operating state without prestress (pressure alone).
    pub pressure_only: Option<(StressField, Vec<f64>)>,
    /// Largest relative heat-balance residual of the transient.
    pub heat_balance: f64,
    /// Thermal time steps.
    pub thermal_steps: usize,
    /// Notes from the solvers.
    pub notes: Vec<String>,
    /// Wall-clock seconds of the analysis (mesh, heat conduction, contact).
    pub seconds: f64,
    /// Of which: heat conduction.
    pub thermal_seconds: f64,
    /// Of which: the contact solves.
    pub contact_seconds: f64,
    /// Newton iterations and solves of the contact analysis.
    pub newton: NewtonStats,
    /// Names of the model interfaces.
    pub interfaces: Vec<String>,
    /// The points of the temperature history ([`history_probes`]).
    pub history_probes: Vec<HistoryProbe>,
    /// Their temperatures at every thermal step.
    pub history: Option<driver::TemperatureHistory>,
    /// Two-way coupling statistics (None: one-way).
    pub coupling: Option<crate::driver::CouplingStats>,
    /// The worst temperature outside the bounds of the maximum principle
    /// (None: every temperature inside; otherwise the notes carry a
    /// warning).
    pub bound_violation: Option<driver::BoundViolation>,
}

/// The coupling parameter δ = (3λ + 2μ)² α² T₀ / ((λ + 2μ) ρ c) at absolute temperature T₀ (K).
pub fn coupling_delta(d: &VesselData, t0_kelvin: f64) -> f64 {
    let m = Material {
        youngs_modulus: d.youngs_modulus,
        poisson_ratio: d.poisson_ratio,
        expansion: d.expansion,
    };
    let (l, mu) = (m.lambda(), m.mu());
    (3.0 * l + 2.0 * mu).powi(2) * d.expansion.powi(2) * t0_kelvin
        / ((l + 2.0 * mu) * d.density * d.specific_heat)
}

/// Runs the whole analysis (no files written): the published case as a
/// built-in case through the one driver, then (with a pressure) the
/// pressure alone for comparison.
pub fn analyse(options: &VesselOptions) -> CliResult<VesselRun> {
    let start = std::time::Instant::now();
    let o = options;
    if !(o.friction.is_finite() && o.friction >= 0.0) {
        return Err(format!(
            "--friction {}: must be a non-negative coefficient",
            o.friction
        )
        .into());
    }
    if !(o.cohesion.is_finite() && o.cohesion >= 0.0) {
        return Err(format!("--cohesion {}: must be non-negative (Pa)", o.cohesion).into());
    }
    let mut mesh = vessel_mesh(&o.geometry, &o.mesh)?;
    let case = crate::builtin::vessel_case(o, &mesh)?;
    setup::declare_interfaces(&case, &mut mesh)?;
    let tie = setup::tie(&case, &mesh)?;
    let history_probes = history_probes(&mesh, o);
    let nodes: Vec<usize> = history_probes.iter().map(|p| p.node).collect();
    let (outcome, pressure_only, bound_violation) = {
        let p = setup::prepare(&case, &mesh, tie.as_ref())?;
        let outcome =
            driver::run_recording(&p.setup, &nodes).map_err(|e| free_layer(e, o.pressure))?;
        let bound_violation = outcome.bound_violation.clone();
        let alone = match o.pressure {
            Some(_) => Some(
                driver::solve_mechanical(&p.setup, LoadFactors::FULL).map_err(|e| {
                    format!(
                        "the pressure alone (the comparison without the weld prestress): {}",
                        free_layer(e, o.pressure)
                    )
                })?,
            ),
            None => None,
        };
        (outcome, alone, bound_violation)
    };
    let mut results = Vec::new();
    let mut operating = None;
    for s in outcome.states {
        if s.stage == 0 {
            results.push(s);
        } else {
            operating = Some(s);
        }
    }
    Ok(VesselRun {
        options: o.clone(),
        mesh,
        results,
        operating,
        pressure_only,
        heat_balance: outcome.thermal.max_balance_residual.unwrap_or(0.0),
        thermal_steps: outcome.thermal.steps,
        notes: outcome.notes,
        seconds: start.elapsed().as_secs_f64(),
        thermal_seconds: outcome.thermal_seconds,
        contact_seconds: outcome.contact_seconds,
        newton: outcome.newton,
        interfaces: outcome.interfaces,
        history_probes,
        history: outcome.history,
        coupling: outcome.coupling,
        bound_violation,
    })
}

/// The points of the vessel's temperature history: in the weld plane
/// θ = 0 the weld centre on the outer surface, the core/layer interface on
/// the layer side and on the core side, and the core's inner surface; and
/// the layer's outer surface at θ = 90°, far from the weld. Each is the
/// node of its body on that circle nearest the angle (its actual angle in
/// the label when it differs, e.g. a fused weld leaves the layer no node
/// at θ = 0 on the interface).
pub fn history_probes(mesh: &Mesh, o: &VesselOptions) -> Vec<HistoryProbe> {
    let (core, layer) = bodies(mesh);
    let g = &o.geometry;
    let deg = |i: usize| r_theta(mesh.nodes()[i]).1.to_degrees();
    let spots = [
        (
            "weld_centre",
            "weld centre, outer surface",
            layer,
            g.outer_radius(),
            0.0,
        ),
        (
            "interface_layer",
            "interface, layer side",
            layer,
            g.interface_radius(),
            0.0,
        ),
        (
            "interface_core",
            "interface, core side",
            core,
            g.interface_radius(),
            0.0,
        ),
        (
            "core_inner",
            "core inner surface",
            core,
            g.inner_radius,
            0.0,
        ),
        (
            "far_field_90deg",
            "layer outer surface",
            layer,
            g.outer_radius(),
            90.0,
        ),
    ];
    spots
        .iter()
        .filter_map(|&(name, what, body, r, angle)| {
            let node = ring_nodes(mesh, body, r)
                .into_iter()
                .min_by(|&a, &b| (deg(a) - angle).abs().total_cmp(&(deg(b) - angle).abs()))?;
            Some(HistoryProbe {
                name: name.into(),
                label: format!(
                    "{what}, θ = {}°",
                    crate::plot::fmt_value((deg(node) * 100.0).round() / 100.0)
                ),
                node,
            })
        })
        .collect()
}

/// A solve that failed because a body is free, explained when `--pressure`
/// is negative: a vacuum inside pulls the core away from the layer, the
/// layer (held only by the interface) loses all contact and nothing holds
/// it, and the solver's advice (add a support …) cannot be followed on the
/// built-in vessel. Other errors are passed on as they are.
fn free_layer(
    e: driver::DriverError,
    pressure: Option<f64>,
) -> Box<dyn std::error::Error + Send + Sync> {
    if let Some(p) = pressure.filter(|p| *p < 0.0)
        && matches!(
            e.elastic(),
            Some(
                tecon_elastic::ElasticError::Fem(tecon_fem::FemError::Unconstrained { .. })
                    | tecon_elastic::ElasticError::Floating { .. }
            )
        )
    {
        return format!(
            "{e}. On the built-in vessel that cannot be done; the cause is the negative --pressure {p:e} Pa (a vacuum inside, a net external pressure): it pulls the core away from the layer, so the layer, held only by the core/layer interface, loses all contact and is free. Give a positive (internal) --pressure, or tie the layer to the core with --interface bonded"
        )
        .into();
    }
    e.into()
}

/// Polar coordinates (r, θ) of a point.
pub(crate) fn r_theta(p: [f64; 2]) -> (f64, f64) {
    ((p[0] * p[0] + p[1] * p[1]).sqrt(), p[1].atan2(p[0]))
}

/// Nodes of one body on the circle of radius `r`, sorted by θ.
pub(crate) fn ring_nodes(mesh: &Mesh, body: usize, r: f64) -> Vec<usize> {
    let tol = 1e-9 * r;
    let mut v: Vec<usize> = (0..mesh.n_nodes())
        .filter(|&i| mesh.node_bodies()[i] == body && (r_theta(mesh.nodes()[i]).0 - r).abs() < tol)
        .collect();
    v.sort_by(|&a, &b| {
        r_theta(mesh.nodes()[a])
            .1
            .total_cmp(&r_theta(mesh.nodes()[b]).1)
    });
    v
}

/// Body index of the core and of the layer (the same when the weld is fused).
pub(crate) fn bodies(mesh: &Mesh) -> (usize, usize) {
    let core = mesh
        .bodies()
        .iter()
        .position(|b| b.name.split('+').any(|n| n == "core"))
        .unwrap_or(0);
    let layer = mesh
        .bodies()
        .iter()
        .position(|b| b.name.split('+').any(|n| n == "layer"))
        .unwrap_or(0);
    (core, layer)
}

/// Radii of the node rows of each body: (body, r) from the inner surface out.
fn rows(o: &VesselOptions) -> Vec<(bool, f64)> {
    let g = &o.geometry;
    let (ri, rc, ro) = (g.inner_radius, g.interface_radius(), g.outer_radius());
    let mut v: Vec<(bool, f64)> = (0..=o.mesh.core_rows)
        .map(|j| (true, ri + (rc - ri) * j as f64 / o.mesh.core_rows as f64))
        .collect();
    v.extend(
        (0..=o.mesh.layer_rows)
            .map(|j| (false, rc + (ro - rc) * j as f64 / o.mesh.layer_rows as f64)),
    );
    v
}

/// Trapezoid mean over θ ∈ [0, π] of a nodal quantity on a ring of nodes.
fn ring_mean(mesh: &Mesh, nodes: &[usize], f: &dyn Fn(usize) -> f64) -> f64 {
    let mut s = 0.0;
    let mut w = 0.0;
    for k in 1..nodes.len() {
        let (a, b) = (nodes[k - 1], nodes[k]);
        let dt = r_theta(mesh.nodes()[b]).1 - r_theta(mesh.nodes()[a]).1;
        s += 0.5 * dt * (f(a) + f(b));
        w += dt;
    }
    if w > 0.0 { s / w } else { f64::NAN }
}

fn hoop(mesh: &Mesh, s: &StressField, i: usize) -> f64 {
    polar(s.nodal[i], mesh.nodes()[i], [0.0, 0.0])[1]
}

/// Circumferential mean of σ_θθ on every node row: (wall %, is core, r, mean).
pub fn hoop_profile(run: &VesselRun, s: &StressField) -> Vec<(f64, bool, f64, f64)> {
    let (core, layer) = bodies(&run.mesh);
    let g = &run.options.geometry;
    let (ri, ro) = (g.inner_radius, g.outer_radius());
    rows(&run.options)
        .into_iter()
        .map(|(is_core, r)| {
            let nodes = ring_nodes(&run.mesh, if is_core { core } else { layer }, r);
            let m = ring_mean(&run.mesh, &nodes, &|i| hoop(&run.mesh, s, i));
            (100.0 * (r - ri) / (ro - ri), is_core, r, m)
        })
        .collect()
}

/// ∫ σ̄_θθ dr through the wall (trapezoid per body), N/m, and ∫ |σ̄_θθ| dr.
fn hoop_force(profile: &[(f64, bool, f64, f64)]) -> (f64, f64) {
    let (mut f, mut fa) = (0.0, 0.0);
    for w in profile.windows(2) {
        if w[0].1 == w[1].1 {
            let dr = w[1].2 - w[0].2;
            f += 0.5 * dr * (w[0].3 + w[1].3);
            fa += 0.5 * dr * (w[0].3.abs() + w[1].3.abs());
        }
    }
    (f, fa)
}

/// The two analytical shrink-fit variants of DESIGN.md §2 and the issue's
/// (interference α ΔT w / 2π in plane strain).
pub fn analytical(o: &VesselOptions) -> [(&'static str, ShrinkFit); 3] {
    let g = &o.geometry;
    let d = &o.data;
    let dt = d.weld_temperature - d.ambient;
    let w = 2.0 * g.weld_half_width;
    let base = ShrinkFit {
        a: g.inner_radius,
        c: g.interface_radius(),
        b: g.outer_radius(),
        delta: d.expansion * dt * w / (2.0 * PI),
        e: d.youngs_modulus,
        nu: d.poisson_ratio,
        state: Cylinders::PlaneStrain,
    };
    [
        ("plane_strain", base),
        (
            "plane_stress_classical",
            ShrinkFit {
                state: Cylinders::PlaneStress,
                ..base
            },
        ),
        (
            "plane_strain_consistent",
            ShrinkFit {
                delta: (1.0 + d.poisson_ratio) * base.delta,
                ..base
            },
        ),
    ]
}

/// Mean contact pressure of the core/layer joint: arc-length weighted over
/// the interface points (open points count as 0); for a bonded interface
/// (no points) the mean of −σ_rr of the layer's nodes on the interface.
fn contact_pressure_mean(run: &VesselRun, r: &TimeResult) -> f64 {
    if run.options.interface == crate::builtin::InterfaceKind::Bonded {
        let (_, layer) = bodies(&run.mesh);
        let rc = run.options.geometry.interface_radius();
        let nodes = ring_nodes(&run.mesh, layer, rc);
        return -ring_mean(&run.mesh, &nodes, &|i| {
            polar(r.stress.nodal[i], run.mesh.nodes()[i], [0.0, 0.0])[0]
        });
    }
    writers::interface_summary(&r.interface, &r.interface_weights, 0)["contact_pressure_mean"]
        .as_f64()
        .unwrap_or(0.0)
}

/// The summary as JSON (SI units).
pub fn summary(run: &VesselRun) -> Value {
    let last = run.results.last();
    let (core, layer) = bodies(&run.mesh);
    let g = &run.options.geometry;
    let mean_at = |s: &StressField, body: usize, r: f64| {
        ring_mean(&run.mesh, &ring_nodes(&run.mesh, body, r), &|i| {
            hoop(&run.mesh, s, i)
        })
    };
    let hoop_keys = |s: &StressField| {
        json!({
            "core_inner": mean_at(s, core, g.inner_radius),
            "core_outer": mean_at(s, core, g.interface_radius()),
            "layer_inner": mean_at(s, layer, g.interface_radius()),
            "layer_outer": mean_at(s, layer, g.outer_radius()),
        })
    };
    let an = analytical(&run.options);
    let an_json = |f: &ShrinkFit| {
        json!({
            "interference": f.delta,
            "contact_pressure": f.pressure(),
            "hoop": {
                "core_inner": f.sigma_tt(f.a, true),
                "core_outer": f.sigma_tt(f.c, true),
                "layer_inner": f.sigma_tt(f.c, false),
                "layer_outer": f.sigma_tt(f.b, false),
            }
        })
    };
    let mut v = json!({
        "mesh": {
            "nodes": run.mesh.n_nodes(),
            "triangles": run.mesh.n_triangles(),
            "interface_elements": run.mesh.interfaces().values().map(|i| i.elements.len()).sum::<usize>(),
            "core_rows": run.options.mesh.core_rows,
            "layer_rows": run.options.mesh.layer_rows,
            "stations": run.options.mesh.stations,
        },
        "analytical": an_json(&an[0].1),
        "analytical_variants": {
            "plane_stress_classical": an_json(&an[1].1),
            "plane_strain_consistent": an_json(&an[2].1),
        },
        "thermal": {
            "capacity": run.options.capacity.name(),
            "heat_balance_max_rel_error": run.heat_balance,
            "steps": run.thermal_steps,
            "output_times": run.results.iter().map(|r| r.time).collect::<Vec<_>>(),
            // K by which the worst nodal temperature of any time step lies
            // outside [min, max] of the initial temperatures, the ambient
            // and any prescribed temperature (0: none, and no note); of the
            // output states alone (their stresses are computed)
            "bound_violation": run.bound_violation.as_ref().map_or(0.0, |b| b.excursion),
            "bound_violation_at_outputs": run.bound_violation.as_ref().map_or(0.0, |b| b.output_excursion),
        },
        "coupling_delta": coupling_delta(&run.options.data, run.options.data.ambient + 273.15),
        "coupling_delta_at_weld_temperature": coupling_delta(&run.options.data, run.options.data.weld_temperature + 273.15),
        "newton": {
            // over every contact solve, written or not (every state's solve is one)
            "max_iterations_per_increment": run.newton.max_per_increment,
            "max_iterations_per_pass": run.newton.max_per_pass,
            "max_augmentations_per_increment": run.newton.max_augmentations,
            "iterations": run.newton.iterations,
            "increments": run.newton.increments,
            "factorisations": run.newton.solves.factorisations,
            "reused_factorisations": run.newton.solves.reused,
            "low_rank_corrected_solves": run.newton.solves.corrected,
            // iterations of failed attempts (cut back or a stalled outer
            // loop), not in "iterations"
            "failed_attempt_iterations": run.newton.failed_iterations,
            // increments solved by the coupled Mohr–Coulomb Newton after the
            // outer loop of the frozen friction limits stalled
            "coupled_increments": run.newton.coupled_increments,
            // passes stopped early because a friction-limit update
            // followed (the last pass of every increment is exact)
            "inexact_passes": run.newton.inexact_passes,
            // the bulk condensed onto this many interface dofs (null: full passes)
            "condensed_interface_dofs": run.newton.condensed_dofs,
            // Newton steps in the coarse interface space before first
            // passes (not in "iterations"), and its dofs (null: none)
            "coarse_iterations": run.newton.coarse_iterations,
            "max_coarse_iterations_per_increment": run.newton.max_coarse_per_increment,
            "coarse_space_dofs": run.newton.coarse_dofs,
            // passes with the coupled law in the tail of an outer loop,
            // and of those the early coupled passes
            "coupled_tail_passes": run.newton.coupled_tail_passes,
            "early_coupled_passes": run.newton.early_coupled_passes,
            "mixed_multiplier_updates": run.newton.mixed_multiplier_updates,
        },
        "joint": {
            "interface": run.options.interface.name(),
            "friction": run.options.friction,
            "cohesion": run.options.cohesion,
            "penalty_factor": run.options.penalty_factor,
            "augmented_lagrangian": run.options.augmented_lagrangian,
        },
        "notes": run.notes,
        "seconds": run.seconds,
        "seconds_heat_conduction": run.thermal_seconds,
        "seconds_contact": run.contact_seconds,
    });
    if let Some(last) = last {
        let profile = hoop_profile(run, &last.stress);
        let (f, fa) = hoop_force(&profile);
        let open = last
            .interface
            .iter()
            .filter(|p| p.status == tecon_contact::ContactStatus::Open)
            .count();
        let slip = last
            .interface
            .iter()
            .filter(|p| p.status == tecon_contact::ContactStatus::Slip)
            .count();
        // points whose cohesion broke (a joint with cohesion; 0 without)
        let debonded = last.interface.iter().filter(|p| p.debonded).count();
        v["final"] = json!({
            "time": last.time,
            "hoop_mean": hoop_keys(&last.stress),
            "contact_pressure_mean": contact_pressure_mean(run, last),
            "hoop_force_balance": f,
            "hoop_force_balance_relative": if fa > 0.0 { f / fa } else { 0.0 },
            // every integration point of every interface element: a node
            // shared by two elements (nodal integration) counts twice
            "interface_points": {
                "open": open,
                "slip": slip,
                "debonded": debonded,
                "total": last.interface.len(),
                "counted": "integration points of the interface elements (with nodal integration a node shared by two elements counts twice); interface_nodes counts the rows of interface_final.csv",
            },
            // the rows of interface_final.csv: coinciding points merged, the
            // more open status kept (open before slip before stick)
            "interface_nodes": interface_nodes(&last.interface),
            "max_temperature_change": temperature(last).iter().map(|t| (t - run.options.data.ambient).abs()).fold(0.0, f64::max),
            "zz_error": {
                "eta": last.stress.error.eta,
                "relative": last.stress.error.relative(),
            },
        });
    }
    if let Some(c) = &run.coupling {
        v["coupling"] = coupling_json(c);
        v["coupling"]["per_output"] = json!(
            run.results
                .iter()
                .map(|r| r.coupling_iterations)
                .collect::<Vec<_>>()
        );
    } else {
        v["coupling"] = json!({ "mode": "one-way" });
    }
    v["conductance"] = json!(if run.options.contact_conductance {
        "contact"
    } else {
        "constant"
    });
    if let (Some(op), Some((alone, _)), Some(p)) =
        (&run.operating, &run.pressure_only, run.options.pressure)
    {
        v["operating"] = json!({
            "pressure": p,
            "hoop_mean_with_prestress": hoop_keys(&op.stress),
            "hoop_mean_pressure_only": hoop_keys(alone),
        });
    }
    if let Some(h) = &run.history {
        v["temperature_history"] = writers::history_summary(&run.mesh, &run.history_probes, h);
    }
    v
}

/// Prints the human-readable report.
pub fn report(run: &VesselRun, v: &Value) -> String {
    let f = |k: &str| v.pointer(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
    let mut s = String::new();
    s += &format!(
        "mesh: {} nodes, {} triangles, {} interface elements\n",
        run.mesh.n_nodes(),
        run.mesh.n_triangles(),
        run.mesh
            .interfaces()
            .values()
            .map(|i| i.elements.len())
            .sum::<usize>()
    );
    s += &format!(
        "heat conduction: {} steps to t = {:.0} s, heat balance residual ≤ {:.1e}\n",
        run.thermal_steps,
        run.results.last().map_or(0.0, |r| r.time),
        run.heat_balance
    );
    let delta = f("/coupling_delta");
    s += &format!(
        "coupling parameter δ = {delta:.4} at ambient ({:.3} at the weld temperature): δ ≪ 1, so neglecting the thermoelastic coupling term is justified\n",
        f("/coupling_delta_at_weld_temperature")
    );
    // the consistent two-cylinder model first: the FE converges to it; the
    // issue's interference αΔTw/2π beside it, as published
    s += "final prestress (circumferential mean of σ_θθ, MPa):\n";
    s +=
        "                      FE   two cylinders, δ = (1+ν)αΔTw/2π   δ = αΔTw/2π (plane strain)\n";
    for (k, label) in [
        ("core_inner", "core inner"),
        ("core_outer", "core outer"),
        ("layer_inner", "layer inner"),
        ("layer_outer", "layer outer"),
    ] {
        s += &format!(
            "  {label:<12} {:>9.4} {:>34.4} {:>28.4}\n",
            f(&format!("/final/hoop_mean/{k}")) / 1e6,
            f(&format!(
                "/analytical_variants/plane_strain_consistent/hoop/{k}"
            )) / 1e6,
            f(&format!("/analytical/hoop/{k}")) / 1e6
        );
    }
    s += &format!(
        "contact pressure mean: FE {:.5} MPa, analytical (δ = αΔTw/2π) {:.5} MPa (variants: plane stress {:.5}, plane-strain consistent {:.5})\n",
        f("/final/contact_pressure_mean") / 1e6,
        f("/analytical/contact_pressure") / 1e6,
        f("/analytical_variants/plane_stress_classical/contact_pressure") / 1e6,
        f("/analytical_variants/plane_strain_consistent/contact_pressure") / 1e6
    );
    s += &format!(
        "net hoop force of the half section: {:.3e} N/m ({:.2e} of ∫|σ_θθ| dr)\n",
        f("/final/hoop_force_balance"),
        f("/final/hoop_force_balance_relative")
    );
    if let (Some(n), Some(p)) = (
        v.pointer("/final/interface_nodes"),
        v.pointer("/final/interface_points"),
    ) {
        s += &format!(
            "final interface: {} positions in interface_final.csv ({} open, {} slip), from {} integration points of the interface elements ({} open, {} slip; with nodal integration a node shared by two elements counts twice there, once in the table, with the more open status)\n",
            n["total"], n["open"], n["slip"], p["total"], p["open"], p["slip"]
        );
        if p["debonded"].as_u64().is_some_and(|d| d > 0) {
            s += &format!(
                "the joint's cohesion broke for good at {} of the {} integration points (faces open at an outer update: debonded)\n",
                p["debonded"], p["total"]
            );
        }
    }
    let ratio_ps = f("/analytical_variants/plane_strain_consistent/contact_pressure")
        / f("/analytical_variants/plane_stress_classical/contact_pressure");
    s += &format!(
        "the plane-strain consistent model gives {:.0} % more pressure than the classical plane-stress one (the paper's FE was ~50 % above its analytical values)\n",
        100.0 * (ratio_ps - 1.0)
    );
    let dev = |fe: &str, an: &str| 100.0 * (f(fe) / f(an) - 1.0);
    let c = "/analytical_variants/plane_strain_consistent";
    s += &format!(
        "FE against the plane-strain consistent model: contact pressure {:+.1} %, hoop core inner {:+.1} %, core outer {:+.1} %, layer inner {:+.1} %, layer outer {:+.1} %\n",
        dev(
            "/final/contact_pressure_mean",
            &format!("{c}/contact_pressure")
        ),
        dev(
            "/final/hoop_mean/core_inner",
            &format!("{c}/hoop/core_inner")
        ),
        dev(
            "/final/hoop_mean/core_outer",
            &format!("{c}/hoop/core_outer")
        ),
        dev(
            "/final/hoop_mean/layer_inner",
            &format!("{c}/hoop/layer_inner")
        ),
        dev(
            "/final/hoop_mean/layer_outer",
            &format!("{c}/hoop/layer_outer")
        ),
    );
    for l in writers::history_lines(&v["temperature_history"]) {
        s += &l;
        s.push('\n');
    }
    s += &format!(
        "Newton: {} iterations in {} increments, at most {} in one increment, all passes counted, and {} in one pass (at most {} outer updates of multipliers and friction limits); {} factorisations, {} reused, {} low-rank corrected\n",
        run.newton.iterations,
        run.newton.increments,
        v["newton"]["max_iterations_per_increment"],
        v["newton"]["max_iterations_per_pass"],
        v["newton"]["max_augmentations_per_increment"],
        run.newton.solves.factorisations,
        run.newton.solves.reused,
        run.newton.solves.corrected,
    );
    if run.newton.failed_iterations > 0 {
        s += &format!(
            "  plus {} iterations in failed attempts (cut back{})\n",
            run.newton.failed_iterations,
            match run.newton.coupled_increments {
                0 => String::new(),
                k => format!(
                    "; {k} increment(s) whose outer loop of frozen friction limits stalled were solved by the coupled Mohr–Coulomb Newton"
                ),
            }
        );
    }
    if let Some(m) = run.newton.condensed_dofs {
        s += &format!(
            "Newton passes condensed onto the {m} interface dofs (the bulk condensed once; --no-condensation for full passes)\n"
        );
    }
    if let Some(c) = run.newton.coarse_dofs {
        s += &format!(
            "coarse interface space of {c} dofs: {} steps before first passes, at most {} before one increment, not counted as Newton iterations (--no-coarse-space to go without)\n",
            run.newton.coarse_iterations, run.newton.max_coarse_per_increment
        );
    }
    if let Some(c) = &run.coupling {
        s += &format!(
            "two-way coupling: {} blocks, {} coupling iterations (at most {} in one block, {} unsettled, final conductance change ≤ {:.1e}{})\n",
            c.blocks,
            c.iterations,
            c.max_iterations,
            c.unsettled,
            c.max_final_change,
            c.intermediate_outer_tolerance.map_or(String::new(), |f| format!(
                "; the contact solves between output times to {f:.1e} of the largest contact pressure in their outer loop"
            ))
        );
    }
    s += &format!(
        "time: {:.2} s (heat conduction {:.2} s, contact {:.2} s{})\n",
        run.seconds,
        run.thermal_seconds,
        run.contact_seconds,
        if run.coupling.is_some() {
            ""
        } else {
            "; side by side"
        }
    );
    for n in &run.notes {
        s += &format!("note: {n}\n");
    }
    s
}

/// Open, slip, stick and total counts of the interface positions, as the
/// rows of `interface_final.csv` count them ([`crate::figures::interface_rows`]:
/// coinciding points of one interface merged, the more open status kept).
fn interface_nodes(points: &[tecon_elastic::InterfacePointResult]) -> Value {
    let rows = crate::figures::interface_rows(points, [0.0, 0.0]);
    let count = |code: u8| rows.iter().filter(|r| r.status == code).count();
    json!({
        "open": count(0),
        "slip": count(2),
        "stick": count(1),
        "total": rows.len(),
        "counted": "rows of interface_final.csv: interface positions, the points of neighbouring elements at one node merged (values averaged, the more open status kept: open before slip before stick)",
    })
}

/// Nodal temperatures of a vessel state (a vessel state always has them).
fn temperature(r: &TimeResult) -> &[f64] {
    r.temperature.as_deref().unwrap_or(&[])
}

/// Writes the figures (CSV, SVG, PNG), the per-state files and
/// `summary.json` into `dir` (staged like every case: a temporary folder,
/// moved into place at the end, `summary.json` last).
pub fn write_outputs(run: &VesselRun, v: &Value, dir: &Path) -> CliResult<()> {
    writers::staged(dir, |tmp| write_files(run, v, tmp))
}

/// The vessel's figure tables (CSV) and figures, then the per-state files and the summary, into
/// `dir`; returns the names written, `summary.json` last.
fn write_files(run: &VesselRun, v: &Value, dir: &Path) -> CliResult<Vec<String>> {
    let mesh = &run.mesh;
    let g = &run.options.geometry;
    let (core, layer) = bodies(mesh);
    let deg = |i: usize| r_theta(mesh.nodes()[i]).1.to_degrees();
    let (Some(last), Some(_)) = (run.results.last(), run.results.first()) else {
        return Err("no results to write".into());
    };

    // Fig. 6: temperature around the layer's inner and outer surfaces.
    let l_in = ring_nodes(mesh, layer, g.interface_radius());
    let l_out = ring_nodes(mesh, layer, g.outer_radius());
    let mut rows6 = Vec::new();
    for r in &run.results {
        for (&a, &b) in l_in.iter().zip(&l_out) {
            rows6.push(vec![r.time, deg(a), temperature(r)[a], temperature(r)[b]]);
        }
    }
    csv(
        &dir.join("fig6_temperature_circumference.csv"),
        "time_s,theta_deg,T_layer_inner_C,T_layer_outer_C",
        rows6,
    )?;

    // Fig. 7: temperature through the wall at several angles.
    let angles = [0.0, 2.0, 10.0, 45.0, 180.0];
    let all_rows = rows(&run.options);
    let mut rows7 = Vec::new();
    for &a in &angles {
        for &(is_core, r) in &all_rows {
            let nodes = ring_nodes(mesh, if is_core { core } else { layer }, r);
            if let Some(&i) = nodes
                .iter()
                .min_by(|&&p, &&q| (deg(p) - a).abs().total_cmp(&(deg(q) - a).abs()))
            {
                let wall = 100.0 * (r - g.inner_radius) / (g.outer_radius() - g.inner_radius);
                for res in &run.results {
                    rows7.push(vec![res.time, deg(i), wall, temperature(res)[i]]);
                }
            }
        }
    }
    csv(
        &dir.join("fig7_temperature_through_wall.csv"),
        "time_s,theta_deg,wall_percent,T_C",
        rows7,
    )?;

    // Fig. 8 and 11: circumferential mean hoop stress through the wall, FE and analytical.
    // Fig. 8 plots the FE and the consistent model, fig. 11 all three
    // models: both tables hold every column, each beside its figure.
    let profile = hoop_profile(run, &last.stress);
    let an = analytical(&run.options);
    for stem in [
        "fig8_hoop_prestress_through_wall",
        "fig11_hoop_fe_vs_analytical",
    ] {
        csv(
            &dir.join(format!("{stem}.csv")),
            "wall_percent,is_core,r_m,hoop_mean_Pa,analytical_plane_strain_Pa,analytical_plane_stress_Pa,analytical_plane_strain_consistent_Pa",
            profile.iter().map(|&(w, c, r, m)| {
                vec![
                    w,
                    f64::from(u8::from(c)),
                    r,
                    m,
                    an[0].1.sigma_tt(r, c),
                    an[1].1.sigma_tt(r, c),
                    an[2].1.sigma_tt(r, c),
                ]
            }),
        )?;
    }

    // Fig. 9: hoop stress around the circumference at the inner and outer surfaces.
    let c_in = ring_nodes(mesh, core, g.inner_radius);
    let hoop_at = |s: &StressField, i: usize| hoop(mesh, s, i);
    csv(
        &dir.join("fig9_hoop_circumference.csv"),
        "surface,theta_deg,hoop_Pa",
        c_in.iter()
            .map(|&i| vec![0.0, deg(i), hoop_at(&last.stress, i)])
            .chain(
                l_out
                    .iter()
                    .map(|&i| vec![1.0, deg(i), hoop_at(&last.stress, i)]),
            ),
    )?;

    // Fig. 10: tangential displacement of the outer surface.
    let u = &last.displacement;
    let ut = |i: usize| {
        let (_, t) = r_theta(mesh.nodes()[i]);
        -u[2 * i] * t.sin() + u[2 * i + 1] * t.cos()
    };
    let kappa = if run.options.analysis == Analysis::PlaneStrain {
        1.0 + run.options.data.poisson_ratio
    } else {
        1.0
    };
    let shrink = kappa
        * run.options.data.expansion
        * (run.options.data.weld_temperature - run.options.data.ambient)
        * g.weld_half_width;
    csv(
        &dir.join("fig10_tangential_displacement.csv"),
        "theta_deg,u_theta_m,free_weld_shrinkage_half_m",
        l_out.iter().map(|&i| vec![deg(i), ut(i), -shrink]),
    )?;

    // The figures (SVG, PNG) and the interface table of the last state,
    // drawn once (crate::front::write_figures).
    crate::front::write_figures(run, dir)?;

    // The figures and tables written so far, then the per-state files every case
    // writes (VTK series, interface CSV), then the summary.
    let mut files: Vec<String> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .collect();
    files.sort();
    let state_files = StateFiles {
        vtu_stem: "vessel",
        pvd: "vessel.pvd",
        vtk: true,
        csv_nodal: false,
        csv_interface: true,
    };
    files.extend(writers::write_states(
        dir,
        mesh,
        &run.interfaces,
        &run.results,
        state_files,
    )?);
    // the operating state (--pressure) beside the series: at the time of
    // the cooled state, which the series holds
    if let Some(op) = &run.operating {
        files.extend(writers::write_state_files(
            dir,
            mesh,
            &run.interfaces,
            op,
            "operating",
            state_files,
        )?);
    }
    if let Some(h) = &run.history {
        let times: Vec<f64> = run.results.iter().map(|r| r.time).collect();
        files.extend(writers::write_temperature_history(
            dir,
            &run.history_probes,
            h,
            &times,
        )?);
    }
    writers::write(&dir.join("summary.json"), &serde_json::to_string_pretty(v)?)?;
    files.push("summary.json".into());
    Ok(files)
}

/// Arguments of `tecon vessel`.
#[derive(clap::Args, Debug)]
pub struct VesselArgs {
    /// Mesh: `gL` (graded toward the weld corners, made for 6-node
    /// triangles: 2 784·4^L triangles, order 2; default g0), `paper` (108
    /// nodes, 136 triangles, 17 interface elements), a uniform refinement
    /// level 0–9 (136·4^level triangles), `xF` (every paper interval in F
    /// parts, 136·F² triangles) or `tN` (about N triangles, e.g. `t1e5`).
    #[arg(long, default_value = crate::builtin::DEFAULT_MESH)]
    pub mesh: String,
    /// Element order: 1 (3-node triangles) or 2 (6-node triangles, curved
    /// edges on the circles). Default: 2 on the graded meshes `gL`, 1 on
    /// `paper` (the paper's linear triangles), the uniform levels, `xF` and
    /// `tN`.
    #[arg(long)]
    pub order: Option<usize>,
    /// The core/layer joint: `frictional` (the paper's: penalty contact
    /// with Mohr–Coulomb friction), `frictionless` (μ = 0, c = 0) or
    /// `bonded` (tied: facing nodes share their displacements, no penalty).
    #[arg(long, default_value = "frictional")]
    pub interface: String,
    /// Friction coefficient μ = tan φ of the core/layer joint (frictional
    /// only; default 0.3).
    #[arg(long, allow_hyphen_values = true)]
    pub friction: Option<f64>,
    /// Cohesion of the joint, Pa (frictional only; default 0): a bond in shear that breaks for good where the faces open.
    #[arg(long, allow_hyphen_values = true)]
    pub cohesion: Option<f64>,
    /// Internal (operating) pressure applied after cooling, Pa.
    #[arg(long, allow_hyphen_values = true)]
    pub pressure: Option<f64>,
    /// Fuse the weld to the core (no interface under the weld).
    #[arg(long)]
    pub fused_weld: bool,
    /// Capacity matrix of the heat conduction: `consistent` (the paper's)
    /// or `lumped` (keeps the first time steps inside the temperature
    /// bounds where the mesh does not resolve the weld's initial jump).
    #[arg(long, default_value = "consistent")]
    pub capacity: String,
    /// Generalised plane strain (free ends) instead of plane strain.
    #[arg(long)]
    pub free_ends: bool,
    /// Pure penalty contact (no augmented-Lagrangian update).
    #[arg(long)]
    pub penalty_only: bool,
    /// Full Newton passes always: no condensation of the bulk onto the
    /// interface dofs (a cross-check; the answers agree to the tolerances)
    #[arg(long)]
    pub no_condensation: bool,
    /// No coarse interface space before the first Newton pass of an
    /// increment (condensed passes; a cross-check: the answers agree to
    /// the tolerances)
    #[arg(long)]
    pub no_coarse_space: bool,
    /// Coarse levels of the coarse interface space before a frictionless
    /// joint's first Newton pass (each four times as wide as the one
    /// before; 1: the finest alone)
    #[arg(long, value_name = "N", default_value_t = tecon_elastic::COARSE_LEVELS,
          value_parser = clap::value_parser!(u32).range(1..=6))]
    pub coarse_levels: u32,
    /// No coupled tail of the outer loop: frozen friction limits to the
    /// end of every increment (a cross-check; the answers agree to the
    /// outer loop's tolerance)
    #[arg(long)]
    pub no_coupled_tail: bool,
    /// Every Newton pass solved to the full tolerances, also those a
    /// friction-limit update follows (a cross-check; the answers agree to
    /// the tolerances)
    #[arg(long)]
    pub exact_passes: bool,
    /// Each interface element's own chord normal (the classical Goodman
    /// element, as in the paper) instead of one smoothed normal per node.
    #[arg(long)]
    pub element_normals: bool,
    /// Interface conductance: `constant` (the paper's 850 W/(m² K)) or
    /// `contact` (power law of the contact pressure plus a gas gap; 850
    /// W/(m² K) at touch-down).
    #[arg(long, default_value = "constant")]
    pub conductance: String,
    /// `one-way` (heat conduction first, then contact) or `two-way`
    /// (staggered per thermal step).
    #[arg(long, default_value = "one-way")]
    pub coupling: String,
    /// Two-way: thermal steps per contact solve (fixed blocks; default:
    /// adaptive blocks, see --sync-tolerance).
    #[arg(long)]
    pub sync_interval: Option<usize>,
    /// Two-way, adaptive blocks: the largest relative conductance error
    /// accepted in a block (default 0.01).
    #[arg(long, allow_hyphen_values = true)]
    pub sync_tolerance: Option<f64>,
    /// Output times, s (comma-separated; the last ends the cooling).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1,10,60,600,3600,72000",
        allow_hyphen_values = true
    )]
    pub times: Vec<f64>,
    /// `--study mesh`: the case on meshes g0, g1, g2 (with `--mesh` a uniform
    /// level or `paper`: paper, 1, 2, 3, 4) with a convergence table.
    #[arg(long)]
    pub study: Option<String>,
    /// Multilayer vessel: the core and N layers wrapped and welded one
    /// after another (staged analysis; the README section "Multilayer vessels").
    #[arg(long)]
    pub layers: Option<usize>,
    /// Multilayer: thickness of every layer, m.
    #[arg(long, default_value_t = 6.4e-3, allow_hyphen_values = true)]
    pub layer_thickness: f64,
    /// Multilayer: seam angle of each layer, degrees in [0, 360)
    /// (comma-separated, one per layer; default staggered evenly, 360°(k − 1)/N).
    /// Seams all at 0° or 180° give a half section, any other the full ring.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub seams: Option<Vec<f64>>,
    /// Output folder.
    #[arg(long, default_value = "tecon-out/vessel")]
    pub out: PathBuf,
    /// Print nothing but warnings and errors: no progress bar, no report on
    /// the terminal (the report is in the output folder's report.txt).
    #[arg(long)]
    pub quiet: bool,
    /// Print the Newton iteration history of every increment.
    #[arg(long)]
    pub verbose: bool,
}

/// Refuses the options this run would ignore, naming the option that
/// they need: `--seams` and `--layer-thickness` (given on the command line:
/// `layer_thickness_given`, as it has a default) describe the layers of
/// `--layers N`; `--sync-interval` and `--sync-tolerance` the blocks of
/// `--coupling two-way`. (`--no-condensation` is honoured with `--layers`.)
pub fn check_combinations(args: &VesselArgs, layer_thickness_given: bool) -> Result<(), String> {
    if args.layers.is_none() {
        if let Some(s) = &args.seams {
            let list: Vec<String> = s.iter().map(f64::to_string).collect();
            return Err(format!(
                "--seams {} needs --layers: the seam angles place the welds of a multilayer vessel's layers, one per layer (give --layers {}, or drop --seams)",
                list.join(","),
                s.len()
            ));
        }
        if layer_thickness_given {
            return Err(format!(
                "--layer-thickness {} needs --layers: it is the thickness of every layer of a multilayer vessel; the monolayer vessel keeps the published layer (give --layers N, or drop --layer-thickness)",
                args.layer_thickness
            ));
        }
    }
    if args.coupling != "two-way" {
        let given = [
            ("--sync-interval", args.sync_interval.map(|v| v.to_string())),
            (
                "--sync-tolerance",
                args.sync_tolerance.map(|v| v.to_string()),
            ),
        ];
        if let Some((flag, Some(v))) = given.iter().find(|(_, v)| v.is_some()) {
            return Err(format!(
                "{flag} {v} needs --coupling two-way: it sets the blocks of thermal steps between the contact solves of the two-way coupling (this run is --coupling {}; add --coupling two-way, or drop {flag})",
                args.coupling
            ));
        }
    }
    Ok(())
}

/// Options from the command line.
pub fn options(args: &VesselArgs) -> CliResult<VesselOptions> {
    let spec =
        crate::mesh_cmd::parse_preset(&args.mesh).map_err(|e| e.replace("--preset", "--mesh"))?;
    let order = match args.order {
        None => spec.order,
        Some(o @ (1 | 2)) => o,
        Some(o) => {
            return Err(format!("--order {o}: expected 1 (3-node) or 2 (6-node triangles)").into());
        }
    };
    let interface = crate::builtin::InterfaceKind::parse(&args.interface)?;
    if interface != crate::builtin::InterfaceKind::Frictional {
        for (flag, given) in [
            ("--friction", args.friction.is_some()),
            ("--cohesion", args.cohesion.is_some()),
        ] {
            if given {
                return Err(format!(
                    "{flag}: only with --interface frictional (this run is --interface {})",
                    interface.name()
                )
                .into());
            }
        }
    }
    if interface == crate::builtin::InterfaceKind::Bonded && args.element_normals {
        return Err("--element-normals: a bonded interface has no interface points".into());
    }
    let d = VesselOptions::default();
    Ok(VesselOptions {
        mesh: VesselMeshSpec {
            fused_weld: args.fused_weld,
            order,
            ..spec
        },
        interface,
        friction: args.friction.unwrap_or(d.friction),
        cohesion: args.cohesion.unwrap_or(d.cohesion),
        capacity: crate::case::Capacity::parse(&args.capacity)?,
        pressure: args.pressure,
        times: args.times.clone(),
        analysis: if args.free_ends {
            Analysis::GeneralisedPlaneStrain
        } else {
            Analysis::PlaneStrain
        },
        augmented_lagrangian: if args.penalty_only { None } else { Some(1e-4) },
        condensation: !args.no_condensation,
        coarse_space: !args.no_coarse_space,
        coarse_levels: args.coarse_levels,
        coupled_tail: !args.no_coupled_tail,
        exact_passes: args.exact_passes,
        normals: if args.element_normals {
            InterfaceNormals::Element
        } else {
            InterfaceNormals::Smoothed
        },
        contact_conductance: match args.conductance.as_str() {
            "constant" => false,
            "contact" => true,
            other => {
                return Err(
                    format!("--conductance {other}: expected 'constant' or 'contact'").into(),
                );
            }
        },
        two_way: match args.coupling.as_str() {
            "one-way" => None,
            "two-way" => Some(two_way_options(args)?),
            other => {
                return Err(format!("--coupling {other}: expected 'one-way' or 'two-way'").into());
            }
        },
        quiet: args.quiet,
        verbose: args.verbose,
        ..VesselOptions::default()
    })
}

/// Runs `tecon vessel`.
pub fn run(args: VesselArgs) -> CliResult<()> {
    let base = options(&args)?;
    match args.study.as_deref() {
        None => {
            let run = analyse(&base)?;
            let v = summary(&run);
            write_outputs(&run, &v, &args.out)?;
            print!("{}", report(&run, &v));
            println!("results in {}", args.out.display());
            Ok(())
        }
        Some("mesh") => study(&base, &args.out, args.mesh.starts_with('g')),
        Some(other) => Err(format!("--study '{other}': the only study is 'mesh'").into()),
    }
}

/// The mesh-convergence study: on the graded family g0, g1, g2 when the
/// mesh asked for is graded (`graded`, the default), else on the uniform
/// family paper, 1, 2, 3, 4; at the element order of `base`.
pub fn study(base: &VesselOptions, out: &Path, graded: bool) -> CliResult<()> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut specs = Vec::new();
    if graded {
        for l in 0..=2 {
            specs.push((format!("g{l}"), VesselMeshSpec::graded(l)?));
        }
    } else {
        // level 0 is the paper mesh
        specs.push(("paper".to_string(), VesselMeshSpec::paper()));
        for l in 1..=4 {
            specs.push((l.to_string(), VesselMeshSpec::refined(l)?));
        }
    }
    let mut table = Vec::new();
    let mut text = String::from(
        "mesh     triangles  core_inner[MPa] core_outer[MPa] layer_inner[MPa] layer_outer[MPa] p_contact[MPa]   seconds  ZZ eta[%]\n",
    );
    let n_meshes = specs.len();
    let mut h = Vec::new();
    for (k, (name, spec)) in specs.into_iter().enumerate() {
        // which mesh the study is on (stderr: stdout keeps the table)
        eprintln!(
            "study: mesh {} of {n_meshes}: {name} ({} triangles)",
            k + 1,
            spec.n_triangles()
        );
        let o = VesselOptions {
            mesh: VesselMeshSpec {
                fused_weld: base.mesh.fused_weld,
                order: base.mesh.order,
                ..spec
            },
            ..base.clone()
        };
        let run = analyse(&o)?;
        let v = summary(&run);
        // element size: the root of the mean triangle area
        h.push((run.mesh.areas().iter().sum::<f64>() / run.mesh.n_triangles() as f64).sqrt());
        let g = |k: &str| v.pointer(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
        let row = vec![
            run.mesh.n_triangles() as f64,
            g("/final/hoop_mean/core_inner"),
            g("/final/hoop_mean/core_outer"),
            g("/final/hoop_mean/layer_inner"),
            g("/final/hoop_mean/layer_outer"),
            g("/final/contact_pressure_mean"),
            run.seconds,
            h[h.len() - 1],
            // relative ZZ estimate of the cooled state, as a fraction
            run.results
                .last()
                .map_or(f64::NAN, |r| r.stress.error.relative()),
        ];
        text += &format!(
            "{name:<8} {:>9} {:>15.3} {:>15.3} {:>16.3} {:>16.3} {:>14.4} {:>9.2} {:>10.3}\n",
            row[0],
            row[1] / 1e6,
            row[2] / 1e6,
            row[3] / 1e6,
            row[4] / 1e6,
            row[5] / 1e6,
            row[6],
            100.0 * row[8]
        );
        table.push(row);
    }
    csv(
        &out.join("study_mesh.csv"),
        "triangles,hoop_core_inner_Pa,hoop_core_outer_Pa,hoop_layer_inner_Pa,hoop_layer_outer_Pa,contact_pressure_Pa,seconds,h_m,zz_eta_relative",
        table.clone(),
    )?;
    // log–log: the change between successive meshes against h, with the fitted order
    let quantities: Vec<crate::figures::StudyQuantity> = [
        ("hoop core inner", 1),
        ("hoop core outer", 2),
        ("hoop layer inner", 3),
        ("hoop layer outer", 4),
        ("contact pressure", 5),
    ]
    .iter()
    .map(|&(l, k)| crate::figures::StudyQuantity {
        label: l.into(),
        values: table.iter().map(|r| r[k] / 1e6).collect(),
    })
    .collect();
    let (fig, orders) = crate::figures::mesh_study(&h, &quantities, "MPa");
    fig.write_svg_png(&out.join("study_mesh"))?;
    text += &order_line(&orders, &quantities);
    print!("{text}");
    std::fs::write(out.join("study_mesh.txt"), &text)
        .map_err(|e| format!("{}: {e}", out.display()))?;
    Ok(())
}

/// The mesh study's line of observed orders: each quantity's slope with
/// its relative changes between successive meshes, and no order where
/// every change is below [`crate::figures::STUDY_TOLERANCE_FLOOR`].
fn order_line(
    orders: &[(String, Option<f64>)],
    quantities: &[crate::figures::StudyQuantity],
) -> String {
    let mut text = String::from(
        "observed order (slope of log |q(h) − q(h/2)| against log h; the changes relative to q):",
    );
    for ((l, p), q) in orders.iter().zip(quantities) {
        let changes = crate::figures::relative_changes(&q.values);
        let listed = changes
            .iter()
            .map(|c| format!("{c:.1e}"))
            .collect::<Vec<_>>()
            .join(", ");
        match p {
            Some(_) if crate::figures::changes_at_tolerance(&q.values) => {
                text += &format!(" {l} - (changes {listed}: at the solvers' tolerances, no order);")
            }
            Some(p) => text += &format!(" {l} {p:.2} (changes {listed});"),
            None => text += &format!(" {l} -;"),
        }
    }
    text.pop();
    text.push('\n');
    text
}

/// `--sync-interval` / `--sync-tolerance`: fixed blocks when only the
/// interval is given, else adaptive blocks.
fn two_way_options(args: &VesselArgs) -> CliResult<crate::driver::TwoWay> {
    let d = crate::driver::TwoWay::default();
    if args.sync_interval == Some(0) {
        return Err("--sync-interval: at least 1".into());
    }
    if let Some(t) = args.sync_tolerance
        && !(t.is_finite() && t > 0.0)
    {
        return Err(format!("--sync-tolerance {t}: must be positive").into());
    }
    Ok(crate::driver::TwoWay {
        sync_interval: args.sync_interval.unwrap_or(d.sync_interval),
        sync_tolerance: match (args.sync_interval, args.sync_tolerance) {
            (Some(_), None) => None,
            (_, t) => t.or(d.sync_tolerance),
        },
        ..d
    })
}

/// The coupling statistics as JSON.
pub fn coupling_json(c: &crate::driver::CouplingStats) -> Value {
    json!({
        "mode": "two-way",
        "sync": if c.sync_tolerance.is_some() { "adaptive" } else { "fixed" },
        "sync_tolerance": c.sync_tolerance,
        "intermediate_outer_tolerance": c.intermediate_outer_tolerance,
        "rejected_blocks": c.rejected,
        "blocks": c.blocks,
        "iterations": c.iterations,
        "max_iterations_per_block": c.max_iterations,
        "unsettled_blocks": c.unsettled,
        "max_final_conductance_change": c.max_final_change,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::StudyQuantity;

    /// A quantity converging at order 2 gets its slope and changes; one
    /// whose changes are all below 1e-5 of it (the solvers' tolerances)
    /// gets no order, whatever its slope.
    #[test]
    fn the_study_prints_no_order_from_changes_at_the_solvers_tolerances() {
        let q = |label: &str, values: Vec<f64>| StudyQuantity {
            label: label.into(),
            values,
        };
        let quantities = [
            q("converging", vec![1.0, 1.04, 1.05]),
            q("noise", vec![2.0, 2.000002, 1.999998]),
        ];
        let orders = vec![
            ("converging".to_string(), Some(2.0)),
            ("noise".to_string(), Some(-1.3)),
        ];
        let line = order_line(&orders, &quantities);
        assert!(
            line.contains("converging 2.00 (changes 4.0e-2, 9.6e-3)"),
            "{line}"
        );
        assert!(
            line.contains("noise - (changes 1.0e-6, 2.0e-6: at the solvers' tolerances, no order)"),
            "{line}"
        );
        assert!(line.ends_with(")\n") && !line.contains(";\n"));
    }
}
