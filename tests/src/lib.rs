//! Helpers shared by the workspace-level integration tests: where the real
//! meshes and the reference distances live, and how to read them.
//!
//! The meshes are in the folder named by `GEODESICS_DATA`, by default
//! `../shared/data/meshes` beside the workspace; the reference distances in
//! its sibling `reference/`. Tests that need them call [`data_dir`] and skip
//! loudly when it returns `None`.
//!
//! ```
//! let parsed = geodesics_tests::parse_distances("0.5\ninf\n1e-3\n").unwrap();
//! assert_eq!(parsed, vec![0.5, f64::INFINITY, 1e-3]);
//! ```

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashSet};
use std::path::{Path, PathBuf};

use geodesics_mesh::{BuildOptions, Mesh};
use geodesics_window::Source;
use serde_json::Value;

/// How far two exact distance fields may differ at any vertex, relative to
/// the largest finite distance: the exactness bar of the issues (two good
/// exact codes agree to about 1e-14 in double precision). Every test and
/// the `xtask sweep` that compares exact solvers uses it; it bounds
/// assertions and is not a solver tolerance (that policy lives in
/// `geodesics_window::Tolerance`).
pub const EXACT: f64 = 1e-12;

/// The folder of real meshes, or `None` (after printing a loud SKIPPED line
/// naming `what`) when it is absent.
pub fn data_dir(what: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("GEODESICS_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/meshes"));
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED {what}: mesh folder {} not found (set GEODESICS_DATA)",
            dir.display()
        );
        None
    }
}

/// The folder of reference distances (`reference/` beside the mesh folder).
pub fn reference_dir(data: &Path) -> PathBuf {
    data.join("../reference")
}

/// The largest finite value of a distance field (0 if none).
pub fn max_finite(distances: &[f64]) -> f64 {
    distances
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max)
}

/// Parses a distance file: one value per line, `inf` for unreachable.
pub fn parse_distances(text: &str) -> Result<Vec<f64>, String> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            l.trim()
                .parse::<f64>()
                .map_err(|e| format!("line {}: {e}: {l:?}", i + 1))
        })
        .collect()
}

