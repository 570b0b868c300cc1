//! Exact geodesic distances on triangle meshes by *parallel* vertex-oriented
//! triangle propagation: PVTP, Algorithm 2 of Du, He, Chen, Xin, Zhang and
//! Liu, "Parallel and approximate geodesic computation" (2021), built on the
//! windows of `geodesics-window` and following our sequential VTP
//! (`geodesics-vtp`) in every geometric case.
//!
//! Two schedules cut the work for the threads ([`Schedule`]): regions of
//! space in distance bands, the default, and the paper's rounds. Both are
//! exact. The regions scale better and give the same bits for every
//! thread count; the rounds follow Algorithm 2 step by step, for
//! comparisons with the paper.
//!
//! [`Schedule::Rounds`]: a round pops the nearest vertices from distance
//! buckets (width `h/τ`, Section 4.2) until `k_ad` vertices (adapted by
//! Eq. 5) or `K = 100·T` face jobs (Eq. 6; a face job holds the up to
//! three window lists of one face; counted by the popped vertices' fan
//! sizes) are ready, then propagates lists in *phases*: all lists of a
//! phase cross their faces in parallel on a crew of `T` threads (the
//! calling thread and `T − 1` helpers spawned once per solve on a rayon
//! pool of `T` threads, which wait for the next phase spinning rather than
//! sleeping: a fork/join per phase cost more than a short phase's work),
//! each thread taking first the jobs of the faces it owns (a hash of
//! space, so a list's windows stay in one core's cache), each face job
//! writing only its own output and the lists it owns in that phase
//! (delayed writes; each list has a main and a side buffer, the dual
//! arrays `A_from` / `A_to`); the distance updates are then applied
//! and the improved vertices re-queued sequentially in job order, and the
//! lists that received windows and touch the traversed area form the next
//! phase. While such a phase has fewer than `K` jobs, the next round's
//! lists join it, so the phases stay full. Rounds and phases repeat until
//! the buckets are empty. The result is exact (the
//! same pruning rules as VTP: Rule 1, the vertex check, Rules 2/3 when
//! merging) and **deterministic**: the same input and `T` give the same
//! bits on every run, whatever the thread timing.
//!
//! [`Schedule::Regions`], the default, cuts the work differently, with no
//! one-thread part between the parallel steps: the faces are cut into
//! regions of space, each running sequential VTP on its own faces up to a
//! distance bound that grows band by band (Du et al.'s buckets); windows
//! and distances that cross into another region are delayed to the next
//! band and read in a fixed order, so the result is the same bits for
//! every thread count. A thread out of one band's regions starts the next
//! band in regions whose neighbours are done with this one, so the threads
//! seldom wait at a band's end. On 2 CPUs it scales better than the rounds
//! (1.83–2.03× against 1.61–1.83× on 235K–871K faces, `cargo xtask
//! pvtp`, two runs on one day) and runs at 0.91–0.98× VTP's speed on one
//! thread, so it reaches 1.75–1.88× VTP on two (the rounds 1.50–1.70×),
//! and 1.77–1.95× on a [`PreparedMesh`], which lays the regions out once
//! for many solves; PAVTP (`geodesics-avtp`) runs on it.
//!
//! Saddle, boundary, flat and pinch vertices, corners of zero-area faces
//! and the sources are pseudo-sources as in VTP: they emit windows when
//! popped and again whenever their distance drops by more than the
//! tolerance afterwards, including inside the swept area (paper 4.7); a
//! saddle or flat vertex only into its shadow, as in VTP
//! (`geodesics_window::Shadow`).
//!
//! # Example
//!
//! ```
//! use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
//! use geodesics_pvtp::{PvtpOptions, solve};
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
//! let options = PvtpOptions { threads: 2, ..PvtpOptions::default() };
//! let (field, stats) = solve(&mesh, &[Source::Vertex(1)], &options).unwrap();
//! assert_eq!(field.distance[1], 0.0);
//! assert!((field.distance[3] - 2f64.sqrt()).abs() < 1e-15);
//! assert_eq!(field.nearest_source, vec![0; 4]);
//! assert!(stats.windows_created > 0);
//! ```

