//! Exact shortest paths rebuilt from VTP's per-vertex provenance.
//!
//! VTP releases its windows behind the wavefront, so unlike MMP it cannot
//! backtrace through them after the solve. What it keeps instead is O(1)
//! words per vertex ([`Provenance`]): how the vertex got its final
//! distance. A path is rebuilt backwards from the target, one straight
//! unfolded piece at a time:
//!
//! - `Window { half_edge, pseudo_source, bend, .. }`: from the apex of the
//!   face of `half_edge` to the crossing `bend` on it, then straight
//!   towards the pseudo-source, unfolding the faces below one by one (in
//!   each face, the line leaves through one of the two other edges) until
//!   the pseudo-source lies in the current face: a corner (a pseudo-source
//!   vertex: continue with its own provenance) or a point source.
//! - `Vertex { from, .. }`: along the mesh edge to `from` (a pinch copy:
//!   the same point, no new segment).
//! - `Source(i)`: the source itself.
//!
//! Every geometric decision goes through [`Tolerance`]. Where the line
//! passes within tolerance of a vertex that is not the pseudo-source, the
//! path goes through that vertex and the walk turns around the vertex's
//! fan to the face the line continues in, first on the side the line
//! passed (the sign of its rounding-level offset) and, if that unfolding
//! does not lead to the pseudo-source, on the other side (the two differ
//! by the vertex's angle defect, so only one reaches it).

use geodesics_mesh::Mesh;
use geodesics_window::{DistanceField, FaceKind, GeodesicPath, Source, SurfacePoint, Tolerance};
use glam::DVec2;
use thiserror::Error;

use crate::{Provenance, VtpError, VtpOptions, solve_with_provenance};

/// "The line passes through a vertex", "the crossing is at an edge end":
/// distances up to this many tolerance margins (rounding of one unfolding
/// step is far below one margin).
const SNAP_MARGINS: f64 = 16.0;

/// "The walk reached the pseudo-source": the unfolded pseudo-source drifts
/// by rounding over a long walk (hundreds of rigid transforms), so this is
/// looser than [`SNAP_MARGINS`]; still far below any edge length of a mesh
/// whose corners the solver can tell apart.
const REACH_MARGINS: f64 = 4096.0;

/// Why a path could not be traced.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum PathError {
    /// The solve itself was refused ([`shortest_path`]).
    #[error(transparent)]
    Solve(#[from] VtpError),
    /// The target is not an input vertex of the mesh.
    #[error("target vertex {target} out of range (the mesh has {vertices} input vertices)")]
    TargetOutOfRange {
        /// The target given.
        target: u32,
        /// Number of input vertices.
        vertices: usize,
    },
    /// No source reaches the target (other component, unreferenced vertex,
    /// beyond the maximum distance).
    #[error("target vertex {target} is not reached from any source")]
    Unreachable {
        /// The target given.
        target: u32,
    },
    /// The provenance slice does not have one entry per mesh vertex.
    #[error(
        "provenance has {got} entries, the mesh has {expected} vertices (pinch copies included)"
    )]
    ProvenanceLength {
        /// Entries given.
        got: usize,
        /// Mesh vertices.
        expected: usize,
    },
    /// The distance field does not have one entry per input vertex.
    #[error("distance field has {got} entries, the mesh has {expected} input vertices")]
    FieldLength {
        /// Entries given.
        got: usize,
        /// Input vertices.
        expected: usize,
    },
    /// A traced point is not on the mesh.
    #[error("path point {index} names a vertex, half-edge or face not in the mesh")]
    PointOutOfRange {
        /// Index of the point.
        index: usize,
    },
    /// The provenance does not describe a path (it belongs to another mesh
    /// or solve, or was altered).
    #[error("provenance of vertex {vertex} is inconsistent: {reason}")]
    Inconsistent {
        /// The mesh vertex whose provenance was being followed.
        vertex: u32,
        /// What did not fit.
        reason: &'static str,
    },
    /// Tracing took more steps than any path on this mesh can (cyclic
    /// provenance).
    #[error("tracing gave up after {steps} steps (cyclic or inconsistent provenance)")]
    StepLimit {
        /// Steps taken.
        steps: usize,
    },
}

