//! `fpc design`: the JSON keys, the files written, the scenes that
//! reproduce the claimed grasps, and requirements errors with their line.

use common::fpc;
use tempfile::TempDir;

mod common;

/// A fresh scratch directory, removed when dropped.
fn tmp(name: &str) -> TempDir {
    common::tmp("design", name)
}

/// `fpc design` on the requirements `text` (written into `scratch`) with
/// one start and `extra` flags, into `<scratch>/out`; it must succeed.
fn design(scratch: &TempDir, text: &str, extra: &[&str]) -> std::process::Output {
    let dir = scratch.path();
    let req = dir.join("req.toml");
    std::fs::write(&req, text).unwrap();
    let out = dir.join("out");
    let mut args = vec![
        "design",
        req.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--starts",
        "0",
    ];
    args.extend_from_slice(extra);
    let o = fpc(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

#[test]
fn a_design_run_writes_its_claim_and_reproducible_scenes() {
    let scratch = tmp("run");
    let o = design(
        &scratch,
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [80.0, 100.0]\nlift_n = 0.3\n[vary]\nmounting_angle_deg = [60.0, 80.0]\n",
        &["--json"],
    );
    let dir = scratch.path();
    let out = dir.join("out");
    // a run that ends within the first 2 s writes no progress: a log of
    // a successful quick run stays empty
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
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

/// A request no design meets: its text names the requirement that kept
/// each object from a claimed grasp, and says what the scene confirms.
#[test]
fn an_infeasible_design_says_why_its_scene_claims_no_grasp() {
    let scratch = tmp("infeasible");
    let o = design(
        &scratch,
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [150.0, 150.0]\nlift_n = 5.0\n[vary]\neps0 = [0.1, 0.5]\nmounting_angle_deg = [60.0, 90.0]\n",
        &[],
    );
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("NO design meets every requirement"), "{text}");
    let scene = text.lines().find(|l| l.starts_with("scene ")).unwrap();
    assert!(
        scene.contains("fpc solve confirms no valid grasp: object[0] cuboid d = 150.0 mm: fits"),
        "{scene}"
    );
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
    let err = String::from_utf8_lossy(&o.stderr);
    // the line and column of the value, as a syntax error has them
    assert!(err.contains(":4:10: object[0].lift_n = -1: "), "{err}");
}

/// The one line of a rejected run (exit 2), with nothing written.
fn rejected(req: &std::path::Path, out: &std::path::Path) -> String {
    let o = fpc(&[
        "design",
        req.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    assert!(o.stdout.is_empty(), "{o:?}");
    assert!(!out.exists(), "{}", out.display());
    let err = String::from_utf8(o.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    err
}

/// Line and column (from 1) of the first `what` in `text`, found by hand.
fn position_of(text: &str, what: &str) -> (usize, usize) {
    let at = text.find(what).unwrap();
    let line = text[..at].matches('\n').count() + 1;
    let col = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, col)
}

/// The audit's example files, changed as it did: a width of 1e308, a lift
/// of 1e-320. Each is refused with the key, its line and column, and the
/// bound, in the form of a scene's value error (`FILE:LINE:COL: key =
/// value: rule`); no NaN or inf is written.
#[test]
fn out_of_range_requirements_are_refused_at_their_line() {
    let scratch = tmp("range");
    let dir = scratch.path();
    let root = env!("CARGO_MANIFEST_DIR");
    for (file, from, to, value, key) in [
        (
            "infeasible.toml",
            "size_mm = [140.0, 150.0]",
            "size_mm = [140.0, 1e308]",
            "1e308",
            "object[0].size_mm[1] = 1e308",
        ),
        (
            "fragile_fruit.toml",
            "lift_n = 0.35",
            "lift_n = 1e-320",
            "1e-320",
            "object[0].lift_n = 1e-320",
        ),
    ] {
        let text = std::fs::read_to_string(format!("{root}/../../scenes/design/{file}")).unwrap();
        assert!(text.contains(from), "{file}");
        let changed = text.replacen(from, to, 1);
        let req = dir.join(file);
        std::fs::write(&req, &changed).unwrap();
        let err = rejected(&req, &dir.join("out"));
        let (line, col) = position_of(&changed, value);
        assert!(
            err.contains(&format!("{file}:{line}:{col}: {key}: must lie in [")),
            "{err}"
        );
        assert!(!err.contains("NaN") && !err.contains("inf "), "{err}");
    }
}

/// A value error names the key with a space after the position, as a
/// scene's does; too many objects are refused at once, at the first table
/// past the bound.
#[test]
fn value_errors_read_as_scene_errors_and_objects_are_bounded() {
    let scratch = tmp("value");
    let dir = scratch.path();
    let req = dir.join("req.toml");
    let object = "[[object]]\nkind = \"cuboid\"\nsize_mm = [80.0, 100.0]\nlift_n = 0.3\n";
    let vary = "[vary]\nmounting_angle_deg = [60.0, 80.0]\n";
    std::fs::write(&req, format!("fingers = 0\n{object}{vary}")).unwrap();
    let err = rejected(&req, &dir.join("out"));
    assert!(
        err.contains("req.toml:1:11: fingers = 0: must lie in [2, 12]"),
        "{err}"
    );
    // no key to point at: the file, then the message
    std::fs::write(&req, vary).unwrap();
    let err = rejected(&req, &dir.join("out"));
    assert!(err.contains("req.toml: object = 0: "), "{err}");
    // 2000 objects: refused before any work (the run took over a minute)
    let text = format!("{}{vary}", object.repeat(2000));
    std::fs::write(&req, &text).unwrap();
    let started = std::time::Instant::now();
    let err = rejected(&req, &dir.join("out"));
    assert!(started.elapsed().as_secs() < 10, "{:?}", started.elapsed());
    // four lines per table: the 33rd starts at line 129
    assert!(
        err.contains("req.toml:129:1: object = 2000: at most 32 [[object]] tables"),
        "{err}"
    );
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

/// Ctrl-C (one SIGINT) during a long design: nothing is written (a design
/// is reported only once found and checked), a note says so, the status
/// is 130, and the command ends soon after (the solves not yet started
/// fail at once).
#[cfg(unix)]
#[test]
fn ctrl_c_stops_a_design_and_writes_nothing() {
    use std::io::Read as _;
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let scratch = tmp("ctrl_c");
    let out = scratch.path().join("out");
    let req = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/design/paper_sec5.toml"
    );
    let mut command = common::fpc_as_in_a_terminal();
    // 10 000 random starts: far longer than the wait below, even in a
    // release build (each start is one evaluation of every margin)
    let mut child = command
        .args(["design", req, "--starts", "10000", "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // the output directory is made just before Ctrl-C is armed
    let t = Instant::now();
    while !out.is_dir() {
        assert!(t.elapsed() < Duration::from_secs(60), "no output directory");
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(300));
    common::ctrl_c(&child);
    let stopped = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if stopped.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            panic!("fpc design went on for 2 minutes after Ctrl-C");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    assert_eq!(status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("fpc: Ctrl-C: stopping; nothing is written"),
        "{stderr}"
    );
    assert!(
        stderr.contains("stopped by Ctrl-C before the design was found; nothing written"),
        "{stderr}"
    );
    assert!(!stderr.contains("error"), "{stderr}");
    let written: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
    assert!(written.is_empty(), "{written:?}");
}

/// A search longer than 2 s says how far it has got on stderr also when
/// stderr is a log (not a terminal): whole lines with the starts screened
/// of all, the evaluations and the best worst margin so far; Ctrl-C
/// still stops it with status 130.
#[cfg(unix)]
#[test]
fn a_long_design_writes_its_progress_into_a_log_and_still_stops_at_ctrl_c() {
    use std::io::BufRead as _;
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let scratch = tmp("progress");
    let out = scratch.path().join("out");
    let req = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/design/paper_sec5.toml"
    );
    let started = Instant::now();
    let mut child = common::fpc_as_in_a_terminal()
        .args(["design", req, "--starts", "10000", "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(stderr).lines() {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let first = rx.recv_timeout(Duration::from_secs(120));
    let waited = started.elapsed();
    let Ok(first) = first else {
        let _ = child.kill();
        panic!("no progress line in 2 minutes: {first:?}");
    };
    common::ctrl_c(&child);
    let status = child.wait().unwrap();
    let rest: Vec<String> = rx.iter().collect();
    // nothing in the first 2 s
    assert!(waited >= Duration::from_secs(2), "{waited:?}: {first}");
    // the centre, 4 corners and 10 000 random starts
    let (done, rest_of_line) = first
        .strip_prefix("fpc design: screening starts ")
        .and_then(|t| t.split_once("/10005; "))
        .unwrap_or_else(|| panic!("{first}"));
    let done: usize = done.parse().unwrap_or_else(|_| panic!("{first}"));
    assert!(done <= 10005, "{first}");
    let (evaluations, best) = rest_of_line
        .split_once(" evaluations; best worst margin ")
        .unwrap_or_else(|| panic!("{first}"));
    assert_eq!(evaluations.parse::<usize>().ok(), Some(done), "{first}");
    assert!(
        best == "none yet" || best.parse::<f64>().is_ok_and(f64::is_finite),
        "{first}"
    );
    assert_eq!(status.code(), Some(130), "{first}\n{rest:?}");
    assert!(
        rest.iter()
            .any(|l| l.contains("stopped by Ctrl-C before the design was found")),
        "{rest:?}"
    );
}

#[test]
fn help_states_vary_is_required_and_the_element_range() {
    let out = fpc(&["design", "--help"]);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(help.contains("`[vary]` is required"), "{help}");
    assert!(help.contains("`elements` lies in [1, 256]"), "{help}");
}
