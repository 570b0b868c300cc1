//! Mesh readers and field writers (being built).
