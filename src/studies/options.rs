//! What every study shares: the paper's values, the studies' settings
//! ([`StudyOptions`]), where a sweep stopped ([`SweepStop`]) and the
//! gripper of the paper's Sec. 5.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, PI};

use crate::actuator::Actuator;
use crate::error::{positive, require, InputError};
use crate::finger::Finger;
use crate::gripper::{Gripper, GripperParams, PalmSpec, SweepEnd};
use crate::model::ModelId;
use crate::partition::Partition;
use crate::solve_error::SolveError;

/// Prestrains of the paper's samples.
pub const PAPER_EPS0: [f64; 3] = [0.4, 0.25, 0.15];

/// Mounting angles of studies 1 and 2: pi/2, pi/2.5, pi/3.
pub const PAPER_ANGLES: [f64; 3] = [FRAC_PI_2, PI / 2.5, FRAC_PI_3];

/// Overlaps of study 2 (mm).
pub const PAPER_OVERLAPS: [f64; 3] = [0.0, 10.0, 20.0];

/// Pressures of study 8 (kPa).
pub const STUDY8_PRESSURES_KPA: [f64; 4] = [0.0, 27.6, 55.2, 82.7];

/// The most elements per finger in a study (a partition's own bound).
pub const MAX_STUDY_ELEMENTS: usize = 1_000;
/// The most `sweep_points` of a study (a sweep of grasp solves per curve).
pub const MAX_SWEEP_POINTS: usize = 2_000;
/// The most `angle_samples` of a study (grasping angles per sphere size).
pub const MAX_ANGLE_SAMPLES: usize = 200;
/// The most `pressure_points` of a study (finger solves per prestrain).
pub const MAX_PRESSURE_POINTS: usize = 10_000;
/// The most `sweep_points x angle_samples x elements` of study 5 (a
/// sweep of grasps at every grasping angle): 100 000 grasps of the
/// default 8 elements, about a minute; a finer finger allows fewer grasps,
/// as each solve's work grows with its elements. Each count alone is
/// bounded by [`StudyOptions::validate`].
pub const MAX_SPHERE_WORK: usize = 800_000;

/// Resolution and shared settings of the studies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StudyOptions {
    /// The element model of the fingers (the paper's CCM by default).
    pub model: ModelId,
    /// Elements per finger (the paper uses 8).
    pub elements: usize,
    /// Friction coefficient.
    pub mu: f64,
    /// Points per grasping-size sweep (studies 1, 2, 3, 5), at least 2.
    pub sweep_points: usize,
    /// Grasping angles scanned (studies 5 and 6), at least 4.
    pub angle_samples: usize,
    /// Pressures in study 7 (0 to 400 kPa inclusive), at least 2.
    pub pressure_points: usize,
    /// Strict mode: grasps that bend an element backwards are invalid and
    /// dropped, as the paper's analysis assumes.
    pub strict: bool,
}

impl Default for StudyOptions {
    fn default() -> StudyOptions {
        StudyOptions {
            model: ModelId::default(),
            elements: 8,
            mu: 0.6,
            sweep_points: 32,
            angle_samples: 24,
            pressure_points: 21,
            strict: false,
        }
    }
}

impl StudyOptions {
    /// Coarse sweeps (for tests and previews).
    pub fn coarse() -> StudyOptions {
        StudyOptions {
            sweep_points: 6,
            angle_samples: 8,
            pressure_points: 5,
            ..StudyOptions::default()
        }
    }

    /// Checks every field, the counts against their bounds
    /// ([`MAX_STUDY_ELEMENTS`], [`MAX_SWEEP_POINTS`], [`MAX_ANGLE_SAMPLES`],
    /// [`MAX_PRESSURE_POINTS`]) before any work. Study 5 also bounds the
    /// product of its counts ([`StudyOptions::validate_sphere`]).
    pub fn validate(&self) -> Result<(), InputError> {
        let within = |field: &'static str, v: usize, min: usize, max: usize| {
            require(
                (min..=max).contains(&v),
                crate::Field::key(field),
                v as f64,
                || format!("must lie in [{min}, {max}]"),
            )
        };
        within("study.elements", self.elements, 1, MAX_STUDY_ELEMENTS)?;
        positive(crate::Field::key("study.mu"), self.mu)?;
        within("study.sweep_points", self.sweep_points, 2, MAX_SWEEP_POINTS)?;
        within(
            "study.angle_samples",
            self.angle_samples,
            4,
            MAX_ANGLE_SAMPLES,
        )?;
        within(
            "study.pressure_points",
            self.pressure_points,
            2,
            MAX_PRESSURE_POINTS,
        )?;
        Ok(())
    }

    /// The work of study 5 (`sweep_points x angle_samples x elements`)
    /// against [`MAX_SPHERE_WORK`], named `study.sweep_points`; each
    /// count's own bounds are [`StudyOptions::validate`]'s.
    pub fn validate_sphere(&self) -> Result<(), InputError> {
        let work = self
            .sweep_points
            .saturating_mul(self.angle_samples)
            .saturating_mul(self.elements);
        require(
            work <= MAX_SPHERE_WORK,
            crate::Field::key("study.sweep_points"),
            self.sweep_points as f64,
            || {
                format!(
                    "study.sweep_points x study.angle_samples x study.elements = {} x {} x {} = \
                     {work}: must be at most {MAX_SPHERE_WORK} (a bound on study 5's work)",
                    self.sweep_points, self.angle_samples, self.elements
                )
            },
        )
    }

    pub(crate) fn finger(&self, actuator: &Actuator, eps0: f64) -> Result<Finger, InputError> {
        let act = actuator.with_eps0(eps0)?;
        let part = Partition::equal(act.geometry().lx, self.elements)?;
        Ok(Finger::with_model(self.model, &act, &part, true))
    }

    pub(crate) fn gripper(
        &self,
        actuator: &Actuator,
        eps0: f64,
        mounting_angle: f64,
        overlap: f64,
    ) -> Result<Gripper, SolveError> {
        Gripper::new(
            self.finger(actuator, eps0)?,
            GripperParams {
                mounting_angle,
                geometry: PalmSpec::Overlap(overlap),
                fingers: 3,
                mu: self.mu,
                strict: self.strict,
            },
        )
    }
}

/// Where and why a sweep stopped before its end.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepStop {
    /// The sweep parameter that failed (grasping size in mm, or pressure in kPa).
    pub at: f64,
    /// Why, in words.
    pub reason: String,
    /// The sweep's natural end (a fold, the validity limit, a force beyond
    /// [`crate::gripper::MAX_GRASP_FORCE_N`]), when it is one; `None` for a
    /// numerical stop.
    pub end: Option<SweepEnd>,
}

impl SweepStop {
    /// A numerical stop (a failed solve).
    pub(crate) fn failed(at: f64, reason: String) -> SweepStop {
        SweepStop {
            at,
            reason,
            end: None,
        }
    }

    /// True when the sweep ended for a reason of the gripper's, not a
    /// failed solve.
    pub fn is_natural(&self) -> bool {
        self.end.as_ref().is_some_and(|e| !e.is_numerical())
    }
}

/// The prestrain of the paper's Sec. 5 gripper.
pub(crate) const SECTION5_EPS0: f64 = 0.25;

/// The gripper of the paper's Sec. 5: eps0 = 0.25, a = pi/3, g = 20 mm.
pub fn section5_gripper(actuator: &Actuator, opts: &StudyOptions) -> Result<Gripper, SolveError> {
    opts.validate()?;
    opts.gripper(actuator, SECTION5_EPS0, FRAC_PI_3, 20.0)
}
