//! Algorithm 1 of Qin et al. 2016 (vertex-oriented triangle propagation).

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::time::Instant;

use geodesics_mesh::Mesh;
use geodesics_window::face_lists::{
    ENTERED, FaceLists, NEW_FACE, NO_LIST, NOT_ENTERED, QUEUED, list_word, list_word_index,
    queue_list,
};
use geodesics_window::prune::{
    CrossBuffers, MergeBuffers, PairOutcome, SplitOutcome, apex_paths, beaten_from_edge_ends,
    merge_behind, merge_sorted, one_angle_two_sides, prune_adjacent_ended,
    prune_adjacent_splitting, vertex_check_ended,
};
use geodesics_window::{
    Arrival, DistanceField, EndedWindow, FaceKind, ResetFront, Shadow, SolverSetup, Source, Stats,
    Tolerance, Triangle, VertexQueue, VertexState, Window, check_spikes, corner_neighbours,
    keep_within, path_to_apex, pseudo_source_window, seeds, validate_sources,
};
use glam::DVec2;

use crate::{Merge, PairRule, Provenance, Rule1, Schedule, VtpError, VtpOptions};

const NONE: u32 = u32::MAX;

/// How many queued vertices have their records loaded ahead: the top of
/// the queue and its children, one of which is popped next.
const UPCOMING: usize = geodesics_window::ARITY + 1;

/// One window list in this many has its phases timed; the phase times are
/// scaled up accordingly (an estimate, unbiased over many lists). A clock
/// read costs about 27 ns here: one list in 32 spent 0.5 % of an
/// armadillo.obj solve reading the clock.
const PHASE_SAMPLE: u64 = 256;

struct Solver<'a> {
    mesh: &'a Mesh,
    options: &'a VtpOptions,
    tol: Tolerance,
    kind: Vec<FaceKind>,
    /// Every face is proper (no zero-area face): `kind` need not be read.
    all_proper: bool,
    verts: Vec<VertexState>,
    /// Per vertex: how its shortest known path arrives (kept for vertices
    /// that emit only into their shadow).
    arrival: Vec<Arrival>,
    /// Per vertex: index into `groups` of its pinch group, or NONE.
    group_of: Vec<u32>,
    groups: Vec<Vec<u32>>,
    heap: VertexQueue,
    /// Per face: its half-edges' lists and when it was entered.
    faces: Vec<FaceLists>,
    pool: Vec<Vec<EndedWindow>>,
    free: Vec<u32>,
    /// The half-edges whose lists wait to be processed in this pop, in
    /// order (drained to empty after each pop: a plain vector read
    /// through a cursor, not a ring buffer).
    fifo: Vec<u32>,
    pops: u32,
    /// Vertices the wavefront has passed (popped once), for the progress
    /// report.
    settled: u64,
    live: u64,
    stats: Stats,
    /// Spare buffers of [`merge_sorted`].
    buffers: MergeBuffers,
    /// When the current list's children were computed (phase timing, on
    /// the sampled lists only).
    merge_start: Option<Instant>,
    /// Whether the current list is one of the timed samples.
    timing: bool,
    lists_processed: u64,
    /// Per vertex: how its distance was last set (only when recording).
    prov: Vec<Provenance>,
    /// AVTP: which vertices the resets restart, which lists they empty.
    reset: Option<ResetFront>,
    /// AVTP lighting apices: Rule 1's paths through a list a reset
    /// empties (kept to allocate nothing per reset).
    reset_paths: Vec<(f64, f64, f64)>,
    /// The default merge (adjacent pairs, lists in edge order), decided
    /// once: the options sit behind a pointer and every append asks.
    sorted_merge: bool,
    /// The distance limit (infinite: none), read by every append.
    limit: f64,
    /// FTP: faces waiting to be traversed, by their best apex distance.
    face_heap: BinaryHeap<Reverse<(u64, u32)>>,
    face_key: Vec<f64>,
    /// The queued vertices whose records were asked for after the last
    /// pop: each stays near the top for several pops, and asking again
    /// walks its fan again (a stall when the fan is not loaded yet).
    prefetched: [u32; UPCOMING],
}

