//! `tecon vessel --layers N`: the multilayer vessel built layer after layer.
//!
//! ```text
//! for stage k = 1..N:
//!   heat conduction on the core and layers 1..k (the layers not yet
//!     wrapped are absent): weld k starts at the weld temperature, layer k
//!     at ambient, the rest where stage k − 1 left it; cooling transient
//!   thermoelastic contact on the whole mesh with layers k+1..N inactive:
//!     layer k activated stress free and tight (its interface measures the
//!     jump from the displacements at activation), one solve per output
//!     time from the previous converged state
//!   → per stage: hoop stress through the wall (circumferential means),
//!     pressure of every interface around the circumference, VTK, summary,
//!     the nodal temperatures at every output time of the cooling
//! optional last stage (--pressure P): the internal pressure P on the bore,
//!   temperatures held; closed form: the prestress plus the Lamé field of
//!   the whole wall under P (the joints stay closed)
//! ```
//!
//! The thermal strain of an element is α (T_e − T_ref,e) with T_ref,e its
//! temperature when its layer was activated (the weld's 1132 °C stays its
//! reference: after cooling it carries the eigenstrain, as in the
//! monolayer). On 6-node triangles (`spec.order = 2`) T is the nodal field
//! interpolated inside the element and T_ref,e the initial value of the
//! element's region. The mesh density is a level of
//! [`MultilayerMeshSpec::refined`] (`--mesh L`, `refine = L`). Beside the FE results: the sequential shrink fit
//! ([`SequentialShrinkFit`]) with the plane-strain interference
//! (1 + ν) α ΔT w / 2π of every weld.

use std::f64::consts::PI;

use tecon_contact::{GhaboussiNormal, PaperJoint};
use tecon_elastic::analytical::{Cylinders, LameCylinder, SequentialShrinkFit};
use tecon_elastic::{
    Analysis, ElasticModel, InterfacePointResult, Joint, Loads, Material, SolverOptions,
    SolverState, StaticSolver, polar,
};
use tecon_mesh::{
    Mesh, MultilayerGeometry, MultilayerMeshSpec, multilayer_stage_mesh, multilayer_vessel_mesh,
};
use tecon_thermal::{EdgeBc, ThermalModel, ThetaScheme};

use crate::builtin::{VesselData, schedule};
use crate::driver::State;
use crate::writers::CliResult;

/// Everything a multilayer run needs.
#[derive(Debug, Clone, PartialEq)]
pub struct MultilayerOptions {
    /// Core and layers.
    pub geometry: MultilayerGeometry,
    /// Mesh density.
    pub spec: MultilayerMeshSpec,
    /// Refinement level of [`MultilayerOptions::spec`]
    /// ([`MultilayerMeshSpec::refined`]); None: a spec of its own.
    pub mesh_level: Option<u32>,
    /// Material and process data (the monolayer's).
    pub data: VesselData,
    /// Friction coefficient μ of every joint.
    pub friction: f64,
    /// Output times of each stage's cooling, s (the last ends it).
    pub times: Vec<f64>,
    /// Per layer stage, its own output times (case files' `[[stage]]`
    /// `times`); None: [`MultilayerOptions::times`] for every stage.
    pub stage_times: Option<Vec<Vec<f64>>>,
    /// Per layer, the initial temperature of its weld, °C; None: the
    /// data's weld temperature for every weld.
    pub weld_temperatures: Option<Vec<f64>>,
    /// Shear penalty of the joints relative to the normal one, k_s / k_n;
    /// None: 1 on a half section (the paper's k_s = k_n) and
    /// [`FULL_RING_SHEAR_RATIO`] on a full ring.
    pub shear_ratio: Option<f64>,
    /// Internal pressure of a last stage after the last layer has cooled
    /// (hydrostatic test or operating pressure), Pa on the bore; the
    /// temperatures stay where the last cooling left them.
    pub pressure: Option<f64>,
    /// No progress output.
    pub quiet: bool,
    /// Print the Newton history of every increment (as `tecon vessel
    /// --verbose` does for the monolayer), with the stage before it.
    pub verbose: bool,
    /// Newton passes condensed onto the interface dofs where cheaper
    /// (false: full passes always).
    pub condensation: bool,
    /// The coarse interface space with condensed passes (see
    /// [`crate::builtin::VesselOptions::coarse_space`]).
    pub coarse_space: bool,
    /// Coarse levels before a frictionless first pass (see
    /// [`crate::builtin::VesselOptions::coarse_levels`]).
    pub coarse_levels: u32,
    /// The coupled tail of the outer loop (see
    /// [`crate::builtin::VesselOptions::coupled_tail`]).
    pub coupled_tail: bool,
    /// Every Newton pass solved to the full tolerances (see
    /// [`crate::builtin::VesselOptions::exact_passes`]).
    pub exact_passes: bool,
    /// Capacity matrix of every stage's heat conduction.
    pub capacity: crate::case::Capacity,
}

