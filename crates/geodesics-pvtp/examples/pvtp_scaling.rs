//! How PVTP scales with threads, against the sequential VTP in the same run.
//!
//! ```text
//! cargo run --release -p geodesics-pvtp --example pvtp_scaling -- [MESH] [--weld]
//!     [--subdivide N] [--source V] [--runs R] [--threads 1,2,4] [--no-vtp]
//! ```
//!
//! Without `MESH` it loads `bunny.off` from `GEODESICS_DATA` (default
//! `../shared/data/meshes`) and Loop-subdivides it once (278,664 faces).
//! `--subdivide N` applies N Loop steps to any mesh. Prints, per solver, the
//! best of `R` runs (default 5), speed-ups, window propagations, and the
//! largest difference from VTP's distances (relative to the largest).
//! `--no-vtp` runs VTP once only, untimed (for profiling PVTP alone).

use std::path::PathBuf;
use std::time::Instant;

use geodesics_mesh::{BuildOptions, Mesh};
use geodesics_pvtp::PvtpOptions;
use geodesics_window::Source;

fn main() {
    let mut args = std::env::args().skip(1);
    let mut path: Option<PathBuf> = None;
    let mut weld = false;
    let mut subdivide: Option<u32> = None;
    let mut source = 0u32;
    let mut runs = 5usize;
    let mut threads: Option<Vec<usize>> = None;
    let mut no_vtp = false;
    while let Some(a) = args.next() {
        let mut value = |name: &str| {
            args.next()
                .unwrap_or_else(|| fail(&format!("{name} needs a value")))
        };
        match a.as_str() {
            "--weld" => weld = true,
            "--no-vtp" => no_vtp = true,
            "--subdivide" => subdivide = Some(parse(&value("--subdivide"))),
            "--source" => source = parse(&value("--source")),
            "--runs" => runs = parse::<usize>(&value("--runs")).max(1),
            "--threads" => {
                threads = Some(value("--threads").split(',').map(parse).collect());
            }
            _ if a.starts_with("--") => fail(&format!("unknown option {a}")),
            _ => path = Some(PathBuf::from(a)),
        }
    }
    let default_mesh = path.is_none();
    let path = path.unwrap_or_else(|| {
        let dir = std::env::var_os("GEODESICS_DATA")
            .map(PathBuf::from)
            .unwrap_or_else(|| {
                PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes")
            });
        dir.join("bunny.off")
    });
    let subdivide = subdivide.unwrap_or(if default_mesh { 1 } else { 0 });
    let mut soup = geodesics_io::read_mesh(&path).unwrap_or_else(|e| fail(&e.to_string()));
    if subdivide > 0 {
        soup = geodesics_shapes::loop_subdivide(&soup, subdivide)
            .unwrap_or_else(|e| fail(&e.to_string()));
    }
    let mesh = Mesh::build(
        soup,
        &BuildOptions {
            weld,
            reorder: true,
        },
    )
    .unwrap_or_else(|e| fail(&e.to_string()));
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = threads.unwrap_or_else(|| (1..=cores).collect());
    println!(
        "{} (Loop x{subdivide}{}): {} vertices, {} faces, source {source}, best of {runs} runs, {cores} cores",
        path.display(),
        if weld { ", welded" } else { "" },
        mesh.input_vertex_count(),
        mesh.face_count()
    );
    let sources = [Source::Vertex(source)];

    let mut vtp_best = f64::INFINITY;
    let mut vtp = None;
    for _ in 0..if no_vtp { 1 } else { runs } {
        let t = Instant::now();
        let r = geodesics_vtp::solve(&mesh, &sources, &geodesics_vtp::VtpOptions::default())
            .unwrap_or_else(|e| fail(&e.to_string()));
        vtp_best = vtp_best.min(t.elapsed().as_secs_f64());
        vtp = Some(r);
    }
    let (vtp_field, vtp_stats) = vtp.unwrap_or_else(|| fail("no VTP run"));
    let max = vtp_field
        .distance
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max);
    println!(
        "VTP: {vtp_best:.3} s, {} propagations, peak {} windows",
        vtp_stats.window_propagations, vtp_stats.peak_live_windows
    );
    println!(
        "{:>3} {:>9} {:>9} {:>9} {:>12} {:>10} {:>10}",
        "T", "best s", "vs T=1", "vs VTP", "props/VTP", "parallel%", "err/max"
    );
    let mut t1 = None;
    for &t in &threads {
        let options = PvtpOptions {
            threads: t,
            ..PvtpOptions::default()
        };
        let mut best = f64::INFINITY;
        let mut last = None;
        for _ in 0..runs {
            let start = Instant::now();
            let r = geodesics_pvtp::solve(&mesh, &sources, &options)
                .unwrap_or_else(|e| fail(&e.to_string()));
            best = best.min(start.elapsed().as_secs_f64());
            last = Some(r);
        }
        let (field, stats) = last.unwrap_or_else(|| fail("no PVTP run"));
        let err = field
            .distance
            .iter()
            .zip(&vtp_field.distance)
            .map(|(a, b)| {
                if a.is_infinite() && b.is_infinite() {
                    0.0
                } else {
                    (a - b).abs()
                }
            })
            .fold(0.0, f64::max);
        let base = *t1.get_or_insert(best);
        println!(
            "{t:>3} {best:>9.3} {:>9.2} {:>9.2} {:>12.4} {:>9.1}% {:>10.1e}",
            base / best,
            vtp_best / best,
            stats.window_propagations as f64 / vtp_stats.window_propagations as f64,
            100.0 * stats.propagation_seconds / stats.total_seconds,
            err / max
        );
    }
}

fn parse<T: std::str::FromStr>(s: &str) -> T {
    s.parse()
        .unwrap_or_else(|_| fail(&format!("cannot parse {s:?}")))
}

fn fail(msg: &str) -> ! {
    eprintln!("pvtp_scaling: {msg}");
    std::process::exit(2)
}