pub(crate) fn solve(
    mesh: &Mesh,
    sources: &[Source],
    options: &VtpOptions,
) -> Result<(DistanceField, Stats, Vec<Provenance>), VtpError> {
    let start = Instant::now();
    validate(mesh, sources, options)?;
    options.progress.start(mesh.vertex_count());
    let mut s = Solver::new(mesh, options);
    for (i, source) in sources.iter().enumerate() {
        s.seed(i as u32, source);
    }
    s.run();
    options.progress.set_reached(s.settled);
    let mut stats = std::mem::take(&mut s.stats);
    stats.threads = 1;
    stats.window_resets = s.reset.as_ref().map_or(0, ResetFront::resets);
    let prov = std::mem::take(&mut s.prov);
    let field = s.finish();
    stats.total_seconds = start.elapsed().as_secs_f64();
    stats.management_seconds =
        (stats.total_seconds - stats.propagation_seconds - stats.pruning_seconds).max(0.0);
    stats.peak_window_bytes = stats.peak_live_windows * std::mem::size_of::<EndedWindow>() as u64;
    Ok((field, stats, prov))
}

fn validate(mesh: &Mesh, sources: &[Source], options: &VtpOptions) -> Result<(), VtpError> {
    validate_sources(mesh, sources, options.max_distance)?;
    check_spikes(mesh)?;
    if let Some(r) = options.reset
        && !r.is_usable()
    {
        return Err(VtpError::Reset {
            lambda: r.lambda,
            lambda_g: r.lambda_g,
        });
    }
    Ok(())
}

impl<'a> Solver<'a> {
    fn new(mesh: &'a Mesh, options: &'a VtpOptions) -> Self {
        let tol = Tolerance::for_mesh(mesh);
        let nf = mesh.face_count();
        let nv = mesh.vertex_count();
        let setup = SolverSetup::new(mesh, &tol);
        let verts = setup.vertex_states();
        let SolverSetup {
            kind,
            group_of,
            groups,
            ..
        } = setup;
        let mean_edge = mesh.average_edge_length();
        let all_proper = kind.iter().all(|&k| k == FaceKind::Proper);
        Solver {
            mesh,
            options,
            tol,
            kind,
            all_proper,
            verts,
            arrival: vec![Arrival::Unknown; nv],
            group_of,
            groups,
            heap: VertexQueue::new(nv),
            faces: vec![NEW_FACE; nf],
            pool: Vec::new(),
            free: Vec::new(),
            fifo: Vec::new(),
            pops: 0,
            settled: 0,
            live: 0,
            stats: Stats::default(),
            buffers: MergeBuffers::default(),
            merge_start: None,
            timing: false,
            lists_processed: 0,
            prov: if options.record_provenance {
                vec![Provenance::Unreached; nv]
            } else {
                Vec::new()
            },
            reset: options.reset.map(|r| ResetFront::new(r, mean_edge, nv)),
            reset_paths: Vec::new(),
            sorted_merge: options.pruning.pairs == PairRule::Adjacent
                && options.merge == Merge::Sorted,
            limit: options.max_distance.unwrap_or(f64::INFINITY),
            face_heap: BinaryHeap::new(),
            prefetched: [NONE; UPCOMING],
            face_key: if options.schedule == Schedule::FaceSorted {
                vec![f64::INFINITY; nf]
            } else {
                Vec::new()
            },
        }
    }

    // ---------------------------------------------------------------- seeds

    fn seed(&mut self, i: u32, source: &Source) {
        let seeds = seeds(self.mesh, &self.kind, source, i);
        for &v in &seeds.pseudo {
            self.force_pseudo(v);
        }
        for &(v, d) in &seeds.distances {
            self.relax(v, d, i, Arrival::Unknown, || Provenance::Source(i));
        }
        for &(t, w) in &seeds.windows {
            self.stats.windows_created += 1;
            let ends = [self.mesh.tail(t), self.mesh.head(t)];
            self.append(t, ends, &mut [EndedWindow::new(w)]);
        }
    }

    /// Makes `v` (and its pinch copies) a pseudo-source that emits into
    /// every direction.
    fn force_pseudo(&mut self, v: u32) {
        let x = &mut self.verts[v as usize];
        x.pseudo = true;
        x.shadowed = false;
        if self.verts[v as usize].grouped {
            let g = self.group_of[v as usize];
            for k in 0..self.groups[g as usize].len() {
                let u = self.groups[g as usize][k];
                self.verts[u as usize].pseudo = true;
            }
        }
    }

    // ------------------------------------------------------------ distances

    /// Lowers the distance of `v` (and its pinch copies) to `d` if shorter,
    /// by a path arriving as `arrival` says (kept for a vertex that emits
    /// into its shadow); `how` is asked only then. The test is inlined at
    /// every call site: most candidates lose.
    #[inline(always)]
    fn relax(
        &mut self,
        v: u32,
        d: f64,
        s: u32,
        arrival: Arrival,
        how: impl FnOnce() -> Provenance,
    ) {
        let x = &self.verts[v as usize];
        if d < x.dist {
            if x.shadowed {
                self.arrival[v as usize] = arrival;
            }
            self.lower(v, d, s, how());
        }
    }

