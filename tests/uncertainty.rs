//! Predictions with error bars (`Scene::uncertainty`): the first-order
//! 1-sigma uncertainties of a finger's and a grasp's outputs agree with a
//! seeded Monte Carlo through the ordinary scene path, and a bad
//! `[calibration]` covariance is an error naming its field. The studies'
//! bands are tests/study_bands.rs.
//!
//! Tolerance of the Monte Carlo: the sample standard deviation of `n`
//! Gaussian draws has a relative standard deviation of about
//! `1 / sqrt(2 n)`, so the propagated sigma must match the sample one
//! within `4 / sqrt(2 n)` (4 sd of the sampling error) plus 3 % for the
//! nonlinearity the first order leaves out. That part grows with sigma:
//! with the finger's covariance below, the tip Z (the most curved output,
//! its first derivative small) differs by 3.1 % from the seeded Monte
//! Carlo, and by 7.6 % with the covariance four times larger, while tip X
//! and the end angle stay at the 1.8 % of their sampling error. Run with
//! `--nocapture` to see the numbers.

#[path = "common/monte_carlo.rs"]
mod monte_carlo;

use fpc::scene::{Scene, SceneFile, SceneSolution};
use monte_carlo::*;

const FINGER: &str = r#"
[actuator.pemc]
eps0 = 0.25
[load]
pressure_kpa = 40.0
kappa = 2.5
[partition]
elements = 4
[solve]
samples_per_element = 2
stability = false
[calibration]
parameters = ["actuator.pemc.eps0", "load.kappa"]
covariance = [[1e-6, -7.5e-6], [-7.5e-6, 0.000625]]
"#;

#[test]
fn finger_tip_and_radius_sigma_match_monte_carlo() {
    let scene = Scene::from_toml(FINGER).unwrap();
    let solved = scene.solve().unwrap();
    let u = scene.uncertainty(&solved).unwrap().unwrap();
    assert_eq!(u.parameters, ["actuator.pemc.eps0", "load.kappa"]);
    let tip = u.tip_mm.unwrap();
    let angle = u.end_angle_rad.unwrap();
    let radius = u.radius_mm.unwrap();
    assert!(u.radius_unavailable.is_none());
    let n = 2000;
    let cov = vec![vec![1e-6, -7.5e-6], vec![-7.5e-6, 0.000625]];
    let cols = monte_carlo(
        FINGER,
        &["actuator.pemc.eps0", "load.kappa"],
        &[0.25, 2.5],
        &cov,
        n,
        21,
        |s| {
            let sol = s.solution();
            // the circle fit of the solve's own shape samples
            vec![sol.tip[0], sol.tip[1], sol.end_angle, sol.radius.unwrap()]
        },
    );
    agree("tip X", tip[0], sd(&cols[0]), n);
    agree("tip Z", tip[1], sd(&cols[1]), n);
    agree("end angle", angle, sd(&cols[2]), n);
    agree("radius", radius, sd(&cols[3]), n);
}

#[test]
fn one_key_sigma_is_the_central_difference_slope() {
    // with C = [[s^2]], sigma = |dy/dp| s: the slope against central
    // differences of two ordinary solves
    let text = FINGER.replace(
        "parameters = [\"actuator.pemc.eps0\", \"load.kappa\"]\ncovariance = [[1e-6, -7.5e-6], [-7.5e-6, 0.000625]]",
        "parameters = [\"actuator.pemc.eps0\"]\ncovariance = [[1.0]]",
    );
    let scene = Scene::from_toml(&text).unwrap();
    let u = scene.uncertainty(&scene.solve().unwrap()).unwrap().unwrap();
    let h = 1e-5;
    let tip = |e: f64| {
        let s = with_values(&text, &["actuator.pemc.eps0"], &[e]);
        s.solve().unwrap().solution().tip
    };
    let (up, down) = (tip(0.25 + h), tip(0.25 - h));
    for k in 0..2 {
        let fd = ((up[k] - down[k]) / (2.0 * h)).abs();
        let got = u.tip_mm.unwrap()[k];
        assert!(
            (got - fd).abs() <= 1e-5 * fd.max(1.0),
            "tip {k}: propagated {got}, central difference {fd}"
        );
    }
    // the radius: the circle fit of each solve's shape samples
    let radius = |e: f64| {
        let s = with_values(&text, &["actuator.pemc.eps0"], &[e]);
        s.solve().unwrap().solution().radius.unwrap()
    };
    let fd = ((radius(0.25 + h) - radius(0.25 - h)) / (2.0 * h)).abs();
    let got = u.radius_mm.unwrap();
    assert!(
        (got - fd).abs() <= 1e-5 * fd,
        "radius: propagated {got}, central difference {fd}"
    );
}

