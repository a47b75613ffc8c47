//! `fpc::compare` against independent paths of the library: radii against
//! study 7, a marker at the tip against an ordinary solve's tip (also
//! through a camera frame), forces against study 8, noise-free synthetic
//! data (examples/calibration/make_data.rs) at chi-square ~ 0 and a wrong
//! prestrain far from it, and the validity verdict on every prediction.

use std::path::Path;

use fpc::measure::{Comparison, Manifest, MeasureError, Prediction};
use fpc::studies::{study7_curvature, study8_force_at_displacement, Axis};
use fpc::{Finger, Load, SolveOptions, StudyOptions};
use tempfile::TempDir;

#[path = "../examples/calibration/make_data.rs"]
mod synthetic;

/// A fresh directory, removed when dropped.
fn dir(tag: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("fpc-compare-{tag}-"))
        .tempdir()
        .unwrap()
}

/// A manifest of one specimen at `eps0` (with `own` added to its own
/// tables) and one test of `kind` holding `csv`; compared.
fn compare_one(tag: &str, eps0: f64, own: &str, kind: &str, test: &str, csv: &str) -> Comparison {
    let d = dir(tag);
    std::fs::write(d.path().join("data.csv"), csv).unwrap();
    let m = format!(
        "[[specimen]]\nname = \"{tag}\"\n[specimen.own.actuator.pemc]\neps0 = {eps0}\n{own}\n[[specimen.test]]\nkind = \"{kind}\"\nfile = \"data.csv\"\n{test}"
    );
    std::fs::write(d.path().join("m.toml"), m).unwrap();
    let manifest = Manifest::load(&d.path().join("m.toml")).unwrap();
    fpc::compare(&manifest).unwrap()
}

fn predictions(c: &Comparison) -> &[Prediction] {
    &c.specimens[0].tests[0].predictions
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * (1.0 + b.abs())
}

#[test]
fn radii_are_study_7s() {
    let study = StudyOptions {
        pressure_points: 9, // 0, 50, ..., 400 kPa
        ..StudyOptions::default()
    };
    let curves = study7_curvature(&fpc::Actuator::default(), &study).unwrap();
    for curve in &curves {
        let rows: Vec<_> = curve
            .rows
            .iter()
            // nearly flat, the radius is ill-conditioned in the shape
            .filter(|r| r.radius.is_some_and(|x| x < 1000.0))
            .take(5)
            .collect();
        assert!(rows.len() >= 3, "eps0 {}", curve.eps0);
        let csv: String = rows
            .iter()
            .map(|r| format!("{},100,5\n", r.pressure_kpa))
            .collect();
        let tag = format!("radius{}", curve.eps0);
        let c = compare_one(
            &tag,
            curve.eps0,
            "",
            "radius",
            "",
            &format!("pressure_kpa,radius_mm,sd_mm\n{csv}"),
        );
        for (p, r) in predictions(&c).iter().zip(&rows) {
            let want = r.radius.unwrap();
            let res = &p.residuals[0];
            let got = res.predicted.unwrap();
            // study 7 warm-starts along its pressures, compare solves each
            // pressure on its own: the same equilibrium to Newton's tolerance
            assert!(
                close(got, want, 1e-7),
                "eps0 {}: {got} vs {want}",
                curve.eps0
            );
            assert!(close(res.residual.unwrap(), 100.0 - want, 1e-7));
            assert!(close(res.residual_sd.unwrap(), (100.0 - want) / 5.0, 1e-7));
            assert_eq!(p.valid, r.warnings.iter().all(|w| !w.is_validity()));
        }
        let chi: f64 = rows
            .iter()
            .map(|r| ((100.0 - r.radius.unwrap()) / 5.0).powi(2))
            .sum();
        assert!(close(c.chi_square, chi, 1e-6), "{} vs {chi}", c.chi_square);
        assert_eq!(c.points, rows.len());
    }
}

