//! A mesh renumbered for memory locality (`BuildOptions::reorder`, what the
//! CLI and the benchmarks use) gives the same answers, in the input's
//! numbering, as the mesh kept in file order: the same triangles back, the
//! same fans, the same distances (to within the exactness bar: the order of
//! floating-point work changes) from vertex, face and edge sources, for
//! every solver, and paths of the same length through the same input
//! vertices' positions.

use geodesics::{Algorithm, compute, shortest_path};
use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
use geodesics_shapes::{bumpy_sphere, regular_torus};
use geodesics_tests::{EXACT, data_dir, max_finite};
use geodesics_window::Source;

fn both(soup: &IndexedTriangles, weld: bool) -> (Mesh, Mesh) {
    let build = |reorder| {
        Mesh::build(soup.clone(), &BuildOptions { weld, reorder }).unwrap_or_else(|e| panic!("{e}"))
    };
    (build(false), build(true))
}

/// The same input face as a source on each mesh: a face point, and an
/// edge point on its first edge (as the file lists its corners).
fn point_sources(kept: &Mesh, renumbered: &Mesh, input_face: u32) -> [(Source, Source); 2] {
    let barycentric = [0.2, 0.3, 0.5];
    let face = |m: &Mesh| Source::FacePoint {
        face: m.mesh_face(input_face),
        barycentric,
    };
    let edge = |m: &Mesh| {
        let f = m.mesh_face(input_face);
        // Half-edge 3f runs between the same two input vertices in both.
        Source::EdgePoint {
            half_edge: 3 * f,
            t: 0.25,
        }
    };
    [
        (face(kept), face(renumbered)),
        (edge(kept), edge(renumbered)),
    ]
}

fn assert_close(what: &str, a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    let max = max_finite(a);
    let mut worst = 0.0f64;
    for (i, (&x, &y)) in a.iter().zip(b).enumerate() {
        assert_eq!(
            x.is_finite(),
            y.is_finite(),
            "{what}: vertex {i}: {x} vs {y}"
        );
        if x.is_finite() {
            worst = worst.max((x - y).abs());
            assert!(
                (x - y).abs() <= EXACT * max,
                "{what}: vertex {i}: {x} vs {y}"
            );
        }
    }
    eprintln!("reorder {what}: max |diff| / max = {:.2e}", worst / max);
}

