use serde::Serialize;

/// The VTP paper's anisotropy g(M) over the faces of a mesh: per face
/// `P·H / (2·√3·S)` (P half-perimeter, H longest edge, S area; 1 for an
/// equilateral triangle), zero-area faces excluded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct AnisotropyStats {
    /// Mean over faces (the paper's g(M)).
    pub mean: f64,
    /// Median over faces.
    pub median: f64,
    /// 99th percentile over faces.
    pub p99: f64,
    /// Largest per-face value.
    pub max: f64,
}

/// What `geodesics info` reports about a mesh. Counts refer to the input
/// vertices (pinch-split copies are not counted twice).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MeshSummary {
    /// Vertices of the input (after welding, if asked), unreferenced ones included.
    pub vertices: usize,
    /// Triangles (after dropping faces that welding collapsed).
    pub faces: usize,
    /// Edges (pairs of vertices joined by at least one face).
    pub edges: usize,
    /// Connected components of the referenced vertices.
    pub components: usize,
    /// Connected components of the boundary-edge graph.
    pub boundary_loops: usize,
    /// Referenced vertices − edges + faces.
    pub euler_characteristic: i64,
    /// `(2·components − χ − boundary loops) / 2`; `None` where it is not
    /// defined (non-manifold vertices).
    pub genus: Option<i64>,
    /// Interior vertices whose angle sum exceeds 2π.
    pub saddle_vertices: usize,
    /// Vertices on a boundary edge.
    pub boundary_vertices: usize,
    /// Vertices whose faces form more than one fan (pinch vertices).
    pub nonmanifold_vertices: usize,
    /// Triangles whose area is exactly zero in double precision.
    pub zero_area_faces: usize,
    /// Vertices whose position equals an earlier vertex's exactly
    /// (vertices − distinct positions); 0 after welding.
    pub duplicate_positions: usize,
    /// Vertices no face refers to.
    pub unreferenced_vertices: usize,
    /// Vertices merged into an earlier one by welding.
    pub welded_vertices: usize,
    /// Faces dropped by welding because two corners merged.
    pub welded_collapsed_faces: usize,
    /// Faces whose orientation was flipped to agree with their component.
    pub reoriented_faces: usize,
    /// Per-face anisotropy statistics.
    pub anisotropy: AnisotropyStats,
    /// Length of the bounding-box diagonal.
    pub bbox_diagonal: f64,
    /// Bounding-box minimum corner.
    pub bbox_min: [f64; 3],
    /// Bounding-box maximum corner.
    pub bbox_max: [f64; 3],
}
