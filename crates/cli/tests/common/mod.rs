//! What the tests of the `fpc` binary share: running it, and the shape of
//! a failed run (a status, nothing on stdout, one `fpc: error:` line on
//! stderr). Each test file that uses it says `mod common;`.
#![allow(dead_code)] // each test file uses its part

use std::ffi::OsStr;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A fresh scratch directory for test `name` of file `file`, removed when
/// dropped (a failed test's too).
pub fn tmp(file: &str, name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("fpc-cli-{file}-{name}-"))
        .tempdir()
        .unwrap()
}

/// The shipped synthetic measurement set's manifest.
pub fn shipped() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/calibration/manifest.toml")
        .display()
        .to_string()
}

/// A scratch directory for one test of this file, removed when dropped:
/// its path, and the [`tmp`] directory that removes it.
pub struct TempDir(pub PathBuf, tempfile::TempDir);

impl TempDir {
    pub fn new(name: &str) -> TempDir {
        let d = tmp(env!("CARGO_CRATE_NAME"), name);
        TempDir(d.path().to_path_buf(), d)
    }

    /// Writes `bytes` to `name` inside the directory.
    pub fn file(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    }
}

/// The `fpc` binary with SIGINT at its default, as a terminal's shell
/// runs a command, so that a test's SIGINT is a user's Ctrl-C (a CI shell
/// may hand SIGINT down ignored, and fpc keeps an ignored SIGINT ignored).
#[cfg(unix)]
pub fn fpc_as_in_a_terminal() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_fpc"));
    // SAFETY: `signal` is async-signal-safe, as `pre_exec` requires
    unsafe {
        use std::os::unix::process::CommandExt as _;
        command.pre_exec(|| {
            libc::signal(libc::SIGINT, libc::SIG_DFL);
            Ok(())
        });
    }
    command
}

/// Presses Ctrl-C once for process `child`: one SIGINT.
#[cfg(unix)]
pub fn ctrl_c(child: &std::process::Child) {
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
}

/// The variable that sets how long `fpc` works before it shows progress
/// (README, "Progress"), and the value the quick runs here give it: a
/// successful run's stderr stays empty however slow a loaded machine
/// makes a debug build. The tests of progress itself leave the default.
pub const QUIET: &str = "FPC_PROGRESS_AFTER_S";
pub const NEVER: &str = "3600";

pub fn fpc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
        .env(QUIET, NEVER)
        .args(args)
        .output()
        .unwrap()
}

/// `fpc args` with stdout and stderr captured, killed and failed when it
/// runs longer than `limit` (the outputs are drained while it runs, so a
/// long output cannot stall it).
pub fn fpc_within<S: AsRef<OsStr> + std::fmt::Debug>(args: &[S], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_fpc"))
        .env(QUIET, NEVER)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    fn drain(mut r: impl Read + Send + 'static) -> std::thread::JoinHandle<Vec<u8>> {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            v
        })
    }
    let stdout = drain(child.stdout.take().unwrap());
    let stderr = drain(child.stderr.take().unwrap());
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("fpc {args:?} still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Output {
        status,
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    }
}

/// `fpc solve SCENE --out OUT`.
pub fn solve_into(scene: &Path, out: &Path) -> Output {
    fpc(&[
        "solve",
        &scene.display().to_string(),
        "--out",
        &out.display().to_string(),
    ])
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Runs `fpc args`, which must fail with `code`, print nothing on stdout
/// and one `fpc: error:` line on stderr; returns that line.
pub fn fails(args: &[&str], code: i32) -> String {
    let out = fpc(args);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(
        out.status.code(),
        Some(code),
        "fpc {args:?}: status {:?}\nstderr: {stderr}",
        out.status
    );
    assert!(stdout.is_empty(), "fpc {args:?}: stdout: {stdout}");
    assert!(stderr.ends_with('\n'), "fpc {args:?}: {stderr:?}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "fpc {args:?}: not one line: {stderr}");
    assert!(
        lines[0].starts_with("fpc: error: "),
        "fpc {args:?}: {stderr}"
    );
    lines[0].to_string()
}

/// `fpc args` is rejected input (status 2) and its message contains each of `parts`.
pub fn rejected(args: &[&str], parts: &[&str]) {
    let line = fails(args, 2);
    for p in parts {
        assert!(line.contains(p), "fpc {args:?}: {line} lacks {p:?}");
    }
}

/// A `refinement` object (of `fpc finger --json` or a scene's
/// `solution.json`) checked against its own levels: one entry per level in
/// every per-level list, each level's steps adding up to its iterations,
/// and the best tip the one its `extrapolation` names, redone here from
/// the levels' tips (`last_two`: `t_n + (t_n - t_n-1) / 3`; `last_three`:
/// `(8 t_n - 6 t_n-1 + t_n-2) / 3`; none: the finest level's).
pub fn check_refinement(r: &serde_json::Value) {
    let list = |key: &str| r[key].as_array().unwrap_or_else(|| panic!("{key}: {r}"));
    let levels = list("levels").len();
    for key in ["level_iterations", "level_steps", "level_tips_mm"] {
        assert_eq!(list(key).len(), levels, "{key}: {r}");
    }
    for (it, st) in list("level_iterations").iter().zip(list("level_steps")) {
        let phases: u64 = ["element", "coupled", "continuation"]
            .iter()
            .map(|k| st[k].as_u64().unwrap())
            .sum();
        assert_eq!(it.as_u64(), Some(phases), "{r}");
    }
    let tips: Vec<[f64; 2]> = list("level_tips_mm")
        .iter()
        .map(|t| [t[0].as_f64().unwrap(), t[1].as_f64().unwrap()])
        .collect();
    let t = |back: usize| tips[levels - 1 - back];
    let want: [f64; 2] = match r["extrapolation"].as_str() {
        None => {
            assert_eq!(r["extrapolated"], false, "{r}");
            t(0)
        }
        Some("last_two") => {
            assert_eq!(levels, 2, "{r}");
            std::array::from_fn(|c| t(0)[c] + (t(0)[c] - t(1)[c]) / 3.0)
        }
        Some("last_three") => {
            assert!(levels >= 3, "{r}");
            std::array::from_fn(|c| (8.0 * t(0)[c] - 6.0 * t(1)[c] + t(2)[c]) / 3.0)
        }
        Some(other) => panic!("unknown extrapolation {other}"),
    };
    for (c, w) in want.iter().enumerate() {
        let got = r["tip_mm"][c].as_f64().unwrap();
        assert!(
            (got - w).abs() <= 1e-9 * w.abs().max(1.0),
            "{got} vs {w}: {r}"
        );
    }
}
