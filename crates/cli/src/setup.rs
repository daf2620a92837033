//! From a case file to the driver's [`Setup`]: the mesh (file or
//! generator), the declared interfaces, materials, the thermal model and its
//! procedure, the elastic model with joints, supports and loads. Every
//! error names the case file and the key at fault; nothing is solved here.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use serde_json::{Value, json};
use tecon_contact::{ElasticJoint, GhaboussiNormal, LinearJoint, PaperJoint};
use tecon_elastic::{
    Analysis, Component, ElasticModel, InterfaceNormals, Joint, Material, SolverOptions, TiedMesh,
};
use tecon_mesh::{
    Mesh, RingLayer, VesselGeometry, layered_annulus_of_order, read_msh, rectangle_of_order,
    vessel_mesh,
};
use tecon_thermal::{EdgeBc, InterfaceQuadrature, ThermalModel, ThetaScheme, TimeSchedule};

use crate::conductance::Conductance;

use crate::case::{
    AnalysisName, Case, CliResult, ComponentName, JointSection, MaterialSection, Scheme, err,
};
use crate::driver::{
    Coupling, LoadFactors, Procedure, Setup, Stage, StageTemperature, ThermalSetup,
};

/// Most coarse levels a case may ask for (each is four times as wide as
/// the one before; beyond a few the coarsest has too few dofs to be made).
const MAX_COARSE_LEVELS: u32 = 6;

pub(crate) fn positive(file: &Path, key: &str, v: f64) -> CliResult<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(err(file, format!("{key} = {v}: must be positive")))
    }
}

/// The mesh of `[mesh]` (a Gmsh file or a generator) at the element order
/// the case asks for; interfaces are declared afterwards
/// ([`declare_interfaces`]).
pub fn build_mesh(case: &Case, base: &Path) -> CliResult<Mesh> {
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
    if let Some(o) = m.order
        && o != 1
        && o != 2
    {
        return Err(err(
            f,
            format!("mesh.order = {o}: expected 1 (3-node triangles) or 2 (6-node triangles)"),
        ));
    }
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
            let mesh = read_msh(&path).map_err(|e| err(f, format!("mesh.file: {e}")))?;
            match (m.order, mesh.order()) {
                (Some(1), 2) => Err(err(
                    f,
                    format!(
                        "mesh.order = 1: {} holds 6-node triangles (Gmsh type 9), which are order 2; drop the key or give order = 2",
                        path.display()
                    ),
                )),
                (Some(2), 1) => mesh.to_quadratic(&[]).map_err(mesh_err),
                _ => Ok(mesh),
            }
        }
        (None, Some("vessel")) => {
            only(&annulus_keys, "annulus")?;
            only(&rect_keys, "rectangle")?;
            let spec = match &m.preset {
                _ if m.vessel_spec.is_some() => {
                    m.vessel_spec.unwrap_or_else(crate::vessel::default_mesh)
                }
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
                order: m.order.unwrap_or(spec.order),
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
            layered_annulus_of_order(&layers, t0, t1, segments, m.order.unwrap_or(1))
                .map_err(mesh_err)
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
            rectangle_of_order(o[0], o[1], s[0], s[1], d[0], d[1], m.order.unwrap_or(1))
                .map_err(mesh_err)
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
                    "{key}.law = \"{other}\": expected \"linear\", \"frictional\", \"sticking\" or \"bonded\""
                ),
            ));
        }
    };
    Ok((
        joint,
        json!({ "law": j.law, "k_n": k_n, "k_s": k_s, "friction": j.friction, "cohesion": j.cohesion }),
    ))
}

