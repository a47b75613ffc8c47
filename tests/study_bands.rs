//! Bands on the studies (`study3_cuboid_region_with`, ...,
//! `study8_force_at_displacement_with`: what `fpc paper --scene` writes
//! from a calibrated scene): each study's first-order 1-sigma agrees with
//! a seeded Monte Carlo through the ordinary study (or scene) path, and
//! with a one-key covariance with central differences of that path.
//!
//! Tolerance of the Monte Carlo: the sample standard deviation of `n`
//! Gaussian draws has a relative standard deviation of about
//! `1 / sqrt(2 n)`, so the propagated sigma must match the sample one
//! within `4 / sqrt(2 n)` (4 sd of the sampling error) plus 3 % for the
//! nonlinearity the first order leaves out.

#[path = "common/monte_carlo.rs"]
mod monte_carlo;

use fpc::scene::{Scene, SceneSolution};
use fpc::studies::{
    section5_gripper, study2_overlap_with, study3_cuboid_region_with, study4_force_control,
    study4_force_control_with, study5_sphere_region, study5_sphere_region_with,
    study6_viable_angles, study6_viable_angles_with, study7_curvature, study7_curvature_with,
    study8_force_at_displacement, study8_force_at_displacement_with, StudyOptions,
};
use monte_carlo::*;

/// A scene for `fpc paper --scene`: the covariance over the prestrain
/// (which every study sets itself: not propagated) and two correlated
/// material parameters (propagated).
const STUDY_SCENE: &str = r#"
[actuator.pemc]
eps0 = 0.25
[partition]
elements = 4
[calibration]
parameters = ["actuator.pemc.eps0", "actuator.pemc.p1", "actuator.cl.e"]
covariance = [[1e-6, 0.0, 0.0], [0.0, 2.56e-4, -0.12], [0.0, -0.12, 225.0]]
"#;

const STUDY_KEYS: [&str; 3] = ["actuator.pemc.eps0", "actuator.pemc.p1", "actuator.cl.e"];

/// Parameter sets drawn from the scene's covariance around its values,
/// each as the actuator the scene resolves to.
fn study_draws(n: usize, seed: u64) -> (Scene, Vec<fpc::Actuator>) {
    let scene = Scene::from_toml(STUDY_SCENE).unwrap();
    let cov: Vec<Vec<f64>> = scene.covariance().unwrap().matrix().to_vec();
    let mean: Vec<f64> = STUDY_KEYS
        .iter()
        .map(|k| {
            fpc::sensitivity::Param::from_name(k)
                .unwrap()
                .value(&scene.actuator, &fpc::Load::unloaded(), None)
                .unwrap()
        })
        .collect();
    let l = cholesky(&cov);
    let mut rng = fastrand::Rng::with_seed(seed);
    let draws = (0..n)
        .map(|_| {
            let z: Vec<f64> = (0..3).map(|_| normal(&mut rng)).collect();
            let x: Vec<f64> = (0..3)
                .map(|i| mean[i] + (0..=i).map(|k| l[i][k] * z[k]).sum::<f64>())
                .collect();
            with_values(STUDY_SCENE, &STUDY_KEYS, &x).actuator
        })
        .collect();
    (scene, draws)
}

fn study_options() -> StudyOptions {
    StudyOptions {
        elements: 4,
        pressure_points: 5,
        ..StudyOptions::coarse()
    }
}

