//! Gmsh MSH 4.1 import (ASCII and binary) through the `mshio` crate.
//!
//! * 3-node triangles (type 2) make a P1 mesh, 6-node triangles (type 9, as
//!   Gmsh writes second-order meshes: corners, then the mid nodes of edges
//!   (0,1), (1,2), (2,0)) a P2 mesh; their physical surface group names
//!   their region (an entity without a physical group gets the region
//!   `surface_<tag>`). Both orders in one file are an error naming the
//!   first element of the other order.
//! * 2-node lines (type 1; type 8, 3-node lines, in a P2 file) of physical
//!   curve groups become edge sets named after the group (corner pairs; the
//!   mid node of a 3-node line must be its edge's mid node). A curve may be
//!   in several physical curves: its lines are in each of their edge sets.
//! * A surface in two physical surfaces (of different names) is an error
//!   naming both: a triangle belongs to one region.
//! * Points (type 15) of physical point groups become node sets named after
//!   the group; a point whose node no triangle uses is left out, with a
//!   [`MeshNotice::PointOffMesh`]. A physical point named like a physical
//!   curve is an error (sets are looked up by name). Every other element
//!   type is an error.
//! * Nodes that no triangle uses are dropped and the rest renumbered in file
//!   order (Gmsh also writes the nodes of geometric points and curves). The
//!   mesh keeps the Gmsh node tag of each node and element tag of each
//!   triangle ([`Mesh::gmsh_tags`]); errors name both numbers.
//! * Physical groups declared in the file that hold no element Tecon reads
//!   are remembered: looking one up gives [`MeshError::EmptyGroup`] (with
//!   its dimension) instead of "no such name".
//! * A mesh more than [`MILLIMETRE_HINT_SIZE`] across gets a
//!   [`MeshNotice::LooksLikeMillimetres`].
//! * Node tags: when mshio reports dense tags, they are taken to run
//!   consecutively through the node blocks in file order, which is how Gmsh
//!   writes them.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

use mshio::mshfile::ElementType;

use crate::error::{GmshTags, MeshError};
use crate::mesh::{Mesh, MeshNotice};

/// Reads a Gmsh MSH 4.1 file (ASCII or binary).
pub fn read_msh(path: impl AsRef<Path>) -> Result<Mesh, MeshError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| MeshError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    parse_msh(&bytes, path)
}