    /// [`Solver::relax`] once `d` is known to be shorter.
    fn lower(&mut self, v: u32, d: f64, s: u32, how: Provenance) {
        self.set_dist(v, d, s);
        if !self.prov.is_empty() {
            self.prov[v as usize] = how;
        }
        if self.verts[v as usize].grouped {
            let g = self.group_of[v as usize];
            for k in 0..self.groups[g as usize].len() {
                let u = self.groups[g as usize][k];
                if u != v && d < self.verts[u as usize].dist {
                    self.set_dist(u, d, s);
                    if !self.prov.is_empty() {
                        self.prov[u as usize] = Provenance::Vertex {
                            from: v,
                            length: 0.0,
                        };
                    }
                }
            }
        }
    }

    #[inline]
    fn set_dist(&mut self, v: u32, d: f64, s: u32) {
        let x = &mut self.verts[v as usize];
        if x.dist == f64::INFINITY {
            // First reached: its fan table loads now, long before the pop
            // loop asks for the faces of the upcoming vertices, which then
            // does not wait on it (AVTP at λ = 8 on the Loop×2 bunny 1–4 %
            // faster, VTP on armadillo.obj 1.5–2 % and on Loop×1 about 1 %).
            self.mesh.prefetch_fan_table(v);
            if let Some(reset) = &mut self.reset
                && !x.inside
            {
                reset.reached(v);
            }
        }
        x.dist = d;
        x.src = s;
        // A vertex ahead of the wavefront is (re)queued; an inside one only
        // matters again if it is a pseudo-source that must re-emit.
        if !x.inside || x.must_emit(d, &self.tol) {
            self.heap.push_or_lower(d.to_bits(), v);
        }
    }

    // ------------------------------------------------------------ main loop

    fn run(&mut self) {
        let mesh = self.mesh;
        let mut scratch = CrossBuffers::default();
        let face_sorted = self.options.schedule == Schedule::FaceSorted;
        loop {
            if face_sorted && self.pop_face(&mut scratch) {
                continue;
            }
            let Some((key, v)) = self.heap.pop() else {
                break;
            };
            let vi = v as usize;
            let d = f64::from_bits(key);
            debug_assert_eq!(key, self.verts[vi].dist.to_bits(), "keys follow distances");
            // A vertex beyond the distance limit still lets the windows
            // waiting around it through: a long edge whose ends both lie
            // beyond it may carry windows that reach nearer vertices past
            // it, and its lists are processed only once an end is popped.
            // It emits nothing (its windows could reach nothing within the
            // limit); windows beyond the limit are dropped as they come
            // (`append`), so the solve still ends soon after the limit.
            let beyond = d > self.limit;
            if !beyond && self.reset.as_ref().is_some_and(|r| r.is_due(d)) {
                self.reset_windows(d);
            }
            // Read after the reset, which may have made v a pseudo-source.
            let x = self.verts[vi];
            let first = !x.inside;
            let emit = !beyond && x.must_emit(d, &self.tol);
            if !first && !emit {
                continue;
            }
            self.pops += 1;
            self.stats.vertex_pops += 1;
            if first {
                self.verts[vi].inside = true;
                if !beyond {
                    self.settled += 1;
                    self.options.progress.note_reached(self.settled);
                }
            }
            if first && !face_sorted {
                // The next vertex's faces load while this one's lists
                // are processed (the wavefront jumps around in memory),
                // asked for once per vertex.
                let mut seen = [NONE; UPCOMING];
                for (i, u) in self.heap.upcoming(UPCOMING).enumerate() {
                    seen[i] = u;
                    if self.prefetched.contains(&u) {
                        continue;
                    }
                    mesh.prefetch_fan(u);
                    // Its angle sum, which a shadowed emission reads.
                    mesh.prefetch_vertex(u);
                    geodesics_mesh::prefetch(&self.verts, u as usize);
                    geodesics_mesh::prefetch(&self.arrival, u as usize);
                }
                self.prefetched = seen;
                // The faces around v join the traversed area; the lists
                // waiting to enter them propagate now. (A list enters the
                // face of its half-edge, so these are the lists on the
                // fan's half-edges; the twins of the edges at v lie in the
                // fan too.)
                for &h in mesh.fan(v) {
                    let f = Mesh::face_of(h);
                    let rec = &mut self.faces[f as usize];
                    if rec[ENTERED] == NOT_ENTERED {
                        rec[ENTERED] = self.pops;
                    }
                    // On the record in hand (no index arithmetic).
                    for (i, word) in rec[..ENTERED].iter_mut().enumerate() {
                        queue_list(word, 3 * f + i as u32, &mut self.fifo);
                    }
                }
            }
            if emit {
                self.emit(v);
            }
            self.drain_fifo(&mut scratch);
        }
    }

