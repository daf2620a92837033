//! `tecon run CASE.toml`: a general thermoelastic contact case from a TOML
//! case file — a Gmsh mesh or a built-in generator, materials per region,
//! thermal boundary conditions per edge set, initial temperatures, a time
//! schedule, mechanical supports and loads, interfaces (thermal conductance
//! and joint law) and outputs.
//!
//! The pipeline is that of [`crate::vessel`]: mesh → heat conduction
//! (transient, steady, or the initial field held) → at every output time a
//! thermoelastic contact solve with `ΔT_e = T_e − T_ref,e` → outputs
//! (`summary.json`, VTK series, nodal and interface CSV, probes).
//!
//! ```text
//! tecon run examples/cases/shrink_fit.toml            # results in tecon-out/run/shrink_fit/
//! tecon run my_case.toml --out results/my_case --quiet
//! ```
//!
//! The format is documented in the README ("Case files"). Every table
//! rejects unknown keys; every error is one line naming the case file and
//! the key, region, edge set or interface at fault. Results are written into
//! a temporary folder inside the output folder and moved into place only
//! when everything has been written (`summary.json` last).

use std::path::{Path, PathBuf};

use serde::Deserialize;
use serde_json::{Value, json};
use tecon_elastic::InterfacePointResult;
use tecon_mesh::{Mesh, VesselMeshSpec};

use crate::driver::{self, NewtonStats, ThermalInfo, ThermalMode};
use crate::setup;
use crate::writers::{self, StateFiles, state_summary};

pub use crate::writers::CliResult;

// ---------------------------------------------------------------------------
// The case file
// ---------------------------------------------------------------------------

/// A parsed case file (see the README for the format).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// `[mesh]`: a Gmsh file or a generator.
    pub mesh: MeshSection,
    /// `[[material]]`: one per region.
    #[serde(default)]
    pub material: Vec<MaterialSection>,
    /// `[[interface]]`: thermal conductance and joint law per interface.
    #[serde(default)]
    pub interface: Vec<InterfaceSection>,
    /// `[thermal]`: absent for a purely mechanical case.
    pub thermal: Option<ThermalSection>,
    /// `[mechanical]`: analysis type, supports, loads, solver options.
    #[serde(default)]
    pub mechanical: MechanicalSection,
    /// `[output]`: times, probes, optional files.
    #[serde(default)]
    pub output: OutputSection,
    /// `[coupling]`: one-way (default) or staggered two-way.
    pub coupling: Option<crate::conductance::CouplingSection>,
    /// The file the case was read from (used in error messages); empty for
    /// a case parsed from a string.
    #[serde(skip)]
    pub source: PathBuf,
    /// Built-in cases: apply the pressures only after the thermal history,
    /// in a second stage with the last temperatures held (`tecon vessel
    /// --pressure`). Case files apply every load from the first solve.
    #[serde(skip)]
    pub staged_pressure: bool,
    /// Show a progress bar (built-in cases; `tecon run` is silent).
    #[serde(skip)]
    pub progress: bool,
    /// Print every Newton pass to stderr.
    #[serde(skip)]
    pub verbose: bool,
}

