//! Placeholder: filled by the issue that builds this part.
fn main() {}
