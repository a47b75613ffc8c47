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

mod bands;
mod cuboid;
mod curvature;
mod displacement;
mod force_control;
mod info;
mod lift;
mod options;
mod output;
mod overlap;
mod prestrain_angle;
mod sphere;
mod sweep;
mod viable;

pub use bands::{not_propagated, BandColumn, NotPropagated, EXACT};
pub use cuboid::{study3_cuboid_region, study3_cuboid_region_with, CuboidRegion, CUBOID_TEST};
pub use curvature::{
    study7_curvature, study7_curvature_with, CurvatureCurve, CurvatureRow, CurvatureSd,
};
pub use displacement::{
    study8_force_at_displacement, study8_force_at_displacement_with, tip_force_for_displacement,
    tip_force_for_displacement_with_kappa, Axis, DisplacementForce, DisplacementForceRow,
};
pub use force_control::{
    study4_force_control, study4_force_control_with, ForceControl, ForceControlRow, ForceControlSd,
};
pub use info::StudyInfo;
pub use lift::{lift_curve, LiftCurve, LiftPoint, LiftSd};
pub use options::{
    section5_gripper, StudyOptions, SweepStop, MAX_ANGLE_SAMPLES, MAX_PRESSURE_POINTS,
    MAX_SPHERE_WORK, MAX_STUDY_ELEMENTS, MAX_SWEEP_POINTS, PAPER_ANGLES, PAPER_EPS0,
    PAPER_OVERLAPS, STUDY8_PRESSURES_KPA,
};
pub use output::{
    angle_key, angle_name, eps0_key, overlap_key, validity_kinds, warnings_cell, Band, Cell, Clip,
    Clipped, Column, Corner, Figure, Overview, Panel, PlotAxis, RefLine, Series, SeriesKind, Stop,
    StopAt, StudyOutput, Table, BENT_BACKWARDS, INVALID, INVALID_GRASP, NEUTRAL, NOTE, REVERSED,
    STATUS, VALID, VALIDITY_KINDS, WARNINGS,
};
pub use overlap::{study2_overlap, study2_overlap_with};
pub use prestrain_angle::{study1_prestrain_angle, study1_prestrain_angle_with};
pub use sphere::{
    study5_sphere_region, study5_sphere_region_with, SphereLiftSd, SpherePoint, SphereRegion,
};
pub use viable::{study6_viable_angles, study6_viable_angles_with, AngleSd, ViableSd};

// ------------------------------------------------------------ registry

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
    use crate::actuator::Actuator;

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
