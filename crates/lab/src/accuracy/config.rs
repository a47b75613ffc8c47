//! The configuration table: the plans every model is run with and what a
//! study times.

use std::time::Duration;

use fpc::plan::{PartitionKind, Refinement};
use fpc::ModelId;
use serde::Serialize;

use super::{EQUAL_ORDER_LEVELS, REFERENCE_START};

/// A configuration without its model: partition kind, coarsest partition,
/// levels and extrapolation (see [`Refinement`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Plan {
    /// Where element boundaries go.
    pub partition: PartitionKind,
    /// Equal: the coarsest N. Material: pieces at most lx / `start`.
    pub start: usize,
    /// Number of levels solved.
    pub levels: usize,
    /// Richardson extrapolation of the tip from the last two levels.
    pub extrapolate: bool,
}

impl Plan {
    /// One solve on `n` equal elements.
    pub const fn equal(n: usize) -> Plan {
        Plan {
            partition: PartitionKind::Equal,
            start: n,
            levels: 1,
            extrapolate: false,
        }
    }

    /// The material partition from pieces at most lx / 8, on `levels` levels.
    pub const fn material(levels: usize, extrapolate: bool) -> Plan {
        Plan {
            partition: PartitionKind::Material,
            start: REFERENCE_START,
            levels,
            extrapolate,
        }
    }

    /// The plan for `model`.
    pub fn for_model(self, model: ModelId) -> Refinement {
        Refinement {
            model,
            partition: self.partition,
            start: self.start,
            levels: self.levels,
            extrapolate: self.extrapolate,
        }
    }
}

/// Every configuration of a full study, applied to every model: equal N
/// from 1 to 512 (one solve), the material partition on 1 to 5 levels, and
/// on 2 to 5 levels with extrapolation.
pub const CONFIGURATIONS: [Plan; 19] = [
    Plan::equal(1),
    Plan::equal(2),
    Plan::equal(4),
    Plan::equal(8),
    Plan::equal(16),
    Plan::equal(32),
    Plan::equal(64),
    Plan::equal(128),
    Plan::equal(256),
    Plan::equal(512),
    Plan::material(1, false),
    Plan::material(2, false),
    Plan::material(3, false),
    Plan::material(4, false),
    Plan::material(5, false),
    Plan::material(2, true),
    Plan::material(3, true),
    Plan::material(4, true),
    Plan::material(5, true),
];

/// A reduced list for tests and previews ([`StudyConfig::quick`], `fpc
/// accuracy --quick`).
pub const QUICK_CONFIGURATIONS: [Plan; 6] = [
    Plan::equal(2),
    Plan::equal(8),
    Plan::equal(32),
    Plan::material(1, false),
    Plan::material(2, false),
    Plan::material(2, true),
];

/// What a study runs and how long it times each point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StudyConfig {
    /// The configurations, applied to every model.
    pub plans: Vec<Plan>,
    /// The models (the default model, the CCM, is always among them).
    pub models: Vec<ModelId>,
    /// Least wall-clock time spent timing each point, over all rounds.
    #[serde(serialize_with = "as_ms", rename = "budget_ms")]
    pub budget: Duration,
    /// Least number of timed runs per point and round.
    pub min_runs: usize,
    /// Rounds over all points: each point is timed once per round, on
    /// `budget / rounds`, and its time is the fastest round's median (a
    /// load that comes and goes on a shared machine then costs rounds, not
    /// the point).
    pub rounds: usize,
    /// Levels of the equal-partition orders (from N = 8).
    pub equal_order_levels: usize,
}

fn as_ms<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64() * 1e3)
}

/// The models the study references: every element model. (The
/// shear-deformable element was left out until its end angle took the
/// shear angle at the element's end: before, its finest reference level,
/// 864 material elements, lost stability; docs/model.md section 4.8.)
pub fn study_models() -> Vec<ModelId> {
    ModelId::ALL.to_vec()
}

impl StudyConfig {
    /// Every studied model ([`study_models`]), [`CONFIGURATIONS`], 7
    /// rounds, 30 ms per point and at least 7 runs per point and round.
    pub fn full() -> StudyConfig {
        StudyConfig {
            plans: CONFIGURATIONS.to_vec(),
            models: study_models(),
            budget: Duration::from_millis(30),
            min_runs: 7,
            rounds: 7,
            equal_order_levels: EQUAL_ORDER_LEVELS,
        }
    }

    /// Every studied model ([`study_models`]), [`QUICK_CONFIGURATIONS`],
    /// equal orders up to N = 64, 2 rounds, 1 ms per point and at least 3
    /// runs per point and round.
    pub fn quick() -> StudyConfig {
        StudyConfig {
            plans: QUICK_CONFIGURATIONS.to_vec(),
            models: study_models(),
            budget: Duration::from_millis(1),
            min_runs: 3,
            rounds: 2,
            equal_order_levels: 4,
        }
    }

    /// With this time budget per point.
    pub fn with_budget(mut self, budget: Duration) -> StudyConfig {
        self.budget = budget;
        self
    }
}
