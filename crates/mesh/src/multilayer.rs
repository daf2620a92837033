//! The multilayer welded vessel: a core and N layers, each wrapped over the
//! ones before it and welded along its own longitudinal seam.
//!
//! ```text
//!        seam 2 (θ = 120°)          every ring a separate body with its own
//!             \  .-~~~~~-.          nodes; interfaces core_layer1,
//!              /  .-~~~-.  \        layer1_layer2, … between adjacent rings;
//!             |  |  core |  |-- seam 1 (θ = 0)     weld k: the sector of
//!              \  '-~~~-'  /        layer k within ±w_k/2 (along its mid
//!             /  '-~~~~~-'          radius) of its seam angle
//!        seam 3 (θ = 240°)
//! ```
//!
//! When every seam lies on the plane y = 0 (θ = 0 or π) the section is
//! symmetric and only the half θ ∈ [0, π] is meshed (edge and node sets
//! `sym0`, `sym180`) unless [`MultilayerMeshSpec::full_section`] asks for
//! the whole ring; otherwise the full ring is meshed.
//!
//! All rings share one set of node stations around the circumference, so
//! facing interface nodes coincide. The stations put every weld edge of every
//! layer on a station, divide each weld uniformly and grow geometrically away
//! from the weld edges, capped at a largest interval.

use crate::error::MeshError;
use crate::mesh::{Mesh, signed_area};
use std::f64::consts::PI;

/// One wrapped layer and its longitudinal weld.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WeldedLayer {
    /// Layer thickness, m.
    pub thickness: f64,
    /// Half width of the weld along the layer's mid radius, m.
    pub weld_half_width: f64,
    /// Angle of the seam (weld centre), rad, in [0, 2π).
    pub seam_angle: f64,
}

/// Dimensions of the multilayer cross-section (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct MultilayerGeometry {
    /// Inner radius of the core, m.
    pub inner_radius: f64,
    /// Core wall thickness, m.
    pub core_thickness: f64,
    /// The layers, from the core outwards.
    pub layers: Vec<WeldedLayer>,
}

impl MultilayerGeometry {
    /// `n` equal layers with seams staggered evenly around the circumference
    /// (seam k at 2π(k − 1)/n).
    pub fn staggered(
        inner_radius: f64,
        core_thickness: f64,
        n: usize,
        thickness: f64,
        weld_half_width: f64,
    ) -> Self {
        let layers = (0..n)
            .map(|k| WeldedLayer {
                thickness,
                weld_half_width,
                seam_angle: 2.0 * PI * k as f64 / n as f64,
            })
            .collect();
        MultilayerGeometry {
            inner_radius,
            core_thickness,
            layers,
        }
    }

    /// Radii r₀ (bore), r₁ (core outer), …, r_{N+1} (outer surface).
    pub fn radii(&self) -> Vec<f64> {
        let mut r = vec![self.inner_radius, self.inner_radius + self.core_thickness];
        for l in &self.layers {
            r.push(r[r.len() - 1] + l.thickness);
        }
        r
    }

    /// Half angle of the weld of layer `k` (0-based), rad.
    pub fn weld_half_angle(&self, k: usize) -> f64 {
        let r = self.radii();
        self.layers[k].weld_half_width / (0.5 * (r[k + 1] + r[k + 2]))
    }

    /// Whether every seam lies on y = 0 (θ = 0 or π), so the half section suffices.
    pub fn is_symmetric(&self) -> bool {
        self.layers.iter().all(|l| {
            let t = l.seam_angle;
            t.abs() < 1e-12 || (t - PI).abs() < 1e-12
        })
    }

    /// Checks every length and angle; names the offending layer.
    pub fn check(&self) -> Result<(), MeshError> {
        let bad = |name: &'static str, value: String, reason: &str| {
            Err(MeshError::InvalidParameter {
                name,
                value,
                reason: reason.into(),
            })
        };
        for (name, v) in [
            ("inner_radius", self.inner_radius),
            ("core_thickness", self.core_thickness),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(name, v.to_string(), "must be a positive length");
            }
        }
        if self.layers.is_empty() {
            return bad("layers", "0".into(), "at least one layer");
        }
        for (k, l) in self.layers.iter().enumerate() {
            let id = format!("layer {}", k + 1);
            if !(l.thickness.is_finite() && l.thickness > 0.0) {
                return bad(
                    "layer thickness",
                    format!("{id}: {}", l.thickness),
                    "must be a positive length (a zero or negative thickness would make layers overlap)",
                );
            }
            if !(l.weld_half_width.is_finite() && l.weld_half_width > 0.0) {
                return bad(
                    "weld_half_width",
                    format!("{id}: {}", l.weld_half_width),
                    "must be a positive length",
                );
            }
            if !(l.seam_angle.is_finite() && (0.0..2.0 * PI).contains(&l.seam_angle)) {
                return bad(
                    "seam_angle",
                    format!("{id}: {} rad", l.seam_angle),
                    "must lie in [0, 2π)",
                );
            }
            if self.weld_half_angle(k) >= 0.25 * PI {
                return bad(
                    "weld_half_width",
                    format!("{id}: {}", l.weld_half_width),
                    "the weld must span less than a quarter of the circumference",
                );
            }
        }
        Ok(())
    }
}

