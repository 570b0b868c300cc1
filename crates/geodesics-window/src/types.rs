//! Types shared by every solver: sources, the distance field, statistics.

use geodesics_mesh::Mesh;

/// Where a geodesic distance field starts. Several sources make one field:
/// the distance to the nearest of them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Source {
    /// A mesh vertex (an input vertex index; for a pinch vertex, any of its
    /// fan copies is the same point).
    Vertex(u32),
    /// A point on the edge of half-edge `half_edge`, at `t` from its tail
    /// (`0`) to its head (`1`).
    EdgePoint {
        /// The half-edge (`3 * face + corner`).
        half_edge: u32,
        /// Position along the half-edge, in `[0, 1]`.
        t: f64,
    },
    /// A point inside face `face` with barycentric coordinates relative to
    /// the face's corners in [`geodesics_mesh::Mesh::face`] order.
    FacePoint {
        /// The face.
        face: u32,
        /// Barycentric coordinates: finite, non-negative, summing to 1.
        barycentric: [f64; 3],
    },
}

/// Sentinel of [`DistanceField::nearest_source`] for unreachable vertices.
pub const NO_SOURCE: u32 = u32::MAX;

/// The result of a solve: one value per input vertex (pinch copies folded).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DistanceField {
    /// Geodesic distance to the nearest source; `f64::INFINITY` where no
    /// source reaches (other component, unreferenced vertex, beyond the
    /// maximum distance).
    pub distance: Vec<f64>,
    /// Index into the sources of the nearest source, [`NO_SOURCE`] where
    /// unreachable.
    pub nearest_source: Vec<u32>,
}

impl DistanceField {
    /// The field a solver reports from its per-vertex state over all of the
    /// mesh's vertices (pinch copies included): `vertex(v)` gives the
    /// distance and nearest source of vertex `v`. Each input vertex takes
    /// the shortest of its pinch copies; distances that are not finite or
    /// lie beyond `max_distance` become unreachable.
    pub fn from_vertices(
        mesh: &Mesh,
        max_distance: Option<f64>,
        vertex: impl Fn(usize) -> (f64, u32),
    ) -> DistanceField {
        // Scattered in the mesh's order: the solver's records are read in
        // sequence, not at each input vertex's (renumbered) place.
        let n = mesh.input_vertex_count();
        let mut distance = vec![f64::INFINITY; n];
        let mut nearest_source = vec![NO_SOURCE; n];
        for v in 0..mesh.vertex_count() as u32 {
            if mesh.is_pinch_copy(v) {
                continue;
            }
            let u = mesh.pinch_origin(v) as usize;
            debug_assert_eq!(mesh.mesh_vertex(u as u32), v);
            (distance[u], nearest_source[u]) = vertex(v as usize);
        }
        DistanceField::from_first_fans(mesh, max_distance, distance, nearest_source, vertex)
    }

    /// [`DistanceField::from_vertices`] with the values of each input
    /// vertex's first fan already gathered in input order (`distance[u]`
    /// and `nearest_source[u]` of `vertex(mesh.mesh_vertex(u))`), as a
    /// solver that gathers them in parallel does; `vertex` is asked for
    /// the further fans of pinch vertices only.
    pub fn from_first_fans(
        mesh: &Mesh,
        max_distance: Option<f64>,
        mut distance: Vec<f64>,
        mut nearest_source: Vec<u32>,
        vertex: impl Fn(usize) -> (f64, u32),
    ) -> DistanceField {
        debug_assert_eq!(distance.len(), mesh.input_vertex_count());
        debug_assert_eq!(nearest_source.len(), mesh.input_vertex_count());
        // The further fans of pinch vertices: the input vertex takes the
        // nearest.
        for v in 0..mesh.vertex_count() as u32 {
            if !mesh.is_pinch_copy(v) {
                continue;
            }
            let o = mesh.pinch_origin(v) as usize;
            let (d, s) = vertex(v as usize);
            if d < distance[o] {
                distance[o] = d;
                nearest_source[o] = s;
            }
        }
        for (d, s) in distance.iter_mut().zip(nearest_source.iter_mut()) {
            if !d.is_finite() || max_distance.is_some_and(|m| *d > m) {
                *d = f64::INFINITY;
                *s = NO_SOURCE;
            }
        }
        DistanceField {
            distance,
            nearest_source,
        }
    }
}

