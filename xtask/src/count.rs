//! `cargo xtask count [--algorithms a,b,..]`: instructions and simulated
//! data-cache misses per solve, from valgrind's cachegrind, on `bunny.off`
//! and `armadillo.obj` from vertex 0.
//!
//! Unlike times, these counts are the same on every run of the same binary,
//! so they settle a change to a hot path in minutes on a noisy machine (and
//! suit CI benchmarks). The solve alone is counted: each case runs once
//! with one solve and once with three, and half the difference is one
//! solve (loading and building the mesh cancel). The last-level cache is
//! set to 2 MB, the L2 of our machines, so its misses are the loads that
//! leave the core. Instructions are not time: much of a solve waits on
//! loads (see docs/architecture.md).
//!
//! Parallel solvers are counted on one thread (the counts of several
//! threads depend on their timing).

use std::process::Command;

use anyhow::{Context, Result, bail};
use geodesics::{Algorithm, Source};

use crate::report::{Cell, Column, JsonFile, Report};
use crate::{build_renumbered, data_dir, read};

const MESHES: [&str; 2] = ["bunny.off", "armadillo.obj"];
const DEFAULT_ALGORITHMS: &str = "vtp,avtp,pvtp";

/// One cachegrind run: totals of the whole process.
#[derive(Clone, Copy, Debug)]
struct Counts {
    instructions: u64,
    l1_misses: u64,
    l2_misses: u64,
}

/// The table. `only`: a comma-separated list of algorithm names.
pub fn table(only: Option<&str>, json: Option<JsonFile>) -> Result<()> {
    let names: Vec<&str> = only
        .unwrap_or(DEFAULT_ALGORITHMS)
        .split(',')
        .map(str::trim)
        .collect();
    for name in &names {
        name.parse::<Algorithm>()?;
    }
    let version = Command::new("valgrind").arg("--version").output();
    if !version.is_ok_and(|o| o.status.success()) {
        bail!(
            "valgrind not found: `cargo xtask count` needs it (Debian: apt-get install valgrind)"
        );
    }
    let dir = data_dir()?;
    let mut report = Report::new("count", None, &dir, json)?;
    let exe = std::env::current_exe().context("the xtask binary's own path")?;
    report.table(
        Some(
            "Per solve from vertex 0 (cachegrind: one solve subtracted from three, halved; L2 simulated at 2 MB; parallel solvers on 1 thread)".to_string(),
        ),
        [
            vec![Column::left("mesh"), Column::left("algorithm")],
            Column::rights(&[
                "instructions",
                "L1 data misses",
                "L2 data misses",
                "propagations",
            ]),
        ]
        .concat(),
    );
    for file in MESHES {
        let path = dir.join(file);
        for &name in &names {
            let (one, propagations) = cachegrind(&exe, &path, name, 1)?;
            let (three, _) = cachegrind(&exe, &path, name, 3)?;
            let per_solve = |f: fn(&Counts) -> u64| f(&three).saturating_sub(f(&one)) / 2;
            report.row(vec![
                Cell::text(file),
                Cell::text(name),
                Cell::shown(per_solve(|c| c.instructions)),
                Cell::shown(per_solve(|c| c.l1_misses)),
                Cell::shown(per_solve(|c| c.l2_misses)),
                propagations_cell(propagations),
            ]);
        }
    }
    report.finish()
}

/// The propagations `solve-times` printed: printed as they came, written
/// as a number when they are one.
fn propagations_cell(printed: String) -> Cell {
    match printed.parse::<u64>() {
        Ok(n) => Cell::new(printed, n.into()),
        Err(_) => Cell::text(printed),
    }
}

/// Runs `solves` solves of `name` on `mesh` under cachegrind: its totals
/// and the propagations of one solve.
fn cachegrind(
    exe: &std::path::Path,
    mesh: &std::path::Path,
    name: &str,
    solves: usize,
) -> Result<(Counts, String)> {
    let out = Command::new("valgrind")
        .args([
            "--tool=cachegrind",
            "--cache-sim=yes",
            "--LL=2097152,16,64",
            "--cachegrind-out-file=/dev/null",
        ])
        .arg(exe)
        .arg("solve-times")
        .arg(mesh)
        .arg(name)
        .arg(solves.to_string())
        .output()
        .context("running valgrind")?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        bail!(
            "cachegrind of {name} on {} failed:\n{stderr}",
            mesh.display()
        );
    }
    // Summary lines such as `==123== I   refs:      1,209,494,209`.
    let total = |label: &str| -> Result<u64> {
        let line = stderr
            .lines()
            .find(|l| l.contains(label))
            .with_context(|| format!("no `{label}` line in cachegrind's summary"))?;
        let after = line.split_once(':').map_or("", |(_, rest)| rest);
        let digits: String = after
            .split_whitespace()
            .next()
            .unwrap_or("")
            .chars()
            .filter(char::is_ascii_digit)
            .collect();
        digits.parse().with_context(|| format!("reading `{line}`"))
    };
    let counts = Counts {
        instructions: total("I   refs:")?,
        l1_misses: total("D1  misses:")?,
        l2_misses: total("LLd misses:")?,
    };
    let propagations = String::from_utf8_lossy(&out.stdout).trim().to_string();
    Ok((counts, propagations))
}

/// `cargo xtask solve-times MESH ALGORITHM N` (run by [`table`] under
/// cachegrind): builds `MESH` as the CLI does and solves from vertex 0 `N`
/// times on one thread; prints the propagations of a solve.
pub fn solve_times(args: &[String]) -> Result<()> {
    let [mesh, name, solves] = args else {
        bail!("usage: cargo xtask solve-times MESH ALGORITHM N");
    };
    let solves: usize = solves.parse().context("N: a number of solves")?;
    let algorithm = match name.parse::<Algorithm>()? {
        Algorithm::Pvtp(o) => Algorithm::Pvtp(geodesics::PvtpOptions { threads: 1, ..o }),
        Algorithm::Avtp(o) => Algorithm::Avtp(geodesics::AvtpOptions {
            threads: o.threads.map(|_| 1),
            ..o
        }),
        other => other,
    };
    let mesh = build_renumbered(read(std::path::Path::new(mesh))?, false)?;
    let mut propagations = 0;
    for _ in 0..solves {
        let (_, stats) = geodesics::compute(&mesh, &[Source::Vertex(0)], &algorithm)?;
        propagations = stats.window_propagations;
    }
    println!("{propagations}");
    Ok(())
}
