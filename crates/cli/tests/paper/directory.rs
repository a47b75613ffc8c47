//! Where a run writes and what it refuses before writing: a nested
//! directory made, a file refused as the directory, an element count
//! beyond the bound refused, and two runs into one directory.

use std::path::Path;

use serde_json::Value;

use super::{assert_complete, fpc, tmp};

#[test]
fn paper_creates_nested_output_directory() {
    let base = tmp("nested");
    let dir = base.path().join("a").join("b");
    let out = fpc()
        .args(["paper", "--coarse", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("summary.json").is_file());
    let s: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["options"]["coarse"], Value::Bool(true));
}

#[test]
fn paper_rejects_a_file_as_output_directory() {
    let scratch = tmp("file");
    let base = scratch.path();
    let file = base.join("not-a-dir");
    std::fs::write(&file, "keep me").unwrap();
    let out = fpc()
        .args(["paper", "--coarse", "--out"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert_eq!(out.status.code(), Some(2), "an input error");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("not a directory"),
        "unclear message: {stderr}"
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep me");
    assert_eq!(std::fs::read_dir(base).unwrap().count(), 1);
}

/// An element count beyond a study's bound is refused before any study
/// runs, under the flag's name (it used to run all eight studies, each
/// failing on `partition.n`), and nothing is written.
#[test]
fn paper_rejects_too_many_elements_before_any_work() {
    let scratch = tmp("elements");
    let out_dir = scratch.path().join("out");
    for n in ["0", "100000"] {
        let out = fpc()
            .args(["paper", "--coarse", "--elements", n, "--out"])
            .arg(&out_dir)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "an input error");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains(&format!("--elements = {n}: must lie in [1, 1000]")),
            "{stderr}"
        );
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(!out_dir.exists());
    }
}

#[test]
fn two_runs_into_one_directory_both_succeed() {
    use std::os::unix::fs::PermissionsExt as _;
    use std::time::{Duration, SystemTime};
    let scratch = tmp("concurrent");
    let dir = scratch.path();
    // a temporary file of a run killed an hour ago, one of a live run, and
    // a file that is none of fpc's business
    let hour_ago = SystemTime::now() - Duration::from_secs(3600);
    std::fs::File::create(dir.join(".fpc-tmp-killed.tmp"))
        .unwrap()
        .set_modified(hour_ago)
        .unwrap();
    std::fs::write(dir.join(".fpc-tmp-live.tmp"), "").unwrap();
    std::fs::File::create(dir.join(".keep"))
        .unwrap()
        .set_modified(hour_ago)
        .unwrap();

    let run = || {
        fpc()
            .args(["paper", "--coarse", "--out"])
            .arg(dir)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (run(), run());
    for child in [a, b] {
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{:?}: {stderr}", out.status);
        assert!(stderr.is_empty(), "{stderr}");
        assert!(String::from_utf8_lossy(&out.stdout).starts_with("fpc paper: 20 files in "));
    }
    assert_complete(dir);

    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    names.sort();
    assert_eq!(
        names,
        [".fpc-tmp-live.tmp", ".keep"],
        "stale removed, the rest kept"
    );

    // the files get the mode a plain File::create gets (not 0600)
    let probe = dir.join("probe");
    std::fs::File::create(&probe).unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&dir.join("summary.json")), mode(&probe));
}

#[test]
fn a_scene_partition_the_studies_cannot_take_is_noted() {
    // tip_tol_mm refines a finger; the studies run on equal elements, so
    // the run says it does not use it (it ran 8 without a word)
    let base = tmp("partition-note");
    let dir = base.path().join("out");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/tip_load.toml");
    let out = fpc()
        .args(["paper", "--coarse", "--scene", scene, "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let note = stdout
        .lines()
        .find(|l| l.starts_with("note "))
        .unwrap_or_else(|| panic!("no note: {stdout}"));
    assert!(
        note.contains("[partition] (tip_tol_mm = 0.05) is not used"),
        "{note}"
    );
    assert!(note.contains("8 equal elements"), "{note}");
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let s: Value = serde_json::from_str(&text).unwrap();
    let notes = s["notes"].as_array().unwrap();
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert_eq!(
        notes[0].as_str().unwrap(),
        note.trim_start_matches("note").trim()
    );
    assert_eq!(s["options"]["elements"], 8);
}
