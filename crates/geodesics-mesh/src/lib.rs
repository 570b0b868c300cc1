//! A validated triangle mesh with half-edge connectivity in flat index arrays,
//! built for geodesic solvers.
//!
//! Input comes as [`IndexedTriangles`] (positions plus index triples, as a file
//! stores them). [`Mesh::build`] validates it, optionally welds exactly equal
//! positions, orients every connected component consistently, links the
//! half-edges, splits non-manifold "pinch" vertices into one vertex per fan
//! (see [`Mesh::pinch_group`]), and precomputes what solvers need: half-edge
//! lengths, corner angles, vertex angle sums, boundary and saddle flags.
//! [`Mesh::summary`] reports the statistics `geodesics info` prints.
//!
//! # Example
//!
//! ```
//! use geodesics_mesh::{IndexedTriangles, Mesh, BuildOptions};
//! use glam::DVec3;
//!
//! // A regular tetrahedron: closed, genus 0.
//! let soup = IndexedTriangles {
//!     positions: vec![
//!         DVec3::new(1.0, 1.0, 1.0),
//!         DVec3::new(1.0, -1.0, -1.0),
//!         DVec3::new(-1.0, 1.0, -1.0),
//!         DVec3::new(-1.0, -1.0, 1.0),
//!     ],
//!     triangles: vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
//! };
//! let mesh = Mesh::build(soup, &BuildOptions::default()).unwrap();
//! let s = mesh.summary();
//! assert_eq!((s.vertices, s.faces, s.euler_characteristic, s.genus), (4, 4, 2, Some(0)));
//! // Every corner of a regular tetrahedron is 60 degrees.
//! assert!((mesh.angle_sum(0) - std::f64::consts::PI).abs() < 1e-12);
//! ```
//!
//! # Invariants
//!
//! - Building never panics on any input; defects are [`MeshError`]s that name
//!   the offending face, vertex or edge.
//! - Half-edge `3 * f + i` runs from corner `i` to corner `(i + 1) % 3` of face
//!   `f`; faces are counter-clockwise seen from outside of a consistently
//!   oriented component; [`Mesh::twin`] is `None` exactly on boundary.
//! - Vertices `0..input_vertex_count()` keep the numbering of the input (after
//!   welding, if asked); pinch-split copies are appended after them. With
//!   [`BuildOptions::reorder`] vertices and faces are renumbered for memory
//!   locality instead: [`Mesh::pinch_origin`] and [`Mesh::mesh_vertex`]
//!   translate vertices, [`Mesh::input_face`] and [`Mesh::mesh_face`] faces
//!   (corners keep their order within a face).

mod build;
mod error;
mod summary;
mod union_find;

pub use build::BuildOptions;
pub use error::MeshError;
pub use summary::{AnisotropyStats, MeshSummary};

/// The largest coordinate magnitude a mesh may have: beyond it, squared
/// lengths (and those of the longest geodesics unfolded in a plane) could
/// overflow or lose their precision. [`Mesh::build`] refuses larger ones
/// ([`MeshError::CoordinateTooLarge`]).
pub const MAX_COORDINATE: f64 = 1e100;

/// How far a mesh's bounding-box diagonal may exceed √F median edges
/// before [`Mesh::length_scale`] stops following it.
pub const LENGTH_SCALE_SPAN: f64 = 1000.0;

/// The smallest a mesh's bounding box may be, on its largest side (unless all its
/// vertices coincide): below it, squared edge lengths could underflow and
/// every distance come out 0. [`Mesh::build`] refuses smaller meshes
/// ([`MeshError::TooSmall`]).
pub const MIN_EXTENT: f64 = 1e-100;

use glam::{DVec2, DVec3};

/// Positions and triangles exactly as a file stores them: the input of
/// [`Mesh::build`] and the output of every reader in `geodesics-io`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct IndexedTriangles {
    /// Vertex positions, in file order (unreferenced vertices included).
    pub positions: Vec<DVec3>,
    /// Triangles as indices into `positions`.
    pub triangles: Vec<[u32; 3]>,
}

/// How a window solver crosses a face, decided by its shape when the mesh
/// is built ([`Mesh::face_kind`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceKind {
    /// Positive area: the generic one-step propagation.
    Proper,
    /// Zero area with two coincident corners (a zero-length edge): the two
    /// long edges are the same segment, so a window entering through one
    /// leaves through the other unchanged (identical frames).
    Zipper,
    /// Any other zero-area face (three coincident or collinear corners):
    /// windows stop there; its corners are pseudo-sources and distances
    /// cross it along its edges.
    Blocked,
}

