//! Project automation, run as `cargo xtask <command>` (an alias in
//! `.cargo/config.toml`, always built in release mode).
//!
//! - `cargo xtask bench [--runs N] [--large]`: the VTP table of the exact-VTP
//!   issue (solve time, ns per window propagation, propagations, peak window
//!   memory) on `bunny.off`, `armadillo.obj`, `bunny.off` after one Loop
//!   step, and the coarse bunny after three (235K faces: `bunny.off`
//!   simplified to the 3,674 faces of the low-resolution bunny the authors
//!   subdivide, so their figures for it compare), with gdist (an
//!   independent MMP) timed in the same run when its environment exists,
//!   and the authors' published figures beside ours; then the peak resident
//!   memory of a whole `geodesics distance` process on `bunny.off` and
//!   `armadillo.obj` (a separate process each), against the authors' VTP
//!   process. `--large` adds a second Loop step of `bunny.off` (1.1 M
//!   faces) and a fourth of the coarse bunny (940K faces).
//! - `cargo xtask avtp [--runs N] [--large]`: AVTP's accuracy/speed table,
//!   λ from 2 to 128 against exact VTP in the same run, on the same meshes,
//!   with PAVTP at T=2 against AVTP (over all rounds, and over those the
//!   cores' slow periods missed: see `cores.rs`), then how much the mean
//!   error falls per doubling of λ, from vertex 0 and averaged over 8
//!   sources.
//! - `cargo xtask pvtp [--runs N] [--large]`: PVTP's scaling, both
//!   schedules (the default regions and the paper's rounds), T = 1, 2, …
//!   up to the machine's CPUs, against VTP in the same run, on the
//!   Loop-subdivided bunnies and the welded dragon, with the time each solve
//!   spends outside its parallel phases (what bounds the speed-up), T
//!   independent VTP solves at once (what the machine allows T threads)
//!   and the cross-core round trip sampled before each round (on shared
//!   VMs it varies tenfold, and PVTP's gain with it).
//! - `cargo xtask tables [--runs N] [--algorithms a,b,..]`: every algorithm
//!   (or those named) on `bunny.off` and `armadillo.obj` (Tables 1 and 3 of
//!   the VTP paper): time, propagations and peak window memory, with ratios
//!   to VTP from the same run.
//! - `cargo xtask load [--runs N]`: read and topology-build times of every
//!   real mesh.
//! - `cargo xtask sweep [--cases N] [--seed S] [--meshes a,b,..] [--large]`:
//!   every solver against our MMP from random sources (vertices, points on
//!   edges and in faces, several at once, with a distance limit) on every
//!   mesh, exact ones to 1e-12 of the largest distance, AVTP/PAVTP never
//!   below exact, paths as long as the distance, symmetry; fails on any
//!   disagreement (see `sweep.rs`). `--large` adds the dragon.
//! - `cargo xtask count [--algorithms a,b,..]`: instructions and simulated
//!   cache misses per solve (valgrind's cachegrind) on `bunny.off` and
//!   `armadillo.obj`: the same on every run, so they settle a change to a
//!   hot path on a noisy machine.
//!
//! Every one of these commands also takes `--json FILE`: it then writes the
//! numbers it prints to `FILE` as JSON (each table with its title, columns
//! and rows; numbers as numbers, unrounded; ratios printed as
//! `median (min–max)` as `{"median", "min", "max"}`), for CI benchmark
//! tracking and plots. The markdown on standard output is the same with or
//! without it. The file is written atomically, never over an existing file
//! that does not end in `.json` nor into the mesh folder.
//!
//! Meshes come from `GEODESICS_DATA` (default `../shared/data/meshes`).
//! Times are the minimum over the runs; only ratios measured in one run mean
//! much on a shared machine, so where a table compares solvers (PVTP's
//! threads against each other and VTP, PAVTP against AVTP, gdist against
//! VTP) their runs alternate and the table gives the median and range of
//! the per-round ratios: the same binary on this kind of machine has run
//! 1.6x slower one minute than the next.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

