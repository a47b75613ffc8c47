//! Unit tests of the scene keys: every library field maps to a key of
//! the schema, and messages name scene keys.

use super::*;
use crate::field::{ChannelKey, ClRibKey, LaminateKey, PemcKey, RibKey, ShearLayer};
use crate::scene::testing::{schema_keys, schema_path};
use crate::scene::Scene;

/// The scene key of a library field.
fn scene_key_of(f: Field) -> String {
    scene_key(&f)
        .unwrap_or_else(|| panic!("{f} is not a library field the scene sets"))
        .to_string()
}

/// Every library field: every actuator key, the indexed ones at `index`,
/// and the fixed ones.
fn library_fields(index: usize) -> Vec<Field> {
    let mut all = Vec::new();
    all.extend(GeometryKey::ALL.iter().map(|&k| Field::Geometry(k)));
    all.extend(ChannelKey::ALL.iter().map(|&k| Field::Channel(k)));
    all.extend(PaperRibKey::ALL.iter().map(|&k| Field::PaperRib(k)));
    all.extend(RibKey::ALL.iter().map(|&k| Field::Rib(index, k)));
    all.extend(ClRibKey::ALL.iter().map(|&k| Field::ClRib(index, k)));
    for &l in Lamina::ALL {
        all.extend(Elastic::ALL.iter().map(|&k| Field::Material(l, k)));
    }
    all.extend(PemcKey::ALL.iter().map(|&k| Field::Pemc(k)));
    all.extend(ShearLayer::ALL.iter().map(|&l| Field::ShearModulus(l)));
    all.extend(LaminateKey::ALL.iter().map(|&k| Field::Laminate(k)));
    all.extend(
        crate::field::RefinementKey::ALL
            .iter()
            .map(|&k| Field::Refinement(k)),
    );
    all.push(Field::PartitionLength(index));
    all.extend_from_slice(Field::FIXED);
    all
}

#[test]
fn toml_paths_of_library_fields() {
    assert_eq!(scene_key_of(Field::Pemc(PemcKey::P1)), "actuator.pemc.p1");
    assert_eq!(scene_key_of(Field::Pemc(PemcKey::P4)), "actuator.pemc.p4");
    assert_eq!(
        scene_key_of(Field::ShearModulus(ShearLayer::Pemc)),
        "actuator.pemc.g13"
    );
    assert_eq!(
        scene_key_of(Field::Laminate(LaminateKey::ShearCorrection)),
        "actuator.laminate.shear_correction"
    );
    assert_eq!(
        scene_key_of(Field::Rib(2, RibKey::Width)),
        "actuator.ribs.list[2].width"
    );
    assert_eq!(
        scene_key_of(Field::PaperRib(PaperRibKey::W1)),
        "actuator.ribs.w1"
    );
    assert_eq!(scene_key_of(Field::Ribs), "actuator.ribs");
    assert_eq!(
        scene_key_of(Field::ClRib(3, ClRibKey::Height)),
        "actuator.cl_ribs.list[3].height"
    );
    assert_eq!(scene_key_of(Field::ClRibs), "actuator.cl_ribs");
    assert_eq!(scene_key_of(Field::LoadPressure), "load.pressure_kpa");
    assert_eq!(scene_key_of(Field::PartitionN), "partition.elements");
    assert_eq!(
        scene_key_of(Field::PartitionLength(12)),
        "partition.lengths[12]"
    );
    assert_eq!(scene_key_of(Field::SphereBeta), "gripper.grasp.beta_deg");
    // a name written out is never read back as a field, even one that
    // spells a library field's name
    for name in [
        "guess",
        "load.pressure",
        "partition.n",
        "actuator.pemc.law.p1",
    ] {
        assert_eq!(scene_key(&Field::key(name)), None, "{name}");
    }
}

