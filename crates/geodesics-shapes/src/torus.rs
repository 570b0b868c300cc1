//! Torus of revolution.

use geodesics_mesh::IndexedTriangles;

/// `(cos, sin)` of `2πk/n` for `k` in `0..n`, mirror-symmetric exactly:
/// entry `n − k` is entry `k` with the sine negated, and the angles 0, π/2,
/// π, 3π/2 are exact.
fn circle(n: u32) -> Vec<(f64, f64)> {
    let mut table: Vec<(f64, f64)> = Vec::with_capacity(n as usize);
    for k in 0..n {
        let entry = if 4 * u64::from(k) == u64::from(n) {
            (0.0, 1.0)
        } else if 2 * u64::from(k) == u64::from(n) {
            (-1.0, 0.0)
        } else if 2 * k <= n {
            let (s, c) = (std::f64::consts::TAU * f64::from(k) / f64::from(n)).sin_cos();
            (c, s)
        } else {
            let (c, s) = table[(n - k) as usize];
            (c, -s)
        };
        table.push(entry);
    }
    table[0] = (1.0, 0.0);
    table
}

/// A torus of revolution around the z axis: tube centre circle of radius
/// `major_radius` in the plane z = 0, tube radius `minor_radius`.
///
/// Vertex `i · minor_segments + j` (`i` around the z axis, `j` around the
/// tube, angles `u = 2πi/M`, `v = 2πj/N`) is at
/// `((R + r cos v) cos u, (R + r cos v) sin u, r sin v)`; vertex 0 is on the
/// outer equator on the +x axis. Each quad `(i, j)–(i+1, j)–(i+1, j+1)–(i, j+1)`
/// is split along the same diagonal `(i, j)–(i+1, j+1)` into two triangles,
/// counter-clockwise from outside. So `M·N` vertices, `2·M·N` faces, χ = 0,
/// genus 1; 120×40 gives 4,800 vertices and 9,600 faces. All faces of one
/// ring (same `j`) are congruent; the mesh is exactly mirror-symmetric in
/// the planes y = 0 and z = 0 (as far as the vertex set goes).
///
/// # Panics
///
/// If a segment count is below 3, the vertex count does not fit 32-bit
/// indices, or the radii are not finite with `0 < minor_radius < major_radius`.
///
/// ```
/// use geodesics_shapes::regular_torus;
/// let t = regular_torus(120, 40, 1.0, 0.3);
/// assert_eq!((t.positions.len(), t.triangles.len()), (4800, 9600));
/// ```
pub fn regular_torus(
    major_segments: u32,
    minor_segments: u32,
    major_radius: f64,
    minor_radius: f64,
) -> IndexedTriangles {
    assert!(
        major_segments >= 3 && minor_segments >= 3,
        "torus segment counts must be at least 3, got {major_segments}x{minor_segments}"
    );
    let (m, n) = (major_segments as usize, minor_segments as usize);
    assert!(
        m.checked_mul(n)
            .and_then(|v| v.checked_mul(6))
            .is_some_and(|h| h < u32::MAX as usize),
        "torus {major_segments}x{minor_segments} is too large for 32-bit indices"
    );
    assert!(
        minor_radius.is_finite()
            && major_radius.is_finite()
            && minor_radius > 0.0
            && minor_radius < major_radius,
        "torus radii must be finite with 0 < minor < major, got major {major_radius}, minor {minor_radius}"
    );
    let around = circle(major_segments);
    let tube = circle(minor_segments);
    let mut positions = Vec::with_capacity(m * n);
    for &(cu, su) in &around {
        for &(cv, sv) in &tube {
            let rho = major_radius + minor_radius * cv;
            positions.push(glam::DVec3::new(rho * cu, rho * su, minor_radius * sv));
        }
    }
    let mut triangles = Vec::with_capacity(2 * m * n);
    let index = |i: usize, j: usize| ((i % m) * n + (j % n)) as u32;
    for i in 0..m {
        for j in 0..n {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    IndexedTriangles {
        positions,
        triangles,
    }
}
