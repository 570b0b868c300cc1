//! Exact geodesic distances on triangle meshes by vertex-oriented triangle
//! propagation: VTP, Algorithm 1 of Qin, Han, Yu, Yu and Zhang, "Fast and
//! Exact Discrete Geodesic Computation Based on Triangle-Oriented Wavefront
//! Propagation" (SIGGRAPH 2016).
//!
//! Windows (from `geodesics-window`) live in lists, one per half-edge: the
//! windows about to cross that half-edge's face. The wavefront is a queue of
//! vertices ordered by `(distance, vertex id)` with lazy deletion (the
//! authors' set keyed on distance alone loses vertices whose distances tie).
//! Popping a vertex adds the faces around it to the traversed area; every
//! list waiting to enter one of them is propagated at once through its face
//! with Rule 1 (one angle two sides), the vertex check, and Rules 2/3
//! (pairwise pruning when the children are merged into the lists beyond:
//! by default the lists are kept in edge order and each child meets every
//! window it shares at least 70 % of the narrower one with, see [`Merge`];
//! the paper's order-free merge is the
//! `vtp-order-free` variant); lists whose next face is already traversed keep propagating
//! (secondary propagation), the others wait on the wavefront.
//!
//! Pseudo-sources: boundary vertices, interior vertices whose angle sum
//! exceeds `2π − 1e-5` (saddles and flat vertices), the fan copies of pinch
//! vertices (they share one distance), the corners of zero-area faces, and
//! the sources. A pseudo-source emits one window per opposite edge when it
//! is popped, and again whenever its distance drops by more than the
//! tolerance after that. A saddle or flat vertex emits only into its
//! shadow: a shortest path through it leaves at least π from where it came
//! in on both sides, so only the rays in that sector (of width `Θ − 2π`,
//! `Θ` its angle sum) can be first anywhere ([`geodesics_window::Shadow`]);
//! on scanned meshes this removes most of the saddle windows, which the
//! windows passing the vertex beat everywhere else (the paper emits around
//! the whole fan: the `vtp-full-emission` variant).
//!
//! Zero-area faces: a face with two coincident corners passes windows from
//! one long edge to the other unchanged (the two edges are one segment and
//! their frames coincide); any other zero-area face stops windows, and
//! distances cross it along its edges through its corners, which are
//! pseudo-sources.
//!
//! # Example
//!
//! ```
//! use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
//! use geodesics_vtp::{VtpOptions, solve};
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
//! let (field, stats) = solve(&mesh, &[Source::Vertex(1)], &VtpOptions::default()).unwrap();
//! assert_eq!(field.distance[1], 0.0);
//! assert!((field.distance[3] - 2f64.sqrt()).abs() < 1e-15);
//! assert_eq!(field.nearest_source, vec![0; 4]);
//! assert!(stats.windows_created > 0);
//! ```
//!
//! # Paths
//!
//! [`shortest_path`] (one solve per call) and [`trace_path`] (from the
//! output of [`solve_with_provenance`], for many targets of one solve)
//! rebuild exact shortest paths from the O(1) words per vertex that the
//! solve records, unfolding face by face back towards each pseudo-source:
//!
//! ```
//! use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
//! use geodesics_vtp::{SurfacePoint, VtpOptions, shortest_path};
//! use geodesics_window::Source;
//! use glam::DVec3;
//!
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
//! let path = shortest_path(&mesh, &[Source::Vertex(1)], 3, &VtpOptions::default()).unwrap();
//! // From vertex 1 across the diagonal 0-2 at its midpoint to vertex 3.
//! assert_eq!(path.points.len(), 3);
//! assert_eq!(path.points[0], SurfacePoint::Vertex(1));
//! assert_eq!(path.points[2], SurfacePoint::Vertex(3));
//! assert!(matches!(path.points[1], SurfacePoint::Edge { t, .. } if (t - 0.5).abs() < 1e-15));
//! assert!((path.length - 2f64.sqrt()).abs() < 1e-15);
//! ```

// Negated comparisons (`!(a < b)`) are deliberate: a NaN fails them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod error;
mod path;
mod solver;

pub use error::VtpError;
pub use geodesics_window::{DistanceField, Progress, Source, Stats, WindowReset};
pub use geodesics_window::{GeodesicPath, SurfacePoint};
pub use path::{PathError, shortest_path, trace_path};

use geodesics_mesh::Mesh;

/// Which pruning rules run: one axis of the paper's variants (Table 3 and
/// the ablations of Fig 12). Every combination is exact; the default is the
/// paper's VTP.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pruning {
    /// Rule 1 (Section 4.1) or Chen and Han's narrower form.
    pub rule1: Rule1,
    /// Which pairs of windows are checked against each other when windows
    /// are merged into a list.
    pub pairs: PairRule,
    /// Checking with vertices (Cases 10–12, the ICH filter, with its
    /// edge-end variants), on each child and each pseudo-source window
    /// emitted into a whole fan.
    pub vertex_check: bool,
    /// A saddle or flat vertex emits pseudo-source windows only into its
    /// shadow, the directions a shortest path through it can take
    /// ([`geodesics_window::Shadow`]), not around its whole fan (not in
    /// the paper; the `vtp-full-emission` variant turns it off).
    pub shadow: bool,
}