/// `[mesh]`: exactly one of `file` or `generator`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSection {
    /// Gmsh MSH 4.1 file, relative to the case file.
    pub file: Option<PathBuf>,
    /// `"vessel"`, `"annulus"` or `"rectangle"`.
    pub generator: Option<String>,
    /// Element order: 1 (3-node triangles) or 2 (6-node triangles with
    /// curved edges on the generators' circles). Default: the generator's
    /// (1), or the Gmsh file's (a file of 6-node triangles is order 2; an
    /// explicit order that contradicts it is an error; `order = 2` promotes a
    /// file of 3-node triangles with straight edges).
    pub order: Option<usize>,
    /// vessel: `"paper"` or a refinement level 0–9 (integer or string); default 2.
    pub preset: Option<toml::Value>,
    /// vessel: fuse the weld to the core (no interface under the weld).
    pub fused_weld: Option<bool>,
    /// vessel: inner radius, m.
    pub inner_radius: Option<f64>,
    /// vessel: core thickness, m.
    pub core_thickness: Option<f64>,
    /// vessel: layer thickness, m.
    pub layer_thickness: Option<f64>,
    /// vessel: half width of the weld, m.
    pub weld_half_width: Option<f64>,
    /// annulus: the concentric layers, innermost first.
    #[serde(default)]
    pub layer: Vec<LayerSection>,
    /// annulus: start angle, degrees (default 0).
    pub theta0: Option<f64>,
    /// annulus: end angle, degrees (default 360).
    pub theta1: Option<f64>,
    /// annulus: element intervals around.
    pub segments: Option<usize>,
    /// rectangle: lower-left corner `[x, y]`, m (default `[0, 0]`).
    pub origin: Option<[f64; 2]>,
    /// rectangle: `[width, height]`, m.
    pub size: Option<[f64; 2]>,
    /// rectangle: cells `[nx, ny]`.
    pub divisions: Option<[usize; 2]>,
    /// vessel, built-in cases: the mesh density itself (overrides `preset`).
    #[serde(skip)]
    pub vessel_spec: Option<VesselMeshSpec>,
}

/// `[[mesh.layer]]` of the annulus generator.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerSection {
    /// Region name.
    pub name: String,
    /// Inner radius, m.
    pub r_in: f64,
    /// Outer radius, m.
    pub r_out: f64,
    /// Element rows through the thickness.
    pub rows: usize,
}

/// `[[material]]`: the material of one region.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSection {
    /// Region (Gmsh physical surface or generator region).
    pub region: String,
    /// Conductivity k, W/(m K) (needed with `[thermal]`).
    pub conductivity: Option<f64>,
    /// Density ρ, kg/m³ (needed with `[thermal]`).
    pub density: Option<f64>,
    /// Specific heat c, J/(kg K) (needed with `[thermal]`).
    pub specific_heat: Option<f64>,
    /// Young's modulus E, Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
    /// Thermal expansion α, 1/K (needed when temperatures change).
    pub expansion: Option<f64>,
    /// Yield stress σ_y, Pa (key `yield`, optional): the report names the
    /// regions where the von Mises stress exceeds it (the analysis stays elastic).
    #[serde(rename = "yield")]
    pub yield_stress: Option<f64>,
}

/// `[[interface]]`: a pair of faces joined thermally and mechanically.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InterfaceSection {
    /// Interface name (generators name theirs, e.g. `core_layer`).
    pub name: String,
    /// Edge set of the bottom face (Gmsh meshes; omit for generated interfaces).
    pub bottom: Option<String>,
    /// Edge set of the top face.
    pub top: Option<String>,
    /// How far facing nodes may lie apart when the faces are paired, as a
    /// fraction of the local element size (default 1e-4; Gmsh places the nodes
    /// of two separately meshed arcs a few nm apart). Facing nodes must
    /// coincide: this only absorbs round-off, in (0, 0.5).
    pub pairing_tolerance: Option<f64>,
    /// Thermal conductance: h_c in W/(m² K), or an `[interface.conductance]`
    /// table with a law; absent: adiabatic.
    pub conductance: Option<toml::Value>,
    /// The joint law.
    pub joint: Option<JointSection>,
}

/// `[interface.joint]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSection {
    /// `"linear"`, `"frictional"`, `"sticking"` or `"bonded"` (tied: the
    /// facing nodes share their displacements; no parameters).
    pub law: String,
    /// Normal stiffness k_n, Pa/m (default β E / h).
    pub k_n: Option<f64>,
    /// Shear stiffness k_s, Pa/m (default k_n).
    pub k_s: Option<f64>,
    /// Penalty factor β of the default k_n = β E / h (default 10).
    pub penalty_factor: Option<f64>,
    /// Friction coefficient μ = tan φ (frictional).
    pub friction: Option<f64>,
    /// Cohesion c, Pa (frictional, default 0).
    pub cohesion: Option<f64>,
    /// Normals of the interface points: `"smoothed"` (default, one per
    /// node) or `"element"` (each element's chord, the classical element).
    pub normals: Option<String>,
}

