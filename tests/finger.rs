//! Validation of the CCM finger (docs/model.md section 4) against methods that do
//! not share the solver's code path: finite differences of the energy, an
//! independent Cholesky and eigen-solver, a gradient-only BFGS minimiser,
//! physical and variational inequalities, and refinement in N.
//!
//! Randomness is fastrand seeded with fixed seeds, so every run sees the same numbers.

use fpc::model::ccm::Ccm;
use fpc::{
    Actuator, Coefficients, ElementModel, Finger, Load, ModelId, Partition, Solution, SolveError,
    SolveOptions, Solver, Strategy, Termination,
};
use fpc_newton::{Bfgs, BfgsOptions, Energy, Gradient};

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

// -------------------------------------------------------- 1. residual, PD

#[test]
fn equilibria_have_tiny_residuals_and_positive_definite_hessians() {
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let s = flat_scales(&finger_scales(&f));
        let n = s.len();
        // the solver's scaled units are the paper's natural scales
        let own = f.unknown_scales();
        assert_eq!(own.len(), n);
        for (i, (a, b)) in own.iter().zip(&s).enumerate() {
            assert!(
                (a - b).abs() <= 1e-15 * b.abs(),
                "eps0 {eps0}: unknown_scales[{i}] = {a:e}, natural scale {b:e}"
            );
        }
        let stiff = f.stiffness_scale();
        for (name, load) in scenes() {
            let sol = solve(&f, &load);
            let what = format!("eps0 {eps0}, {name}");
            assert_eq!(sol.report.reason, Termination::Converged, "{what}");
            assert!(
                sol.report.residual_norm <= 1e-10,
                "{what}: reported residual {:e}",
                sol.report.residual_norm
            );
            assert_eq!(sol.report.coupled, load.has_tip_load(), "{what}");

            // the raw gradient, recomputed: scaled by s it is the residual
            let (v, g) = f.gradient(&load, &sol.coefficients).unwrap();
            let gs: Vec<f64> = g.iter().zip(&s).map(|(g, s)| g * s).collect();
            let r = norm_inf(&gs) / stiff;
            assert!(r <= 1e-10, "{what}: recomputed scaled residual {r:e}");
            // the value returned with the gradient is the reported energy
            assert!(
                (v - sol.energy).abs() <= 1e-12 * (1.0 + sol.energy.abs()),
                "{what}: energy {v} vs {}",
                sol.energy
            );

            // positive definiteness by an independent Cholesky of the raw Hessian
            let (_, _, h) = f.hessian(&load, &sol.coefficients).unwrap();
            assert!(cholesky(n, &h).is_some(), "{what}: raw Hessian not PD");
            // and the reported smallest eigenvalue by another eigen-solver
            let hs = scaled_hessian(&f, &load, &sol.coefficients);
            let sym: Vec<f64> = (0..n * n)
                .map(|idx| 0.5 * (hs[idx] + hs[(idx % n) * n + idx / n]))
                .collect();
            let lam = nalgebra_min_eig(n, &sym) / stiff;
            let reported = sol
                .negative_eigenvalues
                .expect("stability is on by default");
            assert_eq!(reported, 0, "{what}");
            assert!(lam > 0.0, "{what}: min eig {lam:e} (nalgebra)");
            assert_eq!(sol.stable, Some(true));
        }
    }
}

// ------------------------------------------------- 2. assembled derivatives

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