/// Mesh density of the multilayer vessel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultilayerMeshSpec {
    /// Element rows through the core.
    pub core_rows: usize,
    /// Element rows through each layer.
    pub layer_rows: usize,
    /// Element intervals across each weld half width (the narrowest weld sets the size).
    pub weld_divisions: usize,
    /// First interval outside a weld relative to one weld interval.
    pub first_ratio: f64,
    /// Growth ratio of consecutive intervals away from the weld edges (≥ 1).
    pub growth: f64,
    /// Largest interval around the circumference, rad.
    pub max_interval: f64,
    /// Element order, 1 or 2 (6-node triangles, mid nodes at the polar
    /// midpoints of their edges, numbered ring after ring).
    pub order: usize,
    /// Mesh the full ring even when every seam lies on y = 0 (by default
    /// such a section is meshed as the half θ ∈ [0, π]).
    pub full_section: bool,
}

impl Default for MultilayerMeshSpec {
    /// Two rows per ring, two intervals per weld half, growth 1.3 up to 3°, P1.
    fn default() -> Self {
        MultilayerMeshSpec {
            core_rows: 2,
            layer_rows: 2,
            weld_divisions: 2,
            first_ratio: 1.0,
            growth: 1.3,
            max_interval: 3f64.to_radians(),
            order: 1,
            full_section: false,
        }
    }
}

/// Largest level of [`MultilayerMeshSpec::refined`].
pub const MULTILAYER_MAX_LEVEL: u32 = 4;

impl MultilayerMeshSpec {
    /// Refinement level `level` (0 ..= [`MULTILAYER_MAX_LEVEL`]) of the
    /// default density, with elements of order `order`: every interval
    /// halved `level` times. With f = 2^level: 2f rows through the core and
    /// through each layer, 2f intervals across each weld half width, the
    /// intervals outside the welds growing by 1.3^(1/f) from one weld
    /// interval up to 3°/f (so the level's stations interleave those of
    /// the level before, about 4^level times the triangles of level 0).
    /// Level 0 is [`MultilayerMeshSpec::default`] (at order 1).
    pub fn refined(level: u32, order: usize) -> Result<Self, MeshError> {
        if level > MULTILAYER_MAX_LEVEL {
            return Err(MeshError::InvalidParameter {
                name: "level",
                value: level.to_string(),
                reason: format!(
                    "multilayer refinement levels 0..={MULTILAYER_MAX_LEVEL} are offered (each level has about 4 times the triangles of the one before)"
                ),
            });
        }
        crate::generators::check_order(order)?;
        let f = 1usize << level;
        let d = Self::default();
        Ok(MultilayerMeshSpec {
            core_rows: d.core_rows * f,
            layer_rows: d.layer_rows * f,
            weld_divisions: d.weld_divisions * f,
            growth: d.growth.powf(1.0 / f as f64),
            max_interval: d.max_interval / f as f64,
            order,
            ..d
        })
    }

    /// Whether `geo` is meshed as the half section θ ∈ [0, π] (every seam on
    /// y = 0 and no full section asked for).
    pub fn half_section(&self, geo: &MultilayerGeometry) -> bool {
        geo.is_symmetric() && !self.full_section
    }

    fn check(&self) -> Result<(), MeshError> {
        let bad = |name: &'static str, value: String, reason: &str| {
            Err(MeshError::InvalidParameter {
                name,
                value,
                reason: reason.into(),
            })
        };
        crate::generators::check_order(self.order)?;
        for (name, v) in [
            ("core_rows", self.core_rows),
            ("layer_rows", self.layer_rows),
            ("weld_divisions", self.weld_divisions),
        ] {
            if v == 0 {
                return bad(name, "0".into(), "at least one");
            }
        }
        if !(self.first_ratio.is_finite() && self.first_ratio > 0.0) {
            return bad(
                "first_ratio",
                self.first_ratio.to_string(),
                "must be positive",
            );
        }
        if !(self.growth.is_finite() && self.growth >= 1.0) {
            return bad("growth", self.growth.to_string(), "must be at least 1");
        }
        if !(self.max_interval.is_finite() && self.max_interval > 0.0) {
            return bad(
                "max_interval",
                self.max_interval.to_string(),
                "must be a positive angle",
            );
        }
        Ok(())
    }
}

