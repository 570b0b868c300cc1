//! Algorithm 2 of Du et al. 2021 (PVTP) on the primitives of
//! `geodesics-window`, with the sequential VTP of `geodesics-vtp` as the
//! model for every geometric and topological case.
//!
//! # Data flow of one phase (Algorithm 2, lines 11–16)
//!
//! The unit of parallel work is a *face job*: the window lists of one
//! face selected for this phase (up to three half-edges), propagated
//! through it, plus the pseudo-source windows its corners emit, with the
//! children merged (Rules 2/3) into the lists beyond its three edges. A
//! phase runs its jobs in parallel, then applies their delayed writes
//! sequentially in job order.
//!
//! Each half-edge has a main list and a side list (the dual arrays
//! `A_from` / `A_to`), each an index into a pool of window lists (as in
//! VTP: memory follows the wavefront): a job *takes* the main lists of its selected
//! half-edges, and appends children to the lists beyond its edges — to
//! the side list when that list is being taken in the same phase, to the
//! main one otherwise; after the phase the side lists that got windows
//! become main. Each list is thus touched by exactly one job of a phase
//! (its own face's job takes it, the job of the face across writes it),
//! so jobs never wait for each other and the result does not depend on
//! thread timing. (The per-list `Mutex` and the atomic slots only prove
//! that exclusivity to the compiler; they are never contended.) A worker
//! gives the lists it starts pool entries from its own free list (the
//! entries of the lists it consumed), or else from a shared reserve that
//! the sequential part fills before each phase to three per job, the most
//! one job can start.
//!
//! Vertex distances are frozen during a phase: jobs read them for the
//! vertex checks and report their apex candidates; the sequential merge
//! applies them in job order (ties keep the first, so the reduction is by
//! distance, then job order), re-queues improved vertices and selects for
//! the next phase the lists that received children and have an end
//! inside the traversed area, exactly when VTP would queue them.

use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError, RwLock, RwLockReadGuard, RwLockWriteGuard};
use std::thread;
use std::time::Instant;

use geodesics_mesh::Mesh;
use geodesics_window::prune::{
    MergeBuffers, apex_paths, beaten_from_edge_ends, merge_sorted, one_angle_two_sides,
    vertex_check_ended,
};
use geodesics_window::{
    Arrival, DistanceField, EndedWindow, FaceKind, NO_SOURCE, Progress, ResetFront, Shadow,
    SolverSetup, Source, Stats, Tolerance, Triangle, VertexState, check_spikes, corner_neighbours,
    keep_within, path_to_apex, pseudo_source_window, seeds, validate_sources,
};
use glam::DVec2;
use rayon::prelude::*;

use crate::buckets::Buckets;
use crate::crew::Crew;
use crate::{PvtpError, PvtpOptions};

const NONE: u32 = u32::MAX;

/// Face jobs selected per thread and round (`K = min(K_ad, 100·T)`, Eq. 6
/// of the paper, counted in faces of up to three window lists: checking
/// which lists hold windows would cost the sequential part a cache miss
/// per half-edge).
const LISTS_PER_THREAD: usize = 100;

/// How many popped vertices ahead `select` asks for the records of the
/// faces around them.
const PREFETCH_AHEAD: usize = 4;

/// How many popped vertices ahead `select` asks for the records of an
/// emitting vertex's neighbours (after its fan's, `PREFETCH_AHEAD`).
const NEIGHBOURS_AHEAD: usize = 2;

/// How many jobs ahead the delayed writes ask for a job's output record
/// (half of them were written by another core).
const APPLY_AHEAD: usize = 4;

/// How many jobs ahead the delayed writes ask for the records of the
/// faces a job's output queues (after the output's, `APPLY_AHEAD`).
const TARGETS_AHEAD: usize = 2;

/// Bounds of the adaptive vertex count `k_ad` (Eq. 5), as in the authors'
/// code.
const K_AD_MIN: usize = 6;
const K_AD_MAX: usize = 1_000_000_000;

/// Phases with fewer jobs than this run on the calling thread (same code,
/// same result): waking the helpers would cost more than it saves.
const PARALLEL_MIN_JOBS: usize = 24;

/// Free pool entries a worker keeps between phases (the rest go back to
/// the shared reserve): three per job of its usual share of a phase.
const LOCAL_FREE_MAX: usize = 3 * LISTS_PER_THREAD;

/// Slot value of a half-edge list that has no pool entry.
const NO_LIST: u32 = u32::MAX;

/// Flags of a list beyond a job's edge: windows were appended, to the
/// side list, the list has an end inside the traversed area, and (PAVTP)
/// both its ends were restarted by a window reset.
const TOUCHED: u8 = 1;
const TO_SIDE: u8 = 2;
const QUEUE: u8 = 4;
const BETWEEN_RESET: u8 = 8;

/// The two lists of one half-edge, as pool indices (`NO_LIST`: none):
/// which one is the main list is bit 0 of its state word (see
/// [`FaceRec`]), the other is the side list.
type ListSlots = [AtomicU32; 2];

/// One entry of the list pool.
type PooledList = Mutex<Vec<EndedWindow>>;

#[inline]
pub(crate) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A poisoned lock means a worker panicked (an invariant broke); the
    // panic propagates through rayon anyway, the data is still usable.
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

#[inline]
pub(crate) fn read<T>(m: &RwLock<T>) -> RwLockReadGuard<'_, T> {
    m.read().unwrap_or_else(PoisonError::into_inner)
}

#[inline]
pub(crate) fn write<T>(m: &RwLock<T>) -> RwLockWriteGuard<'_, T> {
    m.write().unwrap_or_else(PoisonError::into_inner)
}

// Slots are read and written by the one job that owns the list in a phase
// (and by the sequential part between phases, which holds the solver state
// exclusively), so relaxed loads and stores suffice.
#[inline]
fn slot_get(slots: &ListSlots, which: usize) -> u32 {
    slots[which].load(Ordering::Relaxed)
}

#[inline]
fn slot_set(slots: &ListSlots, which: usize, idx: u32) {
    slots[which].store(idx, Ordering::Relaxed);
}

/// Takes list `which` of a half-edge out of its slot: its pool entry, or
/// `None` if it has none.
#[inline]
fn take_slot(slots: &ListSlots, which: usize) -> Option<u32> {
    let idx = slot_get(slots, which);
    if idx == NO_LIST {
        return None;
    }
    slot_set(slots, which, NO_LIST);
    Some(idx)
}

/// The pool entry of list `which` of a half-edge, giving it `new()` if it
/// has none.
#[inline]
fn claim_slot(slots: &ListSlots, which: usize, new: impl FnOnce() -> u32) -> u32 {
    let idx = slot_get(slots, which);
    if idx != NO_LIST {
        return idx;
    }
    let idx = new();
    slot_set(slots, which, idx);
    idx
}

/// Merges `windows` into `list` with VTP's default merge (lists kept in
/// edge order, [`merge_sorted`]). Returns the new length.
#[inline]
fn prune_append(
    list: &mut Vec<EndedWindow>,
    windows: &mut [EndedWindow],
    buffers: &mut MergeBuffers,
    tol: &Tolerance,
) -> usize {
    merge_sorted(list, windows, buffers, tol);
    list.len()
}

/// Per-face bookkeeping and the list slots of the face's half-edges, in
/// one cache line: selecting a face, running its job and merging into the
/// list beyond an edge each read the state and the slots together (apart,
/// they were two cache misses).
#[derive(Debug)]
#[repr(C, align(64))]
struct FaceRec {
    /// The phase for which the face has a job, and that job's index.
    job_phase: u32,
    job: u32,
    /// The round in which the face joined the traversed area, or NONE.
    entered: u32,
    /// Per half-edge `3f + i`: `phase << 1 | main`, the last phase in which
    /// its main list was (or will be) taken, and which list of its pair is
    /// the main one (they swap when the side list received windows while
    /// the main one was taken).
    state: [u32; 3],
    /// Per half-edge `3f + i`: its two lists.
    slots: [ListSlots; 3],
    /// The worker whose queue takes the face's jobs (see [`face_owner`]).
    owner: u32,
}

