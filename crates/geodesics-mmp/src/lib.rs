//! Exact geodesic distances and shortest paths on triangle meshes by MMP:
//! the window propagation of Mitchell, Mount and Papadimitriou as
//! implemented by Surazhsky, Surazhsky, Kirsanov, Gortler and Hoppe, "Fast
//! exact and approximate geodesics on meshes" (SIGGRAPH 2005), with an
//! optional FWP schedule (Xu et al. 2015, "Fast wavefront propagation").
//!
//! - **Windows on edges.** Every window (a [`geodesics_window::Window`]:
//!   an interval of an edge lit by one pseudo-source) is kept on its edge
//!   for the whole run, in a list sorted along the edge; windows crossing
//!   the edge in both directions share the list.
//! - **Interval trimming.** A window inserted on an edge is compared with
//!   every window it overlaps: each point keeps the window that is shorter
//!   there, cut at the exact tie point of the two distance functions. A
//!   window may shrink, vanish, or split (Section 3.3 of the paper).
//! - **Schedule.** [`Schedule::PriorityQueue`] propagates windows in order
//!   of their smallest distance; [`Schedule::Fwp`] uses distance buckets of
//!   the mean edge length with a FIFO per bucket (any order inside one).
//!   Both are exact: a window propagated too early is trimmed later by the
//!   better one, which is propagated in turn.
//! - **Pseudo-sources** (as in `geodesics-vtp`): boundary vertices,
//!   interior vertices of angle sum above `2π − 1e-5`, pinch-vertex fan
//!   copies (sharing one distance), corners of zero-area faces, and the
//!   sources. When its distance is final a pseudo-source relaxes its
//!   neighbours along edges and puts one window on each edge opposite it;
//!   again whenever its distance drops by more than the tolerance.
//! - **Statistics** ([`Stats`]): `window_propagations` counts children
//!   computed (one per window propagated into a face, per far edge it
//!   reaches), `windows_created` every window made (seeds, pseudo-source
//!   windows, children's surviving pieces, copies made by splitting),
//!   `peak_live_windows` the windows kept at the end (MMP frees none),
//!   `peak_window_bytes` the bytes allocated for them and the per-edge
//!   lists, `vertex_pops` and `pseudo_source_emissions` the pseudo-source
//!   events; only `total_seconds` is timed (no phase split).
//! - **Paths.** [`run`] keeps the windows; [`MmpField::path_to_vertex`] and
//!   [`MmpField::path_to_point`] backtrace from a target to its nearest
//!   source, straight across faces, bending only at pseudo-source vertices.
//!
//! # Example
//!
//! ```
//! use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
//! use geodesics_mmp::{MmpOptions, Schedule, SurfacePoint, run, solve};
//! use geodesics_window::Source;
//! use glam::DVec3;
//!
//! // A unit square in the plane, split along its diagonal.
//! let soup = IndexedTriangles {
//!     positions: vec![
//!         DVec3::new(0.0, 0.0, 0.0),
//!         DVec3::new(1.0, 0.0, 0.0),
//!         DVec3::new(1.0, 1.0, 0.0),
//!         DVec3::new(0.0, 1.0, 0.0),
//!     ],
//!     triangles: vec![[0, 1, 2], [0, 2, 3]],
//! };
//! let mesh = Mesh::build(soup, &BuildOptions::default()).unwrap();
//! let (field, stats) = solve(&mesh, &[Source::Vertex(1)], &MmpOptions::default()).unwrap();
//! assert!((field.distance[3] - 2f64.sqrt()).abs() < 1e-15);
//! assert!(stats.windows_created > 0);
//!
//! // FWP scheduling gives the same distances; paths come from `run`.
//! let options = MmpOptions { schedule: Schedule::Fwp, ..MmpOptions::default() };
//! let mmp = run(&mesh, &[Source::Vertex(1)], &options).unwrap();
//! let path = mmp.path_to_vertex(3).unwrap();
//! assert_eq!(path.points.first(), Some(&SurfacePoint::Vertex(1)));
//! assert_eq!(path.points.last(), Some(&SurfacePoint::Vertex(3)));
//! // It crosses the diagonal in its middle.
//! assert_eq!(path.points.len(), 3);
//! assert!((path.length - 2f64.sqrt()).abs() < 1e-15);
//! ```

// Negated comparisons (`!(a < b)`) are deliberate: a NaN fails them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod error;
mod path;
mod solver;
mod trim;

pub use error::MmpError;
pub use geodesics_window::{DistanceField, GeodesicPath, Progress, Source, Stats, SurfacePoint};
pub use path::MmpField;

use geodesics_mesh::Mesh;

/// The order windows are propagated in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Schedule {
    /// A priority queue keyed on each window's smallest distance (MMP).
    #[default]
    PriorityQueue,
    /// Distance buckets of the mean edge length, a FIFO per bucket
    /// (FWP-MMP, Xu et al. 2015).
    Fwp,
}

/// Options of [`solve`] and [`run`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MmpOptions {
    /// Window schedule.
    pub schedule: Schedule,
    /// Stop the wavefront beyond this distance; vertices farther away are
    /// reported unreachable (`f64::INFINITY`).
    pub max_distance: Option<f64>,
    /// Where the solve reports how far its wavefront has come (see
    /// [`Progress`]); the default reports nowhere.
    pub progress: Progress,
}

/// Computes exact geodesic distances from `sources` to every vertex of
/// `mesh`: per input vertex, the distance to the nearest source and which
/// source that is, plus statistics of the run.
///
/// Never panics on input: an empty source list, an index out of range, an
/// unreferenced source vertex, an edge parameter outside `[0, 1]`,
/// barycentric coordinates that are not finite, negative or do not sum to
/// 1, or a negative maximum distance are [`MmpError`]s.
pub fn solve(
    mesh: &Mesh,
    sources: &[Source],
    options: &MmpOptions,
) -> Result<(DistanceField, Stats), MmpError> {
    run(mesh, sources, options).map(MmpField::into_parts)
}

/// [`solve`], keeping every window so that shortest paths can be traced
/// afterwards ([`MmpField::path_to_vertex`], [`MmpField::path_to_point`]).
pub fn run<'a>(
    mesh: &'a Mesh,
    sources: &[Source],
    options: &MmpOptions,
) -> Result<MmpField<'a>, MmpError> {
    let (field, solved) = solver::solve(mesh, sources, options)?;
    Ok(MmpField {
        mesh,
        sources: sources.to_vec(),
        field,
        solved,
        max_distance: options.max_distance,
    })
}
