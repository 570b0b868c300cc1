//! PVTP's region schedule ([`crate::Schedule::Regions`]): no one-thread
//! part between the parallel steps.
//!
//! The faces are cut into *regions*, the cubes of a grid about
//! [`REGION_CELL_EDGES`] mean edges wide (a face belongs to the cube of its
//! first corner). Each region runs sequential VTP (Algorithm 1 of Qin et
//! al., with the same pruning rules, pseudo-sources and shadows as
//! `geodesics-vtp`) on its own faces, with its own copy — a *slot* — of
//! every vertex touching them, popping only vertices nearer than a bound.
//! The bound grows by [`BAND_EDGES`] mean edges per *band*, Du et al.'s
//! distance bucket. Windows bound for another region's faces, and the
//! lowered distances of vertices that have copies in other regions (a
//! pinch group's other members included), are *mail*: the delayed writes
//! of the band, read by the receiving region at the start of the next one,
//! senders in region order, each sender's in the order it made them.
//!
//! So the regions of one band are independent of each other: the crew's
//! threads take them in any order (each first the regions it owns, the
//! busiest of the last band first, then it steals), and the result does not
//! depend on the thread count at all, not only from run to run. Between
//! bands one thread only picks the next bound and the regions with work.
//! Each band's bound is picked one band early, so a thread that has run
//! out of band `k`'s regions starts band `k + 1` in a region whose
//! neighbours (the regions that can mail it) are done with band `k`: it
//! reads then what it would read after a barrier (see `Driver::run`).
//! Any order of propagation is exact (every pruning rule is sound in any
//! order: a window that arrives a band late is propagated then, like a
//! list VTP queues again after its face was entered), at the cost of
//! windows a timely one would have pruned: 0.1–1.5 % more than VTP on our
//! meshes.
//!
//! With a [`crate::WindowReset`] it is PAVTP: a band stops at the next
//! reset radius, and the next band resets each region's own wavefront
//! copies (Algorithm 3 of Du et al., lines 6–14) before it propagates.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, RwLock};
use std::time::Instant;

use geodesics_mesh::Mesh;
use geodesics_window::face_lists::{
    ENTERED, FaceLists, NEW_FACE, NO_LIST, NOT_ENTERED, QUEUED, queue_list,
};
use geodesics_window::prune::{
    CrossBuffers, MergeBuffers, apex_paths, beaten_from_edge_ends, merge_sorted,
};
use geodesics_window::{
    ARITY, Arrival, DistanceField, EndedWindow, FaceKind, NO_GROUP, NO_SOURCE, Progress, Shadow,
    SolverSetup, Source, Stats, Tolerance, Triangle, VertexQueue, VertexState, corner_neighbours,
    keep_within, path_to_apex, pseudo_source_window, seeds,
};
use rayon::prelude::*;

use crate::PvtpOptions;
use crate::crew::{Crew, Waiting};
use crate::solver::{cell_index, lock, read, step_windows, write};

/// Region size, in mean edge lengths per side of a cube. Smaller regions
/// balance two threads better but copy more vertices and pass more mail.
/// On 2 CPUs, T=2 against VTP in one run (coarse Loop×3 bunny, Loop×1
/// bunny, welded dragon): 32 edges 1.49, 1.38, 1.40×; 64 edges 1.59,
/// 1.55, 1.51× (one thread 1.18–1.25× VTP's time, against 1.20–1.44× at
/// 32); PAVTP at λ = 8 on 70K–280K faces 1.07–1.16× AVTP against
/// 0.90–1.12×. 96 and 128 were no faster and uneven (1.31× on the
/// coarse bunny at 96: too few regions per band to share).
pub(crate) const REGION_CELL_EDGES: f64 = 64.0;

/// How far the bound moves per band, in mean edge lengths: narrower bands
/// waste fewer windows, wider ones cost fewer hand-overs (on the coarse
/// Loop×3 bunny, 0.5: 600 bands, 0.1 % fewer windows, no faster; 2: 160
/// bands and 0.5 % more windows).
pub(crate) const BAND_EDGES: f64 = 1.0;

const NONE: u32 = u32::MAX;
/// A pop's weight against a propagation in a region's work estimate (which
/// orders the next band's regions, busiest first): about their costs in
/// VTP, ~440 ns per vertex (popping, entering the fan, emitting) against
/// ~27 ns per propagation on the coarse Loop×3 bunny.
const POP_WEIGHT: u64 = 16;
/// Queued slots whose records are asked for ahead (the top and its
/// children, one of which is popped next).
const UPCOMING: usize = ARITY + 1;

/// A region's face: its half-edges' lists and the pop (`counts.pops`)
/// at which it was entered, as VTP keeps them (`face_lists`), then the
/// slots of its corners and its global number. One record of half a
/// cache line, since entering, crossing and emitting read them together
/// (in three arrays they cost three cache misses).
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct LocalFace {
    lists: FaceLists,
    corners: [u32; 3],
    global: u32,
}

/// The list word of local half-edge `lh` (see `face_lists`).
#[inline]
fn list_word(faces: &mut [LocalFace], lh: u32) -> &mut u32 {
    &mut faces[(lh / 3) as usize].lists[(lh % 3) as usize]
}

/// [`list_word`], read.
#[inline]
fn list_word_of(faces: &[LocalFace], lh: u32) -> u32 {
    faces[(lh / 3) as usize].lists[(lh % 3) as usize]
}

/// A region's fixed layout: the copies of its faces' corners and where
/// else each vertex is copied.
struct Layout {
    /// Per slot: the vertex.
    slot_vertex: Vec<u32>,
    /// Per slot: its local faces.
    fans: Grouped<u32>,
    /// Per slot: `(region, slot)` of the vertex's copies in other regions
    /// and of its pinch group's members (in this region too).
    copies: Grouped<(u32, u32)>,
    /// Per slot: the vertex's first copy, the one that counts it as
    /// reached in the progress report.
    primary: Vec<bool>,
}

/// One region's solver state (locked by the thread running its band).
struct Region {
    index: usize,
    lay: Layout,
    tol: Tolerance,
    /// Per local face (a face's local number is its index; they follow
    /// the global numbers' order).
    faces: Vec<LocalFace>,
    pool: Vec<Vec<EndedWindow>>,
    free: Vec<u32>,
    /// While the region runs a band: the running thread's spare list
    /// buffers (see `Post::spares`), lent to it.
    spares: Vec<Vec<EndedWindow>>,
    slots: Vec<VertexState>,
    arrival: Vec<Arrival>,
    heap: VertexQueue,
    fifo: Vec<u32>,
    /// Slots lowered in this band that have copies elsewhere.
    dirty: Vec<u32>,
    is_dirty: Vec<bool>,
    /// This band's windows for other regions' half-edges, one letter per
    /// receiving region; the letter last written to; emptied letters
    /// kept for their buffers.
    letters: Vec<Letter>,
    last_letter: usize,
    spare_letters: Vec<Letter>,
    /// The sources' windows, merged in the first band.
    seed_windows: Vec<(u32, EndedWindow)>,
    /// The distance limit (infinite: none): windows reaching nothing
    /// within it are dropped as they are appended.
    limit: f64,
    /// AVTP: slots reached while outside (the wavefront), those reset,
    /// and lists between two reset slots that grew since the last reset.
    resets: bool,
    front: Vec<u32>,
    is_reset: Vec<bool>,
    grown: Vec<u32>,
    /// Crossing's buffers (and lighting's `info`).
    cross: CrossBuffers,
    /// Scratch: the regions this one mails, and those that mailed it.
    mailed: Vec<u32>,
    senders: Vec<u32>,
    merge: MergeBuffers,
    prefetched: [u32; UPCOMING],
    counts: Counts,
}

/// What a region counts for [`Stats`].
#[derive(Clone, Copy, Default)]
struct Counts {
    props: u64,
    prime: u64,
    created: u64,
    pops: u64,
    emissions: u64,
    settled: u64,
    live: u64,
}

/// Where a face is laid out: its region and its local number there (one
/// record, as every crossing that leaves a face reads both).
#[derive(Clone, Copy, Default)]
struct FacePlace {
    region: u32,
    local: u32,
}

/// Read-only during bands.
struct Shared<'a> {
    mesh: &'a Mesh,
    kind: &'a [FaceKind],
    /// Every face is proper (no zero-area face): `kind` need not be read.
    all_proper: bool,
    max_distance: f64,
    /// Per face: its region and its number there.
    place: &'a [FacePlace],
    /// PAVTP: light the apex beyond a list before a reset deletes it
    /// (`WindowReset::light_apices`).
    light_apices: bool,
}

/// The regions of one mesh, laid out by its first region solve and kept
/// for the next ones (see [`crate::PreparedMesh`]): each solve restarts
/// their state instead of laying them out again in fresh memory.
pub(crate) struct Prepared {
    setup: SolverSetup,
    all_proper: bool,
    place: Vec<FacePlace>,
    regions: Vec<Region>,
    copies: Grouped<(u32, u32)>,
    /// Per region: the other regions with a copy of one of its vertices
    /// (those it can mail and be mailed by).
    neighbours: Vec<Vec<u32>>,
    /// The list buffers the threads held as spares when the last solve
    /// ended, handed out again to the next solve's threads.
    spares: Vec<Vec<EndedWindow>>,
    /// How many active region bands the last solve started ahead (a
    /// count of the schedule's work, read by the tests).
    started_ahead: u64,
}

/// The windows one region sends another in a band, in the order it made
/// them. They are handed over, not copied: the receiver merges them from
/// the sender's outbox.
#[derive(Default)]
struct Letter {
    to: u32,
    /// Per window: the receiver's half-edge (global number).
    half_edges: Vec<u32>,
    windows: Vec<EndedWindow>,
}