#[test]
fn a_marker_at_the_tip_is_the_solved_tip_in_either_frame() {
    let (eps0, p) = (0.4, 35.0);
    let tip = Finger::paper(eps0, 8)
        .unwrap()
        .solve(
            &Load::unloaded().with_pressure_kpa(p),
            &SolveOptions::default(),
        )
        .unwrap()
        .tip;
    let csv = format!("pressure_kpa,marker,s_mm,x_mm,z_mm\n{p},tip,110,0,0\n{p},root,0,0,0\n");
    let c = compare_one("tip", eps0, "", "markers", "sd_mm = 0.5", &csv);
    let [at_tip, at_root] = predictions(&c) else {
        panic!("two rows")
    };
    assert!(close(at_tip.residuals[0].predicted.unwrap(), tip[0], 1e-9));
    assert!(close(at_tip.residuals[1].predicted.unwrap(), tip[1], 1e-9));
    assert_eq!(at_tip.residuals[1].sd, 0.5);
    assert_eq!(at_root.residuals[0].predicted, Some(0.0));
    // a camera turned by 90 degrees with its origin at (10, 20) in the
    // finger frame sees the finger point q at (q_z - 20, 10 - q_x)
    let c = compare_one(
        "camera",
        eps0,
        "",
        "markers",
        "sd_mm = 0.5\ncamera = { angle_deg = 90.0, x_mm = 10.0, z_mm = 20.0 }",
        &csv,
    );
    let t = &c.specimens[0].tests[0];
    assert_eq!(t.frame, "camera");
    let r = &t.predictions[0].residuals;
    assert!(close(r[0].predicted.unwrap(), tip[1] - 20.0, 1e-9), "{r:?}");
    assert!(close(r[1].predicted.unwrap(), 10.0 - tip[0], 1e-9), "{r:?}");
}

#[test]
fn forces_are_study_8s() {
    let rows =
        study8_force_at_displacement(&fpc::Actuator::default(), &StudyOptions::default()).unwrap();
    for want in rows.iter().filter(|r| r.pressure_kpa == 27.6) {
        let axis = if want.axis == Axis::X { "X" } else { "Z" };
        let csv = format!(
            "pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n27.6,{axis},10,1.0,0.2,4\n"
        );
        let c = compare_one(&format!("force{axis}"), want.eps0, "", "force", "", &csv);
        let p = &predictions(&c)[0];
        let f = want.force.unwrap();
        let res = &p.residuals[0];
        assert!(close(res.predicted.unwrap(), f, 1e-7), "{res:?} vs {f}");
        // the sd of the mean of 4 repeats
        assert_eq!(res.sd, 0.1);
        assert!(close(res.residual_sd.unwrap(), (1.0 - f) / 0.1, 1e-6));
        assert_eq!(p.axis, Some(axis));
    }
}

/// A specimen's scene may set the gas law's factor kappa (the one load
/// key that belongs to the finger): markers are the tip of an ordinary
/// solve at that kappa, not the default's, and the force is the one that,
/// applied as a tip load at that kappa, moves the tip the test's 10 mm.
#[test]
fn a_specimens_kappa_is_its_scenes() {
    let (eps0, p, kappa) = (0.4, 35.0, 3.2);
    let finger = Finger::paper(eps0, 8).unwrap();
    let opts = SolveOptions::default();
    let at = |k: f64, fx: f64| {
        let load = Load {
            kappa: k,
            ..Load::unloaded()
        }
        .with_pressure_kpa(p)
        .with_tip_force(fx, 0.0);
        finger.solve(&load, &opts).unwrap().tip
    };
    let (tip, default_tip) = (at(kappa, 0.0), at(2.5, 0.0));
    assert!(
        (tip[0] - default_tip[0]).abs() > 1e-2,
        "{tip:?} {default_tip:?}"
    );
    let own = format!("[specimen.own.load]\nkappa = {kappa}\n");
    let csv = format!("pressure_kpa,marker,s_mm,x_mm,z_mm\n{p},tip,110,0,0\n");
    let c = compare_one("kappa", eps0, &own, "markers", "sd_mm = 0.5", &csv);
    assert_eq!(c.specimens[0].kappa, kappa);
    let r = &predictions(&c)[0].residuals;
    assert!(
        close(r[0].predicted.unwrap(), tip[0], 1e-9),
        "{r:?} {tip:?}"
    );
    assert!(
        close(r[1].predicted.unwrap(), tip[1], 1e-9),
        "{r:?} {tip:?}"
    );
    let csv =
        format!("pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n{p},X,10,1.0,0.2,4\n");
    let c = compare_one("kappaf", eps0, &own, "force", "", &csv);
    let f = predictions(&c)[0].residuals[0].predicted.unwrap();
    let moved = at(kappa, f)[0] - tip[0];
    assert!(
        (moved - 10.0).abs() < 1e-6,
        "{f} N moves the tip {moved} mm"
    );
}

