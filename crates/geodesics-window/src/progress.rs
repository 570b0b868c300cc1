//! Progress of a running solve, readable from another thread.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// A view onto a running solve from another thread: how many of the mesh's
/// vertices its wavefront has reached so far. Give a clone of a
/// [`Progress::tracked`] handle to a solver's options and read it while the
/// solve runs (a progress bar, a log line). The default handle tracks
/// nothing and costs nothing.
///
/// What counts as reached: for the VTP family (VTP, AVTP, PVTP, PAVTP) a
/// vertex the wavefront has passed (its distance is final); for MMP and ICH
/// a vertex that has a distance (it may still drop). Either way the count
/// grows with the wavefront and ends at the number of vertices reached
/// (pinch copies included), which is below the total when parts of the
/// mesh are not connected to a source or lie beyond the distance limit.
///
/// ```
/// use geodesics_window::Progress;
///
/// let progress = Progress::tracked();
/// let seen_by_solver = progress.clone();
/// seen_by_solver.start(10);
/// seen_by_solver.set_reached(4);
/// assert_eq!((progress.reached(), progress.total()), (4, 10));
/// assert_eq!(progress.fraction(), Some(0.4));
/// // An untracked handle reports nothing.
/// assert_eq!(Progress::default().fraction(), None);
/// ```
#[derive(Clone, Debug, Default)]
pub struct Progress(Option<Arc<Counters>>);

#[derive(Debug, Default)]
struct Counters {
    reached: AtomicU64,
    total: AtomicU64,
}

impl Progress {
    /// A handle whose clones share one counter.
    pub fn tracked() -> Progress {
        Progress(Some(Arc::default()))
    }

    /// Whether this handle has a counter (an untracked one reports 0 of
    /// 0 whatever the solve does).
    #[inline]
    pub fn is_tracked(&self) -> bool {
        self.0.is_some()
    }

    /// Vertices reached so far.
    pub fn reached(&self) -> u64 {
        self.0
            .as_ref()
            .map_or(0, |c| c.reached.load(Ordering::Relaxed))
    }

    /// Vertices of the mesh being solved (pinch copies included); 0 until
    /// a solve starts.
    pub fn total(&self) -> u64 {
        self.0
            .as_ref()
            .map_or(0, |c| c.total.load(Ordering::Relaxed))
    }

    /// `reached / total`, or `None` before a solve starts or when
    /// untracked.
    pub fn fraction(&self) -> Option<f64> {
        let total = self.total();
        (total > 0).then(|| self.reached() as f64 / total as f64)
    }

    /// For solvers: a solve over `vertices` vertices starts (nothing
    /// reached yet).
    pub fn start(&self, vertices: usize) {
        if let Some(c) = &self.0 {
            c.reached.store(0, Ordering::Relaxed);
            c.total.store(vertices as u64, Ordering::Relaxed);
        }
    }

    /// How many vertices a solver lets pass between two stores of its
    /// count ([`Progress::note_reached`]).
    pub const REPORT_EVERY: u64 = 1024;

    /// For solvers, each time one more vertex is reached: `reached` is the
    /// running count, stored every [`Progress::REPORT_EVERY`] vertices
    /// (call [`Progress::set_reached`] with the final count at the end).
    #[inline]
    pub fn note_reached(&self, reached: u64) {
        if reached.is_multiple_of(Progress::REPORT_EVERY) {
            self.set_reached(reached);
        }
    }

    /// For solvers: `reached` vertices are reached by now (a count that
    /// only grows within a solve).
    #[inline]
    pub fn set_reached(&self, reached: u64) {
        if let Some(c) = &self.0 {
            c.reached.store(reached, Ordering::Relaxed);
        }
    }
}

/// Two handles are equal when they share a counter or both track nothing
/// (so options holding them compare by their settings).
impl PartialEq for Progress {
    fn eq(&self, other: &Progress) -> bool {
        match (&self.0, &other.0) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clones_share_the_counter_and_a_new_solve_restarts_it() {
        let p = Progress::tracked();
        let q = p.clone();
        assert_eq!(p, q);
        assert_ne!(p, Progress::tracked());
        assert_ne!(p, Progress::default());
        assert_eq!(Progress::default(), Progress::default());
        assert_eq!(p.fraction(), None);
        q.start(8);
        q.set_reached(8);
        assert_eq!(p.fraction(), Some(1.0));
        q.start(5);
        assert_eq!((p.reached(), p.total()), (0, 5));
        // Running counts are stored in steps.
        q.note_reached(Progress::REPORT_EVERY - 1);
        assert_eq!(p.reached(), 0);
        q.note_reached(Progress::REPORT_EVERY);
        assert_eq!(p.reached(), Progress::REPORT_EVERY);
        // Untracked: every call is a no-op.
        let none = Progress::default();
        none.start(3);
        none.set_reached(2);
        assert!(!none.is_tracked());
        assert_eq!((none.reached(), none.total()), (0, 0));
    }
}
