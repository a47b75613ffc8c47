//! The CLI says when an answer leaves the model: `fpc: warning:` lines on
//! stderr, `warnings` and `element_lengths_mm` in the JSON, a validity line
//! in the summary; `--elements auto` and `--model`; `fpc models`.

mod common;
use common::{fpc, text};

fn json(args: &[&str]) -> (serde_json::Value, String) {
    let out = fpc(args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    (v, text(&out.stderr))
}

fn kinds(v: &serde_json::Value) -> Vec<String> {
    v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["kind"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn a_finger_outside_the_model_says_so_in_text_json_and_stderr() {
    // one element pushed back on itself: the tip ends metres away
    let out = fpc(&["finger", "--elements", "1", "--fx", "-5"]);
    assert!(out.status.success());
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(
        stdout.contains("validity       OUTSIDE the model's limits"),
        "{stdout}"
    );
    assert!(stderr.contains("fpc: warning: element 0 turns"), "{stderr}");
    assert!(stderr.contains("strain"), "{stderr}");
    let (v, _) = json(&["finger", "--elements", "1", "--fx", "-5", "--json"]);
    let k = kinds(&v);
    assert!(k.contains(&"element_slope".to_string()), "{k:?}");
    assert!(k.contains(&"strain_range".to_string()), "{k:?}");
    for w in v["warnings"].as_array().unwrap() {
        assert!(w["message"].as_str().unwrap().len() > 10);
        assert_eq!(w["element"], 0);
        assert!(w["value"].is_number() && w["limit"].is_number(), "{w}");
    }
    assert_eq!(v["element_lengths_mm"], serde_json::json!([110.0]));
    assert_eq!(v["validity"], false, "the one verdict in the JSON too");

    // the paper's eps0 = 0.4 finger in two elements turns each > 100 degrees
    let (v, stderr) = json(&["finger", "--eps0", "0.4", "--elements", "2", "--json"]);
    assert_eq!(kinds(&v), ["element_slope", "element_slope"]);
    assert_eq!(stderr.lines().count(), 2, "{stderr}");
}

#[test]
fn the_default_finger_raises_nothing_and_auto_fixes_the_coarse_one() {
    let (v, stderr) = json(&["finger", "--json"]);
    assert!(kinds(&v).is_empty() && stderr.is_empty(), "{stderr}");
    assert_eq!(v["validity"], true);
    assert_eq!(v["elements"], 8);
    assert_eq!(v["model"], "ccm");
    let (v, stderr) = json(&["finger", "--eps0", "0.4", "--elements", "auto", "--json"]);
    assert!(kinds(&v).is_empty(), "{stderr}");
    let n = v["elements"].as_u64().unwrap() as usize;
    let lengths = v["element_lengths_mm"].as_array().unwrap();
    assert_eq!(lengths.len(), n);
    let sum: f64 = lengths.iter().map(|l| l.as_f64().unwrap()).sum();
    assert!((sum - 110.0).abs() < 1e-9, "{sum}");
    let out = fpc(&["finger", "--eps0", "0.4", "--elements", "auto"]);
    assert!(text(&out.stdout).contains("(auto)"));
    // below vacuum is rejected input
    let out = fpc(&["finger", "--pressure-kpa", "-10000"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("below absolute vacuum"));
    // neither a count nor auto
    let out = fpc(&["finger", "--elements", "many"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn models_are_listed_and_chosen_by_name() {
    let out = fpc(&["models", "--json"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let names: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert!(
        names.contains(&"ccm") && names.contains(&"quad") && names.contains(&"shear"),
        "{names:?}"
    );
    for m in v.as_array().unwrap() {
        let spec = m["spec"].as_str().unwrap();
        assert!(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../..")
                .join(spec)
                .exists(),
            "{spec}"
        );
    }
    let (v, _) = json(&["finger", "--model", "quad", "--json"]);
    assert_eq!(v["model"], "quad");
    assert_eq!(v["coefficients"][0].as_array().unwrap().len(), 5);
    // a model that is not one names the flag, in every command that takes it
    let dir = common::tmp("validity", "model");
    let out = dir.path().join("out").display().to_string();
    for cmd in [&["finger"][..], &["kernels"], &["paper", "--out", &out]] {
        let out = fpc(&[cmd, &["--model", "nope"][..]].concat());
        assert_eq!(out.status.code(), Some(2), "{cmd:?}");
        let err = text(&out.stderr);
        assert!(
            err.contains("--model = `nope`: not a model (models: ccm, quad, shear)"),
            "{cmd:?}: {err}"
        );
    }
    // the shear-deformable element: five unknowns, the fifth its shear strain
    let (v, _) = json(&["finger", "--model", "shear", "--fx", "0.2", "--json"]);
    assert_eq!(v["model"], "shear");
    assert_eq!(v["coefficients"][0].as_array().unwrap().len(), 5);
    let out = fpc(&["kernels", "--model", "quad", "--report"]);
    assert!(text(&out.stdout).contains("prestressed_hessian"));
}

#[test]
fn a_finger_curled_onto_its_root_is_outside_the_model() {
    // the finger: 371 degrees on the automatic partition, the tip
    // 3.6 mm from the root of a finger 8.2 mm thick
    let out = fpc(&["finger", "--eps0", "0.6", "--elements", "auto"]);
    assert!(out.status.success());
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(
        stdout.contains("validity       OUTSIDE the model's limits: 1 finding(s)"),
        "{stdout}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("fpc: warning: the finger's surfaces meet"),
        "{stderr}"
    );
    assert!(stderr.contains("H = 8.2 mm"), "{stderr}");
    let (v, _) = json(&["finger", "--eps0", "0.6", "--elements", "auto", "--json"]);
    assert_eq!(kinds(&v), ["self_contact"]);
    let w = &v["warnings"][0];
    let n = v["elements"].as_u64().unwrap();
    assert_eq!(w["element"], n - 1, "the tip's element: {w}");
    assert_eq!(w["limit"], 8.2);
    let d = w["value"].as_f64().unwrap();
    assert!((0.0..1.0).contains(&d), "{w}");
}

#[test]
fn an_automatic_partition_that_stops_at_a_fold_says_so() {
    // 20 N each way crushes the default finger: its root element folds,
    // and each split leaves one half with nearly all of the turn
    let args = ["finger", "--elements", "auto", "--fx", "-20", "--fz", "-20"];
    let out = fpc(&args);
    assert!(out.status.success());
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(stdout.contains("OUTSIDE the model's limits"), "{stdout}");
    let fold: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("fpc: warning: the automatic partition stopped at a fold"))
        .collect();
    assert_eq!(fold.len(), 1, "{stderr}");
    let (v, _) = json(&[&args[..], &["--json"]].concat());
    let warnings = v["warnings"].as_array().unwrap();
    let note = warnings
        .iter()
        .find(|w| w["kind"] == "partition_fold")
        .expect("the note");
    let slope = warnings
        .iter()
        .find(|w| w["kind"] == "element_slope")
        .expect("the folded element's slope finding");
    assert_eq!(note["element"], slope["element"], "{note} {slope}");
    let share = note["value"].as_f64().unwrap();
    assert!(share >= 0.9 && note["limit"] == 0.9, "{note}");
    assert_eq!(v["validity"], false);
}

/// `fpc solve` on a scene written from `toml`: its stderr, whether it
/// succeeded, and its solution.json (`Null` when it wrote none).
fn solve_scene(toml: &str) -> (bool, String, serde_json::Value) {
    let scratch = tempfile::Builder::new()
        .prefix("fpc-validity-scene-")
        .tempdir()
        .unwrap();
    let dir = scratch.path();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, toml).unwrap();
    let out_dir = dir.join("out");
    let out = fpc(&[
        "solve",
        scene.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    let v = std::fs::read(out_dir.join("solution.json")).map_or(serde_json::Value::Null, |b| {
        serde_json::from_slice(&b).unwrap()
    });
    (out.status.success(), text(&out.stderr), v)
}

#[test]
fn a_scene_too_thick_for_laminate_theory_says_so_once() {
    let (ok, stderr, v) = solve_scene(
        "[actuator.geometry]\nh = 200\nh1 = 90\nh2 = 44\nh3 = 54\n[actuator.channel]\nh3a = 19\nh3b = 29\n",
    );
    assert!(ok, "{stderr}");
    // against the length and against the width, each printed once
    assert_eq!(
        stderr
            .matches("too thick for classical laminate theory")
            .count(),
        2,
        "{stderr}"
    );
    assert_eq!(v["validity"], false);
    let thick: Vec<&serde_json::Value> = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["kind"] == "thickness_ratio")
        .collect();
    assert_eq!(thick.len(), 2, "{v}");
    assert!((thick[0]["value"].as_f64().unwrap() - 200.0 / 110.0).abs() < 1e-12);
    assert_eq!(thick[0]["limit"], 0.1);
    assert!((thick[1]["value"].as_f64().unwrap() - 200.0 / 31.75).abs() < 1e-12);
    assert_eq!(thick[1]["limit"], 0.5);
}

/// Case 1803 of stress seed 17 as a scene (`quad`, no ribs, 2.4 times the
/// default stack, an axial push of 217 N): the automatic partition's
/// 9-element start solves, beyond the model, and its split into 10 does
/// not (docs/stress.md, "A split that does not solve"). The answer is the
/// 9 elements', outside the model, with the note on stderr, whole, and in
/// solution.json; before, the scene failed with the split's error.
#[test]
fn an_automatic_partition_whose_split_does_not_solve_says_so() {
    let (ok, stderr, v) = solve_scene(
        "[model]\nname = \"quad\"\n\
         [actuator.geometry]\nh = 20.08283220711065\nh1 = 9.06176575198895\n\
         h2 = 4.408426582048678\nh3 = 5.388076933615054\n\
         [actuator.channel]\nh3a = 1.959300703132746\nh3b = 2.9389510546991198\n\
         [actuator.ribs]\nkind = \"none\"\n\
         [actuator.pemc]\neps0 = 0.03436321314444933\n\
         [partition]\nelements = \"auto\"\n\
         [load]\npressure_kpa = 101.77532036673382\nfx = -216.86720813606\n",
    );
    assert!(ok, "{stderr}");
    let notes: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("fpc: warning: the automatic partition stopped at 9 elements"))
        .collect();
    assert_eq!(notes.len(), 1, "{stderr}");
    assert!(notes[0].contains("their split into 10 did not (solve failed: "));
    assert!(!notes[0].contains("chars cut"), "{}", notes[0]);
    assert_eq!(v["elements"], 9);
    assert_eq!(v["validity"], false);
    let warnings = v["warnings"].as_array().unwrap();
    let note = warnings
        .iter()
        .find(|w| w["kind"] == "partition_split_failed")
        .expect("the note");
    assert_eq!(
        (&note["value"], &note["limit"]),
        (&10.0.into(), &9.0.into())
    );
    assert!(warnings.iter().any(|w| w["kind"] == "element_slope"), "{v}");
}

/// Four levels (27 to 216 elements) for 1e-3 mm: the summary names the
/// extrapolation of the last three levels, and the JSON's refinement holds
/// what redoes it (`common::check_refinement`).
#[test]
fn a_refined_solve_says_how_it_extrapolated() {
    let args = ["finger", "--fx", "0.5", "--tip-tol-mm", "0.001"];
    let (v, _) = json(&[&args[..], &["--json"]].concat());
    let r = &v["refinement"];
    assert_eq!(r["extrapolation"], "last_three", "{v}");
    common::check_refinement(r);
    let stdout = text(&fpc(&args).stdout);
    assert!(
        stdout.contains("(h and h^2 terms removed from the last three levels)"),
        "{stdout}"
    );
    assert!(stdout.contains("(of the extrapolated tip)"), "{stdout}");
    // the steps line adds up the levels (the finest level's final solve,
    // from its own converged state, takes none)
    let coupled: u64 = r["level_steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["coupled"].as_u64().unwrap())
        .sum();
    assert!(coupled > 0);
    let steps = stdout.lines().find(|l| l.starts_with("steps")).unwrap();
    assert!(
        steps.contains(&format!(", {coupled} coupled,")) && steps.ends_with("(all levels)"),
        "{steps}"
    );
}

#[test]
fn a_refined_solve_counts_the_iterations_of_every_level() {
    let (v, _) = json(&["finger", "--tip-tol-mm", "0.01", "--json"]);
    let levels = v["refinement"]["level_iterations"].as_array().unwrap();
    assert!(levels.len() > 1, "{v}");
    assert_eq!(
        levels.len(),
        v["refinement"]["levels"].as_array().unwrap().len()
    );
    let total: u64 = levels.iter().map(|l| l.as_u64().unwrap()).sum();
    assert!(total > 0);
    let out = fpc(&["finger", "--tip-tol-mm", "0.01"]);
    let stdout = text(&out.stdout);
    let line = stdout.lines().find(|l| l.starts_with("solver")).unwrap();
    assert!(
        line.contains(&format!("{total} iterations over {} levels", levels.len())),
        "{line}"
    );
}
