//! AVTP (geodesics-avtp) against exact VTP: the limits the paper states
//! (exact VTP for a huge λ, between exact and edge-graph Dijkstra for a tiny
//! one), never below exact at any λ, state kept per solve, and the distance
//! limit, on real meshes and procedural ones.

use geodesics_avtp::{AvtpOptions, solve};
use geodesics_mesh::{BuildOptions, Mesh};
use geodesics_shapes::{bumpy_sphere, jittered_icosphere};
use geodesics_tests::{EXACT, data_dir, edge_graph_distances};
use geodesics_window::Source;

fn exact(mesh: &Mesh, sources: &[Source]) -> Vec<f64> {
    geodesics_vtp::solve(mesh, sources, &Default::default())
        .unwrap()
        .0
        .distance
}

fn avtp(mesh: &Mesh, sources: &[Source], lambda: f64) -> Vec<f64> {
    avtp_on(mesh, sources, lambda, None)
}

/// AVTP (`threads` None) or PAVTP on that many threads.
fn avtp_on(mesh: &Mesh, sources: &[Source], lambda: f64, threads: Option<usize>) -> Vec<f64> {
    let options = AvtpOptions {
        threads,
        ..AvtpOptions::with_lambda(lambda)
    };
    solve(mesh, sources, &options).unwrap().0.distance
}

/// PAVTP on one and two threads, beside sequential AVTP.
const PARALLEL: [Option<usize>; 2] = [Some(1), Some(2)];

fn mean_edge(mesh: &Mesh) -> f64 {
    let n = mesh.half_edge_count() as u32;
    (0..n).map(|h| mesh.length(h)).sum::<f64>() / f64::from(n)
}

fn min_edge(mesh: &Mesh) -> f64 {
    (0..mesh.half_edge_count() as u32)
        .map(|h| mesh.length(h))
        .filter(|l| *l > 0.0)
        .fold(f64::INFINITY, f64::min)
}

/// Meshes every test runs on: procedural ones always, real ones when the
/// data folder is there.
fn meshes() -> Vec<(String, Mesh)> {
    let mut out = vec![
        (
            "bumpy sphere".to_string(),
            Mesh::build(bumpy_sphere(4, 1.0, 40, 0.2, 3), &BuildOptions::default()).unwrap(),
        ),
        (
            "jittered icosphere".to_string(),
            Mesh::build(jittered_icosphere(4, 1.0, 0.1, 5), &BuildOptions::default()).unwrap(),
        ),
    ];
    if let Some(dir) = data_dir("AVTP on real meshes") {
        for name in ["hand.off", "fertility.off", "bunny.off", "fandisk.obj"] {
            let soup = geodesics_io::read_mesh(&dir.join(name)).unwrap();
            out.push((
                name.to_string(),
                Mesh::build(soup, &BuildOptions::default()).unwrap(),
            ));
        }
    }
    out
}

fn scale(d: &[f64]) -> f64 {
    d.iter()
        .copied()
        .filter(|x| x.is_finite())
        .fold(0.0, f64::max)
}

#[test]
fn huge_lambda_is_exact_vtp_bit_for_bit() {
    for (name, mesh) in meshes() {
        let sources = [Source::Vertex(0)];
        let e = exact(&mesh, &sources);
        // λh beyond the largest distance: no reset can happen.
        let lambda = 2.0 * scale(&e) / mean_edge(&mesh) + 1.0;
        let a = avtp(&mesh, &sources, lambda);
        assert!(
            a.iter().zip(&e).all(|(x, y)| x.to_bits() == y.to_bits()),
            "{name}: AVTP with λ = {lambda} differs from VTP"
        );
    }
}

