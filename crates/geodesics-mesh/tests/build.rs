//! Construction, validation and statistics of `Mesh` on small explicit meshes.

use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh, MeshError};
use glam::DVec3;

fn soup(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> IndexedTriangles {
    IndexedTriangles {
        positions: positions.iter().map(|&p| DVec3::from_array(p)).collect(),
        triangles: triangles.to_vec(),
    }
}

fn build(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<Mesh, MeshError> {
    Mesh::build(soup(positions, triangles), &BuildOptions::default())
}

const TET_P: [[f64; 3]; 4] = [
    [1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
];
const TET_T: [[u32; 3]; 4] = [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];

/// Two unit squares' worth of triangles: an open square split by a diagonal.
const SQUARE_P: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
];
const SQUARE_T: [[u32; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

#[test]
fn tetrahedron_is_closed_genus_zero_and_linked() {
    let mesh = build(&TET_P, &TET_T).unwrap();
    let s = mesh.summary();
    assert_eq!(s.vertices, 4);
    assert_eq!(s.faces, 4);
    assert_eq!(s.edges, 6);
    assert_eq!(s.components, 1);
    assert_eq!(s.boundary_loops, 0);
    assert_eq!(s.euler_characteristic, 2);
    assert_eq!(s.genus, Some(0));
    assert_eq!(s.saddle_vertices, 0);
    assert_eq!(s.reoriented_faces, 0);
    for h in 0..mesh.half_edge_count() as u32 {
        let t = mesh.twin(h).expect("closed mesh has a twin everywhere");
        assert_eq!(mesh.twin(t), Some(h));
        assert_eq!(mesh.tail(t), mesh.head(h));
        assert_eq!(mesh.head(t), mesh.tail(h));
        assert!((mesh.length(h) - 8f64.sqrt()).abs() < 1e-15);
        assert!((mesh.corner_angle(h) - std::f64::consts::FRAC_PI_3).abs() < 1e-14);
    }
    for v in 0..4 {
        assert_eq!(mesh.outgoing(v).count(), 3);
        assert!(mesh.outgoing(v).all(|h| mesh.tail(h) == v));
    }
    // Regular tetrahedron: anisotropy 1 everywhere.
    assert!((s.anisotropy.mean - 1.0).abs() < 1e-12);
    assert!((s.bbox_diagonal - 12f64.sqrt()).abs() < 1e-15);
}

#[test]
fn apex_is_the_opposite_corner_in_the_half_edge_frame() {
    // A scalene triangle and a needle with a zero-length edge.
    let p = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.5, 1.0, 0.3],
        [5.0, 5.0, 5.0],
        [5.0, 5.0, 5.0],
        [6.0, 5.0, 5.0],
    ];
    let mesh = build(&p, &[[0, 1, 2], [3, 4, 5]]).unwrap();
    for h in 0..3 {
        let (a, b) = (mesh.position(mesh.tail(h)), mesh.position(mesh.head(h)));
        let c = mesh.position(mesh.opposite_vertex(h));
        let q = mesh.apex(h);
        assert!(q.y > 0.0, "the face lies above the half-edge");
        assert!((q.length() - a.distance(c)).abs() < 1e-15);
        assert!((q.distance(glam::DVec2::new(mesh.length(h), 0.0)) - b.distance(c)).abs() < 1e-15);
    }
    assert_eq!(mesh.apex(0), glam::DVec2::new(0.5, 1.09f64.sqrt()));
    // The zero-length half-edge maps everything to its tail.
    let zero = (3..6).find(|&h| mesh.length(h) == 0.0).unwrap();
    assert_eq!(mesh.apex(zero), glam::DVec2::ZERO);
    // The needle is a zipper: entering along one long edge, a window
    // leaves along the other; along the zero-length edge, nowhere.
    assert_eq!(mesh.face_kind(1), geodesics_mesh::FaceKind::Zipper);
    assert_eq!(mesh.zipper_exit(zero), None);
    let long: Vec<u32> = (3..6).filter(|&h| h != zero).collect();
    assert_eq!(mesh.zipper_exit(long[0]), Some(long[1]));
    assert_eq!(mesh.zipper_exit(long[1]), Some(long[0]));
}

#[test]
fn inconsistent_orientation_is_repaired() {
    let mut t = TET_T;
    t[2] = [0, 3, 2]; // flipped
    t[3] = [1, 2, 3]; // flipped
    let mesh = build(&TET_P, &t).unwrap();
    assert_eq!(mesh.summary().reoriented_faces, 2);
    for h in 0..mesh.half_edge_count() as u32 {
        let tw = mesh.twin(h).unwrap();
        assert_eq!(mesh.tail(tw), mesh.head(h));
    }
}

#[test]
fn open_square_has_one_boundary_loop() {
    let mesh = build(&SQUARE_P, &SQUARE_T).unwrap();
    let s = mesh.summary();
    assert_eq!((s.boundary_loops, s.boundary_vertices), (1, 4));
    assert_eq!(s.euler_characteristic, 1);
    assert_eq!(s.genus, Some(0));
    for v in 0..4 {
        assert!(mesh.is_boundary(v));
        assert!(!mesh.is_saddle(v));
        // The fan walk from the stored half-edge visits every outgoing edge.
        let around: Vec<u32> = mesh.outgoing(v).collect();
        let expected = if v == 0 || v == 2 { 2 } else { 1 };
        assert_eq!(around.len(), expected, "vertex {v}");
    }
    assert!((mesh.angle_sum(0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
}

/// A 4×4-vertex grid of triangles with one corner cut off: interior and
/// boundary vertices, faces numbered in no particular order around them.
fn grid_mesh() -> Mesh {
    let n = 4u32;
    let mut positions = Vec::new();
    for j in 0..n {
        for i in 0..n {
            positions.push([i as f64, j as f64, 0.1 * ((i * j) % 3) as f64]);
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let (a, b, c, d) = (
                j * n + i,
                j * n + i + 1,
                (j + 1) * n + i + 1,
                (j + 1) * n + i,
            );
            if (i, j) != (n - 2, n - 2) {
                triangles.push([a, b, c]);
            }
            triangles.push([a, c, d]);
        }
    }
    // Scramble the face order.
    triangles.reverse();
    triangles.swap(0, 7);
    build(&positions, &triangles).unwrap()
}

#[test]
fn fans_run_counter_clockwise_from_the_boundary() {
    let mesh = grid_mesh();
    let nh = mesh.half_edge_count() as u32;
    for v in 0..mesh.vertex_count() as u32 {
        let around: Vec<u32> = mesh.outgoing(v).collect();
        // Every half-edge leaving v, once.
        let mut leaving: Vec<u32> = (0..nh).filter(|&h| mesh.tail(h) == v).collect();
        let mut sorted = around.clone();
        sorted.sort_unstable();
        leaving.sort_unstable();
        assert_eq!(sorted, leaving, "vertex {v}");
        // Each the twin of the half-edge before the previous one.
        for w in around.windows(2) {
            assert_eq!(mesh.twin(Mesh::prev(w[0])), Some(w[1]), "vertex {v}");
        }
        // A boundary fan starts at the boundary edge leaving v and ends at
        // the face whose incoming edge is the other boundary edge.
        if mesh.is_boundary(v) {
            assert_eq!(mesh.twin(around[0]), None, "vertex {v}");
            assert_eq!(mesh.twin(Mesh::prev(*around.last().unwrap())), None);
        } else {
            let last = *around.last().unwrap();
            assert_eq!(mesh.twin(Mesh::prev(last)), Some(around[0]), "vertex {v}");
        }
        assert_eq!(mesh.outgoing(v).count(), around.len());
        assert_eq!(mesh.vertex_half_edge(v), around.first().copied());
        // The fan table holds the same walk.
        assert_eq!(mesh.fan(v), &around[..], "vertex {v}");
    }
}

#[test]
fn unreferenced_vertices_are_kept_and_counted() {
    let mut p = SQUARE_P.to_vec();
    p.push([5.0, 5.0, 5.0]);
    let mesh = build(&p, &SQUARE_T).unwrap();
    assert_eq!(mesh.summary().vertices, 5);
    assert_eq!(mesh.summary().unreferenced_vertices, 1);
    assert!(!mesh.is_referenced(4));
    assert_eq!(mesh.component(4), None);
    // The unreferenced vertex does not stretch the bounding box.
    assert!((mesh.bbox_diagonal() - 2f64.sqrt()).abs() < 1e-15);
}

#[test]
fn pinch_vertex_is_split_into_fans() {
    // Two tetrahedra sharing vertex 0 only.
    let mut p = TET_P.to_vec();
    p.extend([[3.0, 1.0, 1.0], [3.0, 3.0, 3.0], [1.0, 3.0, 1.0]]);
    let mut t = TET_T.to_vec();
    // Second tetrahedron: 0,4,5,6 (orientation need not be right).
    t.extend([[0, 4, 5], [0, 5, 6], [0, 6, 4], [4, 6, 5]]);
    let mesh = build(&p, &t).unwrap();
    let s = mesh.summary();
    assert_eq!(s.nonmanifold_vertices, 1);
    assert_eq!(s.genus, None);
    assert_eq!(s.components, 1);
    assert_eq!(s.euler_characteristic, 7 - 12 + 8);
    assert_eq!(mesh.vertex_count(), 8);
    assert_eq!(mesh.input_vertex_count(), 7);
    assert_eq!(mesh.pinch_origin(7), 0);
    assert_eq!(mesh.pinch_group(0), vec![7]);
    assert_eq!(mesh.pinch_group(7), vec![0]);
    assert!(mesh.is_pinch(0) && !mesh.is_pinch(1));
    assert_eq!(mesh.position(7), mesh.position(0));
    // Each fan is a closed cone of three faces.
    assert_eq!(mesh.outgoing(0).count(), 3);
    assert_eq!(mesh.outgoing(7).count(), 3);
    // Edge-connected pieces stay apart, the input-vertex count sees one.
    assert_ne!(mesh.component(1), mesh.component(4));
    let folded = mesh.fold_to_input(&[5.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 2.0]);
    assert_eq!(folded, vec![2.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]);
}

#[test]
fn weld_merges_equal_positions_and_drops_collapsed_faces() {
    // The square with vertex 2 duplicated as 4, plus a face that collapses.
    let mut p = SQUARE_P.to_vec();
    p.push([1.0, 1.0, 0.0]);
    let t = [[0, 1, 2], [0, 4, 3], [2, 4, 1]];
    let as_stored = build(&p, &t).unwrap();
    assert_eq!(as_stored.summary().duplicate_positions, 1);
    assert_eq!(as_stored.summary().zero_area_faces, 1);
    assert_eq!(as_stored.summary().components, 1);
    let welded = Mesh::build(
        soup(&p, &t),
        &BuildOptions {
            weld: true,
            ..BuildOptions::default()
        },
    )
    .unwrap();
    let s = welded.summary();
    assert_eq!((s.vertices, s.faces, s.welded_collapsed_faces), (4, 2, 1));
    assert_eq!((s.welded_vertices, s.duplicate_positions), (1, 0));
    assert_eq!(s.boundary_loops, 1);
    assert_eq!(s.zero_area_faces, 0);
}

#[test]
fn saddle_vertex_is_detected() {
    // A vertex surrounded by a zig-zag ring: angle sum above 2π.
    let n = 8;
    let mut p = vec![[0.0, 0.0, 0.0]];
    for i in 0..n {
        let a = i as f64 * std::f64::consts::TAU / n as f64;
        let z = if i % 2 == 0 { 0.8 } else { -0.8 };
        p.push([a.cos(), a.sin(), z]);
    }
    let t: Vec<[u32; 3]> = (0..n).map(|i| [0, 1 + i, 1 + (i + 1) % n]).collect();
    let mesh = build(&p, &t).unwrap();
    assert!(mesh.angle_sum(0) > std::f64::consts::TAU);
    assert!(mesh.is_saddle(0));
    assert_eq!(mesh.summary().saddle_vertices, 1);
}

#[test]
fn defects_are_named() {
    assert_eq!(
        build(&TET_P, &[]).unwrap_err(),
        MeshError::Empty { vertices: 4 }
    );
    assert_eq!(
        build(&TET_P, &[[0, 1, 9]]).unwrap_err(),
        MeshError::IndexOutOfRange {
            face: 0,
            index: 9,
            vertices: 4
        }
    );
    assert_eq!(
        build(&TET_P, &[[0, 1, 2], [1, 1, 3]]).unwrap_err(),
        MeshError::RepeatedVertex {
            face: 1,
            corners: [1, 1, 3]
        }
    );
    let mut nan = TET_P;
    nan[2][1] = f64::NAN;
    let err = build(&nan, &TET_T).unwrap_err();
    assert!(matches!(
        err,
        MeshError::NonFiniteCoordinate { vertex: 2, .. }
    ));
    assert!(err.to_string().contains("vertex 2"));
    // Coordinates whose squares overflow, a mesh whose squares underflow:
    // refused (every distance came out ∞, or 0), but not a mesh at the
    // edge of the range nor one whose vertices all coincide.
    let mut huge = TET_P;
    huge[3][2] = -1e300;
    assert_eq!(
        build(&huge, &TET_T).unwrap_err(),
        MeshError::CoordinateTooLarge {
            vertex: 3,
            value: -1e300
        }
    );
    let tiny = TET_P.map(|p| p.map(|c| c * 1e-300));
    let err = build(&tiny, &TET_T).unwrap_err();
    assert_eq!(err, MeshError::TooSmall { extent: 2e-300 });
    assert!(err.to_string().contains("scale the mesh up"));
    for scale in [
        geodesics_mesh::MAX_COORDINATE,
        geodesics_mesh::MIN_EXTENT,
        0.0,
    ] {
        let scaled = TET_P.map(|p| p.map(|c| c * scale));
        assert!(build(&scaled, &TET_T).is_ok(), "scale {scale}");
    }
    // Three faces on edge 0-1.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let err = build(&p, &[[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap_err();
    assert_eq!(
        err,
        MeshError::NonManifoldEdge {
            a: 0,
            b: 1,
            faces: vec![0, 1, 2]
        }
    );
    assert_eq!(
        err.to_string(),
        "non-manifold edge between vertices 0 and 1: shared by faces [0, 1, 2]"
    );
}

#[test]
fn moebius_strip_is_refused() {
    let n = 12;
    let mut p = Vec::new();
    for i in 0..n {
        let a = i as f64 * std::f64::consts::TAU / n as f64;
        let half = a / 2.0;
        for s in [-0.3, 0.3] {
            let r = 2.0 + s * half.cos();
            p.push([r * a.cos(), r * a.sin(), s * half.sin()]);
        }
    }
    let mut t = Vec::new();
    for i in 0..n as u32 {
        let (a0, a1) = (2 * i, 2 * i + 1);
        let (b0, b1) = if i + 1 < n as u32 {
            (2 * i + 2, 2 * i + 3)
        } else {
            (1, 0) // the half twist
        };
        t.push([a0, b0, b1]);
        t.push([a0, b1, a1]);
    }
    let err = build(&p, &t).unwrap_err();
    assert!(matches!(err, MeshError::NonOrientable { .. }), "{err}");
}

/// Three tetrahedra sharing vertex 0 only.
fn three_tetrahedra_sharing_vertex_0() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut p = vec![[0.0, 0.0, 0.0]];
    let mut t = Vec::new();
    for k in 0..3 {
        let a = k as f64 * std::f64::consts::TAU / 3.0;
        let (c, s) = (a.cos(), a.sin());
        let base = p.len() as u32;
        p.extend([
            [2.0 * c, 2.0 * s, 0.0],
            [2.0 * c - s, 2.0 * s + c, 1.0],
            [2.0 * c + s, 2.0 * s - c, 1.0],
        ]);
        let (b, q, r) = (base, base + 1, base + 2);
        t.extend([[0, b, q], [0, q, r], [0, r, b], [b, r, q]]);
    }
    (p, t)
}

#[test]
fn three_fans_make_a_ring_of_copies() {
    let (p, t) = three_tetrahedra_sharing_vertex_0();
    let mesh = build(&p, &t).unwrap();
    assert_eq!(mesh.summary().nonmanifold_vertices, 1);
    assert_eq!(mesh.summary().components, 1);
    assert_eq!(mesh.vertex_count(), 12);
    assert_eq!(mesh.pinch_group(0), vec![10, 11]);
    assert_eq!(mesh.pinch_group(10), vec![0, 11]);
    assert_eq!(mesh.pinch_group(11), vec![0, 10]);
    for v in [0, 10, 11] {
        assert_eq!(mesh.outgoing(v).count(), 3, "fan {v}");
        assert_eq!(mesh.pinch_origin(v), 0);
    }
    // The fan table, renumbered or not, with unreferenced vertices: the
    // same walks as `outgoing`.
    let mut p = p;
    p.push([9.0, 9.0, 9.0]);
    for reorder in [false, true] {
        let options = BuildOptions {
            reorder,
            ..BuildOptions::default()
        };
        let mesh = Mesh::build(soup(&p, &t), &options).unwrap();
        for v in 0..mesh.vertex_count() as u32 {
            let around: Vec<u32> = mesh.outgoing(v).collect();
            assert_eq!(mesh.fan(v), &around[..], "vertex {v}, reorder {reorder}");
        }
        let lone = mesh.mesh_vertex(p.len() as u32 - 1);
        assert!(!mesh.is_referenced(lone) && mesh.fan(lone).is_empty());
    }
}

#[test]
fn reordered_mesh_translates_every_number() {
    // A pinch vertex with three fans, renumbered for locality, with and
    // without welding.
    let (p, t) = three_tetrahedra_sharing_vertex_0();
    for weld in [false, true] {
        let options = |reorder| BuildOptions { weld, reorder };
        let kept = Mesh::build(soup(&p, &t), &options(false)).unwrap();
        let mesh = Mesh::build(soup(&p, &t), &options(true)).unwrap();
        assert_eq!(kept.summary(), mesh.summary());
        assert_eq!(kept.to_indexed_triangles(), mesh.to_indexed_triangles());
        // Some number really moved (the test means something).
        assert!((0..10).any(|u| mesh.mesh_vertex(u) != u));
        assert!((0..12).any(|f| mesh.mesh_face(f) != f));
        for u in 0..kept.input_vertex_count() as u32 {
            let v = mesh.mesh_vertex(u);
            assert_eq!(mesh.pinch_origin(v), u);
            assert_eq!(mesh.position(v), kept.position(u));
            assert_eq!(mesh.angle_sum(v), kept.angle_sum(u));
        }
        // The pinch vertex: three fans, each a cone of three faces, ringed.
        let first = mesh.mesh_vertex(0);
        let group = mesh.pinch_group(first);
        assert_eq!(group.len(), 2);
        for v in std::iter::once(first).chain(group.iter().copied()) {
            assert!(mesh.is_pinch(v));
            assert_eq!(mesh.pinch_origin(v), 0);
            assert_eq!(mesh.outgoing(v).count(), 3);
            assert!(mesh.outgoing(v).all(|h| mesh.tail(h) == v));
        }
        assert!(!mesh.is_pinch_copy(first) && group.iter().all(|&v| mesh.is_pinch_copy(v)));
        // Faces: same corners (in input numbers), same flips; twins linked.
        for f in 0..mesh.face_count() as u32 {
            let g = mesh.mesh_face(f);
            assert_eq!(mesh.input_face(g), f);
            assert_eq!(
                mesh.face(g).map(|v| mesh.pinch_origin(v)),
                kept.face(f).map(|v| kept.pinch_origin(v))
            );
            assert_eq!(mesh.is_reoriented(g), kept.is_reoriented(f));
        }
        for h in 0..mesh.half_edge_count() as u32 {
            let tw = mesh.twin(h).expect("closed");
            assert_eq!(mesh.twin(tw), Some(h));
            assert_eq!((mesh.tail(tw), mesh.head(tw)), (mesh.head(h), mesh.tail(h)));
        }
        // Per-vertex values fold onto input vertices as before: the
        // minimum over a pinch vertex's fans.
        let values: Vec<f64> = (0..mesh.vertex_count() as u32)
            .map(|v| {
                if v == group[1] {
                    -1.0
                } else {
                    f64::from(mesh.pinch_origin(v))
                }
            })
            .collect();
        let folded = mesh.fold_to_input(&values);
        let expected: Vec<f64> = (0..10)
            .map(|u| if u == 0 { -1.0 } else { f64::from(u) })
            .collect();
        assert_eq!(folded, expected);
    }
}

#[test]
fn prefetch_hints_accept_any_vertex_or_face_number() {
    // Hints only: every vertex and face, and numbers past the end (a
    // solver may ask for an entry it computed from a sentinel), must be
    // accepted without a panic and change nothing.
    let mesh = grid_mesh();
    let before = mesh.fan(0).to_vec();
    let (nv, nf) = (mesh.vertex_count() as u32, mesh.face_count() as u32);
    for v in (0..nv).chain([nv, nv + 1, u32::MAX]) {
        mesh.prefetch_fan_table(v);
        mesh.prefetch_fan(v);
        mesh.prefetch_vertex(v);
    }
    for f in (0..nf).chain([nf, u32::MAX / 3]) {
        mesh.prefetch_face(f);
    }
    assert_eq!(mesh.fan(0), before.as_slice());
}