// Negated comparisons (`!(a < b)`) are deliberate: a NaN fails them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod buckets;
mod crew;
mod error;
mod regions;
mod solver;

pub use error::PvtpError;
pub use geodesics_window::{DistanceField, Progress, Source, Stats, WindowReset};

use std::time::Instant;

use geodesics_mesh::Mesh;

/// Options of [`solve`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PvtpOptions {
    /// Threads of the rayon pool the solve runs on; `0` means rayon's
    /// default (the number of logical CPUs, or `RAYON_NUM_THREADS`); at most
    /// [`max_threads`]. More than the machine's CPUs run, but slower. On
    /// the default schedule the result does not depend on it at all; on
    /// the rounds only through the order of work (it is exact for every
    /// value, and bit-identical between runs with the same value).
    pub threads: usize,
    /// Stop the wavefront beyond this distance; vertices farther away are
    /// reported unreachable (`f64::INFINITY`).
    pub max_distance: Option<f64>,
    /// PAVTP (approximate): AVTP's window reset on top of PVTP, between
    /// bands (between rounds on the rounds schedule). `None` (the
    /// default) is exact PVTP.
    pub reset: Option<WindowReset>,
    /// Where the solve reports how far its wavefront has come (see
    /// [`Progress`]); the default reports nowhere.
    pub progress: Progress,
    /// How the work is cut for the threads (see [`Schedule`]).
    pub schedule: Schedule,
}

/// How PVTP cuts its work for the threads. Both are exact (and PAVTP with a
/// reset); they differ in speed and in how the result's last bits depend on
/// the thread count.
///
/// ```
/// use geodesics_mesh::{BuildOptions, Mesh};
/// use geodesics_pvtp::{PvtpOptions, Schedule, solve};
/// use geodesics_window::Source;
///
/// let mesh = Mesh::build(geodesics_shapes::icosphere(3, 1.0), &BuildOptions::default()).unwrap();
/// let on = |threads| {
///     let options = PvtpOptions { threads, schedule: Schedule::Regions, ..PvtpOptions::default() };
///     solve(&mesh, &[Source::Vertex(0)], &options).unwrap().0
/// };
/// // The region schedule gives the same bits whatever the thread count.
/// assert_eq!(on(1), on(3));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Schedule {
    /// Du et al.'s rounds (the crate docs): one thread selects the nearest
    /// vertices, the threads propagate their faces' lists, one thread
    /// applies the delayed writes. Bit-identical from run to run for a
    /// given thread count. The paper's Algorithm 2, kept for comparisons
    /// with it (`pvtp-rounds` in `geodesics` and the CLI).
    Rounds,
    /// The default: regions of space, each running sequential VTP on its
    /// own faces up to a distance bound that grows band by band; windows
    /// and distances crossing into another region are delayed to the next
    /// band. No one-thread part between bands, so it scales further and
    /// suffers less when the cores talk slowly; 2–9 % slower than VTP on
    /// one thread (by mesh and run). The same bits for every thread count.
    #[default]
    Regions,
}

/// The most threads a solve accepts: 256, or the machine's logical CPU
/// count if larger. Far beyond the CPU count a rayon pool's own start and
/// stop grow with the square of its threads (5,000 threads took 163 s on
/// a 2,390-face mesh on 2 CPUs; 1,024 took 2.5 s; 256, 0.14 s).
pub fn max_threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .max(256)
}

