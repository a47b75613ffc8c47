//! How a tip-loaded solve scales with the number of elements N, and the
//! structured `O(N)` Newton against the dense reference path (the same
//! Newton on the same problem with the Hessian expanded and factorised
//! densely), measured in one run. Prints a table; targets (issue
//! "Linear-time chain solves"): per-iteration cost t(256) / t(32) <= 10,
//! and the N = 256 cold solve >= 100x faster than the dense path.
//!
//! Newton's chord steps (a gradient and a solve, no Hessian) count as
//! iterations in a solve's report, so the product path's time per
//! iteration mixes two kinds of step; the "Newton iteration" columns time
//! the same structured solve with chord steps off, where every iteration
//! is a Hessian, a factorisation and a solve.
//!
//! ```sh
//! cargo bench --bench scaling
//! cargo bench --bench scaling -- --quick     # fewer repetitions
//! ```

use fpc::finger::Solver;
use fpc::{Finger, Load, SolveOptions};
use fpc_newton::NewtonOptions;

#[path = "common/dense.rs"]
mod dense;

#[path = "common/median.rs"]
mod median;
use median::{median_s, reps};

const FX: f64 = 0.939782;
const FZ: f64 = 0.521707;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let load = Load::unloaded().with_tip_force(FX, FZ);
    let opts = SolveOptions::default().tip_only();
    println!("tip-loaded cold solve (from the unloaded equilibrium), eps0 = 0.25, default actuator, release build");
    println!(
        "{:>5} {:>12} {:>6} {:>10} {:>12} {:>6} {:>10} {:>12} {:>12} {:>8} {:>10}",
        "N",
        "solve (us)",
        "iters",
        "per iter",
        "no chord",
        "iters",
        "per iter",
        "Newton (us)",
        "dense (us)",
        "dense/",
        "tip diff"
    );
    let mut per_iter = Vec::new();
    let mut per_newton = Vec::new();
    // (finger, its scaled unloaded start, Newton options) of N = 32 and 256
    let mut paired = Vec::new();
    let mut ratio_256 = f64::NAN;
    for n in [8usize, 32, 128, 256] {
        let finger = Finger::paper(0.25, n).expect("the default finger builds");
        let unloaded = finger
            .solve(&Load::unloaded(), &opts)
            .expect("the unloaded finger solves");
        // the product path: Solver (workspace reused), validity included
        let mut solver = Solver::new(&finger);
        let sol = solver
            .solve(&load, Some(&unloaded.coefficients), &opts)
            .expect("the tip-loaded finger solves");
        let t_solve = median_s(reps(quick, 1e-6 * n as f64), || {
            std::hint::black_box(
                solver
                    .solve(&load, Some(&unloaded.coefficients), &opts)
                    .ok(),
            );
        });
        let it = sol.report.iterations.max(1);
        per_iter.push((n, t_solve / it as f64));
        // the same Newton on the structured and on the dense path
        let nopts = dense::newton_options(&finger, opts.rtol);
        let x0 = dense::scaled(&finger, unloaded.coefficients.as_slice());
        // every iteration a Newton iteration
        let pure = NewtonOptions {
            chord_steps: false,
            ..nopts
        };
        let mut xp = x0.clone();
        let rp = dense::solve_structured(&finger, &load, pure, &mut xp);
        let t_p = median_s(reps(quick, 1e-6 * n as f64), || {
            let mut x = x0.clone();
            std::hint::black_box(dense::solve_structured(&finger, &load, pure, &mut x));
        });
        let it_p = rp.iterations.max(1);
        per_newton.push((n, t_p / it_p as f64));
        if n == 32 || n == 256 {
            paired.push((finger.clone(), x0.clone(), pure, it_p));
        }
        let mut xs = x0.clone();
        let rs = dense::solve_structured(&finger, &load, nopts, &mut xs);
        let t_s = median_s(reps(quick, 1e-6 * n as f64), || {
            let mut x = x0.clone();
            std::hint::black_box(dense::solve_structured(&finger, &load, nopts, &mut x));
        });
        let mut xd = x0.clone();
        let rd = dense::solve_dense(&finger, &load, nopts, &mut xd);
        let dense_reps = if quick { 1 } else { 3 };
        let t_d = median_s(dense_reps, || {
            let mut x = x0.clone();
            std::hint::black_box(dense::solve_dense(&finger, &load, nopts, &mut x));
        });
        let diff = xs
            .iter()
            .zip(&xd)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            rs.reason == rd.reason,
            "N = {n}: structured {rs:?} but dense {rd:?}"
        );
        if n == 256 {
            ratio_256 = t_d / t_s;
        }
        println!(
            "{n:>5} {:>12.1} {it:>6} {:>10.2} {:>12.1} {it_p:>6} {:>10.2} {:>12.1} {:>12.1} {:>8.1} {diff:>10.1e}",
            t_solve * 1e6,
            t_solve * 1e6 / it as f64,
            t_p * 1e6,
            t_p * 1e6 / it_p as f64,
            t_s * 1e6,
            t_d * 1e6,
            t_d / t_s,
        );
    }
    let at = |v: &[(usize, f64)], n: usize| v.iter().find(|p| p.0 == n).map_or(f64::NAN, |p| p.1);
    println!(
        "per-iteration cost t(256) / t(32) = {:.2} per Newton iteration (chord steps off), {:.2} per iteration of the product path (target <= 10; elements ratio 8)",
        at(&per_newton, 256) / at(&per_newton, 32),
        at(&per_iter, 256) / at(&per_iter, 32),
    );
    // the machine changes speed between phases seconds apart: time the two
    // alternately, 7 rounds, and take the median of the rounds' ratios
    if let [(f32, x32, o32, i32), (f256, x256, o256, i256)] = &paired[..] {
        let time = |f: &Finger, x0: &[f64], o: NewtonOptions, it: usize| {
            median_s(reps(quick, 1e-6 * f.len() as f64), || {
                let mut x = x0.to_vec();
                std::hint::black_box(dense::solve_structured(f, &load, o, &mut x));
            }) / it as f64
        };
        let mut ratios: Vec<f64> = (0..7)
            .map(|_| time(f256, x256, *o256, *i256) / time(f32, x32, *o32, *i32))
            .collect();
        ratios.sort_by(f64::total_cmp);
        println!(
            "the same, N = 32 and 256 timed alternately (median of 7 rounds): {:.2} per Newton iteration",
            ratios[3]
        );
    }
    println!("N = 256: dense path / structured = {ratio_256:.0}x (target >= 100)");
    println!(
        "(\"tip diff\" is the largest difference of the scaled unknowns between the two paths)"
    );
}
