//! Geometry of 4-node interface elements (filled by the contact issue).
