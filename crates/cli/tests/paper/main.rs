//! `fpc paper`: runs the built binary and checks what it writes, one
//! module per subject: the files of one run and their content, the
//! output directory and the refused inputs, strict mode, and the error
//! bands of a calibrated scene. The helpers every module reads are here.

#[path = "../common/mod.rs"]
mod common;

mod bands;
mod directory;
mod files;
mod strict;

use std::path::Path;
use std::process::Command;

use serde_json::Value;
use tempfile::TempDir;

fn fpc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
}

fn tmp(name: &str) -> TempDir {
    common::tmp("paper", name)
}

fn expected_files() -> Vec<String> {
    let mut v: Vec<String> = (1..=8)
        .flat_map(|n| [format!("study{n}.csv"), format!("study{n}.svg")])
        .collect();
    v.extend(
        [
            "study1_shapes.csv",
            "study5_envelope.csv",
            "summary.json",
            "index.html",
        ]
        .map(String::from),
    );
    v
}

/// Splits one CSV line (double-quoted fields may hold commas).
fn fields(line: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                chars.next();
                out.last_mut().unwrap().push('"');
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(String::new()),
            _ => out.last_mut().unwrap().push(c),
        }
    }
    out
}

fn number(v: &Value, what: &str) -> f64 {
    let x = v
        .as_f64()
        .unwrap_or_else(|| panic!("{what} is not a number: {v}"));
    assert!(x.is_finite(), "{what} = {x}");
    x
}

/// Every expected file of a run is there and complete: JSON that parses,
/// CSV rows as wide as their header, SVG and HTML documents that close.
fn assert_complete(dir: &Path) {
    for f in expected_files() {
        let text = std::fs::read_to_string(dir.join(&f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        if f.ends_with(".json") {
            let s: Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{f}: {e}"));
            assert_eq!(s["failures"], Value::Array(vec![]), "{f}");
        } else if f.ends_with(".csv") {
            let mut lines = text.lines();
            let width = fields(lines.next().expect("header")).len();
            assert!(text.ends_with('\n'), "{f} is cut short");
            for line in lines {
                assert_eq!(fields(line).len(), width, "{f}: {line}");
            }
        } else if f.ends_with(".svg") {
            assert!(text.trim_start().starts_with("<svg"), "{f}");
            assert!(text.trim_end().ends_with("</svg>"), "{f} is cut short");
            assert_eq!(text.matches("<svg").count(), 1, "{f}: two documents");
        } else {
            assert!(text.trim_end().ends_with("</html>"), "{f} is cut short");
            assert_eq!(text.matches("<html").count(), 1, "{f}: two documents");
        }
    }
}
