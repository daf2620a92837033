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
//! tecon run examples/cases/shrink_fit.toml            # results in tecon-out/shrink_fit/
//! tecon run my_case.toml --out results/my_case --quiet
//! ```
//!
//! The format is documented in the README ("Case files"). Every table
//! rejects unknown keys; every error is one line naming the case file and
//! the key, region, edge set or interface at fault. Results are written into
//! a temporary folder inside the output folder and moved into place only
//! when everything has been written (`summary.json` last).

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use serde::Deserialize;
use serde_json::{Value, json};
use tecon_contact::{ContactStatus, ElasticJoint, GhaboussiNormal, LinearJoint, PaperJoint};
use tecon_elastic::{
    Analysis, Component, ElasticModel, InterfaceNormals, InterfacePointResult, Joint, Loads,
    Material, SolverOptions, StaticSolver, StressField, polar, von_mises,
};
use tecon_mesh::vtk::{Field, VtuPiece, write_pvd, write_vtu};
use tecon_mesh::{
    Mesh, RingLayer, VesselGeometry, layered_annulus, read_msh, rectangle, vessel_mesh,
};
use tecon_thermal::{EdgeBc, ThermalModel, ThetaScheme, TimeSchedule};

use crate::plot::{LinePlot, Series};

/// Boxed error of the command layer.
pub type CliResult<T> = Result<T, Box<dyn std::error::Error + Send + Sync>>;

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
    /// The file the case was read from (used in error messages); empty for
    /// a case parsed from a string.
    #[serde(skip)]
    pub source: PathBuf,
}

/// `[mesh]`: exactly one of `file` or `generator`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSection {
    /// Gmsh MSH 4.1 file, relative to the case file.
    pub file: Option<PathBuf>,
    /// `"vessel"`, `"annulus"` or `"rectangle"`.
    pub generator: Option<String>,
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
    /// Thermal conductance h_c, W/(m² K); absent: adiabatic.
    pub conductance: Option<f64>,
    /// The joint law.
    pub joint: Option<JointSection>,
}

/// `[interface.joint]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSection {
    /// `"linear"`, `"frictional"` or `"sticking"`.
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
    /// Augmented-Lagrangian tolerance (default 1e-4; 0: pure penalty).
    pub augmented_lagrangian: Option<f64>,
    /// Stress-free temperature of every element (default: the initial field).
    pub reference_temperature: Option<f64>,
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
    /// Probe points `[x, y]`, m (nearest node).
    #[serde(default)]
    pub probes: Vec<[f64; 2]>,
}

/// One-line error naming the case file.
fn err(file: &Path, msg: impl std::fmt::Display) -> Box<dyn std::error::Error + Send + Sync> {
    format!("{}: {msg}", display(file)).into()
}

fn display(file: &Path) -> String {
    if file.as_os_str().is_empty() {
        "case".into()
    } else {
        file.display().to_string()
    }
}

/// Parses a case from TOML text; `file` names it in errors.
pub fn parse(text: &str, file: &Path) -> CliResult<Case> {
    let mut case: Case = toml::from_str(text).map_err(|e| {
        let at = e.span().map(|s| {
            let before = text.get(..s.start).unwrap_or(text);
            let line = before.matches('\n').count() + 1;
            let col = before.len() - before.rfind('\n').map_or(0, |p| p + 1) + 1;
            format!("{line}:{col}: ")
        });
        let msg = e.message().replace('\n', " ");
        format!(
            "{}:{}{}",
            display(file),
            at.map_or(" ".into(), |a| a),
            msg.trim()
        )
    })?;
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

/// The state at one output time.
#[derive(Debug, Clone)]
pub struct StateResult {
    /// Time, s (0 for a steady or held state).
    pub time: f64,
    /// Nodal temperatures (None without `[thermal]`).
    pub temperature: Option<Vec<f64>>,
    /// Displacements (2 per node).
    pub displacement: Vec<f64>,
    /// Out-of-plane strain (generalised plane strain; 0 otherwise).
    pub eps_zz: f64,
    /// Stresses.
    pub stress: StressField,
    /// Interface points (all interfaces, in model order).
    pub interface: Vec<InterfacePointResult>,
    /// Relative heat-balance residual (transient).
    pub heat_balance: Option<f64>,
    /// Most Newton iterations of one pass in any increment.
    pub max_iterations: usize,
}

/// A finished case.
#[derive(Debug)]
pub struct CaseResult {
    /// The mesh (with the interfaces the case declared).
    pub mesh: Mesh,
    /// Names of the model interfaces (index of [`InterfacePointResult::interface`]).
    pub interfaces: Vec<String>,
    /// One state per output time.
    pub states: Vec<StateResult>,
    /// Probe points and their nearest nodes.
    pub probes: Vec<([f64; 2], usize)>,
    /// The summary (also written as `summary.json`).
    pub summary: Value,
}

// ---------------------------------------------------------------------------
// Building the model
// ---------------------------------------------------------------------------

fn positive(file: &Path, key: &str, v: f64) -> CliResult<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(err(file, format!("{key} = {v}: must be positive")))
    }
}

