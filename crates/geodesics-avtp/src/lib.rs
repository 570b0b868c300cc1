//! Approximate geodesic distances with one accuracy knob, λ: AVTP,
//! Algorithm 3 of Du, He, Yu, Xin, Ying, Qin, "Parallel and approximate
//! VTP for geodesic distances" (2021).
//!
//! Exact window propagation slows down as the wavefront grows long and
//! carries many windows. AVTP runs exact VTP but, each time the wavefront
//! passes a multiple of `λ·h` (h the mean edge length), deletes the windows
//! waiting on it and restarts the front from its vertices as point sources.
//! Fewer windows, so faster; the price is a small overestimate.
//!
//! What it computes:
//!
//! - every distance is the length of a real path on the surface, so it is
//!   **never below the exact distance**;
//! - with `λ·h` beyond the largest distance no reset happens: the result is
//!   exact VTP's, bit for bit;
//! - with `λ·h` below the shortest edge every vertex restarts the front as it
//!   is reached: the distances follow the mesh edges, shortened only where a
//!   window from a restarted vertex crosses a single face, so they lie
//!   between the exact distance and the edge-graph (Dijkstra) distance;
//! - a vertex that no window reaches although a neighbour was reached (a
//!   narrow sector left uncovered after a reset, where restarted and kept
//!   windows tie to the last digits: one vertex in about 7,700 solves
//!   on our meshes) takes its distance along mesh edges from its reached
//!   neighbours, so nothing reachable is left at ∞
//!   ([`Stats::edge_filled_vertices`] counts them);
//! - in between, the mean error falls fast as λ grows (on `bunny.off`: about
//!   1e-2 relative at λ = 2, 1e-3 at λ = 8, 2e-4 at λ = 32).
//!
//! Not in the paper, and off by default: [`AvtpOptions::light_apices`]
//! lights the apex beyond each list a reset deletes through it first and
//! restarts the front there too, for about half the error at the same λ
//! (40–52 % less mean error at λ = 8 on our real meshes, for 1–7 % more
//! propagations).
//!
//! All reset state belongs to the solve: the mesh is never marked, so solves
//! from other sources on the same mesh are unaffected.
//!
//! A reset costs time in proportion to what changed since the previous one
//! (the vertices that join the reset front, the lists that grew), not to
//! the length of the wavefront, so a tiny λ, which resets at every vertex,
//! stays far faster than exact VTP (the 557K-vertex subdivided bunny at
//! λ = 0.01: 0.46 s; rescanning the wavefront took 5.4 s, as long as VTP).
//!
//! **PAVTP**: with [`AvtpOptions::threads`] set, the same reset runs on top
//! of parallel VTP (`geodesics-pvtp`'s region schedule, `Schedule::Regions`):
//! each band of the wavefront stops at the next reset radius, and each
//! region resets its own wavefront vertices before the next band. The
//! result is the same bits for every thread count (and, like AVTP, never
//! below exact); it differs from sequential AVTP's in the last digits of
//! the error only (mean error 7.63e-4 against 7.64e-4 on the coarse Loop×3
//! bunny at λ = 8). On 2 CPUs it ran at 1.33–1.42× AVTP's speed at λ = 8
//! on meshes of 70K–280K faces and 1.49–1.50× on 0.9–1.1M faces
//! (1.58–1.97× at λ = 32–128 on the larger ones), and, on a mesh kept
//! ready for many solves ([`solve_prepared`]), 1.53–1.72× and 1.68–1.73×
//! (1.85–2.08× at λ = 32–128) (`cargo xtask avtp --large`, on a noisy
//! day);
//! PVTP's rounds, which it used before, ran at 0.7–0.9×: their one-thread
//! part cost about what AVTP's whole solve does.
//!
//! # Example
//!
//! ```
//! use geodesics_avtp::{AvtpOptions, solve};
//! use geodesics_mesh::{BuildOptions, Mesh};
//! use geodesics_window::Source;
//!
//! let sphere = geodesics_shapes::bumpy_sphere(3, 1.0, 40, 0.2, 7);
//! let mesh = Mesh::build(sphere, &BuildOptions::default())?;
//! let sources = [Source::Vertex(0)];
//! let (approx, _) = solve(&mesh, &sources, &AvtpOptions::with_lambda(4.0))?;
//! let (exact, _) = geodesics_vtp::solve(&mesh, &sources, &Default::default())?;
//! for (a, e) in approx.distance.iter().zip(&exact.distance) {
//!     assert!(a >= e); // never below exact
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod gaps;

pub use geodesics_pvtp::PreparedMesh;
pub use geodesics_vtp::WindowReset;
pub use geodesics_window::{DistanceField, Progress, Source, Stats};

use geodesics_mesh::Mesh;
use geodesics_pvtp::{PvtpError, PvtpOptions, Schedule};
use geodesics_vtp::{VtpError, VtpOptions};

