//! Unique edges of a triangle list, found with a counting sort by the smaller
//! endpoint: linear time, flat arrays, no hashing.

use crate::ShapeError;

/// Sentinel for "no half-edge".
pub(crate) const NONE: u32 = u32::MAX;

/// Edges of a triangle list. Half-edge `3 * f + i` runs from corner `i` to
/// corner `(i + 1) % 3` of face `f`.
pub(crate) struct EdgeTopology {
    /// Each edge as `[min, max]`, sorted lexicographically: the edge order
    /// (and so the numbering of subdivision vertices) is a pure function of
    /// the input.
    pub edges: Vec<[u32; 2]>,
    /// Per face, the edge id of each of its three half-edges.
    pub face_edges: Vec<[u32; 3]>,
    /// Per edge, its one or two half-edges in increasing order (`NONE` in
    /// the second slot for a boundary edge).
    pub edge_half_edges: Vec<[u32; 2]>,
}

impl EdgeTopology {
    /// Builds the edge table, refusing out-of-range indices, faces that repeat
    /// a vertex, edges shared by more than two faces, and meshes too large
    /// for 32-bit half-edge ids.
    pub fn new(vertex_count: usize, triangles: &[[u32; 3]]) -> Result<Self, ShapeError> {
        let half_edge_count = triangles
            .len()
            .checked_mul(3)
            .filter(|&n| n < NONE as usize)
            .ok_or(ShapeError::TooLarge {
                vertices: vertex_count,
                faces: triangles.len(),
            })?;
        if vertex_count >= NONE as usize {
            return Err(ShapeError::TooLarge {
                vertices: vertex_count,
                faces: triangles.len(),
            });
        }

        // Counting sort of half-edges by their smaller endpoint.
        let mut offsets = vec![0u32; vertex_count + 1];
        for (face, t) in triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= vertex_count) {
                return Err(ShapeError::IndexOutOfRange {
                    face,
                    index,
                    vertices: vertex_count,
                });
            }
            if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
                return Err(ShapeError::RepeatedVertex { face, corners: *t });
            }
            for i in 0..3 {
                offsets[t[i].min(t[(i + 1) % 3]) as usize + 1] += 1;
            }
        }
        for v in 0..vertex_count {
            offsets[v + 1] += offsets[v];
        }
        // Each slot holds `max << 32 | half_edge`, so sorting a bucket sorts
        // by the other endpoint and then by half-edge id.
        let mut slots = vec![0u64; half_edge_count];
        let mut cursor = offsets[..vertex_count].to_vec();
        for (f, t) in triangles.iter().enumerate() {
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                let lo = a.min(b) as usize;
                let h = (3 * f + i) as u64;
                slots[cursor[lo] as usize] = (u64::from(a.max(b)) << 32) | h;
                cursor[lo] += 1;
            }
        }
        drop(cursor);

        let mut edges = Vec::with_capacity(half_edge_count / 2 + 16);
        let mut edge_half_edges = Vec::with_capacity(half_edge_count / 2 + 16);
        let mut face_edges = vec![[0u32; 3]; triangles.len()];
        for lo in 0..vertex_count {
            let bucket = &mut slots[offsets[lo] as usize..offsets[lo + 1] as usize];
            bucket.sort_unstable();
            let mut k = 0;
            while k < bucket.len() {
                let hi = bucket[k] >> 32;
                let mut end = k + 1;
                while end < bucket.len() && bucket[end] >> 32 == hi {
                    end += 1;
                }
                let (a, b) = (lo as u32, hi as u32);
                if end - k > 2 {
                    return Err(ShapeError::NonManifoldEdge {
                        a,
                        b,
                        faces: bucket[k..end]
                            .iter()
                            .map(|&s| (s as u32 / 3) as usize)
                            .collect(),
                    });
                }
                let id = edges.len() as u32;
                let h0 = bucket[k] as u32;
                let h1 = if end - k == 2 {
                    bucket[k + 1] as u32
                } else {
                    NONE
                };
                edges.push([a, b]);
                edge_half_edges.push([h0, h1]);
                for h in [h0, h1] {
                    if h != NONE {
                        face_edges[(h / 3) as usize][(h % 3) as usize] = id;
                    }
                }
                k = end;
            }
        }
        Ok(Self {
            edges,
            face_edges,
            edge_half_edges,
        })
    }

    /// Splits every face into four (corner faces first, then the middle
    /// one), numbering the vertex on edge `e` as `vertex_count + e`. Faces
    /// keep the orientation of their parent.
    pub fn split_faces(&self, triangles: &[[u32; 3]], vertex_count: u32) -> Vec<[u32; 3]> {
        let mut out = Vec::with_capacity(triangles.len() * 4);
        for (t, e) in triangles.iter().zip(&self.face_edges) {
            let [a, b, c] = *t;
            let [m0, m1, m2] = e.map(|e| vertex_count + e);
            out.push([a, m0, m2]);
            out.push([m0, b, m1]);
            out.push([m2, m1, c]);
            out.push([m0, m1, m2]);
        }
        out
    }

    /// `vertex_count` as the `u32` base of the new edge vertices, after
    /// checking that the split mesh (`vertex_count + edges` vertices, four
    /// times the faces) fits 32-bit indices.
    pub fn checked_split_base(&self, vertex_count: usize, faces: usize) -> Result<u32, ShapeError> {
        let total = vertex_count + self.edges.len();
        if total >= NONE as usize || faces.saturating_mul(12) >= NONE as usize {
            return Err(ShapeError::TooLarge {
                vertices: total,
                faces: faces.saturating_mul(4),
            });
        }
        Ok(vertex_count as u32)
    }
}

/// The corner of `triangles` opposite to half-edge `h`.
#[inline]
pub(crate) fn opposite(triangles: &[[u32; 3]], h: u32) -> u32 {
    triangles[(h / 3) as usize][((h % 3 + 2) % 3) as usize]
}