fn build_mesh(case: &Case, base: &Path) -> CliResult<Mesh> {
    let f = &case.source;
    let m = &case.mesh;
    let vessel_keys = [
        ("preset", m.preset.is_some()),
        ("fused_weld", m.fused_weld.is_some()),
        ("inner_radius", m.inner_radius.is_some()),
        ("core_thickness", m.core_thickness.is_some()),
        ("layer_thickness", m.layer_thickness.is_some()),
        ("weld_half_width", m.weld_half_width.is_some()),
    ];
    let annulus_keys = [
        ("layer", !m.layer.is_empty()),
        ("theta0", m.theta0.is_some()),
        ("theta1", m.theta1.is_some()),
        ("segments", m.segments.is_some()),
    ];
    let rect_keys = [
        ("origin", m.origin.is_some()),
        ("size", m.size.is_some()),
        ("divisions", m.divisions.is_some()),
    ];
    let only = |keys: &[(&str, bool)], owner: &str| -> CliResult<()> {
        if let Some((k, _)) = keys.iter().find(|(_, set)| *set) {
            return Err(err(
                f,
                format!("mesh.{k}: only used with generator = \"{owner}\""),
            ));
        }
        Ok(())
    };
    let mesh_err = |e: tecon_mesh::MeshError| err(f, format!("mesh: {e}"));
    match (&m.file, m.generator.as_deref()) {
        (Some(_), Some(_)) => Err(err(f, "[mesh]: give either file or generator, not both")),
        (None, None) => Err(err(
            f,
            "[mesh]: give file = \"x.msh\" or generator = \"vessel\" | \"annulus\" | \"rectangle\"",
        )),
        (Some(file), None) => {
            only(&vessel_keys, "vessel")?;
            only(&annulus_keys, "annulus")?;
            only(&rect_keys, "rectangle")?;
            let path = base.join(file);
            read_msh(&path).map_err(|e| err(f, format!("mesh.file: {e}")))
        }
        (None, Some("vessel")) => {
            only(&annulus_keys, "annulus")?;
            only(&rect_keys, "rectangle")?;
            let spec = match &m.preset {
                None => crate::vessel::default_mesh(),
                Some(toml::Value::String(s)) => crate::mesh_cmd::parse_preset(s)
                    .map_err(|e| err(f, format!("mesh.preset: {}", e.replace("--preset ", ""))))?,
                Some(toml::Value::Integer(l)) => u32::try_from(*l)
                    .ok()
                    .and_then(|l| tecon_mesh::VesselMeshSpec::refined(l).ok())
                    .ok_or_else(|| {
                        err(
                            f,
                            format!("mesh.preset = {l}: expected \"paper\" or a level 0-9"),
                        )
                    })?,
                Some(other) => {
                    return Err(err(
                        f,
                        format!("mesh.preset = {other}: expected \"paper\" or a level 0-9"),
                    ));
                }
            };
            let d = VesselGeometry::default();
            let geo = VesselGeometry {
                inner_radius: positive(
                    f,
                    "mesh.inner_radius",
                    m.inner_radius.unwrap_or(d.inner_radius),
                )?,
                core_thickness: positive(
                    f,
                    "mesh.core_thickness",
                    m.core_thickness.unwrap_or(d.core_thickness),
                )?,
                layer_thickness: positive(
                    f,
                    "mesh.layer_thickness",
                    m.layer_thickness.unwrap_or(d.layer_thickness),
                )?,
                weld_half_width: positive(
                    f,
                    "mesh.weld_half_width",
                    m.weld_half_width.unwrap_or(d.weld_half_width),
                )?,
            };
            let spec = tecon_mesh::VesselMeshSpec {
                fused_weld: m.fused_weld.unwrap_or(false),
                ..spec
            };
            vessel_mesh(&geo, &spec).map_err(mesh_err)
        }
        (None, Some("annulus")) => {
            only(&vessel_keys, "vessel")?;
            only(&rect_keys, "rectangle")?;
            if m.layer.is_empty() {
                return Err(err(
                    f,
                    "mesh.layer: the annulus needs at least one [[mesh.layer]]",
                ));
            }
            let mut layers = Vec::new();
            for (k, l) in m.layer.iter().enumerate() {
                let key = format!("mesh.layer[{k}] ('{}')", l.name);
                positive(f, &format!("{key}.r_in"), l.r_in)?;
                if !(l.r_out.is_finite() && l.r_out > l.r_in) {
                    return Err(err(
                        f,
                        format!(
                            "{key}: thickness r_out - r_in = {} must be positive",
                            l.r_out - l.r_in
                        ),
                    ));
                }
                if l.rows == 0 {
                    return Err(err(f, format!("{key}.rows: at least 1")));
                }
                layers.push(RingLayer {
                    name: l.name.clone(),
                    r_in: l.r_in,
                    r_out: l.r_out,
                    rows: l.rows,
                });
            }
            let segments = m
                .segments
                .ok_or_else(|| err(f, "mesh.segments: the annulus needs the intervals around"))?;
            let t0 = m.theta0.unwrap_or(0.0).to_radians();
            let t1 = m.theta1.unwrap_or(360.0).to_radians();
            layered_annulus(&layers, t0, t1, segments).map_err(mesh_err)
        }
        (None, Some("rectangle")) => {
            only(&vessel_keys, "vessel")?;
            only(&annulus_keys, "annulus")?;
            let o = m.origin.unwrap_or([0.0, 0.0]);
            let s = m
                .size
                .ok_or_else(|| err(f, "mesh.size: the rectangle needs [width, height]"))?;
            let d = m
                .divisions
                .ok_or_else(|| err(f, "mesh.divisions: the rectangle needs [nx, ny]"))?;
            positive(f, "mesh.size[0] (width)", s[0])?;
            positive(f, "mesh.size[1] (height)", s[1])?;
            rectangle(o[0], o[1], s[0], s[1], d[0], d[1]).map_err(mesh_err)
        }
        (None, Some(other)) => Err(err(
            f,
            format!(
                "mesh.generator = \"{other}\": expected \"vessel\", \"annulus\" or \"rectangle\""
            ),
        )),
    }
}