    /// Processes the queued lists in order, those queued meanwhile too.
    #[inline]
    fn drain_fifo(&mut self, scratch: &mut CrossBuffers) {
        let mut next = 0;
        while let Some(&h) = self.fifo.get(next) {
            next += 1;
            if let Some(&g) = self.fifo.get(next) {
                self.prefetch_list(g);
            }
            self.process(h, scratch);
        }
        self.fifo.clear();
    }

    /// Asks for the first windows of the list on half-edge `h`, queued to
    /// be processed next: with a few windows per list (AVTP), reading
    /// them is otherwise a cache miss per list.
    #[inline]
    fn prefetch_list(&self, h: u32) {
        let idx = self.slot(h) & !QUEUED;
        if let Some(list) = self.pool.get(idx as usize) {
            geodesics_mesh::prefetch(list, 0);
            geodesics_mesh::prefetch(list, 1);
        }
    }

    /// FTP: traverses the waiting face whose entering lists reach its apex
    /// soonest, if that comes before the next vertex. Returns whether a face
    /// was taken (or a stale entry dropped).
    fn pop_face(&mut self, scratch: &mut CrossBuffers) -> bool {
        let Some(&Reverse((key, f))) = self.face_heap.peek() else {
            return false;
        };
        let next_vertex = self.heap.peek().map(|(k, _)| f64::from_bits(k));
        let d = f64::from_bits(key);
        if next_vertex.is_some_and(|v| v < d) {
            return false;
        }
        self.face_heap.pop();
        let fi = f as usize;
        if self.faces[fi][ENTERED] != NOT_ENTERED || self.face_key[fi].to_bits() != key {
            return true; // stale
        }
        self.pops += 1;
        self.faces[fi][ENTERED] = self.pops;
        for e in 3 * f..3 * f + 3 {
            self.enqueue(e);
        }
        self.drain_fifo(scratch);
        true
    }

    /// AVTP's window reset (Du et al. 2021, Algorithm 3, lines 6-14): the
    /// wavefront crossed the next multiple of λh. Every wavefront vertex
    /// within the guard band λ_g·h beyond it becomes a pseudo-source (it
    /// emits when popped, like a saddle) and the windows waiting on the
    /// edges between two such vertices are deleted. `d` is the distance of
    /// the vertex just popped, which crossed (it is still on the wavefront).
    fn reset_windows(&mut self, d: f64) {
        let Some(mut reset) = self.reset.take() else {
            return;
        };
        let verts = &self.verts;
        let inside = |v: u32| verts[v as usize].inside;
        let joined = reset.advance(d, inside, |v| verts[v as usize].dist);
        for &v in joined {
            self.force_pseudo(v);
        }
        let light = reset.lights_apices();
        let verts = &self.verts;
        let n = reset
            .lists_to_empty(self.mesh, |v| verts[v as usize].inside)
            .len();
        // Back in place first: an apex lit for the first time joins the
        // waiting wavefront vertices as any other.
        self.reset = Some(reset);
        for k in 0..n {
            let h = self.reset.as_ref().expect("put back just above").emptied()[k];
            if light {
                self.light_apex_through(h);
            }
            self.drop_list(h);
        }
    }

    /// AVTP lighting apices: the apex of `h`'s face takes Rule 1's best
    /// path through the windows waiting on `h`, as crossing the face would
    /// have given it, before the reset deletes them. An apex it lowers
    /// restarts the front like a reset vertex (a pseudo-source emitting
    /// everywhere): no window carries its new distance on, and without
    /// windows behind it that distance would only prune others' (the
    /// vertex check) and leave sectors beyond it unreached.
    fn light_apex_through(&mut self, h: u32) {
        let idx = self.slot(h) & !QUEUED;
        if idx == NO_LIST || self.face_kind(Mesh::face_of(h)) != FaceKind::Proper {
            return;
        }
        let mesh = self.mesh;
        let list = &self.pool[idx as usize];
        let Some((best, w, bend)) = path_to_apex(mesh, h, list, &mut self.reset_paths) else {
            return;
        };
        let apex = mesh.tail(Mesh::prev(h));
        if best < self.verts[apex as usize].dist {
            // Before it is lowered: an apex already inside is queued again
            // only if it must emit.
            self.force_pseudo(apex);
            self.light_apex(h, apex, best, w, bend);
        }
    }

