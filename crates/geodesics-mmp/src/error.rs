//! Errors of [`crate::solve`], [`crate::run`] and the path queries.

use geodesics_window::SourceError;
use thiserror::Error;

/// Why an MMP solve or a path query was refused. Source errors name the
/// offending source (its index in the `sources` slice) and value, as VTP's.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum MmpError {
    /// A source, or the distance limit, was refused.
    #[error(transparent)]
    Source(#[from] SourceError),
    /// A path was asked to a vertex that does not exist.
    #[error("path target: vertex {vertex} out of range (the mesh has {vertices} input vertices)")]
    TargetVertexOutOfRange {
        /// The vertex given.
        vertex: u32,
        /// Number of input vertices.
        vertices: usize,
    },
    /// A path was asked to a point of a face that does not exist.
    #[error("path target: face {face} out of range (the mesh has {faces})")]
    TargetFaceOutOfRange {
        /// The face given.
        face: u32,
        /// Number of faces.
        faces: usize,
    },
    /// A path target's barycentric coordinates are not finite,
    /// non-negative and summing to 1.
    #[error("path target: barycentric coordinates {0:?} must be finite, non-negative and sum to 1")]
    TargetBarycentric([f64; 3]),
    /// No source reaches the target (another component, an unreferenced
    /// vertex, or beyond the maximum distance).
    #[error("path target is not reached by any source")]
    Unreachable,
    /// The backtrace did not end at a source within the step limit (a bug:
    /// please report it with the mesh and the sources).
    #[error("backtrace did not reach a source after {0} steps")]
    Backtrace(usize),
}