impl FaceRec {
    fn new(owner: u32) -> FaceRec {
        let empty = || [AtomicU32::new(NO_LIST), AtomicU32::new(NO_LIST)];
        FaceRec {
            job_phase: NONE,
            job: NONE,
            entered: NONE,
            state: [0; 3],
            slots: [empty(), empty(), empty()],
            owner,
        }
    }
}

const _: () = assert!(std::mem::size_of::<FaceRec>() == 64);

/// The lists of half-edge `h`.
#[inline]
fn slots_of(faces: &[FaceRec], h: u32) -> &ListSlots {
    &faces[(h / 3) as usize].slots[(h % 3) as usize]
}

/// Read-only state shared by the jobs of a phase.
struct Shared<'a> {
    mesh: &'a Mesh,
    tol: Tolerance,
    kind: &'a [FaceKind],
    verts: &'a [VertexState],
    pool: &'a [PooledList],
    faces: &'a [FaceRec],
    jobs: &'a [JobIn],
    emissions: &'a [[Emission; 3]],
    claim_order: &'a [u32],
    /// Free pool entries for lists a worker starts when its own free list
    /// is empty: `reserve[..reserve_len]`, taken from the top.
    reserve: &'a [u32],
    reserve_len: &'a AtomicUsize,
    reset: Option<&'a ResetFront>,
    round: u32,
    phase: u32,
    /// The distance limit (infinite: none): windows reaching nothing
    /// within it are dropped as they are appended.
    limit: f64,
}

/// What one face job does: which lists it takes and which corners emit.
#[derive(Clone, Copy, Debug)]
struct JobIn {
    face: u32,
    /// Bit `i`: take the main list of half-edge `3·face + i`.
    mask: u8,
    /// Index of the face's corner emissions in the phase's table, or NONE
    /// (most jobs: kept apart, so a job record is 16 bytes).
    emit: u32,
    /// The face's owner, copied from its record when the job is made (the
    /// phase's start sorts the jobs by it without a look at the faces).
    owner: u32,
}

/// What a pseudo-source corner of a face job emits: a window made of the
/// rays `rays` (offsets in its corner, see [`pseudo_source_window`])
/// beyond the opposite edge. (Its relaxations along the face's edges are
/// done when it is selected, see [`Solver::emit`].)
#[derive(Clone, Copy, Debug)]
struct Emission {
    /// The corner's distance (infinite: the corner does not emit).
    sigma: f64,
    source: u32,
    rays: (f64, f64),
}

impl Emission {
    const NONE: Emission = Emission {
        sigma: f64::INFINITY,
        source: NO_SOURCE,
        rays: (0.0, 0.0),
    };
}

/// What one face job reports (its delayed writes), reused across phases.
///
/// The counters come first and fill one cache line (`repr(C)`, aligned to
/// 64 bytes), so clearing a record for its next job writes one line; the
/// update slots follow and are written only as far as they are used.
#[derive(Clone, Debug)]
#[repr(C, align(64))]
struct JobOut {
    n_updates: u8,
    /// Whether the face joined the traversed area in this round.
    prime: bool,
    /// Per edge `3f + e`: the half-edge beyond it and what happened to
    /// its list (`TOUCHED`, `TO_SIDE`, `QUEUE`).
    targets: [(u32, u8); 3],
    /// Windows consumed (the input lists).
    consumed: u64,
    /// Net change of the lengths of the lists beyond.
    grown: i64,
    /// Window propagations (each child computed counts once).
    props: u64,
    /// Pseudo-source windows made.
    emitted: u64,
    /// Distance updates `(vertex, distance, source, how the path
    /// arrives)` that beat the frozen distances: the apex of each list;
    /// `updates[..n_updates]` are valid.
    updates: [(u32, f64, u32, Arrival); 3],
}

// The counters of a record share its first cache line.
const _: () = assert!(std::mem::offset_of!(JobOut, updates) <= 64);

impl Default for JobOut {
    fn default() -> Self {
        JobOut {
            updates: [(NONE, f64::INFINITY, NO_SOURCE, Arrival::Unknown); 3],
            n_updates: 0,
            prime: false,
            targets: [(NONE, 0); 3],
            consumed: 0,
            grown: 0,
            props: 0,
            emitted: 0,
        }
    }
}

impl JobOut {
    /// Clears the record for a new job. Only `updates[..n_updates]` is
    /// ever read, so the update slots are left as they are: clearing
    /// writes the first cache line only.
    #[inline]
    fn reset(&mut self) {
        // Exhaustive on purpose: a field added to the record must be
        // cleared here too, or this stops compiling.
        let JobOut {
            updates: _,
            n_updates,
            prime,
            targets,
            consumed,
            grown,
            props,
            emitted,
        } = self;
        *n_updates = 0;
        *prime = false;
        *targets = [(NONE, 0); 3];
        *consumed = 0;
        *grown = 0;
        *props = 0;
        *emitted = 0;
    }

    #[inline]
    fn push_update(&mut self, v: u32, d: f64, source: u32, arrival: Arrival) {
        // At most 1 per list: 3.
        self.updates[self.n_updates as usize] = (v, d, source, arrival);
        self.n_updates += 1;
    }
}

/// What one thread of the crew owns: its scratch buffers and the outputs
/// of the jobs it ran in the current phase.
#[derive(Default)]
struct Worker {
    scratch: Scratch,
    /// `outs[..used]` are the outputs of jobs `job_of[..used]` (ascending);
    /// records beyond are kept for reuse.
    outs: Vec<JobOut>,
    job_of: Vec<u32>,
    used: usize,
    /// Its number in the crew (0: the driving thread).
    index: usize,
}

impl Worker {
    /// Claims and runs jobs of the current phase until none is left;
    /// returns how many it ran.
    fn work(&mut self, sh: &Shared<'_>, crew: &Crew) -> usize {
        let mut done = 0;
        while let Some(pos) = crew.claim(self.index) {
            let k = sh.claim_order[pos] as usize;
            // A job this worker most likely runs soon (two on, so that the
            // loads have a whole job's time to arrive): its face's records.
            if let Some(&next) = sh.claim_order.get(pos + 2) {
                let f = sh.jobs[next as usize].face;
                sh.mesh.prefetch_face(f);
                geodesics_mesh::prefetch(sh.faces, f as usize);
            }
            if self.used == self.outs.len() {
                self.outs.push(JobOut::default());
            }
            run_job(
                sh,
                &sh.jobs[k],
                &mut self.scratch,
                &mut self.outs[self.used],
            );
            self.job_of.truncate(self.used);
            self.job_of.push(k as u32);
            self.used += 1;
            done += 1;
        }
        done
    }
}

/// A helper of the crew (worker `i > 0`): runs the jobs it claims in every
/// phase until the solve is over.
fn helper(i: usize, state: &RwLock<Solver<'_>>, workers: &[Mutex<Worker>], crew: &Crew) {
    let mut seen = 0;
    while crew.wait_phase(&mut seen) {
        // Lock order: the state (shared) before the worker. The driving
        // thread takes every worker while it holds the state exclusively.
        let Some(done) = crew.guarded(|| {
            let solver = read(state);
            lock(&workers[i]).work(&solver.shared(), crew)
        }) else {
            return; // the driving thread raises the panic
        };
        crew.complete(done);
    }
}

/// Per-worker scratch buffers (never part of a result).
#[derive(Default)]
struct Scratch {
    /// Per edge `3f + e` of the job's face: the windows bound for the list
    /// beyond it.
    beyond: [Bound; 3],
    info: Vec<(f64, f64, f64)>,
    /// Pool entries this worker gives to the lists it starts.
    free: Vec<u32>,
    merge: MergeBuffers,
}

