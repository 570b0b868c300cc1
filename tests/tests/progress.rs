//! Every algorithm reports its progress: the count another thread reads
//! only grows during a solve and ends at the number of vertices reached.

use std::sync::atomic::{AtomicBool, Ordering};

use geodesics::{Algorithm, BuildOptions, Mesh, Progress, Source, compute};

const ALGORITHMS: &[&str] = &[
    "vtp",
    "ftp",
    "opvtp",
    "avtp",
    "pavtp",
    "pvtp",
    "pvtp-rounds",
    "mmp",
    "fwp-mmp",
    "ich",
    "fwp-ch",
];

/// Two flat grids side by side, not joined: the second is never reached
/// from a source in the first.
fn two_components(n: u32) -> Mesh {
    let mut soup = geodesics_shapes::flat_grid(n, n, 1.0);
    let other = geodesics_shapes::flat_grid(n, n, 1.0);
    let offset = soup.positions.len() as u32;
    soup.positions.extend(
        other
            .positions
            .iter()
            .map(|p| *p + glam::DVec3::new(2.0 * n as f64, 0.0, 0.0)),
    );
    soup.triangles
        .extend(other.triangles.iter().map(|f| f.map(|v| v + offset)));
    Mesh::build(soup, &BuildOptions::default()).expect("two valid grids")
}

#[test]
fn the_count_grows_and_ends_at_the_vertices_reached() {
    let mesh = two_components(40);
    let half = (mesh.vertex_count() / 2) as u64;
    for name in ALGORITHMS {
        let progress = Progress::tracked();
        let algorithm = name
            .parse::<Algorithm>()
            .expect("a known algorithm")
            .with_progress(progress.clone());
        let done = AtomicBool::new(false);
        let (field, seen) = std::thread::scope(|scope| {
            let watcher = scope.spawn(|| {
                let mut seen = vec![];
                while !done.load(Ordering::Acquire) {
                    seen.push(progress.reached());
                    std::thread::yield_now();
                }
                seen
            });
            let (field, _) =
                compute(&mesh, &[Source::Vertex(0)], &algorithm).expect("a valid solve");
            done.store(true, Ordering::Release);
            (field, watcher.join().expect("the watcher does not panic"))
        });
        assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{name}: {seen:?}");
        let reached = field.distance.iter().filter(|d| d.is_finite()).count() as u64;
        assert_eq!(reached, half, "{name}");
        assert_eq!(progress.reached(), reached, "{name}");
        assert_eq!(progress.total(), mesh.vertex_count() as u64, "{name}");
    }
}

#[test]
fn each_solve_ends_at_its_own_count() {
    // Two solves on one handle that reach different numbers of vertices,
    // both below `Progress::REPORT_EVERY`: each must store its own final
    // count, not leave the last solve's (or the reset's 0) behind.
    let mesh = two_components(6);
    let progress = Progress::tracked();
    // 7 × 7 vertices each, the second grid's first vertex is 49.
    for (source, limit) in [(0, None), (49, Some(1.5))] {
        let algorithm = Algorithm::default()
            .with_max_distance(limit)
            .with_progress(progress.clone());
        let (field, _) =
            compute(&mesh, &[Source::Vertex(source)], &algorithm).expect("a valid solve");
        let reached = field.distance.iter().filter(|d| d.is_finite()).count() as u64;
        assert_eq!(progress.reached(), reached, "from {source}");
    }
    assert!(progress.reached() < 49, "the limited solve reached fewer");
}
