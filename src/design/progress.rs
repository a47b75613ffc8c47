//! How far [`optimize_with_progress`](super::optimize_with_progress) has
//! got: the events its observer receives ([`crate::progress`]: one at a
//! time, no count falling from one to the next).

/// The stage of a design search.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DesignStage {
    /// Every start evaluated once, to rank them.
    Screening,
    /// The best starts ascended.
    Ascending,
    /// The best design evaluated again with its sensitivities, and its
    /// scenes solved again.
    Checking,
}

/// One progress event of a design search.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DesignProgress {
    /// What the search is doing.
    pub stage: DesignStage,
    /// Starts screened so far.
    pub starts_done: usize,
    /// Starts in all (the centre, the corners and the random ones).
    pub starts: usize,
    /// Ascents finished so far.
    pub ascents_done: usize,
    /// Ascents in all.
    pub ascents: usize,
    /// Design evaluations so far (the count [`Designed::evaluations`]
    /// reports at the end).
    ///
    /// [`Designed::evaluations`]: super::Designed::evaluations
    pub evaluations: usize,
    /// The largest worst margin of the designs screened or reached by an
    /// ascent so far (`None` before the first finite one).
    pub best_worst_margin: Option<f64>,
}

/// The tracker of a design search.
pub(crate) type Tracker<'a> = crate::progress::Tracker<'a, DesignProgress>;

impl Tracker<'_> {
    /// The search is at `stage`.
    pub fn stage(&self, stage: DesignStage) {
        self.update(|p| p.stage = stage);
    }

    /// One design evaluated.
    pub fn evaluated(&self) {
        self.update(|p| p.evaluations += 1);
    }
}

impl DesignProgress {
    /// A search of `starts` starts and `ascents` ascents, not begun.
    pub(crate) fn new(starts: usize, ascents: usize) -> DesignProgress {
        DesignProgress {
            stage: DesignStage::Screening,
            starts_done: 0,
            starts,
            ascents_done: 0,
            ascents,
            evaluations: 0,
            best_worst_margin: None,
        }
    }

    /// `worst` taken as a candidate for the best worst margin so far.
    pub(crate) fn offer(&mut self, worst: f64) {
        if worst.is_finite() && self.best_worst_margin.is_none_or(|b| worst > b) {
            self.best_worst_margin = Some(worst);
        }
    }
}