fn synthetic_chi_square(tag: &str, shift: f64) -> Comparison {
    let d = dir(tag);
    synthetic::generate(
        d.path(),
        synthetic::Options {
            noise: false,
            manifest_eps0_shift: shift,
        },
    )
    .unwrap();
    fpc::compare(&Manifest::load(&d.path().join("manifest.toml")).unwrap()).unwrap()
}

#[test]
fn noise_free_data_fit_and_a_wrong_prestrain_does_not() {
    let exact = synthetic_chi_square("exact", 0.0);
    // markers, radii and forces of every specimen, none failed
    assert!(exact.points > 100, "{}", exact.points);
    assert_eq!(exact.failed, 0);
    // the files round to 4 decimals of a marker's 0.3 mm sd and of a
    // radius: far below one sd
    assert!(
        exact.chi_square < 1e-3 * exact.points as f64,
        "{}",
        exact.chi_square
    );
    let wrong = synthetic_chi_square("wrong", 0.05);
    assert!(
        wrong.chi_square > 100.0 * exact.points as f64,
        "{}",
        wrong.chi_square
    );
    // the shipped noisy set is the generator's output, and its chi-square
    // is of the order of its points
    let again = dir("again");
    synthetic::generate(
        again.path(),
        synthetic::Options {
            noise: true,
            manifest_eps0_shift: 0.0,
        },
    )
    .unwrap();
    let ours = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/calibration");
    for e in std::fs::read_dir(again.path()).unwrap() {
        let name = e.unwrap().file_name();
        let made = std::fs::read_to_string(again.path().join(&name)).unwrap();
        let shipped = std::fs::read_to_string(ours.join(&name)).unwrap();
        assert_eq!(
            made, shipped,
            "examples/calibration/{name:?} is not the generator's"
        );
    }
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/calibration/manifest.toml");
    let c = fpc::compare(&Manifest::load(&shipped).unwrap()).unwrap();
    let per = c.chi_square / c.points as f64;
    assert!((0.5..2.0).contains(&per), "chi-square per residual {per}");
}

#[test]
fn a_prediction_outside_the_model_says_so() {
    // four elements over a strongly curled finger turn beyond the CCM's
    // slope limit
    let c = compare_one(
        "outside",
        0.4,
        "[specimen.own.partition]\nelements = 4",
        "radius",
        "",
        "pressure_kpa,radius_mm,sd_mm\n0,30,1\n",
    );
    let p = &predictions(&c)[0];
    assert!(!p.valid, "{p:?}");
    assert!(
        p.warnings.iter().any(|w| w.kind() == "element_slope"),
        "{p:?}"
    );
    assert!(!p.warning_messages.is_empty());
    assert_eq!(c.outside_model, 1);
    let json = serde_json::to_value(&c).unwrap();
    let jp = &json["specimens"][0]["tests"][0]["predictions"][0];
    assert_eq!(jp["valid"], false);
    assert_eq!(jp["warnings"][0]["kind"], "element_slope");
    let t = fpc::measure::table(&c);
    assert_eq!(t.cell(0, "valid"), Some(&fpc::report::Cell::Bool(false)));
    assert_eq!(
        t.cell(0, "warnings"),
        Some(&fpc::report::Cell::Text("element_slope".into()))
    );
}

#[test]
fn a_row_the_model_cannot_predict_keeps_its_data_and_says_why() {
    // one element given two Newton steps cannot reach the curl of
    // eps0 = 0.4: its solve fails
    let c = compare_one(
        "failed",
        0.4,
        "[specimen.own.partition]\nelements = 1\n[specimen.own.solve]\nmax_iter = 2",
        "radius",
        "",
        "pressure_kpa,radius_mm,sd_mm\n0,30,1\n",
    );
    let p = &predictions(&c)[0];
    assert!(!p.valid && p.failure.is_some(), "{p:?}");
    assert_eq!(p.residuals[0].measured, 30.0);
    assert_eq!(p.residuals[0].residual_sd, None);
    assert_eq!((c.failed, c.points, c.chi_square), (1, 0, 0.0));
}

