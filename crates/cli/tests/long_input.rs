//! Echoed input is bounded: no line `fpc` writes on stderr is longer than
//! 300 characters (src/report.rs, `MAX_LINE`), whatever the size of the
//! argument, value, key or path it quotes, and no line carries a raw
//! control character.

mod common;
use common::{solve_into, text, TempDir};
use std::process::{Command, Output};

/// The bound of src/report.rs, in characters, newline excluded.
const MAX_LINE: usize = 300;

fn fpc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
}

/// Checks that every stderr line is bounded and prefixed, that `whole`
/// does not come back, and that `code` is the status; returns stderr.
fn bounded(out: &Output, code: i32, whole: &str) -> String {
    let stderr = text(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(code),
        "{}",
        &stderr[..stderr.len().min(2000)]
    );
    assert!(!stderr.is_empty());
    for line in stderr.lines() {
        let n = line.chars().count();
        assert!(
            n <= MAX_LINE,
            "{n} characters: {}",
            &line[..line.len().min(2000)]
        );
        assert!(line.starts_with("fpc: "), "{line}");
        assert!(!line.chars().any(|c| c.is_control()), "{line:?}");
    }
    assert!(!stderr.contains(whole), "the input came back whole");
    assert!(
        !text(&out.stdout).contains(whole),
        "the input came back whole"
    );
    stderr
}

#[test]
fn a_309_digit_number_is_not_echoed_whole() {
    // parses as 1e308: finite, but past any prestrain, so it is refused by
    // name, written short
    let digits = format!("1{}", "0".repeat(308));
    let out = fpc().args(["finger", "--eps0", &digits]).output().unwrap();
    let stderr = bounded(&out, 2, &digits);
    assert!(
        stderr.starts_with("fpc: error: --eps0 = 1e308: must lie in (-1, 10]"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("NaN") && !stderr.contains("inf"),
        "{stderr}"
    );
    // the same number where a count is expected: clap's usage error
    let out = fpc()
        .args(["finger", "--elements", &digits])
        .output()
        .unwrap();
    let stderr = bounded(&out, 2, &digits);
    assert!(stderr.contains("--elements"), "{stderr}");
}

#[test]
fn a_huge_argument_is_not_echoed_whole() {
    // one argument is at most 128 KiB on Linux: 100 000 characters
    let junk = "x".repeat(100_000);
    for args in [
        vec!["finger", "--eps0", &junk],
        vec!["finger", &junk],
        vec![&junk],
        vec!["kernels", "--model", &junk],
    ] {
        let out = fpc().args(&args).output().unwrap();
        bounded(&out, 2, &junk);
    }
    // many long arguments, 2 MB in all: only the first is reported
    let args: Vec<String> = (0..20)
        .map(|i| format!("--{i}{}", "y".repeat(100_000)))
        .collect();
    let out = fpc().arg("finger").args(&args).output().unwrap();
    let stderr = bounded(&out, 2, &args[0]);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
}

#[test]
fn a_huge_key_or_value_in_a_scene_is_not_echoed_whole() {
    let tmp = TempDir::new("scene");
    let key = "k".repeat(2_000_000);
    let value = "v".repeat(2_000_000);
    for (name, scene, whole) in [
        ("key", format!("[load]\n{key} = 1\n"), &key),
        ("value", format!("[load]\nfx = \"{value}\"\n"), &value),
        ("section", format!("[{key}]\n"), &key),
    ] {
        let path = tmp.0.join(format!("{name}.toml"));
        std::fs::write(&path, scene).unwrap();
        let out = fpc()
            .arg("solve")
            .arg(&path)
            .arg("--out")
            .arg(tmp.0.join("out"))
            .output()
            .unwrap();
        let stderr = bounded(&out, 2, whole);
        assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
        assert!(
            stderr.contains(&format!("{name}.toml:")),
            "{name}: {stderr}"
        );
    }
}

#[test]
fn control_characters_are_escaped() {
    // in an argument: clap's message, kept on one line
    let forged = "0.5\nfpc: error: forged\u{1b}[2J\nUsage: x";
    let out = fpc().args(["finger", "--eps0", forged]).output().unwrap();
    let stderr = bounded(&out, 2, forged);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("forged"), "{stderr}");
    assert!(stderr.contains("--eps0"), "{stderr}");
    // in a scene key (TOML escapes): written escaped
    let tmp = TempDir::new("controls");
    let path = tmp.0.join("controls.toml");
    std::fs::write(&path, "[load]\n\"a\\nfpc: error: forged\\u001b[2J\" = 1\n").unwrap();
    let out = solve_into(&path, &tmp.0.join("out"));
    let stderr = bounded(&out, 2, "\u{1b}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    // (the library joins the lines of its message with "; ")
    assert!(stderr.contains("forged\\u{1b}[2J`"), "{stderr}");
}

/// A scene file's name is echoed on stdout by `fpc solve`'s summary:
/// escaped there too, so a name cannot drive the terminal.
#[cfg(unix)]
#[test]
fn a_file_name_s_controls_are_escaped_on_stdout() {
    let tmp = TempDir::new("name");
    let path = tmp.0.join("a\u{1b}[2Jb.toml");
    std::fs::write(&path, "[actuator.pemc]\neps0 = 0.3\n").unwrap();
    let out = solve_into(&path, &tmp.0.join("out"));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("a\\u{1b}[2Jb"), "{stdout}");
    for line in stdout.lines() {
        assert!(!line.chars().any(|c| c.is_control()), "{line:?}");
    }
}
