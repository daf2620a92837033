//! `[multilayer]` and `[[stage]]` in case files: a multilayer vessel built
//! layer after layer, through the same pipeline as `tecon vessel --layers`
//! ([`crate::multilayer::analyse`], its writers and report).
//!
//! ```toml
//! [multilayer]
//! inner_radius = 0.762            # m
//! core_thickness = 0.0127         # m
//! friction = 0.3                  # μ of every joint (default 0.3)
//! refine = 0                      # mesh level 0..=4 (default 0), each halving
//!                                 #   every interval of the one before
//! order = 1                       # 1: 3-node (default), 2: 6-node triangles
//! [[multilayer.layer]]            # from the core outwards
//! thickness = 0.0064              # m, or r_in = …, r_out = … (r_in must be
//! seam = 0.0                      #   the outer radius of the ring below)
//! weld_half_width = 0.0038        # m; seam: degrees in [0, 360)
//!
//! [[stage]]                       # one per layer, in order, then optionally
//! activate = ["layer1", "weld1"]  #   a last pressure stage
//! interfaces = ["core_layer1"]
//! temperatures = [{ region = "weld1", value = 1132.0 }]
//! times = [60.0, 72000.0]         # output times of the weld's cooling, s
//!
//! [[stage]]
//! pressure = 1.0e6                # internal pressure on the bore, Pa
//! ```
//!
//! A layer stage activates exactly the next layer (its regions `layer{k}`
//! and `weld{k}`) and the interface below it; the material and process data
//! are the published vessel's. Every error names the case file and the
//! stage, region, interface or layer at fault.

use std::f64::consts::PI;
use std::path::Path;

use serde::Deserialize;
use tecon_mesh::{MultilayerGeometry, WeldedLayer};

use crate::case::{RegionValue, err, from_toml};
use crate::multilayer::{self, MultilayerOptions, interface_name};
use crate::writers::CliResult;

/// A staged multilayer case file: `[multilayer]` and `[[stage]]`, nothing
/// else (the other tables of the case-file grammar are refused by name).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StagedCase {
    /// `[multilayer]`.
    pub multilayer: Option<MultilayerSection>,
    /// `[[stage]]`.
    #[serde(default)]
    pub stage: Vec<StageSection>,
    /// The case file (errors).
    #[serde(skip)]
    pub source: std::path::PathBuf,
    /// Progress output on stderr.
    #[serde(skip)]
    pub progress: bool,
}

/// Whether the TOML `text` is a staged multilayer case (it has a
/// `[multilayer]` or a `[[stage]]` table).
pub fn is_staged(text: &str) -> bool {
    text.parse::<toml::Table>()
        .is_ok_and(|t| t.contains_key("multilayer") || t.contains_key("stage"))
}

/// Parses a staged case; `file` names it in errors. A table of the general
/// grammar ([mesh], [thermal], …) is refused by name.
pub fn parse(text: &str, file: &Path) -> CliResult<StagedCase> {
    if let Ok(t) = text.parse::<toml::Table>()
        && let Some(k) = t
            .keys()
            .find(|k| k.as_str() != "multilayer" && k.as_str() != "stage")
    {
        return Err(err(
            file,
            format!(
                "[{k}] is not available with [multilayer]/[[stage]] yet: the mesh, data and supports of a staged case are the built-in multilayer vessel's, times and loads go in each [[stage]]"
            ),
        ));
    }
    let mut c: StagedCase = from_toml(text, file)?;
    c.source = file.to_path_buf();
    Ok(c)
}

/// `[multilayer]`: the core and the layers.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MultilayerSection {
    /// Inner radius of the core, m.
    pub inner_radius: f64,
    /// Core wall thickness, m.
    pub core_thickness: f64,
    /// Friction coefficient μ of every joint (default 0.3).
    pub friction: Option<f64>,
    /// Mesh refinement level 0..=4 (default 0, two rows of triangles
    /// through every ring), as `tecon vessel --layers N --mesh L`.
    pub refine: Option<u32>,
    /// Element order: 1 (3-node triangles, default) or 2 (6-node).
    pub order: Option<usize>,
    /// `[[multilayer.layer]]`, from the core outwards.
    #[serde(default)]
    pub layer: Vec<WrapSection>,
}

/// `[[multilayer.layer]]`: one wrapped layer.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WrapSection {
    /// Thickness, m (or `r_in` and `r_out`).
    pub thickness: Option<f64>,
    /// Inner radius, m: must be the outer radius of the ring below.
    pub r_in: Option<f64>,
    /// Outer radius, m.
    pub r_out: Option<f64>,
    /// Seam angle, degrees in [0, 360).
    pub seam: f64,
    /// Half width of the weld along the layer's mid radius, m.
    pub weld_half_width: f64,
}

