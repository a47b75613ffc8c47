//! The eight studies of the paper (docs/model.md section 6): functions that
//! return typed results, and the registry [`STUDIES`] that turns each
//! result into its outputs as data ([`StudyOutput`]: tables, a figure,
//! summary entries, an overview and validity counts).
//!
//! Every study takes the base actuator (the paper's by default; each study
//! sets the prestrain it needs) and [`StudyOptions`]. Sweeps warm-start each
//! point from the previous one; a sweep that fails stops cleanly at that
//! point and records where and why ([`SweepStop`]) instead of aborting the
//! study. Only a failure of a gripper's reference state (the unloaded
//! finger) is an error.
//!
//! A study lives in one module: its computation, its typed result, and how
//! that result becomes tables, a figure and summary entries. Adding a study
//! is one module and one entry of [`STUDIES`]; front ends (`fpc paper`) run
//! the registry and need no change.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, PI};

use crate::actuator::Actuator;
use crate::error::{positive, require, InputError};
use crate::field::Field;
use crate::finger::Finger;
use crate::gripper::{
    Grasp, Gripper, GripperParams, Object, PalmSpec, SizeTail, SweepEnd, ViableAngles,
};
use crate::model::ModelId;
use crate::partition::Partition;
use crate::solve_error::SolveError;

mod cuboid;
mod curvature;
mod displacement;
mod force_control;
mod lift;
mod output;
mod overlap;
mod prestrain_angle;
mod sphere;
mod viable;

pub use cuboid::{study3_cuboid_region, CuboidRegion, CUBOID_TEST};
pub use curvature::{study7_curvature, CurvatureCurve, CurvatureRow};
pub use displacement::{
    study8_force_at_displacement, tip_force_for_displacement, Axis, DisplacementForce,
    DisplacementForceRow,
};
pub use force_control::{study4_force_control, ForceControl, ForceControlRow};
pub use lift::{LiftCurve, LiftPoint};
pub use output::{
    angle_key, angle_name, eps0_key, overlap_key, validity_kinds, warnings_cell, Band, Cell, Clip,
    Clipped, Column, Corner, Figure, Overview, Panel, PlotAxis, RefLine, Series, SeriesKind, Stop,
    StopAt, StudyOutput, Table, BENT_BACKWARDS, INVALID, INVALID_GRASP, NEUTRAL, NOTE, REVERSED,
    STATUS, VALID, VALIDITY_KINDS, WARNINGS,
};
pub use overlap::study2_overlap;
pub use prestrain_angle::study1_prestrain_angle;
pub use sphere::{study5_sphere_region, SpherePoint, SphereRegion};
pub use viable::study6_viable_angles;

/// Prestrains of the paper's samples.
pub const PAPER_EPS0: [f64; 3] = [0.4, 0.25, 0.15];

/// Mounting angles of studies 1 and 2: pi/2, pi/2.5, pi/3.
pub const PAPER_ANGLES: [f64; 3] = [FRAC_PI_2, PI / 2.5, FRAC_PI_3];

/// Overlaps of study 2 (mm).
pub const PAPER_OVERLAPS: [f64; 3] = [0.0, 10.0, 20.0];

/// Pressures of study 8 (kPa).
pub const STUDY8_PRESSURES_KPA: [f64; 4] = [0.0, 27.6, 55.2, 82.7];

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

    /// Checks every field.
    pub fn validate(&self) -> Result<(), InputError> {
        let at_least = |field: &'static str, v: usize, min: usize| {
            require(
                v >= min,
                Field::key(field),
                v as f64,
                format!("must be at least {min}"),
            )
        };
        at_least("study.elements", self.elements, 1)?;
        positive(Field::key("study.mu"), self.mu)?;
        at_least("study.sweep_points", self.sweep_points, 2)?;
        at_least("study.angle_samples", self.angle_samples, 4)?;
        at_least("study.pressure_points", self.pressure_points, 2)?;
        Ok(())
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

/// Sweeps the grasping size over `n + 1` points from `from` to `to`
/// (grasping angle `beta`, `f = mu F`), each solve warm-started from the
/// previous. Where a target solve fails, the load path from the last grasp
/// is followed ([`Gripper::size_tail`]): the sweep goes on if it reaches
/// the size, and otherwise ends at the path's natural end (or, if the path
/// cannot be continued, at a numerical stop).
#[allow(clippy::too_many_arguments)]
pub(crate) fn size_sweep(
    g: &Gripper,
    pressure_kpa: f64,
    beta: f64,
    object: Object,
    from: f64,
    to: f64,
    n: usize,
    mut visit: impl FnMut(&Grasp),
) -> Option<SweepStop> {
    let mut warm: Option<Grasp> = None;
    for i in 0..=n {
        let d = from + (to - from) * i as f64 / n as f64;
        let gr = match g.size_grasp(pressure_kpa, d, beta, object, warm.as_ref(), false) {
            Ok(gr) => gr,
            Err(e) => {
                // from the last grasp, or the finger without contact force
                let start = match &warm {
                    Some(w) => Ok(w.clone()),
                    None => g.sweep_start(pressure_kpa, beta, object),
                };
                let last = match start {
                    Ok(l) => l,
                    Err(e2) => {
                        return Some(SweepStop::failed(
                            d,
                            format!("{e}; and the start of the load path: {e2}"),
                        ))
                    }
                };
                match g.size_tail(&last, d) {
                    Ok(SizeTail::Reached(gr)) => *gr,
                    Ok(SizeTail::End(end)) => {
                        return Some(SweepStop {
                            at: d,
                            reason: end.to_string(),
                            end: Some(end),
                        })
                    }
                    Err(e2) => {
                        return Some(SweepStop::failed(
                            d,
                            format!("{e}; following the load path: {e2}"),
                        ))
                    }
                }
            }
        };
        visit(&gr);
        warm = Some(gr);
    }
    None
}

