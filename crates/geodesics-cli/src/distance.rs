//! `geodesics distance`: a geodesic distance field from one or more sources.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use geodesics::{Algorithm, DistanceField, Mesh, Progress, Source, Stats};
use serde::Serialize;

use crate::input::{LoadedMesh, MeshArgs};

/// Arguments of `geodesics distance`.
#[derive(Args, Debug)]
pub struct DistanceArgs {
    #[command(flatten)]
    pub input: MeshArgs,
    /// A source vertex (input numbering). Repeat for several sources; the
    /// field is the distance to the nearest. Default: vertex 0.
    #[arg(long = "source", value_name = "V")]
    pub sources: Vec<u32>,
    /// A source inside a face: `FACE:B0,B1,B2`, barycentric coordinates
    /// relative to the face's corners in file order.
    #[arg(long = "source-point", value_name = "FACE:B0,B1,B2")]
    pub source_points: Vec<String>,
    /// A source on an edge: `A,B:T`, the point at fraction T from vertex A to
    /// vertex B of an edge of the mesh.
    #[arg(long = "source-edge", value_name = "A,B:T")]
    pub source_edges: Vec<String>,
    /// The solver.
    #[arg(long, default_value = "vtp", value_name = "NAME")]
    pub algorithm: String,
    /// Stop propagating beyond this distance (farther vertices are `inf`).
    #[arg(long, value_name = "D")]
    pub max_distance: Option<f64>,
    /// Parallel algorithms (`pvtp`, `pvtp-rounds`, `pavtp`): worker threads (default: every logical
    /// CPU). Results are identical from run to run: for `pvtp` and `pavtp` for every count, for
    /// `pvtp-rounds` (the paper's schedule) for a given count.
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
    /// Approximate algorithms (`avtp`): reset the windows every L mean edge
    /// lengths. Larger is slower and more accurate (default 8, about 0.1 %
    /// mean error).
    #[arg(long, value_name = "L")]
    pub lambda: Option<f64>,
    /// Approximate algorithms: guard band in mean edge lengths; wavefront
    /// vertices farther than this beyond the reset radius keep their
    /// windows (default 8).
    #[arg(long = "lambda-g", value_name = "G")]
    pub lambda_g: Option<f64>,
    /// Approximate algorithms: before a reset deletes the windows between
    /// two restarted vertices, light the apex beyond them through those
    /// windows and restart the front there too. About half the error for
    /// the same λ (40-52 % less at λ = 8 on our real meshes, for 1-7 % more
    /// propagations); not in the paper, so off by default.
    #[arg(long)]
    pub light_apices: bool,
    /// Where to write the field; the format follows the extension: `.txt`
    /// (one value per line, `inf` unreachable), `.csv`, `.npy`, `.ply`
    /// (the mesh colored by distance).
    #[arg(long, short, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Write the run's statistics as JSON to this file.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
}

/// The JSON written by `--stats`.
#[derive(Serialize)]
struct StatsReport<'a> {
    mesh: &'a str,
    algorithm: String,
    vertices: usize,
    faces: usize,
    sources: usize,
    time_seconds: f64,
    window_propagations: u64,
    windows_created: u64,
    peak_windows: u64,
    peak_window_bytes: u64,
    prime_propagations: u64,
    secondary_propagations: u64,
    vertex_pops: u64,
    pseudo_source_emissions: u64,
    parallel_phases: u64,
    /// Threads the solve ran on.
    threads: u64,
    /// AVTP/PAVTP: the reset step λ and guard band λ_g (mean edge
    /// lengths), and how many resets happened; `null`/0 for exact solvers.
    lambda: Option<f64>,
    lambda_g: Option<f64>,
    /// AVTP/PAVTP: whether `--light-apices` was on; `null` for exact
    /// solvers.
    light_apices: Option<bool>,
    window_resets: u64,
    /// AVTP/PAVTP: vertices the windows missed that took their distance
    /// along mesh edges from reached neighbours (almost always 0).
    edge_filled_vertices: u64,
    /// `--max-distance` (propagation stopped beyond it), if given.
    distance_limit: Option<f64>,
    propagation_seconds: f64,
    pruning_seconds: f64,
    management_seconds: f64,
    reached_vertices: usize,
    max_distance: f64,
    load_seconds: f64,
    build_seconds: f64,
    /// The most memory this process held resident at once, from loading
    /// the mesh to writing the output (Linux's `VmHWM`; `null` where the
    /// system does not report it): what `/usr/bin/time` calls the maximum
    /// resident set size.
    peak_rss_bytes: Option<u64>,
}