#[test]
fn tiny_lambda_lies_between_exact_and_edge_graph_dijkstra() {
    for (name, mesh) in meshes() {
        let e = exact(&mesh, &[Source::Vertex(0)]);
        let g = edge_graph_distances(&mesh, 0);
        let lambda = 0.5 * min_edge(&mesh) / mean_edge(&mesh);
        let a = avtp(&mesh, &[Source::Vertex(0)], lambda);
        let tol = EXACT * scale(&e);
        let mut strictly_above_exact = 0;
        for v in 0..e.len() {
            assert!(
                a[v] >= e[v] - tol,
                "{name} vertex {v}: {} < exact {}",
                a[v],
                e[v]
            );
            assert!(
                a[v] <= g[v] + tol,
                "{name} vertex {v}: {} > edge graph {}",
                a[v],
                g[v]
            );
            strictly_above_exact += usize::from(a[v] > e[v] + tol);
        }
        // It really is approximate: many vertices lose accuracy.
        assert!(
            strictly_above_exact > e.len() / 10,
            "{name}: only {strictly_above_exact} vertices above exact"
        );
        eprintln!(
            "{name}: λ = {lambda:.3}, {strictly_above_exact} of {} vertices above exact",
            e.len()
        );
    }
}

#[test]
fn never_below_exact_and_more_accurate_as_lambda_grows() {
    for (name, mesh) in meshes() {
        let sources = [
            Source::Vertex(0),
            Source::Vertex(mesh.vertex_count() as u32 / 2),
        ];
        let e = exact(&mesh, &sources);
        let tol = EXACT * scale(&e);
        let mut means = Vec::new();
        for lambda in [2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0] {
            let a = avtp(&mesh, &sources, lambda);
            let (mut sum, mut n) = (0.0, 0);
            for v in 0..e.len() {
                assert!(
                    a[v] >= e[v] - tol,
                    "{name} λ = {lambda} vertex {v}: {} < exact {}",
                    a[v],
                    e[v]
                );
                if e[v].is_finite() && e[v] > 0.0 {
                    sum += (a[v] - e[v]) / e[v];
                    n += 1;
                }
            }
            means.push(sum / f64::from(n));
        }
        let shown: Vec<String> = means.iter().map(|m| format!("{m:.2e}")).collect();
        eprintln!("{name}: mean relative error for λ = 2..128: {shown:?}");
        assert!(
            means.last().unwrap() <= means.first().unwrap(),
            "{name}: λ = 128 is less accurate than λ = 2: {means:?}"
        );
    }
}

#[test]
fn resets_belong_to_one_solve() {
    // A solve from another source first must not change the next one (the
    // authors' code marks reset vertices on the mesh itself).
    let mesh = Mesh::build(bumpy_sphere(4, 1.0, 40, 0.2, 9), &BuildOptions::default()).unwrap();
    let fresh = avtp(&mesh, &[Source::Vertex(7)], 4.0);
    let _ = avtp(&mesh, &[Source::Vertex(100)], 4.0);
    let again = avtp(&mesh, &[Source::Vertex(7)], 4.0);
    assert!(
        fresh
            .iter()
            .zip(&again)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    );
}

#[test]
fn distance_limit_holds() {
    let mesh = Mesh::build(bumpy_sphere(4, 1.0, 40, 0.2, 9), &BuildOptions::default()).unwrap();
    let options = AvtpOptions {
        max_distance: Some(1.0),
        ..AvtpOptions::with_lambda(4.0)
    };
    let (limited, _) = solve(&mesh, &[Source::Vertex(0)], &options).unwrap();
    let full = avtp(&mesh, &[Source::Vertex(0)], 4.0);
    for (l, f) in limited.distance.iter().zip(&full) {
        if *f <= 1.0 {
            assert!(l.is_finite());
        }
        if l.is_finite() {
            assert!(*l <= 1.0);
        }
    }
}