    /// Lowers the apex of `h`'s face to `best`, the path through window `w`
    /// crossing `h` at `bend` (Rule 1's best path to it).
    #[inline(always)]
    fn light_apex(&mut self, h: u32, apex: u32, best: f64, w: Window, bend: f64) {
        let arrival = Arrival::Window {
            half_edge: h,
            at: bend,
        };
        self.relax(apex, best, w.source, arrival, || Provenance::Window {
            half_edge: h,
            pseudo_source: w.p,
            sigma: w.sigma,
            bend,
        });
    }

    /// Deletes the windows waiting on half-edge `h` (AVTP's reset).
    fn drop_list(&mut self, h: u32) {
        let slot = self.slot_mut(h);
        let idx = *slot & !QUEUED;
        if idx == NO_LIST {
            return;
        }
        *slot = NO_LIST;
        let list = &mut self.pool[idx as usize];
        self.live -= list.len() as u64;
        list.clear();
        self.free.push(idx);
    }

    /// Pseudo-source `v`: relax its neighbours along edges and put one
    /// full-edge window with source `v` on each edge opposite it (Section
    /// 5.2, "Saddle Vertices").
    fn emit(&mut self, v: u32) {
        let mesh = self.mesh;
        let x = &mut self.verts[v as usize];
        let (d, s) = (x.dist, x.src);
        x.emitted = d;
        let fan = mesh.fan(v).iter().copied();
        let shadow = if x.shadowed && self.options.pruning.shadow {
            Shadow::of_fan(mesh, v, fan.clone(), self.arrival[v as usize], &self.tol)
        } else {
            None
        };
        self.stats.pseudo_source_emissions += 1;
        // Emitting into the whole fan also sends windows back into the
        // traversed area (AVTP's reset vertices do, on every step), where
        // the distances at the edge's ends already beat them: the vertex
        // check children meet drops them before they are queued.
        let check_now = shadow.is_none() && self.options.pruning.vertex_check;
        for (h, rays) in Shadow::fan_rays(shadow, mesh, fan) {
            let [(a, la, back_a), (b, lb, back_b)] = corner_neighbours(mesh, h);
            self.relax(a, d + la, s, back_a, || Provenance::Vertex {
                from: v,
                length: la,
            });
            self.relax(b, d + lb, s, back_b, || Provenance::Vertex {
                from: v,
                length: lb,
            });
            if self.face_kind(Mesh::face_of(h)) != FaceKind::Proper {
                continue;
            }
            let Some((t, w)) = rays.and_then(|r| pseudo_source_window(mesh, h, d, s, r)) else {
                continue;
            };
            self.stats.windows_created += 1;
            let w = EndedWindow::new(w);
            // The edge opposite v runs from a to b; `t` from b to a.
            if check_now {
                let (da, db) = (self.verts[a as usize].dist, self.verts[b as usize].dist);
                let l = mesh.length(Mesh::next(h));
                if beaten_from_edge_ends(&w, l, db, da, &self.tol) {
                    continue;
                }
            }
            self.append(t, [a, b], &mut [w]);
        }
    }

    /// The list word of half-edge `h`: its index in `pool` and whether it
    /// is queued (see `QUEUED`).
    #[inline]
    fn slot(&self, h: u32) -> u32 {
        self.faces.as_flattened()[list_word_index(h)]
    }

    /// How face `f` is crossed (no table read when every face is proper).
    #[inline]
    fn face_kind(&self, f: u32) -> FaceKind {
        if self.all_proper {
            FaceKind::Proper
        } else {
            self.kind[f as usize]
        }
    }

    /// Asks for the list word of half-edge `h` ahead of an append.
    #[inline]
    fn prefetch_list_word(&self, h: u32) {
        geodesics_mesh::prefetch(&self.faces, Mesh::face_of(h) as usize);
    }

    #[inline]
    fn slot_mut(&mut self, h: u32) -> &mut u32 {
        list_word(&mut self.faces, h)
    }

    #[inline]
    fn enqueue(&mut self, h: u32) {
        queue_list(list_word(&mut self.faces, h), h, &mut self.fifo);
    }

