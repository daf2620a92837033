//! Helpers shared by the thermal test files.
#![allow(dead_code)]

use tecon_mesh::Mesh;

/// Least-squares slope of log(e) against log(h).
pub fn fitted_slope(h: &[f64], e: &[f64]) -> f64 {
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// A copy of `mesh` with every node not on an edge set moved by a
/// deterministic pseudo-random offset of up to `amount` × `h` in x and y.
pub fn distorted(mesh: &Mesh, h: f64, amount: f64) -> Mesh {
    let mut on_edge = vec![false; mesh.n_nodes()];
    for edges in mesh.edge_sets().values() {
        for e in edges {
            on_edge[e[0]] = true;
            on_edge[e[1]] = true;
        }
    }
    let mut nodes = mesh.nodes().to_vec();
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for (i, p) in nodes.iter_mut().enumerate() {
        let (dx, dy) = (rnd(), rnd());
        if !on_edge[i] {
            p[0] += 2.0 * amount * h * dx;
            p[1] += 2.0 * amount * h * dy;
        }
    }
    let mut out = Mesh::new(
        nodes,
        mesh.triangles().to_vec(),
        mesh.element_regions().to_vec(),
        mesh.region_names().to_vec(),
    )
    .expect("distorted mesh is valid");
    for (name, edges) in mesh.edge_sets() {
        out.add_edge_set(name, edges.clone()).expect("edge set");
    }
    for (name, nodes) in mesh.node_sets() {
        out.add_node_set(name, nodes.clone()).expect("node set");
    }
    for (name, itf) in mesh.interfaces() {
        out.add_interface(name, &itf.bottom_set, &itf.top_set, None)
            .expect("interface");
    }
    out
}

/// Two blocks [0, xm] × [0, ly] and [xm, lx] × [0, ly] with their own nodes
/// on x = xm, joined by interface `mid` (bottom = left block).
/// Regions `left`, `right`; edge sets `west`, `east`, `south`, `north`,
/// `left_mid`, `right_mid`.
pub fn two_blocks(lx: f64, xm: f64, ly: f64, nx: usize, ny: usize) -> Mesh {
    let mut nodes = Vec::new();
    let mut tris = Vec::new();
    let mut region = Vec::new();
    let mut ids = Vec::new();
    for (b, (x0, x1)) in [(0.0, xm), (xm, lx)].into_iter().enumerate() {
        let base = nodes.len();
        for j in 0..=ny {
            for i in 0..=nx {
                nodes.push([
                    x0 + (x1 - x0) * i as f64 / nx as f64,
                    ly * j as f64 / ny as f64,
                ]);
            }
        }
        let id = move |i: usize, j: usize| base + j * (nx + 1) + i;
        for j in 0..ny {
            for i in 0..nx {
                let (a, bb, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                if (i + j) % 2 == 0 {
                    tris.push([a, bb, c]);
                    tris.push([a, c, d]);
                } else {
                    tris.push([a, bb, d]);
                    tris.push([bb, c, d]);
                }
                region.push(b);
                region.push(b);
            }
        }
        ids.push(id);
    }
    let mut mesh =
        Mesh::new(nodes, tris, region, vec!["left".into(), "right".into()]).expect("two blocks");
    let (l, r) = (ids[0], ids[1]);
    let col = |f: &dyn Fn(usize, usize) -> usize, i: usize| -> Vec<[usize; 2]> {
        (0..ny).map(|j| [f(i, j), f(i, j + 1)]).collect()
    };
    let row = |f: &dyn Fn(usize, usize) -> usize, j: usize| -> Vec<[usize; 2]> {
        (0..nx).map(|i| [f(i, j), f(i + 1, j)]).collect()
    };
    mesh.add_edge_set("west", col(&l, 0)).unwrap();
    mesh.add_edge_set("left_mid", col(&l, nx)).unwrap();
    mesh.add_edge_set("right_mid", col(&r, 0)).unwrap();
    mesh.add_edge_set("east", col(&r, nx)).unwrap();
    let mut south = row(&l, 0);
    south.extend(row(&r, 0));
    let mut north = row(&l, ny);
    north.extend(row(&r, ny));
    mesh.add_edge_set("south", south).unwrap();
    mesh.add_edge_set("north", north).unwrap();
    mesh.add_interface("mid", "left_mid", "right_mid", None)
        .unwrap();
    mesh
}
