//! Topology, orientation, symmetry, determinism and bounds of every shape.

use std::collections::{HashMap, HashSet};

use geodesics_mesh::{BuildOptions, Mesh, MeshSummary};
use geodesics_shapes::*;
use glam::DVec3;

fn build(m: &IndexedTriangles) -> Mesh {
    Mesh::build(m.clone(), &BuildOptions::default()).expect("valid mesh")
}

fn summary(m: &IndexedTriangles) -> MeshSummary {
    build(m).summary().clone()
}

/// Topology checks shared by every shape: V, F, χ, genus, boundary loops,
/// and no defect of any kind (in particular no face needed reorienting).
fn check_topology(m: &IndexedTriangles, v: usize, f: usize, chi: i64, genus: i64, loops: usize) {
    let s = summary(m);
    assert_eq!(
        (
            s.vertices,
            s.faces,
            s.euler_characteristic,
            s.genus,
            s.boundary_loops
        ),
        (v, f, chi, Some(genus), loops),
        "{s:?}"
    );
    assert_eq!(s.components, 1);
    assert_eq!(
        s.reoriented_faces, 0,
        "triangles are not consistently oriented"
    );
    assert_eq!(s.nonmanifold_vertices, 0);
    assert_eq!(s.zero_area_faces, 0);
    assert_eq!(s.duplicate_positions, 0);
    assert_eq!(s.unreferenced_vertices, 0);
}

fn corners(m: &IndexedTriangles, t: [u32; 3]) -> [DVec3; 3] {
    t.map(|v| m.positions[v as usize])
}

fn normal(m: &IndexedTriangles, t: [u32; 3]) -> DVec3 {
    let [a, b, c] = corners(m, t);
    (b - a).cross(c - a)
}

