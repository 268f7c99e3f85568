//! Progress of long work on stderr: items done of the total, the time so far and the time
//! left at the pace so far, at most one line a second (and always the last).

use std::sync::Mutex;
use std::time::Instant;

/// A progress line printer, shared between threads.
pub(super) struct Progress {
    label: &'static str,
    started: Instant,
    last: Mutex<Option<Instant>>,
}

impl Progress {
    /// Starts the clock for `label` ("tiles run", "tiles written", ...).
    pub(super) fn new(label: &'static str) -> Self {
        Self {
            label,
            started: Instant::now(),
            last: Mutex::new(None),
        }
    }

    /// Reports `done` of `total`.
    pub(super) fn report(&self, done: usize, total: usize) {
        let now = Instant::now();
        let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
        if done < total && last.is_some_and(|t| now.duration_since(t).as_secs_f64() < 1.0) {
            return;
        }
        *last = Some(now);
        let spent = self.started.elapsed().as_secs_f64();
        let left = if done > 0 {
            spent / done as f64 * (total - done.min(total)) as f64
        } else {
            f64::NAN
        };
        eprintln!(
            "{}: {done} of {total} ({spent:.1} s, about {left:.0} s left)",
            self.label
        );
    }
}
