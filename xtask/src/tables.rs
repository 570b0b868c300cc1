//! `cargo xtask tables`: every algorithm of the facade on `bunny.off` and
//! `armadillo.obj` from vertex 0, in the layout of Tables 1 and 3 of Qin et
//! al. 2016: time, window propagations and peak window memory, each as a
//! ratio to VTP measured in the same run.

use std::time::Instant;

use anyhow::Result;
use geodesics::{Algorithm, BuildOptions, Mesh, Source, Stats};

use crate::{data_dir, read};

/// The best of `runs` solves from vertex 0, with the stats of that run.
fn best(mesh: &Mesh, algorithm: &Algorithm, runs: usize) -> Result<(f64, Stats)> {
    let mut best: Option<(f64, Stats)> = None;
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        let (_, stats) = geodesics::compute(mesh, &[Source::Vertex(0)], algorithm)?;
        let s = t.elapsed().as_secs_f64();
        if best.as_ref().is_none_or(|(b, _)| s < *b) {
            best = Some((s, stats));
        }
    }
    Ok(best.expect("at least one run"))
}

pub fn table(runs: usize) -> Result<()> {
    let dir = data_dir()?;
    println!("Every algorithm from vertex 0, best of {runs} runs (solve only)\n");
    for file in ["bunny.off", "armadillo.obj"] {
        let mesh = Mesh::build(read(&dir.join(file))?, &BuildOptions::default())?;
        println!("{file} ({} faces)\n", mesh.face_count());
        println!(
            "| algorithm | s | × VTP time | propagations | × VTP propagations | peak windows | peak window KiB |"
        );
        println!("|---|---:|---:|---:|---:|---:|---:|");
        let (vtp_s, vtp) = best(&mesh, &Algorithm::default(), runs)?;
        for &name in Algorithm::NAMES {
            let algorithm: Algorithm = name.parse()?;
            let (s, st) = if name == "vtp" {
                (vtp_s, vtp.clone())
            } else {
                best(&mesh, &algorithm, runs)?
            };
            println!(
                "| {name} | {s:.3} | {:.2} | {} | {:.2} | {} | {:.0} |",
                s / vtp_s,
                st.window_propagations,
                st.window_propagations as f64 / vtp.window_propagations.max(1) as f64,
                st.peak_live_windows,
                st.peak_window_bytes as f64 / 1024.0
            );
        }
        println!();
    }
    Ok(())
}
