//! Unit tests of scene resolution: defaults, echo, keys and errors.

use super::*;
use crate::actuator::{ActuatorParams, Isotropic};
use crate::scene::testing::{input_err, schema_keys, schema_path, syntax_err, SCENES};
use crate::scene::Scene;

#[test]
fn empty_scene_is_the_default_actuator() {
    let s = Scene::from_toml("").unwrap();
    assert_eq!(s.actuator.params(), &ActuatorParams::default());
    assert_eq!(
        s.partition,
        PartitionPlan::Fixed(Partition::equal(110.0, DEFAULT_ELEMENTS).unwrap())
    );
    assert_eq!(s.load, Load::default());
    assert_eq!(s.options, SolveOptions::default());
    assert!(s.gripper.is_none());
}

#[test]
fn echo_spells_out_every_default_and_resolves_to_the_same_scene() {
    let more = [
        ("empty", ""),
        ("auto", "[partition]\nelements = \"auto\""),
        (
            "auto gripper",
            "[partition]\nelements = \"auto\"\n[gripper]\n",
        ),
        ("model", "[model]\nname = \"ccm\""),
        ("strict", "[gripper]\nstrict = true\n[gripper.grasp]\n"),
        (
            "laminate",
            "[actuator.laminate]\nplane_strain = true\nshear_correction = 0.7\n[actuator.emc]\ng13 = 0.5",
        ),
    ];
    for (name, text) in SCENES.iter().chain(&more) {
        let s = Scene::from_toml(text).unwrap_or_else(|e| panic!("{name}: {e}"));
        let again = s.file().resolve().unwrap();
        assert_eq!(again.model, s.model, "{name}");
        assert_eq!(again.actuator, s.actuator, "{name}");
        assert_eq!(again.partition, s.partition, "{name}");
        assert_eq!(again.load, s.load, "{name}");
        assert_eq!(again.options, s.options, "{name}");
        assert_eq!(again.gripper, s.gripper, "{name}");
        assert_eq!(again.file(), s.file(), "{name}: the echo is a fixed point");
        // and survives JSON
        let json = serde_json::to_string(s.file()).unwrap();
        let back: SceneFile = serde_json::from_str(&json).unwrap();
        assert_eq!(&back, s.file(), "{name}");
    }
    let echo = Scene::from_toml("").unwrap().file().clone();
    assert_eq!(echo.actuator.geometry.h1, Some(3.7));
    assert_eq!(echo.actuator.emc.kind, Some(MaterialKind::Orthotropic));
    assert_eq!(echo.actuator.pemc.p4, Some(0.698));
    assert_eq!(echo.partition.elements, Some(Elements::Count(8)));
}

#[test]
fn the_laminates_options_reach_the_actuator_and_echo_only_when_given() {
    let s = Scene::from_toml(
        "[actuator.laminate]\nplane_strain = true\nshear_correction = 0.7\n[actuator.emc]\ng13 = 0.5\n[actuator.pemc]\ng13 = 0.9",
    )
    .unwrap();
    let p = s.actuator.params();
    assert!(p.plane_strain);
    assert_eq!(p.shear.correction, 0.7);
    assert_eq!(p.shear.g13, [None, Some(0.5), None, Some(0.9)]);
    // the defaults of the others: E / (2 (1 + nu)), and p1 / 2
    use crate::field::ShearLayer;
    assert_eq!(s.actuator.g13(ShearLayer::Cl), 305.0 / 2.86);
    assert_eq!(s.actuator.g13(ShearLayer::Emc), 0.5);
    assert_eq!(s.actuator.g13(ShearLayer::Fluidic), 1.2 / 2.96);
    let echo = s.file();
    assert_eq!(echo.actuator.laminate.plane_strain, Some(true));
    assert_eq!(echo.actuator.emc.g13, Some(0.5));
    assert_eq!(echo.actuator.cl.g13, None);
    // a scene without them echoes none of them (outputs stay as they were)
    let plain = Scene::from_toml("").unwrap();
    let text = toml::to_string(plain.file()).unwrap();
    assert!(
        !text.contains("laminate") && !text.contains("g13"),
        "{text}"
    );
    assert!(!plain.actuator.params().plane_strain);
    assert_eq!(plain.actuator.shear_correction(), 5.0 / 6.0);
}

