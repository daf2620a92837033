//! `tecon-mesh`: 2D meshes of linear (P1) or quadratic (P2) triangles with
//! named regions, edge sets, node sets and interfaces; the welded-vessel
//! generator; Gmsh MSH 4.1 import; VTK export.
//!
//! # Glossary
//! * node, triangle: 0-based ids; triangles are stored counter-clockwise.
//! * order: 1 (3-node triangles) or 2 (6-node triangles: corners 0, 1, 2,
//!   then the mid nodes of edges (0,1), (1,2), (2,0)).
//! * mid node: the third node of an edge of a P2 mesh, on a circular [`Arc`]
//!   for curved boundary edges, else at the chord midpoint.
//! * ξ, η: reference coordinates of the triangle (0,0), (1,0), (0,1); J the
//!   Jacobian of the isoparametric map.
//! * region: a named set of triangles (one region per triangle), e.g. `core`.
//! * body: a connected set of triangles (through shared nodes); bodies are
//!   named after the regions they contain (`layer+weld`).
//! * edge set: named edges `[a, b]`, boundary edges oriented counter-clockwise
//!   (body on the left, outward normal on the right).
//! * interface: 4-node elements `[1, 2, 3, 4]` between two bodies, 1–2 on the
//!   bottom face, 4 facing 1, 3 facing 2, the top body on the left of 1→2;
//!   on a P2 mesh also the facing mid nodes `[mid of 1–2, mid of 4–3]`.
//! * pairing tolerance: how far facing interface nodes may be apart, by
//!   default relative to the local element size.
//! * θ: polar angle about the origin (vessel: θ = 0 at the weld centre).

mod checks;
mod error;
pub mod generators;
mod interface;
mod mesh;
pub mod msh;
pub mod multilayer;
pub mod quadratic;
pub mod vessel;
pub mod vtk;

pub use error::{GmshRefs, GmshTags, MeshError};
pub use generators::{
    RingLayer, layered_annulus, layered_annulus_of_order, rectangle, rectangle_of_order,
};
pub use interface::{DEFAULT_PAIRING_TOLERANCE, Interface, PairingTolerance};
pub use mesh::{Body, COINCIDENCE_TOLERANCE, Mesh, MeshNotice, Point, signed_area};
pub use msh::read_msh;
pub use multilayer::{
    MultilayerGeometry, MultilayerMeshSpec, WeldedLayer, multilayer_stage_mesh,
    multilayer_station_angles, multilayer_vessel_mesh,
};
pub use quadratic::Arc;
pub use vessel::{
    VesselGeometry, VesselMeshSpec, available_memory_bytes, check_memory, vessel_mesh,
};
