//! `fpc calibrate`: the shipped synthetic set is fitted into
//! calibration.json and one calibrated scene per specimen, which `fpc
//! solve` reads with its `[calibration]` table; bad options exit with
//! status 2 and one line naming the field.

mod common;

use std::path::Path;

use common::{fpc, rejected, shipped, text};
use tempfile::TempDir;

fn tmp(name: &str) -> TempDir {
    common::tmp("calibrate", name)
}

#[test]
fn the_synthetic_set_is_calibrated_into_json_and_scenes() {
    let dir = tmp("run");
    let out = dir.path();
    let o = out.display().to_string();
    let run = fpc(&["calibrate", &shipped(), "--fit", "eps0,kappa", "--out", &o]);
    let stdout = text(&run.stdout);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    assert!(stdout.starts_with("parameter"), "{stdout}");
    assert!(stdout.contains("identify     identifiable"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("calibration.json")).unwrap())
            .unwrap();
    let params = json["parameters"].as_array().unwrap();
    // eps0 per specimen (their own tables), kappa shared
    assert_eq!(params.len(), 4);
    // the README's truth within three standard errors
    for p in params {
        let truth = match p["name"].as_str().unwrap() {
            "actuator.pemc.eps0[eps0-0.15]" => 0.15,
            "actuator.pemc.eps0[eps0-0.25]" => 0.25,
            "actuator.pemc.eps0[eps0-0.4]" => 0.4,
            "load.kappa" => 2.5,
            n => panic!("{n}"),
        };
        let (v, se) = (
            p["value"].as_f64().unwrap(),
            p["standard_error"].as_f64().unwrap(),
        );
        assert!((v - truth).abs() < 3.0 * se, "{p}");
    }
    let chi = json["chi_square"].as_f64().unwrap();
    let z: f64 = json["residuals"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["residual_sd"].as_f64().unwrap().powi(2))
        .sum();
    assert!((chi - z).abs() <= 1e-9 * chi, "{chi} vs {z}");
    assert_eq!(
        json["dof"].as_u64(),
        Some(json["points"].as_u64().unwrap() - 4)
    );
    assert!(json["provenance"]["fpc_version"].is_string());
    // each scene solves, and carries its keys and covariance
    let scenes = json["scenes"].as_array().unwrap();
    assert_eq!(scenes.len(), 3);
    for s in scenes {
        let path = out.join(s.as_str().unwrap());
        let scene = std::fs::read_to_string(&path).unwrap();
        assert!(
            scene.contains("[calibration]") && scene.contains("covariance"),
            "{scene}"
        );
        let sol = out.join(format!("solved-{}", s.as_str().unwrap()));
        let r = fpc(&[
            "solve",
            &path.display().to_string(),
            "--out",
            &sol.display().to_string(),
        ]);
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    }
    // the fit was checked through fpc compare's path, and says so
    assert_eq!(
        json["reproduction"]["reproduced"], true,
        "{}",
        json["reproduction"]
    );
    assert!(
        stdout.contains("check        calibrated scenes compared again as fpc compare does: the fit is reproduced"),
        "{stdout}"
    );
    // and a user can do the same: the shipped manifest with each
    // specimen's calibrated scene in place of its own prestrain (the scene
    // carries the fitted load.kappa), compared, gives the fit's chi-square
    let shipped_dir = Path::new(&shipped()).parent().unwrap().to_path_buf();
    let mut manifest = std::fs::read_to_string(shipped()).unwrap();
    for (name, eps0) in [
        ("eps0-0.15", "0.15"),
        ("eps0-0.25", "0.25"),
        ("eps0-0.4", "0.4"),
    ] {
        let own = format!("name = \"{name}\"\n[specimen.own.actuator.pemc]\neps0 = {eps0}\n");
        assert!(manifest.contains(&own), "{manifest}");
        manifest = manifest.replace(
            &own,
            &format!("name = \"{name}\"\nscene = \"{name}.toml\"\n"),
        );
    }
    for f in std::fs::read_dir(&shipped_dir).unwrap() {
        let f = f.unwrap().path();
        if f.extension().is_some_and(|e| e == "csv") {
            std::fs::copy(&f, out.join(f.file_name().unwrap())).unwrap();
        }
    }
    std::fs::write(out.join("again.toml"), manifest).unwrap();
    let c = fpc(&[
        "compare",
        &out.join("again.toml").display().to_string(),
        "--out",
        &out.join("again").display().to_string(),
        "--json",
    ]);
    assert_eq!(c.status.code(), Some(0), "{}", text(&c.stderr));
    let again: serde_json::Value = serde_json::from_slice(&c.stdout).unwrap();
    let chi_again = again["chi_square"].as_f64().unwrap();
    assert!(
        (chi_again - chi).abs() <= 1e-9 * chi,
        "{chi_again} vs {chi}"
    );
    // --json prints the same object
    let j = fpc(&[
        "calibrate",
        &shipped(),
        "--fit",
        "eps0,kappa",
        "--out",
        &o,
        "--json",
    ]);
    let printed: serde_json::Value = serde_json::from_slice(&j.stdout).unwrap();
    assert_eq!(printed["chi_square"], json["chi_square"]);
}

