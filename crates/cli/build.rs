//! Records the git commit the binary is built from (for the provenance in
//! every JSON file and index.html): `FPC_GIT_COMMIT`, or `unknown` outside
//! a git checkout or without git.

use std::path::Path;
use std::process::Command;

fn main() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_else(|_| ".".into());
    let root = Path::new(&manifest).join("../..");
    let commit = Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .current_dir(&root)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty() && s.chars().all(|c| c.is_ascii_hexdigit()))
        .unwrap_or_else(|| "unknown".into());
    let dirty = Command::new("git")
        .args(["status", "--porcelain", "--untracked-files=no"])
        .current_dir(&root)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .is_some_and(|o| !o.stdout.is_empty());
    let commit = if dirty && commit != "unknown" {
        format!("{commit}+modified")
    } else {
        commit
    };
    println!("cargo:rustc-env=FPC_GIT_COMMIT={commit}");
    // run again when HEAD moves (a commit or a checkout) or a source the
    // binary is built from changes (the `+modified` mark); not on
    // .git/index, which every `git status` rewrites: that recompiled the
    // CLI for nothing
    let git = root.join(".git");
    let p = git.join("HEAD");
    if p.exists() {
        println!("cargo:rerun-if-changed={}", p.display());
    }
    for source in [
        "src",
        "energy-spec",
        "build.rs",
        "Cargo.toml",
        "Cargo.lock",
        "crates/cli/src",
        "crates/newton/src",
        "crates/symbolic/src",
        "crates/modelgen/src",
    ] {
        let p = root.join(source);
        if p.exists() {
            println!("cargo:rerun-if-changed={}", p.display());
        }
    }
    if let Ok(head) = std::fs::read_to_string(git.join("HEAD")) {
        if let Some(r) = head.strip_prefix("ref: ") {
            let p = git.join(r.trim());
            if p.exists() {
                println!("cargo:rerun-if-changed={}", p.display());
            }
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
