//! The exit status, one rule (src/status.rs): 0 success; 2 every rejected
//! input (a bad flag or value, a scene file that cannot be read, is too
//! large, is not TOML or holds an invalid value, an output path that is a
//! file); 1 a failed solve and an I/O failure writing output. One case per
//! class, each through the built binary.

mod common;
use common::TempDir;
use std::path::Path;
use std::process::{Command, Stdio};

fn fpc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
}

/// Runs `cmd` (described by `what`) and checks its status; an error also
/// ends stderr with one `fpc: error:` line and leaves stdout empty.
fn status(what: &str, cmd: &mut Command, code: i32) {
    let out = cmd.output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{what}: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    if code != 0 {
        let last = stderr.lines().last().unwrap_or("");
        assert!(last.starts_with("fpc: error: "), "{what}: {stderr}");
        assert!(out.stdout.is_empty(), "{what}: stdout written");
    }
}

fn solve(scene: &Path, out: &Path) -> Command {
    let mut c = fpc();
    c.arg("solve").arg(scene).arg("--out").arg(out);
    c
}

#[test]
fn success_is_0() {
    status("finger", fpc().arg("finger"), 0);
    status("--help", fpc().arg("--help"), 0);
    status("finger --help", fpc().args(["finger", "--help"]), 0);
    status("--version", fpc().arg("--version"), 0);
    let tmp = TempDir::new("ok");
    let scene = tmp.file("ok.toml", b"[load]\nfx = 0.1\n");
    status("solve", &mut solve(&scene, &tmp.0.join("out")), 0);
}

#[test]
fn every_rejected_input_is_2() {
    // flags and values
    for args in [
        &[][..],
        &["bogus"][..],
        &["finger", "--bogus"][..],
        &["finger", "--eps0"][..],
        &["finger", "--eps0", "abc"][..],
        &["finger", "--elements", "-1"][..],
        &["finger", "--eps0", "-inf"][..],
        &["finger", "--kappa", "0"][..],
        &["finger", "--elements", "0"][..],
        &["kernels", "--model", "nope"][..],
        &["solve"][..],
    ] {
        status(&format!("fpc {args:?}"), fpc().args(args), 2);
    }
    // scene files: unreadable, too large, not UTF-8, not TOML, invalid
    let tmp = TempDir::new("rejected");
    let out = tmp.0.join("out");
    let big = vec![b'#'; 4 * 1024 * 1024 + 1];
    for (what, scene) in [
        ("missing", tmp.0.join("missing.toml")),
        ("directory", tmp.0.clone()),
        ("oversized", tmp.file("big.toml", &big)),
        ("not UTF-8", tmp.file("latin1.toml", b"# \xe9\n")),
        ("syntax", tmp.file("syntax.toml", b"[load]\nfx = = 1\n")),
        ("unknown key", tmp.file("typo.toml", b"[load]\nfxx = 1\n")),
        ("wrong type", tmp.file("type.toml", b"[load]\nfx = \"a\"\n")),
        (
            "invalid value",
            tmp.file("value.toml", b"[actuator.geometry]\nh1 = 5.0\n"),
        ),
        (
            "invalid gripper",
            tmp.file("grip.toml", b"[gripper]\noverlap_mm = 500\n"),
        ),
    ] {
        status(what, &mut solve(&scene, &out), 2);
        assert!(!out.exists(), "{what}: output written");
    }
    // an output path that is a file
    let scene = tmp.file("ok.toml", b"[load]\nfx = 0.1\n");
    let file = tmp.file("not-a-dir", b"keep");
    status("solve --out FILE", &mut solve(&scene, &file), 2);
    status(
        "paper --out FILE",
        fpc().args(["paper", "--coarse", "--out"]).arg(&file),
        2,
    );
    assert_eq!(std::fs::read(&file).unwrap(), b"keep");
}

#[test]
fn failed_solves_and_io_failures_are_1() {
    status("finger --fx 1e6", fpc().args(["finger", "--fx", "1e6"]), 1);
    let tmp = TempDir::new("failed");
    let unsolved = tmp.file(
        "unsolved.toml",
        b"[load]\nfx = 1.0\n[solve]\nmax_iter = 1\ncontinuation = false\n",
    );
    status(
        "solve (fails)",
        &mut solve(&unsolved, &tmp.0.join("out")),
        1,
    );
    // output that cannot be written: stdout full, an output directory
    // that cannot be created
    let full = || -> Stdio {
        std::fs::File::options()
            .write(true)
            .open("/dev/full")
            .unwrap()
            .into()
    };
    status("finger > /dev/full", fpc().arg("finger").stdout(full()), 1);
    status(
        "kernels > /dev/full",
        fpc().arg("kernels").stdout(full()),
        1,
    );
    let scene = tmp.file("ok.toml", b"[load]\nfx = 0.1\n");
    status(
        "solve > /dev/full",
        solve(&scene, &tmp.0.join("out2")).stdout(full()),
        1,
    );
    let file = tmp.file("a-file", b"");
    status(
        "solve --out FILE/sub",
        &mut solve(&scene, &file.join("sub")),
        1,
    );
}