/// A region's mail of one band.
#[derive(Default)]
struct Outbox {
    /// One letter per receiving region, in no particular order.
    letters: Vec<Letter>,
    /// `(region, slot, distance, source, arrival, pseudo)`.
    distances: Vec<(u32, u32, f64, u32, Arrival, bool)>,
}

/// Where regions leave what the next band and the driving thread read.
struct Post {
    /// Per region, by band parity: the mail it wrote.
    out: Vec<[Mutex<Outbox>; 2]>,
    /// Per region, by band parity: whether mail waits for it (what
    /// `senders` being non-empty says, read by the driving thread without
    /// taking each region's lock).
    has_mail: Vec<[AtomicBool; 2]>,
    /// Per region: its nearest queued distance (bits), its last band's
    /// work, whether it has wavefront copies (AVTP), its live windows.
    top: Vec<AtomicU64>,
    load: Vec<AtomicU64>,
    has_front: Vec<AtomicBool>,
    live: Vec<AtomicU64>,
    /// By band parity: the least distance mailed in the band (bits), and
    /// whether anything was mailed.
    least_mailed: [AtomicU64; 2],
    mailed_any: [AtomicBool; 2],
    settled: AtomicU64,
    /// Per region, by band parity: the regions that mailed it (a sender
    /// adds itself once per band; the receiver sorts and empties it).
    senders: Vec<[Mutex<Vec<u32>>; 2]>,
    /// Per thread: list buffers given back by regions the wavefront has
    /// left, for the next region that needs a new list. Each region
    /// growing its own lists kept five times VTP's list memory alive
    /// (1.4M windows' room on the welded dragon against VTP's 0.3M), all
    /// of it fresh pages.
    spares: Vec<Mutex<Vec<Vec<EndedWindow>>>>,
    /// The band the driving thread published last.
    current: AtomicU64,
    /// By band parity: the band's regions that finished.
    done: [AtomicUsize; 2],
    /// Per region: 1 + the band of its task not yet finished (0: none).
    running: Vec<AtomicU64>,
    /// Per region: 1 + the last band it was claimed for (by the driving
    /// thread, or by a thread looking ahead; see `claim_ahead`).
    claimed: Vec<AtomicU64>,
    /// Per region claimed by a thread looking ahead: `(1 + band) << 1 |
    /// active`, written once the claim is decided, and its queue top and
    /// live windows before the band (the driving thread's sums of the
    /// band before read these).
    decided: Vec<AtomicU64>,
    top_at_claim: Vec<AtomicU64>,
    live_at_claim: Vec<AtomicU64>,
}

/// What the threads of a band read.
struct Band {
    index: u64,
    bound: f64,
    /// AVTP: reset the wavefront copies within this distance first.
    guard: Option<f64>,
    /// The active regions the driving thread decided, in the crew's claim
    /// order (those claimed ahead run already).
    order: Vec<u32>,
    /// All of the band's active regions.
    tasks: usize,
    /// The next band's bound when threads may start it ahead (see
    /// `claim_ahead`), and the regions that may be active in it.
    ahead: Option<f64>,
    candidates: Vec<u32>,
}

impl Prepared {
    /// How many regions the mesh was cut into.
    #[cfg(test)]
    pub(crate) fn region_count(&self) -> usize {
        self.regions.len()
    }

    /// How many active region bands the last solve started ahead.
    #[cfg(test)]
    pub(crate) fn started_ahead(&self) -> u64 {
        self.started_ahead
    }
}

/// Runs the region schedule on the current rayon pool of `threads`
/// threads (the sources are valid), on the regions kept in `prepared`
/// (laid out first if there are none; `mesh` is the mesh they were laid
/// out for).
pub(crate) fn solve(
    prepared: &mut Option<Prepared>,
    mesh: &Mesh,
    sources: &[Source],
    options: &PvtpOptions,
    threads: usize,
    start: Instant,
) -> (DistanceField, Stats) {
    let h = mesh.average_edge_length();
    // Taken for the solve: a solve that panics leaves none, and the next
    // one lays the regions out afresh.
    let laid_out = prepared.is_none();
    let mut prep = prepared
        .take()
        .unwrap_or_else(|| build(mesh, REGION_CELL_EDGES * h));
    let resets = options.reset.is_some();
    prep.regions.par_iter_mut().for_each(|r| {
        r.restart(
            &prep.setup,
            resets,
            options.max_distance.unwrap_or(f64::INFINITY),
            !laid_out,
        )
    });
    let mut regions = std::mem::take(&mut prep.regions);
    let copies = &prep.copies;
    let shared = Shared {
        mesh,
        kind: &prep.setup.kind,
        all_proper: prep.all_proper,
        max_distance: options.max_distance.unwrap_or(f64::INFINITY),
        place: &prep.place,
        light_apices: options.reset.is_some_and(|r| r.light_apices),
    };
    let mut created = 0;
    for (i, source) in sources.iter().enumerate() {
        let seeds = seeds(mesh, shared.kind, source, i as u32);
        for &v in &seeds.pseudo {
            for &(r, s) in copies.of(v) {
                let x = &mut regions[r as usize].slots[s as usize];
                x.pseudo = true;
                x.shadowed = false;
            }
        }
        for &(v, d) in &seeds.distances {
            for &(r, s) in copies.of(v) {
                regions[r as usize].lower(s, d, i as u32, Arrival::Unknown);
            }
        }
        for &(t, w) in &seeds.windows {
            created += 1;
            let r = shared.place[(t / 3) as usize].region as usize;
            regions[r].seed_windows.push((t, EndedWindow::new(w)));
        }
    }
    let nr = regions.len();
    let post = Post {
        out: (0..nr)
            .map(|_| [Mutex::default(), Mutex::default()])
            .collect(),
        has_mail: (0..nr)
            .map(|_| [AtomicBool::new(false), AtomicBool::new(false)])
            .collect(),
        top: regions
            .iter()
            .map(|r| AtomicU64::new(r.top().to_bits()))
            .collect(),
        load: (0..nr).map(|_| AtomicU64::new(0)).collect(),
        has_front: regions
            .iter()
            .map(|r| AtomicBool::new(!r.front.is_empty()))
            .collect(),
        live: (0..nr).map(|_| AtomicU64::new(0)).collect(),
        least_mailed: [
            AtomicU64::new(f64::INFINITY.to_bits()),
            AtomicU64::new(f64::INFINITY.to_bits()),
        ],
        mailed_any: [AtomicBool::new(false), AtomicBool::new(false)],
        settled: AtomicU64::new(0),
        senders: (0..nr)
            .map(|_| [Mutex::new(Vec::new()), Mutex::new(Vec::new())])
            .collect(),
        spares: {
            let mut kept = std::mem::take(&mut prep.spares);
            let share = kept.len().div_ceil(threads.max(1));
            (0..threads)
                .map(|_| {
                    let at = kept.len().saturating_sub(share);
                    Mutex::new(kept.split_off(at))
                })
                .collect()
        },
        current: AtomicU64::new(0),
        done: [AtomicUsize::new(0), AtomicUsize::new(0)],
        running: (0..nr).map(|_| AtomicU64::new(0)).collect(),
        claimed: (0..nr).map(|_| AtomicU64::new(0)).collect(),
        decided: (0..nr).map(|_| AtomicU64::new(0)).collect(),
        top_at_claim: (0..nr).map(|_| AtomicU64::new(0)).collect(),
        live_at_claim: (0..nr).map(|_| AtomicU64::new(0)).collect(),
    };
    // The seeds' windows are read in band 0, as mail of "band −1".
    for (r, region) in regions.iter().enumerate() {
        if !region.seed_windows.is_empty() {
            post.has_mail[r][1].store(true, Ordering::Relaxed);
            post.mailed_any[1].store(true, Ordering::Relaxed);
        }
    }
    let regions: Vec<Mutex<Region>> = regions.into_iter().map(Mutex::new).collect();
    let band = RwLock::new(Band {
        index: 0,
        bound: f64::NEG_INFINITY,
        guard: None,
        order: Vec::new(),
        tasks: 0,
        ahead: None,
        candidates: Vec::new(),
    });
    let crew = Crew::new(threads);
    let t0 = Instant::now();
    let mut driver = Driver {
        threads,
        delta: BAND_EDGES * h,
        reset_step: options.reset.map(|r| (r.lambda * h, r.lambda_g * h)),
        next_reset: options.reset.map_or(f64::INFINITY, |r| r.lambda * h),
        bands: 0,
        resets: 0,
        peak_live: 0,
        started_ahead: 0,
        progress: options.progress.clone(),
    };
    let team = Team {
        crew: &crew,
        band: &band,
        regions: &regions,
        post: &post,
        shared: &shared,
        neighbours: &prep.neighbours,
        threads,
    };
    rayon::scope(|scope| {
        for i in 1..threads {
            scope.spawn(move |_| {
                let crew = team.crew;
                let mut seen = 0;
                let mut candidates = Vec::new();
                while crew.wait_phase(&mut seen) {
                    if crew.guarded(|| team.work(i, &mut candidates)).is_none() {
                        return; // the driving thread raises the panic
                    }
                }
            });
        }
        let _stop = crew.stop_on_drop();
        driver.run(&team);
    });
    let band_seconds = t0.elapsed().as_secs_f64();
    let regions: Vec<Region> = regions
        .into_iter()
        .map(|m| {
            m.into_inner()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
        })
        .collect();
    let mut spares = Vec::new();
    for thread in post.spares {
        spares.extend(
            thread
                .into_inner()
                .unwrap_or_else(std::sync::PoisonError::into_inner),
        );
    }
    let mut counts = Counts {
        created,
        ..Counts::default()
    };
    for r in &regions {
        let c = r.counts;
        counts.props += c.props;
        counts.prime += c.prime;
        counts.created += c.created;
        counts.pops += c.pops;
        counts.emissions += c.emissions;
    }
    // Each vertex takes its nearest copy (the first of equal ones, in
    // region order), gathered on the pool.
    let best: Vec<(f64, u32)> = (0..mesh.vertex_count() as u32)
        .into_par_iter()
        .map(|v| {
            copies
                .of(v)
                .iter()
                .map(|&(r, s)| {
                    let x = &regions[r as usize].slots[s as usize];
                    (x.dist, x.src)
                })
                .fold(
                    (f64::INFINITY, NO_SOURCE),
                    |b, c| if c.0 < b.0 { c } else { b },
                )
        })
        .collect();
    let field = DistanceField::from_vertices(mesh, options.max_distance, |v| best[v]);
    let stats = Stats {
        windows_created: counts.created,
        window_propagations: counts.props,
        prime_propagations: counts.prime,
        secondary_propagations: counts.props - counts.prime,
        peak_live_windows: driver.peak_live,
        peak_window_bytes: driver.peak_live * std::mem::size_of::<EndedWindow>() as u64,
        vertex_pops: counts.pops,
        pseudo_source_emissions: counts.emissions,
        parallel_phases: driver.bands,
        threads: threads as u64,
        window_resets: driver.resets,
        propagation_seconds: band_seconds,
        pruning_seconds: 0.0,
        total_seconds: start.elapsed().as_secs_f64(),
        ..Stats::default()
    };
    let management = (stats.total_seconds - band_seconds).max(0.0);
    prep.regions = regions;
    prep.spares = spares;
    prep.started_ahead = driver.started_ahead;
    *prepared = Some(prep);
    (
        field,
        Stats {
            management_seconds: management,
            ..stats
        },
    )
}

