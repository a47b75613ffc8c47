//! The `fpc` binary's error paths: rejected input (a scene file that
//! cannot be read included) exits with status 2, anything else that fails
//! (a solve that does not converge, output that cannot be written) with
//! status 1; either way stdout stays empty and stderr
//! holds exactly one line, `fpc: error: ...`, naming the field, the value
//! and the rule (or the solver's reason).
//!
//! `fpc solve` on bad scene files is in tests/solve.rs, `fpc paper`'s
//! output directory in tests/paper/directory.rs.

mod common;

use common::{fails, fpc, rejected, text};

#[test]
fn a_bad_prestrain_exits_2_naming_eps0() {
    rejected(
        &["finger", "--eps0", "nan"],
        &["fpc: error: --eps0 = NaN: must be finite"],
    );
    // attached with `=` or separate (tests/numbers.rs), a value either way
    rejected(
        &["finger", "--eps0=-inf"],
        &["--eps0 = -inf: must be finite"],
    );
}

#[test]
fn a_bad_element_count_exits_2_naming_the_flag() {
    for n in ["0", "1001"] {
        rejected(
            &["finger", "--elements", n],
            &[&format!("--elements = {n}: must lie in [1, 1000]")],
        );
    }
    // not a count at all: clap's message, in the same form
    rejected(&["finger", "--elements", "-1"], &["--elements", "'-1'"]);
    // a count within the bound whose material partition is not: the
    // count is named, not the piece length it sets (110 mm / 1000)
    rejected(
        &["finger", "--partition", "material", "--elements", "1000"],
        &["--elements = 1000: gives 1017 elements (pieces of at most 0.11 mm"],
    );
}

#[test]
fn a_negative_count_is_the_flags_value_and_named() {
    // a separate value starting with `-` is the flag's (README), on every
    // command's counts, not an unexpected argument
    let repo = |p: &str| format!("{}/../../{p}", env!("CARGO_MANIFEST_DIR"));
    let (design, scene) = (
        repo("scenes/design/paper_sec5.toml"),
        repo("scenes/default.toml"),
    );
    let manifest = common::shipped();
    for (args, flag) in [
        (
            vec!["design", design.as_str(), "--starts", "-1"],
            "--starts",
        ),
        (
            vec![
                "sweep",
                scene.as_str(),
                "--vary",
                "load.fx=0:1:2",
                "--threads",
                "-1",
            ],
            "--threads",
        ),
        (
            vec![
                "calibrate",
                manifest.as_str(),
                "--fit",
                "eps0",
                "--max-iterations",
                "-1",
            ],
            "--max-iterations",
        ),
        (vec!["serve", "--port", "-1"], "--port"),
    ] {
        rejected(&args, &[flag, "'-1'"]);
    }
}

#[test]
fn bad_loads_exit_2_naming_the_flag() {
    rejected(
        &["finger", "--pressure-kpa", "inf"],
        &["--pressure-kpa = inf: must be finite"],
    );
    rejected(
        &["finger", "--pressure-kpa", "NaN"],
        &["--pressure-kpa = NaN: must be finite"],
    );
    // below absolute vacuum: the library's load.pressure (MPa) named by
    // the flag, in the flag's unit
    rejected(
        &["finger", "--pressure-kpa=-500"],
        &["--pressure-kpa = -500: is below absolute vacuum"],
    );
    for k in ["0", "-1"] {
        rejected(
            &["finger", "--kappa", k],
            &[&format!("--kappa = {k}: must be positive")],
        );
    }
    // kappa = 1/(gamma - 1) of a gas: at most 100 (1e300 failed as a
    // singular linear system)
    for k in ["1e300", "100.5"] {
        rejected(
            &["finger", "--kappa", k, "--pressure-kpa", "50"],
            &[&format!("--kappa = {k}: must be at most 100")],
        );
    }
    rejected(&["finger", "--fx", "nan"], &["--fx = NaN: must be finite"]);
    rejected(
        &["finger", "--fz=-inf", "--json"],
        &["--fz = -inf: must be finite"],
    );
}

#[test]
fn a_bad_tip_tolerance_exits_2_naming_it() {
    for t in ["0", "-1"] {
        rejected(
            &["finger", "--tip-tol-mm", t],
            &[&format!("--tip-tol-mm = {t}: must be positive")],
        );
    }
    rejected(
        &["finger", "--tip-tol-mm", "nan"],
        &["--tip-tol-mm = NaN: must be finite"],
    );
    // refinement doubles N up to 1000: it must start at 1 to 500 elements
    for n in ["0", "600"] {
        rejected(
            &["finger", "--tip-tol-mm", "0.1", "--elements", n],
            &[&format!("--elements = {n}: must lie in [1, 500]")],
        );
    }
    // the tolerance chooses the partition, levels and extrapolation
    rejected(
        &["finger", "--tip-tol-mm", "0.1", "--levels", "2"],
        &["--tip-tol-mm: chooses the partition, levels and extrapolation itself"],
    );
}