#[test]
fn every_section_reaches_the_library() {
    let s = Scene::from_toml(
        r#"
        [actuator.geometry]
        lx = 100
        h1 = 3.6
        [actuator.channel]
        cx = 95.0
        [actuator.ribs]
        list = [{ x0 = 0, x1 = 95, width = 2 }, { x0 = 10, x1 = 12, width = 12 }]
        [actuator.cl]
        e = 300
        [actuator.emc]
        kind = "isotropic"
        e = 2.0
        nu = 0.3
        [actuator.fluidic]
        nu = 0.45
        [actuator.pemc]
        eps0 = 0.4
        p2 = 2.0
        [partition]
        lengths = [50, 30, 20]
        [load]
        pressure_kpa = 40
        kappa = 1
        fx = 0.1
        fz = -0.2
        [solve]
        rtol = 1e-10
        max_iter = 40
        strategy = "coupled"
        samples_per_element = 4
        shape = true
        stability = false
        continuation = false
        "#,
    )
    .unwrap();
    let p = s.actuator.params();
    assert_eq!(p.geometry.lx, 100.0);
    assert_eq!(p.geometry.h1, 3.6);
    assert_eq!(p.channel.cx, 95.0);
    assert_eq!(s.actuator.ribs().len(), 2);
    assert_eq!(p.cl, Isotropic { e: 300.0, nu: 0.43 }.into());
    assert_eq!(p.emc, Isotropic { e: 2.0, nu: 0.3 }.into());
    assert_eq!(p.fluidic, Isotropic { e: 1.2, nu: 0.45 }.into());
    assert_eq!(p.pemc.eps0, 0.4);
    assert_eq!(p.pemc.law.to_array(), [1.598, 2.0, 2.29, 0.698]);
    let PartitionPlan::Fixed(part) = &s.partition else {
        panic!()
    };
    assert_eq!(part.lengths(), &[50.0, 30.0, 20.0]);
    assert_eq!(
        s.load,
        Load {
            pressure: 0.04,
            kappa: 1.0,
            fx: 0.1,
            fz: -0.2
        }
    );
    assert_eq!(s.options.strategy, Strategy::Coupled);
    assert_eq!(s.options.max_iter, 40);
    assert_eq!(s.options.samples_per_element, 4);
    assert!(!s.options.stability && !s.options.continuation);
    let sol = s.solve().unwrap();
    assert!(sol.solution().report.coupled);
}

#[test]
fn model_name_selects_the_element_model() {
    let s = Scene::from_toml("").unwrap();
    assert_eq!(s.model, ModelId::default());
    assert_eq!(s.file().model.name.as_deref(), Some("ccm"));
    for name in ModelId::names() {
        let s = Scene::from_toml(&format!("[model]\nname = \"{name}\"\n")).unwrap();
        assert_eq!(s.model.name(), name);
        assert_eq!(s.file().model.name.as_deref(), Some(name));
    }
    let e = input_err("[model]\nname = \"nope\"\n");
    assert_eq!(e.field(), "model.name");
    let listed: Vec<String> = ModelId::names()
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect();
    assert_eq!(
        e.to_string(),
        format!(
            "model.name: unknown model \"nope\"; the models are {}",
            listed.join(", ")
        )
    );
    // a name that is not one line stays one line in the message
    let e = input_err("[model]\nname = \"a\\nb\"\n");
    assert!(!e.to_string().contains('\n'), "{e}");
    // a wrong type or an unknown key is the parser's
    let e = syntax_err("[model]\nname = 3\n");
    assert_eq!((e.line, e.col), (2, 8), "{e}");
    let e = syntax_err("[model]\nnmae = \"ccm\"\n");
    assert_eq!(e.line, 2, "{e}");
    assert!(e.message.contains("nmae"), "{e}");
}

#[test]
fn gripper_strict() {
    let strict = |text: &str| {
        Scene::from_toml(text)
            .unwrap()
            .gripper
            .unwrap()
            .params
            .strict
    };
    assert!(!strict("[gripper]\n"));
    assert!(!strict("[gripper]\nstrict = false\n"));
    assert!(strict("[gripper]\nstrict = true\n"));
    let s = Scene::from_toml("[gripper]\n").unwrap();
    assert_eq!(s.file().gripper.as_ref().unwrap().strict, Some(false));
    // a boolean, in [gripper] only
    for text in ["[gripper]\nstrict = \"yes\"\n", "[gripper]\nstrict = 1\n"] {
        let e = syntax_err(text);
        assert_eq!((e.line, e.col), (2, 10), "{text:?}: {e}");
    }
    let e = syntax_err("[gripper.grasp]\nstrict = true\n");
    assert_eq!(e.line, 2, "{e}");
    assert!(e.message.contains("strict"), "{e}");
}