/// Items grouped by a key below a bound, each group in the items' order
/// (compressed rows): each vertex's copies as `(region, slot)` pairs in
/// region order, each region's runs of faces, and in a region's layout
/// each slot's local fan and its copies elsewhere.
#[derive(Default)]
struct Grouped<T> {
    /// Key `k`'s items are `items[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    items: Vec<T>,
}

impl<T> Grouped<T> {
    /// Where key `k`'s items lie in `items`.
    #[inline]
    fn range(&self, k: u32) -> std::ops::Range<usize> {
        self.start[k as usize] as usize..self.start[k as usize + 1] as usize
    }

    #[inline]
    fn of(&self, k: u32) -> &[T] {
        &self.items[self.range(k)]
    }
}

/// A [`Grouped`] built by counting: each item's key is
/// [`Grouping::count`]ed, then, after [`Grouping::counted`], each item is
/// [`Grouping::put`] in the order its group keeps. (Taking the pairs as an
/// iterator walked twice cost 2–4 ms more per layout on a 941K-face mesh:
/// the callers' pairs come out of nested loops.)
struct Grouping<T> {
    start: Vec<u32>,
    fill: Vec<u32>,
    items: Vec<T>,
}

impl<T: Copy + Default> Grouping<T> {
    fn new(keys: usize) -> Grouping<T> {
        Grouping {
            start: vec![0; keys + 1],
            fill: Vec::new(),
            items: Vec::new(),
        }
    }

    #[inline]
    fn count(&mut self, k: u32) {
        self.start[k as usize + 1] += 1;
    }

    fn counted(mut self) -> Grouping<T> {
        let keys = self.start.len() - 1;
        for k in 0..keys {
            self.start[k + 1] += self.start[k];
        }
        self.fill = self.start[..keys].to_vec();
        self.items = vec![T::default(); self.start[keys] as usize];
        self
    }

    #[inline]
    fn put(&mut self, k: u32, item: T) {
        let at = &mut self.fill[k as usize];
        self.items[*at as usize] = item;
        *at += 1;
    }

    fn finish(self) -> Grouped<T> {
        Grouped {
            start: self.start,
            items: self.items,
        }
    }
}

/// Cuts the mesh into regions of cubes `cell` wide and lays each out, on
/// the current pool (their solve state is set by [`Region::restart`]).
fn build(mesh: &Mesh, cell: f64) -> Prepared {
    let tol = Tolerance::for_mesh(mesh);
    let setup = SolverSetup::new(mesh, &tol);
    let nf = mesh.face_count();
    let nv = mesh.vertex_count();
    let inv = if cell.is_finite() && cell > 0.0 {
        1.0 / cell
    } else {
        1.0
    };
    // A cube's key packs its three 21-bit cell numbers; regions are
    // numbered in key order.
    let keys: Vec<u64> = mesh
        .positions()
        .par_iter()
        .map(|&p| {
            let k = p * inv;
            let m = (1u64 << 21) - 1;
            ((cell_index(k.x) as u64 & m) << 42)
                | ((cell_index(k.y) as u64 & m) << 21)
                | (cell_index(k.z) as u64 & m)
        })
        .collect();
    // Every face's corners, read once from the mesh's half-edge records
    // (96 bytes a face) into 12 bytes a face for the passes below.
    let corners: Vec<[u32; 3]> = (0..nf as u32)
        .into_par_iter()
        .map(|f| mesh.face(f))
        .collect();
    let (runs, nr) = cube_runs(&keys, &corners);
    // A region's faces are its runs' faces, in face order: the local
    // number of each run's first face, and the runs of each region.
    let mut run_local = Vec::with_capacity(runs.len());
    let mut region_faces = vec![0u32; nr];
    for &(r, _, n) in &runs {
        run_local.push(region_faces[r as usize]);
        region_faces[r as usize] += n;
    }
    let mut runs_of_region = Grouping::new(nr);
    for &(r, _, _) in &runs {
        runs_of_region.count(r);
    }
    let mut runs_of_region = runs_of_region.counted();
    for (i, &(r, _, _)) in runs.iter().enumerate() {
        runs_of_region.put(r, i as u32);
    }
    let runs_of_region = runs_of_region.finish();
    let mut place = vec![FacePlace::default(); nf];
    place
        .par_chunks_mut(LAYOUT_CHUNK)
        .enumerate()
        .for_each(|(c, chunk)| {
            let first = (c * LAYOUT_CHUNK) as u32;
            let mut i = runs.partition_point(|&(_, f, n)| f + n <= first);
            for (f, p) in (first..).zip(chunk.iter_mut()) {
                while runs[i].1 + runs[i].2 <= f {
                    i += 1;
                }
                let (region, start, _) = runs[i];
                *p = FacePlace {
                    region,
                    local: run_local[i] + (f - start),
                };
            }
        });
    // Per region: a slot per vertex, numbered as its faces (in face
    // order) meet them, the slots' local fans and the faces' records
    // (the copies are found once every region has its slots).
    // Each thread numbers the slots through one vertex-long table, kept
    // for all the regions it lays out.
    let threads = rayon::current_num_threads().max(1);
    let tables: Vec<Mutex<Vec<(u32, u32)>>> = (0..threads).map(|_| Mutex::default()).collect();
    let parts: Vec<(Layout, Vec<LocalFace>)> = (0..nr)
        .into_par_iter()
        .map(|r| {
            let thread = rayon::current_thread_index().unwrap_or(0) % threads;
            let mut table = lock(&tables[thread]);
            if table.len() != nv {
                // Per vertex: the region that last numbered it, its slot.
                table.resize(nv, (NONE, 0));
            }
            let mut slot_vertex = Vec::new();
            let mut faces = Vec::with_capacity(region_faces[r] as usize);
            for &i in runs_of_region.of(r as u32) {
                let (_, first, n) = runs[i as usize];
                for f in first..first + n {
                    faces.push(LocalFace {
                        lists: NEW_FACE,
                        corners: corners[f as usize].map(|v| {
                            let entry = &mut table[v as usize];
                            if entry.0 != r as u32 {
                                *entry = (r as u32, slot_vertex.len() as u32);
                                slot_vertex.push(v);
                            }
                            entry.1
                        }),
                        global: f,
                    });
                }
            }
            drop(table);
            // Local fans: the faces around each slot.
            let mut fans = Grouping::new(slot_vertex.len());
            for face in &faces {
                for &s in &face.corners {
                    fans.count(s);
                }
            }
            let mut fans = fans.counted();
            for (lf, face) in faces.iter().enumerate() {
                for &s in &face.corners {
                    fans.put(s, lf as u32);
                }
            }
            let lay = Layout {
                slot_vertex,
                fans: fans.finish(),
                copies: Grouped::default(),
                primary: Vec::new(),
            };
            (lay, faces)
        })
        .collect();
    let mut copies = Grouping::new(nv);
    for (lay, _) in &parts {
        for &v in &lay.slot_vertex {
            copies.count(v);
        }
    }
    let mut copies = copies.counted();
    for (r, (lay, _)) in parts.iter().enumerate() {
        for (s, &v) in lay.slot_vertex.iter().enumerate() {
            copies.put(v, (r as u32, s as u32));
        }
    }
    let copies = copies.finish();
    let regions = parts
        .into_par_iter()
        .enumerate()
        .map(|(r, (lay, faces))| {
            let n = lay.slot_vertex.len();
            let mut copy_start = Vec::with_capacity(n + 1);
            let mut others = Vec::new();
            let mut primary = Vec::with_capacity(n);
            for (s, &v) in lay.slot_vertex.iter().enumerate() {
                copy_start.push(others.len() as u32);
                let mine = copies.of(v);
                primary.push(mine[0] == (r as u32, s as u32));
                others.extend(mine.iter().filter(|&&(q, _)| q as usize != r));
                // A pinch group's members: lowering one lowers them all.
                let g = setup.group_of[v as usize];
                if g != NO_GROUP {
                    for &u in setup.groups[g as usize].iter().filter(|&&u| u != v) {
                        others.extend_from_slice(copies.of(u));
                    }
                }
            }
            copy_start.push(others.len() as u32);
            Region {
                index: r,
                tol,
                faces,
                pool: Vec::new(),
                free: Vec::new(),
                spares: Vec::new(),
                slots: Vec::new(),
                arrival: Vec::new(),
                heap: VertexQueue::new(n),
                fifo: Vec::new(),
                dirty: Vec::new(),
                is_dirty: Vec::new(),
                letters: Vec::new(),
                last_letter: 0,
                spare_letters: Vec::new(),
                seed_windows: Vec::new(),
                limit: f64::INFINITY,
                resets: false,
                front: Vec::new(),
                is_reset: Vec::new(),
                grown: Vec::new(),
                cross: CrossBuffers::default(),
                mailed: Vec::new(),
                senders: Vec::new(),
                merge: MergeBuffers::default(),
                prefetched: [NONE; UPCOMING],
                counts: Counts::default(),
                lay: Layout {
                    copies: Grouped {
                        start: copy_start,
                        items: others,
                    },
                    primary,
                    ..lay
                },
            }
        })
        .collect::<Vec<Region>>();
    let neighbours = regions
        .par_iter()
        .map(|r| {
            let mut q: Vec<u32> = r.lay.copies.items.iter().map(|&(q, _)| q).collect();
            q.retain(|&q| q as usize != r.index);
            q.sort_unstable();
            q.dedup();
            q
        })
        .collect();
    Prepared {
        all_proper: setup.kind.iter().all(|&k| k == FaceKind::Proper),
        setup,
        place,
        regions,
        copies,
        neighbours,
        spares: Vec::new(),
        started_ahead: 0,
    }
}