mod avtp;
mod cores;
mod count;
mod pvtp;
mod report;
mod sweep;
mod tables;

use anyhow::{Context, Result, bail, ensure};
use geodesics::{Algorithm, BuildOptions, Mesh, Source, Stats};
use report::{Cell, Column, JsonFile, Report};
use serde_json::json;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(command) = args.first() else {
        eprintln!("{}", usage());
        return Ok(());
    };
    if matches!(command.as_str(), "help" | "--help" | "-h")
        || args.iter().any(|a| a == "--help" || a == "-h")
    {
        println!("{}", usage());
        return Ok(());
    }
    // A misspelt flag would otherwise be ignored, and the table run for
    // many minutes without what was asked for.
    check_flags(command, &args[1..])?;
    let runs = flag_value(&args, "--runs")?.unwrap_or(3);
    let large = args.iter().any(|a| a == "--large");
    // Not for `solve-times`, whose arguments are positional.
    let json = || flag_json(&args);
    match command.as_str() {
        "bench" => bench(runs, large, json()?),
        "avtp" => avtp::table(runs, large, json()?),
        "tables" => tables::table(runs, flag_text(&args, "--algorithms"), json()?),
        "pvtp" => pvtp::table(runs, large, json()?),
        "load" => load(runs, json()?),
        "count" => count::table(flag_text(&args, "--algorithms"), json()?),
        "sweep" => sweep::sweep(
            flag_value(&args, "--cases")?.unwrap_or(5),
            flag_value(&args, "--seed")?.unwrap_or(1) as u64,
            flag_text(&args, "--meshes"),
            large,
            json()?,
        ),
        // Run by `count` under cachegrind, not by hand.
        "solve-times" => count::solve_times(&args[1..]),
        other => {
            bail!(
                "unknown xtask command `{other}` (try: bench, avtp, pvtp, tables, load, count, sweep)"
            )
        }
    }
}

/// A flag and the value it takes (`None`: a switch).
type Flag = (&'static str, Option<&'static str>);

/// The commands run by hand and their flags, each with the value it takes
/// (`None`: a switch); every one also takes `--json FILE`. The usage and
/// the flag check both read it.
const COMMANDS: &[(&str, &[Flag])] = &[
    ("bench", &[("--runs", Some("N")), ("--large", None)]),
    ("avtp", &[("--runs", Some("N")), ("--large", None)]),
    ("pvtp", &[("--runs", Some("N")), ("--large", None)]),
    (
        "tables",
        &[("--runs", Some("N")), ("--algorithms", Some("a,b"))],
    ),
    ("load", &[("--runs", Some("N"))]),
    ("count", &[("--algorithms", Some("a,b"))]),
    (
        "sweep",
        &[
            ("--cases", Some("N")),
            ("--seed", Some("S")),
            ("--meshes", Some("a,b")),
            ("--large", None),
        ],
    ),
];

fn usage() -> String {
    let commands: Vec<String> = COMMANDS
        .iter()
        .map(|(command, flags)| {
            let flags: Vec<String> = flags
                .iter()
                .map(|(flag, value)| match value {
                    Some(value) => format!(" [{flag} {value}]"),
                    None => format!(" [{flag}]"),
                })
                .collect();
            format!("{command}{}", flags.concat())
        })
        .collect();
    format!(
        "usage: cargo xtask {}; each also takes --json FILE (the printed numbers as JSON)",
        commands.join(" | ")
    )
}

/// Refuses a flag that `command` does not take, a value without its flag
/// and a flag missing its value. Nothing is checked for `solve-times`,
/// whose arguments are positional, nor for an unknown command (refused
/// as such later).
fn check_flags(command: &str, args: &[String]) -> Result<()> {
    let Some(&(_, taken)) = COMMANDS.iter().find(|(name, _)| *name == command) else {
        return Ok(());
    };
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        let takes_value = match taken.iter().find(|(flag, _)| flag == arg) {
            Some((_, value)) => value.is_some(),
            None if arg == "--json" => true,
            None => {
                bail!("`cargo xtask {command}` does not take `{arg}` (try `cargo xtask --help`)")
            }
        };
        if takes_value && rest.next().is_none() {
            bail!("{arg} takes a value");
        }
    }
    Ok(())
}