    /// Appends windows to the list of half-edge `h`, pruning adjacent pairs
    /// (Rule 2 within one propagated list, Rule 3 / order-free secondary
    /// merge against what the list already holds). The sorted merge sorts
    /// `windows` in place.
    ///
    /// `ends` are the two vertices of `h`'s edge (in either order): the
    /// callers know them, and reading them from `h`'s record would cost a
    /// cache miss per append (the face beyond is usually not in cache).
    #[inline(always)]
    fn append(&mut self, h: u32, ends: [u32; 2], mut windows: &mut [EndedWindow]) {
        if self.limit < f64::INFINITY {
            windows = keep_within(windows, self.limit, &self.tol);
        }
        if windows.is_empty() {
            return;
        }
        let mut idx = self.slot(h) & !QUEUED;
        if idx == NO_LIST {
            idx = match self.free.pop() {
                Some(i) => i,
                None => {
                    self.pool.push(Vec::new());
                    let i = (self.pool.len() - 1) as u32;
                    assert!(i < NO_LIST, "fewer window lists than 2^31 - 1");
                    i
                }
            };
            // Keeps the queued bit: the half-edge may still wait in the
            // FIFO from a list that emptied.
            let slot = self.slot_mut(h);
            *slot = idx | (*slot & QUEUED);
        }
        let list = &mut self.pool[idx as usize];
        let before = list.len();
        let tol = &self.tol;
        if self.sorted_merge {
            merge_sorted(list, windows, &mut self.buffers, tol);
        } else {
            merge_as_configured(list, windows, self.options, tol);
        }
        let after = list.len();
        self.live = self.live + after as u64 - before as u64;
        if self.live > self.stats.peak_live_windows {
            self.stats.peak_live_windows = self.live;
        }
        if after == 0 {
            let slot = self.slot_mut(h);
            *slot = NO_LIST | (*slot & QUEUED);
            self.free.push(idx);
            return;
        }
        if let Some(reset) = &mut self.reset
            && reset.is_reset(ends[0])
            && reset.is_reset(ends[1])
        {
            reset.grown(h);
        }
        match self.options.schedule {
            Schedule::VertexSorted => {
                debug_assert!(
                    ends.contains(&self.mesh.tail(h)) && ends.contains(&self.mesh.head(h))
                );
                if self.verts[ends[0] as usize].inside || self.verts[ends[1] as usize].inside {
                    self.enqueue(h);
                }
            }
            Schedule::FaceSorted => self.wait_for_face(h, windows),
        }
    }

    /// FTP: a list of half-edge `h` received `windows`. If its face was
    /// entered the list is queued; otherwise the face waits in the face
    /// queue keyed on the best path to its apex through those windows (the
    /// triangle priority). Out of line: the default schedule never calls it.
    #[inline(never)]
    fn wait_for_face(&mut self, h: u32, windows: &[EndedWindow]) {
        let f = h / 3;
        if self.faces[f as usize][ENTERED] != NOT_ENTERED {
            self.enqueue(h);
            return;
        }
        let tri = Triangle::new(self.mesh.length(h), self.mesh.apex(h));
        let key = windows
            .iter()
            .map(|e| e.window.apex_distance(&tri).0)
            .fold(f64::INFINITY, f64::min);
        if key < self.face_key[f as usize] {
            self.face_key[f as usize] = key;
            self.face_heap.push(Reverse((key.to_bits(), f)));
        }
    }

    /// Propagates the list of half-edge `h` through its face (Rules 1 and 2,
    /// vertex check), lights the apex, and merges the children into the
    /// lists beyond the two other edges.
    fn process(&mut self, h: u32, scratch: &mut CrossBuffers) {
        let slot = self.slot_mut(h);
        let idx = *slot & !QUEUED;
        *slot = NO_LIST;
        if idx == NO_LIST {
            return;
        }
        let mut list = std::mem::take(&mut self.pool[idx as usize]);
        self.live -= list.len() as u64;
        // Phase times are sampled: one list in PHASE_SAMPLE is timed (two
        // clock reads per list would cost more than some lists' work).
        self.lists_processed += 1;
        self.timing = self.lists_processed.is_multiple_of(PHASE_SAMPLE);
        let t0 = self.timing.then(Instant::now);
        self.merge_start = t0;
        let mesh = self.mesh;
        let f = Mesh::face_of(h);
        match self.face_kind(f) {
            FaceKind::Proper => self.cross(h, &list, scratch),
            FaceKind::Zipper => {
                if let Some(t) = mesh.zipper_exit(h).and_then(|g| mesh.twin(g)) {
                    self.append(t, [mesh.tail(t), mesh.head(t)], &mut list[..]);
                }
            }
            FaceKind::Blocked => {}
        }
        list.clear();
        self.pool[idx as usize] = list;
        self.free.push(idx);
        if let (Some(t0), Some(t_merge)) = (t0, self.merge_start) {
            let t1 = Instant::now();
            self.stats.propagation_seconds += (t_merge - t0).as_secs_f64() * PHASE_SAMPLE as f64;
            self.stats.pruning_seconds += (t1 - t_merge).as_secs_f64() * PHASE_SAMPLE as f64;
        }
    }