/// `[thermal]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalSection {
    /// `[[thermal.bc]]`: conditions on edge sets (others are adiabatic).
    #[serde(default)]
    pub bc: Vec<ThermalBcSection>,
    /// `[thermal.initial]`.
    pub initial: Option<InitialSection>,
    /// `[thermal.schedule]`: absent → no transient.
    pub schedule: Option<ScheduleSection>,
    /// Capacity matrix: `"consistent"` (default) or `"lumped"`.
    #[serde(default)]
    pub capacity: Capacity,
}

/// The capacity matrix of the heat conduction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Capacity {
    /// Consistent (the element's exact mass matrix; the paper's).
    #[default]
    Consistent,
    /// Lumped (row sums on the diagonal): keeps the first time steps
    /// inside the temperature bounds where the mesh does not resolve a
    /// sharp initial temperature jump.
    Lumped,
}

impl Capacity {
    /// The name in case files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Capacity::Consistent => "consistent",
            Capacity::Lumped => "lumped",
        }
    }

    /// Parses `consistent` or `lumped` (the `--capacity` value).
    pub fn parse(s: &str) -> Result<Capacity, String> {
        match s {
            "consistent" => Ok(Capacity::Consistent),
            "lumped" => Ok(Capacity::Lumped),
            other => Err(format!("--capacity {other}: expected consistent or lumped")),
        }
    }

    /// The thermal crate's kind.
    pub fn kind(self) -> tecon_thermal::CapacityKind {
        match self {
            Capacity::Consistent => tecon_thermal::CapacityKind::Consistent,
            Capacity::Lumped => tecon_thermal::CapacityKind::Lumped,
        }
    }
}

/// `[[thermal.bc]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalBcSection {
    /// Edge set (Gmsh physical curve).
    pub edges: String,
    /// `"convection"`, `"temperature"` or `"flux"`.
    #[serde(rename = "type")]
    pub kind: String,
    /// Film coefficient h, W/(m² K) (convection).
    pub h: Option<f64>,
    /// Ambient temperature (convection).
    pub ambient: Option<f64>,
    /// Prescribed temperature (temperature).
    pub value: Option<f64>,
    /// Inward heat flux, W/m² (flux).
    pub q: Option<f64>,
}

/// `[thermal.initial]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSection {
    /// Temperature of every region not listed.
    pub default: Option<f64>,
    /// `[[thermal.initial.region]]`.
    #[serde(default)]
    pub region: Vec<RegionValue>,
}

/// A region and a value.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionValue {
    /// Region.
    pub region: String,
    /// Value.
    pub value: f64,
}

/// `[thermal.schedule]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScheduleSection {
    /// `[[t_end, dt], ...]`: steps of `dt` up to `t_end`, s.
    pub segments: Vec<[f64; 2]>,
    /// Time integration (default Crank–Nicolson).
    #[serde(default)]
    pub scheme: Scheme,
}

/// θ-method of the transient.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scheme {
    /// θ = 1/2 (with backward-Euler start-up steps).
    #[default]
    CrankNicolson,
    /// θ = 1.
    BackwardEuler,
}

/// Plane analysis type.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AnalysisName {
    /// ε_zz = 0.
    #[default]
    PlaneStrain,
    /// σ_zz = 0.
    PlaneStress,
    /// Uniform ε_zz, zero axial force.
    GeneralisedPlaneStrain,
}