/// Region index → material section; every region needs exactly one.
fn materials<'c>(case: &'c Case, mesh: &Mesh) -> CliResult<Vec<&'c MaterialSection>> {
    let f = &case.source;
    let names = mesh.region_names();
    let mut per: Vec<Option<&MaterialSection>> = vec![None; names.len()];
    for (k, m) in case.material.iter().enumerate() {
        let r = mesh
            .region_index(&m.region)
            .map_err(|e| err(f, format!("material[{k}].region: {e}")))?;
        if per[r].is_some() {
            return Err(err(
                f,
                format!(
                    "material[{k}]: region '{}' has two [[material]] entries",
                    m.region
                ),
            ));
        }
        let key = format!("material[{k}] (region '{}')", m.region);
        positive(f, &format!("{key}.youngs_modulus"), m.youngs_modulus)?;
        if !(m.poisson_ratio.is_finite() && m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5) {
            return Err(err(
                f,
                format!(
                    "{key}.poisson_ratio = {}: must lie in (-1, 0.5)",
                    m.poisson_ratio
                ),
            ));
        }
        for (name, v) in [
            ("conductivity", m.conductivity),
            ("density", m.density),
            ("specific_heat", m.specific_heat),
        ] {
            if let Some(v) = v {
                positive(f, &format!("{key}.{name}"), v)?;
            }
        }
        if let Some(a) = m.expansion
            && !a.is_finite()
        {
            return Err(err(f, format!("{key}.expansion = {a}: must be finite")));
        }
        per[r] = Some(m);
    }
    per.iter()
        .enumerate()
        .map(|(r, m)| {
            m.ok_or_else(|| {
                err(
                    f,
                    format!(
                        "region '{}' has no [[material]] (regions: {})",
                        names[r],
                        names.join(", ")
                    ),
                )
            })
        })
        .collect()
}

/// Element size across the interface: the smaller of the mean heights of
/// the triangles on each face, and the largest Young's modulus next to it.
fn interface_scale(mesh: &Mesh, name: &str, mats: &[&MaterialSection]) -> Option<(f64, f64)> {
    let iface = mesh.interfaces().get(name)?;
    let mut edge_tri: HashMap<(usize, usize), usize> = HashMap::new();
    for (e, t) in mesh.triangles().iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edge_tri.insert((a.min(b), a.max(b)), e);
        }
    }
    let x = mesh.nodes();
    let areas = mesh.areas();
    let regions = mesh.element_regions();
    let mut e_max: f64 = 0.0;
    let mut h = [0.0f64, 0.0];
    let mut n = [0usize, 0];
    for el in &iface.elements {
        for (side, (a, b)) in [(el[0], el[1]), (el[2], el[3])].into_iter().enumerate() {
            if let Some(&t) = edge_tri.get(&(a.min(b), a.max(b))) {
                let len = ((x[a][0] - x[b][0]).powi(2) + (x[a][1] - x[b][1]).powi(2)).sqrt();
                if len > 0.0 {
                    h[side] += 2.0 * areas[t].abs() / len;
                    n[side] += 1;
                }
                e_max = e_max.max(mats[regions[t]].youngs_modulus);
            }
        }
    }
    let mean = |s: usize| {
        if n[s] > 0 {
            h[s] / n[s] as f64
        } else {
            f64::INFINITY
        }
    };
    let size = mean(0).min(mean(1));
    (size.is_finite() && e_max > 0.0).then_some((size, e_max))
}

fn joint(
    f: &Path,
    key: &str,
    j: &JointSection,
    scale: Option<(f64, f64)>,
) -> CliResult<(Joint, Value)> {
    let check = |name: &str, v: Option<f64>| -> CliResult<Option<f64>> {
        v.map(|v| positive(f, &format!("{key}.{name}"), v))
            .transpose()
    };
    let k_n_given = check("k_n", j.k_n)?;
    let k_s_given = check("k_s", j.k_s)?;
    let beta = check("penalty_factor", j.penalty_factor)?;
    if k_n_given.is_some() && beta.is_some() {
        return Err(err(
            f,
            format!("{key}: give k_n or penalty_factor, not both"),
        ));
    }
    let k_n = match k_n_given {
        Some(k) => k,
        None => {
            let (h, e) = scale.ok_or_else(|| {
                err(
                    f,
                    format!("{key}.k_n: cannot size the default penalty; give k_n"),
                )
            })?;
            beta.unwrap_or(tecon_contact::DEFAULT_PENALTY_FACTOR) * e / h
        }
    };
    let k_s = k_s_given.unwrap_or(k_n);
    let law_err = |e: tecon_contact::LawError| err(f, format!("{key}: {e}"));
    let unused = |names: &[(&str, bool)]| -> CliResult<()> {
        if let Some((n, _)) = names.iter().find(|(_, s)| *s) {
            return Err(err(
                f,
                format!("{key}.{n}: not a parameter of law = \"{}\"", j.law),
            ));
        }
        Ok(())
    };
    let joint = match j.law.as_str() {
        "linear" => {
            unused(&[
                ("friction", j.friction.is_some()),
                ("cohesion", j.cohesion.is_some()),
            ])?;
            Joint::Linear(LinearJoint::new(k_s, k_n).map_err(law_err)?)
        }
        "sticking" => {
            unused(&[
                ("friction", j.friction.is_some()),
                ("cohesion", j.cohesion.is_some()),
            ])?;
            Joint::Sticking(
                ElasticJoint::new(GhaboussiNormal::penalty(k_n).map_err(law_err)?, k_s)
                    .map_err(law_err)?,
            )
        }
        "frictional" => {
            let mu = j.friction.ok_or_else(|| {
                err(
                    f,
                    format!("{key}.friction: the frictional law needs a friction coefficient"),
                )
            })?;
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(err(
                    f,
                    format!("{key}.friction = {mu}: must be non-negative"),
                ));
            }
            let c = j.cohesion.unwrap_or(0.0);
            if !(c.is_finite() && c >= 0.0) {
                return Err(err(
                    f,
                    format!("{key}.cohesion = {c}: must be non-negative"),
                ));
            }
            Joint::Frictional(
                PaperJoint::new(
                    GhaboussiNormal::penalty(k_n).map_err(law_err)?,
                    k_s,
                    c,
                    mu.atan(),
                )
                .map_err(law_err)?,
            )
        }
        other => {
            return Err(err(
                f,
                format!(
                    "{key}.law = \"{other}\": expected \"linear\", \"frictional\" or \"sticking\""
                ),
            ));
        }
    };
    Ok((
        joint,
        json!({ "law": j.law, "k_n": k_n, "k_s": k_s, "friction": j.friction, "cohesion": j.cohesion }),
    ))
}