    fn cross(&mut self, h: u32, list: &[EndedWindow], scratch: &mut CrossBuffers) {
        let mesh = self.mesh;
        let f = Mesh::face_of(h);
        let n = Mesh::next(h);
        let p = Mesh::prev(h);
        let (a, b, c) = (mesh.tail(h), mesh.head(h), mesh.tail(p));
        // The list words beyond the two other edges are read when the
        // children are appended: ask for them now.
        let (beyond_left, beyond_right) = (mesh.twin(p), mesh.twin(n));
        for t in [beyond_left, beyond_right].into_iter().flatten() {
            self.prefetch_list_word(t);
        }
        let tri = Triangle::with_lengths(
            mesh.length(h),
            self.mesh.apex(h),
            mesh.length(p),
            mesh.length(n),
        );
        // No second vertex check of the list before it propagates: each
        // window met one as a child, and the distances that fell since then
        // drop 0.3 % of them (armadillo.obj, bunny.off), for 7 % of the
        // solve's instructions. Their children still meet the check.
        // Rule 1: separating points, the list's best path to C.
        let CrossBuffers { info, left, right } = scratch;
        let (best, s) = apex_paths(list, &tri, info);
        if best.is_finite() {
            self.light_apex(h, c, best, list[s].window, info[s].1);
        }
        let sp_s = info.get(s).map_or(0.0, |x| x.1);
        let prime = self.faces[f as usize][ENTERED] == self.pops;
        let check = self.options.pruning.vertex_check;
        // Rule 1 as configured, decided per list, not per window: which
        // dominated windows it cuts (every one, or with `OneAngleOneSplit`
        // only one splitting at the apex, against a best one that splits
        // there too: Case 9; none when it is off).
        let (cut_all, cut_splitting) = match self.options.pruning.rule1 {
            Rule1::OneAngleTwoSides => (true, false),
            Rule1::OneAngleOneSplit => (
                false,
                info.get(s)
                    .is_some_and(|x| list[s].window.b0 <= x.0 && x.0 <= list[s].window.b1),
            ),
            Rule1::Off => (false, false),
        };
        let b_left = tri.to_left_frame(DVec2::new(tri.l, 0.0));
        let a_right = tri.to_right_frame(DVec2::ZERO);
        let (da, db, dc) = (
            self.verts[a as usize].dist,
            self.verts[b as usize].dist,
            self.verts[c as usize].dist,
        );
        // Each window has at most one child per side: the buffers hold a
        // slot per window, filled from the front (no length kept per push).
        if left.len() < list.len() {
            left.resize(list.len(), list[0]);
            right.resize(list.len(), list[0]);
        }
        let (mut n_left, mut n_right) = (0, 0);
        let mut props = 0u64;
        for (i, e) in list.iter().enumerate() {
            let w = &e.window;
            let (t, sp, d) = info[i];
            let dominated = (i != s) & self.tol.beats(best, d);
            let splits = (w.b0 <= t) & (t <= w.b1);
            let cut = (dominated & (cut_all | (cut_splitting & splits))).then_some(sp_s);
            let r = one_angle_two_sides(w, t, sp, cut);
            if let Some((x0, x1, reach)) = r.left {
                props += 1;
                if let Some(cw) = w.child_left(&tri, x0, x1, reach) {
                    let cw = EndedWindow::new(cw);
                    if !(check && vertex_check_ended(&cw, tri.lac, da, dc, b_left, db, &self.tol)) {
                        left[n_left] = cw;
                        n_left += 1;
                    }
                }
            }
            if let Some((x0, x1, from)) = r.right {
                props += 1;
                if let Some(cw) = w.child_right(&tri, x0, x1, from) {
                    let cw = EndedWindow::new(cw);
                    if !(check && vertex_check_ended(&cw, tri.lcb, dc, db, a_right, da, &self.tol))
                    {
                        right[n_right] = cw;
                        n_right += 1;
                    }
                }
            }
        }
        self.stats.window_propagations += props;
        self.stats.windows_created += props;
        if prime {
            self.stats.prime_propagations += props;
        } else {
            self.stats.secondary_propagations += props;
        }
        if self.timing {
            self.merge_start = Some(Instant::now());
        }
        // Beyond C → A and beyond B → C.
        if let Some(t) = beyond_left {
            self.append(t, [c, a], &mut left[..n_left]);
        }
        if let Some(t) = beyond_right {
            self.append(t, [b, c], &mut right[..n_right]);
        }
    }