/// The text after `flag`, if given.
fn flag_text<'a>(args: &'a [String], flag: &str) -> Option<&'a str> {
    args.iter()
        .position(|a| a == flag)
        .and_then(|i| args.get(i + 1))
        .map(String::as_str)
}

/// The file after `--json`, checked (see [`JsonFile::new`]), if given.
fn flag_json(args: &[String]) -> Result<Option<JsonFile>> {
    match args.iter().position(|a| a == "--json") {
        None => Ok(None),
        Some(i) => {
            let path = args
                .get(i + 1)
                .filter(|p| !p.starts_with("--"))
                .context("--json takes a file name")?;
            Ok(Some(JsonFile::new(Path::new(path))?))
        }
    }
}

/// The number after `flag`, if given.
fn flag_value(args: &[String], flag: &str) -> Result<Option<usize>> {
    match args.iter().position(|a| a == flag) {
        None => Ok(None),
        Some(i) => {
            let v = args
                .get(i + 1)
                .with_context(|| format!("{flag} takes a number"))?;
            Ok(Some(v.parse().with_context(|| {
                format!("{flag} takes a number, got {v}")
            })?))
        }
    }
}

fn data_dir() -> Result<PathBuf> {
    geodesics_tests::data_dir("cargo xtask")
        .context("no mesh folder: set GEODESICS_DATA to the real meshes")
}

fn read(path: &Path) -> Result<geodesics::IndexedTriangles> {
    geodesics::io::read_mesh(path).with_context(|| path.display().to_string())
}

/// The best of `runs` solves of `algorithm` from vertex 0: seconds, the
/// field and the stats of that run ([`Interleaved`] with one algorithm).
/// Builds `soup` as the CLI does: renumbered for memory locality.
pub(crate) fn build_renumbered(soup: geodesics::IndexedTriangles, weld: bool) -> Result<Mesh> {
    Ok(Mesh::build(
        soup,
        &BuildOptions {
            weld,
            reorder: true,
        },
    )?)
}

pub(crate) fn best_of(
    mesh: &Mesh,
    algorithm: &Algorithm,
    runs: usize,
) -> Result<(f64, geodesics::DistanceField, Stats)> {
    let mut timed = Interleaved::run(mesh, std::slice::from_ref(algorithm), runs)?;
    let seconds = timed.best(0);
    let (field, stats) = timed.fastest.swap_remove(0);
    Ok((seconds, field, stats))
}

/// Solve times of several algorithms measured in interleaved rounds: each
/// round runs every algorithm once (starting one later each round), so a
/// machine that speeds up or slows down during the table affects all of
/// them alike. Ratios are then taken within a round.
pub(crate) struct Interleaved {
    /// Per algorithm, its time in each round.
    pub seconds: Vec<Vec<f64>>,
    /// Per algorithm, the field and stats of its fastest run.
    pub fastest: Vec<(geodesics::DistanceField, Stats)>,
}

impl Interleaved {
    /// Times `algorithms` on `mesh` from vertex 0 over `runs` rounds.
    pub fn run(mesh: &Mesh, algorithms: &[Algorithm], runs: usize) -> Result<Interleaved> {
        Interleaved::run_with(mesh, algorithms, runs, || {})
    }

    /// [`Interleaved::run`], calling `before_round` before each round
    /// (untimed: to sample the machine's state along the runs).
    pub fn run_with(
        mesh: &Mesh,
        algorithms: &[Algorithm],
        runs: usize,
        before_round: impl FnMut(),
    ) -> Result<Interleaved> {
        let fresh = vec![false; algorithms.len()];
        Interleaved::run_prepared(mesh, algorithms, &fresh, runs, before_round)
    }

