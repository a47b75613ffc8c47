//! Seeded Monte Carlo of a scene's parameters, shared by the error-bar
//! tests (tests/uncertainty.rs, tests/study_bands.rs).
//!
//! Tolerance of the Monte Carlo: the sample standard deviation of `n`
//! Gaussian draws has a relative standard deviation of about
//! `1 / sqrt(2 n)`, so the propagated sigma must match the sample one
//! within `4 / sqrt(2 n)` (4 sd of the sampling error) plus 3 % for the
//! nonlinearity the first order leaves out.

#![allow(dead_code)]

use fpc::scene::{Scene, SceneFile, SceneSolution};

/// A seeded standard normal (Box-Muller).
pub fn normal(rng: &mut fastrand::Rng) -> f64 {
    let u1 = 1.0 - rng.f64(); // in (0, 1]
    let u2 = rng.f64();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// The lower Cholesky factor of a small positive definite matrix.
pub fn cholesky(c: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = c.len();
    let mut l = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..=i {
            let s: f64 = (0..j).map(|k| l[i][k] * l[j][k]).sum();
            if i == j {
                l[i][j] = (c[i][i] - s).sqrt();
            } else {
                l[i][j] = (c[i][j] - s) / l[j][j];
            }
        }
    }
    l
}

/// The scene `text` with its keys set to `values` (`key` as the
/// calibration names it) and no `[calibration]` table.
pub fn with_values(text: &str, keys: &[&str], values: &[f64]) -> Scene {
    let mut file = SceneFile::parse(text).unwrap();
    file.calibration = None;
    for (k, &v) in keys.iter().zip(values) {
        match *k {
            "actuator.pemc.eps0" => file.actuator.pemc.eps0 = Some(v),
            "actuator.pemc.p1" => file.actuator.pemc.p1 = Some(v),
            "actuator.cl.e" => file.actuator.cl.e = Some(v),
            "load.kappa" => file.load.kappa = Some(v),
            other => panic!("no setter for {other}"),
        }
    }
    file.resolve().unwrap()
}

pub fn sd(xs: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let m = xs.iter().sum::<f64>() / n;
    (xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// Draws `n` parameter sets from N(mean, cov), solves each scene and
/// returns the outputs `out` picks, one vector per output.
pub fn monte_carlo(
    text: &str,
    keys: &[&str],
    mean: &[f64],
    cov: &[Vec<f64>],
    n: usize,
    seed: u64,
    out: impl Fn(&SceneSolution) -> Vec<f64>,
) -> Vec<Vec<f64>> {
    let l = cholesky(cov);
    let mut rng = fastrand::Rng::with_seed(seed);
    let mut cols: Vec<Vec<f64>> = Vec::new();
    for _ in 0..n {
        let z: Vec<f64> = (0..keys.len()).map(|_| normal(&mut rng)).collect();
        let x: Vec<f64> = (0..keys.len())
            .map(|i| mean[i] + (0..=i).map(|k| l[i][k] * z[k]).sum::<f64>())
            .collect();
        let y = out(&with_values(text, keys, &x).solve().unwrap());
        if cols.is_empty() {
            cols = vec![Vec::with_capacity(n); y.len()];
        }
        for (c, v) in cols.iter_mut().zip(y) {
            c.push(v);
        }
    }
    cols
}

pub fn tolerance(n: usize) -> f64 {
    4.0 / (2.0 * n as f64).sqrt() + 0.03
}

pub fn agree(name: &str, propagated: f64, sample: f64, n: usize) {
    let rel = (propagated - sample).abs() / sample;
    println!("{name}: propagated {propagated:.6e}, Monte Carlo {sample:.6e} (n = {n}, relative {rel:.4})");
    assert!(
        rel <= tolerance(n),
        "{name}: propagated {propagated:.6e}, Monte Carlo {sample:.6e} (relative {rel:.3}, tolerance {:.3})",
        tolerance(n)
    );
}