/// Intervals filling `length`, growing by `q` from each fine end (first interval `h1`,
/// capped at `hmax`) toward the middle, then shrunk uniformly to fit (so no interval exceeds
/// `hmax`); uniform when neither end is fine.
fn graded(length: f64, fine: [bool; 2], h1: f64, q: f64, hmax: f64) -> Vec<f64> {
    let h1 = h1.min(hmax);
    if !fine[0] && !fine[1] {
        let n = (length / hmax).ceil().max(1.0) as usize;
        return vec![length / n as f64; n];
    }
    let (mut left, mut right) = (Vec::new(), Vec::new());
    let (mut hl, mut hr) = (
        if fine[0] { h1 } else { hmax },
        if fine[1] { h1 } else { hmax },
    );
    let mut sum = 0.0;
    loop {
        let (h, from_left) = if hl <= hr { (hl, true) } else { (hr, false) };
        sum += h;
        if from_left {
            left.push(h);
            hl = (hl * q).min(hmax);
        } else {
            right.push(h);
            hr = (hr * q).min(hmax);
        }
        if sum >= length {
            break;
        }
    }
    right.reverse();
    left.extend(right);
    let s = length / sum;
    left.iter().map(|h| h * s).collect()
}

/// The node stations θ around the circumference: [0, π] (both ends) for a
/// symmetric section, else [0, 2π) (periodic, 2π not repeated).
pub fn multilayer_station_angles(
    geo: &MultilayerGeometry,
    spec: &MultilayerMeshSpec,
) -> Result<Vec<f64>, MeshError> {
    geo.check()?;
    spec.check()?;
    let half = spec.half_section(geo);
    let end = if half { PI } else { 2.0 * PI };
    // weld zones [a, b] of every layer, unrolled onto the domain
    let mut zones = Vec::new();
    let mut breaks = vec![0.0, end];
    let mut hw = f64::INFINITY;
    for k in 0..geo.layers.len() {
        let (s, t) = (geo.layers[k].seam_angle, geo.weld_half_angle(k));
        hw = hw.min(t / spec.weld_divisions as f64);
        for shift in [-2.0 * PI, 0.0, 2.0 * PI] {
            let (a, b) = (s - t + shift, s + t + shift);
            if b > 0.0 && a < end {
                zones.push((a, b));
                for e in [a, b] {
                    if e > 0.0 && e < end {
                        breaks.push(e);
                    }
                }
            }
        }
    }
    breaks.sort_by(f64::total_cmp);
    breaks.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let in_weld = |x: f64| zones.iter().any(|&(a, b)| x > a && x < b);
    // (θ = 0 and the end are weld edges only when a weld ends there; a weld
    // that covers θ = 0 makes its neighbouring segments weld segments.)
    let is_weld_edge = |x: f64| {
        zones
            .iter()
            .any(|&(a, b)| (x - a).abs() < 1e-12 || (x - b).abs() < 1e-12)
    };
    let mut out = vec![0.0];
    for w in breaks.windows(2) {
        let (a, b) = (w[0], w[1]);
        let intervals = if in_weld(0.5 * (a + b)) {
            let n = ((b - a) / hw).round().max(1.0) as usize;
            vec![(b - a) / n as f64; n]
        } else {
            graded(
                b - a,
                [is_weld_edge(a), is_weld_edge(b)],
                spec.first_ratio * hw,
                spec.growth,
                spec.max_interval,
            )
        };
        let n = intervals.len();
        let mut t = a;
        for (i, h) in intervals.into_iter().enumerate() {
            t += h;
            out.push(if i + 1 == n { b } else { t });
        }
    }
    if !half {
        out.pop(); // 2π is station 0 again
    }
    Ok(out)
}

/// Triangles a multilayer mesh of this geometry and spec would have.
pub fn multilayer_triangles(
    geo: &MultilayerGeometry,
    spec: &MultilayerMeshSpec,
) -> Result<usize, MeshError> {
    let st = multilayer_station_angles(geo, spec)?;
    let intervals = if spec.half_section(geo) {
        st.len() - 1
    } else {
        st.len()
    };
    Ok(2 * intervals * (spec.core_rows + geo.layers.len() * spec.layer_rows))
}

