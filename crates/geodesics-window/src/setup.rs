//! What every window solver derives from the mesh before it starts: how
//! each face is crossed, which vertices are pseudo-sources, and the pinch
//! groups (each half-edge's apex in its frame comes with the mesh:
//! [`Mesh::apex`]).

use geodesics_mesh::Mesh;

use crate::Tolerance;

/// `group_of` value of a vertex that is not a pinch copy.
pub const NO_GROUP: u32 = u32::MAX;

/// How a face is crossed, classified when the mesh is built
/// ([`Mesh::face_kind`]).
pub use geodesics_mesh::FaceKind;

/// What a window solver keeps per vertex, packed so that touching a
/// vertex (relaxing it, popping it, checking a window against it) reads
/// one cache line, not one per array.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexState {
    /// Current distance (infinite: not reached).
    pub dist: f64,
    /// Distance at which it last emitted pseudo-source windows (infinite:
    /// never).
    pub emitted: f64,
    /// Index of the source of `dist`.
    pub src: u32,
    /// Popped at least once: in the traversed area.
    pub inside: bool,
    /// A pseudo-source (see [`SolverSetup::pseudo`]).
    pub pseudo: bool,
    /// Has pinch copies (see [`SolverSetup::group_of`]).
    pub grouped: bool,
    /// Emits only into its shadow (see [`SolverSetup::shadowed`]); cleared
    /// when a solver makes the vertex a pseudo-source of its own (a source,
    /// an AVTP restart), which emits everywhere.
    pub shadowed: bool,
}

/// The per-mesh tables a solver starts from.
#[derive(Clone, Debug)]
pub struct SolverSetup {
    /// Per face: how it is crossed.
    pub kind: Vec<FaceKind>,
    /// Per vertex: a pseudo-source (boundary, saddle or flat vertex, corner
    /// of a zero-area face, pinch copy).
    pub pseudo: Vec<bool>,
    /// Per vertex: a pseudo-source only because a geodesic may pass
    /// through it (an interior flat or saddle vertex whose faces are all
    /// proper, not a pinch copy), so its windows are needed only in its
    /// shadow ([`crate::Shadow`]).
    pub shadowed: Vec<bool>,
    /// Per vertex: index into `groups` of its pinch group, or [`NO_GROUP`].
    pub group_of: Vec<u32>,
    /// The pinch groups: the fan copies of one input vertex, which share
    /// one distance.
    pub groups: Vec<Vec<u32>>,
}

impl VertexState {
    /// Whether this vertex, now at `d`, emits pseudo-source windows: it is
    /// a pseudo-source and [`Tolerance::must_emit`] says so.
    #[inline]
    pub fn must_emit(&self, d: f64, tol: &Tolerance) -> bool {
        self.pseudo && tol.must_emit(d, self.emitted)
    }
}

impl SolverSetup {
    /// Every vertex unreached, with its pseudo-source and pinch flags.
    pub fn vertex_states(&self) -> Vec<VertexState> {
        (0..self.pseudo.len())
            .map(|v| self.vertex_state(v))
            .collect()
    }

    /// Vertex `v` unreached, with its pseudo-source and pinch flags (one
    /// entry of [`SolverSetup::vertex_states`], for a solver that fills its
    /// table in parallel).
    #[inline]
    pub fn vertex_state(&self, v: usize) -> VertexState {
        VertexState {
            dist: f64::INFINITY,
            emitted: f64::INFINITY,
            src: crate::NO_SOURCE,
            inside: false,
            pseudo: self.pseudo[v],
            grouped: self.group_of[v] != NO_GROUP,
            shadowed: self.shadowed[v],
        }
    }

    /// The tables of `mesh` under the tolerance policy `tol` (which decides
    /// flat and saddle vertices).
    pub fn new(mesh: &Mesh, tol: &Tolerance) -> SolverSetup {
        let nv = mesh.vertex_count();
        let kind: Vec<FaceKind> = (0..mesh.face_count() as u32)
            .map(|f| mesh.face_kind(f))
            .collect();
        // Pseudo-sources: a geodesic may pass through these vertices.
        let mut pseudo: Vec<bool> = (0..nv as u32)
            .map(|v| mesh.is_boundary(v) || tol.is_flat_or_saddle(mesh.angle_sum(v)))
            .collect();
        let mut shadowed: Vec<bool> = (0..nv as u32)
            .map(|v| pseudo[v as usize] && !mesh.is_boundary(v))
            .collect();
        for (f, k) in kind.iter().enumerate() {
            if *k != FaceKind::Proper {
                for v in mesh.face(f as u32) {
                    pseudo[v as usize] = true;
                    shadowed[v as usize] = false;
                }
            }
        }
        let mut group_of = vec![NO_GROUP; nv];
        let mut groups: Vec<Vec<u32>> = Vec::new();
        for v in 0..nv {
            // The further fans of pinch vertices join their first fan.
            if !mesh.is_pinch_copy(v as u32) {
                continue;
            }
            let o = mesh.mesh_vertex(mesh.pinch_origin(v as u32));
            if group_of[o as usize] == NO_GROUP {
                group_of[o as usize] = groups.len() as u32;
                groups.push(vec![o]);
            }
            let g = group_of[o as usize];
            group_of[v] = g;
            groups[g as usize].push(v as u32);
        }
        for g in &groups {
            for &v in g {
                pseudo[v as usize] = true;
                shadowed[v as usize] = false;
            }
        }
        SolverSetup {
            kind,
            pseudo,
            shadowed,
            group_of,
            groups,
        }
    }
}
