//! The published welded vessel as a built-in case: [`VesselOptions`] (the
//! `tecon vessel` command line) → a [`Case`] like any case file, run by the
//! one driver. Only the mesh density and the pressure stage are set through
//! fields a case file does not have.

use tecon_elastic::{Analysis, InterfaceNormals};
use tecon_mesh::{Mesh, VesselGeometry, VesselMeshSpec};
use tecon_thermal::TimeSchedule;

use crate::case::{
    AnalysisName, Case, CliResult, EdgesSection, InitialSection, InterfaceSection, JointSection,
    MaterialSection, MechanicalSection, MeshSection, OutputSection, PressureSection, RegionValue,
    ScheduleSection, Scheme, ThermalBcSection, ThermalSection,
};
use crate::conductance::CouplingSection;

/// Material and process data of the published case (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VesselData {
    /// Density ρ, kg/m³.
    pub density: f64,
    /// Specific heat c, J/(kg K).
    pub specific_heat: f64,
    /// Conductivity k, W/(m K).
    pub conductivity: f64,
    /// Thermal expansion α, 1/K.
    pub expansion: f64,
    /// Young's modulus E, Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
    /// Initial weld temperature, °C.
    pub weld_temperature: f64,
    /// Ambient and initial temperature of the rest, °C.
    pub ambient: f64,
    /// Film coefficient on the inner and outer surfaces, W/(m² K).
    pub film: f64,
    /// Interface conductance core/layer, W/(m² K).
    pub interface_conductance: f64,
}

impl Default for VesselData {
    fn default() -> Self {
        VesselData {
            density: 7832.0,
            specific_heat: 434.0,
            conductivity: 63.9,
            expansion: 12.51e-6,
            youngs_modulus: 207e9,
            poisson_ratio: 0.3,
            weld_temperature: 1132.0,
            ambient: 21.0,
            film: 10.25,
            interface_conductance: 850.0,
        }
    }
}

/// The core/layer joint of `tecon vessel --interface`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum InterfaceKind {
    /// The paper's joint: penalty contact with Mohr–Coulomb friction
    /// (`--friction`, `--cohesion`).
    #[default]
    Frictional,
    /// Penalty contact without friction (μ = 0, c = 0).
    Frictionless,
    /// Tied: core and layer share the displacements of their facing nodes
    /// (no penalty, never opens).
    Bonded,
}

impl InterfaceKind {
    /// Parses `frictional`, `frictionless` or `bonded`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "frictional" => Ok(InterfaceKind::Frictional),
            "frictionless" => Ok(InterfaceKind::Frictionless),
            "bonded" => Ok(InterfaceKind::Bonded),
            other => Err(format!(
                "--interface {other}: expected 'frictional', 'frictionless' or 'bonded'"
            )),
        }
    }

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            InterfaceKind::Frictional => "frictional",
            InterfaceKind::Frictionless => "frictionless",
            InterfaceKind::Bonded => "bonded",
        }
    }
}

/// Everything a vessel run needs.
#[derive(Debug, Clone, PartialEq)]
pub struct VesselOptions {
    /// Geometry.
    pub geometry: VesselGeometry,
    /// Mesh density.
    pub mesh: VesselMeshSpec,
    /// Material and process data.
    pub data: VesselData,
    /// The core/layer joint (frictional, frictionless or bonded).
    pub interface: InterfaceKind,
    /// Friction coefficient μ = tan φ of the core/layer joint (frictional).
    pub friction: f64,
    /// Cohesion c of the joint, Pa.
    pub cohesion: f64,
    /// Joint penalty factor β (k_n = β E / h, h the radial element size at the interface).
    pub penalty_factor: f64,
    /// Augmented-Lagrangian tolerance (None: pure penalty).
    pub augmented_lagrangian: Option<f64>,
    /// Newton passes condensed onto the interface dofs where cheaper
    /// (false: full passes always).
    pub condensation: bool,
    /// The coarse interface space before the first pass of an increment,
    /// with condensed passes (false: off).
    pub coarse_space: bool,
    /// Coarse levels before a frictionless first pass (1: the finest
    /// alone).
    pub coarse_levels: u32,
    /// The coupled tail of the outer loop under frozen friction limits
    /// (false: frozen passes to the end).
    pub coupled_tail: bool,
    /// Every Newton pass solved to the full tolerances, also those an
    /// outer update follows (false: inexact passes, see
    /// `tecon_elastic::SolverOptions::pass_forcing`).
    pub exact_passes: bool,
    /// Internal (operating) pressure applied after cooling, Pa.
    pub pressure: Option<f64>,
    /// Output times of the transient, s (the last is the end of cooling).
    pub times: Vec<f64>,
    /// Plane strain (default) or generalised plane strain.
    pub analysis: Analysis,
    /// Interface point normals: smoothed per node (default) or each
    /// element's chord (the classical element).
    pub normals: InterfaceNormals,
    /// Interface conductance: the paper's constant 850 W/(m² K) (false) or
    /// the contact law of [`vessel_contact_conductance`] (true).
    pub contact_conductance: bool,
    /// Staggered two-way coupling (None: one-way, the paper's).
    pub two_way: Option<crate::driver::TwoWay>,
    /// Capacity matrix of the heat conduction (consistent: the paper's).
    pub capacity: crate::case::Capacity,
    /// Quiet: no progress bar.
    pub quiet: bool,
    /// Print the Newton iteration history of every increment to stderr.
    pub verbose: bool,
}

