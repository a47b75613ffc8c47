//! `fpc::calibrate` against data made by the library's ordinary paths
//! (`Finger::solve` and its sampled shape, the circle fit of a solve's
//! points, study 8's `tip_force_for_displacement`), written at full
//! precision: noise-free data give back the truth to 1e-8; a pair of
//! parameters that act only through their sum is reported as not
//! identifiable, naming both; with seeded Gaussian noise the reported
//! standard errors cover the truth at their nominal rate; bad options are
//! errors naming the field.

#[path = "common/measured.rs"]
mod measured;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use fpc::calibrate::{calibrate, CalibrateOptions, Verdict, MAX_FIT_NAMES};
use fpc::circle_fit::fit_circle;
use fpc::measure::{Manifest, TestData};
use fpc::studies::Axis;
use fpc::{Actuator, Finger, Load, SolveOptions};
use tempfile::TempDir;

/// A fresh directory, removed when dropped.
fn dir(tag: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("fpc-calibrate-{tag}-"))
        .tempdir()
        .unwrap()
}

/// The true finger: the paper's actuator with `eps0` and the regular
/// EMC's `e1`, eight equal elements.
/// With the ribs modelled or not.
fn finger_with_ribs(eps0: f64, e1: f64, ribs: bool) -> Finger {
    let mut p = Actuator::default().params().clone();
    p.pemc.eps0 = eps0;
    if let fpc::actuator::Material::Orthotropic(m) = &mut p.emc {
        m.e1 = e1;
    }
    let act = Actuator::new(p).unwrap();
    let part = fpc::Partition::equal(act.geometry().lx, 8).unwrap();
    Finger::new(&act, &part, ribs)
}

/// What one specimen's data hold.
struct Spec<'a> {
    name: &'a str,
    eps0: f64,
    marker_kpa: &'a [f64],
    markers: &'a [f64],
    radius_kpa: &'a [f64],
    force_kpa: &'a [f64],
    axis: Axis,
}

/// Writes the noise-free data of `specs` (true e1 `e1`) and a manifest
/// that starts the fit at `eps0 + shift` and `e1_start`.
fn write_set(d: &Path, specs: &[Spec], e1: f64, shift: f64, e1_start: f64) -> PathBuf {
    write_set_ribs(d, specs, e1, shift, e1_start, true)
}

/// [`write_set`] from fingers with the ribs modelled or not (the manifest
/// always has the default ribs).
fn write_set_ribs(
    d: &Path,
    specs: &[Spec],
    e1: f64,
    shift: f64,
    e1_start: f64,
    ribs: bool,
) -> PathBuf {
    let mut m = format!("[shared.actuator.emc]\ne1 = {e1_start}\n");
    for s in specs {
        let f = finger_with_ribs(s.eps0, e1, ribs);
        write!(
            m,
            "\n[[specimen]]\nname = \"{}\"\n[specimen.own.actuator.pemc]\neps0 = {}\n",
            s.name,
            s.eps0 + shift
        )
        .unwrap();
        if !s.markers.is_empty() {
            let csv = measured::markers_csv(&f, s.marker_kpa, s.markers, 0.3, &mut |_| 0.0);
            let file = format!("{}_markers.csv", s.name);
            std::fs::write(d.join(&file), csv).unwrap();
            write!(
                m,
                "[[specimen.test]]\nkind = \"markers\"\nfile = \"{file}\"\n"
            )
            .unwrap();
        }
        if !s.radius_kpa.is_empty() {
            let mut csv = String::from("pressure_kpa,radius_mm,sd_mm\n");
            for &p in s.radius_kpa {
                let sol = f
                    .solve(
                        &Load::unloaded().with_pressure_kpa(p),
                        &SolveOptions::default(),
                    )
                    .unwrap();
                let r = fit_circle(&sol.points).unwrap().radius;
                writeln!(csv, "{p},{r},{}", 0.02 * r + 0.5).unwrap();
            }
            let file = format!("{}_radius.csv", s.name);
            std::fs::write(d.join(&file), csv).unwrap();
            write!(
                m,
                "[[specimen.test]]\nkind = \"radius\"\nfile = \"{file}\"\n"
            )
            .unwrap();
        }
        if !s.force_kpa.is_empty() {
            let rows: Vec<(f64, Axis)> = s.force_kpa.iter().map(|&p| (p, s.axis)).collect();
            let sd = |force: f64| 0.05 * force.abs() + 0.005;
            let csv = measured::force_csv(&f, &rows, sd, 5, &mut |_| 0.0);
            let file = format!("{}_force.csv", s.name);
            std::fs::write(d.join(&file), csv).unwrap();
            write!(
                m,
                "[[specimen.test]]\nkind = \"force\"\nfile = \"{file}\"\n"
            )
            .unwrap();
        }
    }
    let path = d.join("manifest.toml");
    std::fs::write(&path, m).unwrap();
    path
}

