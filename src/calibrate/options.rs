//! What the files of a calibration share: its options, the bounds on
//! every user count checked before any work, and the error of a bad one.

use crate::error::InputError;
use crate::field::Field;

/// Most parameter names in `fit`.
pub const MAX_FIT_NAMES: usize = 16;
/// Most unknowns of a fit, each specimen's own parameters counted once per
/// specimen.
pub const MAX_UNKNOWNS: usize = 64;
/// Most Levenberg-Marquardt iterations a caller may ask for.
pub const MAX_ITERATIONS: usize = 1000;
/// Most distinct pressures a cross-validation leaves out in turn (each
/// costs a fit).
pub const MAX_HELD_OUT_PRESSURES: usize = 100;
/// The iterations of [`CalibrateOptions::new`].
pub const DEFAULT_ITERATIONS: usize = 100;

/// What to fit and how long to try.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrateOptions {
    /// The parameters to fit, by scene key (`actuator.pemc.eps0`,
    /// `load.kappa`, `actuator.cl.e`, ...), by the key without `actuator.`
    /// (`pemc.p1`, `cl.e`), or by the short names `eps0`, `kappa`, `p1` to
    /// `p4`; `camera` fits every markers test's camera frame (angle and
    /// offset, nuisance parameters). A parameter a specimen lists in its
    /// `own` tables is fitted once per specimen; any other is shared by
    /// all.
    pub fit: Vec<String>,
    /// Most Levenberg-Marquardt iterations (1 to [`MAX_ITERATIONS`]).
    pub max_iterations: usize,
    /// Also fit again without each pressure in turn and predict it
    /// (leave-one-pressure-out; one refit per distinct pressure).
    pub cross_validate: bool,
}

impl CalibrateOptions {
    /// Fit `names` with [`DEFAULT_ITERATIONS`] at most.
    pub fn new<S: AsRef<str>>(names: &[S]) -> CalibrateOptions {
        CalibrateOptions {
            fit: names.iter().map(|s| s.as_ref().to_string()).collect(),
            max_iterations: DEFAULT_ITERATIONS,
            cross_validate: false,
        }
    }

    /// Checks the counts before anything is read or solved.
    pub(crate) fn validate(&self) -> Result<(), InputError> {
        if self.fit.is_empty() {
            return Err(inconsistent(
                "fit",
                "names no parameter: give at least one".into(),
            ));
        }
        if self.fit.len() > MAX_FIT_NAMES {
            return Err(InputError::OutOfRange {
                field: Field::key("fit"),
                value: self.fit.len() as f64,
                rule: format!("names more than {MAX_FIT_NAMES} parameters, the limit"),
            });
        }
        if !(1..=MAX_ITERATIONS).contains(&self.max_iterations) {
            return Err(InputError::OutOfRange {
                field: Field::key("max_iterations"),
                value: self.max_iterations as f64,
                rule: format!("must lie in [1, {MAX_ITERATIONS}]"),
            });
        }
        Ok(())
    }
}

/// An input error: `field` with `rule`.
pub(crate) fn inconsistent(field: &'static str, rule: String) -> InputError {
    InputError::Inconsistent {
        field: Field::key(field),
        rule,
    }
}