impl Pruning {
    /// The paper's VTP: Rule 1, Rules 2 and 3, checking with vertices;
    /// with pseudo-source windows only in saddle shadows.
    pub const VTP: Pruning = Pruning {
        rule1: Rule1::OneAngleTwoSides,
        pairs: PairRule::Adjacent,
        vertex_check: true,
        shadow: true,
    };
}

impl Default for Pruning {
    fn default() -> Self {
        Pruning::VTP
    }
}

/// How a list's best path to the apex prunes the other windows' rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule1 {
    /// No pruning against the apex.
    Off,
    /// Chen and Han's "one angle one split" (Case 9 only): among the
    /// windows whose rays split at the apex, only the best splits.
    OneAngleOneSplit,
    /// VTP's Rule 1, "one angle two sides" (Cases 7–9): every window's
    /// rays crossing the best path to the apex are pruned.
    OneAngleTwoSides,
}

/// Which windows of a list are checked against each other on a merge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairRule {
    /// No pairwise checks (the ablation "without Rules 2 and 3").
    Off,
    /// Rules 2 and 3 (VTP): each window against its neighbour in the list
    /// (Cases 1–6), trimming at tie points and splitting a loser that sticks
    /// out on both sides.
    Adjacent,
    /// VTP-Exhaustive: each incoming window against every window of the
    /// list (Cases 1–6 and tie-point trimming, no splitting).
    Exhaustive,
    /// VTP-Trimming: MMP's interval trimming in place of Rules 2 and 3;
    /// each incoming window against every window of the list, losers cut
    /// at tie points or split around the winner.
    Trimming,
}

/// How the wavefront advances: the other axis of the variants.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Schedule {
    /// Vertex-sorted (VTP, Section 5.2): pop the nearest wavefront vertex,
    /// add its one-ring to the traversed area.
    #[default]
    VertexSorted,
    /// Face-sorted (FTP, Section 5.1): pop the triangle whose entering list
    /// reaches its apex soonest and add that triangle alone.
    FaceSorted,
}

/// How windows arriving at a list that already holds windows are merged.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Merge {
    /// Order-free (the paper's VTP and FTP): appended behind the list,
    /// each checked against the window it follows.
    OrderFree,
    /// Order-preserving (OPVTP, OPFTP): each window inserted where its
    /// start belongs (binary search), then checked with both neighbours.
    OrderPreserving,
    /// Sorted (our default): lists kept in edge order and merged in one
    /// linear pass, each window checked against every window before it
    /// that it overlaps by at least 70 % of the narrower one (see
    /// [`geodesics_window::prune::merge_sorted`]).
    /// On scanned meshes it propagates a quarter to a third fewer windows
    /// than the order-free merge and keeps 30-45 % fewer live, for about
    /// the same time (the pruning it adds costs what the propagations it
    /// saves did).
    #[default]
    Sorted,
}

/// Options of [`solve`]. `Default` is the paper's final algorithm with no
/// distance limit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VtpOptions {
    /// Stop the wavefront beyond this distance; vertices farther away are
    /// reported unreachable (`f64::INFINITY`).
    pub max_distance: Option<f64>,
    /// The pruning rules to apply.
    pub pruning: Pruning,
    /// How the wavefront advances.
    pub schedule: Schedule,
    /// How windows are merged into non-empty lists.
    pub merge: Merge,
    /// Record, per vertex, how its distance was obtained (see
    /// [`solve_with_provenance`]).
    pub record_provenance: bool,
    /// AVTP (approximate): reset the windows each time the wavefront
    /// passes a multiple of `lambda` mean edge lengths. `None` (the
    /// default) is exact VTP.
    pub reset: Option<WindowReset>,
    /// Where the solve reports how far its wavefront has come (see
    /// [`Progress`]); the default reports nowhere.
    pub progress: Progress,
}

