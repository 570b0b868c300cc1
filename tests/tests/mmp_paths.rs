//! Exact shortest paths from MMP's kept windows, checked with plain 3D
//! geometry (no window code):
//!
//! - the path starts at the nearest source and ends at the target, and
//!   consecutive points lie in one common face;
//! - its length equals the target's distance (1e-12 relative), and our VTP's
//!   distance for vertex targets; for point targets, VTP solved FROM the
//!   point gives the same distance back to the source vertex (symmetry);
//! - it is straight across every edge it crosses once the two faces are
//!   unfolded (the length saved by straightening each crossing is below
//!   1e-12 of the mesh scale);
//! - it bends only at saddle (or flat), boundary or pinch vertices;
//! - on a flat grid it is the straight segment.

use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
use geodesics_mmp::{GeodesicPath, MmpError, MmpField, MmpOptions, Schedule, SurfacePoint, run};
use geodesics_shapes::{bumpy_sphere, flat_grid, jittered_flat_grid, jittered_icosphere};
use geodesics_tests::{EXACT, data_dir};
use geodesics_vtp::VtpOptions;
use geodesics_window::SourceError;
use geodesics_window::{Source, Tolerance};
use glam::DVec3;

fn build(soup: IndexedTriangles) -> Mesh {
    Mesh::build(soup, &BuildOptions::default()).unwrap()
}

fn load(file: &str) -> Option<Mesh> {
    let data = data_dir(&format!("mmp_paths {file}"))?;
    let soup = geodesics_io::read_mesh(&data.join(file)).unwrap_or_else(|e| panic!("{e}"));
    Some(Mesh::build(soup, &BuildOptions::default()).unwrap_or_else(|e| panic!("{e}")))
}

/// Faces around each input vertex (pinch copies folded).
fn vertex_faces(mesh: &Mesh) -> Vec<Vec<u32>> {
    let mut out = vec![Vec::new(); mesh.input_vertex_count()];
    for f in 0..mesh.face_count() as u32 {
        for v in mesh.face(f) {
            out[mesh.pinch_origin(v) as usize].push(f);
        }
    }
    out
}

fn faces_of(mesh: &Mesh, vf: &[Vec<u32>], p: &SurfacePoint) -> Vec<u32> {
    match *p {
        SurfacePoint::Vertex(v) => vf[v as usize].clone(),
        SurfacePoint::Edge { half_edge, .. } => {
            let mut f = vec![Mesh::face_of(half_edge)];
            f.extend(mesh.twin(half_edge).map(Mesh::face_of));
            f
        }
        SurfacePoint::Face { face, .. } => vec![face],
    }
}

/// Whether a vertex may bend a geodesic: saddle or flat (by the solvers'
/// tolerance), boundary, or pinch.
fn may_bend(mesh: &Mesh, tol: &Tolerance, v: u32) -> bool {
    std::iter::once(v).chain(mesh.pinch_fans(v)).any(|u| {
        mesh.is_boundary(u) || mesh.is_pinch(u) || tol.is_flat_or_saddle(mesh.angle_sum(u))
    })
}

/// Coordinates of `q` relative to the line of half-edge `h`: along it from
/// its tail, and the distance from the line.
fn edge_coords(mesh: &Mesh, h: u32, q: DVec3) -> (f64, f64) {
    let t = mesh.position(mesh.tail(h));
    let e = (mesh.position(mesh.head(h)) - t).normalize();
    let r = q - t;
    let x = r.dot(e);
    (x, (r - e * x).length())
}

struct Checker<'a> {
    mesh: &'a Mesh,
    vf: Vec<Vec<u32>>,
    tol: Tolerance,
    scale: f64,
}

impl<'a> Checker<'a> {
    fn new(mesh: &'a Mesh) -> Self {
        Checker {
            mesh,
            vf: vertex_faces(mesh),
            tol: Tolerance::for_mesh(mesh),
            scale: mesh.bbox_diagonal(),
        }
    }

