//! Times one VTP solve on a mesh file: `vtp_bench MESH [SOURCE_VERTEX] [REPEATS]`.
//!
//! Prints the best wall time over the repeats and the solve's statistics.
//! With `LAMBDA=L` in the environment it runs AVTP (a window reset every
//! `L` mean edge lengths) and also prints its error against exact VTP.

use geodesics_mesh::{BuildOptions, Mesh};
use geodesics_vtp::{VtpOptions, WindowReset, solve};
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
        &BuildOptions {
            weld,
            reorder: true,
        },
    )?;
    let reset = std::env::var("LAMBDA")
        .ok()
        .map(|l| l.parse::<f64>().map(WindowReset::every))
        .transpose()?;
    let options = VtpOptions {
        reset,
        ..VtpOptions::default()
    };
    let sources = [Source::Vertex(source)];
    let mut best = f64::INFINITY;
    let mut last = None;
    let mut field = None;
    for _ in 0..repeats.max(1) {
        let t = std::time::Instant::now();
        let (f, stats) = solve(&mesh, &sources, &options)?;
        best = best.min(t.elapsed().as_secs_f64());
        last = Some(stats);
        field = Some(f);
    }
    if let (Some(_), Some(approx)) = (reset, &field) {
        let (exact, _) = solve(&mesh, &sources, &VtpOptions::default())?;
        let (mut sum, mut max, mut n, mut below) = (0.0, 0.0f64, 0usize, 0usize);
        for (a, e) in approx.distance.iter().zip(&exact.distance) {
            if e.is_finite() && *e > 0.0 {
                let r = (a - e) / e;
                sum += r;
                max = max.max(r);
                n += 1;
                below += usize::from(r < -1e-12);
            }
        }
        println!(
            "AVTP error vs exact: mean {:.3e}, max {:.3e} relative over {n} vertices ({below} below exact)",
            sum / n.max(1) as f64,
            max
        );
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