impl Default for VesselOptions {
    fn default() -> Self {
        VesselOptions {
            geometry: VesselGeometry::default(),
            mesh: default_mesh(),
            data: VesselData::default(),
            interface: InterfaceKind::Frictional,
            friction: 0.3,
            cohesion: 0.0,
            penalty_factor: tecon_contact::DEFAULT_PENALTY_FACTOR,
            augmented_lagrangian: Some(1e-4),
            condensation: true,
            coarse_space: true,
            coarse_levels: tecon_elastic::COARSE_LEVELS,
            coupled_tail: true,
            exact_passes: false,
            pressure: None,
            times: vec![1.0, 10.0, 60.0, 600.0, 3600.0, 72000.0],
            analysis: Analysis::PlaneStrain,
            normals: InterfaceNormals::Smoothed,
            contact_conductance: false,
            two_way: None,
            capacity: crate::case::Capacity::Consistent,
            quiet: false,
            verbose: false,
        }
    }
}

/// The name of the default mesh on the command line (`--mesh`).
pub const DEFAULT_MESH: &str = "g0";

/// The default mesh: graded level 0 with 6-node triangles (2 784
/// triangles, order 2), the cheapest mesh that meets the accuracy targets
/// of the welded vessel (far-field hoop stress, weld plane, gap, temperatures;
/// docs/vessel.md §9).
pub fn default_mesh() -> VesselMeshSpec {
    // level 0 is a valid graded level
    VesselMeshSpec::graded(0).unwrap_or_else(|_| VesselMeshSpec::paper())
}

/// Cooling schedule: steps growing from 0.02 s near the start to 1000 s.
pub fn schedule(end: f64) -> CliResult<TimeSchedule> {
    Ok(TimeSchedule::segments(&schedule_segments(end))?)
}

/// The segments `(t_end, Δt)` of [`schedule`].
pub fn schedule_segments(end: f64) -> Vec<(f64, f64)> {
    let mut seg: Vec<(f64, f64)> = Vec::new();
    for (t, dt) in [
        (1.0, 0.02),
        (10.0, 0.2),
        (100.0, 2.0),
        (1000.0, 20.0),
        (10000.0, 200.0),
        (f64::INFINITY, 1000.0),
    ] {
        let t_end = t.min(end);
        if seg.last().is_none_or(|s| s.0 < t_end) {
            seg.push((t_end, dt));
        }
        if t >= end {
            break;
        }
    }
    seg
}

/// The vessel's contact-dependent conductance (`tecon vessel --conductance
/// contact`): a power law h₀ (p/p₀)^0.95 with h₀ = 3000 W/(m² K) at
/// p₀ = 1 MPa (the Mikic/Yovanovich exponent) plus a gas gap
/// k_g / (g + g₀) with k_g = 0.0425 W/(m K) (air near 300 °C) and
/// g₀ = 50 µm, so that the touching, unloaded joint has the paper's
/// 850 W/(m² K) and a 60 µm gap about 386 W/(m² K).
pub fn vessel_contact_conductance(d: &VesselData) -> toml::Value {
    let mut t = toml::Table::new();
    t.insert("law".into(), toml::Value::String("power".into()));
    t.insert("h0".into(), toml::Value::Float(3000.0));
    t.insert("p0".into(), toml::Value::Float(1e6));
    t.insert("exponent".into(), toml::Value::Float(0.95));
    t.insert("gas_conductivity".into(), toml::Value::Float(0.0425));
    t.insert(
        "jump_distance".into(),
        toml::Value::Float(0.0425 / d.interface_conductance),
    );
    toml::Value::Table(t)
}

