//! VTP from sources inside faces and on edges, against the exact reference
//! (gdist / MMP) on curved real meshes.
//!
//! gdist only takes vertex sources, so each reference in `data/reference/`
//! was made on a refined copy of the mesh where the point is a new vertex
//! (appended last): a face point splits its face into 3, an edge point both
//! faces of its edge into 2 each (see `data/reference/README.md`). The
//! refinement is flat, so distances to the original vertices are those from
//! the point on the original mesh.
//!
//! Each case solves on the original mesh from the `FacePoint` /
//! `EdgePoint` (and from every other way of naming the same point), and on
//! the refined mesh, rebuilt here exactly as the generator made it, from
//! the new vertex. Pass: within `1e-12 ×` the largest reference distance at
//! every original vertex.

use std::path::{Path, PathBuf};
use std::time::Instant;

use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
use geodesics_tests::{EXACT, data_dir, read_distances};
use geodesics_vtp::{VtpOptions, solve};
use geodesics_window::Source;

/// Where the source lies, in the FILE's numbering and corner order.
#[derive(Clone, Copy, Debug)]
enum Point {
    /// Inside file triangle `face`, barycentric in the file's corner order.
    Face { face: usize, barycentric: [f64; 3] },
    /// On the edge from vertex `a` to vertex `b`, at `t` from `a`.
    Edge { a: u32, b: u32, t: f64 },
}

/// The folder of the project's own reference files (`data/reference/`).
fn own_reference_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/reference")
}

/// Renumbered as the CLI builds it: the sources below are named through
/// the mesh's maps from the file's numbers.
fn build(soup: IndexedTriangles) -> Mesh {
    let options = BuildOptions {
        reorder: true,
        ..BuildOptions::default()
    };
    Mesh::build(soup, &options).unwrap_or_else(|e| panic!("{e}"))
}

/// The refined copy of `soup` where `point` is a new last vertex, exactly
/// as the generator made it (same arithmetic, same face order).
fn refine(soup: &IndexedTriangles, point: Point) -> IndexedTriangles {
    let mut out = soup.clone();
    let n = soup.positions.len() as u32;
    match point {
        Point::Face { face, barycentric } => {
            let [a, b, c] = soup.triangles[face];
            let [pa, pb, pc] = [a, b, c].map(|v| soup.positions[v as usize]);
            let [b0, b1, b2] = barycentric;
            out.positions.push(pa * b0 + pb * b1 + pc * b2);
            out.triangles[face] = [a, b, n];
            out.triangles.extend([[b, c, n], [c, a, n]]);
        }
        Point::Edge { a, b, t } => {
            // The face running a -> b and the one running b -> a.
            let find = |x: u32, y: u32| {
                soup.triangles
                    .iter()
                    .enumerate()
                    .find_map(|(j, tri)| {
                        (0..3)
                            .find(|&i| tri[i] == x && tri[(i + 1) % 3] == y)
                            .map(|i| (j, tri[(i + 2) % 3]))
                    })
                    .expect("edge in the file")
            };
            let (f, c) = find(a, b);
            let (g, d) = find(b, a);
            let (pa, pb) = (soup.positions[a as usize], soup.positions[b as usize]);
            out.positions.push(pa * (1.0 - t) + pb * t);
            out.triangles[f] = [a, n, c];
            out.triangles[g] = [b, n, d];
            out.triangles.extend([[n, b, c], [n, a, d]]);
        }
    }
    out
}

