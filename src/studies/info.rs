//! One study of the registry ([`super::STUDIES`]): what it is and how it
//! runs into its outputs.

use crate::actuator::Actuator;
use crate::sensitivity::Covariance;
use crate::solve_error::SolveError;

use super::options::StudyOptions;
use super::output::StudyOutput;

/// One study of the registry: what it is, and how to run it into its
/// outputs.
#[derive(Debug, Clone, Copy)]
pub struct StudyInfo {
    /// Its number in docs/model.md section 6 (1 to 8).
    pub number: usize,
    /// A short stable name (`prestrain_angle`).
    pub key: &'static str,
    /// Title.
    pub title: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// Runs the study and turns its result into outputs (call
    /// [`StudyInfo::output`], which also marks the folds in the figure),
    /// with 1-sigma bands from the covariance when one is given and the
    /// study has bands ([`StudyInfo::has_bands`]).
    pub run: fn(&Actuator, &StudyOptions, Option<&Covariance>) -> Result<StudyOutput, SolveError>,
    /// True when the study's curves get 1-sigma bands from a covariance.
    pub has_bands: bool,
    /// The outputs of a study that produced nothing: its tables with their
    /// columns and no rows, an empty figure, and its summary keys with
    /// empty values (`[]` or `null`).
    pub empty: fn() -> StudyOutput,
}

impl StudyInfo {
    /// Runs the study into its outputs, with every fold its sweeps met
    /// marked in its figure (a line at each fold's grasping size, its force in a note).
    pub fn output(
        &self,
        actuator: &Actuator,
        opts: &StudyOptions,
    ) -> Result<StudyOutput, SolveError> {
        self.output_with(actuator, opts, None)
    }

    /// [`StudyInfo::output`], with 1-sigma bands on its curves from
    /// `covariance` (docs/calibration.md section 7): a study with bands
    /// ([`StudyInfo::has_bands`]) adds a `<column>_sd` column to its main
    /// table for each banded column, shaded bands to its figure, the
    /// standard deviations to its summary and the columns' methods to
    /// [`StudyOutput::bands`]. Without a covariance, or for a study
    /// without bands, the outputs are those of [`StudyInfo::output`].
    pub fn output_with(
        &self,
        actuator: &Actuator,
        opts: &StudyOptions,
        covariance: Option<&Covariance>,
    ) -> Result<StudyOutput, SolveError> {
        let mut out = (self.run)(actuator, opts, covariance)?;
        out.mark_folds();
        Ok(out)
    }

    /// The stem of its figure and main table: `study<number>`.
    pub fn stem(&self) -> String {
        format!("study{}", self.number)
    }
}
