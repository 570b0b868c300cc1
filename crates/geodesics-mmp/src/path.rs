//! Exact shortest paths by backtracing the kept windows (Section 3.4 of
//! Surazhsky et al. 2005): from the target, straight towards the
//! pseudo-source of the window that gave its distance, across the faces
//! that window's ancestors crossed, bending only at the pseudo-source
//! vertex a root window was emitted from, until a source.

use geodesics_mesh::Mesh;
use geodesics_window::{
    DistanceField, FaceKind, GeodesicPath, Source, Stats, SurfacePoint, barycentric_ok,
};
use glam::{DVec2, DVec3};

use crate::MmpError;
use crate::solver::{NONE, Prov, SOURCE_ORIGIN, Solved};

/// Edge crossings closer than this many tolerance margins to an edge end
/// are reported as that vertex (as VTP's tracer does).
const VERTEX_SNAP_MARGINS: f64 = 16.0;

/// The result of [`crate::run`]: the distance field, statistics, and every
/// window kept, for path queries.
pub struct MmpField<'a> {
    pub(crate) mesh: &'a Mesh,
    pub(crate) sources: Vec<Source>,
    pub(crate) field: DistanceField,
    pub(crate) solved: Solved,
    pub(crate) max_distance: Option<f64>,
}

/// Where a backtrace continues.
enum Next {
    Vertex(u32),
    Done,
}

/// Safety net against a corrupted chain (each step strictly lowers the
/// distance, so a real chain is at most a few times the face count).
const STEP_FACTOR: usize = 8;

impl<'a> MmpField<'a> {
    /// The distance field (per input vertex).
    pub fn distance_field(&self) -> &DistanceField {
        &self.field
    }

    /// Statistics of the solve.
    pub fn stats(&self) -> &Stats {
        &self.solved.stats
    }

