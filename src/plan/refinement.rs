//! What a refinement is asked (its partition kind, levels and whether it
//! extrapolates) and what it records (its levels and best tip); the
//! algorithm and its error estimates are in `refine.rs`.

use serde::Serialize;

use crate::actuator::Actuator;
use crate::error::{require, InputError};
use crate::field::{Field, RefinementKey};
use crate::finger::StepCounts;
use crate::model::ModelId;
use crate::partition::Partition;

/// Largest number of elements a refinement uses.
pub const MAX_REFINED_ELEMENTS: usize = 1000;

/// How a refinement places element boundaries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PartitionKind {
    /// `start` equal elements, doubled per level (irregular first order).
    Equal,
    /// Boundaries on the material changes ([`Partition::material`], pieces
    /// at most `lx / start` long), every element halved per level (second
    /// order with a small first-order term; module docs).
    Material,
}

impl PartitionKind {
    /// Every kind.
    pub const ALL: [PartitionKind; 2] = [PartitionKind::Equal, PartitionKind::Material];

    /// The kind's name (`equal`, `material`).
    pub fn name(self) -> &'static str {
        match self {
            PartitionKind::Equal => "equal",
            PartitionKind::Material => "material",
        }
    }

    /// The kind named `name`, or an input error naming `field`.
    pub fn parse(field: impl Into<Field>, name: &str) -> Result<PartitionKind, InputError> {
        PartitionKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| InputError::Unrecognised {
                field: field.into(),
                value: name.into(),
                rule: "must be equal or material".into(),
            })
    }

    /// The leading order of the tip error in the element length on coarse
    /// partitions: 1 for equal elements, 2 for material partitions (whose
    /// expansion also has a small first-order term that leads on fine ones;
    /// the module docs give the estimates built on it).
    pub fn order(self) -> u32 {
        match self {
            PartitionKind::Equal => 1,
            PartitionKind::Material => 2,
        }
    }
}

/// A discretisation plan: model, partition kind, coarsest partition,
/// number of levels and whether to extrapolate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Refinement {
    /// The element model.
    pub model: ModelId,
    /// Where element boundaries go.
    pub partition: PartitionKind,
    /// Equal: the coarsest N. Material: pieces at most `lx / start` long.
    pub start: usize,
    /// Number of solves: the coarsest level and `levels - 1` halvings.
    pub levels: usize,
    /// Extrapolate the tip and end angle (needs `levels >= 2` and a
    /// material partition): from the last two levels with two, removing the
    /// `h^2` term, from the last three with more, removing `h` and `h^2`
    /// (module docs).
    pub extrapolate: bool,
}

impl Refinement {
    /// One solve on `n` equal elements.
    pub fn equal(model: ModelId, n: usize) -> Refinement {
        Refinement {
            model,
            partition: PartitionKind::Equal,
            start: n,
            levels: 1,
            extrapolate: false,
        }
    }

    /// The configuration a tip tolerance ([`crate::Plan::TipTolerance`])
    /// starts from for any
    /// tolerance: the material partition (pieces at most lx / 8) on two
    /// levels with extrapolation, the fastest configuration whose error
    /// estimate can be trusted (docs/performance.md, "The front"; equal
    /// elements are faster for loose tolerances on the standard case, but
    /// their irregular convergence needs three levels for an estimate, and
    /// on a pressurised finger hundreds of elements).
    /// The tolerance's solve adds levels while the estimate is above the
    /// tolerance; `tip_tol_mm` does not change the start.
    pub fn for_tolerance(model: ModelId, _tip_tol_mm: f64) -> Refinement {
        Refinement {
            model,
            partition: PartitionKind::Material,
            start: 8,
            levels: 2,
            extrapolate: true,
        }
    }

    /// A short label, e.g. `ccm/material/8x2+richardson`.
    pub fn label(&self) -> String {
        format!(
            "{}/{}/{}x{}{}",
            self.model.name(),
            self.partition.name(),
            self.start,
            self.levels,
            if self.extrapolate { "+richardson" } else { "" }
        )
    }

    /// Checks the plan against the finger it is for.
    pub(super) fn validate(&self, actuator: &Actuator, ribs: bool) -> Result<(), InputError> {
        require(
            self.start >= 1,
            Field::Refinement(RefinementKey::Start),
            self.start as f64,
            || "must be at least 1".to_string(),
        )?;
        require(
            self.levels >= 1,
            Field::Refinement(RefinementKey::Levels),
            self.levels as f64,
            || "must be at least 1".to_string(),
        )?;
        // (a switch: the message names it without a number)
        if self.extrapolate && (self.levels < 2 || self.partition != PartitionKind::Material) {
            return Err(InputError::Inconsistent {
                field: Field::Refinement(RefinementKey::Extrapolate),
                rule: "needs at least two levels on a material partition (the extrapolation assumes its error expansion)".to_string(),
            });
        }
        let finest = self.partition(actuator, ribs, self.levels - 1)?.len();
        require(
            finest <= MAX_REFINED_ELEMENTS,
            Field::Refinement(RefinementKey::Levels),
            self.levels as f64,
            || {
                format!(
                    "gives {finest} elements at the finest level, more than {MAX_REFINED_ELEMENTS}"
                )
            },
        )
    }

