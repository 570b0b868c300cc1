//! Whole solves on meshes whose exact distances are known in closed form:
//! flat and folded grids (intrinsically flat and convex, so the geodesic
//! distance is the Euclidean distance in the unfolded plane), a pinch.

use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
use geodesics_shapes::{flat_grid, jittered_flat_grid};
use geodesics_window::SourceError;
use geodesics_window::{NO_SOURCE, Source};
use glam::{DVec2, DVec3};

use crate::{IchError, IchOptions, Schedule, solve};

const BOTH: [Schedule; 2] = [Schedule::PriorityQueue, Schedule::Fwp];

fn build(soup: IndexedTriangles) -> Mesh {
    Mesh::build(soup, &BuildOptions::default()).expect("test meshes are valid")
}

fn opts(schedule: Schedule) -> IchOptions {
    IchOptions {
        schedule,
        ..IchOptions::default()
    }
}

/// Max |ours − expected| over all vertices, relative to the largest.
fn rel_err(ours: &[f64], expected: &[f64]) -> f64 {
    let max = expected.iter().cloned().fold(0.0, f64::max);
    let err = ours
        .iter()
        .zip(expected)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    err / max
}

/// A jittered grid folded along the line x = 5 (lengths unchanged): the
/// intrinsic geometry is the flat rectangle, so distances are those in the
/// plane of the unfolded grid.
fn folded_grid() -> (Mesh, Vec<DVec2>) {
    let mut g = jittered_flat_grid(10, 6, 1.0, 0.3, 7);
    let flat: Vec<DVec2> = g.positions.iter().map(|p| p.truncate()).collect();
    // The fold line x = 5 is a grid column; the jitter moved its vertices
    // off it, so they are put back (in both the mesh and the flat copy).
    let (angle_c, angle_s) = (0.6f64.cos(), 0.6f64.sin());
    let regular = flat_grid(10, 6, 1.0);
    let mut flat_fixed = flat.clone();
    for (v, p) in g.positions.iter_mut().enumerate() {
        let rx = regular.positions[v].x;
        if rx == 5.0 {
            // Put the fold column back on the line.
            p.x = 5.0;
            flat_fixed[v].x = 5.0;
        }
        if rx > 5.0 {
            let dx = p.x - 5.0;
            *p = DVec3::new(5.0 + dx * angle_c, p.y, dx * angle_s);
        }
    }
    (build(g), flat_fixed)
}

#[test]
fn flat_grid_distances_are_euclidean() {
    let mesh = build(jittered_flat_grid(20, 15, 0.5, 0.35, 3));
    for s in BOTH {
        for src in [0u32, 170, 335] {
            let (field, stats) = solve(&mesh, &[Source::Vertex(src)], &opts(s)).unwrap();
            let q = mesh.position(src);
            let expected: Vec<f64> = (0..mesh.input_vertex_count() as u32)
                .map(|v| mesh.position(v).distance(q))
                .collect();
            let e = rel_err(&field.distance, &expected);
            assert!(e < 1e-14, "{s:?} from {src}: {e:e}");
            assert!(stats.window_propagations > 0 && stats.peak_live_windows > 0);
            assert_eq!(
                stats.peak_window_bytes,
                stats.peak_live_windows * std::mem::size_of::<geodesics_window::Window>() as u64
            );
        }
    }
}

#[test]
fn folded_grid_distances_are_the_unfolded_ones() {
    let (mesh, flat) = folded_grid();
    for s in BOTH {
        for src in [0u32, 27, 76] {
            let (field, _) = solve(&mesh, &[Source::Vertex(src)], &opts(s)).unwrap();
            let q = flat[src as usize];
            let expected: Vec<f64> = flat.iter().map(|p| p.distance(q)).collect();
            let e = rel_err(&field.distance, &expected);
            assert!(e < 1e-14, "{s:?} from {src}: {e:e}");
        }
    }
}