/// Parses the bytes of a Gmsh MSH 4.1 file; `path` is used in error messages.
pub fn parse_msh(bytes: &[u8], path: &Path) -> Result<Mesh, MeshError> {
    let content = |message: String| MeshError::MshContent {
        path: path.to_path_buf(),
        message,
    };
    check_version(bytes, path)?;
    let binary = is_binary(bytes);
    let file = mshio::parse_msh_bytes(bytes).map_err(|e| {
        // The first backtrace entry is the deepest, where parsing stopped.
        let offset = e
            .backtrace
            .first()
            .map_or(0, |(rest, _)| bytes.len() - rest.len());
        let message = match e.first_msh_error() {
            Some(kind) => format!("{kind:?}"),
            None => "unexpected content".to_string(),
        };
        let context: Vec<String> = e
            .filter_msh_errors()
            .filter_map(|(_, k)| k.context().map(str::to_string))
            .collect();
        let message = if context.is_empty() {
            message
        } else {
            format!("{} ({message})", context.join(" / "))
        };
        MeshError::MshParse {
            path: path.to_path_buf(),
            location: location(bytes, offset, binary),
            message,
        }
    })?;
    let names = physical_names(bytes);
    let entities = file.data.entities.as_ref();
    let groups_of = |dim: i32| -> HashMap<i32, Vec<i32>> {
        let Some(e) = entities else {
            return HashMap::new();
        };
        match dim {
            0 => e
                .points
                .iter()
                .map(|p| (p.tag, p.physical_tags.clone()))
                .collect(),
            1 => e
                .curves
                .iter()
                .map(|c| (c.tag, c.physical_tags.clone()))
                .collect(),
            _ => e
                .surfaces
                .iter()
                .map(|s| (s.tag, s.physical_tags.clone()))
                .collect(),
        }
    };
    let point_groups = groups_of(0);
    let curve_groups = groups_of(1);
    let surface_groups = groups_of(2);
    let group_name = |dim: i32, tag: i32| {
        names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| format!("physical_{dim}_{tag}"))
    };
    // Every physical group the file declares: (dim, tag); those that receive
    // an element Tecon reads are `filled`, the others are empty.
    let mut declared: BTreeSet<(i32, i32)> = names.keys().copied().collect();
    for (dim, map) in [(0, &point_groups), (1, &curve_groups), (2, &surface_groups)] {
        declared.extend(map.values().flatten().map(|&g| (dim, g.abs())));
    }
    if let Some(e) = entities {
        declared.extend(
            e.volumes
                .iter()
                .flat_map(|v| &v.physical_tags)
                .map(|&g| (3, g.abs())),
        );
    }
    let mut filled: BTreeSet<(i32, i32)> = BTreeSet::new();

    // Nodes: tag -> (x, y).
    let nodes_sec = file
        .data
        .nodes
        .as_ref()
        .ok_or_else(|| content("the file has no $Nodes section".into()))?;
    let mut tag_to_file_index: HashMap<u64, usize> = HashMap::new();
    let mut coords = Vec::new();
    let mut file_tags: Vec<u64> = Vec::new();
    let mut next_dense = nodes_sec.min_node_tag;
    for block in &nodes_sec.node_blocks {
        let mut by_index: Vec<u64> = vec![0; block.nodes.len()];
        match &block.node_tags {
            Some(map) => {
                for (&tag, &k) in map {
                    if k < by_index.len() {
                        by_index[k] = tag;
                    }
                }
            }
            None => {
                for slot in by_index.iter_mut() {
                    *slot = next_dense;
                    next_dense += 1;
                }
            }
        }
        for (k, node) in block.nodes.iter().enumerate() {
            if node.z.abs() > 0.0
                && node.z.is_finite()
                && node.z.abs() > 1e-12 * (node.x.abs() + node.y.abs() + 1.0)
            {
                return Err(content(format!(
                    "Gmsh node tag {} has z = {}; Tecon takes planar meshes in the x-y plane",
                    by_index[k], node.z
                )));
            }
            tag_to_file_index.insert(by_index[k], coords.len());
            coords.push([node.x, node.y]);
            file_tags.push(by_index[k]);
        }
    }

    let elements = file
        .data
        .elements
        .as_ref()
        .ok_or_else(|| content("the file has no $Elements section".into()))?;
    let lookup = |tag: u64, elem: u64| {
        tag_to_file_index.get(&tag).copied().ok_or_else(|| {
            content(format!(
                "element tag {elem} refers to node tag {tag}, which is not in $Nodes"
            ))
        })
    };
    // (element tag, Gmsh type) of the first triangle and first line: the
    // file's element order.
    let mut first_tri: Option<(u64, u32)> = None;
    let mut first_line: Option<(u64, u32)> = None;
    let mixed = |first: (u64, u32), tag: u64, ty: u32, entity: i32| {
        content(format!(
            "element {tag} (Gmsh type {ty}, {}, entity {entity}) has a different order than element {} (Gmsh type {}, {}); Tecon takes meshes of one order (save all elements as first or all as second order)",
            type_words(ty),
            first.0,
            first.1,
            type_words(first.1)
        ))
    };
    let mut tris_file: Vec<[usize; 6]> = Vec::new();
    let mut tri_tags: Vec<u64> = Vec::new();
    let mut tri_region_name: Vec<String> = Vec::new();
    // per physical curve: (line nodes, line element tag)
    let mut edge_sets_file: BTreeMap<String, Vec<([usize; 3], u64)>> = BTreeMap::new();
    // per physical point: (group tag, [(file node index, point element tag)])
    let mut node_sets_file: BTreeMap<String, (i32, Vec<(usize, u64)>)> = BTreeMap::new();
    for block in &elements.element_blocks {
        let ty = block.element_type as u32;
        match block.element_type {
            ElementType::Tri3 | ElementType::Tri6 => {
                let n = if ty == 2 { 3 } else { 6 };
                // the surface's physical groups, one per name
                let mut groups: Vec<(i32, String)> = Vec::new();
                for &g in surface_groups.get(&block.entity_tag).into_iter().flatten() {
                    let name = group_name(2, g.abs());
                    if !groups.iter().any(|(_, m)| *m == name) {
                        groups.push((g.abs(), name));
                    }
                }
                if groups.len() > 1 && !block.elements.is_empty() {
                    let list: Vec<String> = groups
                        .iter()
                        .map(|(g, name)| format!("'{name}' (tag {g})"))
                        .collect();
                    return Err(content(format!(
                        "surface {} is in {} physical surfaces, {}; its triangles would belong to several regions, but a triangle belongs to one region (one material): keep the surface in one physical surface (a region of several surfaces lists them all in its one Physical Surface; a region inside another is a surface of its own, cut out of the other)",
                        block.entity_tag,
                        groups.len(),
                        list.join(" and ")
                    )));
                }
                let region = match groups.first() {
                    Some((g, name)) => {
                        if !block.elements.is_empty() {
                            filled.insert((2, *g));
                        }
                        name.clone()
                    }
                    None => format!("surface_{}", block.entity_tag),
                };
                for el in &block.elements {
                    match first_tri {
                        None => first_tri = Some((el.element_tag, ty)),
                        Some(f) if f.1 != ty => {
                            return Err(mixed(f, el.element_tag, ty, block.entity_tag));
                        }
                        _ => {}
                    }
                    if el.nodes.len() != n {
                        return Err(content(format!(
                            "triangle {} has {} nodes (Gmsh type {ty} has {n})",
                            el.element_tag,
                            el.nodes.len()
                        )));
                    }
                    let mut t = [usize::MAX; 6];
                    for (slot, &tag) in t.iter_mut().zip(&el.nodes) {
                        *slot = lookup(tag, el.element_tag)?;
                    }
                    tris_file.push(t);
                    tri_tags.push(el.element_tag);
                    tri_region_name.push(region.clone());
                }
            }
            ElementType::Lin2 | ElementType::Lin3 => {
                let n = if ty == 1 { 2 } else { 3 };
                // a curve may be in several physical curves: its lines go
                // into each of their edge sets
                let groups = curve_groups
                    .get(&block.entity_tag)
                    .cloned()
                    .unwrap_or_default();
                if !block.elements.is_empty() {
                    filled.extend(groups.iter().map(|g| (1, g.abs())));
                }
                for el in &block.elements {
                    match first_line {
                        None => first_line = Some((el.element_tag, ty)),
                        Some(f) if f.1 != ty => {
                            return Err(mixed(f, el.element_tag, ty, block.entity_tag));
                        }
                        _ => {}
                    }
                    if el.nodes.len() != n {
                        return Err(content(format!(
                            "line {} has {} nodes (Gmsh type {ty} has {n})",
                            el.element_tag,
                            el.nodes.len()
                        )));
                    }
                    let mut e = [usize::MAX; 3];
                    for (slot, &tag) in e.iter_mut().zip(&el.nodes) {
                        *slot = lookup(tag, el.element_tag)?;
                    }
                    for &g in &groups {
                        edge_sets_file
                            .entry(group_name(1, g.abs()))
                            .or_default()
                            .push((e, el.element_tag));
                    }
                }
            }
            ElementType::Pnt => {
                let groups = point_groups
                    .get(&block.entity_tag)
                    .cloned()
                    .unwrap_or_default();
                for el in &block.elements {
                    let Some(&tag) = el.nodes.first() else {
                        continue;
                    };
                    let v = lookup(tag, el.element_tag)?;
                    for &g in &groups {
                        node_sets_file
                            .entry(group_name(0, g.abs()))
                            .or_insert_with(|| (g.abs(), Vec::new()))
                            .1
                            .push((v, el.element_tag));
                    }
                }
            }
            other => {
                return Err(MeshError::UnsupportedElement {
                    path: path.to_path_buf(),
                    type_name: format!("{other:?}"),
                    type_id: other as u32,
                    entity: block.entity_tag,
                });
            }
        }
    }
    if let (Some(t), Some(l)) = (first_tri, first_line)
        && (t.1 == 9) != (l.1 == 8)
    {
        return Err(content(format!(
            "line element {} (Gmsh type {}, {}) has a different order than triangle element {} (Gmsh type {}, {}); Tecon takes meshes of one order",
            l.0,
            l.1,
            type_words(l.1),
            t.0,
            t.1,
            type_words(t.1)
        )));
    }
    let quadratic = first_tri.is_some_and(|t| t.1 == 9);
    let width = if quadratic { 6 } else { 3 };
    if tris_file.is_empty() {
        return Err(content(
            "the file has no triangles (3-node or 6-node)".into(),
        ));
    }
    // Compact: keep nodes used by triangles, in file order.
    let mut new_id = vec![usize::MAX; coords.len()];
    for t in &tris_file {
        for &v in &t[..width] {
            new_id[v] = 0;
        }
    }
    let mut nodes = Vec::new();
    let mut node_tags = Vec::new();
    for (i, id) in new_id.iter_mut().enumerate() {
        if *id == 0 {
            *id = nodes.len();
            nodes.push(coords[i]);
            node_tags.push(file_tags[i]);
        }
    }
    // Physical points: node sets of the points that are nodes of the mesh.
    let mut notices = Vec::new();
    let mut node_sets: Vec<(String, Vec<usize>)> = Vec::new();
    for (name, (g, points)) in node_sets_file {
        let mut ids = Vec::new();
        for (v, _) in points {
            match new_id[v] {
                usize::MAX => notices.push(MeshNotice::PointOffMesh {
                    group: name.clone(),
                    node_tag: file_tags[v],
                    x: coords[v][0],
                    y: coords[v][1],
                }),
                id => ids.push(id),
            }
        }
        if ids.is_empty() {
            continue;
        }
        if edge_sets_file.contains_key(&name) {
            return Err(content(format!(
                "'{name}' names both a physical point and a physical curve; Tecon looks node sets and edge sets up by name (as `set` of [[mechanical.fix]]): rename one of them"
            )));
        }
        filled.insert((0, g));
        node_sets.push((name, ids));
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    if size > MILLIMETRE_HINT_SIZE {
        notices.push(MeshNotice::LooksLikeMillimetres { size });
    }
    let tags = GmshTags {
        nodes: node_tags,
        elements: tri_tags,
        empty_groups: declared
            .difference(&filled)
            .map(|&(dim, g)| (dim, group_name(dim, g)))
            .collect(),
    };
    let mut region_names: Vec<String> = Vec::new();
    let regions: Vec<usize> = tri_region_name
        .iter()
        .map(|r| match region_names.iter().position(|x| x == r) {
            Some(k) => k,
            None => {
                region_names.push(r.clone());
                region_names.len() - 1
            }
        })
        .collect();
    let mut mesh = if quadratic {
        let triangles: Vec<[usize; 6]> = tris_file.iter().map(|t| t.map(|v| new_id[v])).collect();
        Mesh::new_quadratic(nodes, triangles, regions, region_names)
    } else {
        let triangles: Vec<[usize; 3]> = tris_file
            .iter()
            .map(|t| [new_id[t[0]], new_id[t[1]], new_id[t[2]]])
            .collect();
        Mesh::new(nodes, triangles, regions, region_names)
    }
    .map_err(|e| content(e.with_gmsh_tags(&tags).to_string()))?;
    mesh.gmsh = Some(Box::new(tags));
    mesh.notices.extend(notices);
    for (name, edges) in edge_sets_file {
        let mut mapped = Vec::with_capacity(edges.len());
        for (e, line) in edges {
            let k = if quadratic { 3 } else { 2 };
            let ids: Vec<usize> = e.iter().take(k).map(|&v| new_id[v]).collect();
            let line_tags: Vec<String> = e
                .iter()
                .take(k)
                .map(|&v| file_tags[v].to_string())
                .collect();
            if ids.contains(&usize::MAX) {
                return Err(content(format!(
                    "physical curve '{name}': line element {line} (Gmsh node tags {}) has a node that no triangle uses (is the curve on the boundary of a meshed surface?)",
                    line_tags.join(", ")
                )));
            }
            if quadratic && mesh.edge_mid_node(ids[0], ids[1]) != Some(ids[2]) {
                return Err(content(format!(
                    "physical curve '{name}': the 3-node line element {line} (Gmsh node tags {}) does not match a triangle edge and its mid node",
                    line_tags.join(", ")
                )));
            }
            mapped.push([ids[0], ids[1]]);
        }
        mesh.add_edge_set(&name, mapped)
            .map_err(|e| content(e.to_string()))?;
    }
    for (name, ids) in node_sets {
        mesh.add_node_set(&name, ids)
            .map_err(|e| content(e.to_string()))?;
    }
    Ok(mesh)
}

