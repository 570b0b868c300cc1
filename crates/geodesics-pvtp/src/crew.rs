//! The crew: the threads of one solve, kept busy-waiting between phases.
//!
//! A phase of PVTP is short (tens to hundreds of microseconds of work on
//! meshes of a million faces), and there are thousands of them. Handing
//! each phase to rayon as a fork/join costs a sleeping worker's wake-up per
//! phase: on the 2-vCPU virtual machines we benchmark on that is 20–80 µs,
//! which held two threads to 1.15× one. Instead the solve spawns its `T − 1`
//! helpers once, as long-running tasks on the rayon pool of `T` threads the
//! caller chose, and they wait for the next phase by spinning on an epoch
//! counter (then yielding, then parking, so an oversubscribed machine is
//! not starved). A phase is published by one atomic increment.
//!
//! Each worker has a queue of the phase's jobs (in PVTP: the jobs of the
//! faces it owns, so the windows a worker writes beyond its faces are read
//! by the same worker in later phases, from its own cache); it takes its own
//! jobs from the front and, when they run out, steals from the back of the
//! others'. The crew only hands out positions; what a job reads and writes
//! is the caller's business (in PVTP: a read lock on the solver state and
//! the worker's own output buffer). Which thread runs which job never
//! changes a result: the jobs of one phase are independent and their
//! outputs are applied in job order.
//!
//! A panic in a job (an invariant broken) must not leave the others
//! waiting: a helper's panic is caught, recorded, and raised again on the
//! driving thread when it waits for the phase ([`Crew::wait_completed`]);
//! if the driving thread unwinds, the guard of [`Crew::stop_on_drop`]
//! stops the helpers, so the rayon scope around them returns and passes
//! the panic on, as a fork/join would.

use std::any::Any;
use std::panic::{self, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};
use std::thread::{self, Thread};
use std::time::{Duration, Instant};

/// How long a waiting thread spins before it starts yielding its CPU.
const SPIN: Duration = Duration::from_micros(50);

/// How long a helper waits for the next phase (spinning, then yielding)
/// before it parks. The sequential part between two phases usually takes
/// tens of microseconds; a parked helper costs a wake-up.
const PARK_AFTER: Duration = Duration::from_millis(2);

/// A value alone on its cache lines (two: the adjacent-line prefetcher), so
/// the counters the threads hammer do not share a line.
#[repr(align(128))]
#[derive(Default)]
struct Padded<T>(T);

/// Phase publication and job claiming for one solve (see the module docs).
pub(crate) struct Crew {
    /// Bumped once per published phase; helpers wait for it to change.
    epoch: Padded<AtomicU64>,
    /// Per worker: the positions `[front, back)` of its queue not yet
    /// claimed, packed as `back << 32 | front`.
    queues: Vec<Padded<AtomicU64>>,
    /// Jobs of the current phase finished (their outputs written).
    completed: Padded<AtomicUsize>,
    /// Set once, when the solve is over: helpers return.
    stop: AtomicBool,
    /// The payload of a helper's panic, raised again by the driving thread.
    failure: Mutex<Option<Box<dyn Any + Send>>>,
    failed: AtomicBool,
    /// Helpers parked (or about to park) waiting for a phase.
    parked: AtomicUsize,
    sleepers: Mutex<Vec<Thread>>,
    /// More workers than the machine has CPUs: a waiting thread yields at
    /// once and a helper parks at once, leaving the CPUs to the threads
    /// with work (spinning, 64 threads on 2 CPUs ran 5× slower than 2).
    oversubscribed: bool,
}

#[inline]
fn pack(front: usize, back: usize) -> u64 {
    debug_assert!(front <= u32::MAX as usize && back <= u32::MAX as usize);
    (back as u64) << 32 | front as u64
}

/// Takes the first (`from_back` false) or last position left in `queue`.
#[inline]
fn take(queue: &AtomicU64, from_back: bool) -> Option<usize> {
    let mut cur = queue.load(Ordering::Acquire);
    loop {
        let (front, back) = ((cur & 0xffff_ffff) as usize, (cur >> 32) as usize);
        if front >= back {
            return None;
        }
        let (new, got) = if from_back {
            (pack(front, back - 1), back - 1)
        } else {
            (pack(front + 1, back), front)
        };
        match queue.compare_exchange_weak(cur, new, Ordering::Acquire, Ordering::Acquire) {
            Ok(_) => return Some(got),
            Err(seen) => cur = seen,
        }
    }
}

impl Crew {
    /// A crew of `workers` threads (the caller and `workers − 1` helpers).
    pub(crate) fn new(workers: usize) -> Crew {
        Crew {
            epoch: Padded::default(),
            queues: (0..workers.max(1)).map(|_| Padded::default()).collect(),
            completed: Padded::default(),
            stop: AtomicBool::new(false),
            failure: Mutex::new(None),
            failed: AtomicBool::new(false),
            parked: AtomicUsize::new(0),
            sleepers: Mutex::new(Vec::new()),
            oversubscribed: thread::available_parallelism().is_ok_and(|n| workers > n.get()),
        }
    }

