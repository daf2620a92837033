//! `tecon-cli`: the commands of the `tecon` binary, usable as a library (the
//! end-to-end tests of the workspace call them directly).
//!
//! * [`vessel`]: the welded-vessel case end to end; [`accuracy`]: the quantities
//!   its accuracy is judged on, at fixed points, and the convergence arithmetic.
//! * [`multilayer`]: `tecon vessel --layers N`, the staged multilayer vessel;
//!   [`case_stages`]: the same from a case file (`[multilayer]`, `[[stage]]`).
//! * [`mesh_cmd`]: mesh generation / import and VTK output.
//! * [`torsion`]: wavelet-BEM torsion of a section.
//! * [`plot`]: SVG/PNG figures (panels, log axes, clipped lines) shared by the commands.
//! * [`front`]: what `tecon vessel` adds: figures, yield check, report.txt, timing.json.
//! * [`figures`]: the vessel's figures and interface tables from plain data.
//! * [`report_html`]: the self-contained `report.html` of an output folder.
//! * [`outdir`]: output folders a run owns (writable check, manifest, stale files).
//! * [`yield_check`]: von Mises against the yield stress, per region.
//! * [`driver`]: the one analysis driver; [`coupling_loop`]: its staggered
//!   two-way thermoelastic coupling.
//! * [`memory`]: memory estimates checked before large meshes are built.
//! * [`probes`]: probe points checked against the mesh.
//! * [`cmdline`]: argument checks before computing; quiet end on a closed pipe.

pub mod accuracy;
pub mod builtin;
pub mod case;
pub mod case_stages;
pub mod cmdline;
pub mod conductance;
pub mod coupling_loop;
pub mod driver;
pub mod duplex;
pub mod figures;
pub mod front;
pub mod interface_table;
pub mod memory;
pub mod mesh_cmd;
pub mod multilayer;
pub mod multilayer_out;
pub mod outdir;
pub mod plot;
pub mod probes;
pub mod report_html;
pub mod setup;
pub mod torsion;
pub mod vessel;
pub mod writers;
pub mod yield_check;