/// Faces per parallel piece of the layout.
const LAYOUT_CHUNK: usize = 4096;

/// The runs of consecutive faces whose first corners lie in one cube
/// (`keys`: each vertex's cube), as `(region, first face, faces)` in face
/// order, and the number of regions: one per cube, numbered in key order.
/// A run does not cross a piece of [`LAYOUT_CHUNK`] faces.
fn cube_runs(keys: &[u64], corners: &[[u32; 3]]) -> (Vec<(u32, u32, u32)>, usize) {
    // Faces are numbered for locality, so runs are long: `(key, first
    // face, faces)` per run.
    let keyed_runs: Vec<(u64, u32, u32)> = corners
        .par_chunks(LAYOUT_CHUNK)
        .enumerate()
        .flat_map_iter(|(c, chunk)| {
            let mut runs: Vec<(u64, u32, u32)> = Vec::new();
            for (i, corner) in chunk.iter().enumerate() {
                let k = keys[corner[0] as usize];
                match runs.last_mut() {
                    Some(run) if run.0 == k => run.2 += 1,
                    _ => runs.push((k, (c * LAYOUT_CHUNK + i) as u32, 1)),
                }
            }
            runs
        })
        .collect();
    let mut distinct: Vec<u64> = keyed_runs.iter().map(|run| run.0).collect();
    distinct.par_sort_unstable();
    distinct.dedup();
    let runs = keyed_runs
        .par_iter()
        .map(|&(k, f, n)| {
            let r = distinct
                .binary_search(&k)
                .expect("every run's key is among the distinct keys");
            (r as u32, f, n)
        })
        .collect();
    (runs, distinct.len())
}

/// The driving thread's state between bands.
struct Driver {
    threads: usize,
    delta: f64,
    /// AVTP: `(λh, λ_g h)` and the next reset radius.
    reset_step: Option<(f64, f64)>,
    next_reset: f64,
    bands: u64,
    resets: u64,
    peak_live: u64,
    /// Active region bands the threads started ahead.
    started_ahead: u64,
    progress: Progress,
}

/// What every thread of a solve reads: the crew, the band, the regions
/// and their mail.
#[derive(Clone, Copy)]
struct Team<'a, 'm> {
    crew: &'a Crew,
    band: &'a RwLock<Band>,
    regions: &'a [Mutex<Region>],
    post: &'a Post,
    shared: &'a Shared<'m>,
    /// Per region: the regions it can mail and be mailed by (those with
    /// a copy of one of its vertices).
    neighbours: &'a [Vec<u32>],
    threads: usize,
}

impl Driver {
    /// The bands, one after the other. Between two bands the driving
    /// thread sums what the regions left (their queues' tops, the mail),
    /// picks the next bound and the regions with work, and hands them to
    /// the crew.
    ///
    /// Band `k + 1`'s bound is picked before band `k` runs (from the state
    /// after band `k − 1`), so a thread that has run out of band `k`'s
    /// regions can start band `k + 1` in a region whose neighbours are
    /// done with band `k` (`claim_ahead`): that region's band reads
    /// exactly what it would read after a barrier, so the result is the
    /// same whoever runs it when. This hides most of the wait at the end
    /// of a band for its longest region. Bands that may reset AVTP's
    /// wavefront are not started ahead: their guard needs the state after
    /// the band before.
    fn run(&mut self, team: &Team<'_, '_>) {
        let Team {
            crew,
            band,
            post,
            neighbours,
            ..
        } = *team;
        let nr = team.regions.len();
        let t = self.threads.max(1);
        let mut bound = f64::NEG_INFINITY;
        let mut queues: Vec<Vec<u32>> = vec![Vec::new(); t];
        let mut bounds = vec![(0, 0); t];
        // Per region: its queue's top after the last band.
        let mut tops = vec![f64::INFINITY; nr];
        // This band's bound, if it was picked a band ahead, and the
        // regions that may be active in it.
        let mut ahead: Option<f64> = None;
        let mut candidates: Vec<u32> = Vec::new();
        let mut next_candidates: Vec<u32> = Vec::new();
        // The band's candidates the driving thread claimed itself (no
        // thread started them ahead).
        let mut mine: Vec<u32> = Vec::new();
        // The band's active regions: the `early` ones started ahead
        // first, then those the driving thread hands to the crew.
        let mut active: Vec<u32> = Vec::new();
        // Per region: the last band whose candidates for the next took it.
        let mut seen = vec![u64::MAX; nr];
        // The driving thread's copy of the next band's candidates while
        // it works (as each helper keeps its own).
        let mut scratch = Vec::new();
        loop {
            let index = self.bands;
            let stamp = index + 1;
            let last = ((index + 1) % 2) as usize;
            // Claim the band's candidates nobody started ahead; wait for
            // the decisions of those somebody did.
            mine.clear();
            active.clear();
            let mut early = 0;
            if ahead.is_some() {
                for &r in &candidates {
                    let claimed = &post.claimed[r as usize];
                    let v = claimed.load(Ordering::Acquire);
                    if v < stamp
                        && claimed
                            .compare_exchange(v, stamp, Ordering::AcqRel, Ordering::Acquire)
                            .is_ok()
                    {
                        mine.push(r);
                        continue;
                    }
                    let mut waiting = Waiting::new();
                    loop {
                        let d = post.decided[r as usize].load(Ordering::Acquire);
                        if d >> 1 == stamp {
                            if d & 1 == 1 {
                                active.push(r);
                                early += 1;
                            }
                            break;
                        }
                        crew.idle(&mut waiting);
                    }
                }
            }
            self.started_ahead += early as u64;
            let mut least = f64::from_bits(
                post.least_mailed[last].swap(f64::INFINITY.to_bits(), Ordering::Acquire),
            );
            let mail = post.mailed_any[last].swap(false, Ordering::Acquire);
            let mut live = 0;
            for (r, top) in tops.iter_mut().enumerate() {
                // A region started ahead reported its state before it.
                let (t, l) = if post.decided[r].load(Ordering::Acquire) >> 1 == stamp {
                    (&post.top_at_claim[r], &post.live_at_claim[r])
                } else {
                    (&post.top[r], &post.live[r])
                };
                *top = f64::from_bits(t.load(Ordering::Relaxed));
                least = least.min(*top);
                live += l.load(Ordering::Relaxed);
            }
            self.peak_live = self.peak_live.max(live);
            self.progress
                .set_reached(post.settled.load(Ordering::Relaxed));
            // Done when nothing is queued and no mail waits. (Slots beyond
            // the distance limit are popped too: the lists around them may
            // still reach within it; see `Region::run`.)
            if !least.is_finite() && !mail {
                break;
            }
            let mut guard = None;
            if let Some(b) = ahead {
                bound = b;
                debug_assert!(
                    (0..nr).all(|r| seen[r] == index - 1
                        || (tops[r] >= bound && !post.has_mail[r][last].load(Ordering::Relaxed))),
                    "only a band's candidates can be active in it"
                );
                for &r in &mine {
                    let mailed = post.has_mail[r as usize][last].swap(false, Ordering::Relaxed);
                    if mailed || tops[r as usize] < bound {
                        active.push(r);
                    }
                }
            } else {
                // AVTP (Algorithm 3 of Du et al.): the wavefront passed
                // the next multiple of λh.
                if let Some((step, guard_band)) = self.reset_step
                    && least <= team.shared.max_distance
                    && least >= self.next_reset
                {
                    let steps = (least / step).floor();
                    self.next_reset = (steps + 1.0) * step;
                    guard = Some(steps * step + guard_band);
                    self.resets += 1;
                }
                if least.is_finite() {
                    bound = self.bound_after(bound, least, team);
                }
                for (r, &top) in tops.iter().enumerate() {
                    let mailed = post.has_mail[r][last].swap(false, Ordering::Relaxed);
                    let front = guard.is_some() && post.has_front[r].load(Ordering::Relaxed);
                    if mailed || front || top < bound {
                        active.push(r as u32);
                    }
                }
            }
            // The next band's bound, from the state after the last band;
            // it is picked now only when no reset can fall in that band
            // (its bound stays below the next reset radius).
            let next = if least.is_finite() {
                self.bound_after(bound, least, team)
            } else {
                f64::INFINITY
            };
            let look_ahead = next < self.next_reset && next.is_finite();
            next_candidates.clear();
            if look_ahead {
                // Active next: this band's regions, their neighbours (the
                // mail) and the regions whose top is below the bound.
                let mut add = |r: u32| {
                    if seen[r as usize] != index {
                        seen[r as usize] = index;
                        next_candidates.push(r);
                    }
                };
                for &r in &active {
                    add(r);
                    for &q in &neighbours[r as usize] {
                        add(q);
                    }
                }
                for (r, &top) in tops.iter().enumerate() {
                    if top < next {
                        add(r as u32);
                    }
                }
                // Each load read once: a region started ahead may be
                // writing its own meanwhile (a comparison that changes
                // under the sort breaks it).
                next_candidates.sort_by_cached_key(|&r| {
                    std::cmp::Reverse(post.load[r as usize].load(Ordering::Relaxed))
                });
            }
            for q in &mut queues {
                q.clear();
            }
            for &r in &active[early..] {
                post.running[r as usize].store(stamp, Ordering::Relaxed);
                queues[r as usize % t].push(r);
            }
            // No task of the next band has started: its count can restart.
            post.done[(stamp % 2) as usize].store(0, Ordering::Relaxed);
            let mut n = 0;
            let mut spec = write(band);
            spec.order.clear();
            for (q, b) in queues.iter_mut().zip(&mut bounds) {
                // The busiest of the last band first: the long ones do not
                // come last.
                q.sort_by_key(|&r| {
                    std::cmp::Reverse(post.load[r as usize].load(Ordering::Relaxed))
                });
                *b = (n, n + q.len());
                n += q.len();
                spec.order.extend_from_slice(q);
            }
            spec.index = index;
            spec.bound = bound;
            spec.guard = guard;
            spec.tasks = active.len();
            spec.ahead = look_ahead.then_some(next);
            std::mem::swap(&mut spec.candidates, &mut next_candidates);
            post.current.store(index, Ordering::Release);
            crew.begin(&bounds);
            drop(spec);
            if t > 1 && (n > 1 || (look_ahead && !active.is_empty())) {
                crew.publish();
            }
            team.work(0, &mut scratch);
            // The next band's candidates, as the threads saw them: `work`
            // copied them into `scratch`.
            std::mem::swap(&mut candidates, &mut scratch);
            ahead = look_ahead.then_some(next);
            self.bands += 1;
        }
    }

