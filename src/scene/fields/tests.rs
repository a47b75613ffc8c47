//! Unit tests of the scene keys: every library field maps to a key of
//! the schema, and messages name scene keys.

use super::*;
use crate::scene::testing::{schema_keys, schema_path};
use crate::scene::Scene;

/// The scene key of a library field name.
fn scene_key_of(library: &str) -> String {
    LibField::from_name(library)
        .unwrap_or_else(|| panic!("{library} is not a library field"))
        .scene_key()
        .to_string()
}

#[test]
fn toml_paths_of_library_fields() {
    assert_eq!(scene_key_of("actuator.pemc.law.p1"), "actuator.pemc.p1");
    assert_eq!(scene_key_of("actuator.pemc.law.p4"), "actuator.pemc.p4");
    assert_eq!(
        scene_key_of("actuator.ribs[2].width"),
        "actuator.ribs.list[2].width"
    );
    assert_eq!(scene_key_of("actuator.ribs.w1"), "actuator.ribs.w1");
    assert_eq!(scene_key_of("actuator.ribs"), "actuator.ribs");
    assert_eq!(scene_key_of("load.pressure"), "load.pressure_kpa");
    assert_eq!(
        scene_key_of("partition.lengths[12]"),
        "partition.lengths[12]"
    );
    assert_eq!(scene_key_of("sphere.beta"), "gripper.grasp.beta_deg");
    // not library fields (or not ones the scene can trigger)
    for name in [
        "guess",
        "actuator.pemc.p1",
        "actuator.ribs[x].x0",
        "actuator.ribs[].x0",
        "actuator.ribs[+1].x0",
        "partition.lengths[1",
        "load.pressure_kpa",
    ] {
        assert_eq!(LibField::from_name(name), None, "{name}");
    }
}

#[test]
fn every_library_field_maps_to_a_scene_key_of_the_schema() {
    let schema = schema_keys();
    for index in [0, 7, 999] {
        for f in LibField::all(index) {
            let name = f.name();
            assert_eq!(LibField::from_name(&name), Some(f), "{name}");
            let key = f.scene_key();
            assert!(
                schema.contains(&schema_path(&key.to_string())),
                "{name} maps to {key}, which is not a key of the schema"
            );
        }
    }
}

#[test]
fn scene_keys_are_the_schema() {
    let schema = schema_keys();
    let keys: Vec<String> = SceneKey::all()
        .iter()
        .map(|k| schema_path(&k.to_string()))
        .collect();
    for k in &keys {
        assert!(schema.contains(k), "{k} is not a key of the schema");
    }
    // every key of the schema is a scene key, or a table that holds some
    for s in schema {
        let table = format!("{s}.");
        let list = format!("{s}[]");
        assert!(
            keys.iter()
                .any(|k| k == s || k.starts_with(&table) || k.starts_with(&list)),
            "the schema's {s} has no SceneKey"
        );
    }
}

