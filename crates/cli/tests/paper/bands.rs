//! A scene with a calibration's covariance: `_sd` columns and bands in
//! the studies that propagate it, nothing else changed; none without it.

use std::path::Path;

use serde_json::Value;

use super::{fields, fpc, number, tmp};

/// A calibrated scene's covariance (as `fpc calibrate` writes one: the
/// prestrain, kappa and the prestressed layer's p1), and the same scene
/// without it.
const CALIBRATED: &str = r#"
[actuator.pemc]
eps0 = 0.25
[load]
kappa = 2.5
[partition]
elements = 4
[calibration]
parameters = ["actuator.pemc.eps0", "load.kappa", "actuator.pemc.p1"]
covariance = [[1.8e-6, -2.9e-5, -2.1e-5], [-2.9e-5, 6.1e-4, 3.8e-4], [-2.1e-5, 3.8e-4, 2.7e-4]]
"#;

/// A CSV without its `_sd` columns, and without the notes that say why
/// a row has no error bars.
fn without_sd(csv: &str) -> String {
    let mut lines = csv.lines();
    let header = fields(lines.next().unwrap());
    let keep: Vec<bool> = header.iter().map(|h| !h.ends_with("_sd")).collect();
    let mut out = String::new();
    for line in csv.lines() {
        let row: Vec<String> = fields(line)
            .into_iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(f, _)| {
                if f.starts_with("no error bar") {
                    return String::new();
                }
                if f.contains([',', '"']) {
                    format!("\"{}\"", f.replace('"', "\"\""))
                } else {
                    f
                }
            })
            .collect();
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

#[test]
fn paper_scene_bands_only_with_a_covariance() {
    let scratch = tmp("bands");
    let base = scratch.path();
    let with = base.join("calibrated.toml");
    let without = base.join("plain.toml");
    std::fs::write(&with, CALIBRATED).unwrap();
    std::fs::write(&without, CALIBRATED.split("[calibration]").next().unwrap()).unwrap();
    let run = |scene: &Path, out: &str| {
        let dir = base.join(out);
        let o = fpc()
            .args(["paper", "--coarse", "--scene"])
            .arg(scene)
            .arg("--out")
            .arg(&dir)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        dir
    };
    let (plain, banded) = (run(&without, "plain"), run(&with, "banded"));
    let read = |d: &Path, f: &str| std::fs::read_to_string(d.join(f)).unwrap();
    let csvs: Vec<String> = std::fs::read_dir(&plain)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".csv"))
        .collect();
    assert!(csvs.len() >= 10, "{csvs:?}");
    // without a covariance: no _sd column, no band, no uncertainty entry
    for f in &csvs {
        let header = read(&plain, f).lines().next().unwrap().to_string();
        assert!(!header.contains("_sd"), "{f}: {header}");
    }
    let s: Value = serde_json::from_str(&read(&plain, "summary.json")).unwrap();
    assert!(s.get("uncertainty").is_none());
    assert!(!read(&plain, "study7.svg").contains("1 sd"));
    // with one: the banded studies gain _sd columns and nothing else
    // changes; the other studies are the same bytes
    for f in &csvs {
        let (a, b) = (read(&plain, f), read(&banded, f));
        if [
            "study1.csv",
            "study2.csv",
            "study3.csv",
            "study4.csv",
            "study5_envelope.csv",
            "study6.csv",
            "study7.csv",
            "study8.csv",
        ]
        .contains(&f.as_str())
        {
            assert_ne!(a, b, "{f}");
            assert_eq!(without_sd(&b), without_sd(&a), "{f} beyond its _sd columns");
        } else {
            assert_eq!(a, b, "{f}");
        }
    }
    // study 1's eps0 = 0.4 fingers curl past their tips: no bands, and why
    let study1 = read(&banded, "study1.csv");
    let why = study1.lines().filter(|l| l.starts_with("0.4,")).all(|l| {
        l.contains("no error bars") && l.contains("innermost point") && l.contains(",,,,")
    });
    assert!(why, "{study1}");
    let header7 = fields(read(&banded, "study7.csv").lines().next().unwrap());
    for c in [
        "radius_mm_sd",
        "curvature_per_mm_sd",
        "end_angle_rad_sd",
        "tip_x_mm_sd",
        "tip_z_mm_sd",
    ] {
        assert!(header7.iter().any(|h| h == c), "{c} in {header7:?}");
    }
    let csv8 = read(&banded, "study8.csv");
    let header8 = fields(csv8.lines().next().unwrap());
    let col = header8.iter().position(|h| h == "force_n_sd").unwrap();
    for line in csv8.lines().skip(1) {
        let sd: f64 = fields(line)[col].parse().unwrap();
        assert!(sd > 0.0 && sd.is_finite(), "{line}");
    }
    assert!(read(&banded, "study5.svg").contains("1 sd"));
    assert!(read(&banded, "study6.svg").contains("1 sd"));
    assert!(read(&banded, "study7.svg").contains("1 sd"));
    assert!(read(&banded, "study8.svg").contains("1 sd"));
    let s: Value = serde_json::from_str(&read(&banded, "summary.json")).unwrap();
    let u = &s["uncertainty"];
    assert_eq!(u["propagated"], serde_json::json!(["actuator.pemc.p1"]));
    let left: Vec<&str> = u["not_propagated"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["parameter"].as_str().unwrap())
        .collect();
    assert_eq!(left, ["actuator.pemc.eps0", "load.kappa"]);
    assert_eq!(
        u["studies_with_bands"],
        serde_json::json!([1, 2, 3, 4, 5, 6, 7, 8])
    );
    assert_eq!(u["methods"]["study1"]["fv_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study2"]["dmax_mm_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study3"]["fv_max_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study4"]["F_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study5"]["fv_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study5"]["F_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study6"]["f_n_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study7"]["radius_mm_sd"], "first_order_exact");
    assert_eq!(u["methods"]["study8"]["force_n_sd"], "first_order_exact");
    let row = &s["force_at_10mm"][0];
    assert!(number(&row["force_n_sd"], "force_n_sd") > 0.0);
    let peak = &s["sphere_region"]["peak"];
    assert!(number(&peak["fv_n_sd"], "fv_n_sd") > 0.0);
    // the envelope's band: positive wherever a row has one, and most do
    let csv5 = read(&banded, "study5_envelope.csv");
    let header5 = fields(csv5.lines().next().unwrap());
    let (fv, f) = (
        header5.iter().position(|h| h == "fv_n_sd").unwrap(),
        header5.iter().position(|h| h == "F_n_sd").unwrap(),
    );
    let rows5: Vec<Vec<String>> = csv5.lines().skip(1).map(fields).collect();
    let banded5 = rows5.iter().filter(|r| !r[fv].is_empty()).count();
    assert!(2 * banded5 > rows5.len(), "{csv5}");
    for r in &rows5 {
        if r[fv].is_empty() {
            assert!(
                r[f].is_empty() && r.iter().any(|c| c.starts_with("no error bars")),
                "{r:?}"
            );
        } else {
            let (a, b): (f64, f64) = (r[fv].parse().unwrap(), r[f].parse().unwrap());
            assert!(
                a > 0.0 && b > 0.0 && a.is_finite() && b.is_finite(),
                "{r:?}"
            );
        }
    }
    // study 6: both ends of its viable interval move
    let ends = &s["sphere_viable_angles"]["intervals_sd_rad"][0];
    assert!(number(&ends[0], "lower end's sd") > 0.0);
    assert!(number(&ends[1], "upper end's sd") > 0.0);
    let point = &s["radius_vs_pressure"][0]["points"][0];
    assert!(number(&point["radius_mm_sd"], "radius_mm_sd") > 0.0);
}
