//! One calibration of the shipped synthetic set (examples/calibration/:
//! three specimens, markers, radii and forces, 142 residuals), fitting
//! eps0 per specimen and kappa (docs/calibration.md). Before the timing
//! it prints the iterations and solves of one fit, so that a change of
//! time can be told apart from a change of work.
//!
//! ```sh
//! cargo bench --bench calibrate
//! ```

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use fpc::calibrate::{calibrate, CalibrateOptions};
use fpc::measure::Manifest;

fn one_calibration(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/calibration/manifest.toml");
    let manifest = Manifest::load(&path).expect("the shipped manifest loads");
    let opts = CalibrateOptions::new(&["eps0", "kappa"]);
    let fit = calibrate(&manifest, &opts).expect("the shipped set calibrates");
    eprintln!(
        "  [calibrate] {} unknowns, {} residuals: {} iterations, {} evaluations, {} equilibrium solves, {} target solves, chi2 {:.4}",
        fit.parameters.len(),
        fit.points,
        fit.iterations,
        fit.evaluations,
        fit.solves,
        fit.target_solves,
        fit.chi_square
    );
    let mut g = c.benchmark_group("calibrate");
    g.sample_size(10);
    g.bench_function("shipped set, eps0 x 3 + kappa", |b| {
        b.iter(|| calibrate(black_box(&manifest), black_box(&opts)).unwrap())
    });
    g.finish();
}

criterion_group!(benches, one_calibration);
criterion_main!(benches);