#[test]
fn assembled_gradient_and_hessian_match_finite_differences() {
    let mut rng = Lcg::new(0x5eed_f1a9);
    // Steps in scaled units, i.e. times each unknown's natural scale (1 for
    // a1, b1; 1/L^2 for a3; 1/L for c2). The Hessian's differences of the
    // gradient are round-off limited at 1e-6 (worst block error 4e-7), so
    // they use 1e-5 (worst 1e-7, truncation still negligible).
    let h = 1e-6;
    let hh = 1e-5;
    let mut worst_g: f64 = 0.0;
    let mut worst_h: f64 = 0.0;
    for n_el in [1usize, 3, 6] {
        for trial in 0..3 {
            let eps0 = EPS0S[trial % 3];
            let f = Finger::paper(eps0, n_el).unwrap();
            let sc = finger_scales(&f);
            let s = flat_scales(&sc);
            let n = 4 * n_el;
            let k = random_coeffs(&mut rng, &f);
            let y = to_scaled(&sc, &k);
            let loaded = Load::unloaded()
                .with_pressure_kpa(rng.range(0.0, 400.0))
                .with_tip_force(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            let unloaded = Load {
                fx: 0.0,
                fz: 0.0,
                ..loaded
            };
            for load in [loaded, unloaded] {
                let what = format!("N {n_el}, trial {trial}, {load:?}");
                let energy = |y: &[f64]| f.energy(&load, &to_raw(&sc, y)).unwrap();
                let grad = |y: &[f64]| -> Vec<f64> {
                    let (_, g) = f.gradient(&load, &to_raw(&sc, y)).unwrap();
                    g.iter().zip(&s).map(|(g, s)| g * s).collect()
                };

                // gradient against central differences of the energy
                let gy = grad(&y);
                let gscale = norm_inf(&gy);
                for j in 0..n {
                    let mut yp = y.clone();
                    let mut ym = y.clone();
                    yp[j] += h;
                    ym[j] -= h;
                    let fd = (energy(&yp) - energy(&ym)) / (2.0 * h);
                    let err = (fd - gy[j]).abs() / gscale;
                    worst_g = worst_g.max(err);
                    assert!(
                        err <= 1e-6,
                        "{what}: dPi/dy[{j}] = {} vs FD {fd} (rel {err:e})",
                        gy[j]
                    );
                }

                // Hessian against central differences of the gradient
                let (_, _, hr) = f.hessian(&load, &k).unwrap();
                for i in 0..n {
                    for j in 0..n {
                        assert_eq!(
                            hr[i + n * j].to_bits(),
                            hr[j + n * i].to_bits(),
                            "{what}: Hessian not exactly symmetric at ({i}, {j})"
                        );
                    }
                }
                let hy: Vec<f64> = (0..n * n)
                    .map(|idx| hr[idx] * s[idx % n] * s[idx / n])
                    .collect();
                let hscale = norm_inf(&hy);
                let mut fdh = vec![0.0; n * n];
                for j in 0..n {
                    let mut yp = y.clone();
                    let mut ym = y.clone();
                    yp[j] += hh;
                    ym[j] -= hh;
                    let (gp, gm) = (grad(&yp), grad(&ym));
                    for i in 0..n {
                        fdh[i + n * j] = (gp[i] - gm[i]) / (2.0 * hh);
                    }
                }
                for bi in 0..n_el {
                    for bj in 0..n_el {
                        let idx = |a: usize, b: usize| (4 * bi + a) + n * (4 * bj + b);
                        let mut bscale: f64 = 0.0;
                        let mut err: f64 = 0.0;
                        for a in 0..4 {
                            for b in 0..4 {
                                bscale = bscale.max(hy[idx(a, b)].abs());
                                err = err.max((hy[idx(a, b)] - fdh[idx(a, b)]).abs());
                            }
                        }
                        if bi != bj {
                            if load.has_tip_load() {
                                // the chain couples every pair of elements
                                assert!(
                                    bscale > 1e-6 * hscale,
                                    "{what}: block ({bi}, {bj}) vanishes ({bscale:e})"
                                );
                            } else {
                                assert_eq!(bscale, 0.0, "{what}: block ({bi}, {bj})");
                                assert_eq!(err, 0.0, "{what}: FD block ({bi}, {bj})");
                                continue;
                            }
                        }
                        let rel = err / bscale;
                        worst_h = worst_h.max(rel);
                        assert!(
                            rel <= 1e-6,
                            "{what}: block ({bi}, {bj}) differs from FD by {err:e} (scale {bscale:e})"
                        );
                    }
                }
            }
        }
    }
    eprintln!("worst relative FD error: gradient {worst_g:.2e}, Hessian block {worst_h:.2e}");
}

// ------------------------------------------------ 3. independent minimiser

/// The finger's energy in scaled unknowns, through the public raw-coefficient
/// API only (no Hessian: BFGS never sees one).
struct ScaledFinger<'a> {
    finger: &'a Finger,
    load: Load,
    s: Vec<Coeffs>,
}

impl Energy for ScaledFinger<'_> {
    fn dim(&self) -> usize {
        4 * self.finger.len()
    }
    fn energy(&mut self, y: &[f64]) -> f64 {
        self.finger.energy(&self.load, &to_raw(&self.s, y)).unwrap()
    }
}

impl Gradient for ScaledFinger<'_> {
    fn gradient(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        let (v, gk) = self
            .finger
            .gradient(&self.load, &to_raw(&self.s, y))
            .unwrap();
        for (i, (g, gk)) in g.iter_mut().zip(gk).enumerate() {
            *g = gk * self.s[i / 4][i % 4];
        }
        v
    }
}

