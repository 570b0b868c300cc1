//! The MMP propagation: windows kept on edges, a window queue (priority
//! queue or FWP buckets), interval trimming on insertion, pseudo-sources.

use std::collections::VecDeque;
use std::time::Instant;

use geodesics_mesh::Mesh;
use geodesics_window::{
    DistanceField, FaceKind, NO_SOURCE, Progress, SolverSetup, Source, Stats, Tolerance, Triangle,
    Window, seeds, validate_sources,
};
use glam::{DVec2, DVec3};

use crate::trim::{Cone, new_wins, subtract};
use crate::{MmpError, MmpOptions, Schedule};

pub(crate) const NONE: u32 = u32::MAX;
/// Queue items: window ids below this bit, vertex events with it set.
const VERTEX_ITEM: u32 = 1 << 31;
/// Root windows: `origin` is a pseudo-source vertex, or a point source
/// `i` tagged `SOURCE_ORIGIN | i`.
pub(crate) const SOURCE_ORIGIN: u32 = 1 << 31;

const PROPAGATED: u8 = 1;
const DEAD: u8 = 2;

/// A window kept on an edge for the whole run (MMP never frees one: the
/// path backtrace walks parents).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Win {
    /// Interval in the frame of the edge's canonical half-edge (the
    /// smaller of the two ids); windows of both directions share it.
    pub c0: f64,
    /// End of the interval (canonical frame).
    pub c1: f64,
    /// Distance function along the edge (canonical frame): the
    /// pseudo-source's foot, height, and distance from the source.
    pub cone: Cone,
    /// Index of the source.
    pub source: u32,
    /// The half-edge whose face this window lights.
    pub h: u32,
    /// The window it was propagated from, `NONE` for a root.
    pub parent: u32,
    /// For a root: the pseudo-source vertex, or `SOURCE_ORIGIN | source`.
    pub origin: u32,
}

/// How a vertex got its distance (for the backtrace).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Prov {
    Unreached,
    /// Straight from point source (or source vertex) `.0`.
    Source(u32),
    /// Along an edge from pseudo-source `from` (or from a pinch sibling).
    Vertex {
        from: u32,
    },
    /// As the apex of window `win`'s face, crossing its edge at `at` (in
    /// the frame of the window's half-edge).
    Window {
        win: u32,
        at: f64,
    },
}

/// A radix heap on the bits of non-negative `f64` keys (Ahuja et al.
/// 1990): window keys never drop below the last popped key (a child's
/// smallest distance is at least its parent's), so items are kept in 65
/// buckets by the highest bit in which their key differs from the last
/// popped one, and only the lowest non-empty bucket is ever sorted out.
/// A key below the last popped one (by rounding) is popped next.
struct RadixHeap {
    last: u64,
    len: usize,
    buckets: Vec<Vec<(u64, u32)>>,
}

impl RadixHeap {
    fn new() -> Self {
        RadixHeap {
            last: 0,
            len: 0,
            buckets: vec![Vec::new(); 65],
        }
    }

    #[inline]
    fn bucket(last: u64, key: u64) -> usize {
        (64 - (key.max(last) ^ last).leading_zeros()) as usize
    }

    #[inline]
    fn push(&mut self, key: u64, item: u32) {
        self.buckets[Self::bucket(self.last, key)].push((key, item));
        self.len += 1;
    }

    fn pop(&mut self) -> Option<(u64, u32)> {
        if self.len == 0 {
            return None;
        }
        if self.buckets[0].is_empty() {
            let i = self.buckets.iter().position(|b| !b.is_empty())?;
            let mut moved = std::mem::take(&mut self.buckets[i]);
            let last = self.last;
            self.last = moved.iter().map(|e| e.0.max(last)).min()?;
            for &e in &moved {
                self.buckets[Self::bucket(self.last, e.0)].push(e);
            }
            // Every moved item went to a lower bucket: reuse the buffer.
            moved.clear();
            self.buckets[i] = moved;
        }
        self.len -= 1;
        self.buckets[0].pop()
    }
}