    /// [`Interleaved::run_with`], where the algorithms flagged in
    /// `prepared` run on one `geodesics::PreparedMesh` kept across the
    /// rounds (laid out before the first, untimed), the others through
    /// `geodesics::compute`, setting up in every solve.
    pub fn run_prepared(
        mesh: &Mesh,
        algorithms: &[Algorithm],
        prepared: &[bool],
        runs: usize,
        mut before_round: impl FnMut(),
    ) -> Result<Interleaved> {
        let n = algorithms.len();
        let rounds = runs.max(1);
        let mut kept = geodesics::PreparedMesh::new(mesh);
        if let Some(i) = prepared.iter().position(|&p| p) {
            kept.compute(&[Source::Vertex(0)], &algorithms[i])?;
        }
        let mut seconds = vec![Vec::with_capacity(rounds); n];
        let mut fastest: Vec<Option<(f64, geodesics::DistanceField, Stats)>> = vec![None; n];
        for round in 0..rounds {
            before_round();
            for k in 0..n {
                let i = (k + round) % n;
                let t = Instant::now();
                let (field, stats) = if prepared[i] {
                    kept.compute(&[Source::Vertex(0)], &algorithms[i])?
                } else {
                    geodesics::compute(mesh, &[Source::Vertex(0)], &algorithms[i])?
                };
                let s = t.elapsed().as_secs_f64();
                seconds[i].push(s);
                if fastest[i].as_ref().is_none_or(|(b, _, _)| s < *b) {
                    fastest[i] = Some((s, field, stats));
                }
            }
        }
        let fastest = fastest
            .into_iter()
            .map(|f| {
                let (_, field, stats) = f.expect("every algorithm ran at least once");
                (field, stats)
            })
            .collect();
        Ok(Interleaved { seconds, fastest })
    }

    /// The fastest time of algorithm `i`.
    pub fn best(&self, i: usize) -> f64 {
        self.seconds[i]
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }

    /// How much faster `i` ran than `base`, round by round: the median and
    /// the range over the rounds.
    pub fn speed_up(&self, base: usize, i: usize) -> Spread {
        self.speed_up_in(base, i, |_| true)
    }

    /// [`Interleaved::speed_up`] over the rounds `keep` accepts (by
    /// number).
    pub fn speed_up_in(&self, base: usize, i: usize, keep: impl Fn(usize) -> bool) -> Spread {
        Spread::of(
            self.seconds[base]
                .iter()
                .zip(&self.seconds[i])
                .enumerate()
                .filter(|&(round, _)| keep(round))
                .map(|(_, (b, s))| b / s)
                .collect(),
        )
    }
}

/// Median and range of a few ratios.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Spread {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    pub fn of(mut values: Vec<f64>) -> Spread {
        values.sort_by(f64::total_cmp);
        let n = values.len();
        let median = if n == 0 {
            f64::NAN
        } else if n % 2 == 1 {
            values[n / 2]
        } else {
            0.5 * (values[n / 2 - 1] + values[n / 2])
        };
        Spread {
            median,
            min: values.first().copied().unwrap_or(f64::NAN),
            max: values.last().copied().unwrap_or(f64::NAN),
        }
    }
}

impl std::fmt::Display for Spread {
    /// `1.52 (1.40–1.61)`: the median and the range over the rounds.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:.2} ({:.2}–{:.2})", self.median, self.min, self.max)
    }
}

