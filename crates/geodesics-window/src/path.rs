//! Shortest paths as every solver returns them: points on the surface and
//! the 3D polyline through them.

use geodesics_mesh::Mesh;
use glam::DVec3;

/// A point on the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfacePoint {
    /// A mesh vertex, as an input vertex id (pinch copies folded back with
    /// [`Mesh::pinch_origin`]).
    Vertex(u32),
    /// A point of the edge of `half_edge`, at `t` from its tail (`0`) to
    /// its head (`1`).
    Edge {
        /// The half-edge (`3 * face + corner`).
        half_edge: u32,
        /// Position along the half-edge.
        t: f64,
    },
    /// A point of face `face`, with barycentric coordinates relative to the
    /// face's corners in [`Mesh::face`] order.
    Face {
        /// The face.
        face: u32,
        /// Barycentric coordinates (summing to 1).
        barycentric: [f64; 3],
    },
}

impl SurfacePoint {
    /// The point in 3D, or `None` if its vertex (an input vertex), half-edge
    /// or face is not in `mesh`.
    pub fn position(&self, mesh: &Mesh) -> Option<DVec3> {
        match *self {
            SurfacePoint::Vertex(v) => ((v as usize) < mesh.input_vertex_count())
                .then(|| mesh.position(mesh.mesh_vertex(v))),
            SurfacePoint::Edge { half_edge, t } => {
                if half_edge as usize >= mesh.half_edge_count() {
                    return None;
                }
                let a = mesh.position(mesh.tail(half_edge));
                let b = mesh.position(mesh.head(half_edge));
                Some(a + (b - a) * t)
            }
            SurfacePoint::Face { face, barycentric } => {
                if face as usize >= mesh.face_count() {
                    return None;
                }
                let c = mesh.face(face).map(|v| mesh.position(v));
                Some(c[0] * barycentric[0] + c[1] * barycentric[1] + c[2] * barycentric[2])
            }
        }
    }
}

/// A shortest path on the surface, from a source to a target.
#[derive(Clone, Debug, PartialEq)]
pub struct GeodesicPath {
    /// The points from the source (first) to the target (last): the source,
    /// every edge crossing, every vertex passed through (where the path may
    /// bend: saddle, boundary and pinch vertices), and the target.
    /// Consecutive points lie in one common face (a zero-area face with two
    /// coincident corners is crossed with two points at one position).
    pub points: Vec<SurfacePoint>,
    /// The same points in 3D.
    pub polyline: Vec<DVec3>,
    /// Length of the polyline: the target's geodesic distance.
    pub length: f64,
    /// Index of the source the path starts at.
    pub source: u32,
}

impl GeodesicPath {
    /// The path through `points` (source first) from source number
    /// `source`: computes the 3D polyline and its length. `Err(index)` names
    /// the first point whose vertex, half-edge or face is not in `mesh`.
    pub fn from_points(
        mesh: &Mesh,
        points: Vec<SurfacePoint>,
        source: u32,
    ) -> Result<GeodesicPath, usize> {
        let polyline = points
            .iter()
            .enumerate()
            .map(|(index, p)| p.position(mesh).ok_or(index))
            .collect::<Result<Vec<DVec3>, usize>>()?;
        let length = polyline.windows(2).map(|w| w[0].distance(w[1])).sum();
        Ok(GeodesicPath {
            points,
            polyline,
            length,
            source,
        })
    }
}
