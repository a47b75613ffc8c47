//! The front door of a finger solve: a finger is built once from its
//! actuator, element model, ribs and a solve [`Plan`] (a fixed partition,
//! N equal elements, the automatic partition, a tip tolerance or nested
//! refinement levels), and solved by [`PlannedFinger::solve`] into one
//! result, [`Solved`], whatever the plan.
//!
//! ```
//! use fpc::{Actuator, Load, Plan, PlannedFinger, SolveOptions};
//!
//! let finger = PlannedFinger::builder(&Actuator::default())
//!     .plan(Plan::TipTolerance { tip_tol_mm: 0.05, start: None })
//!     .build()?;
//! let load = Load::unloaded().with_tip_force(0.0, 0.1);
//! let solved = finger.solve(&load, &SolveOptions::default())?;
//! assert!(solved.estimated_tip_error_mm().unwrap() <= 0.05);
//! assert!(solved.is_valid());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Every bound (element counts, the tolerance, the levels' sizes) is
//! checked by [`FingerBuilder::build`], before any solve. The plans are
//! implemented in the refinement module ([`Refinement`],
//! [`RefinementRecord`]); [`Finger::solve`] stays the low-level solve on one
//! partition.

mod auto;
pub(crate) mod refine;
mod refinement;
mod solved;

use crate::actuator::Actuator;
use crate::coefficients::Coefficients;
use crate::error::InputError;
use crate::field::Field;
use crate::finger::{Finger, Load, SolveOptions};
use crate::model::ModelId;
use crate::partition::Partition;
use crate::solve_error::SolveError;
use auto::Auto;
pub use auto::{FOLD_TURN_RATIO, MAX_AUTO_ELEMENTS, MAX_AUTO_SPLITS, START_HALVINGS};
pub use refine::{intermediate_options, INTERMEDIATE_ELEMENTS, INTERMEDIATE_RTOL};
use refine::{Refiner, TipTolerance};
pub use refinement::{
    Extrapolation, Level, PartitionKind, Refinement, RefinementRecord, MAX_REFINED_ELEMENTS,
};
pub use solved::Solved;

/// Elements of the default plan ([`Plan::default`]).
pub const DEFAULT_PLAN_ELEMENTS: usize = 8;

/// How a finger is discretised and solved.
#[derive(Debug, Clone, PartialEq)]
pub enum Plan {
    /// One solve on this partition.
    Fixed(Partition),
    /// One solve on `n` equal elements ([`Partition::equal`]).
    Equal(usize),
    /// The automatic partition: boundaries on the material changes
    /// ([`Partition::material`], pieces at most `lx / 8`; every piece
    /// halved, up to [`crate::plan::START_HALVINGS`] times, while that
    /// start does not solve from rest), then every
    /// element that turns beyond the CCM's small-slope limit at the solved
    /// state split in two and the finger solved again, up to
    /// [`crate::plan::MAX_AUTO_ELEMENTS`] elements and
    /// [`crate::plan::MAX_AUTO_SPLITS`] rounds of splits, or until a split
    /// meets a fold ([`crate::plan::FOLD_TURN_RATIO`]) or does not solve
    /// (the answer is then the last partition that solved, with the note
    /// [`crate::Warning::PartitionSplitFailed`]); a finger still beyond
    /// the limit then carries its `element_slope` findings.
    Auto,
    /// Refined until the estimated tip error is at most `tip_tol_mm`:
    /// equal elements doubled from `start` (in [1,
    /// [`crate::plan::MAX_REFINED_ELEMENTS`] / 2]; three levels at least), or
    /// without it the material partition with extrapolation
    /// ([`Refinement::for_tolerance`]).
    TipTolerance {
        tip_tol_mm: f64,
        start: Option<usize>,
    },
    /// Nested refinement levels ([`Refinement`] without its model, which
    /// is the finger's).
    Levels {
        /// Where element boundaries go.
        partition: PartitionKind,
        /// Equal: the coarsest N. Material: pieces at most `lx / start` long.
        start: usize,
        /// Number of solves: the coarsest level and `levels - 1` halvings.
        levels: usize,
        /// Extrapolate the tip and end angle (two levels or more on a
        /// material partition).
        extrapolate: bool,
    },
}

impl Default for Plan {
    /// [`DEFAULT_PLAN_ELEMENTS`] equal elements.
    fn default() -> Plan {
        Plan::Equal(DEFAULT_PLAN_ELEMENTS)
    }
}

impl Plan {
    /// The levels of `r` (its model is the finger's: see
    /// [`FingerBuilder::refinement`]).
    pub fn levels(r: &Refinement) -> Plan {
        Plan::Levels {
            partition: r.partition,
            start: r.start,
            levels: r.levels,
            extrapolate: r.extrapolate,
        }
    }
}

/// Builds a [`PlannedFinger`]: the default element model, ribs on and
/// [`Plan::default`] unless set.
#[derive(Debug, Clone)]
pub struct FingerBuilder {
    actuator: Actuator,
    model: ModelId,
    ribs: bool,
    plan: Plan,
}

impl FingerBuilder {
    /// A builder for a finger of `actuator`.
    pub fn new(actuator: &Actuator) -> FingerBuilder {
        FingerBuilder {
            actuator: actuator.clone(),
            model: ModelId::default(),
            ribs: true,
            plan: Plan::default(),
        }
    }

    /// The element model.
    pub fn model(mut self, model: ModelId) -> FingerBuilder {
        self.model = model;
        self
    }

    /// Whether the ribs inside the channel are modelled.
    pub fn ribs(mut self, ribs: bool) -> FingerBuilder {
        self.ribs = ribs;
        self
    }

