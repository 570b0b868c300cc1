//! The cross-core round trip: how fast two threads of this machine pass a
//! cache line, sampled along a benchmark's rounds. On shared VMs it varies
//! tenfold for minutes at a time, and the parallel solvers' gains with it.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

use serde_json::json;

use crate::Interleaved;
use crate::report::{Cell, number};

/// A round trip below this is a fast period of the cores (40–66 ns on our
/// VMs, against 140–800 ns in slow ones).
pub(crate) const FAST_ROUND_TRIP_NS: f64 = 100.0;

/// Round trips sampled before each round of an [`Interleaved`] run and
/// once after the last (none on a machine with one CPU).
pub(crate) struct RoundTrips {
    cores: usize,
    samples: Vec<f64>,
}

impl RoundTrips {
    pub fn new() -> RoundTrips {
        RoundTrips {
            cores: std::thread::available_parallelism().map_or(2, |n| n.get()),
            samples: Vec::new(),
        }
    }

    /// Takes a sample (none with one CPU).
    pub fn sample(&mut self) {
        self.samples.extend(round_trip_ns(self.cores));
    }

    /// Whether round `round` lay between two fast samples (before and
    /// after it): one the cores' slow periods most likely missed.
    fn fast(&self, round: usize) -> bool {
        [round, round + 1].iter().all(|&k| {
            self.samples
                .get(k)
                .is_some_and(|&ns| ns < FAST_ROUND_TRIP_NS)
        })
    }

    /// The samples' range, "lo–hi" ns (all of them in the JSON).
    pub fn range_cell(&self) -> Cell {
        if self.samples.is_empty() {
            return Cell::missing();
        }
        let lo = self.samples.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = self.samples.iter().copied().fold(0.0, f64::max);
        Cell::new(
            format!("{lo:.0}–{hi:.0}"),
            json!({"per_round": self.samples.iter().map(|&x| number(x)).collect::<Vec<_>>()}),
        )
    }

    /// How much faster `i` ran than `base` over the fast rounds only, and
    /// in how many of the rounds (nothing where no sample was taken).
    pub fn fast_speed_up(&self, timed: &Interleaved, base: usize, i: usize) -> Cell {
        if self.samples.is_empty() {
            return Cell::missing();
        }
        let rounds = timed.seconds[i].len();
        let fast_rounds = (0..rounds).filter(|&r| self.fast(r)).count();
        if fast_rounds == 0 {
            return Cell::new("no fast round", json!(null));
        }
        let spread = timed.speed_up_in(base, i, |r| self.fast(r));
        Cell::new(
            format!("{spread} in {fast_rounds} of {rounds}"),
            json!({
                "median": number(spread.median),
                "min": number(spread.min),
                "max": number(spread.max),
                "rounds": fast_rounds,
            }),
        )
    }
}

/// The time for two threads to pass one cache line there and back (the
/// best of three runs of up to 100,000 round trips, each cut short after
/// a second, as on a busy machine a trip can wait for a time slice), in
/// nanoseconds; `None` with one CPU, where the two would only take turns.
fn round_trip_ns(cores: usize) -> Option<f64> {
    const TRIPS: u64 = 100_000;
    const LIMIT_S: f64 = 1.0;
    if cores < 2 {
        return None;
    }
    let best = (0..3)
        .map(|_| {
            let line = AtomicU64::new(0);
            let stop = AtomicBool::new(false);
            let start = Instant::now();
            let mut trips = TRIPS;
            std::thread::scope(|scope| {
                scope.spawn(|| {
                    for i in 0..TRIPS {
                        while line.load(Ordering::Acquire) != 2 * i + 1 {
                            if stop.load(Ordering::Relaxed) {
                                return;
                            }
                            std::hint::spin_loop();
                        }
                        line.store(2 * i + 2, Ordering::Release);
                    }
                });
                for i in 0..TRIPS {
                    if i % 64 == 0 && start.elapsed().as_secs_f64() > LIMIT_S {
                        trips = i;
                        stop.store(true, Ordering::Relaxed);
                        break;
                    }
                    line.store(2 * i + 1, Ordering::Release);
                    while line.load(Ordering::Acquire) != 2 * i + 2 {
                        std::hint::spin_loop();
                    }
                }
            });
            start.elapsed().as_nanos() as f64 / trips.max(1) as f64
        })
        .fold(f64::INFINITY, f64::min);
    Some(best)
}
