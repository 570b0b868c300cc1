//! Planar grids.

use geodesics_mesh::IndexedTriangles;
use glam::DVec3;

use crate::SplitMix64;

/// Largest `jitter` accepted by [`jittered_flat_grid`]. Below `1/(2√2)`
/// (half the smallest altitude of the grid's right triangles, in units of
/// the spacing) no triangle can flip or degenerate.
pub const MAX_GRID_JITTER: f64 = 0.35;

fn check_grid_args(nx: u32, ny: u32, spacing: f64) -> (usize, usize) {
    assert!(
        nx >= 1 && ny >= 1,
        "grid must have at least one cell each way, got {nx}x{ny}"
    );
    let (w, h) = (nx as usize + 1, ny as usize + 1);
    assert!(
        w.checked_mul(h).is_some_and(|v| v < u32::MAX as usize)
            && (nx as usize)
                .checked_mul(ny as usize)
                .and_then(|c| c.checked_mul(6))
                .is_some_and(|c| c < u32::MAX as usize),
        "grid {nx}x{ny} is too large for 32-bit indices"
    );
    assert!(
        spacing.is_finite() && spacing > 0.0,
        "grid spacing must be finite and positive, got {spacing}"
    );
    (w, h)
}

/// A regular planar grid of `nx × ny` square cells of side `spacing` in the
/// plane z = 0, covering `[0, nx·spacing] × [0, ny·spacing]`.
///
/// Vertex `j·(nx + 1) + i` (row-major, x fastest) is at
/// `(i·spacing, j·spacing, 0)`. Each cell with lower-left corner `v` is split
/// along the same diagonal, into `[v, v+1, v+nx+2]` and `[v, v+nx+2, v+nx+1]`,
/// both counter-clockwise seen from +z. `(nx+1)(ny+1)` vertices, `2·nx·ny`
/// faces, one boundary loop, χ = 1. The domain is planar and convex, so the
/// geodesic distance between two points is their Euclidean distance.
///
/// # Panics
///
/// If `nx` or `ny` is 0, the mesh does not fit 32-bit indices, or `spacing`
/// is not finite and positive.
///
/// ```
/// use geodesics_shapes::flat_grid;
/// let g = flat_grid(100, 100, 0.5);
/// assert_eq!((g.positions.len(), g.triangles.len()), (101 * 101, 20_000));
/// assert_eq!(g.positions[102], glam::DVec3::new(0.5, 0.5, 0.0));
/// ```
pub fn flat_grid(nx: u32, ny: u32, spacing: f64) -> IndexedTriangles {
    let (w, h) = check_grid_args(nx, ny, spacing);
    let mut positions = Vec::with_capacity(w * h);
    for j in 0..h {
        for i in 0..w {
            positions.push(DVec3::new(i as f64 * spacing, j as f64 * spacing, 0.0));
        }
    }
    let mut triangles = Vec::with_capacity(2 * (w - 1) * (h - 1));
    for j in 0..h - 1 {
        for i in 0..w - 1 {
            let v = (j * w + i) as u32;
            let (right, up, diag) = (v + 1, v + w as u32, v + w as u32 + 1);
            triangles.push([v, right, diag]);
            triangles.push([v, diag, up]);
        }
    }
    IndexedTriangles {
        positions,
        triangles,
    }
}

/// A [`flat_grid`] with its vertices moved randomly within the plane z = 0;
/// same numbering and triangles.
///
/// Interior vertices move uniformly within a disc of radius
/// `jitter · spacing`; vertices on a border edge (corners excepted) slide
/// along it by less than `jitter · spacing`; the four corners stay. So the
/// domain is still the exact rectangle `[0, nx·spacing] × [0, ny·spacing]`
/// (planar and convex: geodesic distance = Euclidean distance), no triangle
/// flips for `jitter ≤` [`MAX_GRID_JITTER`], and the same `seed` gives the
/// same bits.
///
/// # Panics
///
/// As [`flat_grid`], and if `jitter` is not within `0..=MAX_GRID_JITTER`.
///
/// ```
/// use geodesics_shapes::{flat_grid, jittered_flat_grid};
/// let g = jittered_flat_grid(10, 10, 1.0, 0.3, 1);
/// let regular = flat_grid(10, 10, 1.0);
/// assert!(g.positions.iter().zip(&regular.positions).all(|(p, q)| p.distance(*q) < 0.3));
/// ```
pub fn jittered_flat_grid(
    nx: u32,
    ny: u32,
    spacing: f64,
    jitter: f64,
    seed: u64,
) -> IndexedTriangles {
    let (w, h) = check_grid_args(nx, ny, spacing);
    assert!(
        (0.0..=MAX_GRID_JITTER).contains(&jitter),
        "grid jitter must be within 0..={MAX_GRID_JITTER}, got {jitter}"
    );
    let mut mesh = flat_grid(nx, ny, spacing);
    let step = jitter * spacing;
    let mut rng = SplitMix64::new(seed);
    for (v, p) in mesh.positions.iter_mut().enumerate() {
        // Two draws per vertex whatever its kind.
        let (u1, u2) = (rng.next_f64(), rng.next_signed_open());
        let (i, j) = (v % w, v / w);
        let (x_border, y_border) = (i == 0 || i == w - 1, j == 0 || j == h - 1);
        match (x_border, y_border) {
            (true, true) => {}
            (true, false) => p.y += step * u2,
            (false, true) => p.x += step * u2,
            (false, false) => {
                let r = step * u1.sqrt();
                let (s, c) = (std::f64::consts::PI * u2).sin_cos();
                p.x += r * c;
                p.y += r * s;
            }
        }
    }
    mesh
}