/// Computes exact geodesic distances from `sources` to every vertex of
/// `mesh` with PVTP on `options.threads` threads: per input vertex, the
/// distance to the nearest source and which source that is, plus
/// statistics of the run (counted as VTP counts them;
/// `propagation_seconds` is the wall time of the parallel phases, which
/// include the merges, and `pruning_seconds` is 0).
///
/// Never panics on input: an empty source list, an index out of range, an
/// unreferenced source vertex, an edge parameter outside `[0, 1]`,
/// barycentric coordinates that are not finite, negative or do not sum to 1,
/// a negative maximum distance, more threads than [`max_threads`], or a
/// thread pool that cannot start are
/// [`PvtpError`]s.
///
/// The solve's thread pool is kept for the next solve asking for the same
/// thread count (its threads sleep in between), as rayon keeps its global
/// pool; a solve running while another one holds it makes its own.
///
/// To solve many times on one mesh, [`PreparedMesh`] keeps what a solve
/// derives from the mesh for the next one.
pub fn solve(
    mesh: &Mesh,
    sources: &[Source],
    options: &PvtpOptions,
) -> Result<(DistanceField, Stats), PvtpError> {
    PreparedMesh::new(mesh).solve(sources, options)
}

/// A mesh ready for many PVTP solves (from other sources, with other
/// options): the first solve on [`Schedule::Regions`] lays the regions
/// out (cuts the faces into cubes, copies their corners, finds every
/// vertex's copies) and the next ones only restart their state, in the
/// memory the first one touched. Each solve gives the same bits as
/// [`solve`] would.
///
/// On 2 CPUs a prepared two-thread solve took 8–10 % less time than a
/// fresh one on the welded dragon (exact, 871K faces) and for PAVTP at
/// λ = 8 on the 1.1M-face subdivided bunny, and 3 % less on 235K–280K
/// faces (`cargo xtask pvtp`, `cargo xtask avtp --large`): a fresh solve
/// writes its tables into new memory (about 200 MB on that bunny), and
/// faulting those pages in is the cost. The price is that memory, held
/// until the `PreparedMesh` is dropped. The rounds schedule keeps
/// nothing.
///
/// ```
/// use geodesics_mesh::{BuildOptions, Mesh};
/// use geodesics_pvtp::{PreparedMesh, PvtpOptions, Source};
///
/// let soup = geodesics_shapes::flat_grid(20, 20, 0.1);
/// let mesh = Mesh::build(soup, &BuildOptions::default()).unwrap();
/// let mut prepared = PreparedMesh::new(&mesh);
/// let options = PvtpOptions { threads: 2, ..PvtpOptions::default() };
/// // Distances from a corner, then from the opposite one.
/// let (a, _) = prepared.solve(&[Source::Vertex(0)], &options).unwrap();
/// let (b, _) = prepared.solve(&[Source::Vertex(440)], &options).unwrap();
/// // Both are the diagonal, √8 long (to rounding: the paths differ).
/// assert!((a.distance[440] - 8f64.sqrt()).abs() < 1e-14);
/// assert!((b.distance[0] - 8f64.sqrt()).abs() < 1e-14);
/// ```
pub struct PreparedMesh<'m> {
    mesh: &'m Mesh,
    regions: Option<regions::Prepared>,
}

impl<'m> PreparedMesh<'m> {
    /// `mesh`, with nothing laid out yet (that is the first solve's work).
    pub fn new(mesh: &'m Mesh) -> PreparedMesh<'m> {
        PreparedMesh {
            mesh,
            regions: None,
        }
    }

    /// The mesh solved on.
    pub fn mesh(&self) -> &'m Mesh {
        self.mesh
    }

    /// Distances from `sources` as [`solve`] computes them, on the layout
    /// kept from the last solve (or a new one).
    pub fn solve(
        &mut self,
        sources: &[Source],
        options: &PvtpOptions,
    ) -> Result<(DistanceField, Stats), PvtpError> {
        let start = Instant::now();
        let mesh = self.mesh;
        solver::validate(mesh, sources, options)?;
        let pool = KeptPool::take(options.threads)?;
        let threads = pool.pool.current_num_threads();
        // `threads: 0` takes rayon's default, which `RAYON_NUM_THREADS` sets.
        solver::check_thread_count(threads)?;
        options.progress.start(mesh.vertex_count());
        let result = if options.schedule == Schedule::Regions {
            let prepared = &mut self.regions;
            pool.pool
                .install(|| regions::solve(prepared, mesh, sources, options, threads, start))
        } else {
            pool.pool.install(|| {
                let mut s = solver::Solver::new(mesh, options, threads);
                for (i, source) in sources.iter().enumerate() {
                    s.seed(i as u32, source);
                }
                s.run().finish(start)
            })
        };
        pool.keep();
        Ok(result)
    }
}

