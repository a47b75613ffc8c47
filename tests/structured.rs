//! The structured `O(N)` linear algebra of the finger's Newton problem
//! against the dense reference path (benches/common/dense.rs: the Hessian
//! expanded column by column and factorised densely), on seeded random
//! scenes with N from 1 to 1000:
//!
//! - Newton converges to the same equilibrium on both paths (tip to 1e-12
//!   relative, every unknown to 1e-12 relative to the largest) for N up to
//!   250, from the unloaded equilibrium of the same finger under random
//!   pressures and tip loads;
//! - one Newton direction `H p = -g` agrees with a dense Cholesky solve at
//!   N = 1000 (both solve the system to a relative residual below 1e-12;
//!   the directions agree to 1e-9, the conditioning's share);
//! - the structured factorisation's inertia (stability) equals the count
//!   of negative eigenvalues of the dense matrix at random, also
//!   indefinite, states, and the shifted factorisation `H + tau I` agrees
//!   with the dense one.
//!
//! faer runs at opt-level 3 in test builds (Cargo.toml), so the dense
//! reference stays affordable at 4000 unknowns.

use fpc::{Actuator, Finger, Load, Partition, SolveOptions};
use fpc_newton::{Gradient, Hessian, LinearSystem, PivotKind, Termination};

#[path = "../benches/common/dense.rs"]
mod dense;

/// A seeded random scene: prestrain, pressure (kPa) and tip force (N).
struct Scene {
    eps0: f64,
    load: Load,
}

fn scene(rng: &mut fastrand::Rng) -> Scene {
    let eps0 = 0.1 + 0.3 * rng.f64();
    let kpa = 80.0 * rng.f64();
    let fx = 1.2 * (rng.f64() - 0.5);
    let fz = 1.2 * (rng.f64() - 0.5);
    Scene {
        eps0,
        load: Load::unloaded()
            .with_pressure_kpa(kpa)
            .with_tip_force(fx, fz),
    }
}

fn finger(eps0: f64, n: usize) -> Finger {
    let act = Actuator::paper(eps0).expect("a paper actuator");
    let part = Partition::equal(act.geometry().lx, n).expect("a partition");
    Finger::new(&act, &part, true)
}

fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The dense matrix of the structured Hessian at `x` (column by column).
fn dense_matrix(p: &mut fpc::finger::Problem<'_>, x: &[f64]) -> Vec<f64> {
    let n = x.len();
    let mut g = vec![0.0; n];
    p.hessian(x, &mut g);
    let mut h = vec![0.0; n * n];
    let mut e = vec![0.0; n];
    for j in 0..n {
        e[j] = 1.0;
        p.apply(&e, &mut h[j * n..(j + 1) * n]);
        e[j] = 0.0;
    }
    h
}

#[test]
fn newton_reaches_the_same_equilibrium_on_both_paths() {
    let mut rng = fastrand::Rng::with_seed(11);
    let mut worst = 0.0f64;
    for n in [1usize, 2, 3, 5, 8, 13, 32, 64, 250] {
        for _ in 0..if n <= 32 { 3 } else { 1 } {
            let sc = scene(&mut rng);
            let f = finger(sc.eps0, n);
            let opts = SolveOptions::default().tip_only();
            let unloaded = f
                .solve(&sc.load.with_tip_force(0.0, 0.0), &opts)
                .expect("the untouched finger solves");
            let nopts = dense::newton_options(&f, 1e-12);
            let x0 = dense::scaled(&f, unloaded.coefficients.as_slice());
            let (mut xs, mut xd) = (x0.clone(), x0.clone());
            let rs = dense::solve_structured(&f, &sc.load, nopts, &mut xs);
            let rd = dense::solve_dense(&f, &sc.load, nopts, &mut xd);
            assert_eq!(rs.reason, Termination::Converged, "N = {n}: {rs:?}");
            assert_eq!(rd.reason, Termination::Converged, "N = {n}: {rd:?}");
            let scale = norm_inf(&xd).max(1.0);
            let rel = max_diff(&xs, &xd) / scale;
            worst = worst.max(rel);
            assert!(
                rel <= 1e-12,
                "N = {n}: unknowns differ by {rel:e} (relative)"
            );
            // the tips through the public API
            let raw = |x: &[f64]| {
                let s = f.unknown_scales();
                let k: Vec<f64> = x.iter().zip(s.iter().cycle()).map(|(a, b)| a * b).collect();
                fpc::Coefficients::new(f.unknowns_per_element(), k).expect("coefficients")
            };
            let (ts, _) = f.tip(&raw(&xs)).expect("tip");
            let (td, _) = f.tip(&raw(&xd)).expect("tip");
            let rel_tip = (ts[0] - td[0]).hypot(ts[1] - td[1]) / td[0].hypot(td[1]);
            assert!(
                rel_tip <= 1e-12,
                "N = {n}: tips differ by {rel_tip:e} (relative)"
            );
        }
    }
    eprintln!("largest relative difference of the equilibria: {worst:e}");
}

