//! Procedural meshes (being built).