enum Queue {
    Heap(RadixHeap),
    Buckets {
        width: f64,
        cur: usize,
        buckets: Vec<VecDeque<(u64, u32)>>,
        len: usize,
    },
}

/// Largest bucket index (keys beyond share the last bucket; order inside a
/// bucket does not matter for exactness).
const MAX_BUCKETS: usize = 1 << 22;

impl Queue {
    fn push(&mut self, key: f64, item: u32) {
        match self {
            Queue::Heap(h) => h.push(key.to_bits(), item),
            Queue::Buckets {
                width,
                cur,
                buckets,
                len,
            } => {
                let i = ((key / *width) as usize).clamp(*cur, MAX_BUCKETS);
                if i >= buckets.len() {
                    buckets.resize_with(i + 1, VecDeque::new);
                }
                buckets[i].push_back((key.to_bits(), item));
                *len += 1;
            }
        }
    }

    fn pop(&mut self) -> Option<(u64, u32)> {
        match self {
            Queue::Heap(h) => h.pop(),
            Queue::Buckets {
                cur, buckets, len, ..
            } => {
                if *len == 0 {
                    return None;
                }
                while *cur < buckets.len() {
                    if let Some(x) = buckets[*cur].pop_front() {
                        *len -= 1;
                        return Some(x);
                    }
                    // Release the drained bucket's memory.
                    buckets[*cur] = VecDeque::new();
                    *cur += 1;
                }
                None
            }
        }
    }

    fn is_heap(&self) -> bool {
        matches!(self, Queue::Heap(_))
    }
}

/// Everything a finished solve keeps for distance read-out and paths.
pub(crate) struct Solved {
    pub tol: Tolerance,
    pub kind: Vec<FaceKind>,
    pub dist: Vec<f64>,
    pub prov: Vec<Prov>,
    pub edge_of: Vec<u32>,
    pub edge_he: Vec<u32>,
    pub lists: Vec<Vec<u32>>,
    pub wins: Vec<Win>,
    pub source_points: Vec<DVec3>,
    pub stats: Stats,
}

struct Solver<'a> {
    mesh: &'a Mesh,
    max_distance: Option<f64>,
    /// Vertices that have a distance, reported to `progress` now and then.
    reached: u64,
    progress: Progress,
    tol: Tolerance,
    kind: Vec<FaceKind>,
    pseudo: Vec<bool>,
    dist: Vec<f64>,
    src: Vec<u32>,
    prov: Vec<Prov>,
    emitted: Vec<f64>,
    group_of: Vec<u32>,
    groups: Vec<Vec<u32>>,
    /// Per half-edge: its undirected edge.
    edge_of: Vec<u32>,
    /// Per edge: its canonical half-edge (the smaller id).
    edge_he: Vec<u32>,
    /// Per edge: ids of its live windows, sorted and disjoint along it.
    lists: Vec<Vec<u32>>,
    wins: Vec<Win>,
    state: Vec<u8>,
    queue: Queue,
    stats: Stats,
    source_points: Vec<DVec3>,
    // Scratch for insertion (no allocation per window once warm).
    lost: Vec<(f64, f64)>,
    pieces: Vec<(f64, f64)>,
    rebuilt: Vec<u32>,
}

pub(crate) fn validate(
    mesh: &Mesh,
    sources: &[Source],
    options: &MmpOptions,
) -> Result<(), MmpError> {
    validate_sources(mesh, sources, options.max_distance)?;
    Ok(())
}

