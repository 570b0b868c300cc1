//! Checking the sources and common settings every solver takes, and how
//! each source seeds a wavefront.

use geodesics_mesh::Mesh;
use glam::DVec3;
use thiserror::Error;

use crate::{FaceKind, Source, Tolerance, Window};

/// Why a solve's sources or distance limit were refused. Every variant
/// names the offending source (its index in the `sources` slice) and value.
/// Each solver's error wraps it.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum SourceError {
    /// The source list is empty.
    #[error("no sources given")]
    NoSources,
    /// A vertex source is not a vertex of the mesh.
    #[error(
        "source {source_index}: vertex {vertex} out of range (the mesh has {vertices} input vertices)"
    )]
    VertexOutOfRange {
        /// Index of the source.
        source_index: usize,
        /// The vertex given.
        vertex: u32,
        /// Number of input vertices.
        vertices: usize,
    },
    /// A vertex source belongs to no face.
    #[error("source {source_index}: vertex {vertex} is not referenced by any face")]
    UnreferencedVertex {
        /// Index of the source.
        source_index: usize,
        /// The vertex given.
        vertex: u32,
    },
    /// An edge-point source names a half-edge that does not exist.
    #[error(
        "source {source_index}: half-edge {half_edge} out of range (the mesh has {half_edges})"
    )]
    HalfEdgeOutOfRange {
        /// Index of the source.
        source_index: usize,
        /// The half-edge given.
        half_edge: u32,
        /// Number of half-edges.
        half_edges: usize,
    },
    /// An edge-point parameter is not a number in `[0, 1]`.
    #[error("source {source_index}: edge parameter t = {t} is not in [0, 1]")]
    EdgeParameter {
        /// Index of the source.
        source_index: usize,
        /// The parameter given.
        t: f64,
    },
    /// A face-point source names a face that does not exist.
    #[error("source {source_index}: face {face} out of range (the mesh has {faces})")]
    FaceOutOfRange {
        /// Index of the source.
        source_index: usize,
        /// The face given.
        face: u32,
        /// Number of faces.
        faces: usize,
    },
    /// Barycentric coordinates not finite, negative, or not summing to 1.
    #[error(
        "source {source_index}: barycentric coordinates {barycentric:?} must be finite, non-negative and sum to 1"
    )]
    Barycentric {
        /// Index of the source.
        source_index: usize,
        /// The coordinates given.
        barycentric: [f64; 3],
    },
    /// The maximum distance is NaN or negative.
    #[error("maximum distance {0} must be a non-negative number")]
    MaxDistance(f64),
}

/// Checks `sources` against `mesh` and the distance limit: at least one
/// source; vertices in range and referenced by a face; half-edges in range
/// with `t ∈ [0, 1]`; faces in range with finite, non-negative barycentric
/// coordinates summing to 1 (within the tolerance); a limit that is a
/// non-negative number.
pub fn validate_sources(
    mesh: &Mesh,
    sources: &[Source],
    max_distance: Option<f64>,
) -> Result<(), SourceError> {
    if sources.is_empty() {
        return Err(SourceError::NoSources);
    }
    if let Some(m) = max_distance
        && !(m >= 0.0)
    {
        return Err(SourceError::MaxDistance(m));
    }
    let tol = Tolerance::for_mesh(mesh);
    for (source_index, s) in sources.iter().enumerate() {
        match *s {
            Source::Vertex(vertex) => {
                if vertex as usize >= mesh.input_vertex_count() {
                    return Err(SourceError::VertexOutOfRange {
                        source_index,
                        vertex,
                        vertices: mesh.input_vertex_count(),
                    });
                }
                if !mesh.is_referenced(mesh.mesh_vertex(vertex)) {
                    return Err(SourceError::UnreferencedVertex {
                        source_index,
                        vertex,
                    });
                }
            }
            Source::EdgePoint { half_edge, t } => {
                if half_edge as usize >= mesh.half_edge_count() {
                    return Err(SourceError::HalfEdgeOutOfRange {
                        source_index,
                        half_edge,
                        half_edges: mesh.half_edge_count(),
                    });
                }
                if !(0.0..=1.0).contains(&t) {
                    return Err(SourceError::EdgeParameter { source_index, t });
                }
            }
            Source::FacePoint { face, barycentric } => {
                if face as usize >= mesh.face_count() {
                    return Err(SourceError::FaceOutOfRange {
                        source_index,
                        face,
                        faces: mesh.face_count(),
                    });
                }
                if !barycentric_ok(&barycentric, &tol) {
                    return Err(SourceError::Barycentric {
                        source_index,
                        barycentric,
                    });
                }
            }
        }
    }
    Ok(())
}

