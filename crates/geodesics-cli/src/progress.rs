//! A progress line on standard error while a long solve runs.
//!
//! Shown only when standard error is a terminal and the solve has taken
//! longer than [`QUIET_FOR`]: scripts, pipes and logs see nothing. The line
//! is rewritten in place and erased when the solve ends, so the summary on
//! standard output reads as without it.

use std::io::{IsTerminal, Write};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use geodesics::Progress;

/// How long a solve runs before its progress line appears.
const QUIET_FOR: Duration = Duration::from_secs(1);

/// How often the line is rewritten.
const EVERY: Duration = Duration::from_millis(250);

/// Runs `work` (a solve reporting to `progress`) and, if standard error is a
/// terminal, shows how far it has come while it runs.
pub fn while_solving<T>(label: &str, progress: &Progress, work: impl FnOnce() -> T) -> T {
    if !std::io::stderr().is_terminal() {
        return work();
    }
    let start = Instant::now();
    let (done, finished) = mpsc::channel::<()>();
    std::thread::scope(|scope| {
        scope.spawn(move || {
            let mut shown = 0;
            // Until `work` returns and its sender is dropped.
            while let Err(mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(EVERY) {
                let elapsed = start.elapsed();
                if elapsed < QUIET_FOR {
                    continue;
                }
                let line = progress_line(label, progress.reached(), progress.total(), elapsed);
                shown = shown.max(line.chars().count());
                // A failed write to the terminal only loses the display.
                let _ = write!(std::io::stderr(), "\r{line:<shown$}");
            }
            if shown > 0 {
                let _ = write!(std::io::stderr(), "\r{:shown$}\r", "");
            }
        });
        let result = work();
        drop(done);
        result
    })
}

/// The text of the progress line.
fn progress_line(label: &str, reached: u64, total: u64, elapsed: Duration) -> String {
    let seconds = elapsed.as_secs_f64();
    if total == 0 {
        return format!("{label}: starting, {seconds:.0} s");
    }
    let percent = 100.0 * reached as f64 / total as f64;
    format!("{label}: {reached} of {total} vertices reached ({percent:.0} %), {seconds:.0} s")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_says_how_many_vertices_and_how_long() {
        let line = progress_line("dragon.ply, mmp", 217_500, 435_000, Duration::from_secs(12));
        assert_eq!(
            line,
            "dragon.ply, mmp: 217500 of 435000 vertices reached (50 %), 12 s"
        );
        assert_eq!(
            progress_line("x", 0, 0, Duration::from_millis(1500)),
            "x: starting, 2 s"
        );
    }

    #[test]
    fn without_a_terminal_the_work_just_runs() {
        // Test runs capture standard error: nothing is shown, the result
        // comes back.
        let progress = Progress::tracked();
        assert_eq!(while_solving("test", &progress, || 42), 42);
    }
}
