//! Quadric-error edge-collapse simplification (Garland and Heckbert,
//! "Surface simplification using quadric error metrics", SIGGRAPH 1997).
//!
//! Used to make a coarse mesh from a scan, e.g. the low-resolution Stanford
//! bunny that Du et al. (2021) subdivide for their 235K- and 940K-face test
//! meshes (`bunny.off` brought down to their 3,674 faces).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec3;

use crate::subdivide::check_finite;
use crate::topology::{EdgeTopology, NONE};
use crate::{IndexedTriangles, ShapeError};

/// A face whose normal turns by more than this (as a cosine) in a collapse
/// is a fold: the collapse is refused.
const MIN_NORMAL_COS: f64 = 0.2;

/// A collapse may not leave a face less compact than this (`4√3·area /
/// Σ edge²`: 1 for an equilateral triangle, 0 for a degenerate one), unless
/// the face was already worse before.
const MIN_COMPACTNESS: f64 = 0.05;

/// The error quadric of a set of planes: `xᵀAx + 2bᵀx + c` is the sum of
/// squared distances from `x` to them (each weighted by its face's area).
#[derive(Clone, Copy, Debug, Default)]
struct Quadric {
    /// `A` (symmetric): `xx, xy, xz, yy, yz, zz`.
    a: [f64; 6],
    b: DVec3,
    c: f64,
}

impl Quadric {
    /// The plane through `p` with unit normal `n`, weighted by `weight`.
    fn plane(n: DVec3, p: DVec3, weight: f64) -> Quadric {
        let d = -n.dot(p);
        Quadric {
            a: [
                n.x * n.x,
                n.x * n.y,
                n.x * n.z,
                n.y * n.y,
                n.y * n.z,
                n.z * n.z,
            ]
            .map(|v| v * weight),
            b: n * (d * weight),
            c: d * d * weight,
        }
    }

    fn add(&self, o: &Quadric) -> Quadric {
        let mut a = self.a;
        for (x, y) in a.iter_mut().zip(o.a) {
            *x += y;
        }
        Quadric {
            a,
            b: self.b + o.b,
            c: self.c + o.c,
        }
    }

    fn error(&self, x: DVec3) -> f64 {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let ax = DVec3::new(
            xx * x.x + xy * x.y + xz * x.z,
            xy * x.x + yy * x.y + yz * x.z,
            xz * x.x + yz * x.y + zz * x.z,
        );
        (x.dot(ax) + 2.0 * self.b.dot(x) + self.c).max(0.0)
    }

    /// The point minimising the error, if `A` is well conditioned.
    fn minimiser(&self) -> Option<DVec3> {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let m = glam::DMat3::from_cols(
            DVec3::new(xx, xy, xz),
            DVec3::new(xy, yy, yz),
            DVec3::new(xz, yz, zz),
        );
        let det = m.determinant();
        let scale = xx.abs().max(yy.abs()).max(zz.abs());
        // A flat or cylindrical neighbourhood leaves `A` (nearly) singular:
        // the caller then picks among the ends and the midpoint.
        let well_conditioned = det.abs() > 1e-9 * scale * scale * scale;
        if !well_conditioned {
            return None;
        }
        let x = m.inverse() * -self.b;
        x.is_finite().then_some(x)
    }
}

/// Where a collapse of the edge `u`–`v` puts the merged vertex, and the
/// error it costs.
fn placement(q: &Quadric, pu: DVec3, pv: DVec3) -> (DVec3, f64) {
    let mid = 0.5 * (pu + pv);
    let mut best = (mid, q.error(mid));
    for x in q.minimiser().into_iter().chain([pu, pv]) {
        let e = q.error(x);
        if e < best.1 {
            best = (x, e);
        }
    }
    best
}

/// Twice the area vector of a triangle.
fn area_vector(p: [DVec3; 3]) -> DVec3 {
    (p[1] - p[0]).cross(p[2] - p[0])
}