#[test]
fn bfgs_from_the_straight_finger_reaches_newtons_equilibrium() {
    for (n_el, load) in [
        (8, Load::unloaded()),
        (8, Load::unloaded().with_tip_force(FX, FZ)),
        (4, pressure(100.0).with_tip_force(FX, FZ)),
    ] {
        let f = Finger::paper(0.25, n_el).unwrap();
        let newton = solve(&f, &load);
        let mut p = ScaledFinger {
            finger: &f,
            load,
            s: finger_scales(&f),
        };
        let n = 4 * n_el;
        let opts = BfgsOptions {
            gtol: 1e-11 * f.stiffness_scale(),
            max_iter: 5000,
            ..BfgsOptions::default()
        };
        let mut y = vec![0.0; n];
        let rep = Bfgs::new(n, opts).minimize(&mut p, &mut y);
        let what = format!("N {n_el}, {load:?}");
        assert_eq!(rep.reason, Termination::Converged, "{what}: {rep:?}");
        let k = to_raw(&p.s, &y);
        let (tip, angle) = f.tip(&k).unwrap();
        let dtip = dist(tip, newton.tip);
        let yn = to_scaled(&p.s, &newton.coefficients);
        let dy = norm_inf(&y.iter().zip(&yn).map(|(a, b)| a - b).collect::<Vec<f64>>());
        eprintln!(
            "{what}: BFGS {} iterations, |tip - newton| = {dtip:.2e} mm, max |dy| = {dy:.2e}",
            rep.iterations
        );
        assert!(
            dtip <= 1e-6,
            "{what}: tip {tip:?} vs Newton {:?}",
            newton.tip
        );
        assert!(dy <= 1e-7, "{what}: scaled coefficients differ by {dy:e}");
        assert!((angle - newton.end_angle).abs() <= 1e-8, "{what}");
        assert!(
            (rep.energy - newton.energy).abs() <= 1e-12 * newton.energy.abs().max(1.0),
            "{what}: energy {} vs {}",
            rep.energy,
            newton.energy
        );
    }
}

// ---------------------------------------------------------------- 4. physics

#[test]
fn unloaded_finger_curls_towards_minus_z_tighter_with_prestrain() {
    let mut radii = Vec::new();
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let sol = solve(&f, &Load::unloaded());
        assert!(sol.tip[1] < 0.0, "eps0 {eps0}: tip {:?}", sol.tip);
        assert!(sol.end_angle < 0.0, "eps0 {eps0}: {}", sol.end_angle);
        // every element bends the same way
        assert!(sol.coefficients.iter().all(|k| k[3] < 0.0), "eps0 {eps0}");
        let r = sol.radius.expect("a curled finger has a circle fit");
        // independent estimate: deformed arc length over total turning
        let arc: f64 = sol.points.windows(2).map(|w| dist(w[0], w[1])).sum();
        let r_mean = arc / sol.end_angle.abs();
        eprintln!(
            "eps0 {eps0}: tip {:?}, end angle {:.4}, circle fit {r:.3} mm, arc/turning {r_mean:.3} mm",
            sol.tip, sol.end_angle
        );
        assert!(
            (r - r_mean).abs() <= 0.05 * r,
            "eps0 {eps0}: circle fit {r} vs arc/turning {r_mean}"
        );
        radii.push((r, sol.end_angle));
    }
    for w in radii.windows(2) {
        assert!(w[0].0 > w[1].0, "radius must shrink with eps0: {radii:?}");
        assert!(w[0].1 > w[1].1, "turning must grow with eps0: {radii:?}");
    }
}

/// Turning angle (rad) where the tip height of a circular arc of fixed length
/// is extremal: theta sin(theta) = 1 - cos(theta), about 2.331. Tip Z falls
/// while a finger curled past it flattens, and rises below it.
const ARC_Z_EXTREMUM: f64 = 2.3311;

