use thiserror::Error;

/// Why a set of triangles is not a mesh the solvers can work on. Every
/// variant names the culprit so that the user can find it in the file.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum MeshError {
    /// No triangles at all.
    #[error("the mesh is empty: {vertices} vertices and no triangles")]
    Empty {
        /// Number of vertices given.
        vertices: usize,
    },
    /// More vertices or half-edges than 32-bit indices can address.
    #[error("the mesh is too large: {faces} faces (at most {max})")]
    TooLarge {
        /// Number of faces given.
        faces: usize,
        /// The largest supported face count.
        max: usize,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {index}, but there are only {vertices} vertices")]
    IndexOutOfRange {
        /// The face (0-based, in input order).
        face: usize,
        /// The offending index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFiniteCoordinate {
        /// The vertex.
        vertex: usize,
        /// Its coordinates.
        x: f64,
        /// Its coordinates.
        y: f64,
        /// Its coordinates.
        z: f64,
    },
    /// A coordinate is so large that squared lengths would overflow or
    /// lose their precision (beyond [`MAX_COORDINATE`](crate::MAX_COORDINATE)).
    #[error(
        "vertex {vertex} has a coordinate {value:e}, beyond ±{max:e}: squared lengths would overflow; scale the mesh down",
        max = crate::MAX_COORDINATE
    )]
    CoordinateTooLarge {
        /// The vertex.
        vertex: usize,
        /// The coordinate.
        value: f64,
    },
    /// The whole mesh is so small that squared lengths would underflow
    /// (the largest side of its bounding box is below
    /// [`MIN_EXTENT`](crate::MIN_EXTENT) but not zero).
    #[error(
        "the mesh spans only {extent:e} (the largest side of its bounding box), below {min:e}: squared lengths would underflow; scale the mesh up",
        min = crate::MIN_EXTENT
    )]
    TooSmall {
        /// The largest side of its bounding box.
        extent: f64,
    },
    /// A triangle uses the same vertex twice.
    #[error("face {face} repeats a vertex: [{}, {}, {}]", corners[0], corners[1], corners[2])]
    RepeatedVertex {
        /// The face.
        face: usize,
        /// Its corners.
        corners: [u32; 3],
    },
    /// More than two triangles share an edge.
    #[error("non-manifold edge between vertices {a} and {b}: shared by faces {faces:?}")]
    NonManifoldEdge {
        /// One end of the edge.
        a: u32,
        /// The other end.
        b: u32,
        /// All faces on that edge.
        faces: Vec<usize>,
    },
    /// A connected piece cannot be oriented (a Möbius strip, a Klein bottle).
    #[error(
        "non-orientable surface: face {face} cannot be oriented consistently with face {neighbour} across the edge {a}-{b}"
    )]
    NonOrientable {
        /// A face whose orientation conflicts.
        face: usize,
        /// Its neighbour across the edge.
        neighbour: usize,
        /// One end of the shared edge.
        a: u32,
        /// The other end.
        b: u32,
    },
}