#[test]
fn a_displacement_not_reached_names_the_csv_column() {
    // no finger 110 mm long is pushed 100 m: the row fails, and its
    // failure names the column the user wrote, not the study's key
    let c = compare_one(
        "far",
        0.25,
        "",
        "force",
        "",
        "pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n0,Z,1e5,1,0.1,1\n",
    );
    let p = &predictions(&c)[0];
    let failure = p.failure.as_deref().expect("the row fails");
    assert!(failure.contains("displacement_mm = 100000: "), "{failure}");
    assert!(!failure.contains("displacement.distance"), "{failure}");
    assert_eq!(c.failed, 1);
}

#[test]
fn a_test_without_rows_predicts_nothing_and_draws_nothing() {
    let c = compare_one(
        "empty",
        0.25,
        "",
        "radius",
        "",
        "pressure_kpa,radius_mm,sd_mm\n",
    );
    let t = &c.specimens[0].tests[0];
    assert!(t.predictions.is_empty() && t.model_curve.is_empty());
    assert_eq!((c.points, c.chi_square), (0, 0.0));
    assert!(fpc::measure::figures(&c).is_empty());
}

/// `m.toml` of `manifest` and the files `files` in a fresh directory,
/// loaded.
fn load(tag: &str, manifest: &str, files: &[(&str, &str)]) -> Result<Manifest, MeasureError> {
    let d = dir(tag);
    for (name, text) in files {
        std::fs::write(d.path().join(name), text).unwrap();
    }
    std::fs::write(d.path().join("m.toml"), manifest).unwrap();
    Manifest::load(&d.path().join("m.toml"))
}

/// One specimen with one test of `kind` in `data.csv` (`extra`: more keys
/// of the test, after line 6).
fn one_test(kind: &str, extra: &str) -> String {
    format!("[[specimen]]\nname = \"a\"\n[[specimen.test]]\nkind = \"{kind}\"\nfile = \"data.csv\"\n{extra}")
}

/// The error of a one-test manifest whose data is `csv`, at `file`
/// (`data.csv` or `m.toml`), row, column and field.
fn refused(
    kind: &str,
    extra: &str,
    csv: &str,
    (file, row, col, field): (&str, usize, usize, &str),
) {
    let e = load(field, &one_test(kind, extra), &[("data.csv", csv)])
        .expect_err(&format!("{csv:?} {extra:?} accepted"));
    let place = format!("{file}:{row}:{col}: {field}: ");
    assert!(e.to_string().contains(&place), "{place}: {e}");
    assert_eq!(e.field, field, "{e}");
}

const RADIUS: &str = "pressure_kpa,radius_mm,sd_mm\n";
const FORCE: &str = "pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n";
const MARKERS: &str = "pressure_kpa,marker,s_mm,x_mm,z_mm,sd_mm\n";

