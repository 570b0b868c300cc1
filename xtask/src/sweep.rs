//! `cargo xtask sweep`: every solver against our MMP from random sources on
//! every mesh, the agreement check the fixed reference files cannot give.
//!
//! The reference distances in `../shared/data/reference/` come from one or
//! two sources per mesh, all vertices and none with a distance limit. Bugs
//! can hide elsewhere: near a point source on an edge or inside a face,
//! where the fields of several sources meet, at a distance limit. Each case
//! here draws its sources (a vertex,
//! a point on an edge, a point inside a face, several at once, or one with
//! a limit) and checks:
//!
//! - **exact**: every exact algorithm (PVTP at 1, 2 and 8 threads) within
//!   1e-12 of the largest distance of MMP's field, and ∞ exactly where it
//!   is;
//! - **limit**: MMP with a limit equals MMP without it within the limit and
//!   is ∞ beyond it (the other solvers meet the limited field under
//!   **exact**);
//! - **approximate**: AVTP and PAVTP at λ = 2, 8 and 32, with and without
//!   `light_apices`, never below exact (by more than 1e-12 of the largest
//!   distance), ∞ exactly where exact is;
//! - **paths**: VTP's and MMP's paths to random targets as long as the
//!   exact distance;
//! - **symmetry**: d(s, t) = d(t, s) for a vertex source `s` and a random
//!   vertex `t` (VTP);
//! - **Euclidean**: on a flat grid, MMP's field is the straight-line
//!   distance (an independent check of the reference itself).
//!
//! It prints one row per check and algorithm with the worst case and where
//! it happened, and fails when any check fails. Deterministic per `--seed`.

use std::path::Path;

use anyhow::{Context, Result, bail};
use geodesics::{Algorithm, AvtpOptions, BuildOptions, IndexedTriangles, Mesh, Source, compute};
use geodesics_shapes::SplitMix64;
use geodesics_tests::{EXACT, max_finite};
use glam::DVec3;

use crate::report::{Cell, Column, JsonFile, Report};
use crate::{data_dir, mesh_files, read};

/// What a case draws as its sources.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Vertex,
    EdgePoint,
    FacePoint,
    Several,
    Limited,
}

/// The kinds a case of several sources, or a limited one, draws from.
const SINGLE_KINDS: [Kind; 3] = [Kind::Vertex, Kind::EdgePoint, Kind::FacePoint];

const KINDS: [Kind; 5] = [
    Kind::Vertex,
    Kind::EdgePoint,
    Kind::FacePoint,
    Kind::Several,
    Kind::Limited,
];

/// The worst result of one check of one algorithm over the sweep.
#[derive(Debug, Default)]
struct Worst {
    solves: usize,
    /// Relative to the largest distance; `∞` when reach differed.
    value: f64,
    case: String,
    /// Whether some solve broke the check's bound.
    failed: bool,
}

