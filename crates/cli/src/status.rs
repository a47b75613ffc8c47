//! The exit status of `fpc`, decided in one place ([`exit_code`]):
//!
//! | status | when |
//! | --- | --- |
//! | 0 | success (help and version included); also when the reader of standard output went away (`fpc kernels \| head`): the command stops quietly, as a Unix tool does |
//! | 1 | a failed solve, a failed study, an I/O failure writing output (a file, stdout), anything else |
//! | 2 | rejected input: a bad flag or value, an unreadable, oversized, malformed or invalid scene file or measurement file |
//! | 130 | stopped by Ctrl-C after writing the work finished so far (`fpc sweep`, `fpc-lab stress`; [`crate::interrupt`]), or having written nothing (`fpc design`, stopped before its design is found), or at once by a second Ctrl-C |

use std::fmt;

use fpc::scene::{SceneError, SceneReadError};
use fpc::{InputError, SolveError};

/// The command did what was asked.
pub const SUCCESS: i32 = 0;
/// A solve or study failed, or output could not be written.
pub const FAILURE: i32 = 1;
/// The input was rejected.
pub const REJECTED: i32 = 2;
/// Stopped by Ctrl-C (128 + SIGINT, as a shell reports it).
pub const INTERRUPTED: i32 = 130;

/// An error that is its message and whose type says how the run ended
/// (its status), with the function that makes one.
macro_rules! message_error {
    ($(#[$doc:meta])* $name:ident, $(#[$fdoc:meta])* $make:ident) => {
        $(#[$doc])*
        #[derive(Debug)]
        pub struct $name(String);

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(&self.0)
            }
        }

        impl std::error::Error for $name {}

        $(#[$fdoc])*
        pub fn $make(msg: impl Into<String>) -> anyhow::Error {
            $name(msg.into()).into()
        }
    };
}

message_error!(
    /// Input that the CLI itself rejects before the library sees it: a
    /// usage error, a scene file that cannot be read, is too large or is
    /// not TOML.
    Rejected,
    /// An error that marks rejected input, with this message.
    rejected
);

message_error!(
    /// A command stopped by Ctrl-C that wrote what it had finished; the
    /// message says what was written and what was not.
    Interrupted,
    /// The end of a run stopped by Ctrl-C, with this message.
    interrupted
);

/// Whether the run was stopped by Ctrl-C ([`interrupted`]).
pub fn is_interrupted(e: &anyhow::Error) -> bool {
    e.chain().any(|c| c.is::<Interrupted>())
}

/// The exit status of a run that ended with `result`.
pub fn exit_code(result: &anyhow::Result<()>) -> i32 {
    match result {
        Ok(()) => SUCCESS,
        Err(e) if reader_gone(e) => SUCCESS,
        Err(e) if is_interrupted(e) => INTERRUPTED,
        Err(e) if is_rejected_input(e) => REJECTED,
        Err(_) => FAILURE,
    }
}

/// Whether the run ended because the reader of a pipe went away (EPIPE on
/// standard output): not an error to report.
pub fn reader_gone(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Whether any error in the chain is one of the rejected-input kinds.
fn is_rejected_input(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.is::<Rejected>()
            || c.is::<InputError>()
            || c.is::<SceneError>()
            || c.is::<SceneReadError>()
            || c.is::<fpc::measure::MeasureError>()
            || matches!(c.downcast_ref::<SolveError>(), Some(SolveError::Input(_)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context as _;

    #[test]
    fn each_class_has_its_status() {
        assert_eq!(exit_code(&Ok(())), 0);
        assert_eq!(exit_code(&Err(rejected("usage"))), 2);
        let input = InputError::NotFinite {
            field: fpc::Field::key("x"),
            value: f64::NAN,
        };
        assert_eq!(exit_code(&Err(input.clone().into())), 2);
        // wrapped in context, or inside a SolveError, still input
        let wrapped = Err::<(), _>(SolveError::Input(input)).context("scene.toml");
        assert_eq!(exit_code(&wrapped.map_err(|e| e.context("more"))), 2);
        let io = std::io::Error::new(std::io::ErrorKind::BrokenPipe, "closed");
        assert_eq!(exit_code(&Err(anyhow::Error::new(io))), 0);
        let full = std::io::Error::new(std::io::ErrorKind::StorageFull, "full");
        assert_eq!(exit_code(&Err(anyhow::Error::new(full))), 1);
        assert_eq!(exit_code(&Err(anyhow::anyhow!("anything else"))), 1);
        let stopped = Err::<(), _>(interrupted("stopped")).context("sweep");
        assert_eq!(exit_code(&stopped), 130);
    }
}