/// A switch that cannot apply is named without a value (the user wrote
/// no number).
#[test]
fn extrapolation_without_its_levels_exits_2_naming_the_switch() {
    for extra in [&[][..], &["--levels", "2"], &["--partition", "material"]] {
        let mut args = vec!["finger", "--extrapolate"];
        args.extend_from_slice(extra);
        rejected(
            &args,
            &["--extrapolate: needs at least two levels on a material partition"],
        );
    }
}

#[test]
fn an_unreachable_tip_tolerance_exits_2() {
    // no partition of at most 1000 elements estimates 1e-12 mm; unloaded,
    // the refinement is fast even in a debug build
    for extra in [&[][..], &["--elements", "8"][..]] {
        let mut args = vec!["finger", "--tip-tol-mm", "1e-12"];
        args.extend_from_slice(extra);
        rejected(
            &args,
            &[
                "--tip-tol-mm = 1e-12: not reached with up to 1000 elements",
                "estimated tip error there",
            ],
        );
    }
}

#[test]
fn a_failed_solve_exits_1_with_the_reason() {
    // tip forces no equilibrium within reach balances: Newton and load
    // continuation give up, deterministically
    for args in [
        &["finger", "--fx", "1e6"][..],
        &["finger", "--fz", "1e6", "--json"][..],
    ] {
        let line = fails(args, 1);
        assert!(
            line.starts_with("fpc: error: solve failed: "),
            "fpc {args:?}: {line}"
        );
        assert!(
            line.contains("iterations (relative residual"),
            "fpc {args:?}: {line}"
        );
        assert!(
            !line.contains("NaN") && !line.contains("inf)"),
            "fpc {args:?}: {line}"
        );
    }
}

#[test]
fn usage_errors_exit_2_on_one_line() {
    rejected(&["finger", "--bogus"], &["unexpected argument '--bogus'"]);
    // clap's suggestion stays on the line
    rejected(&["finger", "--fxx", "1"], &["'--fxx'", "'--fx'"]);
    rejected(&["finger", "--eps0", "abc"], &["'abc'", "--eps0"]);
    rejected(&["finger", "--eps0"], &["--eps0", "a value is required"]);
    rejected(&["bogus"], &["'bogus'"]);
    rejected(&["solve"], &["<SCENE>"]);
}

#[test]
fn an_unreadable_scene_exits_2() {
    let dir = tempfile::Builder::new()
        .prefix("fpc-errors-")
        .tempdir()
        .unwrap();
    let missing = dir.path().join("missing.toml");
    let out = dir.path().join("out");
    let line = fails(
        &[
            "solve",
            missing.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        2,
    );
    assert!(line.contains("cannot read"), "{line}");
    assert!(line.contains("missing.toml"), "{line}");
    assert!(!out.exists(), "nothing is written");
}

#[test]
fn warnings_do_not_fail() {
    let out = fpc(&["finger", "--eps0", "0.8"]);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stderr}");
    assert!(stdout.contains("tip"), "{stdout}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(
        lines[0],
        "fpc: warning: --eps0 = 0.8: outside [0, 0.6], the range the prestressed law was fitted to"
    );
    // the coiled finger also leaves the model's limits, each on its own line
    assert!(
        lines.iter().all(|l| l.starts_with("fpc: warning: ")),
        "{stderr}"
    );
    assert!(stderr.contains("strain"), "{stderr}");
}

#[test]
fn help_is_not_an_error() {
    let out = fpc(&["finger", "--help"]);
    assert!(out.status.success());
    assert!(text(&out.stdout).contains("Usage: fpc finger"));
    assert!(out.stderr.is_empty(), "{}", text(&out.stderr));
}

#[test]
fn bad_figure_sizes_exit_2_before_any_directory_is_made() {
    // a directory not yet made, inside one removed when dropped
    let parent = tempfile::Builder::new()
        .prefix("fpc-errors-style-")
        .tempdir()
        .unwrap();
    let out = parent.path().join("out");
    let dir = out.to_str().unwrap();
    // a width from half an inch to 1000 in, tick labels from 1 pt to 100
    // pt (1e-300 pt was written as font-size 0)
    for (flag, v, shown, rule) in [
        ("--width-in", "0", "0", "must lie in [0.5, 1000]"),
        ("--width-in", "nan", "NaN", "must lie in [0.5, 1000]"),
        ("--width-in", "1e300", "1e300", "must lie in [0.5, 1000]"),
        ("--width-in", "1e-300", "1e-300", "must lie in [0.5, 1000]"),
        ("--width-in", "0.4", "0.4", "must lie in [0.5, 1000]"),
        ("--font-pt", "-1", "-1", "must lie in [1, 100]"),
        ("--font-pt", "1e-300", "1e-300", "must lie in [1, 100]"),
        ("--font-pt", "0.5", "0.5", "must lie in [1, 100]"),
        ("--font-pt", "101", "101", "must lie in [1, 100]"),
    ] {
        rejected(
            &["paper", "--coarse", "--out", dir, flag, v],
            &[&format!("{flag} = {shown}: {rule}")],
        );
        assert!(!out.exists(), "{flag} {v}: {out:?} was made");
    }
}
