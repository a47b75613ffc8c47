//! Stopping long work from another thread.
//!
//! A caller that may want to stop a long computation (a study, a design, a
//! sweep) runs it under a flag with [`with_flag`]. Once another thread sets
//! the flag, every finger solve the computation starts on that thread
//! fails at once with [`SolveError::Cancelled`]; the studies and designs
//! treat that like any failed solve, so the computation winds down in
//! microseconds and returns (its result incomplete, to be dropped). The
//! Python module sets the flag on Ctrl-C.
//!
//! The flag is per thread: work that the computation hands to other threads
//! does not see it, except through `par_map`, which runs independent
//! pieces of a computation on rayon's threads under the caller's flag, and
//! `current` and `under`, which hand a flag to a thread of one's own.
//! [`panic_text`] says what a panic on such a thread said, for the
//! front ends that catch one and report it.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crate::solve_error::SolveError;

thread_local! {
    static FLAG: RefCell<Option<Arc<AtomicBool>>> = const { RefCell::new(None) };
}

/// Restores the thread's previous flag when dropped (also on a panic).
struct Restore(Option<Arc<AtomicBool>>);

impl Drop for Restore {
    fn drop(&mut self) {
        let previous = self.0.take();
        FLAG.with(|f| *f.borrow_mut() = previous);
    }
}

/// What a caught panic said: its `&str` or `String` payload.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// Runs `f` on this thread with `flag` as its cancellation flag (module
/// docs); the previous flag, if any, is restored afterwards.
pub fn with_flag<T>(flag: Arc<AtomicBool>, f: impl FnOnce() -> T) -> T {
    let previous = FLAG.with(|cell| cell.borrow_mut().replace(flag));
    let _restore = Restore(previous);
    f()
}

/// `f` of every item, in order, on rayon's thread pool, each call under
/// this thread's flag (if any): a cancelled computation stops its pieces
/// on every thread. The results are those of a sequential map.
pub(crate) fn par_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    use rayon::prelude::*;
    let flag = current();
    items
        .par_iter()
        .map(|item| under(flag.clone(), || f(item)))
        .collect()
}

/// This thread's flag, to run work on another thread under it ([`under`]).
pub(crate) fn current() -> Option<Arc<AtomicBool>> {
    FLAG.with(|cell| cell.borrow().clone())
}

/// `f()` under `flag` where there is one ([`current`] of another thread).
pub(crate) fn under<T>(flag: Option<Arc<AtomicBool>>, f: impl FnOnce() -> T) -> T {
    match flag {
        Some(flag) => with_flag(flag, f),
        None => f(),
    }
}

/// True when this thread runs under a flag that has been set.
pub fn is_cancelled() -> bool {
    FLAG.with(|f| {
        f.borrow()
            .as_ref()
            .is_some_and(|flag| flag.load(Ordering::Relaxed))
    })
}

/// Fails with [`SolveError::Cancelled`] once this thread's flag is set.
pub(crate) fn check() -> Result<(), SolveError> {
    #[cfg(test)]
    if counted_check() {
        return Err(SolveError::Cancelled);
    }
    if is_cancelled() {
        Err(SolveError::Cancelled)
    } else {
        Ok(())
    }
}

#[cfg(test)]
thread_local! {
    /// Tests: the checks made on this thread under [`cancelled_from`], and
    /// the count from which they fail.
    static COUNTED: std::cell::Cell<Option<(usize, usize)>> = const { std::cell::Cell::new(None) };
}

/// Counts a check under [`cancelled_from`]; true where it fails.
#[cfg(test)]
fn counted_check() -> bool {
    COUNTED.with(|c| {
        c.get().is_some_and(|(made, from)| {
            c.set(Some((made + 1, from)));
            made + 1 >= from
        })
    })
}

/// Tests: runs `f` as if Ctrl-C came just before its `from`-th solve (its
/// `from`-th check and every later one fail), and returns its result
/// with the number of checks it made: a Ctrl-C at a chosen point, which
/// a flag set from another thread cannot place.
#[cfg(test)]
pub(crate) fn cancelled_from<T>(from: usize, f: impl FnOnce() -> T) -> (T, usize) {
    COUNTED.with(|c| c.set(Some((0, from))));
    let out = f();
    let made = COUNTED.with(|c| c.take()).map_or(0, |(made, _)| made);
    (out, made)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_flagged_thread_sees_its_flag() {
        let flag = Arc::new(AtomicBool::new(false));
        assert!(!is_cancelled());
        with_flag(flag.clone(), || {
            assert!(!is_cancelled());
            flag.store(true, Ordering::Relaxed);
            assert!(is_cancelled());
            assert_eq!(check(), Err(SolveError::Cancelled));
            // another thread runs without it
            assert!(!std::thread::scope(|s| s
                .spawn(is_cancelled)
                .join()
                .unwrap()));
            // a nested flag takes over, and the outer one comes back
            with_flag(
                Arc::new(AtomicBool::new(false)),
                || assert!(!is_cancelled()),
            );
            assert!(is_cancelled());
        });
        assert!(!is_cancelled());
    }

    #[test]
    fn par_map_keeps_the_order_and_hands_the_flag_on() {
        let items: Vec<usize> = (0..64).collect();
        assert_eq!(
            par_map(&items, |i| i * i),
            items.iter().map(|i| i * i).collect::<Vec<_>>()
        );
        assert!(par_map(&items, |_| is_cancelled()).iter().all(|c| !c));
        let flag = Arc::new(AtomicBool::new(true));
        let seen = with_flag(flag, || par_map(&items, |_| is_cancelled()));
        assert!(seen.iter().all(|c| *c));
        // the pool's threads keep no flag afterwards
        assert!(par_map(&items, |_| is_cancelled()).iter().all(|c| !c));
    }

    #[test]
    fn a_panic_says_what_it_said() {
        // (the test harness captures the panics' messages)
        let text = |f: fn()| panic_text(&*std::panic::catch_unwind(f).unwrap_err());
        assert_eq!(text(|| panic!("a literal")), "a literal");
        assert_eq!(text(|| panic!("formatted {}", 7)), "formatted 7");
        assert_eq!(
            text(|| std::panic::panic_any(7_u8)),
            "a panic without a message"
        );
    }
}
