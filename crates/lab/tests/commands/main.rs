//! The `fpc-lab` binary, run as a user would: `stress`, `accuracy` and
//! `timing` (one module each), their outputs and their rejected flags.

use std::process::{Command, Output};

mod accuracy;
mod stress;
mod timing;

/// `fpc-lab args`, run to completion.
fn lab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fpc-lab"))
        .args(args)
        .output()
        .unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The stdout of a run that succeeded without a panic.
fn ok(what: &str, out: &Output) -> String {
    let stderr = text(&out.stderr);
    assert!(out.status.success(), "{what}: {:?}\n{stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    text(&out.stdout)
}

/// `fpc-lab args` is rejected input (status 2) with one `fpc-lab: error:`
/// line holding `part`: the flag's own parser or rule said why, not clap's
/// "unexpected argument".
fn rejected_with(args: &[&str], part: &str) {
    let out = lab(args);
    let stderr = text(&out.stderr);
    let line = stderr.strip_suffix('\n').unwrap_or(&stderr);
    let one_line = !line.contains('\n') && line.starts_with("fpc-lab: error: ");
    assert!(
        out.status.code() == Some(2) && one_line && line.contains(part),
        "fpc-lab {args:?}: {:?} {stderr} (wanted {part:?})",
        out.status
    );
    assert!(!line.contains("unexpected argument"), "{line}");
}

/// Negative and special numbers given as a separate argument are values,
/// not flags: they reach the flag's parser or rule.
#[test]
fn numbers_reach_their_parsers_and_rules() {
    // whole-number flags: clap's value parser says why, naming the flag
    for (cmd, flag) in [
        ("stress", "--seed"),
        ("stress", "--cases"),
        ("stress", "--max-elements"),
        ("timing", "--budget-ms"),
        ("accuracy", "--budget-ms"),
    ] {
        for v in ["-1", "-inf", "-nan"] {
            rejected_with(
                &[cmd, flag, v],
                &format!("invalid value '{v}' for '{flag} <"),
            );
        }
    }
    // the stress budget takes negative and special values, rejected by its rule
    for (v, shown) in [
        ("-1", "-1"),
        ("-inf", "-inf"),
        ("-nan", "NaN"),
        ("-0", "-0"),
    ] {
        rejected_with(
            &["stress", "--budget-s", v],
            &format!("--budget-s = {shown}: must lie in (0, 86400]"),
        );
    }
}

/// Counts and budgets are bounded before any case is drawn or allocated:
/// 2^64 - 1 cases once panicked (capacity overflow), 10^9 aborted
/// allocating 528 GB.
#[test]
fn counts_and_budgets_are_bounded_before_any_work() {
    for (args, part) in [
        (
            &["stress", "--cases", "18446744073709551615"][..],
            "--cases = 1.8446744073709552e19: must lie in [1, 1000000]",
        ),
        (
            &["stress", "--cases", "1000000000", "--budget-s", "1"][..],
            "--cases = 1000000000: must lie in [1, 1000000]",
        ),
        (&["stress", "--cases", "0"][..], "--cases = 0: must lie in"),
        (
            &["stress", "--max-elements", "0"][..],
            "--max-elements = 0: must lie in [1, 1000]",
        ),
        (
            &["stress", "--budget-s", "1e300"][..],
            // (the huge value shortened on the line, the rule kept)
            "must lie in (0, 86400]",
        ),
    ] {
        rejected_with(args, part);
    }
}

#[test]
fn help_lists_the_lab_commands() {
    let help = ok("fpc-lab --help", &lab(&["--help"]));
    for command in ["stress", "accuracy", "timing"] {
        assert!(help.contains(command), "{help}");
    }
    let out = lab(&["bogus"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
}