#[test]
fn a_newton_direction_at_n_1000_matches_a_dense_solve() {
    let mut rng = fastrand::Rng::with_seed(12);
    let sc = scene(&mut rng);
    let n = 1000;
    let f = finger(sc.eps0, n);
    let opts = SolveOptions::default().tip_only();
    let unloaded = f
        .solve(&sc.load.with_tip_force(0.0, 0.0), &opts)
        .expect("the untouched finger solves");
    let x = dense::scaled(&f, unloaded.coefficients.as_slice());
    let dim = x.len();
    let mut p = f.problem(&sc.load);
    let h = dense_matrix(&mut p, &x);
    let mut g = vec![0.0; dim];
    p.hessian(&x, &mut g);
    // the structured direction
    let inertia = p
        .factor(0.0, PivotKind::Cholesky)
        .expect("positive definite");
    assert_eq!((inertia.positive, inertia.negative), (dim, 0));
    let mut ps: Vec<f64> = g.iter().map(|v| -v).collect();
    p.solve(&mut ps);
    // the dense direction (faer's Cholesky through fpc-newton)
    let mut m = fpc_newton::DenseMatrix::new(dim);
    m.matrix_mut().copy_from_slice(&h);
    m.factor(0.0, PivotKind::Cholesky).expect("dense Cholesky");
    let mut pd: Vec<f64> = g.iter().map(|v| -v).collect();
    m.solve(&mut pd);
    // both solve the system to rounding
    let residual = |v: &[f64]| {
        let mut r = vec![0.0; dim];
        for j in 0..dim {
            for i in 0..dim {
                r[i] += h[i + dim * j] * v[j];
            }
        }
        let hnorm = (0..dim)
            .map(|i| (0..dim).map(|j| h[i + dim * j].abs()).sum::<f64>())
            .fold(0.0, f64::max);
        max_diff(&r, &g.iter().map(|v| -v).collect::<Vec<_>>()) / (hnorm * norm_inf(v))
    };
    let (rs, rd) = (residual(&ps), residual(&pd));
    assert!(rs <= 1e-12 && rd <= 1e-12, "residuals {rs:e} / {rd:e}");
    let rel = max_diff(&ps, &pd) / norm_inf(&pd);
    assert!(rel <= 1e-9, "directions differ by {rel:e} (relative)");
}

#[test]
fn inertia_and_shifted_factorisations_match_the_dense_matrix() {
    let mut rng = fastrand::Rng::with_seed(13);
    for n in [1usize, 2, 4, 8, 16, 40] {
        for trial in 0..4 {
            let sc = scene(&mut rng);
            let f = finger(sc.eps0, n);
            let opts = SolveOptions::default().tip_only();
            let eq = f.solve(&sc.load, &opts).expect("the scene solves");
            // the equilibrium, and random states around it (often indefinite)
            let mut x = dense::scaled(&f, eq.coefficients.as_slice());
            if trial > 0 {
                for v in x.iter_mut() {
                    *v += 3.0 * (rng.f64() - 0.5);
                }
            }
            let dim = x.len();
            let mut p = f.problem(&sc.load);
            let h = dense_matrix(&mut p, &x);
            let want = fpc_newton::negative_eigenvalues(dim, &h).expect("eigenvalues");
            let mut g = vec![0.0; dim];
            p.gradient(&x, &mut g);
            p.hessian(&x, &mut g);
            match p.factor(0.0, PivotKind::Symmetric) {
                Ok(inertia) => {
                    assert_eq!(inertia.negative, want, "N = {n}, trial {trial}: inertia");
                    assert_eq!(inertia.positive + inertia.negative, dim);
                }
                // a (numerically) singular H: the dense count is then
                // ambiguous; the structured path must say so, not guess
                Err(e) => assert!(
                    matches!(e, fpc_newton::FactorError::Singular { .. }),
                    "N = {n}, trial {trial}: {e:?}"
                ),
            }
            // H + tau I with tau above the most negative eigenvalue
            let (lo, hi) = p.diagonal_range();
            let tau = 2.0 * hi.max(lo.abs()) + 1.0;
            p.factor(tau, PivotKind::Cholesky)
                .expect("a large shift makes H positive definite");
            let mut ps = g.clone();
            p.solve(&mut ps);
            let mut m = fpc_newton::DenseMatrix::new(dim);
            m.matrix_mut().copy_from_slice(&h);
            m.factor(tau, PivotKind::Cholesky)
                .expect("dense shifted Cholesky");
            let mut pd = g.clone();
            m.solve(&mut pd);
            let rel = max_diff(&ps, &pd) / norm_inf(&pd).max(1e-300);
            assert!(
                rel <= 1e-12,
                "N = {n}, trial {trial}: shifted solves differ by {rel:e}"
            );
        }
    }
}
