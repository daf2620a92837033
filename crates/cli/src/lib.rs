//! `tecon-cli`: the commands of the `tecon` binary, usable as a library (the
//! end-to-end tests of the workspace call them directly).
//!
//! * [`vessel`]: the welded-vessel case end to end.
//! * [`mesh_cmd`]: mesh generation / import and VTK output.
//! * [`torsion`]: wavelet-BEM torsion of a section.
//! * [`plot`]: SVG/PNG line plots shared by the commands.

pub mod builtin;
pub mod case;
pub mod conductance;
pub mod driver;
pub mod duplex;
pub mod mesh_cmd;
pub mod plot;
pub mod setup;
pub mod torsion;
pub mod vessel;
pub mod writers;
