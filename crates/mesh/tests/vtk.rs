//! The one VTK writer for meshes of either order.
//!
//! Goal: a P1 mesh is written as VTK_TRIANGLE (5) + VTK_QUAD (9) interface
//! cells, a P2 mesh as VTK_QUADRATIC_TRIANGLE (22) + VTK_QUADRATIC_LINEAR_QUAD
//! (30) interface cells with the node order ParaView expects; point data
//! covers mid nodes; wrong field lengths are named.

use std::f64::consts::PI;

use tecon_mesh::vtk::{Field, MeshVtu, mesh_vtu_string, write_mesh_vtu};
use tecon_mesh::{Mesh, RingLayer, layered_annulus_of_order};

fn two_rings(order: usize) -> Mesh {
    let layers = [
        RingLayer {
            name: "core".into(),
            r_in: 1.0,
            r_out: 1.2,
            rows: 1,
        },
        RingLayer {
            name: "layer".into(),
            r_in: 1.2,
            r_out: 1.3,
            rows: 1,
        },
    ];
    layered_annulus_of_order(&layers, 0.0, 0.5 * PI, 4, order).unwrap()
}

/// The lines of the `<DataArray … Name="name" …>` block.
fn array<'a>(text: &'a str, name: &str) -> Vec<&'a str> {
    let start = text.find(&format!("Name=\"{name}\"")).unwrap();
    let body = &text[start..];
    let body = &body[body.find('\n').unwrap() + 1..];
    body[..body.find("</DataArray>").unwrap()].lines().collect()
}

#[test]
fn p2_mesh_is_written_with_quadratic_cells() {
    let m = two_rings(2);
    let n_tri = m.n_triangles();
    let itf = m.interface("core_layer").unwrap();
    let n_itf = itf.elements.len();
    let temp: Vec<f64> = m.nodes().iter().map(|p| p[0].hypot(p[1])).collect();
    let u: Vec<[f64; 2]> = m.nodes().to_vec();
    let id: Vec<f64> = (0..n_tri + n_itf).map(|k| k as f64).collect();
    let vtu = MeshVtu {
        mesh: &m,
        interfaces: true,
        point_data: &[("T", Field::Scalars(&temp)), ("u", Field::Vectors(&u))],
        cell_data: &[("id", Field::Scalars(&id))],
    };
    assert_eq!(vtu.n_cells(), n_tri + n_itf);
    let text = mesh_vtu_string(&vtu).unwrap();
    assert!(text.contains(&format!(
        "NumberOfPoints=\"{}\" NumberOfCells=\"{}\"",
        m.n_nodes(),
        n_tri + n_itf
    )));
    let types = array(&text, "types");
    assert_eq!(types.iter().filter(|&&t| t == "22").count(), n_tri);
    assert_eq!(types.iter().filter(|&&t| t == "30").count(), n_itf);
    assert_eq!(types.len(), n_tri + n_itf);
    let conn = array(&text, "connectivity");
    let t0 = m.triangles6().unwrap()[0];
    assert_eq!(conn[0], t0.map(|v| v.to_string()).join(" "));
    let e0 = itf.elements[0];
    let [mb, mt] = itf.mid_nodes[0];
    assert_eq!(
        conn[n_tri],
        format!("{} {} {} {} {mb} {mt}", e0[0], e0[1], e0[2], e0[3])
    );
    let offsets = array(&text, "offsets");
    assert_eq!(offsets.last().unwrap(), &(6 * (n_tri + n_itf)).to_string());
    assert_eq!(array(&text, "T").len(), m.n_nodes());
    // without interfaces the cell data has one entry per triangle
    let short: Vec<f64> = vec![0.0; n_tri];
    let e = mesh_vtu_string(&MeshVtu {
        cell_data: &[("id", Field::Scalars(&short))],
        ..vtu
    })
    .unwrap_err();
    assert!(
        e.contains(&format!(
            "cell field 'id' has {n_tri} entries for {} cells",
            n_tri + n_itf
        )),
        "{e}"
    );
    let ok = mesh_vtu_string(&MeshVtu {
        interfaces: false,
        cell_data: &[("id", Field::Scalars(&short))],
        ..vtu
    })
    .unwrap();
    assert_eq!(array(&ok, "types").len(), n_tri);
    let dir = std::env::temp_dir().join(format!("tecon-vtk-p2-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    write_mesh_vtu(dir.join("p2.vtu"), &vtu).unwrap();
    assert_eq!(std::fs::read_to_string(dir.join("p2.vtu")).unwrap(), text);
    let e = write_mesh_vtu(dir.join("missing/p2.vtu"), &vtu).unwrap_err();
    assert!(e.to_string().contains("p2.vtu"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn p1_mesh_is_written_with_linear_cells() {
    let m = two_rings(1);
    let n_tri = m.n_triangles();
    let n_itf = m.interface("core_layer").unwrap().elements.len();
    let text = mesh_vtu_string(&MeshVtu {
        mesh: &m,
        interfaces: true,
        point_data: &[],
        cell_data: &[],
    })
    .unwrap();
    let types = array(&text, "types");
    assert_eq!(types.iter().filter(|&&t| t == "5").count(), n_tri);
    assert_eq!(types.iter().filter(|&&t| t == "9").count(), n_itf);
    let offsets = array(&text, "offsets");
    assert_eq!(
        offsets.last().unwrap(),
        &(3 * n_tri + 4 * n_itf).to_string()
    );
}