impl MultilayerOptions {
    /// `n` layers of `thickness` (m) on the published core, seams at
    /// `seams` (degrees; None: staggered evenly, seam k at 360°(k − 1)/n),
    /// the published weld width and data. Seams all on y = 0 (0° or 180°)
    /// give a half section, any other a full ring.
    pub fn new(n: usize, thickness: f64, seams: Option<&[f64]>) -> CliResult<Self> {
        if n == 0 {
            return Err("--layers: at least 1".into());
        }
        let mut geometry = MultilayerGeometry::staggered(0.762, 12.7e-3, n, thickness, 3.8e-3);
        if let Some(s) = seams {
            if s.len() != n {
                return Err(format!("--seams: {} angles for {n} layers", s.len()).into());
            }
            for (l, &a) in geometry.layers.iter_mut().zip(s) {
                if !(a.is_finite() && (0.0..360.0).contains(&a)) {
                    return Err(format!("--seams: {a}° is not in [0, 360)").into());
                }
                l.seam_angle = a.to_radians();
            }
        }
        geometry
            .check()
            .map_err(|e| format!("--layers/--layer-thickness/--seams: {e}"))?;
        Ok(MultilayerOptions {
            geometry,
            spec: MultilayerMeshSpec::default(),
            mesh_level: Some(0),
            data: VesselData::default(),
            friction: 0.3,
            times: vec![1.0, 10.0, 60.0, 600.0, 3600.0, 72000.0],
            shear_ratio: None,
            stage_times: None,
            weld_temperatures: None,
            pressure: None,
            quiet: false,
            verbose: false,
            condensation: true,
            coarse_space: true,
            coarse_levels: tecon_elastic::COARSE_LEVELS,
            coupled_tail: true,
            exact_passes: false,
            capacity: crate::case::Capacity::Consistent,
        })
    }

    /// The mesh of refinement level `level` ([`MultilayerMeshSpec::refined`])
    /// with elements of order `order` (1: 3-node, 2: 6-node triangles).
    pub fn set_mesh(&mut self, level: u32, order: usize) -> CliResult<()> {
        self.spec = MultilayerMeshSpec {
            full_section: self.spec.full_section,
            ..MultilayerMeshSpec::refined(level, order)?
        };
        self.mesh_level = Some(level);
        Ok(())
    }

    /// The initial temperature of weld `k` (1-based), °C.
    pub fn weld_temperature(&self, k: usize) -> f64 {
        self.weld_temperatures
            .as_ref()
            .and_then(|w| w.get(k - 1).copied())
            .unwrap_or(self.data.weld_temperature)
    }

    /// The sorted output times of layer stage `k` (1-based), s; errors if
    /// there is none or one is not positive.
    pub fn stage_output_times(&self, k: usize) -> CliResult<Vec<f64>> {
        let mut times = self
            .stage_times
            .as_ref()
            .and_then(|t| t.get(k - 1).cloned())
            .unwrap_or_else(|| self.times.clone());
        if times.is_empty() || times.iter().any(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(format!("stage {k}: give positive output times in seconds").into());
        }
        times.sort_by(f64::total_cmp);
        times.dedup();
        Ok(times)
    }