    /// The bound of the band after one bounded by `bound` when the
    /// nearest queued or mailed distance is `least` (finite): `δ` beyond
    /// the farther of the two, but not past `stop`.
    fn bound_after(&self, bound: f64, least: f64, team: &Team<'_, '_>) -> f64 {
        (bound.max(least) + self.delta).min(self.stop(least, team))
    }

    /// Where the band after one whose least queued distance is `least`
    /// must stop: the next reset radius, or nowhere beyond the distance
    /// limit (no reset comes there, and a bound held there would never
    /// let the wavefront pass it).
    fn stop(&self, least: f64, team: &Team<'_, '_>) -> f64 {
        if least <= team.shared.max_distance {
            self.next_reset
        } else {
            f64::INFINITY
        }
    }
}

impl Team<'_, '_> {
    /// A thread's share of a band: the regions it claims, then, while the
    /// band's last regions run, regions of the next band it can start
    /// ahead.
    fn work(&self, w: usize, candidates: &mut Vec<u32>) {
        let post = self.post;
        let mut spares = lock(&post.spares[w]);
        let (index, tasks, ahead) = {
            let band = read(self.band);
            while let Some(pos) = self.crew.claim(w) {
                let r = band.order[pos] as usize;
                self.run_band(r, band.index, band.bound, band.guard, &mut spares);
            }
            candidates.clear();
            candidates.extend_from_slice(&band.candidates);
            (band.index, band.tasks, band.ahead)
        };
        let parity = (index % 2) as usize;
        let mut waiting = Waiting::new();
        // The band's finished regions when the candidates were last
        // looked at: none can become ready before another finishes.
        let mut looked = usize::MAX;
        loop {
            let done = post.done[parity].load(Ordering::Acquire);
            // Once the band is over, the driving thread picks the next
            // one; the others look ahead until it is published.
            let over = done >= tasks;
            if (over && (w == 0 || ahead.is_none()))
                || post.current.load(Ordering::Acquire) != index
                || self.crew.stopped()
            {
                return;
            }
            if w == 0 {
                self.crew.raise_failure();
            } else if self.crew.failed() {
                return;
            }
            if let Some(bound) = ahead
                && done != looked
            {
                if self.claim_ahead(w, index + 1, bound, candidates, &mut spares) {
                    waiting = Waiting::new();
                    continue;
                }
                looked = done;
            }
            self.crew.idle(&mut waiting);
        }
    }

    /// Region `r`'s band `index`: its mail, AVTP's reset, VTP's loop up to
    /// `bound`, its own mail out.
    fn run_band(
        &self,
        r: usize,
        index: u64,
        bound: f64,
        guard: Option<f64>,
        spares: &mut Vec<Vec<EndedWindow>>,
    ) {
        let (post, shared) = (self.post, self.shared);
        let mut region = lock(&self.regions[r]);
        let before = region.counts;
        std::mem::swap(&mut region.spares, spares);
        region.receive(shared, post, index);
        if let Some(guard) = guard {
            region.reset(shared, guard);
        }
        region.run(shared, bound);
        region.flush(post, index);
        region.give_back_lists();
        std::mem::swap(&mut region.spares, spares);
        let c = region.counts;
        drop(region);
        post.load[r].store(
            c.props - before.props + POP_WEIGHT * (c.pops - before.pops),
            Ordering::Relaxed,
        );
        post.settled
            .fetch_add(c.settled - before.settled, Ordering::Relaxed);
        // Cleared before counted: the driving thread marks the next
        // band's tasks once all of this band's are counted.
        post.running[r].store(0, Ordering::Release);
        post.done[(index % 2) as usize].fetch_add(1, Ordering::Release);
    }

    /// Starts band `index` ahead in one of its `candidates` (this thread's
    /// own first) whose neighbours and itself are done with the band
    /// before: nothing can reach it from that band any more, so whether
    /// it is active and what it reads are final. Returns whether it
    /// claimed one.
    fn claim_ahead(
        &self,
        w: usize,
        index: u64,
        bound: f64,
        candidates: &[u32],
        spares: &mut Vec<Vec<EndedWindow>>,
    ) -> bool {
        let post = self.post;
        let stamp = index + 1;
        let t = self.threads.max(1);
        for own in [true, false] {
            for &c in candidates {
                let c = c as usize;
                if (c % t == w) != own {
                    continue;
                }
                let claimed = &post.claimed[c];
                let v = claimed.load(Ordering::Acquire);
                // The band before is `index − 1`, marked `index` in `running`.
                let busy = |q: usize| post.running[q].load(Ordering::Acquire) == index;
                if v >= stamp || busy(c) || self.neighbours[c].iter().any(|&q| busy(q as usize)) {
                    continue;
                }
                if claimed
                    .compare_exchange(v, stamp, Ordering::AcqRel, Ordering::Acquire)
                    .is_err()
                {
                    continue;
                }
                let top = post.top[c].load(Ordering::Relaxed);
                post.top_at_claim[c].store(top, Ordering::Relaxed);
                post.live_at_claim[c]
                    .store(post.live[c].load(Ordering::Relaxed), Ordering::Relaxed);
                let mailed =
                    post.has_mail[c][((index + 1) % 2) as usize].swap(false, Ordering::Relaxed);
                let active = mailed || f64::from_bits(top) < bound;
                if active {
                    post.running[c].store(stamp, Ordering::Relaxed);
                }
                post.decided[c].store(stamp << 1 | active as u64, Ordering::Release);
                if active {
                    self.run_band(c, index, bound, None, spares);
                }
                return true;
            }
        }
        false
    }
}

/// How many spare list buffers a thread keeps (beyond, they are freed).
const MAX_SPARE_LISTS: usize = 1 << 14;

impl Region {
    /// Sets the region up for a new solve, as its layout left it: no list,
    /// no face entered, every slot unreached with its vertex's kind from
    /// `setup`; `resets`: AVTP's resets run (PAVTP); `limit`: the distance
    /// limit (infinite: none); `used`: a solve ran since the layout (if
    /// not, the faces are as laid out and there is no list). The buffers
    /// stay.
    fn restart(&mut self, setup: &SolverSetup, resets: bool, limit: f64, used: bool) {
        self.limit = limit;
        if used {
            for face in &mut self.faces {
                face.lists = NEW_FACE;
            }
            for list in &mut self.pool {
                list.clear();
            }
        }
        self.free.clear();
        self.free.extend((0..self.pool.len() as u32).rev());
        let n = self.lay.slot_vertex.len();
        self.slots.clear();
        self.slots.extend(
            self.lay
                .slot_vertex
                .iter()
                .map(|&v| setup.vertex_state(v as usize)),
        );
        self.arrival.clear();
        self.arrival.resize(n, Arrival::Unknown);
        self.heap.clear();
        self.fifo.clear();
        self.dirty.clear();
        self.is_dirty.clear();
        self.is_dirty.resize(n, false);
        self.recycle_letters();
        self.seed_windows.clear();
        self.resets = resets;
        self.front.clear();
        self.is_reset.clear();
        if resets {
            self.is_reset.resize(n, false);
        }
        self.grown.clear();
        self.mailed.clear();
        self.senders.clear();
        self.prefetched = [NONE; UPCOMING];
        self.counts = Counts::default();
    }

