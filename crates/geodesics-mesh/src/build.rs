//! Validation and construction of [`Mesh`] from [`IndexedTriangles`].

use std::collections::HashMap;

use glam::DVec3;

use crate::summary::{AnisotropyStats, MeshSummary};
use crate::union_find::UnionFind;
use crate::{IndexedTriangles, Mesh, MeshError, NONE};

/// How to build a [`Mesh`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BuildOptions {
    /// Merge vertices whose positions are exactly equal (numbered in order of
    /// first appearance) and drop the faces that then repeat a vertex.
    pub weld: bool,
}

impl Mesh {
    /// Validates `input` and builds the half-edge mesh.
    ///
    /// Refused with a [`MeshError`]: no triangles, an index out of range, a
    /// non-finite coordinate, a face repeating a vertex (unless welding
    /// created it, then the face is dropped), an edge shared by more than two
    /// faces, a non-orientable component.
    ///
    /// Handled: unreferenced vertices (kept; solvers leave them unreachable),
    /// pinch vertices (split into one vertex per fan, see
    /// [`Mesh::pinch_group`]), zero-area faces (kept and counted),
    /// inconsistently oriented faces (flipped), duplicate positions (counted;
    /// merged with [`BuildOptions::weld`]).
    pub fn build(input: IndexedTriangles, options: &BuildOptions) -> Result<Mesh, MeshError> {
        let IndexedTriangles {
            mut positions,
            triangles,
        } = input;
        if triangles.is_empty() {
            return Err(MeshError::Empty {
                vertices: positions.len(),
            });
        }
        let max_faces = (u32::MAX / 3 - 1) as usize;
        if triangles.len() > max_faces || positions.len() >= u32::MAX as usize {
            return Err(MeshError::TooLarge {
                faces: triangles.len(),
                max: max_faces,
            });
        }
        for (vertex, p) in positions.iter().enumerate() {
            if !p.is_finite() {
                return Err(MeshError::NonFiniteCoordinate {
                    vertex,
                    x: p.x,
                    y: p.y,
                    z: p.z,
                });
            }
        }
        for (face, t) in triangles.iter().enumerate() {
            for &index in t {
                if index as usize >= positions.len() {
                    return Err(MeshError::IndexOutOfRange {
                        face,
                        index,
                        vertices: positions.len(),
                    });
                }
            }
        }

        let mut duplicate_positions = positions.len() - distinct_position_count(&positions);
        let mut faces = triangles;
        let mut welded_collapsed_faces = 0;
        let mut welded_vertices = 0;
        if options.weld {
            let (welded, remap) = weld_positions(&positions);
            positions = welded;
            let before = faces.len();
            faces = faces
                .into_iter()
                .map(|t| t.map(|v| remap[v as usize]))
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
                .collect();
            welded_collapsed_faces = before - faces.len();
            welded_vertices = duplicate_positions;
            duplicate_positions = 0;
            if faces.is_empty() {
                return Err(MeshError::Empty {
                    vertices: positions.len(),
                });
            }
        }
        for (face, t) in faces.iter().enumerate() {
            if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
                return Err(MeshError::RepeatedVertex { face, corners: *t });
            }
        }

        let edges = EdgeTable::new(&faces, positions.len())?;
        let flipped = orient_components(&mut faces, &edges)?;
        let reoriented_faces = flipped.iter().filter(|&&f| f).count();
        let twin = link_twins(&edges, &flipped);

        let input_vertex_count = positions.len();
        let (pinch_origin, nonmanifold_vertices) =
            split_pinch_vertices(&mut faces, &twin, &mut positions);