#[test]
fn pavtp_huge_lambda_is_exact_pvtp_bit_for_bit() {
    for (name, mesh) in meshes() {
        let sources = [Source::Vertex(0)];
        let e = exact(&mesh, &sources);
        let lambda = 2.0 * scale(&e) / mean_edge(&mesh) + 1.0;
        for threads in PARALLEL {
            // PAVTP runs on PVTP's region schedule.
            let options = geodesics_pvtp::PvtpOptions {
                threads: threads.unwrap(),
                schedule: geodesics_pvtp::Schedule::Regions,
                ..Default::default()
            };
            let pvtp = geodesics_pvtp::solve(&mesh, &sources, &options)
                .unwrap()
                .0
                .distance;
            let a = avtp_on(&mesh, &sources, lambda, threads);
            assert!(
                a.iter().zip(&pvtp).all(|(x, y)| x.to_bits() == y.to_bits()),
                "{name}: PAVTP {threads:?} with λ = {lambda} differs from PVTP"
            );
        }
    }
}

#[test]
fn pavtp_is_deterministic_never_below_exact_and_close_to_avtp() {
    for (name, mesh) in meshes() {
        let sources = [
            Source::Vertex(0),
            Source::Vertex(mesh.vertex_count() as u32 / 2),
        ];
        let e = exact(&mesh, &sources);
        let tol = EXACT * scale(&e);
        for lambda in [0.5 * min_edge(&mesh) / mean_edge(&mesh), 4.0, 16.0] {
            let g: Vec<f64> = {
                let (a, b) = (
                    edge_graph_distances(&mesh, 0),
                    edge_graph_distances(&mesh, mesh.vertex_count() as u32 / 2),
                );
                a.iter().zip(&b).map(|(x, y)| x.min(*y)).collect()
            };
            let mean_err = |a: &[f64]| {
                let (mut sum, mut n) = (0.0, 0);
                for v in 0..e.len() {
                    if e[v] > 0.0 && e[v].is_finite() {
                        sum += (a[v] - e[v]) / e[v];
                        n += 1;
                    }
                }
                sum / f64::from(n)
            };
            let sequential = mean_err(&avtp(&mesh, &sources, lambda));
            // PAVTP runs on the region schedule: the same bits for every
            // thread count, not only from run to run.
            let mut first_count: Option<Vec<f64>> = None;
            for threads in PARALLEL {
                let a = avtp_on(&mesh, &sources, lambda, threads);
                let again = avtp_on(&mesh, &sources, lambda, threads);
                assert!(
                    a.iter()
                        .zip(&again)
                        .all(|(x, y)| x.to_bits() == y.to_bits()),
                    "{name} λ = {lambda} {threads:?}: two runs differ"
                );
                match &first_count {
                    Some(f) => assert!(
                        a.iter().zip(f).all(|(x, y)| x.to_bits() == y.to_bits()),
                        "{name} λ = {lambda}: {threads:?} threads differ from {:?}",
                        PARALLEL[0]
                    ),
                    None => first_count = Some(a.clone()),
                }
                for v in 0..e.len() {
                    assert!(
                        a[v] >= e[v] - tol,
                        "{name} λ = {lambda} {threads:?} vertex {v}: below exact"
                    );
                    assert!(
                        a[v] <= g[v] + tol,
                        "{name} λ = {lambda} {threads:?} vertex {v}: above Dijkstra"
                    );
                }
                let parallel = mean_err(&a);
                eprintln!(
                    "{name} λ = {lambda:.3}: mean error AVTP {sequential:.2e}, PAVTP {threads:?} {parallel:.2e}"
                );
                // The reset happens between rounds instead of between
                // vertices: the same accuracy, give or take.
                assert!(
                    parallel <= 2.0 * sequential + 1e-12,
                    "{name} λ = {lambda} {threads:?}: PAVTP error {parallel:e} vs AVTP {sequential:e}"
                );
            }
        }
    }
}