    /// Whether the section is meshed as a half (every seam on y = 0).
    pub fn half_section(&self) -> bool {
        self.spec.half_section(&self.geometry)
    }

    /// The joints' k_s / k_n (see [`MultilayerOptions::shear_ratio`]). On
    /// a full ring the default keeps the shear penalty k_s of the default
    /// mesh on refined ones: k_n = β E / h grows as the rows h shrink, so
    /// the ratio falls as [`FULL_RING_SHEAR_RATIO`] × 2 / (rows per layer)
    /// (with the ratio held, the stick band μ p / k_s narrowed by 2 per
    /// level and the Newton passes of levels 1 and 2 found a layer free to
    /// spin at the first output time).
    pub fn effective_shear_ratio(&self) -> f64 {
        self.shear_ratio.unwrap_or(if self.half_section() {
            1.0
        } else {
            FULL_RING_SHEAR_RATIO * MultilayerMeshSpec::default().layer_rows as f64
                / self.spec.layer_rows as f64
        })
    }
}

/// k_s / k_n of the joints on a full ring. A layer of a full ring is held
/// in rotation only by friction, and in the exact answer its stick zone
/// shrinks to a point (away from it the layer's and the ring's hoop strains
/// differ, so they slip): the Newton iterates of the frozen-limit friction
/// passes then find every point slipping and the rotation free, and the
/// stick band |τ| ≤ μ p, |g_t| ≤ μ p / k_s they must land in is only
/// ~1e-11 m wide with the paper's k_s = k_n = 10 E/h. A shear penalty
/// 1000 times softer widens it to ~1e-8 m (still 1e-3 of the ~50 µm
/// slips). Measured (elastic test `staged`, 2 layers at seams 0°/90°, one
/// load step per stage): 27 + 62 Newton iterations instead of 672 + 654
/// (with 7 cut-backs), the ring means the same to 1e-6 of their size.
pub const FULL_RING_SHEAR_RATIO: f64 = 1e-3;

/// What one stage left.
#[derive(Debug, Clone)]
pub struct StageResult {
    /// Layers wrapped by the end of the stage.
    pub layers: usize,
    /// Internal pressure of the stage, Pa (0 for a layer stage).
    pub pressure: f64,
    /// The closed form of each ring's mean hoop stress (0 = core; the
    /// rings not wrapped yet carry 0), Pa: the sequential shrink fit after
    /// the stage's layers, plus for a pressure stage the Lamé field of the
    /// whole wall under the pressure (the joints stay closed).
    pub analytical_means: Vec<f64>,
    /// The closed form of each active interface's contact pressure, Pa.
    pub analytical_pressures: Vec<f64>,
    /// The state at the end of the stage's cooling (whole mesh; the
    /// inactive layers at zero).
    pub state: State,
    /// Mean hoop stress (1/(Θ t)) ∫∫ σ_θθ dr dθ of each ring (0 = core), Pa.
    pub ring_means: Vec<f64>,
    /// Arc-weighted mean contact pressure of each active interface, Pa.
    pub pressures: Vec<f64>,
    /// Newton iterations of the stage (all passes, all increments).
    pub newton_iterations: usize,
    /// Thermal steps of the stage.
    pub thermal_steps: usize,
    /// Largest relative heat-balance residual of the stage's outputs.
    pub heat_balance: f64,
    /// Wall-clock seconds of the stage's heat conduction and of its
    /// contact solves (`timing.json`).
    pub seconds: (f64, f64),
    /// The interface dofs the stage's Newton passes were condensed onto
    /// (None: full passes, as with [`MultilayerOptions::condensation`] off).
    pub condensed_dofs: Option<usize>,
    /// Newton steps in the coarse interface space of the condensed passes
    /// (not in `newton_iterations`).
    pub coarse_iterations: usize,
    /// The nodal temperatures (°C) at each of the stage's output times,
    /// (time in s, one value per node of the stage's mesh: the first nodes
    /// of the whole mesh); empty for the pressure stage.
    pub temperatures: Vec<(f64, Vec<f64>)>,
    /// The stage's heat conduction outside the bounds of the maximum
    /// principle, at any time step (None: inside; the pressure stage).
    pub bound_violation: Option<crate::driver::BoundViolation>,
}