/// `4√3·area / Σ edge²` of a triangle (1: equilateral, 0: degenerate).
fn compactness(p: [DVec3; 3]) -> f64 {
    let sum = (p[1] - p[0]).length_squared()
        + (p[2] - p[1]).length_squared()
        + (p[0] - p[2]).length_squared();
    let twice_area = area_vector(p).length();
    if sum > 0.0 {
        2.0 * 3f64.sqrt() * twice_area / sum
    } else {
        0.0
    }
}

/// The working mesh of a simplification.
struct Collapser {
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
    face_alive: Vec<bool>,
    /// Per vertex: its live faces (dead ones are dropped when met).
    around: Vec<Vec<u32>>,
    quadric: Vec<Quadric>,
    /// Vertices on a boundary never move or go.
    fixed: Vec<bool>,
    /// Bumped whenever a vertex moves or goes: heap entries made before
    /// are stale.
    version: Vec<u32>,
    alive_faces: usize,
    heap: BinaryHeap<Reverse<Candidate>>,
}

/// A collapse waiting in the heap: `(cost bits, u, v, version of u,
/// version of v)`, cheapest first, ties by vertex numbers.
type Candidate = (u64, u32, u32, u32, u32);

impl Collapser {
    fn new(mesh: &IndexedTriangles, topology: &EdgeTopology) -> Collapser {
        let n = mesh.positions.len();
        let mut around = vec![Vec::new(); n];
        let mut quadric = vec![Quadric::default(); n];
        for (f, t) in mesh.triangles.iter().enumerate() {
            let p = t.map(|v| mesh.positions[v as usize]);
            let av = area_vector(p);
            let len = av.length();
            for &v in t {
                around[v as usize].push(f as u32);
                if len > 0.0 {
                    let plane = Quadric::plane(av / len, p[0], 0.5 * len);
                    quadric[v as usize] = quadric[v as usize].add(&plane);
                }
            }
        }
        let mut fixed = vec![false; n];
        for (e, h) in topology.edges.iter().zip(&topology.edge_half_edges) {
            if h[1] == NONE {
                fixed[e[0] as usize] = true;
                fixed[e[1] as usize] = true;
            }
        }
        let mut c = Collapser {
            positions: mesh.positions.clone(),
            faces: mesh.triangles.clone(),
            face_alive: vec![true; mesh.triangles.len()],
            around,
            quadric,
            fixed,
            version: vec![0; n],
            alive_faces: mesh.triangles.len(),
            heap: BinaryHeap::new(),
        };
        for e in &topology.edges {
            c.push_edge(e[0], e[1]);
        }
        c
    }

    fn push_edge(&mut self, u: u32, v: u32) {
        let (u, v) = (u.min(v), u.max(v));
        if self.fixed[u as usize] || self.fixed[v as usize] {
            return;
        }
        let q = self.quadric[u as usize].add(&self.quadric[v as usize]);
        let (_, cost) = placement(&q, self.positions[u as usize], self.positions[v as usize]);
        let (vu, vv) = (self.version[u as usize], self.version[v as usize]);
        self.heap.push(Reverse((cost.to_bits(), u, v, vu, vv)));
    }