    /// The partition of `level` (0: the coarsest).
    pub fn partition(
        &self,
        actuator: &Actuator,
        ribs: bool,
        level: usize,
    ) -> Result<Partition, InputError> {
        let lx = actuator.geometry().lx;
        let too_fine = || InputError::OutOfRange {
            field: Field::Refinement(RefinementKey::Levels),
            value: (level + 1) as f64,
            rule: format!("more than {MAX_REFINED_ELEMENTS} elements"),
        };
        match self.partition {
            PartitionKind::Equal => {
                let n = u32::try_from(level)
                    .ok()
                    .and_then(|l| self.start.checked_mul(1usize.checked_shl(l)?))
                    .filter(|&n| n <= MAX_REFINED_ELEMENTS)
                    .ok_or_else(too_fine)?;
                Partition::equal(lx, n)
            }
            PartitionKind::Material => {
                // in the caller's terms: the start, not the piece length
                // it sets
                let mut p =
                    Partition::material(actuator, ribs, lx / self.start as f64).map_err(|e| {
                        e.renamed(Field::Refinement(RefinementKey::Start), |_| {
                            self.start as f64
                        })
                    })?;
                for _ in 0..level {
                    if 2 * p.len() > MAX_REFINED_ELEMENTS {
                        return Err(too_fine());
                    }
                    p = p.halved();
                }
                Ok(p)
            }
        }
    }
}

/// One level of a refinement.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Level {
    /// Elements at this level.
    pub elements: usize,
    /// Tip (mm, finger frame).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// End angle (rad).
    #[serde(rename = "end_angle_rad")]
    pub end_angle: f64,
    /// Newton iterations of this level's solve.
    pub iterations: usize,
    /// Where those iterations went.
    pub steps: StepCounts,
}

/// How a refinement's best tip was extrapolated (the module docs of
/// `refine.rs` give the formulas).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Extrapolation {
    /// `R2`: the `h^2` term removed from the last two levels.
    LastTwo,
    /// `T3`: the `h` and `h^2` terms removed from the last three levels.
    LastThree,
}

impl Extrapolation {
    /// The extrapolation of `plan` once `levels` levels are solved (the
    /// one place that decides it): none unless the plan extrapolates and
    /// two levels are there.
    pub(crate) fn of(plan: &Refinement, levels: usize) -> Option<Extrapolation> {
        match levels {
            _ if !plan.extrapolate || levels < 2 => None,
            2 => Some(Extrapolation::LastTwo),
            _ => Some(Extrapolation::LastThree),
        }
    }

    /// What was removed from which levels, in words.
    pub fn describe(self) -> &'static str {
        match self {
            Extrapolation::LastTwo => "h^2 term removed from the last two levels",
            Extrapolation::LastThree => "h and h^2 terms removed from the last three levels",
        }
    }
}

/// The record of a refinement: its levels and the best tip estimate
/// ([`crate::Solved::refinement`]).
#[derive(Debug, Clone, PartialEq)]
pub struct RefinementRecord {
    /// The best tip estimate: extrapolated when the plan extrapolates,
    /// else the finest level's.
    pub tip: [f64; 2],
    /// The best end-angle estimate (rad), extrapolated like the tip.
    pub end_angle: f64,
    /// Estimated distance of `tip` from the N -> infinity limit (mm;
    /// module docs); `None` with a single level (and with fewer than three
    /// levels of equal elements).
    pub estimated_tip_error_mm: Option<f64>,
    /// Every level, coarsest first.
    pub levels: Vec<Level>,
    /// The plan as run (levels as solved).
    pub plan: Refinement,
}

impl RefinementRecord {
    /// True when the tip is extrapolated.
    pub fn is_extrapolated(&self) -> bool {
        self.extrapolation().is_some()
    }

    /// How the tip was extrapolated: from the last two levels with two,
    /// from the last three with more; `None` when it was not.
    pub fn extrapolation(&self) -> Option<Extrapolation> {
        Extrapolation::of(&self.plan, self.levels.len())
    }

    /// Newton iterations over every level.
    pub fn iterations(&self) -> usize {
        self.levels.iter().map(|l| l.iterations).sum()
    }

    /// Where the iterations of every level went, summed.
    pub fn steps(&self) -> StepCounts {
        let mut all = StepCounts::default();
        for l in &self.levels {
            all += l.steps;
        }
        all
    }
}

/// The keys of `fpc finger --json`'s and a finger scene's `refinement`.
impl Serialize for RefinementRecord {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Keys<'a> {
            configuration: String,
            levels: Vec<usize>,
            level_iterations: Vec<usize>,
            level_steps: Vec<StepCounts>,
            level_tips_mm: Vec<[f64; 2]>,
            extrapolated: bool,
            extrapolation: Option<Extrapolation>,
            tip_mm: &'a [f64; 2],
            end_angle_rad: f64,
        }
        Keys {
            configuration: self.plan.label(),
            levels: self.levels.iter().map(|l| l.elements).collect(),
            level_iterations: self.levels.iter().map(|l| l.iterations).collect(),
            level_steps: self.levels.iter().map(|l| l.steps).collect(),
            level_tips_mm: self.levels.iter().map(|l| l.tip).collect(),
            extrapolated: self.is_extrapolated(),
            extrapolation: self.extrapolation(),
            tip_mm: &self.tip,
            end_angle_rad: self.end_angle,
        }
        .serialize(s)
    }
}