#[test]
fn a_finger_without_shape_samples_says_why_it_has_no_radius_bar() {
    let text = FINGER.replace("[solve]\n", "[solve]\nshape = false\n");
    let scene = Scene::from_toml(&text).unwrap();
    let u = scene.uncertainty(&scene.solve().unwrap()).unwrap().unwrap();
    assert!(u.radius_mm.is_none() && u.tip_mm.is_some());
    let why = u.radius_unavailable.unwrap();
    assert!(why.contains("solve.shape = false"), "{why}");
}

const SPHERE: &str = r#"
[actuator.pemc]
eps0 = 0.25
[partition]
elements = 4
[gripper]
mounting_angle_deg = 60.0
overlap_mm = 20.0
mu = 0.6
[gripper.grasp]
kind = "sphere"
r_mm = 50.0
lift_n = 0.5
beta_deg = 20.0
pressure_kpa = 0.0
[calibration]
parameters = ["actuator.pemc.eps0", "actuator.pemc.p1"]
covariance = [[4e-6, 1e-8], [1e-8, 1e-6]]
"#;

#[test]
fn grasp_force_sigma_matches_monte_carlo() {
    let scene = Scene::from_toml(SPHERE).unwrap();
    let solved = scene.solve().unwrap();
    let u = scene.uncertainty(&solved).unwrap().unwrap();
    let g = u.grasp.clone().unwrap();
    assert!(u.tip_mm.is_none());
    let d_max = u.d_max_mm.unwrap();
    let base = SceneFile::parse(SPHERE).unwrap().resolve().unwrap();
    let p1 = fpc::sensitivity::Param::from_name("actuator.pemc.p1")
        .unwrap()
        .value(&base.actuator, &fpc::Load::unloaded(), None)
        .unwrap();
    let n = 1000;
    let cov = vec![vec![4e-6, 1e-8], vec![1e-8, 1e-6]];
    let cols = monte_carlo(
        SPHERE,
        &["actuator.pemc.eps0", "actuator.pemc.p1"],
        &[0.25, p1],
        &cov,
        n,
        7,
        |s| match s {
            SceneSolution::Gripper {
                gripper,
                grasp: Some(o),
            } => vec![o.grasp.normal, o.grasp.friction, gripper.d_max()],
            _ => panic!("not a grasp"),
        },
    );
    agree("normal force", g.normal_force_n, sd(&cols[0]), n);
    agree("friction", g.friction_n, sd(&cols[1]), n);
    agree("d_max", d_max, sd(&cols[2]), n);
    // the lift is the scene's own, not an output
    assert_eq!(g.lift_n, 0.0);
}

#[test]
fn no_covariance_no_uncertainty() {
    let text = FINGER.split("[calibration]").next().unwrap();
    let scene = Scene::from_toml(text).unwrap();
    let solved = scene.solve().unwrap();
    assert!(scene.uncertainty(&solved).unwrap().is_none());
    let json =
        serde_json::to_value(fpc::scene::SolutionRecord::new("t", scene.file(), &solved)).unwrap();
    assert!(json.get("uncertainty").is_none());
}

/// The field a bad `[calibration]` table is rejected under.
fn rejected(calibration: &str, gripper: bool) -> String {
    let head = if gripper {
        SPHERE.split("[calibration]").next().unwrap()
    } else {
        FINGER.split("[calibration]").next().unwrap()
    };
    let text = format!("{head}[calibration]\n{calibration}\n");
    match Scene::from_toml(&text) {
        Err(fpc::scene::SceneReadError::Input(e)) => e.field().to_string(),
        other => panic!("{calibration}: not an input error: {other:?}"),
    }
}