/// The shortest path from the nearest of `sources` to input vertex
/// `target`: one solve with provenance, then [`trace_path`].
///
/// For many targets from the same sources, solve once with
/// [`solve_with_provenance`] and call [`trace_path`] per target (each trace
/// costs only the faces its path crosses).
pub fn shortest_path(
    mesh: &Mesh,
    sources: &[Source],
    target: u32,
    options: &VtpOptions,
) -> Result<GeodesicPath, PathError> {
    check_target(mesh, target)?;
    let (field, _, provenance) = solve_with_provenance(mesh, sources, options)?;
    trace_path(mesh, sources, &provenance, &field, target)
}

/// The shortest path from the nearest source to input vertex `target`,
/// rebuilt from the output of [`solve_with_provenance`] (`sources`,
/// `provenance` and `field` must come from one solve on `mesh`).
///
/// Never panics or loops on bad data: provenance that does not describe a
/// path is a [`PathError::Inconsistent`] or [`PathError::StepLimit`].
pub fn trace_path(
    mesh: &Mesh,
    sources: &[Source],
    provenance: &[Provenance],
    field: &DistanceField,
    target: u32,
) -> Result<GeodesicPath, PathError> {
    check_target(mesh, target)?;
    if provenance.len() != mesh.vertex_count() {
        return Err(PathError::ProvenanceLength {
            got: provenance.len(),
            expected: mesh.vertex_count(),
        });
    }
    if field.distance.len() != mesh.input_vertex_count() {
        return Err(PathError::FieldLength {
            got: field.distance.len(),
            expected: mesh.input_vertex_count(),
        });
    }
    if !field.distance[target as usize].is_finite() {
        return Err(PathError::Unreachable { target });
    }
    let mut tracer = Tracer {
        mesh,
        sources,
        dist: &field.distance,
        tol: Tolerance::for_mesh(mesh),
        steps: 0,
        cap: 8 * (mesh.face_count() + mesh.vertex_count()) + 1024,
        points: Vec::new(),
        branches: Vec::new(),
    };
    let mut v = mesh.mesh_vertex(target);
    tracer.push_vertex(v);
    loop {
        tracer.tick()?;
        let bad = |reason| PathError::Inconsistent { vertex: v, reason };
        match provenance[v as usize] {
            Provenance::Unreached => return Err(bad("a vertex on the path was never reached")),
            Provenance::Source(i) => {
                let point = tracer.source_point(i).ok_or(bad("no such source"))?;
                if let SurfacePoint::Vertex(s) = point
                    && s != mesh.pinch_origin(v)
                {
                    return Err(bad("the source vertex is not this vertex"));
                }
                tracer.push(point);
                break;
            }
            Provenance::Vertex { from, .. } => {
                if from as usize >= mesh.vertex_count() {
                    return Err(bad("edge provenance from a vertex not in the mesh"));
                }
                tracer.push_vertex(from);
                v = from;
            }
            Provenance::Window {
                half_edge,
                pseudo_source,
                sigma,
                bend,
            } => {
                if half_edge as usize >= mesh.half_edge_count()
                    || mesh.opposite_vertex(half_edge) != v
                {
                    return Err(bad("the window's face does not have this vertex as apex"));
                }
                match tracer.walk(v, half_edge, pseudo_source, sigma, bend)? {
                    Reached::Vertex(u) => v = u,
                    Reached::Source(i) => {
                        let point = tracer.source_point(i).ok_or(bad("no such source"))?;
                        tracer.push(point);
                        break;
                    }
                }
            }
        }
    }
    let mut points = tracer.points;
    points.reverse();
    let source = field.nearest_source[target as usize];
    GeodesicPath::from_points(mesh, points, source)
        .map_err(|index| PathError::PointOutOfRange { index })
}