fn signed_volume(m: &IndexedTriangles) -> f64 {
    m.triangles
        .iter()
        .map(|&t| {
            let [a, b, c] = corners(m, t);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

fn bits(m: &IndexedTriangles) -> Vec<[u64; 3]> {
    m.positions
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect()
}

fn assert_identical(a: &IndexedTriangles, b: &IndexedTriangles) {
    assert_eq!(bits(a), bits(b));
    assert_eq!(a.triangles, b.triangles);
}

/// Every face of a star-shaped closed surface faces away from the origin.
fn assert_outward_star(m: &IndexedTriangles) {
    assert!(signed_volume(m) > 0.0);
    for &t in &m.triangles {
        let [a, b, c] = corners(m, t);
        assert!(
            normal(m, t).dot(a + b + c) > 0.0,
            "face {t:?} points inward"
        );
    }
}

fn shortest_edge(m: &IndexedTriangles) -> f64 {
    let mesh = build(m);
    (0..mesh.half_edge_count() as u32)
        .map(|h| mesh.length(h))
        .fold(f64::INFINITY, f64::min)
}

/// For every interior edge, the far vertex of the neighbouring face lies
/// strictly below the plane of the face: the closed surface is convex.
fn assert_convex(m: &IndexedTriangles) {
    let mesh = build(m);
    for h in 0..mesh.half_edge_count() as u32 {
        let t = mesh.twin(h).expect("closed");
        let [a, b, c] = mesh.face(h / 3).map(|v| mesh.position(v));
        let d = mesh.position(mesh.opposite_vertex(t));
        assert!(
            (b - a).cross(c - a).dot(d - a) < 0.0,
            "edge {h} is not convex"
        );
    }
}

// ---------------------------------------------------------------- icosphere

#[test]
fn icosphere_counts_and_topology() {
    for s in 0..=5u32 {
        let m = icosphere(s, 1.0);
        let v = 10 * 4usize.pow(s) + 2;
        let f = 20 * 4usize.pow(s);
        check_topology(&m, v, f, 2, 0, 0);
        assert_eq!(summary(&m).saddle_vertices, 0);
    }
    let m = icosphere(4, 1.0);
    assert_eq!((m.positions.len(), m.triangles.len()), (2562, 5120));
    let m = icosphere(5, 1.0);
    assert_eq!((m.positions.len(), m.triangles.len()), (10242, 20480));
}

#[test]
fn icosphere_faces_point_outward() {
    for s in 0..=4 {
        assert_outward_star(&icosphere(s, 2.5));
    }
}

#[test]
fn icosphere_radii_exact() {
    for radius in [1.0, 3.7, 1e-3, 12345.678] {
        for s in 0..=6 {
            for p in &icosphere(s, radius).positions {
                let err = (p.length() - radius).abs();
                assert!(
                    err <= 1e-15 * radius,
                    "s={s} r={radius}: {p} off by {err:e}"
                );
            }
        }
    }
}

/// The 24 maps `(x, y, z) ↦ (±x, ±y, ±z)` composed with the cyclic
/// permutations map the vertex set and the face set onto themselves, bit for
/// bit.
#[test]
fn icosphere_exactly_symmetric() {
    let m = icosphere(3, 1.7);
    let index: HashMap<[u64; 3], u32> = bits(&m)
        .into_iter()
        .enumerate()
        .map(|(i, b)| (b, i as u32))
        .collect();
    assert_eq!(index.len(), m.positions.len());
    let faces: HashSet<[u32; 3]> = m
        .triangles
        .iter()
        .map(|t| {
            let mut t = *t;
            t.sort_unstable();
            t
        })
        .collect();
    for rotation in 0..3 {
        for signs in 0..8 {
            let map = |p: DVec3| {
                let mut a = p.to_array();
                a.rotate_left(rotation);
                for (k, x) in a.iter_mut().enumerate() {
                    if signs & (1 << k) != 0 {
                        *x = -*x + 0.0;
                    }
                }
                a.map(f64::to_bits)
            };
            for &t in &m.triangles {
                let mut image = corners(&m, t).map(|p| {
                    *index
                        .get(&map(p))
                        .unwrap_or_else(|| panic!("image of {p} is not a vertex"))
                });
                image.sort_unstable();
                assert!(faces.contains(&image), "image of face {t:?} is not a face");
            }
        }
    }
}

// ---------------------------------------------------------- jittered sphere

#[test]
fn jittered_icosphere_stays_on_sphere_within_bounds_and_convex() {
    for s in 1..=4 {
        let plain = icosphere(s, 2.0);
        let bound = MAX_SPHERE_JITTER * shortest_edge(&plain);
        for seed in 0..8 {
            let m = jittered_icosphere(s, 2.0, MAX_SPHERE_JITTER, seed);
            assert_eq!(m.triangles, plain.triangles);
            let mut moved = 0;
            for (p, q) in m.positions.iter().zip(&plain.positions) {
                assert!((p.length() - 2.0).abs() <= 2e-15);
                let d = p.distance(*q);
                assert!(d < bound, "moved {d} ≥ {bound}");
                moved += usize::from(d > 1e-3 * bound);
            }
            assert!(
                moved * 10 > m.positions.len() * 9,
                "only {moved} vertices moved"
            );
            assert_outward_star(&m);
            assert_convex(&m);
            let s = summary(&m);
            assert_eq!((s.euler_characteristic, s.saddle_vertices), (2, 0));
        }
    }
    let m = jittered_icosphere(5, 1.0, MAX_SPHERE_JITTER, 99);
    assert_convex(&m);
}

#[test]
fn jittered_icosphere_zero_jitter_is_icosphere() {
    let a = jittered_icosphere(3, 1.0, 0.0, 5);
    let b = icosphere(3, 1.0);
    for (p, q) in a.positions.iter().zip(&b.positions) {
        assert!(p.distance(*q) <= 1e-15);
    }
}

#[test]
#[should_panic(expected = "sphere jitter must be within")]
fn jittered_icosphere_rejects_large_jitter() {
    jittered_icosphere(2, 1.0, 0.5, 0);
}

// -------------------------------------------------------------- bumpy sphere

#[test]
fn bumpy_sphere_has_many_saddles() {
    for seed in 0..4 {
        for (amplitude, fraction) in [(0.1, 0.10), (0.2, 0.25)] {
            let m = bumpy_sphere(5, 1.0, 40, amplitude, seed);
            let s = summary(&m);
            assert_eq!(
                (s.vertices, s.euler_characteristic, s.genus),
                (10242, 2, Some(0))
            );
            assert_eq!(s.reoriented_faces, 0);
            let saddles = s.saddle_vertices as f64 / s.vertices as f64;
            assert!(
                saddles >= fraction,
                "seed {seed}, amplitude {amplitude}: only {:.1} % saddles",
                100.0 * saddles
            );
        }
    }
}

#[test]
fn bumpy_sphere_is_outward_and_bounded() {
    let m = bumpy_sphere(4, 3.0, 40, 0.2, 1);
    assert_outward_star(&m);
    let plain = icosphere(4, 3.0);
    assert_eq!(m.triangles, plain.triangles);
    // Vertices move radially only.
    for (p, q) in m.positions.iter().zip(&plain.positions) {
        assert!(p.normalize().distance(q.normalize()) < 1e-12);
    }
    let radii: Vec<f64> = m.positions.iter().map(|p| p.length()).collect();
    let (lo, hi) = radii.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| {
        (lo.min(r), hi.max(r))
    });
    assert!(hi - lo > 0.3, "bumps too flat: {lo}..{hi}");
    // No bumps: the icosphere.
    assert_identical(&bumpy_sphere(3, 1.0, 0, 0.2, 1), &icosphere(3, 1.0));
}

// -------------------------------------------------------------------- torus

#[test]
fn torus_counts_and_topology() {
    let m = regular_torus(120, 40, 1.0, 0.3);
    check_topology(&m, 4800, 9600, 0, 1, 0);
    for (a, b) in [(3, 3), (4, 7), (17, 5)] {
        check_topology(
            &regular_torus(a, b, 2.0, 0.5),
            (a * b) as usize,
            2 * (a * b) as usize,
            0,
            1,
            0,
        );
    }
}

#[test]
fn torus_faces_point_outward() {
    let (big, small) = (1.0, 0.3);
    let m = regular_torus(60, 20, big, small);
    assert!(signed_volume(&m) > 0.0);
    // Exact volume of the solid torus 2π²Rr², approached from below.
    let exact = 2.0 * std::f64::consts::PI.powi(2) * big * small * small;
    assert!((signed_volume(&m) - exact).abs() < 0.02 * exact);
    for &t in &m.triangles {
        let [a, b, c] = corners(&m, t);
        let g = (a + b + c) / 3.0;
        let centre = DVec3::new(g.x, g.y, 0.0).normalize() * big;
        assert!(
            normal(&m, t).dot(g - centre) > 0.0,
            "face {t:?} points inward"
        );
    }
}

#[test]
fn torus_faces_of_a_ring_are_congruent() {
    let (mm, nn) = (120usize, 40usize);
    let m = regular_torus(mm as u32, nn as u32, 1.0, 0.3);
    let sides = |t: [u32; 3]| {
        let [a, b, c] = corners(&m, t);
        [a.distance(b), b.distance(c), c.distance(a)]
    };
    for j in 0..nn {
        for parity in 0..2 {
            let reference = sides(m.triangles[2 * j + parity]);
            for i in 1..mm {
                let s = sides(m.triangles[2 * (i * nn + j) + parity]);
                for k in 0..3 {
                    assert!((s[k] - reference[k]).abs() < 1e-14, "ring {j}, column {i}");
                }
            }
        }
    }
    // Same diagonal everywhere: each quad (i, j) is split along (i, j)-(i+1, j+1).
    for (q, pair) in m.triangles.chunks(2).enumerate() {
        let (i, j) = (q / nn, q % nn);
        let diag = [
            (i * nn + j) as u32,
            (((i + 1) % mm) * nn + (j + 1) % nn) as u32,
        ];
        assert_eq!([pair[0][0], pair[0][2]], diag);
        assert_eq!([pair[1][0], pair[1][1]], diag);
    }
}

#[test]
fn torus_exactly_mirror_symmetric() {
    let m = regular_torus(24, 10, 1.0, 0.4);
    let set: HashSet<[u64; 3]> = bits(&m).into_iter().collect();
    for p in &m.positions {
        for q in [DVec3::new(p.x, -p.y, p.z), DVec3::new(p.x, p.y, -p.z)] {
            let q = q + DVec3::ZERO;
            assert!(set.contains(&q.to_array().map(f64::to_bits)), "{q} missing");
        }
    }
    assert_eq!(m.positions[0], DVec3::new(1.4, 0.0, 0.0));
}

// --------------------------------------------------------------------- grids

#[test]
fn flat_grid_counts_layout_and_orientation() {
    for (nx, ny) in [(1, 1), (3, 2), (100, 100)] {
        let m = flat_grid(nx, ny, 0.25);
        let (w, h) = (nx as usize + 1, ny as usize + 1);
        check_topology(&m, w * h, 2 * (w - 1) * (h - 1), 1, 0, 1);
        assert_eq!(summary(&m).boundary_vertices, 2 * (nx + ny) as usize);
        for (v, p) in m.positions.iter().enumerate() {
            assert_eq!(
                *p,
                DVec3::new((v % w) as f64 * 0.25, (v / w) as f64 * 0.25, 0.0)
            );
        }
        for &t in &m.triangles {
            let n = normal(&m, t);
            assert!(n.z > 0.0 && n.x == 0.0 && n.y == 0.0);
            // Every triangle has the same hypotenuse direction (+1, +1).
            let hyp = m.positions[t[2].max(t[1]) as usize] - m.positions[t[0] as usize];
            assert!(hyp.x == hyp.y && hyp.x == 0.25);
        }
    }
}

#[test]
fn jittered_grid_within_bounds() {
    let (nx, ny, spacing) = (20u32, 13u32, 0.5);
    let regular = flat_grid(nx, ny, spacing);
    let (xmax, ymax) = (f64::from(nx) * spacing, f64::from(ny) * spacing);
    for seed in 0..20 {
        let m = jittered_flat_grid(nx, ny, spacing, MAX_GRID_JITTER, seed);
        assert_eq!(m.triangles, regular.triangles);
        check_topology(&m, 21 * 14, 2 * 20 * 13, 1, 0, 1);
        let bound = MAX_GRID_JITTER * spacing * (1.0 + 1e-12);
        for (v, (p, q)) in m.positions.iter().zip(&regular.positions).enumerate() {
            assert_eq!(p.z, 0.0);
            assert!(
                p.distance(*q) < bound,
                "vertex {v} moved {}",
                p.distance(*q)
            );
            let (i, j) = (v % 21, v / 21);
            let on_x_border = i == 0 || i == 20;
            let on_y_border = j == 0 || j == 13;
            if on_x_border {
                assert_eq!(p.x, q.x);
            }
            if on_y_border {
                assert_eq!(p.y, q.y);
            }
            assert!((0.0..=xmax).contains(&p.x) && (0.0..=ymax).contains(&p.y));
            if on_x_border && on_y_border {
                assert_eq!(p, q);
            } else {
                assert_ne!(p, q);
            }
        }
        for &t in &m.triangles {
            assert!(normal(&m, t).z > 0.0, "face {t:?} flipped");
        }
    }
    assert_identical(
        &jittered_flat_grid(4, 4, 1.0, 0.0, 3),
        &flat_grid(4, 4, 1.0),
    );
}

#[test]
#[should_panic(expected = "grid jitter must be within")]
fn jittered_grid_rejects_large_jitter() {
    jittered_flat_grid(4, 4, 1.0, 0.5, 0);
}

// --------------------------------------------------------------- determinism

#[test]
fn generators_are_deterministic() {
    let makers: Vec<fn() -> IndexedTriangles> = vec![
        || icosphere(4, 1.3),
        || jittered_icosphere(4, 1.3, 0.08, 11),
        || regular_torus(30, 12, 1.0, 0.25),
        || flat_grid(17, 9, 0.1),
        || jittered_flat_grid(17, 9, 0.1, 0.3, 11),
        || bumpy_sphere(4, 1.0, 40, 0.2, 11),
        || loop_subdivide(&bumpy_sphere(2, 1.0, 10, 0.2, 3), 2).expect("manifold"),
        || midpoint_subdivide(&regular_torus(8, 5, 1.0, 0.2), 2).expect("manifold"),
    ];
    for make in makers {
        assert_identical(&make(), &make());
    }
    // Different seeds, different meshes.
    assert_ne!(
        bits(&jittered_icosphere(3, 1.0, 0.1, 1)),
        bits(&jittered_icosphere(3, 1.0, 0.1, 2))
    );
    assert_ne!(
        bits(&jittered_flat_grid(5, 5, 1.0, 0.3, 1)),
        bits(&jittered_flat_grid(5, 5, 1.0, 0.3, 2))
    );
    assert_ne!(
        bits(&bumpy_sphere(3, 1.0, 5, 0.2, 1)),
        bits(&bumpy_sphere(3, 1.0, 5, 0.2, 2))
    );
}

#[test]
fn splitmix64_reference_values() {
    let mut rng = SplitMix64::new(0);
    assert_eq!(rng.next_u64(), 0xE220_A839_7B1D_CDAF);
    assert_eq!(rng.next_u64(), 0x6E78_9E6A_A1B9_65F4);
    assert_eq!(rng.next_u64(), 0x06C4_5D18_8009_454F);
    let mut rng = SplitMix64::new(123);
    for _ in 0..10_000 {
        let (a, b, c) = (rng.next_f64(), rng.next_f64_open(), rng.next_signed_open());
        assert!((0.0..1.0).contains(&a));
        assert!(b > 0.0 && b < 1.0);
        assert!(c > -1.0 && c < 1.0);
    }
}
