//! `geodesics path`: the exact shortest path from sources to one vertex.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use geodesics::{Algorithm, GeodesicPath, Mesh, Source, SurfacePoint};
use serde::Serialize;

use crate::input::MeshArgs;

/// Arguments of `geodesics path`.
#[derive(Args, Debug)]
pub struct PathArgs {
    #[command(flatten)]
    pub input: MeshArgs,
    /// A source vertex (input numbering). Repeat for several: the path
    /// starts at the nearest. Default: vertex 0.
    #[arg(long = "source", value_name = "V")]
    pub sources: Vec<u32>,
    /// The target vertex (input numbering).
    #[arg(long, value_name = "V")]
    pub target: u32,
    /// The solver tracing the path: `vtp` (or one of its variants) or `mmp`.
    #[arg(long, default_value = "vtp", value_name = "NAME")]
    pub algorithm: String,
    /// Where to write the path; the format follows the extension: `.obj`
    /// (a polyline), `.csv` (one point per row), `.json` (surface points
    /// with their 3D positions).
    #[arg(long, short, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// Runs `geodesics path`.
pub fn run(args: &PathArgs) -> Result<()> {
    let algorithm: Algorithm = args.algorithm.parse()?;
    let protected: Vec<&Path> = args.input.mesh.iter().map(PathBuf::as_path).collect();
    let format = match &args.output {
        Some(out) => {
            if geodesics::io::would_overwrite(out, &protected) {
                bail!(
                    "{}: refusing to overwrite the input mesh with the output",
                    out.display()
                );
            }
            Some(Format::of(out)?)
        }
        None => None,
    };
    let loaded = args.input.load()?;
    let mut sources: Vec<Source> = args.sources.iter().map(|&v| Source::Vertex(v)).collect();
    if sources.is_empty() {
        sources.push(Source::Vertex(0));
    }
    let progress = geodesics::Progress::tracked();
    let algorithm = algorithm.with_progress(progress.clone());
    let label = format!("{}, {}", loaded.name, algorithm.name());
    let path = crate::progress::while_solving(&label, &progress, || {
        geodesics::shortest_path(&loaded.mesh, &sources, args.target, &algorithm)
    })
    .with_context(|| loaded.name.clone())?;
    if let (Some(out), Some(format)) = (&args.output, format) {
        let bytes = format.render(&loaded.mesh, &path, args.target);
        geodesics::io::write_bytes_atomic(out, &bytes, &protected)?;
    }
    let mut text = format!(
        "{}: path from vertex {} to vertex {} ({}): length {:.12}, {} points ({} edge crossings)\n",
        loaded.name,
        source_vertex(&sources, path.source),
        args.target,
        algorithm.name(),
        path.length,
        path.points.len(),
        path.points
            .iter()
            .filter(|p| matches!(p, SurfacePoint::Edge { .. }))
            .count()
    );
    if let Some(out) = &args.output {
        text += &format!("wrote {}\n", out.display());
    }
    crate::print_stdout(&text)
}

fn source_vertex(sources: &[Source], index: u32) -> String {
    match sources.get(index as usize) {
        Some(Source::Vertex(v)) => v.to_string(),
        _ => format!("source {index}"),
    }
}

#[derive(Clone, Copy, Debug)]
enum Format {
    Obj,
    Csv,
    Json,
}

/// One point of the JSON output, in the file's numbering.
#[derive(Serialize)]
struct JsonPoint {
    /// `vertex`, `edge` or `face`.
    kind: &'static str,
    /// The vertex, or the edge's two end vertices, or the face's corners.
    vertices: Vec<u32>,
    /// Along the edge from its first vertex (edges only).
    #[serde(skip_serializing_if = "Option::is_none")]
    t: Option<f64>,
    /// Relative to the face's corners as listed (faces only).
    #[serde(skip_serializing_if = "Option::is_none")]
    barycentric: Option<[f64; 3]>,
    position: [f64; 3],
}

#[derive(Serialize)]
struct JsonPath {
    length: f64,
    target: u32,
    points: Vec<JsonPoint>,
}

impl Format {
    fn of(path: &Path) -> Result<Format> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj") => Ok(Format::Obj),
            Some("csv") => Ok(Format::Csv),
            Some("json") => Ok(Format::Json),
            _ => bail!(
                "{}: unknown path format (use .obj, .csv or .json)",
                path.display()
            ),
        }
    }

    fn render(self, mesh: &Mesh, path: &GeodesicPath, target: u32) -> Vec<u8> {
        match self {
            Format::Obj => {
                let mut s = format!(
                    "# geodesic path to vertex {target}, length {:.17}\n",
                    path.length
                );
                for p in &path.polyline {
                    s += &format!("v {:.17} {:.17} {:.17}\n", p.x, p.y, p.z);
                }
                s += "l";
                for i in 1..=path.polyline.len() {
                    s += &format!(" {i}");
                }
                s += "\n";
                s.into_bytes()
            }
            Format::Csv => {
                let mut s = String::from("index,kind,vertices,t,x,y,z\n");
                for (i, (p, q)) in path.points.iter().zip(&path.polyline).enumerate() {
                    let j = json_point(mesh, p, *q);
                    let vertices: Vec<String> = j.vertices.iter().map(u32::to_string).collect();
                    s += &format!(
                        "{i},{},{},{},{:.17},{:.17},{:.17}\n",
                        j.kind,
                        vertices.join(" "),
                        j.t.map_or(String::new(), |t| format!("{t:.17}")),
                        q.x,
                        q.y,
                        q.z
                    );
                }
                s.into_bytes()
            }
            Format::Json => {
                let doc = JsonPath {
                    length: path.length,
                    target,
                    points: path
                        .points
                        .iter()
                        .zip(&path.polyline)
                        .map(|(p, q)| json_point(mesh, p, *q))
                        .collect(),
                };
                let mut text =
                    serde_json::to_string_pretty(&doc).expect("plain data serializes to JSON");
                text.push('\n');
                text.into_bytes()
            }
        }
    }
}

fn json_point(mesh: &Mesh, p: &SurfacePoint, q: glam::DVec3) -> JsonPoint {
    let input = |v: u32| mesh.pinch_origin(v);
    let (kind, vertices, t, barycentric) = match *p {
        SurfacePoint::Vertex(v) => ("vertex", vec![v], None, None),
        SurfacePoint::Edge { half_edge, t } => (
            "edge",
            vec![input(mesh.tail(half_edge)), input(mesh.head(half_edge))],
            Some(t),
            None,
        ),
        SurfacePoint::Face { face, barycentric } => (
            "face",
            mesh.face(face).map(input).to_vec(),
            None,
            Some(barycentric),
        ),
    };
    JsonPoint {
        kind,
        vertices,
        t,
        barycentric,
        position: q.to_array(),
    }
}