#[test]
fn bad_options_exit_2_naming_the_flag() {
    let m = shipped();
    let bad = tmp("bad");
    let o = bad.path().display().to_string();
    rejected(
        &["calibrate", &m, "--fit", "nonsense", "--out", &o],
        &["--fit = `nonsense`"],
    );
    rejected(
        &["calibrate", &m, "--fit", "eps0,eps0", "--out", &o],
        &["--fit", "twice"],
    );
    rejected(
        &[
            "calibrate",
            &m,
            "--fit",
            "eps0",
            "--max-iterations",
            "0",
            "--out",
            &o,
        ],
        &["--max-iterations = 0"],
    );
    rejected(&["calibrate", &m, "--out", &o], &["--fit"]);
    rejected(
        &["calibrate", "no-such-manifest.toml", "--fit", "eps0"],
        &["no-such-manifest.toml"],
    );
    // a bad scene table: fpc solve names the calibration key
    let dir = tmp("scene");
    let d = dir.path();
    let s = d.join("s.toml");
    std::fs::write(
        &s,
        "[calibration]\nparameters = [\"actuator.pemc.eps0\"]\ncovariance = [[1.0, 2.0]]\n",
    )
    .unwrap();
    rejected(
        &[
            "solve",
            &s.display().to_string(),
            "--out",
            &d.join("o").display().to_string(),
        ],
        &["calibration.covariance"],
    );
}