/// `[mechanical]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MechanicalSection {
    /// Analysis type (default plane strain).
    #[serde(default)]
    pub analysis: AnalysisName,
    /// `[[mechanical.fix]]`.
    #[serde(default)]
    pub fix: Vec<FixSection>,
    /// `[[mechanical.symmetry]]`.
    #[serde(default)]
    pub symmetry: Vec<EdgesSection>,
    /// `[[mechanical.pressure]]`.
    #[serde(default)]
    pub pressure: Vec<PressureSection>,
    /// Remove rigid translations the supports leave free (default false).
    #[serde(default)]
    pub remove_free_translations: bool,
    /// Hold the three rigid modes (both translations and the rotation) of
    /// a body without supports, a full ring, by a statically determinate
    /// support on the nodes of this edge set (u_y = 0 at its node of
    /// largest x and at its node of smallest x, u_x = 0 at its node of
    /// largest y: reactions that vanish under self-equilibrated loads).
    pub hold_rigid_modes: Option<String>,
    /// Augmented-Lagrangian tolerance (default 1e-4; 0: pure penalty).
    pub augmented_lagrangian: Option<f64>,
    /// Stress-free temperature of every element (default: the initial field).
    pub reference_temperature: Option<f64>,
    /// Newton passes on the interface dofs alone, the bulk condensed onto
    /// them, where that is cheaper (default true; false: full passes
    /// always, as a cross-check: the answers agree to the tolerances).
    pub condensation: Option<bool>,
    /// With condensed passes, Newton steps in a coarse space of fields
    /// smooth along the interface before the first pass of an increment
    /// that starts far from equilibrium (default true; false as a
    /// cross-check: the answers agree to the tolerances).
    pub coarse_space: Option<bool>,
    /// Coarse levels of the coarse space before the first pass of a
    /// frictionless joint's increment (default
    /// [`tecon_elastic::COARSE_LEVELS`]; 1: the finest level alone).
    pub coarse_levels: Option<u32>,
    /// Under frozen friction limits, once the statuses of two passes in a
    /// row have settled, the rest of the increment's outer loop in Newton
    /// passes on the coupled law (default true; false as a cross-check:
    /// the answers agree to the outer loop's tolerance).
    pub coupled_tail: Option<bool>,
    /// Every Newton pass solved to the full tolerances, also those an
    /// outer update follows (default false: such passes may stop early,
    /// the last one is exact; true as a cross-check: the answers agree to
    /// the tolerances).
    pub exact_passes: Option<bool>,
}

/// `[[mechanical.fix]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixSection {
    /// Node set or edge set.
    pub set: String,
    /// `"x"` or `"y"`.
    pub component: ComponentName,
    /// Prescribed displacement, m (default 0).
    #[serde(default)]
    pub value: f64,
}

/// Displacement component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ComponentName {
    /// u_x.
    X,
    /// u_y.
    Y,
}

/// `[[mechanical.symmetry]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EdgesSection {
    /// Edge set.
    pub edges: String,
}

/// `[[mechanical.pressure]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PressureSection {
    /// Edge set.
    pub edges: String,
    /// Pressure, Pa (positive pushes against the outward normal).
    pub value: f64,
}

/// `[output]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Output times of the transient, s.
    #[serde(default)]
    pub times: Vec<f64>,
    /// VTK series (default true).
    pub vtk: Option<bool>,
    /// Nodal CSV per time (default false).
    #[serde(default)]
    pub csv_nodal: bool,
    /// Probe points `[x, y]`, m (nearest node; a point outside the mesh is an error).
    #[serde(default)]
    pub probes: Vec<[f64; 2]>,
}

/// One-line error naming the case file.
pub(crate) fn err(
    file: &Path,
    msg: impl std::fmt::Display,
) -> Box<dyn std::error::Error + Send + Sync> {
    format!("{}: {msg}", display(file)).into()
}

fn display(file: &Path) -> String {
    if file.as_os_str().is_empty() {
        "case".into()
    } else {
        file.display().to_string()
    }
}

/// A TOML error of `text` as one line naming the file, line and column,
/// and the key path at fault when it is known (`material[0].youngs_modulus`).
pub(crate) fn toml_error(text: &str, file: &Path, key: &str, e: &toml::de::Error) -> String {
    let at = e.span().map(|s| {
        let before = text.get(..s.start).unwrap_or(text);
        let line = before.matches('\n').count() + 1;
        let col = before.len() - before.rfind('\n').map_or(0, |p| p + 1) + 1;
        format!("{line}:{col}: ")
    });
    let mut msg = e.message().replace('\n', " ");
    let key = if key.is_empty() || key == "." {
        String::new()
    } else {
        if msg.contains("invalid type: map, expected a sequence") {
            // `[x]` or `[x.y]` where `x` is a list of tables (`[[x]]`)
            msg = format!(
                "{}; {key} is a list of tables: begin each entry with [[{key}]]",
                msg.trim()
            );
        }
        format!("{key}: ")
    };
    format!(
        "{}:{}{key}{}",
        display(file),
        at.map_or(" ".into(), |a| a),
        msg.trim()
    )
}