#[test]
fn elements_auto() {
    for text in [
        "[partition]\nelements = \"auto\"\n",
        "[partition]\nelements = \"auto\"\n[gripper]\n",
    ] {
        let s = Scene::from_toml(text).unwrap();
        assert_eq!(s.partition, PartitionPlan::Auto, "{text:?}");
        assert_eq!(s.file().partition.elements, Some(Elements::Auto));
        assert_eq!(s.file().partition.lengths, None);
    }
    let echo = Scene::from_toml("[partition]\nelements = \"auto\"").unwrap();
    let json = serde_json::to_value(echo.file()).unwrap();
    assert_eq!(json["partition"]["elements"], "auto");
    let json = serde_json::to_value(Scene::from_toml("").unwrap().file()).unwrap();
    assert_eq!(json["partition"]["elements"], 8);
    // with a tolerance, "auto" (or no count) is the fastest configuration
    for text in [
        "[partition]\nelements = \"auto\"\ntip_tol_mm = 0.1\n",
        "[partition]\ntip_tol_mm = 0.1\n",
    ] {
        let s = Scene::from_toml(text).unwrap();
        assert_eq!(
            s.partition,
            PartitionPlan::TipTolerance {
                tip_tol_mm: 0.1,
                start: None
            },
            "{text:?}"
        );
        assert_eq!(s.file().partition.elements, Some(Elements::Auto));
    }
    // anything else is the parser's, at the value
    for (text, col) in [
        ("[partition]\nelements = \"Auto\"\n", 12),
        ("[partition]\nelements = \"\"\n", 12),
        ("[partition]\nelements = true\n", 12),
        ("[partition]\nelements = -3\n", 12),
        ("[partition]\nelements = 2.0\n", 12),
    ] {
        let e = syntax_err(text);
        assert_eq!((e.line, e.col), (2, col), "{text:?}: {e}");
        assert!(e.message.contains("\"auto\""), "{text:?}: {e}");
    }
}

#[test]
fn bounded_counts() {
    assert_eq!(MAX_ELEMENTS as f64, (1.0 / MIN_ELEMENT_FRACTION).round());
    // the most samples are accepted, one more is not
    let s = Scene::from_toml(&format!(
        "[solve]\nsamples_per_element = {MAX_SAMPLES_PER_ELEMENT}"
    ))
    .unwrap();
    assert_eq!(s.options.samples_per_element, MAX_SAMPLES_PER_ELEMENT);
    let e = input_err(&format!(
        "[solve]\nsamples_per_element = {}",
        MAX_SAMPLES_PER_ELEMENT + 1
    ));
    assert_eq!(
        e.to_string(),
        "solve.samples_per_element = 4097: must lie in [1, 4096]"
    );
    // 1000 lengths are a partition, 1001 are refused as too many, even
    // when each is too short as well
    let list = |n: usize| {
        let l = vec![format!("{}", 110.0 / n as f64); n];
        format!("[partition]\nlengths = [{}]", l.join(", "))
    };
    let s = Scene::from_toml(&list(1000)).unwrap();
    let PartitionPlan::Fixed(p) = &s.partition else {
        panic!()
    };
    assert_eq!(p.len(), 1000);
    let e = input_err(&list(1001));
    assert_eq!(e.field(), "partition.lengths");
    assert!(
        e.to_string()
            .contains("1001 entries, more than the 1000 allowed"),
        "{e}"
    );
}

#[test]
fn library_errors_give_the_value_in_the_keys_unit() {
    // the library checks the pressure in MPa; the scene key is in kPa
    let e = input_err("[load]\npressure_kpa = -200");
    assert!(
        e.to_string()
            .starts_with("load.pressure_kpa = -200: is below absolute vacuum"),
        "{e}"
    );
}