#[test]
fn study7_bands_match_monte_carlo_through_the_study() {
    let opts = study_options();
    let n = 600;
    let (scene, draws) = study_draws(n, 11);
    let banded = study7_curvature_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    // (curve, row): eps0 = 0.15 at 0 kPa, 0.25 at 0 and 100 kPa, 0.4 at
    // 0, 100 and 200 kPa (the radii below 100 mm, far from flat)
    let picks = [(0, 0), (1, 0), (1, 1), (2, 0), (2, 1), (2, 2)];
    let mut radii = vec![Vec::with_capacity(n); picks.len()];
    for act in &draws {
        let curves = study7_curvature(act, &opts).unwrap();
        for (k, &(c, r)) in picks.iter().enumerate() {
            radii[k].push(curves[c].rows[r].radius.unwrap());
        }
    }
    for (k, &(c, r)) in picks.iter().enumerate() {
        let row = &banded[c].rows[r];
        let name = format!(
            "study 7 radius, eps0 = {} at {} kPa (R = {:.1} mm)",
            banded[c].eps0,
            row.pressure_kpa,
            row.radius.unwrap()
        );
        agree(&name, row.sd.unwrap().radius.unwrap(), sd(&radii[k]), n);
    }
    // without a covariance, no sd
    let plain = study7_curvature(&scene.actuator, &opts).unwrap();
    assert!(plain.iter().flat_map(|c| &c.rows).all(|r| r.sd.is_none()));
}

#[test]
fn study8_bands_match_monte_carlo_through_the_study() {
    let opts = study_options();
    let n = 600;
    let (scene, draws) = study_draws(n, 13);
    let banded =
        study8_force_at_displacement_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    let mut forces = vec![Vec::with_capacity(n); banded.len()];
    for act in &draws {
        let rows = study8_force_at_displacement(act, &opts).unwrap();
        for (k, r) in rows.iter().enumerate() {
            forces[k].push(r.force.unwrap());
        }
    }
    for (k, r) in banded.iter().enumerate() {
        let name = format!(
            "study 8 force, eps0 = {} along {} at {} kPa (F = {:.4} N)",
            r.eps0,
            r.axis.name(),
            r.pressure_kpa,
            r.force.unwrap()
        );
        agree(&name, r.force_sd.unwrap(), sd(&forces[k]), n);
    }
}

/// The study scene with C = [[1]] over p1 (a band is then |d(output)/d(p1)|),
/// and its actuator at p1 +- h for central differences.
struct OneKey {
    scene: Scene,
    opts: StudyOptions,
    h: f64,
    up: fpc::Actuator,
    down: fpc::Actuator,
}

fn one_key_p1() -> OneKey {
    let text = STUDY_SCENE.replace(
        "parameters = [\"actuator.pemc.eps0\", \"actuator.pemc.p1\", \"actuator.cl.e\"]\ncovariance = [[1e-6, 0.0, 0.0], [0.0, 2.56e-4, -0.12], [0.0, -0.12, 225.0]]",
        "parameters = [\"actuator.pemc.p1\"]\ncovariance = [[1.0]]",
    );
    let scene = Scene::from_toml(&text).unwrap();
    let opts = study_options();
    let p1 = fpc::sensitivity::Param::from_name("actuator.pemc.p1")
        .unwrap()
        .value(&scene.actuator, &fpc::Load::unloaded(), None)
        .unwrap();
    let h = 1e-5;
    let at = |v: f64| with_values(&text, &["actuator.pemc.p1"], &[v]).actuator;
    let (up, down) = (at(p1 + h), at(p1 - h));
    OneKey {
        scene,
        opts,
        h,
        up,
        down,
    }
}