/// A finished multilayer run.
#[derive(Debug)]
pub struct MultilayerRun {
    /// Options.
    pub options: MultilayerOptions,
    /// The whole mesh.
    pub mesh: Mesh,
    /// One result per stage.
    pub stages: Vec<StageResult>,
    /// The sequential shrink fit of the same rings.
    pub fit: SequentialShrinkFit,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Interface below layer `k` (1-based).
pub fn interface_name(k: usize) -> String {
    if k == 1 {
        "core_layer1".into()
    } else {
        format!("layer{}_layer{k}", k - 1)
    }
}

/// The sequential shrink fit with the plane-strain interference of every weld.
pub fn sequential_fit(o: &MultilayerOptions) -> CliResult<SequentialShrinkFit> {
    let d = &o.data;
    let deltas = o
        .geometry
        .layers
        .iter()
        .enumerate()
        .map(|(k, l)| {
            let dt = o.weld_temperature(k + 1) - d.ambient;
            (1.0 + d.poisson_ratio) * d.expansion * dt * 2.0 * l.weld_half_width / (2.0 * PI)
        })
        .collect();
    Ok(SequentialShrinkFit::new(
        o.geometry.radii(),
        deltas,
        d.youngs_modulus,
        d.poisson_ratio,
        Cylinders::PlaneStrain,
    )?)
}

/// The thermal model of stage `k` on its mesh: conduction in the core and
/// layers 1..k, convection on the bore and on the outer surface of layer
/// k, the interface conductance on every interface; initial field: ambient,
/// weld k at the weld temperature, the nodes of the earlier stages at
/// `previous`.
pub fn stage_thermal_model<'m>(
    o: &MultilayerOptions,
    mesh: &'m Mesh,
    k: usize,
    previous: &[f64],
) -> CliResult<ThermalModel<'m>> {
    let d = &o.data;
    let mut m = ThermalModel::new(mesh);
    m.set_capacity(o.capacity.kind());
    m.set_material_everywhere(tecon_thermal::Material::new(
        d.conductivity,
        d.density,
        d.specific_heat,
    ))?;
    for edges in ["inner", "outer"] {
        m.add_edge_bc(edges, EdgeBc::convection(d.film, d.ambient))?;
    }
    for j in 1..=k {
        m.set_interface_conductance(&interface_name(j), d.interface_conductance)?;
    }
    m.set_initial_default(d.ambient)?;
    m.set_initial_region(&format!("weld{k}"), o.weld_temperature(k))?;
    for (v, &t) in previous.iter().enumerate() {
        m.set_initial_node(v, t)?;
    }
    Ok(m)
}

/// The Lamé cylinder of the whole wall (bore to the outer surface of the
/// last layer) under the internal pressure `p`.
pub fn wall_lame(o: &MultilayerOptions, p: f64) -> LameCylinder {
    let r = o.geometry.radii();
    LameCylinder {
        a: r[0],
        b: r[r.len() - 1],
        p,
        e: o.data.youngs_modulus,
        nu: o.data.poisson_ratio,
    }
}

