//! Errors of [`crate::solve`].

use thiserror::Error;

/// Why an ICH solve was refused. Every variant names the offending source
/// (its index in the `sources` slice) and value.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum IchError {
    /// The source list is empty.
    #[error("no sources given")]
    NoSources,
    /// A vertex source is not a vertex of the mesh.
    #[error(
        "source {source_index}: vertex {vertex} out of range (the mesh has {vertices} input vertices)"
    )]
    VertexOutOfRange {
        /// Index of the source.
        source_index: usize,
        /// The vertex given.
        vertex: u32,
        /// Number of input vertices.
        vertices: usize,
    },
    /// A vertex source belongs to no face.
    #[error("source {source_index}: vertex {vertex} is not referenced by any face")]
    UnreferencedVertex {
        /// Index of the source.
        source_index: usize,
        /// The vertex given.
        vertex: u32,
    },
    /// An edge-point source names a half-edge that does not exist.
    #[error(
        "source {source_index}: half-edge {half_edge} out of range (the mesh has {half_edges})"
    )]
    HalfEdgeOutOfRange {
        /// Index of the source.
        source_index: usize,
        /// The half-edge given.
        half_edge: u32,
        /// Number of half-edges.
        half_edges: usize,
    },
    /// An edge-point parameter is not a number in `[0, 1]`.
    #[error("source {source_index}: edge parameter t = {t} is not in [0, 1]")]
    EdgeParameter {
        /// Index of the source.
        source_index: usize,
        /// The parameter given.
        t: f64,
    },
    /// A face-point source names a face that does not exist.
    #[error("source {source_index}: face {face} out of range (the mesh has {faces})")]
    FaceOutOfRange {
        /// Index of the source.
        source_index: usize,
        /// The face given.
        face: u32,
        /// Number of faces.
        faces: usize,
    },
    /// Barycentric coordinates not finite, negative, or not summing to 1.
    #[error(
        "source {source_index}: barycentric coordinates {barycentric:?} must be finite, non-negative and sum to 1"
    )]
    Barycentric {
        /// Index of the source.
        source_index: usize,
        /// The coordinates given.
        barycentric: [f64; 3],
    },
    /// The maximum distance is NaN or negative.
    #[error("maximum distance {0} must be a non-negative number")]
    MaxDistance(f64),
}