#[test]
fn pressure_flattens_the_finger_monotonically() {
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let sweep: Vec<(f64, Solution, f64)> = (0..=7)
            .map(|i| {
                let kpa = 50.0 * i as f64;
                let sol = solve(&f, &pressure(kpa));
                let v = gas_volume(&f, &sol.coefficients);
                (kpa, sol, v)
            })
            .collect();
        eprintln!("eps0 {eps0}: P (kPa), tip, end angle, radius, gas volume");
        for (kpa, s, v) in &sweep {
            eprintln!(
                "  {kpa:5.0}  ({:8.3}, {:8.3})  {:8.4}  {:>10.3}  {v:.3}",
                s.tip[0],
                s.tip[1],
                s.end_angle,
                s.radius.unwrap_or(f64::INFINITY)
            );
        }
        for w in sweep.windows(2) {
            let ((p0, a, v0), (p1, b, v1)) = (&w[0], &w[1]);
            let what = format!("eps0 {eps0}, {p0} -> {p1} kPa");
            // variational facts: dPi*/dP = -kappa V < 0 and V(P) non-decreasing
            assert!(v1 > v0, "{what}: gas volume {v0} -> {v1}");
            assert!(b.energy < a.energy, "{what}: energy");
            // the finger unbends
            assert!(b.end_angle > a.end_angle, "{what}: end angle");
            if b.end_angle < 0.0 {
                let (ra, rb) = (a.radius.unwrap(), b.radius.unwrap_or(f64::INFINITY));
                assert!(rb > ra, "{what}: radius {ra} -> {rb} while still curled");
            }
            // tip height: rises unless the finger is curled past the arc extremum
            let (ta, tb) = (a.end_angle.abs(), b.end_angle.abs());
            if ta < ARC_Z_EXTREMUM - 0.1 && tb < ARC_Z_EXTREMUM - 0.1 {
                assert!(b.tip[1] > a.tip[1], "{what}: tip Z must rise");
            }
            if ta > ARC_Z_EXTREMUM + 0.1 && tb > ARC_Z_EXTREMUM + 0.1 {
                assert!(b.tip[1] < a.tip[1], "{what}: tip Z must fall (curled past)");
            }
        }
    }
}

#[test]
fn tip_force_along_plus_z_raises_the_tip() {
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let free = solve(&f, &Load::unloaded());
        let mut prev = free.clone();
        for fz in [0.5, 1.0, 1.5, 2.0] {
            let load = Load::unloaded().with_tip_force(0.0, fz);
            let sol = solve(&f, &load);
            let what = format!("eps0 {eps0}, Fz {fz}");
            assert!(sol.tip[1] > prev.tip[1], "{what}: tip Z not monotonic");
            // work inequality: K_F minimises Pi_F and K_0 minimises Pi_0, so
            // 0 <= Pi_0(K_F) - Pi_0(K_0) <= F . (tip_F - tip_0)
            let stored = f.energy(&Load::unloaded(), &sol.coefficients).unwrap() - free.energy;
            let work = fz * (sol.tip[1] - free.tip[1]);
            assert!(stored >= 0.0, "{what}: {stored}");
            assert!(stored <= work, "{what}: stored {stored} > work {work}");
            // where the tip is the outermost point (curl under 90 degrees) the
            // moment of a +Z tip force opens every section: the end angle rises
            let tip_outermost = prev.points.iter().all(|p| p[0] <= prev.tip[0] + 1e-9);
            if tip_outermost {
                assert!(sol.end_angle > prev.end_angle, "{what}: end angle");
            }
            eprintln!(
                "{what}: tip ({:.3}, {:.3}), end angle {:.4}{}",
                sol.tip[0],
                sol.tip[1],
                sol.end_angle,
                if tip_outermost {
                    ""
                } else {
                    " (curled past 90 deg)"
                }
            );
            prev = sol;
        }
    }
    // the general tip load of the brief obeys the same inequality
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let free = solve(&f, &Load::unloaded());
        let sol = solve(&f, &Load::unloaded().with_tip_force(FX, FZ));
        let stored = f.energy(&Load::unloaded(), &sol.coefficients).unwrap() - free.energy;
        let work = FX * (sol.tip[0] - free.tip[0]) + FZ * (sol.tip[1] - free.tip[1]);
        assert!(
            0.0 <= stored && stored <= work,
            "eps0 {eps0}: {stored} {work}"
        );
    }
}

#[test]
fn equilibrium_energy_is_below_perturbed_states() {
    let mut rng = Lcg::new(0xbeef_0042);
    let f = Finger::paper(0.25, 8).unwrap();
    let sc = finger_scales(&f);
    let n = 4 * f.len();
    for (name, load) in scenes() {
        let sol = solve(&f, &load);
        assert_eq!(sol.negative_eigenvalues, Some(0), "{name}");
        let y0 = to_scaled(&sc, &sol.coefficients);
        let hs = scaled_hessian(&f, &load, &sol.coefficients);
        for _ in 0..20 {
            let d: Vec<f64> = (0..n).map(|_| rng.range(-1e-3, 1e-3)).collect();
            let y: Vec<f64> = y0.iter().zip(&d).map(|(a, b)| a + b).collect();
            let de = f.energy(&load, &to_raw(&sc, &y)).unwrap() - sol.energy;
            assert!(de > 0.0, "{name}: perturbation lowers the energy by {de:e}");
            // and the rise is the quadratic form of the Hessian (third order ~ |d|)
            let q: f64 = 0.5
                * (0..n)
                    .map(|j| (0..n).map(|i| d[i] * hs[i + n * j]).sum::<f64>() * d[j])
                    .sum::<f64>();
            assert!(
                (de - q).abs() <= 0.02 * q,
                "{name}: energy rise {de:e} vs 1/2 d^T H d = {q:e}"
            );
        }
    }
}

