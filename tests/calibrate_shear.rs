//! `fpc::calibrate` on the shear model's data and on the state across the
//! width, against synthetic data made by the library's ordinary solve
//! paths with a known truth (`Finger::solve` and its shape samples, study
//! 8's `tip_force_for_displacement`):
//!
//! - forces of a `shear` finger with shear correction 0.5, with seeded
//!   Gaussian noise at their stated standard deviations: the fit of
//!   `shear_correction` (with eps0) from the default 5/6 lands within three
//!   of its reported standard errors of the truth;
//! - noise-free data of a `shear` finger whose constraining layer has a
//!   given G13: the fit of `cl.g13` gives it back;
//! - noise-free, precise data of a finger in plane strain across the
//!   width: the model choice ranks plane strain first by held-out error.

#[path = "common/measured.rs"]
mod measured;

use std::path::{Path, PathBuf};

use fpc::calibrate::{calibrate, choose_model, CalibrateOptions};
use fpc::measure::Manifest;
use fpc::studies::Axis;
use fpc::{Actuator, ActuatorParams, Finger, ModelId, Partition};
use tempfile::TempDir;

/// A fresh directory, removed when dropped.
fn dir(tag: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("fpc-calibrate-shear-{tag}-"))
        .tempdir()
        .unwrap()
}

/// A standard normal variate (Box-Muller).
fn normal(rng: &mut fastrand::Rng) -> f64 {
    let u = 1.0 - rng.f64();
    let v = rng.f64();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// The true finger: `params` with `model`, eight equal elements, ribs.
fn finger(model: ModelId, params: ActuatorParams) -> Finger {
    let act = Actuator::new(params).unwrap();
    let part = Partition::equal(act.geometry().lx, 8).unwrap();
    Finger::with_model(model, &act, &part, true)
}

/// What one specimen's data hold, and how precise they are.
struct Data<'a> {
    /// Markers (arc length, mm) sampled at each of these pressures (kPa).
    marker_kpa: &'a [f64],
    markers: &'a [f64],
    marker_sd_mm: f64,
    /// Study 8 forces (10 mm along the axis) at these pressures.
    force: &'a [(f64, Axis)],
    /// The force's standard deviation, relative to the force.
    force_sd: f64,
}

/// Writes the data of `f` (noisy at their standard deviations when `rng`
/// is given) and a manifest with the `shared` tables and specimen `a`,
/// whose own prestrain starts at `eps0_start`.
fn write_manifest(
    d: &Path,
    f: &Finger,
    data: &Data,
    shared: &str,
    eps0_start: f64,
    mut rng: Option<&mut fastrand::Rng>,
) -> PathBuf {
    let mut noise = |sd: f64| rng.as_deref_mut().map_or(0.0, |r| sd * normal(r));
    let mut m = format!(
        "{shared}\n[[specimen]]\nname = \"a\"\n[specimen.own.actuator.pemc]\neps0 = {eps0_start}\n"
    );
    if !data.markers.is_empty() {
        let csv = measured::markers_csv(
            f,
            data.marker_kpa,
            data.markers,
            data.marker_sd_mm,
            &mut noise,
        );
        std::fs::write(d.join("markers.csv"), csv).unwrap();
        m.push_str("[[specimen.test]]\nkind = \"markers\"\nfile = \"markers.csv\"\n");
    }
    if !data.force.is_empty() {
        let sd = |force: f64| data.force_sd * force.abs();
        let csv = measured::force_csv(f, data.force, sd, 1, &mut noise);
        std::fs::write(d.join("force.csv"), csv).unwrap();
        m.push_str("[[specimen.test]]\nkind = \"force\"\nfile = \"force.csv\"\n");
    }
    let path = d.join("manifest.toml");
    std::fs::write(&path, m).unwrap();
    path
}

/// Forces along both axes at four pressures: what sees the shear (pressure
/// alone bends an element by a moment, without shear force).
const FORCES: [(f64, Axis); 8] = [
    (0.0, Axis::X),
    (0.0, Axis::Z),
    (20.0, Axis::X),
    (20.0, Axis::Z),
    (40.0, Axis::X),
    (40.0, Axis::Z),
    (55.2, Axis::X),
    (55.2, Axis::Z),
];