        let mut mesh = Mesh {
            length: Vec::new(),
            corner_angle: Vec::new(),
            angle_sum: Vec::new(),
            vertex_half_edge: Vec::new(),
            boundary: Vec::new(),
            component: Vec::new(),
            positions,
            faces,
            twin,
            pinch_ring: pinch_rings(&pinch_origin),
            pinch_origin,
            input_vertex_count,
            summary: MeshSummary::default(),
        };
        mesh.compute_geometry();
        mesh.compute_vertex_topology();
        mesh.summary = mesh.compute_summary(
            edges.edge_count,
            nonmanifold_vertices,
            duplicate_positions,
            [welded_vertices, welded_collapsed_faces],
            reoriented_faces,
        );
        Ok(mesh)
    }

    fn compute_geometry(&mut self) {
        let n = self.faces.len() * 3;
        self.length = Vec::with_capacity(n);
        self.corner_angle = Vec::with_capacity(n);
        for f in &self.faces {
            let p = f.map(|v| self.positions[v as usize]);
            for i in 0..3 {
                self.length.push(p[i].distance(p[(i + 1) % 3]));
            }
            for i in 0..3 {
                let a = p[(i + 1) % 3] - p[i];
                let b = p[(i + 2) % 3] - p[i];
                self.corner_angle.push(angle_between(a, b));
            }
        }
        self.angle_sum = vec![0.0; self.positions.len()];
        for (h, &angle) in self.corner_angle.iter().enumerate() {
            let v = self.faces[h / 3][h % 3];
            self.angle_sum[v as usize] += angle;
        }
    }

    fn compute_vertex_topology(&mut self) {
        let nv = self.positions.len();
        self.vertex_half_edge = vec![NONE; nv];
        self.boundary = vec![false; nv];
        for h in 0..self.twin.len() as u32 {
            let v = self.tail(h) as usize;
            if self.twin[h as usize] == NONE {
                // A boundary edge leaving v: the clockwise-most outgoing edge
                // of v's (single, after pinch splitting) fan.
                self.boundary[v] = true;
                self.vertex_half_edge[v] = h;
            } else if self.vertex_half_edge[v] == NONE {
                self.vertex_half_edge[v] = h;
            }
        }
        // Components by shared edges (faces), then per vertex.
        let nf = self.faces.len();
        let mut uf = UnionFind::new(nf);
        for h in 0..self.twin.len() {
            let t = self.twin[h];
            if t != NONE {
                uf.union((h / 3) as u32, t / 3);
            }
        }
        let mut label = vec![NONE; nf];
        let mut next_label = 0;
        self.component = vec![NONE; nv];
        for f in 0..nf {
            let root = uf.find(f as u32) as usize;
            if label[root] == NONE {
                label[root] = next_label;
                next_label += 1;
            }
            for &v in &self.faces[f] {
                self.component[v as usize] = label[root];
            }
        }
    }

    fn compute_summary(
        &self,
        edges: usize,
        nonmanifold_vertices: usize,
        duplicate_positions: usize,
        [welded_vertices, welded_collapsed_faces]: [usize; 2],
        reoriented_faces: usize,
    ) -> MeshSummary {
        let nin = self.input_vertex_count;
        // Components of referenced input vertices: pinch copies join their origin.
        let mut uf = UnionFind::new(nin);
        let mut referenced = vec![false; nin];
        for f in &self.faces {
            let o = f.map(|v| self.pinch_origin[v as usize]);
            for &v in &o {
                referenced[v as usize] = true;
            }
            uf.union(o[0], o[1]);
            uf.union(o[1], o[2]);
        }
        let used = referenced.iter().filter(|&&r| r).count();
        let components = (0..nin as u32)
            .filter(|&v| referenced[v as usize] && uf.find(v) == v)
            .count();

        // Boundary loops: components of the graph of boundary edges.
        let mut buf = UnionFind::new(nin);
        let mut on_boundary = vec![false; nin];
        for h in 0..self.twin.len() as u32 {
            if self.twin[h as usize] == NONE {
                let a = self.pinch_origin(self.tail(h));
                let b = self.pinch_origin(self.head(h));
                on_boundary[a as usize] = true;
                on_boundary[b as usize] = true;
                buf.union(a, b);
            }
        }
        let boundary_loops = (0..nin as u32)
            .filter(|&v| on_boundary[v as usize] && buf.find(v) == v)
            .count();
        let boundary_vertices = on_boundary.iter().filter(|&&b| b).count();

        let euler_characteristic = used as i64 - edges as i64 + self.faces.len() as i64;
        let twice_genus = 2 * components as i64 - euler_characteristic - boundary_loops as i64;
        let genus = (nonmanifold_vertices == 0 && twice_genus >= 0 && twice_genus % 2 == 0)
            .then_some(twice_genus / 2);

        let saddle_vertices = (0..nin as u32)
            .filter(|&v| self.is_referenced(v) && self.is_saddle(v))
            .count();

        let mut zero_area_faces = 0;
        let mut quality = Vec::with_capacity(self.faces.len());
        for (f, corners) in self.faces.iter().enumerate() {
            let p = corners.map(|v| self.positions[v as usize]);
            let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
            if area == 0.0 {
                zero_area_faces += 1;
                continue;
            }
            let l = [0, 1, 2].map(|i| self.length[3 * f + i]);
            let half_perimeter = 0.5 * (l[0] + l[1] + l[2]);
            let longest = l[0].max(l[1]).max(l[2]);
            quality.push(half_perimeter * longest / (2.0 * 3f64.sqrt() * area));
        }
        let anisotropy = anisotropy_stats(&mut quality);

        let (lo, hi) = self.positions[..nin]
            .iter()
            .enumerate()
            .filter(|&(v, _)| referenced[v])
            .fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), (_, &p)| (lo.min(p), hi.max(p)),
            );

        MeshSummary {
            vertices: nin,
            faces: self.faces.len(),
            edges,
            components,
            boundary_loops,
            euler_characteristic,
            genus,
            saddle_vertices,
            boundary_vertices,
            nonmanifold_vertices,
            zero_area_faces,
            duplicate_positions,
            unreferenced_vertices: nin - used,
            welded_vertices,
            welded_collapsed_faces,
            reoriented_faces,
            anisotropy,
            bbox_diagonal: (hi - lo).length(),
            bbox_min: lo.to_array(),
            bbox_max: hi.to_array(),
        }
    }
}