/// The gripper of the paper's Sec. 5: eps0 = 0.25, a = pi/3, g = 20 mm.
pub fn section5_gripper(actuator: &Actuator, opts: &StudyOptions) -> Result<Gripper, SolveError> {
    opts.validate()?;
    opts.gripper(actuator, 0.25, FRAC_PI_3, 20.0)
}

// ------------------------------------------------------------ all

/// The eight studies' results.
#[derive(Debug, Clone, PartialEq)]
pub struct Studies {
    /// Prestrain x mounting angle ([`study1_prestrain_angle`]).
    pub study1: Vec<LiftCurve>,
    /// Overlap ([`study2_overlap`]).
    pub study2: Vec<LiftCurve>,
    /// Cuboid grasping region ([`study3_cuboid_region`]).
    pub study3: CuboidRegion,
    /// Force control by pressure ([`study4_force_control`]).
    pub study4: ForceControl,
    /// Sphere grasping region ([`study5_sphere_region`]).
    pub study5: SphereRegion,
    /// Viable grasping angles ([`study6_viable_angles`]).
    pub study6: ViableAngles,
    /// Curvature versus pressure ([`study7_curvature`]).
    pub study7: Vec<CurvatureCurve>,
    /// Force at a fixed displacement ([`study8_force_at_displacement`]).
    pub study8: Vec<DisplacementForceRow>,
}

/// Runs the eight studies.
pub fn run_all(actuator: &Actuator, opts: &StudyOptions) -> Result<Studies, SolveError> {
    Ok(Studies {
        study1: study1_prestrain_angle(actuator, opts)?,
        study2: study2_overlap(actuator, opts)?,
        study3: study3_cuboid_region(actuator, opts)?,
        study4: study4_force_control(actuator, opts)?,
        study5: study5_sphere_region(actuator, opts)?,
        study6: study6_viable_angles(actuator, opts)?,
        study7: study7_curvature(actuator, opts)?,
        study8: study8_force_at_displacement(actuator, opts)?,
    })
}

// ------------------------------------------------------------ registry

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

/// The paper's studies, in order.
pub const STUDIES: &[StudyInfo] = &[
    prestrain_angle::INFO,
    overlap::INFO,
    cuboid::INFO,
    force_control::INFO,
    sphere::INFO,
    viable::INFO,
    curvature::INFO,
    displacement::INFO,
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_registry_is_numbered_in_order_with_unique_keys() {
        for (i, s) in STUDIES.iter().enumerate() {
            assert_eq!(s.number, i + 1);
            assert!(!s.title.is_empty() && !s.description.is_empty());
            assert_eq!(STUDIES.iter().filter(|t| t.key == s.key).count(), 1);
        }
    }

    /// The tables of every study, empty and run on coarse sweeps: names
    /// unique across all studies, rows as wide as their columns, the same
    /// columns whether empty or filled, `status` and `note` last.
    #[test]
    fn every_study_has_unique_tables_with_consistent_rows() {
        let act = Actuator::default();
        let opts = StudyOptions::coarse();
        let mut names = Vec::new();
        for s in STUDIES {
            let empty = (s.empty)();
            let out = s.output(&act, &opts).unwrap();
            assert_eq!(out.tables.len(), empty.tables.len(), "study {}", s.number);
            assert_eq!(out.tables[0].name, s.stem());
            for (t, e) in out.tables.iter().zip(&empty.tables) {
                assert_eq!(t.name, e.name);
                assert_eq!(t.columns, e.columns, "{}", t.name);
                assert!(e.rows.is_empty());
                assert!(!t.rows.is_empty(), "{} has no rows", t.name);
                let n = t.columns.len();
                assert_eq!(&t.columns[n - 2..], &[STATUS, NOTE], "{}", t.name);
                for r in &t.rows {
                    assert_eq!(r.len(), n, "{}: {r:?}", t.name);
                }
                let mut cols: Vec<_> = t.columns.iter().map(|c| c.name).collect();
                cols.sort_unstable();
                cols.dedup();
                assert_eq!(cols.len(), n, "{}: repeated column", t.name);
                assert!(!names.contains(&t.name), "{} twice", t.name);
                names.push(t.name.clone());
            }
            // the summary has the same keys, filled or empty
            let keys = |o: &StudyOutput| o.summary.iter().map(|e| e.0.clone()).collect::<Vec<_>>();
            assert_eq!(keys(&out), keys(&empty), "study {}", s.number);
            assert!(out.figure.panels().count() > 0);
            assert!(out.points > 0, "study {}", s.number);
            assert!(VALIDITY_KINDS
                .iter()
                .all(|k| out.warnings_by_kind.contains_key(*k)));
            assert!(out.warnings_by_kind.values().all(|&c| c <= out.points));
            assert_eq!(out.strict_dropped, 0, "not strict");
            assert!(!out.overview.rows.is_empty());
        }
    }
}
