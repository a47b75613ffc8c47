//! Experiments on the `fpc` library, kept out of its user API: the seeded
//! numerical stress test ([`stress`](mod@stress)) and the accuracy-time front of every
//! element model, partition kind and extrapolation ([`accuracy`]). Both use
//! only `fpc`'s public API, as a user's own experiment would; the lab's
//! own binary runs them (`fpc-lab stress`, `fpc-lab accuracy`, and
//! `fpc-lab timing` for in-process solve times).

pub mod accuracy;
pub mod stress;

pub use accuracy::{
    accuracy_study, standard_load, study_models, AccuracyRow, AccuracyStudy, Convergence,
    FamilyLimit, Fastest, FrontPoint, LibraryChoice, ModelGap, ModelReference, Plan, StudyConfig,
    TimingReference, CONFIGURATIONS, QUICK_CONFIGURATIONS, TIME_RESOLUTION, TOLERANCES_MM,
};
pub use stress::{
    dense_negative_eigenvalues, finding_name, force_scale, inside_envelope, reason_name, stress,
    stress_case, stress_inputs, stress_with, PartitionKey, Quantiles, StressCase, StressConfig,
    StressInputs, StressOutcome, StressReport, Tally, AUTO_FRACTION, CONDITIONING_MAX_ELEMENTS,
    DENSE_CHECK_MAX_ELEMENTS, FINE_VALIDITY_SAMPLES, MAX_DRAWS, RESIDUAL_LIMIT,
    STABILITY_TOLERANCE, STRESS_ELEMENT_COUNTS,
};