/// The windows a job binds for the list beyond one edge of its face:
/// `windows[..len]`. The slots past `len` stay for the next job, so a
/// crossing stores its children into slots it made room for, keeping the
/// count in a register, instead of pushing each one.
#[derive(Default)]
struct Bound {
    windows: Vec<EndedWindow>,
    len: usize,
}

impl Bound {
    #[inline]
    fn push(&mut self, w: EndedWindow) {
        if self.len < self.windows.len() {
            self.windows[self.len] = w;
        } else {
            self.windows.push(w);
        }
        self.len += 1;
    }

    /// Makes slots `len..len + n` exist (`fill` is a placeholder).
    #[inline]
    fn make_room(&mut self, n: usize, fill: EndedWindow) {
        let need = self.len + n;
        if self.windows.len() < need {
            self.windows.resize(need, fill);
        }
    }

    #[inline]
    fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// One face job: emit the pseudo-source windows of its corners, then
/// propagate the selected lists of face `f` and merge the children beyond
/// (see the module comment). Reads only `sh` and the lists it owns in this
/// phase; writes only `out` and those lists.
fn run_job(sh: &Shared<'_>, job: &JobIn, s: &mut Scratch, out: &mut JobOut) {
    out.reset();
    let mesh = sh.mesh;
    let f = job.face;
    // A face selected around a popped vertex often has no windows waiting
    // and no corner emitting (a fifth of the jobs on bunny.off): the slot
    // words of its half-edges, one cache line, say so before anything else
    // of the face or its corners is read.
    let emissions = sh.emissions.get(job.emit as usize);
    let has_list = |i: u32| {
        job.mask & (1 << i) != 0
            && sh.faces[f as usize].slots[i as usize]
                .iter()
                .any(|slot| slot.load(Ordering::Relaxed) != NO_LIST)
    };
    if emissions.is_none() && !(0..3).any(has_list) {
        return;
    }
    out.prime = sh.faces[f as usize].entered == sh.round;
    let corners = mesh.face(f);
    // Distances of the corners, frozen for the phase (the emitting
    // corners' relaxations along the edges included), lowered locally by
    // this job's own updates (real path lengths, so the vertex checks stay
    // sound).
    let mut d = corners.map(|v| sh.verts[v as usize].dist);
    // Pseudo-sources (Section 5.2 of Qin et al.): a window with source at
    // corner j on the edge opposite it, lighting the face beyond (all of
    // it, or the part in the corner's shadow). Only proper faces get
    // emissions.
    for (j, e) in emissions.into_iter().flatten().enumerate() {
        if e.sigma == f64::INFINITY {
            continue;
        }
        let h = 3 * f + j as u32;
        if let Some((_, w)) = pseudo_source_window(mesh, h, e.sigma, e.source, e.rays) {
            out.emitted += 1;
            let w = EndedWindow::new(w);
            // The window lies on the twin of the edge from corner j + 1 to
            // corner j + 2, which runs back from j + 2 to j + 1. Sent back
            // into the traversed area (a reset vertex emitting into its
            // whole fan), it fails the vertex check at once.
            let (start, end) = (d[(j + 2) % 3], d[(j + 1) % 3]);
            let l = mesh.length(Mesh::next(h));
            if !beaten_from_edge_ends(&w, l, start, end, &sh.tol) {
                s.beyond[(j + 1) % 3].push(w);
            }
        }
    }
    let kind = sh.kind[f as usize];
    for i in 0..3usize {
        if job.mask & (1 << i) == 0 {
            continue;
        }
        let h = 3 * f + i as u32;
        let main = (sh.faces[f as usize].state[i] & 1) as usize;
        let Some(idx) = take_slot(&sh.faces[f as usize].slots[i], main) else {
            continue;
        };
        let mut list = lock(&sh.pool[idx as usize]);
        out.consumed += list.len() as u64;
        match kind {
            FaceKind::Proper => cross(sh, h, i, &list, &mut d, s, out),
            FaceKind::Zipper => {
                if let Some(other) = mesh.zipper_exit(h) {
                    let bound = &mut s.beyond[(other - 3 * f) as usize];
                    for &w in list.iter() {
                        bound.push(w);
                    }
                }
            }
            FaceKind::Blocked => {}
        }
        // The entry keeps its buffer for the next list it is given.
        list.clear();
        drop(list);
        s.free.push(idx);
    }
    // Everything bound for one edge (children of up to two lists and a
    // pseudo-source window) goes in with one merge: one lock and one pass
    // over the list beyond instead of up to three.
    for e in 0..3 {
        if !s.beyond[e].is_empty() {
            let mut bound = std::mem::take(&mut s.beyond[e]);
            let ends = [corners[e], corners[(e + 1) % 3]];
            append_beyond(sh, f, e, ends, &mut bound.windows[..bound.len], s, out);
            bound.len = 0;
            s.beyond[e] = bound;
        }
    }
}

/// Merges `windows` into the list beyond edge `3f + e` (the twin's main
/// list, or its side list if the main one is taken in this phase). `ends`
/// are the edge's vertices (the twin's, reversed), known to the job: read
/// from the twin's record they would cost a cache miss.
#[inline]
fn append_beyond(
    sh: &Shared<'_>,
    f: u32,
    e: usize,
    ends: [u32; 2],
    windows: &mut [EndedWindow],
    s: &mut Scratch,
    out: &mut JobOut,
) {
    let windows = if sh.limit < f64::INFINITY {
        keep_within(windows, sh.limit, &sh.tol)
    } else {
        windows
    };
    if windows.is_empty() {
        return;
    }
    let Some(t) = sh.mesh.twin(3 * f + e as u32) else {
        return;
    };
    let beyond = &sh.faces[(t / 3) as usize];
    let st = beyond.state[(t % 3) as usize];
    let to_side = st >> 1 == sh.phase;
    let which = (st & 1) as usize ^ usize::from(to_side);
    let slots = &beyond.slots[(t % 3) as usize];
    let idx = claim_slot(slots, which, || {
        s.free.pop().unwrap_or_else(|| {
            let top = sh.reserve_len.fetch_sub(1, Ordering::Relaxed);
            assert!(
                top > 0,
                "the reserve holds three entries per job of the phase, the most its jobs start"
            );
            sh.reserve[top - 1]
        })
    });
    let mut list = lock(&sh.pool[idx as usize]);
    let before = list.len();
    let after = prune_append(&mut list, windows, &mut s.merge, &sh.tol);
    drop(list);
    if after == 0 {
        slot_set(slots, which, NO_LIST);
        s.free.push(idx);
    }
    out.grown += after as i64 - before as i64;
    let queue = sh.verts[ends[0] as usize].inside || sh.verts[ends[1] as usize].inside;
    let between_reset = sh
        .reset
        .is_some_and(|r| r.is_reset(ends[0]) && r.is_reset(ends[1]));
    out.targets[e] = (
        t,
        TOUCHED
            | if to_side { TO_SIDE } else { 0 }
            | if queue { QUEUE } else { 0 }
            | if between_reset { BETWEEN_RESET } else { 0 },
    );
}

/// Propagates the list of half-edge `h = 3f + i` through its (proper) face,
/// as VTP's `cross`: Rule 1 (one angle two sides) against the list's best
/// path to the apex, one step per window, the vertex check
/// on each child. Children go to `s.beyond`: those beyond `CA` and those
/// beyond `BC`; the list's best path to the apex, where it beats the
/// frozen distance, to `out`'s updates (the write is delayed to the
/// merge).
///
/// Never inlined: inside the job loop, with the job's other state live,
/// it compiled to 4 % more instructions per solve (Loop×1 bunny, T=1).
#[inline(never)]
fn cross(
    sh: &Shared<'_>,
    h: u32,
    i: usize,
    list: &[EndedWindow],
    d: &mut [f64; 3],
    s: &mut Scratch,
    out: &mut JobOut,
) {
    let mesh = sh.mesh;
    let n = Mesh::next(h);
    let p = Mesh::prev(h);
    // The records of the faces beyond the two other edges are read when
    // the children are appended: ask for them now.
    for t in [mesh.twin(p), mesh.twin(n)].into_iter().flatten() {
        geodesics_mesh::prefetch(sh.faces, Mesh::face_of(t) as usize);
    }
    // Corners: A = i, B = i + 1, C = i + 2.
    let (ia, ib, ic) = (i, (i + 1) % 3, (i + 2) % 3);
    let tri = Triangle::with_lengths(
        mesh.length(h),
        sh.mesh.apex(h),
        mesh.length(p),
        mesh.length(n),
    );
    let tol = sh.tol;
    // As in VTP, the list is not checked with vertices again before it
    // propagates (each window met the check as a child; see `cross` there).
    let info = &mut s.info;
    let (best, k) = apex_paths(list, &tri, info);
    if best < d[ic] {
        d[ic] = best;
        let arrival = Arrival::Window {
            half_edge: h,
            at: info[k].1,
        };
        out.push_update(mesh.tail(p), best, list[k].window.source, arrival);
    }
    // Edge C→A is edge `ic` of the face, B→C edge `ib`.
    let [left, right] = s
        .beyond
        .get_disjoint_mut([ic, ib])
        .expect("ib and ic are distinct edges of the face");
    // At most one child per window and side.
    if let Some(&first) = list.first() {
        left.make_room(list.len(), first);
        right.make_room(list.len(), first);
    }
    let (mut n_left, mut n_right) = (left.len, right.len);
    out.props += step_windows(
        list,
        info,
        &tri,
        (best, k),
        (d[ia], d[ib], d[ic]),
        &tol,
        (&mut left.windows, &mut n_left),
        (&mut right.windows, &mut n_right),
    );
    (left.len, right.len) = (n_left, n_right);
}

/// The per-window part of a crossing, shared by both schedules: Rule 1
/// against the list's best path to the apex (`best` through window `k`;
/// `info` from [`apex_paths`]), one step per window, and the vertex check
/// of each child against the corners' distances `(A, B, C)`. Children
/// beyond `CA` go to `left.0[*left.1..]`, those beyond `BC` to
/// `right.0[*right.1..]` (the callers made room for one per window and
/// side); returns the propagations.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn step_windows(
    list: &[EndedWindow],
    info: &[(f64, f64, f64)],
    tri: &Triangle,
    (best, k): (f64, usize),
    (da, db, dc): (f64, f64, f64),
    tol: &Tolerance,
    left: (&mut [EndedWindow], &mut usize),
    right: (&mut [EndedWindow], &mut usize),
) -> u64 {
    let sp_s = info.get(k).map_or(0.0, |x| x.1);
    let b_left = tri.to_left_frame(DVec2::new(tri.l, 0.0));
    let a_right = tri.to_right_frame(DVec2::ZERO);
    let (left, n_left) = left;
    let (right, n_right) = right;
    let mut props = 0u64;
    for (j, e) in list.iter().enumerate() {
        let w = &e.window;
        let (t, sp, dj) = info[j];
        // Rule 1 (Proposition 4.1 of Qin et al.): only against a best
        // window that beats this one by more than the tolerance.
        let cut = ((j != k) & tol.beats(best, dj)).then_some(sp_s);
        let r = one_angle_two_sides(w, t, sp, cut);
        if let Some((x0, x1, reach)) = r.left {
            props += 1;
            if let Some(cw) = w.child_left(tri, x0, x1, reach) {
                let cw = EndedWindow::new(cw);
                if !vertex_check_ended(&cw, tri.lac, da, dc, b_left, db, tol) {
                    left[*n_left] = cw;
                    *n_left += 1;
                }
            }
        }
        if let Some((x0, x1, from)) = r.right {
            props += 1;
            if let Some(cw) = w.child_right(tri, x0, x1, from) {
                let cw = EndedWindow::new(cw);
                if !vertex_check_ended(&cw, tri.lcb, dc, db, a_right, da, tol) {
                    right[*n_right] = cw;
                    *n_right += 1;
                }
            }
        }
    }
    props
}