/// Declares the case's interfaces on the mesh (from two edge sets, or
/// checks a generated one) and checks that every mesh interface has one.
pub(crate) fn declare_interfaces(case: &Case, mesh: &mut Mesh) -> CliResult<()> {
    let f = &case.source;
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
                let tol = match i.pairing_tolerance {
                    None => tecon_mesh::PairingTolerance::default(),
                    Some(x) if x.is_finite() && x > 0.0 && x < 0.5 => {
                        tecon_mesh::PairingTolerance::Relative(x)
                    }
                    Some(x) => {
                        return Err(err(
                            f,
                            format!(
                                "{key}.pairing_tolerance = {x}: give a fraction of the local element size in (0, 0.5); facing nodes must coincide, the tolerance only absorbs round-off"
                            ),
                        ));
                    }
                };
                mesh.add_interface_with(&i.name, b, t, tol)
                    .map_err(|e| err(f, format!("{key}: {e}")))?;
            }
            (None, None) if i.pairing_tolerance.is_some() => {
                return Err(err(
                    f,
                    format!(
                        "{key}.pairing_tolerance: the mesh generator pairs its own interfaces exactly; give it only with bottom and top edge sets"
                    ),
                ));
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
        if let Some(h) = &i.conductance {
            crate::conductance::parse(f, &key, h)?;
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
    Ok(())
}

/// The joint law name of a bonded (tied) interface.
pub const BONDED: &str = "bonded";

fn is_bonded(i: &crate::case::InterfaceSection) -> bool {
    i.joint.as_ref().is_some_and(|j| j.law == BONDED)
}

/// The mesh of the elastic model when the case ties interfaces (joint
/// `law = "bonded"`): their facing nodes merged ([`TiedMesh`]); `None`
/// when nothing is bonded. A bonded joint takes no parameter (it has no
/// penalty), and its conductance must be a constant (it never opens).
pub fn tie(case: &Case, mesh: &Mesh) -> CliResult<Option<TiedMesh>> {
    let f = &case.source;
    let mut names = Vec::new();
    for (k, i) in case.interface.iter().enumerate() {
        if !is_bonded(i) {
            continue;
        }
        let key = format!("interface[{k}].joint ('{}')", i.name);
        if let Some(j) = &i.joint {
            for (name, given) in [
                ("k_n", j.k_n.is_some()),
                ("k_s", j.k_s.is_some()),
                ("penalty_factor", j.penalty_factor.is_some()),
                ("friction", j.friction.is_some()),
                ("cohesion", j.cohesion.is_some()),
                ("normals", j.normals.is_some()),
            ] {
                if given {
                    return Err(err(
                        f,
                        format!(
                            "{key}.{name}: not a parameter of law = \"bonded\" (a tied interface shares the displacements of its facing nodes; it has no penalty)"
                        ),
                    ));
                }
            }
        }
        if let Some(h) = &i.conductance
            && let crate::conductance::Conductance::Law(_) =
                crate::conductance::parse(f, &format!("interface[{k}] ('{}')", i.name), h)?
        {
            return Err(err(
                f,
                format!(
                    "interface[{k}] ('{}').conductance: a bonded interface never opens; give a constant conductance",
                    i.name
                ),
            ));
        }
        names.push(i.name.as_str());
    }
    if names.is_empty() {
        return Ok(None);
    }
    TiedMesh::new(mesh, &names)
        .map(Some)
        .map_err(|e| err(f, format!("interface (bonded): {e}")))
}

/// A case ready for the driver, with what the summary reports of it.
pub struct Prepared<'m> {
    /// The driver's input.
    pub setup: Setup<'m>,
    /// Joint parameters per interface (summary `joints`).
    pub joints: serde_json::Map<String, Value>,
    /// Augmented-Lagrangian tolerance (None: pure penalty).
    pub augmented_lagrangian: Option<f64>,
    /// Plane analysis type.
    pub analysis: Analysis,
    /// Probe points and their nearest nodes.
    pub probes: Vec<([f64; 2], usize)>,
}

/// Node nearest to `p`.
pub(crate) fn nearest(mesh: &Mesh, p: [f64; 2]) -> usize {
    let d = |q: [f64; 2]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
    (0..mesh.n_nodes())
        .min_by(|&a, &b| d(mesh.nodes()[a]).total_cmp(&d(mesh.nodes()[b])))
        .unwrap_or(0)
}

