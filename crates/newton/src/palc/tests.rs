//! Unit tests of the continuation driver, its corrector and the restricted
//! inertia.

use super::corrector::*;
use super::*;
use crate::linear::Inertia;
use crate::problem::LinearSystem;
use crate::semiseparable::PivotKind;
use crate::testutil::Lcg;
use crate::{Dense, DenseMatrix, DensePathProblem};
#[path = "../../tests/common/reduced.rs"]
mod reduced;
use reduced::{null_basis, reduce};

/// `E = x^4/4 - x^2/2 - lambda x`: `g = x^3 - x - lambda`.
struct Snap;
impl DensePathProblem for Snap {
    fn dim(&self) -> usize {
        1
    }
    fn eval(&mut self, x: &[f64], l: f64, g: &mut [f64], gl: &mut [f64], h: &mut [f64]) -> bool {
        g[0] = x[0].powi(3) - x[0] - l;
        gl[0] = -1.0;
        h[0] = 3.0 * x[0] * x[0] - 1.0;
        true
    }
}

fn work(n: usize, theta: f64) -> Work {
    Work::new(n, theta)
}

#[test]
fn bordered_solve_is_accurate_next_to_a_singular_h() {
    // H = diag(eps, 1, 2), g_l = (1, 1, 1), border c = (1, 0, 1), cl = 0.5
    for eps in [1e-3, 1e-8, 1e-13] {
        let mut m = DenseMatrix::new(3);
        let h = m.matrix_mut();
        h.fill(0.0);
        h[0] = eps;
        h[4] = 1.0;
        h[8] = 2.0;
        m.factor(0.0, PivotKind::Symmetric).unwrap();
        let mut ws = work(3, 1.0);
        ws.gl.copy_from_slice(&[1.0, 1.0, 1.0]);
        ws.w.copy_from_slice(&ws.gl);
        m.solve(&mut ws.w);
        ws.rx.copy_from_slice(&[0.3, -0.2, 0.7]);
        let c = [1.0, 0.0, 1.0];
        let dl = bordered_solve(&mut m, &mut ws, Some(&c), 0.5, 0.1);
        // residual of the bordered system
        let d = &ws.dx;
        let r = [
            eps * d[0] + dl - 0.3,
            d[1] + dl + 0.2,
            2.0 * d[2] + dl - 0.7,
            d[0] + d[2] + 0.5 * dl - 0.1,
        ];
        let rn = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(rn < 1e-14, "eps = {eps}: residual {rn:e}");
    }
}

#[test]
fn tangent_is_unit_and_oriented() {
    let mut p = Dense::path(Snap);
    let o = PalcOptions {
        theta: 2.0,
        ..Default::default()
    };
    let mut ws = work(1, o.theta);
    let mut rep = PathReport::new(0.0, 0.0);
    let mut s = State::new(1);
    s.x[0] = 1.5;
    s.lambda = 1.5f64.powi(3) - 1.5;
    correct(
        &mut p,
        &o,
        &mut ws,
        Row::Lambda(s.lambda),
        &mut s,
        f64::INFINITY,
        &mut rep,
    )
    .unwrap();
    tangent(&mut p, &mut ws, Border::Lambda(-1.0), &mut s).unwrap();
    // dx/dlambda = 1 / (3 x^2 - 1); t ~ (1/(3x^2-1), 1)
    let slope: f64 = 1.0 / (3.0 * 2.25 - 1.0);
    let norm = (slope * slope + 4.0).sqrt();
    assert!((s.tx[0] + slope / norm).abs() < 1e-14);
    assert!((s.tl + 1.0 / norm).abs() < 1e-14);
    assert!((s.tx[0].powi(2) + 4.0 * s.tl * s.tl - 1.0).abs() < 1e-14);
}

#[test]
fn corrector_passes_a_fold_where_natural_continuation_cannot() {
    // from x slightly below -1/sqrt 3 (just before the fold at lambda = 2/(3 sqrt 3)),
    // a step along the tangent lands past the fold
    let mut p = Dense::path(Snap);
    let o = PalcOptions::default();
    let mut ws = work(1, 1.0);
    let mut rep = PathReport::new(0.0, 0.0);
    let mut a = State::new(1);
    a.x[0] = -0.6;
    a.lambda = -0.216 + 0.6;
    correct(
        &mut p,
        &o,
        &mut ws,
        Row::Lambda(a.lambda),
        &mut a,
        f64::INFINITY,
        &mut rep,
    )
    .unwrap();
    tangent(&mut p, &mut ws, Border::Lambda(1.0), &mut a).unwrap();
    let mut b = State::new(1);
    step_to(&mut p, &o, &mut ws, &a, 0.1, &mut b, &mut rep).unwrap();
    assert!(b.x[0] > -1.0 / 3f64.sqrt(), "past the fold: x = {}", b.x[0]);
    assert!(b.tl < 0.0 && a.tl > 0.0);
    assert_eq!((a.inertia.negative, b.inertia.negative), (0, 1));
    let g = b.x[0].powi(3) - b.x[0] - b.lambda;
    assert!(g.abs() <= 1e-10);
}