/// Angle between two vectors, accurate for tiny and near-straight angles.
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

fn anisotropy_stats(quality: &mut [f64]) -> AnisotropyStats {
    if quality.is_empty() {
        return AnisotropyStats::default();
    }
    quality.sort_unstable_by(f64::total_cmp);
    let n = quality.len();
    let rank = |q: f64| quality[((q * (n - 1) as f64).round() as usize).min(n - 1)];
    AnisotropyStats {
        mean: quality.iter().sum::<f64>() / n as f64,
        median: rank(0.5),
        p99: rank(0.99),
        max: quality[n - 1],
    }
}

fn position_key(p: DVec3) -> [u64; 3] {
    // +0.0 and -0.0 are the same point.
    p.to_array().map(|c| if c == 0.0 { 0 } else { c.to_bits() })
}

fn distinct_position_count(positions: &[DVec3]) -> usize {
    let mut keys: Vec<[u64; 3]> = positions.iter().map(|&p| position_key(p)).collect();
    keys.sort_unstable();
    keys.dedup();
    keys.len()
}

/// Merges exactly equal positions; new indices in order of first appearance.
fn weld_positions(positions: &[DVec3]) -> (Vec<DVec3>, Vec<u32>) {
    let mut first: HashMap<[u64; 3], u32> = HashMap::with_capacity(positions.len());
    let mut welded = Vec::new();
    let remap = positions
        .iter()
        .map(|&p| {
            *first.entry(position_key(p)).or_insert_with(|| {
                welded.push(p);
                (welded.len() - 1) as u32
            })
        })
        .collect();
    (welded, remap)
}

/// Undirected edges: for every half-edge slot `3f+i`, the edge id, and per
/// edge the (at most two) half-edges on it.
struct EdgeTable {
    /// Per half-edge slot: its undirected edge.
    edge_of: Vec<u32>,
    /// Per edge: the two half-edge slots on it (second `NONE` on boundary).
    sides: Vec<[u32; 2]>,
    edge_count: usize,
}

