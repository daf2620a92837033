//! Gmsh MSH 4.1 import (ASCII and binary) through the `mshio` crate.
//!
//! * 3-node triangles (type 2) become mesh triangles; their physical surface
//!   group names their region (an entity without a physical group gets the
//!   region `surface_<tag>`).
//! * 2-node lines (type 1) of physical curve groups become edge sets named
//!   after the group.
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
    let mut tris_file: Vec<[usize; 3]> = Vec::new();
    let mut tri_region_name: Vec<String> = Vec::new();
    let mut edge_sets_file: BTreeMap<String, Vec<[usize; 2]>> = BTreeMap::new();
    for block in &elements.element_blocks {
        match block.element_type {
            ElementType::Tri3 => {
                let groups = surface_groups
                    .get(&block.entity_tag)
                    .cloned()
                    .unwrap_or_default();
                let region = match groups.first() {
                    Some(&g) => group_name(2, g.abs()),
                    None => format!("surface_{}", block.entity_tag),
                };
                for el in &block.elements {
                    if el.nodes.len() != 3 {
                        return Err(content(format!(
                            "triangle {} has {} nodes",
                            el.element_tag,
                            el.nodes.len()
                        )));
                    }
                    let t = [
                        lookup(el.nodes[0], el.element_tag)?,
                        lookup(el.nodes[1], el.element_tag)?,
                        lookup(el.nodes[2], el.element_tag)?,
                    ];
                    tris_file.push(t);
                    tri_region_name.push(region.clone());
                }
            }
            ElementType::Lin2 => {
                let groups = curve_groups
                    .get(&block.entity_tag)
                    .cloned()
                    .unwrap_or_default();
                for el in &block.elements {
                    if el.nodes.len() != 2 {
                        return Err(content(format!(
                            "line {} has {} nodes",
                            el.element_tag,
                            el.nodes.len()
                        )));
                    }
                    let e = [
                        lookup(el.nodes[0], el.element_tag)?,
                        lookup(el.nodes[1], el.element_tag)?,
                    ];
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
    if tris_file.is_empty() {
        return Err(content("the file has no 3-node triangles".into()));
    }
    // Compact: keep nodes used by triangles, in file order.
    let mut new_id = vec![usize::MAX; coords.len()];
    for t in &tris_file {
        for &v in t {
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
    let triangles: Vec<[usize; 3]> = tris_file.iter().map(|t| t.map(|v| new_id[v])).collect();
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
    let mut mesh =
        Mesh::new(nodes, triangles, regions, region_names).map_err(|e| content(e.to_string()))?;
    for (name, edges) in edge_sets_file {
        let mut mapped = Vec::with_capacity(edges.len());
        for [a, b] in edges {
            if new_id[a] == usize::MAX || new_id[b] == usize::MAX {
                return Err(content(format!(
                    "physical curve '{name}' has a line whose nodes belong to no triangle"
                )));
            }
            mapped.push([new_id[a], new_id[b]]);
        }
        mesh.add_edge_set(&name, mapped)
            .map_err(|e| content(e.to_string()))?;
    }
    Ok(mesh)
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