/// A temperature state before the mechanical solve.
struct Thermal {
    time: f64,
    temperature: Vec<f64>,
    element_temperature: Vec<f64>,
    heat_balance: Option<f64>,
}

/// Runs the case (no files written).
pub fn execute(case: &Case, base_dir: &Path) -> CliResult<CaseResult> {
    let start = std::time::Instant::now();
    let f = &case.source;
    let mut mesh = build_mesh(case, base_dir)?;

    // Interfaces.
    let mut seen = BTreeMap::new();
    for (k, i) in case.interface.iter().enumerate() {
        let key = format!("interface[{k}] ('{}')", i.name);
        if seen.insert(i.name.clone(), k).is_some() {
            return Err(err(f, format!("{key}: declared twice")));
        }
        match (&i.bottom, &i.top) {
            (Some(b), Some(t)) => {
                if mesh.interfaces().contains_key(&i.name) {
                    return Err(err(
                        f,
                        format!(
                            "{key}: the mesh generator already made this interface; omit bottom and top"
                        ),
                    ));
                }
                mesh.add_interface(&i.name, b, t, None)
                    .map_err(|e| err(f, format!("{key}: {e}")))?;
            }
            (None, None) => {
                mesh.interface(&i.name).map_err(|e| {
                    err(
                        f,
                        format!("{key}: {e}; give bottom and top edge sets to make it"),
                    )
                })?;
            }
            _ => return Err(err(f, format!("{key}: give both bottom and top edge sets"))),
        }
        if let Some(h) = i.conductance {
            positive(f, &format!("{key}.conductance"), h)?;
            if case.thermal.is_none() {
                return Err(err(
                    f,
                    format!("{key}.conductance: needs a [thermal] section"),
                ));
            }
        }
    }
    for name in mesh.interfaces().keys() {
        if !seen.contains_key(name) {
            return Err(err(
                f,
                format!(
                    "the mesh has interface '{name}' but the case has no [[interface]] name = \"{name}\" with its joint"
                ),
            ));
        }
    }
    let mats = materials(case, &mesh)?;
    let names = mesh.region_names().to_vec();

    // Output options.
    let mut times = case.output.times.clone();
    for t in &times {
        if !t.is_finite() || *t < 0.0 {
            return Err(err(f, format!("output.times: {t} is not a time ≥ 0")));
        }
    }
    times.sort_by(f64::total_cmp);
    times.dedup();
    let probes: Vec<([f64; 2], usize)> = case
        .output
        .probes
        .iter()
        .map(|&p| (p, nearest(&mesh, p)))
        .collect();

    // Heat conduction.
    let mut states: Vec<Thermal> = Vec::new();
    let mut t_ref: Option<Vec<f64>> = None;
    let mut thermal_json = Value::Null;
    if let Some(th) = &case.thermal {
        let mut model = ThermalModel::new(&mesh);
        for (r, m) in mats.iter().enumerate() {
            let need = |name: &str, v: Option<f64>| {
                v.ok_or_else(|| {
                    err(
                        f,
                        format!(
                            "material for region '{}': {name} is needed with [thermal]",
                            names[r]
                        ),
                    )
                })
            };
            let mat = tecon_thermal::Material::new(
                need("conductivity", m.conductivity)?,
                need("density", m.density)?,
                need("specific_heat", m.specific_heat)?,
            );
            model
                .set_material(&names[r], mat)
                .map_err(|e| err(f, format!("material: {e}")))?;
        }
        for (k, b) in th.bc.iter().enumerate() {
            let key = format!("thermal.bc[{k}] (edges '{}')", b.edges);
            let need = |n: &str, v: Option<f64>| {
                v.ok_or_else(|| err(f, format!("{key}: type = \"{}\" needs {n}", b.kind)))
            };
            let extra = |allowed: &[&str]| -> CliResult<()> {
                for (n, s) in [
                    ("h", b.h),
                    ("ambient", b.ambient),
                    ("value", b.value),
                    ("q", b.q),
                ] {
                    if s.is_some() && !allowed.contains(&n) {
                        return Err(err(
                            f,
                            format!("{key}.{n}: not a parameter of type = \"{}\"", b.kind),
                        ));
                    }
                }
                Ok(())
            };
            let bc = match b.kind.as_str() {
                "convection" => {
                    extra(&["h", "ambient"])?;
                    EdgeBc::convection(need("h", b.h)?, need("ambient", b.ambient)?)
                }
                "temperature" => {
                    extra(&["value"])?;
                    EdgeBc::temperature(need("value", b.value)?)
                }
                "flux" => {
                    extra(&["q"])?;
                    EdgeBc::flux(need("q", b.q)?)
                }
                other => {
                    return Err(err(
                        f,
                        format!(
                            "{key}.type = \"{other}\": expected \"convection\", \"temperature\" or \"flux\""
                        ),
                    ));
                }
            };
            model
                .add_edge_bc(&b.edges, bc)
                .map_err(|e| err(f, format!("{key}: {e}")))?;
        }
        for i in &case.interface {
            match i.conductance {
                Some(h) => model.set_interface_conductance(&i.name, h),
                None => model.set_interface_adiabatic(&i.name),
            }
            .map_err(|e| err(f, format!("interface '{}': {e}", i.name)))?;
        }
        let init = th.initial.as_ref().ok_or_else(|| {
            err(
                f,
                "thermal.initial: [thermal] needs initial temperatures (default = ...)",
            )
        })?;
        if let Some(d) = init.default {
            model
                .set_initial_default(d)
                .map_err(|e| err(f, format!("thermal.initial.default: {e}")))?;
        }
        for (k, r) in init.region.iter().enumerate() {
            model
                .set_initial_region(&r.region, r.value)
                .map_err(|e| err(f, format!("thermal.initial.region[{k}]: {e}")))?;
        }
        let system = model
            .assemble()
            .map_err(|e| err(f, format!("thermal: {e}")))?;
        let reference = system
            .reference_temperature()
            .ok_or_else(|| err(f, "thermal.initial: no initial temperature"))?;
        match &th.schedule {
            Some(s) => {
                if times.is_empty() {
                    return Err(err(f, "output.times: a transient needs output times"));
                }
                let segs: Vec<(f64, f64)> = s.segments.iter().map(|s| (s[0], s[1])).collect();
                let schedule = TimeSchedule::segments(&segs)
                    .map_err(|e| err(f, format!("thermal.schedule.segments: {e}")))?;
                let scheme = match s.scheme {
                    Scheme::CrankNicolson => ThetaScheme::crank_nicolson(),
                    Scheme::BackwardEuler => ThetaScheme::backward_euler(),
                };
                let summary =
                    tecon_thermal::run_transient(&system, &schedule, scheme, &times, |s| {
                        // report the requested output time (the stepper's
                        // clock carries round-off from summing steps)
                        let k = states.len();
                        states.push(Thermal {
                            time: times.get(k).copied().unwrap_or(s.time),
                            temperature: s.temperature.clone(),
                            element_temperature: s.element_temperature.clone(),
                            heat_balance: Some(s.balance.relative_residual()),
                        })
                    })
                    .map_err(|e| err(f, format!("output.times / thermal.schedule: {e}")))?;
                thermal_json = json!({
                    "mode": "transient",
                    "steps": summary.steps,
                    "heat_balance_max_rel_error": summary.max_balance_residual,
                });
            }
            None => {
                if !times.is_empty() {
                    return Err(err(
                        f,
                        "output.times: output times need a [thermal.schedule] (without one the case has a single state)",
                    ));
                }
                if th.bc.is_empty() {
                    // No transient and no boundary conditions: the initial field is held.
                    let t0 = system
                        .initial_temperature()
                        .ok_or_else(|| err(f, "thermal.initial: no initial temperature"))?
                        .to_vec();
                    states.push(Thermal {
                        time: 0.0,
                        element_temperature: system.element_means(&t0),
                        temperature: t0,
                        heat_balance: None,
                    });
                    thermal_json = json!({ "mode": "initial" });
                } else {
                    let s = system
                        .solve_steady()
                        .map_err(|e| err(f, format!("thermal (steady): {e}")))?;
                    let res = s.balance.relative_residual();
                    states.push(Thermal {
                        time: 0.0,
                        temperature: s.temperature,
                        element_temperature: s.element_temperature,
                        heat_balance: Some(res),
                    });
                    thermal_json = json!({ "mode": "steady", "heat_balance_max_rel_error": res });
                }
            }
        }
        t_ref = Some(reference);
    } else if !times.is_empty() {
        return Err(err(
            f,
            "output.times: output times need a [thermal] section with a schedule",
        ));
    }
    let mech = &case.mechanical;
    if let Some(r) = mech.reference_temperature {
        if t_ref.is_none() {
            return Err(err(
                f,
                "mechanical.reference_temperature: needs a [thermal] section",
            ));
        }
        if !r.is_finite() {
            return Err(err(
                f,
                format!("mechanical.reference_temperature = {r}: must be finite"),
            ));
        }
        t_ref = Some(vec![r; mesh.n_triangles()]);
    }

    // Elastic model.
    let analysis = match mech.analysis {
        AnalysisName::PlaneStrain => Analysis::PlaneStrain,
        AnalysisName::PlaneStress => Analysis::PlaneStress,
        AnalysisName::GeneralisedPlaneStrain => Analysis::GeneralisedPlaneStrain,
    };
    let mut model = ElasticModel::new(&mesh, analysis);
    for (r, m) in mats.iter().enumerate() {
        let expansion = match (m.expansion, case.thermal.is_some()) {
            (Some(a), _) => a,
            (None, false) => 0.0,
            (None, true) => {
                return Err(err(
                    f,
                    format!(
                        "material for region '{}': expansion is needed with [thermal]",
                        names[r]
                    ),
                ));
            }
        };
        model = model
            .material(
                &names[r],
                Material {
                    youngs_modulus: m.youngs_modulus,
                    poisson_ratio: m.poisson_ratio,
                    expansion,
                },
            )
            .map_err(|e| err(f, e))?;
    }
    for (k, x) in mech.fix.iter().enumerate() {
        let c = match x.component {
            ComponentName::X => Component::X,
            ComponentName::Y => Component::Y,
        };
        model = model
            .fix(&x.set, c, x.value)
            .map_err(|e| err(f, format!("mechanical.fix[{k}].set: {e}")))?;
    }
    for (k, s) in mech.symmetry.iter().enumerate() {
        model = model
            .symmetry(&s.edges)
            .map_err(|e| err(f, format!("mechanical.symmetry[{k}].edges: {e}")))?;
    }
    for (k, p) in mech.pressure.iter().enumerate() {
        model = model
            .pressure(&p.edges, p.value)
            .map_err(|e| err(f, format!("mechanical.pressure[{k}].edges: {e}")))?;
    }
    let mut joints_json = serde_json::Map::new();
    for (k, i) in case.interface.iter().enumerate() {
        let key = format!("interface[{k}].joint ('{}')", i.name);
        let j = i
            .joint
            .as_ref()
            .ok_or_else(|| err(f, format!("{key}: missing [interface.joint] (law = \"frictional\" | \"linear\" | \"sticking\")")))?;
        let (law, info) = joint(f, &key, j, interface_scale(&mesh, &i.name, &mats))?;
        joints_json.insert(i.name.clone(), info);
        let normals = match j.normals.as_deref() {
            None | Some("smoothed") => InterfaceNormals::Smoothed,
            Some("element") => InterfaceNormals::Element,
            Some(other) => {
                return Err(err(
                    f,
                    format!("{key}.normals = \"{other}\": expected \"smoothed\" or \"element\""),
                ));
            }
        };
        model = model
            .interface_normals(normals)
            .interface(&i.name, law)
            .map_err(|e| err(f, format!("{key}: {e}")))?;
    }
    model = model.remove_free_translations(mech.remove_free_translations);
    let al = match mech.augmented_lagrangian {
        None => Some(1e-4),
        Some(v) => {
            if v == 0.0 {
                None
            } else {
                Some(positive(f, "mechanical.augmented_lagrangian", v)?)
            }
        }
    };
    let opts = SolverOptions {
        augmented_lagrangian: al,
        max_iterations: 150,
        ..Default::default()
    };
    let mut solver =
        StaticSolver::new(&model, opts).map_err(|e| err(f, format!("mechanical: {e}")))?;
    let iface_names: Vec<String> = model.interfaces().iter().map(|i| i.name.clone()).collect();

    let mut results = Vec::new();
    let targets: Vec<Option<Thermal>> = if states.is_empty() {
        vec![None]
    } else {
        states.into_iter().map(Some).collect()
    };
    for th in targets {
        let loads = match (&th, &t_ref) {
            (Some(s), Some(r)) => Loads {
                delta_t: s
                    .element_temperature
                    .iter()
                    .zip(r)
                    .map(|(t, r)| t - r)
                    .collect(),
                ..Loads::mechanical()
            },
            _ => Loads::mechanical(),
        };
        let time = th.as_ref().map_or(0.0, |s| s.time);
        let reports = solver
            .advance(&loads)
            .map_err(|e| err(f, format!("mechanical solve at t = {time} s: {e}")))?;
        results.push(StateResult {
            time,
            heat_balance: th.as_ref().and_then(|s| s.heat_balance),
            temperature: th.map(|s| s.temperature),
            displacement: solver.displacement().to_vec(),
            eps_zz: solver.eps_zz(),
            stress: solver.stresses(),
            interface: solver.interface_results(),
            max_iterations: reports
                .iter()
                .map(|r| r.max_pass_iterations)
                .max()
                .unwrap_or(0),
        });
    }
    let notes = solver.notes().to_vec();
    drop(solver);
    drop(model);

    let mut summary = json!({
        "case": display(f),
        "mesh": {
            "nodes": mesh.n_nodes(),
            "triangles": mesh.n_triangles(),
            "interface_elements": mesh.interfaces().values().map(|i| i.elements.len()).sum::<usize>(),
            "regions": names,
        },
        "analysis": format!("{:?}", analysis),
        "thermal": thermal_json,
        "joints": joints_json,
        "augmented_lagrangian": al,
        "times": results.iter().map(|r| state_summary(&mesh, &iface_names, r)).collect::<Vec<_>>(),
        "notes": notes,
    });
    summary["newton_max_iterations_per_increment"] =
        json!(results.iter().map(|r| r.max_iterations).max().unwrap_or(0));
    summary["seconds"] = json!(start.elapsed().as_secs_f64());
    Ok(CaseResult {
        mesh,
        interfaces: iface_names,
        states: results,
        probes,
        summary,
    })
}