    /// Empties `letters` into the spare letters, keeping their buffers.
    fn recycle_letters(&mut self) {
        for mut letter in self.letters.drain(..) {
            letter.half_edges.clear();
            letter.windows.clear();
            self.spare_letters.push(letter);
        }
        self.last_letter = 0;
    }

    /// Once the region holds no window (the wavefront has left it, or
    /// not reached it), its list buffers go to the spares: every list
    /// with an index in `pool` holds a window (an emptied list is freed
    /// at once), so no list word points into `pool` any more.
    fn give_back_lists(&mut self) {
        if self.counts.live != 0 || self.pool.is_empty() {
            return;
        }
        debug_assert!(
            self.faces
                .iter()
                .all(|f| f.lists[..ENTERED].iter().all(|&w| w & !QUEUED == NO_LIST)),
            "no list is left when no window is"
        );
        let room = MAX_SPARE_LISTS.saturating_sub(self.spares.len());
        self.spares.extend(
            self.pool
                .drain(..)
                .filter(|list| list.capacity() > 0)
                .take(room),
        );
        self.free.clear();
    }

    fn top(&self) -> f64 {
        self.heap
            .peek()
            .map_or(f64::INFINITY, |(k, _)| f64::from_bits(k))
    }

    /// Lowers slot `s` to `d` if shorter (the test inlined: most
    /// candidates lose).
    #[inline(always)]
    fn lower(&mut self, s: u32, d: f64, src: u32, arrival: Arrival) {
        if d < self.slots[s as usize].dist {
            self.lower_now(s, d, src, arrival);
        }
    }

    fn lower_now(&mut self, s: u32, d: f64, src: u32, arrival: Arrival) {
        let x = &mut self.slots[s as usize];
        if x.dist == f64::INFINITY {
            // First reached: its local fan loads now, long before
            // `prefetch_upcoming` reads it to ask for its faces (as VTP's
            // `set_dist` does with the mesh's fan table).
            let fan = self.lay.fans.range(s);
            geodesics_mesh::prefetch(&self.lay.fans.items, fan.start);
            geodesics_mesh::prefetch(&self.lay.fans.items, fan.end.saturating_sub(1));
            if self.resets && !x.inside {
                self.front.push(s);
            }
        }
        x.dist = d;
        x.src = src;
        if x.shadowed {
            self.arrival[s as usize] = arrival;
        }
        if !x.inside || x.must_emit(d, &self.tol) {
            self.heap.push_or_lower(d.to_bits(), s);
        }
        let copies = self.lay.copies.range(s);
        if copies.is_empty() {
            return;
        }
        if self.slots[s as usize].grouped {
            for k in copies {
                let (q, s2) = self.lay.copies.items[k];
                if q as usize == self.index {
                    self.lower(s2, d, src, Arrival::Unknown);
                }
            }
        }
        if !self.is_dirty[s as usize] {
            self.is_dirty[s as usize] = true;
            self.dirty.push(s);
        }
    }

    /// The mail of the last band: distances from every sender first, then
    /// windows, senders in region order.
    fn receive(&mut self, shared: &Shared<'_>, post: &Post, band: u64) {
        let seeds = std::mem::take(&mut self.seed_windows);
        for &(t, w) in &seeds {
            let lt = 3 * shared.place[(t / 3) as usize].local + t % 3;
            self.append(lt, self.ends_of(lt), &mut [w]);
        }
        let Some(last) = band.checked_sub(1) else {
            return;
        };
        let me = self.index as u32;
        let parity = (last % 2) as usize;
        // The regions that mailed this one, in region order; the emptied
        // buffer goes back for the next band's senders.
        let mut senders = std::mem::take(&mut self.senders);
        senders.clear();
        std::mem::swap(&mut *lock(&post.senders[self.index][parity]), &mut senders);
        senders.sort_unstable();
        for pass in 0..2 {
            for &q in &senders {
                // Written in the last band: q listed itself as it wrote it.
                let mut outbox = lock(&post.out[q as usize][parity]);
                if pass == 0 {
                    let ds = &outbox.distances;
                    let a = ds.partition_point(|m| m.0 < me);
                    let b = ds.partition_point(|m| m.0 <= me);
                    for &(_, s, d, src, arrival, pseudo) in &ds[a..b] {
                        if pseudo && shared.light_apices && d < self.slots[s as usize].dist {
                            // An apex another copy restarted (`light_apex_through`).
                            self.make_pseudo(s);
                        }
                        self.lower(s, d, src, arrival);
                    }
                    continue;
                }
                let Some(letter) = outbox.letters.iter_mut().find(|l| l.to == me) else {
                    continue;
                };
                let n = letter.windows.len();
                let mut i = 0;
                while i < n {
                    // The windows for one half-edge go in with one merge.
                    let t = letter.half_edges[i];
                    let j = i + letter.half_edges[i..]
                        .iter()
                        .take_while(|&&u| u == t)
                        .count();
                    let lt = 3 * shared.place[(t / 3) as usize].local + t % 3;
                    self.append(lt, self.ends_of(lt), &mut letter.windows[i..j]);
                    i = j;
                }
            }
        }
        self.senders = senders;
    }

    /// AVTP's reset on this region's copies: wavefront slots within
    /// `guard` become pseudo-sources emitting everywhere, and the lists
    /// between two of them still outside are emptied (their faces' apices
    /// lit through them first, if asked).
    fn reset(&mut self, shared: &Shared<'_>, guard: f64) {
        let mut check = std::mem::take(&mut self.grown);
        let mut front = std::mem::take(&mut self.front);
        front.retain(|&s| {
            let x = &mut self.slots[s as usize];
            if x.inside {
                return false;
            }
            if x.dist > guard {
                return true;
            }
            x.pseudo = true;
            x.shadowed = false;
            self.is_reset[s as usize] = true;
            for &lf in self.lay.fans.of(s) {
                check.extend((0..3).map(|i| 3 * lf + i));
            }
            false
        });
        self.front = front;
        for &lh in &check {
            let c = self.faces[(lh / 3) as usize].corners;
            let on_front = |i: u32| {
                let s = c[(i % 3) as usize] as usize;
                self.is_reset[s] && !self.slots[s].inside
            };
            if !(on_front(lh % 3) && on_front(lh % 3 + 1)) {
                continue;
            }
            if shared.light_apices {
                self.light_apex_through(shared, lh);
            }
            let word = list_word(&mut self.faces, lh);
            let idx = *word & !QUEUED;
            if idx != NO_LIST {
                *word = NO_LIST | (*word & QUEUED);
                let list = &mut self.pool[idx as usize];
                self.counts.live -= list.len() as u64;
                list.clear();
                self.free.push(idx);
            }
        }
        check.clear();
        self.grown = check;
    }

    /// PAVTP lighting apices: the apex of local half-edge `lh`'s face takes
    /// Rule 1's best path through the windows waiting on `lh`, as crossing
    /// the face would have given it, and restarts the front if that lowers
    /// it (as `geodesics-vtp`'s reset does).
    fn light_apex_through(&mut self, shared: &Shared<'_>, lh: u32) {
        let idx = list_word_of(&self.faces, lh) & !QUEUED;
        let (lf, i) = (lh / 3, lh % 3);
        let f = self.faces[lf as usize].global;
        if idx == NO_LIST || !(shared.all_proper || shared.kind[f as usize] == FaceKind::Proper) {
            return;
        }
        let h = 3 * f + i;
        let list = &self.pool[idx as usize];
        let Some((best, w, bend)) = path_to_apex(shared.mesh, h, list, &mut self.cross.info) else {
            return;
        };
        let apex = self.faces[lf as usize].corners[((i + 2) % 3) as usize];
        if best < self.slots[apex as usize].dist {
            // A restart, as in `geodesics-vtp`'s reset; the copies
            // elsewhere learn it with the distance (`receive`).
            self.make_pseudo(apex);
            let arrival = Arrival::Window {
                half_edge: h,
                at: bend,
            };
            self.lower(apex, best, w.source, arrival);
        }
    }

    /// Makes slot `s` a pseudo-source emitting everywhere, with its pinch
    /// group's members here (a lit apex restarting the front; see
    /// `light_apex_through`). Before it is lowered: a slot already inside
    /// is queued again only if it must emit.
    fn make_pseudo(&mut self, s: u32) {
        let x = &mut self.slots[s as usize];
        x.pseudo = true;
        x.shadowed = false;
        if x.grouped {
            for k in self.lay.copies.range(s) {
                let (q, s2) = self.lay.copies.items[k];
                if q as usize == self.index {
                    self.slots[s2 as usize].pseudo = true;
                }
            }
        }
    }