/// Reads a distance file (see [`parse_distances`]).
pub fn read_distances(path: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    parse_distances(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Reads and builds a mesh file renumbered for locality, as the CLI does,
/// panicking with the reader's or the builder's message (tests and
/// benches only).
pub fn load_mesh(path: &Path, weld: bool) -> Mesh {
    let soup = geodesics_io::read_mesh(path).unwrap_or_else(|e| panic!("{e}"));
    Mesh::build(
        soup,
        &BuildOptions {
            weld,
            reorder: true,
        },
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// One mesh of the reference manifest (`reference/manifest.json`, or
/// `reference/synthetic/manifest.json`), loaded, with its reference files.
pub struct ReferenceMesh {
    /// The mesh, welded when the manifest key ends in `.welded`.
    pub mesh: Mesh,
    /// The mesh's file name (the key without `.welded`).
    pub file: String,
    /// Its reference files, in manifest order (by name).
    pub files: Vec<ReferenceFile>,
    /// Seconds spent reading and building the mesh.
    pub load_seconds: f64,
}

/// One reference distance file of the manifest.
pub struct ReferenceFile {
    /// File name, e.g. `bunny.off.src0.txt`.
    pub name: String,
    /// The source vertices it was computed from (distance to the nearest).
    pub sources: Vec<Source>,
    /// The largest finite distance in it (the scale of the error bar).
    pub max_finite: f64,
    /// Vertices gdist wrongly left unreached (a solver must reach them).
    pub oracle_misses: HashSet<usize>,
    path: PathBuf,
}

impl ReferenceFile {
    /// Reads the reference distances, one per vertex in file numbering.
    pub fn distances(&self) -> Vec<f64> {
        read_distances(&self.path)
    }
}

/// Loads manifest entry `key` (for example `bunny.off` or
/// `dragon.ply.welded`; `synthetic` for the meshes under `synthetic/`), or
/// `None` after a loud SKIPPED line naming `what` when the mesh folder is
/// absent. Panics if the key is not in the manifest: a test that names a
/// mesh must check it.
pub fn reference_mesh(what: &str, key: &str, synthetic: bool) -> Option<ReferenceMesh> {
    let data = data_dir(what)?;
    let (mut refdir, mut meshdir) = (reference_dir(&data), data);
    if synthetic {
        refdir = refdir.join("synthetic");
        meshdir = meshdir.join("synthetic");
    }
    let manifest_path = refdir.join("manifest.json");
    let text = std::fs::read_to_string(&manifest_path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", manifest_path.display()));
    let manifest: Value =
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", manifest_path.display()));
    let entry = &manifest["meshes"][key];
    assert!(
        entry.is_object(),
        "{key} not in {}",
        manifest_path.display()
    );
    let (file, weld) = match key.strip_suffix(".welded") {
        Some(f) => (f, true),
        None => (key, false),
    };
    let start = std::time::Instant::now();
    let mesh = load_mesh(&meshdir.join(file), weld);
    let load_seconds = start.elapsed().as_secs_f64();
    let files = entry["files"]
        .as_object()
        .unwrap_or_else(|| panic!("{key}: no files in the manifest"))
        .iter()
        .map(|(name, info)| {
            let vertex = |v: &Value| {
                v.as_u64()
                    .unwrap_or_else(|| panic!("{name}: a source is not a vertex index"))
                    as u32
            };
            ReferenceFile {
                name: name.clone(),
                sources: info["sources"]
                    .as_array()
                    .unwrap_or_else(|| panic!("{name}: no sources"))
                    .iter()
                    .map(|v| Source::Vertex(vertex(v)))
                    .collect(),
                max_finite: info["max_finite"]
                    .as_f64()
                    .unwrap_or_else(|| panic!("{name}: no max_finite")),
                oracle_misses: info
                    .get("oracle_misses")
                    .and_then(Value::as_array)
                    .map(|a| a.iter().map(|v| vertex(v) as usize).collect())
                    .unwrap_or_default(),
                path: refdir.join(name),
            }
        })
        .collect();
    Some(ReferenceMesh {
        mesh,
        file: file.to_string(),
        files,
        load_seconds,
    })
}

/// Expected statistics of one real mesh, from the table in the meshes' README.
#[derive(Clone, Copy, Debug)]
pub struct ExpectedMesh {
    /// File name in the data folder.
    pub file: &'static str,
    /// Whether to weld exactly equal positions first.
    pub weld: bool,
    /// Vertices.
    pub vertices: usize,
    /// Faces.
    pub faces: usize,
    /// Connected components.
    pub components: usize,
    /// Boundary loops.
    pub boundary_loops: usize,
    /// Euler characteristic.
    pub euler: i64,
    /// Genus (`None` where undefined).
    pub genus: Option<i64>,
    /// Non-manifold (pinch) vertices.
    pub nonmanifold_vertices: usize,
    /// Zero-area faces.
    pub zero_area_faces: usize,
    /// Vertices duplicating an earlier position.
    pub duplicate_positions: usize,
    /// Unreferenced vertices.
    pub unreferenced_vertices: usize,
}

const fn m(
    file: &'static str,
    weld: bool,
    counts: [usize; 4],
    euler: i64,
    genus: Option<i64>,
    defects: [usize; 4],
) -> ExpectedMesh {
    ExpectedMesh {
        file,
        weld,
        vertices: counts[0],
        faces: counts[1],
        components: counts[2],
        boundary_loops: counts[3],
        euler,
        genus,
        nonmanifold_vertices: defects[0],
        zero_area_faces: defects[1],
        duplicate_positions: defects[2],
        unreferenced_vertices: defects[3],
    }
}

/// The README's table (V, F, components, loops; χ; genus; non-manifold,
/// zero-area, duplicate, unreferenced), plus the welded dragon.
pub const REAL_MESHES: &[ExpectedMesh] = &[
    m(
        "armadillo.obj",
        false,
        [43243, 86482, 1, 0],
        2,
        Some(0),
        [0; 4],
    ),
    m("blade.off", false, [8231, 16222, 1, 2], 0, Some(0), [0; 4]),
    m("bunny.off", false, [34835, 69666, 1, 0], 2, Some(0), [0; 4]),
    m(
        "bunny_zipper.ply",
        false,
        [35947, 69451, 1, 5],
        -3,
        Some(0),
        [0, 0, 0, 1113],
    ),
    m(
        "camelhead.off",
        false,
        [11381, 22704, 1, 1],
        1,
        Some(0),
        [0; 4],
    ),
    m("cow.obj", false, [2903, 5804, 1, 0], 1, None, [1, 0, 0, 0]),
    m(
        "dragon.ply",
        false,
        [437645, 871414, 151, 407],
        -197,
        Some(46),
        [0, 108, 2100, 0],
    ),
    m(
        "dragon.ply",
        true,
        [435545, 871306, 1, 0],
        -108,
        Some(55),
        [0; 4],
    ),
    m(
        "fandisk.obj",
        false,
        [6475, 12946, 1, 0],
        2,
        Some(0),
        [0; 4],
    ),
    m(
        "fertility.off",
        false,
        [4494, 9000, 1, 0],
        -6,
        Some(4),
        [0; 4],
    ),
    m("hand.off", false, [1197, 2390, 1, 0], 2, Some(0), [0; 4]),
    m("knot.stl", false, [3200, 6400, 1, 0], 0, Some(1), [0; 4]),
    m(
        "rockerarm.off",
        false,
        [10044, 20088, 1, 0],
        0,
        Some(1),
        [0; 4],
    ),
    m(
        "screw_m3x10.stl",
        false,
        [7768, 15532, 1, 0],
        2,
        Some(0),
        [0; 4],
    ),
    m(
        "skull.glb",
        false,
        [49999, 100002, 1, 0],
        -2,
        Some(2),
        [0; 4],
    ),
];

/// Shortest distances from vertex `source` along mesh edges only (Dijkstra
/// on the edge graph): an upper bound for every geodesic distance, and what
/// AVTP tends to with a tiny λ. Per mesh vertex (pinch copies separate).
pub fn edge_graph_distances(mesh: &Mesh, source: u32) -> Vec<f64> {
    let n = mesh.vertex_count();
    let mut d = vec![f64::INFINITY; n];
    let mut heap = BinaryHeap::new();
    d[source as usize] = 0.0;
    heap.push(Reverse((0u64, source)));
    while let Some(Reverse((k, v))) = heap.pop() {
        if k != d[v as usize].to_bits() {
            continue;
        }
        for h in mesh.outgoing(v) {
            for (u, l) in [
                (mesh.head(h), mesh.length(h)),
                (mesh.tail(Mesh::prev(h)), mesh.length(Mesh::prev(h))),
            ] {
                let nd = d[v as usize] + l;
                if nd < d[u as usize] {
                    d[u as usize] = nd;
                    heap.push(Reverse((nd.to_bits(), u)));
                }
            }
        }
    }
    d
}
