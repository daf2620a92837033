//! VTK output: `.vtu` unstructured grids (XML, ASCII) and `.pvd` time collections.
//!
//! [`write_mesh_vtu`] writes a [`Mesh`] of either order with named point and
//! cell data: P1 triangles as VTK_TRIANGLE (5), P2 triangles as
//! VTK_QUADRATIC_TRIANGLE (22, node order as [`Mesh::triangles6`]); interface
//! elements after the triangles, P1 as VTK_QUAD (9, nodes 1, 2, 3, 4) and P2
//! as VTK_QUADRATIC_LINEAR_QUAD (30: nodes 1, 2, 3, 4, then the mid nodes of
//! 1–2 and 3–4), quadratic along the joint and linear across it, so the
//! zero-thickness cell has no mid nodes on its two zero-length sides and
//! opens into a curved strip when ParaView warps it by the displacement.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::MeshError;
use crate::mesh::Mesh;

/// VTK cell type numbers.
pub mod cell_type {
    /// 3-node triangle.
    pub const TRIANGLE: u8 = 5;
    /// 4-node quadrilateral.
    pub const QUAD: u8 = 9;
    /// 6-node triangle.
    pub const QUADRATIC_TRIANGLE: u8 = 22;
    /// 6-node quadrilateral, quadratic along edges 0–1 and 2–3.
    pub const QUADRATIC_LINEAR_QUAD: u8 = 30;
}

/// A mesh with named data, for [`write_mesh_vtu`].
#[derive(Debug, Clone, Copy)]
pub struct MeshVtu<'a> {
    /// The mesh (P1 or P2); every node is written, mid nodes included.
    pub mesh: &'a Mesh,
    /// Write the interface elements as cells after the triangles (all
    /// interfaces, in name order, each in its element order).
    pub interfaces: bool,
    /// Named point fields, one entry per node.
    pub point_data: &'a [(&'a str, Field<'a>)],
    /// Named cell fields, one entry per triangle, then (with `interfaces`)
    /// one per interface element.
    pub cell_data: &'a [(&'a str, Field<'a>)],
}

impl MeshVtu<'_> {
    /// Number of cells written: triangles, then interface elements.
    pub fn n_cells(&self) -> usize {
        self.mesh.n_triangles()
            + if self.interfaces {
                self.mesh
                    .interfaces()
                    .values()
                    .map(|i| i.elements.len())
                    .sum()
            } else {
                0
            }
    }
}

