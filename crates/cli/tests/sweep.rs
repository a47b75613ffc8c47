//! `fpc sweep`: the grid's rows against independent single solves
//! (`fpc finger --json` at the same point), warm starts that change
//! nothing but the path, rejected points kept as rows, and bad flags.

mod common;
use common::{fpc, solve_into, TempDir};
use std::path::Path;
use std::process::Output;

fn sweep(scene: &Path, out: &Path, vary: &[&str]) -> Output {
    let mut args = vec![
        "sweep".to_string(),
        scene.display().to_string(),
        "--out".into(),
        out.display().to_string(),
    ];
    for v in vary {
        args.push("--vary".into());
        args.push(v.to_string());
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    fpc(&args)
}

fn rows(out: &Path) -> Vec<csv::StringRecord> {
    let mut r = csv::Reader::from_path(out.join("sweep.csv")).unwrap();
    r.records().map(|x| x.unwrap()).collect()
}

fn header(out: &Path) -> Vec<String> {
    let mut r = csv::Reader::from_path(out.join("sweep.csv")).unwrap();
    r.headers().unwrap().iter().map(String::from).collect()
}

#[test]
fn a_grid_matches_single_solves_point_by_point() {
    let tmp = TempDir::new("grid");
    let scene = tmp.0.join("finger.toml");
    std::fs::write(&scene, "[actuator.pemc]\neps0 = 0.3\n").unwrap();
    let out = tmp.0.join("out");
    let o = sweep(
        &scene,
        &out,
        &[
            "load.pressure_kpa=0,40",
            "load.fx=0:1:3",
            "load.fz=-0.2,0.3",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h = header(&out);
    assert_eq!(
        &h[..4],
        &["load.pressure_kpa", "load.fx", "load.fz", "status"]
    );
    let rows = rows(&out);
    assert_eq!(rows.len(), 2 * 3 * 2);
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    // the last axis varies fastest
    assert_eq!(&rows[0][2], "-0.2");
    assert_eq!(&rows[1][2], "0.3");
    assert_eq!(&rows[2][1], "0.5");
    for r in &rows {
        assert_eq!(&r[col("status")], "ok", "{r:?}");
        let (p, fx, fz) = (&r[0], &r[1], &r[2]);
        let single = fpc(&[
            "finger",
            "--eps0",
            "0.3",
            "--pressure-kpa",
            p,
            "--fx",
            fx,
            "--fz",
            fz,
            "--json",
        ]);
        assert!(single.status.success());
        let v: serde_json::Value = serde_json::from_slice(&single.stdout).unwrap();
        let tip = [
            v["tip_mm"][0].as_f64().unwrap(),
            v["tip_mm"][1].as_f64().unwrap(),
        ];
        let got = [
            r[col("tip_x_mm")].parse::<f64>().unwrap(),
            r[col("tip_z_mm")].parse::<f64>().unwrap(),
        ];
        // both converge to the same equilibrium (to the solver's
        // tolerance), the sweep from its neighbour
        for k in 0..2 {
            assert!((tip[k] - got[k]).abs() <= 1e-6, "{r:?}: {tip:?} vs {got:?}");
        }
        assert_eq!(&r[col("valid")], "true");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sweep.json")).unwrap()).unwrap();
    assert_eq!(json["points"], 12);
    assert_eq!(json["ok"], 12);
    assert_eq!(json["rows"].as_array().unwrap().len(), 12);
    assert!(json["provenance"]["git_commit"].is_string());
    assert_eq!(json["provenance"]["command"][1], "sweep");
}

/// A scene refined to a tip tolerance: each row's tip is the refinement's
/// best (extrapolated) tip, the one its `tip_error_mm` is of, and its
/// iterations are those of every level, as `fpc finger --json` at the same
/// point reports them (there cold, in the sweep from the row before).
#[test]
fn a_tip_tolerance_row_gives_the_tip_its_estimate_is_of() {
    let tmp = TempDir::new("tolerance");
    let scene = tmp.file(
        "tol.toml",
        b"[partition]\ntip_tol_mm = 0.05\n[load]\npressure_kpa = 50.0\nfz = 0.2\n",
    );
    let out = tmp.0.join("out");
    let o = sweep(&scene, &out, &["load.fx=0.3,0.5"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h = header(&out);
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    for (i, r) in rows(&out).iter().enumerate() {
        let single = fpc(&[
            "finger",
            "--pressure-kpa",
            "50",
            "--fx",
            &r[0],
            "--fz",
            "0.2",
            "--tip-tol-mm",
            "0.05",
            "--json",
        ]);
        assert!(single.status.success());
        let v: serde_json::Value = serde_json::from_slice(&single.stdout).unwrap();
        let best = &v["refinement"]["tip_mm"];
        for (k, name) in ["tip_x_mm", "tip_z_mm"].iter().enumerate() {
            let got: f64 = r[col(name)].parse().unwrap();
            assert!(
                (got - best[k].as_f64().unwrap()).abs() <= 1e-6,
                "{r:?}: {v}"
            );
        }
        let estimate: f64 = r[col("tip_error_mm")].parse().unwrap();
        let want = v["tip_error_estimate_mm"].as_f64().unwrap();
        assert!((estimate / want - 1.0).abs() < 1e-3, "{estimate} vs {want}");
        // the first row starts cold, as the single solve does
        let iterations: u64 = r[col("iterations")].parse().unwrap();
        let levels = v["refinement"]["level_iterations"].as_array().unwrap();
        let total: u64 = levels.iter().map(|l| l.as_u64().unwrap()).sum();
        assert!(
            iterations > 0 && (i > 0 || iterations == total),
            "{r:?}: {v}"
        );
    }
}

/// A scene with two explicit ribs, the first `width` mm wide.
fn ribbed(width: &str) -> String {
    format!(
        "[actuator.ribs]\nkind = \"list\"\nlist = [{{ x0 = 10.0, x1 = 14.0, width = {width} }}, {{ x0 = 30.0, x1 = 34.0, width = 4.0 }}]\n[load]\npressure_kpa = 30\n"
    )
}

#[test]
fn a_list_entry_is_varied_like_any_key() {
    // the typed key reaches into the rib list; every row equals `fpc solve`
    // of the file with that width written in by hand
    let tmp = TempDir::new("list");
    let scene = tmp.0.join("ribbed.toml");
    std::fs::write(&scene, ribbed("4.0")).unwrap();
    let out = tmp.0.join("out");
    let o = sweep(&scene, &out, &["actuator.ribs.list[0].width=2,8"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h = header(&out);
    assert_eq!(h[0], "actuator.ribs.list[0].width");
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let rows = rows(&out);
    assert_eq!(rows.len(), 2);
    let mut tips = Vec::new();
    for r in &rows {
        assert_eq!(&r[col("status")], "ok", "{r:?}");
        let by_hand = tmp.0.join(format!("width-{}.toml", &r[0]));
        std::fs::write(&by_hand, ribbed(&r[0])).unwrap();
        let solved = tmp.0.join(format!("solved-{}", &r[0]));
        let single = solve_into(&by_hand, &solved);
        assert!(single.status.success());
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(solved.join("solution.json")).unwrap())
                .unwrap();
        for (k, name) in ["tip_x_mm", "tip_z_mm"].iter().enumerate() {
            let got: f64 = r[col(name)].parse().unwrap();
            let want = v["tip_mm"][k].as_f64().unwrap();
            assert!((got - want).abs() <= 1e-6, "{r:?}: {want}");
        }
        tips.push(r[col("tip_x_mm")].to_string());
    }
    // the width reached the finger: the two rows differ
    assert_ne!(tips[0], tips[1]);
}

#[test]
fn an_invalid_grasp_row_says_why_as_fpc_solve_does() {
    // sphere grasps near a design's claim that are not valid (the friction
    // outside the cone; the tip reached from inside the sphere): each row's
    // message carries the verdict `fpc solve` prints
    let tmp = TempDir::new("invalid");
    let grasp = |r: &str| {
        format!(
            "[actuator.pemc]\neps0 = 0.12\n[gripper]\nmounting_angle_deg = 65.3\noverlap_mm = 0\n[gripper.grasp]\nkind = \"sphere\"\nr_mm = {r}\nbeta_deg = 15.67\nlift_n = 0.5262\n"
        )
    };
    let scene = tmp.file("sphere.toml", grasp("35").as_bytes());
    let out = tmp.0.join("out");
    let o = sweep(&scene, &out, &["gripper.grasp.r_mm=31.5,35"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h = header(&out);
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let mut invalid = 0;
    for r in &rows(&out) {
        let by_hand = tmp.file(&format!("r{}.toml", &r[0]), grasp(&r[0]).as_bytes());
        let solved = tmp.0.join(format!("solved-{}", &r[0]));
        let single = solve_into(&by_hand, &solved);
        assert!(single.status.success());
        let text = String::from_utf8_lossy(&single.stdout).into_owned();
        let line = text
            .lines()
            .find(|l| l.starts_with("valid "))
            .unwrap()
            .trim_start_matches("valid")
            .trim()
            .to_string();
        match line.strip_prefix("NO: ") {
            None => {
                assert_eq!(&r[col("valid")], "true", "{r:?}");
                assert!(!r[col("message")].contains("not valid"), "{r:?}");
            }
            Some(why) => {
                invalid += 1;
                assert_eq!(&r[col("valid")], "false", "{r:?}");
                assert!(
                    r[col("message")].contains(&format!("not valid: {why}")),
                    "{r:?} against {why}"
                );
            }
        }
    }
    assert!(invalid > 0, "no invalid row to check");
}

#[test]
fn a_rejected_point_is_a_row_not_the_end_of_the_sweep() {
    let tmp = TempDir::new("rejected");
    let scene = tmp.0.join("finger.toml");
    std::fs::write(&scene, "").unwrap();
    let out = tmp.0.join("out");
    // kappa = 0 is rejected by the library; the others solve
    let o = sweep(&scene, &out, &["load.kappa=1,0,2"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h = header(&out);
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let rows = rows(&out);
    let status: Vec<&str> = rows.iter().map(|r| &r[col("status")]).collect();
    assert_eq!(status, ["ok", "rejected", "ok"]);
    assert!(
        rows[1][col("message")].contains("load.kappa"),
        "{:?}",
        rows[1]
    );
}

#[test]
fn bad_flags_are_rejected() {
    let tmp = TempDir::new("flags");
    let scene = tmp.0.join("finger.toml");
    std::fs::write(&scene, "").unwrap();
    let out = tmp.0.join("out");
    for (vary, part) in [
        ("load.fx", "expected KEY=FROM:TO:COUNT"),
        ("load.fx=1:2", "FROM:TO:COUNT"),
        ("load.fx=a", "is not a number"),
        (
            "load.fxx=1,2",
            "--vary load.fxx=1,2: `load.fxx` is not a key of a scene file (the nearest is `load.fx`)",
        ),
        (
            "model.name=0:1:3",
            "--vary model.name: the key takes a name, not a number",
        ),
        (
            "gripper.strict=0,1",
            "--vary gripper.strict: the key takes true or false, not a number",
        ),
        ("load.fx.y=1,2", "not a key of a scene file"),
        // a list entry the file does not have; a fraction of an element
        (
            "partition.lengths[0]=10,20",
            "--vary partition.lengths[0]: the scene has no list 'lengths'",
        ),
        (
            "partition.elements=4:5:3",
            "--vary partition.elements = 4.5: must be a whole number",
        ),
    ] {
        let o = sweep(&scene, &out, &[vary]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{vary}: {err}");
        assert!(err.contains(part), "{vary}: {err}");
        // no line:column of the document fpc wrote for the point
        assert!(
            !err.contains(": 1:") && !err.contains(": 5:"),
            "{vary}: {err}"
        );
        assert!(!out.join("sweep.csv").exists(), "{vary}");
    }
    let o = sweep(&scene, &out, &["load.fx=1,2", "load.fx=3"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("varied twice"));
}

/// Ctrl-C (one SIGINT) stops a long sweep: the points done are written,
/// the rest are `stopped` rows, the status is 130, and the points done
/// are the answers of an uninterrupted sweep over exactly those points
/// (the same warm chain, solved again through the ordinary path).
#[cfg(unix)]
#[test]
fn ctrl_c_writes_the_points_done() {
    use std::io::{BufRead as _, BufReader, Read as _};
    use std::process::Stdio;
    let tmp = TempDir::new("ctrl_c");
    // about 0.3 ms a point in a release build (6 s in all), far more in
    // a debug one: the first progress line (after 0.5 s) comes long before
    // the end
    let scene = tmp.file(
        "long.toml",
        b"[actuator.pemc]\neps0 = 0.3\n[partition]\nelements = 400\n",
    );
    let out = tmp.0.join("out");
    let total = 20_000;
    let mut command = common::fpc_as_in_a_terminal();
    let mut child = command
        .arg("sweep")
        .arg(&scene)
        .args(["--vary", &format!("load.fx=0:1:{total}"), "--threads", "1"])
        .arg("--out")
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    // wait for the first progress line: the work has begun
    while !seen.contains("fpc sweep: ") {
        assert!(err.read_line(&mut seen).unwrap() > 0, "no progress: {seen}");
    }
    common::ctrl_c(&child);
    err.read_to_string(&mut seen).unwrap();
    let status = child.wait().unwrap();
    let mut stdout = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut stdout)
        .unwrap();
    assert_eq!(status.code(), Some(130), "{seen}");
    assert!(seen.contains("fpc: Ctrl-C: stopping"), "{seen}");
    assert!(seen.contains("fpc: stopped by Ctrl-C: "), "{seen}");
    assert!(!seen.contains("error"), "{seen}");
    assert!(stdout.contains("stopped (Ctrl-C)"), "{stdout}");

    let h = header(&out);
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let written = rows(&out);
    assert_eq!(written.len(), total);
    // one line on one thread: the points done are a prefix
    let done = written
        .iter()
        .position(|r| &r[col("status")] != "ok")
        .unwrap();
    assert!(done > 0);
    for r in &written[done..] {
        assert_eq!(&r[col("status")], "stopped", "{r:?}");
        assert_eq!(&r[col("tip_x_mm")], "");
        assert!(r[col("message")].contains("Ctrl-C"));
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sweep.json")).unwrap()).unwrap();
    assert_eq!(json["points"], total);
    assert_eq!(json["ok"], done);
    assert_eq!(json["stopped"], total - done);
    assert!(
        seen.contains(&format!("{done} of {total} points done")),
        "{seen}"
    );

    // the same points, uninterrupted (the values as the CSV wrote them)
    let values: Vec<&str> = written[..done].iter().map(|r| &r[0]).collect();
    let again = tmp.0.join("again");
    let list = format!("load.fx={}", values.join(","));
    let o = fpc(&[
        "sweep",
        &scene.display().to_string(),
        "--vary",
        &list,
        "--threads",
        "1",
        "--out",
        &again.display().to_string(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(rows(&again), written[..done]);
}

/// `FPC_PROGRESS_AFTER_S` sets the quiet time: at 0 a run of a second or
/// more writes its counts into a log at once; at the tests' usual large
/// value the same run writes nothing (README, "Progress").
#[test]
fn the_quiet_time_is_the_variable_s() {
    let tmp = TempDir::new("quiet");
    // 1000 points on 400 elements: about 0.3 s in a release build, far
    // longer in a debug one, over the first redraw (0.2 s) in either
    let scene = tmp.file(
        "long.toml",
        b"[actuator.pemc]\neps0 = 0.3\n[partition]\nelements = 400\n",
    );
    let run = |quiet: &str, out: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_fpc"))
            .env(common::QUIET, quiet)
            .arg("sweep")
            .arg(&scene)
            .args(["--vary", "load.fx=0:1:1000", "--threads", "1", "--out"])
            .arg(tmp.0.join(out))
            .output()
            .unwrap()
    };
    let at_once = run("0", "a");
    assert!(at_once.status.success());
    let log = String::from_utf8_lossy(&at_once.stderr);
    assert!(log.starts_with("fpc sweep: "), "{log}");
    assert!(log.contains("/1000 points"), "{log}");
    let quiet = run(common::NEVER, "b");
    assert!(quiet.status.success());
    assert!(
        quiet.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&quiet.stderr)
    );
}

#[test]
fn help_states_the_grid_limits() {
    // the caps parse_axis and the grid check enforce, said where the flag is
    let out = fpc(&["sweep", "--help"]);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(help.contains("at most 100000 values"), "{help}");
    assert!(help.contains("at most 1000000 points"), "{help}");
}