/// The point of a source (its position in 3D).
pub(crate) fn source_point(mesh: &Mesh, s: &Source) -> DVec3 {
    match *s {
        Source::Vertex(v) => mesh.position(mesh.mesh_vertex(v)),
        Source::EdgePoint { half_edge: h, t } => {
            let a = mesh.position(mesh.tail(h));
            let b = mesh.position(mesh.head(h));
            a + (b - a) * t
        }
        Source::FacePoint { face, barycentric } => {
            let c = mesh.face(face).map(|v| mesh.position(v));
            let s: f64 = barycentric.iter().sum();
            (c[0] * barycentric[0] + c[1] * barycentric[1] + c[2] * barycentric[2]) / s
        }
    }
}

pub(crate) fn solve(
    mesh: &Mesh,
    sources: &[Source],
    options: &MmpOptions,
) -> Result<(DistanceField, Solved), MmpError> {
    let start = Instant::now();
    validate(mesh, sources, options)?;
    options.progress.start(mesh.vertex_count());
    let mut s = Solver::new(mesh, options);
    for (i, source) in sources.iter().enumerate() {
        s.source_points.push(source_point(mesh, source));
        s.seed(i as u32, source);
    }
    s.run();
    s.progress.set_reached(s.reached);
    let field = s.finish_field();
    let mut solved = s.into_solved();
    solved.stats.total_seconds = start.elapsed().as_secs_f64();
    solved.stats.threads = 1;
    Ok((field, solved))
}

impl<'a> Solver<'a> {
    fn new(mesh: &'a Mesh, options: &MmpOptions) -> Self {
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
        let mut edge_of = vec![NONE; nh];
        let mut edge_he = Vec::new();
        for h in 0..nh as u32 {
            match mesh.twin(h) {
                Some(t) if t < h => edge_of[h as usize] = edge_of[t as usize],
                _ => {
                    edge_of[h as usize] = edge_he.len() as u32;
                    edge_he.push(h);
                }
            }
        }
        let queue = match options.schedule {
            Schedule::PriorityQueue => Queue::Heap(RadixHeap::new()),
            Schedule::Fwp => {
                let mut width = mesh.average_edge_length();
                if !(width > 0.0 && width.is_finite()) {
                    width = mesh.bbox_diagonal().max(1.0);
                }
                Queue::Buckets {
                    width,
                    cur: 0,
                    buckets: Vec::new(),
                    len: 0,
                }
            }
        };
        Solver {
            mesh,
            reached: 0,
            progress: options.progress.clone(),
            max_distance: options.max_distance,
            tol,
            kind,
            pseudo,
            dist: vec![f64::INFINITY; nv],
            src: vec![NO_SOURCE; nv],
            prov: vec![Prov::Unreached; nv],
            emitted: vec![f64::INFINITY; nv],
            group_of,
            groups,
            lists: vec![Vec::new(); edge_he.len()],
            edge_of,
            edge_he,
            wins: Vec::new(),
            state: Vec::new(),
            queue,
            stats: Stats::default(),
            source_points: Vec::new(),
            lost: Vec::new(),
            pieces: Vec::new(),
            rebuilt: Vec::new(),
        }
    }

    // ---------------------------------------------------------------- seeds