/// gdist's solve time from vertex 0 (mesh loading excluded) in one run,
/// through the oracle's environment, or `None` when it is not installed.
fn gdist_seconds(mesh: &Path) -> Option<f64> {
    let home = std::env::var_os("HOME")?;
    let venv = std::env::var_os("ORACLE_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(home).join(".cache/geodesics-oracle"));
    let python = venv.join("bin/python");
    let oracle =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/tools/oracle/oracle.py");
    if !python.exists() || !oracle.exists() {
        return None;
    }
    let out = std::env::temp_dir().join(format!("xtask-gdist-{}.txt", std::process::id()));
    let o = Command::new(&python)
        .arg(&oracle)
        .arg(mesh)
        .args(["--source", "0", "--out"])
        .arg(&out)
        .output()
        .ok();
    let _ = std::fs::remove_file(&out);
    let stderr = String::from_utf8_lossy(&o?.stderr).into_owned();
    // "gdist 2.9.2: 1.234 s"
    stderr.lines().find_map(|l| {
        let rest = l.strip_prefix("gdist ")?;
        let (_, t) = rest.split_once(": ")?;
        t.strip_suffix(" s")?.parse::<f64>().ok()
    })
}

/// Faces of the low-resolution Stanford bunny (1,839 vertices) that Du et
/// al. subdivide 3 and 4 times for their 235,136- and 940,544-face test
/// meshes (peer-figures.md). Their mesh is not public; ours is `bunny.off`
/// simplified to as many faces (the same vertex count comes out).
const AUTHORS_COARSE_BUNNY_FACES: usize = 3_674;

/// The coarse bunny (see [`AUTHORS_COARSE_BUNNY_FACES`]) after `steps` Loop
/// steps, with its table label: the same kind of mesh as the authors'
/// large ones, so their figures compare with ours (subdivisions of the
/// fine scan have many more saddles, which change what a window costs).
pub(crate) fn coarse_bunny(
    bunny: &geodesics::IndexedTriangles,
    steps: u32,
) -> Result<(String, geodesics::IndexedTriangles)> {
    let coarse = geodesics_shapes::simplify(bunny, AUTHORS_COARSE_BUNNY_FACES)?;
    Ok((
        format!("coarse bunny, Loop x{steps}"),
        geodesics_shapes::loop_subdivide(&coarse, steps)?,
    ))
}

/// A mesh of the speed table: name, triangles, and the authors' VTP seconds
/// and propagations from `peer-figures.md` where published.
struct BenchCase {
    name: String,
    soup: geodesics::IndexedTriangles,
    authors: Option<(f64, u64)>,
}

impl BenchCase {
    fn new(name: &str, soup: geodesics::IndexedTriangles, authors: Option<(f64, u64)>) -> Self {
        BenchCase {
            name: name.to_string(),
            soup,
            authors,
        }
    }
}

/// `cargo xtask bench`: the VTP speed table, gdist against VTP, then the
/// CLI's peak memory.
fn bench(runs: usize, large: bool, json: Option<JsonFile>) -> Result<()> {
    let dir = data_dir()?;
    let mut report = Report::new("bench", Some(runs), &dir, json)?;
    let bunny = read(&dir.join("bunny.off"))?;
    // (name, mesh, authors' VTP seconds and propagations from peer-figures.md)
    let mut cases = vec![
        BenchCase::new("bunny.off", bunny.clone(), Some((0.242, 1_673_219))),
        BenchCase::new(
            "armadillo.obj",
            read(&dir.join("armadillo.obj"))?,
            Some((0.282, 1_230_273)),
        ),
        BenchCase::new(
            "bunny.off, Loop x1",
            geodesics_shapes::loop_subdivide(&bunny, 1)?,
            None,
        ),
    ];
    let (name, soup) = coarse_bunny(&bunny, 3)?;
    cases.push(BenchCase::new(&name, soup, Some((1.67, 16_100_000))));
    if large {
        let soup = geodesics_shapes::loop_subdivide(&bunny, 2)?;
        cases.push(BenchCase::new("bunny.off, Loop x2", soup, None));
        let (name, soup) = coarse_bunny(&bunny, 4)?;
        cases.push(BenchCase::new(&name, soup, Some((28.3, 129_600_000))));
    }
    report.table(
        Some(format!(
            "VTP from vertex 0, best of {runs} runs (solve only; each round runs every mesh once, then gdist and VTP on bunny.off), on the mesh renumbered for locality as the CLI loads it; the file-order column solves the mesh kept in file order (`--keep-order`), alternating with the first. The machine is shared and its speed drifts: \"at reference speed\" scales ns / propagation by gdist's best time in this run against its time where the authors' figures were measured ({GDIST_REFERENCE_S} s on bunny.off, peer-figures.md)"
        )),
        [
            vec![Column::left("mesh")],
            Column::rights(&[
                "F",
                "VTP s",
                "ns / propagation",
                "ns / propagation at reference speed",
                "ns / propagation, file order",
                "propagations",
                "peak live windows",
                "peak window KiB",
                "authors' VTP s",
                "authors' propagations",
            ]),
        ]
        .concat(),
    );
    // Every mesh once per round, rounds over the whole table: the best of
    // a mesh's runs then comes from moments spread over the bench, not
    // from one stretch of seconds that a busy neighbour of the machine
    // may cover entirely.
    struct Timed {
        name: String,
        authors: Option<(f64, u64)>,
        mesh: Mesh,
        kept: Mesh,
        best: (f64, Stats),
        best_kept: (f64, Stats),
    }
    let mut timed = Vec::new();
    for BenchCase {
        name,
        soup,
        authors,
    } in cases
    {
        let kept = Mesh::build(soup.clone(), &BuildOptions::default())?;
        let mesh = build_renumbered(soup, false)?;
        let none = (f64::INFINITY, Stats::default());
        timed.push(Timed {
            name,
            authors,
            mesh,
            kept,
            best: none.clone(),
            best_kept: none,
        });
    }
    // gdist against VTP on bunny.off, a pair per round (the ratio taken
    // per pair), until gdist turns out not to be installed.
    let bunny_path = dir.join("bunny.off");
    let bunny = timed.iter().position(|case| case.name == "bunny.off");
    let mut pairs = Vec::new();
    let mut gdist_installed = true;
    // One solve of `mesh`, kept in `best` if it is the fastest yet.
    let solve_into = |mesh: &Mesh, best: &mut (f64, Stats)| -> Result<()> {
        let (t, _, stats) = best_of(mesh, &Algorithm::default(), 1)?;
        if t < best.0 {
            *best = (t, stats);
        }
        Ok(())
    };
    for _ in 0..runs.max(1) {
        for case in &mut timed {
            // Alternating, so that drift of the machine hits both alike.
            solve_into(&case.mesh, &mut case.best)?;
            solve_into(&case.kept, &mut case.best_kept)?;
        }
        if let Some(b) = bunny.filter(|_| gdist_installed) {
            match gdist_seconds(&bunny_path) {
                Some(g) => {
                    let (v, _, _) = best_of(&timed[b].mesh, &Algorithm::default(), 1)?;
                    pairs.push((g, v));
                }
                None => gdist_installed = false,
            }
        }
    }
    let best = |f: fn(&(f64, f64)) -> f64| pairs.iter().map(f).fold(f64::INFINITY, f64::min);
    let (gdist_best, vtp_best) = (best(|p| p.0), best(|p| p.1));
    // How much faster than now the machine ran when the reference was
    // measured (none without gdist).
    let to_reference = (!pairs.is_empty()).then(|| GDIST_REFERENCE_S / gdist_best);
    for case in timed {
        let ((s, st), (s_kept, st_kept)) = (case.best, case.best_kept);
        let ns_per_propagation = ns_per(s, &st);
        let (at, ap) = case
            .authors
            .map_or((Cell::missing(), Cell::missing()), |(t, p)| {
                (Cell::fixed(t, 3), Cell::shown(p))
            });
        report.row(vec![
            Cell::text(&case.name),
            Cell::shown(case.mesh.face_count()),
            Cell::fixed(s, 3),
            Cell::fixed(ns_per_propagation, 1),
            to_reference.map_or(Cell::missing(), |r| Cell::fixed(ns_per_propagation * r, 1)),
            Cell::fixed(ns_per(s_kept, &st_kept), 1),
            Cell::shown(st.window_propagations),
            Cell::shown(st.peak_live_windows),
            Cell::fixed(st.peak_window_bytes as f64 / 1024.0, 0),
            at,
            ap,
        ]);
    }
    report.note("");
    if pairs.is_empty() {
        report.note("gdist not measured: run ../shared/tools/oracle/setup.sh once to install it");
        report.section("gdist", serde_json::Value::Null);
    } else {
        let faster = Spread::of(pairs.iter().map(|(g, v)| g / v).collect());
        // Printed only: its numbers are the `gdist` section.
        println!(
            "gdist (MMP, tvb-gdist) on bunny.off from vertex 0, alternating with VTP, {} pairs: gdist best {gdist_best:.3} s, VTP best {vtp_best:.3} s; VTP faster by {faster} (median and range of the pairs)",
            pairs.len(),
        );
        report.section(
            "gdist",
            json!({
                "mesh": "bunny.off",
                "source": 0,
                "pairs": pairs.len(),
                "gdist_best_s": report::number(gdist_best),
                "gdist_reference_s": GDIST_REFERENCE_S,
                "vtp_best_s": report::number(vtp_best),
                "vtp_faster": Cell::spread(faster),
            }),
        );
    }
    memory(&mut report, &dir)?;
    report.finish()
}

/// Nanoseconds per window propagation of a solve of `seconds`.
fn ns_per(seconds: f64, stats: &Stats) -> f64 {
    1e9 * seconds / stats.window_propagations.max(1) as f64
}

/// gdist's solve time on bunny.off from vertex 0 on the machine where the
/// authors' figures were measured (`peer-figures.md`, the MMP column):
/// the anchor that scales this machine's timings to that one's speed.
const GDIST_REFERENCE_S: f64 = 1.377;

/// The authors' VTP process's peak resident memory, MB, from
/// `peer-figures.md`.
const AUTHORS_PEAK_RSS_MB: [(&str, f64); 2] = [("bunny.off", 43.0), ("armadillo.obj", 52.0)];

/// Bench's memory table: the peak resident memory of a whole
/// `geodesics distance MESH --source 0` process (read, build, solve,
/// write), as the authors' figure counts theirs. A separate process per
/// mesh: this one's peak is long past.
fn memory(report: &mut Report, dir: &Path) -> Result<()> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let built = Command::new(cargo)
        .args([
            "build",
            "--release",
            "--quiet",
            "--package",
            "geodesics-cli",
        ])
        .status()
        .context("building the geodesics CLI")?;
    ensure!(built.success(), "building the geodesics CLI failed");
    let cli = std::env::current_exe()?
        .with_file_name(format!("geodesics{}", std::env::consts::EXE_SUFFIX));
    report.note("");
    report.table(
        Some(
            "Peak resident memory of the whole `geodesics distance MESH --source 0` process (read, build, solve, write: VmHWM), against the authors' VTP process on the same mesh"
                .to_string(),
        ),
        [
            vec![Column::left("mesh")],
            Column::rights(&["peak RSS MiB", "authors' VTP peak RSS MB"]),
        ]
        .concat(),
    );
    let scratch = std::env::temp_dir().join(format!("xtask-memory-{}", std::process::id()));
    std::fs::create_dir_all(&scratch)?;
    let measured = (|| {
        for (name, authors) in AUTHORS_PEAK_RSS_MB {
            let (out, stats) = (scratch.join("d.txt"), scratch.join("stats.json"));
            let run = Command::new(&cli)
                .arg("distance")
                .arg(dir.join(name))
                .args(["--source", "0", "--output"])
                .arg(&out)
                .arg("--stats")
                .arg(&stats)
                .output()
                .with_context(|| format!("running {}", cli.display()))?;
            ensure!(
                run.status.success(),
                "geodesics distance {name}: {}",
                String::from_utf8_lossy(&run.stderr)
            );
            let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&stats)?)?;
            let rss = json["peak_rss_bytes"]
                .as_u64()
                .map_or(Cell::missing(), |b| {
                    Cell::fixed(b as f64 / (1 << 20) as f64, 1)
                });
            report.row(vec![Cell::text(name), rss, Cell::fixed(authors, 0)]);
        }
        Ok(())
    })();
    let _ = std::fs::remove_dir_all(&scratch);
    measured
}

