//! Following equilibrium paths and judging stability, checked
//! independently: every point of a followed load path is an equilibrium
//! of the assembled gradient, its inertia matches the eigenvalues of the
//! dense Hessian, its end matches a direct solve; a target solve's
//! stability matches the eigenvalues of the dense Hessian projected on the
//! constraint; a size sweep that cannot reach its next size ends where the
//! finger really leaves the model.

use fpc::finger::{LoadPathSpec, PathTermination, Solver, TargetProblem};
use fpc::gripper::{grasping_angle_range, SizeTail, SweepEnd};
use fpc::{Coefficients, Finger, Gripper, GripperParams, Load, PalmSpec, SolveOptions};
use nalgebra::{DMatrix, SymmetricEigen};

fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The dense Hessian of the finger at `k` under `load`, in raw unknowns.
fn dense_hessian(f: &Finger, load: &Load, k: &Coefficients) -> DMatrix<f64> {
    let (_, _, h) = f.hessian(load, k).unwrap();
    let n = k.as_slice().len();
    DMatrix::from_column_slice(n, n, &h)
}

fn negative_count(m: &DMatrix<f64>) -> usize {
    let m = 0.5 * (m + m.transpose());
    let e = SymmetricEigen::new(m);
    let scale = e.eigenvalues.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    e.eigenvalues
        .iter()
        .filter(|&&v| v < -1e-12 * scale)
        .count()
}

#[test]
fn every_point_of_a_load_path_is_an_equilibrium_with_the_dense_inertia() {
    for (eps0, dir) in [(0.25, [0.6, 0.8]), (0.4, [-1.0, 0.0]), (0.5, [0.0, -1.0])] {
        let f = Finger::paper(eps0, 6).unwrap();
        let opts = SolveOptions::default().tip_only();
        let start = f.solve(&Load::unloaded(), &opts).unwrap();
        let problem = TargetProblem {
            base: Load::unloaded(),
            direction: dir,
            weights: [1.0, 0.0],
            target: 0.0,
        };
        let spec = LoadPathSpec {
            problem,
            lambda0: 0.0,
            increasing: true,
            lambda_end: Some(3.0),
            lambda_scale: 1.0,
            events: true,
        };
        let mut solver = Solver::new(&f);
        let mut checked = 0;
        let path = solver
            .follow_load(&spec, &start.coefficients, &opts, &mut |p| {
                let k =
                    Coefficients::new(f.unknowns_per_element(), p.coefficients.to_vec()).unwrap();
                let load = problem.load_at(p.lambda);
                let (_, g) = f.gradient(&load, &k).unwrap();
                // the raw gradient times the unknowns' scales, over the stiffness
                let s = f.unknown_scales();
                let scaled: Vec<f64> = g.iter().zip(s.iter().cycle()).map(|(a, b)| a * b).collect();
                assert!(
                    norm_inf(&scaled) <= 1e-8 * f.stiffness_scale(),
                    "eps0 {eps0}, lambda {}: residual {:e}",
                    p.lambda,
                    norm_inf(&scaled) / f.stiffness_scale()
                );
                let (tip, _) = f.tip(&k).unwrap();
                assert!((tip[0] - p.tip[0]).abs() + (tip[1] - p.tip[1]).abs() < 1e-12);
                assert_eq!(
                    p.negative_eigenvalues,
                    negative_count(&dense_hessian(&f, &load, &k)),
                    "lambda {}",
                    p.lambda
                );
                checked += 1;
                true
            })
            .unwrap();
        assert_eq!(path.termination, PathTermination::ReachedTarget);
        assert!(checked >= 3);
        // the end matches a direct solve at that load
        let (k, lambda) = &path.last;
        assert_eq!(*lambda, 3.0);
        let direct = f.solve(&problem.load_at(3.0), &opts).unwrap();
        let (tip, _) = f.tip(k).unwrap();
        assert!((tip[0] - direct.tip[0]).hypot(tip[1] - direct.tip[1]) < 1e-6);
    }
}

#[test]
fn a_target_solve_is_judged_stable_on_its_constraint() {
    let f = Finger::paper(0.4, 6).unwrap();
    let opts = SolveOptions::default();
    let start = f.solve(&Load::unloaded(), &opts).unwrap();
    // push the tip 10 mm along +X, and 5 mm along -Z
    for (direction, weights, shift) in [
        ([1.0, 0.0], [1.0, 0.0], 10.0),
        ([0.0, -1.0], [0.0, 1.0], -5.0),
    ] {
        let problem = TargetProblem {
            base: Load::unloaded(),
            direction,
            weights,
            target: weights[0] * start.tip[0] + weights[1] * start.tip[1] + shift,
        };
        let (sol, lambda) = Solver::new(&f)
            .solve_target(&problem, &start.coefficients, 0.0, 1e-9, &opts)
            .unwrap();
        let load = problem.load_at(lambda);
        let h = dense_hessian(&f, &load, &sol.coefficients);
        // the constraint gradient: d(weights . tip)/dK by central differences
        let k = sol.coefficients.as_slice();
        let n = k.len();
        let per = f.unknowns_per_element();
        let tip_of = |kk: &[f64]| {
            let (t, _) = f
                .tip(&Coefficients::new(per, kk.to_vec()).unwrap())
                .unwrap();
            weights[0] * t[0] + weights[1] * t[1]
        };
        let s = f.unknown_scales();
        let c: Vec<f64> = (0..n)
            .map(|i| {
                let h = 1e-6 * s[i % s.len()].abs().max(1e-12);
                let (mut a, mut b) = (k.to_vec(), k.to_vec());
                a[i] += h;
                b[i] -= h;
                (tip_of(&a) - tip_of(&b)) / (2.0 * h)
            })
            .collect();
        // an orthonormal basis of the constraint's null space (in scaled
        // unknowns, where H is well conditioned): project and count
        let d = DMatrix::from_fn(n, n, |i, j| if i == j { s[i % s.len()] } else { 0.0 });
        let hs = &d * &h * &d;
        let cs = nalgebra::DVector::from_iterator(n, (0..n).map(|i| c[i] * s[i % s.len()]));
        let q = cs.normalize();
        let p = DMatrix::identity(n, n) - &q * q.transpose();
        let svd = p.clone().svd(true, false);
        let u = svd.u.unwrap();
        let z = u.columns(0, n - 1).into_owned();
        let reduced = z.transpose() * hs * &z;
        let want = negative_count(&reduced);
        assert_eq!(sol.negative_eigenvalues, Some(want), "{direction:?}");
        assert_eq!(sol.stable, Some(want == 0));
    }
}