/// The solver state (sequential parts: selection, seeding, merge).
pub(crate) struct Solver<'a> {
    mesh: &'a Mesh,
    max_distance: Option<f64>,
    threads: usize,
    tol: Tolerance,
    kind: Vec<FaceKind>,
    verts: Vec<VertexState>,
    /// Per vertex: how its shortest known path arrives (kept for vertices
    /// that emit only into their shadow).
    arrival: Vec<Arrival>,
    group_of: Vec<u32>,
    groups: Vec<Vec<u32>>,
    buckets: Buckets,
    pool: Vec<PooledList>,
    /// Pool entries no list or worker holds.
    free: Vec<u32>,
    /// Free pool entries the workers of a phase share (see
    /// [`Shared::reserve`]).
    reserve: Vec<u32>,
    reserve_len: AtomicUsize,
    faces: Vec<FaceRec>,
    /// Jobs of the next phase, in scheduling order.
    pending: Vec<JobIn>,
    /// Jobs of the running phase.
    current: Vec<JobIn>,
    /// The corner emissions of the next phase's jobs and of the running
    /// phase's (see [`JobIn::emit`]).
    pending_emissions: Vec<[Emission; 3]>,
    emissions: Vec<[Emission; 3]>,
    /// Per job of the finished phase: (worker, index in its outputs).
    order: Vec<(u32, u32)>,
    /// The vertices `select` popped in this round: (vertex, first pop,
    /// emits).
    chosen: Vec<(u32, bool, bool)>,
    /// The current phase's jobs grouped by owner (indices into `current`),
    /// and each worker's range of it.
    claim_order: Vec<u32>,
    bounds: Vec<(usize, usize)>,
    /// Merge buffers of the sequential part (seeding).
    merge: MergeBuffers,
    phase: u32,
    round: u32,
    /// Adaptive number of vertices popped per round (Eq. 5).
    k_ad: usize,
    /// Distance of the last vertex popped (the paper's `P_nd`).
    p_nd: f64,
    c_large: usize,
    c_small: usize,
    live: u64,
    stats: Stats,
    parallel_seconds: f64,
    /// PAVTP: which vertices the resets restart, which lists they empty.
    reset: Option<ResetFront>,
    /// PAVTP lighting apices: Rule 1's paths through a list a reset
    /// empties (kept to allocate nothing per reset).
    reset_paths: Vec<(f64, f64, f64)>,
    /// Vertices the wavefront has passed (popped once), reported to
    /// `progress` each round.
    settled: u64,
    progress: Progress,
}

