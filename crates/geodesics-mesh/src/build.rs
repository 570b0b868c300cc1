//! Validation and construction of [`Mesh`] from [`IndexedTriangles`].

use glam::DVec3;
use rayon::prelude::*;

use crate::summary::{AnisotropyStats, MeshSummary};
use crate::union_find::UnionFind;
use crate::{
    FaceKind, HalfEdge, IndexedTriangles, LENGTH_SCALE_SPAN, Mesh, MeshError, NONE, frame_coords_of,
};

/// How to build a [`Mesh`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BuildOptions {
    /// Merge vertices whose positions are exactly equal (numbered in order of
    /// first appearance) and drop the faces that then repeat a vertex.
    pub weld: bool,
    /// Store vertices and faces in an order that keeps neighbours close in
    /// memory (vertices along a Morton curve, faces by their first vertex).
    /// Solvers then touch far fewer cache lines per step: 15-20 % faster on
    /// scans whose file order is scattered. The mesh's vertex and face
    /// numbers are then its own; [`Mesh::pinch_origin`],
    /// [`Mesh::mesh_vertex`], [`Mesh::input_face`] and [`Mesh::mesh_face`]
    /// translate. Results keyed by input vertex ([`Mesh::fold_to_input`],
    /// the solvers' distance fields, paths' vertices) are unaffected.
    pub reorder: bool,
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
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for (vertex, p) in positions.iter().enumerate() {
            if !p.is_finite() {
                return Err(MeshError::NonFiniteCoordinate {
                    vertex,
                    x: p.x,
                    y: p.y,
                    z: p.z,
                });
            }
            if let Some(value) = [p.x, p.y, p.z]
                .into_iter()
                .find(|c| c.abs() > crate::MAX_COORDINATE)
            {
                return Err(MeshError::CoordinateTooLarge { vertex, value });
            }
            (lo, hi) = (lo.min(*p), hi.max(*p));
        }
        // The largest side, not the diagonal: squaring is what underflows.
        let extent = (hi - lo).max_element();
        if extent > 0.0 && extent < crate::MIN_EXTENT {
            return Err(MeshError::TooSmall { extent });
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
        let (mut flipped, mut face_component) = orient_components(&mut faces, &edges)?;
        let reoriented_faces = flipped.iter().filter(|&&f| f).count();
        let mut twin = link_twins(&edges, &flipped);

        let input_vertex_count = positions.len();
        let (mut pinch_origin, nonmanifold_vertices) =
            split_pinch_vertices(&mut faces, &twin, &mut positions);
        let mut pinch_ring = pinch_rings(&pinch_origin);
        let mut maps = Renumbering::default();
        if options.reorder {
            let (vertex_order, face_order) = locality_order(&positions, &faces);
            maps = Renumbering::new(vertex_order, face_order);
            maps.apply(
                &mut faces,
                &mut twin,
                &mut flipped,
                &mut face_component,
                &mut positions,
            );
            maps.apply_to_vertex_numbers(&mut pinch_origin, &mut pinch_ring);
        }

        let half = twin
            .iter()
            .enumerate()
            .map(|(h, &twin)| HalfEdge {
                twin,
                tail: faces[h / 3][h % 3],
                ..HalfEdge::default()
            })
            .collect();
        let mut mesh = Mesh {
            half,
            corner_angle: Vec::new(),
            angle_sum: Vec::new(),
            vertex_half_edge: Vec::new(),
            fan_start: Vec::new(),
            fan: Vec::new(),
            boundary: Vec::new(),
            component: Vec::new(),
            positions,
            reoriented: flipped,
            pinch_ring,
            pinch_origin,
            mesh_vertex: {
                let mut first = maps.new_vertex;
                first.truncate(input_vertex_count);
                first
            },
            input_face: maps.face_order,
            mesh_face: maps.new_face,
            input_vertex_count,
            average_edge_length: 0.0,
            length_scale: 0.0,
            face_kind: Vec::new(),
            summary: MeshSummary::default(),
        };
        mesh.compute_geometry();
        mesh.compute_vertex_topology(&face_component);
        mesh.summary = mesh.compute_summary(
            edges.edge_count,
            nonmanifold_vertices,
            duplicate_positions,
            [welded_vertices, welded_collapsed_faces],
            reoriented_faces,
        );
        mesh.length_scale = mesh.capped_length_scale();
        Ok(mesh)
    }

    /// [`Mesh::length_scale`]: the bounding-box diagonal, capped at
    /// [`LENGTH_SCALE_SPAN`] · √F median edges (the median of a sample of
    /// at most 2^16 half-edges, evenly strided: deterministic, and cheap on
    /// the largest meshes).
    fn capped_length_scale(&self) -> f64 {
        const SAMPLE: usize = 1 << 16;
        let diagonal = self.summary.bbox_diagonal;
        let stride = self.half.len().div_ceil(SAMPLE).max(1);
        let mut lengths: Vec<f64> = self
            .half
            .iter()
            .step_by(stride)
            .map(|h| h.length)
            .filter(|&l| l > 0.0)
            .collect();
        if lengths.is_empty() {
            return diagonal;
        }
        let middle = lengths.len() / 2;
        let (_, &mut median, _) = lengths.select_nth_unstable_by(middle, f64::total_cmp);
        let cap = LENGTH_SCALE_SPAN * (self.face_count() as f64).sqrt() * median;
        diagonal.min(cap)
    }

    fn compute_geometry(&mut self) {
        let n = self.half.len();
        // Each face on its own (edge lengths, corner angles, the apex in
        // each edge's frame), on rayon's pool: on the welded dragon this was
        // a third of the build, the atan2 of every corner.
        self.corner_angle = vec![0.0; n];
        let positions = &self.positions;
        self.half
            .par_chunks_mut(3)
            .zip(self.corner_angle.par_chunks_mut(3))
            .with_min_len(1024)
            .for_each(|(half, angle)| {
                let p = [0, 1, 2].map(|i| positions[half[i].tail as usize]);
                for i in 0..3 {
                    half[i].length = p[i].distance(p[(i + 1) % 3]);
                }
                for i in 0..3 {
                    let a = p[(i + 1) % 3] - p[i];
                    let b = p[(i + 2) % 3] - p[i];
                    angle[i] = angle_between(a, b);
                }
                for i in 0..3 {
                    let (tail, head, apex) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
                    half[i].apex = frame_coords_of(tail, head, half[i].length, apex);
                }
            });
        // Summed in the input's corner order: the same bits whatever the
        // numbering (saddle and flat tests sit close to 2π).
        self.angle_sum = vec![0.0; self.positions.len()];
        let mut total_length = 0.0;
        for u in 0..self.face_count() as u32 {
            let f = self.mesh_face(u) as usize;
            for h in 3 * f..3 * f + 3 {
                let v = self.half[h].tail;
                self.angle_sum[v as usize] += self.corner_angle[h];
                total_length += self.half[h].length;
            }
        }
        self.face_kind = (0..n / 3)
            .map(|f| {
                let hs = 3 * f..3 * f + 3;
                let proper = hs
                    .clone()
                    .all(|h| self.half[h].length > 0.0 && self.half[h].apex.y > 0.0);
                let zeros = hs.filter(|&h| self.half[h].length == 0.0).count();
                if proper {
                    FaceKind::Proper
                } else if zeros == 1 {
                    FaceKind::Zipper
                } else {
                    FaceKind::Blocked
                }
            })
            .collect();
        self.average_edge_length = if n == 0 { 0.0 } else { total_length / n as f64 };
    }

    fn compute_vertex_topology(&mut self, face_component: &[u32]) {
        let nv = self.positions.len();
        self.vertex_half_edge = vec![NONE; nv];
        self.boundary = vec![false; nv];
        // In the input's half-edge order, so that a renumbered mesh starts
        // every fan at the same face as the mesh kept in file order.
        for u in 0..self.face_count() as u32 {
            let f = self.mesh_face(u);
            for h in 3 * f..3 * f + 3 {
                let v = self.tail(h) as usize;
                if self.half[h as usize].twin == NONE {
                    // A boundary edge leaving v: the clockwise-most outgoing
                    // edge of v's (single, after pinch splitting) fan.
                    self.boundary[v] = true;
                    self.vertex_half_edge[v] = h;
                } else if self.vertex_half_edge[v] == NONE {
                    self.vertex_half_edge[v] = h;
                }
            }
        }
        // The fans as one flat table, so that solvers read a vertex's faces
        // from contiguous memory (and can ask for them before they need
        // them) instead of chasing twins. The walk follows each half-edge's
        // successor around its tail, `twin(prev(h))`, taken first in one
        // sequential pass: a dense array, not the records scattered over
        // the mesh in file order.
        let successor: Vec<u32> = (0..self.half.len() as u32)
            .map(|h| self.half[Mesh::prev(h) as usize].twin)
            .collect();
        self.fan_start = Vec::with_capacity(nv + 1);
        self.fan = Vec::with_capacity(self.half.len());
        self.fan_start.push(0);
        for &start in &self.vertex_half_edge {
            if start != NONE {
                let mut h = start;
                loop {
                    self.fan.push(h);
                    let t = successor[h as usize];
                    if t == NONE || t == start {
                        break;
                    }
                    h = t;
                }
            }
            self.fan_start.push(self.fan.len() as u32);
        }
        self.component = vec![NONE; nv];
        for (f, &c) in face_component.iter().enumerate() {
            for v in self.face(f as u32) {
                self.component[v as usize] = c;
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
        // Components of referenced input vertices. Edge-connected pieces can
        // share a vertex only at a pinch vertex, which joins them.
        let mut referenced = vec![false; nin];
        for f in self.faces() {
            for v in f {
                referenced[self.pinch_origin[v as usize] as usize] = true;
            }
        }
        let used = referenced.iter().filter(|&&r| r).count();
        let piece_count = self
            .component
            .iter()
            .filter(|&&c| c != NONE)
            .max()
            .map_or(0, |&c| c as usize + 1);
        let components = if nonmanifold_vertices == 0 {
            piece_count
        } else {
            let mut pieces = UnionFind::new(piece_count);
            for v in 0..self.positions.len() as u32 {
                if self.is_pinch_copy(v) {
                    let first = self.mesh_vertex(self.pinch_origin(v));
                    pieces.union(self.component[v as usize], self.component[first as usize]);
                }
            }
            (0..piece_count as u32)
                .filter(|&c| pieces.find(c) == c)
                .count()
        };

        // Boundary loops: components of the graph of boundary edges.
        let mut buf = UnionFind::new(nin);
        let mut on_boundary = vec![false; nin];
        for h in 0..self.half.len() as u32 {
            if self.half[h as usize].twin == NONE {
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

        let euler_characteristic = used as i64 - edges as i64 + self.face_count() as i64;
        let twice_genus = 2 * components as i64 - euler_characteristic - boundary_loops as i64;
        let genus = (nonmanifold_vertices == 0 && twice_genus >= 0 && twice_genus % 2 == 0)
            .then_some(twice_genus / 2);

        let saddle_vertices = (0..nin as u32)
            .map(|u| self.mesh_vertex(u))
            .filter(|&v| self.is_referenced(v) && self.is_saddle(v))
            .count();

        // Per face (on rayon's pool), kept in input order: the mean is then
        // the same to the last bit whatever the numbering. `None`: no area.
        let per_face: Vec<Option<f64>> = (0..self.face_count() as u32)
            .into_par_iter()
            .map(|u| {
                let f = self.mesh_face(u) as usize;
                let p = self.face(f as u32).map(|v| self.positions[v as usize]);
                let area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
                (area != 0.0).then(|| {
                    let l = [0, 1, 2].map(|i| self.half[3 * f + i].length);
                    let half_perimeter = 0.5 * (l[0] + l[1] + l[2]);
                    let longest = l[0].max(l[1]).max(l[2]);
                    half_perimeter * longest / (2.0 * 3f64.sqrt() * area)
                })
            })
            .collect();
        let zero_area_faces = per_face.iter().filter(|q| q.is_none()).count();
        let mut quality: Vec<f64> = per_face.into_iter().flatten().collect();
        let anisotropy = anisotropy_stats(&mut quality);

        let (lo, hi) = (0..nin as u32)
            .filter(|&u| referenced[u as usize])
            .map(|u| self.position(self.mesh_vertex(u)))
            .fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(p), hi.max(p)),
            );

        MeshSummary {
            vertices: nin,
            faces: self.face_count(),
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
    let n = quality.len();
    let mean = quality.iter().sum::<f64>() / n as f64;
    let max = quality.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut rank = |q: f64| {
        let k = ((q * (n - 1) as f64).round() as usize).min(n - 1);
        *quality.select_nth_unstable_by(k, f64::total_cmp).1
    };
    let p99 = rank(0.99);
    let median = rank(0.5);
    AnisotropyStats {
        mean,
        median,
        p99,
        max,
    }
}

fn position_key(p: DVec3) -> [u64; 3] {
    // +0.0 and -0.0 are the same point.
    p.to_array().map(|c| if c == 0.0 { 0 } else { c.to_bits() })
}

fn distinct_position_count(positions: &[DVec3]) -> usize {
    let mut keys: Vec<[u64; 3]> = positions.par_iter().map(|&p| position_key(p)).collect();
    keys.par_sort_unstable();
    keys.dedup();
    keys.len()
}

/// Merges exactly equal positions; new indices in order of first appearance.
///
/// By sorting `(position, index)` pairs (in parallel; the pairs are
/// distinct, so the order is the same every time): each run of equal
/// positions starts at its first appearance. A hash map of positions did
/// the same in one pass, at a random memory access per vertex.
fn weld_positions(positions: &[DVec3]) -> (Vec<DVec3>, Vec<u32>) {
    let n = positions.len();
    let mut keyed: Vec<([u64; 3], u32)> = positions
        .par_iter()
        .enumerate()
        .map(|(i, &p)| (position_key(p), i as u32))
        .collect();
    keyed.par_sort_unstable();
    let mut first = vec![0u32; n];
    let mut run_start = 0;
    for (k, &(key, i)) in keyed.iter().enumerate() {
        if k == 0 || key != keyed[k - 1].0 {
            run_start = i;
        }
        first[i as usize] = run_start;
    }
    // A vertex's first appearance comes no later than the vertex itself,
    // so numbering in index order numbers in order of first appearance.
    let mut new_of = vec![NONE; n];
    let mut welded = Vec::new();
    let remap = first
        .iter()
        .map(|&r| {
            let r = r as usize;
            if new_of[r] == NONE {
                new_of[r] = welded.len() as u32;
                welded.push(positions[r]);
            }
            new_of[r]
        })
        .collect();
    (welded, remap)
}

/// Undirected edges: for every half-edge slot `3f+i`, the other slot on the
/// same edge (`NONE` on boundary), as stored in the input.
struct EdgeTable {
    /// Per half-edge slot: the slot on the other side of its edge.
    mate: Vec<u32>,
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
        // Packed (larger vertex, slot): sorting the u64 sorts by vertex pair.
        let mut bucketed = vec![0u64; n];
        for h in 0..n {
            let (lo, hi) = ends(h);
            bucketed[fill[lo as usize] as usize] = (u64::from(hi) << 32) | h as u64;
            fill[lo as usize] += 1;
        }
        let mut mate = vec![NONE; n];
        let mut edge_count = 0;
        for v in 0..vertex_count {
            let bucket = &mut bucketed[start[v] as usize..start[v + 1] as usize];
            bucket.sort_unstable();
            let mut i = 0;
            while i < bucket.len() {
                let hi = bucket[i] >> 32;
                let mut j = i + 1;
                while j < bucket.len() && bucket[j] >> 32 == hi {
                    j += 1;
                }
                let slot = |k: usize| bucket[k] as u32;
                if j - i > 2 {
                    let faces_on: Vec<usize> = (i..j).map(|k| slot(k) as usize / 3).collect();
                    return Err(MeshError::NonManifoldEdge {
                        a: v as u32,
                        b: hi as u32,
                        faces: faces_on,
                    });
                }
                if j - i == 2 {
                    mate[slot(i) as usize] = slot(i + 1);
                    mate[slot(i + 1) as usize] = slot(i);
                }
                edge_count += 1;
                i = j;
            }
        }
        Ok(Self { mate, edge_count })
    }
}

/// Flips faces so that every edge-connected component is consistently
/// oriented (the first face of each component keeps its orientation).
/// Returns which faces were flipped and each face's edge-connected component.
fn orient_components(
    faces: &mut [[u32; 3]],
    edges: &EdgeTable,
) -> Result<(Vec<bool>, Vec<u32>), MeshError> {
    let nf = faces.len();
    let mut flipped = vec![false; nf];
    let mut visited = vec![false; nf];
    let mut component = vec![NONE; nf];
    let mut components = 0;
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
            component[f as usize] = components;
            for i in 0..3 {
                let h = 3 * f + i;
                let other = edges.mate[h as usize];
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
        components += 1;
    }
    for (face, &flip) in faces.iter_mut().zip(&flipped) {
        if flip {
            face.swap(1, 2);
        }
    }
    Ok((flipped, component))
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
    let mut twin = vec![NONE; edges.mate.len()];
    for (h, &m) in edges.mate.iter().enumerate() {
        if m != NONE {
            twin[current_slot(h as u32) as usize] = current_slot(m);
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
    let nv = positions.len();
    let mut corners_at = vec![0u32; nv];
    let mut first_corner = vec![NONE; nv];
    for h in 0..n {
        let v = faces[h / 3][h % 3] as usize;
        corners_at[v] += 1;
        if first_corner[v] == NONE {
            first_corner[v] = h as u32;
        }
    }
    // A vertex is a pinch vertex when its first fan misses some of its corners.
    let mut seen = vec![false; n];
    let mut pinch = vec![false; nv];
    for v in 0..nv {
        let start = first_corner[v];
        if start != NONE && walk_fan(start, twin, |_| {}) != corners_at[v] {
            pinch[v] = true;
            walk_fan(start, twin, |c| seen[c as usize] = true);
        }
    }
    // Every corner of a pinch vertex outside its first fan starts a new fan.
    let mut origin: Vec<u32> = (0..nv as u32).collect();
    let mut fan = Vec::new();
    for h in 0..n {
        let v = faces[h / 3][h % 3] as usize;
        if v >= nv || !pinch[v] || seen[h] {
            continue;
        }
        positions.push(positions[v]);
        origin.push(v as u32);
        let copy = (positions.len() - 1) as u32;
        fan.clear();
        walk_fan(h as u32, twin, |c| fan.push(c));
        for &c in &fan {
            seen[c as usize] = true;
            faces[(c / 3) as usize][(c % 3) as usize] = copy;
        }
    }
    (origin, pinch.iter().filter(|&&p| p).count())
}

/// Visits the corners of the fan of `corner` (at the tail of half-edge
/// `corner`), rotating both ways across interior edges; returns their count.
fn walk_fan(corner: u32, twin: &[u32], mut visit: impl FnMut(u32)) -> u32 {
    let mut count = 0;
    let mut h = corner;
    // Counter-clockwise: across the incoming edge of the current corner.
    loop {
        visit(h);
        count += 1;
        let t = twin[Mesh::prev(h) as usize];
        if t == NONE {
            break;
        }
        if t == corner {
            return count;
        }
        h = t;
    }
    // Hit a boundary: continue clockwise from the start, across its outgoing edge.
    let mut h = corner;
    loop {
        let t = twin[h as usize];
        if t == NONE {
            return count;
        }
        h = Mesh::next(t);
        visit(h);
        count += 1;
    }
}

/// How a mesh being built is renumbered (see [`BuildOptions::reorder`]);
/// the default, all empty, keeps the input's numbers.
#[derive(Default)]
struct Renumbering {
    /// Per new vertex, its number before; per new face, likewise (what
    /// [`Mesh::input_face`] keeps).
    vertex_order: Vec<u32>,
    face_order: Vec<u32>,
    /// Per vertex before, its new number (its first `input_vertex_count`
    /// entries are what [`Mesh::mesh_vertex`] keeps); per face, likewise
    /// (what [`Mesh::mesh_face`] keeps).
    new_vertex: Vec<u32>,
    new_face: Vec<u32>,
}

impl Renumbering {
    /// Vertex `vertex_order[i]` becomes `i` and face `face_order[j]`
    /// becomes `j`. Before, vertices are the input's (pinch copies after
    /// them) and faces are the input's.
    fn new(vertex_order: Vec<u32>, face_order: Vec<u32>) -> Self {
        let invert = |order: &[u32]| {
            let mut inverse = vec![NONE; order.len()];
            for (i, &x) in order.iter().enumerate() {
                inverse[x as usize] = i as u32;
            }
            inverse
        };
        let new_vertex = invert(&vertex_order);
        let new_face = invert(&face_order);
        Renumbering {
            vertex_order,
            face_order,
            new_vertex,
            new_face,
        }
    }

    fn vertex(&self, v: u32) -> u32 {
        if v == NONE {
            NONE
        } else {
            self.new_vertex[v as usize]
        }
    }

    /// Renumbers the face-indexed tables (corners keep their order within
    /// a face; twins keep pointing at the same half-edges) and positions.
    fn apply(
        &self,
        faces: &mut Vec<[u32; 3]>,
        twin: &mut Vec<u32>,
        flipped: &mut Vec<bool>,
        face_component: &mut Vec<u32>,
        positions: &mut Vec<DVec3>,
    ) {
        let order = &self.face_order;
        *faces = order
            .iter()
            .map(|&f| faces[f as usize].map(|v| self.vertex(v)))
            .collect();
        let new_half_edge = |t: u32| {
            if t == NONE {
                NONE
            } else {
                3 * self.new_face[(t / 3) as usize] + t % 3
            }
        };
        *twin = order
            .iter()
            .flat_map(|&f| [3 * f, 3 * f + 1, 3 * f + 2])
            .map(|h| new_half_edge(twin[h as usize]))
            .collect();
        *flipped = order.iter().map(|&f| flipped[f as usize]).collect();
        *face_component = order.iter().map(|&f| face_component[f as usize]).collect();
        *positions = self
            .vertex_order
            .iter()
            .map(|&v| positions[v as usize])
            .collect();
    }

    /// Renumbers per-vertex tables of input vertex numbers (kept as they
    /// are) and of this mesh's vertex numbers (renumbered).
    fn apply_to_vertex_numbers(&self, pinch_origin: &mut Vec<u32>, pinch_ring: &mut Vec<u32>) {
        let order = &self.vertex_order;
        *pinch_origin = order.iter().map(|&v| pinch_origin[v as usize]).collect();
        *pinch_ring = order
            .iter()
            .map(|&v| self.vertex(pinch_ring[v as usize]))
            .collect();
    }
}

/// A cache-friendly numbering (see [`BuildOptions::reorder`]): vertices
/// sorted along a Morton (Z-order) curve through their positions, then
/// faces sorted by their smallest new corner number, so that a
/// vertex's fan and its neighbours' records sit close together. Returns the
/// old vertex numbers in new order and the old face numbers in new order.
fn locality_order(positions: &[DVec3], faces: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let (lo, hi) = positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let extent = (hi - lo).max_element();
    // 21 bits per axis: a 63-bit code.
    const CELLS: f64 = ((1u64 << 21) - 1) as f64;
    let scale = if extent > 0.0 { CELLS / extent } else { 0.0 };
    let cell = |x: f64| ((x * scale).clamp(0.0, CELLS)) as u64;
    // (code, vertex) pairs are distinct: any sort gives this one order.
    let mut keyed: Vec<(u64, u32)> = positions
        .par_iter()
        .enumerate()
        .map(|(v, &p)| {
            let q = p - lo;
            let code =
                spread_bits(cell(q.x)) | spread_bits(cell(q.y)) << 1 | spread_bits(cell(q.z)) << 2;
            (code, v as u32)
        })
        .collect();
    keyed.par_sort_unstable();
    let vertex_order: Vec<u32> = keyed.iter().map(|&(_, v)| v).collect();
    let mut new_vertex = vec![0u32; vertex_order.len()];
    for (i, &v) in vertex_order.iter().enumerate() {
        new_vertex[v as usize] = i as u32;
    }
    // Faces by their smallest new corner: a counting sort (stable, so a
    // vertex's faces keep their input order).
    let first = |c: &[u32; 3]| {
        let [a, b, d] = c.map(|v| new_vertex[v as usize]);
        a.min(b).min(d) as usize
    };
    let mut start = vec![0u32; vertex_order.len() + 1];
    for corners in faces {
        start[first(corners) + 1] += 1;
    }
    for v in 0..vertex_order.len() {
        start[v + 1] += start[v];
    }
    let mut face_order = vec![0u32; faces.len()];
    for (f, corners) in faces.iter().enumerate() {
        let v = first(corners);
        face_order[start[v] as usize] = f as u32;
        start[v] += 1;
    }
    (vertex_order, face_order)
}

/// Spreads the low 21 bits of `x` to every third bit (bit `i` to `3i`).
fn spread_bits(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x1f_0000_0000_ffff;
    x = (x | x << 16) & 0x1f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

#[cfg(test)]
mod tests {
    use super::{spread_bits, weld_positions};
    use glam::DVec3;

    #[test]
    fn welding_numbers_positions_by_first_appearance() {
        let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
        let positions = [
            p(2.0, 0.0),
            p(1.0, 0.0),
            p(2.0, 0.0),
            p(-0.0, 0.0),
            p(1.0, 0.0),
            p(0.0, 0.0),
            p(3.0, 0.0),
        ];
        let (welded, remap) = weld_positions(&positions);
        assert_eq!(remap, [0, 1, 0, 2, 1, 2, 3]);
        // The first appearance's coordinates, -0.0 included.
        assert_eq!(
            welded,
            [p(2.0, 0.0), p(1.0, 0.0), p(-0.0, 0.0), p(3.0, 0.0)]
        );
        assert!(welded[2].x.is_sign_negative());
        assert_eq!(weld_positions(&[]), (vec![], vec![]));
    }

    #[test]
    fn spread_bits_moves_bit_i_to_bit_3i() {
        for x in [0u64, 1, 2, 3, 0x15_5555, 0x0a_aaaa, 0x1f_ffff, 123_456] {
            let naive = (0..21).fold(0u64, |acc, i| acc | ((x >> i) & 1) << (3 * i));
            assert_eq!(spread_bits(x), naive, "{x:#x}");
        }
        // Bits above 21 are ignored.
        assert_eq!(spread_bits(1 << 21), 0);
    }
}
