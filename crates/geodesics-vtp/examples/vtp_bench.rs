//! Times one VTP solve on a mesh file: `vtp_bench MESH [SOURCE_VERTEX] [REPEATS]`.
//!
//! Prints the best wall time over the repeats and the solve's statistics.

use geodesics_mesh::{BuildOptions, Mesh};
use geodesics_vtp::{VtpOptions, solve};
use geodesics_window::Source;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: vtp_bench MESH [SOURCE] [REPEATS]")?;
    let source: u32 = args.next().map_or(Ok(0), |s| s.parse())?;
    let repeats: usize = args.next().map_or(Ok(5), |s| s.parse())?;
    let weld = std::env::var_os("WELD").is_some();
    let mesh = Mesh::build(
        geodesics_io::read_mesh(path.as_ref())?,
        &BuildOptions { weld },
    )?;
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let t = std::time::Instant::now();
        let (_, stats) = solve(&mesh, &[Source::Vertex(source)], &VtpOptions::default())?;
        best = best.min(t.elapsed().as_secs_f64());
        last = Some(stats);
    }
    let s = last.ok_or("no run")?;
    println!(
        "{path} from {source}: best {best:.4} s, {} propagations ({} prime, {} secondary), {:.1} ns/propagation, peak {} live windows ({} bytes), {} pops, {} emissions",
        s.window_propagations,
        s.prime_propagations,
        s.secondary_propagations,
        best * 1e9 / s.window_propagations as f64,
        s.peak_live_windows,
        s.peak_window_bytes,
        s.vertex_pops,
        s.pseudo_source_emissions
    );
    println!(
        "phases: propagation {:.4} s, pruning {:.4} s, management {:.4} s, total {:.4} s",
        s.propagation_seconds, s.pruning_seconds, s.management_seconds, s.total_seconds
    );
    Ok(())
}