/// Why an AVTP solve was refused.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum AvtpError {
    /// The sources or parameters were refused by the underlying VTP solve
    /// (it names the source or parameter).
    #[error(transparent)]
    Vtp(#[from] VtpError),
    /// The same, from the parallel solve (PAVTP).
    #[error(transparent)]
    Pvtp(#[from] PvtpError),
}

/// Settings of an AVTP solve.
#[derive(Clone, Debug, PartialEq)]
pub struct AvtpOptions {
    /// The reset step λ, in mean edge lengths: larger is slower and more
    /// accurate. The paper's usual values are 8 and 32.
    pub lambda: f64,
    /// The guard band λ_g, in mean edge lengths: wavefront vertices farther
    /// than this beyond the reset radius keep their windows (protects
    /// anisotropic meshes; the authors use 8). A narrower band resets fewer
    /// vertices: on the Loop-subdivided bunny at λ = 8, λ_g = 1 halved the
    /// mean error (5.1e-4 against 1.1e-3) for 19 % more propagations and
    /// about 11 % more time, a little better than raising λ to buy the
    /// same accuracy; λ_g = 2 gave 9.1e-4 in the default's time.
    pub lambda_g: f64,
    /// Before a reset deletes the windows waiting between two reset
    /// vertices, light the apex of the face beyond through them (the best
    /// path to it that crossing the face would have given; a real path, so
    /// still never below exact), and if that lowers the apex, restart the
    /// front there as at a reset vertex. Not in the paper, so off by
    /// default. At λ = 8 it cut the mean error from 1.34e-3 to 8.0e-4 on
    /// `armadillo.obj` (4 % more propagations), 1.20e-3 to 6.6e-4 on
    /// `bunny.off` (5 %), 1.15e-3 to 5.6e-4 on `fandisk.obj` (3 %), 7.6e-4
    /// to 4.0e-4 on the coarse Loop×3 bunny (7 %) and 6.7e-4 to 3.4e-4 on
    /// the coarse Loop×4 bunny (7 % more propagations, about 13 % more
    /// time; λ = 16 instead gives 2.1e-4 for about 24 % more).
    ///
    /// ```
    /// use geodesics_avtp::{AvtpOptions, solve};
    /// use geodesics_mesh::{BuildOptions, Mesh};
    /// use geodesics_window::Source;
    ///
    /// let sphere = geodesics_shapes::bumpy_sphere(3, 1.0, 40, 0.2, 7);
    /// let mesh = Mesh::build(sphere, &BuildOptions::default())?;
    /// let sources = [Source::Vertex(0)];
    /// let (exact, _) = geodesics_vtp::solve(&mesh, &sources, &Default::default())?;
    /// let mean_error = |options: &AvtpOptions| -> Result<f64, Box<dyn std::error::Error>> {
    ///     let (field, _) = solve(&mesh, &sources, options)?;
    ///     let pairs = field.distance.iter().zip(&exact.distance).filter(|(_, e)| **e > 0.0);
    ///     let n = pairs.clone().count() as f64;
    ///     Ok(pairs.map(|(a, e)| (a - e) / e).sum::<f64>() / n)
    /// };
    /// let plain = AvtpOptions::with_lambda(4.0);
    /// let lit = AvtpOptions { light_apices: true, ..plain.clone() };
    /// assert!(mean_error(&lit)? < mean_error(&plain)?);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub light_apices: bool,
    /// Stop the wavefront beyond this distance (farther vertices are ∞).
    pub max_distance: Option<f64>,
    /// `None`: sequential AVTP. `Some(T)`: PAVTP on a pool of `T` threads
    /// (`0`: every logical CPU).
    pub threads: Option<usize>,
    /// Where the solve reports how far its wavefront has come (see
    /// [`Progress`]); the default reports nowhere.
    pub progress: Progress,
}

impl AvtpOptions {
    /// λ as given, the authors' guard band, no distance limit.
    pub fn with_lambda(lambda: f64) -> AvtpOptions {
        AvtpOptions {
            lambda,
            lambda_g: WindowReset::DEFAULT_LAMBDA_G,
            light_apices: false,
            max_distance: None,
            threads: None,
            progress: Progress::default(),
        }
    }
}

impl Default for AvtpOptions {
    /// λ = 8, the paper's default trade-off (about 0.1 % mean error).
    fn default() -> Self {
        AvtpOptions::with_lambda(8.0)
    }
}

impl AvtpOptions {
    /// The reset these options ask for.
    pub fn reset(&self) -> WindowReset {
        WindowReset {
            lambda: self.lambda,
            lambda_g: self.lambda_g,
            light_apices: self.light_apices,
        }
    }

    /// The VTP options that run this AVTP sequentially.
    pub fn vtp_options(&self) -> VtpOptions {
        VtpOptions {
            max_distance: self.max_distance,
            reset: Some(self.reset()),
            progress: self.progress.clone(),
            ..VtpOptions::default()
        }
    }
}

/// Approximate distances from `sources` to every vertex of `mesh` (see the
/// crate documentation for what they are), with the statistics of the run.
pub fn solve(
    mesh: &Mesh,
    sources: &[Source],
    options: &AvtpOptions,
) -> Result<(DistanceField, Stats), AvtpError> {
    solve_prepared(&mut PreparedMesh::new(mesh), sources, options)
}

/// [`solve`] on a mesh kept ready for many solves: PAVTP
/// (`options.threads` set) reuses the region layout of the last parallel
/// solve on it (see [`PreparedMesh`]); sequential AVTP keeps nothing and
/// runs as [`solve`] does. The same bits as [`solve`].
pub fn solve_prepared(
    prepared: &mut PreparedMesh<'_>,
    sources: &[Source],
    options: &AvtpOptions,
) -> Result<(DistanceField, Stats), AvtpError> {
    let (mut field, mut stats) = match options.threads {
        None => geodesics_vtp::solve(prepared.mesh(), sources, &options.vtp_options())?,
        Some(threads) => {
            let pvtp = PvtpOptions {
                threads,
                max_distance: options.max_distance,
                reset: Some(options.reset()),
                progress: options.progress.clone(),
                // Regions, not rounds: at λ = 8 the rounds' one-thread part
                // cost about what AVTP's whole solve does (PAVTP at 0.8×
                // AVTP on 2 CPUs); the regions have none (1.20–1.30×).
                schedule: Schedule::Regions,
            };
            prepared.solve(sources, &pvtp)?
        }
    };
    let start = std::time::Instant::now();
    stats.edge_filled_vertices = gaps::fill_gaps(prepared.mesh(), &mut field, options.max_distance);
    // Part of the solve: its time joins the bookkeeping's.
    let fill = start.elapsed().as_secs_f64();
    stats.management_seconds += fill;
    stats.total_seconds += fill;
    Ok((field, stats))
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesics_mesh::BuildOptions;

    /// A flat grid of `n × n` unit squares (also for the other modules'
    /// tests).
    pub(crate) fn grid(n: u32) -> Mesh {
        Mesh::build(
            geodesics_shapes::flat_grid(n, n, 1.0),
            &BuildOptions::default(),
        )
        .expect("a flat grid is a valid mesh")
    }

    #[test]
    fn bad_parameters_are_errors() {
        let mesh = grid(4);
        for (lambda, lambda_g) in [(0.0, 8.0), (-1.0, 8.0), (f64::NAN, 8.0), (4.0, -1.0)] {
            let options = AvtpOptions {
                lambda,
                lambda_g,
                ..AvtpOptions::default()
            };
            let err = solve(&mesh, &[Source::Vertex(0)], &options).unwrap_err();
            assert!(err.to_string().contains("lambda"), "{err}");
        }
    }

    #[test]
    fn resets_and_threads_are_counted() {
        let mesh = grid(30);
        let sources = [Source::Vertex(0)];
        let lambda = 4.0;
        let (field, stats) = solve(&mesh, &sources, &AvtpOptions::with_lambda(lambda)).unwrap();
        // One reset per multiple of λh the wavefront passes: a step (about
        // 4.6 here) is longer than any edge, so no pop jumps two at once.
        let step = lambda * mesh.average_edge_length();
        let farthest = field.distance.iter().copied().fold(0.0, f64::max);
        assert_eq!(stats.window_resets, (farthest / step).floor() as u64);
        assert_eq!(stats.threads, 1);
        // PAVTP resets between rounds, several steps at once at most.
        let parallel = AvtpOptions {
            threads: Some(2),
            ..AvtpOptions::with_lambda(lambda)
        };
        let (_, stats) = solve(&mesh, &sources, &parallel).unwrap();
        assert!((1..=(farthest / step).floor() as u64).contains(&stats.window_resets));
        assert_eq!(stats.threads, 2);
        // Exact: no reset.
        let (_, stats) = geodesics_vtp::solve(&mesh, &sources, &Default::default()).unwrap();
        assert_eq!((stats.window_resets, stats.threads), (0, 1));
    }

    #[test]
    fn flat_grids_stay_close_to_euclidean() {
        // On a plane the exact distance is Euclidean; AVTP is never below
        // it and within a few percent at λ = 4.
        let n = 30;
        let mesh = grid(n);
        let (field, _) =
            solve(&mesh, &[Source::Vertex(0)], &AvtpOptions::with_lambda(4.0)).unwrap();
        for (v, d) in field.distance.iter().enumerate() {
            let p = mesh.position(v as u32);
            let e = p.length();
            assert!(*d >= e - 1e-12 * (1.0 + e), "vertex {v}: {d} < {e}");
            assert!(*d <= e * 1.05 + 1e-12, "vertex {v}: {d} vs {e}");
        }
    }
}