    /// VTP's loop on this region's slots nearer than `bound`.
    fn run(&mut self, shared: &Shared<'_>, bound: f64) {
        self.drain(shared);
        loop {
            let d = self.top();
            if !(d < bound) {
                break;
            }
            let Some((_, s)) = self.heap.pop() else {
                break;
            };
            // Beyond the distance limit a slot only lets the lists around
            // it propagate (see `geodesics-vtp`'s loop); it emits nothing.
            let beyond = d > self.limit;
            let x = self.slots[s as usize];
            let first = !x.inside;
            let emit = !beyond && x.must_emit(d, &self.tol);
            if !first && !emit {
                continue;
            }
            self.counts.pops += 1;
            if first {
                self.slots[s as usize].inside = true;
                if self.lay.primary[s as usize] && !beyond {
                    self.counts.settled += 1;
                }
                self.prefetch_upcoming(shared);
                // The faces around the vertex join the traversed area.
                for k in self.lay.fans.range(s) {
                    let lf = self.lay.fans.items[k];
                    let face = &mut self.faces[lf as usize];
                    // The mesh's records of the face, which its crossings
                    // read, asked for now that its local record (asked for
                    // by `prefetch_upcoming`) is at hand.
                    shared.mesh.prefetch_face(face.global);
                    let record = &mut face.lists;
                    if record[ENTERED] == NOT_ENTERED {
                        record[ENTERED] = self.counts.pops as u32;
                    }
                    // On the record in hand (no index arithmetic), as VTP.
                    for (i, word) in (3 * lf..).zip(&mut record[..ENTERED]) {
                        queue_list(word, i, &mut self.fifo);
                    }
                }
            }
            if emit {
                self.emit(shared, s);
            }
            self.drain(shared);
        }
    }

    /// Asks for the records of the slots popped soon (once each).
    fn prefetch_upcoming(&mut self, shared: &Shared<'_>) {
        let mut seen = [NONE; UPCOMING];
        for (j, u) in self.heap.upcoming(UPCOMING).enumerate() {
            seen[j] = u;
            if self.prefetched.contains(&u) {
                continue;
            }
            for &lf in self.lay.fans.of(u) {
                geodesics_mesh::prefetch(&self.faces, lf as usize);
            }
            geodesics_mesh::prefetch(&self.slots, u as usize);
            // Emitting walks the vertex's fan in the mesh's table.
            shared
                .mesh
                .prefetch_fan_table(self.lay.slot_vertex[u as usize]);
        }
        self.prefetched = seen;
    }

    #[inline]
    fn queue(&mut self, lh: u32) {
        queue_list(list_word(&mut self.faces, lh), lh, &mut self.fifo);
    }

    fn drain(&mut self, shared: &Shared<'_>) {
        // Held here for the whole drain, not taken and put back per list.
        let mut scratch = std::mem::take(&mut self.cross);
        let mut next = 0;
        while let Some(&lh) = self.fifo.get(next) {
            next += 1;
            if let Some(&lg) = self.fifo.get(next) {
                self.prefetch_list(lg);
            }
            self.process(shared, lh, &mut scratch);
        }
        self.fifo.clear();
        self.cross = scratch;
    }

    /// Asks for the first windows of the list on local half-edge `lh`,
    /// queued next: PAVTP's lists hold a few windows, so reading each was
    /// a cache miss per list (as in VTP's loop).
    #[inline]
    fn prefetch_list(&self, lh: u32) {
        let idx = list_word_of(&self.faces, lh) & !QUEUED;
        if let Some(list) = self.pool.get(idx as usize) {
            geodesics_mesh::prefetch(list, 0);
            geodesics_mesh::prefetch(list, 1);
        }
    }

    /// The slots at the ends of local half-edge `lh`.
    #[inline]
    fn ends_of(&self, lh: u32) -> [u32; 2] {
        let c = self.faces[(lh / 3) as usize].corners;
        [c[(lh % 3) as usize], c[((lh + 1) % 3) as usize]]
    }

    /// Merges `windows` into the list of local half-edge `lh`, whose ends
    /// are slots `ends` (Rules 2 and 3), and queues it if an end was
    /// passed, as VTP's `append`.
    #[inline(always)]
    fn append(&mut self, lh: u32, ends: [u32; 2], mut windows: &mut [EndedWindow]) {
        if self.limit < f64::INFINITY {
            windows = keep_within(windows, self.limit, &self.tol);
        }
        if windows.is_empty() {
            return;
        }
        let word = list_word_of(&self.faces, lh);
        let mut idx = word & !QUEUED;
        if idx == NO_LIST {
            idx = self.free.pop().unwrap_or_else(|| {
                self.pool.push(self.spares.pop().unwrap_or_default());
                let i = self.pool.len() - 1;
                assert!(i < NO_LIST as usize, "fewer window lists than 2^31 - 1");
                i as u32
            });
            *list_word(&mut self.faces, lh) = idx | (word & QUEUED);
        }
        let list = &mut self.pool[idx as usize];
        let before = list.len() as u64;
        merge_sorted(list, windows, &mut self.merge, &self.tol);
        let after = list.len() as u64;
        self.counts.live = self.counts.live + after - before;
        if after == 0 {
            let word = list_word(&mut self.faces, lh);
            *word = NO_LIST | (*word & QUEUED);
            self.free.push(idx);
            return;
        }
        let [a, b] = ends.map(|s| s as usize);
        debug_assert_eq!(
            [a, b].map(|s| s as u32),
            self.ends_of(lh),
            "the caller's ends are the half-edge's"
        );
        if self.resets && self.is_reset[a] && self.is_reset[b] {
            self.grown.push(lh);
        }
        if self.slots[a].inside || self.slots[b].inside {
            self.queue(lh);
        }
    }

    /// Windows for global half-edge `t`: into its list if its face is this
    /// region's, else into the mail. `ends`: the slots of its ends when
    /// the caller knows them (a region has one slot per vertex, so the
    /// ends of the edge just crossed are the ends of its twin here too).
    #[inline(always)]
    fn send(
        &mut self,
        shared: &Shared<'_>,
        t: u32,
        ends: Option<[u32; 2]>,
        windows: &mut [EndedWindow],
    ) {
        self.send_to(shared.place[(t / 3) as usize], t, ends, windows);
    }

    /// [`Region::send`] with the place of `t`'s face looked up.
    #[inline(always)]
    fn send_to(
        &mut self,
        place: FacePlace,
        t: u32,
        ends: Option<[u32; 2]>,
        windows: &mut [EndedWindow],
    ) {
        if windows.is_empty() {
            return;
        }
        if place.region as usize == self.index {
            let lt = 3 * place.local + t % 3;
            let ends = ends.unwrap_or_else(|| self.ends_of(lt));
            self.append(lt, ends, windows);
        } else {
            let letter = self.letter_to(place.region);
            letter
                .half_edges
                .extend(std::iter::repeat_n(t, windows.len()));
            letter.windows.extend_from_slice(windows);
        }
    }

    /// This band's letter to region `to`, started if there is none.
    #[inline]
    fn letter_to(&mut self, to: u32) -> &mut Letter {
        let k = match self.letters.get(self.last_letter) {
            Some(l) if l.to == to => self.last_letter,
            _ => match self.letters.iter().position(|l| l.to == to) {
                Some(k) => k,
                None => {
                    let mut letter = self.spare_letters.pop().unwrap_or_default();
                    letter.to = to;
                    self.letters.push(letter);
                    self.letters.len() - 1
                }
            },
        };
        self.last_letter = k;
        &mut self.letters[k]
    }

    /// Pseudo-source slot `s` (Section 5.2 of Qin et al.): relaxes its
    /// neighbours along the edges of this region's faces around it and
    /// puts a window with source at the vertex on each edge opposite it,
    /// all of it or, for a saddle or flat vertex, the part in its shadow.
    /// Its copies in other regions do the same for their faces.
    fn emit(&mut self, shared: &Shared<'_>, s: u32) {
        let mesh = shared.mesh;
        let v = self.lay.slot_vertex[s as usize];
        let x = &mut self.slots[s as usize];
        let (d, src) = (x.dist, x.src);
        x.emitted = d;
        self.counts.emissions += 1;
        let fan = mesh.fan(v).iter().copied();
        let shadow = if x.shadowed {
            Shadow::of_fan(mesh, v, fan.clone(), self.arrival[s as usize], &self.tol)
        } else {
            None
        };
        let check_now = shadow.is_none();
        for (h, ray) in Shadow::fan_rays(shadow, mesh, fan) {
            let f = Mesh::face_of(h);
            let place = shared.place[f as usize];
            if place.region as usize != self.index {
                continue;
            }
            let c = self.faces[place.local as usize].corners;
            // The vertex is corner h % 3 of the face; a and b follow it.
            let (sa, sb) = (c[((h + 1) % 3) as usize], c[((h + 2) % 3) as usize]);
            let [(_, la, back_a), (_, lb, back_b)] = corner_neighbours(mesh, h);
            self.lower(sa, d + la, src, back_a);
            self.lower(sb, d + lb, src, back_b);
            if !shared.all_proper && shared.kind[f as usize] != FaceKind::Proper {
                continue;
            }
            let Some((t, w)) = ray.and_then(|r| pseudo_source_window(mesh, h, d, src, r)) else {
                continue;
            };
            self.counts.created += 1;
            let w = EndedWindow::new(w);
            if check_now {
                // Sent back into the traversed area (a reset vertex emits
                // into its whole fan), it loses to the edge's ends at once.
                let (da, db) = (self.slots[sa as usize].dist, self.slots[sb as usize].dist);
                if beaten_from_edge_ends(&w, mesh.length(Mesh::next(h)), db, da, &self.tol) {
                    continue;
                }
            }
            self.send(shared, t, Some([sb, sa]), &mut [w]);
        }
    }