fn nearest(mesh: &Mesh, p: [f64; 2]) -> usize {
    let d = |q: [f64; 2]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
    (0..mesh.n_nodes())
        .min_by(|&a, &b| d(mesh.nodes()[a]).total_cmp(&d(mesh.nodes()[b])))
        .unwrap_or(0)
}

/// Arc-length weighted mean contact pressure (open points count as 0) and
/// point counts of one interface.
pub fn interface_summary(points: &[InterfacePointResult], index: usize) -> Value {
    let pts: Vec<&InterfacePointResult> = points.iter().filter(|p| p.interface == index).collect();
    let mut by_el: BTreeMap<usize, Vec<&InterfacePointResult>> = BTreeMap::new();
    for p in &pts {
        by_el.entry(p.element).or_default().push(p);
    }
    let (mut s, mut w) = (0.0, 0.0);
    for el in by_el.values() {
        if el.len() < 2 {
            continue;
        }
        let (a, b) = (el[0].position, el[el.len() - 1].position);
        let len = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        let mean = -el.iter().map(|p| p.traction[1]).sum::<f64>() / el.len() as f64;
        s += len * mean;
        w += len;
    }
    let count = |st: ContactStatus| pts.iter().filter(|p| p.status == st).count();
    json!({
        "contact_pressure_mean": if w > 0.0 { s / w } else { 0.0 },
        "contact_pressure_max": pts.iter().map(|p| -p.traction[1]).fold(0.0, f64::max),
        "points": pts.len(),
        "open": count(ContactStatus::Open),
        "stick": count(ContactStatus::Stick),
        "slip": count(ContactStatus::Slip),
    })
}