/// The closed forms after `k` layers (and the pressure `p` on the whole
/// wall, 0 for none): ring means and contact pressures (see
/// [`StageResult::analytical_means`]).
fn closed_form(
    o: &MultilayerOptions,
    fit: &SequentialShrinkFit,
    k: usize,
    p: f64,
) -> (Vec<f64>, Vec<f64>) {
    let r = o.geometry.radii();
    let lame = wall_lame(o, p);
    let n = o.geometry.layers.len();
    let means = (0..=n)
        .map(|ring| {
            if ring > k {
                return 0.0;
            }
            // (1/t) ∫ (A + B/r²) dr = A + B/(r₁ r₂), A, B of the Lamé field
            let (r1, r2) = (r[ring], r[ring + 1]);
            let b = (lame.sigma_tt(r1) - lame.sigma_tt(r2)) / (1.0 / (r1 * r1) - 1.0 / (r2 * r2));
            let a = lame.sigma_tt(r1) - b / (r1 * r1);
            let pressure_part = if p == 0.0 { 0.0 } else { a + b / (r1 * r2) };
            fit.mean_hoop(k, ring) + pressure_part
        })
        .collect();
    let pressures = (1..=k)
        .map(|j| {
            let pressure_part = if p == 0.0 { 0.0 } else { -lame.sigma_rr(r[j]) };
            fit.contact_pressure(k, j) + pressure_part
        })
        .collect();
    (means, pressures)
}

/// The elastic model of stage `k` on the whole mesh.
fn stage_elastic_model<'m>(
    o: &MultilayerOptions,
    mesh: &'m Mesh,
    k: usize,
    references: &[Vec<f64>],
) -> CliResult<ElasticModel<'m>> {
    let d = &o.data;
    let mut regions = vec!["core".to_string()];
    for j in 1..=k {
        regions.push(format!("layer{j}"));
        regions.push(format!("weld{j}"));
    }
    let names: Vec<&str> = regions.iter().map(String::as_str).collect();
    let mut m = ElasticModel::new(mesh, Analysis::PlaneStrain)
        .material_everywhere(Material {
            youngs_modulus: d.youngs_modulus,
            poisson_ratio: d.poisson_ratio,
            expansion: d.expansion,
        })?
        .active_regions(&names)?;
    m = if o.half_section() {
        m.symmetry("sym0")?
            .symmetry("sym180")?
            .remove_free_translations(true)
    } else {
        m.hold_rigid_modes("inner")?
    };
    for (j, reference) in references.iter().enumerate().take(k) {
        let h = o.geometry.layers[j].thickness / o.spec.layer_rows as f64;
        let k_n = tecon_contact::DEFAULT_PENALTY_FACTOR * d.youngs_modulus / h;
        let law = Joint::Frictional(PaperJoint::new(
            GhaboussiNormal::penalty(k_n)?,
            k_n * o.effective_shear_ratio(),
            0.0,
            o.friction.atan(),
        )?);
        let name = interface_name(j + 1);
        m = m
            .interface(&name, law)?
            .interface_reference(&name, reference.clone())?;
    }
    Ok(m)
}

