//! Shared finite-element machinery of Tecon (placeholder while the workspace issue is built).
pub mod interface;
