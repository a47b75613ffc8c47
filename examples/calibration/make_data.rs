//! Writes the SYNTHETIC measurement set of examples/calibration/ (cargo
//! run --example make_calibration_data): a manifest and, for three
//! specimens of the paper's actuator at eps0 = 0.15, 0.25 and 0.4, marker,
//! radius and force CSV files computed from the model and perturbed by
//! seeded Gaussian noise of the standard deviations the files state.
//!
//! The values come from the library's ordinary paths, not from `fpc
//! compare`: markers from the sampled mid-plane of `Finger::solve`, radii
//! from study 7, forces from study 8. tests/measure.rs calls [`generate`]
//! to make noise-free sets.

use std::error::Error;
use std::fmt::Write as _;
use std::path::Path;

use fpc::studies::{study7_curvature, study8_force_at_displacement, Axis};
use fpc::{Actuator, Finger, Load, SolveOptions, StudyOptions};

/// The specimens: name and true prestrain.
pub const SPECIMENS: [(&str, f64); 3] =
    [("eps0-0.15", 0.15), ("eps0-0.25", 0.25), ("eps0-0.4", 0.4)];
/// The seed of the noise.
pub const SEED: u64 = 21;
/// Standard deviation of a marker coordinate (mm).
pub const MARKER_SD_MM: f64 = 0.3;
/// Marker pressures (kPa).
pub const MARKER_PRESSURES_KPA: [f64; 3] = [0.0, 30.0, 60.0];
/// Repeats of a force measurement.
pub const REPEATS: u32 = 5;
/// The camera frame of the eps0 = 0.25 specimen's markers: rotation
/// (degrees) and its origin in the finger frame (mm).
pub const CAMERA: (f64, f64, f64) = (4.0, -15.0, 40.0);

/// Mid-plane samples per element; the markers sit on samples.
const PER_ELEMENT: usize = 4;
/// Elements of the fingers (the paper's, and a scene's default).
const ELEMENTS: usize = 8;
/// The markers: name and sample index from the root.
const MARKERS: [(&str, usize); 6] = [
    ("M1", 2),
    ("M2", 8),
    ("M3", 10),
    ("M4", 16),
    ("M5", 24),
    ("M6", 32),
];

/// Options of a generated set.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Add the seeded noise (false: the model's values exactly).
    pub noise: bool,
    /// Added to every specimen's eps0 in the manifest, not in the data (a
    /// model that is wrong by this much).
    pub manifest_eps0_shift: f64,
}