/// Runs the stages.
pub fn analyse(o: &MultilayerOptions) -> CliResult<MultilayerRun> {
    let clock = std::time::Instant::now();
    let geo = &o.geometry;
    let n = geo.layers.len();
    for k in 1..=n {
        o.stage_output_times(k)?;
    }
    if o.friction == 0.0 && !o.half_section() {
        // a rigid turn of a ring on a circular joint opens no gap: with
        // frictionless joints nothing holds a full ring in rotation
        return Err(format!(
            "friction 0 on a full ring (seams at {}°, not all on y = 0): a frictionless joint resists no turning, so nothing would hold the rings in rotation; give a friction coefficient, or seams on y = 0 (0° or 180°: the half section, held by its symmetry planes)",
            geo.layers
                .iter()
                .map(|l| format!("{:.0}", l.seam_angle.to_degrees()))
                .collect::<Vec<_>>()
                .join(", ")
        )
        .into());
    }
    let mesh = multilayer_vessel_mesh(geo, &o.spec)?;
    // refused up front when it cannot fit, as every other analysis
    crate::memory::check("the multilayer mesh", mesh.n_triangles(), mesh.order())?;
    let fit = sequential_fit(o)?;
    let solver_options = SolverOptions {
        augmented_lagrangian: Some(1e-4),
        max_iterations: 150,
        condensation: o.condensation,
        coarse_space: o.coarse_space,
        coarse_levels: o.coarse_levels,
        coupled_tail: o.coupled_tail,
        pass_forcing: if o.exact_passes {
            0.0
        } else {
            tecon_elastic::PASS_FORCING
        },
        ..SolverOptions::default()
    };
    let mut temperature: Vec<f64> = Vec::new();
    let mut reference: Vec<f64> = Vec::new();
    let mut references: Vec<Vec<f64>> = Vec::new();
    let mut previous = SolverState::unloaded(2 * mesh.n_nodes());
    let mut stages = Vec::new();
    let n_stages = n + usize::from(o.pressure.is_some());
    for k in 1..=n {
        if !o.quiet {
            eprintln!("stage {k}/{n_stages}: layer {k} wrapped, weld {k} cooling");
        }
        let times = o.stage_output_times(k)?;
        let end = times[times.len() - 1];
        // heat conduction with the bodies present at this stage
        let sm = multilayer_stage_mesh(geo, &o.spec, k)?;
        let thermal = stage_thermal_model(o, &sm, k, &temperature)?;
        let system = thermal.assemble()?;
        // the stress-free temperature of the new ring's elements (the
        // earlier ones keep theirs): on linear triangles the element mean of
        // the initial field, on 6-node ones the region's initial value, so
        // the weld's eigenstrain keeps its jump at the weld edge (as in the
        // monolayer, driver::stress_free_reference)
        let own = if sm.order() == 2 {
            system.region_initial_temperature().map(<[f64]>::to_vec)
        } else {
            system.reference_temperature()
        }
        .ok_or("thermal: no initial temperature")?;
        reference.extend_from_slice(&own[reference.len()..]);
        let mut outputs = Vec::new();
        let heat_clock = std::time::Instant::now();
        let mut extremes = None;
        let summary = tecon_thermal::run_transient_observed(
            &system,
            &schedule(end)?,
            ThetaScheme::crank_nicolson(),
            &times,
            |s| {
                outputs.push((
                    s.temperature.clone(),
                    s.element_temperature.clone(),
                    s.balance.relative_residual(),
                ))
            },
            |time, t| crate::driver::StepExtremes::observe(&mut extremes, time, t),
            || true,
        )
        .map_err(|e| format!("stage {k}: heat conduction: {e}"))?;
        // the maximum principle, at every time step (as the monolayer's)
        let at_outputs: Vec<(f64, &[f64])> = times
            .iter()
            .zip(&outputs)
            .map(|(&t, o)| (t, o.0.as_slice()))
            .collect();
        let bound_violation =
            crate::driver::bound_violation_of(&thermal, &sm, true, &at_outputs, extremes);
        let heat_seconds = heat_clock.elapsed().as_secs_f64();
        let contact_clock = std::time::Instant::now();
        // contact with layer k activated on the deformed assembly
        references.push(previous.displacement.clone());
        let model = stage_elastic_model(o, &mesh, k, &references)?;
        if !o.half_section() {
            let name = interface_name(k);
            let elements = mesh.interface(&name)?.elements.len();
            previous.seed_friction_pressure(&name, elements, fit.stage(k).pressure());
        }
        let mut solver = StaticSolver::new(&model, solver_options)?;
        solver.resume(&previous)?;
        let mut newton = 0;
        let mut last = None;
        for (i, (t_nodal, t_el, balance)) in outputs.iter().enumerate() {
            let delta_t = stage_thermal_load(&mesh, t_nodal, t_el, &reference);
            let reports = solver
                .advance(&Loads {
                    delta_t,
                    ..Loads::mechanical()
                })
                .map_err(|e| format!("stage {k}: contact at t = {} s: {e}", times[i]))?;
            if o.verbose {
                eprintln!("stage {k}:");
                crate::driver::print_history(times[i], &reports);
            }
            newton += reports.iter().map(|r| r.iterations).sum::<usize>();
            let mut t_full = vec![f64::NAN; mesh.n_nodes()];
            t_full[..t_nodal.len()].copy_from_slice(t_nodal);
            let mut te_full = vec![f64::NAN; mesh.n_triangles()];
            te_full[..t_el.len()].copy_from_slice(t_el);
            last = Some(State {
                time: times[i],
                stage: k - 1,
                temperature: Some(t_full),
                element_temperature: Some(te_full),
                heat_balance: Some(*balance),
                displacement: solver.displacement().to_vec(),
                eps_zz: solver.eps_zz(),
                stress: solver.stresses(),
                interface: solver.interface_results(),
                interface_weights: crate::driver::interface_point_weights(&model),
                max_iterations: reports.iter().map(|r| r.iterations).max().unwrap_or(0),
                coupling_iterations: 0,
            });
        }
        let state = last.ok_or("no output time")?;
        temperature = outputs.last().map(|o| o.0.clone()).unwrap_or_default();
        previous = solver.state();
        let ring_means = (0..=n)
            .map(|r| ring_mean(&mesh, &state.stress.element, r))
            .collect();
        let pressures = (0..k)
            .map(|j| mean_pressure(&state.interface, &state.interface_weights, j))
            .collect();
        let (analytical_means, analytical_pressures) = closed_form(o, &fit, k, 0.0);
        stages.push(StageResult {
            layers: k,
            pressure: 0.0,
            analytical_means,
            analytical_pressures,
            state,
            ring_means,
            pressures,
            newton_iterations: newton,
            thermal_steps: summary.steps,
            heat_balance: summary.max_balance_residual,
            seconds: (heat_seconds, contact_clock.elapsed().as_secs_f64()),
            condensed_dofs: solver.condensed_dofs(),
            coarse_iterations: solver.coarse_iterations(),
            temperatures: times
                .iter()
                .zip(&outputs)
                .map(|(&t, o)| (t, o.0.clone()))
                .collect(),
            bound_violation,
        });
    }
    if let Some(p) = o.pressure {
        if !o.quiet {
            eprintln!("stage {}/{n_stages}: internal pressure {p:e} Pa", n + 1);
        }
        let last = stages.last().ok_or("no layer stage")?;
        let contact_clock = std::time::Instant::now();
        let model = stage_elastic_model(o, &mesh, n, &references)?.pressure("inner", p)?;
        let mut solver = StaticSolver::new(&model, solver_options)?;
        // the pressure is new: it starts from factor 0
        previous.loads.pressure = 0.0;
        solver.resume(&previous)?;
        let delta_t = previous.loads.delta_t.clone();
        let reports = solver
            .advance(&Loads {
                delta_t,
                ..Loads::mechanical()
            })
            .map_err(|e| format!("pressure stage: contact: {e}"))?;
        if o.verbose {
            eprintln!("pressure stage:");
            crate::driver::print_history(last.state.time, &reports);
        }
        let newton = reports.iter().map(|r| r.iterations).sum::<usize>();
        let state = State {
            time: last.state.time,
            stage: n,
            displacement: solver.displacement().to_vec(),
            eps_zz: solver.eps_zz(),
            stress: solver.stresses(),
            interface: solver.interface_results(),
            interface_weights: crate::driver::interface_point_weights(&model),
            max_iterations: reports.iter().map(|r| r.iterations).max().unwrap_or(0),
            ..last.state.clone()
        };
        let ring_means = (0..=n)
            .map(|r| ring_mean(&mesh, &state.stress.element, r))
            .collect();
        let pressures = (0..n)
            .map(|j| mean_pressure(&state.interface, &state.interface_weights, j))
            .collect();
        let (analytical_means, analytical_pressures) = closed_form(o, &fit, n, p);
        stages.push(StageResult {
            layers: n,
            pressure: p,
            analytical_means,
            analytical_pressures,
            state,
            ring_means,
            pressures,
            newton_iterations: newton,
            thermal_steps: 0,
            heat_balance: 0.0,
            seconds: (0.0, contact_clock.elapsed().as_secs_f64()),
            condensed_dofs: solver.condensed_dofs(),
            coarse_iterations: solver.coarse_iterations(),
            temperatures: Vec::new(),
            bound_violation: None,
        });
    }
    Ok(MultilayerRun {
        options: o.clone(),
        mesh,
        stages,
        fit,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

/// The thermal load of the whole mesh from a stage's temperatures: the
/// stage mesh's nodes and triangles are the first ones of the whole mesh
/// (`nodal`, `element_mean` and the references `reference` cover them);
/// the layers not yet wrapped get no temperature change. Linear triangles:
/// one value per element, T̄_e − T_ref,e; 6-node triangles: six per
/// element, T_a − T_ref,e (the layout of `Loads::delta_t`).
pub fn stage_thermal_load(
    mesh: &Mesh,
    nodal: &[f64],
    element_mean: &[f64],
    reference: &[f64],
) -> Vec<f64> {
    // the monolayer's thermal load on the stage's elements (the first
    // ones), then zeros for the layers not yet wrapped
    let stage = &reference[..reference.len().min(element_mean.len())];
    let mut d = crate::driver::thermal_load(mesh, nodal, element_mean, stage);
    let per = if mesh.triangles6().is_some() { 6 } else { 1 };
    d.resize(per * mesh.n_triangles(), 0.0);
    d
}

/// Whether region `name` belongs to ring `ring` (0 = core; k = layer k and weld k).
pub fn in_ring(name: &str, ring: usize) -> bool {
    if ring == 0 {
        name == "core"
    } else {
        let id = ring.to_string();
        name.strip_prefix("layer")
            .or_else(|| name.strip_prefix("weld"))
            == Some(id.as_str())
    }
}

/// (1/(Θ t)) ∫∫ σ_θθ dr dθ over the triangles of `ring` (element stresses).
pub fn ring_mean(mesh: &Mesh, stress: &[[f64; 4]], ring: usize) -> f64 {
    let names = mesh.region_names();
    let x = mesh.nodes();
    let (mut s, mut w) = (0.0, 0.0);
    for (e, t) in mesh.triangles().iter().enumerate() {
        if !in_ring(&names[mesh.element_regions()[e]], ring) {
            continue;
        }
        let p = t.map(|v| x[v]);
        let c = [
            (p[0][0] + p[1][0] + p[2][0]) / 3.0,
            (p[0][1] + p[1][1] + p[2][1]) / 3.0,
        ];
        let area = element_area(mesh, e);
        let wr = area / c[0].hypot(c[1]);
        s += polar(stress[e], c, [0.0, 0.0])[1] * wr;
        w += wr;
    }
    if w > 0.0 { s / w } else { f64::NAN }
}

/// The area of triangle `e`: of its curved 6-node shape on a quadratic
/// mesh, of its corners' triangle on a linear one.
pub fn element_area(mesh: &Mesh, e: usize) -> f64 {
    let x = mesh.nodes();
    match mesh.triangles6() {
        Some(t6) => tecon_mesh::quadratic::p2_area(&t6[e].map(|v| x[v])).abs(),
        None => {
            let p = mesh.triangles()[e].map(|v| x[v]);
            0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
                .abs()
        }
    }
}

/// Mean contact pressure of interface `index` (open points count 0),
/// weighted by the points' integration weights `weights` (arc length of
/// the bottom face, one per point of `points`: two per 4-node element,
/// three per 6-node one, as in [`crate::driver::interface_point_weights`]).
pub fn mean_pressure(points: &[InterfacePointResult], weights: &[f64], index: usize) -> f64 {
    let (mut s, mut w) = (0.0, 0.0);
    for (p, &wp) in points.iter().zip(weights) {
        if p.interface == index {
            s += wp * -p.traction[1];
            w += wp;
        }
    }
    if w > 0.0 { s / w } else { 0.0 }
}