    /// The solve plan.
    pub fn plan(mut self, plan: Plan) -> FingerBuilder {
        self.plan = plan;
        self
    }

    /// The model and levels of a refinement plan.
    pub fn refinement(self, r: &Refinement) -> FingerBuilder {
        self.model(r.model).plan(Plan::levels(r))
    }

    /// True when `finger` was built from what this builder holds, so that
    /// building again would give the same fingers.
    pub(crate) fn builds(&self, finger: &PlannedFinger) -> bool {
        (self.model, self.ribs) == (finger.model, finger.ribs)
            && self.plan == finger.plan
            && self.actuator == finger.actuator
    }

    /// Checks the plan against the actuator and builds its fingers.
    pub fn build(self) -> Result<PlannedFinger, InputError> {
        let FingerBuilder {
            actuator,
            model,
            ribs,
            plan,
        } = self;
        let fixed = |p: &Partition| Built::Fixed(Finger::with_model(model, &actuator, p, ribs));
        let built = match &plan {
            Plan::Fixed(p) => fixed(p),
            &Plan::Equal(n) => fixed(&Partition::equal(actuator.geometry().lx, n)?),
            Plan::Auto => Built::Auto(Auto::new(model, &actuator, ribs)?),
            &Plan::TipTolerance { tip_tol_mm, start } => Built::TipTolerance(TipTolerance::new(
                model, &actuator, ribs, tip_tol_mm, start,
            )?),
            &Plan::Levels {
                partition,
                start,
                levels,
                extrapolate,
            } => {
                let r = Refinement {
                    model,
                    partition,
                    start,
                    levels,
                    extrapolate,
                };
                Built::Levels(Refiner::new(&actuator, ribs, &r)?)
            }
        };
        Ok(PlannedFinger {
            actuator,
            model,
            ribs,
            plan,
            built,
        })
    }
}

/// What a plan builds before any solve.
#[derive(Debug, Clone)]
enum Built {
    Fixed(Finger),
    Auto(Auto),
    TipTolerance(TipTolerance),
    Levels(Refiner),
}

/// A finger and its solve plan, checked and built ([`FingerBuilder`]);
/// solve it under any number of loads.
#[derive(Debug, Clone)]
pub struct PlannedFinger {
    actuator: Actuator,
    model: ModelId,
    ribs: bool,
    plan: Plan,
    built: Built,
}

impl PlannedFinger {
    /// A builder for a finger of `actuator`.
    pub fn builder(actuator: &Actuator) -> FingerBuilder {
        FingerBuilder::new(actuator)
    }

    /// The actuator.
    pub fn actuator(&self) -> &Actuator {
        &self.actuator
    }

    /// The element model.
    pub fn model(&self) -> ModelId {
        self.model
    }

    /// Whether the ribs are modelled.
    pub fn ribs(&self) -> bool {
        self.ribs
    }

    /// The plan.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// The fingers built before any solve, coarsest first: the fixed
    /// partition's, every level's, the automatic partition's starting one,
    /// a tip tolerance's first level (its finer levels and the automatic
    /// partition's splits are built while solving).
    pub fn fingers(&self) -> &[Finger] {
        match &self.built {
            Built::Fixed(f) => std::slice::from_ref(f),
            Built::Auto(a) => std::slice::from_ref(a.finger()),
            Built::TipTolerance(t) => t.fingers(),
            Built::Levels(r) => r.fingers(),
        }
    }

    /// The finger of a fixed partition (`Plan::Fixed`, `Plan::Equal`).
    pub fn fixed(&self) -> Option<&Finger> {
        match &self.built {
            Built::Fixed(f) => Some(f),
            _ => None,
        }
    }

    /// `opts` checked on the finest level of nested levels before the
    /// coarser ones are solved. Every other plan's first solve checks them
    /// itself before any work (and the finer fingers of an automatic
    /// partition or a tip tolerance as they are built), so a fixed
    /// partition's solve is not checked twice.
    fn check_options(&self, opts: &SolveOptions) -> Result<(), InputError> {
        match &self.built {
            Built::Levels(r) => {
                let finest = r.fingers().iter().map(Finger::len).max().unwrap_or(1);
                opts.validate_on(finest)
            }
            Built::Fixed(_) | Built::Auto(_) | Built::TipTolerance(_) => Ok(()),
        }
    }

    /// Solves `load` as the plan says.
    pub fn solve(&self, load: &Load, opts: &SolveOptions) -> Result<Solved, SolveError> {
        self.check_options(opts)?;
        match &self.built {
            Built::Fixed(f) => Ok(Solved::single(f.solve(load, opts)?, f)),
            Built::Auto(a) => a.solve(load, opts),
            Built::TipTolerance(t) => t.solve(load, opts),
            Built::Levels(r) => r.solve(load, None, opts),
        }
    }

    /// [`PlannedFinger::solve`] with Newton started from `guess` (raw
    /// coefficients): on a fixed partition, or on the coarsest level of
    /// nested levels. The automatic partition and a tip tolerance start
    /// every solve themselves: an input error naming `guess`.
    pub fn solve_from(
        &self,
        load: &Load,
        guess: &Coefficients,
        opts: &SolveOptions,
    ) -> Result<Solved, SolveError> {
        self.check_options(opts)?;
        match &self.built {
            Built::Fixed(f) => Ok(Solved::single(f.solve_from(load, guess, opts)?, f)),
            Built::Levels(r) => r.solve(load, Some(guess), opts),
            Built::Auto(_) | Built::TipTolerance(_) => Err(InputError::Inconsistent {
                field: Field::Guess,
                rule: "the automatic partition and a tip tolerance start every solve themselves"
                    .into(),
            }
            .into()),
        }
    }
}