#[test]
fn a_size_sweep_that_cannot_reach_a_size_ends_where_the_size_turns_back() {
    let params = GripperParams {
        mounting_angle: std::f64::consts::FRAC_PI_3,
        geometry: PalmSpec::Overlap(20.0),
        ..GripperParams::default()
    };
    let g = Gripper::paper(0.25, 8, params).unwrap();
    let [_, hi] = grasping_angle_range(g.mu());
    // a steep contact: as F grows the grasp size rises to a largest value
    // and falls again (under the object the finger cannot open further)
    let beta = 0.3 + 0.6 * hi;
    let start = g.size_sweep_start(0.0, beta).unwrap();
    assert_eq!(start.lambda, 0.0);
    let end = match g.size_tail(&start, 0.95 * g.d_max()).unwrap() {
        SizeTail::End(e) => e,
        SizeTail::Reached(gr) => panic!("reached d = {} at F = {}", gr.size, gr.normal),
    };
    let SweepEnd::Path { size_mm, .. } = end else {
        panic!("expected the end of the path, got {end:?}");
    };
    assert!(size_mm < 0.95 * g.d_max());
    // independently: the finger under the contact force, raised in small
    // steps from zero (load control), has its largest grasp size there
    let contact = |f: f64| {
        let dir = start.problem.direction;
        Load {
            fx: f * dir[0],
            fz: f * dir[1],
            ..start.problem.base
        }
    };
    let opts = SolveOptions::default().tip_only();
    let mut k = start.solution.coefficients.clone();
    let mut largest: f64 = f64::NEG_INFINITY;
    for i in 1..=400 {
        let f = 40.0 * i as f64 / 400.0;
        let sol = match g.finger().solve_from(&contact(f), &k, &opts) {
            Ok(s) => s,
            Err(_) => break,
        };
        largest = largest.max(g.size_of(sol.tip));
        k = sol.coefficients;
    }
    assert!(
        (largest - size_mm).abs() <= 1e-3 * size_mm.abs().max(1.0),
        "largest size along the load {largest} mm, the sweep's end {size_mm} mm"
    );
}

#[test]
fn a_cold_grasp_that_a_jump_would_take_to_another_branch_is_the_path_s() {
    // eps0 = 0.4, a = 60 deg, g = 20 mm, d = 150 mm at b = 0: one Newton
    // jump from the rest state lands on a coiled, self-crossing equilibrium
    // that is unstable with the object holding the tip; the traced path
    // does not
    let params = GripperParams {
        mounting_angle: std::f64::consts::FRAC_PI_3,
        geometry: PalmSpec::Overlap(20.0),
        ..GripperParams::default()
    };
    let g = Gripper::paper(0.4, 8, params).unwrap();
    let d = 150.0;
    let cold = g.grasp_load_for_size(0.0, d, 0.0, None).unwrap();
    // independently, the path: a sweep of sizes from the rest state, each
    // warm-started from the one before
    let mut warm: Option<fpc::Grasp> = None;
    let n = 60;
    for i in 1..=n {
        let di = g.d_min() + (d - g.d_min()) * i as f64 / n as f64;
        let gr = g.grasp_load_for_size(0.0, di, 0.0, warm.as_ref()).unwrap();
        assert_eq!(gr.solution.negative_eigenvalues, Some(0), "d = {di}");
        warm = Some(gr);
    }
    let path = warm.unwrap();
    // the cold answer is the path's: the same stable equilibrium
    assert_eq!(cold.solution.negative_eigenvalues, Some(0));
    assert!(
        (cold.lift - path.lift).abs() <= 1e-6 * path.lift,
        "cold f_v = {} N, along the path {} N",
        cold.lift,
        path.lift
    );
    let (kc, kp) = (
        cold.solution.coefficients.as_slice(),
        path.solution.coefficients.as_slice(),
    );
    assert!(
        norm_inf(&kc.iter().zip(kp).map(|(a, b)| a - b).collect::<Vec<_>>()) < 1e-6 * norm_inf(kp)
    );
    // the path, not the stability judgement, picks the branch: without the
    // judgement the answer is still the path's
    let blind = g.clone().with_stability(false);
    let traced = blind.grasp_load_for_size(0.0, d, 0.0, None).unwrap();
    assert!((traced.size - d).abs() < 1e-6);
    assert!(
        (traced.lift - path.lift).abs() <= 1e-6 * path.lift,
        "{} {}",
        traced.lift,
        path.lift
    );
    assert_eq!(traced.verdict.stability, fpc::gripper::Stability::NotJudged);
}