/// The checks' results per (check, algorithm), in the order first met.
#[derive(Default)]
struct Tally(Vec<((&'static str, String), Worst)>);

impl Tally {
    fn record(&mut self, check: &'static str, algorithm: &str, value: f64, ok: bool, case: &str) {
        let at = match self
            .0
            .iter()
            .position(|((c, a), _)| *c == check && a == algorithm)
        {
            Some(i) => i,
            None => {
                self.0
                    .push(((check, algorithm.to_string()), Worst::default()));
                self.0.len() - 1
            }
        };
        let w = &mut self.0[at].1;
        w.solves += 1;
        w.failed |= !ok;
        if w.solves == 1 || value > w.value || value.is_nan() {
            w.value = value;
            w.case = case.to_string();
        }
    }

    /// An algorithm refused a case MMP solved.
    fn refused(&mut self, check: &'static str, algorithm: &str, case: &str, error: &str) {
        self.record(
            check,
            algorithm,
            f64::INFINITY,
            false,
            &format!("{case}: {error}"),
        );
    }

    /// The failed checks, one line each.
    fn failures(&self) -> Vec<String> {
        self.0
            .iter()
            .filter(|(_, w)| w.failed)
            .map(|((check, algorithm), w)| {
                format!("{check} {algorithm}: {:.3e} at {}", w.value, w.case)
            })
            .collect()
    }
}

/// A mesh of the sweep.
struct Subject {
    name: String,
    soup: IndexedTriangles,
    weld: bool,
    /// A flat convex grid: distances are Euclidean.
    flat: bool,
}

/// `max |a − b|` over the vertices, relative to `scale` (positive); `∞`
/// if one is finite where the other is not.
fn discrepancy(a: &[f64], b: &[f64], scale: f64) -> f64 {
    let mut worst = 0.0f64;
    for (x, y) in a.iter().zip(b) {
        if x.is_finite() != y.is_finite() {
            return f64::INFINITY;
        }
        if x.is_finite() {
            worst = worst.max((x - y).abs());
        }
    }
    worst / scale
}

/// How far `approx` goes below `exact` at worst (positive: below), relative
/// to `scale` (positive); `∞` if reach differs. With a distance limit an approximate
/// distance may pass it where the exact one does not: ∞ there is allowed.
fn below(approx: &[f64], exact: &[f64], scale: f64, limited: bool) -> f64 {
    let mut worst = f64::NEG_INFINITY;
    for (a, e) in approx.iter().zip(exact) {
        if limited && e.is_finite() && !a.is_finite() {
            continue;
        }
        if a.is_finite() != e.is_finite() {
            return f64::INFINITY;
        }
        if e.is_finite() {
            worst = worst.max(e - a);
        }
    }
    worst / scale
}

/// The sweep: `cases` cases per mesh (the kinds in turn), from `seed`, on
/// the meshes whose name contains one of `only` (all if empty); `large`
/// adds the dragon, as stored and welded.
pub fn sweep(
    cases: usize,
    seed: u64,
    only: Option<&str>,
    large: bool,
    json: Option<JsonFile>,
) -> Result<()> {
    let dir = data_dir()?;
    let mut report = Report::new("sweep", None, &dir, json)?;
    let subjects = subjects(&dir, large, only)?;
    if subjects.is_empty() {
        bail!("no mesh matches --meshes {}", only.unwrap_or(""));
    }
    let tally = run(&subjects, cases, seed)?;
    report.table(
        Some(format!(
            "Every solver against our MMP from random sources (seed {seed}, {cases} cases per mesh on {} meshes); worst relative to the largest distance: for exact, limit, paths and symmetry the largest difference, for approximate how far below exact (negative: never below); edge-filled counts the most vertices AVTP's windows missed in one solve (filled along mesh edges; never a failure)",
            subjects.len()
        )),
        [
            vec![Column::left("check"), Column::left("algorithm")],
            Column::rights(&["solves", "worst"]),
            vec![Column::left("worst case"), Column::left("verdict")],
        ]
        .concat(),
    );
    for ((check, algorithm), w) in &tally.0 {
        report.row(vec![
            Cell::text(*check),
            Cell::text(algorithm),
            Cell::shown(w.solves),
            Cell::sci(w.value, 2),
            Cell::text(&w.case),
            Cell::text(if w.failed { "FAIL" } else { "ok" }),
        ]);
    }
    report.finish()?;
    let failures = tally.failures();
    if !failures.is_empty() {
        bail!(
            "{} check(s) failed:\n{}",
            failures.len(),
            failures.join("\n")
        );
    }
    Ok(())
}

/// Runs `cases` cases on each of `subjects`.
fn run(subjects: &[Subject], cases: usize, seed: u64) -> Result<Tally> {
    let mut tally = Tally::default();
    for subject in subjects {
        let mesh = Mesh::build(
            subject.soup.clone(),
            &BuildOptions {
                weld: subject.weld,
                reorder: true,
            },
        )
        .with_context(|| subject.name.clone())?;
        let mut rng = SplitMix64::new(seed ^ name_hash(&subject.name));
        eprintln!(
            "sweep: {} ({} faces), {cases} cases",
            subject.name,
            mesh.face_count()
        );
        for k in 0..cases {
            let kind = KINDS[k % KINDS.len()];
            run_case(&mut tally, subject, &mesh, kind, &mut rng)?;
        }
    }
    Ok(tally)
}

/// The meshes: every real mesh (the dragon only with `large`), the
/// synthetic ones, and two procedural ones (the CLI's demo and a flat grid).
fn subjects(dir: &Path, large: bool, only: Option<&str>) -> Result<Vec<Subject>> {
    let mut files = mesh_files(dir)?;
    let synthetic = dir.join("synthetic");
    if synthetic.is_dir() {
        files.extend(mesh_files(&synthetic)?);
    }
    let wanted = |name: &str| only.is_none_or(|o| o.split(',').any(|w| name.contains(w)));
    let mut subjects = Vec::new();
    for path in files {
        let name = path
            .strip_prefix(dir)
            .unwrap_or(&path)
            .display()
            .to_string();
        let dragon = name.starts_with("dragon");
        if (dragon && !large) || !(wanted(&name) || dragon && wanted("dragon")) {
            continue;
        }
        let soup = read(&path)?;
        if dragon {
            subjects.push(Subject {
                name: format!("{name}, welded"),
                soup: soup.clone(),
                weld: true,
                flat: false,
            });
        }
        subjects.push(Subject {
            name,
            soup,
            weld: false,
            flat: false,
        });
    }
    subjects.extend(procedural().into_iter().filter(|s| wanted(&s.name)));
    Ok(subjects)
}

/// The CLI's demo mesh and a flat grid (distances Euclidean).
fn procedural() -> Vec<Subject> {
    vec![
        Subject {
            name: "bumpy sphere (the demo)".to_string(),
            soup: geodesics_shapes::bumpy_sphere(5, 1.0, 12, 0.15, 3),
            weld: false,
            flat: false,
        },
        Subject {
            name: "flat grid 40x40".to_string(),
            soup: geodesics_shapes::flat_grid(40, 40, 1.0),
            weld: false,
            flat: true,
        },
    ]
}

/// A stable hash of a mesh name (FNV-1a), so each mesh draws its own cases.
fn name_hash(name: &str) -> u64 {
    name.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A uniform integer in `0..n`.
fn uniform_index(rng: &mut SplitMix64, n: usize) -> u32 {
    (rng.next_u64() % n as u64) as u32
}

/// A random source of `kind` (one of the single kinds) with its position
/// and a description in input numbers.
fn draw_source(mesh: &Mesh, kind: Kind, rng: &mut SplitMix64) -> (Source, DVec3, String) {
    let f = uniform_index(rng, mesh.face_count());
    let corners = mesh.face(f);
    let at = |v: u32| mesh.position(v);
    match kind {
        Kind::EdgePoint => {
            let h = 3 * f + uniform_index(rng, 3);
            let t = rng.next_f64_open();
            let p = at(mesh.tail(h)).lerp(at(mesh.head(h)), t);
            let text = format!(
                "edge {}–{} at {t:.3}",
                mesh.pinch_origin(mesh.tail(h)),
                mesh.pinch_origin(mesh.head(h))
            );
            (Source::EdgePoint { half_edge: h, t }, p, text)
        }
        Kind::FacePoint => {
            let (u, v) = (rng.next_f64_open(), rng.next_f64_open());
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let b = [1.0 - u - v, u, v];
            let p = at(corners[0]) * b[0] + at(corners[1]) * b[1] + at(corners[2]) * b[2];
            let text = format!(
                "face {} at ({:.3}, {:.3}, {:.3})",
                mesh.input_face(f),
                b[0],
                b[1],
                b[2]
            );
            (
                Source::FacePoint {
                    face: f,
                    barycentric: b,
                },
                p,
                text,
            )
        }
        _ => {
            let v = corners[uniform_index(rng, 3) as usize];
            let input = mesh.pinch_origin(v);
            (Source::Vertex(input), at(v), format!("vertex {input}"))
        }
    }
}

/// One case: its sources drawn, every check run on them.
fn run_case(
    tally: &mut Tally,
    subject: &Subject,
    mesh: &Mesh,
    kind: Kind,
    rng: &mut SplitMix64,
) -> Result<()> {
    let mut sources = Vec::new();
    let mut points = Vec::new();
    let mut texts = Vec::new();
    let singles = match kind {
        Kind::Several => 2 + uniform_index(rng, 3) as usize,
        _ => 1,
    };
    for i in 0..singles {
        let single = match kind {
            Kind::Several => SINGLE_KINDS[i % SINGLE_KINDS.len()],
            Kind::Limited => SINGLE_KINDS[uniform_index(rng, SINGLE_KINDS.len()) as usize],
            k => k,
        };
        let (s, p, t) = draw_source(mesh, single, rng);
        sources.push(s);
        points.push(p);
        texts.push(t);
    }
    let h = mesh.average_edge_length();
    let limit = matches!(kind, Kind::Limited).then(|| h * (3.0 + 40.0 * rng.next_f64()));
    let mut case = format!("{}: {}", subject.name, texts.join(" + "));
    if let Some(l) = limit {
        case.push_str(&format!(", limit {:.1} h", l / h));
    }
    let mmp: Algorithm = "mmp".parse()?;
    let exact = match compute(mesh, &sources, &mmp.clone().with_max_distance(limit)) {
        Ok((field, _)) => field.distance,
        Err(e) => {
            // A source MMP refuses (a face of zero area, say): every other
            // solver must refuse it too, which `tests/` covers; skip.
            eprintln!("sweep: skipped {case}: mmp refused it: {e}");
            return Ok(());
        }
    };
    // Never 0, so a field of zeros (a source alone within the limit)
    // compares as equal rather than as NaN.
    let scale = max_finite(&exact).max(f64::MIN_POSITIVE);
    if let Some(l) = limit {
        let unlimited = compute(mesh, &sources, &mmp)?.0.distance;
        // Within the limit: the unlimited distance; beyond it by more than
        // the bound: ∞. (Vertices within the bound of the limit may go
        // either way.)
        let slack = EXACT * max_finite(&unlimited);
        let mut worst = 0.0f64;
        for (lim, full) in exact.iter().zip(&unlimited) {
            if *full <= l - slack {
                worst = worst.max(if lim.is_finite() {
                    (lim - full).abs() / scale
                } else {
                    f64::INFINITY
                });
            } else if *full > l + slack && lim.is_finite() {
                worst = f64::INFINITY;
            }
        }
        tally.record("limit", "mmp", worst, worst <= EXACT, &case);
    }
    if subject.flat {
        let positions = &subject.soup.positions;
        let euclid: Vec<f64> = positions
            .iter()
            .map(|q| {
                points
                    .iter()
                    .map(|p| p.distance(*q))
                    .fold(f64::INFINITY, f64::min)
            })
            .map(|d| {
                if limit.is_some_and(|l| d > l) {
                    f64::INFINITY
                } else {
                    d
                }
            })
            .collect();
        let value = discrepancy(&exact, &euclid, scale);
        tally.record("Euclidean", "mmp", value, value <= EXACT, &case);
    }
    // Every exact solver, the parallel ones at 1, 2 and 8 threads.
    for &name in Algorithm::NAMES {
        let algorithm: Algorithm = name.parse()?;
        if name == "mmp" || !algorithm.is_exact() {
            continue;
        }
        let threads: &[usize] = if name.starts_with("pvtp") {
            &[1, 2, 8]
        } else {
            &[0]
        };
        for &t in threads {
            let (label, algorithm) = if t == 0 {
                (name.to_string(), algorithm.clone())
            } else {
                (format!("{name} T={t}"), algorithm.clone().with_threads(t)?)
            };
            match compute(mesh, &sources, &algorithm.with_max_distance(limit)) {
                Ok((field, _)) => {
                    let value = discrepancy(&field.distance, &exact, scale);
                    tally.record("exact", &label, value, value <= EXACT, &case);
                }
                Err(e) => tally.refused("exact", &label, &case, &e.to_string()),
            }
        }
    }
    // Approximate: never below exact.
    for lambda in [2.0, 8.0, 32.0] {
        for (threads, light_apices) in [None, Some(2)]
            .into_iter()
            .flat_map(|t| [(t, false), (t, true)])
        {
            let algorithm = Algorithm::Avtp(AvtpOptions {
                threads,
                light_apices,
                ..AvtpOptions::with_lambda(lambda)
            })
            .with_max_distance(limit);
            let lit = if light_apices { " lit" } else { "" };
            let label = format!("{} λ={lambda}{lit}", algorithm.name());
            match compute(mesh, &sources, &algorithm) {
                Ok((field, stats)) => {
                    let value = below(&field.distance, &exact, scale, limit.is_some());
                    tally.record("approximate", &label, value, value <= EXACT, &case);
                    // Not a failure (the backstop keeps them finite and never
                    // below exact), but the windows missed them: shown so a
                    // new gap stays visible.
                    let filled = stats.edge_filled_vertices as f64;
                    tally.record("edge-filled", &label, filled, true, &case);
                }
                Err(e) => tally.refused("approximate", &label, &case, &e.to_string()),
            }
        }
    }
    // Paths to three reachable targets, and symmetry for a vertex source.
    let reachable: Vec<u32> = (0..exact.len() as u32)
        .filter(|&v| exact[v as usize].is_finite())
        .collect();
    if reachable.is_empty() {
        return Ok(());
    }
    for name in ["vtp", "mmp"] {
        let algorithm: Algorithm = name.parse()?;
        for _ in 0..3 {
            let target = reachable[uniform_index(rng, reachable.len()) as usize];
            let at = format!("{case}, to vertex {target}");
            match geodesics::shortest_path(
                mesh,
                &sources,
                target,
                &algorithm.clone().with_max_distance(limit),
            ) {
                Ok(path) => {
                    let value = (path.length - exact[target as usize]).abs() / scale;
                    tally.record("paths", name, value, value <= EXACT, &at);
                }
                Err(e) => tally.refused("paths", name, &at, &e.to_string()),
            }
        }
    }
    if let (Kind::Vertex, [Source::Vertex(s)]) = (kind, sources.as_slice()) {
        let target = reachable[uniform_index(rng, reachable.len()) as usize];
        let at = format!("{case}, and back from vertex {target}");
        match compute(mesh, &[Source::Vertex(target)], &Algorithm::default()) {
            Ok((back, _)) => {
                let value = (back.distance[*s as usize] - exact[target as usize]).abs() / scale;
                tally.record("symmetry", "vtp", value, value <= EXACT, &at);
            }
            Err(e) => tally.refused("symmetry", "vtp", &at, &e.to_string()),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrepancy_is_relative_and_infinite_when_reach_differs() {
        let exact = [0.0, 1.0, 4.0, f64::INFINITY];
        assert_eq!(discrepancy(&exact, &exact, 4.0), 0.0);
        let off = [0.0, 1.0, 4.0 + 4e-11, f64::INFINITY];
        assert!((discrepancy(&off, &exact, 4.0) - 1e-11).abs() < 1e-15);
        let unreached = [0.0, 1.0, f64::INFINITY, f64::INFINITY];
        assert_eq!(discrepancy(&unreached, &exact, 4.0), f64::INFINITY);
    }

    #[test]
    fn below_allows_an_approximation_past_a_limit_only_when_there_is_one() {
        let exact = [0.0, 1.0, 2.0, f64::INFINITY];
        let approx = [0.0, 1.5, f64::INFINITY, f64::INFINITY];
        assert_eq!(below(&approx, &exact, 2.0, false), f64::INFINITY);
        assert_eq!(below(&approx, &exact, 2.0, true), 0.0);
        let under = [0.0, 0.5, 2.0, f64::INFINITY];
        assert_eq!(below(&under, &exact, 2.0, false), 0.25);
        // Finite where exact is ∞ (beyond the limit): below exact.
        let reached = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(below(&reached, &exact, 2.0, true), f64::INFINITY);
    }

    /// The sweep on the procedural meshes, one case of each kind: every
    /// check passes, and each check ran.
    #[test]
    fn every_check_passes_on_the_procedural_meshes() {
        let tally = run(&procedural(), KINDS.len(), 7).unwrap();
        assert_eq!(tally.failures(), Vec::<String>::new());
        for check in [
            "exact",
            "limit",
            "approximate",
            "paths",
            "symmetry",
            "Euclidean",
        ] {
            assert!(
                tally
                    .0
                    .iter()
                    .any(|((c, _), w)| *c == check && w.solves > 0),
                "{check} never ran"
            );
        }
        let exact = tally.0.iter().filter(|((c, _), _)| *c == "exact").count();
        // Every exact algorithm but MMP, the two PVTPs at three thread counts.
        assert_eq!(exact, 18 - 1 + 4);
    }

    /// The sweep on every real and synthetic mesh (not the dragon), one
    /// case of each kind from a seed of its own: every check passes. About
    /// 5 minutes on 2 cores; skips loudly without the mesh folder.
    #[test]
    fn every_check_passes_on_the_real_meshes() {
        let Some(dir) = geodesics_tests::data_dir("the sweep on the real meshes") else {
            return;
        };
        let subjects = subjects(&dir, false, None).unwrap();
        assert!(subjects.len() > 2, "no real mesh in {}", dir.display());
        let tally = run(&subjects, KINDS.len(), 3).unwrap();
        assert_eq!(tally.failures(), Vec::<String>::new());
    }

    /// A field off by more than the bound fails its check.
    #[test]
    fn a_wrong_distance_fails_the_sweep() {
        let mut tally = Tally::default();
        let exact = [0.0, 1.0, 2.0];
        let wrong = [0.0, 1.0, 2.0 + 1e-9];
        let value = discrepancy(&wrong, &exact, 2.0);
        tally.record("exact", "vtp", value, value <= EXACT, "a case");
        tally.record("exact", "vtp", 0.0, true, "another");
        let failures = tally.failures();
        assert_eq!(failures.len(), 1);
        assert!(
            failures[0].starts_with("exact vtp: 5.000e-10 at a case"),
            "{failures:?}"
        );
    }
}