#[test]
fn regular_grid_ties_are_safe() {
    // Every distance in a regular grid ties with its mirror image.
    let mesh = build(flat_grid(30, 30, 1.0));
    for s in BOTH {
        let (field, _) = solve(&mesh, &[Source::Vertex(15 * 31 + 15)], &opts(s)).unwrap();
        let q = mesh.position(15 * 31 + 15);
        let expected: Vec<f64> = (0..mesh.vertex_count() as u32)
            .map(|v| mesh.position(v).distance(q))
            .collect();
        let e = rel_err(&field.distance, &expected);
        assert!(e < 1e-14, "{s:?}: {e:e}");
    }
}

#[test]
fn point_sources_in_faces_and_on_edges() {
    let mesh = build(jittered_flat_grid(12, 12, 1.0, 0.3, 11));
    let f = 100u32;
    let bary = [0.2, 0.5, 0.3];
    let c = mesh.face(f).map(|v| mesh.position(v));
    let q_face = c[0] * bary[0] + c[1] * bary[1] + c[2] * bary[2];
    let h = 3 * 57 + 1;
    let (a, b) = (mesh.position(mesh.tail(h)), mesh.position(mesh.head(h)));
    let q_edge = a + (b - a) * 0.25;
    for s in BOTH {
        let sources = [
            Source::FacePoint {
                face: f,
                barycentric: bary,
            },
            Source::EdgePoint {
                half_edge: h,
                t: 0.25,
            },
        ];
        for (src, q) in sources.iter().zip([q_face, q_edge]) {
            let (field, _) = solve(&mesh, std::slice::from_ref(src), &opts(s)).unwrap();
            let expected: Vec<f64> = (0..mesh.vertex_count() as u32)
                .map(|v| mesh.position(v).distance(q))
                .collect();
            let e = rel_err(&field.distance, &expected);
            assert!(e < 1e-14, "{s:?} {src:?}: {e:e}");
        }
        // Both at once: the nearest of the two, and which one it is.
        let (field, _) = solve(&mesh, &sources, &opts(s)).unwrap();
        for v in 0..mesh.vertex_count() as u32 {
            let p = mesh.position(v);
            let (d0, d1) = (p.distance(q_face), p.distance(q_edge));
            let d = d0.min(d1);
            assert!((field.distance[v as usize] - d).abs() < 1e-13);
            if (d0 - d1).abs() > 1e-9 {
                let nearest = if d0 < d1 { 0 } else { 1 };
                assert_eq!(field.nearest_source[v as usize], nearest);
            }
        }
    }
}

#[test]
fn max_distance_stops_the_wavefront() {
    let mesh = build(jittered_flat_grid(20, 20, 1.0, 0.3, 5));
    for s in BOTH {
        let full = solve(&mesh, &[Source::Vertex(0)], &opts(s)).unwrap();
        let limited = IchOptions {
            schedule: s,
            max_distance: Some(7.5),
            ..IchOptions::default()
        };
        let (field, stats) = solve(&mesh, &[Source::Vertex(0)], &limited).unwrap();
        assert!(stats.window_propagations < full.1.window_propagations);
        for (d, f) in field.distance.iter().zip(&full.0.distance) {
            if *f <= 7.5 {
                assert_eq!(d, f);
            } else {
                assert_eq!(*d, f64::INFINITY);
            }
        }
        assert!(field.nearest_source.contains(&NO_SOURCE));
    }
}

