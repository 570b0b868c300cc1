//! VTP invariants on small procedural meshes: metric properties (symmetry,
//! triangle inequality), bounds (Euclidean below, edge-graph Dijkstra
//! above), multi-source = minimum of single sources, exact answers on
//! planar domains (Euclidean, and around a reflex corner), every kind of
//! source, several components, the distance limit, and input errors.

use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
use geodesics_shapes::{bumpy_sphere, flat_grid, jittered_flat_grid, jittered_icosphere};
use geodesics_tests::edge_graph_distances;
use geodesics_vtp::{VtpError, VtpOptions, solve};
use geodesics_window::SourceError;
use geodesics_window::{NO_SOURCE, Source};
use glam::DVec3;
use proptest::prelude::*;

fn build(soup: IndexedTriangles) -> Mesh {
    Mesh::build(soup, &BuildOptions::default()).unwrap()
}

fn field(mesh: &Mesh, sources: &[Source]) -> Vec<f64> {
    solve(mesh, sources, &VtpOptions::default())
        .unwrap()
        .0
        .distance
}

fn check_invariants(mesh: &Mesh, a: u32, b: u32, c: u32) {
    let da = field(mesh, &[Source::Vertex(a)]);
    let db = field(mesh, &[Source::Vertex(b)]);
    let scale = da
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max);
    let tol = 1e-12 * scale.max(1.0);
    // Symmetry.
    assert!(
        (da[b as usize] - db[a as usize]).abs() <= tol,
        "symmetry {} vs {}",
        da[b as usize],
        db[a as usize]
    );
    // Triangle inequality.
    assert!(da[c as usize] <= da[b as usize] + db[c as usize] + tol);
    let g = edge_graph_distances(mesh, a);
    let pa = mesh.position(a);
    for v in 0..mesh.input_vertex_count() {
        let d = da[v];
        assert!(
            d >= pa.distance(mesh.position(v as u32)) - tol,
            "below Euclidean at {v}"
        );
        assert!(
            d <= g[v] + tol,
            "above edge-graph Dijkstra at {v}: {d} > {}",
            g[v]
        );
    }
    // Several sources: the pointwise minimum, with the right nearest source.
    let (m, _) = solve(
        mesh,
        &[Source::Vertex(a), Source::Vertex(b)],
        &VtpOptions::default(),
    )
    .unwrap();
    for v in 0..mesh.input_vertex_count() {
        let want = da[v].min(db[v]);
        assert!(
            (m.distance[v] - want).abs() <= tol,
            "multi at {v}: {} vs {want}",
            m.distance[v]
        );
        let from = [da[v], db[v]][m.nearest_source[v] as usize];
        assert!((from - m.distance[v]).abs() <= tol, "nearest source at {v}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, .. ProptestConfig::default() })]

    #[test]
    fn bumpy_spheres(seed in 0u64..1000, a in 0u32..162, b in 0u32..162, c in 0u32..162) {
        let mesh = build(bumpy_sphere(2, 1.0, 12, 0.25, seed));
        check_invariants(&mesh, a, b, c);
    }

    #[test]
    fn jittered_spheres(seed in 0u64..1000, a in 0u32..642, b in 0u32..642, c in 0u32..642) {
        let mesh = build(jittered_icosphere(3, 1.0, 0.1, seed));
        check_invariants(&mesh, a, b, c);
    }

    #[test]
    fn jittered_planar_grids_are_euclidean(seed in 0u64..1000, s in 0u32..121) {
        let mesh = build(jittered_flat_grid(10, 10, 1.0, 0.3, seed));
        let d = field(&mesh, &[Source::Vertex(s)]);
        let p = mesh.position(s);
        for v in 0..mesh.vertex_count() as u32 {
            let e = p.distance(mesh.position(v));
            prop_assert!((d[v as usize] - e).abs() <= 1e-12 * 15.0, "vertex {}: {} vs {}", v, d[v as usize], e);
        }
    }
}

#[test]
fn flat_grid_from_every_kind_of_source_is_euclidean() {
    let mesh = build(flat_grid(20, 20, 0.5));
    let tol = 1e-12 * 15.0;
    let h = 3 * 137 + 1;
    let a = mesh.position(mesh.tail(h));
    let b = mesh.position(mesh.head(h));
    let f = 301;
    let bary = [0.2, 0.3, 0.5];
    let c = mesh.face(f).map(|v| mesh.position(v));
    let q = c[0] * bary[0] + c[1] * bary[1] + c[2] * bary[2];
    let cases: Vec<(Source, DVec3)> = vec![
        (Source::Vertex(0), mesh.position(0)),
        (Source::Vertex(220), mesh.position(220)),
        (
            Source::EdgePoint {
                half_edge: h,
                t: 0.3,
            },
            a + (b - a) * 0.3,
        ),
        (
            Source::EdgePoint {
                half_edge: h,
                t: 1.0,
            },
            b,
        ),
        (
            Source::FacePoint {
                face: f,
                barycentric: bary,
            },
            q,
        ),
        (
            Source::FacePoint {
                face: f,
                barycentric: [0.0, 0.4, 0.6],
            },
            c[1] * 0.4 + c[2] * 0.6,
        ),
    ];
    for (s, p) in cases {
        let d = field(&mesh, &[s]);
        for v in 0..mesh.vertex_count() as u32 {
            let e = p.distance(mesh.position(v));
            assert!(
                (d[v as usize] - e).abs() <= tol,
                "{s:?} at {v}: {} vs {e}",
                d[v as usize]
            );
        }
    }
}

#[test]
fn around_a_reflex_corner() {
    // An L-shaped planar domain: the 8x8 square minus its upper right quadrant.
    let mut soup = flat_grid(8, 8, 1.0);
    soup.triangles.retain(|t| {
        let c = t.iter().map(|&v| soup.positions[v as usize]).sum::<DVec3>() / 3.0;
        !(c.x > 4.0 && c.y > 4.0)
    });
    let mesh = build(soup);
    let s = (0..mesh.vertex_count() as u32)
        .find(|&v| mesh.position(v) == DVec3::new(8.0, 2.0, 0.0))
        .unwrap();
    let d = field(&mesh, &[Source::Vertex(s)]);
    let sp = mesh.position(s);
    let corner = DVec3::new(4.0, 4.0, 0.0);
    for v in 0..mesh.vertex_count() as u32 {
        if !mesh.is_referenced(v) {
            assert!(d[v as usize].is_infinite());
            continue;
        }
        let p = mesh.position(v);
        // Points of the upper left arm see the source only over the corner.
        let visible = p.y <= 4.0 || {
            let y = sp.y + (p.y - sp.y) * (sp.x - 4.0) / (sp.x - p.x);
            y <= 4.0
        };
        let want = if visible {
            sp.distance(p)
        } else {
            sp.distance(corner) + corner.distance(p)
        };
        assert!(
            (d[v as usize] - want).abs() <= 1e-12 * 16.0,
            "vertex {v} {p}: {} vs {want}",
            d[v as usize]
        );
    }
}

#[test]
fn several_components_max_distance_and_unreferenced_vertices() {
    let mut soup = flat_grid(4, 4, 1.0);
    let n = soup.positions.len() as u32;
    let other = flat_grid(2, 2, 1.0);
    soup.positions.extend(
        other
            .positions
            .iter()
            .map(|p| *p + DVec3::new(10.0, 0.0, 0.0)),
    );
    soup.triangles
        .extend(other.triangles.iter().map(|t| t.map(|v| v + n)));
    soup.positions.push(DVec3::new(-5.0, -5.0, 0.0)); // unreferenced
    let mesh = build(soup);
    let (f, _) = solve(&mesh, &[Source::Vertex(0)], &VtpOptions::default()).unwrap();
    assert!(f.distance[..n as usize].iter().all(|d| d.is_finite()));
    assert!(f.distance[n as usize..].iter().all(|d| d.is_infinite()));
    assert!(
        f.nearest_source[n as usize..]
            .iter()
            .all(|&s| s == NO_SOURCE)
    );
    let limit = VtpOptions {
        max_distance: Some(2.5),
        ..VtpOptions::default()
    };
    let (g, _) = solve(&mesh, &[Source::Vertex(0)], &limit).unwrap();
    for v in 0..mesh.input_vertex_count() {
        if f.distance[v] <= 2.5 {
            assert!((g.distance[v] - f.distance[v]).abs() < 1e-12);
        } else {
            assert!(g.distance[v].is_infinite());
        }
    }
    // Sources in both components.
    let (h, _) = solve(
        &mesh,
        &[Source::Vertex(0), Source::Vertex(n)],
        &VtpOptions::default(),
    )
    .unwrap();
    assert!(
        h.distance[..mesh.input_vertex_count() - 1]
            .iter()
            .all(|d| d.is_finite())
    );
    assert_eq!(h.nearest_source[n as usize], 1);
}

#[test]
fn input_errors_never_panic() {
    let mut soup = flat_grid(2, 2, 1.0);
    soup.positions.push(DVec3::ZERO);
    let mesh = build(soup);
    let o = VtpOptions::default();
    let err = |s: &[Source]| solve(&mesh, s, &o).unwrap_err();
    assert_eq!(err(&[]), VtpError::Source(SourceError::NoSources));
    assert!(matches!(
        err(&[Source::Vertex(99)]),
        VtpError::Source(SourceError::VertexOutOfRange { .. })
    ));
    assert!(matches!(
        err(&[Source::Vertex(9)]),
        VtpError::Source(SourceError::UnreferencedVertex { .. })
    ));
    assert!(matches!(
        err(&[Source::EdgePoint {
            half_edge: 999,
            t: 0.5
        }]),
        VtpError::Source(SourceError::HalfEdgeOutOfRange { .. })
    ));
    assert!(matches!(
        err(&[Source::EdgePoint {
            half_edge: 0,
            t: 1.5
        }]),
        VtpError::Source(SourceError::EdgeParameter { .. })
    ));
    assert!(matches!(
        err(&[Source::EdgePoint {
            half_edge: 0,
            t: f64::NAN
        }]),
        VtpError::Source(SourceError::EdgeParameter { .. })
    ));
    assert!(matches!(
        err(&[Source::FacePoint {
            face: 99,
            barycentric: [1.0, 0.0, 0.0]
        }]),
        VtpError::Source(SourceError::FaceOutOfRange { .. })
    ));
    for bad in [
        [0.5, 0.5, 0.5],
        [-0.1, 0.6, 0.5],
        [f64::NAN, 0.5, 0.5],
        [f64::INFINITY, 0.0, 0.0],
    ] {
        assert!(matches!(
            err(&[Source::FacePoint {
                face: 0,
                barycentric: bad
            }]),
            VtpError::Source(SourceError::Barycentric { .. })
        ));
    }
    let neg = VtpOptions {
        max_distance: Some(-1.0),
        ..VtpOptions::default()
    };
    assert!(matches!(
        solve(&mesh, &[Source::Vertex(0)], &neg),
        Err(VtpError::Source(SourceError::MaxDistance(_)))
    ));
}

#[test]
fn pinch_vertex_fans_share_one_distance() {
    // Two squares touching at one corner (a pinch vertex): distances cross it.
    let mut soup = flat_grid(2, 2, 1.0);
    let n = soup.positions.len() as u32;
    let other = flat_grid(2, 2, 1.0);
    soup.positions.extend(
        other
            .positions
            .iter()
            .map(|p| *p + DVec3::new(2.0, 2.0, 0.0)),
    );
    // Glue the far corner (2,2) of the first to the near corner of the second.
    let corner = 8;
    soup.triangles.extend(
        other
            .triangles
            .iter()
            .map(|t| t.map(|v| if v == 0 { corner } else { v + n })),
    );
    let mesh = build(soup);
    let d = field(&mesh, &[Source::Vertex(0)]);
    let far = n + 8; // (4,4)
    let want = 2.0 * 8f64.sqrt();
    assert!(
        (d[far as usize] - want).abs() < 1e-12,
        "{} vs {want}",
        d[far as usize]
    );
}
