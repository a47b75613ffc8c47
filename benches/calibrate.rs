//! One calibration of the shipped synthetic set (examples/calibration/:
//! three specimens, markers, radii and forces, 142 residuals), fitting
//! eps0 per specimen and kappa (docs/calibration.md); and one of issue 21's
//! size: three specimens with 8 markers at 6 pressures each and two force
//! series, 6 parameters (eps0 per specimen, kappa, emc.e1, p1), on data the
//! ordinary solve makes at run time, started off the truth. Before the timing
//! it prints the iterations and solves of one fit, so that a change of
//! time can be told apart from a change of work.
//!
//! ```sh
//! cargo bench --bench calibrate
//! ```

use std::fmt::Write as _;
use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use fpc::calibrate::{calibrate, CalibrateOptions};
use fpc::measure::Manifest;
use fpc::studies::{tip_force_for_displacement, Axis};
use fpc::{Actuator, Finger, Load, SolveOptions};

/// Writes issue 21's benchmark set: per specimen 8 markers (s = 13.75 to
/// 110 mm) at 0 to 100 kPa in steps of 20, noise-free from the ordinary
/// solve (sd 0.3 mm), and study 8's forces at 4 pressures for two of
/// them (sd 5 % + 0.005 N); the manifest starts eps0 0.02 off, e1 and
/// p1 10 % off. Returns it loaded, its directory removed.
fn issue_set() -> Manifest {
    let dir = tempfile::Builder::new()
        .prefix("fpc-bench-calibrate-")
        .tempdir()
        .expect("a temporary directory");
    let d = dir.path();
    let base = Actuator::default().params().clone();
    let e1 = match &base.emc {
        fpc::actuator::Material::Orthotropic(m) => m.e1,
        _ => unreachable!("the paper's EMC is orthotropic"),
    };
    let p1 = base.pemc.law.to_array()[0];
    let mut m = format!(
        "[shared.actuator.emc]\ne1 = {}\n[shared.actuator.pemc]\np1 = {}\n",
        1.1 * e1,
        1.1 * p1
    );
    let specimens = [(0.15, Some(Axis::Z)), (0.25, None), (0.4, Some(Axis::X))];
    for (i, (eps0, force)) in specimens.into_iter().enumerate() {
        let act = Actuator::default()
            .with_eps0(eps0)
            .expect("a valid prestrain");
        let part = fpc::Partition::equal(act.geometry().lx, 8).expect("8 elements");
        let f = Finger::new(&act, &part, true);
        write!(
            m,
            "\n[[specimen]]\nname = \"s{i}\"\n[specimen.own.actuator.pemc]\neps0 = {}\n",
            eps0 + 0.02
        )
        .unwrap();
        let mut csv = String::from("pressure_kpa,marker,s_mm,x_mm,z_mm,sd_mm\n");
        for p in [0.0, 20.0, 40.0, 60.0, 80.0, 100.0] {
            let sol = f
                .solve(
                    &Load::unloaded().with_pressure_kpa(p),
                    &SolveOptions::default(),
                )
                .expect("the true finger solves");
            // 8 shape samples per element of 13.75 mm: marker k at sample 8 (k + 1)
            let pts = f.shape(&sol.coefficients, 8).expect("its shape");
            for k in 0..8 {
                let q = pts[8 * (k + 1)];
                writeln!(
                    csv,
                    "{p},M{k},{},{},{},0.3",
                    13.75 * (k + 1) as f64,
                    q[0],
                    q[1]
                )
                .unwrap();
            }
        }
        std::fs::write(d.join(format!("s{i}_markers.csv")), csv).unwrap();
        write!(
            m,
            "[[specimen.test]]\nkind = \"markers\"\nfile = \"s{i}_markers.csv\"\n"
        )
        .unwrap();
        if let Some(axis) = force {
            let name = if axis == Axis::X { "X" } else { "Z" };
            let mut csv = String::from("pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats\n");
            for p in [0.0, 27.6, 55.2, 82.7] {
                let r = tip_force_for_displacement(&f, p, axis, 10.0).expect("study 8's solve");
                writeln!(
                    csv,
                    "{p},{name},10,{},{},5",
                    r.force,
                    0.05 * r.force.abs() + 0.005
                )
                .unwrap();
            }
            std::fs::write(d.join(format!("s{i}_force.csv")), csv).unwrap();
            write!(
                m,
                "[[specimen.test]]\nkind = \"force\"\nfile = \"s{i}_force.csv\"\n"
            )
            .unwrap();
        }
    }
    let path = d.join("manifest.toml");
    std::fs::write(&path, m).unwrap();
    Manifest::load(&path).expect("the benchmark set loads")
}

/// The work of one fit, so a change of time can be told from one of work.
fn report(fit: &fpc::calibrate::Calibration) {
    eprintln!(
        "  [calibrate] {} unknowns, {} residuals: {} iterations, {} evaluations, {} equilibrium solves, {} target solves, chi2 {:.4e}",
        fit.parameters.len(),
        fit.points,
        fit.iterations,
        fit.evaluations,
        fit.solves,
        fit.target_solves,
        fit.chi_square
    );
}

fn one_calibration(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/calibration/manifest.toml");
    let manifest = Manifest::load(&path).expect("the shipped manifest loads");
    let opts = CalibrateOptions::new(&["eps0", "kappa"]);
    let fit = calibrate(&manifest, &opts).expect("the shipped set calibrates");
    report(&fit);
    let mut g = c.benchmark_group("calibrate");
    g.sample_size(10);
    g.bench_function("shipped set, eps0 x 3 + kappa", |b| {
        b.iter(|| calibrate(black_box(&manifest), black_box(&opts)).unwrap())
    });
    let manifest = issue_set();
    let opts = CalibrateOptions::new(&["eps0", "kappa", "emc.e1", "p1"]);
    let fit = calibrate(&manifest, &opts).expect("the benchmark set calibrates");
    report(&fit);
    g.bench_function(
        "3 specimens x 6 pressures x 8 markers + 2 force series, 6 parameters",
        |b| b.iter(|| calibrate(black_box(&manifest), black_box(&opts)).unwrap()),
    );
    g.finish();
}

criterion_group!(benches, one_calibration);
criterion_main!(benches);