impl<'a> Solver<'a> {
    pub(crate) fn new(mesh: &'a Mesh, options: &PvtpOptions, threads: usize) -> Self {
        let tol = Tolerance::for_mesh(mesh);
        let nf = mesh.face_count();
        let nv = mesh.vertex_count();
        let setup = SolverSetup::new(mesh, &tol);
        // The per-face and per-vertex tables are filled on the solve's pool:
        // on the welded dragon the face records alone are 56 MB, whose first
        // touch (page faults) took 20-80 ms on one thread, all of it
        // sequential time.
        let verts = (0..nv)
            .into_par_iter()
            .map(|v| setup.vertex_state(v))
            .collect();
        let owners = vertex_owners(mesh, threads);
        let faces = (0..nf as u32)
            .into_par_iter()
            .map(|f| FaceRec::new(face_owner(mesh, &owners, f)))
            .collect();
        let SolverSetup {
            kind,
            group_of,
            groups,
            ..
        } = setup;
        // Bucket width h/τ (Section 4.2): h the mean edge length, τ the
        // rounded mean anisotropy (at least 1).
        let tau = mesh.summary().anisotropy.mean.round().max(1.0);
        let width = mesh.average_edge_length() / tau;
        let cap = (4 * nv + 1024).min(1 << 22);
        Solver {
            mesh,
            max_distance: options.max_distance,
            threads,
            tol,
            kind,
            arrival: (0..nv).into_par_iter().map(|_| Arrival::Unknown).collect(),
            verts,
            group_of,
            groups,
            buckets: Buckets::new(width, cap),
            pool: Vec::new(),
            free: Vec::new(),
            reserve: Vec::new(),
            reserve_len: AtomicUsize::new(0),
            faces,
            pending: Vec::new(),
            current: Vec::new(),
            pending_emissions: Vec::new(),
            emissions: Vec::new(),
            order: Vec::new(),
            chosen: Vec::new(),
            claim_order: Vec::new(),
            bounds: Vec::new(),
            merge: MergeBuffers::default(),
            phase: 1,
            round: 0,
            k_ad: K_AD_MIN.max(threads + 1),
            p_nd: 0.0,
            c_large: 0,
            c_small: 0,
            live: 0,
            stats: Stats::default(),
            parallel_seconds: 0.0,
            reset: options
                .reset
                .map(|r| ResetFront::new(r, mesh.average_edge_length(), nv)),
            reset_paths: Vec::new(),
            settled: 0,
            progress: options.progress.clone(),
        }
    }

    // ---------------------------------------------------------------- seeds

    pub(crate) fn seed(&mut self, i: u32, source: &Source) {
        let seeds = seeds(self.mesh, &self.kind, source, i);
        for &v in &seeds.pseudo {
            self.force_pseudo(v);
        }
        for &(v, d) in &seeds.distances {
            self.relax(v, d, i, Arrival::Unknown);
        }
        for &(t, w) in &seeds.windows {
            self.stats.windows_created += 1;
            self.append_now(t, &mut [EndedWindow::new(w)]);
        }
    }

    /// Makes `v` (and its pinch copies) a pseudo-source that emits into
    /// every direction.
    fn force_pseudo(&mut self, v: u32) {
        self.verts[v as usize].pseudo = true;
        self.verts[v as usize].shadowed = false;
        let g = self.group_of[v as usize];
        if g != NONE {
            for &u in &self.groups[g as usize] {
                self.verts[u as usize].pseudo = true;
            }
        }
    }

    // ------------------------------------------------------------ distances

    /// Lowers the distance of `v` (and its pinch copies) to `d` if shorter,
    /// by a path arriving as `arrival`.
    #[inline]
    fn relax(&mut self, v: u32, d: f64, s: u32, arrival: Arrival) {
        if !(d < self.verts[v as usize].dist) {
            return;
        }
        if self.verts[v as usize].shadowed {
            self.arrival[v as usize] = arrival;
        }
        self.set_dist(v, d, s);
        if self.verts[v as usize].grouped {
            let g = self.group_of[v as usize];
            for k in 0..self.groups[g as usize].len() {
                let u = self.groups[g as usize][k];
                if u != v && d < self.verts[u as usize].dist {
                    self.set_dist(u, d, s);
                }
            }
        }
    }

    #[inline]
    fn set_dist(&mut self, v: u32, d: f64, s: u32) {
        let vi = v as usize;
        if let Some(reset) = &mut self.reset
            && self.verts[vi].dist == f64::INFINITY
            && !self.verts[vi].inside
        {
            reset.reached(v);
        }
        let x = &mut self.verts[vi];
        x.dist = d;
        x.src = s;
        let requeue = !x.inside || x.must_emit(d, &self.tol);
        if d > self.p_nd {
            self.c_large += 1;
        } else if d < self.p_nd {
            self.c_small += 1;
        }
        // A vertex ahead of the wavefront is (re)queued; an inside one only
        // matters again if it is a pseudo-source that must re-emit (paper
        // 4.7: saddle vertices lowered inside the swept region).
        if requeue {
            self.buckets.push(d, v);
        }
    }

    // ------------------------------------------------------------ lists

    /// Appends to the main list of half-edge `h` outside a phase (seeds).
    fn append_now(&mut self, h: u32, windows: &mut [EndedWindow]) {
        let windows = match self.max_distance {
            Some(limit) => keep_within(windows, limit, &self.tol),
            None => windows,
        };
        if windows.is_empty() {
            return;
        }
        let main = (self.faces[(h / 3) as usize].state[(h % 3) as usize] & 1) as usize;
        let slots = slots_of(&self.faces, h);
        let idx = claim_slot(slots, main, || take_entry(&mut self.free, &mut self.pool));
        let list = self.pool[idx as usize]
            .get_mut()
            .unwrap_or_else(PoisonError::into_inner);
        let before = list.len();
        let after = prune_append(list, windows, &mut self.merge, &self.tol);
        if after == 0 {
            slot_set(slots, main, NO_LIST);
            self.free.push(idx);
        }
        if after > 0
            && let Some(reset) = &mut self.reset
            && reset.is_reset(self.mesh.tail(h))
            && reset.is_reset(self.mesh.head(h))
        {
            reset.grown(h);
        }
        self.live = self.live + after as u64 - before as u64;
        self.stats.peak_live_windows = self.stats.peak_live_windows.max(self.live);
        let mesh = self.mesh;
        if after > 0
            && (self.verts[mesh.tail(h) as usize].inside
                || self.verts[mesh.head(h) as usize].inside)
        {
            self.schedule_list(h, self.phase);
        }
    }

    /// The job of face `f` in phase `phase` (made on first use).
    #[inline]
    fn job_for(&mut self, f: u32, phase: u32) -> usize {
        let rec = &mut self.faces[f as usize];
        if rec.job_phase != phase {
            rec.job_phase = phase;
            rec.job = self.pending.len() as u32;
            self.pending.push(JobIn {
                face: f,
                mask: 0,
                emit: NONE,
                owner: rec.owner,
            });
        }
        rec.job as usize
    }

    /// Selects the main list of `h` for phase `phase`; `false` if it
    /// already was.
    #[inline]
    fn schedule_list(&mut self, h: u32, phase: u32) -> bool {
        let st = &mut self.faces[(h / 3) as usize].state[(h % 3) as usize];
        if *st >> 1 == phase {
            return false;
        }
        *st = phase << 1 | (*st & 1);
        let k = self.job_for(Mesh::face_of(h), phase);
        self.pending[k].mask |= 1 << (h % 3);
        true
    }

    /// Selects the lists of face `f` that hold windows for the coming
    /// phase (none: no job; windows that reach them later in this phase
    /// are queued for the next one, as VTP queues a list that fills after
    /// its face was entered).
    #[inline]
    fn schedule_face(&mut self, f: u32) {
        let phase = self.phase;
        let rec = &mut self.faces[f as usize];
        if rec.entered == NONE {
            rec.entered = self.round;
        }
        let mut mask = 0;
        for (i, st) in rec.state.iter_mut().enumerate() {
            let main = (*st & 1) as usize;
            if slot_get(&rec.slots[i], main) != NO_LIST {
                *st = phase << 1 | (*st & 1);
                mask |= 1 << i;
            }
        }
        if mask != 0 {
            let k = self.job_for(f, phase);
            self.pending[k].mask |= mask;
        }
    }

    // ------------------------------------------------------------ main loop