#[test]
fn study_bands_with_one_key_are_central_difference_slopes() {
    // with C = [[1]] over p1 the band is |d(output)/d(p1)|: against
    // central differences of two ordinary runs of each study
    let OneKey {
        scene,
        opts,
        h,
        up,
        down,
    } = one_key_p1();
    let s7 = study7_curvature_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    let (u7, d7) = (
        study7_curvature(&up, &opts).unwrap(),
        study7_curvature(&down, &opts).unwrap(),
    );
    let mut checked = 0;
    for (c, curve) in s7.iter().enumerate() {
        for (r, row) in curve.rows.iter().enumerate() {
            let (Some(sd), Some(a), Some(b)) = (row.sd, u7[c].rows[r].radius, d7[c].rows[r].radius)
            else {
                continue;
            };
            if a > 300.0 {
                // near flat the radius grows without bound: the
                // differences' own truncation error shows
                continue;
            }
            let fd = ((a - b) / (2.0 * h)).abs();
            let got = sd.radius.unwrap();
            assert!(
                (got - fd).abs() <= 1e-4 * fd.max(1e-3),
                "study 7 radius, eps0 = {} at {} kPa: propagated {got}, central difference {fd}",
                curve.eps0,
                row.pressure_kpa
            );
            let tip = |rows: &[fpc::studies::CurvatureRow]| rows[r].tip;
            let fd_tip = (tip(&u7[c].rows)[1] - tip(&d7[c].rows)[1]) / (2.0 * h);
            assert!((sd.tip[1] - fd_tip.abs()).abs() <= 1e-4 * fd_tip.abs().max(1e-3));
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked} rows checked");
    let s4 = study4_force_control_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    let (u4, d4) = (
        study4_force_control(&up, &opts).unwrap(),
        study4_force_control(&down, &opts).unwrap(),
    );
    for ((r, a), b) in s4.rows.iter().zip(&u4.rows).zip(&d4.rows) {
        let sd = r.sd.unwrap();
        for (got, fd, what) in [
            (sd.normal, (a.normal - b.normal) / (2.0 * h), "F"),
            (sd.height, (a.height - b.height) / (2.0 * h), "h"),
        ] {
            assert!(
                (got - fd.abs()).abs() <= 1e-4 * fd.abs(),
                "study 4 {what} at {} kPa: propagated {got}, central difference {fd}",
                r.pressure_kpa
            );
        }
    }
    let s8 = study8_force_at_displacement_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    let (u8, d8) = (
        study8_force_at_displacement(&up, &opts).unwrap(),
        study8_force_at_displacement(&down, &opts).unwrap(),
    );
    for ((r, a), b) in s8.iter().zip(&u8).zip(&d8) {
        let fd = ((a.force.unwrap() - b.force.unwrap()) / (2.0 * h)).abs();
        let got = r.force_sd.unwrap();
        assert!(
            (got - fd).abs() <= 1e-4 * fd,
            "study 8 force, eps0 = {} at {} kPa: propagated {got}, central difference {fd}",
            r.eps0,
            r.pressure_kpa
        );
    }
}

#[test]
fn study4_bands_match_monte_carlo_through_the_study() {
    let opts = study_options();
    let n = 400;
    let (scene, draws) = study_draws(n, 14);
    let banded = study4_force_control_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    assert_eq!(banded.rows.len(), 11, "{:?}", banded.stopped);
    let picks = [0, 5, 10];
    let mut cols = vec![Vec::with_capacity(n); 2 * picks.len()];
    for act in &draws {
        let fc = study4_force_control(act, &opts).unwrap();
        for (k, &r) in picks.iter().enumerate() {
            cols[2 * k].push(fc.rows[r].normal);
            cols[2 * k + 1].push(fc.rows[r].height);
        }
    }
    for (k, &r) in picks.iter().enumerate() {
        let row = &banded.rows[r];
        let sd_row = row.sd.unwrap();
        let at = format!("at {} kPa", row.pressure_kpa);
        agree(
            &format!("study 4 F {at}"),
            sd_row.normal,
            sd(&cols[2 * k]),
            n,
        );
        agree(
            &format!("study 4 h {at}"),
            sd_row.height,
            sd(&cols[2 * k + 1]),
            n,
        );
    }
}

#[test]
fn study2_bands_match_monte_carlo_of_the_grasp_at_its_size() {
    // the band of a lift curve is at a fixed grasping size (the sweep's
    // grid moves with d_max): each draw solves that size's grasp through
    // the ordinary scene path, the gripper of the study's curve a = pi/3,
    // g = 20 mm
    let opts = study_options();
    let scene = Scene::from_toml(STUDY_SCENE).unwrap();
    let curves = study2_overlap_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    let c = curves
        .iter()
        .find(|c| {
            (c.mounting_angle - std::f64::consts::FRAC_PI_3).abs() < 1e-12 && c.overlap == 20.0
        })
        .unwrap();
    let point = c.points.iter().find(|p| p.invalid.is_none()).unwrap();
    let grasp = format!(
        "[gripper]\nmounting_angle_deg = 60.0\noverlap_mm = 20.0\nmu = 0.6\n[gripper.grasp]\nkind = \"size\"\nd_mm = {:.17e}\npressure_kpa = 0.0\n[calibration]",
        point.size
    );
    let text = STUDY_SCENE.replace("[calibration]", &grasp);
    let base = Scene::from_toml(&text).unwrap();
    let mean: Vec<f64> = STUDY_KEYS
        .iter()
        .map(|k| {
            fpc::sensitivity::Param::from_name(k)
                .unwrap()
                .value(&base.actuator, &fpc::Load::unloaded(), None)
                .unwrap()
        })
        .collect();
    // the study sets eps0 itself: the scene's draws hold it too
    let mut cov: Vec<Vec<f64>> = base.covariance().unwrap().matrix().to_vec();
    for row in cov.iter_mut() {
        row[0] = 0.0;
    }
    cov[0] = vec![1e-30, 0.0, 0.0];
    let n = 1500;
    let cols = monte_carlo(&text, &STUDY_KEYS, &mean, &cov, n, 15, |s| match s {
        SceneSolution::Gripper {
            gripper,
            grasp: Some(o),
        } => vec![o.grasp.lift, o.grasp.height, gripper.d_max()],
        _ => panic!("not a grasp"),
    });
    // the scene's grasp is the study's point
    let solved = base.solve().unwrap();
    let SceneSolution::Gripper { grasp: Some(o), .. } = &solved else {
        panic!("not a grasp")
    };
    assert!(
        (o.grasp.lift - point.lift).abs() < 1e-6 * point.lift,
        "{} {}",
        o.grasp.lift,
        point.lift
    );
    let sd_point = point.sd.unwrap();
    let at = format!("a = pi/3, g = 20 mm, d = {:.2} mm", point.size);
    agree(
        &format!("study 2 f_v, {at}"),
        sd_point.lift,
        sd(&cols[0]),
        n,
    );
    agree(
        &format!("study 2 h, {at}"),
        sd_point.height,
        sd(&cols[1]),
        n,
    );
    agree(
        "study 2 d_max, a = pi/3, g = 20 mm",
        c.d_max_sd.unwrap(),
        sd(&cols[2]),
        n,
    );
}

/// The best lift (and its normal force) of a sphere of radius `r` on the
/// study-5 gripper of `act`, through the ordinary path: the scan over the
/// grasping angle and Brent's method (`Gripper::max_sphere_lift`).
fn best_sphere_lift(act: &fpc::Actuator, opts: &StudyOptions, r: f64) -> [f64; 2] {
    let g = section5_gripper(act, opts).unwrap();
    let best = g
        .max_sphere_lift(0.0, r, opts.angle_samples)
        .unwrap()
        .unwrap();
    [best.lift, best.normal]
}

#[test]
fn study5_envelope_bands_match_monte_carlo_of_the_best_lift_at_its_radius() {
    // the envelope's band is at a fixed radius (its radius grid moves with
    // the swept region): each draw solves the best lift at that radius
    // through the ordinary path, the study's gripper at the draw's
    // parameters (eps0 is the study's own)
    let opts = study_options();
    // 200 draws at two radii keep this at about a minute in a debug build
    let n = 200;
    let (scene, draws) = study_draws(n, 16);
    let region = study5_sphere_region_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    assert_eq!(region.envelope_sd.len(), region.envelope.len());
    let m = region.envelope.len();
    assert!(m >= 6, "{m} envelope points");
    let peak = region.peak.clone().unwrap();
    // the smallest radius and the peak's (in the middle of the range)
    let picks: Vec<(String, fpc::gripper::SphereLift, fpc::studies::SphereLiftSd)> = [0]
        .iter()
        .map(|&i| {
            let e = &region.envelope[i];
            let sd = region.envelope_sd[i].clone().unwrap();
            (format!("r = {:.1} mm", e.radius), e.clone(), sd)
        })
        .chain(std::iter::once((
            format!("the peak, r = {:.1} mm", peak.radius),
            peak.clone(),
            region.peak_sd.clone().unwrap().unwrap(),
        )))
        .collect();
    // the ordinary path gives the study's point at the mean
    for (name, e, _) in &picks {
        let [lift, _] = best_sphere_lift(&scene.actuator, &opts, e.radius);
        assert!(
            (lift - e.lift).abs() <= 1e-6 * e.lift,
            "{name}: {lift} {}",
            e.lift
        );
    }
    let mut cols = vec![Vec::with_capacity(n); 2 * picks.len()];
    for act in &draws {
        for (k, (_, e, _)) in picks.iter().enumerate() {
            let [lift, normal] = best_sphere_lift(act, &opts, e.radius);
            cols[2 * k].push(lift);
            cols[2 * k + 1].push(normal);
        }
    }
    for (k, (name, _, sd_e)) in picks.iter().enumerate() {
        agree(
            &format!("study 5 f_v, {name}"),
            sd_e.lift,
            sd(&cols[2 * k]),
            n,
        );
        agree(
            &format!("study 5 F, {name}"),
            sd_e.normal,
            sd(&cols[2 * k + 1]),
            n,
        );
    }
    // without a covariance, none
    let plain = study5_sphere_region(&scene.actuator, &opts).unwrap();
    assert!(plain.envelope_sd.is_empty() && plain.peak_sd.is_none());
    assert_eq!(plain.envelope, region.envelope);
}

#[test]
fn study5_bands_with_one_key_are_central_difference_slopes() {
    // with C = [[1]] over p1 the band is |d(output)/d(p1)|: each envelope
    // point's against central differences of the best lift at its radius
    // (the ordinary path, `Gripper::max_sphere_lift`), and the peak's lift
    // against those of two ordinary runs of the study (the peak is
    // stationary in the radius, so its lift moves as the envelope's at
    // the peak's radius)
    let OneKey {
        scene,
        opts,
        h,
        up,
        down,
    } = one_key_p1();
    let region = study5_sphere_region_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    // The best angle is located to 1e-9 rad (ENVELOPE_BETA_TOL) on a
    // validity boundary, where the lift's slope in the angle is a few N
    // per rad: some 1e-9 N in each lift, against differences 2 h f_v' of
    // about 4e-5 N, and the boundary's own derivative is a Richardson
    // difference; they agree to 2e-4 at this writing, so 1e-3 relative,
    // not the finger's 1e-4
    let tol = 1e-3;
    let mut checked = 0;
    for (e, sd) in region.envelope.iter().zip(&region.envelope_sd) {
        // a best angle held by a boundary the sensitivities do not cover
        // (the largest radius here: the tip's angle limit) has none, and
        // says why
        let Ok(sd) = sd else {
            let why = sd.as_ref().unwrap_err();
            assert!(why.starts_with("no error bars: "), "{why}");
            continue;
        };
        let (a, b) = (
            best_sphere_lift(&up, &opts, e.radius),
            best_sphere_lift(&down, &opts, e.radius),
        );
        for (got, fd, what) in [
            (sd.lift, (a[0] - b[0]) / (2.0 * h), "f_v"),
            (sd.normal, (a[1] - b[1]) / (2.0 * h), "F"),
        ] {
            println!(
                "study 5 {what} at r = {:.2} mm: propagated {got:.6e}, central difference {fd:.6e}",
                e.radius
            );
            assert!(
                (got - fd.abs()).abs() <= tol * fd.abs(),
                "study 5 {what} at r = {:.2} mm: propagated {got}, central difference {fd}",
                e.radius
            );
        }
        checked += 1;
    }
    assert!(
        checked + 2 >= region.envelope.len() && checked >= 6,
        "{checked} of {} envelope points checked",
        region.envelope.len()
    );
    let (u, d) = (
        study5_sphere_region(&up, &opts).unwrap(),
        study5_sphere_region(&down, &opts).unwrap(),
    );
    let fd = (u.peak.unwrap().lift - d.peak.unwrap().lift) / (2.0 * h);
    let got = region.peak_sd.unwrap().unwrap().lift;
    println!("study 5 peak f_v: propagated {got:.6e}, central difference {fd:.6e}");
    assert!(
        (got - fd.abs()).abs() <= tol * fd.abs(),
        "study 5 peak f_v: propagated {got}, central difference {fd}"
    );
}

#[test]
fn study6_bands_match_monte_carlo_through_the_study() {
    // the scan's angles are fixed (they depend on mu only), and the
    // viable interval's ends are the study's own bisection: each draw
    // runs the ordinary study
    let opts = study_options();
    let n = 300;
    let (scene, draws) = study_draws(n, 17);
    let (v, sd6) = study6_viable_angles_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    let sd6 = sd6.unwrap();
    assert_eq!(v.intervals.len(), 1, "{:?}", v.intervals);
    // the scan's first viable angle and the one after it, and both ends
    let first = v.scan.iter().position(|s| s.viable).unwrap();
    let picks = [first, first + 1];
    let mut cols = vec![Vec::with_capacity(n); 2 * picks.len() + 2];
    for act in &draws {
        let w = study6_viable_angles(act, &opts).unwrap();
        for (k, &i) in picks.iter().enumerate() {
            cols[2 * k].push(w.scan[i].normal);
            cols[2 * k + 1].push(w.scan[i].friction);
        }
        assert_eq!(w.intervals.len(), 1, "{:?}", w.intervals);
        cols[4].push(w.intervals[0][0]);
        cols[5].push(w.intervals[0][1]);
    }
    for (k, &i) in picks.iter().enumerate() {
        let row = sd6.scan[i].as_ref().unwrap();
        let at = format!("b = {:.3} rad", v.scan[i].beta);
        agree(&format!("study 6 F, {at}"), row.normal, sd(&cols[2 * k]), n);
        agree(
            &format!("study 6 f, {at}"),
            row.friction,
            sd(&cols[2 * k + 1]),
            n,
        );
    }
    let [lo, hi] = &sd6.intervals[0];
    agree("study 6 lower end", *lo.as_ref().unwrap(), sd(&cols[4]), n);
    agree("study 6 upper end", *hi.as_ref().unwrap(), sd(&cols[5]), n);
}

#[test]
fn study6_bands_with_one_key_are_central_difference_slopes() {
    // with C = [[1]] over p1 the band is |d(output)/d(p1)|: against
    // central differences of two ordinary runs of the study
    let OneKey {
        scene,
        opts,
        h,
        up,
        down,
    } = one_key_p1();
    let (v, sd6) = study6_viable_angles_with(&scene.actuator, &opts, scene.covariance()).unwrap();
    let sd6 = sd6.unwrap();
    let (u, d) = (
        study6_viable_angles(&up, &opts).unwrap(),
        study6_viable_angles(&down, &opts).unwrap(),
    );
    let close = |what: String, got: f64, fd: f64, tol: f64| {
        println!("{what}: propagated {got:.6e}, central difference {fd:.6e}");
        assert!(
            (got - fd.abs()).abs() <= tol * fd.abs(),
            "{what}: propagated {got}, central difference {fd}"
        );
    };
    for (i, s) in v.scan.iter().enumerate() {
        let row = sd6.scan[i].as_ref().unwrap();
        let (a, b) = (&u.scan[i], &d.scan[i]);
        let at = format!("b = {:.3} rad", s.beta);
        let fd = |x: f64, y: f64| (x - y) / (2.0 * h);
        close(
            format!("study 6 F, {at}"),
            row.normal,
            fd(a.normal, b.normal),
            1e-4,
        );
        close(
            format!("study 6 f, {at}"),
            row.friction,
            fd(a.friction, b.friction),
            1e-4,
        );
        close(
            format!("study 6 f/F, {at}"),
            row.ratio.unwrap(),
            fd(a.friction / a.normal, b.friction / b.normal),
            1e-4,
        );
    }
    // the ends are bisected to 1e-9 rad, against differences 2 h db/dp of
    // some 1e-5 rad: 1e-3 relative
    for (k, end) in sd6.intervals[0].iter().enumerate() {
        let fd = (u.intervals[0][k] - d.intervals[0][k]) / (2.0 * h);
        close(format!("study 6 end {k}"), *end.as_ref().unwrap(), fd, 1e-3);
    }
}

#[test]
fn study3_band_is_the_central_difference_slope_of_the_grasp_at_its_size() {
    // with C = [[1]] over cl.e the band is |d(output)/d(cl.e)|: against
    // central differences of the grasp at the point's size (the sweep's
    // grid moves with d_max), each solved through the ordinary scene path
    let text = STUDY_SCENE.replace(
        "parameters = [\"actuator.pemc.eps0\", \"actuator.pemc.p1\", \"actuator.cl.e\"]\ncovariance = [[1e-6, 0.0, 0.0], [0.0, 2.56e-4, -0.12], [0.0, -0.12, 225.0]]",
        "parameters = [\"actuator.cl.e\"]\ncovariance = [[1.0]]",
    );
    let scene = Scene::from_toml(&text).unwrap();
    let region =
        study3_cuboid_region_with(&scene.actuator, &study_options(), scene.covariance()).unwrap();
    let c = &region.curve;
    let valid: Vec<_> = c.points.iter().filter(|p| p.sd.is_some()).collect();
    assert!(valid.len() >= 3, "{} points with a band", valid.len());
    let h = 1e-2;
    let grasp = |e: f64, d: f64| -> (f64, f64, f64) {
        let t = format!(
            "[actuator.cl]\ne = {e:.17e}\n[actuator.pemc]\neps0 = 0.25\n[partition]\nelements = 4\n\
             [gripper]\nmounting_angle_deg = 60.0\noverlap_mm = 20.0\nmu = 0.6\n\
             [gripper.grasp]\nkind = \"size\"\nd_mm = {d:.17e}\npressure_kpa = 0.0\n"
        );
        match Scene::from_toml(&t).unwrap().solve().unwrap() {
            SceneSolution::Gripper {
                gripper,
                grasp: Some(o),
            } => (o.grasp.lift, o.grasp.height, gripper.d_max()),
            _ => panic!("not a grasp"),
        }
    };
    let e = fpc::sensitivity::Param::from_name("actuator.cl.e")
        .unwrap()
        .value(&scene.actuator, &fpc::Load::unloaded(), None)
        .unwrap();
    // inside the sweep: its last point is at d_max, which moves
    for p in [valid[0], valid[valid.len() / 2], valid[3 * valid.len() / 4]] {
        let (mid, _, _) = grasp(e, p.size);
        assert!((mid - p.lift).abs() <= 1e-6 * p.lift, "{mid} vs {}", p.lift);
        let (lu, hu, du) = grasp(e + h, p.size);
        let (ld, hd, dd) = grasp(e - h, p.size);
        let sd = p.sd.unwrap();
        for (what, got, fd) in [
            ("f_v", sd.lift, (lu - ld) / (2.0 * h)),
            ("h", sd.height, (hu - hd) / (2.0 * h)),
            ("d_max", c.d_max_sd.unwrap(), (du - dd) / (2.0 * h)),
        ] {
            assert!(
                (got - fd.abs()).abs() <= 1e-4 * fd.abs().max(1e-6),
                "study 3 {what} at d = {:.2} mm: propagated {got}, central difference {fd}",
                p.size
            );
        }
    }
}