#[test]
fn bad_covariances_are_errors_naming_the_field() {
    let eps = "parameters = [\"actuator.pemc.eps0\", \"load.kappa\"]\n";
    for (cov, field) in [
        (
            "covariance = [[1e-4, 1e-5], [0.0, 1e-2]]",
            "calibration.covariance",
        ),
        (
            "covariance = [[1e-4, 1e-2], [1e-2, 1e-2]]",
            "calibration.covariance",
        ),
        (
            "covariance = [[-1e-4, 0.0], [0.0, 1e-2]]",
            "calibration.covariance",
        ),
        ("covariance = [[1e-4]]", "calibration.covariance"),
    ] {
        assert_eq!(rejected(&format!("{eps}{cov}"), false), field, "{cov}");
    }
    assert_eq!(
        rejected(
            "parameters = [\"actuator.pemc.nope\"]\ncovariance = [[1.0]]",
            false
        ),
        "calibration.parameters"
    );
    assert_eq!(
        rejected(
            "parameters = [\"actuator.pemc.eps0\", \"actuator.pemc.eps0\"]\ncovariance = [[1.0, 0.0], [0.0, 1.0]]",
            false
        ),
        "calibration.parameters"
    );
    assert_eq!(
        rejected("parameters = [\"load.kappa\"]\ncovariance = [[1.0]]", true),
        "calibration.parameters"
    );
}

#[test]
fn standard_errors_and_variances_out_of_bounds_are_errors_naming_the_field() {
    let eps = "parameters = [\"actuator.pemc.eps0\"]\n";
    for (table, field) in [
        // a standard error is a root: never negative nor infinite
        (
            "standard_errors = [-0.1]\ncovariance = [[0.01]]",
            "calibration.standard_errors",
        ),
        ("standard_errors = [-0.1]", "calibration.standard_errors"),
        ("standard_errors = [inf]", "calibration.standard_errors"),
        // sqrt(1e-8) = 1e-4, not 5: the two say different things
        (
            "standard_errors = [5.0]\ncovariance = [[1e-8]]",
            "calibration.standard_errors",
        ),
        (
            "standard_errors = [0.1001]\ncovariance = [[0.01]]",
            "calibration.standard_errors",
        ),
        // no key of a scene reaches 1e7 in its unit, nor its sd
        ("covariance = [[1e308]]", "calibration.covariance"),
        ("covariance = [[1.1e14]]", "calibration.covariance"),
        ("standard_errors = [2e7]", "calibration.standard_errors"),
    ] {
        assert_eq!(rejected(&format!("{eps}{table}"), false), field, "{table}");
    }
    // beside a zero variance no covariance is semi-definite
    assert_eq!(
        rejected(
            "parameters = [\"actuator.pemc.eps0\", \"load.kappa\"]\ncovariance = [[0.0, 1e-3], [1e-3, 0.0]]",
            false
        ),
        "calibration.covariance"
    );
    // agreeing to round-off, and at the bound, they are read
    let head = FINGER.split("[calibration]").next().unwrap();
    for table in [
        "standard_errors = [0.1]\ncovariance = [[0.010000000000000002]]",
        "standard_errors = [0.0]\ncovariance = [[0.0]]",
        "covariance = [[1e14]]",
    ] {
        let text = format!("{head}[calibration]\n{eps}{table}\n");
        assert!(Scene::from_toml(&text).is_ok(), "{table}");
    }
}

#[test]
fn a_rest_shape_the_chaining_does_not_cover_solves_without_error_bars() {
    // eps0 = 0.4 curls the rest shape past its tip: l0's sensitivity is
    // not covered, so the grasp stands and says why it has no bars
    let text = SPHERE
        .replace("eps0 = 0.25", "eps0 = 0.4")
        .replace(
            "kind = \"sphere\"\nr_mm = 50.0\nlift_n = 0.5\nbeta_deg = 20.0",
            "kind = \"cuboid\"\nd_mm = 100.0\nfriction_n = 0.3",
        )
        .replace("pressure_kpa = 0.0", "pressure_kpa = 20.0");
    let scene = Scene::from_toml(&text).unwrap();
    let solved = scene.solve().unwrap();
    let u = scene.uncertainty(&solved).unwrap().unwrap();
    assert!(u.grasp.is_none() && u.d_max_mm.is_none());
    let why = u.unavailable.unwrap();
    assert!(why.contains("innermost"), "{why}");
}