    /// Runs the solve to the end on the crew of `self.threads` threads:
    /// this thread drives (the sequential parts, and its share of every
    /// phase's jobs), the others are helpers spawned once on the current
    /// rayon pool. Between phases this thread holds the state exclusively;
    /// during a phase every thread of the crew holds it shared.
    pub(crate) fn run(self) -> Self {
        let threads = self.threads.max(1);
        let workers: Vec<Mutex<Worker>> = (0..threads)
            .map(|i| {
                Mutex::new(Worker {
                    index: i,
                    ..Worker::default()
                })
            })
            .collect();
        let crew = Crew::new(threads);
        let state = RwLock::new(self);
        rayon::scope(|scope| {
            for i in 1..threads {
                let (state, workers, crew) = (&state, &workers[..], &crew);
                scope.spawn(move |_| helper(i, state, workers, crew));
            }
            let _stop = crew.stop_on_drop();
            Solver::drive(&state, &workers, &crew);
        });
        state.into_inner().unwrap_or_else(PoisonError::into_inner)
    }

    /// The driving thread's loop: select, run a phase, apply its delayed
    /// writes, until the buckets are empty.
    fn drive(state: &RwLock<Solver<'_>>, workers: &[Mutex<Worker>], crew: &Crew) {
        let mut solver = write(state);
        let k_cap = LISTS_PER_THREAD * solver.threads.max(1);
        loop {
            // A round's lists take several phases to reach the wavefront,
            // the later ones with few jobs each. The next round is selected
            // into the same phase while the continuation leaves room for
            // it: fewer, fuller phases, each costing a wake-up of the crew
            // and a pass of delayed writes (on the welded dragon at T=2:
            // 19K phases instead of 78K). Every pruning rule is sound in
            // any order, so this changes only how many windows are
            // propagated (+0.05 % there).
            if solver.pending.len() < k_cap {
                solver.select();
            }
            if solver.pending.is_empty() {
                // A round can give no face any work (its vertices reached
                // only along the edges of zero-area faces, say): then the
                // next round, until no vertex is left.
                if solver.vertices_left() {
                    continue;
                }
                break;
            }
            let (n, parallel) = solver.start_phase(workers);
            crew.begin(&solver.bounds);
            drop(solver);
            let t0 = Instant::now();
            {
                let shared = read(state);
                if parallel {
                    crew.publish();
                }
                let done = lock(&workers[0]).work(&shared.shared(), crew);
                drop(shared);
                crew.complete(done);
                crew.wait_completed(n);
            }
            solver = write(state);
            solver.parallel_seconds += t0.elapsed().as_secs_f64();
            solver.stats.parallel_phases += 1;
            solver.apply_outputs(workers, n);
        }
    }

