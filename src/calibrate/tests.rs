//! The calibration's parts against independent computations: the chain's
//! points against the finger's own shape and their derivatives against
//! central differences of that shape; the circle fit's derivative against
//! differences of the fit; the whole Jacobian against central differences
//! of the residuals (every prediction solved again); the identifiability
//! analysis and the minimiser on problems with known answers.

use nalgebra::{DMatrix, DVector};

use super::identify::{analyse, Verdict};
use super::lm::{minimise, Point, Termination};
use super::options::CalibrateOptions;
use super::params::unknowns;
use super::residuals::evaluate;
use crate::circle_fit::fit_circle;
use crate::circle_fit::radius_tangents;
use crate::measure::{Manifest, TestData};
use crate::sensitivity::Param;
use crate::sensitivity::{points_and_tangents, shape_sites};
use crate::{Actuator, Finger, Load, SolveOptions};

fn finger_at(kpa: f64) -> (Actuator, Finger, crate::Solution, Load) {
    let act = Actuator::default();
    let part = crate::Partition::equal(act.geometry().lx, 8).unwrap();
    let finger = Finger::new(&act, &part, true);
    let load = Load::unloaded().with_pressure_kpa(kpa);
    let sol = finger.solve(&load, &SolveOptions::default()).unwrap();
    (act, finger, sol, load)
}

#[test]
fn chain_points_and_derivatives_match_the_shape() {
    let (act, finger, sol, load) = finger_at(40.0);
    let params = [
        Param::Actuator(crate::actuator::ActuatorParam::Eps0),
        Param::Kappa,
    ];
    let sens = finger.sensitivities(&act, &sol, &load, &params).unwrap();
    let dks: Vec<_> = sens.rows.iter().map(|r| r.coefficients.clone()).collect();
    let per = 5;
    let sites = shape_sites(finger.element_lengths(), per);
    let (pts, d) = points_and_tangents(&finger, &sol.coefficients, &dks, &sites).unwrap();
    let shape = finger.shape(&sol.coefficients, per).unwrap();
    assert_eq!(pts.len(), shape.len());
    for (p, q) in pts.iter().zip(&shape) {
        assert!(
            (p[0] - q[0]).abs() < 1e-11 && (p[1] - q[1]).abs() < 1e-11,
            "{p:?} {q:?}"
        );
    }
    // the explicit map's derivative along dK by central differences of
    // the finger's own shape (no solve: K + h dK)
    for (dk, dp) in dks.iter().zip(&d) {
        let big = dk.as_slice().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let h = 1e-4 / big;
        let at = |t: f64| {
            let mut k = sol.coefficients.clone();
            for (a, b) in k.as_mut_slice().iter_mut().zip(dk.as_slice()) {
                *a += t * b;
            }
            finger.shape(&k, per).unwrap()
        };
        // Richardson-extrapolated central differences
        let (p, m, p2, m2) = (at(h), at(-h), at(h / 2.0), at(-h / 2.0));
        let scale = dp
            .iter()
            .fold(0.0f64, |s, v| s.max(v[0].abs()).max(v[1].abs()));
        for i in 0..p.len() {
            for c in 0..2 {
                let d1 = (p[i][c] - m[i][c]) / (2.0 * h);
                let d2 = (p2[i][c] - m2[i][c]) / h;
                let fd = (4.0 * d2 - d1) / 3.0;
                assert!(
                    (fd - dp[i][c]).abs() < 1e-9 * scale,
                    "sample {i} coordinate {c}: {fd} against {}",
                    dp[i][c]
                );
            }
        }
    }
}

#[test]
fn circle_fit_derivative_matches_differences_of_the_fit() {
    // an elliptic arc: the residuals of the fit are far from zero
    let pts: Vec<[f64; 2]> = (0..40)
        .map(|i| {
            let t = -0.3 + 1.9 * i as f64 / 39.0;
            [30.0 * t.cos() + 2.0, 22.0 * t.sin() - 5.0]
        })
        .collect();
    let mut rng = fastrand::Rng::with_seed(7);
    let dq: Vec<[f64; 2]> = pts
        .iter()
        .map(|_| [rng.f64() - 0.5, rng.f64() - 0.5])
        .collect();
    let (c, d) = radius_tangents(&pts, std::slice::from_ref(&dq)).unwrap();
    assert!(c.rms > 0.1, "a poor fit on purpose: {c:?}");
    let fit = |t: f64| {
        let moved: Vec<[f64; 2]> = pts
            .iter()
            .zip(&dq)
            .map(|(p, v)| [p[0] + t * v[0], p[1] + t * v[1]])
            .collect();
        fit_circle(&moved).unwrap().radius
    };
    let h = 1e-4;
    let fd = (fit(h) - fit(-h)) / (2.0 * h);
    assert!(
        (fd - d[0]).abs() < 1e-7 * fd.abs().max(1.0),
        "{fd} against {}",
        d[0]
    );
}