impl EdgeTable {
    /// Groups half-edge slots by undirected vertex pair with a counting
    /// sort on the smaller vertex (linear time; buckets hold a vertex's few
    /// edges), then by the larger vertex inside each bucket.
    fn new(faces: &[[u32; 3]], vertex_count: usize) -> Result<Self, MeshError> {
        let n = faces.len() * 3;
        let ends = |h: usize| {
            let t = faces[h / 3];
            let (a, b) = (t[h % 3], t[(h + 1) % 3]);
            (a.min(b), a.max(b))
        };
        let mut start = vec![0u32; vertex_count + 1];
        for h in 0..n {
            start[ends(h).0 as usize + 1] += 1;
        }
        for v in 0..vertex_count {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut bucketed = vec![0u32; n];
        for h in 0..n {
            let lo = ends(h).0 as usize;
            bucketed[fill[lo] as usize] = h as u32;
            fill[lo] += 1;
        }
        let mut edge_of = vec![NONE; n];
        let mut sides = Vec::with_capacity(n / 2 + 1);
        for v in 0..vertex_count {
            let bucket = &mut bucketed[start[v] as usize..start[v + 1] as usize];
            bucket.sort_unstable_by_key(|&h| (ends(h as usize).1, h));
            let mut i = 0;
            while i < bucket.len() {
                let hi = ends(bucket[i] as usize).1;
                let mut j = i + 1;
                while j < bucket.len() && ends(bucket[j] as usize).1 == hi {
                    j += 1;
                }
                if j - i > 2 {
                    let mut faces_on: Vec<usize> =
                        bucket[i..j].iter().map(|&h| h as usize / 3).collect();
                    faces_on.sort_unstable();
                    return Err(MeshError::NonManifoldEdge {
                        a: v as u32,
                        b: hi,
                        faces: faces_on,
                    });
                }
                let e = sides.len() as u32;
                for &h in &bucket[i..j] {
                    edge_of[h as usize] = e;
                }
                sides.push([bucket[i], if j - i == 2 { bucket[i + 1] } else { NONE }]);
                i = j;
            }
        }
        let edge_count = sides.len();
        Ok(Self {
            edge_of,
            sides,
            edge_count,
        })
    }
}

/// Flips faces so that every edge-connected component is consistently
/// oriented (the first face of each component keeps its orientation).
/// Returns which faces were flipped.
fn orient_components(faces: &mut [[u32; 3]], edges: &EdgeTable) -> Result<Vec<bool>, MeshError> {
    let nf = faces.len();
    let mut flipped = vec![false; nf];
    let mut visited = vec![false; nf];
    let mut stack = Vec::new();
    // Direction (tail) of half-edge slot h as stored in the input.
    let tail = |faces: &[[u32; 3]], h: u32| faces[(h / 3) as usize][(h % 3) as usize];
    for seed in 0..nf {
        if visited[seed] {
            continue;
        }
        visited[seed] = true;
        stack.push(seed as u32);
        while let Some(f) = stack.pop() {
            for i in 0..3 {
                let h = 3 * f + i;
                let [s0, s1] = edges.sides[edges.edge_of[h as usize] as usize];
                let other = if s0 == h { s1 } else { s0 };
                if other == NONE {
                    continue;
                }
                let g = other / 3;
                // Consistent iff the two faces run the edge in opposite directions
                // (after applying their flips).
                let same_direction_raw = tail(faces, h) == tail(faces, other);
                let need_flip_g = flipped[f as usize] ^ same_direction_raw;
                if !visited[g as usize] {
                    visited[g as usize] = true;
                    flipped[g as usize] = need_flip_g;
                    stack.push(g);
                } else if flipped[g as usize] != need_flip_g {
                    let a = tail(faces, h);
                    let b = faces[f as usize][((i + 1) % 3) as usize];
                    return Err(MeshError::NonOrientable {
                        face: f as usize,
                        neighbour: g as usize,
                        a,
                        b,
                    });
                }
            }
        }
    }
    for (face, &flip) in faces.iter_mut().zip(&flipped) {
        if flip {
            face.swap(1, 2);
        }
    }
    Ok(flipped)
}

/// Twin half-edges after orientation. Flipping face `[a,b,c]` to `[a,c,b]`
/// moves the edge in slot `i` to slot `2 - i`.
fn link_twins(edges: &EdgeTable, flipped: &[bool]) -> Vec<u32> {
    let current_slot = |h: u32| {
        let f = h / 3;
        if flipped[f as usize] {
            3 * f + 2 - h % 3
        } else {
            h
        }
    };
    let mut twin = vec![NONE; edges.edge_of.len()];
    for &[s0, s1] in &edges.sides {
        if s1 != NONE {
            let (h0, h1) = (current_slot(s0), current_slot(s1));
            twin[h0 as usize] = h1;
            twin[h1 as usize] = h0;
        }
    }
    twin
}

/// Links the fans of each pinch vertex into a ring (origin -> copies -> origin).
fn pinch_rings(origin: &[u32]) -> Vec<u32> {
    let mut ring = vec![NONE; origin.len()];
    // Copies are appended in increasing index; chain each after the last one seen.
    let mut last: std::collections::HashMap<u32, u32> = std::collections::HashMap::new();
    for (v, &o) in origin.iter().enumerate() {
        if o as usize != v {
            let prev = last.insert(o, v as u32).unwrap_or(o);
            ring[prev as usize] = v as u32;
            ring[v] = o;
        }
    }
    ring
}

/// Groups the corners at each vertex into fans (corners linked across interior
/// edges). A vertex with several fans is a pinch vertex: its first fan keeps
/// the index, each further fan becomes a new vertex at the same position.
/// Returns each vertex's origin and the number of pinch vertices.
fn split_pinch_vertices(
    faces: &mut [[u32; 3]],
    twin: &[u32],
    positions: &mut Vec<DVec3>,
) -> (Vec<u32>, usize) {
    let n = faces.len() * 3;
    let mut fans = UnionFind::new(n);
    for (h, &t) in twin.iter().enumerate() {
        if t != NONE {
            // Corner h is at tail(h); across the edge, tail(h) is the head of
            // t, i.e. the corner at next(t).
            fans.union(h as u32, Mesh::next(t));
        }
    }
    let nv = positions.len();
    let mut fan_of_vertex = vec![NONE; nv];
    let mut new_index: HashMap<u32, u32> = HashMap::new();
    let mut origin: Vec<u32> = (0..nv as u32).collect();
    let mut pinched = vec![false; nv];
    for h in 0..n {
        let v = faces[h / 3][h % 3];
        let root = fans.find(h as u32);
        let first = fan_of_vertex[v as usize];
        if first == NONE {
            fan_of_vertex[v as usize] = root;
        } else if first != root {
            pinched[v as usize] = true;
            let copy = *new_index.entry(root).or_insert_with(|| {
                positions.push(positions[v as usize]);
                origin.push(v);
                (positions.len() - 1) as u32
            });
            faces[h / 3][h % 3] = copy;
        }
    }
    (origin, pinched.iter().filter(|&&p| p).count())
}
