//! Exact geodesic distances on triangle meshes by ICH: Chen and Han's
//! window-tree propagation as improved by Xin and Wang, "Improving Chen and
//! Han's algorithm on the discrete geodesic problem" (ACM TOG 2009), with
//! the FWP schedule of Xu et al., "Fast wavefront propagation (FWP) for
//! computing exact geodesic distances on meshes" (TVCG 2015) as an option.
//!
//! Every window (from `geodesics-window`) waits in one queue until it is
//! propagated through the face beyond its edge, then it is freed: no window
//! lists are kept on edges, so memory follows the queue. Propagating a
//! window lights the face's opposite vertex and makes at most two children,
//! pruned by two rules:
//!
//! - **one angle one split** (Chen and Han): per face corner, only the window
//!   giving the shortest path to it so far may split there into two
//!   children; a window reaching it longer by more than the tolerance loses
//!   the rays that cross the better path (Cases 7–9 of Qin et al. 2016,
//!   [`geodesics_window::prune::one_angle_two_sides`]);
//! - **the vertex filter** (Xin and Wang): a child is dropped when a corner
//!   of the face it was made in, at its current distance, gives a shorter
//!   path to all of it ([`geodesics_window::prune::vertex_check`]); the
//!   check is repeated when the window leaves the queue, with fresher
//!   distances.
//!
//! The schedule ([`Schedule`]) decides the order: ICH pops the window with
//! the smallest distance first (a binary heap); FWP-CH takes buckets of
//! width about the mean edge length in order, first in first out inside a
//! bucket. Both rules are sound in any order (they only compare lengths of
//! real paths), and pseudo-sources re-emit when their distance drops, so
//! both schedules are exact.
//!
//! Pseudo-sources: boundary vertices, interior vertices whose angle sum
//! exceeds `2π − 1e-5` (saddles and flat vertices), the fan copies of pinch
//! vertices (they share one distance, so geodesics pass through the pinch;
//! Xin's program aborts there), the corners of zero-area faces, and the
//! sources. Zero-area faces are handled as in `geodesics-vtp`. Every
//! comparison goes through [`geodesics_window::Tolerance`] (Xin's program
//! uses fixed `1e-6` margins and ends up to a few `1e-6` too long).
//!
//! # Example
//!
//! ```
//! use geodesics_ich::{IchOptions, Schedule, solve};
//! use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
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
//! for schedule in [Schedule::PriorityQueue, Schedule::Fwp] {
//!     let options = IchOptions { schedule, ..IchOptions::default() };
//!     let (field, stats) = solve(&mesh, &[Source::Vertex(1)], &options).unwrap();
//!     assert_eq!(field.distance[1], 0.0);
//!     assert!((field.distance[3] - 2f64.sqrt()).abs() < 1e-15);
//!     assert_eq!(field.nearest_source, vec![0; 4]);
//!     assert!(stats.windows_created > 0);
//! }
//! ```

// Negated comparisons (`!(a < b)`) are deliberate: a NaN fails them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod error;
mod queue;
mod rules;
mod solver;

pub use error::IchError;
pub use geodesics_window::{DistanceField, Progress, Source, Stats};

use geodesics_mesh::Mesh;

/// In which order windows are propagated. Both are exact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Schedule {
    /// ICH (Xin and Wang 2009): a priority queue keyed on each window's
    /// smallest distance.
    #[default]
    PriorityQueue,
    /// FWP-CH (Xu et al. 2015): buckets of width the mean edge length,
    /// taken in order, first in first out inside a bucket.
    Fwp,
}

/// Options of [`solve`]. `Default` is ICH with its priority queue and no
/// distance limit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IchOptions {
    /// The schedule.
    pub schedule: Schedule,
    /// Stop the wavefront beyond this distance; vertices farther away are
    /// reported unreachable (`f64::INFINITY`).
    pub max_distance: Option<f64>,
    /// Where the solve reports how far its wavefront has come (see
    /// [`Progress`]); the default reports nowhere.
    pub progress: Progress,
}

impl IchOptions {
    /// ICH as in the paper: the priority queue.
    pub fn ich() -> IchOptions {
        IchOptions::default()
    }

    /// FWP-CH: ICH's rules with FWP's buckets.
    pub fn fwp_ch() -> IchOptions {
        IchOptions {
            schedule: Schedule::Fwp,
            ..IchOptions::default()
        }
    }
}

/// Computes exact geodesic distances from `sources` to every vertex of
/// `mesh`: per input vertex, the distance to the nearest source and which
/// source that is, plus statistics of the run (window propagations counted
/// as the papers count them, one per child computed; peak live windows =
/// the most windows waiting in the queue at once; `total_seconds`; the
/// per-phase times are not measured and stay 0).
///
/// Never panics on input: an empty source list, an index out of range, an
/// unreferenced source vertex, an edge parameter outside `[0, 1]`,
/// barycentric coordinates that are not finite, negative or do not sum to 1,
/// or a negative maximum distance are [`IchError`]s.
pub fn solve(
    mesh: &Mesh,
    sources: &[Source],
    options: &IchOptions,
) -> Result<(DistanceField, Stats), IchError> {
    solver::solve(mesh, sources, options)
}

#[cfg(test)]
mod tests;