    /// Checks the geometry of `path` (ends, faces, straightness, bends) and
    /// that its length is `want` (1e-12 relative). Returns the number of
    /// bends at vertices and the largest straightening excess.
    fn check(
        &self,
        path: &GeodesicPath,
        from: SurfacePoint,
        to: SurfacePoint,
        want: f64,
    ) -> (usize, f64) {
        let m = self.mesh;
        let pts = &path.points;
        assert_eq!(
            pts.first(),
            Some(&from),
            "path starts at the source: {pts:?}"
        );
        assert_eq!(pts.last(), Some(&to), "path ends at the target: {pts:?}");
        assert_eq!(pts.len(), path.polyline.len());
        let len: f64 = path.polyline.windows(2).map(|s| s[0].distance(s[1])).sum();
        assert!((len - path.length).abs() <= EXACT * len.max(self.scale * 1e-3));
        assert!(
            (path.length - want).abs() <= EXACT * want.max(self.scale * 1e-3),
            "length {} vs distance {want} (diff {:.3e}) {pts:?}",
            path.length,
            path.length - want
        );
        for (k, s) in pts.windows(2).enumerate() {
            let (fa, fb) = (faces_of(m, &self.vf, &s[0]), faces_of(m, &self.vf, &s[1]));
            assert!(
                fa.iter().any(|f| fb.contains(f)),
                "points {k} and {} share no face: {:?} {:?}",
                k + 1,
                s[0],
                s[1]
            );
        }
        let mut bends = 0;
        let mut worst = 0.0f64;
        for k in 1..pts.len().saturating_sub(1) {
            let (a, b, c) = (pts[k - 1], pts[k], pts[k + 1]);
            let (qa, qb, qc) = (path.polyline[k - 1], path.polyline[k], path.polyline[k + 1]);
            match b {
                SurfacePoint::Vertex(v) => {
                    let straight = qa.distance(qb) + qb.distance(qc) - qa.distance(qc);
                    if straight > EXACT * self.scale {
                        assert!(
                            may_bend(m, &self.tol, v),
                            "path bends at convex vertex {v} (angle sum {}, excess {straight:.3e})",
                            m.angle_sum(v)
                        );
                        bends += 1;
                    }
                }
                SurfacePoint::Edge { half_edge: h, .. } => {
                    let f1 = Mesh::face_of(h);
                    let f2 = m
                        .twin(h)
                        .map(Mesh::face_of)
                        .expect("a crossed edge has two faces");
                    let (fa, fc) = (faces_of(m, &self.vf, &a), faces_of(m, &self.vf, &c));
                    let (sa, sc) = if fa.contains(&f1) && fc.contains(&f2) {
                        (1.0, -1.0)
                    } else if fa.contains(&f2) && fc.contains(&f1) {
                        (-1.0, 1.0)
                    } else {
                        panic!(
                            "edge crossing {k} at {b:?}: neighbours {a:?} {c:?} not on both sides"
                        );
                    };
                    // Unfold: both faces into one plane around the edge line.
                    let (xa, ya) = edge_coords(m, h, qa);
                    let (xb, _) = edge_coords(m, h, qb);
                    let (xc, yc) = edge_coords(m, h, qc);
                    let a2 = glam::DVec2::new(xa, sa * ya);
                    let b2 = glam::DVec2::new(xb, 0.0);
                    let c2 = glam::DVec2::new(xc, sc * yc);
                    let excess = a2.distance(b2) + b2.distance(c2) - a2.distance(c2);
                    worst = worst.max(excess);
                    assert!(
                        excess <= EXACT * self.scale,
                        "path not straight across edge {h} at point {k}: excess {excess:.3e}"
                    );
                }
                SurfacePoint::Face { .. } => panic!("a face point inside a path: {b:?}"),
            }
        }
        (bends, worst)
    }
}