/// The case the random-source sweep (seed 5) found: PAVTP at λ = 32 on
/// `skull.glb` from a point inside face 27721 left one vertex (input 38310)
/// unreached, a narrow sector no window covered after a reset. Every
/// vertex exact VTP reaches must be reached, and none below exact; the
/// vertices filled along edges are counted in the statistics.
#[test]
fn no_reachable_vertex_is_left_unreached() {
    let Some(dir) = data_dir("AVTP gap on skull.glb") else {
        return;
    };
    let mesh = geodesics_tests::load_mesh(&dir.join("skull.glb"), false);
    let sources = [Source::FacePoint {
        face: 27721,
        barycentric: [0.06024216176418662, 0.39408161810923314, 0.5456762201265802],
    }];
    let e = exact(&mesh, &sources);
    let tol = EXACT * scale(&e);
    for threads in [None, Some(1), Some(2)] {
        let options = AvtpOptions {
            threads,
            ..AvtpOptions::with_lambda(32.0)
        };
        let (field, stats) = solve(&mesh, &sources, &options).unwrap();
        for (v, (a, x)) in field.distance.iter().zip(&e).enumerate() {
            assert_eq!(
                a.is_finite(),
                x.is_finite(),
                "{threads:?}: vertex {v}: {a} vs {x}"
            );
            assert!(*a >= x - tol, "{threads:?}: vertex {v}: {a} below {x}");
        }
        // The vertex the windows missed: its edge path (14.5555 against
        // exact 14.5272) stays within λ = 32's largest errors on our
        // meshes (about 1 %), not merely finite.
        let (gap, exact_gap) = (field.distance[38310], e[38310]);
        assert!(
            gap <= 1.01 * exact_gap,
            "{threads:?}: vertex 38310 at {gap}, exact {exact_gap}"
        );
        eprintln!(
            "skull.glb λ = 32, {threads:?}: {} vertices filled along edges, vertex 38310 at {gap} (exact {exact_gap})",
            stats.edge_filled_vertices
        );
    }
}

/// Mean relative error of `approx` against `exact` (over the vertices at a
/// positive finite exact distance), after checking it is never below.
fn mean_error_never_below(approx: &[f64], exact: &[f64], case: &str) -> f64 {
    let tol = EXACT * scale(exact);
    let (mut sum, mut n) = (0.0, 0);
    for (v, (a, e)) in approx.iter().zip(exact).enumerate() {
        assert!(*a >= e - tol, "{case} vertex {v}: {a} < exact {e}");
        if e.is_finite() && *e > 0.0 {
            sum += (a - e) / e;
            n += 1;
        }
    }
    sum / f64::from(n)
}

#[test]
fn lighting_apices_before_resets_stays_above_exact_and_lowers_the_error() {
    for (name, mesh) in meshes() {
        let sources = [Source::Vertex(0)];
        let e = exact(&mesh, &sources);
        for lambda in [2.0, 8.0, 32.0] {
            for threads in [None, Some(2)] {
                let plain = AvtpOptions {
                    threads,
                    ..AvtpOptions::with_lambda(lambda)
                };
                let lit = AvtpOptions {
                    light_apices: true,
                    ..plain.clone()
                };
                let case = format!("{name} λ = {lambda} threads {threads:?}");
                let (a, stats) = solve(&mesh, &sources, &lit).unwrap();
                let with = mean_error_never_below(&a.distance, &e, &case);
                let (b, _) = solve(&mesh, &sources, &plain).unwrap();
                let without = mean_error_never_below(&b.distance, &e, &case);
                eprintln!("{case}: mean error {with:.3e} lit, {without:.3e} not");
                if stats.window_resets == 0 {
                    // λh beyond the largest distance: nothing to light.
                    assert_eq!(a.distance, b.distance, "{case}");
                } else if without == 0.0 {
                    // Resets late enough to cost nothing: none to win back.
                    assert_eq!(with, 0.0, "{case}");
                } else {
                    assert!(with < without, "{case}: {with:e} lit against {without:e}");
                }
            }
        }
    }
}
