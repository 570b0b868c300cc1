//! Loop and midpoint subdivision: counts, topology, weights, errors.

use geodesics_mesh::{BuildOptions, Mesh, MeshSummary};
use geodesics_shapes::*;
use glam::DVec3;

fn summary(m: &IndexedTriangles) -> MeshSummary {
    Mesh::build(m.clone(), &BuildOptions::default())
        .expect("valid mesh")
        .summary()
        .clone()
}

fn samples() -> Vec<(&'static str, IndexedTriangles)> {
    vec![
        ("icosphere", icosphere(2, 1.0)),
        ("torus", regular_torus(12, 8, 1.0, 0.3)),
        ("grid", flat_grid(5, 4, 1.0)),
        ("jittered grid", jittered_flat_grid(6, 3, 0.5, 0.3, 2)),
        ("bumpy", bumpy_sphere(2, 1.0, 10, 0.2, 4)),
        ("tetrahedron", tetrahedron()),
        ("cone", cone()),
    ]
}

fn tetrahedron() -> IndexedTriangles {
    IndexedTriangles {
        positions: vec![
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
        ],
        triangles: vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
    }
}

/// Three triangles around apex 0: a disc whose boundary is the triangle 1-2-3.
fn cone() -> IndexedTriangles {
    IndexedTriangles {
        positions: vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-1.0, 0.0, 0.5),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3], [0, 3, 1]],
    }
}

type Subdivide = fn(&IndexedTriangles, u32) -> Result<IndexedTriangles, ShapeError>;
const SCHEMES: [(&str, Subdivide); 2] =
    [("loop", loop_subdivide), ("midpoint", midpoint_subdivide)];

#[test]
fn counts_and_topology_are_kept() {
    for (name, m) in samples() {
        let before = summary(&m);
        for (scheme, subdivide) in SCHEMES {
            let once = subdivide(&m, 1).expect("manifold");
            let after = summary(&once);
            assert_eq!(
                after.vertices,
                before.vertices + before.edges,
                "{scheme} {name}"
            );
            assert_eq!(after.faces, 4 * before.faces, "{scheme} {name}");
            assert_eq!(
                after.edges,
                2 * before.edges + 3 * before.faces,
                "{scheme} {name}"
            );
            assert_eq!(
                (
                    after.euler_characteristic,
                    after.genus,
                    after.boundary_loops,
                    after.components
                ),
                (
                    before.euler_characteristic,
                    before.genus,
                    before.boundary_loops,
                    before.components
                ),
                "{scheme} {name}"
            );
            assert_eq!(
                after.reoriented_faces, 0,
                "{scheme} {name}: orientation lost"
            );
            assert_eq!(after.zero_area_faces, 0, "{scheme} {name}");
            let twice = subdivide(&m, 2).expect("manifold");
            assert_eq!(twice.triangles.len(), 16 * m.triangles.len());
            assert_eq!(
                twice.positions.len(),
                after.vertices + after.edges,
                "{scheme} {name}"
            );
            assert_eq!(subdivide(&m, 0).expect("manifold"), m);
        }
    }
}

#[test]
fn icosphere_4_is_icosphere_3_subdivided_topologically() {
    let a = midpoint_subdivide(&icosphere(3, 1.0), 1).expect("manifold");
    assert_eq!(a.triangles, icosphere(4, 1.0).triangles);
}

#[test]
fn loop_weights_on_a_tetrahedron() {
    let m = tetrahedron();
    let s = loop_subdivide(&m, 1).expect("manifold");
    let p = &m.positions;
    // Valence 3: β = 3/16, old vertex = (1 − 9/16)·v + 3/16·Σ neighbours.
    for v in 0..4 {
        let others: DVec3 = (0..4).filter(|&u| u != v).map(|u| p[u]).sum();
        let expected = p[v] * (7.0 / 16.0) + others * (3.0 / 16.0);
        assert!(s.positions[v].distance(expected) < 1e-15);
    }
    // Edges sorted by (min, max): 01, 02, 03, 12, 13, 23. Edge ab with
    // opposite corners c, d: 3/8 (a + b) + 1/8 (c + d).
    let edges = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
    for (e, &(a, b)) in edges.iter().enumerate() {
        let (c, d): (Vec<usize>, Vec<usize>) =
            (0..4).filter(|&u| u != a && u != b).partition(|_| true);
        let cd: DVec3 = c.iter().chain(&d).map(|&u| p[u]).sum();
        let expected = (p[a] + p[b]) * 0.375 + cd * 0.125;
        assert!(s.positions[4 + e].distance(expected) < 1e-15, "edge {a}{b}");
    }
}

