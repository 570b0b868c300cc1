//! `geodesics info`: what a mesh is made of.

use anyhow::Result;
use clap::Args;
use serde::Serialize;

use crate::input::MeshArgs;

/// Arguments of `geodesics info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    #[command(flatten)]
    pub input: MeshArgs,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// The JSON object `info --json` prints (flat, stable key names).
#[derive(Serialize)]
struct InfoReport<'a> {
    mesh: &'a str,
    vertices: usize,
    faces: usize,
    edges: usize,
    components: usize,
    boundary_loops: usize,
    euler_characteristic: i64,
    genus: Option<i64>,
    saddle_vertices: usize,
    boundary_vertices: usize,
    nonmanifold_vertices: usize,
    zero_area_faces: usize,
    duplicate_positions: usize,
    unreferenced_vertices: usize,
    welded: bool,
    welded_vertices: usize,
    welded_collapsed_faces: usize,
    reoriented_faces: usize,
    anisotropy_mean: f64,
    anisotropy_median: f64,
    anisotropy_p99: f64,
    anisotropy_max: f64,
    bbox_diagonal: f64,
    bbox_min: [f64; 3],
    bbox_max: [f64; 3],
    /// What the solvers' tolerances scale with: the diagonal unless a few
    /// far-out vertices inflate it (`Mesh::length_scale`).
    length_scale: f64,
    /// The interior vertex (input numbering) whose faces meet at the least
    /// total angle, and that angle (`geodesics::sharpest_vertex`); below
    /// `geodesics::MIN_CONE_ANGLE` only MMP solves the mesh.
    sharpest_vertex: Option<u32>,
    sharpest_angle: Option<f64>,
    load_seconds: f64,
    build_seconds: f64,
}

/// Runs `geodesics info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    let loaded = args.input.load()?;
    let s = loaded.mesh.summary();
    let sharpest = geodesics::sharpest_vertex(&loaded.mesh);
    let report = InfoReport {
        mesh: &loaded.name,
        vertices: s.vertices,
        faces: s.faces,
        edges: s.edges,
        components: s.components,
        boundary_loops: s.boundary_loops,
        euler_characteristic: s.euler_characteristic,
        genus: s.genus,
        saddle_vertices: s.saddle_vertices,
        boundary_vertices: s.boundary_vertices,
        nonmanifold_vertices: s.nonmanifold_vertices,
        zero_area_faces: s.zero_area_faces,
        duplicate_positions: s.duplicate_positions,
        unreferenced_vertices: s.unreferenced_vertices,
        welded: args.input.weld,
        welded_vertices: s.welded_vertices,
        welded_collapsed_faces: s.welded_collapsed_faces,
        reoriented_faces: s.reoriented_faces,
        anisotropy_mean: s.anisotropy.mean,
        anisotropy_median: s.anisotropy.median,
        anisotropy_p99: s.anisotropy.p99,
        anisotropy_max: s.anisotropy.max,
        bbox_diagonal: s.bbox_diagonal,
        bbox_min: s.bbox_min,
        bbox_max: s.bbox_max,
        length_scale: loaded.mesh.length_scale(),
        sharpest_vertex: sharpest.map(|(v, _)| v),
        sharpest_angle: sharpest.map(|(_, a)| a),
        load_seconds: loaded.load_seconds,
        build_seconds: loaded.build_seconds,
    };
    let text = if args.json {
        serde_json::to_string_pretty(&report)? + "\n"
    } else {
        table(&report)
    };
    crate::print_stdout(&text)
}

fn table(r: &InfoReport) -> String {
    let genus = r.genus.map_or_else(
        || "n/a (non-manifold vertices)".to_string(),
        |g| g.to_string(),
    );
    let rows: Vec<(&str, String)> = vec![
        ("mesh", r.mesh.to_string()),
        ("vertices", r.vertices.to_string()),
        ("faces", r.faces.to_string()),
        ("edges", r.edges.to_string()),
        ("components", r.components.to_string()),
        ("boundary loops", r.boundary_loops.to_string()),
        ("Euler characteristic", r.euler_characteristic.to_string()),
        ("genus", genus),
        ("saddle vertices", r.saddle_vertices.to_string()),
        ("boundary vertices", r.boundary_vertices.to_string()),
        ("non-manifold vertices", r.nonmanifold_vertices.to_string()),
        ("zero-area faces", r.zero_area_faces.to_string()),
        ("duplicate positions", r.duplicate_positions.to_string()),
        ("unreferenced vertices", r.unreferenced_vertices.to_string()),
        (
            "welded",
            if r.welded {
                format!(
                    "yes ({} vertices merged, {} faces collapsed)",
                    r.welded_vertices, r.welded_collapsed_faces
                )
            } else {
                "no".to_string()
            },
        ),
        ("reoriented faces", r.reoriented_faces.to_string()),
        (
            "anisotropy g(M)",
            format!(
                "mean {:.3}, median {:.3}, p99 {:.3}, max {:.1}",
                r.anisotropy_mean, r.anisotropy_median, r.anisotropy_p99, r.anisotropy_max
            ),
        ),
        ("bbox diagonal", format!("{:.6}", r.bbox_diagonal)),
        (
            "length scale",
            if r.length_scale == r.bbox_diagonal {
                "the diagonal".to_string()
            } else {
                format!(
                    "{:.6} (a few vertices lie far out of proportion)",
                    r.length_scale
                )
            },
        ),
        (
            "sharpest vertex",
            match (r.sharpest_vertex, r.sharpest_angle) {
                (Some(v), Some(a)) if a < geodesics::MIN_CONE_ANGLE => {
                    format!("{v}, faces meet at {a:.2e} rad: a needle, only mmp solves this mesh")
                }
                (Some(v), Some(a)) => format!("{v}, faces meet at {a:.3} rad"),
                _ => "none (no interior vertex)".to_string(),
            },
        ),
        (
            "time",
            format!(
                "load {:.3} s, build {:.3} s",
                r.load_seconds, r.build_seconds
            ),
        ),
    ];
    let width = rows.iter().map(|(k, _)| k.len()).max().unwrap_or(0);
    rows.iter()
        .map(|(k, v)| format!("{k:<width$}  {v}\n"))
        .collect()
}