// ------------------------------------------------------- 5. convergence in N

/// Tip positions for the partitions, the successive differences and the
/// observed orders `log2(d_k / d_{k+1})`; prints the table.
fn refinement(title: &str, fingers: &[Finger], load: &Load) -> (Vec<f64>, Vec<f64>) {
    let opts = SolveOptions::default().tip_only();
    let sols: Vec<Solution> = fingers
        .iter()
        .map(|f| {
            solve_within(f, *load, opts, 10)
                .unwrap_or_else(|e| panic!("{title}, N {}: {e}", f.len()))
        })
        .collect();
    let diffs: Vec<f64> = sols.windows(2).map(|w| dist(w[0].tip, w[1].tip)).collect();
    let orders: Vec<f64> = diffs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    eprintln!("{title}");
    eprintln!("     N        tip X        tip Z    end angle   |t_N - t_N/2|   order");
    for (i, (f, s)) in fingers.iter().zip(&sols).enumerate() {
        let d = if i > 0 {
            format!("{:.4e}", diffs[i - 1])
        } else {
            String::new()
        };
        let p = if i > 1 {
            format!("{:.3}", orders[i - 2])
        } else {
            String::new()
        };
        eprintln!(
            "  {:4}  {:11.6}  {:11.6}  {:11.8}  {d:>14}  {p:>6}",
            f.len(),
            s.tip[0],
            s.tip[1],
            s.end_angle
        );
    }
    (diffs, orders)
}

#[test]
fn tip_converges_at_second_order_where_elements_resolve_the_material() {
    // Without ribs and with element ends on the channel's end (x = 105 mm),
    // every element is homogeneous along x: the only error is the element's
    // polynomial kinematics, and the order is 2. Partition: 4m elements over
    // the channel and m over the 5 mm solid wall.
    let act = Actuator::paper(0.25).unwrap();
    let fingers: Vec<Finger> = [1usize, 2, 4, 8]
        .iter()
        .map(|&m| {
            let mut lengths = vec![105.0 / (4 * m) as f64; 4 * m];
            lengths.extend(vec![5.0 / m as f64; m]);
            Finger::new(&act, &Partition::custom(lengths, 110.0).unwrap(), false)
        })
        .collect();
    for (name, load) in [
        ("unloaded", Load::unloaded()),
        ("tip load", Load::unloaded().with_tip_force(FX, FZ)),
        ("100 kPa", pressure(100.0)),
    ] {
        let title = format!("eps0 0.25, no ribs, channel-aligned elements, {name}");
        let (diffs, orders) = refinement(&title, &fingers, &load);
        assert!(diffs.windows(2).all(|w| w[1] < w[0]), "{title}: {diffs:?}");
        for p in &orders {
            assert!((1.5..=3.0).contains(p), "{title}: observed order {p}");
        }
    }
}

#[test]
fn tip_converges_in_n_for_the_default_finger() {
    // The default finger (ribs, N equal elements): N = 4, 8, 16, 32.
    // Unloaded, the order is near 2 over this range (1.68, 2.24), but that
    // is pre-asymptotic: refined further (N = 64, 128) the differences stall
    // (1.5e-2, 1.7e-2) because of the cut ribs explained below.
    let fingers: Vec<Finger> = [4usize, 8, 16, 32]
        .iter()
        .map(|&n| Finger::paper(0.25, n).unwrap())
        .collect();
    let (diffs, orders) = refinement(
        "eps0 0.25, default finger (ribs, equal elements), unloaded",
        &fingers,
        &Load::unloaded(),
    );
    assert!(diffs.windows(2).all(|w| w[1] < w[0]), "{diffs:?}");
    for p in &orders {
        assert!((1.5..=3.0).contains(p), "unloaded: observed order {p}");
    }
    // Loaded, the rib edges (every 8 mm) and the channel's end fall inside
    // elements. An element has one curvature, the stiffness-weighted mean of
    // its parts rather than their length-weighted mean, which costs O(L) in
    // turning per cut element, and the number of cut rib edges does not
    // grow with N: the observed order drops towards 1 (tip load 1.15, 1.42;
    // 100 kPa 1.59, 1.27) and varies with where the cuts fall (see the
    // channel-aligned study for the element's own order 2). Asserted: at
    // least first-order shrinkage.
    for (name, load) in [
        ("tip load", Load::unloaded().with_tip_force(FX, FZ)),
        ("100 kPa", pressure(100.0)),
    ] {
        let title = format!("eps0 0.25, default finger (ribs, equal elements), {name}");
        let (diffs, orders) = refinement(&title, &fingers, &load);
        assert!(diffs.windows(2).all(|w| w[1] < w[0]), "{title}: {diffs:?}");
        for p in &orders {
            assert!(*p >= 1.0, "{title}: observed order {p}");
        }
    }
}