/// Paths to every `step`-th vertex and to points of every `step`-th face,
/// against the field, VTP, and (for `sym` face points) VTP solved from the
/// point; both schedules.
fn check_mesh(name: &str, mesh: &Mesh, source: u32, step: usize, sym: usize) {
    let c = Checker::new(mesh);
    let vtp = geodesics_vtp::solve(mesh, &[Source::Vertex(source)], &VtpOptions::default())
        .unwrap()
        .0
        .distance;
    for schedule in [Schedule::PriorityQueue, Schedule::Fwp] {
        let options = MmpOptions {
            schedule,
            ..MmpOptions::default()
        };
        let field = run(mesh, &[Source::Vertex(source)], &options).unwrap();
        let dist = &field.distance_field().distance;
        let max = dist
            .iter()
            .copied()
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max);
        let (mut n, mut bends, mut worst) = (0, 0, 0.0f64);
        for v in (0..mesh.input_vertex_count() as u32).step_by(step) {
            if !dist[v as usize].is_finite() {
                assert_eq!(field.path_to_vertex(v), Err(MmpError::Unreachable));
                continue;
            }
            assert!((dist[v as usize] - vtp[v as usize]).abs() <= EXACT * max);
            let p = field.path_to_vertex(v).unwrap();
            let (b, w) = c.check(
                &p,
                SurfacePoint::Vertex(source),
                SurfacePoint::Vertex(v),
                dist[v as usize],
            );
            n += 1;
            bends += b;
            worst = worst.max(w);
        }
        let (mut np, mut nsym) = (0, 0);
        for f in (0..mesh.face_count() as u32).step_by(step) {
            let bary = [0.2, 0.3, 0.5];
            let to = SurfacePoint::Face {
                face: f,
                barycentric: bary,
            };
            let q = to.position(mesh).unwrap();
            let corners = mesh.face(f);
            let dc: Vec<f64> = corners
                .iter()
                .map(|&v| field_vertex(&field, mesh, v))
                .collect();
            if dc.iter().all(|d| d.is_infinite()) {
                continue;
            }
            let p = field.path_to_point(f, bary).unwrap();
            let d = p.length;
            // Triangle inequality with the corners.
            for (k, &v) in corners.iter().enumerate() {
                let e = mesh.position(v).distance(q);
                assert!(d <= dc[k] + e + EXACT * max, "point above corner bound");
                assert!(d >= dc[k] - e - EXACT * max, "point below corner bound");
            }
            let (b, w) = c.check(&p, SurfacePoint::Vertex(source), to, d);
            bends += b;
            worst = worst.max(w);
            np += 1;
            if nsym < sym && schedule == Schedule::PriorityQueue {
                let back = geodesics_vtp::solve(
                    mesh,
                    &[Source::FacePoint {
                        face: f,
                        barycentric: bary,
                    }],
                    &VtpOptions::default(),
                )
                .unwrap()
                .0
                .distance[source as usize];
                assert!(
                    (back - d).abs() <= EXACT * max,
                    "symmetry at face {f}: path {d}, VTP from the point {back}"
                );
                nsym += 1;
            }
        }
        eprintln!(
            "mmp_paths {name} {schedule:?}: {n} vertex paths, {np} point paths ({nsym} checked by symmetry), {bends} bends at pseudo-source vertices, worst straightening excess {:.2e} of scale",
            worst / c.scale
        );
    }
}

fn field_vertex(field: &MmpField, mesh: &Mesh, v: u32) -> f64 {
    field.distance_field().distance[mesh.pinch_origin(v) as usize]
}

