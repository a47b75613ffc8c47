//! Experiments on the `fpc` library, kept out of its user API: the seeded
//! numerical stress test ([`stress`]) and the study of run time against
//! error ([`accuracy`]). Both use only `fpc`'s public API, as a user's own
//! experiment would; the `fpc` binary runs them (`fpc stress`, `fpc
//! accuracy`).

pub mod accuracy;
pub mod stress;

pub use accuracy::{accuracy_study, AccuracyRow, AccuracyStudy, Reference};
pub use stress::{
    reason_name, stress, stress_inputs, stress_with, StressCase, StressConfig, StressInputs,
    StressOutcome, StressReport, MAX_DRAWS, RESIDUAL_LIMIT, ROTATION_LIMIT, STRESS_ELEMENT_COUNTS,
};
