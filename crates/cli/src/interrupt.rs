//! Ctrl-C in a long command. [`arm`] installs the process's handler, and
//! the first Ctrl-C sets the flag it returns. The command runs its work
//! under that flag ([`fpc::cancel::with_flag`]: solves not yet started
//! fail at once with `SolveError::Cancelled`; `fpc sweep`, `fpc design`) or reads it
//! between pieces of work (`fpc-lab stress`), writes what it finished and
//! ends with [`crate::status::interrupted`] (status 130). A second Ctrl-C
//! ends the process at once, writing nothing more. A
//! process that inherits SIGINT ignored (a background job, `nohup`) keeps
//! it ignored; where the handler cannot be installed otherwise, Ctrl-C
//! keeps its default (the process ends) and a warning says so.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use crate::report;
use crate::status::INTERRUPTED;

/// Signals closer together than this are one press.
const SAME_PRESS: Duration = Duration::from_millis(300);

/// The process's flag, once armed (a handler can be installed only once).
static FLAG: OnceLock<Option<Arc<AtomicBool>>> = OnceLock::new();

/// Arms Ctrl-C for a long command and returns the flag it sets; `keeps`
/// says what the command does with its work when stopped (it ends the
/// note written at the first Ctrl-C). `None` where no handler could be
/// installed.
pub fn arm(keeps: &str) -> Option<Arc<AtomicBool>> {
    let keeps = keeps.to_owned();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let seen = flag.clone();
        let mut first: Option<Instant> = None;
        let installed = ctrlc::try_set_handler(move || {
            seen.store(true, Ordering::SeqCst);
            if let Some(t) = first {
                // one press can arrive twice (a signal sent to the process
                // and to its group, as `timeout` does): not a second press
                if t.elapsed() < SAME_PRESS {
                    return;
                }
                report::end_progress();
                report::note("stopped at once (second Ctrl-C); nothing more is written");
                std::process::exit(INTERRUPTED);
            }
            first = Some(Instant::now());
            report::end_progress();
            report::note(&format!(
                "Ctrl-C: stopping; {keeps} (Ctrl-C again quits at once, writing nothing more)"
            ));
        });
        match installed {
            Ok(()) => Some(flag),
            // SIGINT is not at its default: ignored (a background job,
            // nohup) or caught by someone else; left as it is
            Err(ctrlc::Error::MultipleHandlers) => None,
            Err(e) => {
                report::warning(&format!(
                    "cannot catch Ctrl-C ({e}): it will end the command without writing its results"
                ));
                None
            }
        }
    })
    .clone()
}