    /// Starts a phase: worker `w` gets the positions `bounds[w]` of the
    /// phase's claim order, none of them claimed or finished yet. Call it
    /// while no thread can claim (in PVTP the caller holds the solver state
    /// exclusively, and a helper claims only while it holds it shared).
    pub(crate) fn begin(&self, bounds: &[(usize, usize)]) {
        assert_eq!(bounds.len(), self.queues.len(), "one queue per worker");
        self.completed.0.store(0, Ordering::Relaxed);
        for (q, &(front, back)) in self.queues.iter().zip(bounds) {
            // Release: whoever claims from this queue sees the reset above
            // first, so its completion cannot be wiped by it.
            q.0.store(pack(front, back), Ordering::Release);
        }
    }

    /// Wakes the helpers for the phase [`Crew::begin`] started.
    pub(crate) fn publish(&self) {
        self.epoch.0.fetch_add(1, Ordering::SeqCst);
        // SeqCst on both sides: either this load sees a helper that is
        // about to park, or that helper's own check sees the new epoch.
        if self.parked.load(Ordering::SeqCst) > 0 {
            let mut sleepers = self.sleepers.lock().unwrap_or_else(PoisonError::into_inner);
            self.parked.store(0, Ordering::SeqCst);
            for t in sleepers.drain(..) {
                t.unpark();
            }
        }
    }

    /// Claims a position of the phase's claim order for worker `w`: the
    /// next one of its own queue, else the last one left in another's.
    #[inline]
    pub(crate) fn claim(&self, w: usize) -> Option<usize> {
        let t = self.queues.len();
        (0..t).find_map(|i| take(&self.queues[(w + i) % t].0, i != 0))
    }

    /// Reports `done` jobs finished, after their outputs were released.
    #[inline]
    pub(crate) fn complete(&self, done: usize) {
        if done > 0 {
            self.completed.0.fetch_add(done, Ordering::Release);
        }
    }

    /// Waits until all `n` jobs of the phase are finished; raises again
    /// the panic of a helper that failed instead.
    pub(crate) fn wait_completed(&self, n: usize) {
        let mut waiting = Waiting::new();
        while self.completed.0.load(Ordering::Acquire) < n {
            self.raise_failure();
            self.idle(&mut waiting);
        }
    }

    /// Raises again, on the driving thread, the panic of a helper that
    /// failed (if one did).
    pub(crate) fn raise_failure(&self) {
        if self.failed() {
            let payload = self
                .failure
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .take();
            panic::resume_unwind(payload.unwrap_or_else(|| Box::new("a crew helper panicked")));
        }
    }

    /// Whether a helper panicked (the others should return).
    pub(crate) fn failed(&self) -> bool {
        self.failed.load(Ordering::Acquire)
    }

    /// One pause of a thread waiting for the others: it yields its CPU at
    /// once when the crew has more threads than the machine has CPUs.
    #[inline]
    pub(crate) fn idle(&self, waiting: &mut Waiting) {
        if self.oversubscribed {
            thread::yield_now();
        } else {
            waiting.pause();
        }
    }

    /// A helper's share of a phase: what `work` returns (in PVTP's rounds,
    /// how many jobs it ran), `None` if it panicked (recorded for the
    /// driving thread; the helper should return).
    pub(crate) fn guarded<R>(&self, work: impl FnOnce() -> R) -> Option<R> {
        match panic::catch_unwind(AssertUnwindSafe(work)) {
            Ok(done) => Some(done),
            Err(payload) => {
                *self.failure.lock().unwrap_or_else(PoisonError::into_inner) = Some(payload);
                self.failed.store(true, Ordering::Release);
                None
            }
        }
    }

    /// Whether the solve is over.
    pub(crate) fn stopped(&self) -> bool {
        self.stop.load(Ordering::Acquire)
    }

    /// Ends the solve: waiting helpers return.
    pub(crate) fn stop(&self) {
        self.stop.store(true, Ordering::SeqCst);
        self.publish();
    }

    /// A guard that ends the solve when dropped, also when the driving
    /// thread unwinds.
    pub(crate) fn stop_on_drop(&self) -> StopOnDrop<'_> {
        StopOnDrop(self)
    }

    /// A helper's wait for the phase after epoch `seen`: `false` once the
    /// solve is over.
    pub(crate) fn wait_phase(&self, seen: &mut u64) -> bool {
        let mut waiting = Waiting::new();
        loop {
            let e = self.epoch.0.load(Ordering::SeqCst);
            if self.stop.load(Ordering::SeqCst) {
                return false;
            }
            if e != *seen {
                *seen = e;
                return true;
            }
            if !self.oversubscribed && (!waiting.pause() || waiting.start.elapsed() < PARK_AFTER) {
                continue;
            }
            {
                let mut sleepers = self.sleepers.lock().unwrap_or_else(PoisonError::into_inner);
                sleepers.push(thread::current());
                self.parked.fetch_add(1, Ordering::SeqCst);
            }
            if self.epoch.0.load(Ordering::SeqCst) == *seen && !self.stop.load(Ordering::SeqCst) {
                // An unpark that came first makes this return at once; a
                // spurious return only spins again.
                thread::park();
            }
            waiting = Waiting::new();
        }
    }
}

