//! `cargo xtask pvtp`: how PVTP scales with threads against sequential VTP
//! measured in the same run (the scaling table of the PVTP issue), on
//! meshes of at least 200K faces.

use anyhow::Result;
use geodesics::{Algorithm, PvtpOptions};

use crate::{Interleaved, build_renumbered, data_dir, read};

pub fn table(runs: usize, large: bool) -> Result<()> {
    let dir = data_dir()?;
    let bunny = read(&dir.join("bunny.off"))?;
    let mut cases = vec![
        (
            "bunny.off, Loop x1".to_string(),
            build_renumbered(geodesics_shapes::loop_subdivide(&bunny, 1)?, false)?,
        ),
        (
            "dragon.ply, welded".to_string(),
            build_renumbered(read(&dir.join("dragon.ply"))?, true)?,
        ),
    ];
    if large {
        cases.push((
            "bunny.off, Loop x2".to_string(),
            build_renumbered(geodesics_shapes::loop_subdivide(&bunny, 2)?, false)?,
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
        "PVTP against VTP from vertex 0, {runs} interleaved rounds (each round runs VTP and every T once; solve only), {cores} logical CPUs\n"
    );
    println!(
        "| mesh | F | solver | T | best s | speed-up over T=1 | speed-up over VTP | propagations / VTP's | phases | outside the phases |"
    );
    println!("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|");
    for (name, mesh) in cases {
        let mut algorithms = vec![Algorithm::default()];
        algorithms.extend(threads.iter().map(|&t| {
            Algorithm::Pvtp(PvtpOptions {
                threads: t,
                ..PvtpOptions::default()
            })
        }));
        let timed = Interleaved::run(&mesh, &algorithms, runs)?;
        let vtp = &timed.fastest[0].1;
        println!(
            "| {name} | {} | VTP | 1 | {:.3} | — | 1.00 | 1.000 | — | — |",
            mesh.face_count(),
            timed.best(0)
        );
        for (k, &t) in threads.iter().enumerate() {
            let i = k + 1;
            let st = &timed.fastest[i].1;
            // The one-thread part (selection, delayed writes, setup): what
            // bounds the speed-up, whatever T.
            let outside = st.management_seconds;
            println!(
                "| {name} | {} | PVTP | {t} | {:.3} | {} | {} | {:.3} | {} | {:.3} s ({:.0} %) |",
                mesh.face_count(),
                timed.best(i),
                timed.speed_up(1, i),
                timed.speed_up(0, i),
                st.window_propagations as f64 / vtp.window_propagations.max(1) as f64,
                st.parallel_phases,
                outside,
                100.0 * outside / st.total_seconds.max(f64::MIN_POSITIVE)
            );
        }
    }
    println!(
        "\nSpeed-ups: the median over the rounds of the ratio within a round (range in brackets). Outside the phases: the solve's time on one thread (selection, delayed writes, setup) in the fastest run, and its share of that run."
    );
    Ok(())
}