/// A rule between two keys names the key the scene writes, with its value,
/// and quotes the default it conflicts with; with both keys written, the
/// rule's own key, as the library names it.
#[test]
fn a_rule_between_keys_names_the_key_written() {
    let default = "conflicts with the default of a key not given";
    let cases: &[(&str, &str, &str)] = &[
        (
            "[actuator.geometry]\nlx = 50",
            "actuator.geometry.lx = 50",
            "(actuator.channel.cx = 105: must not exceed the length lx = 50)",
        ),
        (
            "[actuator.geometry]\nly = 20",
            "actuator.geometry.ly = 20",
            "(actuator.channel.cy = 26: must be below the width ly = 20)",
        ),
        (
            "[actuator.geometry]\nh = 6",
            "actuator.geometry.h = 6",
            "(actuator.geometry.h1 = 3.7: must be below H/2 = 3",
        ),
        (
            "[actuator.geometry]\nh1 = 1.5",
            "actuator.geometry.h1 = 1.5",
            "(actuator.geometry.h2 = 1.8: must be below h1 = 1.5",
        ),
        (
            "[actuator.geometry]\nh2 = 0.5",
            "actuator.geometry.h2 = 0.5",
            "(actuator.channel.h3a = 0.8: must be below h2 = 0.5",
        ),
        (
            "[actuator.geometry]\nh3 = 1",
            "actuator.geometry.h3 = 1",
            "(actuator.channel.h3b = 1.2: must be below h3 = 1",
        ),
        (
            "[actuator.channel]\ncy = 10",
            "actuator.channel.cy = 10",
            "(actuator.ribs.w2 = 6: t + 2 w2 = 14 must not exceed the channel width cy = 10)",
        ),
        (
            "[actuator.ribs]\nt = 10",
            "actuator.ribs.t = 10",
            "(actuator.ribs.w1 = 8: must be at least t = 10",
        ),
        (
            "[actuator.geometry]\nlx = 100000\n[actuator.channel]\ncx = 100000",
            "actuator.channel.cx = 100000",
            "(actuator.ribs.w1 = 8: gives 12499 transverse ribs, more than 10000)",
        ),
    ];
    for &(text, written, quoted) in cases {
        let e = input_err(text);
        let key = written.split(" = ").next().unwrap();
        assert_eq!(e.field(), key, "{text:?}: {e}");
        let message = e.to_string();
        assert!(
            message.starts_with(&format!("{written}: {default} {quoted}")),
            "{text:?}: {message}"
        );
    }
    // both keys written: the rule's own key, as before
    for (text, message) in [
        (
            "[actuator.geometry]\nlx = 50\n[actuator.channel]\ncx = 60",
            "actuator.channel.cx = 60: must not exceed the length lx = 50",
        ),
        (
            "[actuator.geometry]\nh = 6\nh1 = 3.5",
            "actuator.geometry.h1 = 3.5: must be below H/2 = 3 ",
        ),
    ] {
        let e = input_err(text).to_string();
        assert!(e.starts_with(message), "{text:?}: {e}");
    }
    // the same rule reached through a parsed table (a sweep's point) or
    // the library's own fields (a scene echoed in full) names the same key
    let doc: toml::Table = toml::from_str("[actuator.geometry]\nlx = 50\n").unwrap();
    let e = SceneFile::from_table(&doc).unwrap().resolve().unwrap_err();
    assert_eq!(e.field(), "actuator.geometry.lx", "{e}");
}