/// A Gmsh mesh larger than this (metres, the largest extent of its bounding
/// box) gets a notice that it may be in millimetres.
pub const MILLIMETRE_HINT_SIZE: f64 = 50.0;

/// Words for the Gmsh element types Tecon reads.
fn type_words(ty: u32) -> &'static str {
    match ty {
        1 => "2-node line, first order",
        2 => "3-node triangle, first order",
        8 => "3-node line, second order",
        9 => "6-node triangle, second order",
        _ => "other",
    }
}

fn check_version(bytes: &[u8], path: &Path) -> Result<(), MeshError> {
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(64)]);
    let mut lines = head.lines();
    let first = lines.next().unwrap_or("").trim();
    if first != "$MeshFormat" {
        return Err(MeshError::MshParse {
            path: path.to_path_buf(),
            location: "line 1".into(),
            message: "not a Gmsh file: expected '$MeshFormat'".into(),
        });
    }
    let version = lines
        .next()
        .unwrap_or("")
        .split_whitespace()
        .next()
        .unwrap_or("");
    if version != "4.1" {
        return Err(MeshError::MshParse {
            path: path.to_path_buf(),
            location: "line 2".into(),
            message: format!(
                "MSH version '{version}' is not supported; save as MSH 4.1 (Gmsh: -format msh41)"
            ),
        });
    }
    Ok(())
}

