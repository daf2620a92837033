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
//!   mid node of a 3-node line must be its edge's mid node).
//! * Points (type 15) are ignored; every other element type is an error.
//! * Nodes that no triangle uses are dropped and the rest renumbered in file
//!   order (Gmsh also writes the nodes of geometric points and curves).
//! * Node tags: when mshio reports dense tags, they are taken to run
//!   consecutively through the node blocks in file order, which is how Gmsh
//!   writes them.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use mshio::mshfile::ElementType;

use crate::error::MeshError;
use crate::mesh::Mesh;

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
    let surface_groups: HashMap<i32, Vec<i32>> = entities
        .map(|e| {
            e.surfaces
                .iter()
                .map(|s| (s.tag, s.physical_tags.clone()))
                .collect()
        })
        .unwrap_or_default();
    let curve_groups: HashMap<i32, Vec<i32>> = entities
        .map(|e| {
            e.curves
                .iter()
                .map(|c| (c.tag, c.physical_tags.clone()))
                .collect()
        })
        .unwrap_or_default();
    let group_name = |dim: i32, tag: i32| {
        names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| format!("physical_{dim}_{tag}"))
    };

    // Nodes: tag -> (x, y).
    let nodes_sec = file
        .data
        .nodes
        .as_ref()
        .ok_or_else(|| content("the file has no $Nodes section".into()))?;
    let mut tag_to_file_index: HashMap<u64, usize> = HashMap::new();
    let mut coords = Vec::new();
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
                    "node {} has z = {}; Tecon takes planar meshes in the x-y plane",
                    by_index[k], node.z
                )));
            }
            tag_to_file_index.insert(by_index[k], coords.len());
            coords.push([node.x, node.y]);
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
                "element {elem} refers to node tag {tag}, which is not in $Nodes"
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
    let mut tri_region_name: Vec<String> = Vec::new();
    let mut edge_sets_file: BTreeMap<String, Vec<[usize; 3]>> = BTreeMap::new();
    for block in &elements.element_blocks {
        let ty = block.element_type as u32;
        match block.element_type {
            ElementType::Tri3 | ElementType::Tri6 => {
                let n = if ty == 2 { 3 } else { 6 };
                let groups = surface_groups
                    .get(&block.entity_tag)
                    .cloned()
                    .unwrap_or_default();
                let region = match groups.first() {
                    Some(&g) => group_name(2, g.abs()),
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
                    tri_region_name.push(region.clone());
                }
            }
            ElementType::Lin2 | ElementType::Lin3 => {
                let n = if ty == 1 { 2 } else { 3 };
                let groups = curve_groups
                    .get(&block.entity_tag)
                    .cloned()
                    .unwrap_or_default();
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
                            .push(e);
                    }
                }
            }
            ElementType::Pnt => {}
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
    for (i, id) in new_id.iter_mut().enumerate() {
        if *id == 0 {
            *id = nodes.len();
            nodes.push(coords[i]);
        }
    }
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
    .map_err(|e| content(e.to_string()))?;
    for (name, edges) in edge_sets_file {
        let mut mapped = Vec::with_capacity(edges.len());
        for e in edges {
            let ids: Vec<usize> = e
                .iter()
                .take(if quadratic { 3 } else { 2 })
                .map(|&v| new_id[v])
                .collect();
            if ids.contains(&usize::MAX) {
                return Err(content(format!(
                    "physical curve '{name}' has a line whose nodes belong to no triangle"
                )));
            }
            if quadratic && mesh.edge_mid_node(ids[0], ids[1]) != Some(ids[2]) {
                return Err(content(format!(
                    "physical curve '{name}': the 3-node line ({}, {}, {}) does not match a triangle edge and its mid node",
                    ids[0], ids[1], ids[2]
                )));
            }
            mapped.push([ids[0], ids[1]]);
        }
        mesh.add_edge_set(&name, mapped)
            .map_err(|e| content(e.to_string()))?;
    }
    Ok(mesh)
}

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
