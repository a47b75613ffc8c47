//! One study of the registry ([`super::STUDIES`]): what it is and how it
//! runs into its outputs.

use crate::actuator::Actuator;
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
    /// [`StudyInfo::output`], which also marks the folds in the figure).
    pub run: fn(&Actuator, &StudyOptions) -> Result<StudyOutput, SolveError>,
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
        let mut out = (self.run)(actuator, opts)?;
        out.mark_folds();
        Ok(out)
    }

    /// The stem of its figure and main table: `study<number>`.
    pub fn stem(&self) -> String {
        format!("study{}", self.number)
    }
}
