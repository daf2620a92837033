//! Tecon facade: re-exports the workspace crates.
pub use tecon_contact as contact;
pub use tecon_elastic as elastic;
pub use tecon_fem as fem;
pub use tecon_mesh as mesh;
pub use tecon_thermal as thermal;
pub use tecon_wavelet_bem as wavelet_bem;