/// Whether barycentric coordinates are finite, non-negative and sum to 1
/// within the tolerance.
pub fn barycentric_ok(b: &[f64; 3], tol: &Tolerance) -> bool {
    b.iter().all(|x| x.is_finite() && *x >= 0.0)
        && (b.iter().sum::<f64>() - 1.0).abs() <= tol.relative
}

/// Where a validated source starts the wavefront, decided once for every
/// solver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SourceStart {
    /// At a mesh vertex (also an edge or face point that sits on one).
    Vertex(u32),
    /// At `point`, inside `faces[0]` and, for a point on an edge, also
    /// inside `faces[1]`, the face across it (if any). A point on an edge
    /// names the edge's ends in `edge_ends`: paths running along the edge's
    /// line may go on through them, so they must act as pseudo-sources.
    Point {
        /// The source position.
        point: DVec3,
        /// The face(s) holding it.
        faces: [Option<u32>; 2],
        /// The ends of the edge holding it, for a point on an edge.
        edge_ends: Option<[u32; 2]>,
    },
}

/// Resolves a source (checked by [`validate_sources`]) into where it
/// starts: a face point with one zero barycentric coordinate is an edge
/// point, with two it is a vertex; an edge point at `t = 0` or `1` is a
/// vertex.
pub fn source_start(mesh: &Mesh, source: &Source) -> SourceStart {
    match *source {
        Source::Vertex(v) => SourceStart::Vertex(mesh.mesh_vertex(v)),
        Source::EdgePoint { half_edge: h, t } => {
            if t == 0.0 {
                return SourceStart::Vertex(mesh.tail(h));
            }
            if t == 1.0 {
                return SourceStart::Vertex(mesh.head(h));
            }
            let a = mesh.position(mesh.tail(h));
            let b = mesh.position(mesh.head(h));
            SourceStart::Point {
                point: a + (b - a) * t,
                faces: [Some(h / 3), mesh.twin(h).map(|t| t / 3)],
                edge_ends: Some([mesh.tail(h), mesh.head(h)]),
            }
        }
        Source::FacePoint { face, barycentric } => {
            let zeros = barycentric.iter().filter(|&&b| b == 0.0).count();
            if zeros == 2 {
                let k = barycentric.iter().position(|&b| b != 0.0).unwrap_or(0);
                return SourceStart::Vertex(mesh.face(face)[k]);
            }
            if zeros == 1 {
                // On the edge opposite the zero coordinate's corner.
                let k = barycentric.iter().position(|&b| b == 0.0).unwrap_or(0);
                let (i1, i2) = ((k + 1) % 3, (k + 2) % 3);
                let t = barycentric[i2] / (barycentric[i1] + barycentric[i2]);
                let half_edge = 3 * face + i1 as u32;
                return source_start(mesh, &Source::EdgePoint { half_edge, t });
            }
            let c = mesh.face(face).map(|v| mesh.position(v));
            let s: f64 = barycentric.iter().sum();
            SourceStart::Point {
                point: (c[0] * barycentric[0] + c[1] * barycentric[1] + c[2] * barycentric[2]) / s,
                faces: [Some(face), None],
                edge_ends: None,
            }
        }
    }
}

/// How a solver starts from one source, whatever its own data layout.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Seeds {
    /// Vertices that must act as pseudo-sources (a solver marks their pinch
    /// copies too): the source vertex, the ends of the edge holding an edge
    /// point, the corners of a zero-area face holding a point.
    pub pseudo: Vec<u32>,
    /// `(vertex, distance)`: the source vertex at 0, or the corners of the
    /// face(s) holding a point at their straight distances.
    pub distances: Vec<(u32, f64)>,
    /// `(half-edge, window)`: for a point inside a proper face, one window
    /// per edge of that face not containing the point, on the half-edge
    /// across it (lighting the next face) with the point as its source.
    pub windows: Vec<(u32, Window)>,
}