#[test]
fn validation_errors_name_the_toml_path() {
    let cases: &[(&str, &str)] = &[
        ("[model]\nname = \"CCM\"", "model.name"),
        ("[model]\nname = \"\"", "model.name"),
        ("[actuator.geometry]\nh1 = 5", "actuator.geometry.h1"),
        ("[actuator.geometry]\nlx = -1", "actuator.geometry.lx"),
        ("[actuator.geometry]\nlx = nan", "actuator.geometry.lx"),
        ("[actuator.channel]\ncx = 120", "actuator.channel.cx"),
        ("[actuator.ribs]\nw1 = 0", "actuator.ribs.w1"),
        ("[actuator.ribs]\nkind = \"none\"\nt = 1", "actuator.ribs.t"),
        ("[actuator.ribs]\nkind = \"paper\"\nlist = []", "actuator.ribs.list"),
        ("[actuator.ribs]\nkind = \"list\"", "actuator.ribs.list"),
        (
            "[actuator.ribs]\nlist = [{ x0 = 0, x1 = 5, width = 2 }, { x0 = 3, x1 = 2, width = 1 }]",
            "actuator.ribs.list[1].x1",
        ),
        (
            "[actuator.ribs]\nlist = [{ x0 = 0, x1 = 5, width = 20 }, { x0 = 3, x1 = 4, width = 20 }]",
            "actuator.ribs",
        ),
        ("[actuator.cl]\nnu = 0.5", "actuator.cl.nu"),
        ("[actuator.cl]\ne = 1\ne1 = 2", "actuator.cl.e1"),
        ("[actuator.emc]\nkind = \"isotropic\"\ne = 2", "actuator.emc.nu"),
        ("[actuator.emc]\ne2 = -1", "actuator.emc.e2"),
        ("[actuator.fluidic]\nkind = \"orthotropic\"\ne = 1", "actuator.fluidic.e"),
        ("[actuator.pemc]\neps0 = inf", "actuator.pemc.eps0"),
        ("[actuator.pemc]\np1 = 0", "actuator.pemc.p1"),
        ("[actuator.pemc]\np3 = nan", "actuator.pemc.p3"),
        ("[actuator.pemc]\ne2 = 0", "actuator.pemc.e2"),
        ("[actuator.cl]\ng13 = -1", "actuator.cl.g13"),
        ("[actuator.fluidic]\ng13 = nan", "actuator.fluidic.g13"),
        ("[actuator.pemc]\ng13 = 0", "actuator.pemc.g13"),
        (
            "[actuator.laminate]\nshear_correction = 0",
            "actuator.laminate.shear_correction",
        ),
        ("[partition]\nelements = 0", "partition.elements"),
        ("[partition]\nelements = 5000", "partition.elements"),
        ("[partition]\nlengths = [50, 50]", "partition.lengths"),
        ("[partition]\nlengths = [110, 0]", "partition.lengths[1]"),
        ("[partition]\nlengths = []", "partition.lengths"),
        ("[partition]\nlengths = [110]\nelements = 1", "partition.lengths"),
        ("[partition]\nlengths = [110]\ntip_tol_mm = 1", "partition.tip_tol_mm"),
        ("[partition]\ntip_tol_mm = 0", "partition.tip_tol_mm"),
        (
            "[partition]\nelements = \"auto\"\nlengths = [110]",
            "partition.lengths",
        ),
        ("[load]\npressure_kpa = nan", "load.pressure_kpa"),
        ("[load]\nkappa = 0", "load.kappa"),
        ("[load]\nfx = inf", "load.fx"),
        ("[solve]\nrtol = 0", "solve.rtol"),
        ("[solve]\nmax_iter = 0", "solve.max_iter"),
        ("[solve]\nmax_iter = 100000000", "solve.max_iter"),
        ("[solve]\nsamples_per_element = 0", "solve.samples_per_element"),
        ("[solve]\nsamples_per_element = 4097", "solve.samples_per_element"),
        (
            "[solve]\nshape = false\nsamples_per_element = 100000000000",
            "solve.samples_per_element",
        ),
        ("[gripper]\nmounting_angle_deg = nan", "gripper.mounting_angle_deg"),
        ("[gripper]\nmu = 0", "gripper.mu"),
        ("[gripper]\nfingers = 0", "gripper.fingers"),
        ("[gripper]\noverlap_mm = 1\npalm_mm = 2", "gripper.palm_mm"),
        ("[gripper]\npalm_mm = -2", "gripper.palm_mm"),
        ("[gripper]\noverlap_mm = inf", "gripper.overlap_mm"),
        ("[gripper]\n[load]\nfx = 1", "load.fx"),
        ("[gripper]\n[solve]\nrtol = 1e-9", "solve.rtol"),
        ("[gripper]\n[partition]\ntip_tol_mm = 0.1", "partition.tip_tol_mm"),
        ("[gripper.grasp]\nkind = \"size\"\nbeta_deg = 91", "gripper.grasp.beta_deg"),
        ("[gripper.grasp]\nkind = \"sphere\"\nbeta_deg = 90", "gripper.grasp.beta_deg"),
        ("[gripper.grasp]\nkind = \"sphere\"\nr_mm = 0", "gripper.grasp.r_mm"),
        ("[gripper.grasp]\nkind = \"sphere\"\nd_mm = 10", "gripper.grasp.d_mm"),
        ("[gripper.grasp]\nkind = \"sphere\"\nlift_n = nan", "gripper.grasp.lift_n"),
        ("[gripper.grasp]\nkind = \"cuboid\"\nbeta_deg = 10", "gripper.grasp.beta_deg"),
        ("[gripper.grasp]\nd_mm = -3", "gripper.grasp.d_mm"),
        ("[gripper.grasp]\nfriction_n = nan", "gripper.grasp.friction_n"),
        ("[gripper.grasp]\npressure_kpa = inf", "gripper.grasp.pressure_kpa"),
        ("[gripper.grasp]\nkind = \"size\"\nr_mm = 3", "gripper.grasp.r_mm"),
        ("[gripper.grasp]\nkind = \"size\"\nd_mm = nan", "gripper.grasp.d_mm"),
    ];
    for (text, path) in cases {
        let e = input_err(text);
        assert_eq!(e.field(), *path, "{text:?}: {e}");
        assert!(e.to_string().starts_with(path), "{text:?}: {e}");
        assert!(
            schema_keys().contains(&schema_path(path)),
            "{path} is not a key of the schema"
        );
    }
}