fn state_summary(mesh: &Mesh, ifaces: &[String], r: &StateResult) -> Value {
    let n = mesh.n_nodes();
    let umax = (0..n)
        .map(|i| r.displacement[2 * i].hypot(r.displacement[2 * i + 1]))
        .fold(0.0, f64::max);
    let vm_max = r
        .stress
        .nodal
        .iter()
        .map(|s| von_mises(*s))
        .fold(0.0, f64::max);
    let mut interfaces = serde_json::Map::new();
    for (k, name) in ifaces.iter().enumerate() {
        interfaces.insert(name.clone(), interface_summary(&r.interface, k));
    }
    // Area-weighted region means of the element stresses (polar about the origin).
    let areas = mesh.areas();
    let x = mesh.nodes();
    let mut regions = serde_json::Map::new();
    for (ri, name) in mesh.region_names().iter().enumerate() {
        let mut acc = [0.0f64; 8];
        let mut area = 0.0;
        for (e, t) in mesh.triangles().iter().enumerate() {
            if mesh.element_regions()[e] != ri {
                continue;
            }
            let a = areas[e].abs();
            let c = [
                (x[t[0]][0] + x[t[1]][0] + x[t[2]][0]) / 3.0,
                (x[t[0]][1] + x[t[1]][1] + x[t[2]][1]) / 3.0,
            ];
            let s = r.stress.element[e];
            let p = polar(s, c, [0.0, 0.0]);
            let v = [s[0], s[1], s[2], s[3], p[0], p[1], p[2], von_mises(s)];
            for (q, vi) in acc.iter_mut().zip(v) {
                *q += a * vi;
            }
            area += a;
        }
        let m = |k: usize| if area > 0.0 { acc[k] / area } else { 0.0 };
        regions.insert(
            name.clone(),
            json!({
                "area": area,
                "stress_mean": {
                    "xx": m(0), "yy": m(1), "xy": m(2), "zz": m(3),
                    "rr": m(4), "tt": m(5), "rt": m(6), "von_mises": m(7),
                }
            }),
        );
    }
    let mut v = json!({
        "time": r.time,
        "max_displacement": umax,
        "max_von_mises": vm_max,
        "eps_zz": r.eps_zz,
        "interfaces": interfaces,
        "regions": regions,
        "newton_max_iterations": r.max_iterations,
    });
    if let Some(t) = &r.temperature {
        v["temperature_min"] = json!(t.iter().copied().fold(f64::INFINITY, f64::min));
        v["temperature_max"] = json!(t.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    }
    if let Some(h) = r.heat_balance {
        v["heat_balance_rel_error"] = json!(h);
    }
    v
}

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

fn csv_line(v: &[f64]) -> String {
    let s: Vec<String> = v.iter().map(|x| format!("{x:.9e}")).collect();
    s.join(",")
}

fn write(path: &Path, text: &str) -> CliResult<()> {
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()).into())
}

