//! Negative and special numbers given as a separate argument
//! (`--eps0 -inf`, `--fx -5`) are values, not flags: every numeric flag of
//! every subcommand hands them to its parser and validation instead of
//! clap reporting an "unexpected argument". And values far from 1
//! (`1e-300`, `1e300`) are written compactly and exactly wherever the CLI
//! shows them: `1e300`, not 301 digits; `1e-300`, not `0.0000`.

mod common;

use std::process::{Command, Output};

use common::{solve_into, TempDir};

fn fpc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
        .args(args)
        .output()
        .unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// `fpc args` exits 2 with one `fpc: error:` line containing `part`.
fn rejected_with(args: &[&str], part: &str) {
    let out = fpc(args);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "fpc {args:?}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "fpc {args:?}: {stderr}");
    assert!(stderr.starts_with("fpc: error: "), "fpc {args:?}: {stderr}");
    assert!(
        stderr.contains(part),
        "fpc {args:?}: {stderr} lacks {part:?}"
    );
    assert!(
        !stderr.contains("unexpected argument"),
        "fpc {args:?}: {stderr}"
    );
}

/// The floating-point flags of `fpc finger` and the name a rejection uses
/// (the flag itself: messages name what the user wrote).
const FINGER_FLOATS: [(&str, &str); 6] = [
    ("--eps0", "--eps0"),
    ("--pressure-kpa", "--pressure-kpa"),
    ("--fx", "--fx"),
    ("--fz", "--fz"),
    ("--kappa", "--kappa"),
    ("--tip-tol-mm", "--tip-tol-mm"),
];

#[test]
fn non_finite_values_reach_the_library_as_separate_arguments() {
    for (flag, field) in FINGER_FLOATS {
        for (v, shown) in [
            ("-inf", "-inf"),
            ("-infinity", "-inf"),
            ("inf", "inf"),
            ("nan", "NaN"),
            ("-nan", "NaN"),
            ("-NaN", "NaN"),
        ] {
            rejected_with(
                &["finger", flag, v],
                &format!("{field} = {shown}: must be finite"),
            );
        }
    }
    // --json after the value stays a flag
    rejected_with(
        &["finger", "--eps0", "-inf", "--json"],
        "--eps0 = -inf: must be finite",
    );
}

#[test]
fn negative_finite_values_reach_the_library() {
    // legal: solved, the value echoed in the summary
    for (args, echo) in [
        (&["finger", "--fx", "-5"][..], "tip force (-5, 0) N"),
        (&["finger", "--fz", "-5"][..], "tip force (0, -5) N"),
        (&["finger", "--pressure-kpa", "-5"][..], "P = -5 kPa"),
        (&["finger", "--eps0", "-0.1"][..], "eps0 = -0.1"),
    ] {
        let out = fpc(args);
        let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
        assert!(out.status.success(), "fpc {args:?}: {stderr}");
        assert!(stdout.contains(echo), "fpc {args:?}: {stdout}");
    }
    // eps0 < 0 is outside the fitted law: the library's warning
    let stderr = text(&fpc(&["finger", "--eps0", "-0.1"]).stderr);
    assert!(
        stderr.contains("fpc: warning: --eps0 = -0.1: outside [0, 0.6]"),
        "{stderr}"
    );
    // rejected by the library's rules
    rejected_with(
        &["finger", "--pressure-kpa", "-1e3"],
        // in the flag's unit (kPa), not the library's MPa
        "--pressure-kpa = -1000: is below absolute vacuum",
    );
    rejected_with(
        &["finger", "--kappa", "-1"],
        "--kappa = -1: must be positive",
    );
    rejected_with(
        &["finger", "--tip-tol-mm", "-1e-3"],
        "--tip-tol-mm = -0.001: must be positive",
    );
}

#[test]
fn negative_counts_reach_the_count_parser() {
    // a whole-number flag: clap's value parser says why, naming the flag
    // (the lab's flags: crates/lab/tests/commands)
    for v in ["-1", "-inf", "-nan"] {
        rejected_with(
            &["finger", "--elements", v],
            &format!("invalid value '{v}' for '--elements <"),
        );
    }
}

/// The longest line of a text, in characters: an extreme value written in
/// full would make it hundreds long.
fn longest_line(s: &str) -> usize {
    s.lines().map(|l| l.chars().count()).max().unwrap_or(0)
}

/// `fpc args` succeeds with empty stderr; its stdout.
fn quiet_success(args: &[&str]) -> String {
    let out = fpc(args);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "fpc {args:?}: {stderr}");
    assert_eq!(stderr, "", "fpc {args:?}");
    stdout
}

#[test]
fn the_finger_header_writes_extreme_values_compactly() {
    for (args, echo) in [
        (&["finger", "--fx", "1e-300"][..], "tip force (1e-300, 0) N"),
        (
            &["finger", "--fz", "-1e-300"][..],
            "tip force (0, -1e-300) N",
        ),
        (
            &["finger", "--pressure-kpa", "1e-300"][..],
            "P = 1e-300 kPa",
        ),
        (&["finger", "--eps0", "2.5e-200"][..], "eps0 = 2.5e-200,"),
        // ordinary values as before
        (&["finger", "--fx", "0.5"][..], "tip force (0.5, 0) N"),
        (&["finger", "--pressure-kpa", "120"][..], "P = 120 kPa"),
    ] {
        let stdout = quiet_success(args);
        assert!(stdout.contains(echo), "fpc {args:?}: {stdout}");
        assert!(longest_line(&stdout) < 120, "fpc {args:?}: {stdout}");
    }
}