/// Every standard deviation of `m` divided by `factor`.
fn more_precise(m: &mut Manifest, factor: f64) {
    for s in &mut m.specimens {
        for t in &mut s.tests {
            match &mut t.data {
                TestData::Markers { rows, .. } => rows.iter_mut().for_each(|r| r.sd_mm /= factor),
                TestData::Radius(rows) => rows.iter_mut().for_each(|r| r.sd_mm /= factor),
                TestData::Force(rows) => rows.iter_mut().for_each(|r| r.sd_n /= factor),
            }
        }
    }
}

const SPECS: [Spec<'static>; 2] = [
    Spec {
        name: "a",
        eps0: 0.15,
        marker_kpa: &[0.0, 30.0, 60.0],
        markers: &[27.5, 55.0, 82.5, 110.0],
        radius_kpa: &[],
        force_kpa: &[0.0, 55.2],
        axis: Axis::Z,
    },
    Spec {
        name: "b",
        eps0: 0.4,
        marker_kpa: &[0.0, 40.0],
        markers: &[55.0, 110.0],
        radius_kpa: &[0.0, 50.0, 100.0],
        force_kpa: &[],
        axis: Axis::X,
    },
];

#[test]
fn noise_free_data_give_back_the_truth() {
    let d = dir("truth");
    let path = write_set(d.path(), &SPECS, 1.5, 0.03, 1.9);
    let m = Manifest::load(&path).unwrap();
    let fit = calibrate(&m, &CalibrateOptions::new(&["eps0", "kappa", "emc.e1"])).unwrap();
    let truth = |name: &str| match name {
        "actuator.pemc.eps0[a]" => 0.15,
        "actuator.pemc.eps0[b]" => 0.4,
        "load.kappa" => 2.5,
        "actuator.emc.e1" => 1.5,
        n => panic!("unexpected unknown {n}"),
    };
    assert_eq!(fit.parameters.len(), 4);
    for p in &fit.parameters {
        let t = truth(&p.name);
        let rel = (p.value - t).abs() / t;
        assert!(
            rel < 1e-8,
            "{}: {} against {t} ({rel:.1e}); {fit:#?}",
            p.name,
            p.value
        );
        assert!(p.standard_error.unwrap() > 0.0);
    }
    assert!(
        fit.start_chi_square > 1e3,
        "the start is far off: {}",
        fit.start_chi_square
    );
    assert!(fit.chi_square < 1e-12, "{}", fit.chi_square);
    assert_eq!(
        fit.identifiability.verdict,
        Verdict::Identifiable,
        "{}",
        fit.identifiability.message
    );
    assert_eq!(fit.dof, fit.points - 4);
    assert!(fit.solves > 0 && fit.target_solves > 0 && fit.iterations > 0);
    // each pressure left out and predicted by the fit without it: exact
    // data are predicted exactly
    let opts = CalibrateOptions {
        cross_validate: true,
        ..CalibrateOptions::new(&["eps0", "kappa", "emc.e1"])
    };
    let cv = calibrate(&m, &opts).unwrap().cross_validation.unwrap();
    assert_eq!(cv.points, fit.points);
    assert_eq!(cv.held_out.len(), 7, "{cv:#?}");
    for h in &cv.held_out {
        assert!(h.failure.is_none() && h.rms_sd < 1e-6, "{h:?}");
    }
    let corr = fit.correlation.unwrap();
    for (i, row) in corr.iter().enumerate() {
        assert!((row[i] - 1.0).abs() < 1e-12);
        assert!(row.iter().all(|c| c.abs() <= 1.0 + 1e-12));
    }
}