fn check_target(mesh: &Mesh, target: u32) -> Result<(), PathError> {
    if target as usize >= mesh.input_vertex_count() {
        return Err(PathError::TargetOutOfRange {
            target,
            vertices: mesh.input_vertex_count(),
        });
    }
    Ok(())
}

// ------------------------------------------------------------ frames

/// The half-edge `i` steps after `e` in its face (0: `e`, 1: next, 2: prev).
/// Its tail is corner `i` of [`corners`]`(e)`.
fn he(e: u32, i: usize) -> u32 {
    3 * Mesh::face_of(e) + (e % 3 + i as u32) % 3
}

/// The corners of the face of `e` in `e`'s frame: tail, head, apex
/// (counter-clockwise; the face lies above the x axis).
fn corners(mesh: &Mesh, e: u32) -> [DVec2; 3] {
    [DVec2::ZERO, DVec2::new(mesh.length(e), 0.0), mesh.apex(e)]
}

/// `q` (in the frame whose face has corners `c`) in the frame of the
/// face's half-edge number `i` (from `c[i]` to `c[i + 1]`).
fn reframe(c: &[DVec2; 3], i: usize, q: DVec2) -> DVec2 {
    let o = c[i];
    let u = (c[(i + 1) % 3] - o).normalize_or_zero();
    let d = q - o;
    DVec2::new(d.dot(u), u.perp_dot(d))
}

/// Signed distance of `q` from the line `a → b`, positive on its left.
fn side(a: DVec2, b: DVec2, q: DVec2) -> f64 {
    (b - a).normalize_or_zero().perp_dot(q - a)
}

/// Whether the direction from corner `k` to `q` lies in the face's angle at
/// that corner (with `slack`).
fn in_wedge(c: &[DVec2; 3], k: usize, q: DVec2, slack: f64) -> bool {
    side(c[k], c[(k + 1) % 3], q) >= -slack && side(c[(k + 2) % 3], c[k], q) >= -slack
}

/// Whether `q` lies in the closed face (with `slack`).
fn in_face(c: &[DVec2; 3], q: DVec2, slack: f64) -> bool {
    (0..3).all(|i| side(c[i], c[(i + 1) % 3], q) >= -slack)
}

/// From corner `k` of a face, coming from `from` and heading to `p`: cross
/// the edge out of the corner (`true`) or the one into it (`false`) first?
/// The line passes the corner on the side of the smaller signed offset, so
/// it leaves the face through the edge whose far end is on that side.
fn prefer_out(c: &[DVec2; 3], k: usize, from: DVec2, p: DVec2) -> bool {
    let r = p - from;
    let off = |q: DVec2| r.perp_dot(q - from);
    let (o, i) = (off(c[(k + 1) % 3]), off(c[(k + 2) % 3]));
    if off(c[k]) > 0.0 { o < i } else { o > i }
}

// ------------------------------------------------------------ the walk

enum Reached {
    /// A pseudo-source vertex (a mesh vertex id, pinch copies separate).
    Vertex(u32),
    /// A point source, by index.
    Source(u32),
}

/// Where the backward line is.
#[derive(Clone, Copy)]
enum State {
    /// About to cross the face of `e` from `x` (in `e`'s frame, on the face's
    /// boundary; corner `corner` if set) towards `p`.
    Face {
        e: u32,
        x: DVec2,
        corner: Option<usize>,
        p: DVec2,
    },
    /// Passing through corner `k` of the face of `e`, coming from `from`.
    Through {
        e: u32,
        k: usize,
        from: DVec2,
        p: DVec2,
    },
}

enum Step {
    Next(State),
    Done(Reached),
    /// This unfolding does not lead to the pseudo-source.
    Fail,
}

/// The other way around a vertex's fan, kept in case the first fails.
struct Branch {
    /// Points recorded when the choice was made.
    len: usize,
    e: u32,
    k: usize,
    p: DVec2,
    out: bool,
}

