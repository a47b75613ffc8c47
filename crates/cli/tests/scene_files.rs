//! `fpc solve` reads its scene file through a bounded reader: at most
//! 4 MiB (the library's `fpc::scene::MAX_SCENE_BYTES`). A file it cannot read (missing,
//! a directory, not UTF-8, not permitted, too large) is rejected input:
//! status 2, one `fpc: error:` line naming the path, nothing written.

mod common;
use common::TempDir;
use std::io::Write as _;
use std::path::Path;
use std::process::{Command, Output};

const MAX_SCENE_BYTES: usize = 4 * 1024 * 1024;
const MAX_LINE: usize = 300;

fn solve(scene: &Path, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
        .arg("solve")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// `fpc solve scene` is rejected with one line containing `parts`, and
/// writes nothing.
fn rejected(tmp: &TempDir, scene: &Path, parts: &[&str]) -> String {
    let out_dir = tmp.0.join("out");
    let out = solve(scene, &out_dir);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{scene:?}: {stderr}");
    assert!(out.stdout.is_empty());
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("fpc: error: cannot read "), "{stderr}");
    assert!(stderr.chars().count() <= MAX_LINE + 1, "{stderr}");
    for p in parts {
        assert!(stderr.contains(p), "{stderr} lacks {p:?}");
    }
    assert!(!out_dir.exists(), "nothing is written");
    stderr
}

#[test]
fn a_missing_scene_is_rejected_naming_the_path() {
    let tmp = TempDir::new("missing");
    let scene = tmp.0.join("missing.toml");
    rejected(&tmp, &scene, &["missing.toml", "No such file or directory"]);
}

#[test]
fn a_directory_is_not_a_scene() {
    let tmp = TempDir::new("dir");
    let scene = tmp.0.join("dir.toml");
    std::fs::create_dir(&scene).unwrap();
    rejected(&tmp, &scene, &["dir.toml", "Is a directory"]);
}

#[test]
fn a_scene_that_is_not_utf8_is_rejected() {
    let tmp = TempDir::new("utf8");
    let scene = tmp.0.join("latin1.toml");
    std::fs::write(&scene, b"[load]\n# caf\xe9\nfx = 0.1\n").unwrap();
    rejected(
        &tmp,
        &scene,
        &["latin1.toml", "not UTF-8 text (invalid byte at offset 12)"],
    );
}

#[test]
fn a_scene_without_read_permission_is_rejected() {
    use std::os::unix::fs::PermissionsExt as _;
    let tmp = TempDir::new("perm");
    let scene = tmp.0.join("secret.toml");
    std::fs::write(&scene, "[load]\nfx = 0.1\n").unwrap();
    std::fs::set_permissions(&scene, std::fs::Permissions::from_mode(0o000)).unwrap();
    if std::fs::read(&scene).is_ok() {
        // root (CAP_DAC_OVERRIDE) reads it anyway: nothing to test here
        eprintln!("skipped: this process can read a file of mode 000");
        return;
    }
    rejected(&tmp, &scene, &["secret.toml", "Permission denied"]);
}

#[test]
fn a_scene_over_the_limit_is_rejected_saying_the_limit() {
    let tmp = TempDir::new("big");
    // one byte over: valid TOML, all comment
    let scene = tmp.0.join("big.toml");
    let mut f = std::fs::File::create(&scene).unwrap();
    f.write_all(b"[load]\nfx = 0.1\n").unwrap();
    let line = format!("#{}\n", "x".repeat(1023));
    while f.metadata().unwrap().len() < MAX_SCENE_BYTES as u64 + 1 {
        f.write_all(line.as_bytes()).unwrap();
    }
    f.set_len(MAX_SCENE_BYTES as u64 + 1).unwrap();
    drop(f);
    rejected(
        &tmp,
        &scene,
        &["big.toml", "larger than 4 MiB (4194304 bytes), the limit"],
    );
    // a sparse 1 GiB file is refused as fast: the reader stops at the limit
    let huge = tmp.0.join("huge.toml");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len(1 << 30)
        .unwrap();
    let t = std::time::Instant::now();
    rejected(&tmp, &huge, &["huge.toml", "larger than 4 MiB"]);
    assert!(t.elapsed().as_secs() < 20, "{:?}", t.elapsed());
    // an endless stream too
    rejected(
        &tmp,
        Path::new("/dev/zero"),
        &["/dev/zero", "larger than 4 MiB"],
    );
}

#[test]
fn a_scene_of_exactly_the_limit_is_read() {
    let tmp = TempDir::new("limit");
    let scene = tmp.0.join("limit.toml");
    let head = "[load]\nfx = 0.1\n# ";
    let mut text = String::from(head);
    text.push_str(&"x".repeat(MAX_SCENE_BYTES - head.len() - 1));
    text.push('\n');
    assert_eq!(text.len(), MAX_SCENE_BYTES);
    std::fs::write(&scene, text).unwrap();
    let out = solve(&scene, &tmp.0.join("out"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(tmp.0.join("out").join("solution.json").is_file());
}

#[test]
fn a_huge_path_is_named_but_not_echoed_whole() {
    let tmp = TempDir::new("path");
    // 100 000 characters: longer than any path the system opens
    let name = "p".repeat(100_000);
    let scene = tmp.0.join(&name);
    let line = rejected(&tmp, &scene, &["cannot read ", "File name too long"]);
    assert!(!line.contains(&name), "the path came back whole");
    assert!(line.contains("pppppppppp"), "{line}");
}
