//! Meshes with a few vertices far out of proportion with the rest (a
//! corrupt coordinate): every solver finishes, with the work and the exact
//! distances of the mesh without them; and needles so thin that the
//! window-list solvers refuse them by name (`check_spikes`) where they
//! would run without end.
//!
//! A byte flipped in a binary STL of a 15 mm screw put one vertex 2e22
//! away. Tolerances scaled with the bounding box then allowed rounding
//! margins of 3e8, larger than the screw: no window was ever pruned, and
//! VTP and ICH ran for minutes. They now scale with
//! `Mesh::length_scale`, which such an outlier does not move.

use geodesics::{Algorithm, compute};
use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
use geodesics_shapes::{bipyramid, flat_grid};
use geodesics_tests::EXACT;
use geodesics_window::Source;
use glam::DVec3;

/// A flat `n × n` grid of side 1, plus (with `far`) one triangle on the
/// middle of its right side whose third corner lies at `x = far`.
fn grid_with_flap(n: u32, far: Option<f64>) -> IndexedTriangles {
    let mut soup = flat_grid(n, n, 1.0);
    if let Some(far) = far {
        let right = |j: u32| j * (n + 1) + n;
        soup.positions.push(DVec3::new(far, 0.5, 0.0));
        let tip = (soup.positions.len() - 1) as u32;
        soup.triangles.push([right(n / 2), tip, right(n / 2 + 1)]);
    }
    soup
}

#[test]
fn a_far_vertex_leaves_the_tolerance_and_the_work_of_the_rest() {
    let n = 60;
    let plain = Mesh::build(grid_with_flap(n, None), &BuildOptions::default()).unwrap();
    let flap = Mesh::build(grid_with_flap(n, Some(1e22)), &BuildOptions::default()).unwrap();
    assert!(flap.bbox_diagonal() > 1e21);
    assert_eq!(plain.length_scale(), plain.bbox_diagonal());
    // Capped at 1000 √F median edges: 85K here, not 1e22.
    assert!(flap.length_scale() < 1e-15 * flap.bbox_diagonal());
    let source = [Source::Vertex(0)];
    let origin = flap.position(0);
    // Rounding allowed: 1e-12 of the grid's largest distance (its diagonal).
    let tol = EXACT * f64::from(n) * 2f64.sqrt();
    for name in ["vtp", "ftp", "ich", "mmp", "pvtp", "pvtp-rounds"] {
        let algorithm: Algorithm = name.parse().unwrap();
        let (base, base_stats) = compute(&plain, &source, &algorithm).unwrap();
        let (field, stats) = compute(&flap, &source, &algorithm).unwrap();
        // The flat grid's distances are Euclidean, with or without the flap.
        for v in 0..plain.input_vertex_count() as u32 {
            let euclid = origin.distance(flap.position(v));
            let d = field.distance[v as usize];
            assert!(
                (d - euclid).abs() <= tol,
                "{name}: vertex {v}: {d} vs {euclid}"
            );
            assert!(
                (d - base.distance[v as usize]).abs() <= tol,
                "{name}: vertex {v}"
            );
        }
        // The tip is reached across the flap from its nearer base corner.
        let tip = plain.input_vertex_count();
        let via = |j: u32| {
            let corner = j * (n + 1) + n;
            field.distance[corner as usize]
                + flap.position(corner).distance(flap.position(tip as u32))
        };
        let expected = via(n / 2).min(via(n / 2 + 1));
        assert!(
            (field.distance[tip] - expected).abs() <= EXACT * expected,
            "{name}: tip {} vs {expected}",
            field.distance[tip]
        );
        // Bounded by the plain grid's work (with bounding-box margins the
        // VTP solve made 31M propagations instead of 0.36M).
        assert!(
            stats.window_propagations <= 2 * base_stats.window_propagations + 1000,
            "{name}: {} propagations, {} without the flap",
            stats.window_propagations,
            base_stats.window_propagations
        );
    }
}

/// A bipyramid over a regular octagon of radius 1: tip (vertex 8) at
/// height `h`.
fn needle(h: f64) -> Mesh {
    Mesh::build(bipyramid(8, 1.0, h), &BuildOptions::default()).unwrap()
}

#[test]
fn a_needle_is_refused_by_every_window_list_solver_and_solved_by_mmp() {
    // 1e12 times longer than wide: VTP and ICH ran without end on it.
    let mesh = needle(1e12);
    let source = [Source::Vertex(0)];
    for &name in Algorithm::NAMES {
        let algorithm: Algorithm = name.parse().unwrap();
        let result = compute(&mesh, &source, &algorithm);
        if name.ends_with("mmp") && !name.starts_with("vtp") {
            let (field, _) = result.unwrap_or_else(|e| panic!("{name}: {e}"));
            // The apex is reached up a face, from the rim.
            let rim = mesh.position(0).distance(mesh.position(8));
            assert!((field.distance[8] - rim).abs() <= EXACT * rim, "{name}");
            continue;
        }
        let message = result.err().map(|e| e.to_string());
        assert!(
            message
                .as_deref()
                .is_some_and(|m| m.starts_with("vertex 8 is a spike")),
            "{name}: {message:?}"
        );
    }
    // A blunt one (1,000 to 1) solves everywhere.
    let blunt = needle(1e3);
    for &name in Algorithm::NAMES {
        let algorithm: Algorithm = name.parse().unwrap();
        compute(&blunt, &source, &algorithm).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}
