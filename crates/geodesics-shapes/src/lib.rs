//! Procedural triangle meshes for the tests, benchmarks and demos of the
//! geodesics workspace.
//!
//! Every generator is deterministic (same arguments → bit-identical output)
//! and returns an [`IndexedTriangles`] whose triangles are consistently
//! oriented, counter-clockwise seen from outside (from +z for the planar
//! grids), ready for [`geodesics_mesh::Mesh::build`]:
//!
//! | function | shape | V, F | χ |
//! |----------|-------|------|---|
//! | [`icosphere`] | exactly symmetric subdivided icosahedron | `10·4ˢ+2`, `20·4ˢ` | 2 |
//! | [`jittered_icosphere`] | the same, vertices randomly slid on the sphere | same | 2 |
//! | [`bumpy_sphere`] | icosphere with random radial bumps: many saddles | same | 2 |
//! | [`regular_torus`] | torus of revolution, uniform quads split alike | `M·N`, `2MN` | 0 |
//! | [`flat_grid`] | planar square grid in z = 0 | `(nx+1)(ny+1)`, `2·nx·ny` | 1 |
//! | [`jittered_flat_grid`] | the same, vertices randomly moved in the rectangle | same | 1 |
//! | [`bipyramid`] | double cone over a regular polygon, its tip as sharp as asked | `n+2`, `2n` | 2 |
//!
//! and two subdivision schemes that keep the old vertex numbering and append
//! one vertex per edge: [`loop_subdivide`] (smooth) and
//! [`midpoint_subdivide`] (keeps the surface exactly), and [`simplify`]
//! for the other way, quadric-error edge collapses down to a face budget
//! (how the benchmarks make a coarse bunny like the one Du et al. subdivide
//! for their large test meshes). [`Shape`] parses
//! specs such as `"torus:120x40"` for the command line, and [`from_spec`]
//! parses and builds in one call. Randomness comes from the built-in
//! [`SplitMix64`].
//!
//! Generators panic (with a message) only on nonsensical arguments, listed
//! under *Panics* on each; [`Shape::build`] validates first and returns a
//! [`ShapeError`] instead, so user input never panics.
//!
//! # Example
//!
//! ```
//! use geodesics_mesh::{BuildOptions, Mesh};
//! use geodesics_shapes::{Shape, icosphere, loop_subdivide};
//!
//! let sphere = icosphere(4, 1.0);
//! assert_eq!((sphere.positions.len(), sphere.triangles.len()), (2562, 5120));
//! let mesh = Mesh::build(sphere, &BuildOptions::default())?;
//! let s = mesh.summary();
//! assert_eq!((s.euler_characteristic, s.genus, s.boundary_loops), (2, Some(0), 0));
//!
//! let torus = geodesics_shapes::from_spec("torus:12x8")?;
//! assert_eq!(Shape::from_spec("torus:12x8")?.build()?, torus);
//! let smooth = loop_subdivide(&torus, 1)?;
//! assert_eq!(smooth.triangles.len(), 4 * torus.triangles.len());
//! let s = Mesh::build(smooth, &BuildOptions::default())?.summary().clone();
//! assert_eq!((s.euler_characteristic, s.genus), (0, Some(1)));
//!
//! assert!(Shape::from_spec("dodecahedron:2").is_err());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod bipyramid;
mod grid;
mod rng;
mod simplify;
mod spec;
mod sphere;
mod subdivide;
mod topology;
mod torus;

pub use bipyramid::bipyramid;
pub use geodesics_mesh::IndexedTriangles;
pub use grid::{MAX_GRID_JITTER, flat_grid, jittered_flat_grid};
pub use rng::SplitMix64;
pub use simplify::simplify;
pub use spec::{MAX_SHAPE_VERTICES, SHAPE_KINDS, Shape, from_spec};
pub use sphere::{
    MAX_SPHERE_JITTER, MAX_SPHERE_SUBDIVISIONS, bumpy_sphere, icosphere, jittered_icosphere,
};
pub use subdivide::{loop_subdivide, midpoint_subdivide};
pub use torus::regular_torus;

use thiserror::Error;

/// Why a subdivision or a shape spec failed.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ShapeError {
    /// More than two triangles share an edge (subdivision needs a manifold
    /// edge graph).
    #[error("non-manifold edge between vertices {a} and {b}: shared by faces {faces:?}")]
    NonManifoldEdge {
        /// Smaller vertex of the edge.
        a: u32,
        /// Larger vertex of the edge.
        b: u32,
        /// All faces on that edge.
        faces: Vec<usize>,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {index}, but there are only {vertices} vertices")]
    IndexOutOfRange {
        /// The face.
        face: usize,
        /// The offending index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A vertex has a NaN or infinite coordinate (subdivision and
    /// simplification would spread it to the vertices around it). Worded
    /// and shaped as `geodesics_mesh::MeshError::NonFiniteCoordinate`.
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
    /// A triangle uses the same vertex twice.
    #[error("face {face} repeats a vertex: [{}, {}, {}]", corners[0], corners[1], corners[2])]
    RepeatedVertex {
        /// The face.
        face: usize,
        /// Its corners.
        corners: [u32; 3],
    },
    /// The result would not fit 32-bit vertex and half-edge indices.
    #[error("mesh too large for 32-bit indices: {vertices} vertices, {faces} faces")]
    TooLarge {
        /// Vertices (of the result, where known).
        vertices: usize,
        /// Faces (of the result, where known).
        faces: usize,
    },
    /// A spec names no known shape.
    #[error("unknown shape kind \"{kind}\"; expected one of: {known}")]
    UnknownShape {
        /// The kind given.
        kind: String,
        /// The known kinds, with examples.
        known: String,
    },
    /// A spec is malformed.
    #[error("invalid shape spec \"{spec}\": {reason}")]
    InvalidSpec {
        /// The spec given.
        spec: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A shape parameter is out of range.
    #[error("{shape}: {parameter} = {value} is out of range (must be {requirement})")]
    InvalidParameter {
        /// The shape kind.
        shape: &'static str,
        /// The parameter.
        parameter: &'static str,
        /// Its value.
        value: String,
        /// What it must satisfy.
        requirement: String,
    },
}