#[test]
fn the_library_spells_its_fields_as_the_enum_does() {
    use crate::actuator::{Actuator, ActuatorParams, Rib, RibLayout};
    use crate::finger::{Finger, Load};
    use crate::gripper::{Gripper, GripperParams, PalmSpec};
    use crate::partition::Partition;

    fn field<T: std::fmt::Debug, E: Into<SolveError>>(r: Result<T, E>) -> String {
        match r.map_err(Into::into) {
            Err(SolveError::Input(e)) => e.field().to_string(),
            other => panic!("expected an input error, got {other:?}"),
        }
    }
    let actuator = |f: &dyn Fn(&mut ActuatorParams)| {
        let mut p = ActuatorParams::default();
        f(&mut p);
        Actuator::new(p)
    };
    let act = Actuator::default();
    let gripper = |params: GripperParams| Gripper::new(Finger::paper(0.25, 4).unwrap(), params);
    let g = gripper(GripperParams::default()).unwrap();
    let names = [
        (field(Partition::equal(110.0, 0)), LibField::PartitionN),
        (field(Partition::equal(-1.0, 8)), LibField::PartitionLx),
        (
            field(Partition::custom(vec![], 110.0)),
            LibField::PartitionLengths,
        ),
        (
            field(Partition::custom(vec![110.0, 0.0], 110.0)),
            LibField::PartitionLength(1),
        ),
        (
            field(Partition::custom(vec![f64::MAX, f64::MAX], 110.0)),
            LibField::PartitionLengthsSum,
        ),
        (
            field(Partition::material(&act, true, -1.0)),
            LibField::PartitionMaxLength,
        ),
        (
            field(Load::unloaded().with_pressure_kpa(-500.0).validate()),
            LibField::LoadPressure,
        ),
        (
            field(actuator(&|p| p.geometry.h1 = -1.0)),
            LibField::Geometry(GeometryKey::H1),
        ),
        (
            field(actuator(&|p| p.pemc.law.p1 = 0.0)),
            LibField::Pemc(PemcKey::P1),
        ),
        (
            field(actuator(&|p| p.pemc.e2 = 0.0)),
            LibField::Pemc(PemcKey::E2),
        ),
        (
            field(actuator(&|p| {
                p.ribs = RibLayout::Explicit(vec![Rib {
                    x0: 5.0,
                    x1: 1.0,
                    width: 1.0,
                }])
            })),
            LibField::Rib(0, RibEntryKey::X1),
        ),
        (
            field(
                crate::PlannedFinger::builder(&act)
                    .plan(crate::Plan::TipTolerance {
                        tip_tol_mm: 0.0,
                        start: Some(8),
                    })
                    .build(),
            ),
            LibField::TipTolMm,
        ),
        (
            field(gripper(GripperParams {
                mounting_angle: f64::NAN,
                ..GripperParams::default()
            })),
            LibField::GripperMountingAngle,
        ),
        (
            field(gripper(GripperParams {
                geometry: PalmSpec::Overlap(500.0),
                ..GripperParams::default()
            })),
            LibField::GripperOverlap,
        ),
        (
            field(gripper(GripperParams {
                geometry: PalmSpec::Palm(-1.0),
                ..GripperParams::default()
            })),
            LibField::GripperPalm,
        ),
        (
            field(g.force_control(0.0, f64::NAN, 0.3, None)),
            LibField::GraspSize,
        ),
        (
            field(g.force_control(0.0, 100.0, f64::NAN, None)),
            LibField::GraspFriction,
        ),
        (
            field(g.force_control(f64::NAN, 100.0, 0.3, None)),
            LibField::GraspPressureKpa,
        ),
        (
            field(g.grasp_load_for_size(0.0, 100.0, f64::NAN, None)),
            LibField::GraspBeta,
        ),
        (
            field(g.sphere_grasp(0.0, -1.0, 0.5, 0.3, None)),
            LibField::SphereRadius,
        ),
        (
            field(g.sphere_grasp(0.0, 50.0, 0.5, std::f64::consts::FRAC_PI_2, None)),
            LibField::SphereBeta,
        ),
        (
            field(g.sphere_grasp(0.0, 50.0, f64::NAN, 0.3, None)),
            LibField::SphereLift,
        ),
    ];
    for (name, f) in names {
        assert_eq!(LibField::from_name(&name), Some(f), "{name}");
    }
}

#[test]
fn library_values_in_scene_units() {
    let e = scene_input(InputError::OutOfRange {
        field: "load.pressure".into(),
        value: -0.2,
        rule: "is below absolute vacuum".into(),
    });
    assert_eq!(
        e.to_string(),
        "load.pressure_kpa = -200: is below absolute vacuum"
    );
    let e = scene_input(InputError::NotFinite {
        field: "gripper.mounting_angle".into(),
        value: f64::INFINITY,
    });
    assert_eq!(e.field(), "gripper.mounting_angle_deg");
    let e = scene_solve(SolveError::TargetNotReached {
        target: "grasp.friction".into(),
        value: 0.3,
        reached: 0.5,
        detail: "stopped".into(),
    });
    assert!(
        e.to_string()
            .starts_with("gripper.grasp.friction_n = 0.3: not reached"),
        "{e}"
    );
    // a field the scene cannot trigger is left alone
    let e = InputError::NotFinite {
        field: "guess".into(),
        value: f64::INFINITY,
    };
    assert_eq!(scene_input(e.clone()), e);
}

#[test]
fn warnings_use_scene_keys() {
    let s = Scene::from_toml("[gripper]\nmounting_angle_deg = 30\npalm_mm = 40\n").unwrap();
    let sol = s.solve().unwrap();
    let texts: Vec<String> = sol.warnings().iter().map(warning_text).collect();
    assert!(
        texts
            .iter()
            .any(|t| t.starts_with("gripper.mounting_angle_deg = 30")),
        "{texts:?}"
    );
    // the advice for too few elements is the scene's key
    let sol = Scene::from_toml("[partition]\nelements = 2\n")
        .unwrap()
        .solve()
        .unwrap();
    let texts: Vec<String> = sol.warnings().iter().map(warning_text).collect();
    assert!(
        texts
            .iter()
            .any(|t| t.starts_with("element 0 turns")
                && t.ends_with("(partition.elements = \"auto\")")),
        "{texts:?}"
    );
    let s = Scene::from_toml("[actuator.pemc]\neps0 = 0.8\n").unwrap();
    let texts: Vec<String> = s.warnings().iter().map(warning_text).collect();
    assert!(
        texts[0].starts_with("actuator.pemc.eps0 = 0.8"),
        "{texts:?}"
    );
}