#[test]
fn loop_weights_valence_and_boundary() {
    // Regular valence-6 vertex: β = 3/(8·6) = 1/16.
    let g = flat_grid(2, 2, 1.0);
    let s = loop_subdivide(&g, 1).expect("manifold");
    // Interior vertex 4 of a planar grid is the average of a symmetric ring: fixed.
    assert!(s.positions[4].distance(g.positions[4]) < 1e-15);
    // Boundary vertex 1 (bottom middle): 3/4 v + 1/8 (v0 + v2), on the line.
    assert!(s.positions[1].distance(DVec3::new(1.0, 0.0, 0.0)) < 1e-15);
    // Corner 0: 3/4·(0,0) + 1/8·((1,0) + (0,1)).
    assert!(s.positions[0].distance(DVec3::new(0.125, 0.125, 0.0)) < 1e-15);
    // A lifted interior vertex with valence 6 moves by (1 − 6β) = 5/8 of its lift.
    let mut lifted = g.clone();
    lifted.positions[4].z = 1.0;
    let s = loop_subdivide(&lifted, 1).expect("manifold");
    assert!((s.positions[4].z - 0.625).abs() < 1e-15);
    // Interior edge 4–5 (opposite corners 8 and 1): 3/8 of the lift. The
    // midpoint split numbers vertices alike, so find it there by position.
    let mid = midpoint_subdivide(&g, 1).expect("manifold");
    let e = mid
        .positions
        .iter()
        .position(|p| *p == DVec3::new(1.5, 1.0, 0.0))
        .expect("midpoint of edge 4-5");
    assert!((s.positions[e].z - 0.375).abs() < 1e-15);
    assert!(
        s.positions[e]
            .truncate()
            .distance(glam::DVec2::new(1.5, 1.0))
            < 1e-15
    );

    // A cone: apex 0 interior with valence 3, base vertices on the boundary.
    let cone = cone();
    let s = loop_subdivide(&cone, 1).expect("manifold");
    let p = &cone.positions;
    let apex = p[0] * (7.0 / 16.0) + (p[1] + p[2] + p[3]) * (3.0 / 16.0);
    assert!(s.positions[0].distance(apex) < 1e-15);
    // Boundary vertex 1 with boundary neighbours 2 and 3: 3/4 v + 1/8 (b₁ + b₂).
    let rim = p[1] * 0.75 + (p[2] + p[3]) * 0.125;
    assert!(s.positions[1].distance(rim) < 1e-15);
    // Boundary edge 1–2 (edge id 3 after 01, 02, 03): its midpoint.
    assert!(s.positions[4 + 3].distance((p[1] + p[2]) * 0.5) < 1e-15);
}

#[test]
fn loop_of_planar_grid_is_planar_and_matches_midpoints_inside() {
    let g = jittered_flat_grid(8, 6, 1.0, 0.0, 0);
    let l = loop_subdivide(&g, 1).expect("manifold");
    let m = midpoint_subdivide(&g, 1).expect("manifold");
    assert!(l.positions.iter().all(|p| p.z == 0.0));
    let s = Mesh::build(m.clone(), &BuildOptions::default()).expect("valid");
    for v in 0..m.positions.len() as u32 {
        if !s.is_boundary(v) {
            assert!(l.positions[v as usize].distance(m.positions[v as usize]) < 1e-13);
        }
    }
}

