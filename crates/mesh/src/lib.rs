//! `tecon-mesh`: 2D meshes of linear triangles with named regions, edge sets,
//! node sets and interfaces; the welded-vessel generator; Gmsh MSH 4.1 import;
//! VTK export.
//!
//! # Glossary
//! * node, triangle: 0-based ids; triangles are stored counter-clockwise.
//! * region: a named set of triangles (one region per triangle), e.g. `core`.
//! * body: a connected set of triangles (through shared nodes); bodies are
//!   named after the regions they contain (`layer+weld`).
//! * edge set: named edges `[a, b]`, boundary edges oriented counter-clockwise
//!   (body on the left, outward normal on the right).
//! * interface: 4-node elements `[1, 2, 3, 4]` between two bodies, 1–2 on the
//!   bottom face, 4 facing 1, 3 facing 2, the top body on the left of 1→2.
//! * θ: polar angle about the origin (vessel: θ = 0 at the weld centre).

mod error;
pub mod generators;
mod mesh;
pub mod msh;
pub mod vessel;
pub mod vtk;

pub use error::MeshError;
pub use generators::{RingLayer, layered_annulus, rectangle};
pub use mesh::{Body, COINCIDENCE_TOLERANCE, Interface, Mesh, MeshNotice, Point, signed_area};
pub use msh::read_msh;
pub use vessel::{VesselGeometry, VesselMeshSpec, vessel_mesh};