    /// The view of the state the jobs of a phase read.
    fn shared(&self) -> Shared<'_> {
        Shared {
            mesh: self.mesh,
            tol: self.tol,
            kind: &self.kind,
            verts: &self.verts,
            pool: &self.pool,
            faces: &self.faces,
            jobs: &self.current,
            emissions: &self.emissions,
            claim_order: &self.claim_order,
            reserve: &self.reserve,
            reserve_len: &self.reserve_len,
            reset: self.reset.as_ref(),
            round: self.round,
            phase: self.phase,
            limit: self.max_distance.unwrap_or(f64::INFINITY),
        }
    }

    /// K-window-list selection (Sections 4.2–4.3): pop the nearest vertices
    /// until `k_ad` of them were popped or they bring `K = 100·T` face jobs
    /// (counted by fan sizes: a vertex's fan once for its faces, once more
    /// if it emits, as its corners' emissions are work of those jobs).
    /// A popped vertex selects the lists VTP would queue: those of the
    /// faces around it and those beyond its edges.
    fn select(&mut self) {
        // Eq. 5: more vertices per round while updates land beyond the
        // popped range, fewer when they land behind it.
        if self.round > 0 {
            let k = self.k_ad as i64 + self.c_large as i64 - self.c_small as i64;
            self.k_ad = (k.max(0) as usize).clamp(K_AD_MIN.max(self.threads + 1), K_AD_MAX);
        }
        self.c_large = 0;
        self.c_small = 0;
        self.round += 1;
        let k_cap = LISTS_PER_THREAD * self.threads.max(1);
        let mut popped = 0;
        let mut lists = 0;
        // First pop the round's vertices, counting the faces they bring by
        // their fans' sizes (exact unless two of them share a face): the
        // face records are then read in a second pass over a known list,
        // each loaded well before it is needed. Read one by one as the
        // vertices came out, they were a chain of cache misses (this part
        // runs alone, while the other threads wait).
        let mut chosen = std::mem::take(&mut self.chosen);
        chosen.clear();
        while popped < self.k_ad && lists < k_cap {
            let verts = &self.verts;
            let Some((d, v)) = self.buckets.peek(|v| verts[v as usize].dist.to_bits()) else {
                break;
            };
            // Beyond the distance limit a vertex only lets the lists
            // around it propagate (see `geodesics-vtp`'s loop): windows
            // on a long edge whose ends both lie beyond it may still reach
            // nearer vertices past it. It emits nothing.
            let beyond = self.max_distance.is_some_and(|m| d > m);
            if !beyond && self.reset.as_ref().is_some_and(|r| r.is_due(d)) {
                self.reset_windows(d);
            }
            self.buckets.pop();
            for u in self.buckets.upcoming(3) {
                geodesics_mesh::prefetch(&self.verts, u as usize);
                self.mesh.prefetch_vertex(u);
            }
            let vi = v as usize;
            let x = self.verts[vi];
            let first = !x.inside;
            let emit = !beyond && x.must_emit(d, &self.tol);
            if !first && !emit {
                continue;
            }
            popped += 1;
            self.p_nd = d;
            self.stats.vertex_pops += 1;
            if first {
                self.verts[vi].inside = true;
                if !beyond {
                    self.settled += 1;
                }
            }
            let fan = self.mesh.fan(v);
            geodesics_mesh::prefetch(fan, 0);
            lists += fan.len() * (usize::from(first) + usize::from(emit));
            chosen.push((v, first, emit));
        }
        self.progress.set_reached(self.settled);
        let mesh = self.mesh;
        for &(u, _, _) in chosen.iter().take(PREFETCH_AHEAD) {
            self.prefetch_fan_records(u);
        }
        for (i, &(v, first, emit)) in chosen.iter().enumerate() {
            if let Some(&(u, _, _)) = chosen.get(i + PREFETCH_AHEAD) {
                self.prefetch_fan_records(u);
            }
            // An emitting vertex relaxes its neighbours: their records,
            // once its fan's (asked for above) has arrived.
            if let Some(&(u, _, true)) = chosen.get(i + NEIGHBOURS_AHEAD) {
                for &h in mesh.fan(u) {
                    geodesics_mesh::prefetch(&self.verts, mesh.head(h) as usize);
                }
            }
            if first {
                // VTP queues the lists of the faces around v and those
                // beyond its edges, which are lists of faces around v too.
                for &h in mesh.fan(v) {
                    self.schedule_face(Mesh::face_of(h));
                }
            }
            if emit {
                self.emit(v);
            }
        }
        self.chosen = chosen;
    }

    /// Whether a vertex is left to pop (beyond the distance limit too:
    /// the lists around it may still reach within it).
    fn vertices_left(&mut self) -> bool {
        let verts = &self.verts;
        self.buckets
            .peek(|v| verts[v as usize].dist.to_bits())
            .is_some()
    }

    /// Asks for the records `select` reads of vertex `u`: its state and
    /// arrival, its fan's faces, their job records, list slots and kinds.
    #[inline]
    fn prefetch_fan_records(&self, u: u32) {
        geodesics_mesh::prefetch(&self.verts, u as usize);
        geodesics_mesh::prefetch(&self.arrival, u as usize);
        if (u as usize) < self.mesh.vertex_count() {
            for &h in self.mesh.fan(u) {
                let f = Mesh::face_of(h);
                self.mesh.prefetch_face(f);
                geodesics_mesh::prefetch(&self.faces, f as usize);
                geodesics_mesh::prefetch(&self.kind, f as usize);
            }
        }
    }

    /// PAVTP: AVTP's window reset (Algorithm 3 of Du et al., lines 6-14)
    /// between rounds: the wavefront passed the next multiple of λh, so every
    /// wavefront vertex within the guard band beyond it becomes a
    /// pseudo-source and the windows waiting between two such vertices are
    /// deleted. The same rule as `geodesics-vtp`'s sequential AVTP.
    fn reset_windows(&mut self, d: f64) {
        let Some(mut reset) = self.reset.take() else {
            return;
        };
        let verts = &self.verts;
        let joined = reset.advance(d, |v| verts[v as usize].inside, |v| verts[v as usize].dist);
        for &v in joined {
            self.force_pseudo(v);
        }
        let light = reset.lights_apices();
        let verts = &self.verts;
        let n = reset
            .lists_to_empty(self.mesh, |v| verts[v as usize].inside)
            .len();
        // Back in place before any apex is lit: one reached for the first
        // time joins the waiting wavefront vertices as any other.
        self.reset = Some(reset);
        let mut dropped = 0u64;
        for k in 0..n {
            let t = self.reset.as_ref().expect("put back just above").emptied()[k];
            if light {
                self.light_apex_through(t);
            }
            for which in 0..2 {
                let Some(idx) = take_slot(slots_of(&self.faces, t), which) else {
                    continue;
                };
                let list = self.pool[idx as usize]
                    .get_mut()
                    .unwrap_or_else(PoisonError::into_inner);
                dropped += list.len() as u64;
                list.clear();
                self.free.push(idx);
            }
        }
        self.live = self.live.saturating_sub(dropped);
    }

    /// PAVTP lighting apices: the apex of `h`'s face takes Rule 1's best
    /// path through the windows waiting on `h` (both of its lists), as
    /// crossing the face would have given it, before the reset deletes
    /// them, and restarts the front if that lowers it (as `geodesics-vtp`'s
    /// reset does).
    fn light_apex_through(&mut self, h: u32) {
        if self.kind[Mesh::face_of(h) as usize] != FaceKind::Proper {
            return;
        }
        let apex = self.mesh.tail(Mesh::prev(h));
        for which in 0..2 {
            let idx = slot_get(slots_of(&self.faces, h), which);
            if idx == NO_LIST {
                continue;
            }
            let list = self.pool[idx as usize]
                .get_mut()
                .unwrap_or_else(PoisonError::into_inner);
            if let Some((best, w, bend)) = path_to_apex(self.mesh, h, list, &mut self.reset_paths)
                && best < self.verts[apex as usize].dist
            {
                // A restart, as in `geodesics-vtp`'s reset.
                self.force_pseudo(apex);
                let arrival = Arrival::Window {
                    half_edge: h,
                    at: bend,
                };
                self.relax(apex, best, w.source, arrival);
            }
        }
    }

    /// Pseudo-source `v`: relaxes its neighbours along the edges now (as
    /// VTP does), and the jobs of its faces put one window with source `v`
    /// on each edge opposite it (Section 5.2 of Qin et al., "Saddle
    /// Vertices"), all of it or, for a saddle or flat vertex, the part in
    /// its shadow. A corner outside the shadow gives its face no work: on
    /// the subdivided bunny, two jobs in five were such a corner's two
    /// relaxations alone.
    fn emit(&mut self, v: u32) {
        let vi = v as usize;
        let x = &mut self.verts[vi];
        let (d, s) = (x.dist, x.src);
        x.emitted = d;
        self.stats.pseudo_source_emissions += 1;
        let mesh = self.mesh;
        // The fan from the mesh's table, not by walking twins: the corner
        // angles along it are independent loads.
        let fan = mesh.fan(v);
        let around = || fan.iter().copied();
        let shadow = if x.shadowed {
            Shadow::of_fan(mesh, v, around(), self.arrival[vi], &self.tol)
        } else {
            None
        };
        for (h, rays) in Shadow::fan_rays(shadow, mesh, around()) {
            for (u, len, arrival) in corner_neighbours(mesh, h) {
                self.relax(u, d + len, s, arrival);
            }
            if let Some(rays) = rays
                && self.kind[Mesh::face_of(h) as usize] == FaceKind::Proper
            {
                self.emit_corner(h, d, s, rays);
            }
        }
    }

    /// The window of the corner at the tail of `h` (see [`Emission`]), in
    /// the job of its face.
    fn emit_corner(&mut self, h: u32, sigma: f64, source: u32, rays: (f64, f64)) {
        let k = self.job_for(Mesh::face_of(h), self.phase);
        let job = &mut self.pending[k];
        if job.emit == NONE {
            job.emit = self.pending_emissions.len() as u32;
            self.pending_emissions.push([Emission::NONE; 3]);
        }
        self.pending_emissions[job.emit as usize][(h % 3) as usize] = Emission {
            sigma,
            source,
            rays,
        };
    }

    /// Fills the shared reserve to three free pool entries per job of the
    /// coming phase (the most one job can start: a list beyond each of its
    /// edges), from the workers' free lists beyond [`LOCAL_FREE_MAX`], the
    /// solver's free list or a grown pool. What it costs does not grow
    /// with the thread count: giving every worker three entries per job of
    /// the phase (any worker may run every job) held `T × 3 × 100·T`
    /// entries, and 1024 threads took seconds on a 2K-face mesh.
    fn fill_reserve(&mut self, workers: &[Mutex<Worker>], jobs: usize) {
        let left = *self.reserve_len.get_mut();
        self.reserve.truncate(left);
        for m in workers {
            let free = &mut lock(m).scratch.free;
            if free.len() > LOCAL_FREE_MAX {
                self.reserve.extend(free.drain(LOCAL_FREE_MAX..));
            }
        }
        while self.reserve.len() < 3 * jobs {
            let idx = take_entry(&mut self.free, &mut self.pool);
            self.reserve.push(idx);
        }
        *self.reserve_len.get_mut() = self.reserve.len();
    }

    /// Makes the selected jobs the current phase and queues each for the
    /// worker owning its face (`claim_order`, `bounds`); returns how many
    /// there are and whether the helpers should be woken for them.
    fn start_phase(&mut self, workers: &[Mutex<Worker>]) -> (usize, bool) {
        std::mem::swap(&mut self.current, &mut self.pending);
        self.pending.clear();
        std::mem::swap(&mut self.emissions, &mut self.pending_emissions);
        self.pending_emissions.clear();
        let n = self.current.len();
        // A counting sort of the jobs by owner, in job order within each.
        let t = workers.len();
        let owner = |job: &JobIn| job.owner as usize;
        self.bounds.clear();
        self.bounds.resize(t, (0, 0));
        for job in &self.current {
            self.bounds[owner(job)].1 += 1;
        }
        let mut start = 0;
        for b in &mut self.bounds {
            let len = b.1;
            *b = (start, start);
            start += len;
        }
        self.claim_order.clear();
        self.claim_order.resize(n, 0);
        for (k, job) in self.current.iter().enumerate() {
            let b = &mut self.bounds[owner(job)];
            self.claim_order[b.1] = k as u32;
            b.1 += 1;
        }
        let parallel = n >= PARALLEL_MIN_JOBS && workers.len() > 1;
        self.fill_reserve(workers, n);
        (n, parallel)
    }

    /// The delayed writes of the `n` jobs of the phase just run, in job
    /// order (whichever worker ran each job).
    fn apply_outputs(&mut self, workers: &[Mutex<Worker>], n: usize) {
        let mut guards: Vec<MutexGuard<'_, Worker>> = workers.iter().map(lock).collect();
        let mut order = std::mem::take(&mut self.order);
        order.clear();
        order.resize(n, (NONE, NONE));
        for (w, g) in guards.iter().enumerate() {
            for (p, &k) in g.job_of[..g.used].iter().enumerate() {
                order[k as usize] = (w as u32, p as u32);
            }
        }
        let next = self.phase + 1;
        let mut live = self.live as i64;
        for (i, &(w, p)) in order.iter().enumerate() {
            if let Some(&(w2, p2)) = order.get(i + APPLY_AHEAD) {
                // Its counters, and its updates on the next cache line.
                let ahead = &guards[w2 as usize].outs[p2 as usize];
                geodesics_mesh::prefetch(std::slice::from_ref(ahead), 0);
                geodesics_mesh::prefetch(&ahead.updates, 0);
            }
            // The faces whose lists a job queues: their records, once the
            // job's output (asked for above) has arrived.
            if let Some(&(w2, p2)) = order.get(i + TARGETS_AHEAD) {
                for &(t, flags) in &guards[w2 as usize].outs[p2 as usize].targets {
                    if flags & QUEUE != 0 {
                        geodesics_mesh::prefetch(&self.faces, (t / 3) as usize);
                    }
                }
            }
            let out = &guards[w as usize].outs[p as usize];
            live += out.grown - out.consumed as i64;
            let props = out.props;
            self.stats.window_propagations += props;
            self.stats.windows_created += props + out.emitted;
            if out.prime {
                self.stats.prime_propagations += props;
            } else {
                self.stats.secondary_propagations += props;
            }
            for &(v, d, s, arrival) in &out.updates[..out.n_updates as usize] {
                self.relax(v, d, s, arrival);
            }
            for &(t, flags) in &out.targets {
                if flags & BETWEEN_RESET != 0
                    && let Some(reset) = &mut self.reset
                {
                    reset.grown(t);
                }
                if flags & TO_SIDE != 0 {
                    // Its main list was taken in this phase: the side list
                    // becomes the main one.
                    self.faces[(t / 3) as usize].state[(t % 3) as usize] ^= 1;
                }
                if flags & QUEUE != 0 {
                    self.schedule_list(t, next);
                }
            }
        }
        for g in &mut guards {
            g.used = 0;
        }
        self.order = order;
        self.live = live.max(0) as u64;
        self.stats.peak_live_windows = self.stats.peak_live_windows.max(self.live);
        self.phase = next;
    }

    pub(crate) fn finish(mut self, start: Instant) -> (DistanceField, Stats) {
        let verts = &self.verts;
        let mesh = self.mesh;
        let vertex = |v: usize| (verts[v].dist, verts[v].src);
        // Gathered on the solve's pool: input order is a scattered walk
        // over the renumbered vertices.
        let (distance, nearest_source) = (0..mesh.input_vertex_count() as u32)
            .into_par_iter()
            .map(|u| vertex(mesh.mesh_vertex(u) as usize))
            .unzip();
        let field = DistanceField::from_first_fans(
            mesh,
            self.max_distance,
            distance,
            nearest_source,
            vertex,
        );
        let mut stats = std::mem::take(&mut self.stats);
        stats.threads = self.threads as u64;
        stats.window_resets = self.reset.as_ref().map_or(0, ResetFront::resets);
        stats.total_seconds = start.elapsed().as_secs_f64();
        stats.propagation_seconds = self.parallel_seconds;
        stats.pruning_seconds = 0.0;
        stats.management_seconds = (stats.total_seconds - self.parallel_seconds).max(0.0);
        stats.peak_window_bytes =
            stats.peak_live_windows * std::mem::size_of::<EndedWindow>() as u64;
        (field, stats)
    }
}

