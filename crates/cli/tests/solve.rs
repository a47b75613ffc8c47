//! `fpc solve` on the example scenes and on bad scenes.

mod common;
use common::{text, TempDir};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fpc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
}

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn run_ok(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status,
        text(&out.stdout),
        text(&out.stderr)
    );
    out
}

fn example_scenes() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(scenes_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    assert!(v.len() >= 6, "{v:?}");
    v
}

/// The keys of `solution.json` in every scene: the finger's equilibrium
/// (the `fpc finger --json` keys) and the run's.
const KEYS: [&str; 18] = [
    "scene_name",
    "kind",
    "elements",
    "tip_error_estimate_mm",
    "tip_mm",
    "end_angle_rad",
    "radius_mm",
    "energy_nmm",
    "negative_eigenvalues",
    "stable",
    "coefficients",
    "points_mm",
    "element_lengths_mm",
    "report",
    "validity",
    "warnings",
    "warning_messages",
    "scene",
];

/// The keys a gripper scene adds.
const GRIPPER_KEYS: [&str; 3] = ["gripper", "grasp", "points_gripper_mm"];

/// The keys of `gripper`: the design and the geometry its rest state fixes.
const GRIPPER: [&str; 15] = [
    "mounting_angle_deg",
    "mu",
    "fingers",
    "params",
    "model",
    "elements",
    "l0_mm",
    "palm_mm",
    "overlap_mm",
    "d_min_mm",
    "d_max_mm",
    "r_max_mm",
    "tip_is_innermost",
    "rest_tip_gripper_mm",
    "warnings",
];

/// The keys of `grasp` (a sphere adds `sphere_radius_mm` and
/// `sphere_center_gripper_mm`).
const GRASP: [&str; 14] = [
    "kind",
    "pressure_kpa",
    "beta_deg",
    "normal_force_n",
    "friction_n",
    "friction_limit_n",
    "lift_n",
    "size_mm",
    "tip_gap_mm",
    "height_mm",
    "tip_gripper_mm",
    "tip_load_finger_n",
    "valid",
    "invalid",
];

/// What `fpc solve` wrote for one scene.
struct Written {
    json: serde_json::Value,
    csv: String,
    svg: String,
    stderr: String,
}

/// Solves `scene` into `out` and reads the three files back.
fn solve_into(scene: &Path, out: &Path) -> Written {
    let o = run_ok(fpc().arg("solve").arg(scene).arg("--out").arg(out));
    assert!(text(&o.stdout).contains("wrote"), "{}", text(&o.stdout));
    let read = |f: &str| {
        std::fs::read_to_string(out.join(f)).unwrap_or_else(|e| panic!("{scene:?}: {f}: {e}"))
    };
    Written {
        json: serde_json::from_str(&read("solution.json"))
            .unwrap_or_else(|e| panic!("{scene:?}: solution.json: {e}")),
        csv: read("shape.csv"),
        svg: read("shape.svg"),
        stderr: text(&o.stderr),
    }
}

/// Writes `text` as `<name>.toml` in `dir` and solves it into `<name>`.
fn solve_text(dir: &Path, name: &str, scene: &str) -> Written {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, scene).unwrap();
    solve_into(&path, &dir.join(name))
}