/// `[[stage]]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StageSection {
    /// Optional name (reports).
    pub name: Option<String>,
    /// Regions the stage adds.
    #[serde(default)]
    pub activate: Vec<String>,
    /// Interfaces the stage adds.
    #[serde(default)]
    pub interfaces: Vec<String>,
    /// Initial temperatures of the added regions, °C (the weld's; the
    /// rest of a new layer starts at ambient).
    #[serde(default)]
    pub temperatures: Vec<RegionValue>,
    /// Output times of the stage's cooling, s (default 1, 10, 60, 600,
    /// 3600, 72000).
    pub times: Option<Vec<f64>>,
    /// Internal pressure on the bore, Pa (a last stage after the last layer).
    pub pressure: Option<f64>,
}

/// The stage as the errors name it.
fn stage_id(i: usize, s: &StageSection) -> String {
    match &s.name {
        Some(n) => format!("[[stage]] {} ('{n}')", i + 1),
        None => format!("[[stage]] {}", i + 1),
    }
}

/// The geometry of `[multilayer]`; errors name the layer.
fn geometry(m: &MultilayerSection) -> Result<MultilayerGeometry, String> {
    let mut outer = m.inner_radius + m.core_thickness;
    let mut layers = Vec::new();
    if m.layer.is_empty() {
        return Err("[multilayer]: no [[multilayer.layer]]".into());
    }
    for (k, l) in m.layer.iter().enumerate() {
        let id = format!("[[multilayer.layer]] {} (layer{})", k + 1, k + 1);
        let thickness = match (l.thickness, l.r_in, l.r_out) {
            (Some(t), None, None) => t,
            (None, Some(a), Some(b)) => {
                let tol = 1e-9 * b.abs().max(1.0);
                if a < outer - tol {
                    return Err(format!(
                        "{id}: r_in = {a} m overlaps the ring below (its outer radius is {outer} m)"
                    ));
                }
                if a > outer + tol {
                    return Err(format!(
                        "{id}: r_in = {a} m leaves a gap above the ring below (outer radius {outer} m): a layer is wrapped tight"
                    ));
                }
                b - outer
            }
            _ => {
                return Err(format!(
                    "{id}: give either thickness or both r_in and r_out"
                ));
            }
        };
        if !(thickness.is_finite() && thickness > 0.0) {
            return Err(format!(
                "{id}: zero or negative thickness ({thickness} m): the layer would overlap the ring below"
            ));
        }
        if !(l.seam.is_finite() && (0.0..360.0).contains(&l.seam)) {
            return Err(format!("{id}: seam = {}° is not in [0, 360)", l.seam));
        }
        outer += thickness;
        layers.push(WeldedLayer {
            thickness,
            weld_half_width: l.weld_half_width,
            seam_angle: l.seam * PI / 180.0,
        });
    }
    let g = MultilayerGeometry {
        inner_radius: m.inner_radius,
        core_thickness: m.core_thickness,
        layers,
    };
    g.check().map_err(|e| format!("[multilayer]: {e}"))?;
    Ok(g)
}