fn check(name: &str, soup: &IndexedTriangles, weld: bool, algorithms: &[&str]) {
    let (kept, renumbered) = both(soup, weld);
    // The mesh itself.
    assert_eq!(kept.summary(), renumbered.summary(), "{name}: summary");
    assert_eq!(
        kept.to_indexed_triangles(),
        renumbered.to_indexed_triangles(),
        "{name}: triangles back in input numbering"
    );
    for u in 0..kept.input_vertex_count() as u32 {
        let (a, b) = (u, renumbered.mesh_vertex(u));
        assert_eq!(
            renumbered.pinch_origin(b),
            u,
            "{name}: vertex {u} round trip"
        );
        assert_eq!(kept.position(a), renumbered.position(b));
        assert_eq!(kept.angle_sum(a), renumbered.angle_sum(b));
        assert_eq!(kept.is_boundary(a), renumbered.is_boundary(b));
        assert_eq!(
            kept.pinch_fans(a).count(),
            renumbered.pinch_fans(b).count(),
            "{name}: fans of {u}"
        );
        // Fans in the same counter-clockwise order, from the same face.
        let fan = |m: &Mesh, v: u32| -> Vec<(u32, u32)> {
            m.outgoing(v)
                .map(|h| (m.input_face(Mesh::face_of(h)), h % 3))
                .collect()
        };
        assert_eq!(fan(&kept, a), fan(&renumbered, b), "{name}: fan of {u}");
    }
    for f in 0..kept.face_count() as u32 {
        let g = renumbered.mesh_face(f);
        assert_eq!(renumbered.input_face(g), f);
        assert_eq!(kept.is_reoriented(f), renumbered.is_reoriented(g));
    }
    // Distances, from a vertex, several vertices, a face point, an edge point.
    let n = kept.input_vertex_count() as u32;
    let referenced = |m: &Mesh, u: u32| m.is_referenced(m.mesh_vertex(u));
    let vertex = (0..n)
        .find(|&u| referenced(&kept, u))
        .expect("a referenced vertex");
    let far = (0..n)
        .rev()
        .find(|&u| referenced(&kept, u))
        .expect("a referenced vertex");
    let mut cases: Vec<(String, Vec<Source>, Vec<Source>)> = vec![
        (
            format!("vertex {vertex}"),
            vec![Source::Vertex(vertex)],
            vec![Source::Vertex(vertex)],
        ),
        (
            format!("vertices {vertex}, {far}"),
            vec![Source::Vertex(vertex), Source::Vertex(far)],
            vec![Source::Vertex(vertex), Source::Vertex(far)],
        ),
    ];
    let face = kept.face_count() as u32 / 3;
    for (a, b) in point_sources(&kept, &renumbered, face) {
        cases.push((format!("{a:?} (input face {face})"), vec![a], vec![b]));
    }
    for algorithm in algorithms {
        let algorithm: Algorithm = algorithm.parse().expect("a known algorithm");
        for (label, sa, sb) in &cases {
            let (fa, _) = compute(&kept, sa, &algorithm).expect("solves in file order");
            let (fb, _) = compute(&renumbered, sb, &algorithm).expect("solves renumbered");
            let what = format!("{name} {} {label}", algorithm.name());
            assert_close(&what, &fa.distance, &fb.distance);
        }
    }
    // Paths to a few vertices: same length, same start and end points.
    let field = compute(&kept, &cases[0].1, &"vtp".parse().unwrap())
        .unwrap()
        .0;
    let max = max_finite(&field.distance);
    for target in (0..n).step_by((n as usize / 7).max(1)) {
        if !field.distance[target as usize].is_finite() {
            continue;
        }
        for algorithm in algorithms.iter().filter(|a| ["vtp", "mmp"].contains(a)) {
            let algorithm: Algorithm = algorithm.parse().unwrap();
            let pa = shortest_path(&kept, &cases[0].1, target, &algorithm).unwrap();
            let pb = shortest_path(&renumbered, &cases[0].2, target, &algorithm).unwrap();
            assert!(
                (pa.length - pb.length).abs() <= EXACT * max,
                "{name}: path to {target}: {} vs {}",
                pa.length,
                pb.length
            );
            assert_eq!(pa.points.last(), pb.points.last(), "{name}: path end");
            assert_eq!(
                pa.polyline.first(),
                pb.polyline.first(),
                "{name}: path start"
            );
            assert_eq!(pa.polyline.last(), pb.polyline.last(), "{name}: path end");
        }
    }
}

const ALL: &[&str] = &["vtp", "pvtp", "pvtp-rounds", "avtp", "mmp", "ich"];

#[test]
fn procedural_meshes() {
    check(
        "bumpy sphere",
        &bumpy_sphere(3, 1.0, 12, 0.25, 7),
        false,
        ALL,
    );
    check(
        "regular torus",
        &regular_torus(48, 16, 1.0, 0.4),
        false,
        ALL,
    );
}

/// Real files: a pinch vertex (cow), boundaries and unreferenced vertices
/// (bunny_zipper), a scattered file order (armadillo), welding (dragon).
#[test]
fn real_meshes() {
    let Some(data) = data_dir("reorder real meshes") else {
        return;
    };
    for (file, weld, algorithms) in [
        ("cow.obj", false, ALL),
        (
            "bunny_zipper.ply",
            false,
            &["vtp", "pvtp", "pvtp-rounds"][..],
        ),
        ("armadillo.obj", false, &["vtp", "avtp"][..]),
        ("blade.off", false, &["vtp"][..]),
    ] {
        let soup = geodesics_io::read_mesh(&data.join(file)).unwrap_or_else(|e| panic!("{e}"));
        check(file, &soup, weld, algorithms);
    }
}
