//! Icosphere, jittered icosphere and bumpy sphere.

use geodesics_mesh::IndexedTriangles;
use glam::DVec3;

use crate::SplitMix64;
use crate::subdivide::midpoint_step;
use crate::topology::EdgeTopology;

/// Largest `subdivisions` accepted by the sphere generators
/// (10·4¹² + 2 ≈ 168 million vertices).
pub const MAX_SPHERE_SUBDIVISIONS: u32 = 12;

/// Largest `jitter` accepted by [`jittered_icosphere`]: up to it the mesh
/// stays convex whatever the seed. (A worst-case analysis, each edge's four
/// vertices pushed in the most harmful tangential directions, puts the limit
/// near 0.117 at every subdivision level; at 0.1 the flattest edge keeps
/// 10 % of its convexity.)
pub const MAX_SPHERE_JITTER: f64 = 0.1;

/// The 12 icosahedron corners (before normalisation): cyclic permutations of
/// `(0, ±1, ±φ)`. All symmetries of this set that permute and negate
/// coordinates (the pyritohedral group, 24 elements) are exact in floating
/// point.
fn icosahedron() -> IndexedTriangles {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let positions = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .map(|p| unit_symmetric(DVec3::from_array(p)))
    .to_vec();
    let triangles = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    IndexedTriangles {
        positions,
        triangles,
    }
}

/// `p / |p|`, computed so that permuting or negating the coordinates of `p`
/// permutes or negates those of the result exactly: the squares are summed
/// in increasing order, and negative zeros are made positive.
fn unit_symmetric(p: DVec3) -> DVec3 {
    let mut s = [p.x * p.x, p.y * p.y, p.z * p.z];
    if s[0] > s[1] {
        s.swap(0, 1);
    }
    if s[1] > s[2] {
        s.swap(1, 2);
    }
    if s[0] > s[1] {
        s.swap(0, 1);
    }
    let len = ((s[0] + s[1]) + s[2]).sqrt();
    DVec3::new(p.x / len + 0.0, p.y / len + 0.0, p.z / len + 0.0)
}

fn check_sphere_args(subdivisions: u32, radius: f64) {
    assert!(
        subdivisions <= MAX_SPHERE_SUBDIVISIONS,
        "sphere subdivisions must be at most {MAX_SPHERE_SUBDIVISIONS}, got {subdivisions}"
    );
    assert!(
        radius.is_finite() && radius > 0.0,
        "sphere radius must be finite and positive, got {radius}"
    );
}

/// The icosphere on the unit sphere.
fn unit_icosphere(subdivisions: u32) -> IndexedTriangles {
    let mut mesh = icosahedron();
    for _ in 0..subdivisions {
        let old = mesh.positions.len();
        mesh = match midpoint_step(&mesh) {
            Ok(m) => m,
            // The icosahedron and its splits are closed 2-manifolds, and
            // `check_sphere_args` bounds the size.
            Err(e) => unreachable!("icosphere subdivision failed: {e}"),
        };
        for p in &mut mesh.positions[old..] {
            *p = unit_symmetric(*p);
        }
    }
    mesh
}

/// An icosphere: the icosahedron with each triangle split into four
/// `subdivisions` times, the new edge midpoints projected onto the sphere.
///
/// `10·4ˢ + 2` vertices and `20·4ˢ` faces (subdivision 4: 2,562 and 5,120;
/// subdivision 5: 10,242 and 20,480). Triangles are counter-clockwise seen
/// from outside. Vertices `0..12` are the icosahedron corners, cyclic
/// permutations of `(0, ±1, ±φ)/√(1 + φ²)·radius` (so no vertex sits on a
/// coordinate axis); each split appends one vertex per edge, edges ordered by
/// their `(min, max)` endpoints.
///
/// The vertex set is *exactly* (bit for bit) invariant under the 24
/// symmetries that permute the coordinates cyclically and flip their signs,
/// and every vertex is at distance `radius` from the origin to within a few
/// ulps: many geodesic distances tie exactly, which stresses a solver's
/// priority queue. Only IEEE-exact operations (`+`, `/`, `√`) are used, so the
/// result is bit-identical on every platform.
///
/// # Panics
///
/// If `subdivisions > MAX_SPHERE_SUBDIVISIONS` or `radius` is not finite and
/// positive.
///
/// ```
/// use geodesics_shapes::icosphere;
/// let s = icosphere(4, 2.0);
/// assert_eq!((s.positions.len(), s.triangles.len()), (2562, 5120));
/// assert!(s.positions.iter().all(|p| (p.length() - 2.0).abs() < 1e-14));
/// ```
pub fn icosphere(subdivisions: u32, radius: f64) -> IndexedTriangles {
    check_sphere_args(subdivisions, radius);
    let mut mesh = unit_icosphere(subdivisions);
    for p in &mut mesh.positions {
        *p *= radius;
    }
    mesh
}

/// Shortest edge of a mesh (the topology is known to be valid).
fn shortest_edge(mesh: &IndexedTriangles) -> f64 {
    let topo = match EdgeTopology::new(mesh.positions.len(), &mesh.triangles) {
        Ok(t) => t,
        Err(e) => unreachable!("icosphere topology failed: {e}"),
    };
    topo.edges
        .iter()
        .map(|&[a, b]| mesh.positions[a as usize].distance(mesh.positions[b as usize]))
        .fold(f64::INFINITY, f64::min)
}