/// Sentinel for "no half-edge" in the flat arrays.
pub(crate) const NONE: u32 = u32::MAX;

/// A validated, consistently oriented triangle mesh with half-edge topology.
#[derive(Clone, Debug)]
pub struct Mesh {
    positions: Vec<DVec3>,
    /// Per half-edge: what the solvers read of it, in one record (the
    /// corners of face `f` are the tails of `3f`, `3f + 1`, `3f + 2`).
    half: Vec<HalfEdge>,
    /// Per corner (indexed like half-edges, `3 * f + i`): interior angle at corner `i`.
    corner_angle: Vec<f64>,
    /// Per vertex: sum of its corner angles.
    angle_sum: Vec<f64>,
    /// Per face: whether building flipped it (`[a, b, c]` became `[a, c, b]`).
    reoriented: Vec<bool>,
    /// Per vertex: one outgoing half-edge; for a boundary vertex the one whose
    /// clockwise rotation ends on the boundary (so walking counter-clockwise
    /// with `twin(prev(h))` from it visits the whole fan). `NONE` if unreferenced.
    vertex_half_edge: Vec<u32>,
    /// Per vertex `v`: its outgoing half-edges in the order of
    /// [`Mesh::outgoing`] are `fan[fan_start[v]..fan_start[v + 1]]`.
    fan_start: Vec<u32>,
    fan: Vec<u32>,
    /// Per vertex: lies on a boundary edge.
    boundary: Vec<bool>,
    /// Per vertex: the input vertex it belongs to (itself for most vertices
    /// unless renumbered; a pinch copy's is the vertex it was split from).
    pinch_origin: Vec<u32>,
    /// Per input vertex: its vertex here (the first fan of a pinch vertex);
    /// empty when vertices keep the input's numbers.
    mesh_vertex: Vec<u32>,
    /// Per face: the input face it is; empty when faces keep the input's
    /// order.
    input_face: Vec<u32>,
    /// Per input face: its face here; empty likewise.
    mesh_face: Vec<u32>,
    /// Per vertex: the next fan of the same pinch vertex (a ring), `NONE` if manifold.
    pinch_ring: Vec<u32>,
    /// Per vertex: index of its connected component (edge-connected), `NONE` if unreferenced.
    component: Vec<u32>,
    input_vertex_count: usize,
    /// Mean half-edge length.
    average_edge_length: f64,
    /// What tolerances scale with (see [`Mesh::length_scale`]).
    length_scale: f64,
    /// Per face: how window solvers cross it.
    face_kind: Vec<FaceKind>,
    summary: MeshSummary,
}

/// What window solvers read of one half-edge whenever they touch it
/// (crossing its face, queueing the list beyond it, walking a fan), packed
/// so that it costs one cache line, not four arrays' worth. Records are
/// 32 bytes, aligned so that none straddles two lines.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
struct HalfEdge {
    /// The opposite corner in the half-edge's frame.
    apex: DVec2,
    /// Its length.
    length: f64,
    /// The opposite half-edge, or `NONE` on boundary.
    twin: u32,
    /// Its start vertex (the face's corner).
    tail: u32,
}

const _: () = assert!(std::mem::size_of::<HalfEdge>() == 32);

