//! Simple structured generators used by examples and verification tests.

use crate::error::MeshError;
use crate::mesh::{Mesh, signed_area};

/// Checks an element order (1 or 2).
pub(crate) fn check_order(order: usize) -> Result<(), MeshError> {
    if order == 1 || order == 2 {
        Ok(())
    } else {
        Err(MeshError::InvalidParameter {
            name: "order",
            value: order.to_string(),
            reason: "the element order is 1 (3-node) or 2 (6-node triangles)".into(),
        })
    }
}

/// [`rectangle`] of element order 1 or 2 (straight edges, mid nodes at the
/// chord midpoints; node sets `left`, … gain the mid nodes of their edges).
pub fn rectangle_of_order(
    x0: f64,
    y0: f64,
    lx: f64,
    ly: f64,
    nx: usize,
    ny: usize,
    order: usize,
) -> Result<Mesh, MeshError> {
    check_order(order)?;
    let m = rectangle(x0, y0, lx, ly, nx, ny)?;
    if order == 2 {
        m.to_quadratic(&[])
    } else {
        Ok(m)
    }
}

/// [`layered_annulus`] of element order 1 or 2. At order 2 every mid node is
/// the polar midpoint of its edge: edges along a node row (inner, outer,
/// interface and interior rows) lie on their circle, radial edges are
/// straight, diagonals follow the polar map.
pub fn layered_annulus_of_order(
    layers: &[RingLayer],
    theta0: f64,
    theta1: f64,
    segments: usize,
    order: usize,
) -> Result<Mesh, MeshError> {
    check_order(order)?;
    let m = layered_annulus(layers, theta0, theta1, segments)?;
    if order == 1 {
        return Ok(m);
    }
    m.to_quadratic_polar([0.0, 0.0])
}

/// A structured rectangle [x0, x0+lx] × [y0, y0+ly] of `nx` × `ny` cells,
/// each cut into two triangles (diagonals alternating).
///
/// Region `domain`; edge sets `left`, `right`, `bottom`, `top`.
pub fn rectangle(
    x0: f64,
    y0: f64,
    lx: f64,
    ly: f64,
    nx: usize,
    ny: usize,
) -> Result<Mesh, MeshError> {
    if nx == 0 || ny == 0 {
        return Err(MeshError::InvalidParameter {
            name: "nx, ny",
            value: format!("{nx}, {ny}"),
            reason: "at least one cell in each direction".into(),
        });
    }
    if !(lx > 0.0 && ly > 0.0 && lx.is_finite() && ly.is_finite()) {
        return Err(MeshError::InvalidParameter {
            name: "lx, ly",
            value: format!("{lx}, {ly}"),
            reason: "positive finite lengths".into(),
        });
    }
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push([
                x0 + lx * i as f64 / nx as f64,
                y0 + ly * j as f64 / ny as f64,
            ]);
        }
    }
    let mut tris = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                tris.push([a, b, c]);
                tris.push([a, c, d]);
            } else {
                tris.push([a, b, d]);
                tris.push([b, c, d]);
            }
        }
    }
    let n = tris.len();
    let mut mesh = Mesh::new(nodes, tris, vec![0; n], vec!["domain".into()])?;
    mesh.add_edge_set(
        "bottom",
        (0..nx).map(|i| [id(i, 0), id(i + 1, 0)]).collect(),
    )?;
    mesh.add_edge_set("top", (0..nx).map(|i| [id(i, ny), id(i + 1, ny)]).collect())?;
    mesh.add_edge_set("left", (0..ny).map(|j| [id(0, j), id(0, j + 1)]).collect())?;
    mesh.add_edge_set(
        "right",
        (0..ny).map(|j| [id(nx, j), id(nx, j + 1)]).collect(),
    )?;
    for name in ["bottom", "top", "left", "right"] {
        let nodes = mesh.edge_set_nodes(name)?;
        mesh.add_node_set(name, nodes)?;
    }
    Ok(mesh)
}

/// One concentric layer of [`layered_annulus`].
#[derive(Debug, Clone, PartialEq)]
pub struct RingLayer {
    /// Region (and body) name.
    pub name: String,
    /// Inner radius.
    pub r_in: f64,
    /// Outer radius.
    pub r_out: f64,
    /// Element rows through the thickness.
    pub rows: usize,
}

