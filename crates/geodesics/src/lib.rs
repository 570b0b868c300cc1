//! Exact geodesic distances on triangle meshes: the facade over the solver
//! crates, with one entry point, [`compute`].
//!
//! Pick a solver with [`Algorithm`] (by value or by the names the CLI and the
//! papers use), give a validated [`Mesh`] and one or more [`Source`]s, get a
//! [`DistanceField`] (one distance per input vertex, `f64::INFINITY` where
//! unreachable) and the [`Stats`] of the run. Every solver returns the same
//! types, so callers can swap them freely. A long solve can be watched from
//! another thread through a [`Progress`] handle
//! ([`Algorithm::with_progress`]).
//!
//! # Example
//!
//! ```
//! use geodesics::{Algorithm, BuildOptions, Mesh, Source, compute};
//!
//! // A flat 10 x 10 grid: geodesic distance is the straight-line distance.
//! let grid = geodesics_shapes::flat_grid(10, 10, 1.0);
//! // Renumbered in memory for speed (as the CLI does); sources and
//! // distances stay in the input's vertex numbers.
//! let options = BuildOptions { reorder: true, ..BuildOptions::default() };
//! let mesh = Mesh::build(grid, &options)?;
//! let algorithm: Algorithm = "vtp".parse()?;
//! let (field, stats) = compute(&mesh, &[Source::Vertex(0)], &algorithm)?;
//! let far_corner = 11 * 11 - 1;
//! assert!((field.distance[far_corner] - 200f64.sqrt()).abs() < 1e-12);
//! assert!(stats.window_propagations > 0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::fmt;
use std::str::FromStr;

pub use geodesics_avtp::{AvtpError, AvtpOptions};
pub use geodesics_ich::{IchError, IchOptions};
pub use geodesics_io as io;
pub use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh, MeshError, MeshSummary};
pub use geodesics_mmp::{MmpError, MmpOptions};
pub use geodesics_pvtp::{PvtpError, PvtpOptions, Schedule as PvtpSchedule};
pub use geodesics_vtp::PathError;
pub use geodesics_vtp::{Merge, PairRule, Pruning, Rule1, Schedule, VtpError, VtpOptions};
pub use geodesics_window::{
    DistanceField, GeodesicPath, MIN_CONE_ANGLE, NO_SOURCE, Progress, Source, SpikeError, Stats,
    SurfacePoint, check_spikes, sharpest_vertex,
};