/// Measured values beyond physical limits (an sd of 1e308 made `fpc
/// compare`'s figure spin forever; a tiny one a chi-square of inf) are
/// refused where they are written; the limits themselves are accepted.
#[test]
fn measured_values_beyond_physical_limits_are_refused() {
    for (row, col, field) in [
        ("0,39.3776,1e308", 3, "sd_mm"),
        ("0,39.3776,1e-200", 3, "sd_mm"),
        ("0,39.3776,1e-320", 3, "sd_mm"),
        ("0,39.3776,9e-7", 3, "sd_mm"),
        ("0,1e308,1", 2, "radius_mm"),
        ("0,100001,1", 2, "radius_mm"),
        ("1e308,40,1", 1, "pressure_kpa"),
        ("10001,40,1", 1, "pressure_kpa"),
    ] {
        let csv = format!("{RADIUS}25,41.8828,1.343\n{row}\n");
        refused("radius", "", &csv, ("data.csv", 3, col, field));
    }
    for (row, col, field) in [
        ("0,X,10,0.5,1e-320,3", 5, "sd_n"),
        ("0,X,10,0.5,1001,3", 5, "sd_n"),
        ("0,X,10,1e308,0.1,3", 4, "force_n"),
        ("0,X,10,-1001,0.1,3", 4, "force_n"),
        ("0,X,1e308,0.5,0.1,3", 3, "displacement_mm"),
        ("0,X,10,0.5,0.1,1000001", 6, "repeats"),
    ] {
        refused(
            "force",
            "",
            &format!("{FORCE}{row}\n"),
            ("data.csv", 2, col, field),
        );
    }
    for (row, col, field) in [
        ("0,M1,50,1e308,2,0.3", 4, "x_mm"),
        ("0,M1,50,1,-1e308,0.3", 5, "z_mm"),
        ("0,M1,50,1,2,1e-9", 6, "sd_mm"),
    ] {
        refused(
            "markers",
            "",
            &format!("{MARKERS}{row}\n"),
            ("data.csv", 2, col, field),
        );
    }
    // the manifest's keys of a markers test, at the test's line (6)
    let head = "pressure_kpa,marker,s_mm,x_mm,z_mm\n0,M1,50,1,2\n";
    for (extra, field) in [
        ("sd_mm = 1e-300", "sd_mm"),
        ("sd_mm = 1e6", "sd_mm"),
        (
            "sd_mm = 0.3\ncamera = { angle_deg = 0, x_mm = 1e308, z_mm = 0 }",
            "camera.x_mm",
        ),
        (
            "sd_mm = 0.3\ncamera = { angle_deg = 0, x_mm = 0, z_mm = -1e6 }",
            "camera.z_mm",
        ),
        (
            "sd_mm = 0.3\ncamera = { angle_deg = 1e308, x_mm = 0, z_mm = 0 }",
            "camera.angle_deg",
        ),
        (
            "sd_mm = 0.3\ncamera = { angle_deg = -361, x_mm = 0, z_mm = 0 }",
            "camera.angle_deg",
        ),
    ] {
        let e = load(field, &one_test("markers", extra), &[("data.csv", head)]).unwrap_err();
        assert!(e.file.ends_with("m.toml"), "{e}");
        assert_eq!(e.field, field, "{e}");
        assert!(matches!(e.row(), Some(6 | 7)), "{e}");
    }
    // the limits: vacuum to 10 MPa, 100 m, 1 kN, sds from 1e-6 of the
    // unit, a turn, a million repeats
    let m = load(
        "limits",
        &format!(
            "{}{}",
            one_test("radius", ""),
            "[[specimen.test]]\nkind = \"force\"\nfile = \"force.csv\"\n[[specimen.test]]\nkind = \"markers\"\nfile = \"markers.csv\"\nsd_mm = 1e-6\ncamera = { angle_deg = -360, x_mm = 1e5, z_mm = -1e5 }\n"
        ),
        &[
            ("data.csv", &format!("{RADIUS}-101.325,1e5,1e-6\n1e4,1e-3,1e5\n")),
            ("force.csv", &format!("{FORCE}1e4,Z,-1e5,-1e3,1e3,1000000\n0,X,1e5,1e3,1e-6,1\n")),
            ("markers.csv", "pressure_kpa,marker,s_mm,x_mm,z_mm\n0,M1,50,-1e5,1e5\n"),
        ],
    )
    .unwrap();
    assert_eq!(m.specimens[0].tests.len(), 3);
}

/// At the limits every residual, chi-square and figure point is finite,
/// and so is compare.json's chi-square.
#[test]
fn a_comparison_at_the_limits_is_finite() {
    let c = compare_one(
        "finite",
        0.25,
        "",
        "radius",
        "",
        &format!("{RADIUS}0,1e5,1e-6\n25,1e-3,1e5\n"),
    );
    assert_eq!((c.points, c.failed), (2, 0));
    for p in predictions(&c) {
        let r = &p.residuals[0];
        assert!(r.residual_sd.unwrap().is_finite(), "{r:?}");
    }
    assert!(
        c.chi_square.is_finite() && c.chi_square > 1e20,
        "{}",
        c.chi_square
    );
    let json = serde_json::to_value(&c).unwrap();
    assert!(json["chi_square"].is_f64(), "{}", json["chi_square"]);
    for (_, fig) in fpc::measure::figures(&c) {
        let fig = serde_json::to_value(&fig).unwrap();
        let rows = fig["rows"].as_array().unwrap().iter();
        let panels = rows.flat_map(|r| r.as_array().unwrap());
        let points: Vec<&serde_json::Value> = panels
            .flat_map(|p| p["series"].as_array().unwrap())
            .flat_map(|s| s["points"].as_array().unwrap())
            .flat_map(|p| p.as_array().unwrap())
            .collect();
        assert!(points.len() > 4, "{fig}");
        assert!(
            points.iter().all(|x| x.is_f64()),
            "a point that is not finite: {fig}"
        );
    }
}