/// Concentric rings (or ring sectors θ0 ≤ θ ≤ θ1) about the origin, each a
/// separate body with its own nodes, consecutive rings joined by interfaces.
///
/// `segments` intervals around; a full circle when θ1 − θ0 = 2π (to 1e-12).
/// Per layer `L`: region `L`, edge sets `L_inner`, `L_outer`, and for a sector
/// `L_start` (θ0) and `L_end` (θ1). Also `inner` (innermost surface), `outer`
/// (outermost), `start` and `end` (all layers). Interface `A_B` between
/// consecutive layers A (bottom) and B (top).
pub fn layered_annulus(
    layers: &[RingLayer],
    theta0: f64,
    theta1: f64,
    segments: usize,
) -> Result<Mesh, MeshError> {
    let bad = |name: &'static str, value: String, reason: &str| MeshError::InvalidParameter {
        name,
        value,
        reason: reason.into(),
    };
    if layers.is_empty() {
        return Err(bad("layers", "[]".into(), "at least one layer"));
    }
    let span = theta1 - theta0;
    if !(span > 0.0 && span <= 2.0 * std::f64::consts::PI + 1e-12) {
        return Err(bad(
            "theta1 - theta0",
            span.to_string(),
            "must lie in (0, 2π]",
        ));
    }
    let closed = (span - 2.0 * std::f64::consts::PI).abs() < 1e-12;
    if segments < if closed { 3 } else { 1 } {
        return Err(bad(
            "segments",
            segments.to_string(),
            "too few intervals around",
        ));
    }
    for (k, l) in layers.iter().enumerate() {
        if !(l.r_in > 0.0 && l.r_out > l.r_in) || l.rows == 0 {
            return Err(bad(
                "layer",
                format!("{} ({}, {}, {})", l.name, l.r_in, l.r_out, l.rows),
                "needs 0 < r_in < r_out and rows ≥ 1",
            ));
        }
        if k > 0 && (l.r_in - layers[k - 1].r_out).abs() > 1e-12 * l.r_in {
            return Err(bad(
                "layer",
                l.name.clone(),
                "must start at the outer radius of the previous layer",
            ));
        }
    }
    let ns = if closed { segments } else { segments + 1 };
    let theta = |i: usize| theta0 + span * i as f64 / segments as f64;
    let mut nodes = Vec::new();
    let mut tris = Vec::new();
    let mut region = Vec::new();
    let mut ids: Vec<Vec<usize>> = Vec::new(); // per layer: (i, j) -> node
    for (k, l) in layers.iter().enumerate() {
        let base = nodes.len();
        for i in 0..ns {
            let t = theta(i);
            for j in 0..=l.rows {
                let r = l.r_in + (l.r_out - l.r_in) * j as f64 / l.rows as f64;
                nodes.push([r * t.cos(), r * t.sin()]);
            }
        }
        let id = |i: usize, j: usize| base + (i % ns) * (l.rows + 1) + j;
        for i in 0..segments {
            for j in 0..l.rows {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                // Diagonals alternate through the thickness only, so every
                // station is alike and an axisymmetric load gives an
                // axisymmetric discrete answer.
                let pair = if j % 2 == 0 {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                for mut t in pair {
                    if signed_area(nodes[t[0]], nodes[t[1]], nodes[t[2]]) < 0.0 {
                        t.swap(1, 2);
                    }
                    tris.push(t);
                    region.push(k);
                }
            }
        }
        ids.push((0..ns * (l.rows + 1)).map(|q| base + q).collect());
    }
    let names: Vec<String> = layers.iter().map(|l| l.name.clone()).collect();
    let mut mesh = Mesh::new(nodes, tris, region, names)?;
    let mut all_start = Vec::new();
    let mut all_end = Vec::new();
    for (k, l) in layers.iter().enumerate() {
        let id = |i: usize, j: usize| ids[k][(i % ns) * (l.rows + 1) + j];
        mesh.add_edge_set(
            &format!("{}_inner", l.name),
            (0..segments).map(|i| [id(i, 0), id(i + 1, 0)]).collect(),
        )?;
        mesh.add_edge_set(
            &format!("{}_outer", l.name),
            (0..segments)
                .map(|i| [id(i, l.rows), id(i + 1, l.rows)])
                .collect(),
        )?;
        if !closed {
            let s: Vec<[usize; 2]> = (0..l.rows).map(|j| [id(0, j), id(0, j + 1)]).collect();
            let e: Vec<[usize; 2]> = (0..l.rows)
                .map(|j| [id(segments, j), id(segments, j + 1)])
                .collect();
            all_start.extend_from_slice(&s);
            all_end.extend_from_slice(&e);
            mesh.add_edge_set(&format!("{}_start", l.name), s)?;
            mesh.add_edge_set(&format!("{}_end", l.name), e)?;
        }
    }
    let first = &layers[0].name;
    let last = &layers[layers.len() - 1].name;
    let inner = mesh.edge_set(&format!("{first}_inner"))?.to_vec();
    let outer = mesh.edge_set(&format!("{last}_outer"))?.to_vec();
    mesh.add_edge_set("inner", inner)?;
    mesh.add_edge_set("outer", outer)?;
    if !closed {
        mesh.add_edge_set("start", all_start)?;
        mesh.add_edge_set("end", all_end)?;
        for name in ["start", "end"] {
            let n = mesh.edge_set_nodes(name)?;
            mesh.add_node_set(name, n)?;
        }
    }
    for w in layers.windows(2) {
        mesh.add_interface(
            &format!("{}_{}", w[0].name, w[1].name),
            &format!("{}_outer", w[0].name),
            &format!("{}_inner", w[1].name),
            None,
        )?;
    }
    Ok(mesh)
}