/// A gripper scene: the shipped sphere grasp with friction `mu`.
fn sphere_with_mu(tmp: &TempDir, mu: &str) -> std::path::PathBuf {
    let shipped = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/sphere_grasp.toml"
    );
    let scene = std::fs::read_to_string(shipped).unwrap();
    assert!(scene.contains("\nmu = 0.6\n"), "{scene}");
    tmp.file(
        &format!("mu_{mu}.toml"),
        scene
            .replace("\nmu = 0.6\n", &format!("\nmu = {mu}\n"))
            .as_bytes(),
    )
}

#[test]
fn the_solve_summary_and_caption_write_extreme_values_compactly() {
    let tmp = TempDir::new("solve");
    // mu = 1e300: the summary and the figure's caption echo it
    let out = tmp.0.join("big");
    let o = solve_into(&sphere_with_mu(&tmp, "1e300"), &out);
    let (stdout, stderr) = (text(&o.stdout), text(&o.stderr));
    assert!(o.status.success(), "{stderr}");
    assert_eq!(stderr, "");
    assert!(stdout.contains(", mu = 1e300\n"), "{stdout}");
    assert!(longest_line(&stdout) < 200, "{stdout}");
    let svg = std::fs::read_to_string(out.join("shape.svg")).unwrap();
    assert!(svg.contains("mu = 1e300,"), "the caption");
    assert!(!svg.contains("00000000000"), "the caption");

    // mu = 1e-300: the friction limit mu F is tiny, not 0.0000
    let out = tmp.0.join("small");
    let o = solve_into(&sphere_with_mu(&tmp, "1e-300"), &out);
    let (stdout, stderr) = (text(&o.stdout), text(&o.stderr));
    assert!(o.status.success(), "{stderr}");
    // the one warning: the mounting angle is outside arccot(mu) to 90 deg
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("fpc: warning: gripper.mounting_angle_deg = 60"));
    assert!(stdout.contains(", mu = 1e-300\n"), "{stdout}");
    assert!(
        stdout.contains("lies outside [0, mu F] = [0, 1.2647e-300] N"),
        "{stdout}"
    );
    let svg = std::fs::read_to_string(out.join("shape.svg")).unwrap();
    assert!(svg.contains("mu = 1e-300,"), "the caption");

    // a finger scene's header
    let scene = tmp.file(
        "finger.toml",
        b"[load]\npressure_kpa = 1e-300\nfz = -2.5e-300\n",
    );
    let o = solve_into(&scene, &tmp.0.join("finger"));
    let (stdout, stderr) = (text(&o.stdout), text(&o.stderr));
    assert!(o.status.success(), "{stderr}");
    assert_eq!(stderr, "");
    assert!(
        stdout.contains("P = 1e-300 kPa, tip force (0, -2.5e-300) N"),
        "{stdout}"
    );
}

#[test]
fn sweep_csv_values_are_exact_and_compact() {
    let tmp = TempDir::new("sweep");
    let scene = tmp.file("finger.toml", b"[actuator.pemc]\neps0 = 0.3\n");
    let out = tmp.0.join("out");
    let values = ["1e-300", "1.5e-12", "0.5", "120", "0.939782", "1e300"];
    let o = fpc(&[
        "sweep",
        &scene.display().to_string(),
        "--vary",
        &format!("load.fx={}", values.join(",")),
        "--out",
        &out.display().to_string(),
        "--threads",
        "1",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(text(&o.stderr), "");
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let column: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    // the value column: as given, and read back to the same f64
    assert_eq!(column, values, "{csv}");
    for (shown, given) in column.iter().zip(values) {
        assert_eq!(shown.parse::<f64>().unwrap(), given.parse::<f64>().unwrap());
    }
    // 1e300 N fails to solve; every other row's line stays short
    assert!(longest_line(&csv) < 300, "{csv}");
}

#[test]
fn a_sweep_range_error_writes_extreme_values_compactly() {
    let tmp = TempDir::new("range");
    let scene = tmp.file("finger.toml", b"");
    rejected_with(
        &[
            "sweep",
            &scene.display().to_string(),
            "--vary",
            "load.fx=1e300:-1e-300:1",
        ],
        "--vary load.fx: one point cannot span 1e300 to -1e-300",
    );
}

#[test]
fn the_paper_note_writes_extreme_values_compactly() {
    let tmp = TempDir::new("paper");
    let scene = tmp.file("tol.toml", b"[partition]\ntip_tol_mm = 1e300\n");
    let out = tmp.0.join("out");
    let stdout = quiet_success(&[
        "paper",
        "--scene",
        &scene.display().to_string(),
        "--out",
        &out.display().to_string(),
    ]);
    assert!(
        stdout.contains("the scene's [partition] (tip_tol_mm = 1e300) is not used"),
        "{stdout}"
    );
}