struct Tracer<'a> {
    mesh: &'a Mesh,
    sources: &'a [Source],
    /// Final distances, per input vertex.
    dist: &'a [f64],
    tol: Tolerance,
    steps: usize,
    cap: usize,
    /// Target first.
    points: Vec<SurfacePoint>,
    branches: Vec<Branch>,
}

impl Tracer<'_> {
    fn tick(&mut self) -> Result<(), PathError> {
        self.steps += 1;
        if self.steps > self.cap {
            return Err(PathError::StepLimit { steps: self.steps });
        }
        Ok(())
    }

    fn snap(&self, magnitude: f64) -> f64 {
        SNAP_MARGINS * self.tol.margin(magnitude)
    }

    fn reach(&self, magnitude: f64) -> f64 {
        REACH_MARGINS * self.tol.margin(magnitude)
    }

    fn push(&mut self, p: SurfacePoint) {
        if self.points.last() != Some(&p) {
            self.points.push(p);
        }
    }

    fn push_vertex(&mut self, v: u32) {
        self.push(SurfacePoint::Vertex(self.mesh.pinch_origin(v)));
    }

    /// Source `i` as a surface point, normalised the way the solver seeds
    /// it (edge ends and face points on edges or corners).
    fn source_point(&self, i: u32) -> Option<SurfacePoint> {
        let mesh = self.mesh;
        let origin = |v: u32| SurfacePoint::Vertex(mesh.pinch_origin(v));
        Some(match *self.sources.get(i as usize)? {
            Source::Vertex(v) => SurfacePoint::Vertex(v),
            Source::EdgePoint { half_edge, t } => {
                if half_edge as usize >= mesh.half_edge_count() {
                    return None;
                }
                if t == 0.0 {
                    origin(mesh.tail(half_edge))
                } else if t == 1.0 {
                    origin(mesh.head(half_edge))
                } else {
                    SurfacePoint::Edge { half_edge, t }
                }
            }
            Source::FacePoint { face, barycentric } => {
                if face as usize >= mesh.face_count() {
                    return None;
                }
                let zeros = barycentric.iter().filter(|&&b| b == 0.0).count();
                if zeros >= 2 {
                    let k = barycentric.iter().position(|&b| b != 0.0).unwrap_or(0);
                    origin(mesh.face(face)[k])
                } else if zeros == 1 {
                    let k = barycentric.iter().position(|&b| b == 0.0).unwrap_or(0);
                    let (i1, i2) = ((k + 1) % 3, (k + 2) % 3);
                    SurfacePoint::Edge {
                        half_edge: 3 * face + i1 as u32,
                        t: barycentric[i2] / (barycentric[i1] + barycentric[i2]),
                    }
                } else {
                    let s: f64 = barycentric.iter().sum();
                    SurfacePoint::Face {
                        face,
                        barycentric: barycentric.map(|b| b / s),
                    }
                }
            }
        })
    }

    /// Follows the straight line from the apex `v` of the face of `h`
    /// through `bend` on `h` back to the pseudo-source `p` (in `h`'s frame).
    fn walk(
        &mut self,
        v: u32,
        h: u32,
        p: DVec2,
        sigma: f64,
        bend: f64,
    ) -> Result<Reached, PathError> {
        let mesh = self.mesh;
        let bad = |reason| PathError::Inconsistent { vertex: v, reason };
        let l = mesh.length(h);
        if !(0.0..=l).contains(&bend) || !p.is_finite() || !sigma.is_finite() {
            return Err(bad("window crossing or pseudo-source out of range"));
        }
        let t = mesh.twin(h).ok_or(bad("window on a boundary half-edge"))?;
        // The face below `h`, in the frame of its half-edge `t`.
        let flip = |q: DVec2| DVec2::new(l - q.x, -q.y);
        let p = flip(p);
        let from = flip(corners(mesh, h)[2]);
        let x = DVec2::new(l - bend, 0.0);
        let snap = self.snap(p.distance(x));
        let mut state = if bend <= snap {
            // The window ends at the tail of `h` (corner 1 of `t`).
            State::Through {
                e: t,
                k: 1,
                from,
                p,
            }
        } else if bend >= l - snap {
            State::Through {
                e: t,
                k: 0,
                from,
                p,
            }
        } else {
            self.push(SurfacePoint::Edge {
                half_edge: h,
                t: bend / l,
            });
            State::Face {
                e: t,
                x,
                corner: None,
                p,
            }
        };
        self.branches.clear();
        loop {
            self.tick()?;
            let step = match state {
                State::Face { e, x, corner, p } => self.cross_face(e, x, corner, p, sigma),
                State::Through { e, k, from, p } => self.through(e, k, from, p),
            };
            match step {
                Step::Next(s) => state = s,
                Step::Done(r) => {
                    self.branches.clear();
                    return Ok(r);
                }
                Step::Fail => loop {
                    // Back to the last vertex passed, the other way round.
                    let b = self.branches.pop().ok_or(bad(
                        "the line towards the window's pseudo-source does not reach it",
                    ))?;
                    self.tick()?;
                    self.points.truncate(b.len);
                    if let Some(s) = self.rotate(b.e, b.k, b.p, b.out) {
                        state = s;
                        break;
                    }
                },
            }
        }
    }

    /// Crossing the face of `e` from `x` towards `p` (both in `e`'s frame).
    fn cross_face(
        &mut self,
        e: u32,
        x: DVec2,
        corner: Option<usize>,
        p: DVec2,
        sigma: f64,
    ) -> Step {
        let mesh = self.mesh;
        let f = Mesh::face_of(e);
        match mesh.face_kind(f) {
            FaceKind::Blocked => return Step::Fail,
            FaceKind::Zipper => {
                // The two long edges are one segment with identical frames
                // (the solver passes windows across unchanged).
                let long = [he(e, 1), he(e, 2)]
                    .into_iter()
                    .find(|&g| mesh.length(g) > 0.0);
                let (Some(g), None) = (long, corner) else {
                    return Step::Fail;
                };
                let Some(t) = mesh.twin(g) else {
                    return Step::Fail;
                };
                if mesh.length(e) <= 0.0 {
                    return Step::Fail;
                }
                self.push(SurfacePoint::Edge {
                    half_edge: t,
                    t: (x.x / mesh.length(t)).clamp(0.0, 1.0),
                });
                return Step::Next(State::Face {
                    e: t,
                    x,
                    corner: None,
                    p,
                });
            }
            FaceKind::Proper => {}
        }
        let c = corners(mesh, e);
        let remaining = p.distance(x);
        let snap = self.snap(remaining);
        // The pseudo-source in this face: a corner or a point source.
        let reach = self.reach(remaining);
        let (k, dk) = (0..3)
            .map(|k| (k, p.distance(c[k])))
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        if dk <= reach {
            let u = mesh.tail(he(e, k));
            let du = self.dist[mesh.pinch_origin(u) as usize];
            // Distances only go down: the vertex is now at most σ away.
            if !(du <= sigma + self.tol.margin(sigma) * REACH_MARGINS) {
                return Step::Fail;
            }
            self.push_vertex(u);
            return Step::Done(Reached::Vertex(u));
        }
        if in_face(&c, p, snap) {
            return match self.point_source_at(e, &c, p, reach) {
                Some(i) => Step::Done(Reached::Source(i)),
                None => Step::Fail,
            };
        }
        // Which edge the line leaves through.
        let i = match corner {
            Some(k) => (k + 1) % 3,
            None => {
                let r = p - x;
                if p.y <= snap {
                    if p.y < -snap {
                        return Step::Fail; // the pseudo-source is behind
                    }
                    // Along the line of `e`: to one of its ends.
                    let k = if r.x < 0.0 { 0 } else { 1 };
                    return Step::Next(State::Through { e, k, from: x, p });
                }
                let dc = r.normalize_or_zero().perp_dot(c[2] - x);
                if dc.abs() <= snap && (c[2] - x).dot(r) > 0.0 {
                    return Step::Next(State::Through {
                        e,
                        k: 2,
                        from: x,
                        p,
                    });
                }
                // Apex left of the line: leave through B→C, else C→A.
                if dc > 0.0 { 1 } else { 2 }
            }
        };
        let g = he(e, i);
        let (xg, pg) = (reframe(&c, i, x), reframe(&c, i, p));
        let len = mesh.length(g);
        let denom = xg.y - pg.y;
        if !(denom > 0.0) {
            return Step::Fail;
        }
        let xc = xg.x + (pg.x - xg.x) * (xg.y / denom);
        if !xc.is_finite() {
            return Step::Fail;
        }
        if xc <= snap {
            return Step::Next(State::Through {
                e,
                k: i,
                from: x,
                p,
            });
        }
        if xc >= len - snap {
            return Step::Next(State::Through {
                e,
                k: (i + 1) % 3,
                from: x,
                p,
            });
        }
        let Some(t) = mesh.twin(g) else {
            return Step::Fail;
        };
        self.push(SurfacePoint::Edge {
            half_edge: g,
            t: xc / len,
        });
        Step::Next(State::Face {
            e: t,
            x: DVec2::new(len - xc, 0.0),
            corner: None,
            p: DVec2::new(len - pg.x, -pg.y),
        })
    }

    /// The line passes through corner `k` of the face of `e`.
    fn through(&mut self, e: u32, k: usize, from: DVec2, p: DVec2) -> Step {
        let mesh = self.mesh;
        let v = mesh.tail(he(e, k));
        self.push_vertex(v);
        let c = corners(mesh, e);
        let snap = self.snap(p.distance(c[k]));
        // Into this face from the corner (the line grazes it, or a window
        // ended at this corner and its rays came through this face).
        if in_wedge(&c, k, p, snap) {
            return Step::Next(State::Face {
                e,
                x: c[k],
                corner: Some(k),
                p,
            });
        }
        let out = prefer_out(&c, k, from, p);
        self.branches.push(Branch {
            len: self.points.len(),
            e,
            k,
            p,
            out: !out,
        });
        match self.rotate(e, k, p, out) {
            Some(s) => Step::Next(s),
            None => Step::Fail,
        }
    }

    /// Turns around corner `k` of the face of `e` (across the edge out of it
    /// if `out`, else the edge into it, and on in that sense) to the first
    /// face whose angle at the corner contains the direction to `p`.
    fn rotate(&self, e: u32, k: usize, p: DVec2, out: bool) -> Option<State> {
        let mesh = self.mesh;
        let v = mesh.tail(he(e, k));
        let fan = mesh.outgoing(v).count() + 1;
        let (mut e, mut k, mut p) = (e, k, p);
        for _ in 0..fan {
            let c = corners(mesh, e);
            let i = if out { k } else { (k + 2) % 3 };
            let g = he(e, i);
            let pg = reframe(&c, i, p);
            let t = mesh.twin(g)?;
            if mesh.face_kind(Mesh::face_of(t)) != FaceKind::Proper {
                return None;
            }
            let len = mesh.length(g);
            p = DVec2::new(len - pg.x, -pg.y);
            e = t;
            // Crossing v→w leaves v at the head of the twin; u→v, the tail.
            k = if out { 1 } else { 0 };
            let c = corners(mesh, e);
            if in_wedge(&c, k, p, self.snap(p.distance(c[k]))) {
                return Some(State::Face {
                    e,
                    x: c[k],
                    corner: Some(k),
                    p,
                });
            }
        }
        None
    }

    /// The point source at `p` (in the frame of `e`, inside its face), if
    /// one is there.
    fn point_source_at(&self, e: u32, c: &[DVec2; 3], p: DVec2, reach: f64) -> Option<u32> {
        let mesh = self.mesh;
        let f = Mesh::face_of(e);
        // p in 3D through its barycentric coordinates in the face.
        let area = (c[1] - c[0]).perp_dot(c[2] - c[0]);
        if !(area > 0.0) {
            return None;
        }
        let b = [
            (c[2] - c[1]).perp_dot(p - c[1]) / area,
            (c[0] - c[2]).perp_dot(p - c[2]) / area,
        ];
        let pos = |k: usize| mesh.position(mesh.tail(he(e, k)));
        let q = pos(0) * b[0] + pos(1) * b[1] + pos(2) * (1.0 - b[0] - b[1]);
        let in_f = |h: u32| Mesh::face_of(h) == f || mesh.twin(h).map(Mesh::face_of) == Some(f);
        (0..self.sources.len() as u32)
            .filter_map(|i| {
                let sp = self.source_point(i)?;
                let here = match sp {
                    SurfacePoint::Face { face, .. } => face == f,
                    SurfacePoint::Edge { half_edge, .. } => in_f(half_edge),
                    SurfacePoint::Vertex(_) => false,
                };
                let d = sp.position(mesh)?.distance(q);
                (here && d <= reach).then_some((i, d))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesics_mesh::{BuildOptions, IndexedTriangles};
    use glam::DVec3;

    fn mesh(positions: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Mesh {
        let soup = IndexedTriangles {
            positions,
            triangles,
        };
        Mesh::build(soup, &BuildOptions::default()).expect("test mesh is valid")
    }

    fn grid_points(w: u32, h: u32) -> Vec<DVec3> {
        (0..h)
            .flat_map(|j| (0..w).map(move |i| DVec3::new(i as f64, j as f64, 0.0)))
            .collect()
    }

    /// Cells `(i, j)` of a `w × h` vertex lattice, each split in two.
    fn cells(w: u32, keep: impl Fn(u32, u32) -> bool, h: u32) -> Vec<[u32; 3]> {
        let mut t = Vec::new();
        for j in 0..h - 1 {
            for i in 0..w - 1 {
                if keep(i, j) {
                    let v = j * w + i;
                    t.push([v, v + 1, v + w + 1]);
                    t.push([v, v + w + 1, v + w]);
                }
            }
        }
        t
    }

    fn path(m: &Mesh, sources: &[Source], target: u32) -> GeodesicPath {
        shortest_path(m, sources, target, &VtpOptions::default()).expect("path exists")
    }

    #[test]
    fn frame_helpers() {
        let c = [DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(1.0, 1.0)];
        // Half-edge 1 runs from (2,0) to (1,1); (1,0), on the face's side,
        // is left of it.
        let q = reframe(&c, 1, DVec2::new(1.0, 0.0));
        assert!((q.x - 0.5f64.sqrt()).abs() < 1e-15 && (q.y - 0.5f64.sqrt()).abs() < 1e-15);
        // (3,0) is outside, right of it.
        assert!(reframe(&c, 1, DVec2::new(3.0, 0.0)).y < 0.0);
        assert_eq!(reframe(&c, 0, DVec2::new(0.3, 0.4)), DVec2::new(0.3, 0.4));
        assert!(in_face(&c, DVec2::new(1.0, 0.5), 0.0));
        assert!(!in_face(&c, DVec2::new(1.0, 1.5), 0.0));
        assert!(in_wedge(&c, 0, DVec2::new(5.0, 1.0), 0.0));
        assert!(!in_wedge(&c, 0, DVec2::new(1.0, 5.0), 0.0));
        // From below, to a point beyond the apex, passing right of it: the
        // line leaves through B→C (the edge out of corner 2 is C→A).
        let from = DVec2::new(1.0, 0.0);
        assert!(!prefer_out(&c, 2, from, DVec2::new(1.1, 3.0)));
        assert!(prefer_out(&c, 2, from, DVec2::new(0.9, 3.0)));
        assert_eq!(he(7, 0), 7);
        assert_eq!(he(7, 1), 8);
        assert_eq!(he(7, 2), 6);
    }

    #[test]
    fn bends_around_a_reflex_corner() {
        // An L-shaped planar domain: the cell (2..4) x (2..4) is missing,
        // (2, 2) is a reflex boundary corner.
        let m = mesh(grid_points(5, 5), cells(5, |i, j| i < 2 || j < 2, 5));
        let (s, t, corner) = (4 * 5 + 1, 5 + 4, 2 * 5 + 2);
        let p = path(&m, &[Source::Vertex(s)], t);
        let (a, b, c) = (m.position(s), m.position(t), m.position(corner));
        assert!((p.length - (a.distance(c) + c.distance(b))).abs() < 1e-14);
        assert!(p.points.contains(&SurfacePoint::Vertex(corner)));
        assert_eq!(p.points.first(), Some(&SurfacePoint::Vertex(s)));
        assert_eq!(p.points.last(), Some(&SurfacePoint::Vertex(t)));
    }

    #[test]
    fn straight_from_face_and_edge_points() {
        let m = mesh(grid_points(6, 6), cells(6, |_, _| true, 6));
        let face = Source::FacePoint {
            face: 0,
            barycentric: [0.2, 0.3, 0.5],
        };
        let q = DVec3::new(0.8, 0.5, 0.0);
        for t in [35u32, 5, 30] {
            let p = path(&m, &[face], t);
            assert!((p.length - q.distance(m.position(t))).abs() < 1e-14);
            assert!(matches!(p.points[0], SurfacePoint::Face { face: 0, .. }));
            assert!(p.polyline[0].distance(q) < 1e-15);
        }
        // Half-edge 3*0+0 runs 0 -> 1; t = 0.25 is (0.25, 0, 0).
        let edge = Source::EdgePoint {
            half_edge: 0,
            t: 0.25,
        };
        let e = DVec3::new(0.25, 0.0, 0.0);
        for t in [35u32, 30, 11] {
            let p = path(&m, &[edge], t);
            assert!((p.length - e.distance(m.position(t))).abs() < 1e-14);
            assert_eq!(
                p.points[0],
                SurfacePoint::Edge {
                    half_edge: 0,
                    t: 0.25
                }
            );
        }
    }

    #[test]
    fn through_a_pinch_vertex() {
        // Two squares touching at one corner (vertex 2 of the first, the
        // shared position (1, 1)).
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(2.0, 2.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
        ];
        let m = mesh(positions, vec![[0, 1, 2], [0, 2, 3], [2, 4, 5], [2, 5, 6]]);
        assert!(m.vertex_count() > m.input_vertex_count());
        let p = path(&m, &[Source::Vertex(0)], 5);
        assert!((p.length - 8f64.sqrt()).abs() < 1e-14);
        assert!(p.points.contains(&SurfacePoint::Vertex(2)));
        // The pinch copy is folded and not repeated.
        let twos = p
            .points
            .iter()
            .filter(|&&q| q == SurfacePoint::Vertex(2))
            .count();
        assert_eq!(twos, 1);
    }

    #[test]
    fn bad_provenance_is_an_error() {
        let m = mesh(grid_points(3, 3), cells(3, |_, _| true, 3));
        let sources = [Source::Vertex(0)];
        let (field, _, mut prov) =
            solve_with_provenance(&m, &sources, &VtpOptions::default()).expect("solves");
        prov[4] = Provenance::Vertex {
            from: 4,
            length: 0.0,
        };
        assert!(matches!(
            trace_path(&m, &sources, &prov, &field, 4),
            Err(PathError::StepLimit { .. })
        ));
        prov[4] = Provenance::Window {
            half_edge: 0,
            pseudo_source: DVec2::ZERO,
            sigma: 0.0,
            bend: 0.5,
        };
        assert!(matches!(
            trace_path(&m, &sources, &prov, &field, 4),
            Err(PathError::Inconsistent { vertex: 4, .. })
        ));
        prov[4] = Provenance::Unreached;
        assert!(matches!(
            trace_path(&m, &sources, &prov, &field, 4),
            Err(PathError::Inconsistent { .. })
        ));
        assert_eq!(
            GeodesicPath::from_points(&m, vec![SurfacePoint::Vertex(99)], 0),
            Err(0)
        );
    }
}