/// What a solve did, counted the way the papers count it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Windows created (seeds, pseudo-source windows, propagated children).
    pub windows_created: u64,
    /// Window propagations as VTP counts them: each left or right child
    /// computed counts once.
    pub window_propagations: u64,
    /// Propagations through faces that joined the traversed area in the
    /// current expansion step (ΔR in the paper).
    pub prime_propagations: u64,
    /// Propagations through faces that were already traversed (R).
    pub secondary_propagations: u64,
    /// Largest number of windows alive at once.
    pub peak_live_windows: u64,
    /// `peak_live_windows` times the size of one window.
    pub peak_window_bytes: u64,
    /// Vertices popped from the wavefront queue (re-emissions included).
    pub vertex_pops: u64,
    /// Pseudo-source emissions (sources, saddles, boundary, pinch vertices).
    pub pseudo_source_emissions: u64,
    /// Phases of parallel propagation, each followed by its delayed writes
    /// (PVTP and PAVTP; 0 for the sequential solvers). Each costs a
    /// fork/join, so fewer phases for the same work scale better.
    pub parallel_phases: u64,
    /// Threads the solve ran on: 1 for the sequential solvers, the size of
    /// the pool for PVTP and PAVTP (after `0`, "every logical CPU", was
    /// resolved).
    pub threads: u64,
    /// AVTP and PAVTP: how many times the wavefront passed a multiple of
    /// `λ·h` and its windows were reset (0 for the exact solvers).
    pub window_resets: u64,
    /// AVTP and PAVTP: vertices the windows left unreached although a
    /// neighbour was reached, which then took their distance along mesh
    /// edges from their reached neighbours (0 in almost every solve; see
    /// `geodesics-avtp`). Always 0 for the exact solvers.
    pub edge_filled_vertices: u64,
    /// Seconds spent propagating windows (Rule 1 splitting, children, and
    /// the vertex check applied to each child as it is made). Solvers may
    /// estimate this by timing a sample of their steps (VTP times one
    /// window list in 32), since reading the clock around every step would
    /// cost more than some steps.
    pub propagation_seconds: f64,
    /// Seconds spent merging children into the lists beyond (Rules 2 and 3:
    /// pairwise checks between adjacent windows); sampled likewise.
    pub pruning_seconds: f64,
    /// Seconds spent managing the wavefront (queue, list bookkeeping).
    pub management_seconds: f64,
    /// Total seconds of the solve.
    pub total_seconds: f64,
}

/// The window reset of AVTP (Du et al. 2021, Algorithm 3): each time the
/// wavefront passes a multiple of `λ·h` (h the mean edge length), the
/// windows waiting between wavefront vertices closer than `λ_g·h` beyond
/// that radius are deleted and those vertices restart the front as point
/// sources.
///
/// Every distance is still the length of a real path on the surface, so it
/// is never below the exact one. With `λ·h` beyond the largest distance no
/// reset happens and the result is the exact solver's, bit for bit. As `λ·h`
/// shrinks below the edge lengths every vertex restarts the front: the
/// result tends to distances along edges, shortened where a window from a
/// restarted vertex crosses one face (between the exact distance and the
/// edge-graph Dijkstra distance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindowReset {
    /// Reset radius step, in mean edge lengths (λ).
    pub lambda: f64,
    /// Guard band, in mean edge lengths (λ_g): wavefront vertices farther
    /// than this beyond the reset radius keep their windows.
    pub lambda_g: f64,
    /// Before the reset deletes the windows waiting on an edge between two
    /// reset vertices, light the apex of the face beyond through them
    /// (Rule 1's best path to it, as crossing the face would): a real
    /// path, so still never below exact. An apex so lowered restarts the
    /// front like a reset vertex (no window carries its new distance on).
    /// Not in the paper; off by default.
    pub light_apices: bool,
}

impl WindowReset {
    /// The guard band the authors' code uses.
    pub const DEFAULT_LAMBDA_G: f64 = 8.0;

    /// Whether λ is a finite positive number and λ_g a finite non-negative
    /// one (what every solver accepts).
    pub fn is_usable(&self) -> bool {
        self.lambda > 0.0
            && self.lambda.is_finite()
            && self.lambda_g >= 0.0
            && self.lambda_g.is_finite()
    }

    /// A reset every `lambda` mean edge lengths, with the default guard.
    pub fn every(lambda: f64) -> WindowReset {
        WindowReset {
            lambda,
            lambda_g: Self::DEFAULT_LAMBDA_G,
            light_apices: false,
        }
    }
}
