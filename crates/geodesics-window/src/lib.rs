//! Windows and their geometry, shared by every exact geodesic solver of the
//! workspace (MMP, ICH, VTP and its variants).
//!
//! - [`Window`]: an interval of a half-edge lit by one pseudo-source, in the
//!   half-edge's 2D frame (tail at the origin, edge along +x, the face to
//!   cross above, the pseudo-source below).
//! - [`EndedWindow`]: a window with its end distances cached, the form
//!   solvers keep in lists.
//! - [`Triangle`]: the face a window crosses, in that frame; one step of
//!   propagation ([`Window::propagate`], [`Window::child_left`],
//!   [`Window::child_right`]), the separating point
//!   ([`Window::separating_point`]) and lighting the apex
//!   ([`Window::apex_distance`]).
//! - [`prune`]: the pairwise and vertex pruning predicates of Qin et al. 2016.
//! - [`Shadow`]: the directions a saddle vertex's pseudo-source windows can
//!   light first, from how its shortest path arrived ([`Arrival`]).
//! - [`ResetFront`]: AVTP's wavefront reset, which vertices it restarts and
//!   which lists it empties.
//! - [`Tolerance`]: the one tolerance policy, relative to the mesh scale.
//! - [`Source`], [`DistanceField`], [`Stats`]: what every solver takes and
//!   returns; [`GeodesicPath`] and [`SurfacePoint`]: the paths they trace.
//!
//! # Example
//!
//! A window lighting the whole base of a triangle from straight below its
//! apex splits into two children, one per opposite edge:
//!
//! ```
//! use geodesics_window::{Triangle, Window};
//! use glam::DVec2;
//!
//! let tri = Triangle::new(2.0, DVec2::new(1.0, 1.0));
//! let w = Window { b0: 0.0, b1: 2.0, p: DVec2::new(1.0, -1.0), sigma: 0.0, source: 0 };
//! assert_eq!(w.separating_point(&tri), 1.0);
//! let (d, _) = w.apex_distance(&tri);
//! assert!((d - 2.0).abs() < 1e-15);
//! let (left, right) = w.propagate(&tri);
//! let (left, right) = (left.unwrap(), right.unwrap());
//! // Both children end at the apex, at the same distance.
//! assert!((left.distance_at(left.b1) - 2.0).abs() < 1e-15);
//! assert!((right.distance_at(right.b0) - 2.0).abs() < 1e-15);
//! ```
//!
//! # Invariants
//!
//! - Nothing here allocates; windows are `Copy`.
//! - No predicate discards a window unless a real path is shorter by more
//!   than [`Tolerance::margin`] wherever the discarded part could reach.
//! - No function returns NaN for finite input: degenerate triangles and
//!   grazing windows give no children.

// Negated comparisons (`!(a < b)`) are deliberate throughout: they make a
// NaN fail the test, so no NaN can ever pass for a valid interval.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod face_lists;
mod path;
mod progress;
pub mod prune;
mod queue;
mod reset;
mod setup;
mod shadow;
mod sources;
mod spike;
mod tolerance;
mod types;
mod window;

pub use path::{GeodesicPath, SurfacePoint};
pub use progress::Progress;
pub use queue::{ARITY, VertexQueue};
pub use reset::{ResetFront, path_to_apex};
pub use setup::{FaceKind, NO_GROUP, SolverSetup, VertexState};
pub use shadow::{ALL_RAYS, Arrival, Shadow, corner_neighbours, pseudo_source_window};
pub use sources::{
    Seeds, SourceError, SourceStart, barycentric_ok, seeds, source_start, validate_sources,
};
pub use spike::{MIN_CONE_ANGLE, SpikeError, check_spikes, sharpest_vertex};
pub use tolerance::Tolerance;
pub use types::{DistanceField, NO_SOURCE, Source, Stats, WindowReset};
pub use window::{EndedWindow, Triangle, Window, keep_within};
