//! `fpc compare`: the shipped synthetic set writes its CSV, JSON and
//! figures; bad measurement input exits with status 2 and one line naming
//! file:row:col and the field.

mod common;

use std::path::Path;

use common::{fails, fpc, shipped, text};
use tempfile::TempDir;

fn tmp(name: &str) -> TempDir {
    common::tmp("compare", name)
}

#[test]
fn the_synthetic_set_is_compared_into_csv_json_and_figures() {
    let dir = tmp("run");
    let out = dir.path();
    let o = out.display().to_string();
    let run = fpc(&["compare", &shipped(), "--out", &o, "--format", "svg,png"]);
    let stdout = text(&run.stdout);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    assert!(stdout.contains("total        chi2 "), "{stdout}");
    for f in [
        "compare.csv",
        "compare.json",
        "compare_radius.svg",
        "compare_radius.png",
        "compare_force.svg",
        "compare_force.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing; {stdout}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("compare.json")).unwrap()).unwrap();
    assert_eq!(json["specimens"].as_array().unwrap().len(), 3);
    assert!(json["provenance"]["fpc_version"].is_string());
    let points = json["points"].as_u64().unwrap();
    // the CSV has one line per residual, and the JSON's chi-square is the
    // sum of their squares in standard deviations
    let csv = std::fs::read_to_string(out.join("compare.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let z = header.iter().position(|h| *h == "residual_sd").unwrap();
    let zs: Vec<f64> = lines
        .map(|l| l.split(',').nth(z).unwrap().parse().unwrap())
        .collect();
    assert_eq!(zs.len() as u64, points);
    let chi: f64 = zs.iter().map(|z| z * z).sum();
    let claimed = json["chi_square"].as_f64().unwrap();
    assert!(
        (chi - claimed).abs() <= 1e-6 * claimed,
        "{chi} vs {claimed}"
    );
    // --json prints the same object
    let j = fpc(&["compare", &shipped(), "--out", &o, "--json"]);
    let printed: serde_json::Value = serde_json::from_slice(&j.stdout).unwrap();
    assert_eq!(printed["chi_square"], json["chi_square"]);
    // that run asked for SVG only: the first run's PNGs are gone
    assert!(!out.join("compare_radius.png").exists());
    assert!(!out.join("compare_force.png").exists());
    // a manifest without force tests, into the same directory: no force
    // figure of the earlier run is left beside its own
    let radius = tmp("radius-only");
    let m = one_radius_test(radius.path());
    std::fs::write(
        radius.path().join("r.csv"),
        "pressure_kpa,radius_mm,sd_mm\n0,68,1\n",
    )
    .unwrap();
    let again = fpc(&["compare", &m, "--out", &o]);
    assert_eq!(again.status.code(), Some(0), "{}", text(&again.stderr));
    assert!(out.join("compare_radius.svg").is_file());
    assert!(!out.join("compare_force.svg").exists());
}

/// A manifest `m.toml` in `d` of one specimen with one radius test,
/// `r.csv` (written by the caller); its path.
fn one_radius_test(d: &Path) -> String {
    std::fs::write(
        d.join("m.toml"),
        "[[specimen]]\nname = \"a\"\n[[specimen.test]]\nkind = \"radius\"\nfile = \"r.csv\"\n",
    )
    .unwrap();
    d.join("m.toml").display().to_string()
}

#[test]
fn bad_measurements_exit_2_naming_file_row_column_and_field() {
    let dir = tmp("bad");
    let d = dir.path();
    let m = one_radius_test(d);
    let r = d.join("r.csv").display().to_string();
    for (csv, place) in [
        (
            "pressure_kpa,radius_mm,sd_mm\n10,NaN,1\n",
            ":2:2: radius_mm: ",
        ),
        ("pressure_kpa,radius_mm,sd_mm\n10,50,-2\n", ":2:3: sd_mm: "),
        (
            "pressure_kpa,radius_mm\n10,50\n",
            ":1:3: sd_mm: missing column",
        ),
        (
            "pressure_kpa,radius_mm,sd_mm\n-300,50,1\n",
            ":2:1: pressure_kpa: ",
        ),
        (
            "pressure_kpa,radius_mm,sd_mm\n10,50,1\n10,51,1\n",
            ":3:1: pressure_kpa: duplicates row 2",
        ),
    ] {
        std::fs::write(d.join("r.csv"), csv).unwrap();
        let line = fails(
            &["compare", &m, "--out", &d.join("out").display().to_string()],
            2,
        );
        assert!(line.contains(&format!("{r}{place}")), "{line}");
    }
    // a manifest that is not one
    std::fs::write(d.join("m.toml"), "[[specimen]]\nname = 3\n").unwrap();
    let line = fails(&["compare", &m], 2);
    assert!(line.contains(&format!("{m}:2:8: manifest: ")), "{line}");
}

/// A row the model cannot predict (its solve fails) is counted, with the
/// nouns in their counts' number, and the run still exits 0 with the other
/// rows compared.
#[test]
fn rows_without_a_prediction_are_counted_in_words() {
    let dir = tmp("failed");
    let d = dir.path();
    let m = one_radius_test(d);
    let o = d.join("out").display().to_string();
    for (rows, count, failed) in [
        (
            "5000,50,1\n",
            "; 1 row without a prediction",
            "; 1 without a prediction",
        ),
        (
            "5000,50,1\n6000,50,1\n",
            "; 2 rows without a prediction",
            "; 2 without a prediction",
        ),
    ] {
        std::fs::write(
            d.join("r.csv"),
            format!("pressure_kpa,radius_mm,sd_mm\n10,40,1\n{rows}"),
        )
        .unwrap();
        let run = fpc(&["compare", &m, "--out", &o]);
        assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
        let stdout = text(&run.stdout);
        let total = stdout.lines().find(|l| l.starts_with("total")).unwrap();
        assert!(
            total.contains("over 1 residual (") && total.ends_with(count),
            "{total}"
        );
        // the test's own line: one residual, and how many rows failed
        let line = stdout.lines().find(|l| l.contains("r.csv")).unwrap();
        assert!(
            line.contains("over   1 residual;") && line.ends_with(failed),
            "{line}"
        );
    }
}
