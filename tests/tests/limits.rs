//! A distance limit cuts the field beyond it, never within it.
//!
//! The window-list solvers process the windows waiting on an edge only
//! once one of the edge's ends has been popped, and used to stop at the
//! first vertex beyond the limit. A vertex within the limit reached only
//! across a long edge whose ends both lie beyond it then came out
//! unreachable (VTP, PVTP, AVTP), and FTP stopped at the first face whose
//! apex lay beyond the limit. Now vertices beyond the limit are popped too
//! (emitting nothing), and windows that reach nothing within the limit are
//! dropped as they are appended.

use geodesics::{Algorithm, compute};
use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
use geodesics_window::Source;
use glam::DVec3;

/// A flat strip: the source `S` at the origin under a long edge `AB`
/// (`y = 1`, from `x = -100` to `100`), and `X = (0, 2)` above it. The
/// shortest path to `X` crosses `AB` in its middle, at distance 1 from
/// `S`, while `A` and `B` lie about 100 away.
fn strip() -> Mesh {
    let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
    // S, L, R, A, B, X
    let positions = vec![
        p(0.0, 0.0),
        p(-100.0, -1.0),
        p(100.0, -1.0),
        p(-100.0, 1.0),
        p(100.0, 1.0),
        p(0.0, 2.0),
    ];
    let triangles = vec![[0, 4, 3], [3, 4, 5], [1, 0, 3], [0, 2, 4], [1, 2, 0]];
    Mesh::build(
        IndexedTriangles {
            positions,
            triangles,
        },
        &BuildOptions::default(),
    )
    .expect("the strip is a valid mesh")
}

/// Every algorithm by name, the parallel ones with 1, 2 and 8 threads.
fn every_algorithm() -> Vec<(String, Algorithm)> {
    let mut all = Vec::new();
    for name in Algorithm::NAMES {
        let algorithm: Algorithm = name.parse().expect("a listed name parses");
        match algorithm.clone().with_threads(1) {
            Ok(_) => {
                for t in [1, 2, 8] {
                    let a = algorithm.clone().with_threads(t).expect("parallel");
                    all.push((format!("{name} T={t}"), a));
                }
            }
            Err(_) => all.push((name.to_string(), algorithm)),
        }
    }
    all
}

#[test]
fn a_vertex_within_the_limit_behind_a_long_edge_is_reached_by_every_algorithm() {
    let mesh = strip();
    let corner = (100.0f64 * 100.0 + 1.0).sqrt();
    for (name, algorithm) in every_algorithm() {
        let unlimited = compute(&mesh, &[Source::Vertex(0)], &algorithm)
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .0
            .distance;
        assert!((unlimited[5] - 2.0).abs() < 1e-12, "{name}: {unlimited:?}");
        let limited = compute(
            &mesh,
            &[Source::Vertex(0)],
            &algorithm.with_max_distance(Some(3.0)),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .0
        .distance;
        assert_eq!(limited[0], 0.0, "{name}");
        assert!(
            (limited[5] - 2.0).abs() < 1e-12,
            "{name}: X within the limit came out {} ({limited:?})",
            limited[5]
        );
        for v in 1..5 {
            assert!(
                (unlimited[v] - corner).abs() < 1e-9,
                "{name}: {unlimited:?}"
            );
            assert!(
                limited[v].is_infinite(),
                "{name}: vertex {v} beyond the limit came out {}",
                limited[v]
            );
        }
    }
}

/// An approximate field under a distance limit: ∞ beyond the limit, never
/// below `exact` within it, and reached well within it.
fn assert_cut_at_limit(what: &str, field: &[f64], exact: &[f64], limit: f64) {
    for (v, (&d, &e)) in field.iter().zip(exact).enumerate() {
        if e > limit + 1e-9 {
            assert!(d.is_infinite(), "{what}: vertex {v} at {e} is {d}");
        } else if d.is_finite() {
            assert!(d >= e - 1e-12, "{what}: vertex {v} {d} below {e}");
        } else {
            assert!(e >= 0.9 * limit, "{what}: vertex {v} at {e} unreached");
        }
    }
}

/// AVTP and PAVTP with a distance limit and resets well inside it finish,
/// never fall below the exact field and leave everything beyond the limit
/// unreachable. (PAVTP's regions once waited for ever once the wavefront
/// passed both the limit and the next reset radius: no reset happens
/// beyond the limit, and the band bound stayed capped at that radius.)
#[test]
fn avtp_with_a_limit_and_resets_finishes_at_or_above_exact() {
    let mesh = Mesh::build(
        geodesics_shapes::flat_grid(40, 40, 1.0),
        &BuildOptions::default(),
    )
    .expect("a flat grid is a valid mesh");
    let source = [Source::Vertex(20 * 41 + 20)]; // the middle
    let limit = 15.0;
    let exact = compute(&mesh, &source, &Algorithm::default())
        .unwrap()
        .0
        .distance;
    for threads in [None, Some(1), Some(2)] {
        let options = geodesics::AvtpOptions {
            threads,
            max_distance: Some(limit),
            ..geodesics::AvtpOptions::with_lambda(2.0)
        };
        let (field, stats) = compute(&mesh, &source, &Algorithm::Avtp(options)).unwrap();
        assert!(stats.window_resets >= 5, "{threads:?}: {stats:?}");
        assert_cut_at_limit(&format!("{threads:?}"), &field.distance, &exact, limit);
    }
    // The same reset on PVTP's rounds (only through `geodesics-pvtp`).
    for threads in [1, 2] {
        let options = geodesics_pvtp::PvtpOptions {
            threads,
            max_distance: Some(limit),
            reset: Some(geodesics_window::WindowReset::every(2.0)),
            schedule: geodesics_pvtp::Schedule::Rounds,
            ..Default::default()
        };
        let (field, stats) = geodesics_pvtp::solve(&mesh, &source, &options).unwrap();
        let what = format!("rounds T={threads}");
        assert!(stats.window_resets >= 5, "{what}: {stats:?}");
        assert_cut_at_limit(&what, &field.distance, &exact, limit);
    }
}
