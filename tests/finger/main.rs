//! Validation of the CCM finger (docs/model.md section 4) against methods that do
//! not share the solver's code path: finite differences of the energy, an
//! independent Cholesky and eigen-solver, a gradient-only quasi-Newton
//! minimiser (argmin's L-BFGS),
//! physical and variational inequalities, and refinement in N.
//!
//! Randomness is fastrand seeded with fixed seeds, so every run sees the same numbers.
//!
//! One module per subject; the shared helpers are here.

use fpc::finger::{Solver, Strategy};
use fpc::model::ccm::Ccm;
use fpc::model::ModelCore;
use fpc::{
    Actuator, Coefficients, Finger, Load, ModelId, Partition, Solution, SolveError, SolveOptions,
    Termination,
};

mod convergence;
mod equilibrium;
mod input;
mod paths;
mod physics;

/// The tip load of the brief's scenes (N, finger frame).
const FX: f64 = 0.939782;
const FZ: f64 = 0.521707;

const EPS0S: [f64; 3] = [0.15, 0.25, 0.4];

// ----------------------------------------------------------------- helpers

/// Seeded uniform doubles (fastrand).
struct Lcg(fastrand::Rng);

impl Lcg {
    fn new(seed: u64) -> Lcg {
        Lcg(fastrand::Rng::with_seed(seed))
    }

    fn next(&mut self) -> f64 {
        self.0.f64()
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// One element's unknowns `[a1, a3, b1, c2]` (the paper's element).
type Coeffs = [f64; 4];

/// Natural scale of each unknown: `K = s * y` with `y = (a1, a3 L^2, b1, c2 L)`.
fn scales(l: f64) -> Coeffs {
    [1.0, 1.0 / (l * l), 1.0, 1.0 / l]
}

/// The scales of every element, from the finger's element lengths (the
/// finger's own `unknown_scales` is checked against these in test 1).
fn finger_scales(f: &Finger) -> Vec<Coeffs> {
    assert_eq!(f.model(), ModelId::Ccm);
    assert_eq!(f.unknowns_per_element(), 4);
    f.element_lengths().iter().map(|&l| scales(l)).collect()
}

fn to_scaled(s: &[Coeffs], k: &Coefficients) -> Vec<f64> {
    assert_eq!(k.per_element(), 4);
    k.iter()
        .zip(s)
        .flat_map(|(k, s)| (0..4).map(move |j| k[j] / s[j]))
        .collect()
}

fn to_raw(s: &[Coeffs], y: &[f64]) -> Coefficients {
    let values = s
        .iter()
        .enumerate()
        .flat_map(|(i, s)| {
            [
                y[4 * i] * s[0],
                y[4 * i + 1] * s[1],
                y[4 * i + 2] * s[2],
                y[4 * i + 3] * s[3],
            ]
        })
        .collect();
    Coefficients::new(4, values).expect("four unknowns per element")
}

fn flat_scales(s: &[Coeffs]) -> Vec<f64> {
    s.iter().flatten().copied().collect()
}

fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The largest entry of the potential's gradient at `k`, taken in raw
/// unknowns (no change of variables) and scaled as Newton's unknowns are.
fn scaled_residual(f: &Finger, load: &Load, k: &Coefficients) -> f64 {
    let (_, g) = f.gradient(load, k).unwrap();
    g.iter()
        .zip(f.unknown_scales())
        .map(|(g, s)| (g * s).abs())
        .fold(0.0, f64::max)
}

fn pressure(kpa: f64) -> Load {
    Load::unloaded().with_pressure_kpa(kpa)
}

/// The brief's five scenes plus a high-pressure loaded one.
fn scenes() -> Vec<(&'static str, Load)> {
    vec![
        ("unloaded", Load::unloaded()),
        ("100 kPa", pressure(100.0)),
        ("386 kPa", pressure(386.0)),
        ("tip load", Load::unloaded().with_tip_force(FX, FZ)),
        ("100 kPa + tip", pressure(100.0).with_tip_force(FX, FZ)),
        ("386 kPa + tip", pressure(386.0).with_tip_force(FX, FZ)),
    ]
}

/// Solves on a worker thread and fails the test if the solver does not
/// return within `secs` (a solver stuck in a loop must not hang CI; the
/// stuck thread is abandoned and ends with the test process).
fn solve_within(
    f: &Finger,
    load: Load,
    opts: SolveOptions,
    secs: u64,
) -> Result<Solution, SolveError> {
    let f = f.clone();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f.solve(&load, &opts));
    });
    rx.recv_timeout(std::time::Duration::from_secs(secs))
        .unwrap_or_else(|_| panic!("{load:?}: the solver did not return within {secs} s"))
}

fn solve(f: &Finger, load: &Load) -> Solution {
    f.solve(load, &SolveOptions::default())
        .unwrap_or_else(|e| panic!("{load:?}: {e}"))
}

/// Scaled Hessian `S H S` (column-major) from the raw one.
fn scaled_hessian(f: &Finger, load: &Load, k: &Coefficients) -> Vec<f64> {
    let s = flat_scales(&finger_scales(f));
    let n = s.len();
    let (_, _, mut h) = f.hessian(load, k).unwrap();
    for j in 0..n {
        for i in 0..n {
            h[i + n * j] *= s[i] * s[j];
        }
    }
    h
}

/// Plain column-major Cholesky `A = L L^T` (lower triangle); `None` when a
/// pivot is not positive. Written here so that it shares nothing with the
/// solver's factorisation.
fn cholesky(n: usize, a: &[f64]) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for j in 0..n {
        let mut d = a[j + n * j];
        for k in 0..j {
            d -= l[j + n * k] * l[j + n * k];
        }
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        let d = d.sqrt();
        l[j + n * j] = d;
        for i in j + 1..n {
            let mut v = a[i + n * j];
            for k in 0..j {
                v -= l[i + n * k] * l[j + n * k];
            }
            l[i + n * j] = v / d;
        }
    }
    Some(l)
}

/// Smallest eigenvalue of a symmetric matrix by nalgebra's eigen-solver
/// (the library uses faer's).
fn nalgebra_min_eig(n: usize, h: &[f64]) -> f64 {
    nalgebra::DMatrix::from_column_slice(n, n, h)
        .symmetric_eigen()
        .eigenvalues
        .min()
}

/// Position of the gas-volume family among the model's integral families.
fn gas_family() -> usize {
    Ccm::FAMILIES
        .iter()
        .position(|f| *f == "gas")
        .expect("the CCM has a gas family")
}

/// Total gas volume of the channel: the gas family of every element alone.
fn gas_volume(f: &Finger, k: &Coefficients) -> f64 {
    let gas = gas_family();
    (0..f.len())
        .map(|i| {
            f.element_hessian(i, Some(gas), &Load::unloaded(), k.element(i))
                .expect("element and family in range")
                .0
        })
        .sum()
}

/// Random coefficients in the brief's realistic ranges.
fn random_coeffs(rng: &mut Lcg, f: &Finger) -> Coefficients {
    let values = f
        .element_lengths()
        .iter()
        .flat_map(|&l| {
            [
                rng.range(-0.05, 0.05),
                rng.range(-0.5, 0.5) / (l * l),
                rng.range(-0.05, 0.05),
                rng.range(-0.5, 0.5) / l,
            ]
        })
        .collect();
    Coefficients::new(4, values).unwrap()
}