/// The options of a staged multilayer case, checked.
pub fn options(case: &StagedCase) -> CliResult<MultilayerOptions> {
    let f = &case.source;
    let Some(m) = &case.multilayer else {
        return Err(err(
            f,
            "[[stage]] needs a [multilayer] table (the core and the layers)",
        ));
    };
    if case.stage.is_empty() {
        return Err(err(f, "[multilayer]: give one [[stage]] per layer"));
    }
    let geometry = geometry(m).map_err(|e| err(f, e))?;
    let n = geometry.layers.len();
    let mut regions = vec!["core".to_string()];
    let mut interfaces = Vec::new();
    for k in 1..=n {
        regions.push(format!("layer{k}"));
        regions.push(format!("weld{k}"));
        interfaces.push(interface_name(k));
    }
    let mut o = MultilayerOptions::new(n, geometry.layers[0].thickness, None)?;
    o.geometry = geometry;
    o.quiet = !case.progress;
    if m.refine.is_some() || m.order.is_some() {
        let (level, order) = (m.refine.unwrap_or(0), m.order.unwrap_or(1));
        o.set_mesh(level, order).map_err(|e| {
            err(
                f,
                format!("[multilayer]: refine = {level}, order = {order}: {e}"),
            )
        })?;
    }
    if let Some(mu) = m.friction {
        if !(mu.is_finite() && mu >= 0.0) {
            return Err(err(
                f,
                format!("[multilayer]: friction = {mu}: must be non-negative"),
            ));
        }
        o.friction = mu;
    }
    let mut stage_times = Vec::new();
    let mut weld_temperatures = Vec::new();
    let mut active: Vec<&str> = vec!["core"];
    for (i, s) in case.stage.iter().enumerate() {
        let id = stage_id(i, s);
        for r in &s.activate {
            if !regions.contains(r) {
                return Err(err(
                    f,
                    format!(
                        "{id}: unknown region '{r}' (the regions are {})",
                        regions.join(", ")
                    ),
                ));
            }
            if active.contains(&r.as_str()) {
                return Err(err(f, format!("{id}: region '{r}' is already active")));
            }
        }
        for name in &s.interfaces {
            if !interfaces.contains(name) {
                return Err(err(
                    f,
                    format!(
                        "{id}: unknown interface '{name}' (the interfaces are {})",
                        interfaces.join(", ")
                    ),
                ));
            }
        }
        if let Some(p) = s.pressure {
            // the pressure stage: after the last layer, nothing added
            if !(p.is_finite() && p > 0.0) {
                return Err(err(
                    f,
                    format!("{id}: pressure = {p}: must be positive (Pa)"),
                ));
            }
            if stage_times.len() < n || i + 1 != case.stage.len() {
                return Err(err(
                    f,
                    format!(
                        "{id}: a pressure stage comes last, after every layer is wrapped (other loads per stage are not available yet)"
                    ),
                ));
            }
            if !s.activate.is_empty()
                || !s.interfaces.is_empty()
                || !s.temperatures.is_empty()
                || s.times.is_some()
            {
                return Err(err(
                    f,
                    format!(
                        "{id}: a pressure stage adds no region, interface, temperature or times (the temperatures are held)"
                    ),
                ));
            }
            o.pressure = Some(p);
            continue;
        }
        let k = stage_times.len() + 1;
        if k > n {
            return Err(err(
                f,
                format!("{id}: every layer is wrapped already ({n} layers)"),
            ));
        }
        let (layer, weld, below) = (format!("layer{k}"), format!("weld{k}"), interface_name(k));
        let mut want = vec![layer.as_str(), weld.as_str()];
        let mut got: Vec<&str> = s.activate.iter().map(String::as_str).collect();
        want.sort_unstable();
        got.sort_unstable();
        if got != want {
            return Err(err(
                f,
                format!(
                    "{id}: activates [{}]; layers are wrapped from the core outwards, one per stage: this stage activates [\"{layer}\", \"{weld}\"]",
                    s.activate.join(", ")
                ),
            ));
        }
        if s.interfaces != [below.clone()] {
            return Err(err(
                f,
                format!(
                    "{id}: interfaces [{}]; the stage wrapping {layer} adds the interface below it: [\"{below}\"]",
                    s.interfaces.join(", ")
                ),
            ));
        }
        let mut weld_t = o.data.weld_temperature;
        for t in &s.temperatures {
            if t.region != weld && t.region != layer {
                return Err(err(
                    f,
                    format!(
                        "{id}: temperature of region '{}': only the stage's own regions ({layer}, {weld}) start at a temperature of their own",
                        t.region
                    ),
                ));
            }
            if !t.value.is_finite() {
                return Err(err(
                    f,
                    format!("{id}: temperature of '{}' is not finite", t.region),
                ));
            }
            if t.region == layer && t.value != o.data.ambient {
                return Err(err(
                    f,
                    format!(
                        "{id}: a layer starts at ambient ({} °C); only its weld starts hot",
                        o.data.ambient
                    ),
                ));
            }
            if t.region == weld {
                weld_t = t.value;
            }
        }
        if let Some(t) = &s.times {
            crate::cmdline::check_increasing(&format!("{id}: times"), t).map_err(|e| err(f, e))?;
        }
        let times = s.times.clone().unwrap_or_else(|| o.times.clone());
        active.push(regions[2 * k - 1].as_str());
        active.push(regions[2 * k].as_str());
        stage_times.push(times);
        weld_temperatures.push(weld_t);
    }
    if stage_times.len() < n {
        return Err(err(
            f,
            format!(
                "{} layer stages for {n} layers: every layer needs its [[stage]]",
                stage_times.len()
            ),
        ));
    }
    o.stage_times = Some(stage_times);
    o.weld_temperatures = Some(weld_temperatures);
    for k in 1..=n {
        o.stage_output_times(k)
            .map_err(|e| err(f, format!("[[stage]] {e}")))?;
    }
    Ok(o)
}

/// Runs a staged multilayer case: options, the staged analysis, the files
/// of `tecon vessel --layers` in `out`, the report (returned).
pub fn run(case: &StagedCase, out: &Path) -> CliResult<String> {
    let o = options(case)?;
    let f = &case.source;
    let run = multilayer::analyse(&o).map_err(|e| err(f, e))?;
    crate::multilayer_out::write_outputs(&run, out)?;
    Ok(crate::multilayer_out::report(&run))
}