/// A standard normal variate (Box-Muller).
fn normal(rng: &mut fastrand::Rng) -> f64 {
    let u = 1.0 - rng.f64();
    let v = rng.f64();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// Writes the manifest and the CSV files into `dir`.
pub fn generate(dir: &Path, o: Options) -> Result<(), Box<dyn Error>> {
    let mut rng = fastrand::Rng::with_seed(SEED);
    let mut noise = |sd: f64| if o.noise { sd * normal(&mut rng) } else { 0.0 };
    let header = "# SYNTHETIC data from examples/calibration/make_data.rs (the model plus seeded noise), not measurements\n";
    let study = StudyOptions {
        pressure_points: 17, // 0, 25, ..., 400 kPa
        ..StudyOptions::default()
    };
    let radii = study7_curvature(&Actuator::default(), &study)?;
    let forces = study8_force_at_displacement(&Actuator::default(), &study)?;
    let mut manifest = String::from(header);
    manifest.push_str(
        "# Every specimen is the paper's actuator (the scene defaults); each has its own prestrain.\n\
         [shared.actuator.pemc]\ne2 = 250.0\n",
    );
    for (name, eps0) in SPECIMENS {
        write!(
            manifest,
            "\n[[specimen]]\nname = \"{name}\"\n[specimen.own.actuator.pemc]\neps0 = {}\n",
            eps0 + o.manifest_eps0_shift
        )?;
        // markers: the sampled mid-plane of an ordinary solve
        let finger = Finger::paper(eps0, ELEMENTS)?;
        let camera = (eps0 == 0.25).then_some(CAMERA);
        let mut csv = format!("{header}pressure_kpa,marker,s_mm,x_mm,z_mm,sd_mm\n");
        let lx = finger.length();
        for p in MARKER_PRESSURES_KPA {
            let sol = finger.solve(
                &Load::unloaded().with_pressure_kpa(p),
                &SolveOptions::default(),
            )?;
            let pts = finger.shape(&sol.coefficients, PER_ELEMENT)?;
            for (m, i) in MARKERS {
                let s = lx * i as f64 / (ELEMENTS * PER_ELEMENT) as f64;
                let mut q = pts[i];
                if let Some((a, x0, z0)) = camera {
                    // camera = R(-a) (finger - origin)
                    let (sn, cs) = (-a.to_radians()).sin_cos();
                    let (dx, dz) = (q[0] - x0, q[1] - z0);
                    q = [cs * dx - sn * dz, sn * dx + cs * dz];
                }
                writeln!(
                    csv,
                    "{p},{m},{s},{:.4},{:.4},{MARKER_SD_MM}",
                    q[0] + noise(MARKER_SD_MM),
                    q[1] + noise(MARKER_SD_MM)
                )?;
            }
        }
        let file = format!("{name}_markers.csv");
        std::fs::write(dir.join(&file), csv)?;
        write!(
            manifest,
            "[[specimen.test]]\nkind = \"markers\"\nfile = \"{file}\"\n"
        )?;
        if let Some((a, x, z)) = camera {
            writeln!(
                manifest,
                "camera = {{ angle_deg = {a}, x_mm = {x}, z_mm = {z} }}"
            )?;
        }
        // radius: study 7's circle fits up to 200 kPa, while the radius
        // stays below 1 m
        let curve = radii
            .iter()
            .find(|c| c.eps0 == eps0)
            .ok_or("study 7 curve")?;
        let mut csv = format!("{header}pressure_kpa,radius_mm,sd_mm\n");
        for r in curve.rows.iter().filter(|r| r.pressure_kpa <= 200.0) {
            let Some(radius) = r.radius.filter(|&x| x < 1000.0) else {
                continue;
            };
            let sd = 0.02 * radius + 0.5;
            writeln!(csv, "{},{:.4},{sd:.3}", r.pressure_kpa, radius + noise(sd))?;
        }
        let file = format!("{name}_radius.csv");
        std::fs::write(dir.join(&file), csv)?;
        write!(
            manifest,
            "[[specimen.test]]\nkind = \"radius\"\nfile = \"{file}\"\n"
        )?;
        // force: study 8's samples (eps0 = 0.4 along X, 0.15 along Z)
        let rows: Vec<_> = forces.iter().filter(|r| r.eps0 == eps0).collect();
        if rows.is_empty() {
            continue;
        }
        let mut csv = format!("{header}pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n");
        for r in rows {
            let Some(f) = r.force else { continue };
            let sd = 0.05 * f.abs() + 0.005;
            let axis = if r.axis == Axis::X { "X" } else { "Z" };
            let mean = f + noise(sd / f64::from(REPEATS).sqrt());
            writeln!(
                csv,
                "{},{axis},10,{mean:.5},{sd:.4},{REPEATS}",
                r.pressure_kpa
            )?;
        }
        let file = format!("{name}_force.csv");
        std::fs::write(dir.join(&file), csv)?;
        write!(
            manifest,
            "[[specimen.test]]\nkind = \"force\"\nfile = \"{file}\"\n"
        )?;
    }
    std::fs::write(dir.join("manifest.toml"), manifest)?;
    Ok(())
}

#[allow(dead_code)] // tests/measure.rs includes this file for `generate`
fn main() -> Result<(), Box<dyn Error>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/calibration");
    std::fs::create_dir_all(&dir)?;
    generate(
        &dir,
        Options {
            noise: true,
            manifest_eps0_shift: 0.0,
        },
    )?;
    println!("wrote {}", dir.display());
    Ok(())
}