#[test]
fn every_library_field_maps_to_a_scene_key_of_the_schema() {
    let schema = schema_keys();
    // the library fields no scene sets: a refinement plan's, a curve's
    // samples, the sensitivities' and the sphere's internal ones
    let unset = [
        Field::Refinement(crate::field::RefinementKey::Start),
        Field::Refinement(crate::field::RefinementKey::Levels),
        Field::Refinement(crate::field::RefinementKey::Extrapolate),
        Field::SamplesPerElement,
        Field::GraspForce,
        Field::SphereSamples,
        Field::Guess,
        Field::Coefficients,
    ];
    for index in [0, 7, 999] {
        let fields = library_fields(index);
        let names: std::collections::BTreeSet<String> =
            fields.iter().map(ToString::to_string).collect();
        assert_eq!(names.len(), fields.len(), "two fields display alike");
        for f in fields {
            match scene_key(&f) {
                Some(key) => assert!(
                    schema.contains(&schema_path(&key.to_string())),
                    "{f} maps to {key}, which is not a key of the schema"
                ),
                None => assert!(unset.contains(&f), "{f} maps to no scene key"),
            }
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

    fn field<T: std::fmt::Debug, E: Into<SolveError>>(r: Result<T, E>) -> Field {
        match r.map_err(Into::into) {
            Err(SolveError::Input(e)) => e.field().clone(),
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
        (field(Partition::equal(110.0, 0)), Field::PartitionN),
        (field(Partition::equal(-1.0, 8)), Field::PartitionLx),
        (
            field(Partition::custom(vec![], 110.0)),
            Field::PartitionLengths,
        ),
        (
            field(Partition::custom(vec![110.0, 0.0], 110.0)),
            Field::PartitionLength(1),
        ),
        (
            field(Partition::custom(vec![f64::MAX, f64::MAX], 110.0)),
            Field::PartitionLengthsSum,
        ),
        (
            field(Partition::material(&act, true, -1.0)),
            Field::PartitionMaxLength,
        ),
        (
            field(Load::unloaded().with_pressure_kpa(-500.0).validate()),
            Field::LoadPressure,
        ),
        (
            field(actuator(&|p| p.geometry.h1 = -1.0)),
            Field::Geometry(GeometryKey::H1),
        ),
        (
            field(actuator(&|p| p.pemc.law.p1 = 0.0)),
            Field::Pemc(PemcKey::P1),
        ),
        (
            field(actuator(&|p| p.pemc.e2 = 0.0)),
            Field::Pemc(PemcKey::E2),
        ),
        (
            field(actuator(&|p| {
                p.ribs = RibLayout::Explicit(vec![Rib {
                    x0: 5.0,
                    x1: 1.0,
                    width: 1.0,
                }])
            })),
            Field::Rib(0, RibKey::X1),
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
            Field::TipTolMm,
        ),
        (
            field(gripper(GripperParams {
                mounting_angle: f64::NAN,
                ..GripperParams::default()
            })),
            Field::GripperMountingAngle,
        ),
        (
            field(gripper(GripperParams {
                geometry: PalmSpec::Overlap(500.0),
                ..GripperParams::default()
            })),
            Field::GripperOverlap,
        ),
        (
            field(gripper(GripperParams {
                geometry: PalmSpec::Palm(-1.0),
                ..GripperParams::default()
            })),
            Field::GripperPalm,
        ),
        (
            field(g.force_control(0.0, f64::NAN, 0.3, None)),
            Field::GraspSize,
        ),
        (
            field(g.force_control(0.0, 100.0, f64::NAN, None)),
            Field::GraspFriction,
        ),
        (
            field(g.force_control(f64::NAN, 100.0, 0.3, None)),
            Field::GraspPressureKpa,
        ),
        (
            field(g.grasp_load_for_size(0.0, 100.0, f64::NAN, None)),
            Field::GraspBeta,
        ),
        (
            field(g.sphere_grasp(0.0, -1.0, 0.5, 0.3, None)),
            Field::SphereRadius,
        ),
        (
            field(g.sphere_grasp(0.0, 50.0, 0.5, std::f64::consts::FRAC_PI_2, None)),
            Field::SphereBeta,
        ),
        (
            field(g.sphere_grasp(0.0, 50.0, f64::NAN, 0.3, None)),
            Field::SphereLift,
        ),
    ];
    for (got, f) in names {
        assert_eq!(got, f);
        assert!(scene_key(&got).is_some(), "{got} maps to no scene key");
    }
}

#[test]
fn library_values_in_scene_units() {
    let e = scene_input(InputError::OutOfRange {
        field: Field::LoadPressure,
        value: -0.2,
        rule: "is below absolute vacuum".into(),
    });
    assert_eq!(
        e.to_string(),
        "load.pressure_kpa = -200: is below absolute vacuum"
    );
    let e = scene_input(InputError::NotFinite {
        field: Field::GripperMountingAngle,
        value: f64::INFINITY,
    });
    assert_eq!(
        e.to_string(),
        "gripper.mounting_angle_deg = inf: must be finite"
    );
    let e = scene_solve(SolveError::TargetNotReached {
        target: Field::GraspFriction,
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
        field: Field::Guess,
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

#[test]
fn sensitivity_parameters_are_named_by_the_scene_keys_of_their_fields() {
    let schema = schema_keys();
    for p in crate::actuator::ActuatorParam::all() {
        let key = scene_key_of(p.field());
        assert_eq!(p.name(), key);
        assert!(schema.contains(&schema_path(&key)), "{key}");
    }
    // the ribs on the constraining layer, by index
    use crate::actuator::ActuatorParam;
    for p in [ActuatorParam::ClRibWidth(3), ActuatorParam::ClRibHeight(0)] {
        let key = scene_key_of(p.field());
        assert_eq!(p.name(), key);
        assert!(schema.contains(&schema_path(&key)), "{key}");
        assert_eq!(ActuatorParam::from_name(&key), Some(p));
    }
}