    /// The mesh the field was computed on.
    pub fn mesh(&self) -> &'a Mesh {
        self.mesh
    }

    /// Consumes the field, keeping the distances and statistics.
    pub fn into_parts(self) -> (DistanceField, Stats) {
        (self.field, self.solved.stats)
    }

    fn within_limit(&self, d: f64) -> bool {
        d.is_finite() && self.max_distance.is_none_or(|m| d <= m)
    }

    /// The shortest path from the nearest source to input vertex `v`.
    pub fn path_to_vertex(&self, v: u32) -> Result<GeodesicPath, MmpError> {
        let mesh = self.mesh;
        if v as usize >= mesh.input_vertex_count() {
            return Err(MmpError::TargetVertexOutOfRange {
                vertex: v,
                vertices: mesh.input_vertex_count(),
            });
        }
        // The fan copy of a pinch vertex holding the distance.
        let mut best = mesh.mesh_vertex(v);
        for u in mesh.pinch_fans(best) {
            if self.solved.dist[u as usize] < self.solved.dist[best as usize] {
                best = u;
            }
        }
        if !self.within_limit(self.solved.dist[best as usize]) {
            return Err(MmpError::Unreachable);
        }
        let mut pts = vec![SurfacePoint::Vertex(v)];
        let source = self.trace_vertex(best, &mut pts)?;
        Ok(self.finish(pts, source))
    }

    /// The shortest path from the nearest source to the point of face
    /// `face` with barycentric coordinates `barycentric` (relative to the
    /// corners of [`Mesh::face`]).
    pub fn path_to_point(
        &self,
        face: u32,
        barycentric: [f64; 3],
    ) -> Result<GeodesicPath, MmpError> {
        let mesh = self.mesh;
        if face as usize >= mesh.face_count() {
            return Err(MmpError::TargetFaceOutOfRange {
                face,
                faces: mesh.face_count(),
            });
        }
        if !barycentric_ok(&barycentric, &self.solved.tol) {
            return Err(MmpError::TargetBarycentric(barycentric));
        }
        let corners = mesh.face(face);
        let zeros = barycentric.iter().filter(|&&b| b == 0.0).count();
        if zeros == 2 {
            let k = barycentric.iter().position(|&b| b != 0.0).unwrap_or(0);
            return self.path_to_vertex(mesh.pinch_origin(corners[k]));
        }
        let target = SurfacePoint::Face { face, barycentric };
        let q = target
            .position(mesh)
            .expect("the target face was checked above");
        let mut faces = vec![face];
        if zeros == 1 {
            let k = barycentric.iter().position(|&b| b == 0.0).unwrap_or(0);
            // The edge opposite corner k is half-edge 3f + (k + 1) % 3.
            if let Some(t) = mesh.twin(3 * face + (k as u32 + 1) % 3) {
                faces.push(Mesh::face_of(t));
            }
        }
        let (d, how) = self.best_in_faces(&faces, q);
        if !self.within_limit(d) {
            return Err(MmpError::Unreachable);
        }
        let mut pts = vec![target];
        let source = match how {
            Cand::None => return Err(MmpError::Unreachable),
            Cand::Source(i) => {
                pts.push(self.source_surface_point(i));
                i
            }
            Cand::Vertex(v) => {
                pts.push(SurfacePoint::Vertex(mesh.pinch_origin(v)));
                self.trace_vertex(v, &mut pts)?
            }
            Cand::Window(id, x) => match self.trace_window(id, x, &mut pts)? {
                (Next::Done, s) => s,
                (Next::Vertex(u), _) => self.trace_vertex(u, &mut pts)?,
            },
        };
        Ok(self.finish(pts, source))
    }

    /// The geodesic distance at a point of a face (the length of
    /// [`MmpField::path_to_point`]), infinite where unreachable.
    pub fn distance_at_point(&self, face: u32, barycentric: [f64; 3]) -> Result<f64, MmpError> {
        match self.path_to_point(face, barycentric) {
            Ok(p) => Ok(p.length),
            Err(MmpError::Unreachable) => Ok(f64::INFINITY),
            Err(e) => Err(e),
        }
    }

    fn finish(&self, mut pts: Vec<SurfacePoint>, source: u32) -> GeodesicPath {
        pts.reverse();
        // An edge crossing within the tolerance of an edge end is that
        // vertex: the path passes through it (it may bend there).
        let mesh = self.mesh;
        let snap = VERTEX_SNAP_MARGINS * self.solved.tol.margin(mesh.length_scale());
        for p in &mut pts {
            if let SurfacePoint::Edge { half_edge, t } = *p {
                let along = t * mesh.length(half_edge);
                let rest = (1.0 - t) * mesh.length(half_edge);
                if along <= snap {
                    *p = SurfacePoint::Vertex(mesh.pinch_origin(mesh.tail(half_edge)));
                } else if rest <= snap {
                    *p = SurfacePoint::Vertex(mesh.pinch_origin(mesh.head(half_edge)));
                }
            }
        }
        pts.dedup();
        GeodesicPath::from_points(self.mesh, pts, source)
            .expect("traced points are vertices, edges and faces of the mesh")
    }

    fn source_surface_point(&self, i: u32) -> SurfacePoint {
        match self.sources[i as usize] {
            Source::Vertex(v) => SurfacePoint::Vertex(v),
            Source::EdgePoint { half_edge, t } => edge_point(self.mesh, half_edge, t),
            Source::FacePoint { face, barycentric } => {
                let s: f64 = barycentric.iter().sum();
                SurfacePoint::Face {
                    face,
                    barycentric: barycentric.map(|b| b / s),
                }
            }
        }
    }

    /// Follows vertex provenance from mesh vertex `u` (already pushed) to
    /// a source; returns the source index.
    fn trace_vertex(&self, mut u: u32, pts: &mut Vec<SurfacePoint>) -> Result<u32, MmpError> {
        let limit = STEP_FACTOR * (self.mesh.vertex_count() + self.solved.wins.len() + 16);
        for _ in 0..limit {
            match self.solved.prov[u as usize] {
                Prov::Unreached => return Err(MmpError::Unreachable),
                Prov::Source(i) => {
                    if !matches!(self.sources[i as usize], Source::Vertex(_)) {
                        pts.push(self.source_surface_point(i));
                    }
                    return Ok(i);
                }
                Prov::Vertex { from } => {
                    pts.push(SurfacePoint::Vertex(self.mesh.pinch_origin(from)));
                    u = from;
                }
                Prov::Window { win, at } => match self.trace_window(win, at, pts)? {
                    (Next::Done, s) => return Ok(s),
                    (Next::Vertex(v), _) => u = v,
                },
            }
        }
        Err(MmpError::Backtrace(limit))
    }

    /// From the point at `x` (frame of the window's half-edge) on window
    /// `id`, back through its ancestors to its root: a source (done) or a
    /// pseudo-source vertex (continue from it).
    fn trace_window(
        &self,
        mut id: u32,
        mut x: f64,
        pts: &mut Vec<SurfacePoint>,
    ) -> Result<(Next, u32), MmpError> {
        let mesh = self.mesh;
        let s = &self.solved;
        for _ in 0..s.wins.len() + 16 {
            let w = s.wins[id as usize];
            let h = w.h;
            let l = mesh.length(h);
            let t = if l > 0.0 {
                (x / l).clamp(0.0, 1.0)
            } else {
                0.0
            };
            pts.push(edge_point(mesh, h, t));
            if w.parent == NONE {
                if w.origin & SOURCE_ORIGIN != 0 {
                    let i = w.origin & !SOURCE_ORIGIN;
                    pts.push(self.source_surface_point(i));
                    return Ok((Next::Done, i));
                }
                pts.push(SurfacePoint::Vertex(mesh.pinch_origin(w.origin)));
                return Ok((Next::Vertex(w.origin), w.source));
            }
            let pw = s.wins[w.parent as usize];
            let hp = pw.h;
            if s.kind[Mesh::face_of(hp) as usize] == FaceKind::Zipper {
                // Same segment, same frame: the crossing is the same point.
                id = w.parent;
                continue;
            }
            // The ends of h in the frame of hp (h is the twin of one of the
            // two other edges of hp's face).
            let lp = mesh.length(hp);
            let c = mesh.apex(hp);
            let (a, b) = if mesh.twin(Mesh::prev(hp)) == Some(h) {
                (DVec2::ZERO, c)
            } else {
                (c, DVec2::new(lp, 0.0))
            };
            let xq = a + (b - a) * t;
            // Straight back towards the parent's pseudo-source: where the
            // segment meets hp.
            let pp = crate::solver::own_window(mesh, &s.edge_of, &s.edge_he, &pw).p;
            let den = xq.y - pp.y;
            let y = if den > 0.0 {
                xq.x + (pp.x - xq.x) * xq.y / den
            } else {
                xq.x
            };
            x = y.clamp(0.0, lp);
            id = w.parent;
        }
        Err(MmpError::Backtrace(s.wins.len() + 16))
    }

    /// The best way to reach point `q` (3D) lying in all of `faces`:
    /// through a window lighting one of them, from one of their corners, or
    /// straight from a point source in one of them.
    fn best_in_faces(&self, faces: &[u32], q: DVec3) -> (f64, Cand) {
        let mesh = self.mesh;
        let s = &self.solved;
        let mut best = (f64::INFINITY, Cand::None);
        for &f in faces {
            for h in 3 * f..3 * f + 3 {
                let e = s.edge_of[h as usize] as usize;
                let q2 = mesh.frame_coords(h, q);
                for &id in &s.lists[e] {
                    let w = s.wins[id as usize];
                    if w.h != h {
                        continue;
                    }
                    let w = crate::solver::own_window(mesh, &s.edge_of, &s.edge_he, &w);
                    let (b0, b1) = (w.b0, w.b1);
                    let den = q2.y - w.p.y;
                    let x = if den > 0.0 {
                        w.p.x + (q2.x - w.p.x) * (-w.p.y) / den
                    } else {
                        q2.x
                    };
                    let m = s.tol.absolute;
                    if !(x >= b0 - m && x <= b1 + m) {
                        continue;
                    }
                    let x = x.clamp(b0, b1);
                    let xp = DVec2::new(x, 0.0);
                    let d = w.sigma + w.p.distance(xp) + xp.distance(q2);
                    if d < best.0 {
                        best = (d, Cand::Window(id, x));
                    }
                }
            }
            for v in mesh.face(f) {
                let d = s.dist[v as usize] + mesh.position(v).distance(q);
                if d < best.0 {
                    best = (d, Cand::Vertex(v));
                }
            }
            for (i, src) in self.sources.iter().enumerate() {
                if source_in_face(mesh, src, f) {
                    let d = s.source_points[i].distance(q);
                    if d < best.0 {
                        best = (d, Cand::Source(i as u32));
                    }
                }
            }
        }
        best
    }
}

enum Cand {
    None,
    Source(u32),
    Vertex(u32),
    Window(u32, f64),
}

/// A point of half-edge `h` at `t`, as a vertex at the ends.
fn edge_point(mesh: &Mesh, h: u32, t: f64) -> SurfacePoint {
    if t <= 0.0 {
        SurfacePoint::Vertex(mesh.pinch_origin(mesh.tail(h)))
    } else if t >= 1.0 {
        SurfacePoint::Vertex(mesh.pinch_origin(mesh.head(h)))
    } else {
        SurfacePoint::Edge { half_edge: h, t }
    }
}

/// Whether point source `s` lies in the closed face `f`.
fn source_in_face(mesh: &Mesh, s: &Source, f: u32) -> bool {
    match *s {
        Source::Vertex(v) => mesh.face(f).iter().any(|&u| mesh.pinch_origin(u) == v),
        Source::EdgePoint { half_edge, .. } => {
            Mesh::face_of(half_edge) == f
                || mesh.twin(half_edge).is_some_and(|t| Mesh::face_of(t) == f)
        }
        Source::FacePoint { face, .. } => face == f,
    }
}
