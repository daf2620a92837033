//! VTK output: `.vtu` unstructured grids (XML, ASCII) and `.pvd` time collections.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::MeshError;

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
    let np = piece.points.len();
    let nc = piece.triangles.len() + piece.quads.len();
    for (name, f) in piece.point_data {
        if f.len() != np {
            return Err(format!(
                "point field '{name}' has {} entries for {np} points",
                f.len()
            ));
        }
    }
    for (name, f) in piece.cell_data {
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
    for p in piece.points {
        let _ = writeln!(s, "{:e} {:e} 0", p[0], p[1]);
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for t in piece.triangles {
        let _ = writeln!(s, "{} {} {}", t[0], t[1], t[2]);
    }
    for q in piece.quads {
        let _ = writeln!(s, "{} {} {} {}", q[0], q[1], q[2], q[3]);
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    let mut off = 0;
    for _ in piece.triangles {
        off += 3;
        let _ = writeln!(s, "{off}");
    }
    for _ in piece.quads {
        off += 4;
        let _ = writeln!(s, "{off}");
    }
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in piece.triangles {
        s.push_str("5\n");
    }
    for _ in piece.quads {
        s.push_str("9\n");
    }
    s.push_str("</DataArray>\n</Cells>\n");
    for (tag, data) in [
        ("PointData", piece.point_data),
        ("CellData", piece.cell_data),
    ] {
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
                let line: Vec<String> = row.iter().map(|x| format!("{x:e}")).collect();
                let _ = writeln!(s, "{}", line.join(" "));
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
