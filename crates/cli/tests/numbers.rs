//! Negative and special numbers given as a separate argument
//! (`--eps0 -inf`, `--fx -5`) are values, not flags: every numeric flag of
//! every subcommand hands them to its parser and validation instead of
//! clap reporting an "unexpected argument".

use std::process::{Command, Output};

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