/// The checks every `solution.json` passes: every key, the findings as
/// typed objects with their text beside them, and `validity` agreeing
/// with them and with the grasp.
fn check_json(name: &str, json: &serde_json::Value) {
    let kind = json["kind"]
        .as_str()
        .unwrap_or_else(|| panic!("{name}: kind"));
    assert!(
        ["finger", "gripper", "grasp"].contains(&kind),
        "{name}: {kind}"
    );
    for key in KEYS {
        assert!(json.get(key).is_some(), "{name}: no {key}");
    }
    // a scene refined to a tip tolerance says how it got the tip its
    // estimate is of
    let refined = !json["tip_error_estimate_mm"].is_null();
    assert_eq!(json.get("refinement").is_some(), refined, "{name}");
    if refined {
        common::check_refinement(&json["refinement"]);
    }
    for key in GRIPPER_KEYS {
        assert_eq!(json.get(key).is_some(), kind != "finger", "{name}: {key}");
    }
    if kind != "finger" {
        for key in GRIPPER {
            assert!(
                json["gripper"].get(key).is_some(),
                "{name}: no gripper.{key}"
            );
        }
        assert_eq!(json["grasp"].is_null(), kind == "gripper", "{name}");
    }
    if kind == "grasp" {
        let g = &json["grasp"];
        for key in GRASP {
            assert!(g.get(key).is_some(), "{name}: no grasp.{key}");
        }
        let sphere = g["kind"] == "sphere";
        assert_eq!(g.get("sphere_radius_mm").is_some(), sphere, "{name}");
        assert_eq!(
            g.get("sphere_center_gripper_mm").is_some(),
            sphere,
            "{name}"
        );
        assert_eq!(g["valid"].as_bool(), Some(g["invalid"].is_null()), "{name}");
    }
    let tip = json["tip_mm"].as_array().unwrap();
    assert!(
        tip.iter().all(|v| v.as_f64().unwrap().is_finite()),
        "{name}"
    );
    // the echo spells out the defaults
    assert!(
        json["scene"]["actuator"]["geometry"]["lx"].is_number(),
        "{name}"
    );

    let warnings = json["warnings"].as_array().unwrap();
    let messages = json["warning_messages"].as_array().unwrap();
    assert_eq!(warnings.len(), messages.len(), "{name}");
    for (w, m) in warnings.iter().zip(messages) {
        assert!(w.is_object(), "{name}: a warning is an object: {w}");
        assert!(
            w["kind"].as_str().is_some_and(|k| !k.is_empty()),
            "{name}: {w}"
        );
        assert!(
            w["message"].as_str().is_some_and(|m| m.len() > 10),
            "{name}: {w}"
        );
        for key in ["element", "value", "limit"] {
            let v = w.get(key);
            assert!(v.is_none_or(serde_json::Value::is_number), "{name}: {w}");
        }
        assert!(m.as_str().is_some_and(|m| m.len() > 10), "{name}: {m}");
    }
    let outside = warnings
        .iter()
        .any(|w| VALIDITY_KINDS.contains(&w["kind"].as_str().unwrap()));
    // one verdict: a grasp's own (which counts the finger's findings), else
    // no finding outside the model
    if kind == "grasp" {
        assert_eq!(json["validity"], json["grasp"]["valid"], "{name}");
        if outside {
            assert_eq!(json["grasp"]["valid"], false, "{name}");
        }
    } else {
        assert_eq!(json["validity"], !outside, "{name}");
    }
}

/// The warning kinds that put an answer outside the model.
const VALIDITY_KINDS: [&str; 5] = [
    "element_slope",
    "strain_range",
    "self_contact",
    "thickness_ratio",
    "beyond_flat",
];

/// `shape.csv`: the header of the scene's kind, one finite row per sample.
fn check_csv(name: &str, json: &serde_json::Value, csv: &str) {
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    let expected = if json["kind"] == "finger" {
        "x_mm,z_mm"
    } else {
        "x_mm,z_mm,xg_mm,zg_mm"
    };
    assert_eq!(header, expected, "{name}");
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(
        rows.len(),
        json["points_mm"].as_array().unwrap().len(),
        "{name}"
    );
    assert!(rows.iter().all(|r| r.len() == header.split(',').count()));
}