/// The mesh files in `folder`, sorted (its README and notes left out).
pub(crate) fn mesh_files(folder: &Path) -> Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
        .with_context(|| folder.display().to_string())?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e != "md" && e != "jsonl"))
        .collect();
    files.sort();
    Ok(files)
}

/// `cargo xtask load`: read and build times of every mesh in the folder.
fn load(runs: usize, json: Option<JsonFile>) -> Result<()> {
    let dir = data_dir()?;
    let mut report = Report::new("load", Some(runs), &dir, json)?;
    let files = mesh_files(&dir)?;
    report.table(
        Some(format!(
            "Read and topology build, best of {runs} runs, {}",
            dir.display()
        )),
        [
            vec![Column::left("mesh")],
            Column::rights(&[
                "V",
                "F",
                "read s",
                "build s",
                "total s",
                "build s, renumbered (as the CLI)",
            ]),
        ]
        .concat(),
    );
    for path in files {
        let name = path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        let (mut read_s, mut build_s, mut size) = (f64::INFINITY, f64::INFINITY, (0, 0));
        let mut renumbered_s = f64::INFINITY;
        for _ in 0..runs.max(1) {
            let t = Instant::now();
            let soup = read(&path)?;
            read_s = read_s.min(t.elapsed().as_secs_f64());
            let t = Instant::now();
            let mesh = Mesh::build(soup.clone(), &BuildOptions::default())
                .with_context(|| name.clone())?;
            build_s = build_s.min(t.elapsed().as_secs_f64());
            size = (mesh.input_vertex_count(), mesh.face_count());
            let t = Instant::now();
            build_renumbered(soup, false).with_context(|| name.clone())?;
            renumbered_s = renumbered_s.min(t.elapsed().as_secs_f64());
        }
        report.row(vec![
            Cell::text(name),
            Cell::shown(size.0),
            Cell::shown(size.1),
            Cell::fixed(read_s, 4),
            Cell::fixed(build_s, 4),
            Cell::fixed(read_s + build_s, 4),
            Cell::fixed(renumbered_s, 4),
        ]);
    }
    report.finish()
}