/// A scene value the library refuses is named by the key as the user
/// wrote it, at its value: in the shared tables, in a specimen's own
/// tables (the second specimen's too), in a scene file.
#[test]
fn a_bad_scene_value_is_named_where_it_is_written() {
    let test = "[[specimen.test]]\nkind = \"radius\"\nfile = \"data.csv\"\n";
    let files = [
        ("data.csv", RADIUS),
        (
            "base.toml",
            "[partition]\nelements = 4\n[actuator.pemc]\ne2 = -5\n",
        ),
    ];
    for (tag, manifest, (file, row, field)) in [
        (
            "type",
            format!("[shared.actuator.pemc]\ne2 = \"abc\"\n[[specimen]]\nname = \"a\"\n{test}"),
            ("m.toml", 2, "shared.actuator.pemc.e2"),
        ),
        (
            "value",
            format!("[shared]\n[shared.actuator.pemc]\n\ne2 = -1\n[[specimen]]\nname = \"a\"\n{test}"),
            ("m.toml", 4, "shared.actuator.pemc.e2"),
        ),
        (
            "unknown",
            format!("[shared.actuator.pemc]\ne3 = 1.0\n[[specimen]]\nname = \"a\"\n{test}"),
            ("m.toml", 2, "shared.actuator.pemc.e3"),
        ),
        (
            "own",
            format!(
                "[[specimen]]\nname = \"a\"\n{test}[[specimen]]\nname = \"b\"\n[specimen.own.actuator.pemc]\neps0 = 0.3\ne2 = \"x\"\n{test}"
            ),
            ("m.toml", 10, "specimen.own.actuator.pemc.e2"),
        ),
        (
            "file",
            format!("[shared]\nscene = \"base.toml\"\n[[specimen]]\nname = \"a\"\n{test}"),
            ("base.toml", 4, "actuator.pemc.e2"),
        ),
    ] {
        let e = load(tag, &manifest, &files).expect_err(tag);
        assert!(e.file.ends_with(file), "{tag}: {e}");
        // at the value: every key here is two characters, `e2 = ...`
        assert_eq!((e.field.as_str(), e.row(), e.column()), (field, Some(row), Some(6)), "{tag}: {e}");
    }
}

/// An error in a key of the `[shared]` section is at that key: a rule
/// between a shared key and a default (the default is not written
/// anywhere, so the error names the shared key), and a `scene` that is no
/// file name; not at the specimen's table.
#[test]
fn an_error_in_a_shared_key_is_at_that_key() {
    let test = "[[specimen.test]]\nkind = \"radius\"\nfile = \"data.csv\"\n";
    let files = [("data.csv", RADIUS)];
    for (tag, manifest, (field, row, col)) in [
        (
            "rule",
            format!("[shared.actuator.geometry]\nlx = 50.0\n[[specimen]]\nname = \"a\"\n{test}"),
            ("shared.actuator.geometry.lx", 2, 6),
        ),
        (
            "scene",
            format!("[shared]\nscene = 3\n[[specimen]]\nname = \"a\"\n{test}"),
            ("shared.scene", 2, 9),
        ),
    ] {
        let e = load(tag, &manifest, &files).expect_err(tag);
        assert_eq!(
            (e.field.as_str(), e.row(), e.column()),
            (field, Some(row), Some(col)),
            "{tag}: {e}"
        );
    }
}

/// A specimen's scene file is used instead of the shared one: the shared
/// file's keys do not override it (docs/measurements.md).
#[test]
fn a_specimens_scene_file_replaces_the_shared_one() {
    let test = "[[specimen.test]]\nkind = \"radius\"\nfile = \"data.csv\"\n";
    let m = load(
        "scenes",
        &format!("[shared]\nscene = \"shared.toml\"\n[[specimen]]\nname = \"a\"\n{test}[[specimen]]\nname = \"b\"\nscene = \"b.toml\"\n{test}"),
        &[
            ("data.csv", RADIUS),
            ("shared.toml", "[partition]\nelements = 6\n"),
            ("b.toml", "[partition]\nelements = 4\n"),
        ],
    )
    .unwrap();
    let elements = |i: usize| m.specimens[i].scene.file().partition.elements;
    assert_eq!(elements(0), Some(fpc::scene::Elements::Count(6)));
    assert_eq!(elements(1), Some(fpc::scene::Elements::Count(4)));
}