/// `shape.svg`: a whole document with axes named in the scene's frame,
/// the tip's caption, every validity finding listed, and no `NaN`.
fn check_svg(name: &str, json: &serde_json::Value, svg: &str) {
    assert!(
        svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"),
        "{name}"
    );
    assert!(!svg.contains("NaN"), "{name}: NaN in the SVG");
    assert!(
        !svg.contains("inf\""),
        "{name}: an infinite coordinate in the SVG"
    );
    let (x, y) = if json["kind"] == "finger" {
        ("X (mm)", "Z (mm)")
    } else {
        ("Xg (mm)", "Zg (mm, pointing down)")
    };
    assert!(svg.contains(x) && svg.contains(y), "{name}: no axis labels");
    assert!(svg.contains("tip X"), "{name}: no tip in the caption");
    assert!(svg.contains("end angle"), "{name}");
    if json["kind"] == "grasp" {
        assert!(svg.contains("kPa") && svg.contains("f_v ="), "{name}");
        let verdict = if json["grasp"]["valid"] == true {
            ": valid"
        } else {
            "NOT valid"
        };
        assert!(svg.contains(verdict), "{name}: {verdict}");
    }
    let findings: Vec<&serde_json::Value> = json["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| VALIDITY_KINDS.contains(&w["kind"].as_str().unwrap()))
        .collect();
    for w in findings.iter().take(MAX_FINDINGS) {
        let kind = w["kind"].as_str().unwrap();
        let line = match w.get("element") {
            Some(e) => format!("outside the model: {kind} at element {e}"),
            None => format!("outside the model: {kind}"),
        };
        assert!(svg.contains(&line), "{name}: {line} not in the SVG");
    }
    if findings.len() > MAX_FINDINGS {
        let more = format!("and {} more findings", findings.len() - MAX_FINDINGS);
        assert!(svg.contains(&more), "{name}: {more} not in the SVG");
    }
    if findings.is_empty() {
        assert!(svg.contains("within the model"), "{name}");
    }
}

/// The findings the SVG's caption lists one by one (src/solve.rs).
const MAX_FINDINGS: usize = 12;

#[test]
fn every_example_scene_solves_and_writes_its_files() {
    let tmp = TempDir::new("examples");
    for scene in example_scenes() {
        let stem = scene.file_stem().unwrap().to_string_lossy().into_owned();
        let out = tmp.0.join(&stem);
        let w = solve_into(&scene, &out);
        check_json(&stem, &w.json);
        check_csv(&stem, &w.json, &w.csv);
        check_svg(&stem, &w.json, &w.svg);
        assert_eq!(w.json["scene_name"], stem.as_str());
        if w.json["kind"] == "grasp" {
            assert_eq!(w.json["grasp"]["valid"], true, "{stem}");
            assert!(w.svg.contains("<polygon"), "{stem}: no object");
        }
        assert!(w.svg.contains("<polyline"), "{stem}: no shape");
        // written atomically: no temporary file left behind
        for e in std::fs::read_dir(&out).unwrap() {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(!name.ends_with(".tmp"), "{stem}: {name}");
        }
    }
}

#[test]
fn ribs_on_the_constraining_layer_are_echoed_and_curl_the_finger_less() {
    let tmp = TempDir::new("cl-ribs");
    let load = "[partition]\nelements = \"auto\"\n[load]\npressure_kpa = 20\n";
    let plain = solve_text(&tmp.0, "plain", load);
    let ribbed = solve_text(
        &tmp.0,
        "ribbed",
        &format!("{load}[actuator.cl_ribs]\nlist = [{{ x0 = 40, x1 = 70, width = 31.75, height = 0.5 }}]\n"),
    );
    assert!(plain.json["scene"]["actuator"].get("cl_ribs").is_none());
    let rib = &ribbed.json["scene"]["actuator"]["cl_ribs"]["list"][0];
    assert_eq!(rib["height"], 0.5);
    let radius = |w: &Written| w.json["radius_mm"].as_f64().unwrap();
    assert!(
        radius(&ribbed) > radius(&plain),
        "{} against {}",
        radius(&ribbed),
        radius(&plain)
    );
    // the rib's ends are element ends of the automatic partition
    let mut x = 0.0;
    let mut ends = Vec::new();
    for l in ribbed.json["element_lengths_mm"].as_array().unwrap() {
        x += l.as_f64().unwrap();
        ends.push(x);
    }
    for end in [40.0, 70.0] {
        assert!(ends.iter().any(|e| (e - end).abs() < 1e-9), "{ends:?}");
    }
}

#[test]
fn findings_are_typed_in_the_json_and_listed_in_the_svg() {
    let tmp = TempDir::new("findings");
    // two elements under pressure each turn beyond the slope limit
    let w = solve_text(
        &tmp.0,
        "coarse",
        "[partition]\nelements = 2\n[load]\npressure_kpa = 60\n",
    );
    check_json("coarse", &w.json);
    check_svg("coarse", &w.json, &w.svg);
    assert_eq!(w.json["validity"], false);
    let warnings = w.json["warnings"].as_array().unwrap();
    let slopes: Vec<&serde_json::Value> = warnings
        .iter()
        .filter(|w| w["kind"] == "element_slope")
        .collect();
    assert_eq!(slopes.len(), 2, "{warnings:?}");
    for (i, s) in slopes.iter().enumerate() {
        assert_eq!(s["element"], i);
        assert!(
            s["value"].as_f64().unwrap() > s["limit"].as_f64().unwrap(),
            "{s}"
        );
    }
    // the text form names the scene's keys, as stderr does
    let messages = w.json["warning_messages"].as_array().unwrap();
    for m in messages {
        let m = m.as_str().unwrap();
        assert!(w.stderr.contains(m), "{m} not on stderr: {}", w.stderr);
    }
    assert!(w
        .svg
        .contains("outside the model: element_slope at element 1"));

    // a grasp breaking a rule: `invalid` is a typed object
    let w = solve_text(
        &tmp.0,
        "cone",
        "[gripper]\n[gripper.grasp]\nfriction_n = 50\n",
    );
    check_json("cone", &w.json);
    check_svg("cone", &w.json, &w.svg);
    let g = &w.json["grasp"];
    assert_eq!(g["valid"], false);
    assert_eq!(g["invalid"]["kind"], "friction_cone", "{g}");
    assert!(
        g["invalid"]["message"].as_str().unwrap().contains("mu F"),
        "{g}"
    );
    assert_eq!(w.json["validity"], false);
    assert!(w.svg.contains("NOT valid: friction_cone"));

    // the gripper's design note is a typed warning too, not a finding
    let w = solve_text(
        &tmp.0,
        "angle",
        "[gripper]\nmounting_angle_deg = 30\npalm_mm = 40\n",
    );
    check_json("angle", &w.json);
    check_svg("angle", &w.json, &w.svg);
    let kinds: Vec<&str> = w.json["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["kind"].as_str().unwrap())
        .collect();
    assert!(
        kinds.contains(&"mounting_angle_outside_design_space"),
        "{kinds:?}"
    );
    assert_eq!(
        w.json["gripper"]["warnings"][0]["kind"],
        "mounting_angle_outside_design_space"
    );
}

#[test]
fn an_unsampled_shape_draws_the_tip_without_nan() {
    let tmp = TempDir::new("unsampled");
    for (name, scene) in [
        ("finger", "[solve]\nshape = false\n"),
        (
            "tip_load",
            "[solve]\nshape = false\n[load]\nfx = 0.5\nfz = -0.5\n",
        ),
    ] {
        let w = solve_text(&tmp.0, name, scene);
        check_json(name, &w.json);
        check_csv(name, &w.json, &w.csv);
        check_svg(name, &w.json, &w.svg);
        assert!(w.json["points_mm"].as_array().unwrap().is_empty(), "{name}");
        assert_eq!(w.csv, "x_mm,z_mm\n", "{name}");
        assert!(w.svg.contains("solve.shape = false"), "{name}");
        assert!(w.svg.contains("<circle"), "{name}: the tip");
    }
}

#[test]
fn every_grasp_kind_and_a_gripper_at_rest_are_drawn() {
    let tmp = TempDir::new("kinds");
    for (name, scene, object) in [
        ("rest", "[gripper]\n", None),
        (
            "size",
            "[gripper]\n[gripper.grasp]\nkind = \"size\"\nd_mm = 90\nbeta_deg = 10\n",
            Some("object surface at the contacts"),
        ),
        ("cuboid", "[gripper]\n[gripper.grasp]\n", Some("cuboid")),
        (
            "sphere",
            "[gripper]\n[gripper.grasp]\nkind = \"sphere\"\n",
            Some("sphere"),
        ),
    ] {
        let w = solve_text(&tmp.0, name, scene);
        check_json(name, &w.json);
        check_csv(name, &w.json, &w.csv);
        check_svg(name, &w.json, &w.svg);
        for entry in [
            "finger mid-plane",
            "opposite finger",
            "fingers at rest",
            "palm",
            "tip",
        ] {
            assert!(w.svg.contains(entry), "{name}: no {entry} in the legend");
        }
        if let Some(o) = object {
            assert!(w.svg.contains(o), "{name}: no {o}");
        }
        assert_eq!(
            w.json["kind"],
            if object.is_some() { "grasp" } else { "gripper" }
        );
    }
}

#[test]
fn default_output_directory_is_named_after_the_scene() {
    let tmp = TempDir::new("default-out");
    let scene = tmp.0.join("my_scene.toml");
    std::fs::write(&scene, "[load]\npressure_kpa = 10\n").unwrap();
    run_ok(fpc().arg("solve").arg("my_scene.toml").current_dir(&tmp.0));
    for f in ["solution.json", "shape.csv", "shape.svg"] {
        assert!(tmp.0.join("my_scene-out").join(f).is_file(), "{f}");
    }
}

fn run_bad(name: &str, scene: &str) -> (i32, String) {
    let tmp = TempDir::new(name);
    let path = tmp.0.join(format!("{name}.toml"));
    std::fs::write(&path, scene).unwrap();
    let out = fpc()
        .arg("solve")
        .arg(&path)
        .arg("--out")
        .arg(tmp.0.join("out"))
        .output()
        .unwrap();
    assert!(
        !tmp.0.join("out").exists(),
        "{name}: nothing is written for a failed scene"
    );
    let stderr = text(&out.stderr);
    assert_eq!(stderr.lines().count(), 1, "{name}: one line: {stderr}");
    (out.status.code().unwrap(), stderr)
}

#[test]
fn a_typo_exits_2_with_line_and_column() {
    let (code, err) = run_bad(
        "typo",
        "# a scene\n[actuator.geometry]\nlx = 100.0\nh11 = 3.0\n",
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("typo.toml:4:1:"), "{err}");
    assert!(err.contains("h11"), "{err}");
}

#[test]
fn a_syntax_error_exits_2_with_line_and_column() {
    let (code, err) = run_bad("syntax", "[load]\nfx = 0.5\nfz = = 1\n");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("syntax.toml:3:6:"), "{err}");
}

#[test]
fn an_invalid_value_exits_2_naming_the_key() {
    let (code, err) = run_bad("value", "[actuator.geometry]\nh1 = 5.0\n");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("actuator.geometry.h1 = 5"), "{err}");
    // found only once the gripper is built
    let (code, err) = run_bad("overlap", "[gripper]\noverlap_mm = 500\n");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("gripper.overlap_mm = 500"), "{err}");
}

