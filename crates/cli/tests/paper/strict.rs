//! `--strict`.

use std::path::Path;

use serde_json::Value;

use super::{fpc, tmp};

/// `--strict` drops the grasps that bend an element backwards: fewer rows,
/// counted under `validity`, and none of the remaining rows reversed.
#[test]
fn strict_mode_drops_reversed_grasps() {
    let scratch = tmp("strict");
    let base = scratch.path();
    let run = |name: &str, strict: bool| {
        let dir = base.join(name);
        let mut cmd = fpc();
        cmd.args(["paper", "--coarse", "--out"]).arg(&dir);
        if strict {
            cmd.arg("--strict");
        }
        let out = cmd.output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let s: Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        (dir, s)
    };
    let (loose_dir, loose) = run("loose", false);
    let (strict_dir, strict) = run("strict", true);
    assert_eq!(strict["strict"], Value::Bool(true));
    assert_eq!(strict["options"]["strict"], Value::Bool(true));
    let count =
        |s: &Value, n: u32, what: &str| s["validity"][format!("study{n}")][what].as_u64().unwrap();
    let reversed = |s: &Value, n: u32| {
        s["validity"][format!("study{n}")]["warnings_by_kind"]["curvature_reversal"]
            .as_u64()
            .unwrap()
    };
    // study 1: every reversed grasp of the default run is dropped
    let dropped = count(&strict, 1, "strict_dropped");
    assert!(dropped > 0, "the coarse study 1 has reversed grasps");
    assert_eq!(dropped, reversed(&loose, 1));
    assert_eq!(reversed(&strict, 1), 0);
    assert_eq!(
        count(&strict, 1, "points") + dropped,
        count(&loose, 1, "points")
    );
    let rows = |dir: &Path| {
        std::fs::read_to_string(dir.join("study1.csv"))
            .unwrap()
            .lines()
            .count()
    };
    assert_eq!(rows(&strict_dir) + dropped as usize, rows(&loose_dir));
    // study 5 drops its reversed sweep grasps too
    assert!(count(&strict, 5, "strict_dropped") > 0);
    assert!(
        strict["sphere_region"]["valid_points"].as_u64()
            < loose["sphere_region"]["valid_points"].as_u64()
    );
    for n in 1..=8 {
        assert_eq!(count(&loose, n, "strict_dropped"), 0, "not strict");
    }
    let html = std::fs::read_to_string(strict_dir.join("index.html")).unwrap();
    assert!(html.contains("strict mode"));
}
