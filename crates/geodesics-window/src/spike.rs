//! The one kind of vertex the window-list solvers (VTP and its variants,
//! PVTP, AVTP, ICH) refuse: a spike so thin that windows winding around it
//! would make the solve crawl or never end.
//!
//! Around an interior vertex whose faces meet at a total angle `θ`, the
//! unfolded faces form a wedge of angle `θ`, and a window turning around the
//! vertex keeps its distance to it: the vertex check there never prunes it,
//! and it goes on until it has turned half a circle, about `π/θ` face
//! crossings. The window solvers consume a list as they propagate it, so a
//! window meets nothing of its own earlier pass. On a needle 1e9 times
//! longer than wide VTP took 1 s; at 1e12, and on a hand scan with one
//! vertex pulled 1e22 away (a corrupt coordinate), VTP and ICH ran without
//! end. MMP keeps every window on its edge, where a winding window meets
//! its earlier pass and is trimmed: it has no such limit.
//!
//! Short of that, spikes cost time in proportion to `1/θ`: on a sphere of
//! 14K faces with a tenth of its vertices pulled out into needles, VTP took
//! 0.45 s at θ = 1.4e-3, 0.97 s at 7.2e-4 and 5.4 s at 7.2e-5 (MMP 0.05 s),
//! and with more needles 15 s at 3e-5. So the limit is 1e-3 rad, a cone
//! 6,000 times longer than wide; the sharpest interior vertex of the shared
//! meshes meets at 0.23 rad (the welded dragon).

use geodesics_mesh::{FaceKind, Mesh};
use thiserror::Error;

/// The least total angle at which the faces around an interior vertex may
/// meet for the window-list solvers (radians; see the module docs).
pub const MIN_CONE_ANGLE: f64 = 1e-3;

/// A vertex too sharp for the window-list solvers.
#[derive(Clone, Debug, Error, PartialEq)]
#[error(
    "vertex {vertex} is a spike: its faces meet at {angle:.2e} rad in total, below {min:e}; windows winding around it would make the solve crawl or never end (flatten or remove it, or use MMP, which has no such limit)",
    min = MIN_CONE_ANGLE
)]
pub struct SpikeError {
    /// The vertex, in the input's numbering.
    pub vertex: u32,
    /// The sum of its faces' angles at it.
    pub angle: f64,
}

/// Refuses a mesh with an interior vertex whose faces meet at less than
/// [`MIN_CONE_ANGLE`] in total (the sharpest such vertex is named). Vertices
/// on a boundary, or beside a face windows cannot cross, are never wound
/// around.
///
/// ```
/// use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
/// use geodesics_window::check_spikes;
/// use glam::DVec3;
///
/// // A square pyramid closed by a base: its apex at height `h`.
/// let pyramid = |h: f64| IndexedTriangles {
///     positions: vec![
///         DVec3::new(0.0, 0.0, 0.0),
///         DVec3::new(1.0, 0.0, 0.0),
///         DVec3::new(1.0, 1.0, 0.0),
///         DVec3::new(0.0, 1.0, 0.0),
///         DVec3::new(0.5, 0.5, h),
///     ],
///     triangles: vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [0, 2, 1], [0, 3, 2]],
/// };
/// let build = |h| Mesh::build(pyramid(h), &BuildOptions::default());
/// assert!(check_spikes(&build(1.0)?).is_ok());
/// let needle = check_spikes(&build(1e12)?).unwrap_err();
/// assert_eq!(needle.vertex, 4);
/// assert!(needle.angle < 1e-11);
/// # Ok::<(), geodesics_mesh::MeshError>(())
/// ```
pub fn check_spikes(mesh: &Mesh) -> Result<(), SpikeError> {
    match sharpest_vertex(mesh) {
        Some((vertex, angle)) if angle < MIN_CONE_ANGLE => Err(SpikeError { vertex, angle }),
        _ => Ok(()),
    }
}

/// The interior vertex whose faces meet at the least total angle, among
/// those windows could wind around (none beside a face they cannot
/// cross), with that angle; the vertex in the input's numbering. `None`
/// if every vertex is on a boundary.
///
/// ```
/// use geodesics_mesh::{BuildOptions, Mesh};
/// use geodesics_window::sharpest_vertex;
///
/// // An icosahedron: five equilateral triangles at every vertex.
/// let ico = Mesh::build(geodesics_shapes::icosphere(0, 1.0), &BuildOptions::default())?;
/// let (_, angle) = sharpest_vertex(&ico).expect("a closed mesh");
/// assert!((angle - 5.0 * std::f64::consts::PI / 3.0).abs() < 1e-12);
/// # Ok::<(), geodesics_mesh::MeshError>(())
/// ```
pub fn sharpest_vertex(mesh: &Mesh) -> Option<(u32, f64)> {
    let mut sharpest: Option<(u32, f64)> = None;
    for v in 0..mesh.vertex_count() as u32 {
        let angle = mesh.angle_sum(v);
        let fan = mesh.fan(v);
        if sharpest.is_some_and(|(_, a)| angle >= a) || mesh.is_boundary(v) || fan.is_empty() {
            continue;
        }
        let blocked = fan
            .iter()
            .any(|&h| mesh.face_kind(Mesh::face_of(h)) == FaceKind::Blocked);
        if !blocked {
            sharpest = Some((v, angle));
        }
    }
    sharpest.map(|(v, angle)| (mesh.pinch_origin(v), angle))
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesics_mesh::{BuildOptions, IndexedTriangles};

    fn bipyramid(n: u32, r: f64, h: f64) -> Mesh {
        Mesh::build(
            geodesics_shapes::bipyramid(n, r, h),
            &BuildOptions::default(),
        )
        .expect("a bipyramid is a closed manifold")
    }

    #[test]
    fn a_needle_is_refused_by_its_tip_and_a_blunt_cone_is_not() {
        assert!(check_spikes(&bipyramid(8, 1.0, 1e3)).is_ok());
        let e = check_spikes(&bipyramid(8, 1.0, 1e7)).unwrap_err();
        assert_eq!(e.vertex, 8);
        // The octagon's perimeter over the height.
        let perimeter = 16.0 * (std::f64::consts::PI / 8.0).sin();
        assert!((e.angle - perimeter * 1e-7).abs() < 1e-12);
        assert!(e.to_string().starts_with("vertex 8 is a spike"));
        assert!(e.to_string().contains("below 1e-3"));
    }

    #[test]
    fn an_open_spike_is_not_wound_around() {
        // The same needle without the faces below: its rim is a boundary,
        // and only the tip is interior.
        let mesh = bipyramid(8, 1.0, 1e7);
        let soup = mesh.to_indexed_triangles();
        let kept = IndexedTriangles {
            positions: soup.positions,
            triangles: soup
                .triangles
                .into_iter()
                .filter(|t| t.contains(&8))
                .collect(),
        };
        let open = Mesh::build(kept, &BuildOptions::default()).unwrap();
        assert!(check_spikes(&open).is_err(), "the tip is still interior");
        // Cut one face of the tip's fan: the tip is on the boundary now.
        let soup = open.to_indexed_triangles();
        let cut = IndexedTriangles {
            positions: soup.positions,
            triangles: soup.triangles[1..].to_vec(),
        };
        assert!(check_spikes(&Mesh::build(cut, &BuildOptions::default()).unwrap()).is_ok());
    }
}