#[test]
fn geodesics_pass_through_a_pinch_vertex() {
    // Two unit grids touching at one corner: (1, 1) of the first is (0, 0)
    // of the second, shifted to (1, 1).
    let a = flat_grid(4, 4, 0.25);
    let b = flat_grid(4, 4, 0.25);
    let n = a.positions.len() as u32;
    let pinch_a = n - 1; // (1, 1) in a
    let mut positions = a.positions.clone();
    // b's vertex 0 is the pinch; the others are appended.
    let map = |v: u32| if v == 0 { pinch_a } else { n + v - 1 };
    positions.extend(
        b.positions[1..]
            .iter()
            .map(|p| *p + DVec3::new(1.0, 1.0, 0.0)),
    );
    let mut triangles = a.triangles.clone();
    triangles.extend(b.triangles.iter().map(|t| t.map(map)));
    let mesh = build(IndexedTriangles {
        positions,
        triangles,
    });
    assert!(mesh.is_pinch(pinch_a));
    let far = n + 24 - 1; // (2, 2)
    for s in BOTH {
        let (field, _) = solve(&mesh, &[Source::Vertex(0)], &opts(s)).unwrap();
        let d = field.distance[far as usize];
        assert!((d - 2.0 * 2f64.sqrt()).abs() < 1e-14, "{s:?}: {d}");
        // A source at the pinch itself lights both fans.
        let (field, _) = solve(&mesh, &[Source::Vertex(pinch_a)], &opts(s)).unwrap();
        assert!((field.distance[0] - 2f64.sqrt()).abs() < 1e-14);
        assert!((field.distance[far as usize] - 2f64.sqrt()).abs() < 1e-14);
    }
}

#[test]
fn other_components_stay_unreachable() {
    let a = flat_grid(3, 3, 1.0);
    let n = a.positions.len() as u32;
    let mut positions = a.positions.clone();
    positions.extend(a.positions.iter().map(|p| *p + DVec3::new(10.0, 0.0, 0.0)));
    let mut triangles = a.triangles.clone();
    triangles.extend(a.triangles.iter().map(|t| t.map(|v| v + n)));
    let mesh = build(IndexedTriangles {
        positions,
        triangles,
    });
    for s in BOTH {
        let (field, _) = solve(&mesh, &[Source::Vertex(0)], &opts(s)).unwrap();
        assert!(field.distance[..n as usize].iter().all(|d| d.is_finite()));
        assert!(field.distance[n as usize..].iter().all(|d| d.is_infinite()));
        assert!(
            field.nearest_source[n as usize..]
                .iter()
                .all(|&s| s == NO_SOURCE)
        );
    }
}

#[test]
fn bad_input_is_an_error() {
    let mesh = build(flat_grid(2, 2, 1.0));
    let o = IchOptions::default();
    assert_eq!(
        solve(&mesh, &[], &o).unwrap_err(),
        IchError::Source(SourceError::NoSources)
    );
    assert!(matches!(
        solve(&mesh, &[Source::Vertex(9)], &o),
        Err(IchError::Source(SourceError::VertexOutOfRange {
            vertex: 9,
            ..
        }))
    ));
    assert!(matches!(
        solve(
            &mesh,
            &[Source::EdgePoint {
                half_edge: 0,
                t: 1.5
            }],
            &o
        ),
        Err(IchError::Source(SourceError::EdgeParameter { .. }))
    ));
    assert!(matches!(
        solve(
            &mesh,
            &[Source::EdgePoint {
                half_edge: 99,
                t: 0.5
            }],
            &o
        ),
        Err(IchError::Source(SourceError::HalfEdgeOutOfRange { .. }))
    ));
    assert!(matches!(
        solve(
            &mesh,
            &[Source::FacePoint {
                face: 0,
                barycentric: [0.5, 0.5, 0.5]
            }],
            &o
        ),
        Err(IchError::Source(SourceError::Barycentric { .. }))
    ));
    assert!(matches!(
        solve(
            &mesh,
            &[Source::FacePoint {
                face: 8,
                barycentric: [1.0, 0.0, 0.0]
            }],
            &o
        ),
        Err(IchError::Source(SourceError::FaceOutOfRange { .. }))
    ));
    let neg = IchOptions {
        max_distance: Some(-1.0),
        ..IchOptions::default()
    };
    assert!(matches!(
        solve(&mesh, &[Source::Vertex(0)], &neg),
        Err(IchError::Source(SourceError::MaxDistance(_)))
    ));
    let mut soup = flat_grid(2, 2, 1.0);
    soup.positions.push(DVec3::ZERO);
    let mesh = build(soup);
    assert!(matches!(
        solve(&mesh, &[Source::Vertex(9)], &o),
        Err(IchError::Source(SourceError::UnreferencedVertex {
            vertex: 9,
            ..
        }))
    ));
}