/// Errors of the facade: one per solver crate, plus bad algorithm names.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The mesh could not be built.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The VTP solver refused its input.
    #[error(transparent)]
    Vtp(#[from] VtpError),
    /// The AVTP solver refused its input.
    #[error(transparent)]
    Avtp(#[from] AvtpError),
    /// The MMP solver refused its input.
    #[error(transparent)]
    Mmp(#[from] MmpError),
    /// The PVTP solver refused its input.
    #[error(transparent)]
    Pvtp(#[from] PvtpError),
    /// The ICH solver refused its input.
    #[error(transparent)]
    Ich(#[from] IchError),
    /// A VTP path could not be traced.
    #[error(transparent)]
    Path(#[from] PathError),
    /// Paths were asked of an algorithm that does not trace them.
    #[error("algorithm `{0}` traces no paths (use vtp, one of its variants, or mmp)")]
    NoPaths(&'static str),
    /// A setting was given to an algorithm that does not have it.
    #[error("algorithm `{algorithm}` takes no {setting}")]
    NoSuchSetting {
        /// The algorithm's name.
        algorithm: &'static str,
        /// The setting given.
        setting: &'static str,
    },
    /// No algorithm has this name.
    #[error("unknown algorithm `{name}` (known: {})", Algorithm::NAMES.join(", "))]
    UnknownAlgorithm {
        /// The name given.
        name: String,
    },
}

/// A geodesic solver and its settings.
#[derive(Clone, Debug, PartialEq)]
pub enum Algorithm {
    /// Vertex-oriented triangle propagation (Qin et al. 2016), exact.
    Vtp(VtpOptions),
    /// Approximate VTP (Du et al. 2021): a window reset every λ mean edge
    /// lengths; never below exact.
    Avtp(AvtpOptions),
    /// MMP (Surazhsky et al. 2005), exact, with a window priority queue or
    /// FWP's distance buckets (Xu et al. 2015).
    Mmp(MmpOptions),
    /// Parallel VTP (Du et al. 2021), exact: in regions of space (`pvtp`,
    /// the default schedule: the same bits for every thread count) or in
    /// the paper's rounds (`pvtp-rounds`, deterministic per thread count).
    Pvtp(PvtpOptions),
    /// ICH (Xin and Wang 2009), exact, with a window priority queue or FWP's
    /// distance buckets (FWP-CH).
    Ich(IchOptions),
}

impl Algorithm {
    /// Names accepted by [`FromStr`] (and the CLI's `--algorithm`).
    pub const NAMES: &'static [&'static str] = &[
        "vtp",
        "ftp",
        "opvtp",
        "opftp",
        "vtp-order-free",
        "vtp-mmp",
        "vtp-ch",
        "vtp-exhaustive",
        "vtp-trimming",
        "vtp-no-rule1",
        "vtp-no-rules23",
        "vtp-full-emission",
        "mmp",
        "fwp-mmp",
        "ich",
        "fwp-ch",
        "pvtp",
        "pvtp-rounds",
        "avtp",
        "pavtp",
    ];

    /// The paper's name of this algorithm (column headers of the tables);
    /// `vtp-custom` for VTP settings that match no named variant.
    pub fn name(&self) -> &'static str {
        match self {
            Algorithm::Vtp(o) => o.variant_name().unwrap_or("vtp-custom"),
            Algorithm::Avtp(o) if o.threads.is_some() => "pavtp",
            Algorithm::Avtp(_) => "avtp",
            Algorithm::Mmp(o) => match o.schedule {
                geodesics_mmp::Schedule::PriorityQueue => "mmp",
                geodesics_mmp::Schedule::Fwp => "fwp-mmp",
            },
            Algorithm::Pvtp(o) => match o.schedule {
                geodesics_pvtp::Schedule::Regions => "pvtp",
                geodesics_pvtp::Schedule::Rounds => "pvtp-rounds",
            },
            Algorithm::Ich(o) => match o.schedule {
                geodesics_ich::Schedule::PriorityQueue => "ich",
                geodesics_ich::Schedule::Fwp => "fwp-ch",
            },
        }
    }

    /// Whether the algorithm computes exact distances.
    pub fn is_exact(&self) -> bool {
        !matches!(self, Algorithm::Avtp(_))
    }

    /// Sets the accuracy knob of an approximate algorithm: a window reset
    /// every `lambda` mean edge lengths, with guard band `lambda_g` (the
    /// authors' 8 when `None`). An error for exact algorithms.
    pub fn with_lambda(mut self, lambda: f64, lambda_g: Option<f64>) -> Result<Self, Error> {
        match &mut self {
            Algorithm::Avtp(o) => {
                o.lambda = lambda;
                if let Some(g) = lambda_g {
                    o.lambda_g = g;
                }
                Ok(self)
            }
            other => Err(Error::NoSuchSetting {
                algorithm: other.name(),
                setting: "lambda (it is exact)",
            }),
        }
    }

    /// Makes an approximate algorithm light the apex beyond each list a
    /// window reset deletes, through that list (see
    /// [`AvtpOptions::light_apices`]). An error for exact algorithms.
    pub fn with_light_apices(mut self) -> Result<Self, Error> {
        match &mut self {
            Algorithm::Avtp(o) => {
                o.light_apices = true;
                Ok(self)
            }
            other => Err(Error::NoSuchSetting {
                algorithm: other.name(),
                setting: "apex lighting at resets (it is exact)",
            }),
        }
    }

    /// Sets the thread count of a parallel algorithm (0: rayon's default,
    /// all logical CPUs). An error for sequential algorithms.
    pub fn with_threads(mut self, threads: usize) -> Result<Self, Error> {
        match &mut self {
            Algorithm::Pvtp(o) => {
                o.threads = threads;
                Ok(self)
            }
            Algorithm::Avtp(o) if o.threads.is_some() => {
                o.threads = Some(threads);
                Ok(self)
            }
            other => Err(Error::NoSuchSetting {
                algorithm: other.name(),
                setting: "thread count (it is sequential)",
            }),
        }
    }

    /// Stops propagation beyond `max_distance` (farther vertices are ∞).
    pub fn with_max_distance(mut self, max_distance: Option<f64>) -> Self {
        match &mut self {
            Algorithm::Vtp(o) => o.max_distance = max_distance,
            Algorithm::Avtp(o) => o.max_distance = max_distance,
            Algorithm::Mmp(o) => o.max_distance = max_distance,
            Algorithm::Pvtp(o) => o.max_distance = max_distance,
            Algorithm::Ich(o) => o.max_distance = max_distance,
        }
        self
    }

    /// Reports the solve's progress to `progress` (see [`Progress`]).
    ///
    /// ```
    /// use geodesics::{Algorithm, BuildOptions, Mesh, Progress, Source, compute};
    ///
    /// let mesh = Mesh::build(geodesics_shapes::flat_grid(5, 5, 1.0), &BuildOptions::default())?;
    /// let progress = Progress::tracked();
    /// // A real caller reads `progress` from another thread while the solve runs.
    /// let algorithm = Algorithm::default().with_progress(progress.clone());
    /// compute(&mesh, &[Source::Vertex(0)], &algorithm)?;
    /// assert_eq!((progress.reached(), progress.total()), (36, 36)); // 6 × 6 vertices
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_progress(mut self, progress: Progress) -> Self {
        match &mut self {
            Algorithm::Vtp(o) => o.progress = progress,
            Algorithm::Avtp(o) => o.progress = progress,
            Algorithm::Mmp(o) => o.progress = progress,
            Algorithm::Pvtp(o) => o.progress = progress,
            Algorithm::Ich(o) => o.progress = progress,
        }
        self
    }
}

impl Default for Algorithm {
    fn default() -> Self {
        Algorithm::Vtp(VtpOptions::default())
    }
}

impl fmt::Display for Algorithm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Algorithm {
    type Err = Error;

    fn from_str(name: &str) -> Result<Self, Error> {
        let name_lower = name.to_ascii_lowercase();
        if let Some(options) = VtpOptions::variant(&name_lower) {
            return Ok(Algorithm::Vtp(options));
        }
        match name_lower.as_str() {
            "avtp" => Ok(Algorithm::Avtp(AvtpOptions::default())),
            "pavtp" => Ok(Algorithm::Avtp(AvtpOptions {
                threads: Some(0),
                ..AvtpOptions::default()
            })),
            // `pvtp-regions`: the region schedule's name before it became
            // the default.
            "pvtp" | "pvtp-regions" => Ok(Algorithm::Pvtp(PvtpOptions::default())),
            "pvtp-rounds" => Ok(Algorithm::Pvtp(PvtpOptions {
                schedule: geodesics_pvtp::Schedule::Rounds,
                ..PvtpOptions::default()
            })),
            "ich" => Ok(Algorithm::Ich(IchOptions::ich())),
            "fwp-ch" => Ok(Algorithm::Ich(IchOptions::fwp_ch())),
            "mmp" | "fwp-mmp" => Ok(Algorithm::Mmp(MmpOptions {
                schedule: if name_lower == "mmp" {
                    geodesics_mmp::Schedule::PriorityQueue
                } else {
                    geodesics_mmp::Schedule::Fwp
                },
                ..MmpOptions::default()
            })),
            _ => Err(Error::UnknownAlgorithm {
                name: name.to_string(),
            }),
        }
    }
}

/// Computes geodesic distances from `sources` (the distance to the nearest)
/// to every input vertex of `mesh` with `algorithm`.
///
/// To compute many times on one mesh, [`PreparedMesh`] keeps what a solve
/// derives from the mesh for the next one.
pub fn compute(
    mesh: &Mesh,
    sources: &[Source],
    algorithm: &Algorithm,
) -> Result<(DistanceField, Stats), Error> {
    PreparedMesh::new(mesh).compute(sources, algorithm)
}

/// A mesh kept ready for many solves (other sources, other algorithms):
/// [`compute`] without the repeated setup, the same bits.
///
/// Only the parallel solvers on PVTP's region schedule keep anything:
/// their region layout, built by the first such solve (see
/// `geodesics_pvtp::PreparedMesh` for what it saves and the memory it
/// holds until this is dropped). The sequential solvers' setup is a small
/// part of a solve (0.4 ms of VTP's 66 ms on armadillo.obj) and they keep
/// nothing.
///
/// ```
/// use geodesics::{Algorithm, BuildOptions, Mesh, PreparedMesh, Source};
///
/// let grid = geodesics_shapes::flat_grid(10, 10, 1.0);
/// let mesh = Mesh::build(grid, &BuildOptions::default())?;
/// let mut prepared = PreparedMesh::new(&mesh);
/// let pavtp: Algorithm = "pavtp".parse()?;
/// for source in [0, 60, 120] {
///     let (field, _) = prepared.compute(&[Source::Vertex(source)], &pavtp)?;
///     assert_eq!(field.distance[source as usize], 0.0);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct PreparedMesh<'m> {
    pvtp: geodesics_pvtp::PreparedMesh<'m>,
}

impl<'m> PreparedMesh<'m> {
    /// `mesh`, with nothing derived yet.
    pub fn new(mesh: &'m Mesh) -> PreparedMesh<'m> {
        PreparedMesh {
            pvtp: geodesics_pvtp::PreparedMesh::new(mesh),
        }
    }

    /// The mesh computed on.
    pub fn mesh(&self) -> &'m Mesh {
        self.pvtp.mesh()
    }

    /// [`compute`] on this mesh.
    pub fn compute(
        &mut self,
        sources: &[Source],
        algorithm: &Algorithm,
    ) -> Result<(DistanceField, Stats), Error> {
        let mesh = self.mesh();
        match algorithm {
            Algorithm::Vtp(options) => Ok(geodesics_vtp::solve(mesh, sources, options)?),
            Algorithm::Avtp(options) => Ok(geodesics_avtp::solve_prepared(
                &mut self.pvtp,
                sources,
                options,
            )?),
            Algorithm::Mmp(options) => Ok(geodesics_mmp::solve(mesh, sources, options)?),
            Algorithm::Pvtp(options) => Ok(self.pvtp.solve(sources, options)?),
            Algorithm::Ich(options) => Ok(geodesics_ich::solve(mesh, sources, options)?),
        }
    }
}

/// The exact shortest path from the nearest of `sources` to vertex
/// `target` (input numbering), as surface points and a 3D polyline.
///
/// VTP (and its variants) traces it from O(1) words recorded per vertex,
/// unfolding face by face; MMP backtraces its kept windows. Both give the
/// same path. One solve per call: for many targets of one source set, use
/// [`geodesics_vtp::trace_path`] or [`geodesics_mmp::run`] directly.
///
/// ```
/// use geodesics::{Algorithm, BuildOptions, Mesh, Source, shortest_path};
///
/// let grid = geodesics_shapes::flat_grid(4, 4, 1.0);
/// let mesh = Mesh::build(grid, &BuildOptions::default())?;
/// let path = shortest_path(&mesh, &[Source::Vertex(0)], 24, &Algorithm::default())?;
/// assert!((path.length - 32f64.sqrt()).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn shortest_path(
    mesh: &Mesh,
    sources: &[Source],
    target: u32,
    algorithm: &Algorithm,
) -> Result<GeodesicPath, Error> {
    match algorithm {
        Algorithm::Vtp(options) => Ok(geodesics_vtp::shortest_path(
            mesh, sources, target, options,
        )?),
        Algorithm::Mmp(options) => {
            Ok(geodesics_mmp::run(mesh, sources, options)?.path_to_vertex(target)?)
        }
        other => Err(Error::NoPaths(other.name())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for &name in Algorithm::NAMES {
            let a: Algorithm = name.parse().unwrap();
            assert_eq!(a.name(), name);
        }
        // The region schedule's name from before it became the default.
        let old: Algorithm = "pvtp-regions".parse().unwrap();
        assert_eq!(old.name(), "pvtp");
        let err = "dijkstra".parse::<Algorithm>().unwrap_err();
        assert_eq!(
            err.to_string(),
            "unknown algorithm `dijkstra` (known: vtp, ftp, opvtp, opftp, vtp-order-free, vtp-mmp, vtp-ch, \
             vtp-exhaustive, vtp-trimming, vtp-no-rule1, vtp-no-rules23, vtp-full-emission, mmp, fwp-mmp, ich, fwp-ch, pvtp, pvtp-rounds, avtp, pavtp)"
        );
    }

    /// Every algorithm, one after another on one prepared mesh (the
    /// parallel ones with more than one region and with other sources in
    /// between), gives the bits `compute` gives.
    #[test]
    fn a_prepared_mesh_computes_what_compute_does() {
        let soup = geodesics_shapes::bumpy_sphere(5, 1.0, 12, 0.15, 3);
        let mesh = Mesh::build(soup, &BuildOptions::default()).unwrap();
        let mut prepared = PreparedMesh::new(&mesh);
        for (k, &name) in Algorithm::NAMES.iter().enumerate() {
            let algorithm: Algorithm = name.parse().unwrap();
            let sources = [Source::Vertex(97 * k as u32)];
            let (a, _) = prepared.compute(&sources, &algorithm).unwrap();
            let (b, _) = compute(&mesh, &sources, &algorithm).unwrap();
            assert!(
                a.distance
                    .iter()
                    .zip(&b.distance)
                    .all(|(x, y)| x.to_bits() == y.to_bits()),
                "{name}"
            );
            assert_eq!(a.nearest_source, b.nearest_source, "{name}");
        }
    }

    #[test]
    fn lambda_only_for_approximate_algorithms() {
        let a = Algorithm::from_str("avtp")
            .unwrap()
            .with_lambda(32.0, None)
            .unwrap();
        assert_eq!(a, Algorithm::Avtp(AvtpOptions::with_lambda(32.0)));
        assert!(!a.is_exact());
        let err = Algorithm::default().with_lambda(8.0, None).unwrap_err();
        assert_eq!(
            err.to_string(),
            "algorithm `vtp` takes no lambda (it is exact)"
        );
    }
}