/// Every way of naming `point` as a source on `mesh` (built from `soup`),
/// with a label.
fn sources(mesh: &Mesh, soup: &IndexedTriangles, point: Point) -> Vec<(String, Source)> {
    match point {
        Point::Face {
            face,
            barycentric: [b0, b1, b2],
        } => {
            let f = mesh.mesh_face(face as u32);
            assert_eq!(mesh.input_face(f), face as u32);
            let [a, b, c] = soup.triangles[face];
            let corners = mesh.face(f).map(|v| mesh.pinch_origin(v));
            let barycentric = if mesh.is_reoriented(f) {
                assert_eq!(corners, [a, c, b], "face {face} flipped");
                [b0, b2, b1]
            } else {
                assert_eq!(corners, [a, b, c], "face {face} kept");
                [b0, b1, b2]
            };
            vec![(
                format!("FacePoint {face} {barycentric:?}"),
                Source::FacePoint {
                    face: f,
                    barycentric,
                },
            )]
        }
        Point::Edge { a, b, t } => {
            let h = mesh
                .outgoing(mesh.mesh_vertex(a))
                .find(|&h| mesh.pinch_origin(mesh.head(h)) == b)
                .expect("half-edge a -> b");
            let tw = mesh.twin(h).expect("interior edge");
            let mut out = vec![
                (
                    format!("EdgePoint {h} t={t}"),
                    Source::EdgePoint { half_edge: h, t },
                ),
                (
                    format!("EdgePoint twin {tw} t={}", 1.0 - t),
                    Source::EdgePoint {
                        half_edge: tw,
                        t: 1.0 - t,
                    },
                ),
            ];
            // The same point as a face point (one zero coordinate) on each
            // of the two faces.
            for (e, s) in [(h, t), (tw, 1.0 - t)] {
                let f = Mesh::face_of(e);
                let i = (e % 3) as usize;
                let mut barycentric = [0.0; 3];
                barycentric[i] = 1.0 - s;
                barycentric[(i + 1) % 3] = s;
                out.push((
                    format!("FacePoint {f} {barycentric:?}"),
                    Source::FacePoint {
                        face: f,
                        barycentric,
                    },
                ));
            }
            out
        }
    }
}

fn check(file: &str, reference: &str, point: Point) {
    let Some(data) = data_dir(&format!("vtp_point_sources {file}")) else {
        return;
    };
    let reference = read_distances(&own_reference_dir().join(reference));
    let soup = geodesics_io::read_mesh(&data.join(file)).unwrap_or_else(|e| panic!("{e}"));
    let n = soup.positions.len();
    assert_eq!(reference.len(), n, "{file}: reference length");
    let max = reference.iter().copied().fold(0.0, f64::max);
    assert!(reference.iter().all(|d| d.is_finite()), "{file}: reference");
    let tol = EXACT * max;

    let refined = refine(&soup, point);
    let mesh = build(soup.clone());
    let mut runs = sources(&mesh, &soup, point)
        .into_iter()
        .map(|(label, s)| (label, mesh.clone(), s))
        .collect::<Vec<_>>();
    runs.push((
        format!("refined mesh, Vertex {n}"),
        build(refined),
        Source::Vertex(n as u32),
    ));

    let mut failures = Vec::new();
    for (label, m, source) in &runs {
        let t = Instant::now();
        let (field, _) = solve(m, &[*source], &VtpOptions::default())
            .unwrap_or_else(|e| panic!("{file} {label}: {e:?}"));
        let secs = t.elapsed().as_secs_f64();
        let mut worst = (0.0f64, 0);
        for (i, (&d, &r)) in field.distance[..n].iter().zip(&reference).enumerate() {
            assert!(!d.is_nan(), "{file} {label}: NaN at vertex {i}");
            let err = (d - r).abs();
            if err > worst.0 {
                worst = (err, i);
            }
            if err > tol {
                failures.push(format!(
                    "{file} {label}: vertex {i}: ours {d:.17}, reference {r:.17}, diff {:.3e}",
                    d - r
                ));
            }
        }
        eprintln!(
            "{file} {label}: max error {:.3e} ({:.3e} relative) at vertex {}, {secs:.3} s",
            worst.0,
            worst.0 / max,
            worst.1
        );
    }
    assert!(
        failures.is_empty(),
        "{} vertices off by more than {tol:.3e}:\n{}",
        failures.len(),
        failures[..failures.len().min(20)].join("\n")
    );
}

#[test]
fn hand_face_point() {
    check(
        "hand.off",
        "hand.off.face1000.txt",
        Point::Face {
            face: 1000,
            barycentric: [0.2, 0.3, 0.5],
        },
    );
}

#[test]
fn hand_edge_point() {
    check(
        "hand.off",
        "hand.off.edge763-860.txt",
        Point::Edge {
            a: 763,
            b: 860,
            t: 0.3,
        },
    );
}

#[test]
fn fertility_face_point() {
    check(
        "fertility.off",
        "fertility.off.face4000.txt",
        Point::Face {
            face: 4000,
            barycentric: [0.2, 0.3, 0.5],
        },
    );
}

#[test]
fn fertility_edge_point() {
    check(
        "fertility.off",
        "fertility.off.edge4063-2237.txt",
        Point::Edge {
            a: 4063,
            b: 2237,
            t: 0.3,
        },
    );
}