#[test]
fn loop_shrinks_a_sphere_slightly() {
    let m = loop_subdivide(&icosphere(3, 1.0), 2).expect("manifold");
    for p in &m.positions {
        let r = p.length();
        assert!(r < 1.0 && r > 0.98, "{r}");
    }
}

#[test]
fn midpoint_keeps_the_surface() {
    for (name, m) in samples() {
        let s = midpoint_subdivide(&m, 2).expect("manifold");
        // Old vertices keep their indices and exact positions.
        assert_eq!(s.positions[..m.positions.len()], m.positions[..], "{name}");
        let area = |m: &IndexedTriangles| -> f64 {
            m.triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|v| m.positions[v as usize]);
                    (b - a).cross(c - a).length() / 2.0
                })
                .sum()
        };
        assert!((area(&s) - area(&m)).abs() < 1e-12 * area(&m), "{name}");
        // Every new vertex lies on an edge of the original mesh.
        let once = midpoint_subdivide(&m, 1).expect("manifold");
        let mesh = Mesh::build(m.clone(), &BuildOptions::default()).expect("valid");
        for (k, p) in once.positions[m.positions.len()..].iter().enumerate() {
            let on_edge = (0..mesh.half_edge_count() as u32).any(|h| {
                let (a, b) = (mesh.position(mesh.tail(h)), mesh.position(mesh.head(h)));
                (a.distance(*p) + p.distance(b) - a.distance(b)).abs() < 1e-14
            });
            assert!(on_edge, "{name}: new vertex {k} off the edges");
        }
    }
}

#[test]
fn non_manifold_input_is_an_error() {
    // Three triangles on the edge 0-1.
    let m = IndexedTriangles {
        positions: vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
            DVec3::new(0.5, -1.0, 0.0),
        ],
        triangles: vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
    };
    for (scheme, subdivide) in SCHEMES {
        for steps in [0, 1, 2] {
            let err = subdivide(&m, steps).expect_err(scheme);
            assert_eq!(
                err,
                ShapeError::NonManifoldEdge {
                    a: 0,
                    b: 1,
                    faces: vec![0, 1, 2]
                },
                "{scheme}"
            );
            assert_eq!(
                err.to_string(),
                "non-manifold edge between vertices 0 and 1: shared by faces [0, 1, 2]"
            );
        }
    }
}

#[test]
fn malformed_input_is_an_error() {
    let mut m = tetrahedron();
    m.triangles[2] = [0, 2, 7];
    for (_, subdivide) in SCHEMES {
        assert_eq!(
            subdivide(&m, 1),
            Err(ShapeError::IndexOutOfRange {
                face: 2,
                index: 7,
                vertices: 4
            })
        );
    }
    m.triangles[2] = [0, 2, 0];
    for (_, subdivide) in SCHEMES {
        assert_eq!(
            subdivide(&m, 1),
            Err(ShapeError::RepeatedVertex {
                face: 2,
                corners: [0, 2, 0]
            })
        );
    }
    // A NaN or infinite coordinate would spread to the new vertices around
    // it; it is refused, even with no step to take.
    let mut m = tetrahedron();
    m.positions[3].z = f64::INFINITY;
    for (_, subdivide) in SCHEMES {
        for steps in [0, 1] {
            let err = subdivide(&m, steps).unwrap_err();
            assert!(
                matches!(err, ShapeError::NonFiniteCoordinate { vertex: 3, .. }),
                "{err:?}"
            );
            assert!(
                err.to_string()
                    .starts_with("vertex 3 has a non-finite coordinate")
            );
        }
    }
    // Empty input subdivides to empty output.
    let empty = IndexedTriangles::default();
    assert_eq!(loop_subdivide(&empty, 3), Ok(empty));
}

#[test]
fn unreferenced_vertices_stay() {
    let mut m = tetrahedron();
    m.positions.push(DVec3::new(5.0, 5.0, 5.0));
    let s = loop_subdivide(&m, 1).expect("manifold");
    assert_eq!(s.positions[4], DVec3::new(5.0, 5.0, 5.0));
    assert_eq!(s.positions.len(), 5 + 6);
}