// ------------------------------------------------- 6. decoupled vs coupled

#[test]
fn decoupled_and_coupled_paths_agree_without_tip_load() {
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let sc = finger_scales(&f);
        let zero = f.straight();
        // Both paths stop once the residual is below rtol (relative), which
        // pins the scaled coefficients only to about rtol / min_hessian_eig
        // (2.4e-9 and 0.67 um at the tip for eps0 0.4, 386 kPa at the
        // default 1e-11, where the decoupled residual is 9.7e-12). Agreement to
        // 1e-9 therefore needs a tighter rtol; 1e-14 is still far above the
        // round-off floor of the residual (~1e-17).
        let tight = SolveOptions {
            rtol: 1e-14,
            ..SolveOptions::default()
        };
        for load in [Load::unloaded(), pressure(100.0), pressure(386.0)] {
            let auto = f.solve_from(&load, &zero, &tight).unwrap();
            let coupled = f
                .solve_from(
                    &load,
                    &zero,
                    &SolveOptions {
                        strategy: Strategy::Coupled,
                        ..tight
                    },
                )
                .unwrap();
            let what = format!("eps0 {eps0}, {load:?}");
            assert!(!auto.report.coupled, "{what}");
            assert!(coupled.report.coupled, "{what}");
            let ya = to_scaled(&sc, &auto.coefficients);
            let yc = to_scaled(&sc, &coupled.coefficients);
            let dy = ya
                .iter()
                .zip(&yc)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(dy <= 1e-9, "{what}: scaled coefficients differ by {dy:e}");
            let dt = dist(auto.tip, coupled.tip);
            assert!(dt <= 1e-9, "{what}: tips differ by {dt:e} mm");
            assert!((auto.end_angle - coupled.end_angle).abs() <= 1e-9, "{what}");
            let de = (auto.energy - coupled.energy).abs();
            assert!(de <= 1e-12 * auto.energy.abs().max(1.0), "{what}: {de:e}");
            assert_eq!(
                auto.negative_eigenvalues, coupled.negative_eigenvalues,
                "{what}: inertia"
            );
        }
    }
}

// ---------------------------------------------------------- 7. equal elements

/// Element `i`'s potential at `load`, and every integral family alone,
/// each with gradient and Hessian, at the element unknowns `k`.
fn element_outputs(f: &Finger, i: usize, load: &Load, k: &[f64]) -> Vec<Vec<f64>> {
    let families = (0..Ccm::FAMILIES.len()).map(Some);
    std::iter::once(None)
        .chain(families)
        .map(|fam| {
            let (v, g, h) = f
                .element_hessian(i, fam, load, k)
                .expect("element and family in range");
            let mut out = vec![v];
            out.extend(g);
            out.extend(h);
            out
        })
        .collect()
}

#[test]
fn equal_elements_without_ribs_have_equal_solutions() {
    let act = Actuator::paper(0.25).unwrap();
    let mut rng = Lcg::new(0x0e9a_1e1e);
    // N = 8: the last element holds the channel's end; N = 22: elements of
    // 5 mm, the last one is the solid wall past the channel.
    for n_el in [8usize, 22] {
        let f = Finger::new(&act, &Partition::equal(110.0, n_el).unwrap(), false);
        let lengths = f.element_lengths();
        // Equal elements have the same energy function: every family's
        // value, gradient and Hessian agree bit for bit at random states
        // (the blocks themselves are compared in src/blocks.rs's tests).
        let load = pressure(100.0);
        let states = random_coeffs(&mut rng, &f);
        for probe in states.iter().chain(std::iter::once(&[0.0; 4][..])) {
            let first = element_outputs(&f, 0, &load, probe);
            for i in 1..n_el - 1 {
                assert_eq!(lengths[i], lengths[0], "N {n_el}: length of element {i}");
                assert_eq!(
                    element_outputs(&f, i, &load, probe),
                    first,
                    "N {n_el}: element {i} differs from element 0 at {probe:?}"
                );
            }
            assert_ne!(
                element_outputs(&f, n_el - 1, &load, probe),
                first,
                "N {n_el}: the last element is special"
            );
        }
        for load in [Load::unloaded(), pressure(100.0)] {
            // the coupled path solves every element itself (no sharing)
            let coupled = f
                .solve(
                    &load,
                    &SolveOptions {
                        strategy: Strategy::Coupled,
                        ..SolveOptions::default()
                    },
                )
                .unwrap();
            let auto = solve(&f, &load);
            let sc = scales(lengths[0]);
            let k0 = coupled.coefficients.element(0);
            for i in 1..n_el - 1 {
                let ki = coupled.coefficients.element(i);
                for j in 0..4 {
                    let d = (ki[j] - k0[j]).abs() / sc[j];
                    assert!(d <= 1e-12, "N {n_el}, element {i}, unknown {j}: {d:e}");
                }
                assert_eq!(auto.coefficients.element(i), auto.coefficients.element(0));
            }
            let kl = coupled.coefficients.element(n_el - 1);
            assert!(
                (kl[3] - k0[3]).abs() / sc[3] > 1e-6,
                "N {n_el}: the last element should bend differently"
            );
        }
    }
}