/// Deserializes a case file's TOML `text` (`file` names it in errors): a
/// syntax error names the line and column, a type error or an unknown key
/// also the key path at fault (`material[0].youngs_modulus`, `interfacee`).
/// Shared by the case files of `tecon run`, general and staged.
pub(crate) fn from_toml<'de, T: Deserialize<'de>>(text: &'de str, file: &Path) -> CliResult<T> {
    let de = toml::Deserializer::parse(text).map_err(|e| toml_error(text, file, "", &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let key = e.path().to_string();
        toml_error(text, file, &key, e.inner()).into()
    })
}

/// Parses a case from TOML text; `file` names it in errors.
pub fn parse(text: &str, file: &Path) -> CliResult<Case> {
    let mut case: Case = from_toml(text, file)?;
    case.source = file.to_path_buf();
    Ok(case)
}

/// Reads and parses a case file.
pub fn load(path: impl AsRef<Path>) -> CliResult<Case> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|e| err(path, e))?;
    parse(&text, path)
}

// ---------------------------------------------------------------------------
// Results
// ---------------------------------------------------------------------------

/// The state at one output time (the driver's state).
pub type StateResult = crate::driver::State;

/// A finished case.
#[derive(Debug)]
pub struct CaseResult {
    /// The mesh (with the interfaces the case declared).
    pub mesh: Mesh,
    /// Names of the model interfaces (index of [`InterfacePointResult::interface`]).
    pub interfaces: Vec<String>,
    /// One state per output time (and stage).
    pub states: Vec<StateResult>,
    /// Probe points and their nearest nodes.
    pub probes: Vec<([f64; 2], usize)>,
    /// The probes' temperatures at every thermal step of a transient (the
    /// nearest nodes', as `probes.csv`).
    pub history: Option<driver::TemperatureHistory>,
    /// The driver's statistics.
    pub newton: NewtonStats,
    /// Heat conduction summary.
    pub thermal: ThermalInfo,
    /// Wall-clock seconds: heat conduction, contact.
    pub seconds: (f64, f64),
    /// The summary (also written as `summary.json`; wall times go to `timing.json`).
    pub summary: Value,
    /// The printed yield check of the last output time.
    pub yield_lines: Vec<String>,
}

/// Runs the case (no files written): mesh and setup, then the driver.
/// A body the supports leave free (a singular system) in a case file: the
/// error with the keys that supply the missing support. Other errors as
/// they are.
fn constraint_hint(e: driver::DriverError) -> String {
    let free = matches!(
        e.elastic(),
        Some(tecon_elastic::ElasticError::Fem(
            tecon_fem::FemError::Unconstrained { .. }
        ))
    );
    if free {
        format!(
            "{e}. In a case file: [[mechanical.fix]] or [[mechanical.symmetry]] support a body; [mechanical] remove_free_translations = true removes translations the supports leave free; hold_rigid_modes = \"EDGES\" holds a body without supports (a full ring) in translation and rotation by a statically determinate support on the nodes of edge set EDGES"
        )
    } else {
        e.to_string()
    }
}

