//! Extreme values through every numeric flag of the user's commands and
//! every numeric key of a scene: each run must answer (status 0 or 1 with a
//! reason) or refuse cleanly (status 2, one `fpc: error:` line), never
//! panic, abort, die of a signal or hang. Seeded; each run is killed after
//! a time limit, which fails the test.

mod common;

use std::time::Duration;

use tempfile::TempDir;

/// No single run may take longer (a debug build; the slowest legal run
/// here, a refined finger, takes about a second).
const LIMIT: Duration = Duration::from_secs(120);

const EXTREMES: [&str; 12] = [
    "0",
    "-1",
    "1e308",
    "-1e308",
    "nan",
    "inf",
    "-inf",
    "18446744073709551615",
    "1e-320",
    "",
    "abc",
    "0x10",
];

fn tmp(name: &str) -> TempDir {
    common::tmp("fuzz", name)
}

/// Runs `fpc args` to its end or the limit; the status and stderr.
fn run(args: &[String]) -> (Option<i32>, String) {
    let out = common::fpc_within(args, LIMIT);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Answered or refused cleanly.
fn clean(args: &[String]) {
    let (code, stderr) = run(args);
    assert!(
        matches!(code, Some(0..=2)),
        "fpc {args:?}: status {code:?} (a signal?): {stderr}"
    );
    assert!(!stderr.contains("panicked"), "fpc {args:?}: {stderr}");
    assert!(!stderr.contains("RUST_BACKTRACE"), "fpc {args:?}: {stderr}");
    if code == Some(2) {
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.is_empty()).collect();
        let errors = lines
            .iter()
            .filter(|l| l.starts_with("fpc: error: "))
            .count();
        assert_eq!(errors, 1, "fpc {args:?}: {stderr}");
    }
}

fn strings(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

#[test]
fn every_numeric_flag_takes_extreme_values_cleanly() {
    let scratch = tmp("flags");
    let dir = scratch.path();
    let out = dir.join("out").to_string_lossy().into_owned();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/default.toml");
    // a small design (one width, one variable): a legal --starts runs a
    // whole search, which must stay well inside the limit on a loaded
    // machine in the debug build
    let design_file = dir.join("small_design.toml");
    std::fs::write(
        &design_file,
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [90.0, 90.0]\nlift_n = 0.3\n[vary]\neps0 = [0.2, 0.3]\n",
    )
    .unwrap();
    let design = design_file.to_str().unwrap();
    let flags: [(&[&str], &str); 12] = [
        (&["finger"], "--eps0"),
        (&["finger"], "--pressure-kpa"),
        (&["finger"], "--fx"),
        (&["finger"], "--fz"),
        (&["finger"], "--kappa"),
        (&["finger"], "--elements"),
        (&["finger"], "--levels"),
        (&["finger"], "--tip-tol-mm"),
        (&["paper", "--coarse", "--out", &out], "--width-in"),
        (&["paper", "--coarse", "--out", &out], "--font-pt"),
        (&["sweep", scene, "--out", &out], "--threads"),
        (&["design", design, "--out", &out], "--starts"),
    ];
    // seeded choice of the extreme values per flag (all of them for the
    // cheap commands; the others get the values that cannot start work)
    for (cmd, flag) in flags {
        for v in EXTREMES {
            let costly = matches!(cmd[0], "paper" | "design" | "sweep");
            if costly && matches!(v, "0x10" | "1e-320") {
                continue;
            }
            let mut args = strings(cmd);
            if cmd[0] == "sweep" {
                args.extend(strings(&["--vary", "load.fx=0,1"]));
            }
            args.push(format!("{flag}={v}"));
            clean(&args);
        }
    }
    // and extreme --vary specs
    for v in EXTREMES {
        for spec in [
            format!("load.fx={v}"),
            format!("load.fx=0:1:{v}"),
            format!("partition.elements={v},8"),
            format!("actuator.geometry.lx={v}"),
        ] {
            clean(&strings(&["sweep", scene, "--out", &out, "--vary", &spec]));
        }
    }
}

/// A small seeded generator (no dependency for a test).
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) % n as u64) as usize
    }
}

#[test]
fn every_numeric_scene_key_takes_extreme_values_cleanly() {
    let scratch = tmp("scenes");
    let dir = scratch.path();
    let keys: [(&str, &str); 22] = [
        ("actuator.geometry", "lx"),
        ("actuator.geometry", "ly"),
        ("actuator.geometry", "h"),
        ("actuator.geometry", "h1"),
        ("actuator.geometry", "h3"),
        ("actuator.channel", "cx"),
        ("actuator.channel", "cy"),
        ("actuator.pemc", "eps0"),
        ("load", "pressure_kpa"),
        ("load", "fx"),
        ("load", "kappa"),
        ("partition", "elements"),
        ("partition", "tip_tol_mm"),
        ("solve", "rtol"),
        ("solve", "max_iter"),
        ("solve", "samples_per_element"),
        ("gripper", "mounting_angle_deg"),
        ("gripper", "overlap_mm"),
        ("gripper", "fingers"),
        ("gripper", "mu"),
        ("gripper.grasp", "d_mm"),
        ("gripper.grasp", "friction_n"),
    ];
    // TOML spellings of the extremes (a bare word is not TOML: the file
    // is refused as such, which is clean too)
    let values = [
        "0",
        "-1",
        "1e308",
        "-1e308",
        "nan",
        "inf",
        "-inf",
        "1e-320",
        "9223372036854775807",
        "-9223372036854775808",
        "0.5",
    ];
    let mut rng = Lcg(7);
    for (table, key) in keys {
        // four values per key, seeded
        for _ in 0..4 {
            let v = values[rng.below(values.len())];
            let gripper = table.starts_with("gripper");
            let mut text = String::new();
            if gripper {
                text.push_str("[gripper]\n[gripper.grasp]\nkind = \"cuboid\"\n");
            }
            if table == "gripper" {
                text = format!("[gripper]\n{key} = {v}\n[gripper.grasp]\nkind = \"cuboid\"\n");
            } else {
                text.push_str(&format!("[{table}]\n{key} = {v}\n"));
            }
            let path = dir.join(format!("{table}.{key}.toml"));
            std::fs::write(&path, &text).unwrap();
            let out = dir.join("out");
            clean(&[
                "solve".into(),
                path.to_string_lossy().into_owned(),
                "--out".into(),
                out.to_string_lossy().into_owned(),
            ]);
        }
    }
}