// --------------------------------------------------------------- 8. bad input

fn input_field(r: Result<Solution, SolveError>) -> String {
    match r {
        Err(SolveError::Input(e)) => {
            let msg = e.to_string();
            assert!(msg.starts_with(e.field()), "{msg}");
            e.field().to_string()
        }
        Err(e) => panic!("expected an input error, got {e}"),
        Ok(s) => panic!("accepted bad input: tip {:?}", s.tip),
    }
}

#[test]
fn bad_input_is_rejected_with_the_field_named() {
    let f = Finger::paper(0.25, 8).unwrap();
    let opts = SolveOptions::default();
    let coupled = SolveOptions {
        strategy: Strategy::Coupled,
        ..opts
    };
    let good = f.straight();
    assert_eq!(good, Coefficients::zeros(f.len(), 4));
    let bad_loads = [
        (
            Load {
                pressure: f64::NAN,
                ..Load::default()
            },
            "load.pressure",
        ),
        (
            Load {
                pressure: f64::INFINITY,
                ..Load::default()
            },
            "load.pressure",
        ),
        (
            Load {
                kappa: 0.0,
                ..Load::default()
            },
            "load.kappa",
        ),
        (
            Load {
                kappa: -2.5,
                ..Load::default()
            },
            "load.kappa",
        ),
        (
            Load {
                kappa: f64::NAN,
                ..Load::default()
            },
            "load.kappa",
        ),
        (Load::unloaded().with_tip_force(f64::NAN, 0.0), "load.fx"),
        (
            Load::unloaded().with_tip_force(0.0, f64::NEG_INFINITY),
            "load.fz",
        ),
    ];
    for (load, field) in bad_loads {
        assert_eq!(input_field(f.solve(&load, &opts)), field);
        assert_eq!(input_field(f.solve(&load, &coupled)), field);
        assert_eq!(input_field(f.solve_from(&load, &good, &opts)), field);
        assert_eq!(
            input_field(Solver::new(&f).solve(&load, Some(&good), &coupled)),
            field
        );
    }
    let tip = Load::unloaded().with_tip_force(FX, FZ);
    for len in [0, 1, f.len() - 1, f.len() + 1] {
        let guess = Coefficients::zeros(len, 4);
        for load in [Load::unloaded(), tip] {
            assert_eq!(input_field(f.solve_from(&load, &guess, &opts)), "guess");
            assert_eq!(input_field(f.solve_from(&load, &guess, &coupled)), "guess");
        }
    }
    // the right number of values, split into elements of the wrong size
    let wrong_split = Coefficients::new(2, vec![0.0; 4 * f.len()]).unwrap();
    for load in [Load::unloaded(), tip] {
        assert_eq!(
            input_field(f.solve_from(&load, &wrong_split, &opts)),
            "guess"
        );
    }
    let mut nan_guess = good.clone();
    nan_guess.as_mut_slice()[4 * 3 + 1] = f64::NAN;
    assert_eq!(input_field(f.solve_from(&tip, &nan_guess, &opts)), "guess");
    let mut bad = opts;
    bad.rtol = 0.0;
    assert_eq!(input_field(f.solve(&Load::unloaded(), &bad)), "solve.rtol");
    bad = opts;
    bad.max_iter = 0;
    assert_eq!(
        input_field(f.solve(&Load::unloaded(), &bad)),
        "solve.max_iter"
    );
}

// ------------------------------------------------------ robustness (coarse N)