#[test]
fn flat_grid_paths_are_straight_segments() {
    let mesh = build(flat_grid(20, 20, 0.5));
    let c = Checker::new(&mesh);
    let p0 = mesh.position(0);
    // Every point of the path on the segment from the source to the
    // target. Where the segment passes exactly through lattice vertices
    // (flat, hence pseudo-sources), the window from the source and the one
    // from the lattice vertex are tangent along it: they differ by
    // rounding over a band of width ~√ε around the segment, so the path may
    // run beside the vertex by ~1e-8 at a length cost of ~δ²/s ≈ 1e-16.
    // Allowed: 1e-8 of the scale (a bend through a wrong lattice vertex is
    // ~1e-1 off, and the length is checked to 1e-12 anyway).
    let lateral = 1e-8 * c.scale;
    for schedule in [Schedule::PriorityQueue, Schedule::Fwp] {
        let field = run(
            &mesh,
            &[Source::Vertex(0)],
            &MmpOptions {
                schedule,
                max_distance: None,
                ..MmpOptions::default()
            },
        )
        .unwrap();
        let mut worst = 0.0f64;
        for v in 0..mesh.input_vertex_count() as u32 {
            let p = field.path_to_vertex(v).unwrap();
            let e = p0.distance(mesh.position(v));
            c.check(&p, SurfacePoint::Vertex(0), SurfacePoint::Vertex(v), e);
            let dir = (mesh.position(v) - p0).normalize_or_zero();
            for q in &p.polyline {
                let r = *q - p0;
                let off = (r - dir * r.dot(dir)).length();
                if off > worst && std::env::var_os("MMP_DEBUG").is_some() {
                    eprintln!("{v}: {off:.3e} {:?} {:?}", p.points, p.polyline);
                }
                worst = worst.max(off);
                assert!(
                    off <= lateral,
                    "off the segment at {v} by {off:.3e}: {:?}",
                    p.points
                );
            }
            assert!((p.length - e).abs() <= EXACT * 15.0);
        }
        eprintln!(
            "mmp_paths flat grid {schedule:?}: worst lateral offset {worst:.2e} (scale {:.2})",
            c.scale
        );
        // Grid corners on the diagonal: the path runs along the diagonal edges.
        let far = mesh.input_vertex_count() as u32 - 1;
        let p = field.path_to_vertex(far).unwrap();
        assert!((p.length - 10.0 * 2f64.sqrt()).abs() <= EXACT * 15.0);
    }
}

#[test]
fn jittered_flat_grid_paths_are_euclidean_from_point_sources() {
    let mesh = build(jittered_flat_grid(12, 12, 1.0, 0.3, 5));
    let c = Checker::new(&mesh);
    let bary = [0.25, 0.25, 0.5];
    let src = Source::FacePoint {
        face: 77,
        barycentric: bary,
    };
    let from = SurfacePoint::Face {
        face: 77,
        barycentric: bary,
    };
    let s = from.position(&mesh).unwrap();
    for schedule in [Schedule::PriorityQueue, Schedule::Fwp] {
        let field = run(
            &mesh,
            &[src],
            &MmpOptions {
                schedule,
                max_distance: None,
                ..MmpOptions::default()
            },
        )
        .unwrap();
        for v in 0..mesh.input_vertex_count() as u32 {
            let p = field.path_to_vertex(v).unwrap();
            let e = s.distance(mesh.position(v));
            c.check(&p, from, SurfacePoint::Vertex(v), e);
        }
        for f in (0..mesh.face_count() as u32).step_by(3) {
            let to = SurfacePoint::Face {
                face: f,
                barycentric: [0.6, 0.3, 0.1],
            };
            let p = field.path_to_point(f, [0.6, 0.3, 0.1]).unwrap();
            c.check(&p, from, to, s.distance(to.position(&mesh).unwrap()));
        }
    }
    // An edge-point source.
    let h = 3 * 40 + 1;
    let src = Source::EdgePoint {
        half_edge: h,
        t: 0.4,
    };
    let field = run(&mesh, &[src], &MmpOptions::default()).unwrap();
    let a = mesh.position(mesh.tail(h));
    let b = mesh.position(mesh.head(h));
    let s = a + (b - a) * 0.4;
    for v in 0..mesh.input_vertex_count() as u32 {
        let p = field.path_to_vertex(v).unwrap();
        let from = SurfacePoint::Edge {
            half_edge: h,
            t: 0.4,
        };
        c.check(
            &p,
            from,
            SurfacePoint::Vertex(v),
            s.distance(mesh.position(v)),
        );
    }
}