/// Writes the files of a finished case into `dir` (temporary folder).
fn write_files(case: &Case, res: &CaseResult, dir: &Path) -> CliResult<Vec<String>> {
    let mesh = &res.mesh;
    let n = mesh.n_nodes();
    let mut files = Vec::new();
    let status = |s: ContactStatus| match s {
        ContactStatus::Open => 0.0,
        ContactStatus::Stick => 1.0,
        ContactStatus::Slip => 2.0,
    };
    let mut pvd = Vec::new();
    for (k, r) in res.states.iter().enumerate() {
        let vm: Vec<f64> = r.stress.nodal.iter().map(|s| von_mises(*s)).collect();
        if case.output.csv_nodal {
            let mut s = String::from(
                "node,x_m,y_m,T_C,ux_m,uy_m,sxx_Pa,syy_Pa,sxy_Pa,szz_Pa,von_mises_Pa\n",
            );
            for i in 0..n {
                let t = r.temperature.as_ref().map_or(f64::NAN, |t| t[i]);
                let st = r.stress.nodal[i];
                s += &format!("{i},");
                s += &csv_line(&[
                    mesh.nodes()[i][0],
                    mesh.nodes()[i][1],
                    t,
                    r.displacement[2 * i],
                    r.displacement[2 * i + 1],
                    st[0],
                    st[1],
                    st[2],
                    st[3],
                    vm[i],
                ]);
                s.push('\n');
            }
            let name = format!("nodal_{k:03}.csv");
            write(&dir.join(&name), &s)?;
            files.push(name);
        }
        if !r.interface.is_empty() {
            let mut s = String::from(
                "interface,element,point,x_m,y_m,jump_t_m,jump_n_m,shear_Pa,contact_pressure_Pa,slip_m,status(0=open,1=stick,2=slip)\n",
            );
            for p in &r.interface {
                s += &format!("{},{},{},", res.interfaces[p.interface], p.element, p.point);
                s += &csv_line(&[
                    p.position[0],
                    p.position[1],
                    p.jump[0],
                    p.jump[1],
                    p.traction[0],
                    -p.traction[1],
                    p.slip,
                    status(p.status),
                ]);
                s.push('\n');
            }
            let name = format!("interface_{k:03}.csv");
            write(&dir.join(&name), &s)?;
            files.push(name);
        }
        if case.output.vtk.unwrap_or(true) {
            let name = format!("state_{k:03}.vtu");
            let disp: Vec<[f64; 2]> = (0..n)
                .map(|i| [r.displacement[2 * i], r.displacement[2 * i + 1]])
                .collect();
            let nodal: Vec<f64> = r
                .stress
                .nodal
                .iter()
                .flat_map(|v| v.iter().copied())
                .collect();
            let cell: Vec<f64> = r
                .stress
                .element
                .iter()
                .flat_map(|v| v.iter().copied())
                .collect();
            let region: Vec<f64> = mesh.element_regions().iter().map(|&r| r as f64).collect();
            let zero = vec![0.0; n];
            let temp = r.temperature.as_deref().unwrap_or(&zero);
            let mut point_data = vec![
                ("displacement_m", Field::Vectors(&disp)),
                (
                    "stress_xx_yy_xy_zz_Pa",
                    Field::Components {
                        n: 4,
                        values: &nodal,
                    },
                ),
                ("von_mises_Pa", Field::Scalars(&vm)),
            ];
            if r.temperature.is_some() {
                point_data.insert(0, ("temperature_C", Field::Scalars(temp)));
            }
            write_vtu(
                dir.join(&name),
                &VtuPiece {
                    points: mesh.nodes(),
                    triangles: mesh.triangles(),
                    quads: &[],
                    point_data: &point_data,
                    cell_data: &[
                        (
                            "stress_xx_yy_xy_zz_Pa",
                            Field::Components {
                                n: 4,
                                values: &cell,
                            },
                        ),
                        ("region", Field::Scalars(&region)),
                    ],
                },
            )?;
            pvd.push((r.time, name.clone()));
            files.push(name);
        }
    }
    if !pvd.is_empty() {
        write_pvd(dir.join("case.pvd"), &pvd)?;
        files.push("case.pvd".into());
    }
    if !res.probes.is_empty() {
        let mut s = String::from(
            "time_s,probe,x_m,y_m,node,node_x_m,node_y_m,T_C,ux_m,uy_m,sxx_Pa,syy_Pa,sxy_Pa,szz_Pa,von_mises_Pa\n",
        );
        for r in &res.states {
            for (k, (p, i)) in res.probes.iter().enumerate() {
                let st = r.stress.nodal[*i];
                let q = mesh.nodes()[*i];
                s += &format!("{:.9e},{k},", r.time);
                s += &csv_line(&[p[0], p[1]]);
                s += &format!(",{i},");
                s += &csv_line(&[
                    q[0],
                    q[1],
                    r.temperature.as_ref().map_or(f64::NAN, |t| t[*i]),
                    r.displacement[2 * i],
                    r.displacement[2 * i + 1],
                    st[0],
                    st[1],
                    st[2],
                    st[3],
                    von_mises(st),
                ]);
                s.push('\n');
            }
        }
        write(&dir.join("probes.csv"), &s)?;
        files.push("probes.csv".into());
        // Histories at the probes (a transient with two or more output times).
        if res.states.len() >= 2 {
            let mut plots = vec![(
                "probes_von_mises",
                "von Mises stress at the probes",
                "σ_vM [MPa]",
                None,
            )];
            if res.states.iter().all(|r| r.temperature.is_some()) {
                plots.push((
                    "probes_temperature",
                    "Temperature at the probes",
                    "T [°C]",
                    Some(()),
                ));
            }
            for (stem, title, y, temperature) in plots {
                let series = res
                    .probes
                    .iter()
                    .enumerate()
                    .map(|(k, (p, i))| Series {
                        label: format!("probe {k} ({}, {})", p[0], p[1]),
                        points: res
                            .states
                            .iter()
                            .map(|r| {
                                let v = match (temperature, &r.temperature) {
                                    (Some(()), Some(t)) => t[*i],
                                    _ => von_mises(r.stress.nodal[*i]) / 1e6,
                                };
                                (r.time.max(f64::MIN_POSITIVE).log10(), v)
                            })
                            .collect(),
                    })
                    .collect();
                LinePlot {
                    title: title.into(),
                    x_label: "log10(time [s])".into(),
                    y_label: y.into(),
                    series,
                }
                .write_svg_png(&dir.join(stem))?;
                files.push(format!("{stem}.svg"));
                files.push(format!("{stem}.png"));
            }
        }
    }
    write(
        &dir.join("summary.json"),
        &serde_json::to_string_pretty(&res.summary)?,
    )?;
    files.push("summary.json".into());
    Ok(files)
}