    fn seed(&mut self, i: u32, source: &Source) {
        let seeds = seeds(self.mesh, &self.kind, source, i);
        for &v in &seeds.pseudo {
            self.force_pseudo(v);
        }
        for &(v, d) in &seeds.distances {
            self.relax(v, d, i, Prov::Source(i));
        }
        for &(t, w) in &seeds.windows {
            self.insert(t, &w, NONE, SOURCE_ORIGIN | i);
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

    #[inline]
    fn relax(&mut self, v: u32, d: f64, s: u32, how: Prov) {
        if !(d < self.dist[v as usize]) {
            return;
        }
        self.set_dist(v, d, s, how);
        let g = self.group_of[v as usize];
        if g != NONE {
            for k in 0..self.groups[g as usize].len() {
                let u = self.groups[g as usize][k];
                if u != v && d < self.dist[u as usize] {
                    self.set_dist(u, d, s, Prov::Vertex { from: v });
                }
            }
        }
    }

    #[inline]
    fn set_dist(&mut self, v: u32, d: f64, s: u32, how: Prov) {
        let vi = v as usize;
        if self.dist[vi] == f64::INFINITY {
            self.reached += 1;
            self.progress.note_reached(self.reached);
        }
        self.dist[vi] = d;
        self.src[vi] = s;
        self.prov[vi] = how;
        // Only pseudo-sources act when their distance is final.
        if self.pseudo[vi] && self.should_emit(vi, d) {
            self.queue.push(d, VERTEX_ITEM | v);
        }
    }

    #[inline]
    fn should_emit(&self, v: usize, d: f64) -> bool {
        self.tol.must_emit(d, self.emitted[v])
    }

    // ------------------------------------------------------------ main loop

    fn run(&mut self) {
        let heap = self.queue.is_heap();
        while let Some((key, item)) = self.queue.pop() {
            let d = f64::from_bits(key);
            if let Some(m) = self.max_distance
                && d > m
            {
                // The heap pops in order: nothing after matters. Buckets
                // are unordered inside: skip this item only.
                if heap {
                    break;
                }
                continue;
            }
            if item & VERTEX_ITEM != 0 {
                let v = item & !VERTEX_ITEM;
                let vi = v as usize;
                if self.dist[vi].to_bits() == key && self.should_emit(vi, d) {
                    self.stats.vertex_pops += 1;
                    self.emit(v);
                }
            } else {
                let id = item as usize;
                if self.state[id] != 0 || self.key(&self.wins[id]).to_bits() != key {
                    continue; // propagated, dead, or re-keyed since
                }
                self.state[id] = PROPAGATED;
                self.propagate(item);
            }
        }
    }

    /// Pseudo-source `v`: relax its neighbours along edges and put one
    /// full-edge window with pseudo-source `v` on each edge opposite it
    /// (Section 4 of Surazhsky et al., "saddle vertices"; as VTP's).
    fn emit(&mut self, v: u32) {
        let mesh = self.mesh;
        let vi = v as usize;
        let d = self.dist[vi];
        let s = self.src[vi];
        self.emitted[vi] = d;
        self.stats.pseudo_source_emissions += 1;
        for h in mesh.outgoing(v) {
            let a = mesh.head(h);
            let p = Mesh::prev(h);
            let b = mesh.tail(p);
            self.relax(a, d + mesh.length(h), s, Prov::Vertex { from: v });
            self.relax(b, d + mesh.length(p), s, Prov::Vertex { from: v });
            if self.kind[Mesh::face_of(h) as usize] != FaceKind::Proper {
                continue;
            }
            let o = Mesh::next(h);
            let Some(t) = mesh.twin(o) else { continue };
            let l = mesh.length(o);
            let c = self.mesh.apex(o);
            let w = Window::across_edge(l, c, d, s);
            self.insert(t, &w, NONE, v);
        }
    }

    /// Queue key: the window's smallest distance.
    #[inline]
    fn key(&self, w: &Win) -> f64 {
        w.cone.min_on(w.c0, w.c1)
    }

    /// The window in the frame of its own half-edge.
    #[inline]
    fn own(&self, w: &Win) -> Window {
        own_window(self.mesh, &self.edge_of, &self.edge_he, w)
    }

    /// One window through the face beyond its edge: light the apex, and
    /// insert the children on the two far edges (Section 3.2).
    fn propagate(&mut self, id: u32) {
        let mesh = self.mesh;
        let win = self.wins[id as usize];
        let h = win.h;
        let f = Mesh::face_of(h);
        let w = self.own(&win);
        match self.kind[f as usize] {
            FaceKind::Proper => {
                let n = Mesh::next(h);
                let p = Mesh::prev(h);
                let tri = Triangle::with_lengths(
                    mesh.length(h),
                    self.mesh.apex(h),
                    mesh.length(p),
                    mesh.length(n),
                );
                let (d, sp) = w.apex_distance(&tri);
                self.relax(mesh.tail(p), d, w.source, Prov::Window { win: id, at: sp });
                let (left, right) = w.propagate(&tri);
                if let Some(cw) = left {
                    self.stats.window_propagations += 1;
                    if let Some(t) = mesh.twin(p) {
                        self.insert(t, &cw, id, NONE);
                    }
                }
                if let Some(cw) = right {
                    self.stats.window_propagations += 1;
                    if let Some(t) = mesh.twin(n) {
                        self.insert(t, &cw, id, NONE);
                    }
                }
            }
            FaceKind::Zipper => {
                if let Some(t) = mesh.zipper_exit(h).and_then(|g| mesh.twin(g)) {
                    self.insert(t, &w, id, NONE);
                }
            }
            FaceKind::Blocked => {}
        }
    }

    fn new_window(&mut self, w: Win, state: u8) -> u32 {
        let id = self.wins.len() as u32;
        self.wins.push(w);
        self.state.push(state);
        self.stats.windows_created += 1;
        if state == 0 {
            let k = self.key(&w);
            self.queue.push(k, id);
        }
        id
    }

    /// Inserts window `w` (in the frame of half-edge `h`, lighting the face
    /// of `h`) into the edge's list with interval trimming: on every
    /// overlap with a kept window, each point goes to the window that is
    /// shorter there, cut at the exact tie point (`trim::new_wins`). A kept
    /// window may shrink, vanish, or split in up to three pieces; the new
    /// one survives as up to (number of overlaps + 1) pieces.
    fn insert(&mut self, h: u32, w: &Window, parent: u32, origin: u32) {
        let mesh = self.mesh;
        let l = mesh.length(h);
        let e = self.edge_of[h as usize] as usize;
        let flip = self.edge_he[e] != h;
        let (b0, b1) = (w.b0.max(0.0), w.b1.min(l));
        if !(b0 < b1) {
            return;
        }
        let (a0, a1) = if flip { (l - b1, l - b0) } else { (b0, b1) };
        let cone_new = Cone {
            px: if flip { l - w.p.x } else { w.p.x },
            py: -w.p.y.min(0.0),
            sigma: w.sigma,
        };
        let nw = Win {
            c0: a0,
            c1: a1,
            cone: cone_new,
            source: w.source,
            h,
            parent,
            origin,
        };
        let list = std::mem::take(&mut self.lists[e]);
        // First kept window ending after a0.
        let i0 = list.partition_point(|&o| self.wins[o as usize].c1 <= a0);
        let mut i1 = i0;
        while i1 < list.len() && self.wins[list[i1] as usize].c0 < a1 {
            i1 += 1;
        }
        let mut lost = std::mem::take(&mut self.lost);
        let mut pieces = std::mem::take(&mut self.pieces);
        let mut rebuilt = std::mem::take(&mut self.rebuilt);
        lost.clear();
        rebuilt.clear();
        for &o in &list[i0..i1] {
            let ow = self.wins[o as usize];
            let (c0, c1) = (a0.max(ow.c0), a1.min(ow.c1));
            if !(c0 < c1) {
                rebuilt.push(o);
                continue;
            }
            let wins = new_wins(&cone_new, &ow.cone, c0, c1, &self.tol);
            // The new window loses the rest of the overlap.
            subtract(c0, c1, wins.as_slice(), &mut lost);
            if wins.n == 0 {
                rebuilt.push(o);
                continue;
            }
            // The kept window loses what the new one wins.
            pieces.clear();
            subtract(ow.c0, ow.c1, wins.as_slice(), &mut pieces);
            let st = self.state[o as usize];
            match pieces.len() {
                0 => self.state[o as usize] = DEAD,
                _ => {
                    for (k, &(x0, x1)) in pieces.iter().enumerate() {
                        let mut piece = ow;
                        piece.c0 = x0;
                        piece.c1 = x1;
                        if k == 0 {
                            self.wins[o as usize] = piece;
                            if st == 0 {
                                let key = self.key(&piece);
                                self.queue.push(key, o);
                            }
                            rebuilt.push(o);
                        } else {
                            let id = self.new_window(piece, st);
                            rebuilt.push(id);
                        }
                    }
                }
            }
        }
        // The new window's surviving pieces.
        pieces.clear();
        subtract(a0, a1, &lost, &mut pieces);
        for &(x0, x1) in &pieces {
            let mut piece = nw;
            piece.c0 = x0;
            piece.c1 = x1;
            let id = self.new_window(piece, 0);
            rebuilt.push(id);
        }
        let wins = &self.wins;
        rebuilt.sort_unstable_by(|&x, &y| wins[x as usize].c0.total_cmp(&wins[y as usize].c0));
        let mut list = list;
        list.splice(i0..i1, rebuilt.iter().copied());
        self.lists[e] = list;
        self.lost = lost;
        self.pieces = pieces;
        self.rebuilt = rebuilt;
    }

    fn finish_field(&self) -> DistanceField {
        DistanceField::from_vertices(self.mesh, self.max_distance, |v| {
            (self.dist[v], self.src[v])
        })
    }

    fn into_solved(self) -> Solved {
        let mut stats = self.stats;
        let kept = self.wins.len() as u64;
        stats.peak_live_windows = kept;
        let list_bytes: usize = self
            .lists
            .iter()
            .map(|l| l.capacity() * std::mem::size_of::<u32>())
            .sum::<usize>()
            + self.lists.capacity() * std::mem::size_of::<Vec<u32>>();
        stats.peak_window_bytes = (self.wins.capacity() * std::mem::size_of::<Win>()
            + self.state.capacity()
            + list_bytes) as u64;
        // Trimming is done at insertion and counted with propagation.
        stats.propagation_seconds = 0.0;
        Solved {
            tol: self.tol,
            kind: self.kind,
            dist: self.dist,
            prov: self.prov,
            edge_of: self.edge_of,
            edge_he: self.edge_he,
            lists: self.lists,
            wins: self.wins,
            source_points: self.source_points,
            stats,
        }
    }
}

/// A kept window in the frame of its own half-edge.
#[inline]
pub(crate) fn own_window(mesh: &Mesh, edge_of: &[u32], edge_he: &[u32], w: &Win) -> Window {
    let e = edge_of[w.h as usize];
    let (b0, b1, px) = if edge_he[e as usize] == w.h {
        (w.c0, w.c1, w.cone.px)
    } else {
        let l = mesh.length(w.h);
        ((l - w.c1).max(0.0), (l - w.c0).max(0.0), l - w.cone.px)
    };
    Window {
        b0,
        b1,
        p: DVec2::new(px, -w.cone.py),
        sigma: w.cone.sigma,
        source: w.source,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesics_mesh::{BuildOptions, IndexedTriangles};

    /// A 2×2 square split along its diagonal 0–2 (half-edges 2 and 3).
    fn square() -> Mesh {
        let soup = IndexedTriangles {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(2.0, 2.0, 0.0),
                DVec3::new(0.0, 2.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        Mesh::build(soup, &BuildOptions::default()).unwrap()
    }

    fn win(b0: f64, b1: f64, px: f64, py: f64, sigma: f64) -> Window {
        Window {
            b0,
            b1,
            p: DVec2::new(px, py),
            sigma,
            source: 0,
        }
    }

    /// The kept intervals on the edge of `h`, in `h`'s frame, with sigmas.
    fn kept(s: &Solver, h: u32) -> Vec<(f64, f64, f64)> {
        let e = s.edge_of[h as usize] as usize;
        let mut out: Vec<(f64, f64, f64)> = s.lists[e]
            .iter()
            .map(|&id| {
                let w = own_window(s.mesh, &s.edge_of, &s.edge_he, &s.wins[id as usize]);
                (w.b0, w.b1, w.sigma)
            })
            .collect();
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out
    }

    #[test]
    fn a_better_window_inside_splits_the_kept_one_in_two() {
        let mesh = square();
        assert_eq!(mesh.twin(3), Some(2));
        let options = MmpOptions::default();
        let mut s = Solver::new(&mesh, &options);
        let l = mesh.length(2);
        s.insert(2, &win(0.0, l, 1.0, -1.0, 1.0), NONE, 0);
        // Same pseudo-source position, much nearer the source: wins on its
        // whole interval, the kept one keeps both sides.
        s.insert(2, &win(1.0, 2.0, 1.0, -1.0, 0.0), NONE, 0);
        let k = kept(&s, 2);
        assert_eq!(k.len(), 3);
        assert_eq!(k[0], (0.0, 1.0, 1.0));
        assert_eq!(k[1], (1.0, 2.0, 0.0));
        assert_eq!((k[2].0, k[2].2), (2.0, 1.0));
        assert!((k[2].1 - l).abs() < 1e-15);
        assert_eq!(s.wins.len(), 3, "the split made one copy");
    }

    #[test]
    fn a_worse_window_is_dropped_and_ties_keep_the_old() {
        let mesh = square();
        let options = MmpOptions::default();
        let mut s = Solver::new(&mesh, &options);
        let l = mesh.length(2);
        s.insert(2, &win(0.0, l, 1.0, -1.0, 0.0), NONE, 0);
        s.insert(2, &win(0.5, 2.0, 1.0, -1.0, 0.5), NONE, 0);
        s.insert(2, &win(0.0, l, 1.0, -1.0, 0.0), NONE, 0);
        assert_eq!(kept(&s, 2).len(), 1);
        assert_eq!(s.wins.len(), 1);
    }

    #[test]
    fn windows_crossing_in_opposite_directions_cut_at_the_tie_point() {
        let mesh = square();
        let options = MmpOptions::default();
        let mut s = Solver::new(&mesh, &options);
        let l = mesh.length(3);
        // On half-edge 3 a source below its foot at 0.5; on the twin (2), a
        // source below its foot at 0.5 of the twin, i.e. at l − 0.5 of 3.
        s.insert(3, &win(0.0, l, 0.5, -1.0, 0.0), NONE, 0);
        s.insert(2, &win(0.0, l, 0.5, -1.0, 0.0), NONE, 1);
        let e = s.edge_of[3] as usize;
        let list: Vec<Win> = s.lists[e].iter().map(|&id| s.wins[id as usize]).collect();
        assert_eq!(list.len(), 2);
        // Canonical frame is half-edge 2: the tie is at the midpoint.
        let mid = 0.5 * l;
        assert!((list[0].c1 - mid).abs() < 1e-14 && (list[1].c0 - mid).abs() < 1e-14);
        assert_eq!(list[0].c1, list[1].c0, "no gap, no overlap");
        assert_eq!(list[0].h, 2);
        assert_eq!(list[1].h, 3);
    }

    #[test]
    fn radix_heap_pops_in_key_order() {
        let mut h = RadixHeap::new();
        let keys = [3.5, 0.25, 7.0, 0.25, 1e-300, 2.0, 100.0, 3.5];
        for (i, k) in keys.iter().enumerate() {
            h.push(f64::to_bits(*k), i as u32);
        }
        let mut out = Vec::new();
        while let Some((k, _)) = h.pop() {
            out.push(f64::from_bits(k));
            if out.len() == 3 {
                h.push(f64::to_bits(5.0), 99);
            }
        }
        assert_eq!(
            out,
            vec![1e-300, 0.25, 0.25, 2.0, 3.5, 3.5, 5.0, 7.0, 100.0]
        );
    }
}
