//! `cargo xtask avtp`: the accuracy/speed table of AVTP against exact VTP
//! measured in the same run (Table 1 and Fig 10 of Du et al. 2021).

use anyhow::Result;
use geodesics::{Algorithm, AvtpOptions, BuildOptions, Mesh};

use crate::{Interleaved, best_of, data_dir, read};

/// λ values of the table.
const LAMBDAS: [f64; 7] = [2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0];

/// Mean and max relative error of `approx` against `exact` over the
/// vertices at positive finite distance.
fn relative_errors(approx: &[f64], exact: &[f64]) -> (f64, f64) {
    let (mut sum, mut max, mut n) = (0.0, 0.0f64, 0usize);
    for (a, e) in approx.iter().zip(exact) {
        if e.is_finite() && *e > 0.0 {
            let r = (a - e) / e;
            sum += r;
            max = max.max(r);
            n += 1;
        }
    }
    (sum / n.max(1) as f64, max)
}

pub fn table(runs: usize, large: bool) -> Result<()> {
    let dir = data_dir()?;
    let bunny = read(&dir.join("bunny.off"))?;
    let mut cases = vec![
        ("bunny.off".to_string(), bunny.clone()),
        (
            "armadillo.obj".to_string(),
            read(&dir.join("armadillo.obj"))?,
        ),
        (
            "bunny.off, Loop x1".to_string(),
            geodesics_shapes::loop_subdivide(&bunny, 1)?,
        ),
    ];
    if large {
        cases.push((
            "bunny.off, Loop x2".to_string(),
            geodesics_shapes::loop_subdivide(&bunny, 2)?,
        ));
    }
    println!(
        "AVTP against exact VTP from vertex 0, best of {runs} runs (solve only); AVTP and PAVTP in {runs} interleaved rounds, their speed-up the median (range) of the per-round ratios\n"
    );
    println!(
        "| mesh | F | λ | s | speed-up over VTP | propagations | mean rel. error | max rel. error | PAVTP T=2 s | PAVTP speed-up over AVTP | PAVTP mean rel. error |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (name, soup) in cases {
        let mesh = Mesh::build(soup, &BuildOptions::default())?;
        let (vtp_s, exact, vtp_stats) = best_of(&mesh, &Algorithm::default(), runs)?;
        println!(
            "| {name} | {} | exact VTP | {vtp_s:.3} | 1.0 | {} | 0 | 0 | | | |",
            mesh.face_count(),
            vtp_stats.window_propagations
        );
        for lambda in LAMBDAS {
            let sequential = Algorithm::Avtp(AvtpOptions::with_lambda(lambda));
            let parallel = Algorithm::Avtp(AvtpOptions {
                threads: Some(2),
                ..AvtpOptions::with_lambda(lambda)
            });
            // AVTP and PAVTP alternate, so their ratio is taken per round.
            let timed = Interleaved::run(&mesh, &[sequential, parallel], runs)?;
            let (s, ps) = (timed.best(0), timed.best(1));
            let (field, stats) = &timed.fastest[0];
            let (mean, max) = relative_errors(&field.distance, &exact.distance);
            let (pmean, _) = relative_errors(&timed.fastest[1].0.distance, &exact.distance);
            println!(
                "| {name} | {} | {lambda} | {s:.3} | {:.2} | {} | {mean:.2e} | {max:.2e} | {ps:.3} | {} | {pmean:.2e} |",
                mesh.face_count(),
                vtp_s / s,
                stats.window_propagations,
                timed.speed_up(0, 1)
            );
        }
    }
    Ok(())
}
