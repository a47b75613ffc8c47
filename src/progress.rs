//! Progress of long work, for a caller that shows it: the design search
//! ([`crate::design::optimize_with_progress`]) and the calibration
//! ([`crate::calibrate::calibrate_with_progress`]) hand an observer an
//! event (their own type) as they go. The library itself prints nothing.
//!
//! The work runs on several threads; each event is made and handed to
//! the observer under one lock ([`Tracker`]), so the observer sees the
//! events one at a time and none of their counts falls from one event to
//! the next. The observer should return quickly (store the event, say):
//! the work waits for it.

use std::sync::{Mutex, PoisonError};

/// The observer of a piece of work and the state its events report.
pub(crate) struct Tracker<'a, P> {
    observer: &'a (dyn Fn(&P) + Sync),
    state: Mutex<P>,
}

impl<'a, P> Tracker<'a, P> {
    /// Work whose first state is `state`, reported to `observer`.
    pub fn new(observer: &'a (dyn Fn(&P) + Sync), state: P) -> Tracker<'a, P> {
        Tracker {
            observer,
            state: Mutex::new(state),
        }
    }

    /// Changes the state by `change` and hands the observer the result,
    /// both under the lock (module docs).
    pub fn update(&self, change: impl FnOnce(&mut P)) {
        // after an observer's panic the state is still whole: go on with it
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        change(&mut state);
        (self.observer)(&state);
    }
}