    /// The distinct other vertices of the live faces around `v`.
    fn neighbours(&self, v: u32) -> Vec<u32> {
        let mut out: Vec<u32> = self.around[v as usize]
            .iter()
            .filter(|&&f| self.face_alive[f as usize])
            .flat_map(|&f| self.faces[f as usize])
            .filter(|&w| w != v)
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Collapses `v` into `u` at `x` if that keeps the surface a manifold
    /// without folds or slivers; returns whether it did.
    fn try_collapse(&mut self, u: u32, v: u32, x: DVec3) -> bool {
        let shared: Vec<u32> = self.around[u as usize]
            .iter()
            .copied()
            .filter(|&f| self.face_alive[f as usize] && self.faces[f as usize].contains(&v))
            .collect();
        // Link condition: the two endpoints share exactly the neighbours
        // opposite the edge in its two faces, or the collapse would pinch
        // the surface.
        if shared.len() != 2 {
            return false;
        }
        let (nu, nv) = (self.neighbours(u), self.neighbours(v));
        let common = nu.iter().filter(|w| nv.binary_search(w).is_ok()).count();
        if common != 2 {
            return false;
        }
        // The faces that stay move one corner to `x`: none may fold over
        // or become a sliver.
        for &w in &[u, v] {
            for &f in &self.around[w as usize] {
                if !self.face_alive[f as usize] || shared.contains(&f) {
                    continue;
                }
                let t = self.faces[f as usize];
                let before = t.map(|c| self.positions[c as usize]);
                let after = t.map(|c| {
                    if c == u || c == v {
                        x
                    } else {
                        self.positions[c as usize]
                    }
                });
                let (n0, n1) = (area_vector(before), area_vector(after));
                let cos = n0.dot(n1) / (n0.length() * n1.length());
                // A NaN (a face of zero area) folds too.
                let folds = cos.is_nan() || cos <= MIN_NORMAL_COS;
                if folds {
                    return false;
                }
                let worse = compactness(after);
                if worse < MIN_COMPACTNESS && worse < compactness(before) {
                    return false;
                }
            }
        }
        for &f in &shared {
            self.face_alive[f as usize] = false;
        }
        self.alive_faces -= 2;
        let moved = std::mem::take(&mut self.around[v as usize]);
        for f in moved {
            if !self.face_alive[f as usize] {
                continue;
            }
            for c in &mut self.faces[f as usize] {
                if *c == v {
                    *c = u;
                }
            }
            self.around[u as usize].push(f);
        }
        let alive = &self.face_alive;
        self.around[u as usize].retain(|&f| alive[f as usize]);
        self.positions[u as usize] = x;
        self.quadric[u as usize] = self.quadric[u as usize].add(&self.quadric[v as usize]);
        self.version[u as usize] += 1;
        self.version[v as usize] += 1;
        for w in self.neighbours(u) {
            self.push_edge(u, w);
        }
        true
    }

    fn run(&mut self, target_faces: usize) {
        while self.alive_faces > target_faces {
            let Some(Reverse((_, u, v, vu, vv))) = self.heap.pop() else {
                break;
            };
            if self.version[u as usize] != vu || self.version[v as usize] != vv {
                continue; // stale: an endpoint moved or went since
            }
            let q = self.quadric[u as usize].add(&self.quadric[v as usize]);
            let (x, _) = placement(&q, self.positions[u as usize], self.positions[v as usize]);
            self.try_collapse(u, v, x);
        }
    }

    /// The live faces over the vertices they use, both renumbered in
    /// their old order.
    fn finish(self) -> IndexedTriangles {
        let mut new_index = vec![NONE; self.positions.len()];
        let faces: Vec<[u32; 3]> = self
            .faces
            .iter()
            .zip(&self.face_alive)
            .filter(|(_, alive)| **alive)
            .map(|(t, _)| *t)
            .collect();
        for t in &faces {
            for &v in t {
                new_index[v as usize] = 0;
            }
        }
        let mut positions = Vec::new();
        for (v, slot) in new_index.iter_mut().enumerate() {
            if *slot != NONE {
                *slot = positions.len() as u32;
                positions.push(self.positions[v]);
            }
        }
        let triangles = faces
            .iter()
            .map(|t| t.map(|v| new_index[v as usize]))
            .collect();
        IndexedTriangles {
            positions,
            triangles,
        }
    }
}

/// The mesh simplified to at most `target_faces` triangles (when it can be)
/// by collapsing, cheapest first, the edges whose merged vertex stays
/// closest to the planes of the original faces around it (Garland and
/// Heckbert's quadric error).
///
/// The result keeps the topology (genus, boundary loops) and orientation of
/// the input: a collapse that would pinch the surface (link condition),
/// fold a face over or leave a sliver is skipped, and boundary vertices
/// never move. So the target may not be reached on a mesh with few
/// interior edges; the result then has more faces. Deterministic (ties by
/// vertex numbers); unreferenced vertices are dropped and the others keep
/// their relative order.
///
/// ```
/// use geodesics_mesh::{BuildOptions, Mesh};
/// use geodesics_shapes::{icosphere, simplify};
///
/// let fine = icosphere(3, 1.0);
/// let coarse = simplify(&fine, 200)?;
/// assert_eq!(coarse.triangles.len(), 200);
/// let mesh = Mesh::build(coarse, &BuildOptions::default())?;
/// assert_eq!(mesh.summary().euler_characteristic, 2); // still a sphere
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
///
/// As for [`crate::loop_subdivide`]: a NaN or infinite coordinate, an
/// index out of range, a face repeating a vertex, an edge shared by more
/// than two faces.
pub fn simplify(
    mesh: &IndexedTriangles,
    target_faces: usize,
) -> Result<IndexedTriangles, ShapeError> {
    check_finite(mesh)?;
    let topology = EdgeTopology::new(mesh.positions.len(), &mesh.triangles)?;
    let mut collapser = Collapser::new(mesh, &topology);
    collapser.run(target_faces);
    Ok(collapser.finish())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{flat_grid, icosphere, regular_torus};

    fn summary(mesh: IndexedTriangles) -> geodesics_mesh::MeshSummary {
        geodesics_mesh::Mesh::build(mesh, &Default::default())
            .expect("a simplified mesh is a valid mesh")
            .summary()
            .clone()
    }

    #[test]
    fn a_sphere_stays_a_sphere_at_the_target() {
        let fine = icosphere(4, 1.0);
        let coarse = simplify(&fine, 500).unwrap();
        assert_eq!(coarse.triangles.len(), 500);
        assert_eq!(coarse.positions.len(), 252);
        let s = summary(coarse.clone());
        assert_eq!((s.euler_characteristic, s.boundary_loops), (2, 0));
        // The vertices stay near the sphere (the quadrics keep them near
        // the planes of the faces around them).
        for p in &coarse.positions {
            assert!((0.97..=1.03).contains(&p.length()), "{p}");
        }
        // Same input, same bits.
        assert_eq!(simplify(&fine, 500).unwrap(), coarse);
    }

    #[test]
    fn a_torus_keeps_its_hole() {
        let torus = regular_torus(48, 24, 2.0, 0.7);
        let coarse = simplify(&torus, 600).unwrap();
        assert_eq!(coarse.triangles.len(), 600);
        let s = summary(coarse);
        assert_eq!((s.euler_characteristic, s.genus), (0, Some(1)));
    }

    #[test]
    fn boundary_vertices_stay_where_they_are() {
        let grid = flat_grid(12, 12, 1.0);
        let coarse = simplify(&grid, 60).unwrap();
        // Only interior edges collapse: the 48 boundary vertices stay, and the
        // flat interior folds nothing, so the target is met.
        assert_eq!(coarse.triangles.len(), 60);
        let on_rim = |p: &DVec3| p.x == 0.0 || p.y == 0.0 || p.x == 12.0 || p.y == 12.0;
        assert_eq!(coarse.positions.iter().filter(|p| on_rim(p)).count(), 48);
        for p in &coarse.positions {
            assert_eq!(p.z, 0.0, "a flat mesh stays flat");
        }
        assert_eq!(summary(coarse).boundary_loops, 1);
    }

    #[test]
    fn a_target_above_the_face_count_changes_nothing() {
        let sphere = icosphere(1, 1.0);
        assert_eq!(simplify(&sphere, 80).unwrap(), sphere);
        assert_eq!(simplify(&sphere, 1000).unwrap(), sphere);
    }

    #[test]
    fn bad_input_is_an_error() {
        let mut sphere = icosphere(1, 1.0);
        sphere.triangles.push(sphere.triangles[0]);
        assert!(matches!(
            simplify(&sphere, 10),
            Err(ShapeError::NonManifoldEdge { .. })
        ));
        let mut sphere = icosphere(1, 1.0);
        sphere.triangles[3][1] = 999;
        assert!(matches!(
            simplify(&sphere, 10),
            Err(ShapeError::IndexOutOfRange { index: 999, .. })
        ));
        let mut sphere = icosphere(1, 1.0);
        sphere.positions[5].y = f64::NAN;
        assert!(matches!(
            simplify(&sphere, 10),
            Err(ShapeError::NonFiniteCoordinate { vertex: 5, .. })
        ));
    }
}