#[test]
fn two_moduli_acting_through_their_sum_are_not_identifiable() {
    // The regular EMC (nu12 = 0) and the prestressed layer (no Poisson
    // coupling) are as thick and as wide as each other, so their Y moduli
    // enter the energy only through 1/2 (e2_emc + e2_pemc) A b1^2: any
    // change of one made up by the other leaves every prediction alone.
    let d = dir("pair");
    let specs = [Spec {
        name: "a",
        eps0: 0.25,
        marker_kpa: &[0.0, 40.0, 80.0],
        markers: &[27.5, 55.0, 82.5, 110.0],
        radius_kpa: &[],
        force_kpa: &[],
        axis: Axis::X,
    }];
    let path = write_set(d.path(), &specs, 1.5, 0.0, 1.5);
    let m = Manifest::load(&path).unwrap();
    let fit = calibrate(&m, &CalibrateOptions::new(&["eps0", "emc.e2", "pemc.e2"])).unwrap();
    let id = &fit.identifiability;
    assert_eq!(id.verdict, Verdict::NotIdentifiable, "{}", id.message);
    let named: Vec<&str> = id.weakest.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(named.len(), 2, "{named:?}");
    assert!(named.contains(&"actuator.emc.e2") && named.contains(&"actuator.pemc.e2"));
    assert!(!named.iter().any(|n| n.contains("eps0")));
    // opposite signs: the sum is what the data see
    assert!(id.weakest[0].weight * id.weakest[1].weight < 0.0);
    assert!(id.message.contains("actuator.emc.e2") && id.message.contains("actuator.pemc.e2"));
    assert!(fit.covariance.is_none() && fit.parameters.iter().all(|p| p.standard_error.is_none()));
}