/// Builds the thermal model of `[thermal]` and its procedure.
fn thermal_setup<'m>(
    case: &Case,
    mesh: &'m Mesh,
    mats: &[&MaterialSection],
    times: &[f64],
) -> CliResult<Option<ThermalSetup<'m>>> {
    let f = &case.source;
    let names = mesh.region_names();
    let Some(th) = &case.thermal else {
        if !times.is_empty() {
            return Err(err(
                f,
                "output.times: output times need a [thermal] section with a schedule",
            ));
        }
        return Ok(None);
    };
    let mut model = ThermalModel::new(mesh);
    model.set_capacity(th.capacity.kind());
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
    for (k, i) in case.interface.iter().enumerate() {
        let key = format!("interface[{k}] ('{}')", i.name);
        match &i.conductance {
            Some(h) => match crate::conductance::parse(f, &key, h)? {
                Conductance::Constant(h) => model.set_interface_conductance(&i.name, h),
                Conductance::Law(law) => {
                    model.set_interface_law(&i.name, law, InterfaceQuadrature::Nodal)
                }
            },
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
    let procedure = match &th.schedule {
        Some(s) => {
            if times.is_empty() {
                return Err(err(f, "output.times: a transient needs output times"));
            }
            let segs: Vec<(f64, f64)> = s.segments.iter().map(|s| (s[0], s[1])).collect();
            let schedule = TimeSchedule::segments(&segs)
                .map_err(|e| err(f, format!("thermal.schedule.segments: {e}")))?;
            let scheme = match s.scheme {
                // On 6-node meshes a backward-Euler step follows every
                // growth of Δt: their stiffest modes (graded to 0.1 mm at
                // the weld edge) would otherwise ring under Crank–Nicolson
                // below the ambient to the end of the run. Linear meshes
                // keep the plain scheme (and their published numbers).
                Scheme::CrankNicolson if mesh.order() == 2 => {
                    ThetaScheme::crank_nicolson().with_restarts(1)
                }
                Scheme::CrankNicolson => ThetaScheme::crank_nicolson(),
                Scheme::BackwardEuler => ThetaScheme::backward_euler(),
            };
            Procedure::Transient {
                schedule,
                scheme,
                times: times.to_vec(),
            }
        }
        None => {
            if !times.is_empty() {
                return Err(err(
                    f,
                    "output.times: output times need a [thermal.schedule] (without one the case has a single state)",
                ));
            }
            if th.bc.is_empty() {
                Procedure::Held
            } else {
                Procedure::Steady
            }
        }
    };
    let reference = case.mechanical.reference_temperature;
    if let Some(r) = reference
        && !r.is_finite()
    {
        return Err(err(
            f,
            format!("mechanical.reference_temperature = {r}: must be finite"),
        ));
    }
    Ok(Some(ThermalSetup {
        model,
        procedure,
        reference_temperature: reference.into(),
    }))
}

/// Builds the driver's setup of a case on its mesh (interfaces declared);
/// `tie` is [`tie`] of the same case and mesh (the elastic model is built on
/// its mesh when some interface is bonded).
pub fn prepare<'m>(
    case: &Case,
    mesh: &'m Mesh,
    tie: Option<&'m TiedMesh>,
) -> CliResult<Prepared<'m>> {
    let f = &case.source;
    let mats = materials(case, mesh)?;
    let names = mesh.region_names().to_vec();

    // Output options.
    let times = case.output.times.clone();
    for t in &times {
        if !t.is_finite() || *t < 0.0 {
            return Err(err(f, format!("output.times: {t} is not a time ≥ 0")));
        }
    }
    crate::cmdline::check_increasing("output.times", &times).map_err(|e| err(f, e))?;
    let probes: Vec<([f64; 2], usize)> = case
        .output
        .probes
        .iter()
        .map(|&p| (p, nearest(mesh, p)))
        .collect();

    let thermal = thermal_setup(case, mesh, &mats, &times)?;
    let mech = &case.mechanical;
    if mech.reference_temperature.is_some() && thermal.is_none() {
        return Err(err(
            f,
            "mechanical.reference_temperature: needs a [thermal] section",
        ));
    }

    // Elastic model.
    let analysis = match mech.analysis {
        AnalysisName::PlaneStrain => Analysis::PlaneStrain,
        AnalysisName::PlaneStress => Analysis::PlaneStress,
        AnalysisName::GeneralisedPlaneStrain => Analysis::GeneralisedPlaneStrain,
    };
    let mut model = ElasticModel::new(tie.map_or(mesh, TiedMesh::mesh), analysis);
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
    let mut joints = serde_json::Map::new();
    // index of each case interface among the model's (bonded ones are tied, not modelled)
    let mut model_index = vec![None; case.interface.len()];
    for (k, i) in case.interface.iter().enumerate() {
        let key = format!("interface[{k}].joint ('{}')", i.name);
        let j = i
            .joint
            .as_ref()
            .ok_or_else(|| err(f, format!("{key}: missing [interface.joint] (law = \"frictional\" | \"linear\" | \"sticking\" | \"bonded\")")))?;
        if j.law == BONDED {
            if tie.is_none_or(|t| !t.tied_interfaces().contains(&i.name)) {
                return Err(err(
                    f,
                    format!("{key}: bonded, but the elastic mesh does not tie it"),
                ));
            }
            joints.insert(i.name.clone(), json!({ "law": BONDED }));
            continue;
        }
        model_index[k] = Some(model.interfaces().len());
        let (law, info) = joint(f, &key, j, interface_scale(mesh, &i.name, &mats))?;
        joints.insert(i.name.clone(), info);
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
    if let Some(edges) = &mech.hold_rigid_modes {
        model = model
            .hold_rigid_modes(edges)
            .map_err(|e| err(f, format!("mechanical.hold_rigid_modes = \"{edges}\": {e}")))?;
    }
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
    let coarse_levels = match mech.coarse_levels {
        None => tecon_elastic::COARSE_LEVELS,
        Some(n @ 1..=MAX_COARSE_LEVELS) => n,
        Some(n) => {
            return Err(err(
                f,
                format!(
                    "mechanical.coarse_levels = {n}: must be 1 to {MAX_COARSE_LEVELS} (1: the finest coarse level alone)"
                ),
            ));
        }
    };
    let solver = SolverOptions {
        augmented_lagrangian: al,
        max_iterations: 150,
        condensation: mech.condensation.unwrap_or(true),
        coarse_space: mech.coarse_space.unwrap_or(true),
        coarse_levels,
        coupled_tail: mech.coupled_tail.unwrap_or(true),
        pass_forcing: if mech.exact_passes.unwrap_or(false) {
            0.0
        } else {
            tecon_elastic::PASS_FORCING
        },
        ..Default::default()
    };
    let mut stages = vec![Stage {
        name: "loading".into(),
        loads: if case.staged_pressure {
            LoadFactors {
                pressure: 0.0,
                ..LoadFactors::FULL
            }
        } else {
            LoadFactors::FULL
        },
        temperature: StageTemperature::FollowThermal,
    }];
    if case.staged_pressure && !mech.pressure.is_empty() {
        stages.push(Stage {
            name: "operating pressure".into(),
            loads: LoadFactors::FULL,
            temperature: StageTemperature::HoldLast,
        });
    }
    let coupling = crate::conductance::coupling(f, case.coupling.as_ref(), thermal.is_some())?;
    if let (Coupling::TwoWay(_), Some(th)) = (coupling, &thermal)
        && matches!(th.procedure, Procedure::Held)
    {
        return Err(err(
            f,
            "coupling.mode = \"two-way\": needs heat conduction (thermal boundary conditions or a schedule), not a held initial field",
        ));
    }
    let coupled_interfaces = case
        .interface
        .iter()
        .zip(&model_index)
        .filter_map(|(i, &m)| {
            // a constant conductance reads no state (radiation reads the
            // face temperatures, which only the two-way loop hands it)
            let reads_state = i.conductance.as_ref().is_some_and(|h| {
                matches!(
                    crate::conductance::parse(f, &i.name, h),
                    Ok(Conductance::Law(l)) if l.depends_on_contact() || l.radiation.is_some()
                )
            });
            Some((i.name.clone(), m?)).filter(|_| reads_state)
        })
        .collect();
    Ok(Prepared {
        setup: Setup {
            mesh,
            tie,
            thermal,
            model,
            solver,
            stages,
            progress: case.progress,
            verbose: case.verbose,
            coupling,
            coupled_interfaces,
        },
        joints,
        augmented_lagrangian: al,
        analysis,
        probes,
    })
}
