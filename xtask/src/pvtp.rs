//! `cargo xtask pvtp`: how PVTP scales with threads against sequential VTP
//! measured in the same run (the scaling table of the PVTP issue), on
//! meshes of at least 200K faces.

use anyhow::Result;
use geodesics::{Algorithm, BuildOptions, Mesh, PvtpOptions};

use crate::{best_of, data_dir, read};

pub fn table(runs: usize, large: bool) -> Result<()> {
    let dir = data_dir()?;
    let bunny = read(&dir.join("bunny.off"))?;
    let mut cases = vec![
        (
            "bunny.off, Loop x1".to_string(),
            Mesh::build(
                geodesics_shapes::loop_subdivide(&bunny, 1)?,
                &BuildOptions::default(),
            )?,
        ),
        (
            "dragon.ply, welded".to_string(),
            Mesh::build(read(&dir.join("dragon.ply"))?, &BuildOptions { weld: true })?,
        ),
    ];
    if large {
        cases.push((
            "bunny.off, Loop x2".to_string(),
            Mesh::build(
                geodesics_shapes::loop_subdivide(&bunny, 2)?,
                &BuildOptions::default(),
            )?,
        ));
    }
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    let mut threads: Vec<usize> = vec![1, 2];
    let mut t = 4;
    while t <= cores {
        threads.push(t);
        t *= 2;
    }
    if !threads.contains(&cores) {
        threads.push(cores);
    }
    println!(
        "PVTP against VTP from vertex 0, best of {runs} runs (solve only), {cores} logical CPUs\n"
    );
    println!(
        "| mesh | F | solver | T | s | speed-up over T=1 | speed-up over VTP | propagations / VTP's |"
    );
    println!("|---|---:|---|---:|---:|---:|---:|---:|");
    for (name, mesh) in cases {
        let (vtp_s, _, vtp) = best_of(&mesh, &Algorithm::default(), runs)?;
        println!(
            "| {name} | {} | VTP | 1 | {vtp_s:.3} | — | 1.00 | 1.000 |",
            mesh.face_count()
        );
        let mut one = None;
        for &t in &threads {
            let algorithm = Algorithm::Pvtp(PvtpOptions {
                threads: t,
                ..PvtpOptions::default()
            });
            let (s, st) = {
                let (s, _, st) = best_of(&mesh, &algorithm, runs)?;
                (s, st)
            };
            let base = *one.get_or_insert(s);
            println!(
                "| {name} | {} | PVTP | {t} | {s:.3} | {:.2} | {:.2} | {:.3} |",
                mesh.face_count(),
                base / s,
                vtp_s / s,
                st.window_propagations as f64 / vtp.window_propagations.max(1) as f64
            );
        }
    }
    Ok(())
}