/// A standard normal variate (Box-Muller).
fn normal(rng: &mut fastrand::Rng) -> f64 {
    let u = 1.0 - rng.f64();
    let v = rng.f64();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

#[test]
fn standard_errors_cover_the_truth_at_their_nominal_rate() {
    // A cheap specimen (four markers at two pressures, 16 residuals) so
    // that 200 fits run in a debug build; eps0 and kappa fitted.
    let d = dir("coverage");
    let specs = [Spec {
        name: "a",
        eps0: 0.25,
        marker_kpa: &[0.0, 60.0],
        markers: &[27.5, 55.0, 82.5, 110.0],
        radius_kpa: &[],
        force_kpa: &[],
        axis: Axis::X,
    }];
    let path = write_set(d.path(), &specs, 1.5, 0.0, 1.5);
    let base = Manifest::load(&path).unwrap();
    let truth = [0.25, 2.5];
    let opts = CalibrateOptions::new(&["eps0", "kappa"]);
    let mut rng = fastrand::Rng::with_seed(2021);
    const TRIALS: usize = 200;
    let (mut one, mut three) = ([0usize; 2], [0usize; 2]);
    for _ in 0..TRIALS {
        let mut m = base.clone();
        for t in &mut m.specimens[0].tests {
            if let TestData::Markers { rows, .. } = &mut t.data {
                for r in rows {
                    r.point_mm[0] += r.sd_mm * normal(&mut rng);
                    r.point_mm[1] += r.sd_mm * normal(&mut rng);
                }
            }
        }
        let fit = calibrate(&m, &opts).unwrap();
        for (k, p) in fit.parameters.iter().enumerate() {
            let z = (p.value - truth[k]).abs() / p.standard_error.unwrap();
            one[k] += usize::from(z <= 1.0);
            three[k] += usize::from(z <= 3.0);
        }
    }
    // 200 trials: the 1-sigma count is binomial with p = 0.6827, sd
    // sqrt(p (1 - p) / 200) = 0.033 of the rate; we accept 3 sd (0.099)
    // either side, which a correct error misses with probability 0.3 %
    // per parameter (the linearisation's bias at this noise is far
    // smaller).
    for k in 0..2 {
        let rate = one[k] as f64 / TRIALS as f64;
        assert!(
            (rate - 0.6827).abs() < 0.099,
            "parameter {k}: 1-sigma coverage {rate}"
        );
        let rate3 = three[k] as f64 / TRIALS as f64;
        assert!(rate3 >= 0.99, "parameter {k}: 3-sigma coverage {rate3}");
        eprintln!("parameter {k}: 1-sigma {rate}, 3-sigma {rate3}");
    }
}

#[test]
fn bad_options_are_errors_naming_the_field() {
    let d = dir("bad");
    let path = write_set(d.path(), &SPECS[1..], 1.5, 0.0, 1.5);
    let m = Manifest::load(&path).unwrap();
    let field = |o: CalibrateOptions| match calibrate(&m, &o) {
        Err(fpc::SolveError::Input(e)) => (e.field().to_string(), e.to_string()),
        other => panic!("{other:?}"),
    };
    // more distinct pressures than a cross-validation leaves out
    let mut many = m.clone();
    if let TestData::Markers { rows, .. } = &mut many.specimens[0].tests[0].data {
        let proto = rows[0].clone();
        rows.clear();
        for i in 0..=fpc::calibrate::MAX_HELD_OUT_PRESSURES {
            let mut r = proto.clone();
            r.pressure_kpa = i as f64;
            rows.push(r);
        }
    }
    let cv = CalibrateOptions {
        cross_validate: true,
        ..CalibrateOptions::new(&["eps0"])
    };
    match calibrate(&many, &cv) {
        Err(fpc::SolveError::Input(e)) => assert_eq!(e.field().to_string(), "cross_validate"),
        other => panic!("{other:?}"),
    }
    let names: Vec<String> = (0..=MAX_FIT_NAMES).map(|i| format!("p{i}")).collect();
    for (o, want) in [
        (CalibrateOptions::new::<&str>(&[]), "fit"),
        (CalibrateOptions::new(&["nonsense"]), "fit"),
        (CalibrateOptions::new(&["load.pressure_kpa"]), "fit"),
        (
            CalibrateOptions::new(&["eps0", "actuator.pemc.eps0"]),
            "fit",
        ),
        (CalibrateOptions::new(&names), "fit"),
        (
            CalibrateOptions {
                max_iterations: 0,
                ..CalibrateOptions::new(&["eps0"])
            },
            "max_iterations",
        ),
        (CalibrateOptions::new(&["cl.e1"]), "fit"),
        // no markers test with a camera frame
        (CalibrateOptions::new(&["camera"]), "fit"),
    ] {
        let (f, msg) = field(o);
        assert_eq!(f, want, "{msg}");
        assert!(!msg.contains("NaN"), "{msg}");
    }
}

#[test]
fn a_camera_frame_is_fitted_with_the_model() {
    // specimen a's markers seen by a camera turned by 4 degrees with its
    // origin at (-15, 40) mm; the manifest's frame starts off by 1 degree
    // and 1 mm, the angle also written a turn away (-357 degrees is 3)
    for start in [3.0, -357.0] {
        camera_fit_from(start);
    }
}

fn camera_fit_from(start_angle_deg: f64) {
    let d = dir("camera");
    let path = write_set(d.path(), &SPECS, 1.5, 0.03, 1.5);
    let mut m = Manifest::load(&path).unwrap();
    let truth = fpc::measure::CameraFrame {
        angle_deg: 4.0,
        x_mm: -15.0,
        z_mm: 40.0,
    };
    for t in &mut m.specimens[0].tests {
        if let TestData::Markers { camera, rows } = &mut t.data {
            for r in rows.iter_mut() {
                r.point_mm = truth.to_camera(r.point_mm);
            }
            *camera = Some(fpc::measure::CameraFrame {
                angle_deg: start_angle_deg,
                x_mm: -14.0,
                z_mm: 41.0,
            });
        }
    }
    let fit = calibrate(&m, &CalibrateOptions::new(&["eps0", "kappa", "camera"])).unwrap();
    let want = |name: &str| match name {
        "actuator.pemc.eps0[a]" => 0.15,
        "actuator.pemc.eps0[b]" => 0.4,
        "load.kappa" => 2.5,
        "camera.angle_deg[a, test 1]" => 4.0,
        "camera.x_mm[a, test 1]" => -15.0,
        "camera.z_mm[a, test 1]" => 40.0,
        n => panic!("unexpected unknown {n}"),
    };
    assert_eq!(fit.parameters.len(), 6);
    assert!(fit.chi_square < 1e-12, "{}", fit.chi_square);
    for p in &fit.parameters {
        let t = want(&p.name);
        assert!(
            (p.value - t).abs() < 1e-8 * t.abs(),
            "{}: {} against {t}",
            p.name,
            p.value
        );
    }
    // the scenes carry the finger's parameters, not the camera's
    let scenes = fpc::calibrate::calibrated_scenes(&m, &fit).unwrap();
    assert!(scenes
        .iter()
        .all(|(_, s)| !s.contains("angle_deg") && !s.contains("z_mm")));
}

#[test]
fn data_of_a_finger_without_ribs_report_their_misfit() {
    // Noise-free data of fingers without ribs, fitted with the default
    // ribs. At the synthetic set's standard deviations (markers 0.3 mm,
    // radii 2 % + 0.5 mm, forces 5 %) eps0 and kappa absorb the ribs
    // (chi-square per dof about 0.06: the data cannot tell); with data 30
    // times as precise the same fit reports the misfit, in its chi-square
    // per degree of freedom and in its held-out pressures.
    let d = dir("ribs");
    let path = write_set_ribs(d.path(), &SPECS, 1.5, 0.0, 1.5, false);
    let mut m = Manifest::load(&path).unwrap();
    let opts = CalibrateOptions {
        cross_validate: true,
        ..CalibrateOptions::new(&["eps0", "kappa"])
    };
    let coarse = calibrate(&m, &opts).unwrap();
    assert!(
        coarse.chi_square_per_dof < 1.0,
        "{}",
        coarse.chi_square_per_dof
    );
    more_precise(&mut m, 30.0);
    let fit = calibrate(&m, &opts).unwrap();
    let cv = fit.cross_validation.as_ref().unwrap();
    eprintln!(
        "without ribs: chi2/dof {:.3} (at the set's sd {:.3}), held out rms {:.3} sd",
        fit.chi_square_per_dof, coarse.chi_square_per_dof, cv.rms_sd
    );
    assert!(fit.chi_square_per_dof > 10.0, "{}", fit.chi_square_per_dof);
    assert!(cv.rms_sd > 3.0, "{}", cv.rms_sd);
}

#[test]
fn the_model_choice_picks_the_model_the_data_were_made_with() {
    // Noise-free data of fingers without ribs (the ccm model), precise
    // enough that ribs cannot hide in the noise: among every element model
    // with and without ribs, the held-out error ranks the true one first,
    // predicting the pressures it did not see to rounding, while the same
    // model with ribs misses them by several standard deviations.
    let d = dir("choice");
    let path = write_set_ribs(d.path(), &SPECS, 1.5, 0.0, 1.5, false);
    let mut m = Manifest::load(&path).unwrap();
    more_precise(&mut m, 30.0);
    let choice =
        fpc::calibrate::choose_model(&m, &CalibrateOptions::new(&["eps0", "kappa"])).unwrap();
    let n = fpc::ModelId::ALL.len();
    // with and without ribs, in plane stress and in plane strain
    assert_eq!(choice.candidates.len(), 4 * n);
    for c in &choice.candidates {
        eprintln!("{c}");
    }
    let best = &choice.candidates[choice.best.unwrap()];
    assert_eq!(
        (best.model, best.ribs, best.plane_strain),
        ("ccm", false, false),
        "{choice:?}"
    );
    assert!(best.held_out_rms_sd.unwrap() < 1e-3, "{best:?}");
    // the truth: eps0 of both specimens, then kappa
    let truth = [0.15, 0.4, 2.5];
    for (name, (v, t)) in choice.names.iter().zip(best.values.iter().zip(truth)) {
        assert!((v - t).abs() < 1e-6 * t, "{name}: {v} vs {t}");
    }
    let with_ribs = choice
        .candidates
        .iter()
        .find(|c| c.model == "ccm" && c.ribs && !c.plane_strain)
        .unwrap();
    assert!(with_ribs.held_out_rms_sd.unwrap() > 3.0, "{with_ribs:?}");
}

#[test]
fn too_many_unknowns_are_refused_with_their_real_count() {
    // 22 markers tests with a camera frame: 66 camera unknowns, over the 64
    let d = dir("unknowns");
    let path = write_set(d.path(), &SPECS, 1.5, 0.03, 1.5);
    let mut m = Manifest::load(&path).unwrap();
    let mut markers = m.specimens[0]
        .tests
        .iter()
        .find(|t| matches!(t.data, TestData::Markers { .. }))
        .unwrap()
        .clone();
    if let TestData::Markers { camera, .. } = &mut markers.data {
        *camera = Some(fpc::measure::CameraFrame {
            angle_deg: 0.0,
            x_mm: 0.0,
            z_mm: 0.0,
        });
    }
    m.specimens[0].tests = vec![markers; 22];
    let e = calibrate(&m, &CalibrateOptions::new(&["camera"])).unwrap_err();
    let text = e.to_string();
    assert!(
        text.starts_with("fit = 66: more than 64 unknowns"),
        "{text}"
    );
}

#[test]
fn a_row_the_model_cannot_solve_is_named_by_its_file_and_line() {
    // the shipped example with one radius row far past any finger appended
    let d = dir("unsolvable");
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/calibration");
    for entry in std::fs::read_dir(&shipped).unwrap() {
        let p = entry.unwrap().path();
        std::fs::copy(&p, d.path().join(p.file_name().unwrap())).unwrap();
    }
    let csv = d.path().join("eps0-0.25_radius.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.ends_with('\n'));
    let lines = text.lines().count();
    std::fs::write(&csv, format!("{text}5000,50,1\n")).unwrap();
    let m = Manifest::load(&d.path().join("manifest.toml")).unwrap();
    let e = calibrate(&m, &CalibrateOptions::new(&["eps0", "kappa"])).unwrap_err();
    let text = e.to_string();
    let at = format!(
        "eps0-0.25_radius.csv:{}: the model does not solve at 5000 kPa",
        lines + 1
    );
    assert!(matches!(e, fpc::SolveError::Input(_)), "{e:?}");
    assert!(
        text.starts_with("pressure_kpa: ") && text.contains(&at),
        "{text}"
    );
}

#[test]
fn a_refit_left_without_enough_data_is_a_failure_not_the_full_fit() {
    // one specimen's markers at one pressure only: leaving that pressure
    // out leaves nothing to fit eps0 to
    let d = dir("one-pressure");
    let path = write_set(d.path(), &SPECS, 1.5, 0.0, 1.5);
    let mut m = Manifest::load(&path).unwrap();
    m.specimens.truncate(1);
    m.specimens[0]
        .tests
        .retain(|t| matches!(t.data, TestData::Markers { .. }));
    for t in &mut m.specimens[0].tests {
        if let TestData::Markers { rows, .. } = &mut t.data {
            rows.retain(|r| r.pressure_kpa == 0.0);
        }
    }
    let opts = CalibrateOptions {
        cross_validate: true,
        ..CalibrateOptions::new(&["eps0"])
    };
    let fit = calibrate(&m, &opts).unwrap();
    let cv = fit.cross_validation.unwrap();
    assert_eq!(cv.held_out.len(), 1, "{cv:#?}");
    let h = &cv.held_out[0];
    let why = h.failure.as_deref().unwrap_or_default();
    assert!(why.contains("the data without 0 kPa has 0"), "{h:?}");
    assert!(h.values.is_empty() && h.points == 0, "{h:?}");
}

#[test]
fn a_fit_far_from_its_data_is_reproduced_to_a_fraction_of_its_residuals() {
    // radii of a nearly straight finger, 1 mm standard deviations: the
    // model stays far from them (residuals of about 1e5 sd), and the two
    // paths' radii of a nearly straight mid-plane agree to about 1e-8 of
    // themselves, not to 1e-6 sd
    let d = dir("far");
    std::fs::write(
        d.path().join("m.toml"),
        "[[specimen]]\nname = \"a\"\n[[specimen.test]]\nkind = \"radius\"\nfile = \"r.csv\"\n",
    )
    .unwrap();
    std::fs::write(
        d.path().join("r.csv"),
        "pressure_kpa,radius_mm,sd_mm\n0,100000,1\n10,99999,1\n20,99998,1\n",
    )
    .unwrap();
    let m = Manifest::load(&d.path().join("m.toml")).unwrap();
    let fit = calibrate(&m, &CalibrateOptions::new(&["eps0"])).unwrap();
    let r = &fit.reproduction;
    assert!(fit.chi_square > 1e8, "{}", fit.chi_square);
    assert!(r.reproduced, "{r:?}");
    let claimed = fit.chi_square;
    let again = r.chi_square.unwrap();
    assert!(
        (again - claimed).abs() <= 1e-9 * claimed,
        "{again} vs {claimed}"
    );
}