#[test]
fn a_failed_solve_exits_1() {
    let (code, err) = run_bad(
        "unsolved",
        "[load]\nfx = 1.0\n[solve]\nmax_iter = 1\ncontinuation = false\n",
    );
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("solve failed"), "{err}");
}

/// A finger scene says whether it is stable and inside the model, as
/// `fpc finger` does, and sums up many findings of one kind in one line
/// while solution.json keeps every one.
#[test]
fn a_finger_scene_prints_its_validity_and_sums_up_its_findings() {
    let tmp = TempDir::new("finger-validity");
    let scene = tmp.0.join("far.toml");
    std::fs::write(
        &scene,
        "[actuator.pemc]\neps0 = 0.9\n[load]\npressure_kpa = 100\n[solve]\nstability = true\n",
    )
    .unwrap();
    let out = run_ok(fpc().arg("solve").arg(&scene).arg("--out").arg(&tmp.0));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("\nstability      0 negative"), "{stdout}");
    assert!(
        stdout.contains("\nvalidity       OUTSIDE the model's limits"),
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.0.join("solution.json")).unwrap()).unwrap();
    let kinds: Vec<&str> = json["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["kind"].as_str().unwrap())
        .collect();
    let slopes = kinds.iter().filter(|k| **k == "element_slope").count();
    assert!(slopes > 2, "{kinds:?}");
    let stderr = text(&out.stderr);
    let slope_lines: Vec<&str> = stderr.lines().filter(|l| l.contains("degrees")).collect();
    assert_eq!(slope_lines.len(), 1, "{stderr}");
    assert!(
        slope_lines[0].contains(&format!("the worst of {slopes} element_slope findings")),
        "{stderr}"
    );
    // the worst is the largest turn of all
    let worst = json["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["kind"] == "element_slope")
        .map(|w| w["value"].as_f64().unwrap())
        .fold(0.0, f64::max);
    assert!(
        slope_lines[0].contains(&format!("turns {worst:.1} degrees")),
        "{stderr}"
    );

    let plain = run_ok(
        fpc()
            .arg("solve")
            .arg(scenes_dir().join("pressurised.toml"))
            .arg("--out")
            .arg(tmp.0.join("p")),
    );
    assert!(text(&plain.stdout).contains("\nvalidity       within the model's limits"));
}

#[test]
fn a_calibration_covariance_gives_error_bars_and_none_leaves_the_output_alone() {
    let dir = TempDir::new("errbars");
    let base = "[actuator.pemc]\neps0 = 0.25\n[load]\npressure_kpa = 40.0\nkappa = 2.5\n[partition]\nelements = 4\n";
    let calibration = "[calibration]\nparameters = [\"actuator.pemc.eps0\", \"load.kappa\"]\ncovariance = [[1e-6, -7.5e-6], [-7.5e-6, 0.000625]]\n";
    let with = solve_text(dir.0.as_path(), "with", &format!("{base}{calibration}"));
    let without = solve_text(dir.0.as_path(), "without", base);
    let u = &with.json["uncertainty"];
    assert_eq!(u["method"], "first_order");
    assert_eq!(u["parameters"][1], "load.kappa");
    let tip = u["tip_mm"].as_array().unwrap();
    assert!(tip.iter().all(|s| s.as_f64().unwrap() > 0.0), "{u}");
    assert!(u["end_angle_rad"].as_f64().unwrap() > 0.0);
    assert!(u["radius_mm"].as_f64().unwrap() > 0.0, "{u}");
    assert!(u.get("radius_unavailable").is_none(), "{u}");
    assert!(without.json.get("uncertainty").is_none());
    // the table changes nothing that is solved
    assert_eq!(with.json["tip_mm"], without.json["tip_mm"]);
    assert_eq!(with.csv, without.csv);

    let o = run_ok(
        fpc()
            .arg("solve")
            .arg(dir.0.join("with.toml"))
            .arg("--out")
            .arg(dir.0.join("again")),
    );
    let stdout = text(&o.stdout);
    assert!(stdout.contains("tip +- 1 sd    X +- "), "{stdout}");
    assert!(stdout.contains("radius +- 1 sd +- "), "{stdout}");
    let o = run_ok(
        fpc()
            .arg("solve")
            .arg(dir.0.join("without.toml"))
            .arg("--out")
            .arg(dir.0.join("again2")),
    );
    assert!(!text(&o.stdout).contains("uncertainty"));

    // a covariance that is not positive semi-definite is rejected, named
    let bad = dir.0.join("bad.toml");
    std::fs::write(
        &bad,
        format!("{base}[calibration]\nparameters = [\"actuator.pemc.eps0\", \"load.kappa\"]\ncovariance = [[1e-4, 1e-2], [1e-2, 1e-2]]\n"),
    )
    .unwrap();
    let o = fpc()
        .arg("solve")
        .arg(&bad)
        .arg("--out")
        .arg(dir.0.join("bad"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("calibration.covariance"),
        "{}",
        text(&o.stderr)
    );
}