/// The [`Seeds`] of source number `index` (checked by
/// [`validate_sources`]), on a mesh whose faces have the kinds `kind` (see
/// [`crate::SolverSetup`]).
pub fn seeds(mesh: &Mesh, kind: &[FaceKind], source: &Source, index: u32) -> Seeds {
    let mut seeds = Seeds::default();
    match source_start(mesh, source) {
        SourceStart::Vertex(v) => {
            seeds.pseudo.push(v);
            seeds.distances.push((v, 0.0));
        }
        SourceStart::Point {
            point,
            faces,
            edge_ends,
        } => {
            seeds.pseudo.extend(edge_ends.into_iter().flatten());
            for f in faces.into_iter().flatten() {
                let proper = kind[f as usize] == FaceKind::Proper;
                // A point inside a zero-area face starts from its corners:
                // they become pseudo-sources.
                if edge_ends.is_none() && !proper {
                    seeds.pseudo.extend(mesh.face(f));
                }
                for v in mesh.face(f) {
                    seeds.distances.push((v, mesh.position(v).distance(point)));
                }
                if !proper {
                    continue;
                }
                for h in 3 * f..3 * f + 3 {
                    let Some(t) = mesh.twin(h) else { continue };
                    let c = mesh.frame_coords(h, point);
                    let l = mesh.length(h);
                    if c.y > 0.0 {
                        let window = Window::across_edge(l, c, 0.0, index);
                        seeds.windows.push((t, window));
                    }
                }
            }
        }
    }
    seeds
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SolverSetup;
    use geodesics_mesh::{BuildOptions, IndexedTriangles};

    /// The unit square split along its diagonal 0-2.
    fn square() -> Mesh {
        let soup = IndexedTriangles {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        Mesh::build(soup, &BuildOptions::default()).expect("a valid square")
    }

    #[test]
    fn a_vertex_source_is_a_pseudo_source_at_zero() {
        let mesh = square();
        let kind = SolverSetup::new(&mesh, &Tolerance::for_mesh(&mesh)).kind;
        let s = seeds(&mesh, &kind, &Source::Vertex(3), 0);
        assert_eq!(s.pseudo, vec![3]);
        assert_eq!(s.distances, vec![(3, 0.0)]);
        assert!(s.windows.is_empty());
    }

    #[test]
    fn a_face_point_lights_the_faces_across_its_edges() {
        let mesh = square();
        let kind = SolverSetup::new(&mesh, &Tolerance::for_mesh(&mesh)).kind;
        let third = 1.0 / 3.0;
        let source = Source::FacePoint {
            face: 0,
            barycentric: [third, third, third],
        };
        let s = seeds(&mesh, &kind, &source, 7);
        assert!(s.pseudo.is_empty());
        let q = DVec3::new(2.0 / 3.0, 1.0 / 3.0, 0.0);
        assert_eq!(s.distances.len(), 3);
        for &(v, d) in &s.distances {
            assert!((d - mesh.position(v).distance(q)).abs() < 1e-15);
        }
        // Only the diagonal has a face across it: one window there, the
        // whole edge, lit from the point (at distance |q - diagonal|).
        assert_eq!(s.windows.len(), 1);
        let (t, w) = s.windows[0];
        assert_eq!(Mesh::face_of(t), 1);
        assert_eq!((w.b0, w.b1, w.sigma, w.source), (0.0, 2f64.sqrt(), 0.0, 7));
        assert!((w.p.y + (1.0 / 3.0) / 2f64.sqrt()).abs() < 1e-15, "{w:?}");
    }

    #[test]
    fn an_edge_point_makes_the_edge_ends_pseudo_sources() {
        let mesh = square();
        let kind = SolverSetup::new(&mesh, &Tolerance::for_mesh(&mesh)).kind;
        // The middle of the diagonal, seen from both faces.
        let h = (0..6)
            .find(|&h| mesh.tail(h) == 0 && mesh.head(h) == 2)
            .expect("diagonal");
        let s = seeds(
            &mesh,
            &kind,
            &Source::EdgePoint {
                half_edge: h,
                t: 0.5,
            },
            0,
        );
        let mut ends = s.pseudo.clone();
        ends.sort_unstable();
        assert_eq!(ends, vec![0, 2]);
        assert_eq!(s.distances.len(), 6);
        // Both faces' other edges are on the boundary: no windows.
        assert!(s.windows.is_empty());
    }
}
