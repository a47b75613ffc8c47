//! Standard output closed, full or read-only: the command exits with
//! status 1 and says so on stderr, never panics, never dies of a signal. A
//! pipe nobody reads any more (`fpc kernels | head`) ends the command
//! quietly with status 0, as a Unix tool does. A stderr that cannot be
//! written costs the messages, not the exit status.

mod common;

use std::fs::File;
use std::path::PathBuf;
use std::process::{Child, Command, Output, Stdio};

use tempfile::TempDir;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_fpc")
}

fn fpc(args: &[&str]) -> Command {
    let mut c = Command::new(bin());
    c.args(args);
    c
}

/// `sh -c 'exec fpc ARGS >&-'`: fpc started with descriptor 1 closed.
fn with_stdout_closed(args: &[&str]) -> Command {
    let mut c = Command::new("sh");
    c.arg("-c")
        .arg("exec \"$0\" \"$@\" >&-")
        .arg(bin())
        .args(args);
    c
}

/// A pipe whose reading end is already closed: every write is EPIPE.
fn dead_pipe() -> Stdio {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    writer.into()
}

fn dev_full() -> Stdio {
    File::options()
        .write(true)
        .open("/dev/full")
        .unwrap()
        .into()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn tmp(name: &str) -> TempDir {
    common::tmp("streams", name)
}

/// Exited by itself (not by a signal) with `code`, no panic on stderr.
fn no_panic(what: &str, out: &Output, code: i32) -> String {
    let stderr = text(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(code),
        "{what}: {:?} {stderr}",
        out.status
    );
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    assert!(!stderr.contains("RUST_BACKTRACE"), "{what}: {stderr}");
    stderr
}

/// Status 0 and nothing on stderr: the reader went away.
fn stops_quietly(what: &str, out: Output) {
    let stderr = no_panic(what, &out, 0);
    assert!(stderr.is_empty(), "{what}: {stderr}");
}

/// Status 1 and one error line on stderr containing `why`.
fn fails_writing(what: &str, out: Output, why: &str) {
    let stderr = no_panic(what, &out, 1);
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{what}: {stderr}");
    assert!(
        lines[0].starts_with("fpc: error: cannot write to standard output: "),
        "{what}: {stderr}"
    );
    assert!(lines[0].contains(why), "{what}: {stderr} lacks {why:?}");
}

fn spawn(mut c: Command, stdout: Stdio) -> Child {
    c.stdout(stdout).stderr(Stdio::piped()).spawn().unwrap()
}

/// The three commands of the brief: each way of breaking stdout.
#[test]
fn finger_json_and_kernels_fail_with_status_1_on_a_broken_stdout() {
    for args in [&["finger", "--json"][..], &["kernels"][..]] {
        let what = format!("fpc {args:?}");
        let out = with_stdout_closed(args).output().unwrap();
        fails_writing(&format!("{what} >&-"), out, "it was closed");
        let out = spawn(fpc(args), dead_pipe()).wait_with_output().unwrap();
        stops_quietly(&format!("{what} | dead pipe"), out);
        let out = spawn(fpc(args), dev_full()).wait_with_output().unwrap();
        fails_writing(
            &format!("{what} > /dev/full"),
            out,
            "No space left on device",
        );
        let ro: Stdio = File::open("/dev/null").unwrap().into();
        let out = spawn(fpc(args), ro).wait_with_output().unwrap();
        fails_writing(
            &format!("{what} 1< /dev/null"),
            out,
            "open for reading only",
        );
    }
}

#[test]
fn compare_writes_its_files_and_stops_quietly_on_a_dead_pipe() {
    let manifest = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/calibration/manifest.toml");
    let scratch = tmp("compare");
    // not there yet: the run makes it
    let d = scratch.path().join("out");
    let args = [
        "compare",
        manifest.to_str().unwrap(),
        "--out",
        d.to_str().unwrap(),
    ];
    let out = spawn(fpc(&args), dead_pipe()).wait_with_output().unwrap();
    stops_quietly("compare | dead pipe", out);
    assert!(d.join("compare.json").is_file());
    let out = with_stdout_closed(&args).output().unwrap();
    fails_writing("compare >&-", out, "it was closed");
}

#[test]
fn paper_fails_with_status_1_on_a_broken_stdout() {
    // all at once (a coarse paper takes seconds in a debug build)
    let scratch = tmp("paper");
    let dirs: Vec<PathBuf> = ["closed", "pipe", "full"]
        .map(|name| scratch.path().join(name))
        .into();
    let args = |d: &PathBuf| -> Vec<String> {
        ["paper", "--coarse", "--out", d.to_str().unwrap()]
            .map(String::from)
            .into()
    };
    let argv: Vec<Vec<String>> = dirs.iter().map(args).collect();
    let argv: Vec<Vec<&str>> = argv
        .iter()
        .map(|a| a.iter().map(String::as_str).collect())
        .collect();
    let closed = spawn(with_stdout_closed(&argv[0]), Stdio::inherit());
    let pipe = spawn(fpc(&argv[1]), dead_pipe());
    let full = spawn(fpc(&argv[2]), dev_full());
    for (child, what, why) in [
        (closed, "paper >&-", "it was closed"),
        (full, "paper > /dev/full", "No space left on device"),
    ] {
        fails_writing(what, child.wait_with_output().unwrap(), why);
    }
    stops_quietly("paper | dead pipe", pipe.wait_with_output().unwrap());
    // the files were written before the summary line failed
    for d in &dirs {
        assert!(d.join("summary.json").is_file(), "{d:?}");
    }
}

#[test]
fn a_reader_that_exits_at_once_never_causes_a_panic() {
    // `fpc ... | head -c1`: whether fpc is still writing when head exits
    // depends on timing; either way it ends with 0 and says nothing
    for args in ["finger --json", "kernels", "finger"] {
        let scratch = tmp(&format!("head-{}", args.replace(' ', "-")));
        let err = scratch.path().join("stderr");
        let script =
            format!("\"$0\" {args} 2>\"$1\" | head -c1 >/dev/null; exit ${{PIPESTATUS[0]}}");
        let out = Command::new("bash")
            .arg("-c")
            .arg(script)
            .arg(bin())
            .arg(&err)
            .output()
            .unwrap();
        let stderr = std::fs::read_to_string(&err).unwrap();
        assert!(!stderr.contains("panicked"), "{args}: {stderr}");
        assert_eq!(out.status.code(), Some(0), "{args}: {stderr}");
        assert!(stderr.is_empty(), "{args}: {stderr}");
    }
}

#[test]
fn help_fails_with_status_1_on_a_broken_stdout() {
    for args in [
        &["--help"][..],
        &["--version"][..],
        &["finger", "--help"][..],
    ] {
        let out = with_stdout_closed(args).output().unwrap();
        fails_writing(&format!("{args:?} >&-"), out, "it was closed");
        let out = spawn(fpc(args), dev_full()).wait_with_output().unwrap();
        fails_writing(
            &format!("{args:?} > /dev/full"),
            out,
            "No space left on device",
        );
    }
}

#[test]
fn a_read_write_dev_null_is_not_a_closed_stdout() {
    // what Python's subprocess.DEVNULL and daemons hand a child: output
    // discarded on purpose, not an error
    let rw: Stdio = File::options()
        .read(true)
        .write(true)
        .open("/dev/null")
        .unwrap()
        .into();
    let out = spawn(fpc(&["finger", "--json"]), rw)
        .wait_with_output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let out = fpc(&["finger", "--json"])
        .stdout(Stdio::null())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
}

#[test]
fn a_broken_stderr_costs_the_messages_not_the_status() {
    // a warning to a closed or full stderr: still success
    let mut c = Command::new("sh");
    c.arg("-c")
        .arg("exec \"$0\" finger --eps0 0.8 2>&-")
        .arg(bin());
    let out = c.output().unwrap();
    assert!(out.status.success(), "{:?}", out.status);
    assert!(text(&out.stdout).contains("tip"));
    let out = fpc(&["finger", "--eps0", "0.8"])
        .stderr(dev_full())
        .output()
        .unwrap();
    assert!(out.status.success(), "{:?}", out.status);
    // an error: its status, whether or not the line can be written
    let out = fpc(&["finger", "--eps0", "nan"])
        .stderr(dev_full())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let out = fpc(&["finger", "--json"])
        .stdout(dev_full())
        .stderr(dev_full())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let mut c = Command::new("sh");
    c.arg("-c").arg("exec \"$0\" kernels >&- 2>&-").arg(bin());
    assert_eq!(c.output().unwrap().status.code(), Some(1));
}