/// The example manifest with at most `keep` rows per test.
fn small_manifest(keep: usize) -> Manifest {
    let mut m = Manifest::load("examples/calibration/manifest.toml".as_ref()).unwrap();
    for s in &mut m.specimens {
        for t in &mut s.tests {
            match &mut t.data {
                TestData::Markers { rows, .. } => rows.truncate(keep),
                TestData::Radius(rows) => rows.truncate(keep),
                TestData::Force(rows) => rows.truncate(keep),
            }
        }
    }
    m
}

#[test]
fn jacobian_matches_central_differences_of_the_residuals() {
    let m = small_manifest(3);
    let opts = CalibrateOptions::new(&["eps0", "kappa", "emc.e1", "p1", "fluidic.e", "camera"]);
    let u = unknowns(&m, &opts).unwrap();
    let theta: Vec<f64> = u.iter().map(|x| x.start).collect();
    let e = evaluate(&m, &u, &theta).unwrap();
    assert!(e.target_solves > 0 && e.rows.iter().any(|r| r.quantity == "radius_mm"));
    for k in 0..u.len() {
        // the residuals come from solves converged to their tolerance: a
        // step of 1e-4 keeps that noise (about 1e-9 relative) well below
        // the tolerance once the differences divide it by 2h
        let h = 1e-4 * theta[k].abs().max(1e-3);
        let at = |t: f64| {
            let mut th = theta.clone();
            th[k] += t;
            evaluate(&m, &u, &th).unwrap()
        };
        let (p, q) = (at(h), at(-h));
        let col: Vec<f64> = e.jacobian.iter().map(|r| r[k]).collect();
        let scale = col.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        assert!(scale > 0.0, "{} has no effect", u[k].label());
        for (i, &exact) in col.iter().enumerate() {
            let fd = (p.rows[i].residual_sd - q.rows[i].residual_sd) / (2.0 * h);
            assert!(
                (fd - exact).abs() < 2e-6 * scale,
                "{} row {i} ({} {}:{}): exact {} against differences {fd}",
                u[k].label(),
                p.rows[i].quantity,
                p.rows[i].file,
                p.rows[i].line,
                exact
            );
        }
    }
}

#[test]
fn identical_columns_are_named_as_not_identifiable() {
    let mut rng = fastrand::Rng::with_seed(3);
    let j = DMatrix::from_fn(20, 3, |_, _| rng.f64() - 0.5);
    let mut j2 = j.clone();
    // the second column a multiple of the third: only their sum acts
    let c = j.column(2).clone_owned() * 4.0;
    j2.set_column(1, &c);
    let names = ["a".to_string(), "b".to_string(), "c".to_string()];
    let (id, cov) = analyse(&j2, &names);
    assert_eq!(id.verdict, Verdict::NotIdentifiable, "{}", id.message);
    assert!(cov.is_none());
    let named: Vec<&str> = id.weakest.iter().map(|c| c.name.as_str()).collect();
    assert!(
        named.contains(&"b") && named.contains(&"c") && !named.contains(&"a"),
        "{named:?}"
    );
    let (ok, cov) = analyse(&j, &names);
    assert_eq!(ok.verdict, Verdict::Identifiable, "{}", ok.message);
    // the covariance inverts J^T J
    let prod = (j.transpose() * &j) * cov.unwrap();
    assert!((prod - DMatrix::<f64>::identity(3, 3)).amax() < 1e-10);
}

