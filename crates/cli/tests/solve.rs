//! `fpc solve` on the example scenes and on bad scenes.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fpc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
}

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// A fresh, empty directory under the system's temporary directory,
/// removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("fpc-solve-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn text(o: &[u8]) -> String {
    String::from_utf8_lossy(o).into_owned()
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

#[test]
fn every_example_scene_solves_and_writes_its_files() {
    let tmp = TempDir::new("examples");
    for scene in example_scenes() {
        let stem = scene.file_stem().unwrap().to_string_lossy().into_owned();
        let out = tmp.0.join(&stem);
        let o = run_ok(fpc().arg("solve").arg(&scene).arg("--out").arg(&out));
        let stdout = text(&o.stdout);
        assert!(stdout.contains("wrote"), "{stem}: {stdout}");

        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap())
                .unwrap_or_else(|e| panic!("{stem}: solution.json: {e}"));
        for key in [
            "tip_mm",
            "end_angle_rad",
            "radius_mm",
            "energy_nmm",
            "negative_eigenvalues",
            "stable",
            "coefficients",
            "points_mm",
            "report",
            "elements",
            "scene",
            "kind",
        ] {
            assert!(json.get(key).is_some(), "{stem}: no {key}");
        }
        assert_eq!(json["scene_name"], stem.as_str());
        let tip = json["tip_mm"].as_array().unwrap();
        assert!(
            tip.iter().all(|v| v.as_f64().unwrap().is_finite()),
            "{stem}"
        );
        // the echo spells out the defaults
        assert!(
            json["scene"]["actuator"]["geometry"]["lx"].is_number(),
            "{stem}"
        );

        let csv = std::fs::read_to_string(out.join("shape.csv")).unwrap();
        let mut lines = csv.lines();
        let header = lines.next().unwrap();
        let grasp = json["kind"] == "grasp";
        if grasp {
            assert_eq!(header, "x_mm,z_mm,xg_mm,zg_mm", "{stem}");
            let g = &json["grasp"];
            for key in [
                "normal_force_n",
                "friction_n",
                "lift_n",
                "size_mm",
                "tip_gap_mm",
                "height_mm",
                "valid",
            ] {
                assert!(g.get(key).is_some(), "{stem}: no grasp.{key}");
            }
            assert_eq!(g["valid"], true, "{stem}");
        } else {
            assert_eq!(header, "x_mm,z_mm", "{stem}");
        }
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        assert_eq!(
            rows.len(),
            json["points_mm"].as_array().unwrap().len(),
            "{stem}"
        );
        assert!(rows.iter().all(|r| r.len() == header.split(',').count()));

        let svg = std::fs::read_to_string(out.join("shape.svg")).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"),
            "{stem}"
        );
        assert!(svg.contains("<polyline"), "{stem}");
        if grasp {
            assert!(
                svg.contains("<polygon") || svg.contains("<circle cx"),
                "{stem}"
            );
        }
        // written atomically: no temporary file left behind
        for e in std::fs::read_dir(&out).unwrap() {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(!name.ends_with(".tmp"), "{stem}: {name}");
        }
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