/// An [`icosphere`] whose vertices are moved by random tangential steps and
/// put back on the sphere: same topology and numbering, every vertex still at
/// distance `radius` from the origin, but no symmetry left (so no exact
/// distance ties).
///
/// Each vertex moves by less than `jitter` times the shortest edge of the
/// unjittered icosphere (uniformly in a tangent disc, then projected back).
/// For `jitter ≤` [`MAX_SPHERE_JITTER`] the surface stays convex (every edge
/// is a convex fold, no saddle vertices). The same `seed` gives the same
/// bits.
///
/// # Panics
///
/// As [`icosphere`], and if `jitter` is not within `0..=MAX_SPHERE_JITTER`.
///
/// ```
/// use geodesics_shapes::{icosphere, jittered_icosphere};
/// let a = jittered_icosphere(3, 1.0, 0.05, 42);
/// assert_eq!(a, jittered_icosphere(3, 1.0, 0.05, 42));
/// assert_eq!(a.triangles, icosphere(3, 1.0).triangles);
/// assert_ne!(a.positions, icosphere(3, 1.0).positions);
/// ```
pub fn jittered_icosphere(
    subdivisions: u32,
    radius: f64,
    jitter: f64,
    seed: u64,
) -> IndexedTriangles {
    check_sphere_args(subdivisions, radius);
    assert!(
        (0.0..=MAX_SPHERE_JITTER).contains(&jitter),
        "sphere jitter must be within 0..={MAX_SPHERE_JITTER}, got {jitter}"
    );
    let mut mesh = unit_icosphere(subdivisions);
    let step = jitter * shortest_edge(&mesh);
    let mut rng = SplitMix64::new(seed);
    for p in &mut mesh.positions {
        let r = step * rng.next_f64().sqrt();
        let (s, c) = (std::f64::consts::TAU * rng.next_f64()).sin_cos();
        let (t1, t2) = p.any_orthonormal_pair();
        // The chord to the projected point is shorter than the tangent step.
        *p = unit_symmetric(*p + t1 * (r * c) + t2 * (r * s)) * radius;
    }
    mesh
}

/// A uniformly random unit vector.
fn random_direction(rng: &mut SplitMix64) -> DVec3 {
    let z = 2.0 * rng.next_f64() - 1.0;
    let (s, c) = (std::f64::consts::TAU * rng.next_f64()).sin_cos();
    let rho = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(rho * c, rho * s, z)
}

/// One smooth radial bump of [`bumpy_sphere`].
#[derive(Clone, Copy, Debug)]
struct Bump {
    centre: DVec3,
    height: f64,
    inv_var: f64,
}

/// A star-shaped, closed, genus-0 surface with many saddle vertices: an
/// [`icosphere`] whose vertex in direction `u` is moved to
/// `radius · exp(Σₖ hₖ · exp(−(1 − u·cₖ)/σₖ²))`, a sum of `bumps` smooth
/// Gaussian-shaped bumps (`hₖ > 0`) and dents (`hₖ < 0`).
///
/// The centres `cₖ` are uniform random directions, the heights `|hₖ|` uniform
/// in `[amplitude/2, amplitude]` with random sign, the angular widths `σₖ`
/// uniform in `[0.15, 0.4]` radians (so `1 − u·c ≈ θ²/2` makes each bump a
/// Gaussian of standard deviation `σₖ` in the angle `θ`). The exponential
/// keeps every radius positive, so faces stay outward-facing for any
/// amplitude; `amplitude = 0.1` changes the radius by roughly ±10 % per bump.
/// With 40 bumps, amplitude 0.2 makes about a third of the vertices saddles
/// (angle sum above 2π) and amplitude 0.1 about 14 %, at any subdivision
/// from 3 up. Same arguments, same bits.
///
/// # Panics
///
/// As [`icosphere`], and if `amplitude` is not finite.
///
/// ```
/// use geodesics_mesh::{BuildOptions, Mesh};
/// use geodesics_shapes::bumpy_sphere;
/// let mesh = Mesh::build(bumpy_sphere(4, 1.0, 40, 0.1, 7), &BuildOptions::default()).unwrap();
/// assert!(mesh.summary().saddle_vertices > 0);
/// ```
pub fn bumpy_sphere(
    subdivisions: u32,
    radius: f64,
    bumps: u32,
    amplitude: f64,
    seed: u64,
) -> IndexedTriangles {
    check_sphere_args(subdivisions, radius);
    assert!(
        amplitude.is_finite(),
        "bump amplitude must be finite, got {amplitude}"
    );
    let mut rng = SplitMix64::new(seed);
    let bumps: Vec<Bump> = (0..bumps)
        .map(|_| {
            let centre = random_direction(&mut rng);
            let sign = if rng.next_u64() & 1 == 0 { 1.0 } else { -1.0 };
            let height = sign * amplitude * (0.5 + 0.5 * rng.next_f64());
            let sigma = 0.15 + 0.25 * rng.next_f64();
            Bump {
                centre,
                height,
                inv_var: 1.0 / (sigma * sigma),
            }
        })
        .collect();
    let mut mesh = unit_icosphere(subdivisions);
    for p in &mut mesh.positions {
        let log_r: f64 = bumps
            .iter()
            .map(|b| b.height * (-(1.0 - p.dot(b.centre)) * b.inv_var).exp())
            .sum();
        *p *= radius * log_r.exp();
    }
    mesh
}