#[test]
fn restricted_inertia_small_cases() {
    let mut m = DenseMatrix::new(3);
    let mut work = [0.0; 6];
    // H = diag(-1, 2, 3): constraint along the negative direction
    // removes it; along a positive one keeps it
    let set = |m: &mut DenseMatrix, d: [f64; 3]| {
        let h = m.matrix_mut();
        h.fill(0.0);
        for (i, v) in d.iter().enumerate() {
            h[i * 4] = *v;
        }
    };
    set(&mut m, [-1.0, 2.0, 3.0]);
    let r = factor_restricted_inertia(&mut m, &[1.0, 0.0, 0.0], &mut work).unwrap();
    assert_eq!(
        r,
        Inertia {
            positive: 2,
            negative: 0
        }
    );
    let r = factor_restricted_inertia(&mut m, &[0.0, 1.0, 0.0], &mut work).unwrap();
    assert_eq!(
        r,
        Inertia {
            positive: 1,
            negative: 1
        }
    );
    // nearly singular H: the near-null direction is constrained away
    set(&mut m, [-1e-14, 2.0, 3.0]);
    let r = factor_restricted_inertia(&mut m, &[1.0, 1.0, 0.0], &mut work).unwrap();
    assert_eq!(
        r,
        Inertia {
            positive: 2,
            negative: 0
        }
    );
    // singular H: an error, even though K is regular
    set(&mut m, [0.0, 2.0, 3.0]);
    assert!(matches!(
        factor_restricted_inertia(&mut m, &[1.0, 0.0, 0.0], &mut work),
        Err(RestrictedInertiaError::Hessian(_))
    ));
    // zero constraint
    set(&mut m, [1.0, 2.0, 3.0]);
    assert_eq!(
        factor_restricted_inertia(&mut m, &[0.0; 3], &mut work),
        Err(RestrictedInertiaError::DegenerateConstraint)
    );
    // K singular: H = diag(1, -1, 2), c = (1, 1, 0): c^T H^-1 c = 0
    set(&mut m, [1.0, -1.0, 2.0]);
    assert_eq!(
        factor_restricted_inertia(&mut m, &[1.0, 1.0, 0.0], &mut work),
        Err(RestrictedInertiaError::Singular)
    );
    // random: the sign rule against a direct count on a Householder basis
    let mut rng = Lcg::new(7);
    for _ in 0..50 {
        let n = 3;
        let mut a = [0.0; 9];
        for j in 0..n {
            for i in j..n {
                let v = 2.0 * rng.sym();
                a[i + n * j] = v;
                a[j + n * i] = v;
            }
        }
        m.matrix_mut().copy_from_slice(&a);
        let c = [rng.sym(), rng.sym(), rng.sym()];
        let Ok(r) = factor_restricted_inertia(&mut m, &c, &mut work) else {
            continue;
        };
        let z = null_basis(&c);
        let red = reduce(n, &a, &z);
        let neg = crate::negative_eigenvalues(n - 1, &red).unwrap();
        assert_eq!(r.negative, neg);
        assert_eq!(r.positive + r.negative, n - 1);
    }
}

#[test]
fn invalid_input_evaluates_nothing() {
    let mut p = Dense::path(Snap);
    let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
    let r = palc.follow(
        &mut p,
        &[0.0],
        f64::NAN,
        Direction::Increasing,
        None,
        &mut |_: &PathPoint<'_>| Control::Continue,
    );
    assert_eq!(r.termination, PathTermination::InvalidInput);
    assert_eq!(r.evaluations, 0);
    let r = palc.follow(
        &mut p,
        &[0.0],
        0.0,
        Direction::Increasing,
        Some(f64::INFINITY),
        &mut |_: &PathPoint<'_>| Control::Continue,
    );
    assert_eq!(r.termination, PathTermination::InvalidInput);
    assert!(palc.last_point().is_none());
    assert!(Palc::new(
        1,
        PalcOptions {
            theta: 0.0,
            ..Default::default()
        }
    )
    .is_err());
}
