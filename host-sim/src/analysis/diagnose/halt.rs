//! Stopping a search early: a wall-time limit
//! ([`DiagnoseOptions::max_seconds`]) or a raised [`StopFlag`] (Ctrl-C);
//! the best set found so far is kept and marked as such.

use super::outcome::{DiagnoseOptions, HaltReason, StopFlag};
use std::time::Instant;

/// When a search stops before its end: a wall-time limit or a raised flag
/// (Ctrl-C). Once it fires, every further simulation of the search is
/// refused, so that each fit ends at once and keeps the set before it; the
/// closing work (strengths, held-out RMS, latch findings) runs after
/// [`Halt::finish`].
pub(super) struct Halt {
    /// The deadline and the limit \[s\] it was set from.
    deadline: Option<(Instant, f64)>,
    stop: Option<StopFlag>,
    /// Why it fired, once it did.
    fired: std::sync::Mutex<Option<HaltReason>>,
    /// Set by [`Halt::finish`]: the search is over, simulate again.
    finished: std::sync::atomic::AtomicBool,
}

impl Halt {
    pub(super) fn new(opts: &DiagnoseOptions, t0: Instant) -> Halt {
        Halt {
            // A limit past what the clock can hold (`inf`, 1e300 s) is no
            // limit.
            deadline: opts.max_seconds.and_then(|s| {
                let d = std::time::Duration::try_from_secs_f64(s.max(0.0)).ok()?;
                Some((t0.checked_add(d)?, s))
            }),
            stop: opts.stop.clone(),
            fired: std::sync::Mutex::new(None),
            finished: std::sync::atomic::AtomicBool::new(false),
        }
    }

    /// True when the search must stop (and records why, once).
    pub(super) fn now(&self) -> bool {
        if self.finished.load(std::sync::atomic::Ordering::Relaxed) {
            return false;
        }
        let why = if self.stop.as_ref().is_some_and(StopFlag::raised) {
            HaltReason::Interrupted
        } else if let Some((_, limit_s)) = self.deadline.filter(|(d, _)| Instant::now() >= *d) {
            HaltReason::TimeLimit { limit_s }
        } else {
            return false;
        };
        let mut f = self.fired.lock().unwrap_or_else(|e| e.into_inner());
        f.get_or_insert(why);
        true
    }

    /// The search is over: simulations are allowed again; why it stopped
    /// early, if it did.
    pub(super) fn finish(&self) -> Option<HaltReason> {
        self.finished
            .store(true, std::sync::atomic::Ordering::Relaxed);
        *self.fired.lock().unwrap_or_else(|e| e.into_inner())
    }
}