/// The thread pool of a solve. A finished solve keeps its pool for the
/// next one asking for the same thread count (one pool is kept, its
/// threads asleep), as rayon keeps its global pool: a fresh pool's threads
/// start with empty allocator arenas, so every solve paid page faults for
/// all the memory its threads touched: repeated solves on two threads ran
/// 1–8 % slower with a new pool each (the welded dragon, PAVTP on the
/// 1.1M-face bunny; the more, the busier the machine). A solve running
/// while another holds the kept pool makes its own, so solves never share
/// threads.
struct KeptPool {
    requested: usize,
    pool: rayon::ThreadPool,
}

/// The pool kept by the last finished solve, with the thread count asked
/// for (`0`: rayon's default).
static KEPT_POOL: std::sync::Mutex<Option<KeptPool>> = std::sync::Mutex::new(None);

impl KeptPool {
    /// The kept pool if it has `requested` threads, else a new one.
    fn take(requested: usize) -> Result<KeptPool, PvtpError> {
        let kept = solver::lock(&KEPT_POOL).take_if(|k| k.requested == requested);
        if let Some(kept) = kept {
            return Ok(kept);
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(requested)
            .build()
            .map_err(|e| PvtpError::ThreadPool {
                threads: requested,
                message: e.to_string(),
            })?;
        Ok(KeptPool { requested, pool })
    }

    /// Keeps this pool for the next solve (replacing a kept one).
    fn keep(self) {
        *solver::lock(&KEPT_POOL) = Some(self);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesics_mesh::{BuildOptions, IndexedTriangles};
    use geodesics_window::SourceError;
    use glam::DVec3;

    fn build(soup: IndexedTriangles) -> Mesh {
        Mesh::build(soup, &BuildOptions::default()).expect("valid test mesh")
    }

    /// Both schedules, each test runs on each.
    const SCHEDULES: [Schedule; 2] = [Schedule::Regions, Schedule::Rounds];

    /// Every pair of a thread count of `threads` and a schedule.
    fn cases(threads: &[usize]) -> impl Iterator<Item = (usize, Schedule)> + '_ {
        threads.iter().flat_map(|&t| SCHEDULES.map(|s| (t, s)))
    }

    fn run(mesh: &Mesh, sources: &[Source], threads: usize, schedule: Schedule) -> DistanceField {
        let options = PvtpOptions {
            threads,
            schedule,
            ..PvtpOptions::default()
        };
        solve(mesh, sources, &options).expect("valid input").0
    }

    fn vtp(mesh: &Mesh, sources: &[Source]) -> DistanceField {
        geodesics_vtp::solve(mesh, sources, &geodesics_vtp::VtpOptions::default())
            .expect("valid input")
            .0
    }

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| {
                assert_eq!(x.is_finite(), y.is_finite(), "{x} vs {y}");
                if x.is_finite() { (x - y).abs() } else { 0.0 }
            })
            .fold(0.0, f64::max)
    }

    /// On a plane every geodesic is straight: exact Euclidean distances,
    /// also on the regular grid, whose ties broke the authors' queue.
    #[test]
    fn flat_grid_gives_euclidean_distances_for_any_thread_count() {
        let soup = geodesics_shapes::flat_grid(40, 30, 0.25);
        let mesh = build(soup.clone());
        for source in [0u32, 20 * 41 + 17] {
            let s = soup.positions[source as usize];
            for (threads, schedule) in cases(&[1, 2, 3, 8]) {
                let field = run(&mesh, &[Source::Vertex(source)], threads, schedule);
                for (v, d) in field.distance.iter().enumerate() {
                    let exact = soup.positions[v].distance(s);
                    assert!(
                        (d - exact).abs() < 1e-13,
                        "{schedule:?}, T={threads}: vertex {v}: {d} vs {exact}"
                    );
                }
            }
        }
    }

    #[test]
    fn point_sources_in_faces_and_on_edges_are_straight_on_a_plane() {
        let soup = geodesics_shapes::flat_grid(20, 20, 0.5);
        let mesh = build(soup.clone());
        let f = 211u32;
        let bary = [0.2, 0.3, 0.5];
        let c = mesh.face(f).map(|v| soup.positions[v as usize]);
        let q = c[0] * bary[0] + c[1] * bary[1] + c[2] * bary[2];
        let h = 3 * 100 + 1;
        let e = soup.positions[mesh.tail(h) as usize] * 0.7
            + soup.positions[mesh.head(h) as usize] * 0.3;
        let sources = [
            Source::FacePoint {
                face: f,
                barycentric: bary,
            },
            Source::EdgePoint {
                half_edge: h,
                t: 0.3,
            },
        ];
        for schedule in SCHEDULES {
            let field = run(&mesh, &sources, 2, schedule);
            for (v, (&d, &s)) in field.distance.iter().zip(&field.nearest_source).enumerate() {
                let p = soup.positions[v];
                let (dq, de) = (p.distance(q), p.distance(e));
                assert!((d - dq.min(de)).abs() < 1e-13, "{schedule:?}: vertex {v}");
                let own = if s == 0 { dq } else { de };
                assert!(
                    (own - d).abs() < 1e-13,
                    "{schedule:?}: vertex {v}: nearest source {s}"
                );
            }
        }
    }

    /// Many saddle vertices (pseudo-sources re-emitting inside the swept
    /// area): bit-identical across runs for a given T, and equal to VTP
    /// for every T.
    #[test]
    fn bumpy_sphere_is_deterministic_and_matches_vtp() {
        let mesh = build(geodesics_shapes::bumpy_sphere(3, 1.0, 12, 0.15, 7));
        let sources = [Source::Vertex(0), Source::Vertex(100)];
        let reference = vtp(&mesh, &sources);
        for (threads, schedule) in cases(&[1, 2, 8]) {
            let a = run(&mesh, &sources, threads, schedule);
            let b = run(&mesh, &sources, threads, schedule);
            assert!(
                a.distance
                    .iter()
                    .zip(&b.distance)
                    .all(|(x, y)| x.to_bits() == y.to_bits())
                    && a.nearest_source == b.nearest_source,
                "{schedule:?}, T={threads}: two runs differ"
            );
            assert!(max_diff(&a.distance, &reference.distance) < 1e-13);
        }
    }

    #[test]
    fn vertices_reached_only_along_zero_area_faces_are_reached() {
        // A strip of collinear points: every face has zero area, so no
        // face gets a job and each round's vertices only relax their
        // neighbours along the edges. The solve once stopped at the first
        // round without jobs, leaving seven of ten vertices at ∞.
        let soup = IndexedTriangles {
            positions: (0..10)
                .map(|i| DVec3::new(f64::from(i), 0.0, 0.0))
                .collect(),
            triangles: (0..8).map(|i| [i, i + 1, i + 2]).collect(),
        };
        let mesh = build(soup);
        let reference = vtp(&mesh, &[Source::Vertex(0)]);
        for (threads, schedule) in cases(&[1, 2]) {
            let field = run(&mesh, &[Source::Vertex(0)], threads, schedule);
            for (v, (&d, &r)) in field.distance.iter().zip(&reference.distance).enumerate() {
                assert_eq!(d, v as f64, "{schedule:?}, T={threads}: vertex {v}");
                assert_eq!(d, r, "{schedule:?}, T={threads}: vertex {v} against VTP");
            }
        }
    }

    /// Two squares touching at one corner (a pinch vertex): paths pass
    /// through it, as in VTP; a second component stays unreachable.
    #[test]
    fn pinch_vertex_is_passed_and_other_components_stay_infinite() {
        let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
        let soup = IndexedTriangles {
            positions: vec![
                p(0.0, 0.0),
                p(1.0, 0.0),
                p(1.0, 1.0),
                p(0.0, 1.0),
                p(2.0, 1.0),
                p(2.0, 2.0),
                p(1.0, 2.0),
                p(5.0, 5.0),
                p(6.0, 5.0),
                p(5.0, 6.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3], [2, 4, 5], [2, 5, 6], [7, 8, 9]],
        };
        let mesh = build(soup);
        let reference = vtp(&mesh, &[Source::Vertex(0)]);
        for schedule in SCHEDULES {
            let field = run(&mesh, &[Source::Vertex(0)], 2, schedule);
            assert!((field.distance[5] - 2.0 * 2f64.sqrt()).abs() < 1e-14);
            assert!((field.distance[4] - (2f64.sqrt() + 1.0)).abs() < 1e-14);
            assert!(field.distance[7..].iter().all(|d| d.is_infinite()));
            assert_eq!(
                &field.nearest_source[7..],
                &[geodesics_window::NO_SOURCE; 3]
            );
            assert!(max_diff(&field.distance, &reference.distance) < 1e-14);
        }
    }

    #[test]
    fn max_distance_cuts_the_field() {
        let soup = geodesics_shapes::flat_grid(30, 30, 0.1);
        let mesh = build(soup.clone());
        let options = PvtpOptions {
            threads: 2,
            max_distance: Some(1.0),
            ..PvtpOptions::default()
        };
        let (field, _) = solve(&mesh, &[Source::Vertex(0)], &options).unwrap();
        for (v, d) in field.distance.iter().enumerate() {
            let exact = soup.positions[v].length();
            if exact <= 1.0 - 1e-12 {
                assert!((d - exact).abs() < 1e-13, "vertex {v}");
            } else if exact > 1.0 + 1e-12 {
                assert!(d.is_infinite(), "vertex {v} beyond the limit: {d}");
            }
        }
    }

    /// The window counts every schedule reports.
    fn assert_windows_counted(stats: &Stats) {
        assert!(stats.window_propagations > 0);
        assert!(stats.windows_created >= stats.window_propagations);
        assert_eq!(
            stats.prime_propagations + stats.secondary_propagations,
            stats.window_propagations
        );
        assert!(stats.peak_live_windows > 0);
        assert_eq!(
            stats.peak_window_bytes,
            stats.peak_live_windows * std::mem::size_of::<geodesics_window::EndedWindow>() as u64
        );
    }

    #[test]
    fn rounds_count_their_statistics() {
        let mesh = build(geodesics_shapes::icosphere(3, 1.0));
        let (_, stats) = solve(
            &mesh,
            &[Source::Vertex(0)],
            &PvtpOptions {
                threads: 0,
                schedule: Schedule::Rounds,
                ..PvtpOptions::default()
            },
        )
        .unwrap();
        assert_windows_counted(&stats);
        // One copy of each vertex, popped once.
        assert_eq!(stats.vertex_pops as usize, mesh.vertex_count());
        assert!(stats.total_seconds > 0.0);
    }

    /// The region schedule: the same bits (distances and nearest sources)
    /// for every thread count, equal to VTP's values, on a mesh of many
    /// saddles with two sources.
    /// One prepared mesh through solves of other sources, thread counts,
    /// resets and limits (a limit leaves lists and queued vertices behind
    /// for the next solve to clear) gives the bits of fresh solves.
    #[test]
    fn a_prepared_mesh_gives_the_bits_of_fresh_solves() {
        let mesh = build(geodesics_shapes::bumpy_sphere(5, 1.0, 12, 0.15, 7));
        let mut prepared = PreparedMesh::new(&mesh);
        let reset = Some(WindowReset::every(8.0));
        let lit = Some(WindowReset {
            light_apices: true,
            ..WindowReset::every(8.0)
        });
        let cases = [
            (vec![Source::Vertex(0)], 2, None, None),
            (vec![Source::Vertex(9000)], 2, lit, None),
            (
                vec![Source::Vertex(500), Source::Vertex(9000)],
                1,
                reset,
                None,
            ),
            (vec![Source::Vertex(3)], 8, None, Some(0.5)),
            (vec![Source::Vertex(0)], 2, reset, Some(0.7)),
            (vec![Source::Vertex(7000)], 2, None, None),
        ];
        for (sources, threads, reset, max_distance) in cases {
            let options = PvtpOptions {
                threads,
                schedule: Schedule::Regions,
                reset,
                max_distance,
                ..PvtpOptions::default()
            };
            let (a, sa) = prepared.solve(&sources, &options).unwrap();
            let (b, sb) = solve(&mesh, &sources, &options).unwrap();
            let case = format!("{sources:?} T={threads} {reset:?} {max_distance:?}");
            assert!(
                a.distance
                    .iter()
                    .zip(&b.distance)
                    .all(|(x, y)| x.to_bits() == y.to_bits()),
                "{case}"
            );
            assert_eq!(a.nearest_source, b.nearest_source, "{case}");
            assert_eq!(sa.window_propagations, sb.window_propagations, "{case}");
            assert_eq!(sa.window_resets, sb.window_resets, "{case}");
            if max_distance.is_some() {
                assert!(a.distance.iter().any(|d| d.is_infinite()), "{case}");
            }
        }
        let regions = prepared.regions.as_ref().map_or(0, |p| p.region_count());
        assert!(regions > 1, "{regions} regions: the test needs several");
    }

    /// PAVTP lighting apices before its resets: on both schedules never
    /// below exact, and below the plain reset's error; the regions give the
    /// same bits for every thread count, as without it.
    #[test]
    fn lighting_apices_at_resets_works_on_both_schedules() {
        let mesh = build(geodesics_shapes::bumpy_sphere(4, 1.0, 40, 0.2, 3));
        let sources = [Source::Vertex(0)];
        let exact = vtp(&mesh, &sources).distance;
        // The issues' exactness bar: 1e-12 of the largest distance.
        let tol = 1e-12 * exact.iter().copied().fold(0.0, f64::max);
        let mean_error = |d: &[f64]| {
            let mut sum = 0.0;
            for (v, (a, e)) in d.iter().zip(&exact).enumerate() {
                assert!(*a >= e - tol, "vertex {v}: {a} < exact {e}");
                if *e > 0.0 {
                    sum += (a - e) / e;
                }
            }
            sum / d.len() as f64
        };
        let on = |schedule, threads, light_apices| {
            let options = PvtpOptions {
                threads,
                schedule,
                reset: Some(WindowReset {
                    light_apices,
                    ..WindowReset::every(4.0)
                }),
                ..PvtpOptions::default()
            };
            solve(&mesh, &sources, &options)
                .expect("valid input")
                .0
                .distance
        };
        for schedule in [Schedule::Rounds, Schedule::Regions] {
            let lit = on(schedule, 2, true);
            let (with, without) = (mean_error(&lit), mean_error(&on(schedule, 2, false)));
            assert!(
                with < without,
                "{schedule:?}: {with:e} lit against {without:e}"
            );
        }
        let (one, two) = (
            on(Schedule::Regions, 1, true),
            on(Schedule::Regions, 2, true),
        );
        assert!(
            one.iter()
                .zip(&two)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
    }

    #[test]
    fn regions_give_the_same_bits_for_every_thread_count() {
        let mesh = build(geodesics_shapes::bumpy_sphere(3, 1.0, 12, 0.15, 7));
        let sources = [Source::Vertex(0), Source::Vertex(300)];
        let reference = vtp(&mesh, &sources);
        let run_with = |threads| {
            let options = PvtpOptions {
                threads,
                schedule: Schedule::Regions,
                ..PvtpOptions::default()
            };
            solve(&mesh, &sources, &options).unwrap()
        };
        let (first, stats) = run_with(1);
        assert!(max_diff(&first.distance, &reference.distance) < 1e-13);
        assert_eq!(first.nearest_source, reference.nearest_source);
        for threads in [2, 3, 8] {
            let (field, s) = run_with(threads);
            assert!(
                field
                    .distance
                    .iter()
                    .zip(&first.distance)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "T={threads}"
            );
            assert_eq!(field.nearest_source, first.nearest_source, "T={threads}");
            assert_eq!(
                s.window_propagations, stats.window_propagations,
                "T={threads}"
            );
            assert_eq!(s.threads, threads as u64);
        }
    }

    /// Regions are found as runs of consecutive faces in one cube; with
    /// the faces in a scattered order nearly every run is one face long,
    /// and a cube's faces lie far apart in the face order.
    #[test]
    fn regions_are_laid_out_from_faces_in_any_order() {
        let mut soup = geodesics_shapes::bumpy_sphere(3, 1.0, 12, 0.15, 7);
        let n = soup.triangles.len();
        // A stride coprime with n visits every face once, far from the last.
        let stride = (n / 3..)
            .find(|s| gcd(*s, n) == 1)
            .expect("some stride is coprime");
        soup.triangles = (0..n).map(|i| soup.triangles[i * stride % n]).collect();
        let mesh = build(soup);
        let sources = [Source::Vertex(0), Source::Vertex(300)];
        let reference = vtp(&mesh, &sources);
        let options = PvtpOptions {
            threads: 2,
            schedule: Schedule::Regions,
            ..PvtpOptions::default()
        };
        let mut prepared = PreparedMesh::new(&mesh);
        let (field, _) = prepared.solve(&sources, &options).unwrap();
        assert!(max_diff(&field.distance, &reference.distance) < 1e-13);
        assert_eq!(field.nearest_source, reference.nearest_source);
        let regions = prepared.regions.as_ref().map_or(0, |p| p.region_count());
        assert!(regions > 1, "{regions} regions: the test needs several");
    }

    fn gcd(a: usize, b: usize) -> usize {
        if b == 0 { a } else { gcd(b, a % b) }
    }

    #[test]
    fn regions_count_their_statistics() {
        let mesh = build(geodesics_shapes::icosphere(3, 1.0));
        let options = PvtpOptions {
            threads: 2,
            schedule: Schedule::Regions,
            ..PvtpOptions::default()
        };
        let (_, stats) = solve(&mesh, &[Source::Vertex(0)], &options).unwrap();
        assert_windows_counted(&stats);
        // Every vertex is popped once per region holding a copy of it.
        assert!(stats.vertex_pops as usize >= mesh.vertex_count());
        assert!(stats.parallel_phases > 0);
        assert_eq!(stats.threads, 2);
    }

    #[test]
    fn bad_input_is_refused() {
        let mesh = build(geodesics_shapes::flat_grid(2, 2, 1.0));
        let o = PvtpOptions::default();
        assert_eq!(
            solve(&mesh, &[], &o),
            Err(PvtpError::Source(SourceError::NoSources))
        );
        assert!(matches!(
            solve(&mesh, &[Source::Vertex(9)], &o),
            Err(PvtpError::Source(SourceError::VertexOutOfRange {
                vertex: 9,
                ..
            }))
        ));
        assert!(matches!(
            solve(
                &mesh,
                &[Source::EdgePoint {
                    half_edge: 0,
                    t: 1.5
                }],
                &o
            ),
            Err(PvtpError::Source(SourceError::EdgeParameter { .. }))
        ));
        assert!(matches!(
            solve(
                &mesh,
                &[Source::FacePoint {
                    face: 0,
                    barycentric: [0.5, 0.5, 0.5]
                }],
                &o
            ),
            Err(PvtpError::Source(SourceError::Barycentric { .. }))
        ));
        assert!(matches!(
            solve(
                &mesh,
                &[Source::Vertex(0)],
                &PvtpOptions {
                    max_distance: Some(f64::NAN),
                    ..o.clone()
                }
            ),
            Err(PvtpError::Source(SourceError::MaxDistance(_)))
        ));
        // Refused before any thread starts, naming the limit.
        let many = max_threads() + 1;
        let refused = solve(
            &mesh,
            &[Source::Vertex(0)],
            &PvtpOptions {
                threads: many,
                ..o.clone()
            },
        );
        assert!(
            matches!(refused, Err(PvtpError::TooManyThreads { threads, max, .. }) if threads == many && max == many - 1),
            "{refused:?}"
        );
        assert!(max_threads() >= 256);
    }
}