fn is_binary(bytes: &[u8]) -> bool {
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(64)]);
    head.lines()
        .nth(1)
        .and_then(|l| l.split_whitespace().nth(1))
        .is_some_and(|t| t == "1")
}

fn location(bytes: &[u8], offset: usize, binary: bool) -> String {
    if binary {
        format!("byte offset {offset}")
    } else {
        let line = bytes[..offset.min(bytes.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1;
        format!("line {line}")
    }
}

/// Reads `$PhysicalNames` (always ASCII): (dim, tag) → name.
fn physical_names(bytes: &[u8]) -> HashMap<(i32, i32), String> {
    let mut out = HashMap::new();
    let key = b"$PhysicalNames";
    let Some(start) = bytes.windows(key.len()).position(|w| w == key) else {
        return out;
    };
    let rest = &bytes[start + key.len()..];
    let end = rest
        .windows(b"$EndPhysicalNames".len())
        .position(|w| w == b"$EndPhysicalNames")
        .unwrap_or(rest.len());
    let text = String::from_utf8_lossy(&rest[..end]);
    for line in text.lines().skip(1) {
        let mut parts = line.trim().splitn(3, char::is_whitespace);
        let (Some(d), Some(t), Some(n)) = (parts.next(), parts.next(), parts.next()) else {
            continue;
        };
        if let (Ok(d), Ok(t)) = (d.parse::<i32>(), t.parse::<i32>()) {
            out.insert((d, t), n.trim().trim_matches('"').to_string());
        }
    }
    out
}
