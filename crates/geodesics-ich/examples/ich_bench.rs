//! Times ICH and FWP-CH on a mesh file:
//! `ich_bench MESH [SOURCE_VERTEX] [REPEATS]` (`WELD=1` welds first).
//!
//! Prints, per schedule, the best wall time over the repeats and the
//! solve's statistics (window propagations, windows created, peak live
//! windows and their bytes), and the largest difference between the two.

use geodesics_ich::{IchOptions, solve};
use geodesics_mesh::{BuildOptions, Mesh};
use geodesics_window::Source;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: ich_bench MESH [SOURCE] [REPEATS]")?;
    let source: u32 = args.next().map_or(Ok(0), |s| s.parse())?;
    let repeats: usize = args.next().map_or(Ok(3), |s| s.parse())?;
    let weld = std::env::var_os("WELD").is_some();
    let mesh = Mesh::build(
        geodesics_io::read_mesh(path.as_ref())?,
        &BuildOptions {
            weld,
            reorder: true,
        },
    )?;
    let sources = [Source::Vertex(source)];
    let mut fields = Vec::new();
    for (name, options) in [("ich", IchOptions::ich()), ("fwp-ch", IchOptions::fwp_ch())] {
        let mut best = f64::INFINITY;
        let mut last = None;
        for _ in 0..repeats.max(1) {
            let (f, stats) = solve(&mesh, &sources, &options)?;
            best = best.min(stats.total_seconds);
            last = Some((f, stats));
        }
        let (f, s) = last.ok_or("no run")?;
        println!(
            "{name:7} {path} from {source}: best {best:.3}s of {repeats}, {} propagations, {} windows created, peak {} windows ({:.2} MB), {} pseudo-source emissions",
            s.window_propagations,
            s.windows_created,
            s.peak_live_windows,
            s.peak_window_bytes as f64 / 1e6,
            s.pseudo_source_emissions,
        );
        fields.push(f.distance);
    }
    let diff = fields[0]
        .iter()
        .zip(&fields[1])
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("max |ich - fwp-ch| = {diff:.3e}");
    Ok(())
}