/// Writes a mesh of either order with its data as a `.vtu` file.
pub fn write_mesh_vtu(path: impl AsRef<Path>, vtu: &MeshVtu<'_>) -> Result<(), MeshError> {
    let path = path.as_ref();
    let text = mesh_vtu_string(vtu).map_err(|message| MeshError::Io {
        path: path.to_path_buf(),
        message,
    })?;
    std::fs::write(path, text).map_err(|e| MeshError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// The XML text of [`write_mesh_vtu`]; errors name a field whose length is wrong.
pub fn mesh_vtu_string(vtu: &MeshVtu<'_>) -> Result<String, String> {
    let m = vtu.mesh;
    let mut cells: Vec<(u8, Vec<usize>)> = Vec::with_capacity(vtu.n_cells());
    match m.triangles6() {
        Some(t6) => cells.extend(
            t6.iter()
                .map(|t| (cell_type::QUADRATIC_TRIANGLE, t.to_vec())),
        ),
        None => cells.extend(
            m.triangles()
                .iter()
                .map(|t| (cell_type::TRIANGLE, t.to_vec())),
        ),
    }
    if vtu.interfaces {
        for itf in m.interfaces().values() {
            for (k, e) in itf.elements.iter().enumerate() {
                cells.push(match itf.mid_nodes.get(k) {
                    Some(&[mb, mt]) => (
                        cell_type::QUADRATIC_LINEAR_QUAD,
                        vec![e[0], e[1], e[2], e[3], mb, mt],
                    ),
                    None => (cell_type::QUAD, e.to_vec()),
                });
            }
        }
    }
    grid_string(m.nodes(), &cells, vtu.point_data, vtu.cell_data)
}

/// Writes any cells (VTK type, point indices) over `points` with their data
/// as a `.vtu` file, e.g. a mesh whose nodes are duplicated per region so
/// that a point field may jump across a region border.
pub fn write_cells_vtu(
    path: impl AsRef<Path>,
    points: &[[f64; 2]],
    cells: &[(u8, Vec<usize>)],
    point_data: &[(&str, Field<'_>)],
    cell_data: &[(&str, Field<'_>)],
) -> Result<(), MeshError> {
    let path = path.as_ref();
    let text =
        grid_string(points, cells, point_data, cell_data).map_err(|message| MeshError::Io {
            path: path.to_path_buf(),
            message,
        })?;
    std::fs::write(path, text).map_err(|e| MeshError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Data attached to points or cells.
#[derive(Debug, Clone, Copy)]
pub enum Field<'a> {
    /// One value per point/cell.
    Scalars(&'a [f64]),
    /// Two components per point/cell (written with z = 0).
    Vectors(&'a [[f64; 2]]),
    /// Any number of components per point/cell, stored row by row.
    Components {
        /// Components per entry.
        n: usize,
        /// Values, `n` per entry.
        values: &'a [f64],
    },
}

impl Field<'_> {
    fn len(&self) -> usize {
        match self {
            Field::Scalars(v) => v.len(),
            Field::Vectors(v) => v.len(),
            Field::Components { n, values } => values.len() / (*n).max(1),
        }
    }
}

/// One unstructured-grid piece: triangles and (interface) quadrilaterals.
#[derive(Debug, Clone, Copy)]
pub struct VtuPiece<'a> {
    /// Point coordinates.
    pub points: &'a [[f64; 2]],
    /// Triangles (VTK_TRIANGLE).
    pub triangles: &'a [[usize; 3]],
    /// Quadrilaterals (VTK_QUAD), e.g. interface elements; cell data lists
    /// triangles first, then quads.
    pub quads: &'a [[usize; 4]],
    /// Named point fields.
    pub point_data: &'a [(&'a str, Field<'a>)],
    /// Named cell fields.
    pub cell_data: &'a [(&'a str, Field<'a>)],
}

/// Writes a `.vtu` file readable by ParaView.
pub fn write_vtu(path: impl AsRef<Path>, piece: &VtuPiece<'_>) -> Result<(), MeshError> {
    let path = path.as_ref();
    let text = vtu_string(piece).map_err(|message| MeshError::Io {
        path: path.to_path_buf(),
        message,
    })?;
    std::fs::write(path, text).map_err(|e| MeshError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// The XML text of a `.vtu` file; errors name a field whose length is wrong.
pub fn vtu_string(piece: &VtuPiece<'_>) -> Result<String, String> {
    let cells: Vec<(u8, Vec<usize>)> = piece
        .triangles
        .iter()
        .map(|t| (cell_type::TRIANGLE, t.to_vec()))
        .chain(piece.quads.iter().map(|q| (cell_type::QUAD, q.to_vec())))
        .collect();
    grid_string(piece.points, &cells, piece.point_data, piece.cell_data)
}

fn grid_string(
    points: &[[f64; 2]],
    cells: &[(u8, Vec<usize>)],
    point_data: &[(&str, Field<'_>)],
    cell_data: &[(&str, Field<'_>)],
) -> Result<String, String> {
    let np = points.len();
    let nc = cells.len();
    for (name, f) in point_data {
        if f.len() != np {
            return Err(format!(
                "point field '{name}' has {} entries for {np} points",
                f.len()
            ));
        }
    }
    for (name, f) in cell_data {
        if f.len() != nc {
            return Err(format!(
                "cell field '{name}' has {} entries for {nc} cells",
                f.len()
            ));
        }
    }
    let mut s = String::with_capacity(64 * (np + nc) + 1024);
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n");
    let _ = writeln!(s, "<Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{nc}\">");
    s.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in points {
        let _ = writeln!(s, "{:e} {:e} 0", p[0], p[1]);
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for (_, c) in cells {
        for (i, v) in c.iter().enumerate() {
            let _ = write!(s, "{}{v}", if i == 0 { "" } else { " " });
        }
        s.push('\n');
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    let mut off = 0;
    for (_, c) in cells {
        off += c.len();
        let _ = writeln!(s, "{off}");
    }
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (t, _) in cells {
        let _ = writeln!(s, "{t}");
    }
    s.push_str("</DataArray>\n</Cells>\n");
    for (tag, data) in [("PointData", point_data), ("CellData", cell_data)] {
        let _ = writeln!(s, "<{tag}>");
        for (name, f) in data {
            write_field(&mut s, name, f);
        }
        let _ = writeln!(s, "</{tag}>");
    }
    s.push_str("</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    Ok(s)
}

fn write_field(s: &mut String, name: &str, f: &Field<'_>) {
    let name = xml_escape(name);
    match f {
        Field::Scalars(v) => {
            let _ = writeln!(
                s,
                "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
            );
            for x in *v {
                let _ = writeln!(s, "{x:e}");
            }
        }
        Field::Vectors(v) => {
            let _ = writeln!(
                s,
                "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" format=\"ascii\">"
            );
            for x in *v {
                let _ = writeln!(s, "{:e} {:e} 0", x[0], x[1]);
            }
        }
        Field::Components { n, values } => {
            let _ = writeln!(
                s,
                "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{n}\" format=\"ascii\">"
            );
            for row in values.chunks(*n) {
                for (i, x) in row.iter().enumerate() {
                    let _ = write!(s, "{}{x:e}", if i == 0 { "" } else { " " });
                }
                s.push('\n');
            }
        }
    }
    s.push_str("</DataArray>\n");
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Writes a `.pvd` collection of (time, file) entries; file names are
/// written relative to the `.pvd`'s folder as given.
pub fn write_pvd(path: impl AsRef<Path>, entries: &[(f64, String)]) -> Result<(), MeshError> {
    let path = path.as_ref();
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n",
    );
    for (t, f) in entries {
        let _ = writeln!(
            s,
            "<DataSet timestep=\"{t:e}\" part=\"0\" file=\"{}\"/>",
            xml_escape(f)
        );
    }
    s.push_str("</Collection>\n</VTKFile>\n");
    std::fs::write(path, s).map_err(|e| MeshError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}
