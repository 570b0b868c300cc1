//! A double cone over a regular polygon: its tip as sharp as one likes.

use glam::DVec3;

use crate::IndexedTriangles;

/// A bipyramid over a regular polygon of `sides` corners at distance
/// `radius` from the z axis in the plane z = 0 (vertices `0..sides`, the
/// first on +x, counter-clockwise seen from +z), with its tip at height
/// `height` (vertex `sides`) and its other apex at depth `radius` (vertex
/// `sides + 1`). A tall one is a needle: the faces meet at its tip at a
/// total angle of about `2π · radius / height`, what the window solvers'
/// spike check (`geodesics_window::check_spikes`) looks at.
///
/// # Panics
///
/// If `sides < 3` or `radius` or `height` is not finite and positive.
///
/// ```
/// use geodesics_shapes::bipyramid;
/// let needle = bipyramid(8, 1.0, 1e6);
/// assert_eq!((needle.positions.len(), needle.triangles.len()), (10, 16));
/// assert_eq!(needle.positions[8].z, 1e6);
/// ```
pub fn bipyramid(sides: u32, radius: f64, height: f64) -> IndexedTriangles {
    assert!(
        sides >= 3,
        "a bipyramid needs at least 3 sides, got {sides}"
    );
    assert!(
        radius.is_finite() && radius > 0.0 && height.is_finite() && height > 0.0,
        "a bipyramid needs a finite positive radius and height, got {radius} and {height}"
    );
    let step = std::f64::consts::TAU / f64::from(sides);
    let mut positions: Vec<DVec3> = (0..sides)
        .map(|i| {
            let a = step * f64::from(i);
            DVec3::new(radius * a.cos(), radius * a.sin(), 0.0)
        })
        .collect();
    positions.push(DVec3::new(0.0, 0.0, height));
    positions.push(DVec3::new(0.0, 0.0, -radius));
    let (tip, bottom) = (sides, sides + 1);
    let triangles = (0..sides)
        .flat_map(|i| {
            let j = (i + 1) % sides;
            [[i, j, tip], [j, i, bottom]]
        })
        .collect();
    IndexedTriangles {
        positions,
        triangles,
    }
}
