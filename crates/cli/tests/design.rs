//! `fpc design`: the JSON keys, the files written, the scenes that
//! reproduce the claimed grasps, and requirements errors with their line.

use std::process::Command;

use tempfile::TempDir;

fn fpc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
        .args(args)
        .output()
        .unwrap()
}

/// A fresh scratch directory, removed when dropped.
fn tmp(name: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("fpc-design-{name}-"))
        .tempdir()
        .unwrap()
}

#[test]
fn a_design_run_writes_its_claim_and_reproducible_scenes() {
    let scratch = tmp("run");
    let dir = scratch.path();
    let req = dir.join("req.toml");
    std::fs::write(
        &req,
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [80.0, 100.0]\nlift_n = 0.3\n[vary]\nmounting_angle_deg = [60.0, 80.0]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = fpc(&[
        "design",
        req.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
        "--starts",
        "0",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for key in [
        "feasible",
        "design",
        "margins",
        "scenes",
        "sensitivities",
        "provenance",
    ] {
        assert!(v.get(key).is_some(), "no {key} in {v}");
    }
    assert_eq!(v["feasible"], true);
    assert_eq!(
        v["design"]["varied"],
        serde_json::json!(["mounting_angle_deg"])
    );
    // each sensitivity names the variable it is taken by, as the design
    // names its variables
    for s in v["sensitivities"].as_array().unwrap() {
        let g = s["gradient"].as_object().expect("a named gradient");
        let mut names: Vec<&str> = g.keys().map(String::as_str).collect();
        names.sort_unstable();
        assert_eq!(names, ["eps0", "mounting_angle_deg", "overlap_mm"], "{s}");
        assert!(g.values().all(|x| x.as_f64().is_some_and(f64::is_finite)));
    }
    let scenes = v["scenes"].as_array().unwrap();
    assert_eq!(scenes.len(), 1);
    assert_eq!(scenes[0]["reproduced"], true, "{}", scenes[0]);
    for f in ["design.json", "design.svg", "object0_cuboid.toml"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    // the scene file runs with fpc solve, and gives the claimed lift
    let s = fpc(&[
        "solve",
        out.join("object0_cuboid.toml").to_str().unwrap(),
        "--out",
        dir.join("solve").to_str().unwrap(),
    ]);
    assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
    let sol: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("solve/solution.json")).unwrap())
            .unwrap();
    let claimed = scenes[0]["claimed_lift_n"].as_f64().unwrap();
    let solved = sol["grasp"]["lift_n"].as_f64().unwrap();
    assert!((claimed - solved).abs() <= 1e-6 * claimed);
    let svg = std::fs::read_to_string(out.join("design.svg")).unwrap();
    assert!(svg.starts_with("<svg") && !svg.contains("NaN"));
}

#[test]
fn bad_requirements_are_rejected_with_their_place() {
    let scratch = tmp("bad");
    let dir = scratch.path();
    let req = dir.join("req.toml");
    std::fs::write(
        &req,
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [80.0, 100.0]\nlift = 0.3\n",
    )
    .unwrap();
    let o = fpc(&[
        "design",
        req.to_str().unwrap(),
        "--out",
        dir.join("o").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains(":4:1:") && err.contains("lift"), "{err}");
    std::fs::write(&req, "[[object]]\nkind = \"cuboid\"\nsize_mm = [80.0, 100.0]\nlift_n = -1\n[vary]\neps0 = [0.1, 0.2]\n").unwrap();
    let o = fpc(&[
        "design",
        req.to_str().unwrap(),
        "--out",
        dir.join("o").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("object[0].lift_n"));
}

#[test]
fn design_takes_its_finger_from_a_scene_and_rejects_a_bad_one() {
    let scratch = tmp("scene");
    let dir = scratch.path();
    let req = dir.join("req.toml");
    std::fs::write(
        &req,
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [80.0, 100.0]\nlift_n = 0.3\n[vary]\nmounting_angle_deg = [60.0, 80.0]\n",
    )
    .unwrap();
    let scene = dir.join("finger.toml");
    std::fs::write(
        &scene,
        "[actuator.pemc]\neps0 = 0.35\n[actuator.cl]\ne = 350.0\n",
    )
    .unwrap();
    let out = dir.join("out");
    let args = |scene: &std::path::Path| {
        fpc(&[
            "design",
            req.to_str().unwrap(),
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--starts",
            "0",
        ])
    };
    let o = args(&scene);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("eps0 = 0.3500"), "{text}");
    assert!(
        text.contains("note           the finger is the scene"),
        "{text}"
    );
    let written = std::fs::read_to_string(out.join("object0_cuboid.toml")).unwrap();
    assert!(written.contains("e = 350.0"), "{written}");
    // a scene with an unknown key: rejected with its file and line, exit 2
    std::fs::write(&scene, "[actuator.pemc]\neps00 = 0.35\n").unwrap();
    let o = args(&scene);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("finger.toml:2"), "{err}");
}