    /// Propagates the list of local half-edge `lh` through its face.
    fn process(&mut self, shared: &Shared<'_>, lh: u32, scratch: &mut CrossBuffers) {
        let idx = std::mem::replace(list_word(&mut self.faces, lh), NO_LIST) & !QUEUED;
        if idx == NO_LIST {
            return;
        }
        let mut list = std::mem::take(&mut self.pool[idx as usize]);
        self.counts.live -= list.len() as u64;
        let lf = lh / 3;
        let f = self.faces[lf as usize].global;
        let h = 3 * f + lh % 3;
        let kind = if shared.all_proper {
            FaceKind::Proper
        } else {
            shared.kind[f as usize]
        };
        match kind {
            FaceKind::Proper => self.cross(shared, lh, h, &list, scratch),
            FaceKind::Zipper => {
                // One edge of length zero: the windows pass on to the twin
                // of the other long edge, as in VTP.
                let mesh = shared.mesh;
                if let Some(t) = mesh.zipper_exit(h).and_then(|g| mesh.twin(g)) {
                    self.send(shared, t, None, &mut list[..]);
                }
            }
            FaceKind::Blocked => {}
        }
        list.clear();
        self.pool[idx as usize] = list;
        self.free.push(idx);
    }

    /// VTP's crossing (Rule 1, one step per window, the vertex check on
    /// each child) of local half-edge `lh`, global `h`.
    fn cross(
        &mut self,
        shared: &Shared<'_>,
        lh: u32,
        h: u32,
        list: &[EndedWindow],
        scratch: &mut CrossBuffers,
    ) {
        let mesh = shared.mesh;
        let (lf, i) = (lh / 3, lh % 3);
        let n = Mesh::next(h);
        let p = Mesh::prev(h);
        // The beyond faces' places, read once: their records are asked
        // for now and written when the children are sent.
        let beyond = |g: u32| mesh.twin(g).map(|t| (t, shared.place[(t / 3) as usize]));
        let (beyond_left, beyond_right) = (beyond(p), beyond(n));
        for (_, place) in [beyond_left, beyond_right].into_iter().flatten() {
            if place.region as usize == self.index {
                geodesics_mesh::prefetch(&self.faces, place.local as usize);
            }
        }
        let c = self.faces[lf as usize].corners;
        let (sa, sb, sc) = (
            c[i as usize],
            c[((i + 1) % 3) as usize],
            c[((i + 2) % 3) as usize],
        );
        let tri =
            Triangle::with_lengths(mesh.length(h), mesh.apex(h), mesh.length(p), mesh.length(n));
        let tol = self.tol;
        let CrossBuffers { info, left, right } = scratch;
        let (best, k) = apex_paths(list, &tri, info);
        if best.is_finite() {
            let arrival = Arrival::Window {
                half_edge: h,
                at: info[k].1,
            };
            self.lower(sc, best, list[k].window.source, arrival);
        }
        let (da, db, dc) = (
            self.slots[sa as usize].dist,
            self.slots[sb as usize].dist,
            self.slots[sc as usize].dist,
        );
        // At most one child per window and side.
        if left.len() < list.len() {
            left.resize(list.len(), list[0]);
            right.resize(list.len(), list[0]);
        }
        let (mut n_left, mut n_right) = (0, 0);
        let props = step_windows(
            list,
            info,
            &tri,
            (best, k),
            (da, db, dc),
            &tol,
            (left, &mut n_left),
            (right, &mut n_right),
        );
        self.counts.props += props;
        self.counts.created += props;
        if self.faces[lf as usize].lists[ENTERED] == self.counts.pops as u32 {
            self.counts.prime += props;
        }
        // Beyond C → A and beyond B → C.
        if let Some((t, place)) = beyond_left {
            self.send_to(place, t, Some([sa, sc]), &mut left[..n_left]);
        }
        if let Some((t, place)) = beyond_right {
            self.send_to(place, t, Some([sc, sb]), &mut right[..n_right]);
        }
    }

    /// Hands this band's letters over, writes the lowered distances
    /// (sorted by receiving region, stable) and what the driving thread
    /// reads.
    fn flush(&mut self, post: &Post, band: u64) {
        let parity = (band % 2) as usize;
        let mut outbox = lock(&post.out[self.index][parity]);
        outbox.distances.clear();
        // The letters read in the last band go back to the spares.
        std::mem::swap(&mut outbox.letters, &mut self.letters);
        self.recycle_letters();
        let mut least = f64::INFINITY;
        for &s in &self.dirty {
            self.is_dirty[s as usize] = false;
            let x = self.slots[s as usize];
            let arrival = self.arrival[s as usize];
            for &(q, s2) in self.lay.copies.of(s) {
                if q as usize != self.index {
                    outbox
                        .distances
                        .push((q, s2, x.dist, x.src, arrival, x.pseudo));
                    least = least.min(x.dist);
                }
            }
        }
        self.dirty.clear();
        outbox.distances.sort_by_key(|m| m.0);
        // Each receiver once (it may have both windows and distances).
        let mut mailed = std::mem::take(&mut self.mailed);
        mailed.clear();
        mailed.extend(outbox.letters.iter().map(|l| l.to));
        mailed.extend(outbox.distances.iter().map(|m| m.0));
        mailed.sort_unstable();
        mailed.dedup();
        for &q in &mailed {
            post.has_mail[q as usize][parity].store(true, Ordering::Relaxed);
            lock(&post.senders[q as usize][parity]).push(self.index as u32);
        }
        if !mailed.is_empty() {
            post.mailed_any[parity].store(true, Ordering::Relaxed);
        }
        self.mailed = mailed;
        drop(outbox);
        post.least_mailed[parity].fetch_min(least.to_bits(), Ordering::Relaxed);
        post.top[self.index].store(self.top().to_bits(), Ordering::Relaxed);
        post.has_front[self.index].store(!self.front.is_empty(), Ordering::Relaxed);
        post.live[self.index].store(self.counts.live, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::WindowReset;
    use geodesics_mesh::BuildOptions;

    /// Solves on regions `cell_edges` mean edges wide with `threads`
    /// threads; returns the distances' bits, the propagations, the bands,
    /// the regions and the region bands started ahead.
    fn small_regions(
        mesh: &Mesh,
        sources: &[Source],
        reset: Option<WindowReset>,
        cell_edges: f64,
        threads: usize,
    ) -> (Vec<u64>, u64, u64, usize, u64) {
        let mut prepared = Some(build(mesh, cell_edges * mesh.average_edge_length()));
        let regions = prepared.as_ref().map_or(0, Prepared::region_count);
        let options = PvtpOptions {
            threads,
            reset,
            ..PvtpOptions::default()
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a test pool");
        let (field, stats) = pool.install(|| {
            solve(
                &mut prepared,
                mesh,
                sources,
                &options,
                threads,
                Instant::now(),
            )
        });
        let bits = field.distance.iter().map(|d| d.to_bits()).collect();
        let ahead = prepared.as_ref().map_or(0, Prepared::started_ahead);
        (
            bits,
            stats.window_propagations,
            stats.parallel_phases,
            regions,
            ahead,
        )
    }

    /// Regions a few edges wide: hundreds of them, tens per band, so
    /// threads start bands ahead (`claim_ahead`) all the time. Whoever
    /// runs a region's band, and when, the bits and counts stay those of
    /// one thread, exact PVTP and PAVTP alike.
    #[test]
    fn starting_bands_ahead_changes_no_bit() {
        let soup = geodesics_shapes::bumpy_sphere(4, 1.0, 12, 0.15, 7);
        let mesh = Mesh::build(soup, &BuildOptions::default()).expect("valid test mesh");
        let sources = [Source::Vertex(0), Source::Vertex(900)];
        let exact = geodesics_vtp::solve(&mesh, &sources, &Default::default())
            .expect("valid input")
            .0;
        for reset in [None, Some(WindowReset::every(3.0))] {
            let one = small_regions(&mesh, &sources, reset, 3.0, 1);
            assert!(one.3 > 100, "{} regions", one.3);
            if reset.is_none() {
                let scale = exact.distance.iter().fold(0.0f64, |m, &d| m.max(d));
                for (v, (&a, e)) in one.0.iter().zip(&exact.distance).enumerate() {
                    let a = f64::from_bits(a);
                    assert!(
                        (a - e).abs() <= 1e-12 * scale,
                        "vertex {v}: {a} against {e}"
                    );
                }
            }
            // One thread never starts a band ahead: it runs each band's
            // regions itself, then picks the next band.
            assert_eq!(one.4, 0);
            let mut ahead = 0;
            for threads in [2, 3, 4] {
                for _ in 0..3 {
                    let other = small_regions(&mesh, &sources, reset, 3.0, threads);
                    assert!(other.0 == one.0, "T={threads}, reset {reset:?}: other bits");
                    assert_eq!((other.1, other.2), (one.1, one.2), "T={threads}");
                    ahead += other.4;
                }
            }
            // What the test is about did happen (thousands of times when
            // measured; how many depends on the threads' timing).
            assert!(ahead > 0, "reset {reset:?}: no band started ahead");
        }
    }

    #[test]
    fn grouped_items_keep_their_order_within_a_key() {
        let pairs = [(2, 'a'), (0, 'b'), (2, 'c'), (3, 'd'), (0, 'e')];
        let mut grouping = Grouping::new(5);
        for &(k, _) in &pairs {
            grouping.count(k);
        }
        let mut grouping = grouping.counted();
        for &(k, item) in &pairs {
            grouping.put(k, item);
        }
        let grouped = grouping.finish();
        assert_eq!(grouped.of(0), ['b', 'e']);
        assert!(grouped.of(1).is_empty());
        assert_eq!(grouped.of(2), ['a', 'c']);
        assert_eq!(grouped.of(3), ['d']);
        assert!(grouped.of(4).is_empty());
    }
}