pub fn execute(case: &Case, base_dir: &Path) -> CliResult<CaseResult> {
    let start = std::time::Instant::now();
    let f = &case.source;
    crate::yield_check::check_case_keys(case).map_err(|e| err(f, e))?;
    // memory: a generator's size is known before it runs, a file's after reading
    if let Some((triangles, order)) = crate::memory::case_triangles(case) {
        crate::memory::check("[mesh]", triangles, order).map_err(|e| err(f, e))?;
    }
    let mut mesh = setup::build_mesh(case, base_dir)?;
    crate::memory::check("[mesh]", mesh.n_triangles(), mesh.order()).map_err(|e| err(f, e))?;
    crate::probes::check_inside(&mesh, &case.output.probes, "output.probes")
        .map_err(|e| err(f, e))?;
    setup::declare_interfaces(case, &mut mesh)?;
    // bodies touching without an interface, a Gmsh mesh that looks like mm, ...
    let mesh_warnings: Vec<String> = mesh
        .warnings()
        .iter()
        .map(|w| format!("mesh: {w}"))
        .collect();
    let tie = setup::tie(case, &mesh)?;
    let (outcome, joints, al, analysis, probes, bound_violation) = {
        let p = setup::prepare(case, &mesh, tie.as_ref())?;
        let nodes: Vec<usize> = p.probes.iter().map(|&(_, i)| i).collect();
        let outcome =
            driver::run_recording(&p.setup, &nodes).map_err(|e| err(f, constraint_hint(e)))?;
        // the measure of `tecon vessel`'s thermal.bound_violation
        let bound_violation = outcome
            .bound_violation
            .as_ref()
            .map_or((0.0, 0.0), |b| (b.excursion, b.output_excursion));
        (
            outcome,
            p.joints,
            p.augmented_lagrangian,
            p.analysis,
            p.probes,
            bound_violation,
        )
    };
    let thermal_json = match outcome.thermal.mode {
        ThermalMode::None => Value::Null,
        ThermalMode::Held => json!({ "mode": "initial" }),
        ThermalMode::Steady => json!({
            "mode": "steady",
            "heat_balance_max_rel_error": outcome.thermal.max_balance_residual,
            "bound_violation": bound_violation.0,
        }),
        ThermalMode::Transient => json!({
            "mode": "transient",
            "capacity": case.thermal.as_ref().map_or("consistent", |t| t.capacity.name()),
            "steps": outcome.thermal.steps,
            "heat_balance_max_rel_error": outcome.thermal.max_balance_residual,
            "bound_violation": bound_violation.0,
            "bound_violation_at_outputs": bound_violation.1,
        }),
    };
    let mut summary = json!({
        "case": display(f),
        "mesh": {
            "nodes": mesh.n_nodes(),
            "triangles": mesh.n_triangles(),
            "interface_elements": mesh.interfaces().values().map(|i| i.elements.len()).sum::<usize>(),
            "regions": mesh.region_names(),
        },
        "analysis": format!("{:?}", analysis),
        "thermal": thermal_json,
        "joints": joints,
        "augmented_lagrangian": al,
        "times": outcome.states.iter().map(|r| state_summary(&mesh, &outcome.interfaces, r)).collect::<Vec<_>>(),
        "notes": outcome.notes,
    });
    // over every contact solve, written or not
    summary["newton_max_iterations_per_increment"] = json!(outcome.newton.max_per_increment);
    summary["newton_max_iterations_per_pass"] = json!(outcome.newton.max_per_pass);
    // the bulk condensed onto this many interface dofs (null: full passes)
    summary["newton_condensed_interface_dofs"] = json!(outcome.newton.condensed_dofs);
    summary["newton_failed_attempt_iterations"] = json!(outcome.newton.failed_iterations);
    summary["newton_coupled_increments"] = json!(outcome.newton.coupled_increments);
    summary["newton_inexact_passes"] = json!(outcome.newton.inexact_passes);
    // Newton steps in the coarse interface space (not in the iterations)
    summary["newton_coarse_iterations"] = json!(outcome.newton.coarse_iterations);
    summary["newton_max_coarse_iterations_per_increment"] =
        json!(outcome.newton.max_coarse_per_increment);
    summary["newton_coarse_space_dofs"] = json!(outcome.newton.coarse_dofs);
    summary["newton_coupled_tail_passes"] = json!(outcome.newton.coupled_tail_passes);
    summary["newton_early_coupled_passes"] = json!(outcome.newton.early_coupled_passes);
    summary["newton_mixed_multiplier_updates"] = json!(outcome.newton.mixed_multiplier_updates);
    if let Some(c) = &outcome.coupling {
        summary["coupling"] = crate::vessel::coupling_json(c);
        summary["coupling"]["per_output"] = json!(
            outcome
                .states
                .iter()
                .map(|r| r.coupling_iterations)
                .collect::<Vec<_>>()
        );
    } else {
        summary["coupling"] = json!({ "mode": "one-way" });
    }
    // the yield check at every output time (elastic: a warning where σ_vM > σ_y)
    let (checks, warnings, yield_lines) =
        crate::yield_check::check_states(&mesh, &outcome.states, &|r| {
            case.material
                .iter()
                .find(|m| m.region == r)
                .and_then(|m| m.yield_stress)
        });
    if let Some(h) = &outcome.history {
        summary["temperature_history"] =
            writers::history_summary(&mesh, &history_probes(&probes), h);
    }
    summary["yield_check"] = checks;
    let warnings: Vec<String> = mesh_warnings.into_iter().chain(warnings).collect();
    if !warnings.is_empty() {
        summary["warnings"] = json!(warnings);
    }
    summary["seconds"] = json!(start.elapsed().as_secs_f64());
    Ok(CaseResult {
        mesh,
        interfaces: outcome.interfaces,
        states: outcome.states,
        probes,
        history: outcome.history,
        newton: outcome.newton,
        thermal: outcome.thermal,
        seconds: (outcome.thermal_seconds, outcome.contact_seconds),
        summary,
        yield_lines,
    })
}