/// Stops the crew when dropped (see [`Crew::stop_on_drop`]).
pub(crate) struct StopOnDrop<'a>(&'a Crew);

impl Drop for StopOnDrop<'_> {
    fn drop(&mut self) {
        self.0.stop();
    }
}

/// Spin, then yield: a wait that is cheap when short and lets other
/// threads run when the machine has fewer cores than the crew.
pub(crate) struct Waiting {
    start: Instant,
    rounds: u32,
}

impl Waiting {
    pub(crate) fn new() -> Waiting {
        Waiting {
            start: Instant::now(),
            rounds: 0,
        }
    }

    /// One pause; returns whether the clock was read (every 64th round:
    /// it costs more than a pause), so the caller may check it too.
    #[inline]
    fn pause(&mut self) -> bool {
        self.rounds = self.rounds.wrapping_add(1);
        if !self.rounds.is_multiple_of(64) {
            std::hint::spin_loop();
            return false;
        }
        if self.start.elapsed() > SPIN {
            thread::yield_now();
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicU32;

    /// Runs the jobs of `crew` that worker `w` claims; returns how many.
    fn work(crew: &Crew, w: usize, runs: &[AtomicU32]) -> usize {
        let mut done = 0;
        while let Some(k) = crew.claim(w) {
            runs[k].fetch_add(1, Ordering::Relaxed);
            done += 1;
        }
        done
    }

    #[test]
    fn every_job_of_every_phase_runs_exactly_once() {
        let workers = 4;
        let crew = Crew::new(workers);
        let n = 203;
        let runs: Vec<AtomicU32> = (0..n).map(|_| AtomicU32::new(0)).collect();
        thread::scope(|s| {
            for w in 1..workers {
                let (crew, runs) = (&crew, &runs);
                s.spawn(move || {
                    let mut seen = 0;
                    while crew.wait_phase(&mut seen) {
                        crew.complete(work(crew, w, runs));
                    }
                });
            }
            for phase in 1..=50u32 {
                // Uneven queues, one of them empty: stealing evens them out.
                let cut = (phase as usize * 7) % n;
                crew.begin(&[(0, cut), (cut, cut), (cut, n - 3), (n - 3, n)]);
                crew.publish();
                crew.complete(work(&crew, 0, &runs));
                crew.wait_completed(n);
                assert!(runs.iter().all(|r| r.load(Ordering::Relaxed) == phase));
            }
            crew.stop();
        });
    }

    #[test]
    fn a_worker_takes_its_own_queue_first_then_steals_from_the_back() {
        let crew = Crew::new(2);
        crew.begin(&[(0, 2), (2, 5)]);
        assert_eq!(crew.claim(1), Some(2));
        assert_eq!(crew.claim(0), Some(0));
        assert_eq!(crew.claim(0), Some(1));
        assert_eq!(crew.claim(0), Some(4), "steals the last of queue 1");
        assert_eq!(crew.claim(1), Some(3));
        assert_eq!(crew.claim(1), None);
        assert_eq!(crew.claim(0), None);
    }

    #[test]
    fn a_helper_panic_reaches_the_driving_thread_instead_of_a_hang() {
        let crew = Crew::new(2);
        let outcome = panic::catch_unwind(AssertUnwindSafe(|| {
            thread::scope(|s| {
                s.spawn(|| {
                    let mut seen = 0;
                    while crew.wait_phase(&mut seen) {
                        let Some(done) = crew.guarded(|| {
                            assert!(crew.claim(1).is_none(), "job 1 is broken");
                            0
                        }) else {
                            return;
                        };
                        crew.complete(done);
                    }
                });
                let _stop = crew.stop_on_drop();
                // Job 1 is the helper's and panics there; job 0 is ours.
                crew.begin(&[(0, 1), (1, 2)]);
                crew.publish();
                assert_eq!(crew.claim(0), Some(0));
                crew.complete(1);
                crew.wait_completed(2);
            });
        }));
        let payload = outcome.expect_err("the helper's panic is raised again");
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied());
        assert_eq!(message, Some("job 1 is broken"));
    }

    #[test]
    fn parked_helpers_wake_for_a_phase_and_for_the_stop() {
        let crew = Crew::new(2);
        let runs = [AtomicU32::new(0)];
        thread::scope(|s| {
            s.spawn(|| {
                let mut seen = 0;
                while crew.wait_phase(&mut seen) {
                    crew.complete(work(&crew, 1, &runs));
                }
            });
            // Long enough for the helper to park.
            thread::sleep(PARK_AFTER * 3);
            crew.begin(&[(0, 0), (0, 1)]);
            crew.publish();
            // The job is the helper's; the caller steals it if the helper
            // is slow, as the solver's driving thread does.
            crew.complete(work(&crew, 0, &runs));
            crew.wait_completed(1);
            thread::sleep(PARK_AFTER * 3);
            crew.stop();
        });
        assert_eq!(runs[0].load(Ordering::Relaxed), 1);
    }
}
