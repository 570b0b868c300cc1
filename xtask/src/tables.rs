//! `cargo xtask tables`: every algorithm of the facade on `bunny.off` and
//! `armadillo.obj` from vertex 0, in the layout of Tables 1 and 3 of Qin et
//! al. 2016: time, window propagations and peak window memory, each as a
//! ratio to VTP measured in the same run.

use anyhow::Result;
use geodesics::Algorithm;

use crate::{best_of, build_renumbered, data_dir, read};

/// `only`: a comma-separated subset of the algorithm names (all if `None`).
pub fn table(runs: usize, only: Option<&str>) -> Result<()> {
    let names: Vec<&str> = match only {
        Some(list) => list.split(',').map(str::trim).collect(),
        None => Algorithm::NAMES.to_vec(),
    };
    for name in &names {
        name.parse::<Algorithm>()?;
    }
    let dir = data_dir()?;
    println!("Every algorithm from vertex 0, best of {runs} runs (solve only)\n");
    for file in ["bunny.off", "armadillo.obj"] {
        let mesh = build_renumbered(read(&dir.join(file))?, false)?;
        println!("{file} ({} faces)\n", mesh.face_count());
        println!(
            "| algorithm | s | × VTP time | propagations | × VTP propagations | peak windows | peak window KiB |"
        );
        println!("|---|---:|---:|---:|---:|---:|---:|");
        let (vtp_s, _, vtp) = best_of(&mesh, &Algorithm::default(), runs)?;
        for &name in &names {
            let algorithm: Algorithm = name.parse()?;
            let (s, st) = if name == "vtp" {
                (vtp_s, vtp.clone())
            } else {
                {
                    let (s, _, st) = best_of(&mesh, &algorithm, runs)?;
                    (s, st)
                }
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
