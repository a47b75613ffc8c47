//! `fpc-lab accuracy`: runs the built binary and checks what it writes. The
//! full configuration list takes half a minute in a debug build, so the
//! runs use the hidden `--quick` flag (the reduced list, 2 rounds of 3
//! runs) and no time budget.

use std::path::Path;
use std::process::{Command, Stdio};

use serde_json::Value;
use tempfile::TempDir;

use super::{lab, ok, text};

/// A fresh scratch directory, removed when dropped (a failed test's too).
fn tmp(name: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("fpc-lab-accuracy-{name}-"))
        .tempdir()
        .unwrap()
}

/// The stdout of `fpc-lab accuracy --quick --budget-ms 0 --out DIR` and
/// `extra` flags.
fn quick(dir: &Path, extra: &[&str]) -> String {
    let mut args = vec!["accuracy", "--quick", "--budget-ms", "0", "--out"];
    args.push(dir.to_str().unwrap());
    args.extend(extra);
    ok(&format!("{args:?}"), &lab(&args))
}

/// Rows per model of the reduced list.
const ROWS_PER_MODEL: usize = fpc_lab::QUICK_CONFIGURATIONS.len();

#[test]
fn accuracy_writes_csv_json_and_svg_and_prints_the_front() {
    let scratch = tmp("table");
    // not there yet: the run makes it
    let dir = scratch.path().join("out");
    let stdout = quick(&dir, &[]);
    for part in [
        "references: material partition, 27 -> 864 elements",
        "observed orders",
        "model gap: quad vs ccm",
        "t8 (ccm/equal/8x1, cold",
        "ccm/material/8x2+richardson",
        "fastest within 1 mm:",
        "fastest within 0.1 mm:",
        "fastest within 0.01 mm:",
    ] {
        assert!(stdout.contains(part), "no {part:?} in\n{stdout}");
    }

    let csv = std::fs::read_to_string(dir.join("accuracy.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for col in [
        "label",
        "model",
        "partition",
        "elements",
        "iterations_per_level",
        "error_vs_ccm_mm",
        "error_vs_own_mm",
        "estimated_error_mm",
        "time_us",
        "time_over_n8",
        "pareto",
    ] {
        assert!(header.contains(&col), "no column {col} in {header:?}");
    }
    let models = fpc_lab::study_models().len();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), ROWS_PER_MODEL * models);
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{r:?}");
        let e: f64 = r[at("error_vs_ccm_mm")].parse().unwrap();
        let t: f64 = r[at("time_us")].parse().unwrap();
        assert!(e.is_finite() && e >= 0.0 && t > 0.0, "{r:?}");
    }

    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("accuracy.json")).unwrap()).unwrap();
    assert_eq!(json["references"].as_array().unwrap().len(), models);
    assert_eq!(json["rows"].as_array().unwrap().len(), rows.len());
    assert_eq!(json["fastest"].as_array().unwrap().len(), 3);
    assert!(!json["front"].as_array().unwrap().is_empty());
    let u = json["references"][0]["uncertainty_mm"].as_f64().unwrap();
    assert!(u < 1e-4, "{u}");

    let svg = std::fs::read_to_string(dir.join("accuracy.svg")).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
    assert!(svg.contains("Pareto front") && svg.contains("ccm material + Richardson"));
    assert!(svg.contains("10⁻²"), "power-of-ten tick labels");
}

#[test]
fn accuracy_json_prints_the_study() {
    let scratch = tmp("json");
    // not there yet: the run makes it
    let dir = scratch.path().join("out");
    // the figure as PNG and PDF only (the rendering itself: fpc-cli's
    // tests/figures.rs)
    let stdout = quick(&dir, &["--json", "--format", "png,pdf"]);
    let printed: Value = serde_json::from_str(&stdout).unwrap();
    let written: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("accuracy.json")).unwrap()).unwrap();
    assert_eq!(printed, written);
    assert_eq!(printed["n8"]["label"], "ccm/equal/8x1");
    let png = std::fs::read(dir.join("accuracy.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
    let pdf = std::fs::read(dir.join("accuracy.pdf")).unwrap();
    assert!(pdf.starts_with(b"%PDF-"));
    assert!(!dir.join("accuracy.svg").exists());
}

#[test]
fn accuracy_rejects_bad_flags_and_a_broken_stdout_without_panicking() {
    let out = lab(&["accuracy", "--budget-ms", "-1"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("--budget-ms"));
    let out = lab(&["accuracy", "--format", "tiff"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("'tiff'"));

    // a file is not an output directory: rejected before any work
    let scratch = tmp("file");
    let dir = scratch.path();
    let file = dir.join("x");
    std::fs::write(&file, "x").unwrap();
    let out = lab(&["accuracy", "--out", file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(text(&out.stderr).contains("not a directory"));

    // stdout closed: status 1, no panic
    let out = Command::new("sh")
        .arg("-c")
        .arg("exec \"$0\" \"$@\" >&-")
        .arg(env!("CARGO_BIN_EXE_fpc-lab"))
        .args(["accuracy", "--quick", "--budget-ms", "0", "--out"])
        .arg(dir.join("out"))
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    assert!(!text(&out.stderr).contains("panicked"));
}

/// Progress into a log (stderr not a terminal): whole lines, the first at
/// once and then at most one every 5 s, no carriage-return redraws.
#[test]
fn accuracy_progress_in_a_log_is_a_few_whole_lines() {
    let scratch = tmp("progress");
    // not there yet: the run makes it
    let dir = scratch.path().join("out");
    let started = std::time::Instant::now();
    let out = lab(&[
        "accuracy",
        "--quick",
        "--budget-ms",
        "0",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let elapsed = started.elapsed().as_secs();
    let stderr = text(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains('\r'), "{stderr:?}");
    let lines = stderr
        .lines()
        .filter(|l| l.starts_with("fpc-lab accuracy: ") && l.ends_with(" steps"))
        .count();
    assert!(
        lines >= 1 && lines as u64 <= 1 + elapsed / 5,
        "{lines} progress lines in {elapsed} s:\n{stderr}"
    );
}