#[test]
fn minimiser_fits_an_exponential_and_respects_bounds() {
    let t: Vec<f64> = (0..30).map(|i| i as f64 * 0.1).collect();
    let y: Vec<f64> = t.iter().map(|t| 2.0 * (-1.3 * t).exp()).collect();
    let eval = |th: &[f64]| -> Result<(Point, ()), ()> {
        let r = DVector::from_iterator(
            30,
            t.iter()
                .zip(&y)
                .map(|(t, y)| y - th[0] * (-th[1] * t).exp()),
        );
        let j = DMatrix::from_fn(30, 2, |i, k| {
            let e = (-th[1] * t[i]).exp();
            if k == 0 {
                -e
            } else {
                th[0] * t[i] * e
            }
        });
        Ok((Point { r, j }, ()))
    };
    let m = minimise(
        vec![1.0, 0.5],
        &[0.0, 0.0],
        &[10.0, 10.0],
        100,
        1e-12,
        eval,
        |_, _| {},
    )
    .unwrap();
    assert!(
        (m.theta[0] - 2.0).abs() < 1e-10 && (m.theta[1] - 1.3).abs() < 1e-10,
        "{:?}",
        m.theta
    );
    assert_ne!(m.termination, Termination::MaxIterations);
    // an upper bound below the truth: the fit stops on it
    let b = minimise(
        vec![1.0, 0.5],
        &[0.0, 0.0],
        &[10.0, 1.0],
        100,
        1e-12,
        eval,
        |_, _| {},
    )
    .unwrap();
    assert_eq!(b.theta[1], 1.0);
}

#[test]
fn exact_jacobians_take_at_least_five_times_fewer_solves_than_differences() {
    use super::driver::{run, STEP_TOLERANCE};
    let m = small_manifest(4);
    let opts = CalibrateOptions::new(&["eps0", "kappa"]);
    let u = unknowns(&m, &opts).unwrap();
    let theta0: Vec<f64> = u.iter().map(|x| x.start * 1.02).collect();
    let exact = run(&m, &u, theta0.clone(), 100).unwrap();
    let exact_solves = exact.solves + exact.target_solves;
    // the same minimiser on central differences of the residuals (every
    // evaluation's solves counted; the differences need only residuals)
    let n = u.len();
    let lower: Vec<f64> = u.iter().map(|x| x.lower).collect();
    let upper: Vec<f64> = u.iter().map(|x| x.upper).collect();
    let mut fd_solves = 0;
    let fd = minimise(
        theta0,
        &lower,
        &upper,
        100,
        STEP_TOLERANCE,
        |th| {
            let e = evaluate(&m, &u, th)?;
            fd_solves += e.solves + e.target_solves;
            let rows = e.rows.len();
            let r = DVector::from_iterator(rows, e.rows.iter().map(|x| x.residual_sd));
            let mut j = DMatrix::<f64>::zeros(rows, n);
            for k in 0..n {
                let h = 1e-6 * th[k].abs().max(1e-3);
                let mut side = |t: f64| -> Result<Vec<f64>, crate::SolveError> {
                    let mut x = th.to_vec();
                    x[k] += t;
                    let e = evaluate(&m, &u, &x)?;
                    fd_solves += e.solves + e.target_solves;
                    Ok(e.rows.iter().map(|x| x.residual_sd).collect())
                };
                let (p, q) = (side(h)?, side(-h)?);
                for i in 0..rows {
                    j[(i, k)] = (p[i] - q[i]) / (2.0 * h);
                }
            }
            Ok::<_, crate::SolveError>((Point { r, j }, ()))
        },
        |_, _| {},
    )
    .unwrap();
    let (c_exact, c_fd) = (exact.min.point.r.norm_squared(), fd.point.r.norm_squared());
    assert!(
        (c_exact - c_fd).abs() <= 1e-6 * c_exact,
        "{c_exact} against {c_fd}"
    );
    assert!(
        5 * exact_solves <= fd_solves,
        "exact: {exact_solves} solves, differences: {fd_solves}"
    );
    eprintln!("chi2 {c_exact:.6}: exact {exact_solves} solves, central differences {fd_solves}");
}

#[test]
fn a_rib_a_specimen_lacks_is_named_as_such() {
    let m = small_manifest(4);
    let opts = CalibrateOptions::new(&["cl_ribs.list[0].height"]);
    let e = unknowns(&m, &opts).unwrap_err().to_string();
    assert!(
        e.contains("actuator.cl_ribs.list[0].height") && e.contains("no such rib"),
        "{e}"
    );
}