#[test]
fn a_reader_gone_ends_it_quietly_after_the_files_are_written() {
    let dir = tmp("pipe");
    let out = dir.path();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_fpc"))
        .env(common::QUIET, common::NEVER)
        .args([
            "calibrate",
            &shipped(),
            "--fit",
            "eps0",
            "--out",
            &out.display().to_string(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // the reader goes away before the fit prints anything
    drop(child.stdout.take());
    let done = child.wait_with_output().unwrap();
    assert_eq!(done.status.code(), Some(0), "{}", text(&done.stderr));
    // nor is there progress: the fit ends within its first 2 s
    assert!(done.stderr.is_empty(), "{}", text(&done.stderr));
    assert!(out.join("calibration.json").is_file());
}

#[test]
fn choose_model_ranks_every_model_with_and_without_ribs_in_both_plane_states() {
    // one specimen's radii from the shipped set: a small fit, each
    // candidate cross-validated over its nine pressures
    let dir = tmp("choice");
    let out = dir.path();
    let shipped_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/calibration");
    std::fs::copy(
        shipped_dir.join("eps0-0.4_radius.csv"),
        out.join("radius.csv"),
    )
    .unwrap();
    std::fs::write(
        out.join("manifest.toml"),
        "[[specimen]]\nname = \"a\"\n[specimen.own.actuator.pemc]\neps0 = 0.38\n[[specimen.test]]\nkind = \"radius\"\nfile = \"radius.csv\"\n",
    )
    .unwrap();
    let m = out.join("manifest.toml").display().to_string();
    let o = out.join("out").display().to_string();
    let run = fpc(&[
        "calibrate",
        &m,
        "--fit",
        "eps0",
        "--choose-model",
        "--json",
        "--out",
        &o,
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let json: serde_json::Value = serde_json::from_str(&text(&run.stdout)).unwrap();
    let choice = &json["model_choice"];
    let candidates = choice["candidates"].as_array().unwrap();
    // with and without ribs, in plane stress then in plane strain
    assert_eq!(candidates.len(), 4 * fpc::ModelId::ALL.len(), "{choice}");
    let n = 2 * fpc::ModelId::ALL.len();
    assert!(candidates[..n].iter().all(|c| c["plane_strain"] == false));
    assert!(candidates[n..].iter().all(|c| c["plane_strain"] == true));
    // the best has the smallest held-out error
    let err = |c: &serde_json::Value| c["held_out_rms_sd"].as_f64().unwrap();
    let best = &candidates[choice["best"].as_u64().unwrap() as usize];
    assert!(candidates.iter().all(|c| err(best) <= err(c)), "{choice}");
    // the manifest's own model and ribs, fitted again with the
    // cross-validation, give the plain calibration's prestrain
    let own = candidates
        .iter()
        .find(|c| c["model"] == "ccm" && c["ribs"] == true && c["plane_strain"] == false)
        .unwrap();
    let plain = json["parameters"][0]["value"].as_f64().unwrap();
    let again = own["values"][0].as_f64().unwrap();
    assert!((plain - again).abs() <= 1e-9 * plain, "{plain} vs {again}");
    assert!((plain - 0.4).abs() < 0.02, "{plain}");
}

/// A fit longer than 2 s says how far it has got on stderr also when
/// stderr is a log: whole lines with the iteration, the evaluations, the
/// specimens solved of the evaluation under way and the chi-square. The
/// data: 32 specimens, each with its own eps0 and 300 force rows at
/// distinct pressures (every row a solve and a target solve per
/// evaluation), several seconds of work even in a release build.
#[test]
fn a_long_fit_writes_its_progress_into_a_log() {
    use std::io::BufRead as _;
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let dir = tmp("progress");
    let rows: String = (0..300)
        .map(|i| format!("{},Z,10,0.3,0.02,5\n", 0.5 * f64::from(i)))
        .collect();
    std::fs::write(
        dir.path().join("f.csv"),
        format!("pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n{rows}"),
    )
    .unwrap();
    let manifest: String = (0..32)
        .map(|i| {
            format!(
                "[[specimen]]\nname = \"s{i}\"\n[specimen.own.actuator.pemc]\neps0 = {}\n[[specimen.test]]\nkind = \"force\"\nfile = \"f.csv\"\n",
                0.2 + 0.001 * f64::from(i)
            )
        })
        .collect();
    let path = dir.path().join("manifest.toml");
    std::fs::write(&path, manifest).unwrap();
    let started = Instant::now();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_fpc"))
        .arg("calibrate")
        .arg(&path)
        .args(["--fit", "eps0", "--out"])
        .arg(dir.path().join("out"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stderr = child.stderr.take().unwrap();
    let first = std::io::BufReader::new(stderr).lines().next();
    let waited = started.elapsed();
    let _ = child.kill();
    let _ = child.wait();
    let first = match first {
        Some(Ok(line)) => line,
        other => panic!("no progress line: {other:?}"),
    };
    assert!(waited >= Duration::from_secs(2), "{waited:?}: {first}");
    let rest = first
        .strip_prefix("fpc calibrate: fitting: iteration ")
        .unwrap_or_else(|| panic!("{first}"));
    let (iteration, rest) = rest
        .split_once("/100, ")
        .unwrap_or_else(|| panic!("{first}"));
    let (evaluations, rest) = rest
        .split_once(" evaluations done (the next: ")
        .unwrap_or_else(|| panic!("{first}"));
    let (solved, chi2) = rest
        .split_once("/32 specimens solved), chi2 ")
        .unwrap_or_else(|| panic!("{first}"));
    let count = |s: &str| s.parse::<usize>().unwrap_or_else(|_| panic!("{first}"));
    assert!(count(iteration) <= count(evaluations), "{first}");
    assert!(count(solved) <= 32, "{first}");
    // the chi-square is known only once the start is evaluated
    if count(evaluations) == 0 {
        assert_eq!(chi2, "not known yet", "{first}");
    }
    assert!(
        chi2 == "not known yet" || chi2.parse::<f64>().is_ok_and(|c| c.is_finite() && c >= 0.0),
        "{first}"
    );
}