/// The case's probes as the points of the temperature history: `probe<k>`,
/// labelled with the point asked for, as in `probes.csv`.
pub fn history_probes(probes: &[([f64; 2], usize)]) -> Vec<writers::HistoryProbe> {
    probes
        .iter()
        .enumerate()
        .map(|(k, &(p, node))| writers::HistoryProbe {
            name: format!("probe{k}"),
            label: format!("probe {k} ({}, {})", p[0], p[1]),
            node,
        })
        .collect()
}

/// Arc-length weighted mean contact pressure (open points count as 0) and
/// point counts of one interface; `weights` parallel to `points` (see
/// [`writers::interface_summary`]).
pub fn interface_summary(points: &[InterfacePointResult], weights: &[f64], index: usize) -> Value {
    writers::interface_summary(points, weights, index)
}

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

/// Writes all outputs into `out` (staged: a temporary folder inside `out`,
/// moved into place at the end, `summary.json` last; on failure nothing is
/// moved and the temporary folder, and `out` if this call created it, is
/// removed).
pub fn write_outputs(case: &Case, res: &CaseResult, out: &Path) -> CliResult<()> {
    writers::staged(out, |dir| {
        let mut files = writers::write_states(
            dir,
            &res.mesh,
            &res.interfaces,
            &res.states,
            StateFiles {
                vtu_stem: "state",
                pvd: "case.pvd",
                vtk: case.output.vtk.unwrap_or(true),
                csv_nodal: case.output.csv_nodal,
                csv_interface: true,
            },
        )?;
        files.extend(writers::write_probes(
            dir,
            &res.mesh,
            &res.probes,
            &res.states,
        )?);
        if let Some(h) = &res.history {
            // the output times, marked on the history
            let times: Vec<f64> = res.states.iter().map(|r| r.time).collect();
            files.extend(writers::write_temperature_history(
                dir,
                &history_probes(&res.probes),
                h,
                &times,
            )?);
        }
        // wall times apart, so that summary.json is bitwise the same for any thread count
        let mut summary = res.summary.clone();
        let mut timing = crate::front::split_timing(&mut summary);
        timing["seconds_heat_conduction"] = json!(res.seconds.0);
        timing["seconds_contact"] = json!(res.seconds.1);
        writers::write(
            &dir.join("timing.json"),
            &(serde_json::to_string_pretty(&timing)? + "\n"),
        )?;
        files.push("timing.json".into());
        writers::write(
            &dir.join("summary.json"),
            &serde_json::to_string_pretty(&summary)?,
        )?;
        files.push("summary.json".into());
        Ok(files)
    })
}

// ---------------------------------------------------------------------------
// The command
// ---------------------------------------------------------------------------

/// Arguments of `tecon run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// The case file (TOML; format in the README, "Case files").
    #[arg(value_name = "CASE")]
    pub case: PathBuf,
    /// Output folder (default `tecon-out/run/<case file stem>`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print nothing but warnings and errors: no progress bar, no report on
    /// the terminal (the report is in the output folder's report.txt).
    #[arg(long)]
    pub quiet: bool,
}