/// Runs `geodesics distance`.
pub fn run(args: &DistanceArgs) -> Result<()> {
    if let Some(d) = args.max_distance
        && (d.is_nan() || d < 0.0)
    {
        bail!("--max-distance must be a non-negative number, got {d}");
    }
    let mut algorithm: Algorithm = args.algorithm.parse()?;
    algorithm = algorithm.with_max_distance(args.max_distance);
    if let Some(t) = args.threads {
        algorithm = algorithm.with_threads(t)?;
    }
    if args.lambda.is_some() || args.lambda_g.is_some() {
        if let Some(l) = args.lambda
            && !(l > 0.0 && l.is_finite())
        {
            bail!("--lambda must be a positive number, got {l}");
        }
        if let Some(g) = args.lambda_g
            && !(g >= 0.0 && g.is_finite())
        {
            bail!("--lambda-g must be a non-negative number, got {g}");
        }
        let lambda = match (&algorithm, args.lambda) {
            (_, Some(l)) => l,
            (Algorithm::Avtp(o), None) => o.lambda,
            _ => 0.0, // refused just below: the algorithm is exact
        };
        algorithm = algorithm.with_lambda(lambda, args.lambda_g)?;
    }
    if args.light_apices {
        algorithm = algorithm.with_light_apices()?;
    }
    let protected: Vec<&Path> = args.input.mesh.iter().map(PathBuf::as_path).collect();
    for out in args.output.iter().chain(&args.stats) {
        refuse_input_as_output(out, &protected)?;
    }
    let loaded = args.input.load()?;
    let sources = parse_sources(args, &loaded.mesh)?;

    let progress = Progress::tracked();
    let algorithm = algorithm.with_progress(progress.clone());
    let label = format!("{}, {}", loaded.name, algorithm.name());
    let start = Instant::now();
    let (field, stats) = crate::progress::while_solving(&label, &progress, || {
        geodesics::compute(&loaded.mesh, &sources, &algorithm)
    })
    .with_context(|| loaded.name.clone())?;
    let solve_seconds = start.elapsed().as_secs_f64();

    if let Some(out) = &args.output {
        let triangles = loaded.mesh.to_indexed_triangles();
        geodesics::io::write_field(out, &field.distance, Some(&triangles), &protected)?;
    }
    let report = stats_report(&loaded, &algorithm, &sources, &field, &stats, solve_seconds);
    if let Some(path) = &args.stats {
        let json = serde_json::to_string_pretty(&report)? + "\n";
        geodesics::io::write_bytes_atomic(path, json.as_bytes(), &protected)?;
    }
    crate::print_stdout(&summary(&report, &args.output))
}

/// Refuses before the solve (which may be long) rather than after it.
fn refuse_input_as_output(out: &Path, inputs: &[&Path]) -> Result<()> {
    if geodesics::io::would_overwrite(out, inputs) {
        bail!(
            "{}: refusing to overwrite the input mesh with the output",
            out.display()
        );
    }
    Ok(())
}

fn parse_sources(args: &DistanceArgs, mesh: &Mesh) -> Result<Vec<Source>> {
    let mut sources: Vec<Source> = args.sources.iter().map(|&v| Source::Vertex(v)).collect();
    for spec in &args.source_points {
        sources.push(parse_face_point(spec, mesh)?);
    }
    for spec in &args.source_edges {
        sources.push(parse_edge_point(spec, mesh)?);
    }
    if sources.is_empty() {
        sources.push(Source::Vertex(0));
    }
    Ok(sources)
}

fn parse_face_point(spec: &str, mesh: &Mesh) -> Result<Source> {
    let bad = || format!("--source-point `{spec}`: expected FACE:B0,B1,B2");
    let (face, bary) = spec.split_once(':').with_context(bad)?;
    let face: u32 = face.trim().parse().with_context(bad)?;
    let b: Vec<f64> = bary
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .with_context(bad)?;
    let [b0, b1, b2] = b[..] else {
        bail!(bad());
    };
    if face as usize >= mesh.face_count() {
        bail!(
            "--source-point `{spec}`: face {face} does not exist (the mesh has {} faces)",
            mesh.face_count()
        );
    }
    // The file's face number; building may renumber faces, and flip one
    // ([a,b,c] -> [a,c,b]) to orient the surface.
    let face = mesh.mesh_face(face);
    let barycentric = if mesh.is_reoriented(face) {
        [b0, b2, b1]
    } else {
        [b0, b1, b2]
    };
    Ok(Source::FacePoint { face, barycentric })
}

fn parse_edge_point(spec: &str, mesh: &Mesh) -> Result<Source> {
    let bad = || format!("--source-edge `{spec}`: expected A,B:T");
    let (ends, t) = spec.split_once(':').with_context(bad)?;
    let (a, b) = ends.split_once(',').with_context(bad)?;
    let a: u32 = a.trim().parse().with_context(bad)?;
    let b: u32 = b.trim().parse().with_context(bad)?;
    let t: f64 = t.trim().parse().with_context(bad)?;
    let n = mesh.input_vertex_count() as u32;
    if a >= n || b >= n {
        bail!("--source-edge `{spec}`: vertex out of range (the mesh has {n} vertices)");
    }
    // Search every half-edge leaving a fan of `a` (pinch vertices have several).
    let first = mesh.mesh_vertex(a);
    let fans = std::iter::once(first).chain(mesh.pinch_fans(first));
    for fan in fans {
        for h in mesh.outgoing(fan) {
            if mesh.pinch_origin(mesh.head(h)) == b {
                return Ok(Source::EdgePoint { half_edge: h, t });
            }
            // The edge may be a boundary edge entering `a` instead.
            let incoming = Mesh::prev(h);
            if mesh.twin(incoming).is_none() && mesh.pinch_origin(mesh.tail(incoming)) == b {
                return Ok(Source::EdgePoint {
                    half_edge: incoming,
                    t: 1.0 - t,
                });
            }
        }
    }
    bail!("--source-edge `{spec}`: vertices {a} and {b} share no edge")
}