    fn finish(self) -> DistanceField {
        DistanceField::from_vertices(self.mesh, self.options.max_distance, |v| {
            (self.verts[v].dist, self.verts[v].src)
        })
    }
}

/// The merges of the ablation variants (every pair rule and merge but the
/// default adjacent-pairs sorted merge, which [`Solver::append`] calls
/// directly). Out of line, so the default append stays small.
#[inline(never)]
fn merge_as_configured(
    list: &mut Vec<EndedWindow>,
    windows: &mut [EndedWindow],
    options: &VtpOptions,
    tol: &Tolerance,
) {
    match (options.pruning.pairs, options.merge) {
        (PairRule::Off, Merge::OrderFree) => list.extend_from_slice(windows),
        (PairRule::Off, Merge::OrderPreserving) => {
            for &w in windows.iter() {
                let at = list.partition_point(|e| e.window.b0 <= w.window.b0);
                list.insert(at, w);
            }
        }
        (PairRule::Adjacent, Merge::OrderFree) => {
            for &w in windows.iter() {
                merge_behind(list, w, tol);
            }
        }
        (PairRule::Off, Merge::Sorted) => {
            list.extend_from_slice(windows);
            list.sort_unstable_by(|a, b| a.window.b0.total_cmp(&b.window.b0));
        }
        (PairRule::Adjacent, Merge::Sorted) => {
            unreachable!("the default merge is called by Solver::append itself")
        }
        (PairRule::Adjacent, Merge::OrderPreserving) => {
            for &w in windows.iter() {
                merge_in_order(list, w, tol);
            }
        }
        (PairRule::Exhaustive, _) => {
            for &w in windows.iter() {
                merge_against_all(list, w, tol, false);
            }
        }
        (PairRule::Trimming, _) => {
            for &w in windows.iter() {
                merge_against_all(list, w, tol, true);
            }
        }
    }
}

/// Rules 2 and 3 with the order-preserving merge (OPVTP): `w` is inserted
/// where its start belongs and checked against both neighbours.
fn merge_in_order(list: &mut Vec<EndedWindow>, mut w: EndedWindow, tol: &Tolerance) {
    let mut at = list.partition_point(|e| e.window.b0 <= w.window.b0);
    // Left neighbours.
    while at > 0 {
        match prune_adjacent_ended(&mut list[at - 1], &mut w, tol) {
            PairOutcome::KeepBoth => break,
            PairOutcome::RemoveSecond => return,
            PairOutcome::RemoveFirst => {
                list.remove(at - 1);
                at -= 1;
            }
        }
    }
    // Right neighbours.
    while at < list.len() {
        match prune_adjacent_ended(&mut w, &mut list[at], tol) {
            PairOutcome::KeepBoth => break,
            PairOutcome::RemoveFirst => return,
            PairOutcome::RemoveSecond => {
                list.remove(at);
            }
        }
    }
    list.insert(at, w);
}

/// VTP-Exhaustive and VTP-Trimming: `w` against every window of the list;
/// with `split`, a loser that sticks out on both sides of the winner is cut
/// into its two outer pieces (MMP's trimming).
fn merge_against_all(list: &mut Vec<EndedWindow>, w: EndedWindow, tol: &Tolerance, split: bool) {
    // Right pieces of the incoming window waiting their turn (no allocation
    // unless the incoming window is split).
    let mut pending: Vec<EndedWindow> = Vec::new();
    let mut next = Some(w);
    'incoming: while let Some(mut w) = next.take().or_else(|| pending.pop()) {
        let mut i = 0;
        while i < list.len() {
            let outcome = if split {
                prune_adjacent_splitting(&mut list[i], &mut w, tol)
            } else {
                SplitOutcome::Pair(prune_adjacent_ended(&mut list[i], &mut w, tol))
            };
            match outcome {
                SplitOutcome::Pair(PairOutcome::KeepBoth) => i += 1,
                SplitOutcome::Pair(PairOutcome::RemoveSecond) => continue 'incoming,
                SplitOutcome::Pair(PairOutcome::RemoveFirst) => {
                    list.swap_remove(i);
                }
                SplitOutcome::FirstSplit(right) => {
                    list.push(right);
                    i += 1;
                }
                SplitOutcome::SecondSplit(right) => {
                    pending.push(right);
                    i += 1;
                }
            }
        }
        list.push(w);
    }
}
