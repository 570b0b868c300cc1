//! Times MMP and FWP-MMP from one source vertex on a mesh file:
//! `cargo run --release -p geodesics-mmp --example mmp_timing -- MESH [VERTEX] [pq|fwp|both]`.

use geodesics_mesh::{BuildOptions, Mesh};
use geodesics_mmp::{MmpOptions, Schedule, solve};
use geodesics_window::Source;

fn main() {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: mmp_timing MESH [VERTEX] [pq|fwp|both]");
        std::process::exit(2);
    };
    let v: u32 = args.next().and_then(|s| s.parse().ok()).unwrap_or(0);
    let which = args.next().unwrap_or_else(|| "both".into());
    let soup = geodesics_io::read_mesh(std::path::Path::new(&path)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
    let mesh = Mesh::build(soup, &BuildOptions::default()).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(1)
    });
    for (name, schedule) in [("MMP", Schedule::PriorityQueue), ("FWP-MMP", Schedule::Fwp)] {
        if (which == "pq" && schedule != Schedule::PriorityQueue)
            || (which == "fwp" && schedule != Schedule::Fwp)
        {
            continue;
        }
        let options = MmpOptions {
            schedule,
            ..MmpOptions::default()
        };
        let (field, stats) = solve(&mesh, &[Source::Vertex(v)], &options).unwrap_or_else(|e| {
            eprintln!("{e}");
            std::process::exit(1)
        });
        let max = field
            .distance
            .iter()
            .copied()
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max);
        println!(
            "{path} {name}: {:.3} s, {} propagations, {} windows created, {} kept, {:.1} MB window storage, max distance {max}",
            stats.total_seconds,
            stats.window_propagations,
            stats.windows_created,
            stats.peak_live_windows,
            stats.peak_window_bytes as f64 / 1e6
        );
    }
}