fn stats_report<'a>(
    loaded: &'a LoadedMesh,
    algorithm: &Algorithm,
    sources: &[Source],
    field: &DistanceField,
    stats: &Stats,
    solve_seconds: f64,
) -> StatsReport<'a> {
    let finite = field.distance.iter().copied().filter(|d| d.is_finite());
    let (reset, distance_limit) = match algorithm {
        Algorithm::Avtp(o) => (Some(o.reset()), o.max_distance),
        Algorithm::Vtp(o) => (o.reset, o.max_distance),
        Algorithm::Pvtp(o) => (o.reset, o.max_distance),
        Algorithm::Mmp(o) => (None, o.max_distance),
        Algorithm::Ich(o) => (None, o.max_distance),
    };
    StatsReport {
        mesh: &loaded.name,
        algorithm: algorithm.name().to_string(),
        vertices: loaded.mesh.input_vertex_count(),
        faces: loaded.mesh.face_count(),
        sources: sources.len(),
        time_seconds: solve_seconds,
        window_propagations: stats.window_propagations,
        windows_created: stats.windows_created,
        peak_windows: stats.peak_live_windows,
        peak_window_bytes: stats.peak_window_bytes,
        prime_propagations: stats.prime_propagations,
        secondary_propagations: stats.secondary_propagations,
        vertex_pops: stats.vertex_pops,
        pseudo_source_emissions: stats.pseudo_source_emissions,
        parallel_phases: stats.parallel_phases,
        threads: stats.threads,
        lambda: reset.map(|r| r.lambda),
        lambda_g: reset.map(|r| r.lambda_g),
        light_apices: reset.map(|r| r.light_apices),
        window_resets: stats.window_resets,
        edge_filled_vertices: stats.edge_filled_vertices,
        distance_limit,
        propagation_seconds: stats.propagation_seconds,
        pruning_seconds: stats.pruning_seconds,
        management_seconds: stats.management_seconds,
        reached_vertices: finite.clone().count(),
        max_distance: finite.fold(0.0, f64::max),
        load_seconds: loaded.load_seconds,
        build_seconds: loaded.build_seconds,
        peak_rss_bytes: peak_resident_bytes(),
    }
}

/// The peak resident memory of this process so far, in bytes, or `None`
/// where the system does not say (it is read from `/proc/self/status`).
fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    // "VmHWM:     21056 kB"
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

fn summary(r: &StatsReport, output: &Option<PathBuf>) -> String {
    let mut s = String::new();
    s += &format!(
        "{}: {} vertices, {} faces, {} source(s), algorithm {}\n",
        r.mesh, r.vertices, r.faces, r.sources, r.algorithm
    );
    s += &format!(
        "reached {} of {} vertices; largest distance {:.6}\n",
        r.reached_vertices, r.vertices, r.max_distance
    );
    // No time per propagation when there was none: dividing by one
    // printed the whole solve's time as if it were one propagation's.
    let each = if r.window_propagations == 0 {
        String::new()
    } else {
        format!(
            " ({:.1} ns each)",
            1e9 * r.time_seconds / r.window_propagations as f64
        )
    };
    s += &format!(
        "solve {:.3} s: {} window propagations{each}, {} windows created, peak {} live windows ({:.1} KiB)\n",
        r.time_seconds,
        r.window_propagations,
        r.windows_created,
        r.peak_windows,
        r.peak_window_bytes as f64 / 1024.0
    );
    if let (Some(lambda), Some(lambda_g)) = (r.lambda, r.lambda_g) {
        s += &format!(
            "approximate: λ = {lambda}, λ_g = {lambda_g} (mean edge lengths), {} window reset{}{}\n",
            r.window_resets,
            if r.window_resets == 1 { "" } else { "s" },
            if r.light_apices == Some(true) {
                ", apices lit before each"
            } else {
                ""
            }
        );
        if r.edge_filled_vertices > 0 {
            s += &format!(
                "{} {} the windows missed took their distance along mesh edges\n",
                r.edge_filled_vertices,
                if r.edge_filled_vertices == 1 {
                    "vertex"
                } else {
                    "vertices"
                }
            );
        }
    }
    if r.threads > 1 {
        s += &format!("ran on {} threads\n", r.threads);
    }
    if let Some(out) = output {
        s += &format!("wrote {}\n", out.display());
    }
    s
}