/// Faces per side of an ownership cell, in mean edge lengths.
const OWNER_CELL_EDGES: f64 = 16.0;

/// Which of `workers` workers takes the jobs of the faces around each
/// vertex (see [`face_owner`]): the vertices in one cube of a grid over
/// the mesh (about `OWNER_CELL_EDGES` mean edges wide) belong to one
/// worker, the cubes spread over the workers by a hash. A list is written
/// by the job of the face before it and read by the job of its own face,
/// usually in the same cube, so its windows stay in one core's cache; two
/// threads on interleaved faces spent 22 % more time per job than one.
/// Positions, not face numbers, so any face order works. Empty for one
/// worker.
///
/// The cubes are found once per vertex, in one pass over the positions in
/// memory order (with three scattered position loads per face, this pass
/// was a third of the solver's setup on the welded dragon).
fn vertex_owners(mesh: &Mesh, workers: usize) -> Vec<u32> {
    if workers <= 1 {
        return Vec::new();
    }
    let cell = OWNER_CELL_EDGES * mesh.average_edge_length();
    let inv = if cell.is_finite() && cell > 0.0 {
        1.0 / cell
    } else {
        1.0
    };
    // On the solve's pool (it only runs for several threads).
    mesh.positions()
        .par_iter()
        .map(|&p| {
            let k = p * inv;
            // The mixing constants are odd 64-bit numbers.
            let mut h = (cell_index(k.x) as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)
                ^ (cell_index(k.y) as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f)
                ^ (cell_index(k.z) as u64).wrapping_mul(0x1656_67b1_9e37_79f9);
            h ^= h >> 29;
            h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
            h ^= h >> 32;
            // Into [0, workers) by the high half of a product, not `%`.
            ((u128::from(h) * workers as u128) >> 64) as u32
        })
        .collect()
}

/// The worker that takes face `f`'s jobs: the owner of its first corner's
/// cube (`owners` from [`vertex_owners`]; worker 0 when it is empty).
#[inline]
fn face_owner(mesh: &Mesh, owners: &[u32], f: u32) -> u32 {
    if owners.is_empty() {
        0
    } else {
        owners[mesh.tail(3 * f) as usize]
    }
}

/// `⌊x⌋` as an integer (saturating; NaN gives 0) without `f64::floor`,
/// which the baseline x86-64 target compiles to a call into libm.
#[inline]
pub(crate) fn cell_index(x: f64) -> i64 {
    let t = x as i64;
    t - i64::from((t as f64) > x)
}

/// A free pool entry: the last one freed, or a new one.
fn take_entry(free: &mut Vec<u32>, pool: &mut Vec<PooledList>) -> u32 {
    free.pop().unwrap_or_else(|| {
        pool.push(Mutex::new(Vec::new()));
        let i = pool.len() - 1;
        assert!(i < NO_LIST as usize, "fewer window lists than 2^32 - 1");
        i as u32
    })
}

/// Checks the sources and options (the same refusals as VTP's).
/// Refuses more threads than [`crate::max_threads`].
pub(crate) fn check_thread_count(threads: usize) -> Result<(), PvtpError> {
    let max = crate::max_threads();
    if threads > max {
        return Err(PvtpError::TooManyThreads {
            threads,
            max,
            cpus: thread::available_parallelism().map_or(1, |n| n.get()),
        });
    }
    Ok(())
}

pub(crate) fn validate(
    mesh: &Mesh,
    sources: &[Source],
    options: &PvtpOptions,
) -> Result<(), PvtpError> {
    validate_sources(mesh, sources, options.max_distance)?;
    check_spikes(mesh)?;
    check_thread_count(if options.threads == 0 {
        // What rayon will take: `RAYON_NUM_THREADS` if a positive number,
        // else the logical CPUs (a pool of thousands takes seconds to
        // start only to be refused).
        std::env::var("RAYON_NUM_THREADS")
            .ok()
            .and_then(|n| n.trim().parse::<usize>().ok())
            .filter(|&n| n > 0)
            .unwrap_or(1)
    } else {
        options.threads
    })?;
    if let Some(r) = options.reset
        && !r.is_usable()
    {
        return Err(PvtpError::Reset {
            lambda: r.lambda,
            lambda_g: r.lambda_g,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_index_is_the_floor() {
        for x in [
            -2.5,
            -2.0,
            -1.0,
            -0.5,
            -1e-300,
            0.0,
            0.25,
            1.0,
            3.999,
            1e6 + 0.5,
        ] {
            assert_eq!(cell_index(x), x.floor() as i64, "x = {x}");
        }
        assert_eq!(cell_index(f64::NAN), 0);
        assert_eq!(cell_index(1e300), i64::MAX);
    }
}