/// Writes all outputs into `out`: first into `out/.partial-<pid>`, then
/// moves each file into `out` (`summary.json` last) and removes the
/// temporary folder; on failure nothing is moved and the temporary folder
/// (and `out`, if this call created it and it is empty) is removed.
pub fn write_outputs(case: &Case, res: &CaseResult, out: &Path) -> CliResult<()> {
    let created = !out.exists();
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let tmp = out.join(format!(".partial-{}", std::process::id()));
    let cleanup = |tmp: &Path| {
        let _ = std::fs::remove_dir_all(tmp);
        if created {
            let _ = std::fs::remove_dir(out);
        }
    };
    if let Err(e) = std::fs::create_dir_all(&tmp) {
        cleanup(&tmp);
        return Err(format!("{}: {e}", tmp.display()).into());
    }
    let files = match write_files(case, res, &tmp) {
        Ok(f) => f,
        Err(e) => {
            cleanup(&tmp);
            return Err(e);
        }
    };
    // summary.json is the last file written, so it is the last one moved.
    for name in &files {
        if let Err(e) = std::fs::rename(tmp.join(name), out.join(name)) {
            cleanup(&tmp);
            return Err(format!("{}: {e}", out.join(name).display()).into());
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
    Ok(())
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
    /// Output folder (default `tecon-out/<case file stem>`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print nothing but errors.
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
    if let Some(notes) = v["notes"].as_array() {
        for n in notes {
            s += &format!("note: {}\n", n.as_str().unwrap_or_default());
        }
    }
    s
}

/// Runs `tecon run`.
pub fn run(args: RunArgs) -> CliResult<()> {
    let case = load(&args.case)?;
    let base = args
        .case
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let out = match &args.out {
        Some(o) => o.clone(),
        None => {
            let stem = args
                .case
                .file_stem()
                .map(|s| s.to_string_lossy().to_string())
                .unwrap_or_else(|| "case".into());
            Path::new("tecon-out").join(stem)
        }
    };
    // one line per error, whatever the solver's message holds
    let one_line =
        |e: Box<dyn std::error::Error + Send + Sync>| -> Box<dyn std::error::Error + Send + Sync> {
            e.to_string().replace('\n', "; ").into()
        };
    let res = execute(&case, &base).map_err(one_line)?;
    write_outputs(&case, &res, &out).map_err(one_line)?;
    if !args.quiet {
        print!("{}", report(&res));
        println!("results in {}", out.display());
    }
    Ok(())
}
