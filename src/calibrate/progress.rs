//! How far [`calibrate_with_progress`](super::calibrate_with_progress)
//! and [`choose_model_with_progress`](super::choose_model_with_progress)
//! have got: the events their observer receives ([`crate::progress`]:
//! one at a time, no count falling from one to the next).

/// The stage of a calibration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CalibrateStage {
    /// Levenberg-Marquardt iterations of the fit.
    Fitting,
    /// The fit again without each pressure in turn (cross-validation).
    CrossValidating,
    /// The calibrated scenes compared with the data again.
    Checking,
    /// Every element model, rib choice and plane state fitted
    /// (`choose_model`).
    ChoosingModel,
}

/// One progress event of a calibration.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CalibrateProgress {
    /// What the calibration is doing.
    pub stage: CalibrateStage,
    /// Levenberg-Marquardt iterations of the fit done so far.
    pub iterations: usize,
    /// The most it may take.
    pub max_iterations: usize,
    /// Evaluations of the residuals and their Jacobian finished so far
    /// (the count the calibration reports at the end; each solves every
    /// specimen).
    pub evaluations: usize,
    /// The chi-square at the fit's current parameters (`None` before the
    /// first evaluation).
    pub chi_square: Option<f64>,
    /// Specimens solved so far over every evaluation of the fit.
    pub specimens_solved: usize,
    /// Specimens of the manifest (solved once per evaluation).
    pub specimens: usize,
    /// Leave-one-pressure-out refits finished.
    pub refits_done: usize,
    /// Refits in all (0 without cross-validation).
    pub refits: usize,
    /// Candidates of a model choice fitted.
    pub candidates_done: usize,
    /// Candidates in all (0 outside a model choice).
    pub candidates: usize,
}

impl CalibrateProgress {
    /// A calibration of `specimens` specimens, not begun.
    pub(crate) fn new(max_iterations: usize, specimens: usize) -> CalibrateProgress {
        CalibrateProgress {
            stage: CalibrateStage::Fitting,
            iterations: 0,
            max_iterations,
            evaluations: 0,
            chi_square: None,
            specimens_solved: 0,
            specimens,
            refits_done: 0,
            refits: 0,
            candidates_done: 0,
            candidates: 0,
        }
    }

    /// The specimens solved of the evaluation under way (0 to
    /// [`specimens`](Self::specimens)): every evaluation finished solved
    /// them all.
    pub fn specimens_of_this_evaluation(&self) -> usize {
        self.specimens_solved
            .saturating_sub(self.evaluations * self.specimens)
            .min(self.specimens)
    }
}

/// The tracker of a calibration.
pub(crate) type Tracker<'a> = crate::progress::Tracker<'a, CalibrateProgress>;
