//! The window-tree propagation of Chen and Han with Xin and Wang's
//! improvements, scheduled by a priority queue (ICH) or buckets (FWP-CH).

use std::time::Instant;

use geodesics_mesh::Mesh;
use geodesics_window::prune::vertex_check;
use geodesics_window::{
    DistanceField, FaceKind, NO_SOURCE, SolverSetup, Source, Stats, Tolerance, Triangle, Window,
    check_spikes, seeds, validate_sources,
};
use glam::DVec2;

use crate::queue::Queue;
use crate::rules::{self, Angle, Corners};
use crate::{IchError, IchOptions, Schedule};

const NONE: u32 = u32::MAX;

/// What waits in the queue.
#[derive(Clone, Copy, Debug)]
enum Item {
    /// A window about to cross a face.
    Window(Pending),
    /// A pseudo-source vertex to emit from (if its distance still calls for
    /// it when popped).
    Vertex(u32),
}

/// A window waiting in the queue.
#[derive(Clone, Copy, Debug)]
struct Pending {
    w: Window,
    /// The half-edge it lies on (it is about to cross that half-edge's face).
    h: u32,
    /// Whether the corner of the face behind it (opposite its half-edge's
    /// twin) may filter it when popped: it then lies on the source side in
    /// the configuration of [`vertex_check`]. False for the windows a point
    /// source puts on the edges of its own face, whose source is inside
    /// that face.
    third: bool,
}

struct Solver<'a> {
    mesh: &'a Mesh,
    options: &'a IchOptions,
    /// Vertices that have a distance, reported to the options' progress
    /// now and then.
    reached: u64,
    tol: Tolerance,
    kind: Vec<FaceKind>,
    /// Per half-edge: Chen and Han's angle record (one angle one split).
    angle: Vec<Angle>,
    dist: Vec<f64>,
    src: Vec<u32>,
    pseudo: Vec<bool>,
    /// Per vertex: distance at which it last emitted pseudo-source windows.
    emitted: Vec<f64>,
    /// Per vertex: index into `groups` of its pinch group, or NONE.
    group_of: Vec<u32>,
    groups: Vec<Vec<u32>>,
    queue: Queue<Item>,
    /// Windows in the queue.
    live: u64,
    stats: Stats,
}

pub(crate) fn solve(
    mesh: &Mesh,
    sources: &[Source],
    options: &IchOptions,
) -> Result<(DistanceField, Stats), IchError> {
    let start = Instant::now();
    validate(mesh, sources, options)?;
    options.progress.start(mesh.vertex_count());
    let mut s = Solver::new(mesh, options);
    for (i, source) in sources.iter().enumerate() {
        s.seed(i as u32, source);
    }
    s.run();
    options.progress.set_reached(s.reached);
    let mut stats = std::mem::take(&mut s.stats);
    stats.threads = 1;
    let field = s.finish();
    stats.total_seconds = start.elapsed().as_secs_f64();
    stats.peak_window_bytes = stats.peak_live_windows * std::mem::size_of::<Window>() as u64;
    Ok((field, stats))
}

fn validate(mesh: &Mesh, sources: &[Source], options: &IchOptions) -> Result<(), IchError> {
    validate_sources(mesh, sources, options.max_distance)?;
    check_spikes(mesh)?;
    Ok(())
}

/// The width of FWP's buckets: the mean edge length (Xu et al. 2015), or
/// the mesh scale if that is not a positive number.
fn bucket_width(mesh: &Mesh) -> f64 {
    let h = mesh.average_edge_length();
    if h.is_finite() && h > 0.0 {
        h
    } else {
        let d = mesh.bbox_diagonal();
        if d.is_finite() && d > 0.0 { d } else { 1.0 }
    }
}

impl<'a> Solver<'a> {
    fn new(mesh: &'a Mesh, options: &'a IchOptions) -> Self {
        let tol = Tolerance::for_mesh(mesh);
        let nh = mesh.half_edge_count();
        let nv = mesh.vertex_count();
        let SolverSetup {
            kind,
            pseudo,
            group_of,
            groups,
            ..
        } = SolverSetup::new(mesh, &tol);
        let queue = match options.schedule {
            Schedule::PriorityQueue => Queue::heap(),
            Schedule::Fwp => Queue::buckets(bucket_width(mesh)),
        };
        Solver {
            mesh,
            reached: 0,
            options,
            tol,
            kind,
            angle: vec![Angle::EMPTY; nh],
            dist: vec![f64::INFINITY; nv],
            src: vec![NO_SOURCE; nv],
            pseudo,
            emitted: vec![f64::INFINITY; nv],
            group_of,
            groups,
            queue,
            live: 0,
            stats: Stats::default(),
        }
    }

    // ---------------------------------------------------------------- seeds

    fn seed(&mut self, i: u32, source: &Source) {
        let seeds = seeds(self.mesh, &self.kind, source, i);
        for &v in &seeds.pseudo {
            self.force_pseudo(v);
        }
        for &(v, d) in &seeds.distances {
            self.relax(v, d, i);
        }
        for &(t, w) in &seeds.windows {
            self.stats.windows_created += 1;
            self.push_window(w, t, false);
        }
    }

    fn force_pseudo(&mut self, v: u32) {
        self.pseudo[v as usize] = true;
        let g = self.group_of[v as usize];
        if g != NONE {
            for k in 0..self.groups[g as usize].len() {
                let u = self.groups[g as usize][k];
                self.pseudo[u as usize] = true;
            }
        }
    }

    // ------------------------------------------------------------ distances