impl Mesh {
    /// Number of vertices, including pinch-split copies.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of vertices of the input (after welding): results are reported
    /// for these, in this order.
    pub fn input_vertex_count(&self) -> usize {
        self.input_vertex_count
    }

    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.half.len() / 3
    }

    /// Number of half-edges (`3 * face_count()`).
    pub fn half_edge_count(&self) -> usize {
        self.half.len()
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Position of vertex `v`.
    #[inline]
    pub fn position(&self, v: u32) -> DVec3 {
        self.positions[v as usize]
    }

    /// Faces (consistently oriented, pinch vertices replaced by their fan
    /// copies), in face order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = [u32; 3]> + '_ {
        self.half
            .chunks_exact(3)
            .map(|e| [e[0].tail, e[1].tail, e[2].tail])
    }

    /// Corners of face `f`.
    #[inline]
    pub fn face(&self, f: u32) -> [u32; 3] {
        let h = 3 * f as usize;
        [
            self.half[h].tail,
            self.half[h + 1].tail,
            self.half[h + 2].tail,
        ]
    }

    /// How window solvers cross face `f`: [`FaceKind::Proper`] when every
    /// edge has positive length and every apex lies strictly above its
    /// edge, [`FaceKind::Zipper`] with exactly one zero-length edge,
    /// [`FaceKind::Blocked`] otherwise.
    #[inline]
    pub fn face_kind(&self, f: u32) -> FaceKind {
        self.face_kind[f as usize]
    }

    /// Where a window entering a [`FaceKind::Zipper`] face along `h`
    /// leaves it: the face's other edge of positive length (the two long
    /// edges are one segment with identical frames, so the window crosses
    /// unchanged). `None` when `h` is the zero-length edge.
    #[inline]
    pub fn zipper_exit(&self, h: u32) -> Option<u32> {
        if self.length(h) > 0.0 {
            let n = Self::next(h);
            Some(if self.length(n) > 0.0 {
                n
            } else {
                Self::prev(h)
            })
        } else {
            None
        }
    }

    /// Whether building flipped face `f` to orient its component
    /// consistently: the input's corners `[a, b, c]` are then `[a, c, b]`.
    #[inline]
    pub fn is_reoriented(&self, f: u32) -> bool {
        self.reoriented[f as usize]
    }

    /// Face of half-edge `h`.
    #[inline]
    pub fn face_of(h: u32) -> u32 {
        h / 3
    }

    /// Next half-edge in the same face.
    #[inline]
    pub fn next(h: u32) -> u32 {
        if h % 3 == 2 { h - 2 } else { h + 1 }
    }

    /// Previous half-edge in the same face.
    #[inline]
    pub fn prev(h: u32) -> u32 {
        if h.is_multiple_of(3) { h + 2 } else { h - 1 }
    }

    /// Vertex at the start of half-edge `h`.
    #[inline]
    pub fn tail(&self, h: u32) -> u32 {
        self.half[h as usize].tail
    }

    /// Vertex at the end of half-edge `h`.
    #[inline]
    pub fn head(&self, h: u32) -> u32 {
        self.tail(Self::next(h))
    }

    /// Vertex of the face of `h` opposite to `h`.
    #[inline]
    pub fn opposite_vertex(&self, h: u32) -> u32 {
        self.tail(Self::prev(h))
    }

    /// Asks the processor to start loading the records of the faces
    /// around `v` into cache: a hint for solvers that know which vertex
    /// they will visit next (a fan's faces lie far apart in memory, and
    /// walking it loads them one after another). No effect on results.
    #[inline]
    pub fn prefetch_fan(&self, v: u32) {
        if (v as usize) < self.vertex_count() {
            for &h in self.fan(v) {
                self.prefetch_face(Self::face_of(h));
            }
        }
    }

    /// Asks the processor to start loading the per-vertex records of `v`
    /// (where its fan starts, its angle sum): a hint for solvers that know
    /// which vertex they will visit soon, before its fan can be read (see
    /// [`Mesh::prefetch_fan`]). No effect on results.
    #[inline]
    pub fn prefetch_vertex(&self, v: u32) {
        prefetch(&self.fan_start, v as usize);
        prefetch(&self.angle_sum, v as usize);
    }

    /// Asks the processor to start loading the entries of `v`'s fan table
    /// (reading where its fan starts): a hint for solvers that will visit
    /// `v` many steps later, so that [`Mesh::prefetch_fan`], shortly before
    /// the visit, finds the fan in cache instead of waiting for it. No
    /// effect on results; nothing for a vertex out of range.
    #[inline]
    pub fn prefetch_fan_table(&self, v: u32) {
        let v = v as usize;
        if let (Some(&start), Some(&end)) = (self.fan_start.get(v), self.fan_start.get(v + 1)) {
            // A usual fan's entries lie on one or two cache lines (16
            // entries each): ask for the first and the last.
            prefetch(&self.fan, start as usize);
            prefetch(&self.fan, (end as usize).saturating_sub(1));
        }
    }

    /// Asks the processor to start loading the records of face `f` (see
    /// [`Mesh::prefetch_fan`]).
    #[inline]
    pub fn prefetch_face(&self, f: u32) {
        let i = 3 * f as usize;
        prefetch(&self.half, i);
        prefetch(&self.half, i + 2);
        prefetch(&self.corner_angle, i);
    }

    /// The half-edge on the other side of `h`, `None` on boundary.
    #[inline]
    pub fn twin(&self, h: u32) -> Option<u32> {
        let t = self.half[h as usize].twin;
        (t != NONE).then_some(t)
    }

    /// Length of half-edge `h`.
    #[inline]
    pub fn length(&self, h: u32) -> f64 {
        self.half[h as usize].length
    }

    /// The corner of `h`'s face opposite `h`, in the frame of `h`: tail at
    /// the origin, head at `(length(h), 0)`, the face above (`y ≥ 0`). A
    /// zero-length half-edge gives the origin. This is the triangle every
    /// window solver unfolds a face into: [`Mesh::frame_coords`] of the
    /// opposite vertex, computed once when the mesh is built.
    #[inline]
    pub fn apex(&self, h: u32) -> DVec2 {
        self.half[h as usize].apex
    }

    /// Coordinates of `q` in the frame of half-edge `h` (tail at the
    /// origin, head on +x, the face of `h` above), for `q` in the closed
    /// face of `h` (so `y ≥ 0`): the frame every window solver puts windows
    /// in. A zero-length half-edge maps everything to the origin.
    pub fn frame_coords(&self, h: u32, q: DVec3) -> DVec2 {
        frame_coords_of(
            self.position(self.tail(h)),
            self.position(self.head(h)),
            self.length(h),
            q,
        )
    }

    /// Interior angle of the face of `h` at the tail of `h` (corner `h`).
    #[inline]
    pub fn corner_angle(&self, h: u32) -> f64 {
        self.corner_angle[h as usize]
    }

    /// Sum of the corner angles at vertex `v`.
    #[inline]
    pub fn angle_sum(&self, v: u32) -> f64 {
        self.angle_sum[v as usize]
    }

    /// Whether `v` lies on a boundary edge.
    #[inline]
    pub fn is_boundary(&self, v: u32) -> bool {
        self.boundary[v as usize]
    }

    /// Whether `v` is a saddle: interior with angle sum above 2π.
    #[inline]
    pub fn is_saddle(&self, v: u32) -> bool {
        !self.boundary[v as usize] && self.angle_sum[v as usize] > std::f64::consts::TAU
    }

    /// Whether `v` belongs to at least one face.
    #[inline]
    pub fn is_referenced(&self, v: u32) -> bool {
        self.vertex_half_edge[v as usize] != NONE
    }

    /// The input vertex that `v` belongs to: `v` itself unless `v` is a copy
    /// made when splitting a pinch vertex into its fans, or the mesh was
    /// renumbered ([`BuildOptions::reorder`]).
    #[inline]
    pub fn pinch_origin(&self, v: u32) -> u32 {
        self.pinch_origin[v as usize]
    }

    /// The vertex of this mesh that input vertex `input` became (for a
    /// pinch vertex, its first fan; the others are [`Mesh::pinch_fans`]):
    /// `input` itself unless the mesh was renumbered.
    /// `input < input_vertex_count()`.
    ///
    /// ```
    /// use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
    /// use glam::DVec3;
    ///
    /// let soup = IndexedTriangles {
    ///     positions: vec![
    ///         DVec3::new(1.0, 1.0, 1.0),
    ///         DVec3::new(1.0, -1.0, -1.0),
    ///         DVec3::new(-1.0, 1.0, -1.0),
    ///         DVec3::new(-1.0, -1.0, 1.0),
    ///     ],
    ///     triangles: vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
    /// };
    /// let options = BuildOptions { reorder: true, ..BuildOptions::default() };
    /// let mesh = Mesh::build(soup.clone(), &options).unwrap();
    /// for u in 0..4 {
    ///     let v = mesh.mesh_vertex(u);
    ///     assert_eq!(mesh.pinch_origin(v), u);
    ///     assert_eq!(mesh.position(v), soup.positions[u as usize]);
    /// }
    /// // Faces too, corners in the same order (here in input numbers).
    /// let f = mesh.mesh_face(1);
    /// assert_eq!(mesh.face(f).map(|v| mesh.pinch_origin(v)), [0, 3, 1]);
    /// // Back in the input's numbering, whatever the mesh's own.
    /// assert_eq!(mesh.to_indexed_triangles(), soup);
    /// ```
    #[inline]
    pub fn mesh_vertex(&self, input: u32) -> u32 {
        renumbered(&self.mesh_vertex, input)
    }

    /// The input face that face `f` of this mesh is (its corners possibly
    /// flipped, see [`Mesh::is_reoriented`]): `f` itself unless the mesh was
    /// renumbered.
    #[inline]
    pub fn input_face(&self, f: u32) -> u32 {
        renumbered(&self.input_face, f)
    }

    /// The face of this mesh that input face `input` became: `input`
    /// itself unless the mesh was renumbered. `input < face_count()`.
    #[inline]
    pub fn mesh_face(&self, input: u32) -> u32 {
        renumbered(&self.mesh_face, input)
    }

    /// Whether `v` is a further fan of a pinch vertex: one of its copies
    /// other than the fan [`Mesh::mesh_vertex`] gives.
    #[inline]
    pub fn is_pinch_copy(&self, v: u32) -> bool {
        self.is_pinch(v) && self.mesh_vertex(self.pinch_origin(v)) != v
    }

    /// Whether `v` is one fan of a non-manifold (pinch) vertex. The fans of one
    /// pinch vertex are separate vertices of this mesh at the same position;
    /// a geodesic may pass from one to another, so solvers give them one
    /// distance and treat each as a point source (like a saddle).
    #[inline]
    pub fn is_pinch(&self, v: u32) -> bool {
        self.pinch_ring[v as usize] != NONE
    }

    /// The other fans of the pinch vertex `v` belongs to, without allocating
    /// (empty for a manifold vertex).
    pub fn pinch_fans(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let first = self.pinch_ring[v as usize];
        std::iter::successors((first != NONE).then_some(first), move |&u| {
            let n = self.pinch_ring[u as usize];
            (n != v).then_some(n)
        })
    }

    /// The other fans of the pinch vertex `v` belongs to, sorted (empty for a
    /// manifold vertex).
    pub fn pinch_group(&self, v: u32) -> Vec<u32> {
        let mut group: Vec<u32> = self.pinch_fans(v).collect();
        group.sort_unstable();
        group
    }

    /// Connected component (by shared edges) of vertex `v`, `None` if unreferenced.
    pub fn component(&self, v: u32) -> Option<u32> {
        let c = self.component[v as usize];
        (c != NONE).then_some(c)
    }

    /// One outgoing half-edge of `v`, `None` if `v` is unreferenced. For a
    /// boundary vertex it is the first of its fan in counter-clockwise order.
    pub fn vertex_half_edge(&self, v: u32) -> Option<u32> {
        let h = self.vertex_half_edge[v as usize];
        (h != NONE).then_some(h)
    }

    /// The outgoing half-edges of `v` as a slice, in the order of
    /// [`Mesh::outgoing`] (empty if `v` is unreferenced).
    ///
    /// ```
    /// use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
    /// use glam::DVec3;
    ///
    /// // A square split into two triangles: the corner shared by both.
    /// let square = IndexedTriangles {
    ///     positions: vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
    ///     triangles: vec![[0, 1, 2], [0, 2, 3]],
    /// };
    /// let mesh = Mesh::build(square, &BuildOptions::default())?;
    /// assert_eq!(mesh.fan(0).len(), 2);
    /// assert!(mesh.fan(0).iter().copied().eq(mesh.outgoing(0)));
    /// # Ok::<(), geodesics_mesh::MeshError>(())
    /// ```
    #[inline]
    pub fn fan(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.fan[self.fan_start[v] as usize..self.fan_start[v + 1] as usize]
    }

    /// Outgoing half-edges of `v` in counter-clockwise order around `v`.
    pub fn outgoing(&self, v: u32) -> OutgoingHalfEdges<'_> {
        let start = self.vertex_half_edge[v as usize];
        OutgoingHalfEdges {
            mesh: self,
            start,
            current: start,
        }
    }

    /// Statistics computed while building (what `geodesics info` prints).
    pub fn summary(&self) -> &MeshSummary {
        &self.summary
    }

    /// Length of the bounding-box diagonal.
    pub fn bbox_diagonal(&self) -> f64 {
        self.summary.bbox_diagonal
    }

    /// The length the solvers' tolerances scale with: the bounding-box
    /// diagonal, but at most [`LENGTH_SCALE_SPAN`] · √F median edges.
    ///
    /// A surface of `F` faces whose edges are about `e` long spans about
    /// `e·√F` (a long strip more, by a factor far below the cap). Only a
    /// few vertices far out of proportion with the rest (a corrupt
    /// coordinate, say 1e22 on a 10 mm part) make the box larger than the
    /// cap; a rounding margin of their scale would exceed the rest of the
    /// mesh, leave every window standing and the solve would never end.
    /// On every other mesh this is the diagonal itself.
    ///
    /// ```
    /// use geodesics_mesh::{BuildOptions, IndexedTriangles, Mesh};
    /// use glam::DVec3;
    ///
    /// // Two triangles; the second reaches out to (far, far, 0).
    /// let flat = |far: f64| IndexedTriangles {
    ///     positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(far, far, 0.0)],
    ///     triangles: vec![[0, 1, 2], [1, 3, 2]],
    /// };
    /// let mesh = Mesh::build(flat(1.0), &BuildOptions::default())?;
    /// assert_eq!(mesh.length_scale(), mesh.bbox_diagonal());
    /// let outlier = Mesh::build(flat(1e22), &BuildOptions::default())?;
    /// assert!(outlier.length_scale() < 1e-15 * outlier.bbox_diagonal());
    /// # Ok::<(), geodesics_mesh::MeshError>(())
    /// ```
    pub fn length_scale(&self) -> f64 {
        self.length_scale
    }

    /// Average half-edge length over all faces (computed once, when
    /// building).
    pub fn average_edge_length(&self) -> f64 {
        self.average_edge_length
    }

    /// The mesh as input-numbered triangles (after welding and reorientation,
    /// pinch copies mapped back to their input vertex): what writers of
    /// colored meshes need.
    pub fn to_indexed_triangles(&self) -> IndexedTriangles {
        let input = self.input_vertex_count as u32;
        IndexedTriangles {
            positions: (0..input)
                .map(|u| self.position(self.mesh_vertex(u)))
                .collect(),
            triangles: (0..self.face_count() as u32)
                .map(|u| {
                    self.face(self.mesh_face(u))
                        .map(|v| self.pinch_origin[v as usize])
                })
                .collect(),
        }
    }

    /// Folds per-vertex values of this mesh (pinch copies included) back onto
    /// the input vertices: each input vertex gets the minimum over its copies.
    pub fn fold_to_input<T: Copy + PartialOrd>(&self, values: &[T]) -> Vec<T> {
        let input = self.input_vertex_count as u32;
        let mut out: Vec<T> = (0..input)
            .map(|u| values[self.mesh_vertex(u) as usize])
            .collect();
        for (&value, &origin) in values.iter().zip(&self.pinch_origin) {
            if value < out[origin as usize] {
                out[origin as usize] = value;
            }
        }
        out
    }
}