/// A short human-readable report of a finished case.
pub fn report(res: &CaseResult) -> String {
    let v = &res.summary;
    let mut s = format!(
        "mesh: {} nodes, {} triangles, {} interface elements\n",
        v["mesh"]["nodes"], v["mesh"]["triangles"], v["mesh"]["interface_elements"]
    );
    if let Some(t) = v["times"].as_array() {
        for st in t {
            s += &format!(
                "t = {} s: max |u| = {:.4e} m, max von Mises = {:.4e} Pa",
                st["time"],
                st["max_displacement"].as_f64().unwrap_or(f64::NAN),
                st["max_von_mises"].as_f64().unwrap_or(f64::NAN)
            );
            if let Some(m) = st["interfaces"].as_object() {
                for (name, i) in m {
                    s += &format!(
                        ", {name}: mean contact pressure {:.4e} Pa",
                        i["contact_pressure_mean"].as_f64().unwrap_or(f64::NAN)
                    );
                }
            }
            s.push('\n');
        }
    }
    for l in writers::history_lines(&v["temperature_history"]) {
        s += &l;
        s.push('\n');
    }
    if let Some(notes) = v["notes"].as_array() {
        for n in notes {
            s += &format!("note: {}\n", n.as_str().unwrap_or_default());
        }
    }
    for l in &res.yield_lines {
        s += l;
        s.push('\n');
    }
    if let Some(w) = v["warnings"].as_array() {
        for w in w {
            s += &format!("warning: {}\n", w.as_str().unwrap_or_default());
        }
    }
    s
}

/// The default output folder of `tecon run CASE.toml`:
/// `tecon-out/run/<case file stem>` (apart from the folders of `tecon vessel`
/// and `tecon mesh`, so `tecon run examples/cases/vessel.toml` does not
/// replace the results of `tecon vessel`).
pub fn default_out(case_file: &Path) -> PathBuf {
    let stem = case_file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "case".into());
    Path::new("tecon-out").join("run").join(stem)
}

/// Runs `tecon run`.
pub fn run(args: RunArgs) -> CliResult<()> {
    let text = std::fs::read_to_string(&args.case).map_err(|e| err(&args.case, e))?;
    if crate::case_stages::is_staged(&text) {
        // [multilayer] + [[stage]]: the pipeline of `tecon vessel --layers`
        let mut case = crate::case_stages::parse(&text, &args.case)?;
        case.progress = !args.quiet;
        let out = args.out.clone().unwrap_or_else(|| default_out(&args.case));
        let text =
            crate::case_stages::run(&case, &out).map_err(|e| e.to_string().replace('\n', "; "))?;
        if !args.quiet {
            print!("{text}");
            println!("results in {}", out.display());
        }
        return Ok(());
    }
    let mut case = parse(&text, &args.case)?;
    // a progress bar on stderr (indicatif draws nothing when it is not a terminal)
    case.progress = !args.quiet;
    let base = args
        .case
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let out = args.out.clone().unwrap_or_else(|| default_out(&args.case));
    // input errors are one line naming the file; a solver failure keeps its
    // report's lines (the summary first, then the attempts and the iteration
    // history), as `tecon vessel` prints it
    let res = execute(&case, &base)?;
    write_outputs(&case, &res, &out)?;
    let text = report(&res);
    let txt = out.join(crate::report_html::REPORT_TEXT);
    std::fs::write(&txt, &text).map_err(|e| format!("{}: {e}", txt.display()))?;
    if args.quiet {
        // nothing but the warnings (stderr), as `tecon vessel --quiet`
        for w in warnings(&res.summary) {
            eprintln!("warning: {w}");
        }
    } else {
        print!("{text}");
        println!("results in {}", out.display());
    }
    Ok(())
}

/// The warnings of a case's summary (the mesh's, a yield stress exceeded).
fn warnings(summary: &Value) -> Vec<&str> {
    summary["warnings"]
        .as_array()
        .map(|w| w.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default()
}