    /// Lowers the distance of `v` (and its pinch copies) to `d` if shorter.
    #[inline]
    fn relax(&mut self, v: u32, d: f64, s: u32) {
        if !(d < self.dist[v as usize]) {
            return;
        }
        self.set_dist(v, d, s);
        let g = self.group_of[v as usize];
        if g != NONE {
            for k in 0..self.groups[g as usize].len() {
                let u = self.groups[g as usize][k];
                if u != v && d < self.dist[u as usize] {
                    self.set_dist(u, d, s);
                }
            }
        }
    }

    #[inline]
    fn set_dist(&mut self, v: u32, d: f64, s: u32) {
        let vi = v as usize;
        if self.dist[vi] == f64::INFINITY {
            self.reached += 1;
            self.options.progress.note_reached(self.reached);
        }
        self.dist[vi] = d;
        self.src[vi] = s;
        // A pseudo-source (re-)emits when it is first reached and whenever
        // its distance drops by more than the tolerance after that.
        if self.pseudo[vi] && self.should_emit(vi, d) {
            self.queue.push(d, Item::Vertex(v));
        }
    }

    #[inline]
    fn should_emit(&self, v: usize, d: f64) -> bool {
        self.tol.must_emit(d, self.emitted[v])
    }

    // ------------------------------------------------------------ windows

    #[inline]
    fn push_window(&mut self, w: Window, h: u32, third: bool) {
        self.live += 1;
        if self.live > self.stats.peak_live_windows {
            self.stats.peak_live_windows = self.live;
        }
        let key = w.least_distance();
        self.queue.push(key, Item::Window(Pending { w, h, third }));
    }

    // ------------------------------------------------------------ main loop

    fn run(&mut self) {
        let sorted = self.queue.is_sorted();
        while let Some((key, item)) = self.queue.pop() {
            let beyond = self.options.max_distance.is_some_and(|m| key > m);
            if beyond && sorted {
                break;
            }
            match item {
                Item::Vertex(v) => {
                    let d = self.dist[v as usize];
                    if !beyond && self.should_emit(v as usize, d) {
                        self.stats.vertex_pops += 1;
                        self.emit(v);
                    }
                }
                Item::Window(p) => {
                    self.live -= 1;
                    if !beyond {
                        self.propagate(p);
                    }
                }
            }
        }
    }

    /// Pseudo-source `v`: relax its neighbours along edges and put one
    /// full-edge window with source `v` on each edge opposite it (Xin and
    /// Wang; Section 5.2 of Qin et al., "Saddle Vertices").
    fn emit(&mut self, v: u32) {
        let mesh = self.mesh;
        let vi = v as usize;
        let d = self.dist[vi];
        let s = self.src[vi];
        self.emitted[vi] = d;
        self.stats.pseudo_source_emissions += 1;
        for h in mesh.outgoing(v) {
            let p = Mesh::prev(h);
            self.relax(mesh.head(h), d + mesh.length(h), s);
            self.relax(mesh.tail(p), d + mesh.length(p), s);
            if self.kind[Mesh::face_of(h) as usize] != FaceKind::Proper {
                continue;
            }
            let o = Mesh::next(h);
            let Some(t) = mesh.twin(o) else { continue };
            let l = mesh.length(o);
            let c = self.mesh.apex(o);
            let w = Window::across_edge(l, c, d, s);
            self.stats.windows_created += 1;
            self.push_window(w, t, true);
        }
    }

    /// Propagates one window through the face of its half-edge.
    fn propagate(&mut self, pending: Pending) {
        let Pending { w, h, third } = pending;
        let mesh = self.mesh;
        match self.kind[Mesh::face_of(h) as usize] {
            FaceKind::Proper => {}
            FaceKind::Zipper => {
                if let Some(t) = mesh.zipper_exit(h).and_then(|g| mesh.twin(g)) {
                    self.push_window(w, t, third);
                }
                return;
            }
            FaceKind::Blocked => return,
        }
        let n = Mesh::next(h);
        let p = Mesh::prev(h);
        let (a, b, c) = (mesh.tail(h), mesh.head(h), mesh.tail(p));
        let l = mesh.length(h);
        let corners = Corners {
            a: self.dist[a as usize],
            b: self.dist[b as usize],
            c: self.dist[c as usize],
        };
        // The vertex filter again, with the distances known now (they only
        // drop while the window waits): the ends of its edge and, when the
        // configuration allows, the corner behind it.
        let behind = match mesh.twin(h) {
            Some(t) if third => {
                let q = self.mesh.apex(t);
                let dq = self.dist[mesh.opposite_vertex(t) as usize];
                (DVec2::new(l - q.x, -q.y), dq)
            }
            _ => (DVec2::ZERO, f64::INFINITY),
        };
        if vertex_check(&w, l, corners.a, corners.b, behind.0, behind.1, &self.tol) {
            return;
        }
        let tri = Triangle::with_lengths(l, self.mesh.apex(h), mesh.length(p), mesh.length(n));
        let out = rules::cross(&w, &tri, &mut self.angle[h as usize], corners, &self.tol);
        self.relax(c, out.apex, w.source);
        let props = u64::from(out.propagations);
        self.stats.window_propagations += props;
        self.stats.windows_created += props;
        if let (Some(cw), Some(t)) = (out.left, mesh.twin(p)) {
            self.push_window(cw, t, true);
        }
        if let (Some(cw), Some(t)) = (out.right, mesh.twin(n)) {
            self.push_window(cw, t, true);
        }
    }

    fn finish(self) -> DistanceField {
        DistanceField::from_vertices(self.mesh, self.options.max_distance, |v| {
            (self.dist[v], self.src[v])
        })
    }
}
