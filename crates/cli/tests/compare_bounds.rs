//! `fpc compare` on the input of a fuzzing audit: absurd measurements
//! (an sd of 1e308 once made the figure spin forever, a tiny one printed a
//! chi-square of inf) exit 2 at once naming file:row:col and the column; a
//! bad shared scene value is named at its key; a run in which the model
//! predicted no row exits 1; nothing written holds inf or NaN.

mod common;

use std::path::Path;
use std::process::Output;
use std::time::Duration;

use common::{fails, fpc_within, text};

/// `fpc args`, killed and failed when it runs longer than a minute.
fn fpc_within_a_minute(args: &[&str]) -> Output {
    fpc_within(args, Duration::from_secs(60))
}

/// `m.toml` of one specimen with one radius test, `r.csv` holding `csv`,
/// in `d`: the manifest's path.
fn radius_test(d: &Path, csv: &str) -> String {
    std::fs::write(
        d.join("m.toml"),
        "[[specimen]]\nname = \"a\"\n[[specimen.test]]\nkind = \"radius\"\nfile = \"r.csv\"\n",
    )
    .unwrap();
    std::fs::write(d.join("r.csv"), csv).unwrap();
    d.join("m.toml").display().to_string()
}

fn no_number_that_is_not_one(what: &str, s: &str) {
    for word in ["inf", "NaN"] {
        assert!(
            !s.split(|c: char| !c.is_ascii_alphanumeric())
                .any(|w| w.eq_ignore_ascii_case(word)),
            "{what} holds {word}: {s}"
        );
    }
}

#[test]
fn absurd_measurements_exit_2_at_once_naming_the_cell() {
    let dir = common::tmp("compare_bounds", "absurd");
    let d = dir.path();
    let out = d.join("out").display().to_string();
    for (row, col, field) in [
        ("0,39.3776,1e308", 3, "sd_mm"),
        ("0,39.3776,1e-200", 3, "sd_mm"),
        ("0,1e308,1.3", 2, "radius_mm"),
        ("1e308,39.3776,1.3", 1, "pressure_kpa"),
    ] {
        let csv = format!("pressure_kpa,radius_mm,sd_mm\n{row}\n25,41.8828,1.343\n");
        let m = radius_test(d, &csv);
        let run = fpc_within_a_minute(&["compare", &m, "--out", &out]);
        let (stdout, stderr) = (text(&run.stdout), text(&run.stderr));
        assert_eq!(run.status.code(), Some(2), "{row}: {stderr}");
        assert!(stdout.is_empty(), "{row}: {stdout}");
        assert_eq!(stderr.lines().count(), 1, "{row}: {stderr}");
        let place = format!("r.csv:2:{col}: {field}: ");
        assert!(stderr.contains(&place), "{row}: {stderr} lacks {place}");
    }
}

#[test]
fn a_bad_shared_value_is_named_at_its_key() {
    let dir = common::tmp("compare_bounds", "shared");
    let d = dir.path();
    std::fs::write(d.join("r.csv"), "pressure_kpa,radius_mm,sd_mm\n0,40,1\n").unwrap();
    std::fs::write(
        d.join("m.toml"),
        "[shared.actuator.pemc]\ne2 = \"abc\"\n[[specimen]]\nname = \"a\"\n[[specimen.test]]\nkind = \"radius\"\nfile = \"r.csv\"\n",
    )
    .unwrap();
    let m = d.join("m.toml").display().to_string();
    let line = fails(
        &["compare", &m, "--out", &d.join("out").display().to_string()],
        2,
    );
    let place = format!("{m}:2:6: shared.actuator.pemc.e2: ");
    assert!(line.contains(&place), "{line} lacks {place}");
}

/// Rows measured and not one predicted (every solve fails at these
/// pressures): the files say why for each row, and the run fails with
/// one line naming the first; a run with a row predicted, or with no row
/// to predict, succeeds.
#[test]
fn a_run_that_predicts_no_row_fails() {
    let dir = common::tmp("compare_bounds", "none");
    let d = dir.path();
    let out = d.join("out");
    let o = out.display().to_string();
    let m = radius_test(d, "pressure_kpa,radius_mm,sd_mm\n5000,50,1\n6000,50,1\n");
    let line = fails(&["compare", &m, "--out", &o], 1);
    assert!(line.contains("none of the 2 measured rows"), "{line}");
    assert!(line.contains("r.csv:2: "), "{line}");
    no_number_that_is_not_one("the error", &line);
    for f in ["compare.csv", "compare.json"] {
        let written = std::fs::read_to_string(out.join(f)).unwrap();
        no_number_that_is_not_one(f, &written);
    }
    let csv = std::fs::read_to_string(out.join("compare.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "{csv}");
    for (rows, what) in [
        ("0,40,1\n5000,50,1\n", "one predicted"),
        ("", "none measured"),
    ] {
        let m = radius_test(d, &format!("pressure_kpa,radius_mm,sd_mm\n{rows}"));
        let run = common::fpc(&["compare", &m, "--out", &o]);
        assert_eq!(run.status.code(), Some(0), "{what}: {}", text(&run.stderr));
        assert!(run.stderr.is_empty(), "{what}: {}", text(&run.stderr));
    }
}

/// The widest error bars and smallest sds accepted: the run ends, and its
/// summary, CSV, JSON and figure hold finite numbers only.
#[test]
fn the_limits_give_finite_output() {
    let dir = common::tmp("compare_bounds", "limits");
    let d = dir.path();
    let out = d.join("out");
    let m = radius_test(
        d,
        "pressure_kpa,radius_mm,sd_mm\n0,39.3776,1e5\n25,1e5,1e-6\n50,1e-3,1e-6\n",
    );
    let run = fpc_within_a_minute(&["compare", &m, "--out", &out.display().to_string()]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    no_number_that_is_not_one("stdout", &text(&run.stdout));
    for f in ["compare.csv", "compare.json", "compare_radius.svg"] {
        let written = std::fs::read_to_string(out.join(f)).unwrap();
        no_number_that_is_not_one(f, &written);
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("compare.json")).unwrap()).unwrap();
    assert!(json["chi_square"].is_f64(), "{}", json["chi_square"]);
    assert_eq!(json["points"], 3);
}