/// Generates the multilayer vessel mesh.
///
/// Regions `core`, `layer1`, `weld1`, `layer2`, `weld2`, …; edge sets `inner`
/// (bore), `outer` (outer surface of the last layer), `core_outer`,
/// `layer{k}_inner`, `layer{k}_outer`; interfaces `core_layer1`,
/// `layer1_layer2`, … (bottom = the inner ring); for a symmetric section also
/// edge and node sets `sym0` (θ = 0) and `sym180` (θ = π).
pub fn multilayer_vessel_mesh(
    geo: &MultilayerGeometry,
    spec: &MultilayerMeshSpec,
) -> Result<Mesh, MeshError> {
    multilayer_stage_mesh(geo, spec, geo.layers.len())
}

/// The mesh of the core and the first `layers` layers of `geo` as they
/// stand during staged construction: the node stations and the symmetry of
/// the whole geometry, and the same numbering as the whole mesh (its nodes
/// and triangles are the first ones of [`multilayer_vessel_mesh`]'s, its
/// regions the first names; at order 2 too, where every ring's corner
/// nodes are followed by its mid nodes). Edge set `outer` is the outer
/// surface of layer `layers`. Errors: `layers` zero or more than the
/// geometry has.
pub fn multilayer_stage_mesh(
    geo: &MultilayerGeometry,
    spec: &MultilayerMeshSpec,
    layers: usize,
) -> Result<Mesh, MeshError> {
    let theta = multilayer_station_angles(geo, spec)?;
    if layers == 0 || layers > geo.layers.len() {
        return Err(MeshError::InvalidParameter {
            name: "layers",
            value: layers.to_string(),
            reason: format!("a stage has 1 to {} layers", geo.layers.len()),
        });
    }
    let half = spec.half_section(geo);
    let ns = theta.len();
    let intervals = if half { ns - 1 } else { ns };
    let radii = geo.radii();
    let n_rings = layers + 1;
    let rows = |ring: usize| {
        if ring == 0 {
            spec.core_rows
        } else {
            spec.layer_rows
        }
    };
    let mut nodes = Vec::new();
    let mut base = Vec::with_capacity(n_rings);
    for ring in 0..n_rings {
        base.push(nodes.len());
        let (r0, r1) = (radii[ring], radii[ring + 1]);
        for &t in &theta {
            for j in 0..=rows(ring) {
                let r = r0 + (r1 - r0) * j as f64 / rows(ring) as f64;
                nodes.push([r * t.cos(), r * t.sin()]);
            }
        }
    }
    let id = |ring: usize, i: usize, j: usize| base[ring] + (i % ns) * (rows(ring) + 1) + j;
    let mut names = vec!["core".to_string()];
    for k in 1..n_rings {
        names.push(format!("layer{k}"));
        names.push(format!("weld{k}"));
    }
    let in_weld = |k: usize, t: f64| {
        let l = &geo.layers[k];
        let d = (t - l.seam_angle).rem_euclid(2.0 * PI);
        d.min(2.0 * PI - d) < geo.weld_half_angle(k)
    };
    let mut tris = Vec::new();
    let mut region = Vec::new();
    for ring in 0..n_rings {
        for i in 0..intervals {
            let t_mid = if i + 1 < ns {
                0.5 * (theta[i] + theta[i + 1])
            } else {
                0.5 * (theta[i] + 2.0 * PI)
            };
            let reg = match ring {
                0 => 0,
                k if in_weld(k - 1, t_mid) => 2 * k,
                k => 2 * k - 1,
            };
            for j in 0..rows(ring) {
                let (a, b, c, d) = (
                    id(ring, i, j),
                    id(ring, i + 1, j),
                    id(ring, i + 1, j + 1),
                    id(ring, i, j + 1),
                );
                // Diagonals alternate through the thickness only: every
                // station is alike, as in the monolayer generator.
                let pair = if j % 2 == 1 {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                for mut t in pair {
                    if signed_area(nodes[t[0]], nodes[t[1]], nodes[t[2]]) < 0.0 {
                        t.swap(1, 2);
                    }
                    tris.push(t);
                    region.push(reg);
                }
            }
        }
    }
    let mut mesh = Mesh::new(nodes, tris, region, names)?;
    let ring_edges = |ring: usize, j: usize| -> Vec<[usize; 2]> {
        (0..intervals)
            .map(|i| [id(ring, i, j), id(ring, i + 1, j)])
            .collect()
    };
    let ring_name = |ring: usize| {
        if ring == 0 {
            "core".to_string()
        } else {
            format!("layer{ring}")
        }
    };
    mesh.add_edge_set("inner", ring_edges(0, 0))?;
    mesh.add_edge_set("outer", ring_edges(n_rings - 1, rows(n_rings - 1)))?;
    for ring in 0..n_rings {
        if ring > 0 {
            mesh.add_edge_set(&format!("{}_inner", ring_name(ring)), ring_edges(ring, 0))?;
        }
        mesh.add_edge_set(
            &format!("{}_outer", ring_name(ring)),
            ring_edges(ring, rows(ring)),
        )?;
    }
    if half {
        for (name, i) in [("sym0", 0), ("sym180", ns - 1)] {
            let edges: Vec<[usize; 2]> = (0..n_rings)
                .flat_map(|ring| (0..rows(ring)).map(move |j| (ring, j)))
                .map(|(ring, j)| [id(ring, i, j), id(ring, i, j + 1)])
                .collect();
            let set: Vec<usize> = edges.iter().flatten().copied().collect();
            mesh.add_edge_set(name, edges)?;
            mesh.add_node_set(name, set)?;
        }
    }
    for ring in 1..n_rings {
        let bottom = format!("{}_outer", ring_name(ring - 1));
        let top = format!("{}_inner", ring_name(ring));
        let name = format!("{}_{}", ring_name(ring - 1), ring_name(ring));
        mesh.add_interface(&name, &bottom, &top, None)?;
    }
    if spec.order == 2 {
        base.push(mesh.n_nodes());
        return ring_major(mesh.to_quadratic_polar([0.0, 0.0])?, &base);
    }
    Ok(mesh)
}

/// A 6-node mesh renumbered ring after ring: the corner nodes of the core,
/// its mid nodes, the corner nodes of layer 1, its mid nodes, … (each block
/// in the order [`Mesh::to_quadratic_polar`] made it), so that the mesh of
/// the first k rings numbers its nodes as the whole mesh does (a stage mesh
/// is a prefix of the whole one at order 2 too). `corners[r]..corners[r + 1]`
/// are ring r's corner nodes; the triangles come ring after ring and no edge
/// is shared by two rings, so every ring's mid nodes form one block too.
fn ring_major(q: Mesh, corners: &[usize]) -> Result<Mesh, MeshError> {
    let n_rings = corners.len() - 1;
    let t6 = q.triangles6.as_deref().unwrap_or(&[]);
    // ring of every corner node, then the first and last mid node of each ring
    let ring_of = |v: usize| corners.partition_point(|&c| c <= v) - 1;
    let mut mids = vec![(usize::MAX, 0usize); n_rings];
    for t in t6 {
        let r = ring_of(t[0]);
        for &m in &t[3..] {
            mids[r].0 = mids[r].0.min(m);
            mids[r].1 = mids[r].1.max(m + 1);
        }
    }
    let mut new_of = vec![usize::MAX; q.n_nodes()];
    let mut next = 0;
    for r in 0..n_rings {
        for v in (corners[r]..corners[r + 1]).chain(mids[r].0..mids[r].1) {
            new_of[v] = next;
            next += 1;
        }
    }
    if next != q.n_nodes() || new_of.contains(&usize::MAX) {
        return Err(MeshError::InvalidParameter {
            name: "order",
            value: "2".into(),
            reason: "internal: the mid nodes of the rings do not form one block per ring".into(),
        });
    }
    let mut nodes = vec![[0.0; 2]; q.n_nodes()];
    for (v, p) in q.nodes.iter().enumerate() {
        nodes[new_of[v]] = *p;
    }
    let tris = t6.iter().map(|t| t.map(|v| new_of[v])).collect();
    let mut out = Mesh::new_quadratic(
        nodes,
        tris,
        q.element_region.clone(),
        q.region_names.clone(),
    )?;
    out.notices = q.notices.clone();
    out.edge_sets = q
        .edge_sets
        .iter()
        .map(|(k, e)| (k.clone(), e.iter().map(|p| p.map(|v| new_of[v])).collect()))
        .collect();
    out.node_sets = q
        .node_sets
        .iter()
        .map(|(k, s)| {
            let mut s: Vec<usize> = s.iter().map(|&v| new_of[v]).collect();
            s.sort_unstable();
            (k.clone(), s)
        })
        .collect();
    out.interfaces = q
        .interfaces
        .iter()
        .map(|(k, i)| {
            let mut i = i.clone();
            i.elements = i.elements.iter().map(|e| e.map(|v| new_of[v])).collect();
            i.mid_nodes = i.mid_nodes.iter().map(|e| e.map(|v| new_of[v])).collect();
            (k.clone(), i)
        })
        .collect();
    Ok(out)
}