#[cfg(test)]
mod tests {
    use super::{check_flags, usage};

    fn args(text: &str) -> Vec<String> {
        text.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn flags_a_command_takes_pass() {
        check_flags("avtp", &args("--runs 3 --large --json t.json")).unwrap();
        check_flags("sweep", &args("--seed 14 --meshes a,b --cases 2")).unwrap();
        check_flags("count", &args("")).unwrap();
        check_flags("solve-times", &args("MESH vtp 3")).unwrap();
    }

    #[test]
    fn the_usage_lists_each_command_with_its_flags() {
        assert_eq!(
            usage(),
            "usage: cargo xtask bench [--runs N] [--large] | avtp [--runs N] [--large] | pvtp [--runs N] [--large] | tables [--runs N] [--algorithms a,b] | load [--runs N] | count [--algorithms a,b] | sweep [--cases N] [--seed S] [--meshes a,b] [--large]; each also takes --json FILE (the printed numbers as JSON)"
        );
    }

    #[test]
    fn unknown_flags_and_missing_values_are_refused() {
        let typo = check_flags("avtp", &args("--larg")).unwrap_err();
        assert!(typo.to_string().contains("`--larg`"), "{typo}");
        // A flag of another command.
        assert!(check_flags("bench", &args("--seed 3")).is_err());
        // A stray value.
        assert!(check_flags("pvtp", &args("--runs 3 5")).is_err());
        let missing = check_flags("sweep", &args("--seed")).unwrap_err();
        assert!(
            missing.to_string().contains("--seed takes a value"),
            "{missing}"
        );
    }
}