/// The paper's named variants (Table 3 and Fig 12 of Qin et al. 2016) as
/// settings of the two axes, schedule × pruning, plus the merge order.
pub const VARIANTS: &[(&str, Schedule, Merge, Pruning)] = &[
    ("vtp", Schedule::VertexSorted, Merge::Sorted, Pruning::VTP),
    (
        "vtp-order-free",
        Schedule::VertexSorted,
        Merge::OrderFree,
        Pruning::VTP,
    ),
    ("ftp", Schedule::FaceSorted, Merge::OrderFree, Pruning::VTP),
    (
        "opvtp",
        Schedule::VertexSorted,
        Merge::OrderPreserving,
        Pruning::VTP,
    ),
    (
        "opftp",
        Schedule::FaceSorted,
        Merge::OrderPreserving,
        Pruning::VTP,
    ),
    // MMP's pruning is trimming against every window ever put on an edge;
    // VTP frees a list once it has propagated, so the vertex distances
    // stand in for the windows MMP would still hold (without any check,
    // windows circle the traversed area for a very long time).
    (
        "vtp-mmp",
        Schedule::VertexSorted,
        Merge::OrderFree,
        Pruning {
            rule1: Rule1::Off,
            pairs: PairRule::Trimming,
            ..Pruning::VTP
        },
    ),
    (
        "vtp-ch",
        Schedule::VertexSorted,
        Merge::OrderFree,
        Pruning {
            rule1: Rule1::OneAngleOneSplit,
            pairs: PairRule::Off,
            ..Pruning::VTP
        },
    ),
    (
        "vtp-exhaustive",
        Schedule::VertexSorted,
        Merge::OrderFree,
        Pruning {
            pairs: PairRule::Exhaustive,
            ..Pruning::VTP
        },
    ),
    (
        "vtp-trimming",
        Schedule::VertexSorted,
        Merge::OrderFree,
        Pruning {
            pairs: PairRule::Trimming,
            ..Pruning::VTP
        },
    ),
    (
        "vtp-no-rule1",
        Schedule::VertexSorted,
        Merge::Sorted,
        Pruning {
            rule1: Rule1::Off,
            ..Pruning::VTP
        },
    ),
    (
        "vtp-no-rules23",
        Schedule::VertexSorted,
        Merge::Sorted,
        Pruning {
            pairs: PairRule::Off,
            ..Pruning::VTP
        },
    ),
    // The paper's emission: every pseudo-source lights its whole fan.
    (
        "vtp-full-emission",
        Schedule::VertexSorted,
        Merge::Sorted,
        Pruning {
            shadow: false,
            ..Pruning::VTP
        },
    ),
];

impl VtpOptions {
    /// The options of a named variant of [`VARIANTS`] (no distance limit,
    /// no reset), or `None` for an unknown name.
    pub fn variant(name: &str) -> Option<VtpOptions> {
        VARIANTS
            .iter()
            .find(|v| v.0 == name)
            .map(|&(_, schedule, merge, pruning)| VtpOptions {
                schedule,
                merge,
                pruning,
                ..VtpOptions::default()
            })
    }

    /// The name of the variant these options run, if it is one of
    /// [`VARIANTS`].
    pub fn variant_name(&self) -> Option<&'static str> {
        VARIANTS
            .iter()
            .find(|v| (v.1, v.2, v.3) == (self.schedule, self.merge, self.pruning))
            .map(|v| v.0)
    }
}

/// How a vertex got its final distance: enough to rebuild (or
/// independently verify) the path, one straight unfolded piece at a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Provenance {
    /// Never reached.
    Unreached,
    /// Straight from source number `.0` (a source vertex, or a corner of
    /// the face or edge holding a point source).
    Source(u32),
    /// Along a mesh edge of length `length` from vertex `from` (a
    /// pseudo-source relaxing its neighbours; `length` 0 for pinch copies).
    Vertex {
        /// The pseudo-source vertex.
        from: u32,
        /// Length of the edge walked.
        length: f64,
    },
    /// Lit as the apex of the face of `half_edge` by a window of that
    /// half-edge: the path is straight from `pseudo_source` (in the
    /// half-edge's frame, at distance `sigma` from the source) through the
    /// window, crossing the half-edge at `bend` (bending there only if the
    /// apex was not visible through the window).
    Window {
        /// The half-edge whose window lit the apex.
        half_edge: u32,
        /// The window's pseudo-source, in the half-edge's frame.
        pseudo_source: glam::DVec2,
        /// Distance of the pseudo-source.
        sigma: f64,
        /// Where the path crosses the half-edge.
        bend: f64,
    },
}

/// Computes exact geodesic distances from `sources` to every vertex of
/// `mesh`: per input vertex, the distance to the nearest source and which
/// source that is, plus statistics of the run.
///
/// Never panics on input: an empty source list, an index out of range, an
/// unreferenced source vertex, an edge parameter outside `[0, 1]`,
/// barycentric coordinates that are not finite, negative or do not sum to 1,
/// or a negative maximum distance are [`VtpError`]s.
pub fn solve(
    mesh: &Mesh,
    sources: &[Source],
    options: &VtpOptions,
) -> Result<(DistanceField, Stats), VtpError> {
    solver::solve(mesh, sources, options).map(|(f, s, _)| (f, s))
}

/// [`solve`], also returning per mesh vertex (pinch copies included, not
/// folded) how its distance was obtained. Recording costs one store per
/// distance update.
pub fn solve_with_provenance(
    mesh: &Mesh,
    sources: &[Source],
    options: &VtpOptions,
) -> Result<(DistanceField, Stats, Vec<Provenance>), VtpError> {
    let options = VtpOptions {
        record_provenance: true,
        ..options.clone()
    };
    solver::solve(mesh, sources, &options)
}