#[test]
fn the_shear_correction_is_recovered_within_three_standard_errors() {
    let d = dir("ks");
    let mut truth = ActuatorParams::default();
    truth.pemc.eps0 = 0.25;
    truth.shear.correction = 0.5;
    let f = finger(ModelId::Shear, truth);
    let data = Data {
        marker_kpa: &[0.0, 40.0],
        markers: &[55.0, 110.0],
        marker_sd_mm: 0.01,
        force: &FORCES,
        force_sd: 2e-4,
    };
    let mut rng = fastrand::Rng::with_seed(25);
    // the fit starts from the default ks = 5/6 and eps0 0.02 off
    let path = write_manifest(
        d.path(),
        &f,
        &data,
        "[shared.model]\nname = \"shear\"\n",
        0.27,
        Some(&mut rng),
    );
    let m = Manifest::load(&path).unwrap();
    let fit = calibrate(&m, &CalibrateOptions::new(&["eps0", "shear_correction"])).unwrap();
    let get = |name: &str| {
        fit.parameters
            .iter()
            .find(|p| p.name == name)
            .unwrap_or_else(|| panic!("no {name}: {fit:#?}"))
    };
    for (name, t) in [
        ("actuator.pemc.eps0[a]", 0.25),
        ("actuator.laminate.shear_correction", 0.5),
    ] {
        let p = get(name);
        let se = p.standard_error.unwrap();
        eprintln!(
            "{name}: {:.5} +- {se:.5} (truth {t}, {:.2} sd off)",
            p.value,
            (p.value - t) / se
        );
        assert!((p.value - t).abs() <= 3.0 * se, "{name}: {p:?}");
    }
    // the data determine ks to a few per cent: the check has teeth
    let ks = get("actuator.laminate.shear_correction");
    assert!(ks.standard_error.unwrap() < 0.05, "{ks:?}");
    assert!(
        (0.3..3.0).contains(&fit.chi_square_per_dof),
        "{}",
        fit.chi_square_per_dof
    );
    // the calibrated scene carries the fitted factor and solves
    let scenes = fpc::calibrate::calibrated_scenes(&m, &fit).unwrap();
    let scene = fpc::scene::Scene::from_toml(&scenes[0].1).unwrap();
    assert_eq!(scene.actuator.shear_correction(), ks.value);
}

#[test]
fn a_given_transverse_shear_modulus_is_recovered() {
    let d = dir("g13");
    let mut truth = ActuatorParams::default();
    truth.pemc.eps0 = 0.25;
    // the film's G13 at half its default (106.6 MPa)
    truth.shear.g13[fpc::actuator::ShearLayer::Cl as usize] = Some(50.0);
    let f = finger(ModelId::Shear, truth);
    let data = Data {
        marker_kpa: &[],
        markers: &[],
        marker_sd_mm: 0.0,
        force: &FORCES,
        force_sd: 1e-4,
    };
    let path = write_manifest(
        d.path(),
        &f,
        &data,
        "[shared.model]\nname = \"shear\"\n",
        0.25,
        None,
    );
    let m = Manifest::load(&path).unwrap();
    let fit = calibrate(&m, &CalibrateOptions::new(&["cl.g13"])).unwrap();
    let p = &fit.parameters[0];
    eprintln!("cl.g13: {} (truth 50)", p.value);
    assert_eq!(p.name, "actuator.cl.g13");
    assert!((p.value - 50.0).abs() < 1e-5 * 50.0, "{p:?}");
    assert!(fit.chi_square < 1e-8, "{}", fit.chi_square);
}

#[test]
fn the_model_choice_ranks_plane_strain_first_for_plane_strain_data() {
    // noise-free data of a ccm finger with ribs in plane strain, precise
    // enough that the state across the width cannot hide in the noise
    let d = dir("plane-strain");
    let mut truth = ActuatorParams::default();
    truth.pemc.eps0 = 0.25;
    truth.plane_strain = true;
    let f = finger(ModelId::Ccm, truth);
    let data = Data {
        marker_kpa: &[0.0, 30.0, 60.0],
        markers: &[55.0, 82.5, 110.0],
        marker_sd_mm: 1e-3,
        force: &[(0.0, Axis::Z), (40.0, Axis::Z)],
        force_sd: 1e-4,
    };
    // the manifest says plane stress: the choice must find plane strain
    let path = write_manifest(d.path(), &f, &data, "", 0.27, None);
    let m = Manifest::load(&path).unwrap();
    let choice = choose_model(&m, &CalibrateOptions::new(&["eps0", "kappa"])).unwrap();
    for c in &choice.candidates {
        eprintln!("{c}");
    }
    let best = &choice.candidates[choice.best.unwrap()];
    assert_eq!(
        (best.model, best.ribs, best.plane_strain),
        ("ccm", true, true),
        "{choice:?}"
    );
    assert!(best.held_out_rms_sd.unwrap() < 1e-3, "{best:?}");
    // eps0 and kappa recovered
    for (name, (v, t)) in choice.names.iter().zip(best.values.iter().zip([0.25, 2.5])) {
        assert!((v - t).abs() < 1e-6 * t, "{name}: {v} vs {t}");
    }
    // the same model in plane stress predicts what it did not see worse
    let stress = choice
        .candidates
        .iter()
        .find(|c| c.model == "ccm" && c.ribs && !c.plane_strain)
        .unwrap();
    assert!(
        stress.held_out_rms_sd.unwrap() > 1.0,
        "plane stress: {stress:?}"
    );
}