#[test]
fn bumpy_sphere_paths() {
    let mesh = build(bumpy_sphere(3, 1.0, 12, 0.25, 7));
    check_mesh("bumpy_sphere(3)", &mesh, 0, 1, 8);
}

#[test]
fn jittered_icosphere_paths() {
    let mesh = build(jittered_icosphere(3, 1.0, 0.1, 3));
    check_mesh("jittered_icosphere(3)", &mesh, 5, 1, 4);
}

#[test]
fn several_sources_pick_the_nearest() {
    let mesh = build(bumpy_sphere(2, 1.0, 12, 0.25, 3));
    let c = Checker::new(&mesh);
    let sources = [Source::Vertex(0), Source::Vertex(100), Source::Vertex(150)];
    let field = run(&mesh, &sources, &MmpOptions::default()).unwrap();
    let df = field.distance_field();
    for v in 0..mesh.input_vertex_count() as u32 {
        let p = field.path_to_vertex(v).unwrap();
        let s = df.nearest_source[v as usize];
        assert_eq!(p.source, s);
        let Source::Vertex(sv) = sources[s as usize] else {
            unreachable!()
        };
        c.check(
            &p,
            SurfacePoint::Vertex(sv),
            SurfacePoint::Vertex(v),
            df.distance[v as usize],
        );
    }
}

#[test]
fn real_hand() {
    if let Some(mesh) = load("hand.off") {
        check_mesh("hand.off", &mesh, 0, 1, 6);
    }
}

#[test]
fn real_blade_with_boundary() {
    if let Some(mesh) = load("blade.off") {
        check_mesh("blade.off", &mesh, 286, 3, 4);
    }
}

#[test]
fn real_cow_with_a_pinch_vertex() {
    if let Some(mesh) = load("cow.obj") {
        check_mesh("cow.obj", &mesh, 1187, 1, 4);
    }
}

#[test]
fn real_fertility_genus_4() {
    if let Some(mesh) = load("fertility.off") {
        check_mesh("fertility.off", &mesh, 1481, 2, 4);
    }
}

#[test]
fn real_bunny_sampled() {
    if let Some(mesh) = load("bunny.off") {
        check_mesh("bunny.off", &mesh, 0, 37, 3);
    }
}

#[test]
fn errors_name_the_problem() {
    let mesh = build(flat_grid(3, 3, 1.0));
    let field = run(&mesh, &[Source::Vertex(0)], &MmpOptions::default()).unwrap();
    assert!(matches!(
        field.path_to_vertex(999),
        Err(MmpError::TargetVertexOutOfRange { vertex: 999, .. })
    ));
    assert!(matches!(
        field.path_to_point(999, [1.0, 0.0, 0.0]),
        Err(MmpError::TargetFaceOutOfRange { face: 999, .. })
    ));
    assert!(matches!(
        field.path_to_point(0, [0.5, 0.6, 0.0]),
        Err(MmpError::TargetBarycentric(_))
    ));
    assert!(matches!(
        field.path_to_point(0, [f64::NAN, 0.5, 0.5]),
        Err(MmpError::TargetBarycentric(_))
    ));
    assert_eq!(
        run(&mesh, &[], &MmpOptions::default()).err(),
        Some(MmpError::Source(SourceError::NoSources))
    );
    assert!(matches!(
        run(&mesh, &[Source::Vertex(99)], &MmpOptions::default()).err(),
        Some(MmpError::Source(SourceError::VertexOutOfRange {
            vertex: 99,
            ..
        }))
    ));
    assert!(matches!(
        run(
            &mesh,
            &[Source::EdgePoint {
                half_edge: 0,
                t: 1.5
            }],
            &MmpOptions::default()
        )
        .err(),
        Some(MmpError::Source(SourceError::EdgeParameter { .. }))
    ));
    assert_eq!(
        run(
            &mesh,
            &[Source::Vertex(0)],
            &MmpOptions {
                max_distance: Some(-1.0),
                ..MmpOptions::default()
            }
        )
        .err(),
        Some(MmpError::Source(SourceError::MaxDistance(-1.0)))
    );
    // Beyond the distance limit: unreachable, and no path.
    let near = run(
        &mesh,
        &[Source::Vertex(0)],
        &MmpOptions {
            max_distance: Some(1.5),
            ..MmpOptions::default()
        },
    )
    .unwrap();
    let far = mesh.input_vertex_count() as u32 - 1;
    assert_eq!(near.distance_field().distance[far as usize], f64::INFINITY);
    assert_eq!(near.path_to_vertex(far), Err(MmpError::Unreachable));
    assert!(near.path_to_vertex(1).is_ok());
}