/// `map[i]`, or `i` itself when the map is empty (numbers kept).
#[inline]
fn renumbered(map: &[u32], i: u32) -> u32 {
    if map.is_empty() { i } else { map[i as usize] }
}

/// Iterator over the outgoing half-edges of a vertex, counter-clockwise.
pub struct OutgoingHalfEdges<'a> {
    mesh: &'a Mesh,
    start: u32,
    current: u32,
}

impl Iterator for OutgoingHalfEdges<'_> {
    type Item = u32;

    fn next(&mut self) -> Option<u32> {
        if self.current == NONE {
            return None;
        }
        let h = self.current;
        // Counter-clockwise around the tail: the incoming edge of this face,
        // then across it.
        let incoming = Mesh::prev(h);
        let t = self.mesh.half[incoming as usize].twin;
        self.current = if t == self.start { NONE } else { t };
        Some(h)
    }
}

/// [`Mesh::frame_coords`] for the half-edge from `tail` to `head` of length
/// `length`.
#[inline]
pub(crate) fn frame_coords_of(tail: DVec3, head: DVec3, length: f64, q: DVec3) -> DVec2 {
    if length <= 0.0 {
        return DVec2::ZERO;
    }
    let e = head - tail;
    let r = q - tail;
    DVec2::new(r.dot(e) / length, e.cross(r).length() / length)
}

/// Asks the processor to start loading `items[i]` into cache (nothing if
/// `i` is out of range): a hint, no effect on results. Solvers use it for
/// their own per-face and per-vertex tables. The workspace's one `unsafe`
/// block: stable Rust has no safe prefetch.
#[inline]
#[allow(unsafe_code)]
pub fn prefetch<T>(items: &[T], i: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(item) = items.get(i) {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: a prefetch reads nothing the program sees and never
        // faults; the pointer is to a live element anyway.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(item).cast::<i8>()) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (items, i);
}