/// Coarse fingers (long elements) are where Newton's globalisation is
/// tested: from the straight finger or the unloaded equilibrium the first
/// Newton step can be long, and the prestressed law's quintic
/// (`-0.698/5 s^5`) makes the energy unbounded below at large strains, so
/// an Armijo step may land there (energy -3e7 N mm instead of +139 for the
/// first scene) and the iterates run away. While this test was written
/// these scenes looped forever in Newton's line search (a NaN step
/// fraction once `g.p` overflowed to -inf), and with that loop fixed the
/// pressure-only ones still failed (`LineSearchFailed`, relative residual
/// ~1e270) until Newton steps were capped (`SolveOptions::max_step`). Each
/// solve must return promptly with an equilibrium; for the pressure scenes
/// a warm-started pressure ramp confirms it is the right one.
#[test]
fn coarse_fingers_solve_promptly() {
    let scenes = [
        (0.25, 4, Load::unloaded().with_tip_force(FX, FZ)),
        (0.15, 3, Load::unloaded().with_tip_force(0.0, 2.0)),
        (0.15, 6, Load::unloaded().with_tip_force(0.0, 2.0)),
        (0.15, 4, pressure(386.0).with_tip_force(FX, FZ)),
        (0.15, 4, pressure(386.0)),
        (0.15, 5, pressure(400.0)),
    ];
    // all scenes at once against one deadline: a stuck solve costs 10 s in all
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
    let pending: Vec<_> = scenes
        .iter()
        .map(|&(eps0, n_el, load)| {
            let f = Finger::paper(eps0, n_el).unwrap();
            let (tx, rx) = std::sync::mpsc::channel();
            let fc = f.clone();
            std::thread::spawn(move || {
                let direct = fc.solve(&load, &SolveOptions::default());
                // warm-started pressure ramp (20 kPa steps), tip load off
                let mut ramp: Result<Solution, SolveError> =
                    fc.solve(&Load::unloaded(), &SolveOptions::default());
                let steps = (load.pressure / 0.02).ceil() as usize;
                for i in 1..=steps {
                    let Ok(prev) = &ramp else { break };
                    let p = load.pressure * i as f64 / steps as f64;
                    let l = Load {
                        pressure: p,
                        ..Load::default()
                    };
                    ramp = fc.solve_from(&l, &prev.coefficients, &SolveOptions::default());
                }
                let _ = tx.send((direct, ramp));
            });
            (format!("eps0 {eps0}, N {n_el}, {load:?}"), f, load, rx)
        })
        .collect();
    let mut failures = Vec::new();
    for (what, f, load, rx) in pending {
        let left = deadline.saturating_duration_since(std::time::Instant::now());
        let (direct, ramp) = match rx.recv_timeout(left) {
            Ok(r) => r,
            Err(_) => {
                failures.push(format!("{what}: no return within 10 s"));
                continue;
            }
        };
        let ramp_tip = ramp.as_ref().map(|s| s.tip).map_err(|e| e.to_string());
        match direct {
            Err(e) => failures.push(format!("{what}: {e} (pressure ramp: {ramp_tip:?})")),
            Ok(sol) => {
                let s = flat_scales(&finger_scales(&f));
                let (_, g) = f.gradient(&load, &sol.coefficients).unwrap();
                let r = g
                    .iter()
                    .zip(&s)
                    .fold(0.0f64, |m, (g, s)| m.max((g * s).abs()))
                    / f.stiffness_scale();
                eprintln!("{what}: tip {:?}, residual {r:.2e}", sol.tip);
                if r > 1e-10 {
                    failures.push(format!("{what}: residual {r:e}"));
                }
                if !load.has_tip_load() {
                    // the same equilibrium: two solves to the default
                    // tolerance differ by about 1e-6 mm here (Newton stops
                    // near gtol), other equilibria by millimetres
                    let t = ramp_tip.expect("the pressure ramp converges");
                    assert!(
                        dist(t, sol.tip) < 1e-4,
                        "{what}: ramp {t:?} vs {:?}",
                        sol.tip
                    );
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// A solver hands its buffers to the next solver of the same finger
/// (`Finger::solve` builds one per call): what a solve leaves in them must
/// not change the next answer. The same scene after others (a decoupled
/// one, a coupled one from elsewhere) gives bit-identical coefficients, and
/// so does a copy of the finger.
#[test]
fn reused_solver_buffers_do_not_change_answers() {
    let f = Finger::paper(0.25, 8).unwrap();
    let opts = SolveOptions::default();
    let tip = Load::unloaded().with_tip_force(FX, FZ);
    let first = f.solve(&tip, &opts).unwrap();
    let _ = f.solve(&pressure(200.0), &opts).unwrap();
    let _ = f
        .solve(&Load::unloaded().with_tip_force(-2.0, 3.0), &opts)
        .unwrap();
    let again = f.solve(&tip, &opts).unwrap();
    assert_eq!(first.coefficients, again.coefficients);
    assert_eq!(first.tip, again.tip);
    let copy = f.clone();
    let on_copy = copy.solve(&tip, &opts).unwrap();
    assert_eq!(first.coefficients, on_copy.coefficients);
}