#[test]
fn other_components_are_unreachable() {
    // Two separate triangles.
    let soup = IndexedTriangles {
        positions: vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(6.0, 0.0, 0.0),
            DVec3::new(5.0, 1.0, 0.0),
        ],
        triangles: vec![[0, 1, 2], [3, 4, 5]],
    };
    let mesh = build(soup);
    let field = run(&mesh, &[Source::Vertex(0)], &MmpOptions::default()).unwrap();
    assert_eq!(field.distance_field().distance[4], f64::INFINITY);
    assert_eq!(field.path_to_vertex(4), Err(MmpError::Unreachable));
    assert_eq!(
        field.path_to_point(1, [0.3, 0.3, 0.4]),
        Err(MmpError::Unreachable)
    );
    let p = field.path_to_point(0, [0.2, 0.3, 0.5]).unwrap();
    assert_eq!(p.points.len(), 2);
}

#[test]
fn paths_cross_a_zero_area_face_straight() {
    // A unit square whose diagonal is doubled by a zero-area "zipper" face
    // [0, 2, 4] (vertex 4 sits on vertex 2): windows and paths go through it.
    let soup = IndexedTriangles {
        positions: vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 4], [0, 4, 3]],
    };
    let mesh = build(soup);
    let c = Checker::new(&mesh);
    for schedule in [Schedule::PriorityQueue, Schedule::Fwp] {
        let field = run(
            &mesh,
            &[Source::Vertex(1)],
            &MmpOptions {
                schedule,
                max_distance: None,
                ..MmpOptions::default()
            },
        )
        .unwrap();
        let d = &field.distance_field().distance;
        assert!((d[3] - 2f64.sqrt()).abs() <= 1e-15, "{}", d[3]);
        let p = field.path_to_vertex(3).unwrap();
        c.check(
            &p,
            SurfacePoint::Vertex(1),
            SurfacePoint::Vertex(3),
            2f64.sqrt(),
        );
        // It crosses the doubled diagonal once, at its middle (two edge
        // points at the same place).
        let mid = DVec3::new(0.5, 0.5, 0.0);
        assert!(
            p.polyline[1..p.polyline.len() - 1]
                .iter()
                .all(|q| q.distance(mid) < 1e-15),
            "{:?}",
            p.points
        );
        // A point in the last face, reached straight across.
        let to = SurfacePoint::Face {
            face: 2,
            barycentric: [0.2, 0.2, 0.6],
        };
        let q = to.position(&mesh).unwrap();
        let p = field.path_to_point(2, [0.2, 0.2, 0.6]).unwrap();
        c.check(
            &p,
            SurfacePoint::Vertex(1),
            to,
            q.distance(mesh.position(1)),
        );
    }
}