/// The published case as a [`Case`] on `mesh` (the vessel mesh of
/// `o.geometry` and `o.mesh`): materials of core, layer and weld; film
/// coefficients inside and outside; the interface conductance and the
/// paper's joint with k_n = β E / h (h the radial element size of the
/// layer); symmetry on both cut edges; the cooling schedule of
/// [`schedule`] with Crank–Nicolson; the pressure (if any) after cooling.
pub fn vessel_case(o: &VesselOptions, mesh: &Mesh) -> CliResult<Case> {
    let d = &o.data;
    let mut times = o.times.clone();
    if times.is_empty() || times.iter().any(|t| !(t.is_finite() && *t > 0.0)) {
        return Err("--times: give positive output times in seconds".into());
    }
    times.sort_by(f64::total_cmp);
    times.dedup();
    let end = *times.last().unwrap_or(&72000.0);
    let segments: Vec<[f64; 2]> = schedule_segments(end)
        .iter()
        .map(|&(t, dt)| [t, dt])
        .collect();
    let material = mesh
        .region_names()
        .iter()
        .map(|r| MaterialSection {
            region: r.clone(),
            conductivity: Some(d.conductivity),
            density: Some(d.density),
            specific_heat: Some(d.specific_heat),
            youngs_modulus: d.youngs_modulus,
            poisson_ratio: d.poisson_ratio,
            expansion: Some(d.expansion),
            yield_stress: None,
        })
        .collect();
    let h = o.geometry.layer_thickness / o.mesh.layer_rows as f64;
    let interface = mesh
        .interfaces()
        .keys()
        .map(|name| InterfaceSection {
            name: name.clone(),
            bottom: None,
            top: None,
            pairing_tolerance: None,
            conductance: Some(if o.contact_conductance {
                vessel_contact_conductance(d)
            } else {
                toml::Value::Float(d.interface_conductance)
            }),
            joint: Some(match o.interface {
                InterfaceKind::Bonded => JointSection {
                    law: crate::setup::BONDED.into(),
                    k_n: None,
                    k_s: None,
                    penalty_factor: None,
                    friction: None,
                    cohesion: None,
                    normals: None,
                },
                kind => JointSection {
                    law: "frictional".into(),
                    k_n: Some(o.penalty_factor * d.youngs_modulus / h),
                    k_s: None,
                    penalty_factor: None,
                    friction: Some(if kind == InterfaceKind::Frictionless {
                        0.0
                    } else {
                        o.friction
                    }),
                    cohesion: Some(if kind == InterfaceKind::Frictionless {
                        0.0
                    } else {
                        o.cohesion
                    }),
                    normals: Some(
                        match o.normals {
                            InterfaceNormals::Smoothed => "smoothed",
                            InterfaceNormals::Element => "element",
                        }
                        .into(),
                    ),
                },
            }),
        })
        .collect();
    let convection = |edges: &str| ThermalBcSection {
        edges: edges.into(),
        kind: "convection".into(),
        h: Some(d.film),
        ambient: Some(d.ambient),
        value: None,
        q: None,
    };
    Ok(Case {
        mesh: MeshSection {
            generator: Some("vessel".into()),
            fused_weld: Some(o.mesh.fused_weld),
            inner_radius: Some(o.geometry.inner_radius),
            core_thickness: Some(o.geometry.core_thickness),
            layer_thickness: Some(o.geometry.layer_thickness),
            weld_half_width: Some(o.geometry.weld_half_width),
            vessel_spec: Some(o.mesh),
            ..Default::default()
        },
        material,
        interface,
        thermal: Some(ThermalSection {
            bc: vec![convection("inner"), convection("outer")],
            initial: Some(InitialSection {
                default: Some(d.ambient),
                region: vec![RegionValue {
                    region: "weld".into(),
                    value: d.weld_temperature,
                }],
            }),
            schedule: Some(ScheduleSection {
                segments,
                scheme: Scheme::CrankNicolson,
            }),
            capacity: o.capacity,
        }),
        mechanical: MechanicalSection {
            analysis: match o.analysis {
                Analysis::PlaneStress => AnalysisName::PlaneStress,
                Analysis::GeneralisedPlaneStrain => AnalysisName::GeneralisedPlaneStrain,
                Analysis::PlaneStrain => AnalysisName::PlaneStrain,
            },
            fix: Vec::new(),
            symmetry: vec![
                EdgesSection {
                    edges: "sym0".into(),
                },
                EdgesSection {
                    edges: "sym180".into(),
                },
            ],
            pressure: o
                .pressure
                .map(|p| PressureSection {
                    edges: "inner".into(),
                    value: p,
                })
                .into_iter()
                .collect(),
            remove_free_translations: true,
            hold_rigid_modes: None,
            augmented_lagrangian: Some(o.augmented_lagrangian.unwrap_or(0.0)),
            reference_temperature: None,
            condensation: Some(o.condensation),
            coarse_space: Some(o.coarse_space),
            coarse_levels: Some(o.coarse_levels),
            coupled_tail: Some(o.coupled_tail),
            exact_passes: Some(o.exact_passes),
        },
        output: OutputSection {
            times,
            ..Default::default()
        },
        coupling: o.two_way.map(|c| CouplingSection {
            mode: Some("two-way".into()),
            sync_interval: Some(c.sync_interval),
            tolerance: Some(c.tolerance),
            max_iterations: Some(c.max_iterations),
            sync_tolerance: c.sync_tolerance,
        }),
        source: "tecon vessel".into(),
        staged_pressure: true,
        progress: !o.quiet,
        verbose: o.verbose,
    })
}