/// The calibrated scenes and fitted cameras, compared with the data as
/// `fpc compare` compares them (its own solves, none of the fit's), give
/// the fit's residuals; and the check sees a claim that is off: a fitted
/// kappa, prestrain or camera angle moved a little after the fit is
/// no longer reproduced (each must reach the comparison).
#[test]
fn a_calibration_is_reproduced_and_a_claim_moved_after_it_is_not() {
    use super::record::REPRODUCE_SD;
    use super::reproduce::reproduce;
    let m = small_manifest(3);
    let opts = CalibrateOptions::new(&["eps0", "kappa", "camera"]);
    let fit = super::calibrate(&m, &opts).unwrap();
    let r = &fit.reproduction;
    assert!(r.reproduced, "{}", r.detail);
    assert!(r.largest_difference_sd.unwrap() <= REPRODUCE_SD);
    assert_eq!(r.points, fit.points);
    let chi = r.chi_square.unwrap();
    assert!(
        (chi - fit.chi_square).abs() <= 1e-9 * fit.chi_square,
        "{chi} {}",
        fit.chi_square
    );
    let u = unknowns(&m, &opts).unwrap();
    for (name, by) in [
        ("load.kappa", 1e-4),
        ("actuator.pemc.eps0[eps0-0.4]", 1e-4),
        ("camera.angle_deg[eps0-0.25, test 1]", 0.01),
    ] {
        let mut moved = fit.clone();
        let p = moved
            .parameters
            .iter_mut()
            .find(|p| p.name == name)
            .unwrap_or_else(|| panic!("{name} is not fitted"));
        p.value += by;
        let again = reproduce(&m, &u, &moved);
        assert!(!again.reproduced, "{name}: {}", again.detail);
    }
}

/// The observer of a calibration sees it begin at zero and every count
/// rise by steps, never falling (the chi-square never rising), the
/// stages in order, and the calibration end where its record says: the
/// iterations and evaluations it reports, each evaluation having solved
/// every specimen, the chi-square at the fit, every pressure refitted.
/// Observing changes nothing in the result.
#[test]
fn progress_counts_rise_to_the_calibrations_own() {
    use super::{calibrate, calibrate_with_progress, CalibrateProgress, CalibrateStage};
    let m = small_manifest(3);
    let opts = CalibrateOptions {
        cross_validate: true,
        ..CalibrateOptions::new(&["eps0", "kappa"])
    };
    let seen = std::sync::Mutex::new(Vec::<CalibrateProgress>::new());
    let fit = calibrate_with_progress(&m, &opts, &|p| seen.lock().unwrap().push(*p)).unwrap();
    let seen = seen.into_inner().unwrap();
    let stage = |p: &CalibrateProgress| match p.stage {
        CalibrateStage::Fitting => 0,
        CalibrateStage::CrossValidating => 1,
        CalibrateStage::Checking => 2,
        CalibrateStage::ChoosingModel => 3,
    };
    let specimens = m.specimens.len();
    let first = seen.first().expect("no progress event");
    assert_eq!(
        (
            first.stage,
            first.iterations,
            first.evaluations,
            first.specimens_solved
        ),
        (CalibrateStage::Fitting, 0, 0, 0)
    );
    assert_eq!(first.chi_square, None);
    for w in seen.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        assert_eq!((b.specimens, b.max_iterations), (specimens, 100));
        assert!(
            (0..=2).contains(&stage(b)) && stage(b) >= stage(a),
            "{a:?} then {b:?}"
        );
        assert!(b.iterations >= a.iterations && b.iterations <= a.iterations + 1);
        assert!(b.evaluations >= a.evaluations && b.evaluations <= a.evaluations + 1);
        assert!(b.specimens_solved >= a.specimens_solved);
        assert!(b.specimens_solved <= a.specimens_solved + 1);
        assert!(b.refits_done >= a.refits_done && b.refits >= a.refits);
        assert!(b.specimens_of_this_evaluation() <= specimens);
        if let (Some(x), Some(y)) = (a.chi_square, b.chi_square) {
            assert!(y <= x, "{a:?} then {b:?}");
        }
        // an evaluation is counted once every specimen is solved
        assert!(b.specimens_solved >= b.evaluations * specimens, "{b:?}");
    }
    let last = seen.last().unwrap();
    assert_eq!(last.stage, CalibrateStage::Checking);
    assert_eq!(
        (last.iterations, last.evaluations),
        (fit.iterations, fit.evaluations)
    );
    assert_eq!(last.specimens_solved, fit.evaluations * specimens);
    let chi = last.chi_square.unwrap();
    assert!(
        (chi - fit.chi_square).abs() <= 1e-12 * fit.chi_square,
        "{chi} {}",
        fit.chi_square
    );
    let refits = fit.cross_validation.as_ref().unwrap().held_out.len();
    assert!(refits > 1);
    assert_eq!((last.refits_done, last.refits), (refits, refits));
    assert_eq!(calibrate(&m, &opts).unwrap(), fit);
}
